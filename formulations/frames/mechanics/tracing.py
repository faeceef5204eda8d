"""Osipova–Popov–Lovtsov's increasing-load analysis of a frame (``trace``),
shared by the plane and the space frame: the engine's parametric LCP trace,
each piece checked like a single solve, merged into the frame's working
schemes; and the load path to one load (:func:`trace_to`), the route "auto"
takes where Lemke's method at a fixed load proves nothing."""

from __future__ import annotations

import numpy as np

from qpcontact import solve as solve_problem
from qpcontact.core.errors import NoSolutionError, QpcontactError, SolverFailedError
from qpcontact.core.problems import ParametricLCP
from qpcontact.judge.lcp_certificate import certify_lcp

from . import contact_lcp, refinement
from .analysis_results import FrameEvent, FrameTrace
from .equilibrium_checks import how_far
from .farkas_rounding import beyond_rounding, collapse_rounding
from .joined_trace import RESTART, RESTARTS, JoinedTrace
from .load_combinations import combination_at, constant_first, trace_combinations
from .loads import VARIABLE, describe
from .no_equilibrium import motion_words
from .time_limits import seconds_left


def trace(frame, p_max: float | None = None, accuracy="high", *, constant: dict | None = None,
          variable=None, _built=None, _deadline=None, _from: float = 0.0) -> FrameTrace:
    """Osipova–Popov–Lovtsov's increasing-load analysis: the ``constant`` combination (default
    the case "constant"), then the ``variable`` loads (a case name or a
    combination; default the case "variable") scaled by p from 0 to
    ``p_max`` (None: until no support changes state again, or no
    equilibrium continues the path).

    Every piece of the path is checked like a single solve (LCP certificate
    and global equilibrium, at its start, middle and end); a piece that
    fails is not returned and the trace ends "breakdown".  Breakpoints where
    only the LCP's bookkeeping changes (a separated contact's slip changing
    sign) are merged: ``breakpoints`` are where a support changes state.
    ``_deadline``: a solve's (:mod:`.time_limits`), where it follows the
    path to its load; a trace of its own has none.  ``_from``: the path
    starts at that p, from the frame's own equilibrium there
    (:func:`frame_start`) — a second-order round on the end's stiffness,
    whose P-Δ terms without their loads stand nowhere near p = 0.
    """
    from qpcontact.core.accuracy import resolve_accuracy

    _, tol = resolve_accuracy(accuracy)
    b = _built if _built is not None else frame.build()
    const, var = trace_combinations(b, constant, variable)
    M, Q, q_gap, P, g, fric = contact_lcp.lcp_matrices(b)
    qc, _ = contact_lcp.combination_q(Q, q_gap, b, const)
    qv, _ = contact_lcp.combination_q(Q, np.zeros_like(q_gap), b, var)
    # followed to its end: solve's time_limit would bound the whole path,
    # and a frame's trace has no limit to raise (its probes keep their caps)
    # — unless a solve follows the path to its load within its own
    limit = (lambda: None) if _deadline is None else (lambda: seconds_left(_deadline))
    upto = np.inf if p_max is None else p_max
    first = ParametricLCP(M, qc + _from * qv, qv)
    try:
        if _from:
            start = frame_start(frame, b, combination_at(const, var, _from), accuracy, tol)
            if start is None:
                raise SolverFailedError(f"frame: no certified equilibrium at p = {_from:.10g} "
                                        "to start the load path from")
            tr = solve_problem(first, method="trace", accuracy=accuracy, p_max=upto - _from,
                               time_limit=limit(), start=start)
        else:
            tr = solve_problem(first, method="trace", accuracy=accuracy, p_max=upto,
                               time_limit=limit())
    except (NoSolutionError, SolverFailedError):
        # Lemke's point at p = 0 doubted for its digits (a degenerate basis:
        # rigid pads under a frame that rests on four legs) may still be the
        # frame's equilibrium: judged on the mechanics, it starts the path
        start = None if _from else judged_start(frame, b, const, accuracy, tol)
        if start is None:
            raise
        tr = solve_problem(first, method="trace", accuracy=accuracy,
                           p_max=upto, time_limit=limit(), start=start)
    tr = JoinedTrace(tr, _from)
    path = dict(M=M, qc=qc, qv=qv, const=const, var=var, upto=upto, accuracy=accuracy, tol=tol,
                limit=limit)
    follow(frame, b, tr, path)
    ft = FrameTrace(breakpoints=np.zeros(0), states=[], intervals=[], events=[],
                    ended=tr.end, message="", ok=False, trace=tr, frame=frame, _built=b,
                    constant=const, variable=var)
    runs = []        # [p_start, p_end, states]
    checked = 0      # pieces of tr checked so far
    while True:
        ended, failed, p_last = tr.end, None, None
        pieces = tr.pieces
        for k in range(checked, len(pieces)):
            piece = pieces[k]
            failed, p_last = check_piece(frame, b, ft, tr, piece, k == len(pieces) - 1, runs,
                                         tol)
            if failed is not None:
                ended = "breakdown"
                break
            checked = k + 1
        if failed is None:
            break
        # a piece that fails the frame's checks (its end computed on the
        # rounded LCP, a degenerate vertex the engine passed): the path
        # restarts just beyond its last certified point, as beyond a
        # degenerate vertex, from an equilibrium certified there
        if not restart(frame, b, tr, path, p_last, cut=True):
            break
        # the pieces before the restart are checked (the one cut at p_last
        # certified up to it): checking goes on with the new segment's
        checked = len(tr.pieces) - len(tr.last[1].pieces)
        follow(frame, b, tr, path)
    ft.intervals = [(r[0], r[1]) for r in runs]
    ft.events = [FrameEvent(r1[0], {k: (r0[2][k], r1[2][k]) for k in r1[2]
                                    if r0[2][k] != r1[2][k]})
                 for r0, r1 in zip(runs[:-1], runs[1:])]
    ft.breakpoints = np.array([ev.p for ev in ft.events])
    for lo, hi in ft.intervals:
        top = hi if np.isfinite(hi) else lo + max(1.0, lo)
        ft.states.append(ft.result_at(0.5 * (lo + top)))
    # where the path stops short of a proof, or ends in the LCP's Farkas
    # proof, the rigid-body proof (a frame resting on its contacts alone)
    # is tried just above the last certified equilibrium, and preferred
    # where its bracket is narrow enough: it is exact on the model as stored, while
    # the Farkas vector is checked on the LCP's data, whose R carries the
    # basic system's rounding (a table on soft pads: "no equilibrium for
    # p >= 26.66666663", 1.4e-9 below the load at which statics lets it
    # tip, 26.6666667)
    proved = (limit_proof(frame, b, ft, tr, fric)
              if ended not in ("p_max", "unbounded") else None)
    verge = None
    if ended == "collapse" and not proved and failed is None and not refinement.is_refined(b):
        # the engine's proof, from the load at which its margin clears the
        # rounding of the LCP's data (:mod:`.farkas_rounding`), or the words
        # for a load at the limit to rounding
        proof, verge = beyond_rounding(b, const, var, narrowed(path, tr, tol) or tr.proof)
    if proved:
        ended, failed = "collapse", None
        ft.message = proved
    elif failed is not None:
        piece, (p_bad, bad) = failed
        ft.message = (f"the piece from p = {piece.p_start:.10g} to {piece.p_end:.10g} failed "
                      f"the frame's checks at p = {p_bad:.10g} ({bad.message}); the trace "
                      f"stops at p = {ft.p_end:.10g}")
    elif ended == "collapse" and refinement.is_refined(b):
        # no proof about the frame, and no limit
        ended = "breakdown"
        ft.message = (f"the load path is certified up to p = {tr.p_end:.10g}; beyond it the "
                      f"contact LCP has no solution, but {refinement.no_farkas_proof(b)}; "
                      "nothing was proved beyond it")
    elif ended == "collapse" and verge:
        # the Farkas certificates' margin is within the data's rounding
        ended = "breakdown"
        ft.message = f"the load path is certified up to p = {tr.p_end:.10g}; beyond it {verge}"
    elif ended == "collapse":
        carrying = ([k for k, v in ft.states[-1].supports.items() if v.state != "separated"]
                    if ft.states else None)
        words = (frame.kind.collapse_words(frame, proof, fric, carrying)
                 if proof["farkas"] is not None
                 else "no combination of support states carries the load")
        how = ("a Farkas certificate" if proof["patterns"] == 1 else
               f"Farkas certificates for all {proof['patterns']} combinations of support "
               "states left after branching")
        bound = ("" if not np.isfinite(proof["z_bound"]) else
                 f" for openings and slips summing below {proof['z_bound']:.1e}")
        ft.limit = (float(tr.p_end), float(proof["p_limit"]))
        ft.message = (f"no equilibrium exists for p >= {proof['p_limit']:.10g} (the last one "
                      f"is at p = {tr.p_end:.10g}): {words} (proved by {how}, checked from "
                      f"the data{bound})")
    elif ended == "unbounded":
        ft.message = (f"no support changes state for p >= {tr.proof['from']:g}: the frame "
                      "carries any larger load in its last working scheme")
    elif ended == "p_max" and tr.last[0]:
        # the engine's words count p from its segment's start
        ft.message = f"traced to p = {tr.p_end:.10g}"
    else:
        ft.message = tr.message
    if ft.limit is not None:
        ft.bound = None
        if ft.intervals:
            # how far the frame has gone by then: a collapse load read off a
            # frame that sways metres is a small-displacement idealisation
            lo, hi = ft.intervals[-1]
            near = lo + (1.0 - 1e-3) * (hi - lo)
            far = how_far(frame, ft.result_at(near)._u, always=True)[2]
            ft.message += f"; just before it (p = {near:.6g}) {far}"
    if ft.bound is not None:
        # the path stops unproved below a proved rigid-body bound (Coulomb's
        # law is non-associated: the load path need not reach the load the
        # rigid body's statics allow): say exactly what is known
        ended = "bounded"
        lo, hi = ft.bound
        last = ft.result_at(lo)
        exhausted = exhausted_words(frame, b, ft, last, lo)
        ft.message = (f"the load path is certified up to p = {lo:.10g}, where "
                      f"{state_words(frame, last)}; {exhausted}"
                      f"no equilibrium exists for p >= {hi:.10g} ({(hi - lo) / abs(hi):.1e} "
                      f"above): {ft.bound_words} (proved by a rigid motion of the whole frame "
                      "checked in rational arithmetic); between them no equilibrium continuing "
                      "the path was found and none was proved impossible"
                      + ("" if exhausted else " — Coulomb's law is non-associated, so the path "
                         "may end below the rigid body's limit")
                      + f" (where the path stopped: {ft.message})")
    if tr.restarts:
        ft.message += (f"; restarted beyond degenerate vertices at p = "
                       + ", ".join(f"{p:.10g}" for p in tr.restarts)
                       + " (each from an equilibrium certified there, "
                       + ", ".join(f"{(p1 - p0) / max(abs(p0), 1.0):.0e}"
                                   for p0, p1 in tr.gaps)
                       + " of p before each not traced)")
    ft.ended = ended
    # a bound is not a limit: the path stopped unproved inside it (a fold
    # that the rigid body's bound then brackets was called ok)
    ft.ok = bool((tr.ok or ft.limit is not None) and failed is None
                 and ended not in ("bounded", "breakdown"))
    ft.message += f"; {len(ft.events)} change(s) of the working scheme"
    return ft



def follow(frame, b, tr, path) -> None:
    """Restart ``tr`` beyond each degenerate vertex where it stopped
    (joined_trace), while an equilibrium certified just beyond continues it."""
    while tr.end in ("breakdown", "fold") and len(tr.segments) <= RESTARTS:
        if not restart(frame, b, tr, path, tr.p_end):
            break


def restart(frame, b, tr, path, p_from, cut=False) -> bool:
    """Trace on from p_from (1 + RESTART) + RESTART, from Lemke's point
    there judged an equilibrium by the frame (its states refined); with
    ``cut`` the path so far is kept only up to p_from.  False where there
    is no such point or no trace from it."""
    if len(tr.segments) > RESTARTS:
        return False
    const, var = path["const"], path["var"]
    # just beyond, else a little further: Lemke at a fixed load can end on
    # a secondary ray right at the vertex and find the equilibrium a step on
    # (a pipe rack on inscribed polygons stopped at 43.29, though Lemke
    # certifies equilibria at 43.3 … 49: judged starts failed up to 1e-4
    # beyond the stop and held 1e-3 beyond; its limit is 50.09)
    for step in RESTART_STEPS:
        p_next = p_from * (1.0 + step) + step
        if p_next >= path["upto"]:
            return False
        at = combination_at(const, var, p_next)
        start = judged_start(frame, b, at, path["accuracy"], path["tol"])
        if start is None:
            continue
        try:
            more = solve_problem(ParametricLCP(path["M"], path["qc"] + p_next * path["qv"],
                                               path["qv"]),
                                 method="trace", accuracy=path["accuracy"],
                                 p_max=path["upto"] - p_next, time_limit=path["limit"](),
                                 start=start)
        except QpcontactError:
            continue
        if more.end in ("breakdown", "fold") and not more.pieces:
            # stopped where it started (another branch of the same vertex):
            # no further on, and a restart spent — the next step is tried
            # (a six-legged table tipping on soft pads used all its restarts
            # 1e-9 apart at 36.005 and stopped there)
            continue
        if cut:
            tr.cut(p_from)
        tr.add(p_next, more)
        return True
    return False


#: the relative steps beyond a stop at which the path restarts, in turn
RESTART_STEPS = (RESTART, 1e-6, 1e-4, 1e-3)


def check_piece(frame, b, ft, tr, piece, last, runs, tol):
    """Check one piece like a single solve (at its start, middle and end)
    and extend ``runs`` ([p_start, p_end, states]) with what passes;
    (None, None) where it all passes, else ((piece, (p, failing result)),
    the last certified p)."""
    hi = piece.p_end if np.isfinite(piece.p_end) else piece.p_start + max(1.0, piece.p_start)
    if tr.end == "collapse" and last:
        # at the collapse load itself the active block turns singular
        # and no digit of the state is guaranteed (the portal: condition
        # 6e14, forward error 2.9); its end is checked just inside,
        # the collapse by the trace's proof
        hi = piece.p_start + (1.0 - 1e-3) * (hi - piece.p_start)
    points = (piece.p_start, 0.5 * (piece.p_start + hi), hi)
    checks = [frame.kind.result_from_z(frame, piece.z(pp), ft.combination_at(pp), "trace",
                                       b=b, tol=tol)
              for pp in points]
    bad = [(pp, r) for pp, r in zip(points, checks) if not r.ok]
    if bad:
        p_last = runs[-1][1] if runs else piece.p_start
        if checks[0].ok:
            # the piece reaches past what its checks accept (a degenerate
            # vertex, or the frame's last equilibrium, computed on the
            # rounded LCP): the path is certified up to where they still
            # pass, found by bisection (p read off the path, not off the
            # result: a result names p only for the case "variable")
            p_last, last_ok = last_certified(frame, b, ft, piece, points, checks, tol)
            key = {k_: v.state for k_, v in last_ok.supports.items()}
            if p_last > piece.p_start and runs and runs[-1][2] == key:
                runs[-1][1] = p_last
            elif p_last > piece.p_start:
                runs.append([piece.p_start, p_last, key])
            p_last = max(p_last, piece.p_start)
        # the message names the piece, not the check point that failed
        return (piece, bad[0]), p_last
    key = {k_: v.state for k_, v in checks[1].supports.items()}
    if runs and runs[-1][2] == key:
        runs[-1][1] = piece.p_end
    else:
        runs.append([piece.p_start, piece.p_end, key])
    return None, None


def trace_to(frame, b, combo, lcp, accuracy, tol, deadline):
    """The equilibrium at ``combo`` found by following the load path to it
    — the route ``trace`` takes, which Lemke's method at a fixed load does
    not: near a collapse Lemke can end on a secondary ray (which proves
    nothing for a nonsymmetric M) where the trace still certifies an
    equilibrium (a 20-storey frame, 12 of 61 loads below its
    tipping load).  Paths tried: the Osipova–Popov–Lovtsov split (constant, then p x
    variable up to the requested p) when ``combo`` is one, then every
    load growing in proportion from the unloaded frame.  Returns (z,
    route words) certified on ``lcp`` itself, or None; raises
    NoSolutionError with the trace's proof when the path collapses
    before the requested load.  Within ``deadline`` (:mod:`.time_limits`):
    None once it has passed."""
    M, Q, q_gap, *_ = contact_lcp.lcp_matrices(b)
    first = constant_first(combo)
    paths = [] if first is None else [first]
    paths.append(({}, dict(combo), 1.0, "every load in proportion from zero"))
    found = engine_paths(frame, b, combo, lcp, accuracy, tol, M, Q, q_gap, paths, deadline)
    if found is not None or not paths[0][0] or deadline.expired():
        return found
    # the frame's own trace of the first path: it restarts beyond degenerate
    # vertices and beyond pieces that fail its checks, where the engine's
    # path stops (a pipe rack on six pads: Lemke ended on secondary rays at
    # 90 and 99 % of the limit that the frame's trace proved)
    const, var, target, words = paths[0]
    try:
        ft = trace(frame, target, accuracy, constant=const, variable=var, _deadline=deadline)
    except QpcontactError:
        return None
    if ft.ended == "p_max" and ft.ok:
        z = ft.trace.z_at(target)
        if certify_lcp(lcp, z).ok(tol):
            return z, f"trace ({words}, restarted; Lemke at the fixed load proved nothing)"
    return None


def engine_paths(frame, b, combo, lcp, accuracy, tol, M, Q, q_gap, paths, deadline):
    """:func:`trace_to` along each of ``paths`` by the engine's trace alone."""
    for const, var, target, words in paths:
        if deadline.expired():
            return None
        qc, _ = contact_lcp.combination_q(Q, q_gap, b, const)
        qv, _ = contact_lcp.combination_q(Q, np.zeros_like(q_gap), b, var)
        try:
            tr = solve_problem(ParametricLCP(M, qc, qv), method="trace", accuracy=accuracy,
                               p_max=target, time_limit=seconds_left(deadline))
        except NoSolutionError:
            continue        # no equilibrium to start this path from
        except QpcontactError:
            continue
        if tr.end == "collapse" and tr.proof["p_limit"] <= target:
            # (a path from zero has no limit load to name: its combination
            # alone cannot stand, and any motion proves it)
            rigid = rigid_words(frame, b, const, var, target) if const else None
            if rigid is not None:
                raise NoSolutionError(f"frame under {describe(combo)}: no equilibrium exists "
                                      f"— {rigid} (the load path, {words}, ends below it)")
            if refinement.is_refined(b):
                return None         # the certificates prove nothing about the frame
            if collapse_rounding(b, const, var, tr.proof) is not None:
                continue            # at the limit to rounding: nothing proved
            fric = contact_lcp.lcp_matrices(b)[5]
            how = (frame.kind.collapse_words(frame, tr.proof, fric, None)
                   if tr.proof["farkas"] is not None
                   else "no combination of support states carries the load")
            at = (f"p = {tr.proof['p_limit']:.10g}" if VARIABLE in var else
                  f"{tr.proof['p_limit']:.10g} x the combination")
            raise NoSolutionError(
                f"frame under {describe(combo)}: no equilibrium exists — {how} (along the "
                f"load path, {words}, none exists from {at} on: proved by Farkas "
                "certificates checked from the data)")
        if tr.end != "p_max":
            continue
        z = tr.z_at(target)
        if certify_lcp(lcp, z).ok(tol):
            return z, (f"trace ({words}; Lemke at the fixed load proved nothing, "
                       f"{len(tr.pieces)} pieces)")
    return None


#: a limit's bracket [p_lo, p_hi] is called the limit where its relative
#: width is at most this
BRACKET = 1e-6


def rigid_words(frame, b, const, var, target):
    """Where a rigid motion of the whole frame proves that no equilibrium
    exists at ``target`` x ``var`` on ``const``: how the frame moves in it
    and the proof, in words; else None.  Preferred to the words read off
    an engine's Farkas vector, which is not unique: on a tall table tipping
    about two legs the vector put the two lifting pads on their cones'
    boundary (opening = f x slip) and read "slides away"."""
    from .rigid_limit import limit_bracket

    try:
        p_hi, proof = limit_bracket(frame, b, const, var, 0.0)
    except QpcontactError:
        return None
    if proof is None or not p_hi <= target:
        return None
    words = motion_words(frame, proof["opening"], proof["sliding"], None) + proof["turn"]
    at = f"p = {p_hi:.10g}" if VARIABLE in var else f"{p_hi:.10g} x the combination"
    return (f"{words} (none exists from {at} on: proved by a rigid motion of the whole frame "
            "in which the loads do positive work and no contact force the friction polygons "
            "allow resists, checked in rational arithmetic)")


def limit_proof(frame, b, ft, tr, fric):
    """The message of a proved rigid-body limit just above the last
    certified equilibrium of the path (``ft.limit`` set), or None."""
    from .rigid_limit import limit_bracket

    p_lo = ft.p_end
    if not np.isfinite(p_lo):
        return None
    p_hi, proof = limit_bracket(frame, b, ft.constant, ft.variable, p_lo)
    if proof is None:
        return None
    carrying = ([k for k, v in ft.states[-1].supports.items() if v.state != "separated"]
                if ft.states else None)
    words = motion_words(frame, proof["opening"], proof["sliding"], carrying) + proof["turn"]
    width = (p_hi - p_lo) / max(abs(p_hi), 1e-300)
    if width > BRACKET:
        # not the limit, but a proved bound above the path's end
        ft.bound, ft.bound_words = (float(p_lo), float(p_hi)), words
        return None
    ft.limit = (float(p_lo), float(p_hi))
    return (f"no equilibrium exists for p >= {p_hi:.12g} (the last one on the path is at "
            f"p = {p_lo:.12g}, {width:.1e} below): {words} (proved by a rigid motion of the "
            f"whole frame in which the loads do positive work and no contact force the "
            f"friction polygons allow resists, checked in rational arithmetic)")


#: where the engine's collapse proof lies further above the path's end than
#: BRACKET, the proof is tried again at these fractions of BRACKET above it
NARROWER = (1.0, 0.5, 0.1)


def narrowed(path, tr, tol):
    """A collapse proof (:meth:`~qpcontact.proofs.parametric.LoadFamily.proof_at`)
    within BRACKET of the path's last equilibrium p_end where the engine's
    lies further out, or None.  Why: the engine proves a hair above p_end
    measured on the load's own scale (1e-9, 1e-6, 1e-4 of max(p, the p at
    which the variable load equals the constant one): a table's corner push
    against 40 kN of weight has unit 27, so its 1e-6 step is 2.7e-6 of p and
    its 1e-4 step 3.5e-4), and the bracket's width is that step; the same
    branch and bound a fraction of BRACKET of p above p_end proves it there
    (each leaf a Farkas vector checked from the data) — the last certified
    equilibrium is the lower end either way."""
    from qpcontact.proofs.parametric import LoadFamily

    p_end, p_limit = float(tr.p_end), float(tr.proof["p_limit"])
    if not (np.isfinite(p_end) and p_limit - p_end > BRACKET * abs(p_limit)):
        return None
    family = LoadFamily(ParametricLCP(path["M"], path["qc"], path["qv"]))
    try:
        z_end = tr.z_at(p_end)
    except QpcontactError:
        # a restart whose own path collapsed at its start: the state there
        # is the one it started from, the last piece's end before it
        last = tr.pieces[-1] if tr.pieces else None
        z_end = last.z(last.p_end) if last is not None else np.zeros(path["qc"].size)
    zeta, _ = family.values.at(z_end, family.q_terms(p_end))
    z_scale = max(float(np.abs(z_end).max(initial=0.0)), float(zeta.max(initial=0.0)), 1e-300)
    best = None
    for fraction in NARROWER:
        out = family.proof_at(p_end + fraction * BRACKET * abs(p_end), z_scale, tol)
        if out is None:
            break
        best = out
    return best


#: the path's last load and what friction carries under its normal forces
#: agree to this (relative) where the path stopped because friction was
#: exhausted there
EXHAUSTED = 1e-6


def exhausted_words(frame, b, ft, res, p) -> str:
    """Where the path's last load ``p`` is what the pads' friction carries
    under the normal forces of its last state ``res``
    (:func:`.friction_capacity.capacity`, set as ``ft.capacity``): words
    saying so, and why the rigid body's bound is out of the path's reach;
    else ""."""
    from .friction_capacity import capacity

    normals = [float(v.normal) for v in res.supports.values()]
    cap = capacity(frame, b, normals, ft.constant, ft.variable)
    if cap is None or not abs(cap - p) <= EXHAUSTED * max(abs(p), 1e-300):
        return ""
    ft.capacity = cap
    force = frame.units[0]
    shares = ", ".join(f"{k} {n:.4g}" for k, n in zip(res.supports, normals))
    return (f"there the friction of every carrying pad is exhausted under the normal forces "
            f"the frame gives them ({shares} {force}): held at those, the pads' friction "
            f"carries at most p = {cap:.10g} in the motions that keep them on the floor (an "
            "LP) — the frame starts to slide or turn, and only other normal forces, which its "
            "stiffness does not give the pads, would carry more (a pad slides without "
            "lifting: Coulomb's law is non-associated); ")


def state_words(frame, res) -> str:
    """How the frame stands in ``res``: which contacts slip (and along
    which direction), stick, or have lifted off."""
    by = {}
    for ci, (key, v) in enumerate(res.supports.items()):
        slip = np.atleast_1d(np.asarray(getattr(v, "slip", 0.0), float))
        if v.state.startswith("slip") and slip.size == 2 and np.any(slip):
            word = f"{key} slips {frame.kind.slide_words(frame, ci, slip)}"
            by.setdefault("slip", []).append(word)
        else:
            by.setdefault(v.state, []).append(str(key))
    names = {"separated": "lifted off", "closed": "closed", "stick": "stick"}
    parts = [", ".join(by.pop("slip"))] if "slip" in by else []
    parts += [f"{', '.join(v)} {names.get(k, k)}" for k, v in by.items()]
    return "; ".join(parts)


def judged_start(frame, b, const, accuracy, tol):
    """Lemke's point under the combination ``const`` where the frame's own
    checks (its states refined, judged on the mechanics) call it an
    equilibrium; else None."""
    M, Q, q_gap, *_ = contact_lcp.lcp_matrices(b)
    lcp = contact_lcp.combination_lcp(M, Q, q_gap, b, const)
    sol = solve_problem(lcp, method="lemke", accuracy=accuracy)
    if sol.z is None or not np.all(np.isfinite(sol.z)) or certify_lcp(lcp, sol.z).error > tol:
        return None
    res = frame.kind.result_from_z(frame, sol.z, const, "start", b=b, lcp=lcp, tol=tol)
    return np.maximum(sol.z, 0.0) if res.ok else None


def frame_start(frame, b, combo, accuracy, tol):
    """The contact LCP's z of the frame's own equilibrium under ``combo``
    — its active set's (plane frames), else Lemke's point — where the
    frame's checks certify it; else None."""
    if frame.kind.active_set is not None:
        found = frame.kind.active_set(frame, b, combo)
        if found is not None and frame.kind.result_from_z(frame, found[0], combo, "start", b=b,
                                                          tol=tol).ok:
            return np.maximum(found[0], 0.0)
    return judged_start(frame, b, combo, accuracy, tol)


def last_certified(frame, b, ft, piece, points, checks, tol):
    """(p, result) at the largest p of ``piece`` whose checks pass (to 1e-12
    of p), bisecting between its last passing check and its first failing
    one (``points``: where ``checks`` were made)."""
    good = max(i for i, r in enumerate(checks) if r.ok and all(c.ok for c in checks[:i + 1]))
    lo, hi, best = points[good], points[good + 1], checks[good]
    while hi - lo > 1e-12 * max(abs(hi), 1.0):
        mid = 0.5 * (lo + hi)
        r = frame.kind.result_from_z(frame, piece.z(mid), ft.combination_at(mid), "trace", b=b,
                                     tol=tol)
        lo, hi, best = (mid, hi, r) if r.ok else (lo, mid, best)
    return lo, best
