"""The elastic critical load factor α_cr of a frame's second-order answer
(:func:`critical_load_factor`), its buckling shape, and whether an answer
whose tangent is within rounding of singular stands (:func:`stable_by_band`).

α_cr.  The smallest factor α on the combination's axial forces at which
the frame's tangent stiffness K(α N), with its contact states held (open
contacts free, closed ones fixed along their normals, sticking and slipping
ones also along their tangents: a slip's tangent stiffness is zero, and the
sway it allows is the sliding limit, which the load path finds), has a
zero eigenvalue.  With the stability functions K(α N) is exact (Livesley's
members, Engesser's with shear; a plane member whose loads make N vary
along it under α N(x), :mod:`.varying_axial`), so α_cr is found on the
count of K's negative eigenvalues (Sylvester's inertia, an LDLᵀ's:
:func:`.tangent_stiffness.first_negative`; the Wittrick–Williams
count without its member term, which is zero below the first member's own
buckling load with its nodes held, where the search stops: 4π²EI/L² for a
member rigidly joined at both ends (less with shear), less where hinged or
semi-rigid, :func:`.second_order.own_buckling`, on its largest compression
where N varies along it: Rayleigh's quotient bounds its own buckling by
that constant N's).  A member compressed past
its own buckling load makes an answer UNSTABLE whatever the count says.
Eurocode 3 (5.2.1) asks for second-order analysis where α_cr < 10.

The count has a rounding floor (16 n ε of the Jacobi-scaled tangent's
largest eigenvalue); α_cr is the lower end of the band in which the least
eigenvalue is within it of zero (:func:`.tangent_stiffness.rounding_bracket`),
the band returned beside it.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import scipy.linalg as la

from qpcontact.core.errors import InvalidOptionError, SolverFailedError

from .second_order import bending, own_buckling
from .second_order_path import axial_forces
from .tangent_stiffness import (first_negative, held_links, least_eigenvalue,
                                negative_eigenvalues, reduced_tangent, restraint,
                                rounding_bracket)
from .varying_axial import least_axial, own_buckling_factors


def critical_load_factor(frame, result) -> dict:
    """α_cr of ``result``'s combination (see the module's docstring): a dict
    with ``alpha`` (inf where no member is in compression), ``bracket``
    ((lo, hi): from lo the tangent's least eigenvalue is within its rounding
    floor of zero, from hi it is negative beyond it; ``alpha`` is lo, the
    conservative end — the two agree to ALPHA_RTOL unless a member many
    orders stiffer than its neighbours leaves the sway mode's eigenvalue
    near rounding, :func:`.tangent_stiffness.rounding_bracket`), ``mode``
    (the buckling shape, global displacements per node, largest 1),
    ``members`` (the compressed members' N L²/EI at α = 1) and
    ``limited_by`` (None, or the member whose own buckling load, its nodes
    held, bounds the search and is then α_cr:
    :func:`.second_order.own_buckling`).  Raises SolverFailedError where
    ``result`` holds no equilibrium, or where the band reaches down to zero
    load (the stiffness carries too few digits to bound α_cr from below)."""
    if result._u is None or np.ndim(result._u) != 1:
        raise SolverFailedError("critical_load_factor: the result holds no equilibrium "
                                f"({result.message[:200]}); α_cr is that of an equilibrium")
    b = frame.build()
    # the answer's own axial forces, not second_order["axial"] (those that built
    # its stiffness, a round behind and converged only to the accuracy asked on
    # a scale of EA/L |u|: a lightly compressed beam's N 1e-3 off at "low")
    N = axial_forces(b, result)[0]
    EI, L = bending(frame)
    t1 = -N * L ** 2 / EI                      # compression positive, at α = 1
    # a member's largest compression where its loads make N vary along it
    # (what bounds its own buckling with its nodes held: the search's pole)
    worst = least_axial(frame, N, result.combination)
    if not np.any(worst < 0):
        return {"alpha": np.inf, "bracket": (np.inf, np.inf), "mode": None, "members": {},
                "limited_by": None}
    ratio = own_buckling_factors(frame, N, result.combination, np.divide(
        own_buckling(frame), -worst, out=np.full(N.size, np.inf), where=worst < 0))
    pole = float(ratio.min())
    held = restraint(b, held_links(frame, b, result))

    def along(alpha):       # the member loads' axial parts grow with α too
        return {c: alpha * f for c, f in result.combination.items()}

    @lru_cache(maxsize=4)      # the bracket's ends are counted, then interpolated on
    def tangent(alpha):
        return reduced_tangent(frame.stiffness(axial=alpha * N, along=along(alpha)), b, held)

    def negatives(alpha):
        return negative_eigenvalues(tangent(alpha))

    def possible(alpha):
        return negative_eigenvalues(tangent(alpha), within=True)

    if negatives(0.0):
        raise InvalidOptionError("critical_load_factor: the frame with its contact states held "
                                 "is not stable at zero load (a mechanism); no α_cr")
    hi = first_negative(negatives, min(1.0, 0.5 * pole), pole,
                        lambda alpha: least_eigenvalue(tangent(alpha)))
    members = dict(zip(frame.members, t1))
    below_pole = pole * (1 - 1e-9)
    if hi is None and not possible(below_pole):
        worst = list(frame.members)[int(np.argmin(ratio))]
        return {"alpha": pole, "bracket": (pole, pole), "mode": None, "limited_by": worst,
                "members": members}
    # the lower end of the loads at which the least eigenvalue is within
    # rounding of zero: conservative where a stiff member makes that band
    # wide (tangent_stiffness.rounding_bracket), the same α to ALPHA_RTOL
    # where it is not — also where a member's own buckling stops the count
    # beyond rounding first (a leaning column beside a beam 1e9 times
    # stiffer: α_cr 2.2 at the column's Euler load, the sway's band from 1.8,
    # the frame's 2.047)
    top = below_pole if hi is None else hi
    lo = rounding_bracket(possible, top,
                          lambda alpha: least_eigenvalue(tangent(alpha), within=True))
    if lo == 0.0:
        raise SolverFailedError(
            "critical_load_factor: the frame's tangent stiffness, contact states held, has an "
            f"eigenvalue within rounding of zero at every load factor from 0 to {top:.6g} (the "
            "count of its inertia cannot bound α_cr from below: a member many orders of "
            "magnitude stiffer than those it joins leaves the sway's eigenvalue at rounding; "
            "model a rigid zone as offset_i/offset_j, a stiff link as a rigid one)")
    return {"alpha": float(lo), "bracket": (float(lo), float(top)),
            "mode": buckling_mode(frame, b, top * N, held, along(top)),
            "members": members, "limited_by": None}


def buckling_mode(frame, b, N, held, along=None) -> dict:
    """The eigenvector of the smallest eigenvalue of K(N) with the held
    links (``held``: a :func:`restraint`; at α_cr: the buckling shape),
    per node, scaled to largest 1."""
    Z = held[0]
    _, V = la.eigh(reduced_tangent(frame.stiffness(axial=N, along=along), b, held))
    v = np.zeros(b["K"].shape[0])
    v[b["free"]] = V[:, 0] if Z is None else Z @ V[:, 0]
    v /= np.abs(v).max() or 1.0
    return dict(zip(b["names"], map(tuple, v.reshape(-1, len(frame.DOFS)).tolist())))


def stable_by_band(frame, res) -> tuple:
    """(stable, undecided) of a second-order answer whose tangent has an
    eigenvalue within rounding of zero, by α_cr's band: (True, False) where
    the band lies above the answer's load (α_cr > 1), else (None, True)."""
    try:
        lo = critical_load_factor(frame, res)["alpha"]
    except (SolverFailedError, InvalidOptionError):
        return None, True
    return (True, False) if lo > 1.0 else (None, True)
