"""A 10-storey concrete space frame standing on 16 frictional pads (the
increasing-load method of Osipova, Popov and Lovtsov in three dimensions):
dead load D, then wind W from 30° growing
until the tower can no longer stand.

The tower is :func:`formulations.frames.space.space_tower.space_tower`: 3 x 3
bays of 6 m, storeys of 3.5 m, columns 0.7 x 0.7 m, beams 0.4 x 0.7 m, each
column pinned on a rigid pad with friction 0.5 on Coulomb's circle (the
default model; ``cone="inscribed"`` or ``"circumscribed"`` for a polygon,
faceted in 8).  Units kN, m.  Solves 1.0 D + 1.0 W (every pad sticks under the design
wind), then traces D + p W from p = 0: the windward pads slip and lift off,
the rest slip one after another, and the trace ends with the proof that no
equilibrium exists beyond its last load (the tower slides away).  Saves the
state just before the collapse (an isometric drawing) and the sway of the
top against p (PNG).

    .venv/bin/python examples/space_frame.py          # plots in out/space_frame/
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.frames import LargeDisplacementWarning  # noqa: E402
from formulations.frames.space.space_tower import node, space_tower  # noqa: E402


def forces(res) -> str:
    lines = [f"{'pad':>8} {'state':>10} {'X_n':>9} {'|X_t|':>8} {'Fx':>8} {'Fy':>8}"]
    for name, (fx, fy, fz) in res.support_reactions.items():
        s = res.supports[name]
        lines.append(f"{name:>8} {s.state:>10} {s.normal:9.1f} {(fx * fx + fy * fy) ** 0.5:8.1f} "
                     f"{fx:8.1f} {fy:8.1f}")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--storeys", type=int, default=10)
    ap.add_argument("--out", default="out/space_frame")
    ap.add_argument("--no-plot", action="store_true")
    ap.add_argument("--cone", default="circular", choices=("circular", "inscribed",
                                                          "circumscribed"),
                    help="the pads' friction: Coulomb's circle (default) or an octagon "
                         "inside or around it")
    args = ap.parse_args(argv)

    fr = space_tower(args.storeys, cone=args.cone)
    top = node(args.storeys, 0, 0)
    res = fr.solve(combination={"D": 1.0, "W": 1.0})
    weight = sum(s.normal for s in res.supports.values())
    print(f"1.0 D + 1.0 W: {res.message}")
    print(f"  pads carry {weight:.0f} kN; the top moves {res.displacements[top][0] * 1e3:.1f} mm "
          f"along x, {res.displacements[top][1] * 1e3:.1f} mm along y")
    print(forces(res))

    # near the collapse the frame sways beyond small-displacement theory; the
    # trace's message says so once, for its last state
    warnings.simplefilter("ignore", LargeDisplacementWarning)
    tr = fr.trace(constant={"D": 1.0}, variable="W")
    print(f"\ntrace of 1.0 D + p W: ended {tr.ended}, ok={tr.ok}")
    for ev in tr.events:
        print(f"  p = {ev.p:8.4f}  {ev}")
    print(f"  {tr.message}")
    last = tr.states[-1]
    print(f"\njust before the collapse (p in {tr.intervals[-1][0]:.4g} .. {tr.p_end:.6g}):")
    print(forces(last))

    if args.no_plot:
        return
    os.makedirs(args.out, exist_ok=True)
    print("wrote", tr.plot(os.path.join(args.out, "space_trace.png"), node=top, dof="ux"))
    # 400 members under member and nodal loads: the loads would hide the frame
    print("wrote", last.plot(os.path.join(args.out, "space_state.png"), loads=False))


if __name__ == "__main__":
    main()
