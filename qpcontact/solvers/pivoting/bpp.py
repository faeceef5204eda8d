"""``"bpp"``: block principal pivoting for LCP(M, q) with M symmetric positive
definite, dense or sparse.

Kostreva (1978) block exchange with the Júdice & Pires (1994) safeguard.  For a
set F of basic z's (w_F = 0, z_N = 0) the point is

    z_F = -M_FF^{-1} q_F,   w_N = M_NF z_F + q_N,

computed by one factorization of M_FF (dense Cholesky; for sparse M, LAPACK's
banded Cholesky when M's bandwidth is at most 16 — contact stacks — and QDLDL's
LDL' with AMD ordering otherwise).  A basis a few components away from the
last factorized one is solved on that factorization bordered by the
components that moved (:class:`.finish.NearbyBases`).  Intermediate bases only need signs; the
basis that looks final is refined iteratively before it is accepted.  The infeasible set
I = {i in F: z_i < 0} ∪ {i in N: w_i < 0} is exchanged as a whole while |I|
keeps decreasing; after ``patience`` exchanges (default 3) without a new smallest
|I|, single pivots by Murty's least-index rule take over until |I| drops again.
Murty's rule is finite for P-matrices, and every full exchange either lowers the
record |I| or uses up patience, so the method terminates.  Convergence in a
handful of factorizations is typical for contact problems.

``initial_active`` (bool mask or indices of the z's expected positive) warm
starts from a known contact set — time-stepping formulations pass the previous
step's.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ...core.deadline import Deadline
from ...core.errors import InvalidOptionError
from ...core.results import MethodResult
from ...core.linalg import BANDED_MAX, SolutionOverflow
from ...judge.scales import ComponentScales
from .active_set import (ExchangeRule, negative_components, not_positive_definite,
                         overflow_result, time_limit_result)
from .finish import NearbyBases
from ...core.options import BySize, Option, read_options

__all__ = ["run_bpp", "block_pivoting", "BPP_OPTIONS"]

BPP_OPTIONS = (
    Option("initial_active", None, "any",
           doc="a bool mask of length n, or the indices of the z's expected positive"),
    Option("max_iter", BySize(lambda n: 10 * n + 100, "10 n + 100"), "int", low=0,
           doc="block exchanges and pivots at most"),
    Option("patience", 3, "int", low=0, doc="full exchanges without a new smallest |I|"),
)


def _as_mask(active, n: int) -> np.ndarray:
    a = np.asarray(active)
    if a.dtype == bool:
        if a.shape != (n,):
            raise InvalidOptionError(f"'bpp': initial_active as a mask must have length {n}, "
                                     f"got shape {a.shape}")
        return a.copy()
    if a.size and (not np.issubdtype(a.dtype, np.integer) or a.min() < 0 or a.max() >= n):
        raise InvalidOptionError(f"'bpp': initial_active must be a bool mask of length {n} or "
                                 f"indices in 0..{n - 1}")
    mask = np.zeros(n, dtype=bool)
    mask[a.astype(np.intp).ravel()] = True
    return mask


def block_pivoting(problem, F: np.ndarray, max_iter: int, patience: int, stats=None,
                   deadline: Deadline | None = None, far: int | None = None):
    """Iterate from the basis F; returns (z, F, stats, status).  ``stats``
    (a dict, updated in place) lets a caller count its own work beside;
    past ``deadline`` (checked at every exchange) the status is
    "time_limit" and z is None.  ``far``: where the first basis has more
    infeasible components than that, the status is "far" and z its basic
    solution (unrefined), before any exchange."""
    M, q = problem.M, problem.q
    scales = ComponentScales.of(problem)
    # Per-matrix analysis, cached on the problem (a time stepper reuses it).
    structure = problem.structure
    bands = structure.upper_bands(BANDED_MAX) if sp.issparse(M) else None
    stats = {} if stats is None else stats
    stats.update(iterations=0, initial_active=int(F.sum()))
    # A banded Cholesky costs a few products with M: nothing to reuse.
    bases = NearbyBases(M, q, stats, bands=bands, reuse=bands is None, absM=scales.absM)
    rule = ExchangeRule(q.size, patience, stats)
    while True:
        # Intermediate bases only need signs: refine once the signs look final.
        z, w = bases.basic_solution(F, refine=0)
        infeasible = negative_components(scales, np.where(F, z, w), F, z)
        if infeasible.size == 0:
            z, w = bases.basic_solution(F, refine=3)
            infeasible = negative_components(scales, np.where(F, z, w), F, z)
        if infeasible.size == 0:
            z[F] = np.maximum(z[F], 0.0)
            return z, F, stats, "solved"
        if far is not None and stats["iterations"] == 0 and infeasible.size > far:
            return z, F, stats, "far"
        if stats["iterations"] >= max_iter:
            return z, F, stats, "max_pivots"
        if deadline is not None and deadline.expired():
            return None, F, stats, "time_limit"
        stats["iterations"] += 1
        rule.step(F, infeasible)


def run_bpp(problem, tol, options, time_limit=None) -> MethodResult:
    """The "bpp" method (module docstring).  Options (:data:`BPP_OPTIONS`):
    ``initial_active``, ``max_iter`` (10 n + 100), ``patience`` (3).
    ``time_limit`` (s): the deadline, checked at every exchange."""
    deadline = Deadline(time_limit)
    n = problem.n
    opts = read_options("bpp", options, BPP_OPTIONS, size=n)
    F = (_as_mask(opts["initial_active"], n) if opts["initial_active"] is not None
         else np.zeros(n, dtype=bool))
    max_iter, patience = opts["max_iter"], opts["patience"]
    try:
        z, F, stats, status = block_pivoting(problem, F, max_iter, patience, deadline=deadline)
    except np.linalg.LinAlgError as exc:
        raise not_positive_definite("bpp", exc) from None
    except SolutionOverflow as exc:
        return overflow_result("bpp", exc)
    if status == "time_limit":
        return time_limit_result("bpp", stats["iterations"], "exchanges", stats)
    stats["active"] = int(F.sum())
    return MethodResult(
        x=z, backend_status=status, iterations=stats["iterations"],
        status="max_pivots" if status == "max_pivots" else None,
        backend_message=(f"iteration limit {max_iter} reached" if status == "max_pivots" else ""),
        stats=stats,
    )
