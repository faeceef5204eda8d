"""Frictional contact on the peers' collection (issue 20): every friction
method on every problem of ``../shared/data/siconos-fc`` — success at the
tolerances 1e-4, 1e-6, 1e-8 of the natural-map error (computed from the data,
whatever a method says, and the componentwise error of
``qpcontact.friction.componentwise_error``: a run succeeds at ε when both are
<= ε), time and iterations — and a Dolan–Moré performance profile at 1e-8.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/friction.py
    .venv/bin/python benchmarks/friction.py --skip-large     # the two big granular files out

Each method runs once per problem with tol = 1e-8 (a method's stopping test
is its own: the fixed points stop at the tolerance or when they stall) in its
own process, killed at ``--limit`` seconds.  The profile plots, for each method, the
fraction of problems it solves to 1e-8 within τ times the fastest method's
time on that problem (Dolan & Moré, Math. Program. 91, 2002).  Prints a
Markdown table; saves out/friction/friction.csv and profile.png.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
DATA = ROOT.parent / "shared" / "data" / "siconos-fc"

#: (label, method, options)
METHODS = [
    ("lemke (2-D exact; 3-D 8 facets)", "lemke", {}),
    ("lemke 16 facets", "lemke", {"facets": 16}),
    ("anitescu", "anitescu", {}),
    ("desaxce-fp", "desaxce-fp", {}),
    ("desaxce-fp (scs)", "desaxce-fp", {"backend": "scs"}),
    ("tresca-fp", "tresca-fp", {}),
    ("desaxce-fp (osqp, 2-D)", "desaxce-fp", {"backend": "osqp"}),
    ("tresca-fp (highs, 2-D)", "tresca-fp", {"backend": "highs"}),
    ("newton", "newton", {}),
    ("nsgs", "nsgs", {}),
    ("auto", "auto", {}),
]
LEVELS = (1e-4, 1e-6, 1e-8)
LARGE = ("fc2d_granularflowonwall_00667_00000.dat", "fc2d_granularflowonwall_02020_00213.dat")


def job(path, method, options):
    import qpcontact
    from qpcontact.core.errors import QpcontactError
    from qpcontact.io import read_problem

    p = read_problem(path)
    # the registry's providers (their modules, numba) loaded before the clock
    # starts, as `import qpcontact` loaded them before they became lazy: the
    # time is the solve's, with its one-off compiled-kernel loads, not imports
    qpcontact.get_method(method) if method != "auto" else qpcontact.methods()
    t = time.perf_counter()
    try:
        s = qpcontact.solve(p, method, accuracy=1e-8, **options)
    except QpcontactError as exc:   # e.g. Lemke's dense basis refused above n = 5000
        return dict(time=time.perf_counter() - t, error=float("inf"),
                    status=f"refused: {str(exc)[:80]}", iterations=None, by="")
    return dict(time=time.perf_counter() - t, siconos_error=s.natural_map_error,
                error=s.error, status=s.status,
                iterations=s.stats.get("iterations"), by=s.method)


def run_one(path, method, options, limit):
    """``job`` in a child process killed at ``limit`` seconds (qpcontact's
    own isolation, which also survives a crashing backend)."""
    from qpcontact.dispatch.isolation import call_isolated

    t = time.perf_counter()
    out = call_isolated(job, (path, method, options), limit)
    if out is None:   # no child process possible here: run in-process
        return job(path, method, options)
    if out.kind == "ok":
        return out.value
    if out.kind == "error":
        raise out.value
    status = f"killed at {limit:.0f} s" if out.kind == "time_limit" else f"died ({out.detail})"
    return dict(time=time.perf_counter() - t, error=float("inf"), status=status,
                iterations=None, by="")


def profile(rows, labels, path):
    """Dolan–Moré profile at 1e-8: ρ_s(τ) = fraction of problems with
    t_{p,s} <= τ min_s t_{p,s}, an unsolved run counting as never."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from qpcontact.plots.figures import save_figure

    problems = sorted({r["problem"] for r in rows})
    T = np.full((len(problems), len(labels)), np.inf)
    for r in rows:
        if r["error"] <= 1e-8:
            T[problems.index(r["problem"]), labels.index(r["label"])] = max(r["time"], 1e-4)
    best = T.min(axis=1)
    solved_by_any = np.isfinite(best)
    ratios = T[solved_by_any] / best[solved_by_any, None]
    taus = np.logspace(0, 4, 400)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for j, label in enumerate(labels):
        frac = [(ratios[:, j] <= tau).sum() / len(problems) for tau in taus]
        ax.step(taus, frac, where="post", label=label)
    ax.set_xscale("log")
    ax.set_xlabel("τ (time / fastest method's time on the problem)")
    ax.set_ylabel("fraction of problems solved to 1e-8")
    ax.set_ylim(0, 1.02)
    ax.set_title(f"Dolan–Moré profile, {len(problems)} Siconos/FCLIB problems")
    ax.legend(fontsize=7, loc="lower right")
    save_figure(fig, path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--limit", type=float, default=60.0, help="seconds per run (killed after)")
    ap.add_argument("--skip-large", action="store_true", help="leave the granular files out")
    ap.add_argument("--out", default="out/friction")
    args = ap.parse_args(argv)
    from qpcontact.io import read_problem

    if not DATA.is_dir():
        print(f"no friction data at {DATA}: nothing to measure")
        return 0
    files = sorted(p for p in DATA.glob("*") if p.suffix in (".dat", ".hdf5"))
    rows = []
    for path in files:
        if args.skip_large and path.name in LARGE:
            continue
        p = read_problem(path)
        if p.n_contacts == 0:
            continue   # the global granular file holds no contact
        print(f"{path.name} (dim {p.dim}, {p.n_contacts} contacts)", flush=True)
        for label, method, options in METHODS:
            if method == "lemke" and options.get("facets") and p.dim == 2:
                continue   # a 2-D cone has two facets: the first row
            if options.get("backend") not in (None, "clarabel", "scs") and p.dim != 2:
                continue   # a QP backend takes only 2-D subproblems
            r = run_one(path, method, options, args.limit)
            r.update(problem=path.name, dim=p.dim, contacts=p.n_contacts, label=label)
            rows.append(r)
            print(f"    {label:34s} {r['time']:8.3f} s  error {r['error']:.1e}  {r['status']}"
                  f"{'  (' + r['by'] + ')' if method == 'auto' else ''}", flush=True)
    labels = [m[0] for m in METHODS]
    print("\n| method | problems | solved at 1e-4 | 1e-6 | 1e-8 | median time s (solved at 1e-8) "
          "| total time s | median iterations |")
    print("|---|---|---|---|---|---|---|---|")
    import numpy as np

    for label in labels:
        mine = [r for r in rows if r["label"] == label]
        if not mine:
            continue
        ok = [r for r in mine if r["error"] <= 1e-8]
        its = [r["iterations"] for r in mine if r["iterations"] is not None]
        print(f"| {label} | {len(mine)} | "
              + " | ".join(str(sum(r["error"] <= e for r in mine)) for e in LEVELS)
              + f" | {np.median([r['time'] for r in ok]) if ok else float('nan'):.3f}"
              f" | {sum(r['time'] for r in mine):.1f}"
              f" | {np.median(its) if its else float('nan'):.0f} |")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    from qpcontact.core.files import write_csv_atomic

    write_csv_atomic(out / "friction.csv", rows, ["problem", "dim", "contacts", "label", "time",
                                                  "error", "siconos_error", "status",
                                                  "iterations", "by"])
    profile(rows, labels, out / "profile.png")
    print(f"\nwrote {out / 'friction.csv'} and {out / 'profile.png'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
