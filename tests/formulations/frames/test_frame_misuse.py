"""Everyday misuse of the frames, and what a user gets instead of a puzzle.

- A frame without contacts is linear: ``solve``, ``solve_combinations`` and
  ``trace`` answer it (route "linear") — checked against the cantilever's
  hand formulas u = P L³ / 3EI, θ = P L² / 2EI, reactions P and P L.
- A mechanism is named by its free motion: a beam pinned at one end turns
  about that node, a beam on two frictionless pads translates along x, a
  node no member holds is free, a part turns about a hinge; in space a
  pinned end turns about x, y and z.
- ``raise_on_failure=False`` returns a proved "no equilibrium" as a result
  (status "infeasible", the proof in ``proof``); by default and with True
  it raises.  The reference is the rigid body's friction limit μW by hand.
- Options a frame's route does not take are refused by name (``route=``
  beside "auto", where the active set answers and Lemke never runs), on
  linear frames too; ``time_limit`` bounds the whole analysis: a random
  117-contact beam whose collapse proof ran for minutes stops at 2 s with
  SolverFailedError saying that nothing was proved.
- Contacts whose normals point along the load (a pad "under" a beam with
  normal (0, -1)) get a hint that the normal points from the ground into
  the frame; normals given right get none.
"""

from __future__ import annotations

import numpy as np
import pytest

from formulations.frames import Frame, SpaceFrame
from qpcontact.core.errors import (InvalidOptionError, InvalidProblemError, NoSolutionError,
                                   SolverFailedError)
from tests.formulations.frames.frame_cases import frictional_beam, random_beam
from tests.helpers.limits import kept, timed

E, A, I = 2.0e8, 1.0e-2, 1.0e-4      # kN/m², m², m⁴
G = 8.0e7
L, P = 4.0, 10.0                      # m, kN


def cantilever():
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, A, I)
    fr.add_support("A")
    fr.add_load("B", fy=-P, case="variable")
    return fr


def space_cantilever():
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", L, 0.0, 0.0)
    fr.add_member("A", "B", E, A, I, I, G=G, J=2 * I)
    fr.add_support("A")
    fr.add_load("B", fz=-P, case="variable")
    return fr


# -- a frame without contacts is solved linearly -----------------------------

def test_a_frame_without_contacts_is_solved_linearly():
    r = cantilever().solve(p=1.0)
    assert r.ok and r.route == "linear", r.message
    ux, uy, rz = r.displacements["B"]
    assert uy == pytest.approx(-P * L ** 3 / (3 * E * I), rel=1e-12)
    assert rz == pytest.approx(-P * L ** 2 / (2 * E * I), rel=1e-12)
    assert r.reactions["A"] == pytest.approx((0.0, P, P * L), abs=1e-9)
    assert r.supports == {}


def test_a_space_frame_without_contacts_is_solved_linearly():
    r = space_cantilever().solve(p=2.0)
    assert r.ok and r.route == "linear", r.message
    uz, ry = r.displacements["B"][2], r.displacements["B"][4]
    assert uz == pytest.approx(-2 * P * L ** 3 / (3 * E * I), rel=1e-12)
    # a positive ry turns +z towards -x: the tip drops, its slope is +
    assert ry == pytest.approx(2 * P * L ** 2 / (2 * E * I), rel=1e-12)


def test_combinations_and_the_trace_of_a_linear_frame():
    fr = cantilever()
    both = fr.solve_combinations({"half": 0.5, "twice": 2.0})
    assert not both.failed
    assert both["twice"].displacements["B"][1] == pytest.approx(
        -2 * P * L ** 3 / (3 * E * I), rel=1e-12)
    ft = fr.trace(p_max=3.0)
    assert ft.ok and ft.ended == "p_max" and ft.events == [] and ft.limit is None
    assert ft.intervals == [(0.0, 3.0)]
    assert ft.result_at(3.0).displacements["B"][1] == pytest.approx(
        -3 * P * L ** 3 / (3 * E * I), rel=1e-12)
    open_ended = fr.trace()
    assert open_ended.ok and open_ended.ended == "unbounded" and "linear" in open_ended.message
    s = space_cantilever().trace(p_max=1.0)
    assert s.ok and s.ended == "p_max" and s.events == []


def test_a_linear_column_to_second_order():
    """A cantilever column without contacts, P = 500 kN down and H = 1 kN
    across at its top: the beam-column's closed form δ = H L³/3EI ·
    3(tan kL − kL)/(kL)³, k² = P/EI, and α_cr = π²EI/(4L²)/P."""
    import math

    Pc, H = 500.0, 1.0
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    fr.add_member("A", "B", E, A, I)
    fr.add_support("A")
    fr.add_load("B", fx=H, fy=-Pc)
    first, second = fr.solve(), fr.solve(second_order=True)
    assert first.ok and second.ok and second.route == "linear", second.message
    kl = math.sqrt(Pc / (E * I)) * L
    hand = H * L ** 3 / (3 * E * I) * 3 * (math.tan(kl) - kl) / kl ** 3
    assert second.displacements["B"][0] == pytest.approx(hand, rel=1e-10)
    assert fr.critical_load_factor(first)["alpha"] == pytest.approx(
        math.pi ** 2 * E * I / (4 * L ** 2) / Pc, rel=1e-8)
    column = SpaceFrame()
    column.add_node("A", 0.0, 0.0, 0.0)
    column.add_node("B", 0.0, 0.0, L)
    column.add_member("A", "B", E, A, I, I, G=G, J=2 * I)
    column.add_support("A")
    column.add_load("B", fx=H, fz=-Pc)
    second = column.solve(second_order=True)
    assert second.ok and second.route == "linear", second.message
    assert second.displacements["B"][0] == pytest.approx(hand, rel=1e-10)


def test_a_linear_frame_still_refuses_a_misspelt_method():
    with pytest.raises(Exception, match="unknown method 'lemk'"):
        cantilever().solve(method="lemk")


def test_options_no_route_takes_are_refused_by_name():
    beam = frictional_beam(10, 4, friction=0.1)
    assert beam.solve().ok                               # the active set answers
    with pytest.raises(InvalidOptionError, match="does not take route"):
        beam.solve(route="lemke")
    with pytest.raises(InvalidOptionError, match="does not take max_pivot .*max_pivots"):
        beam.solve(max_pivot=10)
    assert beam.solve(max_pivots=10, time_limit=30).ok   # Lemke's, and the call's
    with pytest.raises(InvalidOptionError, match="time_limit must be a positive"):
        beam.solve(time_limit="10 s")
    with pytest.raises(InvalidOptionError, match="does not take route"):
        cantilever().solve(route="lemke")               # linear: nothing would read it
    circle, polygon = table((0.0, 0.0, 1.0)), table((0.0, 0.0, 1.0))
    polygon.cone = "inscribed"
    for space in (circle, polygon):                     # the friction solvers', Lemke's
        with pytest.raises(InvalidOptionError, match="does not take route"):
            space.solve(route="lemke")


def test_the_time_limit_bounds_the_whole_analysis():
    """The active set and Lemke find nothing on this beam, and the load
    path's collapse proof branched for minutes: the limit ends it, and the
    error says that nothing was proved (no answer is made up)."""
    beam = random_beam(36)

    def refused():
        with pytest.raises(SolverFailedError) as info:
            beam.solve(time_limit=2.0)
        return str(info.value)

    words, took = timed(refused)      # the wall time and the share of a core it had
    assert "within the time limit" in words and "nothing was proved" in words, words
    assert kept(2.0, took), took
    with pytest.raises(SolverFailedError, match="within the time limit.*before 'lemke'"):
        beam.solve(method="lemke", time_limit=1e-9)


# -- a mechanism is named by its motion ----------------------------------------

def _beam():
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, A, I)
    fr.add_load("B", fy=-P)
    return fr


def test_a_beam_pinned_at_one_end_turns_about_it():
    fr = _beam()
    fr.add_support("A", fix=("ux", "uy"))
    with pytest.raises(InvalidProblemError,
                       match=r"no contacts\): it turns rigidly about node A .*fix rz at A"):
        fr.solve()
    fr.add_contact("B", normal=(1.0, 0.0))      # a contact that does not stop the turn
    with pytest.raises(InvalidProblemError, match="every contact closed: it turns rigidly "
                                                  "about node A"):
        fr.solve()


def test_a_beam_on_frictionless_pads_translates_along_x():
    fr = _beam()
    fr.add_contact("A")
    fr.add_contact("B")
    with pytest.raises(InvalidProblemError, match="it translates rigidly along x; hold ux"):
        fr.solve()


def test_a_loose_node_and_a_hinge_are_named():
    fr = _beam()
    fr.add_support("A")
    fr.add_node("C", 2 * L, 0.0)
    with pytest.raises(InvalidProblemError, match=r"node C is free in (ux, uy|uy, ux)"):
        fr.solve()
    fr = Frame()
    for name, x in (("A", 0.0), ("B", L), ("C", 2 * L)):
        fr.add_node(name, x, 0.0)
    fr.add_member("A", "B", E, A, I, hinge_j=True)
    fr.add_member("B", "C", E, A, I)
    fr.add_support("A")
    fr.add_support("C", fix=("ux",))
    fr.add_load("B", fy=-P)
    with pytest.raises(InvalidProblemError,
                       match="the part of the frame with nodes B, C turns rigidly about node B"):
        fr.solve()


def test_a_portal_that_sways_is_named_by_its_rigid_parts():
    """Pinned bases and a beam hinged at both ends: the columns turn about
    their feet and the beam translates along x (a sway)."""
    fr = Frame()
    for name, xy in (("A", (0.0, 0.0)), ("B", (0.0, L)), ("C", (6.0, L)), ("D", (6.0, 0.0))):
        fr.add_node(name, *xy)
    fr.add_member("A", "B", E, A, I, name="left")
    fr.add_member("B", "C", E, A, I, hinge_i=True, hinge_j=True, name="beam")
    fr.add_member("C", "D", E, A, I, name="right")
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_support("D", fix=("ux", "uy"))
    fr.add_load("B", fx=P)
    with pytest.raises(InvalidProblemError, match=r"a mechanism of 3 rigid parts moving together "
                       r"\(left turns rigidly about node A; beam translates rigidly along x; "
                       r"right turns rigidly about node D\)"):
        fr.solve()


def test_a_space_beam_pinned_at_one_end_turns_about_three_axes():
    fr = space_cantilever()
    fr.fixed.clear()
    fr.add_support("A", fix=("ux", "uy", "uz"))
    with pytest.raises(InvalidProblemError,
                       match=r"turns rigidly about node A \(about x, y, z\); fix rx, ry, rz"):
        fr.solve()


# -- raise_on_failure ---------------------------------------------------------------

MU, W = 0.3, 20.0        # two pads, W = 20 kN in all: the rigid body slides at H = μW = 6


def on_pads(normal=(0.0, 1.0)):
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, A, I)
    for n in ("A", "B"):
        fr.add_contact(n, normal=normal, friction=MU)
        fr.add_load(n, fy=-W / 2)
    fr.add_load("A", fx=1.0, case="variable")
    return fr


def test_raise_on_failure_false_returns_the_proof():
    fr = on_pads()
    assert fr.solve(p=0.99 * MU * W).ok                  # below μW: carried
    r = fr.solve(p=1.01 * MU * W, raise_on_failure=False)
    assert not r.ok and r.status == "infeasible"
    assert "slides away as a rigid body" in r.proof and r.message == r.proof
    with pytest.raises(NoSolutionError, match="slides away"):
        fr.solve(p=1.01 * MU * W)                         # the default raises, as documented
    with pytest.raises(NoSolutionError, match="slides away"):
        fr.solve(p=1.01 * MU * W, raise_on_failure=True)
    second = fr.solve(p=1.01 * MU * W, raise_on_failure=False, second_order=True)
    assert second.status == "infeasible" and "slides away" in second.proof
    both = fr.solve_combinations({"below": 0.99 * MU * W, "beyond": 1.01 * MU * W})
    assert both["below"].status == "solved" and both["beyond"].status == "infeasible"
    with pytest.raises(Exception, match="raise_on_failure must be True, False or None"):
        fr.solve(raise_on_failure="no")


# -- a normal pointing the wrong way gets a hint ---------------------------------------

HINT = "from the ground into the frame"


def test_pads_with_normals_pointing_down_get_the_hint():
    with pytest.raises(NoSolutionError, match=HINT) as err:
        on_pads(normal=(0.0, -1.0)).solve(p=0.0)
    assert "normal=(0.0, 1.0) instead of (0.0, -1.0)" in str(err.value)
    r = on_pads(normal=(0.0, -1.0)).solve(p=0.0, raise_on_failure=False)
    assert HINT in r.proof
    with pytest.raises(NoSolutionError, match=HINT):
        on_pads(normal=(0.0, -1.0)).trace(p_max=1.0)
    with pytest.raises(NoSolutionError, match=HINT):
        on_pads(normal=(0.0, -1.0)).solve(p=0.0, second_order=True)


def test_normals_given_right_get_no_hint():
    with pytest.raises(NoSolutionError) as err:
        on_pads().solve(p=2 * MU * W)
    assert HINT not in str(err.value)


def table(normal):
    fr = SpaceFrame()
    corners = {"P0": (0, 0), "P1": (4, 0), "P2": (4, 3), "P3": (0, 3)}
    for n, (x, y) in corners.items():
        fr.add_node(n, x, y, 0.0)
    for a, b in (("P0", "P1"), ("P1", "P2"), ("P2", "P3"), ("P3", "P0")):
        fr.add_member(a, b, E, A, I, I, G=G, J=2 * I)
    for n in corners:
        fr.add_contact(n, normal=normal, friction=0.3)
        fr.add_load(n, fz=-10.0)
    return fr


def test_a_space_table_with_normals_down_gets_the_hint():
    r = table((0.0, 0.0, -1.0)).solve(raise_on_failure=False)
    assert r.status == "infeasible" and HINT in r.message
    assert "normal=(0.0, 0.0, 1.0) instead of (0.0, 0.0, -1.0)" in r.message
    assert table((0.0, 0.0, 1.0)).solve().ok


def test_a_frame_with_every_dof_held_is_solved_by_statics():
    """A beam clamped at both ends has no free dof: its reactions are the
    fixed-end forces, wL/2 and wL²/12 by hand (the empty system once
    crashed in the LU with scipy's "zero-size array")."""
    w = 10.0
    plane = Frame()
    plane.add_node("A", 0.0, 0.0)
    plane.add_node("B", L, 0.0)
    plane.add_member("A", "B", E=E, A=A, I=I, name="AB")
    plane.add_support("A")
    plane.add_support("B")
    plane.add_distributed_load("AB", wy=-w)
    r = plane.solve()
    assert r.status == "solved"
    np.testing.assert_allclose(r.reactions["A"], (0.0, w * L / 2, w * L ** 2 / 12), atol=1e-12)
    np.testing.assert_allclose(r.reactions["B"], (0.0, w * L / 2, -w * L ** 2 / 12), atol=1e-12)
    space = SpaceFrame()
    space.add_node("A", 0.0, 0.0, 0.0)
    space.add_node("B", L, 0.0, 0.0)
    space.add_member("A", "B", E=E, G=G, A=A, Iy=I, Iz=I, J=I, name="AB")
    space.add_support("A")
    space.add_support("B")
    space.add_distributed_load("AB", wz=-w)
    r = space.solve()
    assert r.status == "solved"
    np.testing.assert_allclose(r.reactions["A"], (0, 0, w * L / 2, 0, -w * L ** 2 / 12, 0),
                               atol=1e-12)


def test_a_space_member_in_the_old_order_of_section_constants_is_refused_by_name():
    """E, G, A, Iy, Iz, J by position (the space frame's old order) would bind
    G to A; the call is refused with the order to write, as is a missing G or J."""
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", L, 0.0, 0.0)
    with pytest.raises(InvalidProblemError, match=r"E, A, Iy, Iz by position .* got 6 section"):
        fr.add_member("A", "B", E, G, A, I, I, 2 * I)
    with pytest.raises(InvalidProblemError, match="got no J"):
        fr.add_member("A", "B", E, A, I, I, G=G)
    assert fr.add_member("A", "B", E, A, I, I, G=G, J=2 * I)
