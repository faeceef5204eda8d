"""The moment diagram of a shear-flexible member of a second-order answer
whose member loads act only along it (a leaning column under its own
weight in a sway frame): it bends only by its ends' sway, so its moment
is Engesser's from its end forces' statics — 0 at its hinges.  Reference:
hand statics (a column hinged at both ends carries no moment at them) and
its Euler–Bernoulli twin (the same column without a shear area, whose
diagram takes N(x))."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from formulations.frames import Frame
from formulations.frames.space.space_frame import SpaceFrame

E, G = 210e9, 81e9


def _plane(shear: bool) -> Frame:
    """Left column fixed (HEB 300, 4 m), a stiff beam 6 m, the right column
    hinged at both ends under its weight 5 N/m (a member load along it) and
    200 kN on top; 20 kN sideways at B."""
    fr = Frame()
    for n, x, y in (("A", 0, 0), ("B", 0, 4), ("C", 6, 4), ("D", 6, 0)):
        fr.add_node(n, x, y)
    fr.add_member("A", "B", E, 1.49e-2, 2.517e-4, name="left")
    fr.add_member("B", "C", E, 1e-1, 1e-2, name="beam")
    kw = dict(G=G, shear_area=1e4) if shear else {}
    fr.add_member("D", "C", E, 1e-2, 1e-5, name="lean", hinge_i=True, hinge_j=True, **kw)
    fr.add_distributed_load("lean", wy=-5.0, case="D")
    fr.add_support("A")
    fr.add_support("D", ("ux", "uy"))
    fr.add_load("C", fy=-200e3, case="D")
    fr.add_load("B", fx=20e3, case="D")
    return fr


def _space(shear: bool) -> SpaceFrame:
    """The same portal in the x-z plane (out-of-plane motion held), the right
    column hinged at its top and pinned at its base."""
    sf = SpaceFrame()
    for n, x, z in (("A", 0, 0), ("B", 0, 4), ("C", 6, 4), ("D", 6, 0)):
        sf.add_node(n, x, 0, z)
    sf.add_member("A", "B", E, 1.49e-2, 2.517e-4, 2.517e-4, G=G, J=1e-6, name="left")
    sf.add_member("B", "C", E, 1e-1, 1e-2, 1e-2, G=G, J=1e-4, name="beam")
    kw = dict(shear_area=(1e4, 1e4)) if shear else {}
    sf.add_member("D", "C", E, 1e-2, 1e-5, 1e-5, G=G, J=1e-6, name="lean", hinge_j=True, **kw)
    sf.add_distributed_load("lean", wz=-5.0, case="D")
    sf.add_support("A")
    sf.add_support("D", ("ux", "uy", "uz", "rz"))
    sf.add_support("B", ("uy",))
    sf.add_support("C", ("uy",))
    sf.add_load("C", fz=-3e5, case="D")
    sf.add_load("B", fx=20e3, case="D")
    return sf


def _moments(fr, space):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve(combination={"D": 1.0}, second_order=True, accuracy="low",
                       raise_on_failure=False)
    d = res.diagram("lean", 3)
    if space:
        return res, np.abs(np.asarray(d[-3:], float)).max(axis=0)     # |M| over its components
    return res, np.abs(np.asarray(d[3], float))


@pytest.mark.parametrize("space", [False, True])
def test_a_shear_flexible_leaning_column_has_no_moment_at_its_hinges(space):
    """Before: its diagram kept the P-Δ end shear and dropped N̄ (v − v(0)),
    −462 N m (plane) and 707 N m (space) at the top hinge, the answer ok
    at "low"."""
    build = _space if space else _plane
    res, M = _moments(build(True), space)
    twin, M_eb = _moments(build(False), space)
    scale = 4e4         # the fixed column's base moment, N m (20 kN × 4 m, amplified)
    assert twin.ok, twin.message
    assert M[-1] <= 1e-9 * scale, M
    assert M == pytest.approx(M_eb, abs=1e-6 * scale)
