"""Dense and sparse linear algebra shared by the judge and the methods.

A pivoting method decides *which* variables are basic; the values are then
recomputed from the original data (never read off a long chain of
Gauss–Jordan updates).  For a basis F (the z's that are basic, so w_F = 0):

    z_F = -M_FF^{-1} q_F,   z_N = 0,   w = M z + q.

:class:`ActiveBlock` factorizes M_FF once (dense Cholesky, sparse LDL' by
QDLDL, LAPACK's banded Cholesky, or LU when M is not symmetric) and refines
the solution against the unfactorized block until the residual stops
shrinking.  The certificates use the same factorizations for their condition
estimates; the scalings (Jacobi's, Ruiz's) equilibrate data whose entries
span decades before anything is factorized.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

# scipy.linalg and scipy.sparse.linalg are imported where a block is factorized:
# they cost more than the rest of `import qpcontact` (tests/package/test_import_cost.py).

__all__ = ["ActiveBlock", "SolutionOverflow", "upper_block", "refined", "sub_bands",
           "symmetric_scaling", "ruiz_scaling", "dense_matrix", "BANDED_MAX"]

_EPS = np.finfo(float).eps


class SolutionOverflow(ArithmeticError):
    """An active block was factorized but its solution does not fit in double
    precision (the data span too many orders of magnitude)."""


def refined(solve, B, rhs: np.ndarray, x: np.ndarray, steps: int = 3) -> np.ndarray:
    """x (an approximate B^{-1} rhs from the factorization ``solve``) refined
    against B itself while the residual shrinks, at most ``steps`` times."""
    r = rhs - B @ x
    rn = np.max(np.abs(r)) if r.size else 0.0
    for _ in range(steps):
        if rn == 0.0:
            break
        x_new = x + solve(r)
        r_new = rhs - B @ x_new
        rn_new = np.max(np.abs(r_new))
        if not rn_new < rn:
            break
        x, r, rn = x_new, r_new, rn_new
    return x


def dense_matrix(M) -> np.ndarray:
    return M.toarray() if sp.issparse(M) else np.asarray(M, dtype=float)


def symmetric_scaling(M) -> np.ndarray:
    """d with d_i = 1/sqrt(M_ii): D M D has a unit diagonal.

    LCP(M, q) and LCP(DMD, Dq) have the same bases (z = D z', w' = D w), and the
    energy criterion q_i^2 / M_ii is invariant under it, so the pivot sequence is
    unchanged while badly scaled stiffness entries (1e7 next to 1) stop costing
    digits in the tableau.
    """
    diag = M.diagonal() if sp.issparse(M) else np.diag(M)
    diag = np.asarray(diag, dtype=float)
    d = np.ones_like(diag)
    pos = diag > 0
    d[pos] = 1.0 / np.sqrt(diag[pos])
    return d


def ruiz_scaling(M, iters: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Row and column factors r, c with r_i |M_ij| c_j near 1 in every row and column
    (M dense or SciPy sparse).

    Ones when every row and column maximum is already within a factor 4 of the
    largest (scaling would only cost time).
    """
    n = M.shape[0]
    r = np.ones(n)
    c = np.ones(n)
    A = abs(sp.csr_matrix(M)) if sp.issparse(M) else np.abs(M)

    def maxima(r, c):
        if sp.issparse(A):
            S = sp.diags(r) @ A @ sp.diags(c)
            return (S.max(axis=1).toarray().ravel(), S.max(axis=0).toarray().ravel())
        S = A * r[:, None] * c[None, :]
        return S.max(axis=1), S.max(axis=0)

    rm, cm = maxima(r, c)
    top = max(rm.max(), cm.max()) if n else 0.0
    if top > 0 and min(rm.min(), cm.min()) >= top / 4:
        return r, c
    for _ in range(iters):
        rm, cm = maxima(r, c)
        r /= np.sqrt(np.where(rm > 0, rm, 1.0))
        c /= np.sqrt(np.where(cm > 0, cm, 1.0))
    return r, c


#: Largest bandwidth for which banded LAPACK Cholesky (O(k b²)) is used for
#: sparse SPD blocks instead of QDLDL.  Measured on a tridiagonal 5e4 block:
#: 4.2 ms against 12.5 ms (docs/pivoting.md); at b = 32 the two are comparable.
BANDED_MAX = 16


def sub_bands(ab: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Upper band storage of the principal block M_FF (F sorted) from that of M.

    A principal block of a banded matrix is banded with no larger bandwidth b:
    entry (a - k, a) of the block is M[F[a-k], F[a]], nonzero only when
    F[a] - F[a-k] <= b.
    """
    b = ab.shape[0] - 1
    m = F.size
    out = np.zeros((b + 1, m))
    out[b] = ab[b, F]
    for k in range(1, min(b, m - 1) + 1):
        d = F[k:] - F[:-k]
        ok = d <= b
        cols = np.flatnonzero(ok) + k
        out[b - k, cols] = ab[b - d[ok], F[cols]]
    return out


def _banded_cholesky(ab_block: np.ndarray):
    from scipy.linalg import lapack

    c, info = lapack.dpbtrf(ab_block, lower=0, overwrite_ab=1)
    if info != 0:
        raise np.linalg.LinAlgError(f"banded Cholesky: leading minor {info} is not positive")

    def solve(r):
        x, info = lapack.dpbtrs(c, r, lower=0)
        return x
    return solve


def upper_block(M, F: np.ndarray) -> sp.csc_matrix:
    """The upper triangle of M_FF in CSC (M sparse; F the block's unknowns
    in M's order): what QDLDL factorizes.  Gathered from M's CSC arrays in
    one compiled pass where F is increasing (a bool mask's unknowns always
    are); a permuted block by SciPy's selections."""
    k = F.size
    if M.nnz >= 2 ** 31 or (k > 1 and not np.all(F[1:] > F[:-1])):
        return sp.triu(M, format="csc")[:, F][F, :].tocsc()
    if M.format != "csc":
        M = sp.csc_matrix(M)
    if not M.has_canonical_format:      # sorted, without duplicates: as triu makes it
        M = M.copy()
        M.sum_duplicates()
    from ._upper_kernels import upper_block as gather

    ptr, idx, val = gather(M.indptr, M.indices, M.data, F.astype(np.int64, copy=False),
                           M.shape[0])
    return sp.csc_matrix((val, idx, ptr), shape=(k, k))


class ActiveBlock:
    """Factorization of M_FF for one basis F, with refined solves.

    ``symmetric`` selects Cholesky / LDL' (SPD blocks) over LU.  For sparse
    symmetric M, QDLDL factorizes the upper triangle of M_FF, gathered from M
    in one pass (:func:`upper_block`).  For banded M pass ``bands``, M's
    LAPACK upper band storage: the block's bands are gathered from it
    (:func:`sub_bands`) and factorized by LAPACK's banded Cholesky, which up
    to BANDED_MAX beats any general sparse ordering (a contact stack is
    banded).
    Raises ``np.linalg.LinAlgError`` when the block is numerically singular
    (or, for ``symmetric=True``, not positive definite).
    """

    #: (z, w) of the last unrefined basic solution (``basic_solution(...,
    #: refine=0)``), before w_F was zeroed
    unrefined = None

    def __init__(self, M, F: np.ndarray, *, symmetric: bool, bands=None):
        import scipy.linalg
        import scipy.sparse.linalg as spla

        self.F = np.flatnonzero(F) if F.dtype == bool else np.asarray(F, dtype=np.intp)
        self.M = M
        self.symmetric = symmetric
        self._B = None
        k = self.F.size
        if k == 0:
            self._solve = lambda r: r
        elif sp.issparse(M):
            if symmetric:
                if bands is not None:
                    self._solve = _banded_cholesky(sub_bands(bands, self.F))
                else:
                    import qdldl

                    try:
                        fac = qdldl.Solver(upper_block(M, self.F), upper=True)
                    except (ValueError, RuntimeError) as exc:  # QDLDL's zero pivot
                        raise np.linalg.LinAlgError(str(exc)) from None
                    self._solve = fac.solve
            else:
                try:
                    lu = spla.splu(self.B)
                except RuntimeError as exc:
                    raise np.linalg.LinAlgError(str(exc)) from None
                self._solve = lu.solve
        else:
            B = self.B
            if symmetric:
                c = scipy.linalg.cho_factor(B, lower=True, check_finite=False)
                self._solve = lambda r: scipy.linalg.cho_solve(c, r, check_finite=False)
            else:
                lu = scipy.linalg.lu_factor(B, check_finite=False)
                if np.min(np.abs(np.diag(lu[0]))) <= _EPS * max(np.max(np.abs(B)), _EPS) * k:
                    raise np.linalg.LinAlgError("singular active block")
                self._solve = lambda r: scipy.linalg.lu_solve(lu, r, check_finite=False)

    @property
    def B(self):
        """M_FF itself (built on first use)."""
        if self._B is None:
            M, F = self.M, self.F
            self._B = M[F][:, F].tocsc() if sp.issparse(M) else M[np.ix_(F, F)]
        return self._B

    def _checked(self, x) -> np.ndarray:
        # The factorization succeeded (positive pivots, or an LU that passed its
        # singularity test), so an infinite entry is the solution overflowing.
        x = np.asarray(x, dtype=float)
        if not np.all(np.isfinite(x)):
            raise SolutionOverflow("the active block's solution has entries beyond 1.8e308")
        return x

    def factor_solve(self, rhs: np.ndarray) -> np.ndarray:
        """B^{-1} rhs from the factorization alone, unrefined (what a condition
        estimate's many solves need)."""
        return self._solve(rhs)

    def solve(self, rhs: np.ndarray, refine: int = 3) -> np.ndarray:
        """B^{-1} rhs, refined until the residual stops shrinking (at most ``refine`` times)."""
        return refined(self._solve, self.B, rhs, self._checked(self._solve(rhs)), refine)

    def basic_solution(self, M, q: np.ndarray, refine: int = 3,
                       start: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(z, w) with z_F = -M_FF^{-1} q_F, z elsewhere 0, w = Mz + q.

        Refined against the full product M z (w_F is the residual), which the
        caller needs anyway: no copy of M_FF is formed.  ``start``: the
        unrefined (z, w) of an earlier call with ``refine=0``
        (``self.unrefined``, its residual w_F kept), refined instead of
        solving and multiplying again.
        """
        n = q.size
        F = self.F
        if F.size == 0:
            return np.zeros(n), q.copy()
        if start is None:
            z = np.zeros(n)
            z[F] = self._checked(self._solve(-q[F]))
            w = np.asarray(M @ z).ravel() + q
        else:
            z, w = start[0].copy(), start[1].copy()
        rn = np.max(np.abs(w[F]))
        for _ in range(refine):
            if rn == 0.0:
                break
            z_new = z.copy()
            z_new[F] -= self._solve(w[F])
            w_new = np.asarray(M @ z_new).ravel() + q
            rn_new = np.max(np.abs(w_new[F]))
            if not rn_new < rn:
                break
            z, w, rn = z_new, w_new, rn_new
        if refine == 0:   # kept for a later call to refine (``start``)
            self.unrefined = (z, w.copy())
        w[F] = 0.0  # exactly zero by definition of the basis; keeps signs clean
        return z, w
