"""Validation of method options: a misspelt or ill-typed option is misuse,
reported before any work with what the method does take."""

from __future__ import annotations

import numpy as np

from .errors import InvalidOptionError

__all__ = ["check_options", "int_option"]


def check_options(method: str, options: dict, allowed: tuple) -> None:
    """InvalidOptionError naming the options ``method`` does not take."""
    unknown = sorted(set(options) - set(allowed))
    if unknown:
        raise InvalidOptionError(f"{method!r} has no option(s) {unknown}; it takes {list(allowed)}")


def int_option(method: str, options: dict, name: str, default: int, minimum: int = 0) -> int:
    """options[name] as an int >= minimum (default when absent), or
    InvalidOptionError saying what was given and what is expected."""
    value = options.get(name, default)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer, float, np.floating)) \
            or not float(value).is_integer() or value < minimum:
        raise InvalidOptionError(
            f"{method!r}: option {name} must be an integer >= {minimum}; got {value!r}"
            + (" (leave it out for the default)" if value is None else "")
        )
    return int(value)
