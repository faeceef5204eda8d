"""The member and support features engineers reach for, each
against an independent reference: hand formulas (a propped cantilever with
an internal hinge or a semi-rigid end, a Timoshenko cantilever, rigid end
offsets), the same structure modelled another way (a Timoshenko member cut
at its point load, where nodal loads need no shape functions; a rigid zone
as a nearly rigid member), statics of an inclined roller, and PyNite
(releases, deflection along a member) where it has the feature."""

from __future__ import annotations

import numpy as np
import pytest

from formulations.frames import Frame
from formulations.frames import SMALL_DISPLACEMENT, LargeDisplacementWarning
from qpcontact.core.errors import InvalidProblemError

E, A, I = 2e8, 0.01, 1e-4          # kN/m², m², m⁴
EI = E * I


def _close(a, b, rtol=1e-9, scale=None):
    scale = np.max(np.abs(b)) if scale is None else scale
    assert np.max(np.abs(np.asarray(a) - np.asarray(b))) <= rtol * scale, (a, b)


def test_propped_cantilever_with_an_internal_hinge():
    """Fixed at A, hinge at C (x = a), propped by a contact at B: CB is
    simply supported, so R_B = w(L-a)/2; AC a cantilever carrying w and
    the hinge's shear."""
    L, a, w = 8.0, 3.0, 12.0
    fr = Frame()
    for n, x in (("A", 0.0), ("C", a), ("B", L)):
        fr.add_node(n, x, 0.0)
    fr.add_member("A", "C", E, A, I, name="AC", hinge_j=True)
    fr.add_member("C", "B", E, A, I, name="CB")
    fr.add_support("A")
    fr.add_contact("B")
    for m in ("AC", "CB"):
        fr.add_distributed_load(m, wy=-w)
    r = fr.solve()
    assert r.ok, r.message
    P = w * (L - a) / 2
    _close(r.supports["B"].normal, P)
    _close(r.reactions["A"], (0.0, w * a + P, w * a ** 2 / 2 + P * a), scale=w * L * L)
    x, _, v = r.deflection("AC", 11)
    # cantilever under w and the tip load P
    ref = -(w * x ** 2 * (6 * a ** 2 - 4 * a * x + x ** 2) / (24 * EI)
            + P * x ** 2 * (3 * a - x) / (6 * EI))
    _close(v, ref)
    assert abs(r.end_forces("AC")["j"]["M"]) <= 1e-9 * w * L * L   # the hinge carries no moment


@pytest.mark.parametrize("k_ratio", [0.0, 0.5, 3.0, 1e9])
def test_semi_rigid_end_of_a_propped_cantilever(k_ratio):
    """A rotational spring k = k_ratio·EI/L at the fixed end: compatibility
    of rotations gives M_A = (wL²/8)/(1 + 3EI/(kL)) (0 for a hinge, the
    fixed end's wL²/8 for k -> inf)."""
    L, w = 6.0, 10.0
    k = k_ratio * EI / L
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, A, I, name="AB", spring_i=k)
    fr.add_support("A")
    fr.add_contact("B")
    fr.add_distributed_load("AB", wy=-w)
    r = fr.solve()
    assert r.ok, r.message
    MA = 0.0 if k == 0 else (w * L * L / 8) / (1 + 3 * EI / (k * L))
    _close(-r.end_forces("AB")["i"]["M"], MA, scale=w * L * L)
    _close(r.supports["B"].normal, w * L / 2 - MA / L, scale=w * L)


def test_hinge_equals_a_spring_of_zero_and_both_are_refused_together():
    def frame(**kw):
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", 5.0, 0.0)
        fr.add_member("A", "B", E, A, I, name="AB", **kw)
        fr.add_support("A")
        fr.add_contact("B")
        fr.add_load("B", fy=-10.0)
        fr.add_distributed_load("AB", wy=-3.0)
        return fr.solve()

    a, b = frame(hinge_i=True), frame(spring_i=0.0)
    _close(a.supports["B"].normal, b.supports["B"].normal)
    with pytest.raises(InvalidProblemError, match="not both"):
        frame(hinge_i=True, spring_i=5.0)


def _cantilever(L, P, **kw):
    """Fixed at A, tip B free (its contact stays open: gap 1 m), P down at B."""
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, A, I, name="AB", **kw)
    fr.add_support("A")
    fr.add_contact("B", gap=1.0)
    fr.add_load("B", fy=-P)
    r = fr.solve()
    assert r.ok and r.supports["B"].state == "separated", r.message
    return r


def test_timoshenko_cantilever_deflects_by_bending_plus_shear():
    L, P, G, As = 2.0, 50.0, 8e7, 0.002      # a deep beam: shear is ~9 % of the tip deflection
    r = _cantilever(L, P, G=G, shear_area=As)
    x, _, v = r.deflection("AB", 21)
    ref = -P * (x ** 2 * (3 * L - x) / (6 * EI) + x / (G * As))
    _close(v, ref)
    _close(r.displacements["B"][1], ref[-1])
    eb = _cantilever(L, P)
    assert abs(r.displacements["B"][1]) > 1.05 * abs(eb.displacements["B"][1])  # shear adds > 5 %


@pytest.mark.parametrize("load", ["force", "moment", "partial"])
def test_timoshenko_member_loads_are_its_exact_fixed_end_forces(load):
    """One Timoshenko member with a load inside its span against the same
    member cut in two at the load (nodal loads need no shape functions)
    or in 40 pieces (a partial distributed load, lumped consistently on
    short pieces converges as h²; compared to 1e-4)."""
    L, a, G, As = 4.0, 1.3, 8e7, 0.006

    def model(cuts):
        fr = Frame()
        xs = sorted(set([0.0, L] + cuts))
        for k, x in enumerate(xs):
            fr.add_node(f"N{k}", x, 0.0)
        for k in range(len(xs) - 1):
            fr.add_member(f"N{k}", f"N{k + 1}", E, A, I, name=f"M{k}", G=G, shear_area=As)
        last = f"N{len(xs) - 1}"
        fr.add_support("N0")
        fr.add_support(last, fix=("ux", "rz"))
        fr.add_contact(last)
        return fr, last

    if load == "partial":
        fr, end = model([])
        fr.add_distributed_load("M0", wy=-20.0, wy2=-5.0, start=0.5, end=3.1)
        xs = np.linspace(0.0, L, 41)
        ref_fr, ref_end = model(list(xs))
        for k in range(len(xs) - 1):
            mid = 0.5 * (xs[k] + xs[k + 1])
            if 0.5 < mid < 3.1:
                q = -20.0 + 15.0 * (mid - 0.5) / 2.6
                ref_fr.add_distributed_load(f"M{k}", wy=q)
        rtol = 1e-3
    else:
        fr, end = model([])
        ref_fr, ref_end = model([a])
        if load == "force":
            fr.add_point_load("M0", a, fy=-30.0)
            ref_fr.add_load("N1", fy=-30.0)
        else:
            fr.add_point_load("M0", a, mz=25.0)
            ref_fr.add_load("N1", mz=25.0)
        rtol = 1e-9
    r, ref = fr.solve(), ref_fr.solve()
    assert r.ok and ref.ok
    _close(r.reactions["N0"], ref.reactions["N0"], rtol=rtol)
    _close(r.supports[end].normal, ref.supports[ref_end].normal, rtol=rtol,
           scale=np.max(np.abs(ref.reactions["N0"])))
    # the deflection along the span, at the cut member's nodes: a load in the
    # span is what shows the shear strain's sign (a constant V is absorbed
    # by the line through the ends; the point force's deflection read
    # -1.7e-5 m for +2.6e-5 with it reversed)
    x, _, v = r.deflection("M0", 41)
    for k, xn in enumerate(sorted(ref_fr.nodes, key=lambda n: ref_fr.nodes[n][0])):
        at = ref_fr.nodes[xn][0]
        hit = np.flatnonzero(np.abs(x - at) <= 1e-12 * L)
        if hit.size and 0.0 < at < L:
            _close(v[hit[-1]], ref.displacements[xn][1], rtol=rtol,
                   scale=np.abs(v).max())


def test_rigid_end_offsets_against_hand_formulas():
    L, P, a, b = 5.0, 20.0, 0.6, 0.8
    # a rigid zone at the clamp: a cantilever of the flexible length
    r = _cantilever(L, P, offset_i=a)
    _close(r.displacements["B"][1], -P * (L - a) ** 3 / (3 * EI))
    _close(r.reactions["A"][2], P * L)
    # a rigid arm at the tip: the flexible end carries P and P·b
    r = _cantilever(L, P, offset_j=b)
    lf = L - b
    d_end = P * lf ** 3 / (3 * EI) + P * b * lf ** 2 / (2 * EI)
    th_end = P * lf ** 2 / (2 * EI) + P * b * lf / EI
    _close(r.displacements["B"][1], -(d_end + b * th_end))
    x, _, v = r.deflection("AB", 11)
    _close(v[x <= lf], -P * x[x <= lf] ** 2 * (3 * lf - x[x <= lf]) / (6 * EI)
           - P * b * x[x <= lf] ** 2 / (2 * EI), scale=abs(v).max())


@pytest.mark.parametrize("hinge", [False, True])
def test_offsets_with_member_loads_match_nearly_rigid_members(hinge):
    """Rigid zones (with a hinge at the face of the first one) under a
    trapezoidal load over the whole member and a point load inside a zone,
    against the zones modelled as members 1e7 times stiffer."""
    L, a, b = 6.0, 0.5, 0.75

    def base():
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", L, 0.0)
        fr.add_support("A", fix=("ux", "uy", "rz"))
        fr.add_contact("B")
        return fr

    fr = base()
    fr.add_member("A", "B", E, A, I, name="AB", offset_i=a, offset_j=b, hinge_i=hinge)
    fr.add_distributed_load("AB", wy=-10.0, wy2=-4.0)
    fr.add_point_load("AB", 0.3, fy=-7.0)
    r = fr.solve()

    ref = base()
    ref.add_node("A1", a, 0.0)
    ref.add_node("B1", L - b, 0.0)
    stiff = 1e7
    ref.add_member("A", "A1", E, A * stiff, I * stiff, name="R1")
    ref.add_member("A1", "B1", E, A, I, name="F", hinge_i=hinge)
    ref.add_member("B1", "B", E, A * stiff, I * stiff, name="R2")
    for m, x0, x1 in (("R1", 0.0, a), ("F", a, L - b), ("R2", L - b, L)):
        ref.add_distributed_load(m, wy=-10.0 + 6.0 * x0 / L, wy2=-10.0 + 6.0 * x1 / L)
    ref.add_point_load("R1", 0.3, fy=-7.0)
    # members 1e7 times stiffer leave the reference 2e-9 off in its reactions
    # (its equilibrium check says so at "high"); it is compared at 1e-6
    rr = ref.solve(accuracy=1e-7)
    assert r.ok and rr.ok
    _close(r.reactions["A"], rr.reactions["A"], rtol=1e-6)
    _close(r.supports["B"].normal, rr.supports["B"].normal, rtol=1e-6)
    _close(r.displacements["B"], rr.displacements["B"], rtol=1e-6)
    x, _, v = r.deflection("AB", 1201)    # fine enough that interpolating it is exact to 1e-6
    xf, _, vf = rr.deflection("F", 9)
    _close(np.interp(xf + a, x, v), vf, rtol=1e-4)


def test_offsets_refused_where_nothing_flexible_is_left():
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 1.0, 0.0)
    with pytest.raises(InvalidProblemError, match="flexible length"):
        fr.add_member("A", "B", E, A, I, offset_i=0.6, offset_j=0.4)


@pytest.mark.parametrize("angle", [30.0, -45.0, 60.0])
def test_inclined_roller_reacts_across_its_slope(angle):
    """A beam pinned at A on an inclined roller at B (fix uy of axes turned
    by the angle): the roller pushes along its normal n = (-sin, cos), so
    moments about A give R = wL/(2 cos) for angle != 90; B moves along the
    slope only."""
    L, w = 6.0, 10.0
    fr = Frame()
    for n, x in (("A", 0.0), ("C", 3.0), ("B", L)):
        fr.add_node(n, x, 0.0)
    fr.add_member("A", "C", E, A, I, name="M1")
    fr.add_member("C", "B", E, A, I, name="M2")
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_support("B", fix=("uy",), angle=angle)
    fr.add_contact("C", gap=1.0)
    for m in ("M1", "M2"):
        fr.add_distributed_load(m, wy=-w)
    fr.add_load("B", fx=4.0)
    c, s = np.cos(np.radians(angle)), np.sin(np.radians(angle))
    r = fr.solve()
    assert r.ok, r.message
    R = (w * L * L / 2) / (c * L)
    _close(r.reactions["B"], (-R * s, R * c, 0.0), scale=w * L)
    _close(r.reactions["A"][:2], (R * s - 4.0, w * L - R * c), scale=w * L)
    d = np.array(r.displacements["B"][:2])
    assert abs(d @ (-s, c)) <= 1e-12 * np.abs(d).max()


def test_one_set_of_axes_per_node():
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_support("A", fix=("uy",), angle=30.0)
    with pytest.raises(InvalidProblemError, match="one set of axes"):
        fr.add_support("A", fix=("ux",), angle=10.0)
    with pytest.raises(InvalidProblemError, match="one set of axes"):
        fr.add_support("A", fix=("ux",))


def test_releases_and_deflection_agree_with_pynite():
    """A two-bay beam with a moment release at an interior member end, on
    compression-only springs, against PyNite: reactions and the deflection
    along a member (PyNite's Member3D.deflection)."""
    pytest.importorskip("Pynite", reason="PyNite is in the test extra (PyNiteFEA)")
    from Pynite import FEModel3D

    xs, k = [0.0, 4.0, 9.0, 12.0], 5e4
    fr = Frame()
    m = FEModel3D()
    m.add_material("s", E, E / 2.6, 0.3, 0.0)
    m.add_section("x", A, I, I, 2 * I)
    for n, x in enumerate(xs):
        fr.add_node(f"N{n}", x, 0.0)
        fr.add_contact(f"N{n}", stiffness=k)
        m.add_node(f"N{n}", x, 0.0, 0.0)
        m.def_support(f"N{n}", support_DX=n == 0, support_DZ=True, support_RX=True,
                      support_RY=True)
        m.def_support_spring(f"N{n}", "DY", k, "-")
    fr.add_support("N0", fix=("ux",))
    for n in range(len(xs) - 1):
        fr.add_member(f"N{n}", f"N{n + 1}", E, A, I, name=f"M{n}", hinge_j=(n == 0))
        fr.add_distributed_load(f"M{n}", wy=-9.0, case="D")
        m.add_member(f"M{n}", f"N{n}", f"N{n + 1}", "s", "x")
        m.add_member_dist_load(f"M{n}", "FY", -9.0, -9.0, case="D")
    m.def_releases("M0", Rzj=True)
    fr.add_point_load("M1", 2.0, fy=-60.0, case="D")
    m.add_member_pt_load("M1", "FY", -60.0, 2.0, case="D")
    fr.add_load("N3", fy=40.0, case="D")        # lifts N3 off
    m.add_node_load("N3", "FY", 40.0, case="D")
    m.add_load_combo("C", {"D": 1.0})
    m.analyze(check_statics=False)
    r = fr.solve(combination={"D": 1.0})
    assert r.ok, r.message
    assert r.supports["N3"].state == "separated"
    ours = np.array([r.supports[f"N{n}"].normal for n in range(len(xs))])
    ref = np.array([m.nodes[f"N{n}"].RxnFY["C"] for n in range(len(xs))])
    _close(ours, ref, rtol=1e-8)
    x, _, v = r.deflection("M1", 11)
    pn = np.array([m.members["M1"].deflection("dy", xx, "C") for xx in x])
    _close(v, pn, rtol=1e-7)


def test_displacements_beyond_small_displacement_theory_are_reported():
    """A cantilever's tip deflection PL³/(3EI) against the frame's size L:
    the result carries the ratio, and solve warns beyond SMALL_DISPLACEMENT
    (and only then)."""
    L = 5.0
    P_limit = SMALL_DISPLACEMENT * L * 3 * EI / L ** 3
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", LargeDisplacementWarning)
        r = _cantilever(L, 0.9 * P_limit)
    _close(r.displacement_ratio, 0.9 * SMALL_DISPLACEMENT, rtol=1e-6)
    with pytest.warns(LargeDisplacementWarning, match=r"node B has moved 0\.15 m \(0\.03 of"):
        r = _cantilever(L, 1.5 * P_limit)
    _close(r.displacement_ratio, 1.5 * SMALL_DISPLACEMENT, rtol=1e-6)
    assert "beyond small-displacement theory" in r.message


def test_deflection_extremes_of_a_simple_beam():
    """On two contacts under a uniform load: the largest deflection is
    5wL⁴/(384EI), at midspan, in extremes() and in the members table."""
    L, w = 7.0, 11.0
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, A, I, name="AB")
    fr.add_support("A", fix=("ux",))
    fr.add_contact("A")
    fr.add_contact("B")
    fr.add_distributed_load("AB", wy=-w)
    r = fr.solve()
    value, x = r.extremes("AB")["v"]["min"]
    _close(value, -5 * w * L ** 4 / (384 * EI))
    _close(x, L / 2, scale=L)
    row = r.rows("members", digits=None)[0]
    assert row["v_min [m]"] == value and row["x(v_min) [m]"] == x


def test_a_moment_on_a_pin_joint_is_refused():
    """Only released ends meet at B: its rotation is no dof, and a moment
    applied there acted on nothing while the result said ok (review)."""
    fr = Frame()
    for n, x in (("A", 0.0), ("B", 4.0), ("C", 8.0)):
        fr.add_node(n, x, 0.0)
    fr.add_member("A", "B", E, A, I, hinge_j=True)
    fr.add_member("B", "C", E, A, I, hinge_i=True)
    fr.add_support("A")
    fr.add_contact("C")
    fr.add_load("B", mz=50.0)
    with pytest.raises(InvalidProblemError, match="node 'B': a moment is applied where no"):
        fr.solve()


@pytest.mark.parametrize("rigid", [False, True])
def test_a_node_on_springs_and_a_contact_alone_is_solved(rigid):
    """A frame of no member — a node on springs to the ground and a
    contact, rigid or elastic — is a sound model: the load goes into the
    spring and the contact by hand.  The contact checks' force scale was
    summed by a bincount of no weights, integers, which the springs' terms
    could not be added to (UFuncTypeError, plane and space frames alike)."""
    from formulations.frames.space.space_frame import SpaceFrame

    fr = Frame()
    fr.add_node("a", 0.0, 0.0)
    fr.add_spring("a", ux=1e3, rz=1e3)
    fr.add_contact("a", normal=(0.0, 1.0), stiffness=None if rigid else 1e4)
    fr.add_load("a", fx=0.5, fy=-1.0)
    r = fr.solve()
    assert r.ok, r.message
    _close(r.displacements["a"], (0.5 / 1e3, 0.0 if rigid else -1.0 / 1e4, 0.0))
    assert r.supports["a"].normal == pytest.approx(1.0, rel=1e-12)
    sf = SpaceFrame()
    sf.add_node("a", 0.0, 0.0, 0.0)
    sf.add_spring("a", ux=1e3, uy=1e3, rx=1e3, ry=1e3, rz=1e3)
    sf.add_contact("a", stiffness=None if rigid else 1e4)
    sf.add_load("a", fz=-1.0)
    r = sf.solve()
    assert r.ok, r.message
    _close(r.displacements["a"], (0.0, 0.0, 0.0 if rigid else -1.0 / 1e4, 0.0, 0.0, 0.0), scale=1e-4)
