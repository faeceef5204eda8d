"""The error measures of a frictional contact answer, computed from the data.

Siconos's natural-map error ‖r − proj_K(r − û)‖ / (1 + ‖q‖) (for a global
problem over 1 + ‖f‖), and each contact judged on its own scale
(:func:`componentwise_error`): with forces in kN and displacements in m
(‖q‖ << 1) Siconos's measure is absolute, and a stiff structure's W ~ 1e-5
hides a force error of 1e-2 kN below 1e-7; the componentwise one does not.
An answer is held to both (and, for a global problem, to its equilibrium
Mv = Hr + f, each equation on its own scale): :func:`certify_friction`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..core.errors import InvalidProblemError
from .forward import ForwardErrorMixin
from .scales import row_rounding
from ..core.friction_problem import FrictionProblem, modified_velocity, project_cone

__all__ = ["FrictionCertificate", "certify_friction", "natural_map_error", "componentwise_error",
           "certified_error", "global_errors", "contact_scales", "contact_sizes", "natural_map",
           "worst_contact", "contact_errors", "sizes", "scales_from_diagonal",
           "projection_jacobian", "natural_map_jacobian"]

_EPS = np.finfo(float).eps


def natural_map_error(problem: FrictionProblem, r, u=None) -> float:
    """Siconos's error measure: ‖r − proj_K(r − û)‖ / (1 + ‖q‖), û the
    modified velocity of u = W r + q (recomputed from the data when u is
    None)."""
    r = np.asarray(r, float)
    u = problem.velocities(r) if u is None else np.asarray(u, float)
    return natural_map(r, u, problem.mu, problem.dim, problem.q)


def natural_map(r, u, mu, d, offset) -> float:
    """‖r − proj_K(r − û)‖ / (1 + ‖offset‖): q for a local problem, f for a
    global one (Siconos's two normalizations)."""
    res = r - project_cone(r - modified_velocity(u, mu, d), mu, d)
    return float(np.linalg.norm(res) / (1.0 + np.linalg.norm(offset)))


def contact_scales(problem: FrictionProblem) -> np.ndarray:
    """ρ_i = 1 / W_nn,i per contact (force per velocity): what turns a
    contact's velocity into a force on its own scale (a contact W says
    nothing about: 1 / the largest normal entry)."""
    return scales_from_diagonal(np.abs(np.asarray(problem.W_diagonal, dtype=float)[0::problem.dim]))


def scales_from_diagonal(wn) -> np.ndarray:
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
    return worst_contact(r, u, problem.mu, problem.dim, rho, contact_sizes(problem, r, rho))


def worst_contact(r, u, mu, d, rho, size) -> float:
    """max_i ‖r_i − proj_K(r_i − ρ_i û_i)‖ / size_i (componentwise_error's core)."""
    errors = contact_errors(r, u, mu, d, rho, size)
    return float(errors.max()) if errors.size else 0.0


def contact_errors(r, u, mu, d, rho, size) -> np.ndarray:
    """‖r_i − proj_K(r_i − ρ_i û_i)‖ / size_i per contact (the raw residuals
    when every size is 0)."""
    x = r - np.repeat(rho, d) * modified_velocity(u, mu, d)
    res = np.linalg.norm((r - project_cone(x, mu, d)).reshape(-1, d), axis=1)
    if not size.max(initial=0.0) > 0:
        return res
    return res / size


def contact_sizes(problem: FrictionProblem, r, rho=None) -> np.ndarray:
    """s_i = ‖r_i‖ + ρ_i(‖q_i‖ + ‖(|W||r|)_i‖), floored at eps · max_j s_j:
    the force scale each contact's residual is judged against."""
    rho = contact_scales(problem) if rho is None else rho
    return sizes(r, rho, problem.q, np.asarray(problem.abs_W @ np.abs(r)).ravel(),
                  problem.dim)


def sizes(r, rho, offset, terms, d) -> np.ndarray:
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
    nat = natural_map(r, u, problem.mu, d, f)
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
    rho = scales_from_diagonal(np.asarray((H.multiply(H)).T @ inv).ravel()[0::d])
    size = sizes(r, rho, w, np.asarray(abs(H).T @ np.abs(v)).ravel(), d)
    return nat, worst_contact(r, u, problem.mu, d, rho, size), equilibrium


def certified_error(problem: FrictionProblem, r, u=None) -> float:
    """What an answer is held to: the larger of Siconos's natural-map error
    and the componentwise one.  A sparse 2-D problem's (the methods check it
    at every few sweeps and Newton steps) in one compiled pass over W's
    blocks, the same value to rounding (:func:`certify_friction`, which an
    answer is finally judged by, keeps the formulas below)."""
    if u is None and problem.dim == 2 and sp.issparse(problem.W):
        r = np.asarray(r, float)
        if np.all(np.isfinite(r)):
            from ._certify_kernels import certified_error_2d   # numba: where it runs
            return float(certified_error_2d(*problem.W_blocks, problem.q, problem.mu, r))
    u = problem.velocities(r) if u is None else u   # once for both measures
    return max(natural_map_error(problem, r, u), componentwise_error(problem, r, u))


def projection_jacobian(x, mu, dim):
    """Blocks of the (generalized) Jacobian of proj_K at x, one per contact."""
    X = x.reshape(-1, dim)
    J = np.zeros((mu.size, dim, dim))
    xn, xt = X[:, 0], X[:, 1:]
    t = np.linalg.norm(xt, axis=1)
    inside = (t <= mu * xn) & (xn >= 0)     # μ = 0: t = 0 <= −0.0 is not inside at xn < 0
    J[inside] = np.eye(dim)
    mid = np.flatnonzero(~inside & ~(mu * t <= -xn))
    m, tm = mu[mid], t[mid]
    that = xt[mid] / tm[:, None]
    alpha = (xn[mid] + m * tm) / (1 + m * m)
    v = np.concatenate([np.ones((mid.size, 1)), m[:, None] * that], axis=1)
    Jm = v[:, :, None] * v[:, None, :] / (1 + m * m)[:, None, None]
    Jm[:, 1:, 1:] += (m * alpha / tm)[:, None, None] * (
        np.eye(dim - 1) - that[:, :, None] * that[:, None, :])
    J[mid] = Jm
    return J


#: A tangential velocity below this fraction of its contact's scale counts as
#: zero when the natural map is linearized (a sticking contact: the kink of
#: ‖u_T‖ at 0 is not differentiated through).
SLIP_RTOL = 1e-10


def natural_map_jacobian(problem: FrictionProblem, r, slip_rtol: float = SLIP_RTOL):
    """J = I − J_P (I − diag(ρ) T W) at r: the (generalized) Jacobian of the
    natural map F(r) = r − proj_K(r − ρ û(r)), ρ per contact
    (:func:`contact_scales`), T = I + Σ_slip μ_i e_N,i g_iᵀ with g_i =
    u_T,i / ‖u_T,i‖ on the contacts that slide (ρ_i‖u_T,i‖ above ``slip_rtol``
    of the contact's size) and J_P the projection's Jacobian, block by
    contact.  Dense for dense W, CSC for sparse W."""
    d, nc, mu = problem.dim, problem.n_contacts, problem.mu
    m = d * nc
    W = problem.W
    r = np.asarray(r, float)
    u = np.asarray(W @ r).ravel() + problem.q
    rho_c = contact_scales(problem)
    if sp.issparse(W) and d == 2:
        # the sizes, x, the slip, J_P and J's blocks in one compiled pass, J
        # in CSC: the same matrix bit for bit (_certify_kernels)
        from ._certify_kernels import natural_map_jacobian_2d   # numba: where it runs
        terms = np.asarray(problem.abs_W @ np.abs(r)).ravel()
        ptr, idx, val = natural_map_jacobian_2d(u, r, np.asarray(problem.q, float), terms, mu,
                                                rho_c, float(slip_rtol), *problem.W_blocks)
        return sp.csc_matrix((val, idx, ptr), shape=(m, m))
    size = contact_sizes(problem, r, rho_c)
    rho = np.repeat(rho_c, d)
    x = r - rho * modified_velocity(u, mu, d)
    U = u.reshape(-1, d)
    tn = np.linalg.norm(U[:, 1:], axis=1)
    slip = np.flatnonzero(rho_c * tn > slip_rtol * size)
    g = U[slip, 1:] / tn[slip, None]
    # block by block, J = I − J_P + B W with B_i = ρ_i J_P,i T_i: one sparse
    # product, where forming T, A and J_P A as matrices cost 3.6 ms a call on
    # a 120-contact pile (mostly scipy's per-operation overhead)
    JP = projection_jacobian(x, mu, d)
    T = np.broadcast_to(np.eye(d), (nc, d, d)).copy()
    T[slip, 0, 1:] += mu[slip, None] * g
    B = rho_c[:, None, None] * np.einsum("kij,kjl->kil", JP, T)
    blocks = dict(shape=(m, m), blocksize=(d, d))
    diag = (np.arange(nc), np.arange(nc + 1))
    J = sp.identity(m, format="csr") - sp.bsr_matrix((JP, *diag), **blocks).tocsr()
    if sp.issparse(W):
        return sp.csc_matrix(J + sp.bsr_matrix((B, *diag), **blocks).tocsr() @ sp.csr_matrix(W))
    Wd = np.asarray(W, float).reshape(nc, d, m)
    return J.toarray() + np.einsum("kij,kjl->kil", B, Wd).reshape(m, m)


#: Jacobians up to this size are inverted explicitly for the condition
#: estimate; larger ones get a 1-norm estimate (scipy's onenormest) from
#: a few LU solves, as the LCP certificate does.
_EXACT_CONDITION_SIZE = 400


def _friction_condition(problem: FrictionProblem, r) -> float:
    """κ = max_k (|J⁻¹| s̄)_k / s̄_k, s̄ each contact's size repeated over its
    components: a residual of ε of each contact's own size moves r_k by at
    most κ ε of its contact's size (first order).  inf when J is singular:
    the solution is not isolated."""
    from scipy.sparse.linalg import LinearOperator, onenormest, splu

    d = problem.dim
    J = natural_map_jacobian(problem, r)
    sbar = np.repeat(contact_sizes(problem, r), d)
    m = sbar.size
    if m == 0:
        return 0.0
    try:
        with np.errstate(all="ignore"):
            if m <= _EXACT_CONDITION_SIZE:
                dense = J.toarray() if sp.issparse(J) else J
                inv = np.linalg.inv(dense)
                kappa = float(np.max((np.abs(inv) @ sbar) / sbar))
            else:
                if sp.issparse(J):
                    lu = splu(sp.csc_matrix(J))
                    if not np.all(np.abs(lu.U.diagonal()) > 0):
                        return np.inf

                    def solve(v, trans=False):
                        return lu.solve(v, trans="T" if trans else "N")
                else:
                    import scipy.linalg

                    fac = scipy.linalg.lu_factor(J, check_finite=False)
                    if np.min(np.abs(np.diag(fac[0]))) <= _EPS * np.abs(J).max() * m:
                        return np.inf

                    def solve(v, trans=False):
                        return scipy.linalg.lu_solve(fac, v, trans=1 if trans else 0,
                                                     check_finite=False)
                # ‖S⁻¹|J⁻¹|s̄‖∞ = ‖S⁻¹ J⁻¹ diag(s̄)‖∞ = ‖diag(s̄) J⁻ᵀ S⁻¹‖₁
                op = LinearOperator((m, m), dtype=float,
                                    matvec=lambda v: sbar * solve(np.ravel(v) / sbar, trans=True),
                                    rmatvec=lambda v: solve(sbar * np.ravel(v)) / sbar)
                kappa = float(onenormest(op, t=2))
    except (np.linalg.LinAlgError, RuntimeError, ValueError):
        return np.inf
    return kappa if np.isfinite(kappa) else np.inf


@dataclass(frozen=True)
class FrictionCertificate(ForwardErrorMixin):
    """The errors of a frictional contact answer, from the data.

    ``error`` — the one held to ``tol`` — is the largest of Siconos's
    natural-map error (``natural_map_error``), the componentwise one (each
    contact on its own force scale, ``componentwise_error``, reached at
    ``worst_contact``) and, for a global problem kept without W, the
    equilibrium's (``equilibrium_error``; nan for a local problem).
    ``forward_error`` estimates how far each contact's reaction may be from an
    exact solution of the data as stored, relative to its contact's size
    (``condition`` times the error, at least rounding), from the natural map's
    Jacobian; inf where that Jacobian is singular (the solution is not
    isolated: a rigid body on redundant supports) and for global problems
    (not estimated).  Computed on first use.
    """

    error: float
    natural_map_error: float
    componentwise_error: float
    equilibrium_error: float
    worst_contact: int
    overflow: bool = False
    _forward: object = field(default=None, repr=False, compare=False)

    @property
    def isolated(self) -> bool | None:
        """Whether the reactions are pinned by the data: the forward error
        bounds each contact's reaction to a digit (forward_error < 1).  False
        where the natural map's Jacobian is singular or nearly so — redundant
        contacts (a table on four legs), whose reactions are a whole set:
        the answer is one point of it, and
        :func:`qpcontact.unique_reactions` gives a unique representative
        (the minimum-norm or the elastic split).  None for a global problem
        kept without W (no estimate)."""
        if not np.isnan(self.equilibrium_error):
            return None
        return bool(self.forward_error < 1.0)


def certify_friction(problem: FrictionProblem, r, v=None, *, u=None) -> FrictionCertificate:
    """The certificate of reactions ``r`` (and, for a global problem kept
    without W, its global velocity ``v``), computed from the data alone;
    ``u`` = W r + q when the caller has formed it already (as the measures
    above take it)."""
    inf, nan = np.inf, np.nan
    m = problem.dim * problem.n_contacts
    r = np.asarray(r, float).ravel()
    if r.shape != (m,):
        raise InvalidProblemError(f"r has {r.size} entries; the problem has {problem.n_contacts} "
                                  f"contacts in dimension {problem.dim} ({m} entries)")
    if not problem.is_reduced:
        if v is None:
            raise InvalidProblemError("this global problem is kept without W: its certificate "
                                      "needs the global velocity v too (certify(problem, r, v=v))")
        v = np.asarray(v, float).ravel()
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(v))):
            return FrictionCertificate(inf, inf, inf, inf, -1, False, (inf, inf))
        nat, cw, eq = global_errors(problem, r, v)
        return FrictionCertificate(max(nat, cw, eq), nat, cw, eq, -1, False, (inf, inf))
    if not np.all(np.isfinite(r)):
        return FrictionCertificate(inf, inf, inf, nan, -1, False, (inf, inf))
    if m == 0:
        return FrictionCertificate(0.0, 0.0, 0.0, nan, -1, False, (0.0, 0.0))
    if u is None:
        with np.errstate(over="ignore", invalid="ignore"):
            u = problem.velocities(r)
    if not np.all(np.isfinite(u)):
        return FrictionCertificate(inf, inf, inf, nan, -1, True, (inf, inf))
    nat = natural_map_error(problem, r, u)
    rho = contact_scales(problem)
    per_contact = contact_errors(r, u, problem.mu, problem.dim, rho,
                                 contact_sizes(problem, r, rho))
    cw = float(per_contact.max())
    error = max(nat, cw)
    level = row_rounding(problem.W)     # the rounding of evaluating one row of W r + q

    def forward_pair():
        kappa = _friction_condition(problem, r)
        forward = max(error, level) * kappa
        return float(kappa), (float(forward) if np.isfinite(forward) else np.inf)

    return FrictionCertificate(error, nat, cw, nan, int(np.argmax(per_contact)), False,
                               forward_pair)
