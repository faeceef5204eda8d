"""2-D drum stepping speed: the old route (each step's friction problem by
"auto", which picks Lemke on the faceted LCP up to 200 contacts) against the
warm-started route (NSGS + Newton from the previous step's impulses, matched
contact by contact, "auto" where that is not certified), in one run.

A bed of discs (4 m drum, 8 lifters, 0.15 rev/s, mu = 0.4, e = 0.2) is first
settled without friction, then both routes step the same state with friction,
rotation and damping at h = 2 ms.  Every step's problem is certified at
"high" by the same certificate; the table gives ms per step, steps/s,
certified contact-steps/s, the mean number of active contacts, the certified
fraction, the worst certificate and how often the warm route fell back.

    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 .venv/bin/python benchmarks/drum2d.py

Options: --discs 100,500  --steps 30  --settle 300  --routes auto,warm
"""

from __future__ import annotations

import argparse
import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.drum2d import Discs, Drum2D, Shell, hex_fill  # noqa: E402

R = 2.0
H = 2e-3
EFFECTS = ("friction", "rotation", "damping")


def settled_bed(n: int, settle: int, seed: int = 1) -> Drum2D:
    """n discs (0.25 m, or 0.12 m above 150 discs, ±20 %) settled for
    ``settle`` frictionless steps, then given friction, rotation, damping."""
    pos, dia = hex_fill(R, n, 0.25 if n <= 150 else 0.12, spread=0.2, seed=seed,
                        clearance=0.005)
    shell = Shell(R, omega=2 * np.pi * 0.15, lifter_angles=np.linspace(0, 2 * np.pi, 8,
                                                                        endpoint=False),
                  lifter_height=0.12, lifter_half_width=0.02)
    run = Drum2D(Discs(dia, pos), shell, ("damping",), restitution=0.2).simulate(
        H, settle, keep_contacts=False)
    p = run.positions[-1]
    # the scheme's drift along the curved shell (<= a micrometre here) put
    # back inside, so that the frictional model accepts the state
    reach = R * (1 - 1e-6) - dia / 2
    p = p * np.minimum(1.0, reach / np.maximum(np.hypot(*p.T), 1e-12))[:, None]
    discs = Discs(dia, p, velocities=run.velocities[-1], spins=run.spins[-1])
    return Drum2D(discs, shell, EFFECTS, restitution=0.2)


ROUTES = {"auto": dict(method="auto"), "warm": dict(warm_start="nsgs-newton")}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--discs", default="100,500")
    ap.add_argument("--steps", type=int, default=30)
    ap.add_argument("--settle", type=int, default=300)
    ap.add_argument("--routes", default="auto,warm")
    args = ap.parse_args(argv)
    print(f"{'discs':>6} {'route':>5} {'contacts':>8} {'ms/step':>9} {'steps/s':>8} "
          f"{'cert c-steps/s':>14} {'certified':>9} {'worst cert':>10} {'fallback':>8}  methods")
    for n in (int(x) for x in args.discs.split(",")):
        model = settled_bed(n, args.settle)
        for route in args.routes.split(","):
            start = time.perf_counter()
            res = model.simulate(H, args.steps, keep_contacts=False, **ROUTES[route])
            wall = time.perf_counter() - start
            used = {m: res.method.count(m) for m in sorted(set(res.method))}
            print(f"{n:>6} {route:>5} {res.n_active.mean():>8.1f} {1e3 * wall / args.steps:>9.1f} "
                  f"{args.steps / wall:>8.2f} "
                  f"{res.n_active[res.certified].sum() / wall:>14.0f} "
                  f"{res.certified.mean():>9.3f} {res.worst_certificate:>10.1e} "
                  f"{int(res.fallback.sum()):>8}  {used}", flush=True)


if __name__ == "__main__":
    main()
