"""The cheap Farkas candidates of an LCP, checked exactly before any LP.

A Farkas vector y >= 0 with Mᵀy <= 0 and qᵀy < 0 proves that no z >= 0 has
w = Mz + q >= 0 (yᵀw = (Mᵀy)ᵀz + qᵀy < 0), so LCP(M, q) has no solution.
Some are found without any search, and an LP can miss them:

- **one row**: a row i with every M_ij <= 0 and q_i < 0 — then w_i <= q_i < 0
  for every z >= 0, and y = e_i.  Exact from the signs alone.
- **all ones**: a mechanism loaded along itself — Mᵀ1 = 0 with qᵀ1 < 0 (a
  floating body under a net load).  Beside far contacts (|q| ~ 1e13) the LP
  cannot see qᵀy = -1 at all; the rational check can.
- **null directions**: for a singular M (or an active block singular to
  working precision) the left null vectors U₀ of M as computed, any
  dimension: each one (signs flipped where that makes it nonnegative) and
  the nonnegative combination y = U₀c minimising qᵀy (an LP in the few
  coefficients c, not in n unknowns).

Each candidate is checked in exact rational arithmetic
(:func:`qpcontact.proofs.exact.exact_farkas`); none is believed in floating
point.  The floating-point filter before the exact check is loose on qᵀy
(qᵀ1 = -1 beside |q| ~ 1e13 may round to either sign)."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import scipy.sparse as sp

from .exact import EXACT_WORK, Proof, candidates, exact_farkas

__all__ = ["one_row_farkas", "cheap_lcp_farkas", "left_null_directions", "exact_friction_motion",
           "exact_equilibrium", "CHEAP_SECONDS",
           "NULL_MAX_N"]

#: largest n whose left null space is computed (a dense SVD, O(n³))
NULL_MAX_N = 400

#: how far a candidate may miss Mᵀy <= 0 (each column against its own terms,
#: |M|ᵀy) and qᵀy <= 0 (against |q|ᵀy) in floating point and still be worth
#: an exact check
_FILTER_RTOL = 1e-6


def _check(Mc, q, y_exact, deadline) -> Proof | None:
    n = q.size
    empty = sp.csr_matrix((0, n))
    return exact_farkas(-Mc, q, empty, np.zeros(0), np.zeros(n), np.full(n, np.inf),
                        y_exact, n, deadline)


def one_row_farkas(M, q) -> Proof | None:
    """y = e_i for a row i with max_j M_ij <= 0 and q_i < 0 (the most
    negative q_i relative to its row first), checked exactly; None when no
    row qualifies."""
    Mc = sp.csr_matrix(M)
    q = np.asarray(q, float)
    n = q.size
    if n == 0:
        return None
    rowmax = np.full(n, -np.inf)
    if Mc.nnz:
        rowmax = np.asarray(Mc.max(axis=1).toarray()).ravel()   # implicit zeros count as 0
        full = np.diff(Mc.indptr) == n
        rowmax = np.where(full, rowmax, np.maximum(rowmax, 0.0))
    else:
        rowmax = np.zeros(n)
    rows = np.flatnonzero((rowmax <= 0) & (q < 0))
    for i in rows[np.argsort(q[rows])][:3]:
        y = [Fraction(0)] * n
        y[int(i)] = Fraction(1)
        proof = _check(Mc, q, y, None)
        if proof is not None:
            return proof
    return None


def left_null_directions(M, rtol: float | None = None) -> np.ndarray:
    """Columns spanning the computed left null space of M (Mᵀu ≈ 0): the
    left singular vectors whose singular value is at most ``rtol`` times the
    largest (default n·eps·100).  Empty (n, 0) above NULL_MAX_N or when M
    has full rank to that tolerance."""
    n = M.shape[0]
    if n == 0 or n > NULL_MAX_N:
        return np.zeros((n, 0))
    A = M.toarray() if sp.issparse(M) else np.asarray(M, float)
    if not np.all(np.isfinite(A)):
        return np.zeros((n, 0))
    try:
        U, s, _ = np.linalg.svd(A)
    except np.linalg.LinAlgError:
        return np.zeros((n, 0))
    tol = (100.0 * n * np.finfo(float).eps if rtol is None else rtol) * (s[0] if s.size else 0.0)
    return U[:, s <= tol]


def _nonnegative_combination(U: np.ndarray, q: np.ndarray, deadline) -> np.ndarray | None:
    """y = U c >= 0, Σy = 1, minimising qᵀy (q scaled to unit size): an LP in
    U's few columns."""
    from .lp import linprog

    k = U.shape[1]
    if k == 0:
        return None
    qs = q / (float(np.max(np.abs(q))) or 1.0)
    res = linprog(qs @ U, A_ub=-U, b_ub=np.zeros(U.shape[0]), A_eq=U.sum(axis=0)[None, :],
                  b_eq=[1.0], bounds=[(None, None)] * k, time_limit=deadline, tight=False)
    if res is None or res.status != 0:
        return None
    return np.maximum(U @ res.x, 0.0)


def _worth_checking(Mc, absM, q, y, rtol=_FILTER_RTOL) -> bool:
    top = float(np.max(y, initial=0.0))
    if not top > 0:
        return False
    y = y / top
    return bool(np.all(Mc.T @ y <= rtol * (absM.T @ y))
                and q @ y <= rtol * (np.abs(q) @ y))


#: seconds the cheap candidates may take together (less when the call's
#: deadline leaves less): they come before the LPs and must stay cheap
CHEAP_SECONDS = 2.0


class _IntegerData:
    """(M, q) as Python integers times one power of two (every double is a
    dyadic rational), for exact checks of many candidates at the cost of
    integer dot products; only for dense data up to NULL_MAX_N."""

    def __init__(self, M: np.ndarray, q: np.ndarray):
        vals = np.concatenate([M.ravel(), q])
        mant, expo = np.frexp(vals)
        mant = (mant * 2.0 ** 53).astype(np.int64)
        expo = expo.astype(np.int64) - 53
        low = int(expo[mant != 0].min(initial=0))
        ints = np.array([int(m) << int(e - low) if m else 0 for m, e in zip(mant, expo)],
                        dtype=object)
        n = q.size
        self.M = ints[:n * n].reshape(n, n)
        self.q = ints[n * n:]

    def farkas(self, cand) -> bool:
        """y >= 0, Mᵀy <= 0, qᵀy < 0 for the rationals ``cand``, exactly."""
        den = 1
        for c in cand:
            if c:
                den = den * c.denominator // math.gcd(den, c.denominator)
        y = np.array([int(c * den) for c in cand], dtype=object)
        if any(v < 0 for v in y) or not any(y):
            return False
        nz = np.flatnonzero(y != 0)
        My = y[nz] @ self.M[nz]
        return bool(all(v <= 0 for v in My) and self.q[nz] @ y[nz] < 0)


def cheap_lcp_farkas(M, q, deadline=None, directions=()) -> Proof | None:
    """The cheap candidates (module docstring) checked exactly, one-row
    first; ``directions`` are further vectors (an active block's left null
    vectors, embedded in n components; a method's Farkas vector) tried with
    the rest.  None when no candidate holds exactly, or once ``deadline`` (a
    :class:`~qpcontact.core.deadline.Deadline`) or CHEAP_SECONDS pass."""
    from ..core.deadline import Deadline

    deadline = (deadline if deadline is not None else Deadline()).within(CHEAP_SECONDS)
    q = np.asarray(q, float).ravel()
    n = q.size
    if not np.all(np.isfinite(q)) or deadline.expired():
        return None     # a dense M's sparse copy alone is O(n²): 1.2 s at n = 3 000
    Mc = sp.csr_matrix(M)
    if Mc.nnz and not np.all(np.isfinite(Mc.data)):
        return None
    proof = one_row_farkas(Mc, q)
    if proof is not None or deadline.expired():
        return proof    # the signs cost O(nnz); nothing else starts past the deadline
    absM = abs(Mc)
    if Mc.nnz <= EXACT_WORK and _worth_checking(Mc, absM, q, np.ones(n)):
        proof = _check(Mc, q, [Fraction(1)] * n, deadline)
        if proof is not None:
            return proof
    if n > NULL_MAX_N:
        return None
    vectors = [np.asarray(d, float).ravel() for d in directions]
    U = left_null_directions(Mc)
    if U.shape[1]:
        comb = _nonnegative_combination(U, q, deadline)
        if comb is not None:
            vectors.insert(0, comb)
        if U.shape[1] <= 3:
            vectors.extend(U.T)
    exact = None
    for v in vectors:
        if deadline.expired():
            return None
        if v.shape != (n,) or not np.all(np.isfinite(v)):
            continue
        for y in (v, -v):
            y = np.maximum(y, 0.0)
            if not _worth_checking(Mc, absM, q, y):
                continue
            y = y / float(y.max())
            for cand in candidates(y, deadline):
                yf = np.array([float(c) for c in cand])
                # a snapping that breaks Mᵀy <= 0 in floating point by more
                # than rounding cannot hold exactly
                if not _worth_checking(Mc, absM, q, yf, 1e-9):
                    continue
                if exact is None:
                    exact = _IntegerData(Mc.toarray(), q)
                if exact.farkas(cand):
                    return _check(Mc, q, cand, None)
    return None


def _cone_holds(u, mu) -> bool:
    """u in the dual cone {u_N >= μ ‖u_T‖}, exactly (squares: no roots)."""
    uN, uT = u[0], u[1:]
    return uN >= 0 and uN * uN >= mu * mu * sum((t * t for t in uT), Fraction(0))


def exact_friction_motion(problem, d, r, deadline=None):
    """Decide a frictional problem within rounding of its friction limit,
    exactly.  Returns ("infeasible", Proof) when a snapping of the motion
    ``d`` has Md = 0, every contact admitting Hᵀd (its dual cone) and
    fᵀd > 0 in rational arithmetic (no reactions within the cones balance
    the loads: 0 = dᵀMv = (Hᵀd)·r + fᵀd > 0 for any equilibrium);
    ("within", None) when the answer ``r``, corrected exactly onto the
    mechanism's balance (:func:`exact_equilibrium`), lies in every cone: an
    equilibrium exists, at or below the limit; None when neither is proved."""
    g = problem.global_data
    dim = problem.dim
    M, H = sp.csc_matrix(g["M"]), sp.csc_matrix(g["H"])
    f = np.asarray(g["f"], float)
    mu = [Fraction(float(m)) for m in problem.mu]
    if M.nnz + H.nnz > EXACT_WORK:
        return None
    Hr = sp.csr_matrix(H.T)
    for cand in candidates(np.asarray(d, float), deadline):
        if not any(cand):
            continue
        Md = {}
        for j, dj in enumerate(cand):
            if dj:
                for p in range(M.indptr[j], M.indptr[j + 1]):
                    i = M.indices[p]
                    Md[i] = Md.get(i, Fraction(0)) + Fraction(float(M.data[p])) * dj
        if any(v != 0 for v in Md.values()):
            continue
        u = [sum((Fraction(float(Hr.data[p])) * cand[Hr.indices[p]]
                  for p in range(Hr.indptr[i], Hr.indptr[i + 1])), Fraction(0))
             for i in range(Hr.shape[0])]
        if not all(_cone_holds(u[c * dim:(c + 1) * dim], mu[c]) for c in range(len(mu))):
            continue
        work = sum((Fraction(float(fi)) * di for fi, di in zip(f, cand) if di), Fraction(0))
        if work <= 0:
            continue
        df = np.array([float(v) for v in cand])
        return "infeasible", Proof(
            kind="infeasible",
            message=("no equilibrium exists: the motion d (stats['ray']) has Md = 0, every "
                     "contact admits it (Hᵀd in its dual cone) and the loads do work "
                     f"fᵀd = {float(work):.3e} > 0 on it, checked from the data in exact "
                     "rational arithmetic (the loads are beyond the friction limit by that "
                     "much)"),
            vector={"d": df, "exact": {"d": list(cand)}})
    if exact_equilibrium(problem, r, deadline):
        return "within", None
    return None


def _exact_null_basis(M, deadline):
    """An exact basis of M's null space (columns of rationals with M N = 0
    exactly) from the computed one, snapped; None when snapping does not
    make it exact."""
    Md = M.toarray()
    n = Md.shape[0]
    if not np.any(Md):
        return [[Fraction(int(i == j)) for j in range(n)] for i in range(n)]
    U = left_null_directions(sp.csr_matrix(Md))
    if U.shape[1] == 0:
        return []
    Mf = [[Fraction(float(x)) for x in row] for row in Md]
    basis = []
    for col in U.T:
        for cand in candidates(col / np.abs(col).max(), deadline):
            if all(sum((a * b for a, b in zip(row, cand) if a and b), Fraction(0)) == 0
                   for row in Mf):
                basis.append(cand)
                break
        else:
            return None
    return [list(x) for x in zip(*basis)]


def _solve_exact(A, b):
    """A x = b by Gauss–Jordan elimination in rationals; None when singular."""
    k = len(A)
    R = [list(A[i]) + [b[i]] for i in range(k)]
    for c in range(k):
        p = next((i for i in range(c, k) if R[i][c] != 0), None)
        if p is None:
            return None
        R[c], R[p] = R[p], R[c]
        for i in range(k):
            if i != c and R[i][c] != 0:
                t = R[i][c] / R[c][c]
                R[i] = [a - t * e for a, e in zip(R[i], R[c])]
    return [R[i][k] / R[i][i] for i in range(k)]


def exact_equilibrium(problem, r, deadline=None) -> bool:
    """Whether reactions within the cones balance the loads on the
    mechanisms, exactly: with N an exact basis of null(M) (M symmetric, so
    H r + f must be orthogonal to it), the answer r is corrected by the
    least-norm change that makes Nᵀ(H r + f) = 0 exactly, and every contact's
    corrected reaction must lie in its cone (r_N >= 0, μ² r_N² >= ‖r_T‖²: no
    roots).  True is a proof that an equilibrium exists; False proves
    nothing."""
    g = problem.global_data
    dim = problem.dim
    M, H = sp.csc_matrix(g["M"]), sp.csr_matrix(g["H"])
    f = [Fraction(float(v)) for v in g["f"]]
    N = _exact_null_basis(M, deadline)
    if N is None or (deadline is not None and deadline.expired()):
        return False
    n, m = H.shape
    k = len(N[0]) if N else 0
    rr = [Fraction(float(v)) for v in np.asarray(r, float).ravel()]
    if len(rr) != m:
        return False
    if k:
        Hd = H.toarray()
        # A = Nᵀ H (k x m), b = -Nᵀ f
        A = [[sum((N[i][c] * Fraction(float(Hd[i, j])) for i in range(n) if N[i][c] and Hd[i, j]),
                  Fraction(0)) for j in range(m)] for c in range(k)]
        b = [-sum((N[i][c] * f[i] for i in range(n) if N[i][c]), Fraction(0)) for c in range(k)]
        res = [b[c] - sum((A[c][j] * rr[j] for j in range(m) if A[c][j]), Fraction(0))
               for c in range(k)]
        AAt = [[sum((A[a][j] * A[c][j] for j in range(m)), Fraction(0)) for c in range(k)]
               for a in range(k)]
        lam = _solve_exact(AAt, res)
        if lam is None:
            return False
        rr = [rr[j] + sum((A[c][j] * lam[c] for c in range(k)), Fraction(0)) for j in range(m)]
    mu = [Fraction(float(x)) for x in problem.mu]
    for c in range(len(mu)):
        rN, rT = rr[c * dim], rr[c * dim + 1:(c + 1) * dim]
        if rN < 0 or mu[c] * mu[c] * rN * rN < sum((t * t for t in rT), Fraction(0)):
            return False
    return True
