"""Frictional contact on the peers' collection and on generated piles: every
friction method on every problem of ``../shared/data/siconos-fc`` — success at the
tolerances 1e-4, 1e-6, 1e-8 of the natural-map error (computed from the data,
whatever a method says, and the componentwise error of
``qpcontact.judge.friction_certificate.componentwise_error``: a run succeeds at ε when both are
<= ε), time and iterations — and a Dolan–Moré performance profile at 1e-8.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/friction.py
    .venv/bin/python benchmarks/friction.py --skip-large     # the two big granular files out
    .venv/bin/python benchmarks/friction.py --methods vi-eg --piles "" --piles-3d ""  # one method

Each method runs once per problem with tol = 1e-8 (a method's stopping test
is its own: the fixed points stop at the tolerance or when they stall) in its
own process, killed at ``--limit`` seconds.  The profile plots, for each method, the
fraction of problems it solves to 1e-8 within τ times the fastest method's
time on that problem (Dolan & Moré, Math. Program. 91, 2002).  Prints a
Markdown table; saves out/friction/friction.csv and profile.png.

Generated piles (:mod:`qpcontact.cases.piles`, ``--seeds``, default 0): 2-D disc piles of
1 000–20 000 contacts ("granular", the generator's defaults, and "compact",
agitation 0.1 and polydispersity 0.005: nearly closed, statically
indeterminate) and 3-D sphere piles of 500–2 000 contacts, solved by "auto",
"nsgs-newton" and plain "nsgs" (the link "auto" began with before the large-pile route),
each in its own process with its time and peak memory (the child's peak
resident set above its size once the problem is built and the methods
loaded).  Saves piles.csv,
piles_time.png (time against contacts) and success.png (the fraction of all
problems certified at 1e-8 within t seconds, per method).

    .venv/bin/python benchmarks/friction.py --only-piles --piles 1000,10000

Dense rows (``--dense``: only these): the nearly closed piles of the issue
"dense packings certified", each at its own tolerance — 3-D compact piles of
540 and 982 contacts, seeds 0–9, and 3-D sphere and compact piles of about
2 000 contacts at 1e-6; 2-D compact piles of 2 000, 5 000 and 10 000 at
1e-8 — by "auto" on its 60 s budget, each in its own process: time, peak
memory, the error reached, the link that answered and each link's share of
the time (``stats["auto_link_times"]``); for a row not certified, after the
clock, whether a solution provably exists
(:func:`qpcontact.proofs.friction_existence.solution_exists`: "proved", or
"undecided" — never a claim that none exists).  Saves dense.csv and
dense_success.png (the fraction of the rows certified within t).

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/friction.py --dense
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
    ("nsgs-newton", "nsgs-newton", {}),
    ("vi-eg", "vi-eg", {}),
    ("auto", "auto", {}),
]
LEVELS = (1e-4, 1e-6, 1e-8)
LARGE = ("fc2d_granularflowonwall_00667_00000.dat", "fc2d_granularflowonwall_02020_00213.dat")


PILE_METHODS = [("auto", "auto", {}), ("nsgs-newton", "nsgs-newton", {}), ("nsgs", "nsgs", {})]
#: (family, dimension, generator parameters, largest size run): the compact
#: piles stall every method beyond these sizes (docs/friction.md)
COMPACT = {"agitation": 0.1, "polydispersity": 0.005}
FAMILIES = [("2-D granular", 2, {}, 10**9), ("2-D compact", 2, COMPACT, 5000),
            ("3-D spheres", 3, {}, 10**9), ("3-D compact", 3, COMPACT, 1000)]


#: the dense rows: (family, dimension, size asked of the generator, parameters, seeds, tol)
DENSE = [("3-D compact", 3, 500, COMPACT, range(10), 1e-6),
         ("3-D compact", 3, 1000, COMPACT, range(10), 1e-6),
         ("2-D compact", 2, 2000, COMPACT, (0,), 1e-8),
         ("2-D compact", 2, 5000, COMPACT, (0,), 1e-8),
         ("2-D compact", 2, 10000, COMPACT, (0,), 1e-8),
         ("3-D spheres", 3, 2000, {}, (0,), 1e-6),
         ("3-D compact", 3, 2000, COMPACT, (0,), 1e-6)]


def pile(dim, n, params, seed=0):
    from qpcontact.cases.piles import disc_pile, sphere_pile

    return (disc_pile if dim == 2 else sphere_pile)(n, seed=seed, **params).problem


def rss_mb():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def job(path, method, options):
    import resource

    import qpcontact
    from qpcontact.core.errors import QpcontactError
    from qpcontact.io import read_problem

    p = read_problem(path) if not isinstance(path, tuple) else pile(*path)
    # the registry's providers (their modules, numba) loaded before the clock
    # starts, as `import qpcontact` loaded them before they became lazy: the
    # time is the solve's, with its one-off compiled-kernel loads, not imports
    qpcontact.get_method(method) if method != "auto" else qpcontact.methods()
    before = rss_mb()
    t = time.perf_counter()
    try:
        s = qpcontact.solve(p, method, accuracy=1e-8, **options)
    except QpcontactError as exc:   # e.g. Lemke's dense basis refused above n = 5000
        return dict(time=time.perf_counter() - t, error=float("inf"),
                    status=f"refused: {str(exc)[:80]}", iterations=None, by="")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return dict(time=time.perf_counter() - t, siconos_error=s.natural_map_error,
                error=s.error, status=s.status, memory_mb=max(peak - before, 0.0),
                iterations=s.stats.get("iterations"), by=s.method)


def dense_job(dim, n, params, seed, tol):
    """"auto" on one dense row at its own tolerance: time, peak memory above
    the built problem, the error reached and each link's seconds."""
    import resource

    import qpcontact

    p = pile(dim, n, params, seed)
    qpcontact.methods()
    before = rss_mb()
    t = time.perf_counter()
    s = qpcontact.solve(p, "auto", accuracy=tol)
    wall = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    links = s.stats.get("auto_link_times", [])
    exists = "certified"
    if not s.ok:       # after the clock: whether the answer the methods missed exists
        from qpcontact.proofs.friction_existence import solution_exists

        exists = "proved" if solution_exists(p, time_limit=30.0) is not None else "undecided"
    return dict(time=wall, error=s.error, status=s.status, ok=s.ok, by=s.method, exists=exists,
                contacts=p.n_contacts, memory_mb=max(peak - before, 0.0),
                links="; ".join(f"{m} {sec:.1f} s" for m, sec in links),
                link_times=links)


def run_dense(args):
    """The dense rows (module docstring), each "auto" in its own process,
    killed at ``--limit`` (auto stops itself at its 60 s budget)."""
    import qpcontact

    qpcontact.solve(pile(2, 100, {}), "nsgs-newton")   # compiled sweeps loaded once
    qpcontact.solve(pile(3, 100, {}), "nsgs-newton")
    rows = []
    for family, dim, n, params, seeds, tol in DENSE:
        for seed in seeds:
            r = isolated(dense_job, (dim, n, params, seed, tol), args.limit)
            if "contacts" not in r:      # killed or died: no row from the child
                r.update(contacts=pile(dim, n, params, seed).n_contacts, links="",
                         link_times=[])
            r.update(family=family, size=n, seed=seed, tol=tol,
                     problem=f"{family} {n} seed {seed}")
            rows.append(r)
            print(f"{family} {n} seed {seed}: {r['contacts']} contacts, {r['time']:6.2f} s, "
                  f"error {r['error']:.1e} at {tol:.0e} {'certified' if r['ok'] else 'NOT'}"
                  f" (by {r['by']}; {r['links']}), {r.get('memory_mb', float('nan')):.0f} MB"
                  + ("" if r["ok"] else f"; a solution exists: {r.get('exists', 'undecided')}"),
                  flush=True)
    print("\n| pile | contacts | seed | tol | time s | error | certified | by | links (s) "
          "| peak memory MB | a solution exists |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['family']} | {r['contacts']} | {r['seed']} | {r['tol']:.0e} | "
              f"{r['time']:.2f} | {r['error']:.1e} | {'yes' if r['ok'] else 'no'} | {r['by']} | "
              f"{r['links']} | {r.get('memory_mb', float('nan')):.0f} | "
              f"{'—' if r['ok'] else r.get('exists', 'undecided')} |")
    total = sum(r["time"] for r in rows)
    shares = {}
    for r in rows:
        for m, sec in r["link_times"]:
            shares[m] = shares.get(m, 0.0) + sec
    print(f"\ncertified: {sum(r['ok'] for r in rows)} of {len(rows)} rows; "
          f"total {total:.0f} s; each route's share of it: "
          + ", ".join(f"{m} {sec / total:.0%}" for m, sec in
                      sorted(shares.items(), key=lambda kv: -kv[1])))
    answered = {}
    for r in rows:
        if r["ok"]:
            answered[r["by"]] = answered.get(r["by"], 0) + 1
    if answered:
        print("certified rows by route: " + ", ".join(f"{m} {k}" for m, k in answered.items()))
    return rows


def dense_success_plot(rows, path):
    """The fraction of the dense rows "auto" certified (each at its own
    tolerance) within t seconds, per family and size."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from qpcontact.plots.figures import save_figure

    groups = {}
    for r in rows:
        groups.setdefault(f"{r['family']} {r['size']} ({r['tol']:.0e})", []).append(r)
    ts = np.logspace(0, np.log10(120), 300)
    fig, ax = plt.subplots(figsize=(7, 4.8))
    fig.subplots_adjust(bottom=0.3)
    for j, (label, mine) in enumerate(groups.items()):
        times = [r["time"] for r in mine if r["ok"]]
        # the groups that certify nothing share the zero line: the legend says so
        ax.step(ts, [sum(t <= x for t in times) / len(mine) for x in ts], where="post",
                color=f"C{j % 10}", label=f"{label}: {len(times)} of {len(mine)}")
    everything = [r["time"] for r in rows if r["ok"]]
    ax.step(ts, [sum(t <= x for t in everything) / len(rows) for x in ts], where="post",
            color="k", lw=2.2, label=f"all rows: {len(everything)} of {len(rows)}")
    ax.axvline(60, color="gray", ls=":", lw=1)
    ax.text(63, 0.8, "\"auto\"'s\nbudget,\n60 s", color="gray", fontsize=8, ha="left",
            va="center")
    ax.set_xscale("log")
    ax.set_xlabel("time limit t [s]")
    ax.set_ylabel('fraction certified by "auto" within t')
    ax.set_ylim(-0.02, 1.02)
    ax.set_title('Dense piles: "auto" on its 60 s budget (2-core machine, one BLAS thread)',
                 fontsize=10)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2,
              frameon=False)
    save_figure(fig, path)


def isolated(fn, args, limit):
    """``fn(*args)`` (a row's dict) in a child process killed at ``limit``
    seconds (qpcontact's own isolation, which also survives a crashing
    backend); where the child gave no row, one with its time and status."""
    from qpcontact.dispatch.isolation import call_isolated

    t = time.perf_counter()
    out = call_isolated(fn, args, limit)
    if out is None:   # no child process possible here: run in-process
        return fn(*args)
    if out.kind == "ok":
        return out.value
    if out.kind == "error":
        raise out.value
    status = f"killed at {limit:.0f} s" if out.kind == "time_limit" else f"died ({out.detail})"
    return dict(time=time.perf_counter() - t, error=float("inf"), ok=False, status=status,
                by="")


def run_one(path, method, options, limit):
    """``job`` in its own process (:func:`isolated`)."""
    return {"iterations": None, **isolated(job, (path, method, options), limit)}


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
    fig, ax = plt.subplots(figsize=(7.5, 6.5))
    fig.subplots_adjust(bottom=0.3)
    for j, label in enumerate(labels):
        frac = [(ratios[:, j] <= tau).sum() / len(problems) for tau in taus]
        # ten colours, then dashed: no two curves look alike
        ax.step(taus, frac, where="post", label=label, color=f"C{j % 10}",
                ls="-" if j < 10 else "--", lw=2.2 if label == "auto" else 1.3)
    ax.set_xscale("log")
    ax.set_xlabel("τ (time / fastest method's time on the problem)")
    ax.set_ylabel("fraction of problems solved to 1e-8")
    ax.set_ylim(0, 1.02)
    ax.set_title(f"Dolan–Moré profile, {len(problems)} Siconos/FCLIB problems")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3,
              frameon=False)
    save_figure(fig, path)


def success_plot(rows, labels, path):
    """The fraction of all problems certified at 1e-8 within t seconds, for
    the methods that ran on every problem (the others ran on the shared
    collection only: their fractions would not compare)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from qpcontact.plots.figures import save_figure

    problems = sorted({r["problem"] for r in rows})
    everywhere = [lb for lb in labels
                  if {r["problem"] for r in rows if r["label"] == lb} == set(problems)]
    piles = sum(1 for p in problems if " seed " in p)
    ts = np.logspace(-3, 2.5, 400)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for j, label in enumerate(everywhere):
        times = [r["time"] for r in rows if r["label"] == label and r["error"] <= 1e-8]
        ax.step(ts, [sum(t <= x for t in times) / len(problems) for x in ts], where="post",
                label=f'"{label}"', color=f"C{j}", lw=2.2 if label == "auto" else 1.4)
    ax.set_xscale("log")
    ax.set_xlabel("time limit t [s]")
    ax.set_ylabel("fraction certified at 1e-8 within t")
    ax.set_ylim(0, 1.02)
    ax.set_title(f"Success against time: {len(problems) - piles} shared files and {piles} "
                 "generated piles", fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    save_figure(fig, path)


def pile_time_plot(rows, path):
    """Time against contacts on the generated piles: colour the method,
    marker the family, filled where certified at 1e-8."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.lines import Line2D

    from qpcontact.plots.figures import save_figure

    fig, ax = plt.subplots(figsize=(7.5, 6))
    fig.subplots_adjust(bottom=0.28)
    markers = dict(zip([f[0] for f in FAMILIES], "osD^"))
    colors = {"auto": "C0", "nsgs": "C3"}
    for family, _, _, _ in FAMILIES:
        for label, color in colors.items():
            mine = sorted((r for r in rows if r["family"] == family and r["label"] == label),
                          key=lambda r: r["contacts"])
            if not mine:
                continue
            x = np.array([r["contacts"] for r in mine])
            y = np.array([r["time"] for r in mine])
            ok = np.array([r["error"] <= 1e-8 for r in mine])
            ax.plot(x, y, color=color, lw=0.8, alpha=0.5)
            ax.scatter(x[ok], y[ok], marker=markers[family], color=color, zorder=3)
            ax.scatter(x[~ok], y[~ok], marker=markers[family], facecolors="white",
                       edgecolors=color, zorder=3)
    ax.axhline(20, color="gray", ls=":", lw=1)
    ax.text(0.01, 21, "20 s: the target at 10 000 contacts", color="gray", fontsize=8,
            transform=ax.get_yaxis_transform())
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("contacts")
    ax.set_ylabel("time [s]")
    seeds = sorted({r.get("seed", 0) for r in rows})
    ax.set_title(f"Generated piles, seed{'s' if len(seeds) > 1 else ''} "
                 f"{', '.join(map(str, seeds))}: time to certify at 1e-8\n"
                 "(hollow: not certified; 2-core machine, one BLAS thread)", fontsize=10)
    handles = [Line2D([], [], color=c, marker="o", lw=0.8, label=f'"{m}"')
               for m, c in colors.items()]
    handles += [Line2D([], [], color="gray", marker=mk, ls="", label=fam)
                for fam, mk in markers.items()]
    ax.legend(handles=handles, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.12),
              ncol=3, frameon=False)
    save_figure(fig, path)


def run_piles(args):
    import qpcontact

    # compiled sweeps loaded (and numba's disk cache written, after a change
    # of the kernels) before any run is timed
    qpcontact.solve(pile(2, 100, {}), "nsgs-newton")
    qpcontact.solve(pile(3, 100, {}), "nsgs-newton")
    rows = []
    sizes = {2: [int(x) for x in args.piles.split(",") if x],
             3: [int(x) for x in args.piles_3d.split(",") if x]}
    seeds = [int(x) for x in args.seeds.split(",")]
    for family, dim, params, largest in FAMILIES:
        for n, seed in ((n, sd) for n in sizes[dim] if n <= largest for sd in seeds):
            p = pile(dim, n, params, seed)
            print(f"{family} pile, {p.n_contacts} contacts, seed {seed}", flush=True)
            for label, method, options in PILE_METHODS:
                r = run_one((dim, n, params, seed), method, options, args.limit)
                r.update(problem=f"{family} {n} seed {seed}", family=family, dim=dim,
                         contacts=p.n_contacts, label=label, seed=seed)
                rows.append(r)
                print(f"    {label:14s} {r['time']:8.2f} s  error {r['error']:.1e}  "
                      f"{r.get('memory_mb', float('nan')):7.0f} MB  {r['status']}"
                      f"{'  (' + r['by'] + ')' if method == 'auto' else ''}", flush=True)
    print("\n| pile | contacts | seed | method | time s | error | peak memory MB | status |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['family']} | {r['contacts']} | {r['seed']} | {r['label']} | {r['time']:.2f} | "
              f"{r['error']:.1e} | {r.get('memory_mb', float('nan')):.0f} | {r['status']}"
              f"{' (' + r['by'] + ')' if r.get('by') and r['label'] == 'auto' else ''} |")
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--limit", type=float, default=90.0,
                    help="seconds per run (killed after; 'auto' stops itself at 60)")
    ap.add_argument("--skip-large", action="store_true", help="leave the granular files out")
    ap.add_argument("--out", default="out/friction")
    ap.add_argument("--piles", default="1000,2000,5000,10000,20000",
                    help="2-D pile sizes in contacts ('' for none)")
    ap.add_argument("--piles-3d", default="500,1000,2000", help="3-D pile sizes in contacts")
    ap.add_argument("--seeds", default="0", help="pile seeds, comma-separated")
    ap.add_argument("--only-piles", action="store_true", help="leave the shared collection out")
    ap.add_argument("--methods", default="",
                    help="the shared collection's methods by label, comma-separated (default all)")
    ap.add_argument("--dense", action="store_true",
                    help="only the dense rows (3-D compact seeds 0-9, 2-D compact to 10 000)")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    from qpcontact.core.files import write_csv_atomic

    if args.dense:
        rows = run_dense(args)
        write_csv_atomic(out / "dense.csv", rows,
                         ["problem", "family", "size", "contacts", "seed", "tol", "time", "error",
                          "ok", "status", "by", "links", "memory_mb", "exists"])
        dense_success_plot(rows, out / "dense_success.png")
        print(f"wrote {out / 'dense.csv'} and {out / 'dense_success.png'}")
        return 0

    pile_rows = run_piles(args) if (args.piles or args.piles_3d) else []
    if pile_rows:
        write_csv_atomic(out / "piles.csv", pile_rows,
                         ["problem", "family", "dim", "contacts", "seed", "label", "time", "error",
                          "siconos_error", "memory_mb", "status", "iterations", "by"])
        pile_time_plot(pile_rows, out / "piles_time.png")
        print(f"wrote {out / 'piles.csv'} and {out / 'piles_time.png'}")
    if args.only_piles:
        return 0
    from qpcontact.io import read_problem

    if not DATA.is_dir():
        print(f"no friction data at {DATA}: nothing to measure")
        return 0
    files = sorted(p for p in DATA.glob("*") if p.suffix in (".dat", ".hdf5"))
    wanted = [w for w in args.methods.split(",") if w]
    chosen = [m for m in METHODS if not wanted or m[0] in wanted]
    if wanted and len(chosen) != len(wanted):
        ap.error(f"--methods: choose from {', '.join(m[0] for m in METHODS)}")
    rows = []
    for path in files:
        if args.skip_large and path.name in LARGE:
            continue
        p = read_problem(path)
        if p.n_contacts == 0:
            continue   # the global granular file holds no contact
        print(f"{path.name} (dim {p.dim}, {p.n_contacts} contacts)", flush=True)
        for label, method, options in chosen:
            if method == "lemke" and options.get("facets") and p.dim == 2:
                continue   # a 2-D cone has two facets: the first row
            if options.get("backend") not in (None, "clarabel", "scs") and p.dim != 2:
                continue   # a QP backend takes only 2-D subproblems
            r = run_one(path, method, options, args.limit)
            r.update(problem=path.name, dim=p.dim, contacts=p.n_contacts, label=label)
            rows.append(r)
            print(f"    {label:34s} {r['time']:8.3f} s  error {r['error']:.1e}  {r['status']}"
                  f"{'  (' + r['by'] + ')' if method == 'auto' else ''}", flush=True)
    labels = [m[0] for m in chosen]
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
    write_csv_atomic(out / "friction.csv", rows, ["problem", "dim", "contacts", "label", "time",
                                                  "error", "siconos_error", "memory_mb",
                                                  "status", "iterations", "by"])
    profile(rows, labels, out / "profile.png")
    success_plot(rows + pile_rows, labels + [m[0] for m in PILE_METHODS if m[0] not in labels],
                 out / "success.png")
    print(f"\nwrote {out / 'friction.csv'}, {out / 'profile.png'} and {out / 'success.png'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
