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

Each subproblem goes to a backend by name (:mod:`qpcontact.solvers.friction.cones`).
Nothing a backend reports is believed: the engine certifies r by the error
measures of :mod:`qpcontact.judge.friction_certificate`.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ...core.deadline import Pace
from ...core.options import PROGRESS, TIME_LIMIT, Option, read_options
from ...proofs.friction_motion import no_equilibrium
from .cones import CONE_OPTIONS, GlobalSubproblem, Subproblem
from ...judge.friction_certificate import componentwise_error, global_errors, natural_map_error

__all__ = ["solve_anitescu", "solve_desaxce_fp", "solve_tresca_fp", "solve_desaxce_global",
           "ANITESCU_OPTIONS", "FIXED_POINT_OPTIONS"]

#: "anitescu" solves one SOCP: the subproblems' options only
ANITESCU_OPTIONS = CONE_OPTIONS

#: "desaxce-fp", "tresca-fp", "desaxce-global"
FIXED_POINT_OPTIONS = CONE_OPTIONS + (
    Option("max_outer", 100, "int", low=1, doc="subproblems (outer iterations) at most"),
    PROGRESS, TIME_LIMIT,
)


def solve_anitescu(problem, tol, options):
    """Anitescu's convex relaxation: one SOCP (module docstring).  Options
    (:data:`ANITESCU_OPTIONS`): ``backend`` (clarabel; scs; in 2-D a QP
    method), ``backend_options``, ``inner_tol`` (1e-10)."""
    sub = Subproblem(problem, read_options("anitescu", options, ANITESCU_OPTIONS))
    r, status = sub.solve(problem.q.copy())
    return r, status, f"one SOCP by {sub.backend} ({status})", {
        "inner_iterations": sub.inner_iterations, "backend": sub.backend}


def _fixed_point(method, problem, tol, options, update, subproblem=None, measure=None):
    """Iterate r ← SOCP(update(r)) until both error measures are <= tol, or
    neither has improved for 5 iterations, or ``max_outer`` (default 100)
    iterations.  Returns the iterate with the smallest certified error (the
    larger of the two), ties going to the smaller natural-map error: where a
    few contacts carrying ~1e-22 forces hold the componentwise error at 0.5
    the iteration still improves the rest, and is kept going for it.
    Options (:data:`FIXED_POINT_OPTIONS`): ``backend`` (clarabel; scs; in
    2-D a QP method), ``backend_options``, ``inner_tol`` (1e-10),
    ``max_outer`` (100), ``progress``, ``time_limit`` (s)."""
    options = read_options(method, options, FIXED_POINT_OPTIONS)
    sub = (subproblem or Subproblem)(problem, options)
    measure = measure or (lambda r: (natural_map_error(problem, r),
                                     componentwise_error(problem, r)))
    max_outer, progress, time_limit = options["max_outer"], options["progress"], \
        options["time_limit"]
    timed_out = False
    pace = Pace(time_limit)
    r = np.zeros(sub.size)
    best_key, best_r, lowest, since, errors = (np.inf, np.inf), None, [np.inf, np.inf], 0, []
    status = "not started"
    for k in range(1, max_outer + 1):
        c, tresca = update(r)
        r_new, status = sub.solve(c, tresca, pace.deadline.left())
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
        pace.step_done()
        if not pace.fits():      # another SOCP like the longest so far would not fit
            timed_out = True
            break
    stats = {"iterations": len(errors), "inner_iterations": sub.inner_iterations,
             "backend": sub.backend, "errors": errors}
    if best_r is None:
        return None, status, f"{sub.backend} returned no point ({status})", stats
    why = ("reached the tolerance" if best_key[0] <= tol else
           "stalled (neither error improved in 5 iterations)" if since >= 5 else
           f"stopped at {max_outer} iterations" if len(errors) >= max_outer else
           f"stopped at its time limit of {time_limit:.3g} s" if timed_out else
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
    """De Saxcé's fixed point of SOCPs (module docstring).  Options
    (:data:`FIXED_POINT_OPTIONS`): ``backend`` (clarabel; scs; in 2-D a QP
    method), ``backend_options``, ``inner_tol`` (1e-10), ``max_outer``
    (100), ``progress``, ``time_limit`` (s)."""
    def update(r):
        return problem.q + _desaxce_shift(problem.velocities(r), problem.mu, problem.dim), None
    return _fixed_point("desaxce-fp", problem, tol, options, update)


def solve_tresca_fp(problem, tol, options):
    """Tresca's fixed point of SOCPs (module docstring).  Options
    (:data:`FIXED_POINT_OPTIONS`): ``backend`` (clarabel; scs; in 2-D a QP
    method), ``backend_options``, ``inner_tol`` (1e-10), ``max_outer``
    (100), ``progress``, ``time_limit`` (s)."""
    d = problem.dim
    first = [True]

    def update(r):
        if first[0]:   # no reaction yet: the first thresholds come from Anitescu's relaxation
            first[0] = False
            return problem.q.copy(), None
        return problem.q.copy(), problem.mu * np.maximum(r[0::d], 0.0)
    return _fixed_point("tresca-fp", problem, tol, options, update)


def solve_desaxce_global(problem, tol, options):
    """De Saxcé's fixed point on a global problem kept without W: each
    iterate one SOCP in v (:class:`GlobalSubproblem`), s = μ‖u_T‖ from the
    last u = H'v + w.  Returns x = (r, v).  Options
    (:data:`FIXED_POINT_OPTIONS`): ``backend`` (clarabel, scs),
    ``backend_options``, ``inner_tol`` (1e-10), ``max_outer`` (100),
    ``progress``, ``time_limit`` (s)."""
    g, d = problem.global_data, problem.dim
    m = d * problem.n_contacts

    def update(x):
        return _desaxce_shift(np.asarray(g["H"].T @ x[m:]).ravel() + g["w"], problem.mu, d), None

    def measure(x):
        nat, cw, eq = global_errors(problem, x[:m], x[m:])
        return nat, max(cw, eq)

    made = []

    def subproblem(problem, options):
        made.append(GlobalSubproblem(problem, options))
        return made[-1]
    x, status, message, stats = _fixed_point("desaxce-global", problem, tol, options, update,
                                             subproblem, measure)
    if x is not None and max(measure(x)) > tol:
        polished = _polish_global(problem, x)
        if polished is not None and max(measure(polished)) < max(measure(x)):
            x = polished
            message += "; polished by Newton on its contact states"
    ray = getattr(made[0], "ray", None) if made else None
    if x is None and ray is not None:
        proof = no_equilibrium(problem, ray)
        if proof is not None:
            message, stats["ray"] = proof
    return x, status, message, stats


def _polish_global(problem, x, max_iter: int = 20):
    """An interior-point answer is accurate to the backend's tolerance (5e-7
    in the equilibrium of a frame whose K spans 1e6…1e8); its contact states
    are usually right.  Fix them and solve, by Newton's method, the smooth
    system they leave: Mv − Hr = f; an open contact r_i = 0; a sticking one
    H_iᵀv + w_i = 0; a sliding one (or a closed frictionless one, μ = 0)
    H_Nᵀv + w_N = 0 and r_T + μ r_N g = 0, g =
    u_T/‖u_T‖ its slip direction (in 2-D ±1, so one linear solve; in 3-D the
    direction moves with v: a table's pad sliding at an angle stalled at
    1.3e-6 with g frozen at the iterate's, where Newton on it reaches
    rounding in a few steps).  A sliding contact without a slip to take the
    direction from keeps its friction's, r_T = μ r_N t̂.  Stops when the
    residual (each row on its own scale) stops falling, returning the point
    where it was smallest; the caller keeps whichever point has the smaller
    error."""
    import scipy.sparse.linalg as spla   # here, not at the top: `import qpcontact` stays cheap

    g, d = problem.global_data, problem.dim
    M, H, f, w, mu = sp.csr_matrix(g["M"]), sp.csr_matrix(g["H"]), g["f"], g["w"], problem.mu
    n, m = M.shape[0], d * problem.n_contacts
    r, v = x[:m].reshape(-1, d), x[m:]
    U = (np.asarray(H.T @ v).ravel() + w).reshape(-1, d)
    size = np.linalg.norm(r, axis=1)
    big = size.max(initial=0.0)
    t = np.linalg.norm(r[:, 1:], axis=1)
    tn = np.linalg.norm(U[:, 1:], axis=1)
    open_ = (size <= 1e-9 * big) & (U[:, 0] >= 0)
    # a closed frictionless contact slides freely: u_N = 0, r_T = 0
    sliding = ~open_ & ((mu == 0) | ((t >= (1 - 1e-6) * mu * r[:, 0]) & (t > 0)))
    follows = sliding & (tn > 0)                  # direction from the slip, else frozen
    that = r[:, 1:] / np.where(t > 0, t, 1.0)[:, None]
    Ht = sp.csr_matrix(H.T)
    stuck = np.flatnonzero(~open_ & ~sliding)

    def system(y):
        """(G, J) at y = (v, r)."""
        v, r = y[:n], y[n:]
        R = r.reshape(-1, d)
        U = (Ht @ v + w).reshape(-1, d)
        rows, res = [sp.hstack([M, -H])], [M @ v - H @ r - f]
        idx = np.flatnonzero(open_)
        sel = (d * idx[:, None] + np.arange(d)).ravel()
        rows.append(sp.hstack([sp.csr_matrix((sel.size, n)), sp.eye(m, format="csr")[sel]]))
        res.append(r[sel])
        sel = (d * stuck[:, None] + np.arange(d)).ravel()
        rows.append(sp.hstack([Ht[sel], sp.csr_matrix((sel.size, m))]))
        res.append(U[stuck].ravel())
        for i in np.flatnonzero(sliding):
            rows.append(sp.hstack([Ht[d * i:d * i + 1], sp.csr_matrix((1, m))]))
            res.append(U[i, :1])
            ut = U[i, 1:]
            norm = np.linalg.norm(ut)
            free = follows[i] and norm > 0
            gi = ut / norm if free else -that[i]
            jr = sp.lil_matrix((d - 1, m))
            jr[:, d * i + 1:d * i + d] = np.eye(d - 1)
            jr[:, d * i] = (mu[i] * gi)[:, None]
            jv = sp.csr_matrix((d - 1, n))
            if free:   # d(u_T/‖u_T‖) = (I − g gᵀ)/‖u_T‖ du_T
                jv = sp.csr_matrix(mu[i] * R[i, 0] / norm
                                   * (np.eye(d - 1) - np.outer(gi, gi))) @ Ht[d * i + 1:d * i + d]
            rows.append(sp.hstack([jv, jr]))
            res.append(R[i, 1:] + mu[i] * R[i, 0] * gi)
        return np.concatenate(res), sp.vstack(rows).tocsc()

    def scaled(y, G):
        """|G| on each row's own scale (the equations' terms)."""
        v, r = y[:n], y[n:]
        s = np.r_[abs(M) @ np.abs(v) + abs(H) @ np.abs(r) + np.abs(f),
                  np.full(G.size - n, np.abs(r).max(initial=0.0) + np.abs(v).max(initial=0.0))]
        s = np.maximum(s, np.finfo(float).eps * s.max(initial=0.0))
        return float(np.max(np.abs(G) / np.where(s > 0, s, 1.0), initial=0.0))

    y = np.concatenate([v, r.ravel()])
    best, best_y = np.inf, None
    for _ in range(max_iter):
        G, J = system(y)
        level = scaled(y, G)
        if not level < best:
            break
        best, best_y = level, y
        try:
            step = spla.splu(J).solve(-G)
        except RuntimeError:
            break
        if not np.all(np.isfinite(step)):
            break
        y = y + step
    if best_y is None:
        return None
    return np.concatenate([best_y[n:], best_y[:n]])
