"""Hard cases in real-valued (rounded) data whose answer is nevertheless exact:
the status or the solution of the problem *as stored* is decided in rational
arithmetic (:mod:`qpcontact.cases.rational_references`), never by a solver.

Ill-posed data: an LCP built as B Bᵀ with Bᵀd = 0, d >= 0 and q'd < 0 has no
solution in exact arithmetic, but the stored, rounded M is usually positive
definite or indefinite, and then the stored problem may have a solution with
|z| ~ 1e16 — or none.  Methods that answer "ok" there have no correct digit.
These builders record what the stored data really are.

Families (``build_rounded(family, n, seed)``):

- ``illposed_psd``: M = fl(B Bᵀ), B real with a left null vector d > 0 (to
  rounding), q'd < 0.  Reference: an exact Farkas vector (y = d) when it
  holds; else, when M is exactly positive definite (every leading minor > 0),
  the unique solution by exact principal pivoting; else an exactly verified
  complementary basis (a solution, not unique); else status "unknown".
- ``ill_conditioned_spd``: SPD M of condition 1e10..1e13, planted z, w;
  q = fl(w - Mz) is not the planted answer's q, so the reference is the exact
  solution of the stored (M, q), found from the planted basis by exact pivoting.
- ``infeasible_rounded``: M = fl(B Bᵀ) with its last row and column rounded
  *downward* so that M y <= 0 holds exactly for a y > 0 of powers of two, and
  q'y < 0: infeasible exactly, M only to rounding PSD.
- ``qp_unbounded_rounded``: P copies the entries of a real SPD K (each
  variable a signed power-of-two multiple of one of K's variables), so two
  variables of one group give a ray d with P d = 0 exactly; rows of G negated
  where needed so that G d <= 0 exactly, q'd < 0 exactly, x = 0 feasible.
- ``qp_infeasible_rounded``: real rows g_a, g_b, g_c = fl(-(g_a + g_b)) with
  h_a + h_b + h_c < 0 by a clear margin, and a box on x; with y = 1 on those
  rows the exact Farkas inequality h'y < min over the box of (Gᵀy)'x holds
  (Gᵀy is only rounding-small, and the box makes that enough).

The exact families are capped at n = 40 (:data:`EXACT_MAX_N`): rational
elimination grows like n³ on integers of n·53 bits.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from qpsolvers import Problem

from ..core.options import check_seed
from ..core.problems import LCP
from .rational_references import ExactLCP, dot_exact, float_bpp, lcp_farkas_holds, round_down
from .families import random_spd
from .planted import Case

__all__ = ["ROUNDED_FAMILIES", "EXACT_MAX_N", "build_rounded", "qp_ray_holds",
           "qp_box_farkas_holds"]

ROUNDED_FAMILIES = ("illposed_psd", "ill_conditioned_spd", "infeasible_rounded",
                    "qp_infeasible_rounded", "qp_unbounded_rounded", "conditioned_spd",
                    "near_singular_pd", "farkas_far_contacts", "farkas_one_row")

#: the families with an exact LCP reference are built at min(n, EXACT_MAX_N)
EXACT_MAX_N = 40

_EXACT_BUDGET_S = 20.0


def _sym(M):
    """Symmetric bit for bit (a BLAS product B Bᵀ need not be)."""
    return np.triu(M) + np.triu(M, 1).T


def _complementary(n, rng):
    active = rng.random(n) < 0.5
    z = np.where(active, rng.uniform(0.1, 2.0, n), 0.0)
    w = np.where(active, 0.0, rng.uniform(0.1, 2.0, n))
    return z, w


def _floats(v):
    return np.array([float(x) for x in v])


def _exact_solution(M, q, start, kind, seed, *, note):
    """Case for a PD M: the exact solution from ``start`` by Murty's method."""
    ex = ExactLCP(M, q)
    if not ex.positive_definite():
        return None
    n = q.size
    sol = ex.murty(start, max_steps=20 * n + 50, budget_s=_EXACT_BUDGET_S)
    lcp = LCP(M, q)
    if sol is None:
        return Case(kind, lcp, "unknown", seed=seed, reference="PD, exact pivoting out of budget")
    z, w = _floats(sol[0]), _floats(sol[1])
    return Case(kind, lcp, "solved", z=z, w=w, unique_z=True, seed=seed,
                reference=f"{note}: exactly positive definite, unique solution by exact pivoting")


def illposed_psd(n: int, seed: int) -> Case:
    seed = check_seed(seed)
    rng = np.random.default_rng([seed, n, 310])
    d = rng.uniform(0.25, 2.0, n)
    rank = n - 1 if rng.random() < 0.75 else max(1, n - 1 - int(rng.integers(1, max(2, n // 4))))
    stiffness = 10.0 ** rng.uniform(-2, 6)
    B = rng.standard_normal((n, rank)) * np.sqrt(stiffness)
    B = B - np.outer(d, d @ B) / (d @ d)            # dᵀB = 0 up to rounding: a mechanism along d
    M = _sym(B @ B.T)
    q0 = rng.standard_normal(n) * stiffness
    c = rng.uniform(0.1, 1.0) * np.linalg.norm(q0) * np.linalg.norm(d)
    q = q0 - (q0 @ d + c) * d / (d @ d)             # q'd < 0: the load pushes along the mechanism
    kind = "illposed_psd"
    if lcp_farkas_holds(M, q, d):
        return Case(kind, LCP(M, q), "infeasible", seed=seed, witness=d,
                    reference="exact Farkas vector y = d (M d <= 0, q'd < 0 in rationals)")
    if ExactLCP(M, q).farkas_by_solve() is not None:
        return Case(kind, LCP(M, q), "infeasible", seed=seed,
                    reference="exact Farkas vector y = -M⁻¹1 >= 0 with q'y < 0 (M indefinite)")
    start = float_bpp(M, q)
    case = _exact_solution(M, q, start, kind, seed, note="stored M")
    if case is not None:
        return case
    sol = ExactLCP(M, q).verify_basis(start)
    if sol is not None:
        z, w = _floats(sol[0]), _floats(sol[1])
        return Case(kind, LCP(M, q), "solved", z=z, w=w, unique_z=False, unique_w=False,
                    seed=seed, reference="not PD; a complementary basis verified exactly")
    return Case(kind, LCP(M, q), "unknown", seed=seed,
                reference="not PD, no exact Farkas vector (y = d) and no verified basis")


def ill_conditioned_spd(n: int, seed: int) -> Case:
    seed = check_seed(seed)
    rng = np.random.default_rng([seed, n, 311])
    cond = 10.0 ** rng.uniform(10.0, 13.0)
    M = random_spd(n, cond, rng)
    z, w = _complementary(n, rng)
    q = w - M @ z                                    # rounded: the planted z is not exact for it
    case = _exact_solution(M, q, np.flatnonzero(z > 0), "ill_conditioned_spd", seed,
                           note=f"cond {cond:.1e}")
    if case is None:
        return Case("ill_conditioned_spd", LCP(M, q), "unknown", seed=seed,
                    reference="stored M not exactly positive definite")
    return case


def conditioned_spd(n: int, seed: int) -> Case:
    """SPD M of condition 1e8..1e16 (beyond 1/eps the stored M may not be
    positive definite: then "unknown"), planted z, w; the reference is the
    exact solution of the stored (M, q)."""
    seed = check_seed(seed)
    rng = np.random.default_rng([seed, n, 315])
    cond = 10.0 ** rng.uniform(8.0, 16.0)
    M = _sym(random_spd(n, cond, rng))
    z, w = _complementary(n, rng)
    q = w - M @ z
    case = _exact_solution(M, q, np.flatnonzero(z > 0), "conditioned_spd", seed,
                           note=f"cond {cond:.1e}")
    return case or Case("conditioned_spd", LCP(M, q), "unknown", seed=seed,
                        reference="stored M not exactly positive definite")


def near_singular_pd(n: int, seed: int) -> Case:
    """M = fl(B Bᵀ) + δ I with B of rank n - k (k = 1..3) and δ = 1e-13..1e-9
    of max|M|: positive definite, near-singular along k directions; planted
    z, w.  The reference is the exact solution of the stored (M, q)."""
    seed = check_seed(seed)
    rng = np.random.default_rng([seed, n, 316])
    k = int(rng.integers(1, min(4, n)))
    B = rng.standard_normal((n, n - k))
    M = B @ B.T
    M = _sym(M + 10.0 ** rng.uniform(-13, -9) * float(np.abs(M).max()) * np.eye(n))
    z, w = _complementary(n, rng)
    q = w - M @ z
    case = _exact_solution(M, q, np.flatnonzero(z > 0), "near_singular_pd", seed,
                           note="B Bᵀ + δI")
    return case or Case("near_singular_pd", LCP(M, q), "unknown", seed=seed,
                        reference="stored M not exactly positive definite")


def farkas_far_contacts(n: int, seed: int) -> Case:
    """A floating mechanism beside far contacts: M = B Bᵀ with 1ᵀB = 0
    exactly (dyadic B, its last row minus the sum of the others), so Mᵀ1 = 0
    and M's null space has dimension 12..14; q of integers up to 2e13..2.5e14
    in size (far contacts), its last entry set so that qᵀ1 = -1 exactly —
    either random (clearly infeasible along other null directions too) or
    balanced (q = -M z0 - e_n: a solution of data within 1 of q, every
    contact closed, so that backends certify "solutions" of nearby data).
    y = 1 is an exact Farkas vector, invisible to an LP beside |q| ~ 1e13."""
    seed = check_seed(seed)
    rng = np.random.default_rng([seed, n, 317])
    n = max(n, 16)
    r = n - int(rng.integers(12, 15))
    balanced = rng.random() < 0.5
    size = 10.0 ** rng.uniform(13.3, 14.4)
    if balanced:
        # every contact loaded and closed: q = -M z0 - e_n with integer B and
        # z0 (exact), a solution of q + e_n, and qᵀ1 = -1 hides in rounding
        B = np.round(rng.standard_normal((n, r)) * 8.0)
        B[-1] = -B[:-1].sum(axis=0)
        M = _sym(B @ B.T)
        z0 = np.round(np.abs(rng.standard_normal(n)) * size / (4.0 * float(np.abs(M).max())))
        z0[rng.random(n) < 0.2] = 0.0
        q = -(M @ z0)
        q[-1] -= 1.0
    else:
        B = np.round(rng.standard_normal((n, r)) * 2.0 ** 10) / 2.0 ** 10
        B[-1] = -B[:-1].sum(axis=0)
        M = _sym(B @ B.T)
        q = np.round(rng.standard_normal(n) * size / 4)
        far = rng.random(n) < 0.3
        q[far] = np.abs(q[far])
        q[-1] = -1.0 - float(sum(Fraction(float(v)) for v in q[:-1]))
    y = np.ones(n)
    if not lcp_farkas_holds(M, q, y):
        raise AssertionError(f"farkas_far_contacts n={n} seed={seed}: the Farkas vector fails")
    return Case("farkas_far_contacts", LCP(M, q), "infeasible", seed=seed, witness=y,
                reference="exact Farkas vector y = 1 (M'1 = 0, q'1 = -1 in rationals)")


def farkas_one_row(n: int, seed: int) -> Case:
    """A random M and q with one row i whose entries are all <= -0.1 and
    q_i <= -0.1: w_i <= q_i < 0 for every z >= 0, so y = e_i is an exact
    Farkas vector with a margin; the other rows are those of a P-matrix
    problem (a diagonally dominant M), so nothing else is wrong."""
    seed = check_seed(seed)
    rng = np.random.default_rng([seed, n, 318])
    A = rng.standard_normal((n, n))
    M = A + np.diag(np.abs(A).sum(axis=1) + rng.uniform(0.5, 2.0, n))
    q = rng.standard_normal(n)
    i = int(rng.integers(n))
    M[i] = -rng.uniform(0.1, 3.0, n)
    q[i] = -rng.uniform(0.1, 3.0)
    y = np.zeros(n)
    y[i] = 1.0
    if not lcp_farkas_holds(M, q, y):
        raise AssertionError(f"farkas_one_row n={n} seed={seed}: the Farkas vector fails")
    return Case("farkas_one_row", LCP(M, q), "infeasible", seed=seed, witness=y,
                reference=f"exact Farkas vector y = e_{i} (row {i} of M <= -0.1, q_{i} <= -0.1)")


def infeasible_rounded(n: int, seed: int) -> Case:
    seed = check_seed(seed)
    rng = np.random.default_rng([seed, n, 312])
    y = 2.0 ** rng.integers(-2, 3, n).astype(float)
    y[-1] = 1.0
    B = rng.standard_normal((n, max(1, n - 1))) * 10.0 ** rng.uniform(-2, 4)
    B = B - np.outer(y, y @ B) / (y @ y)
    M = _sym(B @ B.T)
    # the last row and column rounded downward: (M y)_i <= 0 exactly, where
    # fl(B Bᵀ) y is only rounding-small, of either sign
    for i in range(n - 1):
        s = dot_exact(M[i, :-1], y[:-1])
        M[i, -1] = M[-1, i] = round_down(-s)
    M[-1, -1] = round_down(-dot_exact(M[-1, :-1], y[:-1]))
    q0 = rng.standard_normal(n) * float(np.abs(M).max())
    c = rng.uniform(0.1, 1.0) * np.linalg.norm(q0) * np.linalg.norm(y)
    q = q0 - (q0 @ y + c) * y / (y @ y)
    if not lcp_farkas_holds(M, q, y):   # never seen; an exact check, so say it if it happens
        raise AssertionError(f"infeasible_rounded n={n} seed={seed}: Farkas vector fails")
    return Case("infeasible_rounded", LCP(M, q), "infeasible", seed=seed, witness=y,
                reference="exact Farkas vector y (M y <= 0, q'y < 0 in rationals)")


def qp_ray_holds(P, q, G, h, d) -> bool:
    """P d = 0, G d <= 0, q'd < 0 and h >= 0 (x = 0 feasible), exactly."""
    P, G = np.asarray(P, float), np.asarray(G, float)
    return (all(dot_exact(row, d) == 0 for row in P) and all(dot_exact(row, d) <= 0 for row in G)
            and dot_exact(q, d) < 0 and bool(np.all(h >= 0)))


def qp_box_farkas_holds(G, h, lb, ub, y) -> bool:
    """y >= 0 with h'y < min over lb <= x <= ub of (Gᵀy)'x, exactly: then
    y'(Gx - h) > 0 for every x in the box, so some row of Gx <= h fails."""
    G = np.asarray(G, float)
    if np.any(np.asarray(y) < 0):
        return False
    c = [dot_exact(G[:, j], y) for j in range(G.shape[1])]
    low = sum((min(ci * Fraction(float(lo)), ci * Fraction(float(hi)))
               for ci, lo, hi in zip(c, lb, ub)), Fraction(0))
    return dot_exact(h, y) < low


def qp_unbounded_rounded(n: int, seed: int) -> Case:
    seed = check_seed(seed)
    rng = np.random.default_rng([seed, n, 313])
    n = max(n, 3)
    r = max(2, n - int(rng.integers(1, max(2, n // 3) + 1)))
    group = np.concatenate([np.arange(r), rng.integers(0, r, n - r)])
    rng.shuffle(group)
    sign = rng.choice([-1.0, 1.0], n)
    a = 2.0 ** rng.integers(-3, 4, n).astype(float)
    K = random_spd(r, 10.0 ** rng.uniform(0, 6), rng) * 10.0 ** rng.uniform(-2, 3)
    t = sign * a
    P = t[:, None] * K[np.ix_(group, group)] * t[None, :]   # powers of two and signs: exact copies
    g = next(k for k in range(r) if np.count_nonzero(group == k) >= 2)
    i, j = np.flatnonzero(group == g)[:2]
    d = np.zeros(n)
    d[i], d[j] = 1.0 / t[i], -1.0 / t[j]
    m = n
    G = rng.standard_normal((m, n))
    for row in range(m):
        if dot_exact(G[row], d) > 0:
            G[row] = -G[row]
    h = np.abs(rng.standard_normal(m)) + 0.1
    qv = rng.standard_normal(n)
    if dot_exact(qv, d) > 0:
        qv = -qv
    if dot_exact(qv, d) == 0:
        qv[i] += 1.0 / t[i]
    if not qp_ray_holds(P, qv, G, h, d):
        raise AssertionError(f"qp_unbounded_rounded n={n} seed={seed}: the ray fails")
    return Case("qp_unbounded_rounded", Problem(P, qv, G, h), "unbounded", seed=seed, witness=d,
                reference="exact ray d: P d = 0, G d <= 0, q'd < 0 in rationals")


def qp_infeasible_rounded(n: int, seed: int) -> Case:
    seed = check_seed(seed)
    rng = np.random.default_rng([seed, n, 314])
    n = max(n, 3)
    m = n
    P = random_spd(n, 10.0 ** rng.uniform(0, 6), rng)
    G = rng.standard_normal((m, n)) * 10.0 ** rng.uniform(-3, 3, (m, 1))
    ub = rng.uniform(1.0, 10.0, n)
    lb = -rng.uniform(1.0, 10.0, n)
    x0 = rng.uniform(lb, ub)
    h = G @ x0 + np.abs(rng.standard_normal(m))
    a, b, c = rng.choice(m, 3, replace=False)
    G[c] = -(G[a] + G[b])
    h[a], h[b] = np.abs(rng.standard_normal(2)) + 0.5
    gap = rng.uniform(0.1, 1.0) * (h[a] + h[b])
    h[c] = -(h[a] + h[b]) - gap
    y = np.zeros(m)
    y[[a, b, c]] = 1.0
    if not qp_box_farkas_holds(G, h, lb, ub, y):
        raise AssertionError(f"qp_infeasible_rounded n={n} seed={seed}: Farkas fails")
    return Case("qp_infeasible_rounded", Problem(P, rng.standard_normal(n), G, h, lb=lb, ub=ub),
                "infeasible", seed=seed, witness=y,
                reference="exact Farkas inequality over the box with y = 1 on three rows")


_BUILDERS = {"illposed_psd": illposed_psd, "ill_conditioned_spd": ill_conditioned_spd,
             "infeasible_rounded": infeasible_rounded, "qp_unbounded_rounded": qp_unbounded_rounded,
             "qp_infeasible_rounded": qp_infeasible_rounded, "conditioned_spd": conditioned_spd,
             "near_singular_pd": near_singular_pd, "farkas_far_contacts": farkas_far_contacts,
             "farkas_one_row": farkas_one_row}


def build_rounded(family: str, n: int, seed: int) -> Case:
    """One case of a rounded family, deterministic in (family, n, seed)."""
    seed = check_seed(seed)
    if family not in _BUILDERS:
        raise ValueError(f"unknown rounded family {family!r}; choose from {ROUNDED_FAMILIES}")
    if family in ("illposed_psd", "ill_conditioned_spd", "infeasible_rounded", "conditioned_spd",
                  "near_singular_pd"):
        n = min(n, EXACT_MAX_N)
    return _BUILDERS[family](max(n, 2), seed)
