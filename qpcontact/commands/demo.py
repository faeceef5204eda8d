"""The demo job: every installed method on the decomposition paper's examples,
then each formulation's part.

Each part fits a terminal page and reads on 100 columns: one row per method,
every status explained under the table where it appears, timings taken after
one untimed first call (numba compiling or loading its kernels, a backend's
import) and that first call shown apart.
"""

from __future__ import annotations

import numpy as np

from ..cases.paper import p0_examples
from ..core.errors import InvalidProblemError
from ..core.results import STATUSES
from ..dispatch.driver import solve
from ..solvers.registry import methods

__all__ = ["run_demo", "demo_rows", "status_notes", "WIDTH", "REPEATS"]

#: The demo reads on this many columns (a log or pipe gets exactly this).
WIDTH = 100
#: Timed calls per method and example; the table shows the fastest.
REPEATS = 3


def _lcp_methods() -> list[str]:
    """The installed methods that solve an LCP (the registry also holds the
    friction methods and the load trace)."""
    return [name for name, m in methods().items() if m.solves("lcp")]


def status_notes(statuses) -> list[str]:
    """One line per status that appears, in order: what it means
    (:data:`qpcontact.STATUSES`)."""
    return [f"{s}: {STATUSES[s]}." for s in dict.fromkeys(statuses) if s in STATUSES]


def _first_call(name: str, lcp) -> float:
    """Seconds of the method's first call in this process: numba's compile or
    cache load and the backend's import land here, not in the timed rows."""
    return solve(lcp, method=name, accuracy="high").wall_time


def demo_rows(accuracy="high") -> list[dict]:
    """One row per (method, example): status, certificate error, time (the
    fastest of ``REPEATS`` calls after the method's untimed first call, kept
    in ``first_call``), iterations and
    the largest difference from the paper's solution relative to max|z|."""
    rows = []
    examples = p0_examples()
    for name in _lcp_methods():
        first = _first_call(name, examples[0].lcp)
        for ex in examples:
            # the fastest of three calls: single sub-millisecond calls on a shared
            # machine are mostly scheduling noise
            sols = [solve(ex.lcp, method=name, accuracy=accuracy) for _ in range(REPEATS)]
            sol = min(sols, key=lambda s: s.wall_time)
            dz = np.inf if sol.z is None else float(np.max(np.abs(sol.z - ex.z)) / np.max(np.abs(ex.z)))
            rows.append(dict(method=name, example=ex.name.replace("Kolesnikov example ", "ex "),
                             status=sol.status, ok=sol.ok, error=sol.error, time=sol.wall_time,
                             first_call=first, dz=dz, iterations=sol.iterations))
    return rows


def _table(title, columns, left=("method",)):
    """A rich table whose headers never wrap nor lose their units (escaped, so
    "[ms]" is text, not markup; each column at least as wide as its header)."""
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    table = Table(title=title, box=box.SIMPLE_HEAD, title_justify="left", pad_edge=False)
    for col in columns:
        table.add_column(escape(col), justify="left" if col in left else "right", no_wrap=True,
                         min_width=len(col))
    return table


def _notes(console, lines) -> None:
    """Footnotes, as plain text: a "[ms]" in them is a unit, not markup."""
    for line in lines:
        console.print(line, markup=False, highlight=False)


def _statuses(rs) -> str:
    """'solved' when every example is, else which examples are not and why."""
    bad = {}
    for r in rs:
        if not r["ok"]:
            bad.setdefault(r["status"], []).append(r["example"].removeprefix("ex "))
    if not bad:
        return "solved"
    return "; ".join(f"ex {', '.join(exs)} {status}" for status, exs in bad.items())


def _paper_table(console, accuracy) -> int:
    rows = demo_rows(accuracy)
    table = _table(f"Examples 1-3 of the decomposition paper (Kolesnikov 2013), accuracy {accuracy!r}: "
                   "every installed method, one row each", ("method", "status", "error", "|z-z_paper|/|z|",
                                            "time [ms] ex 1, 2, 3", "iterations"),
                   left=("method", "status"))
    wrong = 0
    slow_first = []
    for name in dict.fromkeys(r["method"] for r in rows):
        rs = [r for r in rows if r["method"] == name]
        disagree = [r for r in rs if r["ok"] and r["dz"] > 1e-6]
        wrong += len(disagree)
        status = _statuses(rs)
        style = "red" if disagree else ("green" if status == "solved" else "yellow")
        timed = [r["time"] for r in rs]
        if rs[0]["first_call"] > max(0.02, 5 * float(np.median(timed))):
            slow_first.append(f"{name} {1e3 * rs[0]['first_call']:.0f}")
        iters = " ".join("-" if r["iterations"] is None else str(r["iterations"]) for r in rs)
        table.add_row(name, f"[{style}]{status}[/{style}]", f"{max(r['error'] for r in rs):.1e}",
                      f"{max(r['dz'] for r in rs):.1e}",
                      " ".join(f"{1e3 * t:.2f}" for t in timed), iters)
    console.print(table)
    n_ok = sum(r["ok"] for r in rows)
    notes = [f"{n_ok}/{len(rows)} answers certified; {wrong} certified answers disagree with the "
             "paper.",
             f"time: the fastest of {REPEATS} calls.  error: the worst of the three "
             "componentwise certificate errors (each row of the LCP against its own data; "
             "docs/certificates.md); |z-z_paper|/|z|: the worst distance to the paper's solution, "
             "relative to max|z|; iterations: pivots or iterations per example, '-' where the "
             "backend reports none.",
             *status_notes(["solved"] + [r["status"] for r in rows])]
    if slow_first:
        notes.append("First calls, on example 1, not in the times above (numba compiling or "
                     f"loading its kernels, an import) [ms]: {', '.join(slow_first)}.")
    _notes(console, notes)
    return wrong


def run_demo(accuracy="high", console=None) -> int:
    """Print the demo, part by part; return the number of checks that failed
    (certified answers that disagree with the paper, wrong pivot counts,
    certified wrong answers, failed formulation checks: 0 when all is well)."""
    from rich.console import Console

    console = console or Console()
    width = console.width
    if not console.is_terminal:
        console.width = WIDTH
    try:
        console.rule("1. The decomposition paper's examples: every method", align="left")
        failed = _paper_table(console, accuracy)
        console.rule("2. The energy method's pivots against the paper's", align="left")
        failed += _pivot_table(console)
        console.rule("3. Far contacts: what the componentwise certificate sees", align="left")
        failed += _far_contact_table(console)
        failed += _formulation_demos(console, first_part=4)
    finally:
        console.width = width
    return failed


def _far_contact_table(console) -> int:
    """One far-contact problem (gaps of 5e11 beside gaps of 0.1) with every
    installed method: the componentwise error against the normwise one and the
    distance to the planted solution.  Returns the answers certified although
    wrong (must be 0)."""
    from ..cases.families import far_contact_lcp, planted_ok

    lcp, z_star, w_star = far_contact_lcp(0)
    table = _table("Far contacts: n = 21, three gaps of 5e11 beside gaps of 0.1",
                   ("method", "status", "error", "normwise", "max|z - z*|", "right"),
                   left=("method", "status"))
    silent = 0
    statuses, refused = [], []
    for name in _lcp_methods():
        try:
            sol = solve(lcp, method=name)
        except InvalidProblemError as exc:      # a size limit ('enumeration': n <= 16)
            statuses.append("not applicable")
            refused.append(f"{name}: {exc}")
            table.add_row(name, "not applicable", "-", "-", "-", "-")
            continue
        statuses.append(sol.status)
        right = planted_ok(sol.z, sol.w, z_star, w_star)
        silent += int(sol.ok and not right)
        cert = sol.certificate
        numbers = (["-"] * 3 if cert is None or sol.z is None else
                   [f"{v:.1e}" for v in (sol.error, cert.normwise_error,
                                         float(np.max(np.abs(sol.z - z_star))))])
        style = "green" if sol.ok and right else ("red" if sol.ok else "yellow")
        table.add_row(name, f"[{style}]{sol.status}[/{style}]", *numbers, "yes" if right else "no")
    console.print(table)
    notes = [f"{silent} answers certified although wrong.  error: componentwise; normwise: "
             "the same residuals against the largest entries only.  A normwise error near 1e-13 "
             "beside a componentwise one near 1 is the blind spot the componentwise certificate "
             "closes (docs/certificates.md).  right: equal to the planted solution (1e-6).",
             *status_notes(s for s in statuses if s != "not applicable")]
    notes += [f"not applicable: the method refuses the problem before solving ({r})."
              for r in refused]
    if any(s not in ("solved", "inaccurate") for s in statuses):
        notes.append("-: no point came back, or the method did not run: nothing to measure.")
    _notes(console, notes)
    return silent


def _formulation_demos(console, first_part: int) -> int:
    """Each installed formulation's demo (entry-point group
    ``qpcontact.formulations``), each a numbered part of its own."""
    from importlib.metadata import entry_points

    failed = 0
    part = first_part
    for ep in sorted(entry_points(group="qpcontact.formulations"), key=lambda e: e.name):
        module = ep.load()
        if hasattr(module, "demo"):
            console.rule(f"{part}. Formulation: {ep.name}", align="left")
            failed += int(module.demo(console))
            part += 1
    return failed


def _pivot_table(console) -> int:
    """Kolesnikov's energy method: our pivot counts beside the paper's; returns mismatches."""
    table = _table("Energy method (Kolesnikov 2013): principal pivots, ours against the paper's and Lemke's",
                   ("example", "energy", "paper", "lemke", "Murty fallback", "note"),
                   left=("example", "note"))
    table.columns[-1].no_wrap = False
    mismatches = 0
    for ex in p0_examples():
        sol = solve(ex.lcp, method="energy")
        lem = solve(ex.lcp, method="lemke")
        same = sol.ok and sol.iterations == ex.pivots
        mismatches += int(not same)
        style = "green" if same else "red"
        table.add_row(ex.name.replace("Kolesnikov example ", "ex "), f"[{style}]{sol.iterations}[/{style}]",
                      str(ex.pivots), str(lem.iterations),
                      "yes" if sol.stats.get("fallback") else "no", ex.note)
    console.print(table)
    _notes(console, ["Murty fallback: whether the energy method met a repeated basis or its "
                     "pivot cap and finished by Murty's least-index rule (finite for every "
                     "P-matrix)."])
    return mismatches
