"""qpcontact.testing: the assertions, cross_validate, the strategies and the pytest plugin."""

from __future__ import annotations

import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from qpsolvers import Problem

import qpcontact
from qpcontact.testing import (CrossValidationError, assert_lcp_solution, assert_qp_kkt,
                               cross_validate, random_spd_lcp)
from qpcontact.cases.planted import build_lcp, build_qp
from qpcontact.testing.strategies import lcps, qps

pytest_plugins = ["pytester"]


def _tiny():
    # M = [[2, 1], [1, 2]], q = [-1, 1]: z = (0.5, 0), w = (0, 1.5)  (by hand)
    return qpcontact.LCP(np.array([[2.0, 1.0], [1.0, 2.0]]), np.array([-1.0, 1.0]))


def test_assert_lcp_solution_passes_on_the_hand_solution():
    assert_lcp_solution(_tiny(), [0.5, 0.0])
    assert_lcp_solution((np.array([[2.0, 1.0], [1.0, 2.0]]), np.array([-1.0, 1.0])), [0.5, 0.0])


@pytest.mark.parametrize("z, condition, index", [
    ([0.5, -1e-3], "z >= 0", 1),
    ([0.4, 0.0], "w = Mz + q >= 0", 0),
    ([0.5, 0.1], "complementarity", 1),
])
def test_assert_lcp_solution_names_condition_and_index(z, condition, index):
    with pytest.raises(AssertionError) as info:
        assert_lcp_solution(_tiny(), z)
    text = str(info.value)
    assert condition in text and f"index {index}" in text and "scale" in text, text


def test_assert_lcp_solution_judges_each_component_on_its_own_scale():
    # a 1 N contact beside a 1e9 N one: the small one wrong by 1e-3 of itself
    M = np.diag([1.0, 1.0])
    q = np.array([-1.0, -1e9])
    assert_lcp_solution((M, q), [1.0, 1e9])
    with pytest.raises(AssertionError, match="index 0"):
        assert_lcp_solution((M, q), [1.001, 1e9])


def test_assert_lcp_solution_refuses_nan_and_wrong_shape():
    with pytest.raises(AssertionError, match="not finite at index 1"):
        assert_lcp_solution(_tiny(), [0.5, np.nan])
    with pytest.raises(AssertionError, match="shape"):
        assert_lcp_solution(_tiny(), [0.5])


def test_assert_qp_kkt_names_the_row():
    # min ½|x|² - x0 s.t. x1 >= 1 (as -x1 <= -1): x = (1, 1), z = 1 (by hand)
    prob = Problem(np.eye(2), np.array([-1.0, 0.0]), np.array([[0.0, -1.0]]), np.array([-1.0]))
    assert_qp_kkt(prob, [1.0, 1.0], z=[1.0])
    with pytest.raises(AssertionError) as info:
        assert_qp_kkt(prob, [1.0, 1.0], z=[0.5])
    assert "stationarity[1]" in str(info.value) and "scale" in str(info.value)
    with pytest.raises(AssertionError, match="missing multiplier"):
        assert_qp_kkt(prob, [1.0, 1.0])


def test_cross_validate_agrees_on_a_unique_solution():
    lcp, z_star = random_spd_lcp(15, 1e4, 3)
    report = cross_validate(lcp, methods=["lemke", "bpp", "osqp", "clarabel"])
    assert report.unique and len(report.certified) == 4 and report.disagreement <= 1.0
    for name in report.certified:
        assert np.allclose(report.solutions[name].z, z_star, rtol=1e-6, atol=1e-8)


def test_cross_validate_explains_non_uniqueness():
    case = build_lcp("psd_singular", 10, 4)
    report = cross_validate(case.problem, methods=["lemke", "osqp"])
    assert not report.unique and "w = Mz + q" in report.uniqueness
    assert report.compared == "w componentwise"


def test_cross_validate_raises_when_certified_answers_disagree(monkeypatch):
    """A method whose certificate let a wrong answer through must be caught:
    one answer is moved by far more than the forward error allows."""
    lcp, _ = random_spd_lcp(8, 10.0, 5)
    real_solve = qpcontact.solve

    def faulty(problem, method, accuracy, **kw):
        sol = real_solve(problem, method, accuracy, **kw)
        if method == "osqp":
            sol.z = sol.z + 1e-3 * np.maximum(np.abs(sol.z), 1.0)
            sol.w = problem.w(sol.z)
        return sol

    monkeypatch.setattr(sys.modules["qpcontact.dispatch.driver"], "solve", faulty)
    with pytest.raises(CrossValidationError, match="osqp"):
        cross_validate(lcp, methods=["lemke", "osqp"])


def test_cross_validate_requires_certified_answers():
    case = build_lcp("infeasible", 6, 1)
    with pytest.raises(CrossValidationError, match="certified"):
        cross_validate(case.problem, methods=["lemke"])


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(lcps(max_n=16))
# infeasible as stored, feasible within rounding: "energy" certifies a point of
# the nearby data, then the exact Farkas check turns it into "infeasible"
@example(build_lcp("infeasible", 3, 890))
# solvable, but Lemke ends on a secondary ray with 31 covering vectors: "auto"
# must go on to "enumeration" (hypothesis found it on 2026-11-23)
@example(build_lcp("friction", 12, 1604))
# a rank-one M = fl(b b') with q = fl(w - Mz): the stored data admit no z at
# all (an exact Farkas vector, 0 <= -1.7e-20; found by hypothesis 2026-12-06)
@example(build_lcp("psd_singular", 2, 25))
def test_strategy_lcps_reach_their_built_in_status(case):
    sol = qpcontact.solve(case.problem, "auto")
    if case.status == "infeasible":
        # one status for a proof checked from the data, whoever found it
        # (Lemke's Farkas vector, or the proof search after another method)
        assert sol.status == "infeasible" and sol.stats.get("proved_infeasible"), sol.message
    elif case.kind == "psd_singular" and sol.status == "infeasible":
        # q = fl(w - Mz) may fall off M's range by rounding: then the data as
        # stored have no solution, and an exact proof of that outranks the
        # planted z (which holds for nearby data only)
        assert sol.stats.get("proved_infeasible"), sol.message
    elif case.kind == "psd_singular" and sol.status == "ill_posed":
        # q = fl(w - Mz) is solvable only up to rounding: where a null vector
        # y >= 0 of the singular M carries q'y within rounding of zero, the
        # stored data may have no solution and no digit is guaranteed — the
        # honest word is "ill_posed", with the vector named (judge/near_farkas)
        assert sol.stats.get("near_farkas") is not None, sol.message
        assert not sol.ok
    else:
        assert sol.ok, (case.kind, sol.message)
        assert case.agrees(sol.z), case.kind
        assert_lcp_solution(case.problem, sol.z)


def test_a_farkas_proof_reads_its_exact_sum():
    """The proof's message shows the weighted sum's right-hand side as it
    was checked, exactly: recomputed in floating point it cancelled, and a
    sound proof read "0 <= 0.000e+00"."""
    sol = qpcontact.solve(build_lcp("psd_singular", 2, 25).problem, "auto")
    assert sol.status == "infeasible" and sol.stats.get("proved_infeasible")
    assert "reads 0 <= -1.689e-20" in sol.message, sol.message


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(qps(max_n=12))
def test_strategy_qps_reach_their_built_in_status(case):
    sol = qpcontact.solve(case.problem, "auto")
    assert sol.status == case.status, (case.kind, sol.message)
    if case.status == "solved":
        assert case.agrees(sol.x), case.kind
        assert_qp_kkt(case.problem, sol.x, y=sol.y, z=sol.z, z_box=sol.z_box)


@pytest.mark.parametrize("kind", ["spd", "badly_scaled", "p_matrix", "friction"])
def test_planted_cases_reject_a_wrong_answer(kind):
    """Case.agrees must be able to fail: the planted answer moved by 1e-3."""
    case = build_lcp(kind, 12, 7)
    wrong = case.z + 1e-3 * np.maximum(np.abs(case.z), 1.0)
    assert case.agrees(case.z) and not case.agrees(wrong)
    qcase = build_qp("convex", 8, 7)
    assert qcase.agrees(qcase.x) and not qcase.agrees(qcase.x + 1e-3)


@pytest.mark.slow
def test_plugin_parametrises_qp_method(pytester):
    pytester.makepyfile("""
        import numpy as np, qpcontact, pytest
        from qpcontact.testing import assert_lcp_solution

        def test_solves(qp_method):
            lcp = qpcontact.LCP(np.array([[2.0, 1.0], [1.0, 2.0]]), np.array([-1.0, 1.0]))
            sol = qpcontact.solve(lcp, method=qp_method)
            assert_lcp_solution(lcp, sol.z)

        @pytest.mark.qp_methods("pivoting")
        def test_only_pivoting(qp_method):
            assert qpcontact.methods()[qp_method].family == "pivoting"
    """)
    # In a subprocess: an in-process run restores sys.modules afterwards, and
    # numba modules first imported inside it (numba.np.polynomial, loaded
    # with a cached kernel) are then imported a second time by later tests in
    # this worker, which numba refuses ("duplicate registration for
    # PolynomialType": 29 failures under pytest -n 2 with some test orders).
    result = pytester.runpytest_subprocess("-p", "no:xdist", "--qp-methods=lemke,osqp,bpp", "-v")
    result.assert_outcomes(passed=5)
    result.stdout.fnmatch_lines(["*test_solves?osqp?*PASSED*"])
    bad = pytester.runpytest_subprocess("-p", "no:xdist", "--qp-methods=lemkee")
    assert bad.ret == pytest.ExitCode.USAGE_ERROR
    assert "Did you mean 'lemke'" in str(bad.stderr) + str(bad.stdout)
