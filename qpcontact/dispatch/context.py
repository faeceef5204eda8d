"""The run context: what one ``solve`` call carries down to every part of it.

``solve(problem, method, accuracy, time_limit=, isolate=)`` turns its
arguments once into a :class:`RunContext` — the accuracy as given and its two
tolerances (what a backend is asked for, what the certificate must meet), the
deadline on the wall clock, isolation, whether proofs are sought — and hands
that one object to "auto"'s chain, to each method's run, to the proofs and,
through the :class:`~qpcontact.dispatch.driver.Engine`, to the sub-solves of
a composite method (the load trace's Lemke solves, the friction fixed points'
QPs).  Time is given out one way: :meth:`RunContext.share` (a fraction of
what is left, never past the caller's deadline).  So ``time_limit`` is the
wall time of the whole call, whatever else the machine runs, plus at most
:func:`~qpcontact.core.deadline.grace` for the step in flight.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from ..core.accuracy import resolve_accuracy
from ..core.deadline import Deadline, check_time_limit, grace
from ..core.errors import InvalidOptionError

__all__ = ["RunContext", "LAST_SHARE"]

#: "auto" starts no further method once less than this fraction of the time
#: limit is left: a method's first step cannot be stopped halfway (a
#: 5 000-contact pile's Newton iteration took 0.8 s, started with 0.13 s of
#: a 4 s limit left), and a share that small certifies nothing
LAST_SHARE = 0.1


@dataclass(frozen=True)
class RunContext:
    """One call's accuracy, deadline, isolation and proof policy.

    ``accuracy``: as the user gave it (a level or a number); ``tol_backend``
    and ``tol_cert``: what :func:`~qpcontact.core.accuracy.resolve_accuracy`
    makes of it.  ``time_limit``: the user's seconds (for messages; None: no
    limit); ``deadline``: when this part of the call must end.  ``isolate``:
    "auto", True or False (see :func:`qpcontact.solve`).  ``prove``: whether
    a failed answer is followed by the search for a proof that no solution
    exists (False for a probe whose failure the caller handles itself)."""

    accuracy: object
    tol_backend: float
    tol_cert: float
    time_limit: float | None
    deadline: Deadline
    isolate: object = "auto"
    prove: bool = True

    @classmethod
    def start(cls, accuracy="high", time_limit=None, isolate="auto") -> "RunContext":
        """The context of a call that starts now (each argument checked)."""
        tol_backend, tol_cert = resolve_accuracy(accuracy)
        time_limit = check_time_limit(time_limit)
        return cls(accuracy, tol_backend, tol_cert, time_limit, Deadline(time_limit),
                   _checked_isolate(isolate))

    def left(self) -> float | None:
        """Seconds left to this part of the call (None: no limit)."""
        return self.deadline.left()

    def expired(self) -> bool:
        return self.deadline.expired()

    def spent(self) -> bool:
        """Whether too little is left to start another method
        (:data:`LAST_SHARE` of the limit)."""
        left = self.left()
        return left is not None and left < LAST_SHARE * self.time_limit

    def share(self, fraction: float) -> "RunContext":
        """The same context with ``fraction`` of the time left (all of it
        for 1)."""
        return replace(self, deadline=self.deadline.share(fraction))

    def seconds(self) -> float | None:
        """What is left as a method's ``time_limit=`` (never below a
        millisecond: a method handed nothing stops at its first check)."""
        left = self.left()
        return None if left is None else max(left, 1e-3)

    def at(self, accuracy=None, time_limit=None, isolate=None, prove=None) -> "RunContext":
        """A sub-solve's context: another accuracy, a time limit of its own
        (never past this deadline), isolation, proof policy."""
        ctx = self
        if accuracy is not None:
            tol_backend, tol_cert = resolve_accuracy(accuracy)
            ctx = replace(ctx, accuracy=accuracy, tol_backend=tol_backend, tol_cert=tol_cert)
        if time_limit is not None:
            ctx = replace(ctx, deadline=ctx.deadline.within(check_time_limit(time_limit)))
        if isolate is not None:
            ctx = replace(ctx, isolate=_checked_isolate(isolate))
        if prove is not None:
            ctx = replace(ctx, prove=bool(prove))
        return ctx

    def kill_after(self) -> float | None:
        """Seconds after which a child process running a backend is killed:
        what is left plus half the grace (the backend's own limit comes first;
        the kill is for one that does not keep it)."""
        left = self.left()
        return None if left is None else max(left, 0.0) + 0.5 * grace(self.time_limit)


def _checked_isolate(isolate):
    if isolate not in ("auto", True, False):
        raise InvalidOptionError(f"isolate must be 'auto', True or False; got {isolate!r}")
    return isolate
