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
