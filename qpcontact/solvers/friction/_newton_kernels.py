"""Compiled helper of nsgs-newton's square step (numba): the Newton system
restricted to the unknowns it does not fix by itself.

Imported only by the function that calls it, so that the registry does not
load numba.
"""

from __future__ import annotations

import numpy as np
from ...core.compiled import njit


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
