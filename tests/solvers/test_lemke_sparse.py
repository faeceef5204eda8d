"""Lemke's sparse revised form (qpcontact.solvers.pivoting.lemke_sparse): the same
pivots and answers as the dense form on the families the dense form is
tested on, and LCPs beyond the dense limit.

References from outside the code under test: solutions planted in the
random problems, the literature's pivot counts (Murty, Fathi), exact-rational
Lemke (tests/helpers/references.py), Siconos's LCP files, and "bpp"."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import qpcontact
from qpcontact import LCP
from qpcontact.io import read_siconos_lcp
from qpcontact.testing import planted_ok, spread_lcp

from tests.helpers.problems import seeded_spd_matrix, planted_spd_lcp
from tests.helpers.paths import siconos_files
from tests.helpers.references import exact_lemke_pivots, fathi_family, murty_family


@pytest.fixture
def sparse_form(monkeypatch):
    """Every sparse LCP goes to the sparse form, however small."""
    import importlib

    monkeypatch.setattr(importlib.import_module("qpcontact.solvers.pivoting.lemke"), "SPARSE_FROM", 0)


def _lemke(M, q):
    return qpcontact.solve(LCP(sp.csc_matrix(M), q), method="lemke")


# n = 11, 12 (2 048 and 4 096 pivots of Fathi's) are the slow end of the same path
@pytest.mark.parametrize("n", [*range(4, 11), *(pytest.param(n, marks=pytest.mark.slow) for n in (11, 12))])
def test_murty_and_fathi_pivot_counts(n, sparse_form):
    """The sparse form follows the same path: Murty's family in exact
    Lemke's pivot count, Fathi's in 2^n — whose ties the ratio test must see
    as ties (with basic-value scales of |x_i| alone it left the 2^n path
    from n = 8)."""
    M, q = murty_family(n)
    sol = _lemke(M, q)
    assert sol.ok and sol.iterations == exact_lemke_pivots(M, q)[1], sol.message
    np.testing.assert_allclose(sol.z, np.eye(n)[-1], atol=1e-12)
    M, q = fathi_family(n)
    sol = _lemke(M, q)
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.z, np.eye(n)[0], atol=1e-10)
    assert sol.iterations == 2 ** n


@pytest.mark.parametrize("n,cond,seed", [(n, c, s) for n, c in ((20, 10.0), (60, 1e4), (40, 1e8))
                                         for s in range(3)])
def test_random_spd_planted_solutions(n, cond, seed, sparse_form):
    lcp, z_star = planted_spd_lcp(n, cond, seed, sparse=True)
    sol = qpcontact.solve(lcp, method="lemke")
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.z, z_star, atol=1e-8 * max(1.0, cond * 1e-8))


@pytest.mark.parametrize("seed", range(4))
def test_degenerate_and_nonsymmetric_problems(seed, sparse_form):
    """z_i = w_i = 0 for a third of the indices with ties in q (no cycling),
    then the same solution planted in M + a skew part (nonsymmetric)."""
    rng = np.random.default_rng(seed)
    n = 24
    M = seeded_spd_matrix(n, 100.0, seed)
    kind = rng.integers(0, 3, n)
    z = np.where(kind == 0, 1.0, 0.0)
    w = np.where(kind == 1, 1.0, 0.0)
    sol = _lemke(M, w - M @ z)
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.z, z, atol=1e-10)
    K = rng.standard_normal((n, n))
    A = M + 0.3 * (K - K.T)
    sol = _lemke(A, w - A @ z)
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.z, z, atol=1e-10)


@pytest.mark.parametrize("seed", range(8))
def test_spread_gaps_and_touching_pairs(seed, sparse_form):
    """Gaps over 1e0..1e12 and touching unloaded pairs, planted: equal
    component by component (the far-contact family)."""
    lcp, z, w = spread_lcp(seed, sparse=True)
    sol = qpcontact.solve(lcp, method="lemke")
    assert sol.ok and planted_ok(sol.z, sol.w, z, w, rtol=1e-9), sol.message


@pytest.mark.parametrize("path", siconos_files(), ids=lambda p: p.name)
def test_siconos_lcps_end_as_in_the_dense_form(path, siconos_dir, sparse_form, monkeypatch):
    lcp = read_siconos_lcp(path)
    sparse = qpcontact.solve(LCP(sp.csc_matrix(lcp.M), lcp.q), method="lemke")
    monkeypatch.undo()
    dense = qpcontact.solve(LCP(np.asarray(lcp.M.toarray() if sp.issparse(lcp.M) else lcp.M),
                                lcp.q), method="lemke")
    assert sparse.status == dense.status, (sparse.message, dense.message)
    if dense.ok:
        assert sparse.ok and sparse.certificate.siconos_error < 1e-10, sparse.message


@pytest.mark.slow
def test_beyond_the_dense_limit():
    """An obstacle problem of 6000 unknowns (a sparse SPD stiffness): the
    dense tableau would need 290 MB; the sparse form solves it, equal to
    "bpp"'s answer."""
    n = 6000
    rng = np.random.default_rng(0)
    M = sp.diags([-np.ones(n - 1), 2.5 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csc")
    q = rng.standard_normal(n)
    sol = qpcontact.solve(LCP(M, q), method="lemke")
    ref = qpcontact.solve(LCP(M, q), method="bpp")
    assert sol.ok and ref.ok, sol.message
    np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-12 * np.abs(ref.z).max())


@pytest.mark.parametrize("block", [1, 2, 3, 7])
def test_blocked_tie_break_picks_as_the_whole_block(block, monkeypatch):
    """The lexicographic tie-break holds LEX_BLOCK tied rows of B⁻¹ at a time
    and carries the smallest: the same row as all rows at once, checked
    against the explicit inverse (rows of B⁻¹ / a_i compared by hand)."""
    import importlib

    mod = importlib.import_module("qpcontact.solvers.pivoting.lemke_sparse")
    rng = np.random.default_rng(block)
    n = 12
    M = sp.csc_matrix(seeded_spd_matrix(n, 10.0, block))
    columns = sp.hstack([sp.identity(n, format="csc"), -M], format="csc")
    basis = np.where(rng.random(n) < 0.5, np.arange(n) + n, np.arange(n))
    F = mod._ProductFormBasis(columns, basis)
    Binv = np.linalg.inv(columns[:, basis].toarray())
    for trial in range(20):
        ties = rng.choice(n, size=9, replace=False)
        a = rng.uniform(0.5, 2.0, n)
        rows = Binv[ties] / a[ties, None]
        expected = ties[sorted(range(ties.size), key=lambda k: tuple(rows[k]))[0]]
        monkeypatch.setattr(mod, "LEX_BLOCK", block)
        assert mod._lex_leaving(ties, a, F, None) == expected


def test_an_uncertified_sparse_answer_falls_back_to_the_dense_form(sparse_form, monkeypatch):
    """Where the sparse form's answer misses the tolerance (here: replaced by
    a wrong basis on purpose) and n <= DENSE_TABLEAU_LIMIT, the dense form
    runs too; the certified answer is returned, and the stats say so."""
    import importlib

    from qpcontact.solvers.pivoting.lemke_tableau import LemkeOutcome

    mod = importlib.import_module("qpcontact.solvers.pivoting.lemke")   # the driver's binding
    lcp, z_star = planted_spd_lcp(30, 100.0, 0, sparse=True)
    monkeypatch.setattr(mod, "sparse_lemke", lambda M, q, d, k, deadline=None: LemkeOutcome(
        "solved", np.ones(q.size), np.ones(q.size, bool), 7))
    sol = qpcontact.solve(lcp, method="lemke")
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.z, z_star, atol=1e-9)
    assert sol.stats["sparse_form"]["pivots"] == 7


@pytest.mark.parametrize("family", ["spread", "far_contact", "degenerate", "badly_scaled"])
def test_hard_families_forced_sparse_stay_certified(family, sparse_form):
    """qpcontact stress's hard LCP families at n = 100 with M stored sparse
    and the sparse form forced: every answer certified against the family's
    built-in solution (where the sparse form alone missed, the dense form
    decides)."""
    from qpcontact.commands.stress import build_case, judge

    for seed in range(10):
        case = build_case(family, 100, seed)
        case.problem = LCP(sp.csc_matrix(case.problem.M), case.problem.q)
        sol = qpcontact.solve(case.problem, method="lemke")
        category, reason = judge(case, sol)
        assert category in ("certified", "proved"), (seed, reason, sol.message)
