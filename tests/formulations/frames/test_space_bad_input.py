"""Bad input to a space frame is refused with an
InvalidProblemError that names what is wrong: the contact's normal, its
facets, friction, stiffness, unknown nodes, dofs, members and load cases,
a contact whose normal a bilateral support already fixes, and a frame that
is a mechanism even with every contact closed — named by its motion (a
moment about a column's axis that nothing resists: a turn about the axis
through its foot; a beam free to roll about its own axis)."""

from __future__ import annotations

import numpy as np
import pytest

from formulations.frames import SpaceFrame
from qpcontact.core.errors import InvalidProblemError

E, G = 2.1e8, 8.1e7           # kN/m²


def _beam():
    fr = SpaceFrame()
    for name, xyz in (("A", (0.0, 0.0, 0.0)), ("B", (4.0, 0.0, 0.0)), ("C", (4.0, 0.0, 3.0))):
        fr.add_node(name, *xyz)
    fr.add_member("A", "B", E, 0.01, 1e-4, 1e-4, G=G, J=2e-4, name="M1")
    fr.add_member("B", "C", E, 0.01, 1e-4, 1e-4, G=G, J=2e-4, name="M2")
    return fr


def _column_twisted():
    """A column standing on a frictional pad, its top held sideways, a
    moment about its axis: nothing resists that rotation."""
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 0.0, 0.0, 3.0)
    fr.add_member("A", "B", E, 0.01, 1e-4, 1e-4, G=G, J=2e-4)
    fr.add_contact("A", friction=0.5)
    fr.add_support("B", fix=("ux", "uy"))
    fr.add_load("B", fz=-10.0, mz=2.0)
    return fr.solve()


def _post_on_a_pad():
    """A single node on a contact, held but for uz and rz: a moment about z."""
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_support("A", fix=("ux", "uy", "rx", "ry"))
    fr.add_contact("A")
    fr.add_load("A", fz=-1.0, mz=1.0)
    return fr.solve()


def _normal_held():
    fr = _beam()
    fr.add_support("A", fix=("uz",))
    fr.add_contact("A")
    fr.add_support("B")
    return fr.solve()


def _rolls_on_two_pads():
    """A beam on two frictionless pads held along x and y: free to roll about
    its axis (B and C turn, C at 3 m swings along y)."""
    fr = _beam()
    fr.add_contact("A")
    fr.add_contact("B")
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_support("B", fix=("uy",))
    fr.add_load("B", fz=-1.0, mx=1.0)
    return fr.solve()


def _twice_the_same_contact():
    fr = _beam()
    fr.add_support("A")
    fr.add_contact("C")
    fr.add_contact("C")
    return fr.solve()


def _frictional():
    fr = _beam()
    fr.add_support("A", fix=("ux", "uy", "rx", "ry", "rz"))
    fr.add_contact("A", friction=0.3)
    fr.add_load("C", fx=1.0)
    return fr


BAD = [
    (lambda: _beam().add_contact("A", normal=(0.0, 0.0, 0.0)), "normal must be a nonzero 3-vector"),
    (lambda: _beam().add_contact("A", normal=(0.0, 1.0)), "normal must be a nonzero 3-vector"),
    (lambda: _beam().add_contact("A", normal="up"), "normal must be a nonzero 3-vector"),
    (lambda: _beam().add_contact("A", normal=(0.0, np.nan, 1.0)), "nonzero 3-vector"),
    (lambda: _beam().add_contact("A", facets=7), "facets must be an even integer >= 4.*got 7"),
    (lambda: _beam().add_contact("A", facets=2), "facets must be an even integer >= 4"),
    (lambda: _beam().add_contact("A", friction=-0.1), "contact at 'A': friction and gap"),
    (lambda: _beam().add_contact("A", stiffness=0.0), "stiffness must be > 0 or None"),
    (lambda: _beam().add_contact("Z"), "no node named 'Z'"),
    (lambda: _beam().add_support("A", fix=("ux", "uw")), r"fix must name dofs among.*\['uw'\]"),
    (lambda: _beam().add_spring("A", uw=1.0), r"spring at 'A'.*\['uw'\]"),
    (lambda: _beam().add_distributed_load("M9", wz=1.0), "no member named 'M9'"),
    (lambda: _beam().add_load("A", fx=np.inf), "load at 'A': fx must be finite"),
    (lambda: _beam().add_member("A", "C", -E, 0.01, 1e-4, 1e-4, G=G, J=2e-4),
     "member A-C: E must be positive"),
    (lambda: _beam().add_member("A", "C", E, 0.01, 1e-4, 1e-4, G=G, J=2e-4, name="S",
                                spring_i={"ry": 1e155}),
     r"member 'S': spring_i: ry must be in \[0, 1e\+100\].*leave it out\); got 1e\+155"),
    (lambda: _beam().add_member("B", "A", E, 0.01, 1e-4, 1e-4, G=G, J=2e-4, name="M1"),
     "member 'M1' exists already"),
    (lambda: (lambda fr: (fr.add_node("A2", 0.0, 0.0, 0.0),
                          fr.add_member("A", "A2", E, 0.01, 1e-4, 1e-4, G=G, J=2e-4)))(_beam()),
     "member A-A2: nodes A and A2 coincide"),
    (lambda: _beam().add_member("A", "C", E, 0.01, 1e-4, 1e-4, G=G, J=2e-4, name="X",
                                ref=(4.0, 0.0, 3.0)),
     r"member 'X': its reference vector \(4.0, 0.0, 3.0\) is parallel to the member"),
    (_normal_held, "node 'A': the contact's normal direction is already fixed by its "
                   "bilateral support"),
    (_column_twisted, r"mechanism even with every contact closed: it turns rigidly about the "
                      r"axis through node [AB] along z .*fix rz at"),
    (_post_on_a_pad, r"mechanism even with every contact closed: it turns rigidly about the "
                     r"axis through node A along z"),
    (_rolls_on_two_pads, r"mechanism even with every contact closed: it turns rigidly about the "
                         r"axis through node [AB] along x"),
    (_twice_the_same_contact, r"contact at 'C': the node has contact 0 with the same normal "
                              r"\(0.0, 0.0, 1.0\) already"),
    (lambda: _beam().solve(), "mechanism on its supports and springs .*it is free as a "
                                     "rigid body"),
    (lambda: _frictional().solve(combination={"wind": 1.0}),
     "names the load case 'wind', which has no loads"),
    (lambda: _frictional().trace(variable="wind"), "names the load case 'wind'"),
    (lambda: _frictional().solve(p=np.nan), "p must be finite"),
    (lambda: _frictional().solve_combinations({}), "combinations: a non-empty dict"),
    (lambda: _frictional().solve().end_forces("M9"), "no member named 'M9'"),
    # a second member between the same nodes, by its name or by its node pair
    (lambda: _beam().add_member("A", "C", E, 0.01, 1e-4, 1e-4, G=G, J=2e-4, name="M1"),
     "member 'M1' exists already; give another name"),
    (lambda: _beam().add_member("B", "A", E, 0.01, 1e-4, 1e-4, G=G, J=2e-4, name="M3"),
     "member 'M3': nodes 'B' and 'A' are joined already by member 'M1'.*combined section"),
    (lambda: SpaceFrame(units=("kN",)), r"units must be \(force, length\) names.*\('kN',\)"),
    (lambda: SpaceFrame(units=("m", "kN")),
     r"units are \(force, length\), in that order; got \('m', 'kN'\).*write \('kN', 'm'\)"),
]


@pytest.mark.parametrize("make, words", BAD, ids=[w[:40] for _, w in BAD])
def test_bad_input_in_space_is_refused_with_what_is_wrong(make, words):
    with pytest.raises(InvalidProblemError, match=words):
        make()


def test_contacts_at_one_node_in_other_directions_are_separate_contacts():
    """Only a second contact with the same normal is refused: a node in a
    corner (two normals) or between two walls (opposite normals) has two."""
    fr = _beam()
    assert fr.add_contact("C", normal=(0.0, 0.0, 1.0)) == 0
    assert fr.add_contact("C", normal=(1.0, 0.0, 0.0)) == 1
    assert fr.add_contact("C", normal=(0.0, 0.0, -1.0), gap=0.01) == 2
    with pytest.raises(InvalidProblemError, match="contact at 'C': the node has contact 1"):
        fr.add_contact("C", normal=(2.0, 0.0, 0.0), friction=0.3)
