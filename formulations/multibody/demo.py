"""The multibody part of ``qpcontact demo``: a Cardan chain's velocities from
momenta by P4's O(N) solvers against a dense solve of G, with timings."""

from __future__ import annotations

import time

import numpy as np
import scipy.linalg

from . import algorithms as alg
from .model import Cardan, Data, Model


def cardan_chain(N: int, link: float = 0.1) -> Model:
    """N bodies (1 kg, 0.1 m links) hanging on 2-DOF Cardan joints (P4's test chains)."""
    m = Model(gravity=(0.0, 0.0, -9.81))
    for i in range(1, N + 1):
        m.add_body(f"b{i}", i - 1, Cardan("x", "y"), placement=(0, 0, -link if i > 1 else 0.0),
                   mass=1.0, com=(0, 0, -link / 2), inertia=(1e-3, 1e-3, 1e-4))
    return m


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
    from rich.table import Table

    table = Table(title="Multibody (P4): velocities from momenta on Cardan chains, "
                        "O(N) solvers against a dense Cholesky of G")
    for col in ("bodies N", "ldlt [ms]", "sweep [ms]", "CRBA + dense Cholesky [ms]",
                "max |Δν| ldlt", "max |Δν| sweep"):
        table.add_column(col, justify="right")
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
        cond = np.linalg.cond(alg.mass_matrix(m, d, q))
        row, errs = [str(N)], []
        for method in ("ldlt", "sweep"):
            row.append(f"{1e3 * _best(lambda: alg.velocities_from_momenta(m, d, q, p, method=method)):.3f}")
            errs.append(np.abs(alg.velocities_from_momenta(m, d, q, p, method=method) - ref).max())
        row.append(f"{1e3 * _best(dense):.3f}")
        row += [f"{e:.1e}" for e in errs]
        wrong += int(max(errs) > 1e-13 * cond * np.abs(ref).max())
        table.add_row(*row)
    console.print(table)
    return wrong
