"""Nonlinear two-point boundary-value problems (the rod paper: Pustovoy, Levin &
Krasnorutskiy 2014, its KLPALG solver): trapezoidal finite
differences, damped Newton, deferred correction, pseudo-arclength continuation.

Problem: y'(s) = f(s, y) on [a, b] (y in R^m), boundary conditions
g(y(a), y(b)) = 0 (m equations; separated or coupled).

Discretisation on a mesh s_0 < ... < s_N (trapezoidal rule, O(h²))::

    y_{j+1} - y_j - h_j/2 (f_j + f_{j+1}) = 0,   j = 0..N-1,   g(y_0, y_N) = 0.

Newton's method on these m(N+1) equations; the step length λ is the largest
of 1, ½, ¼, ... with ‖R(Y + λΔ)‖² <= (1 - 2cλ)‖R(Y)‖², c = 0.11 (the paper's); the
Jacobian is reused while the residual falls by at least half per step.  The
Jacobian is block bidiagonal (m x m blocks) plus the boundary rows: with
separated conditions, ordered [left conditions; intervals; right
conditions], it is banded and factorised by LAPACK's banded LU with partial
pivoting — the paper's block LU with pivoting inside the blocks (:class:`BlockLU`);
coupled conditions go to SuperLU.  Both give the sign of the determinant,
which continuation watches for turning points and bifurcations.

Deferred correction (Pereyra): the trapezoid's local error is
-h³/12 f⁽²⁾(s_{j+½}) - h⁵/480 f⁽⁴⁾(s_{j+½}) + O(h⁷); the derivatives of f are
estimated from nodal values by finite-difference weights on the
(nonuniform) mesh, and the system is solved again with that correction on
the right-hand side: one level (4 nodes, f⁽²⁾) gives O(h⁴), two levels (6
nodes, both terms) O(h⁶).  The change made by the last level estimates the
global error per node; intervals where it exceeds the tolerance are bisected
(mesh refinement where the estimate says so) until it meets the tolerance.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from qpcontact.core.errors import InvalidProblemError

__all__ = ["BVPResult", "BlockLU", "solve", "continuation", "ContinuationResult"]

ARMIJO_C = 0.11


@dataclass
class BVPResult:
    """Solution on ``mesh`` (``y`` has shape (m, N+1)), with what proves it:
    ``status`` "solved" / "no convergence" / "singular Jacobian";
    ``residual`` the max-norm of the discrete equations; ``error_estimate`` the
    estimated max global error; ``order`` 2 or 4 (with deferred correction);
    ``history`` the residual per Newton step."""

    mesh: np.ndarray
    y: np.ndarray
    status: str
    ok: bool
    message: str
    residual: float
    error_estimate: float
    order: int
    newton_steps: int
    history: list = field(default_factory=list)

    def __call__(self, s):
        """Piecewise-linear interpolation of y at s."""
        s = np.atleast_1d(s)
        return np.array([np.interp(s, self.mesh, yi) for yi in self.y])


def _fd_jac(fun, s, Y, F):
    """∂f/∂y at every node by forward differences, shape (m, m, N)."""
    m, N = Y.shape
    J = np.empty((m, m, N))
    for k in range(m):
        h = 1e-7 * np.maximum(1.0, np.abs(Y[k]))
        Yp = Y.copy()
        Yp[k] += h
        J[:, k, :] = (fun(s, Yp) - F) / h
    return J


def _fd_bc_jac(bc, ya, yb, g):
    m = ya.size
    Ja, Jb = np.empty((g.size, m)), np.empty((g.size, m))
    for k in range(m):
        h = 1e-7 * max(1.0, abs(ya[k]))
        e = np.zeros(m)
        e[k] = h
        Ja[:, k] = (bc(ya + e, yb) - g) / h
        h = 1e-7 * max(1.0, abs(yb[k]))
        e = np.zeros(m)
        e[k] = h
        Jb[:, k] = (bc(ya, yb + e) - g) / h
    return Ja, Jb


def _residual(fun, bc, s, Y, corr):
    F = fun(s, Y)
    h = np.diff(s)
    R = Y[:, 1:] - Y[:, :-1] - 0.5 * h * (F[:, :-1] + F[:, 1:])
    if corr is not None:
        R = R - corr
    g = np.asarray(bc(Y[:, 0], Y[:, -1]), float)
    return np.concatenate([R.T.ravel(), g]), F


def _jacobian(fun, bc, s, Y, F, jac):
    """The Newton matrix ∂R/∂Y in factorised form (:class:`BlockLU`)."""
    h = np.diff(s)
    m = Y.shape[0]
    Jf = jac(s, Y) if jac is not None else _fd_jac(fun, s, Y, F)
    eye = np.eye(m)[:, :, None]
    A = -eye - 0.5 * h[None, None, :] * Jf[:, :, :-1]        # (m, m, N): ∂R_j/∂y_j
    B = eye - 0.5 * h[None, None, :] * Jf[:, :, 1:]          # ∂R_j/∂y_{j+1}
    g = np.asarray(bc(Y[:, 0], Y[:, -1]), float)
    Ja, Jb = _fd_bc_jac(bc, Y[:, 0], Y[:, -1], g)
    return BlockLU(A, B, Ja, Jb)


class BlockLU:
    """LU factorisation of the trapezoid's Newton matrix ::

        rows j = 0..N-1:  A_j y_j + B_j y_{j+1}   (m x m blocks),
        boundary rows:    J_a y_0 + J_b y_N.

    With separated conditions (each boundary row touches one end) the rows
    are put in the order [left conditions; intervals 0..N-1; right
    conditions], which makes the matrix banded with kl = p + m - 1 and
    ku = 2m - 1 - p (p left conditions): LAPACK's banded LU with partial
    pivoting (dgbtrf) then is the paper's block elimination with pivoting inside the
    blocks, in O(N m³).  Coupled conditions (a row touching both ends) break
    the band; those go to SuperLU on the sparse matrix.  Either way
    ``det_sign`` gives the sign of det(∂R/∂Y) (fixed row order), whose changes
    along a continuation path mark turning points and bifurcations."""

    def __init__(self, A, B, Ja, Jb):
        m, _, N = A.shape
        self.m, self.N1, self.n = m, N + 1, m * (N + 1)
        left = ~np.any(Jb != 0, axis=1)
        right = ~left & ~np.any(Ja != 0, axis=1)
        self.separated = bool(np.all(left | right))
        j = np.arange(N)
        ii, kk = np.meshgrid(np.arange(m), np.arange(m), indexing="ij")
        rows = (j[None, None, :] * m + ii[:, :, None]).ravel()
        colsA = (j[None, None, :] * m + kk[:, :, None]).ravel()
        r0 = N * m
        rb = np.repeat(r0 + np.arange(m), m)
        cb = np.tile(np.arange(m), m)
        R = np.concatenate([rows, rows, rb, rb])
        C = np.concatenate([colsA, colsA + m, cb, cb + N * m])
        V = np.concatenate([A.ravel(), B.ravel(), Ja.ravel(), Jb.ravel()])
        self._triplets = (R, C, V)
        self._matrix = None
        if self.separated:
            p = int(left.sum())
            # original row -> banded row: left conditions first, then intervals, then right
            new = np.empty(self.n, int)
            new[:r0] = p + np.arange(r0)
            bc_rows = r0 + np.arange(m)
            new[bc_rows[left]] = np.arange(p)
            new[bc_rows[~left]] = p + r0 + np.arange(m - p)
            self._order = new
            kl, ku = p + m - 1, max(2 * m - 1 - p, m - 1)
            Rn = new[R]
            keep = V != 0
            ab = np.zeros((2 * kl + ku + 1, self.n))
            ab[kl + ku + Rn[keep] - C[keep], C[keep]] = V[keep]
            from scipy.linalg.lapack import dgbtrf
            self._lu, self._piv, info = dgbtrf(ab, kl, ku)
            self.kl, self.ku = kl, ku
            self.singular = info > 0       # an exactly zero pivot
        else:
            try:
                self._splu = spla.splu(self.matrix)
                self.singular = False
            except RuntimeError:      # SuperLU: exactly singular
                self.singular = True

    @property
    def matrix(self):
        """The Newton matrix as a sparse CSC (original row order), built on
        demand: SuperLU's input, and the bordered systems' at a fold."""
        if self._matrix is None:
            R, C, V = self._triplets
            self._matrix = sp.csc_matrix((V, (R, C)), shape=(self.n, self.n))
            self._matrix.eliminate_zeros()  # structural zeros would only add fill
        return self._matrix

    @property
    def det_sign(self) -> int:
        """Sign of det(∂R/∂Y) in the original row order (0 when exactly
        singular); computed on demand — only continuation asks for it."""
        if self.singular:
            return 0
        if self.separated:
            diag = self._lu[self.kl + self.ku]
            swaps = int(np.count_nonzero(self._piv != np.arange(self.n)))
            return int(np.prod(np.sign(diag))) * (-1) ** swaps * _perm_sign(self._order)
        return (int(np.prod(np.sign(self._splu.U.diagonal())))
                * _perm_sign(self._splu.perm_r) * _perm_sign(self._splu.perm_c))

    def solve(self, rhs):
        """J⁻¹ rhs (NaN when J is exactly singular: callers test finiteness)."""
        rhs = np.asarray(rhs, float)
        if self.singular:
            return np.full(rhs.shape, np.nan)
        if not self.separated:
            return self._splu.solve(rhs)
        b = np.empty_like(rhs)
        b[self._order] = rhs
        from scipy.linalg.lapack import dgbtrs
        x, info = dgbtrs(self._lu, self.kl, self.ku, b, self._piv)
        return x


def _perm_sign(perm) -> int:
    """Sign (+1/-1) of a permutation given as an index array (cycle count)."""
    perm = np.asarray(perm)
    seen = np.zeros(perm.size, bool)
    sign = 1
    for i in range(perm.size):
        if not seen[i]:
            k, length = i, 0
            while not seen[k]:
                seen[k] = True
                k = perm[k]
                length += 1
            if length % 2 == 0:
                sign = -sign
    return sign


def _newton(fun, bc, s, Y, jac, tol, max_steps, corr=None):
    """Damped Newton with Jacobian reuse; returns (Y, status, residual, steps, history)."""
    m, N1 = Y.shape
    R, F = _residual(fun, bc, s, Y, corr)
    rn = float(np.max(np.abs(R)))
    history = [rn]
    lu = None
    steps = 0
    scale = max(1.0, float(np.max(np.abs(Y))))
    while steps < max_steps:
        if rn <= tol * scale:
            return Y, "solved", rn, steps, history
        if lu is None:
            lu = _jacobian(fun, bc, s, Y, F, jac)
            if lu.singular:
                return Y, "singular Jacobian", rn, steps, history
        d = lu.solve(-R)
        if not np.all(np.isfinite(d)):
            return Y, "singular Jacobian", rn, steps, history
        D = d.reshape(N1, m).T
        lam, accepted = 1.0, False
        r2 = float(R @ R)
        while lam >= 1.0 / 1024:
            Yn = Y + lam * D
            Rn, Fn = _residual(fun, bc, s, Yn, corr)
            if np.all(np.isfinite(Rn)) and float(Rn @ Rn) <= (1 - 2 * ARMIJO_C * lam) * r2:
                accepted = True
                break
            lam /= 2
        steps += 1
        if not accepted:
            if lu is not None and steps > 1:
                lu = None  # stale Jacobian: refactor and try again
                continue
            return Y, "no convergence", rn, steps, history
        rn_new = float(np.max(np.abs(Rn)))
        if rn_new > 0.5 * rn:
            lu = None
        Y, R, F, rn = Yn, Rn, Fn, rn_new
        history.append(rn)
    return Y, ("solved" if rn <= tol * scale else "no convergence"), rn, steps, history


#: Midpoint expansion of the trapezoid's local error per interval:
#: ∫f - h/2 (f_j + f_{j+1}) = -h³/12 f⁽²⁾(m) - h⁵/480 f⁽⁴⁾(m) + O(h⁷).
_DC_TERMS = ((2, -1.0 / 12.0, 3), (4, -1.0 / 480.0, 5))


def _dc_correction(s, F, level):
    """The trapezoid's local error per interval from nodal values of f:
    level 1 (-> order 4): -h³/12 f⁽²⁾ from 4 nodes; level 2 (-> order 6): adds
    -h⁵/480 f⁽⁴⁾ and takes both derivatives from 6 nodes.  Finite-difference
    weights at each midpoint from batched Vandermonde systems (nonuniform
    meshes); stencils are centred and shifted inwards at the ends."""
    m, N1 = F.shape
    k = 2 * level + 2
    corr = np.zeros((m, N1 - 1))
    if N1 < k:
        return corr
    h = np.diff(s)
    j = np.arange(N1 - 1)
    lo = np.clip(j - (k // 2 - 1), 0, N1 - k)
    idx = lo[:, None] + np.arange(k)[None, :]                    # (N, k)
    x = s[idx] - 0.5 * (s[:-1] + s[1:])[:, None]
    V = x[:, None, :] ** np.arange(k)[None, :, None]             # (N, k powers, k nodes)
    terms = _DC_TERMS[:level]
    rhs = np.zeros((N1 - 1, k, len(terms)))
    for c, (d, _, _) in enumerate(terms):
        rhs[:, d, c] = float(np.prod(np.arange(1, d + 1)))      # d-th derivative at 0
    W = np.linalg.solve(V, rhs)                                 # (N, k, terms)
    Fi = F[:, idx]                                              # (m, N, k)
    for c, (_, coef, p) in enumerate(terms):
        corr += coef * h ** p * np.einsum("mnk,nk->mn", Fi, W[:, :, c])
    return corr


def _validate(fun, bc, mesh, y0):
    s = np.asarray(mesh, float)
    if s.ndim != 1 or s.size < 3 or not np.all(np.diff(s) > 0):
        raise InvalidProblemError("mesh must be an increasing 1-D array of at least 3 points")
    Y = np.asarray(y0, float)
    if Y.ndim == 1:
        Y = np.repeat(Y[:, None], s.size, axis=1)
    if Y.ndim != 2 or Y.shape[1] != s.size:
        raise InvalidProblemError(f"y0 must have shape (m, {s.size}) or (m,); got {np.shape(y0)}")
    F = np.asarray(fun(s, Y), float)
    if F.shape != Y.shape:
        raise InvalidProblemError(f"fun(s, y) must return shape {Y.shape}; got {F.shape}")
    g = np.asarray(bc(Y[:, 0], Y[:, -1]), float)
    if g.shape != (Y.shape[0],):
        raise InvalidProblemError(f"bc(ya, yb) must return {Y.shape[0]} residuals; got {g.shape}")
    return s, Y.copy()


def _refine(s, Y, flags):
    """Bisect the flagged intervals; Y interpolated linearly onto the new nodes."""
    mid = 0.5 * (s[:-1] + s[1:])[flags]
    s2 = np.sort(np.concatenate([s, mid]))
    Y2 = np.array([np.interp(s2, s, y) for y in Y])
    return s2, Y2


def solve(fun, bc, mesh, y0, *, jac=None, tol: float = 1e-8, max_newton: int = 50,
          corrections: int = 2, max_refinements: int = 8) -> BVPResult:
    """Solve y' = fun(s, y), bc(y(a), y(b)) = 0 (module docstring).

    ``fun(s, Y)`` is vectorised over the nodes (Y of shape (m, N+1)), as in
    scipy.integrate.solve_bvp; ``jac(s, Y)`` optional, shape (m, m, N+1).
    ``corrections``: deferred-correction levels (0, 1, 2 -> order 2, 4, 6).
    ``tol`` bounds the estimated global error (max norm, relative to
    ``max(1, |y|)``).  The estimate is the change made by the last correction
    level (with ``corrections=0``, a Richardson estimate from a halved mesh);
    the intervals where it exceeds the tolerance are bisected and the problem
    is solved again, until the estimate meets the tolerance.
    """
    if corrections not in (0, 1, 2):
        raise InvalidProblemError(f"corrections must be 0, 1 or 2 (orders 2, 4, 6); got {corrections}")
    s, Y = _validate(fun, bc, mesh, y0)
    history_all = []
    prev = None
    for level in range(max_refinements + 1):
        ntol = max(1e-3 * tol, 1e-13)  # Newton to well below the discretisation error
        Y, status, res, steps, hist = _newton(fun, bc, s, Y, jac, ntol, max_newton)
        history_all += hist
        if status != "solved":
            return BVPResult(s, Y, status, False, f"{status} after {steps} Newton steps on "
                             f"{s.size} nodes (residual {res:.2e})", res, np.inf, 2,
                             len(history_all), history_all)
        order, Ysol, Yprev = 2, Y, None
        for c in range(1, corrections + 1):
            corr = _dc_correction(s, fun(s, Ysol), c)
            Yc, status_c, res_c, _, hist_c = _newton(fun, bc, s, Ysol, jac, ntol, max_newton, corr)
            history_all += hist_c
            if status_c != "solved":
                break
            Yprev, Ysol, order = Ysol, Yc, 2 + 2 * c
        scale = max(1.0, float(np.max(np.abs(Ysol))))
        if Yprev is not None:
            node_err = np.max(np.abs(Ysol - Yprev), axis=0) / scale
            est = float(node_err.max())
            flags = np.maximum(node_err[:-1], node_err[1:]) > tol
            if flags.sum() > 0.5 * flags.size:
                flags[:] = True        # most intervals: refine uniformly
        else:   # order 2 only: Richardson against the previous mesh (halved)
            est = np.inf if prev is None else \
                float(np.max(np.abs(Ysol[:, ::2] - prev[1]))) / scale / 3.0
            flags = np.ones(s.size - 1, bool)
        if est <= tol or level == max_refinements:
            ok = est <= tol
            msg = (f"solved on {s.size} nodes, order {order}, estimated error {est:.1e}"
                   + ("" if ok else f" > tol {tol:.0e} after {level} refinements"))
            return BVPResult(s, Ysol, "solved" if ok else "no convergence", ok, msg, res, est,
                             order, len(history_all), history_all)
        prev = (s, Ysol)
        s, Y = _refine(s, Ysol, flags)
    raise AssertionError("unreachable")


def _bordered_solve(J: BlockLU, column, row, rhs):
    """Solve [[J, column], [row']] x = rhs (row has n + 1 entries).

    Block elimination with J's block LU (cheap); when J is singular or nearly
    so (at a fold, where the bordered matrix is not), the whole bordered
    matrix is factorised by SuperLU instead (its dense border costs fill, so
    only there)."""
    n = J.n
    a = J.solve(rhs[:n])
    b = J.solve(column)
    denom = row[n] - row[:n] @ b
    if np.all(np.isfinite(a)) and np.all(np.isfinite(b)) and \
            abs(denom) > 1e-10 * (abs(row[n]) + np.abs(row[:n]) @ np.abs(b)):
        xi = (rhs[n] - row[:n] @ a) / denom
        return np.concatenate([a - xi * b, [xi]])
    A = sp.bmat([[J.matrix, sp.csc_matrix(column[:, None])],
                 [sp.csc_matrix(row[None, :n]), sp.csc_matrix([[row[n]]])]], format="csc")
    return spla.splu(A).solve(rhs)


@dataclass
class ContinuationResult:
    """The branch: parameter values ``gammas``, solutions ``ys`` (each (m, N+1)
    on ``mesh``), and how it ended.  ``det_signs``: the sign of det(∂R/∂Y) at
    each point.  A sign change between two points marks a singular Jacobian
    on the way: a turning point (``folds``: index of the point after it) when
    γ changed direction there too, a bifurcation point (``bifurcations``)
    when it did not — a branch crossing this one, which continuation steps
    over."""

    mesh: np.ndarray
    gammas: np.ndarray
    ys: list
    folds: list
    status: str
    message: str
    det_signs: list = field(default_factory=list)
    bifurcations: list = field(default_factory=list)


def continuation(fun, bc, mesh, y0, gamma_span, *, jac=None, ds: float = 0.05,
                 ds_max: float = 0.5, ds_min: float = 1e-6, max_steps: int = 500,
                 tol: float = 1e-10) -> ContinuationResult:
    """Pseudo-arclength continuation of y' = fun(s, y, γ), bc(ya, yb, γ) = 0 in γ
    from gamma_span[0] (where y0 is a good guess) until γ reaches gamma_span[1].

    Unknowns (Y, γ); the extra equation t'[(Y, γ) - (Y_k, γ_k)] = ds with t the
    unit tangent (oriented by the previous one), so the branch is followed
    through folds, which are reported where γ changes direction.  The step
    grows after easy corrector steps and halves after failures.
    """
    g0, g1 = float(gamma_span[0]), float(gamma_span[1])
    direction = np.sign(g1 - g0) or 1.0
    f0 = lambda s, Y: fun(s, Y, g0)  # noqa: E731
    b0 = lambda ya, yb: bc(ya, yb, g0)  # noqa: E731
    s, Y = _validate(f0, b0, mesh, y0)
    Y, status, res, _, _ = _newton(f0, b0, s, Y, None if jac is None else (lambda s_, Y_: jac(s_, Y_, g0)),
                                   tol, 100)
    if status != "solved":
        return ContinuationResult(s, np.array([g0]), [Y], [], status,
                                  f"no solution at the start gamma = {g0}: {status}")
    m, N1 = Y.shape
    n = m * N1

    def R_of(Yv, gam):
        return _residual(lambda s_, Y_: fun(s_, Y_, gam), lambda a, b: bc(a, b, gam), s, Yv, None)

    def J_of(Yv, gam, F):
        return _jacobian(lambda s_, Y_: fun(s_, Y_, gam), lambda a, b: bc(a, b, gam), s, Yv, F,
                         None if jac is None else (lambda s_, Y_: jac(s_, Y_, gam)))

    def dR_dgamma(Yv, gam, R0):
        dg = 1e-7 * max(1.0, abs(gam))
        R1, _ = R_of(Yv, gam + dg)
        return (R1 - R0) / dg

    def tangent(Yv, gam, prev_t):
        R0, F = R_of(Yv, gam)
        J = J_of(Yv, gam, F)
        Rg = dR_dgamma(Yv, gam, R0)
        # solve [J Rg; prev_t'] t = [0; 1]
        rhs = np.zeros(n + 1)
        rhs[-1] = 1.0
        t = _bordered_solve(J, Rg, prev_t, rhs)
        return t / np.linalg.norm(t), J.det_sign

    # initial tangent: differentiate along gamma
    R0, F0 = R_of(Y, g0)
    J0 = J_of(Y, g0, F0)
    dY = J0.solve(-dR_dgamma(Y, g0, R0))
    t = np.concatenate([dY, [1.0]]) * direction
    t /= np.linalg.norm(t)
    x = np.concatenate([Y.T.ravel(), [g0]])
    gammas, ys, folds, bifs, dets = [g0], [Y.copy()], [], [], [J0.det_sign]
    step = ds
    for _ in range(max_steps):
        pred = x + step * t
        z = pred.copy()
        ok = False
        for _it in range(30):
            Yz = z[:n].reshape(N1, m).T
            R, F = R_of(Yz, z[-1])
            arc = t @ (z - x) - step
            full = np.concatenate([R, [arc]])
            if np.max(np.abs(full)) <= tol * max(1.0, np.max(np.abs(z))):
                ok = True
                break
            J = J_of(Yz, z[-1], F)
            Rg = dR_dgamma(Yz, z[-1], R)
            try:
                dz = _bordered_solve(J, Rg, t, -full)
            except RuntimeError:
                break
            z = z + dz
        if not ok:
            step /= 2
            if step < ds_min:
                return ContinuationResult(s, np.array(gammas), ys, folds, "no convergence",
                                          f"corrector failed at gamma = {x[-1]:.6g} (step < {ds_min})",
                                          dets, bifs)
            continue
        Yz = z[:n].reshape(N1, m).T
        t_new, det = tangent(Yz, z[-1], t)
        if t_new @ t < 0:
            t_new = -t_new
        turned = np.sign(t_new[-1]) != np.sign(t[-1]) and t[-1] != 0
        if turned:
            folds.append(len(gammas))
        elif det * dets[-1] < 0:
            bifs.append(len(gammas))
        dets.append(det)
        x, t = z, t_new
        gammas.append(z[-1])
        ys.append(Yz)
        if (z[-1] - g1) * direction >= 0:
            # land exactly on g1 with a natural-parameter Newton solve
            Yend, st, *_ = _newton(lambda s_, Y_: fun(s_, Y_, g1), lambda a, b: bc(a, b, g1), s, Yz,
                                   None, tol, 50)
            gammas[-1], ys[-1] = g1, Yend
            return ContinuationResult(s, np.array(gammas), ys, folds, "solved",
                                      f"reached gamma = {g1} in {len(gammas) - 1} steps, "
                                      f"{len(folds)} fold(s), {len(bifs)} bifurcation(s)",
                                      dets, bifs)
        step = min(step * (1.5 if _it < 4 else 1.0), ds_max)
    return ContinuationResult(s, np.array(gammas), ys, folds, "max_steps",
                              f"stopped at gamma = {x[-1]:.6g} after {max_steps} steps", dets, bifs)
