"""The names the command-line options accept, read from the registries, and
the refusal of any other name.

An unknown name (a formulation, a method, a family of hard cases) stops the
command before it runs, with exit code 2 and the valid names listed; so does
a data folder that was asked for and is not there.  The option help lists the
same names, read when the help is shown: the formulations are entry points
(``qpcontact.formulations``) and the methods the registry's providers, which
cost about a second to load, more than a command line should pay to start.
"""

from __future__ import annotations

import math
from pathlib import Path

import typer
from typer.core import TyperCommand

from ..core.files import data_locations, missing_data

__all__ = ["DATA_FORMULATIONS", "formulation_names", "method_names", "family_names", "split_names",
           "data_folder", "RegistryHelp", "positive_seconds", "at_least"]

#: compare's formulations that are data sets, not entry points: name -> the data set
DATA_FORMULATIONS = {"siconos": "siconos-lcp", "friction": "siconos-fc"}


def formulation_names() -> list[str]:
    """compare's formulations: the installed ones that build instances
    (``instances(size, hardness, seed)``), then the data sets."""
    from importlib.metadata import entry_points

    names = [ep.name for ep in sorted(entry_points(group="qpcontact.formulations"),
                                      key=lambda e: e.name)
             if hasattr(ep.load(), "instances")]
    return names + list(DATA_FORMULATIONS)


def method_names(cvxpy: bool = True) -> list[str]:
    """The installed methods and "auto" (``cvxpy=False``: without cvxpy's,
    whose import alone costs a second)."""
    from ..solvers.registry import methods

    return ["auto"] + sorted(name for name, m in methods().items()
                             if cvxpy or m.family != "cvxpy")


def family_names() -> list[str]:
    """The families of hard cases of ``qpcontact stress``."""
    from .stress import FAMILIES

    return list(FAMILIES)


def split_names(value: str | None, valid, option: str, what: str) -> list[str] | None:
    """The comma-separated names of ``option`` (None when not given), each
    one of ``valid`` (a list, or a function returning it, called only when
    the option is given); otherwise typer.BadParameter naming the unknown
    ones and listing the valid ones."""
    if value is None:
        return None
    names = [v.strip() for v in value.split(",") if v.strip()]
    if not names:
        raise typer.BadParameter(f"no {what} given", param_hint=option)
    valid = list(valid() if callable(valid) else valid)
    unknown = [n for n in names if n not in valid]
    if unknown:
        raise typer.BadParameter(
            f"unknown {what} {', '.join(map(repr, unknown))}; choose from {', '.join(valid)}",
            param_hint=option)
    return names


def data_folder(data_set: str, *, folder=None, root=None, required_by: str | None = None):
    """(folder, note) for the data set ``data_set`` ("siconos-lcp"): ``folder``
    when given (--siconos: it must exist), else ``root/data_set`` when
    ``root`` is given (--data: it must exist), else where find_data finds it.
    Not found: typer.BadParameter when the option ``required_by`` asked for
    the data set, else (None, a note saying where it was looked for and how
    to point at it)."""
    if folder is not None:
        folder = Path(folder).expanduser()
        if not folder.is_dir():
            raise typer.BadParameter(f"{folder}: no such folder (expected {data_set}/ files)",
                                     param_hint="'--siconos'")
        return folder, None
    if root is not None:
        root = Path(root).expanduser()
        if not root.is_dir():
            raise typer.BadParameter(f"{root}: no such folder", param_hint="'--data'")
        places = [root / data_set]
    else:
        places = data_locations(data_set)
    found = next((p for p in places if p.is_dir()), None)
    if found is not None:
        return found, None
    why = missing_data(data_set, "--data DIR", places)
    if required_by:
        raise typer.BadParameter(why, param_hint=required_by)
    return None, f"skipped: {why}"


#: placeholders of the option help -> the names they stand for
_HELP_NAMES = {
    "{formulations}": formulation_names,
    "{methods}": lambda: method_names(cvxpy=False),
    "{families}": family_names,
}


class RegistryHelp(TyperCommand):
    """A command whose option help names what the registries hold, read only
    when the help is shown."""

    def format_help(self, ctx, formatter) -> None:
        cache = {}
        for param in self.params:
            text = getattr(param, "help", None) or ""
            for token, names in _HELP_NAMES.items():
                if token in text:
                    if token not in cache:
                        cache[token] = ", ".join(names())
                    text = text.replace(token, cache[token])
            if text:
                param.help = text
        super().format_help(ctx, formatter)


def positive_seconds(value, option: str):
    """``value`` (None: the command's default) when it is a positive, finite
    number of seconds; else typer.BadParameter naming it (exit code 2)."""
    if value is not None and not (math.isfinite(value) and value > 0):
        raise typer.BadParameter(f"{value!r}: expected a positive, finite number of seconds",
                                 param_hint=f"'{option}'")
    return value


def at_least(value, least: int, option: str, what: str):
    """``value`` (None: the command's default) when it is >= ``least``;
    else typer.BadParameter naming it and saying what it counts."""
    if value is not None and value < least:
        raise typer.BadParameter(f"{value!r}: expected {what}, an integer >= {least}",
                                 param_hint=f"'{option}'")
    return value
