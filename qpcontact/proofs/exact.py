"""Exact checks of proofs, in integer arithmetic.

The data's doubles are rationals — each is an integer times a power of two —
so a Farkas vector's weighted sum of constraints, or a ray's products with
the data, are computed without rounding: every array of doubles becomes
Python integers times one power of two (:class:`IntMatrix`, :func:`ints`),
a candidate's rational weights are put over one common denominator, and the
products and sums are taken on NumPy object arrays of Python integers, a
block of rows at a time with the deadline looked at between blocks (a
candidate that cannot be checked before it says nothing: not proved).  The
signs of the results are exact.  Fractions, row by row, took 58 s past a 5 s
limit on a 235-row LCP; the integers take milliseconds.

A candidate from a linear program is tried as it came and snapped to small
denominators (which recovers the exact weights of integer data: 1/3 rather
than 0.3333...); a candidate that fails a loose check in floating point is
not checked exactly (that check can only reject: a vector that holds exactly
holds to within rounding).  A check in floating point is never a proof: with
a rounded r ≈ 1e-16 a Farkas vector only rules out feasible points up to
|c| / ‖r‖₁, and on a badly scaled but solvable LCP the solution lay beyond
that (a false "infeasible", caught by ``qpcontact stress``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import scipy.sparse as sp

__all__ = ["Proof", "EXACT_WORK", "candidates", "snap", "exact_farkas", "exact_ray",
           "FarkasCheck", "RayCheck", "IntMatrix", "ints", "over_common_denominator",
           "exactly_within", "solve_integer"]


#: nonzero products an exact check may take; beyond it no proof is claimed
#: (a rounded check is not a proof).  A million products of a dense
#: 1 000 x 1 000 matrix take about a second of integer work.
EXACT_WORK = 4_000_000

#: products per block between two looks at the deadline
_BLOCK = 100_000

#: how far a candidate may miss its conditions in floating point (relative to
#: each component's own terms) and still be checked exactly; rounding of the
#: floating-point products is below 1e-12 of those terms up to n = 1e4
_LOOSE = 1e-7


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
    """Exact rational vectors near ``values``, simplest first, each once; none
    more once ``deadline`` (a :class:`~qpcontact.core.deadline.Deadline`) has
    passed."""
    top = float(np.max(np.abs(values), initial=0.0))
    seen = set()
    common = _common_denominator(values / top) if top > 0 and np.all(np.isfinite(values)) \
        else None
    if common is not None:
        seen.add(tuple(common))
        yield common
    for tiny in _ZEROS:
        cut = np.where(np.abs(values) <= tiny * top, 0.0, values)
        for limit in _SNAPS:
            if deadline is not None and deadline.expired():
                return
            cand = snap(cut, limit)
            key = tuple(cand)
            if key not in seen:
                seen.add(key)
                yield cand


#: common denominators tried at once (vectorised) before the snaps one
#: component at a time: a vector of small integers over its largest entry
_COMMON = 256


def _common_denominator(v: np.ndarray) -> list | None:
    """k / D for the smallest D <= _COMMON that puts every component of
    ``v`` (largest entry ±1) within 1e-6 of an integer, or None: the exact
    null vectors and Farkas vectors of integer data, found in one NumPy pass
    (snapping 250 components one by one took a second per candidate)."""
    D = np.arange(1, _COMMON + 1, dtype=float)[:, None]
    scaled = v[None, :] * D
    ok = np.flatnonzero(np.max(np.abs(scaled - np.round(scaled)), axis=1) <= 1e-6)
    if not ok.size:
        return None
    d = int(ok[0]) + 1
    return [Fraction(int(k), d) for k in np.round(v * d)]


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


def ints(values) -> tuple[np.ndarray, int]:
    """(I, e) with ``values == I * 2**e`` exactly: I an object array of Python
    integers, e one exponent (the doubles' trailing zero bits stripped, so
    integer data stay small integers).  Nonfinite entries are read as 0: the
    caller masks them."""
    out, e0, _ = _ints(values)
    return out, e0


def _ints(values, python=True) -> tuple[np.ndarray | None, int, np.ndarray | None]:
    """:func:`ints`, and the same integers as int64 when all of them fit in
    62 bits (else None).  ``python=False``: the object array only where the
    int64 one cannot be made (None otherwise) — a million Python integers
    took a second of a proof at n = 1 000 that the int64 products did not
    need."""
    v = np.asarray(values, dtype=float).ravel()
    v = np.where(np.isfinite(v), v, 0.0)
    out = np.zeros(v.size, dtype=object) if python else None
    m, e = np.frexp(v)
    mant = np.ldexp(m, 53).astype(np.int64)
    nz = mant != 0
    if not nz.any():
        return out, 0, np.zeros(v.size, dtype=np.int64)
    mant, e = mant[nz], e[nz].astype(np.int64) - 53
    low = mant & -mant
    tz = np.frexp(low.astype(float))[1].astype(np.int64) - 1
    mant, e = mant >> tz, e + tz
    e0 = int(e.min())
    shift = e - e0
    bits = np.frexp(np.abs(mant).astype(float))[1].astype(np.int64) + shift
    if int(bits.max()) <= 62:
        small = np.zeros(v.size, dtype=np.int64)
        small[nz] = mant << shift
        if out is not None:
            out[nz] = small[nz].astype(object)
        return out, e0, small
    if out is None:
        out = np.zeros(v.size, dtype=object)
    out[nz] = np.left_shift(mant.astype(object), shift.astype(object))
    return out, e0, None


def over_common_denominator(weights) -> tuple[np.ndarray, int]:
    """(W, D): the rationals ``weights`` as W / D, W an object array of
    Python integers, D > 0 their least common denominator."""
    fr = [w if isinstance(w, Fraction) else Fraction(w) for w in weights]
    D = math.lcm(*(f.denominator for f in fr)) if fr else 1
    return np.array([f.numerator * (D // f.denominator) for f in fr] or [0],
                    dtype=object)[:len(fr)], D


def _scaled_sum(terms) -> tuple[int, int]:
    """(s, e0) with Σ v·2^e = s·2^e0 over (v, e) pairs of Python integers,
    e0 the smallest e of a nonzero v: s has the sum's sign."""
    terms = [(v, e) for v, e in terms if v]
    if not terms:
        return 0, 0
    e0 = min(e for _, e in terms)
    return sum(v << (e - e0) for v, e in terms), e0


class IntMatrix:
    """A sparse matrix's doubles as Python integers times one power of two
    (row-major), for exact products with integer vectors."""

    def __init__(self, M):
        M = sp.csr_matrix(M, dtype=float)
        M.sum_duplicates()
        M.eliminate_zeros()
        self.float = M
        self.abs = abs(M)
        self.shape, self.nnz = M.shape, M.nnz
        self.indptr, self.indices = M.indptr, M.indices
        self._data, self.exp, small = _ints(M.data, python=False)
        self._small_data = small
        # the same in int64 (and how many bits its entries take), for
        # products that cannot overflow
        self.small = None if small is None else sp.csr_matrix(
            (small, M.indices, M.indptr), shape=M.shape)
        self.bits = 0 if small is None or not small.size else int(
            np.max(np.abs(small))).bit_length()

    @property
    def data(self) -> np.ndarray:
        """The entries as Python integers (made on first use: the int64
        products need none)."""
        if self._data is None:
            self._data = self._small_data.astype(object)
        return self._data

    def times(self, W: np.ndarray, deadline=None) -> np.ndarray | None:
        """M·W exactly, in units of 2^exp (an object array of Python
        integers), a block of rows at a time; None once ``deadline`` passes."""
        rows = self.shape[0]
        out = np.zeros(rows, dtype=object)
        if deadline is not None and deadline.expired():
            return None
        if not self.nnz or not np.any(W != 0):
            return out
        if self.small is not None:
            wbits = max(int(v).bit_length() for v in (max(W), min(W)))
            longest = int(np.max(np.diff(self.indptr)))
            if self.bits + wbits + longest.bit_length() <= 62:    # no int64 sum can overflow
                return (self.small @ W.astype(np.int64)).astype(object)
        lens = np.diff(self.indptr)
        r0 = 0
        while r0 < rows:
            if deadline is not None and deadline.expired():
                return None
            p0 = self.indptr[r0]
            r1 = int(np.searchsorted(self.indptr, p0 + _BLOCK, side="right")) - 1
            r1 = min(max(r1, r0 + 1), rows)
            busy = r0 + np.flatnonzero(lens[r0:r1])
            if busy.size:
                p1 = self.indptr[r1]
                prod = self.data[p0:p1] * W[self.indices[p0:p1]]
                out[busy] = np.add.reduceat(prod, self.indptr[busy] - p0)
            r0 = r1
        return out


def _floats(exact) -> np.ndarray:
    return np.array([float(v) for v in exact], dtype=float)


def _as_float(v: int, e: int, D: int) -> float:
    """v·2^e / D as the nearest double (inf beyond range)."""
    try:
        return float(Fraction(v, D) * Fraction(2) ** e)
    except OverflowError:
        return math.copysign(math.inf, v)


def _scientific(x: Fraction) -> str:
    """A rational in scientific notation, three digits, also below the
    doubles' range (where float() would print a negative as -0)."""
    f = float(x)
    if f != 0.0 or x == 0:
        return f"{f:.3e}"
    k = math.floor(math.log10(abs(x.numerator)) - math.log10(x.denominator))
    return f"{float(x / Fraction(10) ** k):.3f}e{k:+d}"


class FarkasCheck:
    """Farkas vectors of {Gx <= h, Ax = b, lo <= x <= hi}, checked exactly
    (the data turned into integers once, for every candidate): r = G'z + A'y,
    the bound multipliers that cancel it (μl = r⁺ on finite lower bounds,
    μu = r⁻ on finite upper ones) and c = h'z + b'y − lo'μl + hi'μu < 0.
    Sound: a vector that passes proves that the data as stored admit no x."""

    def __init__(self, G, h, A, b, lo, hi):
        self.m_G = G.shape[0]
        self.lo, self.hi = np.asarray(lo, float), np.asarray(hi, float)
        self.h, self.b = np.asarray(h, float), np.asarray(b, float)
        self.work = sp.csr_matrix(G).nnz + sp.csr_matrix(A).nnz
        self._int = None
        self._G, self._A = G, A

    def _prepare(self):
        if self._int is None:
            self._int = (IntMatrix(sp.csr_matrix(self._G).T), IntMatrix(sp.csr_matrix(self._A).T),
                         ints(self.h), ints(self.b), ints(self.lo), ints(self.hi))
        return self._int

    def check(self, exact, deadline=None) -> Proof | None:
        """The proof for the rational weights ``exact`` (z for G's rows, then
        y for A's), or None: they fail, or the check would pass ``deadline``
        or :data:`EXACT_WORK` products (nothing proved)."""
        if self.work > EXACT_WORK or (deadline is not None and deadline.expired()):
            return None
        z, y = list(exact[:self.m_G]), list(exact[self.m_G:])
        if any(v < 0 for v in z) or not any(v for v in exact):
            return None
        zf, yf = _floats(z), _floats(y)
        # rows with an infinite right-hand side prove nothing (read on the
        # rationals: a weight may round to 0.0 as a double)
        if any(z[i] for i in np.flatnonzero(~np.isfinite(self.h))) or \
                any(y[i] for i in np.flatnonzero(~np.isfinite(self.b))):
            return None
        GT, AT, (hI, eh), (bI, eb), (loI, elo), (hiI, ehi) = self._prepare()
        if not self._plausible(GT, AT, zf, yf):
            return None
        W, D = over_common_denominator(z + y)
        Wz, Wy = W[:self.m_G], W[self.m_G:]
        rG = GT.times(Wz, deadline)
        rA = None if rG is None else AT.times(Wy, deadline)
        if rA is None:
            return None
        e0 = min(GT.exp, AT.exp)
        r = rG * (1 << (GT.exp - e0)) + rA * (1 << (AT.exp - e0))    # r = this · 2^e0 / D
        pos = np.array([v > 0 for v in r], dtype=bool)
        neg = np.array([v < 0 for v in r], dtype=bool)
        if np.any(pos & ~np.isfinite(self.lo)) or np.any(neg & ~np.isfinite(self.hi)):
            return None
        terms = [(int(np.dot(hI, Wz)) if Wz.size else 0, eh),
                 (int(np.dot(bI, Wy)) if Wy.size else 0, eb),
                 (-int(np.dot(loI[pos], r[pos])) if pos.any() else 0, elo + e0),
                 (-int(np.dot(hiI[neg], r[neg])) if neg.any() else 0, ehi + e0)]
        s, es = _scaled_sum(terms)
        if not s < 0:
            return None
        rf = np.array([_as_float(int(v), e0, D) for v in r])
        # the right-hand side the message shows is the exact one, s 2^es / D:
        # recomputed in floating point it cancels, and a rank-deficient M's
        # proof read "0 <= 0.000e+00"
        c_exact = Fraction(s) * Fraction(2) ** es / D
        parts = [f"{name}: {count}" for name, count in
                 (("inequality rows", int(np.count_nonzero(zf))),
                  ("equality rows", int(np.count_nonzero(yf))),
                  ("lower bounds", int(pos.sum())), ("upper bounds", int(neg.sum()))) if count]
        return Proof(
            kind="infeasible",
            message=("no x satisfies the constraints: the weighted sum of " + ", ".join(parts)
                     + f" reads 0 <= {_scientific(c_exact)} (a Farkas vector, checked from the "
                     "data in exact rational arithmetic)"),
            vector={"z": zf, "y": yf, "lower": np.maximum(rf, 0.0), "upper": np.maximum(-rf, 0.0),
                    # the weights as checked (rationals; the floats above may round them)
                    "exact": {"z": z, "y": y}},
        )

    def _plausible(self, GT, AT, zf, yf) -> bool:
        """The conditions to within _LOOSE of each component's own terms, in
        floating point: a vector that holds exactly passes (this only saves
        the exact check of one that cannot)."""
        with np.errstate(all="ignore"):
            r = GT.float @ zf + AT.float @ yf
            scale = GT.abs @ np.abs(zf) + AT.abs @ np.abs(yf)
            if not (np.all(np.isfinite(r)) and np.all(np.isfinite(scale))):
                return True          # beyond double range: the exact check decides
            slack = _LOOSE * scale
            up, down = r > slack, r < -slack
            if np.any(up & ~np.isfinite(self.lo)) or np.any(down & ~np.isfinite(self.hi)):
                return False
            lo = np.where(np.isfinite(self.lo), self.lo, 0.0)
            hi = np.where(np.isfinite(self.hi), self.hi, 0.0)
            hz = np.where(np.isfinite(self.h), self.h, 0.0)
            bz = np.where(np.isfinite(self.b), self.b, 0.0)
            c = hz @ zf + bz @ yf - lo @ np.maximum(r, 0.0) - hi @ np.minimum(r, 0.0)
            c_scale = (np.abs(hz) @ np.abs(zf) + np.abs(bz) @ np.abs(yf)
                       + np.maximum(np.abs(lo), np.abs(hi)) @ (np.abs(r) + slack))
            if not (np.isfinite(c) and np.isfinite(c_scale)):
                return True
            return bool(c <= _LOOSE * c_scale)


def exact_farkas(G, h, A, b, lo, hi, exact, m_G, deadline=None) -> Proof | None:
    """One candidate checked by a :class:`FarkasCheck` (``m_G``: G's rows);
    a loop over candidates should make the check once and call it."""
    return FarkasCheck(G, h, A, b, lo, hi).check(exact, deadline)


class RayCheck:
    """Rays d of {Gx <= h, Ax = b, lb <= x <= ub} along which ½x'Px + q'x
    falls for ever, checked exactly: Pd = 0, Gd <= 0, Ad = 0, q'd < 0 and
    d's signs (``lo``/``hi``: 0 where the bound is finite)."""

    def __init__(self, P, q, G, A, lo, hi):
        self._blocks = [(M, sign) for M, sign in ((P, 0), (G, -1), (A, 0))
                        if M is not None and M.shape[0]]
        self._parts = None
        self.q = np.asarray(q, float)
        self.lo, self.hi = lo, hi

    @property
    def parts(self):
        if self._parts is None:      # the integers once, at the first candidate
            self._parts = [(IntMatrix(M), sign) for M, sign in self._blocks]
        return self._parts

    def check(self, dF, deadline=None) -> bool:
        """Whether the rationals ``dF`` are such a ray (False, nothing proved,
        beyond EXACT_WORK products or once ``deadline`` passes)."""
        if deadline is not None and deadline.expired():
            return False
        df = _floats(dF)
        # d's signs from the rationals (a component may round to 0.0)
        sign = np.array([(v > 0) - (v < 0) for v in dF], dtype=int)
        if not sign.any() or sum(sp.csr_matrix(M).nnz for M, _ in self._blocks) > EXACT_WORK:
            return False
        if np.any((sign > 0) & (self.hi == 0.0)) or np.any((sign < 0) & (self.lo == 0.0)):
            return False
        with np.errstate(all="ignore"):
            for M, sign in self.parts:     # the loose floating-point screen
                v, scale = M.float @ df, M.abs @ np.abs(df)
                if np.all(np.isfinite(v)) and np.all(np.isfinite(scale)):
                    bad = v > _LOOSE * scale if sign else np.abs(v) > _LOOSE * scale
                    if np.any(bad):
                        return False
            qd, qs = float(self.q @ df), float(np.abs(self.q) @ np.abs(df))
            if np.isfinite(qd) and np.isfinite(qs) and qd > _LOOSE * qs:
                return False
        W, _ = over_common_denominator(dF)
        qI, _ = ints(self.q)
        if not int(np.dot(qI, W)) < 0:
            return False
        for M, sign in self.parts:
            v = M.times(W, deadline)
            if v is None:
                return False
            if sign == 0 and any(x != 0 for x in v):
                return False
            if sign < 0 and any(x > 0 for x in v):
                return False
        return True


def exact_ray(P, q, G, A, dF, lo, hi, deadline=None) -> bool:
    """One candidate checked by a :class:`RayCheck`."""
    return RayCheck(P, q, G, A, lo, hi).check(dF, deadline)


def exactly_within(M, x, rhs, equal: bool, deadline=None) -> bool:
    """Whether Mx = rhs (``equal``) or Mx <= rhs holds exactly for the
    doubles x (False once ``deadline`` passes or beyond EXACT_WORK)."""
    Mi = IntMatrix(M)
    if Mi.nnz > EXACT_WORK or not np.all(np.isfinite(rhs)):
        return False
    X, ex = ints(x)
    R, er = ints(rhs)
    v = Mi.times(X, deadline)
    if v is None:
        return False
    e0 = min(Mi.exp + ex, er)
    diff = v * (1 << (Mi.exp + ex - e0)) - R * (1 << (er - e0))
    return all(d == 0 for d in diff) if equal else all(d <= 0 for d in diff)


def solve_integer(A: np.ndarray, b: np.ndarray, deadline=None) -> list[Fraction] | None:
    """x with A x = b exactly, A a square object array of Python integers and
    b a vector of them; None when A is singular or ``deadline`` passes first.

    Fraction-free (Bareiss) elimination: each step's entries are minors of
    A, so the integers grow to n times A's bits and no larger (Fractions
    would grow their denominators step by step).  A step is one product
    over the whole trailing block, and the deadline is looked at between
    steps."""
    n = A.shape[0]
    R = np.empty((n, n + 1), dtype=object)
    R[:, :n], R[:, n] = A, b
    prev = 1
    for k in range(n):
        if deadline is not None and deadline.expired():
            return None
        nz = [i for i in range(k, n) if R[i, k] != 0]
        if not nz:
            return None
        if nz[0] != k:
            R[[k, nz[0]]] = R[[nz[0], k]]
        piv = R[k, k]
        if k + 1 < n:
            R[k + 1:, k + 1:] = (R[k + 1:, k + 1:] * piv
                                 - np.outer(R[k + 1:, k], R[k, k + 1:])) // prev
            R[k + 1:, k] = 0
        prev = piv
    # back-substitution in integers: X = det(A) x is an integer vector
    # (Cramer), and the last pivot is det(A) up to the rows' swaps; Fractions
    # here (a gcd of 1 700-bit integers per step) took most of the solve
    det = R[n - 1, n - 1]
    X = [0] * n
    for i in range(n - 1, -1, -1):
        acc = det * R[i, n] - sum(R[i, j] * X[j] for j in range(i + 1, n) if R[i, j])
        X[i], rem = divmod(acc, R[i, i])
        if rem:                 # cannot happen in exact arithmetic: refuse rather than guess
            return None
    return [Fraction(v, det) for v in X]
