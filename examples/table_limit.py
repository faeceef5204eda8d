"""How much torque until a table on a frictional floor turns, and what are
the forces just before?  A 2.0 x 1.2 m table 0.8 m high on four steel legs
under a deck 100 times stiffer, rigid feet on a floor with f = 0.3, 40 kN
at the centre, twisted by p kN·m about the vertical through its centre.

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
from formulations.frames import SpaceFrame  # noqa: E402

LEG = dict(E=2e8, G=8e7, A=1e-3, Iy=1e-6, Iz=1e-6, J=2e-6)


def table(ratio=100.0, friction=0.3, weight=40.0, a=2.0, b=1.2, h=0.8, cone="circular"):
    fr = SpaceFrame(units=("kN", "m"), cone=cone)
    fr.add_node("C", a / 2, b / 2, h)
    for k, (x, y) in enumerate([(0, 0), (a, 0), (a, b), (0, b)]):
        fr.add_node(f"F{k}", x, y, 0.0)
        fr.add_node(f"T{k}", x, y, h)
        fr.add_member(f"F{k}", f"T{k}", **LEG)
        fr.add_contact(f"F{k}", normal=(0, 0, 1), friction=friction)
    deck = {k: v * (ratio if k not in ("E", "G") else 1.0) for k, v in LEG.items()}
    for k in range(4):
        fr.add_member(f"T{k}", f"T{(k + 1) % 4}", **deck)
        fr.add_member("C", f"T{k}", **deck)
    fr.add_load("C", fz=-weight)
    fr.add_load("C", mz=1.0, case="variable")
    return fr


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plot", default="out/table_limit/trace.png")
    ap.add_argument("--design", type=float, default=10.0, help="design torque [kN·m]")
    args = ap.parse_args(argv)
    fr = table()
    tr = fr.trace()
    hand = 0.3 * 40.0 * np.hypot(2.0, 1.2) / 2
    print(f"ended: {tr.ended}")
    for ev in tr.events:
        print(f"  p in [{ev.bracket[0]:.8g}, {ev.bracket[1]:.8g}]: {ev}")
    lo, hi = tr.limit
    print(f"limit: [{lo:.10g}, {hi:.10g}] kN·m (hand: f W r = {hand:.10g})")
    print(f"safety factor against {args.design:g} kN·m: {tr.safety_factor(args.design)}")
    print(tr.message)
    os.makedirs(os.path.dirname(os.path.abspath(args.plot)), exist_ok=True)
    print("drawn:", tr.plot(args.plot, "C", "rz"))


if __name__ == "__main__":
    main()
