"""Reading README.md's code blocks and comparing what they show with what they give.

Used by tests/package/test_readme.py (every block, in the checkout) and tests/package/test_wheel.py
(the first block, against an installed wheel).  Two kinds of shown output:

- ``expr  # ... -> LITERAL``: the expression's value against a Python literal;
- a ```` ```text ```` block right after a ```` ```python ```` block: what the
  block prints.

Numbers agree to 1e-3 of their size (what the README prints: 4 to 6 digits),
and any two values below 1e-9 agree: round-off (a certificate of 1e-28 here
and 3e-27 on another machine) is shown as an order of magnitude only.  Text
agrees exactly; in a literal string, ``...`` stands for any text.
"""

from __future__ import annotations

import ast
import io
import math
import re
import tokenize
from dataclasses import dataclass
from pathlib import Path
from tests.helpers.paths import ROOT

README = ROOT / "README.md"
REL, FLOOR = 1e-3, 1e-9
NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


@dataclass
class Block:
    lang: str
    line: int            # README line of the block's first code line (1-based)
    code: str
    output: str | None = None   # the ```text block that follows a python block

    @property
    def name(self) -> str:
        return f"README.md:{self.line}"


def blocks(path: Path = README) -> list[Block]:
    """Every fenced block, in order; a ```text block right after a python
    block (blank lines between at most) becomes that block's ``output``."""
    lines = path.read_text(encoding="utf-8").splitlines()
    raw, i = [], 0                     # (Block, line index of its closing fence)
    while i < len(lines):
        m = re.match(r"^```(\w*)\s*$", lines[i])
        if not m:
            i += 1
            continue
        j = i + 1
        while j < len(lines) and not lines[j].startswith("```"):
            j += 1
        if j == len(lines):
            raise ValueError(f"README.md:{i + 1}: a code block is never closed")
        block = Block(m.group(1), i + 2, "\n".join(lines[i + 1:j]) + "\n")
        prev = raw[-1] if raw else None
        if (block.lang == "text" and prev and prev[0].lang == "python"
                and not any(ln.strip() for ln in lines[prev[1] + 1:i])):
            prev[0].output = block.code
        else:
            raw.append((block, j))
        i = j + 1
    return [b for b, _ in raw]


def python_blocks(path: Path = README) -> list[Block]:
    return [b for b in blocks(path) if b.lang == "python"]


def expectations(code: str) -> dict[int, str]:
    """{line in the block: the literal after ``-> `` in that line's comment}."""
    out = {}
    for tok in tokenize.generate_tokens(io.StringIO(code).readline):
        if tok.type == tokenize.COMMENT and "-> " in tok.string:
            out[tok.start[0]] = tok.string.split("-> ", 1)[1].strip()
    return out


def run(block: Block, namespace: dict) -> tuple[str, list[str]]:
    """Execute ``block`` statement by statement in ``namespace``; return what
    it printed and one line per ``# -> value`` that its expression does not give.
    Tracebacks point at README lines."""
    import contextlib

    tree = ast.parse(block.code, filename=block.name)
    expected = expectations(block.code)
    wrong, buf = [], io.StringIO()
    for stmt in tree.body:
        lines = [n for n in range(stmt.lineno, stmt.end_lineno + 1) if n in expected]
        where = f"README.md:{block.line + stmt.lineno - 1}"
        if lines and not isinstance(stmt, ast.Expr):
            wrong.append(f"{where}: '-> {expected[lines[0]]}' on a statement that is not "
                         "an expression: nothing to check it against")
            lines = []
        if lines:
            text = expected[lines[-1]]
            try:
                want = ast.literal_eval(text)
            except (ValueError, SyntaxError):
                wrong.append(f"{where}: '-> {text}' is not a Python literal")
                continue
            code = ast.Expression(stmt.value)
            ast.increment_lineno(code, block.line - 1)
            with contextlib.redirect_stdout(buf):
                got = eval(compile(code, "README.md", "eval"), namespace)
            if not same(got, want):
                wrong.append(f"{where}: {ast.unparse(stmt.value)} is {got!r}, the README shows {text}")
            continue
        mod = ast.Module([stmt], type_ignores=[])
        ast.increment_lineno(mod, block.line - 1)
        with contextlib.redirect_stdout(buf):
            exec(compile(mod, "README.md", "exec"), namespace)
    return buf.getvalue(), wrong


def close(got: float, want: float) -> bool:
    if abs(got) < FLOOR and abs(want) < FLOOR:
        return True
    return math.isclose(got, want, rel_tol=REL, abs_tol=FLOOR)


def same(got, want) -> bool:
    """Whether a value agrees with the literal the README shows."""
    if want is None or isinstance(want, bool):
        return got is want or (type(got).__name__ == "bool_" and bool(got) is want)
    if isinstance(want, (int, float)):
        try:
            return not isinstance(got, (str, bool)) and close(float(got), float(want))
        except (TypeError, ValueError):
            return False
    if isinstance(want, str):
        if not isinstance(got, str):
            return False
        if "..." in want:
            pattern = ".*".join(re.escape(part) for part in want.split("..."))
            return re.fullmatch(pattern, got, flags=re.DOTALL) is not None
        return got == want
    if isinstance(want, (list, tuple)):
        if hasattr(got, "tolist"):
            got = got.tolist()
        return (isinstance(got, (list, tuple)) and len(got) == len(want)
                and all(same(g, w) for g, w in zip(got, want)))
    if isinstance(want, dict):
        return (isinstance(got, dict) and set(got) == set(want)
                and all(same(got[k], w) for k, w in want.items()))
    return got == want


def output_differences(got: str, want: str) -> list[str]:
    """Line by line: the same words and punctuation, numbers as in ``close``."""
    g_lines, w_lines = got.strip().splitlines(), want.strip().splitlines()
    if len(g_lines) != len(w_lines):
        return [f"{len(g_lines)} lines printed, the README shows {len(w_lines)}:\n{got}"]
    out = []
    for k, (g, w) in enumerate(zip(g_lines, w_lines), 1):
        g_words, w_words = NUMBER.split(g), NUMBER.split(w)
        g_nums, w_nums = NUMBER.findall(g), NUMBER.findall(w)
        if ["".join(s.split()) for s in g_words] != ["".join(s.split()) for s in w_words] \
                or not all(close(float(a), float(b)) for a, b in zip(g_nums, w_nums)):
            out.append(f"line {k}: printed {g!r}, the README shows {w!r}")
    return out
