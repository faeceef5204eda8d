"""Compiled helpers of nsgs-newton's square step (numba): the Newton system
restricted to the unknowns it does not fix by itself, and for a sparse 2-D
problem the whole system at an iterate (F, J, the fixed unknowns, the
order, the restriction) in one call.

Imported only by the function that calls it, so that the registry does not
load numba.
"""

from __future__ import annotations

import numpy as np
from ...core._cone_kernels import project_cone_2d
from ...core.compiled import njit
from ...judge._certify_kernels import natural_map_jacobian_2d


@njit
def restricted_system(indptr, indices, data, order, F, fixed):
    """J d = −F with the unknowns ``fixed`` (J's row there is e_iᵀ: d_i = −F_i)
    taken out: (indptr, indices, data) of J[order][:, order] in CSC, its row
    indices sorted, and its right-hand side −F[order] − J[order, fixed] d_fixed
    — ``order`` the other unknowns in the order wanted.  One pass over J (CSC)."""
    n = F.shape[0]
    k = order.shape[0]
    pos = np.full(n, -1, np.int64)
    for c in range(k):
        pos[order[c]] = c
    rhs = np.empty(k)
    for c in range(k):
        rhs[c] = -F[order[c]]
    for f in range(n):
        if fixed[f]:
            for p in range(indptr[f], indptr[f + 1]):
                row = pos[indices[p]]
                if row >= 0:
                    rhs[row] += data[p] * F[f]
    out_ptr = np.zeros(k + 1, np.int64)
    for c in range(k):
        col = order[c]
        m = 0
        for p in range(indptr[col], indptr[col + 1]):
            if pos[indices[p]] >= 0:
                m += 1
        out_ptr[c + 1] = out_ptr[c] + m
    out_idx = np.empty(out_ptr[k], np.int64)
    out_val = np.empty(out_ptr[k])
    for c in range(k):
        col = order[c]
        s = out_ptr[c]
        m = 0
        for p in range(indptr[col], indptr[col + 1]):
            row = pos[indices[p]]
            if row >= 0:
                # insertion into the column's sorted rows (a few dozen entries)
                t = s + m - 1
                while t >= s and out_idx[t] > row:
                    out_idx[t + 1] = out_idx[t]
                    out_val[t + 1] = out_val[t]
                    t -= 1
                out_idx[t + 1] = row
                out_val[t + 1] = data[p]
                m += 1
    return out_ptr, out_idx, out_val, rhs


@njit
def square_system_2d(Wptr, Widx, Wval, q, mu, rho, r, slip_rtol, diag, bptr, bcols, bdata,
                     known, has_known):
    """The square step's system at r for a sparse 2-D problem (W in CSC,
    ``rho`` ρ per contact, W's 2 x 2 blocks ``diag``, ``bptr``, ``bcols``,
    ``bdata``), as hybrid.py forms it through NumPy and scipy, bit for bit:
    u = W r + q and |W||r| summed as scipy's CSC product sums them, the
    natural map F = r − proj_K(r − ρ û) (friction_problem's formulas), J in
    CSC (natural_map_jacobian_2d), the unknowns J fixes by itself (a row
    with its one entry, 1, on the diagonal), the order (the first LU's
    ``known`` order where ``has_known``, then the unknowns it lacks) and the
    restricted system (:func:`restricted_system`).  Returns (F, J's indptr,
    indices, data, fixed, order, the restriction's indptr, indices, data,
    right-hand side)."""
    n = r.shape[0]
    nc = n // 2
    y = np.zeros(n)
    terms = np.zeros(n)
    for c in range(n):
        rc, ac = r[c], abs(r[c])
        for p in range(Wptr[c], Wptr[c + 1]):
            y[Widx[p]] += Wval[p] * rc
            terms[Widx[p]] += abs(Wval[p]) * ac
    u = np.empty(n)
    x = np.empty(n)
    for i in range(nc):
        u[2 * i] = y[2 * i] + q[2 * i]
        u[2 * i + 1] = y[2 * i + 1] + q[2 * i + 1]
        ut = u[2 * i + 1]
        x[2 * i] = r[2 * i] - rho[i] * (u[2 * i] + mu[i] * np.sqrt(ut * ut))
        x[2 * i + 1] = r[2 * i + 1] - rho[i] * ut
    F = r - project_cone_2d(x, mu)
    jptr, jidx, jval = natural_map_jacobian_2d(u, r, q, terms, mu, rho, slip_rtol, diag, bptr,
                                               bcols, bdata)
    count = np.zeros(n, np.int64)
    dvals = np.zeros(n)
    for c in range(n):
        for p in range(jptr[c], jptr[c + 1]):
            count[jidx[p]] += 1
            if jidx[p] == c:
                dvals[c] = jval[p]
    fixed = np.empty(n, np.bool_)
    for c in range(n):
        fixed[c] = count[c] == 1 and dvals[c] == 1.0
    seen = np.zeros(n, np.bool_)
    order = np.empty(n, np.int64)
    k = 0
    if has_known:
        for c in known:
            if not fixed[c]:
                order[k] = c
                seen[c] = True
                k += 1
    for c in range(n):
        if not fixed[c] and not seen[c]:
            order[k] = c
            k += 1
    order = order[:k]
    rptr, ridx, rval, rhs = restricted_system(jptr, jidx, jval, order, F, fixed)
    return F, jptr, jidx, jval, fixed, order, rptr, ridx, rval, rhs
