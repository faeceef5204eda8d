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

W, A, B = 40.0, 2.0, 1.2
LEG = dict(E=2e8, G=8e7, A=1e-3, Iy=1e-6, Iz=1e-6, J=2e-6)
PADS = [(0.0, 0.0), (A, 0.0), (A, B), (0.0, B)]


def table(ratio, *, mu=0.3, h=0.8, polygon="circumscribed", load=(1, 0, 0, 0, 0, 0),
          stiffness=None, facets=16):
    """Four steel legs h high under a deck `ratio` times stiffer, rigid (or
    elastic) frictional feet, 40 kN at the deck's centre C; the variable
    load `load` x p at C."""
    fr = SpaceFrame(units=("kN", "m"))
    fr.add_node("C", A / 2, B / 2, h)
    for k, (x, y) in enumerate(PADS):
        fr.add_node(f"F{k}", x, y, 0.0)
        fr.add_node(f"T{k}", x, y, h)
        fr.add_member(f"F{k}", f"T{k}", **LEG)
        fr.add_contact(f"F{k}", normal=(0, 0, 1), friction=mu, polygon=polygon,
                       stiffness=stiffness, facets=facets)
    deck = {k: v * (ratio if k not in ("E", "G") else 1.0) for k, v in LEG.items()}
    for k in range(4):
        fr.add_member(f"T{k}", f"T{(k + 1) % 4}", **deck)
        fr.add_member("C", f"T{k}", **deck)
    fr.add_load("C", fz=-W)
    fr.add_load("C", *load, case="variable")
    return fr


def rigid_body_limit(mu, polygon, m, torque):
    """The largest torque about C's vertical axis four pads on a floor can
    resist when each pad's friction lies in its m-gon (LP over the pads'
    forces: normal n_k >= 0 and friction Σ_j λ_kj v_j with the polygon's
    vertices v_j scaled by μ; equilibrium of forces and moments)."""
    turn = 0.0 if polygon == "inscribed" else 0.5
    radius = 1.0 if polygon == "inscribed" else 1.0 / np.cos(np.pi / m)
    ang = 2 * np.pi * (np.arange(m) + turn) / m
    verts = mu * radius * np.c_[np.cos(ang), np.sin(ang)]
    c = np.array([A / 2, B / 2])
    # unknowns: per pad (n, λ_1..λ_m), then p
    nv = 1 + m
    A_eq = np.zeros((6, 4 * nv + 1))
    for k, (x, y) in enumerate(PADS):
        rx, ry = x - c[0], y - c[1]
        A_eq[2, k * nv] = 1.0                          # Σ F_z
        for j, (vx, vy) in enumerate(verts):
            col = k * nv + 1 + j                        # force n·(vx, vy, 1) per unit λ
            A_eq[0, col], A_eq[1, col] = vx, vy
            A_eq[5, col] = rx * vy - ry * vx            # moment about z at C
        # each λ_j carries its share of the pad's normal force: Σ λ = n
        # (a force in the cone = n times a point of the polygon)
    rows = []
    for k in range(4):
        r = np.zeros(4 * nv + 1)
        r[k * nv] = -1.0
        r[k * nv + 1:k * nv + 1 + m] = 1.0
        rows.append(r)
    A_eq = np.vstack([A_eq, rows])
    b_eq = np.zeros(A_eq.shape[0])
    b_eq[2] = W
    A_eq[5, -1] = torque
    A_eq = np.delete(A_eq, [3, 4], axis=0)      # moments about x, y: the normals' split is free
    b_eq = np.delete(b_eq, [3, 4])
    res = linprog(np.r_[np.zeros(4 * nv), -1.0], A_eq=A_eq, b_eq=b_eq,
                  bounds=[(0, None)] * (4 * nv) + [(None, None)], method="highs")
    assert res.status == 0
    return res.x[-1]


def assert_bracket(tr, value):
    assert tr.ended == "collapse" and tr.ok, tr.message
    lo, hi = tr.limit
    assert lo <= value * (1 + 1e-9) and value <= hi * (1 + 1e-9), (tr.limit, value)
    assert (hi - lo) / hi <= 1e-6, tr.limit


@pytest.mark.parametrize("ratio", [1e2, 1e4, 1e8])
@pytest.mark.parametrize("polygon", ["inscribed", "circumscribed"])
def test_a_table_pushed_at_its_centre_slides_at_mu_W(ratio, polygon):
    tr = table(ratio, polygon=polygon).trace()
    assert_bracket(tr, 0.3 * W)
    assert "slides" in tr.message


@pytest.mark.parametrize("ratio", [1e2, 1e4, 1e8])
def test_a_tall_table_tips_about_its_far_legs_at_W_a_over_2h(ratio):
    tr = table(ratio, mu=0.9, h=2.0).trace()
    assert_bracket(tr, W * (A / 2) / 2.0)
    assert "tips over about F1, F2" in tr.message


@pytest.mark.parametrize("ratio", [1e2, 1e4, 1e8])
@pytest.mark.parametrize("polygon", ["inscribed", "circumscribed"])
def test_a_twisted_table_turns_at_the_polygons_rigid_body_limit(ratio, polygon):
    tr = table(ratio, polygon=polygon, load=(0, 0, 0, 0, 0, 1)).trace()
    lp = rigid_body_limit(0.3, polygon, 16, 1.0)
    coulomb = 0.3 * W * np.hypot(A, B) / 2
    if polygon == "inscribed":
        assert np.cos(np.pi / 16) * coulomb <= lp <= coulomb
    else:
        assert coulomb <= lp <= coulomb / np.cos(np.pi / 16)
    assert_bracket(tr, lp)
    assert "turns about" in tr.message or "slides" in tr.message


def test_a_frame_held_by_a_spring_is_not_proved_by_a_rigid_motion():
    """The rigid-body proof is for a frame resting on its contacts alone: a
    spring that holds the deck carries any push once the pads slide."""
    fr = table(1e4)
    fr.add_spring("C", ux=100.0)
    tr = fr.trace()
    assert tr.limit is None and "rigid motion" not in tr.message


def test_the_safety_factor_is_the_bracket_over_the_design_load():
    tr = table(1e4).trace()
    lo, hi = tr.safety_factor(8.0)
    assert lo <= 12.0 / 8.0 <= hi and hi - lo <= 1e-6 * hi
    with pytest.raises(Exception, match="p_design must be a positive number"):
        tr.safety_factor(-1.0)
    with pytest.raises(Exception, match="proved no limit"):
        table(1e4).trace(5.0).safety_factor(4.0)
