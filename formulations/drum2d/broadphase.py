r"""Broad phase: the candidate disc–disc pairs in O(n), by a uniform grid.

Two discs i, j can touch within a margin δ [m] only if |c_i − c_j| <= r_i + r_j
+ δ <= 2 r_max + δ.  With square cells of side a >= 2 r_max + δ each disc's
centre falls in one cell, and a pair within reach lies in the same or in
adjacent cells.  Sorting the discs by cell key and looking, from each occupied
cell, at itself and four of its eight neighbours ((+1, 0), (−1, +1), (0, +1),
(+1, +1): the other four see this cell from their side) lists every such pair
once.  The work is the sort, O(n log n) with a tiny constant, plus the pairs
listed, which is O(n) while the discs are packed at bounded density (a cell of
side ~ d holds O(1) discs) — unlike the n(n−1)/2 of all pairs.  The narrow
phase (formulations.drum2d.contacts) keeps the pairs whose gap is within δ.

Disc–shell and disc–lifter candidates need no grid: the shell is one circle
(one test per disc) and the lifters few (k tests per disc), O(n) either way.
"""

from __future__ import annotations

import numpy as np

__all__ = ["grid_pairs", "all_pairs"]

# Half of the 3 x 3 stencil: each unordered pair of adjacent cells is seen once.
_OFFSETS = ((1, 0), (-1, 1), (0, 1), (1, 1))


def _ranges_pairs(starts_a, counts_a, starts_b, counts_b):
    """All (a, b) index pairs of the sorted order, for blocks a = starts_a[k] +
    [0, counts_a[k]) against b = starts_b[k] + [0, counts_b[k])."""
    sizes = counts_a * counts_b
    total = int(sizes.sum())
    if total == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    block = np.repeat(np.arange(sizes.size), sizes)
    local = np.arange(total) - np.repeat(np.cumsum(sizes) - sizes, sizes)
    cb = counts_b[block]
    return starts_a[block] + local // cb, starts_b[block] + local % cb


def grid_pairs(positions: np.ndarray, radii: np.ndarray, margin: float = 0.0):
    """Candidate pairs (i, j), i < j, of discs that may be within ``margin`` [m]
    of each other, and the number of pairs examined (their count: O(n))."""
    n = positions.shape[0]
    if n < 2:
        return np.zeros((0, 2), np.int64), 0
    cell = 2.0 * float(radii.max()) + float(margin)
    ij = np.floor((positions - positions.min(axis=0)) / cell).astype(np.int64)
    width = int(ij[:, 0].max()) + 3       # a neighbour column never wraps into the next row
    key = (ij[:, 1] + 1) * width + (ij[:, 0] + 1)
    order = np.argsort(key, kind="stable")
    skey = key[order]
    cells, starts, counts = np.unique(skey, return_index=True, return_counts=True)
    # the same cell: i < j within the block
    sizes = counts * (counts - 1) // 2
    pa, pb = [], []
    if sizes.sum():
        a, b = _ranges_pairs(starts, counts, starts, counts)
        keep = a < b
        pa.append(a[keep])
        pb.append(b[keep])
    for dx, dy in _OFFSETS:
        target = cells + dy * width + dx
        pos = np.searchsorted(cells, target)
        pos_c = np.minimum(pos, cells.size - 1)
        hit = cells[pos_c] == target
        if hit.any():
            a, b = _ranges_pairs(starts[hit], counts[hit], starts[pos_c[hit]], counts[pos_c[hit]])
            pa.append(a)
            pb.append(b)
    if not pa:
        return np.zeros((0, 2), np.int64), 0
    i = order[np.concatenate(pa)]
    j = order[np.concatenate(pb)]
    pairs = np.column_stack([np.minimum(i, j), np.maximum(i, j)])
    return pairs, int(pairs.shape[0])


def all_pairs(positions: np.ndarray, radii: np.ndarray, margin: float = 0.0):
    """The reference: every pair within ``margin`` by checking all n(n−1)/2 (O(n²))."""
    i, j = np.triu_indices(positions.shape[0], 1)
    gap = np.linalg.norm(positions[i] - positions[j], axis=1) - radii[i] - radii[j]
    keep = gap <= margin
    return np.column_stack([i[keep], j[keep]])
