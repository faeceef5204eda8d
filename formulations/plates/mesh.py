"""Quadrilateral meshes of plates: a structured grid of rectangles (with
openings as removed cells) or the user's own nodes and quadrilaterals.

A :class:`PlateMesh` is nodes (n, 2) [m] and elements (ne, 4) of node
numbers, counterclockwise.  Nodes that no element uses are dropped, so an
opening leaves no loose node behind.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from .element import check_corners

__all__ = ["PlateMesh", "grid", "grid_lines"]


@dataclass(frozen=True)
class PlateMesh:
    """Nodes [m] and counterclockwise quadrilaterals (node numbers)."""

    nodes: np.ndarray
    elements: np.ndarray

    def __post_init__(self):
        nodes = np.asarray(self.nodes, dtype=float)
        elements = np.asarray(self.elements)
        if nodes.ndim != 2 or nodes.shape[1] != 2 or not np.all(np.isfinite(nodes)):
            raise InvalidProblemError(f"nodes must be finite (n, 2) coordinates; got shape "
                                      f"{nodes.shape}")
        if elements.ndim != 2 or elements.shape[1] != 4 or elements.shape[0] == 0:
            raise InvalidProblemError(f"elements must be (ne, 4) node numbers, at least one; "
                                      f"got shape {elements.shape}")
        if not np.issubdtype(elements.dtype, np.integer) or elements.min() < 0 \
                or elements.max() >= nodes.shape[0]:
            raise InvalidProblemError(f"element node numbers must be integers in 0..{nodes.shape[0] - 1}")
        used = np.unique(elements)
        if used.size < nodes.shape[0]:       # drop loose nodes, renumber
            new = np.full(nodes.shape[0], -1)
            new[used] = np.arange(used.size)
            nodes, elements = nodes[used], new[elements]
        check_corners(nodes[elements])
        _refuse_pinches(nodes, elements)
        object.__setattr__(self, "nodes", nodes)
        object.__setattr__(self, "elements", elements.astype(np.int64))

    @property
    def corners(self) -> np.ndarray:
        """(ne, 4, 2) corner coordinates."""
        return self.nodes[self.elements]

    @property
    def areas(self) -> np.ndarray:
        """Element areas [m²] (the shoelace formula)."""
        X = self.corners
        x, y = X[..., 0], X[..., 1]
        return 0.5 * np.abs(np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1))

    @property
    def centres(self) -> np.ndarray:
        """(ne, 2) element centres (the mean of the corners) [m]."""
        return self.corners.mean(axis=1)

    def tributary_areas(self, weights=None) -> np.ndarray:
        """Each node's share of the area [m²]: a quarter of every element it
        is a corner of (exact for rectangles and parallelograms), each element's
        area times ``weights`` per element if given (a modulus of subgrade
        reaction lumps to k_i = Σ k_e A_e / 4 [N/m])."""
        a = self.areas if weights is None else self.areas * np.asarray(weights, float)
        out = np.zeros(self.nodes.shape[0])
        np.add.at(out, self.elements, np.repeat(a[:, None] / 4.0, 4, axis=1))
        return out

    def nearest_node(self, x: float, y: float) -> int:
        d = np.hypot(self.nodes[:, 0] - x, self.nodes[:, 1] - y)
        return int(np.argmin(d))

    def boundary_nodes(self) -> np.ndarray:
        """Nodes on an edge that belongs to one element only (the outline and
        the openings' edges)."""
        edges = np.sort(np.stack([self.elements, np.roll(self.elements, -1, axis=1)], axis=2)
                        .reshape(-1, 2), axis=1)
        uniq, count = np.unique(edges, axis=0, return_counts=True)
        return np.unique(uniq[count == 1])


def _refuse_pinches(nodes, elements):
    """Refuse a node where elements meet by a corner only (two openings'
    corners touching, or a mesh like it): the parts are joined at a point,
    which in a real slab carries nothing, while the elements pass forces
    and moments through the shared node — moments there grew without
    bound as the mesh was refined (173, 258, 443 kN·m/m on 0.5, 0.25,
    0.125 m cells), each answer certified.  Around a node its elements
    form fans; a fan of k elements has k edges at the node (inside) or
    k + 1 (on the outline): two fans or more, k + 2 or more."""
    a, b = elements.ravel(), np.roll(elements, -1, axis=1).ravel()
    n = nodes.shape[0]
    codes = np.unique(np.minimum(a, b).astype(np.int64) * n + np.maximum(a, b))    # each edge once
    at_edges = np.bincount(np.concatenate([codes // n, codes % n]), minlength=n)
    at_elements = np.bincount(elements.ravel(), minlength=n)
    pinched = np.flatnonzero(at_edges - at_elements >= 2)
    if pinched.size:
        x, y = nodes[pinched[0]]
        raise InvalidProblemError(
            f"the slab's parts meet at a point only, at ({x:.6g}, {y:.6g})"
            + (f" and {pinched.size - 1} more" if pinched.size > 1 else "")
            + ": a point carries no load in a slab, but the elements would pass forces and "
            "moments through it; move the openings apart by a cell or join the parts")


def grid_lines(length: float, n: int, through=()) -> np.ndarray:
    """Grid-line coordinates 0..length [m] in about ``n`` equal cells, with
    every coordinate of ``through`` (columns, edges of openings and patches)
    made a line: the nearest line is moved onto it where that keeps cells
    at least a third of the nominal size, otherwise a line is added."""
    if not np.isfinite(length) or length <= 0:
        raise InvalidProblemError(f"a plate's side must be a positive length; got {length!r}")
    if isinstance(n, bool) or int(n) != n or n < 1:
        raise InvalidProblemError(f"the number of cells must be a positive integer; got {n!r}")
    lines = np.linspace(0.0, length, int(n) + 1)
    h = length / n
    for c in sorted(set(float(v) for v in through)):
        if not 0.0 <= c <= length:
            raise InvalidProblemError(f"coordinate {c} is outside the plate [0, {length}]")
        k = int(np.argmin(np.abs(lines - c)))
        if abs(lines[k] - c) < 1e-12 * length:
            continue
        moved = lines.copy()
        moved[k] = c
        pinned = [0.0, length] + [float(v) for v in through]
        # only the two cells beside the moved line: a cell elsewhere already
        # under h/3 (a column's section in COLUMN_CELLS) must not stop every
        # later coordinate from being snapped, each then added beside a line
        # as a sliver (a point load 1 mm off a line: a cell 1 mm wide)
        if 0 < k < lines.size - 1 and moved[k] - moved[k - 1] >= h / 3 \
                and moved[k + 1] - moved[k] >= h / 3 \
                and not any(abs(lines[k] - p) < 1e-12 * length for p in pinned):
            lines = moved
        else:
            lines = np.sort(np.append(lines, c))
    return lines


def grid(x_lines, y_lines, openings=()) -> PlateMesh:
    """A structured mesh on the grid lines ``x_lines`` × ``y_lines`` [m]
    (increasing), without the cells whose centre lies inside one of the
    ``openings`` (rectangles (x0, y0, x1, y1) [m])."""
    x = np.asarray(x_lines, dtype=float)
    y = np.asarray(y_lines, dtype=float)
    for name, v in (("x", x), ("y", y)):
        if v.ndim != 1 or v.size < 2 or not np.all(np.diff(v) > 0) or not np.all(np.isfinite(v)):
            raise InvalidProblemError(f"{name} grid lines must be at least two increasing numbers")
    nx, ny = x.size - 1, y.size - 1
    X, Y = np.meshgrid(x, y, indexing="ij")
    nodes = np.stack([X.ravel(), Y.ravel()], axis=1)
    node = np.arange(nodes.shape[0]).reshape(nx + 1, ny + 1)
    i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    i, j = i.ravel(), j.ravel()
    elements = np.stack([node[i, j], node[i + 1, j], node[i + 1, j + 1], node[i, j + 1]], axis=1)
    cx = 0.5 * (x[i] + x[i + 1])
    cy = 0.5 * (y[j] + y[j + 1])
    keep = np.ones(i.size, bool)
    for hole in openings:
        if len(hole) != 4:
            raise InvalidProblemError(f"an opening is a rectangle (x0, y0, x1, y1); got {hole!r}")
        x0, y0, x1, y1 = (float(v) for v in hole)
        if not (x1 > x0 and y1 > y0):
            raise InvalidProblemError(f"an opening needs x1 > x0 and y1 > y0; got {hole!r}")
        keep &= ~((cx > x0) & (cx < x1) & (cy > y0) & (cy < y1))
    if not keep.any():
        raise InvalidProblemError("the openings remove every cell of the plate")
    return PlateMesh(nodes, elements[keep])
