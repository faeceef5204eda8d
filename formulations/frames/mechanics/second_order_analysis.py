"""Second-order answers of a frame (plane or space) on its contacts: the fixed point of the
axial forces (:func:`solve_second_order`) and the second-order load path
(:func:`trace_second_order`); the elastic critical load factor α_cr is
:mod:`.critical_load`'s.  The members' second-order stiffness is
:mod:`.second_order`'s.

The fixed point.  The stiffness depends on the members' axial forces N,
which depend on the answer: N⁰ from the first-order answer, then for
k = 0, 1, …  solve the contact problem with K(N^k) (its own contact states,
certified as a first-order answer is, its statics on the deformed frame)
and read N^{k+1} off it, until every member's N^{k+1} agrees with N^k on
its own scale (|N| plus the terms EA/L |u_a| it is made of, those at
most its Euler load and the share rounding needs: a frame's rigid sway is
in u_a, :func:`.second_order_path.member_scale`) to the accuracy asked
for.  The answer returned is the last solve's, whose K was
built from N^k: ``second_order["axial_error"]`` says how far its own axial
forces are from those.  Axial forces move little with the sway (the
iteration contracts by about the sway's share of them), so a few rounds
do; where they do not converge the answer is not called ok.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as la

from qpcontact.core.errors import (InvalidOptionError, InvalidProblemError, NoSolutionError,
                                   QpcontactError, SolverFailedError)

from . import tracing
from .load_combinations import combination_at
from .loads import CONSTANT, VARIABLE
from .second_order_path import (SecondOrderTrace, answer_change, axial_forces, member_scale,
                                relative_change)
from .second_order import axial_change, bending, own_buckling, past_own_buckling
from .tracing import BRACKET
from .critical_load import critical_load_factor, stable_by_band  # noqa: F401 (imported from here)
from .tangent_stiffness import (DENSE_DOFS, band_counts, first_holding, first_negative,
                                held_links, negative_eigenvalues, reduced_tangent, restraint,
                                rounding_bracket)

#: rounds of the axial forces' fixed point at most
ROUNDS = 30


def solve_second_order(frame, p, method, accuracy, raise_on_failure, combination, options,
                       _built=None):
    """The second-order answer of one combination (:func:`frame.solve` with
    ``second_order=True``): the first-order answer's axial forces, then the
    fixed point described above, then the answer's stability with its
    contact states held (an equilibrium past which the tangent stiffness
    has a negative eigenvalue is one the frame cannot rest in: a table
    beyond its second-order tipping load balanced on one leg).  The result
    carries ``second_order``: {"rounds", "axial_error", "axial" (N per
    member), "stable" (None where the frame is too large to check, or where
    its tangent has an eigenvalue within rounding of zero inside α_cr's
    band: "STABILITY UNDECIDED", not ok)}."""
    import warnings

    from qpcontact.core.accuracy import resolve_accuracy

    from .equilibrium_checks import (SMALL_DISPLACEMENT, SMALL_ROTATION,
                                     LargeDisplacementWarning, how_far)
    from .loads import describe

    if _built is not None:
        raise InvalidOptionError("second_order=True builds its own stiffness; do not pass _built")
    _, tol = resolve_accuracy(accuracy)

    def solve_on(b):
        return frame.kind.solve_one(frame, p, method, accuracy, raise_on_failure, combination,
                                    b, options)

    N = options.pop("_axial", None)      # a trace's answer at p: from its path's axial forces
    if N is None:
        b = frame.build()
        N, _ = axial_forces(b, solve_on(b))
    # the member loads' axial parts in it make N vary along the members
    # (a plane frame's Euler–Bernoulli members take N(x) as it is)
    along = combination if combination is not None else {CONSTANT: 1.0, VARIABLE: float(p)}
    error, u = np.inf, None
    for rounds in range(1, ROUNDS + 1):
        b = built_on(frame, N, along)
        res = solve_on(b)
        N_new, terms = axial_forces(b, res)
        # converged in N and in the answer: near α_cr the answer moves by
        # N's change times 1/(1 − 1/α_cr) (a portal at 0.98 of it, N to
        # 1e-9, was 3.2e-9 off at "high")
        error = max(relative_change(N_new, N, member_scale(frame, terms, tol)),
                    answer_change(frame, res._u, u))
        if error <= tol:
            break
        N, u = N_new, res._u
    buckled = past_own_buckling(frame, b["axial"], b.get("along"))
    stable = False if buckled else None     # a member past its own buckling: no count needed
    undecided = False
    if stable is None and b["free"].size <= DENSE_DOFS:
        beyond, within = band_counts(
            reduced_tangent(b["K"], b, restraint(b, held_links(frame, b, res))))
        stable = beyond == 0
        if stable and within > 0:
            # an eigenvalue within rounding of zero: a member 1e8 times
            # stiffer than the column it tops left a heavy cantilever at
            # 1.015 of its critical load "stable" by the count beyond
            # rounding.  Stable only where α_cr's band lies above this load
            # (a beam 1e10 times stiffer than its columns in tension sits in
            # the band at zero load, its α_cr 4.6e6)
            stable, undecided = stable_by_band(frame, res)
    res.second_order = {"rounds": rounds, "axial_error": error,
                        "axial": dict(zip(frame.members, N)), "stable": stable}
    words = (f"second order (P-Δ and P-δ): the axial forces that built the stiffness agree "
             f"with the answer's, and its displacements with the previous round's, to "
             f"{error:.1e} after {rounds} round(s)")
    if error > tol:
        res.ok = False
        words += (f" — NOT CONVERGED (asked {tol:.0e}): the frame may be near its elastic "
                  "critical load (critical_load_factor)")
    if stable is False:
        res.ok = False
        words += (" — UNSTABLE: with its contact states held the frame's tangent stiffness "
                  "has a negative eigenvalue, so it cannot rest in this equilibrium (past a "
                  "tipping or buckling load of the deformed frame)" if not buckled else
                  f" — UNSTABLE: {buckled}")
    elif undecided:
        res.ok = False
        words += (" — STABILITY UNDECIDED: with its contact states held the frame's tangent "
                  "stiffness has an eigenvalue within rounding of zero (at its elastic critical "
                  "load to the digits the stiffness carries: critical_load_factor's bracket)")
    elif stable is None:
        words += f"; its stability was not checked (over {DENSE_DOFS} free dofs)"
    res.message = f"{res.message}; {words}"
    if raise_on_failure and not res.ok:
        from qpcontact.core.errors import SolverFailedError
        raise SolverFailedError(f"frame: {res.message}")
    if res.ok and (res.displacement_ratio > SMALL_DISPLACEMENT
                   or res.max_rotation > SMALL_ROTATION):
        warnings.warn(f"frame under {describe(res.combination)}: "
                      f"{how_far(frame, res._u, second_order=True)[2]}",
                      LargeDisplacementWarning, stacklevel=3)
    return res


def built_on(frame, N, along=None):
    """The frame's assembly on K(N).  Its first-order one stands (built
    first), so a basic system K(N) leaves singular is no mechanism: N puts
    the frame at its elastic critical load to rounding (a cantilever within
    1e-12 of π²EI/(4L²)).  ``along``: the combination whose member loads
    make N vary along the members (None: N constant along each).  That loss
    of stiffness is named, not the
    assembly's "node B is free: no member holds it", which sent the
    engineer to look for a missing member."""
    try:
        return frame.build(axial=N, along=along)
    except InvalidProblemError:
        # a member at or past its own buckling load (a shear-flexible one at
        # N = −G A_s exactly has no shear stiffness left: its stiffness is
        # not finite) is what makes K(N) singular there, not the frame's α_cr
        past = past_own_buckling(frame, N, along)
        if past:
            raise SolverFailedError(
                f"frame: the second-order stiffness is singular with the axial forces of this "
                f"load — UNSTABLE: {past} (a hair either side the answer says the "
                "same; critical_load_factor of a lighter combination says how far below "
                "it the frame buckles)") from None
        EI, L = bending(frame)
        t = -np.asarray(N, float) * L ** 2 / EI
        names = list(frame.members)
        words = ", ".join(f"{names[k]} N = {N[k]:.6g} {frame.units[0]} (-N L²/EI = {t[k]:.6g})"
                          for k in np.argsort(-t)[:3] if t[k] > 0)
        raise SolverFailedError(
            f"frame: the second-order stiffness is singular with the axial forces "
            f"{words or 'of this load'}: with every contact closed the frame is at its elastic "
            "critical load to rounding "
            "(α_cr = 1, it buckles there; P-Δ theory has no equilibrium at that load for one "
            "that sways it) — or its stiffness carries too few digits to tell (a member many "
            "orders of magnitude stiffer than those it joins: model a rigid zone as "
            "offset_i/offset_j).  Below it, critical_load_factor of a second-order solve says "
            "how far; above it the answer is UNSTABLE") from None


def trace_second_order(frame, p_max=None, accuracy="high", *, constant=None, variable=None,
                       **options):
    """The load path on the deformed frame, and where the frame stops
    following it.

    A frame's load path is traced on one stiffness (the path is piecewise
    linear in p, each piece and its end certified and proved as first-order
    ones are).  Here that stiffness is K(N), N the axial forces of the
    path's own last stable equilibrium: N⁰ those of the constant loads'
    second-order answer; trace; read N off the end; trace again on K(N¹);
    until the N that built K are the end's own to the accuracy asked for.

    Stability.  Inside a piece of the path the stiffness and the contact
    states are fixed, so each piece is stable (K with its contact states
    held has no negative eigenvalue) or not as a whole.  On the deformed
    frame the path may go on through unstable pieces (P-Δ makes K
    indefinite once pads lift: the linearised model's far branches), which
    the frame cannot follow: it stops at the start of the first unstable
    piece, the load at which it tips over or buckles (``ended``
    "stability", ``limit`` (p, p)).  Where the path itself ends on a stable
    piece whose pads' forces fall to zero and lifting them only closes them
    again under more load (a fold), that end is the stability limit too.

    Before its end the path is written with the end's axial forces;
    ``second_order["path_axial_change"]`` says how far the axial forces
    along it (at each piece's middle) are from them, as a share of each
    member's Euler load π²EI/L² (N(x) along a plane member whose
    variable loads have axial parts, at most: :func:`.second_order.axial_change`;
    result_at(p) solves at p on its own): zero where the variable loads do not
    change the axial forces (a push on a column under its weight), small
    where they redistribute them (wind on a tower: the windward columns'
    compression drops, the leeward's grows, the storey's total stays)."""
    from qpcontact.core.accuracy import resolve_accuracy

    from .load_combinations import trace_combinations

    _, tol = resolve_accuracy(accuracy)
    const, var = trace_combinations(frame.build(), constant, variable)
    # through the frame's solve: a start with no equilibrium raises as a
    # solve does, with the normals' hint
    start = frame.solve(accuracy=accuracy, combination=const, second_order=True)
    N = np.array([start.second_order["axial"][m] for m in frame.members], float)
    N_start = N.copy()
    error, ft, unstable, p_from, inside = np.inf, None, None, 0.0, None
    for rounds in range(1, ROUNDS + 1):
        # N(x) of the load the axial forces were read at: the constant
        # loads' first, then the path's last stable equilibrium's
        b = built_on(frame, N, combination_at(const, var, 0.0 if inside is None else inside))
        p_from = 0.0
        try:
            ft = frame.trace(p_max, accuracy, constant=const, variable=var, _built=b, **options)
        except (NoSolutionError, SolverFailedError) as exc:
            if inside is None:
                raise       # the constant loads' own stiffness: about the frame
            # on the end's stiffness at p = 0 the P-Δ terms of the end's
            # compression act without the loads that make it (a column's 200
            # kN, which also hold its footing down): that frame may stand
            # nowhere near p = 0 — nothing about the frame — and the path on
            # it starts where it stands
            p_from = (None if getattr(frame, "cone", None) == "circular"
                      else first_standing(frame, b, const, var, inside, accuracy, tol))
            if p_from is None:
                raise SolverFailedError(
                    f"frame: the second-order trace's round {rounds}, on the stiffness of the "
                    f"axial forces at p = {inside:.10g}, has no certified equilibrium to start "
                    f"from at p = 0 ({exc}) nor found one below that load; nothing was proved "
                    "about the frame, whose constant loads stand (solve(second_order=True))"
                ) from None
            ft = tracing.trace(frame, p_max, accuracy, constant=const, variable=var, _built=b,
                               _from=p_from)
        unstable = first_unstable_piece(frame, b, ft)
        p_last, inside = stable_end(ft, unstable)
        N_new, terms = axial_forces(b, ft.result_at(inside))
        error = relative_change(N_new, N, member_scale(frame, terms, tol))
        if error <= tol:
            break
        N = N_new
    b = ft._built
    # how far the path's axial forces are from N, as a share of each
    # member's Euler load π²EI/L² (what they change in its stiffness)
    EI, L = bending(frame)
    euler = np.pi ** 2 * EI / L ** 2
    # (N(x)'s where the stiffness took it and the variable loads have axial
    # parts: its mean's change and, at most, the rest's, axial_change)
    change = 0.0
    for lo, hi in ft.intervals:
        if lo >= p_last:
            break
        mid = ft.result_at(0.5 * (lo + min(hi, p_last)))
        N_mid, _ = axial_forces(b, mid)
        rest = axial_change(frame, mid.combination, b.get("along"))
        change = max(change, float(np.max((np.abs(N_mid - N) + rest) / euler, initial=0.0)))
    fold = None
    if unstable is None and ft.limit is None and p_last > 0 and b["free"].size <= DENSE_DOFS:
        fold = fold_at_end(frame, b, ft, inside, p_last,
                           held_links(frame, b, ft.result_at(inside)))
    # the stiffness is one for the whole path: where the variable loads
    # raise the compression, the path cannot be unbounded, and an end
    # past buckling makes every piece look unstable (a column under a
    # growing vertical load was "unbounded", ok; traced to 1.1 P_cr it
    # "stood up to p = 0")
    grows = b["free"].size <= DENSE_DOFS and start.ok and (
        (unstable is None and fold is None and ft.ended == "unbounded")
        or (unstable == 0 and p_last <= 0.0))
    buckle = buckling_along_path(frame, b, ft, N_start) if grows else None
    ft.second_order = {"rounds": rounds, "axial_error": error, "axial": dict(zip(frame.members, N)),
                       "path_axial_change": change,
                       "stable": None if b["free"].size > DENSE_DOFS else True}
    bound = f" (where the path itself ends, on the same stiffness: {ft.message})"
    if buckle is not None:
        p_cr, what = buckle
        ft.ended, ft.limit, ft.bound, ft.ok = "breakdown", None, None, False
        ft.message = ("the variable loads raise the members' compression along the path, which "
                      "one second-order stiffness for the whole path does not follow (it ended "
                      f"at p = {p_last:.10g}{bound}); with the axial forces growing as along "
                      f"the path {what} — solve(p, second_order=True) and its "
                      "critical_load_factor below that load")
    elif unstable is not None:
        changed = [ev for ev in ft.events if abs(ev.p - p_last) <= 1e-12 * max(abs(p_last), 1.0)]
        what = ("; ".join(f"{k}: {a} → {c}" for ev in changed for k, (a, c) in ev.changes.items())
                or "the working scheme changes")
        ft.ended, ft.limit, ft.bound, ft.ok = "stability", (p_last, p_last), None, True
        ft.message = (f"the deformed frame stands up to p = {p_last:.10g} and no further: there "
                      f"{what}, and beyond it the path's equilibria are unstable (with their "
                      "contact states held the deformed frame's tangent stiffness, P-Δ, has a "
                      "negative eigenvalue): it tips over or buckles at that load" + bound)
    elif fold is not None:
        one = len(fold) == 1
        they, them = ("it", "it") if one else ("they", "them")
        ft.ended, ft.limit, ft.bound, ft.ok = "stability", (p_last, p_last), None, True
        ft.message = (f"the deformed frame's load path ends at p = {p_last:.10g}, where "
                      f"{', '.join(fold)} carr{'ies' if one else 'y'} nothing: held, "
                      f"{they} would have to pull; lifted, more load closes {them} again (on "
                      "the deformed frame's stiffness, the other contacts as they are, du/dp "
                      f"opens {them} at a negative rate: that stiffness has a negative "
                      "eigenvalue) — no equilibrium continues the path beyond: it tips over "
                      "here (a fold; equilibria farther from the path are unstable)" + bound)
    if ft.ended == "bounded":
        # the bound's upper end is tracing's rigid-body proof: virtual work
        # with every member annihilating rigid motions, which K(N) does not
        ft.message += ("; that bound's upper end is the rigid body's limit on the undeformed "
                       "frame (first order): its proof does not hold on the deformed one, "
                       "where P-Δ lowers the limit")
    words = (f"second order (P-Δ and P-δ): the stiffness is built from the axial forces of the "
             f"path's last stable equilibrium (p = {p_last:.10g}), which they agree with to "
             f"{error:.1e} after {rounds} round(s); along the path the axial forces differ "
             f"from these by up to {change:.1e} of the members' Euler loads (N(x) along a "
             "member whose loads' axial parts vary it; result_at(p) solves at p on its own)")
    if p_from:
        words += (f"; on that stiffness the path starts at p = {p_from:.10g}, its first "
                  "certified equilibrium (below it the end's compression without its loads "
                  "stands nowhere: the constant loads' own second-order answer stands at p = 0)")
    if b["free"].size > DENSE_DOFS:
        words += f"; its stability was not checked (over {DENSE_DOFS} free dofs)"
    if error > tol:
        ft.ok = False
        words += f" — NOT CONVERGED (asked {tol:.0e})"
    ft.message = f"{ft.message}; {words}"
    return SecondOrderTrace.of(ft, accuracy)


#: the relative bracket to which :func:`first_standing` finds a path's start
START_BRACKET = 1e-6


def first_standing(frame, b, const, var, hi, accuracy, tol):
    """The smallest p (to START_BRACKET of ``hi``) at which the frame on the
    assembly ``b`` has a certified equilibrium (:func:`.tracing.frame_start`)
    under ``const`` + p ``var``, bisecting between p = 0 (none) and ``hi``
    (the previous round's end, where one is expected); None where ``hi``
    has none either."""
    def stands(p):
        try:
            return tracing.frame_start(frame, b, combination_at(const, var, p),
                                       accuracy, tol) is not None
        except QpcontactError:
            return False

    if not (hi > 0 and stands(hi)):
        return None
    return first_holding(stands, 0.0, hi, START_BRACKET)


def buckling_along_path(frame, b, ft, N_start):
    """(p_cr, words) where compression grows with p along ``ft`` (traced on
    ``b``): N(p) = N_start + p dN, N_start the constant loads' axial forces
    and dN their growth per unit p read at a point of the last piece; p_cr
    the smallest p at which the tangent stiffness K(N(p)), that piece's
    contact states held, has an eigenvalue within rounding of zero (the
    count's search and its rounding band's lower end, as α_cr's).  None
    where no member's compression grows."""
    lo, hi = ft.intervals[-1] if ft.intervals else (0.0, np.inf)
    p_read = hi if np.isfinite(hi) and hi > 0 else lo + max(1.0, lo)
    res = ft.result_at(p_read)
    N_read, terms = axial_forces(b, res)
    dN = (N_read - N_start) / p_read
    rounding = 1e-9 * (np.abs(N_read) + terms) / p_read
    if not np.any(dN < -rounding):
        return None
    held = restraint(b, held_links(frame, b, res))

    def negatives(p, within=False):
        return negative_eigenvalues(reduced_tangent(frame.stiffness(
            axial=N_start + p * dN, along=ft.combination_at(p)), b, held), within)

    growing = dN < -rounding
    own = (own_buckling(frame)[growing] + N_start[growing]) / -dN[growing]
    pole = float(own.min())
    if negatives(0.0):
        return 0.0, "the frame is unstable under the constant loads alone"
    top = first_negative(negatives, min(p_read, 0.5 * pole), pole)
    if top is None:
        worst = list(frame.members)[int(np.flatnonzero(growing)[np.argmin(own)])]
        return pole, (f"no sway buckles it before member {worst} buckles on its own "
                      f"(its nodes held) at p = {pole:.10g}")
    c = rounding_bracket(lambda p: negatives(p, within=True), top)   # critical_load_factor's end
    if c == 0.0:
        return 0.0, ("the frame's tangent stiffness (contact states held) has an eigenvalue "
                     f"within rounding of zero at every load up to p = {top:.10g}, where it "
                     "turns singular: its buckling load cannot be bounded from below (a "
                     "member many orders of magnitude stiffer than those it joins)")
    return c, (f"the frame buckles at p = {c:.10g} (its tangent stiffness, the contact "
               "states held, is within rounding of singular from there and singular at "
               f"p = {top:.10g})")


def first_unstable_piece(frame, b, ft):
    """The index of the first interval of ``ft`` (traced on ``b``'s
    second-order stiffness) whose equilibria (at its middle; stability is
    the same all along it) are unstable with their contact states held, or
    None (also where the frame is too large to check)."""
    if b["free"].size > DENSE_DOFS:
        return None
    if past_own_buckling(frame, b["axial"], b.get("along")):   # one stiffness for the round
        return 0 if ft.intervals else None
    for k, (lo, hi) in enumerate(ft.intervals):
        top = hi if np.isfinite(hi) else lo + max(1.0, lo)
        held = restraint(b, held_links(frame, b, ft.result_at(0.5 * (lo + top))))
        if negative_eigenvalues(reduced_tangent(b["K"], b, held)):
            return k
    return None


def stable_end(ft, unstable) -> tuple[float, float]:
    """(p, a point inside the last stable piece just before it): the start
    of the first unstable piece, else the path's last certified load."""
    if unstable is not None:
        p = float(ft.intervals[unstable][0])
        lo = float(ft.intervals[unstable - 1][0]) if unstable > 0 else 0.0
        return p, p - 1e-3 * (p - lo)
    p = last_equilibrium(ft)
    lo = float(ft.intervals[-1][0]) if ft.intervals else 0.0
    return p, (p - 1e-3 * (p - lo) if lo < p else p)


def last_equilibrium(ft) -> float:
    """The path's last certified load: a limit's or a bound's lower end,
    else the end of the traced range (p_max), else the last breakpoint
    beyond which nothing changes."""
    for pair in (ft.limit, ft.bound):
        if pair is not None:
            return float(pair[0])
    if ft.intervals:
        lo, hi = ft.intervals[-1]
        return float(hi if np.isfinite(hi) else lo)
    return 0.0


def fold_at_end(frame, b, ft, inside, p_last, held):
    """The contacts whose normal force falls to zero at the path's end
    ``p_last`` (from ``inside`` the last interval) where neither holding
    them nor releasing them continues the path: held, their normal force
    (linear in p in the last working scheme) turns to a pull; released,
    the frame's response to more load, du/dp = K⁻¹ F_variable on the
    deformed frame's stiffness with the other contacts held, closes them
    (their opening rate is negative: the frame with them lifted only
    stands at smaller loads — its tangent stiffness has a negative
    eigenvalue, which is checked too).  None where that is not so."""
    from .contact_lcp import load_vector

    before, end = ft.result_at(inside), ft.result_at(p_last)
    keys = list(end.supports)
    # a pad's force is linear in p along the last piece: where the path
    # stopped a hair before it reaches zero (a degenerate vertex: the pad
    # slipping at f N as N falls, its three reserves vanishing together),
    # it falls to zero within BRACKET of p_last
    rate = {k: (before.supports[k].normal - end.supports[k].normal) / max(p_last - inside, 1e-300)
            for k in keys}
    falling = [k for k in keys
               if rate[k] > 0 and (end.supports[k].normal <= 1e-9 * before.supports[k].normal
                                   or end.supports[k].normal / rate[k] <= BRACKET * abs(p_last))]
    if not falling:
        return None
    released = held.copy()
    lifting = np.zeros(held.size, bool)
    for i, (ci, kind) in enumerate(b["info"]):
        if keys[ci] in falling:
            released[i] = False
            lifting[i] = kind == "n"
    kept = restraint(b, released)
    Kr = reduced_tangent(b["K"], b, kept)
    if negative_eigenvalues(Kr) == 0:
        return None
    free = b["free"]
    dF = load_vector(b, ft.variable)[0][free]
    Z = kept[0]
    du = (la.solve(Kr, dF, assume_a="sym") if Z is None
          else Z @ la.solve(Kr, Z.T @ dF, assume_a="sym"))
    opening = b["H"][free][:, lifting].T @ du
    if not np.all(opening < 0):
        return None
    return falling
