"""Limit loads of a family of space frames on frictional pads, counted.

For each frame, load case and friction model (Coulomb's circle, the
default; a polygon inscribed in it or circumscribed about it): the reference limit (a rigid body on the
pads: an LP written with scipy.optimize.linprog in tests/helpers/rigid_body_lp.py,
independent of the engine; on the circle the bracket of 2048-gons inside
and around it, within 1.2e-6), the trace's outcome (a proof — "collapse" with
a bracket — or not), the bracket ``tr.limit`` with its relative width and
whether it contains the reference, ``solve()`` at 50 / 90 / 99 / 99.9 % of
the bracket's lower end (ok, CHECK FAILED, SolverFailedError,
NoSolutionError), and the wall time.  One row per case, then counts per
frame.

The family (formulations/frames/space/space_family.py, space_tower.py):
tables on 3, 4 and 6 legs, rigid feet and elastic ones much softer (k 1e2
kN/m) and much stiffer (1e6) than the legs, decks 1, 1e2, 1e4 and 1e8 times
stiffer than the legs, pushed at the centre and at a corner, twisted, loaded
on an overhang; a skid pushed through its centre and at a corner; a pipe
rack on six elastic pads under D + p U (a corner uplift); a 10-storey tower
on 16 pads under D + p W.

Where the trace ends "bounded" (the path stops unproved below the rigid
body's proved limit: non-associated friction) the bracket shown is that
bound [last certified equilibrium, proof], and "exhausted" counts those
whose stop is where the pads' friction is exhausted under the frame's own
normal forces (``tr.capacity``); where a proved bracket lies
below the LP's limit (the path ends before the rigid body's statics
would), the row says "below LP": the reference is then an upper bound,
not the limit.

    .venv/bin/python benchmarks/frame_limits.py            # the family
    .venv/bin/python benchmarks/frame_limits.py --quick    # a small subset
    .venv/bin/python benchmarks/frame_limits.py --only skid,rack
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import time
import warnings
from collections import defaultdict

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.frames.space.space_family import (  # noqa: E402
    RACK_CASES, SKID_CASES, TABLE_CASES, pipe_rack, skid, table)
from formulations.frames.space.space_tower import space_tower  # noqa: E402
from qpcontact.core.errors import (  # noqa: E402
    NoSolutionError, QpcontactError, SolverFailedError)
from tests.helpers.rigid_body_lp import coulomb_limits, static_limit  # noqa: E402

FRACTIONS = (0.5, 0.9, 0.99, 0.999)
CONES = ("circular", "inscribed", "circumscribed")
#: the models in the rows' names
LABEL = {"circular": "circle", "inscribed": "inscr", "circumscribed": "circum"}
#: pads much softer than the legs' bending (1.2e3 kN/m), and much stiffer
#: than their axial stiffness (2.5e5 kN/m)
FEET = {"rigid": None, "soft": 1e2, "stiff": 1e6}
RATIOS = (1.0, 1e2, 1e4, 1e8)


def family(quick: bool):
    """(frame name, builder, case names, constant combination)."""
    out = []
    if quick:
        for polygon in CONES:
            out.append((f"table4 r1e4 rigid {LABEL[polygon]}",
                        lambda p=polygon: table(4, 1e4, cone=p), TABLE_CASES))
        out.append(("skid rigid circle", lambda: skid(), SKID_CASES))
        return [(n, b, c, {"constant": 1.0}) for n, b, c in out]
    for legs in (3, 4, 6):
        for feet, k in FEET.items():
            ratios = RATIOS if legs == 4 else ((1.0, 1e4) if feet == "rigid" else (1e4,))
            for ratio in ratios:
                for polygon in CONES:
                    out.append((f"table{legs} r{ratio:.0e} {feet} {LABEL[polygon]}",
                                lambda lg=legs, r=ratio, kk=k, p=polygon:
                                table(lg, r, stiffness=kk, cone=p), TABLE_CASES))
    for feet, k in (("rigid", None), ("stiff", 1e6)):
        for polygon in CONES:
            out.append((f"skid {feet} {LABEL[polygon]}",
                        lambda kk=k, p=polygon: skid(stiffness=kk, cone=p), SKID_CASES))
    for polygon in CONES:
        out.append((f"rack k1e6 {LABEL[polygon]}", lambda p=polygon: pipe_rack(cone=p),
                    RACK_CASES))
    out = [(n, b, c, {"constant": 1.0}) for n, b, c in out]
    for cone in CONES:
        out.append((f"tower 10x3 rigid {LABEL[cone]}",
                    lambda c=cone: space_tower(10, 3, facets=16, cone=c), ("W",), {"D": 1.0}))
    return out


class Timeout(Exception):
    pass


class Failed(Exception):
    """The trace raised: its row is filled, the solves tried at the reference's fractions."""


def alarm(signum, frame):
    raise Timeout()


def solve_word(fr, const, case, p):
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = fr.solve(combination={**const, case: p})
    except SolverFailedError:
        return "SFE"
    except NoSolutionError:
        return "NOSOL"
    except QpcontactError:
        return "ERR"
    return "ok" if res.ok else "CHECK"


def run_case(name, build, case, const, limit_s):
    fr = build()
    if fr.cone == "circular":     # Coulomb's circle: between 2048-gons inside and around it
        ref_lo, ref = coulomb_limits(fr, const, {case: 1.0})
    else:
        ref_lo = ref = static_limit(fr, const, {case: 1.0})
    start = time.perf_counter()
    signal.alarm(limit_s)
    row = dict(frame=name, case=case, ref=ref)
    try:
        try:
            tr = fr.trace(constant=const, variable=case)
        except QpcontactError as exc:
            row.update(ended=type(exc).__name__[:10], proof=False, bounded=False, lo=np.nan,
                       hi=np.nan,
                       width=np.nan, contains=False, below_lp=False, message=str(exc),
                       trace_s=time.perf_counter() - start,
                       solves=[solve_word(fr, const, case, f * ref) for f in FRACTIONS])
            raise Failed() from exc
        row["trace_s"] = time.perf_counter() - start
        row["ended"] = tr.ended if tr.ok or tr.ended != "collapse" else "collapse?"
        row["proof"] = tr.limit is not None and tr.ok
        row["message"] = tr.message
        bound = getattr(tr, "bound", None)
        lo, hi = (tr.limit if tr.limit is not None else bound if bound is not None
                  else (tr.p_end, np.nan))
        row["lo"], row["hi"] = lo, hi
        row["bounded"] = tr.limit is None and bound is not None
        # bounded where the pads' friction is exhausted under the frame's own
        # normal forces (tr.capacity: the path's stop, not a missing scheme)
        row["exhausted"] = row["bounded"] and getattr(tr, "capacity", None) is not None
        row["width"] = (hi - lo) / abs(hi) if np.isfinite(hi) else np.nan
        tol = 1e-9 * max(abs(ref), 1.0)
        row["contains"] = bool(tr.limit is not None and lo - tol <= ref and ref_lo <= hi + tol)
        row["below_lp"] = bool(tr.limit is not None and hi < ref_lo - tol)
        base = lo if np.isfinite(lo) and lo > 0 else ref
        row["solves"] = [solve_word(fr, const, case, f * base) for f in FRACTIONS]
    except Failed:
        pass
    except Timeout:
        row.update(ended="timeout", proof=False, bounded=False, lo=np.nan, hi=np.nan,
                   width=np.nan,
                   contains=False, below_lp=False, solves=["-"] * 4, message="",
                   trace_s=float(limit_s))
    finally:
        signal.alarm(0)
    row["wall_s"] = time.perf_counter() - start
    return row


def fmt(row):
    solves = "/".join(row["solves"])
    contains = ("yes" if row["contains"] else "below LP" if row["below_lp"] else "NO")
    return (f"{row['frame']:<28} {row['case']:<9} {row['ref']:>14.9g} {row['ended']:<10} "
            f"[{row['lo']:.12g}, {row['hi']:.12g}] {row['width']:8.1e} {contains:<8} "
            f"{solves:<22} {row['wall_s']:6.1f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="a small subset")
    ap.add_argument("--only", default="", help="frames whose name contains one of these "
                                               "comma-separated words")
    ap.add_argument("--time-limit", type=int, default=300, help="seconds per case at most")
    ap.add_argument("--messages", action="store_true", help="print each trace's message")
    args = ap.parse_args()
    signal.signal(signal.SIGALRM, alarm)
    words = [w for w in args.only.split(",") if w]
    cases = [c for c in family(args.quick) if not words or any(w in c[0] for w in words)]
    total = sum(len(c[2]) for c in cases)
    print(f"{'frame':<28} {'case':<9} {'reference':>14} {'trace end':<10} bracket  width  "
          f"contains solves@50/90/99/99.9%  wall_s")
    rows, done = [], 0
    for name, build, load_cases, const in cases:
        for case in load_cases:
            done += 1
            print(f"  [{done}/{total}] {name} {case} ...", file=sys.stderr, flush=True)
            row = run_case(name, build, case, const, args.time_limit)
            rows.append(row)
            print(fmt(row), flush=True)
            if args.messages:
                print("    ", row["message"][:400], flush=True)
    print()
    print(f"{'frame kind':<12} {'cases':>5} {'proof':>5} {'bounded':>7} {'exhausted':>9} "
          f"{'no proof':>8} "
          f"{'bracket>1e-6':>12} "
          f"{'misses ref':>10} {'below LP':>8} {'CHECK':>5} {'SFE':>4} {'NOSOL':>5} "
          f"{'ERR':>4} {'wall_s':>7}")
    groups = defaultdict(list)
    for r in rows:
        groups[r["frame"].split()[0]].append(r)
    groups["all"] = rows
    for kind, rs in groups.items():
        solves = [s for r in rs for s in r["solves"]]
        print(f"{kind:<12} {len(rs):>5} {sum(r['proof'] for r in rs):>5} "
              f"{sum(r.get('bounded', False) for r in rs):>7} "
              f"{sum(r.get('exhausted', False) for r in rs):>9} "
              f"{sum(not r['proof'] and not r.get('bounded', False) for r in rs):>8} "
              f"{sum(r['proof'] and not r['width'] <= 1e-6 for r in rs):>12} "
              f"{sum(not r['contains'] and not r['below_lp'] for r in rs):>10} "
              f"{sum(r['below_lp'] for r in rs):>8} {solves.count('CHECK'):>5} "
              f"{solves.count('SFE'):>4} {solves.count('NOSOL'):>5} {solves.count('ERR'):>4} "
              f"{sum(r['wall_s'] for r in rs):>7.1f}")


if __name__ == "__main__":
    main()
