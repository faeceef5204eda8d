"""The convex subproblems of the friction methods and the backends that take them.

Each subproblem is min ½ r'Wr + c'r over the cones of one method — a
second-order-cone program (SOCP) that Clarabel and SCS accept directly
(:data:`CONE_BACKENDS`, one small function each, settings through
``backend_options``).  In 2-D the cones are polyhedral and every subproblem
is a QP, which any QP method of :func:`qpcontact.solve` takes (``backend=
"osqp"``, ``"daqp"``, ...): the engine passes its solve in (``engine``), and
each QP answer is certified there as a QP before the friction measures judge
the iterate.  Units are the caller's: W in velocity per force, q in
velocity, r in force.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np
import scipy.sparse as sp

from ...core.errors import InvalidOptionError, NotConvexError
from ...core.options import Option

__all__ = ["CONE_BACKENDS", "Subproblem", "GlobalSubproblem", "CONE_OPTIONS"]


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
    usable = status in ("Solved", "AlmostSolved", "MaxIterations", "MaxTime",
                        "InsufficientProgress")
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
#: the options of every method that solves these subproblems (the fixed
#: points add theirs): read by qpcontact.core.options.read_options, handed to
#: Subproblem.  ``engine`` is passed in by :func:`qpcontact.solve`.
CONE_OPTIONS = (
    Option("backend", "clarabel", "any",
           doc="the subproblems' backend: clarabel, scs, or in 2-D a QP method"),
    Option("backend_options", {}, "mapping", none_ok=True, doc="the backend's own settings"),
    Option("inner_tol", 1e-10, "float", low=0.0, low_open=True,
           doc="the tolerance asked of each subproblem"),
    Option("engine", None, "any", doc="the engine running the method (set by qpcontact.solve)"),
)

#: each cone backend's own time-limit setting (seconds)
_TIME_SETTING = {"clarabel": "time_limit", "scs": "time_limit_secs"}


class Subproblem:
    """min ½ r'Wr + c'r over the cones of one method, solved by a named backend.

    In 2-D every cone is polyhedral — K = {|r_T| <= μ r_N}, Tresca's disc the
    interval |r_T| <= g — so the subproblem is a QP, and any QP method of
    :func:`qpcontact.solve` takes it (``backend="osqp"``, ``"proxqp"``,
    ``"daqp"``, ``"cvxpy:OSQP"``, ...), each answer certified there as a QP
    before the friction measures judge the iterate.  The engine that runs the
    method passes itself in ``options["engine"]`` (its ``solve`` and
    ``qp_method``): the friction methods never import the dispatcher.
    ``options`` are the method's, read against :data:`CONE_OPTIONS`."""

    def __init__(self, problem, options, qp_allowed: bool = True):
        self.problem = problem
        self._backend(options, qp_allowed)
        self.P = sp.csc_matrix(problem.W)
        self.P = 0.5 * (self.P + self.P.T)
        self.size = problem.W.shape[0]

    def _backend(self, options, qp_allowed: bool = True):
        self.engine = options["engine"]
        backend = options["backend"]
        self.qp = None
        if backend not in CONE_BACKENDS:
            if isinstance(backend, str) and self.engine is None:
                raise InvalidOptionError(
                    f"backend {backend!r} is not a cone backend ({', '.join(CONE_BACKENDS)}); QP "
                    "backends for the 2-D subproblems are reached through qpcontact.solve")
            self.qp = self.engine.qp_method(backend) if isinstance(backend, str) else None
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
        self.backend_options = dict(options["backend_options"] or {})
        self.inner_tol = options["inner_tol"]
        self.inner_iterations = 0

    def solve(self, c, tresca=None, time_left=None):
        """(r, status) of one subproblem; ``time_left`` (s) bounds the
        backend's own run (a 5000-contact SOCP takes 1.7 s, so a fixed point
        checking its limit between subproblems overran "auto"'s share 3x)."""
        p = self.problem
        if self.qp is not None:
            return self._solve_qp(c, tresca, time_left)
        A, b = _cone_rows(p.dim, p.mu, tresca)
        r, z, status, its = CONE_BACKENDS[self.backend](
            self.P, c, A, b, p.n_contacts, p.dim, self.inner_tol, self._timed(time_left))
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

    def _timed(self, time_left):
        """The backend's settings, with its own time limit where one is given."""
        options = dict(self.backend_options)
        if time_left is not None:
            options[_TIME_SETTING[self.backend]] = max(float(time_left), 0.01)
        return options

    def _solve_qp(self, c, tresca, time_left=None):
        """The 2-D subproblem as a qpsolvers.Problem: r_N >= 0 and either the
        cone's two rows ∓r_T − μ r_N <= 0 or Tresca's bounds |r_T| <= g."""
        import qpsolvers

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
            limit = {} if time_left is None else {"time_limit": max(float(time_left), 0.01)}
            sol = self.engine.solve(qpsolvers.Problem(self.P, c, G, h, lb=lb, ub=ub), self.qp,
                                    accuracy=self.inner_tol, **self.backend_options, **limit)
        except NotConvexError:
            raise NotConvexError(
                f"W is not positive semidefinite, so the subproblems are nonconvex QPs, which "
                f"{self.backend!r} is not given (a file storing a singular W rounded to a few "
                "digits is indefinite at that level); use a cone backend (clarabel, scs), "
                "'nsgs' or 'lemke'") from None
        self.inner_iterations += sol.iterations or 0
        return (sol.x if sol.status != "unbounded" else None), sol.status


class GlobalSubproblem(Subproblem):
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

    def solve(self, shift, tresca=None, time_left=None):
        p, g = self.problem, self.problem.global_data
        b = self.D * (g["w"] + shift)
        v, z, status, its = CONE_BACKENDS[self.backend](
            self.P, -g["f"], self.A, b, p.n_contacts, p.dim, self.inner_tol,
            self._timed(time_left), nonneg=0)
        self.inner_iterations += its
        if status == "unbounded":
            self.ray = v
        if v is None or z is None:
            return None, status
        return np.concatenate([self.D * z, v]), status
