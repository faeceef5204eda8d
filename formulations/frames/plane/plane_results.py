"""A plane frame's result for one load combination (:class:`FrameResult`,
its contacts' :class:`SupportResult`): diagrams, deflections, extremes and
tables along its members (:mod:`.member_diagrams`, :mod:`..reporting.tables`).

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

from dataclasses import dataclass

import numpy as np

from ..mechanics.analysis_results import AnalysisResult
from ..mechanics.loads import stationary_points, turning_points, turning_sections
from ..reporting import tables
from ..reporting.notation import DIGITS
from ..reporting.tables import TABLES
from . import member_diagrams


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
class FrameResult(AnalysisResult):
    """One analysed load combination: support states and forces, nodal
    displacements (ux, uy, rz), member end actions, reactions, and the checks.

    ``combination`` is {case: factor} (``p`` the factor of "variable" for the
    split constant + p x variable).  ``ok`` is True only when the LCP certificate meets the
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
        return member_diagrams.diagram(self.frame, self, member, points)

    def deflection(self, member: str, points: int = 21, axes: str = "member"):
        """(x, dx, dy): the displacement of the member's axis at ``points``
        sections (plus the load positions), x from node i.  ``axes="member"``:
        along and across the member (u, v); ``"global"``: (ux, uy).  Exact
        for the element's loads (integrated from N/EA and M/EI, not
        interpolated between the nodes)."""
        x, u, v = member_diagrams.deflection(self.frame, self, member, points)
        if axes == "member":
            return x, u, v
        if axes != "global":
            from qpcontact.core.errors import InvalidOptionError

            raise InvalidOptionError(f"axes: 'member' or 'global'; got {axes!r}")
        c, s = member_diagrams.direction(self.frame, member)
        return x, c * u - s * v, s * u + c * v

    def extremes(self, member: str) -> dict:
        """{"N"|"V"|"M"|"v": {"max": (value, x), "min": (value, x)}} along a
        member; "v" is the deflection across its axis (member axes,
        :meth:`deflection`).  N, V and v are taken at 201 sections and the
        load positions, N and V also where they turn between them (a
        trapezoidal load that changes sign: :func:`..mechanics.loads.turning_points`),
        M also at the zeros of V between them, where a span moment is
        largest, so the extremes of N, V and M are exact."""
        x, N, V, M = self.diagram(member, 201)
        m = self.frame.members[member]
        at = {"N": x, "V": x}
        bent = member_diagrams.beam_column_axis(self.frame, self, m, x[:1]) is not None
        for key, k in (("N", 0), ("V", 1)):
            x_t = (turning_sections(x, V, lambda s: member_diagrams.sections(
                self.frame, self, m, s)[1]) if bent and key == "V"
                else turning_points(x, (N, V)[k]))
            if x_t.size:
                at[key] = np.r_[x, x_t]
                turned = member_diagrams.sections(self.frame, self, m, x_t)[k]
                N, V = (np.r_[N, turned], V) if k == 0 else (N, np.r_[V, turned])
        # the span moments between the samples, where V = dM/dx changes sign
        x_m = stationary_points(x, V[:x.size], lambda s: member_diagrams.sections(
            self.frame, self, m, s)[1])
        if x_m.size:
            M = np.r_[M, member_diagrams.sections(self.frame, self, m, x_m)[2]]
            x_all = np.r_[x, x_m]
        else:
            x_all = x
        xv, _, v = self.deflection(member, 201)
        out = {}
        for key, xs, arr in (("N", at["N"], N), ("V", at["V"], V), ("M", x_all, M),
                             ("v", xv, v)):
            out[key] = {"max": (float(arr.max()), float(xs[arr.argmax()])),
                        "min": (float(arr.min()), float(xs[arr.argmin()]))}
        return out

    def end_forces(self, member: str) -> dict:
        """Internal forces at the member's ends in the diagrams' convention:
        {"i": {"N": ..., "V": ..., "M": ...}, "j": {...}} (a space frame's
        has its six quantities under the same keys' scheme)."""
        x, *qs = self.diagram(member, 2)
        return {end: {q: float(v[k]) + 0.0 for q, v in zip(("N", "V", "M"), qs)}
                for end, k in (("i", 0), ("j", -1))}

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
        from ..reporting.plane_drawing import plot_result

        return plot_result(self.frame, self, path, diagrams, scale, title, loads, reactions)
