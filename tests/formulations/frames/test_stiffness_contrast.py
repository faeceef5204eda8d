"""Frames whose members differ in stiffness by up to 1e8 (a stiff deck on
slender legs): right answers are ok, to nine digits against hand statics,
in the plane and in space; answers 1e-6 off in a force or a displacement
are not.

References: hand statics of the rigid deck — by symmetry each of a table's
four legs takes W/4 ± (push · h)/(2 a), a portal's two W/2 ∓ push · h/a; the
friction forces sum to the push; on a deck much stiffer than its legs each
leg takes its share of the push in proportion to its lateral stiffness
(equal legs: push / n, to the deck's own flexibility, 1/ratio)."""

from __future__ import annotations

import numpy as np
import pytest

from formulations.frames import Frame, SpaceFrame
from formulations.frames.mechanics import contact_lcp
from formulations.frames.mechanics.equilibrium_checks import equilibrium
from formulations.frames.space import space_recovery

W, MU, A, B, H = 40.0, 0.3, 2.0, 1.2, 0.8
RATIOS = (1e2, 1e4, 1e6, 1e8)
LEG = dict(E=2e8, G=8e7, A=1e-3, Iy=1e-6, Iz=1e-6, J=2e-6)


def table(ratio, stiffness=None, polygon="circumscribed", twist=False):
    """A 2.0 x 1.2 m table 0.8 m high on four steel legs, rigid (or elastic)
    feet on a floor with μ 0.3, 40 kN at the centre of a deck ``ratio``
    times stiffer than the legs; pushed along x at the centre (p x 1 kN)."""
    fr = SpaceFrame(units=("kN", "m"), cone=polygon)
    fr.add_node("C", A / 2, B / 2, H)
    for k, (x, y) in enumerate([(0, 0), (A, 0), (A, B), (0, B)]):
        fr.add_node(f"F{k}", x, y, 0.0)
        fr.add_node(f"T{k}", x, y, H)
        fr.add_member(f"F{k}", f"T{k}", **LEG)
        fr.add_contact(f"F{k}", normal=(0, 0, 1), friction=MU, stiffness=stiffness)
    deck = {k: v * (ratio if k != "E" and k != "G" else 1.0) for k, v in LEG.items()}
    for k in range(4):
        fr.add_member(f"T{k}", f"T{(k + 1) % 4}", **deck)
        fr.add_member("C", f"T{k}", **deck)
    fr.add_load("C", fz=-W)
    fr.add_load("C", **({"mz": 1.0} if twist else {"fx": 1.0}), case="variable")
    return fr


def portal(ratio):
    """The table's x-z section in the plane: two legs 2 m apart."""
    fr = Frame(units=("kN", "m"))
    for name, x, y in (("F0", 0, 0), ("F1", A, 0), ("T0", 0, H), ("T1", A, H), ("C", A / 2, H)):
        fr.add_node(name, x, y)
    for i, j in (("F0", "T0"), ("F1", "T1")):
        fr.add_member(i, j, E=2e8, A=1e-3, I=1e-6)
    for i, j in (("T0", "C"), ("C", "T1")):
        fr.add_member(i, j, E=2e8, A=1e-3 * ratio, I=1e-6 * ratio)
    for n in ("F0", "F1"):
        fr.add_contact(n, normal=(0, 1), friction=MU)
    fr.add_load("C", fy=-W)
    fr.add_load("C", fx=1.0, case="variable")
    return fr


@pytest.mark.parametrize("ratio", RATIOS)
@pytest.mark.parametrize("share", [0.5, 0.9, 0.99, 0.999])
def test_a_stiff_deck_on_four_legs_is_ok_with_hand_statics(ratio, share):
    p = share * MU * W
    r = table(ratio).solve(p)
    assert r.ok, r.message
    n = np.array([r.supports[f"F{k}"].normal for k in range(4)])
    lift = p * H / (2 * A)
    np.testing.assert_allclose(n, W / 4 + np.array([-lift, lift, lift, -lift]), rtol=1e-9)
    t = np.array([r.supports[f"F{k}"].tangential_global for k in range(4)])
    np.testing.assert_allclose(t.sum(axis=0), [-p, 0.0, 0.0], atol=1e-9 * p)
    slip = np.array([r.supports[f"F{k}"].state == "slip" for k in range(4)])
    # a slipping pad gives its full friction (on a facet's direction: the push's)
    np.testing.assert_allclose(t[slip, 0], -MU * n[slip], rtol=1e-9)
    if ratio >= 1e6:     # a rigid deck: the sticking (equal) legs share the rest
        np.testing.assert_allclose(t[~slip, 0], -(p - MU * n[slip].sum()) / (~slip).sum(),
                                   rtol=1e-5)
    # the default polygon circumscribes Coulomb's circle: at most 1/cos(π/16) beyond it
    assert np.all(np.hypot(t[:, 0], t[:, 1]) <= MU * n / np.cos(np.pi / 16) * (1 + 1e-9))


@pytest.mark.parametrize("ratio", RATIOS)
def test_the_portal_in_the_plane_agrees(ratio):
    p = 0.9 * MU * W
    r = portal(ratio).solve(p)
    assert r.ok, r.message
    n = [r.supports["F0"].normal, r.supports["F1"].normal]
    np.testing.assert_allclose(n, [W / 2 - p * H / A, W / 2 + p * H / A], rtol=1e-9)
    t = r.supports["F0"].tangential + r.supports["F1"].tangential
    assert abs(t + p) <= 1e-9 * p


@pytest.mark.parametrize("stiffness", [None, 1e6])
def test_elastic_feet_under_a_stiff_deck_are_ok(stiffness):
    r = table(1e4, stiffness).solve(0.99 * MU * W)
    assert r.ok, r.message


def link_forces(frame, b, r):
    """X in link order from a space result's supports (n, t1, t2 per contact)."""
    pos = contact_lcp.layout(b)
    X = np.zeros(len(b["info"]))
    for ci, s in enumerate(r.supports.values()):
        X[pos[ci]["n"]] = s.normal
        for k, v in zip(("t1", "t2"), s.tangential):
            if k in pos[ci]:
                X[pos[ci][k]] = v
    return X


def judged(frame, b, u, X, p):
    F = b["F"] @ contact_lcp.factors(b, {"constant": 1.0, "variable": p})
    ends = contact_lcp.member_end_actions(b, u, contact_lcp.factors(
        b, {"constant": 1.0, "variable": p}))
    ft = contact_lcp.force_terms(b, u, F, ends)
    r_all = b["K"] @ u - F - b["H"] @ X
    return max(equilibrium(frame, b, F, X, u),
               space_recovery.resultant(frame, b, F, X, r_all, u, ft))


def test_answers_a_millionth_off_are_refused_on_a_stiff_deck():
    """The judge itself: the right answer passes; a pad force 1e-6 off, or
    the deck's displacement 1e-6 off at one node, fails by far."""
    fr, p = table(1e8), 0.9 * MU * W
    r = fr.solve(p)
    b = fr.build()
    u, X = r._u.copy(), link_forces(fr, b, r)
    assert judged(fr, b, u, X, p) <= 1e-9
    X_off = X.copy()
    X_off[contact_lcp.layout(b)[1]["n"]] *= 1 + 1e-6
    assert judged(fr, b, u, X_off, p) > 1e-7
    u_off = u.copy()
    i = b["idx"]["C"]
    u_off[i] += 1e-6 * np.abs(u).max()
    assert judged(fr, b, u_off, X, p) > 1e-7


#: the twisted table's turning limit on Coulomb's circle, by hand: every pad
#: at its full friction μW/4, perpendicular to its radius √(a² + b²)/2
TURNING = MU * W * np.hypot(A, B) / 2


@pytest.mark.parametrize("ratio", [1e2, pytest.param(1e4, marks=pytest.mark.slow)])
def test_the_inscribed_polygon_never_gives_more_friction_than_coulomb(ratio):
    """Twisted about its centre, the table turns at μW r (13.9943 kN·m).  On
    the inscribed 16-gon no pad ever uses more than its circle, and the last
    equilibrium of the load path lies between cos(π/16) of the hand limit
    and the limit itself; on the circumscribed one it may pass the limit
    (by at most 1/cos(π/16))."""
    fr = table(ratio, polygon="inscribed", twist=True)
    for share in (0.5, 0.9, 0.97):
        r = fr.solve(share * TURNING)
        assert r.ok, r.message
        for s in r.supports.values():
            assert np.hypot(*s.tangential) <= MU * s.normal * (1 + 1e-9)
    last = fr.trace().intervals[-1][1]
    assert np.cos(np.pi / 16) * TURNING * (1 - 1e-9) <= last <= TURNING * (1 + 1e-9)
    outer = table(ratio, twist=True).trace().intervals[-1][1]
    assert last < outer <= TURNING / np.cos(np.pi / 16) * (1 + 1e-9)


def test_a_cone_that_is_none_of_the_models_is_refused():
    with pytest.raises(Exception, match="cone must be one of.*'round'"):
        SpaceFrame(cone="round")
    fr = table(1.0)
    with pytest.raises(Exception, match="cone must be one of.*'faceted'"):
        fr.cone = "faceted"
    with pytest.raises(Exception, match="the frame's model, not a solve option"):
        fr.solve(1.0, cone="inscribed")
