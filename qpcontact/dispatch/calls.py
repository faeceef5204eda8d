"""Calling a method: the time its run context leaves it, in a child process
where it cannot honour a time limit itself, with the engine passed to
methods that solve sub-problems."""

from __future__ import annotations

import functools
import inspect

from ..core.results import MethodResult
from ..solvers.method import Method
from ..solvers.registry import get_method

__all__ = ["DEFAULT_TIME_LIMIT", "BACKEND_FAMILIES", "call", "takes_keyword"]

#: Seconds a ``solve`` call may take by default (``solve(..., time_limit=)``:
#: wall time for the whole call), enforced by the backends' own settings where
#: they have one, by a killable child process for those that do not (ProxQP;
#: qpcontact.dispatch.isolation) and by the in-house methods' and proofs'
#: checks of the deadline.  The slowest certified backend call in the
#: benchmarks (PIQP, n = 1e5 membrane) took 9 s; the hangs it cuts took 59 s
#: to more than 120 s on problems of n <= 8.
DEFAULT_TIME_LIMIT = 60.0

#: the families whose calls the time limit and isolation apply to
BACKEND_FAMILIES = ("qpsolvers", "cvxpy")


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
    if ctx.isolate is True or (ctx.isolate == "auto" and time_limit is not None
                               and m.needs_isolation):
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
