"""The plane Frame: one model (nodes, members, supports, springs, contacts,
load cases) whose analysis is functions taking it — solving and the
combinations in :mod:`..mechanics.solving`, Osipova–Popov–Lovtsov's
increasing-load trace in :mod:`..mechanics.tracing`, the export as a
friction problem in :mod:`..mechanics.friction_export`; the public methods
below are thin calls to them.  What is the plane frame's own — its assembly
(:mod:`.plane_assembly`), its results (:mod:`.plane_recovery`), its first
route (:mod:`.sparse_active_set`) — the shared functions reach through
:data:`PLANE`, the frame's ``kind``."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from ..mechanics import (contact_lcp, critical_load, friction_export, second_order_analysis,
                         solving, tracing)
from ..mechanics.analysis_results import keeps_its_answers
from ..mechanics.frame_kind import FrameKind
from ..mechanics.loads import (CONSTANT, SPRING_MAX, VARIABLE, MemberLoad, add_settlements,
                               case_name, check_axes, check_units, known_member, known_node,
                               no_member_between, no_same_contact, number, pair_node,
                               support_keys)
from ..mechanics.plane_element import DOFS, geometry
from ..mechanics.varying_axial import plane_member
from . import plane_assembly, plane_recovery
from .plane_results import FrameResult
from .sparse_active_set import solve_active_set

#: The plane frame's hooks of the shared analysis (:class:`FrameKind`).
PLANE = FrameKind(
    name="plane", routes=("auto", "active-set", "lemke", "tresca"), result_type=FrameResult,
    solve_one=solving.unless_linear(solving.solve_lcp), result_from_z=plane_recovery.result_from_z,
    release_directions=plane_assembly.release_directions,
    support_keys=support_keys, collapse_words=plane_recovery.collapse_words,
    slide_words=plane_recovery.slide_words, active_set=solve_active_set,
    member_under=plane_member)


@dataclass
class Member:
    """A plane frame member (``Frame.add_member``): its nodes, section, end
    releases, shear deformation, rigid end zones and member loads."""

    name: str
    i: str
    j: str
    E: float
    A: float
    I: float
    hinge_i: bool
    hinge_j: bool
    loads: list = field(default_factory=list)   # MemberLoad
    # rotational springs between the member's ends and their nodes (None:
    # rigid joint; a hinge is a spring of 0), shear deformation (G A_s,
    # None: Euler-Bernoulli), rigid end zones (lengths from the nodes)
    spring_i: float | None = None
    spring_j: float | None = None
    GAs: float | None = None
    offset_i: float = 0.0
    offset_j: float = 0.0

    @property
    def end_springs(self):
        """The rotational spring at each end: None (rigid joint) or k >= 0."""
        return (0.0 if self.hinge_i else self.spring_i, 0.0 if self.hinge_j else self.spring_j)


@dataclass
class Contact:
    """A unilateral support of a plane frame (``Frame.add_contact``)."""

    node: str
    normal: np.ndarray
    friction: float
    gap: float
    stiffness: float | None
    other: str | None


@keeps_its_answers
class Frame:
    """A plane frame with bilateral supports and springs, unilateral
    (possibly frictional) contacts, and loads in named cases (package
    docstring: units and sign conventions).  ``units`` = (force, length)
    names, used on drawings and tables only: nothing is converted.

    The model holds the data; ``solve``, ``solve_combinations``, ``trace``
    and ``friction_problem`` are the shared analysis's functions called on
    it (module docstring)."""

    #: a node's dofs, in order (rotations start with "r")
    DOFS = DOFS
    #: the plane frame's hooks of the shared analysis
    kind = PLANE

    def __init__(self, units=("kN", "m")):
        self.units = check_units(units)
        self.nodes: dict[str, np.ndarray] = {}
        self.members: dict[str, Member] = {}
        self._joined: dict[frozenset, str] = {}   # node pair -> member (no_member_between)
        self._contacts_at: dict[str, list] = {}   # node -> its contacts' indices
        self.fixed: dict[str, set] = {}
        self.node_angles: dict[str, float] = {}   # turned node axes (radians)
        self.springs: dict[str, dict] = {}
        self.contacts: list[Contact] = []
        self.nodal_loads: list = []   # (node, fx, fy, mz, case)
        self.settlements: list = []   # (node, dof, case, value)

    # -- model ------------------------------------------------------------
    def add_node(self, name: str, x: float, y: float) -> str:
        if name in self.nodes:
            raise InvalidProblemError(f"node {name!r} exists already")
        self.nodes[name] = np.array([number(x, f"node {name!r}: x"),
                                     number(y, f"node {name!r}: y")])
        return name

    def add_member(self, i: str, j: str, E: float, A: float, I: float, *, name: str | None = None,
                 hinge_i: bool = False, hinge_j: bool = False, spring_i: float | None = None,
                 spring_j: float | None = None, G: float | None = None,
                 shear_area: float | None = None, offset_i: float = 0.0,
                 offset_j: float = 0.0) -> str:
        """A frame member from node i to node j (E, A, I in consistent units).
        Returns its name.

        End releases: ``hinge_i``/``hinge_j`` release the end moment;
        ``spring_i``/``spring_j`` make the joint semi-rigid, a rotational
        spring (moment per radian) between the member's end and its node.
        Shear deformation: ``G`` (shear modulus) with ``shear_area`` (A_s,
        e.g. 5/6 A for a rectangle) makes it a Timoshenko member; without
        them it is Euler-Bernoulli.  Rigid end zones: ``offset_i``/
        ``offset_j`` (lengths along the member from each node, e.g. half
        the depth of the column it frames into) are rigid; member loads are
        still positioned from node i along the whole member."""
        known_node(self, i), known_node(self, j)
        if i == j:
            raise InvalidProblemError("a member needs two different nodes")
        what = f"member {i}-{j}" if name is None else f"member {name!r}"
        vals = {}
        for v, nm in ((E, "E"), (A, "A"), (I, "I")):
            vals[nm] = number(v, f"{what}: {nm}")
            if not vals[nm] > 0:
                raise InvalidProblemError(f"{what}: {nm} must be positive; got {v}")
        springs = []
        for v, hinged, end in ((spring_i, hinge_i, "i"), (spring_j, hinge_j, "j")):
            if v is not None:
                v = number(v, f"{what}: spring_{end}")
                if not 0 <= v <= SPRING_MAX:
                    raise InvalidProblemError(
                        f"{what}: spring_{end} must be in [0, {SPRING_MAX:g}] (moment per "
                        f"radian; stiffer is rigid: leave it out); got {v}")
                if hinged:
                    raise InvalidProblemError(f"{what}: give hinge_{end}=True or spring_{end}=, "
                                              "not both (a hinge is a spring of 0)")
            springs.append(v)
        if (G is None) != (shear_area is None):
            raise InvalidProblemError(f"{what}: shear deformation needs both G (shear modulus) "
                                      "and shear_area (A_s); give both or neither")
        GAs = None
        if G is not None:
            g, a_s = number(G, f"{what}: G"), number(shear_area, f"{what}: shear_area")
            if not (g > 0 and a_s > 0):
                raise InvalidProblemError(f"{what}: G and shear_area must be positive; "
                                          f"got {G}, {shear_area}")
            GAs = g * a_s
        L = float(np.hypot(*(self.nodes[j] - self.nodes[i])))
        if L == 0:
            raise InvalidProblemError(f"{what}: nodes {i} and {j} coincide")
        offs = [number(offset_i, f"{what}: offset_i"), number(offset_j, f"{what}: offset_j")]
        if min(offs) < 0 or not sum(offs) < L:
            raise InvalidProblemError(
                f"{what}: rigid end offsets must be >= 0 and leave a flexible length "
                f"(offset_i + offset_j < L = {L:g}); got {offs[0]:g} and {offs[1]:g}")
        name = name or f"M{len(self.members) + 1}"
        if name in self.members:
            raise InvalidProblemError(f"member {name!r} exists already; give another name")
        no_member_between(self._joined, i, j, what)
        self.members[name] = Member(name, i, j, vals["E"], vals["A"], vals["I"], bool(hinge_i),
                                     bool(hinge_j), spring_i=springs[0], spring_j=springs[1],
                                     GAs=GAs, offset_i=offs[0], offset_j=offs[1])
        self._joined[frozenset((i, j))] = name
        return name

    def add_support(self, node: str, fix=("ux", "uy", "rz"), *, angle: float | None = None) -> None:
        """Bilateral support: the listed degrees of freedom are fixed.

        ``angle`` (degrees, counterclockwise from global x) turns the node's
        axes: ux and uy then run along and across the turned x axis, so an
        inclined roller on a slope of 30° is ``fix=("uy",), angle=30``.  The
        node's settlements are given in those axes; its displacements and
        reactions are reported in global axes."""
        known_node(self, node)
        fix = (fix,) if isinstance(fix, str) else tuple(fix)
        bad = [d for d in fix if d not in DOFS]
        if bad:
            raise InvalidProblemError(f"fix must name dofs among {DOFS}; got {bad}")
        if angle is not None:
            angle = number(angle, f"support at {node!r}: angle")
            before = self.node_angles.get(node, 0.0 if node in self.fixed else None)
            if before is not None and not np.isclose(np.radians(angle), before, atol=1e-15):
                raise InvalidProblemError(
                    f"support at {node!r}: the node's axes are already turned by "
                    f"{np.degrees(before):g}°; a node has one set of axes — give all its fixed "
                    "dofs in one add_support")
            if angle % 360.0:
                self.node_angles[node] = float(np.radians(angle))
        elif node in self.node_angles:
            raise InvalidProblemError(
                f"support at {node!r}: the node's axes are turned by "
                f"{np.degrees(self.node_angles[node]):g}°; pass angle= again (a node has one "
                "set of axes)")
        self.fixed.setdefault(node, set()).update(fix)

    def add_settlement(self, node: str, case: str = CONSTANT, *, ux: float | None = None,
                       uy: float | None = None, rz: float | None = None) -> None:
        """Prescribed displacement of bilateral supports (a settlement, in
        load case ``case``): each dof given must be fixed by add_support."""
        known_node(self, node)
        given = {d: v for d, v in (("ux", ux), ("uy", uy), ("rz", rz)) if v is not None}
        if not given:
            raise InvalidProblemError(f"settlement at {node!r}: give ux=, uy= and/or rz=")
        add_settlements(self, node, given, case)

    def add_spring(self, node: str, *, ux: float = 0.0, uy: float = 0.0, rz: float = 0.0) -> None:
        """Bilateral elastic support to the ground: stiffnesses (force/length,
        moment/radian) along the global dofs; its reaction is -k u."""
        known_node(self, node)
        ks = {d: number(v, f"spring at {node!r}: {d}") for d, v in (("ux", ux), ("uy", uy),
                                                                      ("rz", rz))}
        if any(v < 0 for v in ks.values()):
            raise InvalidProblemError(f"spring at {node!r}: stiffnesses must be >= 0; got {ks}")
        slot = self.springs.setdefault(node, {})
        for d, v in ks.items():
            if v:
                slot[d] = slot.get(d, 0.0) + v

    def add_contact(self, node: str, normal=(0.0, 1.0), friction: float = 0.0, gap: float = 0.0,
                    stiffness: float | None = None, other: str | None = None) -> int:
        """A unilateral support (or node-to-node contact pair with ``other``):
        normal from the support into the structure, Coulomb coefficient
        ``friction`` (0: no tangential link), initial ``gap`` >= 0, rigid unless
        ``stiffness`` is given.  Returns the contact's index."""
        known_node(self, node)
        pair_node(self, node, other)
        try:
            n = np.array(normal, float)
        except (TypeError, ValueError):
            n = np.zeros(0)
        if n.shape != (2,) or not np.isfinite(n).all() or np.linalg.norm(n) == 0:
            raise InvalidProblemError(f"contact at {node!r}: normal must be a nonzero 2-vector")
        friction = number(friction, f"contact at {node!r}: friction")
        gap = number(gap, f"contact at {node!r}: gap")
        if not friction >= 0:
            raise InvalidProblemError(f"contact at {node!r}: friction must be >= 0")
        if not gap >= 0:
            raise InvalidProblemError(f"contact at {node!r}: gap must be >= 0 (no initial overlap)")
        if stiffness is not None:
            stiffness = number(stiffness, f"contact at {node!r}: stiffness")
            if not stiffness > 0:
                raise InvalidProblemError(
                    f"contact at {node!r}: stiffness must be > 0 or None (rigid)")
        n = n / np.linalg.norm(n)
        here = self._contacts_at.setdefault(node, [])
        no_same_contact(self.contacts, here, node, n, other)
        here.append(len(self.contacts))
        self.contacts.append(Contact(node, n, friction, gap, stiffness, other))
        return len(self.contacts) - 1

    # -- loads -------------------------------------------------------------
    def add_load(self, node: str, fx: float = 0.0, fy: float = 0.0, mz: float = 0.0,
                 case: str = CONSTANT) -> None:
        """Nodal force and moment (global axes) in load case ``case``."""
        known_node(self, node)
        self.nodal_loads.append((node, number(fx, f"load at {node!r}: fx"),
                                 number(fy, f"load at {node!r}: fy"),
                                 number(mz, f"load at {node!r}: mz"), case_name(case)))

    def _position(self, m: Member, a, what, relative):
        L = geometry(self, m)[0]
        a = number(a, f"member {m.name}: {what}")
        if relative:
            a *= L
        if not -1e-12 * L <= a <= L * (1 + 1e-12):
            raise InvalidProblemError(
                f"member {m.name}: {what} = {a:g} lies outside the member (length {L:g}"
                + (", positions given as fractions with relative=True" if relative else "") + ")")
        return min(max(a, 0.0), L)

    def add_point_load(self, member: str, a: float, fx: float = 0.0, fy: float = 0.0,
                       mz: float = 0.0, *, axes: str = "global", case: str = CONSTANT,
                       relative: bool = False) -> None:
        """A force (fx, fy) and a moment mz at distance ``a`` from node i
        (a fraction of the length with ``relative=True``)."""
        m = known_member(self, member)
        a = self._position(m, a, "a", relative)
        vals = tuple(number(v, f"point load on {member}: {nm}")
                     for v, nm in ((fx, "fx"), (fy, "fy"), (mz, "mz")))
        m.loads.append(MemberLoad("point", case_name(case), check_axes(axes), a, a, vals))

    def add_distributed_load(self, member: str, wx: float = 0.0, wy: float = 0.0,
                             case: str = CONSTANT, *, wx2: float | None = None,
                             wy2: float | None = None, start: float = 0.0,
                             end: float | None = None, axes: str = "global",
                             relative: bool = False) -> None:
        """A load per unit length of the member, (wx, wy) at ``start`` varying
        linearly to (wx2, wy2) at ``end`` (defaults: uniform over the whole
        member), in global or member axes."""
        m = known_member(self, member)
        L = geometry(self, m)[0]
        a = self._position(m, start, "start", relative)
        b = self._position(m, L if end is None else end, "end", relative and end is not None)
        if b < a:
            raise InvalidProblemError(f"member {member}: end ({b:g}) before start ({a:g})")
        w = [number(v, f"distributed load on {member}: {nm}")
             for v, nm in ((wx, "wx"), (wy, "wy"))]
        w2 = [w[0] if wx2 is None else number(wx2, f"distributed load on {member}: wx2"),
              w[1] if wy2 is None else number(wy2, f"distributed load on {member}: wy2")]
        m.loads.append(MemberLoad("distributed", case_name(case), check_axes(axes), a, b,
                                  (w[0], w[1], w2[0], w2[1])))

    def add_self_weight(self, case: str = "D", *, unit_weight: float | None = None,
                        weight_per_length: float | None = None, members=None,
                        direction=(0.0, -1.0)) -> None:
        """Self-weight as a uniform global load: ``weight_per_length``
        (force/length) or ``unit_weight`` (force/volume, e.g. 78.5 kN/m³ for
        steel) times each member's A, along ``direction`` (default -y)."""
        if (unit_weight is None) == (weight_per_length is None):
            raise InvalidProblemError("give exactly one of unit_weight (force/volume, times A) "
                                      "or weight_per_length (force/length)")
        d = np.array(direction, float)
        if d.shape != (2,) or not np.linalg.norm(d) > 0:
            raise InvalidProblemError(f"direction must be a nonzero 2-vector; got {direction!r}")
        d = d / np.linalg.norm(d)
        names = list(self.members) if members is None else list(members)
        for nm in names:
            m = known_member(self, nm)
            w = (number(weight_per_length, "weight_per_length") if unit_weight is None
                 else number(unit_weight, "unit_weight") * m.A)
            self.add_distributed_load(nm, w * d[0], w * d[1], case)

    @property
    def load_cases(self) -> list:
        return plane_assembly.cases(self)

    @property
    def has_friction(self) -> bool:
        return any(c.friction > 0 for c in self.contacts)

    # -- assembly -----------------------------------------------------------
    def build(self, axial=None, along=None):
        """The assembly (K, links, R and R_F per case): see :mod:`.plane_assembly`;
        ``axial``: the members' axial forces of a second-order stiffness,
        ``along``: the combination whose member loads make them vary."""
        return plane_assembly.build(self, axial, along)

    def stiffness(self, axial=None, along=None):
        """The frame's stiffness K (all dofs, CSR, in the nodes' axes) alone,
        first order or (``axial``: the members' axial forces, tension
        positive) second order: what α_cr's eigenvalue count reads, where
        K may be singular and ``build`` would refuse it."""
        return plane_assembly.assemble(self, axial, along, loads=False)[2]

    def lcp(self, b=None):
        """The contact LCP of the split constant + p x variable as (M,
        q_constant, q_variable, P, g,
        fric) with link displacements Δ = P z - g: z = (Z_n per contact, then
        Z⁺, Z⁻ per frictional contact)."""
        b = b or self.build()
        M, Q, q_gap, P, g, fric = contact_lcp.lcp_matrices(b)
        qc, _ = contact_lcp.combination_q(Q, q_gap, b, {CONSTANT: 1.0})
        qv, _ = contact_lcp.combination_q(Q, np.zeros_like(q_gap), b, {VARIABLE: 1.0})
        return M, qc, qv, P, g, fric

    # -- analysis: the shared functions called on this model ---------------
    def solve(self, p: float = 1.0, method: str = "auto", accuracy="high",
              raise_on_failure: bool | None = None, *, combination: dict | None = None,
              second_order: bool = False, _built=None, **options) -> FrameResult:
        """Analyse one load combination (:func:`..mechanics.solving.solve`,
        which says what ``method``, the errors and the warning are):
        ``combination`` = {case: factor}, or by default constant +
        p·variable.  ``second_order``: equilibrium on the deformed frame (P-Δ
        and P-δ, :mod:`..mechanics.second_order_analysis`).  ``time_limit``:
        wall seconds for the whole analysis (default 60; None: none); other
        keywords are the method's options, refused by name where no route
        reads them."""
        return solving.solve(self, p, method, accuracy, raise_on_failure,
                             combination=combination, second_order=second_order,
                             _built=_built, **options)

    def critical_load_factor(self, result) -> dict:
        """The elastic critical load factor α_cr of ``result``'s combination,
        its contact states held (:func:`..mechanics.critical_load.critical_load_factor`):
        {"alpha", "bracket", "mode", "members", "limited_by"}."""
        return critical_load.critical_load_factor(self, result)

    def solve_combinations(self, combinations: dict, **kw):
        """Each named combination solved on its own, as a CombinationResults
        (:func:`..mechanics.solving.solve_combinations`)."""
        return solving.solve_combinations(self, combinations, **kw)

    def trace(self, p_max: float | None = None, accuracy="high", *, constant: dict | None = None,
              variable=None, second_order: bool = False, _built=None):
        """Osipova–Popov–Lovtsov's increasing-load analysis: ``constant``,
        then ``variable`` times p from 0 to ``p_max``, as a FrameTrace
        (:func:`..mechanics.tracing.trace`; without contacts the linear
        frame's single interval, :func:`..mechanics.solving.linear_trace`);
        ``second_order``: on the deformed frame
        (:func:`..mechanics.second_order_analysis.trace_second_order`)."""
        if second_order:       # its rounds are traces of this method: hinted there
            return second_order_analysis.trace_second_order(
                self, p_max, accuracy, constant=constant, variable=variable)
        if not self.contacts:
            return solving.linear_trace(self, p_max, accuracy, constant, variable, _built)
        return solving.hinted_trace(
            self, lambda: tracing.trace(self, p_max, accuracy, constant=constant,
                                        variable=variable, _built=_built), constant, variable)

    def friction_problem(self, p: float = 1.0, *, combination: dict | None = None, _built=None):
        """The frame's contact problem for one load combination as a 2-D
        :class:`~qpcontact.FrictionProblem` in global form
        (:func:`..mechanics.friction_export.friction_problem`)."""
        return friction_export.friction_problem(self, p, combination=combination, _built=_built)
