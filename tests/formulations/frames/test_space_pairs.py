"""Node-to-node contact pairs of space frames (``SpaceFrame.add_contact(...,
other=)``), against references independent of the code under test.

* Parity: a frame built in the x-y plane of a space frame (uz, rx, ry held
  at every node) with pairs — frictionless and frictional, rigid and
  elastic, with gaps, sticking and sliding, a tilted normal — against the
  plane frame (:class:`~formulations.frames.Frame`), which has its own
  elements, links, LCP layout and results: the same displacements, contact
  forces and states to 1e-10 of each quantity's scale, on the faceted
  route (Lemke) and on the circular cone (the friction solvers and the
  active set on the circle: with the out-of-plane tangent held the cone is
  the segment the plane frame has), and the same load trace.
* Hand statics: two equal cantilevers, tip D resting on tip B, the pair's
  normal along z (out of the plane of the two cantilevers).  By the force
  method, with X the pair's force (up on D, down on B), P down on D and
  c = L³/(3 E Iy) each tip's flexibility along z:

      w_D = −P c + X c,   w_B = −X c,
      opening = g + w_D − w_B = g − P c + 2 X c = 0  ⇒  X = (P c − g)/(2c),

  [X] = force, [c] = length/force, [g] = length; X ≥ 0 needs g ≤ P c, and a
  gap g > P c is never closed: the pair separates with opening g − P c.
  A sideways load Q along y on D, the tips' stiffnesses along y k_D =
  3 E Iz_D / L³ and k_B = 3 E Iz_B / L³ (decoupled from z): while the pair
  sticks the tips move together, (Q − T)/k_D = T/k_B, so the friction force
  on B is T = Q k_B/(k_B + k_D) (on D −T); beyond f X_n the pair slides and
  T = f X_n — the breakpoint at Q* = f X_n (k_B + k_D)/k_B.
* Misuse: ``other`` equal to the node, an unknown ``other``, a pair whose
  normal the bilateral supports at both its nodes fix."""

from __future__ import annotations

import numpy as np
import pytest

from formulations.frames import Frame, SpaceFrame
from qpcontact.core.errors import InvalidProblemError

E, G = 2.1e8, 8.1e7           # kN/m²
RTOL = 1e-10


# -- parity with the plane frame ---------------------------------------------

#: two beams stacked: the lower one (C-N-D) on ground pads, the upper one
#: (A-M-B) on it through three pairs — A on C rigid with friction, B on D
#: elastic with friction, a gap and a tilted normal (it slides), M on N
#: frictionless with a gap (it closes)
PAIRS = [("C", (0.0, 1.0), 0.3, 0.0, None, None), ("D", (0.0, 1.0), 0.3, 0.0, 2e4, None),
         ("A", (0.0, 1.0), 0.2, 0.0, None, "C"), ("B", (0.1, 1.0), 0.2, 1e-4, 5e4, "D"),
         ("M", (0.0, 1.0), 0.0, 2e-4, None, "N")]


def _stacked(cone="circumscribed", pairs=PAIRS):
    """The stacked beams as a Frame and in the x-y plane of a SpaceFrame
    (z = 0; uz, rx, ry held at every node; each member's Iz the plane
    member's I): 3 kN/m on the upper beam, p x (1 along x at A, 1 down at
    M)."""
    plane, space = Frame(), SpaceFrame(cone=cone)
    nodes = {"A": (0, 1), "M": (2, 1), "B": (4, 1), "C": (0, 0), "N": (2, 0), "D": (4, 0)}
    for k, (x, y) in nodes.items():
        plane.add_node(k, x, y)
        space.add_node(k, x, y, 0.0)
        space.add_support(k, fix=("uz", "rx", "ry"))
    for i, j, A, I, name in (("A", "M", 0.004, 2e-6, "U1"), ("M", "B", 0.004, 2e-6, "U2"),
                             ("C", "N", 0.01, 8e-5, "L1"), ("N", "D", 0.01, 8e-5, "L2")):
        plane.add_member(i, j, E, A, I, name=name)
        # Iy and J are never strained (out-of-plane motion held): any values
        space.add_member(i, j, E, A, 3e-5, I, G=G, J=1e-5, name=name)
    for node, n, f, gap, k, other in pairs:
        plane.add_contact(node, normal=n, friction=f, gap=gap, stiffness=k, other=other)
        space.add_contact(node, normal=(n[0], n[1], 0.0), friction=f, gap=gap, stiffness=k,
                          other=other)
    for name in ("U1", "U2"):
        plane.add_distributed_load(name, wy=-3.0)
        space.add_distributed_load(name, wy=-3.0)
    for fr in (plane, space):
        fr.add_load("A", fx=1.0, case="variable")
        fr.add_load("M", fy=-1.0, case="variable")
    return plane, space


def _same(plane, r2, r3):
    """r3 (space, x-y plane) against r2 (plane), each on its own scale."""
    assert r2.ok and r3.ok, (r2.message, r3.message)
    d2 = np.array([r2.displacements[n] for n in plane.nodes])
    d3 = np.array([r3.displacements[n] for n in plane.nodes])
    np.testing.assert_allclose(d3[:, :2], d2[:, :2], rtol=0, atol=RTOL * np.abs(d2[:, :2]).max())
    np.testing.assert_allclose(d3[:, 5], d2[:, 2], rtol=0, atol=RTOL * np.abs(d2[:, 2]).max())
    assert np.all(d3[:, 2:5] == 0.0)                       # held
    force = max(s.normal for s in r2.supports.values())
    assert list(r3.supports) == list(r2.supports)          # "C", ..., "A-C", "B-D", "M-N"
    for c, key in zip(plane.contacts, r2.supports):
        s2, s3 = r2.supports[key], r3.supports[key]
        t = np.array([c.normal[1], -c.normal[0], 0.0])      # the plane frame's tangent
        state = s3.state
        if state == "slip":
            state += "+" if s3.slip_global @ t > 0 else "-"
        assert state == s2.state, (key, s2, s3)
        np.testing.assert_allclose([s3.normal, s3.tangential_global @ t,
                                    s3.tangential_global[2], s3.opening],
                                   [s2.normal, s2.tangential, 0.0, s2.opening], rtol=0,
                                   atol=RTOL * max(force, 1.0))
        # (a sticking pair's slip is rounding of its own size: zero to the digits)
        if s2.state != "stick":
            assert s3.slip_global @ t == pytest.approx(s2.slip, abs=RTOL * np.abs(d2).max())
    for node, rea in r3.reactions.items():     # (every node holds uz, rx, ry in space)
        np.testing.assert_allclose(np.asarray(rea)[[0, 1, 5]],
                                   r2.reactions.get(node, (0.0, 0.0, 0.0)), rtol=0,
                                   atol=RTOL * force)
    # a pair is a force between two parts, not a reaction of the ground
    by_node = [{n for n, parts in r.reactions_by_node.items() if "contact" in parts}
               for r in (r2, r3)]
    assert by_node[0] == by_node[1] == {"C", "D"}
    np.testing.assert_allclose(r3.support_reactions["A-C"][:2], r2.support_reactions["A-C"][:2],
                               rtol=0, atol=RTOL * force)


@pytest.mark.parametrize("cone", ["circumscribed", "inscribed", "circular"])
def test_pairs_in_a_planar_frame_built_in_space_answer_as_the_plane_frame(cone):
    """At p = 0.2 and 0.5: C, D, A-C stick, B-D slides (its normal tilted,
    elastic), M-N (frictionless) closes its gap; a gap of 5 cm there stays
    open — on every cone (a pair whose out-of-plane tangent
    both its nodes hold has the plane frame's segment, on every cone)."""
    plane, space = _stacked(cone)
    states = set()
    for p in (0.2, 0.5):
        r2, r3 = plane.solve(p), space.solve(p)
        _same(plane, r2, r3)
        states |= {(k, s.state) for k, s in r2.supports.items()}
    plane, space = _stacked(cone, PAIRS[:4] + [("M", (0.0, 1.0), 0.0, 0.05, None, "N")])
    r2, r3 = plane.solve(0.5), space.solve(0.5)
    _same(plane, r2, r3)
    states |= {(k, s.state) for k, s in r2.supports.items()}
    # the cases the parity covers (the plane frame's states, not the space frame's)
    assert {("A-C", "stick"), ("B-D", "slip+"), ("M-N", "closed"),
            ("M-N", "separated")} <= states


def test_pairs_trace_as_the_plane_frame():
    """The polygon's exact load path with pairs: the same end, the same
    limit and the same collapse words as the plane frame's (slips written
    (+t) there, (along (x, y, z)) in space)."""
    plane, space = _stacked()
    t2, t3 = plane.trace(), space.trace()
    assert t3.ended == t2.ended
    np.testing.assert_allclose(t3.p_end, t2.p_end, rtol=RTOL)
    np.testing.assert_allclose(t3.breakpoints, t2.breakpoints, rtol=RTOL)
    for a, b in zip(t2.states, t3.states):
        _same(plane, a, b)
    words = [m.split("no equilibrium exists")[1].split(" (")[0] for m in (t2.message, t3.message)]
    assert words[0].split(": friction")[0] == words[1].split(": friction")[0]


# -- hand statics: two cantilevers tip on tip, out of their plane --------------

L, IY, IZ_B, IZ_D, A_ = 2.0, 4e-6, 6e-6, 2e-6, 0.005
C_TIP = L ** 3 / (3 * E * IY)                       # m/kN, each tip along z


def _tips(cone="circular", gap=0.0, friction=0.0, P=10.0, Q=0.0):
    """Cantilever A-B along x (Iz_B) and C-D beside it (Iz_D), both fixed at
    the root; D rests on B through a pair with normal +z (pushing D up and
    B down); P down and Q along y on D (case "variable": Q per unit p)."""
    fr = SpaceFrame(cone=cone)
    for name, xyz in (("A", (0, 0, 0)), ("B", (L, 0, 0)), ("C", (0, 1, 0)), ("D", (L, 1, 0))):
        fr.add_node(name, *xyz)
    fr.add_member("A", "B", E, A_, IY, IZ_B, G=G, J=1e-5)
    fr.add_member("C", "D", E, A_, IY, IZ_D, G=G, J=1e-5)
    fr.add_support("A")
    fr.add_support("C")
    fr.add_contact("D", normal=(0, 0, 1), friction=friction, gap=gap, other="B")
    fr.add_load("D", fz=-P)
    if Q:
        fr.add_load("D", fy=Q, case="variable")
    return fr


@pytest.mark.parametrize("cone", ["circular", "inscribed", "circumscribed"])
@pytest.mark.parametrize("gap", [0.0, 0.3, 0.9])       # per P c
def test_tip_on_tip_closes_at_the_force_methods_force(cone, gap):
    """X = (P c − g)/(2c) on D (up) and B (down) while g <= P c; the tips
    then deflect together, −(P c + g)/2 and −(P c − g)/2."""
    P = 10.0
    g = gap * P * C_TIP
    res = _tips(cone, gap=g, friction=0.3, P=P).solve()
    assert res.ok, res.message
    s = res.supports["D-B"]
    X = (P * C_TIP - g) / (2 * C_TIP)
    assert s.state == "stick"
    assert s.normal == pytest.approx(X, rel=1e-9)
    np.testing.assert_allclose(s.tangential_global, 0.0, atol=1e-9 * X)
    assert res.displacements["D"][2] == pytest.approx(-(P * C_TIP + g) / 2, rel=1e-9)
    assert res.displacements["B"][2] == pytest.approx(-(P * C_TIP - g) / 2, rel=1e-9)
    # the pair's force on D (the support table's "node") is +X along z
    np.testing.assert_allclose(res.support_reactions["D-B"], (0.0, 0.0, X), atol=1e-9 * X)
    # the roots carry P between them as the tips' shares: X at A, P − X at C
    assert res.reactions["A"][2] == pytest.approx(X, rel=1e-9)
    assert res.reactions["C"][2] == pytest.approx(P - X, rel=1e-9)


@pytest.mark.parametrize("cone", ["circular", "inscribed", "circumscribed"])
def test_a_gap_wider_than_the_tips_deflection_stays_open(cone):
    """g = 1.5 P c: D comes down P c and stops g − P c short of B."""
    P = 10.0
    g = 1.5 * P * C_TIP
    res = _tips(cone, gap=g, friction=0.3, P=P).solve()
    assert res.ok, res.message
    s = res.supports["D-B"]
    assert s.state == "separated" and s.normal == 0.0
    assert s.opening == pytest.approx(g - P * C_TIP, rel=1e-9)
    assert res.displacements["B"][2] == 0.0 or abs(res.displacements["B"][2]) < 1e-12 * g


K_B, K_D = 3 * E * IZ_B / L ** 3, 3 * E * IZ_D / L ** 3
SHARE = K_B / (K_B + K_D)                # the part of Q the pair hands to B while it sticks


@pytest.mark.parametrize("cone", ["circular", "inscribed", "circumscribed"])
def test_tip_on_tip_shares_a_sideways_load_then_slides_at_f_Xn(cone):
    """Q along y on D: friction T = Q k_B/(k_B + k_D) while T <= f X_n (the
    tips move together), f X_n beyond, the tips then apart: D at (Q − f
    X_n)/k_D, B at f X_n/k_B."""
    P, f = 10.0, 0.3
    X = P / 2
    Q_slide = f * X / SHARE
    fr = _tips(cone, friction=f, P=P, Q=1.0)
    for Q, state in ((0.5 * Q_slide, "stick"), (1.5 * Q_slide, "slip")):
        res = fr.solve(Q)
        assert res.ok, res.message
        s = res.supports["D-B"]
        T = min(Q * SHARE, f * X)
        assert s.state == state
        assert s.normal == pytest.approx(X, rel=1e-9)
        # the force on D opposes Q (on B it pushes along +y)
        np.testing.assert_allclose(s.tangential_global, (0.0, -T, 0.0), rtol=0, atol=1e-9 * X)
        assert res.displacements["B"][1] == pytest.approx(T / K_B, rel=1e-8)
        assert res.displacements["D"][1] == pytest.approx((Q - T) / K_D, rel=1e-8)
        if state == "slip":
            assert s.slip_global @ (0, 1, 0) == pytest.approx((Q - T) / K_D - T / K_B, rel=1e-8)


def test_tip_on_tip_trace_breaks_at_the_hand_sliding_load():
    """The polygon's exact path: one breakpoint, stick to slip, at Q* = f X_n
    (k_B + k_D)/k_B (a facet lies along y, so the circumscribed polygon's
    friction there is Coulomb's)."""
    P, f = 10.0, 0.3
    t = _tips("circumscribed", friction=f, P=P, Q=1.0).trace(p_max=3 * f * P / 2 / SHARE)
    assert t.ok, t.message
    np.testing.assert_allclose(t.breakpoints, [f * P / 2 / SHARE], rtol=1e-10)
    assert [s.supports["D-B"].state for s in t.states][-1] == "slip"


# -- misuse ------------------------------------------------------------------

def test_a_pair_with_itself_or_an_unknown_node_is_refused():
    fr = _tips()
    with pytest.raises(InvalidProblemError, match=r"other='B' is the contact's own node.*"
                                                  r"leave other out"):
        fr.add_contact("B", normal=(0, 0, 1), other="B")
    with pytest.raises(InvalidProblemError, match="'Z'"):
        fr.add_contact("B", normal=(0, 0, 1), other="Z")
    # the same pair with the same normal twice: refused; against the ground: allowed
    with pytest.raises(InvalidProblemError, match="same normal"):
        fr.add_contact("D", normal=(0, 0, 1), other="B")
    fr.add_contact("D", normal=(0, 0, 1))


def test_a_pair_whose_normal_both_nodes_fix_is_refused_by_name():
    """Held at one node only, the pair is a contact against that node (it
    solves); held at both, it could neither open nor close: the error names
    the pair."""
    fr = _tips(P=10.0)
    fr.add_support("B", fix=("uz",))           # B held: D rests on it with all of P
    res = fr.solve()
    assert res.ok and res.supports["D-B"].normal == pytest.approx(10.0, rel=1e-9)
    fr = _tips(P=0.0)
    fr.add_support("D", fix=("uz",))           # D held: B pushed up into it by 4
    fr.add_load("B", fz=4.0)
    res = fr.solve()
    assert res.ok and res.supports["D-B"].normal == pytest.approx(4.0, rel=1e-9)
    assert abs(res.displacements["B"][2]) < 1e-12
    fr.add_support("B", fix=("uz",))
    with pytest.raises(InvalidProblemError, match=r"contact pair 'D'-'B'.*both its nodes"):
        fr.solve()


# -- collapse with pairs: a table whose top rests on its legs ------------------

SQUARE = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)]


def _table_on_pairs(f_pads, f_pairs, cone, h=0.5, W=40.0):
    """Legs P_k-T_k of height h on pads with friction ``f_pads``, braced by a
    ring T; the top, a ring K over the legs' tops (the same points), rests on
    them through pairs K_k-T_k (normal +z, friction ``f_pairs``); W on the
    top's corners, p pushing the top along x (p/4 a corner)."""
    fr = SpaceFrame(cone=cone)
    for k, (x, y) in enumerate(SQUARE):
        fr.add_node(f"P{k}", x, y, 0.0)
        fr.add_node(f"T{k}", x, y, h)
        fr.add_node(f"K{k}", x, y, h)
        fr.add_member(f"P{k}", f"T{k}", 2e8, 0.01, 1e-4, 1e-4, G=8e7, J=2e-4)
        fr.add_contact(f"P{k}", friction=f_pads, facets=8)
        fr.add_contact(f"K{k}", friction=f_pairs, facets=8, other=f"T{k}")
        fr.add_load(f"K{k}", fz=-W / 4)
        fr.add_load(f"K{k}", fx=0.25, case="variable")
    for k in range(4):
        for ring in "TK":
            fr.add_member(f"{ring}{k}", f"{ring}{(k + 1) % 4}", 2e8, 0.01, 1e-4, 1e-4, G=8e7,
                          J=2e-4)
    return fr


@pytest.mark.parametrize("cone", ["circumscribed", "circular"])
def test_a_table_on_pairs_slides_away_at_f_W_when_its_pads_are_weaker(cone):
    """f_pads = 0.3 < f_pairs = 0.5: the pairs stick, so the table is the one
    piece it would be without them — its back pads slip at f W/(1 + f h)
    (their load W/4 − P h/4 against the push's quarter P/4), and it slides
    away as a rigid body at f W = 12 kN: the pairs are internal forces, no
    pivots (the rigid limit leaves them out: their nodes coincide)."""
    f, W, h = 0.3, 40.0, 0.5
    tr = _table_on_pairs(f, 0.5, cone).trace()
    assert tr.ok and tr.ended == "collapse", tr.message
    rtol = 1e-10 if cone != "circular" else 1e-6       # the circle's events are brackets
    np.testing.assert_allclose(tr.breakpoints, [f * W / (1 + f * h)], rtol=rtol)
    np.testing.assert_allclose(tr.p_end, f * W, rtol=rtol)
    assert "the frame slides away as a rigid body: friction exhausted at P0" in tr.message
    assert "K0-T0" not in tr.message.split("no equilibrium exists")[1].split("(proved")[0]


def test_a_table_whose_top_slides_on_its_legs_is_proved_to_at_f_W():
    """f_pairs = 0.3 < f_pads = 0.5: the top slides off its legs at f_pairs W
    = 12 kN (before the pads' 20): a part sliding on another, proved by the
    polygon's Farkas certificate, its words naming the pairs."""
    tr = _table_on_pairs(0.5, 0.3, "circumscribed").trace()
    assert tr.ok and tr.ended == "collapse", tr.message
    np.testing.assert_allclose(tr.p_end, 0.3 * 40.0, rtol=1e-10)
    assert ("a part of the frame slides on another: friction exhausted at K0-T0 (along "
            "(1, 0, 0)), K1-T1") in tr.message


def test_past_the_contrast_where_r_is_refined_a_farkas_end_is_no_limit(monkeypatch):
    """The same trace, with the contrast beyond which R is refined (and its
    small entries carry rounding) set below this frame's: its end, proved
    only by the LCP's Farkas certificate (no rigid motion moves the top on
    its legs alone), is no proof about the frame — the trace is not ok and
    names no limit: "bounded" between its last certified load and the
    rigid body's proved 20 kN (the pads sliding), and it says why."""
    from formulations.frames.mechanics import refinement

    monkeypatch.setattr(refinement, "CONTRAST", 0.5)
    tr = _table_on_pairs(0.5, 0.3, "circumscribed").trace()
    assert tr.ended == "bounded" and not tr.ok and tr.limit is None, tr.message
    assert tr.bound[1] == pytest.approx(0.5 * 40.0, rel=1e-9)
    assert "not a proof" in tr.message
    np.testing.assert_allclose(tr.p_end, 0.3 * 40.0, rtol=1e-10)   # certified up to it
