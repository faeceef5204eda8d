"""The contact LCP both frames share (Osipova–Popov–Lovtsov's displacement
method): the basic system, the contact stiffness, the LCP of a load combination.
A plane frame's K and links are assembled in
:mod:`..plane.plane_assembly`, a space frame's in :mod:`..space.space_assembly`.

K u = F + H X: the frame's stiffness on its free degrees of freedom, the
loads, and the contact links' forces X mapped by H (columns n and t at the
contact's node, minus at ``other``).  The links' relative displacements are
Δ = H'u.  The contact stiffness R and load vectors R_F of the *basic system*
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
and w = (X_n, f X_n + X_t, f X_n - X_t) (Osipova–Popov–Lovtsov's holonomic Coulomb law: total
slip against total force).  Contacts with f = 0 build no tangential link at
all, and a frame without friction builds the normal-only LCP (M = R_nn,
symmetric positive semidefinite).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from qpcontact.core.problems import LCP

from . import banded_saddle
from .refinement import is_refined, refined_columns


#: Entries of the contact stiffness R below R_ROUNDING x (largest stiffness
#: term) are rounding noise of the basic-system solve and are set to zero.
R_ROUNDING = 256 * np.finfo(float).eps


def global_stiffness(local, springs, idx, dofs, N):
    """K (CSR, N x N) and the members' loads F (N x cases) from their
    blocks ``local`` = (k, T, dofs, Fe) (:func:`.plane_element.member_locals`,
    the space assembly's): Tᵀ k T and Tᵀ Fe scattered to the members' dofs,
    then the springs to the ground {node: {dof: k}} (``dofs``: the dof
    names of a node, in order; ``idx``: each node's first dof), in one
    compiled pass (:func:`._frame_kernels.global_stiffness`: each entry
    summed in member order).  As array expressions it was two stacks of
    BLAS calls, a scipy COO → CSR conversion and a bincount."""
    from ._frame_kernels import global_stiffness as compiled
    k, T, at, Fe = local
    spring = [(idx[node] + dofs.index(d), kval) for node, ks in springs.items()
              for d, kval in ks.items()]
    data, indices, indptr, F = compiled(k, T, at, Fe, np.array([r for r, _ in spring], np.int64),
                                        np.array([v for _, v in spring], float), N)
    K = sp.csr_matrix((data, indices, indptr), shape=(N, N))
    K.has_canonical_format = True       # each row's columns distinct and ascending
    return K, F


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
    # summed by bincount, in np.add.at's order from zero: the same sums, a
    # third of the time (five calls a beam solve: 1.1 ms at 1000 spans)
    # (float where there is no member: bincount of no weights counts, in
    # integers, which the springs' and loads' terms cannot be added to)
    terms = np.bincount(dofs.ravel(),
                        np.abs((T.transpose(0, 2, 1) @ ends[..., None])[..., 0]).ravel(),
                        minlength=ug.size).astype(float, copy=False)
    terms += np.abs(b["springs"] * ug)
    if b["Tn"] is not None:
        terms = abs(b["Tn"]) @ terms
    return terms + np.abs(F)


def member_end_actions(b, u, combo_factors) -> np.ndarray:
    """Every member's end actions k T u - f (member axes), (m, 6), from the
    global displacements u."""
    k, T, dofs, Fe = b["local"]
    # the fixed-end forces as one matrix-vector product (a member's rows
    # are the same dot products as the stack's, one BLAS call for all)
    fixed_end = (Fe.reshape(-1, Fe.shape[2]) @ combo_factors).reshape(Fe.shape[:2])
    return (k @ (T @ u[dofs][..., None]))[..., 0] - fixed_end


def to_global(b, v):
    """A vector (or the columns of a matrix) of dofs from the nodes' axes to global."""
    return v if b["Tn"] is None else b["Tn"].T @ v


def to_nodes(b, v):
    """A vector of dofs from global axes to the nodes' own (a result's
    displacements back into the system's axes, to start a solve from)."""
    return v if b["Tn"] is None else b["Tn"] @ v


#: a saddle matrix whose LU pivots span more than this is singular: a
#: mechanism, which rounding would otherwise answer with a rigid motion of
#: 1e11 m that every scaled check passes
SINGULAR_PIVOTS = 1e-13


class ScaledLU:
    """The LU of D S D (D diagonal, powers of two: exact) solving S x = r as
    x = D (DSD)⁻¹ D r — what :func:`regular_lu` returns.  Pickled without
    its factors (SciPy's SuperLU does not pickle: a trace, which keeps its
    assembly for ``result_at``, could not be sent to another process): S
    goes instead, factorized again on loading — the same call on the same
    matrix, so the same factors and solves bit for bit."""

    def __init__(self, lu, d, S=None):
        self.lu, self.d, self.S = lu, d, S

    def __getstate__(self) -> dict:
        return {"d": self.d, "S": self.S}

    def __setstate__(self, state) -> None:
        self.d, self.S = state["d"], state["S"]
        self.lu = None if self.S is None else spla.splu(_scaled(self.S, self.d))

    def solve(self, rhs):
        rhs = np.asarray(rhs)
        if self.lu is None:                    # the empty system
            return np.zeros(rhs.shape)
        d = self.d if rhs.ndim == 1 else self.d[:, None]
        return d * self.lu.solve(d * rhs)

    def link_rows(self, rhs, nl):
        """The last nl rows (the links') of S⁻¹ rhs: the whole solve
        (:meth:`.banded_saddle.CondensedLU.link_rows` saves work there)."""
        return self.solve(rhs)[len(rhs) - nl:]

    def contact_rows(self, kappa, r1, r2):
        """The link rows of S⁻¹ [0 r1; κI r2]
        (:meth:`.banded_saddle.CondensedLU.contact_rows`)."""
        return self.link_rows(banded_saddle.dislocations(kappa, r1, r2), r2.shape[0])


def regular_lu(S, pivots=True):
    """The LU of S (a :class:`ScaledLU`), or None where S is singular
    (exactly, or, with ``pivots``, its pivots spanning more than
    1/SINGULAR_PIVOTS).

    S is first scaled symmetrically by powers of two, each row and column
    by the square root of its largest entry, so that the pivots measure
    singularity rather than units: an elastic pad's link row carries
    kappa²/k (soft pads under a deck 1e8 times stiffer than the legs:
    4e24 beside the legs' 1e3), and unscaled the pivots of a sound table
    spanned 4e-24 — "a mechanism even with every contact closed"."""
    if S.shape[0] == 0:
        return ScaledLU(None, np.zeros(0))     # every dof held and no link: nothing to solve
    # read only: a canonical CSC without stored zeros (the basic system's S,
    # a state set's matrix) is used as it is; anything else is copied and
    # made so — a copy and its checks are a tenth of a small factorization
    if not (S.format == "csc" and S.has_canonical_format and np.all(S.data != 0.0)):
        S = sp.csc_matrix(S, copy=True)
        S.sum_duplicates()
        S.eliminate_zeros()    # exact zeros (a level member's k) are no structure
    # each row's largest entry, and D S D entry by entry (_scaled)
    big = np.zeros(S.shape[0])
    np.maximum.at(big, S.indices, np.abs(S.data))
    if not np.all(big > 0):
        return None            # an empty row: exactly singular
    d = 2.0 ** -np.round(0.5 * np.log2(big))
    try:
        lu = spla.splu(_scaled(S, d))
    except RuntimeError:   # exactly singular
        return None
    piv = np.abs(lu.U.diagonal())
    return (ScaledLU(lu, d, S) if piv.size and (piv.min() > SINGULAR_PIVOTS * piv.max()
                                                or not pivots and piv.min() > 0) else None)


def _scaled(S, d):
    """D S D of a canonical CSC S, entry by entry (d_i s_ij d_j: exact in
    powers of two; the sparse products D @ S @ D cost more than the
    factorization itself, 1.5 against 1.4 ms at 1600 unknowns)."""
    cols = np.repeat(np.arange(S.shape[1]), np.diff(S.indptr))
    return sp.csc_matrix((S.data * d[S.indices] * d[cols], S.indices, S.indptr), shape=S.shape)


class Built(dict):
    """A frame's assembly: K, loads, links, the saddle matrix's LU, ... (see
    :func:`build`).  The contact stiffness R (and R_solve, the same before its
    rounding-level entries are dropped) and the load columns R_F — dense,
    links x links, the cost of a long beam's LCP (1000 spans: 2 000 links, one
    solve per link) — are computed on first use, so a route that never needs
    the LCP's matrix (the sparse active set) never pays for them."""

    def __missing__(self, key):
        if key in DERIVED:
            self[key] = DERIVED[key](self)
            return self[key]
        if key not in ("R", "RF", "R_solve"):
            raise KeyError(key)
        self.update(contact_stiffness(self))
        return self[key]


#: matrices read off the assembly by every check and state set, made once
#: per assembly on first use (each was a scipy.sparse construction per use:
#: |K| and |H| for every equilibrium check, Hᵀ and |H|ᵀ per solve, the
#: fixed dofs' rows of H per recovery — 27 to 57 constructions of 30-150 µs
#: in a solve); the same values, bit for bit
DERIVED = {
    # |K| on K's own index arrays (abs() copies them)
    "abs_K": lambda b: sp.csr_matrix((np.abs(b["K"].data), b["K"].indices, b["K"].indptr),
                                     shape=b["K"].shape),
    # H's entries (rows, columns, values) in its CSR order, which H X and
    # |H||X| read (:func:`link_forces`, :func:`link_force_sizes`)
    "H_entries": lambda b: csr_triplets(b["H"]),
    "HT": lambda b: b["H"].T.tocsr(),
    "abs_HT": lambda b: abs(b["HT"]),
    "abs_P": lambda b: abs(b["maps"][0]),
    "abs_W": lambda b: abs(b["maps"][1]),
    # the nodes about their centroid (np.mean's sum), the arms' sizes and
    # the frame's extent: what a plane frame's resultant check reads
    "moment_arms": lambda b: _moment_arms(b["coords"]),
    # the links' displacement by the settlements: Hᵀ at the fixed dofs
    "H_fixed_T": lambda b: b["H"][b["fixed_idx"]].T,
    "K_fa": lambda b: _coupling(b),
    "Hf": lambda b: _scaled_free_links(b),
    "S": lambda b: saddle_matrix(b),
}


def _moment_arms(coords):
    xy = coords - coords.sum(axis=0) / len(coords)
    extent = max(float(np.hypot(*(xy.max(axis=0) - xy.min(axis=0)))), 1e-300)
    return xy, np.abs(xy[:, 0]), np.abs(xy[:, 1]), extent


def link_forces(b, X) -> np.ndarray:
    """H X: the link forces X (one vector) as forces on the dofs, each dof's
    terms summed from zero in H's CSR order — scipy's product's sums in its
    order, without its set-up (a few µs a product, where a tower's H has 34
    entries)."""
    rows, cols, vals = b["H_entries"]
    return np.bincount(rows, vals * X[cols], b["H"].shape[0])


def link_force_sizes(b, X) -> np.ndarray:
    """|H||X|: the sizes of the link forces' terms at each dof, summed as
    :func:`link_forces` sums them (|H| was a sparse matrix made per
    assembly for one product)."""
    rows, cols, vals = b["H_entries"]
    return np.bincount(rows, np.abs(vals) * np.abs(X)[cols], b["H"].shape[0])


def basic_system(K, H, fixed, flex, translational, pairs=None, strain_free=None) -> dict:
    """The basic system (every link fixed) of a structure with stiffness K
    (all dofs), links H and contact flexibilities ``flex``, any number of
    dofs per node: the free/fixed blocks of K, the scaled saddle matrix
    S = [K_ff kappa H_f; kappa H_f' -kappa² D] and its LU (None where S is
    singular: a mechanism).  ``translational`` marks the dofs that links
    push along, which set kappa; ``pairs`` (t, n): each frictional
    contact's tangent and normal link (:func:`.banded_saddle.layout`).

    ``strain_free(free)``: the motions of the free dofs that strain no member
    with every link held (:func:`.member_forces.strain_free_motions`).
    Where the pivots alone call S singular, it decides: no such motion —
    the spread is the members' contrast, not a mechanism (a portal whose
    deck is 1e9 times stiffer than its columns: pivots 1e-14 apart), and
    the LU is kept; the answers' checks and the refinement in extended
    precision (R past :data:`.refinement.CONTRAST`) judge what it gives."""
    # the free dofs, kappa and the blocks on the free dofs in one compiled
    # pass over K's and H's entries (as array expressions and fancy
    # indexing, a few dozen NumPy calls)
    free, fixed_idx, kappa, k_ff, (hv, hr, hc) = free_blocks(K, H, fixed, translational)
    nf = free.size
    nl = H.shape[1]
    # on elastic contacts the saddle matrix is solved through its condensed
    # stiffness, banded (:mod:`.banded_saddle`), and S itself is made only
    # where something reads it; else, and where that reads singular, by
    # SuperLU, whose pivots decide
    band = banded_saddle.layout(nf, nl, kappa, flex, k_ff, (hr, hc, hv), pairs, (K, free))
    lu = (banded_saddle.factor(band, np.ones(nl, bool), np.zeros(nl), np.zeros(nl, int))
          if band is not None else None)
    out = dict(free=free, nf=nf, fixed_idx=fixed_idx, kappa=kappa, band=band, lu=lu,
               translational=translational)
    if lu is None:
        # one sparse LU of the saddle matrix (a 1000-span beam: 4000
        # unknowns, 1.7 s dense, milliseconds sparse); its pivots say whether
        # it is singular
        out["S"] = _saddle(k_ff, (hv, hr, hc), flex, nf, kappa)
        out["lu"] = regular_lu(out["S"])
        # (rigid links that constrain the same displacement make S singular
        # with no motion free either: that is no contrast, and the caller
        # names them — a node between two opposite pads)
        if out["lu"] is None and strain_free is not None and 0 < nf <= KINEMATIC_MAX \
                and not dependent_links((hv, hr, hc), nf, nl, flex):
            # (kept for the mechanism's words where it finds a motion: S's
            # null space to rounding mixes a soft member's stretch into it)
            out["strain_free"] = strain_free(free)
        if out["lu"] is None and out.get("strain_free") is not None \
                and out["strain_free"].shape[1] == 0:
            out["lu"] = regular_lu(out["S"], pivots=False)
            if out["lu"] is None:
                out["no_mechanism"] = True     # singular in double, not in the mechanics
    return out


def dependent_links(h_triplets, nf, nl, flex) -> bool:
    """Whether the rigid links' columns of H_f (``h_triplets``: κH_f's
    values, rows, columns) are linearly dependent: two or more of them
    constrain the same displacement, and S is singular whatever the
    members' stiffnesses."""
    rigid = np.asarray(flex, float) == 0.0
    if not rigid.any():
        return False
    hv, hr, hc = h_triplets
    Hf = np.zeros((nf, nl))
    np.add.at(Hf, (hr, hc), hv)
    Hf = Hf[:, rigid]
    if Hf.shape[1] > Hf.shape[0]:
        return True
    s = np.linalg.svd(Hf, compute_uv=False)
    return bool(s.size and s.min() <= 1e-10 * max(s.max(), 1e-300))


#: the most free dofs whose strain-free motions are looked for (a dense SVD)
#: where the pivots call the basic system singular
KINEMATIC_MAX = 3000


def saddle_matrix(b):
    """S = [K_ff κH_f; κH_f' −κ² D] of an assembly (CSC, canonical, without
    stored zeros), made on first use where the basic system's LU is the
    condensed banded one."""
    _, _, kappa, k_ff, h_f = free_blocks(b["K"], b["H"], b["fixed"], b["translational"])
    return _saddle(k_ff, h_f, b["flex"], b["nf"], kappa)


def free_blocks(K, H, fixed, translational):
    """(free dofs, fixed dofs, κ, K_ff's (rows, columns, values) but its
    exact zeros, κH_f's (values, rows, columns)), rows and columns among
    the free dofs, in one compiled pass (:func:`._frame_kernels.free_blocks`).

    The links enter the saddle matrix scaled by a typical stiffness κ, so
    that it is balanced (steel in N and m has K ~ 1e8 against H ~ 1) and
    the singularity test is meaningful: X = −κ y.  Links push nodes along,
    so κ is the largest *translational* stiffness on K's diagonal at the
    free dofs: the largest of all is a rotation's (moment per radian),
    which in N and mm is 1e5 times a translation's, and κ²/k on an elastic
    contact's diagonal then made a sound beam look like a mechanism
    (pivots 3e-14 apart).  No stiffness on those dofs at all (a node on a
    contact, no member): κ = 1, where 0 would drop the links and name a
    held dof as the free one.  K_ff's exact zeros — a level member's
    axial-bending terms, nearly half of a beam's entries — are no
    structure that every state set's matrix and factorization should
    carry."""
    from ._frame_kernels import free_blocks as compiled
    K, H = K.tocsr(), H.tocsr()
    return compiled(K.indptr, K.indices, K.data, H.indptr, H.indices, H.data,
                    np.asarray(fixed, bool), np.asarray(translational, bool))


def _saddle(k_triplets, h_triplets, flex, nf, kappa):
    """The saddle matrix from the blocks' triplets (K and H are summed, so
    no entry is repeated and the order does not matter), without stored
    zeros."""
    (kr, kc, kv), (hv, hr, hc) = k_triplets, h_triplets
    nl = len(flex)
    links_ = np.arange(nl)
    vals = np.concatenate((kv, hv, hv, -kappa ** 2 * np.asarray(flex, float)))
    nz = vals != 0.0
    return sp.csc_matrix((vals[nz], (np.concatenate((kr, hr, nf + hc, nf + links_))[nz],
                                     np.concatenate((kc, nf + hc, hr, nf + links_))[nz])),
                         shape=(nf + nl, nf + nl))


def csr_triplets(A):
    """(rows, columns, values) of a CSR matrix's stored entries in their
    stored order — what ``tocoo`` gives, without building a COO matrix (a
    tenth of a millisecond each, twice per assembly)."""
    A = A.tocsr()
    return np.repeat(np.arange(A.shape[0]), np.diff(A.indptr)), A.indices, A.data


def _positions(b):
    """Each dof's row among the free dofs (-1 where fixed)."""
    at = np.full(b["K"].shape[0], -1)
    at[b["free"]] = np.arange(b["nf"])
    return at


def _coupling(b):
    """K_fa: the free dofs' rows of K at the fixed dofs' columns (what
    settlements load the free dofs with)."""
    at, fixed_idx = _positions(b), b["fixed_idx"]
    at_fixed = np.full(at.size, -1)
    at_fixed[fixed_idx] = np.arange(fixed_idx.size)
    Kc = b["K"].tocoo()
    r, c = at[Kc.row], at[Kc.col]
    fa = (r >= 0) & (c < 0)
    return sp.csr_matrix((Kc.data[fa], (r[fa], at_fixed[Kc.col[fa]])),
                         shape=(b["nf"], fixed_idx.size))


def _scaled_free_links(b):
    """κ H_f: the links at the free dofs, scaled as in the saddle matrix."""
    hv, hr, hc = free_blocks(b["K"], b["H"], b["fixed"], b["translational"])[4]
    return sp.csr_matrix((hv, (hr, hc)), shape=(b["nf"], b["H"].shape[1]))


def settled_links(b, ua):
    """The links' displacements by the settlements ``ua`` (at the fixed
    dofs; a vector or one column per case), Hᵀ at the fixed dofs times ua
    there — zero where nothing settles, without the sparse slice of H
    (made on first use: 0.06 ms of a 20-storey tower's solve, which has
    no fixed dof at all)."""
    ua_fixed = ua[b["fixed_idx"]]
    if not ua_fixed.any():
        return np.zeros((b["H"].shape[1],) + ua.shape[1:])
    return b["H_fixed_T"] @ ua_fixed


def free_loads(b, F, ua):
    """F at the free dofs less what the settlements ``ua`` (at the fixed
    dofs; a vector or one column per case) put on them, K_fa u_a — left
    out, exactly, where nothing settles (x − 0 is x)."""
    ua_fixed = ua[b["fixed_idx"]]
    if not ua_fixed.any():
        return F[b["free"]]
    return F[b["free"]] - b["K_fa"] @ ua_fixed


def basic_columns(b):
    """The right-hand sides of the basic system whose link rows are R_F (the
    columns next to R's unit dislocations, one per load case): the free
    dofs' loads less what the settlements put on them, and −κ times the
    links' settled displacement."""
    U = b["U"]
    return free_loads(b, b["F"], U), -b["kappa"] * settled_links(b, U)


def load_sizes(b) -> np.ndarray:
    """Per load case, the largest load and settlement force (kN) at the scale
    the basic system's solve sees them, max |F| + κ max |U|: what R_F's
    entries are rounded against."""
    return (np.abs(b["F"]).max(axis=0, initial=0.0)
            + b["kappa"] * np.abs(b["U"]).max(axis=0, initial=0.0))


def contact_stiffness(b) -> dict:
    """R (links x links) and R_F (one column per case) from unit
    dislocations through the basic system's LU (the module docstring)."""
    nf, kappa = b["nf"], b["kappa"]
    nl = len(b["info"])
    nc = len(b["cases"])
    # settlements: the free dofs feel -K_fa u_a, the links see H_a' u_a already done
    loads, settled = basic_columns(b)
    refined = is_refined(b)
    if refined:
        rhs = banded_saddle.dislocations(kappa, loads, settled)
        sol, last = refined_columns(b, rhs, b["lu"].solve(rhs))
        sol = sol[nf:]
    else:
        sol = b["lu"].contact_rows(kappa, loads, settled)
    R = -kappa * sol[:, :nl]
    R = 0.5 * (R + R.T)
    # R's entries are sums of terms of size kappa (the stiffness), so each
    # carries a rounding error of a few eps * kappa.  An entry that small is
    # zero: a dislocation that a rigid motion of the frame absorbs (a portal
    # on two pins lifted at one base) costs no force, and noise in its place
    # would turn "this link has no effect" into a random sign — which the
    # trace's collapse proof (a Farkas vector, M'y <= 0 column by column)
    # and the support states would read as data.
    exact = R.copy()
    if refined:
        # refined in extended precision, an entry is known to about its
        # column's size times eps, or the last correction where that is
        # larger — not to eps kappa: with a deck 1e12 times stiffer than
        # its columns, kappa eps (R_ROUNDING kappa = 101 kN/m) is above the
        # frame's sway stiffness (48 kN/m), which zeroing as noise left
        # M = 0 and a "proof" that no equilibrium exists where one does
        noise = np.maximum(R_ROUNDING * np.abs(R).max(axis=0, initial=0.0),
                           kappa * last[:nl])
        R[np.abs(R) <= np.maximum(noise[:, None], noise[None, :])] = 0.0
    else:
        R[np.abs(R) <= R_ROUNDING * kappa] = 0.0
    # the same for the loads' link forces: a link that a case does not
    # load (a pad under a frame whose bilateral supports carry the push)
    # had -2.7e-15 kN under 1 kN, and Lemke "proved" that it would pull.
    # Unrefined, against each case's own loads and the forces its
    # settlements make at the scale the solve sees them, κ|U|; refined, at
    # the column's own rounding as R is — κ|U| is the link rows' size in
    # the solve, not the forces a settlement makes: with a pin settled 1 cm
    # beside a bar whose κ is 4e16 kN/m, R_ROUNDING κ|U| = 25 kN zeroed
    # the whole column, the 4.13 kN load at a pad beyond the bar was lost,
    # and the beam, which has no equilibrium, was "ok" on that LCP
    RF = -kappa * sol[:, nl:]
    if refined:
        noise = np.maximum(R_ROUNDING * np.abs(RF).max(axis=0, initial=0.0), kappa * last[nl:])
    else:
        noise = R_ROUNDING * load_sizes(b)
    RF[np.abs(RF) <= noise] = 0.0
    return {"R": R, "RF": RF, "R_solve": exact}


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


def layout(b):
    """Per contact: the link positions of n and t (cached in b)."""
    if "layout" not in b:
        pos = {}
        for li, (ci, kind) in enumerate(b["info"]):
            pos.setdefault(ci, {})[kind] = li
        b["layout"] = pos
    return b["layout"]


def lcp_matrices(b):
    """(M, Q, q_gap, P, g, fric): w = M z + Q f + q_gap for the case factors
    f (Q has one column per case of b["cases"]); Δ = P z - g (P dense), from
    the link maps b["maps"] = (P, W, g, fric) each frame's build lays out.
    Computed once per assembly (cached in b); forms R."""
    if "lcp" in b:
        return b["lcp"]
    P, W, g, fric = b["maps"]
    R = b["R"]
    nl, nz = P.shape
    # W's three products as one (its rows' sums, column by column, are the
    # same): W R, W R_F and W R g
    WX = W @ np.column_stack((R, b["RF"], R @ g))
    # M = (W R) P: where each column of P has one entry (a plane frame's z
    # each moves one link) M's column is that entry times W R's column, as
    # the sparse product sums it (from +0); else the product
    rows = np.repeat(np.arange(nl), np.diff(P.indptr))
    if np.bincount(P.indices, minlength=nz).max(initial=1) == 1:
        link, entry = np.zeros(nz, int), np.zeros(nz)
        link[P.indices], entry[P.indices] = rows, P.data
        M = WX[:, link] * entry + 0.0
    else:
        M = np.asarray((P.T @ WX[:, :nl].T).T)
    if not fric:
        M = 0.5 * (M + M.T)  # = R_nn exactly; remove rounding asymmetry
    dense_P = np.zeros((nl, nz))
    dense_P[rows, P.indices] = P.data          # (P has no repeated entry)
    b["lcp"] = (M, WX[:, nl:-1], -WX[:, -1], dense_P, g, fric)
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
