"""The drum tests' resolved reference: a small explicit penalty DEM of discs
in a circular shell, written apart from formulations.drum2d.

SI units: m, kg, s, N, J.  Linear spring–dashpot normal forces (the stack
model's springs, c = 1/(2 E ℓ) per log half, the steel rigid; the
dashpot's ζ from the restitution e), Coulomb friction regularized by a
stiff viscous stick (``stick`` [N·s/m]), spins, symplectic Euler.  It
keeps the largest log–log and log–shell normal forces, and the sliding
work where a contact is at the cone (μ F_N |u_T|, as the drum's DEM books
it), not the stick's creep.
"""

import numpy as np

G, E, LENGTH, R, H = 9.81, 0.4e9, 1.0, 1.0, 2e-3


def zeta(e):
    """The dashpot's damping ratio giving restitution e (1 for e <= 0)."""
    if e <= 0:
        return 1.0
    le = np.log(e)
    return -le / np.sqrt(np.pi ** 2 + le * le)


def penalty_dem(pos, vel, radii, masses, e, mu, g, dt, steps, stick):
    """(largest log–log normal force [N], largest log–shell [N], sliding
    work at the cone [J]) of a DEM run of ``steps`` steps of ``dt``."""
    pos, vel = np.array(pos, float), np.array(vel, float)
    n = radii.size
    spin, inertia = np.zeros(n), 0.5 * masses * radii ** 2
    iu, ju = np.triu_indices(n, 1)
    k_pair, k_wall = E * LENGTH, 2 * E * LENGTH      # log halves 2Eℓ in series; the steel rigid
    m_pair = masses[iu] * masses[ju] / (masses[iu] + masses[ju])
    eta_pair = 2 * zeta(e) * np.sqrt(m_pair * k_pair)
    eta_wall = 2 * zeta(e) * np.sqrt(masses * k_wall)
    peak_pair = peak_wall = work = 0.0
    for _ in range(steps):
        f = np.zeros((n, 2))
        f[:, 1] -= masses * g
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
            Ft = -np.clip(stick * ut, -mu * F, mu * F)
            peak_pair = max(peak_pair, F.max())
            cone = (F > 0) & (stick * np.abs(ut) >= mu * F)
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
            Ft = -np.clip(stick * ut, -mu * F, mu * F)
            peak_wall = max(peak_wall, F.max())
            cone = (F > 0) & (stick * np.abs(ut) >= mu * F)
            work += dt * np.abs(Ft * ut)[cone].sum()
            f[k] += F[:, None] * nn + Ft[:, None] * tt
            torque[k] -= radii[k] * Ft
        vel += dt * f / masses[:, None]
        spin += dt * torque / inertia
        pos += dt * vel
    return peak_pair, peak_wall, work


def struck_pile(seed, strike=(0.4, -3.0), d=0.15):
    """Three equal logs on the shell's bottom (0.25 d apart), two on them, one
    on those, each touching; a log of d (1 ± 20 %) strikes the top one at
    ``strike`` (m/s), touching 45 % into the first step: (diameters,
    positions, velocities)."""
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
