r"""Proof that a frictional contact problem has a solution: a velocity that
opens every contact strictly (Acary, Cadoux, Lemaréchal and Malick 2011),
found by an LP and checked from the data.

**The theorem.**  Write the problem in body velocities v (m/s, rad/s): a mass
matrix M, symmetric positive definite, the contacts' relative velocities
u = Hᵀ v + w (per contact (u_N, u_T), m/s) and the impulses r (N·s),

    M v = H r + f,   r_i ∈ K_i = {‖r_T‖ <= μ_i r_N},
    û_i = u_i + μ_i ‖u_T,i‖ e_N ∈ K_i* = {μ_i ‖û_T‖ <= û_N},   r_i · û_i = 0,

De Saxcé's form of Coulomb's law at every contact.  If some velocity v₀ has
Hᵀ v₀ + w in the interior of every dual cone — each contact separates,
u_N > μ ‖u_T‖ — a solution exists.  The argument, in short: for a slip
term s >= 0 (one per contact) the program

    P(s):  minimise ½ vᵀ M v − fᵀ v  subject to  Hᵀ v + w + s e_N ∈ K*

is strictly convex and strictly feasible (v₀ stays strictly feasible for
every s >= 0, adding s e_N only moves a point deeper into K*), so it has one
minimiser v(s), multipliers r ∈ K with M v = H r + f and complementarity
(Slater), and v(s) is continuous in s (the feasible sets move continuously
with s where Slater holds; Berge).  v₀ bounds the optimal value, so v(s)
lies in a bounded set for every s, and F(s) = (μ_i ‖u_T,i(s)‖)_i maps a box
[0, S]ᵐ into itself: by Brouwer it has a fixed point s* = F(s*), and
(v(s*), r) solves the problem above.

**Local form.**  A problem given by W and q (u = W r + q) with W = Hᵀ M⁻¹ H
is the same problem with w = q (a solution v = M⁻¹ H r), and the velocities
Hᵀ v + q that v can make are q + range(W) (range(Hᵀ M⁻¹ H) = range(Hᵀ) for M
definite): the condition is that W y + q lies strictly inside every dual cone
for some y, with W positive semidefinite.  The piles keep W's factors
(``FrictionProblem.delassus_factors``: Hᵀ and m⁻¹ > 0), where the condition
is read in body velocities — only where the factors' product is W to the
rounding of forming it, entry by entry (factors that are not W's prove
nothing about W); for another W, symmetric and small enough, W is shown
definite as M is below (a singular W, semidefinite or not, is undecided:
no floating-point test tells a zero eigenvalue from a slightly negative
one, and a slightly negative one can leave the problem without a solution).

**Definiteness.**  A Cholesky factorization that succeeds in floating point
does not show M definite: M = [[7, 1], [1, fl(1/7)]] has det = −5.6e−17 and
factors.  If the factorization of M − c I succeeds, G Gᵀ = M − c I + E with
|E| <= γ_{n+1} |G| |G|ᵀ, whose 2-norm is at most γ_{n+1}/(1 − γ_{n+1}) tr(M)
(Demmel), so c = (n + 2) ε tr(M) (ε the machine epsilon, twice the unit
roundoff: it covers that and the shift's own rounding) leaves λ_min(M) > 0;
M is first scaled by powers of two (exact, and definiteness is kept by the
congruence) to a diagonal near one.  A diagonal M needs no factorization:
its entries are its eigenvalues.

**The search.**  An LP on the inscribed regular octagon (3-D) or the
segment (2-D): u_N − μ ⟨u_T, d_k⟩ / cos(π/8) >= t at every contact for the
eight unit directions d_k at angles (2k + 1)π/8 in the contact's tangent
plane, t maximised, each velocity component bounded by a hundred times the
data's velocity scale over its column's size.  max_k ⟨u_T, d_k⟩ >=
cos(π/8) ‖u_T‖₂, so the LP is conservative: t > 0 is enough, t <= 0 decides
nothing (the round cone may still hold a point).  Not the inscribed square
(|u_T1| + |u_T2|, √2 ‖u_T‖ along a diagonal): a sphere in a corner of its
box, touching the floor and two walls (gap 0), opens all three contacts
only by moving away diagonally, which slips it at each by √2 times its
normal speed in the tangents' axes — margin 1 − μ√2 > 0 in the round cone
at μ = 0.5, and exactly 0 in the square, so the square's LP left every
pile with such a sphere undecided (the 2 118-contact sphere and compact
piles, the compact 540 seed 4 and 982 seeds 1 and 3: docs/dev-notes.md,
"The dense 3-D route by counts").

**The check.**  u = Hᵀ v + q computed in floating point is within
γ (|Hᵀ| |v| + |q|) of the exact product (γ = (k + 2) ε for rows of k
entries), so each contact's margin u_N − μ ‖u_T‖ is required to exceed
(1 + μ √(dim − 1)) times that bound: then the exact velocity is strictly
inside every dual cone of the data as stored.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..judge.scales import abs_matvec

__all__ = ["solution_exists", "EXISTENCE_MAX_W"]

#: largest local W (unknowns) whose eigenvalues are checked for the local
#: form without factors (a dense eigendecomposition: ~1 s at 2 000)
EXISTENCE_MAX_W = 2000


def solution_exists(problem, time_limit: float = 30.0):
    """(the sentence that says a solution exists, the velocity that shows it)
    where the theorem in this module's docstring applies and its hypothesis
    is checked from the data; None where it is not decided — no strictly
    opening velocity was found (the LP is conservative), M or W could not be
    shown definite (module docstring, "Definiteness"), or the LP ran out of
    ``time_limit`` seconds.  None never means that no solution exists."""
    data = _velocity_map(problem)
    if data is None:
        return None
    A, w, what = data                  # u = A x + w over the unknowns x
    dim, m = problem.dim, problem.n_contacts
    if m == 0 or not np.all(np.isfinite(w)):
        return None
    mu = np.broadcast_to(np.asarray(problem.mu, float), (m,))
    x = _opening_velocity(A, w, mu, dim, time_limit)
    if x is None:
        return None
    u = np.asarray(A @ x).ravel() + w
    k = np.diff(A.indptr).max(initial=0)
    bound = (k + 2) * np.finfo(float).eps * (abs_matvec(A, x) + np.abs(w))
    U, B = u.reshape(m, dim), bound.reshape(m, dim).max(axis=1)
    margin = U[:, 0] - mu * np.linalg.norm(U[:, 1:], axis=1)
    if not np.all(margin > (1.0 + mu * np.sqrt(dim - 1.0)) * B):
        return None
    scale = np.abs(U).max(axis=1)
    least = float(np.min(margin / np.where(scale > 0, scale, 1.0)))
    return (f"a solution exists ({what}; the velocity returned with this sentence opens every "
            f"contact strictly — u_N > μ‖u_T‖, by at least {least:.1e} of the contact's own velocity — "
            f"checked from the data with its rounding; Acary, Cadoux, Lemaréchal and Malick "
            f"2011)"), x


def _velocity_map(problem):
    """(A as CSR, w, the words for M's or W's definiteness) with the velocities
    the problem can make being A x + w; None where that cannot be shown."""
    factors = getattr(problem, "delassus_factors", None)
    if problem.is_reduced and factors is not None:
        HT, minv = factors
        HT, minv = sp.csr_matrix(HT), np.asarray(minv, float)
        if (minv.size and np.all(np.isfinite(minv)) and np.all(minv > 0)
                and np.all(np.isfinite(HT.data)) and _factors_form(problem.W, HT, minv)):
            return HT, np.asarray(problem.q, float), \
                "W = Hᵀ diag(m⁻¹) H (to its product's rounding) from the bodies' positive masses"
        # factors that are not this W's: W itself is judged below
    g = problem.global_data
    if g is not None and g.get("M") is not None:
        M = sp.csr_matrix(g["M"])
        if not _definite(M):
            return None
        return sp.csr_matrix(sp.csc_matrix(g["H"]).T), np.asarray(g["w"], float), \
            "M shown positive definite (a diagonal by its entries, else the Cholesky " \
            "factorization of M less its rounding bound)"
    if problem.is_reduced and problem.W.shape[0] <= EXISTENCE_MAX_W:
        W = sp.csr_matrix(problem.W)
        if not np.all(np.isfinite(W.data)) or not _definite(W):
            return None
        return W, np.asarray(problem.q, float), \
            "W positive definite (the Cholesky factorization of W less its rounding bound)"
    return None


def _factors_form(W, HT, minv) -> bool:
    """Whether Hᵀ diag(m⁻¹) H is W entry by entry to the rounding of
    forming it (rows of k entries: γ_k |Hᵀ| diag(m⁻¹) |H| each way, so twice
    (k + 2) ε of it), W's pattern included."""
    if HT.shape != (W.shape[0], minv.size):
        return False
    D = sp.diags(minv)
    product = (HT @ D @ HT.T).tocsr()
    size = (abs(HT) @ D @ abs(HT).T).tocsr()
    k = int(np.diff(HT.indptr).max(initial=0))
    gap = abs(sp.csr_matrix(W) - product)
    if gap.nnz == 0:
        return True
    if not np.all(np.isfinite(gap.data)):
        return False
    allowed = 2.0 * (k + 2) * np.finfo(float).eps * size
    return bool((gap > allowed).nnz == 0)


def _definite(M: sp.csr_matrix) -> bool:
    """M symmetric and shown positive definite (module docstring,
    "Definiteness": a diagonal by its entries, else by the Cholesky
    factorization of M − (n + 2) ε tr(M) I); dense up to EXISTENCE_MAX_W,
    undecided above."""
    n = M.shape[0]
    if n == 0:
        return True
    if not np.all(np.isfinite(M.data)) or abs(M - M.T).max() > 0:
        return False
    d = M.diagonal()
    off = M - sp.diags(d)
    if off.nnz == 0 or not np.any(off.data):
        return bool(np.all(d > 0))
    if n > EXISTENCE_MAX_W or not np.all(d > 0):
        return False
    # scaled by powers of two (exact) to a diagonal near one: the same
    # definiteness, and a shift by the trace that a wide spread of masses
    # and inertias does not make larger than the smallest eigenvalue
    two = np.exp2(-np.round(np.log2(d) / 2.0))
    A = two[:, None] * M.toarray() * two[None, :]
    shift = (n + 2) * np.finfo(float).eps * float(np.trace(A))
    try:
        np.linalg.cholesky(A - shift * np.eye(n))
    except np.linalg.LinAlgError:
        return False
    return True


def _opening_velocity(A, w, mu, dim, time_limit):
    """The LP of the module docstring: x maximising the smallest contact's
    u_N − μ max_k ⟨u_T, d_k⟩ / cos(π/8) (each contact's rows for every
    direction d_k; in 2-D u_N − μ|u_T|); x, or None where the optimum is not
    positive or not reached."""
    m = mu.size
    N = np.arange(m) * dim
    if dim == 2:
        patterns = [(1.0,), (-1.0,)]
    else:
        angles = (2 * np.arange(8) + 1) * np.pi / 8
        patterns = [(np.cos(a) / np.cos(np.pi / 8), np.sin(a) / np.cos(np.pi / 8))
                    for a in angles]
    # each contact's normal row and its tangential rows scaled by μ, sliced
    # once for every direction
    normal = A[N]
    tangents = [(sp.diags(mu) @ A[N + 1 + j], mu * w[N + 1 + j]) for j in range(dim - 1)]
    rows, rhs = [], []
    for signs in patterns:
        G, b = -normal, w[N].copy()
        for sj, (At, wt) in zip(signs, tangents):
            G = G + sj * At
            b = b - sj * wt
        rows.append(G)
        rhs.append(b)
    G = sp.hstack([sp.vstack(rows), np.ones((len(patterns) * m, 1))]).tocsr()
    scale = float(np.abs(w).max(initial=0.0)) or 1.0
    colmax = np.asarray(abs(A).max(axis=0).toarray()).ravel()
    reach = 100.0 * scale / np.where(colmax > 0, colmax, np.inf)
    bounds = [(-r, r) for r in reach] + [(None, scale)]
    c = np.zeros(A.shape[1] + 1)
    c[-1] = -1.0
    from scipy.optimize import linprog

    # HiGHS's interior point: its simplex took over 30 s on the 2 118-contact
    # pile's LP where the interior point takes 2–3 s (0.2 s at 540 contacts)
    with np.errstate(all="ignore"):
        try:
            res = linprog(c, A_ub=G, b_ub=np.concatenate(rhs), bounds=bounds, method="highs-ipm",
                          options={"time_limit": float(time_limit)})
        except (ValueError, MemoryError):
            return None
    if res.status != 0 or res.x is None or not res.x[-1] > 0:
        return None
    return res.x[:-1]
