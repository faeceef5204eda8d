"""Contact problems from 2-D and 3-D meshes: the shapes finite-element users bring.

Three families, each at any size, each a problem qpcontact solves directly:

**Membrane on an obstacle** (``membrane``).  A membrane under tension T [N/m]
over the unit square, clamped on its boundary, loaded by a pressure f [N/m²]
and kept above an obstacle ψ [m]:  −T Δu = f where u > ψ, −T Δu ≥ f and u ≥ ψ
everywhere.  The five-point Laplacian on an N x N interior grid (h = 1/(N+1))
gives the stiffness K = T h⁻² (4 on the diagonal, −1 to the four neighbours):
symmetric positive definite and an M-matrix.  With z = u − ψ ≥ 0 (the gap
above the obstacle) the problem is LCP(K, Kψ − f): w = Kz + Kψ − f is the
obstacle's reaction per node (a pressure), and w z = 0.

**Plate on an obstacle** (``plate``).  A thin plate of bending stiffness
D [N·m] (simply supported: u = Δu = 0 on the boundary), D Δ²u = f above the
obstacle: K = D (h⁻² L)² with L the five-point stencil above — the 13-point
biharmonic stencil.  Symmetric positive definite but *not* an M-matrix (its
off-diagonal entries change sign), so the active-set iteration has no
monotone convergence to lean on.

**Elastic block pressed onto a rigid foundation** (``signorini``).  A linear
elastic block [0, a] x [0, b] x [0, c] (Young's modulus E [Pa], Poisson ν),
trilinear hexahedra on an nx x ny x nz grid, its top face pushed down by a
prescribed displacement δ [m], its bottom face resting on a rigid foundation
whose surface lies g(x, y) = κ((x − a/2)² + (y − b/2)²) below it (a bowl:
contact starts in the middle and spreads).  Unknowns are the displacements of
every node not on the top face; the only unilateral constraints are on the
bottom nodes' vertical displacement: u_z ≥ −g.  That is the **mixed**
problem finite-element contact really is — ::

    min ½ u'Ku − f'u   subject to  u_z(bottom) ≥ −g,   (f = −K_ut u_top)

free variables plus complementarity pairs — returned as a
``qpsolvers.Problem`` with lower bounds on the contact dofs only (−inf
elsewhere).  Nothing is condensed onto the contact nodes: the Schur complement
there would be dense.

The membrane and plate LCPs carry their grid's coarse levels
(:func:`grid_hierarchy`, bilinear interpolation from every other node): the
multilevel method ``"mg-bpp"`` starts from them.

Each builder can also return a *degenerate* instance (``degenerate=True``):
the load is chosen so that the solution touches the obstacle exactly at
grid points with a zero reaction there (z_i = w_i = 0: no strict
complementarity), built from a manufactured solution, and a ``scale``
multiplies the stiffness (1e9 against loads of order 1: badly scaled data).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from qpcontact.core.errors import InvalidProblemError
from qpcontact.core.problems import LCP

__all__ = ["laplacian", "grid_hierarchy", "membrane", "plate", "signorini", "instances"]


def _grid_size(N) -> int:
    if isinstance(N, bool) or not isinstance(N, (int, np.integer)) or N < 2:
        raise InvalidProblemError(f"grid size must be an integer >= 2; got {N!r}")
    return int(N)


def laplacian(N: int) -> sp.csr_matrix:
    """The five-point stencil (4, −1 x 4) on an N x N interior grid (unit h)."""
    N = _grid_size(N)
    T = sp.diags([-np.ones(N - 1), 2 * np.ones(N), -np.ones(N - 1)], [-1, 0, 1])
    E = sp.identity(N)
    return (sp.kron(E, T) + sp.kron(T, E)).tocsr()


def _interpolation_1d(x, end: float) -> sp.csr_matrix:
    """Linear interpolation onto interior nodes at the sorted positions ``x``
    (0 < x < end) from the coarse grid of their odd-numbered nodes (0-based
    1, 3, ...; x.size // 2 of them), with zero Dirichlet values at 0 and
    ``end``: a coarse node keeps its value (weight 1), a fine node between
    two coarse ones or a coarse one and the boundary takes the linear
    interpolant in the true positions.  On a uniform grid of an odd count
    the weights are ½; where the count is even the last coarse cell is one
    fine cell wide, and every coarser grid keeps that narrower cell: its
    nodes between the last coarse node and the boundary get the weight of
    their true distances (⅓, ⅕, ...), not ½ as if the grid were uniform.
    Nested for every count."""
    N = x.size
    i = np.arange(N)
    odd = i % 2 == 1
    even = i[~odd]
    left = np.where(even > 0, x[np.maximum(even - 1, 0)], 0.0)
    right = np.where(even < N - 1, x[np.minimum(even + 1, N - 1)], end)
    width = right - left
    rows, cols, vals = [i[odd]], [i[odd] // 2], [np.ones(odd.sum())]
    for ok, col, weight in ((even > 0, (even - 1) // 2, (right - x[even]) / width),
                            (even < N - 1, (even + 1) // 2, (x[even] - left) / width)):
        rows.append(even[ok])
        cols.append(col[ok])
        vals.append(weight[ok])
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(N, N // 2))


def grid_hierarchy(N: int, coarsest: int = 7) -> list:
    """Prolongations of the N x N interior grid's hierarchy, finest first:
    bilinear interpolation in the nodes' true positions (the tensor product
    of :func:`_interpolation_1d`), each level on the odd-numbered nodes of
    the one above, down to a grid of fewer than ``coarsest`` nodes a side.
    What ``LCP(..., hierarchy=...)`` takes: the multilevel method's coarse
    grids.  (Weights of ½ next to a narrower last cell, as if the coarse
    grids were uniform, cost the plate's multigrid dearly where N is not
    2^k − 1: CG on its W-cycle took 28 steps at N = 316 and 36 at 1000
    against 9–11 with the true weights; docs/dev-notes.md.)"""
    N = _grid_size(N)
    x = np.arange(1.0, N + 1.0)      # in fine grid steps; the boundary at 0 and N + 1
    out = []
    while x.size >= coarsest:
        p = _interpolation_1d(x, N + 1.0)
        out.append(sp.kron(p, p, format="csr"))
        x = x[1::2]
    return out


def _grid(N):
    h = 1.0 / (N + 1)
    x = h * np.arange(1, N + 1)
    X, Y = np.meshgrid(x, x, indexing="ij")
    return h, X.ravel(), Y.ravel()


def _manufactured(rng, n, frac_contact=0.4, frac_degenerate=0.1):
    """(z, w) complementary, with a fraction of indices where both are 0."""
    z = rng.uniform(0.5, 1.5, n)
    w = np.zeros(n)
    idx = rng.permutation(n)
    nc = int(frac_contact * n)
    nd = int(frac_degenerate * n)
    contact = idx[:nc]
    degenerate = idx[nc:nc + nd]
    z[contact] = 0.0
    w[contact] = rng.uniform(0.5, 1.5, nc)
    z[degenerate] = 0.0
    return z, w


#: The obstacle shapes ψ(x, y) [m] on the unit square.
OBSTACLES = {
    # a dome: contact on one disc
    "dome": lambda x, y: 0.3 - 2.0 * ((x - 0.5) ** 2 + (y - 0.5) ** 2),
    # a roof ridge along the diagonal: contact on a band with a kink in ψ
    "ridge": lambda x, y: 0.2 - np.abs(x - y),
    # three bumps of different heights: several contact regions, some that
    # merge or vanish as the load changes
    "bumps": lambda x, y: np.maximum.reduce([
        np.full_like(x, -0.5),
        0.15 - 8.0 * ((x - 0.3) ** 2 + (y - 0.3) ** 2),
        0.20 - 8.0 * ((x - 0.7) ** 2 + (y - 0.4) ** 2),
        0.10 - 8.0 * ((x - 0.5) ** 2 + (y - 0.75) ** 2)]),
    # skew terraces with a pit: flat steps (contact on whole treads or
    # only their edges) and a hole where nothing touches — a shape the
    # multigrid's stopping rule was checked on, not tuned on
    "terraces": lambda x, y: np.where((x - 0.3) ** 2 + (y - 0.7) ** 2 < 0.01, -0.6,
                                      0.08 * np.floor(4.0 * (0.6 * x + 0.8 * y)) - 0.15),
    # a tilted egg-crate: many small contact patches on a slope
    "crate": lambda x, y: (0.1 * np.sin(5.0 * np.pi * (0.9 * x + 0.44 * y))
                           * np.sin(5.0 * np.pi * (0.9 * y - 0.44 * x)) + 0.05 * (x - 0.5)),
}


def membrane(N: int, *, tension: float = 1.0, load: float = -8.0, obstacle: str = "dome",
             degenerate: bool = False, scale: float = 1.0, seed: int = 0) -> LCP:
    """Membrane obstacle problem on an N x N grid (n = N² unknowns z = u − ψ).

    Default data: tension 1 N/m, pressure −8 N/m² (downwards), obstacle the
    dome ψ = 0.3 − 2((x − ½)² + (y − ½)²) [m]: the membrane drapes over it
    and rests on a disc of about 38 % of the nodes.  ``obstacle`` picks
    another shape of :data:`OBSTACLES` ("ridge", "bumps")."""
    N = _grid_size(N)
    h, x, y = _grid(N)
    K = (scale * tension / h ** 2) * laplacian(N)
    return _obstacle_lcp(K.tocsc(), x, y, scale * load, obstacle, degenerate, seed, N)


def plate(N: int, *, rigidity: float = 1.0, load: float = -1000.0, obstacle: str = "dome",
          degenerate: bool = False, scale: float = 1.0, seed: int = 0) -> LCP:
    """Plate obstacle problem (13-point biharmonic) on an N x N grid."""
    N = _grid_size(N)
    h, x, y = _grid(N)
    L = laplacian(N) / h ** 2
    K = (scale * rigidity) * (L @ L)
    return _obstacle_lcp(sp.csc_matrix(K), x, y, scale * load, obstacle, degenerate, seed, N)


def _obstacle_lcp(K, x, y, load, obstacle, degenerate, seed, N):
    if obstacle not in OBSTACLES:
        raise InvalidProblemError(f"unknown obstacle {obstacle!r}; the shapes are "
                                  + ", ".join(OBSTACLES))
    n = x.size
    if degenerate:
        z, w = _manufactured(np.random.default_rng(seed), n)
        # a load that makes this (z, w) the solution: q = w − K z
        lcp = LCP(K, w - K @ z, hierarchy=grid_hierarchy(N) or None)
    else:
        psi = OBSTACLES[obstacle](x, y)
        f = np.full(n, float(load))
        # each q_i is a difference of K ψ and f: the certificate judges it on that scale
        lcp = LCP(K, K @ psi - f, q_terms=np.abs(K) @ np.abs(psi) + np.abs(f),
                  hierarchy=grid_hierarchy(N) or None)
    lcp.structure.declare_spd()   # a Dirichlet Laplacian and its square: SPD by construction
    return lcp


def _hex_stiffness(dx, dy, dz, E, nu) -> np.ndarray:
    """24 x 24 stiffness of a trilinear brick (2x2x2 Gauss), dofs node-major
    (u_x, u_y, u_z per node), nodes in the order (i, j, k) ∈ {0,1}³ lexicographic."""
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    C = np.zeros((6, 6))
    C[:3, :3] = lam
    C[np.arange(3), np.arange(3)] += 2 * mu
    C[np.arange(3, 6), np.arange(3, 6)] = mu
    corners = np.array([(i, j, k) for i in (0, 1) for j in (0, 1) for k in (0, 1)], float)
    g = 0.5 - 0.5 / np.sqrt(3.0), 0.5 + 0.5 / np.sqrt(3.0)
    Ke = np.zeros((24, 24))
    for gx in g:
        for gy in g:
            for gz in g:
                p = np.array([gx, gy, gz])
                # d N_a / d(xi) for N_a = Π (c p + (1 − c)(1 − p))
                fac = np.where(corners == 1, p, 1 - p)           # (8, 3)
                sgn = np.where(corners == 1, 1.0, -1.0)
                dN = np.empty((8, 3))
                for d in range(3):
                    others = [e for e in range(3) if e != d]
                    dN[:, d] = sgn[:, d] * fac[:, others[0]] * fac[:, others[1]]
                dN /= np.array([dx, dy, dz])
                B = np.zeros((6, 24))
                B[0, 0::3], B[1, 1::3], B[2, 2::3] = dN[:, 0], dN[:, 1], dN[:, 2]
                B[3, 0::3], B[3, 1::3] = dN[:, 1], dN[:, 0]
                B[4, 1::3], B[4, 2::3] = dN[:, 2], dN[:, 1]
                B[5, 0::3], B[5, 2::3] = dN[:, 2], dN[:, 0]
                Ke += B.T @ C @ B * (dx * dy * dz / 8.0)
    return Ke


def signorini(nx: int, ny: int | None = None, nz: int | None = None, *, E: float = 210e9,
              nu: float = 0.3, size=(1.0, 1.0, 0.5), press: float = 1e-3,
              curvature: float = 0.02, scale: float = 1.0):
    """The block of the module docstring: returns ``(problem, info)`` with a
    ``qpsolvers.Problem`` (P = K on the free dofs, lb on the bottom nodes'
    u_z only) and ``info`` (``contact``: indices of the bounded dofs,
    ``gap``: g at them, ``shape``)."""
    from qpsolvers import Problem

    nx = _grid_size(nx)
    ny = nx if ny is None else _grid_size(ny)
    nz = max(1, (nx + 1) // 2) if nz is None else int(nz)
    if nz < 1:
        raise InvalidProblemError(f"nz must be >= 1; got {nz}")
    a, b, c = (float(v) for v in size)
    dx, dy, dz = a / nx, b / ny, c / nz
    Ke = scale * _hex_stiffness(dx, dy, dz, E, nu)
    # node (i, j, k) -> number; element corners in _hex_stiffness's order
    node = np.arange((nx + 1) * (ny + 1) * (nz + 1)).reshape(nx + 1, ny + 1, nz + 1)
    corners = [(i, j, k) for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    conn = np.stack([node[i:nx + i, j:ny + j, k:nz + k].ravel() for i, j, k in corners], axis=1)
    dofs = (3 * conn[:, :, None] + np.arange(3)).reshape(-1, 24)            # (elements, 24)
    ndof = 3 * node.size
    rows = np.repeat(dofs, 24, axis=1).ravel()
    cols = np.tile(dofs, (1, 24)).ravel()
    vals = np.tile(Ke.ravel(), dofs.shape[0])
    K = sp.csr_matrix((vals, (rows, cols)), shape=(ndof, ndof))
    top = node[:, :, nz].ravel()
    prescribed = np.zeros(ndof, bool)
    prescribed[(3 * top[:, None] + np.arange(3)).ravel()] = True
    u_top = np.zeros(ndof)
    u_top[3 * top + 2] = -press
    free = np.flatnonzero(~prescribed)
    K_free_rows = K[free]
    f = -(K_free_rows[:, np.flatnonzero(prescribed)] @ u_top[prescribed])
    bottom = node[:, :, 0].ravel()
    xb = dx * (bottom // ((ny + 1) * (nz + 1)))
    yb = dy * ((bottom // (nz + 1)) % (ny + 1))
    gap = curvature * ((xb - a / 2) ** 2 + (yb - b / 2) ** 2)
    position = np.full(ndof, -1)
    position[free] = np.arange(free.size)
    contact = position[3 * bottom + 2]
    lb = np.full(free.size, -np.inf)
    lb[contact] = -gap
    problem = Problem(K_free_rows[:, free].tocsc(), -f, lb=lb)
    return problem, {"contact": contact, "gap": gap, "shape": (nx, ny, nz), "K": K,
                     "free": free}


_SIZES = {"small": (12, 8, 6), "medium": (60, 40, 14), "large": (200, 100, 24)}


def instances(size: str = "small", hardness: str = "easy", seed: int = 0):
    """``qpcontact compare`` instances: membrane, plate and the 3-D block at
    three sizes ("hard": degenerate obstacle problems, stiffness scaled by
    1e9 against loads of order 1)."""
    from qpcontact.cases.instance import Instance

    nm, npl, nb = _SIZES[size]
    if hardness == "hard":
        return [Instance(f"meshes/membrane-{nm}x{nm}/degenerate-1e9", "meshes", f"n={nm * nm}",
                         membrane(nm, degenerate=True, scale=1e9, seed=seed)),
                Instance(f"meshes/plate-{npl}x{npl}/degenerate", "meshes", f"n={npl * npl}",
                         plate(npl, degenerate=True, seed=seed))]
    block, _ = signorini(nb)
    return [Instance(f"meshes/membrane-{nm}x{nm}", "meshes", f"n={nm * nm}", membrane(nm)),
            Instance(f"meshes/plate-{npl}x{npl}", "meshes", f"n={npl * npl}", plate(npl)),
            Instance(f"meshes/signorini-{nb}", "meshes", f"n={block.P.shape[0]}", block)]
