"""The rigid-body limit of a frame that rests on its contacts, with a proof
in rational arithmetic that no equilibrium exists beyond it.

Mechanics.  A frame held by nothing but its contacts (no bilateral
supports, no springs to the ground) has the rigid motions of the whole
body, φ = t + θ × x at each node's position x with rotation θ (in the
plane: (t_x − θ y, t_y + θ x, θ)), in the null space of its stiffness:
every member's element stiffness annihilates them exactly.  Virtual work
on any equilibrium K u = F + H X then gives

    φᵀ F + Σ_c X_c · (H_cᵀ φ) = φᵀ K u = 0.

If the loads do positive work in φ (φᵀ F > 0) while every contact force
the friction polygon allows does none or negative work against it —
X_c · (H_cᵀ φ) ≥ 0 for each extreme ray X_c of contact c's cone (the
normal alone for a frictionless contact, X_n = 1 with the tangential part
at each vertex of the polygon otherwise) — no contact forces can balance
the loads: no equilibrium exists, whatever the members' stiffness, the
contacts' flexibility or the load path.  That is the Farkas alternative of
the static problem "contact forces in their cones whose resultant and
moment balance the loads", which an LP decides.

Proof.  The largest load factor p* that a statically admissible set of
contact forces carries is one LP (its variables: the rays' multipliers).
Just above it, at p_hi = p*(1 + δ), the dual LP gives the motion's six
(three) parameters c in floating point; the motion is then checked
exactly — c, the nodes' coordinates, the contacts' directions, the
polygons' facets and the loads are the stored floats read as rationals,
the polygon's vertices are intersections of its adjacent facets computed
in rationals, and every inequality above is evaluated in
``fractions.Fraction``.  Rounding can leave an active inequality at −1e-17:
the motion is then lifted along the contacts' normals by the least
amount that makes every inequality hold (a lift opens every contact), and
the work is checked again after the lift.  The proof is exact for the
model as stored; p* itself is only the LP's floating-point optimum, so
[p_lo, p_hi] is a bracket — p_lo a certified equilibrium, p_hi a proof.

Where the frame is held by bilateral supports or springs, its rigid
motions are not free and this route says nothing (None).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import scipy.sparse as sp

from . import contact_lcp

#: relative steps above the LP's limit at which a proof is tried
MARGINS = (1e-10, 1e-9, 1e-8, 1e-7)


def rigid_motions(frame, b):
    """G (params x dofs): the whole frame's rigid motions, exact in floats
    (entries 0, ±1 and the nodes' coordinates); None where the frame is
    held by bilateral supports or springs, or its nodes' axes are turned."""
    if b["fixed"].any() or np.any(b["springs"]) or b.get("Tn") is not None:
        return None
    names = b["names"]
    xyz = np.array([frame.nodes[n] for n in names], float)
    nd = len(frame.DOFS)
    N = nd * len(names)
    if nd == 3:         # plane: ux, uy, rz; params tx, ty, θ
        G = np.zeros((3, N))
        G[0, 0::3] = 1.0
        G[1, 1::3] = 1.0
        G[2, 0::3], G[2, 1::3], G[2, 2::3] = -xyz[:, 1], xyz[:, 0], 1.0
        return G
    G = np.zeros((6, N))   # space: ux, uy, uz, rx, ry, rz; params t (3), θ (3)
    for a in range(3):
        G[a, a::6] = 1.0
        G[3 + a, 3 + a::6] = 1.0
    x, y, z = xyz[:, 0], xyz[:, 1], xyz[:, 2]
    # θ × x: θx (0, -z, y), θy (z, 0, -x), θz (-y, x, 0)
    G[3, 1::6], G[3, 2::6] = -z, y
    G[4, 0::6], G[4, 2::6] = z, -x
    G[5, 0::6], G[5, 1::6] = -y, x
    return G


def contact_rays(b):
    """Per contact: (its links, its cone's extreme rays in those links'
    coordinates as rows of Fractions), from the facets w = W X of the
    LCP's maps (the model as stored)."""
    P, W, g, fric = b["maps"]
    W = sp.csr_matrix(W)
    pos = contact_lcp.layout(b)
    rays = []
    for ci in sorted(pos):
        links = [pos[ci][k] for k in ("n", "t1", "t2", "t") if k in pos[ci]]
        n_link, t_links = links[0], links[1:]
        if not t_links:
            rays.append((links, [(Fraction(1),)]))
            continue
        facets = []
        for row in range(W.shape[0]):
            cols = W.indices[W.indptr[row]:W.indptr[row + 1]]
            vals = W.data[W.indptr[row]:W.indptr[row + 1]]
            if set(cols) <= set(links) and n_link in cols and len(cols) > 1:
                coef = dict(zip(cols, vals))
                facets.append((Fraction(coef[n_link]),
                               [Fraction(coef.get(t, 0.0)) for t in t_links]))
        if len(t_links) == 1:
            # f + d v >= 0 on each side: vertices v = -f/d
            rays.append((links, [(Fraction(1), -f / d[0]) for f, d in facets if d[0] != 0]))
            continue
        facets.sort(key=lambda fd: np.arctan2(float(fd[1][1]), float(fd[1][0])))
        verts = []
        for (f1, d1), (f2, d2) in zip(facets, facets[1:] + facets[:1]):
            det = d1[0] * d2[1] - d1[1] * d2[0]
            if det == 0:
                return None
            # d1·v = -f1, d2·v = -f2
            vx = (-f1 * d2[1] + f2 * d1[1]) / det
            vy = (-f2 * d1[0] + f1 * d2[0]) / det
            verts.append((Fraction(1), vx, vy))
        rays.append((links, verts))
    return rays


def ray_works(G, b, rays) -> np.ndarray:
    """(rays, params): the work of each extreme ray's contact force in each
    rigid motion of G (floats, for the LPs)."""
    Hd = sp.csr_matrix(b["H"])
    rows = []
    for links, verts in rays:
        Hc = Hd[:, links].toarray()
        rows += [G @ (Hc @ np.array([float(a) for a in v])) for v in verts]
    return np.array(rows).reshape(len(rows), G.shape[0])


def static_limit(frame, b, const, var):
    """The largest p such that contact forces in their cones balance
    F(const) + p F(var) (one LP; inf if unbounded, None where the frame is
    held or the LP fails)."""
    from scipy.optimize import linprog

    G = rigid_motions(frame, b)
    rays = contact_rays(b)
    if G is None or rays is None:
        return None
    Fc = b["F"] @ contact_lcp.factors(b, const)
    Fv = b["F"] @ contact_lcp.factors(b, var)
    A = np.column_stack([ray_works(G, b, rays).T, G @ Fv])  # Σ μ (G H ray) + p G F_v = -G F_c
    c = np.zeros(A.shape[1])
    c[-1] = -1.0
    scale = max(np.abs(A).max(), 1e-300)
    res = linprog(c, A_eq=A / scale, b_eq=-(G @ Fc) / scale,
                  bounds=[(0, None)] * (A.shape[1] - 1) + [(None, None)], method="highs")
    if res.status == 3:
        return np.inf
    return float(res.x[-1]) if res.status == 0 else None


def prove_beyond(frame, b, const, var, p):
    """A rigid motion proving that no equilibrium exists at F(const) + p
    F(var), checked in rationals (the module docstring): a dict with the
    motion's parameters, its exact work, and per contact its normal
    opening and tangential motion (floats, for the words); None if none
    is found or it does not check."""
    from scipy.optimize import linprog

    G = rigid_motions(frame, b)
    rays = contact_rays(b)
    if G is None or rays is None:
        return None
    F = b["F"] @ (contact_lcp.factors(b, const) + p * contact_lcp.factors(b, var))
    A = ray_works(G, b, rays)                # A c >= 0 for every ray, (G F)·c = 1
    gF = G @ F
    # balanced for the LP's tolerances: each parameter by its largest
    # lever (a rotation's moves grow with the frame's size, a translation's
    # do not), each ray's row by its size — else a tower's rotation
    # "satisfied" every ray to 1e-10 of the scaled rows and failed the
    # exact check by 3e-5
    col = np.maximum(np.abs(A).max(axis=0, initial=0.0), np.abs(gF))
    col[col == 0] = 1.0
    As, gs = A / col, gF / col
    row = np.abs(As).max(axis=1, initial=0.0)
    row[row == 0] = 1.0
    res = linprog(np.zeros(G.shape[0]), A_ub=-As / row[:, None], b_ub=np.zeros(len(A)),
                  A_eq=gs[None, :], b_eq=[1.0], bounds=[(None, None)] * G.shape[0],
                  method="highs")
    if res.status != 0:
        return None
    return exact_check(frame, b, G, F, rays, res.x / col)


def exact_check(frame, b, G, F, rays, c):
    """The motion G'c checked in rationals, lifted along the normals if
    rounding left an inequality below zero; None if it fails."""
    Gq = [[Fraction(v) for v in row] for row in G]
    cq = [Fraction(v) for v in c]

    def motion(params):
        return [sum((Gq[k][i] * params[k] for k in range(len(params))), Fraction(0))
                for i in range(G.shape[1])]

    Hd = sp.csc_matrix(b["H"])

    def link_motion(phi, link):
        lo, hi = Hd.indptr[link], Hd.indptr[link + 1]
        return sum((Fraction(v) * phi[i] for i, v in zip(Hd.indices[lo:hi], Hd.data[lo:hi])),
                   Fraction(0))

    def works(phi):
        out = []
        for links, verts in rays:
            m = [link_motion(phi, li) for li in links]
            out.append([sum((a * mm for a, mm in zip(v, m)), Fraction(0)) for v in verts])
        return out

    Fq = [Fraction(v) for v in F]
    phi = motion(cq)
    work = sum((f * p for f, p in zip(Fq, phi) if f), Fraction(0))
    if work <= 0:
        return None
    per_ray = works(phi)
    worst = min((w for ws in per_ray for w in ws), default=Fraction(0))
    if worst < 0:
        # lift: translate along the contacts' mean normal (every ray's
        # normal part is 1, so a lift opens every contact)
        normals = np.array([np.asarray(b["H"][:, links[0]].toarray()).ravel() for links, _ in rays])
        up = normals.sum(axis=0)
        lift_params, *_ = np.linalg.lstsq(G.T, up, rcond=None)
        lift = motion([Fraction(v) for v in lift_params])
        gains = works(lift)
        least = min((w for ws in gains for w in ws), default=Fraction(0))
        if least <= 0:
            return None
        delta = 2 * (-worst) / least
        phi = [p + delta * q for p, q in zip(phi, lift)]
        work = sum((f * p for f, p in zip(Fq, phi) if f), Fraction(0))
        per_ray = works(phi)
        if work <= 0 or min(w for ws in per_ray for w in ws) < 0:
            return None
    opening, sliding = [], []
    size = max(abs(float(v)) for v in phi) or 1.0
    for ci, ((links, _), ws) in enumerate(zip(rays, per_ray)):
        m = [float(link_motion(phi, li)) for li in links]
        s = m[1:] + [0.0] * (2 - len(m[1:]))
        # a contact whose tightest ray does no work slides on its polygon
        # (or stays): its opening read as Coulomb's f|s| for the words
        tight = float(min(ws)) <= 1e-9 * size
        opening.append(frame.contacts[ci].friction * float(np.hypot(*s)) if tight else m[0])
        sliding.append(s)
    return {"params": [float(x) for x in c], "work": work, "turn": turn_words(frame, c),
            "opening": np.array(opening), "sliding": np.array(sliding)}


def turn_words(frame, c) -> str:
    """Where the rigid motion turns the frame: the axis its rotation turns
    about (nothing where it is a translation)."""
    c = np.asarray(c, float)
    xyz = np.array(list(frame.nodes.values()), float)
    size = float(np.linalg.norm(np.ptp(xyz, axis=0))) or 1.0
    length = frame.units[1]
    if c.size == 3:
        t, th = c[:2], c[2]
        if abs(th) * size <= 1e-3 * np.linalg.norm(t):
            return ""
        x, y = -t[1] / th, t[0] / th
        return f"; the proof's motion turns about the point ({x:.4g}, {y:.4g}) {length}"
    t, th = c[:3], c[3:]
    if np.linalg.norm(th) * size <= 1e-3 * np.linalg.norm(t):
        return ""
    axis = th / np.linalg.norm(th)
    point = np.cross(th, t) / (th @ th)
    along = tuple(float(f"{v:.3g}") + 0.0 for v in axis)
    return (f"; the proof's motion turns about the axis through ({point[0]:.4g}, {point[1]:.4g}, "
            f"{point[2]:.4g}) {length} along {along}")


def limit_bracket(frame, b, const, var, p_lo):
    """(p_hi, proof): the first margin above the LP's static limit at which
    a rigid motion proves that no equilibrium exists; (None, None) where
    none is found.  ``p_lo``: the last certified equilibrium, which the
    proof must lie above."""
    p_star = static_limit(frame, b, const, var)
    if p_star is None or not np.isfinite(p_star):
        return None, None
    base = max(p_star, p_lo)
    for margin in MARGINS:
        p_hi = base + margin * max(abs(base), 1e-300)
        proof = prove_beyond(frame, b, const, var, p_hi)
        if proof is not None:
            return p_hi, proof
    return None, None
