"""Worked space frames: a pad pushed obliquely (Coulomb's circular cone by
hand), a one-storey frame on six pads where every contact state occurs
(examples/space_frame_on_pads.py, tests/formulations/frames/test_space_results.py), and a
one-storey frame of bays on frictional pads, the instance that
``qpcontact compare`` runs on the circular cone (an FCLIB global problem)."""

from __future__ import annotations

import numpy as np

from .space_frame import SpaceFrame

#: the steel sections of the examples (kN, m): add_member's keywords
COLUMN = dict(E=2.1e8, A=1.5e-2, Iy=1.2e-4, Iz=1.2e-4, G=8.1e7, J=2.0e-6)
BEAM = dict(E=2.1e8, A=1.0e-2, Iy=2.3e-4, Iz=1.6e-5, G=8.1e7, J=1.0e-6)


def pad_example(push: float, angle: float, *, weight: float = 100.0, friction: float = 0.4,
                spring: float = 1e4, stiffness: float | None = None,
                facets: int = 8, cone: str = "circular") -> SpaceFrame:
    """A stiff post P-Q standing on a frictional pad at P (normal +z), its
    rotations at P held, a horizontal spring ``spring`` on ux and uy at P,
    ``weight`` down and ``push`` horizontal at Q along ``angle`` (radians)
    from the pad's first tangent t1 towards t2.  By hand, with the circular
    cone: the pad carries the weight; it sticks while the push is within
    f W (1 + spring/stiffness) (the pad's own spring shares the push), its
    friction −push/(1 + spring/stiffness) along the push; beyond, it slips
    along the push, friction f W against it, the post's foot moving
    (push − f W)/spring."""
    fr = SpaceFrame(cone=cone)
    fr.add_node("P", 0.0, 0.0, 0.0)
    fr.add_node("Q", 0.0, 0.0, 1.0)
    fr.add_member("P", "Q", **COLUMN)
    fr.add_support("P", fix=("rx", "ry", "rz"))
    fr.add_spring("P", ux=spring, uy=spring)
    c = fr.contacts[fr.add_contact("P", friction=friction, stiffness=stiffness, facets=facets)]
    d = np.cos(angle) * c.t1 + np.sin(angle) * c.t2
    fr.add_load("Q", *(push * d[:2]), fz=-weight)
    return fr


def six_pads(*, friction: float = 0.4, spring: float = 5e3, facets: int = 16,
             cone: str = "circular") -> SpaceFrame:
    """One storey, 2 x 1 bays (8 m x 5 m, 3.5 m high; kN, m), steel columns
    P-T on six frictional pads (``friction``, pinned: a pad carries no
    moment), beams along x carrying 10 kN/m (case "D"), 5 kN down at T00 and
    40 kN at T21 (D), a push of (20, 20, 0) kN at T20 (case "W") and 20 kN
    uplift at T00 (case "U"); P10 also has a horizontal ``spring`` [kN/m] in
    x, P21 a guide in y, and a frictionless bumper with a 0.1 mm gap stops
    T21 moving in +x.  Under D+W+U the uplift lifts P00, the push slides P01
    and P20 and the bumper closes: every contact state at once."""
    E, G = 2.1e8, 8.1e7                     # steel, kN/m²
    fr = SpaceFrame(units=("kN", "m"), cone=cone)
    for a, x in enumerate((0.0, 4.0, 8.0)):
        for b, y in enumerate((0.0, 5.0)):
            fr.add_node(f"P{a}{b}", x, y, 0.0)
            fr.add_node(f"T{a}{b}", x, y, 3.5)
            fr.add_member(f"P{a}{b}", f"T{a}{b}", E, 0.01, 8e-5, 8e-5, G=G, J=1e-5, name=f"C{a}{b}")
            fr.add_contact(f"P{a}{b}", friction=friction, facets=facets)
    for b in range(2):
        for a in range(2):
            fr.add_member(f"T{a}{b}", f"T{a + 1}{b}", E, 0.01, 2e-4, 1e-4, G=G, J=2e-5,
                          name=f"Bx{a}{b}")
            fr.add_distributed_load(f"Bx{a}{b}", wz=-10.0, case="D")
    for a in range(3):
        fr.add_member(f"T{a}0", f"T{a}1", E, 0.01, 2e-4, 1e-4, G=G, J=2e-5, name=f"By{a}")
    fr.add_load("T00", fz=-5.0, case="D")
    fr.add_load("T21", fz=-40.0, case="D")
    fr.add_load("T20", fx=20.0, fy=20.0, case="W")
    fr.add_load("T00", fz=20.0, case="U")
    fr.add_contact("T21", normal=(-1.0, 0.0, 0.0), gap=1e-4)
    fr.add_spring("P10", ux=spring)
    fr.add_support("P21", fix=("uy",))
    return fr


def bays_on_pads(bays: int = 2, *, span: float = 5.0, height: float = 3.5,
                 friction: float = 0.5, gravity: float = 20.0, lateral=(8.0, 5.0),
                 stiffness: float | None = None, facets: int = 8,
                 pinned_corners: bool = False, cone: str = "circular") -> SpaceFrame:
    """A one-storey space frame of ``bays`` x ``bays`` bays (``span`` each
    way, columns ``height``), every column's foot on a frictional pad
    (normal +z, free rotations: a point contact), ``gravity`` kN/m down on
    every beam (case "constant") and ``lateral`` = (fx, fy) kN at every top
    node (case "variable").  Nothing holds it but its pads: without them it
    is a mechanism, so its friction problem is global and unreduced.  With
    ``pinned_corners`` the four corner columns are pinned to the ground
    instead (translations held, rotations free) and the others stand on
    pads: then W = Hᵀ K⁻¹ H exists and the problem is reduced too."""
    fr = SpaceFrame(cone=cone)
    n = bays + 1
    for i in range(n):
        for j in range(n):
            base, top = f"B{i}{j}", f"T{i}{j}"
            fr.add_node(base, i * span, j * span, 0.0)
            fr.add_node(top, i * span, j * span, height)
            fr.add_member(base, top, **COLUMN, name=f"C{i}{j}")
            if pinned_corners and i in (0, bays) and j in (0, bays):
                fr.add_support(base, fix=("ux", "uy", "uz"))
            else:
                fr.add_contact(base, friction=friction, stiffness=stiffness, facets=facets)
            fr.add_load(top, fx=lateral[0], fy=lateral[1], case="variable")
    for i in range(n):
        for j in range(n):
            for di, dj, axis in ((1, 0, "x"), (0, 1, "y")):
                if i + di < n and j + dj < n:
                    m = fr.add_member(f"T{i}{j}", f"T{i + di}{j + dj}", **BEAM,
                                      name=f"{axis}{i}{j}")
                    fr.add_distributed_load(m, wz=-gravity)
    return fr


#: the instances' lateral loads: on pads alone, p = 5 of (8, 5) kN per top
#: node (three pads slip, six stick); with the corners pinned, p = 2 of
#: (40, 25) kN (four pads slip, one sticks)
INSTANCES = {"pads": (5.0, (8.0, 5.0)), "pinned": (2.0, (40.0, 25.0))}


def space_instances(size: str = "small", hardness: str = "easy", seed: int = 0) -> list:
    """The circular-cone problems of :func:`bays_on_pads` (2, 4 or 8 bays
    each way for size small/medium/large) for ``qpcontact compare``
    ("hard" only: frictional, 3-D), both FCLIB global problems: on pads
    alone (a mechanism without them: unreduced, for the methods that keep
    the displacements) and with the corners pinned (reduced as well, for
    every friction method); named ``frames/space-2x2-bays-on-9-pads`` and
    ``frames/space-2x2-bays-pinned-on-5-pads``.  ``seed`` is not used: the
    frames are the same every time."""
    from qpcontact.cases.instance import Instance

    if hardness != "hard":
        return []
    bays = {"small": 2, "medium": 4, "large": 8}[size]
    out = []
    for kind, (p, lateral) in INSTANCES.items():
        pinned = kind == "pinned"
        fr = bays_on_pads(bays, lateral=lateral, pinned_corners=pinned)
        pads = len(fr.contacts)
        name = f"space-{bays}x{bays}-bays-" + ("pinned-" if pinned else "") + f"on-{pads}-pads"
        out.append(Instance(f"frames/{name}", "frames", f"space-{pads}-pads",
                            fr.friction_problem(p)))
    return out
