"""Proofs that a convex QP has no minimiser: Farkas vectors and rays.

    minimise ½ x'Px + q'x   subject to  Gx <= h,  Ax = b,  lb <= x <= ub

has no minimiser exactly when it is infeasible or unbounded below (P PSD:
Frank–Wolfe).  Both have certificates that a person can check from the data
alone, without trusting whoever found them:

* **infeasible** — multipliers z >= 0, y, μl >= 0, μu >= 0 with
  r = G'z + A'y − μl + μu = 0 and c = h'z + b'y − lb'μl + ub'μu < 0: summing
  the constraints with these weights gives x'r <= c < 0, impossible;
* **unbounded** — a feasible x0 and a direction d with Pd = 0, Gd <= 0,
  Ad = 0, d_i >= 0 where lb_i is finite, d_i <= 0 where ub_i is finite, and
  q'd < 0: the objective along x0 + t d falls linearly for ever.

Both are checked in **exact rational arithmetic** (the data's doubles are
rationals; :class:`fractions.Fraction`), on the LP's vector and on the same
vector snapped to small denominators (which recovers the exact weights of
integer data).  A check in floating point is not a proof: with a rounded
r ≈ 1e-16 a Farkas vector only rules out feasible points up to |c| / ‖r‖₁,
and on a badly scaled but solvable LCP the solution lay beyond that (a false
"infeasible", caught by ``qpcontact stress``).  The price: on data whose
exact Farkas vector or ray has no short rational form nothing is proved and
the answer stays "failed"/"inaccurate" — never a claim that is not true.
The exact check (:mod:`qpcontact.proofs.exact`, in integers) is skipped above EXACT_WORK
products and stops at the proof's deadline.

Backends say "infeasible" in their own words and on their own absolute
tolerances; QP backends also loop for a long time on such problems (an
unbounded QP took every backend of "auto" in turn).  Here each certificate is
found by one linear program (HiGHS through :func:`scipy.optimize.linprog`,
with every constraint row scaled to unit size so that the LP's absolute
tolerances mean the same on every row) and accepted only after the checks
above are computed from the data.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import scipy.sparse as sp

from .exact import FarkasCheck, Proof, RayCheck, candidates, exactly_within
from .lp import (NULL_SPACE_MAX_N, column_scale, csr_rows, linprog, null_basis, row_abs_max,
                 proof_deadline, row_scale)

__all__ = ["prove_no_minimiser", "find_farkas", "x_size"]


def find_farkas(P, q, G, h, A, b, lb, ub, tl) -> Proof | None:
    n = q.size
    G, A = csr_rows(G, n), csr_rows(A, n)
    h = np.zeros(0) if h is None else np.asarray(h, float)
    b = np.zeros(0) if b is None else np.asarray(b, float)
    il = np.flatnonzero(np.isfinite(lb)) if lb is not None else np.zeros(0, int)
    iu = np.flatnonzero(np.isfinite(ub)) if ub is not None else np.zeros(0, int)
    if G.shape[0] + A.shape[0] + il.size + iu.size == 0:
        return None
    sg, sa = row_scale(G), row_scale(A)
    Gs, As = sp.diags(sg) @ G, sp.diags(sa) @ A
    El = sp.csr_matrix((np.ones(il.size), (il, np.arange(il.size))), shape=(n, il.size))
    Eu = sp.csr_matrix((np.ones(iu.size), (iu, np.arange(iu.size))), shape=(n, iu.size))
    lbf = lb[il] if il.size else np.zeros(0)
    ubf = ub[iu] if iu.size else np.zeros(0)
    A_eq = sp.hstack([Gs.T, As.T, -El, Eu]).tocsr()
    # each equation (one per variable) at unit size as well: a variable
    # scaled by 1e-6 otherwise leaves its equation under HiGHS's tolerance
    A_eq = (sp.diags(row_scale(A_eq)) @ A_eq).tocsc()
    cost = np.concatenate([sg * h, sa * b, -lbf, ubf])
    if not np.all(np.isfinite(cost)):
        return None  # data beyond double precision's range once scaled: nothing to prove here
    bounds = ([(0, 1)] * G.shape[0] + [(-1, 1)] * A.shape[0] + [(0, 1)] * (il.size + iu.size))
    res = linprog(cost, A_eq=A_eq, b_eq=np.zeros(n), bounds=bounds, time_limit=tl)
    if res is None or res.status != 0 or res.x is None or not res.fun < 0:
        return None
    v = res.x
    k = np.cumsum([0, G.shape[0], A.shape[0], il.size, iu.size])
    lo = lb if lb is not None else np.full(n, -np.inf)
    hi = ub if ub is not None else np.full(n, np.inf)
    weights = np.concatenate([sg * np.maximum(v[k[0]:k[1]], 0.0), sa * v[k[1]:k[2]]])
    top = float(np.max(np.abs(weights), initial=0.0))
    if not top > 0:
        return None
    check = FarkasCheck(G, h, A, b, lo, hi)
    for exact in candidates(weights / top, tl):   # the ratios are what matters: 1 : 2 : 3
        proof = check.check(exact, tl)
        if proof is not None:
            return proof
    return None


def _x_size(G, h, A, b, lbf, ubf) -> float:
    """The size the data give x: finite bounds, h_i / max|G_i|, b_i / max|A_i|."""
    size = [np.abs(lbf), np.abs(ubf)]
    for M, rhs in ((G, h), (A, b)):
        if M.shape[0]:
            big = row_abs_max(M)
            size.append(np.abs(rhs[big > 0]) / big[big > 0])
    return max([float(s.max()) for s in size if s.size] + [np.finfo(float).tiny])


def x_size(problem) -> float:
    """The size a QP's data give x (bounds, h_i / max|G_i|, b_i / max|A_i|,
    q_i / max|P_i|): an answer far beyond it is suspect (it may be a point
    of nearby data whose problem has no minimiser)."""
    P, q, G, h, A, b, lb, ub = problem.unpack()
    n = q.size
    lbf = lb[np.isfinite(lb)] if lb is not None else np.zeros(0)
    ubf = ub[np.isfinite(ub)] if ub is not None else np.zeros(0)
    return max(_x_size(csr_rows(G, n), h, csr_rows(A, n), b, lbf, ubf),
               _x_size(csr_rows(P, n), np.asarray(q, float), csr_rows(None, n), None, lbf[:0], ubf[:0]))


def _is_feasible(x, G, h, A, b, lo, hi) -> bool:
    """Each row's violation against its own scale (checked, not believed)."""
    if not (np.all(np.isfinite(x)) and np.all(x >= lo) and np.all(x <= hi)):
        return False
    for M, rhs, eq in ((G, h, False), (A, b, True)):
        if not M.shape[0]:
            continue
        r = M @ x - rhs
        scale = abs(M) @ np.abs(x) + np.abs(rhs)
        bad = np.abs(r) if eq else np.maximum(r, 0.0)
        if np.any(bad > 1e-9 * scale + np.finfo(float).tiny):
            return False
    return True


def _feasible_point(q, G, h, A, b, lb, ub, tl) -> np.ndarray | None:
    n = q.size
    G, A = csr_rows(G, n), csr_rows(A, n)
    lo = lb if lb is not None else np.full(n, -np.inf)
    hi = ub if ub is not None else np.full(n, np.inf)
    x = np.clip(np.zeros(n), lo, hi)
    if _is_feasible(x, G, h, A, b, lo, hi):
        return x
    c = column_scale((G, A), n)
    Cd = sp.diags(c)
    Gc, Ac = G @ Cd, A @ Cd
    sg, sa = row_scale(Gc), row_scale(Ac)
    lo_c, hi_c = lo / c, hi / c
    bounds = list(zip(np.where(np.isfinite(lo_c), lo_c, None),
                      np.where(np.isfinite(hi_c), hi_c, None)))
    res = linprog(np.zeros(n), A_ub=(sp.diags(sg) @ Gc).tocsc() if G.shape[0] else None,
                   b_ub=sg * h if G.shape[0] else None,
                   A_eq=(sp.diags(sa) @ Ac).tocsc() if A.shape[0] else None,
                   b_eq=sa * b if A.shape[0] else None, bounds=bounds, time_limit=tl)
    if res is None or res.status != 0 or res.x is None:
        return None
    x = np.clip(res.x * c, lo, hi)
    return x if _is_feasible(x, G, h, A, b, lo, hi) else None


def _ray(P, q, G, h, A, b, lb, ub, tl) -> Proof | None:
    n = q.size
    P = sp.csr_matrix(P)
    G, A = csr_rows(G, n), csr_rows(A, n)
    lo = np.where(np.isfinite(lb), 0.0, -1.0) if lb is not None else -np.ones(n)
    hi = np.where(np.isfinite(ub), 0.0, 1.0) if ub is not None else np.ones(n)
    # d = c * d~, then every row of the column-scaled matrices at unit size.
    # Where P_jj > 0, c_j = P_jj^-1/2 (to a power of two): the ray lies in P's
    # null space, and Jacobi scaling undoes any diagonal scaling x = D x' of
    # the variables, where column maxima mix the other columns' scales.  With
    # rows scaled before columns, entries of 1e-9..1e-6 fell under HiGHS's
    # absolute tolerances: on QPs scaled over 12 decades the LP then found no
    # ray, or one whose small components had no correct digit.
    c = column_scale((P, G, A), n)
    pdiag = np.asarray(P.diagonal(), dtype=float)
    pos = pdiag > 0
    c[pos] = 2.0 ** -np.round(0.5 * np.log2(pdiag[pos]))
    Cd = sp.diags(c)
    Pc, Gc, Ac = P @ Cd, G @ Cd, A @ Cd
    sp_, sg, sa = row_scale(Pc), row_scale(Gc), row_scale(Ac)
    Ps = (sp.diags(sp_) @ Pc)[np.flatnonzero(sp_ > 0)]
    blocks_eq = [m for m in (Ps, sp.diags(sa) @ Ac) if m.shape[0]]
    A_eq = sp.vstack(blocks_eq).tocsc() if blocks_eq else None
    A_ub = (sp.diags(sg) @ Gc).tocsc() if G.shape[0] else None
    cost = q * c
    top_cost = float(np.max(np.abs(cost), initial=0.0))
    if not np.isfinite(top_cost) or not top_cost > 0:
        return None  # q'd = 0 for every d: no descent direction
    dF = None
    cF = [Fraction(float(v)) for v in c]
    ray = None      # the data as integers: made for the first candidate
    # The cost at unit size too (HiGHS's dual tolerance is absolute: a cost
    # of 1e-9 entries was declared optimal at d = 0).  HiGHS's own
    # tolerances first, then 1e-10: each missed rays the other found (at
    # 1e-10 it called d = 0 optimal beside a rank-deficient P block where the
    # default found q'd = -0.1); the exact check decides.
    descent = False     # whether an LP found q'd < 0 at all: else no sparse search
    for attempt in ("default", "tight", "sparse", "sparse-unscaled"):
        if attempt.startswith("sparse") and not descent:
            break
        if attempt == "sparse-unscaled":
            # the data's own columns: the sparse vertex differs, and each
            # scaling proved rays the other missed (3 of the 14 above)
            rows = [(sp.diags(row_scale(M)) @ M).tocsc() if M.shape[0] else None
                    for M in (P, G, A)]
            eq = [M for M in (rows[0], rows[2]) if M is not None]
            top_q = float(np.max(np.abs(q)))
            dt = _sparse_ray(q / top_q, rows[1], sp.vstack(eq).tocsc() if eq else None, lo, hi,
                             tl)
            if dt is not None:
                dt = dt / c
        elif attempt == "sparse":
            dt = _sparse_ray(cost / top_cost, A_ub, A_eq, lo, hi, tl)
        if attempt.startswith("sparse"):
            if dt is None:
                continue
        else:
            res = linprog(cost / top_cost, A_ub=A_ub,
                          b_ub=np.zeros(A_ub.shape[0]) if A_ub is not None else None,
                          A_eq=A_eq, b_eq=np.zeros(A_eq.shape[0]) if A_eq is not None else None,
                          bounds=list(zip(lo, hi)), time_limit=tl, tight=attempt == "tight")
            if res is None or res.status != 0 or res.x is None or not res.fun < 0:
                continue
            descent = True
            dt = np.clip(res.x, lo, hi)
        # snapped in the LP's balanced coordinates, where a component that is
        # exactly 0 reads 1e-8 beside 1, not beside 1e-12 (components of d
        # itself span the data's decades), and mapped back exactly (c_j are
        # powers of two)
        top = float(np.max(np.abs(dt), initial=0.0))
        if not top > 0 or tl.expired():
            continue
        ray = ray or RayCheck(P, q, G, A, lo, hi)
        dF = next((d for d in ([v * cj for v, cj in zip(vt, cF)]
                                for vt in candidates(dt / top, tl))
                   if ray.check(d, tl)), None)
        if dF is not None:
            break
    if dF is None:
        return None
    return _unbounded(P, q, G, h, A, b, lb, ub, dF, tl)


def _sparse_ray(cost, A_ub, A_eq, lo, hi, tl) -> np.ndarray | None:
    """A ray with few nonzeros: min ‖d‖₁ with cost'd = -1 (d = d⁺ - d⁻).
    Where P's null space has several directions, the first LPs return a mix
    of them whose weights have no short rational form (rounded data: 6 of 14
    unproved cases of the rounded unbounded family); a vertex of this LP is
    one exact null vector, whose few entries snap (8 of those 14)."""
    n = cost.size
    def split(M):
        return None if M is None else sp.hstack([M, -M]).tocsc()

    normalise = sp.csr_matrix(np.r_[cost, -cost][None, :])
    A = sp.vstack([M for M in (split(A_eq), normalise) if M is not None]).tocsc()
    b = np.zeros(A.shape[0])
    b[-1] = -1.0
    bounds = [(0.0, None if h > 0 else 0.0) for h in hi] + [(0.0, None if lo_ < 0 else 0.0)
                                                              for lo_ in lo]
    res = linprog(np.ones(2 * n), A_ub=split(A_ub), b_ub=None if A_ub is None else
                  np.zeros(A_ub.shape[0]), A_eq=A, b_eq=b, bounds=bounds, time_limit=tl)
    if res is None or res.status != 0 or res.x is None:
        return None
    d = res.x[:n] - res.x[n:]
    top = float(np.max(np.abs(d), initial=0.0))
    return d / top if top > 0 else None


def _unbounded(P, q, G, h, A, b, lb, ub, dF, tl) -> Proof | None:
    """The proof for an exactly checked ray ``dF``, with a feasible point."""
    d = np.array([float(v) for v in dF])
    x0 = _feasible_point(q, G, h, A, b, lb, ub, tl)
    if x0 is None:
        return None
    slope = float(q @ d)
    f0 = 0.5 * float(x0 @ (P @ x0)) + float(q @ x0)
    # The ray alone proves that no minimiser exists (feasible: x0 + t d falls
    # for ever; infeasible: nothing to minimise); "unbounded below" also needs
    # x0 feasible, which is said as checked.
    exact = _exactly_feasible(x0, G, h, A, b, lb, ub, tl)
    where = ("feasibility checked in exact rational arithmetic" if exact else
             "feasible to rounding only: if the constraints admit no point at all the QP is "
             "infeasible instead — no minimiser exists either way")
    return Proof(
        kind="unbounded",
        message=(f"the objective is unbounded below: from the point x0 (objective {f0:.3e}, "
                 f"{where}) along the direction d it falls for ever (q'd = {slope:.3e} < 0, "
                 "Pd = 0, Gd <= 0, Ad = 0 and the bounds' signs, checked in exact rational "
                 "arithmetic)"),
        vector={"d": d},
        point=x0,
    )


def _exactly_feasible(x, G, h, A, b, lb, ub, tl=None) -> bool:
    """Gx <= h, Ax = b and the bounds, in exact (integer) arithmetic (False
    beyond EXACT_WORK products or past ``tl``: not checked)."""
    n = x.size
    for M, rhs, eq in ((csr_rows(G, n), h, False), (csr_rows(A, n), b, True)):
        if M.shape[0] and not exactly_within(M, x, np.asarray(rhs, float), eq, tl):
            return False
    lo = lb if lb is not None else np.full(n, -np.inf)
    hi = ub if ub is not None else np.full(n, np.inf)
    return bool(np.all(x >= lo) and np.all(x <= hi))   # comparisons of doubles are exact


def prove_no_minimiser(problem, time_limit=None, hints=(), quick=False) -> Proof | None:
    """A checked Farkas vector or ray for a convex ``qpsolvers.Problem``, or
    None when neither is found (the QP may still have no minimiser; nothing
    is claimed then).  Its LPs and exact checks keep ``time_limit`` (a
    :class:`~qpcontact.core.deadline.Deadline` or seconds; at most
    :data:`~qpcontact.proofs.lp.LP_TIME_LIMIT` from now).  ``hints`` are points a method returned
    far out: their direction is tried exactly as a ray first (a backend on an
    unbounded QP stops at x ~ 1e8..1e11 along it).

    ``quick``: only a ray in P's null space, from one LP in its few
    coordinates (n <= NULL_SPACE_MAX_N) — what "auto" tries before any
    method runs where P is singular."""
    P, q, G, h, A, b, lb, ub = problem.unpack()
    q = np.asarray(q, dtype=float)
    tl = proof_deadline(time_limit)
    if tl.expired():
        # nothing is started past the deadline: the ray search's set-up
        # alone (scalings, the exact check's integers) took 1.3 s at n = 1 000
        return None
    with np.errstate(all="ignore"):
        for x in hints:
            proof = _hinted_ray(P, q, G, h, A, b, lb, ub, x, tl)
            if proof is not None:
                return proof
        proof = _twin_column_ray(P, q, G, h, A, b, lb, ub, tl)
        if proof is not None:
            return proof
        if quick:
            return _null_space_ray(P, q, G, h, A, b, lb, ub, tl)
        proof = None if tl.expired() else find_farkas(P, q, G, h, A, b, lb, ub, tl)
        if proof is None and not tl.expired():
            proof = _ray(P, q, G, h, A, b, lb, ub, tl)
    return proof


def _null_space_ray(P, q, G, h, A, b, lb, ub, tl) -> Proof | None:
    """A ray d = N c, N a basis of P's numerical null space
    (:func:`~qpcontact.proofs.lp.null_basis`): one LP in the null space's few
    coordinates, min q'Nc over G N c <= 0, A N c = 0, the bounds' signs and
    |c| <= 1.  HiGHS took 1.5 s on the full ray LP at n = 250 (P's rows as
    equalities); this one takes milliseconds.  The candidate, snapped, is
    checked exactly (:class:`~qpcontact.proofs.exact.RayCheck`)."""
    n = q.size
    basis = null_basis(P, tl) if n <= NULL_SPACE_MAX_N and np.all(np.isfinite(q)) else None
    if basis is None or tl.expired():
        return None
    B, c = basis
    N = B * c[:, None]
    k = N.shape[1]
    G, A = csr_rows(G, n), csr_rows(A, n)
    lo = np.where(np.isfinite(lb), 0.0, -1.0) if lb is not None else -np.ones(n)
    hi = np.where(np.isfinite(ub), 0.0, 1.0) if ub is not None else np.ones(n)

    def unit_rows(B):
        big = np.max(np.abs(B), axis=1) if B.shape[0] else np.zeros(0)
        keep = big > 0
        return B[keep] / big[keep, None]

    cones = [unit_rows(np.asarray(G @ N)), unit_rows(-N[lo == 0]), unit_rows(N[hi == 0])]
    cones = [r for r in cones if r.shape[0]]
    # |d_i| <= 1 (rather than |c| <= 1): a vertex then has d's entries at
    # ±1 or set by the data's rows, the exact weights of a rounded P's
    # sparse null vectors rather than an eigenbasis's irrational mix
    ub_rows = np.vstack(cones + [B, -B])
    b_ub = np.r_[np.zeros(sum(r.shape[0] for r in cones)), np.ones(2 * n)]
    eq_rows = unit_rows(np.asarray(A @ N))
    qN = N.T @ q
    scale = float(np.max(np.abs(qN)))
    if not scale > 0:
        return None
    res = linprog(qN / scale, A_ub=ub_rows, b_ub=b_ub,
                  A_eq=eq_rows if eq_rows.shape[0] else None,
                  b_eq=np.zeros(eq_rows.shape[0]) if eq_rows.shape[0] else None,
                  bounds=[(None, None)] * k, time_limit=tl, tight=True)
    if res is None or res.status != 0 or res.x is None or not res.fun < -1e-9:
        return None
    # snapped in the balanced coordinates d = c * dt, mapped back exactly
    dt = np.clip(B @ res.x, lo, hi)
    top = float(np.max(np.abs(dt), initial=0.0))
    if not top > 0:
        return None
    ray = RayCheck(sp.csr_matrix(P), q, G, A, lo, hi)
    cF = [Fraction(float(v)) for v in c]
    dF = next((d for d in ([v * cj for v, cj in zip(vt, cF)] for vt in candidates(dt / top, tl))
               if ray.check(d, tl)), None)
    return None if dF is None else _unbounded(P, q, G, h, A, b, lb, ub, dF, tl)


#: the most pairs of twin columns whose rays _twin_column_ray checks
_TWIN_PAIRS = 2000


def _twin_column_ray(P, q, G, h, A, b, lb, ub, tl) -> Proof | None:
    """A ray from two variables that P sees as one: columns i and j of P
    equal up to a signed power of two (P[:, i] = c P[:, j], exact in doubles)
    give P d = 0 exactly for d = e_i - c e_j — a variable entered twice, or
    in two units.  Where P has several such pairs the null space's LP
    returns a mix of them that no snapping makes exact (the stress family
    qp_unbounded_rounded, unproved at n = 250); each pair's ±d is screened in
    floating point (G d <= 0, A d = 0, the bounds' signs, q'd < 0) and the
    survivors checked exactly."""
    n = q.size
    if n < 2 or n > NULL_SPACE_MAX_N or tl.expired():
        return None
    D = P.toarray() if sp.issparse(P) else np.asarray(P, float)
    if not np.all(np.isfinite(D)):
        return None
    # each column over the signed power of two of its largest entry: twins
    # become equal (dividing by a power of two is exact)
    lead = D[np.argmax(np.abs(D), axis=0), np.arange(n)]
    live = lead != 0
    power = np.floor(np.log2(np.where(live, np.abs(lead), 1.0)))
    scale = np.where(live, np.sign(lead) * 2.0 ** power, 1.0)
    N = D / scale[None, :]
    groups: dict = {}
    for j in np.flatnonzero(live):
        groups.setdefault(N[:, j].tobytes(), []).append(j)
    pairs = [(g[0], j) for g in groups.values() if len(g) > 1 for j in g[1:]][:_TWIN_PAIRS]
    if not pairs:
        return None
    G, A = csr_rows(G, n), csr_rows(A, n)
    lo = np.where(np.isfinite(lb), 0.0, -1.0) if lb is not None else -np.ones(n)
    hi = np.where(np.isfinite(ub), 0.0, 1.0) if ub is not None else np.ones(n)
    ray = None
    for i, j in pairs:
        if tl.expired():
            return None
        c = scale[i] / scale[j]              # P[:, i] = c P[:, j]: a power of two, signed
        d = np.zeros(n)
        d[i], d[j] = 1.0, -c
        for s in (1.0, -1.0):
            v = s * d
            if not (q @ v < 0 and np.all(G @ v <= 0) and np.all(A @ v == 0)
                    and np.all(v >= lo * np.abs(v)) and np.all(v <= hi * np.abs(v))):
                continue
            ray = ray or RayCheck(sp.csr_matrix(P), q, G, A, lo, hi)
            dF = [Fraction(float(x)) for x in v]
            if ray.check(dF, tl):
                return _unbounded(P, q, G, h, A, b, lb, ub, dF, tl)
    return None


def _hinted_ray(P, q, G, h, A, b, lb, ub, x, tl) -> Proof | None:
    n = q.size
    x = np.asarray(x, float).ravel()
    top = float(np.max(np.abs(x), initial=0.0)) if x.size == n else 0.0
    if not (np.isfinite(top) and top > 0):
        return None
    P = sp.csr_matrix(P)
    Gr, Ar = csr_rows(G, n), csr_rows(A, n)
    lo = np.where(np.isfinite(lb), 0.0, -1.0) if lb is not None else -np.ones(n)
    hi = np.where(np.isfinite(ub), 0.0, 1.0) if ub is not None else np.ones(n)
    d = np.clip(x / top, lo, hi)
    # worth the exact checks only if it is a descent direction in P's near
    # null space in floating point
    if not (q @ d < 0 and np.all(np.abs(P @ d) <= 1e-6 * (abs(P) @ np.abs(d)))):
        return None
    ray = RayCheck(P, q, Gr, Ar, lo, hi)
    dF = next((c for c in candidates(d, tl) if ray.check(c, tl)), None)
    return None if dF is None else _unbounded(P, q, G, h, A, b, lb, ub, dF, tl)
