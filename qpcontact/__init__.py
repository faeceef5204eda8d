"""qpcontact: mechanics with contact and unilateral constraints, written as
LCPs and QPs, solved by interchangeable backends and certified from the data.

Quick start::

    import qpcontact
    lcp = qpcontact.LCP([[2, 1], [1, 2]], [-5, -6])
    sol = qpcontact.solve(lcp, method="clarabel", accuracy="high")
    sol.z, sol.ok, sol.certificate.error
"""

from .core.accuracy import LEVELS
from .judge.lcp import LCPCertificate
from .judge.qp import QPCertificate
from .judge.certify import certify
from .core.conversions import DualLCP, qp_to_lcp
from .core.errors import (BackendUnavailableError, InvalidOptionError, InvalidProblemError,
                          NoSolutionError, NotConvexError, NotSymmetricError, QpcontactError,
                          SolverFailedError, UnknownMethodError)
from .solvers.registry import Method, all_methods, get_method, methods, register
from .core.problems import LCP, ParametricLCP
from .friction.problem import FrictionProblem
from .core.results import LCPSolution, MethodResult, QPSolution, Solution
from .dispatch.driver import solve

__version__ = "0.1.0"

__all__ = [
    "LCP", "ParametricLCP", "FrictionProblem", "qp_to_lcp", "DualLCP",
    "solve", "certify", "methods", "all_methods", "get_method", "register", "Method",
    "Solution", "LCPSolution", "QPSolution", "MethodResult", "LCPCertificate", "QPCertificate",
    "LEVELS",
    "QpcontactError", "InvalidProblemError", "NotSymmetricError", "NotConvexError",
    "InvalidOptionError", "UnknownMethodError", "BackendUnavailableError",
    "NoSolutionError", "SolverFailedError",
]
