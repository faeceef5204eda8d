"""O(nnz) loops of the multilevel method ("mg-bpp"), compiled with numba.

Gauss–Seidel sweeps are sequential by nature (each row reads the values the
previous rows just wrote); as NumPy calls they would cost a Python loop per
row.  The Galerkin product R A P of a truncated hierarchy is rebuilt when the
contact set moves; one fused pass (a dense accumulator per coarse row) costs
a third of SciPy's two sparse products and their transposes, and as the set
moves only the coarse rows it touches are recomputed, in place on the
untruncated product's pattern (:func:`galerkin_values`, :func:`touched_rows`).
"""

from __future__ import annotations

import numpy as np
from ...core.compiled import njit


@njit
def projected_gauss_seidel(indptr, indices, data, diag, q, z, sweeps):
    """``sweeps`` projected Gauss–Seidel sweeps for LCP(M, q), alternating
    forward and backward (a symmetric smoother), in place:
    z_i <- max(0, z_i − (M z + q)_i / M_ii).  M in CSR (symmetric)."""
    n = z.size
    for s in range(sweeps):
        for k in range(n):
            i = k if s % 2 == 0 else n - 1 - k
            r = q[i]
            for p in range(indptr[i], indptr[i + 1]):
                r += data[p] * z[indices[p]]
            v = z[i] - r / diag[i]
            z[i] = v if v > 0.0 else 0.0


@njit
def gauss_seidel(indptr, indices, data, diag, b, x, free, forward):
    """One Gauss–Seidel sweep for A x = b on the rows where ``free`` (the
    others keep their value, zero for a truncated correction), in place."""
    n = x.size
    for k in range(n):
        i = k if forward else n - 1 - k
        if free[i]:
            r = b[i]
            for p in range(indptr[i], indptr[i + 1]):
                r -= data[p] * x[indices[p]]
            x[i] += r / diag[i]


@njit
def _galerkin_row(I, r_ptr, r_idx, r_val, a_ptr, a_idx, a_val, p_ptr, p_idx, p_val, keep,
                  acc, mark, cols):
    """Row I of R diag(keep) A diag(keep) P into the accumulator ``acc``: the
    columns it reaches, in the order first reached, go to ``cols`` (their
    count returned) and are marked I in ``mark``; acc holds their values."""
    m = 0
    for a in range(r_ptr[I], r_ptr[I + 1]):
        i = r_idx[a]
        if not keep[i]:
            continue
        wi = r_val[a]
        for b in range(a_ptr[i], a_ptr[i + 1]):
            k = a_idx[b]
            if not keep[k]:
                continue
            wik = wi * a_val[b]
            for c in range(p_ptr[k], p_ptr[k + 1]):
                J = p_idx[c]
                if mark[J] != I:
                    mark[J] = I
                    acc[J] = 0.0
                    cols[m] = J
                    m += 1
                acc[J] += wik * p_val[c]
    return m


@njit
def galerkin(r_ptr, r_idx, r_val, a_ptr, a_idx, a_val, p_ptr, p_idx, p_val, keep, nc):
    """C = R diag(keep) A diag(keep) P in CSR (R = P', all CSR), rows of C in
    order, columns unsorted.  ``keep`` truncates the fine level."""
    acc = np.zeros(nc)
    mark = np.full(nc, -1, dtype=np.int64)
    cols = np.empty(nc, dtype=np.int64)
    cap = max(16, 9 * nc)
    out_idx = np.empty(cap, dtype=np.int64)
    out_val = np.empty(cap)
    out_ptr = np.zeros(nc + 1, dtype=np.int64)
    nnz = 0
    for I in range(nc):
        m = _galerkin_row(I, r_ptr, r_idx, r_val, a_ptr, a_idx, a_val, p_ptr, p_idx, p_val,
                          keep, acc, mark, cols)
        if nnz + m > cap:
            cap = max(2 * cap, nnz + m)
            grown_idx = np.empty(cap, dtype=np.int64)
            grown_val = np.empty(cap)
            grown_idx[:nnz] = out_idx[:nnz]
            grown_val[:nnz] = out_val[:nnz]
            out_idx, out_val = grown_idx, grown_val
        for t in range(m):
            J = cols[t]
            out_idx[nnz] = J
            out_val[nnz] = acc[J]
            nnz += 1
        out_ptr[I + 1] = nnz
    return out_ptr, out_idx[:nnz].copy(), out_val[:nnz].copy()


@njit
def galerkin_values(r_ptr, r_idx, r_val, a_ptr, a_idx, a_val, p_ptr, p_idx, p_val, keep,
                    c_ptr, c_idx, c_val, rows):
    """The rows ``rows`` of C = R diag(keep) A diag(keep) P written into
    c_val, in place, on C's pattern (c_ptr, c_idx): the untruncated
    product's, which holds every truncated one (a truncated entry is stored
    as 0).  The same sums in the same order as :func:`galerkin`."""
    nc = c_ptr.size - 1
    acc = np.zeros(nc)
    mark = np.full(nc, -1, dtype=np.int64)
    cols = np.empty(nc, dtype=np.int64)
    for t in range(rows.size):
        I = rows[t]
        _galerkin_row(I, r_ptr, r_idx, r_val, a_ptr, a_idx, a_val, p_ptr, p_idx, p_val, keep,
                      acc, mark, cols)
        for c in range(c_ptr[I], c_ptr[I + 1]):
            J = c_idx[c]
            c_val[c] = acc[J] if mark[J] == I else 0.0


@njit
def touched_rows(b_ptr, b_idx, p_ptr, p_idx, changed, nc):
    """The rows of R diag(keep) B diag(keep) P (R = P') that move when B's
    rows and columns, or ``keep``, change at the fine unknowns ``changed``
    (bool), B's pattern fixed: C_IJ = sum R_Ii keep_i B_ik keep_k P_kJ moves
    only if i or k changed, so i is a changed unknown or a neighbour of one
    in B's pattern and I a coarse function P spreads over i (C is symmetric:
    a moved column J is a moved row J, the same set)."""
    n = changed.size
    near = changed.copy()
    for i in range(n):
        if changed[i]:
            for p in range(b_ptr[i], b_ptr[i + 1]):
                near[b_idx[p]] = True
    out = np.zeros(nc, dtype=np.bool_)
    for i in range(n):
        if near[i]:
            for p in range(p_ptr[i], p_ptr[i + 1]):
                out[p_idx[p]] = True
    return out


@njit
def aggregate(indptr, indices, data, diag, theta):
    """Greedy aggregation on the strength graph |a_ij| >= theta sqrt(a_ii a_jj)
    (Vaněk, Mandel, Brezina): pass 1 makes a node whose strong neighbours are
    all free the root of a new aggregate with them; pass 2 joins every node
    left to the aggregate of a strong neighbour; pass 3 makes aggregates of
    what remains (isolated nodes).  Returns (aggregate of each node, count)."""
    n = diag.size
    agg = np.full(n, -1, dtype=np.int64)
    count = 0
    for i in range(n):
        if agg[i] >= 0:
            continue
        free = True
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if j != i and abs(data[p]) >= theta * np.sqrt(abs(diag[i] * diag[j])) and agg[j] >= 0:
                free = False
                break
        if not free:
            continue
        agg[i] = count
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if j != i and abs(data[p]) >= theta * np.sqrt(abs(diag[i] * diag[j])):
                agg[j] = count
        count += 1
    joined = agg.copy()
    for i in range(n):
        if agg[i] >= 0:
            continue
        best, best_w = -1, 0.0
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            w = abs(data[p]) / np.sqrt(abs(diag[i] * diag[j]))
            if j != i and agg[j] >= 0 and w >= theta and w > best_w:
                best, best_w = agg[j], w
        joined[i] = best
    for i in range(n):
        if joined[i] < 0:
            joined[i] = count
            count += 1
    return joined, count
