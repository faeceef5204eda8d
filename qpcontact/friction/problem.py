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

In 2-D the cone is polyhedral and the problem *is* an LCP (:func:`faceted_lcp`
with k = 2): per contact z = (r_N, β⁺, β⁻, λ) with r_T = β⁺ − β⁻ and

    w = (u_N,  λ + u_T,  λ − u_T,  μ r_N − β⁺ − β⁻) >= 0,  z >= 0,  z'w = 0:

λ is the slip speed, β± the friction parts; sliding with u_T < 0 forces
λ = −u_T, β⁻ = 0 and β⁺ = μ r_N (friction opposes the slip).  Lemke solves it
exactly; it is the oracle for every other 2-D method.  In 3-D the same LCP
with k tangent directions d_j = (cos 2πj/k, sin 2πj/k) (Stewart–Trinkle,
Anitescu–Potra: r_T = Σ β_j d_j, w_β = D'u_T + λ, w_λ = μ r_N − Σ β_j) is
Coulomb's law on the inscribed k-gon: exact for open contacts, approximate
(to about 1 − cos(π/k) in the friction force's size and π/k in its
direction) on sticking and sliding ones.  The 3-D methods on the true cone
are in :mod:`qpcontact.friction_cones`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..core.errors import InvalidOptionError, InvalidProblemError
from ..core.problems import LCP
from ..core.matrices import as_matrix, as_vector

__all__ = ["FrictionProblem", "FrictionSolution", "natural_map_error", "componentwise_error",
           "certified_error", "global_errors", "contact_scales", "contact_sizes", "modified_velocity",
           "project_cone",
           "faceted_lcp", "fc2d_lcp", "solve_friction", "FRICTION_METHODS", "GLOBAL_METHODS"]

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
    def global_problem(cls, M, H, f, w, mu, dim, *, name: str = "", reduce=None):
        """M v = H r + f, u = Hᵀ v + w.

        ``reduce`` None (default): reduced to local form (W = Hᵀ M⁻¹ H, q =
        Hᵀ M⁻¹ f + w, one sparse factorization of M) when W is affordable —
        at most DENSE_W_LIMIT local unknowns — and M is nonsingular; kept
        global otherwise (``W`` is then None and the methods that keep v,
        :data:`GLOBAL_METHODS`, solve it).  True: reduce or raise saying why
        not; False: keep it global."""
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
        if reduce not in (None, True, False):
            raise InvalidOptionError(f"reduce must be None (auto), True or False; got {reduce!r}")
        Ms = sp.csc_matrix(M)
        big = abs(Ms).max() if Ms.nnz else 0.0
        if (Ms.nnz and abs(Ms - Ms.T).max() > 1e-12 * big) or np.any(Ms.diagonal() < 0):
            raise InvalidProblemError("global problem: M must be symmetric with a nonnegative "
                                      "diagonal (a mass or stiffness matrix)")
        why_not = None
        if m > DENSE_W_LIMIT:
            why_not = (f"W = Hᵀ M⁻¹ H would be dense {m} x {m} (above DENSE_W_LIMIT = "
                       f"{DENSE_W_LIMIT} local unknowns)")
        lu = None
        if why_not is None and reduce is not False:
            try:
                lu = spla.splu(Ms)
                piv = np.abs(lu.U.diagonal())
                if n > 0 and not piv.min() > 1e-13 * piv.max():
                    lu = None
            except RuntimeError:   # exactly singular
                lu = None
            if lu is None:
                why_not = ("M is singular (the system without its contacts can move as a "
                           "mechanism), so W = Hᵀ M⁻¹ H does not exist")
        if reduce is True and why_not is not None:
            raise InvalidProblemError(f"global problem: cannot reduce to local form: {why_not}; "
                                      "keep it global (reduce=None or False)")
        if reduce is False or why_not is not None:
            prob = cls.__new__(cls)
            prob.dim, prob.mu, prob.name = int(dim), mu, name
            if not np.all(np.isfinite(mu)) or np.any(mu < 0):
                raise InvalidProblemError("friction coefficients must be finite and >= 0")
            prob.W = prob.q = None
            prob.solution, prob.guesses = None, []
            prob.global_data = {"M": Ms, "H": sp.csc_matrix(H), "f": f, "w": w, "lu": None,
                                "unreduced_because": why_not or "reduce=False"}
            return prob
        Minv_H = lu.solve(np.asarray(sp.csc_matrix(H).toarray())) if m else np.zeros((n, 0))
        W = np.asarray(H.T @ Minv_H) if m else np.zeros((0, 0))
        W = 0.5 * (W + W.T)
        q = np.asarray(H.T @ lu.solve(f)).ravel() + w if m else np.zeros(0)
        prob = cls(W, q, mu, dim, name=name)
        prob.global_data = {"M": M, "H": H, "f": f, "w": w, "lu": lu}
        return prob

    @classmethod
    def frictionless(cls, lcp, dim: int = 2, *, name: str = ""):
        """A normal-contact LCP (w = M z + q, M the symmetric Delassus
        operator of the contacts: a drum step, a mechanism step's exact LCP)
        as a frictional contact problem with μ = 0, for FCLIB export: W's
        normal rows and columns are M, each tangent gets a unit diagonal
        (any positive value: with μ = 0 the cone is the normal ray, so
        r_T = 0 and u_T = 0), q's normal entries are the LCP's q."""
        M = sp.csr_matrix(lcp.M.toarray() if hasattr(lcp.M, "toarray") else lcp.M)
        nc = M.shape[0]
        if nc and abs(M - M.T).max() > 1e-12 * abs(M).max():
            raise InvalidProblemError("only a symmetric contact LCP (a Delassus operator) is a "
                                      "frictionless contact problem; this M is not symmetric")
        m = int(dim) * nc
        normal = sp.csr_matrix((np.ones(nc), (np.arange(nc) * dim, np.arange(nc))),
                               shape=(m, nc))
        tangent = sp.diags(np.tile(np.r_[0.0, np.ones(dim - 1)], nc))
        q = np.zeros(m)
        q[0::dim] = lcp.q
        return cls((normal @ M @ normal.T + tangent).tocsc(), q, np.zeros(nc), dim, name=name)

    @property
    def is_reduced(self) -> bool:
        """False for a global problem kept without W (see global_problem)."""
        return self.W is not None

    @property
    def n_contacts(self) -> int:
        return self.mu.size

    def velocities(self, r) -> np.ndarray:
        if self.W is None:
            raise InvalidOptionError("this global problem is kept without W "
                                     f"({self.global_data['unreduced_because']}): its velocities "
                                     "are u = Hᵀ v + w, from the global velocity v a method "
                                     "returns")
        return np.asarray(self.W @ r).ravel() + self.q

    def global_velocity(self, r) -> np.ndarray | None:
        """v = M⁻¹ (H r + f) of a global problem."""
        g = self.global_data
        if g is None or g["lu"] is None:
            return None
        return g["lu"].solve(np.asarray(g["H"] @ r).ravel() + g["f"])

    def __repr__(self) -> str:
        kind = ("local" if self.global_data is None else "global" if self.is_reduced
                else "global, unreduced")
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
    return _natural_map(r, u, problem.mu, problem.dim, problem.q)


def _natural_map(r, u, mu, d, offset) -> float:
    """‖r − proj_K(r − û)‖ / (1 + ‖offset‖): q for a local problem, f for a
    global one (Siconos's two normalizations)."""
    res = r - project_cone(r - modified_velocity(u, mu, d), mu, d)
    return float(np.linalg.norm(res) / (1.0 + np.linalg.norm(offset)))


def modified_velocity(u, mu, dim) -> np.ndarray:
    """De Saxcé's û = u + μ‖u_T‖ e_N per contact (flat, like u)."""
    U = np.reshape(u, (-1, dim))
    uhat = U.copy()
    uhat[:, 0] += mu * np.linalg.norm(U[:, 1:], axis=1)
    return uhat.ravel()


def contact_scales(problem: FrictionProblem) -> np.ndarray:
    """ρ_i = 1 / W_nn,i per contact (force per velocity): what turns a
    contact's velocity into a force on its own scale (a contact W says
    nothing about: 1 / the largest normal entry)."""
    return _scales(np.abs(np.asarray(problem.W.diagonal(), dtype=float)[0::problem.dim]))


def _scales(wn) -> np.ndarray:
    """1 / wn per contact, 1 / max(wn) where wn is 0 (1 if all are)."""
    fallback = 1.0 / wn.max() if wn.size and wn.max() > 0 else 1.0
    return np.where(wn > 0, 1.0 / np.where(wn > 0, wn, 1.0), fallback)


def componentwise_error(problem: FrictionProblem, r, u=None) -> float:
    """Each contact judged on its own scale: the natural-map residual in
    force units, ‖r_i − proj_K(r_i − ρ_i û_i)‖ (ρ_i from
    :func:`contact_scales`), against s_i = ‖r_i‖ + ρ_i(‖q_i‖ + ‖(|W||r|)_i‖),
    the sizes of the terms it is made of (floored at eps · max_j s_j).

    Siconos's measure divides by 1 + ‖q‖: with forces in kN and
    displacements in m (‖q‖ << 1) it is absolute, and a stiff structure's
    W ~ 1e-5 hides a force error of 1e-2 kN below 1e-7.  This one does not."""
    r = np.asarray(r, float)
    if r.size == 0:
        return 0.0
    u = problem.velocities(r) if u is None else np.asarray(u, float)
    rho = contact_scales(problem)
    return _worst_contact(r, u, problem.mu, problem.dim, rho, contact_sizes(problem, r, rho))


def _worst_contact(r, u, mu, d, rho, size) -> float:
    """max_i ‖r_i − proj_K(r_i − ρ_i û_i)‖ / size_i (componentwise_error's core)."""
    x = r - np.repeat(rho, d) * modified_velocity(u, mu, d)
    res = np.linalg.norm((r - project_cone(x, mu, d)).reshape(-1, d), axis=1)
    if not size.max() > 0:
        return float(res.max()) if res.max() > 0 else 0.0
    return float(np.max(res / size))


def contact_sizes(problem: FrictionProblem, r, rho=None) -> np.ndarray:
    """s_i = ‖r_i‖ + ρ_i(‖q_i‖ + ‖(|W||r|)_i‖), floored at eps · max_j s_j:
    the force scale each contact's residual is judged against."""
    rho = contact_scales(problem) if rho is None else rho
    return _sizes(r, rho, problem.q, np.asarray(abs(problem.W) @ np.abs(r)).ravel(),
                  problem.dim)


def _sizes(r, rho, offset, terms, d) -> np.ndarray:
    """‖r_i‖ + ρ_i(‖offset_i‖ + ‖terms_i‖), floored at eps · the largest."""
    def norms(x):
        return np.linalg.norm(np.reshape(x, (-1, d)), axis=1)
    size = norms(r) + rho * (norms(offset) + norms(terms))
    return np.maximum(size, np.finfo(float).eps * size.max(initial=0.0))


def global_errors(problem: FrictionProblem, r, v) -> tuple[float, float, float]:
    """The errors of (r, v) for a global problem, from M, H, f, w alone (no
    W): Siconos's natural-map error of (r, u = Hᵀv + w) over 1 + ‖f‖; the
    componentwise one (:func:`componentwise_error` with W's diagonal
    estimated by Hᵀ diag(M)⁻¹ H, a scale only); and the equilibrium's
    componentwise residual max_k |Mv − Hr − f|_k / (|M||v| + |H||r| + |f|)_k
    (each equation on its own scale, floored at eps times the largest)."""
    g, d = problem.global_data, problem.dim
    M, H, f, w = g["M"], g["H"], g["f"], g["w"]
    r, v = np.asarray(r, float), np.asarray(v, float)
    u = np.asarray(H.T @ v).ravel() + w
    nat = _natural_map(r, u, problem.mu, d, f)
    eq = np.asarray(M @ v).ravel() - np.asarray(H @ r).ravel() - f
    eq_size = (np.asarray(abs(M) @ np.abs(v)).ravel() + np.asarray(abs(H) @ np.abs(r)).ravel()
               + np.abs(f))
    eq_size = np.maximum(eq_size, np.finfo(float).eps * eq_size.max(initial=0.0))
    equilibrium = float(np.max(np.where(eq == 0, 0.0, np.abs(eq) / np.where(eq_size > 0, eq_size,
                                                                            1.0)), initial=0.0))
    if r.size == 0:
        return nat, 0.0, equilibrium
    dm = np.asarray(M.diagonal(), float)
    inv = np.where(dm > 0, 1.0 / np.where(dm > 0, dm, 1.0), 0.0)
    rho = _scales(np.asarray((H.multiply(H)).T @ inv).ravel()[0::d])
    size = _sizes(r, rho, w, np.asarray(abs(H).T @ np.abs(v)).ravel(), d)
    return nat, _worst_contact(r, u, problem.mu, d, rho, size), equilibrium


def certified_error(problem: FrictionProblem, r, u=None) -> float:
    """What an answer is held to: the larger of Siconos's natural-map error
    and the componentwise one."""
    u = problem.velocities(r) if u is None else u   # once for both measures
    return max(natural_map_error(problem, r, u), componentwise_error(problem, r, u))


def faceted_lcp(problem: FrictionProblem, facets: int = 2):
    """The LCP of the module docstring: z = (r_N, β, λ) stacked by kind
    (n_contacts, k · n_contacts, n_contacts).  Exact in 2-D (k = 2, d = ±1);
    in 3-D the cone faceted by k >= 3 directions.  Returns (LCP, D) with D
    the (dim · nc) x (k · nc) map β -> r (tangent rows)."""
    nc, dim = problem.n_contacts, problem.dim
    if isinstance(facets, bool) or not isinstance(facets, (int, np.integer)):
        raise InvalidOptionError(f"facets must be an integer; got {facets!r}")
    k = int(facets)
    if dim == 2 and k != 2:
        raise InvalidOptionError("a 2-D cone has exactly two facets (±t); facets must be 2")
    if dim == 3 and k < 3:
        raise InvalidOptionError(f"a faceted 3-D cone needs facets >= 3; got {facets!r}")
    W = sp.csr_matrix(problem.W)
    angles = 2 * np.pi * np.arange(k) / k
    dirs = np.array([[1.0], [-1.0]]) if dim == 2 else np.stack([np.cos(angles), np.sin(angles)], 1)
    # column (i, j) of D puts d_j into contact i's tangent rows
    shape = (nc, k, dim - 1)
    rows = np.broadcast_to(dim * np.arange(nc)[:, None, None] + 1 + np.arange(dim - 1), shape)
    cols = np.broadcast_to(k * np.arange(nc)[:, None, None] + np.arange(k)[None, :, None], shape)
    vals = np.broadcast_to(dirs[None, :, :], shape)
    D = sp.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(dim * nc, k * nc))
    En = sp.csr_matrix((np.ones(nc), (np.arange(nc) * dim, np.arange(nc))), shape=(dim * nc, nc))
    E = sp.csr_matrix((np.ones(k * nc), (np.arange(k * nc), np.repeat(np.arange(nc), k))),
                      shape=(k * nc, nc))
    B = sp.hstack([En, D], format="csr")            # (r_N, β) -> r
    M = sp.bmat([[B.T @ W @ B, sp.vstack([sp.csr_matrix((nc, nc)), E])],
                 [sp.hstack([sp.diags(problem.mu), -E.T]), None]], format="csc")
    q = np.concatenate([B.T @ problem.q, np.zeros(nc)])
    return LCP(M, q), D


def fc2d_lcp(problem: FrictionProblem) -> LCP:
    """The exact LCP of a 2-D problem (module docstring); z = (r_N, β, λ)
    stacked by kind, β = (β⁺, β⁻) per contact."""
    if problem.dim != 2:
        raise InvalidOptionError("fc2d_lcp is for 2-D problems; 3-D cones are not polyhedral "
                                 "(faceted_lcp(problem, k) approximates them)")
    return faceted_lcp(problem, 2)[0]


@dataclass
class FrictionSolution:
    """``r``, ``u`` (= W r + q from the data), ``error`` (Siconos's natural
    map), ``componentwise_error`` (each contact on its own scale), ``ok``
    (both <= tol), ``status``, ``message``, ``method``, ``stats``.  For a
    global problem kept without W: ``v`` (its global velocity), u = Hᵀv + w,
    and ``equilibrium_error`` (Mv = Hr + f, each equation on its own scale),
    also held to tol."""

    r: np.ndarray | None
    u: np.ndarray | None
    error: float
    ok: bool
    status: str
    message: str
    method: str
    tol: float
    stats: dict = field(default_factory=dict)
    componentwise_error: float = float("nan")
    v: np.ndarray | None = None
    equilibrium_error: float = float("nan")


def _solve_lemke(problem, tol, options):
    """Lemke on the faceted LCP: exact in 2-D; option ``facets`` (3-D, default
    8); the LCP method's options (``max_pivots``, ``restarts``, ``seed``,
    ``covering``) passed on.  Large sparse LCPs go to the sparse revised form
    (:mod:`qpcontact.methods.lemke_sparse`).

    2-D: a basic solution carries the rounding of one LU solve, eps times
    the forces it is coupled with.  Contacts whose data are themselves at
    that level (q entries of 1e-17 that are rounding residues, beside forces
    of 1e-3) then fail the componentwise measure: on the 2020-contact
    granular file 26 contacts did, worst 2e-2, while the natural-map error
    was 6e-16.  So when the basic solution is not certified, it is
    *polished*: entries below 1e-13 of the largest — the computed values of
    degenerate basic variables, zero in exact arithmetic — are set to zero,
    r_T is clipped to |r_T| <= μ r_N, and semismooth Newton starts there (on
    that file: one iteration to 2e-16 in both measures).  The polished point
    is kept only when its certificate is better; the message says so."""
    from ..dispatch.driver import solve

    options = dict(options)
    facets = options.pop("facets", 2 if problem.dim == 2 else 8)
    lcp, D = faceted_lcp(problem, facets)
    nc = problem.n_contacts
    sol = solve(lcp, "lemke", accuracy=min(tol, 1e-9), **options)
    stats = {"facets": int(facets), "lcp_size": lcp.n, "iterations": sol.iterations}
    if sol.z is None:
        return None, sol.status, f"Lemke {sol.status}: {sol.message}", stats
    r = np.asarray(D @ sol.z[nc:-nc]).ravel()
    r[0::problem.dim] = sol.z[:nc]
    cone = "exact 2-D LCP" if problem.dim == 2 else f"{facets}-faceted cone"
    message = f"{cone}, Lemke: {sol.iterations} pivots, LCP certificate {sol.certificate.error:.1e}"
    if problem.dim == 2:
        before = certified_error(problem, r)
        if before > tol:
            r, message = _polished(problem, r, before, tol, message, stats)
    return r, "solved", message, stats


def _polished(problem, r, before, tol, message, stats):
    """A 2-D basic solution (certified error ``before``) polished by Newton
    from its purified point (see _solve_lemke); the better-certified of the
    two."""
    from .cones import solve_natural_newton

    start = r.copy()
    start[np.abs(start) < 1e-13 * np.abs(start).max(initial=0.0)] = 0.0
    bound = problem.mu * start[0::2]
    start[1::2] = np.clip(start[1::2], -bound, bound)
    rn, _, _, nstats = solve_natural_newton(problem, tol, {"r0": start})
    after = certified_error(problem, rn) if rn is not None else np.inf
    stats["polish_iterations"] = nstats.get("iterations")
    if after < before:
        k = nstats.get("iterations")
        return rn, (f"{message}; its basic solution (error {before:.1e}) polished by Newton from "
                    f"its purified point ({k} iteration{'s' if k != 1 else ''})")
    return r, f"{message}; a Newton polish did not improve it (error {after:.1e})"


def _solve_nsgs(problem, tol, options):
    """Nonsmooth Gauss–Seidel (Siconos's NSGS; :mod:`qpcontact._nsgs_kernels`):
    sweeps over the contacts, each solving its local problem with the
    others frozen — exactly in 2-D, by a local projected fixed point in 3-D.
    Options: ``max_sweeps`` (10 000), ``check_every`` (10 sweeps between
    error checks), ``r0``, ``local_rtol`` (1e-14), ``max_local`` (200
    local iterations).  Stops when both error measures are <= tol, or
    when the best error has not improved for 100 checks; returns the best
    iterate.  No convergence guarantee (Coulomb friction is not a
    minimisation): the certificate decides."""
    from ._nsgs_kernels import sweeps

    options = dict(options)
    max_sweeps = int(options.pop("max_sweeps", 10_000))
    every = max(1, int(options.pop("check_every", 10)))
    local_rtol = float(options.pop("local_rtol", 1e-14))
    max_local = int(options.pop("max_local", 200))
    r0 = options.pop("r0", None)
    if options:
        raise InvalidOptionError(f"'nsgs' does not take {', '.join(sorted(options))}; its options "
                                 "are max_sweeps, check_every, r0, local_rtol, max_local")
    d, nc = problem.dim, problem.n_contacts
    W = sp.csr_matrix(problem.W)
    W.sort_indices()
    blocks = np.empty((nc, d, d))
    for i in range(nc):
        blocks[i] = W[d * i:d * i + d, d * i:d * i + d].toarray()
    r = np.zeros(d * nc) if r0 is None else np.array(r0, float).ravel()
    if r.shape != (d * nc,):
        raise InvalidOptionError(f"'nsgs': r0 must have {d * nc} entries; got {r.size}")
    indices = W.indices.astype(np.int64)
    best, best_r, since, done = np.inf, r.copy(), 0, 0
    while done < max_sweeps:
        sweeps(W.indptr, indices, W.data, problem.q, problem.mu, d, r, blocks, every,
               local_rtol, max_local)
        done += every
        err = certified_error(problem, r)
        if err < best:
            best, best_r, since = err, r.copy(), 0
        else:
            since += 1
        if best <= tol or since >= 100 or not np.all(np.isfinite(r)):
            break
    why = ("reached the tolerance" if best <= tol else
           "stalled (no better iterate in 100 checks)" if since >= 100 else
           f"stopped at {max_sweeps} sweeps")
    return best_r, "solved" if best <= tol else "stopped", \
        f"NSGS {why} after {done} sweeps", {"iterations": done}


def _cones(name):
    def run(problem, tol, options):
        from . import cones as friction_cones

        return getattr(friction_cones, name)(problem, tol, options)
    return run


#: methods by name: (problem, tol, options) -> (r or None, status, message, stats)
FRICTION_METHODS = {
    "lemke": _solve_lemke,
    "nsgs": _solve_nsgs,
    "anitescu": _cones("solve_anitescu"),
    "desaxce-fp": _cones("solve_desaxce_fp"),
    "tresca-fp": _cones("solve_tresca_fp"),
    "newton": _cones("solve_natural_newton"),
    "desaxce-global": _cones("solve_desaxce_global"),
}

#: the methods that solve a global problem kept without W (they return v too)
GLOBAL_METHODS = ("desaxce-global",)

#: what "auto" tries, in order, per dimension: each answer is certified before
#: the next is tried, and the first certified one is returned
AUTO_CHAIN = {2: ("lemke", "nsgs", "desaxce-fp", "newton"),
              3: ("desaxce-fp", "newton", "tresca-fp", "nsgs")}

#: above this many contacts "auto" tries NSGS before Lemke in 2-D: Lemke's
#: pivots grow with the contacts (the 2020-contact granular file: 5461
#: pivots, 4 s) while NSGS takes under a second where it converges
LEMKE_FIRST_MAX_CONTACTS = 200


def solve_friction(problem: FrictionProblem, method: str = "auto", tol: float = 1e-8,
                   **options) -> FrictionSolution:
    """Solve a frictional contact problem and certify the answer by the
    natural-map error computed from the data (:func:`natural_map_error`).

    Methods (:data:`FRICTION_METHODS`): ``"lemke"`` (2-D: the exact LCP; 3-D:
    the LCP of the cone faceted by ``facets`` directions, default 8 — an
    approximation whose error against the true cone is reported),
    ``"anitescu"`` (the convex relaxation, one SOCP), ``"desaxce-fp"`` and
    ``"tresca-fp"`` (fixed points of SOCPs; options ``backend`` "clarabel" or
    "scs" — in 2-D, where the subproblems are QPs, any QP method such as
    "osqp" —, ``backend_options``, ``inner_tol``, ``max_outer``, ``progress``).
    ``"newton"`` (semismooth Newton on the natural map, option ``r0``).
    ``"nsgs"`` (nonsmooth Gauss–Seidel, Siconos's workhorse).
    ``"desaxce-global"`` (global problems kept without W).
    ``"auto"``: in 2-D Lemke and NSGS (NSGS first above
    ``LEMKE_FIRST_MAX_CONTACTS`` contacts), De Saxcé's fixed point, then
    Newton from the best point so far; in
    3-D De Saxcé's fixed point, Newton, Tresca's fixed point, then NSGS —
    each tried only if the one before is not certified.  An answer above ``tol`` comes back with
    status "inaccurate", never as solved."""
    if not isinstance(problem, FrictionProblem):
        raise InvalidProblemError(f"solve_friction takes a FrictionProblem; got "
                                  f"{type(problem).__name__}")
    if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not tol > 0:
        raise InvalidOptionError(f"tol must be a positive number; got {tol!r}")
    chain = AUTO_CHAIN[problem.dim] if method == "auto" else (method,)
    if not problem.is_reduced:
        if method == "auto":
            chain = GLOBAL_METHODS
        elif method not in GLOBAL_METHODS and method in FRICTION_METHODS:
            raise InvalidOptionError(
                f"{method!r} needs the local form, and this global problem is kept without W "
                f"({problem.global_data['unreduced_because']}); use {', '.join(GLOBAL_METHODS)} "
                "or 'auto'")
    elif method in GLOBAL_METHODS:
        raise InvalidOptionError(f"{method!r} solves global problems kept without W; this one is "
                                 "in local form (global_problem(..., reduce=False) keeps M, H)")
    if method == "auto" and problem.n_contacts > LEMKE_FIRST_MAX_CONTACTS and "lemke" in chain:
        chain = ("nsgs", "lemke") + tuple(m for m in chain if m not in ("nsgs", "lemke"))
    for name in chain:
        if name not in FRICTION_METHODS:
            raise InvalidOptionError(f"unknown friction method {name!r}; methods: "
                                     f"{', '.join(FRICTION_METHODS)}, auto")
    start = time.perf_counter()
    runs, best = [], None
    for name in chain:
        opts = dict(options)
        if name == "newton" and best is not None and best.r is not None:
            opts.setdefault("r0", best.r)   # polish the best point so far
        sol = _solve_one(problem, name, tol, opts)
        runs.append(sol)
        if best is None or _worst(sol) < _worst(best):
            best = sol
        if sol.ok:
            break
    chosen = runs[-1] if runs[-1].ok else best   # none certified: the smallest error
    others = [r for r in runs if r is not chosen]
    if others:
        chosen.message += " — also tried " + "; ".join(f"{r.method}: {r.message}" for r in others)
        chosen.stats["tried"] = [r.method for r in others]
    chosen.stats["total_time"] = time.perf_counter() - start
    return chosen


def _worst(sol: FrictionSolution) -> float:
    if sol.r is None:
        return np.inf
    return max(sol.error, sol.componentwise_error, np.nan_to_num(sol.equilibrium_error))


def _certified_global(problem, method, x, tol, message, stats) -> FrictionSolution:
    """A global method's x = (r, v), certified from M, H, f, w (global_errors)."""
    g, m = problem.global_data, problem.dim * problem.n_contacts
    r, v = x[:m], x[m:]
    nat, cw, eq = global_errors(problem, r, v)
    ok = bool(max(nat, cw, eq) <= tol)
    u = np.asarray(g["H"].T @ v).ravel() + g["w"]
    return FrictionSolution(r, u, nat, ok, "solved" if ok else "inaccurate",
                            f"natural-map error {nat:.1e}, componentwise {cw:.1e}, equilibrium "
                            f"{eq:.1e} {'<=' if ok else '>'} {tol:.0e} ({method}: {message})",
                            method, tol, stats, cw, v, eq)


def _solve_one(problem, method, tol, options) -> FrictionSolution:
    if problem.n_contacts == 0 and problem.is_reduced:
        r = np.zeros(0)
        return FrictionSolution(r, r, 0.0, True, "solved", "no contacts", method, tol, {}, 0.0)
    start = time.perf_counter()
    r, status, message, stats = FRICTION_METHODS[method](problem, tol, options)
    stats["time"] = time.perf_counter() - start
    if r is None and "ray" in stats:     # a checked proof that no solution exists
        return FrictionSolution(None, None, np.inf, False, "no_solution",
                                f"{method}: {message}", method, tol, stats)
    if r is None or not np.all(np.isfinite(r)):
        return FrictionSolution(None, None, np.inf, False, "failed",
                                f"{method}: no usable point ({message})", method, tol, stats)
    if not problem.is_reduced:
        return _certified_global(problem, method, r, tol, message, stats)
    u = problem.velocities(r)
    err = natural_map_error(problem, r, u)
    cw = componentwise_error(problem, r, u)
    ok = bool(max(err, cw) <= tol)
    return FrictionSolution(r, u, err, ok, "solved" if ok else "inaccurate",
                            f"natural-map error {err:.1e}, componentwise {cw:.1e} "
                            f"{'<=' if ok else '>'} {tol:.0e} ({method}: {message})",
                            method, tol, stats, cw)
