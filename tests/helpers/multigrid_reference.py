"""The multigrid cycle as it was written in Python before it was compiled
(qpcontact.solvers.pivoting._mg_kernels.tnnmg_cycle): the reference the
compiled cycle is checked against, iterate by iterate — the same
arithmetic, NumPy and SciPy calls in place of the fused loops, its
Gauss–Seidel sweeps dividing by the diagonal (the compiled ones multiply by
its inverse).  The truncated products are the package's kernels, which
tests/solvers/test_multigrid.py checks against SciPy's products."""

from __future__ import annotations


import numpy as np
import scipy.linalg
import scipy.sparse as sp

from qpcontact.core.compiled import njit
from qpcontact.core.linalg import ActiveBlock
from qpcontact.solvers.pivoting import _mg_kernels as K
from qpcontact.solvers.pivoting.multigrid import DENSE_COARSEST, HELD_STOP

__all__ = ["Correction", "tnnmg", "nonzero_rows"]


@njit
def projected_gauss_seidel(indptr, indices, data, diag, q, z, sweeps):
    """``sweeps`` projected Gauss–Seidel sweeps for LCP(M, q), alternating
    forward and backward (a symmetric smoother), in place:
    z_i <- max(0, z_i − (M z + q)_i / M_ii).  M in CSR (symmetric)."""
    n = z.size
    for s in range(sweeps):
        for k in range(n):
            i = k if s % 2 == 0 else n - 1 - k
            r = q[i]
            for p in range(indptr[i], indptr[i + 1]):
                r += data[p] * z[indices[p]]
            v = z[i] - r / diag[i]
            z[i] = v if v > 0.0 else 0.0


@njit
def gauss_seidel(indptr, indices, data, diag, b, x, free, forward):
    """One Gauss–Seidel sweep for A x = b on the rows where ``free`` (the
    others keep their value, zero for a truncated correction), in place."""
    n = x.size
    for k in range(n):
        i = k if forward else n - 1 - k
        if free[i]:
            r = b[i]
            for p in range(indptr[i], indptr[i + 1]):
                r -= data[p] * x[indices[p]]
            x[i] += r / diag[i]


def nonzero_rows(d: np.ndarray) -> np.ndarray:
    """The rows of a truncated Galerkin operator (PSD: a zero diagonal entry
    means a zero row) that some unfrozen fine unknown still reaches."""
    return d > 1e-13 * max(d.max(initial=0.0), 1e-300)


class Coarsest:
    """A solver for the coarsest operator on its nonzero rows: dense
    Cholesky up to DENSE_COARSEST unknowns, a sparse LDLᵀ above (aggregation
    stops early on strongly diagonally dominant matrices, which have no
    strong connections to aggregate)."""

    def __init__(self, A, keep):
        d = A.diagonal()
        self.keep = np.flatnonzero(keep)
        self.c = self.pinv = self.block = None
        if self.keep.size > DENSE_COARSEST:
            A = sp.csc_matrix(A)
            try:
                self.block = ActiveBlock(A, keep, symmetric=True)
            except np.linalg.LinAlgError:   # dependent truncated functions: regularize
                A = (A + sp.diags(1e-10 * d)).tocsc()
                self.block = ActiveBlock(A, keep, symmetric=True)
            return
        B = A.toarray()[self.keep][:, self.keep]   # small: dense indexing beats sparse
        try:
            self.c = scipy.linalg.cho_factor(B, lower=True, check_finite=False)
        except np.linalg.LinAlgError:   # truncated coarse functions dependent
            self.pinv = np.linalg.pinv(B, hermitian=True)

    def solve(self, b):
        x = np.zeros_like(b)
        if self.keep.size:
            r = b[self.keep]
            if self.block is not None:
                x[self.keep] = self.block.factor_solve(r)
            elif self.c is not None:
                x[self.keep] = scipy.linalg.cho_solve(self.c, r, check_finite=False)
            else:
                x[self.keep] = self.pinv @ r
        return x


class Correction:
    """The truncated linear hierarchy of one level: V-cycles for
    (T M T) c = T r with T = diag(free), kept current as ``free`` moves
    (:meth:`update`).  ``patterns``: the coarse levels' untruncated Galerkin
    operators, whose patterns hold the truncated ones'."""

    def __init__(self, A, diag, prolongations, restrictions, free, patterns):
        self.fine, self.diag, self.free = A, diag, ~free
        self.P, self.R = prolongations, restrictions
        self.ops = []           # (A_k, diag_k, free_k) of the coarse levels
        self.diagonal = []      # where each coarse row's diagonal entry is stored
        for C in patterns:
            rows = np.repeat(np.arange(C.shape[0]), np.diff(C.indptr))
            self.diagonal.append(np.flatnonzero(C.indices == rows))
            C = sp.csr_matrix((np.zeros(C.nnz), C.indices, C.indptr), shape=C.shape)
            self.ops.append((C, None, np.zeros(C.shape[0], dtype=bool)))
        self.update(free)

    def update(self, free) -> bool:
        """Truncate at ``free``: only the coarse rows that the unknowns whose
        truncation changed reach are recomputed (:func:`._mg_kernels.touched_rows`),
        the same values a whole product gives, at a cost that follows the
        move (plate, n = 1e4: 0.1–0.4 ms for a move of 1–100 unknowns, a
        whole build 1.4–1.9 ms).  Returns whether anything moved."""
        changed = free != self.free
        if not changed.any():
            return False
        self.free = free.copy()
        B, keep = self.fine, self.free
        for k, (P, R) in enumerate(zip(self.P, self.R)):
            C, _, old_keep = self.ops[k]
            touched = K.touched_rows(B.indptr, B.indices, P.indptr, P.indices, changed,
                                     C.shape[0])
            rows = np.flatnonzero(touched)
            if rows.size == 0:
                return True     # nothing below this level moved
            K.galerkin_values(R.indptr, R.indices, R.data, B.indptr, B.indices, B.data,
                              P.indptr, P.indices, P.data, keep, C.indptr, C.indices, C.data,
                              rows)
            d = C.data[self.diagonal[k]]
            keep = nonzero_rows(d)
            changed = touched | (keep != old_keep)
            self.ops[k] = (C, np.where(keep, d, 1.0), keep)
            B = C
        self.coarsest = Coarsest(B, keep)
        return True

    def vcycle(self, b, visits=1):
        """One cycle for (T A T) c = T b: ``visits`` recursive calls of the
        level below on each level (1 a V-cycle, 2 a W-cycle), the textbook
        recursion the compiled loop (:func:`._mg_kernels.cycle`) unrolls."""
        return self._cycle(0, b, np.zeros_like(b), visits)

    def _cycle(self, k, b, x, visits):
        if k == len(self.P):
            return self.coarsest.solve(b)
        A, d, free = (self.fine, self.diag, self.free) if k == 0 else self.ops[k - 1]
        x = x.copy()
        gauss_seidel(A.indptr, A.indices, A.data, d, b, x, free, True)
        r = b - A @ x
        r[~free] = 0.0
        b_c = self.R[k] @ r
        y = np.zeros(b_c.size)
        for _ in range(visits if k + 1 < len(self.P) else 1):   # an exact solve once
            y = self._cycle(k + 1, b_c, y, visits)
        e = self.P[k] @ y
        e[~free] = 0.0
        x += e
        gauss_seidel(A.indptr, A.indices, A.data, d, b, x, free, False)
        return x


def residual(z, w, diag, q_scale) -> float:
    """max_i |min(M_ii z_i, w_i)| / ‖q‖∞: the natural map in w's units."""
    return float(np.max(np.abs(np.minimum(diag * z, w)), initial=0.0)) / q_scale


def tnnmg(A, q, prolongations, restrictions, patterns, z, cycles, tol, stats, progress, label,
          visits=1):
    """TNNMG cycles on LCP(A, q) (with at least one coarser level) from z
    (in place) until the contact set has held for two cycles with the
    natural-map residual at ``tol``, or for HELD_STOP cycles whatever the
    residual, or ``cycles`` cycles; ``visits`` 2: W-cycles."""
    d = A.diagonal()
    q_scale = max(float(np.max(np.abs(q), initial=0.0)), 1e-300)
    correction = None
    previous, held = None, 0
    n = q.size
    for cycle in range(cycles):
        projected_gauss_seidel(A.indptr, A.indices, A.data, d, q, z, 1)
        free = z > 0.0
        r = -(A @ z + q)
        if correction is None:
            correction = Correction(A, d, prolongations, restrictions, free, patterns)
            stats["mg_rebuilds"] += 1
        elif correction.update(free):
            stats["mg_rebuilds"] += 1
        c = correction.vcycle(np.where(free, r, 0.0), visits)
        c = np.maximum(c, -z)
        den = c @ (A @ c)
        alpha = (r @ c) / den if den > 0 else 0.0
        shrinking = c < 0
        if np.any(shrinking):
            alpha = min(alpha, float(np.min(z[shrinking] / -c[shrinking])))
        if alpha > 0:
            z += alpha * c
            np.maximum(z, 0.0, out=z)
        projected_gauss_seidel(A.indptr, A.indices, A.data, d, q, z, 2)
        active = z > 0.0
        changed = n if previous is None else int(np.count_nonzero(active != previous))
        held = held + 1 if changed == 0 else 0
        stats["mg_cycles"] += 1
        # the residual (a product with M) decides only once the set has held
        res = (residual(z, A @ z + q, d, q_scale) if held >= 2 or progress is not None
               else np.inf)
        if progress is not None:
            progress(f"mg-bpp: {label} cycle {cycle + 1}: residual {res:.1e}, "
                     f"{n - int(active.sum())} at the obstacle, {changed} changed")
        previous = active
        if (held >= 2 and res <= tol) or held >= HELD_STOP:
            break
    return z
