"""The beam-column whose axial force varies along it — Euler–Bernoulli or
shear-flexible (Engesser's, :mod:`.second_order`): a member whose own
loads have parts along its axis (a column's self-weight, a point load
along it) carries N(x), not the constant N of :mod:`.beam_column`'s and
:mod:`.second_order`'s stability functions.

The mechanics.  On the flexible length [0, L] (member axes, as
:mod:`.beam_column`'s) the deflection v(x) [L] under the transverse load
q(x) [F/L] obeys, equilibrium on the deformed axis,

    EI v'''' + (EI/(G A_s)) (N(x) v')''' − (N(x) v')' = q(x)

(q linear between load positions; G A_s [F] the shear stiffness, the
middle term absent without shear deformation:
:mod:`.varying_pieces` derives it), with N(x) [F] (tension positive)
= N̄ + n(x) − (n(−o_i) + n(L + o_j))/2:
N̄ the mean of its nodes' end forces that the frame's fixed point
iterates (:func:`.second_order_path.axial_forces`), n(x) = −∫ p − Σ P the
statics of the axial loads p (distributed, along +x) and P (points) from
node i, x = −o_i, to x — the rigid end zones' (o_i, o_j) loads included:
a zone under its share of a column's weight carries it to the node, so
the flexible length's mean is not N̄ (taken on its own ends, a 5 m
cantilever with a 0.625 m top zone under 0.7 of Greenhill's load had α_cr
1.68 for 1.43 and its base moment 25 % low).  A zone's own P-Δ is
θ ∫_zone N dx (:meth:`Member.arms`).  The
transverse force across the undeformed axis, T = M' − N v' (EI v''' − N v'
without shear), jumps by a transverse point force and is continuous where
only N jumps (an axial point load); the moment M jumps by minus a point
couple.

The solution.  Between load positions N is a polynomial of degree ≤ 2 and
q of degree ≤ 1, so on each piece [x₀, x₀ + h] the solution is an entire
function (with shear, analytic while 1 + N/(G A_s) > 0), written as its
Taylor series in σ = (x − x₀)/h (:mod:`.varying_pieces`: the recurrence,
with units).  Pieces are cut so that |N| h² ≤ EI (1 + N/(G A_s))
everywhere on them: then |A_n| falls like 1/n!, and the series are exact
to rounding; where N comes near −G A_s (shear), shorter as it comes
nearer (:func:`.varying_pieces.cuts`), and where it passes it the member is past its
own buckling.  Four series from the unit states (v, θ, M, S) at x₀ give
each piece's transfer matrix, the particular one (zero state) its load
term; consecutive pieces are multiplied into runs no shorter than a share of
what the rule allows (:func:`.varying_pieces.runs`: two load positions 1 ulp to 1 cm
apart made a piece whose stiffness, ∝ 1/h³, cost the chain 3 log₁₀ of the
ratio in digits — LinAlgError at 1e-9 m), each run's stiffness on its
ends' (v, θ) and clamped end forces follow, and the runs are joined as a
chain (continuity of v, θ; the forces at the joints balanced, a point
load there a nodal load of the joint, inside a run a jump of its state)
with the joints condensed out: the member's 4 × 4 stiffness on (v_i, θ_i,
v_j, θ_j), its consistent nodal loads, and, from its end displacements,
each piece's series — v, v' (the axis' slope; the section turns by θ = v'
+ M'/(G A_s)) and the second-order moment ∫₀ˣ N v' dx (the section moment
on the deformed axis is the first-order statics' plus it; N (v(x) − v(0))
for constant N) between the ends.  A chain of stiffnesses rather than one
transfer matrix end to end: in strong tension that would grow as e^(kL).
Nothing is interpolated: the series are the solution.  With N constant
it is the stability functions' member, Livesley's or Engesser's (tests:
to ~1e-12), a different route.
"""

from __future__ import annotations

import copy

import numpy as np

from . import varying_pieces as pieces
from .end_releases import released_ends
from .loads import clipped

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
    is then not N̄); None where none do (a constant N: the beam-column's,
    :mod:`.beam_column`, Engesser's with shear)."""
    if not along:
        return None
    oi, oj = m.offset_i, m.offset_j
    parts = [part[:-2] + tuple(along[ld.case] * np.array(part[-2:]))
             if part[0] == "distributed" else part[:2] + (along[ld.case] * part[2],)
             for ld in m.loads if along.get(ld.case)
             for part in [along_axis(ld, L, c, s, oi, oj)] if part]
    if not parts:
        return None
    return Member(m.E * m.I, L - oi - oj, Nbar, parts,
                  [x - oi for ld in m.loads for x in (ld.a, ld.b)], series, (oi, oj), m.GAs)


def least_axial(frame, N, along) -> np.ndarray:
    """Per member its least N along it (its largest compression): N where
    it is constant (no axial loads in the
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


def _load_on(parts, lo, hi):
    """(q₀, q₁): the transverse distributed load on [lo, hi] as q₀ + q₁ (x − lo)."""
    q0 = q1 = 0.0
    for part in parts:
        if part[0] != "distributed":
            continue
        _, a, b, w1, w2 = part
        # a piece lies within or outside each load (the cuts include its
        # ends), but a clipped end and the cut computed another way may
        # differ by an ulp ((L − o_j) − o_i against L − o_i − o_j): judged
        # by the piece's middle, not its ends, which dropped the load on
        # the last piece of 5 % of beams with rigid zones
        if b > a and a < 0.5 * (lo + hi) < b:
            slope = (w2 - w1) / (b - a)
            q0 += w1 + slope * (lo - a)
            q1 += slope
    return q0, q1


class Member:
    """One member's chain of pieces under N(x) (module docstring): EI, its
    flexible length L, N̄, the axial parts (times their factors), the
    positions where its loads start, end or act, its rigid end zones'
    lengths ``zones`` (o_i, o_j), its shear stiffness ``GAs`` (None:
    Euler–Bernoulli) and ``also``: another bending plane's (EI, G A_s) that
    the same cut must serve (:meth:`bent`)."""

    def __init__(self, EI, L, Nbar, axial_parts, points, series=True, zones=(0.0, 0.0),
                 GAs=None, also=None):
        self.EI, self.L, self.axial_parts = float(EI), float(L), list(axial_parts)
        self.c = 0.0 if GAs is None else 1.0 / float(GAs)
        self.zones = (float(zones[0]), float(zones[1]))
        self.ends = (-self.zones[0], self.L + self.zones[1])
        self.centre = _centre(self.axial_parts, self.ends)
        planes = [(self.EI, self.c)] + ([] if also is None else
                                        [(float(also[0]), 0.0 if also[1] is None
                                          else 1.0 / float(also[1]))])
        self.Nbar = float(Nbar)
        self.x, reach, self.sheared = pieces.cuts(planes, L, points, lambda x: Nbar + np.stack(
            [variation(self.axial_parts, self.centre, x),
             variation(self.axial_parts, self.centre, x, False)]))
        self._pieces(reach, self.axial_parts)
        self.lowest = _least(self.nu)
        if self.sheared:
            # past its own buckling (own_negatives counts it), its element
            # takes the mean N — at most half G A_s in compression — so that
            # the answer is there to call UNSTABLE
            self.Nbar = max(self.Nbar, -0.5 / max(c for _, c in planes))
            self.x, reach, _ = pieces.cuts(planes, L, points,
                                           lambda x: np.full((2,) + np.shape(x), self.Nbar))
            self._pieces(reach, [])
            self.Nbar = float(Nbar)
        self._scaled()
        if series:        # else by :func:`in_one_pass` with other members'
            Member.in_one_pass([self])

    def _pieces(self, reach, axial_parts):
        """The pieces' lengths, runs and N's coefficients under ``axial_parts``."""
        lo, hi = self.x[:-1], self.x[1:]
        self.h = hi - lo
        self.bounds = pieces.runs(self.h, reach)
        # N on each piece through σ = 0 (its right limit), ½ and 1 (its left):
        # a polynomial of degree ≤ 2 there
        pts = lo[:, None] + self.h[:, None] * np.array([0.0, 0.5, 1.0])
        Nv = self.Nbar + np.c_[variation(axial_parts, self.centre, pts[:, 0], True),
                               variation(axial_parts, self.centre, pts[:, 1:], False)]
        # ν₀ + ν₁ σ + ν₂ σ² through σ = 0, ½, 1
        self.nu = np.stack([Nv[:, 0], -3 * Nv[:, 0] + 4 * Nv[:, 1] - Nv[:, 2],
                            2 * Nv[:, 0] - 4 * Nv[:, 1] + 2 * Nv[:, 2]], axis=1)

    def _scaled(self):
        """β = h² ν/EI and g = EI c/h² of the pieces."""
        self.beta = self.h[:, None] ** 2 * self.nu / self.EI
        with np.errstate(divide="ignore", invalid="ignore"):
            self.g = np.where(self.h > 0, self.EI * self.c / self.h ** 2, 0.0)

    def bent(self, EI, GAs=None, series=True) -> "Member":
        """The same chain (pieces, N(x)) with another plane's bending
        stiffness EI and shear stiffness ``GAs`` (cut for both: ``also``):
        a space member's other bending plane."""
        other = copy.copy(self)
        other.EI = float(EI)
        other.c = 0.0 if GAs is None else 1.0 / float(GAs)
        other._scaled()
        if series:
            Member.in_one_pass([other])
        return other

    def _through(self, T, t, jumps):
        """(T, t) of each run: its pieces' transfer matrices and load terms
        multiplied through, the state's ``jumps`` (P + 1, 4) at its inner
        joints (point loads) added."""
        b = self.bounds
        if b.size == self.h.size + 1:
            return T, t
        Tr, tr = T[b[:-1]].copy(), t[b[:-1]].copy()
        for r in np.flatnonzero(np.diff(b) > 1).tolist():
            for p in range(b[r] + 1, b[r + 1]):
                jump = 0.0 if jumps is None else jumps[p]
                Tr[r] = T[p] @ Tr[r]
                tr[r] = T[p] @ (tr[r] + jump) + t[p]
        return Tr, tr

    @staticmethod
    def in_one_pass(members) -> None:
        """The pieces' solutions from their unit states, their transfer
        matrices and the runs' stiffness k, of many members (built with
        ``series`` false) at once: the series, the end states and the runs'
        stiffness each one pass over all their pieces (per member, in
        NumPy's small calls, a column's cost 0.4 ms, 40 times over in
        α_cr's bisection)."""
        if not members:
            return
        sizes = [m.h.size for m in members]
        cut = np.cumsum(sizes)[:-1]
        nu, h = (np.concatenate([getattr(m, a) for m in members]) for a in ("nu", "h"))
        EI = np.repeat([m.EI for m in members], sizes)
        c = np.repeat([m.c for m in members], sizes)
        H = pieces.series(np.concatenate([m.beta for m in members]),
                          np.concatenate([m.g for m in members]),
                          pieces.starts(nu, h, EI, c)[0])
        T = pieces.end_states(H, nu, h, EI, c)                  # (P, 4, 4)
        runs = []
        for m, Hm, Tm in zip(members, np.split(H, cut), np.split(T, cut)):
            m.H, m.T = Hm, Tm
            b = m.bounds
            m.length = m.x[b[1:]] - m.x[b[:-1]]
            m.Tr = m._through(Tm, np.zeros((m.h.size, 4)), None)[0]
            runs.append(m.Tr)
        count = [m.length.size for m in members]
        k, F = pieces.run_stiffness(np.concatenate(runs),
                                    np.concatenate([m.length for m in members]),
                                    np.repeat([m.EI for m in members], count))
        at = np.cumsum(count)[:-1]
        for m, km, Fm in zip(members, np.split(k, at), np.split(F, at)):
            m.k, m.F = km, Fm

    def _particular(self, parts):
        """(A (P, T), each piece's load term t (P, 4)) of the transverse
        parts' distributed loads: the series from the zero state."""
        P = self.h.size
        q = np.array([_load_on(parts, a, b) for a, b in zip(self.x[:-1], self.x[1:])]
                     ).reshape(P, 2)
        if not np.any(q):
            return np.zeros((P, pieces.TERMS)), np.zeros((P, 4))
        qt = (self.h[:, None] ** 4 * q * np.c_[np.ones(P), self.h] / self.EI)[:, None, :]
        start = pieces.starts(self.nu, self.h, self.EI, self.c, q)[1][:, None, :]
        A = pieces.series(self.beta, self.g, start, qt)
        return A[:, 0], pieces.end_states(A, self.nu, self.h, self.EI, self.c, q)[:, :, 0]

    def _points(self, parts):
        """(the joints' loads (runs + 1, 2), the state's jumps at the pieces'
        edges (P + 1, 4)): a point force py and couple mz at an edge inside
        a run jump S by py and M by −mz there."""
        joints = np.zeros((self.bounds.size, 2))
        jumps = np.zeros((self.h.size + 1, 4))
        at = {int(e): r for r, e in enumerate(self.bounds)}
        for part in parts:
            if part[0] == "point":
                _, a, py, mz = part
                e = int(np.argmin(np.abs(self.x - a)))
                if e in at:
                    joints[at[e]] += (py, mz)
                else:
                    jumps[e, 3] += py
                    jumps[e, 2] -= mz
        return joints, jumps

    def _loads(self, parts):
        """(A, t per piece, jumps, t per run, the joints' loads) of ``parts``."""
        Ap, t = self._particular(parts)
        joints, jumps = self._points(parts)
        return Ap, t, jumps, self._through(self.T, t, jumps)[1], joints

    def _joints(self, parts, loads=None):
        """(K, f): the chain's stiffness and loads on every joint's (v, θ)
        (``loads``: :meth:`_loads` of ``parts`` where known)."""
        R = self.bounds.size - 1
        n = 2 * (R + 1)
        K = np.zeros((n, n))
        f = np.zeros(n)
        fe = np.zeros((R, 4))
        if parts:
            _, _, _, tr, joints = loads or self._loads(parts)
            if np.any(tr):
                fe = -np.einsum("rij,rj->ri", self.F, tr)
            f += joints.ravel()
        for r in range(R):
            K[2 * r:2 * r + 4, 2 * r:2 * r + 4] += self.k[r]
            f[2 * r:2 * r + 4] += fe[r]
        return K, f

    def stiffness(self) -> np.ndarray:
        """The member's 4 × 4 bending stiffness on (v_i, θ_i, v_j, θ_j)."""
        if self.k.shape[0] == 1:
            return self.k[0]
        K, _ = self._joints([])
        return _condensed(K, np.zeros(K.shape[0]))[0]

    def nodal_loads(self, parts) -> np.ndarray:
        """The consistent nodal loads (4) of the transverse parts ``parts``
        (:func:`.beam_column.across`)."""
        K, f = self._joints(parts)
        return _condensed(K, f)[1]

    def least(self) -> float:
        """The least N(x) on the member (its own where the element takes
        the mean N: past its own buckling)."""
        return self.lowest

    def own_negatives(self, springs) -> int:
        """The negative eigenvalues of the chain with its ends held — their
        transverse displacements, and their rotations where rigidly joined
        (``springs`` (i, j): None), a released end's rotation on its spring
        (0: a hinge): the member's own buckling with its nodes held
        (Wittrick–Williams' member term).  No run buckles on its own
        (|N| h² ≤ (1 + 2 SHORT)² EI D < 4π² EI D, Engesser's clamped load),
        so the chain's modes are the member's; a member compressed past
        G A_s somewhere is past its own buckling (at least one)."""
        if self.sheared:
            return 1
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
        factor), v' the axis' slope (a shear-flexible member's section
        turns by θ = v' + M'/(G A_s)): its flexible ends' displacements and
        their nodes' rotations ``ends`` (v_i, θ_i, v_j, θ_j), ``springs``
        (i, j) each None for a rigid joint, 0 for a hinge, else a rotational
        spring — a released end's own rotation from the element's moment
        row, as :func:`.beam_column.axis` does."""
        loads = self._loads(parts)
        K, f = self._joints(parts, loads)
        n = K.shape[0]
        ends = released_ends(lambda: _condensed(K, f), ends, springs)
        e = [0, 1, n - 2, n - 1]
        i = list(range(2, n - 2))
        u = np.zeros(n)
        u[e] = ends
        if i:
            u[i] = np.linalg.solve(K[np.ix_(i, i)], f[i] - K[np.ix_(i, e)] @ np.asarray(ends))
        Ap, t, jumps, tr, _ = loads
        P = self.h.size
        A = np.empty((P, pieces.TERMS))
        b = self.bounds
        for r in range(b.size - 1):
            da, db = u[2 * r:2 * r + 2], u[2 * r + 2:2 * r + 4]
            y = np.r_[da, pieces.start_forces(self.Tr[r], tr[r], self.length[r], self.EI,
                                              da, db)]
            for p in range(b[r], b[r + 1]):
                if p > b[r]:
                    y = y + jumps[p]
                A[p] = y @ self.H[p] + Ap[p]
                y = self.T[p] @ y + t[p]
        # ∫ N w_σ dσ on each piece, as a series in σ, and its totals
        TERMS = pieces.TERMS
        dA = A[:, 1:] * np.arange(1, TERMS)                       # w_σ's coefficients
        prod = np.zeros((P, TERMS + 2))
        for r in range(3):
            prod[:, r:r + TERMS - 1] += self.nu[:, r:r + 1] * dA
        integ = np.c_[np.zeros(P), prod / np.arange(1, TERMS + 3)]   # coefficients of σ^(j+1)
        start = np.r_[0.0, np.cumsum(integ.sum(axis=1))[:-1]]
        x = np.asarray(x, float)
        p = np.clip(np.searchsorted(self.x, x, side="right") - 1, 0, P - 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            s = np.where(self.h[p] > 0, np.clip((x - self.x[p]) / self.h[p], 0.0, 1.0), 0.0)
        powers = s[:, None] ** np.arange(TERMS + 3)
        v = (A[p] * powers[:, :TERMS]).sum(1)
        dv = (dA[p] * powers[:, :TERMS - 1]).sum(1) / self.h[p]
        dM = start[p] + (integ[p] * powers).sum(1)
        return v, dv, dM


def _least(nu) -> float:
    """The least of N on pieces of coefficients ``nu``: at their ends or vertices."""
    n0, n1, n2 = nu.T
    with np.errstate(divide="ignore", invalid="ignore"):
        top = np.where(n2 != 0, np.clip(-n1 / (2 * n2), 0.0, 1.0), 0.0)
    return float(min(n0.min(), (n0 + n1 + n2).min(), (n0 + n1 * top + n2 * top ** 2).min()))


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
