"""The edge families (qpcontact.cases.rounded): their references re-checked
here in this file's own rational arithmetic, never by the engine."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from qpcontact.cases.rounded import build_rounded


def _fr(x) -> Fraction:
    return Fraction(float(x))


def _row_dot(M, i, z) -> Fraction:
    return sum((_fr(M[i, j]) * z[j] for j in range(len(z)) if z[j]), Fraction(0))


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("family", ["farkas_far_contacts", "farkas_one_row"])
def test_farkas_witness_holds_exactly(family, seed):
    case = build_rounded(family, 20, seed)
    assert case.status == "infeasible"
    M, q, y = case.problem.M, case.problem.q, case.witness
    n = q.size
    assert np.all(y >= 0)
    assert all(sum((_fr(M[i, j]) * _fr(y[i]) for i in range(n)), Fraction(0)) <= 0
               for j in range(n))
    assert sum((_fr(a) * _fr(b) for a, b in zip(q, y)), Fraction(0)) < 0
    if family == "farkas_far_contacts":
        assert np.abs(q).max() > 1e13                        # far contacts
        assert n - np.linalg.matrix_rank(M) >= 12            # a wide null space
    else:
        i = int(np.flatnonzero(y)[0])
        assert M[i].max() <= -0.1 and q[i] <= -0.1           # a margin


@pytest.mark.parametrize("seed", range(2))
@pytest.mark.parametrize("family", ["conditioned_spd", "near_singular_pd"])
def test_planted_reference_solves_the_stored_data_exactly(family, seed):
    case = build_rounded(family, 8, seed)
    assert case.status == "solved" and case.unique_z
    M, q = case.problem.M, case.problem.q
    n = q.size
    F = [i for i in range(n) if case.z[i] > 0]
    # z_F solves M_FF z_F = -q_F exactly (Gauss-Jordan on rationals, here)
    A = [[_fr(M[i, j]) for j in F] + [-_fr(q[i])] for i in F]
    k = len(F)
    for c in range(k):
        p = next(r for r in range(c, k) if A[r][c] != 0)
        A[c], A[p] = A[p], A[c]
        for r in range(k):
            if r != c and A[r][c] != 0:
                t = A[r][c] / A[c][c]
                A[r] = [a - t * b for a, b in zip(A[r], A[c])]
    zF = [A[r][k] / A[r][r] for r in range(k)]
    assert all(v > 0 for v in zF)
    assert np.allclose([float(v) for v in zF], case.z[F], rtol=1e-15, atol=0)
    z = [Fraction(0)] * n
    for i, v in zip(F, zF):
        z[i] = v
    for i in set(range(n)) - set(F):
        assert _fr(q[i]) + _row_dot(M, i, z) >= 0
    cond = np.linalg.cond(M)
    assert cond > 1e6, cond                                   # ill-conditioned on purpose
