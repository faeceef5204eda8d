""""No solution" in milliseconds: how long "auto" takes to prove that an LCP
is infeasible or a QP unbounded, and what its proof-first step costs on
problems that have a solution.

Part 1 — time to proof.  Problems with a planted certificate in small
integers (tests/helpers/no_solution.py: infeasible LCPs with a symmetric PSD
M, a general dense M, one row of M with no positive entry; unbounded QPs with
a planted ray), and the stress suite's no-solution families
(qpcontact.commands.stress.build_case: "infeasible", "infeasible_rounded",
"qp_unbounded", "qp_unbounded_rounded", "qp_infeasible").  Each is solved by
"auto" with time_limit=20; printed: the status (and whether it is the
expected one with a proof), wall and CPU seconds, and what "auto" tried.

Part 2 — the overhead on problems with a solution.  For the stress suite's
solvable families, "auto" with its proof-first step
(qpcontact.dispatch.lcp_qp_run.proof_first) and without it, on fresh copies
of the same problem, side by side (CPU seconds: the machine is shared): the
ratio with / without is what the step adds.

Part 3 — the limit kept by backends without a time setting of their own
(PIQP, DAQP, quadprog and their cvxpy twins; ProxQP for comparison), each
called by name on the no-solution families with a short limit: wall seconds
against the limit plus its grace (qpcontact.core.deadline.grace).

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/no_solution.py
    options: --sizes 60,120,250,500,1000  --seeds 2  --part 1|2|3|both
             --limit-methods piqp,daqp,...  --limit-families infeasible,...
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import qpcontact  # noqa: E402
from qpcontact.commands.stress import build_case  # noqa: E402
from qpcontact.core.errors import QpcontactError  # noqa: E402
from tests.helpers.no_solution import farkas_lcp, ray_qp  # noqa: E402

PLANTED = ("lcp-psd", "lcp-general", "lcp-row", "qp-ray")
STRESS_NO_SOLUTION = ("infeasible", "infeasible_rounded", "qp_unbounded", "qp_unbounded_rounded",
                      "qp_infeasible")
STRESS_SOLVABLE = ("spd", "psd_singular", "degenerate", "p_matrix", "friction", "far_contact",
                   "ties", "qp_convex", "qp_degenerate", "qp_penalty")


def _planted(family, n, seed):
    if family == "qp-ray":
        return ray_qp(n, seed)[0], "unbounded"
    return farkas_lcp(n, seed, family[4:])[0], "infeasible"


def _timed(fn, *args, **kwargs):
    wall, cpu = time.perf_counter(), time.process_time()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - wall, time.process_time() - cpu


def part1(sizes, seeds, time_limit):
    print(f"time to proof, 'auto', time_limit={time_limit:g} s (grace "
          f"{0.5 + 0.1 * time_limit:g} s)")
    print(f"{'family':22s} {'n':>5s} {'seed':>4s} {'status':>11s} {'proved':>6s} {'wall':>7s} "
          f"{'cpu':>7s}  tried")
    worst = 0.0
    for family in PLANTED + STRESS_NO_SOLUTION:
        for n in sizes:
            for seed in range(seeds):
                if family in PLANTED:
                    problem, expected = _planted(family, n, seed)
                else:
                    case = build_case(family, n, seed)
                    problem, expected = case.problem, case.status
                sol, wall, cpu = _timed(qpcontact.solve, problem, "auto", time_limit=time_limit)
                proved = sol.status == expected and "proof" in sol.stats
                worst = max(worst, wall)
                tried = ", ".join(f"{m}:{s}" for m, s, _ in sol.stats.get("auto_tried", []))
                print(f"{family:22s} {n:5d} {seed:4d} {sol.status:>11s} {str(proved):>6s} "
                      f"{wall:7.2f} {cpu:7.2f}  {tried}", flush=True)
    print(f"longest call: {worst:.2f} s (limit {time_limit:g} s + grace)")


REPEATS = 3


def part2(sizes, seeds):
    """"auto" with and without its proof-first step, on fresh copies of the
    same problem, alternating which goes first (CPU seconds)."""
    from qpcontact.dispatch import driver

    real = driver.proof_first
    print("overhead of the proof-first step on solvable problems: 'auto' with and without it "
          "(CPU seconds, the least of 3 runs side by side, mean over seeds)")
    print(f"{'family':16s} {'n':>5s} {'with':>8s} {'without':>8s} {'ratio':>7s}")
    for family in STRESS_SOLVABLE:
        for n in sizes:
            with_, without = 0.0, 0.0
            qpcontact.solve(build_case(family, n, 0).problem, "auto")    # warm: imports, caches
            for seed in range(seeds):
                best = {True: float("inf"), False: float("inf")}
                for _ in range(REPEATS):       # the least of a few: the machine is shared
                    for use in (True, False):
                        # a fresh copy each time: an LCP keeps its factorization
                        problem = build_case(family, n, seed).problem
                        driver.proof_first = real if use else (lambda problem, ctx: None)
                        try:
                            _, _, cpu = _timed(qpcontact.solve, problem, "auto")
                        finally:
                            driver.proof_first = real
                        best[use] = min(best[use], cpu)
                with_, without = with_ + best[True], without + best[False]
            print(f"{family:16s} {n:5d} {with_ / seeds:8.4f} {without / seeds:8.4f} "
                  f"{with_ / max(without, 1e-9):7.2f}", flush=True)


LIMIT_METHODS = ("piqp", "daqp", "quadprog", "proxqp", "cvxpy:PIQP", "cvxpy:DAQP")


def part3(sizes, seeds, time_limit, methods, families):
    """Each backend by name on data with no solution, with ``time_limit``:
    the wall seconds, whether they kept limit + grace, and whether the call
    ran in a child process."""
    from qpcontact.core.deadline import grace

    bound = time_limit + grace(time_limit)
    print(f"limits kept by backends without a time setting: time_limit={time_limit:g} s "
          f"(+ grace: {bound:g} s)")
    print(f"{'family':22s} {'n':>5s} {'seed':>4s} {'method':>11s} {'status':>11s} {'wall':>7s} "
          f"{'kept':>5s} {'isolated':>8s}")
    worst = 0.0
    for family in families:
        for n in sizes:
            for seed in range(seeds):
                for method in methods:
                    if family in PLANTED:
                        problem = _planted(family, n, seed)[0]
                    else:
                        problem = build_case(family, n, seed).problem
                    try:
                        sol, wall, _ = _timed(qpcontact.solve, problem, method,
                                              time_limit=time_limit)
                    except QpcontactError as exc:
                        print(f"{family:22s} {n:5d} {seed:4d} {method:>11s} refused: "
                              f"{str(exc)[:60]}", flush=True)
                        continue
                    worst = max(worst, wall)
                    print(f"{family:22s} {n:5d} {seed:4d} {method:>11s} {sol.status:>11s} "
                          f"{wall:7.2f} {str(wall <= bound):>5s} "
                          f"{str(bool(sol.stats.get('isolated'))):>8s}", flush=True)
    print(f"longest call: {worst:.2f} s (limit {time_limit:g} s + grace = {bound:g} s)")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="60,120,250,500,1000")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--part", default="both", choices=("1", "2", "3", "both"))
    ap.add_argument("--limit-methods", default=",".join(LIMIT_METHODS))
    ap.add_argument("--limit-families", default="infeasible,qp_unbounded,qp_infeasible")
    ap.add_argument("--time-limit", type=float, default=20.0)
    args = ap.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",")]
    # the one-time imports paid before timing (HiGHS through SciPy, cvxpy's
    # registry: seconds each on a first call, which time_limit does not cover)
    import scipy.optimize  # noqa: F401

    qpcontact.methods()
    qpcontact.solve(qpcontact.LCP([[1.0]], [-1.0]), "auto")
    if args.part in ("1", "both"):
        part1(sizes, args.seeds, args.time_limit)
    if args.part in ("2", "both"):
        part2(sizes, args.seeds)
    if args.part == "3":
        part3(sizes, args.seeds, args.time_limit, args.limit_methods.split(","),
              args.limit_families.split(","))
    return 0


if __name__ == "__main__":
    sys.exit(main())
