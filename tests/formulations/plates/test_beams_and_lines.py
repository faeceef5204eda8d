"""Line loads and edge beams: a line load across a strip is the two point
loads it lumps to; a simply supported strip stiffened by edge beams deflects
as one beam of EI = D b + 2 EI_beam (5 q L⁴ / 384 EI, by hand); the same
along y; a beam's torsion carries a twist."""

from __future__ import annotations

import numpy as np
import pytest

from formulations.plates import Raft
from qpcontact.core.errors import InvalidProblemError


def test_a_line_load_across_a_strip_is_its_two_point_loads():
    def strip():
        raft = Raft(12.0, 0.5, thickness=0.3, E=3e7, nu=0.0, cells=(60, 1))
        raft.add_soil(2e4)
        return raft

    a, b = strip(), strip()
    a.add_line_load(6.0, 0.0, 6.0, 0.5, 200.0)             # 200 kN/m over 0.5 m
    b.add_point_load(6.0, 0.0, 50.0)
    b.add_point_load(6.0, 0.5, 50.0)
    b.add_line_load(6.0, 0.0, 6.0, 0.5, 0.0)      # no load: the grid lines beside a wall, as a's
    ra, rb = a.solve(), b.solve()
    assert ra.ok and rb.ok and ra.lifted.any()
    assert np.max(np.abs(ra.w - rb.w)) <= 1e-12 * np.max(np.abs(rb.w))


def test_a_line_load_lumps_its_total_and_is_refused_across_an_opening():
    raft = Raft(6.0, 4.0, thickness=0.3, E=3e7, cells=(12, 8), openings=[(2.0, 1.0, 3.0, 2.0)])
    raft.add_soil(2e4)
    raft.add_line_load(0.5, 3.0, 5.5, 3.0, 30.0)             # a wall, 5 m
    r = raft.solve()
    assert r.ok and abs(r.support_force.sum() - 150.0) < 1e-8 * 150
    raft.add_line_load(0.5, 1.5, 5.5, 1.5, 30.0, case="X")
    with pytest.raises(InvalidProblemError, match="crosses an opening"):
        raft.solve({"X": 1.0})
    with pytest.raises(InvalidProblemError, match="along x or along y"):
        raft.add_line_load(0.0, 0.0, 1.0, 1.0, 5.0)


@pytest.mark.parametrize("along", ["x", "y"])
def test_edge_beams_stiffen_a_strip_as_one_beam(along):
    L, b, t, E = 10.0, 1.0, 0.1, 3e7
    EI_beam = 5.0e3
    q = 10.0
    cells = (100, 1) if along == "x" else (1, 100)
    size = (L, b) if along == "x" else (b, L)
    raft = Raft(*size, thickness=t, E=E, nu=0.0, cells=cells)
    if along == "x":
        ends = lambda x, y: np.isclose(x, 0) | np.isclose(x, L)         # noqa: E731
        raft.add_edge_beam(0.0, 0.0, L, 0.0, EI_beam)
        raft.add_edge_beam(L, b, 0.0, b, EI_beam)                        # drawn backwards
    else:
        ends = lambda x, y: np.isclose(y, 0) | np.isclose(y, L)         # noqa: E731
        raft.add_edge_beam(0.0, 0.0, 0.0, L, EI_beam)
        raft.add_edge_beam(b, L, b, 0.0, EI_beam)
    raft.add_support(ends, fix=("w",))
    raft.add_area_load(q)
    r = raft.solve()
    assert r.ok, r.message
    EI = E * t ** 3 / 12 * b + 2 * EI_beam
    ref = 5 * q * b * L ** 4 / (384 * EI)
    mid = r.mesh.nearest_node(*((L / 2, 0.0) if along == "x" else (0.0, L / 2)))
    assert abs(r.w[mid] / ref - 1) < 2e-3                   # plate's shear: (t/L)² terms
    # the beams carry most of it: without them the strip is 1 + 2 EI_beam / (D b) = 5 times softer
    assert 2 * EI_beam / (E * t ** 3 / 12 * b) > 3


def test_a_beam_s_torsion_carries_a_twist():
    """A cantilever strip clamped at x = 0, a torque applied as two opposite
    point loads at the free end's corners: the twist rate is T / (GJ + the
    plate's own), so a beam's GJ reduces the end rotation by that ratio."""
    def end_twist(GJ):
        raft = Raft(4.0, 0.4, thickness=0.05, E=3e7, nu=0.0, cells=(40, 1))
        raft.add_support(lambda x, y: np.isclose(x, 0), fix=("w", "theta_x", "theta_y"))
        if GJ:
            raft.add_edge_beam(0.0, 0.2, 4.0, 0.2, 1.0, GJ)
        raft.add_point_load(4.0, 0.0, -1.0)
        raft.add_point_load(4.0, 0.4, 1.0)
        r = raft.solve()
        assert r.ok
        tip = r.mesh.nearest_node(4.0, 0.4), r.mesh.nearest_node(4.0, 0.0)
        return (r.w[tip[0]] - r.w[tip[1]]) / 0.4

    free = end_twist(0.0)
    GJ = 50.0
    stiff = end_twist(GJ)
    # the plate's own torsional stiffness from the free run: twist = T L / GJ_plate
    T, L = 0.4, 4.0
    GJ_plate = T * L / free
    assert abs(stiff / (T * L / (GJ_plate + GJ)) - 1) < 0.02
