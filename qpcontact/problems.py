"""Problem types: the linear complementarity problem and its parametric form.

An LCP(M, q) asks for z >= 0 with w = M z + q >= 0 and z'w = 0.  In contact
mechanics z is a vector of contact forces (N) and w the matching gaps (m), or
the reverse; the library does not care about units, but its error measures are
scale-free (see :mod:`qpcontact.certify`) so that badly scaled data are judged
fairly.

The quadratic program type is :class:`qpsolvers.Problem`; this module does not
define another.  Conversions between the two live in
:mod:`qpcontact.conversions` and are reachable as :meth:`LCP.to_qp` and
:meth:`LCP.to_monotone_qp`.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np
import scipy.linalg
import scipy.linalg.lapack
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .errors import InvalidProblemError

__all__ = ["LCP", "ParametricLCP", "SYMMETRY_RTOL", "as_matrix", "as_vector", "bandwidth"]

#: Relative tolerance of :attr:`LCP.is_symmetric`: max|M - M'| <= SYMMETRY_RTOL * max|M|.
#: Assembly in floating point (A = J G^-1 J') leaves asymmetry of order n * 1e-16;
#: anything above 1e-10 is a modelling fact, not rounding.
SYMMETRY_RTOL = 1e-10


def _first_bad_index(mask: np.ndarray) -> tuple[int, ...]:
    return tuple(int(i) for i in np.argwhere(mask)[0])


def as_matrix(M, name: str = "M") -> np.ndarray | sp.csc_matrix:
    """Validate a matrix argument and return it as a float array or CSC matrix.

    Raises :class:`InvalidProblemError` naming ``name`` when the matrix is not
    2-D, not real, or holds a NaN or an infinity (the message gives the first bad
    index).
    """
    if sp.issparse(M):
        if M.ndim != 2:
            raise InvalidProblemError(f"{name} must be 2-D; got a sparse array of shape {M.shape}")
        if np.iscomplexobj(M.data):
            raise InvalidProblemError(f"{name} has complex entries; LCP and QP data must be real")
        try:
            out = sp.csc_matrix(M, dtype=float)
        except (TypeError, ValueError) as exc:
            raise InvalidProblemError(f"{name} cannot be read as a real sparse matrix: {exc}") from None
        out.sum_duplicates()
        bad = ~np.isfinite(out.data)
        if bad.any():
            coo = out.tocoo()
            k = int(np.argmax(~np.isfinite(coo.data)))
            raise InvalidProblemError(
                f"{name} has a non-finite entry {coo.data[k]} at index ({coo.row[k]}, {coo.col[k]}); "
                "replace it with a finite number"
            )
        return out
    arr = np.asarray(M)
    if np.iscomplexobj(arr):
        raise InvalidProblemError(f"{name} has complex entries; LCP and QP data must be real")
    if arr.dtype == object or not (np.issubdtype(arr.dtype, np.number) or arr.dtype == bool):
        raise InvalidProblemError(f"{name} must hold real numbers; got dtype {arr.dtype}")
    if arr.ndim != 2:
        raise InvalidProblemError(f"{name} must be a 2-D matrix; got shape {arr.shape}")
    arr = np.array(arr, dtype=float)
    bad = ~np.isfinite(arr)
    if bad.any():
        idx = _first_bad_index(bad)
        raise InvalidProblemError(
            f"{name} has a non-finite entry {arr[idx]} at index {idx}; replace it with a finite number"
        )
    return arr


def as_vector(v, n: int | None, name: str, allow_inf: int = 0) -> np.ndarray:
    """Validate a vector argument of length ``n`` (any length if ``n`` is None).

    A column or row matrix of the right size is flattened.  ``allow_inf`` is
    -1 to accept -inf (lower bounds), +1 to accept +inf (upper bounds), 0 for
    neither.
    """
    if sp.issparse(v):
        v = v.toarray()
    arr = np.asarray(v)
    if np.iscomplexobj(arr):
        raise InvalidProblemError(f"{name} has complex entries; problem data must be real")
    if arr.dtype == object or not (np.issubdtype(arr.dtype, np.number) or arr.dtype == bool):
        raise InvalidProblemError(f"{name} must hold real numbers; got dtype {arr.dtype}")
    if arr.ndim == 2 and 1 in arr.shape:
        arr = arr.ravel()
    if arr.ndim != 1:
        raise InvalidProblemError(f"{name} must be a vector; got shape {arr.shape}")
    if n is not None and arr.shape[0] != n:
        raise InvalidProblemError(f"{name} has length {arr.shape[0]} but the matrix has {n} rows; they must match")
    arr = np.array(arr, dtype=float)
    bad = np.isnan(arr)
    if allow_inf >= 0:
        bad |= arr == -np.inf
    if allow_inf <= 0:
        bad |= arr == np.inf
    if bad.any():
        i = int(np.argmax(bad))
        raise InvalidProblemError(f"{name} has a non-finite entry {arr[i]} at index {i}; replace it with a finite number")
    return arr


def bandwidth(M) -> int:
    """max |i - j| over the stored nonzeros of a matrix (dense or sparse)."""
    C = sp.coo_matrix(M)
    return int(np.max(np.abs(C.row - C.col))) if C.nnz else 0


def _max_abs(M) -> float:
    if sp.issparse(M):
        return float(abs(M).max()) if M.nnz else 0.0
    return float(np.max(np.abs(M))) if M.size else 0.0


class _MatrixStructure:
    """Lazily computed, cached structure of a square matrix (shared by the LCPs
    of a parametric family, which all have the same M)."""

    def __init__(self, M):
        self.M = M

    @cached_property
    def scale(self) -> float:
        return _max_abs(self.M)

    @cached_property
    def asymmetry(self) -> float:
        """max|M - M'| (absolute)."""
        return _max_abs(self.M - self.M.T)

    @cached_property
    def is_symmetric(self) -> bool:
        return self.asymmetry <= SYMMETRY_RTOL * self.scale

    @cached_property
    def symmetric_part(self):
        S = 0.5 * (self.M + self.M.T)
        return sp.csc_matrix(S) if sp.issparse(S) else S

    def _cholesky_ok(self, shift: float) -> bool:
        """Whether the symmetric part plus ``shift`` I has a Cholesky factor whose
        squared pivots all exceed a rounding floor (n eps max|S|)."""
        S = self.symmetric_part
        n = S.shape[0]
        floor = n * np.finfo(float).eps * max(self.scale, np.finfo(float).tiny)
        if sp.issparse(S):
            # SuperLU in symmetric mode with no threshold pivoting picks the
            # diagonal: an LDL' in disguise.  All pivots positive and no row
            # exchange <=> positive definite (Sylvester on the permuted matrix).
            A = (S + shift * sp.identity(n, format="csc")).tocsc()
            try:
                lu = spla.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                               options={"SymmetricMode": True})
            except RuntimeError:  # exactly singular
                return False
            if not np.array_equal(lu.perm_r, lu.perm_c):
                return False
            return bool(np.all(lu.U.diagonal() > floor))
        try:
            L = scipy.linalg.cholesky(S + shift * np.eye(n), lower=True, check_finite=False)
        except np.linalg.LinAlgError:
            return False
        return bool(np.all(np.diag(L) ** 2 > floor))

    def declare_spd(self) -> None:
        """Record that M is symmetric positive definite *by construction* (a
        formulation that proves it, e.g. the drum's A = C + G'H⁻¹G), so the
        checks are not recomputed for every assembled matrix."""
        self.__dict__.update(is_symmetric=True, is_positive_definite=True, is_psd=True,
                             asymmetry=0.0)

    @cached_property
    def upper(self):
        """Upper triangle of a sparse M (CSC), what sparse LDL' codes take."""
        return sp.triu(self.M, format="csc") if sp.issparse(self.M) else None

    @cached_property
    def bandwidth(self) -> int:
        return bandwidth(self.M)

    def upper_bands(self, max_bandwidth: int):
        """LAPACK upper band storage of the symmetric part, ab[b + i - j, j] = S_ij
        (i <= j), when the bandwidth b is at most ``max_bandwidth``; else None."""
        b = self.bandwidth
        if b > max_bandwidth:
            return None
        if self._bands is None:
            S = sp.coo_matrix(self.M if self.is_symmetric else self.symmetric_part)
            up = S.row <= S.col
            ab = np.zeros((b + 1, S.shape[0]))
            ab[b + S.row[up] - S.col[up], S.col[up]] = S.data[up]
            self._bands = ab
        return self._bands

    _bands = None

    @cached_property
    def is_positive_definite(self) -> bool:
        # z'Mz > 0 for all z != 0 depends on the symmetric part only.
        if sp.issparse(self.M) and self.M.shape[0] > 64:
            ab = self.upper_bands(16)
            if ab is not None:  # banded: LAPACK's banded Cholesky, O(n b²)
                _, info = scipy.linalg.lapack.dpbtrf(ab, lower=0)
                return info == 0
        return self._cholesky_ok(0.0)

    @cached_property
    def is_psd(self) -> bool:
        if self.is_positive_definite:
            return True
        if self.scale == 0.0:
            return True
        # A PSD matrix shifted by a little more than Cholesky's rounding error is PD.
        n = self.M.shape[0]
        return self._cholesky_ok(10.0 * n * np.finfo(float).eps * self.scale)


class _LCPBase:
    """Shared validation and structure of LCP and ParametricLCP."""

    _structure: _MatrixStructure

    def _init_matrix(self, M) -> int:
        M = as_matrix(M, "M")
        n0, n1 = M.shape
        if n0 != n1:
            raise InvalidProblemError(f"M must be square; got shape {M.shape}")
        if n0 == 0:
            raise InvalidProblemError("M has no rows; an LCP needs at least one unknown")
        self._structure = _MatrixStructure(M)
        return n0

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

    Raises
    ------
    InvalidProblemError
        When M is not square, q does not match M, a value is complex or not
        finite (the message gives the first bad index), or n = 0.

    Notes
    -----
    Structure (``is_symmetric``, ``is_positive_definite``, ``is_psd``) is
    computed on first use and cached.  The object holds plain arrays and pickles.
    """

    def __init__(self, M, q):
        n = self._init_matrix(M)
        self.q = as_vector(q, n, "q")

    @classmethod
    def _with_structure(cls, structure: _MatrixStructure, q: np.ndarray) -> "LCP":
        obj = cls.__new__(cls)
        obj._structure = structure
        obj.q = q
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
        from .conversions import lcp_to_qp

        return lcp_to_qp(self)

    def to_monotone_qp(self):
        """The QP min z'(Mz + q) subject to Mz + q >= 0, z >= 0 (M + M' PSD).

        For a monotone LCP its optimal value is 0 exactly at the LCP's solutions.
        """
        from .conversions import monotone_lcp_to_qp

        return monotone_lcp_to_qp(self)

    def __repr__(self) -> str:
        return f"LCP({self._kind()})"

    def __getstate__(self):
        return {"M": self.M, "q": self.q}

    def __setstate__(self, state):
        self._structure = _MatrixStructure(state["M"])
        self.q = state["q"]


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
        """The LCP at load parameter p (shares M and its cached structure)."""
        p = float(p)
        if not np.isfinite(p):
            raise InvalidProblemError(f"load parameter p must be finite; got {p}")
        return LCP._with_structure(self._structure, self.q(p))

    def __repr__(self) -> str:
        return f"ParametricLCP({self._kind()})"

    def __getstate__(self):
        return {"M": self.M, "q0": self.q0, "q1": self.q1}

    def __setstate__(self, state):
        self._structure = _MatrixStructure(state["M"])
        self.q0, self.q1 = state["q0"], state["q1"]
