"""A frame's tangent stiffness with its contact states held, and its
inertia: what α_cr's search (:func:`first_negative`, for
:mod:`.second_order_analysis`) and the stability checks of a
second-order answer and trace count.

The links held are a contact's normal unless it lifted off, its tangent
too (stick and slip alike) (:func:`held_links`); elastic ones enter as
springs, rigid ones as constraints (:func:`restraint`,
:func:`reduced_tangent`); the count of negative eigenvalues is the
inertia of a Bunch–Kaufman LDLᵀ (:func:`negative_eigenvalues`).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as la
from scipy.linalg.lapack import dsytrf as sytrf

from qpcontact.core.errors import InvalidOptionError, SolverFailedError

#: largest number of free dofs whose tangent stiffness is decomposed densely
DENSE_DOFS = 3000

#: α_cr's search stops at this relative width
ALPHA_RTOL = 1e-10


def negative_eigenvalues(K, within: bool = False) -> int:
    """The number of K's negative eigenvalues (symmetric, dense) beyond
    rounding — with ``within``, those below +floor instead: negative or
    within rounding of zero, the count a conservative answer needs (see
    :func:`rounding_bracket`).  Counted
    on D K D with D = diag(K_ii)^-1/2 — the same count (Sylvester's law of
    inertia) on a matrix whose entries are O(1): unscaled, a base 1e4
    times stiffer than the column on it put the threshold of rounding
    (1e-13 of the largest eigenvalue) at 3 % of the column's own, and α_cr
    1 % high.  Counted as the inertia of its Bunch–Kaufman LDLᵀ (LAPACK's
    sytrf; Sylvester again: L D Lᵀ has D's inertia), a sixth of the work
    of its eigenvalues, which the bisection of α_cr asked for 40 times
    (a portal in 130 members: 4.9 of its 5.5 s)."""
    Ks = _scaled(K)
    if not Ks.size:
        return 0
    # below zero beyond rounding (a few n ε of the largest eigenvalue, as
    # the eigenvalues were counted): a sway mode held by a stiff beam's
    # axial stiffness has a scaled eigenvalue of 1e-7, and a threshold of
    # 1e-12 put α_cr 1e-5 high.  The eigenvalues below −floor are the
    # negative ones of Ks + floor I: the pivots of Ks itself said
    # "negative" for eigenvalues of −2e-14 within the floor (Bunch–Kaufman's
    # pivots are no smaller than the eigenvalue that makes a matrix
    # singular).  The largest |eigenvalue| by POWER steps of the power
    # method: the largest row sum, its bound, was up to twice it, and the
    # floor with it put a 64-piece portal's α_cr 1.3e-5 higher still
    return _inertia(Ks, -_floor(Ks) if within else _floor(Ks))


def band_counts(K) -> tuple[int, int]:
    """(:func:`negative_eigenvalues` of K, the same ``within``) on one
    scaling and one rounding floor — a second-order answer's stability
    asks both of the same tangent."""
    Ks = _scaled(K)
    if not Ks.size:
        return 0, 0
    floor = _floor(Ks)
    return _inertia(Ks, floor), _inertia(Ks, -floor)


def _inertia(Ks, shift) -> int:
    """The number of negative eigenvalues of Ks + shift I: the inertia of
    its Bunch–Kaufman LDLᵀ."""
    lu, piv, info = sytrf(Ks + shift * np.eye(Ks.shape[0]), lower=1)
    if info < 0:
        raise SolverFailedError(f"negative_eigenvalues: LAPACK sytrf argument {-info}")
    # D's 1 × 1 pivots, and its 2 × 2 blocks where ipiv is negative on
    # their first row (LAPACK's lower storage), each by its determinant
    # and trace
    diag, off = np.diag(lu), np.diag(lu, -1)
    count, k, n = 0, 0, diag.size
    while k < n:
        if piv[k] < 0 and k + 1 < n:
            det = diag[k] * diag[k + 1] - off[k] ** 2
            count += 1 if det < 0 else (2 if det > 0 and diag[k] + diag[k + 1] < 0 else 0)
            k += 2
        else:
            count += int(diag[k] < 0)
            k += 1
    return count


def least_eigenvalue(K, within: bool = False) -> float:
    """The least eigenvalue of D K D + floor I (:func:`negative_eigenvalues`'
    scaling and rounding floor; − floor I with ``within``): below zero where
    that count is not zero, and continuous in K — what α_cr's search
    interpolates on."""
    Ks = _scaled(K)
    if not Ks.size:
        return np.inf
    floor = _floor(Ks)
    return float(la.eigh(Ks, eigvals_only=True, subset_by_index=[0, 0])[0]) + (
        -floor if within else floor)


def _scaled(K) -> np.ndarray:
    """D K D, D = diag(|K_ii|)^-1/2 (1 where K_ii = 0)."""
    d = np.abs(np.diag(K))
    d = np.where(d > 0, 1.0 / np.sqrt(np.where(d > 0, d, 1.0)), 1.0)
    return K * d[:, None] * d[None, :]


def _floor(Ks) -> float:
    """The rounding floor of the scaled Ks's eigenvalues: 16 n ε max |λ|."""
    return 16 * Ks.shape[0] * np.finfo(float).eps * max(largest_eigenvalue(Ks), 1e-300)


#: power steps for a tangent's largest |eigenvalue| (a lower bound that the
#: rounding floor of :func:`negative_eigenvalues` is measured on)
POWER = 20


def largest_eigenvalue(Ks) -> float:
    """max |λ| of the symmetric Ks, from below: POWER steps of the power
    method from a fixed start (clustered largest eigenvalues, many equal
    pieces' axial ones, leave the estimate within the cluster)."""
    x = np.random.default_rng(0).standard_normal(Ks.shape[0])
    size = 0.0
    for _ in range(POWER):
        y = Ks @ x
        size = float(np.linalg.norm(y)) / float(np.linalg.norm(x))
        if size == 0.0:
            return 0.0
        x = y
    return size


def held_links(frame, b, result) -> np.ndarray:
    """The links held in α_cr: a contact's normal unless it lifted off,
    its tangent too (stick and slip alike)."""
    keys = list(result.supports)
    return np.array([result.supports[keys[ci]].state != "separated" for ci, _ in b["info"]],
                    bool)       # a frame without contacts: no links, an empty mask


def restraint(b, held) -> tuple[np.ndarray, np.ndarray]:
    """(Z, S) of the links ``held`` (a mask over b's links) on the free
    dofs: Z an orthonormal basis of the motions the rigid ones allow (None
    where none is rigid: every motion), S the elastic ones' springs (H
    diag(1/flex) H'), dense — what the tangent stiffness of any K is
    reduced with (:func:`reduced_tangent`)."""
    free = b["free"]
    if free.size > DENSE_DOFS:
        raise InvalidOptionError(f"critical_load_factor: {free.size} free dofs; written for "
                                 f"frames of up to {DENSE_DOFS} (a dense eigendecomposition)")
    H = b["H"][free].toarray()[:, held]
    flex = b["flex"][held]
    soft = flex > 0
    rigid = H[:, ~soft]
    Z = la.null_space(rigid.T) if rigid.shape[1] else None
    return Z, (H[:, soft] / flex[soft]) @ H[:, soft].T


def reduced_tangent(K, b, held) -> np.ndarray:
    """The stiffness K (all dofs) on b's free dofs with the links ``held``
    (a :func:`restraint`): elastic ones as springs, rigid ones as
    constraints (projected out: Z'(K_ff + S)Z; none to project where no
    link is rigid — Z = I made a third of α_cr's time), dense, symmetric."""
    Z, S = held
    free = b["free"]
    Kr = K[free][:, free].toarray() + S
    if Z is not None:
        Kr = Z.T @ Kr @ Z
    return 0.5 * (Kr + Kr.T)


def first_negative(negatives, start, pole, least=None):
    """The least x in (0, pole) at which the count ``negatives(x)`` of a
    tangent stiffness's negative eigenvalues leaves zero, to ALPHA_RTOL:
    bracketed by doubling from ``start``, then bisected (Sylvester's law
    of inertia: the count grows with the load).  None where it stays zero
    up to just below ``pole`` (a member's own clamped–clamped buckling,
    where the stability functions have their pole).  ``least``: the
    tangent's least eigenvalue above its floor (:func:`least_eigenvalue`),
    whose zero the bracket is narrowed to first by the Illinois rule (a
    tangent under N(x) rebuilds its members at each step: 39 steps of
    bisection took 0.9 s on a 70-member frame), then widened by TIGHT (else
    NEAR) and kept where the counts at its ends say so, and bisected on the
    counts as before: the same α.  The least eigenvalue's zero and the count's
    change differ by rounding (1.1e-11 on a 30-storey frame), so the
    narrowed bracket alone was not the counts' in one frame of two."""
    lo, hi = 0.0, start
    # toward the pole by decades of its distance, not in one step to 1e-9 of
    # it: there the count is rounding's (a shear-flexible member at N within
    # 1e-9 of −G A_s counted none where the frame's sway had buckled at 0.56
    # of that load, and α_cr was reported at the pole, 78 % high)
    ladder = [pole * (1 - 10.0 ** -k) for k in range(1, 10)]
    while negatives(hi) == 0:
        if hi >= ladder[-1]:
            return None
        lo, hi = hi, min([2.0 * hi] + [x for x in ladder if x > hi])
    return first_in(negatives, lo, hi, least)


def first_in(negatives, lo, hi, least=None):
    """:func:`first_negative` within a bracket: ``negatives`` zero at lo,
    not at hi."""
    if least is not None:
        # to a quarter of ALPHA_RTOL, widened by as much: where the counts at
        # its ends agree no bisection is left (the least eigenvalue's zero and
        # the count's change differ by ~1e-11); else widened by NEAR
        a, b = _illinois(least, lo, hi, TIGHT)
        for margin in (TIGHT, NEAR):
            a2, b2 = max(lo, a * (1 - margin)), min(hi, b * (1 + margin))
            if (a2 == lo or negatives(a2) == 0) and (b2 == hi or negatives(b2) != 0):
                lo, hi = a2, b2
                break
    return first_holding(lambda x: negatives(x) != 0, lo, hi, ALPHA_RTOL)


def rounding_bracket(possible, hi, least=None):
    """The least x ≤ ``hi`` at which ``possible(x)`` — the count of the
    tangent's eigenvalues below +floor (``negative_eigenvalues(...,
    within=True)``) — leaves zero, to ALPHA_RTOL; ``hi`` is where the count
    beyond rounding does (:func:`first_negative`).  Between the two the
    tangent's least eigenvalue is within its rounding floor of zero, so the
    count cannot say whether the frame still stands: what is reported below
    ``hi`` must be this lower end (conservative).  Why it matters: the
    floor is 16 n ε of the scaled tangent's largest eigenvalue, and a
    member 1e6–1e8 times stiffer than its neighbours (a rigid zone modelled
    as a member) shrinks the scaled sway eigenvalue by that contrast — a
    heavy cantilever with its top eighth 1e8 times stiffer had the count
    change at α = 0.9323 where the zero lies at 0.9091 (its zone as an
    offset: 0.90914452).  The band is the stretch just below hi where the
    count is not zero: with members in tension the count need not grow
    with x (a beam 1e10 times stiffer than its columns in tension: not zero
    at x = 0, zero from 100, not zero again near α_cr = 4.6e6).  0.0 where
    it reaches x = 0.  Where the band is narrower than ALPHA_RTOL one count
    says so and hi (1 − ALPHA_RTOL) is the end."""
    lo = hi * (1.0 - ALPHA_RTOL)
    if possible(lo) == 0:
        return lo
    gap = 1e-8
    while True:
        lo = hi * (1.0 - gap) if gap < 1.0 else 0.0
        if possible(lo) == 0:
            return first_in(possible, lo, hi, least)
        if lo == 0.0:
            return 0.0
        gap *= 16.0


#: the relative margins by which the least eigenvalue's bracket is widened
#: before the counts check it: a quarter of ALPHA_RTOL first, else a
#: hundred times the two's rounding difference
TIGHT = 0.25 * ALPHA_RTOL
NEAR = 1e-9


def _illinois(f, a, b, rtol, steps=40):
    """A bracket [a, b] of a zero of f, f(a) > 0 ≥ f(b), narrowed by the
    Illinois rule (regula falsi halving the end that stays) to rtol of b,
    or as far as ``steps`` evaluations take it."""
    fa, fb, side = f(a), f(b), 0
    for _ in range(steps):
        if b - a <= rtol * b or not fa > 0 >= fb:
            break
        c = (a * fb - b * fa) / (fb - fa)
        if not a < c < b:
            c = 0.5 * (a + b)
        fc = f(c)
        if fc > 0:
            a, fa, fb, side = c, fc, fb / 2 if side > 0 else fb, 1
        else:
            b, fb, fa, side = c, fc, fa / 2 if side < 0 else fa, -1
    return a, b


def first_holding(holds, lo, hi, rtol):
    """Bisection of (lo, hi], ``holds`` false at lo and true at hi (and
    monotone between): the least x found to hold, to ``rtol`` of it."""
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if holds(mid) else (mid, hi)
    return hi
