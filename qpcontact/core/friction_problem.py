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
‖r − proj_K(r − û)‖ / (1 + ‖q‖), and each contact's on its own scale
(:mod:`qpcontact.judge.friction_certificate`), computed from the data for every
answer, whatever a method reports.

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
are in :mod:`qpcontact.solvers.friction.fixed_points` and :mod:`qpcontact.solvers.friction.newton`.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .errors import InvalidOptionError, InvalidProblemError
from .matrices import as_matrix, as_vector
from .problems import LCP

__all__ = ["FrictionProblem", "project_cone", "modified_velocity", "faceted_lcp", "fc2d_lcp",
           "DENSE_W_LIMIT"]

#: the largest local problem whose W = Hᵀ M⁻¹ H is formed densely from a global one
DENSE_W_LIMIT = 6000


def _coefficients(mu) -> np.ndarray:
    """The friction coefficients as a float array (at least 1-D);
    InvalidProblemError for what is not numbers (a string, None, a ragged
    list) rather than numpy's ValueError."""
    try:
        out = np.atleast_1d(np.asarray(mu, dtype=float))
        # numpy reads "0.3" as 0.3: a coefficient is a number, not text
        if np.asarray(mu).dtype.kind in "USO" and any(
                isinstance(v, (str, bytes)) for v in np.asarray(mu, dtype=object).ravel()):
            raise TypeError
    except (TypeError, ValueError):
        shown = repr(mu)
        raise InvalidProblemError(
            "friction coefficients mu must be numbers, one per contact; got "
            + (shown if len(shown) <= 80 else shown[:77] + "...")) from None
    return out


class FrictionProblem:
    """A frictional contact problem (module docstring), validated like LCP.

    ``W`` (m x m, m = dim · n_contacts), ``q`` (m,), ``mu`` (n_contacts,),
    ``dim`` 2 or 3.  Global problems (:meth:`global_problem`) keep M, H, f, w
    in ``global_data`` and are reduced to local form.  ``solution`` and
    ``guesses`` hold what an FCLIB file stores (dicts of r, u, v).
    ``delassus_factors`` (None, or (Hᵀ, m⁻¹): W = Hᵀ diag(m⁻¹) H with Hᵀ
    sparse m x n_dofs and the inverse masses) is what a generator that forms W
    so keeps (the piles); a method that can use it checks that it reproduces
    W (ip-lcp's body-space solves), the others read W."""

    def __init__(self, W, q, mu, dim, *, name: str = ""):
        if dim not in (2, 3):
            raise InvalidProblemError(f"dim must be 2 or 3 (the contact space); got {dim!r}")
        self.dim = int(dim)
        mu = _coefficients(mu)
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
        self.delassus_factors = None
        self.solution = None
        self.guesses: list = []
        diag = np.asarray(self.W.diagonal()) if m else np.zeros(0)
        self._diagonal = diag
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
        the methods registered for "friction-global", solve it).  True: reduce or raise saying why
        not; False: keep it global."""
        import scipy.sparse.linalg as spla

        M = as_matrix(M, "M")
        n = M.shape[0]
        mu = _coefficients(mu)
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
            prob.delassus_factors = None
            if not np.all(np.isfinite(mu)) or np.any(mu < 0):
                bad = int(np.flatnonzero(~(np.isfinite(mu) & (mu >= 0)))[0])
                raise InvalidProblemError(
                    f"friction coefficients must be finite and >= 0; mu[{bad}] = {mu[bad]}")
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

    @property
    def W_diagonal(self) -> np.ndarray:
        """W's diagonal, read once (the certificate's contact scales take it
        at every check of an iterate)."""
        if getattr(self, "_diagonal", None) is None:      # a problem built without __init__
            self._diagonal = np.asarray(self.W.diagonal())
        return self._diagonal

    @property
    def W_blocks(self):
        """A 2-D problem's W by its 2 × 2 blocks, formed once: (the diagonal
        blocks (nc, 2, 2), the others as (bptr, bcols, bdata (nb, 2, 2)) by
        block row, columns sorted) — NSGS's sweeps and Newton's Jacobians read
        them."""
        if getattr(self, "_blocks", None) is None:
            from ._block_kernels import blocks_2d   # numba: imported where it runs

            if self.dim != 2:
                raise InvalidOptionError("W_blocks: 2-D problems only")
            W = sp.csr_matrix(self.W)
            self._blocks = blocks_2d(W.indptr.astype(np.int64), W.indices.astype(np.int64),
                                     W.data.astype(float))
        return self._blocks

    @property
    def abs_W(self):
        """W's entries' absolute values, formed on first use and kept (the
        certificate's contact sizes take ``abs(W) @ abs(r)`` at every check of
        an iterate)."""
        if getattr(self, "_abs_W", None) is None:
            self._abs_W = abs(self.W)
        return self._abs_W

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
    if dim == 2:
        from ._cone_kernels import project_cone_2d   # numba: imported where it runs
        return project_cone_2d(np.ascontiguousarray(r, float).ravel(),
                               np.ascontiguousarray(mu, float))
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


def modified_velocity(u, mu, dim) -> np.ndarray:
    """De Saxcé's û = u + μ‖u_T‖ e_N per contact (flat, like u)."""
    U = np.reshape(u, (-1, dim))
    uhat = U.copy()
    uhat[:, 0] += mu * np.linalg.norm(U[:, 1:], axis=1)
    return uhat.ravel()


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
