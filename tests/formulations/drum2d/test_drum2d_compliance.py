"""The 2-D drum's compliant contacts (formulations.drum2d.laws: ``log_elasticity``,
``shell_elasticity``) against the stack model, the linear spring and hand statics.

SI units: m, kg, s, N, J.  References (independent of the code under test):

- masses ρ π d²/4 ℓ and half stiffnesses 2 E ℓ computed here by hand, and the
  stack model (formulations.drum: ``Log.from_wood``, ``Drum``) for the same
  logs, with its own time scheme (backward differences);
- a head-on collision of two bodies on a linear spring of compliance c: peak
  force √(m*/c) Δv, duration T/2 = π √(m* c), rebound Δv (elastic);
- the time-step error of the scheme, from its step map on the linear spring:
  both the 2-D compliant step (θ = 1 positions, the spring at the end of the
  step) and the stack model's step are backward differences, energy factor
  per step 1/(1 + ω²h²), ω = 2π/T: over the half period the energy falls by
  exp(−2π²h/T), so the peak force is low by exp(−π²h/(2T)) and the rebound
  by exp(−π²h/T), first order in the step — halving it halves the error, and
  the two models agree at the same h (to second order: the 2-D impact's first
  step);
- Newton's law with restitution e for an unresolved impact (h ≫ T), and the
  rigid model's rebound e v; the law's docstring's correction
  γ = (1 + e) m* c / h² by hand algebra on one contact;
- statics of a column: the force at each contact is the weight above it, the
  overlap of each spring c F (c = 1/s_i + 1/s_j between logs, 1/s (+ 1/k_s)
  at the shell);
- the kinematics of a log stuck to the turning wall (held from rolling,
  spinning at Ω): it turns with the wall as one rigid body, so its place on
  a lifter's face does not change, and on the shell its overlap is c times
  its weight's normal part plus the centripetal m v²/ρ.
"""

import numpy as np
import pytest

from formulations.drum import Drum, Log
from formulations.drum2d import DISC, SHELL, Discs, Drum2D, Shell, hex_fill
from qpcontact.core.errors import InvalidOptionError

G = 9.81
RHO = 860.0          # green spruce [kg/m³]
E_T = 0.4e9          # spruce across the grain, tangential [Pa]


def _mass(d, length):
    """ρ π d²/4 ℓ [kg] by hand."""
    return RHO * np.pi * np.asarray(d, float) ** 2 / 4.0 * length


def _certified(res):
    assert res.certified.all(), f"uncertified steps {res.uncertified[:5]}"
    assert res.worst_certificate <= 1e-8


# -- 1. head-on impact: the stack model's peak force ------------------------------------

D_PAIR, LENGTH, V1, V2 = np.array([0.12, 0.2]), 1.0, 1.5, -0.5


def _pair_constants():
    m = _mass(D_PAIR, LENGTH)
    m_star = m[0] * m[1] / m.sum()
    c = 2.0 / (2.0 * E_T * LENGTH)             # two log halves in series [m/N]
    T = 2.0 * np.pi * np.sqrt(m_star * c)
    return m, m_star, c, T


def _head_on_2d(h):
    m, _, _, T = _pair_constants()
    x0 = 0.5 * D_PAIR[0] + 0.4 * h * (V1 - V2)   # touch 40 % into the first step
    x1 = -0.5 * D_PAIR[1]
    discs = Discs(D_PAIR, [[-x0, 0.0], [-x1, 0.0]], length=LENGTH,
                  velocities=[[V1, 0.0], [V2, 0.0]])
    res = Drum2D(discs, Shell(2.0), ("log_elasticity",), gravity=0.0, modulus=E_T)\
        .simulate(h, int(round(0.8 * T / h)))
    _certified(res)
    return res


def _head_on_stack(tau):
    logs = [Log.from_wood(d, LENGTH, RHO, E_T) for d in D_PAIR]
    # log 0 below moving up at V1, log 1 above moving down at V2; the shell far away
    drum = Drum(logs, [1.0, 0.4 * tau * (V1 - V2)], [V1, V2], effects=())
    _, _, _, T = _pair_constants()
    res = drum.simulate(tau, int(round(0.8 * T / tau)))
    return res.forces[:, 1].max(), res.velocities[-1]


def test_head_on_peak_force_matches_the_stack_model_and_the_spring():
    m, m_star, c, T = _pair_constants()
    F_spring = np.sqrt(m_star / c) * (V1 - V2)
    lg = Log.from_wood(D_PAIR[0], LENGTH, RHO, E_T)         # the stack model's own data
    assert abs(lg.mass - m[0]) < 1e-12 * m[0] and abs(2.0 / lg.stiffness - c) < 1e-12 * c
    peaks, stack = {}, {}
    for per in (100, 200):
        h = T / per
        res = _head_on_2d(h)
        F = res.force_peak[:, DISC]
        peaks[per] = F.max()
        stack[per] = _head_on_stack(h)[0]
        # the scheme's error, first order: the peak is low by exp(−π²h/(2T)), for
        # the 2-D step and the stack's alike (both backward differences)
        expect = F_spring * np.exp(-np.pi ** 2 * h / (2 * T))
        assert abs(peaks[per] - expect) < 0.1 * (F_spring - expect), (per, peaks[per], expect)
        assert abs(stack[per] - expect) < 0.1 * (F_spring - expect)
        # the contact lasts half a period: steps with force, to a step at each end
        on = np.flatnonzero(F > 0)
        assert np.all(np.diff(on) == 1)
        assert abs((on[-1] - on[0] + 1) * h - T / 2) <= 2 * h
        # elastic: momentum kept, the rebound's loss is the scheme's exp(−π²h/T)
        v = res.velocities[-1, :, 0]
        assert abs(m @ v - m @ [V1, V2]) < 1e-12 * m.sum() * (V1 - V2)
        e_scheme = (v[1] - v[0]) / (V1 - V2)
        e_model = np.exp(-np.pi ** 2 * h / T)
        assert abs(e_scheme - e_model) < 0.1 * (1 - e_model), e_scheme
    # halving h halves the error of either scheme (first order) ...
    for p in (peaks, stack):
        ratio = (F_spring - p[100]) / (F_spring - p[200])
        assert 1.8 < ratio < 2.2, ratio
    # ... so Richardson's 2 F(h/2) − F(h) reaches the spring's √(m*/c) Δv, and the
    # 2-D peak meets the stack's at the same h, the gap shrinking as h² (measured
    # 1.6e-3 and 4e-4 of the force at T/h = 100 and 200)
    for p in (peaks, stack):
        assert abs(2 * p[200] - p[100] - F_spring) < 2e-3 * F_spring
    gap = {per: abs(peaks[per] - stack[per]) for per in peaks}
    assert gap[100] < 2.5e-3 * F_spring and gap[200] < gap[100] / 3, gap


def test_log_dropped_on_an_elastic_shell_matches_the_stack_model():
    d, v, k_s = 0.15, 2.0, 3e8
    m = _mass(d, LENGTH)
    c = 1.0 / (2.0 * E_T * LENGTH) + 1.0 / k_s             # one half and the shell
    T = 2.0 * np.pi * np.sqrt(m * c)
    h = T / 200
    R = 1.0
    y0 = -R + d / 2 + 0.4 * h * v
    discs = Discs([d], [[0.0, y0]], length=LENGTH, velocities=[[0.0, -v]])
    res = Drum2D(discs, Shell(R), ("log_elasticity", "shell_elasticity"), gravity=0.0,
                 modulus=E_T, shell_stiffness=k_s).simulate(h, int(round(0.8 * T / h)))
    _certified(res)
    drum = Drum([Log.from_wood(d, LENGTH, RHO, E_T)], [0.4 * h * v], [-v],
                shell_stiffness=k_s, effects=("shell_elasticity",))
    F_stack = drum.simulate(h, int(round(0.8 * T / h))).forces[:, 0].max()
    F2 = res.force_peak[:, SHELL].max()
    F_spring = np.sqrt(m / c) * v
    assert abs(F2 - F_spring * np.exp(-np.pi ** 2 * h / (2 * T))) < 0.1 * np.pi ** 2 * h / \
        (2 * T) * F_spring
    assert abs(F2 - F_stack) < 1e-3 * F_spring


# -- 2. energy ---------------------------------------------------------------------------

@pytest.mark.slow
def test_resolved_collisions_lose_what_the_implicit_spring_predicts():
    """K + E_el of a gas of discs (no gravity, no friction, e = 1, still
    shell) falls at each collision by (1 − exp(−2π²h/T_k)) ½ m* u_N² — the
    backward spring's step map, T_k the collision's period, u_N its approach
    speed."""
    R, E, n = 0.6, 4e5, 8                    # a soft modulus: T ≈ 19 ms, resolved cheaply
    pos, dia = hex_fill(R, n, 0.12, spread=0.2, seed=1, clearance=0.04)
    discs = Discs(dia, pos, length=LENGTH,
                  velocities=np.random.default_rng(2).normal(0.0, 1.0, (n, 2)))
    m, s = _mass(dia, LENGTH), 2.0 * E * LENGTH
    T_min = 2.0 * np.pi * np.sqrt(m.min() / s)
    h = T_min / 100
    # W + D is positive definite (every contact compliant): the pivoting "bpp" fits
    res = Drum2D(discs, Shell(R), ("log_elasticity",), gravity=0.0, modulus=E)\
        .simulate(h, 1100, method="bpp")
    _certified(res)
    predicted, collisions, touching = 0.0, 0, set()
    for step, c in enumerate(res.contacts):
        now = set()
        for k in np.flatnonzero(c["r_n"] > 0) if c is not None else ():
            i, j = int(c["i"][k]), int(c["j"][k])
            now.add((i, j))
            if (i, j) in touching:
                continue
            v_other = res.velocities[step, j] if j >= 0 else 0.0
            u_n = c["normal"][k] @ (res.velocities[step, i] - v_other)
            m_star, comp = ((m[i] * m[j] / (m[i] + m[j]), 2.0 / s) if j >= 0
                            else (m[i], 1.0 / s))
            T_k = 2.0 * np.pi * np.sqrt(m_star * comp)
            predicted += (1.0 - np.exp(-2 * np.pi ** 2 * h / T_k)) * 0.5 * m_star * u_n ** 2
            collisions += 1
        touching = now
    E_mech = res.kinetic + res.elastic
    lost = E_mech[0] - E_mech[-1]
    assert collisions >= 6
    assert 0.05 * E_mech[0] < lost
    assert abs(lost / predicted - 1.0) < 0.08, (lost, predicted)
    s_ = res.energy_summary()
    assert abs(s_["remainder"]) < 1e-9 * E_mech[0]
    assert abs(s_["impact_loss"] - lost) < 1e-9 * E_mech[0]


def _drop(y_drop, effects, e, h=2e-3, steps=None):
    """A 0.12 m spruce log dropped from rest at height y_drop above its resting
    place on the bottom of a still shell (R = 1 m); (result, mass)."""
    d, R = 0.12, 1.0
    discs = Discs([d], [[0.0, -R + d / 2 + y_drop]], length=LENGTH)
    res = Drum2D(discs, Shell(R), effects, restitution=e, modulus=E_T)\
        .simulate(h, steps or int(1.1 * np.sqrt(2 * y_drop / G) / h) + 8)
    _certified(res)
    return res, _mass(d, LENGTH)


def _impact_step(res):
    return int(np.flatnonzero(res.force_peak[:, SHELL] > 0)[0])


@pytest.mark.parametrize("e", [1.0, 0.5, 0.2, 0.0])
def test_unresolved_impact_is_newtons_law_whatever_the_phase(e):
    """h = 2 ms against T = 2π √(m/s) ≈ 0.69 ms: one step carries the impact,
    u⁺ = (γ u_free − e u⁻)/(1 + γ), γ = (1 + e) m c/h² (hand algebra on the
    law with the gap counted from the step's start), whichever fraction of
    the step the log falls through before touching; the rigid model gives
    −e u⁻ exactly.  With θ = 1 positions no overlap is left to push out
    afterwards, for small e too (with the midpoint an e = 0 log rebounded at 0
    to 0.43 of its speed, by phase)."""
    h = 2e-3
    effects = ("log_elasticity",) + (("damping",) if e < 1 else ())
    m = _mass(0.12, LENGTH)
    c = 1.0 / (2.0 * E_T * LENGTH)
    T = 2.0 * np.pi * np.sqrt(m * c)
    assert 0.3 < T / h < 0.4
    gamma = (1 + e) * m * c / h ** 2
    for y in 0.05 + np.linspace(0.0, 1.0, 7) * 0.0036:   # phases across a step
        res, _ = _drop(y, effects, e)
        k = _impact_step(res)
        vy = res.velocities[:, 0, 1]
        u_minus, u_free = vy[k], vy[k] - G * h
        expect = (gamma * u_free - e * u_minus) / (1 + gamma)
        assert abs(vy[k + 1] - expect) < 1e-7 * abs(u_minus), (y, vy[k + 1], expect)
        assert abs(vy[k + 1] / -u_minus - e) < 1.05 * (1 + e) * gamma
        # free flight after it, nothing pushed out: no impulse until the log,
        # stopped up to a step early (as the rigid law stops it), falls back
        touch = np.flatnonzero(res.force_peak[k + 1:, SHELL] > 0)
        free = min(4, int(touch[0]) if touch.size else 4)
        assert free >= (1 if e == 0 else 4)
        assert np.allclose(vy[k + 2:k + 2 + free], vy[k + 1] - G * h * np.arange(1, free + 1),
                           rtol=0, atol=1e-9)
        rigid, _ = _drop(y, ("damping",) if e < 1 else (), e, steps=k + 3)
        kr = _impact_step(rigid)
        vr = rigid.velocities[:, 0, 1]
        assert abs(vr[kr + 1] + e * vr[kr]) < 1e-9


def test_unresolved_elastic_bounces_keep_newtons_energy():
    """e = 1, h = 2 ms: each bounce is Newton's with e_eff = (1 − γ)/(1 + γ)
    (γ = 2 m c/h², 0.6 % here), so after n bounces the energy above the
    resting height is e_eff^(2n) of the drop's; the rigid model keeps all of
    it (tests/formulations/drum2d/test_drum2d.py)."""
    h, y0 = 2e-3, 0.1
    res, m = _drop(y0, ("log_elasticity",), 1.0, h=h, steps=900)
    c = 1.0 / (2.0 * E_T * LENGTH)
    gamma = 2 * m * c / h ** 2
    hits = np.flatnonzero(res.force_peak[:, SHELL] > 0)
    assert hits.size >= 5 and np.all(np.diff(hits) > 10)          # separate bounces
    vy = res.velocities[:, 0, 1]
    for k in hits:
        expect = (gamma * (vy[k] - G * h) - vy[k]) / (1 + gamma)
        assert abs(vy[k + 1] - expect) < 1e-7 * abs(vy[k])
    e_eff = (1 - gamma) / (1 + gamma)
    y_rest = -1.0 + 0.06
    above = res.kinetic + m * G * (res.positions[:, 0, 1] - y_rest) + res.elastic
    n = hits.size
    kept = above[hits[-1] + 5] / above[0]
    assert abs(kept - e_eff ** (2 * n)) < 0.1 * (1 - e_eff ** (2 * n)), (kept, e_eff ** (2 * n))
    assert abs(res.energy_summary()["remainder"]) < 1e-9 * above[0]


@pytest.mark.slow
def test_energy_closes_on_a_settling_compliant_bed():
    """40 logs with lifters, e = 1, no friction, still shell, h = 2 ms: with
    rigid contacts K + P is kept to rounding (tests/formulations/drum2d/test_drum2d.py); with
    compliant ones the closed contacts' implicit springs damp the bed
    (laws.py), and every joule lost is booked as impact loss.  No step
    creates energy: with e = 1 a contact loses ½ c (F − F_prev)² + F δ in a
    step (from −r_N (u_N⁻ + u_N⁺)/2 = F (ĝ + c F) and ΔE_el; δ >= 0 how far
    its gap at the step's start exceeds −c F_prev), and a contact that opens
    gives up ½ c F_prev²."""
    pos, dia = hex_fill(1.5, 40, 0.2, spread=0.2, seed=4, clearance=0.03)
    rng = np.random.default_rng(5)
    discs = Discs(dia, pos, length=1.0, velocities=rng.normal(0, 1.0, (40, 2)),
                  spins=rng.normal(0, 3.0, 40))
    shell = Shell(1.5, lifter_angles=[0.0, np.pi], lifter_height=0.15, lifter_half_width=0.01)
    res = Drum2D(discs, shell, ("log_elasticity",)).simulate(2e-3, 200)
    _certified(res)
    E = res.kinetic + res.potential + res.elastic
    scale = float(discs.masses.sum() * G * 1.5)
    s_ = res.energy_summary()
    assert E[-1] < E[0]
    assert abs(s_["remainder"]) < 1e-9 * scale
    # the θ = 1 positions' term S (stepper) is booked beside the contacts' loss
    assert abs((E[0] - E[-1]) - s_["impact_loss"] + s_["scheme"]) < 1e-9 * scale
    assert abs(s_["scheme"]) < 1e-2 * (E[0] - E[-1])
    assert np.all(res.impact_loss >= -1e-9 * scale)


# -- 4., 5. statics -----------------------------------------------------------------------

def _settled(diameters, effects, **kw):
    """A column of discs on the bottom of a still shell (R = 1 m), started
    touching, settled with e = 0 (and friction, so that the warm start runs)."""
    R = 1.0
    y = -R + np.cumsum(diameters) - np.asarray(diameters) / 2
    discs = Discs(diameters, np.column_stack([np.zeros(len(diameters)), y]), length=LENGTH)
    h = 2e-3
    res = Drum2D(discs, Shell(R), ("friction", "damping") + effects, restitution=0.0, **kw)\
        .simulate(h, 80)
    _certified(res)
    return res, _mass(diameters, LENGTH), h


def test_column_statics_forces_are_the_weights_and_overlaps_the_springs():
    d = np.array([0.12, 0.18, 0.15, 0.1])
    res, m, h = _settled(d, ("log_elasticity",))
    assert not res.fallback.any() and set(res.method) == {"nsgs-newton"}
    c = res.contacts[-1]
    s = 2.0 * E_T * LENGTH
    assert c["i"].size == d.size
    for k in range(d.size):
        i, j = int(c["i"][k]), int(c["j"][k])
        above = m[max(i, j):].sum() if j >= 0 else m.sum()
        comp = 2.0 / s if j >= 0 else 1.0 / s
        F = c["r_n"][k] / h
        assert abs(F - G * above) < 1e-6 * G * above, (i, j, F, G * above)
        assert abs(-c["gap"][k] - comp * F) < 1e-5 * comp * F, (i, j, c["gap"][k], comp * F)
    assert np.all(np.abs(res.velocities[-1]) < 1e-6)


@pytest.mark.parametrize("logs", [True, False])
def test_elastic_shell_adds_its_compliance(logs):
    k_s = 2e8
    effects = ("shell_elasticity",) + (("log_elasticity",) if logs else ())
    res, m, h = _settled(np.array([0.15]), effects, shell_stiffness=k_s)
    c = res.contacts[-1]
    F = c["r_n"][0] / h
    comp = 1.0 / k_s + (1.0 / (2.0 * E_T * LENGTH) if logs else 0.0)
    assert abs(F - G * m[0]) < 1e-6 * G * m[0]
    assert abs(-c["gap"][0] - comp * F) < 1e-5 * comp * F


# -- 6. bad input ---------------------------------------------------------------------------

@pytest.mark.parametrize("kw, match", [
    (dict(effects=("shell_elasticity",)), "shell_stiffness"),
    (dict(effects=("log_elasticity",), modulus=0.0), "modulus"),
    (dict(effects=("log_elasticity",), modulus=-1e9), "modulus"),
    (dict(effects=("log_elasticity",), modulus=np.nan), "modulus"),
    (dict(effects=("shell_elasticity",), shell_stiffness=-1e8), "shell_stiffness"),
    (dict(effects=("shell_elasticity",), shell_stiffness=0.0), "shell_stiffness"),
    (dict(effects=("shell_elasticity",), shell_stiffness=np.inf), "shell_stiffness"),
])
def test_bad_compliance_input_is_named(kw, match):
    discs = Discs([0.1], [[0.0, -0.5]])
    with pytest.raises(InvalidOptionError, match=match):
        Drum2D(discs, Shell(1.0), **kw)



def test_step_problem_is_the_problem_each_step_solved():
    """Drum2D.step_problem rebuilt from the state and the active contacts that
    on_step hands out: the run's own impulses certify on it (what the
    benchmark's sampled steps rely on), with friction and springs."""
    import qpcontact

    pos, dia = hex_fill(0.6, 12, 0.12, spread=0.2, seed=3, clearance=0.005)
    model = Drum2D(Discs(dia, pos, length=LENGTH), Shell(0.6, omega=1.0),
                   ("friction", "rotation", "damping", "log_elasticity"), restitution=0.3)
    seen = []
    res = model.simulate(2e-3, 150, keep_contacts=False,
                         on_step=lambda n, c, r: seen.append((n - 1, c, r.copy())))
    _certified(res)
    checked = 0
    for s, c, r in seen[50::10]:
        if not (r[0::2] > 0).any():
            continue
        v = np.column_stack([res.velocities[s], res.spins[s]]).ravel()
        prob = model.step_problem(c, v, 2e-3)
        assert prob.n_contacts == c.m
        assert qpcontact.certify(prob, r).error <= 1e-9
        wrong = r.copy()
        wrong[0::2] *= 1.01                                      # and it can fail
        assert qpcontact.certify(prob, wrong).error > 1e-6
        checked += 1
    assert checked >= 3


# -- a log stuck to the turning wall: carried as a rigid body -------------------------------

def _carried(shell, centre, mu, steps=300, h=2e-3, d=0.2):
    """A log held from rolling, spinning with the shell (Ω) and moving as its
    material point at ``centre`` [m] would: stuck from the start."""
    om = shell.omega
    v = om * np.array([-centre[1], centre[0]])
    discs = Discs([d], [centre], length=1.0, velocities=[v], spins=[om], spin_locked=True)
    model = Drum2D(discs, shell, ("friction", "rotation", "damping", "log_elasticity"),
                   mu_shell=mu, mu_lifter=mu, restitution=0.3, modulus=E_T)
    res = model.simulate(h, steps)
    assert res.certified.all()
    return res, discs.masses[0]


def test_a_log_carried_on_the_shell_sits_at_its_springs_overlap():
    """Carried 30° up the shell (stuck at μ = 0.8), the log's overlap is its
    spring's c F, F = m g sin(−θ) + m Ω² ρ by hand (θ and ρ its centre's polar
    angle and radius: it turns with the shell as one body).  The step's gap
    law taken to first order only left it deeper by the chord's ρ (Ω h)²/2,
    1.6 µm here against c F = 0.35 µm (5.6 times the hand overlap)."""
    R, d, om, h = 1.0, 0.2, 0.94, 2e-3
    rho = R - d / 2
    th0 = np.radians(-80.0)
    res, m = _carried(Shell(R, omega=om), rho * np.array([np.cos(th0), np.sin(th0)]), 0.8, d=d)
    c = 1.0 / (2 * E_T * 1.0)                       # 1/s at the rigid steel, ℓ = 1 m
    for s in (100, 200, 300):
        x = res.positions[s, 0]
        r, th = np.hypot(*x), np.arctan2(x[1], x[0])
        assert abs(th - (th0 + om * s * h)) < 1e-5     # carried (9 µm), not sliding
        force = m * G * -np.sin(th) + m * om ** 2 * r
        assert abs((r + d / 2 - R) - c * force) < 0.01 * c * force


def test_a_log_stuck_on_a_lifter_face_is_carried_without_creeping_along_it():
    """A log resting on a lifter's face (stuck, μ = 0.8, clear of the shell)
    keeps its place along the face while the drum turns 32°: stick is the two
    material points moving together over the step.  With the face's velocity
    at the step's start in place of its chord the log crept out along the face
    at ρ Ω² h/2 (0.71 mm/s: 0.42 mm over the 0.6 s)."""
    R, om, d, b = 1.0, 0.94, 0.1, 0.02
    shell = Shell(R, omega=om, lifter_angles=[0.0], lifter_height=0.4, lifter_half_width=b)
    res, m = _carried(shell, np.array([0.8, b + d / 2]), 0.8, d=d)
    for s in (100, 200, 300):
        a = om * s * 2e-3
        x = res.positions[s, 0]
        assert abs(x @ [np.cos(a), np.sin(a)] - 0.8) < 1e-6
        # pressed onto the face by its weight's normal part: the spring's overlap
        overlap = b + d / 2 - x @ [-np.sin(a), np.cos(a)]
        assert 0 < overlap < 2 * m * G / (2 * E_T)
