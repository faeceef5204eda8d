r"""Whether a raft's loads can stand on supports that only push: the
statics of each part of the raft, before any solve.

A part of the plate that no bilateral support holds can move as a rigid
body: w = a + b x + c y [m], θ = (b, c) [rad] (x, y [m]).  On it the loads
(nodal forces F_i [N] on w, downward positive, and any nodal couples on θ
[N m]) do the virtual work a R + b M_y + c M_x with the resultant
R = Σ F_i [N] and its moments M_y = Σ F_i x_i + Σ couples on θx,
M_x = Σ F_i y_i + Σ couples on θy [N m].  Supports that only push (soil,
a rigid floor) resist a rigid motion only where it goes down somewhere
they are, so an equilibrium needs R > 0 (downward) acting at
(M_y, M_x)/R inside the convex hull of the part's supported nodes;
otherwise the part lifts off or tips over the hull's edge with the loads
doing positive work — no equilibrium, proved by the motion.

Parts: nodes joined through the stiffness matrix (an element, an edge
beam).  An opening across the raft cuts it into parts that stand or fall
alone: the whole raft's resultant may stand while a part of it is pulled
off (before, that raft went to the solver and came back "not solved ...
may have no equilibrium"; now the part is named).  A part that a
bilateral support holds is not judged here (a pile may pull).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from qpcontact.core.errors import InvalidProblemError

__all__ = ["NoEquilibriumError", "parts", "check_statics"]


class NoEquilibriumError(InvalidProblemError):
    """The loads have no equilibrium on the raft's tensionless supports
    (proved by statics; the message says how the raft would move)."""


def parts(K) -> np.ndarray:
    """Per node, the number of the part of the plate it belongs to: the
    connected components of the dofs the stiffness K (3 dofs a node)
    couples, read at each node's w (an element couples all its dofs; 0.04
    s CPU at 250 563 dofs)."""
    from scipy.sparse.csgraph import connected_components

    return connected_components(sp.csr_matrix(K), directed=False)[1][0::3]


def check_statics(K, supported, fixed, nodes, f) -> None:
    """Raise :class:`NoEquilibriumError` where a part of the raft held by
    no bilateral support (``fixed`` dofs) has loads ``f`` (3n,) [N] that its
    ``supported`` nodes, which only push, cannot balance (module docstring)."""
    label = parts(K)
    held = np.zeros(label.max() + 1, bool)
    held[label[np.asarray(fixed, dtype=np.int64) // 3]] = True
    on = np.zeros(nodes.shape[0], bool)
    on[supported] = True
    several = held.size > 1
    for part in np.flatnonzero(~held):
        mine = label == part
        where = ""
        if several:
            lo, hi = nodes[mine].min(axis=0), nodes[mine].max(axis=0)
            where = (f"the part of the raft over x {lo[0]:.6g}..{hi[0]:.6g}, y {lo[1]:.6g}.."
                     f"{hi[1]:.6g} (the openings cut it from the rest): ")
        if not on[mine].any():
            raise NoEquilibriumError(
                f"{where or 'the raft: '}no soil, floor or support is under it, so nothing holds "
                "it: give it soil or a support")
        _stand(nodes[mine & on], f.reshape(-1, 3)[mine], nodes[mine], where)


def _stand(pts, loads, at, where):
    """One part: its supported points ``pts``, its nodal loads (k, 3) at ``at``."""
    fw = loads[:, 0]
    total = float(fw.sum())
    scale = float(np.abs(fw).sum())
    if total <= 1e-12 * max(scale, 1e-300):
        raise NoEquilibriumError(
            f"{where}the loads' resultant is {total:.6g} downward: the raft has no equilibrium "
            "on supports that only push (it would lift off as a rigid body); add downward load "
            "(self-weight) or a bilateral support")
    # the virtual work of the rigid motion's b and c: the loads' moments
    point = np.array([fw @ at[:, 0] + loads[:, 1].sum(), fw @ at[:, 1] + loads[:, 2].sum()]) / total
    if pts.shape[0] < 3:
        return
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = ConvexHull(pts)
    except QhullError:              # the supported nodes on a line: the solve decides
        return
    size = float(np.ptp(pts, axis=0).max())
    if np.any(hull.equations[:, :2] @ point + hull.equations[:, 2] > 1e-9 * size):
        raise NoEquilibriumError(
            f"{where}the loads' resultant acts at ({point[0]:.6g}, {point[1]:.6g}), outside the "
            "supported footprint: the raft has no equilibrium on supports that only push "
            "(it would tip over its edge)")
