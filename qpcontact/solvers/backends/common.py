"""What the backend wrappers share: quiet C output, option checks that catch
misspelt settings before a backend ignores them, the data a backend is known to
survive, and the clock test for backends that do not say they ran out of time."""

from __future__ import annotations

import contextlib
import os
import sys

import numpy as np
import scipy.sparse as sp

from ...core.errors import InvalidOptionError
from ...core.options import names_only, read_options
from ...core.results import MethodResult

__all__ = ["SMALL_WORK", "isolate_from", "PRINTS_WHEN_QUIET", "quiet_c_stdout", "ran_out", "DATA_LIMIT", "DEFAULT_DATA_LIMIT",
           "data_magnitude", "refuse_extreme_data", "reject_options", "check_option_names",
           "qpsolvers_known_options", "QPSOLVERS_KEYWORDS"]


#: Unknowns plus constraints below which a backend without a time setting
#: whose work an iteration cap bounds (PIQP, DAQP, quadprog, CVXOPT, ECOS)
#: may run in-process while much time is left
#: (qpcontact.dispatch.calls.IN_PROCESS_MIN_LEFT).  Above it the
#: factorizations are what is slow: PIQP ran 36.5 s of a 6 s share on an
#: infeasible LCP of n = 1 000 and 148 s on an unbounded QP of that size.
#: Below it the slowest call measured was DAQP on a degenerate QP of n = 60
#: (1.8 s, at its iteration cap); a fork costs 15-40 ms, more than such a
#: solve of n = 8.
SMALL_WORK = 200


def isolate_from(has_time_setting: bool, work_bounded: bool) -> int | None:
    """:attr:`~qpcontact.solvers.method.Method.isolate_from` of a backend:
    None where it keeps a limit itself, SMALL_WORK where an iteration cap
    bounds its work, 0 (always, under a limit) where nothing does."""
    if has_time_setting:
        return None
    return SMALL_WORK if work_bounded else 0


# OSQP 1.x prints "Polishing not needed - no active set detected at optimal
# point" from C even with verbose=False; in a time stepper that is one line per
# step.  highspy 1.16 prints its banner ("Running HiGHS 1.16.0 ...") when a
# solver object is made, before qpsolvers can turn its output off.  Their
# C-level stdout is silenced during the call.
PRINTS_WHEN_QUIET = {"osqp", "highs"}


@contextlib.contextmanager
def quiet_c_stdout(enabled: bool):
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


def reject_options(solver: str, options: dict, exc: Exception) -> None:
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


def check_option_names(label: str, options: dict, known) -> None:
    """InvalidOptionError for option names ``label`` does not know, before the
    backend is called: HiGHS, PIQP and cvxpy's DAQP and ProxQP interfaces
    accept unknown names silently (a misspelt tolerance is then ignored).
    ``known`` is a set of names (checked by :func:`qpcontact.core.options.read_options`,
    which suggests a close one), or a predicate for backends that can only be
    asked name by name (HiGHS), or None (the backend rejects names itself)."""
    if known is None or not options:
        return
    if not callable(known):
        read_options(label, options, names_only(known), word="setting")
        return
    unknown = sorted(key for key in options if not known(key))
    if unknown:
        raise InvalidOptionError(
            f"{label} has no setting {', '.join(map(repr, unknown))}; see its documentation "
            "for the setting names")


_PROXQP_SOLVE_KEYWORDS = {  # proxsuite.proxqp.dense.solve's keyword arguments (0.6-0.8)
    "eps_abs", "eps_rel", "rho", "mu_eq", "mu_in", "verbose", "compute_preconditioner",
    "compute_timings", "max_iter", "initial_guess", "check_duality_gap", "eps_duality_gap_abs",
    "eps_duality_gap_rel", "primal_infeasibility_solving", "default_H_eigenvalue_estimate"}


QPSOLVERS_KEYWORDS = {"initvals", "verbose"}


def _highs_accepts(key) -> bool:
    import highspy

    if key in QPSOLVERS_KEYWORDS:
        return True
    with quiet_c_stdout(True):  # HiGHS prints a line for an unknown name
        status, _ = highspy.Highs().getOptionValue(str(key))
    return status == highspy.HighsStatus.kOk


def qpsolvers_known_options(name: str):
    """What ``check_option_names`` needs for ``name`` (None: the backend
    rejects unknown names itself)."""
    if name == "highs":
        return _highs_accepts
    if name == "piqp":
        import piqp

        return QPSOLVERS_KEYWORDS | {"backend"} | {
            a for a in dir(piqp.DenseSolver().settings) if not a.startswith("_")}
    if name == "proxqp":
        return QPSOLVERS_KEYWORDS | {"backend"} | _PROXQP_SOLVE_KEYWORDS
    return None
