"""``solve``: one entry point for every problem kind and every method."""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp
from qpsolvers import Problem

from ..core.accuracy import resolve_accuracy
from ..judge.certify import certify
from ..core.conversions import check_convex, qp_to_lcp, validate_qp
from ..core.errors import (BackendUnavailableError, InvalidOptionError, InvalidProblemError,
                           NoSolutionError, NotConvexError, NotSymmetricError, SolverFailedError,
                           UnknownMethodError)
from ..solvers.registry import Method, get_method
from ..core.linalg import BANDED_MAX
from ..core.problems import LCP, ParametricLCP
from ..core.results import LCPSolution, MethodResult, QPSolution

__all__ = ["solve", "AUTO_ORDER"]

#: Preference of ``method="auto"``: exact pivoting first where it applies (as
#: DESIGN.md asks), then the QP backends in the order that reached "high"
#: fastest in benchmarks/backends.py on this machine class (docs/backends.md).
#: "auto" tries them in turn until one is certified.
#: "enumeration" (n <= 16) follows Lemke: a general M's secondary ray proves
#: nothing, and all 2^n bases of a small LCP cost at most about a second.
#: Measured (docs/backends.md): PIQP reached "high" fastest at n = 100, 1000 and
#: 20 000 but stops at ~2e-7 on degenerate problems, where polished OSQP is exact.
AUTO_ORDER = ("energy", "bpp", "lemke", "enumeration", "piqp", "osqp", "clarabel", "daqp", "proxqp",
              "highs", "quadprog", "scs", "cvxpy:CLARABEL")

#: "auto" puts "ip-bpp" first for sparse SPD LCPs from this size on whose
#: matrix is not banded (meshes: bpp's active-set front moves one grid line
#: per exchange, 25 exchanges at n = 1e4 and 81 at 1e5 on the membrane), and
#: for QPs whose only constraints are lower bounds (the mixed problem of
#: finite-element contact).  Banded matrices (contact chains, bandwidth <= 16)
#: keep "bpp", which needs 3-4 exchanges there (docs/pivoting.md).
AUTO_IP_BPP_MIN = 5000


def _auto_order(problem) -> tuple:
    if isinstance(problem, LCP):
        mesh_like = (problem.is_sparse and problem.n >= AUTO_IP_BPP_MIN
                     and problem.structure.bandwidth > BANDED_MAX)
        return ("ip-bpp",) + AUTO_ORDER if mesh_like else AUTO_ORDER
    if isinstance(problem, Problem) and _lower_bounds_only(problem):
        return ("ip-bpp",) + AUTO_ORDER
    return AUTO_ORDER


def _lower_bounds_only(problem: Problem) -> bool:
    return (problem.G is None and problem.A is None and problem.lb is not None
            and (problem.ub is None or not np.isfinite(problem.ub).any()))


#: Seconds a backend call may take (``solve(..., time_limit=)``), enforced by
#: the backend's own setting where it has one and by a killable child process
#: for ProxQP (qpcontact.isolation).  The slowest certified backend call in the
#: benchmarks (PIQP, n = 1e5 membrane) took 9 s; the hangs it cuts took 59 s
#: to more than 120 s on problems of n <= 8.
DEFAULT_TIME_LIMIT = 60.0

_BACKEND_FAMILIES = ("qpsolvers", "cvxpy")

# Dense-only backends densify sparse input; beyond this size that costs more
# than it is worth for "auto" (an explicit method name is always honoured).
_AUTO_DENSE_LIMIT = 3000


def _jacobi_scaled(lcp: LCP):
    """(LCP(DMD, Dq), d) with D = diag(M)^-1/2 (1 where M_ii = 0: such rows
    of a monotone M carry no quadratic term), or (lcp, None) when a diagonal
    entry is negative or the diagonal is already all ones.

    The QP handed to a backend is the LCP's scaled form, z = D y.  Backends
    stop on *absolute* residuals; in physical units (a compliance of 1e-9 m/N
    against forces of 1e4 N) their tolerances mean nothing.  Measured on the
    drum's step problems: OSQP at "high" certified 15 of 80 steps unscaled and
    80 of 80 scaled (docs/drum.md).  The certificate is always computed on the
    original problem.
    """
    M = lcp.M
    diag = np.asarray(M.diagonal(), dtype=float)
    if np.any(diag < 0):
        return lcp, None
    d = np.ones_like(diag)
    d[diag > 0] = 1.0 / np.sqrt(diag[diag > 0])
    if np.all(d == 1.0):
        return lcp, None
    with np.errstate(over="ignore", invalid="ignore"):
        if sp.issparse(M):
            D = sp.diags(d)
            Ms = (D @ M @ D).tocsc()
            finite = np.all(np.isfinite(Ms.data))
        else:
            Ms = (M * d[:, None]) * d[None, :]
            finite = np.all(np.isfinite(Ms))
        qs = lcp.q * d
    if not (finite and np.all(np.isfinite(qs))):
        return lcp, None
    if lcp.is_symmetric:
        Ms = 0.5 * (Ms + Ms.T)  # keep exact symmetry for the QP route
    scaled = LCP(Ms, qs)
    if lcp.structure.__dict__.get("is_positive_definite"):
        scaled.structure.declare_spd()   # D M D is congruent to M: no second factorization
    return scaled, d


def _check_applicable(lcp: LCP, m: Method) -> None:
    if m.requires == "spd":
        if not lcp.is_symmetric:
            raise NotSymmetricError(
                f"method {m.name!r} needs a symmetric positive definite M and M is not symmetric; "
                "use 'lemke', which accepts any M."
            )
        if not lcp.is_positive_definite:
            raise NotConvexError(
                f"method {m.name!r} needs a positive definite M and M is not; use 'lemke'."
            )
    elif m.requires == "monotone" and not lcp.is_psd:
        if lcp.is_symmetric:
            raise NotConvexError(
                f"M is symmetric but not positive semidefinite, so the QP min ½z'Mz + q'z, z >= 0 "
                f"is nonconvex and {m.name!r} (a QP backend) may return a local minimum. "
                "Use a pivoting method such as 'lemke'."
            )
        raise NotSymmetricError(
            f"M is not symmetric and M + M' is not positive semidefinite, so no convex QP has "
            f"this LCP's solutions as minimisers and {m.name!r} (a QP backend) cannot solve it. "
            "Use a pivoting method such as 'lemke'."
        )


def _applicable(problem, m: Method) -> bool:
    if m.max_n is not None and (problem.n if isinstance(problem, LCP) else
                                problem.P.shape[0]) > m.max_n:
        return False
    if isinstance(problem, LCP):
        try:
            _check_applicable(problem, m)
        except (NotSymmetricError, NotConvexError):
            return False
        n, sparse = problem.n, problem.is_sparse
    else:
        if m.takes == "lcp":
            return False  # QP -> dual LCP is dense; "auto" keeps QPs on QP backends
        if m.constraints == "lower-bounds" and not _lower_bounds_only(problem):
            return False
        n, sparse = problem.P.shape[0], problem.has_sparse
    return m.accepts_sparse or not sparse or n <= _AUTO_DENSE_LIMIT


def _data_range(problem) -> tuple[float, float]:
    """(smallest nonzero, largest) |entry| of an LCP's or a QP's data."""
    parts = [problem.M, problem.q] if isinstance(problem, LCP) else list(problem.unpack())
    vals = []
    for part in parts:
        if part is None:
            continue
        v = part.data if sp.issparse(part) else np.asarray(part, dtype=float).ravel()
        v = np.abs(v[np.isfinite(v) & (v != 0)])
        if v.size:
            vals.append((v.min(), v.max()))
    if not vals:
        return 0.0, 0.0
    return min(a for a, _ in vals), max(b for _, b in vals)


def _needs_isolation(m: Method) -> bool:
    from ..solvers.backends import cvxpy_backends, qpsolvers_backends

    if m.family == "qpsolvers":
        return m.name in qpsolvers_backends.NEEDS_ISOLATION
    return m.name.split(":", 1)[-1] in cvxpy_backends.NEEDS_ISOLATION


def _takes_time_limit(run) -> bool:
    import inspect

    try:
        return "time_limit" in inspect.signature(run).parameters
    except (TypeError, ValueError):
        return False


def _run_with_limit(m: Method, target, tol, options, time_limit):
    if _takes_time_limit(m.run):
        return m.run(target, tol, options, time_limit=time_limit)
    return m.run(target, tol, options)


def _isolated_run(name, target, tol, options, time_limit):
    # in the child: looked up by name so that spawn-started children work too
    return _run_with_limit(get_method(name), target, tol, options, time_limit)


def _call(m: Method, target, tol_backend, options, time_limit, isolate) -> MethodResult:
    """The method's call, with the time limit and isolation of :func:`solve`."""
    if m.family not in _BACKEND_FAMILIES:
        return m.run(target, tol_backend, options)
    if isolate is True or (isolate == "auto" and time_limit is not None and _needs_isolation(m)):
        from .isolation import call_isolated

        # the backend's own limit first; the kill a moment later
        hard = None if time_limit is None else 1.25 * time_limit + 2.0
        out = call_isolated(_isolated_run, (m.name, target, tol_backend, options, time_limit), hard)
        if out is not None:
            if out.kind == "ok":
                # timed in the child: the fork is not the backend's cost
                out.value.stats.update(isolated=True, backend_seconds=out.seconds)
                return out.value
            if out.kind == "error":
                raise out.value
            words = (f"stopped: no answer within the time limit of {time_limit:g} s "
                     f"({out.detail}); raise time_limit= or try another method"
                     if out.kind == "time_limit" else
                     f"{out.detail}; the backend crashed on these data (the caller survived "
                     "because it ran isolated); try another method or rescale the data")
            return MethodResult(x=None, backend_status=out.kind, backend_message=words,
                                status="time_limit" if out.kind == "time_limit" else None,
                                stats={"isolated": True})
    return _run_with_limit(m, target, tol_backend, options, time_limit)


def _run(problem, m: Method, tol_backend, tol_cert, accuracy, options, time_limit=None,
         isolate="auto"):
    """Convert, run, time, certify.  Returns an LCPSolution or QPSolution."""
    route = "direct"
    start = time.perf_counter()
    if isinstance(problem, LCP):
        _check_applicable(problem, m)
        target, unscale = problem, None
        if m.takes == "qp":
            route = "qp" if problem.is_symmetric else "monotone-qp"
            scaled, unscale = _jacobi_scaled(problem)
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
        res: MethodResult = _call(m, target, tol_backend, dict(options), time_limit, isolate)
    wall = time.perf_counter() - start
    if "backend_seconds" in res.stats:
        wall = (called - start) + res.stats.pop("backend_seconds")

    x = None if res.x is None else np.asarray(res.x, dtype=float).ravel()
    if isinstance(problem, LCP) and m.takes == "qp" and unscale is not None and x is not None \
            and x.size == unscale.size:
        x = x * unscale
    expected = target.n if isinstance(target, LCP) else problem.q.size  # the dual LCP's size on "dual-lcp"
    usable = x is not None and x.size == expected and bool(np.all(np.isfinite(x)))
    stats = {"route": route, **res.stats}
    common = dict(method=m.name, accuracy=accuracy, tol=tol_cert,
                  backend_status=res.backend_status, backend_message=res.backend_message,
                  wall_time=wall, iterations=res.iterations, stats=stats)
    if isinstance(problem, LCP):
        cert = certify(problem, x) if usable else None
        fields = dict(z=x if usable else None, w=problem.w(x) if usable else None)
        cls = LCPSolution
    else:
        y, zi, zb = res.y, res.z, res.z_box
        if usable and m.takes == "lcp":
            x, y, zi, zb = dual.primal_dual(x)
        cert = certify(problem, x, y=y, z=zi, z_box=zb) if usable else None
        fields = dict(x=x if usable else None, y=y, z=zi, z_box=zb)
        cls = QPSolution

    if res.status in ("ray", "max_pivots"):
        status = res.status
    elif cert is not None and cert.ok(tol_cert):
        status = "solved"
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
            message += (f"; forward error up to {ferr:.1e} (condition {cert.condition:.1e}): "
                        "components may differ from the exact solution of these data by that "
                        "much of their own size (a component near zero may have no correct digit)"
                        if np.isfinite(ferr) else
                        "; the solution is not isolated (singular active block): other solutions "
                        "may exist")
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
            lo, hi = _data_range(problem)
            message += (f"; the solution does not fit in double precision: the data's magnitudes "
                        f"span {lo:.1e} .. {hi:.1e}. Rescale the units (e.g. of q, or of the "
                        "unknowns) so that the solution's entries stay below 1e300")
    elif status == "time_limit":
        message = res.backend_message if res.status == "time_limit" else (
            f"stopped at the time limit of {time_limit:g} s (backend status "
            f"{res.backend_status!r})" + (f"; the point it had reached has certificate error "
                                          f"{cert.error:.2e} > {tol_cert:.0e}" if cert else "")
            + "; raise time_limit= or try another method")
    else:
        message = res.backend_message or status
    return cls(status=status, ok=ok, message=message, certificate=cert, **common, **fields)


def _check_time_limit(time_limit):
    if time_limit is None:
        return None
    try:
        value = float(time_limit)
    except (TypeError, ValueError):
        value = float("nan")
    if isinstance(time_limit, bool) or not value > 0:
        raise InvalidOptionError(
            f"time_limit must be a positive number of seconds or None; got {time_limit!r}")
    return value


#: A certified QP answer larger than this many times the size the data give x
#: (qpcontact.proofs.x_size) is checked for a proof that no minimiser exists:
#: backends on an unbounded QP return points of 1e8 and more whose residuals
#: pass on their own rows' scales (|P||x| grows with x) — exact answers of
#: nearby data whose problem has no minimiser either.
DOUBT_FACTOR = 1e3


def _doubtful(problem, sol) -> bool:
    """Whether a result should be checked for a proof that no solution exists:
    every result that is not ok (a proved ray aside), and a certified answer
    that may be the solution of nearby data only (an LCP answer whose forward
    error reaches its own size — an infeasible PSD LCP got z ~ 3e8 with
    condition 2e17 from HiGHS, quadprog and ProxQP — or that is far beyond
    |q| / max|M|; a QP answer far beyond the data's size)."""
    if sol.stats.get("proved_infeasible") or sol.stats.get("proved_unbounded"):
        return False
    if not sol.ok:
        return True
    if sol.certificate.normwise_error > max(10.0 * sol.certificate.error, sol.tol):
        # residuals small on their own rows' scales but not on the data's
        # norms: the rows' scales grew with the point (|P||x| at x ~ 1e2..1e17
        # on unbounded QPs), a sign of a point running off to infinity
        return True
    if isinstance(problem, LCP):
        cert = sol.certificate
        if cert.forward_error_known and not cert.forward_error < 1.0:
            return True  # no correct digit guaranteed (singular or nearly singular active block)
        big = float(np.max(np.abs(sol.z), initial=0.0))
        scale_M = problem.matrix_scale
        return scale_M > 0 and big > DOUBT_FACTOR * float(np.max(np.abs(problem.q))) / scale_M
    from ..proofs.qp import x_size

    return float(np.max(np.abs(sol.x), initial=0.0)) > DOUBT_FACTOR * x_size(problem)


def _prove_no_solution(problem, sol, time_limit=None):
    """Turn a result into "infeasible" or "unbounded" when a Farkas vector or a
    ray is found and checked from the data (qpcontact.proofs): a proof about
    the data as stored outranks a certificate, which speaks of nearby data."""
    from ..proofs.lcp import prove_lcp_infeasible
    from ..proofs.qp import prove_no_minimiser

    proof = (prove_lcp_infeasible(problem, time_limit) if isinstance(problem, LCP)
             else prove_no_minimiser(problem, time_limit))
    if proof is None:
        cert = sol.certificate
        if (sol.ok and isinstance(problem, LCP) and cert.forward_error_known
                and np.isfinite(cert.forward_error) and cert.forward_error >= 1.0):
            # an exactly singular M within rounding of a solvable one: what
            # the residuals certify is a solution of nearby data
            sol.message += ("; with no digit guaranteed the data as stored may have no solution "
                            "at all (a Farkas vector was sought and none could be checked "
                            "exactly)")
        return sol
    before = (f"{sol.method} certified a point of nearby data (error {sol.error:.1e})" if sol.ok
              else f"{sol.method} returned {sol.backend_status!r}")
    sol.stats.update({"proof": proof, "proved_infeasible": proof.kind == "infeasible",
                      "proved_unbounded": proof.kind == "unbounded"})
    sol.status, sol.ok = proof.kind, False
    sol.message = f"{proof.message} (found after {before})"
    return sol


def solve(problem, method: str = "auto", accuracy="high", *, raise_on_failure: bool = False,
          time_limit: float | None = DEFAULT_TIME_LIMIT, isolate="auto", **options):
    """Solve an LCP or a QP with a registered method and certify the answer.

    Parameters
    ----------
    problem : LCP, qpsolvers.Problem or ParametricLCP
        A ``ParametricLCP`` is traced in its load parameter (method ``"trace"``
        or ``"auto"``; options ``p_max``, ``max_pieces``) and a
        :class:`~qpcontact.trace.LoadTrace` comes back; fix it first with
        ``problem.at(p)`` to solve one LCP.
    method : str
        A name from :func:`qpcontact.methods` (``"osqp"``, ``"clarabel"``,
        ``"cvxpy:CLARABEL"``, ...) or ``"auto"``, which tries the methods of
        :data:`AUTO_ORDER` that apply to the problem until one is certified.
    accuracy : {"low", "default", "high"} or float
        See :mod:`qpcontact.accuracy`.
    raise_on_failure : bool
        Raise instead of returning a solution that is not ``ok``:
        :class:`NoSolutionError` when no solution exists (a checked Farkas
        vector or ray), :class:`SolverFailedError` otherwise.
    time_limit : float or None
        Seconds each backend call may take (default :data:`DEFAULT_TIME_LIMIT`);
        a call stopped by it has status ``"time_limit"``.  Passed to the
        backends that have a time limit of their own; ProxQP, which has none,
        runs in a child process killed at the limit.  The pivoting methods are
        bounded by their pivot caps instead.  None: no limit.
    isolate : "auto", True or False
        True runs every backend call in a child process (a crash or a hang
        costs that call, not the caller); "auto" only the backends that cannot
        honour the time limit themselves; False none.
    **options
        Passed through to the backend as its own settings (they override the
        accuracy table's).

    Returns
    -------
    LCPSolution or QPSolution
        Always certified from the problem data; ``ok`` is True only when the
        certificate meets the requested accuracy.

    Raises
    ------
    InvalidProblemError, NotSymmetricError, NotConvexError, InvalidOptionError,
    UnknownMethodError, BackendUnavailableError
        On misuse (see :mod:`qpcontact.errors`).
    """
    if not isinstance(method, str):
        raise InvalidOptionError(
            f"method must be a string: 'auto' or a name from qpcontact.methods(); got {method!r}"
        )
    if isinstance(problem, ParametricLCP):
        from ..solvers.trace import solve_parametric

        return solve_parametric(problem, method, accuracy, raise_on_failure, options)
    if isinstance(problem, Problem):
        problem = validate_qp(problem)
        check_convex(problem)
    elif not isinstance(problem, LCP):
        raise InvalidProblemError(
            f"solve() takes an LCP or a qpsolvers.Problem; got {type(problem).__name__}"
        )
    tol_backend, tol_cert = resolve_accuracy(accuracy)
    time_limit = _check_time_limit(time_limit)
    if isolate not in ("auto", True, False):
        raise InvalidOptionError(f"isolate must be 'auto', True or False; got {isolate!r}")
    run = dict(time_limit=time_limit, isolate=isolate)

    if method != "auto":
        sol = _run(problem, get_method(method), tol_backend, tol_cert, accuracy, options, **run)
        if _doubtful(problem, sol):
            sol = _prove_no_solution(problem, sol, time_limit)
    else:
        def candidates():  # lazily: a late entry (cvxpy) is imported only if reached
            for name in _auto_order(problem):
                try:
                    m = get_method(name)
                except (BackendUnavailableError, UnknownMethodError):
                    continue
                if _applicable(problem, m):
                    yield m

        tried, sol, proof_tried = [], None, False
        for m in candidates():
            try:
                attempt = _run(problem, m, tol_backend, tol_cert, accuracy, options, **run)
            except (NotConvexError, NotSymmetricError, InvalidProblemError) as exc:
                # what the up-front checks could not foresee (a block that is not
                # numerically PD, a dense size limit): the next method is tried
                tried.append((m.name, f"skipped: {exc}", np.inf))
                continue
            if not proof_tried and _doubtful(problem, attempt):
                # after the first failure (or doubtful success), not before: a
                # proof costs one or two LPs, and every backend looped on the
                # unbounded QP of the audit
                proof_tried = True
                attempt = _prove_no_solution(problem, attempt, time_limit)
            tried.append((m.name, attempt.status, attempt.error))
            if sol is None or attempt.error < sol.error:
                sol = attempt
            if attempt.ok:
                sol = attempt
                break
            if attempt.stats.get("proved_infeasible") or attempt.stats.get("proved_unbounded"):
                # a Farkas vector or a ray checked from the data: no method can do better
                sol = attempt
                break
        if sol is None:
            raise NotSymmetricError(
                "no installed method applies to this problem; `qpcontact methods` lists what is "
                "installed and what each one requires"
            )
        sol.stats["auto_tried"] = tried
    if raise_on_failure and not sol.ok:
        if sol.status in ("infeasible", "unbounded") or (
                sol.status == "ray" and sol.stats.get("proved_infeasible", True)):
            raise NoSolutionError(f"{sol.method}: {sol.message}")
        raise SolverFailedError(f"{sol.method} returned no certified solution: {sol.message}")
    return sol
