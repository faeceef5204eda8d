"""What a plane frame's result reads back along a member: the internal-force
diagrams N, V, M (the engineering convention: N tension positive, M positive
when it compresses the member's +y fibre, V = dM/dx) and the exact
deflection of its axis, integrated from the internal forces."""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidOptionError, SolverFailedError

from ..mechanics.loads import check_diagram, known_member, load_points, section_sums
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


def sections(frame, res, m, x):
    """(N, V, M) at the sections x (member axes, engineering convention):
    the end actions at node i plus the member loads on [0, x)."""
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
    return -f[0] - fx, f[1] + fy, -f[2] + f[1] * x + mo


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
