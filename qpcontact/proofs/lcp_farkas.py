"""Proofs that an LCP has no solution: a Farkas vector y >= 0 with M'y <= 0 and
q'y < 0 (then y'(Mz + q) < 0 for every z >= 0, so no z >= 0 has Mz + q >= 0).

:func:`prove_lcp_infeasible` tries, cheapest first: a row i with M[i, :] <= 0
and q_i < 0 (y = e_i: w_i <= q_i < 0 for every z >= 0, read off the signs of
the data), the all-ones vector (columns of M summing to <= 0), an interior
Farkas vector from one LP (every column of M'y negative with a margin far
above rounding, so its doubles check exactly as they are), the QP route's
LP (:func:`qpcontact.proofs.qp_farkas.find_farkas`: a vertex, snapped to
short rationals) and, for a symmetric M whose computed null space is wider
than its exact one, a null vector modulo a prime, and for a small symmetric M
a rounding away from singular on its indefinite side, y = -M⁻¹1 solved
exactly; each is checked in exact
arithmetic (:mod:`qpcontact.proofs.exact`) and none runs past the deadline.
:func:`feasibility` is Lemke's test after a secondary ray, in floating point,
each component on its own scale (FARKAS_RTOL): its message says "checked from
the data" in that sense.
"""

from __future__ import annotations

import itertools
import math
from fractions import Fraction

import numpy as np
import scipy.sparse as sp

from .exact import FarkasCheck, Proof, candidates, ints, solve_integer
from .lp import NULL_SPACE_MAX_N, linprog, null_basis, proof_deadline, row_scale
from .qp_farkas import find_farkas

__all__ = ["prove_lcp_infeasible", "inverse_farkas", "sign_farkas", "check_farkas_hint",
           "feasibility", "FARKAS_RTOL"]


def prove_lcp_infeasible(lcp, time_limit=None, hints=(), quick=False) -> Proof | None:
    """A Farkas vector proving that no z >= 0 has Mz + q >= 0 (so LCP(M, q)
    has no solution), checked in exact arithmetic, or None.

    ``hints`` are vectors a method learned on the way — Lemke's Farkas vector
    checked in floating point, or the direction of a huge answer (for a
    symmetric PSD M the answer of nearly infeasible data runs along M's
    near-null vector, which is the Farkas vector when the data are exactly
    singular) — tried exactly first, before the LPs.  The whole search keeps
    ``time_limit`` (a :class:`~qpcontact.core.deadline.Deadline` or seconds;
    at most :data:`~qpcontact.proofs.lp.LP_TIME_LIMIT` from now).

    ``quick``: only the routes that cost milliseconds to a few tenths of a
    second at n <= 1 000 (the signs, the all-ones vector, M's null space
    for a symmetric PSD M, the interior LP otherwise) — what "auto" tries
    before any method runs."""
    tl = proof_deadline(time_limit)
    n = lcp.n
    if tl.expired():
        return None     # nothing is started past the deadline
    M = sp.csr_matrix(lcp.M)
    q = np.asarray(lcp.q, float)
    proof = sign_farkas(M, q)
    if proof is not None or np.all(q >= 0):     # z = 0 solves: no Farkas vector exists
        return proof
    if lcp.structure.is_positive_definite_exactly:   # y'My > 0: none exists
        return None
    check = _lcp_check(M, q)
    if lcp.is_symmetric and n <= _INVERSE_MAX_N:
        # first: one dense solve, exact work only where its guess is
        # one-signed (0.06 s at n = 30, where the hints' snapping and the
        # null-space search cost 0.35 and 0.1 s before it and a 2 s limit
        # at load 3 ran out on them)
        proof = _inverse_farkas(M, q, tl, check)
    for y in list(hints) + [np.ones(n)]:
        if proof is None and not tl.expired():
            proof = check_farkas_hint(M, q, y, tl, check)
    psd = lcp.is_symmetric and lcp.is_psd
    if proof is None and not tl.expired():
        # a symmetric PSD M: every Farkas vector has M y = 0 (y'My <= 0),
        # so it lies in M's null space and the interior LP finds no margin
        proof = (_null_space_farkas(M, q, tl, check) if psd and n <= NULL_SPACE_MAX_N
                 else None if psd else _interior_farkas(M, q, tl, check))
    if quick:
        return proof
    if proof is None and not tl.expired():
        with np.errstate(all="ignore"):
            proof = find_farkas(None, np.zeros(n), -M, q, None, None, np.zeros(n), None, tl)
    if proof is None and n <= _MODULAR_MAX_N and lcp.is_symmetric and not tl.expired():
        proof = _null_vector_farkas(M, q, tl, check)
    return proof


def inverse_farkas(lcp, time_limit=None) -> Proof | None:
    """The rounded mechanism's proof alone (``_inverse_farkas``): for a
    symmetric M of n <= 40, y = -M⁻¹1 solved and checked exactly where its
    guess in doubles is one-signed; None otherwise.  The cheapest route that
    proves those data (0.06 s at n = 30), so a caller tries it first."""
    n = lcp.n
    if not lcp.is_symmetric or n > _INVERSE_MAX_N:
        return None
    tl = proof_deadline(time_limit)
    M = sp.csr_matrix(lcp.M)
    q = np.asarray(lcp.q, float)
    if tl.expired() or np.all(q >= 0):
        return None
    return _inverse_farkas(M, q, tl, _lcp_check(M, q))


def _lcp_check(M, q) -> FarkasCheck:
    """The exact check of y >= 0, M'y <= 0, q'y < 0 (the QP form: rows
    -Mz <= q, bounds z >= 0)."""
    n = q.size
    return FarkasCheck(-M, q, sp.csr_matrix((0, n)), np.zeros(0), np.zeros(n), np.full(n, np.inf))


def sign_farkas(M, q) -> Proof | None:
    """A row i with q_i < 0 and M[i, j] <= 0 for every j: w_i = M[i, :]z + q_i
    <= q_i < 0 for every z >= 0, so no z is feasible (the Farkas vector e_i).
    Exact from the signs of the stored doubles alone; the row whose q_i is
    most negative is named."""
    neg = np.flatnonzero(q < 0)
    if not neg.size:
        return None
    if sp.issparse(M):
        sub = sp.csr_matrix(M)[neg]
        top = np.asarray(sub.max(axis=1).toarray()).ravel() if sub.nnz else np.zeros(neg.size)
    else:
        top = np.max(np.asarray(M)[neg], axis=1)
    rows = neg[top <= 0]
    if not rows.size:
        return None
    i = int(rows[np.argmin(q[rows])])
    M = sp.csr_matrix(M)
    y = np.zeros(q.size)
    y[i] = 1.0
    exact = [Fraction(0)] * q.size
    exact[i] = Fraction(1)
    lower = np.maximum(-M.getrow(i).toarray().ravel(), 0.0)
    return Proof(
        kind="infeasible",
        message=(f"no z >= 0 has Mz + q >= 0: row {i} of M has no positive entry and q[{i}] = "
                 f"{q[i]:.3e} < 0, so w[{i}] <= q[{i}] < 0 for every z >= 0 (the Farkas vector "
                 f"e_{i}, read off the signs of the data)"),
        vector={"z": y, "y": np.zeros(0), "lower": lower, "upper": np.zeros(q.size),
                "exact": {"z": exact, "y": []}})


def _null_space_farkas(M, q, deadline, check) -> Proof | None:
    """For a symmetric PSD M: y = N x >= 0 with q'y < 0, N a basis of M's
    numerical null space (:func:`~qpcontact.proofs.lp.null_basis`), from
    one LP in the null space's few coordinates (HiGHS took 0.7 s on the
    full LP at n = 250 and 90-170 s at n = 1 000, the null space's LP
    milliseconds).  The candidate, snapped to short rationals, is checked
    exactly (a null vector of integer data has a short rational form)."""
    n = q.size
    basis = null_basis(M, deadline)
    if basis is None or deadline.expired():
        return None
    B, c = basis
    k = B.shape[1]
    qN = (B * c[:, None]).T @ q
    scale = float(np.max(np.abs(qN))) or 1.0
    # min q'y over y = c * (B x) >= 0 with |B x| <= 1 (c > 0: the signs are B x's)
    res = linprog(qN / scale, A_ub=np.vstack([-B, B]), b_ub=np.r_[np.zeros(n), np.ones(n)],
                  bounds=[(None, None)] * k, time_limit=deadline, tight=True)
    if res is None or res.status != 0 or res.x is None or not res.fun < -1e-9:
        return None
    # snapped in the balanced coordinates, mapped back exactly (c: powers of two)
    yt = np.maximum(B @ res.x, 0.0)
    top = float(yt.max(initial=0.0))
    if not top > 0:
        return None
    cF = [Fraction(float(v)) for v in c]
    for cand in itertools.chain([[Fraction(float(v)) for v in yt / top]],
                                candidates(yt / top, deadline)):
        proof = check.check([v * cj for v, cj in zip(cand, cF)], deadline)
        if proof is not None:
            return proof
    return None


#: an interior Farkas vector's margin (each column of M'y at most -margin
#: times its own size, after scaling) below which its doubles are not
#: expected to check exactly as they are
_INTERIOR_MARGIN = 1e-9


def _interior_farkas(M, q, deadline, check) -> Proof | None:
    """One LP: max t over y >= 0, sum(y) = 1, with every column of M'y and
    q'y at most -t times its own size (rows of M scaled to unit size, y
    scaled back).  Where Farkas vectors fill a cone with interior, its
    answer has every component of M'y negative with a margin far beyond
    rounding, so the doubles the LP returned check exactly as they are —
    no snapping to short rationals, which fails on the vertex of a random
    dense M (denominators of the size of its minors).  Where every Farkas
    vector has some column of M'y exactly zero (a PSD M: M y = 0) t = 0 and
    the vertex LPs follow."""
    n = q.size
    rs = row_scale(M)
    rs = np.where(np.abs(q) > 0, np.where(rs > 0, rs, 1.0 / np.where(q != 0, np.abs(q), 1.0)), rs)
    Ms = sp.diags(rs) @ M
    qs = rs * q
    live = np.flatnonzero(np.asarray(abs(Ms).max(axis=0).toarray()).ravel() > 0)
    if not live.size or not np.all(np.isfinite(Ms.data)) or not np.all(np.isfinite(qs)):
        return None
    size = np.asarray(abs(Ms).max(axis=0).toarray()).ravel()[live]
    qsize = float(np.max(np.abs(qs))) or 1.0
    # from _GAME_FROM unknowns the game's first-order method first (0.2 s of
    # CPU at n = 500 and 1.1 s at 1 000, where HiGHS took 1.8 s and 27 s);
    # below, HiGHS takes 0.02-0.2 s and ends at once on solvable data, where
    # the game runs until its bound decides (friction LCPs of n = 250: +40 %)
    y = (_margin_game(Ms[:, live], size, qs, qsize, deadline.share(_GAME_SHARE))
         if n >= _GAME_FROM else None)
    if y is _NO_MARGIN:
        return None     # the LP's t* is negative: it would find nothing
    if y is not None:
        y = y * rs
        top = float(y.max(initial=0.0))
        proof = check_farkas_hint(M, q, y / top, deadline, check) if top > 0 else None
        if proof is not None or deadline.expired():
            return proof
    # rows: Ms[:, live]' y + t size <= 0 and qs'y + t qsize <= 0
    A_ub = sp.vstack([sp.hstack([Ms[:, live].T, sp.csr_matrix(size[:, None])]),
                      sp.csr_matrix(np.r_[qs, qsize][None, :])]).tocsc()
    A_eq = sp.csr_matrix(np.r_[np.ones(n), 0.0][None, :])
    cost = np.zeros(n + 1)
    cost[-1] = -1.0
    with np.errstate(all="ignore"):
        res = linprog(cost, A_ub=A_ub, b_ub=np.zeros(A_ub.shape[0]), A_eq=A_eq, b_eq=[1.0],
                      bounds=[(0, None)] * n + [(0, 1)], time_limit=deadline, tight=True)
    if res is None or res.status != 0 or res.x is None or not -res.fun > _INTERIOR_MARGIN:
        return None
    y = np.maximum(res.x[:n], 0.0) * rs
    top = float(y.max(initial=0.0))
    return check_farkas_hint(M, q, y / top, deadline, check) if top > 0 else None


#: unknowns from which the game (_margin_game) is tried before the LP
_GAME_FROM = 300

#: the share of the interior search's time the game (_margin_game) may take
#: before the LP gets the rest
_GAME_SHARE = 0.5

#: a lower bound on the game's value above this ends it: no margin exists
#: (the LP's own acceptance needs t* > _INTERIOR_MARGIN, far below)
_GAME_BOUND = 1e-7

#: iterations of the game at most (each four products with M: n = 1 000
#: found its vectors in 420-510)
_GAME_ITERATIONS = 5000


#: what _margin_game returns when its lower bound shows that no vector has
#: a margin (the interior LP's t* < 0)
_NO_MARGIN = np.zeros(0)


def _margin_game(Ms, size, qs, qsize, deadline) -> np.ndarray | None:
    """y >= 0, sum(y) = 1, with every column of Ms'y and qs'y below
    -_INTERIOR_MARGIN times its size, found as the matrix game min over y
    max over the rows of A y (A: Ms' by columns over their sizes, and qs /
    qsize; entries in [-1, 1]) by Nemirovski's mirror-prox with entropy on
    both simplices (step 1), or None.  The game's value is minus the
    interior LP's margin t*: the averaged iterate's gap falls as O(log n /
    T), and any iterate with max(A y) < 0 is a Farkas vector with a margin
    — on the planted dense LCPs 60-510 iterations (n = 60..1 000, 0.02-1.1 s
    of CPU), margins 1e-5..1e-2.  A candidate only: the exact check decides.
    The averaged row weights x bound the value from below (min over y of
    x'Ay = min(A'x)): once that is positive no y has a margin, and
    _NO_MARGIN comes back (solvable data stop there, not at the cap)."""
    A = sp.vstack([sp.diags(1.0 / size) @ Ms.T, sp.csr_matrix((qs / qsize)[None, :])]).tocsr()
    if A.nnz > 0.3 * A.shape[0] * A.shape[1]:
        A = A.toarray()
    m, n = A.shape
    # the iterations in single precision (half the memory traffic of the
    # products that are all their cost); candidates judged in double
    G = A.astype(np.float32)

    def softmax(logw):
        e = np.exp(logw - logw.max())
        return e / e.sum()

    ly, lx = np.zeros(n, np.float32), np.zeros(m, np.float32)
    y, x = np.full(n, 1.0 / n, np.float32), np.full(m, 1.0 / m, np.float32)
    total, total_x = np.zeros(n), np.zeros(m)
    with np.errstate(all="ignore"):
        for it in range(1, _GAME_ITERATIONS + 1):
            y_h = softmax(ly - G.T @ x)
            x_h = softmax(lx + G @ y)
            ly, lx = ly - G.T @ x_h, lx + G @ y_h
            y, x = softmax(ly), softmax(lx)
            total += y_h
            total_x += x_h
            if it % 10:
                continue
            for cand in (y_h.astype(float), total / it):
                if float(np.max(A @ cand)) < -_INTERIOR_MARGIN:
                    return cand
            if float(np.min(A.T @ (total_x / it))) > _GAME_BOUND:
                return _NO_MARGIN
            if deadline.expired() or not np.all(np.isfinite(ly)):
                return None
    return None


#: how far (relative to each column's terms) a hint may miss M'y <= 0 in
#: floating point and still be checked exactly
_HINT_RTOL = 1e-6


def check_farkas_hint(M, q, y, deadline=None, check=None) -> Proof | None:
    """``y`` (its nonnegative part as it is, then snapped to short rationals)
    checked exactly as a Farkas vector of {z >= 0, Mz + q >= 0}, or None;
    ``check``: the exact check of these data, made once by the caller."""
    y = np.maximum(np.nan_to_num(np.asarray(y, float).ravel(), nan=0.0, posinf=0.0, neginf=0.0),
                   0.0)
    top = float(y.max(initial=0.0))
    if y.size != q.size or not top > 0:
        return None
    n = q.size
    Mc = sp.csr_matrix(M)
    y = y / top
    # the exact checks cost O(nnz) rationals per candidate: only a vector
    # that holds in floating point, to a loose tolerance, is worth them
    Mty, scale = Mc.T @ y, abs(Mc).T @ y
    if not (q @ y < 0 and np.all(Mty <= _HINT_RTOL * scale)):
        return None
    check = check or _lcp_check(Mc, q)
    for cand in itertools.chain([[Fraction(float(v)) for v in y]], candidates(y, deadline)):
        proof = check.check(cand, deadline)
        if proof is not None:
            return proof
    return None


#: largest n for the exact solve of M y = -1 (fraction-free elimination on
#: integers growing to n times the data's bits: 0.16 s at n = 30 and 0.6 s
#: at n = 40 on a loaded core)
_INVERSE_MAX_N = 40


def _inverse_farkas(M, q, deadline, check) -> Proof | None:
    """For a symmetric M a rounding away from singular on the indefinite
    side — B Bᵀ of a mechanism d >= 0 (Bᵀd = 0), rounded — the stored
    doubles have one tiny negative eigenvalue along d, no exact null vector,
    and Farkas vectors only in a thin cone around d: no LP vertex and no
    snapping lands in it.  y = -M⁻¹1 does: M y = -1 < 0 exactly, and the
    eigenvector of the tiny eigenvalue λ < 0 dominates M⁻¹, so y ≈ (1'd /
    |λ|) d >= 0.  In doubles (condition ~1/eps) y's sign is the rounding's,
    but whether it is one-signed is not: the solve in doubles, or where it
    meets an exactly zero pivot the eigenvector of the eigenvalue nearest
    zero, must be; then the exact solve and the exact check decide."""
    n = q.size
    A = M.toarray()
    if not np.all(np.isfinite(A)):
        return None

    def one_signed(v):
        v = v / (np.abs(v).max() or 1.0)
        return bool(np.all(np.isfinite(v)) and (np.all(v >= -1e-6) or np.all(v <= 1e-6)))

    with np.errstate(all="ignore"):
        try:
            guess = np.linalg.solve(A, np.ones(n))
        except np.linalg.LinAlgError:
            w, V = np.linalg.eigh(A)
            guess = V[:, int(np.argmin(np.abs(w)))]
    if not one_signed(guess):
        return None
    I, _ = ints(A.ravel())     # M = I 2^e: I y' = -1 gives y' = 2^e y, the same direction
    y = solve_integer(I.reshape(n, n), np.full(n, -1, dtype=object), deadline)
    if y is None or any(v < 0 for v in y):
        return None
    top = max(y)
    return check.check([v / top for v in y], deadline) if top > 0 else None


#: largest n for the modular null-vector route (O(n³) integer work mod p)
_MODULAR_MAX_N = 400


_PRIME = 2_147_483_629   # < 2^31: products of residues fit in int64


def _null_vector_farkas(M, q, deadline, check) -> Proof | None:
    """For symmetric M a Farkas vector y (y >= 0, M y <= 0, q'y < 0) of a
    PSD M lies in M's null space.  When M is exactly singular but its
    computed null space is wider (a second direction with singular value
    1e-14 of the largest: an LP returns a mix that no snapping makes exact),
    the exact null vector is found modulo a prime — M's doubles are integers
    times a power of two — and read back as small rationals; the exact check
    (``check``) decides.  Only a one-dimensional null space mod p is
    tried; the elimination stops at ``deadline`` (nothing proved)."""
    n = M.shape[0]
    A = M.toarray()
    if not np.all(np.isfinite(A)) or not np.any(A):
        return None
    # residues of the integers A / 2^e (exact: ints strips the power of two)
    I, _ = ints(A.ravel())
    R = np.mod(I, _PRIME).astype(np.int64).reshape(n, n)
    y = _null_mod_p(R, deadline)
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
    return check.check([c / top for c in cand], deadline)


def _null_mod_p(R, deadline=None) -> np.ndarray | None:
    """A basis vector of the null space of R mod p when it is one-dimensional
    (None as well once ``deadline`` passes)."""
    A = R.copy() % _PRIME
    n = A.shape[0]
    pivots, row = [], 0
    for col in range(n):
        if deadline is not None and deadline.expired():
            return None
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


#: Relative residual (each column against its own terms) below which a Farkas
#: vector or a feasible point from an LP is accepted as checked from the data.
FARKAS_RTOL = 1e-12


def feasibility(M: np.ndarray, q: np.ndarray, rs: np.ndarray, cs: np.ndarray,
                deadline=None) -> tuple[bool | None, dict]:
    """Whether {z >= 0, Mz + q >= 0} is nonempty, with evidence checked from the data.

    Returns (False, {"farkas": y}) when y >= 0 with M'y <= 0 and q'y < 0 was
    found (Farkas: then no z >= 0 has Mz + q >= 0, since y'(Mz + q) < 0);
    (True, {"point": z}) for a feasible z; (None, {...}) when neither could be
    checked.  The LPs run on the Ruiz-scaled data (R M C, R q; y = R y',
    z = C z'), and their answers are accepted only when every component holds
    on its own scale to FARKAS_RTOL: (M'y)_j <= FARKAS_RTOL (|M|'y)_j and
    q'y < -FARKAS_RTOL |q|'y; (Mz + q)_i >= -FARKAS_RTOL (|M||z| + |q|)_i.
    An LP's word alone is never a proof: on data spanning 1e-300..1e300 HiGHS
    called a solvable problem infeasible.  ``deadline`` (a
    :class:`~qpcontact.core.deadline.Deadline`): each LP gets what is left, and
    none starts once it has passed (the Farkas LP of a dense n = 1 000 LCP ran
    60 s after Lemke's ray, under a 20 s limit).
    """
    from scipy.optimize import linprog

    def options():
        left = None if deadline is None else deadline.left()
        if left is not None and left <= 0:
            return None
        return {} if left is None else {"time_limit": left}

    late = (None, {"reason": "the time limit passed before the LPs could decide"})

    n = q.size
    if sp.issparse(M):
        M = sp.csr_matrix(M)
        Ms = sp.csr_matrix(sp.diags(rs) @ M @ sp.diags(cs))
        absM = abs(M)
    else:
        Ms = M * rs[:, None] * cs[None, :]
        absM = np.abs(M)
    qs = q * rs
    # Positive scalars change no sign: the LPs see max|M| = max|q| = 1, and
    # z = C (b/a) z'' maps their point back.
    a = float(abs(Ms).max()) or 1.0
    b = float(np.max(np.abs(qs))) or 1.0
    Ms, qs = Ms / a, qs / b
    # Farkas: min qs'y' over y' >= 0, Ms'y' <= 0, sum(y') = 1.
    if options() is None:
        return late
    res = linprog(qs, A_ub=Ms.T, b_ub=np.zeros(n), A_eq=np.ones((1, n)), b_eq=[1.0],
                  bounds=(0, None), method="highs", options=options())
    if res.status == 0 and res.fun < 0:
        y = np.maximum(res.x * rs, 0.0)
        My, scale = M.T @ y, absM.T @ y
        qy, qscale = float(q @ y), float(np.abs(q) @ y)
        bad = np.maximum(My, 0.0) > FARKAS_RTOL * scale
        if not bad.any() and qy < -FARKAS_RTOL * qscale:
            return False, {"farkas": y}
    # A feasible point: z'' >= 0 with Ms z'' + qs >= 0.
    if options() is None:
        return late
    res = linprog(np.zeros(n), A_ub=-Ms, b_ub=qs, bounds=(0, None), method="highs",
                  options=options())
    if res.status == 0:
        z = np.maximum(res.x * cs * (b / a), 0.0)
        w = M @ z + q
        if np.all(np.isfinite(w)) and np.all(w >= -FARKAS_RTOL * (absM @ z + np.abs(q))):
            return True, {"point": z}
    return None, {"reason": "the LPs gave no answer that checks against the data"}
