"""Span loads on members under axial force in a second-order answer: a
plane Euler–Bernoulli member carries them as the beam-column (fixed-end
forces and diagrams with its own P-δ), so one element is ok and right;
what stays first order — a space member's loads, a Timoshenko member's, the
axial parts of member loads that make N vary along a member — is bounded,
and an answer where it is off by more than the accuracy asked is not ok
and names the members.  Reference: the beam-column's closed form for a
pinned span under a uniform load w and a compression P, M(L/2) = (w/k²)
(sec(kL/2) − 1), k = √(P/EI)."""

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
def test_a_loaded_member_with_shear_deformation_under_compression_is_not_ok(space):
    # a Timoshenko member's loads stay its first-order element's: refused
    # by the amplification bound, and named
    fr = SpaceFrame() if space else Frame()
    fr.add_node("A", 0.0, 0.0, *([0.0] if space else []))
    fr.add_node("B", L, 0.0, *([0.0] if space else []))
    if space:
        fr.add_member("A", "B", E, 0.01, I, I, G=8e10, J=1e-5, name="S",
                      shear_area=0.01 * 5 / 6)
        fr.add_distributed_load("S", wz=-W, case="D")
        fr.add_support("A", fix=("ux", "uy", "uz", "rx"))
        fr.add_support("B", fix=("uy", "uz"))
    else:
        fr.add_member("A", "B", E, 0.01, I, name="S", G=8e10, shear_area=0.01 * 5 / 6)
        fr.add_distributed_load("S", wy=-W, case="D")
        fr.add_support("A", fix=("ux", "uy"))
        fr.add_support("B", fix=("uy",))
    fr.add_load("B", fx=-0.3 * P_E, case="D")
    res = _solve(fr, "low")
    assert not res.ok
    assert "span loads of member(s) S" in res.message


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


def test_axial_parts_of_member_loads_under_compression_are_not_ok_where_they_matter():
    # a shear-flexible column's own weight makes N vary along it about the
    # mean its element takes: bounded, not ok beyond the accuracy asked;
    # cut into pieces, each piece's spread is small and their sum (the
    # answer takes them all: second_order.spread_through_frame) falls as
    # 1/pieces² — 1.6e-4 at 64 pieces (whose mid sway is 6.7e-7 off a
    # 256/512-piece lumped cut), a quarter of it at 128 (an Euler–Bernoulli member
    # takes N(x) as it is: test_second_order_varying_axial.py)
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
    res = _solve(column(1), "low")
    assert not res.ok
    assert "axial parts" in res.message and "C0" in res.message
    assert not _solve(column(64), "low").ok
    assert _solve(column(128), "low").ok


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


def test_a_swaying_column_under_its_own_weight_is_judged_on_its_sway_load():
    """A cantilever column at 0.24 of π²EI/L² (0.96 of its sway buckling
    load, α_cr ≈ 1.04) under a self-weight of 1e-4 of it: a shear-flexible
    element takes N as the mean along the member (an Euler–Bernoulli one
    as the mean, its base moment and tip sway were 2.0e-3 off: the column
    cut into 32 and 64 pieces, which agree to 1.2e-6).  The member's own
    bound on its pinned load said 1e-5: ok at "low".  On its sway load
    P_p/4 (and the frame's α_cr) it is not ok; without the self-weight the
    same column is ok.  (The Euler–Bernoulli column now takes N(x):
    test_second_order_varying_axial.py.)"""
    E_, A_, I_, L_ = 2e8, 1e-2, 1e-5, 5.0
    P_p = np.pi ** 2 * E_ * I_ / L_ ** 2

    def column(weight):
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", 0.0, L_)
        fr.add_member("A", "B", E_, A_, I_, name="col", G=8e7, shear_area=A_ * 5 / 6)
        if weight:
            fr.add_distributed_load("col", 0.0, -weight / L_)      # along the axis
        fr.add_support("A")
        fr.add_load("B", fx=0.01, fy=-0.24 * P_p)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return fr.solve(second_order=True, accuracy="low", raise_on_failure=False)

    res = column(1e-4 * P_p)
    assert not res.ok and "col (N = " in res.message and "axial parts" in res.message, res.message
    assert column(0.0).ok
