"""Running the stress suite: each solve in one of several long-lived child
processes, so that a crash or a hang costs one row."""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

from ...core.errors import InvalidOptionError
from ...core.progress import ProgressBar
from .cases import QUICK, StressConfig, build_case, default_siconos
from .judge import DOUBT_WORDS, forward_errors, has_one_row_farkas, judge

__all__ = ["FIELDS", "tasks", "run_stress", "time_share", "OVER_FACTOR"]

FIELDS = ("family", "n", "seed", "instance", "method", "accuracy", "expected", "status",
          "category", "reason", "error", "seconds", "wall", "limit_s", "over_limit",
          "fe_true", "fe_est", "doubt", "one_row")

#: a solve is "over the limit" when its whole wall time (method, certificate,
#: proof) passes OVER_FACTOR x time_limit — "auto" included, which gives each
#: method it tries half of what is left (qpcontact.dispatch.driver), so that
#: its chain fits in the one limit; the rest is conversion, certification and
#: proofs
OVER_FACTOR = 1.5


def _auto_methods(problem) -> list[str]:
    """The installed methods "auto" would try on ``problem``, in order."""
    from ...dispatch.routes import applicable, auto_order
    from ...solvers.registry import methods as installed

    registry = installed()
    return [name for name in auto_order(problem)
            if name in registry and applicable(problem, registry[name])]


def time_share(problem, method: str, time_limit: float) -> float:
    """Seconds one solve may take before the report flags it (OVER_FACTOR)."""
    return OVER_FACTOR * time_limit


def _solve_row(task, siconos_dir, time_limit, cache={}):  # noqa: B006 - per-process cache
    from ...core.errors import QpcontactError
    from ...dispatch.driver import solve

    family, n, seed, method, accuracy = task
    key = (family, n, seed)
    if key not in cache:
        cache.clear()
        cache[key] = build_case(family, n, seed, siconos_dir)
    case = cache[key]
    row = dict(family=family, n=n, seed=seed, instance=getattr(case, "kind", family),
               method=method, accuracy=accuracy, expected=case.status)
    limit = time_share(case.problem, method, time_limit)
    row["limit_s"] = limit
    start = time.perf_counter()
    try:
        # isolate="auto": only ProxQP, which has no time limit of its own, runs
        # in a child killed at the limit (in-process it ran 6 s past a 2 s limit)
        sol = solve(case.problem, method, accuracy, time_limit=time_limit, isolate="auto")
    except QpcontactError as exc:
        wall = time.perf_counter() - start
        row.update(status=type(exc).__name__, category="failed", reason=str(exc)[:160],
                   error=math.inf, seconds=wall, wall=wall, over_limit=int(wall > limit))
        return row
    except Exception as exc:  # noqa: BLE001 - an undocumented exception is a bug: recorded as one
        wall = time.perf_counter() - start
        row.update(status="bug", category="failed", reason=f"BUG {type(exc).__name__}: {exc}"[:160],
                   error=math.inf, seconds=wall, wall=wall, over_limit=int(wall > limit))
        return row
    wall = time.perf_counter() - start
    category, reason = judge(case, sol)
    fe_true, fe_est = forward_errors(case, sol)
    row.update(status=sol.status, category=category, reason=reason, error=sol.error,
               seconds=sol.wall_time, wall=wall, over_limit=int(wall > limit),
               fe_true=fe_true, fe_est=fe_est,
               doubt=int(bool(sol.ok) and any(x in sol.message for x in DOUBT_WORDS)),
               one_row=int(has_one_row_farkas(case)))
    return row


def _worker_loop(conn, siconos_dir, time_limit):
    import faulthandler

    faulthandler.disable()
    while True:
        try:
            task = conn.recv()
        except (EOFError, OSError):
            return
        if task is None:
            return
        conn.send(_solve_row(task, siconos_dir, time_limit))


class _Worker:
    def __init__(self, siconos_dir, time_limit):
        from ...dispatch.isolation import process_context

        self.args = (siconos_dir, time_limit)
        self.ctx = process_context()
        self._start()

    def _start(self):
        self.conn, child = self.ctx.Pipe()
        # not a daemon: a daemonic process may not start children, and ProxQP
        # (no time limit of its own) runs in a child killed at the limit;
        # a worker whose parent is gone ends on the closed pipe instead
        self.proc = self.ctx.Process(target=_worker_loop, args=(child, *self.args), daemon=False)
        self.proc.start()
        child.close()
        self.task, self.deadline = None, None

    def submit(self, task, hard_limit):
        self.task, self.deadline = task, time.monotonic() + hard_limit
        self.conn.send(task)

    def restart(self):
        if self.proc.is_alive():
            self.proc.kill()
        self.proc.join()
        self.conn.close()
        self._start()

    def close(self):
        try:
            self.conn.send(None)
        except OSError:
            pass
        self.proc.join(timeout=5)
        if self.proc.is_alive():
            self.proc.kill()


def tasks(config: StressConfig) -> list[tuple]:
    from ...solvers.registry import methods as installed
    from ...dispatch.routes import applicable

    # "auto" is what users call: it runs in every default run
    names = list(config.methods) if config.methods else ["auto"] + [
        name for name, m in installed().items() if not (config.no_cvxpy and m.family == "cvxpy")]
    registry = installed()
    instances = []
    for family in config.families:
        if family == "siconos":
            d = config.siconos_dir or default_siconos()
            count = len(list(Path(d).glob("*.dat"))) if d and Path(d).is_dir() else 0
            instances += [(family, 0, i) for i in range(count)]
        else:
            instances += [(family, n, s) for n in config.sizes
                          for s in range(config.first_seed, config.first_seed + config.seeds)]
    # seed by seed, each seed over every family: a long run stopped midway
    # (its CSV is written every 2 000 solves) has counted every family.  A
    # case's solves stay together (each worker keeps its last case), and the
    # rotating accuracy follows the families' order, as before.
    order = sorted(range(len(instances)),
                   key=lambda k: -1 if instances[k][0] == "siconos" else instances[k][2])
    tasks = []
    for k in order:
        family_, n, seed = instances[k]
        case = build_case(family_, n, seed, config.siconos_dir)
        levels = ([config.accuracies[k % len(config.accuracies)]] if config.rotate_accuracy
                  else list(config.accuracies))
        for name in names:
            m = registry.get(name)
            if name == "auto":
                if not _auto_methods(case.problem):
                    continue
            elif m is None or not applicable(case.problem, m):
                continue
            for level in levels:
                tasks.append((family_, n, seed, name, level))
    return tasks


def _warm(names) -> None:
    """Each method's one-time costs — importing its backend, numba loading
    its kernels (compiled to the disk cache once per machine) — paid once in
    this process, whose forked workers inherit them.  The time limit's grace
    does not cover them (qpcontact.core.deadline.grace): a worker's first
    solves otherwise counted them (a census's first "auto" on an SPD LCP of
    n = 8: 10-11 s; Lemke 4-5 s "after 1 pivots")."""
    import numpy as np
    import scipy.sparse as sp
    from qpsolvers import Problem

    from ...core.problems import LCP
    from ...dispatch.driver import solve

    M = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]])
    probes = (LCP(M, -np.ones(3)), LCP(sp.csr_matrix(M), -np.ones(3)),
              Problem(M, -np.ones(3), np.eye(3), np.ones(3)))
    for name in names:
        for problem in probes:
            try:
                solve(problem, name, "low", time_limit=30)
            except Exception:  # noqa: BLE001 - a method that does not take this kind
                pass


def run_stress(out_dir, config: StressConfig = QUICK, *, workers: int = 2,
               progress: bool = True) -> Path:
    """Run the suite; write ``stress.csv`` and return its path."""
    out = Path(out_dir)
    from ...core.files import make_folder

    make_folder(out)
    todo = tasks(config)
    if not todo:
        raise InvalidOptionError(
            f"nothing to run: none of the methods {', '.join(config.methods or ['installed'])} "
            f"takes a case of the families {', '.join(config.families)} (siconos: its files "
            "where found); `qpcontact methods` says what each method solves")
    hard = OVER_FACTOR * config.time_limit + 3.0
    from ...dispatch.routes import AUTO_ORDER

    # "auto" fits its backends in the limit, but its pivoting methods and
    # proofs are bounded by their size, not by time: a wider kill, so that a
    # slow one is reported over its share rather than lost
    hard_auto = OVER_FACTOR * config.time_limit * len(AUTO_ORDER) + 3.0
    rows: list[dict] = []
    bar = ProgressBar(len(todo), f"stress: {len(todo)} solves", enabled=progress)
    _warm(dict.fromkeys(task[3] for task in todo))
    pool = [_Worker(config.siconos_dir, config.time_limit) for _ in range(max(1, workers))]
    from multiprocessing.connection import wait

    pending = list(reversed(todo))
    path = out / "stress.csv"
    saved = 0
    try:
        while pending or any(w.task is not None for w in pool):
            for w in pool:
                if w.task is None and pending:
                    task = pending.pop()
                    w.submit(task, hard_auto if task[3] == "auto" else hard)
            busy = [w for w in pool if w.task is not None]
            timeout = max(0.0, min(w.deadline for w in busy) - time.monotonic())
            ready = wait([w.conn for w in busy], timeout=timeout)
            for w in busy:
                family, n, seed, method, accuracy = w.task
                base = dict(family=family, n=n, seed=seed, instance=family, method=method,
                            accuracy=accuracy, expected="", error=math.inf)
                if w.conn in ready:
                    try:
                        rows.append(w.conn.recv())
                    except (EOFError, OSError):
                        w.proc.join()
                        rows.append({**base, "status": "crashed", "category": "failed",
                                     "reason": f"worker died (exit {w.proc.exitcode})",
                                     "seconds": math.nan})
                        w.restart()
                        bar.advance()
                        continue
                    w.task = None
                    bar.advance()
                elif time.monotonic() >= w.deadline:
                    limit = hard_auto if method == "auto" else hard
                    rows.append({**base, "status": "killed", "category": "hung",
                                 "reason": f"no answer in {limit:g} s: worker killed",
                                 "seconds": limit, "wall": limit, "over_limit": 1})
                    w.restart()
                    bar.advance()
            if len(rows) - saved >= 2000:  # a long run killed midway keeps what it did
                _write_csv(path, rows)
                saved = len(rows)
                if progress and not sys.stderr.isatty():  # logs get a line, not a bar
                    wrong = sum(r["category"] == "silent_wrong" for r in rows)
                    hung = sum(r["category"] == "hung" for r in rows)
                    print(f"stress: {len(rows)}/{len(todo)} solves, {wrong} silent wrong, "
                          f"{hung} hung", file=sys.stderr, flush=True)
    finally:
        for w in pool:
            w.close()
        bar.close()
    _write_csv(path, rows)
    return path


def _write_csv(path: Path, rows: list[dict]) -> None:
    from ...core.files import write_csv_atomic

    write_csv_atomic(path, rows, FIELDS)
