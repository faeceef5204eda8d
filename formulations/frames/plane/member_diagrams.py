"""What a plane frame's result reads back along a member: the internal-force
diagrams N, V, M (the engineering convention: N tension positive, M positive
when it compresses the member's +y fibre, V = dM/dx) and the exact
deflection of its axis, integrated from the internal forces."""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidOptionError, SolverFailedError

from ..mechanics.loads import check_diagram, known_member, load_points, section_sums
from ..mechanics import beam_column
from ..mechanics.plane_element import geometry, rotation


def diagram(frame, res, member: str, points: int):
    m = diagram_member(frame, res, member, points)
    L = geometry(frame, m)[0]
    x = np.linspace(0.0, L, int(points))
    pts = [p for p in load_points(loads_of(res, m)) if 0.0 < p < L]
    # both sides of every load position: jumps of V (point loads) and M (moments)
    x = np.unique(np.r_[x, pts, np.nextafter(np.array(pts, float), -np.inf)])
    return (x, *sections(frame, res, m, x))


def diagram_member(frame, res, member, points):
    check_diagram(frame, res, member, points, ("N", "V", "M"))
    return frame.members[member]


def direction(frame, member):
    """(cos, sin) of a member's axis."""
    return geometry(frame, known_member(frame, member))[1:]


def loads_of(res, m):
    return [ld for ld in m.loads if res.combination.get(ld.case)]


def sections(frame, res, m, x, deformed: bool = True):
    """(N, V, M) at the sections x (member axes, engineering convention):
    the end actions at node i plus the member loads on [0, x) — and, in a
    second-order answer (``deformed``), N times the member's own deflection
    (:func:`beam_column_axis`)."""
    L, c, s = geometry(frame, m)
    f = res.member_forces[m.name]
    loads = loads_of(res, m)
    fx, fy, mo = np.zeros_like(x), np.zeros_like(x), np.zeros_like(x)
    for case in {ld.case for ld in loads}:
        ax_, ay_, am_ = section_sums([ld for ld in loads if ld.case == case], x, c, s)
        factor = res.combination[case]
        fx += factor * ax_
        fy += factor * ay_
        mo += factor * am_
    N, V, M = -f[0] - fx, f[1] + fy, -f[2] + f[1] * x + mo
    bent = beam_column_axis(frame, res, m, x) if deformed else None
    if bent is not None:
        # on the deformed axis: the section moment adds ∫₀ˣ N v' (N (v(x) −
        # v(0)) for N constant), V = dM/dx adds N v' (mechanics.beam_column,
        # mechanics.varying_axial)
        axial, added, v, dv = bent
        V, M = V + axial * dv, M + added
    return N, V, M


def beam_column_axis(frame, res, m, x):
    """(N(x), ∫₀ˣ N v', v(x), v'(x)) of a member of a second-order answer whose
    element is the beam-column (N ≠ 0: the stiffness's axial force;
    Engesser's with shear), member axes, node to node (a rigid zone moves
    with its node); None for first order.  The flexible
    part's by :func:`..mechanics.beam_column.deflection` from its ends'
    displacements through the rigid arms and their own rotations — a
    released end's from the element's moment row (hinge: the moment 0;
    spring k: k (θ_node − θ_end)), its consistent loads the beam-column's.
    Where its loads' axial parts make N vary (``res.stiffness_along``) the
    member is :class:`..mechanics.varying_axial.Member`, as its element."""
    if res.stiffness_axial is None:
        return None
    axial = float(res.stiffness_axial[list(frame.members).index(m.name)])
    varying = varying_member(frame, res, m)
    if axial == 0.0 and varying is None:
        return None
    L, c, s = geometry(frame, m)
    oi, oj = m.offset_i, m.offset_j
    Lf, EI = L - oi - oj, m.E * m.I
    idx = {nm: 3 * k for k, nm in enumerate(frame.nodes)}
    T = rotation(c, s)[:3, :3]
    di = T @ res._u[idx[m.i]:idx[m.i] + 3]
    dj = T @ res._u[idx[m.j]:idx[m.j] + 3]
    ends = np.array([di[1] + oi * di[2], di[2], dj[1] - oj * dj[2], dj[2]])
    parts = [part[:-2] + tuple(res.combination[ld.case] * np.array(part[-2:]))
             for ld in loads_of(res, m)
             for part in [beam_column.flexible_part(ld, L, c, s, oi, oj)] if part]
    xf = np.clip(x, oi, L - oj) - oi
    if varying is not None:
        v, dv, added = varying.axis(parts, ends, m.end_springs, xf)
        # N along the zones too (their own loads change it), and their own
        # ∫ N v' = θ ∫ N dx (each moves with its node)
        Nx = varying.N(np.asarray(x, float) - oi)
        arm_i = varying.arms()[0]
        beyond = np.maximum(np.asarray(x, float) - oi, Lf)
        added = added + arm_i * di[2] + dj[2] * varying.integral(Lf, beyond)
        added = np.where(x < oi, di[2] * varying.integral(-oi, np.minimum(x - oi, 0.0)),
                         added)
    else:
        v, dv = beam_column.axis(parts, EI, axial, Lf, ends, m.end_springs, xf,
                                 0.0 if m.GAs is None else 1.0 / m.GAs)
    v = np.where(x < oi, di[1] + x * di[2], np.where(x > L - oj, dj[1] - (L - x) * dj[2], v))
    dv = np.where(x < oi, di[2], np.where(x > L - oj, dj[2], dv))
    if varying is not None:
        return Nx, added, v, dv
    return axial, axial * (v - di[1]), v, dv


def varying_member(frame, res, m):
    """The member's :class:`..mechanics.varying_axial.Member` where its
    answer's stiffness took N(x) (its loads' axial parts in
    ``res.stiffness_along``; Euler–Bernoulli), else None."""
    from ..mechanics.varying_axial import of_member

    return of_member(m, *geometry(frame, m),
                     float(res.stiffness_axial[list(frame.members).index(m.name)]),
                     getattr(res, "stiffness_along", None))


def deflection(frame, res, member: str, points: int):
    """(x, u, v): the displacement of the member's axis along (u) and
    across (v) it, member axes, at ``points`` sections plus the load
    positions and the faces of rigid end zones.  Integrated from the
    internal forces, not interpolated from the nodes: on the flexible
    length u' = N/EA and v'' = M/EI (sagging M bends the axis towards
    +y), plus the shear strain -V/(G A_s) in v' for a Timoshenko member
    (V = dM/dx is minus the shear force on the face at x along +y),
    with v at both flexible ends given by the nodes through the rigid
    arms — which fixes the slope constant without the end rotations, so
    a released end needs nothing special; a rigid zone moves with its
    node.  Each integral is a sum of 4-point Gauss rules between
    consecutive sections, which include every load position, so the
    integrand is one polynomial of degree <= 4 on each piece and the
    result is exact to rounding (the repeated integral by Cauchy's
    formula, v(x) = ∫ (x - s) M/EI ds)."""
    m = diagram_member(frame, res, member, points)
    L, c, s = geometry(frame, m)
    a, e = m.offset_i, L - m.offset_j          # the flexible length [a, e]
    pts = [p for p in load_points(loads_of(res, m)) + [a, e] if 0.0 < p < L]
    x = np.unique(np.r_[np.linspace(0.0, L, int(points)), pts])
    bent = beam_column_axis(frame, res, m, x)
    if bent is not None:        # a second-order answer's: the beam-column's own
        return x, axial_displacement(frame, res, m, x), bent[2]
    t, w = np.polynomial.legendre.leggauss(4)
    lo, hi = np.maximum(x[:-1, None], a), np.minimum(x[1:, None], e)
    gs = (0.5 * (hi - lo) * t + 0.5 * (lo + hi)).ravel()
    gw = (0.5 * np.maximum(hi - lo, 0.0) * w).ravel()
    N, V, M = sections(frame, res, m, gs)
    idx = {nm: 3 * k for k, nm in enumerate(frame.nodes)}
    T = rotation(c, s)[:3, :3]
    di = T @ res._u[idx[m.i]:idx[m.i] + 3]
    dj = T @ res._u[idx[m.j]:idx[m.j] + 3]
    va, ve = di[1] + a * di[2], dj[1] - m.offset_j * dj[2]   # through the rigid arms
    xf = np.clip(x, a, e)
    before = gs[None, :] < xf[:, None]
    u = di[0] + (before * (gw * N / (m.E * m.A))) @ np.ones_like(gs)
    bend = gw * M / (m.E * m.I)
    v = (before * (xf[:, None] - gs[None, :]) * bend) @ np.ones_like(gs)
    if m.GAs is not None:
        # the shear strain is the face's force along +y, -V, over G A_s (a
        # constant V is absorbed by the end values' line: only a load in
        # the span shows its sign)
        v = v - (before * (gw * V / m.GAs)) @ np.ones_like(gs)
    v_e = v[np.searchsorted(x, e)]
    v = va + v + (ve - va - v_e) * (xf - a) / (e - a)
    v = np.where(x < a, di[1] + x * di[2], np.where(x > e, dj[1] - (L - x) * dj[2], v))
    return x, u, v


def axial_displacement(frame, res, m, x):
    """The displacement along the axis at x: node i's plus ∫ N/EA over the
    flexible length (N linear between load edges: 4-point Gauss rules exact)."""
    L, c, s = geometry(frame, m)
    a, e = m.offset_i, L - m.offset_j
    grid = np.unique(np.r_[x, [p for p in load_points(loads_of(res, m)) + [a, e] if 0 < p < L]])
    t, w = np.polynomial.legendre.leggauss(4)
    lo, hi = np.maximum(grid[:-1, None], a), np.minimum(grid[1:, None], e)
    gs = (0.5 * (hi - lo) * t + 0.5 * (lo + hi)).ravel()
    gw = (0.5 * np.maximum(hi - lo, 0.0) * w).ravel()
    N = sections(frame, res, m, gs, deformed=False)[0]
    idx = {nm: 3 * k for k, nm in enumerate(frame.nodes)}
    di = rotation(c, s)[:3, :3] @ res._u[idx[m.i]:idx[m.i] + 3]
    before = gs[None, :] < np.clip(x, a, e)[:, None]
    return di[0] + (before * (gw * N / (m.E * m.A))) @ np.ones_like(gs)


def varying_couples(frame, b, u, couples) -> np.ndarray:
    """``couples`` (:func:`..mechanics.second_order.pdelta_couples`, N̄
    (v_j − v_i) per member) with those of the members whose stiffness took
    N(x) (``b["along"]``) replaced by their own, ∫ N v' node to node: the
    moment of their end forces in the undeformed frame (N (v_j − v_i) at j
    and the axial loads' ∫ p (v − v_i) on the deflected axis) — no longer
    one of the nodes' displacements alone; ``u`` the global displacements.
    The statics check sums the nodes' loads, the members' consistent ones
    among them, whose moment is not their span loads' where N varies (a
    rigid turn of the member is not one of its solutions: (N v')' = N'),
    so each such couple also carries the difference, ρ·f_e less the span
    loads' moment about node i (f_e the member's nodal loads as assembled,
    its releases condensed; ρ the turn about node i, (0, 1, L, 1) on v, θ;
    by virtual work the end forces' moment is ∫ N v' less the loads')."""
    along = b.get("along")
    if not along:
        return couples
    from ..mechanics.varying_axial import Member, of_member

    from ..mechanics.contact_lcp import factors

    couples = np.array(couples, float)
    fe_all = b["local"][3] @ factors(b, along)
    ms = list(frame.members.values())
    members = {k: member for k, m in enumerate(ms) if m.loads
               for member in [of_member(m, *geometry(frame, m), float(b["axial"][k]), along,
                                        False)] if member is not None}
    Member.in_one_pass(list(members.values()))      # their series in one pass
    for k, member in members.items():
        m = ms[k]
        L, c, s = geometry(frame, m)
        oi, oj = m.offset_i, m.offset_j
        T = rotation(c, s)[:3, :3]
        di = T @ u[b["idx"][m.i]:b["idx"][m.i] + 3]
        dj = T @ u[b["idx"][m.j]:b["idx"][m.j] + 3]
        parts = [part[:-2] + tuple(along[ld.case] * np.array(part[-2:]))
                 for ld in m.loads if along.get(ld.case)
                 for part in [beam_column.flexible_part(ld, L, c, s, oi, oj)] if part]
        ends = [di[1] + oi * di[2], di[2], dj[1] - oj * dj[2], dj[2]]
        added = member.axis(parts, ends, m.end_springs, np.array([member.L]))[2][0]
        turn = np.array([1.0, L, 1.0]) @ fe_all[k, [2, 4, 5]] - sum(
            along[ld.case] * load_moment(beam_column.across(ld, c, s))
            for ld in m.loads if along.get(ld.case))
        arm_i, arm_j = member.arms()
        couples[k] = added + arm_i * di[2] + arm_j * dj[2] + turn
    return couples


def load_moment(part) -> float:
    """The moment about x = 0 of a load part across the axis
    (:func:`..mechanics.beam_column.across`): a force's p a plus its
    couple, a trapezoid's ∫ q x dx."""
    if part[0] == "point":
        _, a, py, mz = part
        return py * a + mz
    _, a, b, w1, w2 = part
    # ∫ (w1 + (w2 − w1) t) (a + (b − a) t) (b − a) dt over [0, 1]
    return (b - a) * (w1 * a + (w1 * (b - a) + (w2 - w1) * a) / 2 + (w2 - w1) * (b - a) / 3)
