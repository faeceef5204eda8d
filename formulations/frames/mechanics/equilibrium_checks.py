"""The checks every frame answer passes before it is called one, shared by
the plane and the space frame: equilibrium dof by dof on each dof's own
scale, the componentwise measure of complementarity, what rounding leaves
and is not counted, and how far the frame has moved (where
small-displacement theory stops holding)."""

from __future__ import annotations

import functools
import math

import numpy as np

from .contact_lcp import R_ROUNDING, link_force_sizes, link_forces, to_global


#: A normal force or slip below STATE_RTOL of its own componentwise scale is zero
#: when the support's state is named.
STATE_RTOL = 1e-9


#: The equilibrium check's limit is the requested accuracy (1e-9 at "high"), but
#: never below what rounding leaves in a right answer's per-dof residual (a few
#: thousand eps: the saddle solve's backward error on a long member chain).
EQUILIBRIUM_FLOOR = 4096 * np.finfo(float).eps


#: An answer in double that passes its contact certificate and its statics
#: checks by this factor (1e-12 at "high") is not polished in extended
#: precision (:mod:`.extended_refinement`): the polish is for answers whose
#: digits double precision cannot carry (a portal whose deck is 1e2 to 1e8
#: times stiffer than its legs has statics residuals of 1e-12 to 1e-6 in
#: double, 0 refined; a space member with end pieces 1e5 to 1e7 times
#: stiffer, 1.4e-9 to 1.2e-7), and it cost a third of a 200-span beam's
#: solve where it changed nothing that is checked.
CLEAR = 1e-3

#: Beyond a translation of SMALL_DISPLACEMENT x the frame's size, or a
#: rotation of SMALL_ROTATION rad, equilibrium written on the undeformed frame
#: is no longer the structure's (a 20-storey tower swayed 19.5 m, 0.28 of its
#: size, at its "collapse" load without a word): results say so and warn.
SMALL_DISPLACEMENT = 0.02


#: The rotation [rad] beside SMALL_DISPLACEMENT (see there).
SMALL_ROTATION = 0.05


class LargeDisplacementWarning(UserWarning):
    """A result's displacements are beyond small-displacement theory."""



def loose_forces(cert_error, sigma, xn, tol) -> bool:
    """Whether a contact certificate of ``cert_error`` leaves the normal
    forces ``xn`` that the supports carry (those above STATE_RTOL of their
    row's σ, the rule that names a support separated) less than a margin of
    CLEAR below tol of the largest, once each row's allowance cert_error·σ
    is read in force units: the certificate measures each row on its own σ
    (|M||z| + |q|, or the mechanical terms; normal rows first), which where
    part of a frame moves far is many times the forces.  Such an answer is
    refined on its states (:mod:`.extended_refinement`) as one that fails
    its checks by that margin is.  A trigger, not a bound: the forces come
    from z through the basic system, and on a nearly free part z's own
    error is larger still — Lemke's answer on a beam whose lifted end rises
    188 m about the few contacts still holding it (frictional_beam(35, 4,
    f = 0.1)), certified to 4.6e-14 with cert_error·σ 4.7e-10 of the
    largest force, had its forces 7e-7 of it off (the LCP's own forward
    error estimate: no digit, 2e27, z not isolated); refined, they are the
    active set's to the last digit."""
    carried = xn > STATE_RTOL * sigma[:xn.size]
    return bool(carried.any()) and \
        cert_error * float(sigma.max()) > CLEAR * tol * float(xn[carried].max())


def beyond_rounding(res, scale, largest=None) -> float:
    """max |res| / scale, not counting what rounding of the largest term of the
    same kind leaves (R_ROUNDING of it): a force that is zero in exact
    arithmetic comes out of the solve as a few eps times the largest force
    (a friction force of 1.6e-15 beside a reaction of 50), and judged against
    its own terms — all of them zero — it would be wrong by all of its size."""
    if res.size == 0:
        return 0.0
    floor = R_ROUNDING * (scale.max() if largest is None else largest)
    excess = np.maximum(res - floor, 0.0)
    # only the components beyond the floor (commonly none) are divided:
    # the others are 0 whatever their scale.  A NaN (in the residual, its
    # scale or the floor) is beyond it and counts infinite: NaN itself
    # would pass the callers' max(forces, moments) where it came second
    beyond = excess != 0.0
    if not beyond.any():
        return 0.0
    e, s = excess[beyond], scale[beyond]
    with np.errstate(divide="ignore", invalid="ignore"):
        worst = float(np.where(s > 0, e / s, np.inf).max())
    return worst if worst == worst else np.inf


@functools.lru_cache(maxsize=None)
def rotations(dofs: tuple) -> np.ndarray:
    """Which of a node's dofs (names, in order) are rotations: once per
    kind of frame, not per check (read only)."""
    mask = np.array([d.startswith("r") for d in dofs])
    mask.flags.writeable = False
    return mask


def how_far(frame, u, always=False, second_order=False, coords=None):
    """(largest translation / frame size, largest rotation, words): the
    words say where small-displacement theory stops holding (or, with
    ``always``, how far the frame has moved in any case); a
    ``second_order`` answer's words say what its theory leaves out.
    ``coords``: the nodes' coordinates where an assembly has them (else
    read off the frame)."""
    xy = np.array(list(frame.nodes.values())) if coords is None else coords
    d = xy.max(axis=0) - xy.min(axis=0)
    size = math.sqrt(d.dot(d)) or 1.0        # np.linalg.norm's sum, without its checks
    spin = rotations(frame.DOFS)                  # a node's rotations
    per_node = np.asarray(u).reshape(-1, len(frame.DOFS))
    trans = np.linalg.norm(per_node[:, ~spin], axis=1)
    k = int(np.argmax(trans))
    ratio, rot = float(trans[k]) / size, float(np.abs(per_node[:, spin]).max(initial=0.0))
    length = frame.units[1]
    moved = (f"node {list(frame.nodes)[k]} has moved {trans[k]:.3g} {length} "
             f"({ratio:.2g} of the frame's size, {size:.3g} {length}), rotations up to "
             f"{rot:.2g} rad")
    if ratio > SMALL_DISPLACEMENT or rot > SMALL_ROTATION:
        limits = f"(limits {SMALL_DISPLACEMENT:g} of the size, {SMALL_ROTATION:g} rad)"
        if second_order:
            return ratio, rot, (f"{moved}: beyond moderate rotations {limits}; this second-order "
                                "analysis writes equilibrium on the deformed frame to first order "
                                "in its rotations (P-Δ, P-δ): large rotations (a corotational "
                                "analysis) are not in it")
        return ratio, rot, (f"{moved}: beyond small-displacement theory {limits}, which this "
                            "analysis assumes — the deformed frame's equilibrium (second-order "
                            "effects) is not in it: solve(..., second_order=True) writes it")
    return ratio, rot, (moved if always else "")


def complementarity(z, w, zeta, sigma):
    """(|min(z/ζ, w/σ)| per component, σ)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        Z = np.where(zeta > 0, z / np.where(zeta > 0, zeta, 1.0), np.where(z > 0, np.inf, 0.0))
        Wr = np.where(sigma > 0, w / np.where(sigma > 0, sigma, 1.0),
                      np.where(w != 0, np.sign(w) * np.inf, 0.0))
    return np.abs(np.minimum(Z, Wr)), sigma


def equilibrium(frame, b, F, X, u, residual=None, abs_hx=None, abs_ku=None):
    """Equilibrium judged dof by dof, each on its own scale: the residual of
    K u = F + H X at every free dof against the sum of the absolute values
    of the terms that make it, |K||u| + |F| + |H||X| (a componentwise
    backward error, like the LCP certificate's; the reactions at fixed
    dofs are those rows' remainders, so they hold by definition).  The old
    check — the resultant against the largest load, limit 1e-8 — failed
    right answers on long beams (200 spans: 1.1-2.5e-8 where independent
    statics agree to 1e-9).  ``residual`` (K u - F - H X) and ``abs_hx``
    (|H||X|) where the caller has them already (the reactions are that
    residual at the fixed dofs; the resultant check sizes by |H||X| too);
    ``abs_ku`` (|K||u|) where the caller makes it for
    :func:`reported_balance` too."""
    free = b["free"]
    if residual is None:
        residual = b["K"] @ u - F - link_forces(b, X)
    if abs_hx is None:
        abs_hx = link_force_sizes(b, X)
    if abs_ku is None:
        abs_ku = b["abs_K"] @ np.abs(u)
    res = np.abs(residual)[free]
    scale = (abs_ku + np.abs(F) + abs_hx)[free]
    moment = rotations(frame.DOFS)[free % len(frame.DOFS)]
    return max(beyond_rounding(res[~moment], scale[~moment]),
               beyond_rounding(res[moment], scale[moment]))


def reported_balance(frame, b, F, u, X, reported, r_all, resultant_of, tol, abs_ku=None):
    """(ratio, words): the frame's equilibrium with its contact forces as
    the result reports them (``reported``: X with the forces of the
    contacts named separated set to zero), dof by dof: K u − F − H X_rep
    at every free dof against |K||u| + |F| + |H||X_rep| there, beyond the
    rounding of the largest of its kind (forces, moments); ``words`` name
    the worst dof and what is left there, where the ratio fails the
    answer (beyond ``tol``, at least EQUILIBRIUM_FLOOR).

    Why beside :func:`equilibrium`: that one judges the solve's own link
    forces X, which balance K u − F by construction.  A contact is named
    separated, and its force reported as zero, by the certificate's scale,
    read off the condensed LCP; where that LCP has lost a load (its load
    column's entries zeroed as rounding), the solve's X pulls at a
    "separated" pad with the whole load and every check on X passes — a
    beam's pads reported 24.875 kN against 20.745 of load, "equilibrium
    residual 0.0".  Only forces the report leaves out can break it, so it
    costs nothing where nothing is left out.  r_all: K u − F − H X;
    ``resultant_of(X_rep)``: the frame's global statics with those forces
    (the kind's ``resultant``), judged where a dof is out or the dropped
    forces sum to more than CLEAR × ``tol`` of all the link forces' sizes
    (less cannot move the resultant by tol; a tower's separated pads drop
    3e-13 of them) — a dof's scale holds |K||u|, which a stiff member's
    rigid motion makes large enough to hide a load.  ``abs_ku``: |K||u|
    where the caller has it (:func:`equilibrium`'s)."""
    dropped = X - reported
    if not dropped.any():
        return 0.0, ""
    free = b["free"]
    residual = (r_all + link_forces(b, dropped))[free]
    abs_ku = b["abs_K"] @ np.abs(u) if abs_ku is None else abs_ku
    scale = (abs_ku + np.abs(F) + link_force_sizes(b, reported))[free]
    moment = rotations(frame.DOFS)[free % len(frame.DOFS)]
    worst, words = 0.0, ""
    for kind in (~moment, moment):
        res, size = np.abs(residual[kind]), scale[kind]
        ratio = beyond_rounding(res, size)
        if ratio > worst:
            excess = np.maximum(res - R_ROUNDING * size.max(), 0.0)
            with np.errstate(divide="ignore", invalid="ignore"):
                k = int(np.argmax(np.where(excess > 0, np.where(size > 0, excess / size, np.inf),
                                           0.0)))
            dof = int(free[kind][k])
            n = len(frame.DOFS)
            node, name = b["names"][dof // n], frame.DOFS[dof % n]
            unit = frame.units[0] if name.startswith("u") else "·".join(frame.units)
            worst, words = ratio, (f"the reported contact forces leave {residual[kind][k]:.4g} "
                                   f"{unit} unbalanced at {node} ({name}; {ratio:.1e} of the "
                                   "forces there)")
    if worst > 0.0 or np.abs(dropped).sum() > CLEAR * max(tol, EQUILIBRIUM_FLOOR) * \
            np.abs(X).sum():
        whole = resultant_of(reported)
        if whole > worst:
            worst, words = whole, (f"the reported contact forces, reactions and loads are out of "
                                   f"balance by {whole:.1e} of their terms")
    return worst, (words if worst > max(tol, EQUILIBRIUM_FLOOR) else "")


def member_balance(frame, b, F, X, u, ends, factors):
    """Equilibrium of the member end actions as returned (``ends``, member
    axes, net of the fixed-end forces of member loads), dof by dof at the
    free dofs: Σ Tᵀ (ends + fixed-end forces) + springs − F − H X against
    the sizes of those forces (not |K||u|).

    Why beside :func:`equilibrium`: a member much stiffer than its
    neighbours moving rigidly has |k||u| far above its end forces, so the
    rounding of u times its k (ε|k||u|) passes the per-dof check's scale
    while its end forces computed in double are off by it — the tip piece
    of a cantilever 1e7 times stiffer than its root read its shear 4e-7
    off with every check passed.  Judged on the forces that meet at the
    dof, that error is seen, and the answer is refined."""
    k, T, dofs, Fe = b["local"]
    fixed_end = Fe @ factors
    Tt = T.transpose(0, 2, 1)
    back = (Tt @ (ends + fixed_end)[..., None])[..., 0]
    ug = to_global(b, u)
    total = np.bincount(dofs.ravel(), back.ravel(), ug.size) + b["springs"] * ug
    # each member's end actions sized by the member's largest (an end
    # moment that is zero carries the rounding of the other end's, and of
    # the shear times the length): its forces by max |force| + max |moment|
    # / L, its moments by max |moment| + L max |force|
    nd = dofs.shape[1] // 2
    spin = np.tile([d.startswith("r") for d in frame.DOFS], 2)
    xyz = np.asarray(b["coords"], float)
    L = np.sqrt(((xyz[dofs[:, nd] // nd] - xyz[dofs[:, 0] // nd]) ** 2).sum(axis=1))
    sized = np.abs(ends) + np.abs(fixed_end)
    f_max = sized[:, ~spin].max(axis=1, initial=0.0)
    m_max = sized[:, spin].max(axis=1, initial=0.0)
    size = np.where(spin, (m_max + L * f_max)[:, None], (f_max + m_max / L)[:, None])
    terms = (np.bincount(dofs.ravel(), (np.abs(Tt) @ size[..., None])[..., 0].ravel(), ug.size)
             + np.abs(b["springs"] * ug))
    if b["Tn"] is not None:
        total, terms = b["Tn"] @ total, abs(b["Tn"]) @ terms
    free = b["free"]
    res = np.abs(total - F - link_forces(b, X))[free]
    scale = (terms + np.abs(F) + link_force_sizes(b, X))[free]
    moment = rotations(frame.DOFS)[free % len(frame.DOFS)]
    return max(beyond_rounding(res[~moment], scale[~moment]),
               beyond_rounding(res[moment], scale[moment]))


def mechanical_certificate(b, z, X, u, force_terms):
    """(error, ζ, σ): the LCP certificate's componentwise measure,
    max_i |min(z_i/ζ_i, w_i/σ_i)| with w = W X, where the LCP's matrix is
    not formed (the sparse active set never forms the dense R).  The
    scales are what each quantity is made of, as the certificate's
    |M||z| + |q| are, read off the mechanics instead of M: a link force
    against the forces that meet at its node (contact_lcp.force_terms: the
    members' end forces, the springs', the loads), and a link
    displacement (an opening, a slip part) against |h|ᵀ|u| + |D X| + g.
    Equilibrium is checked on its own (:func:`equilibrium`, the frames'
    resultants).  The links' kinematics Δ = H'u + D X = P z - g are the
    answer's by construction (u solved for them), not judged here."""
    P, W, g, _ = b["maps"]
    # |H|ᵀ as the assembly's CSR: the same sums in the same order as the
    # transposed view's, without making the view (twice a solve)
    absHT = b["abs_HT"]
    forces = absHT @ force_terms
    lengths = absHT @ np.abs(u) + np.abs(b["flex"] * X) + np.abs(g)
    forces = forces + R_ROUNDING * forces.max(initial=0.0)
    lengths = lengths + R_ROUNDING * lengths.max(initial=0.0)
    zeta = b["abs_P"].T @ lengths
    w = W @ X
    e, sigma = complementarity(z, w, zeta, b["abs_W"] @ forces)
    # the LCP's scale of a link force also holds the force its own link
    # displacement makes, R_ll |Δ_l|, which the rounding of the solve
    # follows: a lifted stretch of a foundation beam had X_n = -4e-10
    # from rounding against node forces of 1e-9, where R_ll |Δ| = 2e4 as
    # in the LCP's |R||Δ|.  R_ll is read off the basic system's LU, one
    # solve per moving link whose component is above rounding without it
    # (a bound such as the node's stiffness h'|K|h was 1e9 times too
    # large beside a 1 cm stub, and passed a tip lifted 1 m); leaving it
    # out elsewhere can only overstate the error
    delta = P @ z - g
    # the links that the rows above rounding hold: |W|ᵀ times the rows'
    # indicator (|W|'s entries are positive; a sparse row selection cost 80
    # µs, a fifth of a 200-span beam's certificate)
    touched = (b["abs_W"].T @ (e > 64 * np.finfo(float).eps).astype(float)) > 0
    moving = np.flatnonzero(touched & (delta != 0))
    if moving.size:
        nf, kappa = b["nf"], b["kappa"]
        unit = np.zeros((nf + len(delta), moving.size))
        unit[nf + moving, np.arange(moving.size)] = kappa
        R_ll = np.abs(kappa * b["lu"].solve(unit)[nf + moving, np.arange(moving.size)])
        forces[moving] += R_ll * np.abs(delta[moving])
        e, sigma = complementarity(z, w, zeta, b["abs_W"] @ forces)
    return (float(e.max(initial=0.0)), zeta, sigma)
