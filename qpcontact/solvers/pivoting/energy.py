"""``"energy"``: the decomposition algorithm of Kolesnikov (2013) for
LCP(M, q) with M symmetric positive definite.

The tableau ``y = T x + q̄`` starts as ``w = M z + q``; its constant column q̄
holds the values of all basic variables (basic w's *and* basic z's).  While some
q̄_i is negative, the energy criterion

    p_i = -q̄_i² / T_ii   (the drop of ½z'Mz + q'z when only that variable moves)

picks the index i* = argmin p_i, and one Gauss–Jordan principal pivot on T_i*i*
exchanges w_i* and z_i* (ties: the lowest index).  Mechanically each pivot
switches one contact on or off, largest energy drop first.  A basic z_i that
turns negative is pivoted back out by the same rule (the paper's "facts checked
numerically": a variant that never drops an index is wrong for SPD matrices).

Safety, because termination of the rule is not proven:

- a repeated basis, or more than :func:`energy_pivot_cap` pivots, switches to
  Murty's least-index principal pivoting (pivot on the lowest index with
  q̄_i < 0), finite for every P-matrix from any starting basis (Murty 1974;
  PPTs of a PD matrix are P-matrices).  ``stats["fallback"]`` records it;
- when the tableau says "done", the basic values are recomputed from the active
  block M_FF by Cholesky with iterative refinement; if they disagree in sign the
  tableau is rebuilt from the data and pivoting goes on
  (``stats["refreshes"]`` counts it);
- the LCP is solved in the symmetric Jacobi scaling D M D, D = diag(M)^-1/2,
  which leaves the criterion and so the pivot sequence unchanged.

Cost: a dense n x n tableau, O(n²) per pivot.  For large sparse problems use
``"bpp"``.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg.blas import dger

from ...core.deadline import Deadline
from ...core.errors import NotConvexError
from ...core.results import MethodResult
from ...core.linalg import ActiveBlock, SolutionOverflow, dense_matrix, symmetric_scaling
from ...judge.scales import ComponentScales
from .active_set import (check_dense_size, negative_components, not_positive_definite,
                         overflow_result, sign_tolerances, time_limit_result)
from ...core.options import BySize, Option, read_options

__all__ = ["energy_pivot_cap", "run_energy", "principal_pivot", "ppt_tableau", "ENERGY_OPTIONS"]

ENERGY_OPTIONS = (
    Option("max_pivots", BySize(lambda n: 100 * n + 1000, "100 n + 1000"), "int", low=0,
           doc="principal pivots at most"),
    Option("rule", "energy", "choice", choices=("energy", "murty"),
           doc="the pivot rule: least energy, or Murty's least index"),
)


def energy_pivot_cap(n: int) -> int:
    """Pivots the energy rule may take before Murty's rule takes over: 5n + 20.

    Kolesnikov's numerical study needed 65 pivots at n = 50 (ill-conditioned) and never
    came near this; the cap only bounds the damage of a cycle the repeated-basis
    detector would miss.
    """
    return 5 * n + 20


def principal_pivot(T: np.ndarray, qbar: np.ndarray, r: int) -> None:
    """Principal pivot of ``y = T x + qbar`` on T[r, r], in place (T Fortran-ordered)."""
    piv = T[r, r]
    col = T[:, r].copy()
    row = T[r, :].copy()
    qr = qbar[r]
    # T <- T - col row / piv, then fix row r and column r.
    dger(-1.0 / piv, col, row, a=T, overwrite_a=True)
    T[r, :] = -row / piv
    T[:, r] = col / piv
    T[r, r] = 1.0 / piv
    qbar -= col * (qr / piv)
    qbar[r] = -qr / piv


def ppt_tableau(M: np.ndarray, q: np.ndarray, basic: np.ndarray):
    """The principal pivotal transform of (M, q) on the basis ``basic``, from the data.

    Returns (T, qbar) with T Fortran-ordered.  Raises LinAlgError when M_BB is
    not numerically positive definite.
    """
    n = q.size
    B = np.flatnonzero(basic)
    N = np.flatnonzero(~basic)
    T = np.empty((n, n), order="F")
    qbar = np.empty(n)
    if B.size == 0:
        T[:] = M
        return T, q.copy()
    block = ActiveBlock(M, B, symmetric=True)
    inv = block.solve(np.eye(B.size), refine=0)
    X = block.solve(M[np.ix_(B, N)], refine=0)  # M_BB^-1 M_BN
    T[np.ix_(B, B)] = inv
    T[np.ix_(B, N)] = -X
    T[np.ix_(N, B)] = X.T
    T[np.ix_(N, N)] = M[np.ix_(N, N)] - M[np.ix_(N, B)] @ X
    zB = block.solve(-q[B])
    qbar[B] = zB
    qbar[N] = q[N] + M[np.ix_(N, B)] @ zB
    return T, qbar


def _energy(M: np.ndarray, q: np.ndarray, q_terms: np.ndarray, max_pivots: int, rule: str,
            deadline: Deadline):
    n = q.size
    scale = float(np.max(np.abs(M))) if M.size else 0.0
    scales = ComponentScales(M, q_terms, scale)
    basic = np.zeros(n, dtype=bool)
    T = np.asfortranarray(M.copy())
    qbar = q.copy()
    stats = {"pivots": 0, "energy_pivots": 0, "murty_pivots": 0, "fallback": False,
             "fallback_reason": None, "refreshes": 0}
    seen = {basic.tobytes()}
    cap = energy_pivot_cap(n)
    current = rule
    if current == "murty":
        stats["fallback_reason"] = "requested"
    while True:
        # Each value is judged on its own scale at the current point (the
        # basic z's are qbar's basic entries).
        neg = negative_components(scales, qbar, basic, np.where(basic, qbar, 0.0))
        if neg.size == 0:
            # The tableau says done: recompute from the data before believing it.
            z, w = ActiveBlock(M, basic, symmetric=True).basic_solution(M, q)
            tau_z, tau_w = sign_tolerances(scales, z)
            if np.all(z[basic] >= -tau_z[basic]) and np.all(w[~basic] >= -tau_w[~basic]):
                z[basic] = np.maximum(z[basic], 0.0)
                return z, basic, stats, "solved"
            stats["refreshes"] += 1
            if stats["refreshes"] > 3:
                return z, basic, stats, "inaccurate"
            T, qbar = ppt_tableau(M, q, basic)
            continue
        if stats["pivots"] >= max_pivots:
            z, _ = ActiveBlock(M, basic, symmetric=True).basic_solution(M, q)
            return z, basic, stats, "max_pivots"
        if deadline.expired():
            return None, basic, stats, "time_limit"
        if current == "energy":
            crit = -qbar[neg] ** 2 / T[neg, neg]
            r = int(neg[np.argmin(crit)])
        else:
            r = int(neg[0])
        if not T[r, r] > 0:
            # Exact arithmetic keeps every diagonal of a PPT of a PD matrix positive;
            # rounding does not.  Rebuild once from the data, then give up honestly.
            stats["refreshes"] += 1
            T, qbar = ppt_tableau(M, q, basic)
            if not T[r, r] > 0 or stats["refreshes"] > 3:
                raise NotConvexError(
                    "a pivot of the energy method is not positive: M is not numerically "
                    "positive definite on this active set; use 'lemke'."
                )
            continue
        principal_pivot(T, qbar, r)
        basic[r] = not basic[r]
        stats["pivots"] += 1
        stats[f"{current}_pivots"] += 1
        if current == "energy":
            key = basic.tobytes()
            if key in seen or stats["energy_pivots"] >= cap:
                current = "murty"
                stats["fallback"] = True
                stats["fallback_reason"] = ("repeated basis" if key in seen
                                            else f"pivot cap {cap} reached")
            seen.add(key)


def run_energy(problem, tol, options, time_limit=None) -> MethodResult:
    """The "energy" method (module docstring).  Options
    (:data:`ENERGY_OPTIONS`): ``max_pivots`` (100 n + 1000), ``rule``
    ("energy"; "murty": Murty's least-index rule from the start).
    ``time_limit`` (s): the deadline, checked at every pivot (one pivot of
    a 3 000-unknown tableau is 5 ms; its 1 500 pivots took 12 s)."""
    deadline = Deadline(time_limit)
    n = problem.n
    opts = read_options("energy", options, ENERGY_OPTIONS, size=n)
    check_dense_size("energy", n, f"{n} x {n} tableau",
                     "'bpp' (block pivoting with sparse factorizations)")
    max_pivots, rule = opts["max_pivots"], opts["rule"]
    M = dense_matrix(problem.M)
    d = symmetric_scaling(M)
    Ms = M * d[:, None] * d[None, :]
    qs = problem.q * d
    if not (np.all(np.isfinite(Ms)) and np.all(np.isfinite(qs))):
        return overflow_result("energy", "the Jacobi-scaled data overflow")
    try:
        zs, basic, stats, status = _energy(Ms, qs, problem.q_terms * d, max_pivots, rule,
                                           deadline)
    except np.linalg.LinAlgError as exc:
        raise not_positive_definite("energy", exc) from None
    except SolutionOverflow as exc:
        return overflow_result("energy", exc)
    if status == "time_limit":
        return time_limit_result("energy", stats["pivots"], "pivots", stats)
    z = zs * d
    if not np.all(np.isfinite(z)):
        return overflow_result("energy", "the solution has entries beyond 1.8e308")
    stats["active"] = int(basic.sum())
    return MethodResult(
        x=z, backend_status=status, iterations=stats["pivots"],
        status=status if status == "max_pivots" else None,
        backend_message=(f"pivot limit {max_pivots} reached" if status == "max_pivots" else ""),
        stats=stats,
    )
