"""A worked raft: a 16 m x 12 m concrete raft under twelve columns on
tensionless soil, with dead, live and wind cases; the wind's overturning
couple unloads the windward columns and, combined with the least dead load,
lifts a side of the raft (examples/raft.py prints and draws it); and the
plates part of ``qpcontact demo``.

Units: kN, m.
"""

from __future__ import annotations

from .model import Raft

__all__ = ["raft_example", "windward_raft", "COMBINATIONS", "demo"]

#: the soil under :func:`windward_raft`, kN/m³ (medium dense sand)
WINDWARD_K = 2.0e4

#: design combinations (EN 1990's STR set, wind both ways)
COMBINATIONS = {
    "1.35D+1.5L": {"D": 1.35, "L": 1.5},
    "1.35D+1.5L+0.9W": {"D": 1.35, "L": 1.5, "W": 0.9},
    "1.0D+1.5W": {"D": 1.0, "W": 1.5},
    "1.0D-1.5W": {"D": 1.0, "W": -1.5},
}


def _certificate(r) -> str:
    """A result's certificate in a table cell: its error and route, or why
    it is not certified (the whole message)."""
    from rich.markup import escape

    return f"{r.error:.1e} ({r.method})" if r.ok else escape(r.message)


def windward_raft(cells: int, floor: bool = False) -> Raft:
    """A square raft of 0.5 m cells per side (kN, m): 0.5 m thick on
    tensionless soil k = WINDWARD_K (``floor``: on a rigid floor instead),
    self weight and 5 kN/m² on it, a 4 x 4 grid of columns carrying 6 kN/m²
    of the raft's area each, and wind pulling the windward row up by
    9 kN/m² each: the windward strip lifts (17 % of the area at 20 x 20
    cells on soil, 43 % on the floor), at every size — the raft of
    ``benchmarks/scale.py --raft`` and docs/plates.md's cost table."""
    side = 0.5 * cells
    raft = Raft(side, side, thickness=0.5, E=30e6, nu=0.2, cells=(cells, cells))
    if floor:
        raft.add_rigid_floor()
    else:
        raft.add_soil(WINDWARD_K)
    raft.add_self_weight(25.0)
    raft.add_area_load(5.0)
    grid = [side * (0.5 + k) / 4 for k in range(4)]
    for x in grid:
        for y in grid:
            raft.add_point_load(x, y, side ** 2 * (6.0 - (9.0 if x == grid[0] else 0.0)))
    return raft


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


def demo(console) -> int:
    """The plates part of ``qpcontact demo``: a raft on tensionless soil
    under a point load against Westergaard's w = P/(8√(kD)), and a stiff
    strip loaded beyond its kern against the triangular pressure block of
    statics; then the worked raft's wind combinations.  Returns the number of
    failed checks."""
    import numpy as np
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    failed = 0
    table = Table(title="Rafts on tensionless soil (MITC4 plates): two closed forms",
                  box=box.SIMPLE_HEAD, title_justify="left", pad_edge=False)
    for col in ("case", "ours", "closed form", "ratio", "certificate"):
        table.add_column(escape(col), justify="left" if col in ("case", "certificate") else "right",
                         no_wrap=col != "certificate", min_width=len(col))
    # Westergaard: a raft 10 elastic lengths wide, a pressure keeping the far ring pressed
    raft = Raft(10.0, 10.0, thickness=0.02, E=1e7, nu=0.2, cells=(40, 40))
    k = raft.D
    raft.add_soil(k)
    raft.add_point_load(5.0, 5.0, 1.0, case="P")
    raft.add_area_load(0.0125, case="q")
    r = raft.solve()
    w = r.w[r.mesh.nearest_node(5.0, 5.0)] - 0.0125 / k
    ref = 1.0 / (8 * np.sqrt(k * raft.D))
    failed += int(not r.ok or abs(w / ref - 1) > 0.02)
    table.add_row("point load P on a raft 10 λ wide: w under P", f"{w:.5g}", f"{ref:.5g}",
                  f"{w / ref:.4f}", _certificate(r))
    # a stiff strip B = 4 m, a line load at e = 1 m > B/6
    B, L, P, e = 4.0, 1.0, 100.0, 1.0
    strip = Raft(B, L, thickness=2.0, E=1e9, nu=0.0, cells=(80, 2))
    strip.add_soil(1e3)
    strip.add_patch_load(B / 2 + e - 0.025, 0.0, B / 2 + e + 0.025, L, P / 0.05)
    s = strip.solve()
    peak = s.pressure[np.isclose(s.mesh.nodes[:, 0], B)].mean()
    ref = 2 * P / (3 * L * (B / 2 - e))
    failed += int(not s.ok or abs(peak / ref - 1) > 0.01)
    table.add_row("stiff strip, load beyond the kern: peak pressure", f"{peak:.5g}", f"{ref:.5g}",
                  f"{peak / ref:.4f}", _certificate(s))
    console.print(table)
    for line in ("Westergaard / Hetényi: w = P / (8 √(k D)) under a point load on an infinite "
                 "plate on Winkler soil; statics: a rigid strip loaded at e > B/6 presses over "
                 "3 (B/2 − e) with a peak 2 P / (3 L (B/2 − e)).",):
        console.print(line, markup=False, highlight=False)
    res = raft_example(cells=(16, 12)).solve_combinations(COMBINATIONS)
    table = Table(title="A 16 m x 12 m raft under twelve columns, wind both ways",
                  box=box.SIMPLE_HEAD, title_justify="left", pad_edge=False)
    for col in ("combination", "ok", "uplift", "contact area [m²]", "max pressure [kN/m²]"):
        table.add_column(escape(col), justify="left" if col == "combination" else "right",
                         no_wrap=True, min_width=len(col))
    for name, r in res.items():
        failed += int(not r.ok)
        table.add_row(escape(name), str(r.ok), f"{100 * r.uplift_fraction:.1f} %",
                      f"{r.contact_area:.1f}", f"{r.pressure.max():.1f}")
    console.print(table)
    return failed
