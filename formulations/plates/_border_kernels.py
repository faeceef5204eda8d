"""Compiled forward solves with sparse right-hand sides on an LDLᵀ factor
(numba), for :mod:`.border`.

With A = P (I + L) D (I + L)' P' (any LDLᵀ: L strictly lower, in
CSC; a unit diagonal stored with it, as SuperLU's ``L`` has, is passed
over, so that L is read without a copy), the entry L_ij is nonzero only where i is an ancestor of j in the
elimination tree (parent(j) = the least row of column j of L's full
pattern; :func:`parents` reads it from the entries stored).  So (I + L)⁻¹ b
for a b with few nonzeros is nonzero only on their paths to the root, the
reach (Gilbert and Peierls), and the border's k right-hand sides are
solved together on the union of their reaches, in increasing order, as a
dense block whose rows are the union's: the top of the tree, which every
path crosses, is most of the work — on a 115 x 115 floor raft's factor a
path holds 1 238 of 33 188 columns and 1/7 of L's entries.  Run one
column at a time, the same solves took twice as long.
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.compiled import njit


@njit
def parents(Rp, Ri, n):
    """The elimination tree of L, −1 for a root, by Liu's algorithm from
    the rows of L (CSR; entries on or above the diagonal passed over) — or
    of the factorised matrix itself (symmetric, its CSC read as rows: the
    tree of A is the tree of L's full pattern, and needs no transpose of
    L) — rather than as the least row of each column: a factor may leave
    out an entry that cancelled to exactly zero (SciPy's ``SuperLU.L``
    does), and the least stored row is then a wrong parent, with rows of a
    column off its path to the root, which :func:`forward_block` needs on
    it.  Every stored entry of L is on a path in this tree; with L's full
    pattern it is the least-row tree."""
    parent = np.full(n, -1, np.int64)
    ancestor = np.full(n, -1, np.int64)
    for i in range(n):
        for t in range(Rp[i], Rp[i + 1]):
            k = Ri[t]
            while k != -1 and k < i:
                up = ancestor[k]
                ancestor[k] = i
                if up == -1:
                    parent[k] = i
                k = up
    return parent


@njit
def reach_union(parent, Bi, n):
    """The union of the paths to the root from the rows Bi, ascending."""
    mark = np.zeros(n, np.bool_)
    out = np.empty(n, np.int64)
    k = 0
    for t in range(Bi.size):
        j = Bi[t]
        while j != -1 and not mark[j]:
            mark[j] = True
            out[k] = j
            k += 1
            j = parent[j]
    return np.sort(out[:k])


@njit
def forward_block(Lp, Li, Lx, rows, X):
    """X ← (I + L)⁻¹ X in place on the rows ``rows`` (ascending, closed
    under the elimination tree's parent: every row of L's columns there is
    among them), X dense (len(rows), m) with the right-hand sides in the
    factor's order; L's stored diagonal, if any, passed over."""
    n = Lp.size - 1
    local = np.full(n, -1, np.int64)
    for a in range(rows.size):
        local[rows[a]] = a
    m = X.shape[1]
    for a in range(rows.size):
        j = rows[a]
        xj = X[a]
        nonzero = False
        for c in range(m):
            if xj[c] != 0.0:
                nonzero = True
                break
        if not nonzero:
            continue
        for t in range(Lp[j], Lp[j + 1]):
            if Li[t] == j:
                continue
            row = X[local[Li[t]]]
            v = Lx[t]
            for c in range(m):
                row[c] -= v * xj[c]
