"""The limit load of a frame that rests on its pads, by the statics of a
rigid body: an LP written with scipy.optimize.linprog, independent of the
frames' engine (it reads the model's nodes, contacts and loads, never its
assembly or its LCP).

Mechanics.  Whatever the members' stiffness, an equilibrium of a frame held
only by its contacts balances the loads' resultant force and moment with
contact forces that each lie in their friction cone.  Each pad's force is a
normal force n_c >= 0 along its normal plus a friction force in its
polygon: Σ_j λ_cj μ v_j with λ_cj >= 0, Σ_j λ_cj = n_c (v_j the polygon's
vertices, unit radius for Coulomb's circle).  The largest p for which such
forces balance F(const) + p F(var) — six equations of statics — is an upper
bound of the frame's limit on the load path (and the limit itself where the
law is associated: no friction, or a path that reaches it).

Polygons, in the contact's tangents (t1, t2) as the model lays them: the
circumscribed m-gon has its facets' normals at 2πk/m and its vertices at
(2k+1)π/m, radius 1/cos(π/m); the inscribed one its vertices at 2πk/m on
the circle (docs/frames.md, "Which polygon").  ``polygon="circle"`` brackets
Coulomb's circle by the inscribed and circumscribed 2048-gons.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import linprog


def resultants(frame, combo: dict):
    """(force, moment about the origin) of the combination {case: factor}
    of the frame's nodal loads and uniform member loads in global axes."""
    force, moment = np.zeros(3), np.zeros(3)
    for node, vals, case in frame.nodal_loads:
        f = combo.get(case, 0.0)
        if f:
            x = frame.nodes[node]
            force += f * np.asarray(vals[:3])
            moment += f * (np.asarray(vals[3:]) + np.cross(x, vals[:3]))
    if len(frame.member_loads) != len(frame.span_loads):
        # member_loads lists the whole-member uniform loads only: a point or
        # partial load would be left out of the resultant without a word
        raise ValueError("the rigid-body LP reads uniform whole-member loads only")
    for member, w, axes, case in frame.member_loads:
        f = combo.get(case, 0.0)
        if not f:
            continue
        if axes != "global":
            raise ValueError("the rigid-body LP reads member loads in global axes only")
        m = frame.members[member]
        xi, xj = frame.nodes[m["i"]], frame.nodes[m["j"]]
        total = f * np.asarray(w) * np.linalg.norm(xj - xi)
        force += total
        moment += np.cross(0.5 * (xi + xj), total)
    return force, moment


#: HiGHS's default tolerances (1e-7) left the 16-pad tower's 2048-gon
#: bracket 1.6e-5 wide and 3e-6 below the hand sliding load; tightened,
#: the LP's optimum is good to the polygons' own 1.2e-6
LP_OPTIONS = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}


def vertices(polygon: str, m: int) -> np.ndarray:
    """(m, 2): the polygon's vertices in (t1, t2), Coulomb's circle of radius 1."""
    if polygon == "inscribed":
        a = 2 * np.pi * np.arange(m) / m
        return np.c_[np.cos(a), np.sin(a)]
    a = 2 * np.pi * (np.arange(m) + 0.5) / m
    return np.c_[np.cos(a), np.sin(a)] / np.cos(np.pi / m)


def static_limit(frame, const: dict, var: dict, polygon: str | None = None) -> float:
    """The largest p carried by the pads as a rigid body's supports (the
    module docstring); ``polygon`` None: the frame's polygon and each
    contact's facets; "inscribed"/"circumscribed" with 2048 facets; inf where
    unbounded."""
    if frame.fixed or frame.springs:
        raise ValueError("the rigid-body LP is for frames held by their contacts alone")
    Fc, Mc = resultants(frame, const)
    Fv, Mv = resultants(frame, var)
    cols = []
    rows = []          # per contact: (first column, count)
    for c in frame.contacts:
        x = frame.nodes[c.node]
        kind, m = (frame.cone, c.facets) if polygon is None else (polygon, 2048)
        if kind == "circular":
            raise ValueError("the frame is on Coulomb's circle: ask coulomb_limits for the "
                             "bracket of 2048-gons")
        forces = [np.asarray(c.normal, float)]
        if c.friction > 0:
            forces += [c.friction * (vx * c.t1 + vy * c.t2) for vx, vy in vertices(kind, m)]
        rows.append((len(cols), len(forces)))
        cols += [np.r_[f, np.cross(x, f)] for f in forces]
    n = len(cols)
    A_eq = np.zeros((6 + len(frame.contacts), n + 1))
    A_eq[:6, :n] = np.array(cols).T
    A_eq[:6, n] = np.r_[Fv, Mv]
    for k, (first, count) in enumerate(rows):
        if count > 1:        # the friction weights sum to the normal force
            A_eq[6 + k, first] = -1.0
            A_eq[6 + k, first + 1:first + count] = 1.0
    b_eq = np.r_[-Fc, -Mc, np.zeros(len(frame.contacts))]
    c = np.zeros(n + 1)
    c[-1] = -1.0
    res = linprog(c, A_eq=A_eq, b_eq=b_eq, bounds=[(0, None)] * n + [(None, None)],
                  method="highs", options=LP_OPTIONS)
    if res.status == 3:
        return np.inf
    if res.status != 0:
        raise RuntimeError(f"rigid-body LP: {res.message}")
    return float(res.x[-1])


def coulomb_limits(frame, const: dict, var: dict) -> tuple:
    """(inscribed 2048-gon, circumscribed 2048-gon): Coulomb's circle's rigid-body
    limit lies between them (within 1.2e-6 relative)."""
    return (static_limit(frame, const, var, "inscribed"),
            static_limit(frame, const, var, "circumscribed"))


def bounded_at_the_lp(frame, case: str, const: dict | None = None):
    """The frame's trace of ``case`` (on ``const``, default the case
    "constant") checked to end "bounded" with its proved bound at the LP's
    limit (:func:`static_limit`, to 1e-12), then solved at the bound's
    lower end: (trace, that result, the LP's limit)."""
    const = {"constant": 1.0} if const is None else const
    tr = frame.trace(constant=const, variable=case)
    ref = static_limit(frame, const, {case: 1.0})
    assert tr.ended == "bounded" and tr.limit is None, tr.message
    lo, hi = tr.bound
    assert lo < hi and abs(hi - ref) <= 1e-12 * ref
    return tr, frame.solve(combination={**const, case: lo}), ref
