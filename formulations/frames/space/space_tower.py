"""Worked space frames: a reinforced-concrete tower standing on frictional
pads (the space frames' example and benchmark model).

:func:`space_tower` builds a moment frame of ``storeys`` storeys and
``bays`` x ``bays`` bays, one column line at every grid point, each column
standing on a pad.  A pad carries forces only (the column is pinned on it):
the frame is stable because its beams and columns are rigidly connected at
every floor (members are by default), and a column's foot, held by the
column alone, turns and twists with it.  The pads are its only support: a
normal contact with Coulomb friction (faceted cone), rigid or elastic.

Units kN, m.  Concrete C30/37 (E = 30 GPa, G = E/2.4, Poisson 0.2):

* columns 0.7 x 0.7 m (A = 0.49 m², I = 0.02 m⁴ both ways, J = 0.141 b⁴);
* beams 0.4 m wide, 0.7 m deep (A = 0.28 m², Iy = 0.01143 m⁴ about the
  horizontal axis — the member's local y is horizontal, the default
  reference vector being global Z — Iz = 0.00373 m⁴, J = 0.2125 h b³).

Case "D" (dead and quasi-permanent load, member loads): the floor, 7 kN/m²
(a 0.2 m slab, finishes, partitions) spread on the beams of each square
panel, a quarter of a panel's load to each of its four beams (so an inner
beam carries two panels' shares, 21 kN/m for 6 m bays, an edge beam one);
every beam's own weight below the slab, 5 kN/m; the façade, 5 kN/m on the
edge beams; the columns' own weight, 25 kN/m³ x 0.49 m², along -z.

Case "W" (nodal loads at the floors): wind of peak pressure ``wind`` (kN/m²)
blowing from the direction ``angle`` degrees from the x axis (towards +x
and +y), pressure 0.8 q on the windward façades and suction 0.5 q on the
leeward ones (both pushing the same way), each node taking its tributary
area of façade (half a storey at the roof, half a bay at the corners).  Under
the defaults every pad sticks at 1.0 D + 1.0 W; the trace of 1.0 D + p W (p
from 0) finds the windward corner pad slipping at p = 5.3 and lifting off at
7.2, the others slipping and lifting off one after another (25 changes of
the working scheme), until the tower slides away at p = 26.84 — the load the
friction polygon allows, f W over the wind's largest component along a
facet's normal (tests/formulations/frames/test_space_tower.py).
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from ..mechanics.loads import number
from .space_frame import SpaceFrame

E_CONCRETE = 30e6                       # kN/m²
G_CONCRETE = E_CONCRETE / 2.4           # Poisson's ratio 0.2
#: A, Iy, Iz, J in m² and m⁴: square column 0.7 m, beam 0.4 x 0.7 m
COLUMN = dict(A=0.49, Iy=0.7 ** 4 / 12, Iz=0.7 ** 4 / 12, J=0.141 * 0.7 ** 4)
BEAM = dict(A=0.28, Iy=0.4 * 0.7 ** 3 / 12, Iz=0.7 * 0.4 ** 3 / 12, J=0.2125 * 0.7 * 0.4 ** 3)
FLOOR, BEAM_WEIGHT, FACADE, CONCRETE = 7.0, 5.0, 5.0, 25.0    # kN/m², kN/m, kN/m, kN/m³
WINDWARD, LEEWARD = 0.8, 0.5            # pressure coefficients (suction on the leeward side)


def node(level: int, i: int, j: int) -> str:
    """The name of the node of column line (i, j) (along x, along y) at
    ``level`` (0: the pads)."""
    return f"N{level}_{i}_{j}"


def space_tower(storeys: int = 10, bays: int = 3, *, bay: float = 6.0, storey: float = 3.5,
                friction: float = 0.5, stiffness: float | None = None, facets: int = 8,
                wind: float = 1.0, angle: float = 30.0, cone: str = "circular") -> SpaceFrame:
    """A concrete moment frame on (bays + 1)² frictional pads (the module
    docstring): ``bay`` and ``storey`` in m, ``friction`` the pads' Coulomb
    coefficient, ``stiffness`` their spring in kN/m (None: rigid), ``facets``
    of their friction cones, ``wind`` the peak pressure in kN/m² from
    ``angle`` degrees.  Nodes :func:`node`; members ``C{s}_{i}_{j}`` (the
    column from level s to s + 1), ``BX{s}_{i}_{j}`` and ``BY{s}_{i}_{j}``
    (the beams at level s from line (i, j) along +x and +y)."""
    for value, what in ((storeys, "storeys"), (bays, "bays")):
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise InvalidProblemError(f"space_tower: {what} must be a positive integer; "
                                      f"got {value!r}")
    bay, storey = number(bay, "space_tower: bay"), number(storey, "space_tower: storey")
    wind, angle = number(wind, "space_tower: wind"), number(angle, "space_tower: angle")
    if not (bay > 0 and storey > 0):
        raise InvalidProblemError(f"space_tower: bay and storey must be positive; "
                                  f"got {bay!r}, {storey!r}")
    fr = SpaceFrame(units=("kN", "m"), cone=cone)
    lines = range(bays + 1)
    for s in range(storeys + 1):
        for i in lines:
            for j in lines:
                fr.add_node(node(s, i, j), bay * i, bay * j, storey * s)
    for s in range(storeys):
        for i in lines:
            for j in lines:
                c = fr.add_member(node(s, i, j), node(s + 1, i, j), E_CONCRETE, **COLUMN,
                                  G=G_CONCRETE, name=f"C{s}_{i}_{j}")
                fr.add_distributed_load(c, wz=-CONCRETE * COLUMN["A"], case="D")
    panel_share = FLOOR * bay / 4     # a quarter of a square panel's load per unit length
    for s in range(1, storeys + 1):
        for i in lines:
            for j in lines:
                for name, (di, dj), across in (("BX", (1, 0), j), ("BY", (0, 1), i)):
                    if i + di > bays or j + dj > bays:
                        continue
                    edge = across in (0, bays)
                    m = fr.add_member(node(s, i, j), node(s, i + di, j + dj), E_CONCRETE,
                                      **BEAM, G=G_CONCRETE, name=f"{name}{s}_{i}_{j}")
                    w = BEAM_WEIGHT + (panel_share + FACADE if edge else 2 * panel_share)
                    fr.add_distributed_load(m, wz=-w, case="D")
    _wind(fr, storeys, bays, bay, storey, wind, angle)
    for i in lines:
        for j in lines:
            fr.add_contact(node(0, i, j), normal=(0.0, 0.0, 1.0), friction=friction,
                           stiffness=stiffness, facets=facets)
    return fr


def _wind(fr, storeys, bays, bay, storey, q, angle) -> None:
    """Case "W": the façade pressures of the module docstring, as nodal
    loads at the floors (levels 1 to storeys)."""
    a = np.radians(angle)
    qx, qy = q * np.cos(a), q * np.sin(a)
    # the windward face is the one the wind meets first: x = 0 for qx > 0
    faces = ((0, bays) if qx >= 0 else (bays, 0), (0, bays) if qy >= 0 else (bays, 0))
    for s in range(1, storeys + 1):
        height = storey * (0.5 if s == storeys else 1.0)
        for k in range(bays + 1):
            width = bay * (0.5 if k in (0, bays) else 1.0)
            area = width * height
            windward, leeward = faces[0]
            fr.add_load(node(s, windward, k), fx=WINDWARD * qx * area, case="W")
            fr.add_load(node(s, leeward, k), fx=LEEWARD * qx * area, case="W")
            windward, leeward = faces[1]
            fr.add_load(node(s, k, windward), fy=WINDWARD * qy * area, case="W")
            fr.add_load(node(s, k, leeward), fy=LEEWARD * qy * area, case="W")
