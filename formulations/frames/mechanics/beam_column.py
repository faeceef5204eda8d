"""The beam-column between a member's ends — Euler–Bernoulli, or
shear-flexible (Engesser's, below) —: its member loads' fixed-end forces
and the solution along it, under the constant axial force N that built
its second-order stiffness (:mod:`.second_order`).

The mechanics.  A straight member of flexible length L [L], bending
stiffness EI [F·L²] and axial force N [F] (tension positive), loaded across
its axis by q(x) [F/L] (member axes: x from end i, y its normal turned
counterclockwise), deflects by v(x) [L] with, equilibrium written on the
deformed axis (the section moment is the first-order statics' plus
N (v(x) − v(0)), so its second derivative adds N v''),

    EI v'''' − N v'' = q(x).

With μ = N/EI [1/L²] (t = −μ L², compression positive, as the stability
functions') its homogeneous solutions are 1, x, φ₂(x), φ₃(x) with

    φ_n(x) = Σ_j μ^j x^(n+2j) / (n+2j)!        [L^n],

entire in μ — one series for tension and compression: (1 − cos kx)/k²,
(kx − sin kx)/k³ in compression (k² = −μ), (cosh kx − 1)/k², … in
tension, x²/2, x³/6 at N = 0; φ_n' = φ_(n−1) and φ_n'' = μ φ_n +
x^(n−2)/(n−2)!.  A unit force at a makes the jump in EI v''' of 1: its
particular solution is g(x − a)/EI, g(r) = φ₃(r) for r > 0 and 0 before
(a counterclockwise couple C at a: −C g'(x − a)/EI, the moment diagram's
jump −C; a distributed load ∫ q(s) g(x − s) ds/EI).

Near N = 0 the closed forms cancel (their numerators are x^n/n! to
leading order), so φ₀ … φ₃ come from their series where |μ x²| ≤ 1 and
from closed forms written without cancellation beyond (2 sin²(kx/2)/k² for
φ₂; φ₃'s (kx − sin kx)/k³ loses at most a factor 6 there).  In strong
tension (t < −T_EXP) cosh and sinh grow like e^(kL) while v stays of the
size of the load's: the solution there is written in e^(−kx) and
e^(−k(L−x)) (each end's boundary layer) and the free beam's Green's
function g(r) = −(e^(−k|r|) + k|r|)/(2k³), bounded by |r|/(2k²).

Fixed-end forces.  The operator is self-adjoint (its energy ∫ EI v''² +
N v'² is symmetric), so by Betti's theorem the clamped member's end
forces under a unit force at a are its exact shape functions ψ_k(a) —
the solutions of the homogeneous equation with unit end displacement k
(v_i, θ_i, v_j, θ_j) and the others zero; under a couple C, C ψ_k'(a);
under q, ∫ q ψ_k.  These are the member's consistent nodal loads with
the element's own (exact) shape functions, as the Hermite cubics' are at
N = 0; the integrals by Gauss–Legendre rules of GAUSS points on pieces
with k h ≤ 2π, exact to rounding (the rule's error there is below 1e-18
of the integrand; exact for the cubics at N = 0).  The transverse end
forces are across the undeformed axis, as the stability-function
stiffness's (its end shear EI v''' − N v').

Along the member.  v(x) = Σ ψ_k(x) u_k + the clamped member's deflection
under its loads (a particular solution less its end values and slopes
carried by the ψ_k); the section moment M(x) = M₁(x) + N (v(x) − v(0))
(M₁ the first-order statics from end i, in the diagrams' convention,
sagging positive), and the diagrams' V = dM/dx = V₁(x) + N v'(x): the
shear across the deformed axis, which at end i differs from the end
action across the undeformed one by N θ_i.

Shear deformation (Engesser's, :mod:`.second_order`; c = 1/(G A_s)
[1/F], D = 1 + c N [-], Engesser's β).  The section turns by θ, the axis
slopes by v' = (θ − c S)/D, S = M' − N v' [F] the force across the
undeformed axis (S' = q) and M = EI θ' (:mod:`.varying_pieces`, N'
= 0); in v, EI D v'''' − N v'' = q − EI c q''.  So the homogeneous
solutions are the Euler–Bernoulli ones at μ = N/(EI D) (k² = −μ: kL = π
at Engesser's P_E/(1 + P_E/(G A_s))), each with its own θ = D v' + c S:
1 and x turn by 0 and 1 (a rigid turn, S = −N on x), φ₂ by D φ₁ (S = 0),
φ₃ by D (φ₂ + c EI) (S = EI D); e^(−kx), e^(−k(L−x)) by D v' (S = 0).
The operator stays self-adjoint (the energy ∫ EI θ'² + G A_s (v' − θ)² +
N v'²), so Betti's theorem gives the fixed-end forces as before, a
couple's on the sections' rotations ψ_θ (the slopes' without shear).  A
unit force at a jumps S by 1 and so v' by −c/D: its particular solution
is (g(r)/EI − c g''(r))/D, g the Euler–Bernoulli one at μ (φ₃(r) for
r > 0, or the free beam's in strong tension); a couple C jumps M by −C:
−C g'(r)/(EI D).  The particular solution's end rotations are D v' +
c S, S its loads' sum from zero (in strong tension ±1/2 of each: the
free beam's).  At c = 0 it is the Euler–Bernoulli member bit for bit
(D = 1, the shear terms zero).  The chain of :mod:`.varying_axial` under
a constant N gives the same to ~1e-12, at ~15 × the cost in a frame's
solve and α_cr (docs/dev-notes.md).
"""

from __future__ import annotations

import math

import numpy as np

from .end_releases import released_ends
from .second_order import stability_functions

#: −t beyond which (tension) the solution is written in each end's
#: boundary layer e^(−kx), e^(−k(L−x)) (below it cosh kL ≤ 3.8: the φ
#: basis loses at most that factor)
T_EXP = 4.0

#: |μ x²| up to which φ₀ … φ₃ come from their series
SERIES = 1.0

#: terms of the series (at |μ x²| ≤ SERIES the last one is 1e-19 of the first)
TERMS = 10

#: Gauss–Legendre points per piece of a distributed load (pieces k h ≤ 2π)
GAUSS = 12

_T, _W = np.polynomial.legendre.leggauss(GAUSS)
# 1/(n+2j)! for n = 0..3, j < TERMS
_INV_FACT = np.array([[1.0 / math.factorial(n + 2 * j) for j in range(TERMS)] for n in range(4)])


def phis(mu, x) -> np.ndarray:
    """(4, *shape): φ₀ … φ₃ at x (module docstring), μ = N/EI (a number,
    or an array broadcast with x)."""
    x, mu = np.broadcast_arrays(np.asarray(x, float), np.asarray(mu, float))
    z = mu * x * x
    out = np.empty((4,) + x.shape)
    for n in range(4):                              # Horner on the series in z
        acc = np.full(x.shape, _INV_FACT[n, -1])
        for c in _INV_FACT[n, -2::-1]:
            acc = acc * z + c
        out[n] = acc * x ** n
    far = np.abs(z) > SERIES                        # closed forms, no cancellation
    if np.any(far):
        m, xf = mu[far], x[far]
        k = np.sqrt(np.abs(m))
        y = k * xf
        press = m < 0                               # compression: trigonometric
        yt = np.where(press, 0.0, y)                # (tension's, hyperbolic, kept finite)
        sn = np.where(press, np.sin(y), np.sinh(yt))
        half = np.where(press, np.sin(0.5 * y), np.sinh(0.5 * yt))
        out[0][far] = np.where(press, np.cos(y), np.cosh(yt))
        out[1][far] = sn / k
        out[2][far] = 2.0 * half ** 2 / k ** 2
        out[3][far] = np.where(press, y - sn, sn - y) / k ** 3
    return out


def _regime(EI, N, L, c=0.0):
    """(μ, k or 0, D): D = 1 + c N (Engesser's β; 1 without shear, c = 0),
    μ = N/(EI D), k = √μ where the member is in strong tension."""
    D = 1.0 + c * N
    with np.errstate(divide="ignore", invalid="ignore"):     # D = 0: past its own buckling
        mu = np.float64(N) / (EI * D)
    return mu, (math.sqrt(mu) if -mu * L * L < -T_EXP else 0.0), D


def _basis(mu, k, L, x, D=1.0, cEI=0.0):
    """(b, b', b_θ): the homogeneous solutions at x, each scaled to O(1) on
    [0, L] (1, x/L, φ₂/L², φ₃/L³; or 1, x/L, e^(−kx), e^(−k(L−x))), their
    x-derivatives times L, and their sections' rotations times L, θ =
    D v' + c S (module docstring; v' without shear, ``cEI`` = c EI = 0);
    (4, *x.shape) each."""
    x = np.asarray(x, float)
    one, zero = np.ones_like(x), np.zeros_like(x)
    if k:
        e0, e1 = np.exp(-k * x), np.exp(-k * (L - x))
        db = np.array([zero, one, -k * L * e0, k * L * e1])
        return (np.array([one, x / L, e0, e1]), db,
                db if not cEI else np.array([zero, one, D * db[2], D * db[3]]))
    p = phis(mu, x)
    db = np.array([zero, one, p[1] / L, p[2] / L ** 2])
    return (np.array([one, x / L, p[2] / L ** 2, p[3] / L ** 3]), db,
            db if not cEI else np.array([zero, one, D * db[2], D * (p[2] + cEI) / L ** 2]))


def shape_functions(EI, N, L, x, c=0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(ψ, ψ', ψ_θ): the exact shape functions at x (…, 4) for the end dofs
    (v_i, θ_i, v_j, θ_j), their slopes and their sections' rotations (the
    slopes without shear, c = 1/(G A_s) = 0)."""
    mu, k, D = _regime(EI, N, L, c)
    ends = np.array([0.0, L])
    b, _, tb = _basis(mu, k, L, ends, D, c * EI)
    B = np.array([b[:, 0], tb[:, 0], b[:, 1], tb[:, 1]])   # rows: v, L θ at i then j
    C = np.linalg.solve(B, np.eye(4))
    bx, dbx, tbx = _basis(mu, k, L, x, D, c * EI)
    scale = np.array([1.0, L, 1.0, L])                      # L θ → θ
    psi = np.moveaxis(np.tensordot(C.T, bx, axes=1), 0, -1) * scale
    dpsi = np.moveaxis(np.tensordot(C.T, dbx, axes=1), 0, -1) * scale / L
    tpsi = dpsi if not c else np.moveaxis(np.tensordot(C.T, tbx, axes=1), 0, -1) * scale / L
    return psi, dpsi, tpsi


def _green(mu, k, r, order):
    """g (order 0) or its order-th derivative (1 to 3) of the module
    docstring at r [per unit force and EI]; the third jumps at r = 0, where
    it is its right side's (as a diagram's section at a point load is)."""
    r = np.asarray(r, float)
    if k:
        e = np.exp(-k * np.abs(r))
        return (-(e + k * np.abs(r)) / (2 * k ** 3) if order == 0
                else -np.sign(r) * -np.expm1(-k * np.abs(r)) / (2 * k * k) if order == 1
                else -e / (2 * k) if order == 2 else _jump(k, r) * e)
    rp = np.maximum(r, 0.0)
    return np.where(r >= 0 if order == 3 else r > 0, phis(mu, rp)[3 - order], 0.0)


def _jump(k, r):
    """The force across the axis, S, of g at r per unit force: the unit
    step from zero (±1/2 for the free beam's g in strong tension), its
    right side's at r = 0."""
    r = np.asarray(r, float)
    return np.where(r >= 0, 0.5, -0.5) if k else (r >= 0).astype(float)


def _pieces(a, b, k):
    """Gauss points and weights covering [a, b] in pieces with k h ≤ 2π."""
    n = max(1, int(math.ceil(k * (b - a) / (2 * math.pi))))
    e = np.linspace(a, b, n + 1)
    half = 0.5 * np.diff(e)[:, None]
    return (half * _T + 0.5 * (e[1:] + e[:-1])[:, None]).ravel(), (half * _W).ravel()


def across(load, c, s):
    """A member load's parts across the axis, member axes: ("point", a,
    py, mz) or ("distributed", a, b, wy1, wy2)."""
    v = load.values

    def turn(fx, fy):
        return fy if load.axes == "member" else -s * fx + c * fy
    if load.kind == "point":
        return ("point", load.a, turn(v[0], v[1]), v[2])
    return ("distributed", load.a, load.b, turn(v[0], v[1]), turn(v[2], v[3]))


def nodal_loads(parts, EI, N, L, c=0.0) -> np.ndarray:
    """The consistent nodal loads (4: v_i, θ_i, v_j, θ_j, member axes) of
    the loads ``parts`` (:func:`across`, positions on the flexible length
    L) on the beam-column under N (Engesser's with c = 1/(G A_s) > 0):
    minus its clamped ends' forces."""
    _, k, _ = _regime(EI, N, L, c)
    out = np.zeros(4)
    for part in parts:
        if part[0] == "point":
            _, a, py, mz = part
            psi, _, tpsi = shape_functions(EI, N, L, np.array([a]), c)
            out += py * psi[0] + mz * tpsi[0]
            continue
        _, a, b, w1, w2 = part
        if b <= a:
            continue
        xs, ws = _pieces(a, b, k)
        q = w1 + (w2 - w1) * (xs - a) / (b - a)
        psi = shape_functions(EI, N, L, xs, c)[0]
        out += (q * ws) @ psi
    return out


def deflection(parts, EI, N, L, ends, x, c=0.0) -> tuple[np.ndarray, np.ndarray]:
    """(v, v') at x on the flexible length L: the beam-column's deflection
    (Engesser's with c = 1/(G A_s) > 0: v' the axis' slope) with end
    displacements ``ends`` (v_i, θ_i, v_j, θ_j, member axes; θ the
    sections' rotations) under the loads ``parts`` (:func:`across`)."""
    mu, k, D = _regime(EI, N, L, c)
    cEI = c * EI
    x = np.asarray(x, float)
    at = np.r_[x, 0.0, L]            # the particular solution's end values too
    vp, dvp, sp = np.zeros_like(at), np.zeros_like(at), np.zeros_like(at)
    for part in parts:
        if part[0] == "point":
            _, a, py, mz = part
            r = at - a
            if a >= L:
                # a force at the far end: no material beyond it, so the
                # sections at x = L are its left side (the right side's kink
                # −c py/D in v' put N c py/D into V_j)
                r = np.minimum(r, -np.finfo(float).tiny)
            vp += py * _green(mu, k, r, 0) - mz * _green(mu, k, r, 1)
            dvp += py * _green(mu, k, r, 1) - mz * _green(mu, k, r, 2)
            if cEI:
                vp -= py * cEI * _green(mu, k, r, 2)
                dvp -= py * cEI * _green(mu, k, r, 3)
                sp += py * _jump(k, r)
            continue
        _, a, b, w1, w2 = part
        if b <= a:
            continue
        # each section's own two pieces, [a, x] and [x, b], on which g(x − s)
        # is smooth (its third derivative jumps at s = x)
        mid = np.clip(at, a, b)[:, None]
        n = max(1, int(math.ceil(k * (b - a) / (2 * math.pi))))
        edges = np.linspace(0.0, 1.0, n + 1)
        t = ((0.5 * np.diff(edges)[:, None] * (_T + 1.0) + edges[:-1, None]).ravel())[None, :]
        w = (0.5 * np.diff(edges)[:, None] * _W).ravel()[None, :]
        for lo, hi in ((a, mid), (mid, b)):
            xs = lo + (hi - lo) * t
            q = (w1 + (w2 - w1) * (xs - a) / (b - a)) * w * (hi - lo)
            r = at[:, None] - xs
            vp += (_green(mu, k, r, 0) * q).sum(axis=1)
            dvp += (_green(mu, k, r, 1) * q).sum(axis=1)
            if cEI:
                vp -= cEI * (_green(mu, k, r, 2) * q).sum(axis=1)
                dvp -= cEI * (_green(mu, k, r, 3) * q).sum(axis=1)
                sp += (_jump(k, r) * q).sum(axis=1)
    vp, dvp = vp / (EI * D), dvp / (EI * D)
    # the particular solution's end rotations: θ = D v' + c S
    d = np.array([vp[-2], D * dvp[-2] + c * sp[-2], vp[-1], D * dvp[-1] + c * sp[-1]])
    psi, dpsi, _ = shape_functions(EI, N, L, x, c)
    u = np.asarray(ends, float) - d
    return psi @ u + vp[:-2], dpsi @ u + dvp[:-2]


def nodal_loads_many(parts, EI, N, L, c=0.0) -> np.ndarray:
    """:func:`nodal_loads` of many loads at once, (n, 4): ``parts[r]``
    (:func:`across`) on a member of EI[r], N[r], L[r], c[r] (1/(G A_s), 0
    without shear).  Where the member is not in strong tension (kL ≤ 2π:
    one Gauss piece a load) all in one pass, its basis and shape functions
    as arrays; the others one by one."""
    EI, N, L = (np.asarray(v, float) for v in (EI, N, L))
    c = np.broadcast_to(np.asarray(c, float), N.shape)
    out = np.zeros((len(parts), 4))
    D = 1.0 + c * N
    with np.errstate(divide="ignore", invalid="ignore"):     # D = 0: past its own buckling
        mu = N / (EI * D)
    strong = -mu * L * L < -T_EXP
    for r in np.flatnonzero(strong).tolist():
        out[r] = nodal_loads([parts[r]], EI[r], N[r], L[r], c[r])
    rows = np.flatnonzero(~strong)
    if not rows.size:
        return out
    mu, L, D, cEI = mu[rows], L[rows], D[rows], (c * EI)[rows]
    # each load's points and weights: a point force at a (weight py, a
    # couple mz on the slope there), a trapezoid's GAUSS points
    x = np.zeros((rows.size, GAUSS))
    wq = np.zeros((rows.size, GAUSS))
    mz = np.zeros(rows.size)
    for n, r in enumerate(rows.tolist()):
        part = parts[r]
        if part[0] == "point":
            x[n, 0], wq[n, 0], mz[n] = part[1], part[2], part[3]
            continue
        _, a, b, w1, w2 = part
        if b > a:
            half = 0.5 * (b - a)
            x[n] = half * _T + 0.5 * (a + b)
            wq[n] = (w1 + (w2 - w1) * (x[n] - a) / (b - a)) * half * _W
    one, zero = np.ones_like(L), np.zeros_like(L)
    pe = phis(mu, L)
    # rows v, L θ at i then j; columns 1, x/L, φ₂/L², φ₃/L³
    # (L θ = L (D v' + c S): D times the slope's, and c EI D/L² on φ₃/L³)
    B = np.zeros((rows.size, 4, 4))
    B[:, 0, 0] = 1.0
    B[:, 1, 1] = 1.0
    B[:, 1, 3] = D * cEI / L ** 2
    B[:, 2] = np.stack([one, one, pe[2] / L ** 2, pe[3] / L ** 3], axis=1)
    B[:, 3] = np.stack([zero, one, D * pe[1] / L, D * (pe[2] + cEI) / L ** 2], axis=1)
    C = np.linalg.solve(B, np.broadcast_to(np.eye(4), B.shape))
    scale = np.stack([one, L, one, L], axis=1)                        # L θ → θ
    Lc = L[:, None]
    px = phis(mu[:, None], x)
    basis = np.stack([np.ones_like(x), x / Lc, px[2] / Lc ** 2, px[3] / Lc ** 3], axis=1)
    Dc, cc = D[:, None], cEI[:, None]
    turn = np.stack([np.zeros_like(x), np.ones_like(x) / Lc, Dc * px[1] / Lc ** 2,
                     Dc * (px[2] + cc) / Lc ** 3], axis=1)          # θ: a couple's work
    # ψ_k(x_p) = Σ_j C_jk b_j(x_p)
    psi = np.einsum("njk,njp->nkp", C, basis)
    out[rows] = (np.einsum("nkp,np->nk", psi, wq)
                 + mz[:, None] * np.einsum("njk,nj->nk", C, turn[:, :, 0])) * scale
    return out


def into_loads(Fe, items, EI, N, Lf, rows, signs=(1.0, 1.0, 1.0, 1.0), c=None) -> None:
    """Fe's ``rows`` (the v_i, θ_i, v_j, θ_j of a bending plane, each times
    its sign) of every member k named in ``items`` — (k, case column, the
    load's part on the flexible length: :func:`flexible_part`) — replaced by
    the beam-column's consistent loads of its parts under N[k], Engesser's
    where c[k] = 1/(G A_s) > 0 (:func:`nodal_loads_many`, one pass)."""
    members = sorted({k for k, _, _ in items})
    for k in members:
        Fe[k, list(rows)] = 0.0
    if not items:
        return
    at = np.array([k for k, _, _ in items])
    cases = np.array([c for _, c, _ in items])
    f = nodal_loads_many([p for _, _, p in items], EI[at], N[at], Lf[at],
                         0.0 if c is None else np.asarray(c, float)[at]) * np.asarray(signs)
    np.add.at(Fe, (at[:, None], np.asarray(rows)[None, :], cases[:, None]), f)


def flexible_part(load, L, c, s, oi, oj):
    """:func:`across` of a load's part on the flexible length (positions
    from its start), or None where none lies there."""
    from .loads import clipped

    flex = clipped(load, oi, L - oj, shift=oi)
    return None if flex is None else across(flex, c, s)


def end_block(EI, N, L, c=0.0) -> np.ndarray:
    """The transverse end stiffness (4 × 4 on v_i, θ_i, v_j, θ_j) of the
    beam-column: the stability functions' (:mod:`.second_order`; Engesser's
    with c = 1/(G A_s) > 0, φ = 12 EI c/L²)."""
    t = -N * L * L / EI
    s, sc = (float(v[0]) for v in stability_functions(np.array([t]), 12.0 * EI * c / L ** 2))
    f = EI / L
    vv, vt = (2.0 * (s + sc) - t) * f / L ** 2, (s + sc) * f / L
    return np.array([[vv, vt, -vv, vt], [vt, s * f, -vt, sc * f],
                     [-vv, -vt, vv, -vt], [vt, sc * f, -vt, s * f]])


def axis(parts, EI, N, L, ends, springs, x, c=0.0) -> tuple[np.ndarray, np.ndarray]:
    """(v, v') at x on the flexible length L of a member under N with the
    loads ``parts`` (:func:`across`, each times its factor), Engesser's
    with c = 1/(G A_s) > 0: its flexible
    ends' displacements and their nodes' rotations ``ends`` (v_i, θ_i,
    v_j, θ_j), ``springs`` (i, j) each None for a rigid joint, 0 for a
    hinge, else a rotational spring.  A released end's own rotation θ_r
    comes from the element's moment row, the spring's moment k (θ_node −
    θ_r) on it: (k_rr + k) θ_r + Σ k_rc u_c = f_r + k θ_node, f the
    consistent loads — singular only where the member buckles with its
    nodes held (second_order.own_buckling)."""
    ends = released_ends(lambda: (end_block(EI, N, L, c), nodal_loads(parts, EI, N, L, c)),
                         ends, springs)
    return deflection(parts, EI, N, L, ends, x, c)
