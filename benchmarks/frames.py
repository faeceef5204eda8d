"""Frames: time to analyse one load combination, qpcontact against PyNite on
the same models, measured side by side in one run (ratios), every qpcontact
answer checked (certificate + statics) and its support reactions compared
with PyNite's.

Models: a continuous beam of 50, 200 and 1000 spans (6 m, concrete) on
compression-only elastic supports, self-weight plus a few uplift point loads
(some supports lift off); and a 20-storey, 3-bay frame on compression-only
bases under gravity and wind.

    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 .venv/bin/python benchmarks/frames.py

Targets (issue 17): 200 spans within 3x of OpenSees's time class (0.03 s);
1000 spans under 0.5 s.  Options: --spans 50,200,1000  --storeys 20  --repeat 3
"""

from __future__ import annotations

import argparse
import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.frames import Frame  # noqa: E402

E, A, I, K = 30e6, 0.32, 0.017, 6e4


def beam_model(spans: int):
    """(nodes, members, supports, loads) in plain lists, built into both codes."""
    rng = np.random.default_rng(spans)
    xs = 6.0 * np.arange(spans + 1)
    up = set(rng.choice(np.arange(1, spans), size=max(1, spans // 10), replace=False).tolist())
    loads = {k: 250.0 for k in up}
    return xs, loads


def ours_beam(spans):
    xs, loads = beam_model(spans)
    fr = Frame()
    for k, x in enumerate(xs):
        fr.add_node(f"N{k}", float(x), 0.0)
    for k in range(spans):
        fr.add_beam(f"N{k}", f"N{k + 1}", E, A, I, name=f"M{k}")
        fr.add_distributed_load(f"M{k}", wy=-25.0 * A - 10.0, case="D")
    fr.add_support("N0", fix=("ux",))
    for k in range(len(xs)):
        fr.add_contact(f"N{k}", normal=(0.0, 1.0), stiffness=K)
    for k, f in loads.items():
        fr.add_load(f"N{k}", fy=f, case="D")
    return fr


def pynite_beam(spans):
    from Pynite import FEModel3D

    xs, loads = beam_model(spans)
    m = FEModel3D()
    m.add_material("c", E, E / 2.4, 0.2, 0.0)
    m.add_section("s", A, I, I, 2 * I)
    for k, x in enumerate(xs):
        m.add_node(f"N{k}", float(x), 0.0, 0.0)
        m.def_support(f"N{k}", support_DX=k == 0, support_DZ=True, support_RX=True,
                      support_RY=True)
        m.def_support_spring(f"N{k}", "DY", K, "-")
    for k in range(spans):
        m.add_member(f"M{k}", f"N{k}", f"N{k + 1}", "c", "s")
        m.add_member_dist_load(f"M{k}", "FY", -25.0 * A - 10.0, -25.0 * A - 10.0, case="D")
    for k, f in loads.items():
        m.add_node_load(f"N{k}", "FY", f, case="D")
    m.add_load_combo("C", {"D": 1.0})
    return m, [f"N{k}" for k in range(len(xs))]


def ours_storeys(n):
    fr = Frame()
    bays, h, w = 3, 3.5, 6.0
    for s in range(n + 1):
        for c in range(bays + 1):
            fr.add_node(f"C{c}_{s}", c * w, s * h)
    for s in range(n):
        for c in range(bays + 1):
            fr.add_beam(f"C{c}_{s}", f"C{c}_{s + 1}", E, 0.25, 0.0052)
        for c in range(bays):
            b = fr.add_beam(f"C{c}_{s + 1}", f"C{c + 1}_{s + 1}", E, 0.18, 0.0054)
            fr.add_distributed_load(b, wy=-30.0, case="D")
        fr.add_load(f"C0_{s + 1}", fx=8.0 + 0.5 * s, case="W")
    fr.add_support("C0_0", fix=("ux",))
    for c in range(bays + 1):
        fr.add_contact(f"C{c}_0", normal=(0.0, 1.0), stiffness=2e5)
        fr.add_spring(f"C{c}_0", ux=1e6, rz=5e4)
    return fr


def best_of(fn, repeat):
    """Best of ``repeat`` timed runs after one untimed warm-up (imports,
    numba's cached kernels: a cost paid once per process, not per model)."""
    fn()
    times, out = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--spans", default="50,200,1000")
    ap.add_argument("--storeys", type=int, default=20)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    try:
        import Pynite  # noqa: F401
        have_pynite = True
    except ImportError:
        have_pynite = False
        print("PyNite not installed (pip install PyNiteFEA): qpcontact times only")
    print(f"{'model':>18} {'qpcontact s':>12} {'PyNite s':>10} {'PyNite/qpc':>11} "
          f"{'max |ΔR| / max R':>17}  route / checks")
    for spans in [int(s) for s in args.spans.split(",") if s]:
        t_q, res = best_of(lambda: ours_beam(spans).solve(combination={"D": 1.0}), args.repeat)
        line = f"{f'beam {spans} spans':>18} {t_q:12.3f}"
        if have_pynite:
            def run_pn():
                m, names = pynite_beam(spans)
                m.analyze(check_statics=False)
                return m, names
            t_p, (m, names) = best_of(run_pn, 1 if spans > 200 else args.repeat)
            ours = np.array([res.supports[nm].normal for nm in names])
            ref = np.array([m.nodes[nm].RxnFY["C"] for nm in names])
            diff = np.abs(ours - ref).max() / np.abs(ref).max()
            line += f" {t_p:10.3f} {t_p / t_q:11.2f} {diff:17.1e}"
        else:
            line += " " * 40
        lifted = sum(s.state == "separated" for s in res.supports.values())
        print(line + f"  {res.route}, ok={res.ok}, {lifted} lift off")
    if args.storeys:
        fr = ours_storeys(args.storeys)
        t_q, res = best_of(lambda: fr.solve(combination={"D": 1.0, "W": 1.5}), args.repeat)
        lifted = sum(s.state == "separated" for s in res.supports.values())
        print(f"{f'{args.storeys}-storey frame':>18} {t_q:12.3f} {'':>10} {'':>11} {'':>17}  "
              f"{res.route}, ok={res.ok}, {lifted} lift off")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
