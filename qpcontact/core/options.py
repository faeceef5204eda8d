"""Validation of method options: one declarative checker for every method.

A method declares what it takes as a tuple of :class:`Option` and reads its
options by :func:`read_options`, which refuses a misspelt name (listing what
the method takes, with a close match), an ill-typed or out-of-range value
(naming the method, the option, the value given and what is expected), and a
vector holding NaN or inf (naming the first bad entry) — all before any work —
and fills in the defaults.  :func:`options_doc` writes the option list of a
docstring from the same declaration.

Kinds of value (``Option.kind``):

========== ==============================================================
"int"      an integer (numpy's too, and a float with an integral value),
           not a bool
"float"    a real number, not a bool and not NaN (inf where the bounds
           allow it)
"bool"     True or False (numpy's too)
"callable" anything callable
"vector"   a sequence of finite numbers, returned as a 1-D float array;
           the bounds apply to each entry
"choice"   one of ``choices``
"mapping"  a dict (or any mapping), returned as a new dict
"any"      anything: the method checks it itself
========== ==============================================================

``None`` given for an option whose default is None (or which says
``none_ok``) means "the default"; for any other option it is refused.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .errors import InvalidOptionError

__all__ = ["Option", "BySize", "UNSET", "read_options", "names_only", "check_length",
           "options_doc", "check_options", "int_option", "check_seed", "KINDS", "PROGRESS",
           "TIME_LIMIT"]

KINDS = ("int", "float", "bool", "callable", "vector", "choice", "mapping", "any")


class _Unset:
    def __repr__(self):
        return "UNSET"


#: the default of an option that stays absent from what read_options returns
#: when it is not given (a backend's own settings: the backend has the default)
UNSET = _Unset()


@dataclass(frozen=True)
class BySize:
    """A default that depends on the problem's size n: ``value(n)``, written
    ``doc`` in messages and docstrings; :func:`read_options` needs ``size=n``."""

    value: Callable[[int], Any]
    doc: str


@dataclass(frozen=True)
class Option:
    """One option of a method.

    ``name``; ``default`` (a value, a :class:`BySize`, or :data:`UNSET`);
    ``kind`` (one of :data:`KINDS`); ``low``/``high`` bounds (None: none),
    each open (excluded) when ``low_open``/``high_open``; ``choices`` for
    kind "choice"; ``none_ok``: None is accepted although the default is not
    None; ``doc``: a few words for the method's docstring."""

    name: str
    default: Any = None
    kind: str = "any"
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    choices: tuple = ()
    none_ok: bool = False
    doc: str = ""

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"Option {self.name!r}: kind must be one of {KINDS}; "
                             f"got {self.kind!r}")
        if self.kind == "choice" and not self.choices:
            raise ValueError(f"Option {self.name!r}: kind 'choice' needs choices")

    @property
    def default_doc(self) -> str:
        """The default in words."""
        d = self.default
        if isinstance(d, BySize):
            return d.doc
        if d is None or d is UNSET:
            return "none"
        if isinstance(d, int) and not isinstance(d, bool) and abs(d) >= 10_000:
            return f"{d:,}".replace(",", " ")
        if isinstance(d, float):
            return f"{d:g}"
        return repr(d) if isinstance(d, str) else str(d)

    def expected(self) -> str:
        """What a value must be, in words."""
        bounds = self._bounds_words()
        if self.kind == "int":
            text = "an integer" + bounds
        elif self.kind == "float":
            text = "a number" + bounds
        elif self.kind == "bool":
            text = "True or False"
        elif self.kind == "callable":
            text = "a callable"
        elif self.kind == "vector":
            text = "a vector of finite numbers" + (f", each{bounds}" if bounds else "")
        elif self.kind == "choice":
            text = "one of " + ", ".join(map(repr, self.choices))
        elif self.kind == "mapping":
            text = "a dict"
        else:
            text = "a value"
        if self.none_ok:
            text += " or None"
        return text

    def _bounds_words(self) -> str:
        low = high = ""
        if self.low is not None:
            low = f"{'>' if self.low_open else '>='} {self.low:g}"
        if self.high is not None:
            high = f"{'<' if self.high_open else '<='} {self.high:g}"
        if low and high:
            return (f" in {'(' if self.low_open else '['}{self.low:g}, {self.high:g}"
                    f"{')' if self.high_open else ']'}")
        return f" {low or high}" if (low or high) else ""

    def in_bounds(self, x: float) -> bool:
        if math.isnan(x):
            return False
        if self.low is not None and not (x > self.low if self.low_open else x >= self.low):
            return False
        return self.high is None or (x < self.high if self.high_open else x <= self.high)


#: options several methods share: a callable taking one line of text per
#: iteration, and the iterative methods' own time limit in seconds
#: (:func:`qpcontact.solve`'s time_limit is passed to them as it)
PROGRESS = Option("progress", None, "callable", doc="a callable taking one line per iteration")
TIME_LIMIT = Option("time_limit", None, "float", low=0.0, doc="seconds, checked between iterations")


def _is_real(value) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) \
        and not isinstance(value, (bool, np.bool_))


def _refuse(method: str, opt: Option, value, why: str = "") -> InvalidOptionError:
    shown = repr(value)
    if len(shown) > 80:
        shown = shown[:77] + "..."
    hint = ("" if opt.default is UNSET else " (leave it out for the default)"
            if opt.default is None else f" (leave it out for the default, {opt.default_doc})")
    return InvalidOptionError(f"{method!r}: option {opt.name} must be {opt.expected()}; got "
                              f"{shown}{why}{hint}")


def _vector(method: str, opt: Option, value) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise _refuse(method, opt, value) from None
    arr = arr.ravel()
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        i = int(bad[0])
        raise _refuse(method, opt, value, f": entry {i} is {arr[i]}")
    if opt.low is not None or opt.high is not None:
        for i, x in enumerate(arr):
            if not opt.in_bounds(float(x)):
                raise _refuse(method, opt, value, f": entry {i} is {x:g}")
    return arr


def _value(method: str, opt: Option, value):
    """``value`` checked (and converted) for ``opt``."""
    kind = opt.kind
    if kind == "int":
        if not _is_real(value) or not math.isfinite(float(value)) \
                or not float(value).is_integer() or not opt.in_bounds(float(value)):
            raise _refuse(method, opt, value)
        return int(value)
    if kind == "float":
        if not _is_real(value) or not opt.in_bounds(float(value)):
            raise _refuse(method, opt, value)
        return float(value)
    if kind == "bool":
        if not isinstance(value, (bool, np.bool_)):
            raise _refuse(method, opt, value)
        return bool(value)
    if kind == "callable":
        if not callable(value):
            raise _refuse(method, opt, value)
        return value
    if kind == "vector":
        return _vector(method, opt, value)
    if kind == "choice":
        try:
            known = value in opt.choices
        except TypeError:   # an unhashable or incomparable value
            known = False
        if not known:
            raise _refuse(method, opt, value)
        return value
    if kind == "mapping":
        if not isinstance(value, Mapping):
            raise _refuse(method, opt, value)
        return dict(value)
    return value


def _refuse_unknown(method: str, unknown: list, names: list, word: str) -> None:
    hints = []
    for key in unknown:
        close = difflib.get_close_matches(str(key), names, n=2)
        hints.append(f"{key} (did you mean {' or '.join(close)}?)" if close else str(key))
    if not names:
        takes = f"it takes no {word}s"
    elif word == "option":
        takes = f"it takes {', '.join(names)}"
    else:
        takes = f"its {word}s are {', '.join(names)}"
    raise InvalidOptionError(f"{method!r} does not take {', '.join(hints)}; {takes}")


def read_options(method: str, options: Mapping | None, spec, *, size: int | None = None,
                 word: str = "option") -> dict:
    """``options`` checked against ``spec`` (a sequence of :class:`Option`):
    a dict holding every option of ``spec`` — the value given, converted, or
    the default (:class:`BySize` defaults resolved with ``size``; options
    whose default is :data:`UNSET` only when given).  InvalidOptionError
    for a name ``spec`` does not hold (``word`` names what they are in the
    message: "option", a backend's "setting") or a value it refuses."""
    options = {} if options is None else options
    by_name = {opt.name: opt for opt in spec}
    unknown = [key for key in options if key not in by_name]
    if unknown:
        _refuse_unknown(method, unknown, list(by_name), word)
    out = {}
    for name, opt in by_name.items():
        if name in options:
            value = options[name]
            if value is None and (opt.none_ok or opt.default is None):
                out[name] = None
                continue
            if value is None and opt.kind != "any":
                raise _refuse(method, opt, value)
            out[name] = _value(method, opt, value)
        elif opt.default is UNSET:
            continue
        elif isinstance(opt.default, BySize):
            if size is None:
                raise TypeError(f"read_options: option {name!r} of {method!r} has a default "
                                "that depends on the problem's size: pass size=")
            out[name] = opt.default.value(size)
        else:
            default = opt.default
            out[name] = dict(default) if isinstance(default, Mapping) else default
    return out


def names_only(names) -> tuple:
    """A spec taking the options ``names`` with any value and no default:
    a backend's own settings, which the backend checks and defaults."""
    return tuple(Option(name, UNSET) for name in sorted(names))


def check_length(method: str, name: str, vector: np.ndarray, size: int) -> np.ndarray:
    """``vector`` (read by :func:`read_options`) when it has ``size``
    entries; InvalidOptionError otherwise."""
    if vector.shape != (size,):
        raise InvalidOptionError(f"{method!r}: option {name} must have {size} entries (one per "
                                 f"unknown of this problem); got {vector.size}")
    return vector


def options_doc(spec) -> str:
    """The option list of ``spec`` for a docstring: one line per option,
    its doc, what it must be and its default."""
    lines = []
    for opt in spec:
        if opt.default is UNSET:
            continue
        words = opt.doc or opt.expected()
        default = "" if opt.default is None else f"; default {opt.default_doc}"
        lines.append(f"    ``{opt.name}``: {words} ({opt.expected()}{default})")
    return "Options:\n\n" + "\n".join(lines) if lines else "Options: none."


def check_seed(seed, what: str = "seed") -> int:
    """``seed`` as an int >= 0 (numpy's generators take no negative seed),
    or InvalidOptionError naming ``what`` and the value given."""
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)) \
            or seed < 0:
        raise InvalidOptionError(f"{what} must be an integer >= 0 (a random generator's seed); "
                                 f"got {seed!r} — pass 0 or a positive integer")
    return int(seed)


# The first interface, kept for callers outside the methods
# (formulations/frames/mechanics/tresca.py).

def check_options(method: str, options: dict, allowed: tuple) -> None:
    """InvalidOptionError naming the options ``method`` does not take (the
    values are not checked)."""
    read_options(method, options, names_only(allowed))


def int_option(method: str, options: dict, name: str, default: int, minimum: int = 0) -> int:
    """options[name] as an int >= minimum (default when absent), or
    InvalidOptionError saying what was given and what is expected."""
    spec = (Option(name, default, "int", low=minimum),)
    return read_options(method, {name: options[name]} if name in options else {}, spec)[name]
