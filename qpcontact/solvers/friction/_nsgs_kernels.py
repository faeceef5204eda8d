"""Compiled sweeps of the nonsmooth Gauss–Seidel method ("nsgs", numba).

One sweep visits the contacts in order; contact i's local problem is
u_i = W_ii r_i + b_i with b_i = q_i + Σ_{j≠i} W_ij r_j (the latest r_j), and
r_i is replaced by its local solution.  In 2-D the local problem is a 2 x 2
LCP solved exactly by enumeration (open, sticking, sliding either way); in
3-D in closed form where W_ii = diag(a, c, c) and asked for
(:func:`_local_3d_closed_form`), else by the projected fixed point
r ← proj_K(r − ρ(u + μ‖u_T‖e_N)), ρ = 1/‖W_ii‖_F, iterated to the local
tolerance.  Both sweeps read W by blocks (2 x 2, 3 x 3).  A sweep is
O(nnz(W)).
"""

from __future__ import annotations

import numpy as np
from ...core._cone_kernels import INSIDE, POLAR, cone_region
from ...core.compiled import njit


@njit
def _project(r, mu, d):
    """r projected onto {‖r_T‖ <= μ r_N} in place (d = 2 or 3)."""
    t = 0.0
    for k in range(1, d):
        t += r[k] * r[k]
    t = np.sqrt(t)
    rn = r[0]
    region = cone_region(rn, t, mu)
    if region == INSIDE:
        return
    if region == POLAR:
        for k in range(d):
            r[k] = 0.0
        return
    a = (mu * t + rn) / (1.0 + mu * mu)
    r[0] = a
    for k in range(1, d):
        r[k] = r[k] * mu * a / t if t > 0.0 else 0.0


@njit
def _local_2d(A, b, mu, r):
    """The 2-D local problem by enumeration; False when no case fits (a
    degenerate block), r then left as it was."""
    if b[0] >= 0.0:                        # open
        r[0] = 0.0
        r[1] = 0.0
        return True
    det = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
    if det > 0.0:                          # sticking: A r = -b inside the cone
        rn = (-b[0] * A[1, 1] + b[1] * A[0, 1]) / det
        rt = (-b[1] * A[0, 0] + b[0] * A[1, 0]) / det
        if rn >= 0.0 and abs(rt) <= mu * rn:
            r[0] = rn
            r[1] = rt
            return True
    for s in (1.0, -1.0):                  # sliding with u_T of sign s, r_T = -s μ r_N
        den = A[0, 0] - s * mu * A[0, 1]
        if den > 0.0:
            rn = -b[0] / den
            ut = (A[1, 0] - s * mu * A[1, 1]) * rn + b[1]
            if rn >= 0.0 and s * ut >= 0.0:
                r[0] = rn
                r[1] = -s * mu * rn
                return True
    return False


@njit
def _frobenius_step(A, d):
    """The local fixed point's step ρ = 1/‖W_ii‖_F (1 for a zero block)."""
    rho = 0.0
    for a in range(d):
        for c in range(d):
            rho += A[a, c] * A[a, c]
    return 1.0 / np.sqrt(rho) if rho > 0.0 else 1.0


@njit
def _local_fixed_point(A, b, mu, r, d, rtol, max_local, rho, u, x):
    """The local problem by the projected fixed point from r (in place), ρ
    its step (:func:`_frobenius_step`, once per contact and sweep call),
    ``u`` and ``x`` the sweep's work arrays of d entries."""
    for _ in range(max_local):
        for a in range(d):
            acc = b[a]
            for c in range(d):
                acc += A[a, c] * r[c]
            u[a] = acc
        ut = 0.0
        for k in range(1, d):
            ut += u[k] * u[k]
        ut = np.sqrt(ut)
        x[0] = r[0] - rho * (u[0] + mu * ut)
        for k in range(1, d):
            x[k] = r[k] - rho * u[k]
        _project(x, mu, d)
        step, size = 0.0, 0.0
        for k in range(d):
            step += (x[k] - r[k]) ** 2
            size += x[k] * x[k]
            r[k] = x[k]
        if step <= rtol * rtol * size:
            break


@njit
def _local_3d_closed_form(a, c, b, mu, r):
    """The 3-D local problem u = diag(a, c, c) r + b (a sphere's contact
    block: the normal through both centres), exactly: open where b_N >= 0
    (r = 0, û = b ∈ K*); else the contact closes, u_N = 0, r_N = −b_N/a, and
    it sticks, r_T = −b_T/c, where that lies in the cone (‖b_T‖ <= μ c r_N,
    u_T = 0), else slides: u_T = b_T + c r_T parallel to b_T and opposite
    to r_T = −μ r_N b_T/‖b_T‖, so ‖u_T‖ = ‖b_T‖ − μ c r_N > 0."""
    if b[0] >= 0.0:
        r[0] = 0.0
        r[1] = 0.0
        r[2] = 0.0
        return
    rn = -b[0] / a
    bt = np.sqrt(b[1] * b[1] + b[2] * b[2])
    r[0] = rn
    if bt <= mu * c * rn:
        r[1] = -b[1] / c
        r[2] = -b[2] / c
    else:
        s = mu * rn / bt
        r[1] = -s * b[1]
        r[2] = -s * b[2]


@njit
def diagonal_blocks_3d(blocks, rtol):
    """Per contact whether its 3 x 3 block is diag(a, c, c) to ``rtol`` of
    its largest entry (a > 0, c > 0): where the closed form applies."""
    nc = blocks.shape[0]
    out = np.zeros(nc, np.bool_)
    for i in range(nc):
        A = blocks[i]
        big = 0.0
        for k in range(3):
            for m in range(3):
                big = max(big, abs(A[k, m]))
        off = max(abs(A[0, 1]), abs(A[0, 2]), abs(A[1, 0]), abs(A[2, 0]), abs(A[1, 2]),
                  abs(A[2, 1]), abs(A[1, 1] - A[2, 2]))
        out[i] = A[0, 0] > 0.0 and A[1, 1] > 0.0 and off <= rtol * big
    return out


@njit
def _project_2d(rn, rt, mu):
    """:func:`_project` for d = 2 on scalars, the same operations in the same
    order (so the same bits)."""
    t = np.sqrt(rt * rt)
    region = cone_region(rn, t, mu)
    if region == INSIDE:
        return rn, rt
    if region == POLAR:
        return 0.0, 0.0
    a = (mu * t + rn) / (1.0 + mu * mu)
    return a, (rt * mu * a / t if t > 0.0 else 0.0)


@njit
def _local_2d_scalars(a00, a01, a10, a11, b0, b1, mu):
    """:func:`_local_2d` on scalars: (found, r_N, r_T), the same operations."""
    if b0 >= 0.0:                          # open
        return True, 0.0, 0.0
    det = a00 * a11 - a01 * a10
    if det > 0.0:                          # sticking: A r = -b inside the cone
        rn = (-b0 * a11 + b1 * a01) / det
        rt = (-b1 * a00 + b0 * a10) / det
        if rn >= 0.0 and abs(rt) <= mu * rn:
            return True, rn, rt
    for s in (1.0, -1.0):                  # sliding with u_T of sign s, r_T = -s μ r_N
        den = a00 - s * mu * a01
        if den > 0.0:
            rn = -b0 / den
            ut = (a10 - s * mu * a11) * rn + b1
            if rn >= 0.0 and s * ut >= 0.0:
                return True, rn, -s * mu * rn
    return False, 0.0, 0.0


@njit
def sweeps_2d(bptr, bcols, bdata, q, mu, r, blocks, n_sweeps, local_rtol, max_local, omega,
              held, moved):
    """``sweeps`` for 2-D contacts on W's 2 x 2 blocks (BSR without the
    diagonal ones: ``bptr``, ``bcols``, ``bdata`` (nb, 2, 2)): each
    neighbour's impulse read once for both rows, no test per entry, the
    local problem on scalars (no array views made per contact) — the same
    iterates as the CSR sweep (to rounding; as the array form of this sweep
    bit for bit) at about a fifth of its time on a 1 170-contact drum bed.

    Open contacts passed over while they provably stay open.  A contact whose
    r_i is 0 and whose b_N,i was >= 0 when last visited stays at 0 as long
    as b_N,i does (the local problem's answer is then open, and over-relaxing
    0 towards 0 is 0); b_N,i has moved since by at most
    Σ_j (|W_ij,NN| + |W_ij,NT|) ‖Δr_j‖ <= that row sum times the sum of the
    sweeps' largest changes ‖Δr_j‖ since.  ``held`` (nc, 3): per contact
    b_N,i when it was found open (−1 where not), the row sum, the running
    sum at the start of that sweep; ``moved`` [0]: the running sum of the
    sweeps' largest changes.  Where the bound keeps b_N,i above a margin for
    rounding the contact is passed over — the iterates are the same as
    visiting it."""
    nc = mu.shape[0]
    b = np.empty(2)
    ri = np.empty(2)
    u = np.empty(2)
    x = np.empty(2)
    change = 0.0
    big = 0.0
    for c in range(r.shape[0]):
        big = max(big, abs(r[c]))
    for _ in range(n_sweeps):
        change = 0.0
        largest = 0.0
        total = moved[0]
        for i in range(nc):
            if held[i, 0] >= 0.0:
                reach = held[i, 1] * (total - held[i, 2] + largest)
                if held[i, 0] - reach > 1e-12 * (abs(q[2 * i]) + held[i, 1] * 2.0 * big):
                    continue
            b0 = q[2 * i]
            b1 = q[2 * i + 1]
            for p in range(bptr[i], bptr[i + 1]):
                j = bcols[p]
                x0 = r[2 * j]
                x1 = r[2 * j + 1]
                b0 += bdata[p, 0, 0] * x0 + bdata[p, 0, 1] * x1
                b1 += bdata[p, 1, 0] * x0 + bdata[p, 1, 1] * x1
            old0 = r[2 * i]
            old1 = r[2 * i + 1]
            found, n0, n1 = _local_2d_scalars(blocks[i, 0, 0], blocks[i, 0, 1], blocks[i, 1, 0],
                                              blocks[i, 1, 1], b0, b1, mu[i])
            if not found:     # a degenerate block: the local fixed point from r_i
                b[0] = b0
                b[1] = b1
                ri[0] = old0
                ri[1] = old1
                _local_fixed_point(blocks[i], b, mu[i], ri, 2, local_rtol, max_local,
                                   _frobenius_step(blocks[i], 2), u, x)
                n0, n1 = ri[0], ri[1]
            if omega != 1.0:
                n0, n1 = _project_2d(old0 + omega * (n0 - old0), old1 + omega * (n1 - old1),
                                     mu[i])
            delta = (n0 - old0) ** 2 + (n1 - old1) ** 2
            r[2 * i] = n0
            r[2 * i + 1] = n1
            if old0 == 0.0 and old1 == 0.0 and n0 == 0.0 and n1 == 0.0 and b0 >= 0.0:
                held[i, 0] = b0
                held[i, 2] = total
            else:
                held[i, 0] = -1.0
            if delta > change:
                change = delta
                largest = np.sqrt(change)
                big = max(big, abs(n0), abs(n1))
        moved[0] = total + largest
    return np.sqrt(change)


@njit
def row_sums_2d(bptr, bdata):
    """Σ_j (|W_ij,NN| + |W_ij,NT|) per contact i over its other blocks."""
    nc = bptr.shape[0] - 1
    out = np.zeros(nc)
    for i in range(nc):
        for p in range(bptr[i], bptr[i + 1]):
            out[i] += abs(bdata[p, 0, 0]) + abs(bdata[p, 0, 1])
    return out


@njit
def sweeps_3d(bptr, bcols, bdata, q, mu, r, blocks, closed, n_sweeps, local_rtol, max_local,
              omega):
    """``sweeps`` for 3-D contacts on W's 3 x 3 blocks (BSR, the diagonal
    ones skipped by their column: ``bptr``, ``bcols``, ``bdata`` (nb, 3, 3)):
    each neighbour's impulse read once for the three rows, no test per
    entry; the same sums in the same order as the CSR sweep where W's
    blocks are stored whole."""
    nc = mu.shape[0]
    b = np.empty(3)
    ri = np.empty(3)
    u = np.empty(3)
    x = np.empty(3)
    rho = np.empty(nc)
    for i in range(nc):
        rho[i] = _frobenius_step(blocks[i], 3)
    change = 0.0
    for _ in range(n_sweeps):
        change = 0.0
        for i in range(nc):
            lo = 3 * i
            b0 = q[lo]
            b1 = q[lo + 1]
            b2 = q[lo + 2]
            for p in range(bptr[i], bptr[i + 1]):
                j = bcols[p]
                if j == i:
                    continue
                x0 = r[3 * j]
                x1 = r[3 * j + 1]
                x2 = r[3 * j + 2]
                B = bdata[p]
                b0 = b0 + B[0, 0] * x0 + B[0, 1] * x1 + B[0, 2] * x2
                b1 = b1 + B[1, 0] * x0 + B[1, 1] * x1 + B[1, 2] * x2
                b2 = b2 + B[2, 0] * x0 + B[2, 1] * x1 + B[2, 2] * x2
            b[0] = b0
            b[1] = b1
            b[2] = b2
            for k in range(3):
                ri[k] = r[lo + k]
            A = blocks[i]
            if closed[i]:
                _local_3d_closed_form(A[0, 0], 0.5 * (A[1, 1] + A[2, 2]), b, mu[i], ri)
            else:
                _local_fixed_point(A, b, mu[i], ri, 3, local_rtol, max_local, rho[i], u, x)
            if omega != 1.0:
                for k in range(3):
                    ri[k] = r[lo + k] + omega * (ri[k] - r[lo + k])
                _project(ri, mu[i], 3)
            delta = 0.0
            for k in range(3):
                delta += (ri[k] - r[lo + k]) ** 2
                r[lo + k] = ri[k]
            if delta > change:
                change = delta
    return np.sqrt(change)
