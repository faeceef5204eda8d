"""``"enumeration"``: every complementary basis of a small LCP(M, q), any M.

A solution of w = M z + q >= 0, z >= 0, z'w = 0 is basic for some set F
(z_F from M_FF z_F = -q_F, z elsewhere 0, w_F = 0) wherever M_FF is
nonsingular.  Trying the 2^n sets F in order of size finds one whenever a
basic solution exists — the case Lemke's method cannot promise for a general
M (it may end on a secondary ray although a solution exists).  Cost: up to
2^n small solves, so n <= ENUMERATION_MAX; "auto" tries it after Lemke.
Exact in the same sense as the pivoting methods: the answer is a basic
solution recomputed by an LU solve and certified by the caller; nonbasic
solutions (all M_FF singular) are not found.
"""

from __future__ import annotations

import warnings
from itertools import combinations

import numpy as np
import scipy.linalg

from ...core.deadline import Deadline
from ...core.errors import InvalidProblemError
from ...core.options import read_options
from ...core.results import MethodResult
from ...core.linalg import dense_matrix
from .active_set import time_limit_result

#: 2^16 = 65 536 sets of at most 16 x 16: about a second in the worst case.
ENUMERATION_MAX = 16


def run_enumeration(problem, tol, options, time_limit=None) -> MethodResult:
    """The "enumeration" method (module docstring); it takes no options.
    ``time_limit`` (s): the deadline, checked every 256 bases."""
    read_options("enumeration", options, ())
    n = problem.n
    if n > ENUMERATION_MAX:
        raise InvalidProblemError(f"'enumeration' tries all 2^n complementary bases; n = {n} is "
                                  f"above {ENUMERATION_MAX}: use 'lemke' or a QP backend")
    M, q = dense_matrix(problem.M), problem.q
    with warnings.catch_warnings():
        # an exactly singular M_FF is skipped below, not worth a warning per set
        warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
        return _enumerate(M, q, n, Deadline(time_limit))


def _enumerate(M, q, n, deadline) -> MethodResult:
    tried = 0
    for size in range(n + 1):
        for F in combinations(range(n), size):
            tried += 1
            if tried % 256 == 0 and deadline.expired():
                return time_limit_result("enumeration", tried, "bases",
                                         {"bases_tried": tried})
            F = list(F)
            z = np.zeros(n)
            if F:
                try:
                    lu = scipy.linalg.lu_factor(M[np.ix_(F, F)], check_finite=False)
                except (np.linalg.LinAlgError, ValueError):
                    continue
                if not np.all(np.isfinite(lu[0])) or np.min(np.abs(np.diag(lu[0]))) == 0:
                    continue
                z[F] = scipy.linalg.lu_solve(lu, -q[F], check_finite=False)
            # each row judged on its own scale, |M||z| + |q|; w_F must vanish to
            # the solve's accuracy (an ill-conditioned M_FF's z is skipped)
            scale = np.abs(M) @ np.abs(z) + np.abs(q)
            w = M @ z + q
            slack = 1e-12 * np.maximum(scale, np.finfo(float).tiny)
            if np.all(z >= -slack) and np.all(w >= -slack) and \
                    np.all(np.abs(w[F]) <= 1e-9 * np.maximum(scale[F], np.finfo(float).tiny)):
                return MethodResult(x=np.maximum(z, 0.0), backend_status="solved",
                                    iterations=tried, stats={"bases_tried": tried,
                                                             "basic_set": F})
    return MethodResult(x=None, status="no basic solution", backend_status="exhausted",
                        backend_message=f"none of the {tried} complementary bases with a "
                        "nonsingular M_FF is feasible: no basic solution exists (a nonbasic "
                        "one, on a singular M_FF, is not excluded)", iterations=tried,
                        stats={"bases_tried": tried})
