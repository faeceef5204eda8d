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

from dataclasses import dataclass, fields

import numpy as np

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


def relative_change(new, old, terms) -> float:
    """max over members of |new − old| on each one's own scale."""
    scale, diff = np.abs(new) + terms, np.abs(new - old)
    return float(np.divide(diff, scale, out=np.zeros_like(diff), where=scale > 0).max(initial=0))


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
        as a second-order trace at ``accuracy``."""
        return cls(**{f.name: getattr(ft, f.name) for f in fields(FrameTrace)},
                   accuracy=accuracy)

    def result_at(self, p: float):
        p = float(p)
        N, _ = axial_forces(self._built, FrameTrace.result_at(self, p))
        return self.frame.solve(combination=self.combination_at(p), accuracy=self.accuracy,
                                second_order=True, time_limit=None, _axial=N)
