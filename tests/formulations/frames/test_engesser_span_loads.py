"""Span loads on shear-flexible members under a constant axial force:
Engesser's beam-column in closed form (mechanics/beam_column.py with
c = 1/(G A_s)), as an Euler–Bernoulli member's are Livesley's.  The
references are not the code under test: the clamped member's fixed-end
moment under a uniform load by hand (M'' − μ M = −q/D, μ = N/(EI D),
D = 1 + N/(G A_s), ∫ M dx = 0 between clamped ends), Engesser's three
equations shot with scipy (tests/helpers/engesser.py, span_shot) for point
forces, couples and partial trapezoids, the pinned span's midspan moment
(w EI/P)(sec(kL/2) − 1) and its buckling load P_E/(1 + P_E/(G A_s)) —
in compression near buckling, at N = 0, in tension, and with G A_s from
1e3 to 1e-1 times EI/L²."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from formulations.frames import Frame, SpaceFrame
from formulations.frames.mechanics import beam_column
from formulations.frames.mechanics.critical_load import critical_load_factor
from tests.helpers.engesser import span_shot

EI, L = 2.1e6, 5.0
SCALE = EI / L ** 2                      # the bending stiffness's force scale
GAS = [1e3, 1e1, 1e-1]                   # G A_s / (EI/L²)


def clamped_buckling(GAs):
    """Engesser's clamped–clamped buckling load, P_c/(1 + P_c/(G A_s))."""
    Pc = 4 * np.pi ** 2 * EI / L ** 2
    return Pc / (1 + Pc / GAs)


def uniform_fixed_end_moment(q, N, GAs):
    """The clamped member's end moment (θ-row of the nodal loads) under q:
    M = A cos k(x − L/2) − q/(D k²) in compression with ∫ M = 0 gives
    (q/(D k²)) (1 − u cot u), u = kL/2 (cosh, u coth u − 1, in tension);
    qL²/(12 D) (1 + u²/15 + …) below u = 1e-3 (the closed form cancels)."""
    D = 1 + N / GAs
    if N == 0:
        return q * L ** 2 / 12
    k = np.sqrt(abs(N) / (EI * D))
    u = k * L / 2
    if u < 1e-3:
        return q * L ** 2 / (12 * D) * (1 + np.sign(-N) * u * u / 15)
    return q / (D * k * k) * ((1 - u / np.tan(u)) if N < 0 else (u / np.tanh(u) - 1))


@pytest.mark.parametrize("g", GAS)
@pytest.mark.parametrize("share", [0.999, 0.5, 1e-9, 0.0, -1.0, -3000.0])
def test_a_uniform_loads_fixed_end_forces_are_the_closed_forms(g, share):
    GAs = g * SCALE
    N = -share * clamped_buckling(GAs)
    q = -3.0
    m = uniform_fixed_end_moment(q, N, GAs)
    ref = np.array([q * L / 2, m, q * L / 2, -m])
    part = ("distributed", 0.0, L, q, q)
    one = beam_column.nodal_loads([part], EI, N, L, 1 / GAs)
    many = beam_column.nodal_loads_many([part], [EI], [N], [L], [1 / GAs])[0]
    for got in (one, many):
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
    if share == 0.999 and g == 1e-1:
        # near buckling and G A_s: D ≈ 0.004, far from the Euler–Bernoulli member's
        assert abs(m / beam_column.nodal_loads([part], EI, N, L)[1] - 1) > 0.5


LOADS = [("point", 1.3, -7.0, 2.5), ("distributed", 0.8, 4.1, -3.0, 5.0),
         ("point", 3.7, 4.0, -1.5)]


@pytest.mark.parametrize("g", GAS)
@pytest.mark.parametrize("share", [0.999, 0.5, 0.0, -1.0])
def test_point_forces_couples_and_trapezoids_fixed_end_forces_are_the_shot(g, share):
    GAs = g * SCALE
    N = -share * clamped_buckling(GAs)
    _, at0, atL = span_shot(EI, GAs, N, L, LOADS)
    ref = np.array([-at0[3], at0[2], atL[3], -atL[2]])     # minus the end forces
    one = beam_column.nodal_loads(LOADS, EI, N, L, 1 / GAs)
    many = beam_column.nodal_loads_many(LOADS, [EI] * 3, [N] * 3, [L] * 3, [1 / GAs] * 3)
    for got in (one, many.sum(axis=0)):
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-10 * np.abs(ref).max())


def _span(P, GAs, loads, space=False, case="D"):
    """A pinned span A–B along x under P at B (compression positive) and
    ``loads`` across it, in y (a space span's x-y plane, its x-z held)."""
    fr = SpaceFrame() if space else Frame()
    fr.add_node("A", 0.0, 0.0, *([0.0] if space else []))
    fr.add_node("B", L, 0.0, *([0.0] if space else []))
    if space:
        fr.add_member("A", "B", 2e11, 1e-2, EI / 2e11, EI / 2e11, G=8e10, J=1e-5, name="S",
                      shear_area=(GAs / 8e10, GAs / 8e10))
        fr.add_support("A", fix=("ux", "uy", "uz", "rx", "ry"))
        fr.add_support("B", fix=("uy", "uz", "ry"))
    else:
        fr.add_member("A", "B", 2e11, 1e-2, EI / 2e11, name="S", G=8e10, shear_area=GAs / 8e10)
        fr.add_support("A", fix=("ux", "uy"))
        fr.add_support("B", fix=("uy",))
    for ld in loads:
        if ld[0] == "point":
            fr.add_point_load("S", ld[1], fy=ld[2], mz=ld[3], case=case, axes="member")
        else:
            fr.add_distributed_load("S", wy=ld[3], wy2=ld[4], start=ld[1], end=ld[2], case=case,
                                    axes="member")
    fr.add_load("B", fx=-P, case="D")
    return fr


def _pinned(GAs):
    P_E = np.pi ** 2 * EI / L ** 2
    return P_E / (1 + P_E / GAs)


@pytest.mark.parametrize("g", GAS)
@pytest.mark.parametrize("share", [0.95, 0.3, -2.0])
def test_a_pinned_spans_diagram_and_deflection_are_the_shot(g, share):
    """M, V = dM/dx and v along a pinned shear-flexible span under a point
    force, a couple and a trapezoid, in compression at 0.95 and 0.3 of
    Engesser's pinned load and in tension, against the shot (pinned: v = M
    = 0 at both ends); its space twin's Mz, Vy the plane's."""
    GAs = g * SCALE
    P = share * _pinned(GAs)
    state = span_shot(EI, GAs, -P, L, LOADS, start=(0, 2), end=(0, 2))[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plane = _span(P, GAs, LOADS).solve(combination={"D": 1.0}, second_order=True,
                                            accuracy="high")
        space = _span(P, GAs, LOADS, space=True).solve(combination={"D": 1.0},
                                                       second_order=True, accuracy="high")
    assert plane.ok and space.ok, (plane.message, space.message)
    x, _, V, M = plane.diagram("S", 21)
    y = state(x)
    D = 1 - P / GAs
    dv = (y[:, 1] - y[:, 3] / GAs) / D                   # the axis' slope
    np.testing.assert_allclose(M, y[:, 2], rtol=0, atol=1e-9 * np.abs(y[:, 2]).max())
    np.testing.assert_allclose(V, y[:, 3] - P * dv, rtol=0, atol=1e-9 * np.abs(V).max())
    xd, _, v = plane.deflection("S", 21)
    np.testing.assert_allclose(v, state(xd)[:, 0], rtol=0,
                               atol=1e-9 * np.abs(state(xd)[:, 0]).max())
    sx, _, Vy, _, _, _, Mz = space.diagram("S", 21)
    np.testing.assert_allclose(sx, x)
    np.testing.assert_allclose(Mz, M, rtol=0, atol=1e-9 * np.abs(M).max())
    np.testing.assert_allclose(Vy, V, rtol=0, atol=1e-9 * np.abs(V).max())


@pytest.mark.parametrize("space", [False, True])
def test_a_trace_whose_variable_load_bends_a_shear_flexible_member_is_engessers(space):
    """A constant compression at half Engesser's pinned load, the span load
    the variable one (G A_s = 3 P): at p = 1 the midspan moment is (w EI/P)
    (sec(kL/2) − 1), k² = P/(EI (1 − P/(G A_s))).  Before, the loads the
    trace's stiffness was not built with stayed first order on a
    shear-flexible member, and the trace was NOT OK."""
    w = 10.0
    P_E = np.pi ** 2 * EI / L ** 2
    GAs = 0.5 * P_E                               # then P = P_E/6 and G A_s = 3 P
    P = 0.5 * _pinned(GAs)
    assert GAs == pytest.approx(3 * P, rel=1e-12)
    k = np.sqrt(P / (EI * (1 - P / GAs)))
    exact = w * EI / P * (1 / np.cos(k * L / 2) - 1)
    fr = _span(P, GAs, [("distributed", 0.0, L, -w, -w)], space=space, case="V")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ft = fr.trace(1.0, "high", constant={"D": 1.0}, variable={"V": 1.0}, second_order=True)
    assert ft.ok, ft.message
    at = ft.result_at(1.0)
    key = "Mz" if space else "M"
    mid = max(abs(at.extremes("S")[key][e][0]) for e in ("max", "min"))
    assert mid == pytest.approx(exact, rel=1e-9)
    assert exact / (w * L ** 2 / 8) - 1 > 0.5


@pytest.mark.parametrize("g", GAS)
def test_a_loaded_shear_flexible_spans_critical_load_is_engessers(g):
    """α_cr of a pinned shear-flexible span under a span load and 0.4 of
    P_E/(1 + P_E/(G A_s)): 2.5 (the span load does not change N)."""
    GAs = g * SCALE
    fr = _span(0.4 * _pinned(GAs), GAs, LOADS)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve(combination={"D": 1.0}, second_order=True, accuracy="high")
    assert res.ok, res.message
    assert critical_load_factor(fr, res)["alpha"] == pytest.approx(2.5, rel=1e-9)


@pytest.mark.parametrize("loaded", [True, False])
def test_a_shear_flexible_strut_at_its_shear_limit_is_named_unstable(loaded):
    """At N = −G A_s exactly (G A_s = 1e5 N, a power of ten in binary) a
    shear-flexible member has no shear stiffness left and its stiffness is
    not finite, so K(N) cannot be formed.  The strut is then past its own
    (clamped–clamped) buckling load between its nodes, P_c/(1 + P_c/(G A_s))
    = 96 930.9 N with P_c = 4π²EI/L² by hand, as it is a hair either side:
    the refusal must say UNSTABLE and name the member, not call the load
    the frame's α_cr = 1."""
    from qpcontact.core.errors import SolverFailedError

    E, I, Ls, GAs = 2e11, 1e-5, 5.0, 1e5
    Pc = 4 * np.pi ** 2 * E * I / Ls ** 2
    for share in (1 - 1e-3, 1.0, 1.2):
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", Ls, 0.0)
        fr.add_member("A", "B", E, 1e-2, I, name="S", G=GAs, shear_area=1.0)
        fr.add_support("A", fix=("ux", "uy"))
        fr.add_support("B", fix=("uy",))
        if loaded:
            fr.add_distributed_load("S", wy=-10.0, case="D")
        fr.add_load("B", fx=-share * GAs, fy=0.0, case="D")
        words = f"its own buckling at N = {-Pc / (1 + Pc / GAs):.6g}"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if share == 1.0:
                with pytest.raises(SolverFailedError, match="UNSTABLE") as err:
                    fr.solve(combination={"D": 1.0}, second_order=True, raise_on_failure=False)
                assert words in str(err.value) and "α_cr = 1" not in str(err.value)
            else:
                res = fr.solve(combination={"D": 1.0}, second_order=True,
                               raise_on_failure=False)
                assert not res.ok and "UNSTABLE" in res.message and words in res.message


@pytest.mark.parametrize("space", [False, True])
def test_a_point_force_at_the_far_end_does_not_bend_the_member(space):
    """A point force at a = L on a shear-flexible member lies on its end
    node (its fixed-end forces are all at j), so with node j held across
    the axis the member bends as it does without it: its moments and every
    section before L are the bare member's, and its end force at j carries
    exactly the force.  Taken on the section's right side at L, the force's
    shear kink −c py/D put N c py/D more into V_j (2 222 N, 5.6 % of V_j, on
    this 7 m member under N = −2 MN with G A_s = 20 MN)."""
    E, G, I, A, Lm = 210e9, 81e9, 2.313e-4, 8.45e-3, 7.0
    forces = {"Vy": -20e3, "Vz": -10e3} if space else {"V": -20e3}

    def member(at_end):
        fr = SpaceFrame() if space else Frame()
        if space:
            fr.add_node("A", 0.0, 0.0, 0.0)
            fr.add_node("B", Lm, 0.0, 0.0)
            fr.add_member("A", "B", E, A, I, I, G=G, J=1e-5, name="b",
                          shear_area=(2e7 / G, 2e7 / G))
            fr.add_support("A")
            fr.add_support("B", fix=("uy", "uz", "rx", "ry", "rz"))
            fr.add_distributed_load("b", wy=-5e3, wz=-3e3, case="D")
            if at_end:
                fr.add_point_load("b", Lm, fy=-20e3, fz=-10e3, case="D")
        else:
            fr.add_node("A", 0.0, 0.0)
            fr.add_node("B", Lm, 0.0)
            fr.add_member("A", "B", E, A, I, name="b", G=G, shear_area=2e7 / G)
            fr.add_support("A")
            fr.add_support("B", fix=("uy", "rz"))
            fr.add_distributed_load("b", wy=-5e3, case="D")
            if at_end:
                fr.add_point_load("b", Lm, fy=-20e3, case="D")
        fr.add_load("B", fx=-2e6, case="D")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = fr.solve(combination={"D": 1.0}, second_order=True)
        assert res.ok, res.message
        return res

    loaded, bare = member(True), member(False)
    ends, ends0 = loaded.end_forces("b"), bare.end_forces("b")
    for key in list(forces) + (["My", "Mz"] if space else ["M"]):
        scale = max(abs(ends0["i"][key]), abs(ends0["j"][key]))
        assert ends["i"][key] == pytest.approx(ends0["i"][key], abs=1e-10 * scale), key
        step = abs(ends["j"][key] - ends0["j"][key])
        assert step == pytest.approx(abs(forces.get(key, 0.0)), abs=1e-10 * scale), key
    if not space:
        _, _, V, M = loaded.diagram("b", 9)
        _, _, V0, M0 = bare.diagram("b", 9)
        assert np.allclose(V[:-1], V0[:-1], rtol=0, atol=1e-10 * np.abs(V0).max())
        assert np.allclose(M, M0, rtol=0, atol=1e-10 * np.abs(M0).max())


def test_the_tangent_alpha_cr_counts_is_the_built_stiffness():
    """α_cr's count reads K(N) from ``stiffness(axial, along)``, which
    leaves the members' span loads out (they were half a space frame's
    tangent); K must be the one ``build`` makes with them, entry for entry,
    on members with rigid zones, released ends, springs, shear flexibility,
    point loads and couples under a constant N, and N varying along a
    member (a load with an axial part)."""
    import scipy.sparse as sp

    from formulations.frames.plane import plane_assembly
    from formulations.frames.space import space_assembly

    comb = {"D": 1.0}
    fr = Frame()
    for n, x, y in (("A", 0, 0), ("B", 0, 4), ("C", 6, 4), ("D", 6, 0), ("E", 10, 4)):
        fr.add_node(n, x, y)
    fr.add_member("A", "B", 2.1e11, 1.49e-2, 2.517e-4, name="c1", G=8.1e10, shear_area=4.7e-3)
    fr.add_member("B", "C", 2.1e11, 8.45e-3, 2.313e-4, name="beam", offset_i=0.2,
                  offset_j=0.3, G=8.1e10, shear_area=4e-3)
    fr.add_member("D", "C", 2.1e11, 1.49e-2, 2.517e-4, name="c2", spring_i=5e7)
    fr.add_member("C", "E", 2.1e11, 8.45e-3, 2.313e-4, name="cant", hinge_i=False)
    fr.add_support("A")
    fr.add_support("D")
    fr.add_distributed_load("beam", wy=-30e3, case="D")
    fr.add_point_load("beam", 2.0, fy=-40e3, mz=5e3, case="D")
    fr.add_point_load("c1", 1.5, fx=20e3, fy=-50e3, case="D")      # an axial part: N(x)
    fr.add_distributed_load("cant", wy=-10e3, case="D")
    fr.add_load("B", fx=30e3, case="D")
    N = np.array([-4e5, -3e4, -5e5, 1e4])
    K_alone = fr.stiffness(axial=N, along=comb)
    K_built = plane_assembly.assemble(fr, N, comb)[2]
    assert (sp.csr_matrix(K_alone) != sp.csr_matrix(K_built)).nnz == 0

    sf = SpaceFrame()
    for n, xyz in (("A", (0, 0, 0)), ("B", (0, 0, 4)), ("C", (6, 0, 4)), ("D", (6, 0, 0))):
        sf.add_node(n, *xyz)
    sf.add_member("A", "B", 2.1e11, 1.49e-2, 2.517e-4, 8.56e-5, G=8.1e10, J=1.85e-6,
                  name="c1", shear_area=(4.7e-3, 1.2e-3))
    sf.add_member("B", "C", 2.1e11, 8.45e-3, 2.313e-4, 1.3e-5, G=8.1e10, J=5e-7, name="beam",
                  offset_i=0.2, offset_j=0.3, shear_area=(4e-3, 3e-3))
    sf.add_member("D", "C", 2.1e11, 1.49e-2, 2.517e-4, 8.56e-5, G=8.1e10, J=1.85e-6, name="c2")
    sf.add_support("A")
    sf.add_support("D")
    sf.add_distributed_load("beam", wz=-20e3, case="D")
    sf.add_point_load("beam", 2.0, fy=-10e3, fz=-40e3, case="D")
    sf.add_point_load("c1", 1.5, fx=10e3, fz=-50e3, case="D")
    Ns = np.array([-4e5, -3e4, -5e5])
    K_alone = sf.stiffness(axial=Ns, along=comb)
    K_built = space_assembly.assemble(sf, Ns, comb)[0]
    assert (sp.csr_matrix(K_alone) != sp.csr_matrix(K_built)).nnz == 0
