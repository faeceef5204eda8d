"""Multilevel search for the contact set of LCP(M, q), M sparse SPD: nested
truncated nonsmooth Newton multigrid (TNNMG).

The LCP is the bound-constrained QP min f(z) = ½ z'Mz + q'z, z >= 0.  A
hierarchy of prolongations P_l (given by the mesh, or built here by smoothed
aggregation) gives coarse problems min ½ y'(P'MP)y + (P'q)'y, y >= 0: with
nonnegative P (bilinear interpolation, aggregation smoothed on an M-matrix)
every coarse point is a fine feasible point, so they are the obstacle
problem on coarser grids.  Solved coarsest first, each level's answer
interpolated to the next as its start (nested iteration): the free boundary
then starts within a coarse cell of where it ends, instead of one grid line
per iteration from nothing — what makes plain block pivoting slow on meshes.

On each level, a TNNMG cycle (Gräser & Kornhuber 2009; Gräser, Sack, Sander
2009) is:

1. one projected Gauss–Seidel sweep (the nonsmooth smoother: it alone
   converges, and it puts every component it can at the obstacle);
2. truncation: components at the obstacle (z_i = 0) are frozen;
3. a linear correction c for the frozen-out (truncated) Newton system
   M_TT c_T = −(Mz + q)_T: one V-cycle whose coarse operators are the
   Galerkin products of the *truncated* prolongations, P'TMTP (kept current:
   the coarse rows the moved unknowns touch are recomputed each cycle);
4. projection onto the feasible set (c_i >= −z_i) and an exact line search
   for the quadratic along c, capped where a component would turn negative;
5. one projected Gauss–Seidel sweep (backwards).

Every step decreases f, so the iteration converges whatever the hierarchy;
the hierarchy decides only how fast.  The iterate is a guess: "mg-bpp"
hands its contact set to the exact block-pivoting finish.

References: Kornhuber, R. (1994), Monotone multigrid methods for elliptic
variational inequalities I, Numer. Math. 69, 167–184; Gräser, C., Kornhuber,
R. (2009), Multigrid methods for obstacle problems, J. Comput. Math. 27,
1–44; Vaněk, P., Mandel, J., Brezina, M. (1996), Algebraic multigrid by
smoothed aggregation, Computing 56, 179–196.
"""

from __future__ import annotations

import functools

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from ...core.linalg import ActiveBlock
from ...core.problems import LCP
from .bpp import block_pivoting

__all__ = ["aggregation_hierarchy", "multilevel_guess", "COARSEST_MAX"]


@functools.cache
def _kernels():
    """The compiled loops (:mod:`._mg_kernels`), imported on first use: numba
    costs 0.3 s to import, and a listing of the methods calls none of them."""
    from . import _mg_kernels

    return _mg_kernels


#: Aggregation stops at this many unknowns (the coarsest level is solved
#: directly: densely up to DENSE_COARSEST, sparse above).
COARSEST_MAX = 400

#: Above this many unknowns the coarsest level is factorized sparse.
DENSE_COARSEST = 800

#: Stop a level's cycles once its contact set has not changed for
#: this many cycles in a row, whatever the residual: on a plate (a 4th-order
#: operator) the truncated cycles converge slowly once the set is found
#: (n = 1e4, oblique stripes: the set held from cycle 28, the residual stayed
#: near 2e-4 of ‖q‖ to the 500-cycle limit, 2.1 s of a 2.3 s solve), and the
#: exact finish needs only the set.  A set held but wrong in a few
#: components costs the finish a few exchanges, never the answer.
HELD_STOP = 5

#: Strength threshold of the aggregation graph: |a_ij| >= θ sqrt(a_ii a_jj).
STRENGTH = 0.08


def _csr(A) -> sp.csr_matrix:
    A = sp.csr_matrix(A, dtype=float)
    A.sum_duplicates()
    return A


def aggregation_hierarchy(M) -> tuple:
    """Smoothed-aggregation prolongations for M (finest first): greedy
    aggregates of the strength graph, the piecewise-constant tentative
    prolongation T, smoothed once by damped Jacobi, P = (I − ω D⁻¹M) T with
    ω = 4/(3 ρ) and ρ Gershgorin's bound on D⁻¹M's spectrum.  On an M-matrix
    P >= 0.  Stops at COARSEST_MAX unknowns or when a level no longer
    coarsens (fewer than 2 fine unknowns per coarse one)."""
    A = _csr(M)
    out = []
    while A.shape[0] > COARSEST_MAX:
        n = A.shape[0]
        d = A.diagonal()
        if not np.all(d > 0):
            break
        agg, nc = _kernels().aggregate(A.indptr, A.indices, A.data, d, STRENGTH)
        if nc > n // 2 or nc == 0:
            break
        T = sp.csr_matrix((np.ones(n), (np.arange(n), agg)), shape=(n, nc))
        rho = float(np.max(abs(A) @ np.ones(n) / d))
        P = _csr(T - sp.diags((4.0 / (3.0 * rho)) / d) @ (A @ T))
        P.eliminate_zeros()
        out.append(P)
        A = _product(P.T.tocsr(), A, P, None)
    return tuple(out)


def _nonzero_rows(d: np.ndarray) -> np.ndarray:
    """The rows of a truncated Galerkin operator (PSD: a zero diagonal entry
    means a zero row) that some unfrozen fine unknown still reaches."""
    return d > 1e-13 * max(d.max(initial=0.0), 1e-300)


def _product(R, A, P, keep) -> sp.csr_matrix:
    """R diag(keep) A diag(keep) P (keep None: no truncation)."""
    if keep is None:
        keep = np.ones(A.shape[0], dtype=np.bool_)
    ptr, idx, val = _kernels().galerkin(R.indptr, R.indices, R.data, A.indptr, A.indices, A.data,
                             P.indptr, P.indices, P.data, keep, P.shape[1])
    return sp.csr_matrix((val, idx, ptr), shape=(P.shape[1], P.shape[1]))


class _Coarsest:
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


class _Correction:
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
        K = _kernels()
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
            keep = _nonzero_rows(d)
            changed = touched | (keep != old_keep)
            self.ops[k] = (C, np.where(keep, d, 1.0), keep)
            B = C
        self.coarsest = _Coarsest(B, keep)
        return True

    def vcycle(self, b):
        return self._cycle(0, b)

    def _cycle(self, k, b):
        if k == len(self.P):
            return self.coarsest.solve(b)
        A, d, free = (self.fine, self.diag, self.free) if k == 0 else self.ops[k - 1]
        x = np.zeros_like(b)
        _kernels().gauss_seidel(A.indptr, A.indices, A.data, d, b, x, free, True)
        r = b - A @ x
        r[~free] = 0.0
        e = self.P[k] @ self._cycle(k + 1, self.R[k] @ r)
        e[~free] = 0.0
        x += e
        _kernels().gauss_seidel(A.indptr, A.indices, A.data, d, b, x, free, False)
        return x


def _residual(z, w, diag, q_scale) -> float:
    """max_i |min(M_ii z_i, w_i)| / ‖q‖∞: the natural map in w's units."""
    return float(np.max(np.abs(np.minimum(diag * z, w)), initial=0.0)) / q_scale


def _tnnmg(A, q, prolongations, restrictions, patterns, z, cycles, tol, stats, progress, label):
    """TNNMG cycles on LCP(A, q) (with at least one coarser level) from z
    (in place) until the contact set has held for two cycles with the
    natural-map residual at ``tol``, or for HELD_STOP cycles whatever the
    residual, or ``cycles`` cycles."""
    d = A.diagonal()
    q_scale = max(float(np.max(np.abs(q), initial=0.0)), 1e-300)
    correction = None
    previous, held = None, 0
    n = q.size
    for cycle in range(cycles):
        _kernels().projected_gauss_seidel(A.indptr, A.indices, A.data, d, q, z, 1)
        free = z > 0.0
        r = -(A @ z + q)
        if correction is None:
            correction = _Correction(A, d, prolongations, restrictions, free, patterns)
            stats["mg_rebuilds"] += 1
        elif correction.update(free):
            stats["mg_rebuilds"] += 1
        c = correction.vcycle(np.where(free, r, 0.0))
        c = np.maximum(c, -z)
        den = c @ (A @ c)
        alpha = (r @ c) / den if den > 0 else 0.0
        shrinking = c < 0
        if np.any(shrinking):
            alpha = min(alpha, float(np.min(z[shrinking] / -c[shrinking])))
        if alpha > 0:
            z += alpha * c
            np.maximum(z, 0.0, out=z)
        _kernels().projected_gauss_seidel(A.indptr, A.indices, A.data, d, q, z, 2)
        active = z > 0.0
        changed = n if previous is None else int(np.count_nonzero(active != previous))
        held = held + 1 if changed == 0 else 0
        stats["mg_cycles"] += 1
        # the residual (a product with M) decides only once the set has held
        res = (_residual(z, A @ z + q, d, q_scale) if held >= 2 or progress is not None
               else np.inf)
        if progress is not None:
            progress(f"mg-bpp: {label} cycle {cycle + 1}: residual {res:.1e}, "
                     f"{n - int(active.sum())} at the obstacle, {changed} changed")
        previous = active
        if (held >= 2 and res <= tol) or held >= HELD_STOP:
            break
    return z


def _coincident(P) -> np.ndarray:
    """For each coarse unknown, the fine unknown it weighs most (a grid's
    coarse node's own fine node, weight 1): where a coarse level reads a
    fine vector by injection."""
    C = sp.csc_matrix(P)
    column = np.repeat(np.arange(C.shape[1]), np.diff(C.indptr))
    top = np.flatnonzero(C.data == np.maximum.reduceat(C.data, C.indptr[:-1])[column])
    _, first = np.unique(column[top], return_index=True)
    return C.indices[top[first]]


def _unconstrained_gap(M, q) -> np.ndarray | None:
    """z_u = −M⁻¹q, the gap with no contact (one LDLᵀ of M), or None when M
    does not factorize."""
    try:
        return ActiveBlock(M, np.ones(q.size, dtype=bool), symmetric=True).factor_solve(-q)
    except np.linalg.LinAlgError:
        return None


def multilevel_guess(M, q, prolongations, *, cycles: int, tol: float = 1e-8, stats: dict,
                     progress=None, shifted: bool = False) -> np.ndarray:
    """The nested TNNMG iterate for LCP(M, q) on the hierarchy
    ``prolongations`` (finest first; may be empty): coarsest level solved
    exactly by block pivoting, then on each finer level up to ``cycles``
    cycles, ended by the same rule (``tol`` on the finest, 1e-3 on the
    others).

    ``shifted``: the coarse levels approximate d = z − z_u, z_u = −M⁻¹q the
    gap with no contact, instead of z.  Md = Mz + q is the contact force
    and d vanishes where the structure is held (a plate's edge), so d is as
    smooth as the deflection, while z = u − ψ carries the obstacle's values
    up to the boundary: a layer bilinear coarse functions cannot represent,
    which on a plate (energy ~ h⁻⁴ per unit of misfit) distorts every coarse
    answer (plate D = 1, dome, n = 1e5: no coarse answer touched the
    obstacle).  Level l solves LCP(A_l, −A_l s_l) for e_l = d_l + s_l, s_l
    the injection of z_u (:func:`_coincident`); up a level,
    e = P(e_c − s_c) + s; on the finest level e = z."""
    stats.setdefault("mg_cycles", 0)
    stats.setdefault("mg_rebuilds", 0)
    As, qs = [_csr(M)], [np.asarray(q, dtype=float)]
    Rs = [P.T.tocsr() for P in prolongations]
    for P, R in zip(prolongations, Rs):
        As.append(_product(R, As[-1], P, None))
        qs.append(R @ qs[-1])
    L = len(prolongations)
    stats["mg_levels"] = L + 1
    shift = _unconstrained_gap(M, qs[0]) if shifted and L else None
    stats["shifted"] = shift is not None
    shifts = [np.zeros(q.size) for q in qs]
    if shift is not None:
        shifts[0] = shift
        for l, P in enumerate(prolongations, start=1):
            shifts[l] = shifts[l - 1][_coincident(P)]
            qs[l] = -(As[l] @ shifts[l])
    coarse = LCP(As[L].toarray() if qs[L].size <= DENSE_COARSEST else As[L].tocsc(), qs[L])
    coarse.structure.declare_spd()
    try:
        z, _, _, _ = block_pivoting(coarse, np.zeros(qs[L].size, bool), 10 * qs[L].size + 100, 3)
    except np.linalg.LinAlgError:   # dependent coarse functions: start from nothing
        z = np.zeros(qs[L].size)
    for l in range(L - 1, -1, -1):
        z = np.maximum(prolongations[l] @ (z - shifts[l + 1]) + shifts[l], 0.0)
        finest = l == 0
        z = _tnnmg(As[l], qs[l], prolongations[l:], Rs[l:], As[l + 1:], z, cycles,
                   tol if finest else 1e-3, stats, progress if finest else None,
                   "level 0" if finest else f"level {l}")
    return z
