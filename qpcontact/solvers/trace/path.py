"""Following the solution path of a parametric LCP: working schemes, their
directions, the pieces between breakpoints, and what happens at a vertex.
The module :mod:`.driver` holds the method's description and endings."""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import scipy.linalg
from scipy.linalg import lapack

from ...core.linalg import refined, ruiz_scaling
from ...judge.lcp_certificate import certify_lcp
from ...judge.scales import ComponentScales
from ...proofs.parametric import TIE_RTOL, LoadFamily
from ..pivoting.lemke_tableau import lemke
from .result import TracePiece

__all__ = ["Path", "DIRECTION_RTOL", "SINGULAR_RCOND", "ENUM_MAX"]

#: A direction component below -DIRECTION_RTOL of its own scale is decreasing.
DIRECTION_RTOL = 1e-9


#: Reciprocal condition number (1-norm, equilibrated block) below which a
#: working scheme's block counts as singular (a mechanism, or two links
#: describing the same motion, like the two slip parts of one contact).
SINGULAR_RCOND = 1e-11


#: Most degenerate pairs at one vertex decided by checking every scheme.
ENUM_MAX = 10


class _Block:
    """LU of an equilibrated block Ms_FF with its reciprocal condition number."""

    def __init__(self, Ms: np.ndarray, F: np.ndarray):
        self.F = np.flatnonzero(F)
        k = self.F.size
        self.rcond = 1.0
        if k == 0:
            return
        self.B = Ms[np.ix_(self.F, self.F)]
        with warnings.catch_warnings():  # an exactly singular block is diagnosed by rcond
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            self.lu = scipy.linalg.lu_factor(self.B, check_finite=False)
        diag = np.abs(np.diag(self.lu[0]))
        if not np.all(np.isfinite(diag)) or diag.min() == 0.0:
            self.rcond = 0.0
            return
        anorm = float(np.abs(self.B).sum(axis=0).max())
        self.rcond = float(lapack.dgecon(self.lu[0], anorm, norm="1")[0])

    @property
    def singular(self) -> bool:
        return not self.rcond >= SINGULAR_RCOND

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """B^{-1} rhs, refined while the residual shrinks."""
        def lu(r):
            return scipy.linalg.lu_solve(self.lu, r, check_finite=False)

        return refined(lu, self.B, rhs, lu(rhs))


class Path(LoadFamily):
    """The data of one trace, equilibrated once (:class:`LoadFamily`, which
    also holds the collapse proof), and the operations of following it."""

    def __init__(self, plcp):
        super().__init__(plcp)
        self.slopes = ComponentScales(self.M, np.abs(self.q1))
        self.twins, self.unique = _null_structure(self.M)

    def classify(self, p: float, z: np.ndarray, w: np.ndarray):
        """(α, β, γ) masks: z_i > 0, both zero, w_i > 0 (each on its own scale)."""
        zeta, sigma = self.values.at(z, self.q_terms(p))
        alpha = z > TIE_RTOL * zeta
        gamma = w > TIE_RTOL * sigma
        return alpha, ~(alpha | gamma), gamma, bool(np.any(alpha & gamma))

    def direction(self, F: np.ndarray):
        """(block, dz, dw) of the scheme F, or (block, None, None) when singular."""
        block = _Block(self.Ms, F)
        n = self.q1.size
        dz = np.zeros(n)
        if block.singular:
            return block, None, None
        if block.F.size:
            dz[block.F] = self.cs[block.F] * block.solve(-(self.rs * self.q1)[block.F])
        dw = self.M @ dz + self.q1
        dw[block.F] = 0.0
        return block, dz, dw

    def valid(self, dz, dw, F, beta) -> bool:
        """Whether the direction keeps the degenerate pairs complementary and >= 0."""
        zeta, sigma = self.slopes.at(dz)
        on_z = beta & F
        on_w = beta & ~F
        return bool(np.all(dz[on_z] >= -DIRECTION_RTOL * zeta[on_z])
                    and np.all(dw[on_w] >= -DIRECTION_RTOL * sigma[on_w]))

    def piece(self, block: _Block, F: np.ndarray, p: float, dz, dw) -> TracePiece:
        n = self.q0.size
        z = np.zeros(n)
        if block.F.size:
            q = (self.rs * (self.q0 + p * self.q1))[block.F]
            z[block.F] = self.cs[block.F] * block.solve(-q)
        w = self.M @ z + self.q0 + p * self.q1
        w[block.F] = 0.0
        return TracePiece(float(p), np.inf, F.copy(), z, dz, w, dw)

    def schur_lemke(self, alpha, beta, max_pivots):
        """The directional LCP on β (α basic) solved by Lemke: a scheme or None."""
        A, B = np.flatnonzero(alpha), np.flatnonzero(beta)
        Ms, q1s = self.Ms, self.rs * self.q1
        if A.size:
            blk = _Block(Ms, alpha)
            if blk.singular:
                return None
            X = blk.solve(np.column_stack([Ms[np.ix_(A, B)], q1s[A]]))
            S = Ms[np.ix_(B, B)] - Ms[np.ix_(B, A)] @ X[:, :-1]
            r = q1s[B] - Ms[np.ix_(B, A)] @ X[:, -1]
        else:
            S, r = Ms[np.ix_(B, B)], q1s[B]
        rs, cs = ruiz_scaling(S)
        out = lemke(S * rs[:, None] * cs[None, :], r * rs, rs.copy(), max_pivots)
        if out.status != "solved":
            return None
        F = alpha.copy()
        F[B[out.basic_z]] = True
        return F

    def continuation(self, p, z, w, F_prev, max_pivots):
        """The schemes that continue the path from (p, z, w), closest to the
        previous scheme first: [(F, block, dz, dw)]; and whether every scheme
        holding the current positive z's was checked (exhaustive)."""
        alpha, beta, gamma, clash = self.classify(p, z, w)
        if clash:
            return [], False
        # A degenerate z with a positive twin cannot be basic (singular block).
        forced = [i for i in np.flatnonzero(beta) if any(alpha[k] for k in self.twins[i])]
        free_beta = beta.copy()
        free_beta[forced] = False
        B = np.flatnonzero(free_beta)
        found = []
        if B.size <= ENUM_MAX:
            for k in range(B.size + 1):
                for S in itertools.combinations(B, k):
                    F = alpha.copy()
                    F[list(S)] = True
                    block, dz, dw = self.direction(F)
                    if dz is not None and self.valid(dz, dw, F, beta):
                        found.append((F, block, dz, dw))
            exhaustive = True
        else:
            exhaustive = False
            F = self.schur_lemke(alpha, free_beta, max_pivots)
            if F is not None:
                block, dz, dw = self.direction(F)
                if dz is not None and self.valid(dz, dw, F, beta):
                    found.append((F, block, dz, dw))
        found.sort(key=lambda c: int(np.sum(c[0] != F_prev)))
        return found, exhaustive

    def distinct(self, found) -> int:
        """How many of the continuations differ in w (the forces): schemes that
        differ only along a null vector of M (the two slip parts of a separated
        contact) are one continuation."""
        groups = []
        for _, _, dz, dw in found:
            _, sigma = self.slopes.at(dz)
            if not any(np.all(np.abs(dw - g) <= DIRECTION_RTOL * sigma) for g in groups):
                groups.append(dw)
        return len(groups)

    def next_break(self, piece: TracePiece):
        """(t, index, is_z): the smallest step along the piece at which a
        basic z or a nonbasic w reaches zero; t = inf when none decreases."""
        F = piece.active
        zeta, sigma = self.slopes.at(piece.dz)
        val = np.where(F, piece.z_start, piece.w_start)
        slope = np.where(F, piece.dz, piece.dw)
        scale = np.where(F, zeta, sigma)
        dec = slope < -DIRECTION_RTOL * scale
        if not dec.any():
            return np.inf, -1, False
        t = np.full(val.size, np.inf)
        t[dec] = np.maximum(val[dec], 0.0) / -slope[dec]
        i = int(np.argmin(t))
        return float(t[i]), i, bool(F[i])

    def certified_piece(self, block, F, p, dz, dw, p_max, tol):
        """The piece of scheme F from p, ended at its breakpoint or p_max and
        certified from the data at its start, middle and end: (piece, t,
        crossing row, crossing is a z) or None when it fails."""
        piece = self.piece(block, F, p, dz, dw)
        t, i, is_z = self.next_break(piece)
        stop = np.isfinite(p_max) and p + t >= p_max
        piece.p_end = p_max if stop else p + t
        if not piece.p_end > p:
            return None   # a scheme that ends where it starts continues nothing
        hi = piece.p_end if np.isfinite(piece.p_end) else p + max(1.0, abs(p))
        err = 0.0
        for pp in (p, 0.5 * (p + hi), hi):
            err = max(err, certify_lcp(self.plcp.at(pp), piece.z(pp)).error)
            if not err <= tol:
                return None
        piece.error = err
        return piece, t, i, is_z

    def resolved_piece(self, p, F_prev, p_max, tol, solve_lcp):
        """A scheme found by Lemke's method at p + δ (δ tiny on the scale of p;
        ``solve_lcp``: the engine's solve of one LCP by Lemke, asked for no
        proof where it fails: the trace seeks its own) that also holds at p,
        certified like any piece; or None."""
        unit = self.load_unit(p)
        for rel in (1e-7, 1e-10):
            pp = p + rel * unit
            if np.isfinite(p_max) and pp >= p_max:
                pp = 0.5 * (p + p_max)
            sol = solve_lcp(self.plcp.at(pp), prove=False)
            if sol.ok:
                got = self.piece_through(p, F_prev, sol.z, pp, p_max, tol)
                if got is not None:
                    return got
        return None

    def piece_through(self, p, F_prev, z_beyond, p_beyond, p_max, tol):
        """The piece from p of the scheme of a solution z_beyond at p_beyond > p,
        if it is certified from p on; or None.  The scheme that just ended is
        not taken again: its crossing row would be back within rounding."""
        zeta, _ = self.values.at(z_beyond, self.q_terms(p_beyond))
        F = z_beyond > TIE_RTOL * zeta
        if F_prev is not None and np.array_equal(F, F_prev):
            return None
        block, dz, dw = self.direction(F)
        if dz is None:
            return None
        return self.certified_piece(block, F, p, dz, dw, p_max, tol)


def _null_structure(M: np.ndarray):
    """(twins, unique): twins[j] = the columns that are column j negated (to
    rounding); unique = whether those pairs span M's whole null space.

    A twin pair is a null vector e_j + e_k >= 0: z_j and z_k describe one
    motion in opposite directions (the slip parts Z+ and Z- of a frictional
    contact; for a frame that only its contacts hold, also two contacts'
    slips in one rigid motion), and a scheme with both basic is singular.
    Adding such a vector never changes which z's are positive at a vertex.
    Any other null vector (a zero column: an opening that no force resists;
    two equal columns) lets the same w be written with other positive z's,
    so the schemes containing the current positive z's are then not all the
    schemes there are: "fold" is not claimed.
    """
    n = M.shape[1]
    twins = [[] for _ in range(n)]
    norms = np.linalg.norm(M, axis=0)
    nz = np.flatnonzero(norms > 0)
    vectors = []
    if nz.size >= 2:
        A = M[:, nz] / norms[nz]
        G = A.T @ A
        absM = np.abs(M)
        for a, b in zip(*np.nonzero(np.triu(G < -1 + 1e-12, 1))):
            j, k = nz[a], nz[b]
            if np.all(np.abs(M[:, j] + M[:, k]) <= 1e3 * np.finfo(float).eps * (absM[:, j] + absM[:, k])):
                twins[j].append(k)
                twins[k].append(j)
                v = np.zeros(n)
                v[[j, k]] = 1.0
                vectors.append(v)
    s = np.linalg.svd(M, compute_uv=False)
    null_dim = int(np.sum(s <= 1e3 * np.finfo(float).eps * max(s.max(initial=0.0), 1e-300))) if n else 0
    twin_rank = int(np.linalg.matrix_rank(np.array(vectors))) if vectors else 0
    return twins, null_dim <= twin_rank
