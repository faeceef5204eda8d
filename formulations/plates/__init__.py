r"""Rafts and slabs on tensionless soil: MITC4 plates (:mod:`.element`) on
structured or user-given quadrilateral meshes (:mod:`.mesh`), resting on
Winkler soil that only pushes or on a rigid floor, under load cases and
combinations (:class:`Raft`, :mod:`.model`); each combination's contact is
one convex QP with lower bounds (:mod:`.contact`), solved by Newton's method
on the energy (:mod:`.newton`) or through ``qpcontact.solve``, and certified
from its data; results, tables and envelopes in :mod:`.results`.

Units are the user's (consistent); z and w point down, loads are positive
downward, soil pressure positive when it pushes, moments positive when they
stretch the bottom face.  See docs/plates.md.
"""

from .element import DOFS, rigidity
from .examples import demo
from .mesh import PlateMesh, grid, grid_lines
from .model import Raft
from .results import RaftCombinations, RaftResult
from .statics import NoEquilibriumError

__all__ = ["Raft", "RaftResult", "RaftCombinations", "PlateMesh", "grid", "grid_lines",
           "NoEquilibriumError", "DOFS", "rigidity", "demo"]
