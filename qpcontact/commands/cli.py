"""Command-line interface: ``qpcontact methods | solve | simulate | sweep | plot | demo | compare | stress``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from ..core.errors import QpcontactError

app = typer.Typer(add_completion=False, no_args_is_help=True,
                  help="Contact and unilateral-constraint problems as certified LCPs and QPs.")
console = Console()
if not console.is_terminal:
    console.width = max(console.width, 120)  # tables stay readable in logs and pipes


def _accuracy(value: str):
    try:
        return float(value)
    except ValueError:
        return value


@app.command("methods")
def methods_cmd(all_: bool = typer.Option(False, "--all", help="Also list known methods that are not installed.")):
    """List the methods usable here: what each one solves, where it is exact, what it needs."""
    from ..solvers.method import PROBLEM_KINDS
    from ..solvers.registry import all_methods

    table = Table(title="qpcontact methods: one registry for every kind (* exact: finite "
                        "termination at an exact answer, up to rounding)")
    for col in ("name", "family", "solves", "LCP's M", "sparse", "algorithm", "notes"):
        table.add_column(col)
    requires = {"monotone": "M+M' PSD", "spd": "sym. PD", "any": "any"}
    order = sorted(all_methods().items(),
                   key=lambda kv: (_FAMILY_ORDER.get(kv[1].family, 9), kv[0]))
    for name, m in order:
        if not (m.available or all_):
            continue
        solves = ", ".join(PROBLEM_KINDS[k] + ("*" if m.exact_on(k) else "") for k in m.problems)
        notes = []
        if m.max_n is not None:
            notes.append(f"n <= {m.max_n}")
        if m.constraints == "lower-bounds":
            notes.append("QPs with lower bounds only")
        if m.needs_isolation:
            notes.append("time limit by a child process")
        if not m.available:
            notes.append(f"not installed: {m.install}")
        table.add_row(name, m.family, solves, requires[m.requires] if m.solves("lcp") else "",
                      "yes" if m.accepts_sparse else "no", m.algorithm,
                      escape("; ".join(notes)))
    console.print(table)


_FAMILY_ORDER = {"pivoting": 0, "friction": 1, "qpsolvers": 2, "cvxpy": 3}


@app.command("solve")
def solve_cmd(
    file: Path = typer.Argument(..., exists=True, dir_okay=False,
                                help="Siconos .dat file (LCP or frictional contact) or FCLIB .hdf5."),
    method: str = typer.Option("auto", "--method", "-m",
                               help="Method name (see `qpcontact methods`: what each one solves)."),
    accuracy: str = typer.Option("high", "--accuracy", "-a", help="low, default, high, or a number."),
):
    """Solve a problem file; print the answer and its certificate. Exit code 1 if not certified."""
    from ..dispatch.driver import solve
    from ..friction.problem import FrictionProblem
    from ..io import read_problem

    try:
        problem = read_problem(file)
        sol = solve(problem, method=method, accuracy=_accuracy(accuracy))
    except QpcontactError as exc:
        console.print(f"[red]error:[/red] {escape(str(exc))}")
        raise typer.Exit(2)
    console.print(f"{file.name}: {escape(repr(problem))}")
    console.print(f"method {sol.method}: status [bold]{sol.status}[/bold] — {escape(sol.message)}")
    console.print(f"backend status {escape(repr(sol.backend_status))}; wall time "
                  f"{sol.stats.get('total_time', sol.wall_time):.4f} s; iterations {sol.iterations}")
    variables = ("r", "u", "v") if isinstance(problem, FrictionProblem) else ("z", "w")
    if getattr(sol, variables[0]) is None:
        raise typer.Exit(1)
    with np.printoptions(precision=10, linewidth=120, threshold=60):
        for name in variables:
            if getattr(sol, name) is not None:
                console.print(f"{name} = {getattr(sol, name)}")
    if sol.certificate is not None:
        for key, val in sol.certificate.as_dict().items():
            if isinstance(val, (int, float, np.floating)) and not isinstance(val, bool):
                console.print(f"  {key:18s} {val: .3e}")
    raise typer.Exit(0 if sol.ok else 1)


@app.command("simulate")
def simulate_cmd(
    scene: Path = typer.Argument(..., help="Scene file (TOML); see docs/scenes.md."),
    out: Path = typer.Option(None, "--out", "-o", help="HDF5 results file (default: out/SCENE.h5)."),
    resume: bool = typer.Option(False, "--resume", help="Continue the run whose last checkpoint "
                                "is in --out (after a kill): the result equals an uninterrupted run."),
    checkpoint_seconds: float = typer.Option(5.0, "--checkpoint-seconds",
                                             help="Write the results so far this often."),
):
    """Run a scene with a progress bar; write its results to an HDF5 file,
    checkpointed as it goes."""
    from ..scenes import load_scene, read_state, write_results

    out = out or Path("out") / (scene.stem + ".h5")
    try:
        sc = load_scene(scene)
        _, run = sc.schema.build(sc)
        total = getattr(run, "total_steps", None)
        state = read_state(out, sc) if resume and out.exists() else None
        if state is not None and state["completed"] == total:
            console.print(f"{out}: already complete ({total} steps); nothing to resume")
            raise typer.Exit(0)
        if state is not None:
            console.print(f"resuming {out} after step {state['completed']} of {total}")

        def checkpoint(result):
            write_results(sc, result, out, completed=len(result.t) - 1, total=total)
        result = run(progress=True, resume=state, checkpoint=checkpoint,
                     checkpoint_seconds=checkpoint_seconds)
    except QpcontactError as exc:
        console.print(f"[red]error:[/red] {escape(str(exc))}")
        raise typer.Exit(2)
    if hasattr(result, "summary"):   # the drum's table; a mechanism's result has none
        console.print(escape(result.summary().table()))
    console.print(f"{sc.schema.formulation} scene {scene.name}: effects "
                  f"{', '.join(sc.effects) or '(none)'}; results in {out}")


@app.command("sweep")
def sweep_cmd(
    scene: Path = typer.Argument(..., help="Scene file (TOML)."),
    vary: list[str] = typer.Option(..., "--vary", help="KEY=v1,v2,... (TOML values; repeat for "
                                   "several keys), e.g. effect.damping.ratio=0.02,0.05 or "
                                   "initial.gaps=[0.01,0.02],[0.02,0.01]"),
    grid: bool = typer.Option(False, "--grid", help="Every combination of the --vary lists "
                              "(default: zip them)."),
    out: Path = typer.Option(None, "--out", "-o", help="Folder (default: out/sweep-SCENE)."),
    workers: int = typer.Option(0, "--workers", help="Run on a local Dask cluster with N processes."),
    scheduler: str = typer.Option(None, "--scheduler", help="Run on an existing Dask cluster."),
):
    """Run variants of a scene (serially or on Dask); one HDF5 file per variant
    and summary.csv."""
    from ..scenes import split_values, sweep

    variations = {}
    for item in vary:
        key, sep, values = item.partition("=")
        if not sep or not values:
            console.print(f"[red]error:[/red] --vary {escape(item)}: expected KEY=v1,v2,...")
            raise typer.Exit(2)
        try:
            variations[key.strip()] = split_values(values)
        except QpcontactError as exc:
            console.print(f"[red]error:[/red] --vary {escape(item)}: {escape(str(exc))}")
            raise typer.Exit(2)
    out = out or Path("out") / f"sweep-{scene.stem}"
    try:
        rows = sweep(scene, variations, out, grid=grid, workers=workers, scheduler=scheduler)
    except QpcontactError as exc:
        console.print(f"[red]error:[/red] {escape(str(exc))}")
        raise typer.Exit(2)
    table = Table(title=f"sweep of {scene.name} ({len(rows)} variants) — files in {out}")
    cols = list(dict.fromkeys(k for r in rows for k in r))
    for c in cols:
        table.add_column(escape(c))
    for r in rows:
        table.add_row(*[f"{r.get(c, ''):.4g}" if isinstance(r.get(c), float) else str(r.get(c, ""))
                        for c in cols])
    console.print(table)


@app.command("plot")
def plot_cmd(
    results: Path = typer.Argument(..., help="HDF5 results file written by `qpcontact simulate`."),
    out: Path = typer.Option(None, "--out", "-o", help="Folder for the figures (default: next to the file)."),
):
    """Draw a results file's standard figures (forces, peaks, energy) without re-running."""
    from ..scenes import plot_results

    try:
        paths = plot_results(results, out)
    except QpcontactError as exc:
        console.print(f"[red]error:[/red] {escape(str(exc))}")
        raise typer.Exit(2)
    for p in paths:
        console.print(f"wrote {p}")


@app.command("demo")
def demo_cmd(accuracy: str = typer.Option("high", "--accuracy", "-a", help="low, default, high, or a number.")):
    """Solve the decomposition paper's examples with every installed method."""
    from .demo import run_demo

    wrong = run_demo(_accuracy(accuracy), console)
    raise typer.Exit(1 if wrong else 0)


@app.command("compare")
def compare_cmd(
    out: str = typer.Option("out/compare", "--out", "-o", help="Output folder: results.csv, report.md, wp_*.png."),
    quick: bool = typer.Option(False, "--quick", help="Demo-sized sweep: small instances up to 200 "
                               "unknowns (friction: 50 contacts), 1 repeat, 6 tolerances, no cvxpy "
                               "(under a minute on 2 cores)."),
    resume: bool = typer.Option(False, "--resume", help="Keep the rows already in results.csv and skip those runs."),
    workers: int = typer.Option(0, "--workers", help="Run on a local Dask cluster with N worker processes."),
    scheduler: str = typer.Option(None, "--scheduler", help="Run on an existing Dask cluster, e.g. tcp://host:8786."),
    methods: str = typer.Option(None, "--methods", help="Comma-separated method names (default: every installed one)."),
    formulations: str = typer.Option(None, "--formulations",
                                     help="Comma-separated: drum, frames, penalty, siconos (default: all)."),
    siconos: str = typer.Option(None, "--siconos", help="Folder of Siconos LCP files (default ../shared/data/siconos-lcp)."),
    repeats: int = typer.Option(None, "--repeats", help="Timed repeats per run (default 1 with --quick, else 3)."),
    time_limit: float = typer.Option(10.0, "--time-limit", help="Seconds: a run without a point counts at this "
                                     "time in the aggregates; repeats stop once a run exceeds it."),
):
    """Sweep instances x methods x accuracies; write a CSV, a Markdown report and work-precision plots."""
    from .compare import report, sweep

    csv_path = sweep(out, quick=quick, methods=methods.split(",") if methods else None,
                     formulations=formulations.split(",") if formulations else None,
                     siconos_dir=siconos, repeats=repeats, resume=resume, workers=workers,
                     scheduler=scheduler, time_limit=time_limit)
    md = report(csv_path, time_limit=time_limit)
    console.print(f"results: {csv_path}\nreport:  {md}\nplots:   {md.parent}/wp_*.png")


@app.command("stress")
def stress_cmd(
    out: str = typer.Option("out/stress", "--out", "-o", help="Output folder: stress.csv, stress.md, stress.png."),
    quick: bool = typer.Option(False, "--quick", help="Small seeded slice: sizes 6 and 24, 2 seeds, accuracy "
                               "high, no cvxpy (about 25 s on 2 cores)."),
    methods: str = typer.Option(None, "--methods", help="Comma-separated method names (default: \"auto\" and every installed one)."),
    families: str = typer.Option(None, "--families", help="Comma-separated families (default: all)."),
    sizes: str = typer.Option(None, "--sizes", help="Comma-separated sizes n (default 8,30,100; --quick 6,24)."),
    seeds: int = typer.Option(None, "--seeds", help="Seeds per family and size (default 200; --quick 2)."),
    time_limit: float = typer.Option(None, "--time-limit", help="Seconds per solve (default 2; --quick 10)."),
    workers: int = typer.Option(2, "--workers", help="Worker processes (each solve runs in one; a crash "
                                "or a hang costs one row)."),
    siconos: str = typer.Option(None, "--siconos", help="Folder of Siconos LCP files (default ../shared/data/siconos-lcp)."),
):
    """Hard cases x methods x accuracies, judged against built-in answers: silent wrong must be 0."""
    import dataclasses

    from .stress import FAMILIES, FULL, QUICK, plot_heatmap, run_stress, write_markdown

    config = QUICK if quick else FULL
    changes = {}
    if methods:
        changes["methods"] = tuple(methods.split(","))
    if families:
        bad = [f for f in families.split(",") if f not in FAMILIES]
        if bad:
            console.print(f"[red]error:[/red] unknown families {bad}; choose from {', '.join(FAMILIES)}")
            raise typer.Exit(2)
        changes["families"] = tuple(families.split(","))
    if sizes:
        changes["sizes"] = tuple(int(v) for v in sizes.split(","))
    if seeds is not None:
        changes["seeds"] = seeds
    if time_limit is not None:
        changes["time_limit"] = time_limit
    if siconos:
        changes["siconos_dir"] = siconos
    config = dataclasses.replace(config, **changes)
    try:
        csv_path = run_stress(out, config, workers=workers)
    except QpcontactError as exc:
        console.print(f"[red]error:[/red] {exc}")
        raise typer.Exit(2)
    md, totals = write_markdown(csv_path)
    png = plot_heatmap(csv_path)
    console.print(md.read_text().split("## Per method and family")[0])
    console.print(f"results: {csv_path}\nreport:  {md}\nheat map: {png}")
    raise typer.Exit(1 if totals["silent_wrong"] or totals["bugs"] or (quick and totals["hung"]) else 0)


def main():  # pragma: no cover - console script
    app()


if __name__ == "__main__":  # pragma: no cover
    main()
