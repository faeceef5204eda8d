"""What a space frame's result reads back along a member: the internal
forces N, Vy, Vz, T, My, Mz at any section, their extremes, and the values
at the member's ends — in the plane frame's convention, extended to the
member's second bending plane (docs/frames.md, "Conventions").

Derivation.  Cut the member at x (member axes, x from node i).  The part
[0, x] is held by the end actions at i, f_i = (F, M) — the forces and
moment the node exerts on the member, ``member_forces[:6]`` — by the
member loads on [0, x), and by the force S and moment S_m the rest of the
member exerts on its face at x, whose outward normal is +x.  Equilibrium
of that part about the section's centre, with uniform loads q = (qx, qy,
qz) per unit length (member axes):

    S   = -(F + q x)
    S_m = -(M + (-x e_x) × F + ∫_0^x (s - x) e_x × q ds)

The engineering values are S and S_m read the way a plane frame reads
its single bending plane:

* N = S_x, tension positive;  T = S_mx, the twist of the face at x about +x;
* Mz = S_mz, positive when it compresses the +y fibre (σ = -Mz y / Iz), and
  Vy = dMz/dx = -S_y: the plane frame's M and V, so a frame in the x-y plane
  gives the plane API's numbers;
* My = -S_my, positive when it compresses the +z fibre (S_my = ∫ σ z dA puts
  +z in tension), and Vz = dMy/dx = -S_z: the same reading in the x-z plane.
  A horizontal member's default local z points up (global Z), so My is
  positive in sagging, as Mz of a plane beam drawn left to right.

Written out, with f_i = (f0, ..., f5):

    N  = -f0 - qx x           Vy = f1 + qy x            Vz = f2 + qz x
    T  = -f3                  My = f4 + f2 x + qz x²/2  Mz = -f5 + f1 x + qy x²/2

At x = L the face is node j's: N(L) = N_j, Vy(L) = -Vy_j, Vz(L) = -Vz_j,
T(L) = T_j, My(L) = -My_j, Mz(L) = Mz_j of the end actions at j
(``member_forces[6:]``); at x = 0, N(0) = -N_i, Vy(0) = Vy_i, Vz(0) = Vz_i,
T(0) = -T_i, My(0) = My_i, Mz(0) = -Mz_i.  Units: forces, and moments in
force·length, the frame's own.
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidOptionError, InvalidProblemError, SolverFailedError

from ..mechanics.loads import check_diagram, stationary_points, turning_points, turning_sections
from ..mechanics.space_element import EXTREMES, QUANTITIES
from ..mechanics import beam_column
from . import space_varying
from .space_member_loads import load_points, plane_parts, section_terms, split


def geometry(frame, member: str):
    """(L, R) of a member: its length and the rows of its local x, y, z."""
    return space_varying.geometry(frame, frame.members[member])


def loads_of(frame, res, member: str) -> list:
    """[(load, factor)]: the member's loads in the result's combination."""
    return [(ld, res.combination[ld.case]) for ld in frame.span_loads
            if ld.member == member and res.combination.get(ld.case)]


#: the 4-point Gauss rule (exact to degree 7) of the deflection's integrals
GAUSS = np.polynomial.legendre.leggauss(4)


class Along:
    """What the sections of one member in one result read, gathered once:
    its length, axes, end actions at i and loads split into the planes
    (a members table asks for 400 members' sections hundreds of times)."""

    def __init__(self, frame, res, member: str):
        self.L, self.R = geometry(frame, member)
        self.f = np.asarray(res.member_forces[member], float)
        self.loads = loads_of(frame, res, member)
        self.parts = split(self.loads, self.R)
        self.planes = bent_planes(frame, res, member, self.L, self.R, self.loads)

    def sections(self, x) -> tuple:
        """(N, Vy, Vz, T, My, Mz) at the sections x (module docstring): the
        end actions at i and the loads on [0, x)
        (:func:`.space_member_loads.section_terms`)."""
        x = np.asarray(x, float)
        f = self.f
        fx, fy, fz, tx, mo_xy, mo_xz = section_terms(self.parts, x)
        N, Vy, Vz, T = -f[0] - fx, f[1] + fy, f[2] + fz, -f[3] - tx
        My, Mz = f[4] + f[2] * x + mo_xz, -f[5] + f[1] * x + mo_xy
        # a second-order answer's: N times the member's own deflection in
        # each bending plane (the plane frame's member_diagrams.sections)
        # (∫₀ˣ N v' where N varies along it, N (v − v(0)) where it does not)
        for plane, solution in self.planes.items():
            _, _, shear, moment = solution(x)
            if plane == 1:
                Vy, Mz = Vy + shear, Mz + moment
            else:
                Vz, My = Vz + shear, My + moment
        return N, Vy, Vz, T, My, Mz

    def sample_points(self, points: int):
        """``points`` sections from node i, with every load's position and
        the section just before it (both sides of a jump)."""
        pts = [p for p in load_points(self.loads) if 0.0 < p < self.L]
        return np.unique(np.r_[np.linspace(0.0, self.L, int(points)), pts,
                               np.nextafter(np.array(pts, float), -np.inf)])


def bent_planes(frame, res, member, L, R, loads) -> dict:
    """{1 (across y) | 2 (across z): x ↦ (d(x), d'(x), N d'(x), ∫₀ˣ N d')}:
    the beam-column's deflection of each bending plane (Engesser's with
    shear deformation) of a second-order answer's member under N ≠ 0, member axes,
    node to node (a rigid zone moves with its node), and what N times it
    adds to the plane's shear and moment: the x-y plane with EIz on (v,
    θz), the x-z plane with EIy on (w, θ' = −θy), each as the plane
    frame's (:func:`..mechanics.beam_column.axis`; where the member's
    loads make N vary along it, its chain under N(x),
    :mod:`.space_varying`, as the stiffness took it); {} for first order."""
    if res.stiffness_axial is None:
        return {}
    axial = float(res.stiffness_axial[list(frame.members).index(member)])
    m = frame.members[member]
    # (its pieces cut at every load of the member, as its stiffness's)
    varying = space_varying.of_member(m, space_varying.loads_on(frame, member), L, R, axial,
                                      res.stiffness_along) if loads else None
    if varying is not None:
        return {plane: varying_solution(varying, plane, m, res, L, R, loads)
                for plane in (1, 2)}
    if axial == 0.0:
        return {}
    oi, oj = m["offsets"]
    Lf = L - oi - oj
    di, dj = (np.r_[R @ np.asarray(res.displacements[n][:3], float),
                    R @ np.asarray(res.displacements[n][3:], float)] for n in (m["i"], m["j"]))
    rel = dict(m["releases"])
    out = {}
    for plane, (I_, GAs, turn, sign) in ((1, (m["Iz"], m["GAs"][0], 5, 1.0)),
                                         (2, (m["Iy"], m["GAs"][1], 4, -1.0))):
        # the plane's slope θ' = sign θ: +θz = dv/dx, −θy = dw/dx
        ti, tj = sign * di[turn], sign * dj[turn]
        ends = (di[plane] + oi * ti, ti, dj[plane] - oj * tj, tj)
        parts = []
        for load, factor in loads:
            part = beam_column.flexible_part(plane_parts(load, R)[plane - 1], L, 1.0, 0.0, oi, oj)
            if part is not None:
                parts.append(part[:-2] + tuple(factor * np.array(part[-2:])))
        springs = (rel.get(turn), rel.get(turn + 6))

        def solution(x, ends=ends, parts=parts, springs=springs, EI=m["E"] * I_, plane=plane,
                     ti=ti, tj=tj, c=0.0 if GAs is None else 1.0 / GAs):
            x = np.asarray(x, float)
            xf = np.clip(x, oi, L - oj) - oi
            d, dd = beam_column.axis(parts, EI, axial, Lf, ends, springs, xf, c)
            d = np.where(x < oi, di[plane] + x * ti,
                         np.where(x > L - oj, dj[plane] - (L - x) * tj, d))
            dd = np.where(x < oi, ti, np.where(x > L - oj, tj, dd))
            return d, dd, axial * dd, axial * (d - di[plane])
        out[plane] = solution
    return out


def varying_solution(varying, plane, m, res, L, R, loads):
    """x ↦ (d, d', N(x) d', ∫₀ˣ N d') of one bending plane of a member whose
    stiffness took N(x) (:func:`bent_planes`), node to node: the plane's
    chain between the zones' faces (:meth:`..mechanics.varying_axial.
    Member.axis`), each rigid zone moving with its node and adding its own
    θ ∫ N dx (the plane frame's :func:`..plane.member_diagrams.
    beam_column_axis`)."""
    member, springs = varying.planes[plane - 1], varying.springs[plane - 1]
    oi, oj = m["offsets"]
    di, dj = (np.r_[R @ np.asarray(res.displacements[n][:3], float),
                    R @ np.asarray(res.displacements[n][3:], float)] for n in (m["i"], m["j"]))
    ends, (ti, tj) = space_varying.plane_ends(di, dj, plane, m["offsets"])
    parts = space_varying.plane_loads([ld for ld, _ in loads], R, plane - 1, L, m["offsets"],
                                      res.combination)
    arm_i = varying.arms()[0]

    def solution(x):
        x = np.asarray(x, float)
        xf = np.clip(x, oi, L - oj) - oi
        d, dd, added = member.axis(parts, ends, springs, xf)
        added = added + arm_i * ti + tj * member.integral(member.L, np.maximum(x - oi, member.L))
        added = np.where(x < oi, ti * member.integral(-oi, np.minimum(x - oi, 0.0)), added)
        d = np.where(x < oi, di[plane] + x * ti, np.where(x > L - oj, dj[plane] - (L - x) * tj, d))
        dd = np.where(x < oi, ti, np.where(x > L - oj, tj, dd))
        return d, dd, member.N(x - oi) * dd, added
    return solution


def checked_member(frame, res, member, points) -> str:
    """``member`` if the result can draw it; errors that say what to give."""
    check_diagram(frame, res, member, points, EXTREMES)
    return member


def diagram(frame, res, member: str, points: int = 21) -> tuple:
    """(x, N, Vy, Vz, T, My, Mz) at ``points`` sections from node i."""
    checked_member(frame, res, member, points)
    along = Along(frame, res, member)
    x = along.sample_points(points)
    return (x, *along.sections(x))


def end_forces(frame, res, member: str) -> dict:
    """{"i": {"N": ..., ..., "Mz": ...}, "j": {...}}: the internal forces at
    the member's ends in the diagrams' convention — each end's from its own
    end actions (at j: N_j, -Vy_j, -Vz_j, T_j, -My_j, Mz_j), not carried
    along the member from i, which would add the rounding of the loads."""
    checked_member(frame, res, member, 2)
    f = np.asarray(res.member_forces[member], float)
    sign = np.array([-1.0, 1.0, 1.0, -1.0, 1.0, -1.0])
    ends = {"i": sign * f[:6], "j": -sign * f[6:]}
    # a second-order answer's V = dM/dx adds N times the axis' slope there,
    # as its diagrams do (the end actions are across the undeformed axis)
    L, R = geometry(frame, member)
    for plane, solution in bent_planes(frame, res, member, L, R,
                                       loads_of(frame, res, member)).items():
        shear = solution(np.array([0.0, L]))[2]
        ends["i"][plane] += shear[0]
        ends["j"][plane] += shear[1]
    return {end: {q: float(v) + 0.0 for q, v in zip(QUANTITIES, vals)}
            for end, vals in ends.items()}


def extremes(frame, res, member: str, points: int = 201) -> dict:
    """{quantity: {"max": (value, x), "min": (value, x)}} for the internal
    forces and the deflections v, w across the member, at ``points``
    sections and the load positions; the moments also where their shear
    changes sign between them (:func:`..mechanics.loads.stationary_points`),
    so a span's largest moment is exact, not the nearest sample's; N, V and
    T also where they turn between samples (a trapezoidal load that changes
    sign: :func:`..mechanics.loads.turning_points`), so theirs are exact
    too; v and w are the samples')."""
    checked_member(frame, res, member, points)
    along = Along(frame, res, member)
    x = along.sample_points(points)
    values = dict(zip(QUANTITIES, along.sections(x)))
    at = {q: x for q in QUANTITIES}
    # where N, V and T turn between the samples (a load that changes sign)
    for q in ("N", "Vy", "Vz", "T"):
        plane = {"Vy": 1, "Vz": 2}.get(q)
        x_t = (turning_sections(x, values[q], lambda s, q=q: along.sections(s)[
            QUANTITIES.index(q)]) if plane in along.planes else turning_points(x, values[q]))
        if x_t.size:
            at[q] = np.r_[x, x_t]
            values[q] = np.r_[values[q], along.sections(x_t)[QUANTITIES.index(q)]]
    # the span moments between the samples: where V = dM/dx changes sign
    for V, M in (("Vz", "My"), ("Vy", "Mz")):
        k, km = QUANTITIES.index(V), QUANTITIES.index(M)
        x_m = stationary_points(x, values[V][:x.size], lambda s, k=k: along.sections(s)[k])
        if x_m.size:
            at[M] = np.r_[x, x_m]
            values[M] = np.r_[values[M], along.sections(x_m)[km]]
    xd, d = deflection(frame, res, member, int(points), along=along)
    out = {}
    for key, xs, arr in [(k, at[k], v) for k, v in values.items()] + [("v", xd, d[:, 1]),
                                                                      ("w", xd, d[:, 2])]:
        out[key] = {"max": (float(arr.max()), float(xs[arr.argmax()])),
                    "min": (float(arr.min()), float(xs[arr.argmin()]))}
    return out


def deflection(frame, res, member: str, points: int = 21, axes: str = "member", along=None):
    """(x, d): the displacement d (n, 3) of the member's axis at ``points``
    sections and the load positions, x from node i, in member axes (u, v,
    w) or with ``axes="global"`` in global ones.  Integrated from the
    internal forces, as the plane frame's: on the flexible length u' =
    N/EA, v'' = Mz/EIz, w'' = My/EIy (each M compresses the fibre on its
    axis' + side, so the member bends towards it), with u at its start and
    v, w at both its ends given by the nodes through the rigid arms — which
    fixes the slope constants without the end rotations, so a released end
    needs nothing special; a rigid zone moves with its node (v = v_i + x
    θz_i, w = w_i - x θy_i).  Each integral is a 4-point Gauss rule between
    consecutive sections, which include every load position and the faces
    of the rigid zones: the integrand is a polynomial of degree <= 4 on
    each piece, so the curve is exact to rounding.  A Timoshenko member
    adds its shear strain, the face's force along +y (or +z) over G A_s,
    -Vy/(G A_sy) (or -Vz/(G A_sz)), to the slope."""
    if axes not in ("member", "global"):
        raise InvalidOptionError(f"axes: 'member' or 'global'; got {axes!r}")
    checked_member(frame, res, member, points)
    m = frame.members[member]
    along = along or Along(frame, res, member)
    L, R = along.L, along.R
    a, e = m["offsets"][0], L - m["offsets"][1]          # the flexible length [a, e]
    x = np.unique(np.r_[along.sample_points(points), [p for p in (a, e) if 0.0 < p < L]])
    t, wt = GAUSS
    lo, hi = np.maximum(x[:-1, None], a), np.minimum(x[1:, None], e)
    h = np.maximum(hi - lo, 0.0)[:, 0]
    gs = 0.5 * (hi - lo) * t + 0.5 * (lo + hi)               # (pieces, 4)
    gw = 0.5 * h[:, None] * wt
    N, Vy, Vz, _, My, Mz = (v.reshape(gs.shape) for v in along.sections(gs.ravel()))
    di, dj = (np.r_[R @ np.asarray(res.displacements[n][:3], float),
                    R @ np.asarray(res.displacements[n][3:], float)] for n in (m["i"], m["j"]))
    xf = np.clip(x, a, e)

    def running(per_piece):          # the integral from the first section to each
        return np.r_[0.0, np.cumsum(per_piece)]

    d = [di[0] + running((gw * N).sum(axis=1)) / (m["E"] * m["A"])]
    # across y: a rotation θz carries the axis along +y; across z: θy along -z
    for k, (M, I_, V, GAs, turn, sign) in enumerate(
            ((Mz, m["Iz"], Vy, m["GAs"][0], 5, 1.0), (My, m["Iy"], Vz, m["GAs"][1], 4, -1.0)),
            start=1):
        # piece by piece: the slope gains ∫ κ, the deflection the slope at the
        # piece's start times its length and ∫ (end - s) κ ds (exact, O(n))
        kappa = M / (m["E"] * I_)
        slope = running((gw * kappa).sum(axis=1))
        bend = running(slope[:-1] * h + (gw * (hi - gs) * kappa).sum(axis=1))
        if GAs is not None:          # a Timoshenko member's shear strain -V/(G A_s)
            bend = bend - running((gw * V).sum(axis=1)) / GAs
        start, end = di[k] + sign * a * di[turn], dj[k] - sign * (L - e) * dj[turn]
        curve = start + bend + (end - start - bend[-1]) * (xf - a) / (e - a)
        d.append(np.where(x < a, di[k] + sign * x * di[turn],
                          np.where(x > e, dj[k] - sign * (L - x) * dj[turn], curve)))
    for plane, solution in along.planes.items():     # second order: the beam-column's
        d[plane] = solution(x)[0]
    d = np.stack(d, axis=1)
    return x, (d if axes == "member" else d @ R)
