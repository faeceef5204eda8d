"""MatrixStructure.is_positive_definite_exactly: "positive definite" said of
the stored doubles in exact arithmetic, which lets the proofs skip a search
for a Farkas vector that cannot exist.  The reference is independent: the
leading principal minors of the stored matrix as integers (Bareiss,
qpcontact.cases.rational_references), Sylvester's criterion."""

from __future__ import annotations

import numpy as np

from qpcontact.cases.rational_references import dyadic_integers, leading_minors_positive
from qpcontact.commands.stress import build_case
from qpcontact.core.matrices import MatrixStructure

from tests.helpers.problems import planted_spd_lcp


def _exactly_pd(M) -> bool:
    """Sylvester on the stored symmetric part (halves are exact: no rounding)."""
    M = np.asarray(M, float)
    S = 0.5 * M + 0.5 * M.T
    n = S.shape[0]
    ints, _ = dyadic_integers(S)
    return leading_minors_positive([ints[i * n:(i + 1) * n] for i in range(n)])


def _near_singular(n: int, smallest: float, seed: int) -> np.ndarray:
    """fl(Q diag(λ) Qᵀ), λ from 1 down to ``smallest``: PD, singular or
    indefinite once rounded, depending on the draw."""
    rng = np.random.default_rng(seed)
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    lam = np.geomspace(1.0, smallest, n)
    M = (Q * lam) @ Q.T
    return 0.5 * (M + M.T)


def test_it_is_never_said_of_a_matrix_that_is_not_exactly_definite():
    """Matrices within rounding of singular (rounded B Bᵀ with a null vector,
    the downward-rounded infeasible family, spectra down to 1e-18): whenever
    the property holds, the exact minors agree; and it does not hold on the
    rounded family that is exactly infeasible, although Cholesky in floating
    point may accept it."""
    said, checked = 0, 0
    for seed in range(6):
        for family in ("illposed_psd", "infeasible_rounded"):
            M = build_case(family, 8, seed).problem.M
            verdict = MatrixStructure(M).is_positive_definite_exactly
            if family == "infeasible_rounded":
                assert not verdict, seed
            if verdict:
                said += 1
                assert _exactly_pd(M), (family, seed)
            checked += 1
        for smallest in (1e-18, 1e-16, 1e-14, 1e-12):
            M = _near_singular(12, smallest, seed)
            if MatrixStructure(M).is_positive_definite_exactly:
                said += 1
                assert _exactly_pd(M), (smallest, seed)
            checked += 1
    assert checked == 36
    # draws where Cholesky in floating point accepts a matrix that is
    # exactly not positive definite: the plain test is fooled, this one not
    for seed in (28, 37):
        M = _near_singular(6, 1e-17, seed)
        structure = MatrixStructure(M)
        assert structure.is_positive_definite and not _exactly_pd(M), seed
        assert not structure.is_positive_definite_exactly, seed


def test_it_is_said_where_the_margin_is_clear():
    """Definite matrices of condition up to 1e8 (the cross-validation's,
    n = 300, and small ones checked by the minors): shown definite."""
    for seed, cond in enumerate((1e1, 1e4, 1e8)):
        lcp, _ = planted_spd_lcp(300, cond, seed)
        assert lcp.structure.is_positive_definite_exactly, cond
    for seed in range(4):
        M = _near_singular(10, 1e-6, seed)
        assert _exactly_pd(M)
        assert MatrixStructure(M).is_positive_definite_exactly, seed
    # and not of an indefinite or semidefinite one
    assert not MatrixStructure(np.array([[1.0, 2.0], [2.0, 1.0]])).is_positive_definite_exactly
    assert not MatrixStructure(np.ones((3, 3))).is_positive_definite_exactly
