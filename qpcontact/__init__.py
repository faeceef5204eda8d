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

from .core.accuracy import LEVELS
from .core.conversions import DualLCP, qp_to_lcp
from .core.errors import (BackendUnavailableError, InvalidOptionError, InvalidProblemError,
                          NoSolutionError, NotConvexError, NotSymmetricError, QpcontactError,
                          SolverFailedError, UnknownMethodError)
from .core.problems import LCP, ParametricLCP
from .core.results import (STATUSES, FrictionSolution, LCPSolution, MethodResult, QPSolution,
                           Solution)
from .dispatch.driver import solve, solve_friction
from .friction.measures import FrictionCertificate
from .friction.problem import FrictionProblem
from .judge.certify import certify
from .judge.lcp import LCPCertificate
from .judge.qp import QPCertificate
from .solvers.method import Method
from .solvers.registry import all_methods, get_method, methods, register

__version__ = "0.1.0"

__all__ = [
    "LCP", "ParametricLCP", "FrictionProblem", "qp_to_lcp", "DualLCP",
    "solve", "solve_friction", "certify", "methods", "all_methods", "get_method", "register",
    "Method", "Solution", "LCPSolution", "QPSolution", "FrictionSolution", "MethodResult",
    "LCPCertificate", "QPCertificate", "FrictionCertificate", "LEVELS", "STATUSES",
    "QpcontactError", "InvalidProblemError", "NotSymmetricError", "NotConvexError",
    "InvalidOptionError", "UnknownMethodError", "BackendUnavailableError",
    "NoSolutionError", "SolverFailedError",
]
