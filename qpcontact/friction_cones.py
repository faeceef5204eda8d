r"""3-D (and 2-D) frictional contact through second-order-cone programs.

The Coulomb problem of :mod:`qpcontact.friction` is not the optimality system
of one convex program, but three convex programs sit next to it, each a
second-order-cone program (SOCP) that Clarabel and SCS accept directly:

* **Anitescu's convex relaxation** (``"anitescu"``): min ½ r'Wr + q'r over
  r_i ∈ K_i.  Its optimality system is r_i ∈ K_i, u_i ∈ K_i*, r_i ⟂ u_i —
  Coulomb's with u in place of De Saxcé's û = u + μ‖u_T‖e_N.  The two agree
  where contacts stick or open; a sliding contact of the relaxation separates
  with normal velocity μ‖u_T‖ instead of staying closed.  One SOCP; its
  natural-map error against the true law is reported like every answer.
* **De Saxcé's fixed point** (``"desaxce-fp"``): with s_i = μ_i ‖u_T,i‖
  frozen at the previous iterate, min ½ r'Wr + (q + Σ s_i e_N,i)'r over
  r ∈ K is the relaxation of a problem whose modified velocity is exactly
  û; a fixed point of s ↦ s(r(s)) solves Coulomb's law.  Converges for
  small μ or well-conditioned W (no proof in general: the iteration stops
  and says so when the error stalls).
* **Tresca's fixed point** (``"tresca-fp"``): with the slip threshold
  g_i = μ_i r_N,i frozen, min ½ r'Wr + q'r over r_N >= 0, ‖r_T,i‖ <= g_i is
  Tresca's bounded friction (a disc — a second-order cone with a constant
  axis — so an SOCP, not a QP); a fixed point of g ↦ μ r_N(g) is Coulomb's.

Units are the caller's: W in velocity per force (m/s/N or per impulse), q in
velocity, r in force.  Each subproblem goes to a cone backend by name
(:data:`CONE_BACKENDS`: ``"clarabel"`` (default) or ``"scs"``), one small
function each, settings through ``backend_options``.  Nothing a backend
reports is believed: the caller certifies r by the natural-map error.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .errors import InvalidOptionError

__all__ = ["CONE_BACKENDS", "solve_anitescu", "solve_desaxce_fp", "solve_tresca_fp"]


def _cone_rows(dim: int, mu: np.ndarray, tresca: np.ndarray | None):
    """A, b and the cone sizes for  s = b − A r ∈ R₊^nc × SOC(dim)^nc:
    s = r_N (nonnegative normal reactions), then per contact the cone block
    (μ r_N, r_T) — or (g, r_T) for Tresca's disc of radius g."""
    nc = mu.size
    m = dim * nc
    rows, cols, vals = [], [], []
    b = np.zeros(nc + m)
    normal = np.arange(nc) * dim
    rows.append(np.arange(nc)), cols.append(normal), vals.append(-np.ones(nc))
    head = nc + normal
    if tresca is None:
        rows.append(head), cols.append(normal), vals.append(-mu)
    else:
        b[head] = tresca
    for t in range(1, dim):
        rows.append(head + t), cols.append(normal + t), vals.append(-np.ones(nc))
    A = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(nc + m, m))
    return A, b


def _clarabel(P, c, A, b, nc, dim, tol, options):
    import clarabel

    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = tol
    settings.tol_ktratio = min(settings.tol_ktratio, tol)
    for key, value in options.items():
        if not hasattr(settings, key):
            raise InvalidOptionError(f"clarabel has no setting {key!r}")
        setattr(settings, key, value)
    cones = [clarabel.NonnegativeConeT(nc)] + [clarabel.SecondOrderConeT(dim)] * nc
    sol = clarabel.DefaultSolver(sp.triu(P, format="csc"), c, A, b, cones, settings).solve()
    status = str(sol.status)
    usable = status in ("Solved", "AlmostSolved", "MaxIterations", "InsufficientProgress")
    return (np.asarray(sol.x) if usable else None), status, int(sol.iterations)


def _scs(P, c, A, b, nc, dim, tol, options):
    import scs

    settings = {"verbose": False, "eps_abs": tol, "eps_rel": tol, "max_iters": 100_000}
    settings.update(options)
    data = {"P": sp.triu(P, format="csc"), "A": A, "b": b, "c": c}
    try:
        sol = scs.SCS(data, {"l": nc, "q": [dim] * nc}, **settings).solve()
    except (TypeError, ValueError) as exc:   # an unknown setting
        raise InvalidOptionError(f"scs refused its settings: {exc}") from None
    status = str(sol["info"]["status"])
    usable = status in ("solved", "solved_inaccurate")
    return (np.asarray(sol["x"]) if usable else None), status, int(sol["info"]["iter"])


#: SOCP backends by name: (P, c, A, b, n_contacts, dim, tol, options) -> (r, status, iterations)
CONE_BACKENDS = {"clarabel": _clarabel, "scs": _scs}


class _Subproblem:
    """min ½ r'Wr + c'r over the cones of one method, solved by a named backend."""

    def __init__(self, problem, options):
        backend = options.pop("backend", "clarabel")
        if backend not in CONE_BACKENDS:
            raise InvalidOptionError(f"unknown cone backend {backend!r}; choose from "
                                     f"{', '.join(CONE_BACKENDS)}")
        self.backend = backend
        self.backend_options = dict(options.pop("backend_options", {}) or {})
        self.inner_tol = float(options.pop("inner_tol", 1e-10))
        self.problem = problem
        self.P = sp.csc_matrix(problem.W)
        self.P = 0.5 * (self.P + self.P.T)
        self.inner_iterations = 0

    def solve(self, c, tresca=None):
        p = self.problem
        A, b = _cone_rows(p.dim, p.mu, tresca)
        r, status, its = CONE_BACKENDS[self.backend](
            self.P, c, A, b, p.n_contacts, p.dim, self.inner_tol, self.backend_options)
        self.inner_iterations += its
        return r, status


def _no_options_left(method, options):
    if options:
        raise InvalidOptionError(f"{method!r} does not take {', '.join(sorted(options))}; its "
                                 "options are backend, backend_options, inner_tol"
                                 + ("" if method == "anitescu" else ", max_outer, progress"))


def solve_anitescu(problem, tol, options):
    options = dict(options)
    sub = _Subproblem(problem, options)
    _no_options_left("anitescu", options)
    r, status = sub.solve(problem.q.copy())
    return r, status, f"one SOCP by {sub.backend} ({status})", {
        "inner_iterations": sub.inner_iterations, "backend": sub.backend}


def _fixed_point(method, problem, tol, options, update):
    """Iterate r ← SOCP(update(r)) until the natural-map error is <= tol, or
    stops improving (no new best in ``patience`` = 5 iterations), or
    ``max_outer`` (default 100) iterations."""
    from .friction import natural_map_error

    options = dict(options)
    sub = _Subproblem(problem, options)
    max_outer = int(options.pop("max_outer", 100))
    progress = options.pop("progress", None)
    _no_options_left(method, options)
    r = np.zeros(problem.W.shape[0])
    best, best_r, since_best, errors = np.inf, None, 0, []
    status = "not started"
    for k in range(1, max_outer + 1):
        c, tresca = update(r)
        r_new, status = sub.solve(c, tresca)
        if r_new is None:
            break
        r = r_new
        err = natural_map_error(problem, r)
        errors.append(err)
        if progress is not None:
            progress(f"{method}: iteration {k}: natural-map error {err:.2e}")
        if err < best:
            best, best_r, since_best = err, r.copy(), 0
        else:
            since_best += 1
        if err <= tol or since_best >= 5:
            break
    stats = {"iterations": len(errors), "inner_iterations": sub.inner_iterations,
             "backend": sub.backend, "errors": errors}
    if best_r is None:
        return None, status, f"{sub.backend} returned no point ({status})", stats
    why = ("reached the tolerance" if best <= tol else
           "stalled (no better iterate in 5)" if since_best >= 5 else
           f"stopped at {max_outer} iterations" if len(errors) >= max_outer else
           f"{sub.backend} failed on a subproblem ({status})")
    return best_r, status, f"fixed point {why}, best of {len(errors)} SOCPs by {sub.backend}", \
        stats


def solve_desaxce_fp(problem, tol, options):
    d = problem.dim

    def update(r):
        U = problem.velocities(r).reshape(-1, d)
        c = problem.q.copy()
        c[0::d] += problem.mu * np.linalg.norm(U[:, 1:], axis=1)
        return c, None
    return _fixed_point("desaxce-fp", problem, tol, options, update)


def solve_tresca_fp(problem, tol, options):
    d = problem.dim
    first = [True]

    def update(r):
        if first[0]:   # no reaction yet: the first thresholds come from Anitescu's relaxation
            first[0] = False
            return problem.q.copy(), None
        return problem.q.copy(), problem.mu * np.maximum(r[0::d], 0.0)
    return _fixed_point("tresca-fp", problem, tol, options, update)


def _projection_jacobian(x, mu, dim):
    """Blocks of the (generalized) Jacobian of proj_K at x, one per contact."""
    X = x.reshape(-1, dim)
    J = np.zeros((mu.size, dim, dim))
    xn, xt = X[:, 0], X[:, 1:]
    t = np.linalg.norm(xt, axis=1)
    inside = t <= mu * xn
    J[inside] = np.eye(dim)
    mid = ~inside & ~(mu * t <= -xn)
    for i in np.flatnonzero(mid):   # a few hundred contacts at most per call
        m, that = mu[i], xt[i] / t[i]
        alpha = (xn[i] + m * t[i]) / (1 + m * m)
        v = np.concatenate([[1.0], m * that])
        J[i] = np.outer(v, v) / (1 + m * m)
        J[i][1:, 1:] += m * alpha / t[i] * (np.eye(dim - 1) - np.outer(that, that))
    return J


def solve_natural_newton(problem, tol, options):
    """Semismooth Newton on the natural map F(r) = r − proj_K(r − ρ û(r))
    (Siconos's NSN family), globalized by an Armijo line search on ½‖F‖²;
    ρ_i = 1 / (W_i's normal diagonal entry) per contact, so that each
    contact is judged on its own scale.  Starts from ``r0`` (default:
    Anitescu's relaxation by Clarabel).  Local quadratic convergence near a
    nondegenerate solution; no global guarantee — it stops and says so when
    the line search fails.  Options: ``r0``, ``max_iter`` (100), ``progress``."""
    from .friction import natural_map_error, project_cone

    options = dict(options)
    r0 = options.pop("r0", None)
    max_iter = int(options.pop("max_iter", 100))
    progress = options.pop("progress", None)
    if options:
        raise InvalidOptionError(f"'newton' does not take {', '.join(sorted(options))}; its "
                                 "options are r0, max_iter, progress")
    p, d = problem, problem.dim
    nc, mu = p.n_contacts, p.mu
    stats = {"inner_iterations": 0}
    if r0 is None:
        r0, status, _, st = solve_anitescu(p, tol, {})
        stats["inner_iterations"] = st["inner_iterations"]
        if r0 is None:
            return None, status, "the starting SOCP gave no point", stats
    r = np.asarray(r0, float).copy()
    W = p.W.toarray() if sp.issparse(p.W) else np.asarray(p.W, float)
    wn = np.abs(np.diag(W)[0::d])
    rho = np.repeat(1.0 / np.where(wn > 0, wn, 1.0), d)

    def F(r):
        u = W @ r + p.q
        U = u.reshape(-1, d)
        tn = np.linalg.norm(U[:, 1:], axis=1)
        uh = U.copy()
        uh[:, 0] += mu * tn
        x = r - rho * uh.ravel()
        return r - project_cone(x, mu, d), x, U, tn

    Fr, x, U, tn = F(r)
    phi = 0.5 * Fr @ Fr
    best_err, best_r = natural_map_error(p, r), r.copy()
    k, why = 0, f"stopped at {max_iter} iterations"
    for k in range(1, max_iter + 1):
        if best_err <= tol:
            why = "reached the tolerance"
            break
        # Jacobian of û: W plus μ e_N (u_T/‖u_T‖)' W_T (zero where u_T = 0)
        Juh = W.copy()
        slip = np.flatnonzero(tn > 0)
        for i in slip:
            g = U[i, 1:] / tn[i]
            Juh[d * i] += mu[i] * (g @ W[d * i + 1:d * i + d])
        JP = _projection_jacobian(x, mu, d)
        A = np.eye(W.shape[0]) - rho[:, None] * Juh
        J = np.eye(W.shape[0])
        for i in range(nc):
            s = slice(d * i, d * i + d)
            J[s] -= JP[i] @ A[s]
        found = None
        # LU first (fast); where the generalized Jacobian is near singular its
        # step is huge and fails the line search: then the least-squares step
        for solver in ("lu", "lstsq"):
            try:
                step = (np.linalg.solve(J, -Fr) if solver == "lu"
                        else np.linalg.lstsq(J, -Fr, rcond=None)[0])
            except np.linalg.LinAlgError:
                continue
            t = 1.0
            while t > 1e-10:
                F_new, x_new, U_new, tn_new = F(r + t * step)
                if 0.5 * F_new @ F_new <= (1 - 1e-4 * t) * phi:
                    found = t
                    break
                t *= 0.5
            if found is not None:
                break
        if found is None:
            why = "the line search failed (a stationary point of ½‖F‖² that is not a solution)"
            break
        r = r + t * step
        Fr, x, U, tn = F_new, x_new, U_new, tn_new
        phi = 0.5 * Fr @ Fr
        err = natural_map_error(p, r)
        if progress is not None:
            progress(f"newton: iteration {k}: natural-map error {err:.2e}, step {t:g}")
        if err < best_err:
            best_err, best_r = err, r.copy()
    stats["iterations"] = k
    return best_r, "solved" if best_err <= tol else "stopped", f"semismooth Newton: {why}", stats
