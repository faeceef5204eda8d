"""Inclined supports of space frames: a bilateral support on turned node
axes (``add_support(..., angle=)``, the plane frame's keyword) and a member
on inclined rigid pads, against references independent of the code under
test.

* Parity: a plane frame with inclined rollers, a settlement along a turned
  axis and frictional contacts, built in the x-y plane of a SpaceFrame
  (out-of-plane dofs held, the turn (0, 0, θ)), gives the plane frame's
  states, contact forces, displacements and reactions to 1e-10 — on the
  faceted cone (its LCP is the plane frame's) and on Coulomb's circle.
* Hand statics: a simply supported beam whose roller stands on a slope
  across a turn about y (reaction along the slope's normal, P/(2 cos α);
  the member's axial force its horizontal part), the roller's settlement
  along its normal; a beam on two rigid pads tilted about its axis, which
  sticks with a friction force W/2 sin α against W/2 cos α where μ >
  tan α, and has no equilibrium where μ < tan α.
"""

from __future__ import annotations

import numpy as np
import pytest

from formulations.frames import Frame, SpaceFrame
from qpcontact.core.errors import InvalidProblemError, NoSolutionError

E, G, A, I = 2e8, 8e7, 1e-2, 1e-4
RTOL = 1e-10
OUT = ("uz", "rx", "ry")            # the plane's out-of-plane dofs, held in space


def _portal(space: bool, cone: str = "circumscribed"):
    """A plane frame with two inclined rollers (30° and -20°), a settlement
    along a turned axis, a frictionless pad on a turned node and a
    frictional pad with a gap, built as a Frame or in the x-y plane of a
    SpaceFrame."""
    fr = SpaceFrame(cone=cone) if space else Frame()
    for n, (x, y) in {"A": (0, 0), "B": (4, 0), "C": (8, 0), "D": (4, -3),
                      "E": (8, 3)}.items():
        fr.add_node(n, x, y, 0.0) if space else fr.add_node(n, x, y)
    for i, j in (("A", "B"), ("B", "C"), ("B", "D"), ("C", "E")):
        # in-plane bending is about the local z: the plane's I is Iz
        fr.add_member(i, j, E, A, 2 * I, I, G=G, J=2 * I, name=i + j) if space else \
            fr.add_member(i, j, E, A, I, name=i + j)
    out, dim = (OUT, 3) if space else ((), 2)

    def turn(angle):
        return (0.0, 0.0, angle) if space else angle

    fr.add_support("A", ("ux", "uy") + out)
    fr.add_support("C", ("uy",) + out, angle=turn(30.0))
    fr.add_support("D", ("ux",) + out, angle=turn(-20.0))
    if space:
        for n in "BE":
            fr.add_support(n, OUT)
    fr.add_contact("D", normal=(0.0, 1.0, 0.0)[:dim], gap=2e-4)
    fr.add_contact("E", normal=(0.3, -1.0, 0.0)[:dim], friction=0.2, gap=1e-4)
    fr.add_load("B", fx=3.0, fy=-20.0)
    fr.add_load("E", fx=-5.0, fy=8.0, case="variable")
    fr.add_settlement("C", uy=-2e-4)
    return fr


@pytest.mark.parametrize("cone", ["circumscribed", "circular"])
def test_inclined_supports_built_in_space_give_the_plane_frames_answer(cone):
    for p in (0.5, 2.0):
        plane = _portal(False).solve(p)
        space = _portal(True, cone).solve(p)
        assert plane.ok and space.ok, (plane.message, space.message)
        for key, s in plane.supports.items():
            t = space.supports[key]
            assert t.state.rstrip("+-") == s.state.rstrip("+-")
            scale = max(abs(s.normal), abs(s.tangential), 1.0)
            assert abs(t.normal - s.normal) <= RTOL * scale
            # the plane tangent (n_y, -n_x) is the space contact's ±t1 or ±t2 here
            assert abs(np.linalg.norm(t.tangential) - abs(s.tangential)) <= RTOL * scale
        u = max(np.abs(np.ravel(list(plane.displacements.values()))))
        for n, d in plane.displacements.items():
            np.testing.assert_allclose(np.array(space.displacements[n])[[0, 1, 5]], d,
                                       rtol=0, atol=RTOL * u)
            assert np.allclose(np.array(space.displacements[n])[[2, 3, 4]], 0.0, atol=1e-300)
        r = max(np.abs(np.ravel(list(plane.reactions.values()))))
        for n, f in plane.reactions.items():
            np.testing.assert_allclose(np.array(space.reactions[n])[[0, 1, 5]], f, rtol=0,
                                       atol=RTOL * r)
    # the roller at C carries its force along its normal, turned 30° from +y
    c = np.array(space.reactions["C"][:2])
    assert abs(c @ np.array([np.cos(np.radians(30)), np.sin(np.radians(30))])) <= 1e-12 * r


def _sloped_roller(alpha_deg: float, P: float = 12.0, L: float = 5.0, settle=None):
    """A beam A-B along x, pinned at A (torsion held), at B a roller on a
    slope: B's axes turned by -α about y, so its z' (the fixed dof, with
    uy) is the slope's normal (-sin α, 0, cos α).  P down at midspan."""
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", L, 0.0, 0.0)
    fr.add_member("A", "B", E, A, I, 2 * I, G=G, J=I, name="AB")
    fr.add_support("A", ("ux", "uy", "uz", "rx"))
    fr.add_support("B", ("uy", "uz"), angle=(0.0, -alpha_deg, 0.0))
    fr.add_point_load("AB", L / 2, fz=-P)
    if settle is not None:
        fr.add_settlement("B", uz=settle)
    return fr


@pytest.mark.parametrize("alpha", [10.0, 30.0, 55.0])
def test_a_roller_on_a_slope_pushes_along_its_normal(alpha):
    P, L = 12.0, 5.0
    res = _sloped_roller(alpha, P, L).solve()
    assert res.ok, res.message
    a = np.radians(alpha)
    n = np.array([-np.sin(a), 0.0, np.cos(a)])
    # moments about A: the roller's vertical part is P/2, its force P/(2 cos α) along n
    rb = np.array(res.reactions["B"][:3])
    np.testing.assert_allclose(rb, P / (2 * np.cos(a)) * n, rtol=0, atol=1e-12 * P)
    np.testing.assert_allclose(res.reactions["A"][:3], [P / 2 * np.tan(a), 0.0, P / 2],
                               rtol=0, atol=1e-12 * P)
    # the member carries the roller's horizontal push: compression P/2 tan α
    N = res.end_forces("AB")
    assert abs(N["i"]["N"] + P / 2 * np.tan(a)) <= 1e-12 * P
    assert abs(N["j"]["N"] + P / 2 * np.tan(a)) <= 1e-12 * P
    # B moves along the slope, never across it
    ub = np.array(res.displacements["B"][:3])
    assert abs(ub @ n) <= 1e-12 * np.abs(ub).max()
    assert abs(ub[0]) > 0


def test_a_settlement_along_a_turned_axis_moves_the_node_along_it():
    alpha, delta = 25.0, -3e-3
    res = _sloped_roller(alpha, settle=delta).solve()
    a = np.radians(alpha)
    n = np.array([-np.sin(a), 0.0, np.cos(a)])
    ub = np.array(res.displacements["B"][:3])
    assert res.ok and abs(ub @ n - delta) <= 1e-12 * abs(delta)
    # a statically determinate beam: the settlement moves it rigidly, its forces unchanged
    np.testing.assert_allclose(res.reactions["B"][:3],
                               _sloped_roller(alpha).solve().reactions["B"][:3],
                               rtol=0, atol=1e-9)


def _beam_on_tilted_pads(alpha_deg: float, mu: float, W: float = 40.0, L: float = 6.0):
    """A beam along x on two rigid pads whose normal is tilted by α about
    the beam's axis, n = (0, -sin α, cos α), its twist held at A; W down
    at midspan."""
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", L, 0.0, 0.0)
    fr.add_node("M", L / 2, 0.0, 0.0)
    fr.add_member("A", "M", E, A, I, 2 * I, G=G, J=I)
    fr.add_member("M", "B", E, A, I, 2 * I, G=G, J=I)
    a = np.radians(alpha_deg)
    for node in "AB":
        fr.add_contact(node, normal=(0.0, -np.sin(a), np.cos(a)), friction=mu)
    fr.add_support("A", ("rx",))
    fr.add_load("M", fz=-W)
    return fr


@pytest.mark.parametrize("alpha", [15.0, 35.0])
def test_a_beam_on_tilted_pads_sticks_above_tan_alpha_and_slides_below(alpha):
    W = 40.0
    a = np.radians(alpha)
    res = _beam_on_tilted_pads(alpha, np.tan(a) + 0.02, W).solve()
    assert res.ok, res.message
    for s in res.supports.values():
        assert s.state == "stick"
        # each pad carries W/2 straight up: W/2 cos α along its normal and
        # W/2 sin α of friction, within μ X_n
        assert abs(s.normal - W / 2 * np.cos(a)) <= 1e-9 * W
        assert abs(np.linalg.norm(s.tangential) - W / 2 * np.sin(a)) <= 1e-9 * W
    with pytest.raises(NoSolutionError):
        _beam_on_tilted_pads(alpha, np.tan(a) - 0.02, W).solve()


def test_turned_axes_misuse_is_named():
    fr = _sloped_roller(30.0)
    with pytest.raises(InvalidProblemError, match=r"\(0, 0, 30\)"):
        fr.add_support("A", ("uz",), angle=30)
    with pytest.raises(InvalidProblemError, match="one set of axes"):
        fr.add_support("B", ("ux",), angle=(0.0, 0.0, 10.0))
    with pytest.raises(InvalidProblemError, match="pass the same angle"):
        fr.add_support("B", ("ux",))
    with pytest.raises(InvalidProblemError, match="rotation vector"):
        fr.add_support("A", ("uz",), angle=(1.0, 2.0))
    fr.add_support("B", ("rx",), angle=(0.0, -30.0, 0.0))      # the same axes: fine
    assert fr.fixed["B"] == {"uy", "uz", "rx"}


def _pad_held_across(turned: bool):
    """A cantilever A-B on a frictional pad at B, B held across the beam
    (global y): by ux turned 90° about z, or by uy itself."""
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 4.0, 0.0, 0.0)
    fr.add_member("A", "B", E, A, I, 2 * I, G=G, J=I, name="AB")
    fr.add_support("A", ("ux", "uy", "uz", "rx"))
    if turned:
        fr.add_support("B", ("ux",), angle=(0.0, 0.0, 90.0))
    else:
        fr.add_support("B", ("uy",))
    fr.add_contact("B", normal=(0.0, 0.0, 1.0), friction=0.3)
    fr.add_load("B", fx=-2.0, fy=1.5, fz=-10.0)
    return fr


def test_a_pads_tangent_held_by_turned_axes_is_held():
    """The pad's tangent along y is held by the turned support (its ux' is
    global y): no friction link along it — as with uy held unturned, the
    same answer; read in global axes the held dof would be taken for a
    free one, and the link beside the support would make the frame a
    mechanism of redundant links."""
    turned, plain = _pad_held_across(True).solve(), _pad_held_across(False).solve()
    assert turned.ok and plain.ok, (turned.message, plain.message)
    for key, s in plain.supports.items():
        t = turned.supports[key]
        assert t.state == s.state and abs(t.normal - s.normal) <= 1e-12 * abs(s.normal)
        np.testing.assert_allclose(t.tangential_global, s.tangential_global, rtol=0, atol=1e-12)
    for n in ("A", "B"):
        np.testing.assert_allclose(turned.reactions[n], plain.reactions[n], rtol=0, atol=1e-10)
        np.testing.assert_allclose(turned.displacements[n], plain.displacements[n], rtol=0,
                                   atol=1e-14)
    # B's support carries the 1.5 kN across; the pad the weight and the push along x
    assert abs(turned.reactions["B"][1] + 1.5) <= 1e-10
