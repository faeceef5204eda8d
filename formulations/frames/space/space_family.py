"""A family of space frames that rest on frictional pads, for their limit
loads: tables on 3, 4 or 6 legs (a deck over steel legs, optionally with an
overhang), a skid on four short legs, a pipe rack on six pads.  Built from
the public API as an engineer would (benchmarks/frame_limits.py runs the
family; tests/formulations/frames/test_space_family.py checks its limits).

Units kN, m.  Every frame is held by its pads alone (normal +z, Coulomb
coefficient ``mu``, rigid or a spring ``stiffness`` in kN/m), so each has
a limit load: the largest load a rigid body on those pads carries is an
upper bound, by statics (the reference of the benchmark is an LP of it).

Load cases: "constant" (the weight), and per frame the variable ones named
in :data:`TABLE_CASES`, :data:`SKID_CASES`, :data:`RACK_CASES` (1 kN or
1 kN·m each, to be scaled by p).
"""

from __future__ import annotations

import numpy as np

from .space_frame import SpaceFrame

#: a steel leg (kN, m): E, A, Iy, Iz, G, J — axial stiffness E A / 0.8 m =
#: 2.5e5 kN/m, bending 3 E I / h³ = 1.2e3 kN/m at 0.8 m
LEG = dict(E=2e8, G=8e7, A=1e-3, Iy=1e-6, Iz=1e-6, J=2e-6)

#: the tables' legs in plan (m): a triangle, the issue's 2.0 x 1.2 m
#: rectangle, and that rectangle with legs at mid-length too
TABLE_LEGS = {
    3: ((0.0, 0.0), (2.0, 0.0), (1.0, 1.2)),
    4: ((0.0, 0.0), (2.0, 0.0), (2.0, 1.2), (0.0, 1.2)),
    6: ((0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 1.2), (1.0, 1.2), (0.0, 1.2)),
}

#: a table's variable load cases: a push along x at the deck's centre C and
#: at its corner top node (the one furthest along x + y), a torque about z
#: at C, and a weight at the tip of the overhang
TABLE_CASES = ("centre", "corner", "twist", "overhang")


def table(legs: int = 4, ratio: float = 1e4, *, mu: float = 0.3, h: float = 0.8,
          weight: float = 40.0, stiffness: float | None = None,
          cone: str = "circular", facets: int = 16,
          overhang: float = 0.5) -> SpaceFrame:
    """A table: ``legs`` steel legs (:data:`LEG`, :data:`TABLE_LEGS`) ``h``
    high on frictional pads, a deck of members ``ratio`` times stiffer than
    the legs (E A, E I, G J scaled: a ring along the legs' tops and spokes
    to its centre C, the legs' centroid) carrying ``weight`` at C, and an
    overhang: a node O ``overhang`` m beyond the deck's far edge (x) at
    the height of the deck, tied to the two top nodes furthest along x.
    Cases :data:`TABLE_CASES`."""
    plan = TABLE_LEGS[legs]
    fr = SpaceFrame(units=("kN", "m"), cone=cone)
    cx, cy = np.mean(plan, axis=0)
    fr.add_node("C", cx, cy, h)
    for k, (x, y) in enumerate(plan):
        fr.add_node(f"F{k}", x, y, 0.0)
        fr.add_node(f"T{k}", x, y, h)
        fr.add_member(f"F{k}", f"T{k}", **LEG, name=f"L{k}")
        fr.add_contact(f"F{k}", normal=(0, 0, 1), friction=mu, stiffness=stiffness,
                       facets=facets)
    deck = {k: v * (ratio if k in ("A", "Iy", "Iz", "J") else 1.0) for k, v in LEG.items()}
    for k in range(legs):
        fr.add_member(f"T{k}", f"T{(k + 1) % legs}", **deck, name=f"R{k}")
        fr.add_member("C", f"T{k}", **deck, name=f"S{k}")
    far = sorted(range(legs), key=lambda k: (-plan[k][0], plan[k][1]))[:2]
    xmax = max(x for x, _ in plan)
    fr.add_node("O", xmax + overhang, float(np.mean([plan[k][1] for k in far])), h)
    for k in far:
        fr.add_member(f"T{k}", "O", **deck, name=f"O{k}")
    corner = max(range(legs), key=lambda k: plan[k][0] + plan[k][1])
    fr.add_load("C", fz=-weight)
    fr.add_load("C", fx=1.0, case="centre")
    fr.add_load(f"T{corner}", fx=1.0, case="corner")
    fr.add_load("C", mz=1.0, case="twist")
    fr.add_load("O", fz=-1.0, case="overhang")
    return fr


#: a skid's variable load cases: a push along x through its centre and at
#: a corner of its frame
SKID_CASES = ("centre", "corner")


def skid(*, mu: float = 0.3, weight: float = 53.8, length: float = 3.0, width: float = 1.5,
         leg: float = 0.3, stiffness: float | None = None, cone: str = "circular",
         facets: int = 16) -> SpaceFrame:
    """A skid: a flat steel frame ``length`` x ``width`` (runners along x,
    cross members at the ends and through the middle, 10 times a leg's
    section) on four short legs ``leg`` high at its corners, standing on
    frictional pads; the equipment's ``weight`` at its centre E, pushed
    along x at E (case "centre") and at the corner top node K3 (case
    "corner").  It slides through its centre at μW; pushed at a corner it
    slides and turns."""
    fr = SpaceFrame(units=("kN", "m"), cone=cone)
    plan = ((0.0, 0.0), (length, 0.0), (length, width), (0.0, width))
    beam = {k: v * (10.0 if k in ("A", "Iy", "Iz", "J") else 1.0) for k, v in LEG.items()}
    for k, (x, y) in enumerate(plan):
        fr.add_node(f"P{k}", x, y, 0.0)
        fr.add_node(f"K{k}", x, y, leg)
        fr.add_member(f"P{k}", f"K{k}", **LEG, name=f"L{k}")
        fr.add_contact(f"P{k}", normal=(0, 0, 1), friction=mu, stiffness=stiffness,
                       facets=facets)
    fr.add_node("M0", length / 2, 0.0, leg)
    fr.add_node("M1", length / 2, width, leg)
    fr.add_node("E", length / 2, width / 2, leg)
    for a, b_ in (("K0", "M0"), ("M0", "K1"), ("K1", "K2"), ("K2", "M1"), ("M1", "K3"),
                  ("K3", "K0"), ("M0", "E"), ("E", "M1")):
        fr.add_member(a, b_, **beam, name=f"{a}{b_}")
    fr.add_load("E", fz=-weight)
    fr.add_load("E", fx=1.0, case="centre")
    fr.add_load("K3", fx=1.0, case="corner")
    return fr


#: a pipe rack's variable load case: an uplift at its corner (the pipes'
#: anchor force), with a push along y
RACK_CASES = ("uplift",)


def pipe_rack(*, mu: float = 0.4, bents: int = 3, spacing: float = 6.0, width: float = 4.0,
              height: float = 5.0, pipes: float = 6.0, stiffness: float | None = 1e6,
              cone: str = "circular", facets: int = 16) -> SpaceFrame:
    """A pipe rack: ``bents`` portal bents along x, ``spacing`` apart, each
    two steel columns ``width`` apart in y, ``height`` high, on frictional
    pads (``stiffness`` kN/m, None: rigid); a cross beam on each bent and
    longitudinal beams along both sides at the top (HE-like sections);
    the pipes, ``pipes`` kN/m down on the longitudinal beams (case
    "constant": D), and at the corner top node T00 an uplift of 1 kN with
    0.2 kN along +y (case "uplift": U)."""
    col = dict(E=2.1e8, G=8.1e7, A=1.2e-2, Iy=1.5e-4, Iz=5e-5, J=1e-6)
    beam = dict(E=2.1e8, G=8.1e7, A=8e-3, Iy=8e-5, Iz=1e-5, J=5e-7)
    fr = SpaceFrame(units=("kN", "m"), cone=cone)
    for a in range(bents):
        for b_ in range(2):
            x, y = a * spacing, b_ * width
            fr.add_node(f"P{a}{b_}", x, y, 0.0)
            fr.add_node(f"T{a}{b_}", x, y, height)
            fr.add_member(f"P{a}{b_}", f"T{a}{b_}", **col, name=f"C{a}{b_}")
            fr.add_contact(f"P{a}{b_}", normal=(0, 0, 1), friction=mu, stiffness=stiffness,
                           facets=facets)
        fr.add_member(f"T{a}0", f"T{a}1", **beam, name=f"X{a}")
    for a in range(bents - 1):
        for b_ in range(2):
            m = fr.add_member(f"T{a}{b_}", f"T{a + 1}{b_}", **beam, name=f"Y{a}{b_}")
            fr.add_distributed_load(m, wz=-pipes)
    fr.add_load("T00", fy=0.2, fz=1.0, case="uplift")
    return fr
