"""Second-order analysis of plane frames (P-Δ and P-δ) on their contacts,
against closed forms of the beam-column equation EI v'''' + P v'' = 0
written here: a cantilever's tip deflection under a compressive or tensile
axial force, its base moment by statics on the deformed column, its
buckling load π²EI/(4L²); a sway portal as two cantilevers of half the
height; a column on two rigid pads whose windward pad lifts at the
second-order tipping load W a / (h + (tan kh − kh)/k), below the
first-order W a / h."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from formulations.frames import Frame
from qpcontact.core.errors import NoSolutionError, SolverFailedError

E, A, I = 2e8, 1e-2, 2e-5       # kN/m², m², m⁴: a steel column


def cantilever(L, P, H, stub=True) -> Frame:
    """A column of height L fixed at A, axial load P (compression
    positive) and lateral H at its tip B; a stub on a pad gives the frame
    its one contact."""
    fr = Frame(units=("kN", "m"))
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    fr.add_member("A", "B", E, A, I, name="column")
    fr.add_support("A")
    if stub:
        fr.add_node("C", 2.0, 0.0)
        fr.add_member("A", "C", E, A, I, name="stub")
        fr.add_contact("C", normal=(0.0, 1.0))
    fr.add_load("B", fx=H, fy=-P)
    return fr


@pytest.mark.parametrize("share", [0.1, 0.5, 0.9])
def test_a_cantilever_sways_as_the_beam_column_equation_says(share):
    """Compression P: δ = H (tan kL − kL) / (P k), k = √(P/EI); the base
    moment is H L + P δ (statics on the deformed column); the first-order
    δ is H L³/(3EI)."""
    L = 5.0
    P = share * np.pi ** 2 * E * I / (4 * L ** 2)
    H = 10.0
    fr = cantilever(L, P, H)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        first = fr.solve()
        res = fr.solve(second_order=True)
    assert res.ok, res.message
    k = np.sqrt(P / (E * I))
    delta = H * (np.tan(k * L) - k * L) / (P * k)
    assert first.displacements["B"][0] == pytest.approx(H * L ** 3 / (3 * E * I), rel=1e-12)
    assert res.displacements["B"][0] == pytest.approx(delta, rel=1e-9)
    # the fixed support's moment balances H and P on the deformed column
    assert res.reactions["A"][2] == pytest.approx(H * L + P * delta, rel=1e-9)
    assert res.second_order["axial"]["column"] == pytest.approx(-P, rel=1e-12)
    assert res.second_order["stable"] is True


def test_a_cantilever_in_tension_is_stiffer():
    """Tension T: δ = H (kL − tanh kL) / (T k), k = √(T/EI)."""
    L, T, H = 5.0, 300.0, 10.0
    fr = cantilever(L, -T, H)
    res = fr.solve(second_order=True)
    assert res.ok, res.message
    k = np.sqrt(T / (E * I))
    assert res.displacements["B"][0] == pytest.approx(H * (k * L - np.tanh(k * L)) / (T * k),
                                                      rel=1e-9)


@pytest.mark.parametrize("share", [0.3, 0.5])
def test_the_critical_load_factor_of_a_cantilever_is_eulers(share):
    """α_cr = P_cr / P with P_cr = π²EI/(4L²), from one element per member."""
    L = 5.0
    P_cr = np.pi ** 2 * E * I / (4 * L ** 2)
    fr = cantilever(L, share * P_cr, 1.0)
    res = fr.solve(second_order=True)
    crit = fr.critical_load_factor(res)
    assert crit["alpha"] == pytest.approx(1 / share, rel=1e-8)
    assert crit["limited_by"] is None
    # the mode is the sway of the tip
    assert abs(crit["mode"]["B"][0]) == pytest.approx(1.0)


def test_the_critical_load_factor_at_low_accuracy_reads_the_answers_own_axial_forces():
    """A portal lifted at its joints (columns in tension) whose beam, lightly
    compressed by the sway, sets α_cr: the axial forces that built the last
    stiffness are converged only to "low"'s 1e-4 on the scale EA/L |u|, so
    the beam's N was 2e-3 off and α_cr with it; the answer's own N is
    a round further on, α_cr to 1e-6 of "high"'s."""
    fr = Frame(units=("kN", "m"))
    for name, x, y in (("A", 0, 0), ("B", 0, 4), ("C", 6, 4), ("D", 6, 0)):
        fr.add_node(name, x, y)
    fr.add_member("A", "B", E, 1e-2, 1e-5, name="L")
    fr.add_member("B", "C", E, 5e-3, 4e-5, name="T")
    fr.add_member("D", "C", E, 1e-2, 1e-5, name="R")
    fr.add_support("A")
    fr.add_support("D")
    fr.add_load("B", fx=50.0, fy=300.0)
    fr.add_load("C", fy=300.0)
    fr.add_distributed_load("T", 0.0, -5.0, axes="member")
    alpha = {}
    for accuracy in ("low", "high"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = fr.solve(second_order=True, accuracy=accuracy)
        alpha[accuracy] = fr.critical_load_factor(res)["alpha"]
    assert alpha["low"] == pytest.approx(alpha["high"], rel=1e-5)


def test_a_frame_in_tension_only_has_no_critical_load():
    fr = cantilever(5.0, -100.0, 1.0)
    res = fr.solve(second_order=True)
    assert fr.critical_load_factor(res)["alpha"] == np.inf


def portal(P, H, h=4.0, span=6.0) -> Frame:
    """Columns fixed at their bases A, D, tops B, C held from turning by a
    beam 1e8 times stiffer and by the columns' own axial stiffness (A x
    1e4: with the section's own A the beam turns by the columns'
    shortening, and the portal buckles 4e-4 below the guided column);
    P down on each top, H sideways at B; a stub on a pad gives the frame
    its one contact."""
    fr = Frame(units=("kN", "m"))
    for n, (x, y) in {"A": (0, 0), "B": (0, h), "C": (span, h), "D": (span, 0),
                      "S": (-2.0, 0.0)}.items():
        fr.add_node(n, x, y)
    fr.add_member("A", "B", E, A * 1e4, I, name="AB")
    fr.add_member("D", "C", E, A * 1e4, I, name="DC")
    fr.add_member("B", "C", E, A * 1e4, I * 1e8, name="BC")
    fr.add_member("A", "S", E, A, I)
    fr.add_support("A")
    fr.add_support("D")
    fr.add_contact("S", normal=(0.0, 1.0))
    fr.add_load("B", fy=-P)
    fr.add_load("C", fy=-P)
    if H:
        fr.add_load("B", fx=H)
    return fr


def test_a_sway_portal_with_a_rigid_beam_sways_as_half_cantilevers():
    """Each column bends antisymmetrically about its mid-height: two
    cantilevers of h/2, so its shear at a sway Δ under its axial force P_c
    is V = Δ P_c κ / (2 (tan(κh/2) − κh/2)), κ = √(P_c/EI); the two
    shears carry H.  The columns' axial forces differ by the overturning
    (P ± about H h / span) and sum to 2P (vertical statics)."""
    h, P, H = 4.0, 500.0, 20.0
    fr = portal(P, H, h)
    res = fr.solve(second_order=True)
    assert res.ok, res.message
    axial = res.second_order["axial"]
    assert axial["AB"] + axial["DC"] == pytest.approx(-2 * P, rel=1e-9)
    sway = res.displacements["B"][0]
    shears = 0.0
    for col in ("AB", "DC"):
        Pc = -axial[col]
        kap = np.sqrt(Pc / (E * I))
        shears += sway * Pc * kap / (2 * (np.tan(kap * h / 2) - kap * h / 2))
    assert shears == pytest.approx(H, rel=1e-6)
    # first order: the same columns with no axial force, 12EI/h³ each
    assert fr.solve().displacements["B"][0] == pytest.approx(H * h ** 3 / (24 * E * I), rel=1e-6)


def test_a_sway_portal_buckles_at_eulers_sway_load():
    """P_cr = π²EI/h² per column (fixed at one end, sliding without
    turning at the other)."""
    h, P = 4.0, 500.0
    fr = portal(P, 0.0, h)
    res = fr.solve(second_order=True)
    crit = fr.critical_load_factor(res)
    assert crit["alpha"] == pytest.approx(np.pi ** 2 * E * I / h ** 2 / P, rel=1e-6)
    assert abs(crit["mode"]["B"][0]) == pytest.approx(abs(crit["mode"]["C"][0]), rel=1e-6)


def column_on_pads(W, a=1.0, h=6.0) -> Frame:
    """A column (E, A, I) of height h on a base 1e4 times stiffer, on two
    rigid pads at ±a (μ = 1: it tips before it slides), W on its top and
    the case "variable" a unit push there."""
    fr = Frame(units=("kN", "m"))
    for n, x in (("L", -a), ("O", 0.0), ("R", a)):
        fr.add_node(n, x, 0.0)
    fr.add_node("T", 0.0, h)
    fr.add_member("L", "O", E * 1e4, A * 10, I * 1e4)
    fr.add_member("O", "R", E * 1e4, A * 10, I * 1e4)
    fr.add_member("O", "T", E, A, I, name="column")
    fr.add_contact("L", normal=(0.0, 1.0), friction=1.0)
    fr.add_contact("R", normal=(0.0, 1.0), friction=1.0)
    fr.add_load("T", fy=-W)
    fr.add_load("T", fx=1.0, case="variable")
    return fr


def test_a_column_on_pads_tips_at_its_second_order_load():
    """Statics on the deformed column about the leeward pad R: the windward
    pad carries N_L = W/2 − (H h + W Δ)/(2a), Δ = H (tan kh − kh)/(W k)
    the column's sway on its (rigid) base; it lifts at H = W a / (h + (tan
    kh − kh)/k), 26 % below the first-order W a / h here.  Beyond it no
    equilibrium the frame can rest in exists."""
    h, a = 6.0, 1.0
    W = 0.3 * np.pi ** 2 * E * I / (4 * h ** 2)
    k = np.sqrt(W / (E * I))
    H_tip = W * a / (h + (np.tan(k * h) - k * h) / k)
    assert H_tip < 0.75 * W * a / h
    fr = column_on_pads(W, a, h)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # the column sways 0.26 m
        for share in (0.5, 0.99, 0.999):
            H = share * H_tip
            res = fr.solve(p=H, second_order=True)
            assert res.ok, res.message
            delta = H * (np.tan(k * h) - k * h) / (W * k)
            n_left = W / 2 - (H * h + W * delta) / (2 * a)
            assert res.supports["L"].normal == pytest.approx(n_left, abs=1e-9 * W)
            assert res.supports["L"].normal + res.supports["R"].normal == pytest.approx(W)
            assert fr.critical_load_factor(res)["alpha"] > 1.0
        # first order would carry 1.3 x the second-order tipping load
        assert fr.solve(p=1.3 * H_tip).ok
        for share in (1.001, 1.01):
            try:
                res = fr.solve(p=share * H_tip, second_order=True)
            except NoSolutionError:
                continue
            assert not res.ok, res.message


def test_second_order_is_refused_on_a_frame_passed_prebuilt():
    fr = cantilever(5.0, 10.0, 1.0)
    with pytest.raises(Exception, match="_built"):
        fr.solve(second_order=True, _built=fr.build())


def test_the_second_order_trace_of_a_column_on_pads_ends_where_it_tips():
    """The path on the deformed frame ends where the windward pad's force
    reaches zero, at the hand value W a / (h + (tan kh − kh)/k); the
    first-order path ends at W a / h (the rigid body tips)."""
    h, a = 6.0, 1.0
    W = 0.3 * np.pi ** 2 * E * I / (4 * h ** 2)
    k = np.sqrt(W / (E * I))
    fr = column_on_pads(W, a, h)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        first = fr.trace()
        second = fr.trace(second_order=True)
    assert first.ended == "collapse" and first.ok
    assert first.limit[0] <= W * a / h * (1 + 1e-9) <= first.limit[1] * (1 + 2e-9)
    assert second.ended == "stability" and second.ok, second.message
    assert second.limit[0] == pytest.approx(W * a / (h + (np.tan(k * h) - k * h) / k), rel=1e-9)
    assert "L carries nothing" in second.message
    assert second.second_order["path_axial_change"] < 1e-9


def space_cantilever(L, P, Hx, Hy, Iy=2e-5, Iz=5e-5):
    from formulations.frames import SpaceFrame

    fr = SpaceFrame(units=("kN", "m"), cone="inscribed")
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 0.0, 0.0, L)
    fr.add_node("C", 2.0, 0.0, 0.0)
    section = dict(E=E, G=8e7, A=A, Iy=Iy, Iz=Iz, J=1e-5)
    fr.add_member("A", "B", **section, name="column")
    fr.add_member("A", "C", **section, name="stub")
    fr.add_support("A")
    fr.add_contact("C", normal=(0.0, 0.0, 1.0))
    fr.add_load("B", fx=Hx, fy=Hy, fz=-P)
    return fr


def test_a_space_cantilever_sways_in_each_plane_with_its_own_stiffness():
    """A vertical column's member axes put its x-z bending on Iy and its
    y-z bending on Iz: each sway is the beam-column's closed form with
    that plane's EI, and it buckles about the weaker axis."""
    L, Iy, Iz = 5.0, 2e-5, 5e-5
    P = 0.5 * np.pi ** 2 * E * Iy / (4 * L ** 2)
    fr = space_cantilever(L, P, 7.0, 10.0, Iy, Iz)
    res = fr.solve(second_order=True)
    assert res.ok, res.message

    def sway(H, EI):
        k = np.sqrt(P / EI)
        return H * (np.tan(k * L) - k * L) / (P * k)

    assert res.displacements["B"][0] == pytest.approx(sway(7.0, E * Iy), rel=1e-9)
    assert res.displacements["B"][1] == pytest.approx(sway(10.0, E * Iz), rel=1e-9)
    assert fr.critical_load_factor(res)["alpha"] == pytest.approx(2.0, rel=1e-8)


def test_a_space_frame_in_one_plane_gives_the_plane_frames_second_order_answer():
    """The sway portal built in the x-z plane of a space frame (its
    out-of-plane axis the strong one): the same sway and axial forces as
    the plane frame's, to 1e-9."""
    from formulations.frames import SpaceFrame

    h, span, P, H = 4.0, 6.0, 500.0, 20.0
    plane = portal(P, H, h, span)
    sp_ = SpaceFrame(units=("kN", "m"), cone="inscribed")
    for n, (x, z) in {"A": (0, 0), "B": (0, h), "C": (span, h), "D": (span, 0),
                      "S": (-2.0, 0.0)}.items():
        sp_.add_node(n, x, 0.0, z)
    col = dict(E=E, G=8e7, A=A * 1e4, Iy=I, Iz=I * 1e3, J=I)
    sp_.add_member("A", "B", **col, name="AB")
    sp_.add_member("D", "C", **col, name="DC")
    sp_.add_member("B", "C", E=E, G=8e7, A=A * 1e4, Iy=I * 1e8, Iz=I * 1e8, J=I * 1e8, name="BC")
    sp_.add_member("A", "S", E=E, G=8e7, A=A, Iy=I, Iz=I, J=I)
    sp_.add_support("A")
    sp_.add_support("D")
    sp_.add_contact("S", normal=(0.0, 0.0, 1.0))
    sp_.add_load("B", fz=-P)
    sp_.add_load("C", fz=-P)
    sp_.add_load("B", fx=H)
    a, b = plane.solve(second_order=True), sp_.solve(second_order=True)
    assert a.ok and b.ok, (a.message, b.message)
    assert b.displacements["B"][0] == pytest.approx(a.displacements["B"][0], rel=1e-9)
    for m in ("AB", "DC"):
        assert b.second_order["axial"][m] == pytest.approx(a.second_order["axial"][m], rel=1e-9)


@pytest.mark.slow
def test_a_space_column_on_four_pads_tips_at_its_second_order_load():
    """The 2-D column on pads in 3-D: a stiff cross on four rigid pads at
    (±a, ±a), pushed along x; on inscribed squares (μ = 1: it tips
    before it slides) the path ends where P0 and P3 unload, at the plane
    hand value W a / (h + (tan kh − kh)/k)."""
    from formulations.frames import SpaceFrame

    h, a = 6.0, 1.0
    W = 0.3 * np.pi ** 2 * E * I / (4 * h ** 2)
    fr = SpaceFrame(units=("kN", "m"), cone="inscribed")
    fr.add_node("O", 0.0, 0.0, 0.0)
    fr.add_node("T", 0.0, 0.0, h)
    cross = dict(E=E * 1e4, G=8e11, A=A * 10, Iy=I * 1e4, Iz=I * 1e4, J=I * 1e4)
    for k, (x, y) in enumerate([(-a, -a), (a, -a), (a, a), (-a, a)]):
        fr.add_node(f"P{k}", x, y, 0.0)
        fr.add_member("O", f"P{k}", **cross)
        fr.add_contact(f"P{k}", normal=(0.0, 0.0, 1.0), friction=1.0, facets=4)
    fr.add_member("O", "T", E=E, G=8e7, A=A, Iy=I, Iz=I, J=I, name="column")
    fr.add_load("T", fz=-W)
    fr.add_load("T", fx=1.0, case="variable")
    k = np.sqrt(W / (E * I))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ft = fr.trace(second_order=True)
    assert ft.ended == "stability" and ft.ok, ft.message
    assert ft.limit[0] == pytest.approx(W * a / (h + (np.tan(k * h) - k * h) / k), rel=1e-9)
    assert "P0, P3 carry nothing" in ft.message


def test_the_second_order_trace_of_a_frame_without_contacts_is_second_order():
    """A linear frame's trace is one interval; on the deformed frame its
    sway at p is the beam-column's closed form (its rounds once got a
    first-order assembly: half the sway, called second order)."""
    L = 5.0
    P = 0.5 * np.pi ** 2 * E * I / (4 * L ** 2)
    fr = cantilever(L, P, 0.0, stub=False)
    fr.add_load("B", fx=1.0, case="variable")
    ft = fr.trace(p_max=10.0, second_order=True)
    assert ft.ok, ft.message
    k = np.sqrt(P / (E * I))
    assert ft.result_at(10.0).displacements["B"][0] == pytest.approx(
        10.0 * (np.tan(k * L) - k * L) / (P * k), rel=1e-9)


@pytest.mark.parametrize("share", [1 - 1e-12, 1.0, 1 + 1e-12])
def test_a_column_at_its_buckling_load_is_named_as_buckling_not_as_a_mechanism(share):
    """At P_cr = π²EI/(4L²) to rounding the column's stability functions
    cancel its sway stiffness: K(N) is singular with the column in place.
    The answer must name that loss of stiffness (its elastic critical load),
    not call the frame a mechanism whose node "no member holds" (the words
    of a missing member, which sent the engineer to look for one); plane,
    space and the trace alike.  Either side of it, 1e-6 of P_cr away, the
    answer is the beam-column's amplified sway (ok below, UNSTABLE above)."""
    L = 5.0
    P_cr = np.pi ** 2 * E * I / (4 * L ** 2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for fr in (cantilever(L, share * P_cr, 10.0), space_cantilever(L, share * P_cr, 10.0, 0.0)):
            with pytest.raises(SolverFailedError, match="elastic critical load") as err:
                fr.solve(second_order=True)
            assert "column N = -394.784" in str(err.value)
            assert "no member" not in str(err.value)
        fr = cantilever(L, share * P_cr, 0.0)
        fr.add_load("B", fx=1.0, case="variable")
        with pytest.raises(SolverFailedError, match="elastic critical load"):
            fr.trace(1.0, second_order=True)
        for side, stable in ((1 - 1e-6, True), (1 + 1e-6, False)):
            P = side * P_cr
            res = cantilever(L, P, 10.0).solve(second_order=True)
            k = np.sqrt(P / (E * I))
            assert res.ok is stable and res.second_order["stable"] is stable
            # the closed form's conditioning, 1/(1 - P/P_cr) = 1e6, costs digits
            assert res.displacements["B"][0] == pytest.approx(
                10.0 * (np.tan(k * L) - k * L) / (P * k), rel=1e-8)


def strut(P, hinge_i, hinge_j, L=5.0):
    """A vertical member A-B under P at B: A held in ux, uy (and rz where
    the member is rigidly joined there), B in ux (and rz likewise)."""
    fr = Frame(units=("kN", "m"))
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    fr.add_member("A", "B", E, A, I, name="strut", hinge_i=hinge_i, hinge_j=hinge_j)
    fr.add_support("A", fix=("ux", "uy") if hinge_i else ("ux", "uy", "rz"))
    fr.add_support("B", fix=("ux",) if hinge_j else ("ux", "rz"))
    fr.add_load("B", fy=-P)
    return fr


# ψ² at a member's own buckling with its nodes held: hinged at both ends π²;
# clamped at one, hinged at the other, the root of tan ψ = ψ (4.493409457909064)
# squared; clamped at both 4π²
OWN_T = {(True, True): np.pi ** 2, (False, True): 4.493409457909064 ** 2,
         (False, False): 4 * np.pi ** 2}


@pytest.mark.parametrize("ends", list(OWN_T))
def test_a_strut_buckles_at_its_own_euler_load_whatever_its_ends(ends):
    """A member with hinged ends has end rotations of its own, condensed
    out of the frame's stiffness; at its Euler load that condensation has a
    pole and the frame's count of negative eigenvalues no longer sees the
    member buckle (before: α_cr raised ValueError on a NaN, and the strut at
    1.1–3.9 P_e was answered ok, "stable").  α_cr = ψ² EI/(L² P); past it
    the second-order answer is UNSTABLE, naming the member."""
    L, P = 5.0, 100.0
    own = OWN_T[ends] * E * I / L ** 2
    fr = strut(P, *ends, L=L)
    crit = fr.critical_load_factor(fr.solve())
    assert crit["alpha"] == pytest.approx(own / P, rel=1e-10)
    assert crit["limited_by"] == "strut"
    below = strut(0.9 * own, *ends, L=L).solve(second_order=True)
    assert below.ok and below.second_order["stable"] is True, below.message
    for share in (1.1, 3.9):
        res = strut(share * own, *ends, L=L).solve(second_order=True)
        assert not res.ok and res.second_order["stable"] is False
        assert "strut" in res.message and "own buckling" in res.message
    # the load path under a growing load: before, "p_max", ok, at 2 P_e
    fr = strut(0.0, *ends, L=L)
    fr.add_load("B", fy=-1.0, case="variable")
    tr = fr.trace(2 * own, second_order=True)
    assert not tr.ok and tr.ended == "breakdown"
    assert f"strut buckles on its own (its nodes held) at p = {own:.10g}" in tr.message


def test_a_space_strut_hinged_about_one_axis_buckles_about_it():
    """Hinged about its local y at both ends (ry released), clamped about
    z: it buckles at min(π² E Iy, 4π² E Iz)/L² — here about y, though Iy is
    2.5 times Iz."""
    from formulations.frames import SpaceFrame

    L, Iy, Iz, P = 5.0, 5e-5, 2e-5, 100.0
    fr = SpaceFrame(units=("kN", "m"))
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 0.0, 0.0, L)
    fr.add_member("A", "B", E, A, Iy, Iz, G=8e7, J=1e-5, name="strut",
                  hinge_i=("ry",), hinge_j=("ry",))
    fr.add_support("A")
    fr.add_support("B", fix=("ux", "uy", "rx", "ry", "rz"))
    fr.add_load("B", fz=-P)
    own = min(np.pi ** 2 * E * Iy, 4 * np.pi ** 2 * E * Iz) / L ** 2
    assert own == pytest.approx(np.pi ** 2 * E * Iy / L ** 2)
    crit = fr.critical_load_factor(fr.solve())
    assert crit["alpha"] == pytest.approx(own / P, rel=1e-10)
    fr.add_load("B", fz=-1.05 * own + P)
    res = fr.solve(second_order=True)
    assert not res.ok and "strut" in res.message


def test_a_leaning_column_that_buckles_on_its_own_limits_the_frame():
    """A cantilever (EI, h) holds a leaning column (hinged at both ends,
    EI_l) by a hinged link (EA/3 axially) at the top.  The sway buckles
    where the cantilever's tip flexibility under P, (tan kh − kh)/(P k),
    plus the link's equals the leaning load's h/Q (the link carries
    Q Δ_D/h); a slender leaning column buckles first on its own, at
    π² EI_l/h²: α_cr is the smaller of the two."""
    from scipy.optimize import brentq

    h, P = 4.0, 200.0
    for I_lean, Q in ((2e-5, 600.0), (1e-7, 600.0)):
        fr = Frame(units=("kN", "m"))
        for n, x, y in (("A", 0, 0), ("B", 0, h), ("C", 3, 0), ("D", 3, h)):
            fr.add_node(n, x, y)
        fr.add_member("A", "B", E, A, I, name="column")
        fr.add_member("C", "D", E, A, I_lean, name="leaning", hinge_i=True, hinge_j=True)
        fr.add_member("B", "D", E, A, I, name="link", hinge_i=True, hinge_j=True)
        fr.add_support("A")
        fr.add_support("C", fix=("ux", "uy"))
        fr.add_load("B", fy=-P)
        fr.add_load("D", fy=-Q)

        def sway(a):
            k = np.sqrt(a * P / (E * I))
            return (np.tan(k * h) - k * h) / (a * P * k) + 3.0 / (E * A) - h / (a * Q)

        frame_alpha = brentq(sway, 1e-3, (np.pi / 2) ** 2 * E * I / (h ** 2 * P) * (1 - 1e-12))
        own_alpha = np.pi ** 2 * E * I_lean / (h ** 2 * Q)
        crit = fr.critical_load_factor(fr.solve())
        assert crit["alpha"] == pytest.approx(min(frame_alpha, own_alpha), rel=1e-8)
        assert crit["limited_by"] == (None if frame_alpha < own_alpha else "leaning")


@pytest.mark.parametrize("kappa", [1.0, 10.0, 1e4])
def test_a_strut_between_rotational_springs_buckles_at_its_closed_form(kappa):
    """Both ends held in translation and rotation, the member joined to
    them by springs k = κ EI/L: its symmetric half-wave, v = cos(ψ(x/L −
    1/2)) − cos(ψ/2), meets the springs' M = k v' where κ = −ψ cot(ψ/2),
    ψ in (π, 2π) (π hinged, 2π clamped); α_cr = ψ² EI/(L² P)."""
    from scipy.optimize import brentq

    L, P = 5.0, 100.0
    psi = brentq(lambda p: -p / np.tan(p / 2) - kappa, np.pi + 1e-12, 2 * np.pi - 1e-12,
                 xtol=1e-15)
    fr = Frame(units=("kN", "m"))
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    k = kappa * E * I / L
    fr.add_member("A", "B", E, A, I, name="strut", spring_i=k, spring_j=k)
    fr.add_support("A")
    fr.add_support("B", fix=("ux", "rz"))
    fr.add_load("B", fy=-P)
    crit = fr.critical_load_factor(fr.solve())
    assert crit["alpha"] == pytest.approx(psi ** 2 * E * I / (L ** 2 * P), rel=1e-9)


def test_combinations_are_each_solved_to_second_order():
    """`solve_combinations(..., second_order=True)`: each combination on
    its own deformed frame — the windward pad's W/2 − (H h + W Δ)/(2a)
    (statics on the deformed column) for each H, the envelope over them;
    one past the second-order tipping load is not ok and the others are
    kept.  Before: InvalidOptionError "do not pass _built", which the user
    had not."""
    h, a = 6.0, 1.0
    W = 0.3 * np.pi ** 2 * E * I / (4 * h ** 2)
    k = np.sqrt(W / (E * I))
    H_tip = W * a / (h + (np.tan(k * h) - k * h) / k)
    fr = column_on_pads(W, a, h)
    shares = {"a": 0.3, "b": 0.9, "past": 1.2}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve_combinations({n: {"constant": 1.0, "variable": s * H_tip}
                                     for n, s in shares.items()}, second_order=True)
    assert res.failed == ["past"]
    for name in ("a", "b"):
        H = shares[name] * H_tip
        delta = H * (np.tan(k * h) - k * h) / (W * k)
        assert res[name].second_order["stable"] is True
        assert res[name].supports["L"].normal == pytest.approx(
            W / 2 - (H * h + W * delta) / (2 * a), abs=1e-9 * W)
    assert res.envelope()["supports"]["L"]["Fy"]["min"] == (res["b"].supports["L"].normal, "b")


@pytest.mark.parametrize("kind", ["plane", "space"])
@pytest.mark.parametrize("a, b", [(4.0, 1.0), (3.0, 2.0)])
def test_a_rigid_zone_at_the_loaded_end_carries_its_own_p_delta(kind, a, b):
    """A cantilever whose top b is a rigid end zone over a flexible length
    a, P and H at the top.  The zone turns with the flexible part's top and
    carries P sideways by b θ: EI v'' = H (L − x) + P (δ − v) with δ =
    v(a) + b v'(a) gives δ = c / (cos ka − b k sin ka), c = (H/P) (−L cos ka
    + sin(ka)/k + b + b (L k sin ka + cos ka − 1)), and buckling where
    tan ka = 1/(bk).  Before, the zone's own P-Δ was missing: α_cr 54 %
    (a = 4, b = 1) and 2.5 times (3, 2) high, the plane sway 10 % low and
    ok, the space one CHECK FAILED."""
    from scipy.optimize import brentq

    from formulations.frames import SpaceFrame

    L, P, H = a + b, 100.0, 1.0
    if kind == "plane":
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", 0.0, L)
        fr.add_member("A", "B", E, A, I, name="column", offset_j=b)
        fr.add_load("B", fx=H, fy=-P)
    else:
        fr = SpaceFrame()
        fr.add_node("A", 0.0, 0.0, 0.0)
        fr.add_node("B", 0.0, 0.0, L)
        fr.add_member("A", "B", E, A, I, I, G=8e7, J=1e-5, name="column", offset_j=b)
        fr.add_load("B", fx=H, fz=-P)
    fr.add_support("A")
    k = np.sqrt(P / (E * I))
    c = H / P * (-L * np.cos(k * a) + np.sin(k * a) / k + b
                 + b * (L * k * np.sin(k * a) + np.cos(k * a) - 1))
    delta = c / (np.cos(k * a) - b * k * np.sin(k * a))
    k_cr = brentq(lambda q: np.tan(q * a) - 1 / (b * q), 1e-6, np.pi / (2 * a) * (1 - 1e-12),
                  xtol=1e-15)
    res = fr.solve(second_order=True)
    assert res.ok, res.message
    assert res.displacements["B"][0] == pytest.approx(delta, rel=1e-9)
    assert fr.critical_load_factor(fr.solve())["alpha"] == pytest.approx(
        k_cr ** 2 * E * I / P, rel=1e-8)


def test_a_second_order_trace_read_between_its_ends_is_the_answer_at_that_load():
    """Wind on a portal redistributes its columns' compression (the
    windward one unloads): the path is traced on the end's axial forces,
    and reading its point at p off that stiffness gave displacements 1e-3
    and a joint rotation 9 % off the frame's own second-order equilibrium
    at p, ok.  ``result_at(p)`` is that equilibrium: the solve at p, whose
    axial forces are its own, and whose sway lies between the two
    columns' guided-column bounds."""
    E_, A_, I_, h, b = 2.1e8, 5e-3, 2e-5, 6.0, 4.0
    fr = Frame()
    for n, x, y in (("A", 0, 0), ("B", b, 0), ("C", 0, h), ("D", b, h)):
        fr.add_node(n, x, y)
    fr.add_member("A", "C", E_, A_, I_, name="c1")
    fr.add_member("B", "D", E_, A_, I_, name="c2")
    fr.add_member("C", "D", E_, A_, 10 * I_, name="beam")
    fr.add_support("A")
    fr.add_support("B")
    P = 0.3 * np.pi ** 2 * E_ * I_ / (4 * h * h)
    fr.add_load("C", fy=-P, case="D")
    fr.add_load("D", fy=-P, case="D")
    fr.add_load("C", fx=1.0, case="W")
    ft = fr.trace(400.0, constant={"D": 1.0}, variable="W", second_order=True)
    assert ft.ok, ft.message
    assert ft.second_order["path_axial_change"] > 0.05      # the path's N move
    for p in (50.0, 200.0):
        at = ft.result_at(p)
        alone = fr.solve(combination={"D": 1.0, "W": p}, second_order=True)
        assert at.ok and at.second_order["axial_error"] <= 1e-9
        # two fixed points on the axial forces, each converged to 1e-9 from
        # its own start (the path's axial forces, the first-order answer's)
        for node in ("C", "D"):
            np.testing.assert_allclose(at.displacements[node], alone.displacements[node],
                                       rtol=1e-8, atol=1e-12)
        assert at.member_forces["c1"] == pytest.approx(alone.member_forces["c1"], rel=1e-8)


@pytest.mark.slow
def test_the_towers_second_order_trace_read_near_its_limit_is_on_its_path():
    """4e-5 below the 20-storey tower's second-order tipping load the
    deformed frame has far, unstable equilibria too: a second-order solve
    started from the first-order answer found one 35 m the other way
    (UNSTABLE, not converged).  The trace's answer at that load starts from
    its path's axial forces and is the path's own equilibrium (3.93 m),
    ok; the path's point on the end's stiffness is within 1e-4 of it."""
    from formulations.frames.mechanics.analysis_results import FrameTrace
    from formulations.frames.plane.plane_examples import tower

    fr, _ = tower()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ft = fr.trace(second_order=True)
        p = 13.26
        assert ft.ended == "stability" and ft.limit[0] > p
        at = ft.result_at(p)
        path = FrameTrace.result_at(ft, p)
    assert at.ok and at.second_order["stable"], at.message
    assert at.displacements["N20_0"][0] == pytest.approx(path.displacements["N20_0"][0],
                                                         rel=1e-4)


def test_a_slender_tie_in_tension_keeps_a_finite_stiffness():
    """A tie of small EI (a bar modelled as a member: EI = 0.021 kN·m²)
    pulled by 488 kN has t = −N L²/EI ≈ −9.5e5: the hyperbolic closed
    forms overflowed past ψ ≈ 710 (inf/inf, NaN), and the second-order
    solve was refused as "the frame at its elastic critical load (α_cr =
    1)", α_cr raising ValueError on a NaN.  Divided through by cosh ψ they
    stay finite: s → ψ − 1 + …, s c → 1 (against the closed forms in 400
    digits: 5e-16 up to t = −1e12, Engesser's too)."""
    from formulations.frames.mechanics.second_order import stability_functions

    for phi in (0.0, 1e-8):
        s, sc = stability_functions(np.array([-1e6, -1e12]), phi)
        assert np.all(np.isfinite(s)) and np.all(np.isfinite(sc))
    # Engesser's member compressed a hair past N = −G A_s (β < 0: μ² = t/β
    # → −inf) read the same overflow: refused as "the frame at its critical
    # load", not UNSTABLE past its own buckling load
    s, sc = stability_functions(12.0 / 17.5 * (1 + 1e-9), 17.5)
    assert np.isfinite(s) and np.isfinite(sc)
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, 4.0)
    fr.add_node("C", 5.0, 0.0)
    fr.add_member("A", "B", 2.1e8, 1e-2, 1e-4, name="column")
    fr.add_member("C", "B", 2.1e8, 1e-3, 1e-10, name="tie")
    fr.add_support("A")
    fr.add_support("C")
    fr.add_load("B", fx=-400.0)
    res = fr.solve(second_order=True)
    assert res.ok, res.message
    assert res.second_order["axial"]["tie"] > 480.0
    crit = fr.critical_load_factor(res)
    assert np.isfinite(crit["alpha"]) and crit["alpha"] > 10.0
