"""From the faceted-cone LCP's answer z to a space frame's result, checked
from the data: the saddle solve for the displacements and the link forces,
member end actions, reactions, the contact states (each decided on its own
scale), equilibrium per dof and of the whole frame; and the words for how a
space frame fails (a Farkas vector or a rigid motion read as lifting,
sliding and tipping).  These are the space frame's hooks of the shared
analysis (:class:`~..mechanics.frame_kind.FrameKind`); what is generic is
in :mod:`..mechanics.equilibrium_checks` and :mod:`..mechanics.no_equilibrium`."""

from __future__ import annotations

import numpy as np

from qpcontact.judge.lcp_certificate import componentwise_error

from ..mechanics import contact_lcp, extended_refinement, second_order
from ..mechanics.equilibrium_checks import (CLEAR, EQUILIBRIUM_FLOOR, STATE_RTOL,
                                            beyond_rounding, equilibrium, how_far,
                                            mechanical_certificate, member_balance,
                                            reported_balance)
from ..mechanics.loads import CONSTANT, VARIABLE, support_keys
from ..mechanics.member_forces import refined_actions
from ..mechanics.no_equilibrium import motion_words
from .space_assembly import facet_angles, reach
from .space_results import SpaceFrameResult, SpaceSupportResult
from .space_varying import varying_couples


def result_from_z(frame, z, combo, route, b=None, lcp=None, tol=1e-9) -> SpaceFrameResult:
    b = b or frame.build()
    if not isinstance(combo, dict):   # a number p: the Osipova–Popov–Lovtsov split
        combo = {CONSTANT: 1.0, VARIABLE: float(combo)}
    P, W, g, fric = b["maps"]
    z = np.maximum(np.asarray(z, float), 0.0)
    factors = contact_lcp.factors(b, combo)
    F, ua = contact_lcp.load_vector(b, combo)  # ua: settlements (zero at free dofs)
    delta = P @ z - g
    nf, free = b["nf"], b["free"]
    sol = b["lu"].solve(np.r_[contact_lcp.free_loads(b, F, ua),
                              b["kappa"] * (delta - contact_lcp.settled_links(b, ua))])
    u = ua.copy()
    u[free] = sol[:nf]
    # the forces from the same solve as u (as the plane frame's: R Δ + R_F
    # has R's rounding-level entries dropped)
    X = -b["kappa"] * sol[nf:]
    exact, refined = None, None         # u refined in extended precision
    if not frame.contacts:
        # a linear frame (solving.solve_linear_frame): no contact unknowns
        # to certify; its equilibrium is checked below as any answer's
        cert_error, zeta, sigma = 0.0, np.zeros(0), np.zeros(0)
    else:
        if lcp is None:
            M, Q, q_gap, *_ = contact_lcp.lcp_matrices(b)
            lcp = contact_lcp.combination_lcp(M, Q, q_gap, b, combo)
        # the certificate's error and scales alone (its forward-error estimate
        # is not read here)
        cert_error, zeta, sigma = componentwise_error(lcp, z)
        # the answer refined on its states in extended precision, kept where it
        # checks at least as well (a stiff deck's forces: mechanics/extended_refinement)
        refined = extended_refinement.polished(b, z, F, ua, u, X,
                                               lcp.M @ z + lcp.q, zeta, sigma, cert_error)
    if refined is not None:
        z2, u2, X2 = refined
        # judged on the mechanics: the LCP's matrix carries the rounding of
        # the basic system's solve that the refinement has removed
        uf, Xf = u2.astype(float), X2.astype(float)
        ft2 = contact_lcp.force_terms(b, uf, F, contact_lcp.member_end_actions(
            b, contact_lcp.to_global(b, uf), factors))
        error2, zeta2, sigma2 = mechanical_certificate(b, z2, X2, u2, ft2)
        if error2 <= max(cert_error, tol):
            z, cert_error, zeta, sigma = z2, error2, zeta2, sigma2
            exact, u, X = u2, uf, Xf
            delta = P @ z - g
    r_all, ends, eq = statics(frame, b, F, u, X, exact, factors)
    if not frame.contacts and not eq <= CLEAR * max(tol, EQUILIBRIUM_FLOOR):
        # a linear frame whose answer in double does not pass its statics by
        # CLEAR (the plane recovery's gate): members 1e5 to 1e7 times stiffer
        # than others (rigid end zones, stiff braces) put the rounding of u
        # times the stiff k into the reactions, 1.4e-9 to 1.2e-7 of the
        # forces.  Refined in extended precision as a contact answer is
        # (there are no states to keep), kept where it checks at least as well
        refined = extended_refinement.polished(b, z, F, ua, u, X, np.zeros(0), zeta, sigma,
                                               cert_error)
        if refined is not None:
            uf, Xf = refined[1].astype(float), refined[2].astype(float)
            again = statics(frame, b, F, uf, Xf, refined[1], factors)
            if again[2] <= eq:
                u, X = uf, Xf
                r_all, ends, eq = again
    supports = contact_states(frame, b, z, X, contact_lcp.to_global(b, u), delta, zeta, sigma)
    off, where = as_reported(frame, b, F, u, X, r_all, supports, ends, tol)
    return space_result(frame, b, combo, u, ends, global_reactions(frame, b, r_all), supports,
                        max(eq, off), cert_error, f"contact certificate {cert_error:.1e}", route,
                        tol, where)


def as_reported(frame, b, F, u, X, r_all, supports, ends, tol):
    """(ratio, words) of the frame's balance with its contact forces as
    ``supports`` report them (a separated contact's set to zero):
    :func:`..mechanics.equilibrium_checks.reported_balance` dof by dof,
    with the global statics (:func:`resultant`) where something is out;
    the words where the ratio fails the answer."""
    pos = contact_lcp.layout(b)
    reported = np.zeros_like(X)
    for ci, s in enumerate(supports.values()):
        for kind, value in zip(("n", "t1", "t2"), (s.normal, *s.tangential)):
            if kind in pos[ci]:
                reported[pos[ci][kind]] = value
    return reported_balance(
        frame, b, F, u, X, reported, r_all,
        lambda rep: resultant(frame, b, F, rep, r_all, u, contact_lcp.force_terms(b, u, F, ends)),
        tol)


def global_reactions(frame, b, r_all) -> dict:
    """{node: its six reactions in global axes} at the supported nodes, from
    K u − F − H X over all dofs (the system's axes: a node's may be turned)."""
    # (a turned node's free dofs hold rounding noise, which the turn back
    # would mix into its reactions)
    r = r_all if b["Tn"] is None else b["Tn"].T @ np.where(b["fixed"], r_all, 0.0)
    return {node: tuple(float(v) for v in r[b["idx"][node]:b["idx"][node] + 6])
            for node in b["names"] if node in frame.fixed}


def statics(frame, b, F, u, X, exact, factors):
    """(all dofs' K u − F − H X, the reactions at the fixed ones; the
    members' end actions; the equilibrium residual: dof by dof and the
    frame's global statics; for a linear frame the balance of the end
    actions returned, :func:`..mechanics.equilibrium_checks.member_balance`)
    of an answer (u, X), K u and the end actions
    from ``exact`` (u in extended precision, member by member:
    :mod:`..mechanics.member_forces`) where the answer was refined, else in
    double.  A stiff member's end actions k T u in double carry ε|k||u|: a
    piece 1e7 times stiffer than its neighbour read 5e-6 off."""
    if exact is None:
        r_all = b["K"] @ u - F - contact_lcp.link_forces(b, X)
        ends = contact_lcp.member_end_actions(b, contact_lcp.to_global(b, u), factors)
    else:
        Ku, ends = refined_actions(b, exact, factors)
        r_all = np.asarray(Ku - np.asarray(F, Ku.dtype)
                           - b["H"].astype(Ku.dtype) @ np.asarray(X, Ku.dtype), float)
    ft = contact_lcp.force_terms(b, u, F, ends)
    eq = max(equilibrium(frame, b, F, X, u), resultant(frame, b, F, X, r_all, u, ft))
    if not frame.contacts:
        # the end actions returned balance at every node (a contact frame's
        # answers are not judged on it yet: its gate and cost are the
        # contact routes')
        eq = max(eq, member_balance(frame, b, F, X, u, ends, factors))
    return r_all, ends, eq


def space_result(frame, b, combo, u, ends, reactions, supports, eq, error, checked, route,
                  tol, where="") -> SpaceFrameResult:
    """The result of either cone: ok when the contact certificate's
    ``error`` and the equilibrium residual ``eq`` meet the tolerance;
    ``checked`` words the certificate for the message, ``where`` the
    reported forces' imbalance (:func:`as_reported`) if the check fails."""
    ok = bool(error <= tol and eq <= max(tol, EQUILIBRIUM_FLOOR))
    msg = f"{route}: {checked}, equilibrium residual {eq:.1e}" + (
        "" if ok else " — CHECK FAILED" + (f" ({where})" if where else ""))
    u = contact_lcp.to_global(b, u)           # reported in global axes
    ratio, rot, words = how_far(frame, u, second_order=b.get("axial") is not None,
                                coords=b["coords"])
    if words:
        msg += "; " + words
    msg += cone_words(frame)
    return SpaceFrameResult(
        p=float(combo.get(VARIABLE, 0.0)), supports=supports,
        displacements=dict(zip(b["names"], map(tuple, u.reshape(-1, 6).tolist()))),
        member_forces=dict(zip(frame.members, ends)), reactions=reactions,
        equilibrium_residual=eq, lcp_error=float(error), route=route, ok=ok, message=msg,
        frame=frame, _u=u, combination=dict(combo), displacement_ratio=ratio,
        max_rotation=rot, displacement_words=words, stiffness_axial=b.get("axial"),
        stiffness_along=b.get("along"))


def contact_states(frame, b, z, X, u, delta, zeta, sigma) -> dict:
    """Each contact's state, forces, opening and slip; a normal force or a
    facet's slip is zero below STATE_RTOL of its own scale (the
    certificate's)."""
    pos = contact_lcp.layout(b)
    out = {}
    nc = len(frame.contacts)
    at = nc                                   # the first facet of the next frictional contact
    for ci, (key, c) in enumerate(zip(support_keys(frame), frame.contacts)):
        xn = float(X[pos[ci]["n"]])
        if c.friction > 0:
            # a tangent the supports hold has no link: no slip, no friction
            xt = np.array([X[pos[ci][k]] if k in pos[ci] else 0.0 for k in ("t1", "t2")])
            slip = np.array([delta[pos[ci][k]] if k in pos[ci] else 0.0
                             for k in ("t1", "t2")])
            m = facet_angles(frame, c).size
            facets = slice(at, at + m)
            at += m
            moving = bool(np.any(z[facets] > STATE_RTOL * zeta[facets]))
        else:
            # frictionless: the node slides freely; its slip is the
            # tangential part of its motion (relative to ``other``'s for a pair)
            d = u[b["idx"][c.node]:b["idx"][c.node] + 3]
            if c.other is not None:
                d = d - u[b["idx"][c.other]:b["idx"][c.other] + 3]
            xt, slip, moving = np.zeros(2), np.array([c.t1 @ d, c.t2 @ d]), False
        if xn <= STATE_RTOL * sigma[ci]:
            state, xn, xt = "separated", 0.0, np.zeros(2)
        elif c.friction == 0:
            state = "closed"
        else:
            state = "slip" if moving else "stick"
        use = None
        a = facet_angles(frame, c)
        # (no facet where bilateral supports hold both tangents: friction
        # carries nothing there, and there is no use to report)
        if a.size and state != "separated":
            # the polygon's own measure: the most loaded facet, w_k = reach f X_n + d_k·X_t
            use = float(np.max(-(np.cos(a) * xt[0] + np.sin(a) * xt[1]))
                        / (reach(frame, c) * c.friction * xn))
            use = max(use, 0.0)
        out[key] = SpaceSupportResult(state, xn, xt, float(z[ci]), slip, t1=c.t1, t2=c.t2,
                                      cone_use=use)
    return out


def resultant(frame, b, F, X, r_all, u, force_terms):
    """The frame's global statics: Σ forces and Σ moments (about the
    nodes' centroid) of loads, contact forces, reactions and springs, each
    of the six equations against the sum of its terms' sizes, a reaction
    sized by the forces that meet at its dof (as the plane frame's
    :func:`~..plane.plane_recovery.resultant`, which says why the
    per-dof check cannot replace it)."""
    xyz = b["coords"] - b["coords"].mean(axis=0)
    absHX = contact_lcp.link_force_sizes(b, X)
    terms = F + contact_lcp.link_forces(b, X) + np.where(b["fixed"], r_all, 0.0)
    size = np.abs(F) + absHX + np.where(b["fixed"], force_terms + absHX, 0.0)
    if b["Tn"] is not None:   # sums of forces are taken in global axes
        terms, size, u = b["Tn"].T @ terms, abs(b["Tn"]).T @ size, b["Tn"].T @ u
    spring = -b["springs"] * u
    total = (terms + spring).reshape(-1, 6)
    size = (size + np.abs(spring)).reshape(-1, 6)
    force = total[:, :3].sum(axis=0)
    moment = (total[:, 3:] + np.cross(xyz, total[:, :3])).sum(axis=0)
    couples = None
    if b.get("axial") is not None:
        # second order: the members' end forces are in equilibrium on the
        # deformed frame, so the undeformed moments sum to their P-Δ couples
        couples = varying_couples(frame, b, u, second_order.pdelta_couples(frame, b, u))
        moment = moment - couples.sum(axis=0)
    lever = np.abs(xyz)
    f_size = size[:, :3]
    # |r x f| component by component is at most the sum of |r_a||f_b| over the other two axes
    m_size = size[:, 3:] + np.stack([lever[:, 1] * f_size[:, 2] + lever[:, 2] * f_size[:, 1],
                                     lever[:, 2] * f_size[:, 0] + lever[:, 0] * f_size[:, 2],
                                     lever[:, 0] * f_size[:, 1] + lever[:, 1] * f_size[:, 0]],
                                    axis=1)
    if couples is not None:
        m_size = np.vstack([m_size, np.abs(couples)])
    span = max(float(np.linalg.norm(np.ptp(xyz, axis=0))), 1e-300)
    big_f = max(f_size.max(initial=0.0), m_size.max(initial=0.0) / span)
    n_f = max(np.count_nonzero(f_size), 1)
    n_m = max(np.count_nonzero(m_size), 1)
    return max(beyond_rounding(np.abs(force), f_size.sum(axis=0), n_f * big_f),
               beyond_rounding(np.abs(moment), m_size.sum(axis=0),
                               n_m * m_size.max(initial=0.0)))


def collapse_words(frame, proof, fric, carrying) -> str:
    """How the frame fails, read off the Farkas vector y as the plane
    frame's: A_c = y_n + f Σ_k y_k, T_c = Σ_k y_k d_k (the facets'
    directions in the contact's tangent plane) — the normal and
    tangential parts of a rigid motion in which the contact forces do no
    work.  The contact slides in it when y_n = 0: its T_c is handed on
    with length Σ_k y_k, the faceted cone's measure of it (a slip between
    two facets has |Σ y_k d_k| < Σ y_k, and the Euclidean length read a
    stool turning about one pad as the other two lifting off)."""
    y = proof["farkas"]
    nc = len(frame.contacts)
    A = y[:nc].copy()
    T = np.zeros((nc, 2))
    at = nc
    for ci in fric:
        c = frame.contacts[ci]
        a = facet_angles(frame, c)
        yk = y[at:at + a.size]
        at += a.size
        A[ci] += c.friction * reach(frame, c) * yk.sum()
        T[ci] = [yk @ np.cos(a), yk @ np.sin(a)]
        length = np.linalg.norm(T[ci])
        if length > 0:
            T[ci] *= yk.sum() / length
    return motion_words(frame, A, T, carrying)


def slide_words(frame, ci, t) -> str:
    c = frame.contacts[ci]
    d = t[0] * c.t1 + t[1] * c.t2 if len(t) == 2 else t[0] * c.t1
    d = d / max(np.linalg.norm(d), 1e-300)
    return "along (" + ", ".join(f"{v + 0.0:.3g}" for v in np.round(d, 3)) + ")"


def cone_words(frame) -> str:
    """The bound a polygon's friction keeps from Coulomb's circle, for the
    messages ("" on the circle or without friction)."""
    m = sorted({c.facets for c in frame.contacts if c.friction > 0})
    if frame.cone == "circular" or not m:
        return ""
    facets = "/".join(map(str, m))
    if frame.cone == "inscribed":
        return (f"; friction on the inscribed {facets}-gon: never more than Coulomb's, at most "
                f"{100 * (1 - np.cos(np.pi / m[0])):.2g} % less")
    return (f"; friction on the circumscribed {facets}-gon: never less than Coulomb's, up to "
            f"{100 * (1 / np.cos(np.pi / m[0]) - 1):.2g} % more (the unsafe side for a limit)")
