"""Running a backend call in a child process that can be killed.

Two things cannot be handled inside the process that calls a compiled
backend: a call that never returns (ProxQP 0.8 has no time limit of its own
and ran 77 s — 3e5 inner iterations — on an SPD problem of n = 300 with
``max_iter = 10 000``), and a call that kills the process (HiGHS 1.15: a
segmentation fault on a singular Hessian holding 1e15; docs/backends.md).
:func:`call_isolated` runs ``fn(*args)`` in a forked child and waits at most
``time_limit`` seconds; a hang is killed and reported, a crash is reported
with its signal, and the caller survives both.

The decision (docs/dev-notes.md, "Backend isolation"): :func:`qpcontact.solve`
runs backends in-process by default and gives each its own time limit where
the backend has one (OSQP, Clarabel, HiGHS, SCS); backends without one whose
run time is not bounded by an iteration cap (ProxQP) run isolated; ``isolate=
True`` isolates every backend call (``qpcontact stress`` does, so a crashing
backend costs one row of its table, not the run).
"""

from __future__ import annotations

import multiprocessing as mp
import os
import signal
import sys
import time
import traceback

__all__ = ["call_isolated", "IsolatedOutcome"]


class IsolatedOutcome:
    """What came back from the child: ``kind`` is "ok" (``value`` holds the
    return value), "error" (``value`` is the exception), "time_limit" or
    "crashed" (``detail`` names the signal or exit code)."""

    __slots__ = ("kind", "value", "detail", "seconds")

    def __init__(self, kind, value=None, detail="", seconds=0.0):
        self.kind, self.value, self.detail, self.seconds = kind, value, detail, seconds


def _die_with_parent(parent: int) -> None:
    """Have the kernel kill this child when its parent dies (Linux's
    PR_SET_PDEATHSIG): a caller killed while it waits — a benchmark's or a
    job runner's own time limit — left ProxQP running on, orphaned, for over
    half an hour.  Elsewhere nothing is set (the parent's own kill at the
    deadline still holds)."""
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL)          # PR_SET_PDEATHSIG = 1
    except (OSError, AttributeError):
        return
    if os.getppid() != parent:                 # the parent died before prctl
        os._exit(1)


def _child(conn, fn, args, parent=None):
    import faulthandler

    faulthandler.disable()  # a crash is reported by the parent, in one line
    if parent is not None:
        _die_with_parent(parent)
    try:
        start = time.perf_counter()
        value = fn(*args)
        conn.send(("ok", value, time.perf_counter() - start))
    except BaseException as exc:  # noqa: BLE001 — everything goes back to the parent
        try:
            conn.send(("error", exc, 0.0))
        except Exception:  # an exception that does not pickle goes back as text
            conn.send(("error", RuntimeError("".join(traceback.format_exception_only(exc)).strip()), 0.0))
    finally:
        conn.close()


def process_context():
    """The multiprocessing context of isolated calls: fork, so that the child
    inherits the imported backends and the problem without pickling them;
    elsewhere spawn (fn and args must then pickle)."""
    return mp.get_context("fork" if sys.platform.startswith("linux") else "spawn")


def call_isolated(fn, args: tuple, time_limit: float | None) -> IsolatedOutcome | None:
    """Run ``fn(*args)`` in a child process, at most ``time_limit`` seconds
    (None: no limit).  Returns None when no child can be started here (a
    daemonic process, e.g. some pool workers, may not have children): the
    caller then runs the call in-process."""
    ctx = process_context()
    recv, send = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_child, args=(send, fn, args, os.getpid()), daemon=True)
    try:
        proc.start()
    except (AssertionError, OSError):
        recv.close()
        send.close()
        return None
    send.close()
    try:
        ready = recv.poll(time_limit)
        if not ready:
            proc.kill()
            proc.join()
            return IsolatedOutcome("time_limit", detail=f"killed after {time_limit:g} s")
        try:
            kind, value, seconds = recv.recv()
        except (EOFError, OSError):
            proc.join()
            return IsolatedOutcome("crashed", detail=_exit_words(proc.exitcode))
        # the answer is in hand: the child's orderly exit (multiprocessing's
        # finalizers in a forked copy of this process) is not waited for
        proc.kill()
        proc.join()
        return IsolatedOutcome(kind, value, seconds=seconds)
    finally:
        recv.close()
        if proc.is_alive():
            proc.kill()
            proc.join()


def _exit_words(code) -> str:
    if code is None:
        return "the child process vanished"
    if code < 0:
        try:
            return f"the backend process died of signal {signal.Signals(-code).name}"
        except ValueError:
            return f"the backend process died of signal {-code}"
    return f"the backend process exited with code {code} without answering"
