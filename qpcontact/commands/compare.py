"""What accuracy costs in time: every instance × method × accuracy, certified,
measured against the exact pivoting solution, written as CSV, Markdown and
work-precision plots.

Instances come from the formulations (entry-point group
``qpcontact.formulations``: each module's ``instances(size, hardness, seed)``)
and from the Siconos LCP set when present.  One *run* is one instance, one
method, one accuracy (a ladder level, or a tolerance of the sweep for the
iterative backends); its row holds the median wall time over repeats, the
certificate error, the distance to the exact solution (in the solution and
in the physical contact forces), whether the active sets agree, success
(certified at the requested accuracy) and otherwise the reason.  A method that
cannot handle the problem class is "not applicable", not failed.

Aggregates follow qpbenchmark (github.com/qpsolvers/qpbenchmark,
``qpbenchmark/report.py`` and ``results.py``): success rate in percent; the
shifted geometric mean (shift 10) of the run time, a run without a point
counted at the time limit, and of the certificate error, a run without a point
counted at the requested tolerance; each mean divided by the best method's.
"""

from __future__ import annotations

import csv
import functools
import os
import platform
import statistics
import time
from pathlib import Path

import numpy as np

from ..cases.instance import Instance
from ..core.progress import ProgressBar

__all__ = ["Instance", "collect_instances", "plan", "run_task", "sweep", "summarize", "report",
           "shgeom", "FIELDS", "LADDER", "TOLERANCES"]

LADDER = ("low", "default", "high")
TOLERANCES = tuple(10.0 ** -k for k in range(2, 13))          # 1e-2 ... 1e-12
QUICK_TOLERANCES = (1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
SHIFT = 10.0                                                   # qpbenchmark's shift

FIELDS = ("instance", "formulation", "size", "n", "method", "family", "level", "tol",
          "applicable", "success", "status", "reason", "time_median", "repeats", "cert_error",
          "dist_solution", "dist_forces", "active_set_agree", "exact_method", "exact_time",
          "timed_on", "machine", "versions")
TIMING_FIELDS = ("time_median", "exact_time", "timed_on", "machine")


def shgeom(values, shift: float = SHIFT) -> float:
    """Shifted geometric mean exp(mean(log(v + shift))) - shift (qpbenchmark's shgeom)."""
    v = np.asarray(values, float)
    return float(np.exp(np.mean(np.log(v + shift))) - shift)


def _siconos_instances(directory):
    from ..io import read_siconos_lcp

    d = Path(directory) if directory else None
    if d is None or not d.is_dir():
        return []
    return [Instance(f"siconos/{p.stem}", "siconos", "file", read_siconos_lcp(p))
            for p in sorted(d.glob("*.dat"))]


#: the quick sweep (``make demo``'s) leaves out friction problems with more contacts
#: (Capsules, Box_Stacks: 82-286 contacts, 160 of its 264 s on 2 cores) and other
#: problems with more unknowns (meshes/signorini-6, n = 441: 30 s) than these
QUICK_FRICTION_CONTACTS, QUICK_MAX_N = 50, 200


def _friction_instances(directory, quick: bool):
    """The Siconos/FCLIB friction collection: FrictionProblem instances."""
    from ..io import read_problem

    d = Path(directory) if directory else None
    if d is None or not d.is_dir():
        return []
    out = []
    for p in sorted(d.glob("*")):
        if p.suffix not in (".dat", ".hdf5"):
            continue
        prob = read_problem(p)
        if prob.n_contacts == 0 or (quick and prob.n_contacts > QUICK_FRICTION_CONTACTS):
            continue
        out.append(Instance(f"friction/{p.stem}", "friction", f"{prob.dim}D", prob))
    return out


def collect_instances(quick: bool = True, formulations=None, siconos_dir=None, seed: int = 0,
                      friction_dir=None):
    """Instances of every installed formulation (sizes small, or small to large),
    plus the Siconos LCP set from ``siconos_dir`` and the friction
    collection from ``friction_dir`` (formulation "friction", solved by the
    friction methods); by default the data sets ``siconos-lcp`` and
    ``siconos-fc`` where :func:`qpcontact.core.files.find_data` finds them
    (none: no instances from them)."""
    from importlib.metadata import entry_points

    from ..core.files import find_data

    sizes = ("small",) if quick else ("small", "medium", "large")
    out = []
    for ep in sorted(entry_points(group="qpcontact.formulations"), key=lambda e: e.name):
        if formulations and ep.name not in formulations:
            continue
        module = ep.load()
        if not hasattr(module, "instances"):
            continue
        for size in sizes:
            for hardness in ("easy", "hard"):
                out.extend(i for i in module.instances(size, hardness, seed)
                           if not (quick and _unknowns(i) > QUICK_MAX_N))
    if formulations is None or "siconos" in formulations:
        out.extend(i for i in _siconos_instances(siconos_dir or find_data("siconos-lcp"))
                   if not (quick and _unknowns(i) > QUICK_MAX_N))
    if formulations is None or "friction" in formulations:
        out.extend(_friction_instances(friction_dir or find_data("siconos-fc"), quick))
    return out


def _unknowns(inst) -> int:
    """An LCP's n, a QP's variables, a friction problem's reaction components."""
    p = inst.problem
    return p.dim * p.n_contacts if _is_friction(inst) else int(getattr(p, "n", None) or p.P.shape[0])


def _is_friction(inst) -> bool:
    from ..core.friction_problem import FrictionProblem

    return isinstance(inst.problem, FrictionProblem)


def _friction_methods(inst, names):
    """Every installed method that takes the instance's form (local 2-D or
    3-D, or global kept without W), or those of ``names``; Lemke on faceted
    3-D cones only up to 100 contacts (its LCP's pivots grow with the facets:
    11 828 pivots, 183 s, on 286 contacts)."""
    from ..dispatch.routes import applicable
    from ..solvers.registry import methods as installed

    p = inst.problem
    pool = [name for name, m in installed().items() if applicable(p, m)] + ["auto"]
    chosen = [m for m in names if m in pool] if names else pool
    return [m for m in chosen if not (m == "lemke" and p.dim == 3 and p.n_contacts > 100)]


def plan(instances, methods=None, quick: bool = True):
    """The list of tasks (instance, method name, level); level is a ladder name
    or a tolerance (iterative backends only).  Each instance gets the methods
    that take its kind (an LCP method that refuses its M is "not applicable"
    in the report)."""
    from ..dispatch.routes import kind_of
    from ..solvers.registry import methods as installed

    avail = installed()
    names = list(methods) if methods else [m for m in avail if not (quick and m.startswith("cvxpy:"))]
    tols = QUICK_TOLERANCES if quick else TOLERANCES
    tasks = []
    for inst in instances:
        if _is_friction(inst):
            tasks += [(inst, name, level) for name in _friction_methods(inst, methods)
                      for level in LADDER]
            continue
        kind = kind_of(inst.problem)
        for name in names:
            spec = avail.get(name)
            if spec is None or not spec.solves(kind):
                continue
            levels = list(LADDER) + ([] if spec.exact else [float(t) for t in tols])
            for level in levels:
                tasks.append((inst, name, level))
    return tasks


def _key(inst_name, method, level) -> tuple:
    return (inst_name, method, _level_str(level))


def _level_str(level) -> str:
    return level if isinstance(level, str) else f"{float(level):.0e}"


@functools.lru_cache(maxsize=None)      # metadata lookups took 20 of 44 s on the Siconos set
def _versions(method_name: str) -> str:
    from importlib.metadata import PackageNotFoundError, version

    from ..solvers.registry import all_methods

    pkgs = ["qpcontact", "numpy", "scipy", "qpsolvers"]
    m = all_methods().get(method_name)
    if m is not None:
        pkgs.append(m.package)
    out = []
    for p in dict.fromkeys(pkgs):
        try:
            out.append(f"{p}={version(p)}")
        except PackageNotFoundError:
            pass
    return " ".join(out)


_EXACT_CACHE: dict = {}


def _exact(inst: Instance):
    """The exact pivoting solution and its time (bpp for SPD LCPs, Lemke
    otherwise, Lemke on the dual LCP for QPs), cached per process."""
    from ..core.problems import LCP
    from ..dispatch.driver import solve

    hit = _EXACT_CACHE.get(inst.name)
    if hit is not None:
        return hit
    p = inst.problem
    method = "bpp" if isinstance(p, LCP) and p.is_symmetric and p.is_positive_definite else "lemke"
    t0 = time.perf_counter()
    sol = solve(p, method=method, accuracy="high")
    t = time.perf_counter() - t0
    x = getattr(sol, "z", None) if isinstance(p, LCP) else sol.x
    # A QP's exact answer comes back through its dual LCP; on badly scaled QPs the
    # recovered primal is certified near 1e-9 rather than below it: still the reference.
    res = (x if sol.certificate is not None and sol.error <= 1e-7 else None, method, t, sol)
    _EXACT_CACHE[inst.name] = res
    return res


def _forces(inst: Instance, x, problem):
    if x is None:
        return None
    kind, k = inst.forces
    if kind == "w":
        return np.asarray(problem.w(x))[:k]
    return np.asarray(x)


def _scale(inst: Instance, x_exact):
    from ..core.problems import LCP

    p = inst.problem
    s = float(np.max(np.abs(x_exact))) if x_exact is not None and x_exact.size else 0.0
    if isinstance(p, LCP) and p.matrix_scale > 0:
        s = max(s, float(np.max(np.abs(p.q))) / p.matrix_scale)
    return s if s > 0 else 1.0


def run_task(task, repeats: int = 3, time_limit: float = 10.0) -> dict:
    """One run; never raises (an exception becomes the row's reason)."""
    from ..core.accuracy import resolve_accuracy
    from ..core.errors import NotConvexError, NotSymmetricError, QpcontactError
    from ..solvers.registry import get_method
    from ..dispatch.driver import solve

    inst, name, level = task
    acc = level
    _, tol = resolve_accuracy(acc)
    if _is_friction(inst):
        return _run_friction_task(inst, name, level, tol, repeats, time_limit)
    spec = get_method(name)
    p = inst.problem
    row = _row(inst, name, spec.family, level, tol, p.n if hasattr(p, "n") else p.q.size)
    x_exact, exact_method, exact_time, _ = _exact(inst)
    row.update(exact_method=exact_method, exact_time=exact_time)
    times = []
    try:
        sol = _timed(lambda: solve(p, method=name, accuracy=acc), times, repeats, time_limit, name)
    except (NotSymmetricError, NotConvexError) as exc:
        row.update(applicable=False, status="not applicable", reason=str(exc).split(";")[0])
        return row
    except QpcontactError as exc:
        row.update(applicable=False, status="not applicable", reason=f"{type(exc).__name__}: {exc}")
        return row
    except Exception as exc:  # a backend crash is a result, not the end of the sweep
        row.update(status="exception", reason=f"{type(exc).__name__}: {exc}"[:300],
                   time_median=statistics.median(times) if times else np.nan)
        return row
    row.update(time_median=statistics.median(times), repeats=len(times), status=sol.status,
               cert_error=sol.error, success=bool(sol.ok))
    x = getattr(sol, "z", None) if hasattr(sol, "w") else getattr(sol, "x", None)
    if not sol.ok:
        row["reason"] = sol.message[:300]
    if x is not None and x_exact is not None:
        scale = _scale(inst, x_exact)
        row["dist_solution"] = float(np.max(np.abs(x - x_exact)) / scale)
        f, f_ex = _forces(inst, x, p), _forces(inst, x_exact, p)
        fs = max(float(np.max(np.abs(f_ex))) if f_ex.size else 0.0, 1e-300)
        row["dist_forces"] = float(np.max(np.abs(f - f_ex)) / fs) if f_ex.size else 0.0
        thr = 1e-6 * fs
        row["active_set_agree"] = bool(np.array_equal(f > thr, f_ex > thr))
    elif x_exact is None:
        row["reason"] = (row["reason"] + "; " if row["reason"] else "") + "no exact reference"
    return row


_FRICTION_EXACT: dict = {}


def _friction_exact(inst):
    """Lemke on the exact 2-D LCP, cached; 3-D has no exact route (cones are
    not polyhedral)."""
    from ..dispatch.driver import solve

    if inst.name not in _FRICTION_EXACT:
        p = inst.problem
        hit = (None, "", np.nan)
        if p.dim == 2:
            t0 = time.perf_counter()
            sol = solve(p, "lemke", accuracy=1e-10)
            if sol.ok:
                hit = (sol.r, "lemke (exact 2-D LCP)", time.perf_counter() - t0)
        _FRICTION_EXACT[inst.name] = hit
    return _FRICTION_EXACT[inst.name]


def _run_friction_task(inst, name, level, tol, repeats, time_limit) -> dict:
    """A friction run at the level's tolerance, certified by the friction
    measures (natural map and componentwise); distances to Lemke's exact
    answer in 2-D."""
    from ..core.errors import QpcontactError
    from ..dispatch.driver import solve

    p = inst.problem
    row = _row(inst, name, "friction", level, tol, p.dim * p.n_contacts)
    r_exact, exact_method, exact_time = _friction_exact(inst)
    row.update(exact_method=exact_method, exact_time=exact_time)
    times = []
    try:
        sol = _timed(lambda: solve(p, name, accuracy=tol), times, repeats, time_limit, name)
    except QpcontactError as exc:
        row.update(applicable=False, status="not applicable", reason=f"{type(exc).__name__}: {exc}")
        return row
    except Exception as exc:  # a backend crash is a result, not the end of the sweep
        row.update(status="exception", reason=f"{type(exc).__name__}: {exc}"[:300])
        return row
    row.update(time_median=statistics.median(times), repeats=len(times), status=sol.status,
               cert_error=sol.error, success=bool(sol.ok))
    if not sol.ok:
        row["reason"] = sol.message[:300]
    if sol.r is not None and r_exact is not None:
        scale = max(float(np.max(np.abs(r_exact))), 1e-300)
        row["dist_solution"] = row["dist_forces"] = float(np.max(np.abs(sol.r - r_exact)) / scale)
        rn, rn_ex = sol.r[0::p.dim], r_exact[0::p.dim]
        row["active_set_agree"] = bool(np.array_equal(rn > 1e-6 * scale, rn_ex > 1e-6 * scale))
    return row


def _row(inst, name, family, level, tol, n) -> dict:
    """A run's row before it runs: what it is, and every result field empty."""
    return dict(instance=inst.name, formulation=inst.formulation, size=inst.size, n=n,
                method=name, family=family, level=_level_str(level), tol=tol, applicable=True,
                success=False, status="", reason="", time_median=np.nan, repeats=0,
                cert_error=np.nan, dist_solution=np.nan, dist_forces=np.nan,
                active_set_agree="", exact_method="", exact_time=np.nan, timed_on=_where(),
                machine=f"{platform.node()} {platform.machine()} {os.cpu_count()} cpu",
                versions=_versions(name))


_WARM: set = set()      # the methods already called once, untimed, in this process


def _timed(call, times: list, repeats: int, time_limit: float, name: str = ""):
    """``call()`` up to ``repeats`` times, each wall time appended to
    ``times`` (stopping once one exceeds ``time_limit``); the last answer.
    The method ``name``'s first call in a process runs untimed first: numba
    compiling or loading its kernels and the backend's import are no run's
    work (mg-bpp's first run read 9.6 s, its next ones under 0.1 s)."""
    if name not in _WARM:
        call()
        _WARM.add(name)
    sol = None
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        sol = call()
        times.append(time.perf_counter() - t0)
        if times[-1] > time_limit:
            break
    return sol


def _where() -> str:
    try:
        from distributed import get_worker

        return f"dask worker {get_worker().address}"
    except (ImportError, ValueError):
        return "local"


def _read_rows(path: Path) -> list[dict]:
    if not path.exists():
        return []
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _write_rows(path: Path, rows: list[dict]) -> None:
    """Atomic: a temporary file, then a rename (an interrupted sweep keeps its CSV)."""
    from ..core.files import write_csv_atomic

    rows = sorted(rows, key=lambda r: (r["instance"], r["method"], _level_order(r["level"])))
    write_csv_atomic(path, rows, FIELDS)


def _level_order(level: str):
    return (LADDER.index(level), 0.0) if level in LADDER else (len(LADDER), -float(level))


def sweep(out_dir, *, quick: bool = True, methods=None, formulations=None, siconos_dir=None,
          friction_dir=None, repeats: int | None = None, resume: bool = False, workers: int = 0,
          scheduler: str | None = None, time_limit: float = 10.0, progress: bool = True,
          instances=None, flush_every: int = 50) -> Path:
    """Run the sweep into ``out_dir/results.csv`` (module docstring); returns its path.

    ``resume``: keep the rows already in the CSV and skip those runs.
    ``workers`` > 0: a local Dask cluster; ``scheduler``: an existing one.
    """
    out = Path(out_dir)
    from ..core.files import make_folder

    make_folder(out)
    path = out / "results.csv"
    repeats = repeats or (1 if quick else 3)
    insts = instances if instances is not None else collect_instances(quick, formulations, siconos_dir,
                                                                      friction_dir=friction_dir)
    tasks = plan(insts, methods, quick)
    rows = _read_rows(path) if resume else []
    done = {(r["instance"], r["method"], r["level"]) for r in rows}
    todo = [t for t in tasks if _key(t[0].name, t[1], t[2]) not in done]
    bar = ProgressBar(len(todo), "compare runs", progress)
    results = (_dask_map(todo, repeats, time_limit, workers, scheduler) if workers or scheduler
               else (run_task(task, repeats, time_limit) for task in todo))
    try:
        for k, row in enumerate(results, 1):
            rows.append(row)
            bar.advance()
            if k % flush_every == 0:
                _write_rows(path, rows)
    finally:
        _write_rows(path, rows)
        bar.close()
    return path


def _dask_map(tasks, repeats, time_limit, workers, scheduler):
    from ..core.cluster import dask_client

    with dask_client(workers, scheduler) as client:
        from distributed import as_completed

        futures = [client.submit(run_task, t, repeats, time_limit, pure=False) for t in tasks]
        for fut in as_completed(futures):
            yield fut.result()


# -- aggregation and report ------------------------------------------------------------

def _f(x) -> float:
    try:
        return float(x)
    except (TypeError, ValueError):
        return float("nan")


def _b(x) -> bool:
    return x is True or str(x) == "True"


def summarize(rows: list[dict], time_limit: float = 10.0) -> dict:
    """{formulation: {level: {method: stats}}} over the ladder levels, with
    qpbenchmark's aggregates: success rate [%], shifted geometric means of time
    and certificate error (shift 10; a run without a point counted at the time
    limit / at the tolerance), each divided by the best method's; plus the
    number of applicable instances and the exact oracle's time."""
    out = {}
    forms = sorted({r["formulation"] for r in rows})
    for form in forms:
        fr = [r for r in rows if r["formulation"] == form]
        out[form] = {}
        for level in LADDER:
            per = {}
            for m in sorted({r["method"] for r in fr}):
                rs = [r for r in fr if r["method"] == m and r["level"] == level and _b(r["applicable"])]
                if not rs:
                    continue
                tol = _f(rs[0]["tol"])
                found = [bool(np.isfinite(_f(r["cert_error"]))) for r in rs]  # a point came back
                t = [_f(r["time_median"]) if ok else time_limit for r, ok in zip(rs, found)]
                e = [_f(r["cert_error"]) if ok else tol for r, ok in zip(rs, found)]
                e = [min(x, 1e300) for x in e]
                per[m] = dict(runs=len(rs), success=100.0 * np.mean([_b(r["success"]) for r in rs]),
                              time=shgeom(t), error=shgeom(e),
                              median_time=statistics.median(t))
            if per:
                best_t = min(v["time"] for v in per.values())
                best_e = min(v["error"] for v in per.values())
                for v in per.values():
                    v["time_rel"] = v["time"] / best_t if best_t > 0 else np.nan
                    v["error_rel"] = v["error"] / best_e if best_e > 0 else np.nan
            out[form][level] = per
        ex = {}
        for r in fr:
            if np.isfinite(_f(r["exact_time"])):
                ex[r["instance"]] = _f(r["exact_time"])
        out[form]["_exact_time"] = shgeom(list(ex.values())) if ex else np.nan
        out[form]["_exact_count"] = len(ex)
        out[form]["_instances"] = len({r["instance"] for r in fr})
        out[form]["_not_applicable"] = sorted({r["method"] for r in fr if not _b(r["applicable"])})
    return out


def report(csv_path, out_dir=None, time_limit: float = 10.0) -> Path:
    """Write report.md and the work-precision plots next to the CSV; returns report.md."""
    csv_path = Path(csv_path)
    out = Path(out_dir) if out_dir else csv_path.parent
    rows = _read_rows(csv_path)
    summ = summarize(rows, time_limit)
    lines = ["# Solver comparison: what accuracy costs in time", ""]
    machines = sorted({r["machine"] for r in rows})
    timed = sorted({r["timed_on"].split(" tcp")[0] for r in rows})
    lines += [f"- runs: {len(rows)}; machine: {', '.join(machines)}; timed on: {', '.join(timed)}",
              f"- versions: {sorted({r['versions'] for r in rows})[0] if rows else ''}",
              "- aggregates as in qpbenchmark (github.com/qpsolvers/qpbenchmark, report.py and "
              "results.py): success rate [%]; shifted geometric mean, shift 10, of the time "
              f"(a run without a point counted at the time limit, {time_limit:g} s) and of the "
              "certificate error (a run without a point counted at the tolerance), each divided by "
              "the best method's (1.0 = best).  Success = certified at the requested accuracy.",
              ""]
    for form, levels in summ.items():
        lines += [f"## {form}", "",
                  f"{levels['_instances']} instances; "
                  + ("exact pivoting oracle: none timed (friction: Lemke's exact LCP exists in "
                     "2-D only)." if np.isnan(levels["_exact_time"]) else
                     f"exact pivoting oracle: shifted geometric mean time "
                     f"{levels['_exact_time'] * 1e3:.3f} ms over the {levels['_exact_count']} "
                     f"instance(s) that have one.")
                  + (f"  Not applicable somewhere: {', '.join(levels['_not_applicable'])}."
                     if levels["_not_applicable"] else ""), ""]
        for level in LADDER:
            per = levels.get(level) or {}
            if not per:
                continue
            lines += [f"### accuracy \"{level}\"", "",
                      "| method | runs | success [%] | time (shgeom, rel.) | error (shgeom, rel.) "
                      "| median time [ms] |", "|---|---|---|---|---|---|"]
            for m, v in sorted(per.items(), key=lambda kv: (-kv[1]["success"], kv[1]["time"])):
                lines.append(f"| {m} | {v['runs']} | {v['success']:.1f} | {v['time_rel']:.2f} | "
                             f"{v['error_rel']:.3g} | {v['median_time'] * 1e3:.3f} |")
            lines.append("")
        for png in _plots(rows, out, form):
            lines += [f"![{png.stem}]({png.name})", ""]
    path = out / "report.md"
    tmp = path.with_suffix(".md.tmp")
    tmp.write_text("\n".join(lines))
    os.replace(tmp, path)
    return path


def _plots(rows, out: Path, form: str):
    """Work-precision plots (:mod:`qpcontact.plots.work_precision`): median
    certificate error against median time over the instances, per method,
    one plot per formulation and size, each method in a colour and marker of
    its own within the plot."""
    from ..core.accuracy import LEVELS
    from ..plots.work_precision import plot_work_precision

    high = LEVELS["high"]
    paths = []
    for size in sorted({r["size"] for r in rows if r["formulation"] == form}):
        rs = [r for r in rows if r["formulation"] == form and r["size"] == size
              and _b(r["applicable"]) and np.isfinite(_f(r["cert_error"]))]
        if not rs:
            continue
        points = {}
        for m in sorted({r["method"] for r in rs}):
            def point(level):
                sel = [r for r in rs if r["method"] == m and r["level"] == level]
                return (statistics.median(_f(r["time_median"]) for r in sel),
                        statistics.median(_f(r["cert_error"]) for r in sel))

            levels = sorted({r["level"] for r in rs if r["method"] == m}, key=_level_order)
            points[m] = {"levels": {lv: point(lv) for lv in levels if lv in LADDER},
                         "sweep": [point(lv) for lv in levels if lv not in LADDER]}
        tols = sorted({r["level"] for r in rs if r["level"] not in LADDER}, key=_level_order)
        n_inst = len({r["instance"] for r in rs})
        path = out / f"wp_{form}_{size}.png".replace("/", "-")
        plot_work_precision(points, path, f"{form}, {size}: work against precision "
                            f"({n_inst} instance{'s' if n_inst != 1 else ''})", target=high,
                            target_label=f"accuracy 'high': {_tol_text(high)}",
                            sweep_range=f"{_tol_text(tols[0])} … {_tol_text(tols[-1])}" if tols else "")
        paths.append(path)
    return paths


def _tol_text(level) -> str:
    """'1e-02' -> '1e-2' (a legend's words, not a CSV key)."""
    return f"{float(level):.0e}".replace("e-0", "e-")
