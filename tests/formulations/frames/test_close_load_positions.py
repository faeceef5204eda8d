"""Two load positions on one member from 0 to 1e-3 m apart, under N(x): the
member's chain has a piece that short (mechanics/varying_axial.py), which
as a stiffness (∝ 1/h³) made the chain singular — LinAlgError at 1 ulp to
1e-9 m, garbage refused at 1e-6, a right answer refused at 1e-3 (its
statics residual 2.3e-5) — and as a transfer matrix is the identity's
neighbour (mechanics/varying_pieces.py).  A 5.3 m cantilever column (EI
2.1e6 N m²) under its weight 100 kN/m up to 2L/3, a second load at L − L/3
(2L/3 to the last bit, or 1 ulp to 1e-3 m past it) along its axis (100
kN) or across it (50 N), 10 N across its top; plane and space, Euler–
Bernoulli and shear-flexible.  References: Engesser's equations under N(x)
shot with scipy's DOP853 piece by piece between the load positions (the
equations written here, not the element's), and the two loads at one
position (summed)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from formulations.frames import Frame
from formulations.frames.space.space_frame import SpaceFrame

L, E, A, I = 5.3, 210e9, 1e-2, 1e-5
W, P, Q, H = 100e3, 100e3, 50.0, 10.0
END = 2 * L / 3                     # the weight's end
AT = L - L / 3                      # the second load's position (== END here)
GAPS = [0.0, "ulp", 1e-12, 1e-9, 1e-6, 1e-3]


def _position(gap):
    return float(np.nextafter(AT, np.inf)) if gap == "ulp" else AT + gap


def _column(space, kind, at, GAs=None):
    shear = {} if GAs is None else {"shear_area": GAs / 81e9}
    if space:
        fr = SpaceFrame()
        fr.add_node("A", 0.0, 0.0, 0.0)
        fr.add_node("B", 0.0, 0.0, L)
        fr.add_member("A", "B", E, A, I, I, G=81e9, J=2e-5, name="c", **shear)
        fr.add_distributed_load("c", wz=-W, end=END, case="D")
        fr.add_point_load("c", at, **({"fz": -P} if kind == "along" else {"fx": Q}), case="D")
    else:
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", 0.0, L)
        fr.add_member("A", "B", E, A, I, name="c", **({"G": 81e9} if GAs else {}), **shear)
        fr.add_distributed_load("c", wy=-W, end=END, case="D")
        fr.add_point_load("c", at, **({"fy": -P} if kind == "along" else {"fx": Q}), case="D")
    fr.add_support("A")
    fr.add_load("B", fx=H, case="D")
    return fr


def _shot(kind, at, GAs=None):
    """(the top's sway along +x, the base moment) of the column: member axes
    x up, y = −x global; v' = (θ − S/GAs)/(1 + N/GAs), EI θ' = M, M' = S +
    N v', S constant but for a force across at ``at`` (S jumps by its y
    part); v = θ = 0 at the base, M = 0 and S = H at the top; N(x) = −W
    (END − x)⁺ − P [x < at] (compression); linear in (M(0), S(0))."""
    c = 0.0 if GAs is None else 1.0 / GAs

    def N(x):
        return -W * max(END - x, 0.0) - (P if kind == "along" and x < at else 0.0)

    def rhs(x, y):
        dv = (y[1] - c * y[3]) / (1 + c * N(x))
        return [dv, y[2] / (E * I), y[3] + N(x) * dv, 0.0]

    def shoot(M0, S0):
        y = np.array([0.0, 0.0, M0, S0])
        edges = sorted({0.0, END, at, L})
        for lo, hi in zip(edges[:-1], edges[1:]):
            if hi > lo:
                y = solve_ivp(rhs, (lo, hi), y, method="DOP853", rtol=1e-13,
                              atol=1e-22).y[:, -1]
            if hi == at and kind == "across":
                y = y + [0.0, 0.0, 0.0, -Q]
        return y
    e0, e1, e2 = shoot(0.0, 0.0), shoot(1.0, 0.0), shoot(0.0, 1.0)
    M0, S0 = np.linalg.solve(np.c_[(e1 - e0)[[2, 3]], (e2 - e0)[[2, 3]]],
                             [0.0, H] - e0[[2, 3]])
    return -shoot(M0, S0)[0], M0


def _solve(fr):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fr.solve(combination={"D": 1.0}, second_order=True, accuracy="high",
                        raise_on_failure=False)


@pytest.mark.parametrize("GAs", [None, 3e6])
@pytest.mark.parametrize("kind", ["along", "across"])
@pytest.mark.parametrize("space", [False, True])
def test_two_loads_a_hair_apart_are_the_shots_answer(space, kind, GAs):
    summed = _solve(_column(space, kind, AT, GAs))
    assert summed.ok, summed.message
    for gap in GAPS:
        at = _position(gap)
        res = _solve(_column(space, kind, at, GAs))
        assert res.ok, (gap, res.message)
        sway, base = _shot(kind, at, GAs)
        assert res.displacements["B"][0] == pytest.approx(sway, rel=1e-9), gap
        if not space:
            assert res.end_forces("c")["i"]["M"] == pytest.approx(base, rel=1e-9), gap
        if gap in ("ulp", 1e-12, 1e-9):
            # a hair from one position: the summed answer (it moves by ~gap/L)
            np.testing.assert_allclose(res.displacements["B"], summed.displacements["B"],
                                       rtol=1e-9, atol=1e-15)


def _zoned_portal(span, GAs):
    """A portal whose beam (rigid zones 0.48 and 0.29 m) carries 30 kN/m."""
    E = 210e9
    fr = Frame()
    for n, x, y in (("A", 0, 0), ("B", 0, 4), ("C", span, 4), ("D", span, 0)):
        fr.add_node(n, x, y)
    fr.add_member("A", "B", E, 1.49e-2, 2.517e-4, name="L")
    fr.add_member("D", "C", E, 1.49e-2, 2.517e-4, name="R")
    kw = {} if GAs is None else dict(G=81e9, shear_area=GAs / 81e9)
    fr.add_member("B", "C", E, 8.45e-3, 2.313e-4, name="beam", offset_i=0.48, offset_j=0.29, **kw)
    fr.add_distributed_load("beam", wy=-30e3, case="D")
    fr.add_support("A")
    fr.add_support("D")
    fr.add_load("B", fx=20e3, case="D")
    return fr


@pytest.mark.parametrize("GAs", [3.2e8, None])
def test_a_load_ending_an_ulp_short_of_the_last_cut_stays_on_it(GAs):
    """Span 6.11 m, zones 0.48 / 0.29: the load's clipped end (L − o_j) − o_i
    is 5.34 and the flexible length L − o_i − o_j 5.340000000000001, and the
    last piece of the chain lost its load (equilibrium residual 0.65, not
    ok; beside a larger load elsewhere, ok with the moments' signs wrong).
    The reactions carry the whole load, and the moments are those of the
    span 1e-9 m longer, which has no such ulp."""
    assert (6.11 - 0.29) - 0.48 != 6.11 - 0.48 - 0.29
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = _zoned_portal(6.11, GAs).solve(combination={"D": 1.0}, second_order=True,
                                             raise_on_failure=False)
        ref = _zoned_portal(6.11 + 1e-9, GAs).solve(combination={"D": 1.0}, second_order=True)
    assert res.ok, res.message
    up = sum(res.reactions[s][1] for s in ("A", "D"))
    assert up == pytest.approx(30e3 * 6.11, rel=1e-9)
    for end in ("i", "j"):
        assert res.end_forces("beam")[end]["M"] == pytest.approx(
            ref.end_forces("beam")[end]["M"], rel=1e-6)
