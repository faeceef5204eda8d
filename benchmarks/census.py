"""Census of "ok": does "ok" mean correct digits, against exact references?

Runs the rounded and edge stress families (references decided in rational
arithmetic, qpcontact/cases/rounded.py; --all adds every other stress family)
through the stress machinery — "auto" and every installed LCP/QP method, each
at every accuracy level (low, default, high) — and prints, per family and per
method: certified, ok but wrong (against the exact reference: no correct
leading digit, or ok on a problem without solution), ok beside a doubt (an ok
answer whose message says the data may have no solution), forward-error
misses (the certificate's scale_forward_error below half the true error on
the same scales, where the reference is unique), false proofs, unproved rays
where a one-row Farkas vector exists, proved, honest not-ok, failed, hung,
and the wall time (median, max, count over its limit).

    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/census.py \\
        --out /tmp/census > /tmp/census.txt

Defaults (sizes 8 and 30, 10 seeds, time limit 2 s, 2 workers, no cvxpy)
take about 15 minutes on 2 cores; --seeds, --sizes, --cvxpy, --families,
--all change that, and --csv re-prints the census of an earlier run's
stress.csv.
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

#: counted beside the classes (a solve may be in a class and in these)
MARKS = ("ok_doubt", "fe_miss", "fe_miss_any", "ray_one_row")


def marks(row: dict) -> dict:
    """The census's further counts for one solve: ok beside a doubt, a
    forward-error estimate below half the truth (true error above 1e-12 of
    the scale, so that rounding noise is not counted), an unproved ray where
    a one-row Farkas vector exists."""
    true, est = _float(row.get("fe_true")), _float(row.get("fe_est"))
    missed = math.isfinite(true) and not math.isnan(est) and true > 1e-12 and true > 2 * est
    return {"ok_doubt": int(_float(row.get("doubt")) == 1),
            # an estimate of 0.5 or more already says "no digit": a truth
            # beyond it misleads no one (fe_miss_any counts those too)
            "fe_miss": int(missed and est < 0.5),
            "fe_miss_any": int(missed),
            "ray_one_row": int(row.get("status") == "ray" and _float(row.get("one_row")) == 1)}


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
    head = ("| " + " | ".join(["class", "solves", *CLASSES, *MARKS, "median s", "max s",
                                "over limit"]) + " |")
    lines = [head, "|" + "---|" * (len(CLASSES) + len(MARKS) + 5)]
    for k in sorted(groups):
        rs = groups[k]
        counts = {c: 0 for c in CLASSES + MARKS}
        for r in rs:
            counts[classify(r)] += 1
            for name, v in marks(r).items():
                counts[name] += v
        t = [x for x in (_float(r.get("wall") or r.get("seconds")) for r in rs) if math.isfinite(x)]
        over = sum(int(_float(r.get("over_limit")) or 0) for r in rs
                   if math.isfinite(_float(r.get("over_limit"))))
        lines.append(f"| {k} | {len(rs)} | " + " | ".join(str(counts[c]) for c in CLASSES + MARKS)
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
            "failed: crash, kill or exception; ok_doubt: ok, and the message says the data may "
            "have no solution; fe_miss: the forward-error estimate below half the true error "
            "(unique reference) where the estimate claims a digit (below 0.5); fe_miss_any: the "
            "same without that condition; ray_one_row: an unproved ray although a one-row Farkas vector "
            "exists.", "", "## Totals", ""]
    out += table(rows, lambda r: "all")
    out += ["", "## Per family", ""]
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
    from qpcontact.commands.stress.cases import FAMILIES, ROUNDED_FAMILIES

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="/tmp/census", help="folder for stress.csv")
    ap.add_argument("--sizes", default="8,30")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--first-seed", type=int, default=0,
                    help="seeds first-seed .. first-seed + seeds - 1 (fresh ones for a new census)")
    ap.add_argument("--families", default=",".join(ROUNDED_FAMILIES))
    ap.add_argument("--all", action="store_true",
                    help="every stress family (Siconos files aside), not only the exact ones")
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
            first_seed=args.first_seed,
            families=(tuple(f for f in FAMILIES if f != "siconos") if args.all
                      else tuple(args.families.split(","))), no_cvxpy=not args.cvxpy,
            methods=tuple(args.methods.split(",")) if args.methods else None,
            accuracies=("low", "default", "high"), rotate_accuracy=False,
            time_limit=args.time_limit)
        path = run_stress(args.out, config, workers=args.workers, progress=sys.stderr.isatty())
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    header = [f"# Census of ok on rounded data (qpcontact {getattr(qpcontact, '__version__', '?')})", "",
              f"command: python benchmarks/census.py {' '.join(argv or sys.argv[1:])}",
              f"{len(rows)} solves of {len({(r['family'], r['n'], r['seed']) for r in rows})} "
              f"problems; sizes {args.sizes} (exact LCP families capped at n = 40), "
              f"{args.seeds} seeds from {args.first_seed}, every accuracy (low, default, high), time limit "
              f"{args.time_limit:g} s; {time.time() - start:.0f} s wall"]
    print(report(rows, header), end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
