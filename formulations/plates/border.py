r"""A raft's linear system solved on the LDLᵀ of a nearby one: the bordered
system, for Newton's steps on soil and a rigid floor (:mod:`.newton`).

A step solves the raft with its held floor nodes' w [m] removed and
springs k_i [N/m] on its pressing soil nodes: (K + S₁) u = f [N] on the
dofs D₁ that are not held.  The next step's differs at the nodes whose
state changed — a few dozen to a few hundred, along the lift-off line —
and factorising afresh costs the same whatever the change.  Instead, keep
A₀ = (K + S₀) on D₀ factorised (A₀ = P (I + L) D (I + L)' P', any LDLᵀ) and
border it: a dof held now but free in D₀ is held at zero by a multiplier μ
(the unit column e_j); a dof free now but not in D₀ brings its column of
K; a dof whose spring changed by Δ_j gets a multiplier ν_j = Δ_j u_j
(Sherman–Morrison–Woodbury, A₀ + Δ_j e_j e_j'):

    [ A₀   B   E   F      ] [u₀]   [f₀]
    [ B'   C   0   0      ] [u_N] = [f_N]      B = K[D₀, N],  C = (K + S₁)[N, N]
    [ E'   0   0   0      ] [ μ ]   [ 0 ]
    [ F'   0   0   −Δ⁻¹   ] [ ν ]   [ 0 ]

— a held dof's row is taken up by μ, so u is the new step's answer
exactly.  With V = [B E F] and the k x k Schur complement
S = diag(C, 0, −Δ⁻¹) − V' A₀⁻¹ V, a solve is y = A₀⁻¹ f₀, S [u_N; μ; ν] =
[f_N; 0; 0] − V'y, u₀ = y − A₀⁻¹ V [u_N; μ; ν]: two solves with the factor
and one with S, plus one step of refinement on the new system's own
residual (on a 115 x 115 floor raft it moves u by 1e-10 of its largest,
more than a state's FLIP).

The border's k columns are not k solves: V' A₀⁻¹ V = W' D⁻¹ W with
W = (I + L)⁻¹ P' V, and a column of V has a node's few entries, so its
column of W lives on their paths to the elimination tree's root
(:mod:`._border_kernels`): 1/7 of L's entries on a 115 x 115 floor raft,
where a full solve reads all of L twice.  The columns of W stay with the
factor: the next step's border, mostly the same dofs (a floor's contact
line creeps a row a step), solves only its new columns, and W' D⁻¹ W only
their rows and columns.  A border of more than
BORDER_SHARE √n dofs, or an S whose condition is above 1/BORDER_RCOND (a
release that leaves the plate nearly free), sends the step to a fresh
factorisation.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

#: a step whose dofs and springs differ from the factorised block's at more
#: than BORDER_SHARE √n dofs (n the block's) is factorised afresh: a border
#: column costs a path of the elimination tree (a cost that grows about as
#: n on a plate, a factorisation's as n^1.5); one border matched one
#: factorisation at 2.7 √n (57 x 57 floor raft) to 4.4 √n (115 x 115),
#: and 1.5, 2, 3 √n timed alike within the machine's noise (docs/dev-notes.md)
BORDER_SHARE = 3.0
#: a border of at most this many columns on a factor not yet read takes a
#: full solve per column instead: reading L out of qdldl (``factors()``, a
#: copy) cost 1–5 solves on the worked raft at 96 x 72 cells, where its
#: soil steps end on borders of 1–6 springs
FEW_COLUMNS = 4
#: at most this many entries in the border's forward solves (256 MB)
BORDER_ENTRIES = 2 ** 25
#: S with a larger condition number (1-norm estimate, equilibrated) sends the
#: step to a fresh factorisation
BORDER_RCOND = 1e-10


class FactoredBlock:
    """A factorisation of (K + diag(springs)) on the dofs ``keep`` (a mask
    over K's rows), and solves on it of systems nearby (module docstring).
    Any LDLᵀ will do, given as

    * ``solve``: rhs (n,) ↦ u (n,), the block's solution, zero off ``keep``;
    * ``factors``: () ↦ (L, d, p, parent), read on the first border that
      needs it: L lower triangular (CSC; a stored diagonal is taken as the
      unit one and passed over) and d such that the block in the order p
      (p[i] the dof at the factor's position i) is (I + L) diag(d) (I + L)'
      — qdldl's ``factors()`` with p taken to dofs, or SuperLU's symmetric
      mode with diagonal pivots (L = ``lu.L`` as it is, d = diag(``lu.U``),
      p the order it was given); ``parent`` the elimination tree, or None
      to have it read off L's rows.

    ``K``: the stiffness (CSR or CSC, symmetric, no springs)."""

    def __init__(self, K, keep, springs, solve, factors):
        self.K, self.solve, self.read = K, solve, factors
        self.keep, self.springs = keep.copy(), springs.copy()
        self.n = int(keep.sum())
        self.factors = None                 # L's arrays, 1/d, the dofs' positions, parent
        self._forget()

    def _forget(self):
        """No border column kept.  Kept (:meth:`_inverse_form`): the columns
        solved so far, by key (2 dof for a dof's column of K, 2 dof + 1 for
        a unit column) → their place in W (dense on the union of their
        reaches, ``rows``) and in the Gram matrix W' D⁻¹ W."""
        self.solved, self.rows = {}, np.zeros(0, np.int64)
        self.W, self.gram = np.zeros((0, 0)), np.zeros((0, 0))

    def near(self, keep, springs):
        """The solve rhs ↦ u of (K + diag(springs)) u = rhs on ``keep`` by
        this block's factor and a border, or None where the border would be
        larger than BORDER_SHARE √n or its Schur complement ill-conditioned.
        A dof free now but not in the block brings its column; one in the
        block but held now is held by a multiplier; one whose spring changed
        by Δ is bordered by e_j with −1/Δ on the diagonal (Sherman–Morrison–
        Woodbury: A₀ + Δ e_j e_j')."""
        import scipy.linalg

        both = self.keep & keep
        respring = np.flatnonzero(both & (springs != self.springs))
        new = np.flatnonzero(keep & ~self.keep)
        pinned = np.flatnonzero(self.keep & ~keep)
        k = new.size + pinned.size + respring.size
        if k == 0:
            return self.solve
        if k > BORDER_SHARE * np.sqrt(self.n):
            return None
        # V's entries (row, column, value), column by column: the new dofs'
        # columns of K on the block's dofs (K symmetric: a CSR K's rows are
        # its columns), then a unit column per multiplier — built from K's
        # arrays, not by SciPy's slicing and stacking, whose overhead was
        # half of a border's cost on the 57 x 57 floor raft and its twins
        Kp, Ki, Kx = self.K.indptr, self.K.indices, self.K.data
        counts = Kp[new + 1] - Kp[new]
        at = np.repeat(Kp[new] - np.cumsum(counts) + counts, counts) + np.arange(counts.sum())
        rows, vals, column = Ki[at], Kx[at], np.repeat(np.arange(new.size), counts)
        local = np.full(keep.size, -1)
        local[new] = np.arange(new.size)
        among = local[rows] >= 0                     # K's entries among the new dofs
        C = np.zeros((new.size, new.size))
        np.add.at(C, (column[among], local[rows[among]]), vals[among])
        on = self.keep[rows] & (vals != 0.0)         # on the block's dofs only
        units = np.concatenate((pinned, respring))
        V = (np.concatenate((rows[on], units)),
             np.concatenate((column[on], new.size + np.arange(units.size))),
             np.concatenate((vals[on], np.ones(units.size))))
        keys = np.concatenate((2 * new, 2 * units + 1))
        G = self._inverse_form(V, keys)              # V' A₀⁻¹ V
        if G is None:
            return None
        S = -G
        S[:new.size, :new.size] += C + np.diag(springs[new])
        tail = np.arange(new.size + pinned.size, k)
        S[tail, tail] -= 1.0 / (springs[respring] - self.springs[respring])
        # stiffnesses [N/m] on the new dofs, flexibilities [m/N] on the
        # multipliers: equilibrated before its condition is judged
        with np.errstate(divide="ignore"):
            scale = 1.0 / np.sqrt(np.abs(np.diag(S)))
        if not np.all(np.isfinite(scale)):
            return None
        S *= scale[:, None] * scale[None, :]
        lu = scipy.linalg.lu_factor(S, check_finite=False)
        rcond = scipy.linalg.lapack.dgecon(lu[0], np.abs(S).sum(axis=0).max(), norm="1")[0]
        if not rcond > BORDER_RCOND:
            return None
        Vr, Vc, Vx = V
        gone = ~keep

        def once(rhs):
            y = self.solve(rhs)
            z = scale * scipy.linalg.lu_solve(
                lu, scale * (np.concatenate((rhs[new], np.zeros(k - new.size)))
                             - np.bincount(Vc, Vx * y[Vr], minlength=k)),
                check_finite=False)
            u = y - self.solve(np.bincount(Vr, Vx * z[Vc], minlength=keep.size))
            u[gone] = 0.0
            u[new] = z[:new.size]
            return u

        def solve(rhs):
            u = once(rhs)
            residual = np.where(keep, rhs - (self.K @ u + springs * u), 0.0)
            return u + once(residual)

        return solve

    def _inverse_form(self, V, keys):
        """V' A₀⁻¹ V (dense k x k; V as its entries (rows, columns, values),
        column by column, column c named ``keys[c]``) = W' D⁻¹ W,
        W = (I + L)⁻¹ P' V, by forward solves on the union of the columns'
        reaches (:mod:`._border_kernels`) — or, for FEW_COLUMNS on a factor
        not yet read, a solve each; None where that union holds more than
        BORDER_ENTRIES entries.  A column solved for an earlier border on
        this factor is not solved again: a floor raft's contact line creeps
        a row a step, so each step's border is most of the last one's (at
        100 467 dofs 154, 280, 298, 334, 352 columns), and the forward
        solves were two thirds of a border's cost."""
        from ._border_kernels import parents

        Vr, Vc, Vx = V
        k = keys.size
        if self.factors is None and k <= FEW_COLUMNS:
            dense = np.zeros((self.keep.size, k))
            dense[Vr, Vc] = Vx
            return dense.T @ np.column_stack([self.solve(dense[:, j]) for j in range(k)])
        if self.factors is None:
            L, d, p, tree = self.read()
            L = sp.csc_matrix(L)
            position = np.full(self.keep.size, -1, np.int64)
            position[p] = np.arange(p.size)
            if tree is None:
                rows = L.tocsr()
                tree = parents(rows.indptr, rows.indices, p.size)
            self.factors = (L.indptr, L.indices, L.data, 1.0 / d, position, tree)
        missing = np.array([c for c in range(k) if int(keys[c]) not in self.solved], np.int64)
        if missing.size and not self._solve_columns(Vr, Vc, Vx, keys, missing):
            # more than BORDER_ENTRIES with the columns kept: these alone
            self._forget()
            if not self._solve_columns(Vr, Vc, Vx, keys, np.arange(k)):
                return None
        at = np.array([self.solved[int(key)] for key in keys], np.int64)
        return self.gram[np.ix_(at, at)]

    def _solve_columns(self, Vr, Vc, Vx, keys, missing):
        """W's columns ``missing`` of V (forward solves on the union of their
        reaches) added to those kept, and the Gram matrix's rows and columns
        for them; False where W would hold more than BORDER_ENTRIES entries.
        A kept column is zero off its own reach, so on the rows the new ones
        add it stays zero."""
        from ._border_kernels import forward_block, reach_union

        Lp, Li, Lx, dinv, position, parent = self.factors
        local = np.full(keys.size, -1, np.int64)
        local[missing] = np.arange(missing.size)
        picked = local[Vc] >= 0
        Vi = position[Vr[picked]]
        reach = reach_union(parent, Vi, parent.size)
        rows = np.union1d(self.rows, reach)
        kept = self.W.shape[1]
        if rows.size * (kept + missing.size) > BORDER_ENTRIES:
            return False
        X = np.zeros((reach.size, missing.size))
        X[np.searchsorted(reach, Vi), local[Vc[picked]]] = Vx[picked]
        forward_block(Lp, Li, Lx, reach, X)
        W = np.zeros((rows.size, kept + missing.size))
        W[np.searchsorted(rows, self.rows), :kept] = self.W
        W[np.searchsorted(rows, reach), kept:] = X
        cross = W.T @ (W[:, kept:] * dinv[rows, None])
        gram = np.zeros((kept + missing.size,) * 2)
        gram[:kept, :kept] = self.gram
        gram[:, kept:] = cross
        gram[kept:, :kept] = cross[:kept].T
        for j, c in enumerate(missing):
            self.solved[int(keys[c])] = kept + j
        self.rows, self.W, self.gram = rows, W, gram
        return True
