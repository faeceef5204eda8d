"""An answer keeps the frame it solved: members' diagrams, extremes, tables
and a trace's later states read the model again, and an edit after the solve
(a load, a member, a contact, the cone) must not reach them.  The reference
for each is the same frame built afresh and solved (an independent solve,
not the answer under test)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from formulations.frames import Frame, SpaceFrame
from formulations.frames.space.space_family import table


def _beam():
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 6.0, 0.0)
    fr.add_node("C", 12.0, 0.0)
    fr.add_member("A", "B", 2e8, 0.01, 1e-4, name="M1")
    fr.add_member("B", "C", 2e8, 0.01, 1e-4, name="M2")
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_contact("B")
    fr.add_contact("C")
    fr.add_distributed_load("M1", wy=-10.0, case="D")
    fr.add_load("C", fy=-5.0, case="W")
    return fr


def _readings(res, members):
    out = []
    for m in members:
        d = res.diagram(m, 9)
        out.append(np.concatenate([np.ravel(v) for v in (d.values() if isinstance(d, dict)
                                                          else d)]))
    return np.concatenate(out)


@pytest.mark.parametrize("edit", [
    lambda fr: fr.add_distributed_load("M1", wy=-50.0, case="D"),
    lambda fr: fr.add_point_load("M2", 3.0, fy=-40.0, case="D"),
    lambda fr: (fr.add_node("D", 18.0, 0.0), fr.add_member("C", "D", 2e8, 0.01, 1e-4),
                fr.add_contact("D")),
    lambda fr: fr.add_self_weight("D", unit_weight=78.5),
])
def test_a_plane_answer_reads_the_frame_it_solved(edit):
    fr = _beam()
    res = fr.solve(combination={"D": 1.0})
    assert res.ok
    reference = _beam().solve(combination={"D": 1.0})
    edit(fr)
    # the simply supported span under 10 kN/m by hand: M = wL²/8 = 45 kN·m at midspan
    assert res.extremes("M1")["M"]["max"][0] == pytest.approx(45.0, rel=1e-12)
    np.testing.assert_array_equal(_readings(res, ["M1", "M2"]),
                                  _readings(reference, ["M1", "M2"]))
    assert res.rows("members") == reference.rows("members")
    again = fr.solve(combination={"D": 1.0})           # the edit itself took
    assert not np.array_equal(_readings(again, ["M1", "M2"]), _readings(res, ["M1", "M2"]))


def test_a_trace_reads_the_frame_it_traced():
    fr = _beam()
    tr = fr.trace(2.0, constant={"D": 1.0}, variable={"W": 1.0})
    before = _readings(tr.result_at(1.5), ["M1", "M2"])
    fr.add_distributed_load("M2", wy=-20.0, case="W")
    after = _readings(tr.result_at(1.5), ["M1", "M2"])
    np.testing.assert_array_equal(before, after)
    fresh = _beam().trace(2.0, constant={"D": 1.0}, variable={"W": 1.0})
    np.testing.assert_array_equal(after, _readings(fresh.result_at(1.5), ["M1", "M2"]))


def test_a_space_answer_reads_the_frame_it_solved():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fr = table()
        res = fr.solve()
        reference = table().solve()
        assert res.ok and reference.ok
        member = next(iter(fr.members))
        fr.add_distributed_load(member, wz=-30.0)
        fr.cone = "inscribed"
        np.testing.assert_array_equal(_readings(res, [member]), _readings(reference, [member]))
        assert res.rows("members") == reference.rows("members")
        assert isinstance(res.frame, SpaceFrame) and res.frame.cone == "circular"


def test_a_solved_frame_and_its_answers_still_pickle_and_copy():
    # the answers' register (weak references) is no part of the model: a
    # frame or an answer sent to another process (pickle) or copied must
    # travel without it, and the copy keeps its own frame as solved
    import copy
    import pickle

    fr = _beam()
    res = fr.solve(combination={"D": 1.0})
    fr.trace(2.0, constant={"D": 1.0}, variable={"W": 1.0})   # more answers registered
    for obj in (fr, res):
        pickle.loads(pickle.dumps(obj))
    sent = pickle.loads(pickle.dumps(res))
    np.testing.assert_array_equal(_readings(sent, ["M1", "M2"]), _readings(res, ["M1", "M2"]))
    twin = copy.deepcopy(res)
    before = _readings(twin, ["M1", "M2"])
    twin.frame.add_distributed_load("M1", wy=-50.0, case="D")
    np.testing.assert_array_equal(_readings(twin, ["M1", "M2"]), before)


@pytest.mark.parametrize("second_order", [False, True])
def test_a_trace_pickles_and_reads_the_same_after(second_order):
    """A trace keeps its assembly for ``result_at``, and with it SciPy's
    SuperLU, which does not pickle: a trace sent to another process
    (multiprocessing over load cases) raised TypeError.  Sent, it must give
    the same states and answers between its breakpoints, bit for bit (the
    reference: the trace that was not sent)."""
    import pickle

    fr = _beam()
    tr = fr.trace(2.0, constant={"D": 1.0}, variable={"W": 1.0}, second_order=second_order)
    sent = pickle.loads(pickle.dumps(tr))
    assert type(sent) is type(tr) and sent.ended == tr.ended
    np.testing.assert_array_equal(sent.breakpoints, tr.breakpoints)
    for p in (0.3, 1.5, 2.0):
        a, b = sent.result_at(p), tr.result_at(p)
        assert a.ok == b.ok
        np.testing.assert_array_equal(_readings(a, ["M1", "M2"]), _readings(b, ["M1", "M2"]))
