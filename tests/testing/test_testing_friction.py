"""qpcontact.testing on frictional contact: the assertion, cross-validation,
the planted cases and their strategy, the plugin's friction fixture, and the
friction certificate's forward error.  References: the planted solutions of
qpcontact.cases.planted_friction (exact by construction), and Coulomb's law checked
by hand below."""

from __future__ import annotations

import re
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

import qpcontact
from qpcontact.judge.friction_certificate import contact_sizes
from qpcontact.testing import (FRICTION_KINDS, CrossValidationError, assert_friction_solution,
                               build_friction, cross_validate)
from qpcontact.testing.strategies import frictions
from tests.helpers.paths import DOCS

pytest_plugins = ["pytester"]


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("kind", FRICTION_KINDS)
def test_planted_answers_pass_and_moved_ones_fail(kind, dim):
    """The planted (r, u) satisfies Coulomb's law exactly (checked by hand:
    cone, velocity, complementarity), the assertion passes it at 1e-12, and
    Case.agrees rejects it moved by 1e-3 of each contact's size."""
    case = build_friction(kind, 5, 11, dim=dim)
    R, U = case.r.reshape(-1, dim), case.u.reshape(-1, dim)
    mu = case.problem.mu
    assert np.all(np.linalg.norm(R[:, 1:], axis=1) <= mu * R[:, 0] * (1 + 1e-15))
    uhat_n = U[:, 0] + mu * np.linalg.norm(U[:, 1:], axis=1)
    assert np.all(U[:, 0] >= 0) and np.allclose(R[:, 0] * uhat_n + np.sum(R[:, 1:] * U[:, 1:], 1), 0)
    np.testing.assert_allclose(case.problem.velocities(case.r), case.u,
                               atol=1e-12 * np.abs(case.u).max())
    assert_friction_solution(case.problem, case.r, tol=1e-12)
    assert case.agrees(case.r)
    size = np.repeat(np.maximum(np.linalg.norm(R, axis=1), case.scale), dim)
    wrong = case.r + 1e-3 * size * np.tile(np.r_[1.0, np.zeros(dim - 1)], case.problem.n_contacts)
    assert not case.agrees(wrong)


def _one_contact(dim, r, q, mu=0.5):
    return qpcontact.FrictionProblem(np.eye(dim), q, [mu], dim), np.asarray(r, float)


def test_the_assertion_names_the_contact_and_the_law_it_breaks():
    """Three wrong answers, each breaking one part of Coulomb's law at one
    contact of a two-contact problem whose other contact is right."""
    W = np.eye(4)
    q = np.array([-2.0, 0.5, 1.0, 0.0])      # contact 0 pressed (sticks: |q_T| < μ|q_N|), 1 open
    prob = qpcontact.FrictionProblem(W, q, [0.5, 0.5], 2)
    right = np.array([2.0, -0.5, 0.0, 0.0])   # by hand: r_N = 2, r_T = -q_T, u = 0; contact 1 open
    assert_friction_solution(prob, right)
    outside = right.copy()
    outside[1] = -1.5                          # |r_T| = 1.5 > μ r_N = 1
    with pytest.raises(AssertionError, match=r"contact 0: the reaction is outside its friction "
                                             r"cone: ‖r_T‖ = 1\.500e\+00"):
        assert_friction_solution(prob, outside)
    pushed = right.copy()
    pushed[0] = 1.0                            # u_N = r_N + q_N = -1: into the obstacle
    with pytest.raises(AssertionError, match=r"contact 0: its velocity points into the obstacle"):
        assert_friction_solution(prob, pushed)
    holding = right.copy()
    holding[2] = 0.5                           # a force at the open contact, which separates
    with pytest.raises(AssertionError, match=r"contact 1: it is neither open, sticking nor "
                                             r"sliding"):
        assert_friction_solution(prob, holding)
    with pytest.raises(AssertionError, match="r has 3 entries"):
        assert_friction_solution(prob, right[:3])
    with pytest.raises(AssertionError, match="not finite at index 2 .contact 1"):
        assert_friction_solution(prob, np.r_[right[:2], np.nan, 0.0])


def test_the_assertion_sees_a_contact_the_siconos_measure_hides():
    """Forces in kN, velocities in m/s of a stiff structure (W ~ 1e-5): a
    force error of 1e-2 kN is below 1e-7 in Siconos's measure, and the
    assertion still catches it on the contact's own scale."""
    prob = qpcontact.FrictionProblem(1e-5 * np.eye(2), [-1e-5, 0.0], [0.3], 2)
    exact = np.array([1.0, 0.0])               # r_N = -q_N / W_nn, sticking at r_T = 0
    assert_friction_solution(prob, exact, tol=1e-12)
    off = exact + [1e-2, 0.0]
    cert = qpcontact.certify(prob, off)
    assert cert.natural_map_error < 1e-6 and cert.componentwise_error > 1e-3
    with pytest.raises(AssertionError, match="contact 0"):
        assert_friction_solution(prob, off, tol=1e-6)


def test_certify_takes_a_friction_problem():
    case = build_friction("mixed", 4, 2, dim=3)
    cert = qpcontact.certify(case.problem, case.r)
    assert isinstance(cert, qpcontact.FrictionCertificate)
    assert cert.ok(1e-12) and cert.error == max(cert.natural_map_error, cert.componentwise_error)
    assert set(cert.as_dict()) >= {"error", "natural_map_error", "componentwise_error",
                                   "forward_error", "condition"}


@pytest.mark.parametrize("dim", [2, 3])
def test_forward_error_bounds_the_distance_to_the_unique_solution(dim):
    """Decoupled isotropic contacts have one solution (the planted one): every
    certified answer lies within its forward-error estimate of it, contact by
    contact on the contact's own scale (a factor 2 for first order)."""
    checked = 0
    for seed in range(12):
        case = build_friction("decoupled", 6, seed, dim=dim)
        size = contact_sizes(case.problem, case.r)
        for method in ("desaxce-fp", "newton", "nsgs"):
            sol = qpcontact.solve(case.problem, method, accuracy=1e-7)
            if not sol.ok:
                continue
            dist = np.linalg.norm((sol.r - case.r).reshape(-1, dim), axis=1) / size
            assert np.isfinite(sol.forward_error)
            assert dist.max() <= 2 * sol.forward_error + 1e-14, (seed, method)
            checked += 1
    assert checked >= 20


def test_forward_error_is_infinite_where_the_solution_is_not_isolated():
    """Two contacts with the same row of W (a body on two coincident supports):
    the load splits between them in any proportion, and the estimate says so."""
    W = np.array([[1.0, 0, 1, 0], [0, 1, 0, 1], [1, 0, 1, 0], [0, 1, 0, 1]])
    prob = qpcontact.FrictionProblem(W, [-1.0, 0.0, -1.0, 0.0], [0.5, 0.5], 2)
    sol = qpcontact.solve(prob, accuracy=1e-9)
    assert sol.ok and sol.forward_error == np.inf
    assert sol.r[0] + sol.r[2] == pytest.approx(1.0)     # by hand: r_N1 + r_N2 = 1


def test_cross_validate_agrees_on_a_frictional_problem():
    case = build_friction("mixed", 5, 3, dim=3)
    report = cross_validate(case.problem, accuracy=1e-8)
    assert {"nsgs", "newton", "desaxce-fp"} <= set(report.certified)
    assert report.compared.startswith("r contact by contact") and report.disagreement <= 1.0
    for name in report.certified:
        assert case.agrees(report.solutions[name].r), name


def test_cross_validate_catches_a_moved_friction_answer(monkeypatch):
    case = build_friction("decoupled", 4, 1, dim=2)
    real = qpcontact.solve

    def faulty(problem, method, accuracy, **kw):
        sol = real(problem, method, accuracy, **kw)
        if method == "nsgs":
            sol.r = sol.r + 1e-4 * np.abs(sol.r).max()
        return sol

    monkeypatch.setattr(sys.modules["qpcontact.dispatch.driver"], "solve", faulty)
    with pytest.raises(CrossValidationError, match="nsgs.*at contact"):
        cross_validate(case.problem, methods=["lemke", "nsgs"], accuracy=1e-9)


def test_cross_validate_reports_two_solutions_of_coulombs_law():
    """Six sliding contacts: Lemke and Newton each certify an isolated
    solution, both satisfy Coulomb's law (checked by the case), and they
    differ — several solutions, which cross-validation must not pass."""
    case = build_friction("sliding", 6, 8, dim=2, cond=1e3)
    a = qpcontact.solve(case.problem, "lemke", accuracy=1e-7)
    b = qpcontact.solve(case.problem, "newton", accuracy=1e-7)
    assert a.ok and b.ok and case.agrees(a.r) and case.agrees(b.r)
    assert np.abs(a.r - b.r).max() > 1e-2 * np.abs(a.r).max()
    with pytest.raises(CrossValidationError, match="several solutions"):
        cross_validate(case.problem, methods=["lemke", "newton"], accuracy=1e-7)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(frictions())
def test_strategy_frictions_are_solved_by_auto(case):
    sol = qpcontact.solve(case.problem, accuracy=1e-8)
    assert sol.ok, (case.kind, sol.message)
    assert case.agrees(sol.r, rtol=1e-6), case.kind
    assert_friction_solution(case.problem, sol.r, tol=1e-8)


def test_solve_friction_is_solve():
    case = build_friction("mixed", 3, 4, dim=2)
    a = qpcontact.solve_friction(case.problem, "lemke", accuracy=1e-9)
    b = qpcontact.solve(case.problem, "lemke", accuracy=1e-9)
    np.testing.assert_array_equal(a.r, b.r)
    assert a.status == b.status == "solved" and isinstance(a, qpcontact.FrictionSolution)
    text = repr(a)
    assert "r: [" in text and "status: 'solved' (ok)" in text and len(text) < 800


@pytest.mark.slow
def test_the_plugin_selects_friction_methods(pytester):
    pytester.makepyfile("""
        import qpcontact, pytest
        from qpcontact.testing import assert_friction_solution, build_friction

        def test_solves(friction_method):
            case = build_friction("sticking", 2, 0, dim=2)
            sol = qpcontact.solve(case.problem, method=friction_method, accuracy=1e-8)
            assert_friction_solution(case.problem, sol.r, tol=1e-8)

        def test_lcp(qp_method):
            assert qpcontact.methods()[qp_method].solves("lcp")

        @pytest.mark.qp_methods("friction")
        def test_family(friction_method):
            assert qpcontact.methods()[friction_method].family == "friction"
    """)
    # a subprocess, as in tests/testing/test_testing_module.py (numba in pytester's in-process run)
    result = pytester.runpytest_subprocess("-p", "no:xdist", "--qp-methods=lemke,nsgs,osqp", "-v")
    result.assert_outcomes(passed=5)   # solves: lemke, nsgs; lcp: lemke, osqp; family: nsgs
    result.stdout.fnmatch_lines(["*test_solves?nsgs?*PASSED*", "*test_lcp?osqp?*PASSED*"])


@pytest.mark.slow
def test_the_docs_example_runs(pytester):
    """docs/testing.md's frictional-model example, as a user's test file."""
    text = (DOCS / "testing.md").read_text()
    block = re.search(r"<!-- friction example -->\s*```python\n(.*?)```", text, re.S)
    assert block, "docs/testing.md lost its friction example"
    pytester.makepyfile(test_user=block.group(1))
    result = pytester.runpytest_subprocess("-p", "no:xdist", "--qp-methods=lemke,nsgs,newton")
    result.assert_outcomes(passed=5)
