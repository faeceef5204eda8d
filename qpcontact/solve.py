"""``solve``: one entry point for every problem kind and every method."""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp
from qpsolvers import Problem

from .accuracy import resolve_accuracy
from .certify import certify
from .conversions import check_convex, qp_to_lcp, validate_qp
from .errors import (BackendUnavailableError, InvalidOptionError, InvalidProblemError,
                     NoSolutionError,
                     NotConvexError, NotSymmetricError, SolverFailedError, UnknownMethodError)
from .methods import Method, get_method
from .problems import LCP, ParametricLCP
from .solution import LCPSolution, MethodResult, QPSolution

__all__ = ["solve", "AUTO_ORDER"]

#: Preference of ``method="auto"``: exact pivoting first where it applies (as
#: DESIGN.md asks), then the QP backends in the order that reached "high"
#: fastest in benchmarks/backends.py on this machine class (docs/backends.md).
#: "auto" tries them in turn until one is certified.
#: Measured (docs/backends.md): PIQP reached "high" fastest at n = 100, 1000 and
#: 20 000 but stops at ~2e-7 on degenerate problems, where polished OSQP is exact.
AUTO_ORDER = ("energy", "bpp", "lemke", "piqp", "osqp", "clarabel", "daqp", "proxqp",
              "highs", "quadprog", "scs", "cvxpy:CLARABEL")

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
    return LCP(Ms, qs), d


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
    if isinstance(problem, LCP):
        try:
            _check_applicable(problem, m)
        except (NotSymmetricError, NotConvexError):
            return False
        n, sparse = problem.n, problem.is_sparse
    else:
        if m.takes == "lcp":
            return False  # QP -> dual LCP is dense; "auto" keeps QPs on QP backends
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


def _run(problem, m: Method, tol_backend, tol_cert, accuracy, options):
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
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        res: MethodResult = m.run(target, tol_backend, dict(options))
    wall = time.perf_counter() - start

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
    elif cert is None:
        status = "failed"
    else:
        status = "solved" if cert.ok(tol_cert) else "inaccurate"
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
    else:
        message = res.backend_message or status
    return cls(status=status, ok=ok, message=message, certificate=cert, **common, **fields)


def solve(problem, method: str = "auto", accuracy="high", *, raise_on_failure: bool = False,
          **options):
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
        :class:`NoSolutionError` for a ray, :class:`SolverFailedError` otherwise.
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
        from .trace import solve_parametric

        return solve_parametric(problem, method, accuracy, raise_on_failure, options)
    if isinstance(problem, Problem):
        problem = validate_qp(problem)
        check_convex(problem)
    elif not isinstance(problem, LCP):
        raise InvalidProblemError(
            f"solve() takes an LCP or a qpsolvers.Problem; got {type(problem).__name__}"
        )
    tol_backend, tol_cert = resolve_accuracy(accuracy)

    if method != "auto":
        sol = _run(problem, get_method(method), tol_backend, tol_cert, accuracy, options)
    else:
        def candidates():  # lazily: a late entry (cvxpy) is imported only if reached
            for name in AUTO_ORDER:
                try:
                    m = get_method(name)
                except (BackendUnavailableError, UnknownMethodError):
                    continue
                if _applicable(problem, m):
                    yield m

        tried, sol = [], None
        for m in candidates():
            try:
                attempt = _run(problem, m, tol_backend, tol_cert, accuracy, options)
            except (NotConvexError, NotSymmetricError, InvalidProblemError) as exc:
                # what the up-front checks could not foresee (a block that is not
                # numerically PD, a dense size limit): the next method is tried
                tried.append((m.name, f"skipped: {exc}", np.inf))
                continue
            tried.append((m.name, attempt.status, attempt.error))
            if sol is None or attempt.error < sol.error:
                sol = attempt
            if attempt.ok:
                sol = attempt
                break
            if attempt.stats.get("proved_infeasible"):
                # a Farkas vector checked from the data: no method can do better
                sol = attempt
                break
        if sol is None:
            raise NotSymmetricError(
                "no installed method applies to this problem; `qpcontact methods` lists what is "
                "installed and what each one requires"
            )
        sol.stats["auto_tried"] = tried
    if raise_on_failure and not sol.ok:
        if sol.status == "ray" and sol.stats.get("proved_infeasible", True):
            raise NoSolutionError(f"{sol.method}: {sol.message}")
        raise SolverFailedError(f"{sol.method} returned no certified solution: {sol.message}")
    return sol
