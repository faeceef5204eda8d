"""Basic solutions for a sequence of nearby bases: one factorization, reused.

Block pivoting solves M_FF z_F = −q_F for a basis F that changes by a few
components per exchange once it is close ("bpp" near the end, "mg-bpp"'s
finish from a multilevel guess).  Refactorizing for each costs a whole sparse
LDLᵀ per exchange.  When F differs from the last factorized basis F₀ by k
components, M_FF differs from the block matrix

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

__all__ = ["NearbyBases", "REUSE_MAX"]

#: A basis that differs from the factorized one by more than this many
#: components (or by more than 1/20 of its size) is factorized afresh: CG's
#: steps grow with the change, a factorization does not.
REUSE_MAX = 64

_EPS = np.finfo(float).eps


class NearbyBases:
    """Basic solutions (z, w) of LCP(M, q) for bases F, reusing the last
    factorization of M_FF for bases that differ from it by a few components.

    ``stats`` counts ``factorizations`` and ``krylov_solves`` / ``krylov_steps``.
    ``triu``, ``bands``: as for :class:`ActiveBlock`.  ``reuse=False``
    factorizes every basis (banded blocks: a banded Cholesky costs a few
    products with M, so there is nothing to save).
    """

    def __init__(self, M, q: np.ndarray, stats: dict, *, triu=None, bands=None, reuse=True):
        self.M, self.q, self.stats = M, q, stats
        self.triu, self.bands = triu, bands
        self.reuse = reuse
        self.diag = np.asarray(M.diagonal() if sp.issparse(M) else np.diag(M), dtype=float)
        self.absM = None
        self.block: ActiveBlock | None = None
        self.F0: np.ndarray | None = None
        self.z0: np.ndarray | None = None    # the factorized basis's solution
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
                return self.block.basic_solution(self.M, self.q, refine=refine, start=self.z0)
            if self.reuse and changed <= min(REUSE_MAX, max(1, F.size // 20)):
                z = self._krylov(F, changed)
                if z is not None:
                    w = np.asarray(self.M @ z).ravel() + self.q
                    w[F] = 0.0
                    self.krylov = (F.copy(), z, w)
                    return z.copy(), w.copy()
        self.block = ActiveBlock(self.M, F, symmetric=True, triu=self.triu, bands=self.bands)
        self.F0 = F.copy()
        self.stats["factorizations"] += 1
        z, w = self.block.basic_solution(self.M, self.q, refine=refine)
        self.z0 = z
        return z, w

    def _krylov(self, F: np.ndarray, changed: int) -> np.ndarray | None:
        """CG on M_FF z_F = −q_F preconditioned by the old factor, or None
        when it does not reach rounding level in 3 k + 20 steps."""
        M, q = self.M, self.q
        F0, solve0 = self.F0, self.block.factor_solve
        idx0 = self.block.F
        both = F & F0
        new = F & ~F0
        inv_new = 1.0 / self.diag[new]
        n = q.size

        def precondition(r):
            y = np.zeros(n)
            if idx0.size:
                t = np.where(both, r, 0.0)[idx0]
                y[idx0] = solve0(t)
                y[~both] = 0.0
            y[new] = r[new] * inv_new
            return y

        def apply(x):
            v = np.asarray(M @ x).ravel()
            v[~F] = 0.0
            return v

        if self.absM is None:
            self.absM = abs(M)
        x = np.zeros(n)
        r = np.where(F, -q, 0.0)
        scale = np.abs(q)       # the residual's own scale: |q| + |M||x| on F
        s = precondition(r)
        p = s.copy()
        rs = r @ s
        best = np.inf
        stalled = 0
        steps = 0
        for steps in range(1, 3 * changed + 21):
            Ap = apply(p)
            pAp = p @ Ap
            if not pAp > 0:
                return None
            a = rs / pAp
            x += a * p
            r -= a * Ap
            size = np.max((np.asarray(self.absM @ np.abs(x)).ravel() + scale)[F])
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
        self.stats["krylov_solves"] += 1
        self.stats["krylov_steps"] += steps
        # CG's recurred residual drifts from the true one: judge the true one
        size = np.max((np.asarray(self.absM @ np.abs(x)).ravel() + scale)[F])
        true = np.max(np.abs(np.asarray(M @ x).ravel() + q)[F])
        if not true <= 1e3 * _EPS * size:
            return None
        return x
