"""A worked raft: a 16 m x 12 m concrete raft under twelve columns on
tensionless soil, with dead, live and wind cases; the wind's overturning
couple unloads the windward columns and, combined with the least dead load,
lifts a corner of the raft (examples/raft.py prints and draws it).

Units: kN, m.
"""

from __future__ import annotations

from .model import Raft

__all__ = ["raft_example", "COMBINATIONS"]

#: design combinations (EN 1990's STR set, wind both ways)
COMBINATIONS = {
    "1.35D+1.5L": {"D": 1.35, "L": 1.5},
    "1.35D+1.5L+0.9W": {"D": 1.35, "L": 1.5, "W": 0.9},
    "1.0D+1.5W": {"D": 1.0, "W": 1.5},
    "1.0D-1.5W": {"D": 1.0, "W": -1.5},
}


def raft_example(cells=(32, 24)) -> Raft:
    """The raft of the module docstring: t = 0.6 m, C30/37 (E = 30 GPa),
    k = 20 MN/m³ (medium dense sand), 0.4 m x 0.4 m columns on a 5 m x 4 m
    grid 1 m from the edges, a 2 m x 3 m stair opening."""
    raft = Raft(16.0, 12.0, thickness=0.6, E=30e6, nu=0.2, cells=cells,
                openings=[(7.0, 5.0, 9.0, 8.0)], units=("kN", "m"))
    raft.add_soil(2.0e4)                                 # kN/m³
    raft.add_self_weight(25.0, case="D")                 # kN/m³
    raft.add_area_load(5.0, case="D")                    # floor finishes and a slab on grade, kN/m²
    raft.add_area_load(3.0, case="L")                    # imposed load on the ground floor, kN/m²
    xs, ys = (1.0, 5.5, 10.5, 15.0), (1.0, 6.0, 11.0)
    for i, x in enumerate(xs):
        for j, y in enumerate(ys):
            inner = 0 < i < len(xs) - 1 and 0 < j < len(ys) - 1
            raft.add_column(x, y, 900.0 if inner else 500.0, size=(0.4, 0.4), case="D")
            raft.add_column(x, y, 450.0 if inner else 250.0, size=(0.4, 0.4), case="L")
            # wind along x: an overturning couple taken by the columns' axial forces
            # (windward x = 1 pulled up, leeward x = 15 pushed down)
            lever = (x - 8.0) / 7.0
            raft.add_column(x, y, 600.0 * lever, size=(0.4, 0.4), case="W")
    return raft
