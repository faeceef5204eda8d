"""Compiled nested dissection of a raft's mesh (numba), for :mod:`.ordering`.

The same order as the NumPy version it replaced, step for step — split at
the median distinct coordinate across the longer side, the far side's
nodes with a neighbour across as the separator, halves first, separator
last — without a NumPy call per part: at 288 x 288 cells the 2 055 parts
cost 0.25 s in Python, and the node graph built through a COO matrix of
every stiffness entry (duplicates summed) another 0.18 s.
"""

from __future__ import annotations

import numpy as np
from numba.typed import List

from qpcontact.core.compiled import njit


@njit
def node_graph(Kp, Ki, dof_node, node_first, node_dofs, n_nodes):
    """The mesh's node graph (CSR, each row ascending, its own node in it)
    from a symmetric stiffness's pattern (CSC or CSR: ``Kp``, ``Ki``) on
    dofs whose node is ``dof_node`` (0 … n_nodes − 1): node u's dofs are
    ``node_dofs[node_first[u]:node_first[u + 1]]``."""
    mark = np.full(n_nodes, -1, np.int64)
    count = np.zeros(n_nodes + 1, np.int64)
    for u in range(n_nodes):             # first pass: the row lengths
        mark[u] = u
        c = 1
        for a in range(node_first[u], node_first[u + 1]):
            j = node_dofs[a]
            for t in range(Kp[j], Kp[j + 1]):
                v = dof_node[Ki[t]]
                if mark[v] != u:
                    mark[v] = u
                    c += 1
        count[u + 1] = c
    Gp = np.cumsum(count)
    Gi = np.empty(Gp[-1], np.int64)
    mark[:] = -1
    for u in range(n_nodes):
        k = Gp[u]
        mark[u] = u
        Gi[k] = u
        k += 1
        for a in range(node_first[u], node_first[u + 1]):
            j = node_dofs[a]
            for t in range(Kp[j], Kp[j + 1]):
                v = dof_node[Ki[t]]
                if mark[v] != u:
                    mark[v] = u
                    Gi[k] = v
                    k += 1
        Gi[Gp[u]:Gp[u + 1]].sort()
    return Gp, Gi


@njit
def dissect(x, y, Gp, Gi, leaf):
    """The nested-dissection permutation of the nodes at ``x``, ``y`` with
    the graph ``Gp``, ``Gi`` (every row holding its own node): parts of at
    most ``leaf`` nodes, or all on one line across the longer side, in
    their own order."""
    n = x.size
    in_a = np.zeros(n, np.bool_)
    order = np.empty(n, np.int64)
    filled = 0
    parts = List()
    placed = List()
    parts.append(np.arange(n))
    placed.append(False)
    while len(parts) > 0:
        idx = parts.pop()
        done = placed.pop()
        m = idx.size
        split = False
        if not done and m > leaf:
            x0, x1, y0, y1 = np.inf, -np.inf, np.inf, -np.inf
            for k in range(m):
                i = idx[k]
                x0, x1 = min(x0, x[i]), max(x1, x[i])
                y0, y1 = min(y0, y[i]), max(y1, y[i])
            coord = x if x1 - x0 >= y1 - y0 else y
            values = np.unique(coord[idx])
            if values.size >= 2:
                split = True
                cut = values[values.size // 2]
                below = coord[idx] < cut
                a = idx[below]
                b = idx[~below]
                in_a[a] = True
                touches = np.zeros(b.size, np.bool_)
                for k in range(b.size):
                    i = b[k]
                    for t in range(Gp[i], Gp[i + 1]):
                        if in_a[Gi[t]]:
                            touches[k] = True
                            break
                in_a[a] = False
                parts.append(b[touches])       # popped last: the separator
                placed.append(True)
                parts.append(b[~touches])
                placed.append(False)
                parts.append(a)                # popped first
                placed.append(False)
        if not split:
            order[filled:filled + m] = idx
            filled += m
    return order
