"""O(n) loops of the tableau methods ("lemke", "trace"), compiled with numba.

Each pivot of Lemke's method does O(n²) BLAS work and a handful of O(n)
passes (the ratio test, the update of the per-row scales).  As NumPy calls the
O(n) passes cost ~10 µs each in call overhead, as much as the BLAS update
itself at n = 200; as one compiled loop they cost ~1 µs.
"""

from __future__ import annotations

import numpy as np
from ...core.compiled import njit


@njit
def scales_pivot(V: np.ndarray, col: np.ndarray, r: int) -> float:
    """Per-row scales after a pivot on row r (see RowScales.pivot), in place.

    V is 2 x n (basic values' scales, basis-inverse rows' scales).  Returns
    the largest factor by which a row's scale grew.
    """
    n = col.shape[0]
    cr = abs(col[r])
    grow = 1.0
    tiny = 2.2250738585072014e-308
    for k in range(2):
        vr = V[k, r]
        for i in range(n):
            if i == r:
                continue
            a = abs(col[i]) / cr * vr
            if a > V[k, i]:
                g = a / max(V[k, i], tiny)
                if g > grow:
                    grow = g
                V[k, i] = a
        V[k, r] = vr / cr
    return grow


@njit
def ratio_ties(col: np.ndarray, rhs: np.ndarray, rhs_scale: np.ndarray, inv_scale: np.ndarray,
               col_norm: float, pivot_rtol: float) -> np.ndarray:
    """Rows tied for the minimum ratio rhs_i / col_i among the candidates
    col_i > pivot_rtol * inv_scale_i * col_norm (empty: no candidate, a ray).

    Ratios are tied when they differ by less than 1e-12 of the minimum plus
    the rounding of both rows, 1e-15 * rhs_scale_i / col_i.  The first entry
    is the row of the smallest ratio.
    """
    n = col.shape[0]
    k = -1
    theta = np.inf
    for i in range(n):
        c = col[i]
        if c > pivot_rtol * inv_scale[i] * col_norm:
            t = rhs[i] / c
            if t < theta:
                theta = t
                k = i
    if k < 0:
        return np.empty(0, np.int64)
    unc_k = 1e-15 * rhs_scale[k] / col[k]
    out = np.empty(n, np.int64)
    out[0] = k
    m = 1
    for i in range(n):
        if i == k:
            continue
        c = col[i]
        if c > pivot_rtol * inv_scale[i] * col_norm:
            t = rhs[i] / c
            if t <= theta + 1e-12 * abs(theta) + unc_k + 1e-15 * rhs_scale[i] / c:
                out[m] = i
                m += 1
    return out[:m]


@njit
def sure_negatives(values: np.ndarray, is_z: np.ndarray, z: np.ndarray, q_terms: np.ndarray,
                   row_l1: np.ndarray, inv_diag: np.ndarray, cap_floor: float, rho: float):
    """(indices surely below -tau, whether some value is undecided) for the
    cheap tolerance bounds of active_set.negative_components, in one pass."""
    n = values.shape[0]
    zmax = 0.0
    for i in range(n):
        a = abs(z[i])
        if a > zmax:
            zmax = a
    cap = max(zmax, cap_floor)
    out = np.empty(n, np.int64)
    m = 0
    unsure = False
    for i in range(n):
        v = values[i]
        if v >= 0.0:
            continue
        # the idle-row floor (at most ‖M_i‖₁ cap) exists only where q_i = 0
        sigma_hi = q_terms[i] + row_l1[i] * (zmax + (cap if q_terms[i] == 0.0 else 0.0))
        if is_z[i]:
            hi = rho * min(sigma_hi * inv_diag[i], cap)
            lo = 0.0
        else:
            hi = rho * sigma_hi
            lo = rho * q_terms[i]
        if v < -hi:
            out[m] = i
            m += 1
        elif v < -lo:
            unsure = True
    return out[:m], unsure


@njit
def lex_smallest(V: np.ndarray, floor: float) -> int:
    """Index of the lexicographically smallest row of V, entries within
    ``floor`` of a column's smallest counting as equal (lemke_tableau's
    lex_smallest, whose docstring says why): column by column, the rows
    still tied narrowed to those within ``floor`` of their minimum."""
    k, n = V.shape
    alive = np.arange(k)
    m = k
    for j in range(n):
        low = np.inf
        for t in range(m):
            v = V[alive[t], j]
            if v < low:
                low = v
        kept = 0
        for t in range(m):
            if V[alive[t], j] <= low + floor:
                alive[kept] = alive[t]
                kept += 1
        m = kept
        if m == 1:
            break
    return alive[0]
