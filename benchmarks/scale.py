"""The exact oracle at mesh scale: membrane and plate obstacle
problems (obstacle shapes "dome", "ridge", "bumps", "terraces", "crate"; the
operator's scale by --rigidity: K = rigidity · L² for the plate), a 3-D
elastic block on a rigid foundation (the mixed problem), and MITC4 rafts on
tensionless soil against PyNite's and OpenSees's compression-only spring
iterations, n = 1e4 .. 1e6, every method in its own process (time, peak
memory, killed at the time limit), measured side by side in one run.

    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 .venv/bin/python benchmarks/scale.py
    .venv/bin/python benchmarks/scale.py --quick          # n ~ 1e3 .. 1e4, a minute
    .venv/bin/python benchmarks/scale.py --membrane 1000 --methods mg-bpp   # n = 1e6, 1.3 GB
    .venv/bin/python benchmarks/scale.py --plate 1000 --methods mg-bpp \
        --limit 900                                 # n = 1e6: 1-2 min CPU, 3 GB (opt-in)
    .venv/bin/python benchmarks/scale.py --membrane 100,316 --shapes dome,bumps,ridge
    .venv/bin/python benchmarks/scale.py --plate 100,200 --rigidity 0.05 --shapes terraces,crate
    .venv/bin/python benchmarks/scale.py --raft 57,115 --methods qpcontact,pynite,opensees

Per family and n: each method's wall time (solve() included: conversion,
certificate), iterations, certificate error, the ratio to **one sparse LDLᵀ
of the final free block** (the faster of QDLDL with AMD and SuperLU's
supernodal LDLᵀ with MMD, ordering included — the cheapest exact solve of
the answer's own linear system) for the whole solve() and for the method's
own call (``wall_time``: without solve()'s convexity check and certificate,
which every route pays), the ratio to the fastest QP backend that
certified its answer at "high", and the process's peak memory; for the
obstacle rows also the **next load case** (the load × NEXT_LOAD on the same
M: an LCP sharing the first one's structure, as a raft's or a membrane's
load combinations do) — its time and its ratio to its own final block's
LDLᵀ: what a method keeps of M alone (mg-bpp's Galerkin products and packed
levels, |M|) is not built again there, so the first solve and the next are
both printed.  Prints a
Markdown table and each method's fitted slope (time ∝ n^slope per family),
and saves a log-log plot of time against n with the LDLᵀ floor drawn
(out/scale/scale.png) and the rows (out/scale/scale.csv).  The QP backends
run up to ``--backends-max`` unknowns (default 2e5: at 1e6 none finishes in
any limit worth waiting for).

Raft rows (``--raft``: cells per side of a square raft, n = 3 (cells+1)²
dofs): "qpcontact" is ``Raft.solve`` (one certified contact problem; the
floor is one LDLᵀ of the answer's own linear system: the stiffness on the
free dofs plus the springs of the nodes in contact, factorised as a Newton
step does it — SuperLU in the mesh's nested-dissection order — with
qdldl's under its own AMD, the factorisation before, in the status up to
3e5 dofs, and the solve's CPU time); "pynite" and
"opensees" are the engineers' route (tests/helpers/raft_peers.py), with
"status" saying whether their iteration converged and, where it did, how
far their deflections and lifted set are from ours.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

BACKENDS = ("piqp", "clarabel", "proxqp", "osqp")
RAFT_METHODS = ("qpcontact", "pynite", "opensees")


#: The second load case of an obstacle row: its load times this (the
#: "next load" columns: the same M, another q, the contact set moved).
NEXT_LOAD = 1.25


def build(family: str, size: int, rigidity: float = 1.0, load_factor: float = 1.0):
    """``family`` is "membrane", "plate" (optionally "-<shape>", a key of
    meshes.OBSTACLES) or "signorini"; ``rigidity`` scales the membrane's
    tension or the plate's D, ``load_factor`` the obstacle rows' load."""
    from formulations import meshes

    kind, _, shape = family.partition("-")
    if kind == "membrane":
        return meshes.membrane(size, obstacle=shape or "dome", tension=rigidity,
                               load=-8.0 * load_factor)
    if kind == "plate":
        return meshes.plate(size, obstacle=shape or "dome", rigidity=rigidity,
                            load=-1000.0 * load_factor)
    return meshes.signorini(size)[0]


def raft_model(cells: int):
    """formulations.plates.examples.windward_raft: a square raft of 0.5 m
    cells under a 4 x 4 grid of columns, the windward row pulled up."""
    from formulations.plates.examples import windward_raft

    return windward_raft(cells)


#: the raft's qdldl floor (its own AMD ordering: the factorisation Newton's
#: steps used before the nested-dissection order) is measured up to this
#: many dofs (2.5e5: 11 s CPU; 1e6: 186.5 s CPU and 4.6 GB, longer than the solve)
QDLDL_FLOOR_MAX = 300_000


def _raft_floor(raft, result):
    """(seconds, CPU seconds, qdldl's seconds or None) for one LDLᵀ of the
    answer's own linear system: the stiffness on the dofs no bilateral support holds,
    plus the springs of the soil nodes in contact, less the w of the floor
    nodes held (a lifted floor node's w is an unknown of that system:
    ``qp.free`` leaves every floor node's w out, which made a floor raft's
    floor the smaller system of a raft held everywhere).  The first is the
    factorisation a Newton step makes (formulations/plates/newton.py:
    SuperLU in the mesh's nested-dissection order, its matrix's values
    set; below newton.SUPERNODAL_DOFS qdldl under its AMD, as before); the
    second the same system by qdldl under its own AMD, the factorisation of
    the rows published before 2026-12-06's 10⁶ row, up to QDLDL_FLOOR_MAX
    dofs."""
    import numpy as np
    import qdldl
    import scipy.sparse as sp

    b = raft.build()
    qp = b["qp"]
    contact = result.contact
    # the solve's last LDLᵀ freed (the peak is the solve's) and qdldl's kept
    # analysis too: below newton.SUPERNODAL_DOFS the floor is a fresh qdldl
    # LDLᵀ, its AMD included, as before; above, SuperLU in the order made once
    # per raft (the order itself not timed: 1–2 s at 1e6 dofs)
    qp.newton.solver = qp.newton.factored = qp.newton.analysis = None
    t, cpu = time.perf_counter(), time.process_time()
    qp.newton.factor(contact[qp.soil], contact[qp.floor])
    floor, floor_cpu = time.perf_counter() - t, time.process_time() - cpu
    n = qp.K.shape[0]
    if n - qp.fixed.size > QDLDL_FLOOR_MAX:
        return floor, floor_cpu, None
    springs = np.zeros(n)
    pressing = contact & np.isfinite(b["ks"])
    springs[3 * np.flatnonzero(pressing)] = b["ks"][pressing]
    keep = np.ones(n, bool)
    keep[qp.fixed] = False
    keep[3 * np.flatnonzero(contact & ~np.isfinite(b["ks"]))] = False
    idx = np.flatnonzero(keep)
    A = (qp.K + sp.diags(springs)).tocsc()[idx][:, idx]
    t = time.perf_counter()
    qdldl.Solver(sp.triu(A, format="csc"), upper=True)
    return floor, floor_cpu, time.perf_counter() - t


def raft_job(size, method, queue):
    import resource

    import numpy as np

    from formulations.plates.examples import WINDWARD_K
    from tests.helpers.raft_peers import opensees_raft, pynite_raft

    raft_model(4).solve()              # warm-up: imports, compiled kernels
    raft = raft_model(size)
    raft.build()
    n = 3 * raft.mesh.nodes.shape[0]
    row = dict(family="raft", n=n, method=method, iterations=None, error=None, ldlt=None)
    t, cpu = time.perf_counter(), time.process_time()
    if method == "qpcontact":
        r = raft.solve()
        wall, cpu = time.perf_counter() - t, time.process_time() - cpu
        floor, floor_cpu, qdldl_floor = _raft_floor(raft, r) if r.ok else (None, None, None)
        status = f"certified ({r.method})" if r.ok else r.message
        status += f"; CPU {cpu:.3g} s"
        if r.ok:
            how = "SuperLU, nested dissection" if raft.build()["qp"].newton.supernodal \
                else "qdldl+AMD"
            status += (f"; floor {floor:.3g} s, CPU {floor_cpu:.3g} s ({how}), qdldl+AMD "
                       + ("not measured" if qdldl_floor is None else f"{qdldl_floor:.3g} s"))
        row.update(time=wall, method_time=r.wall_time, ok=r.ok, status=status, error=r.error,
                   ldlt=floor)
    else:
        peer = pynite_raft if method == "pynite" else opensees_raft
        w, _, converged, iterations = peer(raft, WINDWARD_K)
        wall = time.perf_counter() - t
        status = "converged" if converged else "did not converge"
        if converged:      # how far from the certified answer
            ours = raft.solve()
            status += (f"; Δw {np.max(np.abs(w - ours.w)) / np.max(np.abs(ours.w)):.1e} of max w, "
                       f"{int(np.count_nonzero((w < 0) != ours.lifted))} nodes lifted differently")
        row.update(time=wall, method_time=wall, ok=converged, status=status, iterations=iterations)
    row["peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    queue.put(row)


def _final_block_ldlt(problem, x) -> float:
    """Seconds for one LDLᵀ (the faster of QDLDL+AMD and SuperLU+MMD) of the
    final free block: the bounded components strictly inside their bounds
    and every free component."""
    import numpy as np
    import qdldl
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from qpcontact import LCP

    if isinstance(problem, LCP):
        P, free = problem.M, x > 0
    else:
        P = problem.P
        lb = problem.lb
        bounded = np.isfinite(lb)
        lb0 = np.where(bounded, lb, 0.0)
        free = ~bounded | (x > lb0 + 1e-12 * np.maximum(np.abs(lb0), 1.0))
    idx = np.flatnonzero(free)
    if idx.size == 0:
        return 0.0
    B = sp.csc_matrix(P)[idx][:, idx].tocsc()
    t = time.perf_counter()
    qdldl.Solver(sp.triu(B, format="csc"), upper=True)
    t_q = time.perf_counter() - t
    t = time.perf_counter()
    spla.splu(B, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
              options={"SymmetricMode": True})
    t_s = time.perf_counter() - t
    return min(t_q, t_s)


def job(family, size, method, progress, queue, rigidity=1.0):
    import resource

    from qpcontact import solve

    if family == "raft":
        return raft_job(size, method, queue)
    # warm-up on a small instance: imports, compiled kernels, the registry —
    # costs paid once per process, not per problem; a mesh of a few levels
    # and a second load on it, so that neither timed solve pays them
    from qpcontact import LCP

    small = build(family, 31 if family != "signorini" else 2)
    solve(small, method=method)
    if hasattr(small, "n"):
        solve(LCP.with_structure(small.structure, small.q, small.q_terms), method=method)
    problem = build(family, size, rigidity)
    opts = {"progress": lambda line: print(f"    {line}", flush=True)} \
        if progress and method in ("ip-bpp", "mg-bpp") else {}
    t = time.perf_counter()
    # the row's limit is the parent's kill (run_one); solve's own default
    # of 60 s would end the 1e6 rows (the plate at D = 1: 71 s of CPU, 1 020 s
    # of wall before its W-cycles), now that the exact methods keep it
    sol = solve(problem, method=method, accuracy="high", time_limit=None, **opts)
    wall = time.perf_counter() - t
    is_lcp = hasattr(problem, "n")
    x = sol.z if is_lcp else sol.x
    block = (_final_block_ldlt(problem, x) if sol.ok and method in ("bpp", "ip-bpp", "mg-bpp", "auto")
             else None)
    n = problem.n if is_lcp else problem.P.shape[0]
    row = dict(family=family, n=n, method=method, time=wall, method_time=sol.wall_time,
               ok=sol.ok, status=sol.status,
               iterations=sol.iterations,
               error=None if sol.certificate is None else sol.certificate.error,
               ldlt=block)
    if is_lcp and method in ("bpp", "ip-bpp", "mg-bpp", "auto"):
        # the next load case on the same M: an LCP sharing the first one's
        # structure (what a method kept of M alone — mg-bpp's multilevel
        # setup, |M| — is not built again), its own floor
        other = build(family, size, rigidity, NEXT_LOAD)
        again = LCP.with_structure(problem.structure, other.q, other.q_terms)
        t = time.perf_counter()
        sol = solve(again, method=method, accuracy="high", time_limit=None, **opts)
        row.update(next_time=time.perf_counter() - t, next_ok=sol.ok,
                   next_ldlt=_final_block_ldlt(again, sol.z) if sol.ok else None)
    row["peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    queue.put(row)


def run_one(family, size, method, limit, progress, rigidity=1.0):
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    p = ctx.Process(target=job, args=(family, size, method, progress, queue, rigidity))
    t = time.perf_counter()
    p.start()
    p.join(limit)
    def no_answer(status):
        return dict(family=family, n=None, method=method, time=time.perf_counter() - t,
                    method_time=None, ok=False,
                    status=status, iterations=None, error=None, ldlt=None, peak_mb=None)

    if p.is_alive():
        p.kill()
        p.join()
        return no_answer(f"killed at {limit:.0f} s")
    try:
        return queue.get(timeout=5)
    except Exception:   # the child died (out of memory)
        return no_answer(f"died (exit code {p.exitcode})")


def _read_csv(path) -> list:
    """Rows of an earlier run's scale.csv, typed as main() makes them."""
    import csv

    def value(key, text):
        if text in ("", "None"):
            return None
        if key in ("family", "method", "status"):
            return text
        if key == "ok":
            return text == "True"
        if key in ("size", "n", "iterations"):
            return int(float(text))
        return float(text)

    with open(path, newline="") as f:
        return [{k: value(k, v) for k, v in row.items()} for row in csv.DictReader(f)]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="small sizes (n ~ 1e3 .. 1e4)")
    ap.add_argument("--membrane", default=None, help="grid sides, e.g. 100,316")
    ap.add_argument("--plate", default=None)
    ap.add_argument("--block", default=None, help="3-D block: elements per side, e.g. 16,20")
    ap.add_argument("--raft", default=None, help="raft: cells per side, e.g. 57,115 (n = 3 (c+1)²)")
    ap.add_argument("--rigidity", type=float, default=1.0,
                    help="the membrane's tension or the plate's D (K = D L²), e.g. 0.05")
    ap.add_argument("--methods", default=None,
                    help="solve() methods (default bpp, ip-bpp, mg-bpp and the QP backends); "
                         "on rafts qpcontact, pynite, opensees (default all three)")
    ap.add_argument("--shapes", default="dome",
                    help="obstacle shapes for membrane and plate, e.g. dome,bumps,ridge")
    ap.add_argument("--backends-max", type=float, default=2e5,
                    help="run the QP backends up to this many unknowns")
    ap.add_argument("--limit", type=float, default=120.0, help="seconds per run (killed after)")
    ap.add_argument("--out", default="out/scale")
    ap.add_argument("--replot", nargs="+", metavar="CSV",
                    help="draw the plot (into --out) from earlier runs' scale.csv files; run nothing")
    args = ap.parse_args(argv)
    if args.replot:
        rows = [r for path in args.replot for r in _read_csv(path)]
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        _plot(rows, out / "scale.png")
        print(f"wrote {out / 'scale.png'}")
        return 0
    quick = args.quick
    sizes = {"membrane": args.membrane or ("30,100" if quick else "100,316"),
             "plate": args.plate or ("30,100" if quick else "100,316"),
             "signorini": args.block or ("8,16" if quick else "16,20")}
    if any(v is not None for v in (args.membrane, args.plate, args.block, args.raft)):
        sizes = {k: v for k, v, given in (("membrane", sizes["membrane"], args.membrane),
                                          ("plate", sizes["plate"], args.plate),
                                          ("signorini", sizes["signorini"], args.block),
                                          ("raft", args.raft, args.raft)) if given}
    lcp_methods = ("bpp", "ip-bpp", "mg-bpp") + tuple(BACKENDS)
    methods = ([m for m in args.methods.split(",") if m] if args.methods is not None
               else list(lcp_methods) + list(RAFT_METHODS))
    shapes = [s for s in args.shapes.split(",") if s]
    families = []
    for family, spec in sizes.items():
        for shape in (shapes if family in ("membrane", "plate") else [""]):
            name = family if shape in ("", "dome") else f"{family}-{shape}"
            families.append((name, spec))
    rows = []
    for family, spec in families:
        for size in (int(s) for s in spec.split(",") if s):
            group = []
            unknowns = {"signorini": 3 * size ** 3, "raft": 3 * (size + 1) ** 2}.get(family,
                                                                                  size ** 2)
            for method in methods:
                if method in ("bpp", "mg-bpp") and family == "signorini":
                    continue   # they take LCPs: the block's LCP would be its dense Schur complement
                if (method in RAFT_METHODS) != (family == "raft"):
                    continue
                if method in BACKENDS and unknowns > args.backends_max:
                    continue
                print(f"{family} {size}: {method} ...", flush=True)
                r = run_one(family, size, method, args.limit, progress=size >= 500,
                            rigidity=args.rigidity)
                r["size"] = size
                group.append(r)
            n = next((r["n"] for r in group if r["n"]), None)
            certified = [r["time"] for r in group if r["method"] in BACKENDS and r["ok"]]
            best_backend = min(certified) if certified else None
            for r in group:
                r["n"] = n
                r["vs_ldlt"] = r["time"] / r["ldlt"] if r.get("ldlt") else None
                r["method_vs_ldlt"] = r["method_time"] / r["ldlt"] if r.get("ldlt") else None
                r["next_vs_ldlt"] = (r["next_time"] / r["next_ldlt"]
                                     if r.get("next_ldlt") and r.get("next_ok") else None)
                r["vs_backend"] = (r["time"] / best_backend if best_backend and r["ok"]
                                   and r["method"] not in BACKENDS else None)
                if family == "raft" and r["method"] != "qpcontact":   # theirs against ours
                    ours = next((o for o in group if o["method"] == "qpcontact" and o["ok"]), None)
                    r["vs_backend"] = ours["time"] / r["time"] if ours and r["ok"] else None
            rows += group
    if not rows:
        print(f"scale.py: no run matched: --methods {args.methods} names none for "
              f"{', '.join(sizes)} (rafts take {', '.join(RAFT_METHODS)}; the obstacle "
              "problems solve()'s methods)", file=sys.stderr)
        return 2
    fmt = (lambda v, f: "" if v is None else format(v, f))
    if args.rigidity != 1.0:
        print(f"\n(membrane tension / plate rigidity {args.rigidity:g})")
    print("\n| family | n | method | time s | status | iterations | certificate | "
          "time / one LDLᵀ of final block | method's own time / LDLᵀ | "
          "time / fastest certified backend (rafts: ours / theirs) | "
          f"next load (× {NEXT_LOAD:g}, same M) s | next load / its LDLᵀ | peak MB |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['family']} | {r['n'] or ''} | {r['method']} | {r['time']:.3f} | {r['status']} | "
              f"{fmt(r['iterations'], 'd')} | {fmt(r['error'], '.1e')} | {fmt(r['vs_ldlt'], '.1f')} | "
              f"{fmt(r['method_vs_ldlt'], '.1f')} | {fmt(r['vs_backend'], '.2f')} | "
              f"{fmt(r.get('next_time'), '.3f')} | {fmt(r.get('next_vs_ldlt'), '.1f')} | "
              f"{fmt(r['peak_mb'], '.0f')} |")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    from qpcontact.core.files import write_csv_atomic

    write_csv_atomic(out / "scale.csv", rows,
                     ["family", "size", "n", "method", "time", "ok", "status", "iterations",
                      "error", "ldlt", "vs_ldlt", "method_time", "method_vs_ldlt", "vs_backend",
                      "next_time", "next_ldlt", "next_vs_ldlt", "peak_mb"])
    _plot(rows, out / "scale.png")
    print("\nFitted slopes (time ∝ n^slope, least squares on the certified rows):")
    for (family, method), slope in _slopes(rows).items():
        print(f"  {family:18s} {method:10s} {slope:.2f}")
    print(f"\nwrote {out / 'scale.csv'} and {out / 'scale.png'}")
    return 0


def _slopes(rows) -> dict:
    """(family, method) -> the slope of log time against log n, where the
    method certified at two sizes or more; "LDLᵀ floor" for the floor."""
    import numpy as np

    out = {}
    for family in dict.fromkeys(r["family"] for r in rows):
        series = {m: sorted((r["n"], r["time"]) for r in rows
                            if r["family"] == family and r["method"] == m and r["ok"] and r["n"])
                  for m in dict.fromkeys(r["method"] for r in rows)}
        series["LDLᵀ floor"] = _floor(rows, family)
        for method, pts in series.items():
            if len({n for n, _ in pts}) >= 2:
                n, t = np.log(np.array(pts, dtype=float)).T
                out[(family, method)] = float(np.polyfit(n, t, 1)[0])
    return out


def _floor(rows, family) -> list:
    """(n, seconds) of one LDLᵀ of the final free block, per size."""
    best = {}
    for r in rows:
        if r["family"] == family and r.get("ldlt") and r["n"]:
            best[r["n"]] = min(best.get(r["n"], float("inf")), r["ldlt"])
    return sorted(best.items())


def _plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure

    families = list(dict.fromkeys(r["family"] for r in rows))
    colour = {m: f"C{k}" for k, m in enumerate(sorted({r["method"] for r in rows}))}
    slopes = _slopes(rows)
    cols = min(3, len(families))
    nrows = -(-len(families) // cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(5.2 * cols, 5.8 * nrows), squeeze=False)
    for ax in axes.ravel()[len(families):]:
        ax.set_visible(False)
    for ax, fam in zip(axes.ravel(), families):
        for method in sorted({r["method"] for r in rows if r["family"] == fam}):
            pts = sorted((r["n"], r["time"]) for r in rows
                         if r["family"] == fam and r["method"] == method and r["ok"] and r["n"])
            if pts:
                slope = slopes.get((fam, method))
                label = method + ("" if slope is None else f" (slope {slope:.2f})")
                ax.loglog(*zip(*pts), "o-", label=label, color=colour[method])
        floor = _floor(rows, fam)
        if floor:
            slope = slopes.get((fam, "LDLᵀ floor"))
            ax.loglog(*zip(*floor), "k--", lw=1.2,
                      label="one LDLᵀ of the final block"
                      + ("" if slope is None else f" (slope {slope:.2f})"))
        ax.set_title(fam)
        ax.set_xlabel("unknowns n")
        ax.set_ylabel("time to a certified answer [s]")
        ax.grid(True, which="both", alpha=0.3)
        # below the axes: inside, it hid the lowest lines (the floor, mg-bpp)
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2,
                  frameon=False)
    fig.tight_layout()
    save_figure(fig, path)


if __name__ == "__main__":
    raise SystemExit(main())
