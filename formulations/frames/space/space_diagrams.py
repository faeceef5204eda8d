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

from ..mechanics.loads import stationary_points
from ..mechanics.space_element import EXTREMES, QUANTITIES
from ..mechanics.space_element import axes as member_axes


def geometry(frame, member: str):
    """(L, R) of a member: its length and the rows of its local x, y, z."""
    m = frame.members[member]
    xi, xj = frame.nodes[m["i"]], frame.nodes[m["j"]]
    return float(np.linalg.norm(xj - xi)), member_axes(xi, xj, m["ref"], m["roll"])[0]


def uniform_load(frame, res, member: str, R) -> np.ndarray:
    """The member's uniform load per unit length in member axes, summed
    over the cases of the result's combination with their factors."""
    q = np.zeros(3)
    for name, w, ax, case in frame.member_loads:
        factor = res.combination.get(case, 0.0)
        if name == member and factor:
            q += factor * (np.asarray(w, float) if ax == "member" else R @ np.asarray(w, float))
    return q


def checked_member(frame, res, member, points) -> str:
    """``member`` if the result can draw it; errors that say what to give."""
    if not isinstance(member, str):
        raise InvalidOptionError(f"member: a member's name, one of {list(frame.members)}; "
                                 f"got {member!r}")
    if member not in frame.members:
        raise InvalidProblemError(f"no member named {member!r}; members: {list(frame.members)}")
    if isinstance(points, str) and points in EXTREMES:
        raise InvalidOptionError(
            f"points: the number of sample points, not the quantity {points!r}; diagram "
            f"returns all of them, x, N, Vy, Vz, T, My, Mz = result.diagram({member!r}), or "
            f"give points=, e.g. result.diagram({member!r}, 41)")
    if isinstance(points, bool) or not isinstance(points, (int, np.integer)) or points < 2:
        raise InvalidOptionError(f"points: the number of sample points along the member, an "
                                 f"integer >= 2 (default 21); got {points!r}")
    if not res.member_forces:
        raise SolverFailedError(f"no diagram: this result is not an equilibrium ({res.message})")
    return member


def sections(frame, res, member: str, x) -> tuple:
    """(N, Vy, Vz, T, My, Mz) at the sections x (module docstring)."""
    x = np.asarray(x, float)
    _, R = geometry(frame, member)
    qx, qy, qz = uniform_load(frame, res, member, R)
    f = np.asarray(res.member_forces[member], float)
    return (-f[0] - qx * x, f[1] + qy * x, f[2] + qz * x, np.full_like(x, -f[3]),
            f[4] + f[2] * x + 0.5 * qz * x * x, -f[5] + f[1] * x + 0.5 * qy * x * x)


def diagram(frame, res, member: str, points: int = 21) -> tuple:
    """(x, N, Vy, Vz, T, My, Mz) at ``points`` sections from node i."""
    checked_member(frame, res, member, points)
    L, _ = geometry(frame, member)
    x = np.linspace(0.0, L, int(points))
    return (x, *sections(frame, res, member, x))


def end_forces(frame, res, member: str) -> dict:
    """{"i": {"N": ..., ..., "Mz": ...}, "j": {...}}: the internal forces at
    the member's ends in the diagrams' convention — each end's from its own
    end actions (at j: N_j, -Vy_j, -Vz_j, T_j, -My_j, Mz_j), not carried
    along the member from i, which would add the rounding of the loads."""
    checked_member(frame, res, member, 2)
    f = np.asarray(res.member_forces[member], float)
    sign = np.array([-1.0, 1.0, 1.0, -1.0, 1.0, -1.0])
    return {end: {q: float(v) + 0.0 for q, v in zip(QUANTITIES, s * f[o:o + 6])}
            for end, o, s in (("i", 0, sign), ("j", 6, -sign))}


def extremes(frame, res, member: str, points: int = 201) -> dict:
    """{quantity: {"max": (value, x), "min": (value, x)}} for the internal
    forces and the deflections v, w across the member, at ``points``
    sections; the moments also where their shear changes sign between
    them (:func:`..mechanics.loads.stationary_points`), so a span's largest
    moment is exact, not the nearest sample's."""
    checked_member(frame, res, member, points)
    L, _ = geometry(frame, member)
    x = np.linspace(0.0, L, int(points))
    values = dict(zip(QUANTITIES, sections(frame, res, member, x)))
    at = {q: x for q in QUANTITIES}
    # the span moments between the samples: where V = dM/dx changes sign
    for V, M in (("Vz", "My"), ("Vy", "Mz")):
        k, km = QUANTITIES.index(V), QUANTITIES.index(M)
        x_m = stationary_points(x, values[V],
                                lambda s, k=k: sections(frame, res, member, s)[k])
        if x_m.size:
            at[M] = np.r_[x, x_m]
            values[M] = np.r_[values[M], sections(frame, res, member, x_m)[km]]
    from ..reporting.space_drawing import member_deflection

    xd, d = member_deflection(frame, res, member, int(points))
    out = {}
    for key, xs, arr in [(k, at[k], v) for k, v in values.items()] + [("v", xd, d[:, 1]),
                                                                      ("w", xd, d[:, 2])]:
        out[key] = {"max": (float(arr.max()), float(xs[arr.argmax()])),
                    "min": (float(arr.min()), float(xs[arr.argmin()]))}
    return out
