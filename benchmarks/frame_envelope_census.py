"""Random beams on elastic pads under combinations, their extremes and
envelopes counted against a dense sampling and against each combination
solved alone (issue 52: envelopes where users look).

Each beam (seeded; even seeds plane, odd seeds space): 3–5 nodes 2–6 m
apart on elastic pads (stiffness 1e4–1e5), held along the beam at its first
node; in each of three cases D, L, W every member carries a partial
trapezoidal load between two random points (intensities in (−30, 10), so
often changing sign in its stretch; in space also a uniform wy), a point
force and a point moment at a random section, and a nodal load; four
combinations with random factors in (0, 1.6).

Checks, per beam:

* each combination of ``solve_combinations`` against ``solve(combination=)``
  alone: end forces to 1e-9 (nothing carried between combinations);
* ``extremes`` of every internal force against ``diagram(member, 20001)``:
  a miss is an extreme short of the dense samples' by more than 1e-9 of the
  diagram's largest (the unsafe side);
* ``envelope()`` against the dense samples' max/min over the combinations.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/frame_envelope_census.py [--beams 20]
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.frames import Frame, SpaceFrame  # noqa: E402

CASES = ("D", "L", "W")


def random_beam(seed):
    rng = np.random.default_rng(seed)
    space = seed % 2 == 1
    n = int(rng.integers(3, 6))
    xs = np.r_[0, np.cumsum(rng.uniform(2, 6, n - 1))]
    fr = SpaceFrame() if space else Frame()
    for k, x in enumerate(xs):
        fr.add_node(f"S{k}", x, 0.0, *((0.0,) if space else ()))
    for k in range(n - 1):
        section = dict(G=1.2e7, J=1e-3) if space else {}
        fr.add_member(f"S{k}", f"S{k + 1}", 3e7, 0.2, 4e-3, *((2e-3,) if space else ()),
                      name=f"B{k}", **section)
    if space:
        fr.add_support("S0", fix=("ux", "uy", "rx"))
        fr.add_support(f"S{n - 1}", fix=("uy",))
    else:
        fr.add_support("S0", fix=("ux",))
    for k in range(n):
        fr.add_contact(f"S{k}", **({} if space else {"normal": (0, 1)}),
                       stiffness=rng.uniform(1e4, 1e5))
    for c in CASES:
        for k in range(n - 1):
            L = xs[k + 1] - xs[k]
            a, b = np.sort(rng.uniform(0, L, 2))
            w1, w2 = rng.uniform(-30, 10, 2)
            if space:
                fr.add_distributed_load(f"B{k}", wz=w1, wz2=w2, wy=rng.uniform(-5, 5), start=a,
                                        end=b, case=c)
                fr.add_point_load(f"B{k}", rng.uniform(0, L), fz=rng.uniform(-40, 10),
                                  my=rng.uniform(-20, 20), mz=rng.uniform(-5, 5), case=c)
            else:
                fr.add_distributed_load(f"B{k}", wy=w1, wy2=w2, start=a, end=b, case=c)
                fr.add_point_load(f"B{k}", rng.uniform(0, L), fy=rng.uniform(-40, 10),
                                  mz=rng.uniform(-20, 20), case=c)
        fr.add_load("S1", **{"fz" if space else "fy": -rng.uniform(10, 100)}, case=c)
    combos = {f"C{k}": {c: float(f) for c, f in zip(CASES, rng.uniform(0, 1.6, 3))}
              for k in range(4)}
    return fr, combos, ("N", "Vy", "Vz", "T", "My", "Mz") if space else ("N", "V", "M")


def census(seed):
    """(alone differs, extreme misses, envelope misses, worst miss / scale)."""
    fr, combos, names = random_beam(seed)
    alone_bad = extreme_bad = envelope_bad = 0
    worst = 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve_combinations(combos)
        env = res.envelope()
        for name, combination in combos.items():
            alone, r = fr.solve(combination=combination), res[name]
            if r.ok != alone.ok:
                alone_bad += 1
                continue
            for m in (fr.members if r.ok else ()):
                ours, theirs = r.end_forces(m), alone.end_forces(m)
                alone_bad += sum(abs(ours[e][q] - theirs[e][q]) > 1e-9 * (1 + abs(theirs[e][q]))
                                 for e in ("i", "j") for q in ours[e])
        for m in fr.members:
            dense = {}
            for r in res.values():
                if not r.ok:
                    continue
                extremes = r.extremes(m)
                for q, arr in zip(names, r.diagram(m, 20001)[1:]):
                    scale = max(1.0, float(np.abs(arr).max()))
                    miss = max(arr.max() - extremes[q]["max"][0], extremes[q]["min"][0] - arr.min())
                    worst = max(worst, miss / scale)
                    extreme_bad += miss > 1e-9 * scale
                    hi, lo = dense.get(q, (-np.inf, np.inf))
                    dense[q] = (max(hi, arr.max()), min(lo, arr.min()))
            for q, (hi, lo) in dense.items():
                scale = max(1.0, abs(hi), abs(lo))
                envelope_bad += (hi - env[m][q]["max"][0] > 1e-9 * scale
                                 or env[m][q]["min"][0] - lo > 1e-9 * scale)
    return alone_bad, extreme_bad, envelope_bad, worst


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--beams", type=int, default=20)
    args = ap.parse_args(argv)
    totals, beams_missed, worst = np.zeros(3, int), 0, 0.0
    for seed in range(args.beams):
        *counts, w = census(seed)
        totals += counts
        beams_missed += any(counts)
        worst = max(worst, w)
        if any(counts):
            print(f"seed {seed:3d}: alone differs {counts[0]}, extremes missed {counts[1]}, "
                  f"envelope missed {counts[2]} (worst {w:.1e} of the diagram)")
    print(f"{args.beams} beams, {beams_missed} with a miss: alone differs {totals[0]}, extremes "
          f"missed {totals[1]}, envelopes missed {totals[2]}; worst miss {worst:.1e}")
    return 0 if not beams_missed else 1


if __name__ == "__main__":
    sys.exit(main())
