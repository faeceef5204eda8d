""""nsgs-restarts": NSGS + Newton from r0, then from random reactions within
the cones — the starts checked against the cone written out here, the first
start against nsgs-newton (its peer: where that certifies, this is it), and
a later start's answer against the natural map written out here."""

from __future__ import annotations

import numpy as np
import pytest

import qpcontact
from qpcontact.cases.piles import sphere_pile
from qpcontact.core.friction_problem import FrictionProblem
from qpcontact.solvers.friction.restarts import random_cone_point


def _natural_map_here(p, r):
    """Siconos's natural-map error, contact by contact, De Saxcé's velocity
    and the cone's projection written out (not the package's)."""
    u = np.asarray(p.W @ r).ravel() + p.q
    out = np.zeros_like(r)
    for i, mu in enumerate(p.mu):
        ri, ui = r[3 * i:3 * i + 3], u[3 * i:3 * i + 3]
        x = ri - np.array([ui[0] + mu * np.hypot(ui[1], ui[2]), ui[1], ui[2]])
        t = np.hypot(x[1], x[2])
        if t <= mu * x[0]:
            proj = x
        elif mu * t <= -x[0]:
            proj = np.zeros(3)
        else:
            a = (x[0] + mu * t) / (1 + mu * mu)
            proj = np.array([a, mu * a * x[1] / t, mu * a * x[2] / t])
        out[3 * i:3 * i + 3] = ri - proj
    return np.linalg.norm(out) / (1 + np.linalg.norm(p.q))


def test_the_random_starts_lie_in_the_cones_and_repeat():
    rng = np.random.default_rng(0)
    nc = 200
    mu = rng.uniform(0.0, 1.0, nc)          # below 0.3·√2 the projection acts
    p = FrictionProblem(np.eye(3 * nc), -np.ones(3 * nc), mu, 3)
    r = random_cone_point(p, 2.5, 3)
    rn, rt = r[0::3], np.hypot(r[1::3], r[2::3])
    assert np.all(rn >= 0) and np.all(rt <= mu * rn * (1 + 1e-12) + 1e-300)
    assert r.max() <= 2.5 and rn.max() > 2.0       # the scale is spread, not shrunk
    assert np.any(rt < mu * rn * (1 - 1e-6))          # not all pushed onto the cones' sides
    assert np.array_equal(r, random_cone_point(p, 2.5, 3))
    assert not np.array_equal(r, random_cone_point(p, 2.5, 4))


def test_where_nsgs_newton_certifies_the_first_start_is_its_answer():
    """A loose 3-D pile: nsgs-newton certifies it from zero; nsgs-restarts
    returns the same reactions, bit for bit, from one start."""
    p = sphere_pile(300, seed=1).problem
    ref = qpcontact.solve(p, "nsgs-newton", accuracy=1e-8)
    assert ref.ok, ref.message
    s = qpcontact.solve(p, "nsgs-restarts", accuracy=1e-8)
    assert s.ok and np.array_equal(s.r, ref.r), s.message
    assert "from 1 start:" in s.message, s.message


def test_auto_in_3d_from_500_contacts_starts_with_the_restarts():
    """The loose 540-contact pile: "auto"'s first link, nsgs-restarts,
    certifies it from its first start (nsgs-newton's answer)."""
    p = sphere_pile(500, seed=0).problem
    s = qpcontact.solve(p, "auto", accuracy=1e-6)
    assert s.ok and s.method == "nsgs-restarts", s.message
    assert [m for m, _, _ in s.stats["auto_tried"]] == ["nsgs-restarts"]
    assert _natural_map_here(p, s.r) <= 1e-6


@pytest.mark.slow
def test_a_later_start_certifies_a_compact_pile_the_first_does_not():
    """The 540-contact compact pile of seed 9: nsgs-newton and Newton from
    its best point stop above 1e-6 from zero; a start from random reactions
    certifies it (docs/dev-notes.md, "The 3-D compact piles by restarts")."""
    p = sphere_pile(500, seed=9, agitation=0.1, polydispersity=0.005).problem
    first = qpcontact.solve(p, "nsgs-restarts", accuracy=1e-6, starts=1, time_limit=300)
    assert not first.ok, first.message
    s = qpcontact.solve(p, "nsgs-restarts", accuracy=1e-6, starts=6, time_limit=300)
    assert s.ok, s.message
    assert "start 0:" in s.message and "from 1 start:" not in s.message, s.message
    assert _natural_map_here(p, s.r) <= 1e-6


def test_a_first_start_cut_off_by_the_time_limit_returns_its_point():
    """The first start's sweeps stop at the time limit, a little past it:
    Newton from its point then had a negative time limit and "nsgs-restarts"
    raised InvalidOptionError (found on a 982-contact compact pile under
    "auto" at a load of 6).  Now the start's point comes back, judged."""
    p = sphere_pile(300, seed=2, agitation=0.1, polydispersity=0.005).problem
    for limit in (0.05, 0.2):
        s = qpcontact.solve(p, "nsgs-restarts", accuracy=1e-12, time_limit=limit)
        assert not s.ok and np.isfinite(s.error) and "start 0:" in s.message, s.message


def test_a_draw_that_outlasts_the_time_limit_ends_the_starts(monkeypatch):
    """Between the loop's check of the deadline and a start's call the
    random draw takes time; where the deadline passes there, the start got
    a negative time limit and raised.  Here the draw is made to outlast it
    (the sweeps cut to 20 so that the first start ends well before)."""
    import time

    from qpcontact.solvers.friction import restarts
    from qpcontact.solvers.friction.hybrid import solve_nsgs_newton

    def slow_draw(problem, scale, k):
        time.sleep(1.0)
        return random_cone_point(problem, scale, k)

    monkeypatch.setattr(restarts, "random_cone_point", slow_draw)
    monkeypatch.setattr(restarts, "solve_nsgs_newton",
                        lambda p, tol, opts: solve_nsgs_newton(p, tol, {**opts, "max_sweeps": 20}))
    p = sphere_pile(300, seed=2, agitation=0.1, polydispersity=0.005).problem
    r, status, message, stats = restarts.solve_nsgs_restarts(
        p, 1e-12, {"time_limit": 1.0, "starts": 3})
    assert status == "stopped" and stats["starts"] == 1 and r is not None, message


class _SlowClock:
    """``time`` as the deadlines read it on a machine ``factor`` times slower:
    every second of work reads as ``factor`` seconds."""

    def __init__(self, factor):
        import time

        self._time, self._factor = time, factor
        self._t0, self._c0 = time.perf_counter(), time.process_time()

    def perf_counter(self):
        return self._t0 + self._factor * (self._time.perf_counter() - self._t0)

    def process_time(self):
        return self._c0 + self._factor * (self._time.process_time() - self._c0)


def _starts_without_seconds(message):
    import re

    return re.sub(r", [0-9.e+-]+ s\)", ")", message)


def test_the_clock_does_not_change_the_starts(monkeypatch):
    """Where the time limit is not reached, a machine five times slower (the
    deadlines' clock run five times faster) does the same work: the same
    starts, sweep counts, errors and polish, the same reactions bit for bit.
    Before, the first start's Newton polish ran for as long as its sweeps
    took, so its last iterate — and with it every later start's scale —
    moved with the machine's speed."""
    from qpcontact.core import deadline

    p = sphere_pile(300, seed=2, agitation=0.1, polydispersity=0.005).problem
    opts = dict(accuracy=1e-12, starts=3, time_limit=3000)
    here = qpcontact.solve(p, "nsgs-restarts", **opts)
    monkeypatch.setattr(deadline, "time", _SlowClock(5.0))
    slow = qpcontact.solve(p, "nsgs-restarts", **opts)
    assert "start 2:" in here.message and "then Newton" in here.message, here.message
    assert _starts_without_seconds(slow.message) == _starts_without_seconds(here.message)
    assert np.array_equal(slow.r, here.r)


def test_a_start_cut_short_by_the_clock_is_the_last():
    """A start the time limit ends is the last one: a later start would be
    drawn at the scale of a point the run without the limit never had."""
    p = sphere_pile(300, seed=2, agitation=0.1, polydispersity=0.005).problem
    s = qpcontact.solve(p, "nsgs-restarts", accuracy=1e-12, starts=20, time_limit=1.5)
    k = s.message.count("start ")
    assert not s.ok and 1 <= k < 20, s.message
    full = qpcontact.solve(p, "nsgs-restarts", accuracy=1e-12, starts=k - 1 or 1,
                           time_limit=3000) if k > 1 else None
    if full is not None:      # the starts before the cut one: the same work
        head = _starts_without_seconds(full.message).split(": ", 1)[1]
        assert head.split("; ")[:k - 1] == \
            _starts_without_seconds(s.message).split(": ", 1)[1].split("; ")[:k - 1]


def test_a_first_start_that_stalls_gives_the_long_trajectory_its_share():
    """The 540-contact compact pile of seed 8: nsgs-newton from zero stalls
    at 2.8e-4 and Newton from its point stops at 9.5e-5; one ω = 1 NSGS
    trajectory from zero, given as much time as that start took, certifies
    it (its error judged here by the natural map written out) — without a
    single random start."""
    p = sphere_pile(500, seed=8, agitation=0.1, polydispersity=0.005).problem
    s = qpcontact.solve(p, "nsgs-restarts", accuracy=1e-6, starts=1, time_limit=300)
    assert s.ok and "long NSGS" in s.message and "from 1 start:" in s.message, s.message
    assert _natural_map_here(p, s.r) <= 1e-6
