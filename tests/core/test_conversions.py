"""LCP <-> QP conversions, checked against analytic solutions."""

from __future__ import annotations

import numpy as np
import pytest
from qpsolvers import Problem

import qpcontact
from qpcontact.testing import assert_qp_kkt
from qpcontact import LCP, InvalidProblemError, NotConvexError, NotSymmetricError, qp_to_lcp
from qpcontact import certify


def test_to_qp_refuses_nonsymmetric_and_names_lemke():
    lcp = LCP([[1.0, 2.0], [0.0, 1.0]], [-1, -1])
    with pytest.raises(NotSymmetricError) as info:
        lcp.to_qp()
    assert "lemke" in str(info.value) and "to_monotone_qp" in str(info.value)


def test_to_qp_refuses_indefinite():
    with pytest.raises(NotConvexError, match="nonconvex"):
        LCP([[1.0, 2.0], [2.0, 1.0]], [-1, -1]).to_qp()


def test_to_qp_keeps_sparse():
    import scipy.sparse as sp
    qp = LCP(sp.identity(4, format="csc"), -np.ones(4)).to_qp()
    assert sp.issparse(qp.P) and np.all(qp.lb == 0)


@pytest.mark.parametrize("method", ["clarabel", "osqp", "daqp", "quadprog", "cvxpy:CLARABEL"])
def test_monotone_route_solves_nonsymmetric_psd(method):
    # M + M' = 2I; by hand: both z positive, z1 + z2 = 2, -z1 + z2 = 1 -> z = (1/2, 3/2), w = 0
    lcp = LCP([[1.0, 1.0], [-1.0, 1.0]], [-2.0, -1.0])
    sol = qpcontact.solve(lcp, method=method, accuracy="high")
    assert sol.stats["route"].startswith("monotone-qp")
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.z, [0.5, 1.5], atol=1e-8)


def test_monotone_route_on_siconos_ortiz(siconos_dir):
    from qpcontact.io import read_siconos_lcp
    lcp = read_siconos_lcp(siconos_dir / "lcp_ortiz.dat")
    assert not lcp.is_symmetric and lcp.is_positive_definite
    sol = qpcontact.solve(lcp, method="clarabel", accuracy="high")
    assert sol.ok
    np.testing.assert_allclose(sol.z, [2 / 3, 0, 1 / 3, 0], atol=1e-8)  # SOURCE.md


def _project_simplex(c: np.ndarray) -> np.ndarray:
    """Euclidean projection onto {x >= 0, sum x = 1}, by the sort-and-threshold
    rule (Held, Wolfe & Crowder 1974): independent of any QP code."""
    u = np.sort(c)[::-1]
    css = np.cumsum(u) - 1.0
    k = np.nonzero(u - css / np.arange(1, c.size + 1) > 0)[0][-1]
    return np.maximum(c - css[k] / (k + 1), 0.0)


@pytest.mark.parametrize("seed", range(5))
def test_qp_to_lcp_simplex_projection(seed):
    """min ½‖x - c‖² s.t. 1'x = 1, x >= 0: an equality (eliminated) and bounds."""
    rng = np.random.default_rng(seed)
    n = 12
    c = rng.standard_normal(n)
    qp = Problem(np.eye(n), -c, A=np.ones((1, n)), b=np.array([1.0]), lb=np.zeros(n))
    dual = qp_to_lcp(qp)
    assert dual.lcp.n == n and dual.lcp.is_symmetric and dual.lcp.is_psd
    lam = qpcontact.solve(dual.lcp, method="daqp", accuracy="high")
    assert lam.ok
    x, y, z, z_box = dual.primal_dual(lam.z)
    # the dual LCP is singular (rank n - 1: the equality is eliminated), so its
    # 1e-9 certificate carries over to x at the 1e-9 level, not to rounding
    np.testing.assert_allclose(x, _project_simplex(c), atol=1e-9)
    assert_qp_kkt(qp, x, y=y, z=z, z_box=z_box, tol=1e-9)
    assert certify(qp, x, y=y, z=z, z_box=z_box).dual_residual <= 1e-12
    # the same QP through solve(), on the exact LCP route and through a backend
    direct = qpcontact.solve(qp, method="clarabel", accuracy="high")
    assert direct.ok
    np.testing.assert_allclose(direct.x, x, atol=1e-8)


def test_qp_to_lcp_general_constraints_match_backends():
    rng = np.random.default_rng(7)
    n, m, p = 15, 10, 3
    R = rng.standard_normal((n, n))
    P = R @ R.T + n * np.eye(n)
    q = 40.0 * rng.standard_normal(n)  # pushes the unconstrained minimum far outside
    G = rng.standard_normal((m, n))
    h = rng.random(m)
    A = rng.standard_normal((p, n))
    b = rng.standard_normal(p) * 0.1
    lb, ub = -np.ones(n), np.full(n, np.inf)
    ub[:4] = 0.2
    qp = Problem(P, q, G, h, A, b, lb, ub)
    dual = qp_to_lcp(qp)
    assert dual.lcp.n == m + n + 4
    # the dual LCP is PSD but singular (rank <= n - p): quadprog refuses it, daqp does not
    lam = qpcontact.solve(dual.lcp, method="daqp", accuracy="high")
    assert lam.ok, lam.message
    assert np.count_nonzero(lam.z > 1e-8) >= 3  # several constraints active: a real test
    x, y, z, z_box = dual.primal_dual(lam.z)
    assert_qp_kkt(qp, x, y=y, z=z, z_box=z_box, tol=1e-10)
    for method in ("clarabel", "osqp", "daqp"):
        sol = qpcontact.solve(qp, method=method, accuracy="high")
        assert sol.ok, (method, sol.message)
        # strong convexity (λmin(P) >= n) bounds ‖x_a - x_b‖ by the residuals; 1e-7 is generous
        np.testing.assert_allclose(sol.x, x, atol=1e-7)


def test_qp_to_lcp_errors():
    with pytest.raises(NotConvexError, match="positive definite"):
        qp_to_lcp(Problem(np.diag([1.0, 0.0]), np.ones(2), lb=np.zeros(2)))
    with pytest.raises(InvalidProblemError, match="no inequality"):
        qp_to_lcp(Problem(np.eye(2), np.ones(2), A=np.ones((1, 2)), b=np.ones(1)))
    with pytest.raises(InvalidProblemError, match="linearly dependent"):
        qp_to_lcp(Problem(np.eye(2), np.ones(2), A=np.ones((2, 2)), b=np.ones(2), lb=np.zeros(2)))
    with pytest.raises(InvalidProblemError, match="lb\\[1\\] = 2.0 exceeds ub\\[1\\]"):
        qp_to_lcp(Problem(np.eye(2), np.ones(2), lb=np.array([0.0, 2.0]), ub=np.ones(2)))
    with pytest.raises(InvalidProblemError, match="G has 3 columns but P has 2"):
        qp_to_lcp(Problem(np.eye(2), np.ones(2), G=np.ones((1, 3)), h=np.ones(1)))
