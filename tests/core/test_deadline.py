"""A share of a call counted in the process's CPU time: it ends on the CPU it
was given, not on wall time a loaded machine spends elsewhere, and never past
its wall cap."""

from __future__ import annotations

import time

import numpy as np
import pytest

from qpcontact.core.deadline import CpuShare, Deadline


def test_a_cpu_share_waits_while_the_process_sleeps_and_ends_on_its_cpu():
    # the CPU counted from before the share began: the process's other
    # threads (pytest-xdist's) may spend some of the share during the sleep,
    # so the loop alone got 0.096 s of it under load
    start = time.process_time()
    share = Deadline(60.0).cpu_share(0.002, 0.5)         # 0.12 s of CPU, 30 s of wall
    assert isinstance(share, CpuShare)
    time.sleep(0.3)                                      # no CPU used: a loaded machine's wait
    assert not share.expired()
    while not share.expired():
        sum(range(1000))
    assert time.process_time() - start >= 0.12 * (1 - 1e-6)   # it ended on the CPU it was given
    assert share.left() <= 0


def test_a_cpu_share_never_outlasts_its_wall_cap_or_its_parent():
    parent = Deadline(0.2)
    share = parent.cpu_share(10.0, 0.5)                  # CPU enough for ever: the wall cap rules
    assert share.end <= parent.end and share.left() <= 0.1 + 1e-3
    time.sleep(0.15)
    assert share.expired()
    assert share.within(100.0).expired() and share.share(0.5).expired()
    assert not Deadline().cpu_share(0.25, 0.5).limited   # no deadline, no share


def test_a_deadline_leaves_numba_compiling_out():
    """Compiling a kernel is a one-time cost no time limit covers (grace's
    docstring): a deadline's clock does not run while numba compiles (a cold
    cache's multigrid kernels took 16 s of CPU and handed a membrane from
    "auto"'s mg-bpp link, out of its share, to bpp); the work after it
    counts as before."""
    from qpcontact.core.compiled import njit

    @njit(cache=False)
    def once(x):             # compiled on its first call, in this process only
        return x * 2.0 + 1.0

    d = Deadline(100.0)
    before = d.left()
    start = time.perf_counter()
    assert once(1.0) == 3.0
    took = time.perf_counter() - start
    assert took > 0.005, took                      # it did compile
    assert before - d.left() < 0.5 * took, (before - d.left(), took)
    start, left = time.perf_counter(), d.left()
    time.sleep(0.05)
    assert left - d.left() == pytest.approx(time.perf_counter() - start, abs=0.02)


def test_lemkes_proofs_keep_its_time_limit_after_compiling_elsewhere(monkeypatch):
    """lemke's deadline was a raw time.perf_counter value; handed on as
    Deadline(end=...), whose clock leaves compiling out, its infeasibility
    LP ran on for every second this process had compiled before (1 000 s
    here for a 5 s limit).  It is now a Deadline from the start."""
    import qpcontact
    import qpcontact.solvers.pivoting.lemke as lemke_module
    from qpcontact import LCP
    from qpcontact.core.deadline import exclude_one_time

    seen, feasibility = [], lemke_module.feasibility

    def timed_feasibility(M, q, rs, cs, deadline):
        seen.append(deadline.left())
        return feasibility(M, q, rs, cs, deadline)

    monkeypatch.setattr(lemke_module, "feasibility", timed_feasibility)
    exclude_one_time(1000.0, 1000.0)               # as if compiled for 1 000 s before
    try:
        qpcontact.solve(LCP(np.array([[1.0, -1.0], [-1.0, 1.0]]), np.array([-1.0, -1.0])),
                        method="lemke", time_limit=5.0)
    finally:
        exclude_one_time(-1000.0, -1000.0)
    assert seen and all(left <= 5.0 for left in seen), seen


def test_a_deadline_is_moved_by_its_own_threads_compiling_only():
    """Compiling is left out of the deadlines of the thread that compiles,
    not of every thread's: while a kernel compiles on another thread, a
    deadline here runs on second for second, and the process's CPU spent
    there counts against a CPU share here (the process-wide sum extended
    every thread's deadlines by every thread's compiling).  The compiling
    thread's own deadline still leaves it out."""
    import threading

    from qpcontact.core.compiled import njit

    @njit(cache=False)
    def once(x):             # compiled on its first call, on the other thread
        return x * 3.0 - 1.0

    there = {}

    def compile_there():
        d = Deadline(100.0)
        before, start = d.left(), time.perf_counter()
        there["result"] = once(1.0)
        there["took"] = time.perf_counter() - start
        there["moved"] = before - d.left()

    mine = Deadline(100.0)
    cpu_share = Deadline(100.0).cpu_share(0.05, 1.0)     # 5 s of CPU: its left() is the CPU's
    before, cpu_before = mine.left(), cpu_share.left()
    start, cpu_start = time.perf_counter(), time.process_time()
    worker = threading.Thread(target=compile_there)
    worker.start()
    worker.join()
    elapsed, cpu_used = time.perf_counter() - start, time.process_time() - cpu_start
    assert there["result"] == 2.0 and there["took"] > 0.005, there      # it did compile
    assert there["moved"] < 0.5 * there["took"], there                  # left out there
    assert before - mine.left() >= elapsed - 0.1 * there["took"], (before - mine.left(), there)
    cpu_moved = cpu_before - cpu_share.left()
    assert cpu_moved >= cpu_used - 0.5 * there["took"], (cpu_moved, cpu_used, there)


def test_a_thread_waiting_for_the_compiler_lock_leaves_the_wait_out():
    """A thread that needs a kernel while another thread holds numba's
    compiler lock waits for it, then compiles: the wait is its kernel's
    one-time cost as much as the compiling, and its deadlines leave both
    out (timed from its compile event alone, a second's wait ate a second
    of its limit: two threads solving plane frames on a cold cache each
    compiled some of the frames' kernels, waited out the other's, and both
    stopped at a 3 s limit that either met alone).  The thread holding the
    lock here stands for the other thread's compiling."""
    import threading

    from numba.core.compiler_lock import global_compiler_lock

    from qpcontact.core.compiled import njit

    @njit(cache=False)
    def once(x):             # compiled on its first call, on the worker, after the wait
        return x * 7.0 - 4.0

    there = {}

    def work():
        d = Deadline(100.0)
        before, start = d.left(), time.perf_counter()
        there["result"] = once(1.0)
        there["took"] = time.perf_counter() - start
        there["moved"] = before - d.left()

    worker = threading.Thread(target=work)
    with global_compiler_lock:
        worker.start()
        time.sleep(1.0)
    worker.join()
    assert there["result"] == 3.0 and there["took"] >= 1.0, there       # it waited
    assert there["moved"] < 0.5, there                                  # wait and compile left out


def test_a_share_handed_to_a_worker_leaves_out_the_workers_compiling():
    """A share of this thread's deadline made on a worker thread runs on the
    worker's clock from the hand-over: the seconds left are the same then,
    and the worker's own compiling is left out of it, as it would be had
    the worker made its own deadline (the share kept the maker's clock and
    a 0.77 s compile took 0.77 s of a 1 s share).  Wall and CPU shares
    alike."""
    import threading

    from qpcontact.core.compiled import njit

    @njit(cache=False)
    def once(x):             # compiled on its first call, on the worker
        return x * 5.0 + 2.0

    parent = Deadline(100.0)
    there = {}

    def work():
        share, cpu = parent.share(1.0), parent.cpu_share(1.0, 1.0)
        there["at_hand_over"] = (parent.left(), share.left())
        before, cpu_before = share.left(), cpu.left()
        start = time.perf_counter()
        there["result"] = once(1.0)
        there["took"] = time.perf_counter() - start
        there["moved"] = before - share.left()
        there["cpu_moved"] = cpu_before - cpu.left()

    worker = threading.Thread(target=work)
    worker.start()
    worker.join()
    assert there["result"] == 7.0 and there["took"] > 0.005, there        # it did compile
    p_left, s_left = there["at_hand_over"]
    assert abs(p_left - s_left) < 0.05, there                           # the same seconds left
    assert there["moved"] < 0.5 * there["took"], there                  # compiling left out
    assert there["cpu_moved"] < 0.5 * there["took"] + 0.05, there
