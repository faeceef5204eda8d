"""Exception classes of qpcontact.

Misuse (a malformed problem, a method that cannot handle a problem, a backend
that is not installed) raises one of these; numerical outcomes (an inaccurate
answer, a backend failure) are reported through ``Solution.status`` instead,
unless ``solve(..., raise_on_failure=True)`` asks for an exception.

Every message says what is wrong and what to do about it.
"""

from __future__ import annotations

__all__ = [
    "QpcontactError",
    "InvalidProblemError",
    "NotSymmetricError",
    "NotConvexError",
    "NoApplicableMethodError",
    "InvalidOptionError",
    "UnknownMethodError",
    "BackendUnavailableError",
    "NoSolutionError",
    "SolverFailedError",
]


class QpcontactError(Exception):
    """Base class of every exception raised on purpose by qpcontact."""


class InvalidProblemError(QpcontactError, ValueError):
    """Problem data are malformed: wrong shape, non-finite or complex values,
    an empty problem, or a file that does not follow its format."""


class NotSymmetricError(QpcontactError, ValueError):
    """The method needs a symmetric matrix and was given a nonsymmetric one."""


class NotConvexError(QpcontactError, ValueError):
    """The method needs a (semi)definite matrix and the matrix is not."""


class NoApplicableMethodError(QpcontactError, ValueError):
    """No installed method applies to the problem: none solves its kind, or
    each refuses its structure (a nonsymmetric or indefinite M, a size beyond
    its limit).  The message lists what was considered; `qpcontact methods`
    says what each method requires and how to install the missing ones."""


class InvalidOptionError(QpcontactError, ValueError):
    """An accuracy level or a method option is not understood."""


class UnknownMethodError(QpcontactError, ValueError):
    """No method of that name exists (installed or not)."""


class BackendUnavailableError(QpcontactError, ImportError):
    """The method exists but the package that provides it is not installed."""


class NoSolutionError(QpcontactError):
    """The problem was shown to have no solution (raised only on request)."""


class SolverFailedError(QpcontactError):
    """The method returned no certified solution (raised only on request)."""
