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
from numba import njit
from numba.core.errors import NumbaPerformanceWarning

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
def _axis_rotation(a, angle):
    """Rodrigues: rotation by ``angle`` about the unit axis a."""
    c, s = np.cos(angle), np.sin(angle)
    t = 1.0 - c
    R = np.empty((3, 3))
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
    return R


@njit(cache=_CACHE)
def _quat_rotation(qx, qy, qz, qw):
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
def _c_apply(R, rho, V):
    """C V: parent-frame velocity -> child frame."""
    w = V[3:]
    v = V[:3] + _cross(w, rho)
    out = np.empty(6)
    out[:3] = R.T @ v
    out[3:] = R.T @ w
    return out


@njit(cache=_CACHE)
def _ct_apply(R, rho, f):
    """C' f: child-frame force -> parent frame (moment moved to the parent origin)."""
    F = R @ f[:3]
    out = np.empty(6)
    out[:3] = F
    out[3:] = R @ f[3:] + _cross(rho, F)
    return out


@njit(cache=_CACHE)
def _congruence(R, rho, A, sym):
    """C' A C for a 6 x 6 A.  ``sym``: A is symmetric, compute the upper
    triangle and mirror it (the LDL' variant); otherwise the full product (the
    sweep, which as an LU elimination does not use symmetry)."""
    # B = C'A column by column, then B C row by row (C' applied twice via _ct_apply).
    B = np.empty((6, 6))
    for j in range(6):
        B[:, j] = _ct_apply(R, rho, A[:, j])
    out = np.empty((6, 6))
    if sym:
        for i in range(6):
            row = _ct_apply(R, rho, B[i, :])
            for j in range(i, 6):
                out[i, j] = row[j]
                out[j, i] = row[j]
    else:
        for i in range(6):
            out[i, :] = _ct_apply(R, rho, B[i, :])
    return out


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
def _chol_small(D, n):
    L = np.zeros((n, n))
    for j in range(n):
        s = D[j, j]
        for k in range(j):
            s -= L[j, k] * L[j, k]
        if not s > 0.0:
            return L, False
        L[j, j] = np.sqrt(s)
        for i in range(j + 1, n):
            t = D[i, j]
            for k in range(j):
                t -= L[i, k] * L[j, k]
            L[i, j] = t / L[j, j]
    return L, True


@njit(cache=_CACHE)
def _inv_small(D, n):
    """Gauss-Jordan inverse with partial pivoting (the sweep's explicit D⁻¹)."""
    A = D[:n, :n].copy()
    X = np.eye(n)
    for c in range(n):
        p = c
        for r in range(c + 1, n):
            if abs(A[r, c]) > abs(A[p, c]):
                p = r
        if A[p, c] == 0.0:
            return X, False
        if p != c:
            for k in range(n):
                A[c, k], A[p, k] = A[p, k], A[c, k]
                X[c, k], X[p, k] = X[p, k], X[c, k]
        piv = A[c, c]
        for k in range(n):
            A[c, k] /= piv
            X[c, k] /= piv
        for r in range(n):
            if r != c and A[r, c] != 0.0:
                f = A[r, c]
                for k in range(n):
                    A[r, k] -= f * A[c, k]
                    X[r, k] -= f * X[c, k]
    return X, True


@njit(cache=_CACHE)
def _forward_sub(L, b, n):
    x = np.empty(n)
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= L[i, k] * x[k]
        x[i] = s / L[i, i]
    return x


@njit(cache=_CACHE)
def _backward_sub_t(L, b, n):
    """Solve L' x = b."""
    x = np.empty(n)
    for i in range(n - 1, -1, -1):
        s = b[i]
        for k in range(i + 1, n):
            s -= L[k, i] * x[k]
        x[i] = s / L[i, i]
    return x


# -- joints ----------------------------------------------------------------------------------

@njit(cache=_CACHE)
def _joint(jt, ax, fixed, mask, q, iq, nu, iv, want_hdot):
    """Joint transform R_J, p_J (child frame in the joint frame), motion
    subspace H (child frame, padded 6 x 6), its time derivative Ḣ along ν
    (only when ``want_hdot``) and the number of velocity columns."""
    R = np.eye(3)
    p = np.zeros(3)
    H = np.zeros((6, 6))
    Hd = np.zeros((6, 6))
    n = 0
    if jt == REVOLUTE:
        R = _axis_rotation(ax[0], q[iq])
        H[3:, 0] = ax[0]
        n = 1
    elif jt == PRISMATIC:
        p = ax[0] * q[iq]
        H[:3, 0] = ax[0]
        n = 1
    elif jt == CARDAN:
        R1 = _axis_rotation(ax[0], q[iq])
        R2 = _axis_rotation(ax[1], q[iq + 1])
        R = R1 @ R2
        e1 = R2.T @ ax[0]
        H[3:, 0] = e1
        H[3:, 1] = ax[1]
        if want_hdot:
            Hd[3:, 0] = -nu[iv + 1] * _cross(ax[1], e1)
        n = 2
    elif jt == SPHERICAL:
        R = _quat_rotation(q[iq], q[iq + 1], q[iq + 2], q[iq + 3])
        for k in range(3):
            H[3 + k, k] = 1.0
        n = 3
    elif jt == FREE:
        p = q[iq:iq + 3].copy()
        R = _quat_rotation(q[iq + 3], q[iq + 4], q[iq + 5], q[iq + 6])
        for k in range(6):
            H[k, k] = 1.0
        n = 6
    elif jt == PLANAR:
        # translation (x, y) in the joint frame, then rotation θ about z; the
        # axes not in ``mask`` stay at their ``fixed`` values
        xyt = fixed.copy()
        k = 0
        for a in range(3):
            if mask[a]:
                xyt[a] = q[iq + k]
                k += 1
        R = _axis_rotation(np.array([0.0, 0.0, 1.0]), xyt[2])
        p[0] = xyt[0]
        p[1] = xyt[1]
        thd = 0.0
        if mask[2] and want_hdot:
            thd = nu[iv + k - 1]
        col = 0
        for a in range(3):
            if mask[a]:
                if a < 2:
                    e = R[a, :].copy()   # R' e_a
                    H[:3, col] = e
                    if want_hdot:
                        Hd[:3, col] = -thd * _cross(np.array([0.0, 0.0, 1.0]), e)
                else:
                    H[5, col] = 1.0
                col += 1
        n = col
    return R, p, H, Hd, n


@njit(cache=_CACHE)
def relative(parent, jtype, axes, fixed, mask, R0, r0, iq, iv, q, nu, want_hdot):
    """Relative placements (R_i, ρ_i in the parent frame) and H_i, Ḣ_i of every joint."""
    nb = parent.size
    Rrel = np.empty((nb, 3, 3))
    rho = np.zeros((nb, 3))
    H = np.zeros((nb, 6, 6))
    Hd = np.zeros((nb, 6, 6))
    Rrel[0] = np.eye(3)
    for i in range(1, nb):
        RJ, pJ, Hi, Hdi, _ = _joint(jtype[i], axes[i], fixed[i], mask[i], q, iq[i], nu, iv[i],
                                    want_hdot)
        Rrel[i] = R0[i] @ RJ
        rho[i] = r0[i] + R0[i] @ pJ
        H[i] = Hi
        Hd[i] = Hdi
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
        Ra[i] = Ra[p] @ Rrel[i]
        ra[i] = ra[p] + Ra[p] @ rho[i]
    return Ra, ra


@njit(cache=_CACHE)
def velocities(parent, Rrel, rho, H, nvj, iv, nu, V0):
    nb = parent.size
    V = np.zeros((nb, 6))
    V[0] = V0
    for i in range(1, nb):
        Vi = _c_apply(Rrel[i], rho[i], V[parent[i]])
        for k in range(nvj[i]):
            Vi += H[i][:, k] * nu[iv[i] + k]
        V[i] = Vi
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
    for i in range(1, nb):
        p = parent[i]
        Vi = _c_apply(Rrel[i], rho[i], V[p])
        Ai = _c_apply(Rrel[i], rho[i], A[p])
        rel = np.zeros(6)
        for k in range(nvj[i]):
            rel += H[i][:, k] * nu[iv[i] + k]
            Ai += H[i][:, k] * nud[iv[i] + k] + Hd[i][:, k] * nu[iv[i] + k]
        Vi += rel
        Ai += _cross_motion(Vi, rel)
        V[i] = Vi
        A[i] = Ai
        h = M[i] @ Vi
        f[i] = M[i] @ Ai + _cross_force(Vi, h) - fext[i]
    tau = np.zeros(nu.size)
    for i in range(nb - 1, 0, -1):
        for k in range(nvj[i]):
            tau[iv[i] + k] = H[i][:, k] @ f[i]
        p = parent[i]
        if p > 0:
            f[p] += _ct_apply(Rrel[i], rho[i], f[i])
    return tau


@njit(cache=_CACHE)
def crba(parent, Rrel, rho, H, nvj, iv, M, nv):
    """Composite-rigid-body mass matrix G(q) (dense, nv x nv)."""
    nb = parent.size
    Ic = M.copy()
    for i in range(nb - 1, 0, -1):
        p = parent[i]
        if p > 0:
            Ic[p] += _congruence(Rrel[i], rho[i], Ic[i], True)
    G = np.zeros((nv, nv))
    for i in range(1, nb):
        n = nvj[i]
        F = Ic[i] @ H[i][:, :n]
        G[iv[i]:iv[i] + n, iv[i]:iv[i] + n] = H[i][:, :n].T @ F
        j = i
        while parent[j] > 0:
            Fn = np.empty((6, n))
            for k in range(n):
                Fn[:, k] = _ct_apply(Rrel[j], rho[j], F[:, k])
            F = Fn
            j = parent[j]
            m = nvj[j]
            blk = H[j][:, :m].T @ F
            G[iv[j]:iv[j] + m, iv[i]:iv[i] + n] = blk
            G[iv[i]:iv[i] + n, iv[j]:iv[j] + m] = blk.T
    return G


# -- dynamics, momentum form (P4) -------------------------------------------------------------

@njit(cache=_CACHE)
def momentum_solve(parent, Rrel, rho, H, nvj, iv, M, p, V0, ldlt):
    """Solve the block-tridiagonal system (6) of P4 for the joint velocities ν,
    body velocities V and subtree momenta μ, given generalized momenta p:

        M V - S'μ = 0,   S V - H ν = (C_i V0 for the base's children),   H'μ = p.

    Leaves to root: μ_i = Â_i C_i V_parent + β_i (articulated momenta); root
    to leaves: ν_i, V_i, μ_i.  ``ldlt`` False: the sweep (explicit D_i⁻¹, full
    6 x 6 updates); True: the LDL' variant (Cholesky factor of each joint block
    D_i = H_i'Ī_iH_i, triangular solves, symmetric updates).  Returns ok=False
    when a joint block is not positive definite."""
    nb = parent.size
    Ibar = M.copy()
    cbar = np.zeros((nb, 6))
    # per joint: what the root-to-leaves pass needs
    Kmat = np.zeros((nb, 6, 6))    # sweep: D⁻¹U' (n x 6)   | ldlt: W = L⁻¹U' (n x 6)
    Lfac = np.zeros((nb, 6, 6))    # ldlt: Cholesky factor of D
    rhs = np.zeros((nb, 6))        # sweep: D⁻¹(p - H'ĉ)  | ldlt: L⁻¹(p - H'ĉ)
    for i in range(nb - 1, 0, -1):
        n = nvj[i]
        Hi = H[i][:, :n]
        U = Ibar[i] @ Hi                    # 6 x n
        D = Hi.T @ U
        r = np.empty(n)
        for k in range(n):
            r[k] = p[iv[i] + k] - Hi[:, k] @ cbar[i]
        if ldlt:
            L, ok = _chol_small(D, n)
            if not ok:
                return np.zeros(p.size), np.zeros((nb, 6)), np.zeros((nb, 6)), False
            W = np.empty((n, 6))
            for c in range(6):
                W[:, c] = _forward_sub(L, U[c, :], n)
            y = _forward_sub(L, r, n)
            Ahat = Ibar[i].copy()
            for a in range(6):
                for b in range(a, 6):
                    s = 0.0
                    for k in range(n):
                        s += W[k, a] * W[k, b]
                    Ahat[a, b] -= s
                    Ahat[b, a] = Ahat[a, b]
            beta = cbar[i] + W.T @ y
            Kmat[i][:n, :] = W
            Lfac[i][:n, :n] = L
            rhs[i][:n] = y
        else:
            Dinv, ok = _inv_small(D, n)
            if not ok:
                return np.zeros(p.size), np.zeros((nb, 6)), np.zeros((nb, 6)), False
            K = Dinv @ U.T                  # n x 6
            Ahat = Ibar[i] - U @ K
            y = Dinv @ r
            beta = cbar[i] + U @ y
            Kmat[i][:n, :] = K
            rhs[i][:n] = y
        par = parent[i]
        if par > 0:
            Ibar[par] += _congruence(Rrel[i], rho[i], Ahat, ldlt)
            cbar[par] += _ct_apply(Rrel[i], rho[i], beta)
    nu = np.zeros(p.size)
    V = np.zeros((nb, 6))
    V[0] = V0
    for i in range(1, nb):
        n = nvj[i]
        Vp = _c_apply(Rrel[i], rho[i], V[parent[i]])
        if ldlt:
            # ν = L⁻ᵀ(y - W Vp)
            t = rhs[i][:n] - Kmat[i][:n, :] @ Vp
            x = _backward_sub_t(Lfac[i], t, n)
        else:
            x = rhs[i][:n] - Kmat[i][:n, :] @ Vp
        Vi = Vp.copy()
        for k in range(n):
            nu[iv[i] + k] = x[k]
            Vi += H[i][:, k] * x[k]
        V[i] = Vi
    return nu, V, subtree(parent, Rrel, rho, M, V), True


@njit(cache=_CACHE)
def subtree(parent, Rrel, rho, M, V):
    """Subtree momenta μ_i = M_iV_i + Σ_children C_c'μ_c (leaves to root)."""
    nb = parent.size
    mu = np.zeros((nb, 6))
    for i in range(nb - 1, 0, -1):
        mu[i] += M[i] @ V[i]
        par = parent[i]
        if par > 0:
            mu[par] += _ct_apply(Rrel[i], rho[i], mu[i])
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
    external force; the joint reaction's H_i' projection is the joint force τ_i)."""
    nb = parent.size
    F = fapp.copy()
    pd = tau.copy()
    for i in range(nb - 1, 0, -1):
        g = F[i] - _cross_force(V[i], mu[i])
        for k in range(nvj[i]):
            pd[iv[i] + k] += Hd[i][:, k] @ mu[i] + H[i][:, k] @ g
        par = parent[i]
        if par > 0:
            F[par] += _ct_apply(Rrel[i], rho[i], F[i])
    return pd


@njit(cache=_CACHE)
def qdot(jtype, iq, iv, nqj, q, nu, Rrel_J):
    """Configuration rates q̇ = K(q) ν (quaternions: q̇ = ½ q ⊗ (ω, 0))."""
    nb = jtype.size
    out = np.zeros(q.size)
    for i in range(1, nb):
        a, b = iq[i], iv[i]
        jt = jtype[i]
        if jt == SPHERICAL or jt == FREE:
            o = 0
            if jt == FREE:
                out[a:a + 3] = Rrel_J[i] @ nu[b:b + 3]
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
