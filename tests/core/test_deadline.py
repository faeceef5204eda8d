"""A share of a call counted in the process's CPU time: it ends on the CPU it
was given, not on wall time a loaded machine spends elsewhere, and never past
its wall cap."""

from __future__ import annotations

import time

from qpcontact.core.deadline import CpuShare, Deadline


def test_a_cpu_share_waits_while_the_process_sleeps_and_ends_on_its_cpu():
    share = Deadline(60.0).cpu_share(0.002, 0.5)         # 0.12 s of CPU, 30 s of wall
    assert isinstance(share, CpuShare)
    time.sleep(0.3)                                      # no CPU used: a loaded machine's wait
    assert not share.expired()
    start = time.process_time()
    while not share.expired():
        sum(range(1000))
    assert time.process_time() - start >= 0.1            # it ended on the CPU it was given
    assert share.left() <= 0


def test_a_cpu_share_never_outlasts_its_wall_cap_or_its_parent():
    parent = Deadline(0.2)
    share = parent.cpu_share(10.0, 0.5)                  # CPU enough for ever: the wall cap rules
    assert share.end <= parent.end and share.left() <= 0.1 + 1e-3
    time.sleep(0.15)
    assert share.expired()
    assert share.within(100.0).expired() and share.share(0.5).expired()
    assert not Deadline().cpu_share(0.25, 0.5).limited   # no deadline, no share
