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

    min ½ Δqᵀ M Δq  s.t.  g⁺ + Nᵀ Δq >= −TRIGGER/2   ⇔   Δq = M⁻¹ N λ,
    0 <= λ ⟂ (Nᵀ M⁻¹ N) λ + g⁺ + TRIGGER/2 >= 0,

an LCP over the rigid contacts of the step's broad phase (active or not: a
contact the step predicted open may close through the others' impulses)
whose gap g⁺ at the new positions is below ``NEAR`` (1 mm: those a
displacement could close), N their normals at the
new positions (translations only: rotation moves no centre), solved and
certified by qpcontact.solve.  The target is half the trigger's overlap
(5 µm), not the touch: a contact put back exactly at g = 0 with no normal
velocity was active or not in the next step by rounding (a warm-started and
a cold run of the same pile parted there).  Gaps between discs and to the shell are exact
at the new positions (the drift is their curvature); a lifter's gap is
advanced linearly (a flat face).  So a rigid contact of the broad phase never overlaps by more than the
trigger plus one step's drift, whatever the run's length (a contact the
broad phase's margin did not list cannot have closed within the step).

Energy.  The displacement changes the potential energy by m g Δy per disc:
a disc that drifted into the bottom of the shell sits lower than the
constraint allows, so putting it back raises P.  In a still drum that is
energy the discs never had — +0.29 J in 0.4 s of 40 elastic discs (1.7e-5
of m g R), enough to break the midpoint's exact K + P with e = 1 — so each
moved disc pays it from its own kinetic energy: its velocity and spin are
scaled by √(1 − m g Δy / K_i) (a factor 1 − O(1e-5) there), and K + P is what
the step left.  In a turning drum the wall drives the discs that touch it,
and a scaled velocity would be a slip against the wall that friction must
take back (measured: a disc held from rolling then slid at 14.3° instead of
16.8°): there the lift is booked with the positions' terms (``scheme``; the
drive restores the speed), as is any lift a disc at rest cannot pay.  The
step's books are computed with the step's own velocities either way, so
they close.

Which overlaps.  Drift grows by (h v)²/(2ρ) a step, micrometres: an
overlap deeper than ``DEEP`` (1 mm) is something else — a start state with
a disc inside a lifter (tests/formulations/drum2d/test_drum2d_speed.py's pile
has one, 9 cm deep: projecting it out in one step rearranged the pile) — and
is left to the contact law.  A contact that is opening (u_N⁺ > 0: an inelastic impact's
midpoint overlap (1 − e) h |u_N⁻|/2, a bounce) loses its overlap by itself;
the projection counts each contact's gap after ``OPENING`` (10) steps at its
normal velocity, g⁺ + 10 h max(u_N⁺, 0), so it moves only what would stay
overlapped (and Newton's rebound −e u_N⁻ is left exact for e >= 0.05 — below
that the overlap stays and is projected out: the rebound is then slower).
A persistent contact's u_N⁺ = e v² h/ρ (the drift's normal velocity, bounced)
lets its overlap reach about 10 e h² v²/ρ before it is put back (8 µm for
e = 0.2 at 1 m/s on a 1 m shell).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from qpcontact import solve
from qpcontact.core.problems import LCP

from .contacts import DISC, SHELL

__all__ = ["keep_gaps", "TRIGGER", "NEAR", "OPENING", "DEEP"]

#: the overlap [m] of a rigid contact at which the positions are projected
TRIGGER = 1e-5
#: rigid contacts with a gap [m] below this take part in the projection
NEAR = 1e-3
#: an overlap deeper than this [m] is no drift (a start state that puts a disc
#: into a lifter, an impact's): the projection leaves that contact alone
DEEP = 1e-3
#: an opening contact's overlap that its normal velocity clears within this
#: many steps is left to go by itself
OPENING = 10


def keep_gaps(c, rigid, q_old, q_new, v_new, discs, shell_radius, h, gravity, pay,
              accuracy="high"):
    """(positions, velocities, rest): the step's new centres ``q_new`` (n, 2)
    [m] projected so that the step's ``rigid`` contacts ``c`` do not stay
    overlapped (module docstring), and its generalized velocities ``v_new``
    (3n,), scaled per moved disc so that K + P is what the step left where
    ``pay`` (a still drum); ``rest`` [J] the potential energy added and not
    paid for.  ``q_old`` the step's start, for the lifters' linear gaps."""
    if not rigid.any():
        return q_new, v_new, 0.0
    radii, masses = discs.radii, discs.masses
    # an opening contact's overlap goes by itself: the gap it will have after
    # OPENING steps at its present normal velocity
    u_n = c.H[:, 0::2].T @ v_new + c.w[0::2]
    gap = (_gaps(c, q_old, q_new, radii, shell_radius, h)
           + OPENING * h * np.maximum(u_n, 0.0))
    # deeper than a drift can make: a start state or an impact's, not drift
    rigid = rigid & (gap > -DEEP)
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
    # to an overlap of half the trigger, not to 0: a contact put back exactly
    # at touch would be active or not by rounding in the next step
    sol = solve(LCP(0.5 * (W + W.T), gap[k] + 0.5 * TRIGGER), method="auto",
                accuracy=accuracy)
    if not sol.ok or sol.z is None:
        return q_new, v_new, 0.0      # an unproven projection is not applied
    dq = (minv * (N @ np.asarray(sol.z, float))).reshape(n, 2)
    lift = gravity * masses * dq[:, 1]
    if not pay:
        return q_new + dq, v_new, float(lift.sum())
    # the potential the move adds (or frees), paid from the disc's own kinetic
    # energy: its velocity and spin scaled by one factor
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
