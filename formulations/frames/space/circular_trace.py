"""The increasing-load analysis of a space frame on Coulomb's circular cone.

Mechanics.  The frame's contact problem is holonomic (total displacements
from the unloaded frame, as the faceted cone's LCP): its answer at load
level p depends on p alone, not on the path, and between the loads where a
contact changes state (separated, closed, stick, slip) it moves smoothly —
on the circle not linearly, since a slipping contact's friction turns with
its slip.  So the path is followed by certified solves: every point is one
:func:`~.circular_cone.solve_circular` answer, checked from the data
(friction certificate and the frame's statics, refined on its states in
extended precision), and

* the path is sampled at SAMPLES loads up to p_max, or up to the rigid
  limit where the frame rests on its contacts alone;
* each change of state between two certified samples is located by
  bisection between certified answers, to EVENT (relative) — an event is a
  bracket [p_before, p_after] with both ends certified;
* the limit load is a bracket [p_lo, p_hi]: p_hi a rigid motion of the
  whole frame checked in rationals on the circles
  (:mod:`.circular_limit`), or a proof the friction solvers' answer carries
  (no equilibrium, checked from the data); p_lo the largest certified
  equilibrium below it, found by bisection.  Where the bracket stays wider
  than BRACKET — Coulomb's law is non-associated: a rigidly admissible
  load the path does not reach — the trace ends "bounded" (``bound`` set,
  ``limit`` None, as the polygons' trace) and says what is known: the last
  certified equilibrium, how the frame moves there, the proved bound.

A change of state that begins and ends between two samples is not seen;
the samples are dense enough for the frames tried (the table's slips
start at one load each) and their number is an option.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import warnings

from qpcontact.core.accuracy import resolve_accuracy
from qpcontact.core.errors import (InvalidOptionError, NoSolutionError, QpcontactError,
                                   SolverFailedError)

from ..mechanics.analysis_results import FrameEvent, FrameTrace
from ..mechanics.contact_lcp import to_nodes
from ..mechanics.equilibrium_checks import LargeDisplacementWarning, how_far
from ..mechanics.load_combinations import (constant_first, load_combination,
                                           trace_combinations)
from ..mechanics.loads import describe
from ..mechanics.no_equilibrium import motion_words
from ..mechanics.time_limits import out_of_time
from ..mechanics.tracing import BRACKET
from ..mechanics.member_forces import EXTENDED
from .circular_cone import (contact_data, contact_forces, from_polygon, on_states,
                            solve_either_cone)
from .circular_polish import margin, newton, start_rates
from .space_assembly import held
from .circular_limit import limit_bracket

#: certified solves along the path before its events are located
SAMPLES = 24
#: an event's bracket is narrowed to this relative width by bisection
EVENT = 1e-6
#: where the event margin's root is found, the bracket certified around it
ROOT = 1e-10


class CircularPath:
    """The sampled path: {p: result} of every certified solve, and where
    the plot's default range ends."""

    def __init__(self):
        self.results = {}
        self.top = 1.0

    def plot_range(self) -> float:
        return self.top


@dataclass
class CircularTrace(FrameTrace):
    """A :class:`~..mechanics.analysis_results.FrameTrace` on the circular
    cone: ``result_at(p)`` is a certified solve at p (answers the trace
    computed are reused) at the trace's ``accuracy``."""

    accuracy: object = "high"

    def result_at(self, p: float):
        p = float(p)
        known = self.trace.results.get(p)
        if known is not None:
            return known
        with warnings.catch_warnings():
            # how far the frame has moved is in the trace's message
            warnings.simplefilter("ignore", LargeDisplacementWarning)
            # no wall-time limit, as the trace's own solves, and no path
            # followed again from inside a path
            res = self.frame.solve(combination=self.combination_at(p), accuracy=self.accuracy,
                                   _built=self._built, time_limit=None, _on_path=True)
        res.p = p
        return res


def trace(frame, p_max=None, accuracy="high", *, constant=None, variable=None,
          samples: int = SAMPLES, _built=None, _deadline=None) -> CircularTrace:
    """The increasing-load analysis on the circular cone (module
    docstring): ``constant`` (default the case "constant"), then
    ``variable`` x p from 0 to ``p_max`` (None: to the frame's limit,
    where it rests on its contacts alone).  ``_deadline``: a solve's
    (:mod:`..mechanics.time_limits`) where it follows the path to its
    load, read before each of the path's solves (SolverFailedError once it
    has passed); the solves themselves run without a limit, so that the
    path does not depend on the machine's load (the friction solvers cut
    at 60 s on a loaded machine once ended the tower's path 5 % early, and
    a limit sends some of them to a child process).  A trace of its own
    has no deadline."""
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 2:
        raise InvalidOptionError(f"samples must be an integer >= 2; got {samples!r}")
    b = _built if _built is not None else frame.build()
    const, var = trace_combinations(b, constant, variable)
    ft = CircularTrace(breakpoints=np.zeros(0), states=[], intervals=[], events=[],
                       ended="", message="", ok=False, trace=CircularPath(), frame=frame,
                       _built=b, constant=const, variable=var, accuracy=accuracy)
    p_hi, proof, p_poly = limit_bracket(frame, b, const, var, 0.0)
    if p_max is None and p_hi is None:
        raise InvalidOptionError(
            "trace on the circular cone: give p_max — the frame is held by bilateral supports "
            "or springs (or no rigid-body limit was proved), so no limit ends the path by itself")
    top = p_max if p_hi is None or (p_max is not None and p_max < p_poly) else p_poly
    path = ft.trace
    path.top = float(top)

    _, tol = resolve_accuracy(accuracy)

    def at(p, full=False):
        """The certified answer at p, None where none is certified, or the
        NoSolutionError proving that none exists.  First by continuation:
        the active set on the circle from the nearest certified answer
        below p (its displacements, forces and states); then from the
        circumscribed polygon's exact answer; with ``full`` (the samples)
        then the whole solve, friction solvers included — not in the
        bisections, where it would cost 15 s a point on the 16-pad tower
        and rarely certify what the active set does not."""
        p = float(p)
        if p in path.results:
            return path.results[p]
        if _deadline is not None and _deadline.expired():
            raise SolverFailedError(f"the load path on the circle stopped at its time limit, "
                                    f"at p = {p:.10g}")
        combo = ft.combination_at(p)
        below = [q for q in path.results if q < p]
        res = None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", LargeDisplacementWarning)
            prob = frame.friction_problem(combination=combo, _built=b)
            if below:
                near = path.results[max(below)]
                res = on_states(frame, prob, b, combo, to_nodes(b, near._u), contact_forces(near),
                                [s.state for s in near.supports.values()],
                                "circular cone (continued from the path)", tol)
            if (res is None or not res.ok) and not full:
                # Lemke's answer alone: the polygon's load path from zero
                # (its "auto") costs seconds a point where it stops below p
                # — a six-legged table's twist — and the samples' whole
                # solves try it anyway
                res = from_polygon(frame, prob, b, combo, accuracy, tol, "lemke")
            if (res is None or not res.ok) and full:
                try:
                    # no wall-time limit: the path must not depend on how
                    # busy the machine is (the friction solvers cut at 60 s
                    # on a loaded machine ended the tower's path 5 % early)
                    res = frame.solve(combination=combo, accuracy=accuracy, _built=b,
                                      time_limit=None, _on_path=True)
                except NoSolutionError as exc:
                    return exc
                except QpcontactError:
                    return None
        if res is None:
            return None
        res.p = p
        if res.ok:
            path.results[p] = res
        return res if res.ok else None

    def branch(near, p):
        """The answer at p on ``near``'s states kept (Newton alone, no
        change of state): (its event margin, answer) or None."""
        combo = ft.combination_at(p)
        F, Hc, gap, flex, mu = contact_data(frame, b, combo)
        states = [s.state for s in near.supports.values()]
        r0 = contact_forces(near)
        u0 = to_nodes(b, near._u)          # the result's u is global
        lam = start_rates(u0, r0, Hc, gap, flex, states, held_t)
        out = newton(b, F, np.asarray(u0, EXTENDED), np.asarray(r0, EXTENDED), lam, Hc,
                     gap, flex, mu, states, held_t)
        if out is None:
            return None
        return margin(out, Hc, gap, flex, mu, states, held_t)

    held_t = [[held(frame, c, t) for t in (c.t1, c.t2)] for c in frame.contacts]

    grid = np.linspace(0.0, top, samples + 1)
    if p_hi is not None and (p_max is None or p_max >= p_poly):
        grid[-1] = top * (1.0 - 1e-3)       # the limit itself is bracketed below
    good = []
    stop = None
    for p in grid:
        r = at(p, full=True)
        if isinstance(r, NoSolutionError):
            stop = (float(p), r)
            break
        if r is None:
            stop = (float(p), None)
            break
        good.append(r)
    if not good:
        raise NoSolutionError(f"trace on the circular cone: no equilibrium is certified at p = 0 "
                              f"({stop[1] if stop and stop[1] else 'the solvers found none'})")
    # events: bisect every change of state between neighbouring samples
    runs = [[good[0].p, good[0].p, _key(good[0])]]
    events = []
    for r0, r1 in zip(good[:-1], good[1:]):
        while _key(r0) != _key(r1):
            lo, hi = _locate(at, branch, r0, r1, top)
            runs[-1][1] = lo.p
            events.append(FrameEvent(hi.p, {k: (v, _key(hi)[k]) for k, v in _key(lo).items()
                                            if v != _key(hi)[k]}, bracket=(lo.p, hi.p)))
            runs.append([hi.p, hi.p, _key(hi)])
            if hi is r1 or hi.p >= r1.p:
                break
            r0 = hi
        runs[-1][1] = r1.p
    last = good[-1]
    ended, limit_words = "p_max", ""
    if stop is not None or (p_hi is not None and (p_max is None or p_max >= p_poly)):
        ended, limit_words = _limit(frame, b, ft, at, last, stop, p_hi, proof, const, var)
        if ft.limit is not None or ft.bound is not None:
            runs[-1][1] = (ft.limit or ft.bound)[0]
    ft.intervals = [(a, b_) for a, b_, _ in runs]
    path.top = ft.intervals[-1][1]          # the plot ends at the last certified answer
    ft.events = events
    ft.breakpoints = np.array([ev.p for ev in events])

    def state_in(a, b_):
        """A certified answer inside (a, b_): one the path has, else the
        continuation's at the middle, else the whole solve there."""
        known = _inside(path, a, b_)
        if known is None:
            known = at(0.5 * (a + b_))
        if known is None or isinstance(known, NoSolutionError):
            known = ft.result_at(0.5 * (a + b_))
        return known

    ft.states = [state_in(a, b_) for a, b_ in ft.intervals]
    ft.ended = ended
    ft.ok = ended in ("p_max", "collapse")
    where = (f"{len(path.results)} certified solves on Coulomb's circular cone; events located "
             f"to {EVENT:g} of p")
    ft.message = (limit_words + "; " if limit_words else "") + where + \
        f"; {len(events)} change(s) of the working scheme"
    return ft


def solve_on_path(frame, p, method, accuracy, raise_on_failure, combination, _built,
                  options):
    """One combination on the frame's cone
    (:func:`.circular_cone.solve_either_cone`); on the circle, where "auto"
    certifies nothing, the equilibrium reached by following the load path
    to it — the constant loads, then the rest in proportion — as the trace
    does (a six-legged table pushed at a corner, at 99.9 % of its path's
    last certified load: the friction solvers' answer lifted five pads off,
    its certificate 7e-4, where the path's continuation certifies the
    equilibrium).  A path that collapses first raises its proof."""
    options = dict(options)
    on_path = options.pop("_on_path", False)     # a solve made along a path
    deadline = options.get("time_limit")
    failed = None
    try:
        res = solve_either_cone(frame, p, method, accuracy, False, combination, _built, options)
    except SolverFailedError as exc:
        res, failed = None, exc
    # the path is followed where "auto" was asked with no option but the
    # time limit, and not from inside a path
    if ((res is not None and res.ok) or frame.cone != "circular" or method != "auto"
            or set(options) - {"time_limit"} or on_path):
        if res is None:
            raise failed
        if raise_on_failure and not res.ok:
            raise SolverFailedError(f"frame: {res.message}")
        return res
    b = _built if _built is not None else frame.build()
    combo = load_combination(frame, p, combination, b)
    path = constant_first(combo)
    found = None
    if path is not None:
        const, var, target, _ = path
        try:
            ft = trace(frame, target, accuracy, constant=const, variable=var,
                       _deadline=deadline)
        except QpcontactError:
            ft = None
        if ft is not None and ft.ended == "collapse" and ft.limit[1] <= target:
            # a proof at a load above the one asked says nothing about it
            raise NoSolutionError(f"frame under {describe(combo)}: along the load path (the constant "
                                  f"loads, then the rest in proportion) {ft.message}")
        if ft is not None:
            found = ft.trace.results.get(float(target))
            below = [q for q in ft.trace.results if q < target]
            if found is None and below and max(ft.trace.results) > target:
                # the path is certified on both sides: continued from below
                near = ft.trace.results[max(below)]
                prob = frame.friction_problem(combination=combo, _built=b)
                found = on_states(frame, prob, b, combo, to_nodes(b, near._u),
                                  contact_forces(near),
                                  [s_.state for s_ in near.supports.values()],
                                  "circular cone (continued from the path)",
                                  resolve_accuracy(accuracy)[1])
            if found is not None and not found.ok:
                found = None
    if found is not None:
        found.route = ("circular cone (the load path followed to it: the constant loads, "
                       "then the rest in proportion)")
        return found
    if deadline is not None:
        out_of_time(frame, combo, deadline, "the friction solvers certified no answer on the "
                    "circle, and the load path to it did not reach it in time")
    if res is None:
        raise failed
    if raise_on_failure:
        raise SolverFailedError(f"frame: {res.message}")
    return res


def _key(res) -> dict:
    return {k: s.state for k, s in res.supports.items()}


def _inside(path, a, b):
    """A certified answer of the path strictly inside (a, b), the one
    nearest the middle; None if there is none."""
    inside = [q for q in path.results if a < q < b]
    return path.results[min(inside, key=lambda q: abs(q - 0.5 * (a + b)))] if inside else None


def _locate(at, branch, r0, r1, top):
    """The certified answers just before and just after the first change of
    state after r0 (r1 has another state): the root of the event margin
    on r0's states (:func:`.circular_polish.margin`: the first of a
    sticking contact's f X_n − |X_t|, a closed one's X_n, a slipping one's
    λ, a separated one's opening to reach zero) by Illinois' regula falsi,
    then certified answers ROOT of p either side; failing that, bisection
    to EVENT."""
    ga = branch(r0, r0.p)
    gb = branch(r0, r1.p)
    if ga is not None and gb is not None and ga >= 0 > gb:
        a, b, side = r0.p, r1.p, 0
        for _ in range(60):
            c = b - gb * (b - a) / (gb - ga)
            if not a < c < b:
                c = 0.5 * (a + b)
            gc = branch(r0, c)
            if gc is None:
                break
            if gc >= 0:
                a, ga = c, gc
                if side == -1:
                    gb *= 0.5
                side = -1
            else:
                b, gb = c, gc
                if side == 1:
                    ga *= 0.5
                side = 1
            if b - a <= ROOT * max(abs(b), 1e-300):
                lo = at(a)
                if lo is None or isinstance(lo, NoSolutionError) or _key(lo) != _key(r0):
                    break
                # just past the root a new slip or opening is still below
                # what a state is named on: step on until it is
                for step in (1e-9, 1e-8, 1e-7, 1e-6):
                    p_hi = b + step * max(abs(b), 1e-300)
                    if p_hi >= r1.p:
                        break
                    hi = at(p_hi)
                    if hi is None or isinstance(hi, NoSolutionError):
                        break
                    if _key(hi) != _key(r0):
                        return lo, hi
                break
    return _bisect_event(at, r0, r1, top)


def _bisect_event(at, r0, r1, top):
    """The certified answers just before and just after a change of state
    between r0 and r1, EVENT apart (relative to the traced range) or as
    close as certified answers go."""
    lo, hi = r0, r1
    while hi.p - lo.p > EVENT * max(abs(top), abs(hi.p), 1e-300):
        mid = at(0.5 * (lo.p + hi.p))
        if mid is None or isinstance(mid, NoSolutionError):
            break
        if _key(mid) == _key(lo):
            lo = mid
        else:
            hi = mid
    return lo, hi


def _limit(frame, b, ft, at, last, stop, p_hi, proof, const, var):
    """(ended, words) at the path's end, ``ft.limit`` set where a limit is
    proved: bisection between the last certified answer and the proof."""
    lo = last
    bound, how = None, None
    if p_hi is not None:
        bound, how = p_hi, "rigid"
    if stop is not None and isinstance(stop[1], NoSolutionError) and (
            bound is None or stop[0] < bound):
        bound, how = stop[0], stop[1]
    if bound is None:
        p_fail = stop[0] if stop is not None else None
        return "breakdown", (f"no equilibrium is certified at p = {p_fail:.10g} and none is "
                        f"disproved; the last certified one is at p = {lo.p:.10g}")
    if how == "rigid":
        # the best case first: just below the proof, then bisection
        near = at(bound * (1.0 - 0.5 * BRACKET))
        if near is not None and not isinstance(near, NoSolutionError):
            lo = near
    hi, unknown = bound, None     # unknown: the lowest load where nothing was certified
    while True:
        top_ = hi if unknown is None else unknown
        if top_ - lo.p <= 0.25 * BRACKET * abs(top_):
            break
        p_mid = 0.5 * (lo.p + top_)
        mid = at(p_mid)
        if isinstance(mid, NoSolutionError):
            hi, how, unknown = p_mid, mid, None
        elif mid is None:
            unknown = p_mid
        else:
            lo = mid
    if hi - lo.p > 0.25 * BRACKET * abs(hi) and how == "rigid":
        # the proof may stand above where the path can go: try it again
        # from the last certified answer
        p2, proof2, _ = limit_bracket(frame, b, const, var, lo.p)
        if p2 is not None and p2 < hi:
            hi, proof = p2, proof2
    width = (hi - lo.p) / max(abs(hi), 1e-300)
    if width <= BRACKET:
        ft.limit = (float(lo.p), float(hi))
    else:
        ft.bound = (float(lo.p), float(hi))
    carrying = [k for k, v in lo.supports.items() if v.state != "separated"]
    if how == "rigid":
        words = motion_words(frame, proof["opening"], proof["sliding"], carrying) + \
            proof["turn"]
        proved = ("proved by a rigid motion of the whole frame in which the loads do positive "
                  "work and no contact force within Coulomb's circles resists, checked in "
                  "rational arithmetic")
    else:
        words, proved = str(how), "proved by the friction problem's certificate"
    far = how_far(frame, lo._u, always=True)[2]
    if width <= BRACKET:
        return "collapse", (f"no equilibrium exists for p >= {hi:.12g} (the last one on the "
                            f"path is at p = {lo.p:.12g}, {width:.1e} below): {words} "
                            f"({proved}); just before it {far}")
    moving = [f"{k} ({v.state})" for k, v in lo.supports.items()]
    end = ("" if unknown is None else
           f"; the path ends there: nothing is certified from p = {unknown:.12g} on")
    return "bounded", (f"the last certified equilibrium on the path is at p = {lo.p:.12g}{end}; "
                    f"no equilibrium exists for p >= {hi:.12g} ({words}; {proved}); between "
                    f"them ({width:.1e} of p) none is certified and none is disproved — "
                    f"Coulomb's law is non-associated, so the path may end below what a rigid "
                    f"body could carry; at p = {lo.p:.6g} the supports are "
                    f"{', '.join(moving)} and {far}")
