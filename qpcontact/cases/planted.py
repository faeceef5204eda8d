"""Hard LCPs and QPs with their answer built in (no hypothesis needed).

:func:`build_lcp` and :func:`build_qp` make one :class:`Case` from a kind, a
size and a seed; :mod:`qpcontact.testing.strategies` draws them with
hypothesis and ``qpcontact stress`` sweeps them.  The kinds are described in
:mod:`qpcontact.testing.strategies`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from qpsolvers import Problem

from ..core.options import check_seed
from ..core.problems import LCP
from .families import random_spd

__all__ = ["Case", "build_lcp", "build_qp", "LCP_KINDS", "QP_KINDS"]

#: The kinds of LCP :func:`build_lcp` (and the strategy ``lcps``) can plant.
LCP_KINDS = ("spd", "psd_singular", "degenerate", "badly_scaled", "p_matrix", "friction",
             "infeasible")
#: The kinds of QP :func:`build_qp` (and the strategy ``qps``) can plant.
QP_KINDS = ("convex", "degenerate", "infeasible", "unbounded", "penalty")


@dataclass
class Case:
    """A drawn problem and what a correct solver must find.

    ``status``: "solved", "infeasible" or "unbounded".  For LCPs ``z``/``w``
    are the planted solution (``unique_z``: whether z is the only one; w is
    unique for every symmetric PSD kind); for QPs ``x`` is the planted
    minimiser (``unique_z`` then means x is unique) and ``objective`` its value."""

    kind: str
    problem: object
    status: str
    z: np.ndarray | None = None
    w: np.ndarray | None = None
    x: np.ndarray | None = None
    objective: float | None = None
    unique_z: bool = False
    unique_w: bool = True
    seed: int = 0
    #: each component's natural size where the data were scaled (a planted
    #: zero is judged on it); None: the smallest planted nonzero magnitude
    z_scale: np.ndarray | None = None
    w_scale: np.ndarray | None = None
    #: how the answer (or status) was established, for the families whose
    #: reference is computed exactly (qpcontact.cases.rounded)
    reference: str = ""
    #: the exact Farkas vector or ray the status rests on, where it is a
    #: vector of doubles (tests re-check it in their own rational code)
    witness: np.ndarray | None = None

    def scales(self) -> tuple[np.ndarray, np.ndarray]:
        """Per-component scales of z and w that an answer's error is judged on:
        ``max(|planted value|, the component's natural size)``."""
        if self.z_scale is not None:
            return (np.maximum(np.abs(self.z), self.z_scale),
                    np.maximum(np.abs(self.w), self.w_scale))
        nz = np.concatenate([np.abs(self.z[self.z != 0]), np.abs(self.w[self.w != 0])])
        floor = float(nz.min()) if nz.size else 1.0
        return np.maximum(np.abs(self.z), floor), np.maximum(np.abs(self.w), floor)

    def agrees(self, answer, rtol: float = 1e-6) -> bool:
        """Whether an answer (LCP z, or QP x) matches the planted one, each
        component against its own size (the smallest planted nonzero
        magnitude as the floor), on what the data determine: z and w (or only
        w) for LCPs; x, or only the objective, for QPs."""
        if answer is None or self.status != "solved":
            return False
        a = np.asarray(answer, float)
        if isinstance(self.problem, LCP):
            w = self.problem.w(a)
            zs, ws = self.scales()
            floor = float(min(zs.min(), ws.min()))
            if not self.unique_w:
                # nothing planted is determined: z >= 0, w >= 0, z_i w_i = 0
                # checked here, independently of qpcontact.certify, each pair
                # on its own scale |q_i| + (|M||z|)_i
                M, q = self.problem.M, self.problem.q
                sig = np.abs(q) + np.abs(M) @ np.abs(a)
                zs = np.maximum(np.abs(a), floor)
                return bool(np.all(np.minimum(a / zs, w / np.maximum(sig, 1e-300)) >= -rtol)
                            and np.all(np.minimum(np.abs(a) / zs, np.abs(w) / np.maximum(sig, 1e-300))
                                       <= rtol))
            ok_w = np.all(np.abs(w - self.w) <= rtol * ws)
            if not self.unique_z:
                return bool(ok_w and np.all(a >= -rtol * zs))
            return bool(ok_w and np.all(np.abs(a - self.z) <= rtol * zs))
        if self.unique_z:
            floor = max(float(np.abs(self.x).max()), 1e-300) * 1e-3
            return bool(np.all(np.abs(a - self.x) <= rtol * np.maximum(np.abs(self.x), floor)))
        P, q = self.problem.P, self.problem.q
        f = 0.5 * a @ (P @ a) + q @ a
        scale = 0.5 * np.abs(a) @ (np.abs(P) @ np.abs(a)) + np.abs(q) @ np.abs(a)
        return bool(abs(f - self.objective) <= rtol * max(scale, 1e-300))


def _complementary(n, rng, active_fraction=0.5, degenerate=0.0, low=0.1, high=2.0):
    kind = rng.choice(3, size=n, p=[(1 - degenerate) * active_fraction,
                                    (1 - degenerate) * (1 - active_fraction), degenerate])
    z = np.where(kind == 0, rng.uniform(low, high, n), 0.0)
    w = np.where(kind == 1, rng.uniform(low, high, n), 0.0)
    return z, w


def _friction_matrix(contacts: int, rng) -> tuple[np.ndarray, int]:
    """Stewart–Trinkle LCP matrix of ``contacts`` 2-D contacts on a body with
    a random SPD inverse mass: unknowns (λ_n, λ_t+, λ_t-, σ) per contact,
    rows (normal gap rate, tangential rate ± σ, friction-cone slack)."""
    m = 3 * contacts
    W = random_spd(2 * contacts, 10.0, rng) + 0.1 * np.eye(2 * contacts)  # contact-space Delassus
    N = np.zeros((contacts, 2 * contacts))
    T = np.zeros((contacts, 2 * contacts))
    for c in range(contacts):
        N[c, 2 * c], T[c, 2 * c + 1] = 1.0, 1.0
    D = np.vstack([T, -T])  # each contact's +t and -t directions, stacked per sign
    E = np.vstack([np.eye(contacts), np.eye(contacts)])
    mu = np.diag(rng.uniform(0.1, 0.8, contacts))
    size = contacts + 2 * contacts + contacts
    M = np.zeros((size, size))
    M[:contacts, :contacts] = N @ W @ N.T
    M[:contacts, contacts:m] = N @ W @ D.T
    M[contacts:m, :contacts] = D @ W @ N.T
    M[contacts:m, contacts:m] = D @ W @ D.T
    M[contacts:m, m:] = E
    M[m:, :contacts] = mu
    M[m:, contacts:m] = -E.T
    return M, size


def build_lcp(kind: str, n: int, seed: int, *, cond: float = 1e4, decades: float = 8.0) -> Case:
    """One LCP case, deterministic in its arguments (see the module docstring)."""
    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    if kind in ("spd", "degenerate", "badly_scaled"):
        M = random_spd(n, cond, rng)
        z, w = _complementary(n, rng, degenerate=0.3 if kind == "degenerate" else 0.0)
        if kind == "badly_scaled":
            d = 10.0 ** rng.uniform(-decades / 2, decades / 2, n)
            M = (M * d[:, None]) * d[None, :]
            M = 0.5 * (M + M.T)
            z, w = z / d, w * d
            return Case(kind, LCP(M, w - M @ z), "solved", z=z, w=w, unique_z=True, seed=seed,
                        z_scale=0.1 / d, w_scale=0.1 * d)
        return Case(kind, LCP(M, w - M @ z), "solved", z=z, w=w, unique_z=True, seed=seed)
    if kind == "psd_singular":
        r = max(1, n // 2)
        B = rng.standard_normal((n, r))
        M = B @ B.T
        z, w = _complementary(n, rng)
        return Case(kind, LCP(M, w - M @ z), "solved", z=z, w=w, unique_z=False, seed=seed)
    if kind == "p_matrix":
        S = random_spd(n, cond, rng)
        K = rng.standard_normal((n, n))
        M = S + (K - K.T) * rng.uniform(0.1, 2.0)
        z, w = _complementary(n, rng)
        return Case(kind, LCP(M, w - M @ z), "solved", z=z, w=w, unique_z=True, seed=seed)
    if kind == "friction":
        M, size = _friction_matrix(max(1, n // 4), rng)
        z, w = _complementary(size, rng)
        return Case(kind, LCP(M, w - M @ z), "solved", z=z, w=w, unique_z=False, unique_w=False,
                    seed=seed)
    if kind == "infeasible":
        # y >= 0 with M y = 0 and q'y < 0: no z >= 0 has Mz + q >= 0, since
        # y'(Mz + q) = q'y < 0.  Built in small integers, so that M y = 0
        # holds exactly in floating point (a rounded B B' with B'y = 0 is
        # merely nearly singular, and then solvable with a huge z), then
        # scaled by a power of two (exact too).
        y = rng.integers(1, 4, n).astype(float)
        y[-1] = 1.0
        B = rng.integers(-3, 4, (n, max(1, n - 1))).astype(float)
        B[-1] = -(y[:-1] @ B[:-1])
        q = rng.integers(-5, 6, n).astype(float)
        q[-1] -= (q @ y) + rng.integers(1, 4)
        scale = 2.0 ** rng.integers(-20, 21)
        return Case(kind, LCP(scale * (B @ B.T), scale * q), "infeasible", seed=seed)
    raise ValueError(f"unknown LCP kind {kind!r}; choose from {LCP_KINDS}")


def build_qp(kind: str, n: int, seed: int, *, cond: float = 1e4) -> Case:
    """One QP case, deterministic in its arguments (see the module docstring).
    Inequalities Gx <= h with m = n rows, and bounds on some variables."""
    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    m = n
    G = rng.standard_normal((m, n))
    if kind in ("convex", "degenerate"):
        P = random_spd(n, cond, rng)
        if kind == "degenerate":  # singular on a subspace, and weakly active constraints
            U = np.linalg.qr(rng.standard_normal((n, n)))[0][:, : max(1, n // 2)]
            P = P - U @ (U.T @ P @ U) @ U.T
            P = 0.5 * (P + P.T)
            ev = np.linalg.eigvalsh(P)
            # lifted to semidefinite with a margin of the projection's own
            # rounding (normwise, n eps |P|): lifted to exactly 0, a stored P
            # could read as indefinite in its Jacobi scaling (-6e-14: 6 draws
            # in 40 000 at n = 3-4), and solve() rightly refused it as
            # nonconvex where the case promised "solved"
            P = P + (max(-ev[0], 0.0) + 64 * n * np.finfo(float).eps * ev[-1]) * np.eye(n)
        x = rng.standard_normal(n)
        state = rng.choice(3, size=m, p=[0.4, 0.4, 0.2] if kind == "degenerate" else [0.5, 0.5, 0.0])
        zmult = np.where(state == 0, rng.uniform(0.1, 2.0, m), 0.0)
        slack = np.where(state == 1, rng.uniform(0.1, 2.0, m), 0.0)
        h = G @ x + slack
        q = -(P @ x) - G.T @ zmult
        return Case(kind, Problem(P, q, G, h), "solved", x=x,
                    objective=float(0.5 * x @ P @ x + q @ x), unique_z=kind == "convex", seed=seed)
    if kind == "infeasible":
        P = random_spd(n, cond, rng)
        a = rng.standard_normal(n)
        G = np.vstack([G[: m - 2], a, -a])  # a'x <= -1 and -a'x <= -1 contradict
        h = np.concatenate([np.abs(rng.standard_normal(m - 2)) + 1.0, [-1.0, -1.0]])
        return Case(kind, Problem(P, rng.standard_normal(n), G, h), "infeasible", seed=seed)
    if kind == "unbounded":
        # P PSD with P d = 0, q'd < 0 and G d <= -1, x = 0 feasible: the
        # objective falls for ever along t d.  Integers, so that P d = 0 holds
        # exactly in floating point (see the infeasible LCP above).
        d = rng.integers(-2, 3, n).astype(float)
        d[-1] = 1.0
        B = rng.integers(-3, 4, (n, n)).astype(float)
        B[-1] = -(d[:-1] @ B[:-1])
        Gi = rng.integers(-3, 4, (m, n)).astype(float)
        Gi[:, -1] = -(Gi[:, :-1] @ d[:-1]) - rng.integers(1, 4, m)
        h = rng.integers(1, 5, m).astype(float)
        q = rng.integers(-5, 6, n).astype(float)
        q[-1] -= (q @ d) + rng.integers(1, 4)
        return Case(kind, Problem(B @ B.T, q, Gi, h), "unbounded", seed=seed)
    if kind == "penalty":
        return _penalty_qp(n, rng, seed)
    raise ValueError(f"unknown QP kind {kind!r}; choose from {QP_KINDS}")


def _penalty_qp(n: int, rng, seed: int) -> Case:
    """The penalty QP of one integration step (Nikolsky et al. 2012) (formulations/mechanisms/penalty.py):
    min ½λ'(C + 2μA)λ + (C P_y + μb)'λ  s.t.  Aλ >= -b, λ >= 0, with A =
    J G⁻¹ J' singular (more contacts than degrees of freedom) and μ up to
    1e12 times the exactness threshold μ*.  For μ > μ* its minimiser is the
    LCP solution λ* (the penalty paper's exact-penalty result, reconstructed in
    ../shared/PAPERS.md), which is planted here; μ* is computed from the
    planted λ*, so the known answer holds by that theorem, not by a solver."""
    dof, nu = max(2, n // 2), n
    J = rng.standard_normal((nu, dof))
    Ginv = random_spd(dof, 10.0, rng)
    A = J @ Ginv @ J.T
    A = 0.5 * (A + A.T)
    C = 1e-3 * float(np.abs(A).max()) * random_spd(nu, 10.0, rng)
    P_y = rng.uniform(0.0, 1.0, nu)
    # λ*: at most dof positive (A_BB nonsingular), strictly complementary
    support = rng.choice(nu, size=max(1, dof // 2), replace=False)
    lam = np.zeros(nu)
    lam[support] = rng.uniform(0.5, 2.0, support.size)
    w = rng.uniform(0.5, 2.0, nu)
    w[support] = 0.0
    b = w - A @ lam
    free = np.setdiff1d(np.arange(nu), support)
    rhs = C @ (lam + P_y)
    nu_b = np.linalg.solve(A[np.ix_(support, support)], rhs[support])
    mu_star = max(float(np.max(-nu_b / lam[support])),
                  float(np.max(((A[np.ix_(free, support)] @ nu_b - rhs[free]) / w[free]),
                               initial=-np.inf)), 1e-12)
    mu = mu_star * 10.0 ** rng.uniform(1.0, 12.0)
    W = C + 2.0 * mu * A
    W = 0.5 * (W + W.T)
    c = C @ P_y + mu * b
    return Case("penalty", Problem(W, c, -A, b, lb=np.zeros(nu)), "solved", x=lam,
                objective=float(0.5 * lam @ W @ lam + c @ lam), unique_z=True, seed=seed)
