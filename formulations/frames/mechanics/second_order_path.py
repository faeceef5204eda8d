"""A second-order load path read between its ends: the frame's own
second-order answer at a load p, started from the path's point.

A second-order trace (:func:`.second_order_analysis.trace_second_order`)
is traced on one stiffness, K(N) with N the axial forces at its last
stable equilibrium; its pieces, events and limit are on that stiffness.
An answer read at p off that stiffness is not the frame's equilibrium at
p where the variable loads change the axial forces: a portal under wind,
whose windward column unloads as the leeward one loads, had its top sway
1.1e-3 and its joint rotation 9 % off the second-order answer at p, ok.
So :class:`SecondOrderTrace` answers ``result_at(p)`` by the fixed point of
the axial forces at p (``solve(second_order=True)``), started from the
axial forces of the path's point at p rather than from the first-order
answer's: near the path's stability limit the deformed frame has far,
unstable equilibria too (the linearised model's other branches), and
the first-order start led the 20-storey tower at p = 13.26, 4e-5 below its
limit, to one 35 m the other way (UNSTABLE), where the path's start
converges in three rounds to the path's own (3.93 m).

The axial forces of an answer (tension positive) [F]: EA/L times the
members' axial strain, less the mean of their member loads' axial
fixed-end parts (:func:`axial_forces`).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, fields

import numpy as np

from qpcontact.core.errors import QpcontactError

from .analysis_results import FrameTrace


def axial_forces(b, res) -> tuple[np.ndarray, np.ndarray]:
    """(N, scale): each member's axial force (tension positive; the mean
    of its ends' where member loads have an axial part, as a column's own
    weight does) in the answer ``res`` on the assembly ``b``, and the terms
    it is made of (EA/L (|u_i| + |u_j|) along the axis, the member loads'
    axial parts)."""
    from .contact_lcp import factors

    k, T, dofs, Fe = b["local"]
    j = dofs.shape[1] // 2                     # end j's axial dof: 3 (plane), 6 (space)
    d = (T @ np.asarray(res._u, float)[dofs][..., None])[..., 0]
    fe = Fe @ factors(b, res.combination)
    ea = k[:, j, j]
    N = ea * (d[:, j] - d[:, 0]) - 0.5 * (fe[:, j] - fe[:, 0])
    return N, ea * (np.abs(d[:, j]) + np.abs(d[:, 0])) + 0.5 * (np.abs(fe[:, j]) + np.abs(fe[:, 0]))


#: an axial force's scale keeps this share of EA/L (|u_i| + |u_j|) per
#: unit of the accuracy asked (:func:`member_scale`): its rounding's, N being
#: a difference of end displacements that carry the frame's rigid sway
ROUNDING = 1e6 * np.finfo(float).eps


def member_scale(frame, terms, tol) -> np.ndarray:
    """``terms`` (:func:`axial_forces`) as the scale its N converges on to
    ``tol``: at most the member's Euler load (what N changes in its
    stiffness) plus the share of them rounding needs.  Uncapped, a beam's
    ends swaying 0.19 m with the frame put EA/L (|u_i| + |u_j|) at 1.9e5
    kN: at "low" its N stopped 0.17 kN off (its Euler load 123 kN) and a
    portal at 0.98 of α_cr was ok with its columns' moments 7.6e-3 off."""
    from .second_order import pinned_buckling

    terms = np.asarray(terms, float)
    return np.minimum(terms, pinned_buckling(frame) + terms * min(1.0, ROUNDING / tol))


def relative_change(new, old, terms) -> float:
    """max over members of |new − old| on each one's own scale (|new| plus
    ``terms``: :func:`member_scale`'s)."""
    scale, diff = np.abs(new) + terms, np.abs(new - old)
    return float(np.divide(diff, scale, out=np.zeros_like(diff), where=scale > 0).max(initial=0))


def answer_change(frame, u, before) -> float:
    """How far the displacements ``u`` moved from the previous round's
    ``before`` (inf where there is none), translations and rotations each
    on their own largest."""
    if before is None:
        return np.inf
    from .equilibrium_checks import rotations

    spin = np.tile(rotations(frame.DOFS), len(u) // len(frame.DOFS))
    u = np.asarray(u, float)
    diff = np.abs(u - before)
    return max(float(diff[k].max(initial=0.0)) / (float(np.abs(u[k]).max(initial=0.0)) or 1.0)
               for k in (spin, ~spin))


@dataclass
class SecondOrderTrace(FrameTrace):
    """A second-order :class:`FrameTrace`: ``result_at(p)`` is the frame's
    own second-order answer at p at the trace's ``accuracy``, started from
    its path's axial forces there (module docstring), certified and judged
    as a solve is."""

    accuracy: object = "high"

    @classmethod
    def of(cls, ft: FrameTrace, accuracy) -> "SecondOrderTrace":
        """``ft``'s fields (a first-order trace's, or a circular cone's)
        as a second-order trace at ``accuracy``, its pieces cut at a
        stability limit and its states the frame's own answers at their
        middles.  Past the limit the path runs on through unstable pieces
        (no equilibrium the frame rests in: a column on three pads had a
        state at p = 46, ok, where none exists from p = 13.7 on, proved),
        and a state read off the end's stiffness is not the answer at its
        load (a portal's joint rotation 5 % off, ok)."""
        so = cls(**{f.name: getattr(ft, f.name) for f in fields(FrameTrace)},
                 accuracy=accuracy)
        if so.ended == "stability":
            end = so.limit[0]
            so.intervals = [(lo, min(hi, end)) for lo, hi in so.intervals if lo < end]
            so.events = [ev for ev in so.events if ev.p < end]
            so.breakpoints = np.array([ev.p for ev in so.events])
        so.states = [so.answer_at(0.5 * (lo + (hi if np.isfinite(hi) else lo + max(1.0, lo))),
                                  path_state)
                     for (lo, hi), path_state in zip(so.intervals, so.states)]
        return so

    def answer_at(self, p: float, path_state):
        """The frame's own answer at ``p``; where its solve gives none (a
        "breakdown" trace's piece past a member's buckling load: the
        stiffness singular there), the path's state there, not ok, saying
        why."""
        try:
            return self.result_at(p)
        except QpcontactError as exc:
            state = copy.copy(path_state)
            state.ok = False
            state.message = (f"NOT the frame's answer at p = {p:.10g}, whose second-order solve "
                             f"gives none ({exc}); the path's point on the stiffness of its "
                             f"end's axial forces: {state.message}")
            return state

    def result_at(self, p: float):
        p = float(p)
        if self.ended == "stability" and p == self.limit[0] and hasattr(self.trace, "z_at"):
            return self.at_limit()
        lo, hi = (self.intervals[0][0], self.intervals[-1][1]) if self.intervals else (0.0, 0.0)
        # outside the path (below a start above p = 0, first_standing's;
        # past its end), or on the circular cone's sampled path (no z_at:
        # AttributeError), the fixed point starts from the first-order answer
        N = (axial_forces(self._built, FrameTrace.result_at(self, p))[0]
             if lo <= p <= hi and hasattr(self.trace, "z_at") else None)
        return self.frame.solve(combination=self.combination_at(p), accuracy=self.accuracy,
                                second_order=True, time_limit=None, _axial=N)

    def at_limit(self):
        """The path's last stable equilibrium, at its stability limit: the
        one whose axial forces built the trace's stiffness (to its
        ``axial_error``), so the frame's own answer there.  A solve at that
        load sits on the limit, where its rounds need not settle: the
        20-storey tower's, from 1e-9 below it, "NOT CONVERGED" after 30
        rounds with its top 35 m the wrong way."""
        res = FrameTrace.result_at(self, self.limit[0])
        so = self.second_order
        res.second_order = {k: so[k] for k in ("rounds", "axial_error", "axial", "stable")}
        res.ok = bool(res.ok and self.ok)
        res.message = (f"{res.message}; second order: the trace's last stable equilibrium, at "
                       f"its stability limit, on the axial forces it agrees with to "
                       f"{so['axial_error']:.1e}" + ("" if self.ok else
                                                     " — NOT OK: the trace's own checks failed"))
        return res
