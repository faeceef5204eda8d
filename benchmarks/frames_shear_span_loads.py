"""The cost of shear-flexible members carrying span loads in a second-order
answer and its α_cr, beside the same frames without shear deformation.

Cases (D 1.35 + W 1.5, accuracy "high"):

- ``tower20``: a plane tower, 3 bays of 6 m, 20 storeys of 3.5 m, HEB 300
  columns, IPE 400 beams under 30 kN/m, 10 kN sideways a floor
  (Euler–Bernoulli: the reference cost);
- ``shearbeams10``, ``shearbeams20``: the tower with shear-flexible beams
  (A_s 40 cm², G 81 GPa) under their 30 kN/m, 10 and 20 storeys;
- ``shearall10``: 10 storeys, columns shear-flexible too (A_s 47.4 cm²);
- ``portal``: one bay, Euler–Bernoulli;
- ``space_rack``: a 6-level, 4-bay space pipe rack, Euler–Bernoulli beams
  under 20 kN/m;
- ``space_shear``: a 4-level, 3-bay space frame whose columns (shear areas
  47/12 cm²), ties (shear in one plane) and beams (40/30 cm², rigid zones)
  are shear-flexible, with point forces across the columns and point forces
  and couples on the beams beside their distributed loads; ``space_twin``:
  the same without shear deformation.

A constant-N shear-flexible member's loads are Engesser's beam-column in
closed form (formulations/frames/mechanics/beam_column.py); before, each was
a chain of Taylor series (varying_axial.py), rebuilt per tangent.

Prints one line per case: ok, the solve's and α_cr's CPU (process_time) and
wall seconds, each the least of ``--repeat`` runs after one warm-up, α_cr
and the last node's ux to 12 digits, and the load average before and after.

    .venv/bin/python benchmarks/frames_shear_span_loads.py shearbeams20 tower20

Pin BLAS to one thread (as here by default) on a shared machine.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.frames import Frame  # noqa: E402
from formulations.frames.mechanics.critical_load import critical_load_factor  # noqa: E402
from formulations.frames.space.space_frame import SpaceFrame  # noqa: E402

E, G = 210e9, 81e9
COMBINATION = {"D": 1.35, "W": 1.5}


def tower(storeys, bays=3, shear_beams=False, shear_columns=False):
    fr = Frame()
    for s in range(storeys + 1):
        for c in range(bays + 1):
            fr.add_node(f"n{s}_{c}", 6.0 * c, 3.5 * s)
    for c in range(bays + 1):
        fr.add_support(f"n0_{c}")
    for s in range(storeys):
        for c in range(bays + 1):
            kw = dict(G=G, shear_area=4.74e-3) if shear_columns else {}
            fr.add_member(f"n{s}_{c}", f"n{s + 1}_{c}", E, 1.49e-2, 2.517e-4, name=f"c{s}_{c}",
                          **kw)
        for c in range(bays):
            kw = dict(G=G, shear_area=4.0e-3) if shear_beams else {}
            fr.add_member(f"n{s + 1}_{c}", f"n{s + 1}_{c + 1}", E, 8.45e-3, 2.313e-4,
                          name=f"b{s}_{c}", **kw)
            fr.add_distributed_load(f"b{s}_{c}", wy=-30e3, case="D")
        fr.add_load(f"n{s + 1}_0", fx=10e3, case="W")
    return fr


def portal():
    fr = Frame()
    for n, x, y in (("A", 0, 0), ("B", 0, 4), ("C", 6, 4), ("D", 6, 0)):
        fr.add_node(n, x, y)
    fr.add_member("A", "B", E, 1.49e-2, 2.517e-4)
    fr.add_member("B", "C", E, 8.45e-3, 2.313e-4, name="beam")
    fr.add_member("D", "C", E, 1.49e-2, 2.517e-4)
    fr.add_support("A")
    fr.add_support("D")
    fr.add_distributed_load("beam", wy=-30e3, case="D")
    fr.add_load("B", fx=20e3, case="W")
    return fr


def space_grid(levels, bays):
    """Two rows of bays + 1 columns' nodes, levels + 1 high, fixed at the base."""
    fr = SpaceFrame()
    for s in range(levels + 1):
        for c in range(bays + 1):
            for r in range(2):
                fr.add_node(f"n{s}_{c}_{r}", 6.0 * c, 4.0 * r, 3.5 * s)
    for c in range(bays + 1):
        for r in range(2):
            fr.add_support(f"n0_{c}_{r}")
    return fr


def rack(levels=6, bays=4):
    fr = space_grid(levels, bays)
    for s in range(levels):
        for c in range(bays + 1):
            for r in range(2):
                fr.add_member(f"n{s}_{c}_{r}", f"n{s + 1}_{c}_{r}", E, 1.49e-2, 2.517e-4,
                              8.56e-5, G=G, J=1.85e-6, name=f"c{s}_{c}_{r}")
            fr.add_member(f"n{s + 1}_{c}_0", f"n{s + 1}_{c}_1", E, 8.45e-3, 2.313e-4, 1.3e-5,
                          G=G, J=5e-7, name=f"t{s}_{c}")
            fr.add_load(f"n{s + 1}_{c}_0", fy=5e3, case="W")
        for c in range(bays):
            for r in range(2):
                fr.add_member(f"n{s + 1}_{c}_{r}", f"n{s + 1}_{c + 1}_{r}", E, 8.45e-3,
                              2.313e-4, 1.3e-5, G=G, J=5e-7, name=f"b{s}_{c}_{r}")
                fr.add_distributed_load(f"b{s}_{c}_{r}", wz=-20e3, case="D")
    return fr


def space_shear(levels=4, bays=3, shear=True):
    fr = space_grid(levels, bays)
    for s in range(levels):
        for c in range(bays + 1):
            for r in range(2):
                name = f"c{s}_{c}_{r}"
                fr.add_member(f"n{s}_{c}_{r}", f"n{s + 1}_{c}_{r}", E, 1.49e-2, 2.517e-4,
                              8.56e-5, G=G, J=1.85e-6, name=name,
                              shear_area=(4.7e-3, 1.2e-3) if shear else None)
                fr.add_point_load(name, 1.2, fy=3e3, fx=-2e3, case="W")
            fr.add_member(f"n{s + 1}_{c}_0", f"n{s + 1}_{c}_1", E, 8.45e-3, 2.313e-4, 1.3e-5,
                          G=G, J=5e-7, name=f"t{s}_{c}",
                          shear_area=(4e-3, None) if shear else None)
            fr.add_distributed_load(f"t{s}_{c}", wz=-8e3, case="D")
            fr.add_load(f"n{s + 1}_{c}_0", fy=5e3, case="W")
        for c in range(bays):
            for r in range(2):
                name = f"b{s}_{c}_{r}"
                fr.add_member(f"n{s + 1}_{c}_{r}", f"n{s + 1}_{c + 1}_{r}", E, 8.45e-3,
                              2.313e-4, 1.3e-5, G=G, J=5e-7, name=name,
                              shear_area=(4e-3, 3e-3) if shear else None, offset_i=0.1)
                fr.add_distributed_load(name, wz=-20e3, case="D")
                fr.add_point_load(name, 2.0, fz=-10e3, my=2e3, case="D")
    return fr


CASES = {"portal": portal, "tower20": lambda: tower(20), "space_rack": rack,
         "shearbeams10": lambda: tower(10, shear_beams=True),
         "shearbeams20": lambda: tower(20, shear_beams=True),
         "shearall10": lambda: tower(10, shear_beams=True, shear_columns=True),
         "space_shear": space_shear, "space_twin": lambda: space_shear(shear=False)}


def timed(f):
    w, c = time.perf_counter(), time.process_time()
    out = f()
    return out, time.process_time() - c, time.perf_counter() - w


def run(name, repeat):
    fr = CASES[name]()
    solve_t, alpha_t = [], []
    for k in range(repeat + 1):          # the first a warm-up (imports, compiled kernels)
        res, c, w = timed(lambda: fr.solve(combination=COMBINATION, second_order=True,
                                           accuracy="high", raise_on_failure=False))
        alpha, ca, wa = timed(lambda: critical_load_factor(fr, res)["alpha"])
        if k:
            solve_t.append((c, w))
            alpha_t.append((ca, wa))
    ux = list(res.displacements.values())[-1][0]
    (sc, sw), (ac, aw) = min(solve_t), min(alpha_t)
    print(f"{name:13s} ok={res.ok} solve cpu {sc:.3f} wall {sw:.3f}  alpha cpu {ac:.3f} "
          f"wall {aw:.3f}  alpha_cr {alpha:.10f}  ux {ux:.12e}", flush=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cases", nargs="+", choices=sorted(CASES))
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    print(f"load average {' '.join(open('/proc/loadavg').read().split()[:3])}")
    for name in args.cases:
        run(name, args.repeat)
    print(f"load average {' '.join(open('/proc/loadavg').read().split()[:3])}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
