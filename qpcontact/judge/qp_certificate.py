"""Certificates of QP answers (KKT conditions), computed from the data alone.

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

from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from ..core.errors import InvalidProblemError
from .doubt import doubt
from .scales import (Rows, abs_matvec, componentwise_scales, divide, inf_norm, max_abs, ratio,
                     row_scales)

if TYPE_CHECKING:
    from qpsolvers import Problem

__all__ = ["QPCertificate", "certify_qp"]


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
        """The backward error meets ``tol`` and nothing casts doubt on it
        (:func:`qpcontact.judge.doubt.doubt`)."""
        return bool(self.error <= tol) and doubt(self, tol) is None

    def as_dict(self) -> dict:
        return asdict(self)


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
    # x's natural size from the data, |q| / max|P|, floors the primal and gap
    # scales: at x = 0 on zero bounds they were rounding divided by rounding,
    # 1.0 for an exact answer (every step of a compliant tree's penalty QP),
    # and the doubt rule reads this measure (qpcontact.judge.doubt)
    top_P = max_abs(P)
    x_floor = inf_norm(q) / top_P if top_P > 0 else 0.0
    p_terms, d_terms = [0.0], [inf_norm(Px), inf_norm(q)]
    g_terms = [abs(float(x @ Px)), abs(float(q @ x)), inf_norm(q) * x_floor]
    comp_pairs = []
    min_mult = 0.0
    if G is not None:
        Gx = np.asarray(G @ x).ravel()
        p_terms += [inf_norm(Gx), inf_norm(h)]
        if sol.z is not None:
            d_terms.append(inf_norm(np.asarray(G.T @ sol.z).ravel()))
            g_terms.append(abs(float(h @ sol.z)))
            comp_pairs.append((sol.z, h - Gx, _row_inf_norms(G)))
            min_mult = min(min_mult, float(sol.z.min(initial=0.0)))
    if A is not None:
        Ax = np.asarray(A @ x).ravel()
        p_terms += [inf_norm(Ax), inf_norm(b)]
        if sol.y is not None:
            d_terms.append(inf_norm(np.asarray(A.T @ sol.y).ravel()))
            g_terms.append(abs(float(b @ sol.y)))
    if has_bounds:
        p_terms += [inf_norm(x), x_floor]
        zb = sol.z_box if sol.z_box is not None else np.zeros(n)
        d_terms.append(inf_norm(zb))
        for bound, sign in ((lb, -1.0), (ub, 1.0)):
            if bound is None:
                continue
            fin = np.isfinite(bound)
            p_terms.append(inf_norm(bound[fin]))
            mult = np.maximum(sign * zb[fin], 0.0)
            g_terms.append(abs(float(bound[fin] @ (sign * mult))))
            comp_pairs.append((mult, sign * (bound[fin] - x[fin]), 1.0))
    sigma_p, sigma_d, sigma_g = max(p_terms), max(d_terms), max(g_terms)
    comp_rel = 0.0
    for mult, slack, row_norm in comp_pairs:
        if mult.size:
            comp_rel = max(comp_rel, inf_norm(np.minimum(divide(mult * row_norm, sigma_d),
                                                          divide(slack, sigma_p))))
    return max(ratio(r_p, sigma_p), ratio(r_d, sigma_d), ratio(r_g, sigma_g), comp_rel,
               ratio(-min_mult, sigma_d))


@dataclass
class _KKTPoint:
    """A QP's data and a candidate primal-dual point, multipliers validated."""

    P: object
    q: np.ndarray
    G: object
    h: np.ndarray
    A: object
    b: np.ndarray
    lb: np.ndarray | None
    ub: np.ndarray | None
    x: np.ndarray
    y: np.ndarray | None
    z: np.ndarray | None
    z_box: np.ndarray | None

    @property
    def n(self) -> int:
        return self.q.shape[0]

    @property
    def has_bounds(self) -> bool:
        return self.lb is not None or self.ub is not None

    def missing(self) -> list:
        """The multipliers of constraints the problem has that were not given."""
        bounds = self.lb if self.lb is not None else self.ub
        return [name for name, mat, v in (("z (for G x <= h)", self.G, self.z),
                                          ("y (for A x = b)", self.A, self.y),
                                          ("z_box (for the bounds)", bounds, self.z_box))
                if mat is not None and v is None]


def _kkt_point(problem: Problem, x, y, z, z_box) -> _KKTPoint:
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
    return _KKTPoint(P, q, G, h, A, b, lb, ub, x, vector(y, A.shape[0] if A is not None else 0),
                     vector(z, G.shape[0] if G is not None else 0),
                     vector(z_box, n if has_bounds else 0))


def _absolute(mat):
    return abs(mat) if sp.issparse(mat) else np.abs(mat)


def _stationarity(k: _KKTPoint):
    """(Px + q + G'z + A'y + z_box, its rows' terms), each row against its own
    terms (the bounds' multipliers excluded from the scale: they must be
    balanced by the rest)."""
    grad = np.asarray(k.P @ k.x).ravel() + k.q
    S = row_scales(k.P, k.x, k.q)
    if k.G is not None and k.z is not None:
        grad += np.asarray(k.G.T @ k.z).ravel()
        S += abs_matvec(k.G.T, k.z)
    if k.A is not None and k.y is not None:
        grad += np.asarray(k.A.T @ k.y).ravel()
        S += abs_matvec(k.A.T, k.y)
    if k.z_box is not None:
        grad += k.z_box
    return grad, S


def _kkt_scales(k: _KKTPoint, S):
    """Each block of KKT rows with the unknowns that enter it;
    componentwise_scales gives every unknown its own scale and floors
    homogeneous rows.  Returns (the unknowns' scales, the rows' scales:
    stationarity, inequalities or None, equalities or None)."""
    x, q, G, h, A, b = k.x, k.q, k.G, k.h, k.A, k.b
    absG = _absolute(G) if G is not None else None
    absA = _absolute(A) if A is not None else None
    stat_blocks = {"x": _absolute(k.P)}
    if absG is not None and k.z is not None:
        stat_blocks["z"] = absG.T
    if absA is not None and k.y is not None:
        stat_blocks["y"] = absA.T
    rows = [Rows(S, np.abs(q), stat_blocks)]
    if G is not None:
        rows.append(Rows(row_scales(G, x, h), np.abs(h), {"x": absG}))
    if A is not None:
        rows.append(Rows(row_scales(A, x, b), np.abs(b), {"x": absA}))
    # x's own scale is capped by the normwise data floors (all in x's
    # units), each multiplier's by the normwise floor of its own block.
    cap_x = [inf_norm(x)]
    for vec, mat in ((q, k.P), (h, G), (b, A)):
        if mat is not None and max_abs(mat) > 0:
            cap_x.append(inf_norm(vec) / max_abs(mat))
    for bound in (k.lb, k.ub):
        if bound is not None:
            cap_x.append(inf_norm(bound[np.isfinite(bound)]))
    caps = {"x": max(cap_x)}
    for name, v, mat in (("z", k.z, G), ("y", k.y, A)):
        if v is not None and mat is not None:
            scale = max_abs(mat)
            caps[name] = max(inf_norm(v), inf_norm(q) / scale if scale > 0 else 0.0)
    unknown, sig = componentwise_scales(rows, caps)
    return unknown, sig[0], (sig[1] if G is not None else None), (sig[-1] if A is not None else None)


def _row_checks(k: _KKTPoint, grad, S, T, E, unknown):
    """Stationarity, the equalities, the inequalities and their
    complementarity: [(name, componentwise errors, words for component i:
    raw values and scales)], and (|min(z, slack)|∞, the most negative z)."""
    x, z, G, A = k.x, k.z, k.G, k.A
    checks: list[tuple[str, np.ndarray, object]] = [
        ("stationarity", divide(np.abs(grad), S),
         lambda i: f"(Px + q + G'z + A'y + z_box)_{i} = {grad[i]:.3e} against its row's "
                   f"scale {S[i]:.3e} (|P||x| + |q| + |G'||z| + |A'||y|, floored)")]
    if A is not None:
        r_eq = k.b - np.asarray(A @ x).ravel()
        checks.append(("equality", divide(np.abs(r_eq), E),
                       lambda i: f"b_{i} - (Ax)_{i} = {r_eq[i]:.3e} against its row's scale "
                                 f"{E[i]:.3e} (|A||x| + |b|, floored)"))
    comp_abs, min_mult = 0.0, 0.0
    if G is not None:
        slack = k.h - np.asarray(G @ x).ravel()
        if z is not None:
            zs = unknown["z"]
            checks.append(("inequality complementarity",
                           np.abs(np.minimum(divide(z, zs), divide(slack, T))),
                           lambda i: f"z_{i} = {z[i]:.3e} (scale {zs[i]:.3e}) and slack "
                                     f"h_{i} - (Gx)_{i} = {slack[i]:.3e} (scale {T[i]:.3e}): "
                                     "one must be >= 0 and the other 0"))
            comp_abs = max(comp_abs, inf_norm(np.minimum(z, slack)))
            min_mult = min(min_mult, float(z.min(initial=0.0)))
        else:
            checks.append(("inequality", divide(np.maximum(-slack, 0.0), T),
                           lambda i: f"h_{i} - (Gx)_{i} = {slack[i]:.3e} < 0 (scale {T[i]:.3e})"))
    return checks, comp_abs, min_mult


def _bound_checks(k: _KKTPoint, S, xi):
    """The bounds' complementarity and the multipliers' signs, as
    :func:`_row_checks` returns them."""
    n, x, lb, ub = k.n, k.x, k.lb, k.ub
    checks, comp_abs = [], 0.0
    zb = k.z_box if k.z_box is not None else np.zeros(n)
    lb_fin = np.isfinite(lb) if lb is not None else np.zeros(n, bool)
    ub_fin = np.isfinite(ub) if ub is not None else np.zeros(n, bool)
    for bound, fin, sign, name in ((lb, lb_fin, -1.0, "lower"), (ub, ub_fin, 1.0, "upper")):
        if not fin.any():
            continue
        idx = np.flatnonzero(fin)
        mult = np.maximum(sign * zb[idx], 0.0)
        bslack = sign * (bound[idx] - x[idx])
        e = np.zeros(n)
        e[idx] = np.abs(np.minimum(divide(mult, S[idx]),
                                   divide(bslack, np.abs(bound[idx]) + xi[idx])))
        full_slack = np.zeros(n)
        full_slack[idx] = bslack
        checks.append((f"{name} bound complementarity", e,
                       lambda i, sl=full_slack, nm=name:
                       f"z_box_{i} = {zb[i]:.3e} (scale {S[i]:.3e}) and the distance to "
                       f"the {nm} bound {sl[i]:.3e}: one must be >= 0 and the other 0"))
        comp_abs = max(comp_abs, inf_norm(np.minimum(mult, bslack)))
    # z_box_i < 0 claims an active lower bound, > 0 an active upper one: a
    # claim on a bound that does not exist is a multiplier of the wrong sign.
    illegal = np.where((zb < 0) & ~lb_fin, zb, 0.0) - np.where((zb > 0) & ~ub_fin, zb, 0.0)
    checks.append(("bound multiplier sign", divide(np.abs(illegal), S),
                   lambda i: f"z_box_{i} = {zb[i]:.3e} claims a bound x_{i} does not have "
                             f"(scale {S[i]:.3e})"))
    return checks, comp_abs, float(illegal.min(initial=0.0))


def _worst(checks):
    """(the condition and index, its error, its words) of the largest error."""
    worst_name, worst_val, detail = "", 0.0, ""
    for name, vals, words in checks:
        if vals.size:
            i = int(np.argmax(vals))
            if vals[i] > worst_val or not worst_name:
                worst_name, worst_val, detail = f"{name}[{i}]", float(vals[i]), words(i)
    return worst_name, worst_val, detail


def certify_qp(problem: Problem, x, y=None, z=None, z_box=None) -> QPCertificate:
    """Certificate of the primal-dual point (x, y, z, z_box) in qpsolvers'
    conventions: ``Px + q + A'y + G'z + z_box = 0``, z >= 0 for ``Gx <= h``,
    z_box < 0 at an active lower bound and > 0 at an active upper bound.

    A missing multiplier for constraints the problem has makes the error
    infinite (the point cannot be certified without it).
    """
    k = _kkt_point(problem, x, y, z, z_box)
    inf = np.inf
    if not all(np.all(np.isfinite(v)) for v in (k.x, k.y, k.z, k.z_box) if v is not None):
        return QPCertificate(inf, inf, "non-finite point", inf, inf, inf, inf, -inf)
    from qpsolvers import Solution   # a problem to judge means qpsolvers is loaded already

    sol = Solution(problem)
    sol.found = True
    sol.x, sol.y, sol.z, sol.z_box = k.x, k.y, k.z, k.z_box
    duals = k.z_box is not None or not k.has_bounds
    with np.errstate(over="ignore", invalid="ignore"):
        r_p = sol.primal_residual()
        r_d = sol.dual_residual() if duals else inf
        r_g = sol.duality_gap() if duals else inf
        normwise = _qp_normwise(problem, k.x, sol, k.has_bounds)
        grad, S = _stationarity(k)
        if not (np.all(np.isfinite(grad)) and np.all(np.isfinite(S))):
            return QPCertificate(inf, normwise, "overflow", r_p, r_d, r_g, inf, -inf, True)
        unknown, S, T, E = _kkt_scales(k, S)
        checks, comp_abs, min_mult = _row_checks(k, grad, S, T, E, unknown)
        if k.has_bounds:
            more, bound_comp, bound_sign = _bound_checks(k, S, unknown["x"])
            checks += more
            comp_abs = max(comp_abs, bound_comp)
            min_mult = min(min_mult, bound_sign)
    worst_name, worst_val, detail = _worst(checks)
    missing = k.missing()
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
