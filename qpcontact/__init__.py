"""qpcontact: mechanics with contact and unilateral constraints, written as
LCPs, QPs and frictional contact problems, solved by interchangeable methods
on one accuracy ladder and certified from the data.

Quick start::

    import qpcontact
    lcp = qpcontact.LCP([[2, 1], [1, 2]], [-5, -6])
    sol = qpcontact.solve(lcp, method="clarabel", accuracy="high")
    sol.z, sol.ok, sol.certificate.error

One entry point (:func:`solve`) for every kind — ``LCP``, ``qpsolvers.Problem``,
``ParametricLCP``, ``FrictionProblem`` —, one registry (:func:`methods`), one
status vocabulary (:data:`STATUSES`), one certificate interface
(:func:`certify`).  The layout is drawn in docs/architecture.md.
"""

from importlib import import_module

__version__ = "0.1.0"

#: Where each public name is defined.  The names are imported on first use
#: (PEP 562, as SciPy and scikit-image do: Scientific Python SPEC 1), so that
#: ``import qpcontact`` and ``qpcontact --help`` cost no NumPy or SciPy, and
#: the engine costs what it uses (tests/package/test_import_cost.py).
_DEFINED_IN = {
    "LCP": "core.problems", "ParametricLCP": "core.problems",
    "FrictionProblem": "core.friction_problem",
    "qp_to_lcp": "core.conversions", "DualLCP": "core.conversions",
    "solve": "dispatch.driver", "solve_friction": "dispatch.driver",
    "unique_reactions": "solvers.friction.unique_reactions",
    "certify": "judge.certify",
    "methods": "solvers.registry", "all_methods": "solvers.registry",
    "get_method": "solvers.registry", "register": "solvers.registry",
    "Method": "solvers.method",
    "Solution": "core.results", "LCPSolution": "core.results", "QPSolution": "core.results",
    "FrictionSolution": "core.results", "MethodResult": "core.results",
    "LCPCertificate": "judge.lcp_certificate", "QPCertificate": "judge.qp_certificate",
    "FrictionCertificate": "judge.friction_certificate",
    "LEVELS": "core.accuracy", "STATUSES": "core.results",
    **dict.fromkeys(("QpcontactError", "InvalidProblemError", "NotSymmetricError", "NotConvexError",
                     "NoApplicableMethodError", "InvalidOptionError", "UnknownMethodError", "BackendUnavailableError",
                     "NoSolutionError", "SolverFailedError"), "core.errors"),
}
_SUBPACKAGES = ("cases", "commands", "core", "dispatch", "io", "judge", "plots", "proofs",
                "scenes", "solvers", "testing")

__all__ = list(_DEFINED_IN)


def __getattr__(name: str):
    if name in _DEFINED_IN:
        value = getattr(import_module(f".{_DEFINED_IN[name]}", __name__), name)
    elif name in _SUBPACKAGES:
        value = import_module(f".{name}", __name__)
    else:
        raise AttributeError(f"module 'qpcontact' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__) | set(_SUBPACKAGES))
