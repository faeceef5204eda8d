"""Proofs that a convex QP has no minimiser: Farkas vectors and rays.

    minimise ½ x'Px + q'x   subject to  Gx <= h,  Ax = b,  lb <= x <= ub

has no minimiser exactly when it is infeasible or unbounded below (P PSD:
Frank–Wolfe).  Both have certificates that a person can check from the data
alone, without trusting whoever found them:

* **infeasible** — multipliers z >= 0, y, μl >= 0, μu >= 0 with
  r = G'z + A'y − μl + μu = 0 and c = h'z + b'y − lb'μl + ub'μu < 0: summing
  the constraints with these weights gives x'r <= c < 0, impossible for r = 0.
  With a rounded r ≠ 0 it still proves that no feasible x has
  max|x_i| < |c| / ‖r‖₁ (the bound is reported);
* **unbounded** — a feasible x0 and a direction d with Pd = 0, Gd <= 0,
  Ad = 0, d_i >= 0 where lb_i is finite, d_i <= 0 where ub_i is finite, and
  q'd < 0: the objective along x0 + t d falls linearly for ever.  With a
  rounded Pd ≠ 0 it falls by at least (q'd + x0'Pd)² / (2 d'Pd) (reported).

Backends say "infeasible" in their own words and on their own absolute
tolerances; QP backends also loop for a long time on such problems (an
unbounded QP took every backend of "auto" in turn).  Here each certificate is
found by one linear program (HiGHS through :func:`scipy.optimize.linprog`,
with every constraint row scaled to unit size so that the LP's absolute
tolerances mean the same on every row) and accepted only after the checks
above are computed from the data, each residual on its own row's scale.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["QPProof", "prove_no_minimiser"]

_EPS = np.finfo(float).eps
#: a Farkas vector must rule out every feasible point up to this many times
#: the size the data give x (bounds, h_i / |G_i|, b_i / |A_i|)
_REACH = 1e6
#: relative residual |(Pd)_i| / (|P||d|)_i accepted for a ray (and the same
#: for G d <= 0, A d = 0): rounding of a direction computed in double precision
_RAY_RES = 1e-12


@dataclass
class QPProof:
    """A checked certificate that a QP has no minimiser.

    ``kind`` is "infeasible" (``vector`` = (z, y, μl, μu) multipliers of
    G, A, lb, ub) or "unbounded" (``vector`` = the direction d, ``point`` = a
    feasible x0).  ``message`` says what was proved, in numbers."""

    kind: str
    message: str
    vector: dict
    point: np.ndarray | None = None


def _rows(M, n):
    if M is None:
        return sp.csr_matrix((0, n))
    return sp.csr_matrix(M)


def _row_scale(M: sp.csr_matrix) -> np.ndarray:
    big = np.zeros(M.shape[0])
    if M.nnz:
        big = np.asarray(abs(M).max(axis=1).toarray()).ravel()
    return np.where(big > 0, 1.0 / np.where(big > 0, big, 1.0), 0.0)


def _linprog(c, A_ub=None, b_ub=None, A_eq=None, b_eq=None, bounds=None):
    from scipy.optimize import linprog

    options = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10,
               "time_limit": 30.0}
    with np.errstate(all="ignore"):
        try:
            return linprog(c, A_ub=A_ub, b_ub=b_ub, A_eq=A_eq, b_eq=b_eq, bounds=bounds,
                           method="highs", options=options)
        except (ValueError, MemoryError):
            return None


def _farkas(P, q, G, h, A, b, lb, ub) -> QPProof | None:
    n = q.size
    G, A = _rows(G, n), _rows(A, n)
    h = np.zeros(0) if h is None else np.asarray(h, float)
    b = np.zeros(0) if b is None else np.asarray(b, float)
    il = np.flatnonzero(np.isfinite(lb)) if lb is not None else np.zeros(0, int)
    iu = np.flatnonzero(np.isfinite(ub)) if ub is not None else np.zeros(0, int)
    if G.shape[0] + A.shape[0] + il.size + iu.size == 0:
        return None
    sg, sa = _row_scale(G), _row_scale(A)
    Gs, As = sp.diags(sg) @ G, sp.diags(sa) @ A
    El = sp.csr_matrix((np.ones(il.size), (il, np.arange(il.size))), shape=(n, il.size))
    Eu = sp.csr_matrix((np.ones(iu.size), (iu, np.arange(iu.size))), shape=(n, iu.size))
    lbf = lb[il] if il.size else np.zeros(0)
    ubf = ub[iu] if iu.size else np.zeros(0)
    A_eq = sp.hstack([Gs.T, As.T, -El, Eu]).tocsc()
    cost = np.concatenate([sg * h, sa * b, -lbf, ubf])
    bounds = ([(0, 1)] * G.shape[0] + [(-1, 1)] * A.shape[0] + [(0, 1)] * (il.size + iu.size))
    res = _linprog(cost, A_eq=A_eq, b_eq=np.zeros(n), bounds=bounds)
    if res is None or res.status != 0 or res.x is None or not res.fun < 0:
        return None
    v = res.x
    k = np.cumsum([0, G.shape[0], A.shape[0], il.size, iu.size])
    z, y = sg * np.maximum(v[k[0]:k[1]], 0.0), sa * v[k[1]:k[2]]
    ml, mu = np.maximum(v[k[2]:k[3]], 0.0), np.maximum(v[k[3]:k[4]], 0.0)
    r = G.T @ z + A.T @ y - El @ ml + Eu @ mu
    c = h @ z + b @ y - lbf @ ml + ubf @ mu
    c_round = 4 * (n + 1) * _EPS * (np.abs(h) @ z + np.abs(b) @ np.abs(y)
                                     + np.abs(lbf) @ ml + np.abs(ubf) @ mu)
    if not (np.all(np.isfinite(r)) and np.isfinite(c)) or not c < -c_round:
        return None
    size = [np.abs(lbf), np.abs(ubf)]
    for M, rhs in ((G, h), (A, b)):
        if M.shape[0]:
            big = np.asarray(abs(M).max(axis=1).toarray()).ravel()
            size.append(np.abs(rhs[big > 0]) / big[big > 0])
    x_size = max([float(s.max()) for s in size if s.size] + [np.finfo(float).tiny])
    r1 = float(np.abs(r).sum())
    reach = np.inf if r1 == 0.0 else abs(c) / r1
    if reach < _REACH * x_size:
        return None
    where = ("" if reach == np.inf else
             f" (the rounded multipliers leave ‖G'z + A'y − μl + μu‖₁ = {r1:.1e}: no feasible x "
             f"has max|x_i| < {reach:.1e}, {reach / x_size:.0e} times the size the data give x)")
    parts = [f"{name}: {int(np.count_nonzero(vec))}" for name, vec in
             (("inequality rows", z), ("equality rows", y), ("lower bounds", ml),
              ("upper bounds", mu)) if np.count_nonzero(vec)]
    return QPProof(
        kind="infeasible",
        message=("no x satisfies the constraints: the weighted sum of "
                 + ", ".join(parts)
                 + f" reads 0 <= {c:.3e} (a Farkas vector, checked from the data){where}"),
        vector={"z": z, "y": y, "lower": ml, "upper": mu},
    )


def _feasible_point(q, G, h, A, b, lb, ub) -> np.ndarray | None:
    n = q.size
    G, A = _rows(G, n), _rows(A, n)
    sg, sa = _row_scale(G), _row_scale(A)
    lo = lb if lb is not None else np.full(n, -np.inf)
    hi = ub if ub is not None else np.full(n, np.inf)
    bounds = list(zip(np.where(np.isfinite(lo), lo, None), np.where(np.isfinite(hi), hi, None)))
    res = _linprog(np.zeros(n), A_ub=(sp.diags(sg) @ G).tocsc() if G.shape[0] else None,
                   b_ub=sg * h if G.shape[0] else None,
                   A_eq=(sp.diags(sa) @ A).tocsc() if A.shape[0] else None,
                   b_eq=sa * b if A.shape[0] else None, bounds=bounds)
    if res is None or res.status != 0 or res.x is None:
        return None
    x = np.clip(res.x, lo, hi)
    # checked, not believed: each row's violation against its own scale
    for M, rhs, eq in ((G, h, False), (A, b, True)):
        if not M.shape[0]:
            continue
        r = M @ x - rhs
        scale = abs(M) @ np.abs(x) + np.abs(rhs)
        bad = np.abs(r) if eq else np.maximum(r, 0.0)
        if np.any(bad > 1e-9 * scale + np.finfo(float).tiny):
            return None
    return x


def _ray(P, q, G, h, A, b, lb, ub) -> QPProof | None:
    n = q.size
    P = sp.csr_matrix(P)
    G, A = _rows(G, n), _rows(A, n)
    sp_, sg, sa = _row_scale(P), _row_scale(G), _row_scale(A)
    keep = sp_ > 0
    Ps = (sp.diags(sp_) @ P)[np.flatnonzero(keep)]
    blocks_eq = [m for m in (Ps, sp.diags(sa) @ A) if m.shape[0]]
    A_eq = sp.vstack(blocks_eq).tocsc() if blocks_eq else None
    A_ub = (sp.diags(sg) @ G).tocsc() if G.shape[0] else None
    lo = np.where(np.isfinite(lb), 0.0, -1.0) if lb is not None else -np.ones(n)
    hi = np.where(np.isfinite(ub), 0.0, 1.0) if ub is not None else np.ones(n)
    res = _linprog(q, A_ub=A_ub, b_ub=np.zeros(A_ub.shape[0]) if A_ub is not None else None,
                   A_eq=A_eq, b_eq=np.zeros(A_eq.shape[0]) if A_eq is not None else None,
                   bounds=list(zip(lo, hi)))
    if res is None or res.status != 0 or res.x is None:
        return None
    d = np.clip(res.x, lo, hi)
    slope = float(q @ d)
    if not slope < -4 * n * _EPS * float(np.abs(q) @ np.abs(d)):
        return None
    absd = np.abs(d)
    Pd = P @ d
    checks = [(np.abs(Pd), abs(P) @ absd)]
    if G.shape[0]:
        checks.append((np.maximum(G @ d, 0.0), abs(G) @ absd))
    if A.shape[0]:
        checks.append((np.abs(A @ d), abs(A) @ absd))
    for res_, scale in checks:
        if np.any(res_ > _RAY_RES * scale):
            return None
    x0 = _feasible_point(q, G, h, A, b, lb, ub)
    if x0 is None:
        return None
    curv = float(d @ Pd)
    rate = slope + float(x0 @ Pd)
    if not rate < 0:
        return None
    fall = np.inf if curv <= 0 else rate * rate / (2.0 * curv)
    f0 = 0.5 * float(x0 @ (P @ x0)) + float(q @ x0)
    how = ("for ever (Pd = 0 exactly)" if fall == np.inf
           else f"by at least {fall:.1e} (Pd is zero up to rounding: d'Pd = {curv:.1e})")
    return QPProof(
        kind="unbounded",
        message=(f"the objective is unbounded below: from the feasible point x0 (objective "
                 f"{f0:.3e}) along the direction d (q'd = {slope:.3e}, Pd = 0, Gd <= 0, Ad = 0 and "
                 f"the bounds' signs, checked from the data) it falls {how}"),
        vector={"d": d},
        point=x0,
    )


def prove_no_minimiser(problem) -> QPProof | None:
    """A checked Farkas vector or ray for a convex ``qpsolvers.Problem``, or
    None when neither is found (the QP may still have no minimiser; nothing
    is claimed then)."""
    P, q, G, h, A, b, lb, ub = problem.unpack()
    q = np.asarray(q, dtype=float)
    proof = _farkas(P, q, G, h, A, b, lb, ub)
    if proof is None:
        proof = _ray(P, q, G, h, A, b, lb, ub)
    return proof
