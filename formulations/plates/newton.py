r"""A raft on tensionless soil or a rigid floor by Newton's method on its
energy: the supported nodes that press as an active set, one sparse LDLᵀ
per step.

The energy over the displacements alone
----------------------------------------
With w_i [m, downward] the deflection of supported node i, k_i [N/m] a soil
node's spring (modulus of subgrade reaction times tributary area,
:mod:`.contact`), K the plate's stiffness on the dofs no bilateral support
holds and f the nodal loads [N], the soil pushes with k_i max(w_i, 0) and
never pulls, and a floor node cannot go down (w_i ≤ 0).  The total
potential energy ::

    Π(u) = ½ u'K u − f'u + ½ Σ_soil k_i max(w_i, 0)²,    w_i ≤ 0 on the floor

[N m] is :mod:`.contact`'s QP with its gaps minimised out (g_i = max(−w_i,
0)): convex, continuously differentiable on the soil, its gradient
K u − f + Σ k_i max(w_i, 0) e_i piecewise linear.  Its minimiser is the
equilibrium, with the floor's upward reactions λ_i ≥ 0 as the bounds'
multipliers: K u − f + Σ_soil k_i max(w_i, 0) e_i + Σ_floor λ_i e_i = 0,
λ_i w_i = 0.

Newton's step
-------------
On the set A of pressing nodes (soil: w_i > 0; floor: held at w_i = 0) the
generalised Hessian is K plus the springs of A's soil nodes with A's floor
nodes held: the raft on springs and supports at the pressing nodes only.
A step lands on the minimiser of that quadratic, so the iteration is:
solve it, read each node's state off the answer — a soil node presses
where w_i > 0; a held floor node lets go where its reaction λ_i = (f − K u −
soil forces)_i pulls (λ_i < 0), a free one is caught where it goes below
the floor (w_i > 0) — and repeat until no state changes: the primal–dual
active-set method, and what engineers do by hand with compression-only
springs.  When no state changes, every soil node on its spring is pushed,
every lifted one off the soil, every held floor node pushed up and every
free one above the floor, up to rounding: the optimality conditions, which
:mod:`.contact` checks again on the QP from its data before anything is
called solved.

On soil every step's matrix has one pattern, K's, whose diagonal the
springs change, so one fill-reducing order serves every step and every
combination of the raft: from ``SUPERNODAL_DOFS`` on, nested dissection
of the mesh (:mod:`.ordering`), each step a supernodal LDLᵀ in that order
(SuperLU); below it qdldl's AMD, each step a numeric refactorisation on
qdldl's kept analysis.  Where a step's springs differ from the last
factorised ones at few nodes, it is that factorisation with the changed
springs as a border; with floor nodes held, a step factors the block of
the dofs that are not held (w_i = 0 exactly) — or, where it differs from
the last such block at few dofs (floor nodes released or caught, springs
changed), borders that block's LDLᵀ (:mod:`.border`: a floor raft's
contact line creeps a row of nodes a step, so most of its steps are
borders).  (Until 2026-12-06 every
step was qdldl's: 2.5–3.0 s against 0.66 s at 1e5 dofs, and not done in
minutes at 1e6; docs/dev-notes.md, "The 10⁶-dof raft".)  Started
from every node pressing, rafts whose windward strip or corner lifts took
2–11 steps at 1 300–26 000 dofs (docs/plates.md).

Not guaranteed to end: a node on the verge can flip back and forth, and a
step whose pressing nodes leave a rigid motion free is singular.  A set seen
before, a step limit, a zero pivot or a step that is not finite returns None,
and the pinned QP of :mod:`.contact` answers instead.  A node changes state
only beyond rounding on the other side (``FLIP`` of the largest |w| or
|λ|), so a node on the verge keeps its state.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .border import BORDER_RCOND, FactoredBlock
from .ordering import dof_order

#: a node changes state only beyond this fraction of the largest |w| (or
#: floor reaction) on the other side: rounding of the solve, not a lift
FLIP = 1e-13
#: Newton steps before the pinned QP answers
MAX_STEPS = 60
#: a step whose springs differ from the last factorised ones at up to this
#: many nodes is solved by that LDLᵀ and a border (chosen when a solve cost
#: 1/35 of a factorisation and a border of m nodes m + 2 solves; in the
#: nested-dissection order a solve costs 1/20–1/40, but the border's m
#: columns are one solve with m right-hand sides, 11–21 solves' time for 32);
#: its matrix with a condition number above 1/:data:`.border.BORDER_RCOND`
#: sends the step to a refactorisation, as the floor's border does
BORDER_MAX = 32
#: a floor node whose coarser twin lifts it by less than this fraction of the
#: twin's largest |w| starts held (:func:`start_from`): next to the twin's
#: contact line the plate hovers — lifted by 1e-8 to 5e-5 of the largest |w|
#: on the 115 x 115 floor raft — and the fine line lies up to 1.3 coarse
#: cells into that band; started released there, the first step catches
#: twice the band (the plate sags through it) and the rest creep back a row
#: a step (docs/dev-notes.md)
HOVER = 1e-4
#: from this many dofs on a step is SuperLU in the mesh's nested-dissection
#: order, below it qdldl under its own AMD refactorised on its kept analysis
#: (CPU, one factorisation of the windward raft: 10 092 dofs 34 against
#: 33 ms, a solve 2.0 against 0.9 ms; 19 683 dofs 78 against 95 ms; 100 467
#: dofs 0.66 against 2.5–3.0 s)
SUPERNODAL_DOFS = 15_000


class SupportSystem:
    """K on the dofs no bilateral support holds, with the soil nodes' w
    diagonals located, and the last sparse LDLᵀ of it with springs: from
    ``SUPERNODAL_DOFS`` dofs on SuperLU (supernodal: LU with diagonal
    pivots on a symmetric matrix, U = D Lᵀ) in the mesh's nested-dissection
    order (:mod:`.ordering`, made once per raft from the node coordinates),
    below it qdldl under its own AMD, refactorised numerically on the
    analysis it keeps."""

    def __init__(self, qp, points):
        n = qp.K.shape[0]
        held = np.zeros(n, bool)
        held[qp.fixed] = True
        self.dofs = np.flatnonzero(~held)          # the soil's w are free dofs, the floor's too
        at = np.full(n, -1)
        at[self.dofs] = np.arange(self.dofs.size)
        self.free_at = at[qp.free]                 # the QP's free dofs among these
        self.soil_w, self.floor_w = at[3 * qp.soil], at[3 * qp.floor]
        self.k = qp.ks[qp.soil]
        K = qp.K.tocsc()[self.dofs][:, self.dofs]
        self.K = K                                  # (CSC: K u per step, as fast as CSR)
        self.supernodal = self.dofs.size >= SUPERNODAL_DOFS
        #: the factorised matrix's order: its position p is dof order[p]
        #: (qdldl reads the upper triangle as it is and orders it itself)
        if self.supernodal:
            self.order = dof_order(K, self.dofs // 3, points)
            matrix = K[self.order][:, self.order].tocsc()
        else:
            self.order = np.arange(self.dofs.size)
            matrix = sp.triu(K, format="csc")
        matrix.sort_indices()
        self.rank = np.empty_like(self.order)
        self.rank[self.order] = np.arange(self.order.size)
        cols = np.repeat(np.arange(matrix.shape[1]), np.diff(matrix.indptr))
        diagonal = np.full(matrix.shape[1], -1)
        on = np.flatnonzero(matrix.indices == cols)
        diagonal[cols[on]] = on
        self.soil_diag = diagonal[self.rank[self.soil_w]]     # where the springs go in its data
        if np.any(self.soil_diag < 0):
            raise ValueError("a soil node's w has no diagonal entry in K")
        self.matrix, self.base = matrix, matrix.data.copy()
        self.analysis = None                        # qdldl's, of the whole matrix
        self.solver, self.factored = None, None     # the last whole LDLᵀ, its springs
        self.floor_block = None                     # the last block with floor dofs held

    def factorize(self, soil_pressing, floor_held):
        """u ↦ the solution of (K + the pressing soil nodes' springs) u = rhs
        with the held floor dofs at zero.  Where no floor dof is held: from
        the last LDLᵀ with the springs that changed since as a border
        (:meth:`_bordered`), or a fresh one; where some are, from the last
        LDLᵀ of a block with floor dofs held and what changed since as a
        border (:class:`.border.FactoredBlock`), or an LDLᵀ of the block
        without them.  A zero pivot raises RuntimeError or ValueError
        (SuperLU, qdldl)."""
        if floor_held.any():
            return self._floor_step(soil_pressing, floor_held)
        bordered = self._bordered(soil_pressing)
        if bordered is not None:
            return bordered
        self.solver = None                  # its memory before the next one's
        self.solver = self.factor(soil_pressing, floor_held)
        self.factored = soil_pressing.copy()
        return self.solver

    def _floor_step(self, soil_pressing, floor_held):
        """A step with floor dofs held: on the last such step's LDLᵀ with the
        change as a border, or factorised afresh and kept for the next."""
        springs = np.zeros(self.dofs.size)
        springs[self.soil_w] = np.where(soil_pressing, self.k, 0.0)
        keep = np.ones(self.dofs.size, bool)
        keep[self.floor_w[floor_held]] = False
        if self.floor_block is not None:
            solve = self.floor_block.near(keep, springs)
            if solve is not None:
                return solve
        self.floor_block = None             # its memory before the next one's
        factorisation = self.factor(soil_pressing, floor_held)
        self.floor_block = FactoredBlock(self.K, keep, springs, factorisation,
                                         factorisation.factors)
        return factorisation

    def factor(self, soil_pressing, floor_held):
        """A fresh LDLᵀ of (K + the pressing soil nodes' springs) without
        the held floor dofs, a :class:`Factorisation` (one step's
        factorisation: what ``benchmarks/scale.py`` times as the floor)."""
        import qdldl

        self.matrix.data = self.base.copy()
        self.matrix.data[self.soil_diag] += np.where(soil_pressing, self.k, 0.0)
        matrix, dofs = self.matrix, self.order
        if floor_held.any():
            keep = np.ones(self.dofs.size, bool)
            keep[self.rank[self.floor_w[floor_held]]] = False
            kept = np.flatnonzero(keep)
            matrix, dofs = matrix[kept][:, kept], dofs[kept]
        if self.supernodal:
            return _superlu(matrix, dofs)
        if floor_held.any():        # the block's own AMD (the held rows carry fill it has not)
            return Factorisation(dofs, qdldl=qdldl.Solver(matrix, upper=True))
        if self.analysis is None:
            self.analysis = qdldl.Solver(matrix, upper=True)
        else:
            self.analysis.update(matrix, upper=True)
        return Factorisation(dofs, qdldl=self.analysis)

    def _bordered(self, soil_pressing):
        """The solve for springs that differ from the last factorised ones
        at m ≤ BORDER_MAX nodes, by that LDLᵀ and the border (Sherman–
        Morrison–Woodbury: A + E Δ Eᵀ with Δ = ±k_i at the changed w dofs E;
        Z = A⁻¹E, C = Δ⁻¹ + EᵀZ, u = y − Z C⁻¹ Eᵀy for y = A⁻¹ rhs), with one
        step of refinement on the new matrix's own residual; None where
        more changed or C is ill-conditioned (a spring whose removal leaves
        its node nearly free): the caller refactorises.  A Newton step from
        a coarser twin's guess changes 2–64 nodes on 57–115 cells."""
        if self.solver is None or self.factored is None:
            return None
        changed = np.flatnonzero(soil_pressing != self.factored)
        if changed.size == 0:
            return self.solver
        if changed.size > BORDER_MAX:
            return None
        at = self.soil_w[changed]
        delta = np.where(soil_pressing[changed], self.k[changed], -self.k[changed])
        E = np.zeros((self.dofs.size, changed.size))
        E[at, np.arange(changed.size)] = 1.0
        Z = self.solver(E)                          # one solve with m right-hand sides
        C = np.diag(1.0 / delta) + Z[at]
        if np.linalg.cond(C) > 1.0 / BORDER_RCOND:
            return None
        springs = np.zeros(self.dofs.size)
        springs[self.soil_w] = np.where(soil_pressing, self.k, 0.0)

        def once(rhs):
            y = self.solver(rhs)
            return y - Z @ np.linalg.solve(C, y[at])

        def solve(rhs):
            u = once(rhs)
            return u + once(rhs - (self.K @ u + springs * u))

        return solve


class Factorisation:
    """One LDLᵀ of a step's matrix on ``dofs`` (its rows and columns, in
    the matrix's order) as a solve, rhs ↦ u zero outside ``dofs`` (rhs
    (n,) or (n, m)), and the factor itself, for a border built on it:

    * ``lu``: SuperLU's, in the order ``dofs`` (``NATURAL``: no order of
      its own), diagonal pivots in symmetric mode — ``perm_r`` and
      ``perm_c`` the identity (checked: anything else raises as a zero
      pivot does), ``lu.L`` unit lower triangular, ``lu.U`` = D Lᵀ with
      D = diag(``lu.U``); or
    * ``qdldl``: qdldl's Solver of the matrix on ``dofs`` in that order
      (``factors()``: its L, d and its own AMD order p; below
      ``SUPERNODAL_DOFS``; the kept analysis is refactorised in place by
      the next step's update)."""

    def __init__(self, dofs, lu=None, qdldl=None, matrix=None):
        self.dofs, self.lu, self.qdldl = dofs, lu, qdldl
        #: SuperLU's factorised matrix (its pattern: the elimination tree)
        self.matrix = matrix

    def __call__(self, rhs):
        rhs = np.asarray(rhs, float)
        u = np.zeros(rhs.shape)
        part = rhs[self.dofs]
        if self.lu is not None:                 # m columns: one solve
            u[self.dofs] = self.lu.solve(part)
        elif part.ndim == 1:
            u[self.dofs] = self.qdldl.solve(part)
        else:                                   # qdldl solves one column at a time
            u[self.dofs] = np.column_stack([self.qdldl.solve(np.ascontiguousarray(c))
                                            for c in part.T])
        return u

    def factors(self):
        """(L, d, p, parent) for a border (:class:`.border.FactoredBlock`):
        L lower (CSC) and d with the matrix in the order p (p[i] the dof at
        position i) = (I + L) diag(d) (I + L)'.  SuperLU's ``lu.L`` as it
        is (its unit diagonal stored: the border passes over it) and the
        elimination tree of the factorised matrix itself — L − I and L's
        transpose for the tree were two copies of L that cost 0.15 s beside
        a 0.12 s factorisation at 40 368 dofs; qdldl's strictly lower L,
        its tree read off L by the border."""
        if self.lu is not None:
            from ._border_kernels import parents

            tree = None if self.matrix is None else parents(
                self.matrix.indptr, self.matrix.indices, self.dofs.size)
            return self.lu.L, self.lu.U.diagonal(), self.dofs, tree
        L, d, p = self.qdldl.factors()
        return L, d, self.dofs[p], None


def _superlu(ordered, dofs):
    """The :class:`Factorisation` of ``ordered`` (the matrix on ``dofs`` in
    that order) by SuperLU's supernodal LU with diagonal pivots (symmetric
    mode: U = D Lᵀ, an LDLᵀ).  Its ``relax`` and ``panel_size`` are left at
    SuperLU's own: other values were measured 0–25 % faster and corrupted
    the heap twice."""
    import scipy.sparse.linalg as spla

    lu = spla.splu(ordered, permc_spec="NATURAL", diag_pivot_thresh=0.0,
                   options={"SymmetricMode": True})
    identity = np.arange(ordered.shape[0])
    if not (np.array_equal(lu.perm_r, identity) and np.array_equal(lu.perm_c, identity)):
        # a zero diagonal pivot made SuperLU pivot off the diagonal: not an LDLᵀ
        raise RuntimeError("a zero pivot: the matrix is not positive definite")
    return Factorisation(dofs, lu=lu, matrix=ordered)


def solve_supports(qp, nodes, f, deadline=None, guess=None):
    """(x of :mod:`.contact`'s QP — free displacements, then the gaps —,
    Newton steps) for nodal loads f on the raft whose mesh has the node
    coordinates ``nodes`` [m], or None where the iteration does not end
    (module docstring).  ``deadline``: a
    :class:`~qpcontact.core.deadline.Deadline` (or None) past which it gives
    up.  ``guess``: the first step's (pressing soil nodes, held floor nodes)
    — :func:`start_from`, a coarser twin's answer — else every node presses
    first."""
    if qp.newton is None:                   # once per raft: every combination shares it
        qp.newton = SupportSystem(qp, nodes)
    system = qp.newton
    load = np.asarray(f, float)[system.dofs]
    if guess is None:
        soil, floor = np.ones(qp.soil.size, bool), np.ones(qp.floor.size, bool)
    else:
        soil, floor = guess
    seen = set()
    for step in range(1, MAX_STEPS + 1):
        try:
            u = system.factorize(soil, floor)(load)
        except (RuntimeError, ValueError):      # a zero pivot: the pressing nodes leave a
            return None                          # rigid motion free
        if not np.all(np.isfinite(u)):
            return None
        w_soil, w_floor = u[system.soil_w], u[system.floor_w]
        # the floor's reactions: what K u and the springs leave of the load
        spring = np.zeros(u.size)
        spring[system.soil_w] = np.where(soil, system.k * w_soil, 0.0)
        lam = (load - system.K @ u - spring)[system.floor_w]
        w_flip = FLIP * float(np.abs(u[np.concatenate((system.soil_w, system.floor_w))])
                              .max(initial=0.0))
        lam_flip = FLIP * float(np.abs(lam[floor]).max(initial=0.0))
        now_soil = np.where(soil, w_soil > -w_flip, w_soil > w_flip)
        now_floor = np.where(floor, lam > -lam_flip, w_floor > w_flip)
        if np.array_equal(now_soil, soil) and np.array_equal(now_floor, floor):
            x = np.zeros(qp.nx)
            nf, ns = qp.free.size, qp.soil.size
            x[:nf] = u[system.free_at]
            x[nf:nf + ns] = np.where(soil, 0.0, np.maximum(-w_soil, 0.0))
            x[nf + ns:] = np.where(floor, 0.0, np.maximum(-w_floor, 0.0))
            return x, step
        key = now_soil.tobytes() + now_floor.tobytes()
        if key in seen or (deadline is not None and deadline.expired()):
            return None
        seen.add(key)
        soil, floor = now_soil, now_floor
    return None


def start_from(coarse_nodes, coarse_w, qp, nodes):
    """The first step's (pressing soil nodes, held floor nodes) from the
    deflections ``coarse_w`` [m] of the same raft on a coarser grid (nodes
    ``coarse_nodes``): nested iteration.  Where the lift-off line lies is
    mostly a matter of the raft's global shape, which the coarse grid
    resolves; a node presses (or is held) where the coarse deflection,
    interpolated bilinearly in its cell, goes down (or is not up); a node
    in a cell with a corner missing (an opening's edge) presses.  On a
    floor, a coarse lift below HOVER of the largest |w| counts as held: the
    twin's plate hovers there, and the fine contact line lies in that band
    (:data:`HOVER`).  Measured:
    9 and 11 Newton steps from every node pressing, 2 and 3 from the 40 x 40
    twin's answer on 80 x 80 rafts (docs/dev-notes.md)."""
    xs, ys = np.unique(coarse_nodes[:, 0]), np.unique(coarse_nodes[:, 1])
    W = np.full((xs.size, ys.size), np.nan)
    W[np.searchsorted(xs, coarse_nodes[:, 0]), np.searchsorted(ys, coarse_nodes[:, 1])] = coarse_w
    p = nodes[qp.supported]
    i = np.clip(np.searchsorted(xs, p[:, 0]) - 1, 0, xs.size - 2)
    j = np.clip(np.searchsorted(ys, p[:, 1]) - 1, 0, ys.size - 2)
    a = (p[:, 0] - xs[i]) / (xs[i + 1] - xs[i])
    b = (p[:, 1] - ys[j]) / (ys[j + 1] - ys[j])
    w = ((1 - a) * (1 - b) * W[i, j] + a * (1 - b) * W[i + 1, j]
         + a * b * W[i + 1, j + 1] + (1 - a) * b * W[i, j + 1])
    largest = float(np.nanmax(np.abs(coarse_w), initial=0.0))
    soil = ~(w[:qp.soil.size] <= 1e-12 * largest)     # NaN (a corner missing): pressing
    floor = ~(w[qp.soil.size:] < -HOVER * largest)
    return soil, floor
