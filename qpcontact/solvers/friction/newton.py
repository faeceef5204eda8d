"""Semismooth Newton on the natural map (Siconos's NSN family)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ...core.deadline import Deadline, Pace
from ...core.options import PROGRESS, TIME_LIMIT, Option, read_options
from .fixed_points import solve_anitescu
from .nsgs import starting_point
from ...judge.friction_certificate import (certified_error, contact_scales, contact_sizes,
                                           projection_jacobian)
from ...core.friction_problem import modified_velocity, project_cone

__all__ = ["solve_natural_newton", "SPARSE_NEWTON_MIN", "LM_BELOW", "NEWTON_OPTIONS"]


#: above this many local unknowns (and W sparse) Newton's linear algebra is sparse
SPARSE_NEWTON_MIN = 1000


#: a Newton step shorter than this also tries Levenberg–Marquardt's
LM_BELOW = 1e-3


NEWTON_OPTIONS = (
    Option("r0", None, "vector", doc="starting reactions (default: Anitescu's relaxation)"),
    Option("max_iter", 100, "int", low=0, doc="Newton iterations at most"),
    PROGRESS, TIME_LIMIT,
)


def solve_natural_newton(problem, tol, options):
    """Semismooth Newton on the natural map F(r) = r − proj_K(r − ρ û(r))
    (Siconos's NSN family), globalized by an Armijo line search on ½‖F‖²;
    ρ_i = 1 / (W_i's normal diagonal entry) per contact
    (:func:`~qpcontact.judge.friction_certificate.contact_scales`), so that F is a force, and
    the merit ½‖DF‖² weighs each contact by 1 / its size (D from
    :func:`~qpcontact.judge.friction_certificate.contact_sizes`, frozen per iteration).  Starts from
    ``r0`` (default: Anitescu's relaxation by Clarabel).  Local quadratic convergence near a
    nondegenerate solution; no global guarantee — it stops and says so when
    the line search fails.  Options (:data:`NEWTON_OPTIONS`): ``r0``,
    ``max_iter`` (100), ``progress``, ``time_limit`` (s)."""
    import scipy.sparse.linalg as spla   # here, not at the top: `import qpcontact` stays cheap

    opts = read_options("newton", options, NEWTON_OPTIONS)
    r0 = starting_point("newton", problem, opts["r0"])
    max_iter, progress, time_limit = opts["max_iter"], opts["progress"], opts["time_limit"]
    deadline = Deadline(time_limit)
    p, d = problem, problem.dim
    nc, mu = p.n_contacts, p.mu
    stats = {"inner_iterations": 0, "timed_out": False}
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
    pace = Pace(deadline.left())
    for k in range(1, max_iter + 1):
        if k > 1:
            pace.step_done()
        if best_err <= tol:
            why = "reached the tolerance"
            break
        if not pace.fits():
            why = (f"stopped at its time limit of {time_limit:.3g} s (another iteration, "
                   f"{pace.longest:.2g} s the longest so far, would not fit)")
            stats["timed_out"] = True
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
        JP = sp.bsr_matrix((projection_jacobian(x, mu, d), np.arange(nc), np.arange(nc + 1)),
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
