"""Lemke's method on a sparse LU of the basis: the form of ``"lemke"`` for
large sparse M.

Same method as :mod:`.lemke` (``w - M z - d z0 = q``, the complement of the
variable that left enters, lexicographic ratio test), but the basis
B (columns of [I, -M, -d]) is never inverted: it is factorized by SuperLU and
each pivot appends one eta column (product form, B_k = B_0 E_1 ... E_k), with
a fresh factorization every REFACTOR_EVERY = 20 pivots.  Memory O(nnz(LU) + n k)
instead of the dense tableau's n², so the 8080-unknown LCP of a 2020-contact
granular file is solved in 5461 pivots (3 s) where the dense inverse
(520 MB, 65 M flops a pivot) did not finish in 20 minutes.  The
lexicographic tie-break needs rows of B⁻¹ only for tied rows: one transposed
solve each.

Where the time of a pivot goes, and what was cut (CPU, one BLAS thread; the
two versions alternated, the machine loaded 6-9): on the two 2-D drum steps
that a 500-log revolution hands to "auto" (1 208 and 1 293 contacts, 5 172
unknowns, 3 377 and 4 061 pivots) the pivot's column was read by scipy's
column slicing (a third of the pivot), and each refactorization ran SuperLU
on the whole basis, its unit columns included — now the column is read off
the CSC arrays and only C₂ is factorized (:class:`_ProductFormBasis`):
3.1-3.4 and 3.6-3.9 s → 2.1-2.3 and 2.2-2.3 s.  On the 667-contact granular
file, where up to 381 rows tie, the tie-break's rows of B⁻¹ are one
multi-column transposed solve a block, and the lexicographic scan is
compiled: 8.6 → 6.3-7.3 s.  Other rounding, so a tie can go another way:
the drum steps took 3 373 and 4 059 pivots against 3 377 and 4 061, to the
same certificates (2e-16); the stress families (lemke, 20 seeds, 1 156
solves) end in the same category every one.

A warm start from a guessed complementary set B0 (Lemke on the principal pivot
transform, covering vector B0 1) was tried and dropped: from the contact
states of an NSGS answer on that file (natural-map error 3e-7) it ended on a
secondary ray within 1-11 pivots for each of seven covering vectors (the
guessed set's own basic solution was far off: natural-map error 9e-5, three
basic values of -1e-5 to -2e-4).

Tolerances: a ratio-test candidate needs a_i > PIVOT_RTOL max|a| (relative
to the whole column: the dense form's per-row scales of B⁻¹ need the explicit
inverse).  Ratios tie within 1e-12 of the minimum plus each row's own
rounding, 1e-15 times its value's scale, an estimate of (|B⁻¹||q|)_i: it
starts at |q_i| and grows by the pivots' max rule; at every
refactorization the fresh values below 1e-13 of it become exact zeros, and
it is then re-estimated from |x_i| and two solves with random signs
(_rounding_scales).  What was measured on the way:

- a tie window relative to max|x|: on the 2020-contact file, values of 1e-17
  (q entries that are rounding residues, beside values of 0.1) tied with
  exact zeros, and pivots on them left w = -1e-17 on rows whose every term
  is zero;
- never re-estimating (the max rule alone): overestimates, false ties, and
  2064 pivots to a point with LCP certificate 1.0 on that file;
- re-estimating as |x_i| alone: underestimates values made by cancellation,
  so ties became strict minima — Fathi's family left its 2^n path from
  n = 8 (to the same solution).  With the random-sign solves it follows
  2^n up to n = 12 (as the dense form and exact arithmetic do).

"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .active_set import pivot_kernels
from .lemke_tableau import PIVOT_RTOL, LemkeOutcome, lex_smallest, ray_outcome

__all__ = ["sparse_lemke", "SingularBasis"]

#: Tied rows of B⁻¹ held at once by the lexicographic tie-break.
LEX_BLOCK = 128
#: Pivots between fresh factorizations.  Product-form updates drift: on
#: qpcontact stress's hard families (n <= 100) refactoring every 50 pivots
#: left 8 answers uncertified that the dense form certifies, every 20 left 2
#: (and every 10 or 5 the same 2); the 2020-contact file takes 3 % longer
#: at 20 than at 50, a 2500-unknown membrane 17 %.
REFACTOR_EVERY = 20


class SingularBasis(Exception):
    """SuperLU found a basis singular (in exact arithmetic every basis Lemke
    reaches is regular: rounding made a pivot's basis singular)."""


class _ProductFormBasis:
    """B⁻¹ v and B⁻ᵀ v for B = B_0 E_1 ... E_k: an LU of B_0 and eta columns.

    B_0's columns of basic w are unit columns e_i: ordered (rows those w
    cover, the other rows; w columns, the rest) it is [[I, C₁], [0, C₂]],
    so only C₂ — the rest's columns on the rows no w covers, square — is
    factorized, and B_0 x = v is C₂ x_rest = v_other, x_w = v_covered −
    C₁ x_rest.  On a drum step's LCP (5 172 unknowns, 1 941 basic z) C₂'s
    LU took 2.5 ms where SuperLU spent 6.4 ms on all of B_0 (its unit
    columns included) and a solve a third of the time."""

    def __init__(self, columns: sp.csc_matrix, basis: np.ndarray):
        n = basis.size
        unit = basis < n                    # basic w: column e_{basis[k]}
        self.rest = np.flatnonzero(~unit)
        self.unit = np.flatnonzero(unit)
        covered = np.zeros(n, bool)
        covered[basis[unit]] = True
        self.covered = basis[unit]          # the row of each unit column, in basis order
        self.other = np.flatnonzero(~covered)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sp.SparseEfficiencyWarning)
            C = sp.csc_matrix(columns[:, basis[self.rest]])
            self.C1 = sp.csr_matrix(C[self.covered, :])
            self.C1T = self.C1.T.tocsr()
            C2 = sp.csc_matrix(C[self.other, :])
        self.lu = None
        if self.rest.size:
            try:
                self.lu = spla.splu(C2)
            except RuntimeError as exc:   # "exactly singular", or SuperLU's panel failure on one
                raise SingularBasis(str(exc)) from None
        self.etas: list[tuple[int, np.ndarray]] = []

    def _solve0(self, v: np.ndarray) -> np.ndarray:
        y = np.empty(v.size)
        if self.lu is None:
            y[self.unit] = v[self.covered]
            return y
        xr = self.lu.solve(v[self.other])
        y[self.rest] = xr
        y[self.unit] = v[self.covered] - self.C1 @ xr
        return y

    def _solve0_t(self, v: np.ndarray) -> np.ndarray:
        # B_0ᵀ y = v: y_covered = v_unit, C₂ᵀ y_other = v_rest − C₁ᵀ y_covered
        # (v: a vector, or one column per right-hand side)
        y = np.empty(v.shape)
        y[self.covered] = v[self.unit]
        if self.lu is not None:
            y[self.other] = self.lu.solve(v[self.rest] - self.C1T @ v[self.unit], trans="T")
        return y

    def solve(self, v: np.ndarray) -> np.ndarray:
        y = self._solve0(v)
        for p, a in self.etas:
            yp = y[p] / a[p]
            y -= a * yp
            y[p] = yp
        return y

    def solve_t(self, v: np.ndarray) -> np.ndarray:
        """B⁻ᵀ v, v a vector or one column per right-hand side."""
        v = v.copy()
        for p, a in reversed(self.etas):
            # E^T y = v: y_i = v_i (i != p), a . y = v_p
            v[p] = (v[p] - (a @ v - a[p] * v[p])) / a[p]
        return self._solve0_t(v)

    def update(self, p: int, a: np.ndarray) -> None:
        self.etas.append((p, a))


def _lex_leaving(ties: np.ndarray, a: np.ndarray, F: _ProductFormBasis, prefer: int | None) -> int:
    """The lexicographically smallest tied row of B⁻¹[i] / a_i (z0's row if tied)."""
    if prefer is not None and prefer in ties:
        return int(prefer)
    n = a.size
    # in blocks, carrying the smallest row so far: memory LEX_BLOCK x n however
    # many rows tie (up to 381 of 2668 on the 667-contact granular LCP)
    best, best_row = None, None
    for start in range(0, ties.size, LEX_BLOCK):
        block = ties[start:start + LEX_BLOCK]
        V = np.empty((block.size + (best is not None), n))
        # the block's rows of B⁻¹ in one solve (a column each)
        E = np.zeros((n, block.size))
        E[block, np.arange(block.size)] = 1.0
        V[:block.size] = (F.solve_t(E) / a[block]).T
        candidates = block
        if best is not None:
            V[-1] = best_row
            candidates = np.append(block, best)
        k = lex_smallest(V)
        best, best_row = int(candidates[k]), V[k].copy()
    return best


def sparse_lemke(M, q: np.ndarray, d: np.ndarray, max_pivots: int, deadline=None
                 ) -> LemkeOutcome:
    """Lemke's method on (already scaled) sparse data with covering vector
    d > 0; see the module docstring.  Stops with status "time_limit" once
    ``deadline`` (a :class:`~qpcontact.core.deadline.Deadline`; None: never)
    has passed.  Raises
    SingularBasis when SuperLU finds a basis singular."""
    ratio_ties, scales_pivot = pivot_kernels().ratio_ties, pivot_kernels().scales_pivot
    n = q.size
    if np.all(q >= 0):
        return LemkeOutcome("solved", np.zeros(n), np.zeros(n, bool), 0)
    Z0 = 2 * n
    basis = np.arange(n)   # variable ids: w 0..n-1, z n..2n-1, z0 2n
    columns = sp.hstack([sp.identity(n, format="csc"), -sp.csc_matrix(M),
                         sp.csc_matrix(-np.asarray(d, dtype=float)[:, None])], format="csc")
    columns.sort_indices()
    indptr, indices, data = columns.indptr, columns.indices, columns.data
    F = _ProductFormBasis(columns, basis)
    x = np.array(q, dtype=float)
    # row 0: each basic value's rounding scale, (|B⁻¹||q|)_i for B = I, then
    # grown by the pivots' max rule (RowScales) and re-estimated at every
    # refactorization; row 1 is the kernel's basis-inverse scale, unused here
    scales = np.vstack([np.abs(x), np.ones(n)])
    ones = np.ones(n)
    rng = np.random.default_rng(0)

    def pivot(a, r, entering):
        nonlocal x
        t = x[r] / a[r]
        x -= t * a
        x[r] = t
        scales_pivot(scales, a, r)
        F.update(r, a)
        leaving = int(basis[r])
        basis[r] = entering
        return leaving

    # z0 enters at the value that makes q + d z0 >= 0; ties: the largest index,
    # the lexicographic minimum of (q_i, e_i) / d_i
    ratios = q / d
    theta = ratios.min()
    r = int(np.flatnonzero(ratios <= theta + 1e-12 * abs(theta))[-1])
    leaving = pivot(-np.asarray(d, dtype=float), r, Z0)
    z0_row = r
    pivots = 1
    while True:
        entering = leaving + n if leaving < n else leaving - n
        # the entering column read off the CSC arrays (scipy's column
        # slicing cost more than the solve)
        col = np.zeros(n)
        lo, hi = indptr[entering], indptr[entering + 1]
        col[indices[lo:hi]] = data[lo:hi]
        a = F.solve(col)   # raising it by t: x -= t a
        # candidates a_i > PIVOT_RTOL max|a|; ratios tie within their rows' rounding
        ties = ratio_ties(a, x, scales[0], ones, float(np.max(np.abs(a))), PIVOT_RTOL)
        if ties.size == 0:
            return ray_outcome(basis, x, a, entering, pivots)
        if pivots >= max_pivots:
            return LemkeOutcome("max_pivots", None, np.zeros(n, bool), pivots)
        if deadline is not None and deadline.expired():
            return LemkeOutcome("time_limit", None, np.zeros(n, bool), pivots)
        r = int(ties[0]) if ties.size == 1 else _lex_leaving(ties, a, F, z0_row)
        leaving = pivot(a, r, entering)
        pivots += 1
        if leaving == Z0:
            return _finish(columns, basis, q, n, pivots)
        if pivots % REFACTOR_EVERY == 0:
            # product-form updates drift; a feasible basis has x >= 0 exactly,
            # so negatives and values within rounding of zero become zeros
            F = _ProductFormBasis(columns, basis)
            x = F.solve(q)
            x[x < 1e-13 * scales[0]] = 0.0
            scales[0] = _rounding_scales(F, x, q, rng)


def _rounding_scales(F: _ProductFormBasis, x: np.ndarray, q: np.ndarray, rng) -> np.ndarray:
    """Estimates of (|B⁻¹||q|)_i, the size of the terms basic value i is made
    of: |x_i| and |B⁻¹(s ∘ |q|)|_i for two random sign vectors s — each the
    sum of the same terms with random signs, so of the size of their ℓ2 norm
    whatever cancels in x_i itself (two extra solves per refactorization)."""
    est = np.abs(x)
    for _ in range(2):
        est = np.maximum(est, np.abs(F.solve(np.abs(q) * rng.choice([-1.0, 1.0], q.size))))
    return est


def _finish(columns, basis, q, n, pivots) -> LemkeOutcome:
    """The complementary basis's values from a fresh factorization, refined
    twice against w - M z = q."""
    F = _ProductFormBasis(columns, basis)
    with warnings.catch_warnings():       # the residual's basis, made here only
        warnings.simplefilter("ignore", sp.SparseEfficiencyWarning)
        B = sp.csc_matrix(columns[:, basis])
    x = F.solve(q)
    for _ in range(2):
        x += F.solve(q - B @ x)
    is_z = basis >= n
    z = np.zeros(n)
    z[basis[is_z] - n] = np.maximum(x[is_z], 0.0)
    basic_z = np.zeros(n, bool)
    basic_z[basis[is_z] - n] = True
    return LemkeOutcome("solved", z, basic_z, pivots)
