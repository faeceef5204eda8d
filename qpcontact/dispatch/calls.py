"""Calling a method: the time its run context leaves it, in a child process
where it cannot honour a time limit itself, with the engine passed to
methods that solve sub-problems."""

from __future__ import annotations

import functools
import inspect

from ..core.results import MethodResult
from ..solvers.method import Method
from ..solvers.registry import get_method

__all__ = ["DEFAULT_TIME_LIMIT", "BACKEND_FAMILIES", "IN_PROCESS_MIN_LEFT", "call", "isolated",
           "problem_size", "takes_keyword"]

#: Seconds a ``solve`` call may take by default (``solve(..., time_limit=)``:
#: wall time for the whole call), enforced by the backends' own settings where
#: they have one, by a killable child process for those that do not (ProxQP;
#: PIQP, DAQP, quadprog, ... on large problems or short limits: :func:`isolated`)
#: and by the in-house methods' and proofs' checks of the deadline.  The slowest certified backend call in the
#: benchmarks (PIQP, n = 1e5 membrane) took 9 s; the hangs it cuts took 59 s
#: to more than 120 s on problems of n <= 8.
DEFAULT_TIME_LIMIT = 60.0

#: the families whose calls the time limit and isolation apply to
BACKEND_FAMILIES = ("qpsolvers", "cvxpy")

#: A backend without a time setting whose work an iteration cap bounds runs
#: in-process on a small problem (Method.isolate_from) only while at least
#: this many seconds are left: 16 times the slowest such call measured
#: (qpcontact.solvers.backends.common.SMALL_WORK), so the default limit's
#: small solves pay no fork, and a short limit is kept by the kill.
IN_PROCESS_MIN_LEFT = 30.0


def problem_size(target) -> int:
    """Unknowns plus constraint rows of a backend's QP (a qpsolvers.Problem)."""
    n = int(target.P.shape[0])
    rows = sum(int(a.shape[0]) for a in (getattr(target, "G", None), getattr(target, "A", None))
               if a is not None)
    bounds = sum(n for b in (getattr(target, "lb", None), getattr(target, "ub", None))
                 if b is not None)
    return n + rows + bounds


def isolated(m: Method, target, ctx, time_limit) -> bool:
    """Whether ``m``'s call runs in a child process killed at the deadline:
    ``isolate=True``; or under a time limit (``isolate="auto"``), a backend
    that cannot keep it itself (:attr:`Method.isolate_from`) on a problem of
    at least its size, or with less than IN_PROCESS_MIN_LEFT seconds left."""
    if ctx.isolate is True:
        return True
    if ctx.isolate is False or time_limit is None or m.isolate_from is None:
        return False
    return time_limit < IN_PROCESS_MIN_LEFT or problem_size(target) >= m.isolate_from


def takes_keyword(run, name: str) -> bool:
    """Whether ``run`` accepts the keyword ``name`` (a method's run may take
    ``time_limit=`` and ``engine=``; a user's own may take neither)."""
    try:
        return name in _parameters(run)
    except TypeError:   # unhashable: read its signature each time
        try:
            return name in inspect.signature(run).parameters
        except (TypeError, ValueError):
            return False


@functools.lru_cache(maxsize=512)
def _parameters(run) -> frozenset:
    # inspect.signature cost a twentieth of a small LCP's solve, at every call
    try:
        return frozenset(inspect.signature(run).parameters)
    except (TypeError, ValueError):
        return frozenset()


def _run_with_limit(m: Method, target, tol, options, time_limit):
    if takes_keyword(m.run, "time_limit"):
        return m.run(target, tol, options, time_limit=time_limit)
    return m.run(target, tol, options)


def _isolated_run(name, target, tol, options, time_limit):
    # in the child: looked up by name so that spawn-started children work too
    return _run_with_limit(get_method(name), target, tol, options, time_limit)


def call(m: Method, target, options, ctx, engine=None) -> MethodResult:
    """The method's call within the run context ``ctx``
    (:class:`~qpcontact.dispatch.context.RunContext`): it is asked for
    ``ctx.tol_backend`` and given the seconds left as ``time_limit=``;
    ``engine`` is passed to the methods that solve sub-problems through it."""
    time_limit, tol = ctx.seconds(), ctx.tol_backend
    if m.family not in BACKEND_FAMILIES:
        kw = {}
        if engine is not None and takes_keyword(m.run, "engine"):
            kw["engine"] = engine
        if time_limit is not None and takes_keyword(m.run, "time_limit"):
            kw["time_limit"] = time_limit      # an in-house method that watches the clock
        return m.run(target, tol, options, **kw)
    if isolated(m, target, ctx, time_limit):
        from .isolation import call_isolated

        # the backend's own limit first; the kill at the deadline plus half
        # the stated grace, for a backend that does not keep it
        out = call_isolated(_isolated_run, (m.name, target, tol, options, time_limit),
                            ctx.kill_after())
        if out is not None:
            if out.kind == "ok":
                # timed in the child: the fork is not the backend's cost
                out.value.stats.update(isolated=True, backend_seconds=out.seconds)
                return out.value
            if out.kind == "error":
                raise out.value
            limit = "" if ctx.time_limit is None else f" of {ctx.time_limit:g} s"
            words = (f"stopped: no answer within the time limit{limit} ({out.detail}); raise "
                     "time_limit= or try another method"
                     if out.kind == "time_limit" else
                     f"{out.detail}; the backend crashed on these data (the caller survived "
                     "because it ran isolated); try another method or rescale the data")
            return MethodResult(x=None, backend_status=out.kind, backend_message=words,
                                status="time_limit" if out.kind == "time_limit" else None,
                                stats={"isolated": True})
    return _run_with_limit(m, target, tol, options, time_limit)
