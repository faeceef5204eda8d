"""``"trace"``: follow the solution of a parametric LCP as the load grows (P3).

For ``ParametricLCP(M, q0, q1)``, w = M z + q0 + p q1: q0 is the constant load
(gaps, dead weight), q1 the variable load scaled by the load parameter p >= 0
(units: z and w are the LCP's, p is dimensionless).  Osipova, Popov & Lovtsov
follow the solution from p = 0 upwards through the *working schemes* of the
structure: on an interval of p where the set F of basic z's (contacts closed,
links slipping) is fixed,

    z_F(p) = -M_FF^{-1} (q0_F + p q1_F),   z_N = 0,   w = M z + q0 + p q1,

is affine in p, and a breakpoint p_k is where some z_i (i in F) or w_i (i not
in F) reaches zero.

How the path is followed here
-----------------------------
1. Start from a solution at p = 0: z = 0 when q0 >= 0 (P3's cases a and b),
   otherwise the one Lemke's method finds for LCP(M, q0) (case c).
2. At every breakpoint (and at the start) the next working scheme is *decided*,
   not guessed: with α = {z_i > 0}, γ = {w_i > 0} and β the pairs with z_i =
   w_i = 0 (each judged on its own componentwise scale, TIE_RTOL), a scheme F
   continues the path exactly when F contains α, avoids γ, M_FF is nonsingular
   and its direction dz_F = -M_FF^{-1} q1_F, dw = M dz + q1 keeps
   dz_i >= 0 on F ∩ β and dw_i >= 0 on β \\ F (the directional LCP of the
   vertex).  Up to ENUM_MAX degenerate pairs every one of the 2^|β| choices is
   checked, so several links changing at once, a slip turning into lift-off
   (where X_n, f X_n + X_t and f X_n - X_t vanish together) and any tie are
   resolved exactly; above that the directional LCP is solved by Lemke's
   method.  When several schemes continue the path (possible only when M is
   not a P-matrix) the one closest to the previous scheme is taken and the
   event records how many there were.
3. Candidates are tried closest first; a piece is computed from its own block
   (LU of the equilibrated M_FF, iteratively refined), certified from the
   data at its start, middle and end (:func:`qpcontact.certify.certify_lcp`),
   and only then kept.  When no candidate certifies (M with null vectors
   other than slip pairs: the same w written with other positive z's), a
   solve just beyond the vertex is tried and kept only if its scheme
   certifies back at the vertex.

Endings (``LoadTrace.end``), each with what proves it
-----------------------------------------------------
``"p_max"``      the requested load was reached.
``"unbounded"``  (p_max = inf) the last scheme never changes again: no z_i or
                 w_i decreases along its direction, which is in ``proof``.
``"collapse"``   no equilibrium exists for p >= p_limit, a hair above the end
                 point: a Farkas vector y (y >= 0, M'y <= 0, q1'y <= 0,
                 y'q(p_limit) < 0), found by an LP and checked component by
                 component from the data, makes y'w < 0 for every z >= 0; when
                 complementarity is what rules the loads out, branch and bound
                 over the complementary patterns gives one such vector per
                 remaining pattern (``proof["leaves"]``).
``"fold"``       equilibria may exist beyond the end point, but none continues
                 this path: all 2^|β| schemes at the vertex were checked, none
                 goes on with p increasing, and M's only null vectors are slip
                 pairs (a non-P matrix whose load-displacement path turns
                 back).  Solve at a fixed load with ``problem.at(p)`` for other
                 branches.
``"breakdown"``  none of the above could be established: the pieces before
                 are returned (certified), the message says what is known.
``"max_pieces"`` the piece limit was reached.

Nothing is added to the data: degenerate starts (q0 = 0, case a, or zero gaps)
are decided by the directional problem, so every reported state satisfies the
LCP of the real data.
"""

from __future__ import annotations

import itertools
import time
import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg
from scipy.linalg import lapack

from ..core.accuracy import resolve_accuracy
from ..judge.scales import ComponentScales
from ..judge.lcp import certify_lcp
from ..core.errors import (InvalidOptionError, InvalidProblemError, NoSolutionError,
                           SolverFailedError)
from .pivoting.active_set import check_dense_size
from ..core.options import check_options, int_option
from ..core.linalg import dense_matrix, refined
from ..proofs.lcp import FARKAS_RTOL
from .pivoting.lemke_tableau import lemke
from ..core.linalg import ruiz_scaling
from ..plots.figures import save_figure
from ..core.problems import ParametricLCP
from ..core.results import LCPSolution

__all__ = ["TracePiece", "TraceEvent", "LoadTrace", "trace_load", "END_REASONS"]

END_REASONS = ("p_max", "unbounded", "collapse", "fold", "breakdown", "max_pieces")

#: A z_i or w_i within TIE_RTOL of its own componentwise scale is zero at a
#: breakpoint: rows reaching zero together (ties) are decided together.
TIE_RTOL = 1e-10
#: A direction component below -DIRECTION_RTOL of its own scale is decreasing.
DIRECTION_RTOL = 1e-9
#: Reciprocal condition number (1-norm, equilibrated block) below which a
#: working scheme's block counts as singular (a mechanism, or two links
#: describing the same motion, like the two slip parts of one contact).
SINGULAR_RCOND = 1e-11
#: Most degenerate pairs at one vertex decided by checking every scheme.
ENUM_MAX = 10
#: Most branch-and-bound nodes spent proving that no equilibrium exists
#: beyond the end of the path (each one LP or two).
COLLAPSE_NODES = 400
# HiGHS' default feasibility tolerances (1e-7) leave Farkas vectors that fail
# a componentwise check on frames whose stiffnesses span 1e5.
_LP_OPTIONS = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}
#: A Farkas vector whose rounding leaves M'y slightly positive proves "no
#: equilibrium" only for z below a bound; it is accepted when the bound is at
#: least Z_BOUND times the size of the solution at the end of the path (far
#: beyond what a small-displacement model describes).
Z_BOUND = 1e3


@dataclass
class TracePiece:
    """One interval of the load parameter on which the working scheme is fixed.

    ``active`` marks the z's that are basic (contacts closed, or the LCP's
    unknowns that are free) on the interval; on it ``z(p) = z_start + (p -
    p_start) dz`` and ``w(p) = w_start + (p - p_start) dw`` exactly.
    ``p_end`` is inf on a final unbounded piece.  ``error`` is the worst
    certificate of the piece (start, middle, end).
    """

    p_start: float
    p_end: float
    active: np.ndarray
    z_start: np.ndarray
    dz: np.ndarray
    w_start: np.ndarray
    dw: np.ndarray
    error: float = 0.0

    def z(self, p: float) -> np.ndarray:
        return np.maximum(self.z_start + (p - self.p_start) * self.dz, 0.0)

    def w(self, p: float) -> np.ndarray:
        return self.w_start + (p - self.p_start) * self.dw

    def contains(self, p: float) -> bool:
        return self.p_start <= p <= self.p_end


@dataclass
class TraceEvent:
    """A breakpoint: at ``p`` the z's in ``entered`` become basic (may grow
    from zero) and those in ``left`` leave the basis (stay zero; their w's may
    grow).  ``continuations`` is how many working schemes (distinct in w)
    could continue the path there (1 unless M is not a P-matrix);
    ``resolved`` marks a scheme found by a fresh solve just beyond p (the
    vertex's own schemes did not certify), continuations then 0."""

    p: float
    entered: np.ndarray
    left: np.ndarray
    continuations: int = 1
    resolved: bool = False

    def describe(self, names=None) -> str:
        name = (lambda i: names[i]) if names is not None else (lambda i: f"z[{i}]")
        parts = [f"+{name(i)}" for i in self.entered] + [f"-{name(i)}" for i in self.left]
        return " ".join(parts) or "(no change)"


@dataclass(kw_only=True)
class LoadTrace(LCPSolution):
    """The solution path of a ParametricLCP: an ``LCPSolution`` for the final
    state (z, w at ``p_end``, certified) plus the pieces, breakpoints and events.

    ``status`` is "solved" when every piece was certified (start, middle and
    end) and the ending is proved (``end`` in "p_max", "unbounded",
    "collapse", "fold"), "failed" on "breakdown", "max_pivots" at the piece
    limit.  ``proof`` holds the ending's evidence (module docstring).
    """

    pieces: list = field(default_factory=list)
    breakpoints: np.ndarray = field(default_factory=lambda: np.empty(0))
    events: list = field(default_factory=list)
    end: str = ""
    p_end: float = 0.0
    proof: dict = field(default_factory=dict)

    def piece_at(self, p: float) -> TracePiece:
        for piece in self.pieces:
            if piece.contains(p):
                return piece
        lo = self.pieces[0].p_start if self.pieces else 0.0
        hi = self.pieces[-1].p_end if self.pieces else 0.0
        raise InvalidOptionError(f"p = {p} is outside the traced range [{lo:g}, {hi:g}] "
                                 f"(the trace ended: {self.end}; {self.message})")

    def z_at(self, p: float) -> np.ndarray:
        return self.piece_at(p).z(p)

    def w_at(self, p: float) -> np.ndarray:
        return self.piece_at(p).w(p)

    def plot_range(self) -> float:
        """The top of the default plot range: where the trace ended, or 1.5 x
        the last breakpoint (at least the last piece's start + 1) on an
        unbounded last piece."""
        if not self.pieces:
            return 1.0
        last = self.pieces[-1]
        if np.isfinite(last.p_end):
            return last.p_end if last.p_end > 0 else 1.0
        top = 1.5 * self.breakpoints[-1] if self.breakpoints.size else 0.0
        return max(top, last.p_start + 1.0)

    def plot(self, path, indices=None, labels=None, p_max: float | None = None) -> str:
        """Save a load-displacement plot: z_i against p for the chosen indices
        (default: every z that is ever positive, at most 12), breakpoints marked
        and labelled with their events.  The plot ends at ``p_max``, by
        default at :meth:`plot_range`.  Written atomically; returns the path."""
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        top = self.plot_range() if p_max is None else min(float(p_max), self._traced_top())
        ps = [0.0]
        for pc in self.pieces:
            end = min(pc.p_end, top)
            if end > pc.p_start:
                ps += list(np.linspace(pc.p_start, end, 3)[1:])
        zs = np.array([self.z_at(p) for p in ps]) if self.pieces else np.zeros((1, self.z.size))
        if indices is None:
            indices = np.flatnonzero(zs.max(axis=0) > 0)[:12]
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for k, i in enumerate(indices):
            ax.plot(ps, zs[:, i], label=labels[k] if labels else f"z[{i}]")
        for ev in self.events:
            if ev.p <= top:
                ax.axvline(ev.p, color="0.7", lw=0.8, ls="--")
                ax.annotate(ev.describe(), (ev.p, ax.get_ylim()[1]), rotation=90, fontsize=7,
                            va="top", ha="right", color="0.4")
        ax.set_xlabel("load parameter p")
        ax.set_ylabel("z (contact forces or gaps, the LCP's units)")
        ax.set_title(f"load trace: {len(self.breakpoints)} breakpoint(s), end: {self.end}")
        ax.grid(True, alpha=0.3)
        if len(indices):
            ax.legend(fontsize=8)
        fig.tight_layout()
        return save_figure(fig, path)

    def _traced_top(self) -> float:
        return self.pieces[-1].p_end if self.pieces else 0.0


_OPTIONS = ("p_max", "max_pieces")


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


class _Path:
    """The data of one trace, equilibrated once, and the operations on it."""

    def __init__(self, plcp: ParametricLCP):
        self.plcp = plcp
        self.M = dense_matrix(plcp.M)
        self.q0, self.q1 = plcp.q0, plcp.q1
        self.rs, self.cs = ruiz_scaling(self.M)
        self.Ms = self.M * self.rs[:, None] * self.cs[None, :]
        self.values = ComponentScales(self.M, np.abs(self.q0))
        self.slopes = ComponentScales(self.M, np.abs(self.q1))
        self.twins, self.unique = _null_structure(self.M)
        self.Ms_max = float(np.max(np.abs(self.Ms), initial=0.0)) or 1.0

    def q_terms(self, p: float) -> np.ndarray:
        return np.abs(self.q0) + abs(p) * np.abs(self.q1)

    def load_unit(self, p: float) -> float:
        """The load scale at p: p itself, or the p at which the variable load
        reaches the constant one (1 when either is absent: the problem is then
        homogeneous in p)."""
        q0, q1 = np.abs(self.q0).max(initial=0.0), np.abs(self.q1).max(initial=0.0)
        return max(abs(p), q0 / q1 if q0 > 0 and q1 > 0 else 1.0)

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

    def resolved_piece(self, p, F_prev, p_max, tol, accuracy):
        """A scheme found by Lemke's method at p + δ (δ tiny on the scale of p)
        that also holds at p, certified like any piece; or None."""
        from ..dispatch.driver import solve

        unit = self.load_unit(p)
        for rel in (1e-7, 1e-10):
            pp = p + rel * unit
            if np.isfinite(p_max) and pp >= p_max:
                pp = 0.5 * (p + p_max)
            sol = solve(self.plcp.at(pp), method="lemke", accuracy=accuracy)
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

    def collapse_proof(self, p: float, z_scale: float, tol: float,
                       max_nodes: int = COLLAPSE_NODES):
        """Prove that no solution exists for any load p' >= p_limit, p_limit a
        hair above p (1e-9, else 1e-6, else 1e-4 of the load scale): a dict with
        ``p_limit`` and the Farkas vectors; {"solution": (z, p')} when an
        equilibrium beyond p was found instead; None when neither.

        LCP(M, q(p')) has a solution only if one of its complementary patterns
        (z_i = 0 or w_i = 0 for each i) has a feasible point.  Branch and bound
        over the patterns, with p' as one more unknown >= p_limit: a node fixes
        some z_i = 0 and some w_i = 0 and

        - a Farkas vector y (y_i >= 0 on the inequalities, free on the fixed
          w's) with (M'y)_j <= 0 on the free z's, q1'y <= 0 and
          y'q(p_limit) < 0 proves it empty for every p' >= p_limit, since then
          y'w(p') = y'M z + y'q(p_limit) + (p' - p_limit) q1'y < 0 (:meth:`_farkas`);
        - otherwise an LP point (z, p') of it that is complementary is a
          solution beyond p (nothing to prove), and one that is not is split on
          its most violated pair.

        The root alone is the classical Farkas alternative; the branches are
        needed when only complementarity rules the loads out (a frame whose
        separated contacts could carry load only if they touched).

        Where M'y = 0 is an identity (a frame's equilibrium) rounding leaves
        (M'y)_j = δ_j > 0 of a few eps; then y'w <= δ'z + y'q(p') < 0 for
        every z with Σ z_j <= ``z_bound`` = -y'q(p_limit) / Σ δ_j, and a vector
        is accepted only when that bound exceeds Z_BOUND times ``z_scale`` (the
        solution's own size at p): "no equilibrium with openings and slips
        below 1000 times those at the last one".  A bound that small relative
        to the solution (seed 17 of the random frames: 4e-4 against slips of
        0.25, and Lemke found an equilibrium just beyond) proves nothing.
        """
        unit = self.load_unit(p)
        # At p = 0 with no constant load the solution is 0: the displacement
        # scale is then that of the load a unit further, |q| / max|M|.
        scale_M = float(np.abs(self.M).max(initial=0.0))
        if scale_M > 0:
            z_scale = max(z_scale, float(self.q_terms(p + unit).max(initial=0.0)) / scale_M)
        # Just beyond p every LP point is within ~(p' - p) of the last
        # equilibrium, which an LP's tolerances cannot tell from feasible: if the
        # proof does not go through a hair above p it is tried a little further.
        # A "solution" a hair above p may be the last equilibrium itself, within
        # the tolerances; it is believed only if the proof fails further out too.
        found = None
        for rel in (1e-9, 1e-6, 1e-4):
            out = self._branch_and_bound(p + rel * unit, unit, z_scale, tol, max_nodes)
            if out is not None and "solution" not in out:
                return out
            found = out or found
        return found

    def _branch_and_bound(self, p_lo, unit, z_scale, tol, max_nodes):
        n = self.q0.size
        stack = [(np.zeros(n, bool), np.zeros(n, bool))]
        leaves, nodes = [], 0
        while stack:
            nodes += 1
            if nodes > max_nodes:
                return None
            Z0, W0 = stack.pop()
            cert = self._farkas(Z0, W0, p_lo, z_scale, tol)
            if cert is not None:
                leaves.append((np.flatnonzero(Z0), np.flatnonzero(W0)) + cert)
                continue
            found = self._pattern_point(Z0, W0, p_lo, unit)
            if found is None:
                return None   # empty by the LP, but without a certificate that checks
            z, pp = found
            w = self.M @ z + self.q0 + pp * self.q1
            zeta, sigma = self.values.at(z, self.q_terms(pp))
            with np.errstate(divide="ignore", invalid="ignore"):
                zr = np.where(zeta > 0, z / zeta, np.inf * (z > 0))
                wr = np.where(sigma > 0, w / sigma, np.sign(w) * np.inf)
            # The point only guides the branching.  A row it violates on its own
            # scale (the LP's tolerance) is split first; a complementary point
            # that holds is a solution beyond p: nothing to prove.
            open_ = ~(Z0 | W0)
            viol = np.where(open_, np.minimum(zr, np.maximum(wr, 0.0)), 0.0)
            bad = np.where(open_, -wr, 0.0)
            if bad.max() > TIE_RTOL:
                i = int(np.argmax(bad))
            elif viol.max() > TIE_RTOL:
                i = int(np.argmax(viol))
            elif np.all(wr[~W0] >= -TIE_RTOL) and np.all(np.abs(wr[W0]) <= TIE_RTOL):
                return {"solution": (z, pp)}
            else:
                return None
            Zc = Z0.copy()
            Zc[i] = True
            Wc = W0.copy()
            Wc[i] = True
            stack += [(Zc, W0), (Z0, Wc)]
        root = leaves[0] if len(leaves) == 1 and not leaves[0][0].size and not leaves[0][1].size else None
        return {"p_limit": p_lo, "patterns": len(leaves), "nodes": nodes,
                "backward_error": max(leaf[3] for leaf in leaves),
                "z_bound": min(leaf[4] for leaf in leaves),
                "farkas": root[2] if root is not None else None,
                "leaves": [{"z_zero": lf[0], "w_zero": lf[1], "y": lf[2]} for lf in leaves]}

    def _pattern_point(self, Z0, W0, p_lo, unit):
        """(z, p') with p' >= p_lo, z >= 0, w(p') >= 0, z_Z0 = 0, w_W0 = 0 and p'
        as small as the LP finds; None when the LP finds none (equilibrated)."""
        from scipy.optimize import linprog

        J, I, W = np.flatnonzero(~Z0), np.flatnonzero(~W0), np.flatnonzero(W0)
        n = self.q0.size
        Ms = self.Ms
        q_lo, q1 = self.rs * (self.q0 + p_lo * self.q1), self.rs * self.q1 * unit
        a = self.Ms_max
        # unknowns (z'_J, s): z = C z', p' = p_lo + unit * s; minimize s
        A = np.column_stack([Ms[:, J], q1]) / a
        c = np.zeros(J.size + 1)
        c[-1] = 1.0
        res = linprog(c, A_ub=-A[I] if I.size else None, b_ub=q_lo[I] / a if I.size else None,
                      A_eq=A[W] if W.size else None, b_eq=-q_lo[W] / a if W.size else None,
                      bounds=(0, None), method="highs", options=_LP_OPTIONS)
        if res.status != 0:
            return None
        z = np.zeros(n)
        z[J] = np.maximum(res.x[:-1], 0.0) * self.cs[J]
        pp = p_lo + unit * max(float(res.x[-1]), 0.0)
        # Polish the vertex on the original data: the rows the LP holds at zero
        # (and the fixed w's) with its positive z's (and p' when it moved off p_lo)
        # solved exactly — HiGHS's tolerances are absolute, the checks are not.
        w = self.M @ z + self.q0 + pp * self.q1
        _, sigma = self.values.at(z, self.q_terms(pp))
        tight = W0 | (np.abs(w) <= 1e-7 * np.maximum(sigma, 1e-300))
        S = np.flatnonzero(z > 0)
        free_p = pp > p_lo
        A = self.M[np.ix_(np.flatnonzero(tight), S)]
        if free_p:
            A = np.column_stack([A, self.q1[tight]])
        if A.size:
            x = np.linalg.lstsq(A, -(self.q0 + (0.0 if free_p else pp) * self.q1)[tight],
                                rcond=None)[0]
            cand = np.zeros(n)
            cand[S] = x[:S.size]
            p_c = float(x[-1]) if free_p else pp
            if np.all(cand >= 0) and p_c >= p_lo:
                z, pp = cand, p_c
        return z, pp

    def _farkas(self, Z0, W0, p_lo, z_scale, tol):
        """(y, backward, z_bound) proving {z >= 0, w(p') >= 0, z_Z0 = 0, w_W0 = 0}
        empty for every p' >= p_lo and every z below z_bound, checked from the
        data; or None.

        LP: min y'q(p_lo) over y_i in [0, 1] (i not in W0), y_i in [-1, 1]
        (i in W0), (M'y)_j <= 0 for the free z's (to a slack of 1e-10 of their
        terms), q1'y <= 0; a negative optimum is a Farkas vector.  It is polished
        on its support and checked by :meth:`_farkas_check`.
        """
        from scipy.optimize import linprog, lsq_linear

        n = self.q0.size
        J = np.flatnonzero(~Z0)
        Ms, qs, q1s = self.Ms, self.rs * (self.q0 + p_lo * self.q1), self.rs * self.q1
        a = self.Ms_max
        b = float(np.max(np.abs(q1s))) or 1.0
        c = float(np.max(np.abs(qs))) or 1.0
        # Where M'y = 0 is an identity its rounding decides the sign, so the LP
        # gets a little slack: with none it was infeasible or not depending on
        # the number of BLAS threads.  What the slack lets through is bounded
        # in _farkas_check.
        slack = min(0.5 * tol, 1e-10)
        rows = [(Ms[:, J].T - slack * np.abs(Ms[:, J]).T) / a] if J.size else []
        rows.append((q1s - slack * np.abs(q1s))[None, :] / b)
        bounds = [(-1, 1) if W0[i] else (0, 1) for i in range(n)]
        res = linprog(qs / c, A_ub=np.vstack(rows), b_ub=np.zeros(J.size + 1), bounds=bounds,
                      method="highs", options=_LP_OPTIONS)
        if res.status != 0 or not res.fun < 0:
            return None
        y0 = res.x * self.rs
        best = self._farkas_check(y0, J, W0, p_lo, z_scale)
        R = np.flatnonzero(np.abs(y0) > 1e-12 * np.abs(y0).max())
        if R.size:  # polish: M'y = 0 on the tight columns, y'q(p_lo) as found, on y's support
            My, scale = self.M[:, J].T @ y0, np.abs(self.M[:, J]).T @ np.abs(y0)
            T = J[My >= -1e-8 * scale]
            q_lo = self.q0 + p_lo * self.q1
            rows = [self.M[np.ix_(R, T)].T, q_lo[R][None, :]]
            rhs = [np.zeros(T.size), [float(q_lo @ y0)]]
            if float(self.q1 @ y0) >= -1e-8 * float(np.abs(self.q1) @ np.abs(y0)):
                rows.append(self.q1[R][None, :])
                rhs.append([0.0])
            # bounded least squares: y stays >= 0 on the inequality rows
            lower = np.where(W0[R], -np.inf, 0.0)
            yR = lsq_linear(np.vstack(rows), np.concatenate(rhs), bounds=(lower, np.inf),
                            method="bvls", tol=1e-15).x
            y = np.zeros(n)
            y[R] = yR
            polished = self._farkas_check(y, J, W0, p_lo, z_scale)
            if polished is not None and (best is None or polished[2] > best[2]):
                best = polished
        if best is None or not best[1] <= tol:
            return None
        return best

    def _farkas_check(self, y, J, W0, p_lo, z_scale):
        """(y, backward, z_bound) for a candidate y, or None when it proves nothing.

        With δ = max(M_J'y, 0) and g = -y'q(p_lo) (less the rounding of q's
        terms): y'w(p') <= δ'z - g < 0 for every z >= 0 with Σ z_j < z_bound =
        g / Σ δ_j (inf when δ = 0), and for every p' >= p_lo when q1'y <= 0 (to
        FARKAS_RTOL of its terms).  Accepted when z_bound >= Z_BOUND * z_scale.
        ``backward`` = max δ_j / (|M|'|y|)_j is reported beside it.
        """
        if np.any(y[~W0] < 0):
            return None
        ay = np.abs(y)
        My, scale = self.M[:, J].T @ y, np.abs(self.M[:, J]).T @ ay
        q1y, q1s = float(self.q1 @ y), float(np.abs(self.q1) @ ay)
        if q1y > FARKAS_RTOL * q1s:
            return None
        delta = np.maximum(My, 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(delta > 0, delta / scale, 0.0)
        backward = max(FARKAS_RTOL, float(np.max(ratio, initial=0.0)))
        gap = -float((self.q0 + p_lo * self.q1) @ y) \
            - FARKAS_RTOL * float((np.abs(self.q0) + p_lo * np.abs(self.q1)) @ ay)
        if not (np.isfinite(backward) and gap > 0):
            return None
        total = float(delta.sum())
        z_bound = gap / total if total > 0 else np.inf
        if not z_bound >= Z_BOUND * z_scale:
            return None
        return y, backward, z_bound


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


def _start(plcp: ParametricLCP, accuracy):
    """A certified solution at p = 0."""
    n = plcp.n
    if np.all(plcp.q0 >= 0):
        return np.zeros(n)
    from ..dispatch.driver import solve

    sol = solve(plcp.at(0.0), method="lemke", accuracy=accuracy)
    if sol.ok:
        return sol.z
    proved = sol.stats.get("proved_infeasible", False)
    raise NoSolutionError(
        "the constant load alone (p = 0) has no equilibrium"
        + (" (proved: " if proved else " that Lemke's method can find (")
        + f"{sol.message}); a load trace needs an equilibrium to start from"
    )


def trace_load(plcp: ParametricLCP, *, accuracy="high", p_max: float = 1.0,
               max_pieces: int | None = None) -> LoadTrace:
    """Trace the solution of ``plcp`` for p from 0 to ``p_max`` (see module docstring).

    Parameters
    ----------
    plcp : ParametricLCP
    accuracy : level or float
        Tolerance every piece is certified at (:mod:`qpcontact.accuracy`).
    p_max : float
        Stop at this load parameter (``np.inf``: follow until the scheme stops
        changing, or no equilibrium continues the path).
    max_pieces : int, optional
        Default max(1000, 20 n).

    Raises
    ------
    NoSolutionError
        The constant load alone has no solution (nothing to start from).
    """
    if not isinstance(plcp, ParametricLCP):
        raise InvalidProblemError(f"'trace' takes a ParametricLCP; got {type(plcp).__name__}")
    try:
        p_max = float(p_max)
    except (TypeError, ValueError):
        raise InvalidOptionError(f"'trace': p_max must be a number > 0, got {p_max!r}") from None
    if not p_max > 0:
        raise InvalidOptionError(f"'trace': p_max must be > 0, got {p_max}")
    n = plcp.n
    check_dense_size("trace", n, f"{n} x {n} block", "fixed loads with problem.at(p)")
    max_pieces = int_option("trace", {} if max_pieces is None else {"max_pieces": max_pieces},
                            "max_pieces", max(1000, 20 * n), minimum=1)
    _, tol = resolve_accuracy(accuracy)
    start = time.perf_counter()
    path = _Path(plcp)

    z = _start(plcp, accuracy)
    p = 0.0
    w = path.M @ z + plcp.q0
    F_prev = np.zeros(n, bool)
    pieces: list[TracePiece] = []
    events: list[TraceEvent] = []
    end, proof, why = None, {}, ""
    worst = 0.0
    checked = 0
    while True:
        found, exhaustive = path.continuation(p, z, w, F_prev, 50 * n + 1000)
        resolved = False
        accepted = None
        for F, block, dz, dw in found:
            accepted = path.certified_piece(block, F, p, dz, dw, p_max, tol)
            if accepted is not None:
                break
        if accepted is None:
            # Nothing from the vertex's own schemes: a solve just beyond p, kept
            # only if its scheme certifies back at p (the path is then continuous).
            accepted = path.resolved_piece(p, F_prev if pieces else None, p_max, tol, accuracy)
            resolved = accepted is not None
        beyond = None
        if accepted is None:
            zeta_end, _ = path.values.at(z, path.q_terms(p))
            found_y = path.collapse_proof(p, max(float(np.abs(z).max(initial=0.0)),
                                                 float(zeta_end.max(initial=0.0)), 1e-300), tol)
            if found_y is not None and "solution" in found_y:
                # an equilibrium just beyond p that the vertex's schemes did not
                # reach (M's null vectors): continue from its scheme if it holds at p
                beyond = found_y["solution"][1]
                accepted = path.piece_through(p, F_prev if pieces else None, *found_y["solution"],
                                              p_max, tol)
                resolved = accepted is not None
                found_y = None
        if accepted is None:
            if found_y is not None:
                end = "collapse"
                proof = found_y
            elif exhaustive and path.unique:
                end = "fold"
                proof = {"p": p, "schemes_checked": "all"}
            else:
                end = "breakdown"
                why = (f"at p = {p:g} no working scheme that continues the path could be found "
                       "and certified" + ("" if path.unique else
                                          " (M has null vectors: the same forces can be written "
                                          "with other unknowns, so not every scheme was tried)")
                       + (f"; an equilibrium exists at p = {beyond:.10g}, on another branch"
                          if beyond is not None else
                          ", and no equilibrium could be proved impossible beyond it"))
            break
        piece, t, i_cross, cross_z = accepted
        F = piece.active
        worst = max(worst, piece.error)
        checked += 3
        if pieces:
            events.append(TraceEvent(p, np.flatnonzero(F & ~F_prev), np.flatnonzero(F_prev & ~F),
                                     0 if resolved else path.distinct(found), resolved))
        pieces.append(piece)
        if np.isfinite(p_max) and piece.p_end == p_max:
            end = "p_max"
            break
        if not np.isfinite(piece.p_end):
            end = "unbounded"
            proof = {"from": p, "dz": piece.dz, "dw": piece.dw}
            break
        if len(pieces) >= max_pieces:
            end = "max_pieces"
            break
        p = piece.p_end
        z = piece.z_start + t * piece.dz
        w = piece.w_start + t * piece.dw
        # the row that reached zero is zero (not a rounding error's worth off)
        if cross_z:
            z[i_cross] = 0.0
        else:
            w[i_cross] = 0.0
        z = np.maximum(z, 0.0)
        F_prev = F
    wall = time.perf_counter() - start

    last = pieces[-1] if pieces else None
    p_final = (last.p_end if np.isfinite(last.p_end) else last.p_start) if last else 0.0
    z_fin = last.z(p_final) if last else np.maximum(z, 0.0)
    lcp_final = plcp.at(p_final)
    cert = certify_lcp(lcp_final, z_fin)
    breakpoints = np.array([pc.p_end for pc in pieces[:-1]])
    status = {"breakdown": "failed", "max_pieces": "max_pivots"}.get(end, "solved")
    if status == "solved" and not cert.ok(tol):
        status = "inaccurate"
    message = _message(end, p, p_max, p_final, proof, why, max_pieces)
    message += f"; {len(breakpoints)} breakpoint(s)"
    ambiguous = sum(ev.continuations > 1 for ev in events)
    if ambiguous:
        message += (f"; at {ambiguous} breakpoint(s) several working schemes continued the path "
                    "(non-P matrix; the one closest to the previous scheme was followed)")
    return LoadTrace(
        method="trace", status=status, ok=status == "solved", message=message,
        accuracy=accuracy, tol=tol, certificate=cert, backend_status=end,
        wall_time=wall, iterations=len(pieces),
        stats={"pieces": len(pieces), "worst_piece_error": worst, "certified_points": checked,
               "ambiguous_breakpoints": ambiguous},
        z=z_fin, w=lcp_final.w(z_fin), pieces=pieces, breakpoints=breakpoints, events=events,
        end=end, p_end=p_final, proof=proof,
    )


def _message(end, p, p_max, p_final, proof, why, max_pieces) -> str:
    if end == "p_max":
        return f"traced to p = {p_max:g}"
    if end == "unbounded":
        return (f"the working scheme no longer changes for p >= {proof['from']:g}: the solution "
                "grows along proof['dz'] without bound")
    if end == "collapse":
        how = ("by a Farkas vector" if proof["patterns"] == 1 else
               f"over {proof['patterns']} patterns of which z's and w's are zero, each by a Farkas "
               "vector")
        bound = ("" if not np.isfinite(proof["z_bound"]) else
                 f", for every z with sum below {proof['z_bound']:.1e}")
        return (f"no equilibrium exists for p >= {proof['p_limit']:.10g} (proved {how}, "
                f"checked from the data{bound}); the last equilibrium is at p = {p_final:.10g}")
    if end == "fold":
        return (f"the path turns back at p = {p:.10g}: no working scheme continues it with the load "
                "increasing (every scheme of the degenerate pairs checked; M is not a P-matrix, "
                "so other equilibria may exist beyond — solve problem.at(p) for them)")
    if end == "max_pieces":
        return f"piece limit {max_pieces} reached at p = {p:g}"
    return why


def solve_parametric(plcp: ParametricLCP, method: str, accuracy, raise_on_failure: bool,
                     options: dict) -> LoadTrace:
    """What :func:`qpcontact.solve` does with a ParametricLCP."""
    if method not in ("trace", "auto"):
        raise InvalidProblemError(
            f"a ParametricLCP is a family of LCPs; method {method!r} solves one LCP — use "
            "method='trace' to follow the load, or fix it with problem.at(p)"
        )
    check_options("trace", options, _OPTIONS)
    tr = trace_load(plcp, accuracy=accuracy, **options)
    if raise_on_failure and not tr.ok:
        raise SolverFailedError(f"trace: {tr.message}")
    return tr
