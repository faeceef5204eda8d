"""The measurement behind "nsgs-restarts" (issue 50, the 3-D compact piles):
NSGS + Newton from zero, then from random reactions within the cones, each
start followed by Newton, per start in CPU seconds (docs/dev-notes.md, "The
3-D compact piles by restarts", has the tables and what "auto" kept: Newton
after the first start only).

Why.  On the nearly closed piles (``sphere_pile(n, agitation=0.1,
polydispersity=0.005)``) NSGS does not settle: its iterate drifts (3e-4 of
the largest impulse a sweep on the 540-contact pile of seed 2) and whether
Newton certifies depends on the point it is handed.  From other starting
reactions the sweeps wander elsewhere, and some of those points Newton
certifies.

Each start: "nsgs-newton" from r0 to its own stop (the tolerance, 50 checks
without a better point, or its time limit), then, if not certified,
semismooth "newton" from its best point.  Start 0 is zero (nsgs-newton's own
start).  Start k >= 1 (``--starts`` "rand"): r_N uniform in [0, s] per
contact, each tangential component uniform in [−0.3 s, 0.3 s], projected onto
the cone, s (N·s) the largest impulse component of start 0's answer, the
generator seeded by k − 1 (the method, qpcontact/solvers/friction/restarts.py,
seeds start k by k); ``--starts pert``: start 0's answer times factors
uniform in [0, 2] per component, projected (a control: a start near the
stalled point).  The certificate (``qpcontact.solve``'s, at 1e-6) judges
every answer.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/dense3d_restarts.py --n 500 --seeds 0-9
    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/dense3d_restarts.py --n 1000 --seeds 0-2
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import qpcontact
from qpcontact.cases.piles import sphere_pile
from qpcontact.core.friction_problem import project_cone

COMPACT = {"agitation": 0.1, "polydispersity": 0.005}


def start_point(problem, first_r, kind: str, k: int) -> np.ndarray:
    """Start k >= 1 (module docstring)."""
    rng = np.random.default_rng(k - 1)
    m = problem.dim * problem.n_contacts
    if kind == "pert":
        r0 = first_r * rng.uniform(0.0, 2.0, m)
    else:
        scale = float(np.abs(first_r).max())
        r0 = rng.uniform(0.0, 1.0, m) * scale * np.tile([1.0, 0.3, 0.3], problem.n_contacts)
        r0 *= np.where(np.arange(m) % 3 == 0, 1.0, np.sign(rng.standard_normal(m)))
    return project_cone(r0, problem.mu, problem.dim)


def one_start(problem, r0, tol, newton_limit):
    """nsgs-newton from r0, then Newton from its best point; (the text of
    the row, certified, CPU seconds)."""
    t = time.process_time()
    sol = qpcontact.solve(problem, "nsgs-newton", accuracy=tol, time_limit=60, r0=r0)
    text = f"{sol.error:.0e}"
    ok = sol.ok
    if not ok:
        pol = qpcontact.solve(problem, "newton", accuracy=tol, r0=sol.r, time_limit=newton_limit)
        text += f" → {pol.error:.0e}"
        ok = pol.ok
    return text + (" ✓" if ok else ""), ok, time.process_time() - t


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=500, help="contacts asked of sphere_pile")
    ap.add_argument("--seeds", default="0-9")
    ap.add_argument("--count", type=int, default=4, help="starts after the first")
    ap.add_argument("--starts", choices=("rand", "pert"), default="rand")
    ap.add_argument("--newton-limit", type=float, default=3.0, help="Newton's wall limit (s)")
    ap.add_argument("--tol", type=float, default=1e-6)
    args = ap.parse_args(argv)
    a, _, b = args.seeds.partition("-")
    qpcontact.solve(sphere_pile(100).problem, "nsgs-newton")      # compiled kernels loaded
    print("| seed | contacts | start 0 | " + " | ".join(f"start {k}" for k in
                                                         range(1, args.count + 1)) + " |")
    for seed in range(int(a), int(b or a) + 1):
        p = sphere_pile(args.n, seed=seed, **COMPACT).problem
        first = qpcontact.solve(p, "nsgs-newton", accuracy=args.tol, time_limit=60)
        cells = []
        for k in range(args.count + 1):
            r0 = None if k == 0 else start_point(p, first.r, args.starts, k)
            text, _, cpu = one_start(p, r0, args.tol, args.newton_limit)
            cells.append(f"{text} ({cpu:.1f} s)")
        print(f"| {seed} | {p.n_contacts} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
