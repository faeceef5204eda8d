"""One frictional-contact method run: call it (or, for an LCP method, solve the
problem's faceted LCP), certify the reactions from the data, name the outcome;
and "auto"'s chain of such runs on one time budget.

"auto" (:func:`run_friction_auto`) tries :func:`~.routes.auto_chain`'s links in
order.  Each link gets half of the time left (the last one all of it; 2-D
chains above 200 contacts: :func:`~.routes.link_share`), a
share of the run context's deadline: the iterative links check it between
iterations, Lemke at each pivot.  Every link's answer is
certified; the first certified one is returned, else the best-certified
point of all, never a later, worse one.  ``progress`` (a callable taking a
line) hears each link start and end and, from the iterative links, each
check; the message names every link that ran, its time and where it
stopped."""

from __future__ import annotations

import time

import numpy as np

from ..core.errors import InvalidOptionError
from ..core.results import PROVED, FrictionSolution, MethodResult
from ..solvers.friction.lcp_route import LCP_ACCURACY, from_lcp, lcp_of
from ..judge.friction_certificate import certify_friction
from ..judge.near_farkas import near_friction_ray
from ..proofs.candidates import exact_friction_motion
from ..proofs.exact import Proof
from ..solvers.method import PROBLEM_KINDS, Method
from ..solvers.registry import get_method
from .calls import call
from .routes import auto_chain, auto_progress, kind_of, link_options, link_share

__all__ = ["run_friction", "run_friction_auto", "check_friction_method"]


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


def _call(problem, m: Method, options: dict, ctx, engine) -> MethodResult:
    tol = ctx.tol_cert
    if m.takes == "lcp":          # through the faceted LCP, certified there as an LCP
        lcp, D, facets, lcp_options = lcp_of(problem, options, m.name)
        sol = engine.within(ctx).solve(lcp, m.name, accuracy=min(tol, LCP_ACCURACY),
                                       **lcp_options)
        return from_lcp(problem, m.name, sol, D, facets, tol)
    # the friction methods stop at the certificate's tolerance, not a backend's
    return call(m, problem, options, ctx.at(accuracy=tol), engine.within(ctx))


def run_friction(problem, m: Method, options: dict, ctx, engine) -> FrictionSolution:
    """Run ``m`` on a frictional problem within the run context ``ctx`` and
    certify its answer (r, and v for a global problem kept without W) by
    :func:`certify_friction`.  ``ctx.tol_cert`` is both what the method stops
    at and what the certificate must meet."""
    tol = ctx.tol_cert
    common = dict(method=m.name, accuracy=ctx.accuracy, tol=tol)
    if problem.n_contacts == 0 and problem.is_reduced:
        r = np.zeros(0)
        return FrictionSolution(status="solved", ok=True, message="no contacts",
                                certificate=certify_friction(problem, r), r=r, u=r, **common)
    start = time.perf_counter()
    res = _call(problem, m, dict(options), ctx, engine)
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
    status, note = ("solved" if ok else "inaccurate"), ""
    if ok and ctx.prove and not problem.is_reduced:
        status, note = _at_the_limit(problem, r, cert, ctx, stats)
        ok = status == "solved"
    if status == "infeasible":
        return FrictionSolution(status=status, ok=False, message=stats["proof"].message,
                                certificate=cert, r=r, u=u, v=v, **common)
    return FrictionSolution(status=status, ok=ok,
                            message=(f"{measures} {'<=' if cert.error <= tol else '>'} {tol:.0e} "
                                     f"({m.name}: {message})" + note),
                            certificate=cert, r=r, u=u, v=v, **common)


def _at_the_limit(problem, r, cert, ctx, stats) -> tuple[str, str]:
    """A certified answer of a problem with a mechanism, checked against the
    friction limit: a motion the contacts admit on which the loads do work
    within rounding of zero (:func:`qpcontact.judge.near_farkas.near_friction_ray`)
    is decided exactly — positive work proves no equilibrium ("infeasible"),
    none leaves the answer "solved" (at or below the limit), and a motion that
    cannot be checked exactly leaves it "ill_posed": the loads are within
    rounding of the limit, and the equilibrium may not exist."""
    d = near_friction_ray(problem, r, max(10.0 * cert.error, 1e-12))
    if d is None:
        return "solved", ""
    decided = exact_friction_motion(problem, d, r, ctx.deadline)
    if decided is None:
        stats["near_ray"] = d
        return "ill_posed", ("; but not certified: the loads are within rounding of the friction "
                             "limit along a motion the contacts admit (stats['near_ray']), which "
                             "could not be checked exactly, so the equilibrium may not exist")
    if decided[0] == "infeasible":
        proof = decided[1]
        stats.update(proof=proof, ray=proof.vector["d"], proved_infeasible=True)
        return "infeasible", ""
    return "solved", ("; within rounding of the friction limit, at or below it: reactions within "
                      "the cones balance the loads on every mechanism (checked exactly)")


def run_friction_auto(problem, options: dict, ctx, engine) -> FrictionSolution:
    """"auto" on a frictional problem within the run context ``ctx`` (module
    docstring)."""
    start = time.perf_counter()
    options, progress = auto_progress(options)
    chain = [get_method(name) for name in auto_chain(problem)]
    runs, best, lines = [], None, []
    for k, m in enumerate(chain):
        if ctx.spent():
            lines.append(f"{m.name}: not run ({max(ctx.left(), 0.0):.2g} s of the time limit of "
                         f"{ctx.time_limit:g} s was left)")
            continue
        link = ctx.share(link_share(problem, m.name, k == len(chain) - 1))
        share = link.left()
        opts = link_options(options, m.name, progress, share)
        if m.name == "newton" and best is not None and best.r is not None:
            opts.setdefault("r0", best.r)   # polish the best point so far
        sol = run_friction(problem, m, opts, link, engine)
        runs.append(sol)
        where = f"error {sol.error:.1e}" if sol.certificate is not None else sol.status
        lines.append(f"{m.name}: {where} in {sol.wall_time or 0:.2f} s")
        if progress is not None:
            progress(f"auto: {m.name}: {sol.status}, {where} in {sol.wall_time or 0:.2f} s")
        if best is None or sol.error < best.error:
            best = sol
        if sol.ok or sol.status in PROVED:
            break
    others = [r for r in runs if r is not best]
    if others:
        best.message += " — also tried " + "; ".join(f"{r.method}: {r.message}" for r in others)
    best.message += " — links: " + "; ".join(lines)
    # each link's seconds beside auto_tried: where a budget went (benchmarks/friction.py --dense)
    best.stats.update(auto_tried=[(r.method, r.status, r.error) for r in runs],
                      auto_link_times=[(r.method, r.wall_time or 0.0) for r in runs],
                      total_time=time.perf_counter() - start)
    return best
