"""Results of a space-frame analysis: one object per load combination, in
the plane frame's form (:mod:`.results`) with six dofs per node and contact
forces and slips as vectors in the contact's tangent plane.

Sign conventions: global axes x, y, z right-handed, rotations
counterclockwise about each axis (right-hand rule).  ``member_forces`` are
**end actions** in member axes (x from node i to j, y and z the section's
principal axes): the forces and moments the nodes exert on the member,
(N, Vy, Vz, T, My, Mz) at i then at j — the element's K u - f.  The
**diagrams**, ``end_forces``, ``extremes`` and the tables give internal
forces in the plane frame's convention (:mod:`.space_diagrams`; docs/frames.md,
"Conventions"): N tension positive, My and Mz positive when they compress
the +z and +y fibre, Vz = dMy/dx, Vy = dMz/dx.  A contact's
``tangential`` force and ``slip`` are given along its tangents (t1, t2) and,
as ``tangential_global`` / ``slip_global``, in global components.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from ..mechanics.analysis_results import AnalysisResult
from ..reporting import space_tables, tables
from ..reporting.notation import DIGITS
from . import space_diagrams

DOFS = ("ux", "uy", "uz", "rx", "ry", "rz")
#: a space frame's contact states: a slip has a direction in the contact's
#: plane (``slip_global``), not a sign
STATES = ("separated", "closed", "stick", "slip")


@dataclass
class SpaceSupportResult:
    """A contact's outcome: ``state`` in STATES, normal force X_n (>= 0,
    compression), friction force (X_t1, X_t2) along the contact's tangents,
    gap opening Z_n and slip (Δ_t1, Δ_t2) (user's units); ``t1``, ``t2`` the
    tangents in global components (the normal is t1 x t2)."""

    state: str
    normal: float
    tangential: np.ndarray
    opening: float
    slip: np.ndarray
    t1: np.ndarray = field(repr=False, default=None)
    t2: np.ndarray = field(repr=False, default=None)
    #: the share of the model's own friction cone the friction uses, at
    #: most 1 by construction (1 where the contact slips): on a polygon the
    #: largest facet's load max_k(-d_k·X_t) / (reach f X_n); None where the
    #: model is Coulomb's circle itself, whose share is ``|X_t| / (f X_n)``
    cone_use: float | None = None

    @property
    def tangential_global(self) -> np.ndarray:
        return self.tangential[0] * self.t1 + self.tangential[1] * self.t2

    @property
    def slip_global(self) -> np.ndarray:
        return self.slip[0] * self.t1 + self.slip[1] * self.t2


@dataclass
class SpaceFrameResult(AnalysisResult):
    """One analysed load combination of a space frame: support states and
    forces, nodal displacements (ux, uy, uz, rx, ry, rz), member end actions
    (12 per member, member axes), reactions at bilateral supports (six per
    node, global), and the checks — ``ok`` as for the plane frame's
    :class:`~.results.FrameResult`: the LCP certificate and equilibrium at
    every dof and of the whole frame, each on its own scale."""

    #: the tables of this kind of result (CombinationResults asks for them)
    table_kit = space_tables

    def diagram(self, member: str, points: int = 21):
        """(x, N, Vy, Vz, T, My, Mz) along a member at ``points`` sections, x
        from node i (member axes; the convention of docs/frames.md,
        "Conventions": N tension positive, My and Mz positive when they
        compress the +z and +y fibre, V = dM/dx; :mod:`.space_diagrams`)."""
        return space_diagrams.diagram(self.frame, self, member, points)

    def extremes(self, member: str) -> dict:
        """{"N"|"Vy"|"Vz"|"T"|"My"|"Mz"|"v"|"w": {"max": (value, x), "min":
        (value, x)}} along a member; "v" and "w" are the deflections across
        it along its local y and z (:meth:`deflection`)."""
        return space_diagrams.extremes(self.frame, self, member)

    def end_forces(self, member: str) -> dict:
        """Internal forces at the member's ends in the diagrams' convention:
        {"i": {"N": ..., "Vy": ..., ..., "Mz": ...}, "j": {...}} (a column in
        compression has N < 0 at both ends).  ``member_forces`` keeps the
        end actions, the forces the nodes exert on the member."""
        return space_diagrams.end_forces(self.frame, self, member)

    @property
    def support_reactions(self) -> dict:
        """Each contact's force on the structure in global components
        (Fx, Fy, Fz)."""
        return {k: tuple(float(v) for v in s.normal * np.cross(s.t1, s.t2)
                         + s.tangential_global) for k, s in self.supports.items()}

    @property
    def reactions_by_node(self) -> dict:
        """{node: {"total": (Fx, Fy, Fz, Mx, My, Mz), "support"|"spring"|
        "contact": ...}}: what the ground exerts on each node it holds, and
        each kind's part (global axes, full precision)."""
        return space_tables.reactions_by_node(self.frame, self)

    def rows(self, table: str, digits: int | None = DIGITS) -> list:
        """Rows (dicts) of the table "supports", "reactions", "members" or
        "displacements" (:mod:`.space_tables`), units in the headers, rounded
        as the plane frame's (``digits=None``: full precision)."""
        return tables.engineering(space_tables.rows(self.frame, self, table), self.frame, digits)

    def to_csv(self, folder, digits: int | None = DIGITS) -> list:
        """The four tables as folder/<table>.csv, each written atomically."""
        return tables.write_tables(
            folder, {t: self.rows(t, digits) for t in space_tables.TABLES}, digits)

    def to_dataframe(self, table: str = "members", digits: int | None = DIGITS):
        """The table as a pandas DataFrame (the ``tables`` extra)."""
        return tables.dataframe(self.rows(table, digits))

    def deflection(self, member: str, points: int = 21, axes: str = "member"):
        """(x, u (n, 3)): the displacement of the member's axis at
        ``points`` sections and the load positions, x from node i; in member
        axes (u, v, w) or ``axes="global"`` (ux, uy, uz).  Exact for the
        element and its loads (:func:`.space_diagrams.deflection`)."""
        return space_diagrams.deflection(self.frame, self, member, points, axes)

    def plot(self, path, *, scale: float | None = None, title: str = "",
             azimuth: float | None = None, elevation: float | None = None,
             loads: bool = True) -> str:
        """Draw the result (PNG, :mod:`.space_drawing`): the frame and its
        deformed shape (displacements x ``scale``, default the largest drawn
        as 8 % of the frame) in an orthographic view (default isometric), the
        contacts by state, the slip directions, the loads.  Seen from above
        (``elevation=90``) a frame of more than one level is drawn as a
        plan, one panel per level, x to the right and y up
        (:mod:`..reporting.space_plan`).  Raises SolverFailedError for a
        result that is not ok."""
        from ..reporting.space_drawing import plot_space_result
        from ..reporting.space_plan import levels, plot_plan

        if elevation == 90 and len(levels(self.frame)) > 1:
            if not self.ok:
                plot_space_result(self.frame, self, path)    # refuses, saying why
            return plot_plan(self.frame, self, path, scale=scale, title=title, loads=loads)
        return plot_space_result(self.frame, self, path, scale=scale, title=title,
                                 azimuth=azimuth, elevation=elevation, loads=loads)
