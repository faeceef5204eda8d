r"""Rigid contacts keep their gaps: a position-only projection after the step.

SI units: m, kg, s.

Why.  The Moreau–Jean step holds a rigid contact at the velocity level
(0 <= r_N ⟂ u_N⁺ + e u_N⁻): nothing in it sees a gap that is already
negative.  A disc carried along the curved shell moves along the tangent in
each step and leaves the circle by about (h v)²/(2ρ) (ρ its centre's radius of
curvature); the next step holds u_N = 0 from there, so the overlap only
grows — 5.4 mm over a 98° carry at h = 2 ms, 0.25 mm for a disc rolling in the
shell for 14 s.  A gap term in the velocity law (u_N⁺ + g/h, Baumgarte or
Stewart–Trinkle style) would push the disc out with a velocity it keeps:
kinetic energy the drum never had.

What.  After the step, if a rigid contact of the step overlaps by more than
``TRIGGER`` (10 µm) at the new positions, the discs are moved by the smallest mass-weighted displacement that
opens every rigid contact of the step:

    min ½ Δqᵀ M Δq  s.t.  g⁺ + Nᵀ Δq >= 0   ⇔   Δq = M⁻¹ N λ,
    0 <= λ ⟂ (Nᵀ M⁻¹ N) λ + g⁺ >= 0,

an LCP over the rigid contacts of the step's broad phase (active or not: a
contact the step predicted open may close through the others' impulses)
whose gap g⁺ at the new positions is below ``NEAR`` (1 mm: those a
displacement could close), N their normals at the
new positions (translations only: rotation moves no centre), solved and
certified by qpcontact.solve.  Gaps between discs and to the shell are exact
at the new positions (the drift is their curvature); a lifter's gap is
advanced linearly (a flat face).  So a rigid contact of the broad phase never overlaps by more than the
trigger plus one step's drift, whatever the run's length (a contact the
broad phase's margin did not list cannot have closed within the step).

Energy.  The displacement changes the potential energy by m g Δy per disc:
a disc that drifted into the bottom of the shell sits lower than the
constraint allows, so putting it back raises P — energy the drum never had,
measured +0.29 J in 0.4 s of 40 elastic discs (1.7e-5 of m g R), enough to
break K + P's conservation with e = 1.  Each moved disc pays it from its own
kinetic energy: its velocity and spin are scaled by √(1 − m g Δy / K_i)
(a factor 1 − O(1e-5): relative velocities that were 0 stay 0 between
discs; against a moving wall a carried disc gains a slip of that order).
So K + P is what the step left, and the step's books (computed with the
step's own velocities) are unchanged.  Only a disc lifted with less kinetic
energy than m g Δy (from rest) cannot pay: the rest is booked with the
positions' terms (``scheme``).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from qpcontact import solve
from qpcontact.core.problems import LCP

from .contacts import DISC, SHELL

__all__ = ["keep_gaps", "TRIGGER", "NEAR"]

#: the overlap [m] of a rigid contact at which the positions are projected
TRIGGER = 1e-5
#: rigid contacts with a gap [m] below this take part in the projection
NEAR = 1e-3


def keep_gaps(c, rigid, q_old, q_new, v_new, discs, shell_radius, h, gravity,
              accuracy="high"):
    """(positions, velocities, rest): the step's new centres ``q_new`` (n, 2)
    [m] projected so that the step's ``rigid`` contacts ``c`` do not overlap,
    and its generalized velocities ``v_new`` (3n,) scaled per moved disc so
    that K + P is what the step left (module docstring); ``rest`` [J] the
    potential energy no kinetic energy could pay for (0 but for a disc lifted
    from rest).  ``q_old`` the step's start, for the lifters' linear gaps."""
    if not rigid.any():
        return q_new, v_new, 0.0
    radii, masses = discs.radii, discs.masses
    gap = _gaps(c, q_old, q_new, radii, shell_radius, h)
    if not np.any(rigid & (gap < -TRIGGER)):
        return q_new, v_new, 0.0
    k = np.flatnonzero(rigid & (gap < NEAR))
    i, j = c.i[k], c.j[k]
    normal = _normals(c, k, q_new)
    n = masses.size
    rows = np.concatenate([2 * i, 2 * i + 1])
    cols = np.concatenate([np.arange(k.size)] * 2)
    vals = np.concatenate([normal[:, 0], normal[:, 1]])
    pair = j >= 0
    rows = np.concatenate([rows, 2 * j[pair], 2 * j[pair] + 1])
    cols = np.concatenate([cols, np.flatnonzero(pair), np.flatnonzero(pair)])
    vals = np.concatenate([vals, -normal[pair, 0], -normal[pair, 1]])
    N = sp.csc_matrix((vals, (rows, cols)), shape=(2 * n, k.size))
    minv = np.repeat(1.0 / masses, 2)
    W = (N.T @ sp.diags(minv) @ N).tocsc()
    sol = solve(LCP(0.5 * (W + W.T), gap[k]), method="auto", accuracy=accuracy)
    if not sol.ok or sol.z is None:
        return q_new, v_new, 0.0      # an unproven projection is not applied
    dq = (minv * (N @ np.asarray(sol.z, float))).reshape(n, 2)
    # the potential the move adds (or frees), paid from the disc's own kinetic
    # energy: its velocity and spin scaled by one factor
    lift = gravity * masses * dq[:, 1]
    V = v_new.reshape(n, 3)
    kin = 0.5 * (masses * (V[:, 0] ** 2 + V[:, 1] ** 2)
                 + np.where(discs.spin_locked, 0.0, discs.inertias) * V[:, 2] ** 2)
    paid = np.minimum(lift, kin)
    scale = np.sqrt(np.divide(kin - paid, kin, out=np.ones(n), where=kin > 0))
    return q_new + dq, (V * scale[:, None]).ravel(), float((lift - paid).sum())


def _gaps(c, q_old, q_new, radii, R, h):
    disc, shell = c.kind == DISC, c.kind == SHELL
    i, j = c.i[disc], c.j[disc]
    gap = np.array(c.gap, float)
    gap[disc] = np.hypot(*(q_new[i] - q_new[j]).T) - radii[i] - radii[j]
    gap[shell] = R - np.hypot(*q_new[c.i[shell]].T) - radii[c.i[shell]]
    lift = ~(disc | shell)
    # a lifter's face: flat, moving with the wall's normal velocity −w_N
    gap[lift] += ((q_new - q_old)[c.i[lift]] * c.normal[lift]).sum(1) + h * c.w[0::2][lift]
    return gap


def _normals(c, k, q_new):
    normal = np.array(c.normal[k], float)
    kind, i, j = c.kind[k], c.i[k], c.j[k]
    disc, shell = kind == DISC, kind == SHELL
    d = q_new[i[disc]] - q_new[j[disc]]
    normal[disc] = d / np.hypot(*d.T)[:, None]
    p = q_new[i[shell]]
    normal[shell] = -p / np.hypot(*p.T)[:, None]
    return normal
