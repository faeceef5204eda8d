"""Assembly of a plane frame and its contact LCP (P3's displacement method).

K u = F + H X: the frame's stiffness on its free degrees of freedom, the
loads, and the contact links' forces X mapped by H (columns n and t at the
contact's node, minus at ``other``).  The links' relative displacements are
Δ = H'u.  The contact stiffness R and load vectors R_F of P3's *basic system*
(every link fixed) are read from the saddle-point system

    [K  H] [u]   [F]
    [H' 0] [y] = [Δ],     X = -y = R Δ + R_F,

for unit dislocations Δ = e_j (columns of R) and for each load case with
Δ = 0 (one column R_F per case).  Unit dislocations through this system
rather than condensing K onto the links: K alone is singular whenever the
frame relies on its contacts for stability (a beam resting on unilateral
supports only), while the basic system is not.  R is symmetric positive
definite.  Elastic contacts add their flexibility D = diag(1/k) to the
link rows, H'u + D X = Δ, which gives R = (I + R₀ D)⁻¹ R₀ directly.

Unknowns per contact: z = (Z_n, Z⁺, Z⁻) with Δ_n = Z_n - g, Δ_t = Z⁺ - Z⁻,
and w = (X_n, f X_n + X_t, f X_n - X_t) (P3's holonomic Coulomb law: total
slip against total force).  Contacts with f = 0 build no tangential link at
all, and a frame without friction builds the normal-only LCP (M = R_nn,
symmetric positive semidefinite).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from qpcontact.core.errors import InvalidProblemError
from qpcontact.core.problems import LCP

from .elements import member_locals
from .loads import CONSTANT, VARIABLE

#: A plane frame node's degrees of freedom, in the order of its rows.
DOFS = ("ux", "uy", "rz")
#: Entries of the contact stiffness R below R_ROUNDING x (largest stiffness
#: term) are rounding noise of the basic-system solve and are set to zero.
R_ROUNDING = 256 * np.finfo(float).eps


def cases(frame) -> list:
    """Every load case with a load, plus the P3 pair (constant, variable)."""
    names = {CONSTANT, VARIABLE}
    names.update(ld[4] for ld in frame.nodal_loads)
    names.update(st[2] for st in frame.settlements)
    for m in frame.members.values():
        names.update(ld.case for ld in m.loads)
    return sorted(names)


def assemble(frame):
    """K (CSR), loads F and settlements U (one column per case), the fixed
    dofs, and the members' local data for the results (k, T, dofs, Fe):
    all members at once (K from one COO array)."""
    names = list(frame.nodes)
    idx = {nm: 3 * i for i, nm in enumerate(names)}
    N = 3 * len(names)
    case_list = cases(frame)
    col = {c: k for k, c in enumerate(case_list)}
    F = np.zeros((N, len(case_list)))
    if frame.members:
        k_all, T, dofs, Fe = member_locals(frame, names, idx, col)
        Tt = T.transpose(0, 2, 1)
        kg = Tt @ k_all @ T          # batched matmul: 10x einsum's three-operand path
        rows = [np.repeat(dofs, 6, axis=1).ravel()]
        cols = [np.tile(dofs, (1, 6)).ravel()]
        vals = [kg.ravel()]
        np.add.at(F, dofs.ravel(), (Tt @ Fe).reshape(-1, len(col)))
    else:
        k_all, T = np.zeros((0, 6, 6)), np.zeros((0, 6, 6))
        dofs, Fe = np.zeros((0, 6), int), np.zeros((0, 6, len(col)))
        rows, cols, vals = [], [], []
    for node, fx, fy, mz, case in frame.nodal_loads:
        F[idx[node]:idx[node] + 3, col[case]] += (fx, fy, mz)
    U = np.zeros_like(F)   # prescribed displacements (settlements) of fixed dofs, per case
    for node, dof, case, value in frame.settlements:
        U[idx[node] + DOFS.index(dof), col[case]] += value
    K = stiffness_matrix(rows, cols, vals, frame.springs, idx, DOFS, N)
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
    lost = np.flatnonzero(free_spin & np.any(F != 0.0, axis=1))
    if lost.size:
        node = names[lost[0] // 3]
        raise InvalidProblemError(
            f"node {node!r}: a moment is applied where no member and no support resists "
            "rotation (only released ends meet there), so it would act on nothing; put it "
            "on a member end that is not released (add_point_load(member, a, mz=...)) or "
            "release one end fewer")
    fixed |= free_spin
    # per member, for the results: stiffness, rotation, dofs, and the
    # equivalent nodal loads of every case (member axes), (m, 6, cases)
    return names, idx, K, F, U, case_list, fixed, (k_all, T, dofs, Fe), Tn


def stiffness_matrix(rows, cols, vals, springs, idx, dofs, N):
    """K (CSR, N x N) from the members' triplets (lists of arrays) and the
    springs to the ground {node: {dof: k}} (``dofs``: the dof names of a
    node, in order; ``idx``: each node's first dof)."""
    for node, ks in springs.items():
        for d, kval in ks.items():
            rows.append([idx[node] + dofs.index(d)])
            cols.append([idx[node] + dofs.index(d)])
            vals.append([kval])
    return sp.coo_matrix((np.concatenate(vals) if vals else np.zeros(0),
                          (np.concatenate(rows) if rows else np.zeros(0, int),
                           np.concatenate(cols) if cols else np.zeros(0, int))),
                         shape=(N, N)).tocsr()


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


def force_terms(b, u, F, ends):
    """Per dof (the system's axes): the sizes of the forces that meet there —
    every member's end force, the springs', the load: what a contact force
    at that node is made of by equilibrium, and so its scale.  Member end
    forces, not |K||u|: a stiff member moving rigidly has K u ~ 0 from
    terms of 1e10 (a rigid zone as a 1e7-times-stiffer member), which as a
    scale would call a 16 kN contact force zero.  ``ends``: the members'
    end actions (:func:`member_end_actions`), which the results need too."""
    ug = to_global(b, u)
    k, T, dofs, Fe = b["local"]
    terms = np.zeros(ug.size)
    np.add.at(terms, dofs.ravel(),
              np.abs((T.transpose(0, 2, 1) @ ends[..., None])[..., 0]).ravel())
    terms += np.abs(b["springs"] * ug)
    if b["Tn"] is not None:
        terms = abs(b["Tn"]) @ terms
    return terms + np.abs(F)


def member_end_actions(b, u, combo_factors) -> np.ndarray:
    """Every member's end actions k T u - f (member axes), (m, 6), from the
    global displacements u."""
    k, T, dofs, Fe = b["local"]
    return (k @ (T @ u[dofs][..., None]))[..., 0] - Fe @ combo_factors


def to_global(b, v):
    """A vector (or the columns of a matrix) of dofs from the nodes' axes to global."""
    return v if b["Tn"] is None else b["Tn"].T @ v


def contact_column(idx, N, c, vec) -> np.ndarray:
    """The column of H mapping a force along ``vec`` at contact c to the
    nodal forces (minus at ``other`` for a pair)."""
    h = np.zeros(N)
    h[idx[c.node]:idx[c.node] + 2] += vec
    if c.other is not None:
        h[idx[c.other]:idx[c.other] + 2] -= vec
    return h


def links(frame, idx, N):
    """H (N x links, sparse CSR) and, per link: contact index, kind 'n'/'t'."""
    cs = frame.contacts
    nc = len(cs)
    normal = np.array([c.normal for c in cs]).reshape(nc, 2)
    fric = np.array([c.friction > 0 for c in cs], bool)
    node = np.array([idx[c.node] for c in cs], int)
    other = np.array([-1 if c.other is None else idx[c.other] for c in cs], int)
    # links in contact order: n, then t where there is friction
    n_link = np.arange(nc) + np.r_[0, np.cumsum(fric)[:-1]]
    t_link = n_link + 1
    info = []
    for ci in range(nc):
        info.append((ci, "n"))
        if fric[ci]:
            info.append((ci, "t"))
    tangent = np.c_[normal[:, 1], -normal[:, 0]]
    rows, cols, vals = [], [], []
    for links_, vecs, keep in ((n_link, normal, np.ones(nc, bool)), (t_link, tangent, fric)):
        for at, sign in ((node, 1.0), (other, -1.0)):
            k = keep & (at >= 0)
            for d in (0, 1):
                rows.append(at[k] + d)
                cols.append(links_[k])
                vals.append(sign * vecs[k, d])
    H = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(N, len(info)))
    H.eliminate_zeros()
    return H, info


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


#: a saddle matrix whose LU pivots span more than this is singular: a
#: mechanism, which rounding would otherwise answer with a rigid motion of
#: 1e11 m that every scaled check passes
SINGULAR_PIVOTS = 1e-13


def regular_lu(S):
    """SuperLU of S, or None where S is singular (exactly, or its pivots
    spanning more than 1/SINGULAR_PIVOTS)."""
    try:
        lu = spla.splu(S)
    except RuntimeError:   # exactly singular
        return None
    piv = np.abs(lu.U.diagonal())
    return lu if piv.size and piv.min() > SINGULAR_PIVOTS * piv.max() else None


class Built(dict):
    """A frame's assembly: K, loads, links, the saddle matrix's LU, ... (see
    :func:`build`).  The contact stiffness R (and R_solve, the same before its
    rounding-level entries are dropped) and the load columns R_F — dense,
    links x links, the cost of a long beam's LCP (1000 spans: 2 000 links, one
    solve per link) — are computed on first use, so a route that never needs
    the LCP's matrix (the sparse active set) never pays for them."""

    def __missing__(self, key):
        if key not in ("R", "RF", "R_solve"):
            raise KeyError(key)
        self.update(contact_stiffness(self))
        return self[key]


def build(frame):
    """Assemble K, the links, and the LU of the basic system (every link
    fixed).  Returns a :class:`Built` with everything the routes and the
    results need; R and R_F come on first use."""
    if not frame.contacts:
        raise InvalidProblemError("the frame has no contacts: it is a linear problem; "
                                  "add_contact() defines the unilateral supports")
    check_conflicts(frame)
    names, idx, K, F, U, case_list, fixed, local, Tn = assemble(frame)
    N = K.shape[0]
    H, info = links(frame, idx, N)
    if Tn is not None:
        H = (Tn @ H).tocsr()
    # Elastic contacts: the link's displacement is the structure's plus the
    # spring's, H'u + D X = Δ (D = diag 1/k), so D enters the saddle matrix
    # (scaled like the links) and R, R_F come out elastic — no dense
    # (I + R D)⁻¹ on nl x nl.
    flex = np.array([0.0 if frame.contacts[ci].stiffness is None
                     else 1.0 / frame.contacts[ci].stiffness for ci, _ in info])
    basic = basic_system(K, H, fixed, flex, np.arange(N) % 3 != 2)
    if basic["lu"] is None:
        raise InvalidProblemError(mechanism_message(basic["S"], basic["free"], names,
                                                    basic["nf"]))
    springs = np.zeros(N)
    for node, ks in frame.springs.items():
        for d, kval in ks.items():
            springs[idx[node] + DOFS.index(d)] += kval
    return Built(springs=springs, names=names, idx=idx, K=K, F=F, U=U, cases=case_list,
                 fixed=fixed, H=H, info=info, flex=flex, local=local, Tn=Tn, **basic)


def basic_system(K, H, fixed, flex, translational) -> dict:
    """The basic system (every link fixed) of a structure with stiffness K
    (all dofs), links H and contact flexibilities ``flex``, any number of
    dofs per node: the free/fixed blocks of K, the scaled saddle matrix
    S = [K_ff kappa H_f; kappa H_f' -kappa² D] and its LU (None where S is
    singular: a mechanism).  ``translational`` marks the dofs that links
    push along, which set kappa."""
    N = K.shape[0]
    free = np.flatnonzero(~fixed)
    nf = free.size
    # the blocks on the free dofs from triplets, not by fancy indexing (a
    # sparse slice costs a tenth of a millisecond, the whole solve of a
    # 20-storey frame a few)
    at = np.full(N, -1)
    at[free] = np.arange(nf)
    Kc = K.tocoo()
    r, c = at[Kc.row], at[Kc.col]
    ff, fa = (r >= 0) & (c >= 0), (r >= 0) & (c < 0)
    Kf = sp.csr_matrix((Kc.data[ff], (r[ff], c[ff])), shape=(nf, nf))
    fixed_idx = np.flatnonzero(fixed)
    at_fixed = np.full(N, -1)
    at_fixed[fixed_idx] = np.arange(fixed_idx.size)
    K_fa = sp.csr_matrix((Kc.data[fa], (r[fa], at_fixed[Kc.col[fa]])),
                         shape=(nf, fixed_idx.size))
    # The links enter scaled by a typical stiffness kappa, so that the saddle
    # matrix is balanced (steel in N and m has K ~ 1e8 against H ~ 1) and
    # the singularity test is meaningful: X = -kappa y.  Links push nodes
    # along, so kappa is the largest *translational* stiffness: the largest
    # of all is a rotation's (moment per radian), which in N and mm is 1e5
    # times a translation's, and kappa² / k on an elastic contact's diagonal
    # then made a sound beam look like a mechanism (pivots 3e-14 apart).
    diag = np.abs(Kf.diagonal())
    moves = translational[free]
    kappa = float(np.max(diag[moves] if moves.any() else diag)) if free.size else 1.0
    # no stiffness on those dofs at all (a node on a contact, no member):
    # kappa = 0 would drop the links and name a held dof as the free one
    kappa = kappa if kappa > 0 else 1.0
    Hc = H.tocoo()
    hk = at[Hc.row] >= 0
    Hf = sp.csr_matrix((kappa * Hc.data[hk], (at[Hc.row[hk]], Hc.col[hk])), shape=(nf, H.shape[1]))
    nl = H.shape[1]
    Hfc = Hf.tocoo()
    links_ = np.arange(nl)
    S = sp.csc_matrix((np.r_[Kc.data[ff], Hfc.data, Hfc.data, -kappa ** 2 * flex],
                       (np.r_[r[ff], Hfc.row, nf + Hfc.col, nf + links_],
                        np.r_[c[ff], nf + Hfc.col, Hfc.row, nf + links_])),
                      shape=(nf + nl, nf + nl))
    # one sparse LU of the saddle matrix (a 1000-span beam: 4000 unknowns,
    # 1.7 s dense, milliseconds sparse); its pivots say whether it is singular
    return dict(free=free, nf=nf, fixed_idx=fixed_idx, K_fa=K_fa, kappa=kappa, Hf=Hf, S=S,
                lu=regular_lu(S))


def contact_stiffness(b) -> dict:
    """R (links x links) and R_F (one column per case) from unit
    dislocations through the basic system's LU (the module docstring)."""
    nf, kappa, fixed_idx = b["nf"], b["kappa"], b["fixed_idx"]
    nl = len(b["info"])
    nc = len(b["cases"])
    rhs = np.zeros((nf + nl, nl + nc))
    rhs[nf:, :nl] = kappa * np.eye(nl)
    # settlements: the free dofs feel -K_fa u_a, the links see H_a' u_a already done
    U, H = b["U"], b["H"]
    rhs[:nf, nl:] = b["F"][b["free"]] - b["K_fa"] @ U[fixed_idx]
    rhs[nf:, nl:] = -kappa * (H[fixed_idx].T @ U[fixed_idx])
    sol = b["lu"].solve(rhs)
    R = -kappa * sol[nf:, :nl]
    R = 0.5 * (R + R.T)
    # R's entries are sums of terms of size kappa (the stiffness), so each
    # carries a rounding error of a few eps * kappa.  An entry that small is
    # zero: a dislocation that a rigid motion of the frame absorbs (a portal
    # on two pins lifted at one base) costs no force, and noise in its place
    # would turn "this link has no effect" into a random sign — which the
    # trace's collapse proof (a Farkas vector, M'y <= 0 column by column)
    # and the support states would read as data.
    exact = R.copy()
    R[np.abs(R) <= R_ROUNDING * kappa] = 0.0
    return {"R": R, "RF": -kappa * sol[nf:, nl:], "R_solve": exact}


def factors(b, combo: dict) -> np.ndarray:
    col = {c: k for k, c in enumerate(b["cases"])}
    f = np.zeros(len(b["cases"]))
    for case, factor in combo.items():
        f[col[case]] = factor
    return f


def combine(b, combo: dict):
    """(F, R_F) of a combination {case: factor}."""
    f = factors(b, combo)
    return b["F"] @ f, b["RF"] @ f


def load_vector(b, combo: dict):
    """(F, u_a): the combination's nodal loads and settlements."""
    f = factors(b, combo)
    return b["F"] @ f, b["U"] @ f


def mechanism_message(S, free, names, nf, dofs=DOFS) -> str:
    """Name the free motion of a singular basic system (its null vector);
    ``dofs``: the dof names of a node."""
    if S.shape[0] > 4000:
        return ("the basic system (every contact link fixed) is singular: the frame is a "
                "mechanism even with every contact closed, or two contacts constrain the same "
                "displacement; add supports or remove a redundant contact")
    S = S.toarray()
    try:
        null = scipy.linalg.null_space(S, rcond=1e-12)
    except (ValueError, np.linalg.LinAlgError):
        null = np.zeros((S.shape[0], 0))
    if null.shape[1] == 0:
        return ("the basic system (every contact link fixed) is singular: check supports, "
                "hinges and that no two contacts constrain the same displacement")
    v = null[:nf, 0]
    if np.max(np.abs(v)) <= 1e-9 * np.max(np.abs(null[:, 0])):
        return ("two or more contact links constrain the same displacement (redundant links): "
                "remove one of them")
    order = np.argsort(-np.abs(v))[:3]
    moves = ", ".join(f"{names[free[i] // len(dofs)]} {dofs[free[i] % len(dofs)]}" for i in order
                      if abs(v[i]) > 0.1 * abs(v[order[0]]))
    together = "move together" if "," in moves else "alone"
    return (f"the frame is a mechanism even with every contact closed: it can move freely "
            f"({moves} {together}); add supports, contacts or friction that prevent it")


def layout(b):
    """Per contact: the link positions of n and t (cached in b)."""
    if "layout" not in b:
        pos = {}
        for li, (ci, kind) in enumerate(b["info"]):
            pos.setdefault(ci, {})[kind] = li
        b["layout"] = pos
    return b["layout"]


def contact_arrays(frame, b) -> dict:
    """The contacts as arrays (cached in b): link of n and of t (-1 without
    friction), friction, gap, unit normal, node and other node (-1)."""
    if "contact_arrays" not in b:
        pos = layout(b)
        cs = frame.contacts
        idx = b["idx"]
        b["contact_arrays"] = dict(
            n_link=np.array([pos[ci]["n"] for ci in range(len(cs))], int),
            t_link=np.array([pos[ci].get("t", -1) for ci in range(len(cs))], int),
            mu=np.array([c.friction for c in cs]), gap=np.array([c.gap for c in cs]),
            normal=np.array([c.normal for c in cs]).reshape(len(cs), 2),
            node=np.array([idx[c.node] // 3 for c in cs], int),
            other=np.array([-1 if c.other is None else idx[c.other] // 3 for c in cs], int))
    return b["contact_arrays"]


def link_maps(frame, b):
    """(P, W, g, fric): the link displacements Δ = P z - g and the LCP's w =
    W X as sparse selections with the friction coefficients (z = Z_n per
    contact, then Z⁺, Z⁻ per frictional contact; ``fric`` the frictional
    contacts' indices).  Cheap: no R.  Cached in b."""
    if "maps" in b:
        return b["maps"]
    ca = contact_arrays(frame, b)
    nc = len(frame.contacts)
    has_t = ca["t_link"] >= 0
    fric = np.flatnonzero(has_t).tolist()
    nl = len(b["info"])
    nz = nc + 2 * len(fric)
    tl, n_of_t, mu = ca["t_link"][has_t], ca["n_link"][has_t], ca["mu"][has_t]
    plus = nc + 2 * np.arange(len(fric))
    P = sp.csr_matrix((np.r_[np.ones(nc), np.ones(len(fric)), -np.ones(len(fric))],
                       (np.r_[ca["n_link"], tl, tl], np.r_[np.arange(nc), plus, plus + 1])),
                      shape=(nl, nz))
    g = np.zeros(nl)
    g[ca["n_link"]] = ca["gap"]
    # rows of w as combinations of the link forces X: X_n; f X_n + X_t; f X_n - X_t
    W = sp.csr_matrix((np.r_[np.ones(nc), mu, np.ones(len(fric)), mu, -np.ones(len(fric))],
                       (np.r_[np.arange(nc), plus, plus, plus + 1, plus + 1],
                        np.r_[ca["n_link"], n_of_t, tl, n_of_t, tl])), shape=(nz, nl))
    b["maps"] = (P, W, g, fric)
    return b["maps"]


def lcp_matrices(frame, b):
    """(M, Q, q_gap, P, g, fric): w = M z + Q f + q_gap for the case factors
    f (Q has one column per case of b["cases"]); Δ = P z - g (P dense).
    Computed once per assembly (cached in b); forms R."""
    if "lcp" in b:
        return b["lcp"]
    P, W, g, fric = link_maps(frame, b)
    R = b["R"]
    M = np.asarray((P.T @ (W @ R).T).T) if P.shape[1] else np.zeros((0, 0))
    if not fric:
        M = 0.5 * (M + M.T)  # = R_nn exactly; remove rounding asymmetry
    b["lcp"] = (M, np.asarray(W @ b["RF"]), -np.asarray(W @ (R @ g)), P.toarray(), g, fric)
    return b["lcp"]


def combination_q(Q, q_gap, b, combo):
    """q and its terms' sizes (each case's share and the gaps': what a force
    that is their difference is judged against)."""
    col = {c: k for k, c in enumerate(b["cases"])}
    q = q_gap.copy()
    terms = np.abs(q_gap)
    for case, factor in combo.items():
        share = factor * Q[:, col[case]]
        q = q + share
        terms = terms + np.abs(share)
    return q, terms


def combination_lcp(M, Q, q_gap, b, combo) -> LCP:
    q, terms = combination_q(Q, q_gap, b, combo)
    return LCP(M, q, q_terms=terms)
