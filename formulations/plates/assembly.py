"""The raft's assembled stiffness and nodal loads (all 3n dofs, node-major
(w, θx, θy); see :mod:`.element` for the units and signs): the plate, edge
beams along grid lines, area and line loads."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from qpcontact.core.errors import InvalidProblemError

from .element import pressure_load, stiffness

__all__ = ["element_dofs", "assemble_stiffness", "area_load", "segment_edges", "line_load",
           "beam_stiffness"]


def element_dofs(elements: np.ndarray) -> np.ndarray:
    """(ne, 12) global dof numbers: node-major (w, θx, θy)."""
    return (3 * elements[:, :, None] + np.arange(3)).reshape(-1, 12)


def assemble_stiffness(mesh, E, nu, t) -> sp.csr_matrix:
    """The plate's stiffness [N/m, N, N·m by dof] over all 3n dofs."""
    Ke = stiffness(mesh.corners, E, nu, t)
    dofs = element_dofs(mesh.elements)
    rows = np.repeat(dofs, 12, axis=1).ravel()
    cols = np.tile(dofs, (1, 12)).ravel()
    n = 3 * mesh.nodes.shape[0]
    K = sp.csr_matrix((Ke.ravel(), (rows, cols)), shape=(n, n))
    return ((K + K.T) * 0.5).tocsr()      # exactly symmetric (the sums' rounding differs)


def area_load(mesh, pressure, elements=None) -> np.ndarray:
    """Nodal forces on w (n,) [N] of an element-wise pressure [N/m²] on the
    ``elements`` (a mask or indices; default all, pressure (ne,))."""
    out = np.zeros(mesh.nodes.shape[0])
    els = mesh.elements if elements is None else mesh.elements[elements]
    np.add.at(out, els, pressure_load(mesh.nodes[els], pressure))
    return out




def segment_edges(mesh, x0, y0, x1, y1, what: str) -> np.ndarray:
    """(k, 2) node pairs of the element edges lying on the segment
    (x0, y0)–(x1, y1), ordered from its start; refused unless they cover it
    whole (it crosses an opening or the outline, or its ends are not nodes)."""
    p0, p1 = np.array([x0, y0], float), np.array([x1, y1], float)
    d = p1 - p0
    length = float(np.hypot(*d))
    if length == 0:
        raise InvalidProblemError(f"{what} from ({x0}, {y0}) to ({x1}, {y1}) has no length")
    size = float(np.ptp(mesh.nodes, axis=0).max())
    rel = mesh.nodes - p0
    along = rel @ d / length
    off = np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0]) / length
    on = (off <= 1e-9 * size) & (along >= -1e-9 * size) & (along <= length + 1e-9 * size)
    edges = np.sort(np.stack([mesh.elements, np.roll(mesh.elements, -1, axis=1)], axis=2)
                    .reshape(-1, 2), axis=1)
    edges = np.unique(edges[on[edges].all(axis=1)], axis=0)
    covered = float(np.sum(np.hypot(*(mesh.nodes[edges[:, 1]] - mesh.nodes[edges[:, 0]]).T)))
    if abs(covered - length) > 1e-9 * length:
        raise InvalidProblemError(
            f"{what} from ({x0}, {y0}) to ({x1}, {y1}) lies on element edges over {covered:.6g} "
            f"of its {length:.6g}: it crosses an opening or the outline, or is not on grid lines")
    a = along[edges]
    flip = a[:, 0] > a[:, 1]
    edges[flip] = edges[flip][:, ::-1]
    return edges[np.argsort(along[edges[:, 0]])]


def line_load(mesh, edges, q) -> np.ndarray:
    """Nodal forces on w (n,) [force] of a line load q [force/length] along
    the edges: q ℓ / 2 to each end of an edge of length ℓ (w is linear along
    an element edge: the consistent load)."""
    out = np.zeros(mesh.nodes.shape[0])
    ell = np.hypot(*(mesh.nodes[edges[:, 1]] - mesh.nodes[edges[:, 0]]).T)
    np.add.at(out, edges[:, 0], 0.5 * q * ell)
    np.add.at(out, edges[:, 1], 0.5 * q * ell)
    return out


def beam_stiffness(mesh, edges, EI: float, GJ: float) -> sp.csr_matrix:
    """A beam along the edges (all along x or all along y), fixed to the
    plate's dofs: Euler–Bernoulli bending EI [force·length²] on (w, the slope
    along the beam) — Hermite cubics, EI/ℓ³ [[12, 6ℓ, −12, 6ℓ], ...] — and
    St-Venant torsion GJ [force·length²] on the slope across it (the beam's
    twist: ∂w/∂y along x), GJ/ℓ [[1, −1], [−1, 1]].  Bending about the plate's
    mid-surface: a downstand beam's composite EI is the user's to give."""
    n = 3 * mesh.nodes.shape[0]
    d = mesh.nodes[edges[:, 1]] - mesh.nodes[edges[:, 0]]
    along_x = bool(np.all(np.abs(d[:, 1]) <= 1e-12 * np.abs(d).max()))
    along_y = bool(np.all(np.abs(d[:, 0]) <= 1e-12 * np.abs(d).max()))
    if not (along_x or along_y):
        raise InvalidProblemError("an edge beam runs along x or along y")
    slope, twist = (1, 2) if along_x else (2, 1)
    ell = np.abs(d[:, 0] if along_x else d[:, 1])
    # signed so that the slope dof is d w / d s along increasing s: the
    # segment's edges are ordered from its start, which may run backwards
    sign = np.sign(d[:, 0] if along_x else d[:, 1])
    rows, cols, vals = [], [], []
    for (i, j), L, s in zip(edges, ell, sign):
        dofs = np.array([3 * i, 3 * i + slope, 3 * j, 3 * j + slope])
        k = EI / L ** 3 * np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                                    [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]])
        if s < 0:               # the element runs from j to i along the axis
            dofs = dofs[[2, 3, 0, 1]]
        rows.append(np.repeat(dofs, 4))
        cols.append(np.tile(dofs, 4))
        vals.append(k.ravel())
        t = np.array([3 * i + twist, 3 * j + twist])
        rows.append(np.repeat(t, 2))
        cols.append(np.tile(t, 2))
        vals.append((GJ / L * np.array([[1, -1], [-1, 1]])).ravel())
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(n, n))
