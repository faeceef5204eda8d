r"""The order in which the raft's sparse LDLᵀ eliminates its unknowns:
nested dissection of the mesh by coordinate bisection.

Why an order matters
--------------------
Eliminating a node's dofs [m, rad] from the raft's stiffness couples all
its not-yet-eliminated neighbours (the Schur complement's new entries,
the factor's fill).  Split the mesh's nodes into A, B and a separator S
such that no element (nor edge beam) has nodes in both A and B.  Ordered
A, B, then S, the factor has no entry between A and B: the two halves are
independent problems, ordered the same way recursively, and only S, of
about √N nodes on a 2-D mesh of N nodes, becomes a dense block at the end.
That is nested dissection (George, 1973): fill O(N log N) and O(N^{3/2})
operations on a 2-D mesh, the optimal orders of magnitude, with the work
gathered in dense blocks, which a supernodal factorisation does at the
speed of dense linear algebra.

Finding the separators from the coordinates
-------------------------------------------
The mesh is flat and its elements are small, so a straight cut is a good
separator: split the nodes at the median coordinate along the longer side
of their bounding box, A below it and B at or above; the nodes of B with
a neighbour in A (in the stiffness's pattern: a shared element or beam)
are S, and A and B \ S share nothing.  On a structured grid cut at a grid
line, S is that line.  Any split is a valid order (the answer does not
depend on it, only the fill); openings and zones change nothing.  Below
``LEAF`` nodes a part is eliminated in its own order.

Measured (the windward raft of ``benchmarks/scale.py``, K plus every
spring; nnz(L) with its diagonal, SuperLU's count in this order against
qdldl's under its AMD): 57 x 57 cells (10 092 dofs) 0.80 M against 0.84 M;
115 x 115 (40 368) 4.06 M against 4.49 M; 182 x 182 (100 467) 11.6 M
against 14.6 M; 577 x 577 (1 002 252) 160 M (docs/dev-notes.md, "The
10⁶-dof raft").  The bisections and the node graph are compiled
(:mod:`._ordering_kernels`): the same order, made in 0.023 s instead of
0.069 s at 182 x 182 cells (docs/dev-notes.md, "Rafts at their floor,
round two").
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["nested_dissection", "dof_order", "LEAF"]

#: parts of at most this many nodes are not split further (their fill is
#: small; 16, 32 and 64 were measured alike within 10–20 %)
LEAF = 32


def nested_dissection(points: np.ndarray, graph: sp.csr_matrix, leaf: int = LEAF) -> np.ndarray:
    """A permutation of the nodes (``points`` (n, 2) [m], ``graph`` their
    (n, n) adjacency, symmetric): each part's two halves first, the
    separator between them after (module docstring; compiled in
    :mod:`._ordering_kernels`)."""
    from ._ordering_kernels import dissect

    n = points.shape[0]
    graph = (sp.csr_matrix(graph) + sp.identity(n, format="csr")).tocsr()   # no empty row
    points = np.asarray(points, float)
    return dissect(np.ascontiguousarray(points[:, 0]), np.ascontiguousarray(points[:, 1]),
                   graph.indptr.astype(np.int64), graph.indices.astype(np.int64), leaf)


def dof_order(pattern: sp.spmatrix, node_of: np.ndarray, points: np.ndarray) -> np.ndarray:
    """A permutation of the dofs of the symmetric ``pattern`` (a stiffness
    on some of a mesh's dofs; ``node_of`` the node of each, ``points`` the
    mesh's node coordinates): the nodes in nested-dissection order, each
    node's dofs together in their own order."""
    from ._ordering_kernels import dissect, node_graph

    pattern = pattern if pattern.format in ("csc", "csr") else sp.csc_matrix(pattern)
    used, local = np.unique(node_of, return_inverse=True)
    node_dofs = np.argsort(local, kind="stable")
    node_first = np.concatenate(([0], np.cumsum(np.bincount(local, minlength=used.size))))
    Gp, Gi = node_graph(pattern.indptr, pattern.indices, local.astype(np.int64), node_first,
                        node_dofs, used.size)
    p = np.asarray(points, float)[used]
    rank = np.empty(used.size, np.int64)
    rank[dissect(np.ascontiguousarray(p[:, 0]), np.ascontiguousarray(p[:, 1]), Gp, Gi,
                 LEAF)] = np.arange(used.size)
    return np.lexsort((np.arange(node_of.size), rank[local]))
