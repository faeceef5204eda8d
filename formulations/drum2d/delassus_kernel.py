"""The step problem's W = Hᵀ M⁻¹ H + D in one compiled pass (numba).

H (3n x 2m, CSC) maps the contacts' local impulses to the discs' generalized
impulses, M⁻¹ is diagonal and D the springs' diagonal (stepper.py's module
docstring).  Each column of H has its entries on at most two discs (rows
3d, 3d + 1, 3d + 2), so W_ab = Σ_r M⁻¹_r (H_ra H_rb) runs over the rows of
the discs a and b share, in increasing order: W_ab and W_ba are the same
sum — W is symmetric exactly, with no averaging.  Column a's rows b are its
two discs' lists of columns (each increasing) merged, so they come out in
order, with no sort (an insertion sort of each column's rows took a
quarter more: 0.76 against 0.55 ms a step of the 500-log bed, ~1 200
contacts, the same arrays).  scipy's three sparse products, the
symmetrization and the diagonal's addition cost 1.7 ms at 1 180 contacts.
The entries equal those to rounding.  Imported only by the stepper's
assembly, so that importing the drum does not load numba.
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.compiled import njit

__all__ = ["delassus"]


@njit
def delassus(indptr, indices, data, n_rows, minv, diag):
    """(indptr, indices, data) of W = Hᵀ diag(minv) H + diag(diag) in CSC,
    H given by its CSC arrays (n_rows rows, three a disc); each column's
    rows sorted and on at most two discs; exact zeros left out."""
    m = indptr.shape[0] - 1
    nd = (n_rows + 2) // 3
    # each disc's columns in increasing order, with the column's entries on
    # the disc's three rows (x, y, spin) and which of them are stored
    ptr = np.zeros(nd + 1, np.int64)
    for a in range(m):
        last = -1
        for p in range(indptr[a], indptr[a + 1]):
            d = indices[p] // 3
            if d != last:
                ptr[d + 1] += 1
                last = d
    for d in range(nd):
        ptr[d + 1] += ptr[d]
    col = np.empty(ptr[nd], np.int64)
    val = np.zeros((ptr[nd], 3))
    has = np.zeros((ptr[nd], 3), np.bool_)
    at = np.empty(2 * m, np.int64)          # where column a sits in its first and last disc's list
    fill = ptr[:-1].copy()
    for a in range(m):
        last = -1
        e = -1
        at[2 * a] = -1
        at[2 * a + 1] = -1
        for p in range(indptr[a], indptr[a + 1]):
            r = indices[p]
            d = r // 3
            if d != last:
                e = fill[d]
                fill[d] += 1
                col[e] = a
                if last < 0:
                    at[2 * a] = e
                at[2 * a + 1] = e
                last = d
            val[e, r - 3 * d] = data[p]
            has[e, r - 3 * d] = True
    out_ptr = np.zeros(m + 1, np.int64)
    cap = 16 * m + 16
    out_idx = np.empty(cap, np.int64)
    out_val = np.empty(cap)
    nnz = 0
    for a in range(m):
        e1, e2 = at[2 * a], at[2 * a + 1]
        if e1 < 0:                           # no entries: the diagonal alone
            if diag[a] != 0.0:
                out_idx[nnz] = a
                out_val[nnz] = 0.0 + diag[a]
                nnz += 1
            out_ptr[a + 1] = nnz
            continue
        d1 = indices[indptr[a]] // 3
        d2 = indices[indptr[a + 1] - 1] // 3
        p, pe = ptr[d1], ptr[d1 + 1]
        q, qe = ptr[d2], ptr[d2 + 1]
        if d2 == d1:
            q = qe
        if nnz + (pe - p) + (qe - q) > cap:
            cap = 2 * (nnz + (pe - p) + (qe - q))
            out_idx = _grow_int(out_idx, cap)
            out_val = _grow_float(out_val, cap)
        while p < pe or q < qe:
            s = 0.0
            if q >= qe or (p < pe and col[p] <= col[q]):
                b = col[p]
                for c in range(3):
                    if has[e1, c] and has[p, c]:
                        s += minv[3 * d1 + c] * (val[e1, c] * val[p, c])
                p += 1
                if q < qe and col[q] == b:
                    for c in range(3):
                        if has[e2, c] and has[q, c]:
                            s += minv[3 * d2 + c] * (val[e2, c] * val[q, c])
                    q += 1
            else:
                b = col[q]
                for c in range(3):
                    if has[e2, c] and has[q, c]:
                        s += minv[3 * d2 + c] * (val[e2, c] * val[q, c])
                q += 1
            if b == a:
                s += diag[a]
            if s != 0.0:
                out_idx[nnz] = b
                out_val[nnz] = s
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
