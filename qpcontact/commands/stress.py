"""``qpcontact stress``: the hard-case suite, run as a product.

Families x sizes x seeds x methods x accuracy levels.  Every instance carries
its answer or its status, built in (qpcontact.testing.cases, planted
solutions, exact integer constructions, an exact-penalty theorem, the
Siconos files' documented solutions), and every returned answer is judged
against it by code in this module — never by :func:`qpcontact.certify`:

``certified``  ok, and the independent check agrees
``proved``     no solution exists, and the method proved it (a checked Farkas
               vector or ray) — the right answer for infeasible/unbounded cases
``inaccurate`` a point came back and was not certified (said so)
``failed``     nothing usable (said so), a documented exception, or a crash
``silent_wrong`` reported ok (or a proof) and the check disagrees: must be 0
``hung``       stopped at the time limit (the backend's own, or killed)

Each solve runs in one of ``workers`` long-lived child processes, so a
backend that crashes or hangs costs one row, and the run goes on (the child
is replaced).  Outputs: ``stress.csv`` (one row per solve, written
atomically), ``stress.md`` (per method and family), ``stress.png`` (heat map).

An answer counts as agreeing when it is within ``max(100 tol, 10 f)`` of the
planted one, component by component on its own scale (the planted value, its
natural size where the data were scaled, and the scale qpcontact promises it
on — docs/certificates.md — recomputed here by definition), where ``tol`` is the
requested accuracy and ``f`` the forward error the solution itself reports
(an ill-conditioned problem may move a certified answer that far, and the
solution says so; being farther than that is being wrong without saying so).
QPs are judged on the optimal value and on feasibility, each row on its own
scale, at ``1000 tol``.
"""

from __future__ import annotations

import csv
import math
import os
import statistics
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core.progress import ProgressBar

__all__ = ["FAMILIES", "StressConfig", "QUICK", "FULL", "build_case", "judge", "run_stress",
           "summarize", "write_markdown", "plot_heatmap"]

CATEGORIES = ("certified", "proved", "inaccurate", "failed", "silent_wrong", "hung")

#: family -> (problem kind, builder name); sizes apply to every family but siconos
LCP_FAMILIES = ("spd", "psd_singular", "degenerate", "badly_scaled", "p_matrix", "friction",
                "infeasible", "far_contact", "spread", "spread_sparse", "murty", "ties")
QP_FAMILIES = ("qp_convex", "qp_degenerate", "qp_infeasible", "qp_unbounded", "qp_penalty")
FAMILIES = LCP_FAMILIES + QP_FAMILIES + ("siconos",)

# Siconos files whose answer SOURCE.md documents independently (by hand or by
# enumeration): status, and z where unique.  The others are judged by the
# complementarity check alone.
_SICONOS_KNOWN = {
    "lcp_deudeu": ("solved", [4 / 3, 7 / 3]),
    "lcp_deudeu_block": ("solved", [4 / 3, 7 / 3]),
    "lcp_trivial": ("solved", list(1.0 / np.arange(1, 10))),
    "lcp_trivial_block": ("solved", list(1.0 / np.arange(1, 10))),
    "lcp_ortiz": ("solved", [2 / 3, 0.0, 1 / 3, 0.0]),
    "lcp_ortiz_block": ("solved", [2 / 3, 0.0, 1 / 3, 0.0]),
    "lcp_exp_murty": ("solved", [0, 0, 0, 0, 0, 1.0]),
    "lcp_CPS_2": ("solved", [0.0, 1.0, 3.0]),
    "lcp_CPS_4": ("solved", [2.0, 2.0, 2.0, 92.0]),
    "lcp_Pang_isolated_sol": ("solved", [1.0, 0.0, 0.0]),
    "lcp_Pang_isolated_sol_perturbed": ("infeasible", None),
}


@dataclass(frozen=True)
class StressConfig:
    sizes: tuple = (6, 24)
    seeds: int = 2
    accuracies: tuple = ("high",)
    methods: tuple | None = None          # None: every installed method (cvxpy too unless no_cvxpy)
    no_cvxpy: bool = True
    families: tuple = FAMILIES
    time_limit: float = 10.0
    rotate_accuracy: bool = False         # one accuracy per problem, rotating (the full run)
    siconos_dir: str | None = None


QUICK = StressConfig()
FULL = StressConfig(sizes=(8, 30, 100), seeds=200, accuracies=("low", "default", "high"),
                    no_cvxpy=False, time_limit=2.0, rotate_accuracy=True)


# --------------------------------------------------------------------------- instances

def _scaled_lcp(case, rng, decades: float):
    """D M D, D q with D a diagonal of powers of two over ``decades`` decades:
    exact in floating point, so the planted answer (D⁻¹z, Dw) stays exact."""
    from ..core.problems import LCP

    if decades <= 0 or case.status != "solved":
        return case
    M = case.problem.M
    n = M.shape[0]
    d = 2.0 ** np.round(rng.uniform(-decades / 2, decades / 2, n) * math.log2(10))
    import scipy.sparse as sp

    Ms = (sp.diags(d) @ M @ sp.diags(d)).tocsc() if sp.issparse(M) else (M * d[:, None]) * d[None, :]
    case.problem = LCP(Ms, case.problem.q * d)
    if case.z is not None:
        zs, ws = case.scales()
        case.z, case.w = case.z / d, case.w * d
        case.z_scale, case.w_scale = zs / d, ws * d
    return case


def _scaled_qp(case, rng, decades: float):
    """x = D x', constraint rows times E: powers of two, exact."""
    from qpsolvers import Problem

    if decades <= 0:
        return case
    P, q, G, h, A, b, lb, ub = case.problem.unpack()
    n = q.size
    d = 2.0 ** np.round(rng.uniform(-decades / 2, decades / 2, n) * math.log2(10))
    Ps = (P * d[:, None]) * d[None, :]
    Gs = hs = None
    if G is not None:
        e = 2.0 ** np.round(rng.uniform(-decades / 2, decades / 2, G.shape[0]) * math.log2(10))
        Gs, hs = (G * e[:, None]) * d[None, :], h * e
    case.problem = Problem(Ps, q * d, Gs, hs, A, b,
                           None if lb is None else lb / d, None if ub is None else ub / d)
    if case.x is not None:
        case.x = case.x / d
    return case


def _murty(n: int):
    """Murty's example: M upper triangular, 1 on the diagonal and 2 above,
    q = -1; Lemke takes 2^n pivots on it.  M is a P-matrix (triangular, unit
    diagonal) so the solution is unique: z = e_n (w = Mz + q = (1, ..., 1, 0))."""
    from ..core.problems import LCP
    from ..cases.planted import Case

    M = np.triu(2.0 * np.ones((n, n)), 1) + np.eye(n)
    z = np.zeros(n)
    z[-1] = 1.0
    return Case("murty", LCP(M, -np.ones(n)), "solved", z=z, w=M @ z - 1.0, unique_z=True)


def _ties(n: int, rng):
    """M = c(I + J) (SPD), q = -c·1: every ratio test ties; z = 1/(n+1), w = 0
    (every pair degenerate on the w side)."""
    from ..core.problems import LCP
    from ..cases.planted import Case

    c = 2.0 ** int(rng.integers(-10, 11))
    M = c * (np.eye(n) + np.ones((n, n)))
    z = np.full(n, 1.0 / (n + 1))
    return Case("ties", LCP(M, -c * np.ones(n)), "solved", z=z, w=np.zeros(n), unique_z=True,
                z_scale=z, w_scale=np.full(n, c))


def build_case(family: str, n: int, seed: int, siconos_dir: str | None = None):
    """The instance ``(family, n, seed)``: a qpcontact.testing.cases.Case."""
    from ..cases.planted import Case, build_lcp, build_qp
    from ..cases.families import far_contact_lcp, spread_lcp

    rng = np.random.default_rng([seed, n, FAMILIES.index(family)])
    decades = float(rng.choice([0.0, 4.0, 8.0, 12.0]))
    cond = 10.0 ** rng.uniform(0.0, 8.0)
    if family == "siconos":
        from ..io.formats import read_siconos_lcp

        path = Path(siconos_dir or _default_siconos())
        files = sorted(path.glob("*.dat"))
        f = files[seed % len(files)]
        status, z = _SICONOS_KNOWN.get(f.stem, ("unknown", None))
        lcp = read_siconos_lcp(f)
        zz = None if z is None else np.asarray(z, float)
        case = Case(f"siconos/{f.stem}", lcp, status, z=zz,
                    w=None if zz is None else lcp.w(zz), unique_z=zz is not None,
                    unique_w=zz is not None, seed=seed)
        return case
    if family in ("spd", "psd_singular", "degenerate", "badly_scaled", "p_matrix", "friction",
                  "infeasible"):
        case = build_lcp(family, n, seed, cond=cond, decades=decades)
        return case if family == "badly_scaled" else _scaled_lcp(case, rng, decades)
    if family == "far_contact":
        lcp, z, w = far_contact_lcp(seed, n=max(n, 8), n_far=max(1, n // 8))
        return _scaled_lcp(Case(family, lcp, "solved", z=z, w=w, unique_z=True, seed=seed), rng,
                           decades)
    if family in ("spread", "spread_sparse"):
        lcp, z, w = spread_lcp(seed, n=n, cond=cond, sparse=family == "spread_sparse")
        return Case(family, lcp, "solved", z=z, w=w, unique_z=True, seed=seed)
    if family == "murty":
        return _murty(min(n, 16))
    if family == "ties":
        return _ties(n, rng)
    if family in QP_FAMILIES:
        case = build_qp(family[3:], max(n, 3), seed, cond=min(cond, 1e6))
        return _scaled_qp(case, rng, decades) if family != "qp_penalty" else case
    raise ValueError(f"unknown family {family!r}; choose from {', '.join(FAMILIES)}")


def _default_siconos() -> Path:
    return Path("..") / "shared" / "data" / "siconos-lcp"


# --------------------------------------------------------------------------- judging

def _promised_scales(M, q, z_star) -> tuple[np.ndarray, np.ndarray]:
    """The scales on which qpcontact promises each component (docs/
    certificates.md), recomputed here from the planted answer by their
    definition, not by qpcontact.certify: ζ_j = min(cap, min_i σ_i / |M_ij|)
    over rows with data (σ = |q| + |M||z*|; cap = max(|z*|∞, |q|∞ / max|M|)),
    the change of z_j that moves some row by its own size; a row whose data
    are zero gets σ_i = Σ_j |M_ij| ζ_j.  A force of 1e-8 at an unloaded
    contact beside a gap of 4e10 is right on these scales."""
    A = np.abs(M.toarray() if hasattr(M, "toarray") else M)
    sig = np.abs(q) + A @ np.abs(z_star)
    idle = np.abs(q) == 0
    cap = max(float(np.abs(z_star).max()), float(np.abs(q).max()) / max(float(A.max()), 1e-300))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where((A > 0) & ~idle[:, None], sig[:, None] / A, np.inf)
    zeta = np.minimum(ratio.min(axis=0), cap)
    sig_idle = A @ np.where(np.isfinite(zeta), zeta, 0.0)
    return zeta, np.where(idle, np.maximum(sig, sig_idle), sig)


def _lcp_agrees(case, z, rtol: float) -> bool:
    M, q = case.problem.M, case.problem.q
    z = np.asarray(z, float)
    w = np.asarray(M @ z).ravel() + q
    if case.z is not None and case.unique_z:
        zs, ws = case.scales()
        zeta, sigma = _promised_scales(M, q, case.z)
        zs, ws = np.maximum(zs, zeta), np.maximum(ws, sigma)
        return bool(np.all(np.abs(z - case.z) <= rtol * zs) and np.all(np.abs(w - case.w) <= rtol * ws))
    if case.w is not None and case.unique_w:
        zs, ws = case.scales()
        return bool(np.all(np.abs(w - case.w) <= rtol * ws) and np.all(z >= -rtol * zs))
    # nothing determined: z >= 0, w >= 0, min(z_i, w_i) = 0, each pair on its
    # own scale (|q_i| + (|M||z|)_i for w_i; z's own magnitude for z_i)
    absM = abs(M) if hasattr(M, "tocsc") else np.abs(M)
    sig = np.abs(q) + np.asarray(absM @ np.abs(z)).ravel()
    # a row whose data are all (nearly) zero is judged on the others' scale
    sig = np.maximum(sig, 64 * np.finfo(float).eps * max(float(sig.max()), 1e-300))
    zs = max(float(np.abs(z).max()), 1e-300)
    zn, wn = z / zs, w / sig
    return bool(np.all(zn >= -rtol) and np.all(wn >= -rtol)
                and np.all(np.minimum(np.abs(zn), np.abs(wn)) <= rtol))


def _qp_agrees(case, x, rtol: float) -> bool:
    P, q, G, h, A, b, lb, ub = case.problem.unpack()
    x = np.asarray(x, float)
    f = 0.5 * x @ (P @ x) + q @ x
    scale = 0.5 * np.abs(x) @ (np.abs(P) @ np.abs(x)) + np.abs(q) @ np.abs(x)
    xs = case.x
    fscale = max(scale, 0.5 * np.abs(xs) @ (np.abs(P) @ np.abs(xs)) + np.abs(q) @ np.abs(xs), 1e-300)
    if abs(f - case.objective) > rtol * fscale:
        return False
    if G is not None and np.any(G @ x - h > rtol * (np.abs(G) @ np.abs(x) + np.abs(h))):
        return False
    if lb is not None:
        nz = np.abs(xs[xs != 0])
        floor = float(nz.min()) if nz.size else 1.0
        if np.any(lb - x > rtol * np.maximum(np.maximum(np.abs(lb), np.abs(xs)), floor)):
            return False
    return True


def judge(case, sol) -> tuple[str, str]:
    """(category, reason): ``sol`` judged against what ``case`` has built in."""
    from ..core.problems import LCP

    is_lcp = isinstance(case.problem, LCP)
    proved = sol.status in ("infeasible", "unbounded") or (
        sol.status == "ray" and bool(sol.stats.get("proved_infeasible")))
    claimed = "solved" if sol.ok else (sol.status if sol.status in ("infeasible", "unbounded")
                                       else ("infeasible" if proved else None))
    if sol.status == "time_limit":
        return "hung", sol.message[:120]
    if case.status in ("infeasible", "unbounded"):
        if claimed == case.status:
            return "proved", ""
        if claimed is not None:
            return "silent_wrong", f"claimed {claimed} on a {case.status} instance"
    elif case.status == "solved" and claimed in ("infeasible", "unbounded"):
        return "silent_wrong", f"claimed {claimed} on a solvable instance: {sol.message[:100]}"
    if sol.ok:
        if is_lcp:
            ferr = sol.forward_error
            good = _lcp_agrees(case, sol.z, max(100 * sol.tol, 10 * ferr if np.isfinite(ferr) else 0.0))
        else:
            good = _qp_agrees(case, sol.x, 1000 * sol.tol)
        return ("certified", "") if good else (
            "silent_wrong", f"certified (error {sol.error:.1e}) but disagrees with the known answer")
    if sol.status in ("inaccurate", "max_pivots", "ray"):
        return "inaccurate", sol.status
    return "failed", sol.status


# --------------------------------------------------------------------------- workers

FIELDS = ("family", "n", "seed", "instance", "method", "accuracy", "expected", "status",
          "category", "reason", "error", "seconds")


def _solve_row(task, siconos_dir, time_limit, cache={}):  # noqa: B006 - per-process cache
    from ..core.errors import QpcontactError
    from ..dispatch.driver import solve

    family, n, seed, method, accuracy = task
    key = (family, n, seed)
    if key not in cache:
        cache.clear()
        cache[key] = build_case(family, n, seed, siconos_dir)
    case = cache[key]
    row = dict(family=family, n=n, seed=seed, instance=getattr(case, "kind", family),
               method=method, accuracy=accuracy, expected=case.status)
    start = time.perf_counter()
    try:
        sol = solve(case.problem, method, accuracy, time_limit=time_limit, isolate=False)
    except QpcontactError as exc:
        row.update(status=type(exc).__name__, category="failed", reason=str(exc)[:160],
                   error=math.inf, seconds=time.perf_counter() - start)
        return row
    except Exception as exc:  # noqa: BLE001 - an undocumented exception is a bug: recorded as one
        row.update(status="bug", category="failed", reason=f"BUG {type(exc).__name__}: {exc}"[:160],
                   error=math.inf, seconds=time.perf_counter() - start)
        return row
    category, reason = judge(case, sol)
    row.update(status=sol.status, category=category, reason=reason, error=sol.error,
               seconds=sol.wall_time)
    return row


def _worker_loop(conn, siconos_dir, time_limit):
    import faulthandler

    faulthandler.disable()
    while True:
        task = conn.recv()
        if task is None:
            return
        conn.send(_solve_row(task, siconos_dir, time_limit))


class _Worker:
    def __init__(self, siconos_dir, time_limit):
        from ..dispatch.isolation import context

        self.args = (siconos_dir, time_limit)
        self.ctx = context()
        self._start()

    def _start(self):
        self.conn, child = self.ctx.Pipe()
        self.proc = self.ctx.Process(target=_worker_loop, args=(child, *self.args), daemon=True)
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


def _tasks(config: StressConfig) -> list[tuple]:
    from ..solvers.registry import methods as installed
    from ..dispatch.routes import applicable

    names = list(config.methods) if config.methods else [
        name for name, m in installed().items() if not (config.no_cvxpy and m.family == "cvxpy")]
    registry = installed()
    tasks = []
    k = 0
    for family in config.families:
        if family == "siconos":
            d = Path(config.siconos_dir or _default_siconos())
            count = len(list(d.glob("*.dat"))) if d.is_dir() else 0
            instances = [(family, 0, i) for i in range(count)]
        else:
            instances = [(family, n, s) for n in config.sizes for s in range(config.seeds)]
        for family_, n, seed in instances:
            case = build_case(family_, n, seed, config.siconos_dir)
            levels = ([config.accuracies[k % len(config.accuracies)]] if config.rotate_accuracy
                      else list(config.accuracies))
            k += 1
            for name in names:
                m = registry.get(name)
                if m is None or not applicable(case.problem, m):
                    continue
                for level in levels:
                    tasks.append((family_, n, seed, name, level))
    return tasks


def run_stress(out_dir, config: StressConfig = QUICK, *, workers: int = 2,
               progress: bool = True) -> Path:
    """Run the suite; write ``stress.csv`` and return its path."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    tasks = _tasks(config)
    hard = 1.5 * config.time_limit + 3.0
    rows: list[dict] = []
    bar = ProgressBar(len(tasks), f"stress: {len(tasks)} solves", enabled=progress)
    pool = [_Worker(config.siconos_dir, config.time_limit) for _ in range(max(1, workers))]
    from multiprocessing.connection import wait

    pending = list(reversed(tasks))
    path = out / "stress.csv"
    saved = 0
    try:
        while pending or any(w.task is not None for w in pool):
            for w in pool:
                if w.task is None and pending:
                    w.submit(pending.pop(), hard)
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
                    rows.append({**base, "status": "killed", "category": "hung",
                                 "reason": f"no answer in {hard:g} s: worker killed",
                                 "seconds": hard})
                    w.restart()
                    bar.advance()
            if len(rows) - saved >= 2000:  # a long run killed midway keeps what it did
                _write_csv(path, rows)
                saved = len(rows)
                if progress and not sys.stderr.isatty():  # logs get a line, not a bar
                    wrong = sum(r["category"] == "silent_wrong" for r in rows)
                    hung = sum(r["category"] == "hung" for r in rows)
                    print(f"stress: {len(rows)}/{len(tasks)} solves, {wrong} silent wrong, "
                          f"{hung} hung", file=sys.stderr, flush=True)
    finally:
        for w in pool:
            w.close()
        bar.close()
    _write_csv(path, rows)
    return path


def _write_csv(path: Path, rows: list[dict]) -> None:
    from ..core.files import write_csv_atomic

    write_csv_atomic(path, rows, FIELDS)


# --------------------------------------------------------------------------- reports

def _read(path) -> list[dict]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def summarize(rows: list[dict]) -> dict:
    """{(method, family): {category: count, ..., "median_s": seconds}}."""
    table: dict = {}
    for r in rows:
        cell = table.setdefault((r["method"], r["family"]), {c: 0 for c in CATEGORIES} | {"_t": []})
        cell[r["category"]] += 1
        try:
            s = float(r["seconds"])
            if math.isfinite(s):
                cell["_t"].append(s)
        except (TypeError, ValueError):
            pass
    for cell in table.values():
        t = cell.pop("_t")
        cell["median_s"] = statistics.median(t) if t else math.nan
    return table


def write_markdown(csv_path, md_path=None) -> tuple[Path, dict]:
    """Per method (rows) and per family: counts by category and median time;
    then per method over all families.  Returns (path, totals)."""
    rows = _read(csv_path)
    table = summarize(rows)
    md = Path(md_path) if md_path else Path(csv_path).with_suffix(".md")
    totals = {c: sum(cell[c] for cell in table.values()) for c in CATEGORIES}
    problems = len({(r["family"], r["n"], r["seed"]) for r in rows})
    lines = [
        "# qpcontact stress",
        "",
        f"{len(rows)} solves of {problems} problems; silent wrong: **{totals['silent_wrong']}**, "
        f"hung (time-limited): **{totals['hung']}**.",
        "",
        "Categories (judged against each instance's built-in answer, not by qpcontact.certify): "
        "certified · proved (no solution, proof checked) · inaccurate · failed · "
        "**silent wrong** · hung.",
        "",
        "## Per method",
        "",
        "| method | solves | certified | proved | inaccurate | failed | silent wrong | hung | median s |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    methods = sorted({m for m, _ in table})
    families = [f for f in FAMILIES if any(f == fam for _, fam in table)]
    for m in methods:
        cells = [table[(m, f)] for f in families if (m, f) in table]
        counts = {c: sum(cell[c] for cell in cells) for c in CATEGORIES}
        times = [float(r["seconds"]) for r in rows if r["method"] == m
                 and r["seconds"] not in ("", "nan")]
        med = statistics.median(times) if times else math.nan
        lines.append(f"| {m} | {sum(counts.values())} | " + " | ".join(
            str(counts[c]) for c in CATEGORIES) + f" | {med:.2g} |")
    lines += ["", "## Per method and family", "",
              "Each cell: certified+proved / solves (silent wrong, hung when nonzero); median seconds.", "",
              "| method | " + " | ".join(families) + " |",
              "|---|" + "---|" * len(families)]
    for m in methods:
        cells = []
        for f in families:
            cell = table.get((m, f))
            if cell is None:
                cells.append("—")
                continue
            total = sum(cell[c] for c in CATEGORIES)
            text = f"{cell['certified'] + cell['proved']}/{total}"
            if cell["silent_wrong"]:
                text += f" **{cell['silent_wrong']} wrong**"
            if cell["hung"]:
                text += f" ({cell['hung']} hung)"
            text += f"; {cell['median_s']:.1g} s"
            cells.append(text)
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    wrong = [r for r in rows if r["category"] == "silent_wrong"]
    if wrong:
        lines += ["", "## Silent wrong answers", ""]
        lines += [f"- {r['method']} on {r['family']} n={r['n']} seed={r['seed']} "
                  f"({r['accuracy']}): {r['reason']}" for r in wrong[:50]]
    bugs = [r for r in rows if r["status"] == "bug"]
    if bugs:
        lines += ["", "## Undocumented exceptions (bugs)", ""]
        lines += [f"- {r['method']} on {r['family']} n={r['n']} seed={r['seed']}: {r['reason']}"
                  for r in bugs[:50]]
    tmp = md.with_suffix(".md.tmp")
    tmp.write_text("\n".join(lines) + "\n")
    os.replace(tmp, md)
    return md, totals | {"solves": len(rows), "problems": problems, "bugs": len(bugs)}


def plot_heatmap(csv_path, png_path=None) -> Path:
    """Methods x families, coloured by the certified-or-proved fraction;
    cells with silent wrong answers are outlined and labelled."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = _read(csv_path)
    table = summarize(rows)
    methods = sorted({m for m, _ in table})
    families = [f for f in FAMILIES if any(f == fam for _, fam in table)]
    frac = np.full((len(methods), len(families)), np.nan)
    for i, m in enumerate(methods):
        for j, f in enumerate(families):
            cell = table.get((m, f))
            if cell:
                total = sum(cell[c] for c in CATEGORIES)
                frac[i, j] = (cell["certified"] + cell["proved"]) / total
    fig, ax = plt.subplots(figsize=(1.0 + 0.75 * len(families), 1.2 + 0.38 * len(methods)))
    im = ax.imshow(frac, cmap="viridis", vmin=0, vmax=1, aspect="auto")
    ax.set_xticks(range(len(families)), families, rotation=45, ha="right")
    ax.set_yticks(range(len(methods)), methods)
    for i, m in enumerate(methods):
        for j, f in enumerate(families):
            cell = table.get((m, f))
            if not cell:
                continue
            label = f"{frac[i, j]:.0%}".replace("%", "")
            if cell["silent_wrong"]:
                label += f"\n{cell['silent_wrong']}W"
                ax.add_patch(plt.Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, ec="red", lw=2))
            ax.text(j, i, label, ha="center", va="center", fontsize=6,
                    color="white" if frac[i, j] < 0.6 else "black")
    fig.colorbar(im, ax=ax, label="certified or proved (fraction)")
    ax.set_title(f"qpcontact stress: {len(rows)} solves (W: silent wrong, must be 0)")
    fig.tight_layout()
    png = Path(png_path) if png_path else Path(csv_path).with_suffix(".png")
    tmp = png.with_name(png.stem + ".tmp.png")
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, png)
    return png
