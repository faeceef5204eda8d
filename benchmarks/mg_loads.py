"""The multilevel route against its floor, first load and next loads: the
obstacle rows of issue-51-type problems (membranes, plates) solved whole —
``solve(..., method, accuracy="high")`` — on a fresh LCP (the first load on
a matrix: mg-bpp builds its Galerkin products and packed levels) and on an
LCP sharing that LCP's structure with another load (a load combination:
what mg-bpp keeps of M alone is not built again), each the minimum CPU time
(``process_time``; the wall time's minimum printed beside) of ``--repeat`` solves, against one QDLDL LDLᵀ (its AMD
included) of the answer's own final free block measured in the same
process.  One BLAS thread.

Every row runs in its own process; with ``--against PATH`` (another
checkout, e.g. ``git worktree add ../base <commit>``) each row runs there
too, the two alternating which goes first, ``--rounds`` times, so that a
shared machine's load falls on both alike.  Prints a Markdown table (the
minimum over rounds per side) and whether the two sides' z agree to the
bit.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/mg_loads.py --rows membrane:100
    .venv/bin/python benchmarks/mg_loads.py --against ../base --rounds 2 \\
        --rows membrane:100,membrane:316,plate0.05:100,plate1:100 --methods mg-bpp,auto

Shapes: formulations.meshes.OBSTACLES and two held out of its choices
("ripple", "wedge": docs/dev-notes.md, round four), defined here; and,
held out from the stepped-obstacle rule (:func:`qpcontact.solvers.
pivoting.multigrid.layer_share`; docs/dev-notes.md, "a one-step shifted
start for stepped obstacles"), a single step, an oblique staircase, a
rectangular pit and tanh ramps 2, 5 and 20 fine cells wide — not in the
default ``--shapes``.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import subprocess
import sys
import time
from pathlib import Path

THREADS = {k: "1" for k in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")}
os.environ.update(THREADS)

ROOT = Path(__file__).resolve().parents[1]
SHAPES = ("dome", "ridge", "bumps", "terraces", "crate", "ripple", "wedge")
#: the next load: the first one times this
NEXT_LOAD = 1.25


def held_out():
    import numpy as np

    return {
        "ripple": lambda x, y: (0.1 * np.cos(9.0 * np.hypot(x - 0.3, y - 0.7))
                                * np.exp(-2.0 * np.hypot(x - 0.3, y - 0.7)) + 0.04 * x),
        "wedge": lambda x, y: np.minimum(0.18 - 0.5 * np.abs(y - 0.3 - 0.4 * x),
                                         0.12 + 0.1 * np.sin(5.0 * x)),
        "step": lambda x, y: np.where(0.7 * x + 0.3 * y < 0.5, 0.12, 0.02),
        "stairs": lambda x, y: 0.05 * np.floor(6.0 * (0.9 * x - 0.44 * y + 0.44)) - 0.1,
        "pit": lambda x, y: (0.15 - 1.2 * ((x - 0.5) ** 2 + (y - 0.5) ** 2)
                             - 0.3 * ((0.3 < x) & (x < 0.6) & (0.4 < y) & (y < 0.8))),
        # the grid's first node is at h: the ramps are k fine cells wide at every N
        **{f"ramp{k}h": (lambda k: lambda x, y: 0.05 + 0.06 * np.tanh(
            (0.8 * x + 0.6 * y - 0.7) / (k * x.min())))(k) for k in (2, 5, 20)},
    }


def build(kind, shape, N, factor=1.0):
    from formulations import meshes

    for name, f in held_out().items():
        meshes.OBSTACLES.setdefault(name, f)
    if kind == "membrane":
        return meshes.membrane(N, obstacle=shape, load=-8.0 * factor)
    D = float(kind[len("plate"):])
    return meshes.plate(N, obstacle=shape, rigidity=D, load=-1000.0 * factor)


def _floor(lcp, z, repeat=3) -> float:
    """Min CPU seconds of one QDLDL LDLᵀ (AMD included) of the final free block."""
    import numpy as np
    import qdldl
    import scipy.sparse as sp

    idx = np.flatnonzero(z > 0)
    U = sp.triu(sp.csc_matrix(lcp.M)[idx][:, idx], format="csc")
    best = float("inf")
    for _ in range(repeat):
        t = time.process_time()
        qdldl.Solver(U, upper=True)
        best = min(best, time.process_time() - t)
    return best


def row(kind, shape, N, method, repeat) -> dict:
    """One row in this process: first-load and next-load CPU (min of
    ``repeat``), their floors, cycle counts and the answers' digests."""
    import qpcontact
    from qpcontact import LCP, solve

    small = build(kind, shape, 31)      # imports, compiled kernels: paid once, untimed
    solve(small, method=method)
    solve(LCP.with_structure(small.structure, small.q, small.q_terms), method=method)
    first, first_wall = [], []
    for _ in range(repeat):
        lcp = build(kind, shape, N)
        w, t = time.perf_counter(), time.process_time()
        sol = solve(lcp, method=method, accuracy="high", time_limit=None)
        first.append(time.process_time() - t)
        first_wall.append(time.perf_counter() - w)
        assert sol.ok, sol.message
    other = build(kind, shape, N, NEXT_LOAD)
    nexts, next_wall = [], []
    for _ in range(repeat):
        again = LCP.with_structure(lcp.structure, other.q, other.q_terms)
        w, t = time.perf_counter(), time.process_time()
        nxt = solve(again, method=method, accuracy="high", time_limit=None)
        nexts.append(time.process_time() - t)
        next_wall.append(time.perf_counter() - w)
        assert nxt.ok, nxt.message
    digest = (lambda z: hashlib.sha1(z.tobytes()).hexdigest()[:12])
    return dict(kind=kind, shape=shape, N=N, method=method, first=min(first), next=min(nexts),
                first_wall=min(first_wall), next_wall=min(next_wall),
                floor=_floor(lcp, sol.z), next_floor=_floor(again, nxt.z),
                free=float((sol.z > 0).mean()), next_free=float((nxt.z > 0).mean()),
                cycles=sol.stats.get("mg_cycles"), next_cycles=nxt.stats.get("mg_cycles"),
                kept=nxt.stats.get("setup_kept"), z=digest(sol.z), next_z=digest(nxt.z),
                error=sol.certificate.error, next_error=nxt.certificate.error,
                source=str(Path(qpcontact.__file__).parents[1]))


def _run(repo, spec) -> dict:
    env = dict(os.environ, PYTHONPATH=str(repo), **THREADS)
    out = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--one", json.dumps(spec)],
                         cwd=repo, env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rows", default="membrane:100",
                    help="kind:N, kind membrane or plate<D> (plate0.05, plate1), comma-separated")
    ap.add_argument("--shapes", default=",".join(SHAPES))
    ap.add_argument("--methods", default="mg-bpp")
    ap.add_argument("--repeat", type=int, default=5, help="solves per process (the min is kept)")
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--against", default=None, help="another checkout, run alternately")
    ap.add_argument("--one", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        spec = json.loads(args.one)
        print(json.dumps(row(**spec)))
        return 0
    repos = [ROOT] + ([Path(args.against).resolve()] if args.against else [])
    results = {}
    for item in args.rows.split(","):
        kind, N = item.split(":")
        for shape in args.shapes.split(","):
            for method in args.methods.split(","):
                spec = dict(kind=kind, shape=shape, N=int(N), method=method, repeat=args.repeat)
                for r in range(args.rounds):
                    order = repos if r % 2 == 0 else repos[::-1]
                    for repo in order:
                        with open("/proc/loadavg") as f:
                            load = float(f.read().split()[0])
                        res = _run(repo, spec)
                        res["load"] = load
                        results.setdefault((kind, shape, int(N), method), {}).setdefault(
                            str(repo), []).append(res)
                        print(json.dumps(res), file=sys.stderr, flush=True)
    print(f"\n| row | method | side | first ms | × floor | next ms | × its floor | floor / next "
          f"floor ms | free | cycles first / next | z same | load | wall first / next ms |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for (kind, shape, N, method), sides in results.items():
        floor = min(r["floor"] for runs in sides.values() for r in runs)
        next_floor = min(r["next_floor"] for runs in sides.values() for r in runs)
        digests = {(r["z"], r["next_z"]) for runs in sides.values() for r in runs}
        for repo, runs in sides.items():
            first = min(r["first"] for r in runs)
            nxt = min(r["next"] for r in runs)
            side = "this" if repo == str(ROOT) else Path(repo).name
            print(f"| {kind} {shape} {N}² | {method} | {side} | {1e3 * first:.2f} | "
                  f"{first / floor:.2f} | {1e3 * nxt:.2f} | {nxt / next_floor:.2f} | "
                  f"{1e3 * floor:.2f} / {1e3 * next_floor:.2f} | "
                  f"{runs[0]['free']:.0%} / {runs[0]['next_free']:.0%} | "
                  f"{runs[0]['cycles']} / {runs[0]['next_cycles']} | "
                  f"{'yes' if len(digests) == 1 else 'NO'} | "
                  f"{min(r['load'] for r in runs):.1f}–{max(r['load'] for r in runs):.1f} | "
                  f"{1e3 * min(r['first_wall'] for r in runs):.2f} / "
                  f"{1e3 * min(r['next_wall'] for r in runs):.2f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
