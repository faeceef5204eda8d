"""Space frames against references independent of the code under
test.

* Planar frames built in the x-z plane of a space frame (out-of-plane dofs
  held at every node) against the plane frame (:class:`~formulations.frames.
  Frame`): the same states, forces, displacements, trace breakpoints and
  endings to 1e-10 of each quantity's own scale.  The plane frame shares the
  trace engine but not the model: its own elements, links, LCP layout and
  results.
* Tables and a stool on frictional floors: sticking, sliding, tipping and
  turning thresholds by hand statics, and, where the pads' normal forces are
  statically determinate, by an LP over the rigid body's statics with the
  same faceted cones (scipy's linprog, which shares nothing with the LCP).
* PyNite 3-D: a cantilever frame with unequal principal stiffnesses and rolled
  sections (bilateral supports), and a frame on compression-only support
  springs where one support lifts off (PyNite's iteration on the springs
  against the space frame's elastic frictionless contacts).
* Combinations: each solved on its own, what cannot be carried said.
(Bad input: tests/formulations/frames/test_space_bad_input.py.)
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from formulations.frames import Frame
from formulations.frames import SpaceFrame
from qpcontact.core.errors import NoSolutionError
from tests.helpers.frame_twins import pynite_twins

# near their collapse loads some of these frames sway beyond small-displacement
# theory (said and warned elsewhere: tests/formulations/frames/test_plane_features.py)
pytestmark = pytest.mark.filterwarnings(
    "ignore::formulations.frames.LargeDisplacementWarning")

E, G = 2.1e8, 8.1e7           # kN/m²
RTOL = 1e-10


# -- planar frames, built twice ------------------------------------------------

def _planar(nodes, members, fix, contacts, loads, member_loads, shear_area=None, options=None):
    """The same plane frame as a Frame and in the x-z plane of a SpaceFrame:
    (x, y) -> (x, 0, z = y), rz -> -ry (a counterclockwise turn in x-y takes
    x to y, in x-z it takes x to z: a negative turn about y), each member's
    local z the plane member's local y (ref), so that V and M of the plane
    member are Vz and -My of the space one; uy, rx and rz held at every node.
    contacts: (node, 2-D normal, friction, gap, stiffness); loads: (node, fx,
    fy, mz, case); member_loads: (member, wx, wy, case, axes); shear_area:
    every member Timoshenko, the plane member's A_s the space member's A_sz
    (and twice it along y, never strained); options: {member: the plane
    member's hinge_i/hinge_j/spring_i/spring_j/offset_i/offset_j}, a plane
    hinge or spring (about z) the space member's about y."""
    plane, space = Frame(), SpaceFrame(cone="circumscribed")
    for name, (x, y) in nodes.items():
        plane.add_node(name, x, y)
        space.add_node(name, x, 0.0, y)
        space.add_support(name, fix=("uy", "rx", "rz"))
    shear = {} if shear_area is None else {"G": G, "shear_area": shear_area}
    for i, j, A, I, name in members:
        extra = (options or {}).get(name, {})
        plane.add_member(i, j, E, A, I, name=name, **shear, **extra)
        # a plane hinge or spring (about z) is the space member's about y
        extra = {k: (("ry",) if v is True else {"ry": v} if k.startswith("spring") else v)
                 for k, v in extra.items()}
        d = np.subtract(nodes[j], nodes[i]) / np.hypot(*np.subtract(nodes[j], nodes[i]))
        # Iz and J are never strained (out-of-plane motion held): any values
        space.add_member(i, j, E, A, I, 3.0 * I, G=G, J=2.0 * I, name=name, ref=(-d[1], 0.0, d[0]),
                         shear_area=None if shear_area is None else (2 * shear_area,
                                                                     shear_area), **extra)
    to3 = {"ux": "ux", "uy": "uz", "rz": "ry"}
    for node, dofs in fix.items():
        plane.add_support(node, fix=dofs)
        space.add_support(node, fix=tuple(to3[d] for d in dofs))
    for node, n, f, gap, k in contacts:
        plane.add_contact(node, normal=n, friction=f, gap=gap, stiffness=k)
        space.add_contact(node, normal=(n[0], 0.0, n[1]), friction=f, gap=gap, stiffness=k)
    for node, fx, fy, mz, case in loads:
        plane.add_load(node, fx=fx, fy=fy, mz=mz, case=case)
        space.add_load(node, fx=fx, fz=fy, my=-mz, case=case)
    for member, wx, wy, case, axes in member_loads:
        plane.add_distributed_load(member, wx=wx, wy=wy, case=case, axes=axes)
        space.add_distributed_load(member, wx=wx, wz=wy, case=case, axes=axes)
    return plane, space


def _continuous_beam():
    """Five spans of 4 m under 15 kN/m on six supports: a frictionless one
    held in x at N0, elastic and rigid frictional ones, two with gaps; an
    uplift, a push and a moment grow with p."""
    nodes = {f"N{k}": (4.0 * k, 0.0) for k in range(6)}
    members = [(f"N{k}", f"N{k + 1}", 0.02, 2e-4, f"B{k}") for k in range(5)]
    contacts = [("N0", (0.0, 1.0), 0.0, 0.0, None), ("N1", (0.0, 1.0), 0.3, 0.0, 5e4),
                ("N2", (0.0, 1.0), 0.2, 2e-3, 8e4), ("N3", (0.0, 1.0), 0.4, 0.0, None),
                ("N4", (0.0, 1.0), 0.3, 1e-3, None), ("N5", (0.0, 1.0), 0.25, 0.0, 3e4)]
    loads = [("N5", -40.0, 30.0, 0.0, "variable"), ("N2", 0.0, -20.0, 10.0, "variable")]
    member_loads = [(f"B{k}", 0.0, -15.0, "constant", "global") for k in range(5)]
    return _planar(nodes, members, {"N0": ("ux",)}, contacts, loads, member_loads), \
        (0.5, 1.0, 2.0)


def _portal():
    """The plane frame's portal (formulations.frames.portal_example): two
    pads with f = 0.3, 20 kN/m on the beam, p at B; D slips at 25.4363, the
    frame slides away at f w L = 36."""
    nodes = {"A": (0.0, 0.0), "B": (0.0, 4.0), "C": (6.0, 4.0), "D": (6.0, 0.0)}
    A, I = 5.381e-3, 8.356e-5
    members = [("A", "B", A, I, "M1"), ("B", "C", A, I, "M2"), ("D", "C", A, I, "M3")]
    contacts = [("A", (0.0, 1.0), 0.3, 0.0, None), ("D", (0.0, 1.0), 0.3, 0.0, None)]
    return _planar(nodes, members, {}, contacts, [("B", 1.0, 0.0, 0.0, "variable")],
                   [("M2", 0.0, -20.0, "constant", "global")]), (10.0, 30.0)


def _ladder():
    """A ladder: its foot on the floor, its top against a wall (elastic, a
    gap), a rung node near an inclined ledge; self-weight in global axes and
    a load across the upper member in member axes; a load grows at the rung."""
    nodes = {"F": (0.0, 0.0), "M": (1.5, 2.0), "T": (3.0, 4.0)}
    members = [("F", "M", 0.004, 2e-6, "L1"), ("M", "T", 0.004, 2e-6, "L2")]
    contacts = [("F", (0.0, 1.0), 0.4, 0.0, None), ("T", (-1.0, 0.0), 0.2, 1e-3, 2e3),
                ("M", (-0.6, 0.8), 0.3, 1e-2, 1e3)]
    member_loads = [("L1", 0.0, -0.3, "constant", "global"),
                    ("L2", 0.0, -0.3, "constant", "global"),
                    ("L2", 0.0, -0.1, "constant", "member")]
    return _planar(nodes, members, {}, contacts, [("M", 0.0, -1.0, 0.0, "variable")],
                   member_loads), (0.5, 1.0)


def _same_answers(plane, space, r2, r3):
    """r3 (space) against r2 (plane), each quantity on its own scale."""
    assert r2.ok and r3.ok, (r2.message, r3.message)
    names = list(plane.nodes)
    d2 = np.array([r2.displacements[n] for n in names])
    d3 = np.array([r3.displacements[n] for n in names])
    move, turn = np.abs(d2[:, :2]).max(), np.abs(d2[:, 2]).max()
    np.testing.assert_allclose(d3[:, [0, 2]], d2[:, :2], rtol=0, atol=RTOL * move)
    np.testing.assert_allclose(-d3[:, 4], d2[:, 2], rtol=0, atol=RTOL * turn)
    assert np.all(d3[:, [1, 3, 5]] == 0.0)                 # held
    force = max(max(s.normal for s in r2.supports.values()),
                max(np.abs(v).max() for v in r2.member_forces.values()))
    for c2, key in zip(plane.contacts, r2.supports):
        s2, s3 = r2.supports[key], r3.supports[key]
        t = np.array([c2.normal[1], 0.0, -c2.normal[0]])   # the plane frame's tangent
        state = s3.state
        if state == "slip":
            state += "+" if s3.slip_global @ t > 0 else "-"
        assert state == s2.state, (key, s2, s3)
        got = [s3.normal, s3.tangential_global @ t, s3.tangential_global[1]]
        np.testing.assert_allclose(got, [s2.normal, s2.tangential, 0.0], rtol=0,
                                   atol=RTOL * force)
    for name, f2 in r2.member_forces.items():
        f3 = np.asarray(r3.member_forces[name])
        np.testing.assert_allclose(f3[[0, 2, 6, 8]], np.asarray(f2)[[0, 1, 3, 4]], rtol=0,
                                   atol=RTOL * force)
        np.testing.assert_allclose(-f3[[4, 10]], np.asarray(f2)[[2, 5]], rtol=0,
                                   atol=RTOL * force * 10.0)
        assert np.all(np.abs(f3[[1, 3, 5, 7, 9, 11]]) <= RTOL * force * 10.0)
        # the diagrams: the plane member's N, V, M are the space member's N,
        # Vz, My (its local z is the plane member's y; both M compress the
        # fibre on that side, both V = dM/dx), and nothing about its y
        x2, *q2 = r2.diagram(name, 21)
        x3, *q3 = r3.diagram(name, 21)
        np.testing.assert_allclose(x3, x2, rtol=0, atol=RTOL * x2[-1])
        size = RTOL * force * max(1.0, x2[-1])
        for a, b in zip(q2, (q3[0], q3[2], q3[4])):
            np.testing.assert_allclose(b, a, rtol=0, atol=size)
        for b in (q3[1], q3[3], q3[5]):
            np.testing.assert_allclose(b, 0.0, rtol=0, atol=size)
        e2, e3 = r2.end_forces(name), r3.end_forces(name)
        for end in "ij":
            np.testing.assert_allclose([e3[end][q] for q in ("N", "Vz", "My")],
                                       [e2[end][q] for q in ("N", "V", "M")], rtol=0, atol=size)
        ext2, ext3 = r2.extremes(name), r3.extremes(name)
        for p2, p3 in (("N", "N"), ("V", "Vz"), ("M", "My"), ("v", "w")):
            scale = size if p2 != "v" else RTOL * move
            for side in ("max", "min"):
                assert ext3[p3][side][0] == pytest.approx(ext2[p2][side][0], abs=scale), \
                    (p2, side)
    for node, rea in r3.reactions.items():
        want = np.zeros(6)
        if node in r2.reactions:
            want[[0, 2, 4]] = np.array(r2.reactions[node]) * [1.0, 1.0, -1.0]
        np.testing.assert_allclose(rea, want, rtol=0, atol=RTOL * force * 10.0)


def _words(message):
    """A trace's collapse words without the parenthesised details (the slip
    directions are written (+t) in the plane, (along (x, y, z)) in space)
    and without the axis a rigid proof's motion turns about (a point in the
    plane, an axis in space)."""
    while "(" in message:
        message = re.sub(r" ?\([^()]*\)", "", message)
    return message.split("; just before")[0].split("; the proof's motion turns")[0]


@pytest.mark.parametrize("model", [_continuous_beam, _portal, _ladder])
def test_a_planar_frame_built_in_space_solves_and_traces_as_the_plane_frame(model):
    """Every state, force, displacement, member end action and reaction of a
    planar frame built in space equals the plane frame's to 1e-10 of its own
    scale, at fixed loads and along the whole trace: the same breakpoints with
    the same events ("slip±" in the plane is "slip" with that direction in
    space), the same ending and collapse load.  (A contact whose other tangent
    bilateral supports hold has two facets, along the free one — exactly the
    plane frame's LCP; with the octagon's oblique facets too, the portal's
    trace ended in "breakdown" at its sliding load instead of proving it.)"""
    (plane, space), loads = model()
    for p in loads:
        _same_answers(plane, space, plane.solve(p), space.solve(p))
    t2, t3 = plane.trace(), space.trace()
    assert t2.ok and t3.ok, (t2.message, t3.message)
    assert t3.ended == t2.ended == "collapse"
    np.testing.assert_allclose(t3.breakpoints, t2.breakpoints, rtol=RTOL)
    np.testing.assert_allclose(t3.p_end, t2.p_end, rtol=RTOL)
    np.testing.assert_allclose(t3.trace.proof["p_limit"], t2.trace.proof["p_limit"], rtol=RTOL)
    assert [str(ev) for ev in t3.events] == [re.sub(r"slip[+-]", "slip", str(ev))
                                             for ev in t2.events]
    for a, b in zip(t2.states, t3.states):
        _same_answers(plane, space, a, b)
    assert _words(t3.message) == _words(t2.message)


def test_a_settlement_on_a_beam_on_pads_as_the_plane_frame():
    """The continuous beam's horizontal hold at N0 is pushed 8 mm along the
    beam (case "S"), dragging it over its frictional pads: the same states,
    forces, displacements, diagrams and reactions in space as in the plane,
    to 1e-10."""
    (plane, space), _ = _continuous_beam()
    plane.add_settlement("N0", "S", ux=8e-3)
    space.add_settlement("N0", "S", ux=8e-3)
    states = set()
    for combo in ({"constant": 1.0, "S": 1.0}, {"constant": 1.0, "variable": 2.0, "S": 1.0}):
        r2 = plane.solve(combination=combo)
        for cone in ("circumscribed", "circular"):      # the LCP and the friction solvers
            space.cone = cone
            r3 = space.solve(combination=combo)
            assert r2.displacements["N0"][0] == r3.displacements["N0"][0] == 8e-3
            _same_answers(plane, space, r2, r3)
        states |= {s.state for s in r2.supports.values()}
    assert "slip+" in states, states          # the pads are dragged along


def test_a_portal_with_every_member_option_as_the_plane_frame():
    """The portal with shear-deformable members (A_s = 4e-4 m²: φ ~ 0.1 on
    the 4 m columns), rigid end zones at the beam's ends and the left
    column's top, a hinge at the beam's face at C, semi-rigid column ends
    (a spring at A's base, at the right column's top), a point force and moment
    and a partial trapezoid: every answer and diagram in space as in the
    plane, to 1e-10."""
    nodes = {"A": (0.0, 0.0), "B": (0.0, 4.0), "C": (6.0, 4.0), "D": (6.0, 0.0)}
    A, I = 5.381e-3, 8.356e-5
    members = [("A", "B", A, I, "M1"), ("B", "C", A, I, "M2"), ("D", "C", A, I, "M3")]
    contacts = [("A", (0.0, 1.0), 0.3, 0.0, None), ("D", (0.0, 1.0), 0.3, 0.0, None)]
    plane, space = _planar(nodes, members, {}, contacts, [("B", 1.0, 0.0, 0.0, "variable")],
                           [("M2", 0.0, -20.0, "constant", "global")], shear_area=4e-4,
                           options={"M2": {"offset_i": 0.3, "offset_j": 0.5, "hinge_j": True},
                                    "M1": {"offset_j": 0.25, "spring_i": 3e4},
                                    "M3": {"spring_j": 1.5e4}})
    plane.add_point_load("M2", 2.0, fy=-15.0, mz=6.0)
    space.add_point_load("M2", 2.0, fz=-15.0, my=-6.0)
    plane.add_distributed_load("M1", wx=3.0, wx2=1.0, start=1.0, end=3.5, case="variable")
    space.add_distributed_load("M1", wx=3.0, wx2=1.0, start=1.0, end=3.5, case="variable")
    for p in (1.5, 3.0):
        _same_answers(plane, space, plane.solve(p), space.solve(p))


def test_the_portal_in_space_at_the_plane_frames_hand_values():
    """The portal's references by hand (force method, statics) hold in space
    too: D slips at P = 25.4363 kN, the frame slides away at f w L = 36 kN."""
    (_, space), _ = _portal()
    tr = space.trace()
    np.testing.assert_allclose(tr.breakpoints, [25.4363], atol=5e-5)
    np.testing.assert_allclose(tr.p_end, 0.3 * 20.0 * 6.0, rtol=1e-9)
    assert "slides away as a rigid body" in tr.message
    assert "A (along (1, 0, 0)), D (along (1, 0, 0))" in tr.message


# -- tables on a frictional floor --------------------------------------------

SQUARE = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)]     # pads 2 m apart: a = 1 m


def _table(f, corners=SQUARE, h=0.5, W=40.0, facets=8):
    """Legs P_k-T_k of height h on rigid pads with friction f, the top a ring
    of beams, W shared by the top corners (case "constant")."""
    fr = SpaceFrame(cone="circumscribed")
    n = len(corners)
    for k, (x, y) in enumerate(corners):
        fr.add_node(f"P{k}", x, y, 0.0)
        fr.add_node(f"T{k}", x, y, h)
        fr.add_member(f"P{k}", f"T{k}", 2e8, 0.01, 1e-4, 1e-4, G=8e7, J=2e-4)
        fr.add_contact(f"P{k}", friction=f, facets=facets)
        fr.add_load(f"T{k}", fz=-W / n)
    for k in range(n):
        fr.add_member(f"T{k}", f"T{(k + 1) % n}", 2e8, 0.01, 1e-4, 1e-4, G=8e7, J=2e-4)
    return fr


def _push(corners, push, torque):
    """Per top corner (fx, fy) of a push ``push`` (x, y) through the centroid
    and a couple ``torque`` about the vertical through it (forces across the
    radii): per unit load parameter."""
    c = np.mean(corners, axis=0)
    out = []
    for xy in corners:
        r = np.subtract(xy, c)
        out.append(np.asarray(push) / len(corners)
                   + torque * np.array([-r[1], r[0]]) / (len(corners) * (r @ r)))
    return out


def _load(fr, per_corner, case="variable"):
    for k, (fx, fy) in enumerate(per_corner):
        fr.add_load(f"T{k}", fx=fx, fy=fy, case=case)
    return fr


def _rigid_body_limit(f, corners, h, W, per_corner, facets=8):
    """The largest p for which the rigid table's statics admit pad forces in
    the faceted cones (f N_k + d_j . F_k >= 0 at the facet directions d_j, N_k
    >= 0): an LP over (F_k, N_k) and p, by scipy's HiGHS."""
    from scipy.optimize import linprog

    n = len(corners)
    A_eq = np.zeros((6, 3 * n + 1))
    b_eq = np.zeros(6)
    for k, (x, y) in enumerate(corners):
        for a in range(3):                   # pad force components, at z = 0
            e = np.eye(3)[a]
            A_eq[:3, 3 * k + a] = e
            A_eq[3:, 3 * k + a] = np.cross([x, y, 0.0], e)
        top = np.array([x, y, h])
        w, v = np.array([0.0, 0.0, -W / n]), np.array([*per_corner[k], 0.0])
        b_eq -= np.r_[w, np.cross(top, w)]
        A_eq[:, -1] += np.r_[v, np.cross(top, v)]
    angles = 2 * np.pi * np.arange(facets) / facets
    A_ub = np.zeros((n * facets, 3 * n + 1))
    for k in range(n):
        A_ub[k * facets:(k + 1) * facets, 3 * k:3 * k + 3] = \
            -np.c_[np.cos(angles), np.sin(angles), np.full(facets, f)]
    c = np.zeros(3 * n + 1)
    c[-1] = -1.0
    res = linprog(c, A_ub=A_ub, b_ub=np.zeros(n * facets), A_eq=A_eq, b_eq=b_eq,
                  bounds=[(None, None), (None, None), (0, None)] * n + [(0, None)],
                  method="highs")
    assert res.status == 0, res.message
    return res.x[-1]


def test_a_table_pushed_through_its_centre_slips_at_its_back_pads_then_slides():
    """Push P = p at the top's centre (P/4 at each corner), h = 0.5 m, W = 40
    kN, f = 0.3.  Moments about the front pads' line: each back pad carries
    W/4 - P h/4, each front one W/4 + P h/4; while all stick each carries P/4
    of the push (the frame's response to it is antisymmetric about x = 1 m),
    so the back pads slip at P/4 = f (W/4 - P h/4), P = f W/(1 + f h) =
    10.4348, and the table slides away at P = f W = 12."""
    f, W, h = 0.3, 40.0, 0.5
    fr = _load(_table(f), _push(SQUARE, (1.0, 0.0), 0.0))
    tr = fr.trace()
    assert tr.ok and tr.ended == "collapse", tr.message
    np.testing.assert_allclose(tr.breakpoints, [f * W / (1 + f * h)], rtol=1e-10)
    assert [str(ev) for ev in tr.events] == ["P0: stick \u2192 slip; P3: stick \u2192 slip"]
    np.testing.assert_allclose(tr.p_end, f * W, rtol=1e-10)
    assert "the frame slides away as a rigid body" in tr.message
    assert all(f"P{k} (along (1, 0, 0))" in tr.message for k in range(4))
    for p in (5.0, 11.0):
        r = tr.result_at(p)
        s = r.supports
        back, front = W / 4 - p * h / 4, W / 4 + p * h / 4
        np.testing.assert_allclose([s[k].normal for k in ("P0", "P1", "P2", "P3")],
                                   [back, front, front, back], rtol=1e-10)
        fx = [s[k].tangential_global[0] for k in ("P0", "P1", "P2", "P3")]
        want = -p / 4 if p < 10.4348 else -f * back
        np.testing.assert_allclose(fx[0], want, rtol=1e-10)
        np.testing.assert_allclose(sum(fx), -p, rtol=1e-10)
    # solve on its own, between the thresholds and beyond the last
    r = fr.solve(11.0)
    assert r.ok and {k: s.state for k, s in r.supports.items()} == \
        {"P0": "slip", "P1": "stick", "P2": "stick", "P3": "slip"}
    assert r.supports["P0"].slip_global[0] > 0 and r.supports["P3"].slip_global[0] > 0
    with pytest.raises(NoSolutionError, match="no equilibrium exists.*slides away as a rigid body"):
        fr.solve(12.1)


def test_a_high_table_on_a_grippy_floor_tips_over_before_it_slides():
    """h = 2 m, f = 0.8: the back pads carry W/4 - P h/4 and slip at P/4 =
    f (W/4 - P h/4), P = f W/(1 + f h) = 12.3077; they are unloaded at P h =
    W a (a = 1 m, half the pads' spacing), P = 20 kN, where the table tips
    over about the front pads — before f W = 32 kN would slide it."""
    f, W, h = 0.8, 40.0, 2.0
    fr = _load(_table(f, h=h), _push(SQUARE, (1.0, 0.0), 0.0))
    tr = fr.trace()
    assert tr.ok and tr.ended == "collapse", tr.message
    np.testing.assert_allclose(tr.breakpoints, [f * W / (1 + f * h)], rtol=1e-10)
    np.testing.assert_allclose(tr.p_end, W * 1.0 / h, rtol=1e-10)
    assert "it tips over about P1, P2: P0, P3 lift off" in tr.message
    r = fr.solve(15.0)
    assert r.ok and [s.state for s in r.supports.values()] == ["slip", "stick", "stick", "slip"]
    np.testing.assert_allclose(r.supports["P0"].normal, W / 4 - 15.0 * h / 4, rtol=1e-10)


@pytest.mark.slow
def test_a_high_table_pushed_beyond_its_tipping_load_is_proved_to_tip():
    """solve at 20.5 kN, beyond P = W a / h = 20 kN (Lemke ends on a ray
    there; the load path proves it, 1.8 s)."""
    fr = _load(_table(0.8, h=2.0), _push(SQUARE, (1.0, 0.0), 0.0))
    with pytest.raises(NoSolutionError, match="tips over about P1, P2: P0, P3 lift off"):
        fr.solve(20.5)


@pytest.mark.parametrize("how", ["mz at one corner", "a couple of corner forces"])
def test_a_table_twisted_about_its_centre_turns_at_f_W_r(how):
    """A torque about the vertical through the centre leaves every pad W/4
    (no overturning moment) and turns the table once f (W/4) r at each pad is
    used up: Mz = f W r, r = √2 m the pads' distance to the centre.  The pads'
    slip directions are then across the radii, at 45°, which are facets of
    the octagon (and of its 16-gon): the faceted cone is exact there."""
    f, W = 0.3, 40.0
    for facets in (8, 16):
        fr = _table(f, facets=facets)
        if how == "mz at one corner":          # the top is rigidly connected
            fr.add_load("T0", mz=1.0, case="variable")
        else:
            _load(fr, _push(SQUARE, (0.0, 0.0), 1.0))
        tr = fr.trace()
        assert tr.ok and tr.ended == "collapse", tr.message
        np.testing.assert_allclose(tr.p_end, f * W * np.sqrt(2.0), rtol=1e-10)
        assert "the frame slides away as a rigid body" in tr.message
        for k, d in enumerate(["(0.707, -0.707, 0)", "(0.707, 0.707, 0)",
                               "(-0.707, 0.707, 0)", "(-0.707, -0.707, 0)"]):
            assert f"P{k} (along {d})" in tr.message
        for st in tr.states:
            np.testing.assert_allclose([s.normal for s in st.supports.values()], W / 4,
                                       rtol=1e-10)
    with pytest.raises(NoSolutionError, match="slides away as a rigid body"):
        fr.solve(1.01 * f * W * np.sqrt(2.0))
    assert fr.solve(0.9 * f * W * np.sqrt(2.0)).ok


@pytest.mark.parametrize("push, torque", [((1.0, 0.0), 0.5), ((1.0, 0.0), 1.0),
                                          ((0.6, 0.8), -1.5), ((0.0, 0.0), 1.0),
                                          ((1.0, 0.3), 3.0)])
def test_a_stool_pushed_and_twisted_gives_way_at_the_rigid_bodys_limit(push, torque):
    """Three legs (an equilateral triangle of side 2 m): the pads' normal
    forces follow from statics alone, and with them fixed, friction in the
    tangent plane is associated (slip normal to the facet it loads), so the
    load the stool gives way at is the rigid body's statical limit — an LP
    over the pads' forces in the same faceted cones — to 1e-9.  It turns
    about a pad that stays ("it turns about P2") or slides away."""
    f, W, h = 0.3, 30.0, 0.5
    tri = [(0.0, 0.0), (2.0, 0.0), (1.0, np.sqrt(3.0))]
    per_corner = _push(tri, push, torque)
    limit = _rigid_body_limit(f, tri, h, W, per_corner)
    fr = _load(_table(f, tri, h=h, W=W), per_corner)
    tr = fr.trace()
    assert tr.ok and tr.ended == "collapse", tr.message
    np.testing.assert_allclose(tr.p_end, limit, rtol=1e-9)
    assert re.search(r"it turns about P\d: friction exhausted|slides away as a rigid body",
                     tr.message), tr.message
    assert "lift" not in tr.message.split("; just before")[0]
    with pytest.raises(NoSolutionError, match="no equilibrium exists"):
        fr.solve(1.001 * limit)


def test_a_table_pushed_at_a_corner_gives_way_below_the_rigid_bodys_limit():
    """Four pads: which pair carries more of the weight is one statically
    indeterminate force, set by the frame's elasticity, which the LP is free
    to choose.  So the LP's 0.8047 f W only bounds the load from above (no
    equilibrium exists beyond it, whatever the frame), and the frame gives
    way a little earlier, at 0.8038 f W: proved there by Farkas vectors for
    every combination of pad states."""
    f, W = 0.3, 40.0
    per_corner = [(1.0, 0.0), (0.0, 0.0), (0.0, 0.0), (0.0, 0.0)]
    limit = _rigid_body_limit(f, SQUARE, 0.5, W, per_corner)
    np.testing.assert_allclose(limit / (f * W), 0.8047378541, rtol=1e-9)
    tr = _load(_table(f), per_corner).trace()
    assert tr.ok and tr.ended == "collapse", tr.message
    assert 0.998 * limit < tr.p_end < limit
    assert tr.trace.proof["p_limit"] < limit


# -- PyNite 3-D ----------------------------------------------------------------

def _pynite_displacements(model, names, combo="C"):
    out = {}
    for n in names:
        nd = model.nodes[n]
        out[n] = np.array([nd.DX[combo], nd.DY[combo], nd.DZ[combo],
                           nd.RX[combo], nd.RY[combo], nd.RZ[combo]])
    return out


def test_a_cantilever_space_frame_with_unequal_stiffnesses_against_pynite():
    """Four members in four orientations from a clamped base, sections with
    Iy != Iz, two of them rolled (PyNite's ``rotation``); each member's local
    z taken from PyNite's own axes as our reference vector (so both codes
    bend the same section about the same axes); nodal forces and moments:
    every nodal displacement to 1e-9."""
    pytest.importorskip("Pynite", reason="PyNite is in the test extra (PyNiteFEA)")
    nodes = {"A": (0.0, 0.0, 0.0), "B": (3.0, 0.0, 0.0), "C": (3.0, 2.5, 0.5),
             "D": (3.0, 2.5, 3.0), "E": (1.0, 4.0, 3.5)}
    members = [("A", "B", 0.0), ("B", "C", 25.0), ("C", "D", 0.0), ("D", "E", -40.0)]
    loads = {"C": (2.0, 0.0, 0.0, 0.0, 3.0, 0.0), "D": (4.0, -6.0, -10.0, 1.5, -2.0, 0.8),
             "E": (0.0, 3.0, -5.0, 0.0, 0.0, 1.0)}
    m, fr = pynite_twins(nodes, members, E, G, 0.012, 3e-5, 8e-5, 1.2e-5)
    for n, f in loads.items():
        for comp, v in zip(("FX", "FY", "FZ", "MX", "MY", "MZ"), f):
            if v:
                m.add_node_load(n, comp, v, case="D")
        fr.add_load(n, *f)
    m.add_load_combo("C", {"D": 1.0})
    m.analyze(check_statics=False)
    theirs = _pynite_displacements(m, nodes)
    ours = fr.solve().displacements
    big = max(np.abs(v).max() for v in theirs.values())
    for n in nodes:
        np.testing.assert_allclose(ours[n], theirs[n], rtol=1e-9, atol=1e-10 * big)


def test_lift_off_against_pynite_compression_only_springs():
    """A 4 m x 3 m frame, legs 3 m, its feet held horizontally and standing on
    vertical springs k that only push (PyNite: def_support_spring(..., "DZ",
    k, direction="-"), iterated on the springs' states; here: elastic
    frictionless contacts of stiffness k).  Weight at the top corners and a
    lateral load at T2 lift foot P0: both codes lift the same foot, give the
    same displacements and reactions (PyNite's iteration ends on an exact
    linear solve with its final springs, so to 1e-9), and the three feet left
    carry what statics gives them (three vertical supports: determinate)."""
    pytest.importorskip("Pynite", reason="PyNite is in the test extra (PyNiteFEA)")
    from Pynite import FEModel3D

    A, I, J, k, h = 0.012, 6e-5, 1.2e-5, 5e4, 3.0
    corners = [(0.0, 0.0), (4.0, 0.0), (4.0, 3.0), (0.0, 3.0)]
    m, fr = FEModel3D(), SpaceFrame()
    m.add_material("s", E, G, 0.3, 0.0)
    m.add_section("x", A, I, 1.5 * I, J)
    for c, (x, y) in enumerate(corners):
        for name, z in ((f"P{c}", 0.0), (f"T{c}", h)):
            m.add_node(name, x, y, z)
            fr.add_node(name, x, y, z)
        m.def_support(f"P{c}", True, True, False, False, False, False)
        m.def_support_spring(f"P{c}", "DZ", k, direction="-")
        fr.add_support(f"P{c}", fix=("ux", "uy"))
        fr.add_contact(f"P{c}", stiffness=k)
    pairs = [(f"P{c}", f"T{c}") for c in range(4)] + [(f"T{c}", f"T{(c + 1) % 4}")
                                                      for c in range(4)]
    for n, (i, j) in enumerate(pairs):
        m.add_member(f"M{n}", i, j, "s", "x")
        fr.add_member(i, j, E, A, I, 1.5 * I, G=G, J=J, name=f"M{n}",
                      ref=m.members[f"M{n}"].T()[2, :3])
    Hx, Hy = 30.0, 25.0
    loads = {f"T{c}": (0.0, 0.0, -20.0) for c in range(4)}
    loads["T2"] = (Hx, Hy, -20.0)
    for n, f in loads.items():
        for comp, v in zip(("FX", "FY", "FZ"), f):
            if v:
                m.add_node_load(n, comp, v, case="D")
        fr.add_load(n, *f)
    m.add_load_combo("C", {"D": 1.0})
    m.analyze(check_statics=False)
    r = fr.solve()
    assert r.ok, r.message
    lifted = [f"P{c}" for c in range(4) if not m.nodes[f"P{c}"].spring_DZ[2]]
    assert lifted == ["P0"]
    assert [s.state for s in r.supports.values()] == ["separated", "closed", "closed", "closed"]
    theirs = _pynite_displacements(m, fr.nodes)
    big = max(np.abs(v).max() for v in theirs.values())
    for n in fr.nodes:
        np.testing.assert_allclose(r.displacements[n], theirs[n], rtol=1e-9, atol=1e-10 * big)
    for c in range(4):
        nd = m.nodes[f"P{c}"]
        np.testing.assert_allclose([*r.reactions[f"P{c}"][:2], r.supports[f"P{c}"].normal],
                                   [nd.RxnFX["C"], nd.RxnFY["C"], nd.RxnFZ["C"]],
                                   rtol=1e-9, atol=1e-9 * 80.0)
    # statics with P0 off: moments about the lines y = 0 and x = 0 through the feet
    n2_n3 = (2 * 20.0 * 3.0 + Hy * h) / 3.0
    n1_n2 = (2 * 20.0 * 4.0 + Hx * h) / 4.0
    n1 = 80.0 - n2_n3
    np.testing.assert_allclose([r.supports[f"P{c}"].normal for c in (1, 2, 3)],
                               [n1, n1_n2 - n1, n2_n3 - (n1_n2 - n1)], rtol=1e-10)


# -- combinations ----------------------------------------------------------------

def test_combinations_keep_what_the_frame_carries_and_say_what_it_cannot():
    """The table with its weight (D: 40 kN), a push through the centre (W:
    1 kN) and a torque at a top corner (T: 1 kN m), f = 0.3, each combination
    solved on its own: pads at W/4 ∓ P h/4 while sticking, the back pads
    slipping beyond P = f W/(1 + f h) = 10.43, nothing carried beyond f W
    (the push: 10.8 under 0.9 D) or f W √2 = 16.97 (the torque) — those
    have ok False with the reason, the rest are kept."""
    f, h = 0.3, 0.5
    fr = _table(f, W=0.0)
    for k in range(4):
        fr.add_load(f"T{k}", fz=-10.0, case="D")
        fr.add_load(f"T{k}", fx=0.25, case="W")
    fr.add_load("T0", mz=1.0, case="T")
    combos = {"D": {"D": 1.0}, "D+10W": {"D": 1.0, "W": 10.0}, "D+11W": {"D": 1.0, "W": 11.0},
              "0.9D+11W": {"D": 0.9, "W": 11.0}, "D+10T": {"D": 1.0, "T": 10.0},
              "D+17T": {"D": 1.0, "T": 17.0}}
    res = fr.solve_combinations(combos)
    assert list(res) == list(combos)
    assert res.failed == ["0.9D+11W", "D+17T"]
    assert "slides away as a rigid body" in res["0.9D+11W"].message
    assert "along (1, 0, 0)" in res["0.9D+11W"].message
    assert "slides away as a rigid body" in res["D+17T"].message
    for name, P, states in (("D", 0.0, ["stick"] * 4), ("D+10W", 10.0, ["stick"] * 4),
                            ("D+11W", 11.0, ["slip", "stick", "stick", "slip"]),
                            ("D+10T", 0.0, ["stick"] * 4)):
        r = res[name]
        assert r.ok and r.name == name and r.combination == combos[name], r.message
        assert [s.state for s in r.supports.values()] == states
        back, front = 10.0 - P * h / 4, 10.0 + P * h / 4
        np.testing.assert_allclose([s.normal for s in r.supports.values()],
                                   [back, front, front, back], rtol=1e-10)
    np.testing.assert_allclose(res["D+11W"].supports["P0"].tangential_global[0],
                               -f * (10.0 - 11.0 * h / 4), rtol=1e-10)



@pytest.mark.parametrize("option", ["none", "offset", "hinge", "spring", "shear"])
def test_second_order_with_each_member_option_as_the_plane_frame(option):
    """A column under 800 kN and 10 kN across, its top tied to a beam on a
    roller, solved on the deformed frame (P-Δ, P-δ) with the column given
    a rigid zone at its base, a hinge or a spring at its top, or shear
    deformation: the sway of the plane frame and of the same frame built in
    the x-z plane of a SpaceFrame agree to 1e-10."""
    plane_opts = {"none": {}, "offset": {"offset_i": 0.5}, "hinge": {"hinge_j": True},
                  "spring": {"spring_j": 2e4}, "shear": {"G": G, "shear_area": 0.005}}[option]
    space_opts = {"none": {}, "offset": {"offset_i": 0.5}, "hinge": {"hinge_j": ("ry",)},
                  "spring": {"spring_j": {"ry": 2e4}},
                  "shear": {"shear_area": (0.01, 0.005)}}[option]
    A, I = 0.01, 1e-4
    plane, space = Frame(), SpaceFrame()
    for n, (x, y) in {"A": (0.0, 0.0), "B": (0.0, 4.0), "C": (3.0, 4.0)}.items():
        plane.add_node(n, x, y)
        space.add_node(n, x, 0.0, y)
        space.add_support(n, fix=("uy", "rx", "rz"))
    plane.add_member("A", "B", E, A, I, name="c", **plane_opts)
    space.add_member("A", "B", E, A, I, 2 * I, G=G, J=2 * I, name="c", ref=(-1.0, 0.0, 0.0),
                     **space_opts)
    plane.add_member("B", "C", E, A, I, name="b")
    space.add_member("B", "C", E, A, I, 2 * I, G=G, J=2 * I, name="b", ref=(0.0, 0.0, 1.0))
    plane.add_support("A")
    space.add_support("A")
    plane.add_support("C", fix=("uy",))
    space.add_support("C", fix=("uz",))
    plane.add_load("B", fx=10.0, fy=-800.0)
    space.add_load("B", fx=10.0, fz=-800.0)
    r2, r3 = (fr.solve(second_order=True, raise_on_failure=False) for fr in (plane, space))
    first = plane.solve()
    assert r2.ok and r3.ok, (r2.message, r3.message)
    assert r2.displacements["B"][0] > 1.05 * first.displacements["B"][0]   # P-Δ matters here
    np.testing.assert_allclose(r3.displacements["B"][0], r2.displacements["B"][0], rtol=1e-10)
    np.testing.assert_allclose(-r3.displacements["B"][4], r2.displacements["B"][2], rtol=1e-9)
