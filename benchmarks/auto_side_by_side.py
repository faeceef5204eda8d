""""auto" on the 3-D piles, two checkouts side by side: each row run by the
base checkout, then by this one (interleaved row by row), each "auto" in its
own process with one BLAS thread; wall and CPU seconds, the error, the link
that answered, each link's seconds, and the load average before the row.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/auto_side_by_side.py \\
        --base ../base-worktree --rows c500:0-9,c1000:0-9,s2000:0,c2000:0,l500:0-2,l1000:0-2

A row is {c: compact (agitation 0.1, polydispersity 0.005), s: the
generator's defaults (benchmarks/friction.py's DENSE "3-D spheres"), l: the
same (the loose piles of benchmarks/friction.py)}{n}:{seeds}, at 1e-6 with
"auto"'s 60 s.  With --collection DIR the 3-D files of the shared collection
at 1e-8 instead.  With --starts, each row's "nsgs-restarts" starts (error,
sweeps, the first start's Newton polish; seconds left out) follow it, base
then this: where the route decides its work by counts, two runs of a row at
different loads list the same starts up to where the shorter one stopped
(docs/dev-notes.md, "The dense 3-D route by counts").
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[var] = "1"
ROOT = Path(__file__).resolve().parents[1]
COMPACT = {"agitation": 0.1, "polydispersity": 0.005}


def child(root: str, spec: str, tol: float) -> dict:
    """One "auto" in this process on checkout ``root``."""
    import re
    import time

    sys.path.insert(0, root)
    import qpcontact

    if spec.startswith("file:"):
        from qpcontact.io import read_problem

        p = read_problem(spec[5:])
    else:
        from qpcontact.cases.piles import sphere_pile

        kind, n, seed = spec[0], int(spec[1:].split(":")[0]), int(spec.split(":")[1])
        p = sphere_pile(n, seed=seed, **(COMPACT if kind == "c" else {})).problem
    qpcontact.methods()
    wall, cpu = time.perf_counter(), time.process_time()
    s = qpcontact.solve(p, "auto", accuracy=tol)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    starts = [re.sub(r", [0-9.e+-]+ s\)", ")", x) for x in re.findall(
        r"start \d+: [^;)]*\([^)]*\)(?:, then Newton [^;)]*(?:\([^)]*\))?)?", s.message)]
    return dict(file=qpcontact.__file__, dim=p.dim, contacts=p.n_contacts, ok=bool(s.ok),
                error=float(s.error), by=s.method, wall=wall, cpu=cpu, starts=starts,
                links=[(m, round(t, 2)) for m, t in s.stats.get("auto_link_times", [])])


def run(root: str, spec: str, tol: float) -> dict:
    with open("/proc/loadavg") as f:
        load = f.read().split()[0]
    out = subprocess.run([sys.executable, __file__, "--child", root, spec, str(tol)],
                         capture_output=True, text=True, timeout=180)
    try:
        row = json.loads(out.stdout.strip().splitlines()[-1])
    except (IndexError, json.JSONDecodeError):
        row = dict(ok=False, error=float("inf"), by=out.stderr.strip()[-200:], wall=0.0, cpu=0.0,
                   links=[], contacts=0)
    row["load"] = load
    return row


def specs(rows: str):
    for part in rows.split(","):
        head, seeds = part.split(":")
        lo, _, hi = seeds.partition("-")
        for seed in range(int(lo), int(hi or lo) + 1):
            yield f"{head}:{seed}"


def cell(r: dict) -> str:
    links = ", ".join(f"{m} {t:.1f}" for m, t in r["links"])
    return (f"{'✓ ' if r['ok'] else ''}{r['error']:.1e} {r['by']} | {r['wall']:.1f} / "
            f"{r['cpu']:.1f} | {r['load']} | {links}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--base", help="the base checkout (a git worktree of main)")
    ap.add_argument("--rows", default="c500:0-9,c1000:0-9")
    ap.add_argument("--collection", help="a folder of .hdf5/.dat files: its 3-D files at 1e-8")
    ap.add_argument("--starts", action="store_true", help="each row's restarts, start by start")
    ap.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(child(args.child[0], args.child[1], float(args.child[2]))))
        return 0
    if args.base is None:
        ap.error("--base is required")
    if args.collection:
        todo = [(f"file:{f}", 1e-8) for f in sorted(Path(args.collection).iterdir())
                if f.suffix in (".hdf5", ".dat")]
    else:
        todo = [(s, 1e-6) for s in specs(args.rows)]
    print("| row | contacts | base: error, by | wall / CPU s | load | links s | this: error, by "
          "| wall / CPU s | load | links s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for spec, tol in todo:
        base, this = run(args.base, spec, tol), run(str(ROOT), spec, tol)
        if this.get("dim") == 2:       # the collection's 2-D files: not this comparison's
            continue
        print(f"| {Path(spec).name if spec.startswith('file:') else spec} | "
              f"{this['contacts']} | {cell(base)} | {cell(this)} |", flush=True)
        if args.starts:
            for side, r in (("base", base), ("this", this)):
                print(f"|   {side} | | {' · '.join(r.get('starts', []))} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
