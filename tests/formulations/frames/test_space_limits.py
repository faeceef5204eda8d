"""Limit loads of space frames as certified brackets [p_lo, p_hi]: p_lo an
equilibrium on the load path, p_hi a proof that none exists, relative width
<= 1e-6, containing the value an independent route gives.

References: hand statics of the rigid table — it slides at μW (a push along
a facet's direction or a vertex's: both polygons reach Coulomb's circle
there), tips about its two far legs at W (a/2) / h; twisted about its centre
its limit on a friction polygon is an LP written here with
scipy.optimize.linprog (four pads, each force a non-negative combination of
its polygon's vertices, the six equations of a rigid body's statics), which
lies between cos(π/m) and 1 times Coulomb's μW r (inscribed) or 1 and
1/cos(π/m) times it (circumscribed)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import linprog

from formulations.frames import SpaceFrame
from formulations.frames.space.space_frame import CONES
from qpcontact.core.errors import NoSolutionError

W, A, B = 40.0, 2.0, 1.2
LEG = dict(E=2e8, G=8e7, A=1e-3, Iy=1e-6, Iz=1e-6, J=2e-6)
PADS = [(0.0, 0.0), (A, 0.0), (A, B), (0.0, B)]


def table(ratio, *, mu=0.3, h=0.8, cone="circular", load=(1, 0, 0, 0, 0, 0),
          stiffness=None, facets=16):
    """Four steel legs h high under a deck `ratio` times stiffer, rigid (or
    elastic) frictional feet, 40 kN at the deck's centre C; the variable
    load `load` x p at C."""
    fr = SpaceFrame(units=("kN", "m"), cone=cone)
    fr.add_node("C", A / 2, B / 2, h)
    for k, (x, y) in enumerate(PADS):
        fr.add_node(f"F{k}", x, y, 0.0)
        fr.add_node(f"T{k}", x, y, h)
        fr.add_member(f"F{k}", f"T{k}", **LEG)
        fr.add_contact(f"F{k}", normal=(0, 0, 1), friction=mu,
                       stiffness=stiffness, facets=facets)
    deck = {k: v * (ratio if k not in ("E", "G") else 1.0) for k, v in LEG.items()}
    for k in range(4):
        fr.add_member(f"T{k}", f"T{(k + 1) % 4}", **deck)
        fr.add_member("C", f"T{k}", **deck)
    fr.add_load("C", fz=-W)
    fr.add_load("C", *load, case="variable")
    return fr


def rigid_body_limit(mu, polygon, m, load, h=0.8):
    """The largest p for which four pads on a floor hold the deck's weight W
    plus p x ``load`` (force and moment at C, the deck's centre at height
    h) when each pad's friction lies in its m-gon: an LP over the pads'
    normal forces n_k >= 0 and the weights λ_kj >= 0 of the polygon's
    vertices (friction Σ_j λ_kj μ v_j with Σ_j λ_kj = n_k), under the six
    equations of the rigid body's statics (moments about C)."""
    turn = 0.0 if polygon == "inscribed" else 0.5
    radius = 1.0 if polygon == "inscribed" else 1.0 / np.cos(np.pi / m)
    ang = 2 * np.pi * (np.arange(m) + turn) / m
    verts = mu * radius * np.c_[np.cos(ang), np.sin(ang)]
    nv = 1 + m
    A_eq = np.zeros((6 + 4, 4 * nv + 1))
    for k, (x, y) in enumerate(PADS):
        rx, ry, rz = x - A / 2, y - B / 2, -h
        cols = [k * nv] + [k * nv + 1 + j for j in range(m)]
        forces = [(0.0, 0.0, 1.0)] + [(vx, vy, 0.0) for vx, vy in verts]
        for col, (fx, fy, fz) in zip(cols, forces):
            A_eq[0:3, col] = fx, fy, fz
            A_eq[3:6, col] = (ry * fz - rz * fy, rz * fx - rx * fz, rx * fy - ry * fx)
        A_eq[6 + k, k * nv] = -1.0
        A_eq[6 + k, k * nv + 1:(k + 1) * nv] = 1.0
    A_eq[:6, -1] = load
    b_eq = np.zeros(10)
    b_eq[2] = W
    res = linprog(np.r_[np.zeros(4 * nv), -1.0], A_eq=A_eq, b_eq=b_eq,
                  bounds=[(0, None)] * (4 * nv) + [(None, None)], method="highs")
    assert res.status == 0
    return res.x[-1]


def assert_bracket(tr, value):
    assert tr.ended == "collapse" and tr.ok, tr.message
    lo, hi = tr.limit
    assert lo <= value * (1 + 1e-9) and value <= hi * (1 + 1e-9), (tr.limit, value)
    assert (hi - lo) / hi <= 1e-6, tr.limit


@pytest.mark.parametrize("ratio", [pytest.param(1.0, marks=pytest.mark.slow), 1e2, 1e4, 1e8])
@pytest.mark.parametrize("cone", CONES)
def test_a_table_pushed_at_its_centre_slides_at_mu_W(ratio, cone):
    """At ratio 1 (a deck as slender as its legs, rigid pads) the polygons'
    path stops at a degenerate vertex (p = 11.29, every pad starting to
    slip) and restarts beyond it; the circle's path is certified solves."""
    tr = table(ratio, cone=cone).trace()
    assert_bracket(tr, 0.3 * W)
    assert "slides" in tr.message


def test_a_slender_deck_on_a_polygon_slides_at_mu_W():
    """Ratio 1: every pad starts to slip at p = 11.29, a degenerate vertex
    of the LCP's path (it stopped there before); the path ends in a proof."""
    tr = table(1.0, cone="circumscribed").trace()
    assert_bracket(tr, 0.3 * W)


@pytest.mark.parametrize("ratio", [1e2, pytest.param(1e4, marks=pytest.mark.slow), 1e8])
@pytest.mark.parametrize("cone", ["circular", "inscribed"])
def test_a_tall_table_tips_about_its_far_legs_at_W_a_over_2h(ratio, cone):
    tr = table(ratio, mu=0.9, h=2.0, cone=cone).trace()
    assert_bracket(tr, W * (A / 2) / 2.0)
    assert "tips over about F1, F2" in tr.message


@pytest.mark.parametrize("ratio", [pytest.param(1.0, marks=pytest.mark.slow), 1e2,
                                   pytest.param(1e4, marks=pytest.mark.slow), 1e8])
@pytest.mark.parametrize("polygon", ["inscribed", "circumscribed"])
def test_a_twisted_table_turns_at_the_polygons_rigid_body_limit(ratio, polygon):
    tr = table(ratio, cone=polygon, load=(0, 0, 0, 0, 0, 1)).trace()
    lp = rigid_body_limit(0.3, polygon, 16, (0, 0, 0, 0, 0, 1.0))
    coulomb = 0.3 * W * np.hypot(A, B) / 2
    if polygon == "inscribed":
        assert np.cos(np.pi / 16) * coulomb <= lp <= coulomb
    else:
        assert coulomb <= lp <= coulomb / np.cos(np.pi / 16)
    assert_bracket(tr, lp)
    assert "turns about" in tr.message or "slides" in tr.message


@pytest.mark.parametrize("ratio", [1.0, pytest.param(1e2, marks=pytest.mark.slow),
                                   pytest.param(1e4, marks=pytest.mark.slow), 1e8])
def test_by_default_a_twisted_table_turns_at_coulombs_mu_W_r(ratio):
    """On Coulomb's circle (the default) every pad gives its full friction
    μW/4 perpendicular to its radius r = √(a² + b²)/2 from the centre: the
    table turns at μW r = 13.9943 kN·m by hand — and never carries more
    (the default model is never beyond Coulomb's law)."""
    fr = table(ratio, load=(0, 0, 0, 0, 0, 1))
    coulomb = 0.3 * W * np.hypot(A, B) / 2
    for share in (0.5, 0.9, 0.99, 0.999):
        r = fr.solve(share * coulomb)
        assert r.ok, r.message
        for s in r.supports.values():
            assert np.hypot(*s.tangential) <= 0.3 * s.normal * (1 + 1e-12)
    with pytest.raises(NoSolutionError, match="no equilibrium"):
        fr.solve(1.001 * coulomb)
    tr = fr.trace()
    assert_bracket(tr, coulomb)
    assert "Coulomb's circles" in tr.message


@pytest.mark.parametrize("ratio", [1e2, 1e4])
def test_a_table_pushed_at_a_corner_gives_way_at_the_rigid_bodys_limit(ratio):
    """1 kN x p along x at the deck's corner T2 (2, 1.2): at C a force
    (1, 0, 0) and a moment (0, 0, -0.6) — sliding and turning together."""
    fr = table(ratio, cone="circumscribed")
    fr.add_load("T2", fx=1.0, case="corner")
    tr = fr.trace(variable="corner")
    assert_bracket(tr, rigid_body_limit(0.3, "circumscribed", 16, (1, 0, 0, 0, 0, -0.6)))


@pytest.mark.parametrize("ratio", [1e2, pytest.param(1e4, marks=pytest.mark.slow)])
def test_on_the_circle_a_corner_push_ends_at_a_certified_load_below_a_proved_bound(ratio):
    """Coulomb's law is non-associated: pushed at a corner, the elastic
    table on the circle stops following the load at a certified
    equilibrium (about 10.31–10.33, depending on the deck) below the rigid
    body's static limit on the circle, 10.3974 — an LP over 256-gons inside
    and around the circle, written here, brackets it to 8e-5.  The trace
    says so: its upper end is a proof at the static limit, its lower end
    the last certified equilibrium, and the message names both."""
    fr = table(ratio)
    fr.add_load("T2", fx=1.0, case="corner")
    tr = fr.trace(variable="corner")
    inner = rigid_body_limit(0.3, "inscribed", 256, (1, 0, 0, 0, 0, -0.6))
    outer = rigid_body_limit(0.3, "circumscribed", 256, (1, 0, 0, 0, 0, -0.6))
    lo, hi = tr.limit or tr.bound
    assert inner * (1 - 1e-9) <= hi <= outer * (1 + 1e-6)
    assert lo < hi
    r = tr.result_at(lo)
    assert r.ok, r.message
    if tr.ended == "bounded":
        assert not tr.ok and tr.limit is None and "last certified equilibrium" in tr.message
        assert "non-associated" in tr.message
    else:
        assert_bracket(tr, hi)


def test_a_frame_held_by_a_spring_is_not_proved_by_a_rigid_motion():
    """The rigid-body proof is for a frame resting on its contacts alone: a
    spring that holds the deck carries any push once the pads slide."""
    fr = table(1e4, cone="circumscribed")
    fr.add_spring("C", ux=100.0)
    tr = fr.trace()
    assert tr.limit is None and "rigid motion" not in tr.message
    # on the circle the path has no end of its own to find: p_max is asked
    fr.cone = "circular"
    with pytest.raises(Exception, match="give p_max"):
        fr.trace()
    tr = fr.trace(30.0)
    assert tr.ok and tr.ended == "p_max" and tr.limit is None
    assert tr.result_at(30.0).ok


def test_the_safety_factor_is_the_bracket_over_the_design_load():
    tr = table(1e4).trace()
    lo, hi = tr.safety_factor(8.0)
    assert lo <= 12.0 / 8.0 <= hi and hi - lo <= 1e-6 * hi
    with pytest.raises(Exception, match="p_design must be a positive number"):
        tr.safety_factor(-1.0)
    with pytest.raises(Exception, match="proved no limit"):
        table(1e4).trace(5.0).safety_factor(4.0)
