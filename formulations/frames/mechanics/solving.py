"""Solving a frame's contact problem, shared by the plane and the space
frame: one combination (:func:`solve`: the "auto" route, a named method, or
the Tresca fixed point), many (:func:`solve_combinations`).  What differs
between the kinds of frame (their results, their first route) comes from
``frame.kind`` (:class:`~.frame_kind.FrameKind`); when no equilibrium
exists, :mod:`.no_equilibrium` proves it and says how the frame fails (and
:mod:`..reporting.normal_hint` adds a word where the contacts' normals point
along the loads).  A frame without contacts is linear: one solve of the
basic system with no links (:func:`solve_linear_frame`), and a trace of one
interval (:func:`linear_trace`)."""

from __future__ import annotations

import warnings

import numpy as np

from qpcontact import solve as solve_problem
from qpcontact.core.deadline import Deadline, check_time_limit
from qpcontact.core.errors import (InvalidOptionError, InvalidProblemError, NoSolutionError,
                                   QpcontactError, SolverFailedError)
from qpcontact.core.options import check_options

from . import contact_lcp
from .farkas_rounding import judge_proof
from .analysis_results import CombinationResults, FrameTrace
from .equilibrium_checks import SMALL_DISPLACEMENT, SMALL_ROTATION, LargeDisplacementWarning
from .load_combinations import load_combination, trace_combinations
from .loads import CONSTANT, VARIABLE, describe
from .no_equilibrium import proved, raise_no_equilibrium, raise_rigid_motion
from .time_limits import TIME_LIMIT, deadline_of, out_of_time, seconds_left
from .tracing import trace_to
from .tresca import tresca_fixed_point
from ..reporting.normal_hint import normal_hint


#: seconds each QP backend may take inside a frame's "auto" route (Lemke's
#: proof comes first; a backend loop on a load the frame cannot carry took
#: 40 s in ProxQP before)
BACKEND_TIME_LIMIT = 10.0
#: the options "auto" and "active-set" take: Lemke's, which "auto" runs where
#: the active set finds no certified states (checked up front, so that a
#: misspelled name is refused even where the active set answers)
AUTO_OPTIONS = ("covering", "max_pivots", "restarts", "seed")


def solve(frame, p: float = 1.0, method: str = "auto", accuracy="high",
          raise_on_failure: bool | None = None, *, combination: dict | None = None,
          second_order: bool = False, _built=None, **options):
    """Analyse one load combination of ``frame``: ``combination`` = {case:
    factor}, or by default Osipova–Popov–Lovtsov's split constant +
    p·variable (``Frame.solve`` and ``SpaceFrame.solve`` call this).

    ``method``: "auto" (for a plane frame first the sparse active set,
    :mod:`..plane.sparse_active_set`,
    which never forms the dense contact LCP; where it finds no
    consistent states or its answer fails the checks, the LCP:
    frictionless and positive definite, the exact SPD method "bpp";
    otherwise Lemke, whose ray on a load the frame cannot carry comes
    with a Farkas vector checked from the data, then the QP backends
    with a time limit each), "active-set" alone, any registered LCP
    method or QP backend name (frictionless), "lemke", or "tresca" (with
    friction: a fixed point of convex QPs with Tresca bounds, stopped on
    the full LCP certificate; falls back to Lemke).

    ``second_order``: equilibrium on the deformed frame (P-Δ and P-δ,
    :func:`.second_order_analysis.solve_second_order`).

    A frame without contacts is linear: it is solved by one sparse LU of
    its stiffness (route "linear", whatever ``method`` names) and checked
    for equilibrium like any other answer (:func:`solve_linear_frame`).

    ``time_limit``: seconds of wall time for the whole analysis (default
    :data:`.time_limits.TIME_LIMIT`; None: no limit), shared by every route and proof
    after the active set; where it ends the analysis before an answer or a
    proof, SolverFailedError says so.  Other keywords are the method's
    options ("auto", "active-set": Lemke's, :data:`AUTO_OPTIONS`).

    ``raise_on_failure`` says what a load without a certified answer
    does.  By default (None) a proved "no equilibrium" raises
    NoSolutionError, saying how the frame fails, and a result whose checks
    fail comes back with ``ok`` False ("CHECK FAILED" in its message).
    With False nothing raises for the load itself: a proved "no
    equilibrium" comes back as a result with ``ok`` False, ``status``
    "infeasible" and ``proof`` (the words and the proof).  With True both
    raise (SolverFailedError for a failed check).  SolverFailedError is
    raised when no method found an equilibrium and nothing was proved, and
    InvalidProblemError/InvalidOptionError for misuse, whatever the flag.
    Warns (LargeDisplacementWarning) when the displacements
    leave small-displacement theory (``displacement_ratio``,
    ``max_rotation`` of the result).
    """
    # one deadline for the whole analysis (every round of a second-order one)
    options = dict(options, time_limit=Deadline(check_time_limit(
        options.get("time_limit", TIME_LIMIT))))
    if second_order:          # equilibrium on the deformed frame: its own rounds and checks
        from .second_order_analysis import solve_second_order

        return answered(frame, p, combination, None, raise_on_failure,
                        lambda: solve_second_order(frame, p, method, accuracy,
                                                   bool(check_raise(raise_on_failure)),
                                                   combination, options, _built))
    strict = bool(check_raise(raise_on_failure))
    # a kind's solve_one answers a frame without contacts linearly (unless_linear)
    res = answered(frame, p, combination, _built, raise_on_failure,
                   lambda: frame.kind.solve_one(frame, p, method, accuracy, strict,
                                                combination, _built, options))
    if res.proof:
        return res
    if res.ok and (res.displacement_ratio > SMALL_DISPLACEMENT
                   or res.max_rotation > SMALL_ROTATION):
        warnings.warn(f"frame under {describe(res.combination)}: {res.displacement_words}",
                      LargeDisplacementWarning, stacklevel=3)
    return res


def check_raise(raise_on_failure):
    if raise_on_failure not in (None, True, False):
        raise InvalidOptionError(f"raise_on_failure must be True, False or None; got "
                                 f"{raise_on_failure!r}")
    return raise_on_failure


def answered(frame, p, combination, _built, raise_on_failure, run):
    """``run()``, one combination's analysis; a proof that no equilibrium
    exists (NoSolutionError) gets the normals' hint where it applies and is
    raised, or with ``raise_on_failure=False`` returned as a result
    (:func:`infeasible`)."""
    try:
        return run()
    except NoSolutionError as exc:
        exc = with_normal_hint(frame, p, combination, _built, exc)
        if check_raise(raise_on_failure) is not False:
            raise exc from None
        return infeasible(frame, p, combination, exc)


def with_normal_hint(frame, p, combination, _built, exc):
    """The NoSolutionError, its message ending with what a contact's normal
    means where the normals point along the loads
    (:func:`..reporting.normal_hint.normal_hint`)."""
    try:
        b = _built if _built is not None else frame.build()
        hint = normal_hint(frame, b, load_combination(frame, p, combination, b))
    except QpcontactError:
        return exc
    return NoSolutionError(str(exc) + hint) if hint else exc


def hinted_trace(frame, run, constant, variable):
    """``run()``, a trace of ``frame``, with the normals' hint
    (:func:`..reporting.normal_hint.normal_hint`) on a path that ends in a
    proof that no equilibrium exists ("collapse", "bounded") or cannot
    start (NoSolutionError at p = 0), judged on the constant loads plus
    the variable ones."""
    def hint(b):
        const, var = trace_combinations(b, constant, variable)
        combo = dict(const)
        for case, f in var.items():
            combo[case] = combo.get(case, 0.0) + f
        return normal_hint(frame, b, combo)

    try:
        ft = run()
    except NoSolutionError as exc:
        try:
            words = hint(frame.build())
        except QpcontactError:
            raise exc from None
        if words:
            raise NoSolutionError(str(exc) + words) from None
        raise
    if ft.ended in ("collapse", "bounded"):
        ft.message += hint(ft._built if ft._built is not None else frame.build())
    return ft


def infeasible(frame, p, combination, exc):
    """The result of a load that no equilibrium carries, proved: ok False,
    ``proof`` and ``message`` the NoSolutionError's words, no fields."""
    combo = dict(combination) if isinstance(combination, dict) else {
        CONSTANT: 1.0, VARIABLE: float(p)}
    return frame.kind.result_type(
        p=float(combo.get(VARIABLE, 0.0)), supports={}, displacements={}, member_forces={},
        reactions={}, equilibrium_residual=float("nan"), lcp_error=float("nan"), route="",
        ok=False, message=str(exc), frame=frame, combination=combo, proof=str(exc))


def solve_linear_frame(frame, p, method, accuracy, raise_on_failure, combination, _built):
    """A frame without contacts: K u = F on its bilateral supports and
    springs, through the same basic system (with no links) and the same
    checked result as a contact problem's answer, route "linear".  A
    mechanism is refused in build (its message names the free motion)."""
    if not isinstance(method, str):
        raise InvalidOptionError(f"method must be a string; got {method!r}")
    from qpcontact import methods as registry
    from qpcontact.core.accuracy import resolve_accuracy

    if method not in frame.kind.routes + ("linear",) and method not in registry():
        raise InvalidOptionError(
            f"unknown method {method!r}: this frame has no contacts, so it is linear and "
            "method='auto' (or 'linear') solves it")
    _, tol = resolve_accuracy(accuracy)
    b = _built if _built is not None else frame.build()
    combo = load_combination(frame, p, combination, b)
    res = frame.kind.result_from_z(frame, np.zeros(0), combo, "linear", b=b, tol=tol)
    if raise_on_failure and not res.ok:
        raise SolverFailedError(f"frame: {res.message}")
    return res


def unless_linear(solve_one):
    """A kind's ``solve_one`` that answers a frame without contacts by
    :func:`solve_linear_frame`: what every caller of ``kind.solve_one``
    (solve, the second order) then gets for a linear frame."""
    def run(frame, p, method, accuracy, raise_on_failure, combination, _built, options):
        if not frame.contacts:
            check_auto_options(method, options)    # nothing reads them: not ignored silently
            return solve_linear_frame(frame, p, method, accuracy, raise_on_failure, combination,
                                      _built)
        return solve_one(frame, p, method, accuracy, raise_on_failure, combination, _built,
                         options)
    return run


class NoContactPath:
    """The load path of a frame without contacts: one working scheme for
    every p (no contact unknowns: z is empty), what
    :meth:`FrameTrace.result_at` reads."""

    ok = True
    restarts = ()

    def __init__(self, end: float = np.inf):
        self.end = end

    @staticmethod
    def z_at(p):
        return np.zeros(0)

    def plot_range(self) -> float:
        """The top of a plot's default range: the traced end, or 1 where
        the path is unbounded (the trace engine's with no breakpoint; a
        frame without contacts had no range to plot: AttributeError)."""
        return self.end if np.isfinite(self.end) and self.end > 0 else 1.0


def linear_trace(frame, p_max, accuracy, constant, variable, _built=None) -> FrameTrace:
    """The increasing-load analysis of a frame without contacts: nothing
    changes state, so there is one interval and no event; it ends "p_max"
    where ``p_max`` is given, else "unbounded" (a linear frame carries any
    load in small-displacement theory, and the message says that this is
    all the answer claims).  The middle state is checked as a solve is."""
    from qpcontact.core.accuracy import resolve_accuracy

    _, tol = resolve_accuracy(accuracy)
    b = _built if _built is not None else frame.build()
    const, var = trace_combinations(b, constant, variable)
    end = np.inf if p_max is None else float(p_max)
    ft = FrameTrace(breakpoints=np.zeros(0), states=[], intervals=[(0.0, end)], events=[],
                    ended="unbounded" if p_max is None else "p_max", message="", ok=False,
                    trace=NoContactPath(end), frame=frame, _built=b, constant=const,
                    variable=var)
    mid = 0.5 * (end if np.isfinite(end) else 1.0)
    state = frame.kind.result_from_z(frame, np.zeros(0), ft.combination_at(mid), "linear",
                                     b=b, tol=tol)
    ft.states = [state]
    ft.ok = bool(state.ok)
    reach = "up to p_max" if p_max is not None else "for every p >= 0"
    ft.message = (f"the frame has no contacts: it is linear, its response proportional to the "
                  f"load {reach}, with no limit in small-displacement theory (check "
                  f"result_at(p).displacement_ratio for where that theory stops describing "
                  f"it); {'' if state.ok else 'CHECK FAILED: '}{state.message}; "
                  "0 change(s) of the working scheme")
    return ft


def solve_lcp(frame, p, method, accuracy, raise_on_failure, combination, _built, options):
    """One combination solved on the contact LCP (the faceted cone for a
    space frame) by the frame's routes: :func:`solve` without its warning."""
    if not isinstance(method, str):
        raise InvalidOptionError(f"method must be a string; got {method!r}")
    from qpcontact import methods as registry
    from qpcontact.core.accuracy import resolve_accuracy

    _, tol = resolve_accuracy(accuracy)
    routes = frame.kind.routes
    if method not in routes and method not in registry():
        raise InvalidOptionError(
            f"unknown method {method!r}: {', '.join(repr(r) for r in routes)} or a name "
            f"from qpcontact.methods(): {', '.join(registry())}")
    options = dict(options)
    deadline = deadline_of(options)
    check_auto_options(method, options)
    b = _built if _built is not None else frame.build()
    combo = load_combination(frame, p, combination, b)
    if method in ("auto", "active-set") and frame.kind.active_set is not None:
        found = frame.kind.active_set(frame, b, combo)
        if found is not None:
            sets = f"{found[1]} state set" + ("s" if found[1] > 1 else "")
            res = frame.kind.result_from_z(frame, found[0], combo, f"active set ({sets})",
                                           b=b, tol=tol)
            if res.ok:
                return res
        if method == "active-set":
            raise SolverFailedError(
                "frame: the active set found no consistent contact states (a cycle or a "
                "singular state set); method='auto' goes on with the LCP (Lemke, the load "
                "path)")
    out_of_time(frame, combo, deadline, "the active set found no certified contact states"
                if method == "auto" else f"it ended before {method!r} started")
    M, Q, q_gap, P, g, fric = contact_lcp.lcp_matrices(b)
    lcp = contact_lcp.combination_lcp(M, Q, q_gap, b, combo)
    judged = None           # Lemke's point judged on the frame, where it was
    if method == "tresca":
        if not fric:
            raise InvalidOptionError("'tresca' is for frictional frames; this one has no friction")
        z, route = tresca_fixed_point(frame, b, lcp, P, g, fric, combo, tol, accuracy, options,
                                      deadline)
    else:
        if fric and method not in ("auto", "lemke"):
            raise InvalidOptionError(
                f"with friction the LCP is not symmetric; use method='lemke' or 'tresca', "
                f"not {method!r}")
        if method == "auto":
            sol = auto_lcp(lcp, fric, accuracy, options, deadline)
        else:
            sol = solve_problem(lcp, method=method, accuracy=accuracy,
                                time_limit=seconds_left(deadline), **options)
        # a proof exact on the LCP's rounded data but within their rounding
        # proves nothing about the frame (the load at its verge)
        judge_proof(sol, b, combo)
        z, route = sol.z, sol.method
        if not sol.ok and not proved(sol) and sol.z is not None and np.all(np.isfinite(sol.z)):
            # Lemke's point doubted for its digits only (a degenerate basis:
            # rigid pads, four legs — the same forces written with other
            # unknowns): the frame judges it on its own, its states refined in
            # extended precision and checked on the mechanics
            judged = frame.kind.result_from_z(frame, sol.z, combo, f"{sol.method} (judged on "
                                              "the frame)", b=b, lcp=lcp, tol=tol)
        if judged is not None and judged.ok:
            z, route = sol.z, judged.route
        elif not sol.ok:
            found = (trace_to(frame, b, combo, lcp, accuracy, tol, deadline)
                     if method == "auto" and not proved(sol) else None)
            if found is None:
                out_of_time(frame, combo, deadline, f"{sol.method}: {sol.message}; the load "
                            "path to it did not reach it in time")
                raise_no_equilibrium(frame, sol, fric, b, combo, hint=method != "auto")
            z, route = found
    if judged is not None and judged.ok and z is sol.z:
        res = judged     # the same point, route and data: not recovered and checked twice
    else:
        res = frame.kind.result_from_z(frame, z, combo, route, b=b, lcp=lcp, tol=tol)
    if not res.ok and method == "auto" and not route.startswith("trace"):
        # an LCP answer that is no equilibrium of the frame: the load path
        # may still reach one (a table on rigid frictional pads: Lemke's
        # faceted-cone answer rotated it freely by 3.5e9 m, rounding
        # spoiling its forces; the path from the unloaded table sticks)
        found = trace_to(frame, b, combo, lcp, accuracy, tol, deadline)
        if found is not None:
            again = frame.kind.result_from_z(frame, found[0], combo, found[1], b=b, lcp=lcp,
                                             tol=tol)
            res = again if again.ok else res
    if not res.ok and res.lcp_error <= tol:
        # the LCP's answer is no equilibrium of the frame: a contact matrix
        # singular to rounding (the frame is a mechanism once its contacts
        # open) solved at a point of huge openings
        raise_rigid_motion(frame, b, combo, f"{route}'s answer failed the statics check "
                                            f"({res.message})")
    if raise_on_failure and not res.ok:
        raise SolverFailedError(f"frame: {res.message}")
    return res


def check_auto_options(method, options) -> None:
    """InvalidOptionError for a keyword that "auto" or "active-set" would
    not read (Lemke's options and the call's time limit are read)."""
    given = {k: v for k, v in options.items() if k != "time_limit"}
    if given and method in ("auto", "active-set"):     # (nothing given: nothing to refuse)
        check_options(method, given, AUTO_OPTIONS)


def auto_lcp(lcp, fric, accuracy, options, deadline):
    """"auto" on the contact LCP: "bpp" where it is frictionless and
    positive definite; else Lemke, then (frictionless) the QP backends with a
    time limit each — all within ``deadline``."""
    if not fric and lcp.is_positive_definite:
        return solve_problem(lcp, method="bpp", accuracy=accuracy,
                             time_limit=seconds_left(deadline))
    sol = solve_problem(lcp, method="lemke", accuracy=accuracy,
                        time_limit=seconds_left(deadline), **options)
    if sol.ok or fric or proved(sol):
        return sol     # with friction, solve follows the load path where this is not ok
    best = sol
    for name in ("clarabel", "piqp", "osqp", "highs"):
        if deadline.expired():
            break
        try:
            s = solve_problem(lcp, method=name, accuracy=accuracy,
                              time_limit=seconds_left(deadline.within(BACKEND_TIME_LIMIT)))
        except QpcontactError:
            continue
        if s.ok or s.stats.get("proof") is not None:
            return s
        if s.error < best.error:
            best = s
    return best


def solve_combinations(frame, combinations: dict, **kw) -> CombinationResults:
    """Each named combination solved on its own — its own contact states,
    reactions and checks (no state carried over, never superposed).
    Values are {case: factor} dicts (or a number p for the split constant +
    p x variable).  A
    combination that cannot be carried gives a result with ok False and
    the reason; the others are kept.  Returns a CombinationResults."""
    if not isinstance(combinations, dict) or not combinations:
        raise InvalidProblemError("combinations: a non-empty dict {name: {case: factor}}")
    out = CombinationResults()
    # one assembly and one factorization of the basic system for all
    # combinations (and R, formed once if a combination needs the LCP);
    # to second order each combination builds its own K(N), its axial forces'
    if not kw.get("second_order"):
        kw["_built"] = frame.build()
    for name, combo in combinations.items():
        args = dict(kw)
        if isinstance(combo, dict):
            args["combination"] = combo
        else:
            args["p"] = combo
        args.setdefault("raise_on_failure", False)
        try:
            res = frame.solve(**args)
        except NoSolutionError as exc:
            res = infeasible(frame, args.get("p", 1.0), args.get("combination"), exc)
        except SolverFailedError as exc:
            res = frame.kind.result_type(
                p=float("nan"), supports={}, displacements={}, member_forces={}, reactions={},
                equilibrium_residual=float("nan"), lcp_error=float("nan"), route="", ok=False,
                message=str(exc), frame=frame,
                combination=combo if isinstance(combo, dict) else {})
        res.name = str(name)
        out[name] = res
    return out
