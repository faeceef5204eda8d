"""Results of a space-frame analysis: one object per load combination, in
the plane frame's form (:mod:`.results`) with six dofs per node and contact
forces and slips as vectors in the contact's tangent plane.

Sign conventions: global axes x, y, z right-handed, rotations
counterclockwise about each axis (right-hand rule).  ``member_forces`` are
**end actions** in member axes (x from node i to j, y and z the section's
principal axes): the forces and moments the nodes exert on the member,
(N, Vy, Vz, T, My, Mz) at i then at j — the element's K u - f.  A contact's
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

DOFS = ("ux", "uy", "uz", "rx", "ry", "rz")
#: a space frame's contact states: a slip has a direction in the contact's
#: plane (``slip_global``), not a sign
STATES = ("separated", "closed", "stick", "slip")
#: the names of a member's end actions, at i then j (member axes)
END_ACTIONS = ("N", "Vy", "Vz", "T", "My", "Mz")


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

    def end_forces(self, member: str) -> dict:
        """The member's end actions by name: {"i": {"N": ..., ...}, "j": {...}}
        (member axes, the forces the nodes exert on the member)."""
        if member not in self.member_forces:
            raise InvalidProblemError(f"no member named {member!r}; members: "
                                      f"{list(self.member_forces)}")
        f = self.member_forces[member]
        return {"i": dict(zip(END_ACTIONS, map(float, f[:6]))),
                "j": dict(zip(END_ACTIONS, map(float, f[6:])))}

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
        """(x, u (points, 3)): the displacement of the member's axis at
        ``points`` sections, x from node i; in member axes (u, v, w) or
        ``axes="global"`` (ux, uy, uz).  Exact for the element's uniform
        loads (:func:`.space_drawing.member_deflection`)."""
        from ..reporting.space_drawing import member_deflection

        return member_deflection(self.frame, self, member, points, axes)

    def plot(self, path, scale: float | None = None, title: str | None = None, *,
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
