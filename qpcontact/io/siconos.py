"""Siconos's text files: LCPs and frictional contact problems.

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

from ..core.errors import InvalidProblemError
from ..core.problems import LCP
from ..friction.problem import FrictionProblem

__all__ = ["read_siconos", "read_siconos_lcp", "read_siconos_fc"]


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


def _read_cs_print(t: _Tokens, n0: int, n1: int):
    """A CSparse ``cs_print`` listing (NumericsMatrix storage 2): its kind
    (1 triplet, 2 compressed columns), a text header, then the entries
    ("row col : value" or per column "col j : locations a to b" and
    "row : value").  Values are printed with 6 significant digits: the
    matrix read is the one the file holds, not the one that was written."""
    kind = t.int("the sparse kind (1 triplet, 2 compressed columns)")
    if kind not in (1, 2):
        t.pos -= 1
        raise t._fail("sparse kind 1 (triplet) or 2 (compressed columns)", str(kind))
    # skip the banner and the size line up to "nnz: K"
    while t._next("the 'nnz:' of the CSparse header") != "nnz:":
        t.pos += 1
    t.pos += 1
    nnz = int(t._next("the number of nonzeros").rstrip(","))
    t.pos += 1
    if kind == 2 and t.pos < len(t.tokens) and t.tokens[t.pos] == "1-norm:":
        t.pos += 2
    rows, cols = np.zeros(nnz, int), np.zeros(nnz, int)
    vals = np.zeros(nnz)

    def number(tok, what):
        try:
            return float(tok)
        except ValueError:
            raise t._fail(what, tok) from None

    k = 0
    if kind == 1:
        for k in range(nnz):
            r, c = t.int("a row index"), t.int("a column index")
            if t._next("':'") != ":":
                raise t._fail("':'", t.tokens[t.pos])
            t.pos += 1
            rows[k], cols[k] = r, c
            vals[k] = number(t._next("a value"), "a value")
            t.pos += 1
    else:
        while k < nnz:
            if t._next("'col'") != "col":
                raise t._fail("'col'", t.tokens[t.pos])
            t.pos += 1
            c = t.int("a column index")
            t.pos += 2                      # ':' 'locations'
            a = t.int("the first location")
            t.pos += 1                      # 'to'
            b = int(t._next("the last location"))
            t.pos += 1
            for _ in range(b - a + 1):
                rows[k] = t.int("a row index")
                t.pos += 1                  # ':'
                vals[k] = number(t._next("a value"), "a value")
                t.pos += 1
                cols[k] = c
                k += 1
    if np.any(rows >= n0) or np.any(cols >= n1):
        raise InvalidProblemError(f"{t.path.name}: a sparse entry lies outside the {n0} x {n1} matrix")
    return sp.csc_matrix((vals, (rows, cols)), shape=(n0, n1))


def _read_matrix(t: _Tokens, what: str, check=None):
    """A NumericsMatrix: storage (0 dense, 1 sparse block, 2 sparse), sizes,
    body.  ``check(n0, n1)`` may refuse the sizes before anything is read."""
    storage = t.int(f"the storage type of {what} (0 dense, 1 sparse block, 2 sparse)")
    n0 = t.int(f"the number of rows of {what}")
    n1 = t.int(f"the number of columns of {what}")
    if check is not None:
        check(n0, n1)
    if storage == 0:
        r, c = t.int("the number of rows (repeated)"), t.int("the number of columns (repeated)")
        if (r, c) != (n0, n1):
            t.pos -= 2
            raise t._fail(f"the repeated size {n0} {n1}", f"{r} {c}")
        return t.floats(n0 * n1, f"a value of {what}").reshape(n0, n1, order="F")
    if storage == 1:
        return _read_sbm(t, n0, n1)
    if storage == 2:
        return _read_cs_print(t, n0, n1)
    t.pos -= 3
    raise t._fail("storage type 0 (dense), 1 (sparse block) or 2 (sparse)", str(storage))


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
    return _lcp_from(_Tokens(Path(path)))


def _lcp_from(t: _Tokens) -> LCP:
    path = t.path
    n = t.int("the LCP size n", 1)

    def check(n0, n1):
        if (n0, n1) != (n, n):
            raise InvalidProblemError(f"{path.name}: M is {n0} x {n1} but the LCP size is {n}")

    M = _read_matrix(t, "M", check)
    q = t.floats(n, "a value of q")
    return LCP(M, q)


def read_siconos_fc(path: str | os.PathLike):
    """Read a frictional-contact problem from a Siconos ``.dat`` file:
    ``d nc W q mu`` (local) or ``d nc M H f w mu`` (global: the first
    matrix is not d·nc square).  Returns a
    :class:`~qpcontact.friction.FrictionProblem`."""
    return _fc_from(_Tokens(Path(path)))


def _fc_from(t: _Tokens):
    path = t.path
    d = t.int("the dimension d (2 or 3)", 2)
    nc = t.int("the number of contacts")
    first = _read_matrix(t, "W (or M)")
    m = d * nc
    if first.shape == (m, m) and m > 0:
        q = t.floats(m, "a value of q")
        mu = t.floats(nc, "a friction coefficient")
        return FrictionProblem(first, q, mu, d, name=path.stem)
    H = _read_matrix(t, "H")
    n = first.shape[0]
    if first.shape != (n, n) or H.shape != (n, m):
        raise InvalidProblemError(
            f"{path.name}: a global problem needs M square and H of {n} x {m}; got "
            f"{first.shape} and {H.shape}")
    f = t.floats(n, "a value of f")
    w = t.floats(m, "a value of w")
    mu = t.floats(nc, "a friction coefficient")
    return FrictionProblem.global_problem(first, H, f, w, mu, d, name=path.stem)


def read_siconos(path: str | os.PathLike):
    """A Siconos ``.dat`` file, LCP or frictional contact.  The two layouts are
    told apart by which one reads the file; Siconos files may carry trailing
    data (a stored solution), so when both read, the one that leaves fewer
    tokens unread wins."""
    path = Path(path)
    errors, found = [], []
    for kind, reader in (("an LCP", _lcp_from), ("a frictional contact problem", _fc_from)):
        t = _Tokens(path)
        try:
            problem = reader(t)
        except InvalidProblemError as exc:
            errors.append(f"as {kind}: {exc}")
            continue
        found.append((len(t.tokens) - t.pos, kind, problem))
    found.sort(key=lambda f: f[0])
    if len(found) == 2 and found[0][0] == found[1][0]:
        raise InvalidProblemError(f"{path.name} reads both as an LCP and as a frictional contact "
                                  "problem; use read_siconos_lcp or read_siconos_fc")
    if found:
        return found[0][2]
    raise InvalidProblemError(f"{path.name} is neither a Siconos LCP nor a frictional contact "
                              "file: " + "; ".join(errors))
