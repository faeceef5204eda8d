"""Span loads on members under axial force in a second-order answer: a
member carries them as the beam-column (fixed-end forces and diagrams with
its own P-δ; plane or space, Engesser's with shear deformation, under N(x)
where their axial parts make N vary), so one element is ok and right.
Reference: the beam-column's closed form for a pinned span under a uniform
load w and a compression P, M(L/2) = (w/k²) (sec(kL/2) − 1), k = √(P/EI)
(k² = P/(β EI) with shear), and shots of the columns under their weight."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from formulations.frames import Frame, SpaceFrame

E, I, L, W = 2e8, 1e-5, 5.0, 10.0
P_E = np.pi ** 2 * E * I / L ** 2


def _strut(pieces: int, share: float, space: bool = False):
    fr = SpaceFrame() if space else Frame()
    for k in range(pieces + 1):
        fr.add_node(f"N{k}", L * k / pieces, 0.0, *([0.0] if space else []))
    for k in range(pieces):
        if space:
            fr.add_member(f"N{k}", f"N{k + 1}", E, 0.01, I, I, G=8e7, J=1e-5, name=f"S{k}")
            fr.add_distributed_load(f"S{k}", wz=-W, case="D")
        else:
            fr.add_member(f"N{k}", f"N{k + 1}", E, 0.01, I, name=f"S{k}")
            fr.add_distributed_load(f"S{k}", wy=-W, case="D")
    if space:
        fr.add_support("N0", fix=("ux", "uy", "uz", "rx"))
        fr.add_support(f"N{pieces}", fix=("uy", "uz"))
    else:
        fr.add_support("N0", fix=("ux", "uy"))
        fr.add_support(f"N{pieces}", fix=("uy",))
    fr.add_load(f"N{pieces}", fx=-share * P_E, case="D")
    return fr


def _solve(fr, accuracy):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fr.solve(combination={"D": 1.0}, second_order=True, raise_on_failure=False,
                        accuracy=accuracy)


def _midspan(fr, res):
    key = "My" if isinstance(fr, SpaceFrame) else "M"     # wz bends a space member about y
    return max(abs(res.extremes(m)[key][e][0]) for m in fr.members for e in ("max", "min"))


def _closed_form(share):
    k = np.sqrt(share * P_E / (E * I))
    return W / k ** 2 * (1 / np.cos(k * L / 2) - 1)


@pytest.mark.parametrize("space", [False, True])
def test_one_element_under_compression_is_ok_and_the_beam_column(space):
    fr = _strut(1, 0.5, space)
    res = _solve(fr, "high")
    assert res.ok, res.message
    assert _midspan(fr, res) == pytest.approx(_closed_form(0.5), rel=1e-9)
    assert _closed_form(0.5) == pytest.approx(63.435770, abs=1e-6)


@pytest.mark.parametrize("space", [False, True])
@pytest.mark.parametrize("pieces", [3, 16])
@pytest.mark.parametrize("share", [0.1, 0.5, 0.9])
def test_cut_or_not_it_is_ok_and_right(share, pieces, space):
    fr = _strut(pieces, share, space)
    res = _solve(fr, "high")
    assert res.ok, res.message
    assert _midspan(fr, res) == pytest.approx(_closed_form(share), rel=1e-9)


@pytest.mark.parametrize("space", [False, True])
def test_a_loaded_member_with_shear_deformation_under_compression_is_engessers(space):
    # a pinned span with shear deformation (G A_s = 3 P) under w and P: its
    # loads are the beam-column's under N (mechanics.beam_column), the
    # midspan moment Engesser's (w EI/P)(sec(kL/2) − 1), k² = P/(β EI), β =
    # 1 − P/(G A_s) (M'' + k² M = w/β from M' = N v' − V, V' = −w and β v''
    # = M/EI − w/(G A_s)); it was refused ("span loads of member(s) S")
    P, G_ = 0.3 * P_E, 8e4
    As = 3.0 * P / G_
    k = np.sqrt(P / ((1 - P / (G_ * As)) * E * I))
    exact = W * E * I / P * (1 / np.cos(k * L / 2) - 1)
    fr = SpaceFrame() if space else Frame()
    fr.add_node("A", 0.0, 0.0, *([0.0] if space else []))
    fr.add_node("B", L, 0.0, *([0.0] if space else []))
    if space:
        fr.add_member("A", "B", E, 0.01, I, I, G=G_, J=1e-5, name="S", shear_area=As)
        fr.add_distributed_load("S", wz=-W, case="D")
        fr.add_support("A", fix=("ux", "uy", "uz", "rx"))
        fr.add_support("B", fix=("uy", "uz"))
    else:
        fr.add_member("A", "B", E, 0.01, I, name="S", G=G_, shear_area=As)
        fr.add_distributed_load("S", wy=-W, case="D")
        fr.add_support("A", fix=("ux", "uy"))
        fr.add_support("B", fix=("uy",))
    fr.add_load("B", fx=-P, case="D")
    low, high = _solve(fr, "low"), _solve(fr, "high")
    assert low.ok and high.ok, (low.message, high.message)
    assert _midspan(fr, high) == pytest.approx(exact, rel=1e-9)
    assert exact / (W * L ** 2 / 8) - 1 > 0.5         # far from the first-order moment


def test_span_loads_without_axial_force_are_left_alone():
    fr = _strut(1, 0.0)
    res = _solve(fr, "high")
    assert res.ok, res.message
    assert _midspan(fr, res) == pytest.approx(W * L ** 2 / 8, rel=1e-9)


@pytest.mark.parametrize("p_max", [None, 1.0])
def test_a_trace_whose_variable_loads_bend_a_compressed_member_is_the_beam_column(p_max):
    # a constant compression at half the Euler load, the span load the
    # variable one: its moment at p = 1 is the beam-column's (it was first
    # order, half of it, and then refused)
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, 0.01, I, name="S")
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_support("B", fix=("uy",))
    fr.add_load("B", fx=-0.5 * P_E, case="D")
    fr.add_distributed_load("S", wy=-W, case="V")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ft = fr.trace(p_max, "high", constant={"D": 1.0}, variable={"V": 1.0}, second_order=True)
    assert ft.ok, ft.message
    assert _midspan(fr, ft.result_at(1.0)) == pytest.approx(_closed_form(0.5), rel=1e-9)


def test_a_shear_flexible_column_under_its_weight_is_its_shot():
    # a shear-flexible column hinged at both ends, its weight 0.2 P_E, 0.3
    # P_E on top, 1 N across it at mid-height: its element takes N(x)
    # (mechanics.varying_axial), so uncut it is ok and its mid sway the
    # ODE shot's; it was refused at 1 and 64 pieces ("axial parts")
    GAs = 8e7 * 0.01 * 5 / 6

    def column(pieces):
        fr = Frame()
        for k in range(pieces + 1):
            fr.add_node(f"N{k}", 0.0, L * k / pieces)
        for k in range(pieces):
            fr.add_member(f"N{k}", f"N{k + 1}", E, 0.01, I, name=f"C{k}", G=8e7,
                          shear_area=0.01 * 5 / 6)
            fr.add_distributed_load(f"C{k}", wy=-0.2 * P_E / L, case="D")
        fr.add_support("N0", fix=("ux", "uy"))
        fr.add_support(f"N{pieces}", fix=("ux",))
        fr.add_load(f"N{pieces}", fy=-0.3 * P_E, fx=0.0, case="D")
        fr.add_load(f"N{pieces // 2}", fx=1.0, case="D")
        return fr
    ref = _hinged_shot(lambda x: -0.3 * P_E - 0.2 * P_E * (L - x) / L, GAs, 1.0)
    for pieces in (2, 64):
        fr = column(pieces)
        low, high = _solve(fr, "low"), _solve(fr, "high")
        assert low.ok and high.ok, (low.message, high.message)
        assert high.displacements[f"N{pieces // 2}"][0] == pytest.approx(ref, rel=1e-9)
        assert low.displacements[f"N{pieces // 2}"][0] == pytest.approx(ref, rel=1e-4)


def _hinged_shot(N, GAs, H):
    """The mid-height sway [m] of a column hinged at both ends under N(x)
    with H across it at L/2 (global +x): Engesser's equations in member
    axes (y = −x global), v' = (θ − S/GAs)/(1 + N/GAs), EI θ' = M, M' = S
    + N v', S' = 0 but for −H at L/2; v = M = 0 at both ends, by shots
    from (θ(0), S(0)) — linear, so three of them."""
    from scipy.integrate import solve_ivp

    def rhs(x, y):
        dv = (y[1] - y[3] / GAs) / (1 + N(x) / GAs)
        return [dv, y[2] / (E * I), y[3] + N(x) * dv, 0.0]

    def shot(theta, S):
        y = solve_ivp(rhs, (0, L / 2), [0.0, theta, 0.0, S], method="DOP853", rtol=1e-13,
                      atol=1e-22).y[:, -1]
        mid = y[0]
        y = solve_ivp(rhs, (L / 2, L), y + [0.0, 0.0, 0.0, -H], method="DOP853", rtol=1e-13,
                      atol=1e-22).y[:, -1]
        return np.array([y[0], y[2]]), mid
    e0, m0 = shot(0.0, 0.0)
    e1, m1 = shot(1e-6, 0.0)
    e2, m2 = shot(0.0, 1.0)
    a = np.linalg.solve(np.c_[e1 - e0, e2 - e0], -e0)
    return -(m0 + a[0] * (m1 - m0) + a[1] * (m2 - m0))      # member y is −x


@pytest.mark.parametrize("a", [0.0, L])
def test_a_force_at_a_members_end_is_left_alone(a):
    # it goes to the node whatever N (no span moment): the same answer as
    # the nodal load, ok; it was not ok, and no cut of the member cleared it
    def column(on_member):
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", 0.0, L)
        fr.add_member("A", "B", E, 0.01, I, name="C")
        fr.add_support("A", fix=("ux", "uy", "rz"))
        fr.add_load("B", fy=-0.1 * P_E, fx=1.0, case="D")
        if on_member:
            fr.add_point_load("C", a, fx=5.0, case="D")
        else:
            fr.add_load("B" if a else "A", fx=5.0, case="D")
        return fr
    fr, nodal = column(True), column(False)
    res, ref = _solve(fr, "high"), _solve(nodal, "high")
    assert res.ok and ref.ok, res.message
    for node in ("A", "B"):
        assert res.displacements[node] == pytest.approx(ref.displacements[node], rel=1e-9)


def test_a_member_with_shear_deformation_and_no_axial_force_is_left_alone():
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, 0.01, I, name="S", G=8e7, shear_area=0.01 * 5 / 6)
    fr.add_support("A", fix=("ux", "uy", "rz"))
    fr.add_load("B", fy=-10.0, case="D")
    res = _solve(fr, "high")
    assert res.ok, res.message
    # the Timoshenko cantilever's tip deflection by hand: P L³/(3EI) + P L/(G A_s)
    tip = 10.0 * L ** 3 / (3 * E * I) + 10.0 * L / (8e7 * 0.01 * 5 / 6)
    assert res.displacements["B"][1] == pytest.approx(-tip, rel=1e-9)


def test_a_swaying_column_under_its_own_weight_is_its_shot():
    """A shear-flexible cantilever column at 0.24 of π²EI/L² (0.96 of its
    sway buckling load, α_cr ≈ 1.04) under a self-weight of 1e-4 of it:
    its element takes N(x) (mechanics.varying_axial), so uncut it is ok
    and its tip sway the ODE shot's.  It was refused on its sway load's
    bound (and before that bound, taking the mean N, ok at "low" with its
    base moment 2.0e-3 off)."""
    from scipy.integrate import solve_ivp

    E_, A_, I_, L_ = 2e8, 1e-2, 1e-5, 5.0
    P_p = np.pi ** 2 * E_ * I_ / L_ ** 2
    GAs, H, weight = 8e7 * A_ * 5 / 6, 0.01, 1e-4 * P_p

    def column():
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", 0.0, L_)
        fr.add_member("A", "B", E_, A_, I_, name="col", G=8e7, shear_area=A_ * 5 / 6)
        fr.add_distributed_load("col", 0.0, -weight / L_)      # along the axis
        fr.add_support("A")
        fr.add_load("B", fx=H, fy=-0.24 * P_p)
        return fr

    def rhs(x, y):     # member axes (y = −x global): S = H, M' = S + N v'
        N = -0.24 * P_p - weight * (L_ - x) / L_
        dv = (y[1] - H / GAs) / (1 + N / GAs)
        return [dv, y[2] / (E_ * I_), H + N * dv]

    def tip(M0):
        return solve_ivp(rhs, (0, L_), [0.0, 0.0, M0], method="DOP853", rtol=1e-13,
                         atol=1e-22).y[:, -1]
    e0, e1 = tip(0.0), tip(1.0)
    ref = -tip(-e0[2] / (e1[2] - e0[2]))[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        low, high = (column().solve(second_order=True, accuracy=acc, raise_on_failure=False)
                     for acc in ("low", "high"))
    assert low.ok and high.ok, (low.message, high.message)
    assert high.displacements["B"][0] == pytest.approx(ref, rel=1e-9)
    assert low.displacements["B"][0] == pytest.approx(ref, rel=1e-4)
