"""When a frame has no equilibrium: the proof and the words for how it fails.
A failed solve's Farkas vector is read through the frame's
``kind.collapse_words``; where the contact matrix is singular only up to
rounding, one LP over the null space of the free stiffness finds a rigid
motion in which the loads do positive work while every contact opens or
slides within its friction cone (:func:`rigid_motion`).  Shared by the plane
and the space frame."""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import NoSolutionError, SolverFailedError

from . import contact_lcp, refinement
from .loads import describe
from .member_forces import elastic_end_actions, strain_free_motions


def proved(sol) -> bool:
    """Whether a failed solve came with a proof that no equilibrium exists."""
    proof = sol.stats.get("proof")
    # Lemke's stats["farkas"] may hold a vector that holds to rounding only
    # (rounding can leave it just short): a proof is what was checked exactly
    return bool(sol.stats.get("proved_infeasible")) or (
        proof is not None and getattr(proof, "kind", None) == "infeasible")


def raise_no_equilibrium(frame, sol, fric, b, combo, hint=False):
    """Raise with what was proved (a Farkas vector: how the frame fails) or
    with what was tried (``hint``: say that "auto" also follows the load
    path)."""
    proof = sol.stats.get("proof")
    y = sol.stats.get("farkas") if sol.stats.get("proved_infeasible") else None
    if y is None and proof is not None and proof.kind == "infeasible":
        y = proof.vector["z"]
    what = describe(combo)
    if y is not None and refinement.is_refined(b):
        # only the rigid motion, checked on K itself, proves anything here
        raise_rigid_motion(frame, b, combo, f"{sol.method}: {sol.message}")
        raise SolverFailedError(
            f"frame under {what}: {sol.method} found no contact state, and "
            f"{refinement.no_farkas_proof(b)}; nothing was proved either way")
    if y is not None:
        words = frame.kind.collapse_words(frame, {"farkas": np.asarray(y, float)}, fric,
                                          carrying=None)
        raise NoSolutionError(
            f"frame under {what}: no equilibrium exists — {words} (proved by a Farkas "
            f"vector checked from the data: y >= 0, M'y <= 0, q'y < 0)")
    raise_rigid_motion(frame, b, combo, f"{sol.method}: {sol.message}")
    if sol.stats.get("verge"):
        raise SolverFailedError(f"frame under {what}: {sol.stats['verge']}")
    raise SolverFailedError(
        f"frame under {what}: {sol.method} found no contact state ({sol.message}); nothing "
        "was proved either way" + ("; method='auto' also follows the load path to this "
                                   "load (the trace's route)" if hint else
                                   "; following the load path to it (the trace) found no "
                                   "certified equilibrium either"))


def rigid_motion(frame, b, combo):
    """A rigid motion φ of the frame with every contact released (a null
    vector of the free stiffness, springs and bilateral supports
    included) that only opens or slides the contacts within Coulomb's
    cone (a_c >= f |s_c|) and in which the loads do positive work: then
    no equilibrium exists (virtual work: F'φ = -Σ X·(H'φ) <= 0 for any
    admissible contact forces).  Found by one LP over the null space and
    checked in floating point to rounding; returns (a, s) or None.

    This is what proves "no equilibrium" when the contact matrix is
    singular only up to rounding (R has the rigid motion in its null
    space exactly, its computed copy only nearly), where the LCP's exact
    Farkas check cannot pass."""
    from scipy.optimize import linprog

    free = b["free"]
    if free.size > 3000:
        return None
    if b.get("axial") is None:
        # first order: the motions that strain no member, from the members'
        # geometry (K's eigenvectors at a contrast of 1e7 mixed a soft
        # member's stretch into them at 3e-7: every motion "strained", and
        # a beam's part beyond a stiff bar tipping went unproved)
        null = strain_free_motions(b["local"], b["coords"], b["springs"], b["Tn"], free)
    else:
        Kf = b["K"][free][:, free].toarray()
        d = np.sqrt(np.abs(np.diag(Kf)))
        d[d == 0] = 1.0
        lam, V = np.linalg.eigh(Kf / d[:, None] / d[None, :])
        null = V[:, lam <= 1e-10 * max(lam.max(initial=0.0), 1e-300)] / d[:, None]
    if null.shape[1] == 0:
        return None
    F, _ = contact_lcp.load_vector(b, combo)
    Ff = F[free]
    normals, tangents, f = frame.kind.release_directions(frame, b)
    Ha = normals[free].T @ null
    Hs = [t[free].T @ null for t in tangents]        # one (nc x null) per tangent
    work = Ff @ null
    if not np.any(work):
        return None
    # a_c >= f |s_c|: exact with one tangent (a >= ±f s); with two, by
    # a >= f (±s1 ±s2), which implies it (|s| <= |s1| + |s2|) — a proof
    # found under the stronger condition is still one
    signs = np.array(np.meshgrid(*[[1.0, -1.0]] * len(Hs))).reshape(len(Hs), -1).T
    A_ub = np.vstack([-(Ha + f[:, None] * sum(sg * h for sg, h in zip(row, Hs)))
                      for row in signs])
    res = linprog(np.zeros(null.shape[1]), A_ub=A_ub, b_ub=np.zeros(A_ub.shape[0]),
                  A_eq=work[None, :], b_eq=[1.0], bounds=[(None, None)] * null.shape[1],
                  method="highs")
    if res.status != 0:
        return None
    phi = null @ res.x
    a = Ha @ res.x
    sl = np.stack([h @ res.x for h in Hs], axis=1) if Hs else np.zeros((a.size, 0))
    size = np.abs(phi).max()
    w_scale = np.abs(Ff) @ np.abs(phi)
    tol = 1e-9 * size
    if not (Ff @ phi > 1e-6 * w_scale and np.all(a - f * np.linalg.norm(sl, axis=1) >= -tol)):
        return None
    if strains(b, free, phi):
        return None
    a = np.where(np.abs(a) <= tol, 0.0, a)
    sl = np.where(np.abs(sl) <= tol, 0.0, sl)
    return a, sl


#: a member that moves less than this fraction of the largest motion is
#: judged on that fraction (:func:`strains`): the null space is known to
#: about ε of its largest entry, so a member at rest moves by noise
MOTION_ROUNDING = 1e-6


def strains(b, free, phi) -> bool:
    """Whether the motion ``phi`` (on the free dofs) strains a member or a
    spring beyond rounding of that one's own stiffness.  The null space
    above is read off K scaled by its diagonal, where a soft member's
    bending next to a stiff one has an eigenvalue of about the contrast
    squared (a beam 1.5e6 times stiffer than its neighbour: 3e-13, under
    1e-10): that member's bending read as a rigid motion, and a beam on a
    pin and pads, whose pads carry it by statics, "proved" to have no
    equilibrium.  Member by member, rounding is ε of its own k times its
    own motion — or MOTION_ROUNDING of the whole motion's, where the
    member hardly moves: a member at rest has ends of rounding noise
    (1e-15 of φ), which against that noise alone read as a strain and
    refused a beam's tipping part its proof."""
    u = np.zeros(b["K"].shape[0])
    u[free] = phi
    ug = u if b["Tn"] is None else b["Tn"].T @ u
    k, _, dofs, _ = b["local"]
    if len(k):
        ends = np.abs(np.asarray(elastic_end_actions(b, ug[:, None])[..., 0], float))
        moved = np.maximum(np.abs(ug[dofs]).max(axis=1), MOTION_ROUNDING * np.abs(ug).max())
        own = np.abs(k).reshape(len(k), -1).max(axis=1) * moved
        if np.any(ends.max(axis=1) > 1e-6 * own):
            return True
    springs = np.asarray(b["springs"], float)
    return bool(np.any(np.abs(springs * ug) > 1e-6 * springs * np.abs(ug).max(initial=0.0)))


def raise_rigid_motion(frame, b, combo, before: str):
    motion = rigid_motion(frame, b, combo)
    if motion is None:
        return
    raise NoSolutionError(
        f"frame under {describe(combo)}: no equilibrium exists — {motion_words(frame, *motion, None)} "
        f"(a motion of the frame with its contacts released that strains no member — rigid, "
        f"or a mechanism of its hinges — in which the loads do "
        f"positive work while every contact opens or slides within its friction cone; "
        f"found by LP, checked to rounding; {before})")


def motion_words(frame, A, T, carrying) -> str:
    """Words for a rigid motion with normal opening A_c >= f |T_c| and
    tangential motion T_c at each contact (see _collapse_words)."""
    keys = frame.kind.support_keys(frame)
    nc = len(frame.contacts)
    T = np.asarray(T, float).reshape(nc, -1)
    size = np.linalg.norm(T, axis=1)
    big = max(A.max(initial=0.0), size.max(initial=0.0))
    lift, slide, stay, inner, slid = [], [], [], [], []
    for ci in range(nc):
        f = frame.contacts[ci].friction
        if A[ci] <= 1e-9 * big and size[ci] <= 1e-9 * big:
            # a pair (other=) that stays moves with both its parts: no pivot,
            # and no part left behind
            (stay if frame.contacts[ci].other is None else inner).append(keys[ci])
        elif A[ci] > f * size[ci] * (1 + 1e-6) + 1e-9 * big:
            lift.append(keys[ci])
        else:
            slide.append(f"{keys[ci]} ({frame.kind.slide_words(frame, ci, T[ci])})")
            slid.append(ci)
    if slide and not lift:
        if all(frame.contacts[ci].other is not None for ci in slid):
            # only pairs slide: one part of the frame on another, the
            # supports that stay hold the part that does not move
            return "a part of the frame slides on another: friction exhausted at " + \
                ", ".join(slide)
        # a carrying support that stays is a pivot (a table on a floor
        # turning about one leg)
        pivots = [k for k in stay if carrying is not None and k in carrying]
        if pivots:
            return (f"it turns about {', '.join(pivots)}: friction exhausted at "
                    + ", ".join(slide))
        whole = carrying is None or all(any(s.startswith(k + " ") for s in slide)
                                        for k in carrying if k not in inner)
        if not moves_rigidly(frame, A, T, slide_or_stay=[ci for ci in range(nc)
                                                         if keys[ci] not in lift]):
            # a three-hinged frame on pads spreads: its feet slide apart
            return ("it gives way as a mechanism, its parts moving apart (not as a rigid "
                    "body): friction exhausted at " + ", ".join(slide))
        return (("the frame slides away as a rigid body: " if whole else "it slides: ")
                + "friction exhausted at " + ", ".join(slide))
    if lift and not slide:
        if stay:
            return f"it tips over about {', '.join(stay)}: {', '.join(lift)} lift off"
        return "it lifts off: " + ", ".join(lift) + " would have to pull"
    return ("it lifts off at " + ", ".join(lift) + " and slides at " + ", ".join(slide))


def moves_rigidly(frame, A, T, slide_or_stay) -> bool:
    """Whether the tangential motions T of the contacts ``slide_or_stay``
    (those that do not lift off), and no motion at all where one stays,
    are those of one rigid motion of the whole frame: v(x) = t + θ × x,
    whose component along a direction d at x is d·t + θ·(x × d) (in the
    plane d_x t_x + d_y t_y + θ (x d_y − y d_x)) — least squares over the
    3 (6) parameters, rigid where the misfit is rounding.  A pair
    (``other=``) moves with the whole frame only where it does not slip.
    The Farkas vector's motion is the frame's only up to its members'
    deformation: two feet of a three-hinged frame sliding apart are not
    a rigid body sliding away."""
    nc = len(frame.contacts)
    T = np.asarray(T, float).reshape(nc, -1)
    rows, rhs = [], []
    for ci in slide_or_stay:
        c = frame.contacts[ci]
        x = np.asarray(frame.nodes[c.node], float)
        n = np.asarray(c.normal, float)
        dirs = ([np.asarray(c.t1, float), np.asarray(c.t2, float)] if x.size == 3
                else [np.array([n[1], -n[0]])])
        still = A[ci] == 0.0 and not np.any(T[ci])
        for k, d in enumerate(dirs[:T.shape[1]] + ([n] if still else [])):
            if c.other is not None:
                row = np.zeros(3 * x.size - 3)
            elif x.size == 3:
                row = np.concatenate([d, np.cross(x, d)])
            else:
                row = np.array([d[0], d[1], x[0] * d[1] - x[1] * d[0]])
            rows.append(row)
            rhs.append(T[ci, k] if k < T.shape[1] and k < len(dirs) else 0.0)
    rhs = np.array(rhs, float)
    scale = float(np.abs(rhs).max(initial=0.0))
    if not rows or scale == 0.0:
        return True
    G = np.array(rows)
    c, *_ = np.linalg.lstsq(G, rhs, rcond=None)
    return bool(np.abs(G @ c - rhs).max() <= 1e-6 * scale)
