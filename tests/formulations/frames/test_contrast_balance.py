"""Frames at extreme stiffness contrast, each against hand statics: no
answer called ok with its reactions out of balance, no-equilibrium proved
by a motion that strains no member, and frames that are no mechanism not
refused as one.

* A beam N0 … N5 at 3 m whose third span is a bar hinged at both ends
  (its E and I scaled by s): the part beyond the bar, loaded +4.13, −8.21,
  −10 kN at N3, N4, N5 on frictionless pads, has no equilibrium — moments
  about N3 need R₃ = R₅ − 14.13 ≥ 0 and R₄ = (84.63 − 6 R₅)/3 ≥ 0, which
  no R₅ meets; lifting N3 while N5 stays (N4 rising half as much), the
  loads do work 4.13 − 8.21/2 = 0.025 kN per metre of N3's rise.
* A portal on two rigid pads (pinned feet, W, h, b): moments about the
  leeward foot give the windward pad W/2 − p h/b, the leeward W/2 + p h/b.
* A table on four pads under W at the legs' tops, pushed by p along x at
  the top's height h: each back pad carries W/4 − p h/(2a), each front one
  W/4 + p h/(2a) (a the pads' spacing along x).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from formulations.frames import Frame, SpaceFrame
from formulations.frames.mechanics import contact_lcp
from formulations.frames.mechanics.load_combinations import load_combination
from qpcontact.core.errors import InvalidProblemError, NoSolutionError, SolverFailedError

from .test_engineer_checks import portal_on_pads

E, A, I = 2e8, 1e-2, 2e-5          # kN/m², m², m⁴
LOADS = (-3.076, -3.589, 4.13, -8.21, -10.0)


def bar_beam(s, settle=True):
    """The review's beam: spans scaled 1, 1 (hinge_j), s (hinge_j), 1, 2.7;
    a pin at N0 (settled 1 cm down), frictionless pads at N1 … N5."""
    fr = Frame()
    for k in range(6):
        fr.add_node(f"N{k}", 3.0 * k, 0.0)
    for k, (f, hinge) in enumerate([(1.0, False), (1.0, True), (s, True), (1.0, False),
                                    (2.7, False)]):
        fr.add_member(f"N{k}", f"N{k + 1}", f * E, A, f * I, hinge_j=hinge)
    fr.add_support("N0", fix=("ux", "uy"))
    for k in range(1, 6):
        fr.add_contact(f"N{k}")
        fr.add_load(f"N{k}", fy=LOADS[k - 1])
    if settle:
        fr.add_settlement("N0", uy=-0.01)
    return fr


@pytest.mark.parametrize("s", [1.0, 1e6, 1e7, 1e10])
@pytest.mark.parametrize("settle", [True, False])
def test_a_beam_whose_part_beyond_a_bar_cannot_stand_is_proved_to_tip(s, settle):
    """Before: from s = 1e7 with the settlement, ok with "equilibrium
    residual 0.0e+00" and the pads' forces summing to 24.875 kN against
    20.745 of load (the load at N3 lost in R_F's zeroing); elsewhere from
    s = 1e6 SolverFailedError (the Farkas vector no proof there, and the
    rigid motion missed: K's eigenvectors mixed a soft member's stretch
    into it).  The proof names the pads that lift."""
    with pytest.raises(NoSolutionError) as err:
        bar_beam(s, settle).solve()
    assert "N3, N4 lift off" in str(err.value), str(err.value)


def test_the_reported_forces_must_balance_the_loads():
    """The beam at s = 1e7 solved on its LCP as it was before the load
    column was kept (R_F's entries zeroed below R_ROUNDING κ|U|, κ = 4.4e16
    kN/m from the bar: every entry): every pad closed, the solve's own link
    forces balance K u − F (a 4.13 kN pull at N3), but N3 is reported
    separated with no force.  The frame's balance with the reported forces
    fails there, by name; before, it was ok."""
    fr = bar_beam(1e7)
    b = fr.build()
    b["RF"] = np.zeros_like(b["RF"])          # the load columns as they were lost
    combo = load_combination(fr, 1.0, None, b)
    M, Q, q_gap, *_ = contact_lcp.lcp_matrices(b)
    lcp = contact_lcp.combination_lcp(M, Q, q_gap, b, combo)
    r = fr.kind.result_from_z(fr, np.zeros(5), combo, "lost load", b=b, lcp=lcp)
    assert r.lcp_error == 0.0                 # the LCP that lost the load is solved exactly
    assert not r.ok and "CHECK FAILED" in r.message
    assert "-4.13 kN unbalanced at N3 (uy" in r.message, r.message
    pads = sum(s.normal for s in r.supports.values()) + r.reactions["N0"][1]
    assert pads == pytest.approx(24.875, abs=1e-9)          # against 20.745 of load


def test_a_pull_reported_as_zero_fails_a_space_frames_balance(monkeypatch):
    """The same guard on a space frame: a cantilever's tip on a pad, loaded
    upwards 3 kN, answered with the pad closed (z = 0) on an LCP that lost
    the load (and not polished: the polish on that point's states finds
    the lift) — the solve's link force pulls 3 kN, the pad is reported
    separated, and the reported forces leave the load at the tip
    unbalanced."""
    from formulations.frames.space import space_recovery

    monkeypatch.setattr(space_recovery.extended_refinement, "polished", lambda *a: None)
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 2.0, 0.0, 0.0)
    fr.add_member("A", "B", 2e8, 1e-2, 2e-5, 2e-5, G=8e7, J=4e-5)
    fr.add_support("A")
    fr.add_contact("B", normal=(0, 0, 1))
    fr.add_load("B", fz=3.0)
    b = fr.build()
    b["RF"] = np.zeros_like(b["RF"])
    combo = load_combination(fr, 1.0, None, b)
    M, Q, q_gap, *_ = contact_lcp.lcp_matrices(b)
    lcp = contact_lcp.combination_lcp(M, Q, q_gap, b, combo)
    r = fr.kind.result_from_z(fr, np.zeros(1), combo, "lost load", b=b, lcp=lcp)
    assert not r.ok and "unbalanced at B (uz" in r.message, r.message
    assert fr.solve().supports["B"].state == "separated"    # the right answer: it lifts


@pytest.mark.parametrize("deck", [2e8, 4e8])
def test_a_portal_with_a_deck_1e8_times_stiffer_is_no_mechanism(deck):
    """Before: "the frame is a mechanism even with every contact closed"
    (the basic system's pivots spread beyond 1e13 by the contrast); no
    motion leaves its members unstrained, so it is solved: the pads carry
    W/2 ∓ p h/b by moments about each foot."""
    W, h, b, p = 118.4, 5.0, 3.0, 20.0
    r = portal_on_pads(W, h, b, deck=deck).solve(p)
    assert r.ok, r.message
    assert r.supports["A"].normal == pytest.approx(W / 2 - p * h / b, rel=1e-9)
    assert r.supports["D"].normal == pytest.approx(W / 2 + p * h / b, rel=1e-9)


def test_a_portal_beyond_double_precision_is_said_to_be_so_not_a_mechanism():
    """Deck 1e10: its axial stiffness (7e16 kN/m) beside the columns' sway
    (400 kN/m) is beyond double precision — the basic system is singular
    in double.  Not called a mechanism: SolverFailedError saying why."""
    with pytest.raises(SolverFailedError, match="no mechanism"):
        portal_on_pads(118.4, 5.0, 3.0, deck=1e10).build()


def test_a_true_mechanism_is_still_refused_as_one():
    """A portal with both columns hinged at both ends on pinned pads sways
    freely: the kinematic test finds the motion, and the message says so."""
    fr = Frame()
    for n, x, y in (("A", 0, 0), ("B", 0, 4), ("C", 3, 4), ("D", 3, 0)):
        fr.add_node(n, x, y)
    fr.add_member("A", "B", E, A, I, hinge_i=True, hinge_j=True)
    fr.add_member("B", "C", 1e9 * E, A, 1e9 * I)
    fr.add_member("D", "C", E, A, I, hinge_i=True, hinge_j=True)
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_support("D", fix=("ux", "uy"))
    fr.add_load("B", fx=1.0)
    # ("is a mechanism": the words "no mechanism" of a frame beyond double
    # precision hold "mechanism" too)
    with pytest.raises(InvalidProblemError, match="the frame is a mechanism"):
        fr.solve()


@pytest.mark.parametrize("deck", [1.0, 1e7, 1e8])
def test_a_sway_mechanism_is_named_as_its_one_motion_at_any_contrast(deck):
    """The portal on two pinned bars (hinged at both ends) has one free
    motion, the deck's sway along x: the bars hold B and C vertically.
    Named from the members' geometry, not from the basic system's null
    space to rounding, which from a deck 1e7 times stiffer also held the
    bars' stretch — "turns rigidly about (1.5, 4)" and "translates rigidly
    along y; hold uy at one node", both false."""
    fr = Frame()
    for n, x, y in (("A", 0, 0), ("B", 0, 4), ("C", 3, 4), ("D", 3, 0)):
        fr.add_node(n, x, y)
    fr.add_member("A", "B", E, A, I, hinge_i=True, hinge_j=True)
    fr.add_member("B", "C", deck * E, A, deck * I)
    fr.add_member("D", "C", E, A, I, hinge_i=True, hinge_j=True)
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_support("D", fix=("ux", "uy"))
    fr.add_load("B", fx=1.0)
    with pytest.raises(InvalidProblemError, match="the frame is a mechanism") as err:
        fr.solve()
    words = str(err.value)
    assert "translates rigidly along x" in words, words
    assert "along y" not in words and "turns" not in words, words


@pytest.mark.parametrize("angle", [90.0, 17.0, 30.0, 45.0])
def test_a_node_between_two_opposite_pads_is_refused_as_redundant(angle):
    """A node between two pads of opposite normals: with every contact
    closed both links hold the same displacement, so the basic system is
    singular whatever the stiffnesses — refused, by name, as before the
    kinematic test (which finds no free motion there).  After it and
    before this guard: "no mechanism, but its stiffnesses differ by
    1.2e+00, beyond double precision", or at 90° and 17° the singular LU
    kept and the pads reported at 4e31 and 3e15 kN."""
    t = np.radians(angle)
    n = (float(np.cos(t)), float(np.sin(t)))
    fr = Frame()
    fr.add_node("A", 0, 0)
    fr.add_node("B", 4, 0)
    fr.add_node("C", 7, 1.3)
    fr.add_member("A", "B", E, A, I)
    fr.add_member("B", "C", E, A, I)
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_contact("C", normal=n)
    fr.add_contact("C", normal=(-n[0], -n[1]))
    fr.add_contact("B")
    fr.add_load("B", fy=-1.0)
    fr.add_load("C", fx=0.3)
    with pytest.raises(InvalidProblemError, match="redundant links"):
        fr.solve()


@pytest.mark.parametrize("friction", [0.0, 0.4])
def test_a_space_node_between_two_opposite_pads_is_refused_as_redundant(friction):
    """The same on a space cantilever's tip (normal and tangent links both
    doubled where the pads have friction)."""
    fr = SpaceFrame(cone="circumscribed")
    fr.add_node("A", 0, 0, 0)
    fr.add_node("B", 3, 0, 0)
    fr.add_member("A", "B", 2e8, 1e-2, 2e-5, 2e-5, G=8e7, J=4e-5)
    fr.add_support("A")
    fr.add_contact("B", normal=(0, 0, 1), friction=friction)
    fr.add_contact("B", normal=(0, 0, -1), friction=friction)
    fr.add_load("B", fz=-1.0)
    with pytest.raises(InvalidProblemError, match="redundant links"):
        fr.solve()


def pad_table(s, W=40.0, h=0.5, a=2.0):
    """Four legs h high on frictional pads (f 0.5) at the corners of a
    square a wide, their tops joined by a ring s times stiffer (E, I, G,
    J); W/4 at each top, p/4 pushing each along x."""
    fr = SpaceFrame(cone="circumscribed")
    for k, (x, y) in enumerate([(0.0, 0.0), (a, 0.0), (a, a), (0.0, a)]):
        fr.add_node(f"P{k}", x, y, 0.0)
        fr.add_node(f"T{k}", x, y, h)
        fr.add_member(f"P{k}", f"T{k}", 2e8, 0.01, 1e-4, 1e-4, G=8e7, J=2e-4)
        fr.add_contact(f"P{k}", friction=0.5, facets=8)
        fr.add_load(f"T{k}", fz=-W / 4)
        fr.add_load(f"T{k}", fx=0.25, case="variable")
    for k in range(4):
        fr.add_member(f"T{k}", f"T{(k + 1) % 4}", 2e8 * s, 0.01, 1e-4 * s, 1e-4 * s,
                      G=8e7 * s, J=2e-4 * s)
    return fr


@pytest.mark.parametrize("s", [2e7, 4e7])
def test_a_table_whose_top_is_1e7_times_stiffer_is_no_mechanism(s):
    """Before: "a mechanism even with every contact closed" (the legs'
    feet "free in rx, ry, rz"); solved, each back pad carries W/4 − p h/(2a)
    and each front one W/4 + p h/(2a)."""
    W, h, a, p = 40.0, 0.5, 2.0, 5.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = pad_table(s).solve(p)
    assert r.ok, r.message
    back, front = W / 4 - p * h / (2 * a), W / 4 + p * h / (2 * a)
    np.testing.assert_allclose([r.supports[f"P{k}"].normal for k in range(4)],
                               [back, front, front, back], rtol=1e-9)
