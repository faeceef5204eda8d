"""The upper triangle of a principal block of a sparse matrix, in one
compiled pass (numba).

An exact method factorizes M_FF by QDLDL, which takes the block's upper
triangle in CSC.  SciPy made it in three passes — the triangle of the whole
M (through COO), then a column and a row selection — 1.1 ms on a 10⁴-node
membrane whose block's factorization is 1.5 ms.  Imported only by
:class:`qpcontact.core.linalg.ActiveBlock`, where it runs, so that importing
qpcontact does not load numba.
"""

from __future__ import annotations

import numpy as np
from .compiled import njit


@njit
def upper_block(indptr, indices, data, F, n):
    """(indptr, indices, data) in CSC of the upper triangle of M_FF, M in
    CSC (n columns, each column's rows sorted, no duplicates) and F its
    block's unknowns in increasing order: M[i, j] for i <= j both in F, at
    (position of i in F, position of j in F), in M's order within each
    column — the arrays (int32 indices: the caller
    keeps M's nonzeros below 2³¹) ``sp.triu(M, format="csc")[:, F][F, :]`` holds, stored
    zeros included."""
    pos = np.full(n, -1, np.int64)
    for c in range(F.size):
        pos[F[c]] = c
    ptr = np.zeros(F.size + 1, np.int32)
    for c in range(F.size):
        j = F[c]
        k = 0
        for p in range(indptr[j], indptr[j + 1]):
            i = indices[p]
            if i > j:
                break
            if pos[i] >= 0:
                k += 1
        ptr[c + 1] = ptr[c] + k
    idx = np.empty(ptr[F.size], np.int32)
    val = np.empty(ptr[F.size])
    for c in range(F.size):
        j = F[c]
        t = ptr[c]
        for p in range(indptr[j], indptr[j + 1]):
            i = indices[p]
            if i > j:
                break
            if pos[i] >= 0:
                idx[t] = pos[i]
                val[t] = data[p]
                t += 1
    return ptr, idx, val
