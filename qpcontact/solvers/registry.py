"""The one registry of interchangeable methods, every problem kind together.

A method (:class:`~qpcontact.solvers.method.Method`) is registered under a
name with its capabilities.  The providers — the pivoting methods, the QP
backends qpsolvers finds, cvxpy's solvers, the friction methods, the load
trace — each declare their methods in one small module (a ``specs()``
function) and are loaded on first use of the registry, so ``import
qpcontact`` stays cheap; they never import the registry.
"""

from __future__ import annotations

import difflib

from ..core.errors import BackendUnavailableError, UnknownMethodError
from .method import Method

__all__ = ["Method", "register", "methods", "get_method", "all_methods"]


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
        from ..friction import specs as friction
        from .backends import qpsolvers_backends
        from .pivoting import specs as pivoting
        from .trace import specs as trace

        for provider in (pivoting, trace, friction, qpsolvers_backends):
            for m in provider.specs():
                register(m, replace=True)
    if cvxpy and not _loaded_cvxpy:
        _loaded_cvxpy = True
        from .backends import cvxpy_backends

        for m in cvxpy_backends.specs():
            register(m, replace=True)


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
