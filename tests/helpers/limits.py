"""Time limits checked as the library states them, never a machine's speed.

``solve(..., time_limit=t)`` reads its deadline on the wall clock, so a
loaded machine slows the work, not the clock: the call stops at t, and
what runs past it — the step in flight, the certificate,
:func:`qpcontact.core.deadline.grace` seconds of work — runs at the share
of a core the process gets.  On a machine shared by three test runs that
share fell to 1/6 (a Lemke solve of 9.8 s of CPU took 61 s of wall time), so a test
allows grace divided by the share it measured over the call (CPU time over
wall time, at most 1; where the call waits on a child process, the cores
over the machine's load), and never less than the plain grace — nothing
tighter, which would time the machine.  A first call pays the one-time
costs the statement does not cover (imports, numba compiling its kernels
into the on-disk cache)."""

from __future__ import annotations

import os
import time

from qpcontact.core.deadline import grace

#: the smallest CPU share credited (a process starved below it is not a
#: statement about the library)
_MIN_SHARE = 0.05


class Took(float):
    """Wall seconds of a call, with ``share``: the fraction of one core it
    got (its CPU seconds over its wall seconds, at most 1)."""

    share: float = 1.0


def timed(call, *args, **kwargs):
    """(call's result, :class:`Took`: the wall seconds it took and its CPU share)."""
    wall, cpu = time.perf_counter(), time.process_time()
    out = call(*args, **kwargs)
    took = Took(time.perf_counter() - wall)
    own = (time.process_time() - cpu) / took if took > 0 else 1.0
    machine = _machine_share()
    # a call that waits on a child process (isolation) uses no CPU of its own:
    # the machine's load then says what share a process gets; a call that
    # computes is credited the smaller of its own share and the machine's —
    # its own counts every thread's CPU, and a pile's solve (numba's and
    # BLAS's threads) showed a full share while it ran 1.8-2.0 s of a 1 s
    # limit in `make test` beside two other jobs on 2 cores (load 3.5)
    took.share = min(1.0, machine if own < 0.5 * machine else min(own, machine))
    return out, took


def _machine_share() -> float:
    """The share of a core a runnable process gets: cores over the 1-minute
    load (1 where the load is unknown or below the core count)."""
    try:
        load = os.getloadavg()[0]
    except (AttributeError, OSError):
        return 1.0
    return min(1.0, (os.cpu_count() or 1) / load) if load > 0 else 1.0


def kept(limit: float, took: float) -> bool:
    """Whether ``took`` seconds keeps ``time_limit=limit`` as stated: the
    grace stretched by the CPU share the call got (``took.share`` when it
    came from :func:`timed`, else 1)."""
    share = max(_MIN_SHARE, min(1.0, getattr(took, "share", 1.0)))
    return took <= limit + grace(limit) / share
