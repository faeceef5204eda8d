"""Result objects: what a method computed, certified from the problem data.

Modelled on ``scipy.optimize.OptimizeResult``: a ``status`` string, a
``message``, counts and timings, plus the certificate.  Plain dataclasses of
arrays and numbers, so they pickle (a sweep can run on Dask unchanged).

Statuses
--------
``"solved"``      the certificate meets the requested tolerance (``ok`` is True)
``"inaccurate"``  a point came back but its certificate misses the tolerance —
                  whatever the backend said about it
``"failed"``      no point came back (the backend gave up, raised, or said the
                  problem is infeasible — its claim is kept in ``backend_status``)
``"time_limit"``  the backend call was stopped by ``solve(..., time_limit=)``
                  (by the backend's own setting, or killed in its child
                  process) and no certified point came back
``"infeasible"``, ``"unbounded"``
                  no solution exists (an LCP: infeasible; a QP: infeasible or
                  unbounded), proved by a Farkas vector or a ray checked from
                  the data (``stats["proof"]``, qpcontact.proofs).  Also
                  replaces a certified answer that only nearby data have (a
                  point at 1e8 on an unbounded QP)
``"ray"``, ``"max_pivots"``
                  reserved for pivoting methods (a secondary ray, or with
                  ``stats["proved_infeasible"]`` a checked Farkas vector; the
                  pivot cap)
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..judge.lcp import LCPCertificate
from ..judge.qp import QPCertificate

__all__ = ["Solution", "LCPSolution", "QPSolution", "MethodResult", "STATUSES"]

STATUSES = ("solved", "inaccurate", "failed", "time_limit", "infeasible", "unbounded", "ray",
            "max_pivots")


@dataclass(kw_only=True)
class MethodResult:
    """What a registered method returns to :func:`qpcontact.solve`, before
    certification.  ``x`` is the primal vector (the LCP's z, or the QP's x),
    None when the method produced nothing usable.  Multipliers follow
    qpsolvers' conventions.  ``status`` may force a pivoting outcome ("ray",
    "max_pivots"); otherwise the certificate decides.
    """

    x: np.ndarray | None
    y: np.ndarray | None = None
    z: np.ndarray | None = None
    z_box: np.ndarray | None = None
    backend_status: str = ""
    backend_message: str = ""
    iterations: int | None = None
    status: str | None = None
    stats: dict = field(default_factory=dict)


@dataclass(kw_only=True)
class Solution:
    """Common fields of every certified result.

    Attributes
    ----------
    method : str
        Registered name of the method that ran.
    status : str
        One of :data:`STATUSES` (see the module docstring).
    ok : bool
        True only when the certificate meets ``tol``.
    message : str
        One line for a person: what happened and, when not ok, what to try.
    accuracy : str or float
        What was asked.
    tol : float
        The tolerance the certificate was held to.
    certificate : LCPCertificate or QPCertificate or None
        None only when no point came back.
    backend_status, backend_message : str
        The backend's own verdict, kept verbatim, never believed alone.
    wall_time : float
        Seconds for the whole method call, conversions included, certification
        excluded (qpsolvers' build/solve split differs per backend).
    iterations : int or None
        Iterations or pivots, when the method reports them.
    stats : dict
        Method-specific extras (conversion route, fallback flags, ...).
    """

    method: str
    status: str
    ok: bool
    message: str
    accuracy: str | float
    tol: float
    certificate: LCPCertificate | QPCertificate | None
    backend_status: str = ""
    backend_message: str = ""
    wall_time: float = 0.0
    iterations: int | None = None
    stats: dict = field(default_factory=dict)

    @property
    def error(self) -> float:
        """The certificate's componentwise (backward) error; inf when no point came back."""
        return self.certificate.error if self.certificate is not None else float("inf")


@dataclass(kw_only=True)
class LCPSolution(Solution):
    """A certified answer to an LCP: ``z`` and ``w = Mz + q`` (recomputed from
    the problem data, never taken from the method)."""

    z: np.ndarray | None
    w: np.ndarray | None

    @property
    def forward_error(self) -> float:
        """Estimated largest distance of a component of (z, w) from the exact
        solution of the data as stored, relative to its own size (the
        certificate's condition times its error); inf when no point came back
        or the solution is not isolated."""
        return self.certificate.forward_error if self.certificate is not None else float("inf")


@dataclass(kw_only=True)
class QPSolution(Solution):
    """A certified answer to a QP, with multipliers in qpsolvers' conventions."""

    x: np.ndarray | None
    y: np.ndarray | None = None
    z: np.ndarray | None = None
    z_box: np.ndarray | None = None
