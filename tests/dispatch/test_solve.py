"""solve(): statuses decided by the certificate, and every documented exception."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from qpsolvers import Problem

import qpcontact
from qpcontact import (LCP, BackendUnavailableError, InvalidOptionError, InvalidProblemError,
                       MethodResult, NoSolutionError, NotConvexError, NotSymmetricError,
                       ParametricLCP, SolverFailedError, UnknownMethodError)
from qpcontact.solvers.registry import _REGISTRY, get_method
from qpcontact.cases.paper import p0_examples

EX1 = p0_examples()[0]


def _patched(monkeypatch, name, transform):
    """Replace method ``name`` by a wrapper whose answer passes through ``transform``."""
    original = get_method(name)

    def run(problem, tol, options):
        res = original.run(problem, tol, options)
        return transform(res)

    monkeypatch.setitem(_REGISTRY, name, dataclasses.replace(original, run=run))


@pytest.mark.parametrize("name", ["osqp", "clarabel", "daqp"])
def test_perturbed_backend_is_reported_inaccurate(monkeypatch, name):
    def perturb(res):
        res.x = res.x + 1e-3
        return res
    _patched(monkeypatch, name, perturb)
    sol = qpcontact.solve(EX1.lcp, method=name, accuracy="high")
    assert sol.status == "inaccurate" and not sol.ok
    assert sol.backend_status.lower() in ("solved", "found")  # the backend still claims success
    assert "not certified" in sol.message
    with pytest.raises(SolverFailedError, match="no certified solution"):
        qpcontact.solve(EX1.lcp, method=name, accuracy="high", raise_on_failure=True)


def test_nan_answer_is_failed(monkeypatch):
    def nan(res):
        res.x = np.full_like(res.x, np.nan)
        return res
    _patched(monkeypatch, "osqp", nan)
    sol = qpcontact.solve(EX1.lcp, method="osqp")
    assert sol.status == "failed" and sol.z is None and sol.certificate is None


def test_an_unproved_ray_is_no_proof(monkeypatch):
    """A secondary ray with no checked Farkas vector proves nothing: status
    "ray", and raise_on_failure says the method failed — never "no solution"
    (EX1 has one)."""
    _patched(monkeypatch, "osqp", lambda res: MethodResult(x=None, status="ray", backend_message="secondary ray"))
    assert qpcontact.solve(EX1.lcp, method="osqp").status == "ray"
    with pytest.raises(SolverFailedError, match="secondary ray"):
        qpcontact.solve(EX1.lcp, method="osqp", raise_on_failure=True)


def test_low_accuracy_is_certified_at_its_own_level():
    sol = qpcontact.solve(EX1.lcp, method="scs", accuracy="low")
    assert sol.tol == 1e-4 and sol.ok == (sol.error <= 1e-4)
    sol = qpcontact.solve(EX1.lcp, method="osqp", accuracy="default")  # OSQP defaults: eps 1e-3, no polish
    assert sol.tol == 1e-6 and sol.status == "inaccurate"


def test_auto_certifies_and_records_attempts():
    for ex in p0_examples():
        sol = qpcontact.solve(ex.lcp)
        assert sol.ok and sol.stats["auto_tried"][-1][0] == sol.method
        np.testing.assert_allclose(sol.z, ex.z, atol=1e-8)


def test_auto_hands_progress_only_to_the_links_that_report_it():
    """Before: "auto" passed ``progress`` to every link, and an LCP that
    reached Lemke raised "'lemke' does not take progress" after the first
    links had run.  A nonsymmetric M with M + M' positive definite: Lemke
    first, which takes no progress; the lines say which link ran."""
    rng = np.random.default_rng(0)
    B = rng.normal(size=(12, 12))
    M = B @ B.T + np.eye(12)
    M[0, 1] += 3.0
    lines = []
    sol = qpcontact.solve(LCP(M, rng.normal(size=12)), "auto", progress=lines.append)
    assert sol.ok and sol.method == "lemke"
    assert lines[0].startswith("auto: lemke") and lines[-1].startswith("auto: lemke: solved")
    with pytest.raises(InvalidOptionError, match="'auto': option progress must be a callable"):
        qpcontact.solve(LCP(M, np.ones(12)), "auto", progress="lines")


def test_qp_input_returns_duals_in_qpsolvers_convention():
    qp = EX1.lcp.to_qp()
    for name in ("clarabel", "daqp", "cvxpy:CLARABEL"):
        sol = qpcontact.solve(qp, method=name)
        assert isinstance(sol, qpcontact.QPSolution) and sol.ok, (name, sol.message)
        np.testing.assert_allclose(-sol.z_box, EX1.w, atol=1e-8)


def test_cvxpy_equality_duals_have_qpsolvers_sign():
    qp = Problem(np.eye(2), np.zeros(2), A=np.array([[1.0, 1.0]]), b=np.array([1.0]), lb=np.zeros(2))
    ref = qpcontact.solve(qp, method="clarabel")
    sol = qpcontact.solve(qp, method="cvxpy:CLARABEL")
    assert sol.ok and ref.ok
    np.testing.assert_allclose(sol.y, ref.y, atol=1e-8)  # y = -1/2: P x + A'y = 0 at x = (1/2, 1/2)
    np.testing.assert_allclose(sol.y, [-0.5], atol=1e-8)


def test_misuse_raises_documented_exceptions(monkeypatch):
    with pytest.raises(UnknownMethodError, match="Did you mean 'osqp'"):
        qpcontact.solve(EX1.lcp, method="osqpp")
    fake = dataclasses.replace(get_method("osqp"), name="notinstalled", run=None, available=False,
                               install="pip install notinstalled-solver")
    monkeypatch.setitem(_REGISTRY, "notinstalled", fake)
    with pytest.raises(BackendUnavailableError, match="pip install notinstalled-solver"):
        qpcontact.solve(EX1.lcp, method="notinstalled")
    with pytest.raises(InvalidOptionError, match="'low', 'default', 'high'"):
        qpcontact.solve(EX1.lcp, accuracy="ultra")
    with pytest.raises(InvalidOptionError, match=r"in \(0, 1\)"):
        qpcontact.solve(EX1.lcp, accuracy=2.0)
    with pytest.raises(InvalidOptionError, match="osqp rejected the option"):
        qpcontact.solve(EX1.lcp, method="osqp", not_an_option=1)
    with pytest.raises(InvalidProblemError, match="problem.at"):
        qpcontact.solve(ParametricLCP(np.eye(2), [1, 1], [1, 1]), method="osqp")
    with pytest.raises(InvalidProblemError, match="got list"):
        qpcontact.solve([[1.0]])
    nonmonotone = LCP([[1.0, 3.0], [0.0, 1.0]], [-1.0, -1.0])  # M + M' indefinite
    with pytest.raises(NotSymmetricError, match="lemke"):
        qpcontact.solve(nonmonotone, method="clarabel")
    indefinite = LCP([[1.0, 2.0], [2.0, 1.0]], [-1.0, -1.0])
    with pytest.raises(NotConvexError, match="lemke"):
        qpcontact.solve(indefinite, method="osqp")


def test_methods_lists_the_required_backends():
    names = set(qpcontact.methods())
    for required in ("osqp", "clarabel", "proxqp", "daqp", "piqp", "highs", "quadprog"):
        assert required in names
    assert any(n.startswith("cvxpy:") for n in names)
    m = qpcontact.methods()["daqp"]
    assert m.exact and not m.accepts_sparse and m.returns_duals and not m.needs_symmetric


def test_pivoting_method_on_a_qp_with_more_constraints_than_variables():
    """The dual-LCP route: its z has one entry per constraint, not per variable
    (a size check once rejected every such answer as 'no usable point')."""
    from qpsolvers import Problem

    P = np.array([[2.0, 0.5], [0.5, 1.0]])
    G = np.array([[1.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])
    prob = Problem(P, np.array([-3.0, -2.0]), G, np.array([1.0, 0.0, 0.0]))
    sol = qpcontact.solve(prob, method="lemke")
    ref = qpcontact.solve(prob, method="quadprog" if "quadprog" in qpcontact.methods() else "clarabel")
    assert sol.ok and sol.stats["route"] == "dual-lcp", sol.message
    np.testing.assert_allclose(sol.x, ref.x, atol=1e-8)


def test_the_registry_knows_its_in_house_names_before_loading_them():
    """get_method loads only the provider that has the name; the names it
    knows in advance are exactly what the providers declare."""
    from qpcontact.solvers.friction import friction_specs as friction
    from qpcontact.solvers import registry
    from qpcontact.solvers.pivoting import pivoting_specs as pivoting
    from qpcontact.solvers.trace import trace_specs as trace

    for provider, module in (("pivoting", pivoting), ("trace", trace), ("friction", friction)):
        assert registry.IN_HOUSE[provider] == tuple(m.name for m in module.specs())
    every = qpcontact.all_methods()
    assert set(every) >= {name for names in registry.IN_HOUSE.values() for name in names}


def test_no_applicable_method_is_its_own_error(monkeypatch):
    """Where no installed method applies (here "auto" limited to methods that
    need a symmetric M, given a nonsymmetric one) the error says so and names
    what was considered — not NotSymmetricError, which is about one method."""
    import qpcontact.dispatch.driver as driver

    monkeypatch.setattr(driver, "auto_order", lambda problem: ("energy", "bpp", "no-such-method"))
    lcp = LCP(np.array([[2.0, 1.0], [0.0, 2.0]]), [-1.0, -1.0])
    with pytest.raises(qpcontact.NoApplicableMethodError, match="energy, bpp") as info:
        qpcontact.solve(lcp)
    assert "qpcontact methods" in str(info.value)
    assert not isinstance(info.value, qpcontact.NotSymmetricError)
    # the same problem with the real order is solved (Lemke takes any M)
    monkeypatch.undo()
    assert qpcontact.solve(lcp).ok
