"""Reading problem files.

Siconos LCP text format (as written by ``linearComplementarity_printInFile``):
whitespace-separated tokens, read in order::

    n  storageType  size0  size1
    storageType 0 (dense):  size0 size1, then size0*size1 values COLUMN-major
    storageType 1 (sparse block, block CSR):
        nbblocks  nbrows  nbcols
        cumulative row end of each block row (nbrows ints)
        cumulative column end of each block column (nbcols ints)
        filled1 (= nbrows + 1)  filled2 (= nbblocks)
        block-row pointers (filled1 ints)  block-column indices (filled2 ints)
        for each block, in block-row order: its number, then its values COLUMN-major
    q: size0 values; anything after them is a comment and is ignored.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from .errors import InvalidProblemError
from .problems import LCP

__all__ = ["read_siconos_lcp"]


class _Tokens:
    def __init__(self, path: Path):
        self.path = path
        if path.is_dir():
            raise InvalidProblemError(f"{path} is a directory; give the path of a Siconos .dat file")
        if not path.exists():
            raise InvalidProblemError(f"{path}: no such file; check the path (relative paths start "
                                      f"at {Path.cwd()})")
        try:
            self.tokens = path.read_text(errors="replace").split()
        except OSError as exc:
            raise InvalidProblemError(f"{path}: cannot be read ({exc.strerror or exc})") from None
        self.pos = 0

    def _fail(self, what: str, got: str | None = None) -> InvalidProblemError:
        found = f"found {got!r}" if got is not None else "the file ended"
        return InvalidProblemError(f"{self.path.name}: token {self.pos + 1}: expected {what}, {found}")

    def _next(self, what: str) -> str:
        if self.pos >= len(self.tokens):
            raise self._fail(what)
        tok = self.tokens[self.pos]
        return tok

    def int(self, what: str, minimum: int = 0) -> int:
        tok = self._next(what)
        try:
            value = int(tok)
        except ValueError:
            raise self._fail(f"an integer ({what})", tok) from None
        if value < minimum:
            raise self._fail(f"an integer >= {minimum} ({what})", tok)
        self.pos += 1
        return value

    def ints(self, count: int, what: str) -> np.ndarray:
        return np.array([self.int(what) for _ in range(count)], dtype=int)

    def floats(self, count: int, what: str) -> np.ndarray:
        left = len(self.tokens) - self.pos
        if count > left:   # before allocating: a header may announce 1e10 values
            raise InvalidProblemError(
                f"{self.path.name}: token {self.pos + left + 1}: expected {what}, the file ended "
                f"(the header announces {count} values here, the file holds {left} more)")
        out = np.empty(count)
        for i in range(count):
            tok = self._next(what)
            try:
                out[i] = float(tok)
            except ValueError:
                raise self._fail(f"a number ({what})", tok) from None
            if not np.isfinite(out[i]):
                raise self._fail(f"a finite number ({what})", tok)
            self.pos += 1
        return out


def _read_sbm(t: _Tokens, n0: int, n1: int):
    nblocks = t.int("number of blocks")
    nbr = t.int("number of block rows", 1)
    nbc = t.int("number of block columns", 1)
    row_ends = t.ints(nbr, "cumulative block-row end")
    col_ends = t.ints(nbc, "cumulative block-column end")
    if row_ends[-1] != n0 or col_ends[-1] != n1 or np.any(np.diff(row_ends) <= 0) \
            or np.any(np.diff(col_ends) <= 0) or row_ends[0] <= 0 or col_ends[0] <= 0:
        raise InvalidProblemError(
            f"{t.path.name}: block sizes {row_ends.tolist()} x {col_ends.tolist()} do not tile a "
            f"{n0} x {n1} matrix"
        )
    filled1 = t.int("filled1 (number of block rows + 1)")
    filled2 = t.int("filled2 (number of blocks)")
    if filled1 != nbr + 1 or filled2 != nblocks:
        raise InvalidProblemError(
            f"{t.path.name}: filled1 = {filled1}, filled2 = {filled2} do not match "
            f"{nbr} block rows and {nblocks} blocks"
        )
    row_ptr = t.ints(filled1, "block-row pointer")
    col_idx = t.ints(filled2, "block-column index")
    if row_ptr[0] != 0 or row_ptr[-1] != nblocks or np.any(np.diff(row_ptr) < 0) \
            or np.any(col_idx >= nbc):
        raise InvalidProblemError(f"{t.path.name}: inconsistent block-row pointers or block-column indices")
    row_start = np.concatenate([[0], row_ends[:-1]])
    col_start = np.concatenate([[0], col_ends[:-1]])
    rows, cols, vals = [], [], []
    for br in range(nbr):
        for b in range(row_ptr[br], row_ptr[br + 1]):
            number = t.int("block number")
            if number != b:
                t.pos -= 1
                raise t._fail(f"block number {b}", str(number))
            bc = col_idx[b]
            nr = row_ends[br] - row_start[br]
            nc = col_ends[bc] - col_start[bc]
            block = t.floats(nr * nc, f"value of block {b}").reshape(nr, nc, order="F")
            r, c = np.nonzero(block)
            rows.append(r + row_start[br])
            cols.append(c + col_start[bc])
            vals.append(block[r, c])
    cat = (lambda parts, dt: np.concatenate(parts) if parts else np.zeros(0, dt))
    return sp.csc_matrix((cat(vals, float), (cat(rows, int), cat(cols, int))), shape=(n0, n1))


def read_siconos_lcp(path: str | os.PathLike) -> LCP:
    """Read an LCP from a Siconos ``.dat`` file (dense or sparse-block storage).

    Dense storage gives a dense M, sparse-block storage a SciPy CSC matrix.

    Raises
    ------
    InvalidProblemError
        The file does not follow the format (the message gives the file name
        and the 1-based position of the offending token, or the size its
        header announces against what it holds), is missing, or is a
        directory.
    """
    path = Path(path)
    t = _Tokens(path)
    n = t.int("the LCP size n", 1)
    storage = t.int("the storage type (0 dense, 1 sparse block)")
    n0 = t.int("the number of rows of M", 1)
    n1 = t.int("the number of columns of M", 1)
    if n0 != n or n1 != n:
        raise InvalidProblemError(f"{path.name}: M is {n0} x {n1} but the LCP size is {n}")
    if storage == 0:
        r, c = t.int("the number of rows (repeated)"), t.int("the number of columns (repeated)")
        if (r, c) != (n0, n1):
            t.pos -= 2
            raise t._fail(f"the repeated size {n0} {n1}", f"{r} {c}")
        M = t.floats(n0 * n1, "a value of M").reshape(n0, n1, order="F")
    elif storage == 1:
        M = _read_sbm(t, n0, n1)
    else:
        t.pos -= 3
        raise t._fail("storage type 0 (dense) or 1 (sparse block)", str(storage))
    q = t.floats(n, "a value of q")
    return LCP(M, q)
