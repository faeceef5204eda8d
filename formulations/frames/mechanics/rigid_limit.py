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

#: a last certified equilibrium (to the checks' tolerance) may lie this far
#: above the exact limit of the proof's motion: rounding, not a contradiction
ABOVE = 1e-9


def rigid_motions(frame, b):
    """G (params x dofs): the whole frame's rigid motions, exact in floats
    (entries 0, ±1 and the nodes' coordinates); a motion that moves a dof
    held by a bilateral support or a spring has its row zeroed (a planar
    frame built in space, held out of its plane, keeps the plane's three
    motions); None where no motion is left, or the nodes' axes are turned."""
    if b.get("Tn") is not None:
        return None
    G = all_rigid_motions(frame, b)
    held = np.asarray(b["fixed"], bool) | (np.asarray(b["springs"]) != 0)
    if held.any():
        G[np.any(G[:, held] != 0, axis=1)] = 0.0
    return G if np.any(G) else None


def all_rigid_motions(frame, b):
    """G of :func:`rigid_motions` before the held dofs are considered."""
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


def static_limit(frame, b, const, var, G=None, rays=None):
    """(p*, motion): the largest p such that contact forces in their cones
    balance F(const) + p F(var) (one LP), and the LP's dual there — the
    rigid motion's parameters c (floats) in which the rays do no negative
    work and the variable loads unit work; (inf, None) if unbounded, None
    where the frame is held or the LP fails.  ``G``, ``rays``: computed
    here if not given."""
    from scipy.optimize import linprog

    G = rigid_motions(frame, b) if G is None else G
    rays = contact_rays(b) if rays is None else rays
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
        return np.inf, None
    if res.status != 0:
        return None
    # the dual y of the equations: every ray's work in -y is >= 0 and the
    # variable loads' is 1 (the free column p), so -y is the motion
    motion = getattr(getattr(res, "eqlin", None), "marginals", None)
    return float(res.x[-1]), (None if motion is None else -np.asarray(motion, float))


def prove_beyond(frame, b, const, var, p, G=None, rays=None):
    """A rigid motion proving that no equilibrium exists at F(const) + p
    F(var), checked in rationals (the module docstring): a dict with the
    motion's parameters, its exact work, and per contact its normal
    opening and tangential motion (floats, for the words); None if none
    is found or it does not check."""
    G = rigid_motions(frame, b) if G is None else G
    rays = contact_rays(b) if rays is None else rays
    if G is None or rays is None:
        return None
    F = b["F"] @ (contact_lcp.factors(b, const) + p * contact_lcp.factors(b, var))
    c = balanced_motion(G, ray_works(G, b, rays), G @ F)
    return None if c is None else exact_check(frame, b, G, F, rays, c)


def balanced_motion(G, A, gF, cost=None):
    """The parameters c of a rigid motion G'c with A c >= 0 (each row a
    contact ray's work) and unit load work (G F)·c = 1, from one LP — with
    ``cost``·c least where given — or None where there is none; the
    parameters of motions G has zeroed (held dofs) are 0."""
    from scipy.optimize import linprog

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
    objective = np.zeros(G.shape[0])
    if cost is not None:
        objective = cost / col
        objective = objective / max(np.abs(objective).max(), 1e-300)
    res = linprog(objective, A_ub=-As / row[:, None], b_ub=np.zeros(len(A)),
                  A_eq=gs[None, :], b_eq=[1.0], bounds=[(None, None)] * G.shape[0],
                  method="highs")
    if res.status != 0:
        return None
    return np.where(np.any(G != 0, axis=1), res.x / col, 0.0)


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
    phi_f = np.array([float(v) for v in phi])
    proof = motion_words(frame, b, rays, phi_f, [[float(w) for w in ws] for ws in per_ray], c)
    proof["work"] = work
    return proof


def motion_words(frame, b, rays, phi, per_ray, c) -> dict:
    """The proof's record for the words: the motion's parameters, per
    contact its normal opening and tangential motion, the axis it turns
    about (floats: ``phi`` the nodes' motion, ``per_ray`` each contact's
    rays' works)."""
    Hd = sp.csc_matrix(b["H"])
    pos = contact_lcp.layout(b)
    # a frictionless contact has no tangential link, but the motion slides
    # along it all the same (a beam riding up a frictionless V-groove's
    # faces translates along them: it does not tip over about them)
    _, tangents, _ = frame.kind.release_directions(frame, b)
    along = [np.asarray(t.T @ phi, float) for t in tangents]
    opening, sliding = [], []
    size = float(np.abs(phi).max(initial=0.0)) or 1.0
    for ci, ((links, _), ws) in enumerate(zip(rays, per_ray)):
        m = [float((Hd[:, [li]].T @ phi)[0]) for li in links]
        # the slip in the contact's tangents: (t1, t2) in space — one of
        # them absent where a bilateral support holds it — or (t,) in a plane
        kinds = [k for k in ("t1", "t2") if k in pos[ci]]
        s = ([m[1 + kinds.index(k)] if k in kinds else 0.0 for k in ("t1", "t2")]
             if kinds else m[1:] + [0.0] * (2 - len(m[1:])))
        if len(links) == 1:
            s = [float(a[ci]) for a in along] + [0.0] * (2 - len(along))
        # a contact whose tightest ray does no work slides on its polygon
        # (or stays): its opening read as Coulomb's f|s| for the words
        tight = float(min(ws)) <= 1e-9 * size
        opening.append(frame.contacts[ci].friction * float(np.hypot(*s)) if tight else m[0])
        sliding.append(s)
    return {"params": [float(x) for x in c], "turn": turn_words(frame, [float(x) for x in c]),
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
    """(p_hi, proof): a load above which a rigid motion proves that no
    equilibrium exists — first the LP's own dual motion made exact on its
    active rays (:func:`vertex_proof`: p_hi the next float above the exact
    limit of that motion), else the first margin above the LP's static
    limit at which the dual LP's motion checks; (None, None) where none is
    found.  ``p_lo``: the last certified equilibrium, which the proof must
    lie above.  The rays and their rational vertices are computed once."""
    G = rigid_motions(frame, b)
    rays = contact_rays(b)
    if G is None or rays is None:
        return None, None
    found = static_limit(frame, b, const, var, G, rays)
    if found is None or not np.isfinite(found[0]):
        return None, None
    p_star, motion = found
    if motion is not None:
        proof = vertex_proof(frame, b, const, var, G, rays, motion)
        if proof is not None and proof["p_hi"] <= p_lo <= proof["p_exact"] * (1 + ABOVE):
            # the last equilibrium, certified to the checks' tolerance, lies
            # a rounding above the exact limit: the proof holds for every p
            # above p_exact, so just above p_lo too
            import math

            proof["p_hi"] = math.nextafter(p_lo, math.inf)
            proof["work"] = proof["work_c"] + Fraction(proof["p_hi"]) * proof["work_v"]
        if proof is not None and proof["p_hi"] > p_lo:
            return proof["p_hi"], proof
    base = max(p_star, p_lo)
    for margin in MARGINS:
        p_hi = base + margin * max(abs(base), 1e-300)
        proof = prove_beyond(frame, b, const, var, p_hi, G, rays)
        if proof is not None:
            return p_hi, proof
    return None, None


def exact_rows(G, b, rays):
    """Per ray, its work in each of the rigid motions G's rows, in
    Fractions: the exact linear map from a motion's parameters to the
    rays' works (the model as stored)."""
    Hd = sp.csc_matrix(b["H"])
    Gq = {}
    rows = []
    for links, verts in rays:
        per_link = []
        for li in links:
            lo, hi = Hd.indptr[li], Hd.indptr[li + 1]
            m = [Fraction(0)] * G.shape[0]
            for i, v in zip(Hd.indices[lo:hi], Hd.data[lo:hi]):
                for k in range(G.shape[0]):
                    if G[k, i]:
                        key = (k, i)
                        if key not in Gq:
                            Gq[key] = Fraction(G[k, i])
                        m[k] += Fraction(v) * Gq[key]
            per_link.append(m)
        for vert in verts:
            rows.append([sum((a * pl[k] for a, pl in zip(vert, per_link)), Fraction(0))
                         for k in range(G.shape[0])])
    return rows


def per_contact(rows, rays) -> list:
    """``rows`` (one per ray, in order) split per contact."""
    out, at = [], 0
    for _, verts in rays:
        out.append(rows[at:at + len(verts)])
        at += len(verts)
    return out


def load_work(G, F) -> list:
    """The work of the loads F (floats, read as rationals) in each rigid
    motion of G: exact."""
    nz = np.flatnonzero(F)
    return [sum((Fraction(G[k, i]) * Fraction(F[i]) for i in nz if G[k, i]), Fraction(0))
            for k in range(G.shape[0])]


def solve_exact(A, rhs):
    """x with A x = rhs (square, Fractions) by Gauss–Jordan; None if singular."""
    n = len(A)
    M = [list(row) + [r] for row, r in zip(A, rhs)]
    for col in range(n):
        piv = next((r for r in range(col, n) if M[r][col] != 0), None)
        if piv is None:
            return None
        M[col], M[piv] = M[piv], M[col]
        inv = 1 / M[col][col]
        M[col] = [v * inv for v in M[col]]
        for r in range(n):
            if r != col and M[r][col] != 0:
                f = M[r][col]
                M[r] = [a - f * c for a, c in zip(M[r], M[col])]
    return [M[r][n] for r in range(n)]


def vertex_proof(frame, b, const, var, G, rays, motion):
    """The LP's dual motion made exact: the rays it leaves at (nearly)
    zero work are held at exactly zero, the variable loads' work at one,
    and any parameters these leave free at the LP's values; the motion,
    solved in rationals, must give every ray non-negative work exactly.
    Then the loads' work (F_c + p F_v)·φ is positive for every p above
    p_exact = −F_c·φ / F_v·φ, so no equilibrium exists there whatever the
    members and pads: p_hi is the next float above p_exact.  Why: the LP's
    optimum stands on rays that do no work in its motion (the pads that
    stay put or slide exactly along a vertex), and in floats those come
    out at ±1e-17 — a margin above p* then had to outweigh the LP's
    tolerances (a table tipping about its far legs on inscribed polygons
    was proved only 1e-6 above its limit).  None where the motion fails."""
    import math

    motion = np.asarray(motion, float)
    A = ray_works(G, b, rays)
    size = np.abs(A).max(axis=1) * np.abs(motion).max()
    if not np.all(np.isfinite(motion)) or not size.max() > 0:
        return None
    active = np.flatnonzero(A @ motion <= 1e-7 * np.maximum(size, 1e-300))
    npar = G.shape[0]
    Fc = b["F"] @ contact_lcp.factors(b, const)
    Fv = b["F"] @ contact_lcp.factors(b, var)
    gv = G @ Fv
    # independent active rows, and the normalisation, by QR with pivoting
    import scipy.linalg

    rows_f = np.vstack([A[active] / np.maximum(size[active, None], 1e-300),
                        gv[None, :] / max(np.abs(gv).max(), 1e-300)])
    _, R, piv = scipy.linalg.qr(rows_f.T, pivoting=True, mode="economic")
    diag = np.abs(np.diag(R))
    rank = int(np.sum(diag > 1e-9 * diag.max())) if diag.size else 0
    chosen = [int(i) for i in piv[:rank]]
    if len(active) not in chosen:        # the normalisation must be in the system
        chosen = chosen[:rank - 1] + [len(active)] if rank == npar else chosen + [len(active)]
    exact = exact_rows(G, b, rays)
    wv = load_work(G, Fv)
    system, rhs = [], []
    for i in chosen:
        if i == len(active):
            system.append(wv)
            rhs.append(Fraction(1))
        else:
            system.append(exact[active[i]])
            rhs.append(Fraction(0))
    # parameters left free: pinned at the LP's motion (normalised); those of
    # held motions (zero rows of G) at zero
    scale_v = float(gv @ motion)
    if not scale_v > 0:
        return None
    motion = np.where(np.any(G != 0, axis=1), motion, 0.0)
    basis = np.array([[float(x) for x in row] for row in system])
    for k in sorted(range(npar), key=lambda k: (np.any(G[k] != 0), -abs(motion[k]))):
        if len(system) >= npar:
            break
        trial = np.vstack([basis, np.eye(npar)[k]])
        if np.linalg.matrix_rank(trial, tol=1e-9 * np.abs(trial).max()) == len(system) + 1:
            unit = [Fraction(0)] * npar
            unit[k] = Fraction(1)
            system.append(unit)
            rhs.append(Fraction(motion[k] / scale_v))
            basis = trial
    if len(system) != npar:
        return None
    c = solve_exact(system, rhs)
    if c is None:
        return None
    per_ray_all = [sum((a * x for a, x in zip(row, c)), Fraction(0)) for row in exact]
    worst = min(per_ray_all)
    if worst < 0:
        # an active ray dependent in floats on the others (the LP's basis)
        # is not exactly so in rationals: lift the motion along the
        # contacts' normals (every ray gains) by the least that restores it
        normals = np.array([np.asarray(b["H"][:, links[0]].toarray()).ravel()
                            for links, _ in rays])
        lift, *_ = np.linalg.lstsq(G.T, normals.sum(axis=0), rcond=None)
        lift = [Fraction(v) for v in lift]
        gains = [sum((a * x for a, x in zip(row, lift)), Fraction(0)) for row in exact]
        if not min(gains) > 0:
            return None
        delta = 2 * (-worst) / min(gains)
        c = [x + delta * y for x, y in zip(c, lift)]
        per_ray_all = [sum((a * x for a, x in zip(row, c)), Fraction(0)) for row in exact]
        if min(per_ray_all) < 0:
            return None
    work_v = sum((a * x for a, x in zip(wv, c)), Fraction(0))
    work_c = sum((a * x for a, x in zip(load_work(G, Fc), c)), Fraction(0))
    if not work_v > 0:
        return None
    p_exact = -work_c / work_v
    p_hi = math.nextafter(float(p_exact), math.inf)
    while Fraction(p_hi) <= p_exact:
        p_hi = math.nextafter(p_hi, math.inf)
    cf = np.array([float(x) for x in c])
    works = [[float(sum((a * x for a, x in zip(row, c)), Fraction(0))) for row in rows]
             for rows in per_contact(exact, rays)]
    proof = motion_words(frame, b, rays, G.T @ cf, works, c)
    proof.update(p_hi=p_hi, work=work_c + Fraction(p_hi) * work_v, p_exact=p_exact,
                 work_c=work_c, work_v=work_v)
    return proof
