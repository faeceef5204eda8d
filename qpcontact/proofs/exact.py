"""Exact checks of proofs, in rational arithmetic.

The data's doubles are rationals (:class:`fractions.Fraction`), so a Farkas
vector's weighted sum of constraints, or a ray's products with the data, are
computed without rounding.  A candidate from a linear program is tried as it
came and snapped to small denominators (which recovers the exact weights of
integer data: 1/3 rather than 0.3333...).  A check in floating point is not a
proof: with a rounded r ≈ 1e-16 a Farkas vector only rules out feasible
points up to |c| / ‖r‖₁, and on a badly scaled but solvable LCP the solution
lay beyond that (a false "infeasible", caught by ``qpcontact stress``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import scipy.sparse as sp

__all__ = ["Proof", "EXACT_WORK", "candidates", "snap", "exact_farkas", "exact_ray"]


#: nonzero products an exact (rational) check may take; beyond it no proof
#: is claimed (a rounded check is not a proof: with r = G'z + ... ≈ 1e-16 it
#: only rules out feasible points up to |c| / ‖r‖₁, and a scaled problem's
#: solution was found beyond that)
EXACT_WORK = 200_000


@dataclass
class Proof:
    """A checked certificate that a problem has no solution (a QP: no minimiser).

    ``kind`` is "infeasible" (``vector`` = (z, y, μl, μu) multipliers of
    G, A, lb, ub) or "unbounded" (``vector`` = the direction d, ``point`` = a
    feasible x0).  ``message`` says what was proved, in numbers."""

    kind: str
    message: str
    vector: dict
    point: np.ndarray | None = None


#: denominators tried when snapping an LP's vector to exact rationals
#: (None: the doubles themselves); small first, since an LP solution is only
#: accurate to its tolerance and a large denominator fits the error instead
_SNAPS = (1 << 4, 1 << 8, 1 << 12, 1 << 16, 1 << 20, None)


#: components below this fraction of the largest are tried as exact zeros
#: (an LP leaves 1e-11 where the exact ray has 0)
_ZEROS = (0.0, 1e-12, 1e-9, 1e-6)


def candidates(values: np.ndarray, deadline=None):
    """Exact rational vectors near ``values``, simplest first; none more once
    ``deadline`` (a :class:`~qpcontact.core.deadline.Deadline`) has passed."""
    top = float(np.max(np.abs(values), initial=0.0))
    for tiny in _ZEROS:
        cut = np.where(np.abs(values) <= tiny * top, 0.0, values)
        for limit in _SNAPS:
            if deadline is not None and deadline.expired():
                return
            yield snap(cut, limit)


def snap(values: np.ndarray, limit) -> list:
    """Exact rationals near an LP's floating-point solution (small denominators
    recover the exact weights of integer data: 1/3 rather than 0.3333...)."""
    if limit is None:
        return [Fraction(float(v)) for v in values]
    out = []
    for v in values:
        # each component's mantissa on its own: scaled data put the exact
        # weights at different powers of two (2^-23 beside 1)
        m, e = math.frexp(float(v))
        out.append(Fraction(m).limit_denominator(limit) * Fraction(2) ** e)
    return out


def exact_farkas(G, h, A, b, lo, hi, exact, m_G, deadline=None) -> Proof | None:
    """Check a Farkas vector in exact rational arithmetic: the data's doubles
    are rationals, so G'z + A'y, the bound multipliers that cancel it, and
    c = h'z + b'y - lb'μl + ub'μu are computed without rounding.  Sound: a
    vector that passes proves infeasibility of the data as stored.  Gives up
    (None: nothing proved) once ``deadline`` passes, row by row."""
    n = lo.size
    z, y = exact[:m_G], exact[m_G:]
    Gc, Ac = G.tocsr(), A.tocsr()
    work = sum(Gc.indptr[i + 1] - Gc.indptr[i] for i in range(Gc.shape[0]) if z[i]) + \
        sum(Ac.indptr[i + 1] - Ac.indptr[i] for i in range(Ac.shape[0]) if y[i])
    if work > EXACT_WORK:
        return None
    r = [Fraction(0)] * n
    c = Fraction(0)
    for M, rhs, w in ((Gc, h, z), (Ac, b, y)):
        for i in range(M.shape[0]):
            if not w[i]:
                continue
            if deadline is not None and deadline.expired():
                return None
            c += Fraction(float(rhs[i])) * w[i]
            for p in range(M.indptr[i], M.indptr[i + 1]):
                r[M.indices[p]] += Fraction(float(M.data[p])) * w[i]
    used = {"lower": 0, "upper": 0}
    for j in range(n):
        if r[j] > 0:      # cancelled by μl_j = r_j >= 0 on a finite lower bound
            if not np.isfinite(lo[j]):
                return None
            c -= Fraction(float(lo[j])) * r[j]
            used["lower"] += 1
        elif r[j] < 0:    # cancelled by μu_j = -r_j >= 0 on a finite upper bound
            if not np.isfinite(hi[j]):
                return None
            c -= Fraction(float(hi[j])) * r[j]
            used["upper"] += 1
    if not c < 0:
        return None
    zf = np.array([float(v) for v in z])
    yf = np.array([float(v) for v in y])
    rf = np.array([float(v) for v in r])
    parts = [f"{name}: {count}" for name, count in
             (("inequality rows", int(np.count_nonzero(zf))), ("equality rows", int(np.count_nonzero(yf))),
              ("lower bounds", used["lower"]), ("upper bounds", used["upper"])) if count]
    return Proof(
        kind="infeasible",
        message=("no x satisfies the constraints: the weighted sum of " + ", ".join(parts)
                 + f" reads 0 <= {float(c):.3e} (a Farkas vector, checked from the data in exact "
                 "rational arithmetic)"),
        vector={"z": zf, "y": yf, "lower": np.maximum(rf, 0.0), "upper": np.maximum(-rf, 0.0),
                # the weights as checked (rationals; the floats above may round them)
                "exact": {"z": list(z), "y": list(y)}},
    )


def exact_ray(P, q, G, A, dF, lo, hi, deadline=None) -> bool:
    """Pd = 0, Gd <= 0, Ad = 0, q'd < 0 and d's signs, in exact arithmetic
    (False, nothing proved, once ``deadline`` passes)."""
    support = [j for j, v in enumerate(dF) if v]
    if not support:
        return False
    for j in support:
        if (dF[j] > 0 and hi[j] == 0.0) or (dF[j] < 0 and lo[j] == 0.0):
            return False
    if sum(Fraction(float(q[j])) * dF[j] for j in support) >= 0:
        return False
    for M, sign in ((P, 0), (G, -1), (A, 0)):
        if not M.shape[0]:
            continue
        Mc = sp.csc_matrix(M)
        if sum(Mc.indptr[j + 1] - Mc.indptr[j] for j in support) > EXACT_WORK:
            return False
        acc: dict[int, Fraction] = {}
        for j in support:
            if deadline is not None and deadline.expired():
                return False
            for p in range(Mc.indptr[j], Mc.indptr[j + 1]):
                i = Mc.indices[p]
                acc[i] = acc.get(i, Fraction(0)) + Fraction(float(Mc.data[p])) * dF[j]
        if sign == 0 and any(v != 0 for v in acc.values()):
            return False
        if sign < 0 and any(v > 0 for v in acc.values()):
            return False
    return True
