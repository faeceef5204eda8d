"""The row maxima the QP doubt test asks of every answer, read off the CSR
arrays; the reference is scipy's own abs(M).max(axis=1)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from qpcontact.proofs.lp import row_abs_max


def test_row_maxima_agree_with_scipy_on_random_and_duplicate_entries():
    rng = np.random.default_rng(0)
    for seed in range(100):
        A = sp.random(7, 5, density=rng.uniform(0.0, 1.0), random_state=seed, format="csr")
        A.data -= 0.5
        ref = np.asarray(abs(A).max(axis=1).toarray()).ravel() if A.nnz else np.zeros(7)
        np.testing.assert_array_equal(row_abs_max(A), ref)
    # duplicates are summed first (1 - 3 = -2 in row 0), as scipy does
    A = sp.csr_matrix((np.array([1.0, -3.0, 2.0]), np.array([0, 0, 1]), np.array([0, 2, 3])),
                      shape=(2, 2))
    np.testing.assert_array_equal(row_abs_max(A), [2.0, 2.0])
    assert row_abs_max(sp.csr_matrix((3, 4))).tolist() == [0.0, 0.0, 0.0]
