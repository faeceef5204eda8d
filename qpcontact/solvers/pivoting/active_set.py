"""What the pivoting methods share: scaling, sign tolerances, and the exact
solve of an active block with iterative refinement.

A pivoting method decides *which* variables are basic; the values are then
recomputed here from the original data (never read off a long chain of
Gauss–Jordan updates).  For a basis F (the z's that are basic, so w_F = 0):

    z_F = -M_FF^{-1} q_F,   z_N = 0,   w = M z + q.

M_FF is factorized once (dense Cholesky, sparse LDL' by QDLDL, or LU when M is
not symmetric) and the solution is refined against the unfactorized block
until the residual stops shrinking.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from scipy.linalg import lapack
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ...judge.certify import ComponentScales
from ._pivot_kernels import sure_negatives

__all__ = ["sign_tolerances", "negative_components", "ComponentScales", "SolutionOverflow",
           "overflow_result", "ActiveBlock", "symmetric_scaling", "dense_matrix",
           "check_options", "check_dense_size", "not_positive_definite", "refined", "int_option",
           "DENSE_TABLEAU_LIMIT", "BANDED_MAX", "ExchangeRule"]

_EPS = np.finfo(float).eps

#: Largest n for which the tableau methods ("energy", "lemke", "trace") build their
#: dense n x n (or n x 2n) tableau: 8 n^2 bytes is 200 MB at n = 5000.
DENSE_TABLEAU_LIMIT = 5000

#: Relative size below which a value counts as zero when deciding signs.
SIGN_RTOL = 1e3 * _EPS


class SolutionOverflow(ArithmeticError):
    """An active block was factorized but its solution does not fit in double
    precision (the data span too many orders of magnitude)."""


def overflow_result(method: str, exc: Exception):
    """The MethodResult of a method whose solution overflowed: no point, and a
    message that :func:`qpcontact.solve` completes with the data's range."""
    from ...core.results import MethodResult

    return MethodResult(x=None, backend_status="overflow",
                        backend_message=f"{method}: {exc}")


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


class ExchangeRule:
    """Kostreva's block exchange with the Júdice & Pires (1994) safeguard.

    Given the basis F (bool mask, changed in place) and the indices of its
    infeasible components, the whole infeasible set is exchanged while its
    size keeps reaching a new minimum; after ``patience`` exchanges without
    one, single pivots by Murty's least-index rule (finite for P-matrices)
    take over until the size drops again — so the iteration terminates for
    every SPD matrix, whatever basis it starts from.  ``stats`` counts the
    exchanges for the method's report.
    """

    def __init__(self, n: int, patience: int, stats: dict):
        self.best, self.patience, self.left = n + 1, patience, patience
        self.stats = stats
        for key in ("block_exchanges", "single_pivots", "exchanged"):
            stats.setdefault(key, 0)

    def step(self, F: np.ndarray, infeasible: np.ndarray) -> None:
        k = infeasible.size
        if k < self.best or self.left > 0:
            if k < self.best:
                self.best, self.left = k, self.patience
            else:
                self.left -= 1
            F[infeasible] = ~F[infeasible]
            self.stats["block_exchanges"] += 1
            self.stats["exchanged"] += k
        else:
            r = infeasible[0]
            F[r] = not F[r]
            self.stats["single_pivots"] += 1
            self.stats["exchanged"] += 1


def check_options(method: str, options: dict, allowed: tuple) -> None:
    """InvalidOptionError naming the options ``method`` does not take."""
    from ...core.errors import InvalidOptionError

    unknown = sorted(set(options) - set(allowed))
    if unknown:
        raise InvalidOptionError(f"{method!r} has no option(s) {unknown}; it takes {list(allowed)}")


def int_option(method: str, options: dict, name: str, default: int, minimum: int = 0) -> int:
    """options[name] as an int >= minimum (default when absent), or
    InvalidOptionError saying what was given and what is expected."""
    from ...core.errors import InvalidOptionError

    value = options.get(name, default)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer, float, np.floating)) \
            or not float(value).is_integer() or value < minimum:
        raise InvalidOptionError(
            f"{method!r}: option {name} must be an integer >= {minimum}; got {value!r}"
            + (" (leave it out for the default)" if value is None else "")
        )
    return int(value)


def check_dense_size(method: str, n: int, what: str, instead: str) -> None:
    """InvalidProblemError when a dense-tableau method meets n > DENSE_TABLEAU_LIMIT."""
    from ...core.errors import InvalidProblemError

    if n > DENSE_TABLEAU_LIMIT:
        raise InvalidProblemError(
            f"{method!r} keeps a dense {what}; above n = {DENSE_TABLEAU_LIMIT} use {instead}."
        )


def not_positive_definite(method: str, exc: Exception):
    """The NotConvexError an SPD method raises when a block fails to factorize."""
    from ...core.errors import NotConvexError

    return NotConvexError(
        f"{method!r} met an active block that is not numerically positive definite ({exc}); "
        "the matrix (M of an LCP, P of a QP) is too close to singular for it — use 'lemke' "
        "for an LCP, a QP backend ('clarabel', 'piqp') for a QP."
    )


def dense_matrix(M) -> np.ndarray:
    return M.toarray() if sp.issparse(M) else np.asarray(M, dtype=float)


def sign_tolerances(scales: ComponentScales, z: np.ndarray, q_terms: np.ndarray | None = None
                    ) -> tuple[np.ndarray, np.ndarray]:
    """(tau_z, tau_w): per-component magnitudes below which z_i or w_i counts as zero.

    SIGN_RTOL times the certificate's own scales at z (ζ_i for z_i, σ_i =
    |q_i| + (|M||z|)_i for w_i): each decision is made on the component's own
    size, so a gap of 5e11 at one contact does not make -0.09 look like zero at
    another (issue 14), and scaling M or q does not change any decision.
    """
    zeta, sigma = scales.at(z, q_terms)
    return SIGN_RTOL * zeta, SIGN_RTOL * sigma


def negative_components(scales: ComponentScales, values: np.ndarray, is_z: np.ndarray,
                        z: np.ndarray) -> np.ndarray:
    """Indices i with values_i < -tau_i, tau the per-component sign tolerances
    at the point z (ρ ζ_i where is_z, ρ σ_i elsewhere; see sign_tolerances).

    The exact scales cost a pass over |M| (O(n²) dense), which would double the
    cost of a dense pivot.  Cheap bounds decide almost every component:
    σ_i <= |q_i| + ‖M_i‖₁ ‖z‖∞ (+ ‖M_i‖₁ cap on idle rows, the floor) and
    ζ_i <= σ_i / |M_ii|, with 0 as the lower bound of both; the exact
    tolerances are computed only when some value falls between the two.
    """
    row_l1, inv_diag, cap_floor = scales.bound_data()
    surely, unsure = sure_negatives(np.asarray(values, dtype=float), np.asarray(is_z, dtype=bool),
                                    np.asarray(z, dtype=float), scales.q_terms, row_l1, inv_diag,
                                    cap_floor, SIGN_RTOL)
    if not unsure:
        return surely
    tau_z, tau_w = sign_tolerances(scales, z)
    return np.flatnonzero(values < -np.where(is_z, tau_z, tau_w))


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
    c, info = lapack.dpbtrf(ab_block, lower=0, overwrite_ab=1)
    if info != 0:
        raise np.linalg.LinAlgError(f"banded Cholesky: leading minor {info} is not positive")

    def solve(r):
        x, info = lapack.dpbtrs(c, r, lower=0)
        return x
    return solve


class ActiveBlock:
    """Factorization of M_FF for one basis F, with refined solves.

    ``symmetric`` selects Cholesky / LDL' (SPD blocks) over LU.  For sparse
    symmetric M, pass ``triu = sp.triu(M, format="csc")`` computed once: the
    upper triangle of M_FF is then sliced from it directly (what QDLDL takes).
    For banded M pass ``bands``, M's LAPACK upper band storage: the block's
    bands are gathered from it (:func:`sub_bands`) and factorized by LAPACK's
    banded Cholesky, which up to BANDED_MAX beats any general sparse ordering
    (a contact stack is banded).
    Raises ``np.linalg.LinAlgError`` when the block is numerically singular
    (or, for ``symmetric=True``, not positive definite).
    """

    def __init__(self, M, F: np.ndarray, *, symmetric: bool, triu=None, bands=None):
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

                    if triu is None:
                        triu = sp.triu(M, format="csc")
                    upper = triu[:, self.F][self.F, :]
                    try:
                        fac = qdldl.Solver(upper.tocsc(), upper=True)
                    except ValueError as exc:  # QDLDL reports a zero pivot this way
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

    def solve(self, rhs: np.ndarray, refine: int = 3) -> np.ndarray:
        """B^{-1} rhs, refined until the residual stops shrinking (at most ``refine`` times)."""
        return refined(self._solve, self.B, rhs, self._checked(self._solve(rhs)), refine)

    def basic_solution(self, M, q: np.ndarray, refine: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """(z, w) with z_F = -M_FF^{-1} q_F, z elsewhere 0, w = Mz + q.

        Refined against the full product M z (w_F is the residual), which the
        caller needs anyway: no copy of M_FF is formed.
        """
        n = q.size
        z = np.zeros(n)
        F = self.F
        if F.size == 0:
            return z, q.copy()
        z[F] = self._checked(self._solve(-q[F]))
        w = np.asarray(M @ z).ravel() + q
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
        w[F] = 0.0  # exactly zero by definition of the basis; keeps signs clean
        return z, w
