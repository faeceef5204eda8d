"""Load-parameter tracing ("trace"; the load-trace paper of Osipova, Popov &
Lovtsov) checked against independent solves.

Every breakpoint is verified by solving the LCP at p_k - eps and p_k + eps
from scratch (another method) and comparing the sets of positive z's; between
breakpoints the reported solution must be affine and solve the LCP of the real
data (no artificial right-hand side)."""

from __future__ import annotations

import numpy as np
import pytest

import qpcontact
from qpcontact.testing import assert_lcp_solution
from qpcontact import InvalidProblemError, NoSolutionError, ParametricLCP

from tests.helpers.limits import kept, timed
from tests.helpers.problems import seeded_spd_matrix
from tests.helpers.references import enumerate_lcp


def _independent(lcp, symmetric):
    """A certified solution by a method that shares no code with "trace": the
    external QP backends for symmetric M (active-set ones first), Lemke otherwise."""
    names = ("quadprog", "daqp", "clarabel", "piqp", "osqp") if symmetric else ("lemke",)
    tried = []
    for name in names:
        if name in qpcontact.methods():
            sol = qpcontact.solve(lcp, method=name, accuracy="high")
            if sol.ok:
                return sol.z
            tried.append((name, sol.message))
    raise AssertionError(f"no independent certified solution: {tried}")


def _z_scale(lcp, z):
    """The certificate's sigma_z: |z| with the floor |q| / max|M|."""
    return max(np.abs(z).max(), np.abs(lcp.q).max() / np.abs(lcp.M).max())


def _support(z, scale):
    return z > 1e-8 * scale


def _check_trace(plcp, tr, symmetric, p_max):
    assert tr.ok, tr.message
    bps = tr.breakpoints
    assert np.all(np.diff(bps) > 0)
    edges = [0.0, *bps, p_max if np.isfinite(p_max) else (bps[-1] + 1 if bps.size else 1.0)]
    # the active set on each piece matches an independent solve inside it
    for piece, lo, hi in zip(tr.pieces, edges[:-1], edges[1:]):
        for frac in (0.25, 0.5, 0.75):
            p = lo + frac * (hi - lo)
            z_ref = _independent(plcp.at(p), symmetric)
            z_tr = tr.z_at(p)
            scale = _z_scale(plcp.at(p), z_ref)
            np.testing.assert_allclose(z_tr, z_ref, rtol=0, atol=1e-6 * scale)
            assert np.array_equal(_support(z_ref, scale), piece.active & _support(z_tr, scale))
        # affine: the midpoint is the mean of the quarter points, exactly
        zs = [tr.z_at(lo + f * (hi - lo)) for f in (0.25, 0.5, 0.75)]
        np.testing.assert_allclose(zs[1], 0.5 * (zs[0] + zs[2]), atol=1e-12 * max(1, np.abs(zs[1]).max()))
    # each breakpoint separates two different working schemes
    for k, pk in enumerate(bps):
        eps = 1e-3 * min(edges[k + 1] - edges[k], edges[k + 2] - edges[k + 1])
        below = _independent(plcp.at(pk - eps), symmetric)
        above = _independent(plcp.at(pk + eps), symmetric)
        sb = _support(below, _z_scale(plcp.at(pk - eps), below))
        sa = _support(above, _z_scale(plcp.at(pk + eps), above))
        assert not np.array_equal(sb, sa), f"no change of scheme at p_{k} = {pk}"
        assert np.array_equal(sb, tr.pieces[k].active & sb)
        assert np.array_equal(sa, tr.pieces[k + 1].active & sa)


def _family(seed, n=8):
    rng = np.random.default_rng(seed)
    M = seeded_spd_matrix(n, 50.0, seed)
    q1 = -rng.uniform(0.2, 1.0, n) * np.sign(rng.standard_normal(n) + 0.8)
    return M, q1, rng


@pytest.mark.parametrize("seed", range(4))
def test_trace_case_b_constant_load_nonnegative(seed):
    M, q1, rng = _family(seed)
    q0 = rng.uniform(0.0, 0.5, M.shape[0])  # open gaps
    plcp = ParametricLCP(M, q0, q1)
    tr = qpcontact.solve(plcp, method="trace", p_max=3.0)
    assert tr.end == "p_max" and tr.p_end == 3.0
    assert tr.breakpoints.size >= 1
    _check_trace(plcp, tr, True, 3.0)


@pytest.mark.parametrize("seed", range(3))
def test_trace_case_c_constant_load_with_negative_entries(seed):
    M, q1, rng = _family(seed + 10)
    q0 = rng.standard_normal(M.shape[0])
    assert (q0 < 0).any()
    plcp = ParametricLCP(M, q0, q1)
    tr = qpcontact.solve(plcp, method="trace", p_max=2.0)
    np.testing.assert_allclose(tr.pieces[0].z(0.0), _independent(plcp.at(0.0), True), atol=1e-8)
    _check_trace(plcp, tr, True, 2.0)


def test_trace_case_a_variable_load_only_has_no_pre_force():
    """q0 = 0: the LCP is positively homogeneous, so z(p) = p z(1) exactly —
    a unit pre-force (the published implementation's fault) would break it."""
    M, q1, _ = _family(3)
    plcp = ParametricLCP(M, np.zeros(M.shape[0]), q1)
    tr = qpcontact.solve(plcp, method="trace", p_max=np.inf)
    assert tr.end == "unbounded" and tr.breakpoints.size == 0
    z1 = _independent(plcp.at(1.0), True)
    for p in (1e-8, 0.3, 1.0, 250.0):
        np.testing.assert_allclose(tr.z_at(p), p * z1, rtol=0, atol=1e-9 * p * np.abs(z1).max())
        w = M @ tr.z_at(p) + p * q1  # the real data, nothing added
        assert w.min() >= -1e-12 * p and abs(tr.z_at(p) @ w) <= 1e-12 * max(p, 1e-8) ** 2 * 1e3


@pytest.mark.parametrize("seed", range(3))
def test_trace_nonsymmetric_friction_like(seed):
    """Monotone nonsymmetric M (stiffness plus a skew coupling, as friction
    brings): breakpoints checked with Lemke as the independent solver."""
    M, q1, rng = _family(seed + 20)
    K = np.triu(rng.standard_normal(M.shape), 1) * 0.5
    A = M + K - K.T
    q0 = rng.uniform(0.0, 0.3, M.shape[0])
    plcp = ParametricLCP(A, q0, q1)
    tr = qpcontact.solve(plcp, method="trace", p_max=3.0)
    _check_trace(plcp, tr, False, 3.0)


def test_trace_mechanism_and_ray_ends():
    # Two bodies joined by a spring, pushed apart: w = (z1 - z2 - p, -z1 + z2 + p/2)
    # cannot hold for p > 0 — the pair becomes a mechanism at p = 0.
    M = np.array([[1.0, -1.0], [-1.0, 1.0]])
    tr = qpcontact.solve(ParametricLCP(M, [0.0, 0.0], [-1.0, 0.5]), method="trace", p_max=np.inf)
    assert tr.end == "collapse"
    assert not enumerate_lcp(M, np.array([-1.0, 0.5]))  # no solution at p = 1
    # A single support under a growing load: one breakpoint when the gap closes, then a ray.
    tr = qpcontact.solve(ParametricLCP([[2.0]], [1.0], [-1.0]), method="trace", p_max=np.inf)
    assert tr.end == "unbounded"
    np.testing.assert_allclose(tr.breakpoints, [1.0])
    np.testing.assert_allclose(tr.z_at(3.0), [1.0])


def test_trace_errors():
    with pytest.raises(InvalidProblemError, match="trace"):
        qpcontact.solve(ParametricLCP(np.eye(2), [1, 1], [1, 1]), method="lemke")
    # the constant load alone has no equilibrium: nothing to start from
    M = np.array([[1.0, -1.0], [-1.0, 1.0]])
    with pytest.raises(NoSolutionError, match="constant load"):
        qpcontact.solve(ParametricLCP(M, [-1.0, -1.0], [1.0, 1.0]), method="trace")
    with pytest.raises(qpcontact.InvalidOptionError, match="p_max"):
        qpcontact.solve(ParametricLCP(np.eye(2), [1, 1], [1, 1]), method="trace", p_max=-1)


def test_trace_plot_is_written(tmp_path):
    M, q1, rng = _family(1)
    tr = qpcontact.solve(ParametricLCP(M, rng.uniform(0, 0.5, M.shape[0]), q1), method="trace",
                         p_max=2.0)
    from qpcontact.plots.trace import plot_trace

    out = plot_trace(tr, tmp_path / "trace.png")
    assert (tmp_path / "trace.png").stat().st_size > 1000
    assert not list(tmp_path.glob("*.tmp.png"))
    assert out.endswith("trace.png")


@pytest.mark.parametrize("seed", range(4))
def test_trace_with_far_and_touching_gaps_agrees_componentwise(seed):
    """The far-contact family in the trace: gaps spread over 1e0..1e12
    and gaps of exactly zero (touching, unloaded).  Each piece must match an
    independent solve ("bpp", no shared pivoting code) component by component,
    w_i against its own size — a normwise check would let near contacts be
    wrong by the far gaps' 1e12 * 1e-6."""
    M, q1, rng = _family(seed + 30)
    n = M.shape[0]
    q0 = np.where(rng.random(n) < 0.5, 10.0 ** rng.uniform(0, 12, n), 0.0)
    plcp = ParametricLCP(M, q0, q1)
    tr = qpcontact.solve(plcp, method="trace", p_max=3.0)
    assert tr.ok, tr.message
    for piece in tr.pieces:
        hi = piece.p_end if np.isfinite(piece.p_end) else piece.p_start + 1.0
        for frac in (0.25, 0.5, 0.75):
            p = piece.p_start + frac * (hi - piece.p_start)
            ref = qpcontact.solve(plcp.at(p), method="bpp")
            assert ref.ok
            z, w = tr.z_at(p), tr.w_at(p)
            np.testing.assert_allclose(z, ref.z, rtol=1e-9, atol=1e-12 * np.abs(ref.z).max())
            np.testing.assert_allclose(w, ref.w, rtol=1e-9, atol=1e-12 * np.abs(q1).max() * (1 + p))


def _strict_solutions(M, q):
    """Every complementary basic solution that the certificate accepts at 1e-12
    (the reference enumeration's absolute tolerance lets -5e-12 pass)."""
    return [z for z in enumerate_lcp(M, q) if qpcontact.certify(qpcontact.LCP(M, q), z).error <= 1e-12]


# the first 100 seeds hold every kind of ending (59 unbounded, 40 collapses,
# one fold): 15 s, and the other 300 20 s more, both in make test-all
@pytest.mark.parametrize("seeds", [pytest.param(range(100), marks=pytest.mark.slow),
                                   pytest.param(range(100, 400), marks=pytest.mark.slow)],
                         ids=["first-100", "next-300"])
def test_nonP_traces_end_as_proved(seeds):
    """Random non-P matrices (n = 2, 3): every ending checked by enumerating all
    complementary bases — a collapse has no solution beyond it; a fold has none
    near the end point just beyond it (the path does not continue), though
    other equilibria may exist; an unbounded end holds its scheme at any load."""
    seen = {}
    for seed in seeds:
        rng = np.random.default_rng(seed)
        n = int(rng.integers(2, 4))
        M = rng.standard_normal((n, n))
        q0, q1 = rng.uniform(0.1, 1, n), rng.standard_normal(n)
        plcp = ParametricLCP(M, q0, q1)
        tr = qpcontact.solve(plcp, method="trace", p_max=np.inf)
        seen[tr.end] = seen.get(tr.end, 0) + 1
        assert tr.ok and tr.end in ("unbounded", "collapse", "fold"), (seed, tr.message)
        for piece in tr.pieces:
            hi = piece.p_end if np.isfinite(piece.p_end) else piece.p_start + 1.0
            for p in (piece.p_start, 0.5 * (piece.p_start + hi), hi):
                assert_lcp_solution(plcp.at(p), piece.z(p), tol=1e-9)
        p_end, z_end = tr.p_end, tr.z
        scale = max(1.0, abs(p_end))
        if tr.end == "collapse":
            for p in (tr.proof["p_limit"] + 1e-6 * scale, 2 * p_end + 1.0, p_end + 100.0):
                assert not _strict_solutions(M, plcp.at(p).q), (seed, p)
        elif tr.end == "fold":
            near = [z for z in _strict_solutions(M, plcp.at(p_end + 1e-7 * scale).q)
                    if np.abs(z - z_end).max() <= 1e-4 * max(1.0, np.abs(z_end).max())]
            assert not near, (seed, near)
        else:
            for p in (p_end + 1.0, 10 * p_end + 10):
                z = tr.z_at(p)
                assert any(np.allclose(z, s, rtol=1e-8, atol=1e-10 * max(1, np.abs(s).max()))
                           for s in enumerate_lcp(M, plcp.at(p).q)), (seed, p)
    assert seen.get("fold", 0) >= 1 and seen.get("collapse", 0) >= 3 and seen.get("unbounded", 0) >= 3, seen


def test_collapse_proof_checks_from_the_data():
    """The spring pair pushed apart has no equilibrium for any p > 0; the
    proof's y is checked here from M and q, independently of the trace."""
    M = np.array([[1.0, -1.0], [-1.0, 1.0]])
    q0, q1 = np.zeros(2), np.array([-1.0, 0.5])
    tr = qpcontact.solve(ParametricLCP(M, q0, q1), method="trace", p_max=np.inf)
    assert tr.ok and tr.end == "collapse"
    for leaf in tr.proof["leaves"]:
        y = leaf["y"]
        free_z = np.setdiff1d(np.arange(2), leaf["z_zero"])
        assert np.all(y[np.setdiff1d(np.arange(2), leaf["w_zero"])] >= 0)
        assert q1 @ y <= 1e-12 * np.abs(q1) @ np.abs(y)
        # y'w <= delta'z + y'q(p) < 0 for every z >= 0 summing below the bound
        delta = np.maximum(M.T @ y, 0.0)[free_z]
        gap = -(q0 + tr.proof["p_limit"] * q1) @ y
        assert gap > 0 and delta.sum() * tr.proof["z_bound"] <= gap * (1 + 1e-12)
    assert tr.proof["p_limit"] <= 1e-6 and tr.proof["z_bound"] >= 1e3 * 0.5


def test_the_collapse_proof_stops_at_the_callers_deadline():
    """The branch and bound behind a collapse proof (an LP or two a node: a
    117-contact frame's ran for minutes) stops where the caller's deadline
    has passed, proving nothing; the same family without a deadline is
    proved (the spring pair pushed apart, as above)."""
    from qpcontact.proofs.parametric import LoadFamily

    family = LoadFamily(ParametricLCP(np.array([[1.0, -1.0], [-1.0, 1.0]]), np.zeros(2),
                                      np.array([-1.0, 0.5])))
    assert family.collapse_proof(0.0, 1.0, 1e-9)["p_limit"] <= 1e-6
    assert family.collapse_proof(0.0, 1.0, 1e-9, expired=lambda: True) is None


@pytest.mark.parametrize("seed", range(3))
def test_trace_psd_singular_matrix_w_matches_independent_solves(seed):
    """Symmetric PSD but singular M (a frictionless frame resting on its
    contacts): z need not be unique, w = Mz + q is.  Every piece's w is
    compared with an independent QP backend's inside it, and every piece is
    certified from the data."""
    rng = np.random.default_rng(seed + 50)
    n, k = 8, 5
    A = rng.standard_normal((n, k))
    M = A @ A.T
    q0 = rng.uniform(0.0, 1.0, n)
    q1 = -rng.uniform(0.1, 1.0, n) * np.sign(rng.standard_normal(n) + 0.5)
    plcp = ParametricLCP(M, q0, q1)
    tr = qpcontact.solve(plcp, method="trace", p_max=5.0)
    assert tr.ok and tr.end == "p_max" and tr.breakpoints.size >= 3, tr.message
    for piece in tr.pieces:
        hi = min(piece.p_end, 5.0)
        for frac in (0.25, 0.75):
            p = piece.p_start + frac * (hi - piece.p_start)
            lcp = plcp.at(p)
            assert_lcp_solution(lcp, tr.z_at(p), tol=1e-9)
            ref = None
            for name in ("clarabel", "piqp", "osqp"):
                if name in qpcontact.methods():
                    sol = qpcontact.solve(lcp, method=name, accuracy="high")
                    if sol.ok:
                        ref = sol
                        break
            assert ref is not None
            w = lcp.w(tr.z_at(p))
            np.testing.assert_allclose(w, ref.w, rtol=1e-6, atol=1e-6 * np.abs(lcp.q).max())


def test_the_trace_keeps_the_calls_time_limit_and_certifies_what_it_traced():
    """solve's time_limit bounds the whole trace (its Lemke solves share the
    call's deadline through the engine): a 300-unknown path of some 300
    pieces stops at 0.3 s, says so, and every piece it returns matches
    independent solves inside it."""
    M = seeded_spd_matrix(300, 1e3, 1)
    rng = np.random.default_rng(2)
    plcp = ParametricLCP(M, rng.uniform(0.0, 1.0, 300), -rng.uniform(0.5, 1.5, 300))
    qpcontact.solve(ParametricLCP(M[:20, :20], plcp.q0[:20], plcp.q1[:20]), method="trace",
                    p_max=np.inf)                                   # one-time costs first
    tr, took = timed(qpcontact.solve, plcp, method="trace", p_max=np.inf, time_limit=0.3)
    assert kept(0.3, took), took
    assert tr.status == "time_limit" and tr.end == "time_limit" and not tr.ok, tr.message
    assert "time limit" in tr.message and tr.stats["worst_piece_error"] <= 1e-9
    for piece in tr.pieces[:-1][:8]:      # the path up to where it stopped, checked independently
        for p in (piece.p_start, 0.5 * (piece.p_start + piece.p_end)):
            z_ref = _independent(plcp.at(p), True)
            np.testing.assert_allclose(tr.z_at(p), z_ref, rtol=0,
                                       atol=1e-6 * _z_scale(plcp.at(p), z_ref))


def test_trace_starts_from_a_given_solution_and_refuses_a_wrong_one():
    """``start``: the caller's solution at p = 0, checked by the certificate;
    the path from it is the path from Lemke's."""
    M = seeded_spd_matrix(6, 30.0, 3)
    q0 = np.array([-1.0, 2.0, -0.5, 1.0, -2.0, 0.3])
    qv = np.array([1.0, -1.0, 0.5, -0.2, 0.4, -1.0])
    plcp = ParametricLCP(M, q0, qv)
    (z0,) = enumerate_lcp(M, q0)           # SPD: one solution
    ref = qpcontact.solve(plcp, method="trace", p_max=2.0)
    got = qpcontact.solve(plcp, method="trace", p_max=2.0, start=z0)
    assert got.ok and np.allclose(got.z_at(1.5), ref.z_at(1.5), atol=1e-12)
    with pytest.raises(qpcontact.InvalidOptionError, match="start is no solution at p = 0"):
        qpcontact.solve(plcp, method="trace", p_max=2.0, start=z0 + 1.0)
    with pytest.raises(qpcontact.InvalidOptionError, match="start has 5 entries"):
        qpcontact.solve(plcp, method="trace", p_max=2.0, start=z0[:5])
