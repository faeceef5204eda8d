"""The Euler–Bernoulli beam-column whose axial force varies along it: a
member whose own loads have parts along its axis (a column's self-weight,
a point load along it) carries N(x), not the constant N of
:mod:`.beam_column`'s stability functions.

The mechanics.  On the flexible length [0, L] (member axes, as
:mod:`.beam_column`'s) the deflection v(x) [L] under the transverse load
q(x) [F/L] obeys, equilibrium on the deformed axis,

    EI v'''' − (N(x) v')' = q(x),

with N(x) [F] (tension positive) = N̄ + n(x) − (n(−o_i) + n(L + o_j))/2:
N̄ the mean of its nodes' end forces that the frame's fixed point
iterates (:func:`.second_order_path.axial_forces`), n(x) = −∫ p − Σ P the
statics of the axial loads p (distributed, along +x) and P (points) from
node i, x = −o_i, to x — the rigid end zones' (o_i, o_j) loads included:
a zone under its share of a column's weight carries it to the node, so
the flexible length's mean is not N̄ (taken on its own ends, a 5 m
cantilever with a 0.625 m top zone under 0.7 of Greenhill's load had α_cr
1.68 for 1.43 and its base moment 25 % low).  A zone's own P-Δ is
θ ∫_zone N dx (:meth:`Member.arms`).  The
transverse force across the undeformed axis, T = EI v''' − N v', jumps by
a transverse point force and is continuous where only N jumps (an axial
point load); EI v'' jumps by minus a point couple.

The solution.  Between load positions N is a polynomial of degree ≤ 2 and
q of degree ≤ 1, so on each piece [x₀, x₀ + h] the solution is an entire
function, written as its Taylor series in σ = (x − x₀)/h: with
w = Σ A_n σⁿ and N = ν₀ + ν₁ σ + ν₂ σ², β_i = h² ν_i / EI,

    (m+1)(m+2)(m+3)(m+4) A_{m+4} = β₁ B_m + 2 β₂ B_{m−1} + β₀ C_m
                                   + β₁ C_{m−1} + β₂ C_{m−2} + h⁴ q_m / EI,

B_j = (j+1) A_{j+1}, C_j = (j+1)(j+2) A_{j+2} (the coefficients of w' and
w'').  Pieces are cut so that |N| h² ≤ EI everywhere on them (|β| ≤ 1):
then |A_n| falls like 1/n!, and TERMS terms are exact to rounding (the
last one 1e-30 of the first).  Four homogeneous solutions (unit initial
w, w', w'', w''') and the particular one (zero initial data) give each
piece's exact stiffness on its ends' (v, θ) and its clamped end forces;
the pieces are joined as a chain (continuity of v, θ; the forces at the
joints balanced, a point load there a nodal load of the joint) and the
joints condensed out: the member's 4 × 4 stiffness on (v_i, θ_i, v_j,
θ_j), its consistent nodal loads, and, from its end displacements, each
piece's series — v, v' and the second-order moment ∫₀ˣ N v' dx (the
section moment on the deformed axis is the first-order statics' plus it;
N (v(x) − v(0)) for constant N) between the ends.  Nothing is
interpolated: the series are the solution.  With N constant it is the
stability functions' member (tests: to ~1e-12), a different route.
"""

from __future__ import annotations

import copy

import numpy as np

from .end_releases import released_ends
from .loads import clipped

#: Taylor terms per piece at most (|β| ≤ 1: 22 make the tail 1e-19 of the
#: first; the series stops once four terms in a row are below TAIL of the
#: largest, each solution's own: a short piece under little N needs ten)
TERMS = 32

#: the share of a solution's largest coefficient below which its tail is dropped
TAIL = 1e-19

#: the largest |N| h² / EI of a piece
PIECE = 1.0


def along_axis(load, L, c, s, oi, oj):
    """A member load's part along the axis node to node (positions from
    the flexible length's start, the zones' negative or beyond it):
    ("point", a, P) or ("distributed", a, b, p₁, p₂), member axes; None
    where it has none."""
    flex = clipped(load, 0.0, L, shift=oi)
    if flex is None:
        return None
    v = flex.values

    def axial(fx, fy):
        return fx if load.axes == "member" else c * fx + s * fy
    if flex.kind == "point":
        P = axial(v[0], v[1])
        return ("point", flex.a, P) if P else None
    p1, p2 = axial(v[0], v[1]), axial(v[2], v[3])
    return ("distributed", flex.a, flex.b, p1, p2) if (p1 or p2) and flex.b > flex.a else None


def of_member(m, L, c, s, Nbar, along, series=True):
    """The :class:`Member` of a plane member ``m`` (node-to-node length L,
    direction (c, s)) under N̄ where its loads in the combination ``along``
    have axial parts (on its rigid end zones too: its flexible length's N
    is then not N̄); None where none do (or it is shear-flexible: its
    element keeps the mean N)."""
    if not along or m.GAs is not None:
        return None
    oi, oj = m.offset_i, m.offset_j
    parts = [part[:-2] + tuple(along[ld.case] * np.array(part[-2:]))
             if part[0] == "distributed" else part[:2] + (along[ld.case] * part[2],)
             for ld in m.loads if along.get(ld.case)
             for part in [along_axis(ld, L, c, s, oi, oj)] if part]
    if not parts:
        return None
    return Member(m.E * m.I, L - oi - oj, Nbar, parts,
                  [x - oi for ld in m.loads for x in (ld.a, ld.b)], series, (oi, oj))


def least_axial(frame, N, along) -> np.ndarray:
    """Per member its least N along it (its largest compression): N where
    it is constant (a shear-flexible member, no axial loads in the
    combination ``along``), the least of N(x) on its pieces elsewhere —
    what bounds its own buckling with its nodes held from below (Rayleigh:
    a member nowhere more compressed than a constant N buckles no earlier
    than under it)."""
    out = np.array(N, float)
    for k, member in members_under(frame, N, along).items():
        out[k] = member.least()
    return out


def members_under(frame, N, along):
    """{index: the member's chain(s) under N(x)} of a frame's members whose
    loads in ``along`` make N vary along them, each under its N̄ = N[index]
    (:func:`member_under`)."""
    out = {}
    for k, name in enumerate(frame.members):
        member = member_under(frame, name, float(N[k]), along)
        if member is not None:
            out[k] = member
    return out


def member_under(frame, name, Nbar, along):
    """The chain(s) under N(x) of the frame's member ``name`` under N̄ where
    its loads in ``along`` make N vary along it, else None: a plane
    member's :class:`Member` (:func:`plane_member`), a space member's two
    bending planes (the frame's kind's ``member_under``), each with
    ``least()`` and ``own_negatives(springs)``."""
    return frame.kind.member_under(frame, name, Nbar, along) if along else None


def plane_member(frame, name, Nbar, along):
    """:func:`of_member` of one of a plane frame's members, from its nodes
    (the plane frame's kind's ``member_under``)."""
    m = frame.members[name]
    if not m.loads or not along:
        return None
    d = np.subtract(frame.nodes[m.j], frame.nodes[m.i]).astype(float)
    L = float(np.hypot(*d))
    return of_member(m, L, d[0] / L, d[1] / L, Nbar, along)


def end_springs(m):
    """A plane member's end springs (i, j) for :meth:`Member.own_negatives`;
    None for a space member, whose two planes keep their own."""
    return None if isinstance(m, dict) else m.end_springs


def own_buckling_factors(frame, N, along, bound, rtol=1e-10) -> np.ndarray:
    """``bound`` (a factor α per member below which it cannot buckle on its
    own with its nodes held: own_buckling over its largest compression)
    with each member whose loads make N vary along it given its own factor
    instead: the least α at which its chain under α N(x), its nodes held
    (rigid joints' rotations too, a released end's on its spring), has a
    negative eigenvalue (:meth:`Member.own_negatives`), by doubling from
    its bound and bisecting to ``rtol``.  Only those whose bound is below
    the least factor found so far are searched (the frame's search stops
    at the least)."""
    out = np.array(bound, float)
    names = list(frame.members)
    ms = list(frame.members.values())
    varying = sorted(members_under(frame, N, along), key=lambda k: out[k])
    best = np.inf
    for k in varying:
        if not out[k] < best:
            break

        def buckled(alpha):
            member = member_under(frame, names[k], alpha * float(N[k]),
                                  {c: alpha * f for c, f in along.items()})
            return member is not None and member.own_negatives(end_springs(ms[k])) > 0
        lo = out[k] if np.isfinite(out[k]) else 1.0
        hi = 2.0 * lo
        while not buckled(hi):
            lo, hi = hi, 2.0 * hi
            if hi > 1e6 * max(out[k], 1.0):
                hi = np.inf
                break
        while np.isfinite(hi) and hi - lo > rtol * hi:
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if buckled(mid) else (mid, hi)
        out[k] = hi
        best = min(best, hi)
    return out


def variation(axial_parts, centre, x, right=True) -> np.ndarray:
    """N(x) − N̄ of the axial parts ``axial_parts`` (:func:`along_axis`, each
    times its factor) at x: n(x) less the mean of the nodes' (``centre``,
    :func:`_centre`; module docstring); a point load at x counted on the
    right side (``right``)."""
    return _statics(axial_parts, np.asarray(x, float), right) - centre


def _statics(axial_parts, at, right):
    """n(at): minus the axial loads up to ``at`` (a point load there on the
    right side where ``right``)."""
    out = np.zeros_like(at)
    for part in axial_parts:
        if part[0] == "point":
            _, a, P = part
            out -= P * ((at >= a) if right else (at > a))
            continue
        _, a, b, p1, p2 = part
        t = np.clip(at, a, b) - a
        out -= p1 * t + 0.5 * (p2 - p1) * t * t / (b - a)
    return out


def _centre(axial_parts, ends):
    """The mean of n at the nodes ``ends``, a point load at a node on the
    member's side (the node's load: fixed-end forces put it there)."""
    lo, hi = ends
    return 0.5 * (_statics(axial_parts, np.array([lo]), False)[0]
                  + _statics(axial_parts, np.array([hi]), True)[0])


def _statics_integral(axial_parts, at) -> np.ndarray:
    """∫ n dx from below every load to ``at`` (n piecewise quadratic: exact)."""
    at = np.asarray(at, float)
    out = np.zeros_like(at)
    for part in axial_parts:
        if part[0] == "point":
            _, a, P = part
            out -= P * np.maximum(at - a, 0.0)
            continue
        _, a, b, p1, p2 = part
        slope = (p2 - p1) / (b - a)
        t = np.clip(at, a, b) - a
        T = b - a
        out -= (p1 * t * t / 2 + slope * t ** 3 / 6
                + (p1 * T + 0.5 * slope * T * T) * np.maximum(at - b, 0.0))
    return out


def _cuts(EI, L, Nbar, axial_parts, points, centre):
    """The pieces' edges: the load positions ``points`` and cuts that keep
    |N| h² ≤ PIECE EI (module docstring)."""
    edges = np.unique(np.r_[0.0, [p for p in points if 0.0 < p < L], L])
    # |N| on each stretch from 9 points (both sides of its ends)
    xs = edges[:-1, None] + np.diff(edges)[:, None] * np.linspace(0.0, 1.0, 9)
    big = np.maximum(np.abs(Nbar + variation(axial_parts, centre, xs)),
                     np.abs(Nbar + variation(axial_parts, centre, xs, False))).max(axis=1)
    n = np.maximum(1, np.ceil(np.diff(edges) * np.sqrt(big / (PIECE * EI)) * 1.05)).astype(int)
    if not np.any(n > 1):
        return edges
    return np.concatenate([edges[:1]] + [np.linspace(a, b, k + 1)[1:]
                                         for a, b, k in zip(edges[:-1], edges[1:], n)])


def _load_on(parts, lo, hi):
    """(q₀, q₁): the transverse distributed load on [lo, hi] as q₀ + q₁ (x − lo)."""
    q0 = q1 = 0.0
    for part in parts:
        if part[0] != "distributed":
            continue
        _, a, b, w1, w2 = part
        if a <= lo and hi <= b and b > a:
            slope = (w2 - w1) / (b - a)
            q0 += w1 + slope * (lo - a)
            q1 += slope
    return q0, q1


def _series(beta, qt) -> np.ndarray:
    """(P, 5, TERMS): each piece's four homogeneous solutions and its
    particular one (zero initial data) as Taylor coefficients in σ;
    ``beta`` (P, 3), ``qt`` (P, 2) h⁴ (q₀, q₁ h)/EI."""
    P = beta.shape[0]
    A = np.zeros((P, 5, TERMS))
    for k in range(4):
        A[:, k, k] = 1.0
    b0, b1, b2 = (beta[:, i:i + 1] for i in range(3))
    for m in range(TERMS - 4):
        rhs = (b1 * (m + 1) * A[..., m + 1] + 2 * b2 * m * A[..., m]
               + b0 * (m + 2) * (m + 1) * A[..., m + 2] + b1 * (m + 1) * m * A[..., m + 1]
               + b2 * m * (m - 1) * A[..., m])
        if m < 2:
            rhs[:, 4] += qt[:, m]
        A[..., m + 4] = rhs / ((m + 1) * (m + 2) * (m + 3) * (m + 4))
        if m % 4 == 3 and np.all(np.abs(A[..., m + 1:m + 5]).max(axis=-1)
                                 <= TAIL * np.abs(A[..., :m + 1]).max(axis=-1)):
            break
    return A


_N = np.arange(TERMS, dtype=float)


def _ends(A, h):
    """(w, w', w'', w''') at σ = 0 and 1 of coefficients A (…, TERMS), x-derivatives."""
    at0 = np.stack([A[..., 0], A[..., 1] / h, 2 * A[..., 2] / h ** 2, 6 * A[..., 3] / h ** 3])
    d1 = _N
    d2 = _N * (_N - 1)
    d3 = d2 * (_N - 2)
    at1 = np.stack([A.sum(-1), (A * d1).sum(-1) / h, (A * d2).sum(-1) / h ** 2,
                    (A * d3).sum(-1) / h ** 3])
    return at0, at1


class Member:
    """One member's chain of pieces under N(x) (module docstring): EI, its
    flexible length L, N̄, the axial parts (times their factors), the
    positions where its loads start, end or act and its rigid end zones'
    lengths ``zones`` (o_i, o_j)."""

    def __init__(self, EI, L, Nbar, axial_parts, points, series=True, zones=(0.0, 0.0)):
        self.EI, self.L, self.axial_parts = float(EI), float(L), list(axial_parts)
        self.zones = (float(zones[0]), float(zones[1]))
        self.ends = (-self.zones[0], self.L + self.zones[1])
        self.centre = _centre(self.axial_parts, self.ends)
        self.x = _cuts(EI, L, Nbar, self.axial_parts, points, self.centre)
        lo, hi = self.x[:-1], self.x[1:]
        self.h = hi - lo
        self.Nbar = float(Nbar)
        # N on each piece through σ = 0 (its right limit), ½ and 1 (its left):
        # a polynomial of degree ≤ 2 there
        pts = lo[:, None] + self.h[:, None] * np.array([0.0, 0.5, 1.0])
        Nv = Nbar + np.c_[variation(self.axial_parts, self.centre, pts[:, 0], True),
                          variation(self.axial_parts, self.centre, pts[:, 1:], False)]
        # ν₀ + ν₁ σ + ν₂ σ² through σ = 0, ½, 1
        self.nu = np.stack([Nv[:, 0], -3 * Nv[:, 0] + 4 * Nv[:, 1] - Nv[:, 2],
                            2 * Nv[:, 0] - 4 * Nv[:, 1] + 2 * Nv[:, 2]], axis=1)
        self.beta = self.h[:, None] ** 2 * self.nu / self.EI
        if series:        # else by :func:`in_one_pass` with other members'
            self.solutions(_series(self.beta, np.zeros((lo.size, 2)))[:, :4])

    def bent(self, EI, series=True) -> "Member":
        """The same chain (pieces, N(x)) with the bending stiffness EI ≥
        this one's (its pieces still |N| h² ≤ EI): a space member's stiffer
        bending plane, cut once for both."""
        other = copy.copy(self)
        other.EI = float(EI)
        other.beta = self.h[:, None] ** 2 * self.nu / other.EI
        if series:
            other.solutions(_series(other.beta, np.zeros((self.h.size, 2)))[:, :4])
        return other

    def solutions(self, H):
        """The pieces' homogeneous solutions H (P, 4, TERMS) taken: the
        shape functions' coefficients C and the pieces' stiffness k."""
        self.H = H                                           # (P, 4, T)
        at0, at1 = _ends(H, self.h[:, None])                 # (4 quantities, P, 4 solutions)
        B = np.stack([at0[0], at0[1], at1[0], at1[1]], axis=1)      # (P, 4 ends, 4 sols)
        self.C = np.linalg.solve(B, np.broadcast_to(np.eye(4), B.shape))
        forces = self._forces(at0, at1)                     # (P, 4 forces, 4 sols)
        k = forces @ self.C
        self.k = 0.5 * (k + np.swapaxes(k, 1, 2))

    @staticmethod
    def in_one_pass(members) -> None:
        """The homogeneous solutions of many members (built with ``series``
        false) in one pass of the recurrence: one member's (a column piece
        under its weight) cost a quarter of a millisecond, 40 times over in
        α_cr's bisection."""
        if not members:
            return
        H = _series(np.concatenate([m.beta for m in members]),
                    np.zeros((sum(m.h.size for m in members), 2)))[:, :4]
        for m, Hm in zip(members, np.split(H, np.cumsum([m.h.size for m in members])[:-1])):
            m.solutions(Hm)

    def _forces(self, at0, at1):
        """The end forces (v_a, θ_a, v_b, θ_b) of solutions whose end
        values ``at0``, ``at1`` are (w, w', w'', w''') × (P, …)."""
        EI = self.EI
        n0 = self.nu[:, 0].reshape((-1,) + (1,) * (at0.ndim - 2))
        n1 = self.nu.sum(axis=1).reshape(n0.shape)
        return np.stack([EI * at0[3] - n0 * at0[1], -EI * at0[2],
                         -(EI * at1[3] - n1 * at1[1]), EI * at1[2]], axis=1)

    def _particular(self, parts):
        """(A (P, T), clamped consistent loads per piece (P, 4)) of the
        transverse parts' distributed loads."""
        P = self.h.size
        q = np.array([_load_on(parts, a, b) for a, b in zip(self.x[:-1], self.x[1:])]
                     ).reshape(P, 2)
        qt = self.h[:, None] ** 4 * q * np.c_[np.ones(P), self.h] / self.EI
        if not np.any(qt):
            return np.zeros((P, TERMS)), np.zeros((P, 4))
        A = _series(self.beta, qt)[:, 4]
        at0, at1 = _ends(A, self.h)
        d = np.stack([at0[0], at0[1], at1[0], at1[1]], axis=1)          # (P, 4)
        R = self._forces(at0, at1) - np.einsum("pij,pj->pi", self.k, d)
        return A, -R

    def _joints(self, parts):
        """(K, f): the chain's stiffness and loads on every joint's (v, θ)."""
        P = self.h.size
        n = 2 * (P + 1)
        K = np.zeros((n, n))
        f = np.zeros(n)
        fe = self._particular(parts)[1] if parts else np.zeros((P, 4))
        for p in range(P):
            K[2 * p:2 * p + 4, 2 * p:2 * p + 4] += self.k[p]
            f[2 * p:2 * p + 4] += fe[p]
        for part in parts:
            if part[0] == "point":
                _, a, py, mz = part
                j = int(np.argmin(np.abs(self.x - a)))
                f[2 * j] += py
                f[2 * j + 1] += mz
        return K, f

    def stiffness(self) -> np.ndarray:
        """The member's 4 × 4 bending stiffness on (v_i, θ_i, v_j, θ_j)."""
        if self.h.size == 1:
            return self.k[0]
        K, _ = self._joints([])
        return _condensed(K, np.zeros(K.shape[0]))[0]

    def nodal_loads(self, parts) -> np.ndarray:
        """The consistent nodal loads (4) of the transverse parts ``parts``
        (:func:`.beam_column.across`)."""
        K, f = self._joints(parts)
        return _condensed(K, f)[1]

    def least(self) -> float:
        """The least N(x) on the member: at a piece's ends or its vertex."""
        n0, n1, n2 = self.nu.T
        with np.errstate(divide="ignore", invalid="ignore"):
            top = np.where(n2 != 0, np.clip(-n1 / (2 * n2), 0.0, 1.0), 0.0)
        return float(min(n0.min(), (n0 + n1 + n2).min(), (n0 + n1 * top + n2 * top ** 2).min()))

    def own_negatives(self, springs) -> int:
        """The negative eigenvalues of the chain with its ends held — their
        transverse displacements, and their rotations where rigidly joined
        (``springs`` (i, j): None), a released end's rotation on its spring
        (0: a hinge): the member's own buckling with its nodes held
        (Wittrick–Williams' member term).  No piece buckles on its own
        (|N| h² ≤ EI < π² EI), so the chain's modes are the member's."""
        K, _ = self._joints([])
        n = K.shape[0]
        keep = list(range(2, n - 2))
        for dof, spring in ((1, springs[0]), (n - 1, springs[1])):
            if spring is not None:
                K[dof, dof] += spring
                keep.append(dof)
        if not keep:
            return 0
        Kh = K[np.ix_(keep, keep)]
        d = 1.0 / np.sqrt(np.abs(np.diag(Kh)))
        lam = np.linalg.eigvalsh(Kh * d[:, None] * d[None, :])
        return int(np.sum(lam < -16 * lam.size * np.finfo(float).eps * np.abs(lam).max()))

    def arms(self) -> tuple[float, float]:
        """The rigid end zones' ∫ N dx, (zone i's, zone j's): each one's P-Δ
        couple per unit of its rotation (N o for N constant)."""
        lo, hi = self.ends
        return tuple(float(self.integral(a, np.array([b]))[0]) if b > a else 0.0
                     for a, b in ((lo, 0.0), (self.L, hi)))

    def integral(self, a, x) -> np.ndarray:
        """∫ₐˣ N dx (positions from the flexible length's start)."""
        x = np.asarray(x, float)
        c = self.Nbar - self.centre
        return (c * (x - a) + _statics_integral(self.axial_parts, x)
                - _statics_integral(self.axial_parts, np.array([float(a)]))[0])

    def N(self, x) -> np.ndarray:
        """N(x) (the right side at a point load), positions from the
        flexible length's start (a zone's too)."""
        return self.Nbar + variation(self.axial_parts, self.centre, x)

    def axis(self, parts, ends, springs, x):
        """(v, v', ∫₀ˣ N v' dx) at x under ``parts`` (each times its
        factor): its flexible ends' displacements and their nodes'
        rotations ``ends`` (v_i, θ_i, v_j, θ_j), ``springs`` (i, j) each
        None for a rigid joint, 0 for a hinge, else a rotational spring —
        a released end's own rotation from the element's moment row, as
        :func:`.beam_column.axis` does."""
        K, f = self._joints(parts)
        n = K.shape[0]
        ends = released_ends(lambda: _condensed(K, f), ends, springs)
        e = [0, 1, n - 2, n - 1]
        i = list(range(2, n - 2))
        u = np.zeros(n)
        u[e] = ends
        if i:
            u[i] = np.linalg.solve(K[np.ix_(i, i)], f[i] - K[np.ix_(i, e)] @ np.asarray(ends))
        Ap, _ = self._particular(parts)
        P = self.h.size
        A = np.empty((P, TERMS))
        for p in range(P):
            up = u[2 * p:2 * p + 4]
            at0, at1 = _ends(Ap[p], self.h[p])
            d = np.array([at0[0], at0[1], at1[0], at1[1]])
            A[p] = (self.C[p] @ (up - d)) @ self.H[p] + Ap[p]
        # ∫ N w_σ dσ on each piece, as a series in σ, and its totals
        dA = A[:, 1:] * _N[1:]                                    # w_σ's coefficients
        prod = np.zeros((P, TERMS + 2))
        for r in range(3):
            prod[:, r:r + TERMS - 1] += self.nu[:, r:r + 1] * dA
        integ = np.c_[np.zeros(P), prod / np.arange(1, TERMS + 3)]   # coefficients of σ^(j+1)
        start = np.r_[0.0, np.cumsum(integ.sum(axis=1))[:-1]]
        x = np.asarray(x, float)
        p = np.clip(np.searchsorted(self.x, x, side="right") - 1, 0, P - 1)
        s = np.clip((x - self.x[p]) / self.h[p], 0.0, 1.0)
        powers = s[:, None] ** np.arange(TERMS + 3)
        v = (A[p] * powers[:, :TERMS]).sum(1)
        dv = (dA[p] * powers[:, :TERMS - 1]).sum(1) / self.h[p]
        dM = start[p] + (integ[p] * powers).sum(1)
        return v, dv, dM


def _condensed(K, f):
    """(4 × 4, 4): K and f on the chain's end joints, the others condensed."""
    n = K.shape[0]
    e = [0, 1, n - 2, n - 1]
    i = list(range(2, n - 2))
    if not i:
        return 0.5 * (K + K.T), f
    Kie = K[np.ix_(i, e)]
    sol = np.linalg.solve(K[np.ix_(i, i)], np.c_[Kie, f[i]])
    Kc = K[np.ix_(e, e)] - Kie.T @ sol[:, :4]
    return 0.5 * (Kc + Kc.T), f[e] - Kie.T @ sol[:, 4]
