"""``solve``: one entry point for every problem kind and every method.

Every kind goes the same way: the problem is validated, the accuracy ladder
gives the tolerance (:mod:`qpcontact.core.accuracy`), the method comes from
the one registry — or "auto" tries the kind's methods in order until one is
certified or no solution is proved — and every answer is certified from the
data, whatever the method says (:mod:`qpcontact.judge`).  The kinds differ
only in how one run goes: :mod:`.lcp_qp` (LCPs and QPs, with proofs where an
answer is in doubt), :mod:`.friction` (frictional contact), and the load
trace, which certifies its pieces itself.
"""

from __future__ import annotations

import time

import numpy as np

from ..core.accuracy import resolve_accuracy
from ..core.conversions import check_convex, is_qp, validate_qp
from ..core.errors import (BackendUnavailableError, InvalidOptionError, InvalidProblemError,
                           NoSolutionError, NotConvexError, NotSymmetricError, SolverFailedError,
                           UnknownMethodError)
from ..core.problems import LCP, ParametricLCP
from ..core.results import PROVED
from ..friction.problem import FrictionProblem
from ..solvers.method import PROBLEM_KINDS
from ..solvers.registry import get_method
from .calls import DEFAULT_TIME_LIMIT, check_time_limit
from .friction import check_friction_method, run_friction, run_friction_auto
from .lcp_qp import doubtful, hints, prove_no_solution, run_lcp_qp
from .routes import applicable, auto_order, kind_of

__all__ = ["solve", "solve_friction", "Engine", "DEFAULT_TIME_LIMIT"]


class Engine:
    """What a method that solves sub-problems is given (``engine=``): the
    engine's own :func:`solve`, at the accuracy, time limit and isolation of
    the call that runs it — the trace's Lemke solves, the friction fixed
    points' 2-D QPs, the faceted LCP of a frictional problem.  Methods never
    import the dispatcher."""

    def __init__(self, accuracy, time_limit, isolate):
        self.accuracy, self.time_limit, self.isolate = accuracy, time_limit, isolate

    def solve(self, problem, method: str, *, prove: bool = True, **kw):
        """``prove=False``: one named method's certified answer to an LCP,
        without the search for a proof that no solution exists where it
        fails — for a probe whose failure the caller handles itself (the
        trace's solve just beyond a vertex, followed by its own collapse
        proof: the exact Farkas search there took 2.3 s of a 10-storey space
        frame's 3.4 s trace and proved nothing the trace used)."""
        kw.setdefault("accuracy", self.accuracy)
        kw.setdefault("time_limit", self.time_limit)
        kw.setdefault("isolate", self.isolate)
        if not prove and isinstance(problem, LCP) and method != "auto":
            m = get_method(method)
            _check_kind(problem, m)
            tol_backend, tol_cert = resolve_accuracy(kw.pop("accuracy"))
            run = dict(time_limit=check_time_limit(kw.pop("time_limit")),
                       isolate=kw.pop("isolate"))
            return run_lcp_qp(problem, m, tol_backend, tol_cert, self.accuracy, kw, **run)
        return solve(problem, method, **kw)

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


def _solve_lcp_qp(problem, method, tol_backend, tol_cert, accuracy, options, run):
    if method != "auto":
        m = get_method(method)
        _check_kind(problem, m)
        sol = run_lcp_qp(problem, m, tol_backend, tol_cert, accuracy, options, **run)
        if not doubtful(problem, sol):
            return sol
        limit = run["time_limit"]
        # the proof gets what the method left of the limit, at least a quarter
        return prove_no_solution(problem, sol, None if limit is None else
                                 max(limit - sol.wall_time, 0.25 * limit))
    start, limit = time.perf_counter(), run["time_limit"]
    learned, seen = [], {"proofs": 0, "evidence": 0}

    def left():
        return None if limit is None else limit - (time.perf_counter() - start)

    def attempt(m, best):
        # each link gets half of what is left, so the chain fits in the limit
        # and a backend looping at its iteration cap cannot take it all
        share = None if limit is None else left() / 2
        sol = run_lcp_qp(problem, m, tol_backend, tol_cert, accuracy, options,
                         time_limit=share, isolate=run["isolate"])
        if share is not None:
            sol.stats["time_share"] = share
        if doubtful(problem, sol):
            new = hints(sol)
            # a proof is sought where a result points to no solution (its
            # own verdict, an answer in doubt, a ray, a point far out), again
            # whenever a later one brings something new; a plain miss of the
            # tolerance waits for the end of the chain (most are certified by
            # the next method: a penalty step's QP took 1.5 proofs per step)
            if seen["proofs"] < AUTO_PROOFS and (_points_to_no_solution(sol)
                                                 or _asks_for_proof(sol)):
                seen["proofs"] += 1
                sol = prove_no_solution(problem, sol, _proof_time(left(), limit), learned)
            learned.extend(new)
        if _points_to_no_solution(sol):
            seen["evidence"] += 1
        return sol

    def stop(sol):
        if sol.status == "ray" and sol.stats.get("proved_infeasible"):
            return True
        return seen["evidence"] >= AUTO_EVIDENCE or (limit is not None and left() < 0.01 * limit)

    sol, tried = _auto(_installed(auto_order(problem), problem), attempt, stop_early=stop)
    if sol is None:
        raise NotSymmetricError(
            "no installed method applies to this problem; `qpcontact methods` lists what is "
            "installed and what each one requires")
    if not sol.ok and sol.status not in PROVED and seen["proofs"] == 0 and doubtful(problem, sol):
        sol = prove_no_solution(problem, sol, _proof_time(left(), limit), learned)
    if not sol.ok and sol.status not in PROVED and seen["evidence"] >= AUTO_EVIDENCE:
        sol.message += (f" — 'auto' stopped after {len(tried)} method(s): {seen['evidence']} of "
                        "them point to data with no solution (an answer in doubt, a Farkas vector "
                        "holding to rounding, a backend's own verdict) and no proof could be "
                        "checked exactly")
    sol.stats["auto_tried"] = tried
    return sol


def _proof_time(left, limit):
    """Seconds each proof LP may take: what is left of the call's limit, but
    never nothing (a proof is worth a tenth of the limit beyond it)."""
    return None if left is None else max(left, 0.1 * limit)


def _solve_friction(problem, method, tol, accuracy, options, run, engine):
    if method != "auto":
        m = get_method(method)
        check_friction_method(problem, m)
        return run_friction(problem, m, tol, accuracy, options, engine=engine, **run)
    return run_friction_auto(problem, tol, accuracy, options, engine=engine, **run)


def _solve_parametric(problem, method, tol, accuracy, options, engine):
    if method not in ("trace", "auto"):
        raise InvalidProblemError(
            f"a ParametricLCP is a family of LCPs; method {method!r} solves one LCP — use "
            "method='trace' to follow the load, or fix it with problem.at(p)")
    sol = get_method("trace").run(problem, tol, options, engine=engine)
    sol.accuracy = accuracy
    return sol


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
        Seconds each backend call may take (default :data:`DEFAULT_TIME_LIMIT`);
        a call stopped by it has status ``"time_limit"``.  Passed to the
        backends that have a time limit of their own; ProxQP, which has none,
        runs in a child process killed at the limit.  Lemke's sparse form
        checks it at each pivot, the iterative friction methods between
        iterations, and a frictional "auto" gives each link half of what is
        left; the other pivoting methods are bounded by their pivot caps.
        None: no limit.
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
    InvalidProblemError, NotSymmetricError, NotConvexError
        On misuse (see :mod:`qpcontact.core.errors`).
    InvalidOptionError, UnknownMethodError, BackendUnavailableError
        On misuse (see :mod:`qpcontact.core.errors`).
    """
    if not isinstance(method, str):
        raise InvalidOptionError(
            f"method must be a string: 'auto' or a name from qpcontact.methods(); got {method!r}")
    problem = _validated(problem)
    tol_backend, tol_cert = resolve_accuracy(accuracy)
    time_limit = check_time_limit(time_limit)
    if isolate not in ("auto", True, False):
        raise InvalidOptionError(f"isolate must be 'auto', True or False; got {isolate!r}")
    run = dict(time_limit=time_limit, isolate=isolate)
    engine = Engine(accuracy, time_limit, isolate)
    if isinstance(problem, ParametricLCP):
        sol = _solve_parametric(problem, method, tol_cert, accuracy, options, engine)
    elif isinstance(problem, FrictionProblem):
        sol = _solve_friction(problem, method, tol_cert, accuracy, options, run, engine)
    else:
        sol = _solve_lcp_qp(problem, method, tol_backend, tol_cert, accuracy, options, run)
    if raise_on_failure and not sol.ok:
        if sol.status in PROVED or (sol.status == "ray"
                                    and sol.stats.get("proved_infeasible", True)):
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
