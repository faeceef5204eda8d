"""Rafts against closed forms written here: a strip on tensionless Winkler
soil under a central load, lifting off (the finite beam on an elastic
foundation, Hetényi's functions, with the contact length found from
w(c) = 0), and a rigid raft with an opening under moments about both axes
(p = N/A + M_y x/I_y + M_x y/I_x from the section's own properties)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from formulations.plates import Raft


def tensionless_beam(EI, kb, P):
    """A free beam [force·length², force/length²] on soil that only pushes,
    a central load P, long enough to lift off: (c, w) — the contact reaches
    c either side of the load, w(x) [length] on 0 ≤ x ≤ c.

    In contact EI w'''' + kb w = 0, so w = Re/Im of cosh(zx) and sinh(zx),
    z = (1 + i) β, β = (kb / 4EI)^¼.  Beyond c the beam carries nothing and
    soil nothing: M = V = 0 at c, the overhang straight.  With w'(0) = 0
    (symmetry) and kb ∫₀ᶜ w = P/2 (the half's equilibrium) the four
    constants follow; c is where w(c) = 0."""
    beta = (kb / (4 * EI)) ** 0.25
    z = (1 + 1j) * beta

    def basis(x, n):                     # the n-th derivatives of the four functions at x
        even, odd = np.cosh(z * x), np.sinh(z * x)
        g, h = (even, odd) if n % 2 == 0 else (odd, even)
        g, h = z ** n * g, z ** n * h
        return [g.real, g.imag, h.real, h.imag]

    def constants(c):
        ig, ih = np.sinh(z * c) / z, (np.cosh(z * c) - 1) / z
        rows = [basis(0.0, 1), basis(c, 2), basis(c, 3),
                [kb * ig.real, kb * ig.imag, kb * ih.real, kb * ih.imag]]
        return np.linalg.solve(np.array(rows), [0.0, 0.0, 0.0, P / 2])

    def end(c):
        return float(np.dot(constants(c), basis(c, 0)))

    cs = np.linspace(0.5 / beta, 6 / beta, 400)
    vals = [end(c) for c in cs]
    i = next(i for i in range(cs.size - 1) if vals[i] > 0 >= vals[i + 1])
    c = brentq(end, cs[i], cs[i + 1], xtol=1e-12)
    a = constants(c)
    return c, lambda x: float(np.dot(a, basis(x, 0)))


@pytest.mark.parametrize("k, cells", [(2e4, 240), (5e4, 240)])
def test_a_strip_lifting_off_against_the_tensionless_beams_closed_form(k, cells):
    """A 12 m strip, 0.5 m wide, ν = 0, a central line load of 100 kN: a
    beam of EI = E b t³/12.  Thin (t = 0.03 m, E = 3e10 kN/m², EI as a
    0.3 m concrete strip's) so that Mindlin's shear does not add to the
    beam's deflection: the centre deflection within 1e-4 (measured 1e-5),
    the contact's end within one cell of c = 3.011 m (k = 2e4) and 2.394 m
    (5e4).  At t = 0.3 m, E = 3e7 the plate deflects 0.59 % more — its
    shear, which the beam leaves out."""
    length, width, t, E, P = 12.0, 0.5, 0.03, 3e10, 100.0
    c, w = tensionless_beam(E * width * t ** 3 / 12, k * width, P)
    raft = Raft(length, width, thickness=t, E=E, nu=0.0, cells=(cells, 1))
    raft.add_soil(k)
    raft.add_point_load(length / 2, 0.0, P / 2)
    raft.add_point_load(length / 2, width, P / 2)
    r = raft.solve()
    assert r.ok, r.message
    centre = r.w[r.mesh.nearest_node(length / 2, 0.0)]
    assert centre == pytest.approx(w(0.0), rel=1e-4)
    x = r.mesh.nodes[:, 0] - length / 2
    h = length / cells
    assert x[r.contact].max() <= c + 1e-9 and x[r.lifted & (x > 0)].min() >= c - h - 1e-9
    assert x[r.contact].max() > c - h and x[r.lifted & (x > 0)].min() < c + h


def test_a_rigid_raft_with_an_opening_under_moments_about_both_axes():
    """The worked raft's plan (16 m x 12 m, a 2 m x 3 m opening), 1000 times
    stiffer (E = 3e10, t = 2 m) on k = 1e4: nothing lifts and the soil
    pressure is the rigid raft's p = N/A + M_y (x − x̄)/I_y + M_x (y − ȳ)/I_x
    with A, x̄, ȳ, I_x, I_y of the rectangle less the opening (I_xy = 0: the
    opening is centred in x).  Twelve columns, wind across both axes.
    Measured within 4.9e-4 of the peak at 32 x 24 cells (1.5e-4 at 64 x 48;
    the reported peak 0.99955 and 0.99989 of the rigid raft's)."""
    raft = Raft(16.0, 12.0, thickness=2.0, E=3e10, nu=0.2, cells=(32, 24),
                openings=[(7.0, 5.0, 9.0, 8.0)])
    raft.add_soil(1e4)
    raft.add_area_load(55.0, case="D")                   # self-weight and finishes, kN/m²
    columns = []
    for x in (1.0, 5.5, 10.5, 15.0):
        for y in (1.0, 6.0, 11.0):
            dead, wind = 700.0, 200.0 * (x - 8.0) / 7.0 + 50.0 * (y - 6.0) / 5.0
            raft.add_column(x, y, dead, size=(0.4, 0.4), case="D")
            raft.add_column(x, y, wind, size=(0.4, 0.4), case="W")
            columns.append((x, y, dead, wind))
    A = 16 * 12 - 2 * 3
    xb, yb = 8.0, (16 * 12 * 6.0 - 2 * 3 * 6.5) / A
    Ix = 16 * 12 ** 3 / 12 + 16 * 12 * (6 - yb) ** 2 - (2 * 3 ** 3 / 12 + 2 * 3 * (6.5 - yb) ** 2)
    Iy = 12 * 16 ** 3 / 12 - 3 * 2 ** 3 / 12
    for factor in (1.5, -1.5):
        r = raft.solve({"D": 1.0, "W": factor})
        assert r.ok and not r.lifted.any(), r.message
        loads = [(x, y, d + factor * wd) for x, y, d, wd in columns]
        N = 55.0 * A + sum(p for _, _, p in loads)
        My = sum(p * (x - xb) for x, _, p in loads)
        Mx = sum(p * (y - yb) for _, y, p in loads)
        X = r.mesh.nodes
        p = N / A + My * (X[:, 0] - xb) / Iy + Mx * (X[:, 1] - yb) / Ix
        assert np.max(np.abs(r.pressure - p)) < 1e-3 * p.max()


def test_the_moment_under_a_wall_against_the_infinite_beams():
    """A wall (a line load P per unit length) across a long strip on soil:
    the beam on an elastic foundation's M0 = P/(4β), β = (k/4D)^¼ — a kink,
    the moment's peak.  60 m long (β L/2 = 9.3: infinite), thin (t = 0.06
    m, E = 3e10: Mindlin's shear left out, D as a 0.6 m concrete raft's),
    self-weight keeping it pressed (a uniform settlement, no moment), the
    wall off the nominal grid lines, on 0.5 m cells.  Measured 0.9875; the
    element centres were half a cell off the kink before the lines beside a
    wall: 0.889)."""
    t, E, k, P, L = 0.06, 3e10, 2e4, 200.0, 60.0
    raft = Raft(L, 1.0, thickness=t, E=E, nu=0.0, cells=(120, 1))
    raft.add_soil(k)
    raft.add_self_weight(25.0)
    x0 = L / 2 + 0.13
    raft.add_line_load(x0, 0.0, x0, 1.0, P)
    r = raft.solve()
    assert r.ok and not r.lifted.any(), r.message
    beta = (k / (4 * raft.D)) ** 0.25
    value, x, _ = r.extremes()["mx"]["max"]
    assert 0.98 * P / (4 * beta) <= value <= P / (4 * beta)
    assert abs(x - x0) < 0.05


def _rigid_raft(B, L, k, N, ex, ey, m=600):
    """A rigid B x L raft on soil that only pushes, loads N at (ex, ey) from
    its centre: w = a + b x + c y with ∫ k max(w, 0) dA = N and its moments
    N ex, N ey — three equations, the integrals by the midpoint rule on m x
    m cells, solved by fsolve.  Returns the plane (a, b, c) (about the
    centre)."""
    from scipy.optimize import fsolve

    xs = (np.arange(m) + 0.5) / m * B - B / 2
    ys = (np.arange(m) + 0.5) / m * L - L / 2
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    dA = B * L / m ** 2

    def balance(v):
        p = k * np.maximum(v[0] + v[1] * X + v[2] * Y, 0.0)
        return [p.sum() * dA / N - 1, (p * X).sum() * dA / N - ex, (p * Y).sum() * dA / N - ey]

    return fsolve(balance, [N / (k * B * L), 0.0, 0.0], xtol=1e-13)


def test_a_stiff_raft_lifting_at_a_corner_against_rigid_statics():
    """An 8 m x 6 m raft 2 m thick (E = 3e9: D/(k B⁴) = 51) on k = 1e4, 20
    kN/m² and a 1500 kN column at (7, 5): the resultant 1.08 m and 0.72 m
    off the centre, beyond the kern both ways — a corner lifts along a line
    across both axes.  Against the rigid raft's statics: the contact
    nodes are its pressed ones but for a cell's width along the line (2 of
    1280), the pressure k max(w, 0) within 1 % of the peak (measured 3.0e-3),
    the lifted fraction 0.3694 against 0.3721, the peak 0.9977 of it
    (64 cells a side: 1.0000)."""
    B, L, k = 8.0, 6.0, 1e4
    raft = Raft(B, L, thickness=2.0, E=3e9, nu=0.2, cells=(32, 24))
    raft.add_soil(k)
    raft.add_area_load(20.0)
    raft.add_column(7.0, 5.0, 1500.0, size=(0.4, 0.4))
    r = raft.solve()
    assert r.ok, r.message
    N = 20.0 * B * L + 1500.0
    a, b, c = _rigid_raft(B, L, k, N, 1500.0 * 3.0 / N, 1500.0 * 2.0 / N)
    X = r.mesh.nodes
    w = a + b * (X[:, 0] - B / 2) + c * (X[:, 1] - L / 2)
    p = k * np.maximum(w, 0.0)
    assert np.max(np.abs(r.pressure - p)) < 1e-2 * p.max()
    h = max(B / 32, L / 24)
    disagree = (w > 0) != r.contact
    slope = np.hypot(b, c)
    assert np.all(np.abs(w[disagree]) <= slope * h)          # within a cell of the line
    assert disagree.sum() <= 10 and r.lifted.sum() > 100
