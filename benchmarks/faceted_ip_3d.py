r"""An experiment: dense 3-D piles by an interior point on the k-faceted LCP,
then Newton on the true (round) Coulomb cone from its answer — measured, not
integrated (docs/dev-notes.md, "Dense 3-D piles: an interior point on the
faceted cone, then Newton on the true one — measured", has the tables and
the decision).

**The faceted problem.**  :func:`qpcontact.core.friction_problem.faceted_lcp`
with k facets: per contact z = (r_N, β_1 … β_k, λ) — the normal impulse (N·s),
the impulses along the unit tangent directions e_j = (cos 2πj/k, sin 2πj/k)
(r_T = Σ β_j e_j, N·s) and a slip speed λ (m/s) — and

    w = (u_N,  λ + e_j · u_T (j = 1 … k),  μ r_N − Σ β_j) = M z + q,  z, w >= 0,  z ∘ w = 0,

u = W r + q (m/s).  Σ β_j <= μ r_N keeps r_T inside the polygon inscribed in
the disc |r_T| <= μ r_N, and slip goes along a facet direction only: its
answer is *not* Coulomb's, but it is an LCP, which an interior point solves.
The hope: its answer lies on the branch of Coulomb's solutions that Newton's
method can reach, where NSGS's points (docs/dev-notes.md, "Dense piles: where
every iterative route stops") do not.

**The interior point** is ip-lcp's (qpcontact/solvers/friction/interior_lcp.py,
whose docstring derives Mehrotra's steps, the path followed past folds and
the start on the problem's scale), copied here and generalised from the two
2-D facets to k: only the condensed linear algebra changes.

**The condensed system for k facets.**  Every system is (M + diag(d)) u = g,
d = s/x > 0.  Per contact, with b = (W dr)_T (the tangent rows, 2-vector),
P_j = 1/d_βj, the β_j rows read e_j·b + dλ + d_βj dβ_j = g_j, so dβ_j =
P_j (g_j − e_j·b − dλ); the λ row μ dr_N − Σ dβ_j + d_λ dλ = g_λ gives

    dλ = (g_λ − μ dr_N + Σ P_j g_j − p·b) / K,   p = Σ P_j e_j,  K = d_λ + Σ P_j,

and dr_T = Σ e_j dβ_j = c + (μ/K) p dr_N − G b with S = Σ P_j e_j e_jᵀ,
G = S − p pᵀ/K (positive definite: p pᵀ <= (Σ P_j) S by Cauchy–Schwarz and
K > Σ P_j) and c = Σ P_j g_j e_j − p (g_λ + Σ P_j g_j)/K.  So

    (W + L) dr = (g_N, G⁻¹ c),   L per contact [[d_N, 0], [−(μ/K) G⁻¹ p, G⁻¹]]

(3 × 3; for k = 2 in 2-D it is ip-lcp's block): one LU of W's pattern, 3 nc
unknowns whatever k.  The eliminated (dβ, dλ) come back per contact from
the k + 3 equations they satisfy (the k β rows, the λ row and Σ dβ_j e_j =
dr_T), rows scaled to unit norm, by least squares (a batched
pseudo-inverse, formed once per factorization): no row is relied on where
its pivot d is small.  Then refinement on M + diag(d).

**The hand-over.**  r = (r_N, Σ β_j e_j) from the last iterate; entries below
1e-10 of the largest set to zero, r_T scaled into the true cone (it is in
the polygon already, up to the iterate's θ-sized rounding); then the
package's Newton steps on the true cone: minimum-norm Newton (nsgs-newton's
steps, :func:`qpcontact.solvers.friction.hybrid.minimum_norm_newton`) and
semismooth Newton on the natural map (method "newton",
:func:`~qpcontact.solvers.friction.newton.solve_natural_newton`); and, unless
``--no-tries``, a 20-iteration semismooth Newton try from each iterate where
the mean complementarity first falls below a decade of its start (from 1e-3
down), the path stopped at the first certified try.  Every
error quoted is the package's certificate (:func:`certified_error`, the
larger of the natural-map and componentwise measures) against the *true*
cone; "certified" below means that at 1e-6, re-judged by
``qpcontact.solve(problem, method="newton", max_iter=0, r0=r)``.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/faceted_ip_3d.py --n 500 --seeds 0-9 --facets 4,8,16
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import qpcontact
from qpcontact.core.deadline import Pace
from qpcontact.core.friction_problem import faceted_lcp
from qpcontact.judge.friction_certificate import certified_error
from qpcontact.solvers.friction.hybrid import minimum_norm_newton
from qpcontact.solvers.friction.interior_lcp import (CENTRALITY, CONVERGED, MAX_PATH_STEPS,
                                                     NEIGHBOURHOOD, RUNAWAY, SHORT_STEP,
                                                     STRETCH_GOAL)
from qpcontact.solvers.friction.lcp_route import reactions_of
from qpcontact.solvers.friction.newton import solve_natural_newton

COMPACT = {"agitation": 0.1, "polydispersity": 0.005}


def start_point(problem, q, k):
    """(x⁰, s⁰) on the problem's scale (ip-lcp's start): impulses F, speeds V."""
    nc = problem.n_contacts
    V = float(np.abs(q).max()) or 1.0
    wn = np.abs(np.asarray(problem.W_diagonal, float)[0::3])
    F = V / (float(np.median(wn[wn > 0])) if np.any(wn > 0) else 1.0)
    x = np.concatenate([np.full((1 + k) * nc, F), np.full(nc, V)])
    s = np.concatenate([np.full((1 + k) * nc, V), np.full(nc, F)])
    return x, s


def max_step(x, s, dx, ds) -> float:
    a = np.inf
    for v, d in ((x, dx), (s, ds)):
        neg = d < 0
        if neg.any():
            a = min(a, float(np.min(-v[neg] / d[neg])))
    return a


class CondensedK:
    """(M + diag(d)) u = g for the k-faceted 3-D LCP (module docstring)."""

    def __init__(self, M, W, mu, k, d, stats):
        nc = mu.size
        self.M, self.W, self.mu, self.k, self.d, self.nc = M, W, mu, k, d, nc
        ang = 2 * np.pi * np.arange(k) / k
        e = np.stack([np.cos(ang), np.sin(ang)], 1)                    # (k, 2)
        self.e = e
        dn = d[:nc]
        db = d[nc:(1 + k) * nc].reshape(nc, k)
        dl = d[(1 + k) * nc:]
        P = 1.0 / db
        K = dl + P.sum(1)
        p = P @ e                                                       # (nc, 2)
        S = np.einsum("ij,ja,jb->iab", P, e, e)                          # (nc, 2, 2)
        # G = S − ppᵀ/K as a sum of positive terms (Lagrange's identity:
        # ΣP·S − ppᵀ = ½ Σ_ij P_i P_j (e_i − e_j)(e_i − e_j)ᵀ), no cancellation
        de = e[:, None, :] - e[None, :, :]                                  # (k, k, 2)
        pair = 0.5 * np.einsum("ij,ik,jka,jkb->iab", P, P, de, de)
        G = (dl[:, None, None] * S + pair) / K[:, None, None]
        # where one facet's pivot dominates G is rank one to rounding: a
        # relative 1e-15 of its trace pins the other direction (refinement
        # takes the rest)
        tr = G[:, 0, 0] + G[:, 1, 1]
        G[:, 0, 0] += 1e-15 * tr
        G[:, 1, 1] += 1e-15 * tr
        Gi = np.linalg.inv(G)
        self.P, self.K, self.p, self.Gi = P, K, p, Gi
        blocks = np.zeros((nc, 3, 3))
        blocks[:, 0, 0] = dn
        blocks[:, 1:, 0] = -(mu / K)[:, None] * np.einsum("iab,ib->ia", Gi, p)
        blocks[:, 1:, 1:] = Gi
        L = sp.bsr_matrix((blocks, np.arange(nc), np.arange(nc + 1)), shape=(3 * nc, 3 * nc))
        stats["factorizations"] += 1
        self.lu = spla.splu(sp.csc_matrix(W + L), permc_spec="COLAMD")
        # the per-contact least squares for (dβ, dλ): rows k β rows, the λ row, 2 dr_T rows
        A = np.zeros((nc, k + 3, k + 1))
        A[:, np.arange(k), np.arange(k)] = db
        A[:, :k, k] = 1.0
        A[:, k, :k] = -1.0
        A[:, k, k] = dl
        A[:, k + 1, :k] = e[:, 0]
        A[:, k + 2, :k] = e[:, 1]
        self.rowscale = 1.0 / np.linalg.norm(A, axis=2)
        self.pinv = np.linalg.pinv(A * self.rowscale[:, :, None])      # (nc, k+1, k+3)

    def _once(self, g):
        nc, k, mu, P, K, p = self.nc, self.k, self.mu, self.P, self.K, self.p
        gn = g[:nc]
        gb = g[nc:(1 + k) * nc].reshape(nc, k)
        gl = g[(1 + k) * nc:]
        Pg = P * gb
        c = Pg @ self.e - p * ((gl + Pg.sum(1)) / K)[:, None]
        rhs = np.empty(3 * nc)
        rhs[0::3] = gn
        rhs[1::3], rhs[2::3] = np.einsum("iab,ib->ia", self.Gi, c).T
        dr = self.lu.solve(rhs)
        n = dr[0::3]
        bT = np.asarray(self.W @ dr).ravel().reshape(nc, 3)[:, 1:]
        R = np.empty((nc, k + 3))
        R[:, :k] = gb - bT @ self.e.T
        R[:, k] = gl - mu * n
        R[:, k + 1], R[:, k + 2] = dr[1::3], dr[2::3]
        bl = np.einsum("iab,ib->ia", self.pinv, R * self.rowscale)
        return np.concatenate([n, bl[:, :k].ravel(), bl[:, k]])

    def solve(self, g):
        u = self._once(g)
        for _ in range(2):
            u = u + self._once(g - (self.M @ u + self.d * u))
        return u


class Path:
    """ip-lcp's Mehrotra steps and followed stretches, copied from
    interior_lcp._Path (private, and edited elsewhere while this was
    measured); only the linear algebra differs (:class:`CondensedK`).  Were
    this route integrated, _Path would take the condensed solver as a
    parameter and this copy would go."""

    def __init__(self, M, q, W, mu, k, stats):
        self.M, self.q, self.n = M, q, q.size
        self.W, self.mu, self.k = W, mu, k
        self.stats = stats

    def _lu(self, d):
        return CondensedK(self.M, self.W, self.mu, self.k, d, self.stats)

    def follow(self, x, s, max_iter, time_limit, log=None, tries=None):
        """Mehrotra's steps and followed stretches; ``tries(x, level)`` is
        called the first time the mean complementarity falls below each
        decade of its start (1e-2, 1e-3, …) and stops the path where it
        returns True."""
        M, q, n = self.M, self.q, self.n
        decade = 1e-2
        mu0 = x @ s / n
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
            if tries is not None and mu <= decade * mu0:
                while decade >= mu / mu0:
                    decade /= 10
                if tries(x, mu / mu0):
                    why = f"a Newton try from iteration {k} certified"
                    break
            if short >= 2:
                x, s = self._stretch(x, s, pace)
                short = 0
                pace.step_done()
                continue
            a, x, s = self._mehrotra(x, s, rp, mu)
            short = short + 1 if a < SHORT_STEP else 0
            pace.step_done()
            if log:
                log(f"  it {k}: mean compl {mu / mu0:.2e}, infeas {np.abs(rp).max() / rp0:.2e}, "
                    f"step {a:.2g}")
        self.stats["iterations"] = k
        self.stats["complementarity"] = float(x @ s / n / mu0)
        return x, s, why

    def _mehrotra(self, x, s, rp, mu):
        M, n = self.M, self.n
        lu = self._lu(s / x)

        def direction(rc):
            dx = lu.solve(rc / x + rp)
            return dx, M @ dx - rp

        dx, ds = direction(-x * s)
        a_aff = min(1.0, max_step(x, s, dx, ds))
        mu_aff = (x + a_aff * dx) @ (s + a_aff * ds) / n
        sigma = min(1.0, (mu_aff / mu) ** 3)
        ex, es = direction(sigma * mu - x * s - dx * ds)
        a = 0.0
        for fallback in (None, 0.3, 0.8):
            if fallback is not None:
                ex, es = direction(fallback * mu - x * s)
            a = min(1.0, 0.99 * max_step(x, s, ex, es))
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
            def __init__(self, y, t):
                f, xx, ss, th = residual(y)
                self.xx, self.scale, self.t = xx, th * c, t
                self.lu = lu_of(ss / xx)
                self.A = sp.diags(xx / self.scale) @ (M + sp.diags(ss / xx)) @ sp.diags(xx)
                self.b = xx * r0 / c - (f + 1.0)
                self.w = self._a(self.b)
                self.den = t[n] - t[:n] @ self.w

            def _a(self, f):
                return self.lu.solve(f * self.scale / self.xx) / self.xx

            def _once(self, rhs):
                u = self._a(rhs[:n])
                v = (rhs[n] - self.t[:n] @ u) / self.den
                return np.concatenate([u - v * self.w, [v]])

            def solve(self, rhs):
                u = self._once(rhs)
                res = rhs - np.concatenate([self.A @ u[:n] + self.b * u[n], [self.t @ u]])
                return u + self._once(res)

        y = np.concatenate([np.log(x), [0.0]])
        t = -e
        tangent = Bordered(y, t).solve(e)
        t = tangent / np.linalg.norm(tangent)
        if t[n] > 0:
            t = -t
        h, steps, folds, falling = 1.0, 0, 0, True
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            while (y[n] > goal and y[n] < np.log(RUNAWAY) and steps < MAX_PATH_STEPS
                   and h >= 1e-6 and pace.fits()):
                yp = y + h * t
                B = Bordered(yp, t)
                z, (f, *_), it = yp.copy(), residual(yp), 0
                while not np.abs(f).max() <= NEIGHBOURHOOD and it < 4:
                    z = z + B.solve(-np.concatenate([f, [t @ (z - yp)]]))
                    f, it = residual(z)[0], it + 1
                pace.step_done()
                if not np.abs(f).max() <= NEIGHBOURHOOD:
                    h *= 0.5
                    continue
                tangent = B.solve(e)
                tn = tangent / np.linalg.norm(tangent)
                if tn @ t < 0:
                    tn = -tn
                if (tn[n] < 0) != falling:
                    folds += 1
                    falling = tn[n] < 0
                y, t, steps = z, tn, steps + 1
                h *= 1.5 if it <= 1 else 1.0 if it == 2 else 0.7
        _, xx, ss, th = residual(y)
        stats["path_stretches"] += 1
        stats["path_steps"] += steps
        stats["folds"] += folds
        return xx, ss


def purified_3d(problem, r, rtol=1e-10):
    """Entries below rtol of the largest zeroed, r_T scaled into |r_T| <= μ r_N."""
    out = r.copy()
    out[np.abs(out) < rtol * np.abs(out).max(initial=0.0)] = 0.0
    R = out.reshape(-1, 3)
    R[:, 0] = np.maximum(R[:, 0], 0.0)
    t = np.linalg.norm(R[:, 1:], axis=1)
    bound = problem.mu * R[:, 0]
    over = t > bound
    R[over, 1:] *= (bound[over] / t[over])[:, None]
    return out


def judged(problem, r, tol):
    """The package's own verdict on r: solve by "newton" with no iteration from r."""
    res = qpcontact.solve(problem, method="newton", accuracy=tol, r0=r, max_iter=0)
    return res.status, float(res.error) if res.error is not None else np.inf


def check_condensed(problem, k, seed=0):
    """The condensed solve against SciPy's LU of the whole M + diag(d):
    relative difference and backward error, d spread over 1e±8."""
    lcp, _ = faceted_lcp(problem, k)
    M = sp.csc_matrix(lcp.M)
    rng = np.random.default_rng(seed)
    d = 10.0 ** rng.uniform(-8, 8, M.shape[0])
    g = rng.standard_normal(M.shape[0])
    C = CondensedK(M, sp.csr_matrix(problem.W), problem.mu, k, d, {"factorizations": 0})
    u = C.solve(g)
    ref = spla.spsolve(sp.csc_matrix(M + sp.diags(d)), g)
    A = M + sp.diags(d)
    back = np.abs(A @ u - g).max() / (abs(A) @ np.abs(u) + np.abs(g)).max()
    return float(np.abs(u - ref).max() / np.abs(ref).max()), float(back)


def run_one(problem, k, tol, ip_limit, newton_limit, log=None, with_tries=True):
    row = {"facets": k, "contacts": problem.n_contacts}
    t0 = time.process_time()
    lcp, D = faceted_lcp(problem, k)
    M, q = sp.csc_matrix(lcp.M), np.asarray(lcp.q, float)
    stats = {"iterations": 0, "path_stretches": 0, "path_steps": 0, "folds": 0,
             "factorizations": 0}
    x, s = start_point(problem, q, k)
    path = Path(M, q, sp.csr_matrix(problem.W), problem.mu, k, stats)
    tried, found = [], {}

    def tries(xx, level):
        """semismooth Newton (20 iterations) from the purified iterate, below
        1e-3 of the start's complementarity (minimum-norm Newton's steps
        never lowered the faceted error there: measured, dev-notes)"""
        if level > 1e-3:
            return False
        c0 = time.process_time()
        rr = purified_3d(problem, reactions_of(problem, xx, D))
        e0 = certified_error(problem, rr)
        rm, _, _, _ = solve_natural_newton(problem, tol, {"r0": rr, "max_iter": 20})
        em = certified_error(problem, rm) if rm is not None else np.inf
        tried.append((float(f"{level:.2g}"), float(f"{e0:.2g}"), float(f"{em:.2g}"),
                      round(time.process_time() - c0, 2)))
        if log:
            log(f"  try at {level:.1e}: faceted {e0:.2e} -> Newton {em:.2e}")
        if em <= tol:
            found["r"] = rm
            return True
        return False

    x, s, why = path.follow(x, s, 300, ip_limit, log, tries if with_tries else None)
    row.update(ip_cpu=time.process_time() - t0, ip_why=why, tries=tried, **stats)
    if "r" in found:
        row["status"], row["judged_err"] = judged(problem, found["r"], tol)
        row["total_cpu"] = time.process_time() - t0
        return row
    row["lcp_rel_infeas"] = float(np.abs(s - (M @ x + q)).max() / np.abs(q).max())
    r = purified_3d(problem, reactions_of(problem, x, D))
    row["faceted_err"] = float(certified_error(problem, r))
    Rr = r.reshape(-1, 3)
    row["open"] = int(np.sum(Rr[:, 0] == 0))
    # minimum-norm Newton (nsgs-newton's steps) from the faceted answer
    t1 = time.process_time()
    rm, em, km = minimum_norm_newton(problem, r.copy(), tol, max_steps=30)
    row.update(mn_err=float(em), mn_steps=km, mn_cpu=time.process_time() - t1)
    # semismooth Newton (method "newton") from the faceted answer
    t2 = time.process_time()
    rn, _, msg, nst = solve_natural_newton(problem, tol, {"r0": r.copy(), "max_iter": 100,
                                                          "time_limit": newton_limit})
    en = certified_error(problem, rn) if rn is not None else np.inf
    row.update(nt_err=float(en), nt_iters=nst.get("iterations"), nt_cpu=time.process_time() - t2,
               nt_msg=msg)
    best = rm if em <= en else rn
    # nsgs-newton (the package's method, its own stopping rules) from the faceted point
    t3 = time.process_time()
    res = qpcontact.solve(problem, method="nsgs-newton", accuracy=tol, time_limit=30, r0=r.copy())
    row.update(ns_status=res.status, ns_err=float(res.error), ns_cpu=time.process_time() - t3)
    row["status"], row["judged_err"] = judged(problem, best, tol)
    row["total_cpu"] = time.process_time() - t0
    return row


def random_starts(problem, tol, count):
    """The control: nsgs-newton from ``count`` random points of the cone
    (r_N uniform up to the largest impulse of a first nsgs-newton answer,
    r_T up to 0.3 of it, signs random)."""
    first = qpcontact.solve(problem, method="nsgs-newton", accuracy=tol, time_limit=30)
    scale = float(np.abs(first.r).max()) if first.r is not None else 1.0
    rows = [("zero", first.status, float(first.error))]
    m = 3 * problem.n_contacts
    for rs in range(count):
        rng = np.random.default_rng(rs)
        r0 = rng.uniform(0, 1, m) * scale * np.tile([1.0, 0.3, 0.3], problem.n_contacts)
        r0 *= np.where(np.arange(m) % 3 == 0, 1.0, np.sign(rng.standard_normal(m)))
        res = qpcontact.solve(problem, method="nsgs-newton", accuracy=tol, time_limit=30,
                              r0=purified_3d(problem, r0))
        rows.append((f"random {rs}", res.status, float(res.error)))
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=500, help="contacts asked of sphere_pile")
    ap.add_argument("--seeds", default="0-9")
    ap.add_argument("--facets", default="4,8,16")
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--ip-limit", type=float, default=120.0, help="the IP's time limit (s, wall)")
    ap.add_argument("--newton-limit", type=float, default=60.0)
    ap.add_argument("--spheres", action="store_true", help="the loose sphere pile (defaults)")
    ap.add_argument("--check", action="store_true", help="only check the condensed solve")
    ap.add_argument("--no-tries", action="store_true",
                    help="no Newton tries at the decades of the complementarity")
    ap.add_argument("--random-starts", type=int, default=0,
                    help="only the control: nsgs-newton from this many random starts")
    ap.add_argument("--verbose", action="store_true")
    ap.add_argument("--out", default=None, help="append JSON rows here")
    args = ap.parse_args(argv)
    from qpcontact.cases.piles import sphere_pile
    a, _, b = args.seeds.partition("-")
    seeds = range(int(a), int(b or a) + 1)
    params = {} if args.spheres else COMPACT
    for seed in seeds:
        problem = sphere_pile(args.n, seed=seed, **params).problem
        for k in (int(f) for f in args.facets.split(",")):
            if args.random_starts:
                print(seed, random_starts(problem, args.tol, args.random_starts), flush=True)
                break
            if args.check:
                print(seed, k, check_condensed(problem, k, seed), flush=True)
                continue
            row = run_one(problem, k, args.tol, args.ip_limit, args.newton_limit,
                          print if args.verbose else None, not args.no_tries)
            row["seed"] = seed
            print(json.dumps(row), flush=True)
            if args.out:
                with open(args.out, "a") as fh:
                    fh.write(json.dumps(row) + "\n")


if __name__ == "__main__":
    main()
