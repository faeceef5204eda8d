"""Second order: qpcontact's `second_order=True` against the beam-column
equation's closed forms and OpenSees (openseespy) on the same frames.

OpenSees runs each frame with every member cut into ``--sub`` (64) elastic
beam-column elements (its P-δ comes from the cut: one element with the
PDelta transformation has P-Δ only; the cut's error falls as 1/sub², 8e-4
at 16, 5e-5 at 64 on the cantilever at half its buckling load) under the PDelta and the Corotational
transformations, the vertical loads applied first (LoadControl, 10 steps),
then the lateral ones (10 steps), Newton, NormDispIncr 1e-12.  Corotational
is large-displacement theory: it differs from a linearised (P-Δ) answer by
the rotations' second-order terms, ~θ², which the table shows beside.
qpcontact: one element per member (the stability functions are exact for
Euler–Bernoulli members), contacts as in the model.

Rows: a cantilever at 0.5 and 0.9 of its buckling load with a lateral tip
load; a sway portal (columns fixed at their bases, a beam 1e8 times stiffer);
time of qpcontact's solve and of OpenSees' analysis (median of --repeat).

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/frames_second_order.py [--sub 64]

(also printed at the end of benchmarks/frames.py).

Exits non-zero when qpcontact's answer is not ok or differs from the
closed form by more than 1e-8, or from OpenSees PDelta (cut) by more than
its cut's error (1e-3).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
import warnings

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.frames import Frame  # noqa: E402
from tests.helpers.opensees_chains import plane_chain, static_analysis  # noqa: E402

E, A, I = 2e8, 1e-2, 2e-5


def cantilever(share, H=10.0, L=5.0):
    """(name, members [(i, j, A, I)], nodes {n: (x, y)}, fixed, loads {n: (fx, fy)},
    closed-form sway of the top)."""
    P = share * np.pi ** 2 * E * I / (4 * L ** 2)
    k = np.sqrt(P / (E * I))
    exact = H * (np.tan(k * L) - k * L) / (P * k)
    return (f"cantilever {share:g} P_cr", [("A", "B", A, I)], {"A": (0, 0), "B": (0, L)},
            ["A"], {"B": (H, -P)}, "B", exact)


def portal(P=500.0, H=20.0, h=4.0, span=6.0):
    members = [("A", "B", A * 1e4, I), ("D", "C", A * 1e4, I), ("B", "C", A * 1e4, I * 1e8)]
    nodes = {"A": (0, 0), "B": (0, h), "C": (span, h), "D": (span, 0)}
    return ("sway portal", members, nodes, ["A", "D"], {"B": (H, -P), "C": (0.0, -P)}, "B",
            None)


def ours(model):
    name, members, nodes, fixed, loads, top, _ = model
    fr = Frame(units=("kN", "m"))
    for n, (x, y) in nodes.items():
        fr.add_node(n, x, y)
    fr.add_node("S", -2.0, 0.0)
    for i, j, a, ii in members:
        fr.add_member(i, j, E, a, ii)
    fr.add_member(fixed[0], "S", E, A, I)        # a stub on a pad: the frame's one contact
    fr.add_contact("S", normal=(0.0, 1.0))
    for n in fixed:
        fr.add_support(n)
    for n, (fx, fy) in loads.items():
        fr.add_load(n, fx=fx, fy=fy)
    res = fr.solve(second_order=True)
    return res, res.displacements[top][0]


def opensees(model, transformation, sub):
    import openseespy.opensees as ops

    name, members, nodes, fixed, loads, top, _ = model
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    tags = {n: k + 1 for k, n in enumerate(nodes)}
    for n, (x, y) in nodes.items():
        ops.node(tags[n], float(x), float(y))
    for n in fixed:
        ops.fix(tags[n], 1, 1, 1)
    ops.geomTransf(transformation, 1)
    nxt, ele = len(nodes) + 1, 1
    for i, j, a, ii in members:
        _, nxt, ele = plane_chain(ops, tags[i], tags[j], nodes[i], nodes[j], sub, nxt, ele, a, E,
                                  ii)
    for pattern, part in ((1, 1), (2, 0)):
        ops.timeSeries("Linear", pattern)
        ops.pattern("Plain", pattern, pattern)
        for n, f in loads.items():
            if f[part]:
                ops.load(tags[n], *((0.0, f[1], 0.0) if part else (f[0], 0.0, 0.0)))
        # the gravity pattern sets the analysis up; the push reuses it
        if not (static_analysis(ops, 1e-12, steps=10) if pattern == 1 else ops.analyze(10) == 0):
            return None
        ops.loadConst("-time", 0.0)
    return ops.nodeDisp(tags[top], 1)


def median_time(fn, repeat):
    fn()
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def table(sub=64, repeat=5) -> int:
    """Print the rows; the number of failed checks."""
    try:
        import openseespy.opensees  # noqa: F401
        have = True
    except (ImportError, RuntimeError):
        have = False
    failures = 0
    print(f"\nsecond order (P-Δ and P-δ): top sway [m], qpcontact (one element a member) "
          f"against the closed form and OpenSees ({sub} elements a member)")
    print(f"{'frame':<24} {'qpcontact':>13} {'closed form':>13} {'PDelta':>13} "
          f"{'Corotational':>13} {'vs PDelta':>10} {'ours ms':>8} {'OpenSees ms':>11}")
    for model in (cantilever(0.5), cantilever(0.9), portal()):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res, sway = ours(model)
            t_ours = median_time(lambda: ours(model), repeat)
        exact = model[-1]
        if not res.ok or (exact is not None and abs(sway - exact) > 1e-8 * abs(exact)):
            failures += 1
        pd = co = None
        t_os = float("nan")
        if have:
            pd = opensees(model, "PDelta", sub)
            co = opensees(model, "Corotational", sub)
            t_os = median_time(lambda: opensees(model, "PDelta", sub), repeat)
            if pd is None or abs(sway - pd) > 1e-3 * abs(pd):
                failures += 1
        cell = (lambda v: f"{v:13.8g}" if v is not None else f"{'-':>13}")
        rel = f"{abs(sway - pd) / abs(pd):10.1e}" if pd else f"{'-':>10}"
        print(f"{model[0]:<24} {sway:13.8g} {cell(exact)} {cell(pd)} {cell(co)} {rel} "
              f"{1e3 * t_ours:8.1f} {1e3 * t_os:11.1f}")
    return failures


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sub", type=int, default=64, help="OpenSees elements a member")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    sys.exit(1 if table(args.sub, args.repeat) else 0)


if __name__ == "__main__":
    main()
