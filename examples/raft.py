"""A raft under twelve columns on tensionless soil, with wind combinations:
each combination is its own contact problem (the lifted zone differs), then
the uplift zone, the extremes, the envelope over the combinations, CSV
tables and one drawing per combination (soil pressure with the lift-off
line, mx contours).

Run:  .venv/bin/python examples/raft.py   (writes out/raft/)
Units: kN, m.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from formulations.plates.examples import COMBINATIONS, raft_example  # noqa: E402


def main(out="out/raft") -> int:
    raft = raft_example()
    res = raft.solve_combinations(COMBINATIONS)
    print(f"raft {raft.width} m x {raft.length} m, t = {raft.thickness} m, "
          f"{raft.mesh.elements.shape[0]} MITC4 elements, {raft.mesh.nodes.shape[0]} nodes\n")
    print(res.table("combinations"), "\n")
    for name, r in res.items():
        if not r.ok:
            print(f"{name}: NOT OK — {r.message}")
            continue
        lifted = r.mesh.nodes[r.lifted]
        zone = (f"x {lifted[:, 0].min():.2f}..{lifted[:, 0].max():.2f} m, "
                f"y {lifted[:, 1].min():.2f}..{lifted[:, 1].max():.2f} m" if len(lifted) else "none")
        print(f"{name}: uplift {100 * r.uplift_fraction:.1f} % of the soil area ({zone}); "
              f"contact area {r.contact_area:.2f} m²")
        r.plot(Path(out) / f"{name}.png")
    print("\nenvelope over the combinations that are ok:")
    print(res.table("envelope"))
    res.to_csv(out)
    for name, r in res.items():
        if r.ok:
            r.to_csv(Path(out) / name)
    return len(res.failed)


if __name__ == "__main__":
    sys.exit(main())
