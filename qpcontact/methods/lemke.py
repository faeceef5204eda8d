"""``"lemke"``: Lemke's complementary pivoting method for LCP(M, q), any M.

Tableau form of ``w - M z - d z0 = q`` with the covering vector d > 0
(default e): z0 enters at the value that makes q + d z0 >= 0, and from then on
the complement of the variable that just left enters.  The ratio test is
lexicographic (rows of the basis inverse, which the tableau carries in its
first n columns), so degenerate problems cannot cycle; ties are resolved in
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
(stiffness 1e8 next to loads of 1).  Cost: a dense n x (2n + 2) tableau, O(n²)
per pivot; up to a few thousand unknowns.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.linalg.blas import dger

from ..errors import InvalidOptionError, InvalidProblemError
from ..solution import MethodResult
from .active_set import DENSE_TABLEAU_LIMIT, ActiveBlock, dense_matrix

__all__ = ["LemkeOutcome", "lemke", "run_lemke", "ruiz_scaling", "lex_ratio_test",
           "tableau_pivot"]

_OPTIONS = ("covering", "max_pivots", "restarts", "seed")
#: Entries of an entering column below this fraction of its largest entry are
#: treated as zero in the ratio test.
PIVOT_RTOL = 1e-11


@dataclass
class LemkeOutcome:
    status: str                    # "solved", "ray", "max_pivots"
    z: np.ndarray | None           # the solution (unscaled) when solved
    basic_z: np.ndarray            # bool mask: z_i basic
    pivots: int
    ray: dict = field(default_factory=dict)


def ruiz_scaling(M: np.ndarray, iters: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Row and column factors r, c with r_i |M_ij| c_j near 1 in every row and column."""
    n = M.shape[0]
    r = np.ones(n)
    c = np.ones(n)
    A = np.abs(M)
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


def lex_ratio_test(T: np.ndarray, col: np.ndarray, rhs: np.ndarray, lex_cols: slice,
                   prefer_row: int | None = None) -> int | None:
    """Leaving row of a lexicographic minimum-ratio test, or None (a ray).

    Rows with col_i > PIVOT_RTOL max|col| compete on rhs_i / col_i; ties (equal
    up to rounding) go to ``prefer_row`` if it is among them, else to the
    lexicographically smallest row of T[:, lex_cols] / col_i.
    """
    cmax = float(np.max(np.abs(col))) if col.size else 0.0
    cand = np.flatnonzero(col > PIVOT_RTOL * cmax) if cmax > 0 else np.empty(0, int)
    if cand.size == 0:
        return None
    ratios = rhs[cand] / col[cand]
    theta = ratios.min()
    slack = 1e-12 * max(abs(theta), 1e-300) + 1e-15 * float(np.max(np.abs(rhs[cand])))
    ties = cand[ratios <= theta + slack]
    if ties.size == 1:
        return int(ties[0])
    if prefer_row is not None and prefer_row in ties:
        return int(prefer_row)
    V = T[ties, lex_cols] / col[ties, None]
    # Rounding noise is relative to the whole block, not to one column's entries
    # (an exact 0 computed as 1e-18 must still tie with another 0).
    floor = 1e-11 * max(float(np.max(np.abs(V))), 1e-300)
    alive = np.arange(ties.size)
    for k in range(V.shape[1]):
        vals = V[alive, k]
        alive = alive[vals <= vals.min() + floor]
        if alive.size == 1:
            break
    return int(ties[alive[0]])


def lemke(M: np.ndarray, q: np.ndarray, d: np.ndarray, max_pivots: int) -> LemkeOutcome:
    """Lemke's method on dense (already scaled) data; see the module docstring."""
    n = q.size
    if np.all(q >= 0):
        return LemkeOutcome("solved", np.zeros(n), np.zeros(n, bool), 0)
    # columns: w (0..n-1) | z (n..2n-1) | z0 (2n) | rhs (2n+1)
    T = np.empty((n, 2 * n + 2), order="F")
    T[:, :n] = np.eye(n)
    T[:, n:2 * n] = -M
    T[:, 2 * n] = -d
    T[:, 2 * n + 1] = q
    basis = np.arange(n)
    Z0, RHS = 2 * n, 2 * n + 1
    ratios = q / d
    theta = ratios.min()
    ties = np.flatnonzero(ratios <= theta + 1e-12 * abs(theta))
    r = int(ties[-1])  # lexicographic minimum of (q_i, e_i')/d_i: the largest tied index
    tableau_pivot(T, r, Z0)
    leaving = int(basis[r])
    basis[r] = Z0
    pivots = 1
    while True:
        entering = leaving + n if leaving < n else leaving - n
        col = T[:, entering]
        z0_row = np.flatnonzero(basis == Z0)
        r = lex_ratio_test(T, col, T[:, RHS], slice(0, n),
                           prefer_row=int(z0_row[0]) if z0_row.size else None)
        if r is None:
            x = np.zeros(2 * n + 1)
            x[basis] = T[:, RHS]
            dx = np.zeros(2 * n + 1)
            dx[basis] = -col
            dx[entering] = 1.0
            return LemkeOutcome("ray", None, (basis >= n) & (basis < 2 * n), pivots,
                                ray={"z": x[n:2 * n], "dz": dx[n:2 * n], "z0": x[Z0],
                                     "dz0": dx[Z0], "entering": entering})
        if pivots >= max_pivots:
            return LemkeOutcome("max_pivots", None, np.zeros(n, bool), pivots)
        tableau_pivot(T, r, entering)
        leaving = int(basis[r])
        basis[r] = entering
        pivots += 1
        if leaving == Z0:
            z = np.zeros(n)
            is_z = (basis >= n) & (basis < 2 * n)
            z[basis[is_z] - n] = np.maximum(T[is_z, RHS], 0.0)
            basic_z = np.zeros(n, bool)
            basic_z[basis[is_z] - n] = True
            return LemkeOutcome("solved", z, basic_z, pivots)


def _refined(M: np.ndarray, q: np.ndarray, z_tab: np.ndarray, basic_z: np.ndarray) -> np.ndarray:
    """The better certified of the tableau's z and the one recomputed from M_FF."""
    from ..certify import certify_lcp
    from ..problems import LCP

    lcp = LCP(M, q)
    best, best_err = z_tab, certify_lcp(lcp, z_tab).error
    try:
        z, _ = ActiveBlock(M, basic_z, symmetric=False).basic_solution(M, q)
    except np.linalg.LinAlgError:
        return best
    z = np.maximum(z, 0.0)
    err = certify_lcp(lcp, z).error
    return z if err <= best_err else best


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
    unknown = sorted(set(options) - set(_OPTIONS))
    if unknown:
        raise InvalidOptionError(f"'lemke' has no option(s) {unknown}; it takes {list(_OPTIONS)}")
    n = problem.n
    if n > DENSE_TABLEAU_LIMIT:
        raise InvalidProblemError(
            f"'lemke' keeps a dense {n} x {2 * n + 2} tableau; above n = {DENSE_TABLEAU_LIMIT} "
            "use 'bpp' (symmetric positive definite M) or a QP backend (monotone M)."
        )
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
    rng = np.random.default_rng(options.get("seed", 0))

    rs, cs = ruiz_scaling(M)
    Ms = M * rs[:, None] * cs[None, :]
    qs = q * rs
    monotone = problem.is_psd
    d = np.ones(n) if d_user is None else d_user
    total = 0
    tried = []
    while True:
        out = lemke(Ms, qs, d * rs, max_pivots)
        total += out.pivots
        tried.append(d)
        # A ray proves infeasibility for copositive-plus M; otherwise another
        # covering vector may well find a solution (CPS Example 4.4.23).
        if out.status != "ray" or monotone or len(tried) > restarts:
            break
        d = 0.5 + rng.random(n)
    stats = {"pivots": total, "last_run_pivots": out.pivots, "covering_vectors_tried": len(tried)}
    if out.status == "solved":
        z = _refined(M, q, out.z * cs, out.basic_z)
        return MethodResult(x=z, backend_status="solved", iterations=total, stats=stats)
    if out.status == "max_pivots":
        return MethodResult(x=None, status="max_pivots", backend_status="max_pivots",
                            backend_message=f"pivot limit {max_pivots} reached", iterations=total,
                            stats=stats)
    ray = out.ray
    stats["ray"] = {"z": ray["z"] * cs, "dz": ray["dz"] * cs, "z0": ray["z0"], "dz0": ray["dz0"]}
    feasible = _lp_feasible(M, q)
    stats["feasible"] = feasible
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
