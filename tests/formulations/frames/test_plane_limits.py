"""Frames near their limits, each against an independent reference.

- A 3-bay, 20-storey frame on a foundation beam resting on elastic frictional
  supports tips over at its moment balance about the toe (hand statics); every
  load below it has an equilibrium, which solve() must find (Lemke alone ended
  on unproved secondary rays at 12 of 61 loads in [0.5, 1) x the tipping load).
- A continuous beam on 51 (201) rigid unilateral supports under its weight and
  midspan point loads p x 250 kN: the supports can carry any p, so the trace
  runs on unbounded (it broke down at p = 83.3 (11.7) on a fixed-scale
  equilibrium check), and every state agrees with an independent NumPy beam
  code given the same closed supports (its reactions >= 0, openings >= 0).
- The Tresca fixed point on a ground beam whose P'RP has a rounding-level
  negative eigenvalue (-4.4e-12) agrees with Lemke.
- Clear errors for a frame whose loads are all in named cases, and for
  diagram's arguments.
"""

from __future__ import annotations

import numpy as np
import pytest

from formulations.frames import Frame
from qpcontact.core.errors import InvalidOptionError, InvalidProblemError, NoSolutionError

from .frame_cases import beam_on_supports, three_bay_tower

# near their limits these frames sway beyond small-displacement theory on
# purpose; the warning that says so is tested in tests/formulations/frames/test_plane_features.py
pytestmark = pytest.mark.filterwarnings(
    "ignore::formulations.frames.LargeDisplacementWarning")


# moments about the toe (x = 21): the weight 20 x 3 x 6 m x 30 kN/m acts at
# x = 9; the floor loads 10 p at heights 3.5 s, s = 1..20
P_TIP = 20 * 3 * 6 * 30.0 * (21.0 - 9.0) / (10.0 * 3.5 * 210)


@pytest.mark.slow
def test_tower_solves_every_load_below_its_tipping_load():
    fr, base = three_bay_tower()
    tr = fr.trace()
    assert tr.ok and tr.ended == "collapse", tr.message
    np.testing.assert_allclose(tr.p_end, P_TIP, rtol=1e-9)
    assert f"tips over about {base[-1]}" in tr.message
    # and how far it has swayed by then, against small-displacement theory
    assert "N20_0 has moved" in tr.message and "beyond small-displacement theory" in tr.message
    loads = np.linspace(0.5 * P_TIP, P_TIP * (1 - 1e-6), 61)
    for p in loads:
        r = fr.solve(p)
        assert r.ok, (p, r.message)
        # vertical equilibrium and moments about the toe, by hand
        normals = {k: s.normal for k, s in r.supports.items()}
        np.testing.assert_allclose(sum(normals.values()), 20 * 3 * 6 * 30.0, rtol=1e-9)
        xs = {k: fr.nodes[k][0] for k in normals}
        moment = sum(n * (21.0 - xs[k]) for k, n in normals.items())
        np.testing.assert_allclose(moment, 10800 * 12.0 - 10 * p * 3.5 * 210, rtol=1e-8,
                                   atol=1e-8 * 10800 * 12.0)
        # the same supports carry it as in the trace (the holonomic path is unique here)
        ref = tr.result_at(p)
        assert {k: s.state for k, s in r.supports.items()} == \
            {k: s.state for k, s in ref.supports.items()}
    with pytest.raises(NoSolutionError, match="tips over"):
        fr.solve(P_TIP * (1 + 1e-4))


def _independent_beam(spans, closed, p, every=10, P=250.0):
    """Reactions and deflections of the same beam with uy fixed at the closed
    supports: a plain Euler-Bernoulli stiffness code (uy, rz per node)."""
    EI, L, w = 30e6 * 1e-4, 6.0, 25.0 * 0.32 + 10.0
    n = spans + 1
    K = np.zeros((2 * n, 2 * n))
    f = np.zeros(2 * n)
    ke = EI / L ** 3 * np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                                 [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]])
    loaded = set(range(every // 2, spans, every))
    for e in range(spans):
        d = [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3]
        K[np.ix_(d, d)] += ke
        # equivalent nodal loads: uniform w, and P p at midspan
        f[d] += -w * np.array([L / 2, L * L / 12, L / 2, -L * L / 12])
        if e in loaded:
            f[d] += -P * p * np.array([0.5, L / 8, 0.5, -L / 8])
    fix = [2 * k for k in closed]
    free = [i for i in range(2 * n) if i not in fix]
    u = np.zeros(2 * n)
    u[free] = np.linalg.solve(K[np.ix_(free, free)], f[free])
    reactions = K @ u - f
    return {k: reactions[2 * k] for k in range(n)}, {k: u[2 * k] for k in range(n)}


@pytest.mark.parametrize("spans", [50, pytest.param(200, marks=pytest.mark.slow)])
def test_long_beam_trace_runs_on_and_solves_pass_their_checks(spans):
    fr = beam_on_supports(spans)
    tr = fr.trace()
    # before: "breakdown" at p = 83.26 (50 spans), 11.69 (200) on equilibrium 1e-8
    assert tr.ok and tr.ended == "unbounded", tr.message
    for p in (10.0, 50.0, 100.0):
        r = fr.solve(p)
        assert r.ok, (p, r.message)   # before: CHECK FAILED at p = 100 (50 spans)
        closed = [k for k in range(spans + 1) if r.supports[f"N{k}"].state == "closed"]
        R, uy = _independent_beam(spans, closed, p)
        big = max(R.values())
        assert all(R[k] >= -1e-9 * big for k in closed)                     # compression only
        assert all(uy[k] >= -1e-12 for k in range(spans + 1) if k not in closed)   # no overlap
        got = np.array([r.supports[f"N{k}"].normal for k in range(spans + 1)])
        want = np.array([R[k] if k in closed else 0.0 for k in range(spans + 1)])
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-8 * big)
        st = tr.result_at(p)
        np.testing.assert_allclose([s.normal for s in st.supports.values()], want, rtol=0,
                                   atol=1e-8 * big)


def test_equilibrium_limit_follows_the_requested_accuracy(monkeypatch):
    """The limit is the accuracy asked for: a result whose per-dof residual is
    2e-6 passes at 'low' (1e-4) and fails at 'high' (1e-9)."""
    from formulations.frames.plane import plane_recovery

    fr = beam_on_supports(20)
    monkeypatch.setattr(plane_recovery, "equilibrium", lambda frame, b, F, X, u, **kw: 2e-6)
    assert fr.solve(10.0, accuracy="low").ok
    r = fr.solve(10.0, accuracy="high")
    assert not r.ok and "CHECK FAILED" in r.message


def test_breakdown_message_names_the_piece_that_failed(monkeypatch):
    from dataclasses import replace

    from formulations.frames.plane import plane_recovery

    fr = beam_on_supports(20)
    tr = fr.trace(p_max=50.0)
    second = tr.trace.pieces[1]
    real = plane_recovery.equilibrium

    def fails_inside_the_second_piece(frame, b, F, X, u, **kw):
        return (1.0 if (second.p_start < frame._p_now < second.p_end)
                else real(frame, b, F, X, u, **kw))

    orig = plane_recovery.result_from_z

    def spy(frame, z, combo, *a, **k):
        frame._p_now = combo.get("variable", 0.0) if isinstance(combo, dict) else combo
        return orig(frame, z, combo, *a, **k)

    monkeypatch.setattr(plane_recovery, "equilibrium", fails_inside_the_second_piece)
    monkeypatch.setattr(fr, "kind", replace(fr.kind, result_from_z=spy))
    bad = fr.trace(p_max=50.0)
    assert bad.ended == "breakdown" and not bad.ok
    assert f"the piece from p = {second.p_start:.10g} to {second.p_end:.10g}" in bad.message
    assert f"stops at p = {second.p_start:.10g}" in bad.message


def _ground_beam(n=30):
    """A ground beam on n + 1 elastic frictional supports (f = 0.4, k = 1e5),
    2 m apart, 6 kN/m, a column at its middle with 200 kN and 10 p kN on top."""
    fr = Frame()
    for i in range(n + 1):
        fr.add_node(f"S{i}", 2.0 * i, 0.0)
    for i in range(n):
        fr.add_distributed_load(fr.add_member(f"S{i}", f"S{i + 1}", 30e6, 0.24, 0.0072), wy=-6.0)
    fr.add_node("T", n * 1.0, 3.0)
    fr.add_member(f"S{n // 2}", "T", 30e6, 0.09, 6.75e-4)
    for i in range(n + 1):
        fr.add_contact(f"S{i}", normal=(0.0, 1.0), friction=0.4, stiffness=1e5)
    fr.add_load("T", fy=-200.0)
    fr.add_load("T", fx=10.0, case="variable")
    return fr


def test_tresca_accepts_a_contact_matrix_convex_to_rounding():
    # before: NotConvexError "eigenvalue -4.37e-12 ... a maximisation written as a minimisation?"
    fr = _ground_beam()
    for p in (1.0, 3.0):
        t = fr.solve(p, method="tresca")
        ref = fr.solve(p, method="lemke")
        assert t.ok and "tresca" in t.route, t.message
        for k in ref.supports:
            assert t.supports[k].state == ref.supports[k].state
        np.testing.assert_allclose([s.normal for s in t.supports.values()],
                                   [s.normal for s in ref.supports.values()], atol=1e-7 * 380)
        # statics by hand: the supports carry the weight 6 x 60 + 200 and the push 10 p
        np.testing.assert_allclose(sum(s.normal for s in t.supports.values()), 560.0, rtol=1e-9)
        np.testing.assert_allclose(sum(s.tangential for s in t.supports.values()), -10 * p,
                                   rtol=1e-9)


def test_tresca_judges_its_iterates_by_the_frames_checks():
    """On the tower (resting on its contacts) a QP iterate lifted the frame by
    2e9 m and passed the LCP certificate; the frame's checks refuse that."""
    fr, _ = three_bay_tower(4)
    r = fr.solve(2.0, method="tresca")
    ref = fr.solve(2.0)
    assert r.ok, r.message
    assert max(s.opening for s in r.supports.values()) < 1.0
    np.testing.assert_allclose([s.normal for s in r.supports.values()],
                               [s.normal for s in ref.supports.values()], atol=1e-7 * 2160)


def _cased_frame():
    fr = Frame()
    for k, x in enumerate([0, 3, 6]):
        fr.add_node(f"S{k}", x, 0.0)
    fr.add_member("S0", "S1", E=30e6, A=0.32, I=0.017, name="B1")
    fr.add_member("S1", "S2", E=30e6, A=0.32, I=0.017, name="B2")
    fr.add_support("S0", fix=("ux",))
    for k in range(3):
        fr.add_contact(f"S{k}", normal=(0, 1))
    fr.add_load("S1", fy=-10, case="D")
    fr.add_load("S2", fy=-5, case="W")
    return fr


def test_a_frame_whose_loads_are_all_in_cases_says_what_to_pass():
    fr = _cased_frame()
    for call in (lambda: fr.solve(), lambda: fr.solve(2.0), lambda: fr.trace(),
                 lambda: fr.trace(constant={"D": 1.0})):
        with pytest.raises(InvalidProblemError, match=r"no load.*'D', 'W'.*combination="):
            call()
    # what the message says to do works: D + W by hand, 15 kN on the supports
    r = fr.solve(combination={"D": 1.0, "W": 1.0})
    assert r.ok
    np.testing.assert_allclose(sum(s.normal for s in r.supports.values()), 15.0, rtol=1e-12)
    tr = fr.trace(constant={"D": 1.0}, variable="W")
    assert tr.ok and tr.ended == "unbounded", tr.message
    # a frame with only constant loads still solves (p has nothing to scale)
    plain = Frame()
    for k, x in enumerate([0, 3]):
        plain.add_node(f"S{k}", x, 0.0)
    plain.add_member("S0", "S1", E=30e6, A=0.32, I=0.017)
    plain.add_support("S0", fix=("ux",))
    for k in range(2):
        plain.add_contact(f"S{k}", normal=(0, 1))
    plain.add_load("S1", fy=-4.0)
    assert plain.solve().ok


def test_diagram_arguments_are_named_in_errors():
    r = _cased_frame().solve(combination={"D": 1.0})
    with pytest.raises(InvalidOptionError, match=r"points: the number of sample points.*'M'"):
        r.diagram("B1", "M")
    for bad in (1.5, 0, True, "21"):
        with pytest.raises(InvalidOptionError, match="points"):
            r.diagram("B1", bad)
    with pytest.raises(InvalidOptionError, match=r"member: .*\['B1', 'B2'\]"):
        r.diagram(3)
    with pytest.raises(InvalidProblemError, match="no member named 'B9'"):
        r.diagram("B9")
    x, N, V, M = r.diagram("B1", 5)
    assert len(x) == 5
