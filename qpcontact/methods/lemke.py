"""``"lemke"``: Lemke's complementary pivoting method for LCP(M, q), any M.

Revised (basis-inverse) form of ``w - M z - d z0 = q`` with the covering vector d > 0
(default e): z0 enters at the value that makes q + d z0 >= 0, and from then on
the complement of the variable that just left enters.  The ratio test is
lexicographic (rows of the basis inverse), so degenerate problems cannot cycle; ties are resolved in
favour of z0 leaving.  The method ends

- ``solved``: z0 left the basis, the basis is complementary.  The basic values
  are then recomputed from the active block M_FF (LU with iterative refinement)
  and the better-certified of the two points is returned;
- ``ray``: the entering column has no positive entry (a secondary ray).  When M
  is copositive-plus (e.g. positive semidefinite) this proves the LCP has no
  solution (Cottle, Pang & Stone 1992, Thm 4.4.13).  For other M it proves
  nothing, so the method restarts with other covering vectors (``restarts``,
  seeded) before reporting the ray, and an LP tells whether {z >= 0,
  Mz + q >= 0} is empty (then no solution exists);
- ``max_pivots``: the pivot limit was reached.

The LCP is solved after row/column equilibration (w' = D_r w, z = D_c z'), which
keeps complementarity and makes sign tolerances meaningful for badly scaled data
(stiffness 1e8 next to loads of 1).  Cost: a dense n x n basis inverse, O(n²)
per pivot; up to a few thousand unknowns (DENSE_TABLEAU_LIMIT).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg
from scipy.linalg.blas import dger

from ..errors import InvalidOptionError
from ..solution import MethodResult
from .active_set import (ActiveBlock, check_dense_size, check_options, dense_matrix,
                         sign_tolerances)

__all__ = ["LemkeOutcome", "lemke", "run_lemke", "ruiz_scaling", "lex_ratio_test",
           "tableau_pivot"]

_OPTIONS = ("covering", "max_pivots", "restarts", "seed")
#: Entries of an entering column below this fraction of its largest entry are
#: treated as zero in the ratio test.
PIVOT_RTOL = 1e-11
#: Pivots between recomputations of the basis inverse from the basis columns
#: (at least n, so refactoring costs O(n²) per pivot on average).
REFACTOR_EVERY = 50


@dataclass
class LemkeOutcome:
    status: str                    # "solved", "ray", "max_pivots"
    z: np.ndarray | None           # the solution (unscaled) when solved
    basic_z: np.ndarray            # bool mask: z_i basic
    pivots: int
    ray: dict = field(default_factory=dict)


def ruiz_scaling(M: np.ndarray, iters: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Row and column factors r, c with r_i |M_ij| c_j near 1 in every row and column.

    Ones when every row and column maximum is already within a factor 4 of the
    largest (scaling would only cost time).
    """
    n = M.shape[0]
    r = np.ones(n)
    c = np.ones(n)
    A = np.abs(M)
    rm, cm = A.max(axis=1), A.max(axis=0)
    top = max(rm.max(), cm.max()) if n else 0.0
    if top > 0 and min(rm.min(), cm.min()) >= top / 4:
        return r, c
    for _ in range(iters):
        S = A * r[:, None] * c[None, :]
        rm = S.max(axis=1)
        cm = S.max(axis=0)
        r /= np.sqrt(np.where(rm > 0, rm, 1.0))
        c /= np.sqrt(np.where(cm > 0, cm, 1.0))
    return r, c


def tableau_pivot(T: np.ndarray, r: int, c: int) -> None:
    """Gauss–Jordan pivot of the (Fortran-ordered) tableau T on (r, c), in place."""
    col = T[:, c].copy()
    T[r, :] /= col[r]
    col[r] = 0.0
    dger(-1.0, col, T[r, :].copy(), a=T, overwrite_a=True)


def lex_ratio_test(col: np.ndarray, rhs: np.ndarray, lex: np.ndarray,
                   prefer_row: int | None = None, rhs_scale: float | None = None) -> int | None:
    """Leaving row of a lexicographic minimum-ratio test, or None (a ray).

    Rows with col_i > PIVOT_RTOL max|col| compete on rhs_i / col_i; ties (equal
    up to rounding) go to ``prefer_row`` if it is among them, else to the
    lexicographically smallest row of lex[i, :] / col_i (lex is the basis
    inverse, or any matrix whose rows make the tableau lexico-positive).
    """
    cmax = np.abs(col).max() if col.size else 0.0
    if not cmax > 0:
        return None
    cand = (col > PIVOT_RTOL * cmax).nonzero()[0]
    if cand.size == 0:
        return None
    ratios = rhs[cand] / col[cand]
    k = ratios.argmin()
    theta = ratios[k]
    if rhs_scale is None:
        rhs_scale = np.abs(rhs).max()
    tied = ratios <= theta + (1e-12 * abs(theta) + 1e-15 * rhs_scale)
    if np.count_nonzero(tied) == 1:
        return int(cand[k])
    ties = cand[tied]
    if prefer_row is not None and prefer_row in ties:
        return int(prefer_row)
    V = lex[ties] / col[ties, None]
    # Rounding noise is relative to the whole block, not to one column's entries
    # (an exact 0 computed as 1e-18 must still tie with another 0).
    floor = 1e-10 * max(float(np.max(np.abs(V))), 1e-300)
    alive = np.arange(ties.size)
    for j in range(V.shape[1]):
        vals = V[alive, j]
        alive = alive[vals <= vals.min() + floor]
        if alive.size == 1:
            break
    return int(ties[alive[0]])


def lemke(M: np.ndarray, q: np.ndarray, d: np.ndarray, max_pivots: int) -> LemkeOutcome:
    """Lemke's method on dense (already scaled) data; see the module docstring.

    Revised form: T = [B^-1 | x] (n x (n + 1)) holds the basis inverse and the
    basic values; each entering column is B^-1 times a column of [I, -M, -d],
    and a pivot is one rank-one update of T — half the work of the full
    n x (2n + 2) tableau.
    """
    n = q.size
    if np.all(q >= 0):
        return LemkeOutcome("solved", np.zeros(n), np.zeros(n, bool), 0)
    Mf = np.asfortranarray(M)
    T = np.zeros((n, n + 1), order="F")
    T[:, :n] = np.eye(n)
    T[:, n] = q
    Binv, x = T[:, :n], T[:, n]  # views
    basis = np.arange(n)  # variable ids: w 0..n-1, z n..2n-1, z0 2n
    Z0 = 2 * n

    def refactor():
        # Product-form updates drift: on Fathi's family (2^n pivots) a column
        # computed from the updated inverse was off by O(100) after ~1000
        # pivots.  Recompute the inverse from the basis columns periodically.
        B = np.zeros((n, n), order="F")
        is_w = basis < n
        B[basis[is_w], np.flatnonzero(is_w)] = 1.0
        is_z = (basis >= n) & (basis < Z0)
        B[:, is_z] = -Mf[:, basis[is_z] - n]
        B[:, basis == Z0] = -d[:, None]
        Binv[:] = scipy.linalg.inv(B, check_finite=False)
        x[:] = scipy.linalg.solve(B, q, check_finite=False)
        # Basic values of a feasible basis are >= 0; rounding leaves exact
        # (degenerate) zeros at +-1e-17, which would win or lose ratio tests
        # that the lexicographic rule must decide.
        x[x < 1e-13 * max(float(np.max(np.abs(x))), 1e-300)] = 0.0

    refactor_every = max(REFACTOR_EVERY, n)

    def pivot(col, r):
        row = T[r] / col[r]
        col[r] = 0.0
        dger(-1.0, col, row, a=T, overwrite_a=True)
        T[r] = row

    ratios = q / d
    theta = ratios.min()
    ties = np.flatnonzero(ratios <= theta + 1e-12 * abs(theta))
    r = int(ties[-1])  # lexicographic minimum of (q_i, e_i')/d_i: the largest tied index
    pivot(-(Binv @ d), r)
    leaving = int(basis[r])
    basis[r] = Z0
    z0_row = r
    pivots = 1
    while True:
        entering = leaving + n if leaving < n else leaving - n
        if entering < n:
            col = Binv[:, entering].copy()
        else:
            col = Binv @ Mf[:, entering - n]
            np.negative(col, out=col)
        r = lex_ratio_test(col, x, Binv, prefer_row=z0_row)
        if r is None:
            v = np.zeros(2 * n + 1)
            v[basis] = x
            dv = np.zeros(2 * n + 1)
            dv[basis] = -col
            dv[entering] = 1.0
            return LemkeOutcome("ray", None, (basis >= n) & (basis < Z0), pivots,
                                ray={"z": v[n:Z0], "dz": dv[n:Z0], "z0": v[Z0], "dz0": dv[Z0],
                                     "entering": entering})
        if pivots >= max_pivots:
            return LemkeOutcome("max_pivots", None, np.zeros(n, bool), pivots)
        pivot(col, r)
        leaving = int(basis[r])
        basis[r] = entering
        pivots += 1
        if pivots % refactor_every == 0:
            refactor()
        if leaving == Z0:
            is_z = basis >= n  # z0 has left: every basic variable is a w or a z
            zi, wi = basis[is_z] - n, basis[~is_z]
            for _ in range(2):
                # Iterative refinement against the data: w - M z = q on the basis.
                z = np.zeros(n)
                z[zi] = x[is_z]
                w = np.zeros(n)
                w[wi] = x[~is_z]
                r = q - w + Mf @ z
                x += Binv @ r
            z = np.zeros(n)
            z[zi] = np.maximum(x[is_z], 0.0)
            basic_z = np.zeros(n, bool)
            basic_z[zi] = True
            return LemkeOutcome("solved", z, basic_z, pivots)


def _sign_errors(lcp, M, z, basic_z) -> bool:
    """Whether z (nonbasic entries 0) leaves a nonbasic w negative or a basic
    w nonzero beyond the sign tolerances."""
    tau_z, tau_w = sign_tolerances(M, lcp.q, lcp.matrix_scale)
    w = M @ z + lcp.q
    return bool(np.any(w[~basic_z] < -tau_w) or np.any(np.abs(w[basic_z]) > tau_w))


def _refined(lcp, M: np.ndarray, z_tab: np.ndarray, basic_z: np.ndarray) -> np.ndarray:
    """z recomputed from the active block M_FF (LU, refined) when its signs are
    right; the tableau's z otherwise (a singular or degenerate block)."""
    q = lcp.q
    tau_z, tau_w = sign_tolerances(M, q, lcp.matrix_scale)
    try:
        z, w = ActiveBlock(M, basic_z, symmetric=False).basic_solution(M, q, refine=2)
    except np.linalg.LinAlgError:
        return z_tab
    if np.all(z[basic_z] >= -tau_z) and np.all(w[~basic_z] >= -tau_w):
        return np.maximum(z, 0.0)
    return z_tab


def _lp_feasible(M, q) -> bool | None:
    """Whether {z >= 0, Mz + q >= 0} is nonempty (None if the LP solver cannot say)."""
    from scipy.optimize import linprog

    res = linprog(np.zeros(q.size), A_ub=-M, b_ub=q, bounds=(0, None), method="highs")
    if res.status == 0:
        return True
    if res.status == 2:
        return False
    return None


def run_lemke(problem, tol, options) -> MethodResult:
    check_options("lemke", options, _OPTIONS)
    n = problem.n
    check_dense_size("lemke", n, f"{n} x {n} basis inverse",
                     "'bpp' (symmetric positive definite M) or a QP backend (monotone M)")
    M = dense_matrix(problem.M)
    q = problem.q
    d_user = options.get("covering")
    if d_user is not None:
        d_user = np.asarray(d_user, dtype=float).ravel()
        if d_user.shape != (n,) or not np.all(np.isfinite(d_user)) or not np.all(d_user > 0):
            raise InvalidOptionError(
                f"'lemke': covering must be a vector of {n} finite positive numbers"
            )
    max_pivots = int(options.get("max_pivots", max(10_000, 50 * n)))
    restarts = int(options.get("restarts", 3))
    rng = None

    rs, cs = ruiz_scaling(M)
    Ms = M if (rs == 1).all() and (cs == 1).all() else M * rs[:, None] * cs[None, :]
    qs = q * rs
    d = np.ones(n) if d_user is None else d_user
    total = 0
    tried = []
    while True:
        out = lemke(Ms, qs, d * rs, max_pivots)
        total += out.pivots
        tried.append(d)
        # A ray proves infeasibility for copositive-plus M; otherwise another
        # covering vector may well find a solution (CPS Example 4.4.23).
        if out.status != "ray" or problem.is_psd or len(tried) > restarts:
            break
        rng = rng or np.random.default_rng(options.get("seed", 0))
        d = 0.5 + rng.random(n)
    stats = {"pivots": total, "last_run_pivots": out.pivots, "covering_vectors_tried": len(tried)}
    if out.status == "solved":
        z = out.z * cs
        if _sign_errors(problem, M, z, out.basic_z):
            z = _refined(problem, M, z, out.basic_z)
        return MethodResult(x=z, backend_status="solved", iterations=total, stats=stats)
    if out.status == "max_pivots":
        return MethodResult(x=None, status="max_pivots", backend_status="max_pivots",
                            backend_message=f"pivot limit {max_pivots} reached", iterations=total,
                            stats=stats)
    ray = out.ray
    stats["ray"] = {"z": ray["z"] * cs, "dz": ray["dz"] * cs, "z0": ray["z0"], "dz0": ray["dz0"]}
    feasible = _lp_feasible(M, q)
    stats["feasible"] = feasible
    monotone = problem.is_psd
    if monotone:
        why = ("M is positive semidefinite (copositive-plus), so Lemke's secondary ray proves "
               "the LCP has no solution")
    elif feasible is False:
        why = "no z >= 0 has Mz + q >= 0 (an LP proves the feasible set empty): no solution exists"
    else:
        why = (f"Lemke's method ended on a secondary ray with {len(tried)} covering vector(s); "
               "for this M that does not prove there is no solution (the feasible set is "
               f"{'nonempty' if feasible else 'of unknown emptiness'}); try other covering vectors "
               "(option covering=) or an enumeration method")
    stats["proved_infeasible"] = bool(monotone or feasible is False)
    return MethodResult(x=None, status="ray", backend_status="ray", backend_message=why,
                        iterations=total, stats=stats)
