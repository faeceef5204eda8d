"""Second-order answers of a frame on its contacts: the fixed point of the
axial forces (:func:`solve_second_order`) and the elastic critical load
factor α_cr (:func:`critical_load_factor`).  The members' second-order
stiffness is :mod:`.second_order`'s.

The fixed point.  The stiffness depends on the members' axial forces N,
which depend on the answer: N⁰ from the first-order answer, then for
k = 0, 1, …  solve the contact problem with K(N^k) (its own contact states,
certified as a first-order answer is, its statics on the deformed frame)
and read N^{k+1} off it, until every member's N^{k+1} agrees with N^k on
its own scale (|N| plus the terms EA/L |u_a| it is made of) to the
accuracy asked for.  The answer returned is the last solve's, whose K was
built from N^k: ``second_order["axial_error"]`` says how far its own axial
forces are from those.  Axial forces move little with the sway (the
iteration contracts by about the sway's share of them), so a few rounds
do; where they do not converge the answer is not called ok.

α_cr.  The smallest factor α on the combination's axial forces at which
the frame's tangent stiffness K(α N), with its contact states held (open
contacts free, closed ones fixed along their normals, sticking and slipping
ones also along their tangents: a slip's tangent stiffness is zero, and the
sway it allows is the sliding limit, which the load path finds), has a
zero eigenvalue.  With the stability functions K(α N) is exact for
Euler–Bernoulli members, so α_cr is found by bisection on the count of
K's negative eigenvalues (Sylvester's inertia; the Wittrick–Williams
count without its member term, which is zero below the first member's
clamped–clamped load α N L²/EI = 4π², where the search stops).
Eurocode 3 (5.2.1) asks for second-order analysis where α_cr < 10.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as la

from qpcontact.core.errors import InvalidOptionError

from .second_order import clamped_buckling_t

#: rounds of the axial forces' fixed point at most
ROUNDS = 30

#: α_cr's bisection stops at this relative width
ALPHA_RTOL = 1e-10

#: largest number of free dofs whose tangent stiffness is decomposed densely
DENSE_DOFS = 3000


def axial_forces(b, u) -> tuple[np.ndarray, np.ndarray]:
    """(N, scale): each member's axial force (tension positive) from the
    global displacements u on the assembly ``b``, and the terms it is made
    of (EA/L (|u_i| + |u_j|) along the axis, its member loads' share)."""
    k, T, dofs, _ = b["local"]
    d = (T @ np.asarray(u, float)[dofs][..., None])[..., 0]
    ea = k[:, 3, 3]
    N = ea * (d[:, 3] - d[:, 0])
    return N, ea * (np.abs(d[:, 3]) + np.abs(d[:, 0]))


def solve_second_order(frame, p, method, accuracy, raise_on_failure, combination, options):
    """The second-order answer of one combination (:func:`frame.solve` with
    ``second_order=True``): the first-order answer's axial forces, then the
    fixed point described above, then the answer's stability with its
    contact states held (an equilibrium past which the tangent stiffness
    has a negative eigenvalue is one the frame cannot rest in: a table
    beyond its second-order tipping load balanced on one leg).  The result
    carries ``second_order``: {"rounds", "axial_error", "axial" (N per
    member), "stable" (None where the frame is too large to check)}."""
    import warnings

    from qpcontact.core.accuracy import resolve_accuracy

    from .equilibrium_checks import (SMALL_DISPLACEMENT, SMALL_ROTATION,
                                     LargeDisplacementWarning, how_far)
    from .loads import describe

    if frame.kind.name != "plane":
        raise InvalidOptionError("second_order=True is written for plane frames (Frame); a "
                                 "SpaceFrame is analysed to first order")
    _, tol = resolve_accuracy(accuracy)

    def solve_on(b):
        return frame.kind.solve_one(frame, p, method, accuracy, raise_on_failure, combination,
                                    b, options)

    b = frame.build()
    res = solve_on(b)
    N, _ = axial_forces(b, res._u)
    error = np.inf
    for rounds in range(1, ROUNDS + 1):
        b = frame.build(axial=N)
        res = solve_on(b)
        N_new, terms = axial_forces(b, res._u)
        scale = np.abs(N_new) + terms
        diff = np.abs(N_new - N)
        error = float(np.max(np.divide(diff, scale, out=np.zeros_like(diff),
                                       where=scale > 0), initial=0.0))
        if error <= tol:
            break
        N = N_new
    stable = None
    if b["free"].size <= DENSE_DOFS:
        stable = negative_eigenvalues(reduced_tangent(frame, b, N, held_links(frame, b, res))) == 0
    res.second_order = {"rounds": rounds, "axial_error": error,
                        "axial": dict(zip(frame.members, N)), "stable": stable}
    words = (f"second order (P-Δ and P-δ): the axial forces that built the stiffness agree "
             f"with the answer's to {error:.1e} after {rounds} round(s)")
    if error > tol:
        res.ok = False
        words += (f" — NOT CONVERGED (asked {tol:.0e}): the frame may be near its elastic "
                  "critical load (critical_load_factor)")
    if stable is False:
        res.ok = False
        words += (" — UNSTABLE: with its contact states held the frame's tangent stiffness "
                  "has a negative eigenvalue, so it cannot rest in this equilibrium (past a "
                  "tipping or buckling load of the deformed frame)")
    elif stable is None:
        words += f"; its stability was not checked (over {DENSE_DOFS} free dofs)"
    res.message = f"{res.message}; {words}"
    if raise_on_failure and not res.ok:
        from qpcontact.core.errors import SolverFailedError
        raise SolverFailedError(f"frame: {res.message}")
    if res.ok and (res.displacement_ratio > SMALL_DISPLACEMENT
                   or res.max_rotation > SMALL_ROTATION):
        warnings.warn(f"frame under {describe(res.combination)}: "
                      f"{how_far(frame, res._u, second_order=True)[2]}",
                      LargeDisplacementWarning, stacklevel=3)
    return res


def critical_load_factor(frame, result) -> dict:
    """α_cr of ``result``'s combination (see the module's docstring): a dict
    with ``alpha`` (inf where no member is in compression), ``mode`` (the
    buckling shape, global displacements per node, largest 1), ``members``
    (the compressed members' N L²/EI at α = 1) and ``limited_by`` (None, or
    the member whose own clamped–clamped buckling bounds the search)."""
    if frame.kind.name != "plane":
        raise InvalidOptionError("critical_load_factor is written for plane frames (Frame)")
    b = frame.build()
    N = np.array([result.member_forces[m][3] for m in frame.members], float)
    if getattr(result, "second_order", None):
        N = np.array([result.second_order["axial"][m] for m in frame.members], float)
    EI = np.array([m.E * m.I for m in frame.members.values()], float)
    L = np.array([np.linalg.norm(np.subtract(frame.nodes[m.j], frame.nodes[m.i]))
                  - m.offset_i - m.offset_j for m in frame.members.values()], float)
    t1 = -N * L ** 2 / EI                      # compression positive, at α = 1
    if not np.any(t1 > 0):
        return {"alpha": np.inf, "mode": None, "members": {}, "limited_by": None}
    pole = clamped_buckling_t() / t1.max()
    held = held_links(frame, b, result)

    def negatives(alpha):
        return negative_eigenvalues(reduced_tangent(frame, b, alpha * N, held)), None

    if negatives(0.0)[0]:
        raise InvalidOptionError("critical_load_factor: the frame with its contact states held "
                                 "is not stable at zero load (a mechanism); no α_cr")
    lo, hi = 0.0, min(1.0, 0.5 * pole)
    while negatives(hi)[0] == 0:
        lo, hi = hi, min(2.0 * hi, pole * (1 - 1e-9))
        if hi >= pole * (1 - 1e-9) and negatives(hi)[0] == 0:
            worst = list(frame.members)[int(np.argmax(t1))]
            return {"alpha": float(pole), "mode": None, "limited_by": worst,
                    "members": dict(zip(frame.members, t1))}
    while hi - lo > ALPHA_RTOL * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if negatives(mid)[0] == 0 else (lo, mid)
    return {"alpha": float(hi), "mode": buckling_mode(frame, b, hi * N, held),
            "members": dict(zip(frame.members, t1)), "limited_by": None}


def negative_eigenvalues(K) -> int:
    """The number of K's negative eigenvalues (symmetric, dense), counted
    on D K D with D = diag(K_ii)^-1/2 — the same count (Sylvester's law of
    inertia) on a matrix whose entries are O(1): unscaled, a base 1e4
    times stiffer than the column on it put the threshold of rounding
    (1e-13 of the largest eigenvalue) at 3 % of the column's own, and α_cr
    1 % high."""
    d = np.abs(np.diag(K))
    d = np.where(d > 0, 1.0 / np.sqrt(np.where(d > 0, d, 1.0)), 1.0)
    lam = la.eigvalsh(K * d[:, None] * d[None, :])
    # below zero beyond the eigensolver's rounding (a few n ε of the
    # largest): a sway mode held by a stiff beam's axial stiffness has a
    # scaled eigenvalue of 1e-7, and a threshold of 1e-12 put α_cr 1e-5 high
    floor = 16 * lam.size * np.finfo(float).eps * max(float(np.abs(lam).max(initial=0.0)), 1e-300)
    return int(np.sum(lam < -floor))


def held_links(frame, b, result) -> np.ndarray:
    """The links held in α_cr: a contact's normal unless it lifted off,
    its tangent too (stick and slip alike)."""
    keys = list(result.supports)
    return np.array([result.supports[keys[ci]].state != "separated" for ci, _ in b["info"]])


def reduced_tangent(frame, b, N, held) -> np.ndarray:
    """K(N) on the free dofs, elastic held links as springs, rigid ones as
    constraints (projected out: Z' K Z over their null space), dense."""
    K = frame.stiffness(axial=N)
    free = b["free"]
    if free.size > DENSE_DOFS:
        raise InvalidOptionError(f"critical_load_factor: {free.size} free dofs; written for "
                                 f"frames of up to {DENSE_DOFS} (a dense eigendecomposition)")
    Kf = K[free][:, free].toarray()
    H = b["H"][free].toarray()[:, held]
    flex = b["flex"][held]
    soft = flex > 0
    if soft.any():
        Kf = Kf + (H[:, soft] / flex[soft]) @ H[:, soft].T
    rigid = H[:, ~soft]
    if rigid.shape[1]:
        Z = la.null_space(rigid.T)
        Kf = Z.T @ Kf @ Z
    return 0.5 * (Kf + Kf.T)


def buckling_mode(frame, b, N, held) -> dict:
    """The eigenvector of the smallest eigenvalue of K(N) with the held
    links (at α_cr: the buckling shape), per node, scaled to largest 1."""
    K = frame.stiffness(axial=N)
    free = b["free"]
    Kf = K[free][:, free].toarray()
    H = b["H"][free].toarray()[:, held]
    flex = b["flex"][held]
    soft = flex > 0
    if soft.any():
        Kf = Kf + (H[:, soft] / flex[soft]) @ H[:, soft].T
    rigid = H[:, ~soft]
    Z = la.null_space(rigid.T) if rigid.shape[1] else np.eye(free.size)
    lam, V = la.eigh(0.5 * (Z.T @ Kf @ Z + (Z.T @ Kf @ Z).T))
    v = np.zeros(b["K"].shape[0])
    v[free] = Z @ V[:, 0]
    v /= np.abs(v).max() or 1.0
    return dict(zip(b["names"], map(tuple, v.reshape(-1, 3).tolist())))
