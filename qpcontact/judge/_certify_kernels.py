"""Compiled loops of the certificate (numba).

The column influences c_j = max_i |M_ij| / σ_i of a sparse M are one pass over
its nonzeros; as NumPy calls (divide, then maximum.reduceat) they cost 4 ms on
a 3e5-nonzero chain, a tenth of a bpp solve; as one loop, a few hundred µs.
"""

from __future__ import annotations

import numpy as np
from ..core.compiled import njit


@njit
def csc_column_max_ratio(indptr: np.ndarray, indices: np.ndarray, data: np.ndarray,
                         sigma: np.ndarray) -> np.ndarray:
    """max_i |data_ij| / sigma_i per column of a CSC matrix (0/0 = 0, x/0 = inf)."""
    n = indptr.shape[0] - 1
    out = np.zeros(n)
    for j in range(n):
        best = 0.0
        for k in range(indptr[j], indptr[j + 1]):
            a = abs(data[k])
            if a == 0.0:
                continue
            s = sigma[indices[k]]
            r = a / s if s > 0.0 else np.inf
            if r > best:
                best = r
        out[j] = best
    return out
