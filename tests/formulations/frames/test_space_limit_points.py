"""Where the load paths of frames on faceted pads end: six-legged tables
(statically indeterminate friction on rigid pads), a collapse bracket
narrowed to 1e-6, a pipe rack and a soft-padded table near their limits.
References from outside the engine: hand statics, and LPs written here or in
tests/helpers/rigid_body_lp.py with scipy.optimize.linprog."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.optimize import linprog

from formulations.frames import SpaceFrame
from formulations.frames.space.space_family import LEG, TABLE_LEGS, pipe_rack, table
from qpcontact.core.errors import QpcontactError
from tests.helpers.rigid_body_lp import bounded_at_the_lp, static_limit

CONST = {"constant": 1.0}
W = 40.0          # the tables' weight at C (kN)
MU = 0.3


def round_table(facets: int, r: float = 1.0, h: float = 0.8) -> SpaceFrame:
    """Six legs on a circle of radius r about C, a deck 1e4 times stiffer
    than the legs (a ring and spokes), rigid pads on inscribed polygons,
    W at C and a torque about z at C (case "twist")."""
    fr = SpaceFrame(units=("kN", "m"), cone="inscribed")
    fr.add_node("C", 0.0, 0.0, h)
    deck = {k: v * (1e4 if k in ("A", "Iy", "Iz", "J") else 1.0) for k, v in LEG.items()}
    for k in range(6):
        x, y = r * np.cos(np.pi / 3 * k), r * np.sin(np.pi / 3 * k)
        fr.add_node(f"F{k}", x, y, 0.0)
        fr.add_node(f"T{k}", x, y, h)
        fr.add_member(f"F{k}", f"T{k}", **LEG, name=f"L{k}")
        fr.add_contact(f"F{k}", normal=(0, 0, 1), friction=MU, facets=facets)
    for k in range(6):
        fr.add_member(f"T{k}", f"T{(k + 1) % 6}", **deck, name=f"R{k}")
        fr.add_member("C", f"T{k}", **deck, name=f"S{k}")
    fr.add_load("C", fz=-W)
    fr.add_load("C", mz=1.0, case="twist")
    return fr


@pytest.mark.slow
def test_six_legs_on_a_circle_twisted_turn_at_the_lp_limit():
    """Six rigid pads: friction statically indeterminate, the contact
    matrix singular.  On 12-gons each leg's turning direction is a vertex
    of its polygon, so whatever the normal forces the pads resist μ N r
    each: the table turns at μ W r = 12 kN·m (hand), the LP's value, and
    the trace proves it with a bracket of width <= 1e-6."""
    fr = round_table(12)
    ref = static_limit(fr, CONST, {"twist": 1.0})
    assert ref == pytest.approx(MU * W * 1.0, rel=1e-12)
    tr = fr.trace(variable="twist")
    assert tr.ended == "collapse" and tr.ok, tr.message
    lo, hi = tr.limit
    assert lo <= ref * (1 + 1e-9) and ref <= hi * (1 + 1e-9), (tr.limit, ref)
    assert (hi - lo) / hi <= 1e-6


def in_plane_capacity(normals, plan, polygon):
    """The largest torque about z at the centroid of ``plan`` that pads
    with normal forces ``normals`` carry, each friction force within its
    polygon (vertices ``polygon``, a unit-μ list of (cx, cy)) scaled by
    μ N: an LP over the vertices' multipliers (Fx = Fy = 0, Mz = -p)."""
    cx, cy = np.mean(plan, axis=0)
    cols, sums = [], []
    for i, ((x, y), n) in enumerate(zip(plan, normals)):
        for vx, vy in polygon:
            fx, fy = MU * n * vx, MU * n * vy
            cols.append([fx, fy, (x - cx) * fy - (y - cy) * fx])
            sums.append(i)
    A = np.column_stack([np.array(cols).T, [0.0, 0.0, 1.0]])
    A_ub = np.zeros((len(plan), A.shape[1]))
    for j, i in enumerate(sums):
        A_ub[i, j] = 1.0
    cost = np.zeros(A.shape[1])
    cost[-1] = -1.0
    res = linprog(cost, A_ub=A_ub, b_ub=np.ones(len(plan)), A_eq=A, b_eq=np.zeros(3),
                  bounds=[(0, None)] * len(cols) + [(None, None)], method="highs")
    assert res.status == 0
    return res.x[-1]


@pytest.mark.slow
def test_six_legs_on_a_rectangle_twisted_stop_where_friction_is_exhausted():
    """The rigid body's LP turns the six-legged table at 13.84 kN·m only
    with the whole weight on the four corner legs (1.17 m from C) and none
    on the middle ones (0.6 m); the table keeps about W/6 on each leg, and
    Coulomb's law (non-associated: a pad slides without lifting) gives it
    no way to move its weight.  Its path stops where friction is exhausted
    under its own normal forces: the torque the pads carry with the normal
    forces of the last certified state (solved there, an LP here over the
    inscribed 16-gon) is the stop, 16 % below the LP's bound."""
    tr, res, ref = bounded_at_the_lp(table(6, 1e4, cone="inscribed"), "twist")
    lo = tr.bound[0]
    assert res.ok, res.message
    normals = [res.supports[f"F{k}"].normal for k in range(6)]
    assert sum(normals) == pytest.approx(W, rel=1e-9)
    polygon = [(np.cos(a), np.sin(a)) for a in 2 * np.pi * np.arange(16) / 16]
    cap = in_plane_capacity(normals, TABLE_LEGS[6], polygon)
    assert lo == pytest.approx(cap, rel=1e-6)
    assert tr.capacity == pytest.approx(cap, rel=1e-6)
    assert lo < 0.85 * ref
    assert "friction of every carrying pad is exhausted" in tr.message


@pytest.mark.parametrize("ratio, stiffness, width", [
    (1.0, 1e6, 1e-6),
    pytest.param(1e2, 1e6, 1e-6, marks=pytest.mark.slow),
    pytest.param(1.0, None, 1e-6, marks=pytest.mark.slow),
    pytest.param(1e2, 1e2, 1e-5, marks=pytest.mark.slow),
])
def test_a_corner_push_collapse_is_bracketed_as_narrowly_as_certified(ratio, stiffness, width):
    """The path's own collapse proof (branch and bound over the support
    states, a Farkas vector per leaf) was made a step measured on the
    load's scale above the last equilibrium: 2.7e-6 of p.  Tried again
    within 1e-6 of p above it, it holds there — where one pattern's Farkas
    LP stopped on HiGHS's numerical difficulties at tolerances of 1e-10,
    HiGHS's own 1e-7 gives a vector that checks to 1.5e-10 (a candidate:
    the check decides; brackets were 2.6e-6 and 3.5e-4 wide), and where a
    vector's slack on M'y <= 0 bounded z too tightly to prove anything, a
    smaller slack does.  The bracket lies below the rigid body's LP
    (non-associated friction) and its lower end solves, by hand statics:
    the pads carry W and the push.

    Inside the bracket no load has a certified equilibrium (its middle
    checked: the trace skipped none).  On soft pads under the stiff deck
    the bracket's width is the data's rounding, not the proof's step: the
    LCP there has
    solutions whose deck moves 0.4-2 km (a near-mechanism: its pivot is R's
    rounding), which the frame's equilibrium check refuses (residual
    4e-7 … 2e-6), and the Farkas proofs just above the path's end need z
    bounds that R's last digits decide: 1e-7 wide with the dependencies of
    2026-12-05, 2.5e-6 with numpy 2.4.6 / scipy 1.17.1 / highspy 1.16.0
    (docs/dev-notes.md, "The soft-padded table's collapse bracket")."""
    fr = table(4, ratio, stiffness=stiffness, cone="inscribed")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")      # the deck moves 0.07-0.4 m: large displacements
        tr = fr.trace(variable="corner")
        assert tr.ended == "collapse" and tr.ok, tr.message
        lo, hi = tr.limit
        assert 0 < (hi - lo) / hi <= width, tr.limit
        assert hi < static_limit(fr, CONST, {"corner": 1.0})
        res = fr.solve(combination={"constant": 1.0, "corner": lo})
        try:
            inside = fr.solve(combination={"constant": 1.0, "corner": 0.5 * (lo + hi)})
            assert not inside.ok, inside.message
        except QpcontactError:
            pass
    assert res.ok, res.message
    assert sum(v.normal for v in res.supports.values()) == pytest.approx(W, rel=1e-9)
    push = sum(v.tangential_global[:2] for v in res.supports.values())
    assert np.hypot(*push) == pytest.approx(lo, rel=1e-9)


def test_six_legs_a_millionth_below_sliding_away_are_ok():
    """A millionth below μW = 12 kN (hand: the 16-gon's vertex lies along
    the push, so every pad carries μ N along it at the limit) Lemke's basis
    held the last sticking pad's slip at 1e-4 of the others': with all six
    slipping the deck's rigid motion is free and the polish's system
    singular, and the answer kept its double-precision forces (statics off
    by 2e-5: "CHECK FAILED").  By hand: the pads carry W and the push, each
    within its friction, and the friction left over sums to 12 - p."""
    fr = table(6, 1e4, stiffness=1e6, cone="inscribed")
    p = MU * W * (1 - 1e-6)
    res = fr.solve(combination={"constant": 1.0, "centre": p})
    assert res.ok, res.message
    normals = np.array([v.normal for v in res.supports.values()])
    # the pads' forces on the deck resist the push (along -x)
    tang = -np.array([v.tangential_global[:2] for v in res.supports.values()])
    assert normals.sum() == pytest.approx(W, rel=1e-9)
    assert tang[:, 0].sum() == pytest.approx(p, rel=1e-9)
    assert abs(tang[:, 1].sum()) <= 1e-9 * p
    assert np.all(np.hypot(*tang.T) <= MU * normals * (1 + 1e-9))
    assert (MU * normals - tang[:, 0]).sum() == pytest.approx(MU * W - p, rel=1e-3)


@pytest.mark.slow
def test_a_pipe_rack_is_solved_at_999_per_mille_of_its_limit():
    """solve() at 99.9 % of the inscribed rack's limit raised
    SolverFailedError: Lemke at the fixed load ends on a secondary ray, and
    the load path, which reaches it by restarting beyond a degenerate
    vertex at 43.3, was judged "not ok" for that stop.  By hand: the pads
    carry the pipes (6 kN/m on two 12 m lines) less the uplift, and the
    sideways 0.2 p by friction.  No time limit: the test checks the answer,
    not the time (solve's default 60 s of wall time held its ~30 s of CPU
    alone and ran out at load 5-6, as a time limit should on a busy machine;
    docs/dev-notes.md, "Time limits per thread")."""
    fr = pipe_rack(cone="inscribed")
    p = 0.999 * static_limit(fr, CONST, {"uplift": 1.0})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # the corner lifts: large displacements
        res = fr.solve(combination={"constant": 1.0, "uplift": p}, time_limit=None)
    assert res.ok, res.message
    assert sum(v.normal for v in res.supports.values()) == pytest.approx(2 * 12.0 * 6.0 - p,
                                                                          rel=1e-9)
    fy = sum(v.tangential_global[1] for v in res.supports.values())
    assert fy == pytest.approx(-0.2 * p, rel=1e-9)


def test_a_table_on_soft_pads_tipping_is_ok_with_two_feet_in_the_air():
    """Two feet lifted carry nothing, so their slips may point anywhere
    and Lemke writes them on either facet by rounding; the polish dropped
    the one rounding put on the wrong side and the answer kept its
    double-precision forces (statics off by 7e-4: "CHECK FAILED").  By
    hand: the pads carry W + p, and their moments about the y axis balance
    W at x = 1 and p at the overhang's tip, x = 2.5."""
    fr = table(6, 1e4, stiffness=1e2, cone="circumscribed")
    p = 0.999 * 36.1055911426
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # soft pads: the deck tilts 0.16 rad
        res = fr.solve(combination={"constant": 1.0, "overhang": p})
    assert res.ok, res.message
    normals = [res.supports[f"F{k}"].normal for k in range(6)]
    assert sum(normals) == pytest.approx(W + p, rel=1e-9)
    xs = [x for x, _ in TABLE_LEGS[6]]
    assert sum(n * x for n, x in zip(normals, xs)) == pytest.approx(W * 1.0 + p * 2.5, rel=1e-9)


@pytest.mark.slow
def test_a_table_on_soft_pads_is_traced_to_its_tipping_load():
    """Its path stopped at 36.1 ("bounded", the rigid body's 80 unreached):
    its restarts beyond a degenerate vertex at 36.005 were all spent 1e-9
    apart, each stopping where it started.  It tips about its far legs at
    W·1/0.5 = 80 (hand)."""
    fr = table(6, 1e4, stiffness=1e2, cone="circumscribed")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tr = fr.trace(variable="overhang")
    assert tr.ended == "collapse" and tr.ok, tr.message
    lo, hi = tr.limit
    assert lo <= 80.0 * (1 + 1e-9) and 80.0 <= hi * (1 + 1e-9) and (hi - lo) / hi <= 1e-6
    assert "tips over about F2, F3" in tr.message
