""""vi-eg" (projected gradient with Khobotov's step, Siconos's VI_EG) on the
dense 3-D compact piles of issue 50, each row in its own process, one BLAS
thread: the error reached, iterations, wall and CPU seconds, and the share of
an iteration that is W's products (whether a compiled kernel would pay).

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/vi_eg_piles.py
    .venv/bin/python benchmarks/vi_eg_piles.py --rows 500:0,500:8,1000:6 --limit 60
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]


def row(n: int, seed: int, tol: float, limit: float) -> str:
    sys.path.insert(0, str(ROOT))
    import numpy as np
    import scipy.sparse as sp

    import qpcontact
    from qpcontact.cases.piles import sphere_pile

    p = sphere_pile(n, seed=seed, agitation=0.1, polydispersity=0.005).problem
    qpcontact.get_method("vi-eg")
    W, r = sp.csr_matrix(p.W), np.ones(p.W.shape[0])
    t = time.perf_counter()
    for _ in range(200):
        W @ r
    product = (time.perf_counter() - t) / 200
    wall, cpu = time.perf_counter(), time.process_time()
    s = qpcontact.solve(p, "vi-eg", accuracy=tol, time_limit=limit)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    its = s.stats.get("iterations") or 0
    per = wall / max(its, 1)
    return (f"| {p.n_contacts} seed {seed} | {'✓ ' if s.ok else ''}{s.error:.1e} | {its} | "
            f"{wall:.1f} | {cpu:.1f} | {its / wall:.0f} | {1e6 * per:.0f} | "
            f"{1e6 * product:.0f} |")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rows", default="500:0,500:8,1000:6",
                    help="n:seed of sphere_pile(n, seed, agitation=0.1, polydispersity=0.005)")
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--limit", type=float, default=60.0, help="time_limit of each solve (s)")
    ap.add_argument("--one", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        n, seed = map(int, args.one.split(":"))
        print(row(n, seed, args.tol, args.limit), flush=True)
        return 0
    print("| row | error | iterations | wall s | CPU s | it/s | µs/it | µs per W r |")
    print("|---|---|---|---|---|---|---|---|")
    for spec in args.rows.split(","):
        with open("/proc/loadavg") as f:
            load = f.read().split()[0]
        out = subprocess.run([sys.executable, __file__, "--one", spec, "--tol", str(args.tol),
                              "--limit", str(args.limit)], capture_output=True, text=True)
        print(out.stdout.strip() or out.stderr.strip()[-300:], f"load {load}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
