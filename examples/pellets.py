"""Shot pellets in a tube pushed by a piston (the penalty paper's pellet example): a gas
force pulse drives the wad, pellets collide and travel as a column.

Prints momentum and contact figures and saves positions, velocities and
reactions against time (PNG).  SI units.

    .venv/bin/python examples/pellets.py                    # out/pellets.png
    .venv/bin/python examples/pellets.py --pellets 12 --method clarabel
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.mechanisms import pellet_scene  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pellets", type=int, default=8)
    ap.add_argument("--method", default="auto")
    ap.add_argument("--restitution", type=float, default=0.5)
    ap.add_argument("--out", default="out/pellets.png")
    args = ap.parse_args(argv)

    force, pulse = 400.0, 2e-3
    mech, h, steps, dt = pellet_scene(args.pellets, restitution=args.restitution,
                                      pressure_force=force, pulse=pulse)
    res = mech.simulate(h, steps, lookahead=dt, method=args.method)
    masses = np.diag(mech.inertia())
    p_end = masses @ res.v[-1]
    print(f"{args.pellets} pellets, {steps} steps of {1e6 * h:.0f} us; impulse of the gas force "
          f"{force * min(pulse, res.t[-1]):.4f} N s, momentum at the end {p_end:.4f} N s")
    print("velocities at the end [m/s]: " + ", ".join(f"{x:.1f}" for x in res.v[-1]))
    print("peak reactions [N]: " + ", ".join(f"{x:.0f}" for x in res.reactions.max(axis=0)))
    print(f"deepest penetration {max(0.0, -res.gaps.min()) * 1e6:.2f} um")
    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
    print("wrote", res.plot(args.out, f"{args.pellets} shot pellets pushed by a piston"))


if __name__ == "__main__":
    main()
