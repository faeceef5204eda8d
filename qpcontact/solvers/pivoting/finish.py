"""Basic solutions for a sequence of nearby bases: one factorization, reused.

Block pivoting solves M_FF z_F = −q_F for a basis F that changes by a few
components per exchange once it is close ("bpp" near the end, "mg-bpp"'s
finish from a multilevel guess).  Refactorizing for each costs a whole sparse
LDLᵀ per exchange.  When F differs from the last factorized basis F₀ by k
components (k <= 64 and k <= n/200: :func:`reusable`), M_FF z_F = −q_F is
solved on M_F₀F₀'s factor bordered by those k components
(:meth:`NearbyBases._bordered`): an unknown added to F₀ brings its column of
M, one removed is held at zero by a multiplier, and the k x k Schur
complement of the bordered matrix takes one solve with the factor per
border column (kept while the factor is).  A basic solution is then one
solve with the factor and one with the small complement, refined against M
itself as a factorized block is; if it does not reach rounding level the
basis is factorized instead.

Conjugate gradients preconditioned with the old factor did this job before
(:func:`preconditioned_cg`, which "ip-bpp" still uses on its own bases):
about 2k + 1 steps of a solve and a product each against the border's k
solves, and it gave up more often where k neared the limit (a 150 x 150
plate's finish from a held set 7 components off: 85 exchanges, 35
factorizations with CG, 12 bordered; docs/dev-notes.md).

Both routes return the basic solution recomputed from the data, as
:meth:`qpcontact.core.linalg.ActiveBlock.basic_solution` does.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from ...core.linalg import ActiveBlock

__all__ = ["NearbyBases", "reusable", "preconditioned_cg", "restricted_preconditioner"]

_EPS = np.finfo(float).eps

#: A basis that differs from the factorized one by more than this many
#: components, or by more than n / REUSE_SHARE, is factorized afresh: the
#: solves grow with the change, a factorization does not, and on small blocks
#: a factorization is cheap (measured for CG, which takes about twice the
#: border's solves: plate, n = 900: CG at k <= n/20 cost 1.7 x
#: refactorizing; n = 3600: 0.7 x).
REUSE_MAX = 64
REUSE_SHARE = 200

#: At most this many entries (k columns of the factorized block's size) in a
#: border: 256 MB.  Beyond (k near REUSE_MAX on a block of millions) the
#: basis is factorized: there the border's k solves cost about as much.
BORDER_ENTRIES = 2 ** 25


def reusable(changed: int, n: int) -> bool:
    """Whether a basis ``changed`` components from the factorized one (of
    n unknowns) is solved on the old factor rather than refactorized."""
    return 0 < changed <= min(REUSE_MAX, n // REUSE_SHARE)


class NearbyBases:
    """Basic solutions (z, w) of LCP(M, q) for bases F, reusing the last
    factorization of M_FF for bases that differ from it by a few components
    (:meth:`_bordered`).

    ``stats`` counts ``factorizations``, ``bordered_solves`` (bases solved on
    an older factor) and ``border_columns`` (the factor's solves their
    borders took).  ``bands``: as for :class:`ActiveBlock`.  ``reuse=False``
    factorizes every basis (banded blocks: a banded Cholesky costs a few
    products with M, so there is nothing to save).  ``absM``: |M| where the
    caller has it (the problem's structure keeps one; formed here on the
    first bordered solve otherwise: 1 ms of a 10⁵ membrane's finish).
    """

    def __init__(self, M, q: np.ndarray, stats: dict, *, bands=None, reuse=True, absM=None):
        self.M, self.q, self.stats = M, q, stats
        self.bands = bands
        self.reuse = reuse
        self.absM = absM
        self.block: ActiveBlock | None = None
        self.F0: np.ndarray | None = None
        self.border = np.zeros(0, dtype=np.intp)   # the unknowns bordering the factor,
        self.W = None                              # and M_F0F0⁻¹ of their columns
        self.nearby = None                   # (F, z, w) of the last bordered solve
        stats.setdefault("factorizations", 0)
        stats.setdefault("bordered_solves", 0)
        stats.setdefault("border_columns", 0)

    def basic_solution(self, F: np.ndarray, refine: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """(z, w): z_F = −M_FF⁻¹ q_F, z = 0 elsewhere, w = M z + q (w_F = 0).

        ``refine`` > 0 asks for a solution refined to rounding level (the
        basis that looks final); 0 for one whose signs are all that matters."""
        if self.nearby is not None and np.array_equal(F, self.nearby[0]):
            return self.nearby[1].copy(), self.nearby[2].copy()   # already at rounding level
        if self.block is not None:
            changed = int(np.count_nonzero(F != self.F0))
            if changed == 0:   # the same basis, now to be refined
                return self.block.basic_solution(self.M, self.q, refine=refine,
                                                 start=self.block.unrefined)
            if self.reuse and reusable(changed, F.size):
                zw = self._bordered(F)
                if zw is not None:
                    self.nearby = (F.copy(), *zw)
                    return zw[0].copy(), zw[1].copy()
        self.block = ActiveBlock(self.M, F, symmetric=True, bands=self.bands)
        self.F0 = F.copy()
        self.border, self.W = np.zeros(0, dtype=np.intp), None
        self.stats["factorizations"] += 1
        return self.block.basic_solution(self.M, self.q, refine=refine)

    def _bordered(self, F: np.ndarray):
        """(z, w) for the basis F on the factor of M_F0F0 (F₀ = ``self.F0``),
        refined to rounding level, or None where it does not get there (the
        caller then factorizes).  The unknowns added to F₀ border the
        factorized block with their columns of M; those removed are held at
        zero by a multiplier each (their rows of M_F0F0 then hold whatever
        that multiplier takes up):

            [ M_00    M_0A   E ] [z_0]   [r_0]
            [ M_A0    M_AA   0 ] [z_A] = [r_A]
            [ E'      0      0 ] [ λ ]   [ 0 ]

        (E the unit columns of the removed unknowns).  With W = M_00⁻¹ [M_0A E]
        (a solve per border column, kept for the next basis on this factor)
        and the k x k
        Schur complement S = [M_AA 0; 0 0] − [M_0A E]' W, a solve is one
        solve with the factor and one with S: y = M_00⁻¹ r_0,
        (z_A, λ) = S⁻¹([r_A; 0] − [M_0A E]' y), z_0 = y − W (z_A, λ); S is
        nonsingular where M_FF is.  Refined against M itself, as a
        factorized block is."""
        M, q, idx0 = self.M, self.q, self.block.F
        if not F.any():             # every unknown left the basis: z = 0, w = q exactly
            return np.zeros(q.size), np.array(q, dtype=float)
        added = np.flatnonzero(F & ~self.F0)
        removed = np.flatnonzero(self.F0 & ~F)
        border = np.concatenate([added, removed])
        if border.size * idx0.size > BORDER_ENTRIES:
            return None
        where = np.cumsum(self.F0) - 1               # each unknown of F₀: its place in idx0
        at_removed = where[removed]
        if sp.issparse(M):
            M_A = sp.csc_matrix(M[:, added])
            M_AA, M_0A = M_A[added].toarray(), M_A[idx0]
        else:
            M_A = np.asarray(M)[:, added]
            M_AA, M_0A = M_A[added], M_A[idx0]
        kept = dict(zip(self.border.tolist(), range(self.border.size)))
        W = np.empty((idx0.size, border.size))
        for c, j in enumerate(border.tolist()):
            if j in kept:
                W[:, c] = self.W[:, kept[j]]
                continue
            if c < added.size:                       # a new border column: one solve
                column = M_0A[:, [c]]
                column = column.toarray().ravel() if sp.issparse(column) else column.ravel()
            else:
                column = np.zeros(idx0.size)
                column[where[j]] = 1.0
            W[:, c] = self.block.factor_solve(column)
            self.stats["border_columns"] += 1
        self.border, self.W = border, W
        a = added.size
        S = -np.vstack([np.asarray(M_0A.T @ W), W[at_removed]])
        S[:a, :a] += M_AA
        with warnings.catch_warnings():     # a singular S ends in the finiteness test below
            warnings.simplefilter("ignore")
            try:
                lu = scipy.linalg.lu_factor(S)
            except (ValueError, np.linalg.LinAlgError):
                return None

        def solve(r_0, r_A):
            y = self.block.factor_solve(r_0)
            u = scipy.linalg.lu_solve(lu, np.concatenate([r_A - np.asarray(M_0A.T @ y).ravel(),
                                                          -y[at_removed]]), check_finite=False)
            return y - W @ u, u[:a]

        n = q.size
        z = np.zeros(n)
        z[idx0], z[added] = solve(-q[idx0], -q[added])
        z[removed] = 0.0
        w = np.asarray(M @ z).ravel() + q
        rn = np.max(np.abs(w[F]))
        for _ in range(3):          # refined while the residual shrinks, as a factorized block is
            if not rn > 0.0:
                break
            z_new = z.copy()
            d_0, d_A = solve(-w[idx0], -w[added])
            z_new[idx0] += d_0
            z_new[added] += d_A
            z_new[removed] = 0.0
            w_new = np.asarray(M @ z_new).ravel() + q
            rn_new = np.max(np.abs(w_new[F]))
            if not rn_new < rn:
                break
            z, w, rn = z_new, w_new, rn_new
        self.stats["bordered_solves"] += 1
        if self.absM is None:
            self.absM = abs(M)
        size = np.max((np.asarray(self.absM @ np.abs(z)).ravel() + np.abs(q))[F])
        if not (np.all(np.isfinite(z)) and rn <= 1e3 * _EPS * size):
            return None
        w[F] = 0.0
        return z, w


def restricted_preconditioner(solve0, idx0: np.ndarray, F0: np.ndarray, F: np.ndarray,
                              diag: np.ndarray):
    """r ↦ y on F: the factorized block's solve (of M_F₀F₀, on the indices
    ``idx0`` of F₀) restricted to F ∩ F₀, and diag(M)⁻¹ on F ∖ F₀ — SPD, and
    within rank 2k + |F₀∖F| of M_FF⁻¹ when F and F₀ differ by k components."""
    both = F & F0
    new = F & ~F0
    inv_new = 1.0 / diag[new]
    n = F.size

    def precondition(r):
        y = np.zeros(n)
        if idx0.size:
            y[idx0] = solve0(np.where(both, r, 0.0)[idx0])
            y[~both] = 0.0
        y[new] = r[new] * inv_new
        return y
    return precondition


def preconditioned_cg(A, absA, F: np.ndarray, b: np.ndarray, precondition, max_steps: int):
    """(x, steps): x with A_FF x_F = b_F (zero off F) to rounding level —
    max|A x − b| on F at most 10³ eps × max(|A||x| + |b|) on F, the rows' own
    terms — by CG, or (None, steps) when it does not get there in
    ``max_steps`` steps (the caller then factorizes).  The iteration stops
    when its residual is at 4 eps of that scale or has stopped halving for
    three steps; the true residual, not CG's recurred one, is judged."""
    n = b.size
    x = np.zeros(n)
    r = np.where(F, b, 0.0)
    scale = np.abs(r)
    s = precondition(r)
    p = s.copy()
    rs = r @ s
    best, stalled, steps, rn = np.inf, 0, 0, np.inf
    for steps in range(1, max_steps + 1):
        Ap = np.asarray(A @ p).ravel()
        Ap[~F] = 0.0
        pAp = p @ Ap
        if not pAp > 0:
            return None, steps
        a = rs / pAp
        x += a * p
        r -= a * Ap
        size = np.max((np.asarray(absA @ np.abs(x)).ravel() + scale)[F])
        rn = np.max(np.abs(r[F])) / size if size > 0 else 0.0
        if rn <= 4 * _EPS:
            break
        stalled = stalled + 1 if rn >= 0.5 * best else 0
        best = min(best, rn)
        if stalled >= 3:
            break
        s = precondition(r)
        rs_new = r @ s
        p = s + (rs_new / rs) * p
        rs = rs_new
    size = np.max((np.asarray(absA @ np.abs(x)).ravel() + scale)[F])
    true = np.max(np.abs(np.asarray(A @ x).ravel() - b)[F])
    if not true <= 1e3 * _EPS * size:
        return None, steps
    return x, steps
