"""Loads along a space member: point forces and moments, and distributed
loads — uniform or trapezoidal, over the whole member or part of it — in
global or member axes (the plane frame's options, :mod:`..mechanics.loads`,
with the third axis).

Derivation.  In member axes the 3-D element is three uncoupled problems:
the axial bar with bending in the x-y plane (u, v, θz: the plane element
itself), bending in the x-z plane (w, θy), and Saint-Venant torsion (θx).
A load is split along them:

* x-y: (qx, qy) and the moment mz — the plane element's load, whose
  consistent nodal loads :func:`..mechanics.loads.equivalent_nodal` gives
  (exact fixed-end forces for the Hermite cubics);
* x-z: the plane element again with its y read as z.  Its rotation θ' =
  dw/dx is -θy (a positive θy turns +z towards -x), so a moment my about y
  is -my on θ', and the nodal moments it gives act on θy with the opposite
  sign;
* torsion: a point torque mx at a goes to the ends as mx (1 - a/L) and
  mx a/L (the twist is linear between the ends: its shape functions).

The internal forces at a section add the loads on [0, x) to the end
actions at i the same way (:mod:`.space_diagrams`): the x-y plane's sums
give N, Vy and Mz, the x-z plane's Vz and My, the torques T.  Units: forces
per unit length, forces and moments, positions in length from node i.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from ..mechanics.loads import MemberLoad, equivalent_nodal, offset_parts, section_sums


@dataclass(frozen=True)
class SpanLoad:
    """A load on a space member: ``kind`` "point" (values fx, fy, fz, mx,
    my, mz at a = b) or "distributed" (values wx, wy, wz at a, then at b);
    ``axes`` "global" or "member"; positions from node i."""

    member: str
    kind: str
    case: str
    axes: str
    a: float
    b: float
    values: tuple

    def whole_uniform(self, L: float) -> bool:
        """A uniform load over the whole member (the drawings' and the
        benchmarks' ``member_loads``)."""
        # L as the caller computed it: equal to the stored end to rounding
        return (self.kind == "distributed" and self.a == 0.0 and self.b >= L * (1 - 1e-12)
                and self.values[:3] == self.values[3:])


def position(L: float, a, what: str, relative: bool, member: str) -> float:
    """A position along a member of length L, from node i (a fraction of L
    with ``relative``); an error naming it when it lies outside."""
    from ..mechanics.loads import number

    a = number(a, f"member {member}: {what}") * (L if relative else 1.0)
    if not -1e-12 * L <= a <= L * (1 + 1e-12):
        raise InvalidProblemError(
            f"member {member}: {what} = {a:g} lies outside the member (length {L:g}"
            + (", positions given as fractions with relative=True" if relative else "") + ")")
    return min(max(a, 0.0), L)


def in_member_axes(load: SpanLoad, R) -> np.ndarray:
    """The load's values with each vector in member axes: (6,) for a point
    load (force, moment), (6,) for a distributed one (w at a, w at b)."""
    v = np.asarray(load.values, float)
    if load.axes == "member":
        return v
    return np.r_[R @ v[:3], R @ v[3:]]


def plane_parts(load: SpanLoad, R):
    """(the x-y plane's load, the x-z plane's load, the point torque): two
    plane-element loads in member axes (module docstring) and mx (0 for a
    distributed load)."""
    v = in_member_axes(load, R)
    if load.kind == "point":
        xy = MemberLoad("point", load.case, "member", load.a, load.b, (v[0], v[1], v[5]))
        xz = MemberLoad("point", load.case, "member", load.a, load.b, (0.0, v[2], -v[4]))
        return xy, xz, float(v[3])
    xy = MemberLoad("distributed", load.case, "member", load.a, load.b,
                    (v[0], v[1], v[3], v[4]))
    xz = MemberLoad("distributed", load.case, "member", load.a, load.b,
                    (0.0, v[2], 0.0, v[5]))
    return xy, xz, 0.0


def fixed_end(load: SpanLoad, L: float, R, phi=(0.0, 0.0)) -> np.ndarray:
    """The load's equivalent nodal loads in member axes, 12 (u, v, w, θx,
    θy, θz at i then j): the exact fixed-end forces of the element —
    against each plane's own interpolation, the Timoshenko one where
    ``phi`` (shear along y, along z) is not 0."""
    xy, xz, mx = plane_parts(load, R)
    out = to_member(equivalent_nodal(xy, L, 1.0, 0.0, phi[0]),
                    equivalent_nodal(xz, L, 1.0, 0.0, phi[1]))
    out[[3, 9]] = mx * (1.0 - load.a / L), mx * load.a / L
    return out


def to_member(xy, xz) -> np.ndarray:
    """The two plane elements' end numbers (u, v, θ at i then j, 6 each) as
    the member's 12: the x-y plane's on (u, v, θz), the x-z plane's on (w,
    θy) with the rotation's sign reversed (its θ' = dw/dx is -θy)."""
    out = np.zeros(12)
    out[[0, 1, 5, 6, 7, 11]] = xy
    out[[2, 8]] = xz[[1, 4]]
    out[[4, 10]] = -xz[[2, 5]]
    return out


def offset_fixed_end(load: SpanLoad, L: float, R, phi, offsets):
    """A load on a member with rigid end zones of lengths ``offsets``, as
    the plane frame's :func:`..mechanics.loads.offset_parts` in each plane:
    (the consistent loads of the part on the flexible length, on its own
    end dofs; the parts on the rigid zones moved statically to their
    nodes), both 12 in member axes.  A point torque on the flexible length
    goes to its ends linearly, on a rigid zone to the zone's node."""
    xy, xz, mx = plane_parts(load, R)
    fe_xy, rigid_xy = offset_parts(xy, L, 1.0, 0.0, phi[0], offsets)
    fe_xz, rigid_xz = offset_parts(xz, L, 1.0, 0.0, phi[1], offsets)
    fe, rigid = to_member(fe_xy, fe_xz), to_member(rigid_xy, rigid_xz)
    if mx:
        oi, oj = offsets
        if load.a < oi:
            rigid[3] += mx
        elif load.a > L - oj:
            rigid[9] += mx
        else:
            s = (load.a - oi) / (L - oi - oj)
            fe[3] += mx * (1.0 - s)
            fe[9] += mx * s
    return fe, rigid


def offset_map(oi: float, oj: float) -> np.ndarray:
    """(12, 12): the nodes' displacements (member axes) to the flexible
    ends': a rigid arm oi e_x at i moves its end by θ × (oi e_x) = oi (0,
    θz, -θy), at j by -oj (0, θz, -θy)."""
    A = np.eye(12)
    A[1, 5], A[2, 4] = oi, -oi
    A[7, 11], A[8, 10] = -oj, oj
    return A


def split(loads, R) -> list:
    """[(x-y part, x-z part, point torque, its position, factor)] of
    (load, factor) pairs (:func:`plane_parts`), for :func:`section_terms`."""
    return [(*plane_parts(load, R), load.a if load.kind == "point" else None, factor)
            for load, factor in loads]


def section_terms(parts, x):
    """For sections at x: the loads (:func:`split`, each times its
    combination factor) on [0, x) summed as (Fx, Fy, Fz, the torques, the
    x-y plane's moment about the section, the x-z plane's) in member axes —
    a point load exactly at a section counts as left of it."""
    x = np.asarray(x, float)
    out = [np.zeros_like(x) for _ in range(6)]
    for xy, xz, mx, a, factor in parts:
        fx, fy, mo_xy = section_sums([xy], x, 1.0, 0.0)
        _, fz, mo_xz = section_sums([xz], x, 1.0, 0.0)
        tx = np.where(x >= a, mx, 0.0) if a is not None else np.zeros_like(x)
        for k, term in enumerate((fx, fy, fz, tx, mo_xy, mo_xz)):
            out[k] += factor * term
    return out


def load_points(loads) -> list:
    """Positions along the member where a diagram has a kink or a jump."""
    return sorted({p for load, _ in loads for p in (load.a, load.b)})
