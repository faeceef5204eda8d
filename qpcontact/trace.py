"""``"trace"``: follow the solution of a parametric LCP as the load grows (P3).

For ``ParametricLCP(M, q0, q1)``, w = M z + q0 + p q1: q0 is the constant load
(gaps, dead weight), q1 the variable load scaled by the load parameter p >= 0.
The increasing-load algorithm of Osipova, Popov & Lovtsov is Lemke's scheme with
p as the driving variable in the tableau

    w - M z - q1 p = q0.

1. Start from a solution at p = 0: z = 0 when q0 >= 0 (P3's cases a and b),
   otherwise the solution Lemke's method finds for LCP(M, q0) (case c).
2. p enters the basis; a lexicographic ratio test picks the leaving variable;
   from then on the complement of the variable that left enters.  Along each
   edge the point is complementary and moves affinely with p, so every vertex is
   a *breakpoint* p_k where the working scheme changes (a support lifts off,
   closes, starts or stops slipping).
3. The trace ends when p reaches ``p_max`` ("p_max"); when the entering column
   has no positive entry and p grows without bound along it ("ray": the working
   scheme no longer changes as the load grows); when it has none and p stays
   fixed ("mechanism": displacements grow without bound at a finite load); when
   p decreases back to 0 ("returned"); or at the pivot limit ("max_pivots").

No artificial right-hand side is added: degenerate starts (q0 = 0, case a, or
zero gaps) are handled by the lexicographic rule, so every reported state
satisfies the LCP of the real data.  Each piece's solution is recomputed from its
active block, z_F(p) = -M_FF^{-1} (q0_F + p q1_F), w = M z + q0 + p q1, and
certified at its ends and midpoint.

For non-P matrices (Coulomb friction) p can decrease along an edge: the load-
displacement path folds back and several solutions exist at those loads.  Such
pieces are reported as they are, with p_start > p_end.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from .accuracy import resolve_accuracy
from .certify import certify_lcp
from .errors import InvalidOptionError, InvalidProblemError, NoSolutionError, SolverFailedError
from .methods.active_set import ActiveBlock, check_dense_size, check_options, dense_matrix
from .methods.lemke import PIVOT_RTOL, RowScales, lemke, lex_ratio_test, ruiz_scaling, tableau_pivot
from .plotting import save_figure
from .problems import ParametricLCP
from .solution import LCPSolution

__all__ = ["TracePiece", "LoadTrace", "trace_load", "END_REASONS"]

END_REASONS = ("p_max", "ray", "mechanism", "returned", "max_pivots")


@dataclass
class TracePiece:
    """One interval of the load parameter on which the working scheme is fixed.

    ``active`` marks the z's that are basic (contacts closed, or the LCP's
    unknowns that are free) on the interval; on it ``z(p) = z_start + (p -
    p_start) dz`` and ``w(p) = w_start + (p - p_start) dw`` exactly.
    ``p_end`` is inf on a final ray.
    """

    p_start: float
    p_end: float
    active: np.ndarray
    z_start: np.ndarray
    dz: np.ndarray
    w_start: np.ndarray
    dw: np.ndarray

    def z(self, p: float) -> np.ndarray:
        return self.z_start + (p - self.p_start) * self.dz

    def w(self, p: float) -> np.ndarray:
        return self.w_start + (p - self.p_start) * self.dw

    def contains(self, p: float) -> bool:
        lo, hi = sorted((self.p_start, self.p_end))
        return lo <= p <= hi


@dataclass(kw_only=True)
class LoadTrace(LCPSolution):
    """The solution path of a ParametricLCP: an ``LCPSolution`` for the final
    state (z, w at ``p_end``, certified) plus the pieces and breakpoints.

    ``status`` is "solved" when every piece was certified (ends and midpoint) at
    the requested accuracy, "inaccurate" when one was not, "max_pivots" at the
    pivot limit.  ``end`` says why the trace stopped (:data:`END_REASONS`).
    """

    pieces: list = field(default_factory=list)
    breakpoints: np.ndarray = field(default_factory=lambda: np.empty(0))
    end: str = ""
    p_end: float = 0.0

    def piece_at(self, p: float) -> TracePiece:
        for piece in self.pieces:
            if piece.contains(p):
                return piece
        raise ValueError(f"p = {p} is outside the traced range")

    def z_at(self, p: float) -> np.ndarray:
        return self.piece_at(p).z(p)

    def w_at(self, p: float) -> np.ndarray:
        return self.piece_at(p).w(p)

    def plot(self, path, indices=None, labels=None, p_max: float | None = None) -> str:
        """Save a load-displacement plot: z_i against p for the chosen indices
        (default: every z that is ever positive, at most 12), breakpoints marked.
        The plot ends at ``p_max``, by default where the trace ended (a final
        ray: 1.5 x the last breakpoint).
        Written atomically (temporary file, then rename); returns the path."""
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        last = self.breakpoints[-1] if self.breakpoints.size else 1.0
        if p_max is not None:
            top = p_max
        elif self.pieces and np.isfinite(self.pieces[-1].p_end):
            top = self.pieces[-1].p_end
        else:
            top = max(1.5 * last, 1.0)
        ps = [0.0]
        for pc in self.pieces:
            end = pc.p_end if np.isfinite(pc.p_end) else top
            ps += list(np.linspace(pc.p_start, end, 3)[1:])
        zs = np.array([self.z_at(min(p, top)) if self.pieces else self.z for p in ps])
        if indices is None:
            indices = np.flatnonzero(zs.max(axis=0) > 0)[:12]
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for k, i in enumerate(indices):
            ax.plot(ps, zs[:, i], label=labels[k] if labels else f"z[{i}]")
        for pk in self.breakpoints:
            ax.axvline(pk, color="0.7", lw=0.8, ls="--")
        ax.set_xlabel("load parameter p")
        ax.set_ylabel("z (contact forces or gaps, the LCP's units)")
        ax.set_title(f"load trace: {len(self.breakpoints)} breakpoint(s), end: {self.end}")
        ax.grid(True, alpha=0.3)
        if len(indices):
            ax.legend(fontsize=8)
        fig.tight_layout()
        return save_figure(fig, path)


_OPTIONS = ("p_max", "max_pivots")


def _start_basis(Ms, q0s, max_pivots):
    """Complementary basis valid at p = 0 (bool mask of basic z's)."""
    n = q0s.size
    if np.all(q0s >= 0):
        return np.zeros(n, bool), 0
    out = lemke(Ms, q0s, np.ones(n), max_pivots)
    if out.status != "solved":
        raise NoSolutionError(
            f"the constant load alone (p = 0) has no solution Lemke's method can find "
            f"({out.status}); a load trace needs an equilibrium to start from"
        )
    return out.basic_z, out.pivots


def _piece(plcp, M, active, p_a, p_b, z_a_tab, dz_tab) -> TracePiece:
    """Exact affine piece from the active block; the tableau's values if it is singular."""
    q0, q1 = plcp.q0, plcp.q1
    try:
        block = ActiveBlock(M, active, symmetric=False)
        z_a = np.zeros(q0.size)
        dz = np.zeros(q0.size)
        F = block.F
        if F.size:
            z_a[F] = block.solve(-(q0[F] + p_a * q1[F]))
            dz[F] = block.solve(-q1[F])
    except np.linalg.LinAlgError:
        z_a, dz = z_a_tab, dz_tab
    w_a = M @ z_a + q0 + p_a * q1
    dw = M @ dz + q1
    return TracePiece(float(p_a), float(p_b), active.copy(), z_a, dz, w_a, dw)


def trace_load(plcp: ParametricLCP, *, accuracy="high", p_max: float = 1.0,
               max_pivots: int | None = None) -> LoadTrace:
    """Trace the solution of ``plcp`` for p from 0 to ``p_max`` (see module docstring).

    Parameters
    ----------
    plcp : ParametricLCP
    accuracy : level or float
        Tolerance the pieces are certified at (:mod:`qpcontact.accuracy`).
    p_max : float
        Stop at this load parameter (``np.inf``: follow until a ray or a mechanism).
    max_pivots : int, optional
        Default max(10 000, 50 n).

    Raises
    ------
    NoSolutionError
        The constant load alone has no solution (nothing to start from).
    """
    if not isinstance(plcp, ParametricLCP):
        raise InvalidProblemError(f"'trace' takes a ParametricLCP; got {type(plcp).__name__}")
    p_max = float(p_max)
    if not p_max > 0:
        raise InvalidOptionError(f"'trace': p_max must be > 0, got {p_max}")
    n = plcp.n
    check_dense_size("trace", n, f"{n} x {2 * n + 2} tableau", "fixed loads with problem.at(p)")
    max_pivots = int(max_pivots if max_pivots is not None else max(10_000, 50 * n))
    _, tol_cert = resolve_accuracy(accuracy)
    start = time.perf_counter()

    M = dense_matrix(plcp.M)
    rs, cs = ruiz_scaling(M)
    Ms = M * rs[:, None] * cs[None, :]
    q0s, q1s = plcp.q0 * rs, plcp.q1 * rs
    basic_z, pivots = _start_basis(Ms, q0s, max_pivots)

    # columns: w (0..n-1) | z (n..2n-1) | p (2n) | rhs (2n+1)
    P, RHS = 2 * n, 2 * n + 1
    A = np.empty((n, 2 * n + 2))
    A[:, :n] = np.eye(n)
    A[:, n:P] = -Ms
    A[:, P] = -q1s
    A[:, RHS] = q0s
    basis = np.where(basic_z, np.arange(n) + n, np.arange(n))
    B = A[:, basis]
    T = np.asfortranarray(scipy.linalg.solve(B, A) if basic_z.any() else A.copy())
    # Per-row rounding scales of the tableau (T[:, :n] is the basis inverse):
    # every sign and ratio test is made on its own row's size.
    scales = RowScales(np.abs(q0s))
    if basic_z.any():
        scales.anchor(T[:, :n])
    col_norms = np.concatenate([np.ones(n), np.max(np.abs(Ms), axis=0),
                                [float(np.max(np.abs(q1s)))]])

    def values(t, col, entering):
        """All 2n + 1 variables at step t along the current edge."""
        x = np.zeros(2 * n + 1)
        x[basis] = T[:, RHS] - t * col
        x[entering] = t
        return x

    pieces, end, p_now = [], None, 0.0
    entering = P
    degenerate_pivots = 0
    while True:
        col = T[:, entering].copy()
        p_row = np.flatnonzero(basis == P)
        rate = 1.0 if entering == P else -float(col[p_row[0]])
        if entering != P and abs(rate) <= PIVOT_RTOL * scales.inv[p_row[0]] * col_norms[entering]:
            rate = 0.0
        r = lex_ratio_test(col, T[:, RHS], T[:, :n], scales, col_norms[entering])
        t_block = T[r, RHS] / col[r] if r is not None else np.inf
        t_block = max(t_block, 0.0)
        stop_at_pmax = rate > 0 and np.isfinite(p_max) and p_now + rate * t_block >= p_max
        t_end = (p_max - p_now) / rate if stop_at_pmax else t_block
        if t_end > 0 and rate != 0:
            x0, x1 = values(0.0, col, entering), values(1.0, col, entering)
            dxdt = x1 - x0
            on_edge = np.zeros(2 * n + 1, bool)
            on_edge[basis] = True
            on_edge[entering] = True
            active = on_edge[n:P].copy()
            p_b = p_max if stop_at_pmax else (p_now + rate * t_end if np.isfinite(t_end) else
                                              np.sign(rate) * np.inf)
            pieces.append(_piece(plcp, M, active, p_now, p_b, x0[n:P] * cs,
                                 dxdt[n:P] * cs / rate))
        elif t_end == 0:
            degenerate_pivots += 1
        if stop_at_pmax:
            p_now, end = p_max, "p_max"
            break
        if r is None:
            end = "mechanism" if rate == 0 else "ray"
            if rate == 0 and not pieces:
                pieces.append(_piece(plcp, M, basic_z, p_now, p_now, np.zeros(n), np.zeros(n)))
            break
        if pivots >= max_pivots:
            end = "max_pivots"
            break
        p_now = p_now + rate * t_block
        scales.pivot(col, r)
        tableau_pivot(T, r, entering)
        scales.reanchor_if_grown(T[:, :n])
        leaving = int(basis[r])
        basis[r] = entering
        pivots += 1
        if leaving == P:
            end, p_now = "returned", 0.0
            break
        entering = leaving + n if leaving < n else leaving - n
    wall = time.perf_counter() - start

    # Certify every piece at its ends and midpoint against the real data.
    worst = 0.0
    for piece in pieces:
        ends = [piece.p_start] + ([piece.p_end] if np.isfinite(piece.p_end) else
                                  [piece.p_start + 1.0])
        for p in (ends[0], 0.5 * (ends[0] + ends[1]), ends[1]):
            worst = max(worst, certify_lcp(plcp.at(p), np.maximum(piece.z(p), 0.0)).error)
    last = pieces[-1] if pieces else None
    if last is None:
        p_final = p_now
    else:  # a final ray piece has p_end = inf: report its start
        p_final = last.p_end if np.isfinite(last.p_end) else last.p_start
    z = np.maximum(last.z(p_final), 0.0) if last is not None else np.zeros(n)
    lcp_final = plcp.at(p_final)
    cert = certify_lcp(lcp_final, z)
    breakpoints = np.array([pc.p_end for pc in pieces[:-1]])
    if end == "max_pivots":
        status = "max_pivots"
    else:
        status = "solved" if worst <= tol_cert and cert.ok(tol_cert) else "inaccurate"
    messages = {
        "p_max": f"traced to p = {p_max:g}",
        "ray": f"the working scheme no longer changes for p >= {p_final:g} (ray)",
        "mechanism": f"at p = {p_now:g} the structure becomes a mechanism: the solution is "
                     "unbounded at a finite load",
        "returned": "the path turned back to p = 0 (non-P matrix)",
        "max_pivots": f"pivot limit {max_pivots} reached at p = {p_now:g}",
    }
    message = f"{messages[end]}; {len(breakpoints)} breakpoint(s), {pivots} pivot(s)"
    if status == "inaccurate":
        message += f"; NOT certified: worst piece error {worst:.2e} > {tol_cert:.0e}"
    return LoadTrace(
        method="trace", status=status, ok=status == "solved", message=message,
        accuracy=accuracy, tol=tol_cert, certificate=cert, backend_status=end,
        wall_time=wall, iterations=pivots,
        stats={"pivots": pivots, "degenerate_pivots": degenerate_pivots,
               "worst_piece_error": worst,
               "monotone_in_p": all(pc.p_end >= pc.p_start for pc in pieces)},
        z=z, w=lcp_final.w(z), pieces=pieces, breakpoints=breakpoints, end=end, p_end=p_final,
    )


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
