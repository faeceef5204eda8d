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
The exact check is skipped above _EXACT_WORK products.

Backends say "infeasible" in their own words and on their own absolute
tolerances; QP backends also loop for a long time on such problems (an
unbounded QP took every backend of "auto" in turn).  Here each certificate is
found by one linear program (HiGHS through :func:`scipy.optimize.linprog`,
with every constraint row scaled to unit size so that the LP's absolute
tolerances mean the same on every row) and accepted only after the checks
above are computed from the data.
"""

from __future__ import annotations

from dataclasses import dataclass

import math
from fractions import Fraction

import numpy as np
import scipy.sparse as sp

__all__ = ["QPProof", "prove_no_minimiser", "prove_lcp_infeasible", "x_size"]

_EPS = np.finfo(float).eps
#: nonzero products an exact (rational) check may take; beyond it no proof
#: is claimed (a rounded check is not a proof: with r = G'z + ... ≈ 1e-16 it
#: only rules out feasible points up to |c| / ‖r‖₁, and a scaled problem's
#: solution was found beyond that)
_EXACT_WORK = 200_000


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


#: seconds each LP may take (solve's time_limit when smaller)
LP_TIME_LIMIT = 30.0


def _linprog(c, A_ub=None, b_ub=None, A_eq=None, b_eq=None, bounds=None, time_limit=LP_TIME_LIMIT,
             tight=True):
    from scipy.optimize import linprog

    options = {"time_limit": time_limit}
    if tight:
        options.update(primal_feasibility_tolerance=1e-10, dual_feasibility_tolerance=1e-10)
    with np.errstate(all="ignore"):
        try:
            return linprog(c, A_ub=A_ub, b_ub=b_ub, A_eq=A_eq, b_eq=b_eq, bounds=bounds,
                           method="highs", options=options)
        except (ValueError, MemoryError):
            return None


def _farkas(P, q, G, h, A, b, lb, ub, tl) -> QPProof | None:
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
    A_eq = sp.hstack([Gs.T, As.T, -El, Eu]).tocsr()
    # each equation (one per variable) at unit size as well: a variable
    # scaled by 1e-6 otherwise leaves its equation under HiGHS's tolerance
    A_eq = (sp.diags(_row_scale(A_eq)) @ A_eq).tocsc()
    cost = np.concatenate([sg * h, sa * b, -lbf, ubf])
    if not np.all(np.isfinite(cost)):
        return None  # data beyond double precision's range once scaled: nothing to prove here
    bounds = ([(0, 1)] * G.shape[0] + [(-1, 1)] * A.shape[0] + [(0, 1)] * (il.size + iu.size))
    res = _linprog(cost, A_eq=A_eq, b_eq=np.zeros(n), bounds=bounds, time_limit=tl)
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
    for exact in _candidates(weights / top):   # the ratios are what matters: 1 : 2 : 3
        proof = _exact_farkas(G, h, A, b, lo, hi, exact, G.shape[0])
        if proof is not None:
            return proof
    return None


#: denominators tried when snapping an LP's vector to exact rationals
#: (None: the doubles themselves); small first, since an LP solution is only
#: accurate to its tolerance and a large denominator fits the error instead
_SNAPS = (1 << 4, 1 << 8, 1 << 12, 1 << 16, 1 << 20, None)


#: components below this fraction of the largest are tried as exact zeros
#: (an LP leaves 1e-11 where the exact ray has 0)
_ZEROS = (0.0, 1e-12, 1e-9, 1e-6)


def _candidates(values: np.ndarray):
    """Exact rational vectors near ``values``, simplest first."""
    top = float(np.max(np.abs(values), initial=0.0))
    for tiny in _ZEROS:
        cut = np.where(np.abs(values) <= tiny * top, 0.0, values)
        for limit in _SNAPS:
            yield _snap(cut, limit)


def _snap(values: np.ndarray, limit) -> list:
    """Exact rationals near an LP's floating-point solution (small denominators
    recover the exact weights of integer data: 1/3 rather than 0.3333...)."""
    if limit is None:
        return [Fraction(float(v)) for v in values]
    out = []
    for v in values:
        # each component's mantissa on its own: scaled data put the exact
        # weights at different powers of two (2^-23 beside 1)
        m, e = math.frexp(float(v))
        out.append(Fraction(m).limit_denominator(limit) * Fraction(2) ** e)
    return out


def _exact_farkas(G, h, A, b, lo, hi, exact, m_G) -> QPProof | None:
    """Check a Farkas vector in exact rational arithmetic: the data's doubles
    are rationals, so G'z + A'y, the bound multipliers that cancel it, and
    c = h'z + b'y - lb'μl + ub'μu are computed without rounding.  Sound: a
    vector that passes proves infeasibility of the data as stored."""
    n = lo.size
    z, y = exact[:m_G], exact[m_G:]
    Gc, Ac = G.tocsr(), A.tocsr()
    work = sum(Gc.indptr[i + 1] - Gc.indptr[i] for i in range(Gc.shape[0]) if z[i]) + \
        sum(Ac.indptr[i + 1] - Ac.indptr[i] for i in range(Ac.shape[0]) if y[i])
    if work > _EXACT_WORK:
        return None
    r = [Fraction(0)] * n
    c = Fraction(0)
    for M, rhs, w in ((Gc, h, z), (Ac, b, y)):
        for i in range(M.shape[0]):
            if not w[i]:
                continue
            c += Fraction(float(rhs[i])) * w[i]
            for p in range(M.indptr[i], M.indptr[i + 1]):
                r[M.indices[p]] += Fraction(float(M.data[p])) * w[i]
    used = {"lower": 0, "upper": 0}
    for j in range(n):
        if r[j] > 0:      # cancelled by μl_j = r_j >= 0 on a finite lower bound
            if not np.isfinite(lo[j]):
                return None
            c -= Fraction(float(lo[j])) * r[j]
            used["lower"] += 1
        elif r[j] < 0:    # cancelled by μu_j = -r_j >= 0 on a finite upper bound
            if not np.isfinite(hi[j]):
                return None
            c -= Fraction(float(hi[j])) * r[j]
            used["upper"] += 1
    if not c < 0:
        return None
    zf = np.array([float(v) for v in z])
    yf = np.array([float(v) for v in y])
    rf = np.array([float(v) for v in r])
    parts = [f"{name}: {count}" for name, count in
             (("inequality rows", int(np.count_nonzero(zf))), ("equality rows", int(np.count_nonzero(yf))),
              ("lower bounds", used["lower"]), ("upper bounds", used["upper"])) if count]
    return QPProof(
        kind="infeasible",
        message=("no x satisfies the constraints: the weighted sum of " + ", ".join(parts)
                 + f" reads 0 <= {float(c):.3e} (a Farkas vector, checked from the data in exact "
                 "rational arithmetic)"),
        vector={"z": zf, "y": yf, "lower": np.maximum(rf, 0.0), "upper": np.maximum(-rf, 0.0),
                # the weights as checked (rationals; the floats above may round them)
                "exact": {"z": list(z), "y": list(y)}},
    )


def _x_size(G, h, A, b, lbf, ubf) -> float:
    """The size the data give x: finite bounds, h_i / max|G_i|, b_i / max|A_i|."""
    size = [np.abs(lbf), np.abs(ubf)]
    for M, rhs in ((G, h), (A, b)):
        if M.shape[0]:
            big = np.asarray(abs(M).max(axis=1).toarray()).ravel()
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
    return max(_x_size(_rows(G, n), h, _rows(A, n), b, lbf, ubf),
               _x_size(_rows(P, n), np.asarray(q, float), _rows(None, n), None, lbf[:0], ubf[:0]))


def prove_lcp_infeasible(lcp, time_limit: float | None = None) -> QPProof | None:
    """A checked Farkas vector proving that no z >= 0 has Mz + q >= 0 (so
    LCP(M, q) has no solution), or None."""
    import scipy.sparse as sp_

    n = lcp.n
    M = sp_.csr_matrix(lcp.M)
    tl = min(LP_TIME_LIMIT, time_limit or LP_TIME_LIMIT)
    q = np.asarray(lcp.q, float)
    with np.errstate(all="ignore"):
        proof = _farkas(None, np.zeros(n), -M, q, None, None, np.zeros(n), None, tl)
    if proof is None and n <= _MODULAR_MAX_N and lcp.is_symmetric:
        proof = _null_vector_farkas(M, q)
    return proof


#: largest n for the modular null-vector route (O(n³) integer work mod p)
_MODULAR_MAX_N = 400
_PRIME = 2_147_483_629   # < 2^31: products of residues fit in int64


def _null_vector_farkas(M, q) -> QPProof | None:
    """For symmetric M a Farkas vector y (y >= 0, M y <= 0, q'y < 0) of a
    PSD M lies in M's null space.  When M is exactly singular but its
    computed null space is wider (a second direction with singular value
    1e-14 of the largest: an LP returns a mix that no snapping makes exact),
    the exact null vector is found modulo a prime — M's doubles are integers
    times a power of two — and read back as small rationals; the exact check
    (_exact_farkas) decides.  Only a one-dimensional null space mod p is
    tried."""
    n = M.shape[0]
    A = M.toarray()
    if not np.all(np.isfinite(A)) or not np.any(A):
        return None
    nz = A[A != 0]
    emin = min(math.frexp(float(v))[1] for v in nz) - 53
    # residues of the integers A / 2^emin, entry by entry (exact)
    R = np.zeros((n, n), dtype=np.int64)
    for i, j in zip(*np.nonzero(A)):
        m, e = math.frexp(float(A[i, j]))
        mant = int(m * (1 << 53))
        R[i, j] = (mant % _PRIME) * pow(2, e - 53 - emin, _PRIME) % _PRIME
    y = _null_mod_p(R)
    if y is None:
        return None
    k = int(np.flatnonzero(y)[0])
    inv = pow(int(y[k]), _PRIME - 2, _PRIME)
    cand = []
    for v in y:
        r = _rational(int(v) * inv % _PRIME)
        if r is None:
            return None
        cand.append(r)
    if all(c <= 0 for c in cand):
        cand = [-c for c in cand]
    if any(c < 0 for c in cand):
        return None
    top = max(cand)
    cand = [c / top for c in cand]
    empty = sp.csr_matrix((0, n))
    return _exact_farkas(sp.csr_matrix(-M), q, empty, np.zeros(0), np.zeros(n),
                         np.full(n, np.inf), cand, n)


def _null_mod_p(R) -> np.ndarray | None:
    """A basis vector of the null space of R mod p when it is one-dimensional."""
    A = R.copy() % _PRIME
    n = A.shape[0]
    pivots, row = [], 0
    for col in range(n):
        nzr = np.flatnonzero(A[row:, col]) if row < n else np.zeros(0, int)
        if nzr.size == 0:
            continue
        r = row + int(nzr[0])
        A[[row, r]] = A[[r, row]]
        inv = pow(int(A[row, col]), _PRIME - 2, _PRIME)
        A[row] = A[row] * inv % _PRIME
        others = np.flatnonzero(A[:, col])
        others = others[others != row]
        if others.size:
            f = A[others, col][:, None]
            A[others] = (A[others] - (f * A[row]) % _PRIME) % _PRIME
        pivots.append(col)
        row += 1
        if row == n:
            break
    pivot_set = set(pivots)
    free = [c for c in range(n) if c not in pivot_set]
    if len(free) != 1:
        return None
    y = np.zeros(n, dtype=np.int64)
    y[free[0]] = 1
    for r, c in enumerate(pivots):
        y[c] = (-A[r, free[0]]) % _PRIME
    return y


def _rational(a: int) -> Fraction | None:
    """The fraction u/v with |u|, v <= sqrt(p/2) congruent to a mod p, if any."""
    bound = math.isqrt(_PRIME // 2)
    r0, r1, s0, s1 = _PRIME, a, 0, 1
    while r1 > bound:
        qt = r0 // r1
        r0, r1 = r1, r0 - qt * r1
        s0, s1 = s1, s0 - qt * s1
    if s1 == 0 or abs(s1) > bound:
        return None
    return Fraction(r1, s1)


def _column_scale(blocks, n) -> np.ndarray:
    """Powers of two near 1 / max|column j| of the stacked blocks: x = c * x~.
    Data scaled over decades make the LP's answer span them too, and HiGHS's
    absolute tolerances would leave the small components without a correct
    digit (a feasible point whose rows were violated by 27 % of their size
    came back "optimal" on a QP scaled over 12 decades)."""
    stacked = [m for m in blocks if m is not None and m.shape[0]]
    if not stacked:
        return np.ones(n)
    colmax = np.asarray(abs(sp.vstack(stacked)).max(axis=0).toarray()).ravel()
    return np.where(colmax > 0, 2.0 ** -np.round(np.log2(np.where(colmax > 0, colmax, 1.0))), 1.0)


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
    G, A = _rows(G, n), _rows(A, n)
    lo = lb if lb is not None else np.full(n, -np.inf)
    hi = ub if ub is not None else np.full(n, np.inf)
    x = np.clip(np.zeros(n), lo, hi)
    if _is_feasible(x, G, h, A, b, lo, hi):
        return x
    c = _column_scale((G, A), n)
    Cd = sp.diags(c)
    Gc, Ac = G @ Cd, A @ Cd
    sg, sa = _row_scale(Gc), _row_scale(Ac)
    lo_c, hi_c = lo / c, hi / c
    bounds = list(zip(np.where(np.isfinite(lo_c), lo_c, None),
                      np.where(np.isfinite(hi_c), hi_c, None)))
    res = _linprog(np.zeros(n), A_ub=(sp.diags(sg) @ Gc).tocsc() if G.shape[0] else None,
                   b_ub=sg * h if G.shape[0] else None,
                   A_eq=(sp.diags(sa) @ Ac).tocsc() if A.shape[0] else None,
                   b_eq=sa * b if A.shape[0] else None, bounds=bounds, time_limit=tl)
    if res is None or res.status != 0 or res.x is None:
        return None
    x = np.clip(res.x * c, lo, hi)
    return x if _is_feasible(x, G, h, A, b, lo, hi) else None


def _ray(P, q, G, h, A, b, lb, ub, tl) -> QPProof | None:
    n = q.size
    P = sp.csr_matrix(P)
    G, A = _rows(G, n), _rows(A, n)
    lo = np.where(np.isfinite(lb), 0.0, -1.0) if lb is not None else -np.ones(n)
    hi = np.where(np.isfinite(ub), 0.0, 1.0) if ub is not None else np.ones(n)
    # d = c * d~, then every row of the column-scaled matrices at unit size.
    # Where P_jj > 0, c_j = P_jj^-1/2 (to a power of two): the ray lies in P's
    # null space, and Jacobi scaling undoes any diagonal scaling x = D x' of
    # the variables, where column maxima mix the other columns' scales.  With
    # rows scaled before columns, entries of 1e-9..1e-6 fell under HiGHS's
    # absolute tolerances: on QPs scaled over 12 decades the LP then found no
    # ray, or one whose small components had no correct digit.
    c = _column_scale((P, G, A), n)
    pdiag = np.asarray(P.diagonal(), dtype=float)
    pos = pdiag > 0
    c[pos] = 2.0 ** -np.round(0.5 * np.log2(pdiag[pos]))
    Cd = sp.diags(c)
    Pc, Gc, Ac = P @ Cd, G @ Cd, A @ Cd
    sp_, sg, sa = _row_scale(Pc), _row_scale(Gc), _row_scale(Ac)
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
    # The cost at unit size too (HiGHS's dual tolerance is absolute: a cost
    # of 1e-9 entries was declared optimal at d = 0).  HiGHS's own
    # tolerances first, then 1e-10: each missed rays the other found (at
    # 1e-10 it called d = 0 optimal beside a rank-deficient P block where the
    # default found q'd = -0.1); the exact check decides.
    for tight in (False, True):
        res = _linprog(cost / top_cost, A_ub=A_ub,
                       b_ub=np.zeros(A_ub.shape[0]) if A_ub is not None else None,
                       A_eq=A_eq, b_eq=np.zeros(A_eq.shape[0]) if A_eq is not None else None,
                       bounds=list(zip(lo, hi)), time_limit=tl, tight=tight)
        if res is None or res.status != 0 or res.x is None or not res.fun < 0:
            continue
        # snapped in the LP's balanced coordinates, where a component that is
        # exactly 0 reads 1e-8 beside 1, not beside 1e-12 (components of d
        # itself span the data's decades), and mapped back exactly (c_j are
        # powers of two)
        dt = np.clip(res.x, lo, hi)
        top = float(np.max(np.abs(dt), initial=0.0))
        if not top > 0:
            continue
        dF = next((d for d in ([v * cj for v, cj in zip(vt, cF)] for vt in _candidates(dt / top))
                   if _exact_ray(P, q, G, A, d, lo, hi)), None)
        if dF is not None:
            break
    if dF is None:
        return None
    d = np.array([float(v) for v in dF])
    x0 = _feasible_point(q, G, h, A, b, lb, ub, tl)
    if x0 is None:
        return None
    slope = float(q @ d)
    f0 = 0.5 * float(x0 @ (P @ x0)) + float(q @ x0)
    return QPProof(
        kind="unbounded",
        message=(f"the objective is unbounded below: from the feasible point x0 (objective "
                 f"{f0:.3e}, feasibility checked to rounding) along the direction d it falls for "
                 f"ever (q'd = {slope:.3e} < 0, Pd = 0, Gd <= 0, Ad = 0 and the bounds' signs, "
                 "checked in exact rational arithmetic)"),
        vector={"d": d},
        point=x0,
    )


def _exact_ray(P, q, G, A, dF, lo, hi) -> bool:
    """Pd = 0, Gd <= 0, Ad = 0, q'd < 0 and d's signs, in exact arithmetic."""
    support = [j for j, v in enumerate(dF) if v]
    if not support:
        return False
    for j in support:
        if (dF[j] > 0 and hi[j] == 0.0) or (dF[j] < 0 and lo[j] == 0.0):
            return False
    if sum(Fraction(float(q[j])) * dF[j] for j in support) >= 0:
        return False
    for M, sign in ((P, 0), (G, -1), (A, 0)):
        if not M.shape[0]:
            continue
        Mc = sp.csc_matrix(M)
        if sum(Mc.indptr[j + 1] - Mc.indptr[j] for j in support) > _EXACT_WORK:
            return False
        acc: dict[int, Fraction] = {}
        for j in support:
            for p in range(Mc.indptr[j], Mc.indptr[j + 1]):
                i = Mc.indices[p]
                acc[i] = acc.get(i, Fraction(0)) + Fraction(float(Mc.data[p])) * dF[j]
        if sign == 0 and any(v != 0 for v in acc.values()):
            return False
        if sign < 0 and any(v > 0 for v in acc.values()):
            return False
    return True


def prove_no_minimiser(problem, time_limit: float | None = None) -> QPProof | None:
    """A checked Farkas vector or ray for a convex ``qpsolvers.Problem``, or
    None when neither is found (the QP may still have no minimiser; nothing
    is claimed then).  Each LP gets at most ``time_limit`` seconds (default
    and cap :data:`LP_TIME_LIMIT`)."""
    P, q, G, h, A, b, lb, ub = problem.unpack()
    q = np.asarray(q, dtype=float)
    tl = min(LP_TIME_LIMIT, time_limit or LP_TIME_LIMIT)
    with np.errstate(all="ignore"):
        proof = _farkas(P, q, G, h, A, b, lb, ub, tl)
        if proof is None:
            proof = _ray(P, q, G, h, A, b, lb, ub, tl)
    return proof
