"""A frame's stiffness times displacements in extended precision, member by
member, with each member's rigid motion taken out first.

Why.  K u assembled in double carries ε|K||u| at every dof; beside a deck
1e8 times stiffer than its legs that is 1e-6 of the pads' forces.  Computed
member by member as Tᵀ k (T u_e − r_e), with r_e the member's own rigid
motion (its end i's translation and the rotation that carries its chord
from i to j), the large rigid part of a stiff member's motion never meets
its large stiffness: k annihilates r_e in exact arithmetic but not as
rounded (12EI/L³·L against 2·6EI/L²: a twisted 1e8 deck kept 4e-9 of its
pads' forces that way).  In ``numpy.longdouble`` (64-bit mantissa on x86,
113 on aarch64) the rest carries 1e-19 |k||u_e − r_e|.

Used by the refinement of an answer on its contact states
(:mod:`.extended_refinement`) and of the contact stiffness R where the
members' stiffness differs by orders of magnitude (:mod:`.contact_lcp`).
"""

from __future__ import annotations

import numpy as np

#: the extended format of the residuals
EXTENDED = np.longdouble


def stiffness_times(b, u) -> np.ndarray:
    """K u in extended precision, member by member: Σ Tᵀ k (T u_e − r_e)
    plus the springs, in the system's (node) axes; u (all dofs, the same
    axes) a vector or a matrix of columns."""
    u = np.asarray(u, EXTENDED)
    vector = u.ndim == 1
    f, _ = _stiffness_and_ends(b, u.reshape(u.shape[0], -1))
    return f[:, 0] if vector else f


def refined_actions(b, u, factors) -> tuple[np.ndarray, np.ndarray]:
    """(K u in extended precision, the members' end actions net of the
    fixed-end forces of the load combination ``factors``, in double) of a
    refined u (a vector in the system's axes): the end actions computed
    once for both, what a recovery reads off an answer refined in
    extended precision (in double a stiff member's carry ε|k||u|)."""
    f, ends = _stiffness_and_ends(b, np.asarray(u, EXTENDED)[:, None])
    return f[:, 0], np.asarray(ends[..., 0], float) - b["local"][3] @ factors


def _stiffness_and_ends(b, u):
    """(K u, the elastic end actions) for u a matrix of columns."""
    _, T, dofs, _ = b["local"]
    Tn = b["Tn"]
    ug = u if Tn is None else Tn.T.astype(EXTENDED) @ u
    ends = elastic_end_actions(b, ug)
    back = np.einsum("mji,mjc->mic", T.astype(EXTENDED), ends)
    f = np.zeros(ug.shape, EXTENDED)
    np.add.at(f, dofs.ravel(), back.reshape(-1, back.shape[2]))
    f += np.asarray(b["springs"], EXTENDED)[:, None] * ug
    return (f if Tn is None else Tn.astype(EXTENDED) @ f), ends


def elastic_end_actions(b, ug) -> np.ndarray:
    """Every member's end actions k (T u_e − r_e) in its own axes, in
    extended precision, (m, 2 nd, columns), from ``ug`` (all dofs in
    global axes, one column per vector): the elastic part of what
    :func:`..contact_lcp.member_end_actions` gives in double, without the
    ε|k||u| a stiff member's rigid motion leaves there."""
    k, T, dofs, _ = b["local"]
    d = np.einsum("mij,mjc->mic", T.astype(EXTENDED), np.asarray(ug, EXTENDED)[dofs])
    d = d - rigid_part(b, d, dofs)
    return np.einsum("mij,mjc->mic", k.astype(EXTENDED), d)


def rigid_part(b, d, dofs):
    """Each member's rigid motion in its own axes (m, 2 nd, columns) from
    its end displacements d: end i's translation and the chord's rotation
    (plane: u, v, θ; space: u, v, w, θx, θy, θz) — each mode only where the
    member's k annihilates it (as rounded): a second-order member resists
    the chord's rotation (its P-Δ shear) but not a translation, and an
    element this does not know keeps all of d."""
    k = b["local"][0]
    nd = dofs.shape[1] // 2
    xyz = np.asarray(b["coords"], EXTENDED)
    L = np.sqrt(((xyz[dofs[:, nd] // nd] - xyz[dofs[:, 0] // nd]) ** 2).sum(axis=1))[:, None]
    if nd == 3:
        c = np.stack([d[:, 0], d[:, 1], (d[:, 4] - d[:, 1]) / L], axis=1)
    else:
        c = np.stack([d[:, 0], d[:, 1], d[:, 2], d[:, 3], -(d[:, 8] - d[:, 2]) / L,
                      (d[:, 7] - d[:, 1]) / L], axis=1)
    unit = rigid_basis(np.asarray(L[:, 0], float), nd)
    kr = np.abs(k @ unit).max(axis=1)                                   # (m, modes)
    size = np.abs(k).max(axis=(1, 2))[:, None] * np.abs(unit).max(axis=1)
    kept = kr <= 1e-9 * size
    if b.get("axial") is not None:
        # a second-order member's P-Δ shear N θ is a real force, though
        # under 1e-9 of a stiff member's k (a rigid beam's N of 10 kN
        # beside EA/L of 3e9 kN/m): its chord rotation stays in d
        translations = 2 if nd == 3 else 3          # the modes before the rotations
        kept[:, translations:] &= (np.asarray(b["axial"]) == 0.0)[:, None]
    return np.einsum("mij,mjc->mic", unit.astype(EXTENDED), c * kept[:, :, None])


def rigid_basis(L, nd):
    """(m, 2 nd, modes): each member's rigid motions in its own axes."""
    m = L.size
    if nd == 3:
        B = np.zeros((m, 6, 3))
        B[:, [0, 3], 0] = 1.0
        B[:, [1, 4], 1] = 1.0
        B[:, 2, 2] = B[:, 5, 2] = 1.0
        B[:, 4, 2] = L
        return B
    B = np.zeros((m, 12, 6))
    for a in range(3):
        B[:, a, a] = B[:, 6 + a, a] = 1.0
        B[:, 3 + a, 3 + a] = B[:, 9 + a, 3 + a] = 1.0
    B[:, 7, 5] = L          # θz carries j along +y
    B[:, 8, 4] = -L         # θy carries j along -z
    return B


def contrast(b) -> float:
    """The members' stiffness contrast: the largest entry of one member's k
    over the largest of another's (1 for a single member)."""
    k = b["local"][0]
    if not len(k):
        return 1.0
    big = np.abs(k).reshape(len(k), -1).max(axis=1)     # (over two axes: three times slower)
    return float(big.max() / max(big.min(), 1e-300))


#: a motion whose deformations are below this fraction of the largest a
#: unit motion can make strains nothing (:func:`strain_free_motions`)
KINEMATIC_RCOND = 1e-10


def strain_free_motions(local, coords, springs, Tn, free, H=None) -> np.ndarray:
    """An orthonormal basis (free dofs x k, the system's axes) of the
    motions that strain no member and stretch no spring — with the links
    ``H`` (the system's axes), that also move no contact link (every
    contact closed) — read off the
    members' geometry, not their stiffness.  A member's deformations are
    its end displacements (member axes) along the range of its own k (its
    rigid motions and a hinge's released rotation are k's null space);
    each member's rows are orthonormal, so a deck 1e12 times stiffer than
    its columns weighs as much as they do.  K's own null space, read with
    its eigenvalues against the largest, mixes a soft member's bending
    (eigenvalue about 1/contrast) into the rigid motions at that contrast.
    Rotations are weighed against translations by the frame's size.
    ``local``, ``coords``, ``springs``, ``Tn``, ``free``: an assembly's
    (:class:`.contact_lcp.Built`)."""
    k, T, dofs, _ = local
    xyz = np.asarray(coords, float)
    N = np.asarray(springs).size
    size = float(np.ptp(xyz, axis=0).max()) if len(xyz) > 1 else 1.0
    size = size if size > 0 else 1.0
    nd = N // len(xyz)
    spin = np.array([d >= (2 if nd == 3 else 3) for d in range(nd)])   # rotations last
    weight = np.where(np.tile(spin, len(xyz)), 1.0 / size, 1.0)   # u = weight * (scaled u)
    rows = []
    if len(k):
        w = weight[dofs]                                        # (m, 2 nd)
        ks = k * w[:, :, None] * w[:, None, :]
        ks = ks / np.maximum(np.abs(ks).max(axis=(1, 2)), 1e-300)[:, None, None]
        U, s, _ = np.linalg.svd(ks)
        keep = s > 1e-12 * s[:, :1]       # k's null space: rounding of its max (1e-16)
        # deformations: the range of W k W against T v (u = W v, and T
        # turns translations into translations, rotations into rotations:
        # T W = W T, so k T u = 0 where (W k W) T v = 0)
        C = np.einsum("mia,mij->maj", U, T) * keep[:, :, None]
        n2 = dofs.shape[1]
        row = np.broadcast_to(np.arange(len(k))[:, None, None] * n2
                              + np.arange(n2)[None, :, None], C.shape)    # (m, a, j): m n2 + a
        dense = np.zeros((len(k) * n2, N))
        np.add.at(dense, (row, np.broadcast_to(dofs[:, None, :], C.shape)), C)
        rows.append(dense)
    spring = np.flatnonzero(np.asarray(springs) > 0)
    if spring.size:
        rows.append(np.eye(N)[spring] * weight[spring][:, None])
    C = np.vstack(rows) if rows else np.zeros((0, N))
    if Tn is not None:                                        # node axes -> global
        C = C @ (Tn.T.toarray() if hasattr(Tn, "toarray") else Tn.T)
    if H is not None:
        h = H.toarray().T
        h = h / np.maximum(np.abs(h).max(axis=1, keepdims=True), 1e-300)
        C = np.vstack([C, h * weight[None, :]])
    C = C[:, free]
    if C.shape[0] == 0:
        return np.eye(free.size) * weight[free][:, None]
    _, s, Vt = np.linalg.svd(C, full_matrices=True)
    rank = int(np.count_nonzero(s > KINEMATIC_RCOND * max(s.max(initial=0.0), 1e-300)))
    null = Vt[rank:].T * weight[free][:, None]
    return np.linalg.qr(null)[0] if null.shape[1] else null
