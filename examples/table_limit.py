"""How much torque until a table on a frictional floor turns, and what are
the forces just before?  A 2.0 x 1.2 m table 0.8 m high on four steel legs
under a deck 100 times stiffer, rigid feet on a floor with f = 0.3, 40 kN
at the centre, twisted by p kN·m about the vertical through its centre
(formulations/frames/space/space_family.py's table).

On Coulomb's circle (the space frame's default) every pad ends at its full
friction f W/4 perpendicular to its radius r = √(a² + b²)/2: the table
turns at f W r = 13.9943 kN·m by hand.  The trace gives that limit as a
bracket [p_lo, p_hi] — p_lo a certified equilibrium, p_hi a rigid motion
checked in rational arithmetic — the loads at which pads start to slip,
and the safety factor against a design torque.  Units: kN, m.

    .venv/bin/python examples/table_limit.py
    .venv/bin/python examples/table_limit.py --plot docs/figures/frame_limit_circle.png
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.frames.space.space_family import table  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plot", default="out/table_limit/trace.png")
    ap.add_argument("--design", type=float, default=10.0, help="design torque [kN·m]")
    args = ap.parse_args(argv)
    fr = table(4, 100.0)          # 4 legs, the deck 100 times stiffer: Coulomb's circle
    tr = fr.trace(variable="twist")
    hand = 0.3 * 40.0 * np.hypot(2.0, 1.2) / 2
    print(f"ended: {tr.ended}")
    for ev in tr.events:
        print(f"  p in [{ev.bracket[0]:.12g}, {ev.bracket[1]:.12g}]: {ev}")
    lo, hi = tr.limit
    print(f"limit: [{lo:.10g}, {hi:.10g}] kN·m (hand: f W r = {hand:.10g})")
    print(f"safety factor against {args.design:g} kN·m: {tr.safety_factor(args.design)}")
    print(tr.message)
    os.makedirs(os.path.dirname(os.path.abspath(args.plot)), exist_ok=True)
    print("drawn:", tr.plot(args.plot, "C", "rz"))


if __name__ == "__main__":
    main()
