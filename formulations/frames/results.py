"""Results of a frame analysis: one object per load combination, the trace's
objects, envelopes over combinations, and their tables (built and rounded in
:mod:`.tables`; CSV always, written atomically; pandas DataFrames with the
``tables`` extra).

Sign conventions (docs/frames.md): global x right, y up, moments
counterclockwise.  ``member_forces`` are **end actions** in member axes (x
from node i to j): the forces and moments the nodes exert on the member,
(N_i, V_i, M_i, N_j, V_j, M_j) along the member's axes — the element's
K u - f.  The **diagrams** and ``end_forces`` use the engineering convention
instead: N tension positive, M positive when it compresses the member's +y
fibre (sagging for a beam drawn left to right), V = dM/dx.  At node i the
two agree up to sign: N(0) = -N_i, V(0) = V_i, M(0) = -M_i.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import tables
from .notation import DIGITS
from .tables import TABLES

#: A plane frame's contact states; slip+ and slip- are the sign of the slip Δ_t
#: along the contact's tangent t.
STATES = ("separated", "closed", "stick", "slip+", "slip-")


@dataclass
class SupportResult:
    """A contact's outcome: ``state`` in STATES, normal force X_n (>= 0,
    compression), tangential force X_t (along t = (n_y, -n_x)), gap opening
    Z_n and slip Δ_t (user's units)."""

    state: str
    normal: float
    tangential: float
    opening: float
    slip: float


@dataclass
class AnalysisResult:
    """What every frame's analysed load combination holds (plane:
    :class:`FrameResult`, space: :class:`~.space_results.SpaceFrameResult`,
    which add their own readings of it)."""

    p: float
    supports: dict
    displacements: dict
    member_forces: dict
    reactions: dict
    equilibrium_residual: float
    lcp_error: float
    route: str
    ok: bool
    message: str
    frame: "object" = field(repr=False, default=None)
    _u: np.ndarray = field(repr=False, default=None)
    combination: dict = field(default_factory=dict)
    name: str = ""
    #: the largest nodal translation over the frame's size (the diagonal of
    #: its nodes' bounding box), and the largest rotation [rad]: beyond
    #: recovery.SMALL_DISPLACEMENT / SMALL_ROTATION the analysis (small
    #: displacements, equilibrium on the undeformed frame) no longer
    #: describes the structure, and solve warns
    displacement_ratio: float = 0.0
    max_rotation: float = 0.0


@dataclass
class FrameResult(AnalysisResult):
    """One analysed load combination: support states and forces, nodal
    displacements (ux, uy, rz), member end actions, reactions, and the checks.

    ``combination`` is {case: factor} (``p`` the factor of "variable" for the
    P3 split).  ``ok`` is True only when the LCP certificate meets the
    tolerance and equilibrium holds at every dof to the same tolerance, each
    dof's residual against its own terms (``equilibrium_residual``);
    a result that is not ok is never drawn (``plot`` raises) and its numbers
    are not an equilibrium.  ``route`` says which method produced the contact
    forces.
    """

    #: the module whose TABLES, COMBINED, rows, envelope and envelope_rows
    #: tabulate this kind of result (CombinationResults asks its results)
    table_kit = tables

    def diagram(self, member: str, points: int = 21):
        """(x, N, V, M) along a member, x from node i (member axes); the load
        positions are added to the sample points (both sides of a jump)."""
        return self.frame._diagram(self, member, points)

    def deflection(self, member: str, points: int = 21, axes: str = "member"):
        """(x, dx, dy): the displacement of the member's axis at ``points``
        sections (plus the load positions), x from node i.  ``axes="member"``:
        along and across the member (u, v); ``"global"``: (ux, uy).  Exact
        for the element's loads (integrated from N/EA and M/EI, not
        interpolated between the nodes)."""
        x, u, v = self.frame._deflection(self, member, points)
        if axes == "member":
            return x, u, v
        if axes != "global":
            from qpcontact.core.errors import InvalidOptionError

            raise InvalidOptionError(f"axes: 'member' or 'global'; got {axes!r}")
        c, s = self.frame._direction(member)
        return x, c * u - s * v, s * u + c * v

    def extremes(self, member: str) -> dict:
        """{"N"|"V"|"M"|"v": {"max": (value, x), "min": (value, x)}} along a
        member; "v" is the deflection across its axis (member axes,
        :meth:`deflection`)."""
        x, N, V, M = self.diagram(member, 201)
        xv, _, v = self.deflection(member, 201)
        out = {}
        for key, at, arr in (("N", x, N), ("V", x, V), ("M", x, M), ("v", xv, v)):
            out[key] = {"max": (float(arr.max()), float(at[arr.argmax()])),
                        "min": (float(arr.min()), float(at[arr.argmin()]))}
        return out

    def end_forces(self, member: str) -> dict:
        """Internal forces at the member's ends in the diagrams' convention:
        {"i": (N, V, M), "j": (N, V, M)}."""
        x, N, V, M = self.diagram(member, 2)
        return {"i": (float(N[0]), float(V[0]), float(M[0])),
                "j": (float(N[-1]), float(V[-1]), float(M[-1]))}

    @property
    def support_reactions(self) -> dict:
        """Every support's force on the structure in global axes (Fx, Fy, Mz),
        one entry per support: bilateral supports, springs (-k u) and
        contacts (X_n n + X_t t; for a pair, the force on ``node``).  Full
        precision; ``reactions_by_node`` sums them per node."""
        return tables.support_reactions(self.frame, self)

    @property
    def reactions_by_node(self) -> dict:
        """{node: {"total": (Fx, Fy, Mz), "support"|"spring"|"contact": ...}}:
        what the ground exerts on each node it holds, summed over the kinds
        there and each kind's part (global axes, full precision; contact
        pairs between two nodes are not reactions)."""
        return tables.reactions_by_node(self.frame, self)

    def rows(self, table: str, digits: int | None = DIGITS) -> list:
        """Rows (dicts) of the table "supports", "reactions", "members" or
        "displacements", units in the headers, rounded for reading
        (``digits`` significant digits per column, noise as 0; ``None``: full
        precision); none for a result that is no equilibrium."""
        return tables.engineering(tables.rows(self.frame, self, table), self.frame, digits)

    def to_csv(self, folder, digits: int | None = DIGITS) -> list:
        """supports.csv, reactions.csv, members.csv, displacements.csv in
        ``folder`` (each written atomically); returns the paths."""
        return tables.write_tables(folder, {t: self.rows(t, digits) for t in TABLES}, digits)

    def to_dataframe(self, table: str = "members", digits: int | None = DIGITS):
        """The table as a pandas DataFrame (the ``tables`` extra)."""
        return tables.dataframe(self.rows(table, digits))

    def plot(self, path, diagrams=("deflection", "M"), *, scale: float | None = None,
             title: str = "", loads: bool = True, reactions: bool = True) -> str:
        """Draw the result (PNG): one panel per name in ``diagrams``, among
        "deflection" (the deformed shape, exact along each member, with the
        support states, ``loads`` and ``reactions`` as arrows with values),
        "M", "V" and "N" (the internal-force diagrams, each with a scale
        bar; a straight beam is drawn as functions of x instead, its
        ordinate in the quantity's units).  ``scale``: the displacement
        magnification (default: the largest displacement drawn as 8 % of the
        structure); ``title``: replaces the combination's name.  Raises
        SolverFailedError for a result that is not ok (it is not an
        equilibrium) and InvalidOptionError for an unknown diagram."""
        from .drawing import plot_result

        return plot_result(self.frame, self, path, diagrams, scale, title, loads, reactions)


class CombinationResults(dict):
    """{combination name: FrameResult}, each solved on its own.  A
    combination the frame cannot carry has ``ok`` False and a message saying
    what happens; it does not discard the others.  ``failed`` lists them.
    The tables are those of the results' kind (``table_kit``: a plane
    frame's :mod:`.tables`, a space frame's :mod:`.space_tables`)."""

    @property
    def failed(self) -> list:
        return [name for name, r in self.items() if not r.ok]

    def envelope(self) -> dict:
        """Max/min over the combinations that are ok (full precision): per
        member {"N"|"V"|"M": {"max": (value, x, combination), "min": ...}}
        (the diagrams' extremes, ends included), and per node the ground
        holds {"Fx"|"Fy"|"Mz": {"max": (value, combination), ...}} of its
        total reaction under the key "supports" (a space frame's: see
        :func:`.space_tables.envelope`)."""
        return self._kit().envelope(self)

    def rows(self, table: str, digits: int | None = DIGITS) -> list:
        """One table over all combinations, rounded per column over all of
        them (``digits=None``: full precision): a result table with a
        "combination" column first, "envelope" (members),
        "envelope_reactions" (nodes) or "combinations" (each one's status);
        a space frame's also "envelope_supports" (contacts)."""
        kit = self._kit()
        tables.check_table(table, kit.TABLES + kit.COMBINED)
        if table == "combinations":
            return [{"combination": n, "ok": r.ok, "route": r.route, "message": r.message}
                    for n, r in self.items()]
        frame = self._frame()
        if frame is None:
            return []
        if table in kit.COMBINED:
            raw = kit.envelope_rows(frame, self.envelope(), table)
        else:
            raw = [{"combination": name, "ok": r.ok, **row} for name, r in self.items()
                   for row in kit.rows(frame, r, table)]
        return tables.engineering(raw, frame, digits)

    def envelope_rows(self, digits: int | None = DIGITS) -> list:
        """The members' envelope table: rows("envelope")."""
        return self.rows("envelope", digits)

    def to_csv(self, folder, digits: int | None = DIGITS) -> list:
        """Every table of ``rows`` as folder/<table>.csv (atomic writes)."""
        kit = self._kit()
        return tables.write_tables(
            folder, {t: self.rows(t, digits) for t in kit.TABLES + kit.COMBINED}, digits)

    def to_dataframe(self, table: str = "members", digits: int | None = DIGITS):
        """A table of ``rows`` as a pandas DataFrame (the ``tables`` extra)."""
        return tables.dataframe(self.rows(table, digits))

    def _frame(self):
        return next((r.frame for r in self.values() if r.frame is not None), None)

    def _kit(self):
        return next((type(r).table_kit for r in self.values()), tables)


@dataclass
class FrameEvent:
    """A breakpoint of the trace: at load parameter ``p`` the supports in
    ``changes`` go from one state to another ({support: (before, after)})."""

    p: float
    changes: dict

    def __str__(self) -> str:
        return "; ".join(f"{k}: {a} \u2192 {b}" for k, (a, b) in self.changes.items())


@dataclass
class FrameTrace:
    """The increasing-load analysis (P3).

    ``breakpoints``: the values of p where some support changes state, with
    ``events`` saying which and how ("S3: stick → slip-"); ``intervals``
    [(p_start, p_end)] between them and ``states`` (a FrameResult at the
    middle of each); ``ended``: why the trace stopped — "p_max" (reached),
    "unbounded" (no support changes state again, p_max = inf), "collapse"
    (no equilibrium exists beyond the end: proved, and ``message`` says how
    the frame fails), "fold" (equilibria may exist beyond but none continues
    this path), "breakdown", "max_pieces" (see docs/frames.md); ``ok`` is True
    when every traced piece passed the LCP certificate and the equilibrium
    check at its start, middle and end, and the ending is proved.
    ``result_at(p)`` analyses any p inside the traced range.
    """

    breakpoints: np.ndarray
    states: list
    intervals: list
    events: list
    ended: str
    message: str
    ok: bool
    trace: object = field(repr=False, default=None)
    frame: "object" = field(repr=False, default=None)
    _built: dict = field(repr=False, default=None)   # the frame's assembly, reused by result_at
    constant: dict = field(default_factory=dict)
    variable: dict = field(default_factory=dict)

    @property
    def p_end(self) -> float:
        """Where the traced range ends (inf on an unbounded last interval)."""
        return self.intervals[-1][1] if self.intervals else 0.0

    def result_at(self, p: float) -> FrameResult:
        return self.frame._result_from_z(self.trace.z_at(p), self._combo(p), "trace",
                                         b=self._built)

    def _combo(self, p):
        combo = dict(self.constant)
        for case, f in self.variable.items():
            combo[case] = combo.get(case, 0.0) + p * f
        return combo

    def plot(self, path, node: str, dof: str = "ux", p_max: float | None = None) -> str:
        """Load parameter against a displacement of ``node`` (PNG), each
        breakpoint numbered on the curve and listed with its events in a key
        beside it.  Default range: the traced one (an unbounded last
        interval: 1.5 x the last breakpoint)."""
        from .trace_plot import plot_trace

        return plot_trace(self.frame, self, path, node, dof, p_max)
