"""Coarse levels a problem may carry: prolongations from a mesh hierarchy.

A finite-element or finite-difference problem knows its grid, and its grid
knows coarser ones.  A prolongation P_l maps the unknowns of level l + 1 to
those of level l (P_0 to the problem's own n unknowns): column J of P_l is
coarse basis function J written in the fine basis — bilinear interpolation
on a structured grid, the coarse element's shape functions on a nested mesh.
The multilevel method ("mg-bpp") uses them for its coarse corrections and
its nested start (coarse problems min ½y'(P'MP)y + (P'q)'y, y >= 0); without
them it builds its own by aggregation.

A hierarchy only decides how fast the method finds the contact set: the
answer is the exact basic solution of the basis it ends on, certified from
M and q like every answer.  A hierarchy that does not match (wrong shapes, a
coarse unknown with no fine support) is refused here, before anything runs.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .errors import InvalidProblemError

__all__ = ["as_hierarchy"]


def as_hierarchy(prolongations, n: int) -> tuple:
    """The prolongations ``[P_0, P_1, ...]`` (finest first; P_l of shape
    n_l x n_(l+1), n_0 = n, each level smaller than the one above) as CSR
    matrices, validated.

    Raises
    ------
    InvalidProblemError
        Not a sequence of matrices, a shape that does not chain, a level that
        does not coarsen, an entry that is not finite, or a coarse unknown
        whose column is zero; the message names the level.
    """
    if sp.issparse(prolongations) or isinstance(prolongations, np.ndarray):
        raise InvalidProblemError(
            "hierarchy must be a sequence of prolongation matrices [P_0, P_1, ...], finest "
            "first; got a single matrix — wrap it in a list: hierarchy=[P]")
    try:
        levels = list(prolongations)
    except TypeError:
        raise InvalidProblemError(
            "hierarchy must be a sequence of prolongation matrices [P_0, P_1, ...], finest "
            f"first; got {type(prolongations).__name__}") from None
    if not levels:
        raise InvalidProblemError("hierarchy is empty: pass None for no coarse levels")
    out = []
    rows = n
    for l, P in enumerate(levels):
        dtype = getattr(P, "dtype", None)
        if dtype is None:
            try:
                dtype = np.asarray(P).dtype
            except (TypeError, ValueError):
                dtype = None
        if dtype is not None and dtype.kind == "c":
            raise InvalidProblemError(
                f"hierarchy level {l}: the prolongation has complex entries (dtype {dtype}); a "
                "prolongation is a real matrix — pass its real part (P.real) if the imaginary "
                "part is zero, or build it from real shape functions")
        try:
            P = sp.csr_matrix(P, dtype=float)
        except (TypeError, ValueError) as exc:
            raise InvalidProblemError(f"hierarchy level {l}: not a real matrix ({exc})") from None
        if P.ndim != 2 or P.shape[0] != rows:
            what = "the problem's" if l == 0 else f"level {l}'s"
            raise InvalidProblemError(
                f"hierarchy level {l}: the prolongation has {P.shape[0]} rows but {what} "
                f"{rows} unknowns; P_{l} maps level {l + 1} to level {l} (shape n_{l} x "
                f"n_{l + 1}), finest first")
        cols = P.shape[1]
        if not 0 < cols < rows:
            raise InvalidProblemError(
                f"hierarchy level {l}: a coarse level must have fewer unknowns than the one "
                f"above and at least one; P_{l} has shape {P.shape}")
        bad = np.flatnonzero(~np.isfinite(P.data))
        if bad.size:
            row = int(np.searchsorted(P.indptr, bad[0], side="right") - 1)
            raise InvalidProblemError(
                f"hierarchy level {l}: the prolongation has entries that are not finite "
                f"(P_{l}[{row}, {int(P.indices[bad[0]])}] = {P.data[bad[0]]}); replace them "
                "with the coarse shape functions' values")
        P.eliminate_zeros()
        empty = np.flatnonzero(np.diff(P.tocsc().indptr) == 0)
        if empty.size:
            raise InvalidProblemError(
                f"hierarchy level {l}: coarse unknown {int(empty[0])} (of {cols}) has no fine "
                f"support (column {int(empty[0])} of P_{l} is zero) — the coarse level does not "
                "match the fine one")
        out.append(P)
        rows = cols
    return tuple(out)
