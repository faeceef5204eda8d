"""Certificates: residuals computed from the problem data and a candidate point.

Nothing a backend reports about its own answer is used here.  Every method's
answer goes through :func:`certify`, the shared error measure (in the spirit of
Siconos' ``lcp_compute_error``), so numbers mean the same for every method.
docs/certificates.md gives the definitions with their reasons and the
far-contact example that made them componentwise.

LCP (z, w = Mz + q): the componentwise error
---------------------------------------------
Each row is judged against its own data, in the sense of Oettli and Prager:

    σ_i = |q_i| + (|M| |z|)_i          the size of the terms w_i is made of
    c_i = max_j |M_ji| / σ_j           how strongly z_i moves any w_j, relative
                                       to that w_j's own size
    ζ_i = min(1 / c_i, ζ)              z_i's own scale, capped by the normwise
                                       ζ = max(‖z‖∞, ‖q‖∞ / max|M_ij|)
    error = max_i |min(z_i / ζ_i, w_i / σ_i)|

``error <= ε`` says: moving each z_i by at most ε ζ_i and each entry of M and q
by at most ε of its own size (to first order, up to a factor of the row's
nonzero count) makes z an exact solution.  A gap of 5e11 at a far contact
cannot hide an error at a contact whose gap is 0.1, because no row borrows
another row's size.  The error is invariant under row and column scaling of
the data (D_r M D_c, D_r q; z -> D_c⁻¹ z) except through the cap, and lies
in [0, 1]: 1 means a component is wrong by all of its own size.

Reported beside it: ``normwise_error`` (the former scale-free measure,
max_i |min(z_i/‖·‖, w_i/max(‖Mz‖∞, ‖q‖∞))|), ``comp_abs = ‖min(z, w)‖∞``,
``siconos_error = ‖min(z, w)‖₂ / ‖q‖₂`` (Siconos' relative form),
``min_z``, ``min_w``, ``zw = z'w``, the ``worst_index`` and ``overflow``
(a product |M_ij z_j| beyond double precision: nothing can be certified).

QP (qpsolvers.Problem: min ½x'Px + q'x, Gx <= h, Ax = b, lb <= x <= ub)
-------------------------------------------------------------------------
The same construction for every KKT condition, each row against its own terms:
stationarity row k against S_k = (|P||x|)_k + |q_k| + (|G'||z|)_k + (|A'||y|)_k;
inequality row i's slack against T_i = |h_i| + (|G||x|)_i; equality row i
against |b_i| + (|A||x|)_i; a bound's slack against |bound_k| + ξ_k, with
ξ_k x_k's own scale (as ζ_i above, from the rows x_k enters); each
multiplier against the stationarity rows it enters.  Complementarity is
judged pair by pair (|min(multiplier/scale, slack/scale)|, negative values
included) and a bound multiplier claiming a bound that does not exist counts
in full.  For the QP of a symmetric LCP with z_box = -w the two certificates
coincide.  ``primal_residual``, ``dual_residual`` and ``duality_gap`` are
qpsolvers' own definitions, kept for comparison with published figures.
"""

from __future__ import annotations

import warnings
from dataclasses import asdict, dataclass, field, fields

import numpy as np
import scipy.linalg
import scipy.sparse as sp
from qpsolvers import Problem
from qpsolvers import Solution as _QPSolution

from ..core.errors import InvalidProblemError
from ..core.problems import LCP

__all__ = ["certify", "LCPCertificate", "QPCertificate", "ComponentScales", "row_scales",
           "column_influence"]

_EPS = np.finfo(float).eps
_DENSE_CHUNK = 1 << 22  # entries of |M| / σ formed at a time for dense matrices


def _ratio(num: float, den: float) -> float:
    """num / den, with 0/0 = 0 and x/0 = inf."""
    if num == 0.0:
        return 0.0
    return num / den if den > 0.0 else np.inf


def _divide(v: np.ndarray, scale) -> np.ndarray:
    """v / scale elementwise (scale a number or an array), with 0/0 = 0 and
    x/0 = ±inf: a component whose scale is zero must itself be exactly zero."""
    v = np.asarray(v, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        out = v / scale
    nan = np.isnan(out)
    if nan.any():
        # 0/0 is a component that is exactly zero at a zero scale: no error
        out[nan & np.broadcast_to(v == 0, out.shape)] = 0.0
    return out


def _inf_norm(v) -> float:
    return float(np.max(np.abs(v))) if np.size(v) else 0.0


def _max_abs(M) -> float:
    if sp.issparse(M):
        return float(abs(M).max()) if M.nnz else 0.0
    return float(np.max(np.abs(M))) if M.size else 0.0


def _abs_matvec(M, v) -> np.ndarray:
    """|M| |v| (overflow gives inf, never a warning)."""
    with np.errstate(over="ignore", invalid="ignore"):
        if sp.issparse(M):
            return np.asarray(abs(M) @ np.abs(v)).ravel()
        return np.abs(M) @ np.abs(v)


def row_scales(M, z, q=None) -> np.ndarray:
    """σ_i = |q_i| + (|M| |z|)_i: the size of the terms row i of Mz + q is made of
    (Oettli–Prager's componentwise scale; its rounding error is O(eps σ_i))."""
    s = _abs_matvec(M, z)
    return s if q is None else s + np.abs(q)


def _column_max_ratio(absM, sigma: np.ndarray) -> np.ndarray:
    """max_i absM_ij / σ_i per column j (0/0 = 0, x/0 = inf); absM holds |M|."""
    n_rows, n_cols = absM.shape
    out = np.zeros(n_cols)
    if n_rows == 0 or n_cols == 0:
        return out
    if sp.issparse(absM):
        from ._certify_kernels import csc_column_max_ratio

        C = absM if absM.format == "csc" else absM.tocsc()
        return csc_column_max_ratio(C.indptr, C.indices, C.data.astype(float, copy=False),
                                    np.ascontiguousarray(sigma, dtype=float))
    step = max(1, _DENSE_CHUNK // n_rows)
    for start in range(0, n_cols, step):
        out[start:start + step] = _divide(absM[:, start:start + step], sigma[:, None]).max(axis=0)
    return out


def column_influence(M, sigma: np.ndarray) -> np.ndarray:
    """c_j = max_i |M_ij| / σ_i (0/0 = 0, x/0 = inf): the largest relative change
    a unit of unknown j makes to any row, each row measured by its own σ_i."""
    return _column_max_ratio(abs(M) if sp.issparse(M) else np.abs(M), sigma)


def _forward_scale(influence: np.ndarray, cap: float) -> np.ndarray:
    """min(1 / influence, cap) elementwise (1/0 = inf, 1/inf = 0)."""
    with np.errstate(divide="ignore"):
        inv = np.where(influence > 0, 1.0 / np.where(influence > 0, influence, 1.0), np.inf)
    return np.minimum(inv, cap)


@dataclass
class _Rows:
    """One block of equations for the componentwise scales: ``terms`` are the
    Oettli–Prager scales at the point (|data| + Σ |A||v|), ``data`` the
    magnitudes of the block's own data (zero marks a homogeneous row), and
    ``blocks`` the |coefficient| matrices of the unknowns that enter it."""

    terms: np.ndarray
    data: np.ndarray
    blocks: dict


def _scales(rows: list[_Rows], caps: dict) -> tuple[dict, list]:
    """Forward scales of the unknowns and the row scales, in two passes.

    An unknown's scale is min(cap, 1 / max_i |A_ij| / scale_i): the change that
    moves some row by all of that row's own size.  A *homogeneous* row (its own
    data exactly zero, e.g. q_i = 0 at an idle contact) whose unknowns are zero
    at the solution has no size of its own — any rounding noise would be all of
    it.  So the unknowns' scales are first taken from the rows with data only,
    a homogeneous row's scale gets the change those allowances can make to it
    (Σ_j |A_ij| scale_j), and the scales are taken again from every row.
    """
    def unknown_scales(row_scales):
        infl = {}
        for R, sc in zip(rows, row_scales):
            for name, absA in R.blocks.items():
                c = _column_max_ratio(absA, sc)
                infl[name] = c if name not in infl else np.maximum(infl[name], c)
        return {name: _forward_scale(c, caps[name]) for name, c in infl.items()}

    homogeneous = [R.data == 0 for R in rows]
    if not any(h.any() for h in homogeneous):
        return unknown_scales([R.terms for R in rows]), [R.terms for R in rows]
    first = unknown_scales([np.where(h, np.inf, R.terms) for R, h in zip(rows, homogeneous)])
    sig = []
    for R, h in zip(rows, homogeneous):
        extra = sum(_abs_matvec(absA, first[name]) for name, absA in R.blocks.items())
        sig.append(R.terms + np.where(h, extra, 0.0))
    return unknown_scales(sig), sig


class ComponentScales:
    """The componentwise scales of LCP(M, q) at any point z: σ (rows, w's
    units) and ζ (columns, z's units), as the certificate defines them.

    Keeps |M| so that a pivoting method can ask for them at every iterate; the
    sign tests of "energy", "bpp", "lemke" and "trace" are ρ σ_i and ρ ζ_i,
    so no component's decision depends on another component's size.
    """

    def __init__(self, M, q_terms: np.ndarray, scale_M: float | None = None):
        self.absM = abs(M).tocsc() if sp.issparse(M) else np.abs(M)
        self.q_terms = np.abs(np.asarray(q_terms, dtype=float))
        self.scale_M = _max_abs(M) if scale_M is None else scale_M

    def bound_data(self) -> tuple[np.ndarray, np.ndarray, float]:
        """(‖M_i‖₁ per row, 1/|M_ii| (inf where 0), ‖q‖∞ / max|M|): what cheap
        upper bounds of the scales need — σ_i <= |q_i| + ‖M_i‖₁ ‖z‖∞, plus
        ‖M_i‖₁ cap on an idle row (q_i = 0: the floor _scales adds),
        ζ_i <= min(σ_i / |M_ii|, cap), cap = max(‖z‖∞, ‖q‖∞ / max|M|)."""
        if self._bounds is None:
            A = self.absM
            diag = np.asarray(A.diagonal()).ravel()
            with np.errstate(divide="ignore"):
                inv_diag = np.where(diag > 0, 1.0 / np.where(diag > 0, diag, 1.0), np.inf)
            floor = _inf_norm(self.q_terms) / self.scale_M if self.scale_M > 0 else 0.0
            self._bounds = (np.asarray(A.sum(axis=1)).ravel(), inv_diag, floor)
        return self._bounds

    _bounds = None

    def at(self, z: np.ndarray, q_terms: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(ζ, σ) at z; ``q_terms`` are the magnitudes of q's terms (|q|, or
        LCP.q_terms; default the ones given at construction)."""
        q = self.q_terms if q_terms is None else q_terms
        with np.errstate(over="ignore", invalid="ignore"):
            sigma = np.asarray(self.absM @ np.abs(z)).ravel() + q
        cap = max(_inf_norm(z), _inf_norm(q) / self.scale_M if self.scale_M > 0 else 0.0)
        zeta, (sigma,) = _scales([_Rows(sigma, q, {"z": self.absM})], {"z": cap})
        return zeta["z"], sigma


def _safe_norm2(v: np.ndarray) -> float:
    """‖v‖₂ without overflow (BLAS nrm2 scales)."""
    return float(scipy.linalg.norm(v)) if v.size else 0.0


@dataclass(frozen=True)
class LCPCertificate:
    """Residuals of a candidate z for LCP(M, q); see the module docstring.

    ``error`` (componentwise backward error, in [0, 1]) decides ``ok``;
    ``worst_index`` is the component where it is reached.  ``forward_error``
    estimates how far, relative to its own size, a component may be from the
    exact solution of the data as stored (``condition`` times the backward
    error, at least rounding): an answer can be exact for data within 1e-16 of
    yours and still differ from the exact solution of yours in the 7th digit,
    when the problem is ill-conditioned.
    """

    error: float
    normwise_error: float
    worst_index: int
    comp_abs: float
    siconos_error: float
    min_z: float
    min_w: float
    zw: float
    overflow: bool = False
    # (condition, forward_error), or a function computing them on first use:
    # for an active block above _EXACT_CONDITION_SIZE the estimate costs one
    # more factorization of it, which a solve should not pay unasked.
    _forward: object = field(default=None, repr=False, compare=False)

    @property
    def condition(self) -> float:
        return self._forward_pair()[0]

    @property
    def forward_error(self) -> float:
        return self._forward_pair()[1]

    @property
    def forward_error_known(self) -> bool:
        """Whether the forward error is already computed (small active blocks:
        always; large ones: once asked for)."""
        return not callable(self._forward)

    def _forward_pair(self) -> tuple[float, float]:
        if callable(self._forward):
            object.__setattr__(self, "_forward", self._forward())
        return self._forward

    def __getstate__(self):
        self._forward_pair()
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def __setstate__(self, state):
        for k, v in state.items():
            object.__setattr__(self, k, v)

    def ok(self, tol: float) -> bool:
        return bool(self.error <= tol)

    def as_dict(self) -> dict:
        d = {f.name: getattr(self, f.name) for f in fields(self) if not f.name.startswith("_")}
        d["condition"], d["forward_error"] = self._forward_pair()
        return d


@dataclass(frozen=True)
class QPCertificate:
    """Residuals of a candidate (x, y, z, z_box) for a QP; see the module docstring.

    ``error`` (componentwise) decides ``ok``; ``worst`` names the condition
    where it is reached (e.g. ``"stationarity[3]"``, ``"bound complementarity[0]"``).
    """

    error: float
    normwise_error: float
    worst: str
    primal_residual: float
    dual_residual: float
    duality_gap: float
    comp_abs: float
    min_multiplier: float
    overflow: bool = False
    #: the worst condition in numbers: raw residual and the scale it was judged on
    detail: str = ""

    def ok(self, tol: float) -> bool:
        return bool(self.error <= tol)

    def as_dict(self) -> dict:
        return asdict(self)


def _bad_lcp_certificate(overflow: bool = False) -> LCPCertificate:
    inf = np.inf
    return LCPCertificate(inf, inf, -1, inf, inf, -inf, -inf, inf, overflow, (inf, inf))


def _lcp_normwise(lcp: LCP, z, Mz, w) -> float:
    scale_M = lcp.matrix_scale
    sigma_z = max(_inf_norm(z), _inf_norm(lcp.q) / scale_M if scale_M > 0 else 0.0)
    sigma_w = max(_inf_norm(Mz), _inf_norm(lcp.q))
    return _inf_norm(np.minimum(_divide(z, sigma_z), _divide(w, sigma_w)))


def _rounding_level(M) -> float:
    """(row nonzeros + 1) eps: the rounding of evaluating one row of Mz + q."""
    if not sp.issparse(M):
        row_nnz = M.shape[1]
    elif M.nnz == 0:
        row_nnz = 0
    elif M.format == "csr":
        row_nnz = int(np.diff(M.indptr).max())
    else:
        # counted from the row indices: a CSC -> CSR copy costs a solve's worth
        rows = M.indices if M.format == "csc" else M.tocoo().row
        row_nnz = int(np.bincount(rows, minlength=M.shape[0]).max())
    return (row_nnz + 1) * _EPS


#: Active blocks up to this size get |M_FF⁻¹| formed exactly; larger ones a
#: 1-norm estimate (Higham & Tisseur, scipy's onenormest) from a few solves.
_EXACT_CONDITION_SIZE = 400


def _block_solver(M, F: np.ndarray, structure):
    """solve(r, trans=False) with M_FF (or its transpose) for the condition
    estimate.  A symmetric M's block is tried with the factorizations the
    exact methods use (banded or sparse LDLᵀ, dense Cholesky: one factorization
    of a contact chain's block costs 1 ms where SuperLU took 27 ms); LU when it
    is not symmetric or not positive definite."""
    if structure is not None and structure.is_symmetric:
        from ..solvers.pivoting.active_set import BANDED_MAX, ActiveBlock

        try:
            if sp.issparse(M):
                bands = structure.upper_bands(BANDED_MAX)
                block = ActiveBlock(M, F, symmetric=True,
                                    triu=structure.upper if bands is None else None, bands=bands)
            else:
                block = ActiveBlock(M, F, symmetric=True)
            return lambda r, trans=False: block._solve(r)
        except (np.linalg.LinAlgError, ValueError):
            pass
    if sp.issparse(M):
        import scipy.sparse.linalg as spla

        lu = spla.splu(M[F][:, F].tocsc())
        return lambda r, trans=False: lu.solve(r, trans="T" if trans else "N")
    with warnings.catch_warnings():  # a singular block: inf below
        warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
        lu = scipy.linalg.lu_factor(M[np.ix_(F, F)], check_finite=False)
    return lambda r, trans=False: scipy.linalg.lu_solve(lu, r, trans=1 if trans else 0,
                                                        check_finite=False)


def _lcp_condition(M, z, w, zeta, sigma, level: float, structure=None
                   ) -> tuple[float, float, float]:
    """(condition, forward z factor, forward w factor) of a solution at its basis.

    F = {i: z_i / ζ_i > w_i / σ_i} (the z's that are "on"), N the rest.  On F,
    z_F = -M_FF⁻¹ q_F; data perturbed by ε of each entry's own size, with the
    forward allowance ε ζ_F, move z_F by at most ε v, v = |M_FF⁻¹| σ_F + ζ_F
    (first order), and w_N by at most ε (σ_N + |M_NF| v).  Returned: the
    largest relative factors max_i v_i / |z_i| (F) and max_j (σ_j + (|M_NF|
    v)_j) / |w_j| (N), and their maximum as the condition number; the forward
    error is ε times them.  For active blocks above _EXACT_CONDITION_SIZE, v is
    bounded through a 1-norm estimate of ‖Z⁻¹|M_FF⁻¹|σ_F‖∞ (so |M_NF| v <=
    κ_z σ_N, a cruder bound).  Every value is judged against itself — a
    component near zero may have no correct digit, and that is what a user
    reading it must be told — except values below ``level`` (the rounding of
    evaluating their row) times their scale, which carry no information and are
    judged against the scale (ζ_i, σ_j).  inf when M_FF is singular: the
    solution is not isolated.
    """
    Z, W = _divide(z, zeta), _divide(w, sigma)
    on = Z > W
    F, N = np.flatnonzero(on), np.flatnonzero(~on)
    kappa_z, v = 0.0, np.zeros(0)
    if F.size:
        den = np.where(np.abs(z[F]) > level * zeta[F], np.abs(z[F]), zeta[F])
        g = sigma[F]
        k = F.size
        try:
            with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
                if k <= _EXACT_CONDITION_SIZE:
                    B = M[F][:, F].toarray() if sp.issparse(M) else M[np.ix_(F, F)]
                    inv = np.linalg.inv(B)  # LinAlgError when exactly singular
                    if not np.all(np.isfinite(inv)):
                        return np.inf, np.inf, np.inf
                    v = np.abs(inv) @ g + zeta[F]
                    kappa_z = float(np.max(_divide(v, den)))
                else:
                    from scipy.sparse.linalg import LinearOperator, onenormest

                    solve = _block_solver(M, F, structure)
                    # ‖Z⁻¹ |B⁻¹| g‖∞ = ‖Z⁻¹ B⁻¹ G‖∞ = ‖G B⁻ᵀ Z⁻¹‖₁
                    op = LinearOperator((k, k), dtype=float,
                                        matvec=lambda x: g * solve(np.ravel(x) / den, trans=True),
                                        rmatvec=lambda y: solve(g * np.ravel(y)) / den)
                    kappa_z = float(onenormest(op, t=1)) + float(np.max(zeta[F] / den))
                    v = None
        except (RuntimeError, ValueError, np.linalg.LinAlgError):
            return np.inf, np.inf, np.inf
        if not np.isfinite(kappa_z):
            return np.inf, np.inf, np.inf
    kappa_w = 0.0
    if N.size:
        if F.size and v is not None:
            MNF = M[N][:, F] if sp.issparse(M) else M[np.ix_(N, F)]
            spread = sigma[N] + _abs_matvec(MNF, v)
        else:
            spread = (1.0 + kappa_z) * sigma[N]
        wd = np.where(np.abs(w[N]) > level * sigma[N], np.abs(w[N]), sigma[N])
        kappa_w = float(np.max(_divide(spread, wd)))
    return max(kappa_z, kappa_w), kappa_z, kappa_w


def certify_lcp(lcp: LCP, z) -> LCPCertificate:
    """Certificate of z for ``lcp`` (see the module docstring)."""
    z = np.asarray(z, dtype=float).ravel()
    if z.shape != (lcp.n,):
        raise InvalidProblemError(f"z has shape {z.shape}; the LCP has n = {lcp.n} unknowns")
    if not np.all(np.isfinite(z)):
        return _bad_lcp_certificate()
    with np.errstate(over="ignore", invalid="ignore"):
        Mz = np.asarray(lcp.M @ z).ravel()
        w = Mz + lcp.q
    if not (np.all(np.isfinite(w)) and np.all(np.isfinite(row_scales(lcp.M, z, lcp.q_terms)))):
        return _bad_lcp_certificate(overflow=True)
    zeta, sigma = ComponentScales(lcp.M, lcp.q_terms, lcp.matrix_scale).at(z)
    Z, W = _divide(z, zeta), _divide(w, sigma)
    e = np.abs(np.minimum(Z, W))
    worst = int(np.argmax(e))
    r = np.minimum(z, w)
    qn = _safe_norm2(lcp.q)
    rn = _safe_norm2(r)
    with np.errstate(over="ignore", invalid="ignore"):
        zw = float(z @ w)
    # Below the rounding of evaluating a row (LAPACK's FERR convention) no
    # backward error can be seen.
    level = _rounding_level(lcp.M)
    error = float(e[worst])

    def forward_pair(M=lcp.M, structure=lcp._structure):
        condition, kappa_z, kappa_w = _lcp_condition(M, z, w, zeta, sigma, level, structure)
        forward = max(error, level) * max(kappa_z, kappa_w)
        return float(condition), (float(forward) if np.isfinite(forward) else np.inf)

    active = np.count_nonzero(Z > W)   # the basis _lcp_condition factorizes
    return LCPCertificate(
        error=error,
        _forward=forward_pair() if active <= _EXACT_CONDITION_SIZE else forward_pair,
        normwise_error=float(_lcp_normwise(lcp, z, Mz, w)),
        worst_index=worst,
        comp_abs=_inf_norm(r),
        siconos_error=rn / qn if qn > _EPS else rn,
        min_z=float(min(z.min(), 0.0)),
        min_w=float(min(w.min(), 0.0)),
        zw=zw,
    )


def _row_inf_norms(G) -> np.ndarray:
    if sp.issparse(G):
        return np.asarray(abs(G).max(axis=1).todense()).ravel()
    return np.max(np.abs(G), axis=1) if G.shape[1] else np.zeros(G.shape[0])


def _qp_normwise(problem, x, sol, has_bounds) -> float:
    """The former scale-free QP measure (OSQP-style relative residuals with a
    per-constraint complementarity), kept beside the componentwise one."""
    P, q, G, h, A, b, lb, ub = problem.unpack()
    n = q.shape[0]
    r_p = sol.primal_residual()
    r_d = sol.dual_residual() if (sol.z_box is not None or not has_bounds) else np.inf
    r_g = sol.duality_gap() if (sol.z_box is not None or not has_bounds) else np.inf
    Px = np.asarray(P @ x).ravel()
    p_terms, d_terms = [0.0], [_inf_norm(Px), _inf_norm(q)]
    g_terms = [abs(float(x @ Px)), abs(float(q @ x))]
    comp_pairs = []
    min_mult = 0.0
    if G is not None:
        Gx = np.asarray(G @ x).ravel()
        p_terms += [_inf_norm(Gx), _inf_norm(h)]
        if sol.z is not None:
            d_terms.append(_inf_norm(np.asarray(G.T @ sol.z).ravel()))
            g_terms.append(abs(float(h @ sol.z)))
            comp_pairs.append((sol.z, h - Gx, _row_inf_norms(G)))
            min_mult = min(min_mult, float(sol.z.min(initial=0.0)))
    if A is not None:
        Ax = np.asarray(A @ x).ravel()
        p_terms += [_inf_norm(Ax), _inf_norm(b)]
        if sol.y is not None:
            d_terms.append(_inf_norm(np.asarray(A.T @ sol.y).ravel()))
            g_terms.append(abs(float(b @ sol.y)))
    if has_bounds:
        p_terms.append(_inf_norm(x))
        zb = sol.z_box if sol.z_box is not None else np.zeros(n)
        d_terms.append(_inf_norm(zb))
        for bound, sign in ((lb, -1.0), (ub, 1.0)):
            if bound is None:
                continue
            fin = np.isfinite(bound)
            p_terms.append(_inf_norm(bound[fin]))
            mult = np.maximum(sign * zb[fin], 0.0)
            g_terms.append(abs(float(bound[fin] @ (sign * mult))))
            comp_pairs.append((mult, sign * (bound[fin] - x[fin]), 1.0))
    sigma_p, sigma_d, sigma_g = max(p_terms), max(d_terms), max(g_terms)
    comp_rel = 0.0
    for mult, slack, row_norm in comp_pairs:
        if mult.size:
            comp_rel = max(comp_rel, _inf_norm(np.minimum(_divide(mult * row_norm, sigma_d),
                                                          _divide(slack, sigma_p))))
    return max(_ratio(r_p, sigma_p), _ratio(r_d, sigma_d), _ratio(r_g, sigma_g), comp_rel,
               _ratio(-min_mult, sigma_d))


def certify_qp(problem: Problem, x, y=None, z=None, z_box=None) -> QPCertificate:
    """Certificate of the primal-dual point (x, y, z, z_box) in qpsolvers'
    conventions: ``Px + q + A'y + G'z + z_box = 0``, z >= 0 for ``Gx <= h``,
    z_box < 0 at an active lower bound and > 0 at an active upper bound.

    A missing multiplier for constraints the problem has makes the error
    infinite (the point cannot be certified without it).
    """
    P, q, G, h, A, b, lb, ub = problem.unpack()
    n = q.shape[0]
    x = np.asarray(x, dtype=float).ravel()
    if x.shape != (n,):
        raise InvalidProblemError(f"x has shape {x.shape}; the QP has n = {n} variables")
    def vector(v, size):
        # Backends hand back empty arrays for constraints the problem lacks.
        if v is None:
            return None
        v = np.asarray(v, float).ravel()
        if size == 0 and not np.any(v):
            return None
        if v.size != size:
            raise InvalidProblemError(f"a multiplier has {v.size} entries where the QP has {size} "
                                      "matching constraints")
        return v

    has_bounds = lb is not None or ub is not None
    y = vector(y, A.shape[0] if A is not None else 0)
    z = vector(z, G.shape[0] if G is not None else 0)
    z_box = vector(z_box, n if has_bounds else 0)
    inf = np.inf
    bad = QPCertificate(inf, inf, "non-finite point", inf, inf, inf, inf, -inf)
    if not all(np.all(np.isfinite(v)) for v in (x, y, z, z_box) if v is not None):
        return bad
    missing = [name for name, mat, v in (("z (for G x <= h)", G, z), ("y (for A x = b)", A, y),
                                         ("z_box (for the bounds)", lb if lb is not None else ub,
                                          z_box))
               if mat is not None and v is None]

    sol = _QPSolution(problem)
    sol.found = True
    sol.x, sol.y, sol.z, sol.z_box = x, y, z, z_box
    with np.errstate(over="ignore", invalid="ignore"):
        r_p = sol.primal_residual()
        r_d = sol.dual_residual() if (z_box is not None or not has_bounds) else inf
        r_g = sol.duality_gap() if (z_box is not None or not has_bounds) else inf
        normwise = _qp_normwise(problem, x, sol, has_bounds)

        # Stationarity, row by row against its own terms (bounds' multipliers
        # excluded from the scale: they must be balanced by the rest).
        grad = np.asarray(P @ x).ravel() + q
        S = row_scales(P, x, q)
        if G is not None and z is not None:
            grad += np.asarray(G.T @ z).ravel()
            S += _abs_matvec(G.T, z)
        if A is not None and y is not None:
            grad += np.asarray(A.T @ y).ravel()
            S += _abs_matvec(A.T, y)
        if z_box is not None:
            grad += z_box
        overflow = not (np.all(np.isfinite(grad)) and np.all(np.isfinite(S)))
        if overflow:
            return QPCertificate(inf, normwise, "overflow", r_p, r_d, r_g, inf, -inf, True)

        def absolute(mat):
            return abs(mat) if sp.issparse(mat) else np.abs(mat)

        # Each block of KKT rows with the unknowns that enter it; _scales gives
        # every unknown its own scale and floors homogeneous rows.
        absG = absolute(G) if G is not None else None
        absA = absolute(A) if A is not None else None
        stat_blocks = {"x": absolute(P)}
        if absG is not None and z is not None:
            stat_blocks["z"] = absG.T
        if absA is not None and y is not None:
            stat_blocks["y"] = absA.T
        rows = [_Rows(S, np.abs(q), stat_blocks)]
        slack = None
        if G is not None:
            slack = h - np.asarray(G @ x).ravel()
            rows.append(_Rows(row_scales(G, x, h), np.abs(h), {"x": absG}))
        if A is not None:
            rows.append(_Rows(row_scales(A, x, b), np.abs(b), {"x": absA}))
        # x's own scale is capped by the normwise data floors (all in x's
        # units), each multiplier's by the normwise floor of its own block.
        cap_x = [_inf_norm(x)]
        for vec, mat in ((q, P), (h, G), (b, A)):
            if mat is not None and _max_abs(mat) > 0:
                cap_x.append(_inf_norm(vec) / _max_abs(mat))
        for bound in (lb, ub):
            if bound is not None:
                cap_x.append(_inf_norm(bound[np.isfinite(bound)]))
        caps = {"x": max(cap_x)}
        for name, v, mat in (("z", z, G), ("y", y, A)):
            if v is not None and mat is not None:
                scale = _max_abs(mat)
                caps[name] = max(_inf_norm(v), _inf_norm(q) / scale if scale > 0 else 0.0)
        unknown, sig = _scales(rows, caps)
        S = sig[0]
        T = sig[1] if G is not None else None
        E = sig[-1] if A is not None else None
        xi = unknown["x"]

        # (name, componentwise errors, words for component i: raw values and scales)
        checks: list[tuple[str, np.ndarray, object]] = [
            ("stationarity", _divide(np.abs(grad), S),
             lambda i: f"(Px + q + G'z + A'y + z_box)_{i} = {grad[i]:.3e} against its row's "
                       f"scale {S[i]:.3e} (|P||x| + |q| + |G'||z| + |A'||y|, floored)")]
        if A is not None:
            r_eq = b - np.asarray(A @ x).ravel()
            checks.append(("equality", _divide(np.abs(r_eq), E),
                           lambda i: f"b_{i} - (Ax)_{i} = {r_eq[i]:.3e} against its row's scale "
                                     f"{E[i]:.3e} (|A||x| + |b|, floored)"))

        comp_abs, min_mult = 0.0, 0.0
        if G is not None:
            if z is not None:
                zs = unknown["z"]
                checks.append(("inequality complementarity",
                               np.abs(np.minimum(_divide(z, zs), _divide(slack, T))),
                               lambda i: f"z_{i} = {z[i]:.3e} (scale {zs[i]:.3e}) and slack "
                                         f"h_{i} - (Gx)_{i} = {slack[i]:.3e} (scale {T[i]:.3e}): "
                                         "one must be >= 0 and the other 0"))
                comp_abs = max(comp_abs, _inf_norm(np.minimum(z, slack)))
                min_mult = min(min_mult, float(z.min(initial=0.0)))
            else:
                checks.append(("inequality", _divide(np.maximum(-slack, 0.0), T),
                               lambda i: f"h_{i} - (Gx)_{i} = {slack[i]:.3e} < 0 (scale {T[i]:.3e})"))
        if has_bounds:
            zb = z_box if z_box is not None else np.zeros(n)
            lb_fin = np.isfinite(lb) if lb is not None else np.zeros(n, bool)
            ub_fin = np.isfinite(ub) if ub is not None else np.zeros(n, bool)
            for bound, fin, sign, name in ((lb, lb_fin, -1.0, "lower"), (ub, ub_fin, 1.0, "upper")):
                if not fin.any():
                    continue
                k = np.flatnonzero(fin)
                mult = np.maximum(sign * zb[k], 0.0)
                bslack = sign * (bound[k] - x[k])
                e = np.zeros(n)
                e[k] = np.abs(np.minimum(_divide(mult, S[k]),
                                         _divide(bslack, np.abs(bound[k]) + xi[k])))
                full_slack = np.zeros(n)
                full_slack[k] = bslack
                checks.append((f"{name} bound complementarity", e,
                               lambda i, zb=zb, sl=full_slack, nm=name:
                               f"z_box_{i} = {zb[i]:.3e} (scale {S[i]:.3e}) and the distance to "
                               f"the {nm} bound {sl[i]:.3e}: one must be >= 0 and the other 0"))
                comp_abs = max(comp_abs, _inf_norm(np.minimum(mult, bslack)))
            # z_box_i < 0 claims an active lower bound, > 0 an active upper one: a
            # claim on a bound that does not exist is a multiplier of the wrong sign.
            illegal = np.where((zb < 0) & ~lb_fin, zb, 0.0) - np.where((zb > 0) & ~ub_fin, zb, 0.0)
            min_mult = min(min_mult, float(illegal.min(initial=0.0)))
            checks.append(("bound multiplier sign", _divide(np.abs(illegal), S),
                           lambda i: f"z_box_{i} = {zb[i]:.3e} claims a bound x_{i} does not have "
                                     f"(scale {S[i]:.3e})"))

    worst_name, worst_val, detail = "", 0.0, ""
    for name, vals, words in checks:
        if vals.size:
            i = int(np.argmax(vals))
            if vals[i] > worst_val or not worst_name:
                worst_name, worst_val, detail = f"{name}[{i}]", float(vals[i]), words(i)
    if missing:
        worst_name, worst_val = "missing multiplier " + ", ".join(missing), inf
        detail = "the QP has these constraints; certify needs their multipliers"
    return QPCertificate(
        error=float(worst_val),
        normwise_error=float(normwise),
        worst=worst_name,
        primal_residual=float(r_p),
        dual_residual=float(r_d),
        duality_gap=float(r_g),
        comp_abs=float(comp_abs),
        min_multiplier=float(min_mult),
        detail=detail,
    )


def certify(problem, x, *, y=None, z=None, z_box=None):
    """Certify a candidate solution from the problem data alone.

    Parameters
    ----------
    problem : LCP or qpsolvers.Problem
    x : array_like
        For an LCP, the candidate z; for a QP, the candidate primal x.
    y, z, z_box : array_like, optional
        QP multipliers in qpsolvers' conventions (equalities, inequalities,
        bounds).  Required for the QP constraints the problem has.

    Returns
    -------
    LCPCertificate or QPCertificate
        ``cert.error`` is the componentwise measure compared with the requested
        tolerance (``cert.ok(tol)``); see the module docstring for every field.
    """
    if isinstance(problem, LCP):
        return certify_lcp(problem, x)
    if isinstance(problem, Problem):
        return certify_qp(problem, x, y, z, z_box)
    raise InvalidProblemError(f"cannot certify a {type(problem).__name__}; expected an LCP or a qpsolvers.Problem")
