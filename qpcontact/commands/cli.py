"""Command-line interface: ``qpcontact methods | solve | simulate | sweep | plot | demo | compare | stress``.

Every command refuses a name it does not know (exit code 2, the valid names
listed: :mod:`.choices`) and exits non-zero when it did nothing.  The help is
click's plain text, rewrapped to the terminal, not rich's panels: they keep
the docstrings' line breaks and cost 0.1 s more to draw.  NumPy and the
engine are imported by the commands that use them, so that ``qpcontact
--help`` starts in a tenth of a second.
"""

from __future__ import annotations

from pathlib import Path

import typer
from rich.console import Console
from rich.markup import escape

from ..core.errors import QpcontactError
from ..core.files import DATA_ENV
from .choices import (DATA_FORMULATIONS, RegistryHelp, at_least, data_folder, family_names,
                      formulation_names, method_names, positive_seconds, split_names)

app = typer.Typer(add_completion=False, no_args_is_help=True, rich_markup_mode=None,
                  help="Contact and unilateral-constraint problems as certified LCPs and QPs.")
console = Console()
if not console.is_terminal:
    console.width = max(console.width, 120)  # tables stay readable in logs and pipes


def _accuracy(value: str):
    """The accuracy a command was given (a ladder level or a number),
    refused with the valid levels when it is neither."""
    from ..core.accuracy import resolve_accuracy

    try:
        level = float(value)
    except ValueError:
        level = value
    try:
        resolve_accuracy(level)
    except QpcontactError as exc:
        raise typer.BadParameter(str(exc), param_hint="'--accuracy'") from None
    return level


def _error(exc: Exception, code: int = 2):
    console.print(f"[red]error:[/red] {escape(str(exc))}")
    raise typer.Exit(code)


_DATA_HELP = (f"Folder that holds the data sets siconos-lcp/ and siconos-fc/ (default: ${DATA_ENV}, "
              "else ../shared/data beside the checkout, else beside the current folder).")


@app.command("methods")
def methods_cmd(all_: bool = typer.Option(False, "--all", help="Also list known methods that are not installed.")):
    """List the methods installed here.

    For each one: what it solves, where it is exact, what it needs."""
    from rich.table import Table

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
        if m.isolate_from == 0:
            notes.append("time limit by a child process")
        elif m.isolate_from is not None:
            notes.append(f"time limit by a child process (from {m.isolate_from} unknowns and "
                         "constraints, or a short limit)")
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
                               help="Method name: auto, or one of `qpcontact methods` (which says "
                                    "what each one solves)."),
    accuracy: str = typer.Option("high", "--accuracy", "-a", help="low, default, high, or a number "
                                 "in (0, 1)."),
):
    """Solve a problem file and certify the answer.

    Prints the answer and its certificate.  Exit code 1 if the answer is not
    certified, 2 if the file or an option is wrong."""
    import numpy as np

    from ..dispatch.driver import solve
    from ..core.friction_problem import FrictionProblem
    from ..io import read_problem

    try:
        level = _accuracy(accuracy)
        problem = read_problem(file)
        sol = solve(problem, method=method, accuracy=level)
    except QpcontactError as exc:
        _error(exc)
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
        fields = [(key, val) for key, val in sol.certificate.as_dict().items()
                  if isinstance(val, (int, float, np.integer, np.floating))
                  and not isinstance(val, (bool, np.bool_))]
        width = max((len(key) for key, _ in fields), default=0)
        for key, val in fields:   # an index is an integer, a measure a float
            text = f"{val: d}" if isinstance(val, (int, np.integer)) else f"{val: .3e}"
            console.print(f"  {key:{width}s} {text}")
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
    """Run a scene file; write its results to an HDF5 file.

    The results are checkpointed as the run goes (see --resume)."""
    from ..core.files import file_target
    from ..scenes import load_scene, read_state, write_results

    positive_seconds(checkpoint_seconds, "--checkpoint-seconds")
    out = out or Path("out") / (scene.stem + ".h5")
    try:
        file_target(out)
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
        _error(exc)
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
    """Run variants of a scene, serially or on Dask.

    Writes one HDF5 file per variant and summary.csv."""
    from rich.table import Table

    from ..scenes import split_values, sweep

    at_least(workers, 0, "--workers", "local Dask processes (0: run here)")
    variations = {}
    for item in vary:
        key, sep, values = item.partition("=")
        if not sep or not values:
            console.print(f"[red]error:[/red] --vary {escape(item)}: expected KEY=v1,v2,...")
            raise typer.Exit(2)
        try:
            variations[key.strip()] = split_values(values)
        except QpcontactError as exc:
            _error(f"--vary {item}: {exc}")
    out = out or Path("out") / f"sweep-{scene.stem}"
    try:
        rows = sweep(scene, variations, out, grid=grid, workers=workers, scheduler=scheduler)
    except QpcontactError as exc:
        _error(exc)
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
    """Draw a results file's standard figures without re-running.

    The figures: contact forces, their peaks, the energy."""
    from ..scenes import plot_results

    try:
        paths = plot_results(results, out)
    except QpcontactError as exc:
        _error(exc)
    for p in paths:
        console.print(f"wrote {p}")


@app.command("demo")
def demo_cmd(accuracy: str = typer.Option("high", "--accuracy", "-a", help="low, default, high, or a number "
                                          "in (0, 1).")):
    """Solve the paper's examples with every installed method.

    The examples of the decomposition paper (Kolesnikov 2013); exit code 1
    if a certified answer disagrees with it."""
    from .demo import run_demo

    wrong = run_demo(_accuracy(accuracy), console)
    raise typer.Exit(1 if wrong else 0)


@app.command("compare", cls=RegistryHelp)
def compare_cmd(
    out: str = typer.Option("out/compare", "--out", "-o", help="Output folder: results.csv, report.md, wp_*.png."),
    quick: bool = typer.Option(False, "--quick", help="Demo-sized sweep: small instances up to 200 "
                               "unknowns (friction: 50 contacts), 1 repeat, 6 tolerances, no cvxpy "
                               "(under a minute on 2 cores)."),
    resume: bool = typer.Option(False, "--resume", help="Keep the rows already in results.csv and skip those runs."),
    workers: int = typer.Option(0, "--workers", help="Run on a local Dask cluster with N worker processes."),
    scheduler: str = typer.Option(None, "--scheduler", help="Run on an existing Dask cluster, e.g. tcp://host:8786."),
    methods: str = typer.Option(None, "--methods", help="Comma-separated method names, from: {methods}, "
                                "or cvxpy:SOLVER (default: every installed one; --quick: but cvxpy's)."),
    formulations: str = typer.Option(None, "--formulations",
                                     help="Comma-separated, from: {formulations} (default: all; the "
                                          "data sets where they are found)."),
    data: str = typer.Option(None, "--data", help=_DATA_HELP),
    siconos: str = typer.Option(None, "--siconos", help="Folder of Siconos LCP files (default: "
                                "siconos-lcp/ in the --data folder)."),
    repeats: int = typer.Option(None, "--repeats", help="Timed repeats per run (default 1 with --quick, else 3)."),
    time_limit: float = typer.Option(10.0, "--time-limit", help="Seconds: a run without a point counts at this "
                                     "time in the aggregates; repeats stop once a run exceeds it."),
):
    """Time every method at every accuracy on the instances.

    The formulations' instances and the data sets x methods x accuracies,
    each answer certified and measured against the exact solution; writes a
    CSV, a Markdown report and work-precision plots.  Exit code 2 when the
    options leave nothing to run."""
    from ..core.files import make_folder
    from .compare import collect_instances, plan, report, sweep

    positive_seconds(time_limit, "--time-limit")
    at_least(repeats, 1, "--repeats", "timed repeats per run")
    at_least(workers, 0, "--workers", "local Dask processes (0: run here)")
    try:
        make_folder(out)
    except QpcontactError as exc:
        _error(exc)
    chosen = split_names(formulations, formulation_names, "'--formulations'", "formulation")
    names = split_names(methods, method_names, "'--methods'", "method")
    folders = {}
    for name, data_set in DATA_FORMULATIONS.items():
        if chosen is None or name in chosen:
            folders[name], note = data_folder(
                data_set, folder=siconos if name == "siconos" else None, root=data,
                required_by="'--formulations'" if chosen else None)
            if note:
                console.print(f"{name}: {escape(note)}")
    instances = collect_instances(quick, chosen, folders.get("siconos"), friction_dir=folders.get("friction"))
    found = {inst.formulation for inst in instances}
    for name in chosen or ():
        if name not in found:
            _error(f"--formulations {name}: no instances (none in {folders[name]})"
                   if name in folders else f"--formulations {name}: no instances")
    tasks = plan(instances, names, quick)
    if not tasks:
        _error(f"nothing to run: none of the methods {', '.join(names or ['(installed)'])} takes "
               f"the instances of {', '.join(sorted(found)) or '(no formulation)'}")
    try:
        csv_path = sweep(out, quick=quick, methods=names, instances=instances, repeats=repeats,
                         resume=resume, workers=workers, scheduler=scheduler,
                         time_limit=time_limit)
    except QpcontactError as exc:
        _error(exc)
    md = report(csv_path, time_limit=time_limit)
    console.print(f"results: {csv_path}\nreport:  {md}\nplots:   {md.parent}/wp_*.png")


@app.command("stress", cls=RegistryHelp)
def stress_cmd(
    out: str = typer.Option("out/stress", "--out", "-o", help="Output folder: stress.csv, stress.md, stress.png."),
    quick: bool = typer.Option(False, "--quick", help="Small seeded slice: sizes 6 and 24, 2 seeds, accuracy "
                               "high, no cvxpy (about a minute on 2 cores)."),
    methods: str = typer.Option(None, "--methods", help="Comma-separated method names, from: {methods}, "
                                "or cvxpy:SOLVER (default: auto and every installed one)."),
    families: str = typer.Option(None, "--families", help="Comma-separated, from: {families} "
                                 "(default: all; siconos where its files are found)."),
    sizes: str = typer.Option(None, "--sizes", help="Comma-separated sizes n (default 8,30,100; --quick 6,24)."),
    seeds: int = typer.Option(None, "--seeds", help="Seeds per family and size (default 200; --quick 2)."),
    time_limit: float = typer.Option(None, "--time-limit", help="Seconds per solve (default 2; --quick 10)."),
    workers: int = typer.Option(2, "--workers", help="Worker processes (each solve runs in one; a crash "
                                "or a hang costs one row)."),
    data: str = typer.Option(None, "--data", help=_DATA_HELP),
    siconos: str = typer.Option(None, "--siconos", help="Folder of Siconos LCP files (default: "
                                "siconos-lcp/ in the --data folder)."),
):
    """Run the hard cases with every method; silent wrong must be 0.

    Cases x methods x accuracies, each answer judged against the case's
    built-in answer.  Exit code 1 when an answer is silently wrong."""
    import dataclasses

    from ..core.files import make_folder
    from .stress import FULL, QUICK, plot_heatmap, run_stress, write_markdown

    positive_seconds(time_limit, "--time-limit")
    at_least(seeds, 1, "--seeds", "seeds per family and size")
    at_least(workers, 1, "--workers", "worker processes")
    try:
        make_folder(out)
    except QpcontactError as exc:
        _error(exc)
    config = QUICK if quick else FULL
    changes = {}
    names = split_names(methods, method_names, "'--methods'", "method")
    if names:
        changes["methods"] = tuple(names)
    chosen = split_names(families, family_names, "'--families'", "family")
    if chosen:
        changes["families"] = tuple(chosen)
    if sizes:
        try:
            changes["sizes"] = tuple(int(v) for v in sizes.split(","))
        except ValueError:
            raise typer.BadParameter(f"{sizes!r}: expected integers such as 8,30,100",
                                     param_hint="'--sizes'") from None
        for n in changes["sizes"]:
            at_least(n, 1, "--sizes", f"a problem size in {sizes!r}")
    if seeds is not None:
        changes["seeds"] = seeds
    if time_limit is not None:
        changes["time_limit"] = time_limit
    if "siconos" in (chosen or family_names()):
        folder, note = data_folder("siconos-lcp", folder=siconos, root=data,
                                   required_by="'--families'" if chosen else None)
        if note:
            console.print(f"siconos: {escape(note)}")
        changes["siconos_dir"] = str(folder) if folder else None
    config = dataclasses.replace(config, **changes)
    try:
        csv_path = run_stress(out, config, workers=workers)
    except QpcontactError as exc:
        _error(exc)
    md, totals = write_markdown(csv_path)
    png = plot_heatmap(csv_path)
    console.print(md.read_text().split("## Per method and family")[0])
    console.print(f"results: {csv_path}\nreport:  {md}\nheat map: {png}")
    raise typer.Exit(1 if totals["silent_wrong"] or totals["bugs"] or (quick and totals["hung"]) else 0)


def main():  # pragma: no cover - console script
    app()


if __name__ == "__main__":  # pragma: no cover
    main()
