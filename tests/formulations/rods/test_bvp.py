"""The BVP solver (Pustovoy, Levin & Krasnorutskiy 2014) against exact
elliptic-integral solutions of the elastica, observed orders on a problem with
a known solution, and SciPy."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_bvp
from scipy.optimize import brentq
from scipy.special import ellipe, ellipeinc, ellipk, ellipkinc

from formulations import rods
from formulations.rods import bvp


def _analytic_cantilever(alpha):
    """δ_v/L for the tip-loaded cantilever (the elliptic-integral closed form)."""
    def phi1(m):
        return np.arcsin(1.0 / np.sqrt(2.0 * m))

    def gap(theta):
        m = (1 + np.sin(theta)) / 2            # k² (scipy's parameter)
        return ellipk(m) - ellipkinc(phi1(m), m) - np.sqrt(alpha)

    theta = brentq(gap, 1e-12, np.pi / 2 - 1e-14)
    m = (1 + np.sin(theta)) / 2
    return 1 - 2 / np.sqrt(alpha) * (ellipe(m) - ellipeinc(phi1(m), m))


@pytest.mark.parametrize("alpha,printed", [(1, 0.301721), (2, 0.493457), (5, 0.713792),
                                           (10, 0.810609), (100, 0.941421)])
def test_cantilever_matches_elliptic_integrals(alpha, printed):
    exact = _analytic_cantilever(alpha)
    assert exact == pytest.approx(printed, abs=5e-7)  # our closed form = the printed table
    res = rods.cantilever(alpha, tol=1e-8)
    assert res.ok, res.message
    assert rods.tip_deflection(res) == pytest.approx(exact, abs=1e-6)


def test_cantilever_alpha_1e4_from_a_straight_guess_by_continuation():
    direct = bvp.solve(lambda s, Y: rods.cantilever_f(s, Y, 1e4), rods.clamped_free_bc,
                       np.linspace(0, 1, 81), np.zeros(4))
    assert not direct.ok          # Newton alone does not get there ...
    res = rods.cantilever(1e4, tol=1e-8)
    assert res.ok, res.message    # ... continuation does, and says so only when it did
    assert rods.tip_deflection(res) == pytest.approx(_analytic_cantilever(1e4), abs=1e-6)


def test_column_buckled_branch_past_alpha_10():
    res, path = rods.column(10.0, tol=1e-9)
    assert res.ok, res.message
    theta_L = res.y[0, -1]
    assert abs(theta_L) == pytest.approx(2.795729, abs=1e-5)
    # every point of the path is on the analytic branch alpha = K(k)^2, k = sin(theta_L / 2)
    for g, Y in zip(path.gammas[::10], path.ys[::10]):
        k = np.sin(abs(Y[0, -1]) / 2)
        assert ellipk(k * k) ** 2 == pytest.approx(g, rel=2e-3)


def test_observed_orders_two_four_and_six():
    # y'' = -y on [0, 1], y(0) = 0, y'(1) = cos 1: y = sin s
    f = lambda s, Y: np.array([Y[1], -Y[0]])  # noqa: E731
    bc = lambda a, b: np.array([a[0], b[1] - np.cos(1.0)])  # noqa: E731
    errs = {0: [], 1: [], 2: []}
    for N in (10, 20, 40):
        mesh = np.linspace(0, 1, N + 1)
        for c in errs:
            r = bvp.solve(f, bc, mesh, np.zeros(2), corrections=c, max_refinements=0, tol=1e-15)
            assert r.order == 2 + 2 * c
            errs[c].append(np.max(np.abs(r.y[0] - np.sin(mesh))))
    orders = {c: np.log2(np.array(e[:-1]) / np.array(e[1:])) for c, e in errs.items()}
    assert np.all(np.abs(orders[0] - 2) < 0.1), orders
    assert np.all(np.abs(orders[1] - 4) < 0.3), orders
    assert np.all(np.abs(orders[2] - 6) < 0.5), orders


def test_error_estimate_is_honest_and_refinement_is_local():
    """A boundary layer: ε y'' = y, y(0) = 1, y(1) = 0 (ε = 1e-3), exact
    y = sinh((1 - s)/√ε)/sinh(1/√ε).  The estimate must bound the true error
    and the added nodes must crowd into the layer at s = 0."""
    eps = 1e-3
    f = lambda s, Y: np.array([Y[1], Y[0] / eps])  # noqa: E731
    bc = lambda a, b: np.array([a[0] - 1.0, b[0]])  # noqa: E731
    r = bvp.solve(f, bc, np.linspace(0, 1, 11), np.zeros(2), tol=1e-7)
    assert r.ok, r.message
    k = 1 / np.sqrt(eps)
    exact = np.sinh(k * (1 - r.mesh)) / np.sinh(k)
    scale = max(1.0, np.abs(r.y).max())
    assert np.abs(r.y[0] - exact).max() / scale <= r.error_estimate <= 1e-7
    h = np.diff(r.mesh)
    assert h[0] < h[-1] / 4              # refined where the layer is, not everywhere


def test_same_answer_as_scipy_solve_bvp():
    alpha = 3.0
    mesh = np.linspace(0, 1, 41)
    f = lambda s, Y: rods.cantilever_f(s, Y, alpha)  # noqa: E731
    ref = solve_bvp(f, rods.clamped_free_bc, mesh, np.zeros((4, mesh.size)), tol=1e-10,
                    max_nodes=10000)
    assert ref.success
    ours = bvp.solve(f, rods.clamped_free_bc, mesh, np.zeros(4), tol=1e-9)
    assert ours.ok
    # compare at our nodes with SciPy's own (cubic) interpolant
    np.testing.assert_allclose(ours.y, ref.sol(ours.mesh), atol=1e-7)


def test_bad_input_is_explained():
    from qpcontact import InvalidProblemError

    with pytest.raises(InvalidProblemError, match="mesh"):
        bvp.solve(lambda s, Y: Y, lambda a, b: a, [0, 1], np.zeros(1))
    with pytest.raises(InvalidProblemError, match="residuals"):
        bvp.solve(lambda s, Y: Y, lambda a, b: np.r_[a, b], np.linspace(0, 1, 5), np.zeros(1))


def test_pinned_column_branch_against_the_exact_elastica():
    # pinned-pinned: alpha = 4 K(k)^2, k = sin(theta_0 / 2), Euler load pi^2
    res, _ = rods.column(20.0, ends="pinned-pinned", tol=1e-9)
    assert res.ok, res.message
    k = np.sin(abs(res.y[0, 0]) / 2)
    assert 4 * ellipk(k * k) ** 2 == pytest.approx(20.0, rel=1e-7)
    np.testing.assert_allclose(res.y[3, -1], 0.0, atol=1e-9)   # the far pin stays on the axis
    with pytest.raises(Exception, match="Euler load"):
        rods.column(5.0, ends="pinned-pinned")


def _shoot(alpha, follower, beta):
    """Independent route: shooting with solve_ivp on the unknown root curvature
    (and, for a follower load, the tip angle), solved by fsolve."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import fsolve

    def rhs(s, y, thL):
        th, ka, x, yy = y
        fx, fy = (np.sin(thL), -np.cos(thL)) if follower else (0.0, -1.0)
        ft = fx * np.cos(th) + fy * np.sin(th)
        cross = np.cos(th) * fy - np.sin(th) * fx
        st = 1 + alpha * beta * ft
        return [ka, -alpha * st * cross, st * np.cos(th), st * np.sin(th)]

    def miss(u):
        ka0, thL = u
        sol = solve_ivp(rhs, (0, 1), [0, ka0, 0, 0], args=(thL,), rtol=1e-12, atol=1e-12)
        th1, ka1 = sol.y[0, -1], sol.y[1, -1]
        return [ka1, (thL - th1) if follower else 0.0]

    u = fsolve(miss, [-alpha / 2, -0.5], xtol=1e-13)
    sol = solve_ivp(rhs, (0, 1), [0, u[0], 0, 0], args=(u[1],), rtol=1e-12, atol=1e-12)
    return -sol.y[3, -1], sol.y[2, -1]


@pytest.mark.parametrize("follower,beta", [(False, 0.0), (True, 0.0), (False, 0.01), (True, 0.01)])
def test_follower_and_extensible_cantilever_against_shooting(follower, beta):
    alpha = 2.0
    res = rods.cantilever_general(alpha, follower=follower, extensibility=beta, tol=1e-9)
    assert res.ok, res.message
    dv, xt = _shoot(alpha, follower, beta)
    assert -res.y[3, -1] == pytest.approx(dv, abs=1e-7)
    assert res.y[2, -1] == pytest.approx(xt, abs=1e-7)
    if not follower and beta == 0.0:   # the dead-load case is the elastica above
        assert -res.y[3, -1] == pytest.approx(0.493457, abs=1e-6)


def test_spatial_rod_reduces_to_the_planar_elastica():
    res = rods.spatial_cantilever(force=(0.0, -2.0, 0.0), tol=1e-9)   # alpha = 2 in the x-y plane
    assert res.ok, res.message
    assert -res.y[1, -1] == pytest.approx(0.493457, abs=1e-6)
    np.testing.assert_allclose(res.y[2], 0.0, atol=1e-12)               # stays in its plane
    np.testing.assert_allclose(np.sum(res.y[3:7] ** 2, axis=0), 1.0, atol=1e-9)  # unit quaternion


def test_spatial_rod_pure_bending_and_torsion_exactly():
    mu = 1.2   # end moment about z: a circular arc of curvature mu
    res = rods.spatial_cantilever(moment=(0.0, 0.0, mu), tol=1e-10)
    assert res.ok, res.message
    np.testing.assert_allclose(res.y[0:3, -1], [np.sin(mu) / mu, (1 - np.cos(mu)) / mu, 0.0], atol=1e-8)
    tau, ratio = 0.7, 0.8   # end moment about the tangent: twist angle tau L / GJ, tip unmoved
    res = rods.spatial_cantilever(moment=(tau, 0.0, 0.0), torsion_ratio=ratio, tol=1e-10)
    assert res.ok, res.message
    np.testing.assert_allclose(res.y[0:3, -1], [1.0, 0.0, 0.0], atol=1e-10)
    angle = 2 * np.arctan2(np.linalg.norm(res.y[4:7, -1]), res.y[3, -1])
    assert angle == pytest.approx(tau / ratio, abs=1e-8)


def test_spatial_rod_out_of_plane_against_shooting():
    from scipy.integrate import solve_ivp
    from scipy.optimize import fsolve

    F, M, ratio = np.array([0.0, -1.5, 0.8]), np.array([0.3, 0.0, 0.0]), 0.7
    res = rods.spatial_cantilever(force=F, moment=M, torsion_ratio=ratio, tol=1e-10)
    assert res.ok, res.message

    def rhs(s, y):
        Y = y[:, None]
        q, n, m = Y[3:7], Y[7:10], Y[10:13]
        t = rods.rotate(q, np.array([[1.0], [0.0], [0.0]]))
        kappa = np.array([[1 / ratio], [1.0], [1.0]]) * rods.rotate_T(q, m)
        dq = 0.5 * rods.qmul(q, np.vstack([np.zeros(1), kappa]))
        return np.vstack([t, dq, np.zeros((3, 1)), -np.cross(t.T, n.T).T]).ravel()

    def miss(m0):   # shoot on the root moment; n is constant = F
        y0 = np.r_[0, 0, 0, 1, 0, 0, 0, F, m0]
        sol = solve_ivp(rhs, (0, 1), y0, rtol=1e-12, atol=1e-12)
        return sol.y[10:13, -1] - M

    m0 = fsolve(miss, res.y[10:13, 0], xtol=1e-13)
    sol = solve_ivp(rhs, (0, 1), np.r_[0, 0, 0, 1, 0, 0, 0, F, m0], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(res.y[0:3, -1], sol.y[0:3, -1], atol=1e-7)


@pytest.mark.parametrize("coupled", [False, True])
def test_block_lu_solves_and_signs_the_determinant_like_a_dense_lu(coupled):
    rng = np.random.default_rng(5 + coupled)
    m, N = 4, 12
    A = rng.standard_normal((m, m, N))
    B = rng.standard_normal((m, m, N))
    Ja, Jb = rng.standard_normal((m, m)), rng.standard_normal((m, m))
    if not coupled:               # two conditions at each end
        Ja[2:] = 0.0
        Jb[:2] = 0.0
    lu = bvp.BlockLU(A, B, Ja, Jb)
    assert lu.separated == (not coupled)
    dense = lu.matrix.toarray()
    sign, _ = np.linalg.slogdet(dense)
    assert lu.det_sign == int(sign)
    r = rng.standard_normal(dense.shape[0])
    np.testing.assert_allclose(lu.solve(r), np.linalg.solve(dense, r), rtol=1e-9, atol=1e-9)


def test_bratu_fold_found_by_the_determinant_sign():
    """y'' + λ e^y = 0, y(0) = y(1) = 0: the branch turns at λ* = 3.513830719
    (the classical value); continuation must report it as a fold."""
    lam_star = 3.513830719125162

    def f(s, Y, lam):
        return np.array([Y[1], -lam * np.exp(Y[0])])

    def bc(ya, yb, lam):
        return np.array([ya[0], yb[0]])

    mesh = np.linspace(0, 1, 201)
    # aim past λ*: the path turns at the fold and comes back down the upper branch
    path = bvp.continuation(f, bc, mesh, np.zeros(2), (0.0, 5.0), ds=0.5, ds_max=4.0,
                            max_steps=40)
    assert len(path.folds) == 1 and not path.bifurcations
    k = path.folds[0]
    assert path.det_signs[k] != path.det_signs[k - 1]
    assert abs(path.gammas.max() - lam_star) < 2e-3 * lam_star     # trapezoid, h = 1/200
    assert path.status == "max_steps" and path.gammas[-1] < 2.0    # back down ...
    assert path.ys[-1][0].max() > 2.0                               # ... on the large solutions


def test_straight_column_branch_reports_the_buckling_bifurcation():
    """Following the straight (unbuckled) column in α crosses α_cr = π²/4,
    where the buckled branch leaves: a determinant sign change without a turn."""
    def f(s, Y, a):
        return rods.column_f(s, Y, a)

    path = bvp.continuation(f, rods.clamped_free_bc, np.linspace(0, 1, 81), np.zeros(4), (1.0, 4.0),
                            ds=0.3, ds_max=0.3)
    assert path.status == "solved" and not path.folds
    assert len(path.bifurcations) == 1
    k = path.bifurcations[0]
    assert path.gammas[k - 1] < np.pi ** 2 / 4 < path.gammas[k]


BETA1 = 1.8751040687119611            # first root of 1 + cos β cosh β = 0 (cantilever)
T1 = 2 * np.pi / BETA1 ** 2           # first period, units L²√(ρA/EI)


def _period(m):
    y, t = m.tip[:, 1], m.t
    i = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    crossings = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
    return float(np.diff(crossings).mean())


def test_rod_dynamics_small_vibration_has_the_euler_bernoulli_period_at_order_two():
    """Released from a small static tip deflection, the tip vibrates at the
    Euler-Bernoulli fundamental period 2π/β₁²; Park's method converges to it
    at second order."""
    errs = []
    for per_period in (20, 40, 80):
        m = rods.cantilever_dynamics(0.01, 3 * T1, T1 / per_period)
        assert m.ok, m.message
        errs.append(abs(_period(m) / T1 - 1))
    assert errs[-1] < 3e-3
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all((orders > 1.6) & (orders < 2.4)), (errs, orders)


def test_rod_dynamics_suddenly_applied_load_doubles_the_static_deflection():
    """A tip load P applied suddenly to the straight rod at rest: the tip swings
    to about twice the static deflection PL³/3EI (linear theory, first mode)."""
    m = rods.cantilever_dynamics(0.0, 1.2 * T1, T1 / 160, tip_load=lambda t: (0.0, -0.01))
    assert m.ok, m.message
    ratio = m.tip[:, 1].min() / (-0.01 / 3)
    assert 1.95 < ratio < 2.02, ratio


def test_rod_dynamics_large_swing_keeps_the_length_and_the_amplitude():
    m = rods.cantilever_dynamics(5.0, 1.0 * T1, T1 / 80)
    assert m.ok, m.message
    assert np.hypot(*m.tip.T).max() <= 1.0 + 1e-6          # inextensible
    lo, hi = m.tip[:, 1].min(), m.tip[:, 1].max()
    assert abs(hi + lo) < 0.02 * abs(lo)                    # swings to the mirror position
    np.testing.assert_allclose(lo, -rods.tip_deflection(rods.cantilever(5.0)), rtol=1e-6)


@pytest.mark.parametrize("plane", ["y", "z"])
def test_spatial_rod_dynamics_in_a_plane_is_the_planar_rod_dynamics(plane):
    """Large in-plane motion (released from α = 2) of the 13-unknown spatial
    rod against the 6-unknown planar one, in either bending plane."""
    force = (0.0, -2.0, 0.0) if plane == "y" else (0.0, 0.0, -2.0)
    spatial = rods.spatial_cantilever_dynamics(force, 0.6 * T1, T1 / 30, torsion_ratio=0.6)
    planar = rods.cantilever_dynamics(2.0, 0.6 * T1, T1 / 30)
    assert spatial.ok and planar.ok
    cols = [0, 1] if plane == "y" else [0, 2]
    np.testing.assert_allclose(spatial.tip[:, cols], planar.tip, atol=2e-6)


def test_spatial_rod_dynamics_oblique_small_vibration_period():
    m = rods.spatial_cantilever_dynamics((0.0, 0.006, -0.008), 2.2 * T1, T1 / 80, torsion_ratio=0.7)
    assert m.ok, m.message
    d = (0.006 * m.tip[:, 1] - 0.008 * m.tip[:, 2]) / 0.01      # along the initial deflection
    motion = type("M", (), {"tip": np.column_stack([m.tip[:, 0], d]), "t": m.t})
    assert abs(_period(motion) / T1 - 1) < 3e-3
    # the motion stays in the plane of the initial deflection (isotropic section)
    np.testing.assert_allclose(m.tip[:, 1] * 0.008, -m.tip[:, 2] * 0.006, atol=1e-9)
