"""The pivoting methods ("energy", "bpp", "lemke") as the exact oracle.

References come from outside the code under test: the paper's printed
solutions and pivot counts (Kolesnikov 2013), the literature's pivot counts (Fathi 1979),
exact-rational Lemke and enumeration (tests/helpers/references.py), solutions built
into the random problems, and the QP backends."""

from __future__ import annotations


import numpy as np
import pytest
import scipy.sparse as sp

import qpcontact
from qpcontact import (LCP, InvalidOptionError, NoSolutionError, NotConvexError,
                       NotSymmetricError, SolverFailedError)
from qpcontact.io import read_siconos_lcp
from qpcontact.cases.paper import p0_examples

from tests.helpers.problems import planted_spd_lcp
from tests.helpers.paths import siconos_files
from tests.helpers.references import enumerate_lcp, exact_lemke_pivots, fathi_family, murty_family
from tests.helpers.limits import kept, timed

PIVOTING = ("energy", "bpp", "lemke")


# --- Kolesnikov (2013): the decomposition paper's examples ----------------------

@pytest.mark.parametrize("ex", p0_examples(), ids=lambda e: e.name)
def test_energy_reproduces_paper_solution_and_pivot_count(ex):
    sol = qpcontact.solve(ex.lcp, method="energy")
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.z, ex.z, atol=1e-12)
    np.testing.assert_allclose(sol.w, ex.w, atol=1e-12)
    assert sol.iterations == ex.pivots
    assert sol.stats["fallback"] is False


@pytest.mark.parametrize("method", ["bpp", "lemke"])
@pytest.mark.parametrize("ex", p0_examples(), ids=lambda e: e.name)
def test_other_pivoting_methods_solve_paper_examples(ex, method):
    sol = qpcontact.solve(ex.lcp, method=method)
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.z, ex.z, atol=1e-12)


def test_energy_drops_basic_z_that_turns_negative():
    # Kolesnikov (2013; digest in PAPERS.md): never-drop ends at
    # z = (6/13, -1/13, 11/13); the rule with dropping reaches z = (3/7, 0, 5/7),
    # w = (0, 1/7, 0) in 4 pivots.
    M = np.array([[4.0, 0, -1], [0, 7, 3], [-1, 3, 2]])
    q = np.array([-1.0, -2, -1])
    sol = qpcontact.solve(LCP(M, q), method="energy")
    np.testing.assert_allclose(sol.z, [3 / 7, 0, 5 / 7], atol=1e-14)
    np.testing.assert_allclose(sol.w, [0, 1 / 7, 0], atol=1e-14)
    assert sol.iterations == 4


# --- Siconos data -------------------------------------------------------------

NO_SOLUTION = {"lcp_Pang_isolated_sol_perturbed.dat"}      # SOURCE.md: infeasible
LEMKE_RAY_ALTHOUGH_SOLVABLE = {"lcp_CPS_3.dat"}             # SOURCE.md: bimatrix game


@pytest.mark.parametrize("path", siconos_files(), ids=lambda p: p.name)
def test_lemke_on_siconos(path, siconos_dir):
    lcp = read_siconos_lcp(path)
    sol = qpcontact.solve(lcp, method="lemke")
    if path.name in NO_SOLUTION:
        assert sol.status == "infeasible" and sol.stats["proved_infeasible"], sol.message
        assert "no solution" in sol.message
        with pytest.raises(NoSolutionError):
            qpcontact.solve(lcp, method="lemke", raise_on_failure=True)
    elif path.name in LEMKE_RAY_ALTHOUGH_SOLVABLE:
        # A documented limit of Lemke's method, not an infeasibility: enumeration
        # finds solutions, and the message must not claim there are none.
        assert enumerate_lcp(lcp.M, lcp.q)
        assert sol.status == "ray" and not sol.stats["proved_infeasible"]
        assert "does not prove" in sol.message
    else:
        assert sol.ok, sol.message
        assert sol.certificate.siconos_error < 1e-10
        assert sol.error < 1e-10


def _is_spd(M) -> bool:
    M = M.toarray() if sp.issparse(M) else np.asarray(M)
    return np.allclose(M, M.T, rtol=0, atol=1e-12 * np.abs(M).max()) and \
        np.linalg.eigvalsh(0.5 * (M + M.T)).min() > 1e-12 * np.abs(M).max()


@pytest.mark.parametrize("method", ["energy", "bpp"])
@pytest.mark.parametrize("path", siconos_files(), ids=lambda p: p.name)
def test_energy_and_bpp_on_siconos(path, method, siconos_dir):
    lcp = read_siconos_lcp(path)
    if _is_spd(lcp.M):
        sol = qpcontact.solve(lcp, method=method)
        assert sol.ok and sol.certificate.siconos_error < 1e-10, sol.message
    else:
        with pytest.raises((NotSymmetricError, NotConvexError), match="lemke"):
            qpcontact.solve(lcp, method=method)


# --- pivot-count families -------------------------------------------------------

@pytest.mark.parametrize("n", range(4, 13))
def test_lemke_on_murty_family(n, record_property):
    M, q = murty_family(n)
    sol = qpcontact.solve(LCP(M, q), method="lemke")
    assert sol.ok
    np.testing.assert_allclose(sol.z, np.eye(n)[-1], atol=1e-12)  # unique solution e_n
    record_property("lemke_pivots", sol.iterations)
    assert sol.iterations == exact_lemke_pivots(M, q)[1]


@pytest.mark.parametrize("n", range(2, 13))
def test_fathi_family_energy_one_pivot_lemke_two_to_the_n(n):
    # Fathi (1979): Lemke's method takes 2^n pivots on this SPD family.
    M, q = fathi_family(n)
    lcp = LCP(M, q)
    energy = qpcontact.solve(lcp, method="energy")
    lemke = qpcontact.solve(lcp, method="lemke")
    assert energy.ok and lemke.ok
    assert energy.iterations == 1
    assert lemke.iterations == 2 ** n
    np.testing.assert_allclose(lemke.z, energy.z, atol=1e-10)
    if n <= 7:
        assert exact_lemke_pivots(M, q) == ("solved", 2 ** n)


# --- random SPD families ----------------------------------------------------------

CASES = [(n, cond, seed, sparse) for n, cond in ((20, 10.0), (60, 1e4), (40, 1e8))
         for seed in range(3) for sparse in (False, True)]


@pytest.mark.parametrize("n,cond,seed,sparse", CASES)
def test_pivoting_methods_and_backends_agree_on_random_spd(n, cond, seed, sparse):
    lcp, z_star = planted_spd_lcp(n, cond, seed, sparse=sparse)
    rel = 1e-12 * cond  # forward error of an exact method: cond * rounding
    for method in PIVOTING:
        sol = qpcontact.solve(lcp, method=method)
        assert sol.ok, (method, sol.message)
        assert np.max(np.abs(sol.z - z_star)) <= max(rel, 1e-12) * np.max(np.abs(z_star)), method
    # QP backends at "high": every certified answer has the planted active set
    # (margins 0.5) and z within the error bound; at least one is certified.
    # Interior-point/ADMM backends sit near 1e-9 here (Clarabel 1.07e-9 on one
    # cond-1e4 case), so a miss is reported as "inaccurate", never as wrong.
    certified = []
    for name in ("clarabel", "osqp", "piqp"):
        if name in qpcontact.methods():
            sol = qpcontact.solve(lcp, method=name, accuracy="high")
            assert sol.ok == (sol.error <= 1e-9), name
            if sol.ok:
                certified.append(name)
                assert np.array_equal(sol.z > 1e-6 * z_star.max(), z_star > 0), name
    assert certified or cond > 1e4, "no QP backend certified at 'high'"


def test_energy_rule_fallback_frequency_on_random_spd(record_property):
    """The energy rule alone terminated in every trial Kolesnikov's study ran; count
    how often the Murty fallback is needed here and fail loudly if ever."""
    needed, pivots, trials = [], [], 0
    for seed in range(150):
        n = 5 + seed % 40
        cond = 10.0 ** (seed % 9)
        lcp, _ = planted_spd_lcp(n, cond, seed)
        sol = qpcontact.solve(lcp, method="energy")
        assert sol.ok, (seed, sol.message)
        trials += 1
        pivots.append(sol.iterations)
        if sol.stats["fallback"]:
            needed.append((seed, n, cond, sol.stats["fallback_reason"]))
    record_property("fallback_runs", len(needed))
    record_property("trials", trials)
    assert not needed, f"Murty fallback was needed in {len(needed)}/{trials} trials: {needed}"


def test_fallback_runs_and_is_recorded(monkeypatch):
    from qpcontact.solvers.pivoting import energy

    monkeypatch.setattr(energy, "energy_pivot_cap", lambda n: 1)
    lcp, z_star = planted_spd_lcp(30, 100.0, 7)
    sol = qpcontact.solve(lcp, method="energy")
    assert sol.ok
    assert sol.stats["fallback"] and "cap" in sol.stats["fallback_reason"]
    assert sol.stats["murty_pivots"] > 0
    np.testing.assert_allclose(sol.z, z_star, atol=1e-10)


def test_murty_rule_alone_solves():
    lcp, z_star = planted_spd_lcp(25, 1e3, 3)
    sol = qpcontact.solve(lcp, method="energy", rule="murty")
    assert sol.ok and sol.stats["energy_pivots"] == 0
    np.testing.assert_allclose(sol.z, z_star, atol=1e-9)


# --- degeneracy ---------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(4))
def test_degenerate_problems_certified_without_cycling(seed):
    """z_i = w_i = 0 for a third of the indices, plus ties in q."""
    rng = np.random.default_rng(seed)
    n = 24
    from tests.helpers.problems import seeded_spd_matrix
    M = seeded_spd_matrix(n, 100.0, seed)
    kind = rng.integers(0, 3, n)  # 0: z > 0, 1: w > 0, 2: both zero
    z = np.where(kind == 0, 1.0, 0.0)  # equal values: ties in the criterion
    w = np.where(kind == 1, 1.0, 0.0)
    lcp = LCP(M, w - M @ z)
    for method in PIVOTING:
        sol = qpcontact.solve(lcp, method=method)
        assert sol.ok and sol.status == "solved", (method, sol.message)
        np.testing.assert_allclose(sol.z, z, atol=1e-10)
    # Lemke on a fully degenerate nonsymmetric P-matrix problem (q = 0 rows).
    A = M + np.triu(rng.standard_normal((n, n)), 1) * 0.1
    A = A - np.tril(A, -1) + np.tril(-np.triu(A, 1).T, -1)  # M + skew part: monotone, nonsymmetric
    sol = qpcontact.solve(LCP(A, A @ -z + w), method="lemke")
    assert sol.ok, sol.message


# --- options, warm start, failures ----------------------------------------------------

def test_bpp_warm_start_with_the_true_active_set_needs_no_exchange():
    lcp, z_star = planted_spd_lcp(400, 1e3, 1, sparse=True)
    cold = qpcontact.solve(lcp, method="bpp")
    warm = qpcontact.solve(lcp, method="bpp", initial_active=z_star > 0)
    assert cold.ok and warm.ok
    assert warm.iterations == 0 and warm.stats["factorizations"] == 1
    assert cold.iterations >= 1
    wrong = qpcontact.solve(lcp, method="bpp", initial_active=np.flatnonzero(z_star == 0))
    assert wrong.ok
    np.testing.assert_allclose(wrong.z, z_star, atol=1e-9)


def test_bpp_large_sparse_stays_sparse():
    n = 20_000
    rng = np.random.default_rng(0)
    M = sp.diags([-np.ones(n - 1), 2.5 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csc")
    q = rng.standard_normal(n)
    sol = qpcontact.solve(LCP(M, q), method="bpp")
    assert sol.ok and sol.error < 1e-12, sol.message
    assert sol.iterations < 30


def test_option_errors():
    lcp = p0_examples()[0].lcp
    with pytest.raises(InvalidOptionError, match="initial_active"):
        qpcontact.solve(lcp, method="bpp", initial_active=[0, 9])
    with pytest.raises(InvalidOptionError, match="covering"):
        qpcontact.solve(lcp, method="lemke", covering=[1, -1, 1, 1])
    with pytest.raises(InvalidOptionError, match="takes"):
        qpcontact.solve(lcp, method="energy", tolerance=1)
    with pytest.raises(InvalidOptionError, match="rule"):
        qpcontact.solve(lcp, method="energy", rule="bard")


def test_refusals_name_lemke():
    nonsym = LCP([[2.0, 1.0], [0.0, 2.0]], [-1.0, -1.0])
    indefinite = LCP([[1.0, 2.0], [2.0, 1.0]], [-1.0, -1.0])
    for method in ("energy", "bpp"):
        with pytest.raises(NotSymmetricError, match="'lemke'"):
            qpcontact.solve(nonsym, method=method)
        with pytest.raises(NotConvexError, match="'lemke'"):
            qpcontact.solve(indefinite, method=method)
    assert qpcontact.solve(nonsym, method="lemke").ok
    assert qpcontact.solve(indefinite, method="lemke").ok


def test_lemke_user_covering_vector_and_pivot_limit():
    M, q = fathi_family(8)
    lcp = LCP(M, q)
    sol = qpcontact.solve(lcp, method="lemke", covering=np.arange(1, 9, dtype=float))
    assert sol.ok
    capped = qpcontact.solve(lcp, method="lemke", max_pivots=10)
    assert capped.status == "max_pivots" and not capped.ok and capped.z is None
    with pytest.raises(SolverFailedError, match="pivot limit"):
        qpcontact.solve(lcp, method="lemke", max_pivots=10, raise_on_failure=True)


def test_lemke_ray_on_monotone_infeasible_problem_proves_no_solution():
    # CPS Example 4.4.16 turned infeasible: w1 = z1 - z2 - 1, w2 = -z1 + z2 - 1.
    lcp = LCP([[1.0, -1.0], [-1.0, 1.0]], [-1.0, -1.0])
    sol = qpcontact.solve(lcp, method="lemke")
    assert sol.status == "infeasible" and sol.stats["proved_infeasible"]
    assert sol.stats["covering_vectors_tried"] == 1  # a ray proves it for PSD M: no restarts


def test_auto_prefers_pivoting_for_spd():
    sol = qpcontact.solve(p0_examples()[1].lcp)
    assert sol.method == "energy" and sol.ok
    nonsym = LCP([[2.0, 1.0], [0.0, 2.0]], [-1.0, -1.0])
    assert qpcontact.solve(nonsym).method == "lemke"


def test_tableau_rebuilt_from_data_matches_pivoting_to_it():
    """The energy method's refresh rebuilds the principal pivotal transform from
    the data; it must equal the tableau reached by Gauss–Jordan pivots."""
    from qpcontact.solvers.pivoting.energy import ppt_tableau, principal_pivot

    from tests.helpers.problems import seeded_spd_matrix
    M = seeded_spd_matrix(9, 50.0, 4)
    q = np.random.default_rng(4).standard_normal(9)
    basic = np.array([1, 0, 1, 1, 0, 0, 1, 0, 1], bool)
    T, qbar = ppt_tableau(M, q, basic)
    T2, q2 = np.asfortranarray(M.copy()), q.copy()
    for r in np.flatnonzero(basic):
        principal_pivot(T2, q2, r)
    np.testing.assert_allclose(T, T2, atol=1e-12)
    np.testing.assert_allclose(qbar, q2, atol=1e-12)


@pytest.mark.slow
def test_bpp_general_sparse_pattern_uses_ldl_and_agrees():
    """A 2-D grid Laplacian (bandwidth 30 > BANDED_MAX: the QDLDL path)."""
    from qpcontact.core.linalg import BANDED_MAX

    k = 30
    T = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(k, k))
    L = (sp.kron(T, sp.identity(k)) + sp.kron(sp.identity(k), T) + 0.01 * sp.identity(k * k)).tocsc()
    assert k > BANDED_MAX
    lcp = LCP(L, np.random.default_rng(0).standard_normal(k * k))
    bpp = qpcontact.solve(lcp, method="bpp")
    ref = qpcontact.solve(LCP(L.toarray(), lcp.q), method="energy")
    assert bpp.ok and ref.ok
    np.testing.assert_allclose(bpp.z, ref.z, atol=1e-12 * np.abs(ref.z).max())


@pytest.mark.parametrize("seed", range(3))
def test_exact_methods_on_very_ill_conditioned_spd(seed):
    """cond 1e12: certified, and forward error within cond * eps of the planted z."""
    lcp, z_star = planted_spd_lcp(60, 1e12, seed)
    for method in PIVOTING:
        sol = qpcontact.solve(lcp, method=method)
        assert sol.ok, (method, sol.message)
        assert np.max(np.abs(sol.z - z_star)) <= 1e12 * 1e-16 * 100 * np.max(z_star), method


# --- gaps far apart, touching contacts (the far-contact family) -------------------

@pytest.mark.parametrize("sparse", [False, True])
@pytest.mark.parametrize("seed", range(8))
def test_exact_methods_on_spread_gaps_and_degenerate_pairs(seed, sparse):
    """Planted gaps over 1e0..1e12 and touching unloaded contacts (z = w = 0):
    every exact method equals the planted solution component by component."""
    from qpcontact.testing import planted_ok, spread_lcp

    lcp, z, w = spread_lcp(seed, sparse=sparse)
    for method in ("bpp",) if sparse else PIVOTING:
        sol = qpcontact.solve(lcp, method=method)
        assert sol.ok and planted_ok(sol.z, sol.w, z, w, rtol=1e-9), (method, sol.message)


@pytest.mark.parametrize("seed", range(8))
def test_lemke_on_nonsymmetric_p_matrices_with_spread_gaps(seed):
    """M = SPD + skew (a P-matrix: z'Mz > 0), gaps over 1e0..1e12 and touching
    pairs, solution planted: Lemke equals it componentwise."""
    from qpcontact.testing import planted_ok, spread_lcp

    lcp, z, w = spread_lcp(seed, n=20)
    rng = np.random.default_rng(seed)
    K = rng.standard_normal((20, 20))
    M = lcp.M + 0.3 * (K - K.T)
    q = w - M @ z
    sol = qpcontact.solve(LCP(M, q), method="lemke")
    assert sol.ok and planted_ok(sol.z, sol.w, z, w, rtol=1e-9), sol.message


def test_enumeration_finds_what_lemke_misses_and_refuses_large_n():
    """A solvable 12 x 12 LCP (the testing module's friction kind, seed 1604)
    on which Lemke ends on a secondary ray with 31 covering vectors:
    "enumeration" returns a certified basic solution, one of those the tests'
    own enumeration lists; "auto" reaches it after Lemke.  Random small LCPs
    with a P-matrix (unique solution) agree with the reference; n = 17 is
    refused with the alternative named; an LCP without any solution is
    proved infeasible."""
    from qpcontact.testing.strategies import build_lcp

    p = build_lcp("friction", 12, 1604).problem
    # every covering vector and every rung of the regularised ladder end on
    # a ray, or on an ε-solution that does not solve M itself
    lemke = qpcontact.solve(p, "lemke")
    assert lemke.status == "ray" and not lemke.stats["proved_infeasible"], lemke.message
    sol = qpcontact.solve(p, "enumeration")
    assert sol.ok, sol.message
    assert any(np.allclose(sol.z, z, atol=1e-9) for z in enumerate_lcp(p.M, p.q))
    auto = qpcontact.solve(p, "auto")
    assert auto.ok and auto.method == "enumeration", auto.message
    rng = np.random.default_rng(3)
    for _ in range(5):
        A = rng.standard_normal((6, 6))
        M = A @ A.T + 6 * np.eye(6) + 0.5 * rng.standard_normal((6, 6))   # P-matrix-ish: PD sym part
        q = rng.standard_normal(6)
        ref = enumerate_lcp(M, q)
        assert len(ref) == 1
        np.testing.assert_allclose(qpcontact.solve(LCP(M, q), "enumeration").z, ref[0], atol=1e-10)
    with pytest.raises(qpcontact.InvalidProblemError, match="2\\^n.*lemke"):
        qpcontact.solve(LCP(np.eye(17), -np.ones(17)), "enumeration")
    # w = -z - 1 >= 0 has no z >= 0: enumeration exhausts its bases, and solve's
    # proof step turns that into a Farkas certificate checked from the data
    none = qpcontact.solve(LCP(np.array([[-1.0]]), np.array([-1.0])), "enumeration")
    assert not none.ok and none.status == "infeasible" and "exhausted" in none.message


def test_dense_lemke_stops_at_the_time_limit():
    """Fathi's family takes 2^n pivots; with the pivot cap lifted, the dense
    form stops at solve()'s time_limit (a frame's 3003-unknown LCP ran for
    12 minutes under its pivot cap alone)."""
    M, q = fathi_family(30)
    qpcontact.solve(LCP(M, q), "lemke", time_limit=0.05, max_pivots=10 ** 9)   # compile
    s, took = timed(qpcontact.solve, LCP(M, q), "lemke", time_limit=0.5, max_pivots=10 ** 9)
    assert kept(0.5, took), took
    assert s.status == "time_limit" and not s.ok, s.message
