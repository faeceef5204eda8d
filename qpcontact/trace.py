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
3. Each piece is computed from its own block (LU of the equilibrated M_FF,
   iteratively refined), certified from the data at its start, middle and end
   (:func:`qpcontact.certify.certify_lcp`), and only then kept.

Endings (``LoadTrace.end``), each with what proves it
-----------------------------------------------------
``"p_max"``      the requested load was reached.
``"unbounded"``  (p_max = inf) the last scheme never changes again: no z_i or
                 w_i decreases along its direction, which is in ``proof``.
``"collapse"``   no equilibrium exists beyond the end point: a Farkas vector
                 y >= 0 with M'y <= 0 and y'q(p) < 0 for every p > p_limit,
                 found by an LP and checked component by component from the
                 data (``proof["farkas"]``): y'w = y'Mz + y'q(p) < 0 for any
                 z >= 0, so w >= 0 is impossible.
``"fold"``       equilibria may exist beyond the end point, but none continues
                 this path: all 2^|β| schemes at the vertex were checked and
                 none goes on with p increasing (a non-P matrix, e.g. friction:
                 the load-displacement path turns back).  Solve at a fixed load
                 with ``problem.at(p)`` to find other branches.
``"breakdown"``  the path could not be continued or certified (a degenerate
                 vertex too large to enumerate that Lemke's method could not
                 decide, or a piece whose certificate failed): the pieces before
                 it are returned, the failing one is not.
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

from .accuracy import resolve_accuracy
from .certify import ComponentScales, certify_lcp
from .errors import InvalidOptionError, InvalidProblemError, NoSolutionError, SolverFailedError
from .methods.active_set import check_dense_size, check_options, dense_matrix
from .methods.lemke import FARKAS_RTOL, lemke, ruiz_scaling
from .plotting import save_figure
from .problems import ParametricLCP
from .solution import LCPSolution

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
SINGULAR_RCOND = 1e-13
#: Most degenerate pairs at one vertex decided by checking every scheme.
ENUM_MAX = 10


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
    grow).  ``continuations`` is how many working schemes could continue the
    path there (1 unless M is not a P-matrix)."""

    p: float
    entered: np.ndarray
    left: np.ndarray
    continuations: int = 1

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
        raise ValueError(f"p = {p} is outside the traced range [{lo:g}, {hi:g}] "
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
        x = scipy.linalg.lu_solve(self.lu, rhs, check_finite=False)
        r = rhs - self.B @ x
        rn = np.max(np.abs(r))
        for _ in range(3):
            if rn == 0.0:
                break
            x_new = x + scipy.linalg.lu_solve(self.lu, r, check_finite=False)
            r_new = rhs - self.B @ x_new
            rn_new = np.max(np.abs(r_new))
            if not rn_new < rn:
                break
            x, r, rn = x_new, r_new, rn_new
        return x


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
        self.twin = _twins(self.M)

    def q_terms(self, p: float) -> np.ndarray:
        return np.abs(self.q0) + abs(p) * np.abs(self.q1)

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
        """The scheme that continues the path from (p, z, w): (F, block, dz, dw,
        count) or None; and whether every scheme was checked (exhaustive)."""
        alpha, beta, gamma, clash = self.classify(p, z, w)
        if clash:
            return None, True
        # A degenerate z whose twin (a column that is its exact negative: the two
        # slip parts of one contact) is positive cannot be basic — the block
        # would be singular — so it is decided without enumeration.
        forced = np.array([i for i in np.flatnonzero(beta)
                           if self.twin[i] >= 0 and alpha[self.twin[i]]], dtype=int)
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
        if not found:
            return None, exhaustive
        F, block, dz, dw = min(found, key=lambda c: int(np.sum(c[0] != F_prev)))
        return (F, block, dz, dw, self._distinct(found)), exhaustive

    def _distinct(self, found) -> int:
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

    def collapse_proof(self, tol: float):
        """A Farkas vector proving that no solution exists for p > p_limit:
        (p_limit, y, backward) or None.

        LP (equilibrated): min q0'y over y >= 0, M'y <= 0, q1'y = -1; its answer
        is polished on its support (least squares on the tight columns) and
        accepted when each component of M'y is <= ``backward`` times its own
        terms (|M|'y)_j with backward <= tol: then y'(Mz + q(p)) < 0 for every
        z >= 0 and p > p_limit, for data within ``backward`` (componentwise) of
        yours — the same reading as a solution's certificate.  Where M'y = 0 is
        an identity (a frame's equilibrium equations), rounding of the assembly
        is all that is left of it.
        """
        from scipy.optimize import linprog

        n = self.q0.size
        Ms, q0s, q1s = self.Ms, self.rs * self.q0, self.rs * self.q1
        a = float(np.max(np.abs(Ms))) or 1.0
        b = float(np.max(np.abs(q1s))) or 1.0
        c = float(np.max(np.abs(q0s))) or 1.0
        A_ub = (Ms.T - 0.5 * FARKAS_RTOL * np.abs(Ms).T) / a
        res = linprog(q0s / c, A_ub=A_ub, b_ub=np.zeros(n), A_eq=(q1s / b)[None, :],
                      b_eq=[-1.0], bounds=(0, None), method="highs")
        if res.status != 0:
            return None
        best = None
        for y in (np.maximum(res.x * self.rs, 0.0), None):
            if y is None:  # polish: M'y = 0 on the tight columns, q1'y = -1, on y's support
                y0 = best[1] if best is not None else np.maximum(res.x * self.rs, 0.0)
                R = np.flatnonzero(y0 > 1e-12 * y0.max()) if y0.max() > 0 else np.empty(0, int)
                if R.size == 0:
                    break
                My, scale = self.M.T @ y0, np.abs(self.M).T @ y0
                J = np.flatnonzero(My >= -1e-8 * scale)
                A = np.vstack([self.M[np.ix_(R, J)].T, self.q1[R][None, :]])
                rhs = np.r_[np.zeros(J.size), float(self.q1 @ y0)]
                yR = np.linalg.lstsq(A, rhs, rcond=None)[0]
                if np.any(yR < 0):
                    break
                y = np.zeros(n)
                y[R] = yR
            checked = self._farkas_check(y)
            if checked is not None and (best is None or checked[2] < best[2]):
                best = checked
        if best is None or not best[2] <= tol:
            return None
        return best

    def _farkas_check(self, y):
        """(p_limit, y, backward) for a candidate y, or None when it proves nothing."""
        My, scale = self.M.T @ y, np.abs(self.M).T @ y
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(My > 0, My / scale, 0.0)
        backward = max(FARKAS_RTOL, float(np.max(ratio, initial=0.0)))
        if not np.isfinite(backward):
            return None
        a0 = float(self.q0 @ y) + backward * float(np.abs(self.q0) @ y)
        b1 = -float(self.q1 @ y) - backward * float(np.abs(self.q1) @ y)
        if not b1 > 0:
            return None
        return a0 / b1, y, backward


def _twins(M: np.ndarray) -> np.ndarray:
    """twin[j] = k when column k of M is column j negated (to rounding), else -1.

    Such a pair is a null vector e_j + e_k of M: z_j and z_k describe one
    motion in opposite directions (the slip parts Z+ and Z- of a frictional
    contact), and a scheme with both basic is singular.
    """
    n = M.shape[1]
    twin = np.full(n, -1)
    norms = np.linalg.norm(M, axis=0)
    nz = np.flatnonzero(norms > 0)
    if nz.size < 2:
        return twin
    A = M[:, nz] / norms[nz]
    G = A.T @ A
    absM = np.abs(M)
    for a, b in zip(*np.nonzero(np.triu(G < -1 + 1e-12, 1))):
        j, k = nz[a], nz[b]
        if np.all(np.abs(M[:, j] + M[:, k]) <= 1e3 * np.finfo(float).eps * (absM[:, j] + absM[:, k])):
            twin[j], twin[k] = k, j
    return twin


def _start(plcp: ParametricLCP, accuracy):
    """A certified solution at p = 0."""
    n = plcp.n
    if np.all(plcp.q0 >= 0):
        return np.zeros(n)
    from .solve import solve

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
    if max_pieces is None:
        max_pieces = max(1000, 20 * n)
    if not isinstance(max_pieces, (int, np.integer)) or max_pieces < 1:
        raise InvalidOptionError(f"'trace': max_pieces must be a positive integer, got {max_pieces!r}")
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
        cont, exhaustive = path.continuation(p, z, w, F_prev, 50 * n + 1000)
        if cont is None:
            found = path.collapse_proof(tol)
            scale_p = max(abs(p), 1e-300)
            if found is not None and found[0] <= p + 1e-8 * max(scale_p, _p_unit(plcp, found[1])):
                end = "collapse"
                proof = {"p_limit": found[0], "farkas": found[1], "backward_error": found[2],
                         "rows": np.flatnonzero(found[1] > 1e-9 * found[1].max())}
            elif exhaustive:
                end = "fold"
                proof = {"p": p, "schemes_checked": "all"}
                if found is not None:
                    proof["no_equilibrium_beyond"] = found[0]
            else:
                end = "breakdown"
                why = (f"at p = {p:g} more than {ENUM_MAX} pairs are degenerate and Lemke's method "
                       "found no working scheme that continues the path")
            break
        F, block, dz, dw, count = cont
        piece = path.piece(block, F, p, dz, dw)
        t, i_cross, cross_z = path.next_break(piece)
        p_next = p + t
        stop = np.isfinite(p_max) and p_next >= p_max
        piece.p_end = p_max if stop else p_next
        # certify from the data at the start, the middle and the end
        hi = piece.p_end if np.isfinite(piece.p_end) else p + max(1.0, abs(p))
        err = 0.0
        for pp in (p, 0.5 * (p + hi), hi):
            err = max(err, certify_lcp(plcp.at(pp), piece.z(pp)).error)
        checked += 3
        if not err <= tol:
            end = "breakdown"
            why = (f"the working scheme from p = {p:g} could not be certified "
                   f"(error {err:.1e} > {tol:.0e}); the trace stops there")
            break
        piece.error = err
        worst = max(worst, err)
        if pieces:
            events.append(TraceEvent(p, np.flatnonzero(F & ~F_prev), np.flatnonzero(F_prev & ~F),
                                     count))
        pieces.append(piece)
        if stop:
            end = "p_max"
            break
        if not np.isfinite(p_next):
            end = "unbounded"
            proof = {"from": p, "dz": dz, "dw": dw}
            break
        if len(pieces) >= max_pieces:
            end = "max_pieces"
            break
        p = p_next
        z = piece.z_start + t * piece.dz
        w = piece.w_start + t * piece.dw
        # the rows that reached zero are zero (not a rounding error's worth off)
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


def _p_unit(plcp: ParametricLCP, y: np.ndarray) -> float:
    """The change of p that moves y'q by the size of its constant terms."""
    den = float(np.abs(plcp.q1) @ y)
    return float(np.abs(plcp.q0) @ y) / den if den > 0 else 0.0


def _message(end, p, p_max, p_final, proof, why, max_pieces) -> str:
    if end == "p_max":
        return f"traced to p = {p_max:g}"
    if end == "unbounded":
        return (f"the working scheme no longer changes for p >= {proof['from']:g}: the solution "
                "grows along proof['dz'] without bound")
    if end == "collapse":
        return (f"no equilibrium exists for p > {proof['p_limit']:.10g} (proved by a Farkas "
                f"vector checked from the data to {proof['backward_error']:.0e} componentwise, "
                f"rows {[int(i) for i in proof['rows']]}); the last equilibrium is at "
                f"p = {p_final:.10g}")
    if end == "fold":
        extra = (f"; no equilibrium at all beyond p = {proof['no_equilibrium_beyond']:.6g}"
                 if "no_equilibrium_beyond" in proof else "")
        return (f"the path turns back at p = {p:.10g}: no working scheme continues it with the load "
                "increasing (every scheme of the degenerate pairs checked; M is not a P-matrix, "
                f"so other equilibria may exist beyond — solve problem.at(p) for them){extra}")
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
