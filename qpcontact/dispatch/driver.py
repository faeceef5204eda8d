"""``solve``: one entry point for every problem kind and every method.

Every kind goes the same way: the problem is validated, the call's run
context is made once (:mod:`.context`: the accuracy ladder's tolerances, the
deadline, isolation), the method comes from the one registry — or "auto"
tries the kind's methods in order until one is certified or no solution is
proved — and every answer is certified from the data, whatever the method
says (:mod:`qpcontact.judge`).  The kinds differ only in how one run goes:
:mod:`.lcp_qp_run` (LCPs and QPs, with proofs where an answer is in doubt),
:mod:`.friction_run` (frictional contact), and the load trace, which
certifies its pieces itself.
"""

from __future__ import annotations

import itertools

import numpy as np

from ..core.conversions import check_convex, is_qp, validate_qp
from ..core.errors import (BackendUnavailableError, InvalidOptionError, InvalidProblemError,
                           NoApplicableMethodError, NoSolutionError, NotConvexError,
                           NotSymmetricError, SolverFailedError, UnknownMethodError)
from ..core.problems import LCP, ParametricLCP
from ..core.results import PROVED
from ..core.friction_problem import FrictionProblem
from ..solvers.method import PROBLEM_KINDS
from ..solvers.registry import get_method
from .calls import DEFAULT_TIME_LIMIT
from .context import RunContext
from .friction_run import check_friction_method, run_friction, run_friction_auto
from .lcp_qp_run import doubtful, hints, proof_first, prove_no_solution, run_lcp_qp
from .routes import applicable, auto_order, auto_progress, kind_of, link_options

__all__ = ["solve", "solve_friction", "Engine", "DEFAULT_TIME_LIMIT"]


class Engine:
    """What a method that solves sub-problems is given (``engine=``): the
    engine's own :func:`solve` within the run context of the call that runs
    it — the trace's Lemke solves, the friction fixed points' 2-D QPs, the
    faceted LCP of a frictional problem.  A sub-solve keeps the caller's
    deadline (a ``time_limit=`` of its own can only shorten it), so the whole
    call stays within the user's limit.  Methods never import the
    dispatcher."""

    def __init__(self, ctx: RunContext):
        self.ctx = ctx

    def within(self, ctx: RunContext) -> "Engine":
        """The engine for a part of the call with a context of its own."""
        return Engine(ctx)

    def expired(self) -> bool:
        """Whether the call's deadline has passed (a composite method stops)."""
        return self.ctx.expired()

    def solve(self, problem, method: str, *, prove: bool = True, accuracy=None,
              time_limit=None, isolate=None, **options):
        """A certified sub-solve; ``prove=False``: without the search for a
        proof that no solution exists where it fails — for a probe whose
        failure the caller handles itself (the trace's solve just beyond a
        vertex, followed by its own collapse proof: the exact Farkas search
        there took 2.3 s of a 10-storey space frame's 3.4 s trace and proved
        nothing the trace used)."""
        ctx = self.ctx.at(accuracy=accuracy, time_limit=time_limit, isolate=isolate, prove=prove)
        return solve_within(problem, method, ctx, options)

    def qp_method(self, name: str) -> str | None:
        """The registered QP method called ``name`` (any constraints), or None.
        A known but uninstalled one raises BackendUnavailableError (with its
        pip command)."""
        try:
            m = get_method(name)
        except UnknownMethodError:
            return None
        return m.name if m.takes == "qp" and m.constraints == "any" else None


def _validated(problem):
    if is_qp(problem):
        problem = validate_qp(problem)
        check_convex(problem)
        return problem
    if isinstance(problem, (LCP, ParametricLCP, FrictionProblem)):
        return problem
    raise InvalidProblemError(
        "solve() takes an LCP, a qpsolvers.Problem, a ParametricLCP or a FrictionProblem; got "
        f"{type(problem).__name__}")


def _auto(candidates, attempt, stop_early=None):
    """Try ``attempt(m, best)`` for each candidate method until one is ok or a
    proof ends the search; the ok one, the proof, or else the smallest error.
    Returns (solution or None, what was tried: (name, status, error))."""
    tried, best = [], None
    for m in candidates:
        try:
            sol = attempt(m, best)
        except (NotConvexError, NotSymmetricError, InvalidProblemError) as exc:
            # what the up-front checks could not foresee (a block that is not
            # numerically PD, a dense size limit): the next method is tried
            tried.append((m.name, f"skipped: {exc}", np.inf))
            continue
        tried.append((m.name, sol.status, sol.error))
        if best is None or sol.error < best.error:
            best = sol
        if sol.ok or sol.status in PROVED or (stop_early is not None and stop_early(sol)):
            return sol, tried
    return best, tried


def _installed(names, problem):
    """The applicable installed methods among ``names``, looked up lazily (a
    late entry, cvxpy, is imported only if reached)."""
    for name in names:
        try:
            m = get_method(name)
        except (BackendUnavailableError, UnknownMethodError):
            continue
        if applicable(problem, m):
            yield m


def _check_kind(problem, m) -> None:
    kind = kind_of(problem)
    if not m.solves(kind):
        raise InvalidOptionError(
            f"{m.name!r} does not solve {PROBLEM_KINDS[kind]} problems; it takes "
            f"{', '.join(PROBLEM_KINDS[k] for k in m.problems)} (`qpcontact methods` lists what "
            "each method takes)")


#: how many times one "auto" call looks for a proof that no solution exists
#: (each time with what the methods so far learned); each search is a few
#: LPs on one time budget, plus exact checks
AUTO_PROOFS = 3

#: "auto" ends its chain once this many results point to no solution — an
#: answer in doubt (status "ill_posed"), Lemke's Farkas vector holding to
#: rounding only, a backend's own "infeasible"/"unbounded" — and the proofs
#: they led to failed: further methods only repeat it (measured:
#: over 12 s on ill-posed LCPs, over 5 s on unbounded QPs)
AUTO_EVIDENCE = 2


def _asks_for_proof(sol) -> bool:
    """Besides the results that point to no solution: an ok answer that
    doubtful() still questions (its size, its forward error), and a method
    that returned no point at all."""
    return sol.ok or (sol.status == "failed" and sol.certificate is None)


def _points_to_no_solution(sol) -> bool:
    return (sol.status == "ill_posed" or bool(sol.stats.get("backend_verdict"))
            or (sol.status == "ray" and sol.stats.get("farkas") is not None))


def _solve_lcp_qp(problem, method, ctx, options):
    if method != "auto":
        m = get_method(method)
        _check_kind(problem, m)
        sol = run_lcp_qp(problem, m, options, ctx)
        if not ctx.prove or not doubtful(problem, sol):
            return sol
        return prove_no_solution(problem, sol, ctx.deadline)
    options, progress = auto_progress(options)
    # where no solution may exist, its proof first (an LP of milliseconds,
    # where the methods can loop for the whole time limit)
    proved = proof_first(problem, ctx)
    if proved is not None:
        proved.stats["auto_tried"] = [(proved.method, proved.status, proved.error)]
        if progress is not None:
            progress(f"auto: {proved.message}")
        return proved
    learned, seen = [], {"proofs": 0, "evidence": 0}

    def attempt(m, best):
        # each link gets half of what is left, so the chain fits in the limit
        # and a backend looping at its iteration cap cannot take it all
        link = ctx.share(0.5)
        share = link.left()
        sol = run_lcp_qp(problem, m, link_options(options, m.name, progress, share), link)
        if progress is not None:
            progress(f"auto: {m.name}: {sol.status} in {sol.wall_time or 0:.2f} s")
        if share is not None:
            sol.stats["time_share"] = share
        if ctx.prove and doubtful(problem, sol):
            new = hints(sol)
            # a proof is sought where a result points to no solution (its
            # own verdict, an answer in doubt, a ray, a point far out), again
            # whenever a later one brings something new; a plain miss of the
            # tolerance waits for the end of the chain (most are certified by
            # the next method: a penalty step's QP took 1.5 proofs per step).
            # The proof has what is left of the call.
            if seen["proofs"] < AUTO_PROOFS and (_points_to_no_solution(sol)
                                                 or _asks_for_proof(sol)):
                seen["proofs"] += 1
                sol = prove_no_solution(problem, sol, ctx.deadline, learned)
            elif seen["proofs"] < AUTO_PROOFS and sol.status == "time_limit":
                # a backend that used its whole share without an answer: on a
                # QP with no feasible point at n = 1 000 PIQP and OSQP took
                # the limit between them and the Farkas LP (2 s of CPU) had
                # none left; it gets half of what is left, the chain the rest
                seen["proofs"] += 1
                sol = prove_no_solution(problem, sol, ctx.deadline.share(0.5), learned)
            learned.extend(new)
        if _points_to_no_solution(sol):
            seen["evidence"] += 1
        return sol

    def stop(sol):
        return seen["evidence"] >= AUTO_EVIDENCE or ctx.spent()

    # looked up lazily: a late entry (cvxpy, a second to import) only if reached
    candidates = _installed(auto_order(problem), problem)
    first = next(candidates, None)
    if first is None:
        raise NoApplicableMethodError(
            f"no installed method applies to this {kind_of(problem).upper()} (of the ones "
            f"'auto' tries: {', '.join(auto_order(problem))}); `qpcontact methods` lists what "
            "is installed and what each one requires")
    sol, tried = _auto(itertools.chain([first], candidates), attempt, stop_early=stop)
    if sol is None:
        raise NoApplicableMethodError(
            "no installed method could take this problem: " + "; ".join(
                f"{name}: {status}" for name, status, _ in tried)
            + " — `qpcontact methods` lists what each one requires")
    if (ctx.prove and not sol.ok and sol.status not in PROVED and seen["proofs"] == 0
            and doubtful(problem, sol)):
        sol = prove_no_solution(problem, sol, ctx.deadline, learned)
    if not sol.ok and sol.status not in PROVED and seen["evidence"] >= AUTO_EVIDENCE:
        sol.message += (f" — 'auto' stopped after {len(tried)} method(s): {seen['evidence']} of "
                        "them point to data with no solution (an answer in doubt, a Farkas vector "
                        "holding to rounding, a backend's own verdict) and no proof could be "
                        "checked exactly")
    elif not sol.ok and sol.status not in PROVED and ctx.spent():
        sol.message += (f" — 'auto' stopped at the time limit of {ctx.time_limit:g} s after "
                        f"{len(tried)} method(s)")
    sol.stats["auto_tried"] = tried
    return sol


def _solve_friction(problem, method, ctx, options):
    engine = Engine(ctx)
    if method != "auto":
        m = get_method(method)
        check_friction_method(problem, m)
        return run_friction(problem, m, options, ctx, engine)
    return run_friction_auto(problem, options, ctx, engine)


def _solve_parametric(problem, method, ctx, options):
    if method not in ("trace", "auto"):
        raise InvalidProblemError(
            f"a ParametricLCP is a family of LCPs; method {method!r} solves one LCP — use "
            "method='trace' to follow the load, or fix it with problem.at(p)")
    sol = get_method("trace").run(problem, ctx.tol_cert, options, engine=Engine(ctx))
    sol.accuracy = ctx.accuracy
    return sol


def solve_within(problem, method: str, ctx: RunContext, options: dict):
    """:func:`solve` within a run context (the engine's sub-solves come here):
    the problem validated, then run by its kind."""
    problem = _validated(problem)
    if isinstance(problem, ParametricLCP):
        return _solve_parametric(problem, method, ctx, options)
    if isinstance(problem, FrictionProblem):
        return _solve_friction(problem, method, ctx, options)
    return _solve_lcp_qp(problem, method, ctx, options)


def solve(problem, method: str = "auto", accuracy="high", *, raise_on_failure: bool = False,
          time_limit: float | None = DEFAULT_TIME_LIMIT, isolate="auto", **options):
    """Solve a problem with a registered method and certify the answer.

    Parameters
    ----------
    problem : LCP, qpsolvers.Problem, ParametricLCP or FrictionProblem
        A ``ParametricLCP`` is traced in its load parameter (method ``"trace"``
        or ``"auto"``; options ``p_max``, ``max_pieces``) and a
        :class:`~qpcontact.solvers.trace.result.LoadTrace` comes back; fix it
        first with ``problem.at(p)`` to solve one LCP.  A ``FrictionProblem``
        (local, or global kept without W) is solved by the friction methods
        and by the LCP methods that take any M, through its faceted LCP.
    method : str
        A name from :func:`qpcontact.methods` (``"osqp"``, ``"lemke"``,
        ``"nsgs"``, ``"cvxpy:CLARABEL"``, ...) or ``"auto"``, which tries the
        kind's methods in order (:data:`~qpcontact.dispatch.routes.AUTO_ORDER`;
        friction: :func:`~qpcontact.dispatch.routes.auto_chain`) until one is
        certified or no solution is proved.
    accuracy : {"low", "default", "high"} or float
        The tolerance the certificate must meet, the same for every kind
        (:mod:`qpcontact.core.accuracy`); a number is that tolerance.  The
        friction methods also stop at it.
    raise_on_failure : bool
        Raise instead of returning a solution that is not ``ok``:
        :class:`NoSolutionError` when no solution exists (a checked Farkas
        vector, ray or motion), :class:`SolverFailedError` otherwise.
    time_limit : float or None
        Seconds of wall time the whole call may take (default
        :data:`DEFAULT_TIME_LIMIT`), however busy the machine is: it returns
        within ``time_limit`` plus :func:`~qpcontact.core.deadline.grace`
        (0.5 s and a tenth of the limit: the step in flight ends and its
        answer is certified; that much work at a full core's speed — on a
        loaded machine it takes longer).  The default limit makes a large
        problem's outcome depend on the machine's load (a 2 020-contact
        Lemke solve: 9.8 s of CPU, 61 s of wall time when the process got a
        sixth of a core): pass ``time_limit=None`` where the answer must not.  Every part keeps the same deadline
        (:mod:`qpcontact.dispatch.context`): "auto" gives each method half of
        what is left, a proof gets what is left, the backends get it as
        their own time setting, ProxQP (which has none) runs in a child
        process killed at the deadline, Lemke and the iterative friction
        methods check it as they go, and a composite method's sub-solves
        (the load trace's, the friction fixed points') share it.  A call
        stopped by it has status ``"time_limit"`` (or the best answer found,
        not certified).  The pivoting methods other than Lemke are bounded by
        their pivot caps.  None: no limit.
    isolate : "auto", True or False
        True runs every backend call in a child process (a crash or a hang
        costs that call, not the caller); "auto" only the backends that cannot
        honour the time limit themselves; False none.
    **options
        The method's own settings, passed through (a backend's override the
        accuracy table's).

    Returns
    -------
    LCPSolution, QPSolution, FrictionSolution or LoadTrace
        Always certified from the problem data; ``ok`` is True only when the
        certificate meets the requested accuracy.

    Raises
    ------
    InvalidProblemError, NotSymmetricError, NotConvexError, NoApplicableMethodError
        On misuse (see :mod:`qpcontact.core.errors`).
    InvalidOptionError, UnknownMethodError, BackendUnavailableError
        On misuse (see :mod:`qpcontact.core.errors`).
    """
    if not isinstance(method, str):
        raise InvalidOptionError(
            f"method must be a string: 'auto' or a name from qpcontact.methods(); got {method!r}")
    if not isinstance(raise_on_failure, bool):
        raise InvalidOptionError(f"raise_on_failure must be True or False; got {raise_on_failure!r}")
    ctx = RunContext.start(accuracy, time_limit, isolate)
    sol = solve_within(problem, method, ctx, options)
    if raise_on_failure and not sol.ok:
        if sol.status in PROVED:
            raise NoSolutionError(f"{sol.method}: {sol.message}")
        raise SolverFailedError(f"{sol.method} returned no certified solution: {sol.message}")
    return sol


def solve_friction(problem: FrictionProblem, method: str = "auto", accuracy="high", **options):
    """:func:`solve` for a frictional contact problem (a thin alias: the same
    methods, ladder, statuses and certificate)."""
    if not isinstance(problem, FrictionProblem):
        raise InvalidProblemError(f"solve_friction takes a FrictionProblem; got "
                                  f"{type(problem).__name__}")
    return solve(problem, method, accuracy, **options)
