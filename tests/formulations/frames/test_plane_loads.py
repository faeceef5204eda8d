"""Frames for engineers: member loads against hand statics and
textbook fixed-end forces, load cases and combinations solved independently,
springs, named conflicts, fast proved failure, tables and bad input."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from formulations.frames import Frame
from qpcontact.core.errors import (InvalidOptionError, InvalidProblemError, NoSolutionError,
                                   SolverFailedError)
from .frame_cases import beam_solve

E, A, I = 2e8, 0.01, 1e-4   # kN/m², m², m⁴


def _simple_beam(L=6.0, n_inner=0):
    """Pinned at A (x = 0), resting on a frictionless contact at B (x = L)."""
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    m = fr.add_member("A", "B", E, A, I)
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_contact("B", normal=(0.0, 1.0))
    return fr, m


def _clamped_beam(L=6.0):
    """Clamped at A; at B ux and rz fixed, uy held by a contact (closed under
    downward loads): a clamped-clamped beam."""
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    m = fr.add_member("A", "B", E, A, I)
    fr.add_support("A")
    fr.add_support("B", fix=("ux", "rz"))
    fr.add_contact("B", normal=(0.0, 1.0))
    return fr, m


def test_point_load_on_a_simple_beam_matches_statics():
    L, P, a = 6.0, 10.0, 2.0
    fr, m = _simple_beam(L)
    fr.add_point_load(m, a, fy=-P)
    r = fr.solve()
    assert r.ok, r.message
    b = L - a
    assert r.supports["B"].normal == pytest.approx(P * a / L, rel=1e-10)
    assert r.reactions["A"][1] == pytest.approx(P * b / L, rel=1e-10)
    ext = r.extremes(m)["M"]["max"]
    assert ext[0] == pytest.approx(P * a * b / L, rel=1e-10) and ext[1] == pytest.approx(a)
    x, N, V, M = r.diagram(m)
    # shear jumps by -P at the load; both sides are sampled
    assert V.max() == pytest.approx(P * b / L, rel=1e-10)
    assert V.min() == pytest.approx(-P * a / L, rel=1e-10)
    ends = r.end_forces(m)
    assert abs(ends["i"]["M"]) < 1e-9 and abs(ends["j"]["M"]) < 1e-9


def test_point_moment_makes_the_moment_diagram_jump():
    L, M0, a = 6.0, -20.0, 2.5          # clockwise: B pushes, A pulls
    fr, m = _simple_beam(L)
    fr.add_point_load(m, a, mz=M0)
    r = fr.solve()
    assert r.ok, r.message
    assert r.supports["B"].normal == pytest.approx(-M0 / L, rel=1e-10)
    x, N, V, M = r.diagram(m, 61)
    # M = M0 x / L left of a and M0 x / L - M0 right of it
    np.testing.assert_allclose(M[x < a - 1e-9], M0 * x[x < a - 1e-9] / L, atol=1e-9)
    np.testing.assert_allclose(M[x > a + 1e-9], M0 * x[x > a + 1e-9] / L - M0, atol=1e-9)
    assert M.max() - M.min() >= abs(M0) * (1 - 1e-9)   # the jump is sampled on both sides


def test_clamped_beam_point_load_matches_textbook_fixed_end_moments():
    L, P, a = 6.0, 12.0, 1.5
    b = L - a
    fr, m = _clamped_beam(L)
    fr.add_point_load(m, a / L, fy=-P, relative=True)
    r = fr.solve()
    assert r.ok, r.message
    ends = r.end_forces(m)
    assert ends["i"]["M"] == pytest.approx(-P * a * b ** 2 / L ** 2, rel=1e-9)
    assert ends["j"]["M"] == pytest.approx(-P * a ** 2 * b / L ** 2, rel=1e-9)
    assert r.reactions["A"][1] == pytest.approx(P * b ** 2 * (3 * a + b) / L ** 3, rel=1e-9)


@pytest.mark.parametrize("shear, axes", [(None, "global"), (None, "member"),
                                         ((8e7, 0.004), "global"), ((8e7, 0.004), "member")])
def test_a_uniform_load_over_a_whole_inclined_member_gives_its_fixed_end_forces(shear, axes):
    """An inclined member clamped at both ends under a uniform load over its
    whole length (Euler–Bernoulli or Timoshenko: a symmetric load's fixed-end
    forces do not depend on shear) carries it by its fixed-end forces alone,
    by hand: w∥ L/2 along the axis and w⊥ L/2 across it at each end, ∓w⊥ L²/12
    as the end moments; beside it (the same assembly) a clamped level beam
    with a point load at midspan, P/2 and PL/8."""
    dx, dy, w = 3.0, 4.0, (1.5, -6.0)
    L = np.hypot(dx, dy)
    c, s = dx / L, dy / L
    fr = Frame()
    for name, x, y in (("A", 0.0, 0.0), ("B", dx, dy), ("C", 10.0, 0.0), ("D", 16.0, 0.0)):
        fr.add_node(name, x, y)
        fr.add_support(name)
    g = {} if shear is None else dict(G=shear[0], shear_area=shear[1])
    fr.add_member("A", "B", E, A, I, name="AB", **g)
    fr.add_member("C", "D", E, A, I, name="CD", **g)
    fr.add_distributed_load("AB", wx=w[0], wy=w[1], axes=axes)
    fr.add_point_load("CD", 3.0, fy=-12.0)
    r = fr.solve()
    assert r.status == "solved"
    along, across = (w if axes == "member" else (c * w[0] + s * w[1], -s * w[0] + c * w[1]))
    # the member's end forces, back in global axes (x, y) and reversed: the reactions
    fx, fy = c * along - s * across, s * along + c * across
    np.testing.assert_allclose(r.reactions["A"], (-fx * L / 2, -fy * L / 2, -across * L ** 2 / 12),
                               rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(r.reactions["B"], (-fx * L / 2, -fy * L / 2, across * L ** 2 / 12),
                               rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(r.reactions["C"], (0.0, 6.0, 12.0 * 6.0 / 8), rtol=1e-12,
                               atol=1e-12)
    np.testing.assert_allclose(r.reactions["D"], (0.0, 6.0, -12.0 * 6.0 / 8), rtol=1e-12,
                               atol=1e-12)


@pytest.mark.parametrize("w1, w2, start, end", [(-4.0, -4.0, 0.0, 6.0), (-2.0, -8.0, 1.0, 4.5),
                                                (-6.0, 0.0, 2.0, 6.0)])
def test_partial_trapezoidal_load_matches_integrated_influence_lines(w1, w2, start, end):
    L = 6.0
    fr, m = _clamped_beam(L)
    fr.add_distributed_load(m, wy=w1, wy2=w2, start=start, end=end)
    r = fr.solve()
    assert r.ok, r.message
    # fixed-end moments of a clamped beam: the point-load formula integrated
    # over the load (a fine midpoint rule, independent of the code's quadrature)
    xi = np.linspace(start, end, 200001)
    mid, dx = 0.5 * (xi[1:] + xi[:-1]), np.diff(xi)
    w = -(w1 + (w2 - w1) * (mid - start) / (end - start))      # downward intensity
    MA = -np.sum(w * mid * (L - mid) ** 2 / L ** 2 * dx)
    MB = -np.sum(w * mid ** 2 * (L - mid) / L ** 2 * dx)
    ends = r.end_forces(m)
    assert ends["i"]["M"] == pytest.approx(MA, rel=1e-7)
    assert ends["j"]["M"] == pytest.approx(MB, rel=1e-7)
    # vertical equilibrium: the reactions carry the resultant
    total = np.sum(w * dx)
    assert r.reactions["A"][1] + r.supports["B"].normal == pytest.approx(total, rel=1e-7)


def test_member_axes_load_on_an_inclined_member_equals_its_global_components():
    def frame(axes):
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", 3.0, 4.0)
        m = fr.add_member("A", "B", E, A, I)
        fr.add_support("A", fix=("ux", "uy"))
        fr.add_contact("B", normal=(-0.8, 0.6))   # the member's own y axis
        if axes == "member":
            fr.add_distributed_load(m, wy=-2.0, axes="member")
        else:  # member y = (-sin, cos) = (-0.8, 0.6)
            fr.add_distributed_load(m, wx=1.6, wy=-1.2)
        return fr.solve()

    a, g = frame("member"), frame("global")
    assert a.ok and g.ok
    assert a.supports["B"].normal == pytest.approx(g.supports["B"].normal, rel=1e-12)
    # statics: a transverse load 2 x 5 m on a simply supported member: 5 kN at each end
    assert a.supports["B"].normal == pytest.approx(5.0, rel=1e-10)


def test_self_weight_from_unit_weight_equals_weight_per_length_and_the_reactions_carry_it():
    res = []
    for kw in ({"unit_weight": 78.5}, {"weight_per_length": 78.5 * A}):
        fr, m = _simple_beam(6.0)
        fr.add_self_weight("D", **kw)
        res.append(fr.solve(combination={"D": 1.0}))
    assert all(r.ok for r in res)
    total = 78.5 * A * 6.0
    for r in res:
        assert r.reactions["A"][1] + r.supports["B"].normal == pytest.approx(total, rel=1e-10)


def _grade_beam():
    """Six nodes on unilateral supports, pinned horizontally at N0; case D a
    uniform downward load, case W an uplift at N4."""
    xs = np.array([0.0, 2.0, 4.5, 6.5, 9.0, 11.0])
    fr = Frame()
    for k, x in enumerate(xs):
        fr.add_node(f"N{k}", float(x), 0.0)
    for k in range(len(xs) - 1):
        m = fr.add_member(f"N{k}", f"N{k + 1}", E=2e4 / 1e-4, A=1.0, I=1e-4)
        fr.add_distributed_load(m, wy=-5.0, case="D")
    fr.add_support("N0", fix=("ux",))
    for k in range(len(xs)):
        fr.add_contact(f"N{k}", normal=(0.0, 1.0))
    fr.add_load("N4", fy=20.0, case="W")
    fr.add_load("N2", fy=-10.0, case="L")
    return fr, xs


def _enumerated(xs, w, loads):
    """Normal forces by enumeration of every contact state (tests/test_frames)."""
    n = len(xs)
    for held in itertools.chain.from_iterable(itertools.combinations(range(n), k)
                                              for k in range(2, n + 1)):
        try:
            v, r = beam_solve(xs, 2e4, w, loads, held)
        except np.linalg.LinAlgError:
            continue
        scale = np.abs(r).max()
        if all(r[i] >= -1e-9 * scale for i in held) and all(
                v[i] >= -1e-12 for i in range(n) if i not in held):
            return r
    raise AssertionError("no admissible state")


def test_combinations_are_solved_independently_with_their_own_lift_off():
    fr, xs = _grade_beam()
    combos = {"1.4D": {"D": 1.4}, "0.9D+1.0W": {"D": 0.9, "W": 1.0},
              "1.2D+1.6L": {"D": 1.2, "L": 1.6}}
    res = fr.solve_combinations(combos)
    assert not res.failed, [r.message for r in res.values()]
    lifted = {name: {k for k, s in r.supports.items() if s.state == "separated"}
              for name, r in res.items()}
    assert not lifted["1.4D"] and lifted["0.9D+1.0W"], lifted
    refs = {"1.4D": _enumerated(xs, -7.0, {}),
            "0.9D+1.0W": _enumerated(xs, -4.5, {4: 20.0}),
            "1.2D+1.6L": _enumerated(xs, -6.0, {2: -16.0})}
    for name, r in res.items():
        got = np.array([r.supports[f"N{k}"].normal for k in range(len(xs))])
        np.testing.assert_allclose(got, refs[name], atol=1e-8 * np.abs(refs[name]).max())
    # never superposed: the contact states differ, so 0.9 D + W is not 0.9 x (D alone) + W's share
    d_only = fr.solve(combination={"D": 1.0})
    assert d_only.ok
    sup = 0.9 * np.array([d_only.supports[f"N{k}"].normal for k in range(len(xs))])
    got = np.array([res["0.9D+1.0W"].supports[f"N{k}"].normal for k in range(len(xs))])
    assert np.min(got) >= 0 and not np.allclose(got, sup + 0.0, atol=1e-3)
    env = res.envelope()
    for member in fr.members:
        hi = max(r.extremes(member)["M"]["max"][0] for r in res.values())
        assert env[member]["M"]["max"][0] == pytest.approx(hi)


def test_a_combination_that_cannot_be_carried_is_reported_and_the_others_kept(tmp_path):
    fr, xs = _grade_beam()
    res = fr.solve_combinations({"D": {"D": 1.0}, "uplift": {"D": 0.1, "W": 10.0}})
    assert res["D"].ok and res.failed == ["uplift"]
    assert "no equilibrium" in res["uplift"].message and "lift off" in res["uplift"].message
    with pytest.raises(NoSolutionError, match="tips over about N0"):
        fr.solve(combination={"D": 0.1, "W": 10.0})
    with pytest.raises(SolverFailedError, match="not an equilibrium"):
        res["uplift"].plot(tmp_path / "x.png")
    paths = res.to_csv(tmp_path)
    assert {p.split("/")[-1] for p in paths} >= {"members.csv", "envelope.csv", "supports.csv"}
    text = (tmp_path / "combinations.csv").read_text()
    assert "uplift,False" in text and "D,True" in text
    assert res["D"].plot(tmp_path / "d.png").endswith(".png")


def test_elastic_beam_under_an_uplift_it_cannot_carry_fails_fast_and_says_how():
    fr = Frame()
    for k in range(6):
        fr.add_node(f"N{k}", 2.0 * k, 0.0)
    for k in range(5):
        fr.add_member(f"N{k}", f"N{k + 1}", E, A, I)
    fr.add_support("N0", fix=("ux",))
    for k in range(1, 6):
        fr.add_contact(f"N{k}", normal=(0.0, 1.0), stiffness=5e3)
    fr.add_contact("N0", normal=(0.0, 1.0), stiffness=5e3)
    fr.add_load("N3", fy=-10.0, case="D")
    fr.add_load("N5", fx=5.0, fy=40.0, case="W")
    assert fr.solve(combination={"D": 1.0}).ok
    with pytest.raises(NoSolutionError, match="tips over about N0: N1, N2, N3, N4, N5 lift off"):
        fr.solve(combination={"D": 1.0, "W": 2.0})


def test_spring_support_gives_the_textbook_tip_deflection():
    L, k, P = 4.0, 2e3, 10.0
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, A, I)
    fr.add_support("A")
    fr.add_spring("B", uy=k)
    fr.add_contact("B", normal=(-1.0, 0.0), gap=1.0)   # never touched
    fr.add_load("B", fy=-P)
    r = fr.solve()
    assert r.ok, r.message
    v = -P / (k + 3 * E * I / L ** 3)
    assert r.displacements["B"][1] == pytest.approx(v, rel=1e-10)
    assert r.support_reactions["B (contact)"][0] == 0.0
    assert r.support_reactions["B"][1] == pytest.approx(-k * v, rel=1e-10)
    assert r.reactions["A"][1] + r.support_reactions["B"][1] == pytest.approx(P, rel=1e-10)


def test_contact_on_a_direction_a_support_fixes_names_the_node_and_dofs():
    fr, m = _simple_beam()
    fr.add_contact("A", normal=(0.0, 1.0))
    with pytest.raises(InvalidProblemError, match=r"node 'A'.*already fixed.*uy"):
        fr.solve()


@pytest.mark.parametrize("call, match", [
    (lambda fr, m: fr.add_node("Z", float("nan"), 0.0), r"node 'Z': x must be finite"),
    (lambda fr, m: fr.add_node("Z", "3", 0.0), r"node 'Z': x must be a number"),
    (lambda fr, m: fr.add_point_load(m, 7.0, fy=-1.0), "outside the member"),
    (lambda fr, m: fr.add_distributed_load(m, wy="5"), "must be a number"),
    (lambda fr, m: fr.add_load("A", fy=-1.0, case=""), "load case"),
    (lambda fr, m: fr.solve(method="nope"), "unknown method 'nope'"),
    (lambda fr, m: fr.solve(combination={"X": 1.0}), "load case 'X'"),
    (lambda fr, m: fr.add_member("A", "B", "2e8", A, I), "E must be a number"),
])
def test_bad_input_names_the_culprit(call, match):
    fr, m = _simple_beam()
    fr.add_load("B", fy=-1.0)
    with pytest.raises((InvalidProblemError, InvalidOptionError), match=match):
        call(fr, m)


def test_tables_and_diagram_names(tmp_path):
    fr, m = _simple_beam()
    fr.add_point_load(m, 2.0, fy=-10.0)
    r = fr.solve()
    with pytest.raises(InvalidProblemError, match="members"):
        r.diagram("nope")
    with pytest.raises(InvalidOptionError, match="tables"):
        r.rows("nope")
    rows = r.rows("members")
    assert rows[0]["x(M_max) [m]"] == pytest.approx(2.0)
    paths = r.to_csv(tmp_path)
    assert all((tmp_path / p.split("/")[-1]).exists() for p in paths)
    assert not list(tmp_path.glob("*.tmp"))


def test_a_load_that_lifts_a_frame_off_elastic_supports_is_proved_by_a_rigid_motion():
    """Net uplift on a beam held horizontally and by a rotational spring only:
    the contact matrix is singular exactly (a uniform lift costs no force) but
    only nearly so in floating point, where "bpp" finds an LCP answer of huge
    openings that fails the statics check; the rigid motion proves it."""
    fr = Frame()
    for k, x in enumerate([0, 1.5, 3, 4.5, 6]):
        fr.add_node(f"S{k}", x, 0.0)
    for k in range(4):
        fr.add_member(f"S{k}", f"S{k + 1}", E=30e6, A=0.32, I=0.017)
    fr.add_support("S0", fix=("ux",))
    fr.add_spring("S4", rz=5e3)
    for k in range(5):
        fr.add_contact(f"S{k}", normal=(0, 1), stiffness=6e4)
    fr.add_load("S2", fy=-180, case="D")
    fr.add_load("S4", fy=150, mz=-40, case="W")
    assert fr.solve(combination={"D": 0.9, "W": 0.5}).ok
    # 0.9 x 180 = 162 down against 1.6 x 150 = 240 up: every support would have to pull
    with pytest.raises(NoSolutionError, match="S0, S1, S2, S3, S4 would have to pull"):
        fr.solve(combination={"D": 0.9, "W": 1.6})


def test_settlement_of_a_middle_support_matches_the_force_method():
    """Two-span beam (spans L) on end supports, resting on a contact at
    mid-span; the right end settles by δ < 0.  Force method: the rigid tilt
    presses the mid-point |δ|/2 into its support, whose reaction (5/8 w 2L
    under the uniform load) grows by (|δ|/2) · 48 EI / (2L)³."""
    L, w, delta = 4.0, -10.0, -0.002
    EI = E * I
    fr = Frame()
    for k, x in enumerate((0.0, L, 2 * L)):
        fr.add_node(f"N{k}", x, 0.0)
    for k in range(2):
        fr.add_distributed_load(fr.add_member(f"N{k}", f"N{k + 1}", E, A, I), wy=w)
    fr.add_support("N0", fix=("ux", "uy"))
    fr.add_support("N2", fix=("uy",))
    fr.add_contact("N1", normal=(0.0, 1.0))
    fr.add_settlement("N2", "S", uy=delta)
    base = fr.solve(combination={"constant": 1.0})
    settled = fr.solve(combination={"constant": 1.0, "S": 1.0})
    assert base.ok and settled.ok, settled.message
    assert base.supports["N1"].normal == pytest.approx(-5 * w * 2 * L / 8, rel=1e-9)
    change = (-delta / 2) * 48 * EI / (2 * L) ** 3
    assert settled.supports["N1"].normal == pytest.approx(base.supports["N1"].normal + change,
                                                          rel=1e-9)
    assert settled.displacements["N2"][1] == pytest.approx(delta)
    with pytest.raises(InvalidProblemError, match="not fixed by a bilateral support"):
        fr.add_settlement("N1", "S", uy=-0.001)


def test_trace_plot_names_the_valid_dofs_and_nodes(tmp_path):
    from formulations.frames import portal_example

    tr = portal_example().trace(p_max=10.0)
    with pytest.raises(InvalidOptionError, match=r"\('ux', 'uy', 'rz'\)"):
        tr.plot(tmp_path / "t.png", node="B", dof="uz")
    with pytest.raises(InvalidProblemError, match="nodes"):
        tr.plot(tmp_path / "t.png", node="Q", dof="ux")
    # the constant/variable split as named combinations: the same trace
    tr2 = portal_example().trace(p_max=10.0, constant={"constant": 1.0}, variable="variable")
    assert tr2.ok and np.allclose(tr2.breakpoints, tr.breakpoints)


def test_a_combination_solved_directly_agrees_with_the_trace_at_the_same_load():
    """Two routes: the parametric trace (pieces of the path) and a direct
    solve of the combination G + p·W."""
    from formulations.frames import portal_example

    fr = portal_example()
    tr = fr.trace(p_max=35.0)
    for p in (5.0, 20.0, 30.0):
        direct = fr.solve(combination={"constant": 1.0, "variable": p})
        traced = tr.result_at(p)
        assert direct.ok and traced.ok
        for key in direct.supports:
            assert direct.supports[key].state == traced.supports[key].state
            assert direct.supports[key].normal == pytest.approx(traced.supports[key].normal,
                                                                rel=1e-9, abs=1e-9)


def test_moment_labels_do_not_overprint(monkeypatch):
    """A long beam with lift-off: end moments and span extremes crowd near the
    joints; the drawing keeps the larger label and drops the one that would
    print on top of it (checked on the rendered boxes)."""
    import matplotlib
    matplotlib.use("Agg")
    import qpcontact.plots.figures

    fr = Frame(units=("kN", "m"))
    n = 40
    for k in range(n + 1):
        fr.add_node(f"N{k}", 6.0 * k, 0.0)
    for k in range(n):
        fr.add_member(f"N{k}", f"N{k + 1}", 30e6, 0.32, 0.017, name=f"M{k}")
        fr.add_distributed_load(f"M{k}", wy=-18.0, case="D")
    fr.add_support("N0", fix=("ux",))
    for k in range(n + 1):
        fr.add_contact(f"N{k}", normal=(0.0, 1.0), stiffness=6e4)
    for k in (31, 33, 35):
        fr.add_load(f"N{k}", fy=250.0, case="D")
    res = fr.solve(combination={"D": 1.0})
    assert res.ok and any(s.state == "separated" for s in res.supports.values())
    figs = []
    monkeypatch.setattr(qpcontact.plots.figures, "save_figure", lambda fig, path: figs.append(fig))
    res.plot("unused.png")
    fig = figs[0]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    moment_ax = fig.axes[1]
    boxes = [t.get_window_extent(renderer) for t in moment_ax.texts]
    assert len(boxes) >= 4
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b), "two moment labels print on top of each other"
