r"""The raft's contact with tensionless soil or a rigid floor: one convex QP
with lower bounds per combination, solved and certified by ``qpcontact.solve``.

Tensionless Winkler soil
------------------------
The soil under node i is a spring of stiffness k_i = Σ_e k_e A_e / 4 [N/m]
(the modulus of subgrade reaction k_e [N/m³] of each element the node is a
corner of, times a quarter of the element's area: the tributary area) that
pushes and never pulls.  Split the node's deflection w_i [m, downward] into
the soil's compression c_i ≥ 0 and the lift-off gap g_i ≥ 0, w_i = c_i − g_i.
The total potential energy of raft and soil over the free displacements u
and the gaps g is ::

    Π(u, g) = ½ u'K u + ½ Σ_i k_i (w_i + g_i)² − f'u,    g ≥ 0

(K: the plate's stiffness, f: the nodal loads, downward positive).  Its
minimum is the equilibrium: ∂Π/∂g_i = k_i c_i ≥ 0 is the soil's upward
force on node i, complementary to g_i (a node presses on the soil, g_i = 0,
or has lifted, c_i = 0); ∂Π/∂u = 0 is the plate's equilibrium under the loads
and those forces.  It is the mixed QP ::

    min ½ x'Px + c'x,   x = (u, g),   g ≥ 0,
    P = T'KT + S'K_s S,   c = −T'f

(T takes x to the plate's displacements, S to the compressions w + g,
K_s = diag(k_i)): free displacements and one bound per soil node, nothing
condensed — the form the exact method ``"ip-bpp"`` takes (an LCP on the soil
nodes alone would be dense: the Schur complement of the raft).

The rigid floor (k → ∞): the node cannot go down, w_i = −g_i ≤ 0; the same
QP with w_i replaced by −g_i and no spring; the bound's multiplier
∂Π/∂g_i = (f − Ku)_{w_i} is the floor's upward reaction.

Newton's method first
---------------------
Where "auto" is asked, the gaps are minimised out — Π(u) = ½ u'Ku − f'u +
½ Σ k_i max(w_i, 0)², convex and C¹, with w_i ≤ 0 at floor nodes — and
Newton's method on it (:mod:`.newton`: the nodes that press as an active
set, one sparse LDLᵀ of the raft on their springs and floor supports per
step) answers in a few steps; its x = (u, g = max(−w, 0)) is certified on this
QP like every other answer.  Where it does not end, or its answer is not
certified, the pinned QP below answers; a named method always takes the
pinned QP.

Why nodes are pinned first
--------------------------
A raft held by nothing but the soil can lift off as a rigid body: u = r
(w = a + b x + c y, θ = (b, c)) with g = −w keeps every compression at zero
and costs no energy, so P is only semidefinite.  That is the physics (no
choice of unknowns that lets the whole raft lift is definite), and the exact
methods refuse a singular P.  But the minimum is unique as soon as three
non-collinear nodes stay in contact, and a node in contact has g_i = 0.  So
nodes are **pinned** — their gap removed from the unknowns, g_i = 0 — which
makes P definite (the rigid motions vanishing at three non-collinear points
are zero).  First every node the bilateral solution (every spring pulling
too) presses is pinned: the LCP keeps only the others, a small one.  Where
the answer pulls on pins, they are released (all at once: a released node
is an unknown of the next LCP, free to press again) and the QP solved
again, at most ``MAX_ROUNDS`` times; if that runs out, or leaves a rigid
motion free, three pins are chosen where the bilateral solution presses
hardest, apart from each other, a pin in tension replaced by the node the
last answer presses hardest.  When every pin's force comes out ≥ 0, the
answer satisfies the unpinned problem's optimality conditions exactly (the
bound g_i ≥ 0 holds with multiplier ≥ 0), which :func:`qpcontact.certify`
then checks on the unpinned QP from its data; ``ok`` needs that and the
pinned solve's certificate.  Nothing is pinned where bilateral supports
already fix the rigid motions and no node presses.

How the pinned QP is solved
---------------------------
Condensed onto its gaps (at most ``CONDENSE_MAX``): one sparse LDLᵀ of P
with the gaps ordered last gives the Schur complement S as its trailing
block, and the dense LCP g ≥ 0, S g + q_S ≥ 0 (S symmetric positive
definite) goes to ``qpcontact.solve``; with no gap left, one linear solve;
above ``CONDENSE_MAX`` the mixed QP goes to "auto" whole.  (The condensed
LCP was chosen while "ip-bpp"'s condensed branch returned wrong answers on
these QPs, which the certificate rejected; that branch is mended —
docs/dev-notes.md, "ip-bpp: the condensed branch's refinement" — and which
route is faster on rafts was not measured again.)

A raft on supports that all push, whose loads push it up or tip it over the
edge of its footprint, has no equilibrium (statics: the loads' resultant
must be downward and inside the convex hull of the supported nodes); that
is refused before any solve, with the reason — for each part of the raft
an opening cuts off, which stands or falls alone (:mod:`.statics`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from qpcontact.core.accuracy import resolve_accuracy
from qpcontact.core.errors import InvalidProblemError

from .newton import solve_supports
from .statics import check_statics

__all__ = ["ContactQP", "ContactAnswer", "solve_contact", "rigid_motions"]

#: rounds of releasing the pressed nodes' pins the answer pulls on, at most
MAX_ROUNDS = 25
#: three pins released and re-chosen at most this many times
MAX_REPINS = 8
#: up to this many gaps the QP is condensed onto them (a dense SPD LCP,
#: n² memory: 128 MB at 4000); above it the mixed QP goes to "auto" whole
CONDENSE_MAX = 4000


def _solve_condensed(problem, method, accuracy, time_limit):
    """The pinned QP through its Schur complement on the gaps: the dense SPD
    LCP  z = g >= 0,  w = S g + q_S >= 0,  z'w = 0  with
    S = P_BB − P_BU P_UU⁻¹ P_UB and q_S = c_B − P_BU P_UU⁻¹ c_U (w: the
    supports' forces), solved by ``qpcontact.solve``; then the displacements
    u = P_UU⁻¹ (−c_U − P_UB g).  Returns (the LCP's solution, x)."""
    import qpcontact
    import scipy.sparse.linalg as spla
    from qpcontact.core.problems import LCP

    P, c, lb = problem.P.tocsc(), problem.q, problem.lb
    B = np.flatnonzero(np.isfinite(lb))
    U = np.flatnonzero(~np.isfinite(lb))
    # one sparse LDLᵀ of P with the gaps ordered last: its trailing block is S
    # (P = LU with U = DLᵀ; S = P_BB − L_BU U_UB = L_BB U_BB), no solves with
    # m right-hand sides; diagonal pivots in a fixed order (SPD: Sylvester)
    opts = {"SymmetricMode": True}
    try:
        lu_U = spla.splu(P[U][:, U].tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                         options=opts)
        order = np.concatenate([U[np.argsort(lu_U.perm_c)], B])
        lu = spla.splu(P[order][:, order].tocsc(), permc_spec="NATURAL", diag_pivot_thresh=0.0,
                       options=opts)
    except RuntimeError:                # exactly singular
        raise InvalidProblemError("the raft's pinned stiffness is singular: its supports leave "
                                  "a rigid motion free") from None
    k = U.size
    if not (np.array_equal(lu.perm_r, np.arange(c.size))
            and np.array_equal(lu.perm_c, np.arange(c.size)) and np.all(lu.U.diagonal() > 0)):
        raise InvalidProblemError("the raft's pinned stiffness is not positive definite: its "
                                  "supports leave a rigid motion free")
    # multiplied dense: the trailing block fills in (a sparse product took half the time)
    S = lu.L.tocsc()[k:, k:].toarray() @ lu.U.tocsc()[k:, k:].toarray()
    S = 0.5 * (S + S.T)
    q = c[B] - P[B][:, U] @ lu_U.solve(c[U])       # q_S = c_B − P_BU P_UU⁻¹ c_U
    lcp = LCP(S, q)
    lcp.structure.declare_spd()       # a Schur complement of a positive definite P
    # "auto" would start with "energy" on a dense LCP: one principal pivot
    # per gap that lifts (a 40 x 40 raft's LCPs of 328-533 gaps: 0.12-0.29 s,
    # block pivoting 0.03-0.04 s in 1-3 exchanges, the same answers), so
    # block pivoting first; "auto" still answers if its answer is not certified
    first = "bpp" if method == "auto" else method
    sol = qpcontact.solve(lcp, method=first, accuracy=accuracy, time_limit=time_limit)
    if first != method and not sol.ok:
        sol = qpcontact.solve(lcp, method=method, accuracy=accuracy, time_limit=time_limit)
    if sol.z is None:
        return sol, None
    # the displacements for those gaps: P_UU x_U = −c_U − P_UB x_B
    x = np.zeros(c.size)
    x[B] = np.maximum(sol.z, 0.0)
    x[U] = lu_U.solve(-c[U] - P[U][:, B] @ x[B])
    return sol, x


def rigid_motions(nodes: np.ndarray) -> np.ndarray:
    """(3n, 3): the rigid motions of a flat plate, w = a + b x + c y, θ = (b, c)."""
    n = nodes.shape[0]
    R = np.zeros((3 * n, 3))
    R[0::3, 0] = 1.0
    R[0::3, 1] = nodes[:, 0]
    R[0::3, 2] = nodes[:, 1]
    R[1::3, 1] = 1.0
    R[2::3, 2] = 1.0
    return R


class ContactQP:
    """The QP of the module docstring for one raft, reused by every
    combination (only c changes): ``ks`` per node (0: no soil, inf: the rigid
    floor), ``fixed`` the bilaterally fixed dofs."""

    def __init__(self, K: sp.csr_matrix, ks: np.ndarray, fixed: np.ndarray):
        n = K.shape[0]
        ks = np.asarray(ks, dtype=float)
        fixed_mask = np.zeros(n, bool)
        fixed_mask[np.asarray(fixed, dtype=np.int64)] = True
        w_fixed = fixed_mask[0::3]
        self.soil = np.flatnonzero((ks > 0) & np.isfinite(ks) & ~w_fixed)
        self.floor = np.flatnonzero(np.isinf(ks) & ~w_fixed)
        on_floor = np.zeros(n, bool)
        on_floor[3 * self.floor] = True
        self.free = np.flatnonzero(~fixed_mask & ~on_floor)
        self.fixed = np.flatnonzero(fixed_mask)
        nf, ns, nr = self.free.size, self.soil.size, self.floor.size
        self.nx = nf + ns + nr
        if self.nx == 0:
            raise InvalidProblemError("the raft has no unknown: every dof is fixed")
        T = sp.csr_matrix((np.concatenate([np.ones(nf), -np.ones(nr)]),
                           (np.concatenate([self.free, 3 * self.floor]),
                            np.concatenate([np.arange(nf), nf + ns + np.arange(nr)]))),
                          shape=(n, self.nx))
        pos = np.full(n, -1)
        pos[self.free] = np.arange(nf)
        S = sp.csr_matrix((np.ones(2 * ns), (np.tile(np.arange(ns), 2),
                                             np.concatenate([pos[3 * self.soil], nf + np.arange(ns)]))),
                          shape=(ns, self.nx))
        self.T, self.S, self.K, self.ks = T, S.tocsr(), K, ks
        P = T.T @ K @ T + S.T @ sp.diags(ks[self.soil]) @ S
        self.P = ((P + P.T) * 0.5).tocsc()
        self.lb = np.concatenate([np.full(nf, -np.inf), np.zeros(ns + nr)])
        #: the supported nodes in the order of the gaps in x
        self.supported = np.concatenate([self.soil, self.floor])
        #: K and its LDLᵀ for Newton's method (:mod:`.newton`), made on first
        #: use and kept for every combination
        self.newton = None

    def c(self, f):
        return -(self.T.T @ f)

    def problem(self, f, pinned=()):
        """The qpsolvers.Problem for nodal loads f, with the gaps of the
        ``pinned`` nodes removed (their positions in ``supported``)."""
        from qpsolvers import Problem

        keep = self.kept(pinned)
        return Problem(self.P[keep][:, keep].tocsc(), self.c(f)[keep], lb=self.lb[keep])

    def kept(self, pinned):
        keep = np.ones(self.nx, bool)
        keep[self.free.size + np.asarray(pinned, dtype=np.int64)] = False
        return keep

    def gaps(self, x):
        return x[self.free.size:]

    def support_forces(self, x, f) -> np.ndarray:
        """The upward force of the soil or floor on every node [N]: k_i (w_i +
        g_i) on the springs, (f − K u) on w at a floor node; 0 elsewhere."""
        out = np.zeros(self.K.shape[0] // 3)
        out[self.soil] = self.ks[self.soil] * (self.S @ x)
        if self.floor.size:
            out[self.floor] = (f - self.K @ (self.T @ x))[3 * self.floor]
        return out

    def unrestrained(self, nodes) -> np.ndarray:
        """A basis (3, k) of the rigid motions (a, b, c) the bilateral
        supports leave free."""
        R = rigid_motions(nodes)[self.fixed]
        if R.shape[0] == 0:
            return np.eye(3)
        _, s, vt = np.linalg.svd(R)
        rank = int(np.sum(s > 1e-9 * max(1.0, s[0])))
        return vt[rank:].T


@dataclass
class ContactAnswer:
    """x of the unpinned QP, its certificate, the solve's record."""

    x: np.ndarray
    ok: bool
    status: str
    message: str
    method: str
    pinned: list = field(default_factory=list)
    error: float = float("inf")
    wall_time: float = 0.0
    repins: int = 0


def _choose_pins(qp, nodes, forces, count, exclude=()):
    """``count`` supported nodes (positions in ``qp.supported``) pressed hardest,
    apart: each new one at least a tenth of the footprint's size from the
    line (or point) of those taken."""
    order = [k for k in np.argsort(-forces[qp.supported], kind="stable") if k not in exclude
             and forces[qp.supported[k]] > 0]
    pts = nodes[qp.supported]
    size = float(np.ptp(pts, axis=0).max()) if pts.shape[0] > 1 else 1.0
    for frac in (0.1, 0.03, 0.0):
        taken = []
        for k in order:
            p = pts[k]
            if len(taken) == 0:
                taken.append(k)
            elif len(taken) == 1:
                if np.hypot(*(p - pts[taken[0]])) > frac * size:
                    taken.append(k)
            else:
                a, b = pts[taken[0]], pts[taken[1]]
                d = b - a
                dist = abs(d[0] * (p - a)[1] - d[1] * (p - a)[0]) / np.hypot(*d)
                if dist > frac * size:
                    taken.append(k)
            if len(taken) == count:
                return taken
    return None


def _bilateral_forces(qp, f):
    """The supports' forces when every gap is closed (the soil pulls too):
    one sparse solve with the displacements alone; None where that system is
    singular (the raft's supports lie on a line)."""
    import scipy.sparse.linalg as spla

    nf = qp.free.size
    try:
        lu = spla.splu(qp.P[:nf][:, :nf].tocsc())
    except RuntimeError:
        return None
    x0 = np.zeros(qp.nx)
    x0[:nf] = lu.solve(-qp.c(f)[:nf])
    return qp.support_forces(x0, f) if np.all(np.isfinite(x0)) else None


def _linear(qp, f, accuracy, start):
    """Bilateral supports only: one linear solve, certified as a QP."""
    import time

    import qpcontact
    import scipy.sparse.linalg as spla
    from qpsolvers import Problem

    problem = Problem(qp.P, qp.c(f))
    try:
        x = spla.splu(problem.P.tocsc()).solve(-problem.q)
    except RuntimeError:                # exactly singular
        raise InvalidProblemError("the plate has no soil and its supports leave a rigid motion "
                                  "free: add soil, a floor or supports") from None
    cert = qpcontact.certify(problem, x)
    tol = resolve_accuracy(accuracy)[1]      # what qpcontact.solve's certificate must meet
    ok = bool(cert.ok(tol))
    message = (f"certified: error {cert.error:.2e} (no contact: the linear system)" if ok else
               f"not certified: error {cert.error:.2e}, but no digit is guaranteed (the "
               "supports leave the plate singular or nearly so)")
    return ContactAnswer(x, ok, "solved" if ok else "inaccurate", message, "splu", [],
                         float(cert.error), time.perf_counter() - start)


class _NoGap:
    """What a solve returns when every gap is pinned: the displacements come
    from one linear solve and only the unpinned QP's certificate judges."""

    ok, status, method = True, "solved", "splu"
    message = "every supported node pinned: one linear solve"

    def __init__(self, tol):
        self.tol = tol


def _solve_pinned(qp, f, pinned, method, accuracy, time_limit):
    """(solution, x of the unpinned QP or None) with the ``pinned`` gaps held at 0."""
    import qpcontact

    problem = qp.problem(f, pinned)
    gaps = qp.supported.size - len(pinned)
    if gaps == 0:
        import scipy.sparse.linalg as spla

        sol = _NoGap(resolve_accuracy(accuracy)[1])
        try:
            x = spla.splu(problem.P.tocsc()).solve(-problem.q)
        except RuntimeError:            # exactly singular
            raise InvalidProblemError("the raft's pinned stiffness is singular") from None
    elif gaps <= CONDENSE_MAX:
        sol, x = _solve_condensed(problem, method, accuracy, time_limit)
    else:
        sol = qpcontact.solve(problem, method=method, accuracy=accuracy, time_limit=time_limit)
        x = sol.x
    if x is None:
        return sol, None
    x_full = np.zeros(qp.nx)
    x_full[qp.kept(pinned)] = x
    return sol, x_full


def solve_contact(qp: ContactQP, nodes, f, method="auto", accuracy="default",
                  time_limit=None, guess=None) -> ContactAnswer:
    """Solve one combination's QP (module docstring): Newton's method
    (``guess(deadline)``: its first step's states or None, called once
    statics has passed — :func:`.newton.start_from`), else
    pin, solve, release the pins the answer pulls on; certify on the
    unpinned QP."""
    import time

    import qpcontact
    from qpcontact.core.deadline import Deadline

    start = time.perf_counter()
    # one clock for every part, compiling left out as in every time limit
    deadline = Deadline(None if time_limit is None else float(time_limit))
    need = qp.unrestrained(nodes).shape[1]
    if qp.supported.size == 0:
        if need:
            raise InvalidProblemError("the plate has no soil and its supports leave a rigid "
                                      "motion free: add soil, a floor or supports")
        return _linear(qp, f, accuracy, start)
    # each part of the raft that only rests on its supports: statics decides first
    check_statics(qp.K, qp.supported, qp.fixed, nodes, f)
    tol = resolve_accuracy(accuracy)[1]      # what qpcontact.solve's certificate must meet
    if method == "auto":
        # Newton's method on the energy (:mod:`.newton`): a few LDLᵀ of the
        # raft on its pressing nodes; where it does not end, or its answer is
        # not certified, the pinned QP below answers
        first = None if guess is None else guess(deadline)
        found = solve_supports(qp, nodes, f, deadline, first)
        how = "" if first is None else ", started from a coarser grid's answer"
        if found is None and first is not None:      # the guess misled it: from every node
            found, how = solve_supports(qp, nodes, f, deadline), ""
        if found is not None:
            x_full, steps = found
            cert = _unpinned_certificate(qp, f, x_full)
            if cert.ok(tol):
                return ContactAnswer(
                    x_full, True, "solved",
                    f"certified: error {cert.error:.2e} <= {tol:.0e} on the unpinned QP (active "
                    f"set: Newton's method on the energy, {steps} steps on the raft's "
                    f"pressing nodes{how})", "active-set", [], float(cert.error),
                    time.perf_counter() - start)
        if time_limit is not None:
            time_limit = deadline.left()
            if time_limit <= 0.0:
                return ContactAnswer(np.full(qp.nx, np.nan), False, "time_limit",
                                     "not solved: the time limit ran out in Newton's method, "
                                     "before the pinned QP could answer", "active-set", [],
                                     wall_time=time.perf_counter() - start)
    forces = _bilateral_forces(qp, f)
    if forces is None:                   # singular: the loads themselves rank the nodes
        forces = np.zeros(nodes.shape[0])
        forces[qp.supported] = f[0::3][qp.supported]
    # first every node the bilateral answer presses (the LCP keeps the others);
    # where that runs out of rounds or leaves a rigid motion free, three pins
    pressed = [k for k in range(qp.supported.size) if forces[qp.supported[k]] > 0]
    plans = [("pressed", pressed, MAX_ROUNDS)] if pressed else []
    released, rounds, sol, x_full, pinned = [], 0, None, None, []
    why = ""
    while plans or x_full is None:
        if not plans:
            three = _choose_pins(qp, nodes, forces, need) if need else []
            if three is None:
                raise InvalidProblemError(
                    "no three supported nodes off one line carry load in the bilateral "
                    "solution; the raft's supported area is a line — give it soil over an area")
            plans = [("three", three, MAX_REPINS)]
        plan, pinned, budget = plans.pop(0)
        released = []
        for _ in range(budget + 1):
            rounds += 1
            try:
                sol, x_full = _solve_pinned(qp, f, pinned, method, accuracy, time_limit)
            except InvalidProblemError:   # the pins leave a rigid motion free
                sol, x_full = None, None
                why = ("pinning the pressed nodes leaves a rigid motion free: the loads may "
                       "have no equilibrium on these supports (or they touch along a line)")
                break
            if x_full is None:
                break
            now = qp.support_forces(x_full, f)
            scale = float(np.abs(now).max()) or 1.0
            tension = [k for k in pinned if now[qp.supported[k]] < -1e-12 * scale]
            if not tension or not sol.ok:
                plans = []
                break
            released += tension
            if plan == "pressed":        # release them all; the LCP takes them
                gone = set(tension)
                pinned = [k for k in pinned if k not in gone]
            else:
                keep = [k for k in pinned if k not in tension]
                pinned = _choose_pins_with(qp, nodes, now, keep, need, released)
                if pinned is None:
                    plans = []
                    break
        else:
            x_full = None                # out of rounds: the next plan
            why = f"a pinned node still pulled on its support after {rounds} solves"
        if x_full is None and not plans and plan == "three":
            break
    wall = time.perf_counter() - start
    if x_full is None or sol is None:
        failed = sol is None or sol.ok            # the pins failed, not the solver
        return ContactAnswer(np.full(qp.nx, np.nan), False, "failed" if failed else sol.status,
                             f"not solved: {why}" if failed else sol.message,
                             sol.method if sol else "", list(pinned or []), wall_time=wall,
                             repins=len(released))
    cert = _unpinned_certificate(qp, f, x_full)
    tol = sol.tol
    ok = bool(sol.ok and cert.ok(tol))
    if ok:
        message = (f"certified: error {cert.error:.2e} <= {tol:.0e} on the unpinned QP "
                   f"({sol.method}; {len(pinned)} of {qp.supported.size} supported nodes pinned, "
                   f"every one in compression; {rounds} solve(s))")
        status = "solved"
    elif sol.ok:
        status = "inaccurate"
        message = (f"not certified: the pinned QP was solved ({sol.message}) but on the unpinned "
                   f"QP {_why_not(qp, cert, tol)}")
    else:
        status, message = sol.status, sol.message
    return ContactAnswer(x_full, ok, status, message, sol.method, list(pinned),
                         float(cert.error), wall, len(released))


def _why_not(qp, cert, tol) -> str:
    """Why the unpinned QP's certificate refuses an answer: its error, or —
    where the error meets ``tol`` — the doubt rule's (the normwise error
    beyond the tolerance).  On a raft that
    only rests on its supports statics has already found an equilibrium
    (:func:`.statics.check_statics`), so the doubt is not that none exists: a plate far
    stiffer than its soil moves nearly rigidly, K u is a sum of terms that
    cancel, and rounding of that sum hides whether the forces balance
    (a 4 m strip with D/(k B⁴) = 2.6e3 loaded 1.93 m off centre, 2.9 times
    the kern: componentwise error 1e-16 to 3e-10, normwise 2e-6 to 9e-5).
    Stiff rafts of concrete are far from it: D/(k B⁴) = 78 certified to
    1e-16 at the same eccentricity."""
    if cert.error > tol:
        return f"the error is {cert.error:.2e} > {tol:.0e}"
    if qp.fixed.size == 0:
        return (f"its residuals are small only against terms that cancel (componentwise error "
                f"{cert.error:.1e}, normwise {cert.normwise_error:.1e} > {tol:.0e}): the plate "
                "is so stiff against its soil that it moves nearly rigidly, and rounding of K u "
                "hides whether the forces balance. Statics puts the loads' resultant inside the "
                "footprint, so an equilibrium exists, but this answer's digits are not "
                "guaranteed: take the rigid raft's statics, or a plate 10 to 100 times softer "
                "that is still rigid against the soil")
    return (f"its residuals are small only against terms that cancel (componentwise error "
            f"{cert.error:.1e}, normwise {cert.normwise_error:.1e} > {tol:.0e}): no digit of it "
            "is guaranteed, and the loads may have no equilibrium on these supports")


def _unpinned_certificate(qp, f, x_full):
    """The certificate of x on the unpinned QP, the bound multipliers read
    from its gradient (the supports' forces)."""
    import qpcontact

    full = qp.problem(f)
    grad = qp.P @ x_full + full.q
    z_box = np.zeros(qp.nx)
    z_box[qp.free.size:] = -grad[qp.free.size:]
    return qpcontact.certify(full, x_full, z_box=z_box)


def _choose_pins_with(qp, nodes, forces, keep, need, released):
    """Fill ``keep`` up to ``need`` pins from the nodes ``forces`` press
    hardest, never one released before."""
    f2 = forces.copy()
    for k in keep:                      # the kept ones first, in their order
        f2[qp.supported[k]] = np.inf
    chosen = _choose_pins(qp, nodes, np.where(np.isinf(f2), 1e300, f2), need,
                          exclude=set(released))
    return chosen
