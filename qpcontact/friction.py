r"""Frictional contact problems (Coulomb), local and global, in 2-D and 3-D.

Mechanics.  At contact i the local frame has the normal first, then one (2-D)
or two (3-D) tangents.  The local velocities u (m/s, or displacements per
step) are affine in the reactions r (N, or impulses N·s):

    u = W r + q,       W = Hᵀ M⁻¹ H (Delassus operator), q = Hᵀ M⁻¹ f + w,

from the global problem M v = H r + f, u = Hᵀ v + w of a discretised
mechanical system (M its mass/iteration matrix, H the contact Jacobian
transposed).  Coulomb's law with Signorini's condition, in De Saxcé's form:

    r_i ∈ K_i = {‖r_T‖ <= μ_i r_N},   û_i = u_i + μ_i ‖u_T,i‖ e_N ∈ K_i*,   r_i ⟂ û_i

(contact open: r = 0; sticking: u = 0; sliding: u_N = 0 and r_T = -μ r_N
u_T/‖u_T‖).  The error of a candidate is Siconos's natural-map residual
‖r − proj_K(r − û)‖ / (1 + ‖q‖) (:func:`natural_map_error`), computed from the
data for every answer, whatever a method reports.

In 2-D the cone is polyhedral and the problem *is* an LCP (:func:`fc2d_lcp`):
per contact z = (r_N, β⁺, β⁻, λ) with r_T = β⁺ − β⁻ and

    w = (u_N,  λ + u_T,  λ − u_T,  μ r_N − β⁺ − β⁻) >= 0,  z >= 0,  z'w = 0:

λ is the slip speed, β± the friction parts; sliding with u_T < 0 forces
λ = −u_T, β⁻ = 0 and β⁺ = μ r_N (friction opposes the slip).  Lemke solves it
exactly; it is the oracle for every other 2-D method.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .errors import InvalidOptionError, InvalidProblemError
from .problems import LCP, as_matrix, as_vector

__all__ = ["FrictionProblem", "FrictionSolution", "natural_map_error", "project_cone",
           "fc2d_lcp", "solve_friction", "FRICTION_METHODS"]

#: the largest local problem whose W = Hᵀ M⁻¹ H is formed densely from a global one
DENSE_W_LIMIT = 6000


class FrictionProblem:
    """A frictional contact problem (module docstring), validated like LCP.

    ``W`` (m x m, m = dim · n_contacts), ``q`` (m,), ``mu`` (n_contacts,),
    ``dim`` 2 or 3.  Global problems (:meth:`global_problem`) keep M, H, f, w
    in ``global_data`` and are reduced to local form.  ``solution`` and
    ``guesses`` hold what an FCLIB file stores (dicts of r, u, v)."""

    def __init__(self, W, q, mu, dim, *, name: str = ""):
        if dim not in (2, 3):
            raise InvalidProblemError(f"dim must be 2 or 3 (the contact space); got {dim!r}")
        self.dim = int(dim)
        mu = np.atleast_1d(np.asarray(mu, dtype=float))
        nc = mu.size
        m = self.dim * nc
        self.W = as_matrix(W, "W") if m else np.zeros((0, 0))
        if self.W.shape != (m, m):
            raise InvalidProblemError(
                f"W must be {m} x {m} ({nc} contacts in dimension {dim}); got {self.W.shape}")
        self.q = as_vector(q, m, "q") if m else np.zeros(0)
        if not np.all(np.isfinite(mu)) or np.any(mu < 0):
            bad = int(np.flatnonzero(~(np.isfinite(mu) & (mu >= 0)))[0])
            raise InvalidProblemError(
                f"friction coefficients must be finite and >= 0; mu[{bad}] = {mu[bad]}")
        self.mu = mu
        self.name = name
        self.global_data = None
        self.solution = None
        self.guesses: list = []
        diag = np.asarray(self.W.diagonal()) if m else np.zeros(0)
        if np.any(diag[0::self.dim] < 0):
            i = int(np.flatnonzero(diag[0::self.dim] < 0)[0])
            raise InvalidProblemError(
                f"W's normal diagonal entry of contact {i} is {diag[self.dim * i]:.3g} < 0: W is "
                "a Delassus operator Hᵀ M⁻¹ H, whose diagonal blocks are positive semidefinite")

    @classmethod
    def global_problem(cls, M, H, f, w, mu, dim, *, name: str = ""):
        """M v = H r + f, u = Hᵀ v + w, reduced to local (W = Hᵀ M⁻¹ H,
        q = Hᵀ M⁻¹ f + w) by one sparse factorization of M."""
        import scipy.sparse.linalg as spla

        M = as_matrix(M, "M")
        n = M.shape[0]
        mu = np.atleast_1d(np.asarray(mu, dtype=float))
        m = int(dim) * mu.size
        H = as_matrix(H, "H") if H.shape[1] else sp.csc_matrix((n, 0))
        if M.shape != (n, n) or H.shape != (n, m):
            raise InvalidProblemError(f"global problem: M must be square and H {n} x {m}; got "
                                      f"{M.shape} and {H.shape}")
        f = as_vector(f, n, "f")
        w = as_vector(w, m, "w") if m else np.zeros(0)
        if m > DENSE_W_LIMIT:
            raise InvalidProblemError(
                f"global problem with {m} local unknowns: W = Hᵀ M⁻¹ H would be dense "
                f"{m} x {m}; the reduction stops at {DENSE_W_LIMIT}")
        lu = spla.splu(sp.csc_matrix(M))
        Minv_H = lu.solve(np.asarray(sp.csc_matrix(H).toarray())) if m else np.zeros((n, 0))
        W = np.asarray(H.T @ Minv_H) if m else np.zeros((0, 0))
        W = 0.5 * (W + W.T)
        q = np.asarray(H.T @ lu.solve(f)).ravel() + w if m else np.zeros(0)
        prob = cls(W, q, mu, dim, name=name)
        prob.global_data = {"M": M, "H": H, "f": f, "w": w, "lu": lu}
        return prob

    @property
    def n_contacts(self) -> int:
        return self.mu.size

    def velocities(self, r) -> np.ndarray:
        return np.asarray(self.W @ r).ravel() + self.q

    def global_velocity(self, r) -> np.ndarray | None:
        """v = M⁻¹ (H r + f) of a global problem."""
        g = self.global_data
        if g is None:
            return None
        return g["lu"].solve(np.asarray(g["H"] @ r).ravel() + g["f"])

    def __repr__(self) -> str:
        kind = "global" if self.global_data is not None else "local"
        return (f"FrictionProblem({self.name or 'unnamed'}: {kind}, dim {self.dim}, "
                f"{self.n_contacts} contacts)")


def project_cone(r: np.ndarray, mu: np.ndarray, dim: int) -> np.ndarray:
    """Projection of each contact's r onto K_i = {‖r_T‖ <= μ_i r_N}."""
    R = np.asarray(r, float).reshape(-1, dim)
    rn, rt = R[:, 0], R[:, 1:]
    t = np.linalg.norm(rt, axis=1)
    out = R.copy()
    inside = t <= mu * rn
    polar = mu * t <= -rn
    mid = ~(inside | polar)
    alpha = (mu[mid] * t[mid] + rn[mid]) / (1.0 + mu[mid] ** 2)
    out[polar] = 0.0
    out[mid, 0] = alpha
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(t[mid] > 0, mu[mid] * alpha / np.where(t[mid] > 0, t[mid], 1.0), 0.0)
    out[mid, 1:] = rt[mid] * scale[:, None]
    return out.ravel()


def natural_map_error(problem: FrictionProblem, r, u=None) -> float:
    """Siconos's error measure: ‖r − proj_K(r − û)‖ / (1 + ‖q‖), û the
    modified velocity of u = W r + q (recomputed from the data when u is
    None)."""
    r = np.asarray(r, float)
    u = problem.velocities(r) if u is None else np.asarray(u, float)
    d = problem.dim
    U = u.reshape(-1, d)
    uhat = U.copy()
    uhat[:, 0] += problem.mu * np.linalg.norm(U[:, 1:], axis=1)
    res = r - project_cone(r - uhat.ravel(), problem.mu, d)
    return float(np.linalg.norm(res) / (1.0 + np.linalg.norm(problem.q)))


def fc2d_lcp(problem: FrictionProblem) -> LCP:
    """The exact LCP of a 2-D problem (module docstring); z = (r_N, β⁺, β⁻, λ)
    stacked by kind, each of length n_contacts."""
    if problem.dim != 2:
        raise InvalidOptionError("fc2d_lcp is for 2-D problems; 3-D cones are not polyhedral")
    nc = problem.n_contacts
    W = sp.csr_matrix(problem.W)
    N, T = np.arange(nc) * 2, np.arange(nc) * 2 + 1
    Wnn, Wnt = W[N][:, N], W[N][:, T]
    Wtn, Wtt = W[T][:, N], W[T][:, T]
    I = sp.identity(nc, format="csr")
    Mu = sp.diags(problem.mu)
    M = sp.bmat([[Wnn, Wnt, -Wnt, None],
                 [Wtn, Wtt, -Wtt, I],
                 [-Wtn, -Wtt, Wtt, I],
                 [Mu, -I, -I, None]], format="csc")
    q = np.concatenate([problem.q[N], problem.q[T], -problem.q[T], np.zeros(nc)])
    return LCP(M, q)


def _r_from_z(z, nc):
    r = np.zeros(2 * nc)
    r[0::2] = z[:nc]
    r[1::2] = z[nc:2 * nc] - z[2 * nc:3 * nc]
    return r


@dataclass
class FrictionSolution:
    """``r``, ``u`` (= W r + q from the data), ``error`` (natural map), ``ok``
    (error <= tol), ``status``, ``message``, ``method``, ``stats``."""

    r: np.ndarray | None
    u: np.ndarray | None
    error: float
    ok: bool
    status: str
    message: str
    method: str
    tol: float
    stats: dict = field(default_factory=dict)


def _solve_lemke_2d(problem, tol, options):
    from .solve import solve

    nc = problem.n_contacts
    sol = solve(fc2d_lcp(problem), "lemke", accuracy=min(tol, 1e-9), **options)
    if sol.z is None:
        return None, sol.status, sol.message
    return _r_from_z(sol.z, nc), sol.status, sol.message


FRICTION_METHODS = {"lemke": _solve_lemke_2d}


def solve_friction(problem: FrictionProblem, method: str = "auto", tol: float = 1e-8,
                   **options) -> FrictionSolution:
    """Solve a frictional contact problem and certify the answer by the
    natural-map error computed from the data.  Methods: "lemke" (2-D: the
    exact LCP); "auto" picks it for 2-D.  3-D methods are not implemented
    yet (issue 20)."""
    if not isinstance(problem, FrictionProblem):
        raise InvalidProblemError(f"solve_friction takes a FrictionProblem; got "
                                  f"{type(problem).__name__}")
    if method == "auto":
        if problem.dim != 2:
            raise InvalidOptionError(
                "no 3-D friction method yet: faceted-cone LCPs and the cone-programming fixed "
                "points are issue 20's next part")
        method = "lemke"
    if method not in FRICTION_METHODS:
        raise InvalidOptionError(f"unknown friction method {method!r}; methods: "
                                 f"{', '.join(FRICTION_METHODS)}, auto")
    if problem.n_contacts == 0:
        r = np.zeros(0)
        return FrictionSolution(r, r, 0.0, True, "solved", "no contacts", method, tol)
    r, status, message = FRICTION_METHODS[method](problem, tol, options)
    if r is None:
        return FrictionSolution(None, None, np.inf, False, status, message, method, tol)
    u = problem.velocities(r)
    err = natural_map_error(problem, r, u)
    ok = bool(err <= tol)
    return FrictionSolution(r, u, err, ok, "solved" if ok else "inaccurate",
                            f"natural-map error {err:.1e} {'<=' if ok else '>'} {tol:.0e} "
                            f"({method}: {message})", method, tol)
