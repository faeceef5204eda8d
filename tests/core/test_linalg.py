"""The upper triangle of a principal block, gathered in one pass, against
SciPy's three (the triangle of M, then the columns and rows of F)."""

import numpy as np
import pytest
import scipy.sparse as sp

from qpcontact.core.linalg import upper_block


def _matrices():
    rng = np.random.default_rng(7)
    for n in (1, 2, 9, 60):
        A = sp.random(n, n, density=0.3, random_state=rng, format="csc")
        A = sp.csc_matrix(A + A.T + n * sp.identity(n))
        A.data[::4] = 0.0                   # stored zeros stay stored
        yield A
        yield sp.csr_matrix(A)
        B = A.copy()                        # each column's rows reversed: not sorted
        for j in range(n):
            a, b = B.indptr[j], B.indptr[j + 1]
            B.indices[a:b], B.data[a:b] = B.indices[a:b][::-1].copy(), B.data[a:b][::-1].copy()
        B.has_sorted_indices = False
        yield B


@pytest.mark.parametrize("k", range(12))
def test_the_upper_block_is_scipys_triangle_of_the_block(k):
    M = list(_matrices())[k]
    n = M.shape[0]
    rng = np.random.default_rng(k)
    for F in (np.arange(n), np.flatnonzero(rng.random(n) < 0.5), np.arange(0)):
        expected = sp.triu(M, format="csc")[:, F][F, :].tocsc()
        got = upper_block(M, F)
        assert got.format == "csc" and got.shape == (F.size, F.size)
        np.testing.assert_array_equal(got.indptr, expected.indptr)
        np.testing.assert_array_equal(got.indices, expected.indices)
        np.testing.assert_array_equal(got.data, expected.data)


def test_a_permuted_block_is_taken_as_scipy_takes_it():
    """Unknowns not in increasing order: SciPy's selections, in that order."""
    M = list(_matrices())[9]
    F = np.array([5, 1, 30, 2])
    expected = sp.triu(M, format="csc")[:, F][F, :].toarray()
    np.testing.assert_array_equal(upper_block(M, F).toarray(), expected)
