"""Where a 2-D drum step's CPU time goes, size by size: wrapped timers and the
solver's own counts, on benchmarks/drum.py's beds.

For each --logs size: the bed settled by benchmarks/drum.py (read from its
cache, out/bench/drum2d/, or settled and kept there; --settle steps), turned
for --warmup untimed steps, then --steps steps timed.  Each piece is timed
by a wrapper around the function that does it (CPU time, time.process_time;
cProfile's overhead doubled the Python-heavy pieces), so the pieces nest:
the step = contact detection + the problem's assembly + the solve + the
peak forces' cluster runs + the books; the solve = NSGS's sweeps + Newton's
tries (their LUs, Jacobians, checks) + the error checks between chunks.
Beside the times, per step: sweeps, Newton tries and steps, SuperLU
factorizations with their size and fill (nnz of L + U).  Last, each piece's time and count at the
largest size over the smallest, against the ratio of contacts.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/drum2d_split.py \\
        --logs 500,2000 --settle 150 --warmup 5 --steps 12

(2 000 logs: about 10 s once the bed is cached; settling it, ~10 minutes.)
docs/dev-notes.md, "The drum's step ... fourth round", has its output.

With --scene FILE the scene's own run instead (from its start state, as
`qpcontact simulate` runs it, without the results file), split by windows
of --window steps, --scene-steps of them (default: the whole run; the
500-log example's revolution takes ~2 min of CPU):

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/drum2d_split.py \\
        --scene examples/scenes/drum2d_500.toml

docs/dev-notes.md, "The revolution's CPU", has its output.
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, ROOT)
import formulations.drum2d.impact_kernel as impact_kernel  # noqa: E402
import formulations.drum2d.stepper as stepper  # noqa: E402
import qpcontact.solvers.friction._newton_kernels as newton_kernels  # noqa: E402
import qpcontact.solvers.friction.hybrid as hybrid  # noqa: E402
import qpcontact.solvers.friction.nsgs as nsgs  # noqa: E402
from benchmarks.drum import (EFFECTS_2D, H2D, RESTITUTION, drum2d_shell,  # noqa: E402
                             settled_bed)
from formulations.drum2d import Drum2D  # noqa: E402

#: (module or class, function, label): the pieces timed, outermost first
PIECES = (
    (stepper, "find_contacts", "contact detection"),
    (stepper.Drum2D, "_assemble", "assembly (W, q)"),
    (stepper, "solve", "solve"),
    (nsgs.NSGS, "sweep", "  NSGS sweeps"),
    (hybrid, "minimum_norm_newton", "  Newton tries"),
    (spla, "splu", "    SuperLU"),
    (hybrid, "natural_map_jacobian", "    Jacobians"),
    (newton_kernels, "closed_system_2d", "    F and the closed contacts' system (2-D kernel)"),
    (hybrid, "certified_error", "  error checks"),
    (stepper, "step_forces", "peak forces"),
    (impact_kernel, "cluster_forces", "  cluster runs (kernel)"),
)


class Split:
    """The wrapped pieces' CPU seconds and calls, and the counts kept."""

    def __init__(self):
        self.cpu, self.calls = collections.defaultdict(float), collections.Counter()
        self.counts = collections.defaultdict(list)
        for owner, name, label in PIECES:
            self._wrap(owner, name, label)

    def _wrap(self, owner, name, label):
        inner = getattr(owner, name)
        split = self

        def timed(*args, **kw):
            t = time.process_time()
            try:
                out = inner(*args, **kw)
            finally:
                split.cpu[label] += time.process_time() - t
                split.calls[label] += 1
            split.count(name, args, out)
            return out

        setattr(owner, name, timed)

    def count(self, name, args, out):
        c = self.counts
        if name == "splu":
            c["LU size"].append(out.shape[0])
            c["LU fill (nnz L + U)"].append(out.L.nnz + out.U.nnz)
        elif name == "solve":
            c["sweeps a step"].append(out.iterations or 0)
            c["Newton tries a step"].append(out.stats.get("newton_tries", 0))
            c["Newton steps a step"].append(out.stats.get("newton_steps", 0))

    def clear(self):
        self.cpu.clear()
        self.calls.clear()
        self.counts.clear()


def measure(n, args, split):
    """One run of --warmup + --steps steps from the settled bed, the split
    cleared after the warm-up (as benchmarks/drum.py times its steps: the
    warm start carried over)."""
    discs, _ = settled_bed(n, args.settle, args.cache)
    model = Drum2D(discs, drum2d_shell(), EFFECTS_2D, restitution=RESTITUTION)
    start = []

    def after(k, contacts, r):
        if k == args.warmup:
            split.clear()
            start.append(time.process_time())

    res = model.simulate(H2D, args.warmup + args.steps, keep_contacts=False, on_step=after)
    step = (time.process_time() - start[0]) / args.steps
    timed = slice(args.warmup, None)
    return dict(step=step, cpu={k: v / args.steps for k, v in split.cpu.items()},
                calls={k: v / args.steps for k, v in split.calls.items()},
                counts={k: np.asarray(v, float) for k, v in split.counts.items()},
                contacts=float(res.n_active[timed].mean()),
                certified=bool(res.certified[timed].all()),
                worst=float(res.certificate_error[timed].max()),
                fallbacks=int(res.fallback[timed].sum()))


def measure_scene(args, split):
    """The scene's run split by windows of --window steps: one row a window."""
    from formulations.drum2d.scene import scene_model
    from qpcontact.scenes.schema import load_scene

    scene = load_scene(args.scene)
    model, h, steps = scene_model(scene)
    steps = args.scene_steps or steps
    solver = scene.data["solver"]
    start = [time.process_time(), 0]
    print("| steps | ms a step | " + " | ".join(label.strip() for _, _, label in PIECES)
          + " | sweeps | LUs |\n" + "|---" * (len(PIECES) + 4) + "|")

    def after(k, contacts, r):
        if k % args.window and k != steps:
            return
        n = k - start[1]
        cpu = time.process_time() - start[0]
        cells = [f"{1e3 * split.cpu.get(label, 0.0) / n:.2f}" for _, _, label in PIECES]
        sweeps = np.mean(split.counts["sweeps a step"]) if split.counts["sweeps a step"] else 0
        print(f"| {start[1]}–{k} | {1e3 * cpu / n:.1f} | " + " | ".join(cells)
              + f" | {sweeps:.0f} | {len(split.counts['LU size']) / n:.1f} |", flush=True)
        split.clear()
        start[:] = [time.process_time(), k]

    t = time.process_time()
    res = model.simulate(h, steps, method=solver["method"], accuracy=solver["accuracy"],
                         keep_contacts=scene.data["output"]["contacts_every"], on_step=after)
    print(f"\n{args.scene}: {steps} steps, {time.process_time() - t:.1f} s of CPU in "
          f"simulate; every step certified: {bool(res.certified.all())} (worst "
          f"{res.certificate_error.max():.1e}, fallbacks {int(res.fallback.sum())}); "
          f"load {os.getloadavg()[0]:.1f}")


def report(n, m):
    print(f"\n{n} logs: {m['contacts']:.0f} contacts, {1e3 * m['step']:.1f} ms of CPU a step, "
          f"every step certified: {m['certified']} (worst {m['worst']:.1e}, fallbacks "
          f"{m['fallbacks']})")
    print("| piece | ms a step | calls a step |\n|---|---|---|")
    for _, _, label in PIECES:
        if label in m["cpu"]:
            print(f"| {label} | {1e3 * m['cpu'][label]:.2f} | {m['calls'][label]:.1f} |")
    print("\n| count | mean | median | max |\n|---|---|---|---|")
    for k, v in m["counts"].items():
        print(f"| {k} | {v.mean():.0f} | {np.median(v):.0f} | {v.max():.0f} |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--logs", default="500,2000")
    ap.add_argument("--settle", type=int, default=150)
    ap.add_argument("--warmup", type=int, default=5)
    ap.add_argument("--steps", type=int, default=12)
    ap.add_argument("--cache", default=os.path.join(ROOT, "out", "bench", "drum2d"))
    ap.add_argument("--scene", help="split this drum2d scene's run instead of the beds")
    ap.add_argument("--scene-steps", type=int, default=0, help="with --scene: steps (0: all)")
    ap.add_argument("--window", type=int, default=500, help="with --scene: steps a row")
    args = ap.parse_args(argv)
    if args.scene:
        measure_scene(args, Split())
        return
    sizes = [int(x) for x in args.logs.split(",")]
    split = Split()
    got = {}
    for n in sizes:
        got[n] = measure(n, args, split)
        report(n, got[n])
    if len(sizes) > 1:
        lo, hi = got[sizes[0]], got[sizes[-1]]
        print(f"\n{sizes[-1]} logs over {sizes[0]}: contacts × "
              f"{hi['contacts'] / lo['contacts']:.2f}, the step × {hi['step'] / lo['step']:.1f}")
        print("| piece | × time | × calls |\n|---|---|---|")
        for _, _, label in PIECES:
            if label in lo["cpu"] and label in hi["cpu"] and lo["cpu"][label] > 0:
                print(f"| {label} | {hi['cpu'][label] / lo['cpu'][label]:.1f} | "
                      f"{hi['calls'][label] / lo['calls'][label]:.1f} |")
        for k in lo["counts"]:
            if k in hi["counts"] and lo["counts"][k].mean() > 0:
                print(f"| {k} (mean) | {hi['counts'][k].mean() / lo['counts'][k].mean():.1f} | |")
    print(f"\n(OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}; "
          f"load {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
