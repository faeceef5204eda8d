"""The linear programs behind the proofs: HiGHS through :func:`scipy.optimize.linprog`,
on data whose rows (and, for rays, columns) are scaled to unit size, so that
the LP's absolute tolerances mean the same on every row.  An LP's answer is
only a candidate: :mod:`qpcontact.proofs.exact` decides."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..core.deadline import Deadline

__all__ = ["linprog", "csr_rows", "row_scale", "row_abs_max", "column_scale", "LP_TIME_LIMIT", "proof_deadline",
           "null_basis", "NULL_SPACE_MAX_N"]


#: seconds a proof's LPs may take together (solve's time_limit when smaller)
LP_TIME_LIMIT = 30.0


def proof_deadline(time_limit) -> Deadline:
    """A proof's deadline: ``time_limit`` (a :class:`Deadline` or seconds;
    None: none) and never more than :data:`LP_TIME_LIMIT` from now.  A search
    of four to six LPs used to get the whole time limit for each and doubled
    a solve's time; they now share one deadline, which the exact checks watch
    too."""
    given = time_limit if isinstance(time_limit, Deadline) else Deadline(time_limit)
    return given.within(LP_TIME_LIMIT)


def linprog(c, A_ub=None, b_ub=None, A_eq=None, b_eq=None, bounds=None, time_limit=LP_TIME_LIMIT,
             tight=True):
    """HiGHS's LP; ``time_limit`` in seconds or a :class:`Deadline` (None
    once it has passed: no LP is started without time to finish it)."""
    from scipy.optimize import linprog as highs_lp

    deadline = time_limit if isinstance(time_limit, Deadline) else Deadline(time_limit)
    res = None
    # HiGHS's choice first; where it stops on numerical difficulties (status
    # 4, no point: SciPy 1.17's HiGHS on a frame's degenerate patterns at its
    # collapse load, with tolerances at 1e-10) the dual simplex, then the
    # interior point, then HiGHS's own tolerances (1e-7): a four-legged
    # table's collapse patterns 5e-7 of p above its path's end failed the
    # three at 1e-10 and gave, at 1e-7, a Farkas vector that checks to 1.5e-10
    # — an LP's answer is only a candidate, checked after
    attempts = [("highs", tight), ("highs-ds", tight), ("highs-ipm", tight)]
    if tight:
        attempts.append(("highs", False))
    for method, tighten in attempts:
        left = deadline.left()
        if left is not None and left <= 0.0:
            break
        options = {} if left is None else {"time_limit": left}
        if tighten:
            options.update(primal_feasibility_tolerance=1e-10, dual_feasibility_tolerance=1e-10)
        with np.errstate(all="ignore"):
            try:
                res = highs_lp(c, A_ub=A_ub, b_ub=b_ub, A_eq=A_eq, b_eq=b_eq, bounds=bounds,
                               method=method, options=options)
            except (ValueError, MemoryError):
                return None
        if res.status != 4:
            break
    return res


def csr_rows(M, n):
    if M is None:
        return sp.csr_matrix((0, n))
    return sp.csr_matrix(M)


def row_abs_max(M: sp.csr_matrix) -> np.ndarray:
    """max_j |M_ij| per row (0 for an empty row), read off the CSR arrays: the
    doubt test asks it of every certified QP answer, where scipy's
    abs(M).max(axis=1) cost 2 ms a call (a third of a mechanism's step)."""
    big = np.zeros(M.shape[0])
    if M.nnz:
        if not M.has_canonical_format:
            M = M.copy()
            M.sum_duplicates()
        starts = M.indptr[:-1]
        rows = np.flatnonzero(np.diff(M.indptr) > 0)
        big[rows] = np.maximum.reduceat(np.abs(M.data), starts[rows])
    return big


def row_scale(M: sp.csr_matrix) -> np.ndarray:
    big = row_abs_max(M)
    return np.where(big > 0, 1.0 / np.where(big > 0, big, 1.0), 0.0)


def column_scale(blocks, n) -> np.ndarray:
    """Powers of two near 1 / max|column j| of the stacked blocks: x = c * x~.
    Data scaled over decades make the LP's answer span them too, and HiGHS's
    absolute tolerances would leave the small components without a correct
    digit (a feasible point whose rows were violated by 27 % of their size
    came back "optimal" on a QP scaled over 12 decades)."""
    stacked = [m for m in blocks if m is not None and m.shape[0]]
    if not stacked:
        return np.ones(n)
    colmax = np.asarray(abs(sp.vstack(stacked)).max(axis=0).toarray()).ravel()
    return np.where(colmax > 0, 2.0 ** -np.round(np.log2(np.where(colmax > 0, colmax, 1.0))), 1.0)


#: largest n whose null space is computed densely (an eigendecomposition:
#: 0.02 s at n = 250, about a second at 1 000 on one core)
NULL_SPACE_MAX_N = 1000


#: seconds per n³ of a dense eigendecomposition on one core (measured:
#: 1.2-1.5 s at n = 1 000), with a margin: it cannot be stopped halfway, so
#: it is not started where it would not end before the deadline
EIGH_SECONDS_PER_N3 = 2e-9


def null_basis(S, deadline=None) -> tuple[np.ndarray, np.ndarray] | None:
    """(B, c): a basis of the numerical null space of the symmetric PSD
    matrix S (dense or sparse, n <= NULL_SPACE_MAX_N) is c * B (row i of B
    times c_i), each column of B scaled to max 1.  c_i are powers of two
    near S_ii^-1/2, and B is the eigenvectors of the scaled D S D whose
    eigenvalues lie within 1e3 n eps of the largest: balanced coordinates,
    where a candidate is snapped (a component at 1e-12 of the largest in
    S's own units keeps no digit there) and mapped back exactly.  None when
    S is definite (or not finite), and where ``deadline`` leaves less time
    than the eigendecomposition takes (EIGH_SECONDS_PER_N3)."""
    from scipy.linalg import eigh

    n = S.shape[0]
    left = None if deadline is None else deadline.left()
    if n > NULL_SPACE_MAX_N or (left is not None and left < EIGH_SECONDS_PER_N3 * n ** 3):
        return None
    A = S.toarray() if sp.issparse(S) else np.asarray(S, dtype=float)
    if not np.all(np.isfinite(A)):
        return None
    diag = np.abs(A.diagonal())
    c = np.where(diag > 0, 2.0 ** -np.round(0.5 * np.log2(np.where(diag > 0, diag, 1.0))), 1.0)
    with np.errstate(all="ignore"):
        lam, V = eigh(A * c[:, None] * c[None, :])
    top = float(np.max(np.abs(lam), initial=0.0))
    B = V[:, np.abs(lam) <= 1e3 * n * np.finfo(float).eps * top]
    if not B.shape[1]:
        return None
    return B / np.max(np.abs(B), axis=0), c
