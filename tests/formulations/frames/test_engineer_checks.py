"""Frames tried as a structural engineer would, each answer against a
reference derived here by hand (statics, the three-moment equation, the
force method, the beam-column equation), none from the code under test.

* A beam in two frictionless V-grooves: each face carries P/(4 cos α)
  under its weight; pushed along its axis, one face of the pushed groove
  lifts at H = (P/2) tan α and the beam rides up the faces at P tan α — a
  translation along them, not a tipping.
* A three-hinged portal on frictional pads: thrust w L²/(8h) against
  w L/2 at each foot, so it stands at every load when f ≥ L/(4h) and at
  none below — where it spreads, its feet sliding apart (a mechanism, not
  a rigid body sliding away).
* A portal with pinned feet on two rigid pads under its weight, pushed
  sideways: the second-order trace's end against the windward pad's
  force falling to zero on the deformed frame, W b/2 = H h + W Δ.
* A continuous beam whose supports lift off (the three-moment equation on
  what still bears), a pad under a gap at, below and beyond the verge
  (the force method), a raised middle support lifting the far end.
* The same portal in kN and m and in N and mm (the same answers scaled),
  a table pushed along its diagonal (tipping about the leeward corner,
  W (a/√2)/h), and the sway buckling of a pinned-base portal with a
  flexible beam (kh tan kh = 6 I_b h/(I_c L)).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

from formulations.frames import Frame, SpaceFrame
from qpcontact.core.errors import NoSolutionError, SolverFailedError

pytestmark = pytest.mark.filterwarnings(
    "ignore::formulations.frames.LargeDisplacementWarning")

E, A, I = 2e8, 1e-2, 2e-5          # kN/m², m², m⁴


# -- a beam in two frictionless V-grooves --------------------------------------

def v_grooves(P=10.0, alpha=30.0, L=4.0) -> Frame:
    """Both ends of a beam in a groove whose faces rise at ±alpha (two
    frictionless contacts at each end node), P at midspan, a unit push
    along the beam at its left end (variable)."""
    a = np.radians(alpha)
    fr = Frame()
    for n, x in (("L", 0.0), ("M", L / 2), ("R", L)):
        fr.add_node(n, x, 0.0)
    fr.add_member("L", "M", E, A, I)
    fr.add_member("M", "R", E, A, I)
    for n in ("L", "R"):
        fr.add_contact(n, normal=(np.sin(a), np.cos(a)))      # the face that pushes right
        fr.add_contact(n, normal=(-np.sin(a), np.cos(a)))     # the face that pushes left
    fr.add_load("M", fy=-P)
    fr.add_load("L", fx=1.0, case="variable")
    return fr


def test_a_beam_in_v_grooves_by_hand():
    """Vertical statics give P/2 per groove; at a node the two faces'
    forces N1 (pushing right) and N2 (pushing left) balance V = P/2 and
    the push H: N1 + N2 = V / cos α, N2 − N1 = H / sin α.  The pushed
    groove's right-pushing face lifts at H = V tan α; beyond, the other
    groove takes the rest through the beam's axial force."""
    P, alpha = 10.0, 30.0
    a = np.radians(alpha)
    fr = v_grooves(P, alpha)
    V = P / 2
    for H in (0.0, 0.5 * V * np.tan(a)):
        s = fr.solve(p=H).supports
        assert s["L"].normal == pytest.approx((V / np.cos(a) - H / np.sin(a)) / 2, rel=1e-10)
        assert s["L#1"].normal == pytest.approx((V / np.cos(a) + H / np.sin(a)) / 2, rel=1e-10)
        assert s["R"].normal == pytest.approx(V / (2 * np.cos(a)), rel=1e-10)
    H = 1.5 * V * np.tan(a)
    r = fr.solve(p=H)
    assert r.ok, r.message
    rest = H - V * np.tan(a)
    assert r.supports["L"].state == "separated"
    assert r.supports["L#1"].normal == pytest.approx(V / np.cos(a), rel=1e-10)
    assert r.supports["R"].normal == pytest.approx((V / np.cos(a) - rest / np.sin(a)) / 2, rel=1e-10)
    assert r.supports["R#3"].normal == pytest.approx((V / np.cos(a) + rest / np.sin(a)) / 2,
                                                     rel=1e-10)


def test_a_beam_pushed_out_of_its_v_grooves_rides_up_the_faces():
    """At H = P tan α the beam rides up both grooves' left-pushing faces,
    lifting off the others: a translation along those faces (no
    tipping: nothing to turn about)."""
    P, alpha = 10.0, 30.0
    fr = v_grooves(P, alpha)
    tr = fr.trace()
    ref = P * np.tan(np.radians(alpha))
    assert tr.ok and tr.ended == "collapse", tr.message
    assert tr.limit[0] <= ref * (1 + 1e-12) and ref <= tr.limit[1] * (1 + 1e-12)
    assert "tips over" not in tr.message, tr.message
    assert "slides at L#1" in tr.message and "R#3" in tr.message, tr.message


# -- a three-hinged portal on frictional pads ----------------------------------

def three_hinged(f, L=8.0, h=4.0) -> Frame:
    """Columns on frictional pads (their feet pinned: a contact holds no
    rotation), a hinge at midspan of the beam, a uniform load on the beam
    (variable, 1 kN/m)."""
    fr = Frame()
    for n, x, y in (("A", 0, 0), ("B", 0, h), ("K", L / 2, h), ("C", L, h), ("D", L, 0)):
        fr.add_node(n, x, y)
    fr.add_member("A", "B", E, A, I, name="c1")
    fr.add_member("B", "K", E, A, I, name="b1", hinge_j=True)
    fr.add_member("K", "C", E, A, I, name="b2")
    fr.add_member("D", "C", E, A, I, name="c2")
    fr.add_contact("A", friction=f)
    fr.add_contact("D", friction=f)
    for m in ("b1", "b2"):
        fr.add_distributed_load(m, wy=-1.0, case="variable")
    return fr


def test_a_three_hinged_portal_stands_at_the_verge_of_its_friction():
    """Statically determinate: V = w L/2, thrust H = w L²/(8h) at each
    foot, the knee moment H h; it stands at any load while f ≥ L/(4h)
    (here 0.5), exactly at the verge included."""
    L, h, w = 8.0, 4.0, 5.0
    for f in (L / (4 * h), 1.01 * L / (4 * h)):
        fr = three_hinged(f, L, h)
        r = fr.solve(p=w)
        assert r.ok, r.message
        for n, sign in (("A", 1.0), ("D", -1.0)):
            assert r.supports[n].normal == pytest.approx(w * L / 2, rel=1e-10)
            assert r.supports[n].tangential == pytest.approx(sign * w * L ** 2 / (8 * h), rel=1e-10)
        assert abs(r.end_forces("c1")["j"]["M"]) == pytest.approx(w * L ** 2 / 8, rel=1e-10)
        tr = fr.trace()
        assert tr.ok and tr.ended == "unbounded", tr.message


def test_a_three_hinged_portal_below_its_friction_spreads():
    """At f = 0.99 L/(4h) no load is carried: the feet slide apart — a
    mechanism, which the message must not call a rigid body sliding
    away."""
    fr = three_hinged(0.99 * 8.0 / (4 * 4.0))
    with pytest.raises(NoSolutionError) as info:
        fr.solve(p=5.0)
    assert "rigid body" not in str(info.value).replace("not as a rigid body", "")
    assert "mechanism" in str(info.value)
    tr = fr.trace()
    assert tr.ended == "collapse" and tr.limit[1] <= 1e-6, tr.message
    assert "mechanism" in tr.message and "A (-t)" in tr.message and "D (+t)" in tr.message


# -- a portal on two rigid pads, to second order --------------------------------

def portal_on_pads(W, h, b, f=0.9, area=10.0, deck=1e4) -> Frame:
    """Columns (E, area × A, I) of height h with pinned feet on two rigid
    pads b apart, a beam ``deck`` times stiffer (E and I) between their
    tops, W/2 on each top, a unit push at the windward top (variable)."""
    fr = Frame()
    for n, x, y in (("A", 0, 0), ("B", 0, h), ("C", b, h), ("D", b, 0)):
        fr.add_node(n, x, y)
    fr.add_member("A", "B", E, area * A, I, name="L")
    fr.add_member("B", "C", deck * E, area * A, deck * I, name="T")
    fr.add_member("D", "C", E, area * A, I, name="R")
    fr.add_contact("A", friction=f)
    fr.add_contact("D", friction=f)
    fr.add_load("B", fy=-W / 2)
    fr.add_load("C", fy=-W / 2)
    fr.add_load("B", fx=1.0, case="variable")
    return fr


def second_order_tipping_push(W, h, b):
    """The push H at which the portal on pads tips on its deformed frame
    (the next test's docstring derives it): W b/2 = H h + W Δ, with the
    leeward column's sway Δ = H (tan kh − kh)/(W k), k = √(W/EI)."""
    k = np.sqrt(W / (E * I))
    return W * b / 2 / (h + (np.tan(k * h) - k * h) / k)


def test_a_portal_on_pads_tips_on_the_deformed_frame():
    """When the windward pad's force reaches zero it slips at f·0 = 0, so
    the leeward column carries the whole push and the whole weight: a
    column clamped at its top (the stiff beam) and pinned at its foot, whose
    sway under H and W is Δ = H (tan kh − kh)/(W k), k = √(W/EI).  Moments
    about the leeward foot on the deformed frame: W b/2 = H h + W Δ, so
    H = W b/2 / (h + (tan kh − kh)/k) (the beam's and the columns' own
    strains, left out here, move it by a few 1e-6).  The LCP path stops
    2.5e-7 short of the pad's zero (a degenerate vertex: the pad slipping
    at f N as N falls): the trace ended "bounded", ok True, against the
    first-order rigid body's limit; the pad's force falls to zero within
    1e-6 of that load, a fold, and the frame tips there."""
    h, b = 5.0, 3.0
    W = 0.05 * np.pi ** 2 * E * I / (4 * h ** 2)
    H_tip = second_order_tipping_push(W, h, b)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tr = portal_on_pads(W, h, b).trace(second_order=True)
    assert tr.ended == "stability" and tr.ok, (tr.ended, tr.ok, tr.message)
    assert tr.limit[0] == pytest.approx(H_tip, rel=5e-6), tr.message
    assert "A carries nothing" in tr.message


def test_a_second_order_path_that_stops_short_is_not_ok():
    """The same portal at 0.1 P_cr with members 1e3 times stiffer
    axially: its path turns back with the windward pad still carrying
    2e-4 kN, 1e-5 of the load before its zero (the stiffness is built from
    the axial forces 1e-3 of the last piece before the end), and it ends
    "bounded" — which was ok.  A bound is not a limit: not ok, its lower
    end within the hand value's 2e-5."""
    h, b = 5.0, 3.0
    W = 0.1 * np.pi ** 2 * E * I / (4 * h ** 2)
    H_tip = second_order_tipping_push(W, h, b)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tr = portal_on_pads(W, h, b, area=1e3).trace(second_order=True)
    if tr.ended == "stability":
        assert tr.ok and tr.limit[0] == pytest.approx(H_tip, rel=2e-5), tr.message
    else:
        assert tr.ended == "bounded" and not tr.ok, (tr.ended, tr.ok, tr.message)
        assert tr.bound[0] == pytest.approx(H_tip, rel=2e-5), tr.message
        # its upper end, W b/(2h), is the undeformed frame's: said so
        assert tr.bound[1] == pytest.approx(W * b / (2 * h), rel=1e-9)
        assert "undeformed" in tr.message and "P-Δ lowers the limit" in tr.message


# -- continuous beams: lift-off, a gap at its verge, a raised support ------------

def beam(spans, w=10.0, per_span=4, EI=(3e7, 1e-3)):
    """A beam over the given support positions, ``per_span`` members per
    span, w down on every member of the first span."""
    xs = [spans[0]]
    for a, c in zip(spans[:-1], spans[1:]):
        xs += [a + (c - a) * j / per_span for j in range(1, per_span + 1)]
    fr = Frame()
    for k, x in enumerate(xs):
        fr.add_node(f"N{k}", x, 0.0)
    for k in range(len(xs) - 1):
        fr.add_member(f"N{k}", f"N{k + 1}", EI[0], 0.1, EI[1], name=f"B{k}")
    for k in range(per_span):
        fr.add_distributed_load(f"B{k}", wy=-w)
    return fr


def test_three_spans_loaded_on_the_first_lift_off_the_far_pads():
    """Pins at 0 and L, pads at 2L and 3L, w on the first span: the
    first span alone is simply supported (20, 20; wL²/8 at midspan) and
    the rest turns up with its end slope wL³/(24EI): openings θL and 2θL.
    With the far end a bilateral support, only the pad at 2L lifts: the
    three-moment equation over spans L and 2L gives M1 = −wL²/24, so
    R0 = wL/2 + M1/L, R3 = M1/(2L) (a pull) and the pad opens by
    |M1| (2L)²/(16EI)."""
    L, w, EI = 4.0, 10.0, 3e7 * 1e-3
    fr = beam([0, L, 2 * L, 3 * L], w)
    fr.add_support("N0", fix=("ux", "uy"))
    fr.add_support("N4", fix=("uy",))
    fr.add_contact("N8")
    fr.add_contact("N12")
    r = fr.solve()
    assert r.ok, r.message
    theta = w * L ** 3 / (24 * EI)
    assert [r.supports[n].state for n in ("N8", "N12")] == ["separated", "separated"]
    assert r.supports["N8"].opening == pytest.approx(theta * L, rel=1e-10)
    assert r.supports["N12"].opening == pytest.approx(2 * theta * L, rel=1e-10)
    for n in ("N0", "N4"):
        assert r.reactions_by_node[n]["total"][1] == pytest.approx(w * L / 2, rel=1e-10)
    assert r.end_forces("B1")["j"]["M"] == pytest.approx(w * L ** 2 / 8, rel=1e-10)

    fr = beam([0, L, 2 * L, 3 * L], w)
    fr.add_support("N0", fix=("ux", "uy"))
    fr.add_support("N4", fix=("uy",))
    fr.add_contact("N8")
    fr.add_support("N12", fix=("uy",))
    r = fr.solve()
    M1 = -w * L ** 2 / 24
    assert r.supports["N8"].state == "separated"
    assert r.supports["N8"].opening == pytest.approx(abs(M1) * (2 * L) ** 2 / (16 * EI), rel=1e-10)
    R = [r.reactions_by_node[n]["total"][1] for n in ("N0", "N4", "N12")]
    R0, R3 = w * L / 2 + M1 / L, M1 / (2 * L)
    np.testing.assert_allclose(R, [R0, w * L - R0 - R3, R3], rtol=1e-10)
    assert r.end_forces("B4")["i"]["M"] == pytest.approx(M1, rel=1e-10)


@pytest.mark.parametrize("share", [0.5, 1.0 - 1e-9, 1.0, 1.0 + 1e-9, 1.5])
def test_a_pad_under_a_gap_at_below_and_beyond_its_verge(share):
    """A beam of 2L pinned at its ends, w over it, a rigid pad at midspan
    under a gap g = share × δ0, δ0 = 5w(2L)⁴/(384EI) its free deflection:
    the pad carries (δ0 − g) 48EI/(2L)³ where the beam reaches it, nothing
    otherwise; midspan moves down by min(δ0, g)."""
    L, w, EI = 4.0, 10.0, 3e7 * 1e-3
    d0 = 5 * w * (2 * L) ** 4 / (384 * EI)
    fr = beam([0, L, 2 * L], w, per_span=4)
    for k in range(4, 8):
        fr.add_distributed_load(f"B{k}", wy=-w)
    fr.add_support("N0", fix=("ux", "uy"))
    fr.add_support("N8", fix=("uy",))
    fr.add_contact("N4", gap=share * d0)
    r = fr.solve()
    assert r.ok, r.message
    X = max(d0 - share * d0, 0.0) * 48 * EI / (2 * L) ** 3
    assert r.supports["N4"].normal == pytest.approx(X, abs=1e-9 * 2 * w * L)
    assert r.displacements["N4"][1] == pytest.approx(-min(d0, share * d0), rel=1e-10)
    assert r.supports["N4"].opening == pytest.approx(max(share * d0 - d0, 0.0), abs=1e-12 * d0)


@pytest.mark.parametrize("share", [0.5, 2.0])
def test_a_raised_middle_support_lifts_the_far_end_pad(share):
    """Pin at 0, a bilateral support at L raised by s, a pad at 2L, w
    over both spans.  While the pad bears, the force method on the simple
    beam of 2L: X_mid = (δ0 + s) 48EI/(2L)³, R_end = (2wL − X_mid)/2; it
    lifts at s* = 2wL (2L)³/(48EI) − δ0.  Beyond, the beam is an
    overhanging one on 0 and L (R0 = 0, R_L = 2wL by statics) and the pad
    opens by 2s − w a (4a²L − L³ + 3a³)/(24EI), a = L."""
    L, w, EI = 4.0, 10.0, 3e7 * 1e-3
    d0 = 5 * w * (2 * L) ** 4 / (384 * EI)
    s_star = 2 * w * L * (2 * L) ** 3 / (48 * EI) - d0
    s = share * s_star
    fr = beam([0, L, 2 * L], w)
    for k in range(4, 8):
        fr.add_distributed_load(f"B{k}", wy=-w)
    fr.add_support("N0", fix=("ux", "uy"))
    fr.add_support("N4", fix=("uy",))
    fr.add_settlement("N4", "constant", uy=s)
    fr.add_contact("N8")
    r = fr.solve()
    assert r.ok, r.message
    pad = r.supports["N8"]
    if s < s_star:
        X = (d0 + s) * 48 * EI / (2 * L) ** 3
        assert pad.normal == pytest.approx((2 * w * L - X) / 2, rel=1e-10)
        assert r.reactions_by_node["N4"]["total"][1] == pytest.approx(X, rel=1e-10)
    else:
        assert pad.state == "separated"
        assert r.reactions_by_node["N4"]["total"][1] == pytest.approx(2 * w * L, rel=1e-10)
        assert abs(r.reactions_by_node["N0"]["total"][1]) <= 1e-10 * w * L
        opening = 2 * s - w * L * (4 * L ** 3 - L ** 3 + 3 * L ** 3) / (24 * EI)
        assert pad.opening == pytest.approx(opening, rel=1e-10)


# -- units, a diagonal push in space, sway buckling ------------------------------

def pushed_portal(f, h, b, W, length=1.0, force=1.0) -> Frame:
    """A portal on two rigid frictional pads, W/2 on each top, a push at
    the windward top of 1 kN (variable), in kN and m (length = force = 1)
    or in N and mm (1e3, 1e3): E in force/length², A and I scaled."""
    fr = Frame(units=("kN", "m") if length == 1.0 else ("N", "mm"))
    Es, As, Is = 2e8 * force / length ** 2, 1e-2 * length ** 2, 2e-4 * length ** 4
    for n, x, y in (("A", 0, 0), ("B", 0, h), ("C", b, h), ("D", b, 0)):
        fr.add_node(n, x * length, y * length)
    fr.add_member("A", "B", Es, As, Is)
    fr.add_member("B", "C", Es, As, Is)
    fr.add_member("D", "C", Es, As, Is)
    fr.add_contact("A", friction=f)
    fr.add_contact("D", friction=f)
    fr.add_load("B", fy=-W / 2 * force)
    fr.add_load("C", fy=-W / 2 * force)
    fr.add_load("B", fx=force, case="variable")
    return fr


@pytest.mark.parametrize("f, h, b", [(0.3, 4.0, 6.0), (0.9, 6.0, 3.0)])
def test_a_portal_on_pads_gives_way_at_the_same_load_in_kn_m_and_n_mm(f, h, b):
    """It slides at f W or tips about the leeward foot at W b/(2h),
    whichever is less (moments about the toe); in N and mm the same load
    factor, the same first slip, the pads' forces 1e3 times larger."""
    W = 100.0
    ref = min(f * W, W * b / (2 * h))
    traces = []
    for length, force in ((1.0, 1.0), (1e3, 1e3)):
        tr = pushed_portal(f, h, b, W, length, force).trace()
        assert tr.ok and tr.ended == "collapse", tr.message
        assert tr.limit[0] == pytest.approx(ref, rel=1e-12)
        traces.append(tr)
    np.testing.assert_allclose(traces[1].breakpoints, traces[0].breakpoints, rtol=1e-10)
    p = 0.999 * ref
    kn = pushed_portal(f, h, b, W).solve(p=p)
    n = pushed_portal(f, h, b, W, 1e3, 1e3).solve(p=p)
    for pad in ("A", "D"):
        assert n.supports[pad].normal == pytest.approx(1e3 * kn.supports[pad].normal, abs=1e-7 * W)
        assert n.supports[pad].state == kn.supports[pad].state
    # moments about the leeward foot: N_A = W/2 − p h/b
    assert kn.supports["A"].normal == pytest.approx(W / 2 - p * h / b, abs=1e-10 * W)


def test_a_table_pushed_along_its_diagonal_tips_about_the_far_corner():
    """A square table (legs a apart, deck at h) on four rigid frictional
    pads, weight W, pushed at a corner of the deck along the diagonal:
    it tips when the push's moment about the line through the far leg
    across the diagonal, H h, reaches W a/√2 (the centre's distance from
    that line) — before it slides (μ W)."""
    a, h, W, mu = 2.0, 3.0, 40.0, 0.8
    fr = SpaceFrame(cone="inscribed")
    for k, (x, y) in enumerate([(0, 0), (a, 0), (a, a), (0, a)]):
        fr.add_node(f"P{k}", x, y, 0.0)
        fr.add_node(f"T{k}", x, y, h)
        fr.add_member(f"P{k}", f"T{k}", 2e8, 0.01, 1e-4, 1e-4, G=8e7, J=2e-4)
        fr.add_contact(f"P{k}", normal=(0, 0, 1), friction=mu)
        fr.add_load(f"T{k}", fz=-W / 4)
    for i, j in ((0, 1), (1, 2), (2, 3), (3, 0), (0, 2)):
        fr.add_member(f"T{i}", f"T{j}", 2e8, 0.1, 1e-3, 1e-3, G=8e7, J=2e-3)
    fr.add_load("T0", fx=1 / np.sqrt(2), fy=1 / np.sqrt(2), case="variable")
    ref = W * (a / np.sqrt(2)) / h
    tr = fr.trace()
    assert tr.ok and tr.ended == "collapse", tr.message
    assert tr.limit[0] <= ref * (1 + 1e-9) and ref <= tr.limit[1] * (1 + 1e-9)
    r = fr.solve(p=0.999 * ref)
    assert r.ok, r.message
    # all but the far leg nearly unloaded: its force W − 3 × (the others)
    n = [r.supports[f"P{k}"].normal for k in range(4)]
    assert n[2] == pytest.approx(W - n[0] - n[1] - n[3], rel=1e-12) and n[2] > 0.99 * W
    with pytest.raises(NoSolutionError, match="tips over"):
        fr.solve(p=1.001 * ref)


@pytest.mark.parametrize("beam_share, L", [(1.0, 6.0), (3.0, 4.0), (0.2, 8.0)])
def test_a_pinned_base_portal_buckles_in_sway_as_its_transcendental_equation(beam_share, L):
    """Feet pinned, P on each column top, the beam (I_b = beam_share × I)
    bent in double curvature by the sway (6 E I_b / L at each end): the
    column's top is held by that spring, its foot free to turn, and the
    sway buckling load solves kh tan kh = 6 I_b h / (I L), k² = P/EI.  The
    members are nearly inextensible (A × 1e3): the equation's
    assumption."""
    h, P = 5.0, 40.0         # below the buckling load of each case
    fr = Frame()
    for n, x, y in (("A", 0, 0), ("B", 0, h), ("C", L, h), ("D", L, 0)):
        fr.add_node(n, x, y)
    fr.add_member("A", "B", E, 1e3 * A, I)
    fr.add_member("B", "C", E, 1e3 * A, beam_share * I)
    fr.add_member("D", "C", E, 1e3 * A, I)
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_support("D", fix=("ux", "uy"))
    fr.add_load("B", fy=-P)
    fr.add_load("C", fy=-P)
    r = fr.solve(second_order=True)
    assert r.ok, r.message
    c = 6 * beam_share * h / L
    kh = brentq(lambda x: x * np.tan(x) - c, 1e-9, np.pi / 2 - 1e-12)
    crit = fr.critical_load_factor(r)
    ref = kh ** 2 * E * I / h ** 2 / P
    # the eigenvalue count's rounding band (a few n eps of the Jacobi-scaled
    # matrix, on members 1e3 times stiffer axially) is ~1e-6 wide; alpha is
    # its lower end, and extensible members buckle a little below the
    # equation's inextensible ones (its upper end 6e-7 below on one case)
    lo, hi = crit["bracket"]
    assert crit["alpha"] == lo <= hi
    assert ref * (1 - 2e-6) <= lo <= ref * (1 + 1e-9)
    assert hi == pytest.approx(ref, rel=1e-6)


# -- a column under a growing vertical load, to second order ---------------------

def column_on_footing(H=0.0, h=6.0, a=3.0) -> Frame:
    """A column (E, A, I) of height h clamped to a footing beam 1e4 times
    stiffer on two rigid frictional pads at ±a (wide: it buckles before it
    tips), the footing's weight on the pads, H across the top (constant),
    a unit vertical load on the top (variable)."""
    fr = Frame()
    for n, x in (("L", -a), ("O", 0.0), ("R", a)):
        fr.add_node(n, x, 0.0)
    fr.add_node("T", 0.0, h)
    fr.add_member("L", "O", 1e2 * E, 10 * A, 1e2 * I)
    fr.add_member("O", "R", 1e2 * E, 10 * A, 1e2 * I)
    fr.add_member("O", "T", E, A, I, name="column")
    fr.add_contact("L", friction=0.8)
    fr.add_contact("R", friction=0.8)
    fr.add_load("L", fy=-1.0)
    fr.add_load("R", fy=-1.0)
    if H:
        fr.add_load("T", fx=H)
    fr.add_load("T", fy=-1.0, case="variable")
    return fr


@pytest.mark.parametrize("H, p_max", [(0.0, None), (0.5, None), (0.0, 300.0)])
def test_a_column_under_a_growing_load_is_not_unbounded_to_second_order(H, p_max):
    """Its compression grows with p, so on the deformed frame it buckles
    at Euler's P_cr = π²EI/(4h²) (274 kN; the footing's flexibility lowers
    it by 1.7e-5): the second-order trace, one stiffness for the whole
    path, said "unbounded" and ok (or, traced to 300, that it "stands up to
    p = 0"); it now says what it cannot follow, is not ok, and names the
    buckling load."""
    h = 6.0
    P_cr = np.pi ** 2 * E * I / (4 * h ** 2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tr = column_on_footing(H, h).trace(p_max, second_order=True)
    assert not tr.ok and tr.ended != "unbounded" and tr.limit is None, tr.message
    assert "compression" in tr.message
    found = float(tr.message.split("buckles at p = ")[1].split(" ")[0])
    assert found == pytest.approx(P_cr, rel=5e-5)


def test_a_column_that_stands_is_never_proved_to_fall():
    """Under its constant loads alone (H = 0.5 across a 6 m column, the
    footing's 2 kN on pads 3 m either side) the column stands by statics:
    the windward pad keeps 1 − H h/(2a) = 0.5 kN.  Traced to 200 (73 % of
    its buckling load) on the end's second-order stiffness, Lemke's method
    found no start at p = 0 and the trace raised NoSolutionError — a proof
    that nothing stands — with "does not prove there is no solution" in
    its words; later it raised SolverFailedError: on the end's stiffness
    at p = 0 the P-Δ terms of the end's compression act without the load
    that makes it (and holds the footing down), and there the column tips.
    The path on that stiffness starts where it stands: the windward pad's
    force 1 + p/2 − M/(2a) reaches zero, M = H h + N Δ the moment of a
    cantilever beam-column under N and H, Δ = H (tan kh − kh)/(k N),
    k² = N/EI, so p₀ = M/a − 2 (N the end's compression the stiffness is
    built from, which the trace reports; the footing's flexibility moves it
    by 1.3e-4)."""
    H, h, a = 0.5, 6.0, 3.0
    fr = column_on_footing(H, h, a)
    r = fr.solve(p=0.0, second_order=True)
    assert r.ok and r.supports["L"].normal == pytest.approx(1.0 - H * h / (2 * a), rel=1e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tr = fr.trace(200.0, second_order=True)
    assert tr.ok and tr.ended == "p_max" and tr.p_end == 200.0, tr.message
    N = -tr.second_order["axial"]["column"]
    k = np.sqrt(N / (E * I))
    M = H * h + N * H * (np.tan(k * h) - k * h) / (k * N)
    p0 = float(tr.message.split("the path starts at p = ")[1].split(",")[0])
    assert p0 == pytest.approx(M / a - 2.0, rel=5e-4)
    assert tr.intervals[0][0] == pytest.approx(p0, rel=1e-9)
    # at 200 the windward pad's force by the same statics, N = 200
    k = np.sqrt(200.0 / (E * I))
    M = H * h + H * (np.tan(k * h) - k * h) / k
    assert tr.result_at(200.0).supports["L"].normal == pytest.approx(1.0 + 100.0 - M / (2 * a),
                                                                     rel=1e-4)


@pytest.mark.parametrize("f", [0.5, 0.3])
def test_a_beam_on_a_slope_sticks_or_slides_up_by_hand(f):
    """A beam along a 20° slope on two frictional pads (normals across the
    slope), W at its middle: it sticks under its weight iff f ≥ tan α, each
    pad carrying W cos α/2; pushed horizontally at its middle (no
    overturning: the push acts on the slope's line) it slides up the slope
    when P cos α − W sin α = f (W cos α + P sin α)."""
    W, L, alpha = 20.0, 4.0, np.radians(20.0)
    c, s = np.cos(alpha), np.sin(alpha)
    fr = Frame()
    for n, k in (("A", 0.0), ("M", 0.5), ("B", 1.0)):
        fr.add_node(n, k * L * c, k * L * s)
    fr.add_member("A", "M", E, A, I)
    fr.add_member("M", "B", E, A, I)
    for n in ("A", "B"):
        fr.add_contact(n, normal=(-s, c), friction=f)
    fr.add_load("M", fy=-W)
    fr.add_load("M", fx=1.0, case="variable")
    if f < np.tan(alpha):
        with pytest.raises(NoSolutionError, match="slides away as a rigid body"):
            fr.solve(p=0.0)
        return
    r = fr.solve(p=0.0)
    assert [r.supports[n].normal for n in ("A", "B")] == pytest.approx([W * c / 2] * 2, rel=1e-10)
    # the friction holds the weight's component along the slope (t = (cos α, sin α))
    assert sum(r.supports[n].tangential for n in ("A", "B")) == pytest.approx(W * s, rel=1e-10)
    tr = fr.trace()
    ref = W * (s + f * c) / (c - f * s)
    assert tr.ok and tr.ended == "collapse", tr.message
    assert tr.limit[0] <= ref * (1 + 1e-12) and ref <= tr.limit[1] * (1 + 1e-12)


# -- a deck 1e12 times stiffer than its columns ----------------------------------

@pytest.mark.parametrize("deck", [1e4, 1e6, 3e6])
def test_a_portal_with_a_rigid_deck_slides_and_tips_by_hand(deck):
    """The portal on two rigid pads (pinned feet, f 0.9) with its deck's E
    and I both ``deck`` times the columns' (EI contrast deck²): moments
    about the leeward foot give N_A = W/2 − p h/b, and it tips at
    W b/(2h).  At deck 1e6 the contact stiffness R, refined in extended
    precision, had its entries zeroed below eps·κ (κ: the deck's axial
    stiffness, 1.8e15 kN/m), which is above the frame's sway stiffness
    (48 kN/m): M was zero and "no equilibrium exists" was "proved" at
    p = 30, below the limit 35.52."""
    W, h, b = 118.4, 5.0, 3.0
    fr = portal_on_pads(W, h, b, deck=deck)
    limit = W * b / (2 * h)
    for p in (20.0, 30.0, 0.999 * limit):
        res = fr.solve(p=p)
        assert res.ok, res.message
        assert res.supports["A"].normal == pytest.approx(W / 2 - p * h / b, abs=1e-9 * W)
    with pytest.raises(NoSolutionError, match="tips over about D"):
        fr.solve(p=1.001 * limit)


# -- stiff members beside soft ones: statics, not rounding, decides ---------------

def test_a_soft_span_beside_a_stiff_one_is_not_a_mechanism():
    """A beam on a pin (settled 1 cm) and three pads, hinged at N2 after a
    span 1.5e6 times stiffer than the first: N1's pad carries
    (0.713·3 − 0.26·6)/3 = 0.193 kN by moments about the pin, N3's 10 kN.
    The first span's bending, next to the stiff one, has an eigenvalue of
    K scaled by its diagonal of 3e-13 (the contrast squared), under the
    null space's 1e-10: it was read as a rigid motion, and "no
    equilibrium exists" proved.  An answer or an honest doubt, not that."""
    fr = Frame()
    for k in range(4):
        fr.add_node(f"N{k}", 3.0 * k, 0.0)
    for k, (s, hinge) in enumerate([(1.0, False), (1.5e6, True), (1.8, False)]):
        fr.add_member(f"N{k}", f"N{k + 1}", s * E, A, s * I, hinge_j=hinge)
    fr.add_support("N0", fix=("ux", "uy"))
    for k in range(1, 4):
        fr.add_contact(f"N{k}")
    fr.add_settlement("N0", uy=-0.01)
    for k, q in zip(range(1, 4), (-0.713, 0.26, -10.0)):
        fr.add_load(f"N{k}", fy=q)
    res = fr.solve()
    assert res.supports["N1"].normal == pytest.approx((0.713 * 3 - 0.26 * 6) / 3, rel=0.02)
    assert res.supports["N3"].normal == pytest.approx(10.0, rel=1e-6)


def test_past_a_stiffness_contrast_of_1e6_a_farkas_vector_is_no_proof():
    """A beam pinned at N0 (settled 10 mm down) on frictionless pads at
    N1–N4, spans E·I scaled by 7.1e6, 2.1e2, 18 (hinged at its right end)
    and 3.3e8: by hand the right span takes N4's 10 kN (no shear through
    the hinge) and the left part balances with N1 = 14.34 kN — the same
    beam with equal spans is certified so.  At this contrast R is refined
    and its small entries carry rounding; Lemke's Farkas vector on them
    "proved" that it tips.  It is not called a proof: SolverFailedError,
    never NoSolutionError (or an answer, which must then be right, or is
    not ok: since the load columns R_F are zeroed at their own rounding,
    Lemke answers this LCP, and the frame's recovery in double does not
    carry its digits — "CHECK FAILED", no claim)."""
    fr = Frame()
    for k in range(5):
        fr.add_node(f"N{k}", 3.0 * k, 0.0)
    for k, (s, hinge) in enumerate([(7.1e6, False), (2.1e2, False), (18.0, True),
                                    (3.3e8, False)]):
        fr.add_member(f"N{k}", f"N{k + 1}", s * E, A, s * I, hinge_j=hinge)
    fr.add_support("N0", fix=("ux", "uy"))
    for k in range(1, 5):
        fr.add_contact(f"N{k}")
    fr.add_settlement("N0", uy=-0.01)
    for k, q in ((1, -9.117), (2, -5.863), (3, 2.167), (4, -10.0)):
        fr.add_load(f"N{k}", fy=q)
    try:
        res = fr.solve()
    except SolverFailedError as exc:
        assert "not a proof" in str(exc) or "nothing was proved" in str(exc), str(exc)
        return
    assert not res.ok and "CHECK FAILED" in res.message \
        or res.ok and res.supports["N4"].normal == pytest.approx(10.0, rel=1e-6), res.message
