"""Hard cases: time limits, isolation, proofs of infeasibility and
unboundedness for QPs, option names, and the definiteness test's scale."""

from __future__ import annotations

import os
import signal
import sys
import time

import numpy as np
import pytest
import scipy.sparse as sp
from qpsolvers import Problem

import qpcontact
from formulations import meshes
from qpcontact import LCP
from qpcontact.core.errors import InvalidOptionError, NoSolutionError
from qpcontact.dispatch.isolation import call_isolated
from qpcontact.testing import far_contact_lcp, random_spd
from qpcontact.cases.planted import build_qp
from tests.helpers.limits import kept, timed


def _segfault():
    os.kill(os.getpid(), signal.SIGSEGV)


def _sleep(seconds):
    time.sleep(seconds)
    return seconds


def _raise():
    raise ValueError("from the child")


def test_isolation_survives_a_crash_and_a_hang_and_passes_results_and_errors():
    crashed = call_isolated(_segfault, (), 10.0)
    assert crashed.kind == "crashed" and "SIGSEGV" in crashed.detail
    hung, took = timed(call_isolated, _sleep, (30.0,), 0.5)
    assert hung.kind == "time_limit" and kept(0.5, took)
    assert call_isolated(_sleep, (0.01,), 10.0).value == 0.01
    err = call_isolated(_raise, (), 10.0)
    assert err.kind == "error" and isinstance(err.value, ValueError)


def test_proxqp_is_killed_at_the_time_limit():
    """ProxQP has no time limit of its own: with an iteration cap it ignores
    (its inner iterations are not counted), it is run in a child and killed."""
    lcp, _, _ = far_contact_lcp(7)
    qpcontact.solve(lcp, "proxqp", time_limit=0.1)    # the backend's first import
    sol, took = timed(qpcontact.solve, lcp, "proxqp", max_iter=10**9, eps_abs=1e-300,
                      time_limit=1.0)
    assert kept(1.0, took), took
    assert sol.status in ("time_limit", "solved"), sol.message
    if sol.status == "time_limit":
        assert "time limit of 1 s" in sol.message and not sol.ok and sol.z is None


@pytest.mark.parametrize("method", ["osqp", "highs", "clarabel", "cvxpy:HIGHS"])
def test_native_time_limit_is_reported_as_such(method):
    rng = np.random.default_rng(0)
    n = 800
    P = sp.random(n, n, density=3e-3, random_state=1)
    P = (P @ P.T + 1e-6 * sp.identity(n)).tocsc()
    prob = Problem(P, rng.standard_normal(n), sp.csc_matrix(rng.standard_normal((50, n))),
                   np.zeros(50), lb=-np.ones(n), ub=np.ones(n))
    sol = qpcontact.solve(prob, method, accuracy=1e-12, time_limit=1e-3)
    assert sol.status == "time_limit" and not sol.ok, sol.message
    assert "time limit" in sol.message


def test_isolate_true_gives_the_in_process_answer():
    lcp, z_star, _ = far_contact_lcp(3)
    a = qpcontact.solve(lcp, "clarabel", isolate=True)
    b = qpcontact.solve(lcp, "clarabel", isolate=False)
    assert a.stats.get("isolated") and not b.stats.get("isolated")
    assert a.status == b.status and np.array_equal(a.z, b.z)


@pytest.mark.parametrize("value", [0, -1, "x", True, float("nan")])
def test_time_limit_must_be_positive_seconds(value):
    with pytest.raises(InvalidOptionError, match="time_limit"):
        qpcontact.solve(LCP([[1.0]], [-1.0]), "lemke", time_limit=value)


def test_isolate_must_be_auto_or_bool():
    with pytest.raises(InvalidOptionError, match="isolate"):
        qpcontact.solve(LCP([[1.0]], [-1.0]), "osqp", isolate="yes")


@pytest.mark.parametrize("seed", range(4))
def test_unbounded_qp_is_proved_fast_with_a_ray_that_checks(seed):
    case = build_qp("unbounded", 8, seed)
    sol = qpcontact.solve(case.problem, "auto")
    assert sol.status == "unbounded" and not sol.ok, sol.message
    # the proof, checked here from the data (not by qpcontact.proofs)
    proof = sol.stats["proof"]
    P, q, G, h = case.problem.P, case.problem.q, case.problem.G, case.problem.h
    d, x0 = proof.vector["d"], proof.point
    assert q @ d < 0 and np.max(np.abs(P @ d)) <= 1e-12 * np.max(np.abs(P)) * np.max(np.abs(d))
    assert np.all(G @ d <= 1e-12 * np.abs(G) @ np.abs(d)) and np.all(G @ x0 <= h + 1e-9)
    with pytest.raises(NoSolutionError, match="unbounded"):
        qpcontact.solve(case.problem, "auto", raise_on_failure=True)


@pytest.mark.parametrize("seed", range(4))
def test_infeasible_qp_is_proved_with_a_farkas_vector_that_checks(seed):
    case = build_qp("infeasible", 8, seed)
    sol = qpcontact.solve(case.problem, "auto")
    assert sol.status == "infeasible", sol.message
    v = sol.stats["proof"].vector
    G, h = case.problem.G, case.problem.h
    assert np.all(v["z"] >= 0)
    r = G.T @ v["z"]
    assert h @ v["z"] < 0 and np.max(np.abs(r)) <= 1e-9 * abs(h @ v["z"])
    assert sol.stats["auto_tried"][-1][1] == "infeasible" and len(sol.stats["auto_tried"]) == 1


# (family, n, seed, method, accuracy) of the full stress run where a backend
# certified a point of an unbounded QP whose variables were scaled over 8-12
# decades, and the proof's LPs (scaled by rows only) found no ray that checked,
# or no feasible point (HiGHS called a point violating rows by 27 % optimal)
_SCALED_UNBOUNDED = [("qp_unbounded", 8, 10, "osqp", "default"),
                     ("qp_unbounded", 8, 19, "clarabel", "default"),
                     ("qp_unbounded", 30, 19, "proxqp", "default"),
                     ("qp_unbounded", 30, 21, "clarabel", "low"),
                     ("qp_unbounded", 100, 7, "osqp", "default"),
                     ("qp_unbounded", 100, 23, "quadprog", "high")]


@pytest.mark.parametrize("family, n, seed, method, accuracy", _SCALED_UNBOUNDED)
def test_a_certified_point_of_a_scaled_unbounded_qp_is_replaced_by_the_ray(
        family, n, seed, method, accuracy):
    from fractions import Fraction

    from qpcontact.commands.stress import build_case

    case = build_case(family, n, seed)
    assert case.status == "unbounded"
    sol = qpcontact.solve(case.problem, method, accuracy)
    assert sol.status == "unbounded" and not sol.ok, sol.message
    # checked here in exact arithmetic, independently of qpcontact.proofs
    P, q, G, h = case.problem.P, case.problem.q, case.problem.G, case.problem.h
    d = [Fraction(float(v)) for v in sol.stats["proof"].vector["d"]]
    F = np.vectorize(lambda v: Fraction(float(v)), otypes=[object])
    assert all(v == 0 for v in F(P) @ d) and all(v <= 0 for v in F(G) @ d)
    assert sum(Fraction(float(a)) * b for a, b in zip(q, d)) < 0
    x0 = sol.stats["proof"].point
    assert np.all(G @ x0 - h <= 1e-9 * (np.abs(G) @ np.abs(x0) + np.abs(h)))


def test_explicit_backend_on_an_infeasible_qp_gets_the_proof():
    prob = Problem(np.eye(2), np.zeros(2), np.array([[1.0, 0.0], [-1.0, 0.0]]),
                   np.array([-1.0, -1.0]))
    sol = qpcontact.solve(prob, "osqp")
    assert sol.status == "infeasible" and "Farkas" in sol.message


def test_a_bounded_qp_is_not_called_unbounded():
    """P nearly singular but PD (smallest eigenvalue 1e-10): the minimiser is
    far away but exists; no ray may be claimed."""
    rng = np.random.default_rng(3)
    P = random_spd(6, 1e10, rng)
    sol = qpcontact.solve(Problem(P, rng.standard_normal(6)), "auto")
    assert sol.status in ("solved", "inaccurate"), sol.message


@pytest.mark.parametrize("method, bad, hint", [
    ("highs", {"dual_feasibility_tolerence": 1e-9}, "no setting"),
    ("piqp", {"eps_ab": 1e-9}, "eps_abs"),
    ("cvxpy:DAQP", {"primal_tl": 1e-9}, "primal_tol"),
    ("cvxpy:PROXQP", {"eps_ab": 1e-9}, "eps_abs"),
    ("proxqp", {"max_iter_in": 10}, "max_iter"),
])
def test_unknown_option_names_are_refused_before_the_backend_runs(method, bad, hint):
    if method not in qpcontact.methods():
        pytest.skip(f"{method} is not installed")
    prob = Problem(np.eye(2), np.ones(2))
    with pytest.raises(InvalidOptionError, match=hint) as info:
        qpcontact.solve(prob, method, **bad)
    assert len(str(info.value)) < 1500


def test_known_option_names_still_pass():
    prob = Problem(np.eye(2), np.ones(2))
    assert qpcontact.solve(prob, "highs", dual_feasibility_tolerance=1e-10).ok
    assert qpcontact.solve(prob, "piqp", eps_abs=1e-10).ok


def test_definiteness_does_not_depend_on_scaling_nor_overflow():
    rng = np.random.default_rng(0)
    A = rng.standard_normal((5, 5))
    S = A @ A.T + np.eye(5)
    D = np.diag(10.0 ** np.arange(-6, 9, 3))
    assert LCP(D @ S @ D, np.ones(5)).is_positive_definite
    assert not LCP([[1e308, -1e308], [-1e308, 1e308]], [1.0, 1.0]).is_positive_definite
    assert LCP([[1e308, -1e308], [-1e308, 1e308]], [1.0, 1.0]).is_psd


@pytest.mark.parametrize("method, key", [("highs", "time_limit"), ("osqp", "time_limit"),
                                         ("clarabel", "time_limit"), ("scs", "time_limit_secs")])
def test_every_backend_with_a_time_setting_gets_the_limit(monkeypatch, method, key):
    """HiGHS ran > 120 s on a small PD QP: the limit must reach it, as what
    is left of the call's deadline (a moment under 7.5 s, never more)."""
    import qpsolvers

    seen = {}
    real = qpsolvers.solve_problem

    def spy(problem, solver, **kwargs):
        seen.update(kwargs)
        return real(problem, solver=solver, **kwargs)

    monkeypatch.setattr(qpsolvers, "solve_problem", spy)
    qpcontact.solve(Problem(np.eye(3), np.ones(3)), method, time_limit=7.5)
    assert 5.0 < seen.get(key) <= 7.5, seen


@pytest.mark.parametrize("seed, method", [(175, "piqp"), (49, "highs")])
def test_infeasible_lcp_with_a_wider_computed_null_space_is_proved(seed, method):
    """M = c B B' exactly singular, its computed null space two-dimensional
    (singular values 2.8e-14 and 2.5e-16 of the largest): the LP's Farkas
    vector mixes both and no snapping makes it exact; the null vector found
    modulo a prime does (full stress run: these two instances were certified
    as "solved" by four backends)."""
    from fractions import Fraction

    from qpcontact.commands.stress import build_case

    case = build_case("infeasible", 100, seed)
    sol = qpcontact.solve(case.problem, method)
    assert sol.status == "infeasible", sol.message
    y = sol.stats["proof"].vector["exact"]["z"]
    assert all(isinstance(v, Fraction) for v in y)
    M, q = case.problem.M, case.problem.q
    assert all(v >= 0 for v in y)
    # independently: M'y <= 0 and q'y < 0 in exact arithmetic
    for j in range(M.shape[0]):
        assert sum(Fraction(float(M[i, j])) * y[i] for i in range(M.shape[0]) if y[i]) <= 0
    assert sum(Fraction(float(a)) * b for a, b in zip(q, y)) < 0


def _isolated_sleep_then_report(queue):
    """A caller that runs a 60 s call isolated and reports its child's pid."""
    import multiprocessing
    import threading

    def report():
        time.sleep(1.0)
        queue.put([c.pid for c in multiprocessing.active_children()])

    threading.Thread(target=report, daemon=True).start()
    call_isolated(_sleep, (60.0,), 120.0)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG is Linux's")
def test_an_isolated_call_dies_with_its_caller():
    """A caller killed while it waits (a benchmark's or a job runner's own
    limit) takes its isolated backend with it: ProxQP children used to run on,
    orphaned, for over half an hour."""
    import multiprocessing
    import os

    ctx = multiprocessing.get_context("spawn")
    queue = ctx.Queue()
    caller = ctx.Process(target=_isolated_sleep_then_report, args=(queue,))
    caller.start()
    children = queue.get(timeout=60)
    caller.kill()
    caller.join()
    assert children, "the caller started no child"
    deadline = time.perf_counter() + 10.0
    alive = children
    while alive and time.perf_counter() < deadline:
        time.sleep(0.1)
        alive = [pid for pid in alive if _running(pid)]
    for pid in alive:       # leave nothing behind, whatever the outcome
        os.kill(pid, 9)
    assert not alive, f"isolated children outlived their caller: {alive}"


def _running(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split()[2] != "Z"
    except FileNotFoundError:
        return False


def _spd_lcp(n, seed=0):
    rng = np.random.default_rng(seed)
    B = rng.standard_normal((n, n))
    M = B @ B.T / n + np.eye(n)
    return LCP(M, rng.standard_normal(n))


@pytest.mark.parametrize("method", ["piqp", "daqp", "quadprog"])
def test_a_backend_without_a_time_setting_runs_killable_where_its_work_can_outlast_the_limit(
        method):
    """PIQP, DAQP and quadprog have no time setting: their iteration caps
    bound the factorizations, not the clock (PIQP ran 148 s on an unbounded
    QP of n = 1 000 under a 20 s limit).  From SMALL_WORK unknowns and
    constraints, or with a short limit, the call runs in a child killed at
    the deadline; a small problem under a long limit pays no fork."""
    from qpcontact.solvers.backends.common import SMALL_WORK
    from qpcontact.solvers.registry import get_method

    if not get_method(method).available:
        pytest.skip(f"{method} not installed")
    assert get_method(method).isolate_from == SMALL_WORK
    small, large = _spd_lcp(8), _spd_lcp(SMALL_WORK)
    assert not qpcontact.solve(small, method, time_limit=60).stats.get("isolated")
    assert qpcontact.solve(small, method, time_limit=5).stats.get("isolated")
    big = qpcontact.solve(large, method, time_limit=60)
    assert big.stats.get("isolated") and big.ok, big.message
    assert not qpcontact.solve(large, method, time_limit=None).stats.get("isolated")
    assert not qpcontact.solve(large, method, time_limit=60, isolate=False).stats.get("isolated")


def test_proxqp_runs_killable_at_every_size():
    from qpcontact.solvers.registry import get_method

    assert get_method("proxqp").isolate_from == 0
    assert qpcontact.solve(_spd_lcp(8), "proxqp", time_limit=60).stats.get("isolated")


def test_a_backend_killed_at_the_deadline_says_time_limit():
    """PIQP on a dense LCP of n = 3 000 (its QP has 6 000 bounds and
    unknowns; PIQP alone takes about 10 s on the 2-core machine) given
    0.2 s: killed, status "time_limit" (the wall time is the benchmark's:
    benchmarks/no_solution.py --part 3).  At n = 1 000 PIQP finished within
    the limit plus the kill's grace on a faster machine and the test failed
    on a right answer."""
    sol = qpcontact.solve(_spd_lcp(3000), "piqp", time_limit=0.2)
    assert sol.stats.get("isolated")
    assert sol.status == "time_limit" and not sol.ok, sol.message


@pytest.mark.parametrize("method, problem, limit", [
    ("energy", lambda: _spd_lcp(1500), 0.05),     # ~700 pivots of 1-2 ms: over a second
    ("bpp", lambda: _spd_lcp(1500), 1e-3),        # each exchange a 1 500 x 1 500 Cholesky
    ("ip-bpp", lambda: _spd_lcp(1500), 1e-3),
    ("mg-bpp", lambda: meshes.membrane(100), 1e-3),  # n = 1e4: the guess alone takes longer
])
def test_the_exact_methods_keep_the_time_limit(method, problem, limit):
    """The in-house pivoting methods read the deadline at every pivot,
    exchange or cycle: energy ran a dense 3 000-unknown SPD LCP for 12 s
    under time_limit=0.05 and answered "solved" (the limit was not passed
    to them).  Past it: status "time_limit", no point.  Each problem takes
    its method far longer than the limit at any speed (energy: ~700 pivots
    of O(n²); the others: factorizations of thousands of unknowns), so the
    status alone shows the deadline was read; the wall time is not asserted
    (a factorization in flight ran past the grace at a load of 6)."""
    lcp = problem()
    sol = qpcontact.solve(lcp, method, time_limit=limit)
    assert sol.status == "time_limit" and not sol.ok and sol.z is None, sol.message
    assert "time limit" in sol.message


def test_auto_takes_block_pivoting_first_on_a_dense_spd_lcp():
    """A dense SPD LCP from AUTO_DENSE_BPP_MIN unknowns goes to "bpp" first
    (a few Cholesky factorizations, where energy's ~n/2 pivots were O(n²)
    each: 12 s against 1.7 s at n = 3 000); its answer is energy's, to the
    certificate's digits; below, the order the hard cases were measured
    with ("energy" first)."""
    from qpcontact.dispatch.routes import AUTO_DENSE_BPP_MIN

    big = _spd_lcp(AUTO_DENSE_BPP_MIN + 50, seed=3)
    auto = qpcontact.solve(big)
    exact = qpcontact.solve(big, "energy")
    assert auto.ok and exact.ok and auto.method == "bpp"
    assert np.array_equal(auto.z > 0, exact.z > 0)
    assert np.max(np.abs(auto.z - exact.z)) <= 1e-12 * np.max(np.abs(exact.z))
    small = qpcontact.solve(_spd_lcp(AUTO_DENSE_BPP_MIN - 10, seed=3))
    assert small.ok and small.method == "energy"
