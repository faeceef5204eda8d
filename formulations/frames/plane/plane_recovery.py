"""From the contact LCP's answer z to a plane frame's result: displacements,
member end actions, reactions, each support's state (decided on the
component's own scale), the global statics check; and the words for how a
plane frame fails (a Farkas vector read as lifting, sliding and tipping).
These are the plane frame's hooks of the shared analysis
(:class:`~..mechanics.frame_kind.FrameKind`)."""

from __future__ import annotations

import numpy as np

from qpcontact.judge.lcp_certificate import componentwise_error

from ..mechanics import contact_lcp, extended_refinement, second_order
from ..mechanics.equilibrium_checks import (CLEAR, EQUILIBRIUM_FLOOR, STATE_RTOL, loose_forces,
                                            beyond_rounding, equilibrium, how_far,
                                            mechanical_certificate, member_balance,
                                            reported_balance)
from ..mechanics.loads import CONSTANT, VARIABLE, support_keys
from ..mechanics.member_forces import refined_actions
from ..mechanics.no_equilibrium import motion_words
from ..mechanics.plane_element import DOFS
from . import plane_assembly
from .member_diagrams import varying_couples
from .plane_results import FrameResult, SupportResult


def result_from_z(frame, z, combo, route, b=None, lcp=None, tol=1e-9) -> FrameResult:
    """The frame's result for the LCP point z, checked: the contact
    certificate (the LCP's when its matrix is at hand, else the same
    componentwise measure on the contact quantities' mechanical scales:
    :func:`..mechanics.equilibrium_checks.mechanical_certificate`) and
    equilibrium; an answer that does not pass those by a margin of CLEAR
    in double has its digits refined on its states in extended precision
    (:mod:`..mechanics.extended_refinement`) and is judged again."""
    b = b or frame.build()
    if not isinstance(combo, dict):   # a number p: the Osipova–Popov–Lovtsov split
        combo = {CONSTANT: 1.0, VARIABLE: float(combo)}
    P, W, g, fric = b["maps"]
    z = np.maximum(np.asarray(z, float), 0.0)
    F, ua = contact_lcp.load_vector(b, combo)  # ua: settlements (zero at free dofs)
    delta = P @ z - g                      # link displacements incl. contact flexibility
    nf, free = b["nf"], b["free"]
    rhs = np.concatenate((contact_lcp.free_loads(b, F, ua),
                          b["kappa"] * (delta - contact_lcp.settled_links(b, ua))))
    sol = b["lu"].solve(rhs)
    u = ua.copy()
    u[free] = sol[:nf]
    # The contact forces from the same solve as u, not R Δ + R_F: R has its
    # rounding-level entries dropped (contact_lcp.contact_stiffness), which times the large
    # openings of a long lifted stretch left forces 1e-9 off and out of
    # equilibrium with u (a 200-span beam); the solve's own
    # multipliers satisfy K u = F + H X to rounding.
    X = -b["kappa"] * sol[nf:]
    if lcp is None and "R" in b:
        M, Q, q_gap, *_ = contact_lcp.lcp_matrices(b)
        lcp = contact_lcp.combination_lcp(M, Q, q_gap, b, combo)
    combo_factors = contact_lcp.factors(b, combo)

    def checked(z, u, X, mechanical=lcp is None, ends=None):
        """(certificate error, ζ, σ, member ends, force terms) of an answer;
        ``ends`` where given (an answer refined in extended precision: in
        double a stiff member's carry ε|k||u|), else from u in double"""
        if ends is None:
            ends = contact_lcp.member_end_actions(b, contact_lcp.to_global(b, u), combo_factors)
        ft = contact_lcp.force_terms(b, u, F, ends)
        if mechanical:
            return (*mechanical_certificate(b, z, X, u, ft), ends, ft)
        # the certificate's error and scales alone: its forward-error estimate
        # (a basis inverted per probe) was a quarter of a tower's recovery
        return (*componentwise_error(lcp, z), ends, ft)

    cert_error, zeta, sigma, ends, ft = checked(z, u, X)
    # reactions at the fixed dofs: K u - F - H X on them (member loads
    # included), reported in global axes (a node's axes may be turned)
    HX = contact_lcp.link_forces(b, X)
    r_all = b["K"] @ u - F - HX

    ca = plane_assembly.contact_arrays(frame, b)
    has_t = ca["t_link"] >= 0

    def statics(u, X, r_all, ends, ft, sigma, HX=None):
        """(the equilibrium residual, words where the reported forces are
        out): dof by dof, the global statics, the balance with the contact
        forces as they will be reported (a separated contact's zero:
        :func:`..mechanics.equilibrium_checks.reported_balance`), and for
        a linear frame the balance of the member end actions returned; |H||X|
        made once for both, and where ``HX`` is given (r_all is then K u - F
        - H X in double, the per-dof residual) that residual"""
        abs_hx = contact_lcp.link_force_sizes(b, X)
        abs_ku = b["abs_K"] @ np.abs(u)
        eq = max(equilibrium(frame, b, F, X, u, residual=None if HX is None else r_all,
                             abs_hx=abs_hx, abs_ku=abs_ku),
                 resultant(frame, b, F, X, r_all, u, ft, HX=HX, abs_hx=abs_hx))
        if not frame.contacts:
            # (a contact frame's answers are not judged on it yet: its own
            # gate and cost are the contact routes')
            return max(eq, member_balance(frame, b, F, X, u, ends, combo_factors)), ""
        reported = X.copy()
        separated = X[ca["n_link"]] <= STATE_RTOL * sigma[:nc]     # the states' rule below
        reported[ca["n_link"][separated]] = 0.0
        reported[ca["t_link"][separated & has_t]] = 0.0
        off, where = reported_balance(frame, b, F, u, X, reported, r_all,
                                      lambda rep: resultant(frame, b, F, rep, r_all, u, ft), tol,
                                      abs_ku)
        return max(eq, off), where

    nc = len(frame.contacts)
    eq, where = statics(u, X, r_all, ends, ft, sigma, HX)
    if not (cert_error <= CLEAR * tol and eq <= CLEAR * max(tol, EQUILIBRIUM_FLOOR)) \
            or loose_forces(cert_error, sigma, X[ca["n_link"]], tol):
        # the answer refined on its states in extended precision, kept where
        # it checks at least as well (a stiff member's forces:
        # mechanics/extended_refinement) — where the answer in double does
        # not pass its checks by a margin of CLEAR already
        w = W @ X if lcp is None else lcp.M @ z + lcp.q
        refined = extended_refinement.polished(b, z, F, ua, u, X, w, zeta, sigma, cert_error)
        if refined is not None:
            z2, u2, X2 = refined[0], *(np.asarray(v, float) for v in refined[1:])
            # judged on the mechanics: the LCP's matrix carries the rounding of
            # the basic system's solve that the refinement has removed
            Ku, ends2 = refined_actions(b, refined[1], combo_factors)
            again = checked(z2, u2, X2, mechanical=True, ends=ends2)
            if again[0] <= max(cert_error, tol):
                z, u, X = z2, u2, X2
                cert_error, zeta, sigma, ends, ft = again
                delta = P @ z - g
                r_all = np.asarray(Ku - np.asarray(F, Ku.dtype) - b["H"].astype(Ku.dtype)
                                   @ np.asarray(refined[2], Ku.dtype), float)
                eq, where = statics(u, X, r_all, ends, ft, sigma)
    reactions = {}
    if frame.fixed:             # (a frame on contacts alone has no reaction to report)
        r_glob = contact_lcp.to_global(b, np.where(b["fixed"], r_all, 0.0))
        reactions = {node: tuple(float(v) for v in r_glob[b["idx"][node]:b["idx"][node] + 3])
                     for node in b["names"] if node in frame.fixed}
    u = contact_lcp.to_global(b, u)
    xn = X[ca["n_link"]]
    xt = np.where(has_t, X[ca["t_link"]], 0.0)
    if has_t.all():             # every contact's slip is its tangential link's
        slip = delta[ca["t_link"]]
    else:
        # frictionless: no tangential link, the node slides freely (t·relative motion)
        u2 = u.reshape(-1, 3)[:, :2]
        rel = u2[ca["node"]] - np.where(ca["other"][:, None] >= 0, u2[ca["other"]], 0.0)
        tangent = np.column_stack((ca["normal"][:, 1], -ca["normal"][:, 0]))
        slip = np.where(has_t, delta[ca["t_link"]], np.einsum("ij,ij->i", tangent, rel))
    # each state decided on the component's own scale (the certificate's):
    # X_n against the terms it is made of, a slip part against its own size
    sl = nc + 2 * np.arange(int(has_t.sum()))      # Z⁺ of each frictional contact
    moving = np.zeros(nc, bool)
    moving[has_t] = (np.maximum(z[sl], z[sl + 1])
                     > STATE_RTOL * np.maximum(zeta[sl], zeta[sl + 1]))
    separated = xn <= STATE_RTOL * sigma[:nc]
    states = np.where(separated, "separated", np.where(
        ~has_t, "closed", np.where(~moving, "stick", np.where(slip > 0, "slip+", "slip-"))))
    xn = np.where(separated, 0.0, xn)   # rounding noise of a force that is zero
    xt = np.where(separated, 0.0, xt)
    # Python numbers by tolist (one numpy scalar converted at a time cost
    # a millisecond on a 200-contact beam)
    supports = dict(zip(support_keys(frame), map(
        SupportResult, states.tolist(), xn.tolist(), xt.tolist(),
        np.asarray(z[:nc], float).tolist(), np.asarray(slip, float).tolist())))
    displacements = dict(zip(b["names"], map(tuple, u.reshape(-1, 3).tolist())))
    member_forces = dict(zip(frame.members, ends))
    ok = cert_error <= tol and eq <= max(tol, EQUILIBRIUM_FLOOR)
    msg = (f"{route}: contact certificate {cert_error:.1e}, equilibrium residual {eq:.1e}"
           + ("" if ok else " — CHECK FAILED") + (f" ({where})" if where and not ok else ""))
    ratio, rot, words = how_far(frame, u, second_order=b.get("axial") is not None,
                                coords=b["coords"])
    if words:
        msg += "; " + words
    return FrameResult(p=float(combo.get(VARIABLE, 0.0)), supports=supports,
                       displacements=displacements, member_forces=member_forces,
                       reactions=reactions, equilibrium_residual=eq, lcp_error=cert_error,
                       route=route, ok=ok, message=msg, frame=frame, _u=u,
                       combination=dict(combo), displacement_ratio=ratio,
                       max_rotation=rot, displacement_words=words,
                       stiffness_axial=b.get("axial"), stiffness_along=b.get("along"))


def resultant(frame, b, F, X, r_all, u, force_terms, HX=None, abs_hx=None):
    """The frame's global statics: Σ forces and Σ moments (about the nodes'
    centroid) of the loads, contact forces, bilateral reactions and
    springs, each equation against the sum of the absolute values of its
    terms (a 200-span beam's resultant is the rounding of 200 reactions,
    judged against all of them).

    The per-dof check cannot replace it: its scale holds |K||u|, which a
    rigid motion makes huge while K u stays zero — a Tresca iterate that
    lifted a frame resting on its contacts by 2e9 m passed it and the LCP
    certificate, and fails here by the weight its "separated" supports
    do not carry.  For the same reason a reaction is sized by the forces
    that meet at its dof (``force_terms``: members' end forces, springs,
    loads), not by |K||u|: sized so, a lever lifted off as a rigid motion
    of 1e11 m had its wrong pin reaction pass.  ``HX`` and ``abs_hx``:
    H X and |H||X| where the caller has them."""
    xy, lx, ly, size_xy = b["moment_arms"]
    absHX = contact_lcp.link_force_sizes(b, X) if abs_hx is None else abs_hx
    terms = [F, contact_lcp.link_forces(b, X) if HX is None else HX,
             np.where(b["fixed"], r_all, 0.0)]
    # each term by what it is made of: H X by |H||X|, a reaction (K u - F -
    # H X at its dof) by the forces meeting there and |H||X|
    size = np.abs(F) + absHX + np.where(b["fixed"], force_terms + absHX, 0.0)
    if b["Tn"] is not None:   # sums of forces are taken in global axes
        terms = [b["Tn"].T @ t for t in terms]
        size = abs(b["Tn"]).T @ size
        u = b["Tn"].T @ u
    spring = np.zeros_like(F)
    for node, ks in frame.springs.items():
        for d, kval in ks.items():
            i = b["idx"][node] + DOFS.index(d)
            spring[i] -= kval * u[i]
    terms.append(spring)
    size = size + np.abs(spring)
    total = sum(terms)
    fx, fy, mz = total[0::3], total[1::3], total[2::3]
    ax, ay, am = size[0::3], size[1::3], size[2::3]
    res = np.abs([fx.sum(), fy.sum(), (mz + xy[:, 0] * fy - xy[:, 1] * fx).sum()])
    scale = np.array([ax.sum(), ay.sum(), (am + lx * ay + ly * ax).sum()])
    if b.get("axial") is not None:
        # second order: the members' end forces are in equilibrium on the
        # deformed frame, so the undeformed moments sum to their P-Δ couples
        couples = varying_couples(frame, b, u, second_order.pdelta_couples(frame, b, u))
        res[2] = abs((mz + xy[:, 0] * fy - xy[:, 1] * fx).sum() - couples.sum())
        scale[2] += np.abs(couples).sum()
    big_m = (am + lx * ay + ly * ax).max(initial=0.0)
    # forces carry the rounding of the moments they balance too (a frame
    # loaded by a moment alone has shears that are zero but for it)
    big_f = max(ax.max(initial=0.0), ay.max(initial=0.0), am.max(initial=0.0) / size_xy)
    # every term of a sum carries its own rounding (R_ROUNDING of the largest)
    n_f = max(np.count_nonzero(ax), np.count_nonzero(ay), 1)
    n_m = np.count_nonzero(size)
    return max(beyond_rounding(res[:2], scale[:2], n_f * big_f),
               beyond_rounding(res[2:], scale[2:], n_m * big_m))


def collapse_words(frame, proof, fric, carrying) -> str:
    """How the frame fails, read off the Farkas vector y.

    y'w = Σ_c (A_c X_n + T_c X_t) with A_c = y_n + f (y+ + y-) and T_c =
    y+ - y-, and y'M = 0 makes this combination independent of the
    displacements: it is the virtual work of the contact forces in a rigid
    motion of the frame with normal motion A_c >= f |T_c| and tangential
    motion T_c at each contact.  A contact lifts off in it when A_c >
    f |T_c|, slides (along ±t) when T_c != 0 and A_c = f |T_c| (Coulomb's
    cone), and stays (a pivot) when both are zero.
    """
    y = proof["farkas"]
    nc = len(frame.contacts)
    A = y[:nc].copy()
    T = np.zeros(nc)
    for k, ci in enumerate(fric):
        yp, ym = y[nc + 2 * k], y[nc + 2 * k + 1]
        A[ci] += frame.contacts[ci].friction * (yp + ym)
        T[ci] = yp - ym
    return motion_words(frame, A, T, carrying)


def slide_words(frame, ci, t) -> str:
    """Which way contact ci slides in a rigid motion with tangential part
    t (its components along the contact's tangents)."""
    return "+t" if t[0] > 0 else "-t"
