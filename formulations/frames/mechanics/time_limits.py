"""A frame analysis's time limit: one wall-clock deadline for the whole
call (every route after the active set, every round of a second-order
analysis, the proofs along a load path), handed on to each method as the
seconds that are left."""

from __future__ import annotations

from qpcontact.core.deadline import Deadline, check_time_limit
from qpcontact.core.errors import SolverFailedError

from .loads import describe

#: seconds of wall time one analysis may take by default (``time_limit=``),
#: as ``qpcontact.solve``'s calls: the routes after the active set (Lemke,
#: the load path, the proofs along it) share it; a random 117-contact
#: frame's collapse proof branched for minutes without one
TIME_LIMIT = 60.0


def deadline_of(options) -> Deadline:
    """The analysis's wall-clock deadline, taken out of ``options``: the
    one :func:`solve` put there for the whole call, or one made here from
    a number of seconds (None: none)."""
    given = options.pop("time_limit", None)
    return given if isinstance(given, Deadline) else Deadline(check_time_limit(given))


def seconds_left(deadline: Deadline) -> float | None:
    """What is left of ``deadline`` as a ``time_limit=`` (None: no limit;
    at least a millisecond, so that a method called at the deadline stops
    at once with its own "time_limit" status rather than refusing the
    value)."""
    left = deadline.left()
    return None if left is None else max(left, 1e-3)


def out_of_time(frame, combo, deadline: Deadline, what: str) -> None:
    """SolverFailedError where ``deadline`` has passed: what had been tried
    (``what``), and that nothing was proved."""
    if deadline.expired():
        raise SolverFailedError(
            f"frame under {describe(combo)}: no certified equilibrium and no proof within the "
            f"time limit ({what}); nothing was proved either way — solve(..., time_limit=...) "
            "gives the analysis longer (None: no limit)")
