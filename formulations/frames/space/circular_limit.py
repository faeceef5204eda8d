"""The rigid-body limit of a space frame that rests on its contacts, on
Coulomb's circular cone, with a proof in rational arithmetic that no
equilibrium exists beyond it — :mod:`..mechanics.rigid_limit` for the circle.

Mechanics.  A rigid motion φ of the whole frame (translation t, rotation
θ: φ = t + θ × x at a node at x) is in the null space of its stiffness, so
on any equilibrium φᵀF + Σ_c X_c·φ(x_c) = 0.  Contact c's force is X_n n +
X_t1 t1 + X_t2 t2 with |X_t| ≤ f X_n; it does no positive work against φ
exactly when a_c = n·φ(x_c) and s_c = (t1·φ(x_c), t2·φ(x_c)) satisfy

    a_c ≥ f |s_c|                (the dual of Coulomb's cone)

— the contact opens at least f times as fast as it slides.  A motion with
that at every contact and φᵀF > 0 proves that no contact forces within
the circles balance the loads, whatever the members, the contacts'
springs or the load path.  Checked exactly as a_c ≥ 0 and a_c² ≥ f²|s_c|²
in ``fractions.Fraction`` with every stored float read as a rational.

The limit.  The largest p that forces within the circles carry is a
second-order-cone program; it is solved here by LPs over polygons
circumscribing each contact's circle, each new polygon adding the tangent
at the direction where the previous LP's optimal force stood outside the
circle (Kelley's cutting planes: the polygons' limits decrease to the
circle's, the error falling with the square of the angle missed).  A
circumscribed polygon's limit is never below the circle's, so a motion
the LP's dual gives just above it passes the circle's test too; only its
rounding is left, which a lift along the contacts' normals removes (a
lift opens every contact).  [p_lo, p_hi]: p_lo a certified equilibrium on
the path (the trace's), p_hi this proof.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from ..mechanics import contact_lcp
from ..mechanics.rigid_limit import balanced_motion, rigid_motions, turn_words

#: relative steps above the polygons' limit at which a proof is tried
MARGINS = (1e-10, 1e-9, 1e-8, 1e-7)
#: the cutting planes stop when no optimal force stands further outside its
#: circle than this (relative): the polygons' limit is then within about
#: this of the circle's
OUTSIDE = 1e-12
#: a contact whose opening is within this (relative to the motion's
#: largest) of f|s| is named sliding, not lifting, in the words
WORDS = 1e-2
#: at most this many rounds of cutting planes
ROUNDS = 200
#: the polygons' tangent directions to start from, per contact
START = 16


def contact_frames(frame, b, G):
    """Per contact: the rigid motions' (n, t1, t2) components at its node
    (relative to its other node's for a pair), (3, params) in floats, and
    the contact's f."""
    out = []
    for c in frame.contacts:
        rows = G[:, b["idx"][c.node]:b["idx"][c.node] + 3]      # (params, 3): φ at the node
        if c.other is not None:
            rows = rows - G[:, b["idx"][c.other]:b["idx"][c.other] + 3]
        out.append((np.array([rows @ c.normal, rows @ c.t1, rows @ c.t2]), c.friction))
    return out


def vertices(angles, f):
    """The vertices of the polygon circumscribing the circle of radius f
    whose sides touch it at ``angles`` (sorted): between two touching
    directions, at their bisector, radius f / cos(half the gap)."""
    a = np.sort(np.asarray(angles, float))
    nxt = np.r_[a[1:], a[0] + 2 * np.pi]
    mid, half = 0.5 * (a + nxt), 0.5 * (nxt - a)
    rad = f / np.cos(half)
    return np.c_[rad * np.cos(mid), rad * np.sin(mid)]


def rays(cf, angles):
    """(columns, owners): each contact's extreme rays — its normal alone
    without friction, else (1, vertex) of its circumscribed polygon — as
    the rigid motions' work (columns), and whose they are (contact,
    vertex)."""
    cols, owner = [], []
    for ci, ((A, f), ang) in enumerate(zip(cf, angles)):
        if not A.any():
            # no rigid motion moves it (a pair whose nodes coincide): its
            # force does no work in any, and is left out of the LP
            continue
        if f == 0:
            cols.append(A[0]), owner.append((ci, None))
            continue
        for v in vertices(ang, f):
            cols.append(A[0] + v[0] * A[1] + v[1] * A[2]), owner.append((ci, v))
    return cols, owner


def cut(x, owner, cf, angles) -> bool:
    """Each contact's force from the LP's ray weights ``x``; where one
    stands outside its circle (beyond OUTSIDE), its polygon gets the
    tangent at that direction (``angles`` updated).  True if any did."""
    xn = np.zeros(len(cf))
    xt = np.zeros((len(cf), 2))
    for lam, (ci, v) in zip(x, owner):
        xn[ci] += lam
        if v is not None:
            xt[ci] += lam * v
    added = False
    for ci, (_, f) in enumerate(cf):
        if f > 0 and xn[ci] > 0 and np.linalg.norm(xt[ci]) > f * xn[ci] * (1 + OUTSIDE):
            new = np.arctan2(xt[ci, 1], xt[ci, 0]) % (2 * np.pi)
            if np.min(np.abs((angles[ci] - new + np.pi) % (2 * np.pi) - np.pi)) > 1e-9:
                angles[ci] = np.sort(np.r_[angles[ci], new])
                added = True
    return added


def polygon_limit(frame, b, const, var):
    """(p, angles): the largest p carried on circumscribed polygons refined
    by cutting planes until the limit settles (the module docstring); p is
    never below the circle's limit.  (None, None) where the frame is held,
    inf where nothing limits p."""
    from scipy.optimize import linprog

    G = rigid_motions(frame, b)
    if G is None or frame.DOFS != ("ux", "uy", "uz", "rx", "ry", "rz"):
        return None, None
    cf = contact_frames(frame, b, G)
    gc = G @ (b["F"] @ contact_lcp.factors(b, const))
    gv = G @ (b["F"] @ contact_lcp.factors(b, var))
    angles = [2 * np.pi * np.arange(START) / START if f > 0 else np.zeros(0) for _, f in cf]
    for _ in range(ROUNDS):
        cols, owner = rays(cf, angles)
        Aeq = np.column_stack(cols + [gv])
        scale = max(np.abs(Aeq).max(), 1e-300)
        c = np.zeros(Aeq.shape[1])
        c[-1] = -1.0
        res = linprog(c, A_eq=Aeq / scale, b_eq=-gc / scale,
                      bounds=[(0, None)] * (Aeq.shape[1] - 1) + [(None, None)],
                      method="highs")
        if res.status == 3:
            return np.inf, angles
        if res.status != 0:
            return None, None
        p = float(res.x[-1])
        if not cut(res.x[:-1], owner, cf, angles):
            return p, angles
    return p, angles


def prove_beyond(frame, b, const, var, p, angles):
    """A rigid motion proving that no equilibrium on Coulomb's circles
    exists at F(const) + p F(var), checked in rationals: a dict with its
    parameters, exact work, and per contact its opening a and tangential
    motion s (floats, for the words); None if none is found or it fails."""
    G = rigid_motions(frame, b)
    if G is None:
        return None
    cf = contact_frames(frame, b, G)
    F = b["F"] @ (contact_lcp.factors(b, const) + p * contact_lcp.factors(b, var))
    R = np.array(rays(cf, angles)[0])
    # the motion that opens the contacts least for unit work: the tight one
    # (a contact slides where it can), so that its words name the mechanism
    c = balanced_motion(G, R, G @ F, cost=sum(A[0] for A, _ in cf))
    if c is None:
        c = balanced_motion(G, R, G @ F)
    return None if c is None else exact_check(frame, G, cf, F, c)


def exact_check(frame, G, cf, F, c):
    """The motion G'c checked on the circles in rationals, lifted along the
    contacts' mean normal where rounding left a contact short; None if it
    fails."""
    def parts(params):
        q = [Fraction(v) for v in params]
        out = []
        for A, _ in cf:
            out.append([sum((Fraction(A[k, j]) * q[j] for j in range(len(q))), Fraction(0))
                        for k in range(3)])
        return out

    def holds(a, s, f):
        fq = Fraction(f)
        return a >= 0 and a * a >= fq * fq * (s[0] * s[0] + s[1] * s[1])

    def work(params):
        q = [Fraction(v) for v in params]
        total = Fraction(0)
        for i in np.flatnonzero(np.asarray(F) != 0):
            total += Fraction(F[i]) * sum((Fraction(G[k, i]) * q[k] for k in range(len(q))
                                           if G[k, i] != 0), Fraction(0))
        return total

    c = np.asarray(c, float)
    m = parts(c)
    if not all(holds(a, (s1, s2), f) for (a, s1, s2), (_, f) in zip(m, cf)):
        # lift: the rigid motion that opens every contact at unit rate
        # (least squares), added just enough to cover the rounding
        # (a contact no rigid motion moves holds in every one: left out)
        moved = [k for k, (A, _) in enumerate(cf) if A.any()]
        if not moved:
            return None
        lift, *_ = np.linalg.lstsq(np.array([cf[k][0][0] for k in moved]),
                                   np.ones(len(moved)), rcond=None)
        gain = [float(A[0] @ lift) - f * float(np.hypot(A[1] @ lift, A[2] @ lift))
                for A, f in (cf[k] for k in moved)]
        if min(gain) <= 0:
            return None
        short = [max(cf[k][1] * float(np.hypot(float(m[k][1]), float(m[k][2])))
                     - float(m[k][0]), 0.0) for k in moved]
        size = max(float(np.abs(c).max()), 1e-300)
        delta = 2.0 * max(s / g for s, g in zip(short, gain)) + 1e-15 * size
        c = c + delta * lift
        m = parts(c)
        if not all(holds(a, (s1, s2), f) for (a, s1, s2), (_, f) in zip(m, cf)):
            return None
    w = work(c)
    if w <= 0:
        return None
    opening = np.array([float(a) for a, _, _ in m])
    sliding = np.array([[float(s1), float(s2)] for _, s1, s2 in m])
    # for the words: a contact that opens within WORDS of f|s| (the slack a
    # load beyond the limit leaves in any proof) slides rather than lifts
    f = np.array([ff for _, ff in cf])
    slide = f * np.linalg.norm(sliding, axis=1)
    big = max(float(np.abs(opening).max(initial=0.0)), float(slide.max(initial=0.0)), 1e-300)
    opening = np.where(opening <= slide + WORDS * big, slide, opening)
    return {"params": [float(x) for x in c], "work": w, "turn": turn_words(frame, c),
            "opening": opening, "sliding": sliding}


def limit_bracket(frame, b, const, var, p_lo):
    """(p_hi, proof, p_poly): the first margin above the polygons' limit
    (and above ``p_lo``, the last certified equilibrium) at which a rigid
    motion proves that no equilibrium on the circles exists; (None, None,
    p_poly) where none is found."""
    p_poly, angles = polygon_limit(frame, b, const, var)
    if p_poly is None or not np.isfinite(p_poly):
        return None, None, p_poly
    base = max(p_poly, p_lo)
    for margin in MARGINS:
        p_hi = base + margin * max(abs(base), 1e-300)
        proof = prove_beyond(frame, b, const, var, p_hi, angles)
        if proof is not None:
            return p_hi, proof, p_poly
    return None, None, p_poly



def prove_no_equilibrium(frame, b, combo):
    """A rigid-motion proof (as :func:`prove_beyond`'s) that the frame
    cannot carry the combination ``combo`` on Coulomb's circles, or None.
    Cutting planes on the fixed load: forces within circumscribed polygons
    that balance it are sought by an LP; where one stands outside its
    circle, the polygon gets the tangent there; once no forces exist, the
    LP's dual motion is the proof (it passes the circles' test too)."""
    from scipy.optimize import linprog

    G = rigid_motions(frame, b)
    if G is None:
        return None
    cf = contact_frames(frame, b, G)
    gF = G @ (b["F"] @ contact_lcp.factors(b, combo))
    angles = [2 * np.pi * np.arange(START) / START if f > 0 else np.zeros(0) for _, f in cf]
    for _ in range(ROUNDS):
        cols, owner = rays(cf, angles)
        Aeq = np.column_stack(cols)
        scale = max(np.abs(Aeq).max(), 1e-300)
        res = linprog(np.zeros(Aeq.shape[1]), A_eq=Aeq / scale, b_eq=-gF / scale,
                      bounds=[(0, None)] * Aeq.shape[1], method="highs")
        if res.status == 2:             # infeasible: the polygons cannot carry it
            return prove_beyond(frame, b, {}, combo, 1.0, angles)
        if res.status != 0:
            return None
        if not cut(res.x, owner, cf, angles):
            return None                 # forces within the circles carry it
    return None
