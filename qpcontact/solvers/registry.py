"""Registry of interchangeable methods.

A method is a function ``run(problem, tol, options) -> MethodResult`` registered
under a name with declared capabilities.  ``tol`` is the tolerance to ask of the
backend, or None for its own defaults; ``options`` are passed through to the
backend as keyword arguments.  A backend's ``run`` may also take
``time_limit=`` (seconds or None), which :func:`qpcontact.solve` then passes.  :func:`qpcontact.solve` converts the problem to
the kind the method takes ("qp" or "lcp"), times the call, and certifies the
answer: methods never certify themselves.

Backends live one small module each (``qpsolvers_backends``, ``cvxpy_backends``)
and register on first use of the registry, so ``import qpcontact`` stays cheap.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from typing import Callable

from ..core.errors import BackendUnavailableError, UnknownMethodError

__all__ = ["Method", "register", "methods", "get_method", "all_methods"]


@dataclass(frozen=True)
class Method:
    """A registered method and what it can do.

    Attributes
    ----------
    name : str
        Registry key, e.g. ``"osqp"`` or ``"cvxpy:CLARABEL"``.
    run : callable
        ``run(problem, tol, options) -> MethodResult``.
    takes : {"qp", "lcp"}
        The problem kind the function accepts; :func:`qpcontact.solve` converts.
    requires : {"monotone", "spd", "any"}
        What an LCP's M must be: M + M' PSD (any convex QP route), symmetric
        positive definite, or anything.
    accepts_sparse : bool
        Works on sparse matrices without densifying them.
    returns_duals : bool
        Gives the QP multipliers (for LCPs, w is recomputed anyway).
    algorithm : str
        "active-set", "interior-point", "ADMM", "augmented-Lagrangian",
        "pivoting", ...
    exact : bool
        Finite termination at an exact answer up to rounding (active-set and
        pivoting methods) rather than convergence to a tolerance.
    family : str
        "qpsolvers", "cvxpy" or "pivoting".
    install : str
        The command that installs what the method needs.
    available : bool
        Installed on this machine.
    constraints : {"any", "lower-bounds"}
        The QPs it takes: any, or only those whose sole constraints are lower
        bounds x_i >= l_i (an LCP's QP form, the mixed contact problem).
    max_n : int or None
        The largest problem it takes ("enumeration": 16), or None.
    """

    name: str
    run: Callable | None
    takes: str
    requires: str
    accepts_sparse: bool
    returns_duals: bool
    algorithm: str
    exact: bool
    family: str
    install: str
    available: bool = True
    constraints: str = "any"
    max_n: int | None = None

    @property
    def needs_symmetric(self) -> bool:
        return self.requires == "spd"


_REGISTRY: dict[str, Method] = {}
_loaded = False


def register(method: Method, *, replace: bool = False) -> None:
    """Add a method to the registry (``replace=True`` to override a name)."""
    if method.name in _REGISTRY and not replace and _REGISTRY[method.name].available:
        raise ValueError(f"a method named {method.name!r} is already registered")
    _REGISTRY[method.name] = method


_loaded_cvxpy = False


def _ensure_loaded(cvxpy: bool = True) -> None:
    """Register the backends on first use.  cvxpy costs a second to import, so
    it is loaded only when a listing or a ``cvxpy:`` name needs it."""
    global _loaded, _loaded_cvxpy
    if not _loaded:
        _loaded = True
        from .pivoting import specs as pivoting
        from .backends import qpsolvers_backends

        pivoting.register_all()
        qpsolvers_backends.register_all()
    if cvxpy and not _loaded_cvxpy:
        _loaded_cvxpy = True
        from .backends import cvxpy_backends

        cvxpy_backends.register_all()


def all_methods() -> dict[str, Method]:
    """Every known method, installed or not."""
    _ensure_loaded()
    return dict(_REGISTRY)


def methods() -> dict[str, Method]:
    """The methods usable on this machine, by name, with their capabilities."""
    return {name: m for name, m in all_methods().items() if m.available}


def get_method(name: str) -> Method:
    """Look a method up by name.

    Raises
    ------
    BackendUnavailableError
        The method is known but its package is not installed (the message has
        the pip command).
    UnknownMethodError
        No method of that name exists (the message suggests close names).
    """
    _ensure_loaded(cvxpy=False)
    known = _REGISTRY
    if name not in known:
        known = all_methods()
    m = known.get(name)
    if m is None and ":" in name:  # cvxpy solver names are upper case
        family, solver = name.split(":", 1)
        m = known.get(f"{family.lower()}:{solver.upper()}")
    if m is None:
        m = known.get(name.lower())
    if m is None:
        close = difflib.get_close_matches(name, list(known), n=3)
        hint = f" Did you mean {', '.join(map(repr, close))}?" if close else ""
        raise UnknownMethodError(
            f"no method named {name!r}.{hint} `qpcontact methods` lists the installed ones."
        )
    if not m.available:
        raise BackendUnavailableError(
            f"method {m.name!r} is not installed on this machine; install it with: {m.install}"
        )
    return m
