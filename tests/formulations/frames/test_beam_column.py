"""The Euler–Bernoulli beam-column in a second-order answer: member loads'
fixed-end forces and the diagrams between the ends, against references
that do not use the code under test — the closed forms of Timoshenko &
Gere (evaluated in 50-digit arithmetic, where their cancellation costs
nothing), the cantilever's solved symbolically (sympy, once: its formula is
written out below), and a member cut at its point load into two elements
whose stiffness is the stability functions' (no member load)."""

from __future__ import annotations

import math
import warnings

import mpmath as mp
import numpy as np
import pytest

from formulations.frames import Frame, SpaceFrame
from formulations.frames.mechanics import beam_column
from formulations.frames.mechanics.second_order import stability_functions

E, I, L, W = 2e8, 1e-5, 5.0, 10.0
EI = E * I
P_E = np.pi ** 2 * EI / L ** 2
mp.mp.dps = 50

# t = −N L²/EI, compression positive: across the series switch (|t| = 1),
# the strong-tension switch (t = −4), near 0, and up to the clamped pole
T_VALUES = [1e-8, -1e-8, 0.2, -0.2, 0.3, -0.3, 0.99, 1.01, -0.99, -1.01, 3.9, -3.9, 4.1, -4.1,
            10.0, -10.0, 30.0, 39.0, -100.0, -1e4, 4 * np.pi ** 2 * (1 - 1e-9)]


def _clamped_uniform_end_moment(t):
    """wL²/12 · 3(tan u − u)/(u² tan u), u = kL/2 (tanh in tension)."""
    u = mp.sqrt(abs(mp.mpf(t))) / 2
    if t > 0:
        f = 3 * (mp.tan(u) - u) / (u ** 2 * mp.tan(u))
    else:
        f = 3 * (u - mp.tanh(u)) / (u ** 2 * mp.tanh(u))
    return float(W * L ** 2 / 12 * f)


@pytest.mark.parametrize("t", T_VALUES)
def test_clamped_uniform_load_fixed_end_forces_are_the_closed_forms(t):
    N = -t * EI / L ** 2
    fe = beam_column.nodal_loads([("distributed", 0.0, L, -W, -W)], EI, N, L)
    ref = _clamped_uniform_end_moment(t)
    # the fixed-end moment grows without bound at the pole: its rounding
    # there is the 4 × 4 solve's, 1/(1 − t/4π²) times ε
    rel = 1e-13 / max(1e-9, 1 - t / (4 * np.pi ** 2)) ** 0.0 if t < 39.4 else 1e-6
    assert fe[1] == pytest.approx(-ref, rel=max(rel, 2e-14))
    assert fe[3] == pytest.approx(ref, rel=max(rel, 2e-14))
    assert fe[0] == pytest.approx(-W * L / 2, rel=1e-14)
    assert fe[2] == pytest.approx(-W * L / 2, rel=1e-14)


def _two_elements(t, a, P):
    """The clamped member's end forces under a force P at a: cut there
    into two elements with the stability functions' stiffness (the
    middle node free, its v and θ solved), the reactions at the ends."""
    N = -t * EI / L ** 2
    K = np.zeros((6, 6))
    for n, (x0, x1) in enumerate(((0.0, a), (a, L))):
        h = x1 - x0
        s, sc = (float(v[0]) for v in stability_functions(np.array([-N * h ** 2 / EI])))
        f = EI / h
        k = np.array([[(2 * (s + sc) + N * h ** 2 / EI) * f / h ** 2, (s + sc) * f / h,
                       -(2 * (s + sc) + N * h ** 2 / EI) * f / h ** 2, (s + sc) * f / h],
                      [(s + sc) * f / h, s * f, -(s + sc) * f / h, sc * f],
                      [-(2 * (s + sc) + N * h ** 2 / EI) * f / h ** 2, -(s + sc) * f / h,
                       (2 * (s + sc) + N * h ** 2 / EI) * f / h ** 2, -(s + sc) * f / h],
                      [(s + sc) * f / h, sc * f, -(s + sc) * f / h, s * f]])
        K[2 * n:2 * n + 4, 2 * n:2 * n + 4] += k
    u = np.zeros(6)
    u[2:4] = np.linalg.solve(K[2:4, 2:4], [P, 0.0])
    return K @ u          # the ends' reactions: minus the consistent loads


@pytest.mark.parametrize("t", [1e-8, -0.3, 0.3, 5.0, -5.0, 25.0, -400.0])
@pytest.mark.parametrize("a", [0.3, 1.7, 2.5, 4.1])
def test_point_force_fixed_end_forces_are_the_cut_members_reactions(t, a):
    fe = beam_column.nodal_loads([("point", a, -3.0, 0.0)], EI, -t * EI / L ** 2, L)
    ends = _two_elements(t, a, -3.0)[[0, 1, 4, 5]]
    assert fe == pytest.approx(-ends, rel=1e-11, abs=1e-13 * 3.0 * L)


def _solve(fr):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fr.solve(combination={"D": 1.0}, second_order=True, raise_on_failure=False,
                        accuracy="high")


def _strut(share, *, w=0.0, point=0.0, moments=0.0, hinged=False, offset=0.0):
    """A strut of flexible length L on pins (or on fixed nodes, hinged at
    the faces of rigid end zones ``offset`` long) under an axial force
    share × P_E (compression positive) and span loads."""
    fr = Frame()
    fr.add_node("A", -offset, 0.0)
    fr.add_node("B", L + offset, 0.0)
    fr.add_member("A", "B", E, 0.01, I, name="S", hinge_i=hinged, hinge_j=hinged,
                  offset_i=offset, offset_j=offset)
    if hinged:
        fr.add_support("A", fix=("ux", "uy", "rz"))
        fr.add_support("B", fix=("uy", "rz"))
    else:
        fr.add_support("A", fix=("ux", "uy"))
        fr.add_support("B", fix=("uy",))
    fr.add_load("B", fx=-share * P_E, case="D")
    if w:
        fr.add_distributed_load("S", wy=-w, case="D")
    if point:
        fr.add_point_load("S", offset + L / 2, fy=-point, case="D")
    if moments:
        fr.add_load("A", mz=moments, case="D")
        fr.add_load("B", mz=-moments, case="D")
    return fr


def _k(share):
    return math.sqrt(abs(share) * P_E / EI)


SHARES = [1e-8, -1e-8, 0.03, -0.03, 0.1, 0.5, 0.9, -0.5, -3.0, -50.0]


@pytest.mark.parametrize("share", SHARES)
def test_pinned_uniform_load_midspan_moment_and_deflection(share):
    fr = _strut(share, w=W)
    res = _solve(fr)
    assert res.ok, res.message
    k = mp.sqrt(mp.mpf(abs(share)) * P_E / EI)
    c = 1 / mp.cos(k * L / 2) if share > 0 else 1 / mp.cosh(k * L / 2)
    sign = 1 if share > 0 else -1
    m_mid = float(sign * W / k ** 2 * (c - 1))
    # k² → −k² in tension: its terms' signs as k⁴'s and k²'s
    v_mid = float(W / (EI * k ** 4) * (c - 1) - sign * W * L ** 2 / (8 * EI * k ** 2))
    ext = res.extremes("S")
    assert ext["M"]["max"][0] == pytest.approx(m_mid, rel=1e-10)
    assert ext["M"]["max"][1] == pytest.approx(L / 2, abs=1e-6)
    assert ext["v"]["min"][0] == pytest.approx(-v_mid, rel=1e-10)
    if share == 0.5:
        assert m_mid == pytest.approx(63.435770, abs=1e-6)      # the docs' figure


@pytest.mark.parametrize("share", SHARES)
def test_pinned_midspan_point_force(share):
    P = 7.0
    res = _solve(_strut(share, point=P))
    assert res.ok, res.message
    k = mp.sqrt(mp.mpf(abs(share)) * P_E / EI)
    ref = float(P / (2 * k) * (mp.tan(k * L / 2) if share > 0 else mp.tanh(k * L / 2)))
    assert res.extremes("S")["M"]["max"][0] == pytest.approx(ref, rel=1e-10)


@pytest.mark.parametrize("share", [0.1, 0.5, 0.9, -0.5, -20.0])
def test_equal_end_moments_in_single_curvature(share):
    m = 10.0
    res = _solve(_strut(share, moments=m))
    assert res.ok, res.message
    k = mp.sqrt(mp.mpf(abs(share)) * P_E / EI)
    ref = float(m / (mp.cos(k * L / 2) if share > 0 else mp.cosh(k * L / 2)))
    # the ends' moment is m, midspan's m sec(kL/2): 2.25 m at half P_E
    x, _, _, M = res.diagram("S", 41)
    assert abs(M[20]) == pytest.approx(ref, rel=1e-10)
    assert abs(M[0]) == pytest.approx(m, rel=1e-12)
    ext = res.extremes("S")["M"]
    assert max(abs(ext["max"][0]), abs(ext["min"][0])) == pytest.approx(max(ref, m), rel=1e-10)


@pytest.mark.parametrize("share", [0.05, 0.2, 0.24, -0.5])
def test_cantilever_with_a_tip_force_and_a_uniform_load(share):
    """Base moment of a cantilever under compression P = k²EI, a uniform
    load w and a tip force H across it (sympy's solution of EI v'''' +
    P v'' = w, clamped at the base, free at the tip):
    w (kL tan kL + 1 − sec kL)/k² + H tan(kL)/k (tension: tanh, and
    w (1 + sech kL − kL tanh kL)/k² … sign-flipped k², here by mpmath)."""
    H, w = 3.0, 2.0
    P = share * P_E
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    fr.add_member("A", "B", E, 0.01, I, name="C")
    fr.add_support("A", fix=("ux", "uy", "rz"))
    fr.add_load("B", fy=-P, fx=H, case="D")
    fr.add_distributed_load("C", wx=w, case="D")
    res = _solve(fr)
    assert res.ok, res.message
    k = mp.sqrt(mp.mpf(abs(share)) * P_E / EI)
    kL = k * L
    if share > 0:
        ref = w * (kL * mp.tan(kL) + 1 - 1 / mp.cos(kL)) / k ** 2 + H * mp.tan(kL) / k
    else:   # k → i k: tan → i tanh, cos → cosh
        ref = w * (-kL * mp.tanh(kL) + 1 - 1 / mp.cosh(kL)) / -k ** 2 + H * mp.tanh(kL) / k
    assert abs(res.end_forces("C")["i"]["M"]) == pytest.approx(float(ref), rel=1e-10)


@pytest.mark.parametrize("share", [0.3, 0.8, -2.0])
def test_hinges_at_the_faces_of_rigid_end_zones(share):
    # fixed nodes, rigid zones 0.4 long, the member hinged at their faces:
    # its flexible length L is a pinned strut under the uniform load
    res = _solve(_strut(share, w=W, hinged=True, offset=0.4))
    assert res.ok, res.message
    k = mp.sqrt(mp.mpf(abs(share)) * P_E / EI)
    c = 1 / mp.cos(k * L / 2) if share > 0 else 1 / mp.cosh(k * L / 2)
    ref = float((1 if share > 0 else -1) * W / k ** 2 * (c - 1))
    ext = res.extremes("S")["M"]["max"]
    assert ext[0] == pytest.approx(ref, rel=1e-10)
    assert ext[1] == pytest.approx(0.4 + L / 2, abs=1e-6)


def test_extremes_match_dense_sampling_of_an_unsymmetric_member():
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 4.0, 3.0)
    fr.add_member("A", "B", E, 0.01, I, name="S", spring_j=2e3)
    fr.add_support("A", fix=("ux", "uy", "rz"))
    fr.add_support("B", fix=("uy",))
    fr.add_load("B", fx=-0.3 * P_E * 0.8, fy=-0.3 * P_E * 0.6, case="D")
    fr.add_distributed_load("S", wy=-8.0, wy2=3.0, start=0.5, end=3.9, axes="member", case="D")
    fr.add_point_load("S", 1.2, fy=-5.0, mz=2.0, axes="member", case="D")
    res = _solve(fr)
    assert res.ok, res.message
    x, N, V, M = res.diagram("S", 20001)
    ext = res.extremes("S")
    for key, arr in (("M", M), ("V", V)):
        assert ext[key]["max"][0] >= arr.max() - 1e-12 * np.abs(arr).max()
        assert ext[key]["max"][0] == pytest.approx(arr.max(), rel=1e-7)
        assert ext[key]["min"][0] == pytest.approx(arr.min(), rel=1e-7)
    # V = dM/dx: the moment's slope by central differences
    mid = (x[2:] - x[:-2]) > 0
    slope = (M[2:] - M[:-2])[mid] / (x[2:] - x[:-2])[mid]
    assert np.median(np.abs(slope - V[1:-1][mid])) < 1e-6 * np.abs(V).max()


def test_no_axial_force_leaves_the_first_order_answer_bit_for_bit():
    fr = _strut(0.0, w=W, point=3.0)
    second, first = _solve(fr), fr.solve(combination={"D": 1.0}, accuracy="high")
    assert second.member_forces["S"].tolist() == first.member_forces["S"].tolist()
    assert [a.tolist() for a in second.diagram("S", 21)] == \
        [a.tolist() for a in first.diagram("S", 21)]


def _plane_and_space(share, I_, loads, space_loads, spring=None, offset=0.0):
    """The same strut (a rigid zone at each end, a semi-rigid joint at
    j) as a plane frame (I_, ``loads`` across y) and as a space frame
    along X whose two bending planes carry ``space_loads``."""
    plane, space = Frame(), SpaceFrame()
    for fr, extra in ((plane, []), (space, [0.0])):
        fr.add_node("A", 0.0, 0.0, *extra)
        fr.add_node("B", L + 2 * offset, 0.0, *extra)
    plane.add_member("A", "B", E, 0.01, I_, name="S", spring_j=spring, offset_i=offset,
                     offset_j=offset)
    space.add_member("A", "B", E, 0.01, I, 2 * I, G=8e7, J=1e-5, name="S", spring_j=spring,
                     offset_i=offset, offset_j=offset)
    plane.add_support("A", fix=("ux", "uy"))
    plane.add_support("B", fix=("uy",))
    space.add_support("A", fix=("ux", "uy", "uz", "rx"))
    space.add_support("B", fix=("uy", "uz"))
    for fr in (plane, space):
        fr.add_load("B", fx=-share * P_E, case="D")
    for w, (a, p) in loads:
        plane.add_distributed_load("S", wy=w, case="D")
        plane.add_point_load("S", a, fy=p, case="D")
    for kwargs, point in space_loads:
        space.add_distributed_load("S", case="D", **kwargs)
        space.add_point_load("S", point[0], case="D", **point[1])
    return plane, space


@pytest.mark.parametrize("share", [0.4, -3.0])
@pytest.mark.parametrize("spring, offset", [(None, 0.0), (2e3, 0.3)])
def test_a_plane_strut_built_in_space_gives_the_plane_answers(share, spring, offset):
    # bending about y (Iy = I) under wz and fz; about z (Iz = 2I) under
    # wy and fy: each plane is the plane frame's with its own I
    space_loads = [({"wz": -10.0, "wy": -3.0}, (1.3, {"fz": -4.0, "fy": 2.0}))]
    res = {}
    for key, I_, loads in (("My", I, [(-10.0, (1.3, -4.0))]), ("Mz", 2 * I, [(-3.0, (1.3, 2.0))])):
        plane, space = _plane_and_space(share, I_, loads, space_loads, spring, offset)
        p, s = _solve(plane), _solve(space)
        assert p.ok and s.ok, (p.message, s.message)
        res[key] = (p, s)
        pe, se = p.extremes("S"), s.extremes("S")
        for side in ("max", "min"):
            assert se[key][side][0] == pytest.approx(pe["M"][side][0], rel=1e-10, abs=1e-10)
        x, _, _, M = p.diagram("S", 31)
        xs, *q = s.diagram("S", 31)
        assert q[4 if key == "My" else 5] == pytest.approx(M, rel=1e-10, abs=1e-9)
        xp, _, v = p.deflection("S", 31)
        xd, d = s.deflection("S", 31)
        _, ip, isp = np.intersect1d(xp, xd, return_indices=True)
        assert ip.size >= 31
        assert d[isp, 2 if key == "My" else 1] == pytest.approx(v[ip], rel=1e-10, abs=1e-13)


@pytest.mark.parametrize("space", [False, True])
def test_end_forces_are_the_diagrams_ends(space):
    # V = dM/dx at the ends too: the end action across the undeformed axis
    # plus N times the axis' slope there
    plane, sp = _plane_and_space(0.4, 2 * I, [(-3.0, (1.3, 2.0))],
                                 [({"wy": -3.0}, (1.3, {"fy": 2.0}))], 2e3, 0.3)
    res = _solve(sp if space else plane)
    assert res.ok, res.message
    x, *q = res.diagram("S", 11)
    names = ("N", "Vy", "Vz", "T", "My", "Mz") if space else ("N", "V", "M")
    ends = res.end_forces("S")
    scale = max(np.abs(v).max() for v in q)
    for k, name in enumerate(names):
        assert ends["i"][name] == pytest.approx(q[k][0], abs=1e-12 * scale)
        assert ends["j"][name] == pytest.approx(q[k][-1], abs=1e-12 * scale)
    v_end = res.member_forces["S"][1]
    assert abs(ends["i"]["Vy" if space else "V"] - v_end) > 1e-3     # N θ_i


@pytest.mark.parametrize("share", [0.3, 0.8, -2.0])
@pytest.mark.parametrize("spring", [0.5, 5.0])
def test_semi_rigid_ends_under_a_uniform_load(share, spring):
    """Fixed nodes, the member joined to them by rotational springs
    k_s = spring EI/L: the end moment M from compatibility with the pinned
    beam-column's end rotations, w (tan u − u)/(EI k³) under the load and
    M tan u/(EI k) under equal end moments M, so
    M = w (tan u − u)/(EI k³) / (1/k_s + tan u/(EI k)), and midspan
    (w/k²)(sec u − 1) − M sec u (tension: tanh, sech, k² → −k²)."""
    k_s = spring * EI / L
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, 0.01, I, name="S", spring_i=k_s, spring_j=k_s)
    fr.add_support("A", fix=("ux", "uy", "rz"))
    fr.add_support("B", fix=("uy", "rz"))
    fr.add_load("B", fx=-share * P_E, case="D")
    fr.add_distributed_load("S", wy=-W, case="D")
    res = _solve(fr)
    assert res.ok, res.message
    k = mp.sqrt(mp.mpf(abs(share)) * P_E / EI)
    u = k * L / 2
    if share > 0:
        rot_w, rot_m, sec = W * (mp.tan(u) - u) / (EI * k ** 3), mp.tan(u) / (EI * k), 1 / mp.cos(u)
        mid_w = W / k ** 2 * (sec - 1)
    else:
        rot_w, rot_m, sec = W * (u - mp.tanh(u)) / (EI * k ** 3), mp.tanh(u) / (EI * k), 1 / mp.cosh(u)
        mid_w = W / k ** 2 * (1 - sec)
    M = rot_w / (1 / k_s + rot_m)
    ends = res.end_forces("S")
    assert ends["i"]["M"] == pytest.approx(-float(M), rel=1e-10)
    assert ends["j"]["M"] == pytest.approx(-float(M), rel=1e-10)
    assert res.extremes("S")["M"]["max"][0] == pytest.approx(float(mid_w - M * sec), rel=1e-10)


def test_a_shear_that_turns_inside_the_span_has_its_extreme_found():
    # a load from −8 to +8 kN/m under 0.7 P_e: V = V₁ + N v' turns in the
    # span, where no sample need lie; dense sampling approaches it from
    # inside (h = 2.5e-5: its error ~ V'' h²/8)
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, 0.01, I, name="S")
    fr.add_support("A", fix=("ux", "uy", "rz"))
    fr.add_support("B", fix=("uy",))
    fr.add_load("B", fx=-0.7 * P_E, case="D")
    fr.add_distributed_load("S", wy=-8.0, wy2=8.0, case="D")
    res = _solve(fr)
    assert res.ok, res.message
    x, _, V, _ = res.diagram("S", 200001)
    low, at = res.extremes("S")["V"]["min"]
    assert 0.1 * L < at < 0.9 * L
    assert low <= V.min()
    assert low == pytest.approx(V.min(), rel=1e-9)
