r"""Frictional contact in 2-D by an interior-point method on its LCP, the
central path followed past its folds ("ip-lcp").

**The problem.**  In 2-D Coulomb's law is an LCP
(:func:`qpcontact.core.friction_problem.faceted_lcp` with k = 2): per contact
z = (r_N, β⁺, β⁻, λ) — the normal impulse and the two friction parts
(N·s, or N·s/m in 2-D: r_T = β⁺ − β⁻), the slip speed λ (m/s) — and

    w = (u_N,  λ + u_T,  λ − u_T,  μ r_N − β⁺ − β⁻) = M z + q,   z, w >= 0,   z ∘ w = 0,

u = W r + q the local velocities (m/s).  Each product z_i w_i is an impulse
times a speed (N·s · m/s, J per step).

**The path.**  From a start (x⁰, s⁰) > 0 (the z's and w's; below), the
infeasible central path is, for θ in (0, 1],

    x ∘ s = θ c,   s = M x + q + θ r⁰,   x, s > 0,    c = x⁰ ∘ s⁰,  r⁰ = s⁰ − M x⁰ − q:

at θ = 1 the start, and every limit point as θ → 0 solves the LCP.
Mehrotra's predictor–corrector steps along it (Wright, *Primal-dual
interior-point methods*, 1997, ch. 10 and 11): per iteration one sparse LU of
M + X⁻¹S (condensed to W's pattern: "The linear algebra") and two solves;
the step stays in the neighbourhood x_i s_i >= 10⁻³ mean(x ∘ s).  The
infeasibility falls by exactly 1 − α at a step of length α, so every
iterate lies *on* the path of its own weights c = x ∘ s / θ.  The start
is the problem's own scale: impulses F = ‖q‖∞ / median(W_nn), speeds
V = ‖q‖∞ (x⁰ = F for r_N, β±, V for λ; s⁰ = V for the velocity rows, F for
the friction-limit row), so that c = F V for every pair and the path does
not depend on the units.

**Why the path folds.**  For a monotone M (the frictionless pile: M = PSD +
skew) the path goes to θ = 0 without turning back, and Mehrotra needs 20–40
iterations whatever the pile's size.  M is not monotone, and where the pile is
hyperstatic it is not even P0: for contacts i, j the principal minor on
(r_N,i, r_N,j, β⁺_j, λ_j) is

    (W_ii W_jj − W_ij²) + μ_j (W_ii W_j,tj − W_ij W_i,tj)

(normal entries W_ii, W_ij; W_j,tj the coupling of j's normal to its own
tangent, W_i,tj to i's normal), whose first term vanishes for contacts that
the pile couples rigidly, the second has either sign.  Then the path can turn
back — θ has a local minimum along it, a *fold* — and Mehrotra's long steps
land beyond it: its steps collapse (on the 1 941-contact compact pile of seed
0 to 1e-5 of the way to the boundary, at a mean complementarity of 4e-6 from
two different starts).  Centring steps do not help there: below the fold the
path has no point near the iterate.

**Past a fold.**  Where two steps in a row go less than 5 % of the way, the
path through the current iterate is followed by pseudo-arclength continuation
(Keller) in y = (log x, log θ) — log x keeps x > 0 whatever the step, and on
the path s = θ c / x > 0 — on

    F(y) = x ∘ s / (θ c) − 1 = 0:

the predictor along the unit tangent, the corrector Newton's method on F with
the arclength condition, both through the bordered matrix
[[∂F/∂log x, ∂F/∂log θ], [tangentᵀ]] solved by block elimination on the LU of
∂F/∂log x = diag(1/θc) (S + X M) X (the sparsity of M + X⁻¹S; the bordered
matrix's dense row and column made its own LU ten times dearer) with one
step of refinement on the bordered system (the condensed solves inside it
unrefined: the same steps, 10 % less CPU a step at 1 941 contacts); the
tangent's first approximation is (−w, 1)/den with w = A⁻¹ b, which the
elimination already holds, so a step with one corrector iteration costs one
LU and four solves (w, the corrector's two, the tangent's refinement).  The
corrector stops inside the neighbourhood ‖F‖∞ <= 0.3, not on the path: a
path-following method needs no more, and a looser one (0.5) let the tracker
jump between branches.  The step grows by
1.5 after a one-iteration corrector and halves where the corrector fails.
θ may rise (the fold) and fall again; once it is 0.3 of where the stretch
began, Mehrotra takes over.  A stretch gives up where θ grows past RUNAWAY
times its start (the path running away: a 361-contact pile of seed 1 did)
or after MAX_PATH_STEPS steps.  Measured on the 1 941-contact compact pile of
seed 0 (docs/dev-notes.md, "Dense 2-D piles by interior point"): two
stretches, 474 steps, 12 turns, 32 s of CPU; most piles need none.

**The linear algebra.**  Every system is (M + diag(d)) u = g, d = s/x > 0.
Per contact, with (a, b) the normal and tangent rows of W dr (dr = (dr_N,
dr_T), dr_T = dβ⁺ − dβ⁻), the rows read a + d_N dr_N = g_N, ±b + dλ + d_±
dβ± = g_±, μ dr_N − dβ⁺ − dβ⁻ + d_λ dλ = g_λ; eliminating dβ±, dλ leaves
(W + L) dr = rhs with L block-diagonal, per contact [[d_N, 0], [−μ Δ/(K G),
1/G]] (P = 1/d_+, Q = 1/d_−, Δ = P − Q, K = d_λ + P + Q, G = ((P + Q) d_λ +
4PQ)/K > 0): one LU of W's pattern, half the unknowns of M's (15.9 s of CPU
against 32.8 s on the 1 941-contact pile of seed 2, the same 263 path
steps).  The eliminated parts come back from whichever of their rows is
well conditioned (a part's own row where its d is at least W's tangent
diagonal, else β⁺ + β⁻ from the λ row and β⁺ − β⁻ = dr_T), and one step of
refinement on M + diag(d) follows: normwise backward errors 1e-16 for d
spread over 1e±12, as the full LU's; componentwise (200-disc piles, five
seeds) 2e-16 at 1e±8, 2e-14 … 5.5e-11 at 1e±12 (the old COLAMD LU's
4.8e-11 … 6.3e-6), up to 6e-6 at 1e±14 — a poor solve costs path steps,
not the answer, which the stopping test and the certificate judge from M
and q.  W + L keeps one pattern, so its fill-reducing order
is found once — minimum degree on W's own pattern, symmetric, and each LU
pivots on the diagonal unless that entry is below 1e-3 of its column's
largest (:class:`_Ordered`).  At 9 842 contacts that LU takes 0.09–0.10 s
of CPU with 3.0–3.15 M entries in its factors, against 0.26–0.29 s and
5.9 M by COLAMD with partial pivoting at every step (at 1 941: 0.010 against
0.020 s); W + L's symmetric part need not be definite (μ's entries), hence
the threshold, which on folding piles pivots off the diagonal in 0–60 of
19 684 columns.  Where W's factors W = J diag(m⁻¹) Jᵀ are known (the piles
keep them: :attr:`FrictionProblem.delassus_factors`), W + L is solved in body
space instead (:mod:`~qpcontact.solvers.friction.body_space`: Woodbury's
identity, one LU on the bodies' graph, a third of the fill): the same path
steps at 1 941 contacts, 0.006 against 0.013 s of CPU a step; 4 874 contacts
seed 1, 411 steps, 15 s against 56 s.

**The answer.**  r = (r_N, β⁺ − β⁻) from the last iterate, entries below
1e-10 of the largest set to zero (the interior point's zeros are θ-sized),
r_T clipped to the cone, then semismooth Newton
(:func:`~qpcontact.solvers.friction.newton.solve_natural_newton`) polishes
it; the better-certified of the two points is returned.  On a hyperstatic
pile the forces are not unique: the interior point tends to a point inside
the solution set, not to a vertex as Lemke's method does.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ...core.deadline import Deadline, Pace
from ...core.errors import InvalidOptionError
from ...core.friction_problem import faceted_lcp
from ...core.options import PROGRESS, TIME_LIMIT, Option, read_options
from ...judge.friction_certificate import certified_error
from .body_space import BodySpaceLU, InOrder, OrderedPattern, factors_match
from .lcp_route import purified, reactions_of
from .newton import solve_natural_newton

__all__ = ["solve_ip_lcp", "IP_LCP_OPTIONS", "CENTRALITY", "SHORT_STEP", "NEIGHBOURHOOD",
           "STRETCH_GOAL", "RUNAWAY", "MAX_PATH_STEPS", "NEAR"]

IP_LCP_OPTIONS = (
    Option("max_iter", 200, "int", low=1,
           doc="Mehrotra iterations at most (the followed stretches of the path not counted)"),
    PROGRESS, TIME_LIMIT,
)

#: Mehrotra's steps keep x_i s_i >= CENTRALITY · mean(x ∘ s)
CENTRALITY = 1e-3
#: a Mehrotra step shorter than this (of the way to the boundary) is short;
#: two in a row start a followed stretch of the path
SHORT_STEP = 0.05
#: the followed path's corrector stops at ‖x ∘ s / (θ c) − 1‖∞ <= NEIGHBOURHOOD
NEIGHBOURHOOD = 0.3
#: a followed stretch ends where θ is this fraction of where it began
STRETCH_GOAL = 0.3
#: a followed stretch gives up where θ exceeds this multiple of where it began
RUNAWAY = 1e3
#: or after this many steps
MAX_PATH_STEPS = 2000
#: each LU's pivot stays on the diagonal unless below this fraction of its
#: column's largest entry (the order found once is then kept; 0.1 and above
#: pivot off it often enough on folding piles to triple the fill)
PIVOT_THRESHOLD = 1e-3
#: the interior point's converged measure: mean(x ∘ s) and the infeasibility
#: below this fraction of their starting values
CONVERGED = 1e-13
#: two short steps in a row below this fraction of the start's complementarity
#: and infeasibility end the interior point; Newton's polish takes over
NEAR = 1e-10


def solve_ip_lcp(problem, tol, options):
    """The 2-D frictional problem by interior point on its LCP, folds of the
    central path followed by arclength, Newton's polish (module docstring).
    Options (:data:`IP_LCP_OPTIONS`): ``max_iter`` (200 Mehrotra
    iterations), ``progress``, ``time_limit`` (s).  Returns (r, status,
    message, stats)."""
    opts = read_options("ip-lcp", options, IP_LCP_OPTIONS)
    if problem.dim != 2:
        raise InvalidOptionError("ip-lcp solves 2-D problems (their exact LCP); 3-D cones are "
                                 "not polyhedral")
    time_limit, progress = opts["time_limit"], opts["progress"]
    deadline = Deadline(time_limit)
    nc = problem.n_contacts
    stats = {"iterations": 0, "path_stretches": 0, "path_steps": 0, "folds": 0,
             "factorizations": 0}
    if nc == 0:
        return np.zeros(0), "solved", "no contacts", stats
    lcp, D = faceted_lcp(problem, 2)
    M, q = sp.csc_matrix(lcp.M), np.asarray(lcp.q, float)
    x, s = _start(problem, q)
    W = sp.csr_matrix(problem.W)
    factors = getattr(problem, "delassus_factors", None)
    body = factors is not None and factors_match(W, factors)
    stats["body_space"] = body
    path = _Path(M, q, W, problem.mu, stats, progress, factors if body else None)
    x, s, why = path.follow(x, s, opts["max_iter"], deadline.left())
    r = reactions_of(problem, x, D)
    if not np.all(np.isfinite(r)):
        return None, "stopped", f"interior point on the 2-D LCP: {why}, at no finite point", stats
    r = purified(problem, r, 1e-10)
    before = certified_error(problem, r)
    message = f"interior point on the 2-D LCP: {why}"
    left = deadline.left()
    if before > tol and (left is None or left > 0):
        rn, _, _, nstats = solve_natural_newton(problem, tol, {"r0": r, "max_iter": 30,
                                                               "time_limit": left})
        stats["polish_iterations"] = nstats.get("iterations")
        after = certified_error(problem, rn) if rn is not None else np.inf
        if after < before:
            r, before = rn, after
            message += (f"; polished by Newton from its purified point "
                        f"({nstats.get('iterations')} iterations)")
        else:
            message += f"; a Newton polish did not improve it (error {after:.1e})"
    return r, "solved" if before <= tol else "stopped", message, stats


def _start(problem, q):
    """(x⁰, s⁰) on the problem's scale (module docstring): every pair's
    product F V."""
    nc = problem.n_contacts
    V = float(np.abs(q).max()) or 1.0
    wn = np.abs(np.asarray(problem.W_diagonal, float)[0::2])
    F = V / (float(np.median(wn[wn > 0])) if np.any(wn > 0) else 1.0)
    x = np.concatenate([np.full(3 * nc, F), np.full(nc, V)])
    s = np.concatenate([np.full(3 * nc, V), np.full(nc, F)])
    return x, s


def _max_step(x, s, dx, ds) -> float:
    """The largest α with x + α dx >= 0 and s + α ds >= 0 (inf if none
    bounds it)."""
    a = np.inf
    for v, d in ((x, dx), (s, ds)):
        neg = d < 0
        if neg.any():
            a = min(a, float(np.min(-v[neg] / d[neg])))
    return a


class _Ordered:
    """W + L on one pattern in one order, found once (module docstring, "The
    linear algebra"): W's pattern and each contact's 2 × 2 block do not
    change between steps, only the values of L.  The order is SuperLU's
    minimum degree on A + Aᵀ, symmetric, taken from one factorization of a
    diagonally dominant matrix of that pattern; each step's LU keeps it
    (permc_spec "NATURAL" on the permuted matrix) and pivots off the
    diagonal only where a diagonal entry is below PIVOT_THRESHOLD of its
    column's largest."""

    def __init__(self, W):
        n = W.shape[0]
        nc = n // 2
        rows = np.concatenate([2 * np.arange(nc), 2 * np.arange(nc) + 1, 2 * np.arange(nc) + 1])
        cols = np.concatenate([2 * np.arange(nc), 2 * np.arange(nc), 2 * np.arange(nc) + 1])
        ones = sp.csc_matrix((np.ones(3 * nc), (rows, cols)), shape=(n, n))
        pattern = sp.csc_matrix(abs(W) + ones)
        # ordered on W's own pattern: with the blocks' lower entries (absent from
        # W where a disc contact's normal and tangent do not couple) minimum
        # degree's order fills 4.6 M entries against 3.0 M at 9 842 contacts
        dominant = abs(W) + sp.diags(np.asarray(abs(W).sum(axis=1)).ravel() + 1.0)
        order = OrderedPattern(pattern, dominant)
        self.p, self.indices, self.indptr, self.n = order.p, order.indices, order.indptr, n
        position, keys = order.position, order.keys

        Wc = sp.coo_matrix(W)
        kept = Wc.data != 0                     # an explicit zero has no place in the pattern
        self.w_data = np.zeros(keys.size)
        self.w_data[position(Wc.row[kept], Wc.col[kept])] = Wc.data[kept]
        self.l_pos = position(rows, cols)       # L's d_N, lower and 1/G entries, distinct

    def factor(self, l_values):
        """The solver of (W + L) u = g in the contacts' order: the LU of the
        ordered W + L, L's entries in the order of l_pos."""
        import scipy.sparse.linalg as spla

        data = self.w_data.copy()
        data[self.l_pos] += l_values
        A = sp.csc_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))
        return InOrder(spla.splu(A, permc_spec="NATURAL", diag_pivot_thresh=PIVOT_THRESHOLD,
                                  options={"SymmetricMode": True}), self.p)


class _Condensed:
    """(M + diag(d)) u = g for the 2-D LCP's M, d > 0, by eliminating each
    contact's β±, λ (module docstring, "The linear algebra"): one LU of
    W + L, L block-diagonal 2 × 2, then one step of refinement on M + diag(d)."""

    def __init__(self, M, W, ordered, mu, d, stats, tangent_diagonal):
        nc = mu.size
        self.M, self.W, self.mu, self.d, self.nc = M, W, mu, d, nc
        dn, dp, dm, dl = d[:nc], d[nc:3 * nc:2], d[nc + 1:3 * nc:2], d[3 * nc:]
        P, Q = 1.0 / dp, 1.0 / dm
        K = dl + P + Q
        G = ((P + Q) * dl + 4.0 * P * Q) / K
        self.P, self.Q, self.K, self.G, self.dl = P, Q, K, G, dl
        # the coefficients of h_t, each a quotient of positive sums (no cancellation)
        self.cp, self.cm, self.cl = P * (dl + 2.0 * Q) / K, Q * (dl + 2.0 * P) / K, (P - Q) / K
        # which friction part is found from its own row: the one whose pivot d is large
        self.p_own, self.m_own = dp >= tangent_diagonal, dm >= tangent_diagonal
        stats["factorizations"] += 1
        self.lu = ordered.factor(np.concatenate([dn, -self.cl * mu / G, 1.0 / G]))

    def _once(self, g):
        nc, mu = self.nc, self.mu
        gn, gp, gm, gl = g[:nc], g[nc:3 * nc:2], g[nc + 1:3 * nc:2], g[3 * nc:]
        rhs = np.empty(2 * nc)
        rhs[0::2] = gn
        rhs[1::2] = (self.cp * gp - self.cm * gm - self.cl * gl) / self.G
        dr = self.lu.solve(rhs)
        n, t = dr[0::2], dr[1::2]
        b = np.asarray(self.W @ dr).ravel()[1::2]
        l = (gl - mu * n - (self.P - self.Q) * b) / self.K + (self.P / self.K) * gp \
            + (self.Q / self.K) * gm
        total = mu * n + self.dl * l - gl           # β⁺ + β⁻, from the λ row
        p, m = 0.5 * (total + t), 0.5 * (total - t)
        own_p = (gp - b - l) * self.P
        own_m = (gm + b - l) * self.Q
        p = np.where(self.p_own, own_p, np.where(self.m_own, t + own_m, p))
        m = np.where(self.m_own, own_m, np.where(self.p_own, own_p - t, m))
        u = np.empty(4 * nc)
        u[:nc], u[nc:3 * nc:2], u[nc + 1:3 * nc:2], u[3 * nc:] = n, p, m, l
        return u

    def solve(self, g):
        u = self._once(g)
        return u + self._once(g - (self.M @ u + self.d * u))


class _Path:
    """Mehrotra's steps, and the stretches of path followed by arclength
    where they collapse (module docstring)."""

    def __init__(self, M, q, W, mu, stats, progress, factors=None):
        self.M, self.q, self.n = M, q, q.size
        self.W, self.mu = W, mu
        # W + L's LU on W's pattern, or in body space where W's factors are known
        self.ordered = (_Ordered(W) if factors is None
                        else BodySpaceLU(*factors))
        self.stats, self.progress = stats, progress
        self.tangent_diagonal = np.abs(np.asarray(W.diagonal())[1::2])

    def _lu(self, d):
        """The solver of (M + diag(d)) u = g."""
        return _Condensed(self.M, self.W, self.ordered, self.mu, d, self.stats,
                          self.tangent_diagonal)

    def follow(self, x, s, max_iter, time_limit):
        """(x, s, why it stopped) after Mehrotra's steps and the followed
        stretches."""
        M, q, n = self.M, self.q, self.n
        mu0 = x @ s / n
        # the infeasibility's scale: the start's, or the data's where the start is feasible
        rp0 = max(np.abs(s - (M @ x + q)).max(), np.abs(q).max())
        pace = Pace(time_limit)
        short, k = 0, 0
        why = f"stopped at {max_iter} iterations"
        for k in range(1, max_iter + 1):
            rp = s - (M @ x + q)
            mu = x @ s / n
            if mu <= CONVERGED * mu0 and np.abs(rp).max() <= CONVERGED * rp0:
                why = f"converged in {k - 1} iterations"
                break
            if not pace.fits():
                why = "stopped at its time limit"
                break
            if short >= 2 and mu <= NEAR * mu0 and np.abs(rp).max() <= NEAR * rp0:
                # short steps this near the end are the solves' rounding, not a fold
                # (the body-space solves' at 1e-11 of the start): Newton's polish ends it
                why = f"its steps stalled at {mu / mu0:.1e} of the start's complementarity"
                break
            if short >= 2:
                # a fold: follow the path through this point past it
                x, s = self._stretch(x, s, pace)
                short = 0
                pace.step_done()
                continue
            a, x, s = self._mehrotra(x, s, rp, mu)
            short = short + 1 if a < SHORT_STEP else 0
            pace.step_done()
            if self.progress is not None:
                self.progress(f"ip-lcp: iteration {k}: mean complementarity {mu:.2e}, "
                              f"infeasibility {np.abs(rp).max():.2e}, step {a:.2g}")
        self.stats["iterations"] = k
        self.stats["complementarity"] = float(x @ s / n)
        return x, s, why

    def _mehrotra(self, x, s, rp, mu):
        """One predictor–corrector step (falling back to centring steps of
        σ = 0.3 and 0.8 where the corrected one is short): (α, x, s)."""
        M, n = self.M, self.n
        lu = self._lu(s / x)

        def direction(rc):
            dx = lu.solve(rc / x + rp)
            return dx, M @ dx - rp

        dx, ds = direction(-x * s)
        a_aff = min(1.0, _max_step(x, s, dx, ds))
        mu_aff = (x + a_aff * dx) @ (s + a_aff * ds) / n
        sigma = min(1.0, (mu_aff / mu) ** 3)
        ex, es = direction(sigma * mu - x * s - dx * ds)
        a = 0.0
        for fallback in (None, 0.3, 0.8):
            if fallback is not None:
                ex, es = direction(fallback * mu - x * s)
            a = min(1.0, 0.99 * _max_step(x, s, ex, es))
            while a > 1e-8:
                xn, sn = x + a * ex, s + a * es
                if (xn * sn).min() >= CENTRALITY * (xn @ sn) / n:
                    break
                a *= 0.7
            if a >= SHORT_STEP:
                break
        if a <= 1e-8:
            return 0.0, x, s
        return a, x + a * ex, s + a * es

    def _stretch(self, x, s, pace):
        """Pseudo-arclength continuation of x ∘ s = θ c, s = M x + q + θ r⁰
        through (x, s) at θ = 1, in y = (log x, log θ), until θ <=
        STRETCH_GOAL (module docstring): the point where it ends."""
        M, q, n, stats = self.M, self.q, self.n, self.stats
        c = x * s
        r0 = s - (M @ x + q)
        e = np.zeros(n + 1)
        e[n] = 1.0
        goal = np.log(STRETCH_GOAL)

        def residual(y):
            xx, th = np.exp(y[:n]), np.exp(y[n])
            ss = M @ xx + q + th * r0
            return xx * ss / (th * c) - 1.0, xx, ss, th

        lu_of = self._lu

        class Bordered:
            """[[A, b], [tᵀ, t_n]] (A = ∂F/∂log x, b = ∂F/∂log θ) by block
            elimination on the LU of M + X⁻¹S: A = diag(1/θc) X (M + X⁻¹S) X."""

            def __init__(self, y, t):
                f, xx, ss, th = residual(y)
                self.f, self.xx, self.scale, self.t = f, xx, th * c, t
                self.lu = lu_of(ss / xx)
                self.ss = ss
                self.b = xx * r0 / c - (f + 1.0)
                self.w = self._a(self.b)
                self.den = t[n] - t[:n] @ self.w

            def _a(self, f):
                return self.lu._once(f * self.scale / self.xx) / self.xx

            def _once(self, rhs):
                u = self._a(rhs[:n])
                v = (rhs[n] - self.t[:n] @ u) / self.den
                return np.concatenate([u - v * self.w, [v]])

            def tangent(self):
                """The solution of [[A, b], [tᵀ, t_n]] v = e_θ: its first
                approximation (−w, 1)/den needs no solve, then one refinement."""
                v = 1.0 / self.den
                return self.solve(e, np.concatenate([-v * self.w, [v]]))

            def solve(self, rhs, u=None):
                u = self._once(rhs) if u is None else u
                # A u = diag(x/θc) (M (x ∘ u) + s ∘ u), A not formed (three sparse
                # matrix products a step)
                au = (self.xx / self.scale) * (M @ (self.xx * u[:n]) + self.ss * u[:n])
                res = rhs - np.concatenate([au + self.b * u[n], [self.t @ u]])
                return u + self._once(res)

        y = np.concatenate([np.log(x), [0.0]])
        t = -e
        tangent = Bordered(y, t).tangent()
        t = tangent / np.linalg.norm(tangent)
        if t[n] > 0:
            t = -t
        h, steps, folds, falling = 1.0, 0, 0, True
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            # the path may also run away (θ growing without a turn: no
            # solution reached this way); a stretch is bounded in steps and θ
            while (y[n] > goal and y[n] < np.log(RUNAWAY) and steps < MAX_PATH_STEPS
                   and h >= 1e-6 and pace.fits()):
                yp = y + h * t
                B = Bordered(yp, t)
                z, f, it = yp.copy(), B.f, 0
                while not np.abs(f).max() <= NEIGHBOURHOOD and it < 4:
                    z = z + B.solve(-np.concatenate([f, [t @ (z - yp)]]))
                    f, it = residual(z)[0], it + 1
                pace.step_done()
                if not np.abs(f).max() <= NEIGHBOURHOOD:
                    h *= 0.5
                    continue
                tangent = B.tangent()
                tn = tangent / np.linalg.norm(tangent)
                if tn @ t < 0:
                    tn = -tn
                if (tn[n] < 0) != falling:
                    folds += 1
                    falling = tn[n] < 0
                y, t, steps = z, tn, steps + 1
                h *= 1.5 if it <= 1 else 1.0 if it == 2 else 0.7
                if self.progress is not None:
                    self.progress(f"ip-lcp: path step {steps}: θ {np.exp(y[n]):.3g} of where the "
                                  f"stretch began, {it} corrector iterations, next step {h:.2g}")
        _, xx, ss, th = residual(y)
        stats["path_stretches"] += 1
        stats["path_steps"] += steps
        stats["folds"] += folds
        if self.progress is not None:
            self.progress(f"ip-lcp: followed the path past a fold: {steps} steps, {folds} "
                          f"turns, θ {th:.2g} of where it began")
        return xx, ss
