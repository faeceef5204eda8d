"""The penalty formulation (Nikolsky et al. 2012) against hand-computed
accelerations, the exact LCP (pivoting), Gauss' principle (a QP in the
accelerations), and the KKT threshold for μ."""

from __future__ import annotations

import numpy as np
import pytest
from qpsolvers import Problem

import qpcontact
from qpcontact.testing import assert_lcp_solution
from formulations.mechanisms import Mechanism, ramming_scene
from formulations.mechanisms.penalty import (PenaltyStep, exact_lcp, gauss_qp, mu_threshold,
                                             penalty_qp, solve_penalty)
from qpcontact import InvalidProblemError, NotConvexError

QP_BACKENDS = [m for m in ("clarabel", "osqp", "piqp", "daqp", "quadprog", "proxqp", "highs")
               if m in qpcontact.methods()]


def _two_bodies(F1, F2, m1=2.0, m2=3.0):
    """Bodies on a line touching (Φ = x2 - x1 - L = 0, at rest): J = [-1, 1], B = D = 0."""
    return PenaltyStep(np.diag([m1, m2]), [F1, F2], [[-1.0, 1.0]], [0.0])


@pytest.mark.parametrize("method", QP_BACKENDS)
def test_two_bodies_pressed_and_pulled_exact_by_hand(method):
    m1, m2 = 2.0, 3.0
    # pressed: they move together, a = (F1 + F2)/(m1 + m2), reaction on body 2 = m2 a - F2
    F1, F2 = 10.0, -5.0
    a = (F1 + F2) / (m1 + m2)
    res = solve_penalty(_two_bodies(F1, F2), mu=1e3, method=method)
    assert res.ok, res.message
    np.testing.assert_allclose(res.lam, [m2 * a - F2], rtol=1e-8)
    np.testing.assert_allclose(res.accelerations, [a, a], rtol=1e-8)
    # pulled apart: no reaction, free accelerations
    res = solve_penalty(_two_bodies(-10.0, 5.0), mu=1e3, method=method)
    assert res.ok, res.message
    np.testing.assert_allclose(res.lam, [0.0], atol=1e-9)
    np.testing.assert_allclose(res.accelerations, [-10.0 / m1, 5.0 / m2], rtol=1e-9)


@pytest.mark.parametrize("method", ["lemke", "energy", "bpp"])
def test_two_bodies_by_the_pivoting_reference(method):
    sol = qpcontact.solve(exact_lcp(_two_bodies(10.0, -5.0)), method=method)
    assert sol.ok
    np.testing.assert_allclose(sol.z, [3.0 * 1.0 + 5.0], rtol=1e-12)


def _random_step(seed, n=7, nu=4, rigid=False):
    rng = np.random.default_rng(seed)
    R = rng.standard_normal((n, n))
    G = R @ R.T + n * np.eye(n)
    J = rng.standard_normal((nu, n))
    C = None if rigid else np.diag(rng.uniform(1e-3, 1e-2, nu))
    return PenaltyStep(G, 10 * rng.standard_normal(n), J, rng.standard_normal(nu), C=C,
                       P_y=None if rigid else rng.standard_normal(nu))


@pytest.mark.parametrize("seed", range(8))
def test_active_set_matches_above_the_threshold_and_not_below(seed):
    step = _random_step(seed)
    exact = qpcontact.solve(exact_lcp(step), method="lemke")
    assert exact.ok
    mu_star = mu_threshold(step, exact.z)
    assert np.isfinite(mu_star)
    scale = max(exact.z.max(), np.abs(step.b).max() / np.abs(step.A).max())  # certificate's sigma_z
    above = solve_penalty(step, mu=10 * max(mu_star, 1e-6), method="clarabel")
    assert above.ok, above.message
    assert np.array_equal(above.lam > 1e-7 * scale, exact.z > 0)
    np.testing.assert_allclose(above.lam, exact.z, atol=1e-8 * scale)
    if mu_star > 0:
        below = solve_penalty(step, mu=mu_star / 10, method="clarabel")
        assert not below.ok  # never reported as the mechanics solution
        diff = np.abs(below.lam - exact.z).max() / scale
        changed = np.flatnonzero((below.lam > 1e-7 * scale) != (exact.z > 0))
        # how it differs: the reactions move (and possibly the active set)
        assert diff > 1e-4, f"mu*/10 still gave lambda*, diff {diff:.1e}, active-set changes {changed}"


def test_threshold_brackets_the_measured_transition():
    step = _random_step(0)
    exact = qpcontact.solve(exact_lcp(step), method="lemke")
    mu_star = mu_threshold(step, exact.z)
    assert solve_penalty(step, mu=1.05 * mu_star, method="daqp").ok
    assert not solve_penalty(step, mu=0.95 * mu_star, method="daqp").ok


@pytest.mark.parametrize("seed", range(4))
def test_gauss_principle_in_the_rigid_case(seed):
    step = _random_step(seed, rigid=True)
    pen = solve_penalty(step, mu="auto", method="clarabel")
    assert pen.ok, pen.message
    gauss = qpcontact.solve(gauss_qp(step), method="quadprog" if "quadprog" in QP_BACKENDS
                            else "clarabel", accuracy="high")
    assert gauss.ok
    scale = np.abs(gauss.x).max()
    np.testing.assert_allclose(pen.accelerations, gauss.x, atol=1e-7 * scale)
    np.testing.assert_allclose(pen.lam, gauss.z, atol=1e-7 * max(np.abs(gauss.z).max(), 1.0))


@pytest.mark.parametrize("mu", [1e12, 1e16])
@pytest.mark.parametrize("singular_A", [False, True])
def test_huge_mu_is_right_or_flagged(mu, singular_A, record_property):
    # singular A: more contacts than degrees of freedom (W = C + 2 mu A loses C)
    step = _random_step(3, n=4 if singular_A else 7, nu=6 if singular_A else 4)
    exact = qpcontact.solve(exact_lcp(step), method="lemke")
    outcomes = {}
    # ProxQP iterates to its limit here (38 s measured at mu = 1e16): left out.
    for method in (m for m in QP_BACKENDS if m != "proxqp"):
        res = solve_penalty(step, mu=mu, method=method)
        if res.ok:
            # a certified answer must be right: it solves the exact LCP
            assert_lcp_solution(exact_lcp(step), res.lam, tol=1e-9)
            if exact.ok and not singular_A:
                np.testing.assert_allclose(res.lam, exact.z, atol=1e-7 * exact.z.max())
            outcomes[method] = "right"
        else:
            assert res.status == "inaccurate" and res.flags and res.message
            outcomes[method] = "flagged"
    if singular_A and mu >= 1e16:
        assert solve_penalty(step, mu=mu, method=QP_BACKENDS[0]).cond_W > 1e13
    record_property("outcomes", str(outcomes))


def test_auto_mu_reports_the_choice():
    step = _random_step(5)
    res = solve_penalty(step, mu="auto", method="piqp")
    assert res.ok and res.mu == res.mu_tried[-1] and len(res.mu_tried) >= 2
    assert res.mu > mu_threshold(step, res.lam)


def test_penalty_qp_is_a_qpsolvers_problem_and_inputs_are_validated():
    prob = penalty_qp(np.diag([2.0, 3.0]), [1.0, -1.0], [[-1.0, 1.0]], np.eye(1), [0.0], [0.0],
                      [0.0], 10.0)
    assert isinstance(prob, Problem)
    np.testing.assert_allclose(prob.P, np.eye(1) + 2 * 10.0 * (1 / 2 + 1 / 3))
    with pytest.raises(InvalidProblemError, match="J"):
        PenaltyStep(np.eye(2), [0, 0], [[1.0, 0.0, 0.0]], [0.0])
    with pytest.raises(NotConvexError, match="G"):
        PenaltyStep(np.array([[1.0, 2.0], [2.0, 1.0]]), [0, 0], [[1.0, 0.0]], [0.0])
    with pytest.raises(NotConvexError, match="C"):
        PenaltyStep(np.eye(2), [0, 0], [[1.0, 0.0]], [0.0], C=[[-1.0]])
    with pytest.raises(InvalidProblemError, match="B"):
        PenaltyStep(np.eye(2), [0, 0], [[1.0, 0.0]], [0.0, 1.0])
    with pytest.raises(qpcontact.InvalidOptionError, match="mu"):
        penalty_qp(np.eye(2), [0, 0], [[1.0, 0.0]], None, [0.0], [0.0], [0.0], -1.0)


def test_sparse_inertia_is_supported():
    import scipy.sparse as sp

    dense = _random_step(1, rigid=True)
    sparse = PenaltyStep(sp.csc_matrix(dense.G), dense.Q, dense.J, dense.B)
    np.testing.assert_allclose(sparse.A, dense.A, rtol=1e-12)


# --- the mechanism simulation ---------------------------------------------------------

def _momentum_check(res):
    """Bolt + cartridge: total momentum change per step = h x (spring force),
    as long as the chamber is not touched (the contact force is internal)."""
    mech = res.mechanism
    masses = np.diag(mech.inertia())
    worst = 0.0
    for i in range(1, res.t.size):
        if res.reactions[i, 1] > 0:
            continue
        Q = mech.generalized_forces(res.t[i - 1], res.q[i - 1], res.v[i - 1])
        dp = masses @ (res.v[i] - res.v[i - 1])
        worst = max(worst, abs(dp - res.h * Q.sum()) / max(masses @ np.abs(res.v[i]), 1e-12))
    return worst


@pytest.mark.slow   # two full runs of the scene (about a minute); make test runs the scene
# through its file (tests/scenes) and the penalty routes against the exact LCP
def test_ramming_scene_no_penetration_momentum_and_backend_independence():
    mech, h, steps, dt = ramming_scene()
    a = mech.simulate(h, steps, lookahead=dt, method="piqp")
    mech2, *_ = ramming_scene()
    b = mech2.simulate(h, steps, lookahead=dt, method="clarabel")
    v_max = np.abs(a.v).max()
    tol = h * v_max  # module docstring: a plastic-ish impact penetrates ~ h |v| / 2
    assert a.gaps.min() >= -tol
    on = a.reactions > 1e-9 * a.reactions.max()  # QP noise is not a contact
    onsets = (on[1:] & ~on[:-1]).sum(axis=0)
    assert onsets[0] >= 1 and onsets[1] >= 2   # bolt hits cartridge; cartridge re-contacts chamber
    assert _momentum_check(a) < 1e-9
    np.testing.assert_allclose(a.q, b.q, atol=1e-9 * np.abs(a.q).max())
    # at rest: the spring holds bolt and cartridge against the chamber
    spring = 800.0 * (0.240 - (a.q[-1, 0] + 0.120))
    np.testing.assert_allclose(a.reactions[-1], [spring, spring], rtol=1e-6)


@pytest.mark.slow
def test_penalty_and_exact_lcp_routes_give_the_same_trajectory():
    mech, h, steps, dt = ramming_scene()
    pen = mech.simulate(h, 600, lookahead=dt, method="daqp")
    lcp = ramming_scene()[0].simulate(h, 600, lookahead=dt, route="lcp")
    np.testing.assert_allclose(pen.q, lcp.q, atol=1e-10)


def test_mechanism_effects_are_only_what_is_named():
    with pytest.raises(InvalidProblemError, match="springs"):
        Mechanism(effects=("gravity", "friction"))
    m = Mechanism(effects=("gravity",))
    m.add_body("a", 1.0)
    with pytest.raises(InvalidProblemError, match="'springs'"):
        m.add_spring("a", None, 10.0, 0.1)
    with pytest.raises(InvalidProblemError, match="'compliance'"):
        m.add_contact("c", "a", None, compliance=1e-6)
    compliant, h, steps, dt = ramming_scene(effects=("springs", "compliance"))
    assert compliant.compliance().shape == (2, 2)
    assert ramming_scene()[0].compliance() is None


def test_rotating_mechanism_step_data_against_dense_and_finite_differences():
    """A swinging bar (x, y, θ on a planar joint) with a hanging link on it and
    a wall contact at the link's tip: the step data from the multibody model
    (O(N) operator for G, Q by Newton-Euler, J and D by point Jacobians)
    against a dense G and finite differences of Φ along the motion."""
    m = Mechanism(effects=("gravity", "springs"))
    m.add_body("bar", 2.0, 0.05, dofs=("x", "y", "theta"), position=(0.0, 0.0, 0.3),
               velocity=(0.2, -0.1, 1.5))
    m.add_body("link", 0.5, 0.01, dofs=("theta",), position=(0.4, 0.0, -0.8), velocity=(0, 0, -2.0),
               parent="bar")
    m.add_spring("bar", None, 50.0, 0.1, point_a=(-0.2, 0.0), point_b=(-0.5, 0.2))
    m.add_contact("wall", None, "link", normal=(-1.0, 0.0), point_a=(0.9, 0.0), point_b=(0.3, 0.0))
    q, v = m.initial_state()
    Gop, Q, J, D, Phi = m.step_data(0.0, q, v)
    G = m.inertia(q)
    np.testing.assert_allclose(Gop.solve(J.T), np.linalg.solve(G, J.T), rtol=1e-12, atol=1e-14)
    a = np.linalg.solve(G, Q)                          # free motion: q̈ = G⁻¹Q
    from formulations import multibody as mb
    eps = 1e-5

    def phi(qq):
        return m.constraints(qq, np.zeros_like(v))[0]

    qp = mb.integrate(m.model, q, eps * v + 0.5 * eps ** 2 * a)
    qm = mb.integrate(m.model, q, -eps * v + 0.5 * eps ** 2 * a)
    np.testing.assert_allclose((phi(qp) - phi(qm)) / (2 * eps), J @ v, atol=1e-8)
    np.testing.assert_allclose((phi(qp) - 2 * phi(q) + phi(qm)) / eps ** 2, J @ a + D, atol=1e-4)
    # the contact stepper, while the contact stays open, follows the ODE
    # G q̈ = Q integrated independently (SciPy, tight tolerance), error O(h)
    from scipy.integrate import solve_ivp
    h, steps = 2e-5, 250
    res = m.simulate(h, steps, route="lcp")
    assert np.all(res.gaps > 0) and np.all(res.reactions == 0)

    def rhs(t, y):
        qq, vv = y[:4], y[4:]
        return np.concatenate([vv, np.linalg.solve(m.inertia(qq), m.generalized_forces(t, qq, vv))])

    ref = solve_ivp(rhs, (0, h * steps), np.concatenate([q, v]), rtol=1e-11, atol=1e-12)
    np.testing.assert_allclose(res.q[-1], ref.y[:4, -1], atol=2e-3 * h)   # measured 5e-4 h
