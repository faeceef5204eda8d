"""Second-order answers with P-δ along members against references that do
not come from qpcontact: the beam-column equation's closed forms
(Timoshenko & Gere, *Theory of Elastic Stability*, ch. 1) evaluated here in
mpmath at 50 digits, and (slow, where openseespy is installed) OpenSees
with every member cut into 64 elasticBeamColumn pieces under its PDelta
transformation.  The fast subset of benchmarks/frame_pdelta_census.py.

k = √(|N|/EI), u = kL/2; a 5 m member, EI = 2000 kN·m², P_e = π²EI/L².

Members with shear deformation are Engesser's beam-column.  These were
written before the beam-column element's member loads and diagrams landed
(the diagrams between a member's ends were the statics of its end forces on
the undeformed axis, without N·v(x), and span loads kept first-order
fixed-end forces), as ``xfail(strict=True)`` where the answer was wrong:
each now passes.
"""

from __future__ import annotations

import warnings

import mpmath as mp
import numpy as np
import pytest

from formulations.frames import Frame, SpaceFrame
from tests.helpers.opensees_chains import plane_chain, static_analysis

mp.mp.dps = 50
E, A, I, L = 2e8, 1e-2, 1e-5, 5.0
EI = E * I
P_E = float(mp.pi ** 2 * EI / L ** 2)
REL = 1e-8             # the closed forms are exact; the element should be too


def _k(N, EI_=EI):
    return mp.sqrt(abs(mp.mpf(N)) / EI_)


def _solve(fr):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")        # the large-displacement warning near P_cr
        return fr.solve(second_order=True, accuracy="high", raise_on_failure=False)


def _span(N, *, clamped=False, w=0.0, Q=0.0, Ma=0.0, Mb=0.0):
    """A span A→B along x, pinned (A: ux, uy; B: uy) or clamped (rz held at
    both), axial force N (tension positive) applied at B, uniform w and a
    midspan force Q along local y, sagging end moments Ma, Mb as nodal
    couples (−Ma at A, +Mb at B)."""
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, A, I, name="S")
    rz = ("rz",) if clamped else ()
    fr.add_support("A", fix=("ux", "uy") + rz)
    fr.add_support("B", fix=("uy",) + rz)
    fr.add_load("A", mz=-Ma)
    fr.add_load("B", fx=N, mz=Mb)
    if w:
        fr.add_distributed_load("S", wy=w, axes="member")
    if Q:
        fr.add_point_load("S", L / 2, fy=Q, axes="member")
    return fr


def _cantilever(N, H, w=0.0):
    """A column A (clamped) → B (up), tip force H along +x and N, uniform w
    along +x (local wy = −w: a member up +y has local y along −x)."""
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    fr.add_member("A", "B", E, A, I, name="C")
    fr.add_support("A")
    fr.add_load("B", fx=H, fy=N)
    if w:
        fr.add_distributed_load("C", wy=-w, axes="member")
    return fr


def _cantilever_closed(H, w, N):
    """Tip sway δ, tip slope v'(L) and base moment of the deformed cantilever:
    EI v'' = H(L − x) + P(δ − v) + w(L − x)²/2, v(0) = v'(0) = 0 (P = −N)."""
    k, P, Lm = _k(N), -mp.mpf(N), mp.mpf(L)
    c, b = w / (2 * P), H / P
    C2 = (b + 2 * c * Lm) / k
    if N < 0:
        C1 = (w / (P * k ** 2) - C2 * mp.sin(k * Lm)) / mp.cos(k * Lm)
        delta = -C1 - b * Lm - c * Lm ** 2 + w / (P * k ** 2)
        slope = -C1 * k * mp.sin(k * Lm) + C2 * k * mp.cos(k * Lm) - b
    else:
        C1 = (-w / (P * k ** 2) - C2 * mp.sinh(k * Lm)) / mp.cosh(k * Lm)
        delta = -C1 - b * Lm - c * Lm ** 2 - w / (P * k ** 2)
        slope = C1 * k * mp.sinh(k * Lm) + C2 * k * mp.cosh(k * Lm) - b
    return float(delta), float(slope), float(H * Lm + P * delta + w * Lm ** 2 / 2)


def _end_moments_closed(Ma, Mb, N):
    """Pinned span, sagging end moments: (M(x) as a function, θ_A, θ_B) from
    EI v'' = M, M = M_lin − P v (compression), v(0) = v(L) = 0."""
    k, P, Lm = _k(N), mp.mpf(-N), mp.mpf(L)
    Aa = -Ma / P
    B = (-Mb / P - Aa * mp.cos(k * Lm)) / mp.sin(k * Lm)

    def M(x):
        return float(-P * (Aa * mp.cos(k * x) + B * mp.sin(k * x)))
    slope = (Mb - Ma) / (Lm * P)
    return (M, float(B * k + slope),
            float(-Aa * k * mp.sin(k * Lm) + B * k * mp.cos(k * Lm) + slope))


def _largest_M(res, member):
    e = res.extremes(member)["M"]
    return e["max"][0], e["min"][0]


# -- where main is right today: nodes and end actions of members without span loads ----

@pytest.mark.parametrize("share", [0.1, 0.5, 0.95, -0.5])
def test_cantilever_tip_force_nodes_and_base_moment(share):
    N = -share * P_E / 4                       # share of π²EI/(4L²); −0.5: tension
    res = _solve(_cantilever(N, 5.0))
    assert res.ok, res.message
    delta, slope, base = _cantilever_closed(5.0, 0.0, N)
    ux, _, rz = res.displacements["B"]
    assert ux == pytest.approx(delta, rel=REL)
    assert rz == pytest.approx(-slope, rel=REL)        # leaning toward +x turns it clockwise
    assert res.member_forces["C"][2] == pytest.approx(base, rel=REL)   # the clamp's moment


@pytest.mark.parametrize("Mb", [10.0, 5.0, -5.0])
def test_end_moments_end_rotations_and_end_actions(Mb):
    N = -0.5 * P_E
    res = _solve(_span(N, Ma=10.0, Mb=Mb))
    assert res.ok, res.message
    _, th_a, th_b = _end_moments_closed(10.0, Mb, N)
    assert res.displacements["A"][2] == pytest.approx(th_a, rel=REL)
    assert res.displacements["B"][2] == pytest.approx(th_b, rel=REL)
    f = res.member_forces["S"]
    assert (f[2], f[5]) == pytest.approx((-10.0, Mb), rel=REL)


def test_a_plane_frame_built_in_3d_gives_the_plane_answer():
    """The cantilever in the x-y plane of a space frame (out-of-plane dofs
    held): the same status, node displacements and end actions to 1e-10."""
    N = -0.5 * P_E / 4
    plane = _solve(_cantilever(N, 5.0))
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 0.0, L, 0.0)
    fr.add_member("A", "B", E, A, I, I, G=8e7, J=2 * I, name="C", ref=(0.0, 0.0, 1.0))
    fr.add_support("A")
    fr.add_support("B", fix=("uz", "rx", "ry"))
    fr.add_load("B", fx=5.0, fy=N)
    space = _solve(fr)
    assert space.ok == plane.ok
    assert np.array(space.displacements["B"])[[0, 1, 5]] == pytest.approx(
        np.array(plane.displacements["B"]), rel=1e-10)
    assert np.array(space.member_forces["C"])[[0, 1, 5, 6, 7, 11]] == pytest.approx(
        np.array(plane.member_forces["C"]), rel=1e-10, abs=1e-10 * abs(N))


# -- where main is wrong today: the diagrams between the ends --------------------------

@pytest.mark.parametrize("share", [0.1, 0.5, 0.95])
def test_equal_end_moments_peak_at_midspan_as_M_sec_u(share):
    # single curvature, no span load: main answers ok with M (the end moment) as the largest
    N = -share * P_E
    res = _solve(_span(N, Ma=10.0, Mb=10.0))
    assert res.ok, res.message
    u = _k(N) * L / 2
    M_max, x = res.extremes("S")["M"]["max"]
    assert M_max == pytest.approx(float(10 * mp.sec(u)), rel=REL)
    assert x == pytest.approx(L / 2, rel=1e-6)
    v = res.extremes("S")["v"]["min"][0]          # sagging: down, (M/P)(sec u − 1)
    assert v == pytest.approx(float(-10 / (share * P_E) * (mp.sec(u) - 1)), rel=REL)


@pytest.mark.parametrize("Mb", [5.0, -5.0])
def test_unequal_end_moments_diagram(Mb):
    N = -0.5 * P_E
    res = _solve(_span(N, Ma=10.0, Mb=Mb))
    assert res.ok, res.message
    M, _, _ = _end_moments_closed(10.0, Mb, N)
    x, _, _, got = res.diagram("S", 9)
    assert got == pytest.approx([M(xx) for xx in x], rel=REL, abs=REL * 10)


@pytest.mark.parametrize("share", [0.5, -0.5])
def test_a_swaying_cantilevers_diagram_closes_at_its_free_tip(share):
    # main: end_forces (and the members table) give the tip N·δ instead of 0
    N = -share * P_E / 4
    res = _solve(_cantilever(N, 5.0))
    assert res.ok, res.message
    _, _, base = _cantilever_closed(5.0, 0.0, N)
    ends = res.end_forces("C")
    assert ends["i"]["M"] == pytest.approx(-base, rel=REL)
    assert ends["j"]["M"] == pytest.approx(0.0, abs=REL * base)


def test_a_swaying_space_cantilevers_diagrams():
    """A vertical cantilever pushed along x and y under 0.5 of its weaker
    buckling load: in each bending plane (its own EI) the moment is
    H sin k(L − x)/(k cos kL) — H tan(kL)/k at the clamp, 0 at the tip."""
    Iy, Iz, Hx, Hy = 3e-5, 1e-5, 3.0, 2.0
    P = 0.5 * float(mp.pi ** 2) * E * Iz / (4 * L ** 2)
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 0.0, 0.0, L)
    fr.add_member("A", "B", E, A, Iy, Iz, G=8e7, J=Iy + Iz, name="C", ref=(1.0, 0.0, 0.0))
    fr.add_support("A")
    fr.add_load("B", fx=Hx, fy=Hy, fz=-P)
    res = _solve(fr)
    assert res.ok, res.message
    x, *_, My, Mz = res.diagram("C", 3)
    # local z along global x (ref), y = z × x along −y: Hx bends about local y (Iy), Hy about z
    for got, H, I_ in ((My, Hx, Iy), (Mz, Hy, Iz)):
        k = _k(-P, E * I_)
        closed = [float(H * mp.sin(k * (L - xx)) / (k * mp.cos(k * L))) for xx in x]
        assert abs(got) == pytest.approx(closed, rel=REL, abs=REL * closed[0])


# -- where main refuses today: span loads on members under N ---------------------------

@pytest.mark.parametrize("share", [0.1, 0.5, 0.95, -0.5])
def test_pinned_span_under_uniform_load(share):
    N, w = -share * P_E, -10.0
    res = _solve(_span(N, w=w))
    assert res.ok, res.message
    k = _k(N)
    u = k * L / 2
    if N < 0:       # 5 m at 0.5 P_e under 10 kN/m: 63.435770 kN·m
        m, th = (mp.sec(u) - 1) / k ** 2, (mp.tan(u) - u) / (EI * k ** 3)
    else:
        m, th = (1 - mp.sech(u)) / k ** 2, (u - mp.tanh(u)) / (EI * k ** 3)
    assert _largest_M(res, "S")[0] == pytest.approx(float(-w * m), rel=REL)
    assert res.displacements["A"][2] == pytest.approx(float(w * th), rel=REL)


def test_the_pinned_spans_reference_is_the_documented_figure():
    # the closed form above at 0.5 P_e, 10 kN/m (docs/frames.md): 63.435770
    k = _k(-0.5 * P_E)
    assert float(10 / k ** 2 * (mp.sec(k * L / 2) - 1)) == pytest.approx(63.435770, abs=5e-7)


@pytest.mark.parametrize("share", [0.1, 0.5, 0.95, -0.5])
def test_clamped_span_under_uniform_load(share):
    # share of its own buckling load 4 P_e; end moment (wL²/12)·3(tan u − u)/(u² tan u)
    N, w = -share * 4 * P_E, -10.0
    res = _solve(_span(N, clamped=True, w=w))
    assert res.ok, res.message
    k = _k(N)
    u = k * L / 2
    if N < 0:
        end = w * L ** 2 / 12 * 3 * (mp.tan(u) - u) / (u ** 2 * mp.tan(u))
        mid = (u / mp.sin(u) - 1) / k ** 2
    else:
        end = w * (u / mp.tanh(u) - 1) / k ** 2
        mid = (1 - u / mp.sinh(u)) / k ** 2
    f = res.member_forces["S"]
    assert (f[2], f[5]) == pytest.approx((-float(end), float(end)), rel=REL)
    assert _largest_M(res, "S")[0] == pytest.approx(float(-w * mid), rel=REL)


@pytest.mark.parametrize("share", [0.5, -0.5])
def test_pinned_span_under_a_midspan_force(share):
    N, Q = -share * P_E, -20.0
    res = _solve(_span(N, Q=Q))
    assert res.ok, res.message
    k = _k(N)
    u = k * L / 2
    m = mp.tan(u) / (2 * k) if N < 0 else mp.tanh(u) / (2 * k)
    assert _largest_M(res, "S")[0] == pytest.approx(float(-Q * m), rel=REL)


@pytest.mark.parametrize("share", [0.5, -0.5])
def test_cantilever_with_a_tip_force_and_a_uniform_load(share):
    N = -share * P_E / 4
    res = _solve(_cantilever(N, 5.0, w=2.0))
    assert res.ok, res.message
    delta, _, base = _cantilever_closed(5.0, 2.0, N)
    assert res.displacements["B"][0] == pytest.approx(delta, rel=REL)
    assert res.member_forces["C"][2] == pytest.approx(base, rel=REL)


def test_space_strut_loaded_about_both_axes():
    """A pinned strut along x, Iy = 2 Iz, uniform wy and wz, N = 0.3 of its
    weaker Euler load: each bending plane is its own pinned beam-column."""
    Iy, Iz, wy, wz = 2e-5, 1e-5, -6.0, -9.0
    N = -0.3 * float(mp.pi ** 2) * E * Iz / L ** 2
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", L, 0.0, 0.0)
    fr.add_member("A", "B", E, A, Iy, Iz, G=8e7, J=Iy + Iz, name="S")
    fr.add_support("A", fix=("ux", "uy", "uz", "rx"))
    fr.add_support("B", fix=("uy", "uz"))
    fr.add_load("B", fx=N)
    fr.add_distributed_load("S", wy=wy, wz=wz, axes="member")
    res = _solve(fr)
    assert res.ok, res.message
    e = res.extremes("S")
    for key, w, I_ in (("Mz", wy, Iz), ("My", wz, Iy)):
        k = _k(N, E * I_)
        closed = float(abs(w) / k ** 2 * (mp.sec(k * L / 2) - 1))
        got = max(abs(e[key]["max"][0]), abs(e[key]["min"][0]))
        assert got == pytest.approx(closed, rel=REL)


@pytest.mark.parametrize("share", [0.5, 0.9, -0.5])
def test_shear_flexible_cantilever_as_engesser(share):
    """A cantilever with GA_s = 4000 kN (P_e/GA_s ≈ 0.05 for its own
    buckling), tip force 5 kN, N a share of Engesser's buckling load
    P_c/(1 + P_c/GA_s), P_c = π²EI/(4L²) (−0.5: tension of 0.5 P_c).
    Engesser (shear driven by V = dM/dx): M'' + k²M = 0, k² = P/(EI μ),
    μ = 1 − P/GA_s; the clamp holds the bending slope only, so
    M'(0) = −H/μ and the clamp's moment is H tan(kL)/(μk); δ = (M(0) − HL)/P."""
    GAs = 8e7 * 5e-5
    Pc = float(mp.pi ** 2) * EI / (4 * L ** 2)
    N = -share * Pc / (1 + Pc / GAs) if share > 0 else -share * Pc
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    fr.add_member("A", "B", E, A, I, name="C", G=8e7, shear_area=5e-5)
    fr.add_support("A")
    fr.add_load("B", fx=5.0, fy=N)
    res = _solve(fr)
    assert res.ok, res.message
    mu = 1 + mp.mpf(N) / GAs
    k = mp.sqrt(abs(mp.mpf(N)) / (EI * mu))
    base = 5 * (mp.tan(k * L) if N < 0 else mp.tanh(k * L)) / (mu * k)
    assert res.member_forces["C"][2] == pytest.approx(float(base), rel=REL)
    assert res.displacements["B"][0] == pytest.approx(float((base - 5 * L) / -N), rel=REL)
    if N < 0:
        alpha = fr.critical_load_factor(res)["alpha"]
        assert alpha == pytest.approx(1 / share, rel=REL)


def test_shear_flexible_span_under_equal_end_moments_peaks_as_M_sec_u():
    """Engesser: M'' + k²M = 0, k² = P/(EI μ), μ = 1 − P/GA_s, so two equal
    end moments peak at M sec(kL/2) at midspan (ok today, shown as M)."""
    GAs = 8e7 * 5e-5
    N = -0.5 * P_E / (1 + P_E / GAs)
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, A, I, name="S", G=8e7, shear_area=5e-5)
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_support("B", fix=("uy",))
    fr.add_load("A", mz=-10.0)
    fr.add_load("B", fx=N, mz=10.0)
    res = _solve(fr)
    assert res.ok, res.message
    k = mp.sqrt(-mp.mpf(N) / (EI * (1 + mp.mpf(N) / GAs)))
    assert res.extremes("S")["M"]["max"][0] == pytest.approx(float(10 * mp.sec(k * L / 2)),
                                                            rel=REL)


# -- against OpenSees (slow; skipped without openseespy) -------------------------------

def _portal_opensees(sub, P, H):
    """The pinned-base portal of ``_portal`` in OpenSees, each member cut into
    ``sub`` elasticBeamColumn pieces (PDelta): top displacements, the right
    column's end moment at its top (global), and M at its pieces' nodes."""
    ops = pytest.importorskip("openseespy.opensees")
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    pts = {1: (0.0, 0.0), 2: (0.0, 4.0), 3: (6.0, 4.0), 4: (6.0, 0.0)}
    for t, xy in pts.items():
        ops.node(t, *xy)
    ops.fix(1, 1, 1, 0)
    ops.fix(4, 1, 1, 0)
    ops.geomTransf("PDelta", 1)
    nxt, ele, chains = 5, 1, {}
    for name, a, b, Iz in (("C1", 1, 2, 4e-5), ("C2", 4, 3, 4e-5), ("B", 2, 3, 2e-4)):
        chains[name], nxt, ele = plane_chain(ops, a, b, pts[a], pts[b], sub, nxt, ele, 1e-2, E,
                                             Iz)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, H, -P, 0.0)
    ops.load(3, 0.0, -P, 0.0)
    assert static_analysis(ops, 1e-12, steps=10)
    forces = [ops.eleResponse(e, "localForce") for e in chains["C2"]]
    M = np.r_[[-f[2] for f in forces], forces[-1][5]]      # sagging positive along D→C
    return np.array(ops.nodeDisp(2) + ops.nodeDisp(3)), M


def _portal(P, H):
    fr = Frame()
    for n, xy in (("A", (0.0, 0.0)), ("B", (0.0, 4.0)), ("C", (6.0, 4.0)), ("D", (6.0, 0.0))):
        fr.add_node(n, *xy)
    fr.add_member("A", "B", E, 1e-2, 4e-5, name="C1")
    fr.add_member("D", "C", E, 1e-2, 4e-5, name="C2")
    fr.add_member("B", "C", E, 1e-2, 2e-4, name="B")
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_support("D", fix=("ux", "uy"))
    fr.add_load("B", fx=H, fy=-P)
    fr.add_load("C", fy=-P)
    return fr


@pytest.mark.slow
def test_pinned_portal_nodes_against_opensees():
    # no span loads, columns at about half their sway buckling load: main is right
    ours = _solve(_portal(600.0, 10.0))
    assert ours.ok, ours.message
    u64, _ = _portal_opensees(64, 600.0, 10.0)
    u32, _ = _portal_opensees(32, 600.0, 10.0)
    got = np.r_[ours.displacements["B"], ours.displacements["C"]]
    cut_error = abs(u64 - u32).max()
    assert abs(got - u64).max() <= max(cut_error, 1e-9 * abs(u64).max())


@pytest.mark.slow
def test_pinned_portal_column_diagram_against_opensees():
    ours = _solve(_portal(600.0, 10.0))
    assert ours.ok, ours.message
    _, M64 = _portal_opensees(64, 600.0, 10.0)
    _, M32 = _portal_opensees(32, 600.0, 10.0)
    x, _, _, M = ours.diagram("C2", 9)
    ref = M64[::8]                                 # x = kL/8, the diagram's nine sections
    cut_error = abs(M64[::2] - M32).max()          # ≈ 3× the 64 cuts' own error
    assert abs(M - ref).max() <= max(cut_error, 1e-6 * abs(ref).max())
