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
    q: size0 values.

After the data (q for an LCP; mu, or w and mu, for frictional contact) a file
may hold only: whitespace; for frictional contact, the 0/1 ``isComplete`` flag
older Siconos writers put on its own line; and a comment that starts with
``#`` or follows a blank line and does not start with a number (the Siconos
LCP files end with notes such as "Example 4.4.7 CPS 2009").  Anything else —
text glued to the data, more numbers than the header announces, binary bytes —
raises InvalidProblemError naming the file, the line and what was found:
Siconos's fscanf reader ignores it, but a file with more values than its
header announces was most likely written with a different size, and solving
what was read would answer another problem.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from ..core.errors import InvalidProblemError
from ..core.files import write_text_atomic
from ..core.problems import LCP
from ..core.friction_problem import FrictionProblem

__all__ = ["read_siconos", "read_siconos_lcp", "read_siconos_fc", "write_siconos_fc"]


def _is_number(tok: str) -> bool:
    try:
        float(tok)
    except ValueError:
        return False
    return True


class _Tokens:
    def __init__(self, path: Path):
        self.path = path
        if path.is_dir():
            raise InvalidProblemError(f"{path} is a directory; give the path of a Siconos .dat file")
        if not path.exists():
            raise InvalidProblemError(f"{path}: no such file; check the path (relative paths start "
                                      f"at {Path.cwd()})")
        try:
            # undecodable bytes become U+FFFD: a token holding one fails to
            # parse, and after the data they are reported as binary
            self.text = path.read_bytes().decode("utf-8", errors="replace")
        except OSError as exc:
            raise InvalidProblemError(f"{path}: cannot be read ({exc.strerror or exc})") from None
        self.tokens = self.text.split()
        self.pos = 0

    def finish(self, after: str, flag_allowed: bool = False) -> None:
        """Refuse what follows the data unless it is a comment (or the
        isComplete flag where ``flag_allowed``); see the module docstring."""
        left = len(self.tokens) - self.pos
        if left == 0:
            return
        head = self._head(self.pos)   # ends with the last token read
        rest = self.text[len(head):]
        data_line = head.count("\n") + 1
        first = re.search(r"\S", rest).start()
        line = data_line + rest[:first].count("\n")
        binary = re.search(r"[\x00-\x08\x0e-\x1f\x7f\ufffd]", rest)
        if binary:
            at = data_line + rest[:binary.start()].count("\n")
            raise self._trailing(f"line {at}: binary data after {after} (which end on line "
                                 f"{data_line}): {rest[binary.start():binary.start() + 12]!r}")
        tok = self.tokens[self.pos]
        if flag_allowed and tok in ("0", "1") and "\n" in rest[:first]:
            # older writers end frictional-contact files with isComplete (0/1)
            self.pos += 1
            if self.pos == len(self.tokens):
                return
            return self.finish("the isComplete flag", False)
        blank_before = rest[:first].count("\n") >= 2
        if (tok.startswith("#") or blank_before) and not _is_number(tok):
            return
        if _is_number(tok):
            what = (f"{left} more number{'s' if left > 1 else ''} than the header announces "
                    f"(first: {tok!r})")
        else:
            what = (f"text {tok!r} (a comment after the data must start with '#' or follow a "
                    "blank line)")
        raise self._trailing(f"line {line}: {what} after {after}, which end on line {data_line}")

    def _trailing(self, text: str) -> InvalidProblemError:
        exc = InvalidProblemError(f"{self.path.name}: {text}")
        exc.trailing = True   # the data read; read_siconos reports this error alone
        return exc

    def _head(self, index: int) -> str:
        """The text up to the end of token ``index - 1`` (tokens 0-based)."""
        left = len(self.tokens) - index
        if index == 0:
            return ""
        return self.text.rsplit(None, left)[0] if left > 0 else self.text.rstrip()

    def _line(self, index: int) -> int:
        """The 1-based line of token ``index`` (past the end: the last line)."""
        head = self._head(index)
        rest = self.text[len(head):]
        if index >= len(self.tokens):
            return head.count("\n") + 1
        gap = len(rest) - len(rest.lstrip())
        return head.count("\n") + 1 + rest[:gap].count("\n")

    def _fail(self, what: str, got: str | None = None) -> InvalidProblemError:
        found = f"found {got!r}" if got is not None else "the file ended"
        return InvalidProblemError(f"{self.path.name}: line {self._line(self.pos)}, token "
                                   f"{self.pos + 1}: expected {what}, {found}")

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
    t.finish(f"the {n} values of q")
    return LCP(M, q)


def read_siconos_fc(path: str | os.PathLike):
    """Read a frictional-contact problem from a Siconos ``.dat`` file:
    ``d nc W q mu`` (local) or ``d nc M H f w mu`` (global: the first
    matrix is not d·nc square).  Returns a
    :class:`~qpcontact.core.friction_problem.FrictionProblem`."""
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
        t.finish(f"the {nc} friction coefficients", flag_allowed=True)
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
    t.finish(f"the {nc} friction coefficients", flag_allowed=True)
    return FrictionProblem.global_problem(first, H, f, w, mu, d, name=path.stem)


def write_siconos_fc(problem, path: str | os.PathLike) -> Path:
    """Write a local frictional contact problem (W, q, mu) as a Siconos
    ``.dat`` file, the layout ``frictionContact_newFromFile`` reads: ``d nc``,
    W in sparse-block storage (its nonzero d x d blocks), q, mu.  Values are
    written with 17 significant digits, so :func:`read_siconos_fc` gives back
    the same numbers.  Sparse-block storage rather than dense because a
    3-D pile's W of 2 000 contacts would be 40 million values dense, and
    Siconos's NSGS works on the blocks as they are.  A global problem kept
    without W has no W to write: use :func:`qpcontact.io.write_fclib`.
    Returns the path."""
    if not problem.is_reduced:
        raise InvalidProblemError("this global problem is kept without W; Siconos's local .dat "
                                  "layout needs W: write it with qpcontact.io.write_fclib")
    path = Path(path)
    d, nc = problem.dim, problem.n_contacts
    m = d * nc
    W = sp.bsr_matrix(sp.csr_matrix(problem.W), blocksize=(d, d))
    W.sum_duplicates()
    W.sort_indices()
    ends = " ".join(str(d * (i + 1)) for i in range(nc))
    lines = [str(d), str(nc), f"1 {m} {m}", str(len(W.indices)), str(nc), str(nc), ends, ends,
             str(nc + 1), str(len(W.indices)), " ".join(map(str, W.indptr)),
             " ".join(map(str, W.indices))]
    for b, block in enumerate(W.data):
        lines.append(str(b))
        lines.append(" ".join(repr(float(x)) for x in block.ravel(order="F")))   # column-major
    lines.append(" ".join(repr(float(x)) for x in problem.q))
    lines.append(" ".join(repr(float(x)) for x in problem.mu))
    return write_text_atomic(path, "\n".join(lines) + "\n")


def read_siconos(path: str | os.PathLike):
    """A Siconos ``.dat`` file, LCP or frictional contact.  The two layouts are
    told apart by which one reads the file (a comment after the data is
    allowed, anything else refused: the module docstring); when both read, the
    one that leaves fewer tokens unread wins."""
    path = Path(path)
    errors, found, trailing = [], [], []
    for kind, reader in (("an LCP", _lcp_from), ("a frictional contact problem", _fc_from)):
        t = _Tokens(path)
        try:
            problem = reader(t)
        except InvalidProblemError as exc:
            errors.append(f"as {kind}: {exc}")
            if getattr(exc, "trailing", False):
                trailing.append(exc)
            continue
        found.append((len(t.tokens) - t.pos, kind, problem))
    if not found and len(trailing) == 1:
        # one layout read all the data and stopped only at what follows it:
        # that is the file's layout, and what follows is the error
        raise trailing[0]
    found.sort(key=lambda f: f[0])
    if len(found) == 2 and found[0][0] == found[1][0]:
        raise InvalidProblemError(f"{path.name} reads both as an LCP and as a frictional contact "
                                  "problem; use read_siconos_lcp or read_siconos_fc")
    if found:
        return found[0][2]
    raise InvalidProblemError(f"{path.name} is neither a Siconos LCP nor a frictional contact "
                              "file: " + "; ".join(errors))
