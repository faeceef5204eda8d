"""Plane frame elements: the member's local stiffness (Euler-Bernoulli or
Timoshenko), its rotation to global axes, end releases (hinges, semi-rigid
springs) and rigid end zones, and their equivalent nodal loads — for all
members at once (:func:`member_locals`), which :mod:`.assembly` scatters
into the frame's K and F.  Member axes: x from node i to node j, y turned
counterclockwise; end dofs (u, v, θ) at i then j; units the user's."""

from __future__ import annotations

import math
from itertools import chain
from operator import attrgetter

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from .loads import equivalent_nodal_many, offset_parts
from .second_order import stability_functions

#: A plane frame node's degrees of freedom, in the order of its rows.
DOFS = ("ux", "uy", "rz")


def beam_column_k(E, A, I, L, N, phi=0.0) -> np.ndarray:
    """Local stiffness (m, 6, 6) of members carrying axial forces N
    (tension positive): the stability functions s, s c of t = −N L²/EI
    and the shear parameter φ (:mod:`.second_order`: Livesley's for
    Euler–Bernoulli members, φ = 0; Engesser's Timoshenko beam-column for
    φ > 0) in place of 4, 2 (or (4 + φ)/(1 + φ), (2 − φ)/(1 + φ)) and the
    P-Δ shear in the transverse term."""
    E, A, I, L, N, phi = np.broadcast_arrays(
        *(np.asarray(v, float) for v in (E, A, I, L, N, phi)))
    f = E * I / L
    t = -N * L ** 2 / (E * I)
    s, sc = stability_functions(t, phi)
    return beam_layout(E * A / L, (2.0 * (s + sc) - t) * f / L ** 2, (s + sc) * f / L, s * f,
                       sc * f)


def beam_layout(a, vv, vt, tt, tc) -> np.ndarray:
    """The (…, 6, 6) matrix of a plane member in its axes, end dofs (u, v,
    θ) at i then j, from its axial term a, transverse vv, transverse-to-
    rotation vt, rotation tt and carried-over rotation tc (first order:
    EA/L, 12EI/L³, 6EI/L², 4EI/L, 2EI/L, which the compiled
    :func:`._frame_kernels.plane_members` lays out the same way)."""
    k = np.zeros(np.shape(a) + (6, 6))
    k[..., 0, 0] = k[..., 3, 3] = a
    k[..., 0, 3] = k[..., 3, 0] = -a
    k[..., 1, 1] = k[..., 4, 4] = vv
    k[..., 1, 4] = k[..., 4, 1] = -vv
    k[..., 1, 2] = k[..., 2, 1] = k[..., 1, 5] = k[..., 5, 1] = vt
    k[..., 2, 4] = k[..., 4, 2] = k[..., 4, 5] = k[..., 5, 4] = -vt
    k[..., 2, 2] = k[..., 5, 5] = tt
    k[..., 2, 5] = k[..., 5, 2] = tc
    return k


def geometry(frame, m):
    """(L, cos, sin) of a member's axis."""
    d = frame.nodes[m.j] - frame.nodes[m.i]
    L = math.hypot(d[0], d[1])
    if L == 0:
        raise InvalidProblemError(f"member {m.name}: nodes {m.i} and {m.j} coincide")
    return L, float(d[0]) / L, float(d[1]) / L


def rotation(c, s) -> np.ndarray:
    """T (6x6, or (m, 6, 6) for arrays): global end displacements to member axes."""
    c, s = np.broadcast_arrays(np.asarray(c, float), np.asarray(s, float))
    T = np.zeros(c.shape + (6, 6))
    for o in (0, 3):
        T[..., o, o] = T[..., o + 1, o + 1] = c
        T[..., o, o + 1] = s
        T[..., o + 1, o] = -s
        T[..., o + 2, o + 2] = 1.0
    return T


def _offset_map(oi, oj) -> np.ndarray:
    """Node displacements (member axes) to the flexible ends': the rigid arm
    of length oi moves the end across the axis by oi·θ_i, at j by -oj·θ_j."""
    A = np.eye(6)
    A[1, 2], A[4, 5] = oi, -oj
    return A


def _release(k, fe, r, spring):
    """Condense the member end's own rotation (dof r) behind a rotational
    spring to the node (0: a hinge): row/column r then belong to the node's
    rotation.  The member's loads fe (6, cases) are condensed alike."""
    k7 = np.zeros((7, 7))
    k7[:6, :6] = k
    k7[r, r] += spring
    k7[r, 6] = k7[6, r] = -spring
    k7[6, 6] = spring
    col = k7[:, r].copy()
    kc = k7 - np.outer(col, col) / k7[r, r]
    keep = [6 if d == r else d for d in range(6)]
    f7 = np.vstack([fe, np.zeros((1, fe.shape[1]))])
    fc = f7 - np.outer(col, f7[r]) / k7[r, r]
    return kc[np.ix_(keep, keep)], fc[keep]


def varying_members(ms, L, c, s, axial, along, col, k_all, Fe) -> dict:
    """The members whose loads in ``along`` (a combination) have axial
    parts: their bending block of
    ``k_all`` and rows of ``Fe`` (each case's loads) set to the beam-column's under N(x)
    (:class:`.varying_axial.Member`, N̄ = ``axial``); {index: (zone i's
    ∫ N dx, zone j's)}, their rigid arms' P-Δ per unit rotation."""
    from .beam_column import flexible_part
    from .varying_axial import Member, of_member

    rows = [1, 2, 4, 5]
    members = {k: member for k, m in enumerate(ms)
               if along and m.loads
               for member in [of_member(m, L[k], c[k], s[k], axial[k], along, False)]
               if member is not None}
    Member.in_one_pass(list(members.values()))
    for k, member in members.items():
        m = ms[k]
        offsets = (m.offset_i, m.offset_j)
        k_all[k][np.ix_(rows, rows)] = member.stiffness()
        Fe[k][rows] = 0.0
        for case, j in col.items():
            loads = [part for ld in m.loads if ld.case == case
                     for part in [flexible_part(ld, L[k], c[k], s[k], *offsets)] if part]
            if loads:
                Fe[k][rows, j] = member.nodal_loads(loads)
    return {k: member.arms() for k, member in members.items()}


def member_locals(frame, xy, idx, col, axial=None, along=None, loads=True):
    """Every member's local stiffness (node dofs, member axes), rotation,
    dofs and equivalent nodal loads per case, computed for all members at
    once: (k (m,6,6), T (m,6,6), dofs (m,6), Fe (m,6,cases)); ``xy`` the
    nodes' coordinates (n, 2), ``idx`` each node's first dof, ``col`` maps
    a case to its column.  ``axial`` (m,): the members' axial forces
    (tension positive) for a second-order stiffness
    (:mod:`.second_order`), None for first order; ``along``: the
    combination ({case: factor}) whose member loads' axial parts make N
    vary along the Euler–Bernoulli members that carry them, which then
    take N(x) as it is (:mod:`.varying_axial`, N̄ = ``axial``); ``loads``
    False: the stiffness alone (Fe left without the members' span loads but
    where N varies along a member) — α_cr's count reads K only, and the
    loads were half a space frame's tangent."""
    ms = list(frame.members.values())
    nm = len(ms)
    # one pass over the members for their numbers, their nodes' first dofs
    # among them (a Python call per member and property cost 2 ms on a
    # 400-member beam; three passes, a tenth of its assembly)
    # (and whether an end is released, how many loads it carries: two more
    # passes before, a sixth of a 400-member beam's assembly)
    i3, j3, E, A, I, oi, oj, GAs, released, n_loads = np.fromiter(chain.from_iterable(
        [(idx[m.i], idx[m.j], m.E, m.A, m.I, m.offset_i, m.offset_j,
          0.0 if m.GAs is None else m.GAs,
          m.hinge_i or m.hinge_j or m.spring_i is not None or m.spring_j is not None,
          len(m.loads)) for m in ms]), float, 10 * nm).reshape(nm, 10).T
    # the members' geometry, first-order stiffness, rotations and dofs in
    # one compiled loop (as array expressions: dozens of NumPy calls)
    from ._frame_kernels import plane_members
    L, c, s, Lf, phi, k_all, T, dofs = plane_members(i3, j3, E, A, I, oi, oj, GAs, xy)
    if axial is not None:          # the beam-column's, Timoshenko members' with their φ
        axial = np.asarray(axial, float)
        k_all = beam_column_k(E, A, I, Lf, axial, phi)
    has_offset = (oi > 0) | (oj > 0)
    offset = np.flatnonzero(has_offset).tolist()
    Fe = np.zeros((nm, 6, len(col)))
    # every load with its member's index, in member order
    plain = list(chain.from_iterable(map(attrgetter("loads"), ms)))
    rows = np.repeat(np.arange(nm), n_loads.astype(int))
    if offset:
        plain = [ld for k, ld in zip(rows.tolist(), plain) if not has_offset[k]]
        rows = rows[~has_offset[rows]]
    if plain and loads:
        nodal = equivalent_nodal_many(plain, L[rows], c[rows], s[rows], phi[rows])
        # summed into Fe entry by entry in the loads' order, as np.add.at
        # (bincount: a third of add.at's time with three index arrays)
        nc = len(col)
        case = np.fromiter(map(col.__getitem__, map(attrgetter("case"), plain)), int, len(plain))
        at = ((rows * 6)[:, None] + np.arange(6)) * nc + case[:, None]
        Fe = np.bincount(at.ravel(), nodal.ravel(), nm * 6 * nc).reshape(nm, 6, nc)
    rigid = {k: np.zeros((6, len(col))) for k in offset}
    for k in offset if loads else ():
        for ld in ms[k].loads:
            fe, at_nodes = offset_parts(ld, L[k], c[k], s[k], phi[k],
                                        (ms[k].offset_i, ms[k].offset_j))
            Fe[k, :, col[ld.case]] += fe
            rigid[k][:, col[ld.case]] += at_nodes
    if axial is not None:
        # members' loads under a constant N: the beam-column's fixed-end
        # forces (:mod:`.beam_column`, Engesser's with shear) across the axis
        from .beam_column import flexible_part, into_loads
        varying = varying_members(ms, L, c, s, axial, along, col, k_all, Fe)
        items = [] if not loads else [(k, col[ld.case], part)
                 for k in np.flatnonzero((n_loads > 0) & (axial != 0)).tolist()
                 if k not in varying
                 for ld in ms[k].loads
                 for part in [flexible_part(ld, L[k], c[k], s[k], ms[k].offset_i,
                                            ms[k].offset_j)] if part is not None]
        shear = np.divide(1.0, GAs, out=np.zeros(nm), where=GAs > 0)      # 1/(G A_s)
        into_loads(Fe, items, E * I, axial, Lf, (1, 2, 4, 5), c=shear)
    # releases act at the flexible ends (the face of the rigid zone), so
    # they come before the rigid arms carry the end to the node
    for k in np.flatnonzero(released).tolist():
        for r, spring in zip((2, 5), ms[k].end_springs):
            if spring is not None:
                k_all[k], Fe[k] = _release(k_all[k], Fe[k], r, spring)
    for k in offset:
        Aoff = _offset_map(ms[k].offset_i, ms[k].offset_j)
        k_all[k] = Aoff.T @ k_all[k] @ Aoff
        Fe[k] = Aoff.T @ Fe[k] + rigid[k]
        if axial is not None:        # each rigid arm's own P-Δ, N o θ²/2 (second_order)
            # (θ²/2 ∫ N dx over the zone where N varies along the member)
            arm_i, arm_j = varying.get(k, (axial[k] * ms[k].offset_i,
                                           axial[k] * ms[k].offset_j))
            k_all[k][2, 2] += arm_i
            k_all[k][5, 5] += arm_j
    return k_all, T, dofs, Fe
