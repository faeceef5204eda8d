"""A frame's answer on Coulomb's circular cone found, or refined, on its
contact states in extended precision: Newton's method on the states'
smooth system inside an active-set loop that corrects the states.

Why.  The friction solvers work in double on the frame's global problem:
beside a deck 1e8 times stiffer than its legs, their answer carries
ε|K||u| in the forces — the table's pads 0.27 kN out of balance at 1e8,
2e-7 at 1e4 — and the frame's statics rightly refuse it; near a change of
state or the limit they may stop uncertified (a certificate of 1e-5 …
1e-2 on the pushed table).  Once each contact's state is known the answer
is the root of a small smooth system, and Newton's method on it with the
residual in ``numpy.longdouble`` (member forces member by member, each
member's rigid motion taken out:
:func:`..mechanics.member_forces.stiffness_times`) gives the digits back;
where a state proves wrong (a sticking contact whose friction leaves the
circle, a slipping one whose slip turns against its force, a closed one
in tension, a separated one that penetrates) it is changed and Newton run
again — a primal-dual active set on the circle, started from the friction
solvers' answer or from the faceted cone's exact one.

The system.  Unknowns: the free displacements u_f, each contact's force
r_c = (X_n, X_t1, X_t2) and, per slipping contact, its slip rate λ_c ≥ 0;
Δ_c = H_cᵀ u + g_c + r_c/k_c the contact's opening and slip (k_c its
spring, ∞ when rigid):

    (K u − F − H r)_f = 0                              [force]
    separated:  r_c = 0
    sticking:   Δ_c = 0                                [length, × κ]
    slipping:   Δ_n = 0,  Δ_t + λ X_t = 0,  |X_t| − f X_n = 0
    frictionless and closed: Δ_n = 0, X_t = 0

— the slip opposite to the friction, which is on the circle (maximal
dissipation).  Unlike X_t = −f X_n s/|s| this stays regular where a slip
starts (λ = 0).  A tangent held by the node's bilateral supports carries
no friction here (the support's reaction does): X along it is 0 and the
slip is the other tangent's.

The caller keeps an answer only where it passes the frame's own checks
(friction certificate, equilibrium): the states and Newton are how it is
found, not why it is believed.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..mechanics.member_forces import EXTENDED, stiffness_times

#: Newton steps at most per set of states
STEPS = 12
#: changes of the states at most
CHANGES = 12
#: a state is wrong where its inequality fails by more than this (relative
#: to the quantity's own scale)
SLACK = 1e-12


def solve_on_states(b, F, u, r, Hc, gap, flex, mu, states, held):
    """(u, r, states): the answer (extended precision) and the states it
    settled on, from the start (u over all dofs, settlements at the fixed
    ones; r per contact (n, t1, t2)) and its ``states`` ("separated",
    "closed", "stick", "slip"; ``held`` (nc, 2) the tangents the bilateral
    supports hold); None where Newton does not settle or the states cycle."""
    states = list(states)
    E = EXTENDED
    u = np.asarray(u, E).copy()
    r = np.asarray(r, E).copy()
    lam = start_rates(u, r, Hc, gap, flex, states, held)
    seen = set()
    for _ in range(CHANGES):
        out = newton(b, F, u, r, lam, Hc, gap, flex, mu, states, held)
        if out is None:
            return None
        u, r, lam = out
        new = corrected(u, r, lam, Hc, gap, flex, mu, states, held)
        if new == states:
            return u, r, states
        key = tuple(new)
        if key in seen:
            return None
        seen.add(key)
        for c, (a, bb) in enumerate(zip(states, new)):
            if bb == "slip" and a != "slip":
                lam[c] = E(0)
        states = new
    return None


def start_rates(u, r, Hc, gap, flex, states, held):
    """λ_c for the slipping contacts from the start: |slip| / |X_t|."""
    delta = np.asarray(Hc, float).T @ np.asarray(u, float) + gap + flex * np.asarray(r, float)
    lam = np.zeros(len(states), EXTENDED)
    for c, s in enumerate(states):
        if s == "slip":
            t = _free_tangents(held[c])
            xt = np.linalg.norm([float(r[3 * c + k]) for k in t])
            st = np.linalg.norm([delta[3 * c + k] for k in t])
            lam[c] = st / xt if xt > 0 else 0.0
    return lam


def _free_tangents(held_c):
    return [k for k in (1, 2) if not held_c[k - 1]]


def corrected(u, r, lam, Hc, gap, flex, mu, states, held):
    """The states the answer (u, r, λ) shows: a sticking contact whose
    friction leaves the circle slips, a slipping one with λ < 0 sticks, a
    closed one in tension separates, a separated one that penetrates
    closes — each beyond SLACK of its own scale."""
    new = []
    for s, checks in zip(states, inequalities((u, r, lam), Hc, gap, flex, mu, states, held)):
        broken = [to for value, scale, to in checks if value < -SLACK * scale]
        new.append(broken[0] if broken else s)
    return new


def inequalities(answer, Hc, gap, flex, mu, states, held) -> list:
    """Per contact, the inequalities its state keeps, in the order they are
    read: (value, its scale, the state the contact goes to where the value
    is below zero) — a separated contact's opening (over |h|ᵀ|u| + gap +
    |X|/k), then for the others X_n (over the largest force), a sticking
    one's f X_n − |X_t| (over f X_n and the largest force), a slipping
    one's λ (over the largest λ)."""
    u, r, lam = (np.asarray(x, float) for x in answer)
    delta = np.asarray(Hc, float).T @ u + gap + flex * r
    size = np.abs(np.asarray(Hc, float)).T @ np.abs(u) + np.abs(gap) + np.abs(flex * r)
    force = max(float(np.abs(r).max(initial=0.0)), 1e-300)
    rate = max(float(np.abs(lam).max(initial=0.0)), 1e-300)
    out = []
    for c, s in enumerate(states):
        f = mu[c]
        if s == "separated":
            out.append([(delta[3 * c], max(size[3 * c], 1e-300),
                         "stick" if f > 0 else "closed")])
            continue
        xn = r[3 * c]
        t = _free_tangents(held[c])
        checks = [(xn, force, "separated")]
        if s == "stick" and t:
            xt = np.linalg.norm([r[3 * c + k] for k in t])
            checks.append((f * xn - xt, f * xn + force, "slip"))
        elif s == "slip":
            checks.append((lam[c], rate, "stick"))
        out.append(checks)
    return out


def newton(b, F, u, r, lam, Hc, gap, flex, mu, states, held):
    """(u, r, λ) solving the states' system (module docstring) by Newton's
    method from (u, r, λ), the residual in extended precision; None where
    its matrix is singular or it does not settle.

    The matrix is factored again only where the last factorization stops
    contracting the steps (a chord step costs a residual; a factorization
    of the tower's 1 100 unknowns twenty): the residual, not the matrix,
    sets the answer's digits.  The factorization at the start is kept for
    the next call from the same forces and rates (its matrix does not
    depend on u or the load): an event's root search starts every solve
    from one answer."""
    nc = len(states)
    E = EXTENDED
    Hl = np.asarray(Hc, E)
    u, r, lam = u.copy(), r.copy(), lam.copy()
    Fl, gl, fl = np.asarray(F, E), np.asarray(gap, E), np.asarray(flex, E)
    free, kappa = b["free"], b["kappa"]
    nf, m = free.size, 3 * nc
    slips = [c for c in range(nc) if states[c] == "slip"]
    at = {c: nf + m + i for i, c in enumerate(slips)}      # λ's column and its row
    n = nf + m + len(slips)
    key = (tuple(states), np.asarray(r, E).tobytes(), np.asarray(lam, E).tobytes())
    # the frame is known by its stiffness matrix itself, held here, so that
    # another frame's matrix cannot take its place at the same address
    factor = _KEPT[key][1] if key in _KEPT and _KEPT[key][0] is b["K"] else None
    last = np.inf
    for it in range(STEPS + 8):
        delta = Hl.T @ u + gl + fl * r
        res = np.zeros(n, E)
        res[:nf] = (stiffness_times(b, u) - Fl - Hl @ r)[free]
        for c in range(nc):
            t = _free_tangents(held[c])
            for k in range(3):
                i, j = nf + 3 * c + k, 3 * c + k
                if _zero(states[c], k, t):
                    res[i] = r[j]
                elif k == 0 or states[c] == "stick":
                    res[i] = kappa * delta[j]
                else:       # slipping: Δ_t + λ X_t = 0, scaled like a length
                    res[i] = kappa * (delta[j] + lam[c] * r[j])
            if states[c] == "slip":
                xt = np.sqrt(sum(r[3 * c + k] ** 2 for k in t))
                if not float(xt) > 0:
                    return None     # at the cone's tip the circle has no direction yet
                res[at[c]] = xt - E(mu[c]) * r[3 * c]
        fresh = factor is None      # a Newton step (else a chord step)
        if fresh:
            factor = _factor(b, r, lam, Hc, flex, mu, states, held, slips, at, n)
            if factor is None:
                return None
            if it == 0:
                _KEPT.clear()
                _KEPT[key] = (b["K"], factor)
        lu, dr, dc = factor
        d = dc * lu.solve(-dr * np.asarray(res, float))
        if not np.all(np.isfinite(d)):
            return None
        u[free] += np.asarray(d[:nf], E)
        r += np.asarray(d[nf:nf + m], E)
        for c in slips:
            lam[c] += E(d[at[c]])
        step = float(np.abs(d[:nf]).max(initial=0.0))
        size = max(float(np.abs(u).max(initial=0.0)), 1e-300)
        if step <= 1e-18 * size:
            return u, r, lam
        if step > 0.25 * last and step > 1e-12 * size:
            if fresh and it >= 4 and step > 0.5 * last:
                return None         # not settling on a fresh matrix
            factor = None           # the chord no longer contracts: refactor
        last = step
    return u, r, lam


#: the last starting factorization: {(states, r, λ): (K, (lu, dr, dc))}
_KEPT: dict = {}


def _zero(state, k, t) -> bool:
    """Whether component k (0 normal, 1, 2 tangents) of a contact in
    ``state`` is zero: separated, or a tangent held or of a frictionless
    closed contact."""
    return state == "separated" or (k > 0 and (k not in t or state == "closed"))


def _factor(b, r, lam, Hc, flex, mu, states, held, slips, at, n):
    """(LU, row scales, column scales) of the states' Newton matrix at
    (r, λ) — None where it is singular."""
    free, kappa = b["free"], b["kappa"]
    nf, nc = free.size, len(states)
    top_rows, top_cols, top_vals, Hf = _frame_block(b, Hc)
    rows, cols, vals = [], [], []

    def put(i, j, v):
        rows.append(i), cols.append(j), vals.append(v)

    def kinematic(i, j, factor):
        """Row i holds factor × Δ_j's derivative."""
        lo, hi = Hf.indptr[j], Hf.indptr[j + 1]
        for d, h in zip(Hf.indices[lo:hi], Hf.data[lo:hi]):
            put(i, d, factor * h)
        put(i, nf + j, factor * float(flex[j]))

    for c in range(nc):
        t = _free_tangents(held[c])
        for k in range(3):
            i, j = nf + 3 * c + k, 3 * c + k
            if _zero(states[c], k, t):
                put(i, nf + j, 1.0)
            elif k == 0 or states[c] == "stick":
                kinematic(i, j, kappa)
            else:
                kinematic(i, j, kappa)
                put(i, nf + j, kappa * float(lam[c]))
                put(i, at[c], kappa * float(r[j]))
        if states[c] == "slip":
            xt = float(np.sqrt(sum(r[3 * c + k] ** 2 for k in t)))
            put(at[c], nf + 3 * c, -float(mu[c]))
            for k in t:
                put(at[c], nf + 3 * c + k, float(r[3 * c + k]) / xt)
    # one construction (repeated entries summed), then equilibrated in
    # place — rows, then columns, by their largest entries: a deck's
    # stiffness 1e13 beside the slip law's unit entries
    A = sp.csr_matrix((np.concatenate([top_vals, vals]),
                       (np.concatenate([top_rows, rows]).astype(np.int64),
                        np.concatenate([top_cols, cols]).astype(np.int64))), shape=(n, n))
    row_of = np.repeat(np.arange(n), np.diff(A.indptr))
    big = np.zeros(n)
    np.maximum.at(big, row_of, np.abs(A.data))
    dr = 1.0 / np.maximum(big, 1e-300)
    A.data *= dr[row_of]
    big = np.zeros(n)
    np.maximum.at(big, A.indices, np.abs(A.data))
    dc = 1.0 / np.maximum(big, 1e-300)
    A.data *= dc[A.indices]
    try:
        lu = spla.splu(A.tocsc())
    except RuntimeError:
        return None
    piv = np.abs(lu.U.diagonal())
    if not (piv.size and piv.min() > 1e-14 * piv.max()):
        return None
    return lu, dr, dc


#: the last frame's rows of the Newton matrix, [K_ff, −H_f], as (rows,
#: columns, values), H_f by columns, and what they were formed from (its
#: stiffness matrix itself, held, and H_c): {"kept": (...)}
_BLOCKS: dict = {}


def _frame_block(b, Hc):
    """The rows of the Newton matrix that no state changes — the free dofs'
    equilibrium, [K_ff, −H_f] — as COO arrays, and H_f by columns: formed
    once per frame and contact layout."""
    Hc = np.asarray(Hc, float)
    kept = _BLOCKS.get("kept")
    if kept is not None and kept[-2] is b["K"] and np.array_equal(kept[-1], Hc):
        return kept[:4]
    free = b["free"]
    Kff = sp.coo_matrix(b["K"][free][:, free])
    Hf = sp.csc_matrix(Hc[free])
    Hcoo = Hf.tocoo()
    kept = (np.concatenate([Kff.row, Hcoo.row]),
            np.concatenate([Kff.col, Hcoo.col + free.size]),
            np.concatenate([Kff.data, -Hcoo.data]), Hf, b["K"], Hc.copy())
    _BLOCKS["kept"] = kept
    return kept[:4]


def margin(answer, Hc, gap, flex, mu, states, held) -> float:
    """How far the answer (u, r, λ) on ``states`` is from needing another
    state: the least of its :func:`inequalities`, each over its own scale.
    Negative where a state no longer holds: its root in p is where the
    state changes (an event)."""
    checks = inequalities(answer, Hc, gap, flex, mu, states, held)
    return float(min((value / scale for cs in checks for value, scale, _ in cs), default=1.0))
