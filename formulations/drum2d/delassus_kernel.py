"""The step problem's W = Hᵀ M⁻¹ H + D in one compiled pass (numba).

H (3n x 2m, CSC) maps the contacts' local impulses to the discs' generalized
impulses, M⁻¹ is diagonal and D the springs' diagonal (stepper.py's module
docstring); W is formed column by column from H's few rows per column (at
most two discs, six rows): W_ab = Σ_r M⁻¹_r (H_ra H_rb) over their common
rows r in increasing order, so W_ab and W_ba are the same sum — W is
symmetric exactly, with no averaging.  scipy's three sparse products, the
symmetrization and the diagonal's addition cost 1.7 ms at 1 180 contacts;
this, a tenth.  The entries equal those to rounding.  Imported only by the
stepper's assembly, so that importing the drum does not load numba.
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.compiled import njit

__all__ = ["delassus"]


@njit
def delassus(indptr, indices, data, n_rows, minv, diag):
    """(indptr, indices, data) of W = Hᵀ diag(minv) H + diag(diag) in CSC,
    H given by its CSC arrays (n_rows rows); each column's rows sorted, exact
    zeros left out."""
    m = indptr.shape[0] - 1
    # H by rows: the columns that have an entry in each row, in column order
    row_ptr = np.zeros(n_rows + 1, np.int64)
    for p in range(indptr[m]):
        row_ptr[indices[p] + 1] += 1
    for r in range(n_rows):
        row_ptr[r + 1] += row_ptr[r]
    fill = row_ptr[:-1].copy()
    row_col = np.empty(indptr[m], np.int64)
    row_val = np.empty(indptr[m])
    for a in range(m):
        for p in range(indptr[a], indptr[a + 1]):
            r = indices[p]
            row_col[fill[r]] = a
            row_val[fill[r]] = data[p]
            fill[r] += 1
    slot = np.full(m, -1, np.int64)       # where column b's sum sits in this column's list
    cols = np.empty(m, np.int64)
    sums = np.empty(m)
    out_ptr = np.zeros(m + 1, np.int64)
    cap = 16 * m + 16
    out_idx = np.empty(cap, np.int64)
    out_val = np.empty(cap)
    nnz = 0
    for a in range(m):
        slot[a] = 0                       # the diagonal first
        cols[0] = a
        sums[0] = 0.0
        k = 1
        # rows of column a in increasing order: W_ab and W_ba sum the same terms in the same order
        for p in range(indptr[a], indptr[a + 1]):
            r = indices[p]
            for s in range(row_ptr[r], row_ptr[r + 1]):
                b = row_col[s]
                if slot[b] < 0:
                    slot[b], cols[k], sums[k] = k, b, 0.0
                    k += 1
                sums[slot[b]] += minv[r] * (data[p] * row_val[s])   # h_ra h_rb = h_rb h_ra exactly
        sums[0] += diag[a]
        for s in range(k):
            slot[cols[s]] = -1
        for s in range(1, k):        # a few dozen rows at most: insertion sort
            c, v = cols[s], sums[s]
            t = s - 1
            while t >= 0 and cols[t] > c:
                cols[t + 1], sums[t + 1] = cols[t], sums[t]
                t -= 1
            cols[t + 1], sums[t + 1] = c, v
        if nnz + k > cap:
            cap = 2 * (nnz + k)
            out_idx = _grow_int(out_idx, cap)
            out_val = _grow_float(out_val, cap)
        for s in range(k):
            if sums[s] != 0.0:
                out_idx[nnz] = cols[s]
                out_val[nnz] = sums[s]
                nnz += 1
        out_ptr[a + 1] = nnz
    return out_ptr, out_idx[:nnz], out_val[:nnz]


@njit
def _grow_int(x, n):
    y = np.empty(n, np.int64)
    y[:x.size] = x
    return y


@njit
def _grow_float(x, n):
    y = np.empty(n)
    y[:x.size] = x
    return y
