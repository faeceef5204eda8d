"""Loads on plane frames: load cases, nodal and member loads, combinations.

A load belongs to a named **load case** ("D", "L", "W", ...).  A
**combination** is a dict {case: factor}; each combination is analysed as its
own nonlinear problem (contact states differ between combinations, so results
are never superposed).  The cases "constant" and "variable" are the Osipova–Popov–Lovtsov split
used by ``Frame.solve(p)`` and ``Frame.trace``: constant + p x variable.

Member loads are stored in the axes they were given in ("global": x right,
y up; "member": x from node i to node j, y its normal turned counterclockwise)
and turned into member axes when the member's geometry is known:

* point force (px, py) and moment mz at a distance ``a`` from node i;
* distributed load, trapezoidal from (wx1, wy1) at ``a`` to (wx2, wy2) at
  ``b`` (per unit length of the member: for a load per horizontal projection,
  multiply by cos θ yourself);
* self-weight: a uniform global load of (weight per length) x direction.

Their equivalent nodal loads are the consistent ones, ∫ Nᵀ w dx with the
element's own shape functions (linear axially, cubic Hermite transversely),
which for an Euler–Bernoulli element are the exact fixed-end forces; the
integrals are computed by Gauss–Legendre quadrature exact for these
polynomial integrands.  Units: the user's, consistent.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from itertools import chain
from operator import attrgetter

import numpy as np

from qpcontact.core.errors import InvalidOptionError, InvalidProblemError, SolverFailedError

#: the two cases of the Osipova–Popov–Lovtsov split (constant + p x variable)
CONSTANT, VARIABLE = "constant", "variable"
AXES = ("global", "member")

_GAUSS = np.polynomial.legendre.leggauss(4)   # exact to degree 7: cubic x linear load


@dataclass(frozen=True)
class MemberLoad:
    """One load on a member (see the module docstring).  ``kind``: "point",
    "distributed"; positions ``a`` <= ``b`` in length units from node i."""

    kind: str
    case: str
    axes: str
    a: float
    b: float
    values: tuple   # point: (px, py, mz); distributed: (wx1, wy1, wx2, wy2)
    #: the numbers the assembly reads, as one row: member axes?, a point
    #: load?, a, b and the values padded to four — made once here, not by
    #: eight attribute reads per load and solve (a third of a 400-member
    #: beam's equivalent loads)
    row: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "row", (float(self.axes == "member"), float(self.kind == "point"),
                                         self.a, self.b, *self.values, 0.0)[:8])


def number(value, what: str) -> float:
    """A finite float, or an error that names ``what``."""
    if isinstance(value, (bool, str, bytes)) or value is None:
        raise InvalidProblemError(f"{what} must be a number; got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InvalidProblemError(f"{what} must be a number; got {value!r}") from None
    if not np.isfinite(v):
        raise InvalidProblemError(f"{what} must be finite; got {v}")
    return v


#: unit names recognised as forces and as lengths (others pass unchecked)
FORCE_UNITS = ("N", "kN", "MN", "daN", "lbf", "kip", "kips", "klf", "tf", "kgf", "lb")
LENGTH_UNITS = ("m", "mm", "cm", "dm", "km", "in", "ft", "inch", "yd")


def check_units(units) -> tuple:
    """``units`` as a (force, length) pair of names; InvalidProblemError for
    another shape, or for a known length named first or a known force second
    (the order swapped)."""
    if (not isinstance(units, (tuple, list)) or len(units) != 2
            or not all(isinstance(u, str) and u for u in units)):
        raise InvalidProblemError(f"units must be (force, length) names, e.g. ('kN', 'm'); "
                                  f"got {units!r}")
    force, length = units
    if force in LENGTH_UNITS or length in FORCE_UNITS:
        raise InvalidProblemError(
            f"units are (force, length), in that order; got {tuple(units)!r}, which names "
            f"{'a length' if force in LENGTH_UNITS else 'a force'} "
            f"{'first' if force in LENGTH_UNITS else 'second'} — write "
            f"({length!r}, {force!r})")
    return tuple(units)


#: the stiffest semi-rigid end spring taken [moment per radian]: its
#: condensation squares it, which overflows past ~1.3e154 into a NaN
#: stiffness; any joint near this is rigid (leave the spring out)
SPRING_MAX = 1e100

def no_member_between(joined: dict, i: str, j: str, what: str) -> None:
    """InvalidProblemError if a member joins the nodes i and j already, in
    either direction.  ``joined`` maps each member's node pair (a
    frozenset) to its name: the frames keep it as members are added, where
    a scan of every member per call made building a frame quadratic (the
    2 000-member beam: 0.5 s of its 0.6)."""
    name = joined.get(frozenset((i, j)))
    if name is not None:
        raise InvalidProblemError(
            f"{what}: nodes {i!r} and {j!r} are joined already by member {name!r}; a "
            "second member between the same nodes would add its stiffness unseen — give "
            "one member with the combined section, or add a node between them")


def no_same_contact(contacts, here, node: str, normal, other=None) -> None:
    """InvalidProblemError if one of ``contacts`` (with ``node``, ``normal``
    (unit) and ``other``) is at ``node`` (against ``other``) with the same
    normal: two unilateral links in one direction at one node are one link
    whose force is split in no determined way.  Other normals (a node in a
    corner, or between two walls) are separate contacts and allowed.
    ``here``: the indices of the contacts already at ``node`` (the frames
    keep them by node, for the same reason as ``no_member_between``)."""
    for k in here:
        c = contacts[k]
        if c.node == node and getattr(c, "other", None) == other \
                and np.allclose(c.normal, normal, rtol=0.0, atol=1e-12):
            raise InvalidProblemError(
                f"contact at {node!r}: the node has contact {k} with the same normal "
                f"{tuple(round(float(v), 12) for v in normal)} already; a second one in the same "
                f"direction is redundant (its force is not determined) — change contact {k}'s "
                "friction, gap or stiffness instead, or give another normal")


def known_node(frame, name) -> str:
    """``name`` if the frame has a node of that name; else the error lists them."""
    if name not in frame.nodes:
        raise InvalidProblemError(f"no node named {name!r}; nodes: {list(frame.nodes)}")
    return name


def pair_node(frame, node: str, other) -> None:
    """InvalidProblemError unless ``other`` (a contact pair's second node,
    or None for a support on the ground) is a node of the frame other than
    ``node``."""
    if other is None:
        return
    known_node(frame, other)
    if other == node:
        raise InvalidProblemError(
            f"contact at {node!r}: other={other!r} is the contact's own node; a pair "
            "acts between two different nodes — name the node it presses against, "
            "or leave other out for a support on the ground")


def support_keys(frame) -> list:
    """The key of each contact in a result's supports, in contact order,
    for plane and space frames alike: its node, "node-other" for a pair,
    "#k" added (k the contact's index) where the key is taken."""
    keys, taken = [], set()       # a set beside the list: 1000 contacts in 0.5 ms, not 18
    for c in frame.contacts:
        key = c.node if c.other is None else f"{c.node}-{c.other}"
        keys.append(f"{key}#{len(keys)}" if key in taken else key)
        taken.add(keys[-1])
    return keys


def known_member(frame, name):
    """The frame's member of that name; else the error lists them."""
    if name not in frame.members:
        raise InvalidProblemError(f"no member named {name!r}; members: {list(frame.members)}")
    return frame.members[name]


def add_settlements(frame, node: str, given: dict, case) -> None:
    """Append ``given`` {dof: displacement} at ``node`` to the frame's
    settlements (load case ``case``): each dof must be fixed there by a
    bilateral support, since a settlement moves a support."""
    held = frame.fixed.get(node, set())
    for d in given:
        if d not in held:
            raise InvalidProblemError(
                f"settlement at {node!r}: {d} is not fixed by a bilateral support there "
                f"(fixed: {sorted(held) or 'none'}); add_support({node!r}, fix=(..., {d!r})) "
                "first — a settlement moves a support")
    # all checked before any is kept: a refused call leaves the frame as it was
    rows = [(node, d, case_name(case), number(v, f"settlement at {node!r}: {d}"))
            for d, v in given.items()]
    frame.settlements.extend(rows)


def check_diagram(frame, res, member: str, points, quantities) -> None:
    """The checks a result's ``diagram(member, points)`` makes of its
    arguments (``quantities``: the names it returns, which a user may pass
    as ``points`` by mistake): errors that say what to give."""
    if not isinstance(member, str):
        raise InvalidOptionError(f"member: a member's name, one of {list(frame.members)}; "
                                 f"got {member!r}")
    known_member(frame, member)
    if isinstance(points, str) and points in quantities:
        names = ", ".join(("x",) + tuple(quantities))
        raise InvalidOptionError(
            f"points: the number of sample points, not the quantity {points!r}; diagram "
            f"returns all of them, {names} = result.diagram({member!r}), or give "
            f"points=, e.g. result.diagram({member!r}, 41)")
    if isinstance(points, bool) or not isinstance(points, (int, np.integer)) or points < 2:
        raise InvalidOptionError(f"points: the number of sample points along the member, an "
                                 f"integer >= 2 (default 21); got {points!r}")
    if not res.member_forces:
        raise SolverFailedError(f"no diagram: this result is not an equilibrium ({res.message})")


def case_name(case) -> str:
    if not isinstance(case, str) or not case:
        raise InvalidProblemError(f"a load case is named by a non-empty string; got {case!r}")
    return case


def check_axes(axes) -> str:
    if axes not in AXES:
        raise InvalidProblemError(f"axes must be one of {AXES}; got {axes!r}")
    return axes


def combination(combo, cases) -> dict:
    """Validate {case: factor}; every case named must have loads or be known."""
    if not isinstance(combo, dict) or not combo:
        raise InvalidProblemError(
            f"a combination is a non-empty dict {{case: factor}}, e.g. {{'D': 1.2, 'L': 1.6}}; "
            f"got {combo!r}")
    out = {}
    for case, f in combo.items():
        if case not in cases:
            raise InvalidProblemError(
                f"combination names the load case {case!r}, which has no loads; cases: "
                f"{sorted(cases)}")
        out[case] = number(f, f"the factor of case {case!r}")
    return out


def describe(combo: dict) -> str:
    """A combination in words: "1.2·D + 1.6·L" ("no load" when every factor
    is 0); the Osipova–Popov–Lovtsov split as "p = 2" (constant + 2 × variable)."""
    if set(combo) <= {CONSTANT, VARIABLE} and combo.get(CONSTANT, 1.0) in (0.0, 1.0) \
            and VARIABLE in combo:
        p = combo[VARIABLE]
        return f"p = {p:g}" + ("" if combo.get(CONSTANT, 0.0) else " (no constant load)")
    return " + ".join(f"{f:g}·{c}" for c, f in combo.items() if f) or "no load"


def _local(axes, c, s, fx, fy):
    """Components in member axes of a vector given in ``axes``."""
    if axes == "member":
        return fx, fy
    return c * fx + s * fy, -s * fx + c * fy


def _gauss(a, b):
    t, w = _GAUSS
    return 0.5 * (b - a) * t + 0.5 * (a + b), 0.5 * (b - a) * w


def _trapezoid(load, c, s):
    """(wx1, wy1, wx2, wy2) in member axes."""
    wx1, wy1, wx2, wy2 = load.values
    a1 = _local(load.axes, c, s, wx1, wy1)
    a2 = _local(load.axes, c, s, wx2, wy2)
    return a1[0], a1[1], a2[0], a2[1]


def equivalent_nodal(load: MemberLoad, L: float, c: float, s: float,
                     phi: float = 0.0) -> np.ndarray:
    """Consistent nodal loads (member axes, order ux, uy, rz at i then j) of
    a load on a flexible element of length L: forces against the element's
    own displacement interpolation, a moment against its rotation — for the
    Timoshenko element (φ > 0) the interdependent interpolation, which makes
    them its exact fixed-end forces as the Hermite cubics do for φ = 0
    (:func:`equivalent_nodal_many` of the one load)."""
    return equivalent_nodal_many([load], [L], [c], [s], [phi])[0]


def equivalent_nodal_many(loads, L, c, s, phi) -> np.ndarray:
    """:func:`equivalent_nodal` of many loads at once, (n, 6): load k on a
    flexible element of length L[k], direction (c[k], s[k]), parameter
    phi[k], in one compiled pass (:func:`._frame_kernels.equivalent_loads`:
    as array expressions dozens of NumPy calls; a Python call per load
    before that: a 400-member beam spent 12 ms there)."""
    from ._frame_kernels import equivalent_loads
    # one pass over the loads: their axes, kind, stretch and four values
    # (a point load's (fx, fy, mz, 0)) as the rows of one array, read by
    # fromiter (np.array of 400 tuples: a third of this function's time)
    table = np.fromiter(chain.from_iterable(map(attrgetter("row"), loads)), float,
                        8 * len(loads)).reshape(-1, 8)
    L, c, s, phi = (np.asarray(v, float) for v in (L, c, s, phi))
    # ξ³ at a point load's position and a trapezoid's Gauss points by
    # NumPy's power (its vector library's rounding, which the kernel's
    # x·x·x and libm's pow do not give bit for bit)
    t, wg = _GAUSS
    a, b = table[:, 2:3], table[:, 3:4]
    half = 0.5 * (b - a)
    x = np.where(table[:, 1:2] > 0, a, half * t + 0.5 * (a + b))
    return equivalent_loads(table, L, c, s, phi, (x / L[:, None]) ** 3, t, wg)


def clipped(load: MemberLoad, lo: float, hi: float, shift: float = 0.0):
    """The part of a load on [lo, hi], positions moved by -shift (None if
    nothing lies there); a trapezoid's values interpolated at the cuts."""
    if load.kind == "point":
        inside = lo <= load.a <= hi if hi > lo else False
        return replace(load, a=load.a - shift, b=load.a - shift) if inside else None
    a, b = max(load.a, lo), min(load.b, hi)
    if b <= a:
        return None
    wx1, wy1, wx2, wy2 = load.values
    span = load.b - load.a

    def at(x):
        t = (x - load.a) / span
        return wx1 + t * (wx2 - wx1), wy1 + t * (wy2 - wy1)

    (ax, ay), (bx, by) = at(a), at(b)
    return replace(load, a=a - shift, b=b - shift, values=(ax, ay, bx, by))


def _rigid_transfer(load: MemberLoad, c: float, s: float, about: float) -> np.ndarray:
    """A load on a rigid end zone moved statically to the node at ``about``:
    its resultant force and its moment about the node (member axes)."""
    if load.kind == "point":
        px, py = _local(load.axes, c, s, *load.values[:2])
        return np.array([px, py, load.values[2] + (load.a - about) * py])
    wx1, wy1, wx2, wy2 = _trapezoid(load, c, s)
    xs, ws = _gauss(load.a, load.b)
    t = (xs - load.a) / (load.b - load.a)
    qx, qy = wx1 + t * (wx2 - wx1), wy1 + t * (wy2 - wy1)
    return np.array([qx @ ws, qy @ ws, (qy * (xs - about)) @ ws])


def offset_parts(load: MemberLoad, L: float, c: float, s: float, phi: float, offsets):
    """A load on a member with rigid end zones of lengths ``offsets``, split:
    (the consistent loads of the part on the flexible length, on the flexible
    element's own end dofs; the parts on the rigid zones moved statically to
    their nodes, member axes).  The first reaches the nodes through the
    rigid arms (assembly: a shear V at the flexible end is a moment ±V·offset
    at the node)."""
    oi, oj = offsets
    rigid = np.zeros(6)
    flex = clipped(load, oi, L - oj, shift=oi)
    fe = np.zeros(6) if flex is None else equivalent_nodal(flex, L - oi - oj, c, s, phi)
    for lo, hi, node, about in ((0.0, oi, 0, 0.0), (L - oj, L, 3, L)):
        part = clipped(load, lo, hi) if hi > lo else None
        # a point load exactly at the face is the flexible element's
        if part is not None and not (part.kind == "point" and flex is not None):
            rigid[node:node + 3] += _rigid_transfer(part, c, s, about)
    return fe, rigid


def section_sums(loads, x: np.ndarray, c: float, s: float):
    """For sections at x (member axes): the loads on [0, x) summed as
    (axial force, transverse force, moment about the section) — what the
    diagrams add to the end forces.  A point load exactly at a section counts
    as left of it (the diagram's value just right of the load)."""
    fx = np.zeros_like(x)
    fy = np.zeros_like(x)
    mo = np.zeros_like(x)
    for load in loads:
        if load.kind == "point":
            px, py = _local(load.axes, c, s, *load.values[:2])
            on = x >= load.a
            fx += np.where(on, px, 0.0)
            fy += np.where(on, py, 0.0)
            mo += np.where(on, py * (x - load.a) - load.values[2], 0.0)
            continue
        wx1, wy1, wx2, wy2 = _trapezoid(load, c, s)
        span = load.b - load.a
        if span <= 0:
            continue
        # every section at once: the load on [a, min(x, b)] by one Gauss rule each
        top = np.clip(x, load.a, load.b)[:, None]
        t_, w_ = _GAUSS
        xs = 0.5 * (top - load.a) * t_ + 0.5 * (top + load.a)
        ws = 0.5 * (top - load.a) * w_
        t = (xs - load.a) / span
        qx, qy = wx1 + t * (wx2 - wx1), wy1 + t * (wy2 - wy1)
        fx += (ws * qx).sum(axis=1)
        fy += (ws * qy).sum(axis=1)
        mo += (ws * qy * (x[:, None] - xs)).sum(axis=1)
    return fx, fy, mo


def load_points(loads) -> list:
    """Positions along the member where a diagram has a kink or a jump."""
    pts = []
    for load in loads:
        pts += [load.a, load.b]
    return pts


def turning_points(x, F) -> np.ndarray:
    """Where a force diagram F (N or V, sampled at x, load edges among the
    samples) may turn between samples: for each sample whose neighbours'
    differences change sign, the vertex of the parabola through the three.
    Between load edges F is the integral of a linear load, a parabola, so
    the vertex is its extreme exactly (a trapezoidal load that changes sign
    in its stretch: V's extreme where w = 0, which samples alone missed by
    up to 2e-4 of it, on the unsafe side); elsewhere it is one more section
    of the true diagram, which the caller evaluates."""
    x, F = np.asarray(x, float), np.asarray(F, float)
    d = np.diff(F)
    k = np.flatnonzero(d[:-1] * d[1:] < 0)
    x0, x1, x2 = x[k], x[k + 1], x[k + 2]
    f0, f1, f2 = F[k], F[k + 1], F[k + 2]
    den = (x0 - x1) * (f1 - f2) - (x1 - x2) * (f0 - f1)
    ok = (den != 0) & (x0 < x1) & (x1 < x2)
    num = (x0 ** 2 - x1 ** 2) * (f1 - f2) - (x1 ** 2 - x2 ** 2) * (f0 - f1)
    at = 0.5 * num[ok] / den[ok]
    return at[(at > x0[ok]) & (at < x2[ok])]


def stationary_points(x, V, shear_at, iterations: int = 60) -> np.ndarray:
    """The sections where a moment is stationary: the zeros of its shear V
    (V = dM/dx) between consecutive samples x where V changes sign, found
    by false position with the Illinois step on ``shear_at`` (V at an
    array of sections) — exact in one step where V is linear (a uniform
    load), a few where it is quadratic — until V is rounding of the
    samples' or the bracket 1e-9 of the span (M is flat there: a section
    δ off moves it by w δ²/2).  A diagram's extremes taken at samples alone
    miss a span moment between them, on the unsafe side (a continuous
    beam's 7.977632 for 7.977839 kN·m at 201 samples); with these points
    added they are exact."""
    x, V = np.asarray(x, float), np.asarray(V, float)
    k = np.flatnonzero(np.sign(V[:-1]) * np.sign(V[1:]) < 0)
    if not k.size:
        return np.zeros(0)
    lo, hi, v_lo, v_hi = x[k], x[k + 1], V[k], V[k + 1]
    small, narrow = 1e-13 * np.abs(V).max(), 1e-9 * (x[-1] - x[0])
    at = lo - v_lo * (hi - lo) / (v_hi - v_lo)
    side = np.zeros(k.size)
    for _ in range(iterations):
        at = lo - v_lo * (hi - lo) / (v_hi - v_lo)
        v_at = shear_at(at)
        if np.all((np.abs(v_at) <= small) | (hi - lo <= narrow)):
            break
        left = np.sign(v_at) == np.sign(v_lo)
        # Illinois: halve the end that stays twice running, so both ends move
        v_hi = np.where(left, np.where(side > 0, 0.5 * v_hi, v_hi), v_at)
        v_lo = np.where(left, v_at, np.where(side < 0, 0.5 * v_lo, v_lo))
        lo, hi = np.where(left, at, lo), np.where(left, hi, at)
        side = np.where(left, 1.0, -1.0)
    return at


def turning_sections(x, F, F_at) -> np.ndarray:
    """Where a diagram F (sampled at x) that is no polynomial between its
    samples — a beam-column's V, with N v' in it — turns: for each sample
    whose neighbours' differences change sign, the extreme of ``F_at`` (F
    at an array of sections) between those neighbours by Brent's bounded
    search to 1e-12 of the span, started from nothing but the bracket
    (:func:`turning_points`' parabola vertex is exact only where F is a
    parabola)."""
    from scipy.optimize import minimize_scalar

    x, F = np.asarray(x, float), np.asarray(F, float)
    d = np.diff(F)
    out = []
    for k in np.flatnonzero(d[:-1] * d[1:] < 0).tolist():
        if not x[k] < x[k + 2]:
            continue
        sign = -1.0 if d[k] > 0 else 1.0           # a maximum: minimise −F
        found = minimize_scalar(lambda s: sign * float(F_at(np.array([s]))[0]),
                                bounds=(x[k], x[k + 2]), method="bounded",
                                options={"xatol": 1e-12 * (x[-1] - x[0])})
        out.append(found.x)
    return np.array(out, float)
