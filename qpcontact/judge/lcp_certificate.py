"""Certificates of LCP answers, computed from the data alone.

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
"""

from __future__ import annotations

import warnings
import weakref
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..core.errors import InvalidProblemError
from ..core.problems import LCP
from .forward import ForwardErrorMixin
from .near_farkas import near_farkas
from .scales import ComponentScales, abs_matvec, divide, inf_norm, row_rounding, safe_norm2

__all__ = ["LCPCertificate", "certify_lcp", "componentwise_error"]

_EPS = np.finfo(float).eps


@dataclass(frozen=True)
class LCPCertificate(ForwardErrorMixin):
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
    # the near-Farkas vector (None or an array), or a function finding it:
    # asked for only where the active block is singular to working precision
    _near: object = field(default=None, repr=False, compare=False)

    @property
    def near_farkas(self):
        """Where the forward error is known and no digit is guaranteed
        (forward error >= 1, the active block singular or nearly so): a
        vector y >= 0 on the active rows with Mᵀy <= 0 and qᵀy <= 0 to
        rounding (each column against its own terms ``|M|ᵀy``, qᵀy against
        ``|q|ᵀy``) — the data are then within rounding of a problem with no
        solution, and y is the Farkas vector to check exactly.  None
        otherwise (also when the forward error is not computed yet)."""
        if not self.forward_error_known or self.forward_error < 1.0:
            return None
        if callable(self._near):
            object.__setattr__(self, "_near", self._near())
        return self._near


    @property
    def scale_forward_error(self) -> float:
        """The forward error with each component judged against its scale
        (ζ_j for z_j, σ_i for w_i) rather than its own value: at least
        FORWARD_LIMIT means no digit even on that scale
        (:func:`qpcontact.judge.doubt.no_digit`)."""
        return self._forward_pair()[2]

    @property
    def scale_condition(self) -> float:
        """The condition factor of :attr:`scale_forward_error` (components
        against their scales): 1/eps or more means the active block is
        singular to working precision — the solution is not isolated as far
        as double precision can tell."""
        return self._forward_pair()[3]


def _bad_lcp_certificate(overflow: bool = False) -> LCPCertificate:
    inf = np.inf
    return LCPCertificate(inf, inf, -1, inf, inf, -inf, -inf, inf, overflow, (inf, inf, inf, inf))


def _lcp_normwise(lcp: LCP, z, Mz, w) -> float:
    scale_M = lcp.matrix_scale
    sigma_z = max(inf_norm(z), inf_norm(lcp.q) / scale_M if scale_M > 0 else 0.0)
    sigma_w = max(inf_norm(Mz), inf_norm(lcp.q))
    return inf_norm(np.minimum(divide(z, sigma_z), divide(w, sigma_w)))


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
        from ..core.linalg import BANDED_MAX, ActiveBlock

        try:
            if sp.issparse(M):
                bands = structure.upper_bands(BANDED_MAX)
                block = ActiveBlock(M, F, symmetric=True, bands=bands)
            else:
                block = ActiveBlock(M, F, symmetric=True)
            return lambda r, trans=False: block.factor_solve(r)
        except (np.linalg.LinAlgError, ValueError):
            pass
    if sp.issparse(M):
        import scipy.sparse.linalg as spla

        lu = spla.splu(M[F][:, F].tocsc())
        return lambda r, trans=False: lu.solve(r, trans="T" if trans else "N")
    import scipy.linalg

    with warnings.catch_warnings():  # a singular block: inf below
        warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
        lu = scipy.linalg.lu_factor(M[np.ix_(F, F)], check_finite=False)
    return lambda r, trans=False: scipy.linalg.lu_solve(lu, r, trans=1 if trans else 0,
                                                        check_finite=False)


def _basis_factors(M, F, N, z, w, zeta, sigma, level, structure, eps):
    """(κ_z, κ_w, per-component factors on the scales) of the basis F (z_F
    on, w_N on); see :func:`_lcp_condition`.  The per-component factors
    (v_i / ζ_i on F, (σ_j + (|M_NF| v + |M_NN| a_N)_j) / σ_j on N) are None above
    _EXACT_CONDITION_SIZE (a 1-norm estimate gives their maximum only);
    inf everywhere when M_FF is singular."""
    n = z.size
    inf = (np.inf, np.inf, np.full(n, np.inf))
    kappa_z, v, by_scale = 0.0, np.zeros(0), np.zeros(n)
    # The z's that are off need not be zero: the exact solution's are, and
    # zeroing them moves the rows by |M_·N| |z_N| = ε |M_·N| (|z_N| / ε),
    # which σ at the answer does not hold when z_N is small (ProxQP's 1e-8's
    # beside one active row of σ = 0.02 read 8.7e-8 where the error was
    # 2.4e-7).  On the answer's own basis |z_N| <= ε ζ_N (the backward
    # error); on a probe's the allowance is capped at ε ζ_N, the change
    # "ε of each entry's own size" allows.  Each |M_ij| ζ_j <= σ_i (the
    # scale's definition), so this adds at most |N| σ_i to a row, and
    # nothing where z_N = 0 exactly (the pivoting methods).
    allowance = np.zeros(n)
    if N.size and eps > 0:
        allowance[N] = np.minimum(divide(np.abs(z[N]), eps), zeta[N])
    off = abs_matvec(M, allowance) if np.any(allowance) else allowance
    if F.size:
        den = np.where(np.abs(z[F]) > level * zeta[F], np.abs(z[F]), zeta[F])
        g = sigma[F] + off[F]
        k = F.size
        try:
            with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
                if k <= _EXACT_CONDITION_SIZE:
                    B = M[F][:, F].toarray() if sp.issparse(M) else M[np.ix_(F, F)]
                    inv = np.linalg.inv(B)  # LinAlgError when exactly singular
                    if not np.all(np.isfinite(inv)):
                        return inf
                    v = np.abs(inv) @ g + zeta[F]
                    kappa_z = float(np.max(divide(v, den)))
                    by_scale[F] = divide(v, zeta[F])
                else:
                    from scipy.sparse.linalg import LinearOperator, onenormest

                    solve = _block_solver(M, F, structure)
                    # ‖Z⁻¹ |B⁻¹| g‖∞ = ‖Z⁻¹ B⁻¹ G‖∞ = ‖G B⁻ᵀ Z⁻¹‖₁
                    op = LinearOperator((k, k), dtype=float,
                                        matvec=lambda x: g * solve(np.ravel(x) / den, trans=True),
                                        rmatvec=lambda y: solve(g * np.ravel(y)) / den)
                    kappa_z = float(onenormest(op, t=1)) + float(np.max(zeta[F] / den))
                    by_scale_op = LinearOperator(
                        (k, k), dtype=float,
                        matvec=lambda x: g * solve(np.ravel(x) / zeta[F], trans=True),
                        rmatvec=lambda y: solve(g * np.ravel(y)) / zeta[F])
                    by_scale = None
                    scaled_z = float(onenormest(by_scale_op, t=1)) + 1.0
                    v = None
        except (RuntimeError, ValueError, np.linalg.LinAlgError):
            return inf
        if not np.isfinite(kappa_z):
            return inf
    kappa_w = 0.0
    if N.size:
        if F.size and v is not None:
            MNF = M[N][:, F] if sp.issparse(M) else M[np.ix_(N, F)]
            spread = sigma[N] + abs_matvec(MNF, v) + off[N]
        else:
            spread = (1.0 + kappa_z) * sigma[N] + off[N]
        wd = np.where(np.abs(w[N]) > level * sigma[N], np.abs(w[N]), sigma[N])
        kappa_w = float(np.max(divide(spread, wd)))
        if by_scale is not None:
            by_scale[N] = divide(spread, sigma[N])
        else:
            scaled_z = max(scaled_z, float(np.max(divide(spread, sigma[N]))))
    if by_scale is None:
        by_scale = np.full(n, scaled_z)
    return kappa_z, kappa_w, by_scale


#: how many times the basis is widened by its ambiguous components (below)
_PROBES = 4

#: a component is ambiguous when it lies within this many times its own
#: forward-error estimate of switching sides (z_i -> 0 on F, w_j -> 0 on N)
_AMBIGUITY = 4.0


def _lcp_condition(M, z, w, zeta, sigma, level: float, structure=None, error: float = 0.0
                   ) -> tuple[float, float, float, float]:
    """(condition, forward z factor, forward w factor, scale factor) of a
    solution, over the bases it may have.

    F = {i: z_i / ζ_i > w_i / σ_i} (the z's that are "on"), N the rest.  On F,
    z_F = -M_FF⁻¹ q_F; data perturbed by ε of each entry's own size, with the
    forward allowance ε ζ_F, and the off z's (within ε ζ_N of zero, not at
    it) set to zero, move z_F by at most ε v, v = |M_FF⁻¹| (σ_F + |M_FN| a_N)
    + ζ_F with a_N = min(|z_N| / ε, ζ_N) (first order), and w_N by at most
    ε (σ_N + |M_NF| v + |M_NN| a_N).  Returned: the
    largest relative factors max_i v_i / |z_i| (F) and max_j (σ_j + (|M_NF|
    v)_j) / |w_j| (N), and their maximum as the condition number; the forward
    error is ε times them.  For active blocks above _EXACT_CONDITION_SIZE, v is
    bounded through a 1-norm estimate of ‖Z⁻¹|M_FF⁻¹|σ_F‖∞ (so |M_NF| v <=
    κ_z σ_N, a cruder bound).  Every value is judged against itself — a
    component near zero may have no correct digit, and that is what a user
    reading it must be told — except values below ``level`` (the rounding of
    evaluating their row) times their scale, which carry no information and are
    judged against the scale (ζ_i, σ_j).  inf when M_FF is singular: the
    solution is not isolated.  The scale factor judges every value against
    its scale instead (max v_i / ζ_i, max (σ_j + (|M_NF| v)_j) / σ_j): how
    many digits a component has relative to the size its data give it —
    the measure of "no digit at all" (qpcontact.judge.doubt.no_digit), where
    a w of 5e-9 beside forces of 1 may well have none of its own.

    The answer's own basis need not be the solution's: a w_j of 2e-5 of its
    scale, with an estimate of 5e-2, may be a z_j > 0 of the exact solution,
    whose block is worse conditioned (an SPD LCP of condition 1e13 read
    5.6e-2 at the answer's basis where the true error was 0.59).  So the
    components within _AMBIGUITY times their own estimate (``error`` times
    the scale factor) of switching sides are probed: the basis widened by
    the ambiguous w's (F ∪ A_N: for a positive definite M the larger block
    is the worse conditioned) and narrowed by the ambiguous z's (F \ A_F),
    repeated with the new estimates until no component joins (at most
    _PROBES times); every factor is the largest over the probes.
    """
    Z, W = divide(z, zeta), divide(w, sigma)
    on = Z > W
    eps = max(error, level)
    worst = (0.0, 0.0, np.zeros(z.size))
    probes = [on]
    seen = set()
    for _ in range(_PROBES + 1):
        new = []
        for basis in probes:
            key = basis.tobytes()
            if key in seen:
                continue
            seen.add(key)
            F, N = np.flatnonzero(basis), np.flatnonzero(~basis)
            kz, kw, by = _basis_factors(M, F, N, z, w, zeta, sigma, level, structure, eps)
            if not np.isfinite(kz):
                return np.inf, np.inf, np.inf, np.inf
            worst = (max(worst[0], kz), max(worst[1], kw), np.maximum(worst[2], by))
            new.append(basis)
        if not new or eps * float(worst[2].max(initial=0.0)) >= 1.0 \
                or np.count_nonzero(on) > _EXACT_CONDITION_SIZE:
            # nothing new, no digit on some scale already, or a block whose
            # factors are 1-norm estimates (no per-component reach to probe)
            break
        reach = _AMBIGUITY * eps * worst[2]
        amb_n = ~on & (np.abs(W) <= reach)
        amb_f = on & (np.abs(Z) <= reach)
        probes = [on | amb_n, on & ~amb_f]
    kappa_z, kappa_w, by = worst
    return max(kappa_z, kappa_w), kappa_z, kappa_w, float(by.max(initial=0.0))


def _componentwise(lcp: LCP, z):
    """(M z, w, ζ, σ, z/ζ, w/σ, |min(z/ζ, w/σ)|) of a finite z, or None
    where a product overflows."""
    with np.errstate(over="ignore", invalid="ignore"):
        Mz = np.asarray(lcp.M @ z).ravel()
        w = Mz + lcp.q
    scales = ComponentScales.of(lcp)
    with np.errstate(over="ignore", invalid="ignore"):
        terms = np.asarray(scales.absM @ np.abs(z)).ravel() + scales.q_terms   # |M||z| + |q|
    if not (np.all(np.isfinite(w)) and np.all(np.isfinite(terms))):
        return None
    zeta, sigma = scales.at(z, terms=terms)
    Z, W = divide(z, zeta), divide(w, sigma)
    return Mz, w, zeta, sigma, Z, W, np.abs(np.minimum(Z, W))


def componentwise_error(lcp: LCP, z) -> tuple[float, np.ndarray, np.ndarray]:
    """(error, ζ, σ): the componentwise error of z (``certify_lcp(lcp,
    z).error``, the same number) and the scales it is measured on, without
    the certificate's forward-error estimate (a basis factorized per probe:
    most of its cost on a small LCP) — for a caller that judges on the
    error alone.  inf (and ζ, σ of inf) where z is not finite or a product
    overflows."""
    z = np.asarray(z, dtype=float).ravel()
    if z.shape != (lcp.n,):
        raise InvalidProblemError(f"z has shape {z.shape}; the LCP has n = {lcp.n} unknowns")
    parts = _componentwise(lcp, z) if np.all(np.isfinite(z)) else None
    if parts is None:
        return np.inf, np.full(lcp.n, np.inf), np.full(lcp.n, np.inf)
    e = parts[-1]
    return float(e[int(np.argmax(e))]) if e.size else 0.0, parts[2], parts[3]


def certify_lcp(lcp: LCP, z) -> LCPCertificate:
    """Certificate of z for ``lcp`` (see the module docstring)."""
    z = np.asarray(z, dtype=float).ravel()
    if z.shape != (lcp.n,):
        raise InvalidProblemError(f"z has shape {z.shape}; the LCP has n = {lcp.n} unknowns")
    if not np.all(np.isfinite(z)):
        return _bad_lcp_certificate()
    parts = _componentwise(lcp, z)
    if parts is None:
        return _bad_lcp_certificate(overflow=True)
    Mz, w, zeta, sigma, Z, W, e = parts
    worst = int(np.argmax(e))
    r = np.minimum(z, w)
    qn = safe_norm2(lcp.q)
    rn = safe_norm2(r)
    with np.errstate(over="ignore", invalid="ignore"):
        zw = float(z @ w)
    # Below the rounding of evaluating a row (LAPACK's FERR convention) no
    # backward error can be seen.
    level = row_rounding(lcp.M)
    error = float(e[worst])

    # a kept answer must not keep the problem's caches alive (a multilevel
    # setup is several times M): the structure only speeds the factorization
    # up, and without it the condition estimate factors by LU
    structure_ref = weakref.ref(lcp.structure)

    def forward_pair(M=lcp.M):
        condition, kappa_z, kappa_w, scaled = _lcp_condition(M, z, w, zeta, sigma, level,
                                                             structure_ref(), error)
        eps = max(error, level)
        forward, by_scale = eps * max(kappa_z, kappa_w), eps * scaled
        return (float(condition), (float(forward) if np.isfinite(forward) else np.inf),
                float(by_scale) if np.isfinite(by_scale) else np.inf, float(scaled))

    def near(M=lcp.M, q=lcp.q):
        # an answer that solves the stored data exactly is right whatever
        # data within rounding of them do (Siconos' CPS_5: z = (0, 1) solves
        # M = [[1, -1], [-1, 1]], q = (1, -1) exactly; y = (1, 1) has
        # M'y = 0 = q'y, and q rounded the other way would have none)
        if error == 0.0 and exactly_solves(M, q, z):
            return None
        # a Farkas vector lives where w is zero to within what the answer's
        # residuals can hide: the active rows, and the rows whose w is within
        # the error's reach of zero (1ᵀw = -1 beside σ ~ 1e13 spreads over them)
        rows = (Z > W) | (np.abs(W) <= max(100.0 * error, np.sqrt(_EPS)))
        return near_farkas(M, q, rows, max(10.0 * error, 100.0 * level))

    active = np.count_nonzero(Z > W)   # the basis _lcp_condition factorizes
    return LCPCertificate(
        error=error,
        _forward=forward_pair() if active <= _EXACT_CONDITION_SIZE else forward_pair,
        _near=near,
        normwise_error=float(_lcp_normwise(lcp, z, Mz, w)),
        worst_index=worst,
        comp_abs=inf_norm(r),
        siconos_error=rn / qn if qn > _EPS else rn,
        min_z=float(min(z.min(), 0.0)),
        min_w=float(min(w.min(), 0.0)),
        zw=zw,
    )


#: the exact check of an answer runs up to this many products
EXACT_PRODUCTS = 200_000


def exactly_solves(M, q, z) -> bool:
    """Whether z solves the LCP (M, q) exactly, in rationals from the stored
    floats: z >= 0, w = M z + q >= 0, z_i w_i = 0 (False where the check
    would take more than EXACT_PRODUCTS products)."""
    from fractions import Fraction

    z = np.asarray(z, float)
    if np.any(z < 0) or not np.all(np.isfinite(z)):
        return False
    support = np.flatnonzero(z)
    if q.size * max(support.size, 1) > EXACT_PRODUCTS:
        return False
    cols = (M[:, support].toarray() if hasattr(M, "toarray") else np.asarray(M)[:, support])
    zq = [Fraction(float(v)) for v in z[support]]
    for i in range(q.size):
        w = Fraction(float(q[i])) + sum((Fraction(float(a)) * b for a, b in zip(cols[i], zq)
                                          if a != 0.0), Fraction(0))
        if w < 0 or (w != 0 and z[i] != 0):
            return False
    return True
