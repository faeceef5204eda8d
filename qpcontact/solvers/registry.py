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

#: The providers, in the order a listing shows them.
PROVIDERS = ("pivoting", "trace", "friction", "qpsolvers", "cvxpy")
#: The in-house providers' method names, known without importing them, so that
#: asking for one method loads its provider only (tests/dispatch/test_solve.py holds
#: them to the providers' specs()).
IN_HOUSE = {
    "pivoting": ("energy", "bpp", "ip-bpp", "mg-bpp", "lemke", "enumeration"),
    "trace": ("trace",),
    "friction": ("nsgs", "nsgs-newton", "nsgs-restarts", "anitescu", "desaxce-fp", "tresca-fp",
                 "newton", "vi-eg", "ip-lcp", "desaxce-global"),
}
_loaded: set = set()


def register(method: Method, *, replace: bool = False) -> None:
    """Add a method to the registry (``replace=True`` to override a name)."""
    if method.name in _REGISTRY and not replace and _REGISTRY[method.name].available:
        raise ValueError(f"a method named {method.name!r} is already registered")
    _REGISTRY[method.name] = method


def _load(provider: str) -> None:
    """Register one provider's methods (once)."""
    if provider in _loaded:
        return
    _loaded.add(provider)
    if provider == "pivoting":
        from .pivoting import pivoting_specs as module
    elif provider == "trace":
        from .trace import trace_specs as module
    elif provider == "friction":
        from .friction import friction_specs as module
    elif provider == "qpsolvers":
        from .backends import qpsolvers_backends as module
    else:
        from .backends import cvxpy_backends as module
    for m in module.specs():
        register(m, replace=True)


def _ensure_loaded(cvxpy: bool = True) -> None:
    """Register every provider.  cvxpy costs a second to import, so it is
    loaded only when a listing or a ``cvxpy:`` name needs it."""
    for provider in PROVIDERS:
        if provider != "cvxpy" or cvxpy:
            _load(provider)


def _provider_of(name: str) -> str:
    for provider, names in IN_HOUSE.items():
        if name.lower() in names:
            return provider
    return "cvxpy" if name.lower().startswith("cvxpy:") else "qpsolvers"


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
    if name not in _REGISTRY:
        _load(_provider_of(name))
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
        installed = ", ".join(sorted(n for n, m in known.items() if m.available))
        raise UnknownMethodError(
            f"no method named {name!r}.{hint} The installed methods: {installed} "
            "(`qpcontact methods` says what each one solves)."
        )
    if not m.available:
        raise BackendUnavailableError(
            f"method {m.name!r} is not installed on this machine; install it with: {m.install}"
        )
    return m
