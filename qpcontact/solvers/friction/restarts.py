"""NSGS + Newton restarted from random reactions within the cones ("nsgs-restarts").

The problem is the local frictional contact problem of
:mod:`qpcontact.core.friction_problem`: per contact i the impulse
r_i = (r_N, r_T) (N·s) lies in Coulomb's cone ‖r_T‖ <= μ_i r_N, the
relative velocity u = W r + q (m/s; W the Delassus operator Hᵀ M⁻¹ H,
m/(N·s)) and De Saxcé's modified velocity û_i = u_i + μ_i ‖u_T,i‖ e_N lie in
the dual cone, and r_i · û_i = 0.  A nearly closed pile of rigid spheres is
hyperstatic (more contacts than the bodies' degrees of freedom): W is
singular, the reactions are not unique, and Coulomb's law makes the set of
equilibria non-convex — the branch of solutions winds and has kinks as μ
grows (docs/dev-notes.md, "Dense piles: where every iterative route stops").
There NSGS (:mod:`.nsgs`) does not settle on a solution: its iterate drifts
by ~3e-4 of the largest impulse a sweep with the certified error between
3e-4 and 3e-3, and whether Newton certifies depends on the point it is
handed.  Which solution (if any) the sweeps come near is decided by where
they start; the pile's own impulses, perturbed, lead back to the same stall
(docs/dev-notes.md, "The 3-D compact piles by restarts").

So each start runs nsgs-newton (:func:`.hybrid.solve_nsgs_newton`) to its
own stop: the tolerance, a stall (50 checks without a better point), or the
time left.  The first start is ``r0`` (default zero), so that where
nsgs-newton certifies the problem this method is nsgs-newton; where it does
not, semismooth Newton on the natural map (:func:`.newton.solve_natural_newton`)
polishes its point for :data:`POLISH_ITERATIONS` iterations (what "auto" ran
next before the restarts: it certifies some piles there).  Start k >= 1
spreads impulses of the pile's size at random over the contacts: r_N,i
uniform in [0, s], each tangential component uniform in [−0.3 s, 0.3 s],
projected onto the cone, s (N·s) the largest impulse component of the best
point so far to two digits (:func:`start_scale`); the random generator is
seeded by k.  And one trajectory more, Siconos's NSGS: plain ω = 1 sweeps
from zero with the closed-form local solve (:class:`.nsgs.NSGS`), kept
across the starts and advanced only where a start stalls without a better
point (the first: without the tolerance), by :data:`LONG_PER_SWEEP` of its
sweeps per sweep of that start — as much time as the stalled start took.
It is the ticket the restarts do not draw: one long run, certified after
31 000–106 000 sweeps on piles where the restarts stall at their first
start (the 540-contact compact pile of seed 8, 982 of seeds 5 and 7) and
after 39 000 on the 2 118-contact sphere pile, which no start of ours or
of Siconos's solvers had certified.  Every choice — which starts, at
which scale, how many sweeps, when Newton is tried, how long it polishes,
the long run's share — is made by iteration counts and the iterates, never
by the clock: the time limit only ends the run (a start it cuts short is
the last), so two runs on the same problem do the same arithmetic up to
where the shorter one stops, and a verdict depends on the machine's speed
and load only through where the budget ends (docs/dev-notes.md, "The dense
3-D route by counts").  The best point of all starts is returned, for
Newton to polish ("auto" runs "newton" from it next): Newton after every
start took 60–70 % of each start's CPU on the 540-contact piles and
certified fewer starts than it cost.  No global guarantee: the certificate decides.
"""

from __future__ import annotations

import numpy as np

from ...core.deadline import Deadline
from ...core.friction_problem import project_cone
from ...core.options import PROGRESS, TIME_LIMIT, Option, read_options
from ...judge.friction_certificate import certified_error
from .hybrid import solve_nsgs_newton
from .newton import solve_natural_newton
from .nsgs import NSGS, R0, starting_point

__all__ = ["solve_nsgs_restarts", "random_cone_point", "start_scale", "POLISH_ITERATIONS",
           "NSGS_RESTARTS_OPTIONS"]

NSGS_RESTARTS_OPTIONS = (
    Option("starts", 20, "int", low=1, doc="starts at most (the first from r0)"),
    R0, TIME_LIMIT, PROGRESS,
)

#: Newton iterations polishing the first start's point: the loose 982-contact
#: pile of seed 2 is certified at the 23rd (2.2 s of CPU; its sweeps took 4.6 s,
#: the polish's limit before it was counted).  A count, not the seconds the
#: sweeps took: a polish stopped at another iteration gave every later start
#: another draw, so a row's verdict moved with the load
POLISH_ITERATIONS = 30

#: the long ω = 1 trajectory's sweeps per sweep of a stalled start: its
#: closed-form sweeps are 8 times cheaper than the starts' fixed-point ones
#: (35 500 against 4 400 a second on the 540-contact piles), so it gets as
#: much time as the start that stalled; and its sweeps between checks
LONG_PER_SWEEP = 8
LONG_CHECK = 500

#: the tangential components' range, a fraction of the normal one's: inside
#: the cone for μ >= 0.3·√2 before the projection (the piles' μ is 0.5)
_TANGENTIAL = 0.3


def random_cone_point(problem, scale: float, k: int) -> np.ndarray:
    """Start k's reactions (module docstring): impulses up to ``scale`` (N·s)
    spread at random over the contacts, projected onto their cones."""
    d, nc = problem.dim, problem.n_contacts
    rng = np.random.default_rng(k)
    r = rng.uniform(0.0, 1.0, d * nc) * scale
    tangential = np.arange(d * nc) % d != 0
    r[tangential] *= _TANGENTIAL * np.sign(rng.standard_normal(int(tangential.sum())))
    return project_cone(r, problem.mu, d)


def start_scale(best_r) -> float:
    """The later starts' scale s (N·s): the best point's largest impulse
    component to two significant digits, so that a draw does not depend on
    the last bits of where the polish or the sweeps stopped (1 where the
    point is all zero)."""
    s = float(np.abs(best_r).max())
    return float(f"{s:.2g}") if s > 0 and np.isfinite(s) else 1.0


def solve_nsgs_restarts(problem, tol, options):
    """nsgs-newton from ``r0``, then from random reactions within the cones
    (module docstring), until the certified error is <= tol, the time limit
    or ``starts``; the best point.  Options (:data:`NSGS_RESTARTS_OPTIONS`):
    ``starts`` (20), ``r0``, ``time_limit`` (s), ``progress``."""
    opts = read_options("nsgs-restarts", options, NSGS_RESTARTS_OPTIONS)
    time_limit, progress = opts["time_limit"], opts["progress"]
    r0 = starting_point("nsgs-restarts", problem, opts["r0"])
    deadline = Deadline(time_limit)
    best_r, best = None, np.inf
    lines = []
    long_run = None         # one ω = 1 NSGS trajectory from zero, advanced at stalls
    long_best, long_r = np.inf, None
    for k in range(opts["starts"]):
        if deadline.expired():
            break
        start = r0 if k == 0 else random_cone_point(problem, start_scale(best_r), k)
        left = deadline.left()
        if left is not None and left <= 0:      # the draw took the last of the time
            break
        t_start = deadline.now()
        r, _, _, stats = solve_nsgs_newton(
            problem, tol, {"r0": start, "time_limit": left, "progress": progress})
        err = certified_error(problem, r)
        took = deadline.now() - t_start
        where = f"start {k}: {err:.1e} ({stats['iterations']} sweeps, {took:.2g} s)"
        timed_out = stats["timed_out"]
        # a start that stalled without a better point (the first: without the
        # tolerance) gives the long trajectory its share, LONG_PER_SWEEP
        # closed-form sweeps per sweep of that start
        stalled = (err > tol if k == 0 else not err < best) and not timed_out
        if stalled and problem.dim == 3:
            if long_run is None:
                long_run = NSGS(problem, np.zeros_like(r), omega=1.0, closed_form=True)
            goal = long_run.done + LONG_PER_SWEEP * stats["iterations"]
            while long_run.done < goal and long_best > tol:
                if deadline.expired():
                    timed_out = True
                    break
                lr = long_run.sweep(LONG_CHECK)
                e = certified_error(problem, lr)
                if e < long_best:
                    long_best, long_r = e, lr.copy()
            where += f"; long NSGS {long_best:.1e} ({long_run.done} sweeps)"
        left = deadline.left()
        if k == 0 and err > tol and long_best > tol and not timed_out and (left is None or left > 0):
            # Newton from the first start's point: what "auto" did before the
            # restarts (the loose 982-contact pile of seed 2 is certified so,
            # 5.7e-8 at its 23rd iteration; Newton from the best of ten
            # starts stopped at 1.8e-6); POLISH_ITERATIONS, not seconds
            polished, _, _, polish = solve_natural_newton(
                problem, tol, {"r0": r, "time_limit": left, "max_iter": POLISH_ITERATIONS})
            polished_err = certified_error(problem, polished)
            where += f", then Newton {polished_err:.1e} ({polish['iterations']} iterations)"
            timed_out = polish["timed_out"]
            if polished_err < err:
                r, err = polished, polished_err
        lines.append(where)
        if progress is not None:
            progress(f"nsgs-restarts: {where}")
        if best_r is None or err < best:     # a first start's non-finite error still gives a scale
            best_r, best = r, err
        if long_best <= tol:
            best_r, best = long_r, long_best
        if best <= tol or timed_out:
            # a start the clock cut short ends the starts: the next one's
            # scale would be read off a point the uncut run never had
            break
    if long_r is not None and long_best < best:
        best_r, best = long_r, long_best
    message = (f"NSGS + minimum-norm Newton from {len(lines)} "
               f"start{'' if len(lines) == 1 else 's'}: " + "; ".join(lines))
    return best_r, "solved" if best <= tol else "stopped", message, {
        "iterations": len(lines), "starts": len(lines)}
