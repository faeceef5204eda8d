"""Member loads on space frames — point forces and moments, partial and
trapezoidal distributed loads, self-weight, in global and member axes —
against PyNite 3-D (nodal displacements, reactions and the members'
deflection along their length, on a frame with members in four
orientations, two of them rolled) and against statics by hand (a
cantilever under a point load and a moment inside its span, a partial
load; the diagrams' jumps at the load)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from formulations.frames import SpaceFrame
from qpcontact.core.errors import InvalidProblemError
from tests.helpers.frame_twins import A, E, G, IY, IZ, J, OI, pynite_twins, space_zones

L = 4.0


def _cantilever():
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", L, 0.0, 0.0)
    fr.add_member("A", "B", E, A, IY, IZ, G=G, J=J, name="M")
    fr.add_support("A")
    return fr


def test_a_point_force_and_moment_inside_a_cantilever_by_hand():
    """At a = 1.5 m: F = (2, -3, 5) kN, M = (0.7, -1.1, 0.4) kN·m (member
    axes = global here).  Beyond a nothing; before it the section carries
    the load: N = Fx, Vy = -Fy, Vz = -Fz, T = Mx, Mz = Fy (a - x) + Mz_load,
    My = Fz (a - x) - My_load (module space_diagrams' reading of the face's
    forces); the tip deflections from the clamp's curvature by hand."""
    a, F, M = 1.5, np.array([2.0, -3.0, 5.0]), np.array([0.7, -1.1, 0.4])
    fr = _cantilever()
    fr.add_point_load("M", a, *F, *M)
    r = fr.solve()
    assert r.ok, r.message
    x, N, Vy, Vz, T, My, Mz = r.diagram("M", 9)
    assert a in x and np.nextafter(a, 0.0) in x               # both sides of the jump
    left = x < a
    hand = {"N": np.where(left, F[0], 0.0), "Vy": np.where(left, -F[1], 0.0),
            "Vz": np.where(left, -F[2], 0.0), "T": np.where(left, M[0], 0.0),
            "My": np.where(left, F[2] * (a - x) - M[1], 0.0),
            "Mz": np.where(left, F[1] * (a - x) + M[2], 0.0)}
    for q, got in zip(hand, (N, Vy, Vz, T, My, Mz)):
        np.testing.assert_allclose(got, hand[q], rtol=0, atol=1e-12, err_msg=q)
    # the tip: w(L) = ∫ (L - s) My/EIy ds over [0, a], v(L) likewise with Mz
    v_tip = (F[1] * a ** 2 * (3 * L - a) / 6 + M[2] * a * (L - a / 2)) / (E * IZ)
    w_tip = (F[2] * a ** 2 * (3 * L - a) / 6 - M[1] * a * (L - a / 2)) / (E * IY)
    assert r.displacements["B"][1] == pytest.approx(v_tip, rel=1e-12)
    assert r.displacements["B"][2] == pytest.approx(w_tip, rel=1e-12)
    xd, d = r.deflection("M", 5)
    assert d[-1, 1] == pytest.approx(v_tip, rel=1e-12) and d[-1, 2] == pytest.approx(w_tip,
                                                                                    rel=1e-12)
    assert r.displacements["B"][3] == pytest.approx(M[0] * a / (G * J), rel=1e-12)


def test_a_partial_trapezoidal_load_on_a_cantilever_by_hand():
    """wz from -4 at x = 1 to -10 kN/m at x = 3 (global): the clamp carries
    the resultant R = -14 kN at its centroid x̄ = 1 + 2(2·10 + 4)/(3·14)...
    written as ∫ w and ∫ w s: My(0) = ∫ w(s) s ds, Vz(0) = -∫ w ds."""
    fr = _cantilever()
    fr.add_distributed_load("M", wz=-4.0, wz2=-10.0, start=1.0, end=3.0)
    r = fr.solve()
    s = np.linspace(1.0, 3.0, 200001)
    w = -4.0 - 3.0 * (s - 1.0)
    R, Ms = np.trapezoid(w, s), np.trapezoid(w * s, s)
    ends = r.end_forces("M")
    assert ends["i"]["Vz"] == pytest.approx(-R, rel=1e-9)
    assert ends["i"]["My"] == pytest.approx(Ms, rel=1e-9)
    assert ends["j"]["My"] == pytest.approx(0.0, abs=1e-12)
    x, *_, My, _ = r.diagram("M", 41)
    beyond = x >= 3.0
    assert np.all(np.abs(My[beyond]) <= 1e-12)


def test_self_weight_is_unit_weight_times_area_along_its_direction():
    """A simply supported member, 78.5 kN/m³ x A along -z: My = wL²/8 at
    midspan with w = 78.5 A; the same by weight_per_length."""
    for kw in ({"unit_weight": 78.5}, {"weight_per_length": 78.5 * A}):
        fr = SpaceFrame()
        fr.add_node("A", 0.0, 0.0, 0.0)
        fr.add_node("B", 0.0, L, 0.0)
        fr.add_member("A", "B", E, A, IY, IZ, G=G, J=J, name="M")
        fr.add_support("A", fix=("ux", "uy", "uz", "ry"))
        fr.add_support("B", fix=("ux", "uz"))
        fr.add_self_weight(**kw)
        r = fr.solve(combination={"D": 1.0})
        assert r.extremes("M")["My"]["max"] == pytest.approx((78.5 * A * L * L / 8, L / 2),
                                                             rel=1e-12)
        assert sum(rea[2] for rea in r.reactions.values()) == pytest.approx(78.5 * A * L,
                                                                            rel=1e-12)


def test_misplaced_member_loads_are_named():
    fr = _cantilever()
    with pytest.raises(InvalidProblemError, match="lies outside the member"):
        fr.add_point_load("M", 4.5, fz=-1.0)
    with pytest.raises(InvalidProblemError, match="end .* before start"):
        fr.add_distributed_load("M", wz=-1.0, start=3.0, end=1.0)
    with pytest.raises(InvalidProblemError, match="no member named 'Q'"):
        fr.add_point_load("Q", 1.0, fz=-1.0)
    with pytest.raises(InvalidProblemError, match="exactly one of unit_weight"):
        fr.add_self_weight()
    with pytest.raises(InvalidProblemError, match="nonzero 3-vector"):
        fr.add_self_weight(unit_weight=1.0, direction=(0.0, -1.0))


# -- against PyNite 3-D -------------------------------------------------------------------

NODES = {"A": (0.0, 0.0, 0.0), "B": (3.0, 0.0, 0.0), "C": (3.0, 2.5, 0.5),
         "D": (3.0, 2.5, 3.0), "E": (1.0, 4.0, 3.5)}
MEMBERS = [("A", "B", 0.0), ("B", "C", 25.0), ("C", "D", 0.0), ("D", "E", -40.0)]
#: (member, PyNite direction, value, x) point loads; lower case: member axes
POINT = [("M0", "Fy", -6.0, 1.0), ("M0", "FZ", 4.0, 2.2), ("M1", "Mz", 2.5, 1.0),
         ("M1", "MX", -1.5, 0.8), ("M2", "Fz", 3.0, 1.25), ("M2", "My", -2.0, 2.0),
         ("M3", "FX", 5.0, 0.6), ("M3", "Mx", 0.9, 1.7)]
#: (member, direction, w1, w2, x1, x2) distributed loads
DIST = [("M0", "Fz", -3.0, -7.0, 0.5, 2.5), ("M1", "FY", 2.0, 2.0, 0.0, None),
        ("M2", "Fy", -4.0, 1.0, 0.3, 2.2), ("M3", "FZ", -5.0, -2.0, 1.0, None)]
PYNITE_TO_OURS = {"FX": "fx", "FY": "fy", "FZ": "fz", "MX": "mx", "MY": "my", "MZ": "mz"}


def _length(i, j):
    return float(np.linalg.norm(np.subtract(NODES[j], NODES[i])))


def test_point_partial_and_trapezoidal_loads_against_pynite():
    """Every kind of member load, in member and global axes, on members in
    four orientations (two rolled): nodal displacements and the clamp's
    reactions to 1e-9, and each member's deflection along its local y and
    z at seven sections (PyNite's ``deflection``) to 1e-8 of the largest."""
    pytest.importorskip("Pynite", reason="PyNite is in the test extra (PyNiteFEA)")
    m, fr = pynite_twins(NODES, MEMBERS, E, G, A, IY, IZ, J)
    for member, direction, value, x in POINT:
        m.add_member_pt_load(member, direction, value, x, case="D")
        axes = "global" if direction.isupper() else "member"
        fr.add_point_load(member, x, **{PYNITE_TO_OURS[direction.upper()]: value}, axes=axes,
                          case="D")
    for member, direction, w1, w2, x1, x2 in DIST:
        i, j, _ = MEMBERS[int(member[1])]
        x2 = _length(i, j) if x2 is None else x2
        m.add_member_dist_load(member, direction, w1, w2, x1, x2, case="D")
        comp = PYNITE_TO_OURS[direction.upper()][1]
        fr.add_distributed_load(member, **{f"w{comp}": w1, f"w{comp}2": w2}, start=x1,
                                end=x2, axes="global" if direction.isupper() else "member",
                                case="D")
    m.add_load_combo("C", {"D": 1.0})
    m.analyze(check_statics=False)
    r = fr.solve(combination={"D": 1.0})
    assert r.ok, r.message
    big = 0.0
    for n in NODES:
        nd = m.nodes[n]
        theirs = np.array([getattr(nd, d)["C"] for d in ("DX", "DY", "DZ", "RX", "RY", "RZ")])
        big = max(big, np.abs(theirs).max())
        np.testing.assert_allclose(r.displacements[n], theirs, rtol=1e-9, atol=1e-10 * big,
                                   err_msg=n)
    a = m.nodes["A"]
    theirs = [getattr(a, f"Rxn{c}")["C"] for c in ("FX", "FY", "FZ", "MX", "MY", "MZ")]
    np.testing.assert_allclose(r.reactions["A"], theirs, rtol=1e-9,
                               atol=1e-9 * np.abs(theirs).max())
    for k, (i, j, _) in enumerate(MEMBERS):
        name = f"M{k}"
        x, d = r.deflection(name, 7)
        for xs, dd in zip(x[1:-1], d[1:-1]):
            theirs = [m.members[name].deflection(c, xs, "C") for c in ("dy", "dz")]
            np.testing.assert_allclose(dd[1:], theirs, rtol=0, atol=1e-8 * big * _length(i, j),
                                       err_msg=f"{name} at {xs}")


# -- end releases -------------------------------------------------------------------------

@pytest.mark.parametrize("axis, hinge", [("z", True), ("z", ("ry",)), ("y", ("rz",)),
                                         ("y", ("ry",))])
def test_a_hinge_at_a_members_end_carries_no_moment(axis, hinge):
    """A clamp at A, a roller at C, the member A-B hinged at B (about the
    loaded plane's axis), w = 5 kN/m down both members of 3 m: B-C is a
    simply supported span hung from the cantilever's tip, which carries
    its wL/2 — so M = 0 at the hinge, wL²/8 in the span B-C, and the clamp
    -(wL²/2 + wL/2·L) = -wL²; a hinge about the other axis alone leaves
    the frame as if continuous (its moment at B nonzero)."""
    w, span = 5.0, 3.0
    fr = SpaceFrame()
    for n, x in (("A", 0.0), ("B", span), ("C", 2 * span)):
        fr.add_node(n, x, 0.0, 0.0)
    fr.add_member("A", "B", E, A, IY, IZ, G=G, J=J, name="AB", hinge_j=hinge)
    fr.add_member("B", "C", E, A, IY, IZ, G=G, J=J, name="BC")
    fr.add_support("A")
    fr.add_support("C", fix=("uy", "uz", "rx"))
    M, V = ("My", "Vz") if axis == "z" else ("Mz", "Vy")
    for m in ("AB", "BC"):
        fr.add_distributed_load(m, **{f"w{axis}": -w})
    r = fr.solve()
    assert r.ok, r.message
    released = hinge is True or ("ry" if axis == "z" else "rz") in hinge
    if not released:
        assert abs(r.end_forces("AB")["j"][M]) > 0.1 * w * span ** 2
        return
    assert r.end_forces("AB")["j"][M] == pytest.approx(0.0, abs=1e-9)
    assert r.end_forces("BC")["i"][M] == pytest.approx(0.0, abs=1e-9)
    assert r.end_forces("AB")["i"][M] == pytest.approx(-w * span ** 2, rel=1e-12)
    assert r.extremes("BC")[M]["max"] == pytest.approx((w * span ** 2 / 8, span / 2), rel=1e-12)
    assert r.end_forces("BC")["i"][V] == pytest.approx(w * span / 2, rel=1e-12)


def test_releases_against_pynite():
    """The frame of four orientations with member loads, and releases at
    member ends in member axes — about z at one end, both bending moments
    at another, the twist at a third (its far node's rotations held):
    nodal displacements and reactions as PyNite's ``def_releases``."""
    pytest.importorskip("Pynite", reason="PyNite is in the test extra (PyNiteFEA)")
    # (PyNite's def_releases, our add_member keywords) per member
    releases = {"M1": ({"Rzi": True}, {"hinge_i": ("rz",)}),
                "M2": ({"Ryj": True, "Rzj": True}, {"hinge_j": True}),
                "M3": ({"Rxi": True}, {"hinge_i": ("rx",)})}
    m, fr = pynite_twins(NODES, MEMBERS, E, G, A, IY, IZ, J, releases=releases)
    m.def_support("E", False, False, True, True, True, True)
    fr.add_support("E", fix=("uz", "rx", "ry", "rz"))
    for member, direction, value, x in POINT:
        m.add_member_pt_load(member, direction, value, x, case="D")
        fr.add_point_load(member, x, **{PYNITE_TO_OURS[direction.upper()]: value},
                          axes="global" if direction.isupper() else "member", case="D")
    m.add_node_load("C", "FY", 3.0, case="D")
    fr.add_load("C", fy=3.0, case="D")
    m.add_load_combo("C", {"D": 1.0})
    m.analyze(check_statics=False)
    r = fr.solve(combination={"D": 1.0})
    assert r.ok, r.message
    big = max(abs(getattr(m.nodes[n], d)["C"]) for n in NODES for d in ("DX", "DY", "DZ"))
    for n in NODES:
        nd = m.nodes[n]
        theirs = np.array([getattr(nd, d)["C"] for d in ("DX", "DY", "DZ", "RX", "RY", "RZ")])
        np.testing.assert_allclose(r.displacements[n], theirs, rtol=1e-9, atol=1e-9 * big,
                                   err_msg=n)
    for n in ("A", "E"):
        theirs = [getattr(m.nodes[n], f"Rxn{c}")["C"] for c in ("FX", "FY", "FZ", "MX", "MY",
                                                                "MZ")]
        np.testing.assert_allclose(r.reactions[n], theirs, rtol=1e-9, atol=1e-9 * 10.0)
    # the released ends carry no moment
    ends = {name: r.end_forces(name) for name in releases}
    assert abs(ends["M1"]["i"]["Mz"]) <= 1e-9 and abs(ends["M3"]["i"]["T"]) <= 1e-9
    assert max(abs(ends["M2"]["j"]["My"]), abs(ends["M2"]["j"]["Mz"])) <= 1e-9


def test_a_twist_released_at_both_ends_is_refused():
    fr = _cantilever()
    fr.add_node("C", L, 2.0, 0.0)
    with pytest.raises(InvalidProblemError, match="twist is released at both ends"):
        fr.add_member("B", "C", E, A, IY, IZ, G=G, J=J, hinge_i=("rx",), hinge_j=("rx", "ry"))
    with pytest.raises(InvalidProblemError, match="hinge_j: True .* among"):
        fr.add_member("B", "C", E, A, IY, IZ, G=G, J=J, hinge_j="x")


# -- settlements --------------------------------------------------------------------------

@pytest.mark.parametrize("dof, axis", [("uz", "y"), ("uy", "z")])
def test_a_clamped_beams_support_settles(dof, axis):
    """Both ends clamped, B settles by δ = -5 mm across the member (case
    "S"): the fixed-end actions of a sway by hand, M = ∓6EIδ/L² at A and B
    (the end that stays hogs when B drops: the +side fibre in tension),
    V = 12EIδ/L³ — about y for a settlement along z, about z along y;
    nothing else moves."""
    delta = -5e-3
    fr = SpaceFrame()
    for n, x in (("A", 0.0), ("C", L / 2), ("B", L)):     # C: a free node between
        fr.add_node(n, x, 0.0, 0.0)
    fr.add_member("A", "C", E, A, IY, IZ, G=G, J=J, name="M")
    fr.add_member("C", "B", E, A, IY, IZ, G=G, J=J, name="N")
    fr.add_support("A")
    fr.add_support("B")
    fr.add_settlement("B", "S", **{dof: delta})
    r = fr.solve(combination={"S": 1.0})
    assert r.ok, r.message
    I_ = IY if axis == "y" else IZ
    M, V = f"M{axis}", f"V{'z' if axis == 'y' else 'y'}"
    at_a, at_b = r.end_forces("M")["i"], r.end_forces("N")["j"]
    assert at_a[M] == pytest.approx(6 * E * I_ * delta / L ** 2, rel=1e-12)
    assert at_b[M] == pytest.approx(-6 * E * I_ * delta / L ** 2, rel=1e-12)
    assert at_a[V] == pytest.approx(-12 * E * I_ * delta / L ** 3, rel=1e-12)
    assert r.displacements["B"][("ux", "uy", "uz").index(dof)] == delta


def test_a_settlement_needs_a_support_there():
    fr = _cantilever()
    with pytest.raises(InvalidProblemError, match="uz is not fixed by a bilateral support"):
        fr.add_settlement("B", uz=-0.01)
    with pytest.raises(InvalidProblemError, match="dofs among"):
        fr.add_settlement("A", wz=-0.01)


# -- Timoshenko members ---------------------------------------------------------------------

AS_Y, AS_Z = 0.004, 0.007              # m², shear areas along local y and z (stubby: φ ~ 0.1-1)


def test_a_timoshenko_cantilever_bends_and_shears_along_both_axes():
    """Tip forces Py, Pz on a 1.2 m cantilever with shear areas: the
    deflection along the span is P x²(3L - x)/6EI + P x/(G A_s) in each
    plane (bending plus the constant shear strain V/(G A_s))."""
    Ls, py, pz = 1.2, 30.0, -45.0
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", Ls, 0.0, 0.0)
    fr.add_member("A", "B", E, A, IY, IZ, G=G, J=J, name="M", shear_area=(AS_Y, AS_Z))
    fr.add_support("A")
    fr.add_load("B", fy=py, fz=pz)
    r = fr.solve()
    assert r.ok, r.message
    x, d = r.deflection("M", 13)
    for k, (P, I_, As) in enumerate(((py, IZ, AS_Y), (pz, IY, AS_Z)), start=1):
        hand = P * x ** 2 * (3 * Ls - x) / (6 * E * I_) + P * x / (G * As)
        np.testing.assert_allclose(d[:, k], hand, rtol=1e-12, atol=1e-15)
        assert P * Ls / (G * As) / hand[-1] > 0.05           # the shear part matters here
    # one number is both planes' area
    fr2 = SpaceFrame()
    fr2.add_node("A", 0.0, 0.0, 0.0)
    fr2.add_node("B", Ls, 0.0, 0.0)
    fr2.add_member("A", "B", E, A, IY, IZ, G=G, J=J, name="M", shear_area=AS_Y)
    fr2.add_support("A")
    fr2.add_load("B", fz=pz)
    assert fr2.solve().displacements["B"][2] == pytest.approx(
        pz * Ls ** 3 / (3 * E * IY) + pz * Ls / (G * AS_Y), rel=1e-12)


@pytest.mark.parametrize("load", ["point", "partial"])
def test_timoshenko_member_loads_are_its_exact_fixed_end_forces(load):
    """A clamped-clamped Timoshenko member, 1.5 m, with a load in its span
    (a point force and moment about both axes, or a partial trapezoid
    across both) against the same member cut at the load's ends into
    pieces (the point load: a nodal load; the trapezoid: 60 pieces with
    its resultants at the nodes, which converges as h², compared to 1e-4):
    the displacements where they meet."""
    Ls, a = 1.5, 0.55

    def frame(cuts):
        fr = SpaceFrame()
        xs = sorted({0.0, Ls, *cuts})
        for k, x in enumerate(xs):
            fr.add_node(f"N{k}", x, 0.0, 0.0)
        for k in range(len(xs) - 1):
            fr.add_member(f"N{k}", f"N{k + 1}", E, A, IY, IZ, G=G, J=J, name=f"M{k}",
                          shear_area=(AS_Y, AS_Z))
        fr.add_support("N0")
        # the far end clamped but for its twist, which no load here strains (a frame
        # with no free dof at all is refused by the basic system's LU: dev-notes)
        fr.add_support(f"N{len(xs) - 1}", fix=("ux", "uy", "uz", "ry", "rz"))
        return fr, xs

    if load == "point":
        one, _ = frame([])
        one.add_point_load("M0", a, fy=20.0, fz=-35.0, my=4.0, mz=-6.0)
        cut, xs = frame([a])
        cut.add_load("N1", fy=20.0, fz=-35.0, my=4.0, mz=-6.0)
        rtol = 1e-12
    else:
        one, _ = frame([])
        one.add_distributed_load("M0", wy=-10.0, wz=4.0, wy2=-30.0, wz2=-8.0, start=0.3,
                                 end=1.2)
        pieces = np.linspace(0.3, 1.2, 61)
        cut, xs = frame(list(pieces))
        at = {x: k for k, x in enumerate(xs)}
        h = pieces[1] - pieces[0]
        for lo, hi in zip(pieces[:-1], pieces[1:]):
            t = (0.5 * (lo + hi) - 0.3) / 0.9
            wy, wz = -10.0 - 20.0 * t, 4.0 - 12.0 * t
            for x in (lo, hi):
                cut.add_load(f"N{at[x]}", fy=wy * h / 2, fz=wz * h / 2)
        rtol = 1e-4
    r1, r2 = one.solve(), cut.solve()
    x, d = r1.deflection("M0", 7)
    ref = {xs[k]: r2.displacements[f"N{k}"] for k in range(len(xs))}
    for xx, dd in zip(x, d):
        near = min(ref, key=lambda s: abs(s - xx))
        if abs(near - xx) < 1e-12 and 0.0 < xx < Ls:
            np.testing.assert_allclose(dd[1:], np.asarray(ref[near][1:3]), rtol=rtol,
                                       atol=rtol * np.abs(d).max())


# -- rigid end zones ------------------------------------------------------------------------

def test_rigid_end_zones_against_hand_formulas():
    """A 5 m cantilever, tip forces Py, Pz.  A rigid zone of 0.6 m at the
    clamp: a cantilever of the flexible length, P (L - a)³/3EI across each
    axis, the clamp's moment still P L.  A rigid arm of 0.8 m at the tip:
    the flexible end carries P and P b, d = P l³/3EI + P b l²/2EI, slope
    P l²/2EI + P b l/EI, and the tip d + b·slope; the curve along the
    flexible length P x²(3l - x)/6EI + P b x²/2EI."""
    Ls, a, b, py, pz = 5.0, 0.6, 0.8, 3.0, -4.0

    def cantilever(**offsets):
        fr = SpaceFrame()
        fr.add_node("A", 0.0, 0.0, 0.0)
        fr.add_node("B", Ls, 0.0, 0.0)
        fr.add_member("A", "B", E, A, IY, IZ, G=G, J=J, name="M", **offsets)
        fr.add_support("A")
        fr.add_load("B", fy=py, fz=pz)
        r = fr.solve()
        assert r.ok, r.message
        return r

    r = cantilever(offset_i=a)
    for k, (P, I_) in enumerate(((py, IZ), (pz, IY)), start=1):
        assert r.displacements["B"][k] == pytest.approx(P * (Ls - a) ** 3 / (3 * E * I_),
                                                        rel=1e-12)
    ends = r.end_forces("M")["i"]
    assert (ends["Mz"], ends["My"]) == pytest.approx((py * Ls, pz * Ls), rel=1e-12)
    r = cantilever(offset_j=b)
    lf = Ls - b
    x, d = r.deflection("M", 11)
    for k, (P, I_) in enumerate(((py, IZ), (pz, IY)), start=1):
        end = P * lf ** 3 / (3 * E * I_) + P * b * lf ** 2 / (2 * E * I_)
        slope = P * lf ** 2 / (2 * E * I_) + P * b * lf / (E * I_)
        assert r.displacements["B"][k] == pytest.approx(end + b * slope, rel=1e-12)
        flex = x <= lf
        hand = P * x[flex] ** 2 * (3 * lf - x[flex]) / (6 * E * I_) \
            + P * b * x[flex] ** 2 / (2 * E * I_)
        np.testing.assert_allclose(d[flex, k], hand, rtol=0, atol=1e-12 * abs(end))
        np.testing.assert_allclose(d[~flex, k], end + (x[~flex] - lf) * slope, rtol=0,
                                   atol=1e-12 * abs(end))


def test_rigid_zones_with_a_face_hinge_and_loads_match_nearly_rigid_members():
    """Zones of 0.4 and 0.7 m, a hinge about y at the j face, a partial
    trapezoid, a point force and a torque on the zones and the span, the
    member rolled: against the same member cut at the faces with the zones
    as members 1e6 times stiffer (the hinge then a release at that piece's
    end; the linear route refines such an answer in extended precision, its
    check passing to 1e7: dev-notes, "Frames: the linear route's check at
    high stiffness contrast"): the reactions and the deflection at the point
    load in the span to 1e-5, the stiff zones' own flexibility being 1e-6."""
    one, cut = space_zones(1e6)
    r1, r2 = one.solve(), cut.solve()
    assert r1.ok and r2.ok, (r1.message, r2.message)
    big = np.abs(r2.reactions["A"]).max()
    np.testing.assert_allclose(r1.reactions["A"], r2.reactions["A"], rtol=0, atol=1e-5 * big)
    np.testing.assert_allclose(r1.reactions["B"], r2.reactions["B"], rtol=0, atol=1e-5 * big)
    x, d = r1.deflection("M", 9)
    at = np.flatnonzero(x == 2.0)
    xf, df = r2.deflection("F", 9)
    np.testing.assert_allclose(d[at[-1]], df[np.flatnonzero(np.isclose(xf, 2.0 - OI))[-1]], rtol=0,
                               atol=1e-5 * np.abs(d).max())


@pytest.mark.parametrize("ratio_y, ratio_z", [(0.5, 3.0), (1e9, 0.0)])
def test_a_semi_rigid_clamp_of_a_propped_beam_about_each_axis(ratio_y, ratio_z):
    """A member clamped at A through rotational springs k = ratio EI/L
    about its y and z, propped at B, w = 6 kN/m across both axes: the
    clamp's moment (wL²/8)/(1 + 3EI/(kL)) in each plane (0 for a spring of
    0, the hinge; wL²/8 for a stiff one)."""
    w = 6.0
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", L, 0.0, 0.0)
    fr.add_member("A", "B", E, A, IY, IZ, G=G, J=J, name="M",
                  spring_i={"ry": ratio_y * E * IY / L, "rz": ratio_z * E * IZ / L})
    fr.add_support("A")
    fr.add_support("B", fix=("uy", "uz"))
    fr.add_distributed_load("M", wy=-w, wz=-w)
    r = fr.solve()
    assert r.ok, r.message
    ends = r.end_forces("M")["i"]
    for q, ratio in (("My", ratio_y), ("Mz", ratio_z)):
        hand = 0.0 if ratio == 0 else -(w * L * L / 8) / (1 + 3 / ratio)
        assert ends[q] == pytest.approx(hand, rel=1e-9, abs=1e-12), q


def test_a_spring_and_a_hinge_on_one_rotation_are_refused():
    fr = _cantilever()
    fr.add_node("C", L, 2.0, 0.0)
    with pytest.raises(InvalidProblemError, match="give hinge_i or spring_i for \\['rz'\\]"):
        fr.add_member("B", "C", E, A, IY, IZ, G=G, J=J, hinge_i=("rz",), spring_i={"rz": 1e3})
    with pytest.raises(InvalidProblemError, match=r"ry must be in \[0, 1e\+100\].*got -1.0"):
        fr.add_member("B", "C", E, A, IY, IZ, G=G, J=J, spring_j=-1.0)


def test_point_and_partial_member_loads_are_drawn_with_their_values():
    """The drawing shows a member's point force where it acts and a partial
    trapezoid with its end values, besides the uniform load (the texts on
    the rendered figure)."""
    import matplotlib

    matplotlib.use("Agg")
    from tests.helpers.figures import drawn, overlapping

    fr = _cantilever()
    fr.add_point_load("M", 1.5, fz=-12.0)
    fr.add_distributed_load("M", wy=-2.0, wy2=-6.0, start=2.0, end=3.5)
    fr.add_distributed_load("M", wz=-1.0)
    r = fr.solve()
    fig = drawn(r.plot)
    texts = [t for ax in fig.axes for t in ax.texts if t.get_text().strip()]
    words = [t.get_text() for t in texts]
    assert any("12" in w and "kN" in w and "/" not in w for w in words), words
    assert any("→" in w and "2" in w and "6" in w for w in words), words
    assert any("kN/m" in w and "1" in w and "→" not in w for w in words), words
    assert not overlapping(fig, texts)
