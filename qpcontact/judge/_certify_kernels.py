"""Compiled loops of the certificate (numba).

The column influences c_j = max_i |M_ij| / σ_i of a sparse M are one pass over
its nonzeros; as NumPy calls (divide, then maximum.reduceat) they cost 4 ms on
a 3e5-nonzero chain, a tenth of a bpp solve; as one loop, a few hundred µs.
"""

from __future__ import annotations

import numpy as np
from ..core.compiled import njit


@njit
def csc_column_max_ratio(indptr: np.ndarray, indices: np.ndarray, data: np.ndarray,
                         sigma: np.ndarray) -> np.ndarray:
    """max_i |data_ij| / sigma_i per column of a CSC matrix (0/0 = 0, x/0 = inf)."""
    n = indptr.shape[0] - 1
    out = np.zeros(n)
    for j in range(n):
        best = 0.0
        for k in range(indptr[j], indptr[j + 1]):
            a = abs(data[k])
            if a == 0.0:
                continue
            s = sigma[indices[k]]
            r = a / s if s > 0.0 else np.inf
            if r > best:
                best = r
        out[j] = best
    return out



@njit
def blocks_2d(indptr: np.ndarray, indices: np.ndarray, data: np.ndarray):
    """A 2-D contact problem's W (CSR, 2 nc square) by its 2 × 2 blocks:
    (bptr, bcols, bdata (nb, 2, 2)), each block row's block columns sorted,
    the diagonal block always among them (zero where W has none), duplicates
    summed.  What scipy's BSR conversion gives, in one pass (it cost 0.6 ms
    on a 1 170-contact drum bed)."""
    nc = (indptr.shape[0] - 1) // 2
    mark = np.full(nc, -1, np.int64)
    slot = np.zeros(nc, np.int64)
    bptr = np.zeros(nc + 1, np.int64)
    for i in range(nc):
        mark[i] = i
        k = 1
        for row in (2 * i, 2 * i + 1):
            for p in range(indptr[row], indptr[row + 1]):
                cb = indices[p] // 2
                if mark[cb] != i:
                    mark[cb] = i
                    k += 1
        bptr[i + 1] = bptr[i] + k
    bcols = np.empty(bptr[nc], np.int64)
    bdata = np.zeros((bptr[nc], 2, 2))
    mark[:] = -1
    for i in range(nc):
        lo, k = bptr[i], 1
        mark[i] = i
        bcols[lo] = i
        for row in (2 * i, 2 * i + 1):
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
                bdata[slot[indices[p] // 2], a, indices[p] % 2] += data[p]
    return bptr, bcols, bdata


@njit
def jacobian_2d_csr(bptr: np.ndarray, bcols: np.ndarray, bdata: np.ndarray, jp: np.ndarray,
                    b: np.ndarray):
    """(indptr, indices, data) of J = I − blockdiag(jp) + blockdiag(b) W in CSR
    for 2-D contacts, W by its blocks (:func:`blocks_2d`), jp and b (nc, 2, 2):
    J's entries in the sparse products' order of summation, exact zeros left
    out as they leave them — the same J bit for bit at a fraction of their
    cost (scipy's per-operation overhead was most of it)."""
    nc = jp.shape[0]
    nb = bptr[nc]
    out_ptr = np.zeros(2 * nc + 1, np.int64)
    out_idx = np.empty(4 * nb, np.int64)
    out_val = np.empty(4 * nb)
    nnz = 0
    for i in range(nc):
        for a in range(2):
            for s in range(bptr[i], bptr[i + 1]):
                cb = bcols[s]
                for e in range(2):
                    v = b[i, a, 0] * bdata[s, 0, e] + b[i, a, 1] * bdata[s, 1, e]
                    if cb == i:      # (I − J_P) + B W
                        v = ((1.0 if a == e else 0.0) - jp[i, a, e]) + v
                    if v != 0.0:
                        out_idx[nnz] = 2 * cb + e
                        out_val[nnz] = v
                        nnz += 1
            out_ptr[2 * i + a + 1] = nnz
    return out_ptr, out_idx[:nnz], out_val[:nnz]
