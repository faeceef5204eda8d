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


def grid_pairs(positions: np.ndarray, radii: np.ndarray, margin: float = 0.0):
    """Candidate pairs (i, j), i < j, of discs that may be within ``margin`` [m]
    of each other, and the number of pairs examined (their count: O(n)).  The
    grid's pass is compiled (contact_kernel.candidate_pairs: the cells in key
    order, the same cell's pairs first, then the four offsets' cell by cell)."""
    from .contact_kernel import candidate_pairs   # numba: imported where it runs

    pairs = candidate_pairs(np.ascontiguousarray(positions, float),
                            np.ascontiguousarray(radii, float), float(margin))
    return pairs, int(pairs.shape[0])


def all_pairs(positions: np.ndarray, radii: np.ndarray, margin: float = 0.0):
    """The reference: every pair within ``margin`` by checking all n(n−1)/2 (O(n²))."""
    i, j = np.triu_indices(positions.shape[0], 1)
    gap = np.linalg.norm(positions[i] - positions[j], axis=1) - radii[i] - radii[j]
    keep = gap <= margin
    return np.column_stack([i[keep], j[keep]])
