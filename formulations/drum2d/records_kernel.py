"""A step's force statistics in one compiled pass (numba): records.Recorder.forces'
peaks, histograms and sliding work, the same numbers as its NumPy route
(~15 calls of 10-30 µs a step: masks by kind, searchsorted, bincount,
np.add.at).  SI units: N, J.  Imported only where a run records, so that
importing the drum does not load numba.
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.compiled import njit

__all__ = ["force_books"]


@njit
def force_books(F, kind, i, j, sliding, edges, disc, peak, counts, work):
    """Into the step's rows: ``peak`` (3,) the largest force F >= edges[0] by
    contact kind, ``counts`` (3, B) the forces' bins (the last edge's excess
    in the last bin), ``work`` (n,) the contacts' friction work ``sliding``
    [J] charged half to each log at a log–log contact (kind ``disc``), all
    to the log otherwise —
    summed onto the row in contact order, the i ends first, then the j ends,
    as np.add.at sums."""
    nb = edges.shape[0] - 1
    seen = np.zeros(3, np.bool_)
    for k in range(F.shape[0]):
        f = F[k]
        if f >= edges[0]:
            c = kind[k]
            if not seen[c] or f > peak[c]:
                peak[c] = f
                seen[c] = True
            at = np.searchsorted(edges, f, side="right") - 1
            counts[c, min(max(at, 0), nb - 1)] += 1
    m = F.shape[0]
    share = np.empty(m)
    for k in range(m):
        share[k] = (0.5 if kind[k] == disc else 1.0) * sliding[k]
    for k in range(m):
        work[i[k]] += share[k]
    for k in range(m):
        if j[k] >= 0:
            work[j[k]] += share[k]
