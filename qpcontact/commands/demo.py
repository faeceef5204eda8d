"""The demo job: every installed method on the decomposition paper's examples.

Each method solves P0 examples 1-3 at the requested accuracy; the table shows
the certificate, the wall time and the distance to the solution printed in
the paper.  A second table puts the energy method's pivot counts beside the
paper's.  Later formulations extend this demo.
"""

from __future__ import annotations

import numpy as np

from ..core.errors import InvalidProblemError
from ..solvers.registry import methods
from ..cases.paper import p0_examples
from ..dispatch.driver import solve

__all__ = ["run_demo"]


def _lcp_methods() -> list[str]:
    """The installed methods that solve an LCP (the registry also holds the
    friction methods and the load trace)."""
    return [name for name, m in methods().items() if m.solves("lcp")]


def demo_rows(accuracy="high") -> list[dict]:
    """One row per (method, example): status, certificate error, time, and the
    largest difference from the paper's solution relative to max|z|."""
    rows = []
    examples = p0_examples()
    for name in _lcp_methods():
        for ex in examples:
            sol = solve(ex.lcp, method=name, accuracy=accuracy)
            dz = np.inf if sol.z is None else float(np.max(np.abs(sol.z - ex.z)) / np.max(np.abs(ex.z)))
            cert = sol.certificate
            rows.append(dict(method=name, example=ex.name.replace("P0 example ", "ex "), status=sol.status, ok=sol.ok,
                             error=sol.error, forward=sol.forward_error,
                             siconos=(cert.siconos_error if cert else np.inf),
                             time=sol.wall_time, dz=dz, iterations=sol.iterations))
    return rows


def run_demo(accuracy="high", console=None) -> int:
    """Print the demo table; return the number of certified answers that
    disagree with the paper (0 when all is well)."""
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    console = console or Console()
    if not console.is_terminal:
        console.width = max(console.width, 120)  # keep rows on one line in logs
    rows = demo_rows(accuracy)
    table = Table(title=f"P0 examples (Kolesnikov 2013), accuracy={accuracy!r}: "
                        "certificate, time, agreement with the paper")
    for col in ("method", "example", "status", "error", "fwd err", "Siconos err", "time [ms]", "iters",
                "|z-z_paper|/|z|"):
        table.add_column(escape(col), justify="left" if col in ("method", "example", "status") else "right")
    wrong = 0
    for r in rows:
        agree = r["dz"] <= 1e-6
        wrong += int(r["ok"] and not agree)
        style = "green" if r["ok"] and agree else ("red" if r["ok"] else "yellow")
        table.add_row(r["method"], r["example"], f"[{style}]{r['status']}[/{style}]", f"{r['error']:.1e}",
                      f"{r['forward']:.1e}", f"{r['siconos']:.1e}", f"{1e3 * r['time']:.2f}",
                      "" if r["iterations"] is None else str(r["iterations"]), f"{r['dz']:.1e}")
    console.print(table)
    n_ok = sum(r["ok"] for r in rows)
    console.print(f"{n_ok}/{len(rows)} answers certified; "
                  f"{len(rows) - n_ok} reported not certified (status 'inaccurate' or 'failed'); "
                  f"{wrong} certified answers disagree with the paper.")
    console.print("error = componentwise certificate (qpcontact.certify: each row against its own "
                  "data); fwd err = estimated distance from the exact solution, relative to each "
                  "component's own size; 'inaccurate' means the backend returned a point the "
                  "certificate rejects — see docs/certificates.md and docs/backends.md.")
    return wrong + _pivot_table(console) + _far_contact_table(console) + _formulation_demos(console)


def _far_contact_table(console) -> int:
    """One far-contact problem (gaps of 5e11 beside gaps of 0.1) with every
    installed method: the componentwise error against the normwise one and the
    distance to the planted solution.  Returns the answers certified although
    wrong (must be 0)."""
    from rich.table import Table

    from ..cases.families import far_contact_lcp, planted_ok

    lcp, z_star, w_star = far_contact_lcp(0)
    table = Table(title="Far contacts (n = 21, three gaps of 5e11 beside gaps of 0.1): what each "
                        "method returns, judged componentwise")
    for col in ("method", "status", "error", "normwise", "max|z - z*|", "right"):
        table.add_column(col, justify="left" if col in ("method", "status") else "right")
    silent = 0
    for name in _lcp_methods():
        try:
            sol = solve(lcp, method=name)
        except InvalidProblemError as exc:      # a size limit ('enumeration': n <= 16)
            table.add_row(name, "not applicable", "", "", "", str(exc).split(";")[0][:40])
            continue
        right = planted_ok(sol.z, sol.w, z_star, w_star)
        silent += int(sol.ok and not right)
        dz = np.inf if sol.z is None else float(np.max(np.abs(sol.z - z_star)))
        nw = sol.certificate.normwise_error if sol.certificate is not None else np.inf
        style = "green" if sol.ok and right else ("red" if sol.ok else "yellow")
        table.add_row(name, f"[{style}]{sol.status}[/{style}]", f"{sol.error:.1e}", f"{nw:.1e}",
                      f"{dz:.1e}", "yes" if right else "no")
    console.print(table)
    console.print(f"{silent} answers certified although wrong. A normwise error below 1e-9 next "
                  "to a large componentwise one is the blind spot the componentwise certificate "
                  "closes (docs/certificates.md).")
    return silent


def _formulation_demos(console) -> int:
    """Each installed formulation's demo (entry-point group ``qpcontact.formulations``)."""
    from importlib.metadata import entry_points

    failed = 0
    for ep in sorted(entry_points(group="qpcontact.formulations"), key=lambda e: e.name):
        module = ep.load()
        if hasattr(module, "demo"):
            failed += int(module.demo(console))
    return failed


def _pivot_table(console) -> int:
    """P0's energy method: our pivot counts beside the paper's; returns mismatches."""
    from rich.table import Table

    table = Table(title="Energy method (P0): principal pivots, ours vs the paper's")
    for col in ("example", "pivots (energy)", "pivots (paper)", "lemke pivots", "Murty fallback",
                "note"):
        table.add_column(col, justify="left" if col in ("example", "note") else "right")
    mismatches = 0
    for ex in p0_examples():
        sol = solve(ex.lcp, method="energy")
        lem = solve(ex.lcp, method="lemke")
        same = sol.ok and sol.iterations == ex.pivots
        mismatches += int(not same)
        style = "green" if same else "red"
        table.add_row(ex.name, f"[{style}]{sol.iterations}[/{style}]", str(ex.pivots),
                      str(lem.iterations), "yes" if sol.stats.get("fallback") else "no", ex.note)
    console.print(table)
    return mismatches
