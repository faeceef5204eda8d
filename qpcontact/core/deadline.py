"""A deadline on the wall clock: the one way time is measured and shared out.

``solve(..., time_limit=t)`` means the call returns within t seconds of wall
time (plus the grace :data:`GRACE` states) however busy the machine is: a
loaded machine slows the work, not the clock.  So every part of a call —
"auto"'s chain, each method, each proof — measures the same deadline, never a
duration of its own started later, and a part given a share gets a deadline
no later than its caller's.
"""

from __future__ import annotations

import math
import threading
import time

from .errors import InvalidOptionError

__all__ = ["Deadline", "CpuShare", "Pace", "check_time_limit", "grace", "exclude_one_time"]

#: Per thread, the (wall, CPU) seconds it has spent on what no time limit
#: covers (:func:`grace`): numba compiling kernels, which :mod:`.compiled`
#: reports from the thread that compiles.  Deadlines run on clocks that leave
#: them out, so that a first call's compiling (16 s of CPU for the
#: multigrid's kernels on a cold cache, a minute of wall time at load 8) does
#: not eat a link's share of "auto" and hand the problem to a slower method —
#: it delays the answer instead, as grace's docstring states.  Per thread: a
#: deadline is moved only by its own thread's compiling, not by a kernel
#: another thread compiles meanwhile (the process-wide sum extended every
#: thread's deadlines by every thread's compiling).  A thread that needs a
#: kernel while another thread compiles waits for numba's compiler lock:
#: that wait is its own kernel's one-time cost, left out with its compiling.
_THREAD = threading.local()


def _one_time() -> list:
    """This thread's [wall, CPU] seconds of one-time work: one list per
    thread, which every Deadline made on the thread keeps (its clock reads it
    from any thread)."""
    try:
        return _THREAD.spent
    except AttributeError:
        _THREAD.spent = spent = [0.0, 0.0]
        return spent


def exclude_one_time(wall: float, cpu: float) -> None:
    """Leave ``wall`` and ``cpu`` seconds just spent on one-time work by this
    thread out of the clocks of this thread's deadlines."""
    spent = _one_time()
    spent[0] += wall
    spent[1] += cpu


def grace(time_limit: float | None) -> float:
    """Seconds a call may run past its time limit: the step in flight at the
    deadline ends (a backend's iteration, one factorization, one exact check
    of a candidate) and the answer is certified.  0.5 s plus a tenth of the
    limit, of work at a full core's speed (a process that gets a share of
    a core takes that much longer).  Not covered: the one-time costs of a process's first use of a
    method — importing its backend (up to a second or two) and numba
    compiling its kernels into the on-disk cache (once per machine; the
    deadlines' clocks leave compiling out: :func:`exclude_one_time`)."""
    return 0.0 if time_limit is None else 0.5 + 0.1 * time_limit


def check_time_limit(time_limit) -> float | None:
    """``time_limit`` as positive finite seconds, or None for no limit;
    InvalidOptionError naming the value otherwise (a string, a bool, zero, a
    negative number, NaN, inf)."""
    if time_limit is None:
        return None
    if isinstance(time_limit, bool) or not isinstance(time_limit, (int, float)) \
            and type(time_limit).__module__ != "numpy":
        raise InvalidOptionError(
            f"time_limit must be a positive number of seconds or None (no limit); got "
            f"{time_limit!r} of type {type(time_limit).__name__}")
    try:
        value = float(time_limit)
    except (TypeError, ValueError):
        value = math.nan
    if not (value > 0 and math.isfinite(value)):
        raise InvalidOptionError(
            f"time_limit must be a positive, finite number of seconds or None (no limit); got "
            f"{time_limit!r}")
    return value


class Deadline:
    """A point on the monotonic wall clock (``time.perf_counter``, less the
    one-time work of the thread it was made on: :func:`exclude_one_time`),
    or none.

    ``Deadline(seconds)`` ends that many seconds from now (None: never).
    :meth:`share` gives a part of the work a deadline of its own, never later
    than this one; a part made on another thread runs on that thread's
    clock from the hand-over (its own compiling left out).  A deadline
    waited on by one thread while another compiles for it is not extended.
    """

    __slots__ = ("end", "spent")

    def __init__(self, seconds: float | None = None, *, end: float | None = None):
        self.spent = _one_time()
        self.end = end if seconds is None else self.now() + float(seconds)

    def now(self) -> float:
        """This deadline's clock: the wall clock less the one-time work of
        the thread it was made on."""
        return time.perf_counter() - self.spent[0]

    def cpu_now(self) -> float:
        """This process's CPU time less that thread's one-time work."""
        return time.process_time() - self.spent[1]

    def _on_my_clock(self, end: float | None) -> "Deadline":
        """A Deadline ending at ``end`` (on this one's clock), moved to the
        clock of the thread that asks: the seconds left are the same at the
        hand-over, and from then on the part leaves out the compiling of
        the thread that does its work (a worker given a share of the main
        thread's limit would otherwise be charged for its own compiling)."""
        part = object.__new__(Deadline)
        part.end, part.spent = self._moved(end, 0)
        return part

    def _moved(self, end, which):
        mine = _one_time()
        if end is None or mine is self.spent:
            return end, mine
        return end + self.spent[which] - mine[which], mine

    @property
    def limited(self) -> bool:
        return self.end is not None

    def left(self) -> float | None:
        """Seconds left (negative once passed), or None without a deadline."""
        return None if self.end is None else self.end - self.now()

    def expired(self) -> bool:
        return self.end is not None and self.now() >= self.end

    def share(self, fraction: float) -> "Deadline":
        """A deadline ``fraction`` of what is left from now (this one's when
        ``fraction`` >= 1)."""
        if self.end is None or fraction >= 1.0:
            return self._on_my_clock(self.end)
        now = self.now()
        return self._on_my_clock(now + max(self.end - now, 0.0) * fraction)

    def within(self, seconds: float | None) -> "Deadline":
        """The earlier of this deadline and ``seconds`` from now."""
        if seconds is None:
            return self._on_my_clock(self.end)
        end = self.now() + seconds
        return self._on_my_clock(end if self.end is None else min(end, self.end))

    def cpu_share(self, fraction: float, wall_fraction: float) -> "Deadline":
        """A share of the work measured in this process's CPU time: it ends
        once the process has used ``fraction`` of what is left as CPU
        seconds, or at ``wall_fraction`` of what is left on the wall clock,
        whichever comes first (:class:`CpuShare`).  On an idle core the two
        agree; on a loaded machine the part gets the work it would get
        alone, up to ``wall_fraction`` of the time — a proof that needs 0.05
        s of CPU is not cut off at 0.5 s of wall time that held 0.04 s of
        it.  Without a deadline: none."""
        if self.end is None:
            return self._on_my_clock(None)
        now = self.now()
        left = max(self.end - now, 0.0)
        return _cpu_part(self, now + left * min(wall_fraction, 1.0),
                         self.cpu_now() + left * fraction)

    def __repr__(self) -> str:
        left = self.left()
        return "Deadline(none)" if left is None else f"Deadline({left:.3g} s left)"


class CpuShare(Deadline):
    """A :class:`Deadline` that also ends once this process's CPU time
    (``time.process_time``, every thread of it, less the one-time work of
    the thread it was made on) reaches ``cpu_end``; made by
    :meth:`Deadline.cpu_share`, on the clocks of the deadline it shares
    (``spent``: its thread's one-time work).  ``left()`` is the smaller of
    the two, so a part handing it on as wall seconds stops no later than
    either."""

    __slots__ = ("cpu_end",)

    def __init__(self, end: float, cpu_end: float, spent: list):
        self.end, self.cpu_end, self.spent = end, cpu_end, spent

    def left(self) -> float:
        return min(self.end - self.now(), self.cpu_end - self.cpu_now())

    def expired(self) -> bool:
        return self.now() >= self.end or self.cpu_now() >= self.cpu_end

    def share(self, fraction: float) -> "Deadline":
        return self._on_my_clock(self.now() + max(self.left(), 0.0) * min(fraction, 1.0))

    def within(self, seconds: float | None) -> "Deadline":
        end = self.end if seconds is None else min(self.end, self.now() + seconds)
        return _cpu_part(self, end, self.cpu_end)


def _cpu_part(parent: Deadline, end: float, cpu_end: float) -> CpuShare:
    """A :class:`CpuShare` ending at ``end`` and ``cpu_end`` on ``parent``'s
    clocks, moved to the asking thread's (:meth:`Deadline._on_my_clock`)."""
    end, spent = parent._moved(end, 0)
    cpu_end, _ = parent._moved(cpu_end, 1)
    return CpuShare(end, cpu_end, spent)


class Pace:
    """Whether one more step of a loop fits in ``time_limit`` seconds from
    now, judged by the longest step so far: a step that cannot be stopped
    halfway (a Newton iteration's factorization, one SOCP) is not started
    where the last one would not have fitted (a 5 000-contact pile's Newton
    step took 0.8 s, started with 0.13 s left).  ``time_limit`` None: always.
    Steps are timed on the deadline's clock (compiling left out)."""

    __slots__ = ("deadline", "longest", "_since")

    def __init__(self, time_limit: float | None):
        self.deadline = Deadline(time_limit)
        self.longest = 0.0
        self._since = self.deadline.now()

    def step_done(self) -> None:
        now = self.deadline.now()
        self.longest = max(self.longest, now - self._since)
        self._since = now

    def fits(self) -> bool:
        left = self.deadline.left()
        return left is None or left > self.longest
