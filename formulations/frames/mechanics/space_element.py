"""Space-frame members: the 3-D beam-column element's
stiffness and its rotation to global axes, for all members at once.

Member axes: x from node i to node j; y and z the section's principal axes,
fixed by a reference vector ``ref`` that lies in the member's local x-z
plane (OpenSees' ``vecxz``): z = x × (ref × x) normalised, y = z × x; a roll
angle turns y and z about x afterwards.  The default reference is global Z
(vertical: y then lies horizontal), or global X for a vertical member.

End dofs (member axes), at i then j: u, v, w (translations along x, y, z),
θx (twist), θy, θz — 12 per member.  Units the user's, consistent: E, G in
force/length², A in length², Iy, Iz (second moments about y and z) and J
(torsion constant) in length⁴.

Stiffness (Euler-Bernoulli bending in each principal plane, Saint-Venant
torsion, no warping, no coupling between the planes — a doubly symmetric
section or the principal axes of any section through its shear centre):

* axial EA/L on (u_i, u_j); torsion GJ/L on (θx_i, θx_j);
* bending in the x-y plane (EIz): v with θz, the plane frame's 4 x 4 block;
* bending in the x-z plane (EIy): w with θy, the same block with the signs of
  the couplings reversed, since a positive θy turns +z towards -x
  (dw/dx = -θy while dv/dx = +θz).
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from .second_order import stability_functions

#: the internal forces along a space member (member axes), in the order of a
#: result's ``diagram`` (docs/frames.md, "Conventions")
QUANTITIES = ("N", "Vy", "Vz", "T", "My", "Mz")
#: what a result's ``extremes`` gives: the internal forces and the
#: deflection of the axis across the member along its local y (v) and z (w)
EXTREMES = QUANTITIES + ("v", "w")


def stiffness(E, G, A, Iy, Iz, J, L, N=None, phi_y=0.0, phi_z=0.0) -> np.ndarray:
    """Local stiffness of space-frame members, (m, 12, 12) (or (12, 12) for
    scalars); dofs (u, v, w, θx, θy, θz) at i then j.  ``N``: the members'
    axial forces (tension positive) for the second-order stiffness — each
    bending plane's block from its stability functions
    (:mod:`.second_order`), torsion and the axial row as first order.
    ``phi_y``, ``phi_z``: shear deformation along local y (bending about z)
    and along z (about y), φ = 12 EI / (G A_s L²): the exact two-node
    Timoshenko block of each plane, the plane frame's (12EI/(L³(1+φ)),
    6EI/(L²(1+φ)), (4+φ)EI/(L(1+φ)), (2−φ)EI/(L(1+φ))); with ``N``
    Engesser's Timoshenko beam-column of that plane's φ, as the plane
    frame's."""
    E, G, A, Iy, Iz, J, L, N, phi_y, phi_z = np.broadcast_arrays(
        *(np.asarray(v, float) for v in (E, G, A, Iy, Iz, J, L, 0.0 if N is None else N,
                                         phi_y, phi_z)))
    k = np.zeros(E.shape + (12, 12))

    def put(a, b, value):
        k[..., a, b] = value
        k[..., b, a] = value

    ea, gj = E * A / L, G * J / L
    for (a, b), s in (((0, 0), 1), ((6, 6), 1), ((0, 6), -1)):
        put(a, b, s * ea)
    for (a, b), s in (((3, 3), 1), ((9, 9), 1), ((3, 9), -1)):
        put(a, b, s * gj)
    # bending: (translation, rotation) dofs of each plane and the sign that
    # relates the rotation to the slope (+θz = dv/dx, -θy = dw/dx)
    for EI, t, r, sign, phi in ((E * Iz, 1, 5, 1.0, phi_y), (E * Iy, 2, 4, -1.0, phi_z)):
        tt = -N * L ** 2 / EI
        s_, sc = stability_functions(tt, phi)
        b12, b6 = (2 * (s_ + sc) - tt) * EI / L ** 3, (s_ + sc) * EI / L ** 2
        b4, b2 = s_ * EI / L, sc * EI / L
        ti, tj, ri, rj = t, t + 6, r, r + 6
        put(ti, ti, b12)
        put(tj, tj, b12)
        put(ti, tj, -b12)
        put(ri, ri, b4)
        put(rj, rj, b4)
        put(ri, rj, b2)
        put(ti, ri, sign * b6)
        put(ti, rj, sign * b6)
        put(tj, ri, -sign * b6)
        put(tj, rj, -sign * b6)
    return k


def axes(xi, xj, ref=None, roll=0.0) -> np.ndarray:
    """Rotation matrices (m, 3, 3) whose rows are the members' local x, y, z
    in global components (see the module docstring); ``xi``, ``xj`` (m, 3)
    end coordinates, ``ref`` (m, 3) (a row of NaN: the default) or None,
    ``roll`` (m,) radians."""
    xi, xj = np.atleast_2d(np.asarray(xi, float)), np.atleast_2d(np.asarray(xj, float))
    d = xj - xi
    L = np.linalg.norm(d, axis=1)
    if np.any(L == 0):
        raise InvalidProblemError(f"space-frame member {int(np.argmin(L))}: its nodes coincide")
    x = d / L[:, None]
    # the default reference (rows of NaN, or ref None): Z, or X for a vertical member
    vertical = np.abs(x[:, 2]) > 1.0 - 1e-9
    default = np.where(vertical[:, None], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    ref = default if ref is None else np.broadcast_to(np.asarray(ref, float), x.shape)
    ref = np.where(np.isnan(ref), default, ref)
    z = np.cross(x, np.cross(ref, x))
    zn = np.linalg.norm(z, axis=1)
    bad = zn <= 1e-9 * np.linalg.norm(ref, axis=1)
    if np.any(bad):
        raise InvalidProblemError(
            f"space-frame member {int(np.flatnonzero(bad)[0])}: its reference vector is "
            "parallel to the member; give one in the plane of the member's local x-z axes")
    z = z / zn[:, None]
    y = np.cross(z, x)
    roll = np.broadcast_to(np.asarray(roll, float), L.shape)
    c, s = np.cos(roll)[:, None], np.sin(roll)[:, None]
    y, z = c * y + s * z, -s * y + c * z
    return np.stack([x, y, z], axis=1)


def rotation(R) -> np.ndarray:
    """T (m, 12, 12): the four 3 x 3 blocks of R, global end dofs to member axes."""
    R = np.asarray(R, float)
    T = np.zeros(R.shape[:-2] + (12, 12))
    for o in range(0, 12, 3):
        T[..., o:o + 3, o:o + 3] = R
    return T


#: a member end's rotations by name, and their rows in the member's 12 dofs
END_ROTATIONS = {"rx": 3, "ry": 4, "rz": 5}


def condense(k, fe, released) -> tuple:
    """A member's stiffness (12, 12) and loads (12, cases) with its end
    rotations ``released`` — (row, spring) pairs — joined to their nodes
    through rotational springs (moment per radian; 0: a hinge), as the
    plane frame's releases: the member's own end rotation is an extra dof
    between the member and the spring, condensed out (static condensation:
    k' = k - k_r k_rᵀ / k_rr, f' = f - k_r f_r / k_rr), after which row r
    belongs to the node's rotation again.  A hinge leaves that row empty:
    the node's rotation gets nothing from this member, its moment is zero."""
    k, fe = np.array(k, float), np.array(fe, float)
    for r, spring in released:
        n = k.shape[0]
        big = np.zeros((n + 1, n + 1))
        big[:n, :n] = k
        big[r, r] += spring
        big[r, n] = big[n, r] = -spring
        big[n, n] = spring
        col = big[:, r].copy()
        fb = np.vstack([fe, np.zeros((1, fe.shape[1]))])
        fb = fb - np.outer(col, fb[r]) / big[r, r]
        big = big - np.outer(col, col) / big[r, r]
        keep = [n if d == r else d for d in range(n)]     # the node's rotation in r's place
        k, fe = big[np.ix_(keep, keep)], fb[keep]
    return k, fe
