"""cvxpy with each of its installed QP-capable solvers, as ``cvxpy:NAME``.

cvxpy canonicalises the problem and then calls the solver with its own
defaults, which differ from the solver's (its OSQP interface turns polishing
on and tightens eps to 1e-5), so ``"osqp"`` and ``"cvxpy:OSQP"`` at
``accuracy="default"`` are different configurations; both are reported.
The canonicalisation time is part of the wall time: it is what a cvxpy user pays.
"""

from __future__ import annotations

import importlib.util
import time
import warnings

import numpy as np

from ...core.results import MethodResult
from ..method import Method
from .common import (PRINTS_WHEN_QUIET, isolate_from, check_option_names, qpsolvers_known_options,
                     quiet_c_stdout, ran_out, refuse_extreme_data, reject_options)
from .settings import backend_settings

_ALGORITHMS = {
    "CLARABEL": "interior-point", "SCS": "ADMM (conic)", "ECOS": "interior-point (conic)",
    "OSQP": "ADMM", "PIQP": "interior-point (proximal)", "PROXQP": "augmented-Lagrangian",
    "DAQP": "active-set (dual)", "HIGHS": "active-set", "QPALM": "augmented-Lagrangian",
    "MOSEK": "interior-point", "GUROBI": "barrier/simplex", "CVXOPT": "interior-point",
}
_EXACT = {"DAQP", "HIGHS"}
_DENSE_ONLY = {"DAQP"}  # cvxpy hands them a dense copy: n x n doubles
#: Each solver's own time-limit setting under cvxpy (seconds).
TIME_LIMIT_KEY = {"OSQP": "time_limit", "CLARABEL": "time_limit", "HIGHS": "time_limit",
                  "SCS": "time_limit_secs"}
#: as qpsolvers_backends.UNBOUNDED_WORK
UNBOUNDED_WORK = {"PROXQP"}
_CVXPY_KEYWORDS = {"verbose", "warm_start"}


def _known_options(solver: str):
    """Option names cvxpy's interface passes on, for the interfaces that drop
    the others silently (DAQP filters by ALLOWED_SOLVER_OPTS; ProxQP reads six
    names); None where the solver itself rejects unknown names."""
    if solver == "PROXQP":  # cvxpy 1.4-1.7 proxqp_qpif.solve_via_data
        return _CVXPY_KEYWORDS | {"backend", "eps_abs", "eps_rel", "max_iter", "rho", "mu_eq", "mu_in"}
    if solver == "DAQP":
        from cvxpy.reductions.solvers.qp_solvers.daqp_qpif import DAQP

        return _CVXPY_KEYWORDS | set(DAQP.ALLOWED_SOLVER_OPTS)
    if solver in ("HIGHS", "PIQP"):
        known = qpsolvers_known_options(solver.lower())
        if callable(known):
            return lambda key: key in _CVXPY_KEYWORDS or known(key)
        return _CVXPY_KEYWORDS | (known - {"initvals", "backend"})
    return None


def _qp_capable(installed: list[str]) -> list[str]:
    """Installed solvers that take a QP: cvxpy's QP solvers, and conic solvers
    with second-order cones or quadratic objectives."""
    from cvxpy.reductions.solvers import defines

    out = []
    for name in installed:
        if name in defines.QP_SOLVERS:
            out.append(name)
            continue
        conic = defines.SOLVER_MAP_CONIC.get(name)
        if conic is None:
            continue
        cones = {c.__name__ for c in conic.SUPPORTED_CONSTRAINTS}
        if "SOC" in cones or getattr(conic, "supports_quad_obj", lambda: False)():
            out.append(name)
    return sorted(out)


def _make_run(solver: str):
    def run(problem, tol, options, time_limit=None) -> MethodResult:
        import cvxpy as cp

        check_option_names(f"cvxpy:{solver}", options, _known_options(solver))
        refused = refuse_extreme_data(f"cvxpy:{solver}", problem)
        if refused is not None:
            return refused
        P, q, G, h, A, b, lb, ub = problem.unpack()
        n = q.shape[0]
        x = cp.Variable(n)
        objective = cp.Minimize(0.5 * cp.quad_form(x, P, assume_PSD=True) + q @ x)
        cons, names = [], []
        if G is not None:
            cons.append(G @ x <= h)
            names.append("G")
        if A is not None:
            cons.append(A @ x == b)
            names.append("A")
        lower = np.flatnonzero(np.isfinite(lb)) if lb is not None else np.zeros(0, int)
        upper = np.flatnonzero(np.isfinite(ub)) if ub is not None else np.zeros(0, int)
        if lower.size:
            cons.append(x[lower] >= lb[lower])
            names.append("lb")
        if upper.size:
            cons.append(x[upper] <= ub[upper])
            names.append("ub")
        prob = cp.Problem(objective, cons)
        settings = {**backend_settings("cvxpy", solver, tol), **options}
        if time_limit is not None and solver in TIME_LIMIT_KEY:
            settings.setdefault(TIME_LIMIT_KEY[solver], float(time_limit))
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                started = time.perf_counter()
                with quiet_c_stdout(solver.lower() in PRINTS_WHEN_QUIET):
                    prob.solve(solver=solver, **settings)
                elapsed = time.perf_counter() - started
        except Exception as exc:
            reject_options(f"cvxpy:{solver}", options, exc)
            return MethodResult(x=None, backend_status="exception", backend_message=f"{type(exc).__name__}: {exc}")
        stats = prob.solver_stats
        duals = dict(zip(names, (c.dual_value for c in cons)))
        y = np.asarray(duals["A"]).ravel() if "A" in duals and duals["A"] is not None else None
        z = np.asarray(duals["G"]).ravel() if "G" in duals and duals["G"] is not None else None
        z_box = None
        if lb is not None or ub is not None:
            z_box = np.zeros(n)
            if duals.get("lb") is not None:
                z_box[lower] -= np.asarray(duals["lb"]).ravel()
            if duals.get("ub") is not None:
                z_box[upper] += np.asarray(duals["ub"]).ravel()
        # cvxpy reports a solver's time limit as "user_limit", as it does an
        # iteration cap: the clock decides
        extra = ({"time_limit_reached": True}
                 if ran_out(elapsed, time_limit, solver in TIME_LIMIT_KEY) else {})
        return MethodResult(
            x=None if x.value is None else np.asarray(x.value).ravel(),
            y=y, z=z, z_box=z_box,
            backend_status=str(prob.status),
            backend_message="; ".join(str(w.message) for w in caught),
            iterations=getattr(stats, "num_iters", None),
            stats=extra,
        )

    return run


def specs() -> list[Method]:
    """``cvxpy:NAME`` for each QP-capable solver cvxpy has installed; without
    cvxpy, ``cvxpy:CLARABEL`` as unavailable (so asking for it names the
    pip command)."""
    if importlib.util.find_spec("cvxpy") is None:
        return [Method(name="cvxpy:CLARABEL", run=None, takes="qp", requires="monotone",
                       accepts_sparse=True, returns_duals=True, algorithm="interior-point",
                       exact=False, family="cvxpy", install="pip install cvxpy", available=False,
                       package="cvxpy")]
    import cvxpy as cp

    return [Method(
        name=f"cvxpy:{solver}",
        run=_make_run(solver),
        takes="qp",
        requires="monotone",
        accepts_sparse=solver not in _DENSE_ONLY,
        returns_duals=True,
        algorithm=_ALGORITHMS.get(solver, "unknown"),
        exact=solver in _EXACT,
        family="cvxpy",
        install=f"pip install cvxpy  # and the {solver} solver package",
        available=True,
        isolate_from=isolate_from(solver in TIME_LIMIT_KEY, solver not in UNBOUNDED_WORK),
        package="cvxpy",
    ) for solver in _qp_capable(cp.installed_solvers())]
