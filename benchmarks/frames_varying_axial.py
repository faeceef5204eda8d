"""Second order with N varying along the members: the steel sway portal
under its own weight (HEB 300 columns 6 m high fixed at A and D, an IPE
400 beam 12 m across under 30 kN/m, 20 kN sideways at B, self-weight at
78.5 kN/m³), uncut and with each column cut into k members.

Table 1: per k, whether the answer is ok at "low" and "high", its base
moment M_A and sway of B at "high", the solve's and α_cr's wall and CPU
time.  The reference (last row): the columns cut into 32 and 64
constant-N elements with their weight lumped at the cuts (no member load
with an axial part: the stability functions' route) extrapolated as 1/k²
(Richardson); the uncut answer must be ok and within 1e-9 of it.

Table 2 (``--kernels``): the two parts of α_cr's bisection step that
grew with k, on the portal's reduced tangent at 42 × its loads — the
projection Zᵀ(K + S)Z with Z = I (now skipped where no link is rigid) and
the count of negative eigenvalues by eigvalsh against an LDLᵀ's inertia.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/frames_varying_axial.py [--k 1 16 32 64] [--kernels]
    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/frames_varying_axial.py --space 1 3 10
    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/frames_varying_axial.py --tower 10 [--shear]

Table 3 (``--space S …``): a space building under its own weight, 3 × 3
columns (HEB 300) 6 m apart and 4 m storeys, S storeys, IPE 400 beams
both ways under 20 kN/m, 10 kN sideways (x) at each floor's corner, all
members' self-weight: ok at "low" and "high", the top corner's sway, the
solve's and α_cr's wall and CPU time.  Its columns carry their weight as
member loads, so both bending planes of each take N(x)
(formulations/frames/space/space_varying.py); on the mean N the answer
was refused ("… have axial parts … add nodes").

Table 4 (``--tower S …``): a plane tower, 3 bays of 6 m and S storeys of
3.5 m, HEB 300 columns, IPE 400 beams under 30 kN/m, 10 kN sideways a
floor, every member's self-weight: the same columns.  ``--shear``: the
columns (plane and space) with their shear area, 47.4 cm² (G A_s = 3.8e8
N), so Engesser's beam-column under N(x)
(formulations/frames/mechanics/varying_pieces.py).

Pin BLAS to one thread on a shared machine: unpinned, OpenBLAS's threads
made one eigvalsh of the 384-dof tangent 1.5 s (5 ms pinned) on two busy
cores.  Exits non-zero when the uncut answer is not ok at "high" or off
the reference by more than 1e-9.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import scipy.linalg as la  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.frames import Frame  # noqa: E402
from formulations.frames.mechanics import tangent_stiffness  # noqa: E402
from formulations.frames.mechanics.second_order_analysis import critical_load_factor  # noqa: E402

E, GAMMA, H, SPAN = 210e9, 78.5e3, 6.0, 12.0
A_C, I_C, A_B, I_B = 149e-4, 25170e-8, 84.5e-4, 23130e-8
AS_C = 47.4e-4          # HEB 300's shear area across its web


def portal(k=1, lumped=False):
    """The portal, its columns cut into k members (their weight lumped at
    the cuts where ``lumped``), all loads in case "D"."""
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("D", SPAN, 0.0)
    fr.add_node("B", 0.0, H)
    fr.add_node("C", SPAN, H)
    for side, x, base, top in (("L", 0.0, "A", "B"), ("R", SPAN, "D", "C")):
        nodes = [base] + [f"{side}{j}" for j in range(1, k)] + [top]
        for j in range(1, k):
            fr.add_node(nodes[j], x, H * j / k)
        for j in range(k):
            fr.add_member(nodes[j], nodes[j + 1], E, A_C, I_C, name=f"c{side}{j + 1}")
            if lumped:
                for node in nodes[j:j + 2]:
                    fr.add_load(node, fy=-0.5 * GAMMA * A_C * H / k, case="D")
    fr.add_member("B", "C", E, A_B, I_B, name="b")
    if not lumped:
        fr.add_self_weight("D", unit_weight=GAMMA)
        fr.add_distributed_load("b", wy=-30e3, case="D")
    else:
        fr.add_distributed_load("b", wy=-30e3 - GAMMA * A_B, case="D")
    fr.add_support("A")
    fr.add_support("D")
    fr.add_load("B", fx=20e3, case="D")
    return fr


def building(storeys, shear=False):
    """Table 3's space building (module docstring), all loads in case "D";
    its columns shear-flexible where ``shear``."""
    from formulations.frames.space.space_frame import SpaceFrame

    sf = SpaceFrame()
    grid = [(6.0 * a, 6.0 * c) for a in range(3) for c in range(3)]
    for level in range(storeys + 1):
        for n, (x, y) in enumerate(grid):
            sf.add_node(f"n{level}_{n}", x, y, 4.0 * level)
    for level in range(1, storeys + 1):
        for n in range(len(grid)):
            sf.add_member(f"n{level - 1}_{n}", f"n{level}_{n}", E, A_C, I_C, 8563e-8,
                          G=81e9, J=185e-8, name=f"c{level}_{n}",
                          **({"shear_area": (AS_C, AS_C)} if shear else {}))
        for n, (x, y) in enumerate(grid):
            for m, (x2, y2) in enumerate(grid):
                if m > n and abs(x2 - x) + abs(y2 - y) == 6.0:
                    name = f"b{level}_{n}_{m}"
                    sf.add_member(f"n{level}_{n}", f"n{level}_{m}", E, A_B, I_B, 1318e-8,
                                  G=81e9, J=51e-8, name=name)
                    sf.add_distributed_load(name, wz=-20e3, case="D")
        sf.add_load(f"n{level}_0", fx=10e3, case="D")
    sf.add_self_weight("D", unit_weight=GAMMA)
    for n in range(len(grid)):
        sf.add_support(f"n0_{n}")
    return sf


def tower(storeys, shear=False):
    """Table 4's plane tower (module docstring), all loads in case "D"."""
    fr = Frame()
    for s in range(storeys + 1):
        for b in range(4):
            fr.add_node(f"n{s}_{b}", 6.0 * b, 3.5 * s)
    for s in range(storeys):
        for b in range(4):
            fr.add_member(f"n{s}_{b}", f"n{s + 1}_{b}", E, A_C, I_C, name=f"c{s}_{b}",
                          **({"G": 81e9, "shear_area": AS_C} if shear else {}))
        for b in range(3):
            fr.add_member(f"n{s + 1}_{b}", f"n{s + 1}_{b + 1}", E, A_B, I_B, name=f"b{s}_{b}")
            fr.add_distributed_load(f"b{s}_{b}", wy=-30e3, case="D")
        fr.add_load(f"n{s + 1}_0", fx=10e3, case="D")
    for b in range(4):
        fr.add_support(f"n0_{b}")
    fr.add_self_weight("D", unit_weight=GAMMA)
    return fr


def building_rows(storeys, shear=False, make=building, name="space building (3 × 3 columns"):
    print(f"\n{name}, S storeys, self-weight{', shear-flexible columns' if shear else ''}):"
          " wall / CPU s")
    print(f"{'S':>3} {'members':>7} {'ok low':>6} {'ok high':>7} {'ux top [m]':>18}"
          f" {'solve s':>8} {'cpu':>6} {'α_cr':>14} {'α s':>6} {'cpu':>6}")
    for S in storeys:
        sf = make(S, shear)
        low = solve(sf, "low")
        res, w, c = timed(lambda: solve(sf))
        alpha, wa, ca = timed(lambda: critical_load_factor(sf, res))
        print(f"{S:>3} {len(sf.members):>7} {str(low.ok):>6} {str(res.ok):>7}"
              f" {res.displacements[f'n{S}_0'][0]:>18.12e} {w:>8.2f} {c:>6.2f}"
              f" {alpha['alpha']:>14.10f} {wa:>6.2f} {ca:>6.2f}")


def timed(f):
    w, c = time.perf_counter(), time.process_time()
    out = f()
    return out, time.perf_counter() - w, time.process_time() - c


def solve(fr, accuracy="high"):
    return fr.solve(combination={"D": 1.0}, second_order=True, accuracy=accuracy,
                    raise_on_failure=False)


def reference():
    """(M_A, ux_B): the lumped cut portal at 32 and 64, extrapolated."""
    vals = []
    for k in (32, 64):
        res = solve(portal(k, lumped=True))
        assert res.ok, res.message
        vals.append(np.array([res.diagram("cL1", 2)[3][0], res.displacements["B"][0]]))
    return (4 * vals[1] - vals[0]) / 3


def kernels(ks):
    print("\nα_cr's step on the portal's reduced tangent at 42 × its loads (best of 5), ms")
    print(f"{'k':>4} {'dofs':>5} {'Z=I proj':>9} {'no proj':>8} {'eigvalsh':>9} {'LDL':>7}  counts")

    def best(f):
        return min(timed(f)[1] for _ in range(5)) * 1e3

    for k in ks:
        fr = portal(k)
        b = fr.build()
        res = solve(fr)
        N = np.array([res.second_order["axial"][m] for m in fr.members])
        K = fr.stiffness(axial=42.0 * N, along={"D": 42.0})
        n = b["free"].size
        S = np.zeros((n, n))
        Kr = tangent_stiffness.reduced_tangent(K, b, (None, S))

        def by_eigenvalues():
            d = 1.0 / np.sqrt(np.abs(np.diag(Kr)))
            lam = la.eigvalsh(Kr * d[:, None] * d[None, :])
            return int(np.sum(lam < -16 * n * np.finfo(float).eps * np.abs(lam).max()))

        print(f"{k:>4} {n:>5} {best(lambda: tangent_stiffness.reduced_tangent(K, b, (np.eye(n), S))):>9.2f}"
              f" {best(lambda: tangent_stiffness.reduced_tangent(K, b, (None, S))):>8.2f}"
              f" {best(by_eigenvalues):>9.2f} {best(lambda: tangent_stiffness.negative_eigenvalues(Kr)):>7.2f}"
              f"  {by_eigenvalues()} {tangent_stiffness.negative_eigenvalues(Kr)}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--k", type=int, nargs="+", default=[1, 16, 32, 64])
    ap.add_argument("--kernels", action="store_true")
    ap.add_argument("--space", type=int, nargs="+", default=[], metavar="S",
                    help="Table 3 alone, for these storey counts")
    ap.add_argument("--tower", type=int, nargs="+", default=[], metavar="S",
                    help="Table 4 alone, for these storey counts")
    ap.add_argument("--shear", action="store_true", help="shear-flexible columns (3, 4)")
    args = ap.parse_args(argv)
    if args.space or args.tower:
        warnings.simplefilter("ignore")
        print(f"load average {' '.join(open('/proc/loadavg').read().split()[:3])}")
        if args.space:
            building_rows(args.space, args.shear)
        if args.tower:
            building_rows(args.tower, args.shear, tower, "plane tower (3 bays")
        print(f"load average {' '.join(open('/proc/loadavg').read().split()[:3])}")
        return 0
    warnings.simplefilter("ignore")
    print(f"load average {' '.join(open('/proc/loadavg').read().split()[:3])}")
    print(f"{'k':>4} {'ok low':>6} {'ok high':>7} {'M_A [N m]':>18} {'ux_B [m]':>18}"
          f" {'solve s':>8} {'cpu':>6} {'α_cr':>12} {'α s':>6} {'cpu':>6}")
    rows = {}
    for k in args.k:
        low = solve(portal(k), "low")
        fr = portal(k)
        res, w, c = timed(lambda: solve(fr))
        alpha, wa, ca = timed(lambda: critical_load_factor(fr, res))
        rows[k] = (res.ok, res.diagram("cL1", 2)[3][0], res.displacements["B"][0])
        print(f"{k:>4} {str(low.ok):>6} {str(res.ok):>7} {rows[k][1]:>18.10f} {rows[k][2]:>18.12e}"
              f" {w:>8.2f} {c:>6.2f} {alpha['alpha']:>12.9f} {wa:>6.2f} {ca:>6.2f}")
    ref = reference()
    print(f"{'ref':>4} {'':>6} {'':>7} {ref[0]:>18.10f} {ref[1]:>18.12e}"
          "   (32 and 64 constant-N pieces, weight lumped, Richardson)")
    failed = 0
    if 1 in rows:
        off = abs(rows[1][1] / ref[0] - 1), abs(rows[1][2] / ref[1] - 1)
        print(f"uncut against the reference: M_A {off[0]:.1e}, ux_B {off[1]:.1e}")
        failed = int(not rows[1][0] or max(off) > 1e-9)
    if args.kernels:
        kernels(args.k)
    print(f"load average {' '.join(open('/proc/loadavg').read().split()[:3])}")
    return failed


if __name__ == "__main__":
    sys.exit(main())
