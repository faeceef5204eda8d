"""Certificates: residuals computed from the problem data and a candidate point.

Nothing a backend reports about its own answer is used here.  Every method's
answer goes through :func:`certify`, the shared error measure (in the spirit of
Siconos' ``lcp_compute_error``), so numbers mean the same for every method.

LCP (z, w = Mz + q)
-------------------
The natural residual r = min(z, w) (componentwise) is zero exactly at a
solution: a negative z_i or w_i, or a pair with both positive, all show in it.
Reported:

- ``comp_abs = ‖min(z, w)‖∞`` — absolute, in the units of z and w mixed;
- ``siconos_error = ‖min(z, w)‖₂ / ‖q‖₂`` (not normalised when ‖q‖₂ <= DBL_EPSILON),
  Siconos' relative form, to compare with its solvers' published figures;
- ``min_z``, ``min_w`` — the most negative entries (0 when none is negative);
- ``zw = z'w``;
- ``error`` — the **scale-free** measure that decides ``ok``:

      error = max_i | min(z_i / σ_z, w_i / σ_w) |,
      σ_z = max(‖z‖∞, ‖q‖∞ / max|M_ij|),  σ_w = max(‖Mz‖∞, ‖q‖∞)

  Each side is measured against its own magnitude, so multiplying M by 1e8
  (stiff contacts) or q by 1e-8 (tiny loads) leaves ``error`` unchanged: z and
  w have different units and a mixed absolute norm would favour one of them.
  The floor ‖q‖/max|M| (the size z would need to move w by ‖q‖) keeps a
  solution z = 0 from being judged against the noise in its own entries.
  This is the relative complementarity residual of the QP form below with the
  same scalings, so an LCP solved as a QP is judged identically either way.

QP (qpsolvers.Problem: min ½x'Px + q'x, Gx <= h, Ax = b, lb <= x <= ub)
-------------------------------------------------------------------------
``primal_residual``, ``dual_residual`` and ``duality_gap`` are exactly
qpsolvers' definitions (computed by ``qpsolvers.Solution`` from our copy of the
point).  They are not enough: the gap is a sum over constraints, so every
single pair can be off by √gap while the sum looks tiny, and qpsolvers never
checks the sign of inequality multipliers.  So the certificate adds the
per-constraint complementarity ``|min(multiplier_i, slack_i)|`` (a negative
multiplier shows in it) and ``error`` is

    max( r_p / σ_p,  r_d / σ_d,  r_g / σ_g,
         max_i |min(μ_i ‖row_i‖∞ / σ_d,  s_i / σ_p)| )

with σ_p the largest of ‖Gx‖, ‖h‖, ‖Ax‖, ‖b‖ and the finite bound and x
magnitudes; σ_d the largest of ‖Px‖, ‖q‖, ‖A'y‖, ‖G'z‖, ‖z_box‖; σ_g the largest
term of the gap — OSQP's relative residuals, applied per constraint.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
import scipy.sparse as sp
from qpsolvers import Problem
from qpsolvers import Solution as _QPSolution

from .errors import InvalidProblemError
from .problems import LCP

__all__ = ["certify", "LCPCertificate", "QPCertificate"]

_EPS = np.finfo(float).eps


def _ratio(num: float, den: float) -> float:
    """num / den, with 0/0 = 0 and x/0 = inf."""
    if num == 0.0:
        return 0.0
    return num / den if den > 0.0 else np.inf


def _scaled(v: np.ndarray, sigma: float) -> np.ndarray:
    """v / sigma elementwise, with the same 0/0 = 0, x/0 = ±inf rule as _ratio."""
    if sigma > 0.0:
        return v / sigma
    with np.errstate(invalid="ignore"):  # 0 * inf in the branch np.where discards
        return np.where(v == 0, 0.0, np.sign(v) * np.inf)


def _inf_norm(v) -> float:
    return float(np.max(np.abs(v))) if np.size(v) else 0.0


@dataclass(frozen=True)
class LCPCertificate:
    """Residuals of a candidate z for LCP(M, q); see the module docstring."""

    error: float
    comp_abs: float
    siconos_error: float
    min_z: float
    min_w: float
    zw: float

    def ok(self, tol: float) -> bool:
        return bool(self.error <= tol)

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class QPCertificate:
    """Residuals of a candidate (x, y, z, z_box) for a QP; see the module docstring."""

    error: float
    primal_residual: float
    dual_residual: float
    duality_gap: float
    comp_abs: float
    min_multiplier: float

    def ok(self, tol: float) -> bool:
        return bool(self.error <= tol)

    def as_dict(self) -> dict:
        return asdict(self)


def _bad_lcp_certificate() -> LCPCertificate:
    inf = np.inf
    return LCPCertificate(inf, inf, inf, -inf, -inf, inf)


def certify_lcp(lcp: LCP, z) -> LCPCertificate:
    """Certificate of z for ``lcp`` (see the module docstring)."""
    z = np.asarray(z, dtype=float).ravel()
    if z.shape != (lcp.n,):
        raise InvalidProblemError(f"z has shape {z.shape}; the LCP has n = {lcp.n} unknowns")
    if not np.all(np.isfinite(z)):
        return _bad_lcp_certificate()
    Mz = np.asarray(lcp.M @ z).ravel()
    w = Mz + lcp.q
    r = np.minimum(z, w)
    scale_M = lcp.matrix_scale
    sigma_z = max(_inf_norm(z), _inf_norm(lcp.q) / scale_M if scale_M > 0 else 0.0)
    sigma_w = max(_inf_norm(Mz), _inf_norm(lcp.q))
    error = _inf_norm(np.minimum(_scaled(z, sigma_z), _scaled(w, sigma_w)))
    qn = float(np.linalg.norm(lcp.q))
    rn = float(np.linalg.norm(r))
    return LCPCertificate(
        error=float(error),
        comp_abs=_inf_norm(r),
        siconos_error=rn / qn if qn > _EPS else rn,
        min_z=float(min(z.min(), 0.0)),
        min_w=float(min(w.min(), 0.0)),
        zw=float(z @ w),
    )


def _row_inf_norms(G) -> np.ndarray:
    if sp.issparse(G):
        return np.asarray(abs(G).max(axis=1).todense()).ravel()
    return np.max(np.abs(G), axis=1) if G.shape[1] else np.zeros(G.shape[0])


def certify_qp(problem: Problem, x, y=None, z=None, z_box=None) -> QPCertificate:
    """Certificate of the primal-dual point (x, y, z, z_box) in qpsolvers'
    conventions: ``Px + q + A'y + G'z + z_box = 0``, z >= 0 for ``Gx <= h``,
    z_box < 0 at an active lower bound and > 0 at an active upper bound.

    A missing multiplier for constraints the problem has makes the dual
    residual infinite (the point cannot be certified without it).
    """
    P, q, G, h, A, b, lb, ub = problem.unpack()
    n = q.shape[0]
    x = np.asarray(x, dtype=float).ravel()
    if x.shape != (n,):
        raise InvalidProblemError(f"x has shape {x.shape}; the QP has n = {n} variables")
    vecs = [x] + [np.asarray(v, float).ravel() for v in (y, z, z_box) if v is not None]
    if not all(np.all(np.isfinite(v)) for v in vecs):
        inf = np.inf
        return QPCertificate(inf, inf, inf, inf, inf, -inf)

    sol = _QPSolution(problem)
    sol.found = True
    sol.x = x
    sol.y = None if y is None else np.asarray(y, float).ravel()
    sol.z = None if z is None else np.asarray(z, float).ravel()
    sol.z_box = None if z_box is None else np.asarray(z_box, float).ravel()
    # qpsolvers' dual residual silently treats a missing z_box as zero.
    has_bounds = lb is not None or ub is not None
    r_p = sol.primal_residual()
    r_d = sol.dual_residual() if (z_box is not None or not has_bounds) else np.inf
    r_g = sol.duality_gap() if (z_box is not None or not has_bounds) else np.inf

    Px = np.asarray(P @ x).ravel()
    p_terms, d_terms = [0.0], [_inf_norm(Px), _inf_norm(q)]
    g_terms = [abs(float(x @ Px)), abs(float(q @ x))]
    comp_pairs = []  # (multipliers, slacks, row norms) per constraint block
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
            slack = sign * (bound[fin] - x[fin])
            g_terms.append(abs(float(bound[fin] @ (sign * mult))))
            comp_pairs.append((mult, slack, 1.0))
        # z_box_i < 0 claims an active lower bound, > 0 an active upper one: a
        # claim on a bound that does not exist is a multiplier of the wrong sign.
        lb_fin = np.isfinite(lb) if lb is not None else np.zeros(n, bool)
        ub_fin = np.isfinite(ub) if ub is not None else np.zeros(n, bool)
        illegal = np.where((zb < 0) & ~lb_fin, zb, 0.0) - np.where((zb > 0) & ~ub_fin, zb, 0.0)
        min_mult = min(min_mult, float(illegal.min(initial=0.0)))

    sigma_p, sigma_d, sigma_g = max(p_terms), max(d_terms), max(g_terms)
    comp_abs, comp_rel = 0.0, 0.0
    for mult, slack, row_norm in comp_pairs:
        if mult.size:
            comp_abs = max(comp_abs, _inf_norm(np.minimum(mult, slack)))
            comp_rel = max(comp_rel, _inf_norm(np.minimum(_scaled(mult * row_norm, sigma_d),
                                                          _scaled(slack, sigma_p))))
    error = max(_ratio(r_p, sigma_p), _ratio(r_d, sigma_d), _ratio(r_g, sigma_g), comp_rel,
                _ratio(-min_mult, sigma_d))
    return QPCertificate(
        error=float(error),
        primal_residual=float(r_p),
        dual_residual=float(r_d),
        duality_gap=float(r_g),
        comp_abs=float(comp_abs),
        min_multiplier=float(min_mult),
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
        ``cert.error`` is the scale-free measure compared with the requested
        tolerance (``cert.ok(tol)``); see the module docstring for every field.
    """
    if isinstance(problem, LCP):
        return certify_lcp(problem, x)
    if isinstance(problem, Problem):
        return certify_qp(problem, x, y, z, z_box)
    raise InvalidProblemError(f"cannot certify a {type(problem).__name__}; expected an LCP or a qpsolvers.Problem")
