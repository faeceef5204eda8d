"""The friction methods as registered methods (the order "auto" tries them in
is the dispatcher's: :func:`qpcontact.dispatch.routes.auto_chain`).

Each method's function returns (r or (r, v), its own status, a message,
stats); the run functions below hand that to the engine as a MethodResult,
which the engine certifies by :mod:`qpcontact.judge.friction_certificate`.  "lemke"
and "enumeration" (registered with the pivoting methods) reach frictional
problems through their LCP (:mod:`qpcontact.solvers.friction.lcp_route`).
"""

from __future__ import annotations

import numpy as np

from ...core.results import MethodResult
from ..method import Method
from .fixed_points import solve_anitescu, solve_desaxce_fp, solve_desaxce_global, solve_tresca_fp
from .newton import solve_natural_newton
from .hybrid import solve_nsgs_newton
from .interior_lcp import solve_ip_lcp
from .nsgs import solve_nsgs
from .projected_gradient import solve_vi_eg
from .restarts import solve_nsgs_restarts

__all__ = ["specs"]

def _run(function, takes_engine: bool = False, timed: bool = True):
    """The registry's run for ``function``: ``engine`` for the methods that
    solve subproblems through it, and ``solve``'s ``time_limit`` as the
    iterative methods' own option (they check it between iterations)."""
    def run(problem, tol, options, engine=None, time_limit=None) -> MethodResult:
        options = dict(options)
        if takes_engine and engine is not None:
            options["engine"] = engine
        if timed and time_limit is not None:
            options.setdefault("time_limit", time_limit)
        x, status, message, stats = function(problem, tol, options)
        if x is not None:
            x = np.asarray(x, float)
        return MethodResult(x=x, backend_status=str(status), backend_message=message,
                            iterations=stats.get("iterations"), stats=stats)
    run.__doc__ = function.__doc__
    return run


_INSTALL = "pip install qpcontact"
_LOCAL = ("friction-2d", "friction-3d")


def specs() -> list[Method]:
    common = dict(requires="any", accepts_sparse=True, returns_duals=False, exact=False,
                  family="friction", install=_INSTALL)
    return [
        Method("nsgs", _run(solve_nsgs), takes="friction",
               algorithm="nonsmooth Gauss-Seidel (Siconos NSGS)", **common),
        Method("nsgs-newton", _run(solve_nsgs_newton), takes="friction",
               algorithm="NSGS, then minimum-norm semismooth Newton steps", **common),
        Method("nsgs-restarts", _run(solve_nsgs_restarts), takes="friction",
               algorithm="NSGS + Newton, restarted from random reactions within the cones",
               **common),
        Method("anitescu", _run(solve_anitescu, True, timed=False), takes="friction",
               algorithm="convex relaxation: one SOCP (Anitescu)", **common),
        Method("desaxce-fp", _run(solve_desaxce_fp, True), takes="friction",
               algorithm="fixed point of SOCPs (De Saxce)", **common),
        Method("tresca-fp", _run(solve_tresca_fp, True), takes="friction",
               algorithm="fixed point of Tresca SOCPs", **common),
        Method("newton", _run(solve_natural_newton), takes="friction",
               algorithm="semismooth Newton on the natural map", **common),
        Method("vi-eg", _run(solve_vi_eg), takes="friction",
               algorithm="projected gradient with Khobotov's step (Siconos VI_EG)", **common),
        Method("ip-lcp", _run(solve_ip_lcp), takes="friction", problems=("friction-2d",),
               algorithm="interior point on the 2-D LCP, its path followed past folds; "
                         "Newton's polish", **common),
        Method("desaxce-global", _run(solve_desaxce_global, True), takes="friction-global",
               algorithm="fixed point of SOCPs in the velocities (De Saxce)", **common),
    ]
