"""A method's time limit leaves numba's compiling out, as grace's docstring
says and core.deadline's clocks do: these routes kept raw time.perf_counter
deadlines of their own, so a kernel compiled inside their limit ate it.
Compiling is emulated where each route first loads a kernel or measures its
iterate (a sleep longer than the limit, booked as core.compiled books
numba's compile events), and the route must still answer; on the raw clock
each stopped at its limit."""

from __future__ import annotations

import time

import numpy as np
import pytest

import qpcontact
from qpcontact import LCP
from qpcontact.cases.planted_friction import build_friction
from qpcontact.core.deadline import exclude_one_time

COMPILING_S, LIMIT_S = 0.8, 0.5


def compiling_once(fn):
    """``fn``, whose first call first spends COMPILING_S seconds compiling."""
    done = []

    def first_compiles(*args, **kwargs):
        if not done:
            done.append(True)
            time.sleep(COMPILING_S)
            exclude_one_time(COMPILING_S, 0.0)
        return fn(*args, **kwargs)
    return first_compiles


def test_lemkes_pivots_leave_compiling_out(monkeypatch):
    import qpcontact.solvers.pivoting.lemke_tableau as tableau

    rng = np.random.default_rng(3)
    A = rng.standard_normal((8, 8))
    problem = LCP(A @ A.T + np.eye(8), rng.standard_normal(8))
    assert qpcontact.solve(problem, method="lemke").ok                  # kernels loaded
    monkeypatch.setattr(tableau, "pivot_kernels", compiling_once(tableau.pivot_kernels))
    sol = qpcontact.solve(problem, method="lemke", time_limit=LIMIT_S)
    assert sol.ok, sol.message


@pytest.mark.parametrize("method, module", [("nsgs", "nsgs"), ("nsgs-newton", "hybrid"),
                                            ("newton", "newton")])
def test_friction_methods_leave_compiling_out(monkeypatch, method, module):
    import importlib

    where = importlib.import_module(f"qpcontact.solvers.friction.{module}")
    problem = build_friction("mixed", 12, 4).problem
    assert qpcontact.solve(problem, method=method).ok                   # kernels loaded
    monkeypatch.setattr(where, "certified_error", compiling_once(where.certified_error))
    sol = qpcontact.solve(problem, method=method, time_limit=LIMIT_S)
    assert sol.ok, sol.message
