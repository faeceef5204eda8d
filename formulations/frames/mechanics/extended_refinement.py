"""A frame's answer refined on its contact states in extended precision.

Why.  A frame whose members differ in stiffness by 1e8 (a stiff deck on
slender legs, a rigid zone modelled as a very stiff member) has its
displacements u of the deck's size δ but stiffness terms |K| 1e8 times the
legs'.  Any answer held in double precision carries ε|u| in each
displacement, and the forces it implies, K u, carry ε|K||u| — on a table of
2e13 kN/m deck members moved 3e-4 m by its legs, 1e-6 kN on a 12 kN pad
force: six digits, not the nine "high" promises.  The LCP's pivoting is
exact for its matrix, but that matrix (R, from the basic system's LU) and
the recovery's saddle solve are both rounded at that level; the global
statics check sees the difference (the forces of the pads no longer sum to
the loads) and rightly refuses the answer.

What.  Once the contact states are known (which links are open, which
facets slip: the LCP's basis), the answer is the solution of one linear
system — equilibrium at the free dofs, the links' kinematics, and the
reserve of every moving unknown at zero:

    K_ff u_f − H_f X        = F_f − K_fa u_a          [force]
    H_fᵀ u_f + D X − P_B z_B = −g − H_aᵀ u_a           [length]
    (W X)_B                  = 0                       [force]

(z_B the unknowns off zero, Δ = P z − g the links' displacements, w = W X
the reserves; every other z stays 0).  It is solved by iterative refinement:
the residual in extended precision (``numpy.longdouble``: 64-bit mantissa on
x86, 113 on aarch64), the member forces computed member by member as the
element stiffness k times the member's own end displacements T u_e — so a
rigid motion of a stiff member cancels within the member, exactly in the
translations, instead of leaving ε|K||u| behind in the assembled K — and the
correction from one sparse LU in double.  The refined u and X carry the
rounding of the extended format (1e-19 |K||u|), which puts the deck's
forces back to their nine digits.

The refinement is an answer's polish, not a solver: it keeps the states it
is given, and the caller keeps it only if it passes the same checks (the
contact certificate and equilibrium) at least as well as the answer it
came from.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .contact_lcp import regular_lu
from .equilibrium_checks import STATE_RTOL
from .member_forces import EXTENDED, stiffness_times

#: refinement steps at most (each one gains about -log10(ε cond) digits)
STEPS = 5

#: a resting unknown whose reserve the refinement takes below -PIVOT_RTOL of
#: its scale moves (far above the extended format's rounding, far below
#: the certificate's tolerance)
PIVOT_RTOL = 1e-12

#: an answer is polished only where its contact certificate holds to this
#: already: the polish refines a right answer's digits, it does not turn a
#: wrong point (a tip lifted 1 m, with a certificate of 1.0) into another
POLISHABLE = 1e-6


def moving_unknowns(z, w, zeta, sigma) -> np.ndarray:
    """The LCP's basis read off a point: z_i is off zero where it is larger
    on its own scale than its reserve w_i on its own (the certificate's
    scales ζ, σ)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        zr = np.where(zeta > 0, z / np.where(zeta > 0, zeta, 1.0), np.where(z > 0, np.inf, 0.0))
        wr = np.where(sigma > 0, np.abs(w) / np.where(sigma > 0, sigma, 1.0), 0.0)
    return (z > 0) & (zr >= wr)


def refine(b, z, F, ua, basis, u, X):
    """(z, u, X) refined on ``basis`` (a mask over z: the unknowns off zero)
    from the answer (z, u, X) in double; u, F and ua over all dofs (system
    axes).  None where the states' system is singular (a degenerate basis:
    the answer is kept as it was)."""
    P, W, g, _ = b["maps"]
    P, W = sp.csr_matrix(P), sp.csr_matrix(W)
    nf, free, kappa = b["nf"], b["free"], b["kappa"]
    H = sp.csr_matrix(b["H"])
    B = np.flatnonzero(basis)
    PB, WB = P[:, B], W[B]
    nl = H.shape[1]
    A = sp.bmat([[b["S"], sp.vstack([sp.csr_matrix((nf, B.size)), -kappa * PB])],
                 [sp.hstack([sp.csr_matrix((B.size, nf)), kappa * WB]), None]],
                format="csc")
    if A.shape[0] > nf + nl:
        # singular where the states do not fix the answer; judged on the
        # scaled pivots, as the basic system is (elastic pads under a deck
        # 1e8 times stiffer than the legs: unscaled pivots spanned 8e-20)
        lu = regular_lu(A)
        if lu is None:
            return None
    else:
        lu = b["lu"]
    E = EXTENDED
    Hl, PBl, WBl = H.astype(E), PB.astype(E), WB.astype(E)
    Fl, gl = np.asarray(F, E), np.asarray(g, E)
    flex = np.asarray(b["flex"], E)
    u = np.asarray(u, E).copy()
    u[b["fixed_idx"]] = np.asarray(ua, E)[b["fixed_idx"]]
    X = np.asarray(X, E).copy()
    zB = np.asarray(z, E)[B].copy()
    z0 = Pz = None
    for _ in range(STEPS):
        Pz = PBl @ zB
        r1 = (Fl + Hl @ X - stiffness_times(b, u))[free]
        r2 = (Pz - gl) - (Hl.T @ u + flex * X)
        r3 = -(WBl @ X)
        rhs = np.r_[r1, kappa * r2, -r3].astype(float)
        d = lu.solve(rhs)
        if not np.all(np.isfinite(d)):
            return None
        u[free] += d[:nf]
        X -= kappa * np.asarray(d[nf:nf + nl], E)
        zB += np.asarray(d[nf + nl:], E)
        size = max(float(np.abs(u).max(initial=0.0)), 1e-300)
        if float(np.abs(d[:nf]).max(initial=0.0)) <= 1e-18 * size and z0 is not None:
            break
        z0 = True
    zz = np.zeros(len(z))
    zz[B] = np.asarray(zB, float)
    return zz, u, X


def polished(b, z, F, ua, u, X, w, zeta, sigma, error):
    """(z, u, X) of the answer (z, u, X) refined on its own states (``w``
    its reserves, ζ and σ the certificate's scales, ``error`` its contact
    certificate), u and X in extended precision; None where it is not
    refined: its certificate above POLISHABLE, its states' system
    singular, or an unknown the refinement drives below zero beyond
    rounding (then the states were not the answer's)."""
    if not error <= POLISHABLE:
        return None
    basis = moving_unknowns(z, w, zeta, sigma)
    W = sp.csr_matrix(b["maps"][1])
    # at a breakpoint of the load path an unknown is at zero on both sides
    # (a slip just starting: z and its reserve both ~0), and the answer's
    # own rounding decides on which side it was put: the refinement may then
    # drive a moving unknown a rounding below zero (it is not moving: out of
    # the basis) or a resting one's reserve below zero (it moves: into the
    # basis) — a few exact pivots at the degenerate vertex
    dropped = 0
    seen = set()
    for _ in range(6):
        seen.add(basis.tobytes())
        refined = refine(b, z, F, ua, basis, u, X)
        if refined is None:
            # singular where an unknown Lemke left at rounding level closes a
            # mechanism: a six-legged table pushed to 2e-6 below the load at
            # which it slides as a rigid body had its last sticking pad's
            # slip at 1e-4 of the others' in the basis, and all six slipping
            # leave a rigid motion of the deck free — the polish failed and
            # the answer kept its double-precision forces ("CHECK FAILED").
            # That unknown, the smallest on its own scale, is taken out of
            # the basis once; the checks below put it back if its reserve
            # says it moves
            if dropped or not basis.any():
                return None
            with np.errstate(divide="ignore", invalid="ignore"):
                size = np.where(basis, z / np.where(zeta > 0, zeta, 1.0), np.inf)
            basis = basis.copy()
            basis[int(np.argmin(size))] = False
            dropped += 1
            continue
        below = basis & (refined[0] < 0)
        short = ~basis & (np.asarray(W @ np.asarray(refined[2], float)) < -PIVOT_RTOL * sigma)
        if not below.any() and not short.any():
            break
        turned = lifted_turns(b, basis, refined[0], below)
        basis = turned if turned is not None else (basis & ~below) | short
        if basis.tobytes() in seen:
            # a basis met before: the pivots go round (a lifted contact
            # whose slip is zero to 1e-37 turns from one facet to the other
            # and back, 6 refinements on a 1000-span beam for one answer);
            # its refinement is the one just made
            break
    if np.any(refined[0] < -STATE_RTOL * zeta):
        return None
    return (np.maximum(refined[0], 0.0), *refined[1:])


def lifted_turns(b, basis, z, below):
    """``basis`` with the slips of each lifted contact whose slip unknown
    went ``below`` zero re-read as the facets whose directions bracket the
    slip z gives it (adjacent ones on a polygon, the one of its sign on a
    line); None where no lifted contact's slip went below zero.

    Why.  A lifted contact (its normal unknown moving) carries nothing, so
    every facet's reserve is zero and its foot may move in any direction:
    which two facets the slip is written with is decided by its direction
    alone.  Lemke's answer puts a slip near a facet's direction on either
    side by rounding (a six-legged table on soft pads tipping over, its
    lifted feet's slips 3e-9 on one facet), the refinement then drives that
    one below zero, and dropping it left the slip a direction it cannot
    take: the polish failed and the answer kept its double-precision forces
    (global statics off by 7e-4, "CHECK FAILED" on a right answer).  No
    reserve tells which facet to take instead (they are all zero), the
    direction does."""
    P, owner, kind, normal_of = unknown_owners(b)
    out, changed = basis.copy(), False
    for c in sorted({owner[j] for j in np.flatnonzero(below) if kind[j] == "t"}):
        if c not in normal_of or not basis[normal_of[c]]:
            continue                      # not lifted: the reserves decide
        facets = np.flatnonzero((owner == c) & (kind == "t")).tolist()
        links = sorted({int(r) for j in facets
                        for r in P.indices[P.indptr[j]:P.indptr[j + 1]]})
        D = np.array([[P[r, j] for r in links] for j in facets])    # facets x tangents
        slip = D.T @ np.asarray(z, float)[facets]
        pair = bracketing(D, slip)
        if pair is None:
            continue
        out[facets] = False
        out[[facets[k] for k in pair]] = True
        changed = True
    return out if changed else None


def unknown_owners(b):
    """(P as CSC, the contact of each unknown of z, its kind "n" or "t",
    {contact: its normal unknown}), read off the link map P once per
    assembly (cached in b: a Python loop over 4000 unknowns)."""
    if "unknown_owners" not in b:
        P = sp.csc_matrix(b["maps"][0])
        info = b["info"]
        link_owner = np.array([ci for ci, _ in info], int)
        link_normal = np.array([k == "n" for _, k in info], bool)
        counts = np.diff(P.indptr)
        has = counts > 0
        owner = np.full(P.shape[1], -1)
        owner[has] = link_owner[P.indices[P.indptr[:-1][has]]]
        # "n" where every link of the unknown is a normal one
        tangential = np.zeros(P.shape[1], int)
        np.add.at(tangential, np.repeat(np.arange(P.shape[1]), counts),
                  ~link_normal[P.indices])
        kind = np.where((counts > 0) & (tangential == 0), "n", "t")
        normal_of = {int(owner[j]): j for j in np.flatnonzero(kind == "n")}
        b["unknown_owners"] = (P, owner, kind, normal_of)
    return b["unknown_owners"]


def bracketing(D, s):
    """Indices of the rows of D (facet directions) whose non-negative
    combination is s: the adjacent pair around s's angle in a plane, the
    row of s's sign on a line; None where s is zero."""
    if not np.any(s):
        return None
    if D.shape[1] == 1:
        return [int(np.argmax(D[:, 0] * np.sign(s[0])))]
    ang = np.arctan2(D[:, 1], D[:, 0])
    order = np.argsort(ang)
    target = np.arctan2(s[1], s[0])
    for a, b_ in zip(order, np.roll(order, -1)):
        lo, span = ang[a], (ang[b_] - ang[a]) % (2 * np.pi)
        if (target - lo) % (2 * np.pi) <= span:
            return [int(a), int(b_)]
    return None
