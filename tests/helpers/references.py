"""Independent references for the pivoting and friction tests: textbook algorithms in exact
rational arithmetic and brute-force enumeration.  Deliberately slow and
simple; they share no code with qpcontact."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np


def exact_lemke_pivots(M, q) -> tuple[str, int]:
    """Lemke's method (covering vector e, lexicographic ratio test, z0 preferred
    on ties) in exact rationals; returns (status, pivots), counting the pivot
    that brings z0 in."""
    M = [[Fraction(x) for x in row] for row in np.asarray(M).tolist()]
    q = [Fraction(x) for x in np.asarray(q).tolist()]
    n = len(q)
    if min(q) >= 0:
        return "solved", 0
    T = [[Fraction(int(i == j)) for j in range(n)] + [-M[i][j] for j in range(n)]
         + [Fraction(-1), q[i]] for i in range(n)]
    basis, Z0 = list(range(n)), 2 * n

    def pivot(r, c):
        p = T[r][c]
        T[r] = [x / p for x in T[r]]
        for i in range(n):
            if i != r and T[i][c] != 0:
                f = T[i][c]
                T[i] = [a - f * b for a, b in zip(T[i], T[r])]

    m = min(q)
    r = max(i for i in range(n) if q[i] == m)
    pivot(r, Z0)
    leaving, basis[r], count = basis[r], Z0, 1
    while True:
        e = leaving + n if leaving < n else leaving - n
        cand = [i for i in range(n) if T[i][e] > 0]
        if not cand:
            return "ray", count
        theta = min(T[i][-1] / T[i][e] for i in cand)
        ties = [i for i in cand if T[i][-1] / T[i][e] == theta]
        z0 = [i for i in ties if basis[i] == Z0]
        if z0:
            r = z0[0]
        else:
            for col in range(n):
                v = min(T[i][col] / T[i][e] for i in ties)
                ties = [i for i in ties if T[i][col] / T[i][e] == v]
                if len(ties) == 1:
                    break
            r = ties[0]
        pivot(r, e)
        leaving, basis[r], count = basis[r], e, count + 1
        if leaving == Z0:
            return "solved", count


def enumerate_lcp(M, q, tol=1e-9) -> list[np.ndarray]:
    """Every complementary basic solution of a small LCP (2^n bases)."""
    M, q = np.asarray(M, float), np.asarray(q, float)
    n = q.size
    out = []
    for k in range(n + 1):
        for F in itertools.combinations(range(n), k):
            F = list(F)
            z = np.zeros(n)
            if F:
                try:
                    z[F] = np.linalg.solve(M[np.ix_(F, F)], -q[F])
                except np.linalg.LinAlgError:
                    continue
            w = M @ z + q
            scale = max(1.0, np.abs(q).max())
            if z.min() >= -tol * scale and w.min() >= -tol * scale:
                out.append(z)
    return out


def murty_family(n: int):
    """Murty (1988, ch. 6): upper triangular, 1 on the diagonal, 2 above; q = -e."""
    return np.eye(n) + 2 * np.triu(np.ones((n, n)), 1), -np.ones(n)


def fathi_family(n: int):
    """Fathi (1979): M = L L', L lower triangular, 1 on the diagonal, 2 below; q = -e."""
    L = np.eye(n) + 2 * np.tril(np.ones((n, n)), -1)
    return L @ L.T, -np.ones(n)


def _exact_basic(M, q, F):
    """(z, w) as Fractions on the basis F (z_F = -M_FF^-1 q_F), None if M_FF is singular."""
    n = len(q)
    A = [[M[i][j] for j in F] for i in F]
    b = [-q[i] for i in F]
    m = len(F)
    for k in range(m):
        p = max(range(k, m), key=lambda r: abs(A[r][k]))
        if A[p][k] == 0:
            return None
        A[k], A[p], b[k], b[p] = A[p], A[k], b[p], b[k]
        for r in range(k + 1, m):
            f = A[r][k] / A[k][k]
            if f:
                for c in range(k, m):
                    A[r][c] -= f * A[k][c]
                b[r] -= f * b[k]
    x = [Fraction(0)] * m
    for k in reversed(range(m)):
        x[k] = (b[k] - sum(A[k][c] * x[c] for c in range(k + 1, m))) / A[k][k]
    z = [Fraction(0)] * n
    for k, i in enumerate(F):
        z[i] = x[k]
    w = [sum(M[i][j] * z[j] for j in F) + q[i] for i in range(n)]
    return z, w


def exact_lcp_solution(M, q, guess) -> tuple[np.ndarray, np.ndarray]:
    """The exact solution of the data *as stored* (every float taken as the
    rational it is), found by Murty's least-index principal pivoting in exact
    rational arithmetic from the basis ``guess`` (bool mask of positive z's) —
    finite for P-matrices.  Near a planted solution only the degenerate pairs,
    which the rounding of q decides, move.  Returned rounded to floats."""
    M = [[Fraction(float(x)) for x in row] for row in np.asarray(M, float).tolist()]
    q = [Fraction(float(x)) for x in np.asarray(q, float).tolist()]
    F = set(int(i) for i in np.flatnonzero(guess))
    for _ in range(10 * len(q) + 100):
        zw = _exact_basic(M, q, sorted(F))
        assert zw is not None, "singular principal block: not a P-matrix"
        z, w = zw
        bad = [i for i in range(len(q)) if (i in F and z[i] < 0) or (i not in F and w[i] < 0)]
        if not bad:
            return np.array([float(v) for v in z]), np.array([float(v) for v in w])
        F ^= {bad[0]}
    raise AssertionError("exact pivoting did not finish")


def exact_basic_solution(M, q, active) -> tuple[np.ndarray, np.ndarray]:
    """The exact solution of the data *as stored* (every float taken as the
    rational it is) on the basis ``active``: z_F = -M_FF^-1 q_F in rationals,
    w = M z + q; returned rounded to floats, with a check that it solves the
    LCP (z >= 0, w >= 0) exactly."""
    Mf = [[Fraction(float(x)) for x in row] for row in np.asarray(M, float).tolist()]
    qf = [Fraction(float(x)) for x in np.asarray(q, float).tolist()]
    z, w = _exact_basic(Mf, qf, [int(i) for i in np.flatnonzero(active)])
    assert all(v >= 0 for v in z) and all(v >= 0 for v in w), "not a solution on this basis"
    return np.array([float(v) for v in z]), np.array([float(v) for v in w])


def natural_map_error_by_hand(W, q, mu, r) -> float:
    """Siconos's natural-map error ‖r − P_K(r − û)‖ / (1 + ‖q‖), written out
    contact by contact (û = u + μ‖u_T‖ e_N, u = W r + q; P_K the projection
    onto the Coulomb cone in closed form): the friction tests' reference,
    independent of the package's own measure."""
    if len(mu) == 0:
        return 0.0
    u = W @ r + q
    d = len(r) // len(mu)
    total = 0.0
    for i, m in enumerate(mu):
        ri, ui = r[d * i:d * i + d], u[d * i:d * i + d]
        uh = ui.copy()
        uh[0] += m * np.linalg.norm(ui[1:])
        x = ri - uh
        xn, xt = x[0], x[1:]
        nt = np.linalg.norm(xt)
        if nt <= m * xn:
            p = x
        elif m * nt <= -xn:
            p = np.zeros(d)
        else:
            a = (xn + m * nt) / (1 + m * m)
            p = np.r_[a, m * a * xt / nt]
        total += np.sum((ri - p) ** 2)
    return np.sqrt(total) / (1 + np.linalg.norm(q))


def coulomb_local_by_hand(A, b, mu) -> np.ndarray:
    """One contact's Coulomb problem u = A r + b (A = W_ii, 2 x 2, or 3 x 3
    diagonal with equal tangential entries: a sphere's), solved by its three
    cases written out here: open where b_N >= 0; sticking where A r = −b
    lies in the cone; else sliding with r_T = −μ r_N (the direction of u_T)
    and u_N = 0 — in 2-D each sign tried, in 3-D the direction of b_T
    (with A diagonal u_T = b_T + c r_T is parallel to b_T)."""
    d = len(b)
    if b[0] >= 0:
        return np.zeros(d)
    r = np.linalg.solve(A, -b)
    if r[0] >= 0 and np.linalg.norm(r[1:]) <= mu * r[0]:
        return r
    if d == 2:
        for s in (1.0, -1.0):         # u_T of sign s, r_T = −s μ r_N
            rn = -b[0] / (A[0, 0] - s * mu * A[0, 1])
            ut = (A[1, 0] - s * mu * A[1, 1]) * rn + b[1]
            if rn >= 0 and s * ut >= 0:
                return np.array([rn, -s * mu * rn])
        raise ValueError("no case fits this 2-D block")
    assert np.allclose(A, np.diag(np.diag(A)), rtol=0, atol=1e-12 * abs(A).max())
    rn = -b[0] / A[0, 0]
    return np.r_[rn, -mu * rn * b[1:] / np.linalg.norm(b[1:])]


def nsgs_sweeps_by_hand(W, q, mu, r, n_sweeps) -> np.ndarray:
    """``n_sweeps`` Gauss–Seidel sweeps over the contacts in order, each
    contact's problem solved with the others' latest r frozen
    (:func:`coulomb_local_by_hand`), W dense: the friction tests' NSGS."""
    W = np.asarray(W.toarray() if hasattr(W, "toarray") else W, float)
    d = len(r) // len(mu)
    r = np.array(r, float)
    for _ in range(n_sweeps):
        for i, m in enumerate(mu):
            own = slice(d * i, d * i + d)
            b = q[own] + W[own] @ r - W[own, own] @ r[own]
            r[own] = coulomb_local_by_hand(W[own, own], b, m)
    return r
