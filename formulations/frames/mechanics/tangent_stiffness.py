"""A frame's tangent stiffness with its contact states held, and its
inertia: what α_cr's bisection (:mod:`.second_order_analysis`) and the
stability checks of a second-order answer and trace count.

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


def negative_eigenvalues(K) -> int:
    """The number of K's negative eigenvalues (symmetric, dense), counted
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
    lu, piv, info = sytrf(Ks + _floor(Ks) * np.eye(Ks.shape[0]), lower=1)
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


def least_eigenvalue(K) -> float:
    """The least eigenvalue of D K D + floor I (:func:`negative_eigenvalues`'
    scaling and rounding floor): below zero where that count is not zero,
    and continuous in K — what α_cr's search interpolates on."""
    Ks = _scaled(K)
    if not Ks.size:
        return np.inf
    return float(la.eigh(Ks, eigvals_only=True, subset_by_index=[0, 0])[0]) + _floor(Ks)


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
