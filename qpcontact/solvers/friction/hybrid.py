r"""NSGS to get close, then minimum-norm Newton steps to finish ("nsgs-newton").

Why.  On a pile of rigid bodies W = Hᵀ M⁻¹ H has more rows (contact
unknowns) than the bodies have degrees of freedom: it is singular, the forces
are statically indeterminate, and so is the generalized Jacobian J of the
natural map F(r) = r − proj_K(r − ρ û(r)) wherever contacts stick.  NSGS
(Gauss–Seidel over the contacts) handles the singularity — each local
problem is regular — but its convergence is linear with a rate that tends
to one as the pile grows: on a 2 000-contact generated pile it is at 4.5e-7
after 10 000 sweeps, and the 2 020-contact granular file stalls near 3e-7.
Semismooth Newton converges quadratically once the contact states are
right, but J is singular, so its LU step fails or is huge, and a line search
on ½‖F‖² then creeps (:mod:`qpcontact.solvers.friction.newton`).

The step.  A singular J d = −F is consistent when the states are right (a
whole family of forces balances the pile); its *minimum-norm* solution
moves r the least among them, so it keeps what NSGS found in the directions
that the equations leave free.  It is computed without forming JᵀJ (which
would square the condition number) from the regularized augmented system

    [ I    Jᵀ ] [d]   [ 0 ]
    [ J  −λI  ] [y] = [−F ],    λ = 1e-12:   d = Jᵀ(JJᵀ + λI)⁻¹(−F),

one sparse LU (SuperLU) per step: Levenberg–Marquardt with a vanishing
parameter, the proximal-point limit.  Full steps, no line search: a step is
kept only when the certified error falls, else the method goes back to
sweeping.  Measured on the 2 000-contact pile from NSGS's 4.5e-7: 1.1e-10,
3.9e-13, 9.4e-16 in three steps (0.08 s each); from 5e-4 the same steps
diverge — the states are not yet right — which is why NSGS comes first and
Newton is tried only each time NSGS's error has fallen tenfold (below
:data:`NEWTON_FROM`) and on a plateau — NSGS without progress — after 3
checks (on the 20 000-contact pile from 3.8e-5 to 1.4e-14 in two steps),
the wait doubling with each try that fails there (on the 2020-contact
granular file 19 tries in a 50-check stall cost 0.4 s).
NSGS is never restarted from a Newton point (docs/dev-notes.md, issue 33).

No global guarantee (Coulomb friction is not a minimisation); every point is
judged by the certified error (both measures), and the best is returned.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ...core.deadline import Deadline
from ...core.options import PROGRESS, TIME_LIMIT, Option, read_options
from ...judge.friction_certificate import (SLIP_RTOL, certified_error, contact_scales,
                                           natural_map_jacobian)
from .nsgs import NSGS, R0, starting_point
from ...core.friction_problem import modified_velocity, project_cone

__all__ = ["solve_nsgs_newton", "minimum_norm_newton", "NEWTON_FROM", "OMEGA",
           "NSGS_NEWTON_OPTIONS"]

#: Newton is first tried once NSGS's certified error is below this
NEWTON_FROM = 1e-3

#: NSGS's over-relaxation here: 1.3 took the 10 000-contact pile from 4 240
#: sweeps to 340 and solved two 2 000-contact compact piles that 1.0 left at
#: 1.8e-6; 1.5 and 1.7 did worse on the compact 3-D pile (1e-3, 6e-3)
OMEGA = 1.3

NSGS_NEWTON_OPTIONS = (
    Option("omega", OMEGA, "float", low=0.0, high=2.0, low_open=True, high_open=True,
           doc="NSGS's over-relaxation"),
    Option("max_sweeps", 100_000, "int", low=0, doc="NSGS sweeps at most"),
    Option("square_first", False, "bool",
           doc="try Newton's step by J's own LU before the minimum-norm one (a problem "
               "whose J is regular, e.g. with compliant contacts)"),
    R0, TIME_LIMIT, PROGRESS,
)

#: the augmented system's regularization (J is dimensionless)
_LAMBDA = 1e-12
#: a square Newton step this many times ‖r‖ + ‖F‖ or longer marks J as
#: numerically singular (a rigid pile's: 7e13; the drum's regular J: <= 2e-2)
_SINGULAR = 1e6


def minimum_norm_newton(problem, r, tol, max_steps=6, square=None, error=None):
    """Up to ``max_steps`` full minimum-norm Newton steps from ``r`` (module
    docstring), stopped at tol or once the certified error is 100 times the
    start's; (the best point, its error, steps taken).  With ``square`` =
    {"on": True} (a dict the caller keeps across tries; default off) each
    step tries J's own LU first (:func:`_square_step`): where J is regular
    that is the minimum-norm step at a tenth of the fill; once J is found
    singular it is off.  Off by default: on a rigid pile J is singular and
    the extra LU only costs (0.17 s beside the augmented system's 1.1 s on
    5 000 contacts, which broke nsgs-newton's time limit there).  ``error``:
    the certified error at ``r`` where the caller has computed it."""
    square = {"on": False} if square is None else square
    d, W, q, mu = problem.dim, problem.W, problem.q, problem.mu
    rho_c = contact_scales(problem)
    rho = np.repeat(rho_c, d)
    best_r, best = r, certified_error(problem, r) if error is None else error
    start = best
    steps = 0
    for steps in range(1, max_steps + 1):
        if square["on"] and d == 2 and sp.issparse(W):
            # F and the system on the closed contacts' unknowns in one compiled call
            F, step, err = _square_step_2d(problem, r, rho_c, square)
            J = None
        else:
            F = r - project_cone(r - rho * modified_velocity(np.asarray(W @ r).ravel() + q, mu, d),
                                 mu, d)
            J = sp.csc_matrix(natural_map_jacobian(problem, r))
            step, err = _square_step(problem, r, J, F, square) if square["on"] else (None, None)
        if step is None:
            square["on"] = False           # J is singular: off for the rest of the solve
            if J is None:
                J = sp.csc_matrix(natural_map_jacobian(problem, r))
            step = _minimum_norm_step(J, F)
            if step is None:   # exactly singular even regularized: give up this try
                break
            err = _error_at(problem, r + step)
        r = r + step
        if err > 100 * start:     # a first step may worsen the error, then converge
            break
        if err < best:
            best_r, best = r, err
        if best <= tol:
            break
    return best_r, best, steps


def _error_at(problem, r):
    return certified_error(problem, r) if np.all(np.isfinite(r)) else np.inf


def _square_step(problem, r, J, F, square=None):
    """The plain Newton step J d = −F and the certified error at r + d;
    (None, None) where J is singular (no LU, or a step :data:`_SINGULAR`
    times ‖r‖ + ‖F‖ long: huge along directions the minimum-norm step leaves
    alone).  Where J is regular this is the minimum-norm step (the only
    solution; the augmented system's differs from it by its λ alone, 1e-5 of
    the step on the drum's beds), and its LU has a tenth of the augmented
    system's fill: 5-10 ms against 45-100 ms on a 1 170-contact drum bed.  It
    is kept whether or not it lowers the error, as the minimum-norm step is
    (the caller judges the point): re-solving a regular J by the augmented
    system where the square step did not help gave the same step at ten
    times the cost, a sixth of the drum's step
    (docs/dev-notes.md, "The drum's step: where the time goes").

    Where the projection opens a contact (J_P = 0) J's rows are e_iᵀ: d_i =
    −F_i, and the LU is of the system on the other unknowns — half of them
    on a settled drum bed, its LU 3.5 -> 1.4 ms.  ``square`` (the caller's
    dict, kept across the steps and tries of one solve) keeps the first LU's
    order under "order": J's pattern is W's (less a state's zeros), so the
    later LUs of the solve take it (restricted to their unknowns, the others
    after them) instead of computing one — the ordering was half of each
    LU's time."""
    from ._newton_kernels import restricted_system   # numba: imported where it runs

    J = sp.csc_matrix(J)
    n = F.size
    fixed = (np.bincount(J.indices, minlength=n) == 1) & (J.diagonal() == 1.0)
    known = None if square is None else square.get("order")
    if known is None:
        order = np.flatnonzero(~fixed)
    else:        # the first LU's order, then the unknowns it did not have
        order = known[~fixed[known]]
        seen = np.zeros(n, bool)
        seen[order] = True
        order = np.concatenate([order, np.flatnonzero(~fixed & ~seen)])
    system = restricted_system(J.indptr, J.indices.astype(np.int64), J.data, order, F, fixed)
    base = np.where(fixed, -F, 0.0)
    return _restricted_step(problem, r, F, base, order, system, known is None, square)


def _square_step_2d(problem, r, rho_c, square):
    """:func:`_square_step` at r for a sparse 2-D problem, its system formed
    in one compiled call (_newton_kernels.closed_system_2d: F, the unknowns
    the step gives by itself — an open contact's both, d = −F; the
    tangential one of a contact on the cone's side, tied to its normal one
    — and the system on the others); (F, the step, its certified error).
    Tying the sliding contacts' tangential unknowns takes a sixth of the
    unknowns out of the LU on the drum's beds (1 124 -> ~960): an LU 20 %
    cheaper with a given order."""
    from ._newton_kernels import closed_system_2d   # numba: imported where it runs

    W = problem.W if problem.W.format == "csc" else sp.csc_matrix(problem.W)
    known = square.get("order")
    F, base, tie, order, *system = closed_system_2d(
        W.indptr, W.indices, W.data, np.asarray(problem.q, float), problem.mu, rho_c,
        np.asarray(r, float), SLIP_RTOL, *problem.W_blocks,
        np.zeros(0, np.int64) if known is None else known, known is not None)
    step, err = _restricted_step(problem, r, F, base, order, tuple(system), known is None,
                                 square, tie)
    return F, step, err


def _restricted_step(problem, r, F, base, order, system, fresh, square, tie=None):
    """The square step from the restricted system (ptr, idx, val, rhs) on the
    unknowns ``order`` (``fresh``: SuperLU orders them, else their order is
    kept), ``base`` on the others; with ``tie`` (per contact, 2-D), d_T +=
    tie d_N.  (None, None) where J is singular."""
    ptr, idx, val, rhs = system
    J_r = sp.csc_matrix((val, idx, ptr), shape=(order.size, order.size))
    # panel_size 1 (SuperLU's default 10): the drum's J has small supernodes,
    # and its LUs of ~1 000 unknowns took 0.62 against 0.81 ms with a given
    # order, 0.93 against 1.16 fresh (docs/dev-notes.md, "The drum step's
    # contact solve")
    lu_options = dict(diag_pivot_thresh=0.1, panel_size=1, options={"SymmetricMode": True})
    step = base.copy()
    try:
        if order.size and fresh:
            # J's pattern is W's, symmetric: a minimum-degree order on J + Jᵀ
            # with pivots kept on the diagonal where they are a tenth of the
            # column's largest has 0.55-0.65 of COLAMD's fill on the drum's beds
            lu = spla.splu(J_r, permc_spec="MMD_AT_PLUS_A", **lu_options)
            step[order] = lu.solve(rhs)
            if square is not None:
                square["order"] = order[np.argsort(lu.perm_c)]
        elif order.size:       # SuperLU's own ordering skipped
            step[order] = spla.splu(J_r, permc_spec="NATURAL", **lu_options).solve(rhs)
    except RuntimeError:          # singular: the augmented system's step
        return None, None
    if tie is not None:
        step[1::2] += tie * step[0::2]
    if not np.linalg.norm(step) <= _SINGULAR * (np.linalg.norm(r) + np.linalg.norm(F)):
        return None, None         # numerically singular: a rigid pile's 7e13 × ‖r‖
    return step, _error_at(problem, r + step)


def _minimum_norm_step(J, F):
    """d = Jᵀ(JJᵀ + λI)⁻¹(−F) from the augmented system (module docstring)."""
    m = J.shape[0]
    K = sp.bmat([[sp.identity(m), J.T], [J, -_LAMBDA * sp.identity(m)]], format="csc")
    try:
        return spla.splu(K).solve(np.concatenate([np.zeros(m), -F]))[:m]
    except RuntimeError:
        return None


def solve_nsgs_newton(problem, tol, options):
    """NSGS, with minimum-norm Newton steps tried each time its error falls
    tenfold below :data:`NEWTON_FROM` and on a plateau, with a wait that
    doubles after each failed try (module docstring).  Options
    (:data:`NSGS_NEWTON_OPTIONS`): ``omega``
    (NSGS's over-relaxation, :data:`OMEGA`), ``max_sweeps`` (100 000), ``r0``,
    ``time_limit`` (s), ``progress`` (a callable taking a line),
    ``square_first`` (Newton's step by J's own LU where J is regular, before
    the minimum-norm step: the drum's compliant contacts).  Stops at tol, at
    the time limit, or when neither NSGS nor Newton has improved the best
    error over the last 50 checks; returns the best point.  The clock only
    ends the run (between sweeps; or where a Newton try is due and would
    not fit: then sweeps only, to the deadline); ``stats["timed_out"]``
    says the clock ended the run or skipped a try, so that up to then a run
    did the same work as a longer one."""
    opts = read_options("nsgs-newton", options, NSGS_NEWTON_OPTIONS)
    omega, max_sweeps = opts["omega"], opts["max_sweeps"]
    time_limit, progress = opts["time_limit"], opts["progress"]
    r0 = starting_point("nsgs-newton", problem, opts["r0"])
    deadline = Deadline(time_limit)
    gs = NSGS(problem, r0, omega=omega)
    r = gs.r.copy()
    best, best_r = certified_error(problem, r), r.copy()
    next_try, since, chunk = NEWTON_FROM, 0, 20
    quiet, wait = 0, 3            # checks since the last Newton try, and the wait
    tries = newton_steps = 0
    # J's own LU where asked, until J is found singular (minimum_norm_newton)
    square = {"on": bool(opts["square_first"])}
    longest_try = 0.0           # a Newton try is not started where the longest would not fit
    why = f"stopped at {max_sweeps} sweeps"
    timed_out = False           # stopped by the clock, not by the iterates
    while gs.done < max_sweeps:
        if best <= tol:
            why = "reached the tolerance"
            break
        if deadline.expired():
            why = f"stopped at its time limit of {time_limit:.3g} s"
            timed_out = True
            break
        # the 3-D local problems solved only as tightly as the whole is
        # solved so far: their projected fixed point contracts slowly
        gs.local_rtol = max(1e-14, 1e-2 * min(best, 1.0))
        r = gs.sweep(min(chunk, max_sweeps - gs.done))
        chunk = min(2 * chunk, 100)
        err = certified_error(problem, r)
        improved = err < best
        if improved:
            best, best_r = err, r.copy()
        if best <= tol:
            continue
        quiet += 1
        left = deadline.left()
        # before any try its cost is unknown (one uninterruptible LU: ~1 s on a
        # 5 000-contact pile, which a first try started 0.9 s into a 1 s limit
        # overran by 0.9 s): the first starts only while half the limit is left
        need = longest_try if tries else 0.5 * (time_limit or 0.0)
        due = best < next_try or (since and quiet >= wait)
        if due and left is not None and left <= need:
            # skipped, the sweeps go on to the deadline: from here the work
            # depends on the machine's speed, which timed_out tells the caller
            # ("nsgs-restarts" starts no other start after this one).  Ending
            # the run here instead lost the 2 118-contact sphere pile of seed 2
            # (a try there took ~10 s: the run ended 10 s before its limit)
            timed_out = True
            due = False
        if due:
            tries += 1
            t_try = deadline.now()
            rn, en, k = minimum_norm_newton(problem, r.copy(), tol, square=square, error=err)
            longest_try = max(longest_try, deadline.now() - t_try)
            newton_steps += k
            next_try = min(next_try, best / 10.0)
            quiet = 0
            if en < best:         # a candidate only: NSGS goes on along its own
                improved = True   # path (restarted from a Newton point it stalled)
                best, best_r = en, rn.copy()
                wait = 3
            elif since:           # on a plateau each failed try doubles the wait
                wait = min(2 * wait, 48)
        since = 0 if improved else since + 1
        if progress is not None:
            progress(f"nsgs-newton: {gs.done} sweeps, {tries} Newton tries: best error {best:.2e}")
        if since >= 50:
            why = "stalled (no better point in 50 checks)"
            break
    message = (f"NSGS + minimum-norm Newton {why}: {gs.done} sweeps, {tries} Newton "
               f"tr{'y' if tries == 1 else 'ies'} ({newton_steps} steps)")
    return best_r, "solved" if best <= tol else "stopped", message, {
        "iterations": gs.done, "newton_tries": tries, "newton_steps": newton_steps,
        "timed_out": timed_out}
