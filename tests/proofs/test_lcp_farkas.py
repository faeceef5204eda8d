"""Proofs that an LCP has no solution, on data with a planted Farkas vector
(tests/helpers/no_solution.py), each proof checked here in Fractions; and
no proof on data with a solution."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
import pytest

import qpcontact
from qpcontact import LCP
from qpcontact.core.deadline import Deadline
from qpcontact.proofs.lcp_farkas import prove_lcp_infeasible, sign_farkas
from qpcontact.cases.rounded import build_rounded
from tests.helpers.no_solution import KINDS, farkas_lcp


def _holds_exactly(M, q, y) -> bool:
    """y >= 0, M'y <= 0 and q'y < 0 in Fractions."""
    M = M.toarray() if hasattr(M, "toarray") else np.asarray(M)
    y = [Fraction(v) for v in y]
    n = len(y)
    if any(v < 0 for v in y):
        return False
    cols = [sum(Fraction(float(M[i, j])) * y[i] for i in range(n) if y[i]) for j in range(n)]
    return all(c <= 0 for c in cols) and sum(Fraction(float(q[i])) * y[i] for i in range(n)) < 0


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("n, seed", [(30, 0), (60, 1)])
def test_planted_infeasible_lcps_are_proved_by_the_quick_routes(kind, n, seed):
    lcp, _ = farkas_lcp(n, seed, kind)
    proof = prove_lcp_infeasible(lcp, 20.0, quick=True)
    assert proof is not None and proof.kind == "infeasible"
    assert _holds_exactly(lcp.M, lcp.q, proof.vector["exact"]["z"])


def test_a_row_of_nonpositive_signs_is_its_own_proof():
    M = np.array([[2.0, 1.0, -1.0], [-1.0, 0.0, -3.0], [1.0, 1.0, 1.0]])
    q = np.array([-1.0, -0.5, 2.0])
    proof = sign_farkas(M, q)
    assert proof is not None and list(proof.vector["z"]) == [0.0, 1.0, 0.0]
    assert _holds_exactly(M, q, proof.vector["exact"]["z"])
    assert sign_farkas(M, np.array([-1.0, 0.5, 2.0])) is None      # q_1 >= 0: no such row


def test_the_all_ones_vector_is_tried():
    """Columns of M summing to <= 0 with sum(q) < 0 and no row of
    nonpositive signs: y = 1."""
    M = np.array([[1.0, -2.0, 1.0], [-2.0, 1.0, 1.0], [1.0, 1.0, -3.0]])
    q = np.array([1.0, -2.0, 0.5])
    assert sign_farkas(M, q) is None
    proof = prove_lcp_infeasible(LCP(M, q), 20.0, quick=True)
    assert proof is not None and _holds_exactly(M, q, proof.vector["exact"]["z"])


@pytest.mark.parametrize("seed", range(3))
def test_solvable_lcps_get_no_proof(seed):
    """A planted solution z >= 0, w = Mz + q >= 0: no Farkas vector exists,
    whatever the LPs return (a symmetric PSD singular M and a general M)."""
    rng = np.random.default_rng(seed)
    n = 40
    B = rng.integers(-3, 4, (n, n // 2)).astype(float)
    for M in (B @ B.T, rng.standard_normal((n, n))):
        z = np.where(rng.random(n) < 0.5, rng.uniform(0.1, 2.0, n), 0.0)
        w = np.where(z > 0, 0.0, rng.uniform(0.1, 2.0, n))
        assert prove_lcp_infeasible(LCP(M, w - M @ z), 20.0) is None


def test_no_proof_is_sought_past_the_deadline():
    lcp, _ = farkas_lcp(60, 0, "general")
    assert prove_lcp_infeasible(lcp, Deadline(end=0.0)) is None


@pytest.mark.parametrize("n, seeds", [(8, range(12)), (30, range(6))])
def test_a_rounded_mechanism_on_the_indefinite_side_is_proved(n, seeds):
    """M = fl(B Bᵀ) with Bᵀd = 0, d > 0, q'd < 0, whose stored doubles have
    a tiny negative eigenvalue along d (the cases' reference: y = -M⁻¹1 >= 0
    with q'y < 0, found by their own exact solve): no LP vertex or snapped
    vector lands in the thin cone of Farkas vectors; the quick routes must
    still prove it, and the proof must hold in Fractions."""
    seen = 0
    for seed in seeds:
        case = build_rounded("illposed_psd", n, seed)
        if "-M⁻¹1" not in case.reference:
            continue
        seen += 1
        proof = prove_lcp_infeasible(case.problem, 20.0, quick=True)
        assert proof is not None, seed
        assert _holds_exactly(case.problem.M, case.problem.q, proof.vector["exact"]["z"]), seed
    assert seen >= 2


def test_the_rounded_mechanisms_inverse_comes_before_the_costly_candidates(monkeypatch):
    """Its proof costs one exact solve (0.05 s at n = 30); the hints' snapping
    and the null-space search before it cost 0.35 s and 0.1 s, and a 2 s call
    at a machine's load of 3 ran out on them.  With those routes made to
    fail loudly, the quick proof search and the proof that follows a
    method's ray (Lemke's, whose own LP vector fails exactly) still prove
    the data."""
    from qpcontact.dispatch import lcp_qp_run
    from qpcontact.proofs import lcp_farkas

    def costly(*args, **kwargs):
        raise AssertionError("a costlier route ran before the exact inverse")

    cases = list(itertools.islice((case for case in (build_rounded("illposed_psd", 30, seed)
                                                      for seed in range(200, 212))
                                   if "-M⁻¹1" in case.reference), 3))
    assert len(cases) == 3
    with monkeypatch.context() as mp:
        mp.setattr(lcp_farkas, "check_farkas_hint", costly)
        mp.setattr(lcp_farkas, "_null_space_farkas", costly)
        for case in cases:
            proof = prove_lcp_infeasible(case.problem, 20.0, quick=True)
            assert proof is not None and _holds_exactly(case.problem.M, case.problem.q,
                                                        proof.vector["exact"]["z"])
    monkeypatch.setattr(lcp_qp_run, "cheap_lcp_farkas", costly)
    for case in cases:
        sol = qpcontact.solve(case.problem, "lemke", time_limit=20.0)
        assert sol.status == "infeasible" and sol.stats["proved_infeasible"], sol.message
