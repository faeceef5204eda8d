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

    @property
    def tangential_global(self) -> np.ndarray:
        return self.tangential[0] * self.t1 + self.tangential[1] * self.t2

    @property
    def slip_global(self) -> np.ndarray:
        return self.slip[0] * self.t1 + self.slip[1] * self.t2


@dataclass
class SpaceFrameResult:
    """One analysed load combination of a space frame: support states and
    forces, nodal displacements (ux, uy, uz, rx, ry, rz), member end actions
    (12 per member, member axes), reactions at bilateral supports (six per
    node, global), and the checks — ``ok`` as for the plane frame's
    :class:`~.results.FrameResult`: the LCP certificate and equilibrium at
    every dof and of the whole frame, each on its own scale."""

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
    displacement_ratio: float = 0.0
    max_rotation: float = 0.0

    def end_forces(self, member: str) -> dict:
        """The member's end actions by name: {"i": {"N": ..., ...}, "j": {...}}
        (member axes, the forces the nodes exert on the member)."""
        if member not in self.member_forces:
            raise InvalidProblemError(f"no member named {member!r}; members: "
                                      f"{list(self.member_forces)}")
        f = self.member_forces[member]
        return {"i": dict(zip(END_ACTIONS, map(float, f[:6]))),
                "j": dict(zip(END_ACTIONS, map(float, f[6:])))}

    def support_reactions(self) -> dict:
        """Each contact's force on the structure in global components
        (Fx, Fy, Fz)."""
        return {k: tuple(float(v) for v in s.normal * np.cross(s.t1, s.t2)
                         + s.tangential_global) for k, s in self.supports.items()}
