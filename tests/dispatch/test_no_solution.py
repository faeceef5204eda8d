""""auto" on data with no solution: the proof comes first, before any method
runs, and its time is a share of the call's deadline.  Planted certificates
(tests/helpers/no_solution.py); every proof checked here in Fractions."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from qpsolvers import Problem

import qpcontact
from qpcontact import LCP
from qpcontact.core.errors import NoSolutionError
from qpcontact.dispatch import lcp_qp_run
from qpcontact.dispatch.context import RunContext
from tests.helpers.no_solution import KINDS, farkas_lcp, ray_qp


def _F(v) -> Fraction:
    return Fraction(float(v))


@pytest.mark.parametrize("kind", KINDS)
def test_auto_proves_an_infeasible_lcp_before_any_method(kind):
    lcp, _ = farkas_lcp(80, 2, kind)
    sol = qpcontact.solve(lcp, "auto", time_limit=20)
    assert sol.status == "infeasible" and not sol.ok, sol.message
    assert [t[0] for t in sol.stats["auto_tried"]] == ["proof"]
    y = sol.stats["proof"].vector["exact"]["z"]
    M, q = lcp.M, lcp.q
    assert all(v >= 0 for v in y)
    assert all(sum(_F(M[i, j]) * y[i] for i in range(lcp.n) if y[i]) <= 0 for j in range(lcp.n))
    assert sum(_F(q[i]) * y[i] for i in range(lcp.n)) < 0
    with pytest.raises(NoSolutionError):
        qpcontact.solve(lcp, "auto", raise_on_failure=True)


def test_auto_proves_an_unbounded_qp_before_any_method():
    problem, _ = ray_qp(80, 3)
    sol = qpcontact.solve(problem, "auto", time_limit=20)
    assert sol.status == "unbounded" and not sol.ok, sol.message
    assert [t[0] for t in sol.stats["auto_tried"]] == ["proof"]
    proof = sol.stats["proof"]
    d = [_F(v) for v in proof.vector["d"]]
    P, q, G, h = problem.P, problem.q, problem.G, problem.h
    n = q.size
    assert all(sum(_F(P[i, j]) * d[j] for j in range(n)) == 0 for i in range(n))
    assert all(sum(_F(G[i, j]) * d[j] for j in range(n)) <= 0 for i in range(G.shape[0]))
    assert sum(_F(q[j]) * d[j] for j in range(n)) < 0
    x0 = proof.point
    assert np.all(G @ x0 <= h + 1e-9 * (np.abs(G) @ np.abs(x0) + np.abs(h)))


@pytest.mark.parametrize("problem", [
    LCP(np.eye(3), [-1.0, 2.0, -3.0]),                       # positive definite M
    LCP([[0.0, -1.0], [1.0, 0.0]], [1.0, 2.0]),              # q >= 0: z = 0 solves
    LCP([[1.0, 2.0], [3.0, -1.0]], [-1.0, -1.0]),            # M·1 > 0: z = t·1 solves
    Problem(np.eye(2), np.ones(2)),                          # P positive definite
], ids=["pd", "q-nonnegative", "ones-solve", "qp-pd"])
def test_no_proof_is_sought_where_a_solution_is_known_to_exist(monkeypatch, problem):
    called = []
    monkeypatch.setattr(lcp_qp_run, "prove_lcp_infeasible", lambda *a, **k: called.append(a))
    monkeypatch.setattr(lcp_qp_run, "prove_no_minimiser", lambda *a, **k: called.append(a))
    assert lcp_qp_run.proof_first(problem, RunContext.start("high", 10.0)) is None
    assert not called
    assert qpcontact.solve(problem, "auto").ok


@pytest.mark.parametrize("time_limit", [2.0, 60.0, None])
def test_the_first_proof_gets_a_share_of_the_deadline(monkeypatch, time_limit):
    """Its deadline: PROOF_FIRST_SHARE of what is left, at most
    PROOF_FIRST_SECONDS — read off the deadline it is given, not timed."""
    seen = []

    def spy(problem, deadline, **kwargs):
        seen.append(deadline.left())
        return None

    monkeypatch.setattr(lcp_qp_run, "prove_lcp_infeasible", spy)
    lcp, _ = farkas_lcp(20, 0, "general")
    ctx = RunContext.start("high", time_limit)
    assert lcp_qp_run.proof_first(lcp, ctx) is None
    cap = lcp_qp_run.PROOF_FIRST_SECONDS
    if time_limit is not None:
        cap = min(cap, lcp_qp_run.PROOF_FIRST_SHARE * time_limit)
    assert len(seen) == 1 and 0 < seen[0] <= cap


def test_a_call_past_its_deadline_seeks_no_proof():
    lcp, _ = farkas_lcp(40, 1, "psd")
    ctx = RunContext.start("high", 1.0)
    object.__setattr__(ctx.deadline, "end", 0.0)         # the deadline has passed
    assert lcp_qp_run.proof_first(lcp, ctx) is None


def _exact_farkas_holds(lcp, y) -> bool:
    """y >= 0, M'y <= 0, q'y < 0 in integers: y over its common denominator,
    M and q integer-valued doubles (the planted family's)."""
    import math

    M, q = np.asarray(lcp.M), np.asarray(lcp.q)
    assert np.all(M == np.round(M)) and np.all(q == np.round(q))
    D = math.lcm(*(Fraction(v).denominator for v in y))
    Y = np.array([int(Fraction(v) * D) for v in y], dtype=object)
    MtY = M.astype(np.int64).astype(object).T.dot(Y)
    return bool(np.all(Y >= 0) and all(v <= 0 for v in MtY)
                and q.astype(np.int64).astype(object).dot(Y) < 0)


@pytest.mark.parametrize("n", [500, pytest.param(1000, marks=pytest.mark.slow)])
def test_auto_proves_a_general_dense_infeasible_lcp_before_any_method(n):
    """A general dense M (no sign pattern, not PSD): the interior Farkas LP
    took 1.8 s of CPU at n = 500 and 27 s at 1 000 in HiGHS, past the proof
    step's share; the margin game finds the vector in under a second."""
    lcp, _ = farkas_lcp(n, 1, "general")
    sol = qpcontact.solve(lcp, "auto", time_limit=20)
    assert sol.status == "infeasible" and not sol.ok, sol.message
    if n <= 500:
        # at 1 000 a loaded machine may push it past the step's 5 s share,
        # and the chain's proof then finds it (the same game)
        assert [t[0] for t in sol.stats["auto_tried"]] == ["proof"]
    assert _exact_farkas_holds(lcp, sol.stats["proof"].vector["exact"]["z"])


@pytest.mark.parametrize("n,seed", [(60, 0), (120, 1)])
def test_a_ray_of_twin_variables_is_proved_before_any_method(n, seed):
    """P with several null directions, pairs of columns equal up to a signed
    power of two (the stress family qp_unbounded_rounded): the null space's
    LP mixes them beyond any snapping (unproved at n = 250 in 18 s, proved at
    120 only by the chain, in 6 s); the
    pair itself is the ray.  Checked here in Fractions."""
    from qpcontact.commands.stress import build_case

    problem = build_case("qp_unbounded_rounded", n, seed).problem
    sol = qpcontact.solve(problem, "auto", time_limit=20)
    assert sol.status == "unbounded" and not sol.ok, sol.message
    assert [t[0] for t in sol.stats["auto_tried"]] == ["proof"]
    d = [_F(v) for v in sol.stats["proof"].vector["d"]]
    P, q, G = problem.P, problem.q, problem.G
    nz = [j for j in range(n) if d[j]]
    assert nz
    assert all(sum(_F(P[i, j]) * d[j] for j in nz) == 0 for i in range(n))
    assert all(sum(_F(G[i, j]) * d[j] for j in nz) <= 0 for i in range(G.shape[0]))
    assert sum(_F(q[j]) * d[j] for j in nz) < 0


def test_a_backend_that_runs_out_of_its_share_is_followed_by_the_proof(monkeypatch):
    """Every method of the chain stopped by its share of the limit (as PIQP
    and OSQP on an infeasible QP of n = 1 000 under load): the Farkas search
    gets half of what is left after the first one, not nothing at the end.
    The data: a'x <= -1 and -a'x <= -1, no x at all (y = (1, 1) by hand)."""
    from qpcontact.dispatch import driver

    rng = np.random.default_rng(5)
    n = 12
    a = rng.standard_normal(n)
    G = np.vstack([rng.standard_normal((4, n)), a, -a])
    h = np.r_[np.ones(4), -1.0, -1.0]
    problem = Problem(np.eye(n), rng.standard_normal(n), G, h)
    real = driver.run_lcp_qp
    shares = []

    def out_of_time(problem, m, options, ctx):
        sol = real(problem, m, options, ctx)
        sol.status, sol.ok, sol.x = "time_limit", False, None
        sol.stats.pop("backend_verdict", None)
        return sol

    def spy(problem, sol, deadline, *args):
        shares.append((deadline.left(), sol.status))
        return prove(problem, sol, deadline, *args)

    prove = driver.prove_no_solution
    monkeypatch.setattr(driver, "run_lcp_qp", out_of_time)
    monkeypatch.setattr(driver, "prove_no_solution", spy)
    sol = qpcontact.solve(problem, "auto", time_limit=60)
    assert sol.status == "infeasible" and sol.stats.get("proved_infeasible"), sol.message
    assert shares and shares[0][1] == "time_limit" and shares[0][0] <= 0.5 * 60
    z = [_F(v) for v in sol.stats["proof"].vector["z"]]
    assert z[4] > 0 and z[5] > 0 and z[4] == z[5] and not any(z[:4])
