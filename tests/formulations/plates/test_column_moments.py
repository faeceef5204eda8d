"""The design moment under a column, against the infinite plate on Winkler
soil under a uniform square patch — an integral of its Fourier transform,
written here, independent of the element.

Mindlin's plate (bending stiffness D, shear stiffness κGt) on soil of
modulus k under a pressure p(x, y): the Marcus moment ℳ = (mx + my)/(1 + ν)
obeys ∇²ℳ = −(p − k w) and, transformed (wave vector α),
D α⁴ W = (1 + c α²)(P̂ − k W) with c = D/(κ G t), so

    ℳ̂ = P̂ D α² / (D α⁴ + k (1 + c α²)),
    P̂ = P sinc(αx a/2) sinc(αy a/2)      (a patch a x a of total P).

Under the patch's centre mx = my = (1 + ν) ℳ(0)/2 by symmetry, ℳ(0) the
integral of ℳ̂ over the plane / 4π².  The same integral for a disc of
radius b (P̂ = P 2 J1(αb)/(αb), Kirchhoff: c = 0) gives Westergaard's
interior moment (1 + ν) P/(4π) (ln(2ℓ/b) + ½ − γ), ℓ = (D/k)^¼, for small
b: checked below, so the integral is checked by a closed form before it
judges the raft.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate, special

from formulations.plates import Raft

E, NU, T, K, P = 3.0e7, 0.2, 0.6, 2.0e4, 1000.0      # kN, m: a 0.6 m concrete raft on sand


def _stiffnesses():
    D = E * T ** 3 / (12 * (1 - NU ** 2))
    G = E / (2 * (1 + NU))
    return D, D / (5 / 6 * G * T)


def _marcus_integral(transform, D, c, size):
    """∫ ℳ̂ / (4π²) over the plane, the load's transform averaged over the
    angle by ``transform(α)``; intervals on a log scale from 1e-3/ℓ to
    4000/size (the integrand's tail beyond is below 1e-6 of the whole)."""
    def integrand(al):
        return transform(al) * D * al ** 3 / (D * al ** 4 + K * (1 + c * al ** 2))

    ell = (D / K) ** 0.25
    edges = np.concatenate([[0.0], np.geomspace(1e-3 / ell, 4000 / size, 60)])
    total = sum(integrate.quad(integrand, lo, hi, limit=100)[0]
                for lo, hi in zip(edges[:-1], edges[1:]))
    return P * total / (4 * np.pi ** 2)


def square_patch_moment(a, D, c):
    """mx = my under the centre of an a x a patch of total P [kN·m/m]."""
    x, wx = np.polynomial.legendre.leggauss(48)
    phi, wphi = (x + 1) * np.pi / 4, wx * np.pi / 4          # a quarter turn, x 4 by symmetry
    cos, sin = np.cos(phi), np.sin(phi)

    def around(al):
        s = np.sinc(al * cos * a / (2 * np.pi)) * np.sinc(al * sin * a / (2 * np.pi))
        return 4 * (wphi @ s)

    return (1 + NU) / 2 * _marcus_integral(around, D, c, a)


def disc_moment(b, D):
    """The same for a disc of radius b on a Kirchhoff plate (c = 0)."""
    def around(al):
        return 2 * np.pi * (2 * special.j1(al * b) / (al * b) if al > 0 else 1.0)

    return (1 + NU) / 2 * _marcus_integral(around, D, 0.0, b)


def test_the_reference_integral_gives_westergaards_interior_moment():
    D, _ = _stiffnesses()
    ell = (D / K) ** 0.25
    for b in (0.05, 0.1):
        west = (1 + NU) * P / (4 * np.pi) * (np.log(2 * ell / b) + 0.5 - np.euler_gamma)
        assert disc_moment(b, D) == pytest.approx(west, rel=2e-3)


@pytest.mark.parametrize("a", [0.4, 0.8])
def test_the_moment_under_a_column_converges_to_the_infinite_plates(a):
    """A 30 m raft (13 ℓ, ℓ = 2.30 m) on 0.5 m cells, a column a x a off the
    grid lines, P = 1000 kN, self-weight keeping every node pressed: the
    largest mx and my are under the column, 0.97–1.0 of the infinite
    plate's (measured 0.978 and 0.979; 1.0 only as the cells shrink: 0.989
    on 0.25 m cells).  Before the column's section was meshed finer the
    column was one element, and the design moment 0.777 (a = 0.4) and
    0.830 (a = 0.8) of the true one."""
    D, c = _stiffnesses()
    ref = square_patch_moment(a, D, c)
    side = 30.0
    raft = Raft(side, side, thickness=T, E=E, nu=NU, cells=(60, 60))
    raft.add_soil(K)
    raft.add_self_weight(25.0)
    x0 = side / 2 + 0.13
    raft.add_column(x0, x0, P, size=(a, a))
    r = raft.solve()
    assert r.ok and not r.lifted.any(), r.message
    ext = r.extremes()
    for q in ("mx", "my"):
        value, x, y = ext[q]["max"]
        assert 0.97 * ref <= value <= 1.0 * ref, (q, value / ref)
        assert max(abs(x - x0), abs(y - x0)) < a / 2
    # the tables say it is the mesh's value, from below
    assert r.notes()["mx"]["max"].startswith("under a column: the mesh's value, from below")
    assert r.notes()["qx"]["max"].startswith("in a column: a shear peaks on its face")
