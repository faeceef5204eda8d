"""Compiled helpers of nsgs-newton's square step (numba): the Newton system
restricted to the unknowns it does not fix by itself, and for a sparse 2-D
problem the whole system at an iterate (F, J, the fixed unknowns, the
order, the restriction) in one call.

Imported only by the function that calls it, so that the registry does not
load numba.
"""

from __future__ import annotations

import numpy as np
from ...core._cone_kernels import INSIDE, POLAR, SIDE, cone_region, project_cone_2d
from ...core.compiled import njit
from ...judge._certify_kernels import csr_transposed, jacobian_blocks_2d


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
def closed_system_2d(Wptr, Widx, Wval, q, mu, rho, r, slip_rtol, diag, bptr, bcols, bdata,
                     known, has_known):
    """The square step's system at r for a sparse 2-D problem (W in CSC,
    ``rho`` ρ per contact, W's 2 x 2 blocks ``diag``, ``bptr``, ``bcols``,
    ``bdata``) on the unknowns the step does not give by itself.  u = W r + q
    and |W||r| summed as scipy's CSC product sums them, the natural map
    F = r − proj_K(r − ρ û) (friction_problem's formulas) and J's blocks
    (_certify_kernels.jacobian_blocks_2d).  Where the projection opens a
    contact (J_P = 0) its rows of J are e_iᵀ: d = −F there.  Where it puts x
    on the cone's side, J_P = v vᵀ/(1 + μ²), v = (1, μ sign x_T), has rank
    one in 2-D, so J's tangential row less v_T times its normal row is
    e_Tᵀ − v_T e_Nᵀ: d_T = v_T d_N − (F_T − v_T F_N), and the contact keeps
    one unknown, d_N, and its normal row.  The others keep both.  The kept
    unknowns (full indices) in ``order``: the first LU's ``known`` order
    where ``has_known`` (those still kept), then the rest ascending.
    Returns (F, base, tie, order, indptr, indices, data, rhs): d = base
    outside ``order``, d[order] the restricted system's solution (CSC, rows
    ascending), then d_T += tie d_N on the contacts on the cone's side
    (``tie`` v_T there, 0 elsewhere)."""
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
    for c in range(n):
        u[c] = y[c] + q[c]
    jp, b, xs = jacobian_blocks_2d(u, r, q, terms, mu, rho, slip_rtol)
    F = r - project_cone_2d(xs.ravel(), mu)
    # each contact's region: POLAR opens it, on the cone's SIDE its unknowns are tied
    state = np.empty(nc, np.int64)
    tie = np.zeros(nc)
    base = np.zeros(n)
    for i in range(nc):
        xn, xt = xs[i, 0], xs[i, 1]
        state[i] = cone_region(xn, abs(xt), mu[i])
        if state[i] == POLAR:
            base[2 * i], base[2 * i + 1] = -F[2 * i], -F[2 * i + 1]
        elif state[i] == SIDE:
            tie[i] = mu[i] if xt > 0 else -mu[i]
            base[2 * i + 1] = -(F[2 * i + 1] - tie[i] * F[2 * i])
    kept = np.zeros(n, np.bool_)
    for i in range(nc):
        kept[2 * i] = state[i] != POLAR
        kept[2 * i + 1] = state[i] == INSIDE
    seen = np.zeros(n, np.bool_)
    order = np.empty(n, np.int64)
    k = 0
    if has_known:
        for c in known:
            if kept[c] and not seen[c]:
                order[k] = c
                seen[c] = True
                k += 1
    for c in range(n):
        if kept[c] and not seen[c]:
            order[k] = c
            k += 1
    order = order[:k]
    pos = np.full(n, -1, np.int64)
    for p in range(k):
        pos[order[p]] = p
    # the restricted rows in order (CSR), then transposed: rows ascending
    rptr = np.zeros(k + 1, np.int64)
    ridx = np.empty(2 * (bptr[nc] + nc) * 2 + 1, np.int64)
    rval = np.empty(ridx.shape[0])
    rhs = np.empty(k)
    count = np.zeros(k + 1, np.int64)
    nnz = 0
    w = np.empty((2, 2))
    for p in range(k):
        g = order[p]
        i, a = g // 2, g % 2
        acc = -F[g]
        nb = bptr[i + 1] - bptr[i]
        for s in range(-1, nb):
            if s < 0:
                j = i
                for e in range(2):
                    v = b[i, a, 0] * diag[i, 0, e] + b[i, a, 1] * diag[i, 1, e]
                    w[0, e] = ((1.0 if a == e else 0.0) - jp[i, a, e]) + v
            else:
                j = bcols[bptr[i] + s]
                for e in range(2):
                    w[0, e] = (b[i, a, 0] * bdata[bptr[i] + s, 0, e]
                               + b[i, a, 1] * bdata[bptr[i] + s, 1, e])
            sj = state[j]
            if sj == POLAR:
                acc -= w[0, 0] * base[2 * j] + w[0, 1] * base[2 * j + 1]
                continue
            if sj == SIDE:
                acc -= w[0, 1] * base[2 * j + 1]
                v = w[0, 0] + tie[j] * w[0, 1]
                if v != 0.0:
                    ridx[nnz] = pos[2 * j]
                    rval[nnz] = v
                    count[pos[2 * j] + 1] += 1
                    nnz += 1
                continue
            for e in range(2):
                if w[0, e] != 0.0:
                    ridx[nnz] = pos[2 * j + e]
                    rval[nnz] = w[0, e]
                    count[pos[2 * j + e] + 1] += 1
                    nnz += 1
        rhs[p] = acc
        rptr[p + 1] = nnz
    cptr, cidx, cval = csr_transposed(rptr, ridx, rval, count)
    return F, base, tie, order, cptr, cidx, cval, rhs
