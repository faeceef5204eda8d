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
function each, settings through ``backend_options``.  In 2-D the cones are
polyhedral and every subproblem is a QP: any QP method of
:func:`qpcontact.solve` takes it (``backend="osqp"``, ``"daqp"``, ...).
Nothing a backend reports is believed: the caller certifies r by the
natural-map error.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..core.errors import InvalidOptionError, NotConvexError

__all__ = ["CONE_BACKENDS", "solve_anitescu", "solve_desaxce_fp", "solve_tresca_fp",
           "solve_desaxce_global", "no_equilibrium"]


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


def _clarabel(P, c, A, b, nc, dim, tol, options, nonneg=None):
    import clarabel

    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = tol
    settings.tol_ktratio = min(settings.tol_ktratio, tol)
    for key, value in options.items():
        if not hasattr(settings, key):
            raise InvalidOptionError(f"clarabel has no setting {key!r}")
        setattr(settings, key, value)
    nonneg = nc if nonneg is None else nonneg
    cones = ([clarabel.NonnegativeConeT(nonneg)] if nonneg else []) + \
        [clarabel.SecondOrderConeT(dim)] * nc
    sol = clarabel.DefaultSolver(sp.triu(P, format="csc"), c, A, b, cones, settings).solve()
    status = str(sol.status)
    usable = status in ("Solved", "AlmostSolved", "MaxIterations", "InsufficientProgress")
    if status in ("DualInfeasible", "AlmostDualInfeasible"):   # x is then a ray: unbounded
        return np.asarray(sol.x), None, "unbounded", int(sol.iterations)
    if not usable:
        return None, None, status, int(sol.iterations)
    return np.asarray(sol.x), np.asarray(sol.z), status, int(sol.iterations)


def _scs(P, c, A, b, nc, dim, tol, options, nonneg=None):
    import scs

    settings = {"verbose": False, "eps_abs": tol, "eps_rel": tol, "max_iters": 100_000}
    settings.update(options)
    data = {"P": sp.triu(P, format="csc"), "A": A, "b": b, "c": c}
    try:
        sol = scs.SCS(data, {"l": nc if nonneg is None else nonneg, "q": [dim] * nc},
                      **settings).solve()
    except (TypeError, ValueError) as exc:   # an unknown setting
        raise InvalidOptionError(f"scs refused its settings: {exc}") from None
    status = str(sol["info"]["status"])
    usable = status in ("solved", "solved_inaccurate")
    if status in ("unbounded", "unbounded_inaccurate"):   # x is then a ray
        return np.asarray(sol["x"]), None, "unbounded", int(sol["info"]["iter"])
    if not usable:
        return None, None, status, int(sol["info"]["iter"])
    return np.asarray(sol["x"]), np.asarray(sol["y"]), status, int(sol["info"]["iter"])


#: SOCP backends by name: (P, c, A, b, n_contacts, dim, tol, options, nonneg=n_contacts) ->
#: (x, the cone constraints' multipliers, status, iterations); ``nonneg`` nonnegative rows
#: come before the n_contacts second-order cones of size dim.  Status "unbounded": x is the
#: backend's ray (the objective decreases without bound along it), no multipliers.
CONE_BACKENDS = {"clarabel": _clarabel, "scs": _scs}


def _qp_method(name: str):
    """The registered QP method called ``name`` (any constraints), or None."""
    from ..core.errors import UnknownMethodError
    from ..solvers.registry import get_method

    try:
        m = get_method(name)    # BackendUnavailableError (with its pip command) goes up
    except UnknownMethodError:
        return None
    return m.name if m.takes == "qp" and m.constraints == "any" else None


class _Subproblem:
    """min ½ r'Wr + c'r over the cones of one method, solved by a named backend.

    In 2-D every cone is polyhedral — K = {|r_T| <= μ r_N}, Tresca's disc the
    interval |r_T| <= g — so the subproblem is a QP, and any QP method of
    :func:`qpcontact.solve` takes it (``backend="osqp"``, ``"proxqp"``,
    ``"daqp"``, ``"cvxpy:OSQP"``, ...), each answer certified there as a QP
    before the friction measures judge the iterate."""

    def __init__(self, problem, options, qp_allowed: bool = True):
        self.problem = problem
        self._backend(options, qp_allowed)
        self.P = sp.csc_matrix(problem.W)
        self.P = 0.5 * (self.P + self.P.T)
        self.size = problem.W.shape[0]

    def _backend(self, options, qp_allowed: bool = True):
        backend = options.pop("backend", "clarabel")
        self.qp = None
        if backend not in CONE_BACKENDS:
            self.qp = _qp_method(backend) if isinstance(backend, str) else None
            if self.qp is None:
                raise InvalidOptionError(
                    f"unknown cone backend {backend!r}; choose from {', '.join(CONE_BACKENDS)}"
                    + (", or in 2-D any QP method of qpcontact.methods() (osqp, proxqp, daqp, "
                       "...)" if qp_allowed else ""))
            if not qp_allowed or self.problem.dim != 2:
                raise InvalidOptionError(
                    f"{backend!r} is a QP method: it takes the subproblems of local 2-D "
                    "problems, whose cones are polyhedral; here they have second-order cones — "
                    f"use {' or '.join(CONE_BACKENDS)}")
        self.backend = backend
        self.backend_options = dict(options.pop("backend_options", {}) or {})
        self.inner_tol = float(options.pop("inner_tol", 1e-10))
        self.inner_iterations = 0

    def solve(self, c, tresca=None):
        p = self.problem
        if self.qp is not None:
            return self._solve_qp(c, tresca)
        A, b = _cone_rows(p.dim, p.mu, tresca)
        r, z, status, its = CONE_BACKENDS[self.backend](
            self.P, c, A, b, p.n_contacts, p.dim, self.inner_tol, self.backend_options)
        self.inner_iterations += its
        return (None if status == "unbounded" else r), status

    @cached_property
    def _cone_rows_2d(self) -> sp.csc_matrix:
        """G with G r <= 0 the 2-D cones: ∓r_T − μ r_N <= 0, two rows a contact."""
        p = self.problem
        nc = p.n_contacts
        normal, tangent = 2 * np.arange(nc), 2 * np.arange(nc) + 1
        rows = np.repeat(np.arange(2 * nc), 2)
        cols = np.stack([normal, tangent, normal, tangent], 1).ravel()
        vals = np.stack([-p.mu, np.ones(nc), -p.mu, -np.ones(nc)], 1).ravel()
        return sp.csc_matrix((vals, (rows, cols)), shape=(2 * nc, self.size))

    def _solve_qp(self, c, tresca):
        """The 2-D subproblem as a qpsolvers.Problem: r_N >= 0 and either the
        cone's two rows ∓r_T − μ r_N <= 0 or Tresca's bounds |r_T| <= g."""
        import qpsolvers

        from ..dispatch.driver import solve

        p = self.problem
        nc, m = p.n_contacts, self.size
        normal, tangent = 2 * np.arange(nc), 2 * np.arange(nc) + 1
        lb, ub = np.full(m, -np.inf), np.full(m, np.inf)
        lb[normal] = 0.0
        G = h = None
        if tresca is None:
            G, h = self._cone_rows_2d, np.zeros(2 * nc)
        else:
            lb[tangent], ub[tangent] = -tresca, tresca
        try:
            sol = solve(qpsolvers.Problem(self.P, c, G, h, lb=lb, ub=ub), self.qp,
                        accuracy=self.inner_tol, **self.backend_options)
        except NotConvexError:
            raise NotConvexError(
                f"W is not positive semidefinite, so the subproblems are nonconvex QPs, which "
                f"{self.backend!r} is not given (a file storing a singular W rounded to a few "
                "digits is indefinite at that level); use a cone backend (clarabel, scs), "
                "'nsgs' or 'lemke'") from None
        self.inner_iterations += sol.iterations or 0
        return (sol.x if sol.status != "unbounded" else None), sol.status


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


def _fixed_point(method, problem, tol, options, update, subproblem=None, measure=None):
    """Iterate r ← SOCP(update(r)) until both error measures are <= tol, or
    neither has improved for 5 iterations, or ``max_outer`` (default 100)
    iterations.  Returns the iterate with the smallest certified error (the
    larger of the two), ties going to the smaller natural-map error: where a
    few contacts carrying ~1e-22 forces hold the componentwise error at 0.5
    the iteration still improves the rest, and is kept going for it."""
    from .problem import componentwise_error, natural_map_error

    options = dict(options)
    sub = (subproblem or _Subproblem)(problem, options)
    measure = measure or (lambda r: (natural_map_error(problem, r),
                                     componentwise_error(problem, r)))
    max_outer = int(options.pop("max_outer", 100))
    progress = options.pop("progress", None)
    _no_options_left(method, options)
    r = np.zeros(sub.size)
    best_key, best_r, lowest, since, errors = (np.inf, np.inf), None, [np.inf, np.inf], 0, []
    status = "not started"
    for k in range(1, max_outer + 1):
        c, tresca = update(r)
        r_new, status = sub.solve(c, tresca)
        if r_new is None:
            break
        r = r_new
        nat, cw = measure(r)
        errors.append(max(nat, cw))
        if progress is not None:
            progress(f"{method}: iteration {k}: natural-map error {nat:.2e}, "
                     f"componentwise {cw:.2e}")
        key = (max(nat, cw), nat)
        if key < best_key:
            best_key, best_r = key, r.copy()
        improved = nat < lowest[0] or cw < lowest[1]
        lowest = [min(lowest[0], nat), min(lowest[1], cw)]
        since = 0 if improved else since + 1
        if key[0] <= tol or since >= 5:
            break
    stats = {"iterations": len(errors), "inner_iterations": sub.inner_iterations,
             "backend": sub.backend, "errors": errors}
    if best_r is None:
        return None, status, f"{sub.backend} returned no point ({status})", stats
    why = ("reached the tolerance" if best_key[0] <= tol else
           "stalled (neither error improved in 5 iterations)" if since >= 5 else
           f"stopped at {max_outer} iterations" if len(errors) >= max_outer else
           f"{sub.backend} failed on a subproblem ({status})")
    return best_r, status, f"fixed point {why}, best of {len(errors)} SOCPs by {sub.backend}", \
        stats


def _desaxce_shift(u, mu, d) -> np.ndarray:
    """s with s_N,i = μ_i‖u_T,i‖ and zero tangents: De Saxcé's û − u."""
    U = np.reshape(u, (-1, d))
    shift = np.zeros(U.size)
    shift[0::d] = mu * np.linalg.norm(U[:, 1:], axis=1)
    return shift


def solve_desaxce_fp(problem, tol, options):
    def update(r):
        return problem.q + _desaxce_shift(problem.velocities(r), problem.mu, problem.dim), None
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


class _GlobalSubproblem(_Subproblem):
    """De Saxcé's subproblem of a global problem, in the velocities v:

        min ½ v'Mv − f'v   s.t.   D_i (H_i'v + w_i + s_i e_N) ∈ SOC(dim),

    D_i = diag(1, μ_i, …) (so the constraint reads û_i ∈ K_i*).  Its
    multipliers z_i give r_i = D_i z_i ∈ K_i and stationarity Mv = Hr + f, and
    complementarity is û'r = 0: for s = μ‖u_T‖ its solution is Coulomb's.  M
    may be singular (a mechanism without its contacts) wherever the contacts
    bound the motion; W is never formed.  The iterate is x = (r, v)."""

    def __init__(self, problem, options):
        self.problem = problem
        self._backend(options, qp_allowed=False)
        g, d = problem.global_data, problem.dim
        self.P = 0.5 * (g["M"] + g["M"].T)
        scale = np.ones(d * problem.n_contacts)
        for t in range(1, d):
            scale[t::d] = problem.mu
        self.D = scale
        self.A = -(sp.diags(scale) @ g["H"].T).tocsc()
        self.m = d * problem.n_contacts
        self.size = self.m + g["M"].shape[0]

    def solve(self, shift, tresca=None):
        p, g = self.problem, self.problem.global_data
        b = self.D * (g["w"] + shift)
        v, z, status, its = CONE_BACKENDS[self.backend](
            self.P, -g["f"], self.A, b, p.n_contacts, p.dim, self.inner_tol,
            self.backend_options, nonneg=0)
        self.inner_iterations += its
        if status == "unbounded":
            self.ray = v
        if v is None or z is None:
            return None, status
        return np.concatenate([self.D * z, v]), status


def solve_desaxce_global(problem, tol, options):
    """De Saxcé's fixed point on a global problem kept without W: each
    iterate one SOCP in v (:class:`_GlobalSubproblem`), s = μ‖u_T‖ from the
    last u = H'v + w.  Returns x = (r, v)."""
    from .problem import global_errors

    g, d = problem.global_data, problem.dim
    m = d * problem.n_contacts

    def update(x):
        return _desaxce_shift(np.asarray(g["H"].T @ x[m:]).ravel() + g["w"], problem.mu, d), None

    def measure(x):
        nat, cw, eq = global_errors(problem, x[:m], x[m:])
        return nat, max(cw, eq)

    made = []

    def subproblem(problem, options):
        made.append(_GlobalSubproblem(problem, options))
        return made[-1]
    x, status, message, stats = _fixed_point("desaxce-global", problem, tol, options, update,
                                             subproblem, measure)
    if x is not None and max(measure(x)) > tol:
        polished = _polish_global(problem, x)
        if polished is not None and max(measure(polished)) < max(measure(x)):
            x = polished
            message += "; polished by one linear solve on its contact states"
    ray = getattr(made[0], "ray", None) if made else None
    if x is None and ray is not None:
        proof = no_equilibrium(problem, ray)
        if proof is not None:
            message, stats["ray"] = proof
    return x, status, message, stats


def _polish_global(problem, x):
    """An interior-point answer is accurate to the backend's tolerance (5e-7
    in the equilibrium of a frame whose K spans 1e6…1e8); its contact states
    are usually right.  Fix them and solve the square linear system exactly:
    Mv − Hr = f; an open contact r_i = 0; a sticking one H_iᵀv + w_i = 0; a
    sliding one H_Nᵀv + w_N = 0 and r_T = μ r_N t̂ (t̂ its current friction
    direction).  None when that system is singular; the caller keeps
    whichever point has the smaller error."""
    g, d = problem.global_data, problem.dim
    M, H, f, w, mu = g["M"], g["H"], g["f"], g["w"], problem.mu
    n, m = M.shape[0], d * problem.n_contacts
    r, v = x[:m].reshape(-1, d), x[m:]
    U = (np.asarray(H.T @ v).ravel() + w).reshape(-1, d)
    size = np.linalg.norm(r, axis=1)
    big = size.max(initial=0.0)
    t = np.linalg.norm(r[:, 1:], axis=1)
    Ht = sp.csr_matrix(H.T)
    rows = [sp.hstack([sp.csr_matrix(M), -sp.csr_matrix(H)])]
    rhs = [f]
    for i in range(problem.n_contacts):
        block = slice(d * i, d * i + d)
        if size[i] <= 1e-9 * big and U[i, 0] >= 0:            # open
            rows.append(sp.hstack([sp.csr_matrix((d, n)), sp.eye(d, m, d * i)]))
            rhs.append(np.zeros(d))
        elif mu[i] > 0 and t[i] >= (1 - 1e-6) * mu[i] * r[i, 0] and t[i] > 0:   # sliding
            rows.append(sp.hstack([Ht[d * i:d * i + 1], sp.csr_matrix((1, m))]))
            rhs.append(-w[d * i:d * i + 1])
            tangent = sp.lil_matrix((d - 1, m))
            for k in range(1, d):
                tangent[k - 1, d * i + k] = 1.0
                tangent[k - 1, d * i] = -mu[i] * r[i, k] / t[i]
            rows.append(sp.hstack([sp.csr_matrix((d - 1, n)), tangent]))
            rhs.append(np.zeros(d - 1))
        else:                                                   # sticking
            rows.append(sp.hstack([Ht[block], sp.csr_matrix((d, m))]))
            rhs.append(-w[block])
    K = sp.vstack(rows).tocsc()
    try:
        lu = spla.splu(K)
    except RuntimeError:
        return None
    y = lu.solve(np.concatenate(rhs))
    y = y + lu.solve(np.concatenate(rhs) - K @ y)          # one step of refinement
    if not np.all(np.isfinite(y)):
        return None
    return np.concatenate([y[n:], y[:n]])


def no_equilibrium(problem, d):
    """Check a ray d of De Saxcé's subproblem from the data: Md = 0, Hᵀd in
    every contact's dual cone K_i* and fᵀd > 0 (each to rounding).  Then no
    r in the cones balances the loads — for any v, Mv = Hr + f would give
    0 = dᵀMv = (Hᵀd)·r + fᵀd > 0.  Returns (the sentence that says so, the
    checked d — scaled to max|d| = 1, entries below 1e-9 set to zero), or
    None when d does not prove it."""
    g, dim = problem.global_data, problem.dim
    d = np.asarray(d, float)
    if not np.all(np.isfinite(d)) or not np.abs(d).max(initial=0.0) > 0:
        return None
    d = d / np.abs(d).max()
    d[np.abs(d) < 1e-9] = 0.0     # an interior-point ray's noise; the checks below are on this d
    Md, size = np.asarray(g["M"] @ d).ravel(), np.asarray(abs(g["M"]) @ np.abs(d)).ravel()
    U = np.asarray(g["H"].T @ d).ravel().reshape(-1, dim)
    slack = U[:, 0] - problem.mu * np.linalg.norm(U[:, 1:], axis=1)
    work, work_size = float(g["f"] @ d), float(np.abs(g["f"]) @ np.abs(d))
    rounding = 1e-9 * max(np.abs(U).max(initial=0.0), 1e-300)
    if np.any(np.abs(Md) > 1e-9 * np.maximum(size, 1e-300)) or np.any(slack < -rounding) \
            or not work > 1e-9 * work_size:
        return None
    return (f"no equilibrium exists: no contact forces within the friction cones balance the "
            f"loads — the motion d (stats['ray']) has Md = 0, every contact admits it (Hᵀd in "
            f"its dual cone: it opens or slides within the cone), and the loads do positive "
            f"work fᵀd = {work:.3g} on it (checked from the data)"), d


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


#: above this many local unknowns (and W sparse) Newton's linear algebra is sparse
SPARSE_NEWTON_MIN = 1000

#: a Newton step shorter than this also tries Levenberg–Marquardt's
LM_BELOW = 1e-3


def solve_natural_newton(problem, tol, options):
    """Semismooth Newton on the natural map F(r) = r − proj_K(r − ρ û(r))
    (Siconos's NSN family), globalized by an Armijo line search on ½‖F‖²;
    ρ_i = 1 / (W_i's normal diagonal entry) per contact
    (:func:`~qpcontact.friction.contact_scales`), so that F is a force, and
    the merit ½‖DF‖² weighs each contact by 1 / its size (D from
    :func:`~qpcontact.friction.contact_sizes`, frozen per iteration).  Starts from ``r0`` (default:
    Anitescu's relaxation by Clarabel).  Local quadratic convergence near a
    nondegenerate solution; no global guarantee — it stops and says so when
    the line search fails.  Options: ``r0``, ``max_iter`` (100), ``progress``."""
    from .problem import (certified_error, contact_scales, contact_sizes, modified_velocity,
                          project_cone)

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
    m = d * nc
    # sparse Jacobians and factorizations for large sparse W (a granular
    # file: 4040 unknowns, 0.8 % filled); dense LAPACK below that
    sparse = sp.issparse(p.W) and m > SPARSE_NEWTON_MIN
    W = sp.csr_matrix(p.W) if sparse else (p.W.toarray() if sp.issparse(p.W)
                                           else np.asarray(p.W, float))
    rho = np.repeat(contact_scales(p), d)
    normal_rows = d * np.arange(nc)

    def sparse_solve(A, rhs):
        try:
            return spla.splu(sp.csc_matrix(A)).solve(rhs)
        except RuntimeError as exc:   # exactly singular: as LAPACK would say
            raise np.linalg.LinAlgError(str(exc)) from None

    def F(r):
        u = W @ r + p.q
        U = u.reshape(-1, d)
        x = r - rho * modified_velocity(u, mu, d)
        return r - project_cone(x, mu, d), x, U, np.linalg.norm(U[:, 1:], axis=1)

    weighted = [False]

    def weights(r):
        """Unweighted first (½‖F‖² globalizes best from a far start); once
        its line search fails, 1 / each contact's size, frozen for one
        iteration: the merit ½‖DF‖² then weighs a small contact's residual
        on its own scale, as the certificate does — the unweighted merit
        reaches rounding level on the large contacts and stalls while a
        small one is still 1e-6 off."""
        if not weighted[0]:
            return np.ones(r.size)
        s = contact_sizes(p, r, rho[0::d])
        return np.repeat(1.0 / np.where(s > 0, s, 1.0), d)

    Fr, x, U, tn = F(r)
    D = weights(r)
    phi = 0.5 * np.sum((D * Fr) ** 2)
    best_err, best_r = certified_error(p, r), r.copy()
    k, why = 0, f"stopped at {max_iter} iterations"
    for k in range(1, max_iter + 1):
        if best_err <= tol:
            why = "reached the tolerance"
            break
        # Jacobian of û: (I + Σ_slip μ_i e_N,i g_i') W, g_i = u_T,i/‖u_T,i‖ placed
        # in contact i's tangent columns (zero where u_T = 0)
        slip = np.flatnonzero(tn > 0)
        g = U[slip, 1:] / tn[slip, None]
        rows = np.repeat(normal_rows[slip], d - 1)
        cols = (normal_rows[slip, None] + 1 + np.arange(d - 1)).ravel()
        T = sp.identity(m, format="csr") + sp.csr_matrix(
            ((mu[slip, None] * g).ravel(), (rows, cols)), shape=(m, m))
        A = sp.identity(m, format="csr") - sp.diags(rho) @ (T @ W)
        JP = sp.bsr_matrix((_projection_jacobian(x, mu, d), np.arange(nc), np.arange(nc + 1)),
                           shape=(m, m))
        J = sp.csc_matrix(sp.identity(m) - JP @ A) if sparse else \
            np.eye(m) - JP.toarray() @ np.asarray(A)
        # The Newton step first (LU, fast).  Where the generalized Jacobian
        # is near singular (a rank-deficient W: BoxesStack1's is 78 of 156)
        # that step is huge and the line search creeps: then also
        # Levenberg–Marquardt's, (J'J + λI) d = −J'F with λ = ‖F‖
        # (Yamashita–Fukushima), well posed and fast near a solution; the
        # one whose point has the smaller certified error is taken.  Where
        # both fail, the least-squares (minimum-norm) step: on Capsules-i101
        # only that one leaves the point where the others stall.
        def search(step):
            t = 1.0
            while t > 1e-10:
                trial = F(r + t * step)
                if 0.5 * np.sum((D * trial[0]) ** 2) <= (1 - 1e-4 * t) * phi:
                    return t, step, trial
                t *= 0.5
            return None

        def lm_step():
            JD = sp.diags(D) @ J if sparse else D[:, None] * J
            JtJ = JD.T @ JD + np.sqrt(2 * phi) * (sp.identity(m) if sparse else np.eye(m))
            rhs = -(JD.T @ (D * Fr))
            return sparse_solve(JtJ, rhs) if sparse else np.linalg.solve(JtJ, rhs)

        def newton_step():
            return sparse_solve(J, -Fr) if sparse else np.linalg.solve(J, -Fr)

        def least_squares_step():
            if sparse:
                return spla.lsqr(J, -Fr, atol=1e-14, btol=1e-14, iter_lim=10 * m)[0]
            return np.linalg.lstsq(J, -Fr, rcond=None)[0]

        try:
            chosen = search(newton_step())
        except np.linalg.LinAlgError:
            chosen = None
        if chosen is None or chosen[0] < LM_BELOW:
            try:
                lm = search(lm_step())
            except np.linalg.LinAlgError:
                lm = None
            if lm is not None and (chosen is None or certified_error(p, r + lm[0] * lm[1])
                                   < certified_error(p, r + chosen[0] * chosen[1])):
                chosen = lm
        if chosen is None:   # the minimum-norm step of a singular J
            chosen = search(least_squares_step())
        if chosen is None and not weighted[0]:
            weighted[0] = True
            D = weights(r)
            phi = 0.5 * np.sum((D * Fr) ** 2)
            continue
        if chosen is None:
            why = "the line search failed (a stationary point of ½‖DF‖² that is not a solution)"
            break
        t, step, (F_new, x_new, U_new, tn_new) = chosen
        r = r + t * step
        Fr, x, U, tn = F_new, x_new, U_new, tn_new
        D = weights(r)
        phi = 0.5 * np.sum((D * Fr) ** 2)
        err = certified_error(p, r)
        if progress is not None:
            progress(f"newton: iteration {k}: error {err:.2e} (natural map and componentwise), "
                     f"step {t:g}, ½‖DF‖² = {phi:.2e}")
        if err < best_err:
            best_err, best_r = err, r.copy()
    stats["iterations"] = k
    return best_r, "solved" if best_err <= tol else "stopped", f"semismooth Newton: {why}", stats
