"""No "ok" beside a doubt: data within rounding of a problem with no solution
are proved infeasible (an exact Farkas vector or motion) or called "ill_posed";
never "solved".  Every reference here is built and checked in this file, in
rational arithmetic (fractions of the stored doubles) or by hand mechanics."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from qpcontact import LCP, FrictionProblem, solve
from qpcontact.judge.near_farkas import near_farkas
from qpcontact.proofs.candidates import cheap_lcp_farkas, one_row_farkas


def _fr(x) -> Fraction:
    return Fraction(float(x))


def _farkas_exact(M, q, y) -> bool:
    """y >= 0, Mᵀy <= 0, qᵀy < 0 in rationals (this file's own check)."""
    n = len(q)
    if any(v < 0 for v in y):
        return False
    cols = [sum((_fr(M[i, j]) * Fraction(y[i]) for i in range(n)), Fraction(0)) for j in range(n)]
    return all(c <= 0 for c in cols) and sum((_fr(q[i]) * Fraction(y[i]) for i in range(n)),
                                             Fraction(0)) < 0


def _floating_mechanism(n=24, null=13, seed=0, size=1e13):
    """M = B Bᵀ with 1ᵀB = 0 exactly (dyadic B), far contacts |q| ~ size,
    qᵀ1 = -1 exactly: infeasible, y = 1."""
    rng = np.random.default_rng(seed)
    B = np.round(rng.standard_normal((n, n - null)) * 2 ** 8) / 2 ** 8
    B[-1] = -B[:-1].sum(axis=0)
    M = B @ B.T
    M = np.triu(M) + np.triu(M, 1).T
    q = np.round(rng.standard_normal(n) * size)
    q[-1] = float(-1 - sum(_fr(v) for v in q[:-1]))
    assert _farkas_exact(M, q, [1] * n)           # the reference, in rationals
    assert np.linalg.matrix_rank(M) == n - null
    return M, q


@pytest.mark.parametrize("seed", range(3))
def test_all_ones_beside_far_contacts_is_checked_exactly(seed):
    M, q = _floating_mechanism(seed=seed)
    proof = cheap_lcp_farkas(M, q)
    assert proof is not None and proof.kind == "infeasible"
    y = proof.vector["exact"]["z"]
    assert _farkas_exact(M, q, y)


@pytest.mark.parametrize("method", ["auto", "lemke", "highs", "piqp"])
def test_far_contacts_without_solution_are_proved_infeasible(method):
    pytest.importorskip("qpsolvers")
    M, q = _floating_mechanism(seed=7)
    for accuracy in ("low", "high"):
        sol = solve(LCP(M, q), method, accuracy=accuracy, time_limit=20)
        assert not sol.ok
        assert sol.status == "infeasible" and sol.stats["proved_infeasible"], sol.message


def _one_row(seed, n=10):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n))
    M = A + np.diag(np.abs(A).sum(axis=1) + 1.0)
    q = rng.standard_normal(n)
    i = int(rng.integers(n))
    M[i] = -rng.uniform(0.1, 2.0, n)
    q[i] = -0.5
    y = [0] * n
    y[i] = 1
    assert _farkas_exact(M, q, y)
    return M, q, i


@pytest.mark.parametrize("seed", range(3))
def test_one_row_farkas_vector_turns_a_ray_into_a_proof(seed):
    M, q, i = _one_row(seed)
    proof = one_row_farkas(M, q)
    assert proof is not None and proof.vector["z"][i] == 1.0
    sol = solve(LCP(M, q), "lemke")
    assert sol.status == "infeasible" and sol.stats["proved_infeasible"]
    assert "within rounding" not in sol.message
    # the candidate must be able to fail: the row loses its sign
    M[i, (i + 1) % len(q)] = 0.25
    assert one_row_farkas(M, q) is None


def test_near_farkas_sees_a_mechanism_and_nothing_on_solvable_data():
    # M = [[1, -1], [-1, 1]]: null vector (1, 1); q'(1, 1) = 0 exactly (at the
    # edge: within rounding of no solution), then clearly positive (solvable)
    M = np.array([[1.0, -1.0], [-1.0, 1.0]])
    y = near_farkas(M, np.array([-1.0, 1.0]), np.array([True, True]), 1e-12)
    assert y is not None and np.allclose(y, [1.0, 1.0])
    assert near_farkas(M, np.array([-1.0, 2.0]), np.array([True, True]), 1e-12) is None
    # a nonsingular block has no left null vector
    assert near_farkas(np.eye(2), np.array([-1.0, -1.0]), np.array([True, True]), 1e-12) is None


def _block(rel, dim=2, mu=0.5, weight=10.0, angle=0.0):
    """A rigid block on the ground (M = 0: no stiffness), pushed along the
    ground by P = μW(1 + rel).  By hand: equilibrium needs |r_T| = P <= μ r_N
    = μW, so a solution exists iff P <= μW."""
    n = dim
    f = np.zeros(n)
    f[0] = -weight
    P = mu * weight * (1 + rel)
    if dim == 2:
        f[1] = P
    else:
        f[1], f[2] = P * np.cos(angle), P * np.sin(angle)
    prob = FrictionProblem.global_problem(np.zeros((n, n)), np.eye(n), f, np.zeros(n), [mu], dim)
    tangential = sum((_fr(v) ** 2 for v in f[1:]), Fraction(0))
    solvable = tangential <= (_fr(mu) * _fr(weight)) ** 2        # by hand, in rationals
    return prob, solvable


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("rel", [1e-14, 1e-12])
def test_block_within_rounding_beyond_the_friction_limit_is_not_ok(dim, rel):
    prob, solvable = _block(rel, dim)
    assert not solvable
    for accuracy in ("low", "default", "high"):
        sol = solve(prob, "auto", accuracy=accuracy, time_limit=20)
        # never "solved"; an honest miss of the tolerance is allowed
        assert not sol.ok and sol.status in ("infeasible", "ill_posed", "inaccurate"), sol.message
    if sol.status == "infeasible":
        d = sol.stats["proof"].vector["exact"]["d"]
        f = prob.global_data["f"]
        assert sum((_fr(fi) * di for fi, di in zip(f, d)), Fraction(0)) > 0


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("rel", [0.0, -1e-14, -1e-3])
def test_block_at_or_below_the_friction_limit_stays_solved(dim, rel):
    prob, solvable = _block(rel, dim)
    assert solvable
    # "low": at 1e-9 De Saxcé's fixed point stalls at 1.4e-9 just below the
    # limit (the method's reach, not the rule's; an honest "inaccurate")
    sol = solve(prob, "auto", accuracy="low", time_limit=20)
    assert sol.ok and sol.status == "solved", sol.message


def test_block_pushed_askew_beyond_the_limit_is_proved():
    prob, solvable = _block(1e-12, dim=3, angle=0.7)
    assert not solvable
    sol = solve(prob, "auto", accuracy="low", time_limit=20)
    assert not sol.ok and sol.status in ("infeasible", "ill_posed", "inaccurate"), sol.message
