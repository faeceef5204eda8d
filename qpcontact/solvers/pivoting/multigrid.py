"""Multilevel search for the contact set of LCP(M, q), M sparse SPD: nested
truncated nonsmooth Newton multigrid (TNNMG).

The LCP is the bound-constrained QP min f(z) = ½ z'Mz + q'z, z >= 0.  A
hierarchy of prolongations P_l (given by the mesh, or built here by smoothed
aggregation) gives coarse problems min ½ y'(P'MP)y + (P'q)'y, y >= 0: with
nonnegative P (bilinear interpolation, aggregation smoothed on an M-matrix)
every coarse point is a fine feasible point, so they are the obstacle
problem on coarser grids.  Solved coarsest first, each level's answer
interpolated to the next as its start (nested iteration): the free boundary
then starts within a coarse cell of where it ends, instead of one grid line
per iteration from nothing — what makes plain block pivoting slow on meshes.

On each level, a TNNMG cycle (Gräser & Kornhuber 2009; Gräser, Sack, Sander
2009) is:

1. one projected Gauss–Seidel sweep (the nonsmooth smoother: it alone
   converges, and it puts every component it can at the obstacle);
2. truncation: components at the obstacle (z_i = 0) are frozen;
3. a linear correction c for the frozen-out (truncated) Newton system
   M_TT c_T = −(Mz + q)_T: one V-cycle (a W-cycle on a plate, below) whose
   coarse operators are the Galerkin products of the *truncated*
   prolongations, P'TMTP (kept current: the coarse rows the moved unknowns
   touch are recomputed each cycle);
4. projection onto the feasible set (c_i >= −z_i) and an exact line search
   for the quadratic along c, capped where a component would turn negative;
5. two projected Gauss–Seidel sweeps, forward then backward.

On a plate (M not a Z-matrix) the correction of step 3 is a W-cycle: each
coarser level visited twice.  Bilinear coarse functions with their
transposes as restrictions have the orders 2 + 2 = 4 that a 4th-order
operator needs, and no more (Hemker's rule asks m_P + m_R > 2m for a rate
independent of h; here = 2m): on the 13-point biharmonic the V-cycle with
one Gauss–Seidel sweep each way barely converges by itself, and as the
preconditioner of z_u's conjugate gradients (below) it took 22–30 steps at
n = 1e4 and 52–78 at 1e5.  The W-cycle (on a grid coarsened by 4, about 1.8
V-cycles of work) takes 7–10 at both sizes (with the coarse grids
interpolating in their nodes' true positions: formulations/meshes.py), and
cuts the TNNMG cycles by 17–52 % at 1e4, 51–87 % at 1e5.  On a membrane
(2nd order: 2 + 2 > 2) the V-cycle is as good, and W-cycles there cost
1–19 % for no cycle saved.  Cubic interpolation (orders 4 + 4) cut the
steps too, but its Galerkin operators carry 81–121 entries a row against
25: dearer per cycle than it saved.

The cycle is one compiled call (:func:`._mg_kernels.tnnmg_cycle`, the
hierarchy packed once per solve by :class:`_Levels`); the loop over cycles,
the stop and the progress lines stay in Python.  Every step decreases f,
so the iteration converges whatever the hierarchy; the hierarchy decides
only how fast.  The iterate is a guess: "mg-bpp" hands its contact set to
the exact block-pivoting finish.

References: Hemker, P. W. (1990), On the order of prolongations and
restrictions in multigrid procedures, J. Comput. Appl. Math. 32, 423–429;
Kornhuber, R. (1994), Monotone multigrid methods for elliptic
variational inequalities I, Numer. Math. 69, 167–184; Gräser, C., Kornhuber,
R. (2009), Multigrid methods for obstacle problems, J. Comput. Math. 27,
1–44; Vaněk, P., Mandel, J., Brezina, M. (1996), Algebraic multigrid by
smoothed aggregation, Computing 56, 179–196.
"""

from __future__ import annotations

import functools
import threading

import numpy as np
import scipy.sparse as sp

from ...core.problems import LCP
from .bpp import block_pivoting

__all__ = ["aggregation_hierarchy", "multilevel_guess", "MultilevelSetup", "COARSEST_MAX",
           "settled_flips", "layer_share", "LAYER_SHARE", "LAYER_MIN"]


@functools.cache
def _kernels():
    """The compiled loops (:mod:`._mg_kernels`), imported on first use: numba
    costs 0.3 s to import, and a listing of the methods calls none of them."""
    from . import _mg_kernels

    return _mg_kernels


#: Aggregation stops at this many unknowns (the coarsest level is solved
#: directly, by a dense Cholesky factorization).
COARSEST_MAX = 400

#: A coarsest level above this many unknowns (aggregation stopped early,
#: typically with nothing strong left: a diagonally dominant operator) is
#: smoothed by Gauss–Seidel sweeps (:data:`._mg_kernels.COARSE_SWEEPS`), not
#: factorized: elsewhere a weaker coarse solve, more cycles, the same answer;
#: and the first coarse LCP there goes to sparse block pivoting.
DENSE_COARSEST = 800

#: Stop a level's cycles once its contact set has not changed for
#: this many cycles in a row, whatever the residual: on a plate (a 4th-order
#: operator) the truncated cycles converge slowly once the set is found
#: (n = 1e4, oblique stripes: the set held from cycle 28, the residual stayed
#: near 2e-4 of ‖q‖ to the 500-cycle limit, 2.1 s of a 2.3 s solve), and the
#: exact finish needs only the set.  A set held but wrong in a few
#: components costs the finish a few exchanges, never the answer.
HELD_STOP = 5

#: Up to this many unknowns the finest level stops at its first cycle that
#: leaves the contact set as it was: the finish's first factorization then
#: checks that set, and the four further held cycles are insurance that
#: costs more than what it insures there.  At n = 1e4 a W-cycle on a plate
#: is ~2 ms (four of them ~1.3 factorizations of a D = 0.05 plate's final
#: block), and the first held set was the final one on 41 of 42 plates
#: measured from 38² to 100² (the other: 3 components off, one bordered
#: exchange on the factor, a few of its solves at ~0.3-1 ms each).  At
#: 200² and 316² a held set was off by 1-9 components on 8 of 28 plates and
#: a solve with the factor costs more than a cycle (316², D = 1: 50 ms
#: against 35): the held cycles stay.
FIRST_HOLD_MAX = 20_000

#: On a Z-matrix (a membrane: V-cycles) the finest level ends, at every
#: size, at its first held cycle — or, where at most 1/SETTLED_SHARE of its
#: nodes are free, at its first cycle that flips at most SETTLED components
#: between the free set and the obstacle (``settled``).  On the seven
#: shapes at 100² and 316² a cycle that flipped k components left a set at
#: most k off the final one (every cycle: 0-9 off after the first) — not a
#: bound: on anisotropic membranes and aggregated chains a cycle of 0-4
#: flips left 13-62 off (review 6a; the finish exact all the same, its
#: exchanges 2-24) — and the finish borders those on its factor: a few solves with
#: the factor of a small free block, against a cycle over every node (316²
#: ripple: 14 662 free of 99 856, a cycle ~6 ms, a solve ~0.3 ms).  On a
#: large free block a bordered exchange costs more than the cycle it saves
#: (100² crate, 7 784 free: one exchange for two cycles, +10 %).  A plate's
#: cycles flip a few components while hundreds are still off (it creeps:
#: 316², D = 0.05, terraces: 3 flipped with 116 off), so a plate keeps
#: FIRST_HOLD_MAX and HELD_STOP.
SETTLED = 4
SETTLED_SHARE = 3

#: ... and above SETTLED × SETTLED_SCALE unknowns, at its first cycle that
#: flips at most n / SETTLED_SCALE (:func:`settled_flips`): a cycle costs
#: O(n) and the components such a cycle leaves off stay few (10⁶ ripple and
#: wedge: 5-14 flips left 0-1 off, then a cycle of ~85 ms that flipped
#: 0-1; docs/dev-notes.md, "cycle counts at scale").
SETTLED_SCALE = 50_000


def settled_flips(n: int) -> int:
    """The flips a Z-matrix's finest cycle may make and still end its level
    where at most 1/SETTLED_SHARE of its n unknowns are free."""
    return max(SETTLED, n // SETTLED_SCALE)

#: The shifted start's z_u = −M⁻¹q (:func:`multilevel_guess`) is solved by
#: conjugate gradients preconditioned with the hierarchy's cycle (a plate's
#: W-cycle; :func:`._mg_kernels.unconstrained_gap`) to GAP_RTOL of ‖q‖∞ in
#: the residual, GAP_STEPS steps at most: a start needs no more (plates at
#: n = 1e4: the exact z_u's cycle counts to within ±7; 7–10 steps of ~1.3 ms
#: from 1e4 to 1e5 against the LDLᵀ of M's 40–70 ms at 1e4).
GAP_RTOL = 1e-4
GAP_STEPS = 150

#: A Z-matrix's LCP (a membrane) starts shifted by one conjugate-gradient
#: step of z_u (``gap_steps=1`` in :func:`multilevel_guess`) where its q
#: carries a layer the first coarse space cannot hold — more than
#: LAYER_SHARE of q's mass cancelled by the first restriction
#: (:func:`layer_share`) — and it has at least LAYER_MIN unknowns: the step
#: costs about one finest cycle, which the shifted start repays only where
#: the plain nested start leaves many layers of nodes for the finest
#: level to free (docs/dev-notes.md, "a one-step shifted start for
#: stepped obstacles").  The cut, fixed before the held-out shapes were
#: looked at: the continuous obstacles' shares are O(h²) (at most 0.023
#: at 100², 0.0034 at 316²), a step's O(1) (terraces 0.50, a single step
#: 0.33-0.37, an oblique staircase 0.41, a pit 0.26); ramps 2h wide read
#: 0.024 and the shift, forced there, cost 10 %.  The size: on the
#: terraces the shift is even at 100²-110² and gains 5-22 % from 120² on.
LAYER_SHARE = 0.1
LAYER_MIN = 20_000


def layer_share(q, R) -> float:
    """The share of q's mass that the restriction R = P' (P >= 0, the first
    prolongation) cancels: 1 − ‖Rq‖₁ / ‖R|q|‖₁.

    Why it tells a stepped obstacle: on a membrane q = Kψ − f, and an
    obstacle that jumps by Δψ between two neighbouring nodes puts a dipole
    ±T Δψ/h² across the step (z = u − ψ jumps there: a layer no coarse
    function holds).  R sums each coarse node's neighbours, so the
    dipole's two signs meet in the coarse nodes next to the step and about
    half its mass cancels (exactly half for one across a fine edge: the
    coarse problems see a step of half its strength), while a smooth q
    cancels only near its zeros: on the O(h) band around a zero line the
    cancelled part is O(h)|∇q| of an O(1) value, so the share is O(h²) —
    ≤ 0.0034 at 316², ≤ 0.0015 at 500², ≤ 0.0004 at 1000² on the seven
    shapes of the benchmarks, falling 4 × per halving of h.  A step's
    share does not fall with h: its dipoles' mass is ~2 T Δψ ℓ / h³ (ℓ its
    length), and every other part of q's mass is either the smooth part's,
    O(n) = O(h⁻²), or the boundary's — the obstacle's values next to the
    held edge, T |ψ_b| / h² on 4 N nodes, O(h⁻³) too, but one-signed: R
    keeps it, and every coarse level holds that jump, as it holds the edge
    (the terraces: 0.50 at every size from 100² to 1000²).  So the share
    reads about half "of the jumps in z = u − ψ, the part inside the
    domain", and a cut between O(h²) and O(1) separates
    them ever more widely as n grows.  A continuous ramp of width w counts
    as smooth once w spans a few fine cells ((h/w)² of its own mass)."""
    q = np.asarray(q, dtype=float)
    mass = float((R @ np.abs(q)).sum())
    if not mass > 0.0:
        return 0.0
    return 1.0 - float(np.abs(R @ q).sum()) / mass


#: Strength threshold of the aggregation graph: |a_ij| >= θ sqrt(a_ii a_jj).
STRENGTH = 0.08


def _csr(A) -> sp.csr_matrix:
    A = sp.csr_matrix(A, dtype=float)
    A.sum_duplicates()
    return A


def aggregation_hierarchy(M) -> tuple:
    """Smoothed-aggregation prolongations for M (finest first): greedy
    aggregates of the strength graph, the piecewise-constant tentative
    prolongation T, smoothed once by damped Jacobi, P = (I − ω D⁻¹M) T with
    ω = 4/(3 ρ) and ρ Gershgorin's bound on D⁻¹M's spectrum.  On an M-matrix
    P >= 0.  Stops at COARSEST_MAX unknowns or when a level no longer
    coarsens (fewer than 2 fine unknowns per coarse one)."""
    A = _csr(M)
    out = []
    while A.shape[0] > COARSEST_MAX:
        n = A.shape[0]
        d = A.diagonal()
        if not np.all(d > 0):
            break
        agg, nc = _kernels().aggregate(A.indptr, A.indices, A.data, d, STRENGTH)
        if nc > n // 2 or nc == 0:
            break
        T = sp.csr_matrix((np.ones(n), (np.arange(n), agg)), shape=(n, nc))
        rho = float(np.max(abs(A) @ np.ones(n) / d))
        P = _csr(T - sp.diags((4.0 / (3.0 * rho)) / d) @ (A @ T))
        P.eliminate_zeros()
        out.append(P)
        A = _product(P.T.tocsr(), A, P, None)
    return tuple(out)


def _product(R, A, P, keep) -> sp.csr_matrix:
    """R diag(keep) A diag(keep) P (keep None: no truncation)."""
    if keep is None:
        keep = np.ones(A.shape[0], dtype=np.bool_)
    ptr, idx, val = _kernels().galerkin(R.indptr, R.indices, R.data, A.indptr, A.indices, A.data,
                             P.indptr, P.indices, P.data, keep, P.shape[1])
    return sp.csr_matrix((val, idx, ptr), shape=(P.shape[1], P.shape[1]))


class _Levels:
    """The whole hierarchy packed once for the compiled cycle
    (:func:`._mg_kernels.tnnmg_cycle`): the levels' operators (``operators``:
    M and its untruncated Galerkin products, finest first; below the level
    being cycled they are rewritten as its truncated products, on the same
    patterns), the prolongations and restrictions, each kind in flat arrays
    with one segment per level; and the cycles' state (the truncations, the
    inverse diagonals, work vectors, the coarsest level's dense factor).
    ``visits``: how many times a cycle visits each coarser level (1: V-cycles,
    2: W-cycles; :func:`._mg_kernels.cycle`).  :meth:`below` gives level l's
    view: its operator and every level under it, the segments' starts being
    absolute."""

    def __init__(self, operators, prolongations, restrictions, visits=1):
        self.As = operators
        # the untruncated inverse diagonals, each level's cycles' first (a
        # 10⁵ membrane's diagonal read off its CSR: 0.5 ms a solve)
        self.inv_diag = [1.0 / A.diagonal() for A in operators]
        self.visits = visits
        self.sizes = [A.shape[0] for A in operators]
        # where each coarse row's diagonal entry is stored (the finest
        # level is never coarse: an empty segment)
        diagonal = [np.zeros(0, dtype=np.int64)] + [
            np.flatnonzero(C.indices == np.repeat(np.arange(C.shape[0]), np.diff(C.indptr)))
            for C in operators[1:]]
        rofs = np.cumsum([0] + self.sizes)
        dofs = np.cumsum([0] + [d.size for d in diagonal])
        self.H = _pack(operators) + _pack(prolongations) + _pack(restrictions) + (
            np.concatenate(diagonal), dofs, rofs)
        nc = self.sizes[-1]
        large = nc > DENSE_COARSEST
        self.S = (np.zeros(rofs[-1], dtype=np.bool_), np.ones(rofs[-1]), np.zeros(rofs[-1]),
                  np.zeros(rofs[-1]), np.zeros(rofs[-1]),
                  np.zeros((1, 1) if large else (nc, nc)), np.zeros(nc + 1, dtype=np.int64),
                  np.array([2 if large else 0]))

    def below(self, l) -> tuple:
        """(H, S) for cycles on level l, its inverse diagonal set (the
        cycles on the level above, if any ran, left its truncated one)."""
        H = self.H
        rofs = H[17]
        self.S[1][rofs[l]:rofs[l + 1]] = self.inv_diag[l]
        # the segment starts from level l on (they stay absolute): level l is
        # the view's level 0; the diagonal positions start at its first
        # coarse level, l + 1
        return (H[:3] + (H[3][l:], H[4][l:]) + H[5:8] + (H[8][l:], H[9][l:])
                + H[10:13] + (H[13][l:], H[14][l:]) + (H[15], H[16][l + 1:], rofs[l:])), self.S

    def operator(self, k) -> sp.csr_matrix:
        """Level k's operator as it stands (truncated below the level last
        cycled)."""
        ptr, idx, val, pofs, nofs = self.H[:5]
        return sp.csr_matrix((val[nofs[k]:nofs[k + 1]], idx[nofs[k]:nofs[k + 1]],
                              ptr[pofs[k]:pofs[k + 1]]), shape=(self.sizes[k],) * 2)

    def truncation(self, k) -> np.ndarray:
        """Level k's kept unknowns (the level cycled: its free set)."""
        rofs = self.H[17]
        return self.S[0][rofs[k]:rofs[k + 1]]


def _pack(matrices) -> tuple:
    """CSR matrices as (row pointers, indices, values, pointer segment
    starts, entry segment starts): each matrix's arrays one segment, its row
    pointers local to its own entries.  Concatenated into the kernels' types
    at once: a converted copy of the concatenation is one more fresh array
    the size of the hierarchy to fault in (1.5 ms of a 10⁵ membrane's
    packing).  (32-bit indices, half the bytes, made a 10⁴ plate's solve
    3-10 % slower: docs/dev-notes.md, "small free blocks".)"""
    return (np.concatenate([M.indptr for M in matrices], dtype=np.int64),
            np.concatenate([M.indices for M in matrices], dtype=np.int64),
            np.concatenate([M.data for M in matrices], dtype=float),
            np.cumsum([0] + [M.shape[0] + 1 for M in matrices]),
            np.cumsum([0] + [M.nnz for M in matrices]))


class MultilevelSetup:
    """What the cycles need of M and its hierarchy alone — the untruncated
    Galerkin products, the restrictions, the packed :class:`_Levels`, the
    coarsest level's problem — built once and kept for the next LCP on the
    same M (a raft's load combinations, a membrane under another load: only
    q changes).  On a 10⁴ membrane this is 2.5–3 floors of the ripple's
    whole solve (docs/dev-notes.md, "small free blocks": Galerkin products
    1.3 ms, packing 1.2, of a 0.77 ms floor), paid once instead of per load.

    :meth:`fits` says whether it is the setup of a given finest operator
    and hierarchy: the operator's CSR arrays equal, entry for entry, the
    packed copy of it (a changed M — another matrix, or this one's values
    rewritten in place — never reuses a stale setup), the prolongations
    the very same objects (their values compared too) and the cycles the
    same kind.  :meth:`fresh`
    restores what a solve rewrites (the coarse operators' truncated values)
    before each use.  One solve at a time holds it (:attr:`lock`), for its
    cycles: a solve that finds it held, in another thread, builds its own
    and leaves this one kept."""

    def __init__(self, M, prolongations, visits):
        self.lock = threading.Lock()
        self.prolongations = prolongations
        # the hierarchy is checked by its values too: a prolongation shares
        # the arrays its user gave (as_hierarchy), which may be rewritten
        self._P = [(P.indptr.copy(), P.indices.copy(), P.data.copy()) for P in prolongations]
        self.visits = visits
        As = [_csr(M)]
        self.Rs = [P.T.tocsr() for P in prolongations]
        for P, R in zip(prolongations, self.Rs):
            As.append(_product(R, As[-1], P, None))
        self.As = As
        L = len(prolongations)
        self.levels = _Levels(As, prolongations, self.Rs, visits) if L else None
        if not L:   # no packed copy of M to check it against: the setup's own
            As[0] = As[0].copy()
        self._used = False
        C = As[L].toarray() if As[L].shape[0] <= DENSE_COARSEST else As[L].tocsc()
        coarse = LCP(C, np.zeros(C.shape[0]))
        coarse.structure.declare_spd()
        # the coarsest LCP's structure, shared by every q (its |M| and scales)
        self.coarse = coarse.structure

    def __getstate__(self):
        return {k: v for k, v in self.__dict__.items() if k != "lock"}

    def __setstate__(self, state):
        self.__dict__.update(state, lock=threading.Lock())

    def fits(self, M, prolongations, visits) -> bool:
        """Whether this is the setup of the operator M (CSR, rows), the
        hierarchy ``prolongations`` and cycles visiting each level
        ``visits`` times."""
        if prolongations is not self.prolongations or visits != self.visits:
            return False
        same = _kernels().same_csr
        for P, (ptr, idx, val) in zip(prolongations, self._P):
            if P.nnz != val.size or not same(P.indptr, P.indices, P.data, ptr, idx, val):
                return False
        if not (sp.issparse(M) and M.format == "csr"):
            M = _csr(M)
        A = self.As[0]
        if A.shape != M.shape or A.nnz != M.nnz:
            return False
        if self.levels is None:
            return _kernels().same_csr(M.indptr, M.indices, M.data,
                                       A.indptr, A.indices, A.data)
        ptr, idx, val, pofs, nofs = self.levels.H[:5]
        return _kernels().same_csr(M.indptr, M.indices, M.data, ptr[pofs[0]:pofs[1]],
                                   idx[nofs[0]:nofs[1]], val[nofs[0]:nofs[1]])

    def fresh(self) -> "_Levels | None":
        """The packed levels with the coarse operators' values as built (a
        previous solve left them truncated to its own free set; a level's
        first cycle truncates the levels below it from its own values, so
        these must be the untruncated products).  The cycles' state needs
        no reset: every first cycle, and z_u's, writes all of it first."""
        levels = self.levels
        if levels is not None and self._used:
            values, nofs = levels.H[2], levels.H[4]
            for k in range(1, len(self.As)):     # the products as built (level 0 is M)
                values[nofs[k]:nofs[k + 1]] = self.As[k].data
        self._used = True
        return levels


def _tnnmg(levels, l, q, z, cycles, tol, stats, progress, label, deadline=None,
           held_stop=HELD_STOP, settled=0):
    """TNNMG cycles on level l of ``levels`` (a :class:`_Levels`; with at
    least one coarser level), LCP(A_l, q), from z (in place) until the
    contact set has held for two cycles with the natural-map residual at
    ``tol``, or for ``held_stop`` cycles whatever the residual, or ``cycles``
    cycles; a cycle that flips at most ``settled`` components, with at
    most 1/SETTLED_SHARE of the unknowns free, counts as one that held the
    set.  Each cycle is one compiled call
    (:func:`._mg_kernels.tnnmg_cycle`); the loop, the stop and the progress
    lines stay here.  Past ``deadline`` (read before each cycle) the
    iterate so far."""
    cycle_once = _kernels().tnnmg_cycle
    H, S = levels.below(l)
    q = np.ascontiguousarray(q, dtype=float)
    q_scale = max(float(np.max(np.abs(q), initial=0.0)), 1e-300)
    previous = np.zeros(q.size, dtype=np.bool_)
    held = 0
    # the residual (a product with M) decides only once the set has held,
    # and never where one held cycle ends the level
    wanted = 2 if progress is not None else int(held_stop > 1)
    for cycle in range(cycles):
        if deadline is not None and deadline.expired():
            break
        changed, at, moved, res = cycle_once(H, S, q, z, previous, cycle == 0,
                                             wanted if held >= 1 or progress is not None else 0,
                                             levels.visits)
        stats["mg_rebuilds"] += int(moved)
        stats["mg_cycles"] += 1
        settles = changed == 0 or (changed <= settled and (q.size - at) * SETTLED_SHARE <= q.size)
        held = held + 1 if settles else 0
        res /= q_scale
        if progress is not None:
            progress(f"mg-bpp: {label} cycle {cycle + 1}: residual {res:.1e}, "
                     f"{at} at the obstacle, {changed} changed")
        if (held >= 2 and res <= tol) or held >= held_stop:
            break
    return z


def _coincident(R) -> np.ndarray:
    """For each coarse unknown, the fine unknown it weighs most (a grid's
    coarse node's own fine node, weight 1): where a coarse level reads a
    fine vector by injection.  R = P' in CSR (P's columns as its rows: the
    restriction the cycles use, no conversion of P)."""
    column = np.repeat(np.arange(R.shape[0]), np.diff(R.indptr))
    top = np.flatnonzero(R.data == np.maximum.reduceat(R.data, R.indptr[:-1])[column])
    _, first = np.unique(column[top], return_index=True)
    return R.indices[top[first]]


def multilevel_guess(M, q, prolongations, *, cycles: int, tol: float = 1e-8, stats: dict,
                     progress=None, shifted: bool = False, w_cycles: bool = False,
                     settled: int | None = None, deadline=None, start=None,
                     setup: MultilevelSetup | None = None,
                     gap_steps: int | None = None) -> np.ndarray:
    """The nested TNNMG iterate for LCP(M, q) on the hierarchy
    ``prolongations`` (finest first; may be empty): coarsest level solved
    exactly by block pivoting, then on each finer level up to ``cycles``
    cycles, ended by the same rule (``tol`` on the finest, 1e-3 on the
    others); past ``deadline`` (a :class:`~qpcontact.core.deadline.Deadline`,
    read before each cycle) the iterate so far.

    ``shifted``: the coarse levels approximate d = z − z_u, z_u = −M⁻¹q the
    gap with no contact (to GAP_RTOL, by conjugate gradients on the
    hierarchy's V-cycle), instead of z.  Md = Mz + q is the contact force
    and d vanishes where the structure is held (a plate's edge), so d is as
    smooth as the deflection, while z = u − ψ carries the obstacle's values
    up to the boundary: a layer bilinear coarse functions cannot represent,
    which on a plate (energy ~ h⁻⁴ per unit of misfit) distorts every coarse
    answer (plate D = 1, dome, n = 1e5: no coarse answer touched the
    obstacle).  Level l solves LCP(A_l, −A_l s_l) for e_l = d_l + s_l, s_l
    the injection of z_u (:func:`_coincident`); up a level,
    e = P(e_c − s_c) + s; on the finest level e = z.

    ``gap_steps``: z_u's conjugate-gradient steps, all of them (no
    tolerance), instead of GAP_RTOL's (a membrane's one-step shift, where
    its obstacle has steps: :func:`layer_share`).  A shift that far from
    z_u leaves a residual r = q + A s_0 the coarse levels must carry, so
    level l solves LCP(A_l, q_l) with q_l = R(q_(l−1) + A_(l−1) s_(l−1)) −
    A_l s_l: the coarse problem of d = P d_c in f(s_0 + d), the bounds
    d_c >= −s_c read by injection — consistent for any shift.  (The
    plate's q_l = −A_l s_l drops the residual: z_u to GAP_RTOL leaves none
    worth carrying; for one step it leaves the coarse problems another q.)

    ``w_cycles``: every linear correction (the TNNMG cycles' and z_u's
    preconditioner) a W-cycle, each coarser level visited twice, instead of
    a V-cycle (the module docstring says why a plate wants them).

    ``settled``: the finest level ends at its first held cycle whatever
    its size, or at its first that flips at most that many components
    where at most 1/SETTLED_SHARE of its unknowns are free (a Z-matrix's:
    :data:`SETTLED`); None, at its first held cycle up to FIRST_HOLD_MAX
    unknowns, by HELD_STOP above.

    ``start``: cycle the finest level only, from ``start`` (no coarse
    levels' answers, no z_u): the search resumed from a point it did not
    reach by itself.

    ``setup``: a :class:`MultilevelSetup` of M and ``prolongations`` with
    these cycles (the caller checked :meth:`MultilevelSetup.fits`), used
    instead of building one."""
    stats.setdefault("mg_cycles", 0)
    stats.setdefault("mg_rebuilds", 0)
    if setup is None:
        setup = MultilevelSetup(M, prolongations, 2 if w_cycles else 1)
    As, Rs = setup.As, setup.Rs
    qs = [np.asarray(q, dtype=float)]
    for R in Rs:
        qs.append(R @ qs[-1])
    L = len(prolongations)
    stats["mg_levels"] = L + 1
    if deadline is not None and deadline.expired():
        return np.zeros(qs[0].size)     # no guess: the caller reads the deadline too
    levels = setup.fresh()
    held_stop = 1 if settled is not None or qs[0].size <= FIRST_HOLD_MAX else HELD_STOP
    settled = settled or 0
    if start is not None:
        if not L:
            return np.array(start, dtype=float)
        return _tnnmg(levels, 0, qs[0], np.array(start, dtype=float), cycles, tol, stats,
                      progress, "level 0", deadline, held_stop, settled)
    shift = None
    if shifted and L:
        H, S = levels.below(0)
        shift, steps, residual = _kernels().unconstrained_gap(
            H, S, qs[0], GAP_STEPS if gap_steps is None else gap_steps,
            GAP_RTOL if gap_steps is None else 0.0, levels.visits)
        stats.update(gap_steps=int(steps), gap_residual=float(residual))
        if not np.all(np.isfinite(shift)):    # a hierarchy whose V-cycle broke CG
            shift = None
    stats["shifted"] = shift is not None
    stats["w_cycles"] = bool(L and w_cycles)
    shifts = [np.zeros(q.size) for q in qs]
    if shift is not None:
        shifts[0] = shift
        for l, R in enumerate(Rs, start=1):
            shifts[l] = shifts[l - 1][_coincident(R)]
            if gap_steps is None:
                qs[l] = -(As[l] @ shifts[l])
            else:
                qs[l] = R @ (qs[l - 1] + As[l - 1] @ shifts[l - 1]) - As[l] @ shifts[l]
    coarse = LCP.with_structure(setup.coarse, qs[L])
    try:
        z, _, _, _ = block_pivoting(coarse, np.zeros(qs[L].size, bool), 10 * qs[L].size + 100, 3)
    except np.linalg.LinAlgError:   # dependent coarse functions: start from nothing
        z = np.zeros(qs[L].size)
    for l in range(L - 1, -1, -1):
        z = np.maximum(prolongations[l] @ (z - shifts[l + 1]) + shifts[l], 0.0)
        finest = l == 0
        z = _tnnmg(levels, l, qs[l], z, cycles, tol if finest else 1e-3, stats,
                   progress if finest else None, "level 0" if finest else f"level {l}", deadline,
                   held_stop if finest else HELD_STOP, settled if finest else 0)
    return z
