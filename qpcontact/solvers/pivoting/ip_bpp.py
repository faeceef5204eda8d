"""``"ip-bpp"``: an interior-point warm start and an exact block-pivoting
finish, for strictly convex QPs with lower bounds — LCPs with M symmetric
positive definite (through their QP form) and the *mixed* problems finite-
element contact produces: free displacements plus bounds on the contact dofs
only, taken as they come (the user never condenses).

    min ½ x'Px + c'x   subject to   x_B >= l_B     (B: the bounded components)

Two routes, chosen by the number m of bounded components:

* **Few bounded components** (sparse P, m <= ``CONDENSE_MAX`` = 3000 and
  4m <= n: a 3-D body touching on one face).  One sparse LDLᵀ of P with B
  ordered last yields the Schur complement S = P_BB − P_BU P_UU⁻¹ P_UB as its
  dense trailing block — no solves with m right-hand sides — and the reduced
  problem min ½ y'Sy + c_S'y, y >= l_B, is solved by the two phases below on
  dense m × m matrices.  The same factor then gives x = P⁻¹(−c + E λ),
  refined on the final active set's free block (solves with P_FF from the
  factor of P and S).  The elastic block with 441 contact dofs among 13 230
  unknowns: 3.8 s for the whole solve (2.3 s in the method, 3.0 LDLᵀs)
  against 9.9 s on the full route (measured in docs/pivoting.md).  S is never formed when m is large (m² memory, m³/3 per
  interior step); then the full route below.
* **Otherwise**, the two phases on P itself.

Why two phases.  Block pivoting alone ("bpp") is exact and fast when few
exchanges are needed, but on a mesh the active set's boundary moves about one
grid line per exchange (a membrane on 316 x 316 nodes: 81 exchanges, each a
factorization).  An interior-point method moves every component at once and
gets close in a mesh-independent number of steps, but only to a tolerance.
So:

1. **Interior point** (Mehrotra predictor-corrector, primal feasible: s =
   x_B − l_B > 0, multipliers λ > 0).  Each step solves with P + EΣE'
   (Σ = diag(λ/s) on B).  Its pattern never changes: the ordering and
   symbolic analysis are done once and each step is a numeric
   refactorization (QDLDL's ``update``; for 3-D stiffnesses and n > 4e5
   SuperLU's supernodal LDLᵀ, which is faster there even with its ordering
   redone each time).  The phase stops as soon as the
   active-set guess {i : λ_i > P_ii s_i} (force against stiffness times gap)
   has changed and then held for two steps (the first guesses, from the
   shifted start, mean little), once μ has dropped ``ip_drop`` times (default
   1e16: a guess that never moves), or after ``max_ip`` steps.
2. **Block pivoting from that guess** on the mixed problem: basis F (the free
   components and the inactive bounded ones), x_F from
   P_FF x_F = −(c_F + P_FA l_A), x_A = l_A, λ_A = (Px + c)_A.  Kostreva's
   exchange of the infeasible set with the Júdice–Pires safeguard and Murty's
   least-index pivots (:class:`ExchangeRule`): finite for every SPD P from any
   starting basis (eliminating the free components leaves an LCP whose matrix,
   a Schur complement of P, is SPD, and this is bpp on it).  The block solves
   reuse phase 1's symbolic analysis: rows and columns outside F are replaced
   by their diagonal entries, which keeps the pattern; a basis a few
   components from the last factorized one is solved by CG preconditioned
   with that factorization (:mod:`.finish`).  The accepted basis is
   refined iteratively against P itself.

The answer is exact up to rounding (a basic solution recomputed from the
data) and, like every answer, certified by :func:`qpcontact.solve`.  Signs are
decided componentwise: x_i − l_i against ρ(|l_i| + ((|P||x|)_i + |c_i|)/P_ii),
λ_i against ρ((|P||x|)_i + |c_i|), ρ = 1e3 eps.

Options: ``max_ip`` (default 60), ``ip_drop`` (1e16), ``max_iter`` (pivoting
steps, default 10 n + 100), ``patience`` (3), ``progress`` (a callable taking
one line per step, for long solves).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from ...core.deadline import Deadline
from ...core.errors import InvalidProblemError
from ...core.results import MethodResult
from .active_set import SIGN_RTOL, ExchangeRule, not_positive_definite, time_limit_result
from .finish import preconditioned_cg, restricted_preconditioner, reusable
from ...core.options import PROGRESS, BySize, Option, read_options

__all__ = ["run_ip_bpp", "IP_BPP_OPTIONS"]

IP_BPP_OPTIONS = (
    Option("max_ip", 60, "int", low=0, doc="interior-point steps at most"),
    Option("ip_drop", 1e16, "float", low=1.0,
           doc="the interior-point phase stops once the gap has dropped by this factor"),
    Option("max_iter", BySize(lambda n: 10 * n + 100, "10 n + 100"), "int", low=0,
           doc="pivoting steps at most"),
    Option("patience", 3, "int", low=0, doc="full exchanges without a new smallest |I|"),
    PROGRESS,
)


class _Factor:
    """Factorizations of P with a diagonal added, or of P with rows and
    columns outside a basis F replaced by their diagonal — every one with the
    same pattern, so the sparse symbolic analysis is done once."""

    #: Above this many entries per row of P (a 3-D elasticity stiffness has
    #: ~80, a 2-D Laplacian 5, the biharmonic 13), or above SUPERNODAL_N
    #: unknowns, SuperLU's supernodal factorization, ordering included, beats
    #: QDLDL's numeric-only update.  Measured (one thread): 3-D block
    #: n = 13 230, 0.63 s against 4.45 s; membrane n = 1e5, 0.28 s against
    #: 0.17 s; n = 2.5e5, 1.77 s against 1.04 s; n = 1e6, 8.6 s against 13.7 s.
    SUPERNODAL_ROW_NNZ = 20
    SUPERNODAL_N = 400_000

    def __init__(self, P):
        self.sparse = sp.issparse(P)
        n = P.shape[0]
        self.superlu = self.sparse and (P.nnz > self.SUPERNODAL_ROW_NNZ * n
                                        or n > self.SUPERNODAL_N)
        if self.superlu:
            self.P = P.tocsc()
            self.diag = np.asarray(P.diagonal(), dtype=float)
        elif self.sparse:
            U = (sp.triu(P, format="csc") + sp.identity(n, format="csc")).tocsc()
            U.sort_indices()
            self.indptr, self.indices = U.indptr, U.indices
            self.diag_pos = U.indptr[1:] - 1   # sorted upper triangle: the diagonal is last
            if not np.array_equal(self.indices[self.diag_pos], np.arange(n)):
                raise InvalidProblemError("P's upper triangle could not be read; pass a "
                                          "scipy.sparse matrix with real entries")
            self.diag = np.asarray(P.diagonal(), dtype=float)
            self.base = U.data.copy()
            self.base[self.diag_pos] = self.diag
            self.col = np.repeat(np.arange(n), np.diff(self.indptr))
            self.solver = None
        else:
            self.P = np.asarray(P, dtype=float)
            self.diag = np.diag(self.P).copy()

    def _qdldl(self, data):
        import qdldl

        A = sp.csc_matrix((data, self.indices, self.indptr), shape=(self.diag.size,) * 2)
        try:
            if self.solver is None:
                self.solver = qdldl.Solver(A, upper=True)
            else:
                self.solver.update(A, upper=True)
        except (ValueError, RuntimeError) as exc:   # QDLDL's zero pivot, or "not quasi-definite"
            raise np.linalg.LinAlgError(str(exc)) from None
        return self.solver.solve

    def _superlu(self, A):
        import scipy.sparse.linalg as spla

        try:   # symmetric mode, diagonal pivots: an LDL' of an SPD matrix
            lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options={"SymmetricMode": True})
        except RuntimeError as exc:   # exactly singular
            raise np.linalg.LinAlgError(str(exc)) from None
        return lu.solve

    def with_diagonal(self, bounded: np.ndarray, add: np.ndarray):
        """Solver for P + diag(add on ``bounded``)."""
        if self.superlu:
            extra = np.zeros(self.diag.size)
            extra[bounded] = add
            return self._superlu(self.P + sp.diags(extra))
        if self.sparse:
            data = self.base.copy()
            data[self.diag_pos[bounded]] += add
            return self._qdldl(data)
        A = self.P.copy()
        A[bounded, bounded] += add
        c = scipy.linalg.cho_factor(A, lower=True, check_finite=False)
        return lambda r: scipy.linalg.cho_solve(c, r, check_finite=False)

    def basis(self, F: np.ndarray):
        """Solver y = P_FF^{-1} r_F on F (zero elsewhere) for a bool mask F."""
        if self.sparse and not self.superlu:
            keep = F[self.indices] & F[self.col]
            data = np.where(keep, self.base, 0.0)
            data[self.diag_pos] = self.diag        # rows outside F: their diagonal alone
            solve_all = self._qdldl(data)
            return lambda r: np.where(F, solve_all(np.where(F, r, 0.0)), 0.0)
        idx = np.flatnonzero(F)
        if idx.size == 0:
            return np.zeros_like
        if self.superlu:
            solve_FF = self._superlu(self.P[idx][:, idx])
        else:
            c = scipy.linalg.cho_factor(self.P[np.ix_(idx, idx)], lower=True, check_finite=False)
            solve_FF = lambda r: scipy.linalg.cho_solve(c, r, check_finite=False)  # noqa: E731

        def solve(r):
            y = np.zeros_like(r)
            y[idx] = solve_FF(r[idx])
            return y
        return solve


def _problem_data(problem):
    P, c, G, h, A, b, lb, ub = problem.unpack()
    n = c.size
    if G is not None or A is not None or (ub is not None and np.any(np.isfinite(ub))):
        raise InvalidProblemError(
            "'ip-bpp' solves strictly convex QPs whose only constraints are lower bounds "
            "(x_i >= l_i, -inf for free components); this problem has "
            + ", ".join(w for w, v in (("inequalities G x <= h", G), ("equalities A x = b", A))
                        if v is not None)
            + (" upper bounds" if ub is not None and np.any(np.isfinite(ub)) else "")
            + " — use a QP backend (e.g. 'piqp', 'clarabel')")
    lb = np.full(n, -np.inf) if lb is None else np.asarray(lb, dtype=float)
    P = P.tocsc() if sp.issparse(P) else np.asarray(P, dtype=float)
    diag = np.asarray(P.diagonal() if sp.issparse(P) else np.diag(P), dtype=float)
    if not np.all(diag > 0):
        i = int(np.flatnonzero(~(diag > 0))[0])
        raise InvalidProblemError(f"'ip-bpp' needs P symmetric positive definite; P[{i},{i}] = "
                                  f"{diag[i]:g} is not positive — use a QP backend or 'lemke'")
    return P, np.asarray(c, dtype=float), lb


def _step_to_boundary(v, dv) -> float:
    """Largest α <= 1 with v + α dv >= 0 (v > 0)."""
    neg = dv < 0
    return min(1.0, float(np.min(-v[neg] / dv[neg]))) if np.any(neg) else 1.0


def _interior_point(P, c, lb, bounded, fac, max_ip, drop, stats, progress, deadline):
    """Phase 1: returns the active-set guess (mask over all components);
    past ``deadline`` the guess so far (the pivoting then stops at once)."""
    n = c.size
    B = np.flatnonzero(bounded)
    d = fac.diag[B]
    lB = lb[B]
    # start: the unconstrained minimizer, shifted into the interior (Mehrotra)
    x = fac.with_diagonal(B, np.zeros(B.size))(-c)
    stats["factorizations"] += 1
    s = x[B] - lB
    scale_s = max(np.max(np.abs(s)), np.max(np.abs(lB)), 1e-300)
    s = np.maximum(s, 0.0) + 1e-2 * scale_s
    lam = d * s
    shift = 0.5 * (s @ lam)
    s, lam = s + shift / max(lam.sum(), 1e-300), lam + shift / max(s.sum(), 1e-300)
    x[B] = lB + s
    mu0 = (s @ lam) / B.size
    guess_prev, moved, still = None, False, 0
    for k in range(max_ip):
        if deadline.expired():
            break
        r_d = P @ x + c
        r_d[B] -= lam
        sigma_diag = lam / s
        solve = fac.with_diagonal(B, sigma_diag)
        stats["factorizations"] += 1
        stats["ip_steps"] = k + 1

        def direction(r_c):
            rhs = -r_d
            rhs[B] -= r_c / s
            dx = solve(rhs)
            ds = dx[B]
            return dx, ds, (-r_c - lam * ds) / s

        dx, ds, dl = direction(s * lam)
        a_p, a_d = _step_to_boundary(s, ds), _step_to_boundary(lam, dl)
        mu = (s @ lam) / B.size
        mu_aff = ((s + a_p * ds) @ (lam + a_d * dl)) / B.size
        sigma = (mu_aff / mu) ** 3
        dx, ds, dl = direction(s * lam + ds * dl - sigma * mu)
        a_p = 0.99 * _step_to_boundary(s, ds)
        a_d = 0.99 * _step_to_boundary(lam, dl)
        x = x + a_p * dx
        s = np.maximum(s + a_p * ds, 1e-300)
        x[B] = lB + s
        lam = np.maximum(lam + a_d * dl, 1e-300)
        mu = (s @ lam) / B.size
        guess = np.zeros(n, bool)
        guess[B] = lam > d * s
        changed = 0 if guess_prev is None else int(np.count_nonzero(guess != guess_prev))
        moved = moved or changed > 0
        still = still + 1 if changed == 0 else 0
        if progress is not None:
            progress(f"ip-bpp: interior step {k + 1}: mu/mu0 = {mu / mu0:.1e}, "
                     f"{int(guess.sum())} active, {changed} changed")
        # The first guesses come from the shifted start and mean little: trust
        # a guess once it has moved and then held for two steps, or once μ is
        # negligible (a guess that never moves: right from the start).
        if (moved and still >= 2) or mu <= mu0 / drop:
            return guess
        guess_prev = guess
    return guess_prev if guess_prev is not None else np.zeros(n, bool)


class _NotConverged(Exception):
    """CG on a nearby basis did not reach rounding level: factorize it."""


def _nearby_solver(P, absP, F, factored, diag, max_steps, stats):
    """r ↦ P_FF⁻¹ r_F (zero off F) by CG preconditioned with the factorized
    basis ``factored`` = (F₀, its solve) — :mod:`.finish`'s reuse for the
    mixed problem; raises _NotConverged where CG does not get to rounding
    level, so the caller factorizes."""
    F0, solve0 = factored
    precondition = restricted_preconditioner(solve0, np.arange(F.size), F0, F, diag)
    stats.setdefault("krylov_solves", 0)
    stats.setdefault("krylov_steps", 0)

    def solve(r):
        x, steps = preconditioned_cg(P, absP, F, np.where(F, r, 0.0), precondition, max_steps)
        stats["krylov_solves"] += 1
        stats["krylov_steps"] += steps
        if x is None:
            raise _NotConverged
        return x
    return solve


def _pivoting(P, c, lb, bounded, active, fac, max_iter, patience, stats, progress, deadline):
    """Phase 2: block pivoting from the active set ``active``; returns (x, λ,
    status) and counts the final active set in ``stats["active"]``."""
    absP = abs(P)
    F = ~active
    rule = ExchangeRule(int(bounded.sum()), patience, stats)
    lb0 = np.where(bounded, lb, 0.0)

    def evaluate(solve, refine):
        A = ~F
        x = np.where(A, lb0, 0.0)
        g = P @ x + c
        x = x + solve(-g)
        g = P @ x + c
        rn = np.max(np.abs(g[F]), initial=0.0)
        for _ in range(refine):   # against P itself while the residual on F shrinks
            if rn == 0.0:
                break
            x_new = x + solve(-g)
            g_new = P @ x_new + c
            rn_new = np.max(np.abs(g_new[F]), initial=0.0)
            if not rn_new < rn:
                break
            x, g, rn = x_new, g_new, rn_new
        lam = np.where(A, g, 0.0)
        size = absP @ np.abs(x) + np.abs(c)
        tau_x = SIGN_RTOL * (np.abs(lb0) + size / fac.diag)
        bad = np.flatnonzero((F & bounded & (x - lb0 < -tau_x)) | (A & (lam < -SIGN_RTOL * size)))
        return x, lam, bad

    def evaluated(solve):
        # intermediate bases only need signs: refine once they look final
        x, lam, bad = evaluate(solve, 0)
        return evaluate(solve, 3) if bad.size == 0 else (x, lam, bad)

    factored = None   # (F, solve) of the last factorized basis
    while True:
        result = None
        if factored is not None:
            k = int(np.count_nonzero(F != factored[0]))
            if k == 0:
                result = evaluated(factored[1])
            elif reusable(k, F.size):
                try:
                    result = evaluated(_nearby_solver(P, absP, F.copy(), factored, fac.diag,
                                                      3 * k + 20, stats))
                except _NotConverged:
                    pass
        if result is None:
            solve = fac.basis(F)
            stats["factorizations"] += 1
            factored = (F.copy(), solve)
            result = evaluated(solve)
        x, lam, bad = result
        if progress is not None:
            progress(f"ip-bpp: pivoting step {stats['iterations'] + 1}: {bad.size} infeasible, "
                     f"{int((~F).sum())} active")
        if bad.size == 0:
            x[bounded] = np.maximum(x[bounded], lb[bounded])
            stats["active"] = int(np.count_nonzero(~F))
            return x, lam, "solved"
        if stats["iterations"] >= max_iter:
            return x, lam, "max_pivots"
        if deadline.expired():
            return None, None, "time_limit"
        stats["iterations"] += 1
        rule.step(F, bad)


#: Condense onto the bounded components when there are at most this many of
#: them and they are at most a quarter of the unknowns: the dense Schur
#: complement costs m² memory and m³/3 per interior step.
CONDENSE_MAX = 3000


def _condensed(P, bounded):
    """One sparse LDLᵀ of P with the bounded components ordered last; returns
    (S, solve): S = P_BB − P_BU P_UU⁻¹ P_UB, the dense trailing block of the
    factorization (no extra solves), and a solver for P itself.

    The free components U are ordered by SuperLU's minimum degree on P_UU
    (found by factoring P_UU: scipy exposes no ordering alone), then the
    factorization runs in symmetric mode with diagonal pivots on that fixed
    order, so P = L U with U = D Lᵀ and the trailing block of L U is S.  A
    row exchange or a pivot that is not positive means P is not positive
    definite (Sylvester) and raises LinAlgError."""
    import scipy.sparse.linalg as spla

    U, B = np.flatnonzero(~bounded), np.flatnonzero(bounded)
    opts = {"SymmetricMode": True}
    try:
        order_U = spla.splu(P[U][:, U].tocsc(), permc_spec="MMD_AT_PLUS_A",
                            diag_pivot_thresh=0.0, options=opts).perm_c
        order = np.concatenate([U[np.argsort(order_U)], B])
        lu = spla.splu(P[order][:, order].tocsc(), permc_spec="NATURAL",
                       diag_pivot_thresh=0.0, options=opts)
    except RuntimeError as exc:   # exactly singular
        raise np.linalg.LinAlgError(str(exc)) from None
    n, k = P.shape[0], U.size
    if not (np.array_equal(lu.perm_r, np.arange(n)) and np.array_equal(lu.perm_c, np.arange(n))
            and np.all(lu.U.diagonal() > 0)):
        raise np.linalg.LinAlgError("a pivot of P's LDL' is not positive")
    S = (lu.L.tocsc()[k:, k:] @ lu.U.tocsc()[k:, k:]).toarray()
    S = 0.5 * (S + S.T)
    inverse = np.argsort(order)
    return S, lambda r: lu.solve(r[order])[inverse]


def _free_block_solver(S, solve_P, B, active_B):
    """r ↦ δ with δ_A = 0 and (Pδ)_F = r_F (r zero on A): a solve with P_FF,
    F the complement of the active set A ⊂ B, from the factor of P and the
    dense S — no new sparse factorization.  δ = P⁻¹(r + E_A μ) for the
    multipliers μ that hold δ_A = 0; on B, S δ_B = S w_B + E_A μ with
    w = P⁻¹r, so δ_I = S_II⁻¹ (S w_B)_I on the inactive I and
    μ = S_AI δ_I − (S w_B)_A."""
    A_set, I_set = B[active_B], B[~active_B]
    if A_set.size == 0:
        return solve_P
    inner = np.flatnonzero(~active_B)
    S_II = scipy.linalg.cho_factor(S[np.ix_(inner, inner)], lower=True, check_finite=False) \
        if inner.size else None
    S_AI = S[np.ix_(np.flatnonzero(active_B), inner)]

    def solve(r):
        t = S @ solve_P(r)[B]
        d_I = scipy.linalg.cho_solve(S_II, t[~active_B], check_finite=False) \
            if S_II is not None else np.zeros(0)
        rhs = r.copy()
        rhs[A_set] += S_AI @ d_I - t[active_B]
        d = solve_P(rhs)
        d[A_set] = 0.0
        d[I_set] = d_I
        return d
    return solve


def _refined(P, c, x, active, solve_F, steps=3):
    """Iterative refinement of the final active set's KKT system, x_A held at
    its bound and (Px + c)_F = 0 solved on the free block F; a step is kept
    only while it lowers max |(Px + c)_F|, so the answer never gets worse,
    and none is taken once that is at the rounding of computing it (each
    step costs two solves with P's factor)."""
    F = np.ones(c.size, bool)
    F[active] = False
    rounding = 4 * np.finfo(float).eps * np.max((abs(P) @ np.abs(x) + np.abs(c))[F], initial=0.0)
    g = np.where(F, P @ x + c, 0.0)
    rn = np.max(np.abs(g), initial=0.0)
    for _ in range(steps):
        if rn <= rounding:
            break
        x_new = x - solve_F(g)
        g_new = np.where(F, P @ x_new + c, 0.0)
        rn_new = np.max(np.abs(g_new), initial=0.0)
        if not rn_new < rn:
            break
        x, g, rn = x_new, g_new, rn_new
    return x


def _solve_condensed(P, c, lb, bounded, max_ip, drop, max_iter, patience, stats, progress,
                     deadline):
    """The mixed problem through its Schur complement on the bounded
    components: the dense bound-constrained QP min ½ y'Sy + c_S'y, y >= l_B,
    by the same two phases, then x = P⁻¹(−c + E λ) with the full factor,
    refined on the free block F of the final active set A: x_A = l_A held,
    (Px + c)_F = 0.  Not with P itself and x_B reset after each step: that
    step's matrix on the free unknowns is (P⁻¹)_UU, the inverse of P_UU with
    the bounded unknowns' coupling removed, and where that coupling is stiff
    (soil springs under a soft plate) the iteration diverges."""
    B = np.flatnonzero(bounded)
    S, solve_P = _condensed(P, bounded)
    stats["factorizations"] += 2
    stats["condensed"] = int(B.size)
    # c_S = c_B − P_BU P_UU⁻¹ c_U, read off P⁻¹c whose B part is S⁻¹ c_S
    c_S = S @ solve_P(c)[B]
    fac = _Factor(S)
    all_bounded = np.ones(B.size, bool)
    active = _interior_point(S, c_S, lb[B], all_bounded, fac, max_ip, drop, stats, progress,
                             deadline)
    stats["initial_active"] = int(active.sum())
    _, lam_B, status = _pivoting(S, c_S, lb[B], all_bounded, active, fac, max_iter, patience,
                                 stats, progress, deadline)
    if status == "time_limit":
        return None, None, status
    lam = np.zeros(c.size)
    lam[B] = lam_B
    x = solve_P(lam - c)
    # the final active set: _pivoting's λ is exactly zero off it
    active = B[lam_B != 0]
    x[active] = lb[active]
    x = _refined(P, c, x, active, _free_block_solver(S, solve_P, B, lam_B != 0))
    x[B] = np.maximum(x[B], lb[B])
    lam = np.zeros(c.size)
    lam[active] = (P @ x + c)[active]
    return x, lam, status


def run_ip_bpp(problem, tol, options, time_limit=None) -> MethodResult:
    """The "ip-bpp" method (module docstring; options :data:`IP_BPP_OPTIONS`).
    ``time_limit`` (s): the deadline, checked at every interior step and
    exchange."""
    deadline = Deadline(time_limit)
    P, c, lb = _problem_data(problem)
    n = c.size
    opts = read_options("ip-bpp", options, IP_BPP_OPTIONS, size=n)
    bounded = np.isfinite(lb)
    max_ip, max_iter, patience = opts["max_ip"], opts["max_iter"], opts["patience"]
    drop, progress = opts["ip_drop"], opts["progress"]
    stats = {"iterations": 0, "factorizations": 0, "ip_steps": 0}
    m = int(bounded.sum())
    try:
        if sp.issparse(P) and 0 < m <= CONDENSE_MAX and 4 * m <= n:
            x, lam, status = _solve_condensed(P, c, lb, bounded, max_ip, float(drop), max_iter,
                                              patience, stats, progress, deadline)
            return _result(x, lam, bounded, status, max_iter, stats)
        fac = _Factor(P)
        active = (_interior_point(P, c, lb, bounded, fac, max_ip, float(drop), stats, progress,
                                  deadline)
                  if bounded.any() else np.zeros(n, bool))
        stats["initial_active"] = int(active.sum())
        x, lam, status = _pivoting(P, c, lb, bounded, active, fac, max_iter, patience, stats,
                                   progress, deadline)
    except np.linalg.LinAlgError as exc:
        raise not_positive_definite("ip-bpp", exc) from None
    return _result(x, lam, bounded, status, max_iter, stats)


def _result(x, lam, bounded, status, max_iter, stats) -> MethodResult:
    if status == "time_limit":
        return time_limit_result("ip-bpp", stats["iterations"] + stats["ip_steps"],
                                 "interior steps and exchanges", stats)
    return MethodResult(
        x=x, z_box=np.where(bounded, -lam, 0.0), backend_status=status,
        iterations=stats["iterations"] + stats["ip_steps"],
        status="max_pivots" if status == "max_pivots" else None,
        backend_message=(f"pivoting limit {max_iter} reached" if status == "max_pivots" else ""),
        stats=stats)
