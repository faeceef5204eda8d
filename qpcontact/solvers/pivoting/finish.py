"""Basic solutions for a sequence of nearby bases: one factorization, reused.

Block pivoting solves M_FF z_F = −q_F for a basis F that changes by a few
components per exchange once it is close ("bpp" near the end, "mg-bpp"'s
finish from a multilevel guess).  Refactorizing for each costs a whole sparse
LDLᵀ per exchange.  When F differs from the last factorized basis F₀ by k
components (k <= 64 and k <= n/200: :func:`reusable`), M_FF differs from the block matrix

    [ M_{F∩F₀} (preconditioned by M_F₀F₀⁻¹ restricted to F∩F₀)     0      ]
    [                  0                                    diag(M)_{F∖F₀} ]

by a matrix of rank at most 2k + |F₀∖F|, so conjugate gradients
preconditioned by the old factor converge in about that many steps (exact
arithmetic; the restriction of an SPD inverse to a principal block is SPD, so
the preconditioner is).  Each step is one product with M and one solve with
the old factor: much cheaper than a new factorization when k is small.  The
iteration runs until its residual stops shrinking (it then sits at rounding
level: the same accuracy as a refined direct solve); if it has not reached
rounding level within 3k + 20 steps the basis is factorized instead.

Both routes return the basic solution recomputed from the data, as
:meth:`qpcontact.core.linalg.ActiveBlock.basic_solution` does.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ...core.linalg import ActiveBlock

__all__ = ["NearbyBases", "reusable", "preconditioned_cg", "restricted_preconditioner"]

_EPS = np.finfo(float).eps

#: A basis that differs from the factorized one by more than this many
#: components, or by more than n / REUSE_SHARE, is factorized afresh: CG's
#: steps grow with the change (about 2k + 1), a factorization does not, and on
#: small blocks a factorization is cheap (plate, n = 900: CG at k <= n/20
#: cost 1.7 x refactorizing; n = 3600: 0.7 x).
REUSE_MAX = 64
REUSE_SHARE = 200


def reusable(changed: int, n: int) -> bool:
    """Whether a basis ``changed`` components from the factorized one (of
    n unknowns) is solved by CG on the old factor rather than refactorized."""
    return 0 < changed <= min(REUSE_MAX, n // REUSE_SHARE)


class NearbyBases:
    """Basic solutions (z, w) of LCP(M, q) for bases F, reusing the last
    factorization of M_FF for bases that differ from it by a few components.

    ``stats`` counts ``factorizations`` and ``krylov_solves`` / ``krylov_steps``.
    ``bands``: as for :class:`ActiveBlock`.  ``reuse=False``
    factorizes every basis (banded blocks: a banded Cholesky costs a few
    products with M, so there is nothing to save).
    """

    def __init__(self, M, q: np.ndarray, stats: dict, *, bands=None, reuse=True):
        self.M, self.q, self.stats = M, q, stats
        self.bands = bands
        self.reuse = reuse
        self.diag = np.asarray(M.diagonal() if sp.issparse(M) else np.diag(M), dtype=float)
        self.absM = None
        self.block: ActiveBlock | None = None
        self.F0: np.ndarray | None = None
        self.krylov = None                   # (F, z, w) of the last CG solve
        stats.setdefault("factorizations", 0)
        stats.setdefault("krylov_solves", 0)
        stats.setdefault("krylov_steps", 0)

    def basic_solution(self, F: np.ndarray, refine: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """(z, w): z_F = −M_FF⁻¹ q_F, z = 0 elsewhere, w = M z + q (w_F = 0).

        ``refine`` > 0 asks for a solution refined to rounding level (the
        basis that looks final); 0 for one whose signs are all that matters."""
        if self.krylov is not None and np.array_equal(F, self.krylov[0]):
            return self.krylov[1].copy(), self.krylov[2].copy()   # already at rounding level
        if self.block is not None:
            changed = int(np.count_nonzero(F != self.F0))
            if changed == 0:   # the same basis, now to be refined
                return self.block.basic_solution(self.M, self.q, refine=refine,
                                                 start=self.block.unrefined)
            if self.reuse and reusable(changed, F.size):
                z = self._krylov(F, changed)
                if z is not None:
                    w = np.asarray(self.M @ z).ravel() + self.q
                    w[F] = 0.0
                    self.krylov = (F.copy(), z, w)
                    return z.copy(), w.copy()
        self.block = ActiveBlock(self.M, F, symmetric=True, bands=self.bands)
        self.F0 = F.copy()
        self.stats["factorizations"] += 1
        return self.block.basic_solution(self.M, self.q, refine=refine)

    def _krylov(self, F: np.ndarray, changed: int) -> np.ndarray | None:
        """CG on M_FF z_F = −q_F preconditioned by the old factor, or None
        when it does not reach rounding level in 3 k + 20 steps."""
        if self.absM is None:
            self.absM = abs(self.M)
        precondition = restricted_preconditioner(self.block.factor_solve, self.block.F, self.F0,
                                                 F, self.diag)
        x, steps = preconditioned_cg(self.M, self.absM, F, np.where(F, -self.q, 0.0),
                                     precondition, 3 * changed + 20)
        self.stats["krylov_solves"] += 1
        self.stats["krylov_steps"] += steps
        return x


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
