"""The 2-D drum's sliding work where an impact drives it, against a resolved
simulation of the same scene.

SI units: m, kg, s, N, J.  A log strikes a pile of six resting on the shell's
bottom (the pile of test_drum2d_peaks.py): the impact's wave makes the
pile's logs slip on each other and on the shell for a millisecond or two,
within one 2 ms step, and stick again.  The 2-D step (h longer than the
contact periods, 0.6–0.8 ms) resolves the impact in one implicit step, in
which those contacts barely slip: the step's slip taken linear over the
step (records.sliding_speed) alone booked 0.34 and 0.33 J of the vertical
strikes' 7.37 and 6.40 J (−95 %), 4.83 and 4.55 J of the oblique strikes'
7.15 and 6.49 J (−32 and −30 %).  The cluster run's slip beyond its own
linear-slip estimate (formulations.drum2d.impacts, "Sliding work") books
the rest: −1.8 and −0.9 % (vertical), −16.5 and −13.8 % (oblique, kept as
a strict xfail: the striker's own contact, whose slip after it leaves the
top log the linear estimates read, docs/dev-notes.md).

The reference is a small explicit penalty DEM written here: linear
spring–dashpot normal forces (the stack model's springs, the dashpot's ζ
from the restitution), Coulomb friction with a stiff viscous stick, spins,
symplectic Euler at h/400, and the sliding work booked where a contact is
at the cone (μ F_N |u_T|, as the drum's DEM books it), not the stick's
creep.  The stick is stiff enough that the booked work no longer depends
on it: γ = 3e5 N·s/m here (0.1 m/Δt); the vertical strike on the pile of
seed 0 read 5.31, 6.77, 7.32, 7.39 J at γ = 3e4, 1e5, 3e5, 1e6 N·s/m
(each at Δt with γ Δt/m_t <= 0.1, converged in Δt to 0.5 %).  The 2-D
itself at a much smaller h is no second reference: below the contact
period its contacts are backward-Euler springs whose damping falls with h
(laws.py), not the dashpot of e, and the same pile read 5.5, 9.1, 12.1 J
at h = 0.1, 0.05, 0.025 ms.
"""

import numpy as np
import pytest

from formulations.drum2d import Discs, Drum2D, Shell

G, E, LENGTH, R, H = 9.81, 0.4e9, 1.0, 1.0, 2e-3
STICK = 3e5                 # N·s/m: the DEM's viscous stick, converged (module docstring)


def _zeta(e):
    le = np.log(e)
    return -le / np.sqrt(np.pi ** 2 + le * le)


def _dem_sliding(pos, vel, radii, masses, e, mu, dt, steps):
    """Sliding work [J] at the cone of a penalty DEM run (module docstring)."""
    pos, vel = np.array(pos, float), np.array(vel, float)
    n = radii.size
    spin, inertia = np.zeros(n), 0.5 * masses * radii ** 2
    iu, ju = np.triu_indices(n, 1)
    k_pair, k_wall = E * LENGTH, 2 * E * LENGTH      # log halves 2Eℓ in series; the steel rigid
    m_pair = masses[iu] * masses[ju] / (masses[iu] + masses[ju])
    eta_pair = 2 * _zeta(e) * np.sqrt(m_pair * k_pair)
    eta_wall = 2 * _zeta(e) * np.sqrt(masses * k_wall)
    work = 0.0
    for _ in range(steps):
        f = np.zeros((n, 2))
        f[:, 1] -= masses * G
        torque = np.zeros(n)
        d = pos[iu] - pos[ju]
        dist = np.hypot(*d.T)
        k = np.flatnonzero(radii[iu] + radii[ju] - dist > 0)
        if k.size:
            nn = d[k] / dist[k, None]
            tt = np.column_stack([-nn[:, 1], nn[:, 0]])
            a, b = iu[k], ju[k]
            dv = vel[a] - vel[b]
            un = (nn * dv).sum(1)
            ut = (tt * dv).sum(1) - radii[a] * spin[a] - radii[b] * spin[b]
            F = np.maximum(0.0, k_pair * (radii[a] + radii[b] - dist[k]) - eta_pair[k] * un)
            Ft = -np.clip(STICK * ut, -mu * F, mu * F)
            cone = (F > 0) & (STICK * np.abs(ut) >= mu * F)
            work += dt * np.abs(Ft * ut)[cone].sum()
            fv = F[:, None] * nn + Ft[:, None] * tt
            np.add.at(f, a, fv)
            np.add.at(f, b, -fv)
            np.add.at(torque, a, -radii[a] * Ft)
            np.add.at(torque, b, -radii[b] * Ft)
        dist = np.hypot(*pos.T)
        k = np.flatnonzero(dist + radii - R > 0)
        if k.size:
            nn = -pos[k] / dist[k, None]
            tt = np.column_stack([-nn[:, 1], nn[:, 0]])
            un = (nn * vel[k]).sum(1)
            ut = (tt * vel[k]).sum(1) - radii[k] * spin[k]
            F = np.maximum(0.0, k_wall * (dist[k] + radii[k] - R) - eta_wall[k] * un)
            Ft = -np.clip(STICK * ut, -mu * F, mu * F)
            cone = (F > 0) & (STICK * np.abs(ut) >= mu * F)
            work += dt * np.abs(Ft * ut)[cone].sum()
            f[k] += F[:, None] * nn + Ft[:, None] * tt
            torque[k] -= radii[k] * Ft
        vel += dt * f / masses[:, None]
        spin += dt * torque / inertia
        pos += dt * vel
    return work


def _pile(seed, strike, d=0.15):
    """Three equal logs on the shell's bottom (0.25 d apart), two on them, one
    on those, each touching; a log of d (1 ± 20 %) strikes the top one at
    ``strike`` (m/s), touching 45 % into the first step."""
    r = d / 2
    rows = [np.array([[x, -np.sqrt((R - r) ** 2 - x ** 2)] for x in (-1.25 * d, 0, 1.25 * d)])]
    for _ in range(2):
        up = []
        for a, b in zip(rows[-1][:-1], rows[-1][1:]):
            half = np.linalg.norm(b - a) / 2
            normal = np.array([a[1] - b[1], b[0] - a[0]]) / (2 * half)
            up.append((a + b) / 2 + np.sqrt(d * d - half * half) * normal)
        rows.append(np.array(up))
    pts = np.vstack(rows)
    striker = d * (1 + 0.2 * np.random.default_rng(seed).uniform(-1, 1))
    top = pts[-1] + [0.0, (d + striker) / 2 - 0.45 * H * strike[1]]
    vel = np.zeros((7, 2))
    vel[-1] = strike
    return np.append(np.full(6, d), striker), np.vstack([pts, top]), vel


def _two_d(d, pos, vel, h, seconds, e=0.2, mu=0.4):
    discs = Discs(d, pos, length=LENGTH, velocities=vel)
    res = Drum2D(discs, Shell(R), ("log_elasticity", "damping", "friction"), restitution=e,
                 mu_disc=mu, mu_shell=mu, modulus=E).simulate(h, int(round(seconds / h)),
                                                              keep_contacts=False)
    assert res.certified.all() and res.worst_certificate <= 1e-8
    return res


def _booked_and_dem(seed, strike, seconds=0.02):
    """(the 2-D's sliding work at h = 2 ms, the DEM's) [J] over ``seconds``
    (the DEM's pile slides within the first 3 ms, not after)."""
    d, pos, vel = _pile(seed, strike)
    res = _two_d(d, pos, vel, H, seconds)
    radii = d / 2
    masses = 860.0 * np.pi * radii ** 2 * LENGTH
    dem = _dem_sliding(pos, vel, radii, masses, 0.2, 0.4, H / 400, int(round(seconds / H)) * 400)
    return res.sliding_work.sum(), dem


@pytest.mark.parametrize("seed", [0, 1])
def test_a_pile_struck_from_above_books_the_sliding_its_resolved_dynamics_do(seed):
    """Within 5 % of the DEM (−1.8 and −0.9 %; the step's own booking −95 %)."""
    booked, dem = _booked_and_dem(seed, (0.4, -3.0))
    assert booked == pytest.approx(dem, rel=0.05), (booked, dem)


@pytest.mark.xfail(strict=True, reason="the striker's contact: −16.5 and −13.8 % (module "
                   "docstring)")
@pytest.mark.parametrize("seed", [0, 1])
def test_a_pile_struck_obliquely_books_the_sliding_its_resolved_dynamics_do(seed):
    booked, dem = _booked_and_dem(seed, (1.5, -2.0))
    assert booked == pytest.approx(dem, rel=0.05), (booked, dem)
