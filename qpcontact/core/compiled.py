"""numba's ``njit`` with its on-disk cache, wherever the cache can be written.

A kernel compiled once is kept on disk, so that the next process loads it
instead of compiling it again (0.5–2 s per kernel module).  numba looks for a
writable place in order: ``NUMBA_CACHE_DIR`` when set, the ``__pycache__``
beside the source (a checkout), the user's cache folder (``~/.cache/numba``:
an installed wheel in a read-only site-packages).  Where none is writable (a
read-only home as well) numba refuses to import the module at all; the cache
then goes to the temporary folder, and failing that the kernel compiles in
every process.  The kernels' modules are imported only by the functions that
call them, so that ``import qpcontact`` never loads numba.
"""

from __future__ import annotations

import os
import tempfile
import threading
import time

import numba
from numba.core import event

from .deadline import exclude_one_time

__all__ = ["njit", "fallback_cache_dir"]


class _CompileClock(event.Listener):
    """numba's compile events (a kernel and the kernels it calls: nested)
    timed from the outermost one's start to its end and left out of the
    compiling thread's deadlines (:func:`.deadline.exclude_one_time`): a
    time limit does not cover compiling.  numba calls a listener on the
    thread that compiles, so each thread's compiling moves only its own
    deadlines; its CPU is that thread's (``time.thread_time``), not the
    process's, which would take another thread's work meanwhile off too.
    Timed from the thread's asking for numba's compiler lock, not from its
    compile event, which starts once the lock is held: a thread that needs
    a kernel while another thread compiles waits for the lock, and that
    wait is its own kernel's one-time cost too (two threads solving plane
    frames on a cold cache each compiled some of the frames' kernels and
    waited out the other's: both stopped at a 3 s limit that either met
    alone).  numba loads a kernel from the on-disk cache under the lock
    too, so that load is left out with it."""

    def __init__(self):
        self.depth = threading.local()

    def on_start(self, ev):
        depth = getattr(self.depth, "n", 0)
        if depth == 0:
            self.depth.started = (time.perf_counter(), time.thread_time())
        self.depth.n = depth + 1

    def on_end(self, ev):
        # an end without its start: the clock was registered while this
        # thread held the lock (another library's compiling), nothing to time
        depth = getattr(self.depth, "n", 0)
        if depth == 0:
            return
        self.depth.n = depth - 1
        if depth == 1:
            wall, cpu = self.depth.started
            exclude_one_time(time.perf_counter() - wall, time.thread_time() - cpu)


_CLOCK = _CompileClock()
# the compiler lock's events span the wait for it and the compiling inside
# it (the compile events nest in them: the clock times the outermost)
event.register("numba:compiler_lock", _CLOCK)
event.register("numba:compile", _CLOCK)


def fallback_cache_dir() -> str:
    """The cache folder used when numba finds no writable place of its own."""
    # one per user where the temporary folder is shared (Windows has one per user)
    user = f"-{os.getuid()}" if hasattr(os, "getuid") else ""
    return os.path.join(tempfile.gettempdir(), f"qpcontact-numba-cache{user}")


def njit(function=None, *, cache: bool = True, **options):
    """``numba.njit(cache=True, **options)``, used bare (``@njit``) or with
    options; see the module docstring for where the cache goes."""
    def compile_(f):
        if not cache:
            return numba.njit(**options)(f)
        try:
            return numba.njit(cache=True, **options)(f)
        except RuntimeError:   # "cannot cache function ...: no locator available"
            pass
        if not numba.config.CACHE_DIR:
            numba.config.CACHE_DIR = fallback_cache_dir()
            try:
                return numba.njit(cache=True, **options)(f)
            except RuntimeError:
                pass
        return numba.njit(**options)(f)
    return compile_ if function is None else compile_(function)
