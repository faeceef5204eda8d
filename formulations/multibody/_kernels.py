"""O(N) recursions over the body tree, compiled with numba.

Conventions (see formulations/multibody/__init__.py for the derivation):
body 0 is the base, bodies 1..N have parent[i] < i.  A spatial velocity is
V = (v, ω) in the body's own frame (v: velocity of the frame origin O_i), a
spatial force f = (F, N) with the moment about O_i.  The velocity transform of
joint i is C_i = diag(R_i', R_i') [[I, -ρ̃_i], [0, I]] with R_i, ρ_i the child
frame's orientation and origin in the parent frame; C_i' carries a force from
the child to the parent frame.  Joint motion subspaces H_i (6 x n_i, child
frame) are stored padded to 6 x 6.

Why numba: the recursions are sequential along the tree (a chain of N bodies
has depth N), so they cannot be vectorised over bodies; NumPy calls on 6 x 6
blocks cost ~1 µs each and would dominate.  Everything here is plain loops on
small fixed-size arrays.
"""

from __future__ import annotations

import warnings

import numpy as np
from numba.core.errors import NumbaPerformanceWarning

from qpcontact.core.compiled import njit

# numba notes that '@' on non-contiguous 6 x n slices is slower than BLAS on
# contiguous ones; at these sizes the loops win anyway.
warnings.filterwarnings("ignore", category=NumbaPerformanceWarning)

REVOLUTE, PRISMATIC, CARDAN, SPHERICAL, FREE, PLANAR = 0, 1, 2, 3, 4, 5

_CACHE = True


# -- small dense helpers -------------------------------------------------------------------

@njit(cache=_CACHE)
def _cross(a, b):
    out = np.empty(3)
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]
    return out


@njit(cache=_CACHE)
def quat_rotation(qx, qy, qz, qw):
    """Rotation matrix of a quaternion (x, y, z, w), normalised here so that a
    drifting integrated quaternion still gives an orthogonal matrix."""
    n = np.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    x, y, z, w = qx / n, qy / n, qz / n, qw / n
    R = np.empty((3, 3))
    R[0, 0] = 1 - 2 * (y * y + z * z)
    R[0, 1] = 2 * (x * y - z * w)
    R[0, 2] = 2 * (x * z + y * w)
    R[1, 0] = 2 * (x * y + z * w)
    R[1, 1] = 1 - 2 * (x * x + z * z)
    R[1, 2] = 2 * (y * z - x * w)
    R[2, 0] = 2 * (x * z - y * w)
    R[2, 1] = 2 * (y * z + x * w)
    R[2, 2] = 1 - 2 * (x * x + y * y)
    return R


@njit(cache=_CACHE)
def _c_to(R, rho, V, out):
    """out = C V: parent-frame velocity -> child frame (no allocation)."""
    wx, wy, wz = V[3], V[4], V[5]
    vx = V[0] + wy * rho[2] - wz * rho[1]
    vy = V[1] + wz * rho[0] - wx * rho[2]
    vz = V[2] + wx * rho[1] - wy * rho[0]
    for r in range(3):
        out[r] = R[0, r] * vx + R[1, r] * vy + R[2, r] * vz
        out[3 + r] = R[0, r] * wx + R[1, r] * wy + R[2, r] * wz


@njit(cache=_CACHE)
def _ct_add(R, rho, f, out):
    """out += C' f: child-frame force -> parent frame, moment moved to the parent
    origin (no allocation)."""
    F0 = R[0, 0] * f[0] + R[0, 1] * f[1] + R[0, 2] * f[2]
    F1 = R[1, 0] * f[0] + R[1, 1] * f[1] + R[1, 2] * f[2]
    F2 = R[2, 0] * f[0] + R[2, 1] * f[1] + R[2, 2] * f[2]
    out[0] += F0
    out[1] += F1
    out[2] += F2
    out[3] += R[0, 0] * f[3] + R[0, 1] * f[4] + R[0, 2] * f[5] + rho[1] * F2 - rho[2] * F1
    out[4] += R[1, 0] * f[3] + R[1, 1] * f[4] + R[1, 2] * f[5] + rho[2] * F0 - rho[0] * F2
    out[5] += R[2, 0] * f[3] + R[2, 1] * f[4] + R[2, 2] * f[5] + rho[0] * F1 - rho[1] * F0


@njit(cache=_CACHE)
def _cross_force(V, f):
    """V x* f = (ω x F, v x F + ω x N)."""
    out = np.empty(6)
    out[:3] = _cross(V[3:], f[:3])
    out[3:] = _cross(V[:3], f[:3]) + _cross(V[3:], f[3:])
    return out


@njit(cache=_CACHE)
def _cross_motion(V, U):
    """V x U = (ω x u + v x υ, ω x υ) for U = (u, υ)."""
    out = np.empty(6)
    out[:3] = _cross(V[3:], U[:3]) + _cross(V[:3], U[3:])
    out[3:] = _cross(V[3:], U[3:])
    return out


@njit(cache=_CACHE)
def _axis_rotation_to(a, angle, R):
    c, s = np.cos(angle), np.sin(angle)
    t = 1.0 - c
    x, y, z = a[0], a[1], a[2]
    R[0, 0] = c + x * x * t
    R[0, 1] = x * y * t - z * s
    R[0, 2] = x * z * t + y * s
    R[1, 0] = y * x * t + z * s
    R[1, 1] = c + y * y * t
    R[1, 2] = y * z * t - x * s
    R[2, 0] = z * x * t - y * s
    R[2, 1] = z * y * t + x * s
    R[2, 2] = c + z * z * t


@njit(cache=_CACHE)
def _matmul3_to(A, B, out):
    for i in range(3):
        for j in range(3):
            out[i, j] = A[i, 0] * B[0, j] + A[i, 1] * B[1, j] + A[i, 2] * B[2, j]


_EZ = np.array([0.0, 0.0, 1.0])


# -- joints ----------------------------------------------------------------------------------

@njit(cache=_CACHE)
def _joint_to(jt, ax, fixed, mask, q, iq, nu, iv, want_hdot, R, p, H, Hd, T1, T2):
    """Joint transform R_J, p_J (child frame in the joint frame), motion
    subspace H (child frame, padded 6 x 6; zero on entry) and its time
    derivative Ḣ along ν (only when ``want_hdot``; zero on entry), written in
    place; T1, T2 are 3 x 3 work arrays.  Returns the number of columns."""
    for a in range(3):
        p[a] = 0.0
        for b in range(3):
            R[a, b] = 1.0 if a == b else 0.0
    if jt == REVOLUTE:
        _axis_rotation_to(ax[0], q[iq], R)
        for a in range(3):
            H[3 + a, 0] = ax[0, a]
        return 1
    if jt == PRISMATIC:
        for a in range(3):
            p[a] = ax[0, a] * q[iq]
            H[a, 0] = ax[0, a]
        return 1
    if jt == CARDAN:
        _axis_rotation_to(ax[0], q[iq], T1)
        _axis_rotation_to(ax[1], q[iq + 1], T2)
        _matmul3_to(T1, T2, R)
        for a in range(3):       # e1 = R2' a1
            H[3 + a, 0] = T2[0, a] * ax[0, 0] + T2[1, a] * ax[0, 1] + T2[2, a] * ax[0, 2]
            H[3 + a, 1] = ax[1, a]
        if want_hdot:            # d/dt(R2'a1) = -q̇2 a2 x (R2'a1)
            w = nu[iv + 1]
            e0, e1_, e2 = H[3, 0], H[4, 0], H[5, 0]
            Hd[3, 0] = -w * (ax[1, 1] * e2 - ax[1, 2] * e1_)
            Hd[4, 0] = -w * (ax[1, 2] * e0 - ax[1, 0] * e2)
            Hd[5, 0] = -w * (ax[1, 0] * e1_ - ax[1, 1] * e0)
        return 2
    if jt == SPHERICAL:
        T1[:, :] = quat_rotation(q[iq], q[iq + 1], q[iq + 2], q[iq + 3])
        R[:, :] = T1
        for k in range(3):
            H[3 + k, k] = 1.0
        return 3
    if jt == FREE:
        for a in range(3):
            p[a] = q[iq + a]
        R[:, :] = quat_rotation(q[iq + 3], q[iq + 4], q[iq + 5], q[iq + 6])
        for k in range(6):
            H[k, k] = 1.0
        return 6
    # PLANAR: translation (x, y) in the joint frame, then rotation θ about z;
    # the axes not in ``mask`` stay at their ``fixed`` values
    xyt0, xyt1, xyt2 = fixed[0], fixed[1], fixed[2]
    k = 0
    if mask[0]:
        xyt0 = q[iq + k]
        k += 1
    if mask[1]:
        xyt1 = q[iq + k]
        k += 1
    if mask[2]:
        xyt2 = q[iq + k]
        k += 1
    _axis_rotation_to(_EZ, xyt2, R)
    p[0] = xyt0
    p[1] = xyt1
    thd = nu[iv + k - 1] if (mask[2] and want_hdot) else 0.0
    col = 0
    for a in range(3):
        if mask[a]:
            if a < 2:
                for b in range(3):
                    H[b, col] = R[a, b]          # R' e_a
                if want_hdot:                    # -θ̇ e_z x (R' e_a)
                    Hd[0, col] = thd * R[a, 1]
                    Hd[1, col] = -thd * R[a, 0]
            else:
                H[5, col] = 1.0
            col += 1
    return col


@njit(cache=_CACHE)
def relative(parent, jtype, axes, fixed, mask, R0, r0, iq, iv, q, nu, want_hdot):
    """Relative placements (R_i, ρ_i in the parent frame) and H_i, Ḣ_i of every joint."""
    nb = parent.size
    Rrel = np.empty((nb, 3, 3))
    rho = np.zeros((nb, 3))
    H = np.zeros((nb, 6, 6))
    Hd = np.zeros((nb, 6, 6))
    RJ = np.empty((3, 3))
    pJ = np.empty(3)
    T1 = np.empty((3, 3))
    T2 = np.empty((3, 3))
    Rrel[0] = np.eye(3)
    for i in range(1, nb):
        _joint_to(jtype[i], axes[i], fixed[i], mask[i], q, iq[i], nu, iv[i], want_hdot,
                  RJ, pJ, H[i], Hd[i], T1, T2)
        _matmul3_to(R0[i], RJ, Rrel[i])
        for a in range(3):
            rho[i, a] = r0[i, a] + R0[i, a, 0] * pJ[0] + R0[i, a, 1] * pJ[1] + R0[i, a, 2] * pJ[2]
    return Rrel, rho, H, Hd


@njit(cache=_CACHE)
def absolute(parent, Rrel, rho, Rbase, rbase):
    """World orientation and origin of every body frame."""
    nb = parent.size
    Ra = np.empty((nb, 3, 3))
    ra = np.empty((nb, 3))
    Ra[0] = Rbase
    ra[0] = rbase
    for i in range(1, nb):
        p = parent[i]
        _matmul3_to(Ra[p], Rrel[i], Ra[i])
        for a in range(3):
            ra[i, a] = ra[p, a] + Ra[p, a, 0] * rho[i, 0] + Ra[p, a, 1] * rho[i, 1] + Ra[p, a, 2] * rho[i, 2]
    return Ra, ra


@njit(cache=_CACHE)
def velocities(parent, Rrel, rho, H, nvj, iv, nu, V0):
    nb = parent.size
    V = np.zeros((nb, 6))
    V[0] = V0
    for i in range(1, nb):
        _c_to(Rrel[i], rho[i], V[parent[i]], V[i])
        for k in range(nvj[i]):
            for c in range(6):
                V[i, c] += H[i, c, k] * nu[iv[i] + k]
    return V


# -- dynamics, Lagrange form ----------------------------------------------------------------

@njit(cache=_CACHE)
def rnea(parent, Rrel, rho, H, Hd, nvj, iv, M, nu, nud, V0, A0, fext):
    """Inverse dynamics: τ = G(q) ν̇ + c(q, ν) - (J' of the body forces ``fext``).
    A0 is the base's spatial acceleration (gravity enters as -g there)."""
    nb = parent.size
    V = np.zeros((nb, 6))
    A = np.zeros((nb, 6))
    f = np.zeros((nb, 6))
    V[0] = V0
    A[0] = A0
    rel = np.empty(6)
    for i in range(1, nb):
        p = parent[i]
        _c_to(Rrel[i], rho[i], V[p], V[i])
        _c_to(Rrel[i], rho[i], A[p], A[i])
        rel[:] = 0.0
        for k in range(nvj[i]):
            rel += H[i][:, k] * nu[iv[i] + k]
            A[i] += H[i][:, k] * nud[iv[i] + k] + Hd[i][:, k] * nu[iv[i] + k]
        V[i] += rel
        A[i] += _cross_motion(V[i], rel)
        h = M[i] @ V[i]
        f[i] = M[i] @ A[i] + _cross_force(V[i], h) - fext[i]
    tau = np.zeros(nu.size)
    for i in range(nb - 1, 0, -1):
        for k in range(nvj[i]):
            tau[iv[i] + k] = H[i][:, k] @ f[i]
        p = parent[i]
        if p > 0:
            _ct_add(Rrel[i], rho[i], f[i], f[p])
    return tau


@njit(cache=_CACHE)
def crba(parent, Rrel, rho, H, nvj, iv, M, nv):
    """Composite-rigid-body mass matrix G(q) (dense, nv x nv)."""
    nb = parent.size
    Ic = M.copy()
    B = np.empty((6, 6))
    col = np.empty(6)
    row = np.empty(6)
    for i in range(nb - 1, 0, -1):
        p = parent[i]
        if p > 0:
            _congruence_add(Rrel[i], rho[i], Ic[i], True, B, col, row, Ic[p])
    G = np.zeros((nv, nv))
    for i in range(1, nb):
        n = nvj[i]
        F = Ic[i] @ H[i][:, :n]
        G[iv[i]:iv[i] + n, iv[i]:iv[i] + n] = H[i][:, :n].T @ F
        j = i
        while parent[j] > 0:
            Fn = np.zeros((6, n))
            for k in range(n):
                _ct_add(Rrel[j], rho[j], F[:, k], Fn[:, k])
            F = Fn
            j = parent[j]
            m = nvj[j]
            blk = H[j][:, :m].T @ F
            G[iv[j]:iv[j] + m, iv[i]:iv[i] + n] = blk
            G[iv[i]:iv[i] + n, iv[j]:iv[j] + m] = blk.T
    return G


# -- dynamics, momentum form (Ivanov & Shimanovsky 2017) ---------------------------------------

@njit(cache=_CACHE)
def _congruence_add(R, rho, A, sym, B, col, row, out):
    """out += C'AC using the work arrays B (6 x 6), col, row (6).  ``sym``:
    A symmetric, only the upper triangle of the result is computed (LDL');
    otherwise the full product (the sweep)."""
    for j in range(6):
        for k in range(6):
            col[k] = 0.0
        _ct_add(R, rho, A[:, j], col)
        for k in range(6):
            B[k, j] = col[k]
    for i in range(6):
        for k in range(6):
            row[k] = 0.0
        _ct_add(R, rho, B[i, :], row)
        if sym:
            for j in range(i, 6):
                out[i, j] += row[j]
                if j != i:
                    out[j, i] += row[j]
        else:
            for j in range(6):
                out[i, j] += row[j]


@njit(cache=_CACHE)
def _congruence_sym_add(R, rho, A, T, B11, B12, B22, X, out):
    """out += C'AC for a symmetric 6 x 6 A, by 3 x 3 blocks: B = diag(R) A
    diag(R') (the diagonal blocks as symmetric products), then the shift
    P B P' with P = [[I, 0], [ρ̃, I]], upper triangles only (the LDL' variant's
    use of symmetry; T, B11, B12, B22, X are 3 x 3 work arrays)."""
    # B11 = R A11 R', B22 = R A22 R' (upper triangles), B12 = R A12 R'
    for blk in range(2):
        o = 3 * blk
        for i in range(3):
            for j in range(3):
                T[i, j] = A[o + i, o] * R[j, 0] + A[o + i, o + 1] * R[j, 1] + A[o + i, o + 2] * R[j, 2]
        Bd = B11 if blk == 0 else B22
        for i in range(3):
            for j in range(i, 3):
                Bd[i, j] = R[i, 0] * T[0, j] + R[i, 1] * T[1, j] + R[i, 2] * T[2, j]
                Bd[j, i] = Bd[i, j]
    for i in range(3):
        for j in range(3):
            T[i, j] = A[i, 3] * R[j, 0] + A[i, 4] * R[j, 1] + A[i, 5] * R[j, 2]
    for i in range(3):
        for j in range(3):
            B12[i, j] = R[i, 0] * T[0, j] + R[i, 1] * T[1, j] + R[i, 2] * T[2, j]
    r0, r1, r2 = rho[0], rho[1], rho[2]
    # top blocks: B11 and B12 - B11 ρ̃  (column j of B11 ρ̃ = B11 (ρ x e_j)... via ρ̃'s entries)
    for i in range(3):
        for j in range(i, 3):
            out[i, j] += B11[i, j]
            if j != i:
                out[j, i] += B11[i, j]
        b0, b1, b2 = B11[i, 0], B11[i, 1], B11[i, 2]
        # row i of B11 ρ̃: (b1 r2 - b2 r1, b2 r0 - b0 r2, b0 r1 - b1 r0)
        X[i, 0] = B12[i, 0] - (b1 * r2 - b2 * r1)
        X[i, 1] = B12[i, 1] - (b2 * r0 - b0 * r2)
        X[i, 2] = B12[i, 2] - (b0 * r1 - b1 * r0)
        for j in range(3):
            out[i, 3 + j] += X[i, j]
            out[3 + j, i] += X[i, j]
    # bottom-right: ρ̃B11ρ̃' + ρ̃B12 + B21ρ̃' + B22 = B22 + X + X' - ρ̃B11ρ̃ with
    # X = ρ̃B12 (ρ̃' = -ρ̃; B21ρ̃' = X'); ρ̃B11ρ̃ from T = ρ̃B11
    for j in range(3):              # T = ρ̃ B11 (rows: ρ x column), reuse T
        c0, c1, c2 = B11[0, j], B11[1, j], B11[2, j]
        T[0, j] = r1 * c2 - r2 * c1
        T[1, j] = r2 * c0 - r0 * c2
        T[2, j] = r0 * c1 - r1 * c0
    for j in range(3):              # X = ρ̃ B12
        c0, c1, c2 = B12[0, j], B12[1, j], B12[2, j]
        X[0, j] = r1 * c2 - r2 * c1
        X[1, j] = r2 * c0 - r0 * c2
        X[2, j] = r0 * c1 - r1 * c0
    for i in range(3):
        t0, t1, t2 = T[i, 0], T[i, 1], T[i, 2]
        # row i of (ρ̃B11) ρ̃ : (t1 r2 - t2 r1, t2 r0 - t0 r2, t0 r1 - t1 r0)
        z = (t1 * r2 - t2 * r1, t2 * r0 - t0 * r2, t0 * r1 - t1 * r0)
        for j in range(i, 3):
            v = B22[i, j] + X[i, j] + X[j, i] - z[j]
            out[3 + i, 3 + j] += v
            if j != i:
                out[3 + j, 3 + i] += v


@njit(cache=_CACHE)
def momentum_factor(parent, Rrel, rho, H, nvj, M, ldlt):
    """Factor the momentum form's system (6), leaves to root, independently of p: the
    articulated inertias Ī_i = M_i + Σ_c C_c'Â_cC_c, the joint blocks
    D_i = H_i'Ī_iH_i and what the solve needs of them.  ``ldlt`` False: the
    sweep (explicit D_i⁻¹, full 6 x 6 updates); True: the LDL' variant
    (Cholesky factor of D_i, triangular solves, symmetric updates).  Returns
    (Kmat, Lfac, Dinv, U, ok): per joint, Kmat = D⁻¹H'Ī (sweep) or W = L⁻¹U'
    (ldlt), Lfac = L (ldlt), Dinv = D⁻¹ and U = Ī H (sweep; each array has
    one dummy block for the variant that does not use it); ok=False when a
    joint block is not positive definite.  No allocation inside the loop."""
    nb = parent.size
    Ibar = M.copy()
    Kmat = np.zeros((nb, 6, 6))
    # each variant keeps only what its solve reads (the other's arrays are stubs)
    Lfac = np.zeros((nb if ldlt else 1, 6, 6))
    Dinv = np.zeros((1 if ldlt else nb, 6, 6))
    Us = np.zeros((1 if ldlt else nb, 6, 6))
    Ubuf = np.empty((6, 6))
    D = np.empty((6, 6))
    Ah = np.empty((6, 6))
    B = np.empty((6, 6))
    col = np.empty(6)
    row = np.empty(6)
    T3 = np.empty((3, 3))
    B11 = np.empty((3, 3))
    B12 = np.empty((3, 3))
    B22 = np.empty((3, 3))
    X3 = np.empty((3, 3))
    for i in range(nb - 1, 0, -1):
        n = nvj[i]
        Hi = H[i]
        Ii = Ibar[i]
        U = Ubuf if ldlt else Us[i]
        for a in range(6):                       # U = Ī H
            for k in range(n):
                s = 0.0
                for b in range(6):
                    s += Ii[a, b] * Hi[b, k]
                U[a, k] = s
        for k in range(n):                       # D = H'U
            for l in range(n):
                s = 0.0
                for b in range(6):
                    s += Hi[b, k] * U[b, l]
                D[k, l] = s
        if ldlt:
            L = Lfac[i]
            for j in range(n):                   # Cholesky D = L L'
                s = D[j, j]
                for k in range(j):
                    s -= L[j, k] * L[j, k]
                if not s > 0.0:
                    return Kmat, Lfac, Dinv, Us, False
                L[j, j] = np.sqrt(s)
                for a in range(j + 1, n):
                    t = D[a, j]
                    for k in range(j):
                        t -= L[a, k] * L[j, k]
                    L[a, j] = t / L[j, j]
            W = Kmat[i]
            for c in range(6):                   # W = L⁻¹U'
                for a in range(n):
                    s = U[c, a]
                    for k in range(a):
                        s -= L[a, k] * W[k, c]
                    W[a, c] = s / L[a, a]
            for a in range(6):                   # Â = Ī - W'W (upper triangle)
                for b in range(a, 6):
                    s = Ii[a, b]
                    for k in range(n):
                        s -= W[k, a] * W[k, b]
                    Ah[a, b] = s
                    Ah[b, a] = s
        else:
            Di = Dinv[i]
            for a in range(n):                   # explicit inverse (Gauss-Jordan, partial pivoting)
                for b in range(n):
                    B[a, b] = D[a, b]
                    Di[a, b] = 1.0 if a == b else 0.0
            for c in range(n):
                piv = c
                for a in range(c + 1, n):
                    if abs(B[a, c]) > abs(B[piv, c]):
                        piv = a
                if B[piv, c] == 0.0:
                    return Kmat, Lfac, Dinv, Us, False
                if piv != c:
                    for k in range(n):
                        B[c, k], B[piv, k] = B[piv, k], B[c, k]
                        Di[c, k], Di[piv, k] = Di[piv, k], Di[c, k]
                d = B[c, c]
                for k in range(n):
                    B[c, k] /= d
                    Di[c, k] /= d
                for a in range(n):
                    if a != c and B[a, c] != 0.0:
                        f = B[a, c]
                        for k in range(n):
                            B[a, k] -= f * B[c, k]
                            Di[a, k] -= f * Di[c, k]
            # K = D⁻¹H'Ī (the row factor of the elimination; D⁻¹U' would be
            # the same in exact arithmetic, but mixing Ī and Ī' lets the
            # rounding asymmetry of Ī grow along a chain)
            for k in range(n):
                for c in range(6):
                    s = 0.0
                    for b in range(6):
                        s += Hi[b, k] * Ii[b, c]
                    B[k, c] = s
            Km = Kmat[i]
            for a in range(n):
                for c in range(6):
                    s = 0.0
                    for k in range(n):
                        s += Di[a, k] * B[k, c]
                    Km[a, c] = s
            for a in range(6):                   # Â = Ī - U K (full)
                for b in range(6):
                    s = Ii[a, b]
                    for k in range(n):
                        s -= U[a, k] * Km[k, b]
                    Ah[a, b] = s
        par = parent[i]
        if par > 0:
            if ldlt:
                _congruence_sym_add(Rrel[i], rho[i], Ah, T3, B11, B12, B22, X3, Ibar[par])
            else:
                _congruence_add(Rrel[i], rho[i], Ah, False, B, col, row, Ibar[par])
    return Kmat, Lfac, Dinv, Us, True


@njit(cache=_CACHE)
def momentum_apply(parent, Rrel, rho, H, nvj, iv, M, Kmat, Lfac, Dinv, Us, p, V0, ldlt):
    """Solve (6) for ν, V and the subtree momenta μ with the factors of
    :func:`momentum_factor`, given generalized momenta p:

        M V - S'μ = 0,   S V - H ν = (C_i V0 for the base's children),   H'μ = p.

    Leaves to root, μ_i = Â_i C_i V_parent + β_i with β_i = c̄_i + Ī_iH_iD_i⁻¹
    (p_i - H_i'c̄_i), c̄ the transported β of the children; root to leaves,
    ν_i = D_i⁻¹(p_i - H_i'c̄_i - H_i'Ī_iC_iV_parent) and V_i by (1).  O(N) per
    right-hand side."""
    nb = parent.size
    cbar = np.zeros((nb, 6))
    rhs = np.zeros((nb, 6))        # sweep: D⁻¹(p - H'c̄)  | ldlt: L⁻¹(p - H'c̄)
    r = np.empty(6)
    beta = np.empty(6)
    for i in range(nb - 1, 0, -1):
        n = nvj[i]
        Hi = H[i]
        for k in range(n):                       # r = p - H'c̄
            s = p[iv[i] + k]
            for b in range(6):
                s -= Hi[b, k] * cbar[i, b]
            r[k] = s
        y = rhs[i]
        if ldlt:
            L = Lfac[i]
            W = Kmat[i]
            for a in range(n):                   # y = L⁻¹r
                s = r[a]
                for k in range(a):
                    s -= L[a, k] * y[k]
                y[a] = s / L[a, a]
            for a in range(6):                   # β = c̄ + W'y
                s = cbar[i, a]
                for k in range(n):
                    s += W[k, a] * y[k]
                beta[a] = s
        else:
            Di = Dinv[i]
            U = Us[i]
            for a in range(n):                   # y = D⁻¹r
                s = 0.0
                for k in range(n):
                    s += Di[a, k] * r[k]
                y[a] = s
            for a in range(6):                   # β = c̄ + U y
                s = cbar[i, a]
                for k in range(n):
                    s += U[a, k] * y[k]
                beta[a] = s
        par = parent[i]
        if par > 0:
            _ct_add(Rrel[i], rho[i], beta, cbar[par])
    nu = np.zeros(p.size)
    V = np.zeros((nb, 6))
    V[0] = V0
    Vp = np.empty(6)
    x = np.empty(6)
    for i in range(1, nb):
        n = nvj[i]
        _c_to(Rrel[i], rho[i], V[parent[i]], Vp)
        Km = Kmat[i]
        for a in range(n):
            s = rhs[i, a]
            for c in range(6):
                s -= Km[a, c] * Vp[c]
            x[a] = s
        if ldlt:                                 # ν = L⁻ᵀ(y - W Vp)
            L = Lfac[i]
            for a in range(n - 1, -1, -1):
                s = x[a]
                for k in range(a + 1, n):
                    s -= L[k, a] * x[k]
                x[a] = s / L[a, a]
        for c in range(6):
            V[i, c] = Vp[c]
        for k in range(n):
            nu[iv[i] + k] = x[k]
            for c in range(6):
                V[i, c] += H[i, c, k] * x[k]
    return nu, V, subtree(parent, Rrel, rho, M, V)


@njit(cache=_CACHE)
def subtree(parent, Rrel, rho, M, V):
    """Subtree momenta μ_i = M_iV_i + Σ_children C_c'μ_c (leaves to root)."""
    nb = parent.size
    mu = np.zeros((nb, 6))
    for i in range(nb - 1, 0, -1):
        for a in range(6):
            s = 0.0
            for b in range(6):
                s += M[i, a, b] * V[i, b]
            mu[i, a] += s
        par = parent[i]
        if par > 0:
            _ct_add(Rrel[i], rho[i], mu[i], mu[par])
    return mu


@njit(cache=_CACHE)
def project(H, nvj, iv, mu, nv):
    """p_i = H_i'μ_i."""
    p = np.zeros(nv)
    for i in range(1, nvj.size):
        for k in range(nvj[i]):
            p[iv[i] + k] = H[i][:, k] @ mu[i]
    return p


@njit(cache=_CACHE)
def momenta(parent, Rrel, rho, H, nvj, iv, M, nu, V0):
    """Generalized momenta p_i = H_i'μ_i from velocities (O(N))."""
    V = velocities(parent, Rrel, rho, H, nvj, iv, nu, V0)
    return project(H, nvj, iv, subtree(parent, Rrel, rho, M, V), nu.size)


@njit(cache=_CACHE)
def momentum_rate(parent, Rrel, rho, H, Hd, nvj, iv, V, mu, fapp, tau):
    """ṗ_i = Ḣ_i'μ_i + H_i'(F_i - V_i x* μ_i) + τ_i, F_i the applied forces on
    the subtree of i about O_i (the rate of the subtree momentum is the
    external force; the joint reaction's H_i' projection is the joint force τ_i).
    No allocation inside the loop."""
    nb = parent.size
    F = fapp.copy()
    pd = tau.copy()
    g = np.empty(6)
    for i in range(nb - 1, 0, -1):
        w0, w1, w2 = V[i, 3], V[i, 4], V[i, 5]
        v0, v1, v2 = V[i, 0], V[i, 1], V[i, 2]
        L0, L1, L2 = mu[i, 0], mu[i, 1], mu[i, 2]
        N0, N1, N2 = mu[i, 3], mu[i, 4], mu[i, 5]
        # g = F - V x* μ,  V x* μ = (ω x L, v x L + ω x N)
        g[0] = F[i, 0] - (w1 * L2 - w2 * L1)
        g[1] = F[i, 1] - (w2 * L0 - w0 * L2)
        g[2] = F[i, 2] - (w0 * L1 - w1 * L0)
        g[3] = F[i, 3] - (v1 * L2 - v2 * L1 + w1 * N2 - w2 * N1)
        g[4] = F[i, 4] - (v2 * L0 - v0 * L2 + w2 * N0 - w0 * N2)
        g[5] = F[i, 5] - (v0 * L1 - v1 * L0 + w0 * N1 - w1 * N0)
        for k in range(nvj[i]):
            s = 0.0
            for c in range(6):
                s += Hd[i, c, k] * mu[i, c] + H[i, c, k] * g[c]
            pd[iv[i] + k] += s
        par = parent[i]
        if par > 0:
            _ct_add(Rrel[i], rho[i], F[i], F[par])
    return pd


@njit(cache=_CACHE)
def qdot(jtype, iq, iv, nqj, q, nu):
    """Configuration rates q̇ = K(q) ν (quaternions: q̇ = ½ q ⊗ (ω, 0))."""
    nb = jtype.size
    out = np.zeros(q.size)
    for i in range(1, nb):
        a, b = iq[i], iv[i]
        jt = jtype[i]
        if jt == SPHERICAL or jt == FREE:
            o = 0
            if jt == FREE:      # position rate: R_J ν_lin
                out[a:a + 3] = quat_rotation(q[a + 3], q[a + 4], q[a + 5], q[a + 6]) @ nu[b:b + 3]
                o = 3
            x, y, z, w = q[a + o], q[a + o + 1], q[a + o + 2], q[a + o + 3]
            wx, wy, wz = nu[b + o], nu[b + o + 1], nu[b + o + 2]
            out[a + o] = 0.5 * (w * wx + y * wz - z * wy)
            out[a + o + 1] = 0.5 * (w * wy + z * wx - x * wz)
            out[a + o + 2] = 0.5 * (w * wz + x * wy - y * wx)
            out[a + o + 3] = 0.5 * (-x * wx - y * wy - z * wz)
        else:
            for k in range(nqj[i]):
                out[a + k] = nu[b + k]
    return out


@njit(cache=_CACHE)
def point_jacobians(parent, Rabs, rabs, H, Hd, nvj, iv, V, body, x, nv):
    """World-frame Jacobian J (3 x nv) of the world point x fixed to ``body``
    and J̇ (along the current motion): column of joint k on the path,
    l + a x (x - o_k) with l, a = R_k H_k's linear and angular parts."""
    J = np.zeros((3, nv))
    Jd = np.zeros((3, nv))
    # velocity of the point
    Rb = Rabs[body]
    xd = Rb @ V[body][:3] + _cross(Rb @ V[body][3:], x - rabs[body])
    k = body
    while k > 0:
        Rk = Rabs[k]
        wk = V[k][3:]
        ok_dot = Rk @ V[k][:3]
        rel = x - rabs[k]
        for c in range(nvj[k]):
            hl = H[k][:3, c]
            ha = H[k][3:, c]
            lw = Rk @ hl
            aw = Rk @ ha
            J[:, iv[k] + c] = lw + _cross(aw, rel)
            ld = Rk @ (_cross(wk, hl) + Hd[k][:3, c])
            ad = Rk @ (_cross(wk, ha) + Hd[k][3:, c])
            Jd[:, iv[k] + c] = ld + _cross(ad, rel) + _cross(aw, xd - ok_dot)
        k = parent[k]
    return J, Jd
