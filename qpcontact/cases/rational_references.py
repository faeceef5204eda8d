"""Exact rational arithmetic on stored doubles, for the stress families whose
reference must not come from a solver: every double is a dyadic rational, so
``(M, q)`` scaled by one power of two is a matrix of Python integers, and
fraction-free (Bareiss) elimination decides definiteness, solves principal
blocks and checks Farkas vectors without a single rounding.

Written here, on purpose apart from :mod:`qpcontact.proofs.exact`: the stress
suite judges the engine, so its references take a route that shares no code
with the engine's proofs.  Sizes up to about 40 cost well under a second per
solve; the work grows like n³ on integers of n·(bits of the data) digits.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from ..core.deadline import Deadline

__all__ = ["ExactLCP", "dyadic_integers", "leading_minors_positive", "solve_exact",
           "lcp_farkas_holds", "dot_exact", "round_down", "round_up"]


def dyadic_integers(*arrays) -> tuple[list, int]:
    """The arrays (flattened, concatenated) times 2**k as Python integers, with
    the smallest k that makes every entry an integer.  One k for all, so that
    ratios (a solution z of M z = -q) are unchanged."""
    flat = np.concatenate([np.asarray(a, float).ravel() for a in arrays])
    if not np.all(np.isfinite(flat)):
        raise ValueError("exact arithmetic needs finite data")
    fr = [Fraction(float(v)) for v in flat]
    k = max((f.denominator.bit_length() - 1 for f in fr), default=0)
    return [f.numerator * ((1 << k) // f.denominator) for f in fr], k


def dot_exact(a, b) -> Fraction:
    """Σ a_i b_i in exact arithmetic (doubles or Fractions)."""
    return sum((Fraction(x) * Fraction(y) for x, y in zip(a, b)), Fraction(0))


def round_down(x: Fraction) -> float:
    """The largest double <= x (a rounding the caller can rely on the side of)."""
    f = float(x)
    return float(np.nextafter(f, -np.inf)) if Fraction(f) > x else f


def round_up(x: Fraction) -> float:
    f = float(x)
    return float(np.nextafter(f, np.inf)) if Fraction(f) < x else f


def _bareiss(rows: list[list[int]], ncols_solved: int, pivoting: bool):
    """In-place fraction-free elimination of the first ``ncols_solved``
    columns.  Returns the list of pivots (the k-th, without pivoting, is the
    k-th leading principal minor), or None when a pivot is zero (and
    ``pivoting`` is off, or no row below has a nonzero)."""
    n = ncols_solved
    prev = 1
    pivots = []
    for k in range(n):
        if rows[k][k] == 0:
            if not pivoting:
                return None
            swap = next((r for r in range(k + 1, n) if rows[r][k] != 0), None)
            if swap is None:
                return None
            rows[k], rows[swap] = rows[swap], rows[k]
        piv = rows[k][k]
        rk = rows[k]
        for i in range(k + 1, n):
            ri = rows[i]
            m = ri[k]
            if m == 0:
                for j in range(k + 1, len(ri)):
                    ri[j] = ri[j] * piv // prev
            else:
                for j in range(k + 1, len(ri)):
                    ri[j] = (ri[j] * piv - m * rk[j]) // prev
            ri[k] = 0
        prev = piv
        pivots.append(piv)
    return pivots


def leading_minors_positive(Mi: list[list[int]]) -> bool:
    """Whether every leading principal minor of the integer matrix is > 0:
    for a symmetric matrix, exactly positive definiteness (Sylvester), and
    the same as a rational LDLᵀ with every pivot positive."""
    rows = [list(r) for r in Mi]
    pivots = _bareiss(rows, len(rows), pivoting=False)
    return pivots is not None and all(p > 0 for p in pivots)


def solve_exact(A: list[list[int]], b: list[int]) -> list[Fraction] | None:
    """x with A x = b exactly (A square, integer), None when A is singular."""
    n = len(A)
    if n == 0:
        return []
    rows = [list(A[i]) + [b[i]] for i in range(n)]
    if _bareiss(rows, n, pivoting=True) is None:
        return None
    x = [Fraction(0)] * n
    for i in range(n - 1, -1, -1):
        s = Fraction(rows[i][n]) - sum((rows[i][j] * x[j] for j in range(i + 1, n)), Fraction(0))
        x[i] = s / rows[i][i]
    return x


def lcp_farkas_holds(M, q, y) -> bool:
    """Whether y >= 0, Mᵀy <= 0 and q'y < 0 hold exactly for the stored
    doubles: then y'(Mz + q) = (Mᵀy)'z + q'y < 0 for every z >= 0, so no z
    has w = Mz + q >= 0.  Checked on integers (one power of two for M, y, q)."""
    y = np.asarray(y, float)
    if np.any(y < 0) or not np.any(y > 0):
        return False
    M = np.asarray(M, float)
    n = M.shape[0]
    ints, _ = dyadic_integers(M, q)
    Mi = [ints[i * n:(i + 1) * n] for i in range(n)]
    qi = ints[n * n:]
    yi, _ = dyadic_integers(y)
    for j in range(n):
        if sum(Mi[i][j] * yi[i] for i in range(n) if yi[i]) > 0:
            return False
    return sum(qi[i] * yi[i] for i in range(n)) < 0


class ExactLCP:
    """An LCP (M, q) held as integers, with exact principal-block solves."""

    def __init__(self, M, q):
        M = np.asarray(M, float)
        self.n = n = M.shape[0]
        ints, self.shift = dyadic_integers(M, q)
        self.M = [ints[i * n:(i + 1) * n] for i in range(n)]
        self.q = ints[n * n:]

    def positive_definite(self) -> bool:
        return leading_minors_positive(self.M)

    def basis_solution(self, F) -> tuple[list[Fraction], list[Fraction]] | None:
        """(z, w) of the complementary basis F (z_N = 0, w_F = 0) exactly,
        None when M_FF is singular.  The integers are (M, q) times 2**shift:
        z is unchanged by that, w is scaled back."""
        F = sorted(F)
        zF = solve_exact([[self.M[i][j] for j in F] for i in F], [-self.q[i] for i in F])
        if zF is None:
            return None
        z = [Fraction(0)] * self.n
        for i, v in zip(F, zF):
            z[i] = v
        unit = Fraction(1, 1 << self.shift)
        w = [(self.q[i] + sum((self.M[i][j] * z[j] for j in F), Fraction(0))) * unit
             for i in range(self.n)]
        for i in F:
            w[i] = Fraction(0)   # zero by construction; exact arithmetic agrees
        return z, w

    def murty(self, start, *, max_steps: int, budget_s: float):
        """Murty's least-index principal pivoting from the basis ``start``:
        finite on a P-matrix from any start (Murty 1974); here every step is
        one exact block solve.  Returns (z, w) exactly, or None when the step
        or time budget runs out or a block is singular."""
        F = set(int(i) for i in start)
        deadline = Deadline(budget_s)
        for _ in range(max_steps):
            sol = self.basis_solution(F)
            if sol is None:
                return None
            z, w = sol
            bad = next((i for i in range(self.n)
                        if (i in F and z[i] < 0) or (i not in F and w[i] < 0)), None)
            if bad is None:
                return z, w
            F ^= {bad}
            if deadline.expired():
                return None
        return None

    def farkas_by_solve(self) -> list[Fraction] | None:
        """y with M y = -1 exactly, when y >= 0 and q'y < 0: a Farkas vector
        (Mᵀy = My = -1 < 0 for symmetric M).  It is found where the stored M
        is a rounding away from singular on the indefinite side: M⁻¹1 is then
        dominated by the eigenvector of the tiny negative eigenvalue, and
        that eigenvector is the mechanism d >= 0.  Exact, so no margin needed."""
        if any(self.M[i][j] != self.M[j][i] for i in range(self.n) for j in range(i)):
            return None
        y = solve_exact(self.M, [-1] * self.n)
        if y is None or any(v < 0 for v in y):
            return None
        return y if sum((qi * yi for qi, yi in zip(self.q, y)), Fraction(0)) < 0 else None

    def verify_basis(self, F):
        """(z, w) when the basis F is exactly complementary-feasible, else None."""
        sol = self.basis_solution(F)
        if sol is None:
            return None
        z, w = sol
        return (z, w) if all(v >= 0 for v in z) and all(v >= 0 for v in w) else None


def float_bpp(M, q, start=None, iters: int = 30):
    """A candidate basis by block principal pivoting in floating point
    (Júdice–Pires): only a starting point for the exact pivoting, never an
    answer, so its failures cost steps, not correctness."""
    M = np.asarray(M, float)
    n = q.size
    F = np.zeros(n, bool) if start is None else np.isin(np.arange(n), list(start))
    if start is None:
        F = q < 0
    best = F.copy()
    for _ in range(iters):
        z = np.zeros(n)
        if F.any():
            try:
                z[F] = np.linalg.solve(M[np.ix_(F, F)], -q[F])
            except np.linalg.LinAlgError:
                break
        w = M @ z + q
        bad = (F & (z < 0)) | (~F & (w < 0))
        best = F.copy()
        if not bad.any():
            break
        F = F ^ bad
    return set(np.flatnonzero(best).tolist())
