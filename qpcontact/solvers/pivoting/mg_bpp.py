"""``"mg-bpp"``: a multilevel search for the contact set and an exact
block-pivoting finish, for LCP(M, q) with M sparse symmetric positive
definite — the obstacle and contact problems of meshes.

Plain block pivoting ("bpp") is exact, but on a mesh its active-set front
moves about one grid line per exchange, each exchange a factorization (81 on
a 316 x 316 membrane).  Multigrid methods for obstacle problems find the
contact set at the cost of a few linear multigrid cycles, but only to a
tolerance, and nobody certifies their iterates.  So:

1. **Nested TNNMG** (:mod:`.multigrid`): the obstacle problem solved on the
   coarsest level exactly, then on each finer level from the interpolated
   coarser answer by truncated nonsmooth Newton multigrid cycles, until the
   level's contact set has held for two cycles with its natural-map residual
   at 1e-8 of ‖q‖∞ (1e-3 below the finest), or for five whatever the
   residual (or ``max_cycles``, default 500, on each level); on a finest
   level of at most 2·10⁴ unknowns the first cycle that leaves the set as
   it was ends the search (:data:`.multigrid.FIRST_HOLD_MAX`), on a
   Z-matrix's (a membrane) at every size, or where at most a third of its
   nodes are free the first cycle that flips at most four components, or
   n / 50 000 above 2.5·10⁵ unknowns (:func:`.multigrid.settled_flips`:
   the finish borders them on its factor of a
   small block for less than a cycle over every node).  A membrane of at
   least 2·10⁴ unknowns whose q carries a layer the coarse grids cannot
   hold (an obstacle with steps: :func:`.multigrid.layer_share`) starts
   from one conjugate-gradient step of the plate's shift (terraces at 10⁶:
   60 → 46 cycles).  The coarse levels are the
   problem's own (``LCP(..., hierarchy=[P_0, P_1, ...])``: a mesh knows its
   coarser grids; :mod:`formulations.meshes` passes them) or, when it
   carries none, built by smoothed aggregation and kept on M's structure for
   the next LCP with the same M.
2. **Block pivoting from that contact set** ("bpp"'s iteration,
   :func:`.bpp.block_pivoting`): z_F = −M_FF⁻¹ q_F for F = {z_i > 0}, the
   infeasible set exchanged with the Júdice–Pires safeguard and Murty's
   least-index pivots — finite for every SPD M from any basis, so a poor
   guess costs exchanges, never the answer.  The first basis is factorized
   (QDLDL, AMD ordering); a basis a few components away is solved on that
   factorization bordered by them (:mod:`.finish`).  Where the first basis breaks
   more bounds than that factor can border (min(64, n/200): a held set a
   few components off whose exact solution puts hundreds of free nodes
   below the obstacle — a plate's basis moves all over the block), the
   finest level's cycles are resumed once from that basic solution,
   projected, and the finish starts again from the set they hold (a
   140 x 140 plate at D = 1: 82 exchanges and 44 factorizations before,
   9.2 s; resumed, 30 cycles and one more factorization, 0.55 s).

The answer is the exact basic solution of the final basis, certified from M
and q by :func:`qpcontact.solve` like every answer; the multigrid iterate is
never returned.

What the search builds of M and its hierarchy alone (the untruncated
Galerkin products, the packed levels, the coarsest problem:
:class:`.multigrid.MultilevelSetup`) is kept on M's structure, and the next
LCP on it — ``LCP.with_structure(lcp.structure, q)``, a raft's or a
membrane's next load combination — starts from it where it still fits M
entry for entry (a 10⁴ membrane's ripple: 9.5 → 5.4 ms a load after the
first; docs/dev-notes.md, "the setup a matrix carries").

Options: ``max_cycles`` (finest-level cycles, default 500: a cycle is O(n),
an exchange a factorization, so the search runs until the contact set has
settled — plate n = 4e4: 40 cycles left 280 exchanges, 20 s; 400 cycles
none, 6.3 s), ``max_iter``
(pivoting steps, 10 n + 100), ``patience`` (3), ``progress`` (a callable
taking one line per cycle and exchange).  ``stats``: ``mg_levels``,
``mg_cycles`` (all levels), ``mg_rebuilds`` (cycles whose truncated coarse
operators moved), ``hierarchy`` ("given" or "aggregation"), ``shifted``,
``gap_steps`` and ``gap_residual`` (a plate's z_u, or a stepped membrane's
one step: conjugate-gradient steps and the residual over ‖q‖∞ they reached), ``w_cycles`` (a plate's corrections
are W-cycles), ``initial_active``,
``restarts`` (the search resumed), ``setup_kept`` (the multilevel setup
came with M's structure), ``factorizations``, ``bordered_solves``,
``block_exchanges``, ...
"""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp

from ...core.deadline import Deadline
from ...core.errors import InvalidProblemError
from ...core.linalg import SolutionOverflow
from ...core.options import PROGRESS, BySize, Option, read_options
from ...core.results import MethodResult
from .active_set import not_positive_definite, overflow_result, time_limit_result
from .bpp import block_pivoting
from .finish import REUSE_MAX, REUSE_SHARE
from .multigrid import (LAYER_MIN, LAYER_SHARE, MultilevelSetup, aggregation_hierarchy,
                        layer_share, multilevel_guess, settled_flips)

__all__ = ["run_mg_bpp", "MG_BPP_OPTIONS"]

MG_BPP_OPTIONS = (
    Option("max_cycles", 500, "int", low=0, doc="finest-level multigrid cycles at most"),
    Option("max_iter", BySize(lambda n: 10 * n + 100, "10 n + 100"), "int", low=0,
           doc="pivoting steps at most"),
    Option("patience", 3, "int", low=0, doc="full exchanges without a new smallest |I|"),
    PROGRESS,
)


def _hierarchy(problem, stats) -> tuple:
    structure = problem.structure
    if structure.hierarchy is not None:
        stats["hierarchy"] = "given"
        return structure.hierarchy
    stats["hierarchy"] = "aggregation"
    if structure.aggregated_hierarchy is None:
        t = time.perf_counter()
        structure.aggregated_hierarchy = aggregation_hierarchy(problem.M)
        stats["setup_time"] = time.perf_counter() - t
    return structure.aggregated_hierarchy


def _setup(problem, rows, prolongations, visits, stats) -> MultilevelSetup:
    """The multilevel setup of M and its hierarchy, held (its lock taken)
    for this solve: the one kept on M's structure for the next LCP on it
    (``LCP.with_structure``, ``ParametricLCP.at``: load cases share M)
    where it :meth:`~MultilevelSetup.fits` M as it is now and no other
    solve holds it; else a new one, kept in its place."""
    structure = problem.structure
    kept = structure.multilevel_setup
    held_elsewhere = kept is not None and not kept.lock.acquire(blocking=False)
    if kept is not None and not held_elsewhere:
        if kept.fits(rows, prolongations, visits):
            stats["setup_kept"] = True
            return kept
        kept.lock.release()
    stats["setup_kept"] = False
    # a kept setup fits an M whose diagonal was checked here when it was built
    M = problem.M
    diag = np.asarray(M.diagonal() if sp.issparse(M) else np.diag(M), dtype=float)
    if not np.all(diag > 0):
        i = int(np.flatnonzero(~(diag > 0))[0])
        raise InvalidProblemError(f"'mg-bpp' needs M symmetric positive definite; M[{i},{i}] = "
                                  f"{diag[i]:g} is not positive — use 'lemke'")
    setup = MultilevelSetup(rows, prolongations, visits)
    setup.lock.acquire()
    if not held_elsewhere:
        # a setup another solve holds stays kept: it is free again in a few
        # cycles' time, and the next load on M finds it (replacing it made
        # every solve beside another build its own)
        structure.multilevel_setup = setup
    return setup


def run_mg_bpp(problem, tol, options, time_limit=None) -> MethodResult:
    """The "mg-bpp" method (module docstring; options :data:`MG_BPP_OPTIONS`).
    ``time_limit`` (s): the deadline, read before every multigrid cycle
    and at every exchange of the exact finish."""
    deadline = Deadline(time_limit)
    n = problem.n
    opts = read_options("mg-bpp", options, MG_BPP_OPTIONS, size=n)
    M = problem.M
    stats: dict = {}
    t = time.perf_counter()
    # a plate (not a Z-matrix) starts from the shifted coarse answers, and
    # its linear corrections are W-cycles (multigrid's docstring says why)
    plate = not problem.structure.is_z_matrix
    # a symmetric M stored by columns is, read by rows, itself: the cycles
    # take it as it is instead of a converted copy (1.0-1.3 ms of a 10⁵
    # membrane's 80-100); within SYMMETRY_RTOL of symmetric, they search on
    # Mᵀ, a guess for data that close — the finish solves M's own LCP
    rows = (M.T if sp.issparse(M) and M.format == "csc" and M.has_canonical_format
            and problem.is_symmetric else M)
    hierarchy = _hierarchy(problem, stats)
    setup = _setup(problem, rows, hierarchy, 2 if plate else 1, stats)
    return _solve(problem, rows, hierarchy, setup, plate, opts, stats, deadline, t)


def _solve(problem, rows, hierarchy, setup, plate, opts, stats, deadline, t) -> MethodResult:
    """The search and the finish on a held setup (:func:`run_mg_bpp`).  The
    setup is held for the cycles only: the exact finish reads M alone, and
    another load on M may cycle meanwhile."""
    n = problem.n
    cycles, max_iter = opts["max_cycles"], opts["max_iter"]
    patience, progress = opts["patience"], opts["progress"]
    settled = None if plate else settled_flips(n)
    # a large membrane whose obstacle has steps starts from one step of the
    # plate's shift (multigrid.layer_share says how the steps show in q)
    layered = (not plate and n >= LAYER_MIN and len(hierarchy) > 0
               and layer_share(problem.q, setup.Rs[0]) > LAYER_SHARE)
    try:
        z = multilevel_guess(rows, problem.q, hierarchy, cycles=cycles, stats=stats,
                             shifted=plate or layered, w_cycles=plate, settled=settled,
                             progress=progress, deadline=deadline, setup=setup,
                             gap_steps=1 if layered else None)
    finally:
        setup.lock.release()
    stats["multigrid_time"] = time.perf_counter() - t
    if deadline.expired():
        return time_limit_result("mg-bpp", stats["mg_cycles"], "multigrid cycles", stats)
    stats["restarts"] = 0
    try:
        z, F, stats, status = block_pivoting(problem, z > 0.0, max_iter, patience, stats, deadline,
                                             # below REUSE_SHARE unknowns nothing is bordered
                                             far=min(REUSE_MAX, n // REUSE_SHARE) or None)
        if status == "far":
            # the held set's exact solution breaks more bounds than the factor
            # can border: the cycles, resumed from it, find the set where
            # block pivoting would wander (a plate's exchanges move
            # components all over the block)
            stats["restarts"] += 1
            with setup.lock:
                z = multilevel_guess(rows, problem.q, hierarchy, cycles=cycles,
                                     stats=stats, w_cycles=plate, settled=settled,
                                     progress=progress, deadline=deadline,
                                     start=np.maximum(z, 0.0), setup=setup)
            if deadline.expired():
                return time_limit_result("mg-bpp", stats["mg_cycles"], "multigrid cycles", stats)
            z, F, stats, status = block_pivoting(problem, z > 0.0, max_iter, patience, stats,
                                                 deadline)
    except np.linalg.LinAlgError as exc:
        raise not_positive_definite("mg-bpp", exc) from None
    except SolutionOverflow as exc:
        return overflow_result("mg-bpp", exc)
    if status == "time_limit":
        return time_limit_result("mg-bpp", stats["mg_cycles"] + stats["iterations"],
                                 "cycles and exchanges", stats)
    stats["active"] = int(F.sum())
    if progress is not None:
        progress(f"mg-bpp: exact finish: {stats['iterations']} exchanges, "
                 f"{stats['factorizations']} factorizations, {stats['bordered_solves']} bordered solves")
    return MethodResult(
        x=z, backend_status=status, iterations=stats["mg_cycles"] + stats["iterations"],
        status="max_pivots" if status == "max_pivots" else None,
        backend_message=(f"iteration limit {max_iter} reached" if status == "max_pivots" else ""),
        stats=stats,
    )
