"""Span loads on members under axial force in a second-order answer: their
fixed-end forces and diagrams are first order (no P-δ of their own in the
element), so an answer where that is off by more than the accuracy asked is
not ok and names the members; cut into pieces (whose stability functions
carry the P-δ), the same member is ok and right.  Reference: the
beam-column's closed form for a pinned span under a uniform load w and a
compression P, M(L/2) = (w/k²)(sec(kL/2) − 1), k = √(P/EI)."""

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
def test_one_element_under_compression_is_not_ok_and_names_the_member(space):
    fr = _strut(1, 0.5, space)
    res = _solve(fr, "low")
    assert not res.ok
    assert "span loads of member(s) S0" in res.message and "add nodes" in res.message
    # what it would have said: first order, wL²/8, half the beam-column's 63.44
    assert _midspan(fr, res) == pytest.approx(W * L ** 2 / 8, rel=1e-9)
    assert _closed_form(0.5) > 2 * W * L ** 2 / 8


@pytest.mark.parametrize("share", [0.1, 0.5, 0.9])
def test_cut_into_pieces_it_is_ok_to_the_accuracy_asked_and_right(share):
    fr = _strut(16, share)
    res = _solve(fr, "low")
    assert res.ok, res.message
    assert _midspan(fr, res) == pytest.approx(_closed_form(share), rel=1e-4)
    assert not _solve(fr, "high").ok          # 16 pieces are not the beam-column to 1e-9


def test_span_loads_without_axial_force_are_left_alone():
    fr = _strut(1, 0.0)
    res = _solve(fr, "high")
    assert res.ok, res.message
    assert _midspan(fr, res) == pytest.approx(W * L ** 2 / 8, rel=1e-9)


@pytest.mark.parametrize("p_max", [None, 1.0])
def test_a_trace_whose_variable_loads_bend_a_compressed_member_is_not_ok(p_max):
    # a constant compression at half the Euler load, the span load the
    # variable one: traced without p_max the path is one unbounded piece
    # starting at p = 0, where no span load acts yet; it was ok, its moment
    # at p = 1 first order, half the beam-column's
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
        ft = fr.trace(p_max, "low", constant={"D": 1.0}, variable={"V": 1.0}, second_order=True)
    assert not ft.ok
    assert "span loads of member(s) S" in ft.message
    assert _midspan(fr, ft.result_at(1.0)) == pytest.approx(W * L ** 2 / 8, rel=1e-9)
    assert _closed_form(0.5) > 2 * W * L ** 2 / 8


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
