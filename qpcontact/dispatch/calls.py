"""Calling a method: its time limit, in a child process where it cannot honour
one itself, with the engine passed to methods that solve sub-problems."""

from __future__ import annotations

import inspect

from ..core.errors import InvalidOptionError
from ..core.results import MethodResult
from ..solvers.method import Method
from ..solvers.registry import get_method

__all__ = ["DEFAULT_TIME_LIMIT", "BACKEND_FAMILIES", "call", "check_time_limit", "takes_keyword"]

#: Seconds a backend call may take (``solve(..., time_limit=)``), enforced by
#: the backend's own setting where it has one and by a killable child process
#: for ProxQP (qpcontact.dispatch.isolation).  The slowest certified backend call in the
#: benchmarks (PIQP, n = 1e5 membrane) took 9 s; the hangs it cuts took 59 s
#: to more than 120 s on problems of n <= 8.
DEFAULT_TIME_LIMIT = 60.0

#: the families whose calls the time limit and isolation apply to
BACKEND_FAMILIES = ("qpsolvers", "cvxpy")


def takes_keyword(run, name: str) -> bool:
    """Whether ``run`` accepts the keyword ``name`` (a method's run may take
    ``time_limit=`` and ``engine=``; a user's own may take neither)."""
    try:
        return name in inspect.signature(run).parameters
    except (TypeError, ValueError):
        return False


def _run_with_limit(m: Method, target, tol, options, time_limit):
    if takes_keyword(m.run, "time_limit"):
        return m.run(target, tol, options, time_limit=time_limit)
    return m.run(target, tol, options)


def _isolated_run(name, target, tol, options, time_limit):
    # in the child: looked up by name so that spawn-started children work too
    return _run_with_limit(get_method(name), target, tol, options, time_limit)


def call(m: Method, target, tol_backend, options, time_limit, isolate, engine=None
         ) -> MethodResult:
    """The method's call, with the time limit and isolation of :func:`solve`;
    ``engine`` is passed to the methods that solve sub-problems through it."""
    if m.family not in BACKEND_FAMILIES:
        kw = {}
        if engine is not None and takes_keyword(m.run, "engine"):
            kw["engine"] = engine
        if time_limit is not None and takes_keyword(m.run, "time_limit"):
            kw["time_limit"] = time_limit      # an in-house method that watches the clock
        return m.run(target, tol_backend, options, **kw)
    if isolate is True or (isolate == "auto" and time_limit is not None and m.needs_isolation):
        from .isolation import call_isolated

        # the backend's own limit first; the kill a moment later — but within
        # half the limit again, so that a call stays inside 1.5 x its limit
        # (qpcontact stress flags solves beyond that)
        hard = None if time_limit is None else 1.2 * time_limit + min(2.0, 0.1 * time_limit)
        out = call_isolated(_isolated_run, (m.name, target, tol_backend, options, time_limit), hard)
        if out is not None:
            if out.kind == "ok":
                # timed in the child: the fork is not the backend's cost
                out.value.stats.update(isolated=True, backend_seconds=out.seconds)
                return out.value
            if out.kind == "error":
                raise out.value
            words = (f"stopped: no answer within the time limit of {time_limit:g} s "
                     f"({out.detail}); raise time_limit= or try another method"
                     if out.kind == "time_limit" else
                     f"{out.detail}; the backend crashed on these data (the caller survived "
                     "because it ran isolated); try another method or rescale the data")
            return MethodResult(x=None, backend_status=out.kind, backend_message=words,
                                status="time_limit" if out.kind == "time_limit" else None,
                                stats={"isolated": True})
    return _run_with_limit(m, target, tol_backend, options, time_limit)


def check_time_limit(time_limit):
    if time_limit is None:
        return None
    try:
        value = float(time_limit)
    except (TypeError, ValueError):
        value = float("nan")
    if isinstance(time_limit, bool) or not value > 0:
        raise InvalidOptionError(
            f"time_limit must be a positive number of seconds or None; got {time_limit!r}")
    return value
