"""Is an answer with no guaranteed digit beside data that may have no solution?

A certified LCP answer z whose active block M_FF is singular to working
precision solves data within rounding of yours; whether *yours* have a
solution is then the question.  If they have none, a Farkas vector y >= 0
(Mᵀy <= 0, qᵀy < 0) exists, and since z nearly solves them,
yᵀw = (Mᵀy)ᵀz + qᵀy is rounding-small while every term is >= 0 to rounding:
y lives on the active rows (w_F ≈ 0) and in the left null space of M_FF.
So the search is small: the left null vectors U₀ of M_FF (any dimension),
and the nonnegative combination y_F = U₀c, Σy = 1, that minimises qᵀy
within Mᵀy <= 0 (an LP in the few coefficients c).  When it holds to
rounding — each column of Mᵀy against its own terms |M|ᵀy, qᵀy against
|q|ᵀy — the data are within rounding of a problem with no solution, and the
answer is in doubt (:func:`qpcontact.judge.doubt.doubt`); y is the vector
the proofs check exactly.  When none holds, the block's singularity says
only that the solution is not isolated (a Stewart–Trinkle friction LCP
answered exactly by Lemke): other solutions may exist, none is missing.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["near_farkas", "near_friction_ray", "NEAR_MAX_BLOCK"]

#: active blocks up to this size are searched (a dense SVD of the block)
NEAR_MAX_BLOCK = 400


def near_farkas(M, q, active: np.ndarray, rtol: float) -> np.ndarray | None:
    """y >= 0 (n components, zero off the active rows) with Mᵀy <= rtol |M|ᵀy
    and qᵀy <= rtol |q|ᵀy, from the left null space of M_FF (F = ``active``),
    or None (nothing near, or the block above NEAR_MAX_BLOCK)."""
    from scipy.optimize import linprog

    q = np.asarray(q, float).ravel()
    n = q.size
    F = np.flatnonzero(active)
    k = F.size
    if k == 0 or k > NEAR_MAX_BLOCK:
        return None
    Mc = sp.csr_matrix(M)
    B = Mc[F][:, F].toarray()
    if not np.all(np.isfinite(B)):
        return None
    try:
        U, s, _ = np.linalg.svd(B)
    except np.linalg.LinAlgError:
        return None
    top = float(s[0]) if s.size else 0.0
    U0 = U[:, s <= max(rtol, 100.0 * k * np.finfo(float).eps) * top] if top > 0 else np.eye(k)
    if U0.shape[1] == 0:
        return None
    cols = Mc[F].toarray()                       # rows F of M: (Mᵀy) = colsᵀ y_F
    absM = np.abs(cols)
    # unit scales: the LP's tolerances mean the same on every column
    cscale = absM.max(axis=0)
    cscale = np.where(cscale > 0, 1.0 / np.where(cscale > 0, cscale, 1.0), 0.0)
    qs = q[F] / (float(np.max(np.abs(q[F]))) or 1.0)
    A_ub = np.vstack([-U0, (cols * cscale).T @ U0])
    with np.errstate(all="ignore"):
        try:
            res = linprog(qs @ U0, A_ub=A_ub, b_ub=np.zeros(A_ub.shape[0]),
                          A_eq=U0.sum(axis=0)[None, :], b_eq=[1.0],
                          bounds=[(None, None)] * U0.shape[1], method="highs")
        except ValueError:
            return None
    tries = [U0 @ res.x] if res.status == 0 else []
    tries += [U0[:, j] for j in range(U0.shape[1])] + [-U0[:, j] for j in range(U0.shape[1])]
    for yF in tries:
        yF = np.maximum(yF, 0.0)
        big = float(yF.max(initial=0.0))
        if not big > 0:
            continue
        yF = yF / big
        My, scale = cols.T @ yF, absM.T @ yF
        if np.all(My <= rtol * scale) and q[F] @ yF <= rtol * (np.abs(q[F]) @ yF):
            y = np.zeros(n)
            y[F] = yF
            return y
    return None


def near_friction_ray(problem, r, rtol: float) -> np.ndarray | None:
    """For a global frictional problem with a singular M (a mechanism): the
    motion d (Md = 0 as computed, every contact admitting it — Hᵀd in its dual
    cone, normalised Σ u_N = 1) on which the loads do the most work fᵀd, when
    that work is at least -rtol |f|ᵀ|d|: the loads are then within rounding
    of the friction limit (a block pushed at μW(1 + 1e-14)), and whether an
    equilibrium exists is decided by d's exact work.  None otherwise.  The
    cones are replaced by the pyramids inscribed in them, aligned with each
    contact's answer r_T (a slide at the limit opposes r_T exactly)."""
    from scipy.optimize import linprog

    g = getattr(problem, "global_data", None)
    if g is None or getattr(problem, "W", None) is not None:
        return None
    M = g["M"]
    n = M.shape[0]
    if n == 0 or n > NEAR_MAX_BLOCK:
        return None
    A = M.toarray() if sp.issparse(M) else np.asarray(M, float)
    try:
        U, s, _ = np.linalg.svd(A)
    except np.linalg.LinAlgError:
        return None
    top = float(s[0]) if s.size else 0.0
    N = U[:, s <= 100.0 * n * np.finfo(float).eps * top] if top > 0 else np.eye(n)
    k = N.shape[1]
    if k == 0:
        return None
    dim, mu = problem.dim, np.asarray(problem.mu, float)
    H = g["H"].toarray() if sp.issparse(g["H"]) else np.asarray(g["H"], float)
    Ut = (H.T @ N).reshape(-1, dim, k)          # u_i = Ut[i] c
    R = np.asarray(r, float).reshape(-1, dim)
    rows = []
    for i in range(Ut.shape[0]):
        uN, uT = Ut[i, 0], Ut[i, 1:]
        rT = R[i, 1:]
        size = float(np.linalg.norm(rT))
        a = -rT / size if size > 0 else np.eye(dim - 1)[0]
        if dim == 2:
            dirs = [a, -a]
        else:
            b = np.array([-a[1], a[0]])
            dirs = [sa * a + sb * b for sa in (1, -1) for sb in (1, -1)]
        for e in dirs:
            rows.append(mu[i] * (e @ uT) - uN)   # μ (e·u_T) <= u_N
    A_ub = np.array(rows)
    f = np.asarray(g["f"], float)
    with np.errstate(all="ignore"):
        try:
            res = linprog(-(f @ N), A_ub=A_ub, b_ub=np.zeros(len(rows)),
                          A_eq=Ut[:, 0, :].sum(axis=0)[None, :], b_eq=[1.0],
                          bounds=[(None, None)] * k, method="highs")
        except ValueError:
            return None
    if res.status != 0:
        return None
    d = N @ res.x
    big = float(np.abs(d).max(initial=0.0))
    if not big > 0:
        return None
    d = d / big
    if f @ d >= -rtol * (np.abs(f) @ np.abs(d)):
        return d
    return None
