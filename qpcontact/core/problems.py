"""Problem types: the linear complementarity problem and its parametric form.

An LCP(M, q) asks for z >= 0 with w = M z + q >= 0 and z'w = 0.  In contact
mechanics z is a vector of contact forces (N) and w the matching gaps (m), or
the reverse; the library does not care about units, but its error measures
judge every component against its own data (see :mod:`qpcontact.certify`), so
badly scaled data and contacts far apart are judged fairly.

The quadratic program type is :class:`qpsolvers.Problem`; this module does not
define another.  Conversions between the two live in
:mod:`qpcontact.core.conversions`; the two LCP -> QP routes are here, as
:meth:`LCP.to_qp` and :meth:`LCP.to_monotone_qp`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from .errors import InvalidProblemError, NotConvexError, NotSymmetricError
from .matrices import MatrixStructure, as_matrix, as_vector

if TYPE_CHECKING:
    from qpsolvers import Problem

__all__ = ["LCP", "ParametricLCP", "lcp_to_qp", "monotone_lcp_to_qp"]


class _LCPBase:
    """Shared validation and structure of LCP and ParametricLCP."""

    _structure: MatrixStructure

    def _init_matrix(self, M) -> int:
        M = as_matrix(M, "M")
        n0, n1 = M.shape
        if n0 != n1:
            raise InvalidProblemError(f"M must be square; got shape {M.shape}")
        if n0 == 0:
            raise InvalidProblemError("M has no rows; an LCP needs at least one unknown")
        self._structure = MatrixStructure(M)
        return n0

    @property
    def structure(self) -> MatrixStructure:
        """M's structure, computed on first use and cached (shared by the LCPs
        of a parametric family, which all have the same M)."""
        return self._structure

    @property
    def M(self):
        """The matrix (NumPy array or SciPy CSC matrix)."""
        return self._structure.M

    @property
    def n(self) -> int:
        """Number of complementarity pairs."""
        return self.M.shape[0]

    @property
    def is_sparse(self) -> bool:
        return sp.issparse(self.M)

    @property
    def is_symmetric(self) -> bool:
        """M = M' up to :data:`SYMMETRY_RTOL` times max|M|."""
        return self._structure.is_symmetric

    @property
    def is_positive_definite(self) -> bool:
        """z'Mz > 0 for every z != 0 (Cholesky of the symmetric part; sparse-aware)."""
        return self._structure.is_positive_definite

    @property
    def is_psd(self) -> bool:
        """z'Mz >= 0 for every z, up to rounding (the LCP is then monotone)."""
        return self._structure.is_psd

    @property
    def matrix_scale(self) -> float:
        """max |M_ij|."""
        return self._structure.scale

    def _kind(self) -> str:
        sym = "symmetric" if self.is_symmetric else "nonsymmetric"
        storage = f"sparse nnz={self.M.nnz}" if self.is_sparse else "dense"
        return f"n={self.n}, {storage}, {sym}"


class LCP(_LCPBase):
    """Linear complementarity problem: find z >= 0 with w = M z + q >= 0, z'w = 0.

    Parameters
    ----------
    M : (n, n) array_like or scipy.sparse matrix
        Real, finite.  Kept sparse (CSC) when given sparse.
    q : (n,) array_like
        Real, finite.
    q_terms : (n,) array_like, optional
        When q was computed as a sum (q = q0 + p q1, gaps plus velocity terms),
        the sum of the magnitudes of its terms, ``>= |q|``.  The certificate
        judges row i against ``|q_terms_i| + (|M||z|)_i``, so a q_i that
        cancelled to rounding noise is not judged against the noise.  Default
        ``|q|``.
    hierarchy : sequence of (n_l, n_(l+1)) matrices, optional
        Coarse levels of the mesh M comes from, as prolongations finest first
        (:func:`qpcontact.core.hierarchy.as_hierarchy`): the multilevel method
        ``"mg-bpp"`` uses them instead of building its own by aggregation.
        They only decide how fast the contact set is found, never the answer.

    Raises
    ------
    InvalidProblemError
        When M is not square, q does not match M, a value is complex or not
        finite (the message gives the first bad index), n = 0, or a hierarchy
        does not match M (the message names the level).

    Notes
    -----
    Structure (``is_symmetric``, ``is_positive_definite``, ``is_psd``) is
    computed on first use and cached.  The object holds plain arrays and pickles.
    """

    def __init__(self, M, q, *, q_terms=None, hierarchy=None):
        n = self._init_matrix(M)
        self.q = as_vector(q, n, "q")
        self.q_terms = np.abs(self.q) if q_terms is None else np.abs(as_vector(q_terms, n, "q_terms"))
        if hierarchy is not None:
            self._structure.declare_hierarchy(hierarchy)

    @classmethod
    def with_structure(cls, structure: MatrixStructure, q: np.ndarray,
                       q_terms: np.ndarray | None = None) -> "LCP":
        """An LCP on the matrix of ``structure`` (an ``LCP.structure``) and an
        already validated float vector q, sharing the cached structure: a time
        stepper meets the same M with a new q every step."""
        obj = cls.__new__(cls)
        obj._structure = structure
        obj.q = q
        obj.q_terms = np.abs(q) if q_terms is None else q_terms
        return obj

    def w(self, z) -> np.ndarray:
        """w = M z + q."""
        return np.asarray(self.M @ z).ravel() + self.q

    def to_qp(self):
        """The QP min ½ z'Mz + q'z subject to z >= 0 (M symmetric PSD).

        Its minimisers are exactly the LCP's solutions; the multipliers of the
        bounds are -w in qpsolvers' sign convention (``z_box = -w``).

        Raises
        ------
        NotSymmetricError
            M is not symmetric: use a pivoting method such as ``"lemke"``, or
            :meth:`to_monotone_qp` when M + M' is positive semidefinite.
        NotConvexError
            M is symmetric but indefinite: the QP would be nonconvex.
        """
        return lcp_to_qp(self)

    def to_monotone_qp(self):
        """The QP min z'(Mz + q) subject to Mz + q >= 0, z >= 0 (M + M' PSD).

        For a monotone LCP its optimal value is 0 exactly at the LCP's solutions.
        """
        return monotone_lcp_to_qp(self)

    def __repr__(self) -> str:
        return f"LCP({self._kind()})"

    def __getstate__(self):
        return {"M": self.M, "q": self.q, "q_terms": self.q_terms,
                "hierarchy": self._structure.hierarchy}

    def __setstate__(self, state):
        self._structure = MatrixStructure(state["M"])
        self.q = state["q"]
        self.q_terms = state.get("q_terms", np.abs(self.q))
        if state.get("hierarchy") is not None:
            self._structure.declare_hierarchy(state["hierarchy"])


class ParametricLCP(_LCPBase):
    """The increasing-load LCP family: q(p) = q0 + p q1, p >= 0.

    Parameters
    ----------
    M : (n, n) array_like or scipy.sparse matrix
    q0 : (n,) array_like
        Constant part of the load vector.
    q1 : (n,) array_like
        Variable part, scaled by the load parameter p.

    Raises
    ------
    InvalidProblemError
        As for :class:`LCP`, for each of M, q0 and q1.
    """

    def __init__(self, M, q0, q1):
        n = self._init_matrix(M)
        self.q0 = as_vector(q0, n, "q0")
        self.q1 = as_vector(q1, n, "q1")

    def q(self, p: float) -> np.ndarray:
        """q(p) = q0 + p q1."""
        return self.q0 + float(p) * self.q1

    def at(self, p: float) -> LCP:
        """The LCP at load parameter p (shares M and its cached structure; its
        ``q_terms`` are ``|q0| + |p q1|``, the parametric data's own sizes)."""
        p = float(p)
        if not np.isfinite(p):
            raise InvalidProblemError(f"load parameter p must be finite; got {p}")
        return LCP.with_structure(self._structure, self.q(p),
                                   np.abs(self.q0) + abs(p) * np.abs(self.q1))

    def __repr__(self) -> str:
        return f"ParametricLCP({self._kind()})"

    def __getstate__(self):
        return {"M": self.M, "q0": self.q0, "q1": self.q1}

    def __setstate__(self, state):
        self._structure = MatrixStructure(state["M"])
        self.q0, self.q1 = state["q0"], state["q1"]


def lcp_to_qp(lcp: LCP) -> Problem:
    """``min ½ z'Mz + q'z, z >= 0`` for a symmetric PSD LCP (see the module docstring)."""
    if not lcp.is_symmetric:
        raise NotSymmetricError(
            f"M is not symmetric (max|M - M'| = {lcp.structure.asymmetry:.3g}, "
            f"max|M| = {lcp.matrix_scale:.3g}), so the LCP is not the optimality "
            "condition of a QP. Use a pivoting method such as 'lemke' for any M, or "
            "LCP.to_monotone_qp() when M + M' is positive semidefinite."
        )
    if not lcp.is_psd:
        raise NotConvexError(
            "M is symmetric but not positive semidefinite, so the QP min ½z'Mz + q'z, z >= 0 "
            "is nonconvex and QP backends may return local minima. Use a pivoting method "
            "such as 'lemke'."
        )
    from qpsolvers import Problem

    P = lcp.structure.symmetric_part  # drops rounding-level asymmetry
    return Problem(P, lcp.q.copy(), lb=np.zeros(lcp.n))


def monotone_lcp_to_qp(lcp: LCP) -> Problem:
    """``min z'(Mz + q), Mz + q >= 0, z >= 0`` for M + M' PSD (see the module docstring)."""
    if not lcp.is_psd:
        raise NotConvexError(
            "M + M' is not positive semidefinite, so the LCP is not monotone and no convex "
            "QP has its solutions as minimisers. Use a pivoting method such as 'lemke'."
        )
    from qpsolvers import Problem

    M = lcp.M
    P = 2.0 * lcp.structure.symmetric_part
    return Problem(P, lcp.q.copy(), G=-M, h=lcp.q.copy(), lb=np.zeros(lcp.n))
