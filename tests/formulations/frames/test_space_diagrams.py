"""A space member's internal forces along its length (``diagram``,
``extremes``, ``end_forces``) against statics by hand: a cantilever under
tip forces across both axes and a torque, the same with the member standing
up and rolled (its local axes not the global ones: the statics written with
vectors), a simply supported member under a uniform load across each axis
(wL²/8 at midspan, 5wL⁴/384EI), a load given in member axes on an inclined
member; and the misuse of the methods."""

from __future__ import annotations

import math

import numpy as np
import pytest

from formulations.frames import SpaceFrame
from qpcontact.core.errors import InvalidOptionError, InvalidProblemError

E, G = 2.1e8, 8.1e7                    # kN/m²
A, IY, IZ, J = 0.01, 2e-5, 5e-5, 1e-5   # m², m⁴
L = 4.0                                 # m


def _cantilever(end, load, ref=None, roll=0.0):
    """A member clamped at A = 0, free at B = ``end``, ``load`` (fx, fy, fz,
    mx, my, mz) at B (global)."""
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", *end)
    fr.add_member("A", "B", E, A, IY, IZ, G=G, J=J, name="M", ref=ref, roll=roll)
    fr.add_support("A")
    fr.add_load("B", *load)
    r = fr.solve()
    assert r.ok, r.message
    return fr, r


def test_a_cantilever_under_tip_forces_across_both_axes_and_a_torque():
    """Along global x (local y = Y, z = Z): Py = 2 kN, Pz = -3 kN (down),
    Mx = 1.5 kN·m at the tip.  The part beyond a section carries the tip
    load: V = -P on the section's face (V = dM/dx), Mz = Py (L - x) (+y
    fibre in compression: the tip moves to +y), My = Pz (L - x) (hogging:
    the top fibre +z in tension, so negative), T = Mx, N = 0."""
    py, pz, mx = 2.0, -3.0, 1.5
    fr, r = _cantilever((L, 0.0, 0.0), (0.0, py, pz, mx, 0.0, 0.0))
    x, N, Vy, Vz, T, My, Mz = r.diagram("M", 9)
    np.testing.assert_allclose(x, np.linspace(0.0, L, 9), rtol=0, atol=1e-15)
    hand = {"N": 0 * x, "Vy": -py + 0 * x, "Vz": -pz + 0 * x, "T": mx + 0 * x,
            "My": pz * (L - x), "Mz": py * (L - x)}
    for q, got in zip(hand, (N, Vy, Vz, T, My, Mz)):
        np.testing.assert_allclose(got, hand[q], rtol=0, atol=1e-12, err_msg=q)
    ends = r.end_forces("M")
    assert ends["i"] == pytest.approx({"N": 0.0, "Vy": -py, "Vz": -pz, "T": mx,
                                       "My": pz * L, "Mz": py * L}, abs=1e-12)
    assert ends["j"] == pytest.approx({"N": 0.0, "Vy": -py, "Vz": -pz, "T": mx, "My": 0.0,
                                       "Mz": 0.0}, abs=1e-12)
    ext = r.extremes("M")
    assert ext["My"]["min"] == pytest.approx((pz * L, 0.0), abs=1e-12)
    assert ext["Mz"]["max"] == pytest.approx((py * L, 0.0), abs=1e-12)
    # the tip's deflections: P L³ / 3EI across each axis
    assert ext["v"]["max"] == pytest.approx((py * L ** 3 / (3 * E * IZ), L), rel=1e-12)
    assert ext["w"]["min"] == pytest.approx((pz * L ** 3 / (3 * E * IY), L), rel=1e-12)


@pytest.mark.parametrize("end, ref, roll", [((0.0, 0.0, L), None, 0.0),
                                            ((1.0, 2.0, 2.0), (0.0, 0.0, 1.0), 0.7),
                                            ((0.0, -L, 0.0), (1.0, 0.0, 1.0), -1.2)])
def test_a_cantilever_in_any_orientation_against_vector_statics(end, ref, roll):
    """The member standing up, inclined and rolled: its local axes are read
    off the element (a unit vector along each local axis turned into global
    components by the user's ref/roll rule, written here: z = x × (ref × x),
    y = z × x, then the roll), the tip load moved to each section with
    vectors — S = P, S_m = (L - x) e_x × P + M in member axes — and read as
    N = S_x, Vy = -S_y, Vz = -S_z, T = S_mx, My = -S_my, Mz = S_mz."""
    load = (1.2, -2.5, 0.8, 0.6, -0.9, 1.4)
    fr, r = _cantilever(end, load, ref, roll)
    e = np.asarray(end, float)
    Lm = float(np.linalg.norm(e))
    ex = e / Lm
    rv = np.asarray(ref if ref is not None else ((1.0, 0.0, 0.0) if abs(ex[2]) > 0.999
                                                 else (0.0, 0.0, 1.0)), float)
    z = np.cross(ex, np.cross(rv, ex))
    z /= np.linalg.norm(z)
    y = np.cross(z, ex)
    y, z = math.cos(roll) * y + math.sin(roll) * z, -math.sin(roll) * y + math.cos(roll) * z
    R = np.array([ex, y, z])
    P, M = R @ np.array(load[:3]), R @ np.array(load[3:])
    x, *got = r.diagram("M", 11)
    for k, xs in enumerate(x):
        S, Sm = P, np.cross([Lm - xs, 0.0, 0.0], P) + M
        want = [S[0], -S[1], -S[2], Sm[0], -Sm[1], Sm[2]]
        np.testing.assert_allclose([g[k] for g in got], want, rtol=0, atol=1e-11)


def _simply_supported(w, axis, along=(1.0, 0.0, 0.0), axes="global"):
    """A member of length L on a pin (and its twist held) at A and a roller
    at B, a uniform load ``w`` along global ``axis`` (or member axes)."""
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", *(L * np.asarray(along, float)))
    fr.add_member("A", "B", E, A, IY, IZ, G=G, J=J, name="M")
    fr.add_support("A", fix=("ux", "uy", "uz", "rx"))
    fr.add_support("B", fix=("uy", "uz") if along[0] else ("ux", "uz"))
    load = {"wx": 0.0, "wy": 0.0, "wz": 0.0}
    load["w" + axis] = w
    fr.add_distributed_load("M", **load, axes=axes)
    r = fr.solve()
    assert r.ok, r.message
    return r


@pytest.mark.parametrize("axis", ["y", "z"])
def test_a_simply_supported_member_under_a_uniform_load_across_each_axis(axis):
    """w = 6 kN/m against the local axis (-y, or -z: down): the member sags
    away from it, the fibre on the axis' side is compressed, M = w x (L -
    x)/2 > 0 with wL²/8 = 12 kN·m at midspan; V = dM/dx = w (L/2 - x);
    the deflection 5wL⁴/384EI at midspan; nothing about the other axis."""
    w = 6.0
    r = _simply_supported(-w, axis)
    M, V, other_M, other_V = ("Mz", "Vy", "My", "Vz") if axis == "y" else ("My", "Vz", "Mz",
                                                                           "Vy")
    I_ = IZ if axis == "y" else IY
    x, *qs = r.diagram("M", 41)
    got = dict(zip(("N", "Vy", "Vz", "T", "My", "Mz"), qs))
    np.testing.assert_allclose(got[M], w * x * (L - x) / 2, rtol=0, atol=1e-11)
    np.testing.assert_allclose(got[V], w * (L / 2 - x), rtol=0, atol=1e-11)
    for q in ("N", "T", other_M, other_V):
        np.testing.assert_allclose(got[q], 0.0, rtol=0, atol=1e-11, err_msg=q)
    ext = r.extremes("M")
    assert ext[M]["max"] == pytest.approx((w * L * L / 8, L / 2), rel=1e-12)
    deflection = "v" if axis == "y" else "w"
    assert ext[deflection]["min"] == pytest.approx((-5 * w * L ** 4 / (384 * E * I_), L / 2),
                                                   rel=1e-12)
    assert r.end_forces("M")["i"][V] == pytest.approx(w * L / 2, rel=1e-12)


def test_the_largest_moment_between_samples_is_found():
    """The extremes add the stationary points of the parabola: a propped
    cantilever's span moment 9wL²/128 at x = 5L/8 (clamp at A, roller at B),
    which no evenly spaced sample of 201 hits."""
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", L, 0.0, 0.0)
    fr.add_member("A", "B", E, A, IY, IZ, G=G, J=J, name="M")
    fr.add_support("A")
    fr.add_support("B", fix=("uy", "uz"))
    w = 7.0
    fr.add_distributed_load("M", wz=-w)
    ext = fr.solve().extremes("M")
    # the span: sagging, 9wL²/128 at 5L/8 from the clamp's far end (x from A: 5L/8)
    assert ext["My"]["max"] == pytest.approx((9 * w * L * L / 128, 5 * L / 8), rel=1e-12)
    assert ext["My"]["min"] == pytest.approx((-w * L * L / 8, 0.0), rel=1e-12)


def test_a_load_in_member_axes_on_an_inclined_member():
    """A member from (0,0,0) to (3,0,4) simply supported, q = -5 kN/m along
    its local z (member axes), pinned at both ends: My = q x (L - x)/2, the
    member's length 5 m — the same numbers as a horizontal member."""
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 3.0, 0.0, 4.0)
    fr.add_member("A", "B", E, A, IY, IZ, G=G, J=J, name="M")
    fr.add_support("A", fix=("ux", "uy", "uz", "rx"))
    fr.add_support("B", fix=("ux", "uy", "uz"))    # a pin: no axial force in linear theory
    fr.add_distributed_load("M", wz=-5.0, axes="member")
    r = fr.solve()
    x, N, Vy, Vz, T, My, Mz = r.diagram("M", 21)
    np.testing.assert_allclose(My, 5.0 * x * (5.0 - x) / 2, rtol=0, atol=1e-10)
    np.testing.assert_allclose(Mz, 0.0, rtol=0, atol=1e-10)


def test_misuse_of_the_diagram_methods_is_named():
    _, r = _cantilever((L, 0.0, 0.0), (0.0, 1.0, 0.0, 0.0, 0.0, 0.0))
    with pytest.raises(InvalidOptionError, match="not the quantity 'My'"):
        r.diagram("M", "My")
    with pytest.raises(InvalidProblemError, match="no member named 'Q'"):
        r.extremes("Q")
    with pytest.raises(InvalidOptionError, match="integer >= 2"):
        r.diagram("M", 1)
    with pytest.raises(InvalidOptionError, match="a member's name"):
        r.end_forces(3)
