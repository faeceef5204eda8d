"""Componentwise scales: each row and each unknown of a problem judged on its own size.

The certificates (:mod:`qpcontact.judge.lcp_certificate`, :mod:`qpcontact.judge.qp_certificate`) and
the pivoting methods' sign tests share these scales, in the sense of Oettli
and Prager: a row is measured against the sizes of the terms it is made of,
an unknown against the change that moves some row by all of that row's own
size.  docs/certificates.md derives them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["ComponentScales", "Rows", "componentwise_scales", "row_scales", "column_influence",
           "column_max_ratio", "ratio", "divide", "inf_norm", "max_abs", "abs_matvec", "safe_norm2",
           "row_rounding"]

_EPS = np.finfo(float).eps


_DENSE_CHUNK = 1 << 22  # entries of |M| / σ formed at a time for dense matrices


def ratio(num: float, den: float) -> float:
    """num / den, with 0/0 = 0 and x/0 = inf."""
    if num == 0.0:
        return 0.0
    return num / den if den > 0.0 else np.inf


def divide(v: np.ndarray, scale) -> np.ndarray:
    """v / scale elementwise (scale a number or an array), with 0/0 = 0 and
    x/0 = ±inf: a component whose scale is zero must itself be exactly zero."""
    v = np.asarray(v, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        out = v / scale
    nan = np.isnan(out)
    if nan.any():
        # 0/0 is a component that is exactly zero at a zero scale: no error
        out[nan & np.broadcast_to(v == 0, out.shape)] = 0.0
    return out


def inf_norm(v) -> float:
    return float(np.max(np.abs(v))) if np.size(v) else 0.0


def max_abs(M) -> float:
    if sp.issparse(M):
        return float(abs(M).max()) if M.nnz else 0.0
    return float(np.max(np.abs(M))) if M.size else 0.0


def row_rounding(M) -> float:
    """(row nonzeros + 1) eps: the rounding of evaluating one row of M z + q
    (the most nonzeros of any row; a dense M's every column)."""
    if not sp.issparse(M):
        row_nnz = M.shape[1]
    elif M.nnz == 0:
        row_nnz = 0
    elif M.format == "csr":
        row_nnz = int(np.diff(M.indptr).max())
    else:
        # counted from the row indices: a CSC -> CSR copy costs a solve's worth
        rows = M.indices if M.format == "csc" else M.tocoo().row
        row_nnz = int(np.bincount(rows, minlength=M.shape[0]).max())
    return (row_nnz + 1) * _EPS


def abs_matvec(M, v) -> np.ndarray:
    """|M| |v| (overflow gives inf, never a warning)."""
    with np.errstate(over="ignore", invalid="ignore"):
        if sp.issparse(M):
            return np.asarray(abs(M) @ np.abs(v)).ravel()
        return np.abs(M) @ np.abs(v)


def row_scales(M, z, q=None) -> np.ndarray:
    """σ_i = |q_i| + (|M| |z|)_i: the size of the terms row i of Mz + q is made of
    (Oettli–Prager's componentwise scale; its rounding error is O(eps σ_i))."""
    s = abs_matvec(M, z)
    return s if q is None else s + np.abs(q)


def column_max_ratio(absM, sigma: np.ndarray) -> np.ndarray:
    """max_i absM_ij / σ_i per column j (0/0 = 0, x/0 = inf); absM holds |M|."""
    n_rows, n_cols = absM.shape
    out = np.zeros(n_cols)
    if n_rows == 0 or n_cols == 0:
        return out
    if sp.issparse(absM):
        from ._certify_kernels import csc_column_max_ratio

        C = absM if absM.format == "csc" else absM.tocsc()
        return csc_column_max_ratio(C.indptr, C.indices, C.data.astype(float, copy=False),
                                    np.ascontiguousarray(sigma, dtype=float))
    step = max(1, _DENSE_CHUNK // n_rows)
    for start in range(0, n_cols, step):
        out[start:start + step] = divide(absM[:, start:start + step], sigma[:, None]).max(axis=0)
    return out


def column_influence(M, sigma: np.ndarray) -> np.ndarray:
    """c_j = max_i |M_ij| / σ_i (0/0 = 0, x/0 = inf): the largest relative change
    a unit of unknown j makes to any row, each row measured by its own σ_i."""
    return column_max_ratio(abs(M) if sp.issparse(M) else np.abs(M), sigma)


def _forward_scale(influence: np.ndarray, cap: float) -> np.ndarray:
    """min(1 / influence, cap) elementwise (1/0 = inf, 1/inf = 0)."""
    with np.errstate(divide="ignore"):
        inv = np.where(influence > 0, 1.0 / np.where(influence > 0, influence, 1.0), np.inf)
    return np.minimum(inv, cap)


@dataclass
class Rows:
    """One block of equations for the componentwise scales: ``terms`` are the
    Oettli–Prager scales at the point (|data| + Σ |A||v|), ``data`` the
    magnitudes of the block's own data (zero marks a homogeneous row), and
    ``blocks`` the |coefficient| matrices of the unknowns that enter it."""

    terms: np.ndarray
    data: np.ndarray
    blocks: dict


def componentwise_scales(rows: list[Rows], caps: dict) -> tuple[dict, list]:
    """Forward scales of the unknowns and the row scales, in two passes.

    An unknown's scale is min(cap, 1 / max_i |A_ij| / scale_i): the change that
    moves some row by all of that row's own size.  A *homogeneous* row (its own
    data exactly zero, e.g. q_i = 0 at an idle contact) whose unknowns are zero
    at the solution has no size of its own — any rounding noise would be all of
    it.  So the unknowns' scales are first taken from the rows with data only,
    a homogeneous row's scale gets the change those allowances can make to it
    (Σ_j |A_ij| scale_j), and the scales are taken again from every row.
    """
    def unknown_scales(row_scales):
        infl = {}
        for R, sc in zip(rows, row_scales):
            for name, absA in R.blocks.items():
                c = column_max_ratio(absA, sc)
                infl[name] = c if name not in infl else np.maximum(infl[name], c)
        return {name: _forward_scale(c, caps[name]) for name, c in infl.items()}

    homogeneous = [R.data == 0 for R in rows]
    if not any(h.any() for h in homogeneous):
        return unknown_scales([R.terms for R in rows]), [R.terms for R in rows]
    first = unknown_scales([np.where(h, np.inf, R.terms) for R, h in zip(rows, homogeneous)])
    sig = []
    for R, h in zip(rows, homogeneous):
        extra = sum(abs_matvec(absA, first[name]) for name, absA in R.blocks.items())
        sig.append(R.terms + np.where(h, extra, 0.0))
    return unknown_scales(sig), sig


class ComponentScales:
    """The componentwise scales of LCP(M, q) at any point z: σ (rows, w's
    units) and ζ (columns, z's units), as the certificate defines them.

    Keeps |M| so that a pivoting method can ask for them at every iterate; the
    sign tests of "energy", "bpp", "lemke" and "trace" are ρ σ_i and ρ ζ_i,
    so no component's decision depends on another component's size.
    """

    def __init__(self, M, q_terms: np.ndarray, scale_M: float | None = None):
        self.absM = abs(M).tocsc() if sp.issparse(M) else np.abs(M)
        self.q_terms = np.abs(np.asarray(q_terms, dtype=float))
        self.scale_M = max_abs(M) if scale_M is None else scale_M

    @classmethod
    def of(cls, lcp) -> "ComponentScales":
        """The scales of an LCP, with |M| and its row sums taken from (and
        kept in) its structure, which a time stepper's LCPs share."""
        st = lcp.structure
        obj = cls.__new__(cls)
        obj.absM = st.abs_matrix
        obj.q_terms = np.abs(np.asarray(lcp.q_terms, dtype=float))
        obj.scale_M = st.scale
        obj._row_sums = st.abs_row_sums
        return obj

    _row_sums = None

    def bound_data(self) -> tuple[np.ndarray, np.ndarray, float]:
        """(‖M_i‖₁ per row, 1/|M_ii| (inf where 0), ‖q‖∞ / max|M|): what cheap
        upper bounds of the scales need — σ_i <= |q_i| + ‖M_i‖₁ ‖z‖∞, plus
        ‖M_i‖₁ cap on an idle row (q_i = 0: the floor componentwise_scales adds),
        ζ_i <= min(σ_i / |M_ii|, cap), cap = max(‖z‖∞, ‖q‖∞ / max|M|)."""
        if self._bounds is None:
            A = self.absM
            diag = np.asarray(A.diagonal()).ravel()
            with np.errstate(divide="ignore"):
                inv_diag = np.where(diag > 0, 1.0 / np.where(diag > 0, diag, 1.0), np.inf)
            floor = inf_norm(self.q_terms) / self.scale_M if self.scale_M > 0 else 0.0
            sums = np.asarray(A.sum(axis=1)).ravel() if self._row_sums is None else self._row_sums
            self._bounds = (sums, inv_diag, floor)
        return self._bounds

    _bounds = None

    def at(self, z: np.ndarray, q_terms: np.ndarray | None = None,
           terms: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(ζ, σ) at z; ``q_terms`` are the magnitudes of q's terms (|q|, or
        LCP.q_terms; default the ones given at construction); ``terms``:
        |M||z| + q_terms where the caller has formed them (the certificate
        checks them for overflow first)."""
        q = self.q_terms if q_terms is None else q_terms
        if terms is None:
            with np.errstate(over="ignore", invalid="ignore"):
                terms = np.asarray(self.absM @ np.abs(z)).ravel() + q
        cap = max(inf_norm(z), inf_norm(q) / self.scale_M if self.scale_M > 0 else 0.0)
        zeta, (sigma,) = componentwise_scales([Rows(terms, q, {"z": self.absM})], {"z": cap})
        return zeta["z"], sigma


def safe_norm2(v: np.ndarray) -> float:
    """‖v‖₂ without overflow (BLAS nrm2 scales)."""
    import scipy.linalg   # not at the top: it would double the cost of `import qpcontact`

    return float(scipy.linalg.norm(v)) if v.size else 0.0
