"""One vocabulary for every answer: the statuses, and the result types.

Modelled on ``scipy.optimize.OptimizeResult``: a ``status`` word, a
``message``, counts and timings, plus the certificate computed from the
problem data (:mod:`qpcontact.judge`).  Every problem kind — LCP, QP, load
trace, frictional contact — answers with a :class:`Solution` that has the
same fields; each kind adds its own variables (``z``/``w``; ``x``/``y``/
``z``/``z_box``; the trace's pieces; ``r``/``u``/``v``).  Plain dataclasses
of arrays and numbers, so they pickle (a sweep can run on Dask unchanged).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # the judge's types, for the annotations only
    from ..judge.lcp_certificate import LCPCertificate
    from ..judge.qp_certificate import QPCertificate

__all__ = ["Solution", "LCPSolution", "QPSolution", "FrictionSolution", "MethodResult",
           "STATUSES", "PROVED"]

#: Every status an answer can have, for every problem kind, and what it means.
#: ``ok`` is True for "solved" alone.
STATUSES = {
    "solved": "the certificate computed from the data meets the requested tolerance",
    "inaccurate": "a point came back but its certificate misses the tolerance, whatever the "
                  "method said about it",
    "ill_posed": "a point came back whose residuals are small, but the data are within "
                 "rounding of a problem with no solution — its residuals are small only on "
                 "scales that grew with it (normwise error far above the componentwise one), "
                 "or it has no digit guaranteed beside a vector that is a Farkas vector to "
                 "rounding, or a frictional problem's loads are within rounding of the "
                 "friction limit — and no proof either way could be checked exactly; no digit "
                 "of the answer is guaranteed (it is kept)",
    "failed": "no usable point came back (the method gave up, raised, or claimed no solution "
              "exists without a proof; its own words are kept in backend_status)",
    "time_limit": "the call was stopped by solve(..., time_limit=) and no certified point came "
                  "back",
    "infeasible": "no solution exists, proved from the data: a Farkas vector (an LCP or a QP: "
                  "no point satisfies the constraints), or a motion on which the loads do work "
                  "that no reactions within the friction cones can resist (frictional contact); "
                  "the proof is in stats['proof']",
    "unbounded": "a QP's objective falls without bound along a ray checked from the data "
                 "(stats['proof'])",
    "ray": "a pivoting method ended on a secondary ray and nothing is proved (where a Farkas "
           "vector was checked from the data the status is \"infeasible\", whichever method "
           "found it)",
    "max_pivots": "a pivoting method reached its pivot or piece limit",
}

#: the statuses that say "no solution exists" with a proof checked from the data
PROVED = ("infeasible", "unbounded")


@dataclass(kw_only=True)
class MethodResult:
    """What a registered method returns to :func:`qpcontact.solve`, before
    certification.  ``x`` is the primal vector (the LCP's z, the QP's x, a
    frictional problem's r — or (r, v) for a global one), None when the
    method produced nothing usable.  Multipliers follow qpsolvers'
    conventions.  ``status`` may force a pivoting outcome ("ray",
    "max_pivots", "time_limit"); otherwise the certificate decides.
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


def _short(value) -> str:
    """A value as a person reads it in a repr: arrays summarised, never dumped."""
    if isinstance(value, np.ndarray):
        if value.size <= 6:
            return np.array2string(value, precision=4, separator=", ")
        head = np.array2string(value[:3], precision=4, separator=", ")[:-1]
        return f"{head}, ...] ({value.size} entries)"
    if isinstance(value, float):
        return f"{value:.3e}"
    return repr(value)


@dataclass(kw_only=True, repr=False)
class Solution:
    """Common fields of every certified result.

    Attributes
    ----------
    method : str
        Registered name of the method that ran.
    status : str
        One of :data:`STATUSES`.
    ok : bool
        True only when the certificate meets ``tol`` ("solved").
    message : str
        One line for a person: what happened and, when not ok, what to try.
    accuracy : str or float
        What was asked.
    tol : float
        The tolerance the certificate was held to.
    certificate : LCPCertificate, QPCertificate, FrictionCertificate or None
        None only when no point came back.
    backend_status, backend_message : str
        The method's own verdict, kept verbatim, never believed alone.
    wall_time : float
        Seconds for the whole method call, conversions included, certification
        excluded (qpsolvers' build/solve split differs per backend).
    iterations : int or None
        Iterations or pivots, when the method reports them.
    stats : dict
        Method-specific extras (conversion route, fallback flags, the proof,
        what "auto" tried: ``stats["auto_tried"]``, ...).
    """

    method: str
    status: str
    ok: bool
    message: str
    accuracy: str | float
    tol: float
    certificate: LCPCertificate | QPCertificate | object | None
    backend_status: str = ""
    backend_message: str = ""
    wall_time: float = 0.0
    iterations: int | None = None
    stats: dict = field(default_factory=dict)

    #: the kind's own variables, shown by the repr
    _variables = ()

    @property
    def error(self) -> float:
        """The certificate's error, the one held to ``tol`` (componentwise);
        inf when no point came back."""
        return self.certificate.error if self.certificate is not None else float("inf")

    @property
    def forward_error(self) -> float:
        """Estimated largest distance of a component of the answer from the
        exact solution of the data as stored, relative to its own size
        (condition times error); inf when no point came back, the solution is
        not isolated, or the kind has no estimate."""
        if self.certificate is None:
            return float("inf")
        return float(getattr(self.certificate, "forward_error", float("inf")))

    def __repr__(self) -> str:
        rows = [("method", repr(self.method)),
                ("status", f"{self.status!r} ({'ok' if self.ok else 'not ok'})"),
                ("message", self.message),
                ("error", f"{self.error:.2e} (tol {self.tol:.0e})"),
                ("iterations", repr(self.iterations)),
                ("wall_time", f"{self.wall_time:.4g} s")]
        rows += [(name, _short(getattr(self, name))) for name in self._variables
                 if getattr(self, name) is not None]
        width = max(len(k) for k, _ in rows)
        body = "\n".join(f"  {k.rjust(width)}: {v}" for k, v in rows)
        return f"{type(self).__name__}\n{body}"

    def as_dict(self) -> dict:
        """The fields as a plain dict (the certificate as its own dict)."""
        out = {f.name: getattr(self, f.name) for f in fields(self)}
        if self.certificate is not None:
            out["certificate"] = self.certificate.as_dict()
        return out


@dataclass(kw_only=True, repr=False)
class LCPSolution(Solution):
    """A certified answer to an LCP: ``z`` and ``w = Mz + q`` (recomputed from
    the problem data, never taken from the method)."""

    z: np.ndarray | None
    w: np.ndarray | None

    _variables = ("z", "w")


@dataclass(kw_only=True, repr=False)
class QPSolution(Solution):
    """A certified answer to a QP, with multipliers in qpsolvers' conventions."""

    x: np.ndarray | None
    y: np.ndarray | None = None
    z: np.ndarray | None = None
    z_box: np.ndarray | None = None

    _variables = ("x", "y", "z", "z_box")


@dataclass(kw_only=True, repr=False)
class FrictionSolution(Solution):
    """A certified answer to a frictional contact problem: the reactions ``r``
    (force, or impulse), the local velocities ``u`` (recomputed from the data:
    u = W r + q, or Hᵀv + w for a global problem kept without W) and, for a
    global problem, the global velocity ``v``.  ``error`` is the larger of
    Siconos's natural-map error and the componentwise one (and the
    equilibrium's, globally); each is also here on its own."""

    r: np.ndarray | None
    u: np.ndarray | None
    v: np.ndarray | None = None

    _variables = ("r", "u", "v")

    def _measure(self, name: str) -> float:
        return getattr(self.certificate, name) if self.certificate is not None else float("inf")

    def __repr__(self) -> str:
        text = super().__repr__()
        if self.ok and self.certificate is not None and self.certificate.isolated is False:
            text += ("\n  not unique: the reactions are one point of a set (redundant contacts: "
                     "the forward error is unbounded); qpcontact.unique_reactions(problem, sol) "
                     "gives the minimum-norm one")
        return text

    @property
    def natural_map_error(self) -> float:
        """Siconos's error ‖r − proj_K(r − û)‖ / (1 + ‖q‖) (over 1 + ‖f‖ globally)."""
        return self._measure("natural_map_error")

    @property
    def componentwise_error(self) -> float:
        """The worst contact's natural-map residual on its own force scale."""
        return self._measure("componentwise_error")

    @property
    def equilibrium_error(self) -> float:
        """A global problem's Mv = Hr + f, each equation on its own scale (nan
        for a local problem)."""
        return self._measure("equilibrium_error")
