"""The load combination a frame's solve or trace analyses: ``solve(p)``'s
Osipova–Popov–Lovtsov split (constant + p x variable) or a named
combination {case: factor}, and the refusal of one that puts no load on the
frame where one is meant."""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from . import contact_lcp
from .loads import CONSTANT, VARIABLE, combination, number


def load_combination(frame, p, combo, b) -> dict:
    if combo is None:
        require_loads({CONSTANT: 1.0, VARIABLE: 1.0}, b, "solve(p)",
                            "constant + p x variable", only_if_named=True)
        return {CONSTANT: 1.0, VARIABLE: number(p, "p")}
    return combination(combo, set(b["cases"]))


def require_loads(combo, b, what, part, only_if_named=False) -> None:
    """Refuse a combination that puts no load on the frame where one is
    meant: solve(p) or trace() on a frame whose loads are all in named
    cases returned ok=True at zero load, silently.  With
    ``only_if_named`` only when such cases exist (a frame with constant
    loads alone still solves, and traces trivially)."""
    factors = contact_lcp.factors(b, combo)
    if np.any(b["F"] @ factors) or np.any(b["U"] @ factors):
        return
    named = [c for c in b["cases"] if c not in (CONSTANT, VARIABLE)
             and (np.any(b["F"][:, b["cases"].index(c)])
                  or np.any(b["U"][:, b["cases"].index(c)]))]
    if only_if_named and not named:
        return
    cases = ", ".join(repr(c) for c in named) or "none"
    example = "{" + ", ".join(f"{c!r}: 1.0" for c in named[:2]) + "}"
    raise InvalidProblemError(
        f"{what}: {part} (the cases {', '.join(repr(c) for c in combo)}) has no load, so "
        f"there is nothing to analyse; this frame's loads are in the cases {cases} — pass "
        f"combination={example} to solve, constant=/variable= to trace (e.g. "
        f"variable={named[-1] if named else 'W'!r}), or add loads with case='variable'")


def trace_combinations(b, constant, variable) -> tuple:
    """(constant, variable) of a trace, validated: ``constant`` a
    combination (default the case "constant"), ``variable`` a case name or
    a combination (default the case "variable"), which must load the frame
    where named cases hold its loads."""
    known = set(b["cases"])
    const = combination(constant or {CONSTANT: 1.0}, known)
    var = combination({variable: 1.0} if isinstance(variable, str)
                      else (variable or {VARIABLE: 1.0}), known)
    require_loads(var, b, "trace", "the variable part", only_if_named=True)
    return const, var


def constant_first(combo: dict):
    """The load path to ``combo`` that puts the constant loads on first:
    (constant, variable, target p, words) — the Osipova–Popov–Lovtsov split
    (constant, then p x variable up to the requested p) where ``combo`` is
    one, else the case "constant", then the other loads in proportion up to
    1 — or None where it has no constant part and another load."""
    if set(combo) <= {CONSTANT, VARIABLE} and combo.get(VARIABLE, 0.0) > 0:
        return ({CONSTANT: combo.get(CONSTANT, 0.0)}, {VARIABLE: 1.0}, combo[VARIABLE],
                "constant, then p x variable")
    if combo.get(CONSTANT, 0.0) > 0 and len(combo) > 1:
        return ({CONSTANT: combo[CONSTANT]}, {c: f for c, f in combo.items() if c != CONSTANT},
                1.0, "constant, then the other loads in proportion")
    return None


def combination_at(const: dict, var: dict, p: float) -> dict:
    """The combination ``const`` + p ``var`` ({case: factor}): the load at p
    along a frame's path."""
    return {c: const.get(c, 0.0) + p * var.get(c, 0.0) for c in set(const) | set(var)}
