"""Space frames on unilateral frictional supports: Osipova–Popov–Lovtsov's displacement method
in three dimensions.

Six dofs per node, (ux, uy, uz, rx, ry, rz) in global axes (right-handed,
rotations counterclockwise about each axis); members are the 3-D
beam-column elements of :mod:`..mechanics.space_element`; bilateral supports fix any
subset of the six dofs; springs resist -k·u on any dof; loads belong to
named cases as in 2-D (:mod:`.loads`).  Units the user's, consistent.

What is here: the model and the assembly of its problem (``build``: K,
the load columns, the links); a frame without contacts is solved
linearly by ``solve`` as any other.  Solving, combinations and the
trace are the plane frame's (:mod:`.solving`, :mod:`.tracing`: the LCP is
the same in any dimension once the links and the cone's facets are laid
out); the results are built in :mod:`.space_recovery` (the circular cone's
in :mod:`.space_circular`), tabulated in :mod:`.space_tables` and drawn in
:mod:`.space_drawing`.

Contacts (the displacement method's, in 3-D): at a node, a contact plane with unit normal n from the
support into the structure, tangents t1, t2 (t1 = n x e normalised for the
global axis e least aligned with n, t2 = n x t1).  Links: the opening Z_n =
g + n·u (+X_n/k), and with friction f > 0 the tangential displacement
(t1·u, t2·u) (+X_t/k).  The cone |X_t| <= f X_n is replaced by the m-gon
circumscribing it: w_k = f X_n + d_k·X_t >= 0 for the facet directions d_k =
cos(2πk/m) t1 + sin(2πk/m) t2, k = 0..m-1, each complementary to a slip
magnitude Z_k >= 0 along d_k (the slip is Σ Z_k d_k; slipping along d_k
takes the friction force to -f X_n along it).  With m = 2 in a plane this
is the plane frame's 2-D LCP; along the directions d_k the faceted and circular cones
agree, between them the facets allow up to 1/cos(π/m) more friction.  Where
the node's bilateral supports hold one tangent, that tangent has no link
and the cone is the segment along the other, two facets: a planar frame
built in space has exactly the plane frame's LCP.  A node-to-node pair
(``other``) reads the relative motion u_node − u_other in place of u (its
links +n at the node, −n at the other): equal and opposite forces, and a
tangent is held only where both nodes' supports fix it.

Member loads (the plane frame's options with the third axis): point forces
and moments, and distributed loads, uniform or trapezoidal over the whole
member or part of it, and self-weight, in global or member axes
(:mod:`.space_member_loads`).  Their equivalent nodal loads are the
element's exact fixed-end forces: for a uniform load w over the whole
member w L / 2 at each end along each axis, and the end moments w L² / 12 —
in the x-y plane +q_y L²/12 about z at i and minus that at j; in the x-z
plane the signs reversed (a positive θy turns +z towards -x).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from ..mechanics import (critical_load, friction_export, second_order_analysis, solving,
                         tracing)
from ..mechanics.analysis_results import hand_over, keeps_its_answers
from ..mechanics.frame_kind import FrameKind
from ..mechanics.loads import (CONSTANT, SPRING_MAX, VARIABLE, add_settlements, case_name,
                               check_axes, check_units, known_member, known_node,
                               no_member_between, no_same_contact, number, pair_node,
                               support_keys)
from ..mechanics.space_element import END_ROTATIONS, axes
from . import circular_cone, circular_trace, space_assembly, space_recovery, space_varying
from .space_member_loads import SpanLoad, position
from .space_results import DOFS, SpaceFrameResult

#: The space frame's hooks of the shared analysis (:class:`FrameKind`): Lemke
#: on the faceted cone, or the friction solvers on the circular one.
SPACE = FrameKind(
    name="space", routes=("auto", "lemke"), result_type=SpaceFrameResult,
    solve_one=solving.unless_linear(circular_trace.solve_on_path),
    result_from_z=space_recovery.result_from_z,
    release_directions=space_assembly.release_directions,
    support_keys=support_keys, collapse_words=space_recovery.collapse_words,
    slide_words=space_recovery.slide_words, member_under=space_varying.member_under)


#: the frame's friction models: Coulomb's circle itself, or a polygon of
#: each contact's facets inside it (never more friction: the safe side) or
#: around it (never less)
CONES = ("circular", "inscribed", "circumscribed")


def unit_vector(value, message: str) -> np.ndarray:
    """``value`` as a unit 3-vector; InvalidProblemError(``message``) where it
    is not a finite nonzero 3-vector."""
    try:
        v = np.array(value, float)
    except (TypeError, ValueError):
        v = np.zeros(0)
    if v.shape != (3,) or not np.all(np.isfinite(v)) or not np.linalg.norm(v) > 0:
        raise InvalidProblemError(message)
    return v / np.linalg.norm(v)


def turned_axes(angle, what: str) -> np.ndarray:
    """The turned axes of a rotation vector ``angle`` (degrees) as the rows
    of a 3 x 3 matrix (Rodrigues: the node's axis e'_k = Rot e_k, the rows
    are Rotᵀ, so u' = Rotᵀ u); InvalidProblemError(``what``) unless a
    finite 3-vector."""
    if isinstance(angle, (int, float, np.number)) and not isinstance(angle, bool):
        raise InvalidProblemError(
            f"{what}: in space a rotation vector (ax, ay, az) in degrees — the axes turned "
            f"about its direction by its length; got the number {angle!r} (the plane frame's "
            f"angle={angle!r} is (0, 0, {angle!r}))")
    try:
        v = np.array(angle, float)
    except (TypeError, ValueError):
        v = np.zeros(0)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise InvalidProblemError(f"{what}: a rotation vector (ax, ay, az) in degrees; got "
                                  f"{angle!r}")
    theta = float(np.radians(np.linalg.norm(v)))
    if theta % (2 * np.pi) == 0.0:
        return np.eye(3)
    k = v / np.linalg.norm(v)
    cross = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    rot = np.eye(3) + np.sin(theta) * cross + (1.0 - np.cos(theta)) * cross @ cross
    return rot.T


@dataclass
class SpaceContact:
    """A unilateral support at a node: unit normal n (from the support into
    the structure), tangents t1, t2, Coulomb coefficient, initial gap,
    stiffness (None: rigid), facets of the friction cone's polygon (where
    the frame's cone is one); ``other``: the second node of a node-to-node
    pair (None: the ground)."""

    node: str
    normal: np.ndarray
    t1: np.ndarray
    t2: np.ndarray
    friction: float
    gap: float
    stiffness: float | None
    facets: int
    other: str | None = None


def shear_areas(shear_area, G: float, what: str) -> tuple:
    """(G A_sy, G A_sz), None for a plane without shear deformation."""
    if shear_area is None:
        return (None, None)
    pair = (shear_area, shear_area) if not isinstance(shear_area, (tuple, list)) \
        else tuple(shear_area)
    if len(pair) != 2:
        raise InvalidProblemError(f"{what}: shear_area is one area or a pair (A_sy, A_sz); "
                                  f"got {shear_area!r}")
    out = []
    for v, axis in zip(pair, "yz"):
        if v is not None:
            v = number(v, f"{what}: shear_area along {axis}")
            if not v > 0:
                raise InvalidProblemError(f"{what}: shear_area along {axis} must be positive "
                                          f"(or None: no shear deformation); got {v}")
            v = G * v
        out.append(v)
    return tuple(out)


def end_springs(spring, what: str) -> dict:
    """{rotation: stiffness} of a ``spring_i``/``spring_j`` value: None
    none, a number both bending rotations, or a dict by member-axis
    rotation."""
    if spring is None:
        return {}
    given = spring if isinstance(spring, dict) else {"ry": spring, "rz": spring}
    out = {}
    for r, v in given.items():
        if r not in END_ROTATIONS:
            raise InvalidProblemError(f"{what}: rotations among {tuple(END_ROTATIONS)} in member "
                                      f"axes; got {r!r}")
        out[r] = number(v, f"{what}: {r}")
        if not 0 <= out[r] <= SPRING_MAX:
            raise InvalidProblemError(f"{what}: {r} must be in [0, {SPRING_MAX:g}] (moment per "
                                      f"radian; stiffer is rigid: leave it out); got {out[r]}")
    return out


def released(hinge, what: str) -> tuple:
    """The member-axis rotations a ``hinge_i``/``hinge_j`` value releases:
    False none, True both bending moments, or names among rx, ry, rz."""
    if hinge is False or hinge is None:
        return ()
    if hinge is True:
        return ("ry", "rz")
    names = (hinge,) if isinstance(hinge, str) else hinge
    try:
        names = tuple(names)
    except TypeError:
        names = (hinge,)
    bad = [r for r in names if r not in END_ROTATIONS]
    if bad or not names or len(set(names)) != len(names):
        raise InvalidProblemError(
            f"{what}: True (both bending moments), False, or the rotations to release among "
            f"{tuple(END_ROTATIONS)} in member axes, each once, e.g. ('rz',); got {hinge!r}")
    return names


@keeps_its_answers
class SpaceFrame:
    """A space frame (see the module docstring); ``units`` = (force, length)
    names, for tables and drawings only.

    ``solve(p, method="auto", combination=...)``, ``solve_combinations`` and
    ``trace`` are the plane frame's (:class:`~.model.Frame`): "auto" is
    Lemke on the faceted-cone LCP (the exact SPD method without friction),
    then the load path where Lemke's answer fails the frame's checks;
    "lemke" alone, or a registered LCP method or QP backend for a
    frictionless frame.  ``friction_problem`` gives the circular-cone
    problem (3-D FrictionProblem, global form) for the friction solvers and
    FCLIB; ``solve(..., cone="circular")`` solves it by them ("auto" or a
    friction method's name) and gives the frame's result
    (:mod:`.space_circular`)."""

    #: a node's dofs, in order (rotations start with "r")
    DOFS = DOFS
    #: the space frame's hooks of the shared analysis
    kind = SPACE

    def __init__(self, units=("kN", "m"), cone: str = "circular"):
        self.units = check_units(units)
        self.cone = cone
        self.nodes: dict[str, np.ndarray] = {}
        self.members: dict[str, dict] = {}
        self._joined: dict[frozenset, str] = {}   # node pair -> member (no_member_between)
        self._contacts_at: dict[str, list] = {}   # node -> its contacts' indices
        self.fixed: dict[str, set] = {}
        # turned node axes: rows the node's x', y', z' in global axes (add_support's angle)
        self.node_axes: dict[str, np.ndarray] = {}
        self.springs: dict[str, dict] = {}
        self.nodal_loads: list = []   # (node, 6 values, case)
        self.span_loads: list = []    # SpanLoad: point and distributed member loads
        self.settlements: list = []   # (node, dof, case, value)
        self.contacts: list = []      # SpaceContact

    def add_node(self, name: str, x: float, y: float, z: float) -> str:
        if name in self.nodes:
            raise InvalidProblemError(f"node {name!r} exists already")
        self.nodes[name] = np.array([number(v, f"node {name!r}: {c}")
                                     for v, c in zip((x, y, z), "xyz")])
        return name

    def add_member(self, i: str, j: str, E: float, A: float, Iy: float, Iz: float, *more,
                   G: float | None = None, J: float | None = None, name: str | None = None,
                   ref=None, roll: float = 0.0,
                   hinge_i=False, hinge_j=False, spring_i=None, spring_j=None,
                   shear_area=None, offset_i: float = 0.0, offset_j: float = 0.0) -> str:
        """A member from node i to node j: E, A, Iy, Iz (about the local y
        and z axes) in the plane frame's order (E, A, I), and its torsion,
        the shear modulus ``G`` and torsion constant ``J`` (keywords: ``G``
        is the plane frame's, which there comes with ``shear_area``); its
        local x-z plane contains ``ref`` (default global Z, or X for a
        vertical member), turned by ``roll`` (radians) about x.  Returns
        its name.

        End releases, as the plane frame's: ``hinge_i``/``hinge_j`` True
        releases both bending moments at that end (My and Mz: a ball joint
        that still carries the twist), or name the member-axis rotations to
        release, e.g. ``hinge_j=("rz",)`` (a hinge about the local z only)
        or ``("rx",)`` (a torsion release).  ``spring_i``/``spring_j`` make
        the joint semi-rigid: a rotational spring (moment per radian)
        between the member's end and its node, one number for both bending
        rotations or {"rx"|"ry"|"rz": k} (a hinge is a spring of 0).

        Shear deformation, as the plane frame's ``shear_area``: the shear
        areas (A_sy, A_sz) for shear along the local y and z axes (e.g. 5/6
        A each for a rectangle; one number for both) make it a Timoshenko
        member in each plane given (None in the pair: that plane
        Euler-Bernoulli); G is the member's own.

        Rigid end zones, as the plane frame's: ``offset_i``/``offset_j``
        (lengths along the member from each node) are rigid; releases act
        at the faces of the zones; member loads are still placed from node
        i along the whole member."""
        what = f"member {i}-{j}" if name is None else f"member {name!r}"
        if more or G is None or J is None:
            # the space frame's constants once came in the order E, G, A,
            # Iy, Iz, J: such a call would bind G to A, so it is refused
            got = f"{4 + len(more)} section constants by position" if more else \
                "no " + " and no ".join(k for k, v in (("G", G), ("J", J)) if v is None)
            raise InvalidProblemError(
                f"{what}: add_member takes E, A, Iy, Iz by position (the plane frame's order "
                f"E, A, I) and the torsion's G and J by keyword; got {got} — write e.g. "
                "add_member(i, j, E, A, Iy, Iz, G=G, J=J)")
        known_node(self, i), known_node(self, j)
        if i == j:
            raise InvalidProblemError("a member needs two different nodes")
        props = {}
        for v, nm in ((E, "E"), (A, "A"), (Iy, "Iy"), (Iz, "Iz"), (G, "G"), (J, "J")):
            props[nm] = number(v, f"{what}: {nm}")
            if not props[nm] > 0:
                raise InvalidProblemError(f"{what}: {nm} must be positive; got {v}")
        if ref is not None:
            ref = np.asarray(ref, float)
            if ref.shape != (3,) or not np.all(np.isfinite(ref)):
                raise InvalidProblemError(f"{what}: ref must be a finite 3-vector")
        roll = number(roll, f"{what}: roll")
        if not np.linalg.norm(self.nodes[j] - self.nodes[i]) > 0:
            raise InvalidProblemError(f"{what}: nodes {i} and {j} coincide")
        try:
            axes(self.nodes[i], self.nodes[j], ref, roll)
        except InvalidProblemError as exc:     # it numbers the member; name it
            raise InvalidProblemError(
                f"{what}: its reference vector {tuple(map(float, ref))} is parallel to the "
                "member; give one in the plane of the member's local x-z axes") from exc
        GAs = shear_areas(shear_area, props["G"], what)
        L = space_varying.member_length(self.nodes[i], self.nodes[j])
        offs = [number(offset_i, f"{what}: offset_i"), number(offset_j, f"{what}: offset_j")]
        if min(offs) < 0 or not sum(offs) < L:
            raise InvalidProblemError(
                f"{what}: rigid end offsets must be >= 0 and leave a flexible length "
                f"(offset_i + offset_j < L = {L:g}); got {offs[0]:g} and {offs[1]:g}")
        releases = []
        for hinge, spring, end, at in ((hinge_i, spring_i, "i", 0), (hinge_j, spring_j, "j", 6)):
            hinged = released(hinge, f"{what}: hinge_{end}")
            springs = end_springs(spring, f"{what}: spring_{end}")
            both = sorted(set(hinged) & set(springs))
            if both:
                raise InvalidProblemError(f"{what}: give hinge_{end} or spring_{end} for {both}, "
                                          "not both (a hinge is a spring of 0)")
            releases += [(at + END_ROTATIONS[r], 0.0) for r in hinged]
            releases += [(at + END_ROTATIONS[r], k) for r, k in springs.items()]
        if {3, 9} <= {r for r, k in releases if k == 0.0}:
            raise InvalidProblemError(
                f"{what}: its twist is released at both ends (rx in hinge_i and hinge_j), so "
                "nothing holds it from spinning about its axis; release rx at one end at most")
        name = name or f"M{len(self.members) + 1}"
        if name in self.members:
            raise InvalidProblemError(f"member {name!r} exists already; give another name")
        no_member_between(self._joined, i, j, what)
        self.members[name] = dict(i=i, j=j, ref=ref, roll=roll, releases=tuple(releases),
                                  GAs=GAs, offsets=tuple(offs), **props)
        self._joined[frozenset((i, j))] = name
        return name

    def add_support(self, node: str, fix=DOFS, *, angle=None) -> None:
        """Bilateral support: the listed degrees of freedom are fixed.

        ``angle`` (degrees) turns the node's axes, as the plane frame's:
        a rotation vector (ax, ay, az) — the axes turned by its length
        about its direction, counterclockwise seen from its tip; (0, 0, θ)
        is the plane frame's ``angle=θ``.  The dofs fixed and the node's
        settlements are then along the turned axes; its displacements and
        reactions are reported in global axes.  A roller on a slope rising
        at 30° along +x (its normal turned from +z towards -x) is
        ``fix=("uz",), angle=(0, -30, 0)``."""
        known_node(self, node)
        fix = (fix,) if isinstance(fix, str) else tuple(fix)
        bad = [d for d in fix if d not in DOFS]
        if bad:
            raise InvalidProblemError(f"fix must name dofs among {DOFS}; got {bad}")
        if angle is not None:
            turn = turned_axes(angle, f"support at {node!r}: angle")
            before = self.node_axes.get(node, np.eye(3) if node in self.fixed else None)
            if before is not None and not np.allclose(turn, before, rtol=0.0, atol=1e-15):
                raise InvalidProblemError(
                    f"support at {node!r}: the node's axes are already turned otherwise; a node "
                    "has one set of axes — give all its fixed dofs in one add_support")
            if not np.array_equal(turn, np.eye(3)):
                self.node_axes[node] = turn
        elif node in self.node_axes:
            raise InvalidProblemError(
                f"support at {node!r}: the node's axes are turned; pass the same angle= again "
                "(a node has one set of axes)")
        self.fixed.setdefault(node, set()).update(fix)

    def add_settlement(self, node: str, case: str = CONSTANT, **displacements) -> None:
        """Prescribed displacement of bilateral supports (a settlement, in
        load case ``case``), global axes: add_settlement("A", "S", uz=-0.01);
        each dof given must be fixed by add_support."""
        known_node(self, node)
        if not displacements:
            raise InvalidProblemError(f"settlement at {node!r}: give displacements among "
                                      f"{DOFS}, e.g. uz=-0.01")
        bad = [d for d in displacements if d not in DOFS]
        if bad:
            raise InvalidProblemError(f"settlement at {node!r}: dofs among {DOFS}; got {bad[0]!r}")
        add_settlements(self, node, displacements, case)

    def add_spring(self, node: str, **stiffnesses) -> None:
        """Springs to the ground on the named dofs: add_spring("A", uz=1e5)."""
        known_node(self, node)
        bad = [d for d in stiffnesses if d not in DOFS]
        if bad:
            raise InvalidProblemError(f"spring at {node!r}: dofs among {DOFS}; got {bad}")
        slot = self.springs.setdefault(node, {})
        for d, v in stiffnesses.items():
            v = number(v, f"spring at {node!r}: {d}")
            if v < 0:
                raise InvalidProblemError(f"spring at {node!r}: {d} must be >= 0; got {v}")
            slot[d] = slot.get(d, 0.0) + v

    def add_load(self, node: str, fx=0.0, fy=0.0, fz=0.0, mx=0.0, my=0.0, mz=0.0,
                 case: str = CONSTANT) -> None:
        known_node(self, node)
        vals = tuple(number(v, f"load at {node!r}: {c}") for v, c in
                     zip((fx, fy, fz, mx, my, mz), ("fx", "fy", "fz", "mx", "my", "mz")))
        self.nodal_loads.append((node, vals, case_name(case)))

    def _member_length(self, member: str) -> float:
        m = known_member(self, member)
        return space_varying.member_length(self.nodes[m["i"]], self.nodes[m["j"]])

    def add_point_load(self, member: str, a: float, fx=0.0, fy=0.0, fz=0.0, mx=0.0, my=0.0,
                       mz=0.0, *, axes: str = "global", case: str = CONSTANT,
                       relative: bool = False) -> None:
        """A force (fx, fy, fz) and a moment (mx, my, mz) at distance ``a``
        from node i (a fraction of the length with ``relative=True``), in
        global or member axes (:mod:`.space_member_loads`)."""
        L = self._member_length(member)
        a = position(L, a, "a", relative, member)
        vals = tuple(number(v, f"point load on {member}: {c}") for v, c in
                     zip((fx, fy, fz, mx, my, mz), ("fx", "fy", "fz", "mx", "my", "mz")))
        self.span_loads.append(SpanLoad(member, "point", case_name(case), check_axes(axes), a, a,
                                        vals))

    def add_distributed_load(self, member: str, wx=0.0, wy=0.0, wz=0.0, case: str = CONSTANT,
                             *, wx2=None, wy2=None, wz2=None, start: float = 0.0,
                             end: float | None = None, axes: str = "global",
                             relative: bool = False) -> None:
        """A load per unit length of the member, (wx, wy, wz) at ``start``
        varying linearly to (wx2, wy2, wz2) at ``end`` (defaults: uniform
        over the whole member), in global or member axes — the plane
        frame's keywords with the third axis."""
        L = self._member_length(member)
        a = position(L, start, "start", relative, member)
        b = position(L, L if end is None else end, "end", relative and end is not None, member)
        if b < a:
            raise InvalidProblemError(f"member {member}: end ({b:g}) before start ({a:g})")
        w = tuple(number(v, f"distributed load on {member}: {c}")
                  for v, c in zip((wx, wy, wz), ("wx", "wy", "wz")))
        w2 = tuple(w[k] if v is None else number(v, f"distributed load on {member}: {c}")
                   for k, (v, c) in enumerate(zip((wx2, wy2, wz2), ("wx2", "wy2", "wz2"))))
        self.span_loads.append(SpanLoad(member, "distributed", case_name(case), check_axes(axes),
                                        a, b, w + w2))

    def add_self_weight(self, case: str = "D", *, unit_weight: float | None = None,
                        weight_per_length: float | None = None, members=None,
                        direction=(0.0, 0.0, -1.0)) -> None:
        """Self-weight as a uniform global load: ``weight_per_length``
        (force/length) or ``unit_weight`` (force/volume, e.g. 78.5 kN/m³ for
        steel) times each member's A, along ``direction`` (default -z)."""
        if (unit_weight is None) == (weight_per_length is None):
            raise InvalidProblemError("give exactly one of unit_weight (force/volume, times A) "
                                      "or weight_per_length (force/length)")
        d = unit_vector(direction, f"direction must be a nonzero 3-vector; got {direction!r}")
        for name in (list(self.members) if members is None else list(members)):
            m = known_member(self, name)
            w = (number(weight_per_length, "weight_per_length") if unit_weight is None
                 else number(unit_weight, "unit_weight") * m["A"])
            self.add_distributed_load(name, *(w * d), case)

    @property
    def member_loads(self) -> list:
        """The uniform loads over whole members as (member, (wx, wy, wz),
        axes, case) — what the drawings and the benchmarks' exports read."""
        return [(ld.member, ld.values[:3], ld.axes, ld.case) for ld in self.span_loads
                if ld.whole_uniform(self._member_length(ld.member))]

    def add_contact(self, node: str, normal=(0.0, 0.0, 1.0), friction: float = 0.0,
                    gap: float = 0.0, stiffness: float | None = None,
                    facets: int = 16, other: str | None = None) -> int:
        """A unilateral support at ``node`` (the module docstring): its
        normal, Coulomb coefficient, initial gap, spring (None: rigid), and
        the number of facets (even, >= 4) of its friction cone's polygon
        where the frame's ``cone`` is one ("inscribed" or "circumscribed":
        docs/frames.md).  ``other``: a node-to-node pair, as the plane
        frame's — the contact acts on ``node`` along n and on ``other``
        opposite; its opening and slip are the relative motion of ``node``
        from ``other``."""
        known_node(self, node)
        pair_node(self, node, other)
        n = unit_vector(normal, f"contact at {node!r}: normal must be a nonzero 3-vector")
        friction, gap = number(friction, "friction"), number(gap, "gap")
        if friction < 0 or gap < 0:
            raise InvalidProblemError(f"contact at {node!r}: friction and gap must be >= 0")
        if stiffness is not None and not number(stiffness, "stiffness") > 0:
            raise InvalidProblemError(f"contact at {node!r}: stiffness must be > 0 or None")
        if isinstance(facets, bool) or not isinstance(facets, int) or facets < 4 or facets % 2:
            raise InvalidProblemError(f"contact at {node!r}: facets must be an even integer "
                                      f">= 4 (opposite directions both facets); got {facets!r}")
        here = self._contacts_at.setdefault(node, [])
        no_same_contact(self.contacts, here, node, n, other)
        here.append(len(self.contacts))
        e = np.eye(3)[int(np.argmin(np.abs(n)))]
        t1 = np.cross(n, e)
        t1 /= np.linalg.norm(t1)
        self.contacts.append(SpaceContact(node, n, t1, np.cross(n, t1), friction, gap,
                                          None if stiffness is None else float(stiffness),
                                          facets, other))
        return len(self.contacts) - 1

    @property
    def cone(self) -> str:
        """The friction model of every contact: "circular" (Coulomb's cone
        itself, the default: solved by the friction solvers), "inscribed"
        (each contact's m-gon inside the circle: never more friction than
        Coulomb, at most 1 - cos(π/m) less — 1.9 % with 16 facets) or
        "circumscribed" (around it: at most 1/cos(π/m) - 1 more, 2.0 %);
        the polygons are solved as an LCP by Lemke and the load path."""
        return self._cone

    @cone.setter
    def cone(self, value: str) -> None:
        if value not in CONES:
            raise InvalidProblemError(
                f"cone must be one of {CONES}; got {value!r} (\"circular\": Coulomb's law; a "
                "polygon only on request: \"inscribed\" never gives more friction than "
                "Coulomb, the safe side)")
        hand_over(self)
        self._cone = value

    @property
    def load_cases(self) -> list:
        names = {CONSTANT, VARIABLE}
        names.update(c for *_, c in self.nodal_loads)
        names.update(ld.case for ld in self.span_loads)
        names.update(st[2] for st in self.settlements)
        return sorted(names)

    @property
    def has_friction(self) -> bool:
        return any(c.friction > 0 for c in self.contacts)

    def build(self, axial=None, along=None):
        """The assembly the solving routes share with the plane frame (an
        :class:`~..mechanics.contact_lcp.Built`): K, loads, links, the basic
        system's LU, the faceted cones' maps; R and R_F on first use
        (:func:`.space_assembly.build`); ``axial``, ``along``: a second-order
        stiffness's axial forces and the loads making N vary (:mod:`.space_varying`)."""
        return space_assembly.build(self, axial, along)

    def stiffness(self, axial=None, along=None):
        """The frame's stiffness K (all dofs, CSR) alone, first order or
        (``axial``, ``along``: :meth:`build`) second order: what α_cr's count reads."""
        return space_assembly.assemble(self, axial, along, loads=False)[0]

    # -- analysis: the shared functions called on this model ---------------
    def solve(self, p: float = 1.0, method: str = "auto", accuracy="high",
              raise_on_failure: bool | None = None, *, combination: dict | None = None,
              second_order: bool = False, _built=None, **options) -> SpaceFrameResult:
        """Analyse one load combination (:func:`..mechanics.solving.solve`)
        on the frame's ``cone``: the circular one by the friction solvers
        (:mod:`.circular_cone`), a polygon as the LCP of its facets;
        ``second_order``: on the deformed frame
        (:func:`..mechanics.second_order_analysis.solve_second_order`);
        ``time_limit``: wall seconds for the whole analysis (default 60;
        None: none; the circle's load path reads it between its solves)."""
        return solving.solve(self, p, method, accuracy, raise_on_failure,
                             combination=combination, second_order=second_order,
                             _built=_built, **options)

    def critical_load_factor(self, result) -> dict:
        """The elastic critical load factor α_cr of ``result``'s combination,
        its contact states held
        (:func:`..mechanics.critical_load.critical_load_factor`)."""
        return critical_load.critical_load_factor(self, result)

    def solve_combinations(self, combinations: dict, **kw):
        """Each named combination solved on its own, as a CombinationResults
        (:func:`..mechanics.solving.solve_combinations`)."""
        return solving.solve_combinations(self, combinations, **kw)

    def trace(self, p_max: float | None = None, accuracy="high", *, constant: dict | None = None,
              variable=None, second_order: bool = False, _built=None, **options):
        """The increasing-load analysis, as a FrameTrace: on the circular
        cone by certified solves, events and the limit as brackets
        (:func:`.circular_trace.trace`; option ``samples``); on a polygon
        the LCP's exact path (:func:`..mechanics.tracing.trace`); without
        contacts the linear frame's single interval
        (:func:`..mechanics.solving.linear_trace`); ``second_order``: on the
        deformed frame (:func:`..mechanics.second_order_analysis.trace_second_order`)."""
        if second_order:       # its rounds are traces of this method: hinted there
            return second_order_analysis.trace_second_order(
                self, p_max, accuracy, constant=constant, variable=variable, **options)
        if not self.contacts:
            if options:
                raise InvalidProblemError(f"a frame without contacts is traced with no "
                                          f"options; got {sorted(options)}")
            return solving.linear_trace(self, p_max, accuracy, constant, variable, _built)
        if self.cone == "circular":
            return solving.hinted_trace(self, lambda: circular_trace.trace(
                self, p_max, accuracy, constant=constant, variable=variable, _built=_built,
                **options), constant, variable)
        if options:
            raise InvalidProblemError(f"trace on a polygon takes no options {sorted(options)} "
                                      "(samples is the circular cone's)")
        return solving.hinted_trace(self, lambda: tracing.trace(
            self, p_max, accuracy, constant=constant, variable=variable, _built=_built),
            constant, variable)

    def friction_problem(self, p: float = 1.0, *, combination: dict | None = None, _built=None):
        """The frame's contact problem for one load combination as a 3-D
        :class:`~qpcontact.FrictionProblem` with the circular cone, in global
        form (:func:`..mechanics.friction_export.friction_problem`)."""
        return friction_export.friction_problem(self, p, combination=combination, _built=_built)
