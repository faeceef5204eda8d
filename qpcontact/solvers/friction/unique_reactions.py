r"""One set of reactions where a frictional contact problem has many.

Mechanics.  A rigid body on more contacts than its statics determines — a
table on four legs, a box on three points, a pile whose grains touch in
closed loops — has a singular Delassus operator W = Hᵀ M⁻¹ H (H: the
contacts' directions, n dofs x m = dim·n_c local unknowns, m > rank H).  The
velocities u* = W r* + q of a solution are then shared by a whole set of
reactions (N, or impulses N·s per step):

    S(u*) = { r :  W (r − r*) = 0,
              r_i = 0                          where contact i opens  (u*_N > δ),
              r_i = s_i (1, −μ_i t̂_i), s_i >= 0  where it slides (‖u*_T‖ > δ, t̂ = u*_T/‖u*_T‖),
              r_i ∈ K_i = {‖r_T‖ <= μ_i r_N}   where it sticks (u*_i ≈ 0) }.

Every r in S(u*) solves the problem: W r + q = u*, so De Saxcé's modified
velocity û_i = u*_i + μ_i ‖u*_T,i‖ e_N is the same, and r_i ⟂ û_i with
r_i ∈ K_i holds in each case (open: û_i is inside K*_i, r_i = 0; sliding:
û_i = (μ‖u_T‖, u_T) and r_i on the ray opposite u_T, where r_i · û_i =
s_i (μ‖u_T‖ − μ ‖u_T‖) = 0; sticking: û_i = 0).  S(u*) is convex (an affine
space cut by cones and rays), and the answer a method returns is one point
of it — often a vertex, where a contact the body rests on carries nothing.
No error bound can say which contact carries what: the certificate's
forward error is infinite there (the natural map's Jacobian is singular).

A unique representative is the minimiser of a strictly convex function on
S(u*):

    r̂ = argmin_{r ∈ S(u*)}  Σ_i c_i ‖r_i‖²

with c_i = 1 the minimum-norm reactions, and with c_i the contacts'
compliances (m/N: the support's deflection per unit force) the least
complementary energy ½ Σ c_i ‖r_i‖², which by Menabrea's theorem is the
split elastic supports of those compliances give a rigid body (its
stationarity, C r ∈ range Hᵀ plus the cones' multipliers, is the
compatibility of the supports' deflections with a rigid motion) — exact
where no contact is at its friction limit in between (a sliding contact's
elastic slip would follow Coulomb's non-associated law, not the cone's
normal).  The minimisation runs in the null space of W (r = r* + N z, N an
orthonormal basis of null W, or of null H when the global data are kept:
W's null space is H's and H is better conditioned), as a second-order cone
programme through cvxpy, and the result is certified from the data like
any other answer.

δ: a contact's velocity counts as zero below ten times the answer's own
error (at most a tenth of its tolerance) times the problem's velocity scale
(max |q|, |u*|); a touching contact inside that band keeps its cone.
"""

from __future__ import annotations

import time

import numpy as np

import scipy.sparse as sp

from ...core.errors import InvalidOptionError, InvalidProblemError
from ...core.friction_problem import FrictionProblem
from ...core.results import FrictionSolution
from ...judge.friction_certificate import certify_friction

__all__ = ["unique_reactions", "UNIQUE_MAX_UNKNOWNS"]

#: the largest problem (local unknowns m = dim · contacts) whose null space
#: is computed densely (one SVD of H or eigendecomposition of W: O(m³), about
#: 10 s at m = 3 000)
UNIQUE_MAX_UNKNOWNS = 3000


def _null_basis(problem: FrictionProblem, m: int) -> np.ndarray:
    """An orthonormal basis of W's null space (H's, where H is kept)."""
    g = problem.global_data
    if g is not None and g.get("H") is not None:
        H = g["H"]
        A = H.toarray() if hasattr(H, "toarray") else np.asarray(H, float)
        _, s, Vt = np.linalg.svd(A, full_matrices=True)
        top = s.max(initial=0.0)
        rank = int(np.sum(s > max(A.shape) * np.finfo(float).eps * top)) if top > 0 else 0
        return Vt[rank:].T
    W = problem.W.toarray() if hasattr(problem.W, "toarray") else np.asarray(problem.W, float)
    lam, V = np.linalg.eigh(0.5 * (W + W.T))
    top = np.abs(lam).max(initial=0.0)
    return V[:, lam <= m * np.finfo(float).eps * top] if top > 0 else np.eye(m)


def _classes(problem: FrictionProblem, u: np.ndarray, error: float, tol: float):
    """(open, sliding, slip direction t̂ per contact) from the velocities u*.
    A velocity counts as zero below δ = min(10 error, tol/10) of the
    problem's velocity scale: above the answer's own noise (an NSGS answer
    certified to 2e-10 has slips of 5e-10 where Newton's has 1e-22 — read
    as slips they pinned 16 contacts on their rays and moved the
    representative by 1 %), and low enough that a touching contact given a
    force keeps its residual ten times inside the tolerance."""
    d = problem.dim
    U = u.reshape(-1, d)
    q = problem.q if problem.is_reduced else problem.global_data["w"]
    scale = max(float(np.abs(q).max(initial=0.0)), float(np.abs(u).max(initial=0.0)), 1e-300)
    delta = min(10.0 * max(error, 1e-15), 0.1 * tol) * scale
    slip = np.linalg.norm(U[:, 1:], axis=1)
    opened = U[:, 0] > delta
    sliding = ~opened & (slip > delta) & (problem.mu > 0)
    t_hat = np.zeros_like(U[:, 1:])
    t_hat[sliding] = U[sliding, 1:] / slip[sliding, None]
    return opened, sliding, t_hat


def unique_reactions(problem: FrictionProblem, solution: FrictionSolution,
                     compliance=None) -> FrictionSolution:
    """The unique representative of the reactions sharing ``solution``'s
    velocities (module docstring): the minimum-norm ones, or — given the
    contacts' ``compliance`` (one value per contact, m/N, or one for all) —
    the least complementary energy, the split elastic supports of those
    compliances give where no contact is at its friction limit.

    ``solution`` must be an ok answer of ``problem`` (``qpcontact.solve``'s).
    Returns a new :class:`FrictionSolution`, certified from the data; its
    ``stats["null_dimension"]`` is how many independent directions the
    reactions could move along (0: they were unique already, and the
    answer is ``solution``'s own).  Dense: at most UNIQUE_MAX_UNKNOWNS local
    unknowns."""
    if not isinstance(problem, FrictionProblem):
        raise InvalidProblemError(f"unique_reactions takes a FrictionProblem; got "
                                  f"{type(problem).__name__}")
    if not isinstance(solution, FrictionSolution) or solution.r is None or not solution.ok:
        raise InvalidOptionError("unique_reactions needs an ok FrictionSolution of this problem "
                                 "(qpcontact.solve(problem) with sol.ok); got "
                                 f"{getattr(solution, 'status', type(solution).__name__)!r}")
    d, nc = problem.dim, problem.n_contacts
    m = d * nc
    r0 = np.asarray(solution.r, float).ravel()
    if r0.shape != (m,):
        raise InvalidOptionError(f"the solution has {r0.size} reactions; the problem has {m} "
                                 f"({nc} contacts in dimension {d}): it is another problem's")
    if m > UNIQUE_MAX_UNKNOWNS:
        raise InvalidOptionError(f"unique_reactions is dense: {m} local unknowns, above "
                                 f"UNIQUE_MAX_UNKNOWNS = {UNIQUE_MAX_UNKNOWNS}")
    c = _compliance(compliance, nc)
    start = time.perf_counter()
    u0 = (np.asarray(solution.u, float).ravel() if solution.u is not None
          else problem.velocities(r0))
    N = _null_basis(problem, m)
    common = dict(method=f"{solution.method} + unique_reactions", accuracy=solution.accuracy,
                  tol=solution.tol)
    what = "minimum-norm" if compliance is None else "least complementary energy"
    if N.shape[1] == 0:
        return FrictionSolution(status=solution.status, ok=solution.ok,
                                message="the reactions are unique (W is regular): "
                                        + solution.message,
                                certificate=solution.certificate, r=r0, u=solution.u,
                                v=solution.v, wall_time=time.perf_counter() - start,
                                stats={"null_dimension": 0, "representative": what}, **common)
    opened, sliding, t_hat = _classes(problem, u0, solution.error, solution.tol)
    r, status = _minimise(problem, r0, N, c, opened, sliding, t_hat)
    k = N.shape[1]
    if r is None:
        return FrictionSolution(status="failed", ok=False,
                                message=f"the {what} reactions were not found (the cone programme "
                                        f"ended {status!r}); keep {solution.method}'s own answer",
                                certificate=None, r=None, u=None,
                                wall_time=time.perf_counter() - start,
                                stats={"null_dimension": k, "representative": what}, **common)
    # u = W r + q once, for the certificate and the answer (run_friction's way)
    v, u = (None, problem.velocities(r)) if problem.is_reduced else (solution.v, solution.u)
    cert = certify_friction(problem, r, v, u=u if problem.is_reduced else None)
    ok = cert.ok(solution.tol)
    words = (f"the {what} reactions among those sharing {solution.method}'s velocities "
             f"({k} independent direction{'s' if k > 1 else ''} the reactions could move along): "
             f"natural-map error {cert.natural_map_error:.1e}, componentwise "
             f"{cert.componentwise_error:.1e} {'<=' if ok else '>'} {solution.tol:.0e}")
    return FrictionSolution(status="solved" if ok else "inaccurate", ok=ok,
                            message=words if ok else words + ": not certified, keep the method's "
                            "own answer",
                            certificate=cert, r=r, u=u, v=v,
                            wall_time=time.perf_counter() - start,
                            stats={"null_dimension": k, "representative": what,
                                   "open": np.flatnonzero(opened),
                                   "sliding": np.flatnonzero(sliding)},
                            **common)


def _compliance(compliance, nc: int) -> np.ndarray:
    if compliance is None:
        return np.ones(nc)
    try:
        c = np.broadcast_to(np.asarray(compliance, dtype=float), (nc,)).copy()
    except (TypeError, ValueError):
        raise InvalidOptionError(f"compliance must be one number per contact ({nc}) or one for "
                                 f"all, in m/N; got {compliance!r}") from None
    if not np.all(np.isfinite(c) & (c > 0)):
        bad = int(np.flatnonzero(~(np.isfinite(c) & (c > 0)))[0])
        raise InvalidOptionError(f"compliance[{bad}] = {c[bad]}: each contact's compliance must "
                                 "be finite and > 0 (a rigid contact has none to split by: leave "
                                 "compliance=None for the minimum-norm reactions)")
    return c


def _minimise(problem, r0, N, c, opened, sliding, t_hat) -> tuple[np.ndarray | None, str]:
    """argmin Σ c_i ‖r_i‖² over r = r0 + N z, as an SOCP (Clarabel: min
    ½ y'Py + p'y, A y + s = b, s in the cones), in units of max |r0|.
    The method's answer is on the contacts' sets only to its tolerance, so
    each set is taken around it: an open contact keeps its reaction
    (N_i z = 0), a sliding one its offset from the ray (the ray's equations
    on N z) — both by z = Z y, Z an orthonormal basis of those equations'
    null space, so that they hold to rounding, not to the programme's
    tolerance (which an open contact's own scale, its reaction 0, reads as
    an error of 1e-8) — and a cone or a sign the answer misses by a rounding
    is widened by that much: y = 0 is feasible, and no leftover 1e-12 makes
    the programme infeasible.  Then polished where no cone bounds the
    minimiser."""
    import clarabel

    d, mu = problem.dim, problem.mu
    s = float(np.abs(r0).max(initial=0.0)) or 1.0
    x0 = r0 / s
    E = _equations(N, opened, sliding, t_hat, mu, d)
    if E.shape[0]:
        _, sv, Vt = np.linalg.svd(E, full_matrices=True)
        rank = int(np.sum(sv > 1e-9 * max(sv.max(initial=0.0), 1.0)))
        N = N @ Vt[rank:].T
    if N.shape[1] == 0:
        return r0.copy(), "fixed"
    D2 = np.repeat(c / c.max(), d)
    P = 2.0 * N.T @ (D2[:, None] * N)
    p = 2.0 * N.T @ (D2 * x0)
    rows, b = [], []
    for i in np.flatnonzero(sliding):           # r_N = x_N + N_N y >= min(x_N, 0)
        rows.append(-N[d * i: d * i + 1]), b.append([max(x0[d * i], 0.0)])
    n_pos = len(rows)
    stick = np.flatnonzero(~opened & ~sliding)
    for i in stick:                              # (μ r_N + widening, r_T) in the cone
        Ni, xi = N[d * i: d * i + d], x0[d * i: d * i + d]
        widen = max(np.linalg.norm(xi[1:]) - mu[i] * xi[0], 0.0)
        rows.append(-np.vstack([mu[i] * Ni[:1], Ni[1:]]))
        b.append(np.concatenate([[mu[i] * xi[0] + widen], xi[1:]]))
    A = np.vstack(rows) if rows else np.zeros((0, N.shape[1]))
    b = np.concatenate([np.asarray(x, float) for x in b]) if b else np.zeros(0)
    cones = ([clarabel.NonnegativeConeT(n_pos)] if n_pos else []) + \
        [clarabel.SecondOrderConeT(d)] * stick.size
    for tol in (1e-12, 1e-9):      # tight first; Clarabel stalls on some piles there
        settings = clarabel.DefaultSettings()
        settings.verbose = False
        settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = tol
        result = clarabel.DefaultSolver(sp.triu(sp.csc_matrix(P), format="csc"), p,
                                        sp.csc_matrix(A), b, cones, settings).solve()
        status = str(result.status)
        if status in ("Solved", "AlmostSolved"):
            break
    else:
        return None, status
    y = _polished(x0, N, D2, np.asarray(result.x), opened, sliding, mu, d)
    return (x0 + N @ y) * s, status


def _equations(N, opened, sliding, t_hat, mu, d) -> np.ndarray:
    """The rows E with E z = 0: an open contact's N_i z = 0, a sliding one's
    (N_T + μ t̂ N_N) z = 0."""
    rows = [N[d * i: d * i + d] for i in np.flatnonzero(opened)]
    rows += [N[d * i + 1: d * i + d] + mu[i] * np.outer(t_hat[i], N[d * i])
             for i in np.flatnonzero(sliding)]
    return np.vstack(rows) if rows else np.zeros((0, N.shape[1]))


def _polished(x0, N, D2, y, opened, sliding, mu, d) -> np.ndarray:
    """The SOCP's minimiser to working precision where no cone or sign bounds
    it (every sticking contact strictly inside its cone, every sliding one
    pressing, at 1e-6 of the reactions' size): then it is the weighted least
    squares' minimiser over y, kept where it stays inside the same sets.
    Else the SOCP's (to its tolerance)."""
    R = (x0 + N @ y).reshape(-1, d)
    stick = ~opened & ~sliding
    slack = mu[stick] * R[stick, 0] - np.linalg.norm(R[stick, 1:], axis=1)
    if np.any(slack <= 1e-6) or np.any(R[sliding, 0] <= 1e-6):
        return y
    w = np.sqrt(D2)
    polished = np.linalg.lstsq(w[:, None] * N, -w * x0, rcond=None)[0]
    P = (x0 + N @ polished).reshape(-1, d)
    inside = (np.all(mu[stick] * P[stick, 0] >= np.linalg.norm(P[stick, 1:], axis=1))
              and np.all(P[sliding, 0] >= 0))
    return polished if inside else y
