"""docs/plates.md's raft cost rows: CPU time of ``Raft.solve()`` against one
LDLᵀ of the answer's own linear system (the floor).

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/rafts_cost.py KIND CELLS [REPS]

prints one JSON row: the least CPU time (``time.process_time``) of REPS
solves (default 2), each on a fresh raft whose build is not timed, after a
warm-up (imports, numba's cached kernels); the Newton steps; the lifted
nodes; whether certified; and two floors, each the least of three: qdldl's
LDLᵀ, ordering included, of the stiffness on the dofs no bilateral support
holds plus the pressing soil nodes' springs, less the held floor nodes' w
(``floor``, ``ratio``: the rows published before 2026-12-06's
nested-dissection order), and the same system factorised as the solve's
own steps do (``floor_own``, ``ratio_own``: SuperLU in the mesh's
nested-dissection order from newton.SUPERNODAL_DOFS on, the order made
once per raft and not timed; qdldl under its AMD below — as
benchmarks/scale.py's floor).  The
rafts are defined here (not through examples.windward_raft's ``floor``) so
that the same script times an older commit.  KIND:

* ``windward``: examples.windward_raft, on soil (benchmarks/scale.py's);
* ``floor``: the same raft on a rigid floor instead of soil;
* ``floor_opening``: that, with a central opening 0.16 of the side square
  (not looked at while the floor's border and start were chosen);
* ``floor_corner``: a 0.4 m slab on a rigid floor, 0.5 m cells, side x 0.75
  side, a corner pulled up and a column at (0.6, 0.4) of the sides (not
  looked at either);
* ``centre``: a 0.25 m raft on soil k = 2e4 under its self-weight and a
  2 MN point load at its centre: a lift-off ring.
"""

from __future__ import annotations

import json
import re
import sys
import time

import numpy as np


def _floor_raft(cells, openings=()):
    from formulations.plates import Raft

    side = 0.5 * cells
    raft = Raft(side, side, thickness=0.5, E=30e6, nu=0.2, cells=(cells, cells),
                openings=openings)
    raft.add_rigid_floor()
    raft.add_self_weight(25.0)
    raft.add_area_load(5.0)
    grid = [side * (0.5 + k) / 4 for k in range(4)]
    for x in grid:
        for y in grid:
            raft.add_point_load(x, y, side ** 2 * (6.0 - (9.0 if x == grid[0] else 0.0)))
    return raft


def make(kind, cells):
    from formulations.plates import Raft
    from formulations.plates.examples import windward_raft

    side = 0.5 * cells
    if kind == "windward":
        return windward_raft(cells)
    if kind == "floor":
        return _floor_raft(cells)
    if kind == "floor_opening":
        return _floor_raft(cells, [(0.42 * side, 0.42 * side, 0.58 * side, 0.58 * side)])
    if kind == "floor_corner":
        raft = Raft(side, 0.75 * side, thickness=0.4, E=30e6, nu=0.2,
                    cells=(cells, int(0.75 * cells)))
        raft.add_rigid_floor()
        raft.add_self_weight(25.0)
        raft.add_point_load(0.0, 0.0, -4.0 * side)
        raft.add_point_load(0.6 * side, 0.4 * side, 30.0 * side)
        return raft
    if kind == "centre":
        raft = Raft(side, side, thickness=0.25, E=30e6, nu=0.2, cells=(cells, cells))
        raft.add_soil(2e4)
        raft.add_self_weight(25.0)
        raft.add_point_load(side / 2, side / 2, 2e4)
        return raft
    raise SystemExit(f"unknown raft {kind!r}")


def floor_seconds(raft, result) -> float:
    """CPU seconds of one LDLᵀ of the answer's own system, the least of three."""
    import qdldl
    import scipy.sparse as sp

    b = raft.build()
    qp = b["qp"]
    n = qp.K.shape[0]
    springs = np.zeros(n)
    pressing = result.contact & np.isfinite(b["ks"])
    springs[3 * np.flatnonzero(pressing)] = b["ks"][pressing]
    keep = np.ones(n, bool)
    keep[qp.fixed] = False
    keep[3 * np.flatnonzero(result.contact & ~np.isfinite(b["ks"]))] = False
    idx = np.flatnonzero(keep)
    A = sp.triu((qp.K + sp.diags(springs)).tocsc()[idx][:, idx], format="csc")
    best = np.inf
    for _ in range(3):
        t = time.process_time()
        qdldl.Solver(A, upper=True)
        best = min(best, time.process_time() - t)
    return best


def own_floor_seconds(raft, result) -> float:
    """CPU seconds of the solve's own factorisation of the answer's system
    (``SupportSystem.factor``, its kept factors freed first), least of three."""
    qp = raft.build()["qp"]
    system = qp.newton
    for kept in ("solver", "factored", "analysis", "floor_block"):
        setattr(system, kept, None)
    best = np.inf
    for _ in range(3):
        t = time.process_time()
        system.factor(result.contact[qp.soil], result.contact[qp.floor])
        best = min(best, time.process_time() - t)
    return best


def main(argv):
    kind, cells = argv[0], int(argv[1])
    reps = int(argv[2]) if len(argv) > 2 else 2
    make("floor", 40).solve()            # warm-up: imports, numba's cached kernels
    make("centre", 40).solve()
    times = []
    for _ in range(reps):
        raft = make(kind, cells)
        raft.build()
        t = time.process_time()
        r = raft.solve()
        times.append(time.process_time() - t)
    floor = floor_seconds(raft, r)
    own = own_floor_seconds(raft, r)
    steps = re.search(r"(\d+) (?:LDLᵀ|steps)", r.message)
    print(json.dumps(dict(kind=kind, cells=cells, dofs=3 * r.mesh.nodes.shape[0], ok=bool(r.ok),
                          lifted=int(r.lifted.sum()), steps=int(steps.group(1)) if steps else None,
                          cpu=round(min(times), 4), floor=round(floor, 4),
                          ratio=round(min(times) / floor, 2), floor_own=round(own, 4),
                          ratio_own=round(min(times) / own, 2), method=r.method)))


if __name__ == "__main__":
    main(sys.argv[1:])
