"""The edge families (qpcontact.cases.rounded): their references re-checked
here in this file's own rational arithmetic, never by the engine."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from qpcontact.cases.rounded import build_rounded

from tests.helpers.references import exact_basic_solution


def _fr(x) -> Fraction:
    return Fraction(float(x))


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
    # z_F = -M_FF^-1 q_F in rationals, w >= 0 checked there (tests.helpers)
    z, _ = exact_basic_solution(M, q, case.z > 0)
    assert np.all(z[case.z > 0] > 0)
    assert np.allclose(z, case.z, rtol=1e-15, atol=0)
    cond = np.linalg.cond(M)
    assert cond > 1e6, cond                                   # ill-conditioned on purpose
