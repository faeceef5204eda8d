"""Scenes for the multibody model (Ivanov & Shimanovsky's Cardan chains, a closed four-bar
linkage) and the multibody part of ``qpcontact demo``: a Cardan chain's
velocities from momenta by the O(N) solvers against a dense solve of G."""

from __future__ import annotations

import time

import numpy as np
import scipy.linalg

from . import algorithms as alg
from .constraints import PointLoop, assemble_loop_state
from .model import Cardan, Data, Model, Revolute

#: four-bar link lengths [m]: crank, coupler, rocker, ground
FOUR_BAR = (0.2, 0.5, 0.4, 0.45)


def cardan_chain(N: int, link: float = 0.1) -> Model:
    """N bodies (1 kg, 0.1 m links) hanging on 2-DOF Cardan joints (Ivanov & Shimanovsky's test chains)."""
    m = Model(gravity=(0.0, 0.0, -9.81))
    for i in range(1, N + 1):
        m.add_body(f"b{i}", i - 1, Cardan("x", "y"), placement=(0, 0, -link if i > 1 else 0.0),
                   mass=1.0, com=(0, 0, -link / 2), inertia=(1e-3, 1e-3, 1e-4))
    return m


def four_bar():
    """Crank (1 kg), coupler (2 kg), rocker (1.5 kg) as uniform rods on
    revolute joints in the xy plane, the rocker's tip pinned to the ground at
    (0.45 m, 0); gravity -y.  Returns (model, loops, q0, v0) with the crank at
    1.2 rad turning at 3 rad/s, closed consistently (positions and velocities)."""
    crank, coupler, rocker, ground = FOUR_BAR
    m = Model(gravity=(0.0, -9.81, 0.0))

    def rod(L, mass):
        return dict(mass=mass, com=(L / 2, 0, 0),
                    inertia=np.diag([1e-6, mass * L ** 2 / 12, mass * L ** 2 / 12]))

    m.add_body("crank", 0, Revolute("z"), **rod(crank, 1.0))
    m.add_body("coupler", 1, Revolute("z"), placement=(crank, 0, 0), **rod(coupler, 2.0))
    m.add_body("rocker", 2, Revolute("z"), placement=(coupler, 0, 0), **rod(rocker, 1.5))
    loops = [PointLoop("rocker", (rocker, 0, 0), 0, (ground, 0, 0), axes=(0, 1))]
    q, v = assemble_loop_state(m, [1.2, -1.0, -1.5], [3.0, 0.0, 0.0], loops, fixed=[0])
    return m, loops, q, v


def _best(fn, reps=5):
    fn()
    best = np.inf
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def demo(console) -> int:
    """Returns the number of chains where an O(N) solve disagrees with the dense one."""
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    table = Table(title="Multibody (Ivanov & Shimanovsky 2017): velocities from momenta on Cardan chains",
                  box=box.SIMPLE_HEAD, title_justify="left", pad_edge=False)
    for col in ("bodies N", "ldlt [ms]", "sweep [ms]", "CRBA + dense Cholesky [ms]",
                "max |Δν| ldlt", "max |Δν| sweep"):
        table.add_column(escape(col), justify="right", no_wrap=True, min_width=len(col))
    rng = np.random.default_rng(0)
    wrong = 0
    for N in (10, 100, 400):
        m = cardan_chain(N)
        d = Data(m)
        q, v = 0.3 * rng.standard_normal(m.nq), rng.standard_normal(m.nv)
        p = alg.momenta(m, d, q, v)

        def dense():
            G = alg.mass_matrix(m, d, q)
            return scipy.linalg.cho_solve(scipy.linalg.cho_factor(G), p)

        ref = dense()
        cond = np.linalg.cond(d.G)          # the G that dense() just formed
        row, errs = [str(N)], []
        for method in ("ldlt", "sweep"):
            row.append(f"{1e3 * _best(lambda: alg.velocities_from_momenta(m, d, q, p, method=method)):.3f}")
            errs.append(np.abs(alg.velocities_from_momenta(m, d, q, p, method=method) - ref).max())
        row.append(f"{1e3 * _best(dense):.3f}")
        row += [f"{e:.1e}" for e in errs]
        wrong += int(max(errs) > 1e-13 * cond * np.abs(ref).max())
        table.add_row(*row)
    console.print(table)
    console.print("ldlt and sweep: Ivanov & Shimanovsky's O(N) solvers of G ν = p; CRBA + dense Cholesky: G formed "
                  "and factored, O(N³).  Times: the best of repeated calls after a first, untimed "
                  "one.  max |Δν|: the largest difference from the dense solve's joint rates [rad/s]; "
                  "the check allows 1e-13 × cond(G) × max |ν|.",
                  markup=False, highlight=False)
    return wrong
