"""A 2-D contact problem's W by its 2 × 2 blocks, in one compiled pass (numba).

Imported only by FrictionProblem.W_blocks, where it runs, so that importing
qpcontact does not load numba.  (No other module's kernel calls into this
one: numba's on-disk cache keys a kernel by its own file, so a kernel
calling a helper of another file would keep a stale copy of it.)
"""

from __future__ import annotations

import numpy as np
from .compiled import njit


@njit
def blocks_2d(indptr: np.ndarray, indices: np.ndarray, data: np.ndarray):
    """W (CSR, 2 nc square) by its 2 × 2 blocks: (diagonal blocks (nc, 2, 2),
    and the others as bptr, bcols, bdata (nb, 2, 2)), each block row's block
    columns sorted, duplicates summed — what scipy's BSR conversion gives, in
    one pass (it and the diagonal's gathering cost 1 ms on a 1 170-contact
    drum bed)."""
    nc = (indptr.shape[0] - 1) // 2
    mark = np.full(nc, -1, np.int64)
    slot = np.zeros(nc, np.int64)
    bptr = np.zeros(nc + 1, np.int64)
    for i in range(nc):
        mark[i] = i
        k = 0
        for row in range(2 * i, 2 * i + 2):
            for p in range(indptr[row], indptr[row + 1]):
                cb = indices[p] // 2
                if mark[cb] != i:
                    mark[cb] = i
                    k += 1
        bptr[i + 1] = bptr[i] + k
    diag = np.zeros((nc, 2, 2))
    bcols = np.empty(bptr[nc], np.int64)
    bdata = np.zeros((bptr[nc], 2, 2))
    mark[:] = -1
    for i in range(nc):
        lo, k = bptr[i], 0
        mark[i] = i
        for row in range(2 * i, 2 * i + 2):
            for p in range(indptr[row], indptr[row + 1]):
                cb = indices[p] // 2
                if mark[cb] != i:
                    mark[cb] = i
                    bcols[lo + k] = cb
                    k += 1
        # a few dozen block columns at most: insertion sort
        for s in range(lo + 1, lo + k):
            c = bcols[s]
            t = s - 1
            while t >= lo and bcols[t] > c:
                bcols[t + 1] = bcols[t]
                t -= 1
            bcols[t + 1] = c
        for s in range(lo, lo + k):
            slot[bcols[s]] = s
        for a in range(2):
            row = 2 * i + a
            for p in range(indptr[row], indptr[row + 1]):
                cb = indices[p] // 2
                if cb == i:
                    diag[i, a, indices[p] % 2] += data[p]
                else:
                    bdata[slot[cb], a, indices[p] % 2] += data[p]
    return diag, bptr, bcols, bdata

