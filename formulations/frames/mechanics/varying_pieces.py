"""One piece of a beam-column under N(x) — Euler–Bernoulli or
shear-flexible (Engesser's) — as Taylor series, its transfer matrix, and
the stiffness of a run of pieces: the arithmetic under
:class:`.varying_axial.Member`.

The mechanics.  On a piece [x₀, x₀ + h] of a member (member axes, x along
it) the axial force N(x) [F] (tension positive) is a polynomial of degree
≤ 2 and the load across it q(x) [F/L] of degree ≤ 1.  The state is
(v, θ, M, S): the deflection v [L], the section's rotation θ [-], the
section moment on the deformed axis M = EI θ' [F·L] and the force across
the undeformed axis S = M' − N v' [F] (the chain's end shear).
Equilibrium on the deformed axis gives S' = q and M' = S + N v'.  The
shear across the deformed axis (Engesser's, :mod:`.second_order`), M',
strains the section: v' = θ − M'/(G A_s), G A_s [F] (v' = θ for an
Euler–Bernoulli member, 1/(G A_s) = 0).  In v alone, with c = 1/(G A_s)
[1/F] (M = EI θ' = EI v'' + EI c M'', M'' = q + (N v')'):

    EI v'''' + EI c (N v')''' − (N v')' = q        (q'' = 0 on a piece).

N = ν₀ + ν₁ σ + ν₂ σ², σ = (x − x₀)/h, β_r = h² ν_r / EI, g = EI c / h²
[-], v = Σ A_n σⁿ [L]: the coefficient of σ^m gives

    (m+1)(m+2)(m+3)(m+4)(1 + g β₀) A_{m+4}
        = (m+1) [β₀ (m+2) A_{m+2} + β₁ (m+1) A_{m+1} + β₂ m A_m]
          − g (m+1)(m+2)(m+3) [β₁ (m+3) A_{m+3} + β₂ (m+2) A_{m+2}]
          + h⁴ q_m / EI.

1 + g β₀ = 1 + N(x₀)/(G A_s) is Engesser's β at the piece's start; the
g-terms alone fall geometrically, by (|ν₁| + |ν₂|)/(G A_s + ν₀) a term,
so a piece is cut where N changes along it by more than SHEAR of
G A_s + N (never in practice: G A_s is 1e2–1e3 times a column's N), and
where |N| h²/(EI (1 + N/(G A_s))) > 1 (Engesser's μ², as the
Euler–Bernoulli chain's |N| h² ≤ EI): the terms then fall as 1/n! too.

The derivatives at a point from the state and back (c = 0: v' = θ,
M = EI v'', S = EI v''' − N v'):

    v'   = (θ − c S)/D,                            D = 1 + c N,
    v''  = (M/EI − c N' v' − c q)/D,
    v''' = ((S + N v')/EI − c (N'' v' + 2 N' v'') − c q')/D;
    M = EI (D v'' + c N' v' + c q),  M' = EI (v''' + c (N v')'' + c q'),
    θ = v' + c M',  S = M' − N v'.

So four series from the unit states at x₀ give the piece's transfer
matrix T (state at x₀ + h from the state at x₀) directly — no matrix is
inverted, and a piece of any length, 1e-16 m or 0, is well conditioned
(T → I: a load position 1 ulp from another was a piece whose stiffness,
∝ 1/h³, made the chain singular).  The particular series (zero state at
x₀, q) gives its load term t.  A run of pieces (a few short ones with a
longer one) multiplies them; its stiffness on the ends' (v, θ) — the end
forces (S_a, −M_a, −S_b, M_b) as the Euler–Bernoulli element's — follows
from d_b = T_dd d_a + T_df f_a + t_d (d = (v, θ), f = (M, S)): f_a =
T_df⁻¹ (d_b − T_dd d_a − t_d), f_b = T_fd d_a + T_ff f_a + t_f, taken in
states scaled by the run's length ℓ (v, ℓ θ, ℓ² M/EI, ℓ³ S/EI, all
lengths).  Runs are no longer than a few pieces, so the products do not
grow as e^(kL) in strong tension (the reason for a chain of stiffnesses,
:mod:`.varying_axial`).
"""

from __future__ import annotations

import numpy as np

#: Taylor terms per piece at most (|β| ≤ 1: 22 make the tail 1e-19 of the
#: first; the series stops once four terms in a row are below TAIL of the
#: largest, each solution's own: a short piece under little N needs ten)
TERMS = 32

#: the share of a solution's largest coefficient below which its tail is dropped
TAIL = 1e-19

#: the most that N may change along a piece, as a share of G A_s + N (the
#: series' shear terms fall by it a term: 8⁻²⁸ at TERMS)
SHEAR = 0.125

#: the largest |N| h² / (EI D) of a piece (D = 1 + N/(G A_s), Engesser's)
PIECE = 1.0

#: a run of pieces (:func:`runs`) at least this share of its pieces' reach
SHORT = 0.25


def cuts(planes, L, points, N):
    """(edges, reach, sheared): the pieces' edges — the load positions
    ``points`` and cuts that keep |N| h² ≤ PIECE EI D (D = 1 + N/(G A_s),
    Engesser's; 1 without shear) and N's change along a piece below SHEAR
    of G A_s D, on each of the bending ``planes`` [(EI, 1/(G A_s) or 0)] —
    each piece's reach (the longest that the first rule allows on its
    stretch, at most L: what makes a piece short, :func:`runs`), and
    whether D ≤ 0 somewhere (N past G A_s in compression: there v' =
    (θ − S/(G A_s))/D has no bound, the member is past its own buckling).
    A stretch where D is small (N near −G A_s) is cut in pieces that
    shorten with D (:func:`_graded`): even cuts there would number 1/D.
    ``N(x)``: N at the sections x (2, …): their right and left sides."""
    edges = np.unique(np.r_[0.0, [p for p in points if 0.0 < p < L], L])
    # N on each stretch from 9 points (both sides of its ends)
    xs = edges[:-1, None] + np.diff(edges)[:, None] * np.linspace(0.0, 1.0, 9)
    both = N(xs)
    big = np.abs(both).max(axis=(0, 2))
    swing = both.max(axis=(0, 2)) - both.min(axis=(0, 2))
    n = np.ones(edges.size - 1)
    reach = np.full(edges.size - 1, float(L))
    graded = np.zeros(edges.size - 1, bool)
    for EI, c in planes:
        D = (1.0 + c * both).min(axis=(0, 2))
        if np.any(D <= 0.0):
            return edges, reach, True
        with np.errstate(divide="ignore"):
            allowed = np.sqrt(PIECE * EI * D / big)
        n = np.maximum(n, np.diff(edges) / allowed * 1.05)
        reach = np.minimum(reach, allowed)
        if c:
            n = np.maximum(n, swing * c / (SHEAR * D))
            graded |= D < 0.5
    n = np.ceil(n).astype(int)
    if not np.any(n > 1):
        return edges, reach, False
    parts, reaches = [edges[:1]], []
    for a, b, k, r, grade in zip(edges[:-1], edges[1:], n, reach, graded):
        if grade and k > 1:
            cut, each = _graded(a, b, planes, N)
            if cut is None:
                return edges, reach, True
            parts.append(cut)
            reaches.append(each)
        else:
            parts.append(np.linspace(a, b, k + 1)[1:])
            reaches.append(np.full(k, r))
    return np.concatenate(parts), np.concatenate(reaches), False


#: the most pieces a stretch is cut in where D = 1 + N/(G A_s) is small
#: (:func:`_graded`: about 8 ln(1/D) pieces; beyond it D is 1e-30 or less)
GRADED = 1000


def _graded(a, b, planes, N):
    """(the ends of pieces on [a, b] that meet :func:`cuts`' rules each on
    its own N — short where D is small, long where it is not —, their
    reaches), or None where D ≤ 0 somewhere or GRADED pieces do not cover
    it (the member is past its own buckling: :func:`cuts`)."""
    out, reaches, x = [], [], a
    h = b - a
    while x < b and len(out) < GRADED:
        h = min(2.0 * h, b - x)
        for _ in range(60):
            Nx = N(x + h * np.linspace(0.0, 1.0, 5))
            big, swing = np.abs(Nx).max(), Nx.max() - Nx.min()
            limit = h
            for EI, c in planes:
                D = (1.0 + c * Nx).min()
                if D <= 0.0:
                    return None, None
                reach = np.sqrt(PIECE * EI * D / big) if big else np.inf
                limit = min(limit, reach / 1.05, SHEAR * D / (c * swing) * h
                            if c and swing else np.inf)
            if limit >= h:
                break
            h = 0.9 * limit
        x = b if b - (x + h) <= 1e-12 * (b - a) else x + h
        out.append(x)
        reaches.append(h)
    if x < b:
        return None, None
    return np.array(out), np.array(reaches)


def runs(h, reach) -> np.ndarray:
    """The runs' bounds (piece indices, 0 … P): consecutive pieces joined
    until a run is SHORT of its least reach long (a last short run joins
    the one before): a piece much shorter than its neighbours, as a
    stiffness (∝ 1/h³), costs the chain 3 log₁₀ of the ratio in digits
    (1e-16 m: singular), as a transfer matrix nothing."""
    P = h.size
    if P == 1 or np.all(h >= SHORT * reach):
        return np.arange(P + 1)
    bounds, length, least = [0], 0.0, np.inf
    for p in range(P):
        length, least = length + h[p], min(least, reach[p])
        if length >= SHORT * least:
            bounds.append(p + 1)
            length, least = 0.0, np.inf
    if bounds[-1] != P:
        if len(bounds) > 1:
            bounds[-1] = P
        else:
            bounds.append(P)
    return np.array(bounds)


_N = np.arange(TERMS, dtype=float)
_D1, _D2 = _N, _N * (_N - 1)
_D3 = _D2 * (_N - 2)


def series(beta, g, init, qt=None) -> np.ndarray:
    """(P, S, TERMS): S solutions on each of P pieces from their first
    four coefficients ``init`` (P, S, 4); ``beta`` (P, 3), ``g`` (P,),
    ``qt`` (P, S, 2) h⁴ (q₀, q₁ h)/EI or None (module docstring)."""
    P, S = init.shape[:2]
    A = np.zeros((P, S, TERMS))
    A[..., :4] = init
    b0, b1, b2 = (beta[:, None, i] for i in range(3))
    gg = np.asarray(g, float)[:, None]
    lead = 1.0 + gg * b0
    shear = bool(np.any(gg))
    for m in range(TERMS - 4):
        rhs = (m + 1) * (b0 * (m + 2) * A[..., m + 2] + b1 * (m + 1) * A[..., m + 1]
                         + b2 * m * A[..., m])
        if shear:
            rhs -= gg * ((m + 1) * (m + 2) * (m + 3)) * (b1 * (m + 3) * A[..., m + 3]
                                                        + b2 * (m + 2) * A[..., m + 2])
        if m < 2 and qt is not None:
            rhs += qt[..., m]
        A[..., m + 4] = rhs / ((m + 1) * (m + 2) * (m + 3) * (m + 4) * lead)
        if m % 4 == 3 and np.all(np.abs(A[..., m + 1:m + 5]).max(axis=-1)
                                 <= TAIL * np.abs(A[..., :m + 1]).max(axis=-1)):
            break
    return A


def _axial(nu, h, at_end):
    """(N, N', N'') at a piece's start or end (x-derivatives), (P,) each."""
    n0, n1, n2 = nu[:, 0], nu[:, 1], nu[:, 2]
    if at_end:
        return n0 + n1 + n2, (n1 + 2 * n2) / h, 2 * n2 / h ** 2
    return n0, n1 / h, 2 * n2 / h ** 2


def starts(nu, h, EI, c, q=None) -> tuple[np.ndarray, np.ndarray]:
    """(the first four coefficients of the solutions from the unit states
    (P, 4 solutions, 4), the particular's from the zero state under q
    (P, 4)) on pieces of N coefficients ``nu`` (P, 3), lengths ``h``,
    ``c`` = 1/(G A_s) (0: Euler–Bernoulli), ``q`` (P, 2) its (q₀, q') or None."""
    N, dN, ddN = _axial(nu, h, False)
    P = h.size
    D = 1.0 + c * N
    eye = np.broadcast_to(np.eye(4), (P, 4, 4))
    v, th, M, S = (eye[:, k, :] for k in range(4))         # (P, 4 solutions)
    col = (lambda a: np.asarray(a, float).reshape(-1, 1))
    D_, c_, N_, dN_, ddN_, EI_ = (col(a) for a in np.broadcast_arrays(D, c, N, dN, ddN, EI))
    d1 = (th - c_ * S) / D_
    d2 = (M / EI_ - c_ * dN_ * d1) / D_
    d3 = ((S + N_ * d1) / EI_ - c_ * (ddN_ * d1 + 2 * dN_ * d2)) / D_
    hh = h[:, None]
    unit = np.stack([v, hh * d1, hh ** 2 * d2 / 2, hh ** 3 * d3 / 6], axis=-1)
    part = np.zeros((P, 4))
    if q is not None:
        p2 = -c_[:, 0] * q[:, 0] / D_[:, 0]
        p3 = -c_[:, 0] * (2 * dN_[:, 0] * p2 + q[:, 1]) / D_[:, 0]
        part[:, 2], part[:, 3] = h ** 2 * p2 / 2, h ** 3 * p3 / 6
    return unit, part


def derivatives(A, h) -> np.ndarray:
    """(4, P, S): v and its first three x-derivatives at σ = 1 of the
    coefficients A (P, S, TERMS)."""
    hh = np.asarray(h, float).reshape((-1,) + (1,) * (A.ndim - 2))
    return np.stack([A.sum(-1), (A * _D1).sum(-1) / hh, (A * _D2).sum(-1) / hh ** 2,
                     (A * _D3).sum(-1) / hh ** 3])


def end_states(A, nu, h, EI, c, q=None) -> np.ndarray:
    """(P, 4 states, S): (v, θ, M, S) at each piece's end of its
    solutions A (P, S, TERMS); ``q`` (P, 2) (q₀, q') where A carries it."""
    v, d1, d2, d3 = derivatives(A, h)
    N, dN, ddN = (a[:, None] for a in _axial(nu, h, True))
    cc = np.asarray(c, float).reshape(-1, 1) * np.ones_like(N)
    qe = np.zeros_like(N) if q is None else (q[:, 0] + q[:, 1] * h)[:, None]
    dq = np.zeros_like(N) if q is None else q[:, 1:2]
    EI = np.asarray(EI, float).reshape(-1, 1)
    M = EI * ((1.0 + cc * N) * d2 + cc * dN * d1 + cc * qe)
    dM = EI * (d3 + cc * (ddN * d1 + 2 * dN * d2 + N * d3) + cc * dq)
    return np.stack([v, d1 + cc * dM, M, dM - N * d1], axis=1)


def _scales(length, EI):
    """(4,) or (G, 4): the states' scales (1, ℓ, ℓ²/EI, ℓ³/EI): all lengths."""
    ell = np.asarray(length, float)[..., None]
    EI = np.asarray(EI, float)[..., None] if np.ndim(EI) else EI
    return np.concatenate([np.ones_like(ell), ell, ell ** 2 / EI, ell ** 3 / EI], axis=-1)


def run_stiffness(T, length, EI) -> tuple[np.ndarray, np.ndarray]:
    """(k (G, 4, 4), F (G, 4, 4)): the stiffness on (v_a, θ_a, v_b, θ_b) of
    runs of transfer matrices T (G, 4, 4), and the map F from a run's load
    term t (4) to its clamped end forces (S_a, −M_a, −S_b, M_b), F t
    (module docstring); EI a number or one a run."""
    s = _scales(length, EI)
    Ts = s[:, :, None] * T / s[:, None, :]
    Tdd, Tdf, Tfd, Tff = Ts[:, :2, :2], Ts[:, :2, 2:], Ts[:, 2:, :2], Ts[:, 2:, 2:]
    X = np.linalg.inv(Tdf)
    # f_a = X d_b − X Tdd d_a − X t_d ; f_b = Tfd d_a + Tff f_a + t_f: on the
    # ends' displacements, then on t (scaled: s t)
    fa = np.concatenate([-X @ Tdd, X], axis=2)                       # (G, 2, 4)
    fb = np.concatenate([Tfd, np.zeros_like(Tfd)], axis=2) + Tff @ fa
    ta = np.concatenate([-X, np.zeros_like(X)], axis=2) * s[:, None, :]
    tb = Tff @ ta + np.concatenate([np.zeros_like(X), np.eye(2) * s[:, None, 2:]], axis=2)
    # scaled displacements (v, ℓθ) back to (v, θ), scaled forces to (M, S)
    dsc = np.concatenate([s[:, :2], s[:, :2]], axis=1)
    fa, fb = fa * dsc[:, None, :], fb * dsc[:, None, :]
    fa, fb, ta, tb = (f / s[:, 2:, None] for f in (fa, fb, ta, tb))
    k = np.stack([fa[:, 1], -fa[:, 0], -fb[:, 1], fb[:, 0]], axis=1)
    F = np.stack([ta[:, 1], -ta[:, 0], -tb[:, 1], tb[:, 0]], axis=1)
    return 0.5 * (k + np.swapaxes(k, 1, 2)), F


def start_forces(T, t, length, EI, da, db) -> np.ndarray:
    """(M, S) at a run's start from its ends' (v, θ) ``da``, ``db``."""
    s = _scales(length, EI)
    Ts = s[:, None] * T / s[None, :]
    ts = s * t
    fa = np.linalg.solve(Ts[:2, 2:], s[:2] * db - Ts[:2, :2] @ (s[:2] * da) - ts[:2])
    return fa / s[2:]
