"""Certificates: residuals computed from the problem data and a candidate point.

Nothing a backend reports about its own answer is used here.  Every method's
answer goes through :func:`certify`, the shared error measure (in the spirit of
Siconos' ``lcp_compute_error``), so numbers mean the same for every method.
docs/certificates.md gives the definitions with their reasons and the
far-contact example that made them componentwise.

:func:`certify` takes any problem kind; the measures live one module each:
:mod:`qpcontact.judge.lcp_certificate`, :mod:`qpcontact.judge.qp_certificate` (and the friction
measures of :mod:`qpcontact.judge.friction_certificate`), on the componentwise scales
of :mod:`qpcontact.judge.scales`.
"""

from __future__ import annotations

from ..core.conversions import is_qp
from ..core.errors import InvalidProblemError
from ..core.problems import LCP
from .friction_certificate import FrictionCertificate, certify_friction
from ..core.friction_problem import FrictionProblem
from .lcp_certificate import LCPCertificate, certify_lcp
from .qp_certificate import QPCertificate, certify_qp

__all__ = ["certify", "LCPCertificate", "QPCertificate", "FrictionCertificate"]


def certify(problem, x, *, y=None, z=None, z_box=None, v=None):
    """Certify a candidate solution from the problem data alone.

    Parameters
    ----------
    problem : LCP, qpsolvers.Problem or FrictionProblem
    x : array_like
        For an LCP, the candidate z; for a QP, the candidate primal x; for a
        frictional problem, the reactions r.
    y, z, z_box : array_like, optional
        QP multipliers in qpsolvers' conventions (equalities, inequalities,
        bounds).  Required for the QP constraints the problem has.
    v : array_like, optional
        The global velocity of a frictional problem kept without W (required
        there).

    Returns
    -------
    LCPCertificate, QPCertificate or FrictionCertificate
        ``cert.error`` is the componentwise measure compared with the requested
        tolerance (``cert.ok(tol)``), ``cert.forward_error`` where defined; see
        each type for its fields.
    """
    if isinstance(problem, LCP):
        return certify_lcp(problem, x)
    if is_qp(problem):
        return certify_qp(problem, x, y, z, z_box)
    if isinstance(problem, FrictionProblem):
        return certify_friction(problem, x, v)
    raise InvalidProblemError(f"cannot certify a {type(problem).__name__}; expected an LCP, a "
                              "qpsolvers.Problem or a FrictionProblem")
