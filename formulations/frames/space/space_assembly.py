"""Assembly of a space frame (Osipova–Popov–Lovtsov's displacement method in
three dimensions): K and the load columns, the basic system, the contact
links H (a tangent the node's bilateral supports hold gets none) and the
faceted cones' maps to the LCP's unknowns; the LCP itself is the shared
:mod:`..mechanics.contact_lcp`'s."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from qpcontact.core.errors import InvalidProblemError

from ..mechanics import contact_lcp
from ..mechanics.member_forces import strain_free_motions
from ..mechanics.space_element import axes, condense, rotation, stiffness
from ..reporting.free_motion import refuse_singular
from . import space_member_loads, space_varying
from .space_results import DOFS


def assemble(frame, axial=None, along=None, loads=True):
    """(K (CSR), F (dofs x cases), fixed mask, cases, idx, local): local =
    the members' (k (m, 12, 12), T, dofs (m, 12), Fe (m, 12, cases):
    their fixed-end forces in member axes), as the plane frame's;
    ``axial``: the members' axial forces of a second-order stiffness;
    ``along``: the combination whose member loads' axial parts make N
    vary along the Euler–Bernoulli members that carry them, which then
    take N(x) in both bending planes (:mod:`.space_varying`, N̄ = ``axial``);
    ``loads`` False: K alone is meant (α_cr's count), the members' span
    loads left out of Fe and F."""
    names = list(frame.nodes)
    idx = {nm: 6 * k for k, nm in enumerate(names)}
    N = 6 * len(names)
    cases = frame.load_cases
    col = {c: k for k, c in enumerate(cases)}
    ms = list(frame.members.values())
    m = len(ms)
    k_local, T = np.zeros((m, 12, 12)), np.zeros((m, 12, 12))
    dofs, Fe = np.zeros((m, 12), int), np.zeros((m, 12, len(cases)))
    if ms:
        xi = np.array([frame.nodes[m_["i"]] for m_ in ms])
        xj = np.array([frame.nodes[m_["j"]] for m_ in ms])
        ref = np.array([np.full(3, np.nan) if m_["ref"] is None else m_["ref"] for m_ in ms])
        R = axes(xi, xj, ref, np.array([m_["roll"] for m_ in ms]))
        T = rotation(R)
        L = np.array([space_varying.member_length(a, b) for a, b in zip(xi, xj)])
        offsets = np.array([m_["offsets"] for m_ in ms], float).reshape(m, 2)
        Lf = L - offsets.sum(axis=1)                     # the flexible lengths
        phi = shear_parameters(ms, Lf)
        k_local = stiffness(*(np.array([m_[p] for m_ in ms]) for p in
                              ("E", "G", "A", "Iy", "Iz", "J")), Lf, axial, *phi.T)
        rigid = np.zeros_like(Fe)                        # loads on the rigid zones
        dofs = np.array([np.r_[idx[m_["i"]] + np.arange(6), idx[m_["j"]] + np.arange(6)]
                         for m_ in ms])
        where = {nm: k for k, nm in enumerate(frame.members)}
        for load in frame.span_loads if loads else ():
            k = where[load.member]
            if offsets[k].any():
                fe, at_nodes = space_member_loads.offset_fixed_end(load, L[k], R[k], phi[k],
                                                                   offsets[k])
                Fe[k, :, col[load.case]] += fe
                rigid[k, :, col[load.case]] += at_nodes
            elif load.whole_uniform(L[k]) and not phi[k].any():
                w = np.asarray(load.values[:3])
                q = w if load.axes == "member" else R[k] @ w
                Fe[k, :, col[load.case]] += fixed_end(q, L[k])
            else:      # a point load or a part of the member (its own module)
                Fe[k, :, col[load.case]] += space_member_loads.fixed_end(load, L[k], R[k],
                                                                         phi[k])
        varying = {}
        if axial is not None:
            if loads:
                beam_column_loads(frame, ms, axial, col, L, R, offsets, Fe)
            if along:
                varying = space_varying.varying_members(frame, ms, L, R, np.asarray(axial, float),
                                                        along, col, k_local, Fe)
        # end releases: the member's own end rotations condensed out, its
        # loads with them (the released end moments are zero)
        for k, m_ in enumerate(ms):
            if m_["releases"]:
                k_local[k], Fe[k] = condense(k_local[k], Fe[k], m_["releases"])
        # rigid end zones: the arms carry the flexible ends to the nodes
        # (after the releases, which act at the faces)
        for k in np.flatnonzero(offsets.any(axis=1)):
            A_ = space_member_loads.offset_map(*offsets[k])
            k_local[k] = A_.T @ k_local[k] @ A_
            Fe[k] = A_.T @ Fe[k] + rigid[k]
            if axial is not None:    # each rigid arm's own P-Δ, N o (θy² + θz²)/2
                # (θ²/2 ∫ N dx over the zone where N varies along the member)
                arms = varying.get(k, (axial[k] * offsets[k, 0], axial[k] * offsets[k, 1]))
                for at, arm in ((4, arms[0]), (10, arms[1])):
                    k_local[k][[at, at + 1], [at, at + 1]] += arm
    K, F = contact_lcp.global_stiffness((k_local, T, dofs, Fe), frame.springs, idx, DOFS, N)
    for node, v, case in frame.nodal_loads:
        F[idx[node]:idx[node] + 6, col[case]] += v
    Tn = node_axes(frame, idx, N)
    if Tn is not None:     # turned node axes: the system is written in them
        K = (Tn @ K @ Tn.T).tocsr()
        F = Tn @ F
    fixed = np.zeros(N, bool)
    for node, fx in frame.fixed.items():
        for d in fx:
            fixed[idx[node] + DOFS.index(d)] = True
    return K, F, fixed, cases, idx, (k_local, T, dofs, Fe), Tn


def node_axes(frame, idx, N):
    """Tn (sparse, orthogonal) turning global dofs into the nodes' own axes
    (u' = Tn u: a turned node's translations and rotations alike), or None
    where no node's axes are turned."""
    if not frame.node_axes:
        return None
    turned = list(frame.node_axes.items())
    blocks = np.array([np.kron(np.eye(2), turn) for _, turn in turned])      # (n, 6, 6)
    first = np.array([idx[node] for node, _ in turned])
    at = first[:, None] + np.arange(6)
    rows = np.repeat(at, 6, axis=1).ravel()
    cols = np.tile(at, (1, 6)).ravel()
    rest = np.setdiff1d(np.arange(N), at.ravel())
    return sp.csr_matrix((np.r_[blocks.ravel(), np.ones(rest.size)],
                          (np.r_[rows, rest], np.r_[cols, rest])), shape=(N, N))


def build(frame, axial=None, along=None):
    """The assembly the solving routes share with the plane frame (an
    :class:`~..mechanics.contact_lcp.Built`): K, loads, links, the basic system's LU,
    the faceted cones' maps; R and R_F on first use.  ``axial``: the
    members' axial forces of a second-order stiffness (``b["axial"]``);
    ``along``: the combination whose N(x) it took (:func:`assemble`),
    kept as ``b["along"]``."""
    check_conflicts(frame)
    K, F, fixed, cases, idx, local, Tn = assemble(frame, axial, along)
    N = K.shape[0]
    H, info = links(frame, idx, N)
    if Tn is not None:
        H = (Tn @ H).tocsr()
    flex = np.array([0.0 if frame.contacts[ci].stiffness is None
                     else 1.0 / frame.contacts[ci].stiffness for ci, _ in info])
    springs = np.zeros(N)
    for node, ks in frame.springs.items():
        for d, kval in ks.items():
            springs[idx[node] + DOFS.index(d)] += kval
    coords = np.array(list(frame.nodes.values()), float)
    basic = contact_lcp.basic_system(
        K, H, fixed, flex, np.arange(N) % 6 < 3,
        strain_free=None if axial is not None else
        lambda free: strain_free_motions(local, coords, springs, Tn, free, H))
    refuse_singular(basic, local, list(frame.nodes), DOFS, list(frame.nodes.values()), Tn,
                    contacts=bool(frame.contacts))
    b = contact_lcp.Built(springs=springs, names=list(frame.nodes), idx=idx, K=K, F=F,
                          coords=coords,
                          U=settlements(frame, idx, cases, F.shape), cases=cases,
                          fixed=fixed, H=H, info=info, flex=flex, local=local, Tn=Tn,
                          axial=None if axial is None else np.asarray(axial, float), **basic)
    b["maps"] = lcp_maps(frame, info)
    b["along"] = None if axial is None or not along else dict(along)
    return b


def shear_parameters(members, L) -> np.ndarray:
    """(m, 2): each member's φ = 12 EI / (G A_s L²) for shear along its
    local y (with Iz) and along z (with Iy); 0 where it has no shear area
    (Euler–Bernoulli)."""
    out = np.zeros((len(members), 2))
    for k, m in enumerate(members):
        for a, (GAs, I_) in enumerate(zip(m["GAs"], (m["Iz"], m["Iy"]))):
            if GAs is not None:
                out[k, a] = 12.0 * m["E"] * I_ / (GAs * L[k] ** 2)
    return out


def settlements(frame, idx, cases, shape) -> np.ndarray:
    """U (dofs x cases): the prescribed displacements of fixed dofs, per
    case (zero elsewhere)."""
    col = {c: k for k, c in enumerate(cases)}
    U = np.zeros(shape)
    for node, dof, case, value in frame.settlements:
        U[idx[node] + DOFS.index(dof), col[case]] += value
    return U


def held_at(frame, node, vec) -> bool:
    """Whether the bilateral supports at ``node`` fix the direction vec
    (global axes; the support's dofs are along the node's axes)."""
    fixed = frame.fixed.get(node, set())
    if node in frame.node_axes:
        vec = frame.node_axes[node] @ np.asarray(vec, float)
    return all(d in fixed for d, comp in zip(DOFS[:3], vec) if abs(comp) > 1e-12)


def held(frame, c, vec) -> bool:
    """Whether bilateral supports fix c's relative motion along vec: at
    its node, and for a pair at its other node too (held at one end only,
    the pair still opens or slides by the other's motion)."""
    return held_at(frame, c.node, vec) and (c.other is None or held_at(frame, c.other, vec))


def check_conflicts(frame):
    """A contact's normal that bilateral supports fix (for a pair, at both
    its nodes) makes the basic system singular: name it instead.  (A
    tangent they fix is no link: the support carries that part of the
    friction, :func:`links`.)"""
    for c in frame.contacts:
        if not held(frame, c, c.normal):
            continue
        if c.other is None:
            raise InvalidProblemError(
                f"node {c.node!r}: the contact's normal direction is already fixed by its "
                "bilateral support; a contact and a support may share a node only where "
                "they constrain different directions — remove one of them")
        raise InvalidProblemError(
            f"contact pair {c.node!r}-{c.other!r}: the pair's normal direction is fixed by "
            "the bilateral supports at both its nodes, so it can neither open nor close — "
            "remove the pair, or free that direction at one of its nodes")


def links(frame, idx, N):
    """H (N x links) and per link (contact, kind "n" | "t1" | "t2"): a
    link's direction at its node's translations, and opposite at its other
    node's for a pair (the pair pushes the two apart; its opening and slip
    are the relative motion).  A tangent that the node's bilateral
    supports hold gets no link (its slip is zero, its friction the
    support's reaction): a planar frame built in space, out-of-plane
    motion held, has the plane frame's links and, through the facets
    along the plane, its LCP."""
    rows, cols, vals, info = [], [], [], []
    for ci, c in enumerate(frame.contacts):
        kinds = ("n", "t1", "t2") if c.friction > 0 else ("n",)
        for kind, vec in zip(kinds, (c.normal, c.t1, c.t2)):
            if kind != "n" and held(frame, c, vec):
                continue
            for node, sign in ((c.node, 1.0), (c.other, -1.0))[:1 + (c.other is not None)]:
                rows += [idx[node] + d for d in range(3)]
                cols += [len(info)] * 3
                vals += list(sign * vec)
            info.append((ci, kind))
    H = sp.csr_matrix((vals, (rows, cols)), shape=(N, len(info)))
    H.eliminate_zeros()
    return H, info


def lcp_maps(frame, info):
    """(P, W, g, fric) as :func:`..plane.plane_assembly.links` gives the plane
    frame's: Δ = P z - g, w = W X; z = Z_n per contact, then the slips
    along each facet direction of each frictional contact."""
    nl = len(info)
    pos = {}
    for li, (ci, kind) in enumerate(info):
        pos.setdefault(ci, {})[kind] = li
    nc = len(frame.contacts)
    pr, pc, pv, wr, wc, wv = [], [], [], [], [], []
    g = np.zeros(nl)
    nz = nc
    fric = []
    for ci, c in enumerate(frame.contacts):
        pr.append(pos[ci]["n"]), pc.append(ci), pv.append(1.0)
        wr.append(ci), wc.append(pos[ci]["n"]), wv.append(1.0)
        g[pos[ci]["n"]] = c.gap
        angles = facet_angles(frame, c)
        if not angles.size:
            continue
        fric.append(ci)
        for a in angles:
            for kind, comp in (("t1", np.cos(a)), ("t2", np.sin(a))):
                if kind in pos[ci]:
                    pr.append(pos[ci][kind]), pc.append(nz), pv.append(comp)
                    wr.append(nz), wc.append(pos[ci][kind]), wv.append(comp)
            wr.append(nz), wc.append(pos[ci]["n"]), wv.append(c.friction * reach(frame, c))
            nz += 1
    P = sp.csr_matrix((pv, (pr, pc)), shape=(nl, nz))
    W = sp.csr_matrix((wv, (wr, wc)), shape=(nz, nl))
    P.eliminate_zeros(), W.eliminate_zeros()
    return P, W, g, fric


def facet_angles(frame, c) -> np.ndarray:
    """The angles of c's facet directions from t1 towards t2: the m-gon's,
    or where bilateral supports hold one tangent only ±(the other) — the
    cone is then the segment |X_t| <= f X_n, exact with two facets, and
    the m-gon's oblique facets only repeat it, looser, with slips that
    move nothing the two do not (a planar portal built in space: the
    load path could not prove its sliding collapse through them) — and
    none where both are held or without friction."""
    if c.friction == 0:
        return np.zeros(0)
    free = [not held(frame, c, t) for t in (c.t1, c.t2)]
    if all(free):
        # an inscribed m-gon's facets face the midpoints between its
        # vertices, which lie on the circle at 2πk/m
        turn = 0.5 if frame.cone == "inscribed" else 0.0
        return 2 * np.pi * (np.arange(c.facets) + turn) / c.facets
    if not any(free):
        return np.zeros(0)
    return np.array([0.0, np.pi]) + (0.0 if free[0] else 0.5 * np.pi)


def reach(frame, c) -> float:
    """How far c's facets stand from the cone's axis, per f X_n: 1 for a
    polygon around Coulomb's circle (or the exact segment of one free
    tangent), cos(π/m) for the m-gon inscribed in it."""
    if frame.cone == "inscribed" and facet_angles(frame, c).size > 2:
        return float(np.cos(np.pi / c.facets))
    return 1.0


def release_directions(frame, b):
    """Each contact's normal and tangents as columns over the dofs, in the
    system's (the nodes') axes, minus at ``other`` for a pair: (normals
    N x nc, [t1s, t2s], friction per contact)."""
    N = b["K"].shape[0]
    cols = []
    for vec in ("normal", "t1", "t2"):
        h = np.zeros((N, len(frame.contacts)))
        for ci, c in enumerate(frame.contacts):
            h[b["idx"][c.node]:b["idx"][c.node] + 3, ci] = getattr(c, vec)
            if c.other is not None:
                h[b["idx"][c.other]:b["idx"][c.other] + 3, ci] -= getattr(c, vec)
        cols.append(h if b["Tn"] is None else b["Tn"] @ h)
    return cols[0], cols[1:], np.array([c.friction for c in frame.contacts])


def beam_column_loads(frame, ms, axial, col, L, R, offsets, Fe) -> None:
    """Fe's bending rows of the members under axial force, in each bending
    plane: the beam-column's consistent loads of the flexible length
    (:func:`..mechanics.beam_column.into_loads`, the plane element's;
    Engesser's in a plane with shear deformation) — x-y with EIz on (v,
    θz), x-z with EIy on (w, θ' = −θy) — in place of the first-order
    element's."""
    from ..mechanics.beam_column import flexible_part, into_loads

    where = {nm: k for k, nm in enumerate(frame.members)}
    Lf = L - offsets.sum(axis=1)
    for plane, (I_, rows, signs) in enumerate((("Iz", (1, 5, 7, 11), (1.0, 1.0, 1.0, 1.0)),
                                               ("Iy", (2, 4, 8, 10), (1.0, -1.0, 1.0, -1.0)))):
        items = []
        for load in frame.span_loads:
            k = where[load.member]
            if axial[k] == 0.0:
                continue
            part = flexible_part(space_member_loads.plane_parts(load, R[k])[plane], L[k], 1.0,
                                 0.0, *offsets[k])
            if part is not None:
                items.append((k, col[load.case], part))
        EI = np.array([m_["E"] * m_[I_] for m_ in ms])
        shear = np.array([0.0 if m_["GAs"][plane] is None else 1.0 / m_["GAs"][plane]
                          for m_ in ms])
        into_loads(Fe, items, EI, np.asarray(axial, float), Lf, rows, signs, shear)


def fixed_end(q, L) -> np.ndarray:
    """Equivalent nodal loads (member axes, 12) of a uniform load q = (qx,
    qy, qz) per unit length over a member of length L."""
    qx, qy, qz = q
    m_y, m_z = qz * L * L / 12.0, qy * L * L / 12.0
    return np.array([qx * L / 2, qy * L / 2, qz * L / 2, 0.0, -m_y, m_z,
                     qx * L / 2, qy * L / 2, qz * L / 2, 0.0, m_y, -m_z])

