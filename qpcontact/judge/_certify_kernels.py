"""Compiled loops of the certificate (numba).

The column influences c_j = max_i |M_ij| / σ_i of a sparse M are one pass over
its nonzeros; as NumPy calls (divide, then maximum.reduceat) they cost 4 ms on
a 3e5-nonzero chain, a tenth of a bpp solve; as one loop, a few hundred µs.
"""

from __future__ import annotations

import numpy as np
from ..core.compiled import njit


@njit
def csc_column_max_ratio(indptr: np.ndarray, indices: np.ndarray, data: np.ndarray,
                         sigma: np.ndarray) -> np.ndarray:
    """max_i |data_ij| / sigma_i per column of a CSC matrix (0/0 = 0, x/0 = inf)."""
    n = indptr.shape[0] - 1
    out = np.zeros(n)
    for j in range(n):
        best = 0.0
        for k in range(indptr[j], indptr[j + 1]):
            a = abs(data[k])
            if a == 0.0:
                continue
            s = sigma[indices[k]]
            r = a / s if s > 0.0 else np.inf
            if r > best:
                best = r
        out[j] = best
    return out



@njit
def jacobian_2d_csr(diag: np.ndarray, bptr: np.ndarray, bcols: np.ndarray, bdata: np.ndarray,
                    jp: np.ndarray, rho: np.ndarray, t01: np.ndarray):
    """(indptr, indices, data) of J = I − blockdiag(jp) + blockdiag(B) W in CSR
    for 2-D contacts, W by its 2 × 2 blocks (FrictionProblem.W_blocks: the
    diagonal ones, the others by block row), B_i = ρ_i jp_i T_i with T_i =
    [[1, t01_i], [0, 1]]: J's entries in the order of summation of the array
    products they replace, exact zeros left out as those leave them — the
    same J bit for bit once in CSC, at a fraction of their cost (scipy's
    per-operation overhead was most of it)."""
    b = np.empty((jp.shape[0], 2, 2))
    for i in range(jp.shape[0]):
        for a in range(2):
            b[i, a, 0] = rho[i] * (jp[i, a, 0] * 1.0 + jp[i, a, 1] * 0.0)
            b[i, a, 1] = rho[i] * (jp[i, a, 0] * t01[i] + jp[i, a, 1] * 1.0)
    nc = jp.shape[0]
    nb = bptr[nc] + nc
    out_ptr = np.zeros(2 * nc + 1, np.int64)
    out_idx = np.empty(4 * nb, np.int64)
    out_val = np.empty(4 * nb)
    nnz = 0
    for i in range(nc):
        for a in range(2):
            for e in range(2):        # the diagonal block: (I − J_P) + B W
                v = b[i, a, 0] * diag[i, 0, e] + b[i, a, 1] * diag[i, 1, e]
                v = ((1.0 if a == e else 0.0) - jp[i, a, e]) + v
                if v != 0.0:          # exact zeros left out, as the sparse products do
                    out_idx[nnz] = 2 * i + e
                    out_val[nnz] = v
                    nnz += 1
            for s in range(bptr[i], bptr[i + 1]):
                cb = bcols[s]
                for e in range(2):
                    v = b[i, a, 0] * bdata[s, 0, e] + b[i, a, 1] * bdata[s, 1, e]
                    if v != 0.0:
                        out_idx[nnz] = 2 * cb + e
                        out_val[nnz] = v
                        nnz += 1
            out_ptr[2 * i + a + 1] = nnz
    return out_ptr, out_idx[:nnz], out_val[:nnz]


@njit
def _cone_residual_2d(rn, rt, xn, xt, mu):
    """(r − proj_K(x)) for one 2-D contact, proj_K as friction_problem.project_cone."""
    t = abs(xt)
    if t <= mu * xn:
        pn, pt = xn, xt
    elif mu * t <= -xn:
        pn, pt = 0.0, 0.0
    else:
        alpha = (mu * t + xn) / (1.0 + mu * mu)
        pn = alpha
        pt = xt * (mu * alpha / t) if t > 0.0 else 0.0
    return rn - pn, rt - pt


@njit
def certified_error_2d(diag, bptr, bcols, bdata, q, mu, r):
    """max(natural-map error, componentwise error) of finite impulses r for a
    2-D problem given by W's 2 × 2 blocks (FrictionProblem.W_blocks) and q:
    friction_certificate's formulas in one pass over W's blocks (u = W r + q
    and |W||r| together), without its dozen array operations — 0.33 against
    0.04 ms at 1 176 contacts, the same value to rounding (a few units in the
    last place: the sums are taken in another order)."""
    nc = mu.shape[0]
    if nc == 0:
        return 0.0
    wmax = 0.0
    for i in range(nc):
        wmax = max(wmax, abs(diag[i, 0, 0]))
    fallback = 1.0 / wmax if wmax > 0.0 else 1.0
    res = np.empty(nc)
    size = np.empty(nc)
    nat2 = 0.0
    q2 = 0.0
    for i in range(nc):
        u0 = q[2 * i] + diag[i, 0, 0] * r[2 * i] + diag[i, 0, 1] * r[2 * i + 1]
        u1 = q[2 * i + 1] + diag[i, 1, 0] * r[2 * i] + diag[i, 1, 1] * r[2 * i + 1]
        t0 = abs(diag[i, 0, 0]) * abs(r[2 * i]) + abs(diag[i, 0, 1]) * abs(r[2 * i + 1])
        t1 = abs(diag[i, 1, 0]) * abs(r[2 * i]) + abs(diag[i, 1, 1]) * abs(r[2 * i + 1])
        for p in range(bptr[i], bptr[i + 1]):     # u = W r + q and |W||r| together
            w = bdata[p]
            x = r[2 * bcols[p]:2 * bcols[p] + 2]
            u0 += w[0, 0] * x[0] + w[0, 1] * x[1]
            u1 += w[1, 0] * x[0] + w[1, 1] * x[1]
            t0 += abs(w[0, 0]) * abs(x[0]) + abs(w[0, 1]) * abs(x[1])
            t1 += abs(w[1, 0]) * abs(x[0]) + abs(w[1, 1]) * abs(x[1])
        m = mu[i]
        un_hat = u0 + m * abs(u1)          # De Saxcé's modified velocity
        wn = abs(diag[i, 0, 0])
        rho = 1.0 / wn if wn > 0.0 else fallback
        # Siconos's natural map: ρ = 1
        e0, e1 = _cone_residual_2d(r[2 * i], r[2 * i + 1], r[2 * i] - un_hat,
                                   r[2 * i + 1] - u1, m)
        nat2 += e0 * e0 + e1 * e1
        q2 += q[2 * i] * q[2 * i] + q[2 * i + 1] * q[2 * i + 1]
        # each contact on its own scale: ρ_i = 1 / W_nn,i
        e0, e1 = _cone_residual_2d(r[2 * i], r[2 * i + 1], r[2 * i] - rho * un_hat,
                                   r[2 * i + 1] - rho * u1, m)
        res[i] = np.sqrt(e0 * e0 + e1 * e1)
        size[i] = (np.sqrt(r[2 * i] ** 2 + r[2 * i + 1] ** 2)
                   + rho * (np.sqrt(q[2 * i] ** 2 + q[2 * i + 1] ** 2) + np.sqrt(t0 * t0 + t1 * t1)))
    smax = 0.0
    for i in range(nc):
        smax = max(smax, size[i])
    floor = np.finfo(np.float64).eps * smax
    worst = 0.0
    for i in range(nc):
        e = res[i] / max(size[i], floor) if smax > 0.0 else res[i]
        worst = max(worst, e)
    return max(np.sqrt(nat2) / (1.0 + np.sqrt(q2)), worst)
