"""Friction frames (Osipova–Popov–Lovtsov's model) against independent references: enumeration of all
contact states with a separate beam code, hand-computed friction limits,
statics, rescaled data, and independent solves around every breakpoint."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import qpcontact
from formulations.frames import Frame

from .frame_cases import beam_solve
from qpcontact import InvalidProblemError


def _continuous_beam(xs, EI, w, loads):
    fr = Frame()
    for k, x in enumerate(xs):
        fr.add_node(f"N{k}", x, 0.0)
    for k in range(len(xs) - 1):
        m = fr.add_member(f"N{k}", f"N{k + 1}", E=EI / 1e-4, A=1.0, I=1e-4)
        fr.add_distributed_load(m, wy=w)
    fr.add_support("N0", fix=("ux",))
    for k in range(len(xs)):
        fr.add_contact(f"N{k}", normal=(0.0, 1.0))
    for node, fy in loads.items():
        fr.add_load(f"N{node}", fy=fy)
    return fr


@pytest.mark.parametrize("case", range(4))
def test_continuous_beam_matches_enumeration_of_all_contact_states(case):
    rng = np.random.default_rng(case)
    xs = np.cumsum(np.r_[0.0, rng.uniform(1.5, 3.0, 5)])
    EI, w = 2e4, -5.0
    loads = {int(rng.integers(1, 6)): float(rng.uniform(10.0, 25.0))}   # an upward point load
    feasible = []
    for held in itertools.chain.from_iterable(itertools.combinations(range(6), k) for k in range(2, 7)):
        try:
            v, r = beam_solve(xs, EI, w, loads, held)
        except np.linalg.LinAlgError:
            continue
        scale = np.abs(r).max()
        if all(r[i] >= -1e-9 * scale for i in held) and all(v[i] >= -1e-12 for i in range(6) if i not in held):
            feasible.append((set(held), r))
    assert feasible, "the enumeration found no admissible state"
    res = _continuous_beam(xs, EI, w, loads).solve()
    assert res.ok, res.message
    closed = {int(k[1:]) for k, s in res.supports.items() if s.state != "separated"}
    matches = [r for held, r in feasible if {i for i in held if r[i] > 1e-9 * np.abs(r).max()} == closed]
    assert matches, (closed, [h for h, _ in feasible])
    normals = np.array([res.supports[f"N{k}"].normal for k in range(6)])
    np.testing.assert_allclose(normals, matches[0], atol=1e-8 * np.abs(matches[0]).max())


def _cantilever_with_two_contacts(upper_second: bool, f=0.3, gap=0.0, stiffness=None):
    fr = Frame()
    for k, x in enumerate((0.0, 3.0, 6.0)):
        fr.add_node(f"N{k}", x, 0.0)
    m1 = fr.add_member("N0", "N1", E=2e8, A=0.01, I=1e-4)
    m2 = fr.add_member("N1", "N2", E=2e8, A=0.01, I=1e-4)
    fr.add_support("N0", fix=("ux", "uy", "rz"))
    fr.add_contact("N1", normal=(0.0, 1.0), friction=f, gap=gap, stiffness=stiffness)
    fr.add_contact("N2", normal=(0.0, -1.0) if upper_second else (0.0, 1.0), friction=f)
    for m in (m1, m2):
        fr.add_distributed_load(m, wy=-10.0)
    return fr


def test_support_moved_to_the_other_side_separates_and_the_other_sticks_without_friction_force():
    both = _cantilever_with_two_contacts(False).solve()
    assert both.ok and both.supports["N1"].state == "stick" and both.supports["N2"].state == "stick"
    moved = _cantilever_with_two_contacts(True).solve()
    assert moved.ok, moved.message
    assert moved.supports["N2"].state == "separated"
    s1 = moved.supports["N1"]
    assert s1.state == "stick" and s1.normal > 0
    assert abs(s1.tangential) <= 1e-9 * s1.normal
    # the same through the Tresca fixed point
    tres = _cantilever_with_two_contacts(True).solve(method="tresca")
    assert tres.ok and tres.route.startswith("tresca")
    assert {k: v.state for k, v in tres.supports.items()} == {k: v.state for k, v in moved.supports.items()}


def _pinned_beam_on_friction_support(H, f=0.3, P=100.0):
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("C", 2.0, 0.0)
    fr.add_node("B", 4.0, 0.0)
    fr.add_member("A", "C", E=2e8, A=0.01, I=1e-4)
    fr.add_member("C", "B", E=2e8, A=0.01, I=1e-4)
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_contact("B", normal=(0.0, 1.0), friction=f)
    fr.add_load("C", fy=-P)
    fr.add_load("B", fx=H)
    return fr


@pytest.mark.parametrize("method", ["lemke", "tresca"])
def test_friction_threshold_by_hand(method):
    # vertical reaction at B is P/2 whatever H; the node cannot move while it sticks,
    # so the support takes all of H: stick iff H <= f P/2 = 15
    stick = _pinned_beam_on_friction_support(14.0).solve(method=method)
    assert stick.ok and stick.supports["B"].state == "stick"
    np.testing.assert_allclose(stick.supports["B"].normal, 50.0, rtol=1e-9)
    np.testing.assert_allclose(stick.supports["B"].tangential, -14.0, rtol=1e-9)
    slip = _pinned_beam_on_friction_support(16.0).solve(method=method)
    assert slip.ok and slip.supports["B"].state == "slip+"
    np.testing.assert_allclose(slip.supports["B"].tangential, -15.0, rtol=1e-9)
    # the rest of H goes through the beam's axial stiffness to the pin: slip = 1 / (EA / L)
    np.testing.assert_allclose(slip.supports["B"].slip, 1.0 / (2e8 * 0.01 / 4.0), rtol=1e-9)
    np.testing.assert_allclose(slip.reactions["A"][0], -1.0, rtol=1e-9)


def test_badly_scaled_data_give_the_same_states():
    """Steel in N, m (E = 2e11, stiffness entries ~1e8) with 1e-8 m gaps, against
    the same frame in kN and mm."""
    def portal(E, length, load, gap):
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", 0.0, 3 * length)
        fr.add_node("C", 4 * length, 3 * length)
        fr.add_node("D", 4 * length, 0.0)
        fr.add_member("A", "B", E=E, A=4e-3 * length ** 2, I=2e-5 * length ** 4)
        fr.add_member("B", "C", E=E, A=4e-3 * length ** 2, I=2e-5 * length ** 4)
        fr.add_member("C", "D", E=E, A=4e-3 * length ** 2, I=2e-5 * length ** 4)
        fr.add_support("A", fix=("ux", "uy", "rz"))
        fr.add_contact("D", normal=(0.0, 1.0), friction=0.25, gap=gap)
        fr.add_contact("C", normal=(-1.0, 0.0), friction=0.1, gap=2 * gap)
        fr.add_load("B", fx=0.3 * load, fy=-load)
        fr.add_load("C", fy=-load)
        return fr

    si = portal(2e11, 1.0, 5e4, 1e-8).solve()
    kmm = portal(200.0, 1e3, 50.0, 1e-5).solve()
    assert si.ok and kmm.ok, (si.message, kmm.message)
    assert {k: v.state for k, v in si.supports.items()} == {k: v.state for k, v in kmm.supports.items()}
    for k in si.supports:
        np.testing.assert_allclose(si.supports[k].normal / 1e3, kmm.supports[k].normal, rtol=1e-6,
                                   atol=1e-9 * 50.0)


def _trace_frame():
    fr = _pinned_beam_on_friction_support(0.0)
    fr.add_node("E", 4.0, 2.0)
    fr.add_member("B", "E", E=2e8, A=0.01, I=1e-4)
    fr.add_contact("E", normal=(-1.0, 0.0), friction=0.2, gap=1e-5)   # a wall to the right
    fr.add_load("E", fx=10.0, case="variable")
    return fr


def test_trace_breakpoints_confirmed_independently():
    fr = _trace_frame()
    tr = fr.trace(p_max=20.0)
    assert tr.ended == "p_max" and tr.breakpoints.size >= 1
    for st in tr.states:
        assert st.equilibrium_residual < 1e-8, st.message   # every reported state in equilibrium
        assert st.lcp_error < 1e-9
    for k, pk in enumerate(tr.breakpoints):
        eps = 1e-4 * pk
        below, above = fr.solve(p=pk - eps), fr.solve(p=pk + eps)
        sb = {n: s.state for n, s in below.supports.items()}
        sa = {n: s.state for n, s in above.supports.items()}
        assert sb != sa, f"no change of scheme at p = {pk}"
        assert sb == {n: s.state for n, s in tr.states[k].supports.items()}
        assert sa == {n: s.state for n, s in tr.states[k + 1].supports.items()}
    # reactions linear in p between breakpoints
    edges = [0.0, *tr.breakpoints, 20.0]
    for lo, hi in zip(edges[:-1], edges[1:]):
        ps = [lo + f * (hi - lo) for f in (0.2, 0.5, 0.8)]
        xs = [np.array([s.normal for s in tr.result_at(p).supports.values()]) for p in ps]
        np.testing.assert_allclose(xs[1], 0.5 * (xs[0] + xs[2]), atol=1e-9 * max(1, np.abs(xs[1]).max()))


def test_trace_case_without_constant_load_has_no_pre_force():
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 3.0, 0.0)
    fr.add_member("A", "B", E=2e8, A=0.01, I=1e-4)
    fr.add_support("A", fix=("ux", "uy", "rz"))
    fr.add_contact("B", normal=(0.0, 1.0), friction=0.3)
    fr.add_load("B", fy=-10.0, fx=2.0, case="variable")   # only variable loads: case (a)
    tr = fr.trace(p_max=5.0)
    r1 = fr.solve(p=1.0)
    for p in (1e-6, 0.5, 3.0):
        st = tr.result_at(p)
        np.testing.assert_allclose(st.supports["B"].normal, p * r1.supports["B"].normal, rtol=1e-9)
        assert st.equilibrium_residual < 1e-8


def test_frictionless_same_answer_through_every_route():
    fr = Frame()
    for k, x in enumerate((0.0, 2.0, 4.0, 6.0)):
        fr.add_node(f"N{k}", x, 0.0)
    for k in range(3):
        fr.add_member(f"N{k}", f"N{k + 1}", E=2e8, A=0.01, I=1e-4)
    fr.add_support("N0", fix=("ux", "uy", "rz"))   # stable without contacts: R_nn positive definite
    for k in (1, 2, 3):
        fr.add_contact(f"N{k}", normal=(0.0, 1.0), gap=1e-4 * k)
    fr.add_load("N2", fy=-80.0)
    fr.add_load("N3", fy=15.0)
    ref = fr.solve(method="lemke")
    assert ref.ok
    assert fr.solve().route.startswith("active set")
    routes = ["auto", "active-set", "energy", "bpp"] + [m for m, spec in qpcontact.methods().items() if spec.takes == "qp"]
    for route in routes:
        r = fr.solve(method=route)
        if not r.ok:   # an inaccurate backend is reported, never silently wrong
            assert r.lcp_error > 1e-9, route
            continue
        for k in ref.supports:
            assert r.supports[k].state == ref.supports[k].state, route
            np.testing.assert_allclose(r.supports[k].normal, ref.supports[k].normal, atol=1e-6 * 80.0)


def test_combinations_each_get_their_own_contact_state():
    fr = _pinned_beam_on_friction_support(0.0)
    fr.add_load("B", fx=20.0, case="variable")
    res = fr.solve_combinations({"gravity": 0.0, "wind": 1.0})
    assert res["gravity"].supports["B"].state == "stick"
    assert res["wind"].supports["B"].state == "slip+"     # 20 > f P/2 = 15
    for r in res.values():
        assert r.ok and r.equilibrium_residual < 1e-10
    np.testing.assert_allclose(res["gravity"].supports["B"].tangential, 0.0, atol=1e-9)
    np.testing.assert_allclose(res["wind"].supports["B"].tangential, -15.0, rtol=1e-9)


def test_checks_flag_and_errors_name_the_problem(tmp_path):
    fr = _pinned_beam_on_friction_support(5.0)
    r = fr.solve()
    assert r.ok and r.equilibrium_residual < 1e-10 and "equilibrium" in r.message
    assert r.plot(tmp_path / "frame.png").endswith("frame.png")
    tr = fr.trace(p_max=2.0)
    assert tr.plot(tmp_path / "trace.png", node="B").endswith("trace.png")
    with pytest.raises(InvalidProblemError, match="no node"):
        fr.add_member("A", "Z", E=1.0, A=1.0, I=1.0)
    with pytest.raises(InvalidProblemError, match="gap"):
        fr.add_contact("B", gap=-1.0)
    with pytest.raises(qpcontact.InvalidOptionError, match="lemke"):
        fr.solve(method="clarabel")
    lone = Frame()
    lone.add_node("A", 0, 0)
    lone.add_node("B", 1, 0)
    lone.add_member("A", "B", E=1.0, A=1.0, I=1.0)
    lone.add_contact("B", normal=(0, 1))
    with pytest.raises(InvalidProblemError, match="mechanism"):
        lone.solve()


def test_elastic_contact_and_hinge_against_hand_formulas():
    # cantilever (L = 3, EI) with tip load P resting on a spring k at the tip:
    # spring force = P * (L^3/3EI) / (L^3/3EI + 1/k)
    E, I, L, P, k = 2e8, 1e-4, 3.0, 10.0, 5e3
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E=E, A=0.01, I=I)
    fr.add_support("A", fix=("ux", "uy", "rz"))
    fr.add_contact("B", normal=(0.0, 1.0), stiffness=k)
    fr.add_load("B", fy=-P)
    r = fr.solve()
    flex = L ** 3 / (3 * E * I)
    np.testing.assert_allclose(r.supports["B"].normal, P * flex / (flex + 1 / k), rtol=1e-9)
    # a hinge at the end of a member carries no moment
    fr2 = Frame()
    for nm, x in (("A", 0.0), ("B", 2.0), ("C", 4.0)):
        fr2.add_node(nm, x, 0.0)
    m1 = fr2.add_member("A", "B", E=E, A=0.01, I=I, hinge_j=True)
    fr2.add_member("B", "C", E=E, A=0.01, I=I)
    fr2.add_support("A", fix=("ux", "uy", "rz"))
    fr2.add_contact("C", normal=(0.0, 1.0))
    fr2.add_distributed_load(m1, wy=-4.0)
    r2 = fr2.solve()
    x, N, V, M = r2.diagram(m1)
    assert abs(M[-1]) <= 1e-9 * np.abs(M).max()
    # with the hinge, the B-C part is a beam pinned at B on a roller at C, unloaded: C carries nothing
    np.testing.assert_allclose(r2.supports["C"].normal, 0.0, atol=1e-9)


@pytest.mark.parametrize("H, stiffness", [(0.0, None), (5.0, None), (50.0, None), (50.0, 2e4)])
def test_friction_problem_export_reproduces_the_frame_solution(H, stiffness, tmp_path):
    """The exported 2-D problem (global K v = H r + f, u = Hᵀ v + w), written
    to FCLIB and read back, solved by qpcontact.solve (Lemke's exact LCP and
    the cone methods): the same contact forces as Frame.solve, sticking and
    sliding, rigid and elastic contacts."""
    from qpcontact.io import read_fclib, write_fclib

    fr = _cantilever_with_two_contacts(False, gap=1e-4, stiffness=stiffness)
    fr.add_load("N2", fx=H)
    res = fr.solve()
    assert res.ok, res.message
    expected = np.array([[s.normal, s.tangential] for s in res.supports.values()]).ravel()
    prob = read_fclib(write_fclib(fr.friction_problem(), tmp_path / "frame.hdf5"))
    for method, tol in (("lemke", 1e-9), ("auto", 1e-9), ("newton", 1e-9)):
        sol = qpcontact.solve(prob, method, accuracy=tol)
        assert sol.ok, sol.message
        np.testing.assert_allclose(sol.r, expected, rtol=0, atol=1e-6 * np.abs(expected).max())


def test_a_frame_that_is_a_mechanism_without_contacts_is_exported_unreduced(tmp_path):
    """A beam pinned at A and resting on a frictional contact at B: K is
    singular, so W does not exist.  The problem is kept global, survives
    FCLIB, and the global method reproduces Frame.solve's contact forces;
    with an elastic contact too (its spring to a contact point of its own is
    two more dofs of the global problem)."""
    from qpcontact.io import read_fclib, write_fclib

    def frame(stiffness=None):
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", 4.0, 0.0)
        fr.add_member("A", "B", E=2e8, A=0.01, I=1e-4)
        fr.add_support("A", fix=("ux", "uy"))
        fr.add_contact("B", normal=(0.0, 1.0), friction=0.3, stiffness=stiffness)
        fr.add_load("B", fx=2.0, fy=-10.0)
        return fr
    fr = frame()
    res = fr.solve()
    assert res.ok, res.message
    expected = np.array([[s.normal, s.tangential] for s in res.supports.values()]).ravel()
    prob = fr.friction_problem()
    assert not prob.is_reduced and "singular" in prob.global_data["unreduced_because"]
    back = read_fclib(write_fclib(prob, tmp_path / "mechanism.hdf5"))
    assert not back.is_reduced
    sol = qpcontact.solve(back, accuracy=1e-9)
    assert sol.ok and sol.method == "desaxce-global", sol.message
    np.testing.assert_allclose(sol.r, expected, rtol=0, atol=1e-7 * np.abs(expected).max())
    fr = frame(stiffness=1e6)
    res = fr.solve()
    assert res.ok, res.message
    expected = np.array([[s.normal, s.tangential] for s in res.supports.values()]).ravel()
    back = read_fclib(write_fclib(fr.friction_problem(), tmp_path / "elastic.hdf5"))
    assert not back.is_reduced and back.global_data["M"].shape == (6, 6)
    sol = qpcontact.solve(back, accuracy=1e-9)
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.r, expected, rtol=0, atol=1e-7 * np.abs(expected).max())


def _two_nodes():
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 4.0, 0.0)
    fr.add_member("A", "B", E=2e8, A=0.01, I=1e-4, name="M1")
    return fr


@pytest.mark.parametrize("add, words", [
    (lambda fr: fr.add_member("A", "B", E=2e8, A=0.01, I=1e-4, name="M1"),
     "member 'M1' exists already; give another name"),
    # a spring whose condensation overflows (its square: ~1.3e154) made the
    # member's stiffness NaN: an internal matrix's refusal, or an answer
    # with an infinite residual
    (lambda fr: fr.add_member("A", "B", E=2e8, A=0.01, I=1e-4, name="M2", spring_j=1e155),
     r"member 'M2': spring_j must be in \[0, 1e\+100\].*rigid: leave it out\); got 1e\+155"),
    (lambda fr: fr.add_member("B", "A", E=2e8, A=0.01, I=1e-4),
     "member B-A: nodes 'B' and 'A' are joined already by member 'M1'.*combined section"),
    (lambda fr: fr.add_member("A", "B", E=2e8, A=0.01, I=1e-4, name="M2"),
     "member 'M2': nodes 'A' and 'B' are joined already by member 'M1'"),
    (lambda fr: (fr.add_contact("B"), fr.add_contact("B", normal=(0.0, 3.0), friction=0.2)),
     r"contact at 'B': the node has contact 0 with the same normal \(0.0, 1.0\) already.*"
     "change contact 0's friction, gap or stiffness"),
])
def test_a_member_or_a_contact_given_twice_is_refused_naming_it(add, words):
    with pytest.raises(InvalidProblemError, match=words):
        add(_two_nodes())


def test_contacts_at_one_node_with_other_normals_are_allowed():
    fr = _two_nodes()
    fr.add_contact("B", normal=(0.0, 1.0))
    fr.add_contact("B", normal=(-1.0, 0.0))                 # a corner
    fr.add_contact("B", normal=(0.0, -1.0), gap=0.01)       # a slot: the wall above
    assert len(fr.contacts) == 3


@pytest.mark.parametrize("units, words", [
    (("kN",), r"units must be \(force, length\) names, e.g. \('kN', 'm'\); got \('kN',\)"),
    ("kN", "units must be .* got 'kN'"),
    (("m", "kN"), r"units are \(force, length\), in that order; got \('m', 'kN'\), which names "
                  r"a length first — write \('kN', 'm'\)"),
    (("N", "MN"), r"got \('N', 'MN'\), which names a force second"),
])
def test_units_of_the_wrong_shape_or_order_are_refused(units, words):
    with pytest.raises(InvalidProblemError, match=words):
        Frame(units=units)
    assert Frame(units=("lbf", "in")).units == ("lbf", "in")
    assert Frame(units=("kN", "furlong")).units == ("kN", "furlong")   # unknown names pass
