"""Limit loads of the family of frames on frictional pads
(formulations/frames/space/space_family.py; benchmarks/frame_limits.py runs
all of it): one test per failure the family found, each against a
reference from outside the engine — hand statics of the rigid body, or the
rigid-body LP over the pads' polygons written with scipy.optimize.linprog
(tests/helpers/rigid_body_lp.py)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from formulations.frames import SpaceFrame
from formulations.frames.mechanics.rigid_limit import limit_bracket
from formulations.frames.space.space_family import pipe_rack, skid, table
from qpcontact.core.errors import InvalidProblemError, SolverFailedError
from tests.helpers.limits import kept, timed
from tests.helpers.rigid_body_lp import bounded_at_the_lp, coulomb_limits, static_limit

CONST = {"constant": 1.0}
W = 40.0          # the tables' weight at C (kN)


def assert_bracket(tr, value, rtol=1e-9):
    assert tr.ended == "collapse" and tr.ok, tr.message
    lo, hi = tr.limit
    assert lo <= value * (1 + rtol) and value <= hi * (1 + rtol), (tr.limit, value)
    assert (hi - lo) / hi <= 1e-6, tr.limit


def test_the_reference_lp_agrees_with_hand_statics():
    """The LP's own check: sliding μW, tipping about the far legs W·1/0.5
    (C at x = 1, the overhang's tip 0.5 beyond x = 2), and Coulomb's
    circle's turning limit μW·r̄ of four pads at the corners of 2.0 x 1.2
    (each at r = √(1² + 0.6²) from C) between the 2048-gons."""
    fr = table(4, 1e4, cone="circumscribed")
    assert static_limit(fr, CONST, {"centre": 1.0}) == pytest.approx(0.3 * W, rel=1e-12)
    assert static_limit(fr, CONST, {"overhang": 1.0}) == pytest.approx(W * 1.0 / 0.5, rel=1e-12)
    lo, hi = coulomb_limits(fr, CONST, {"twist": 1.0})
    assert lo <= 0.3 * W * np.hypot(1.0, 0.6) <= hi * (1 + 1e-12)


@pytest.mark.parametrize("build, case", [
    (lambda: table(3, 1e4, cone="inscribed"), "twist"),
    (lambda: table(4, 1e4, cone="inscribed"), "overhang"),
    (lambda: table(6, 1.0, cone="circumscribed"), "corner"),
    (lambda: skid(cone="inscribed"), "corner"),
    (lambda: pipe_rack(cone="circumscribed"), "uplift"),
])
def test_the_rigid_proof_stands_within_rounding_of_the_lp(build, case):
    """The proof's motion is the LP's dual made exact on its active rays:
    its load p_hi is the next float above the exact limit of that motion,
    so it lies within rounding of the independent LP's optimum (before, a
    margin 1e-10 … 1e-7 above; the tipping table on inscribed polygons
    found no proof below 1e-6)."""
    fr = build()
    ref = static_limit(fr, CONST, {case: 1.0})
    p_hi, proof = limit_bracket(fr, fr.build(), CONST, {case: 1.0}, 0.0)
    assert proof is not None
    assert abs(p_hi - ref) <= 1e-12 * ref, (p_hi, ref)
    assert proof["work"] > 0


@pytest.mark.parametrize("cone", ["circular", "circumscribed"])
@pytest.mark.parametrize("stiffness", [1e2, 1e6])
def test_elastic_pads_under_a_deck_1e8_stiffer_are_no_mechanism(stiffness, cone):
    """Pads much softer (1e2 kN/m) or much stiffer (1e6) than the legs under
    a deck 1e8 times stiffer: the basic system's pivots spanned 4e-24 and
    8e-20 unscaled, and the table was refused as "a mechanism even with
    every contact closed".  It tips about its far legs at W·1/0.5 = 80."""
    fr = table(4, 1e8, stiffness=stiffness, cone=cone)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")       # soft pads settle 0.1 m: large displacements
        tr = fr.trace(variable="overhang")
    assert_bracket(tr, 80.0)
    assert "tips over about F1, F2" in tr.message


@pytest.mark.parametrize("cone", ["circular", "circumscribed"])
def test_a_stiff_deck_on_stiff_pads_slides_at_mu_w_with_right_forces(cone):
    """Its answers were refused by the refinement's own singularity test
    (unscaled pivots 8e-20: "CHECK FAILED" on right forces).  Below μW by
    hand: the normal forces W/4 ∓ p h / (2 a) on the legs behind and ahead
    (the push p at h = 0.8 m, the legs a = 2 m apart along it), the friction
    forces summing to p."""
    fr = table(4, 1e8, stiffness=1e6, cone=cone)
    tr = fr.trace(variable="centre")
    assert_bracket(tr, 0.3 * W)
    for f in (0.5, 0.9, 0.99):
        p = f * tr.limit[0]
        res = fr.solve(combination={"constant": 1.0, "centre": p})
        assert res.ok, res.message
        n = [res.supports[f"F{k}"].normal for k in range(4)]
        heavy, light = W / 4 + p * 0.8 / (2 * 2.0), W / 4 - p * 0.8 / (2 * 2.0)
        assert n == pytest.approx([light, heavy, heavy, light], rel=1e-9)
        fx = sum(res.supports[f"F{k}"].tangential_global[0] for k in range(4))
        assert fx == pytest.approx(-p, rel=1e-9)


@pytest.mark.slow
def test_a_twisted_table_on_inscribed_polygons_is_traced_to_its_limit():
    """Before: a piece failed the frame's checks 3e-5 below the limit
    (equilibrium residual 1.4e-9) and the trace ended "breakdown"; the path
    now restarts just beyond the last certified point."""
    fr = table(4, 1e4, cone="inscribed")
    tr = fr.trace(variable="twist")
    ref = static_limit(fr, CONST, {"twist": 1.0})
    assert np.cos(np.pi / 16) * 0.3 * W * np.hypot(1.0, 0.6) <= ref
    assert_bracket(tr, ref)


def test_a_corner_push_says_what_is_known_where_the_path_stops_below_the_lp():
    """Coulomb's law is non-associated: pushed at a corner, the table's
    path on inscribed polygons stops at 10.225 with every pad slipping,
    below the rigid body's 10.3227 (the LP), and Lemke beyond it ends on
    secondary rays.  Before: "breakdown", nothing proved.  Now "bounded":
    the last certified equilibrium (checked here by solving there), how
    the frame moves there, and the proved upper bound, at the LP's value."""
    tr, res, _ = bounded_at_the_lp(table(4, 1e4, cone="inscribed"), "corner")
    assert res.ok and all(v.state == "slip" for v in res.supports.values()), res.message
    assert "certified up to p = 10.22" in tr.message and "slips along" in tr.message
    assert "no equilibrium exists for p >= 10.32273" in tr.message


@pytest.mark.parametrize("polygon", ["inscribed", "circumscribed"])
@pytest.mark.slow
def test_a_pipe_rack_under_uplift_is_solved_below_its_limit(polygon):
    """Lemke at the fixed load can end on a secondary ray (the rack at 90 and
    99 % of its limit raised SolverFailedError); the load path — the pipes'
    weight first, then the uplift — reaches it.  By hand: the pads carry the
    pipes (6 kN/m on two 12 m lines) less the uplift, and the sideways 0.2 p
    by friction."""
    fr = pipe_rack(cone=polygon)
    ref = static_limit(fr, CONST, {"uplift": 1.0})
    for f in (0.5, 0.9, 0.99):
        p = f * ref
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = fr.solve(combination={"constant": 1.0, "uplift": p})
        assert res.ok, res.message
        forces = sum(v.normal for v in res.supports.values())
        assert forces == pytest.approx(2 * 12.0 * 6.0 - p, rel=1e-9)
        fy = sum(v.tangential_global[1] for v in res.supports.values())
        assert fy == pytest.approx(-0.2 * p, rel=1e-9)


def test_a_beam_on_two_pads_is_still_a_mechanism():
    """The scaled pivots still see a true mechanism: a beam on two point
    pads turns freely about its own axis."""
    fr = SpaceFrame()
    fr.add_node("A", 0, 0, 0)
    fr.add_node("B", 1, 0, 0)
    fr.add_member("A", "B", 2e8, 1e-3, 1e-6, 1e-6, G=8e7, J=2e-6)
    fr.add_contact("A", friction=0.3)
    fr.add_contact("B", friction=0.3)
    fr.add_load("B", fz=-1.0)
    with pytest.raises(InvalidProblemError, match="mechanism"):
        fr.solve(0.0)


def test_on_the_circle_the_load_path_keeps_the_time_limit():
    """The path that solve() follows where the friction solvers fail (the
    table below: ~3 s on an idle machine) reads the call's deadline before
    each of its solves: with 1 s it stops, and says that nothing was
    proved."""
    fr = table(6, 1.0)

    def refused():
        with pytest.raises(SolverFailedError) as info, warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fr.solve(combination={"constant": 1.0, "corner": 0.999 * 7.1162938026},
                     time_limit=1.0)
        return str(info.value)

    # One-time costs first (imports, numba's cache).  Its outcome is not what
    # is tested: compiling is left out of the time limit, so on a cold cache
    # the friction solvers get further and once certified the answer (a
    # fresh clone's make test).
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fr.solve(combination={"constant": 1.0, "corner": 0.999 * 7.1162938026},
                     time_limit=1.0)
    except SolverFailedError:
        pass
    words, took = timed(refused)
    assert "within the time limit" in words and "nothing was proved" in words, words
    assert kept(1.0, took), took


@pytest.mark.slow
def test_on_the_circle_solve_follows_the_load_path_where_the_friction_solvers_fail():
    """A slender six-legged table (deck as stiff as its legs) pushed at a
    corner, at 99.9 % of the load where its path on Coulomb's circle ends
    (7.11629, well below the rigid body's 10.397: its own normal forces
    exhaust the pads' friction): the friction solvers' answer lifted five
    pads off and failed its certificate (7e-4).  solve() now follows the
    constant loads, then the push, to it.  Checked by hand statics: the
    pads' forces balance the 40 kN weight and the push in force and in
    moment about the deck's centre, each within Coulomb's circle."""
    fr = table(6, 1.0)
    p = 0.999 * 7.1162938026
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve(combination={"constant": 1.0, "corner": p})
    assert res.ok, res.message
    # the loads, read off the frame: 40 kN down at the deck's centre C and
    # the push p along x at a corner of the deck (the family's cases)
    force, moment = np.zeros(3), np.zeros(3)
    for nd, v, case in fr.nodal_loads:
        f = {"constant": 1.0, "corner": p}.get(case, 0.0) * np.asarray(v, float)
        force += f[:3]
        moment += np.cross(np.asarray(fr.nodes[nd], float), f[:3]) + f[3:]
    assert np.hypot(*force[:2]) == pytest.approx(p, rel=1e-12) and force[2] == pytest.approx(-W)
    pads = res.support_reactions
    total = sum(np.asarray(f, float) for f in pads.values())
    turning = sum(np.cross(np.asarray(fr.nodes[nd], float), np.asarray(f, float))
                  for nd, f in pads.items())
    assert np.abs(total + force).max() <= 1e-9 * W
    assert np.abs(turning + moment).max() <= 1e-9 * W * 3.0
    for s in res.supports.values():
        assert s.normal >= 0.0 and np.hypot(*s.tangential) <= 0.3 * s.normal * (1 + 1e-9)
