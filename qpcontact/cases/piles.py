r"""Generated granular piles: frictional contact problems at the scale of the
contact community's collections, reproducible by seed.

The shared Siconos/FCLIB files stop at 2 020 contacts; real granular flows
and rigid-body piles have ten times more.  These generators build such
problems from the mechanics, one Moreau–Jean time step of a pile of rigid
bodies, so that the benchmark and the tests can reach them.

**2-D disc pile in a box** (:func:`disc_pile`).  Discs on a hexagonal
packing of spacing 2R (every other row shifted by R) between a floor and two
walls, radii R(1 − δξ) with ξ uniform in [0, 1) (default R = 1 cm,
δ = 0.02): every neighbour pair is a candidate contact with its own small
gap, about three contacts per disc.  W then has more rows (two per
contact) than the bodies have degrees of freedom (three per disc), so it is
*singular* — the forces in a pile are statically indeterminate, as in the
granular files.

**3-D sphere pile in a box** (:func:`sphere_pile`).  Spheres on a
face-centred cubic packing of spacing 2R, radii R(1 − δξ), in a box with a
floor and four walls; about six candidate contacts per sphere, three
unknowns each against six degrees of freedom per sphere: W is singular by
far, with many sliding contacts once the pile is agitated — the dense pile
on which fixed points and plain Newton stall.

**Mechanics** (both).  Bodies i with mass m_i = ρ V_i and inertia I_i (a disc
per unit length: m = ρπr², I = m r²/2 in kg·m²/m; a sphere: m = ρ 4πr³/3,
I = 2 m r²/5), velocities v = (translation, rotation).  A candidate contact
between bodies a and b (or a body and a wall) has its normal n pointing from
a to b, tangents t (2-D: t = (−n_y, n_x); 3-D: an orthonormal pair) and the
gap g >= 0 between the surfaces; it is kept when g <= ``gap`` · R.  The
relative velocity at the contact point, in (n, t) coordinates, is

    u = Hᵀ v,   Hᵀ rows:  n·(v_b − v_a),   t·(v_b + ω_b × (−r_b n)) − t·(v_a + ω_a × (r_a n)),

and one step of length h (Moreau–Jean, s) from velocities v⁻ under gravity
gives M v⁺ = M v⁻ + h f + H r with the impulses r (N·s, or N·s/m in 2-D), so

    u = W r + q,   W = Hᵀ M⁻¹ H,   q = Hᵀ (v⁻ + h M⁻¹ f) + g / h e_N,

the gap term letting a contact close within the step only by what it is
open.  M is diagonal, so W is formed exactly and stays sparse (contacts
that share a body).  v⁻ is the pile's agitation: each body gets a random
velocity of ``agitation`` · √(gR) (m/s) and a random spin, so that contacts
open, stick and slide in one problem.

Everything is drawn from ``numpy.random.default_rng(seed)``: one seed, one
problem, on every machine.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..core.options import check_seed
from ..core.errors import InvalidProblemError
from ..core.friction_problem import FrictionProblem

__all__ = ["Pile", "disc_pile", "sphere_pile", "GRAVITY"]

#: m/s²
GRAVITY = 9.81


@dataclass
class Pile:
    """A generated pile: its frictional contact problem and its geometry
    (``centers`` m, ``radii`` m, ``pairs`` the contacts' bodies, −1 for a
    wall, with the wall's index in ``walls``; ``box`` the container's size)."""

    problem: FrictionProblem
    centers: np.ndarray
    radii: np.ndarray
    pairs: np.ndarray
    box: tuple
    seed: int

    @property
    def n_contacts(self) -> int:
        return self.problem.n_contacts

    @property
    def n_bodies(self) -> int:
        return self.radii.size


def _check(name, value, low, high=np.inf, integer=False):
    ok = np.isfinite(value) and low <= value <= high and (not integer or value == int(value))
    if not ok:
        kind = "an integer" if integer else "a number"
        raise InvalidProblemError(f"{name} must be {kind} in [{low}, {high}]; got {value!r}")


def _check_common(n_contacts, mu, radius, polydispersity, gap, h, agitation, density):
    _check("n_contacts", n_contacts, 10, 10_000_000, integer=True)
    _check("mu", mu, 0.0)
    _check("polydispersity", polydispersity, 0.0, 0.5)
    for name, value in (("radius", radius), ("h", h), ("density", density)):
        _check(name, value, 1e-300)
    _check("gap", gap, 0.0, 1.0)
    _check("agitation", agitation, 0.0)


def _contacts(centers, radii, walls, max_gap):
    """Candidate contacts with gap <= max_gap: (a, b, normal a→b, gap), a = −1
    − wall index for a wall (walls: list of (point, outward normal into the box))."""
    from scipy.spatial import cKDTree

    tree = cKDTree(centers)
    pairs = tree.query_pairs(2 * radii.max() + max_gap, output_type="ndarray")
    a, b = pairs[:, 0], pairs[:, 1]
    d = centers[b] - centers[a]
    dist = np.linalg.norm(d, axis=1)
    gap = dist - radii[a] - radii[b]
    keep = gap <= max_gap
    a, b, n, gap = a[keep], b[keep], d[keep] / dist[keep, None], np.maximum(gap[keep], 0.0)
    A, B, N, G = [a], [b], [n], [gap]
    for w, (point, normal) in enumerate(walls):
        g = (centers - point) @ normal - radii
        near = np.flatnonzero(g <= max_gap)
        A.append(np.full(near.size, -1 - w))
        B.append(near)
        N.append(np.repeat(normal[None, :], near.size, axis=0))
        G.append(np.maximum(g[near], 0.0))
    a, b = np.concatenate(A), np.concatenate(B)
    order = np.lexsort((b, a))
    return a[order], b[order], np.concatenate(N)[order], np.concatenate(G)[order]


def _tangents(n):
    """Two unit tangents per 3-D normal (rows), orthonormal with it."""
    helper = np.where(np.abs(n[:, [0]]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    t1 = np.cross(n, helper)
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    return t1, np.cross(n, t1)


def _jacobian(a, b, n, radii, dim):
    """Hᵀ (m x n_dofs, sparse): rows (normal, tangents) per contact, columns
    (translation, rotation) per body (module docstring)."""
    nc = a.size
    dofs = 3 if dim == 2 else 6
    rows, cols, vals = [], [], []
    if dim == 2:
        frames = [n, np.column_stack([-n[:, 1], n[:, 0]])]
    else:
        frames = [n, *_tangents(n)]
    for side, body, sign in ((0, a, -1.0), (1, b, 1.0)):
        real = body >= 0
        k, bd = np.flatnonzero(real), body[real]
        # the contact point is at −r_b n from b's centre, at +r_a n from a's
        arm = (-1.0 if side == 1 else 1.0) * radii[bd][:, None] * n[k]
        for j, e in enumerate(frames):
            row = dim * k + j
            for c in range(dim):                     # translation: ±e
                rows.append(row)
                cols.append(dofs * bd + c)
                vals.append(sign * e[k, c])
            if dim == 2:                             # ω × arm = ω (−arm_y, arm_x)
                rows.append(row)
                cols.append(dofs * bd + 2)
                vals.append(sign * (e[k, 1] * arm[:, 0] - e[k, 0] * arm[:, 1]))
            else:                                    # e · (ω × arm) = ω · (arm × e)
                coeff = np.cross(arm, e[k])
                for c in range(3):
                    rows.append(row)
                    cols.append(dofs * bd + 3 + c)
                    vals.append(sign * coeff[:, c])
    rows = np.concatenate([np.broadcast_to(x, np.shape(v)) for x, v in zip(rows, vals)])
    cols = np.concatenate([np.broadcast_to(x, np.shape(v)) for x, v in zip(cols, vals)])
    return sp.csr_matrix((np.concatenate(vals), (rows, cols)),
                         shape=(dim * nc, dofs * radii.size))


def _step_problem(centers, radii, a, b, n, gap, dim, mu, h, density, agitation, rng, name):
    nb, dofs = radii.size, (3 if dim == 2 else 6)
    if dim == 2:
        mass = density * np.pi * radii ** 2
        inertia = 0.5 * mass * radii ** 2
        inv = np.column_stack([1 / mass, 1 / mass, 1 / inertia]).ravel()
    else:
        mass = density * 4.0 / 3.0 * np.pi * radii ** 3
        inertia = 0.4 * mass * radii ** 2
        inv = np.column_stack([np.repeat(1 / mass[:, None], 3, 1),
                               np.repeat(1 / inertia[:, None], 3, 1)]).ravel()
    Ht = _jacobian(a, b, n, radii, dim)
    W = sp.csr_matrix(Ht @ sp.diags(inv) @ Ht.T)
    W.sum_duplicates()
    speed = agitation * np.sqrt(GRAVITY * radii.mean())
    v = np.zeros((nb, dofs))
    v[:, :dim] = speed * rng.standard_normal((nb, dim))
    v[:, dim:] = speed / radii[:, None] * rng.standard_normal((nb, dofs - dim))
    v[:, dim - 1] -= h * GRAVITY                     # gravity along −y (2-D) or −z (3-D)
    q = Ht @ v.ravel()
    q[0::dim] += gap / h
    mu_arr = np.full(a.size, float(mu))
    prob = FrictionProblem(sp.csc_matrix(W), q, mu_arr, dim, name=name)
    # W in its factors: ip-lcp solves its Newton systems on the bodies' graph
    prob.delassus_factors = (sp.csr_matrix(Ht), inv)
    return prob


def disc_pile(n_contacts: int = 2000, *, seed: int = 0, mu: float = 0.3, columns=None,
              radius: float = 0.01, polydispersity: float = 0.02, gap: float = 0.05,
              h: float = 1e-2, agitation: float = 0.3, density: float = 2500.0) -> Pile:
    """A 2-D pile of discs in a box with about ``n_contacts`` contacts
    (module docstring).  ``columns`` discs on the floor (default: about
    √(n_contacts/6), a pile twice as tall as wide); ``radius`` R (m),
    ``polydispersity`` δ, ``gap`` the largest gap kept as a contact, in R;
    ``h`` the step (s); ``agitation`` the bodies' speed in √(gR);
    ``density`` kg/m³ (masses per metre of disc length)."""
    _check_common(n_contacts, mu, radius, polydispersity, gap, h, agitation, density)
    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    columns = int(columns or max(3, round(np.sqrt(n_contacts / 6.0))))
    _check("columns", columns, 3, integer=True)
    rows = max(2, round(n_contacts / (3.0 * columns - 1.0)))
    # a hexagonal packing of spacing 2R, every other row shifted by R
    I, J = np.meshgrid(np.arange(columns), np.arange(rows), indexing="xy")
    sites = np.column_stack([(2 * I + (J % 2)).ravel() * radius,
                             np.sqrt(3.0) * J.ravel() * radius])
    sites = sites[(J % 2 == 0).ravel() | (I < columns - 1).ravel()]
    radii = radius * (1.0 - polydispersity * rng.random(sites.shape[0]))
    centers = sites + radius
    width = 2 * radius * columns
    walls = [(np.zeros(2), np.array([0.0, 1.0])), (np.zeros(2), np.array([1.0, 0.0])),
             (np.array([width, 0.0]), np.array([-1.0, 0.0]))]
    a, b, n, g = _contacts(centers, radii, walls, gap * radius)
    # a wall contact: the wall is body a; its normal points into the box, a → b
    name = f"disc pile: {radii.size} discs, {a.size} contacts, seed {seed}"
    prob = _step_problem(centers, radii, a, b, n, g, 2, mu, h, density, agitation, rng, name)
    return Pile(prob, centers, radii, np.column_stack([a, b]), (width, centers[:, 1].max()),
                seed)


def sphere_pile(n_contacts: int = 500, *, seed: int = 0, mu: float = 0.5, layers=None,
                radius: float = 0.01, polydispersity: float = 0.02, gap: float = 0.05,
                h: float = 1e-2, agitation: float = 0.5, density: float = 2500.0) -> Pile:
    """A 3-D pile of spheres in a box with about ``n_contacts`` contacts
    (module docstring): a face-centred cubic packing of spacing 2R; see
    :func:`disc_pile` for the other parameters;
    ``layers`` the pile's height in cubic cells of four spheres (default:
    what makes about ``n_contacts``)."""
    _check_common(n_contacts, mu, radius, polydispersity, gap, h, agitation, density)
    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    # about five contacts per sphere, four spheres per cubic cell
    side = max(2, round((n_contacts / 20.0) ** (1.0 / 3.0)))
    height = layers or max(1, round(n_contacts / (20.0 * side * side)))
    _check("layers", height, 1, integer=True)
    s = 2.0 * radius                                        # FCC: 4 sites per cube of 2s/√2
    a0 = s * np.sqrt(2.0)
    X, Y, Z = np.meshgrid(np.arange(side), np.arange(side), np.arange(height), indexing="ij")
    base = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()]).astype(float)
    sites = np.concatenate([base, base + [0.5, 0.5, 0], base + [0.5, 0, 0.5],
                            base + [0, 0.5, 0.5]]) * a0
    radii = radius * (1.0 - polydispersity * rng.random(sites.shape[0]))
    centers = sites + radius
    # the floor under the lowest layer, walls around
    centers[:, 2] -= (centers[:, 2] - radii).min()
    lo, hi = (centers - radii[:, None]).min(0), (centers + radii[:, None]).max(0)
    walls = [(np.array([0.0, 0.0, lo[2]]), np.array([0.0, 0.0, 1.0]))]
    for axis in (0, 1):
        e = np.zeros(3)
        e[axis] = 1.0
        p_lo, p_hi = np.zeros(3), np.zeros(3)
        p_lo[axis], p_hi[axis] = lo[axis], hi[axis]
        walls += [(p_lo, e), (p_hi, -e)]
    a, b, n, g = _contacts(centers, radii, walls, gap * radius)
    name = f"sphere pile: {radii.size} spheres, {a.size} contacts, seed {seed}"
    prob = _step_problem(centers, radii, a, b, n, g, 3, mu, h, density, agitation, rng, name)
    return Pile(prob, centers, radii, np.column_stack([a, b]), tuple(hi - lo), seed)
