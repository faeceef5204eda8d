"""Matrix and vector data: validated on the way in, their structure computed once.

:func:`as_matrix` and :func:`as_vector` turn what a user passes into float
arrays or CSC matrices, or raise :class:`~qpcontact.core.errors.InvalidProblemError`
naming the first bad entry.  :class:`MatrixStructure` computes on first use,
and caches, what the dispatcher and the methods ask of a square matrix:
symmetry (each pair against its own size), definiteness (on the Jacobi scaling,
so that no row's size decides for another's), bandwidth, band storage.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np
import scipy.sparse as sp

from .errors import InvalidProblemError

__all__ = ["MatrixStructure", "SYMMETRY_RTOL", "EXACT_PD_MAX_N", "as_matrix", "as_vector", "bandwidth"]


#: Relative tolerance of :attr:`LCP.is_symmetric`: |M_ij - M_ji| <= SYMMETRY_RTOL *
#: max(sqrt|M_ii M_jj|, |M_ij|, |M_ji|) for every pair (each against its own size).
#: Assembly in floating point (A = J G^-1 J') leaves asymmetry of order n * 1e-16;
#: anything above 1e-10 is a modelling fact, not rounding.
SYMMETRY_RTOL = 1e-10

#: largest n whose exact positive definiteness is tested (one dense Cholesky,
#: 0.1 s at 2 000)
EXACT_PD_MAX_N = 2000


def _first_bad_index(mask: np.ndarray) -> tuple[int, ...]:
    return tuple(int(i) for i in np.argwhere(mask)[0])


def _as_array(x, name: str, what: str) -> np.ndarray:
    """np.asarray, with NumPy's complaint about ragged nesting turned into ours."""
    try:
        return np.asarray(x)
    except (ValueError, TypeError) as exc:
        raise InvalidProblemError(
            f"{name} cannot be read as a {what}: {exc.__class__.__name__} from NumPy "
            "(rows of different lengths?); give a rectangular array of numbers"
        ) from None


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
    arr = _as_array(M, name, "matrix")
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
    arr = _as_array(v, name, "vector")
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


def _major(M) -> np.ndarray:
    """The column (CSC) or row (CSR) of each stored entry of a compressed M."""
    return np.repeat(np.arange(len(M.indptr) - 1), np.diff(M.indptr))


def bandwidth(M) -> int:
    """max |i - j| over the stored nonzeros of a matrix (dense or sparse)."""
    if sp.issparse(M) and M.format in ("csr", "csc"):
        # read off the compressed index arrays: no COO copy (a time stepper
        # meets a new matrix every step)
        if not M.nnz:
            return 0
        if M.has_sorted_indices:
            # the farthest entry of a sorted column (row) is its first or its
            # last: O(n), not O(nnz) (a plate of 10⁴ nodes: 0.48 -> 0.05 ms)
            j = np.flatnonzero(np.diff(M.indptr) > 0)
            first, last = M.indices[M.indptr[j]], M.indices[M.indptr[j + 1] - 1]
            return int(max(np.max(j - first), np.max(last - j)))
        return int(np.max(np.abs(M.indices - _major(M))))
    C = sp.coo_matrix(M)
    return int(np.max(np.abs(C.row - C.col))) if C.nnz else 0


def _ratio_or_inf(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    """num / den elementwise with 0/0 = 0 and x/0 = inf."""
    out = np.zeros(np.shape(num))
    pos = den > 0
    np.divide(num, den, out=out, where=pos)
    out[~pos & (num != 0)] = np.inf
    return out


def _max_abs(M) -> float:
    if sp.issparse(M):
        return float(abs(M).max()) if M.nnz else 0.0
    # two reductions and no |M| copy (n = 3 000 dense: 0.3 s -> 0.02 s)
    return max(float(np.max(M)), -float(np.min(M))) if M.size else 0.0


def _diagonally_dominant(A, strict: bool) -> bool:
    """Whether Gershgorin proves the symmetric, unit-diagonal sparse A
    positive semidefinite (every row's off-diagonal |a_ij| summing to at
    most 1) or, with ``strict``, definite: also, in every connected
    component of A's graph, a row whose sum is below 1 — an irreducibly
    diagonally dominant block is nonsingular (Taussky 1949), and a
    nonsingular PSD matrix is PD.  A membrane's stiffness (rows 4, −1 x 4;
    the boundary rows strictly dominant) passes in O(nnz): the factorization
    it saves cost more than the solve (n = 1e5).  The sums are compared as
    computed, to rounding like the factorization's pivot test."""
    C = sp.coo_matrix(A)
    off = C.row != C.col
    sums = np.bincount(C.row[off], weights=np.abs(C.data[off]), minlength=A.shape[0])
    if not np.all(sums <= 1.0):
        return False
    if not strict:
        return True
    below = sums < 1.0 - 64 * np.finfo(float).eps
    if below.all():
        return True
    from scipy.sparse.csgraph import connected_components

    count, label = connected_components(sp.csr_matrix((np.ones(int(off.sum())),
                                                       (C.row[off], C.col[off])),
                                                      shape=A.shape), directed=False)
    return bool(np.all(np.bincount(label[below], minlength=count) > 0))


class MatrixStructure:
    """Lazily computed, cached structure of a square matrix (shared by the LCPs
    of a parametric family, which all have the same M)."""

    def __init__(self, M):
        self.M = M

    @cached_property
    def scale(self) -> float:
        """max|M| (of a sparse M read off |M|, which its scales keep anyway)."""
        if sp.issparse(self.M):
            A = self.abs_matrix
            return float(A.data.max()) if A.nnz else 0.0
        return _max_abs(self.M)

    @cached_property
    def asymmetry(self) -> float:
        """max|M - M'| (absolute; for messages)."""
        return _max_abs(self.M - self.M.T)

    @cached_property
    def relative_asymmetry(self) -> float:
        """max over pairs of |M_ij - M_ji| / max(sqrt|M_ii M_jj|, |M_ij|, |M_ji|).

        Each pair is judged against its own size, never against max|M|: a
        coupling of 1e-8 in a row whose only other entry is 0 is not rounding
        beside a 1e300 elsewhere.  The scale sqrt|M_ii M_jj| (what bounds an
        entry of a PSD matrix) keeps assembly noise at a true zero (1e-17
        against -1e-17) symmetric.  Invariant under symmetric scaling D M D.
        """
        M = self.M
        n = M.shape[0]
        d = np.sqrt(np.abs(np.asarray(M.diagonal(), dtype=float)))
        if sp.issparse(M):
            A = sp.coo_matrix(M - M.T)
            A.eliminate_zeros()
            if A.nnz == 0:
                return 0.0
            r, c = A.row, A.col
            absM = abs(M).tocsr()
            mij = np.asarray(absM[r, c]).ravel()
            mji = np.asarray(absM[c, r]).ravel()
            scale = np.maximum(d[r] * d[c], np.maximum(mij, mji))
            return float(np.max(_ratio_or_inf(np.abs(A.data), scale)))
        if self._exactly_symmetric:
            return 0.0          # the common case, in one pass (n = 3 000: 0.8 s -> 0.03 s)
        worst = 0.0
        step = max(1, (1 << 22) // max(n, 1))
        for start in range(0, n, step):
            rows = slice(start, start + step)
            A, B = M[rows, :], M[:, rows].T
            scale = np.maximum(np.outer(d[rows], d), np.maximum(np.abs(A), np.abs(B)))
            worst = max(worst, float(np.max(_ratio_or_inf(np.abs(A - B), scale))))
        return worst

    @cached_property
    def _exactly_symmetric(self) -> bool:
        """A dense M equal to its transpose bit for bit (one pass, asked by
        the symmetry measure and the symmetric part alike)."""
        return bool(np.array_equal(self.M, self.M.T))

    @cached_property
    def is_symmetric(self) -> bool:
        return self.relative_asymmetry <= SYMMETRY_RTOL

    @cached_property
    def symmetric_part(self):
        """(M + M')/2 — a copy of a dense M where it is exactly symmetric (the
        sum's three n x n arrays took 0.6 s at n = 3 000; a copy, because
        callers scale what they get in place)."""
        if not sp.issparse(self.M) and self._exactly_symmetric:
            # asked of the data, not of relative_asymmetry: a declared SPD
            # matrix (declare_spd) reads 0 there without being symmetric bit for bit
            return self.M.copy()
        S = 0.5 * self.M + 0.5 * self.M.T  # halves first: no overflow near 1e308
        return sp.csc_matrix(S) if sp.issparse(S) else S

    def _definite(self, semi: bool) -> bool:
        """Whether the symmetric part S is positive definite (semi=False) or
        semidefinite (semi=True), decided on its Jacobi scaling D S D
        (D = diag(S)^-1/2) so that no row's size decides for another's.

        Rows with S_ii = 0 must be zero for S to be PSD (|S_ij|² <= S_ii S_jj),
        up to the cancellation noise of forming S; they are then dropped.  The
        remaining unit-diagonal block passes when its Cholesky factor (of the
        block plus 10 n eps I for semi=True) has squared pivots above n eps.
        """
        import scipy.linalg
        import scipy.linalg.lapack
        import scipy.sparse.linalg as spla

        S = self.symmetric_part
        n = S.shape[0]
        eps = np.finfo(float).eps
        diag = np.asarray(S.diagonal(), dtype=float)
        if np.any(diag < 0):
            return False
        pos = diag > 0
        if not pos.all():
            if not semi:
                return False
            zero = np.flatnonzero(~pos)
            if sp.issparse(S):
                Z = abs(S[zero]).toarray() if zero.size else np.zeros((0, n))
                noise = 1e3 * eps * abs(self.M[zero]).maximum(abs(self.M.T[zero])).toarray()
            else:
                Z = np.abs(S[zero])
                noise = 1e3 * eps * np.maximum(np.abs(self.M[zero]), np.abs(self.M.T[zero]))
            if np.any(Z > noise):
                return False
            keep = np.flatnonzero(pos)
            if keep.size == 0:
                return True
            S = S[keep][:, keep] if sp.issparse(S) else S[np.ix_(keep, keep)]
            diag = diag[keep]
        m = S.shape[0]
        dsc = 1.0 / np.sqrt(diag)
        floor = m * eps
        shift = 10.0 * m * eps if semi else 0.0
        if sp.issparse(S):
            D = sp.diags(dsc)
            with np.errstate(over="ignore", invalid="ignore"):
                A = (D @ S @ D + shift * sp.identity(m)).tocsc()
            if not np.all(np.isfinite(A.data)):
                return False
            if _diagonally_dominant(A, strict=not semi):
                return True
            if m > 64 and bandwidth(A) <= 16:  # banded: LAPACK's banded Cholesky, O(n b²)
                b = bandwidth(A)
                C = sp.coo_matrix(A)
                up = C.row <= C.col
                ab = np.zeros((b + 1, m))
                ab[b + C.row[up] - C.col[up], C.col[up]] = C.data[up]
                c, info = scipy.linalg.lapack.dpbtrf(ab, lower=0)
                return info == 0 and bool(np.all(c[b] ** 2 > floor))
            # SuperLU in symmetric mode with no threshold pivoting picks the
            # diagonal: an LDL' in disguise.  All pivots positive and no row
            # exchange <=> positive definite (Sylvester on the permuted matrix).
            try:
                lu = spla.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                               options={"SymmetricMode": True})
            except RuntimeError:  # exactly singular
                return False
            if not np.array_equal(lu.perm_r, lu.perm_c):
                return False
            return bool(np.all(lu.U.diagonal() > floor))
        # A = D S D (A_ij = (S_ij d_i) d_j) written transposed in C order, so
        # that its transpose is A in Fortran order: LAPACK's lower Cholesky
        # factors it in place, the same entries and operations as
        # scipy.linalg.cholesky(A, lower=True), which copied A to Fortran
        # order first (n = 3 000: a third of the check)
        with np.errstate(over="ignore", invalid="ignore"):
            C = np.multiply(S.T, dsc[None, :], order="C")
            C *= dsc[:, None]
        A = C.T
        if shift:
            A[np.diag_indices(m)] += shift
        if not np.all(np.isfinite(A)):  # a scaled entry beyond 1e308: |S_ij|² > S_ii S_jj
            return False
        c, info = scipy.linalg.lapack.dpotrf(A, lower=1, clean=0, overwrite_a=1)
        return info == 0 and bool(np.all(np.diag(c) ** 2 > floor))

    def declare_spd(self) -> None:
        """Record that M is symmetric positive definite *by construction* (a
        formulation that proves it, e.g. the drum's A = C + G'H⁻¹G), so the
        checks are not recomputed for every assembled matrix."""
        self.__dict__.update(is_symmetric=True, is_positive_definite=True, is_psd=True,
                             asymmetry=0.0, relative_asymmetry=0.0)

    #: Prolongations of the mesh hierarchy M comes from (finest first), or None.
    hierarchy = None
    #: The hierarchy "mg-bpp" built by aggregation when none was given, kept
    #: for the next LCP on this M (a time stepper's).
    aggregated_hierarchy = None
    #: What "mg-bpp" built of M and its hierarchy alone (Galerkin products,
    #: packed levels), kept for the next LCP on this M; used only where it
    #: still fits M entry for entry (solvers.pivoting.multigrid.MultilevelSetup).
    multilevel_setup = None

    def declare_hierarchy(self, prolongations) -> None:
        """Record the coarse levels of the mesh M comes from (validated by
        :func:`qpcontact.core.hierarchy.as_hierarchy`; the LCPs sharing this
        structure — a time stepper's — share them)."""
        from .hierarchy import as_hierarchy

        self.hierarchy = as_hierarchy(prolongations, self.M.shape[0])

    @cached_property
    def is_z_matrix(self) -> bool:
        """Every off-diagonal entry <= 0 (a Z-matrix; symmetric positive
        definite ones are Stieltjes matrices, the M-matrices of meshes: a
        membrane's stiffness, not a plate's)."""
        M = self.M
        if sp.issparse(M):
            if M.format in ("csr", "csc"):    # the stored arrays: no COO copy
                return bool(np.all(M.data[M.indices != _major(M)] <= 0))
            C = sp.coo_matrix(M)
            return bool(np.all(C.data[C.row != C.col] <= 0))
        off = M - np.diag(np.diag(M))
        return bool(np.all(off <= 0))

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
            S = sp.csc_matrix(self.M if self.is_symmetric else self.symmetric_part)
            ab = np.zeros((b + 1, S.shape[0]))
            for k in range(b + 1):   # superdiagonal k: ab[b - k, j] = S[j - k, j]
                ab[b - k, k:] = S.diagonal(k)
            self._bands = ab
        return self._bands

    _bands = None

    @cached_property
    def is_positive_definite(self) -> bool:
        # z'Mz > 0 for all z != 0 depends on the symmetric part only.
        return self._definite(semi=False)

    @cached_property
    def is_psd(self) -> bool:
        return self.scale == 0.0 or self.is_positive_definite or self._definite(semi=True)

    @cached_property
    def abs_matrix(self):
        """|M| (CSC when M is sparse), for the componentwise scales: a time
        stepper's LCPs share this structure, and forming |M| anew at every
        certificate and every pivoting run was a sixth of a drum step."""
        return abs(self.M).tocsc() if sp.issparse(self.M) else np.abs(self.M)

    @cached_property
    def abs_row_sums(self) -> np.ndarray:
        """‖M_i‖₁ per row (the row sums of :attr:`abs_matrix`)."""
        A = self.abs_matrix
        if sp.issparse(A):
            # the sums of SciPy's product with ones, in the same order (each
            # row's terms as stored, column by column), without its checks
            return np.bincount(A.indices, weights=A.data, minlength=A.shape[0])
        return np.asarray(A.sum(axis=1)).ravel()

    @cached_property
    def is_positive_definite_exactly(self) -> bool:
        """Whether the symmetric part of M *as stored* is positive definite in
        exact arithmetic, not only to rounding — then z'Mz > 0 for every z != 0,
        LCP(M, q) has a solution for every q, and no Farkas vector exists
        (y >= 0, M'y <= 0 would give y'My <= 0).  False means "not shown"
        (also above EXACT_PD_MAX_N: one dense Cholesky).

        Rump's test (BIT 46, 2006): A = D S D (D = diag(S)^-1/2, which changes
        no sign of z'Sz) is formed and factored in floating point after its
        diagonal is lowered by α = 2 n (n + 6) eps.  If that Cholesky runs
        through, L L' = A - αI + E with ‖E‖₂ <= n γ_{n+1} (each row of L has
        norm <= 1 + O(eps)), and forming S and A put at most 5 n eps in
        2-norm on top: so λ_min(D S D) >= α - n (n + 6) eps > 0 for the
        exact D S D of the stored data."""
        n = self.M.shape[0]
        if n == 0 or n > EXACT_PD_MAX_N or not self.is_positive_definite:
            return False
        import scipy.linalg

        S = self.symmetric_part
        S = S.toarray() if sp.issparse(S) else np.asarray(S, dtype=float)
        diag = np.diag(S).copy()
        if not np.all(diag > 0) or not np.all(np.isfinite(S)):
            return False
        d = 1.0 / np.sqrt(diag)
        with np.errstate(over="ignore", invalid="ignore", under="ignore"):
            A = (S * d[:, None]) * d[None, :]
        alpha = 2.0 * n * (n + 6) * np.finfo(float).eps
        if not (np.all(np.isfinite(A)) and alpha < 0.5):
            return False
        A[np.diag_indices(n)] -= alpha
        try:
            scipy.linalg.cholesky(A, lower=True, overwrite_a=True, check_finite=False)
        except np.linalg.LinAlgError:
            return False
        return True
