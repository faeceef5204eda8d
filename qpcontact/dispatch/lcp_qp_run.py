"""One LCP or QP method run: convert, call, certify, name the outcome — and,
where the answer is in doubt, look for a proof that no solution exists."""

from __future__ import annotations

import time

import numpy as np

from ..core.conversions import qp_to_lcp
from ..core.problems import LCP
from ..core.results import LCPSolution, MethodResult, QPSolution
from ..judge.doubt import doubt, no_digit, singular_block
from ..judge.lcp_certificate import certify_lcp
from ..judge.qp_certificate import certify_qp
from ..core.matrices import MatrixStructure
from ..proofs.candidates import cheap_lcp_farkas
from ..proofs.lcp_farkas import inverse_farkas, prove_lcp_infeasible, sign_farkas
from ..proofs.lp import NULL_SPACE_MAX_N
from ..proofs.qp_farkas import prove_no_minimiser, x_size
from ..solvers.method import Method
from .calls import call
from .routes import check_applicable, data_range, jacobi_scaled

__all__ = ["run_lcp_qp", "doubtful", "prove_no_solution", "proof_first", "verdict", "hints",
           "DOUBT_FACTOR", "PROOF_FIRST_SHARE", "PROOF_FIRST_WALL", "PROOF_FIRST_SECONDS"]


def run_lcp_qp(problem, m: Method, options, ctx):
    """Convert, run, time, certify, within the run context ``ctx`` (its
    accuracy, deadline, isolation).  Returns an LCPSolution or QPSolution.  A
    method that proved the data have no solution (Lemke's Farkas vector,
    checked exactly) gives status "infeasible", as a proof found afterwards
    would; "ray" is left for a secondary ray that proves nothing."""
    tol_cert = ctx.tol_cert
    route = "direct"
    start = time.perf_counter()
    if isinstance(problem, LCP):
        check_applicable(problem, m)
        target, unscale = problem, None
        if m.takes == "qp":
            route = "qp" if problem.is_symmetric else "monotone-qp"
            scaled, unscale = jacobi_scaled(problem)
            if unscale is not None:
                route += " (Jacobi-scaled)"
            target = scaled.to_qp() if problem.is_symmetric else scaled.to_monotone_qp()
    else:
        target, dual = problem, None
        if m.takes == "lcp":
            dual = qp_to_lcp(problem)
            target, route = dual.lcp, "dual-lcp"
    # Overflow on extreme data is an outcome the certificate reports, not a
    # warning to print from deep inside a method.
    called = time.perf_counter()
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        res: MethodResult = call(m, target, dict(options), ctx)
    wall = time.perf_counter() - start
    if "backend_seconds" in res.stats:
        wall = (called - start) + res.stats.pop("backend_seconds")
    said = verdict(res.backend_status)
    if said:
        res.stats["backend_verdict"] = said

    x = None if res.x is None else np.asarray(res.x, dtype=float).ravel()
    if isinstance(problem, LCP) and m.takes == "qp" and unscale is not None and x is not None \
            and x.size == unscale.size:
        x = x * unscale
    expected = target.n if isinstance(target, LCP) else problem.q.size  # the dual LCP's size on "dual-lcp"
    usable = x is not None and x.size == expected and bool(np.all(np.isfinite(x)))
    stats = {"route": route, **res.stats}
    common = dict(method=m.name, accuracy=ctx.accuracy, tol=tol_cert,
                  backend_status=res.backend_status, backend_message=res.backend_message,
                  wall_time=wall, iterations=res.iterations, stats=stats)
    if isinstance(problem, LCP):
        cert = certify_lcp(problem, x) if usable else None
        fields = dict(z=x if usable else None, w=problem.w(x) if usable else None)
        cls = LCPSolution
    else:
        y, zi, zb = res.y, res.z, res.z_box
        if usable and m.takes == "lcp":
            x, y, zi, zb = dual.primal_dual(x)
        cert = certify_qp(problem, x, y, zi, zb) if usable else None
        fields = dict(x=x if usable else None, y=y, z=zi, z_box=zb)
        cls = QPSolution

    proof = res.stats.get("proof")
    if res.status == "ray" and proof is not None:
        status = proof.kind            # a Farkas vector checked exactly by the method
        stats.update(proved_infeasible=proof.kind == "infeasible",
                     proved_unbounded=proof.kind == "unbounded")
    elif res.status in ("ray", "max_pivots"):
        status = res.status
    elif cert is not None and cert.error <= tol_cert:
        status = ("solved" if cert.ok(tol_cert) else
                  "ill_posed" if doubt(cert, tol_cert) else "inaccurate")
    elif res.status == "time_limit" or res.stats.get("time_limit_reached"):
        status = "time_limit"
    elif cert is None:
        status = "failed"
    else:
        status = "inaccurate"
    ok = status == "solved"
    if ok:
        message = f"certified: error {cert.error:.2e} <= {tol_cert:.0e}"
        # The forward error is in the message when it came for free (active
        # blocks up to 400); above that, sol.forward_error computes it on request.
        ferr = cert.forward_error if getattr(cert, "forward_error_known", False) else 0.0
        if ferr > tol_cert:
            message += ("; the solution is not isolated (its active block is singular to "
                        "working precision): other solutions may exist" if singular_block(cert)
                        else f"; forward error up to {ferr:.1e} (condition {cert.condition:.1e}): "
                        "components may differ from the exact solution of these data by that "
                        "much of their own size (a component near zero may have no correct digit)")
    elif status == "ill_posed":
        message = f"not certified: {doubt(cert, tol_cert)}"
        if getattr(cert, "near_farkas", None) is not None:
            stats["near_farkas"] = cert.near_farkas
    elif status == "inaccurate" and cert.error <= tol_cert:
        message = f"not certified: error {cert.error:.2e} <= {tol_cert:.0e}, but {no_digit(cert)}"
    elif status == "inaccurate":
        where = (f" at component {cert.worst_index}" if hasattr(cert, "worst_index")
                 else f" at {cert.worst}")
        message = (f"not certified: error {cert.error:.2e}{where} > {tol_cert:.0e} although the "
                   f"backend said {res.backend_status!r}; ask for a tighter accuracy or use an "
                   "exact method")
        if cert.overflow:
            message = ("not certified: the answer's products overflow double precision (beyond "
                       "1e308); rescale the data's units")
    elif status == "failed":
        message = (f"no usable point came back (backend status {res.backend_status!r}"
                   + (f": {res.backend_message}" if res.backend_message else "") + ")")
        if res.backend_status == "overflow" or (x is not None and not np.all(np.isfinite(x))):
            lo, hi = data_range(problem)
            message += (f"; the solution does not fit in double precision: the data's magnitudes "
                        f"span {lo:.1e} .. {hi:.1e}. Rescale the units (e.g. of q, or of the "
                        "unknowns) so that the solution's entries stay below 1e300")
    elif status == "time_limit":
        message = res.backend_message if res.status == "time_limit" else (
            f"stopped at the time limit{_seconds(ctx.time_limit)} (backend status "
            f"{res.backend_status!r})" + (f"; the point it had reached has certificate error "
                                          f"{cert.error:.2e} > {tol_cert:.0e}" if cert else "")
            + "; raise time_limit= or try another method")
    else:
        message = res.backend_message or status
    return cls(status=status, ok=ok, message=message, certificate=cert, **common, **fields)


def _seconds(time_limit) -> str:
    return "" if time_limit is None else f" of {time_limit:g} s"


#: A certified answer larger than this many times the size the data give it
#: (|q| / max|M| for an LCP, qpcontact.proofs.qp_farkas.x_size for a QP) is checked
#: for a proof that no solution exists: backends on an unbounded QP return
#: points of 1e8 and more whose residuals pass on their own rows' scales.
#: Size alone does not take "solved" away (an SPD LCP of condition 1e8 has
#: answers that large, digits and all); the doubt rule does.
DOUBT_FACTOR = 1e3


def verdict(backend_status) -> str | None:
    """"infeasible" or "unbounded" when a backend's own status says so, in
    its own words (OSQP "primal infeasible", Clarabel "DualInfeasible",
    PIQP "PIQP_DUAL_INFEASIBLE", HiGHS "Unbounded", ...), else None.  Never
    believed: it only sends the search for a proof at once."""
    words = "".join(ch for ch in str(backend_status).lower() if ch.isalpha())
    if "dualinfeasible" in words or "unbounded" in words:
        return "unbounded"
    if "infeasible" in words:
        return "infeasible"
    return None


def doubtful(problem, sol) -> bool:
    """Whether a result should be checked for a proof that no solution exists:
    every result that is not ok (a proved ray aside) — among them the
    "ill_posed" answers (qpcontact.judge.doubt) — and a certified answer that
    may be the solution of nearby data only (an LCP answer whose forward
    error reaches its own size, or any answer far beyond the data's size)."""
    if sol.stats.get("proved_infeasible") or sol.stats.get("proved_unbounded"):
        return False
    if not sol.ok:
        return True
    if isinstance(problem, LCP):
        cert = sol.certificate
        if cert.forward_error_known and not cert.forward_error < 1.0:
            return True  # no correct digit guaranteed (singular or nearly singular active block)
        big = float(np.max(np.abs(sol.z), initial=0.0))
        scale_M = problem.matrix_scale
        return scale_M > 0 and big > DOUBT_FACTOR * float(np.max(np.abs(problem.q))) / scale_M
    return float(np.max(np.abs(sol.x), initial=0.0)) > DOUBT_FACTOR * x_size(problem)


def hints(sol) -> list:
    """What a result teaches the proofs: Lemke's Farkas vector checked in
    floating point, and the answer itself (its direction, when it ran far
    out along a ray or a near-null vector)."""
    out = [sol.stats["farkas"]] if sol.stats.get("farkas") is not None else []
    point = sol.z if isinstance(sol, LCPSolution) else sol.x
    if point is not None and np.all(np.isfinite(point)):
        out.append(point)
    return out


def prove_no_solution(problem, sol, deadline, extra_hints=()):
    """Turn a result into "infeasible" or "unbounded" when a Farkas vector or a
    ray is found and checked in exact arithmetic (qpcontact.proofs) before
    ``deadline`` (a :class:`~qpcontact.core.deadline.Deadline`): a proof
    about the data as stored outranks a certificate, which speaks of nearby
    data.  ``extra_hints``: what earlier methods of the same call learned."""

    tried = hints(sol) + list(extra_hints)
    if isinstance(problem, LCP) and problem.structure.is_positive_definite_exactly:
        # no Farkas vector exists (y'My > 0): the search would cost LPs and
        # an O(n³) elimination mod p to find nothing (53 s of a 300-unknown
        # SPD cross-validation); the answer keeps its own verdict
        proof = None
    elif isinstance(problem, LCP):
        # the cheap candidates (one row, all ones, null directions, the
        # hints) exactly, before any LP: an LP misses qᵀ1 = -1 beside |q| ~ 1e13
        near = getattr(sol.certificate, "near_farkas", None)
        # the rounded mechanism's exact inverse first: 0.06 s at n = 30,
        # where the candidates' snapping costs 0.35 s and, at a machine's
        # load of 3, a 2 s call's share ran out on them
        proof = inverse_farkas(problem, deadline) or cheap_lcp_farkas(
            problem.M, problem.q, deadline, ([] if near is None else [near]) + tried)
        if proof is None:
            proof = prove_lcp_infeasible(problem, deadline, tried)
    else:
        proof = prove_no_minimiser(problem, deadline, tried)
    if proof is None:
        cert = sol.certificate
        if (sol.ok and isinstance(problem, LCP) and cert.forward_error_known
                and not cert.forward_error < 1.0):
            # no vector near the active block's null space is Farkas to
            # rounding (else the answer would be "ill_posed"): the data are
            # solvable nearby and the solution is not isolated
            sol.message += ("; no digit is guaranteed: the solution is not isolated (other "
                            "solutions may be as right), and no vector on its active rows is a "
                            "Farkas vector to rounding (judge/near_farkas)")
        elif sol.status == "ill_posed":
            sol.message += ("; no Farkas vector or ray could be checked exactly, so nothing is "
                            "proved either way")
        return sol
    before = (f"{sol.method} certified a point of nearby data (error {sol.error:.1e})" if sol.ok
              else f"{sol.method} returned {sol.backend_status!r}")
    sol.stats.update({"proof": proof, "proved_infeasible": proof.kind == "infeasible",
                      "proved_unbounded": proof.kind == "unbounded"})
    sol.status, sol.ok = proof.kind, False
    sol.message = f"{proof.message} (found after {before})"
    return sol


#: what the proof sought before any method runs ("auto") may take: this
#: share of what is left of the call as CPU time, at most PROOF_FIRST_WALL
#: of it on the wall clock (a loaded machine), and never more than
#: PROOF_FIRST_SECONDS
PROOF_FIRST_SHARE = 0.25
PROOF_FIRST_WALL = 0.5
PROOF_FIRST_SECONDS = 5.0


def proof_first(problem, ctx):
    """"auto"'s first step: a proof that no solution exists, sought before
    any method runs where the data's cheap signs allow one, or None.

    Iterative backends spend their whole share on data with no solution
    (an unbounded QP at n = 250 took 19 s of a 20 s limit, Lemke reached its
    pivot cap on a 250-row infeasible LCP) while the proof costs an LP of a
    few coordinates.  The step is skipped where a solution is known to
    exist: q >= 0 (z = 0), an M or P that is positive definite (one
    factorization, kept for the methods), a nonsymmetric M with M·1 > 0
    (z = t·1 for large t).  Otherwise, up to NULL_SPACE_MAX_N unknowns:
    the signs of the rows (a row of M with no positive entry and q_i < 0,
    at any size), the all-ones vector, and one LP — in the null space of a
    symmetric PSD M or of P, or the interior Farkas LP of a general M.
    It keeps PROOF_FIRST_SHARE of what is left of the call, counted in CPU
    time up to PROOF_FIRST_WALL of it on the wall clock: at load 3–6 a wall
    share of 0.5 s of a 2 s call held less CPU than the proof of a rounded
    mechanism needs (0.05 s), and the methods after it could not prove it."""
    if not ctx.prove:
        return None
    started = time.perf_counter()
    deadline = ctx.deadline.cpu_share(PROOF_FIRST_SHARE, PROOF_FIRST_WALL).within(
        PROOF_FIRST_SECONDS)
    if isinstance(problem, LCP):
        q = problem.q
        if np.all(q >= 0):
            return None
        proof = sign_farkas(problem.M, q)
        if proof is None and problem.n <= NULL_SPACE_MAX_N and not problem.is_positive_definite \
                and (problem.is_symmetric or not _ones_solve(problem)):
            proof = prove_lcp_infeasible(problem, deadline, quick=True)
        cls, fields = LCPSolution, dict(z=None, w=None)
    else:
        n = problem.q.size
        if n > NULL_SPACE_MAX_N or MatrixStructure(problem.P).is_positive_definite:
            return None
        proof = prove_no_minimiser(problem, deadline, quick=True)
        cls, fields = QPSolution, dict(x=None if proof is None else proof.point)
    if proof is None:
        return None
    wall = time.perf_counter() - started
    return cls(method="proof", status=proof.kind, ok=False,
               message=f"{proof.message} (found before any method ran, in {wall:.2g} s)",
               accuracy=ctx.accuracy, tol=ctx.tol_cert, certificate=None, wall_time=wall,
               stats={"route": "proof first", "proof": proof,
                      "proved_infeasible": proof.kind == "infeasible",
                      "proved_unbounded": proof.kind == "unbounded"}, **fields)


def _ones_solve(lcp) -> bool:
    """M·1 > 0 row by row (a screen, in floating point): then z = t·1 is
    feasible for t large, and no Farkas vector exists."""
    with np.errstate(all="ignore"):
        return bool(np.all(np.asarray(lcp.M @ np.ones(lcp.n)).ravel() > 0))
