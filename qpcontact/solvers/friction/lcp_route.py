"""Frictional contact through its LCP (:func:`qpcontact.core.friction_problem.faceted_lcp`).

Any LCP method that takes any M ("lemke", "enumeration") solves a frictional
problem this way: exactly in 2-D, on the cone faceted by ``facets``
directions in 3-D (default 8; an approximation whose error against the true
cone is reported like every answer's).  The engine solves the LCP itself, so
that its answer is certified as an LCP; here are the two ends of the route:
the LCP and, from its answer, the reactions.

2-D: a basic solution carries the rounding of one LU solve, eps times the
forces it is coupled with.  Contacts whose data are themselves at that level
(q entries of 1e-17 that are rounding residues, beside forces of 1e-3) then
fail the componentwise measure: on the 2020-contact granular file 26 contacts
did, worst 2e-2, while the natural-map error was 6e-16.  So when the basic
solution is not certified, it is *polished*: entries below 1e-13 of the
largest — the computed values of degenerate basic variables, zero in exact
arithmetic — are set to zero, r_T is clipped to |r_T| <= μ r_N, and
semismooth Newton starts there (on that file: one iteration to 2e-16 in both
measures).  The polished point is kept only when its certificate is better;
the message says so.
"""

from __future__ import annotations

import numpy as np

from ...core.options import Option, read_options
from ...core.results import MethodResult
from ...judge.friction_certificate import certified_error
from .newton import solve_natural_newton
from ...core.friction_problem import faceted_lcp

__all__ = ["lcp_of", "from_lcp", "reactions_of", "purified", "LCP_ACCURACY", "FACETS"]

#: the LCP is solved at least this tightly: its answer is the exact oracle of 2-D
LCP_ACCURACY = 1e-9


#: the route's own option; the others are the LCP method's, which reads them
FACETS = Option("facets", None, "int", doc="directions of the faceted cone (2-D: 2, the exact "
                "cone; 3-D: default 8, at least 3)")


def lcp_of(problem, options: dict, method: str = "the LCP route"):
    """(LCP, D, facets, the LCP method's own options) for ``problem``; option
    ``facets`` (2-D: 2, the exact cone; 3-D: default 8), checked here (its
    type) and by :func:`faceted_lcp` (its range for the problem's dim)."""
    options = dict(options)
    given = {"facets": options.pop("facets")} if "facets" in options else {}
    facets = read_options(method, given, (FACETS,))["facets"]
    if facets is None:
        facets = 2 if problem.dim == 2 else 8
    lcp, D = faceted_lcp(problem, facets)
    return lcp, D, facets, options


def from_lcp(problem, method: str, sol, D, facets: int, tol: float) -> MethodResult:
    """The reactions r from the LCP's certified answer ``sol`` (an LCPSolution),
    polished in 2-D where the basic solution misses ``tol`` (module docstring)."""
    nc = problem.n_contacts
    stats = {"facets": facets, "lcp_size": 2 * nc + D.shape[1], "iterations": sol.iterations}
    name = method.capitalize() if method == "lemke" else method
    if sol.z is None:
        return MethodResult(x=None, backend_status=sol.status,
                            status="time_limit" if sol.status == "time_limit" else None,
                            backend_message=f"{name} {sol.status}: {sol.message}",
                            iterations=sol.iterations, stats=stats)
    r = reactions_of(problem, sol.z, D)
    cone = "exact 2-D LCP" if problem.dim == 2 else f"{facets}-faceted cone"
    message = (f"{cone}, {name}: {sol.iterations} pivots, LCP certificate "
               f"{sol.certificate.error:.1e}")
    if problem.dim == 2:
        before = certified_error(problem, r)
        if before > tol:
            r, message = _polished(problem, r, before, tol, message, stats)
    return MethodResult(x=r, backend_status="solved", backend_message=message,
                        iterations=sol.iterations, stats=stats)


def reactions_of(problem, z, D):
    """The reactions r from the faceted LCP's z = (r_N, the facets' parts,
    the slip speeds): r_N, and r_T = D times the facets' parts."""
    nc = problem.n_contacts
    r = np.asarray(D @ z[nc:-nc]).ravel()
    r[0::problem.dim] = z[:nc]
    return r


def purified(problem, r, rtol):
    """A 2-D point's copy with the entries below ``rtol`` of its largest
    set to zero (rounding-level values that are zero in exact arithmetic)
    and r_T clipped to |r_T| <= μ r_N: where Newton's polish starts."""
    start = r.copy()
    start[np.abs(start) < rtol * np.abs(start).max(initial=0.0)] = 0.0
    bound = problem.mu * start[0::2]
    start[1::2] = np.clip(start[1::2], -bound, bound)
    return start


def _polished(problem, r, before, tol, message, stats):
    """A 2-D basic solution (certified error ``before``) polished by Newton
    from its purified point (module docstring); the better-certified of the
    two."""
    rn, _, _, nstats = solve_natural_newton(problem, tol, {"r0": purified(problem, r, 1e-13)})
    after = certified_error(problem, rn) if rn is not None else np.inf
    stats["polish_iterations"] = nstats.get("iterations")
    if after < before:
        k = nstats.get("iterations")
        return rn, (f"{message}; its basic solution (error {before:.1e}) polished by Newton from "
                    f"its purified point ({k} iteration{'s' if k != 1 else ''})")
    return r, f"{message}; a Newton polish did not improve it (error {after:.1e})"
