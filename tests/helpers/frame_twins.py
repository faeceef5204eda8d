"""Frames built twice — the same structure in two models whose answers must
agree: a member with rigid end zones and the same member cut at its faces
with the zones as stiff pieces (plane and space), and a space frame built
both in PyNite and here (the peer's own local axes as our reference
vectors, so both codes bend the same section about the same axes)."""

from __future__ import annotations

from formulations.frames import Frame, SpaceFrame

E, G = 2.1e8, 8.1e7                    # kN/m²
A, IY, IZ, J = 0.012, 3e-4, 8e-4, 1.2e-4
LS, OI, OJ = 4.0, 0.4, 0.7            # the member's length and its zones (m)


def space_zones(stiff):
    """(the member with rigid zones, the member cut with stiff zone pieces),
    rolled, a hinge about y at the j face, point forces and torques on the
    zones and the span, a partial trapezoid across all three pieces."""
    def base():
        fr = SpaceFrame()
        fr.add_node("A", 0.0, 0.0, 0.0)
        fr.add_node("B", LS, 0.0, 0.0)
        fr.add_support("A")
        fr.add_support("B", fix=("uz", "uy", "rx"))
        return fr

    one = base()
    one.add_member("A", "B", E, A, IY, IZ, G=G, J=J, name="M", roll=0.4, offset_i=OI, offset_j=OJ,
                   hinge_j=("ry",))
    one.add_distributed_load("M", wz=-6.0, wz2=-2.0, wy=1.0, start=0.1, end=3.9)
    cut = base()
    cut.add_node("P", OI, 0.0, 0.0)
    cut.add_node("Q", LS - OJ, 0.0, 0.0)
    for name, i, j, s, hinge in (("R1", "A", "P", stiff, False), ("F", "P", "Q", 1.0, ("ry",)),
                                 ("R2", "Q", "B", stiff, False)):
        cut.add_member(i, j, E, s * A, s * IY, s * IZ, G=G, J=s * J, name=name, roll=0.4,
                       hinge_j=hinge)
    pieces = {"R1": (0.0, OI), "F": (OI, LS - OJ), "R2": (LS - OJ, LS)}
    for a, kw in ((0.2, dict(fy=-5.0, mx=1.5)), (2.0, dict(fz=-8.0, my=2.0)),
                  (3.6, dict(fy=3.0, fz=2.0, mx=-0.8))):
        one.add_point_load("M", a, **kw)
        name = next(n for n, (lo, hi) in pieces.items() if lo <= a < hi)
        cut.add_point_load(name, a - pieces[name][0], **kw)
    for name, (lo, hi) in pieces.items():
        s, e = max(lo, 0.1), min(hi, 3.9)
        cut.add_distributed_load(name, wz=-6.0 + 4.0 * (s - 0.1) / 3.8,
                                 wz2=-6.0 + 4.0 * (e - 0.1) / 3.8, wy=1.0, start=s - lo,
                                 end=e - lo)
    return one, cut


def plane_zones(stiff):
    """The plane analogue: a propped beam with zones of 0.4 and 0.7 m."""
    def base():
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", LS, 0.0)
        fr.add_support("A")
        fr.add_support("B", fix=("uy",))
        return fr

    one = base()
    one.add_member("A", "B", E, A, IZ, name="M", offset_i=OI, offset_j=OJ)
    cut = base()
    cut.add_node("P", OI, 0.0)
    cut.add_node("Q", LS - OJ, 0.0)
    for name, i, j, s in (("R1", "A", "P", stiff), ("F", "P", "Q", 1.0), ("R2", "Q", "B", stiff)):
        cut.add_member(i, j, E, s * A, s * IZ, name=name)
    pieces = {"R1": (0.0, OI), "F": (OI, LS - OJ), "R2": (LS - OJ, LS)}
    for a, kw in ((0.2, dict(fy=-5.0, mz=1.5)), (2.0, dict(fy=-8.0, fx=2.0)),
                  (3.6, dict(fy=3.0, mz=-0.8))):
        one.add_point_load("M", a, **kw)
        name = next(n for n, (lo, hi) in pieces.items() if lo <= a < hi)
        cut.add_point_load(name, a - pieces[name][0], **kw)
    one.add_distributed_load("M", wy=-6.0)
    for name in pieces:
        cut.add_distributed_load(name, wy=-6.0)
    return one, cut


def pynite_twins(nodes, members, e, g, a, iy, iz, j_t, *, releases=None):
    """(PyNite's FEModel3D, our SpaceFrame) of the same frame clamped at node
    "A": ``nodes`` {name: (x, y, z)}, ``members`` [(i, j, roll in degrees)]
    named M0, M1, ..., one section (E, G, A, Iy, Iz, J); ``releases``
    {member: (PyNite's def_releases keywords, our add_member keywords)}.
    Needs PyNite (callers skip without it)."""
    from Pynite import FEModel3D

    releases = releases or {}
    m, fr = FEModel3D(), SpaceFrame()
    m.add_material("s", e, g, 0.3, 0.0)
    m.add_section("x", a, iy, iz, j_t)
    for n, xyz in nodes.items():
        m.add_node(n, *xyz)
        fr.add_node(n, *xyz)
    m.def_support("A", True, True, True, True, True, True)
    fr.add_support("A")
    for k, (i, j, roll) in enumerate(members):
        name = f"M{k}"
        m.add_member(name, i, j, "s", "x", rotation=roll)
        theirs, ours = releases.get(name, ({}, {}))
        if theirs:
            m.def_releases(name, **theirs)
        fr.add_member(i, j, e, a, iy, iz, G=g, J=j_t, name=name, ref=m.members[name].T()[2, :3],
                      **ours)
    return m, fr
