"""A grade beam on compression-only soil supports under three load
combinations: each combination is solved as its own contact problem (which
supports lift off differs between them), then tables, an envelope and a
drawing per combination.

Run:  .venv/bin/python examples/grade_beam.py   (writes out/grade_beam/)
Units: kN, m.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from formulations.frames import Frame  # noqa: E402


def grade_beam() -> Frame:
    fr = Frame(units=("kN", "m"))
    xs = [0.0, 1.5, 3.0, 4.5, 6.0, 7.5, 9.0, 10.5, 12.0]
    for k, x in enumerate(xs):
        fr.add_node(f"S{k}", x, 0.0)
    # concrete 0.4 m x 0.8 m: E = 30 GPa
    E, A, I = 30e6, 0.32, 0.4 * 0.8 ** 3 / 12
    for k in range(len(xs) - 1):
        fr.add_member(f"S{k}", f"S{k + 1}", E, A, I, name=f"B{k + 1}")
    fr.add_self_weight("D", unit_weight=25.0)                     # kN/m³
    fr.add_support("S0", fix=("ux",))                              # horizontal restraint only
    for k in range(len(xs)):                                       # soil: elastic, compression only
        fr.add_contact(f"S{k}", normal=(0.0, 1.0), stiffness=6e4)  # kN/m per support
    # columns: dead and live loads, a wind couple that lifts the right end
    fr.add_load("S2", fy=-180.0, case="D")
    fr.add_load("S6", fy=-120.0, case="D")
    fr.add_load("S2", fy=-90.0, case="L")
    fr.add_load("S6", fy=-140.0, case="L")
    fr.add_point_load("B5", 0.75, fy=-60.0, case="L")              # a machine mid-span of B5
    fr.add_distributed_load("B1", wy=-10.0, wy2=0.0, case="L")     # a triangular surcharge
    fr.add_load("S6", fy=150.0, mz=-40.0, case="W")
    fr.add_load("S2", fy=-60.0, case="W")
    return fr


def main(out="out/grade_beam") -> int:
    fr = grade_beam()
    combos = {"1.4D": {"D": 1.4},
              "1.2D+1.6L": {"D": 1.2, "L": 1.6},
              "0.9D+1.6W": {"D": 0.9, "W": 1.6}}
    res = fr.solve_combinations(combos)
    out = Path(out)
    for name, r in res.items():
        lifted = [k for k, s in r.supports.items() if s.state == "separated"]
        print(f"{name:>10}: ok={r.ok}  lift off: {', '.join(lifted) or 'none'}  ({r.message})")
        if r.ok:
            print(f"            drawing: {r.plot(out / f'{name}.png')}")
    # the tables are rounded for reading already (docs/frames.md, "Tables")
    print("\nsupport reactions [kN] (Fy, one row per node) per combination:")
    for row in res.rows("reactions"):
        print(f"  {row['combination']:>10} {row['node']:>4} {row['Fy [kN]']:>9}  "
              f"({row['kinds']})")
    print("\nbending moment envelope [kN·m]:")
    for row in res.rows("envelope"):
        print(f"  {row['member']:>3}  max {row['M_max [kN·m]']:>9} at x = "
              f"{row['x(M_max) [m]']} ({row['combination(M_max)']})   "
              f"min {row['M_min [kN·m]']:>9} at x = {row['x(M_min) [m]']} "
              f"({row['combination(M_min)']})")
    for path in res.to_csv(out):
        print("wrote", path)
    return 0 if not res.failed else 1


if __name__ == "__main__":
    raise SystemExit(main())
