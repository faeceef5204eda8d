"""Words for a frame that is a mechanism: which nodes move, and how.

A singular basic system (the frame with every contact link fixed, or with
no contacts its bilateral supports and springs alone) has null vectors:
displacements that cost no energy.  They are read in two parts.

- The rigid motions of the whole frame among them: the null space is
  intersected with the frame's rigid-body modes (in the plane a translation
  t and a turn θ about a point, u(x) = t + θ e_z × (x - c); in space a
  translation and a rotation vector ω, u(x) = t + ω × (x - c), with every
  node's rotation dofs equal to θ or ω).  A turn is named by its centre
  (plane) or its axis (space): u vanishes at p = c + e_z × t / θ, and in
  space on the axis through p = c + ω × t / |ω|² along ω — named after a
  node where one lies on it ("a rigid rotation about A").
- What is left (a local mechanism: a node no member holds, a node whose
  member ends are all hinged, a part turning about a hinge) is named by
  the nodes and dofs that move.

Each reading comes with what to do (a support, a spring or a contact that
holds that motion).  Rotation dofs are weighed against translations by the
frame's size, so that the fit does not depend on the units.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from qpcontact.core.errors import InvalidProblemError, SolverFailedError

from ..mechanics.member_forces import contrast

#: a null vector's component below this fraction of its largest is zero
SMALL = 1e-7


def mechanism_message(S, free, nf, names, dofs, coords, Tn=None, contacts=True,
                      members=(), motions=None) -> str:
    """The message for a frame whose basic system S is singular: the free
    motions (module docstring) and what to do.  ``free``: the free dofs
    (nf of them, first in S); ``names``/``coords``: the nodes; ``dofs``:
    a node's dof names; ``Tn``: turned node axes (None: global);
    ``contacts``: whether the frame has contact links (fixed in S);
    ``members``: (name, i, j) of each member, which names the rigid parts of
    a plane mechanism (a portal's sway); ``motions``: where given (free dofs
    x k, k > 0), the motions that strain no member, read off the members'
    geometry (:func:`..mechanics.member_forces.strain_free_motions`) —
    named instead of S's null space, which at a stiffness contrast of 1e7
    holds a soft member's stretch too (a sway frame on pinned bars "turned
    rigidly" and "translated along y" as well)."""
    where = ("even with every contact closed" if contacts
             else "on its supports and springs (it has no contacts)")
    head = f"the frame is a mechanism {where}"
    if S.shape[0] > 4000:
        return (f"{head}, or two contacts constrain the same displacement (the basic system is "
                "singular; too large to name the motion); add supports or remove a redundant "
                "contact")
    if motions is not None and motions.shape[1]:
        null = motions
    else:
        try:
            null = scipy.linalg.null_space(S.toarray(), rcond=1e-12)
        except (ValueError, np.linalg.LinAlgError):
            null = np.zeros((S.shape[0], 0))
    if null.shape[1] == 0:
        return (f"{head}: the basic system is singular to rounding; check supports, hinges and "
                "that no two contacts constrain the same displacement")
    nd = len(dofs)
    N = len(names) * nd
    V = np.zeros((N, null.shape[1]))
    V[free] = null[:nf]
    keep = np.abs(V).max(axis=0) > 1e-9 * np.abs(null).max(axis=0)
    if not keep.any():
        return ("two or more contact links constrain the same displacement (redundant links): "
                "remove one of them")
    V = V[:, keep]
    if Tn is not None:
        V = Tn.T @ V                       # node axes -> global
    coords = np.asarray(coords, float)
    dim = coords.shape[1]
    size = float(np.ptp(coords, axis=0).max()) if len(coords) > 1 else 1.0
    size = size if size > 0 else 1.0
    rot = np.array([d.startswith("r") for d in dofs] * len(names))
    weight = np.where(rot, size, 1.0)      # rotations weighed by the frame's size
    G, centre = rigid_modes(coords, dim, nd)
    rigid = rigid_in_null(V * weight[:, None], G * weight[:, None])
    parts = []
    if rigid.shape[1] == G.shape[1]:
        parts.append("it is free as a rigid body (nothing holds it: "
                     + ("it translates in x and y and turns" if dim == 2 else
                        "it translates and turns about any axis") + "); "
                     + ("hold it by three independent restraints" if dim == 2 else
                        "hold it by six independent restraints")
                     + " (add_support, add_spring, or contacts that the loads press)")
    else:
        parts += merged([rigid_words(a, dim, coords, centre, names, size)
                         for a in nice_basis(rigid, dim)])
    local = [local_words(v, names, dofs, size, G, weight, coords, centre, members)
             for v in local_motions(V, G, rigid, weight)]
    local = merged(local)
    parts += local[:3]
    if len(local) > 3:
        parts.append(f"and {len(local) - 3} more independent motion(s)")
    return f"{head}: " + "; ".join(parts)


def merged(readings) -> list:
    """Readings (kind, subject, dof, words) merged where they share kind and
    subject: translations along x and y, turns about one node about x, y
    and z, a node free in ux and uy — one phrase each, in words."""
    out, seen = [], {}
    for kind, subject, dof, words in readings:
        key = (kind, subject)
        if kind is None or key not in seen:
            seen[key] = len(out)
            out.append([kind, subject, [dof], words])
        else:
            out[seen[key]][2].append(dof)
    return [phrase(kind, subject, dofs_, words) for kind, subject, dofs_, words in out]


def phrase(kind, subject, dofs_, words) -> str:
    if kind is None or len(dofs_) == 1:
        return words
    ds = ", ".join(dofs_)
    if kind == "translation":
        axes_ = ", ".join(d[1:] for d in dofs_)
        return (f"it translates rigidly along {axes_}; hold {ds} at a node each (add_support, "
                "add_spring, or contacts along them)")
    if kind == "turn":
        return (f"it turns rigidly about node {subject} (about {', '.join(d[1:] for d in dofs_)}"
                f"); fix {ds} at {subject} or hold other nodes across those turns")
    return (f"node {subject} is free in {ds} (no member, support or spring holds it there); "
            "connect it with a member or hold it (add_support, add_spring)")


def rigid_modes(coords, dim, nd):
    """(G, c): the frame's rigid-body modes as columns over all dofs (plane:
    tx, ty, θ about the centroid c; space: tx, ty, tz, ωx, ωy, ωz)."""
    c = coords.mean(axis=0)
    n = len(coords)
    r = coords - c
    if dim == 2:
        G = np.zeros((n * nd, 3))
        G[0::nd, 0] = 1.0
        G[1::nd, 1] = 1.0
        G[0::nd, 2], G[1::nd, 2], G[2::nd, 2] = -r[:, 1], r[:, 0], 1.0
        return G, c
    G = np.zeros((n * nd, 6))
    for k in range(3):
        G[k::nd, k] = 1.0
        w = np.zeros(3)
        w[k] = 1.0
        G[np.arange(n) * nd, 3 + k], G[np.arange(n) * nd + 1, 3 + k], \
            G[np.arange(n) * nd + 2, 3 + k] = np.cross(w, r).T
        G[np.arange(n) * nd + 3 + k, 3 + k] = 1.0
    return G, c


def rigid_in_null(V, G):
    """The rigid modes' coefficients a (columns) with G a in span(V): the
    null space of [V, -G] (columns normalised), its G part."""
    Vn = V / np.linalg.norm(V, axis=0)
    gn = np.linalg.norm(G, axis=0)
    both = scipy.linalg.null_space(np.hstack([Vn, -G / gn]), rcond=1e-8)
    return both[V.shape[1]:] / gn[:, None]


def nice_basis(A, dim):
    """A basis of the rigid motions with as few turns as can be: the
    translations first, each turn in a vector of its own where the span
    allows (reduced echelon form with the rotation coordinates last)."""
    if A.shape[1] == 0:
        return []
    nt = dim
    order = list(range(nt, A.shape[0])) + list(range(nt))   # eliminate rotations first
    B = A[order].T.copy()                                    # rows: basis vectors
    row = 0
    for col in range(B.shape[1]):
        if row == B.shape[0]:
            break
        piv = row + int(np.argmax(np.abs(B[row:, col])))
        if abs(B[piv, col]) <= 1e-9 * np.abs(B).max():
            continue
        B[[row, piv]] = B[[piv, row]]
        B[row] /= B[row, col]
        for other in range(B.shape[0]):
            if other != row:
                B[other] -= B[other, col] * B[row]
        row += 1
    back = np.argsort(order)
    return [b[back] for b in B]


def axis_name(d) -> str:
    d = d / np.linalg.norm(d)
    for k, nm in enumerate("xyz"[:d.size]):
        if abs(abs(d[k]) - 1.0) <= 1e-9:
            return nm
    return "(" + ", ".join(f"{v:.3g}" for v in d) + ")"


def node_at(p, coords, names, size):
    gap = np.linalg.norm(coords - p, axis=1)
    k = int(np.argmin(gap))
    return names[k] if gap[k] <= 1e-6 * size else None


def rigid_words(a, dim, coords, c, names, size) -> tuple:
    """One rigid motion (translation t at the centroid c, turn θ or ω) as a
    reading (kind, subject, dof, words) that :func:`merged` may join with
    others: kind "translation" or "turn" (about a node), else None."""
    t, w = a[:dim], a[dim:]
    small = np.linalg.norm(w) * size <= 1e-9 * max(np.linalg.norm(t), 1e-300)
    if small:
        ax = axis_name(t)
        held = f"u{ax}" if len(ax) == 1 else f"the direction {ax}"
        return ("translation" if len(ax) == 1 else None, None, held,
                f"it translates rigidly along {ax}; hold {held} at one node (add_support, "
                "add_spring, or a contact along it)")
    if dim == 2:
        theta = float(w[0])
        p = c + np.array([-t[1], t[0]]) / theta
        at = node_at(p, coords, names, size)
        where = f"node {at}" if at else f"the point ({p[0]:.4g}, {p[1]:.4g})"
        fix = (f"fix rz at {at} (add_support({at!r}, fix=(..., 'rz'))) or hold a second "
               "node" if at else "hold a second node across the motion")
        return ("turn" if at else None, at, "rz",
                f"it turns rigidly about {where} (a rigid rotation); {fix}")
    om = np.asarray(w, float)
    p = c + np.cross(om, t) / (om @ om)
    pitch = (om @ t) / (om @ om)
    # the node nearest the axis, if one lies on it
    d = om / np.linalg.norm(om)
    r = coords - p
    off = np.linalg.norm(r - np.outer(r @ d, d), axis=1)
    k = int(np.argmin(off))
    at = names[k] if off[k] <= 1e-6 * size else None
    ax = axis_name(om)
    where = (f"the axis through node {at} along {ax}" if at else
             f"the axis through ({', '.join(f'{v:.4g}' for v in p)}) along {ax}")
    screw = "" if abs(pitch) <= 1e-9 * size else " while sliding along it (a screw motion)"
    rdof = f"r{ax}" if len(ax) == 1 else "the rotation about that axis"
    fix = (f"fix {rdof} at {at} or hold another node against that turn" if at else
           "hold a node off the axis against that turn (a support, spring or frictional "
           "contact across it)")
    return ("turn" if at and not screw and len(ax) == 1 else None, at, rdof,
            f"it turns rigidly about {where}{screw} (a rigid rotation); {fix}")


def local_motions(V, G, rigid, weight):
    """The null vectors left once the rigid motions are taken out (in the
    weighed metric), each as a vector over all dofs (unweighed)."""
    Vw = V * weight[:, None]
    scale = np.linalg.norm(Vw, 2) if Vw.size else 0.0
    if rigid.shape[1]:
        Rw = (G @ rigid) * weight[:, None]
        Q, _ = np.linalg.qr(Rw)
        Vw = Vw - Q @ (Q.T @ Vw)
    U, s, _ = np.linalg.svd(Vw, full_matrices=False)
    keepers = s > 1e-6 * scale
    return [U[:, k] / weight for k in np.flatnonzero(keepers)]


def local_words(v, names, dofs, size, G, weight, coords, centre, members=()):
    """A local mechanism as a reading (kind, subject, dof, words): the nodes
    that move and their dofs — a part that moves as a rigid body named by
    its turn (about a hinge) or translation."""
    nd = len(dofs)
    rot = np.array([d.startswith("r") for d in dofs] * len(names))
    mag = np.abs(v) * np.where(rot, size, 1.0)
    moving = mag > SMALL * mag.max()
    by_node = {}
    for i in np.flatnonzero(moving):
        by_node.setdefault(names[i // nd], []).append(dofs[i % nd])
    if len(by_node) == 1:
        node, ds = next(iter(by_node.items()))
        held = "(add_support, add_spring)"
        if all(d.startswith("r") for d in ds):
            return (None, None, None,
                    f"node {node} turns freely ({', '.join(ds)}): every member end there is "
                    f"hinged and nothing holds its rotation; fix {ds[0]} at {node} or make one "
                    "member end rigid there")
        words = (f"node {node} is free in {', '.join(ds)} (no member, support or spring holds "
                 f"it there); connect it with a member or hold it {held}")
        return ("node", node, ds[0], words) if len(ds) == 1 else (None, None, None, words)
    # a part of the frame moving as a rigid body (about a hinge, on a roller)
    rows = np.flatnonzero(np.isin(np.arange(v.size) // nd, [names.index(n) for n in by_node]))
    Gw, vw = G[rows] * weight[rows, None], v[rows] * weight[rows]
    a = np.linalg.lstsq(Gw, vw, rcond=None)[0]
    part = list(by_node)
    who = ", ".join(part[:6]) + ("..." if len(part) > 6 else "")
    if np.linalg.norm(Gw @ a - vw) <= 1e-6 * np.linalg.norm(vw):
        words = rigid_words(a, coords.shape[1], coords, centre, names, size)[3]
        words = words.replace("it turns", "turns").replace("it translates", "translates")
        return (None, None, None, f"the part of the frame with nodes {who} {words} (other "
                "members' ends hinged or free there: a local mechanism)")
    parts = rigid_parts(v, names, nd, size, G, members) if coords.shape[1] == 2 else None
    if parts:
        said = "; ".join(part_words(a, ms, coords, centre, names, size) for a, ms in parts[:4])
        more = f"; and {len(parts) - 4} more parts" if len(parts) > 4 else ""
        return (None, None, None, f"a mechanism of {len(parts)} rigid parts moving together "
                f"({said}{more}); hold one of them (a support, a brace or a rigid joint)")
    shown = "; ".join(f"{n} in {', '.join(ds)}" for n, ds in list(by_node.items())[:4])
    more = f" and {len(by_node) - 4} more nodes" if len(by_node) > 4 else ""
    return (None, None, None, f"a part of the frame moves freely ({shown}{more}: nodes {who} "
            "together); add a support, a member or a rigid joint that holds it")


def rigid_parts(v, names, nd, size, G, members):
    """A plane mechanism as rigid parts: each moving member's rigid motion
    (translation and turn, from its ends' translations: a mechanism strains
    no member), members moving alike grouped — [(motion, [member names])],
    or None where a member does not move rigidly or no member moves."""
    parts = []
    for name, i, j in members:
        rows = np.r_[[names.index(i) * nd + k for k in (0, 1)],
                     [names.index(j) * nd + k for k in (0, 1)]]
        if np.abs(v[rows]).max() <= SMALL * np.abs(v).max():
            continue
        a, *_ = np.linalg.lstsq(G[rows], v[rows], rcond=None)
        if np.linalg.norm(G[rows] @ a - v[rows]) > 1e-6 * np.linalg.norm(v[rows]):
            return None
        scale = np.abs(a[:2]).max() + abs(a[2]) * size
        for motion, group in parts:
            if np.abs(motion[:2] - a[:2]).max() + abs(motion[2] - a[2]) * size <= 1e-6 * scale:
                group.append(name)
                break
        else:
            parts.append((a, [name]))
    return parts or None


def part_words(a, members, coords, centre, names, size) -> str:
    """"M1 turns rigidly about node A", "M2, M3 translate rigidly along x"."""
    words = rigid_words(a, 2, coords, centre, names, size)[3]
    words = words.split(" (a rigid rotation)")[0].split(";")[0].replace("it ", "", 1)
    if len(members) > 1:
        words = words.replace("turns", "turn", 1).replace("translates", "translate", 1)
    return f"{', '.join(members[:4])}{'...' if len(members) > 4 else ''} {words}"


def unsolvable(local) -> str:
    """The words for a basic system that no motion leaves unstrained but
    that is singular in double: the stiffnesses' contrast is beyond it."""
    return (f"the frame is no mechanism (no motion with every contact closed leaves every "
            f"member unstrained), but its stiffnesses differ by {contrast({'local': local}):.1e}, "
            "beyond what its basic system solves in double precision (singular to rounding); "
            "model the stiff part as rigid or as less stiff")


def refuse_singular(basic, local, names, dofs, coords, Tn=None, contacts=True,
                    members=()) -> None:
    """Raise where an assembly's basic system (``basic``:
    :func:`..mechanics.contact_lcp.basic_system`'s) has no LU:
    SolverFailedError where no motion leaves every member unstrained but S
    is singular in double (:func:`unsolvable`), else InvalidProblemError
    naming the mechanism (:func:`mechanism_message`, by the strain-free
    motions where they were read)."""
    if basic.get("no_mechanism"):
        raise SolverFailedError(unsolvable(local))
    if basic["lu"] is None:
        raise InvalidProblemError(mechanism_message(
            basic["S"], basic["free"], basic["nf"], names, dofs, coords, Tn, contacts=contacts,
            members=members, motions=basic.get("strain_free")))
