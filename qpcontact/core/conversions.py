"""Conversions between LCPs and quadratic programs (``qpsolvers.Problem``).

Three routes, each exact (the solution sets correspond one to one):

1. **Symmetric PSD LCP -> QP** (:meth:`LCP.to_qp`, defined with the LCP in
   :mod:`qpcontact.core.problems`).  The KKT conditions of
   ``min ½ z'Mz + q'z  s.t.  z >= 0`` are ``Mz + q - μ = 0, μ >= 0, z >= 0,
   μ'z = 0``: with w = μ they are the LCP.  In qpsolvers' sign convention the
   bound multipliers come back as ``z_box = -w``.

2. **Monotone LCP -> QP** (:meth:`LCP.to_monotone_qp`, likewise), for nonsymmetric M with
   M + M' PSD: ``min z'(Mz + q)  s.t.  Mz + q >= 0, z >= 0``.  The objective
   is ½ z'(M + M')z + q'z, convex; it is >= 0 on the feasible set and equals 0
   exactly at the LCP's solutions (a feasible monotone LCP is solvable, so the
   optimum is 0 whenever the LCP has a solution).

3. **Strictly convex QP -> dual LCP** (:func:`qp_to_lcp`), so that a pivoting
   method can solve any such QP exactly and cross-check every backend.  For
   ``min ½ x'Px + q'x  s.t.  Gx <= h, Ax = b, lb <= x <= ub`` with P positive
   definite, the finite bounds become rows of G.  Stationarity gives
   ``x = -P⁻¹(q + G'λ + A'y)``.  The **equality constraints are eliminated**
   (not kept as a mixed block): Ax = b fixes
   ``y = -S⁻¹(b + AP⁻¹(q + G'λ))`` with the Schur complement S = AP⁻¹A', so
   that ``x = -K(q + G'λ) + P⁻¹A'S⁻¹b`` with the projected inverse
   ``K = P⁻¹ - P⁻¹A'S⁻¹AP⁻¹`` (symmetric PSD).  The slacks s = h - Gx are then

       s = (G K G') λ + (h + G K q - G P⁻¹ A' S⁻¹ b),

   an LCP in the multipliers λ >= 0 with a symmetric PSD matrix — eligible
   for every method, pivoting or QP backend.  Elimination needs A of full row
   rank (S positive definite).  The work is dense: O(n³ + n m²).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from .errors import InvalidProblemError, NotConvexError, NotSymmetricError
from .matrices import MatrixStructure, as_matrix, as_vector
from .problems import LCP

if TYPE_CHECKING:
    from qpsolvers import Problem

__all__ = ["qp_to_lcp", "DualLCP", "validate_qp", "check_convex", "is_qp"]

# scipy.linalg and qpsolvers (which imports every backend it finds) are
# imported where they are used, so that `import qpcontact` stays cheap
# (tests/package/test_import_cost.py).


def is_qp(problem) -> bool:
    """Whether ``problem`` is a ``qpsolvers.Problem``, decided without
    importing qpsolvers: an instance exists only once its caller has."""
    module = sys.modules.get("qpsolvers.problem")
    return module is not None and isinstance(problem, module.Problem)


def _dense(M) -> np.ndarray:
    return M.toarray() if sp.issparse(M) else np.asarray(M)


def validate_qp(problem: Problem) -> Problem:
    """Check a ``qpsolvers.Problem`` and return a copy with float, finite data.

    Raises :class:`InvalidProblemError` naming the bad argument: shapes that do
    not match, non-finite values (infinite bounds are allowed), a matrix given
    without its vector, or lb > ub.
    """
    if not is_qp(problem):
        raise InvalidProblemError(
            f"expected an LCP or a qpsolvers.Problem; got {type(problem).__name__}"
        )
    P = as_matrix(problem.P, "P")
    n = P.shape[0]
    if P.shape != (n, n) or n == 0:
        raise InvalidProblemError(f"P must be square with at least one row; got shape {P.shape}")
    q = as_vector(problem.q, n, "q")
    parts = {}
    for mat, vec in (("G", "h"), ("A", "b")):
        Mx, v = getattr(problem, mat), getattr(problem, vec)
        if (Mx is None) != (v is None):
            raise InvalidProblemError(f"{mat} and {vec} must be given together")
        if Mx is None:
            parts[mat], parts[vec] = None, None
            continue
        Mx = as_matrix(Mx.reshape(1, -1) if isinstance(Mx, np.ndarray) and Mx.ndim == 1 else Mx, mat)
        if Mx.shape[1] != n:
            raise InvalidProblemError(f"{mat} has {Mx.shape[1]} columns but P has {n}; they must match")
        parts[mat], parts[vec] = Mx, as_vector(v, Mx.shape[0], vec)
    lb = None if problem.lb is None else as_vector(problem.lb, n, "lb", allow_inf=-1)
    ub = None if problem.ub is None else as_vector(problem.ub, n, "ub", allow_inf=+1)
    if lb is not None and ub is not None and np.any(lb > ub):
        i = int(np.argmax(lb > ub))
        raise InvalidProblemError(f"lb[{i}] = {lb[i]} exceeds ub[{i}] = {ub[i]}: the QP is infeasible as posed")
    from qpsolvers import Problem

    return Problem(P, q, parts["G"], parts["h"], parts["A"], parts["b"], lb, ub)


def check_convex(problem: Problem) -> None:
    """Refuse a QP whose objective is not convex, before any backend is trusted.

    P must be symmetric (pair by pair against its own entries, as
    :attr:`LCP.is_symmetric`) and positive semidefinite, decided on its Jacobi
    scaling by a Cholesky factorization with a rounding-level shift: dense
    LAPACK, LAPACK's banded Cholesky for sparse P of bandwidth <= 16, and SuperLU
    in symmetric mode (an LDL' whose pivots must all be positive) for other
    sparse P — one factorization, the cost of one backend iteration.

    Raises
    ------
    NotSymmetricError
        P is not symmetric.
    NotConvexError
        P is symmetric but indefinite: a backend would return a KKT point, which
        need not be the minimiser (Clarabel, ProxQP, PIQP and HiGHS all said
        "solved" at such points).
    """
    st = MatrixStructure(problem.P)
    if not st.is_symmetric:
        raise NotSymmetricError(
            f"P is not symmetric (max|P - P'| = {st.asymmetry:.3g}); the objective ½x'Px only "
            "sees its symmetric part, and backends read different triangles. Pass 0.5 * (P + P.T)."
        )
    if not st.is_psd:
        n = problem.P.shape[0]
        detail = ""
        if n <= 2000:
            P = _dense(problem.P)
            d = np.sqrt(np.abs(np.diag(P)))
            d[d == 0] = 1.0
            lam = float(np.linalg.eigvalsh(P / d[:, None] / d[None, :])[0])
            detail = f" (its Jacobi scaling has the eigenvalue {lam:.3g})"
        raise NotConvexError(
            f"P is not positive semidefinite{detail}, so the QP is nonconvex: a backend would "
            "return a point satisfying the KKT conditions that need not be the minimiser. "
            "qpcontact solves convex QPs only (a nonconvex QP's global minimum is NP-hard in "
            "general); check the sign of P — a maximisation written as a minimisation?"
        )


@dataclass
class DualLCP:
    """The dual LCP of a strictly convex QP and the map back to the QP's
    primal-dual point (see :func:`qp_to_lcp`).

    Attributes
    ----------
    lcp : LCP
        Unknowns: the multipliers of the rows ``G``, then of the finite lower
        bounds, then of the finite upper bounds, in index order.
    problem : qpsolvers.Problem
        The QP it came from.
    """

    lcp: LCP
    problem: Problem
    _P_cho: tuple
    _G: np.ndarray
    _S_cho: tuple | None
    _A: np.ndarray | None
    _b: np.ndarray | None
    _n_ineq: int
    _lower: np.ndarray
    _upper: np.ndarray

    def __repr__(self) -> str:
        n, m = self._G.shape[1], self.lcp.n
        eq = self._A.shape[0] if self._A is not None else 0
        return (f"DualLCP({m} multipliers of a QP with {n} variables and {eq} equalities "
                f"eliminated; lcp={self.lcp!r})")

    def primal_dual(self, lam) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None, np.ndarray | None]:
        """(x, y, z, z_box) in qpsolvers' conventions from the LCP unknowns λ."""
        import scipy.linalg

        lam = np.asarray(lam, dtype=float)
        n = self._G.shape[1]
        rhs = self.problem.q + self._G.T @ lam
        y = None
        if self._A is not None:
            y = -scipy.linalg.cho_solve(
                self._S_cho, self._b + self._A @ scipy.linalg.cho_solve(self._P_cho, rhs)
            )
            rhs = rhs + self._A.T @ y
        x = -scipy.linalg.cho_solve(self._P_cho, rhs)
        z = lam[: self._n_ineq] if self.problem.G is not None else None
        z_box = None
        if self.problem.lb is not None or self.problem.ub is not None:
            z_box = np.zeros(n)
            k = self._n_ineq
            z_box[self._lower] -= lam[k: k + self._lower.size]
            z_box[self._upper] += lam[k + self._lower.size:]
        return x, y, z, z_box


def qp_to_lcp(problem: Problem) -> DualLCP:
    """The dual LCP of a strictly convex QP (equalities eliminated; see the module docstring).

    Raises
    ------
    InvalidProblemError
        The QP has no inequality constraints or finite bounds (its solution is one
        linear solve, not an LCP), or its equality constraints are linearly dependent.
    NotConvexError
        P is not symmetric positive definite; use a QP backend instead.
    """
    import scipy.linalg

    problem = validate_qp(problem)
    P = _dense(problem.P)
    n = P.shape[0]
    if np.max(np.abs(P - P.T), initial=0.0) > 1e-10 * np.max(np.abs(P), initial=0.0):
        raise NotConvexError("P is not symmetric; a QP's Hessian must be. Pass 0.5 * (P + P.T).")
    P = 0.5 * (P + P.T)
    try:
        P_cho = scipy.linalg.cho_factor(P, lower=True, check_finite=False)
    except np.linalg.LinAlgError:
        raise NotConvexError(
            "P is not positive definite, so the QP has no unique dual LCP. "
            "Solve it with a QP backend (e.g. method='clarabel') instead."
        ) from None
    if np.min(np.abs(np.diag(P_cho[0]))) ** 2 <= n * np.finfo(float).eps * np.max(np.abs(P)):
        raise NotConvexError("P is numerically singular (not strictly convex); use a QP backend instead.")

    rows, rhs = [], []
    n_ineq = 0
    if problem.G is not None:
        rows.append(_dense(problem.G))
        rhs.append(problem.h)
        n_ineq = problem.G.shape[0]
    lower = np.flatnonzero(np.isfinite(problem.lb)) if problem.lb is not None else np.zeros(0, int)
    upper = np.flatnonzero(np.isfinite(problem.ub)) if problem.ub is not None else np.zeros(0, int)
    eye = np.eye(n)
    if lower.size:
        rows.append(-eye[lower])
        rhs.append(-problem.lb[lower])
    if upper.size:
        rows.append(eye[upper])
        rhs.append(problem.ub[upper])
    if not rows:
        raise InvalidProblemError(
            "the QP has no inequality constraints or finite bounds; its solution is one linear "
            "(KKT) solve, not an LCP. Solve it with a QP backend or numpy.linalg.solve."
        )
    G = np.vstack(rows)
    h = np.concatenate(rhs)

    L = np.tril(P_cho[0])  # P = L L' (cho_factor leaves garbage above the diagonal)
    W = scipy.linalg.solve_triangular(L, G.T, lower=True)  # L⁻¹G'
    u = scipy.linalg.solve_triangular(L, problem.q, lower=True)  # L⁻¹q
    M = W.T @ W
    qd = h + W.T @ u
    S_cho = A = b = None
    if problem.A is not None:
        A, b = _dense(problem.A), problem.b
        V = scipy.linalg.solve_triangular(L, A.T, lower=True)  # L⁻¹A'
        S = V.T @ V
        try:
            S_cho = scipy.linalg.cho_factor(S, lower=True, check_finite=False)
        except np.linalg.LinAlgError:
            raise InvalidProblemError(
                "the equality constraints A x = b are linearly dependent (A P⁻¹ A' is singular); "
                "remove the redundant rows of A"
            ) from None
        if np.min(np.abs(np.diag(S_cho[0]))) ** 2 <= A.shape[0] * np.finfo(float).eps * np.max(np.abs(S)):
            raise InvalidProblemError(
                "the equality constraints A x = b are (numerically) linearly dependent; remove the redundant rows of A"
            )
        C = V.T @ W  # A P⁻¹ G'
        T = scipy.linalg.cho_solve(S_cho, C)
        M = M - C.T @ T
        # G K q - G P⁻¹A'S⁻¹b, with K = P⁻¹ - P⁻¹A'S⁻¹AP⁻¹
        qd = qd - T.T @ (V.T @ u) - C.T @ scipy.linalg.cho_solve(S_cho, b)
    M = 0.5 * (M + M.T)
    return DualLCP(LCP(M, qd), problem, P_cho, G, S_cho, A, b, n_ineq, lower, upper)
