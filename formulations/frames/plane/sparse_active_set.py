"""The frame's contact problem solved on the sparse structure: an active set.

The LCP of :mod:`.assembly` needs the contact stiffness R, dense, links x
links — one solve of the basic system per link.  A 1000-span beam has 2 000
links: R alone took 0.9 s, where OpenSees analyses the whole beam in 0.1 s.
This route never forms R.  It guesses every contact's state (closed or
open; with friction stick, slip+ or slip-), solves the frame with those
states as one sparse linear system, and corrects the states from what that
solution violates, the way a Newton iteration on compression-only springs
does — until no state changes:

    [ K_ff   κH_f ] [u_f]   [F_f - K_fa u_a]
    [ C_u    C_y  ] [ y ] = [      c       ],     X = -κ y,

one row per link: kinematic where the link holds (closed normal: the
opening Z_n = g + Δ_n = 0; sticking tangent: the slip Δ_t = 0, with Δ =
H'u + D X, D the contact flexibility), static where it does not (open:
X = 0; slip±: X_t = ∓f X_n, friction at its bound against the slip).

In the links' own space (few links: a tower's 17 contacts) the state sets
start from the closed set that single principal pivots on the contact
stiffness choose, friction left out of the choice (:func:`_held_start`):
the map X = R Δ + R_F with one contact's link forces and displacements
exchanged at a time, a rank-2 update where a state set is a dense solve
and its proposal — a tower's lift-off front moved one or two contacts a
state set.  The start decides no state: the state sets from it do, and a
start from which they find nothing gives way to every contact closed.

A state is changed only by a violation beyond rounding (a closed contact
pulling, an open one overlapping, a sticking one beyond f X_n, a slipping
one moving backwards), so a degenerate contact keeps its state.  A state
set seen before ends the search (a cycle), as does the iteration limit:
the route then returns None and the frame falls back to its LCP (Lemke,
the load path), which is exact where this is not guaranteed to terminate.

The answer is returned as the LCP's point z (openings, slip parts), from
which :func:`~.plane_recovery.result_from_z` rebuilds the frame's
result and checks it from the data: whatever this route did, the result is
ok only if the contact certificate and equilibrium hold.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from ..mechanics import banded_saddle, contact_lcp
from . import plane_assembly

#: a state changes on a violation beyond this fraction of its own scale
VIOLATION = 1e-12
#: state changes tried before the LCP route takes over
MAX_ITERATIONS = 100
#: a state set's system in the links' space with a smaller reciprocal
#: condition (LAPACK's 1-norm estimate) is a mechanism
RCOND_MIN = 1e-12
#: up to this many links the states are solved on the dense contact
#: stiffness R (its nl solves cost less than the sparse factorizations:
#: 5.1 against 8.1 ms at 101 links, 11.0 against 9.8 ms at 201, beams of 50
#: and 100 spans on frictional supports)
LINK_SPACE_MAX = 150


def solve_active_set(frame, b, combo):
    """(z, iterations) of an equilibrium with consistent contact states, or
    None (a cycle, the iteration limit, a singular system).  Few links
    (at most LINK_SPACE_MAX): the states are solved in the links' own space
    on the contact stiffness R (:func:`_link_space`), from the closed set
    that single pivots on R choose (:func:`_held_start`); many: on the
    sparse saddle system (:func:`_sparse`), from every contact closed.
    ``iterations``: the state sets of the series that answered (the
    start's pivots are not state sets).  A start whose state sets end
    without an answer (a cycle, the limit, a mechanism) is dropped — its
    sets are not counted, so a solve may run up to twice MAX_ITERATIONS
    sets — and the state sets begin again from every contact closed, as
    they did before there was a start."""
    ca = plane_assembly.contact_arrays(frame, b)
    nc = len(frame.contacts)
    required = np.zeros(len(b["info"]))
    required[ca["n_link"]] = -ca["gap"]                # a closed link: Δ_n = -g
    if len(b["info"]) <= LINK_SPACE_MAX:
        # the combination's link forces with every link held, for the state
        # sets' solver and the start alike
        RF = b["RF"] @ contact_lcp.factors(b, combo)
        states, start = _link_space(b, RF, required), _held_start(b, RF, ca, required)
    else:
        states, start = _sparse(b, combo, required), None
    if start is not None and not start.all():
        found = _state_sets(frame, b, ca, states, start)
        if found is not None:
            return found
    return _state_sets(frame, b, ca, states, np.ones(nc, bool))


def _state_sets(frame, b, ca, states, closed):
    """The state sets from the closed contacts ``closed`` (all sticking):
    (z, iterations) or None (:func:`solve_active_set`)."""
    nc = len(frame.contacts)
    n_link, t_link, mu, gap = ca["n_link"], ca["t_link"], ca["mu"], ca["gap"]
    has_t = t_link >= 0
    tl = np.where(has_t, t_link, 0)
    slip = np.zeros(nc, int)          # 0 stick, +1 slip+, -1 slip-
    seen, one_at_a_time, last = set(), False, None
    for it in range(1, MAX_ITERATIONS + 1):
        key = closed.tobytes() + slip.tobytes()
        if key in seen:
            if one_at_a_time:
                return None
            # a cycle of whole state sets (a gap contact flipping closed and
            # open as its neighbours change with it): go on from here changing
            # only the most violated contact each time
            one_at_a_time, seen = True, set()
        seen.add(key)
        kin = np.zeros(len(b["info"]), bool)
        kin[n_link[closed]] = True
        kin[t_link[closed & has_t & (slip == 0)]] = True
        sliding = np.flatnonzero(closed & has_t & (slip != 0))
        found = states(kin, sliding, n_link, t_link, mu * slip)
        if found is None:
            if last is None or one_at_a_time:
                return None
            # the whole step left a mechanism (every contact of a frame that
            # rests on them opened at once): back to the last state set, and
            # from there one contact at a time
            one_at_a_time = True
            closed, slip, proposal, _ = last
            seen = {closed.tobytes() + slip.tobytes()}
        else:
            proposal = _proposal(found, closed, slip, n_link, tl, has_t, mu, gap)
            if not ((proposal[0] != closed) | (proposal[1] != slip)).any():
                delta = found[1]
                return _point(frame, b, closed, slip, delta[n_link] + gap, delta, t_link,
                              has_t), it
            last = (closed, slip, proposal, found)
        new_closed, new_slip = proposal
        if one_at_a_time:
            changed = (new_closed != closed) | (new_slip != slip)
            how_much = _how_much(last[3], closed, slip, new_closed, n_link, tl, mu, gap)
            worst = int(np.argmax(np.where(changed, how_much, -np.inf)))
            new_closed, new_slip = closed.copy(), slip.copy()
            new_closed[worst], new_slip[worst] = proposal[0][worst], proposal[1][worst]
        closed, slip = new_closed, new_slip
    return None


#: the start's single pivots, per contact, before it is given up
START_PIVOTS = 2


def _held_start(b, RF, ca, required):
    """Which contacts to close first in the links' space: the closed set of
    the contact problem with friction left out of the choice — a closed
    contact holds its links (Δ = −g normal, 0 tangential: it sticks), an
    open one releases them (X = 0) — found one contact at a time by
    principal pivots on the map of the links, X = R Δ + R_F [kN].

    The map's inputs are the held links' displacements Δ [m] and the
    released links' forces X (zero), its outputs the held links' forces
    and the released links' displacements.  Releasing contact c exchanges
    its links' input and output: with T the map (links x links, and R_F's
    column), p c's links and r the others, Δ_p = T_pp⁻¹ (X_p − T_pr x_r),
    so T_pp⁻¹ becomes the pp block, −T_pp⁻¹ T_pr the p rows, T_rp T_pp⁻¹
    the p columns and T_rr − T_rp T_pp⁻¹ T_pr the rest; closing it again
    is the same exchange back.  Each step takes the closed contact that
    pulls hardest (X_n < 0 beyond VIOLATION of the forces with every link
    held), else the open one that overlaps most (Z_n = Δ_n + g < 0 beyond
    VIOLATION of |Δ_n| + |g|).  A pivot is a rank-2 update of a 34 x 35
    array on a 20-storey tower (:func:`._plane_kernels.held_start`), where
    a state set and its proposal are some 70 NumPy calls: its lift-off
    front moves one or two contacts a state set (seven sets), one a pivot
    (eleven), and the state sets then start from the closed set they end
    on (one set).

    Only a start: the state sets from it decide every state (friction's
    too) and solve the answer as from any start; a start is never an
    answer.  None where the pivots run out (START_PIVOTS per contact: a
    cycle), where a pivot block is singular (a release that leaves a
    mechanism), or where the map stops being finite.  ``RF``: R_F [kN] of
    the combination."""
    from ._plane_kernels import held_start
    # the pivots in one compiled loop (as array expressions: a sixteenth of
    # a 20-storey tower's solve)
    found, closed = held_start(b["R_solve"], RF, required, ca["n_link"], ca["t_link"], ca["gap"],
                               VIOLATION, RCOND_MIN, START_PIVOTS)
    return closed if found else None


def _proposal(found, closed, slip, n_link, tl, has_t, mu, gap):
    """The states the solution of a state set calls for: a closed contact
    opens where it pulls, an open one closes where it overlaps, a sticking
    one slips beyond f X_n, a slipping one sticks again when it moves
    backwards (each beyond VIOLATION of its own scale)."""
    X, delta, force_scale, length_scale = found
    Xn = X[n_link]
    fn = force_scale[n_link]
    new_closed = np.where(closed, Xn >= -VIOLATION * fn,
                          delta[n_link] + gap < -VIOLATION * length_scale[n_link])
    # friction where the contact was and stays closed (a newly closed one
    # starts sticking)
    xt = X[tl]
    bound = mu * np.maximum(Xn, 0.0)
    ft = VIOLATION * force_scale[tl]
    starts = (xt < -bound - ft).astype(slip.dtype) - (xt > bound + ft)
    goes_on = np.where(slip * delta[tl] >= -VIOLATION * length_scale[tl], slip, 0)
    new_slip = np.where(new_closed & closed & has_t, np.where(slip == 0, starts, goes_on), 0)
    return new_closed, new_slip


def _how_much(found, closed, slip, new_closed, n_link, tl, mu, gap):
    """How far each contact is from its present state (a pull, an overlap,
    a friction force beyond f X_n, a slip running backwards — each against
    its own scale): the order in which one contact at a time changes.
    Read only on that path (it was a tenth of a millisecond per state set)."""
    X, delta, force_scale, length_scale = found
    Xn, Zn = X[n_link], delta[n_link] + gap
    fn, ln = force_scale[n_link], length_scale[n_link]
    xt, dt = X[tl], delta[tl]
    bound = mu * np.maximum(Xn, 0.0)
    ft, lt = force_scale[tl], length_scale[tl]
    with np.errstate(divide="ignore", invalid="ignore"):
        how_much = np.where(new_closed != closed, np.where(closed, -Xn / fn, -Zn / ln),
                            np.where(slip == 0, (np.abs(xt) - bound) / ft, -slip * dt / lt))
    return np.nan_to_num(how_much, nan=0.0, posinf=1e300)


def _sparse(b, combo, required):
    """The states' solver on the sparse saddle system: one SuperLU per state
    set (the first, every link holding, is the basic system's, already
    factorized).  Returns solve(kin, sliding, n_link, t_link, f·slip) ->
    (X, Δ, force scales, length scales) or None (singular)."""
    kappa, nf, free = b["kappa"], b["nf"], b["free"]
    nl = len(required)
    F, ua = contact_lcp.load_vector(b, combo)
    rhs_top = contact_lcp.free_loads(b, F, ua)
    shift = -contact_lcp.settled_links(b, ua)   # what settlements do to the links
    H, flex = b["H"], b["flex"]
    held = {}

    def triplets():
        """The saddle matrix as triplets: the top rows, and the link rows
        that are kept where a link holds (each state set's matrix is one
        COO -> CSC); made where a state set is factorized by SuperLU."""
        if "top" not in held:
            S = b["S"].tocoo()
            top = S.row < nf
            held["top"] = S.row[top], S.col[top], S.data[top]
            held["link"] = S.row[~top] - nf, S.col[~top], S.data[~top]
        return held["top"], held["link"]

    def link_rows(links):
        """The saddle matrix's rows of the given links where they hold
        (dense, one row per link)."""
        out = np.zeros((links.size, nf + nl))
        link_r, link_c, link_v = triplets()[1]
        at = np.full(nl, -1)
        at[links] = np.arange(links.size)
        k = at[link_r] >= 0
        out[at[link_r[k]], link_c[k]] = link_v[k]
        return out

    def partners(n_link, t_link):
        """Each tangent link's normal link (what a slipping row couples to)."""
        if "partner" not in held:
            has_t = t_link >= 0
            held["partner"] = np.zeros(nl, int)
            held["partner"][t_link[has_t]] = n_link[has_t]
        return held["partner"]

    factors = contact_lcp.factors(b, combo)
    # the transposes once per assembly, not three per state set
    HT, absHT = b["HT"], b["abs_HT"]

    # the last factorized state set (its LU, which rows hold, the slip rows'
    # coefficients): a state set that differs from it in few link rows is
    # solved against that LU (:func:`_bordered`), not factorized afresh
    held.update(lu=b["lu"], kin=np.ones(nl, bool), coef=np.zeros(nl))

    def solve(kin, sliding, n_link, t_link, f_slip):
        rhs = np.concatenate((rhs_top, np.where(kin, kappa * (required + shift), 0.0)))
        coef = np.zeros(nl)
        coef[t_link[sliding]] = f_slip[sliding]
        if kin.all():             # every link holds: the basic system, factorized by build
            sol = b["lu"].solve(rhs)
        else:
            partner = partners(n_link, t_link)

            def times(x):
                """B x: the saddle matrix's product with this state set's
                static rows put in (κ x_l, plus κ f x_n on a slipping tangent)."""
                y = b["S"] @ x
                static = np.flatnonzero(~kin)
                y[nf + static] = kappa * x[nf + static] + kappa * coef[static] * x[
                    nf + partner[static]]
                return y

            if b["band"] is not None:
                # elastic contacts: a fresh banded LU of the condensed
                # stiffness costs less than a bordered solve against the last
                lu = banded_saddle.factor(b["band"], kin, coef, partner)
                sol = None if lu is None else lu.solve(rhs)
            else:
                sol = _bordered(held, kin, coef, partner, rhs, nf, kappa, link_rows, times)
            if sol is None:
                # static rows: X = 0 (open), X_t ± f X_n = 0 (slip±), scaled like the links
                static = np.flatnonzero(~kin)
                (top_r, top_c, top_v), (link_r, link_c, link_v) = triplets()
                keep = kin[link_r]
                rows = np.concatenate([top_r, nf + link_r[keep], nf + static,
                                       nf + t_link[sliding]])
                cols = np.concatenate([top_c, link_c[keep], nf + static, nf + n_link[sliding]])
                vals = np.concatenate([top_v, link_v[keep], np.full(static.size, kappa),
                                       kappa * f_slip[sliding]])
                # a state set that leaves a mechanism is singular — to rounding
                # only, where the frame is not square to the axes: solved anyway
                # it gave rigid motions of 1e11 m that passed every scaled check
                lu = contact_lcp.regular_lu(sp.csc_matrix((vals, (rows, cols)),
                                                       shape=(nf + nl, nf + nl)))
                if lu is None:
                    return None
                held.update(lu=lu, kin=kin.copy(), coef=coef)
                sol = lu.solve(rhs)
        if not np.all(np.isfinite(sol)):
            return None
        u = ua.copy()
        u[free] = sol[:nf]
        X = -kappa * sol[nf:]
        return (X, HT @ u + flex * X, absHT @ contact_lcp.force_terms(
            b, u, F, contact_lcp.member_end_actions(b, contact_lcp.to_global(b, u), factors)),
                absHT @ np.abs(u) + np.abs(flex * X) + np.abs(required))

    return solve


#: a state set that changes at most this many link rows of the last
#: factorized one is solved against its LU with the changed rows as a
#: border (one solve with this many right-hand sides and a small dense
#: system): a SuperLU solve costs a fifth of a factorization, and each
#: further right-hand side adds a little; measured even with a fresh
#: factorization at about 20 rows on 200- and 1000-span beams
BORDERED_MAX = 12
#: the border's dense system (rows equilibrated) with a smaller reciprocal
#: condition is not trusted: the state set is factorized afresh (and judged
#: singular or not on its own pivots, as every state set was)
BORDER_RCOND = 1e-8


def _bordered(held, kin, coef, partner, rhs, nf, kappa, link_rows, times):
    """The state set's system B x = rhs solved against the LU of the last
    factorized one, A, where they differ in at most BORDERED_MAX link rows
    R: with Y = A⁻¹ E (E the unit columns of R) and the border C = B_R Y
    (B's rows R times Y; A_R Y = I, so this is I + (B_R − A_R) Y of
    Sherman–Morrison–Woodbury without its cancellation), x = A⁻¹ rhs −
    Y C⁻¹ (B_R A⁻¹ rhs − rhs_R): B's rows outside R are A's, which Y does
    not move, and its rows R hold by construction.  None where more rows
    changed or C is ill-conditioned (a state set that leaves a mechanism
    makes C singular): the caller factorizes B.  What this changes is the
    rounding of the state set's openings and slips; the answer's u and X
    are recovered and checked from them as before."""
    changed = np.flatnonzero((kin != held["kin"]) | (~kin & (coef != held["coef"])))
    if changed.size > BORDERED_MAX:
        return None
    if changed.size == 0:
        return held["lu"].solve(rhs)
    # B's rows R: a held link's row is the saddle matrix's; a static one is
    # κ on its diagonal and, for a slipping tangent, κ f on its normal link
    BR = link_rows(changed) * kin[changed][:, None]
    static = ~kin[changed]
    BR[np.flatnonzero(static), nf + changed[static]] = kappa
    slides = static & (coef[changed] != 0.0)
    BR[np.flatnonzero(slides), nf + partner[changed[slides]]] = kappa * coef[changed[slides]]
    E = np.zeros((rhs.size, changed.size + 1))
    E[:, 0] = rhs
    E[nf + changed, np.arange(1, changed.size + 1)] = 1.0
    sol = held["lu"].solve(E)
    x, Y = sol[:, 0], sol[:, 1:]
    C = BR @ Y
    big = np.abs(C).max(axis=1)
    if not np.all(big > 0):
        return None
    C /= big[:, None]                        # rows equilibrated: rcond measures C, not units
    lu, piv, info = scipy.linalg.lapack.dgetrf(C)
    if info != 0 or scipy.linalg.lapack.dgecon(
            lu, np.abs(C).sum(axis=0).max(), norm="1")[0] < BORDER_RCOND:
        return None

    def solved(v, target):
        """B⁻¹ target from v = A⁻¹ target and the border."""
        return v - Y @ scipy.linalg.lu_solve((lu, piv), (BR @ v - target[nf + changed]) / big,
                                             check_finite=False)

    x = solved(x, rhs)
    # one step of refinement on B's own residual (B x: the saddle matrix's
    # product with the static rows put in), for one more solve: without it
    # a bordered answer was up to 8 times farther from the extended-precision
    # one than a fresh LU's (4e-12 against 5e-13 of the forces, a 153-span
    # beam); with it within a factor 4 either way, nearer on three of the
    # four beams that differed most (dev-notes, round four)
    res = rhs - times(x)
    return x + solved(held["lu"].solve(res), res)


def _link_space(b, RF, required):
    """The states' solver in the links' space, for few links on many dofs
    (a tower on 17 contacts: 34 links, 291 dofs): the contact stiffness R
    (one solve of the basic system per link, from its LU) condenses the
    frame onto its links, X = R Δ + R_F; each state set is then a dense
    system in the displacements of the links that do not hold, C R_SS Δ_S =
    -C (R_SK Δ_K + R_F) with C the static rows (X = 0, X_t ± f X_n = 0).
    R stays in b: the result is then certified on the LCP itself.  The
    solves use R before its rounding-level entries are dropped (those are
    dropped for the trace's proofs; here, times the large openings of a
    lifted stretch, they put the support forces 1.7e-9 off OpenSees and
    PyNite on a 50-span beam, where the sparse route agrees to 3e-13).
    ``RF``: R_F [kN] of the combination."""
    R = b["R_solve"]
    absR, absRF, abs_required = np.abs(R), np.abs(RF), np.abs(required)

    at = np.empty(R.shape[0], int)

    def solve(kin, sliding, n_link, t_link, f_slip):
        delta = np.where(kin, required, 0.0)
        S = np.flatnonzero(~kin)
        if S.size:
            # C's rows picked out of R, not multiplied: a static link's row
            # is its own (X_l = 0), a slipping tangent's adds f_slip times
            # its normal's (X_t ± f X_n = 0) — C @ R[:, S] with C's unit rows
            # made as a dense product (a tenth of a tower's state set)
            at[S] = np.arange(S.size)
            t, n, f = at[t_link[sliding]], n_link[sliding], f_slip[sliding]
            A = R[S[:, None], S]
            X0 = R @ delta + RF
            b_ = -X0[S]
            if t.size:
                A[t] += f[:, None] * R[n[:, None], S]
                b_[t] -= f * X0[n]
            # as in the sparse form: a mechanism's A is singular to rounding
            lu, piv, info = scipy.linalg.lapack.dgetrf(A)
            if info != 0 or scipy.linalg.lapack.dgecon(
                    lu, np.abs(A).sum(axis=0).max(), norm="1")[0] < RCOND_MIN:
                return None
            delta[S] = scipy.linalg.lapack.dgetrs(lu, piv, b_)[0]
        X = R @ delta + RF
        if not (np.isfinite(X).all() and np.isfinite(delta).all()):
            return None
        return X, delta, absR @ np.abs(delta) + absRF, np.abs(delta) + abs_required

    return solve


def _point(frame, b, closed, slip, Zn, delta, t_link, has_t):
    """The LCP's z of a converged state set: openings of the open contacts,
    slip parts of the slipping (and the open) frictional ones."""
    nc = len(frame.contacts)
    dt = delta[t_link[has_t]]
    moving = ~closed[has_t] | (slip[has_t] != 0)
    z = np.zeros(nc + 2 * dt.size)
    z[:nc] = np.where(closed, 0.0, np.maximum(Zn, 0.0))
    z[nc::2] = np.where(moving, np.maximum(dt, 0.0), 0.0)
    z[nc + 1::2] = np.where(moving, np.maximum(-dt, 0.0), 0.0)
    return z
