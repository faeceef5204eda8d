"""Assembly of a plane frame (Osipova–Popov–Lovtsov's displacement method):
K, the loads and settlements per case, the turned node axes, the contact
links H and their maps to the LCP's unknowns; the basic system and the LCP
itself are the shared :mod:`..mechanics.contact_lcp`'s."""

from __future__ import annotations

import math
from itertools import chain
from operator import attrgetter

import numpy as np
import scipy.sparse as sp

from qpcontact.core.errors import InvalidProblemError

from ..mechanics.contact_lcp import Built, basic_system, global_stiffness
from ..mechanics.loads import CONSTANT, VARIABLE
from ..mechanics.member_forces import strain_free_motions
from ..mechanics.plane_element import DOFS, member_locals
from ..reporting.free_motion import refuse_singular


def cases(frame) -> list:
    """Every load case with a load, plus the pair (constant, variable) of the
    split constant + p x variable."""
    names = {CONSTANT, VARIABLE}
    names.update(ld[4] for ld in frame.nodal_loads)
    names.update(st[2] for st in frame.settlements)
    # the member loads' cases read in C (map, chain): a generator over the
    # members and their loads was a sixth of a 20-storey tower's assembly
    names.update(map(attrgetter("case"), chain.from_iterable(
        map(attrgetter("loads"), frame.members.values()))))
    return sorted(names)


def assemble(frame, axial=None, along=None, loads=True):
    """K (CSR), loads F and settlements U (one column per case), the fixed
    dofs, the members' local data for the results (k, T, dofs, Fe) and the
    nodes' coordinates: all members at once (K and the members' loads F
    in one compiled pass: :func:`..mechanics.contact_lcp.global_stiffness`);
    ``loads`` False: K alone is meant (the members' span loads left out of F,
    :func:`..mechanics.plane_element.member_locals`)."""
    names = list(frame.nodes)
    idx = dict(zip(names, range(0, 3 * len(names), 3)))
    N = 3 * len(names)
    # the nodes' coordinates once, for the members and the checks
    xy = (np.concatenate(list(frame.nodes.values())).reshape(-1, 2) if names
          else np.zeros((0, 2)))
    case_list = cases(frame)
    col = {c: k for k, c in enumerate(case_list)}
    nc = len(case_list)
    if frame.members:
        local = member_locals(frame, xy, idx, col, axial, along, loads)
    else:
        local = (np.zeros((0, 6, 6)), np.zeros((0, 6, 6)), np.zeros((0, 6), np.int64),
                 np.zeros((0, 6, nc)))
    K, F = global_stiffness(local, frame.springs, idx, DOFS, N)
    if frame.nodal_loads:
        # added one by one in the loads' order, as a loop over them did
        # (np.add.at's order; the loop cost 2 µs a load)
        at = np.fromiter(chain.from_iterable((idx[node], col[case]) for node, *_, case
                                             in frame.nodal_loads), int,
                         2 * len(frame.nodal_loads)).reshape(-1, 2)
        np.add.at(F, ((at[:, :1] + np.arange(3)).ravel(), np.repeat(at[:, 1], 3)),
                  np.array([ld[1:4] for ld in frame.nodal_loads], float).ravel())
    U = np.zeros_like(F)   # prescribed displacements (settlements) of fixed dofs, per case
    for node, dof, case, value in frame.settlements:
        U[idx[node] + DOFS.index(dof), col[case]] += value
    Tn = node_axes(frame, idx, N)
    if Tn is not None:     # turned node axes: the system is written in them
        K = (Tn @ K @ Tn.T).tocsr()
        F = Tn @ F
    fixed = np.zeros(N, bool)
    for node, dofs_fixed in frame.fixed.items():
        for d in dofs_fixed:
            fixed[idx[node] + DOFS.index(d)] = True
    # a rotation no member resists (only hinged ends, or no member) is not a
    # dof — exactly zero: a hinge condenses to exact zeros, and a tiny
    # rotational spring is a spring.  A moment applied there has nothing to
    # act on; it is refused rather than lost
    free_spin = (K.diagonal() == 0.0) & (np.arange(N) % 3 == 2) & ~fixed
    if free_spin.any():
        lost = np.flatnonzero(free_spin & np.any(F != 0.0, axis=1))
        if lost.size:
            node = names[lost[0] // 3]
            raise InvalidProblemError(
                f"node {node!r}: a moment is applied where no member and no support resists "
                "rotation (only released ends meet there), so it would act on nothing; put "
                "it on a member end that is not released (add_point_load(member, a, mz=...)) "
                "or release one end fewer")
        fixed |= free_spin
    # per member, for the results: stiffness, rotation, dofs, and the
    # equivalent nodal loads of every case (member axes), (m, 6, cases)
    return names, idx, K, F, U, case_list, fixed, local, Tn, xy


def node_axes(frame, idx, N):
    """Tn (sparse, orthogonal) turning global dofs into the nodes' own axes
    (u' = Tn u), or None where no node's axes are turned."""
    if not frame.node_angles:
        return None
    Tn = sp.lil_matrix((N, N))
    Tn.setdiag(1.0)
    for node, a in frame.node_angles.items():
        i = idx[node]
        c, s = math.cos(a), math.sin(a)
        Tn[i, i], Tn[i, i + 1], Tn[i + 1, i], Tn[i + 1, i + 1] = c, s, -s, c
    return Tn.tocsr()


def contact_column(idx, N, c, vec) -> np.ndarray:
    """The column of H mapping a force along ``vec`` at contact c to the
    nodal forces (minus at ``other`` for a pair)."""
    h = np.zeros(N)
    h[idx[c.node]:idx[c.node] + 2] += vec
    if c.other is not None:
        h[idx[c.other]:idx[c.other] + 2] -= vec
    return h


def contact_table(frame, idx) -> np.ndarray:
    """The contacts' numbers in one pass, (nc, 7): the node's first dof, the
    other node's (-1 for none), the unit normal, the friction coefficient,
    the gap and the flexibility 1/k (0 for a rigid contact) — what the
    links, their maps and the results read (four passes over the contacts
    before: a tenth of a 200-span beam's assembly)."""
    cs = frame.contacts
    return np.fromiter(chain.from_iterable(
        (idx[c.node], -1 if c.other is None else idx[c.other], c.normal[0], c.normal[1],
         c.friction, c.gap, 0.0 if c.stiffness is None else 1.0 / c.stiffness)
        for c in cs), float, 7 * len(cs)).reshape(len(cs), 7)


def links(frame, idx, N, table=None):
    """H (N x links, sparse CSR), per link its contact index and kind
    'n'/'t', the contacts as arrays (:func:`contact_arrays`) and the LCP's
    maps (P, W, g, fric): the link displacements Δ = P z − g and the LCP's
    w = W X as sparse selections with the friction coefficients (z = Z_n
    per contact, then Z⁺, Z⁻ per frictional contact; ``fric`` the
    frictional contacts' indices) — all in one compiled pass over the
    contacts (:func:`._plane_kernels.contact_links`; as array expressions
    dozens of NumPy calls on a tower's 17 contacts); ``table``:
    :func:`contact_table`'s, where made already."""
    from ._plane_kernels import contact_links
    table = contact_table(frame, idx) if table is None else table
    (n_link, t_link, h_ptr, h_ind, h_val, p_ptr, p_ind, p_val, w_ptr, w_ind, w_val,
     g) = contact_links(table, N)
    nl, nz = len(p_ptr) - 1, len(w_ptr) - 1
    fric = t_link >= 0
    info = [(ci, kind) for ci, f in enumerate(fric.tolist()) for kind in ("n", "t")[:1 + f]]
    # (int32 indices: scipy keeps them as they are, where int64 ones are
    # scanned and copied at every construction)
    H = sp.csr_matrix((h_val, h_ind, h_ptr), shape=(N, nl))
    maps = (sp.csr_matrix((p_val, p_ind, p_ptr), shape=(nl, nz)),
            sp.csr_matrix((w_val, w_ind, w_ptr), shape=(nz, nl)), g, np.flatnonzero(fric).tolist())
    node, other = table[:, 0].astype(int), table[:, 1].astype(int)
    arrays = dict(n_link=n_link, t_link=t_link, mu=table[:, 4], gap=table[:, 5],
                  normal=table[:, 2:4], node=node // 3, other=np.where(other >= 0, other // 3, -1))
    return H, info, arrays, maps


def check_conflicts(frame):
    """A contact whose normal (or tangent, with friction) displacement the
    bilateral supports already fix would make the basic system singular:
    name the node and the dofs instead."""
    for c in frame.contacts:
        if c.other is not None or c.node not in frame.fixed:
            continue
        fixed = frame.fixed[c.node]
        dirs = [("normal", c.normal)]
        if c.friction > 0:
            dirs.append(("tangential", np.array([c.normal[1], -c.normal[0]])))
        angle = frame.node_angles.get(c.node, 0.0)
        turn = np.array([[math.cos(angle), math.sin(angle)], [-math.sin(angle), math.cos(angle)]])
        for what, vec in dirs:
            vec = np.where(np.abs(turn @ vec) <= 1e-12, 0.0, turn @ vec)
            free_axes = [d for d, comp in zip(("ux", "uy"), vec) if abs(comp) > 0 and d not in fixed]
            if not free_axes:
                held = sorted(d for d, comp in zip(("ux", "uy"), vec) if abs(comp) > 0)
                shown = tuple(float(v) + 0.0 for v in np.round(vec, 6))
                raise InvalidProblemError(
                    f"node {c.node!r}: the contact's {what} direction {shown} is "
                    f"already fixed by its bilateral support ({', '.join(held)}); a contact and a "
                    "support may share a node only where they constrain different directions — "
                    "remove one of them")


def build(frame, axial=None, along=None):
    """Assemble K, the links, and the LU of the basic system (every link
    fixed).  Returns a :class:`Built` with everything the routes and the
    results need; R and R_F come on first use.  ``axial``: the members'
    axial forces (tension positive, in the order of ``frame.members``) of
    a second-order stiffness, kept as ``b["axial"]``; None: first order;
    ``along``: the combination whose member loads' axial parts make N vary
    along the members (:func:`..mechanics.plane_element.member_locals`),
    kept as ``b["along"]``."""
    check_conflicts(frame)
    names, idx, K, F, U, case_list, fixed, local, Tn, coords = assemble(frame, axial, along)
    N = K.shape[0]
    table = contact_table(frame, idx)
    H, info, arrays, maps = links(frame, idx, N, table)
    if Tn is not None:
        H = (Tn @ H).tocsr()
    # Elastic contacts: the link's displacement is the structure's plus the
    # spring's, H'u + D X = Δ (D = diag 1/k), so D enters the saddle matrix
    # (scaled like the links) and R, R_F come out elastic — no dense
    # (I + R D)⁻¹ on nl x nl.
    # one number per contact, then spread to its links (a lookup per link
    # through frame.contacts cost half a millisecond on a 200-span beam)
    flex = np.repeat(table[:, 6], 1 + (table[:, 4] > 0))   # a contact's links follow it
    has_t = arrays["t_link"] >= 0     # each frictional contact's tangent and normal link
    springs = np.zeros(N)
    for node, ks in frame.springs.items():
        for d, kval in ks.items():
            springs[idx[node] + DOFS.index(d)] += kval
    basic = basic_system(K, H, fixed, flex, np.arange(N) % 3 != 2,
                         (arrays["t_link"][has_t], arrays["n_link"][has_t]),
                         strain_free=None if axial is not None else
                         lambda free: strain_free_motions(local, coords, springs, Tn, free, H))
    refuse_singular(basic, local, names, DOFS, [frame.nodes[n] for n in names], Tn,
                    contacts=bool(frame.contacts),
                    members=[(m.name, m.i, m.j) for m in frame.members.values()])
    b = Built(springs=springs, names=names, idx=idx, K=K, F=F, U=U, cases=case_list,
              coords=coords,
              fixed=fixed, H=H, info=info, flex=flex, local=local, Tn=Tn,
              axial=None if axial is None else np.asarray(axial, float), **basic)
    b["along"] = None if axial is None or not along else dict(along)
    b["contact_arrays"] = arrays
    b["maps"] = maps         # which the shared LCP reads
    return b


def contact_arrays(frame, b) -> dict:
    """The contacts as arrays (cached in b; :func:`build` puts them there):
    link of n and of t (-1 without friction), friction, gap, unit normal,
    node and other node (-1)."""
    if "contact_arrays" not in b:
        b["contact_arrays"] = links(frame, b["idx"], b["K"].shape[0])[2]
    return b["contact_arrays"]


def release_directions(frame, b):
    """Each contact's normal and tangent as columns over the dofs, in the
    system's (the nodes') axes, minus at ``other`` for a pair: (normals
    N x nc, [tangents N x nc], friction per contact)."""
    N = b["K"].shape[0]
    cols = [np.array([contact_column(b["idx"], N, c, vec(c))
                      for c in frame.contacts]).T.reshape(N, -1)
            for vec in (lambda c: c.normal, lambda c: (c.normal[1], -c.normal[0]))]
    if b["Tn"] is not None:
        cols = [b["Tn"] @ h for h in cols]
    return cols[0], cols[1:], np.array([c.friction for c in frame.contacts])
