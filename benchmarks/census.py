"""Census of "ok" on rounded data: does "ok" mean correct digits on real-valued data?

Runs the rounded stress families (references decided in rational arithmetic,
qpcontact/cases/rounded.py) through the stress machinery — "auto" and every
installed LCP/QP method, accuracies rotating low/default/high — and prints,
per family and per method: certified, ok but wrong (against the exact
reference), false proofs, proved, honest not-ok, failed, hung, and the whole
wall time (median, max, count over its time share).

    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/census.py \\
        --out /tmp/census > docs/census-after.txt

Defaults (sizes 8 and 30, 20 seeds, time limit 2 s, 2 workers, no cvxpy)
take about 10 minutes on 2 cores; --seeds, --sizes, --cvxpy, --families
change that, and --csv re-prints the census of an earlier run's stress.csv.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import math
import statistics
import sys
import time
from collections import defaultdict

CLASSES = ("certified", "ok_wrong", "false_proof", "proved", "honest_not_ok", "failed", "hung")


def classify(row: dict) -> str:
    """One census class per solve, from the stress row (judged against the
    exact reference by qpcontact/commands/stress/judge.py)."""
    cat, status = row["category"], row["status"]
    if cat == "silent_wrong":
        return "ok_wrong" if status == "solved" else "false_proof"
    if cat in ("certified", "proved", "hung"):
        return cat
    if cat == "inaccurate":
        return "honest_not_ok"
    # "failed": an honest status (failed, or a proof on a case whose reference
    # is unknown) is still honest; crashes, kills and exceptions are failures
    return "honest_not_ok" if status in ("failed", "infeasible", "unbounded", "time_limit") \
        else "failed"


def _float(v) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def table(rows: list[dict], key) -> list[str]:
    groups: dict = defaultdict(list)
    for r in rows:
        groups[key(r)].append(r)
    head = ("| " + " | ".join(["class", "solves", *CLASSES, "median s", "max s", "over limit"])
            + " |")
    lines = [head, "|" + "---|" * (len(CLASSES) + 5)]
    for k in sorted(groups):
        rs = groups[k]
        counts = {c: 0 for c in CLASSES}
        for r in rs:
            counts[classify(r)] += 1
        t = [x for x in (_float(r.get("wall") or r.get("seconds")) for r in rs) if math.isfinite(x)]
        over = sum(int(_float(r.get("over_limit")) or 0) for r in rs
                   if math.isfinite(_float(r.get("over_limit"))))
        lines.append(f"| {k} | {len(rs)} | " + " | ".join(str(counts[c]) for c in CLASSES)
                     + f" | {statistics.median(t) if t else math.nan:.3g}"
                     f" | {max(t) if t else math.nan:.3g} | {over} |")
    return lines


def report(rows: list[dict], header: list[str]) -> str:
    expected: dict = defaultdict(lambda: defaultdict(int))
    # killed or crashed rows do not know the case's status: take a row that does
    for r in {(r["family"], r["n"], r["seed"]): r for r in rows if r["expected"]}.values():
        expected[r["family"]][r["expected"]] += 1
    out = header + ["", "Reference status per family (problems): " + "; ".join(
        f"{f}: " + ", ".join(f"{k} {v}" for k, v in sorted(d.items()))
        for f, d in sorted(expected.items()))]
    out += ["", "ok_wrong: said ok, disagrees with the exact reference (no correct digit, or "
            "ok on an infeasible/unbounded case); false_proof: claimed no solution on a solvable "
            "case; honest_not_ok: not ok and said so (inaccurate, ill_posed, failed, ...); "
            "failed: crash, kill or exception.", "", "## Per family", ""]
    out += table(rows, lambda r: r["family"])
    out += ["", "## Per method", ""]
    out += table(rows, lambda r: r["method"])
    out += ["", "## Per family and method", ""]
    out += table(rows, lambda r: f"{r['family']} / {r['method']}")
    out += ["", "## Per method and accuracy", ""]
    out += table(rows, lambda r: f"{r['method']} / {r['accuracy']}")
    wrong = [r for r in rows if r["category"] == "silent_wrong"]
    if wrong:
        out += ["", f"## The {len(wrong)} wrong answers (first 60)", ""]
        out += [f"- {r['method']} on {r['family']} n={r['n']} seed={r['seed']} ({r['accuracy']}, "
                f"reference {r['expected']}): {r['status']}: {r['reason']}" for r in wrong[:60]]
    return "\n".join(out) + "\n"


def main(argv=None) -> int:
    from qpcontact.commands.stress import QUICK, run_stress
    from qpcontact.commands.stress.cases import ROUNDED_FAMILIES

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="/tmp/census", help="folder for stress.csv")
    ap.add_argument("--sizes", default="8,30")
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--families", default=",".join(ROUNDED_FAMILIES))
    ap.add_argument("--methods", default=None, help="default: auto and every installed method")
    ap.add_argument("--cvxpy", action="store_true", help="include the cvxpy methods")
    ap.add_argument("--time-limit", type=float, default=2.0)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--csv", default=None, help="re-print the census of an earlier stress.csv")
    args = ap.parse_args(argv)
    import qpcontact

    start = time.time()
    if args.csv:
        path = args.csv
    else:
        config = dataclasses.replace(
            QUICK, sizes=tuple(int(s) for s in args.sizes.split(",")), seeds=args.seeds,
            families=tuple(args.families.split(",")), no_cvxpy=not args.cvxpy,
            methods=tuple(args.methods.split(",")) if args.methods else None,
            accuracies=("low", "default", "high"), rotate_accuracy=True,
            time_limit=args.time_limit)
        path = run_stress(args.out, config, workers=args.workers, progress=sys.stderr.isatty())
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    header = [f"# Census of ok on rounded data (qpcontact {getattr(qpcontact, '__version__', '?')})", "",
              f"command: python benchmarks/census.py {' '.join(argv or sys.argv[1:])}",
              f"{len(rows)} solves of {len({(r['family'], r['n'], r['seed']) for r in rows})} "
              f"problems; sizes {args.sizes} (exact LCP families capped at n = 40), "
              f"{args.seeds} seeds, accuracy rotating low/default/high, time limit "
              f"{args.time_limit:g} s; {time.time() - start:.0f} s wall"]
    print(report(rows, header), end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
