"""A space member whose own loads make its axial force vary along it (a
column's self-weight, a point load along it): both bending planes under
N(x), each the plane beam-column of :mod:`..mechanics.varying_axial`.

The mechanics.  At this order the 3-D Euler–Bernoulli member is two plane
beam-columns under the same N(x) — the x-y plane with EIz on (v, θz), the
x-z plane with EIy on (w, θ' = dw/dx = −θy) — beside an axial bar and a
twist that N does not enter (:mod:`..mechanics.space_element`).  N(x) is
the plane element's, node to node: N̄ (the fixed point's mean of the end
forces) plus the statics of the loads' parts along the axis, which are the
x-y plane's part of each load (:func:`.space_member_loads.plane_parts`: its
x component), the same in both planes; so is each rigid end zone's P-Δ,
θ ∫_zone N dx.  Each plane is then :class:`..mechanics.varying_axial.Member`
with its own EI, its end releases the member's about that plane's axis
(with a shear area, Engesser's beam-column under N(x), its own G A_s).
Used where N varies, as the plane path.
"""

from __future__ import annotations

import numpy as np

from ..mechanics.beam_column import across, flexible_part
from ..mechanics.space_element import axes as member_axes
from ..mechanics.varying_axial import Member, along_axis
from .space_member_loads import plane_parts

#: each bending plane: (its second moment, its (translation, rotation) rows
#: at i then j in the member's 12, their signs in the plane's (v, θ') — θ'
#: = −θy across z), as :func:`.space_assembly.beam_column_loads` has them
PLANES = (("Iz", (1, 5, 7, 11), (1.0, 1.0, 1.0, 1.0)),
          ("Iy", (2, 4, 8, 10), (1.0, -1.0, 1.0, -1.0)))


class BothPlanes:
    """A space member's two plane chains under N(x) (module docstring):
    ``planes`` [x-y's, x-z's] (:class:`..mechanics.varying_axial.Member`),
    ``springs`` per plane (i, j): a released end's spring (0: a hinge),
    None where rigidly joined."""

    def __init__(self, planes, springs):
        self.planes, self.springs = planes, springs

    def least(self) -> float:
        """The least N(x) on the member (the same in both planes)."""
        return self.planes[0].least()

    def own_negatives(self, springs=None) -> int:
        """Both planes' negative eigenvalues with the member's nodes held
        (:meth:`..mechanics.varying_axial.Member.own_negatives`), each
        plane's ends on its own releases (``springs`` unread: a space
        member's differ by plane, and it keeps them)."""
        return sum(p.own_negatives(s) for p, s in zip(self.planes, self.springs))

    def arms(self) -> tuple[float, float]:
        """The rigid end zones' ∫ N dx (the same in both planes)."""
        return self.planes[0].arms()


def member_length(xi, xj) -> float:
    """A space member's node-to-node length, the one number every part of
    the frame takes (the assembly, the loads' positions, the chains under
    N(x), the diagrams): the norm along an array's axis summed in another
    order and was 1 ulp longer on ~6 % of inclined members, which cut a
    1e-16 m piece (stiffness ~1e25) into their N(x) chains."""
    return float(np.linalg.norm(xj - xi))


def geometry(frame, m):
    """(L, R): a space member's node-to-node length and its axes' rows."""
    xi, xj = frame.nodes[m["i"]], frame.nodes[m["j"]]
    return member_length(xi, xj), member_axes(xi, xj, m["ref"], m["roll"])[0]


def loads_on(frame, name):
    """The span loads of member ``name``, in the frame's order."""
    return [ld for ld in frame.span_loads if ld.member == name]


def of_member(m, loads, L, R, Nbar, along, series=True):
    """:class:`BothPlanes` of a space member ``m`` (its span loads ``loads``,
    node-to-node length L, axes R) under N̄ where its loads in the
    combination ``along`` have parts along its axis; None otherwise."""
    if not along:
        return None
    oi, oj = m["offsets"]
    parts = []
    for ld in loads:
        factor = along.get(ld.case)
        part = along_axis(plane_parts(ld, R)[0], L, 1.0, 0.0, oi, oj) if factor else None
        if part:
            parts.append(part[:-2] + tuple(factor * np.array(part[-2:]))
                         if part[0] == "distributed" else part[:2] + (factor * part[2],))
    if not parts:
        return None
    points = [x - oi for ld in loads for x in (ld.a, ld.b)]
    rel = dict(m["releases"])
    # one cut for both planes (a chain per plane cost its cuts and N(x)
    # table twice: a fifth of α_cr's time on a building), on the weaker's EI
    # and serving the other's
    EI = [m["E"] * m[I_] for I_, _, _ in PLANES]
    weak = int(EI[1] < EI[0])
    GAs = m["GAs"]
    first = Member(EI[weak], L - oi - oj, Nbar, parts, points, series, (oi, oj), GAs[weak],
                   (EI[1 - weak], GAs[1 - weak]))
    planes = [first, first.bent(EI[1 - weak], GAs[1 - weak], series)]
    return BothPlanes(planes[::-1] if weak else planes,
                      [(rel.get(rows[1]), rel.get(rows[1] + 6)) for _, rows, _ in PLANES])


def member_under(frame, name, Nbar, along):
    """:func:`of_member` of the space frame's member ``name`` (the frame's
    kind's hook, :mod:`..mechanics.frame_kind`)."""
    m = frame.members[name]
    loads = loads_on(frame, name) if along else []
    if not loads:
        return None
    return of_member(m, loads, *geometry(frame, m), Nbar, along)


def plane_loads(loads, R, plane, L, offsets, factors=None):
    """The parts across one bending plane (0: x-y, 1: x-z) of ``loads`` on
    the flexible length, in the plane's (v, θ') (:func:`..mechanics.
    beam_column.across`), each times its factor in ``factors`` ({case:
    factor}; None: as given)."""
    out = []
    for ld in loads:
        f = 1.0 if factors is None else factors.get(ld.case, 0.0)
        part = flexible_part(plane_parts(ld, R)[plane], L, 1.0, 0.0, *offsets) if f else None
        if part is not None:
            out.append(part[:-2] + tuple(f * np.array(part[-2:])))
    return out


def varying_members(frame, ms, L, R, axial, along, col, k_local, Fe) -> dict:
    """The Euler–Bernoulli space members whose loads in ``along`` have
    parts along their axes: each bending plane's block of ``k_local`` and
    rows of ``Fe`` (each case's loads) set to its chain's under N(x)
    (N̄ = ``axial``), as :func:`..mechanics.plane_element.varying_members`
    does for a plane member; {index: (zone i's ∫ N dx, zone j's)}."""
    names = list(frame.members)
    by_member = {}
    for ld in frame.span_loads:
        by_member.setdefault(ld.member, []).append(ld)
    members = {}
    for k, name in enumerate(names):
        loads = by_member.get(name)
        if loads:
            both = of_member(ms[k], loads, L[k], R[k], axial[k], along, False)
            if both is not None:
                members[k] = both
    Member.in_one_pass([p for both in members.values() for p in both.planes])
    for k, both in members.items():
        loads = by_member[names[k]]
        for plane, ((_, rows, signs), member) in enumerate(zip(PLANES, both.planes)):
            S = np.asarray(signs)
            rows = list(rows)
            k_local[k][np.ix_(rows, rows)] = S[:, None] * member.stiffness() * S[None, :]
            Fe[k][rows] = 0.0
            for case, j in col.items():
                parts = plane_loads([ld for ld in loads if ld.case == case], R[k], plane,
                                    L[k], ms[k]["offsets"])
                if parts:
                    Fe[k][rows, j] = S * member.nodal_loads(parts)
    return {k: both.arms() for k, both in members.items()}


def plane_ends(di, dj, plane, offsets):
    """(v_i, θ_i, v_j, θ_j) of one bending plane (1: across y, 2: across
    z) at the flexible ends, and its nodes' rotations (θ_i, θ_j), from the
    nodes' displacements in member axes ``di``, ``dj`` (6 each) through
    the rigid arms."""
    turn, sign = ((5, 1.0), (4, -1.0))[plane - 1]
    oi, oj = offsets
    ti, tj = sign * di[turn], sign * dj[turn]
    return (di[plane] + oi * ti, ti, dj[plane] - oj * tj, tj), (ti, tj)


def varying_couples(frame, b, u, couples) -> np.ndarray:
    """``couples`` (:func:`..mechanics.second_order.pdelta_couples`, N̄ e_x
    × (u_j − u_i) per member, global) with those of the members whose
    stiffness took N(x) replaced by their own (the plane frame's
    :func:`..plane.member_diagrams.varying_couples`, in each bending
    plane): about local z the x-y plane's ∫ N v' node to node plus its
    nodal loads' turn less its span loads' moment, about −y the x-z
    plane's — N̄ (0, −Δw, Δv) in member axes where N is constant; ``u`` the
    global displacements."""
    along = b.get("along")
    if not along:
        return couples
    from ..mechanics.contact_lcp import factors
    from ..plane.member_diagrams import load_moment

    couples = np.array(couples, float)
    fe_all = b["local"][3] @ factors(b, along)
    items = list(frame.members.items())
    members = {k: both for k, (name, m) in enumerate(items)
               for loads in [loads_on(frame, name)] if loads
               for both in [of_member(m, loads, *geometry(frame, m), float(b["axial"][k]),
                                      along, False)] if both is not None}
    Member.in_one_pass([p for both in members.values() for p in both.planes])
    for k, both in members.items():
        name, m = items[k]
        loads = loads_on(frame, name)
        L, R = geometry(frame, m)
        di, dj = (np.r_[R @ u[b["idx"][n]:b["idx"][n] + 3], R @ u[b["idx"][n] + 3:b["idx"][n] + 6]]
                  for n in (m["i"], m["j"]))
        arm_i, arm_j = both.arms()
        local = np.zeros(3)
        for plane, ((_, rows, signs), member, springs) in enumerate(
                zip(PLANES, both.planes, both.springs), start=1):
            ends, (ti, tj) = plane_ends(di, dj, plane, m["offsets"])
            parts = plane_loads(loads, R, plane - 1, L, m["offsets"], along)
            added = member.axis(parts, ends, springs, np.array([member.L]))[2][0]
            fe = np.asarray(signs) * fe_all[k, list(rows)]
            turn = fe[1] + L * fe[2] + fe[3] - sum(
                along[ld.case] * load_moment(across(plane_parts(ld, R)[plane - 1], 1.0, 0.0))
                for ld in loads if along.get(ld.case))
            couple = added + arm_i * ti + arm_j * tj + turn
            local[3 - plane] += couple if plane == 1 else -couple
        couples[k] = R.T @ local
    return couples
