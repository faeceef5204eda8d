"""Ramming cycle: a spring-driven bolt pushes a cartridge along the guide into
the chamber stop (the penalty paper's automatic-weapon subsystem), one penalty
QP per step.

Prints the contact events and saves positions, velocities and reactions
against time (PNG).  SI units.

    .venv/bin/python examples/ramming.py                    # out/ramming.png
    .venv/bin/python examples/ramming.py --method osqp --restitution 0.0
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.mechanisms import ramming_scene  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--method", default="auto", help="QP backend for the penalty QP")
    ap.add_argument("--restitution", type=float, default=0.3)
    ap.add_argument("--route", default="penalty", choices=("penalty", "lcp"))
    ap.add_argument("--out", default="out/ramming.png")
    args = ap.parse_args(argv)

    mech, h, steps, dt = ramming_scene(restitution=args.restitution)
    res = mech.simulate(h, steps, lookahead=dt, route=args.route, method=args.method)
    on = res.reactions > 1e-9 * max(res.reactions.max(), 1e-300)
    for k, c in enumerate(mech.contacts):
        starts = np.flatnonzero(on[1:, k] & ~on[:-1, k]) + 1
        ends = np.flatnonzero(~on[1:, k] & on[:-1, k]) + 1
        print(f"{c.name}: contact at t = " + ", ".join(f"{1e3 * res.t[i]:.2f}" for i in starts)
              + " ms; separation at t = " + (", ".join(f"{1e3 * res.t[i]:.2f}" for i in ends) or "-")
              + f" ms; peak reaction {res.reactions[:, k].max():.4g} N; "
              f"deepest penetration {max(0.0, -res.gaps[:, k].min()) * 1e6:.2f} um")
    if args.route == "penalty":
        print(f"penalty mu chosen: {np.nanmin(res.mu):.3g} .. {np.nanmax(res.mu):.3g} s^2")
    print(f"final: bolt at {1e3 * res.q[-1, 0]:.2f} mm, cartridge at {1e3 * res.q[-1, 1]:.2f} mm, "
          f"reactions {res.reactions[-1].round(3)} N")
    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
    print("wrote", res.plot(args.out, "Ramming: bolt pushes the cartridge into the chamber"))


if __name__ == "__main__":
    main()
