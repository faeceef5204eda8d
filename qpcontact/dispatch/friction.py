"""One frictional-contact method run: call it (or, for an LCP method, solve the
problem's faceted LCP), certify the reactions from the data, name the outcome."""

from __future__ import annotations

import time

import numpy as np

from ..core.errors import InvalidOptionError
from ..core.results import PROVED, FrictionSolution, MethodResult
from ..friction.lcp_route import LCP_ACCURACY, from_lcp, lcp_of
from ..friction.measures import certify_friction
from ..proofs.exact import Proof
from ..solvers.method import PROBLEM_KINDS, Method
from .calls import call
from .routes import kind_of

__all__ = ["run_friction", "check_friction_method"]


def check_friction_method(problem, m: Method) -> None:
    """InvalidOptionError when ``m`` does not take this form of frictional problem."""
    kind = kind_of(problem)
    if m.solves(kind):
        return
    if kind == "friction-global":
        raise InvalidOptionError(
            f"{m.name!r} needs the local form, and this global problem is kept without W "
            f"({problem.global_data['unreduced_because']}); use desaxce-global or 'auto'")
    if m.solves("friction-global"):
        raise InvalidOptionError(f"{m.name!r} solves global problems kept without W; this one is "
                                 "in local form (global_problem(..., reduce=False) keeps M, H)")
    raise InvalidOptionError(
        f"{m.name!r} does not solve frictional contact problems (it takes "
        f"{', '.join(PROBLEM_KINDS[k] for k in m.problems)}); `qpcontact methods` lists what "
        "each method takes (friction: nsgs, lemke, enumeration, anitescu, desaxce-fp, tresca-fp, "
        "newton, desaxce-global, auto)")


def _call(problem, m: Method, tol: float, options: dict, time_limit, isolate, engine
          ) -> MethodResult:
    if m.takes == "lcp":          # through the faceted LCP, certified there as an LCP
        lcp, D, facets, lcp_options = lcp_of(problem, options)
        sol = engine.solve(lcp, m.name, accuracy=min(tol, LCP_ACCURACY), **lcp_options)
        return from_lcp(problem, m.name, sol, D, facets, tol)
    return call(m, problem, tol, options, time_limit, isolate, engine)


def run_friction(problem, m: Method, tol: float, accuracy, options: dict, time_limit=None,
                 isolate="auto", engine=None) -> FrictionSolution:
    """Run ``m`` on a frictional problem and certify its answer (r, and v for a
    global problem kept without W) by :func:`certify_friction`.  ``tol`` is
    both what the method stops at and what the certificate must meet."""
    common = dict(method=m.name, accuracy=accuracy, tol=tol)
    if problem.n_contacts == 0 and problem.is_reduced:
        r = np.zeros(0)
        return FrictionSolution(status="solved", ok=True, message="no contacts",
                                certificate=certify_friction(problem, r), r=r, u=r, **common)
    start = time.perf_counter()
    res = _call(problem, m, tol, dict(options), time_limit, isolate, engine)
    wall = time.perf_counter() - start
    stats = {**res.stats, "time": wall}
    common.update(backend_status=res.backend_status, backend_message=res.backend_message,
                  wall_time=wall, iterations=res.iterations, stats=stats)
    message = res.backend_message
    if res.x is None and "ray" in stats:     # a checked proof that no equilibrium exists
        stats["proof"] = Proof(kind="infeasible", message=message, vector={"d": stats["ray"]})
        return FrictionSolution(status=PROVED[0], ok=False, message=message,
                                certificate=None, r=None, u=None, **common)
    x = None if res.x is None else np.asarray(res.x, float).ravel()
    if x is None or not np.all(np.isfinite(x)):
        status = "time_limit" if res.status == "time_limit" else "failed"
        return FrictionSolution(status=status, ok=False,
                                message=f"{m.name}: no usable point ({message})",
                                certificate=None, r=None, u=None, **common)
    size = problem.dim * problem.n_contacts
    if problem.is_reduced:
        r, v = x, None
        u = problem.velocities(r)
    else:
        g = problem.global_data
        r, v = x[:size], x[size:]
        u = np.asarray(g["H"].T @ v).ravel() + g["w"]
    cert = certify_friction(problem, r, v, u=u if problem.is_reduced else None)
    ok = cert.ok(tol)
    measures = (f"natural-map error {cert.natural_map_error:.1e}, componentwise "
                f"{cert.componentwise_error:.1e}")
    if not problem.is_reduced:
        measures += f", equilibrium {cert.equilibrium_error:.1e}"
    return FrictionSolution(status="solved" if ok else "inaccurate", ok=ok,
                            message=(f"{measures} {'<=' if ok else '>'} {tol:.0e} "
                                     f"({m.name}: {message})"),
                            certificate=cert, r=r, u=u, v=v, **common)
