"""Every QP solver that qpsolvers finds installed, as a registered method.

One generic wrapper around ``qpsolvers.solve_problem``; the table below only
declares what each backend is and how to install it.  Solvers qpsolvers knows
but that are missing here are registered as unavailable, so that asking for
one names the pip command.
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from ...core.results import MethodResult
from ..method import Method
from .common import (PRINTS_WHEN_QUIET, isolate_from, check_option_names, qpsolvers_known_options,
                     quiet_c_stdout, ran_out, refuse_extreme_data, reject_options)
from .settings import backend_settings

#: name: (pip package, algorithm, exact)
KNOWN = {
    "osqp": ("osqp", "ADMM", False),
    "clarabel": ("clarabel", "interior-point", False),
    "proxqp": ("proxsuite", "augmented-Lagrangian", False),
    "daqp": ("daqp", "active-set (dual)", True),
    "piqp": ("piqp", "interior-point (proximal)", False),
    "highs": ("highspy", "active-set", True),
    "quadprog": ("quadprog", "active-set (Goldfarb-Idnani)", True),
    "scs": ("scs", "ADMM (conic)", False),
    "cvxopt": ("cvxopt", "interior-point", False),
    "ecos": ("ecos", "interior-point (conic)", False),
    "qpalm": ("qpalm", "augmented-Lagrangian", False),
    "qpoases": ('"qpsolvers[qpoases]"', "active-set", True),
    "hpipm": ('"qpsolvers[hpipm]"', "interior-point", False),
    "qpswift": ('"qpsolvers[qpswift]"', "interior-point", False),
}


def _report(sol) -> tuple[str, int | None]:
    """The backend's own status and iteration count, from qpsolvers' extras."""
    extras = sol.extras or {}
    info = extras.get("info", extras)
    status = getattr(info, "status", None)
    if status is None and isinstance(info, dict):
        status = info.get("status")
    if status is None:
        status = extras.get("status")
    iters = getattr(info, "iter", None)
    if iters is None and isinstance(info, dict):
        iters = info.get("iter")
    if iters is None:
        iters = extras.get("iterations")
    if iters is not None and not np.isscalar(iters):
        iters = int(np.sum(iters))  # quadprog reports [iterations, constraint drops]
    text = str(status) if status is not None else ("found" if sol.found else "not found")
    return text, (int(iters) if iters is not None else None)


#: Each backend's own time-limit setting, in seconds.  The others have none.
TIME_LIMIT_KEY = {"osqp": "time_limit", "clarabel": "time_limit", "highs": "time_limit",
                  "scs": "time_limit_secs"}
#: No time limit of their own, and an iteration cap that does not bound the
#: work (ProxQP counts outer iterations; 77 s and 3e5 inner iterations on an
#: SPD problem of n = 300 at max_iter = 10 000): run in a killable child
#: process whenever a time limit is in force (qpcontact.dispatch.isolation).
#: The others without a time setting (PIQP, DAQP, quadprog, CVXOPT, ECOS)
#: stop after a bounded number of factorizations, which at n = 1 000 is no
#: bound on the clock: they run in a child from common.SMALL_WORK unknowns
#: and constraints, or when little time is left.
UNBOUNDED_WORK = {"proxqp"}


def _make_run(name: str):
    def run(problem, tol, options, time_limit=None) -> MethodResult:
        import qpsolvers
        from qpsolvers.warnings import SparseConversionWarning

        check_option_names(name, options, qpsolvers_known_options(name))
        refused = refuse_extreme_data(name, problem)
        if refused is not None:
            return refused
        settings = {**backend_settings("qpsolvers", name, tol), **options}
        if time_limit is not None and name in TIME_LIMIT_KEY:
            settings.setdefault(TIME_LIMIT_KEY[name], float(time_limit))
        stats = {}
        if name not in qpsolvers.sparse_solvers and problem.has_sparse:
            P, q, G, h, A, b, lb, ub = problem.unpack_as_dense()
            problem = qpsolvers.Problem(P, q, G, h, A, b, lb, ub)
            stats["densified"] = True
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                started = time.perf_counter()
                with quiet_c_stdout(name in PRINTS_WHEN_QUIET):
                    sol = qpsolvers.solve_problem(problem, solver=name, **settings)
                elapsed = time.perf_counter() - started
            except Exception as exc:
                reject_options(name, options, exc)
                # otherwise a backend failure is a numerical outcome, not misuse
                return MethodResult(x=None, backend_status="exception",
                                    backend_message=f"{type(exc).__name__}: {exc}", stats=stats)
        status, iters = _report(sol)
        stats["found"] = bool(sol.found)
        # OSQP says "time limit reached", Clarabel MaxTime, SCS "reached
        # time_limit_secs"; HiGHS through qpsolvers only "not found", so the
        # clock is asked too
        if "time" in status.lower() or ran_out(elapsed, time_limit, name in TIME_LIMIT_KEY):
            stats["time_limit_reached"] = True
        message = "; ".join(str(w.message) for w in caught
                            if not issubclass(w.category, SparseConversionWarning))
        return MethodResult(
            x=sol.x,
            y=sol.y, z=sol.z, z_box=sol.z_box,
            backend_status=status,
            backend_message=message,
            iterations=iters,
            stats=stats,
        )

    return run


def specs() -> list[Method]:
    """Every solver qpsolvers knows, available or not (then with its pip command)."""
    import qpsolvers

    names = list(dict.fromkeys(list(KNOWN) + list(qpsolvers.available_solvers)))
    out = []
    for name in names:
        pip, algorithm, exact = KNOWN.get(name, (f'"qpsolvers[{name}]"', "unknown", False))
        available = name in qpsolvers.available_solvers
        out.append(Method(
            name=name,
            run=_make_run(name) if available else None,
            takes="qp",
            requires="monotone",
            accepts_sparse=name in qpsolvers.sparse_solvers,
            returns_duals=True,
            algorithm=algorithm,
            exact=exact,
            family="qpsolvers",
            install=f"pip install {pip}",
            available=available,
            isolate_from=isolate_from(name in TIME_LIMIT_KEY, name not in UNBOUNDED_WORK),
            package=pip.strip('"').split("[")[0],
        ))
    return out
