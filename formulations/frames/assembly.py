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

from .loads import CONSTANT, VARIABLE, equivalent_nodal

DOFS = ("ux", "uy", "rz")
#: Entries of the contact stiffness R below R_ROUNDING x (largest stiffness
#: term) are rounding noise of the basic-system solve and are set to zero.
R_ROUNDING = 256 * np.finfo(float).eps


def beam_k(E, A, I, L):
    """Local 6x6 stiffness of a 2-D Euler-Bernoulli frame element."""
    a, b, c, d = E * A / L, 12 * E * I / L ** 3, 6 * E * I / L ** 2, 4 * E * I / L
    return np.array([[a, 0, 0, -a, 0, 0],
                     [0, b, c, 0, -b, c],
                     [0, c, d, 0, -c, d / 2],
                     [-a, 0, 0, a, 0, 0],
                     [0, -b, -c, 0, b, -c],
                     [0, c, d / 2, 0, -c, d]])


def geometry(frame, m):
    """(L, cos, sin) of a member's axis."""
    d = frame.nodes[m.j] - frame.nodes[m.i]
    L = math.hypot(d[0], d[1])
    if L == 0:
        raise InvalidProblemError(f"member {m.name}: nodes {m.i} and {m.j} coincide")
    return L, float(d[0]) / L, float(d[1]) / L


def rotation(c, s) -> np.ndarray:
    """T (6x6): global end displacements to member axes."""
    T = np.zeros((6, 6))
    T[:3, :3] = T[3:, 3:] = ((c, s, 0.0), (-s, c, 0.0), (0.0, 0.0, 1.0))
    return T


def member_local(frame, m):
    """Local stiffness and equivalent nodal loads of every case that loads
    the member, with hinges condensed.  Returns (k, {case: fe}, T, L)."""
    L, c, s = geometry(frame, m)
    T = rotation(c, s)
    k = beam_k(m.E, m.A, m.I, L)
    fes = {}
    for load in m.loads:
        fes[load.case] = fes.get(load.case, 0.0) + equivalent_nodal(load, L, c, s)
    for r, hinged in ((2, m.hinge_i), (5, m.hinge_j)):
        if hinged:
            kr = k[:, r].copy()
            fes = {case: fe - kr * fe[r] / k[r, r] for case, fe in fes.items()}
            k = k - np.outer(kr, kr) / k[r, r]
            k[r, :] = 0.0
            k[:, r] = 0.0
    return k, fes, T, L


def cases(frame) -> list:
    """Every load case with a load, plus the P3 pair (constant, variable)."""
    names = {CONSTANT, VARIABLE}
    names.update(ld[4] for ld in frame.nodal_loads)
    names.update(st[2] for st in frame.settlements)
    for m in frame.members.values():
        names.update(ld.case for ld in m.loads)
    return sorted(names)


def assemble(frame):
    names = list(frame.nodes)
    idx = {nm: 3 * i for i, nm in enumerate(names)}
    N = 3 * len(names)
    rows, cols, vals = [], [], []   # K in triplets: frames are sparse (a beam is banded)
    case_list = cases(frame)
    col = {c: k for k, c in enumerate(case_list)}
    F = np.zeros((N, len(case_list)))
    local = {}   # per member: (k, {case: fe}, T, dofs), reused by the results
    for m in frame.members.values():
        k, fes, T, _ = member_local(frame, m)
        dofs = np.r_[idx[m.i]:idx[m.i] + 3, idx[m.j]:idx[m.j] + 3]
        local[m.name] = (k, fes, T, dofs)
        rows.append(np.repeat(dofs, 6))
        cols.append(np.tile(dofs, 6))
        vals.append((T.T @ k @ T).ravel())
        for case, fe in fes.items():
            F[dofs, col[case]] += T.T @ fe
    for node, fx, fy, mz, case in frame.nodal_loads:
        F[idx[node]:idx[node] + 3, col[case]] += (fx, fy, mz)
    U = np.zeros_like(F)   # prescribed displacements (settlements) of fixed dofs, per case
    for node, dof, case, value in frame.settlements:
        U[idx[node] + DOFS.index(dof), col[case]] += value
    for node, ks in frame.springs.items():
        for d, kval in ks.items():
            i = idx[node] + DOFS.index(d)
            rows.append([i])
            cols.append([i])
            vals.append([kval])
    K = sp.csr_matrix((np.concatenate(vals) if vals else np.zeros(0),
                       (np.concatenate(rows) if rows else np.zeros(0, int),
                        np.concatenate(cols) if cols else np.zeros(0, int))), shape=(N, N))
    fixed = np.zeros(N, bool)
    for node, dofs in frame.fixed.items():
        for d in dofs:
            fixed[idx[node] + DOFS.index(d)] = True
    # a rotation no member resists (only hinged ends, or no member) is not a dof
    fixed |= np.isclose(K.diagonal(), 0.0) & (np.arange(N) % 3 == 2)
    return names, idx, K, F, U, case_list, fixed, local


def contact_column(idx, N, c, vec) -> np.ndarray:
    """The column of H mapping a force along ``vec`` at contact c to the
    nodal forces (minus at ``other`` for a pair)."""
    h = np.zeros(N)
    h[idx[c.node]:idx[c.node] + 2] += vec
    if c.other is not None:
        h[idx[c.other]:idx[c.other] + 2] -= vec
    return h


def links(frame, idx, N):
    """H (N x links) and, per link: contact index, kind 'n'/'t'."""
    cols, info = [], []
    for ci, c in enumerate(frame.contacts):
        t = np.array([c.normal[1], -c.normal[0]])
        for kind, vec in (("n", c.normal), ("t", t)):
            if kind == "t" and c.friction == 0:
                continue  # no tangential link without friction
            cols.append(contact_column(idx, N, c, vec))
            info.append((ci, kind))
    return (np.array(cols).T if cols else np.zeros((N, 0))), info


def check_conflicts(frame):
    """A contact whose normal (or tangent, with friction) displacement the
    bilateral supports already fix would make the basic system singular:
    name the node and the dofs instead."""
    for c in frame.contacts:
        if c.other is not None:
            continue
        fixed = frame.fixed.get(c.node, set())
        dirs = [("normal", c.normal)]
        if c.friction > 0:
            dirs.append(("tangential", np.array([c.normal[1], -c.normal[0]])))
        for what, vec in dirs:
            free_axes = [d for d, comp in zip(("ux", "uy"), vec) if abs(comp) > 0 and d not in fixed]
            if not free_axes:
                held = sorted(d for d, comp in zip(("ux", "uy"), vec) if abs(comp) > 0)
                raise InvalidProblemError(
                    f"node {c.node!r}: the contact's {what} direction {tuple(np.round(vec, 6))} is "
                    f"already fixed by its bilateral support ({', '.join(held)}); a contact and a "
                    "support may share a node only where they constrain different directions — "
                    "remove one of them")


def build(frame):
    """Assemble K, the links, and R, R_F per load case.  Returns a dict with
    everything the LCP and the results need."""
    if not frame.contacts:
        raise InvalidProblemError("the frame has no contacts: it is a linear problem; "
                                  "add_contact() defines the unilateral supports")
    check_conflicts(frame)
    names, idx, K, F, U, case_list, fixed, local = assemble(frame)
    N = K.shape[0]
    H, info = links(frame, idx, N)
    free = np.flatnonzero(~fixed)
    Kf = K[free][:, free]
    # The links enter scaled by a typical stiffness kappa, so that the saddle
    # matrix is balanced (steel in N and m has K ~ 1e8 against H ~ 1) and
    # the singularity test below is meaningful: X = -kappa y.
    kappa = float(np.max(np.abs(Kf.diagonal()))) if free.size else 1.0
    Hf = sp.csr_matrix(kappa * H[free])
    nl = Hf.shape[1]
    # one sparse LU of the saddle matrix (a 1000-span beam: 4000 unknowns,
    # 1.7 s dense, milliseconds sparse); its pivots say whether it is singular
    # Elastic contacts: the link's displacement is the structure's plus the
    # spring's, H'u + D X = Δ (D = diag 1/k), so D enters the saddle matrix
    # (scaled like the links) and R, R_F come out elastic — no dense
    # (I + R D)⁻¹ on nl x nl.
    flex = np.array([0.0 if frame.contacts[ci].stiffness is None
                     else 1.0 / frame.contacts[ci].stiffness for ci, _ in info])
    S = sp.bmat([[Kf, Hf], [Hf.T, sp.diags(-kappa ** 2 * flex)]], format="csc")
    try:
        lu = spla.splu(S)
        piv = np.abs(lu.U.diagonal())
    except RuntimeError:   # exactly singular
        lu, piv = None, np.zeros(1)
    if lu is None or not piv.min() > 1e-13 * piv.max():
        raise InvalidProblemError(mechanism_message(S, free, names, Kf.shape[0]))
    nf = free.size
    nc = len(case_list)
    rhs = np.zeros((nf + nl, nl + nc))
    rhs[nf:, :nl] = kappa * np.eye(nl)
    # settlements: the free dofs feel -K_fa u_a, the links see H_a' u_a already done
    fixed_idx = np.flatnonzero(fixed)
    rhs[:nf, nl:] = F[free] - K[free][:, fixed_idx] @ U[fixed_idx]
    rhs[nf:, nl:] = -kappa * (H[fixed_idx].T @ U[fixed_idx])
    sol = lu.solve(rhs)
    R = -kappa * sol[nf:, :nl]
    R = 0.5 * (R + R.T)
    # R's entries are sums of terms of size kappa (the stiffness), so each
    # carries a rounding error of a few eps * kappa.  An entry that small is
    # zero: a dislocation that a rigid motion of the frame absorbs (a portal
    # on two pins lifted at one base) costs no force, and noise in its place
    # would turn "this link has no effect" into a random sign — which the
    # trace's collapse proof (a Farkas vector, M'y <= 0 column by column)
    # and the support states would read as data.
    R[np.abs(R) <= R_ROUNDING * kappa] = 0.0
    RF = -kappa * sol[nf:, nl:]
    return dict(names=names, idx=idx, K=K, F=F, U=U, cases=case_list, fixed=fixed, free=free, H=H,
                info=info, lu=lu, R=R, RF=RF, flex=flex, nf=nf, kappa=kappa, local=local)


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


def mechanism_message(S, free, names, nf) -> str:
    """Name the free motion of a singular basic system (its null vector)."""
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
    moves = ", ".join(f"{names[free[i] // 3]} {DOFS[free[i] % 3]}" for i in order
                      if abs(v[i]) > 0.1 * abs(v[order[0]]))
    return (f"the frame is a mechanism even with every contact closed: it can move freely "
            f"({moves} move together); add supports, contacts or friction that prevent it")


def layout(b):
    """Per contact: the link positions of n and t."""
    pos = {}
    for li, (ci, kind) in enumerate(b["info"]):
        pos.setdefault(ci, {})[kind] = li
    return pos


def lcp_matrices(frame, b):
    """(M, Q, q_gap, P, g, fric): w = M z + Q f + q_gap for the case factors
    f (Q has one column per case of b["cases"]); Δ = P z - g.  Computed once
    per assembly (cached in b)."""
    if "lcp" in b:
        return b["lcp"]
    pos = layout(b)
    nc = len(frame.contacts)
    fric = [ci for ci in range(nc) if "t" in pos[ci]]
    nl = len(b["info"])
    nz = nc + 2 * len(fric)
    # P (links x z) and W (w rows x links) are selections with friction
    # coefficients: sparse, so that M = W R P costs what R costs
    pr, pc, pv = [], [], []
    g = np.zeros(nl)
    for ci in range(nc):
        pr.append(pos[ci]["n"]), pc.append(ci), pv.append(1.0)
        g[pos[ci]["n"]] = frame.contacts[ci].gap
    for k, ci in enumerate(fric):
        pr += [pos[ci]["t"], pos[ci]["t"]]
        pc += [nc + 2 * k, nc + 2 * k + 1]
        pv += [1.0, -1.0]
    P = sp.csr_matrix((pv, (pr, pc)), shape=(nl, nz))
    # rows of w as combinations of the link forces X: X_n; f X_n + X_t; f X_n - X_t
    wr, wc, wv = [], [], []
    for ci in range(nc):
        wr.append(ci), wc.append(pos[ci]["n"]), wv.append(1.0)
    for k, ci in enumerate(fric):
        f = frame.contacts[ci].friction
        n_, t_ = pos[ci]["n"], pos[ci]["t"]
        wr += [nc + 2 * k, nc + 2 * k, nc + 2 * k + 1, nc + 2 * k + 1]
        wc += [n_, t_, n_, t_]
        wv += [f, 1.0, f, -1.0]
    W = sp.csr_matrix((wv, (wr, wc)), shape=(nz, nl))
    R = b["R"]
    M = np.asarray((P.T @ (W @ R).T).T) if nz else np.zeros((0, 0))
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
