"""A plane frame's assembly loops, compiled (numba): the members' local
stiffness and rotation, and K's CSR from the members' triplets.

Imported only by :func:`.plane_element.plane_kernels`, where it runs, so
that importing the frames does not load numba.  Each kernel does the
arithmetic of the NumPy expressions it replaces operation by operation, in
their order (the same bits), and nothing that NumPy computes by its own
vectorized library (``hypot``, ``power``), which the callers pass in.  (No
kernel calls into another module: numba's on-disk cache keys a kernel by its
own file.)
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.compiled import njit


@njit
def member_arrays(ii, jj, E, A, I, Lf, phi, c, s, first_order):
    """(k (m, 6, 6), T (m, 6, 6), dofs (m, 6)): each member's stiffness in
    its axes as :func:`.plane_element.beam_k` (Euler-Bernoulli, Timoshenko
    for phi > 0; left zero where ``first_order`` is False: the second-order
    stiffness is NumPy's), its rotation as :func:`.plane_element.rotation`
    and its dofs (u, v, θ at node ii, then at jj)."""
    m = ii.shape[0]
    k = np.zeros((m, 6, 6))
    T = np.zeros((m, 6, 6))
    dofs = np.empty((m, 6), np.int64)
    for e in range(m):
        if first_order:
            L = Lf[e]
            f = E[e] * I[e] / (L * (1.0 + phi[e]))
            a = E[e] * A[e] / L
            vv = 12.0 * f / (L * L)
            vt = 6.0 * f / L
            tt = (4.0 + phi[e]) * f
            tc = (2.0 - phi[e]) * f
            k[e, 0, 0] = k[e, 3, 3] = a
            k[e, 0, 3] = k[e, 3, 0] = -a
            k[e, 1, 1] = k[e, 4, 4] = vv
            k[e, 1, 4] = k[e, 4, 1] = -vv
            k[e, 1, 2] = k[e, 2, 1] = k[e, 1, 5] = k[e, 5, 1] = vt
            k[e, 2, 4] = k[e, 4, 2] = k[e, 4, 5] = k[e, 5, 4] = -vt
            k[e, 2, 2] = k[e, 5, 5] = tt
            k[e, 2, 5] = k[e, 5, 2] = tc
        for o in (0, 3):
            T[e, o, o] = T[e, o + 1, o + 1] = c[e]
            T[e, o, o + 1] = s[e]
            T[e, o + 1, o] = -s[e]
            T[e, o + 2, o + 2] = 1.0
        for d in range(3):
            dofs[e, d] = 3 * ii[e] + d
            dofs[e, 3 + d] = 3 * jj[e] + d
    return k, T, dofs


@njit
def _less(keys, i, j):
    return keys[i] < keys[j]


@njit
def _swap(keys, vals, i, j):
    keys[i], keys[j] = keys[j], keys[i]
    vals[i], vals[j] = vals[j], vals[i]


@njit
def _linear_insert(keys, vals, last):
    kv, vv = keys[last], vals[last]
    nxt = last - 1
    while kv < keys[nxt]:
        keys[last], vals[last] = keys[nxt], vals[nxt]
        last = nxt
        nxt -= 1
    keys[last], vals[last] = kv, vv


@njit
def _insertion_sort(keys, vals, first, last):
    if first == last:
        return
    for i in range(first + 1, last):
        if keys[i] < keys[first]:
            kv, vv = keys[i], vals[i]
            for q in range(i, first, -1):
                keys[q], vals[q] = keys[q - 1], vals[q - 1]
            keys[first], vals[first] = kv, vv
        else:
            _linear_insert(keys, vals, i)


@njit
def _introsort_loop(keys, vals, depth):
    """libstdc++'s std::sort above 16 elements: median-of-three pivot to
    the front, unguarded Hoare partition, each part on with the depth
    limit less one (its recursion as a stack of ranges: the parts are
    disjoint, so the order they are done in changes nothing; numba's
    cache does not load recursive kernels).  False where the depth limit
    would hand over to heapsort (not copied)."""
    stack = [(0, keys.shape[0], depth)]
    while stack:
        first, last, depth = stack.pop()
        while last - first > 16:
            if depth == 0:
                return False
            depth -= 1
            mid = first + (last - first) // 2
            a, b, c = first + 1, mid, last - 1
            if _less(keys, a, b):
                if _less(keys, b, c):
                    _swap(keys, vals, first, b)
                elif _less(keys, a, c):
                    _swap(keys, vals, first, c)
                else:
                    _swap(keys, vals, first, a)
            elif _less(keys, a, c):
                _swap(keys, vals, first, a)
            elif _less(keys, b, c):
                _swap(keys, vals, first, c)
            else:
                _swap(keys, vals, first, b)
            lo, hi = first + 1, last
            while True:
                while keys[lo] < keys[first]:
                    lo += 1
                hi -= 1
                while keys[first] < keys[hi]:
                    hi -= 1
                if not lo < hi:
                    break
                _swap(keys, vals, lo, hi)
                lo += 1
            stack.append((lo, last, depth))
            last = lo
    return True


@njit
def _std_sort(keys, vals):
    """keys (with vals alongside) sorted as libstdc++'s std::sort sorts
    them — the order in which scipy's CSR conversion leaves equal columns,
    so that their sums come out in its order; False where its heapsort
    fallback would be reached."""
    n = keys.shape[0]
    if n == 0:
        return True
    lg = 0
    while (n >> (lg + 1)) > 0:
        lg += 1
    if not _introsort_loop(keys, vals, 2 * lg):
        return False
    if n > 16:
        _insertion_sort(keys, vals, 0, 16)
        for i in range(16, n):
            _linear_insert(keys, vals, i)
    else:
        _insertion_sort(keys, vals, 0, n)
    return True


@njit
def csr_of_blocks(dofs, kg, N, extra_rows, extra_vals):
    """(ok, data, indices, indptr): K (N x N) as CSR arrays from the
    members' 6 x 6 blocks ``kg`` at ``dofs`` and diagonal terms (springs)
    after them, as scipy's COO to CSR conversion makes it from these
    triplets: each row's entries in the triplets' order, sorted by column
    with libstdc++'s std::sort (where any row is out of order), equal
    columns summed in the order the sort left them, from the first; exact
    zeros kept.  ok False (a row deep enough for the sort's heapsort
    fallback): the caller converts the triplets with scipy."""
    m = dofs.shape[0]
    count = np.zeros(N + 1, np.int64)
    for e in range(m):
        for a in range(6):
            count[dofs[e, a] + 1] += 6
    for r in extra_rows:
        count[r + 1] += 1
    start = np.cumsum(count)
    fill = start[:-1].copy()
    col = np.empty(start[-1], np.int64)
    val = np.empty(start[-1])
    for e in range(m):
        for a in range(6):
            r = dofs[e, a]
            for b in range(6):
                col[fill[r]] = dofs[e, b]
                val[fill[r]] = kg[e, a, b]
                fill[r] += 1
    for q in range(extra_rows.shape[0]):
        r = extra_rows[q]
        col[fill[r]] = r
        val[fill[r]] = extra_vals[q]
        fill[r] += 1
    # scipy sorts every row, or none where all are in order already
    ordered = True
    for r in range(N):
        for p in range(start[r], start[r + 1] - 1):
            if col[p] > col[p + 1]:
                ordered = False
    indptr = np.zeros(N + 1, np.int64)
    indices = np.empty(start[-1], np.int64)
    data = np.empty(start[-1])
    nnz = 0
    for r in range(N):
        lo, hi = start[r], start[r + 1]
        if not ordered and not _std_sort(col[lo:hi], val[lo:hi]):
            return False, data, indices, indptr
        p = lo
        while p < hi:
            j = col[p]
            x = val[p]
            p += 1
            while p < hi and col[p] == j:
                x += val[p]
                p += 1
            indices[nnz] = j
            data[nnz] = x
            nnz += 1
        indptr[r + 1] = nnz
    return True, data[:nnz], indices[:nnz], indptr
