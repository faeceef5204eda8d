"""Compiled loops of the certificate (numba).

The column influences c_j = max_i |M_ij| / σ_i of a sparse M are one pass over
its nonzeros; as NumPy calls (divide, then maximum.reduceat) they cost 4 ms on
a 3e5-nonzero chain, a tenth of a bpp solve; as one loop, a few hundred µs.
"""

from __future__ import annotations

import numpy as np
from ..core._cone_kernels import INSIDE, POLAR, cone_region
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
def jacobian_blocks_2d(u, r, q, terms, mu, rho, slip_rtol):
    """Per 2-D contact at r, the blocks of :func:`natural_map_jacobian_2d`'s
    J = I − blockdiag(J_P) + blockdiag(B) W: (J_P, B, x_N, x_T), (nc, 2, 2)
    twice and x = r − ρ û (u = W r + q, ``terms`` = |W| |r|, ρ per contact)."""
    nc = mu.shape[0]
    size = np.empty(nc)
    big = 0.0
    for i in range(nc):
        s_i = np.sqrt(r[2 * i] * r[2 * i] + r[2 * i + 1] * r[2 * i + 1]) + rho[i] * (
            np.sqrt(q[2 * i] * q[2 * i] + q[2 * i + 1] * q[2 * i + 1])
            + np.sqrt(terms[2 * i] * terms[2 * i] + terms[2 * i + 1] * terms[2 * i + 1]))
        size[i] = s_i
        big = max(big, s_i)
    floor = np.finfo(np.float64).eps * big
    b = np.empty((nc, 2, 2))
    jp = np.zeros((nc, 2, 2))
    xs = np.empty((nc, 2))
    for i in range(nc):
        un, ut = u[2 * i], u[2 * i + 1]
        tn = np.sqrt(ut * ut)
        xn = r[2 * i] - rho[i] * (un + mu[i] * tn)
        xt = r[2 * i + 1] - rho[i] * ut
        xs[i, 0], xs[i, 1] = xn, xt
        t01 = mu[i] * (ut / tn) if rho[i] * tn > slip_rtol * max(size[i], floor) else 0.0
        m = mu[i]
        t = np.sqrt(xt * xt)
        region = cone_region(xn, t, m)
        if region == INSIDE:
            jp[i, 0, 0] = 1.0
            jp[i, 1, 1] = 1.0
        elif region != POLAR:           # on its side (the polar cone: 0)
            that = xt / t
            alpha = (xn + m * t) / (1 + m * m)
            v1 = m * that
            den = 1 + m * m
            jp[i, 0, 0] = (1.0 * 1.0) / den
            jp[i, 0, 1] = (1.0 * v1) / den
            jp[i, 1, 0] = (v1 * 1.0) / den
            jp[i, 1, 1] = (v1 * v1) / den + (m * alpha / t) * (1.0 - that * that)
        for a in range(2):
            b[i, a, 0] = rho[i] * (jp[i, a, 0] * 1.0 + jp[i, a, 1] * 0.0)
            b[i, a, 1] = rho[i] * (jp[i, a, 0] * t01 + jp[i, a, 1] * 1.0)
    return jp, b, xs


@njit
def natural_map_jacobian_2d(u, r, q, terms, mu, rho, slip_rtol, diag, bptr, bcols, bdata):
    """(indptr, indices, data) of the natural map's Jacobian
    J = I − blockdiag(J_P) + blockdiag(B) W in CSC for 2-D contacts at r
    (friction_certificate.natural_map_jacobian: u = W r + q, ``terms`` =
    |W| |r|, ρ per contact; W by its 2 × 2 blocks, FrictionProblem.W_blocks),
    B_i = ρ_i J_P,i T_i, T_i = [[1, μ_i g_i], [0, 1]] on a sliding contact
    (g_i = u_T,i/|u_T,i|, sliding where ρ_i |u_T,i| > slip_rtol s_i, s_i
    contact_sizes'), J_P the cone projection's Jacobian at x = r − ρ û
    (:func:`jacobian_blocks_2d`).
    Every entry is the array formulas' (contact_sizes', projection_jacobian's,
    the sparse products' order of summation), exact zeros left out as those
    leave them; formed by rows and transposed here, rows ascending: the CSR
    form's tocsc() bit for bit, without scipy's conversion and the NumPy
    passes (0.6 -> 0.3 ms a call on the drum's 1 100-contact beds)."""
    nc = mu.shape[0]
    jp, b, _ = jacobian_blocks_2d(u, r, q, terms, mu, rho, slip_rtol)
    # by rows: the diagonal block, then the row's others
    nb = bptr[nc]
    rptr = np.zeros(2 * nc + 1, np.int64)
    ridx = np.empty(4 * (nb + nc), np.int64)
    rval = np.empty(4 * (nb + nc))
    count = np.zeros(2 * nc + 1, np.int64)
    nnz = 0
    for i in range(nc):
        for a in range(2):
            for e in range(2):        # the diagonal block: (I − J_P) + B W
                v = b[i, a, 0] * diag[i, 0, e] + b[i, a, 1] * diag[i, 1, e]
                v = ((1.0 if a == e else 0.0) - jp[i, a, e]) + v
                if v != 0.0:          # exact zeros left out, as the sparse products do
                    ridx[nnz] = 2 * i + e
                    rval[nnz] = v
                    count[2 * i + e + 1] += 1
                    nnz += 1
            for s in range(bptr[i], bptr[i + 1]):
                cb = bcols[s]
                for e in range(2):
                    v = b[i, a, 0] * bdata[s, 0, e] + b[i, a, 1] * bdata[s, 1, e]
                    if v != 0.0:
                        ridx[nnz] = 2 * cb + e
                        rval[nnz] = v
                        count[2 * cb + e + 1] += 1
                        nnz += 1
            rptr[2 * i + a + 1] = nnz
    return csr_transposed(rptr, ridx, rval, count)


@njit
def csr_transposed(rptr, ridx, rval, count):
    """The CSC arrays (indptr, indices, data) of a square matrix given by rows
    (``rptr``, ``ridx``, ``rval``), each column's rows ascending; ``count``
    [c + 1] holds column c's entries (changed here)."""
    n = rptr.shape[0] - 1
    for c in range(n):
        count[c + 1] += count[c]
    cptr = count.copy()
    cidx = np.empty(rptr[n], np.int64)
    cval = np.empty(rptr[n])
    for row in range(n):
        for k in range(rptr[row], rptr[row + 1]):
            c = ridx[k]
            cidx[count[c]] = row
            cval[count[c]] = rval[k]
            count[c] += 1
    return cptr, cidx, cval


@njit
def _cone_residual_2d(rn, rt, xn, xt, mu):
    """(r − proj_K(x)) for one 2-D contact, proj_K as friction_problem.project_cone."""
    t = abs(xt)
    region = cone_region(xn, t, mu)
    if region == INSIDE:
        pn, pt = xn, xt
    elif region == POLAR:
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
