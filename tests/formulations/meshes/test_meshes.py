"""Mesh-scale contact: the membrane, plate and 3-D block families
and the "ip-bpp" method, at small n against independent references — the
energy method on the LCP, a manufactured solution (degenerate instances), the
dense Schur complement of the mixed problem solved by Lemke, and Clarabel."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from qpsolvers import Problem

import qpcontact
from formulations import meshes
from qpcontact import InvalidOptionError, InvalidProblemError, NotConvexError


def _lcp_reference(lcp):
    ref = qpcontact.solve(lcp, method="energy")
    assert ref.ok, ref.message
    return ref.z


@pytest.mark.parametrize("family,N", [("membrane", 15), ("membrane", 24), ("plate", 12),
                                      ("plate", 18)])
def test_obstacle_families_agree_with_the_energy_method(family, N):
    lcp = getattr(meshes, family)(N)
    z_ref = _lcp_reference(lcp)
    assert 0 < np.count_nonzero(z_ref == 0) < z_ref.size   # some contact, some free
    sol = qpcontact.solve(lcp, method="ip-bpp")
    assert sol.ok, sol.message
    scale = np.abs(z_ref).max()
    np.testing.assert_allclose(sol.z, z_ref, rtol=0, atol=1e-10 * scale)
    np.testing.assert_array_equal(sol.z == 0, z_ref == 0)


@pytest.mark.parametrize("family", ["membrane", "plate"])
@pytest.mark.parametrize("scale", [1.0, 1e9])
def test_degenerate_and_badly_scaled_instances_recover_the_manufactured_solution(family, scale):
    """z and w built first, 10 % of the indices with z_i = w_i = 0 (the obstacle
    touches without pressing); M SPD makes z the unique solution."""
    N = 14
    lcp = getattr(meshes, family)(N, degenerate=True, scale=scale, seed=3)
    z_true, w_true = meshes._manufactured(np.random.default_rng(3), N * N)
    assert np.count_nonzero((z_true == 0) & (w_true == 0)) >= 0.09 * N * N
    for method in ("ip-bpp", "bpp"):
        sol = qpcontact.solve(lcp, method=method)
        assert sol.ok, (method, sol.message)
        np.testing.assert_allclose(sol.z, z_true, rtol=0, atol=1e-10 * z_true.max())


def _schur_reference(problem):
    """The mixed problem condensed onto its bounded components by dense
    algebra (x_f = -P_ff⁻¹(c_f + P_fb x_b)), the resulting LCP in
    y = x_b − l_b solved by Lemke, then x_f recovered."""
    P = problem.P.toarray() if sp.issparse(problem.P) else np.asarray(problem.P)
    c, lb = problem.q, problem.lb
    b = np.flatnonzero(np.isfinite(lb))
    f = np.flatnonzero(~np.isfinite(lb))
    Pff_inv_Pfb = np.linalg.solve(P[np.ix_(f, f)], P[np.ix_(f, b)])
    Pff_inv_cf = np.linalg.solve(P[np.ix_(f, f)], c[f])
    S = P[np.ix_(b, b)] - P[np.ix_(b, f)] @ Pff_inv_Pfb
    S = 0.5 * (S + S.T)
    c_red = c[b] - P[np.ix_(b, f)] @ Pff_inv_cf
    sol = qpcontact.solve(qpcontact.LCP(S, S @ lb[b] + c_red), method="lemke")
    assert sol.ok, sol.message
    x = np.empty(c.size)
    x[b] = sol.z + lb[b]
    x[f] = -Pff_inv_cf - Pff_inv_Pfb @ x[b]
    return x


@pytest.mark.parametrize("nx", [4, 6])
def test_elastic_block_mixed_problem_agrees_with_its_condensed_lcp(nx):
    problem, info = meshes.signorini(nx)
    assert np.isfinite(problem.lb).sum() == (nx + 1) ** 2          # u_z of the bottom nodes only
    x_ref = _schur_reference(problem)
    sol = qpcontact.solve(problem, method="ip-bpp")
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.x, x_ref, rtol=0, atol=1e-9 * np.abs(x_ref).max())
    gap = sol.x[info["contact"]] + info["gap"]
    assert np.any(gap <= 1e-12 * info["gap"].max()) and np.any(gap > 1e-6 * info["gap"].max())
    # the bounds' multipliers are the foundation's reactions: compressive where closed
    zb = sol.z_box[info["contact"]]
    assert np.all(zb <= 0) and np.all(zb[gap > 1e-9 * info["gap"].max()] == 0)


@pytest.mark.parametrize("route", ["condensed", "full"])
def test_both_routes_of_the_mixed_problem_agree_with_the_condensed_lcp(route):
    """Few bounded dofs: ip-bpp condenses onto them (the Schur complement is
    read off one LDLᵀ).  Many: it works on P itself.  Bounds far below the
    answer on half the free dofs force the second route without changing the
    answer."""
    problem, _ = meshes.signorini(5)
    x_ref = _schur_reference(problem)
    if route == "full":
        lb = problem.lb.copy()
        spare = np.flatnonzero(~np.isfinite(lb))[::2]
        lb[spare] = x_ref[spare] - 1e3 * np.abs(x_ref).max()
        problem = Problem(problem.P, problem.q, lb=lb)
    sol = qpcontact.solve(problem, method="ip-bpp")
    assert sol.ok, sol.message
    assert ("condensed" in sol.stats) == (route == "condensed")
    np.testing.assert_allclose(sol.x, x_ref, rtol=0, atol=1e-9 * np.abs(x_ref).max())


def test_condensed_route_refuses_a_singular_free_block():
    P = sp.block_diag([np.ones((2, 2))] + [np.eye(1)] * 6, format="csc")
    lb = np.full(8, -np.inf)
    lb[7] = 0.0
    with pytest.raises(NotConvexError, match="not numerically positive definite"):
        qpcontact.solve(Problem(P, -np.ones(8), lb=lb), method="ip-bpp")


def test_elastic_block_agrees_with_clarabel():
    problem, _ = meshes.signorini(6)
    ours = qpcontact.solve(problem, method="ip-bpp")
    other = qpcontact.solve(problem, method="clarabel", accuracy="high")
    assert ours.ok and other.ok
    np.testing.assert_allclose(ours.x, other.x, rtol=0, atol=1e-7 * np.abs(ours.x).max())


@pytest.mark.parametrize("max_ip", [0, 1])
def test_pivoting_phase_alone_is_exact_from_a_poor_start(max_ip):
    """No or one interior step: the block pivoting (with its safeguard) does
    everything, on the plate, whose matrix is not an M-matrix."""
    lcp = meshes.plate(12)
    z_ref = _lcp_reference(lcp)
    sol = qpcontact.solve(lcp, method="ip-bpp", max_ip=max_ip)
    assert sol.ok, sol.message
    assert sol.stats["iterations"] > 0 and sol.stats["ip_steps"] == max_ip
    np.testing.assert_allclose(sol.z, z_ref, rtol=0, atol=1e-10 * np.abs(z_ref).max())


def test_progress_lines_report_each_step():
    lines = []
    sol = qpcontact.solve(meshes.membrane(20), method="ip-bpp", progress=lines.append)
    assert sol.ok
    assert any("interior step" in ln for ln in lines) and any("pivoting step" in ln for ln in lines)
    assert len(lines) == sol.stats["ip_steps"] + sol.stats["iterations"] + 1


def test_ip_bpp_refuses_what_it_cannot_solve():
    P = sp.identity(3, format="csc")
    with pytest.raises(InvalidProblemError, match="inequalities"):
        qpcontact.solve(Problem(P, np.ones(3), G=np.eye(3), h=np.ones(3)), method="ip-bpp")
    with pytest.raises(InvalidProblemError, match="upper bounds"):
        qpcontact.solve(Problem(P, np.ones(3), lb=np.zeros(3), ub=np.ones(3)), method="ip-bpp")
    with pytest.raises(InvalidProblemError, match="P\\[1,1\\]"):
        qpcontact.solve(Problem(sp.diags([1.0, 0.0, 1.0]).tocsc(), np.ones(3), lb=np.zeros(3)),
                        method="ip-bpp")
    with pytest.raises(InvalidOptionError, match="ip_drop"):
        qpcontact.solve(meshes.membrane(4), method="ip-bpp", ip_drop=0.5)
    with pytest.raises(InvalidOptionError, match="progress"):
        qpcontact.solve(meshes.membrane(4), method="ip-bpp", progress="yes")


def test_dense_p_takes_the_same_route():
    lcp = meshes.membrane(10)
    dense = qpcontact.LCP(lcp.M.toarray(), lcp.q)
    a = qpcontact.solve(lcp, method="ip-bpp")
    b = qpcontact.solve(dense, method="ip-bpp")
    assert a.ok and b.ok
    np.testing.assert_allclose(a.z, b.z, rtol=0, atol=1e-12 * np.abs(a.z).max())


def test_mesh_instances_for_compare():
    insts = meshes.instances("small", "easy") + meshes.instances("small", "hard")
    names = [i.name for i in insts]
    assert any("signorini" in nm for nm in names) and any("degenerate" in nm for nm in names)
    for inst in insts:
        sol = qpcontact.solve(inst.problem, method="ip-bpp")
        assert sol.ok, (inst.name, sol.message)
