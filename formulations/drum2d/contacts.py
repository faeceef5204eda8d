r"""Narrow phase and contact kinematics of the 2-D drum.

SI units: metres, m/s, rad/s, N·s (impulses).

Every contact k joins disc i to an *other* body — disc j, the shell, or a
lifter — with the unit normal n_k pointing from the other body into disc i (an
impulse r_N > 0 pushes i along +n) and the tangent t_k = ẑ × n_k = (−n_y, n_x).
Disc i's material point at the contact, c_i − r_i n, moves at
v_i + ω_i ẑ × (−r_i n) = v_i − r_i ω_i t; disc j's, c_j + r_j n, at
v_j + r_j ω_j t; a wall point p at V(p) = Ω ẑ × p.  The relative velocity in
the local frame (u_N, u_T) is therefore

    u_N = n · (v_i − v_j),           u_T = t · (v_i − v_j) − r_i ω_i − r_j ω_j

between discs, and u_N = n · v_i − n · V,  u_T = t · v_i − r_i ω_i − t · V
against a wall:  u = Hᵀ ν + w with ν = (vx, vy, ω) per disc, H's column pair of
contact k carrying (n, 0), (t, −r_i) on disc i and (−n, 0), (−t, −r_j) on disc
j, and w = −(n · V, t · V) (zero between discs).  The same H maps the local
impulse (r_N, r_T) to generalized impulses on the discs (the torque on i is
(−r_i n) × (r_N n + r_T t) = −r_i r_T ẑ): the virtual-work pairing that makes
W = Hᵀ M⁻¹ H symmetric.

Gaps [m]: between discs |c_i − c_j| − r_i − r_j; to the shell R − |c_i| − r_i
(normal −c_i/|c_i|, towards the axis); to a lifter, the distance from c_i to
the lifter's segment minus r_i + b (normal from the segment's nearest point).
Contacts are listed when the gap is at most the margin δ the stepper asks for.
The detection and H's arrays are formed in one compiled pass
(formulations.drum2d.contact_kernel).

Over a step h (the stepper's θ = 1: each centre moves along the chord h ν⁺,
the walls turn by Ω h) two of these first-order readings are not what the
step does, and both are taken over the step instead:

- *Stick is two material points moving together over the step.*  A wall
  point moves along its arc, by Rot(Ω h) p − p, not by h V(p); so w's
  tangential part is −t · (Rot(Ω h) − I) p / h, the wall's mean velocity
  along t.  At the shell the two differ by a factor sin(Ω h)/(Ω h) (1 − 6e-7
  at the drum's Ω h = 1.9e-3); along a lifter's radial face by the arc's
  centripetal part, Ω² h (p · e_r)/2 [m/s] (0.8 mm/s at 0.9 m, h = 2 ms), which
  a log carried in stick on a chord has too: read with V(p) it was slip, so a
  log stuck on a face crept out along it at that speed, and a log wedged
  between a face and the shell could stay stuck at both only by rolling into
  the face, which pumped its indeterminate force loop (the face's push and the
  shell's backward friction) to the cone (docs/dev-notes.md, "The lifter
  pocket's force loop").  w's normal part stays −n · V(p), the gap's exact
  rate: the shell's circle does not move along its normal however it turns.
- *The gap at the step's end to second order.*  ``bend`` [m] is what the gap
  after the step, taken along the start motion (centres at c + h v⁻, the
  walls turned by Ω h), exceeds its linear part g + h u_N⁻: a centre moving
  straight across the shell's curve closes on it by h² v_⊥²/(2ρ) (1.6 µm a 2
  ms step for a log carried at 0.9 m, five times its weight's overlap), two
  logs passing each other open by h² (t · Δv)²/(2|c_i − c_j|).  The springs'
  law (laws.py) reads the gap at the step's end as g + bend + h u_N⁺, so a
  carried log sits at its spring's overlap c F instead of deeper by the
  chord's drift.  Zero at step 0 (``find_contacts`` without a step).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .geometry import Discs, Shell

__all__ = ["Contacts", "find_contacts", "KINDS", "DISC", "SHELL", "LIFTER"]

#: contact kinds, the index in ``Contacts.kind``
KINDS = ("disc", "shell", "lifter")
#: ``Contacts.kind`` of a disc–disc contact
DISC = 0
#: ``Contacts.kind`` of a disc–shell contact
SHELL = 1
#: ``Contacts.kind`` of a disc–lifter contact
LIFTER = 2


@dataclass
class Contacts:
    """m contacts: disc ``i``, ``j`` (the other disc, −1 for a wall), ``kind``,
    ``normal`` (m, 2), ``gap`` (m,) [m], ``wall_point`` (m, 2) [m] (where the
    wall's velocity is taken; unused between discs), ``w`` (2m,) [m/s], ``H``
    (3n x 2m, sparse) and ``bend`` (m,) [m] (the gap's second-order part over
    the step; zeros without one) (module docstring)."""

    i: np.ndarray
    j: np.ndarray
    kind: np.ndarray
    normal: np.ndarray
    gap: np.ndarray
    wall_point: np.ndarray
    w: np.ndarray
    H: sp.csc_matrix
    pairs_checked: int = 0
    bend: np.ndarray | None = None

    @property
    def m(self) -> int:
        return self.i.size

    def subset(self, keep: np.ndarray) -> "Contacts":
        from .contact_kernel import keep_columns   # numba: imported where it runs

        keep = np.asarray(keep, bool)
        cols = np.repeat(2 * np.flatnonzero(keep), 2)
        cols[1::2] += 1
        ptr, idx, val = keep_columns(self.H.indptr, self.H.indices, self.H.data, keep)
        return Contacts(self.i[keep], self.j[keep], self.kind[keep], self.normal[keep],
                        self.gap[keep], self.wall_point[keep], self.w[cols],
                        sp.csc_matrix((val, idx, ptr), shape=(self.H.shape[0], cols.size)),
                        self.pairs_checked, None if self.bend is None else self.bend[keep])


def find_contacts(discs: Discs, shell: Shell, t: float, omega: float, margin: float,
                  positions: np.ndarray | None = None, step: float = 0.0,
                  velocities: np.ndarray | None = None) -> Contacts:
    """Every contact with gap <= ``margin`` [m] at time t [s], the shell turning
    at ``omega`` [rad/s]; over a ``step`` [s] (module docstring; 0: none) w's
    tangential part the walls' chord and ``bend`` the gaps' second-order
    remainder along the centres' ``velocities`` (n, 2) [m/s]."""
    from .contact_kernel import detect   # numba: imported where it runs

    pos = np.ascontiguousarray(discs.positions if positions is None else positions, float)
    inner, outer = shell.lifter_segments(t, omega)
    vel = np.zeros_like(pos) if velocities is None else np.ascontiguousarray(velocities, float)
    i, j, kind, normal, gap, wall_point, w, indptr, indices, data, checked, bend = detect(
        pos, np.asarray(discs.radii, float), float(margin), float(shell.radius),
        np.ascontiguousarray(inner, float), np.ascontiguousarray(outer, float),
        float(shell.lifter_half_width), float(omega), float(step), vel)
    H = sp.csc_matrix((data, indices, indptr), shape=(3 * discs.n, 2 * i.size))
    return Contacts(i, j, kind, normal, gap, wall_point, w, H, checked + discs.n
                    * (1 + shell.lifter_angles.size), bend)
