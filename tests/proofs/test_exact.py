"""The exact checks in integers: every double read as an integer times a
power of two, products and sums exact, the deadline looked at between
blocks.  References are Python's Fractions, computed here."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
import scipy.sparse as sp

from qpcontact.proofs.exact import FarkasCheck, IntMatrix, RayCheck, ints, over_common_denominator


class _Expiring:
    """A deadline that expires after ``looks`` looks (a fake clock: no wall
    time is measured)."""

    def __init__(self, looks: int):
        self.looks = looks
        self.seen = 0

    def expired(self) -> bool:
        self.seen += 1
        return self.seen > self.looks


def _exact(v) -> Fraction:
    return Fraction(float(v))


def test_doubles_become_integers_times_one_power_of_two_exactly():
    rng = np.random.default_rng(1)
    for _ in range(20):
        v = rng.standard_normal(40) * 10.0 ** rng.integers(-300, 300, 40) * (rng.random(40) < 0.8)
        v[:3] = [5e-324, -1.7976931348623157e308, 3.0]      # subnormal, largest, an integer
        I, e = ints(v)
        assert all(Fraction(int(a)) * Fraction(2) ** e == _exact(x) for a, x in zip(I, v))


def test_sparse_products_match_fractions():
    rng = np.random.default_rng(2)
    for trial in range(10):
        M = sp.random(15, 25, density=0.4, random_state=trial, format="csr")
        M.data = rng.standard_normal(M.data.size) * 10.0 ** rng.integers(-30, 30, M.data.size)
        w = [Fraction(int(a), int(b)) for a, b in zip(rng.integers(-50, 50, 25),
                                                      rng.integers(1, 40, 25))]
        W, D = over_common_denominator(w)
        Mi = IntMatrix(M)
        got = Mi.times(W)
        dense = M.toarray()
        for i in range(15):
            ref = sum(_exact(dense[i, j]) * w[j] for j in range(25))
            assert ref == Fraction(int(got[i])) * Fraction(2) ** Mi.exp / D


def _lcp_check(M, q):
    n = q.size
    return FarkasCheck(sp.csr_matrix(-M), q, sp.csr_matrix((0, n)), np.zeros(0), np.zeros(n),
                       np.full(n, np.inf))


def test_a_farkas_vector_that_holds_only_to_rounding_is_refused():
    """M'y = 0 exactly for y = (1, 1, 1); one weight moved by one ulp makes a
    column of M'y positive by ~1e-16: a floating-point check passes it, the
    exact one must not."""
    M = np.array([[1.0, -2.0, 0.5], [-0.5, 1.0, -1.5], [-0.5, 1.0, 1.0]])
    q = np.array([-1.0, 0.25, -0.5])
    check = _lcp_check(M, q)
    proof = check.check([Fraction(1)] * 3)
    assert proof is not None and proof.kind == "infeasible"
    up = Fraction(np.nextafter(1.0, 2.0))
    y = [up, Fraction(1), Fraction(1)]
    assert sum(_exact(M[i, 0]) * y[i] for i in range(3)) > 0     # column 0 now positive
    assert check.check(y) is None


def test_the_exact_check_stops_at_its_deadline():
    """A check that cannot finish before the deadline proves nothing (a fake
    deadline, expiring after its first look, on a matrix of several blocks)."""
    n = 400          # 160 000 products: two blocks
    rng = np.random.default_rng(3)
    M = -np.abs(rng.standard_normal((n, n)))       # every column of M'1 negative
    q = -np.ones(n)
    check = _lcp_check(M, q)
    ones = [Fraction(1)] * n
    assert check.check(ones) is not None
    late = _Expiring(looks=1)
    assert check.check(ones, late) is None and late.seen >= 2


def test_a_ray_is_checked_exactly():
    """P d = 0, G d <= 0, q'd < 0 for d = (1, 1); (1, 1 + ulp) leaves P d
    nonzero."""
    P = sp.csr_matrix(np.array([[1.0, -1.0], [-1.0, 1.0]]))
    G = sp.csr_matrix(np.array([[-1.0, 0.0]]))
    q = np.array([-1.0, 0.0])
    ray = RayCheck(P, q, G, sp.csr_matrix((0, 2)), -np.ones(2), np.ones(2))
    assert ray.check([Fraction(1), Fraction(1)])
    assert not ray.check([Fraction(1), Fraction(np.nextafter(1.0, 2.0))])
    assert not ray.check([Fraction(1), Fraction(1)], _Expiring(looks=0))


@pytest.mark.parametrize("seed", range(4))
def test_the_integer_solve_is_exact(seed):
    """A x = b for integer A (entries of 1 to 60 bits, rows swapped by a zero
    leading pivot) and b, checked by substitution in Fractions; a singular A
    gives None."""
    from qpcontact.proofs.exact import solve_integer

    rng = np.random.default_rng(seed)
    n = 12
    A = np.empty((n, n), dtype=object)
    for i in range(n):
        for j in range(n):
            A[i, j] = int(rng.integers(-2 ** 20, 2 ** 20)) << int(rng.integers(0, 40))
    A[0, 0] = 0
    b = np.array([int(v) for v in rng.integers(-1000, 1000, n)], dtype=object)
    x = solve_integer(A, b)
    assert x is not None
    assert all(sum((Fraction(A[i, j]) * x[j] for j in range(n)), Fraction(0)) == b[i]
               for i in range(n))
    A[:, 3] = 2 * A[:, 5]
    assert solve_integer(A, b) is None
