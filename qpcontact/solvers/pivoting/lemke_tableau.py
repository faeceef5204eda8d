"""Lemke's method in its dense tableau (basis-inverse) form, and what the dense
and the sparse form (:mod:`.lemke_sparse`) share: the outcome, the lexicographic
ratio test and tie-break, and the test for a secondary ray.

The driver, with the method's outcomes and guarantees, is :mod:`.lemke`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import warnings

import numpy as np
import scipy.linalg
from scipy.linalg.blas import dger

from .active_set import pivot_kernels

__all__ = ["LemkeOutcome", "lemke", "lex_ratio_test", "lex_smallest", "ray_outcome",
           "tableau_pivot", "RowScales", "PIVOT_RTOL", "REFACTOR_EVERY"]


#: Entries of an entering column below this fraction of its largest entry are
#: treated as zero in the ratio test.
PIVOT_RTOL = 1e-11


#: Pivots between recomputations of the basis inverse from the basis columns
#: (at least n, so refactoring costs O(n²) per pivot on average).
REFACTOR_EVERY = 50


@dataclass
class LemkeOutcome:
    status: str                    # "solved", "ray", "max_pivots"
    z: np.ndarray | None           # the solution (unscaled) when solved
    basic_z: np.ndarray            # bool mask: z_i basic
    pivots: int
    ray: dict = field(default_factory=dict)


def tableau_pivot(T: np.ndarray, r: int, c: int) -> None:
    """Gauss–Jordan pivot of the (Fortran-ordered) tableau T on (r, c), in place."""
    col = T[:, c].copy()
    T[r, :] /= col[r]
    col[r] = 0.0
    dger(-1.0, col, T[r, :].copy(), a=T, overwrite_a=True)


#: Growth of the tracked row scales (see RowScales) after which they are
#: recomputed exactly from the basis inverse (O(n²), a few pivots' worth).
_REANCHOR_GROWTH = 1e3


class RowScales:
    """Per-row rounding scales of a pivoting tableau, for its sign and ratio tests.

    ``rhs[i]`` bounds (|B⁻¹| |q|)_i, the size of the terms basic value i is
    made of, and ``inv[i]`` bounds the row sum of |B⁻¹|, so an entering column
    B⁻¹a has row scales ``inv * max|a|``.  A pivot updates both in O(n) by the
    triangle inequality (row i gains |col_i / col_r| times row r); when that
    bound has grown by more than _REANCHOR_GROWTH since the last exact values,
    and at every refactorization, they are recomputed exactly.  Each row is
    thus tested against its own size: a gap of 5e11 in one row no longer sets
    the tolerance of every other row.
    """

    def __init__(self, q_abs: np.ndarray):
        self.q_abs = q_abs
        self._v = np.vstack([q_abs, np.ones_like(q_abs)])  # rows: rhs, inv
        self.growth = 1.0
        self.anchors = 0

    @property
    def rhs(self) -> np.ndarray:
        return self._v[0]

    @property
    def inv(self) -> np.ndarray:
        return self._v[1]

    def anchor(self, Binv: np.ndarray) -> None:
        A = np.abs(Binv)
        self._v[0] = A @ self.q_abs
        self._v[1] = A.sum(axis=1)
        self.growth = 1.0
        self.anchors += 1

    def pivot(self, col: np.ndarray, r: int) -> None:
        """Update for a pivot on row r of the entering column ``col`` (taken
        before the pivot); then call :meth:`reanchor_if_grown` with the new
        basis inverse.

        Row i becomes row i - (col_i / col_r) row r.  Its scale is updated to
        max(scale_i, |col_i / col_r| scale_r), an estimate of the rounding size
        rather than the triangle inequality's sum: an overestimate is not safe
        here (false ties in the ratio test pick a wrong row, a too large
        threshold hides the only candidate), so growth is bounded instead by
        recomputing the scales exactly once it exceeds _REANCHOR_GROWTH.
        """
        self.growth *= pivot_kernels().scales_pivot(self._v, col, r)

    def reanchor_if_grown(self, Binv: np.ndarray) -> None:
        if self.growth > _REANCHOR_GROWTH:
            self.anchor(Binv)


def lex_ratio_test(col: np.ndarray, rhs: np.ndarray, lex: np.ndarray, scales: RowScales,
                   col_norm: float, prefer_row: int | None = None) -> int | None:
    """Leaving row of a lexicographic minimum-ratio test, or None (a ray).

    Rows with col_i > PIVOT_RTOL times the row's own scale (``scales.inv[i] *
    col_norm``, col_norm = max|a| of the entering column before B⁻¹) compete on
    rhs_i / col_i; ratios equal up to the rounding of their own rows
    (``scales.rhs``) are ties, which go to ``prefer_row`` if it is among them,
    else to the lexicographically smallest row of lex[i, :] / col_i (lex is the
    basis inverse, or any matrix whose rows make the tableau lexico-positive).
    """
    ties = pivot_kernels().ratio_ties(col, rhs, scales.rhs, scales.inv, float(col_norm), PIVOT_RTOL)
    if ties.size <= 1:
        return int(ties[0]) if ties.size else None
    if prefer_row is not None and prefer_row in ties:
        return int(prefer_row)
    return int(ties[lex_smallest(lex[ties] / col[ties, None])])


def ray_outcome(basis: np.ndarray, x: np.ndarray, col: np.ndarray, entering: int, pivots: int,
                **extra) -> LemkeOutcome:
    """A secondary ray: the point (z, z0) and the direction (dz, dz0) along
    which raising the entering variable keeps every basic value >= 0
    (x - t col, col = B⁻¹ times the entering column)."""
    n = x.size
    Z0 = 2 * n
    v = np.zeros(2 * n + 1)
    v[basis] = x
    dv = np.zeros(2 * n + 1)
    dv[basis] = -col
    dv[entering] = 1.0
    return LemkeOutcome("ray", None, (basis >= n) & (basis < Z0), pivots,
                        ray={"z": v[n:Z0], "dz": dv[n:Z0], "z0": v[Z0], "dz0": dv[Z0],
                             "entering": entering, **extra})


def lex_smallest(V: np.ndarray) -> int:
    """Index of the lexicographically smallest row of V, entries within
    1e-10 of the block's largest magnitude counting as equal.  A tie-break,
    not a sign test: rounding noise is relative to the whole block of tied
    rows (an exact 0 computed as 1e-18 must still tie with another 0), and
    any tied row is a correct minimum ratio."""
    floor = 1e-10 * max(float(np.max(np.abs(V))), 1e-300)
    # compiled: rows of B⁻¹ tie on long runs of zeros, and column by column
    # in NumPy a 128-row block of the 667-contact granular file's LCP took
    # 20 ms
    return int(pivot_kernels().lex_smallest(np.ascontiguousarray(V, dtype=float), floor))


def lemke(M: np.ndarray, q: np.ndarray, d: np.ndarray, max_pivots: int,
          deadline=None) -> LemkeOutcome:
    """Lemke's method on dense (already scaled) data; see the module docstring.
    Stops with "time_limit" once ``deadline`` (a :class:`~qpcontact.core.deadline.Deadline`,
    or None) has passed.

    Revised form: T = [B^-1 | x] (n x (n + 1)) holds the basis inverse and the
    basic values; each entering column is B^-1 times a column of [I, -M, -d],
    and a pivot is one rank-one update of T — half the work of the full
    n x (2n + 2) tableau.
    """
    n = q.size
    if np.all(q >= 0):
        return LemkeOutcome("solved", np.zeros(n), np.zeros(n, bool), 0)
    Mf = np.asfortranarray(M)
    col_norms = np.max(np.abs(Mf), axis=0)
    T = np.zeros((n, n + 1), order="F")
    T[:, :n] = np.eye(n)
    T[:, n] = q
    Binv, x = T[:, :n], T[:, n]  # views
    basis = np.arange(n)  # variable ids: w 0..n-1, z n..2n-1, z0 2n
    Z0 = 2 * n
    scales = RowScales(np.abs(q))

    def refactor():
        # Product-form updates drift: on Fathi's family (2^n pivots) a column
        # computed from the updated inverse was off by O(100) after ~1000
        # pivots.  Recompute the inverse from the basis columns periodically.
        B = np.zeros((n, n), order="F")
        is_w = basis < n
        B[basis[is_w], np.flatnonzero(is_w)] = 1.0
        is_z = (basis >= n) & (basis < Z0)
        B[:, is_z] = -Mf[:, basis[is_z] - n]
        B[:, basis == Z0] = -d[:, None]
        # An ill-conditioned basis is a numerical outcome the certificate
        # judges, not a warning to print from inside the pivoting.
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            try:
                fresh = scipy.linalg.inv(B, check_finite=False)
                values = scipy.linalg.solve(B, q, check_finite=False)
            except np.linalg.LinAlgError:
                # singular to working precision (a Stewart-Trinkle LCP scaled
                # over 12 decades, n = 100): the updated inverse goes on, and
                # the certificate judges where it ends
                return
            Binv[:], x[:] = fresh, values
        scales.anchor(Binv)
        # Basic values of a feasible basis are >= 0; rounding leaves exact
        # (degenerate) zeros at +-1e-17 of their row's size, which would win or
        # lose ratio tests that the lexicographic rule must decide.
        x[x < 1e-13 * scales.rhs] = 0.0

    refactor_every = max(REFACTOR_EVERY, n)

    def pivot(col, r):
        row = T[r] / col[r]
        scales.pivot(col, r)
        col[r] = 0.0
        dger(-1.0, col, row, a=T, overwrite_a=True)
        T[r] = row
        scales.reanchor_if_grown(Binv)

    ratios = q / d
    theta = ratios.min()
    ties = np.flatnonzero(ratios <= theta + 1e-12 * abs(theta))
    r = int(ties[-1])  # lexicographic minimum of (q_i, e_i')/d_i: the largest tied index
    pivot(-(Binv @ d), r)
    leaving = int(basis[r])
    basis[r] = Z0
    z0_row = r
    pivots = 1
    while True:
        entering = leaving + n if leaving < n else leaving - n
        if entering < n:
            col = Binv[:, entering].copy()
            col_norm = 1.0
        else:
            col = Binv @ Mf[:, entering - n]
            np.negative(col, out=col)
            col_norm = col_norms[entering - n]
        r = lex_ratio_test(col, x, Binv, scales, col_norm, prefer_row=z0_row)
        if r is None:
            return ray_outcome(basis, x, col, entering, pivots, anchors=scales.anchors)
        if pivots >= max_pivots:
            return LemkeOutcome("max_pivots", None, np.zeros(n, bool), pivots)
        if deadline is not None and deadline.expired():
            return LemkeOutcome("time_limit", None, np.zeros(n, bool), pivots)
        pivot(col, r)
        leaving = int(basis[r])
        basis[r] = entering
        pivots += 1
        if pivots % refactor_every == 0:
            refactor()
        if leaving == Z0:
            is_z = basis >= n  # z0 has left: every basic variable is a w or a z
            zi, wi = basis[is_z] - n, basis[~is_z]
            for _ in range(2):
                # Iterative refinement against the data: w - M z = q on the basis.
                z = np.zeros(n)
                z[zi] = x[is_z]
                w = np.zeros(n)
                w[wi] = x[~is_z]
                r = q - w + Mf @ z
                x += Binv @ r
            z = np.zeros(n)
            z[zi] = np.maximum(x[is_z], 0.0)
            basic_z = np.zeros(n, bool)
            basic_z[zi] = True
            return LemkeOutcome("solved", z, basic_z, pivots)
