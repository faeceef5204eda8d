"""Every QP solver that qpsolvers finds installed, as a registered method.

One generic wrapper around ``qpsolvers.solve_problem``; the table below only
declares what each backend is and how to install it.  Solvers qpsolvers knows
but that are missing here are registered as unavailable, so that asking for
one names the pip command.
"""

from __future__ import annotations

import contextlib
import os
import sys
import time
import warnings

import numpy as np
import scipy.sparse as sp

from ...core.accuracy import backend_settings
from ...core.errors import InvalidOptionError
from ...core.results import MethodResult
from ..registry import Method, register

# name: (pip package, algorithm, exact)
_KNOWN = {
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


# OSQP 1.x prints "Polishing not needed - no active set detected at optimal
# point" from C even with verbose=False; in a time stepper that is one line per
# step.  highspy 1.16 prints its banner ("Running HiGHS 1.16.0 ...") when a
# solver object is made, before qpsolvers can turn its output off.  Their
# C-level stdout is silenced during the call.
_PRINTS_WHEN_QUIET = {"osqp", "highs"}


@contextlib.contextmanager
def _quiet_c_stdout(enabled: bool):
    if not enabled:
        yield
        return
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # captured stdout (pytest, notebooks)
        fd = 1
    sys.stdout.flush()
    saved = os.dup(fd)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), fd)
            yield
    finally:
        os.dup2(saved, fd)
        os.close(saved)


def ran_out(elapsed: float, time_limit, has_setting: bool) -> bool:
    """Whether a call that was given its time-limit setting used it all up
    (HiGHS through qpsolvers and every solver through cvxpy do not say)."""
    return time_limit is not None and has_setting and elapsed >= 0.95 * time_limit


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


#: Largest data magnitude handed to an external backend (after qpcontact's own
#: scaling), measured by benchmarks/backend_limits.py (docs/backends.md): HiGHS
#: 1.15 dies with a segmentation fault on a singular Hessian holding an entry of
#: 1e15 (its large_matrix_value); ProxQP 0.8 does not return on a linear term
#: of 1e200.  The others returned at every magnitude up to 1e300, but nothing
#: beyond 1e100 leaves room for the products an iteration forms.
DATA_LIMIT = {"highs": 1e14}
DEFAULT_DATA_LIMIT = 1e100


def data_magnitude(problem) -> float:
    """Largest |entry| of a QP's data (infinite bounds excluded)."""
    out = 0.0
    for part in problem.unpack():
        if part is None:
            continue
        if sp.issparse(part):
            vals = part.data
        else:
            vals = np.asarray(part, dtype=float).ravel()
        vals = np.abs(vals[np.isfinite(vals)])
        if vals.size:
            out = max(out, float(vals.max()))
    return out


def refuse_extreme_data(solver: str, problem) -> MethodResult | None:
    """A ``failed`` result, without calling the backend, when the data exceed
    what ``solver`` is known to survive; None otherwise."""
    limit = DATA_LIMIT.get(solver.split(":")[-1].lower(), DEFAULT_DATA_LIMIT)
    mag = data_magnitude(problem)
    if mag <= limit:
        return None
    return MethodResult(
        x=None, backend_status="refused",
        backend_message=(f"not called: the data hold an entry of magnitude {mag:.1e}, above the "
                         f"{limit:.0e} that {solver} is known to survive (docs/backends.md); "
                         "rescale the units, or use an exact method ('lemke', 'bpp')"))


def _reject_options(solver: str, options: dict, exc: Exception) -> None:
    """Raise InvalidOptionError when ``exc`` is the backend refusing one of the
    user's own options (backends say so in many ways: ValueError, TypeError,
    AttributeError, their own exception classes)."""
    bad = [key for key in options if key in str(exc)]
    if bad or (options and isinstance(exc, TypeError) and "argument" in str(exc)):
        text = str(exc)
        if len(text) > 300:  # pybind11 prints every overload's full signature
            text = text[:300] + " ..."
        raise InvalidOptionError(
            f"{solver} rejected the option(s) {bad or sorted(options)}: {type(exc).__name__}: {text}. "
            "See the backend's documentation for its setting names."
        ) from None


#: Each backend's own time-limit setting, in seconds.  The others have none.
TIME_LIMIT_KEY = {"osqp": "time_limit", "clarabel": "time_limit", "highs": "time_limit",
                  "scs": "time_limit_secs"}
#: No time limit of their own, and an iteration cap that does not bound the
#: work (ProxQP counts outer iterations; 77 s and 3e5 inner iterations on an
#: SPD problem of n = 300 at max_iter = 10 000): run in a killable child
#: process whenever a time limit is in force (qpcontact.isolation).  PIQP,
#: DAQP, quadprog, CVXOPT and ECOS stop after a bounded number of
#: factorizations.
NEEDS_ISOLATION = {"proxqp"}


def check_option_names(label: str, options: dict, known) -> None:
    """InvalidOptionError for option names ``label`` does not know, before the
    backend is called: HiGHS, PIQP and cvxpy's DAQP and ProxQP interfaces
    accept unknown names silently (a misspelt tolerance is then ignored).
    ``known`` is a set of names, or a predicate for backends that can only be
    asked name by name (HiGHS), or None (the backend rejects names itself)."""
    if known is None or not options:
        return
    accepts = known if callable(known) else known.__contains__
    unknown = sorted(key for key in options if not accepts(key))
    if not unknown:
        return
    if callable(known):
        raise InvalidOptionError(
            f"{label} has no setting {', '.join(map(repr, unknown))}; see its documentation "
            "for the setting names")
    import difflib

    hints = [f"{key!r} (did you mean {', '.join(map(repr, close))}?)"
             if (close := difflib.get_close_matches(key, sorted(known), n=2)) else repr(key)
             for key in unknown]
    raise InvalidOptionError(
        f"{label} has no setting {', '.join(hints)}; its settings are: {', '.join(sorted(known))}")


_PROXQP_SOLVE_KEYWORDS = {  # proxsuite.proxqp.dense.solve's keyword arguments (0.6-0.8)
    "eps_abs", "eps_rel", "rho", "mu_eq", "mu_in", "verbose", "compute_preconditioner",
    "compute_timings", "max_iter", "initial_guess", "check_duality_gap", "eps_duality_gap_abs",
    "eps_duality_gap_rel", "primal_infeasibility_solving", "default_H_eigenvalue_estimate"}
_QPSOLVERS_KEYWORDS = {"initvals", "verbose"}


def _highs_accepts(key) -> bool:
    import highspy

    if key in _QPSOLVERS_KEYWORDS:
        return True
    with _quiet_c_stdout(True):  # HiGHS prints a line for an unknown name
        status, _ = highspy.Highs().getOptionValue(str(key))
    return status == highspy.HighsStatus.kOk


def _known_options(name: str):
    """What ``check_option_names`` needs for ``name`` (None: the backend
    rejects unknown names itself)."""
    if name == "highs":
        return _highs_accepts
    if name == "piqp":
        import piqp

        return _QPSOLVERS_KEYWORDS | {"backend"} | {
            a for a in dir(piqp.DenseSolver().settings) if not a.startswith("_")}
    if name == "proxqp":
        return _QPSOLVERS_KEYWORDS | {"backend"} | _PROXQP_SOLVE_KEYWORDS
    return None


def _make_run(name: str):
    def run(problem, tol, options, time_limit=None) -> MethodResult:
        import qpsolvers
        from qpsolvers.warnings import SparseConversionWarning

        check_option_names(name, options, _known_options(name))
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
                with _quiet_c_stdout(name in _PRINTS_WHEN_QUIET):
                    sol = qpsolvers.solve_problem(problem, solver=name, **settings)
                elapsed = time.perf_counter() - started
            except Exception as exc:
                _reject_options(name, options, exc)
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


def register_all() -> None:
    import qpsolvers

    names = list(dict.fromkeys(list(_KNOWN) + list(qpsolvers.available_solvers)))
    for name in names:
        pip, algorithm, exact = _KNOWN.get(name, (f'"qpsolvers[{name}]"', "unknown", False))
        available = name in qpsolvers.available_solvers
        register(Method(
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
        ), replace=True)
