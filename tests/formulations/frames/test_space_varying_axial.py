"""Second-order space members whose own loads make N vary along them take
N(x) in both bending planes (formulations/frames/space/space_varying.py),
shear-flexible ones too (Engesser's beam-column under N(x):
mechanics/varying_pieces.py), cut or not.  References from other
routes: Greenhill's heavy column (the first zero of J_(−1/3), scipy), the
plane frame's member under N(x) (the plane path, no space code), the space
column cut into constant-N pieces with its weight lumped at the cuts
(Richardson), and Engesser's beam-column under N(x) shot with scipy's
DOP853 (the equations written here, not the element's)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.special import jv

from formulations.frames import Frame
from formulations.frames.mechanics.critical_load import critical_load_factor
from formulations.frames.space.space_frame import SpaceFrame
from tests.helpers.engesser import heavy_cantilever_shot

E, A, L, G = 210e9, 1e-2, 5.0, 81e9
GREENHILL = 2.25 * brentq(lambda z: jv(-1.0 / 3.0, z), 1.0, 2.5) ** 2      # 7.837347439


def _solve(fr, accuracy="high"):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fr.solve(combination={"D": 1.0}, second_order=True, accuracy=accuracy,
                        raise_on_failure=False)


def _space_column(k, q, Iy=1e-5, Iz=1e-5, tip=(10.0, 0.0), lumped=False):
    """A vertical space cantilever (L along z) cut into k members under its
    weight q per length — as member loads, or lumped at the cuts — and a
    tip force (fx, fy)."""
    sf = SpaceFrame()
    nodes = ["A"] + [f"n{j}" for j in range(1, k)] + ["B"]
    for j, node in enumerate(nodes):
        sf.add_node(node, 0.0, 0.0, L * j / k)
    for j in range(k):
        sf.add_member(nodes[j], nodes[j + 1], E, A, Iy, Iz, G=G, J=2e-5, name=f"c{j}")
        if lumped:
            for node in nodes[j:j + 2]:
                sf.add_load(node, fz=-0.5 * q * L / k, case="D")
        else:
            sf.add_distributed_load(f"c{j}", wz=-q, case="D")
    sf.add_support("A")
    sf.add_load("B", fx=tip[0], fy=tip[1], case="D")
    return sf


@pytest.mark.parametrize("weak", ["Iy", "Iz"])
def test_greenhills_heavy_column_in_space_buckles_about_its_weaker_axis(weak):
    """α q L³/(E I_weak) = 7.837347439 with the other axis twice as stiff,
    each axis the weaker in turn (the mean N put it at π²/2 = 4.93)."""
    I_weak, q = 1e-5, 1e3
    sections = {"Iy": 2e-5, "Iz": 2e-5, weak: I_weak}
    res = _solve(_space_column(1, q, sections["Iy"], sections["Iz"], tip=(0.0, 0.0)))
    assert res.ok, res.message
    alpha = critical_load_factor(_space_column(1, q, sections["Iy"], sections["Iz"],
                                               tip=(0.0, 0.0)), res)
    assert alpha["alpha"] * q * L ** 3 / (E * I_weak) == pytest.approx(GREENHILL, rel=1e-9)


def _plane_column(q, I=1e-5, tip=10.0):
    """The space column's plane twin (the plane path: no space code)."""
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    fr.add_member("A", "B", E, A, I, name="c")
    fr.add_support("A")
    fr.add_distributed_load("c", wy=-q, case="D")
    fr.add_load("B", fx=tip, case="D")
    return fr


@pytest.mark.parametrize("k", [1, 4, 64])
@pytest.mark.parametrize("accuracy", ["low", "high"])
def test_the_heavy_space_cantilever_is_the_plane_members_answer_at_every_cut(k, accuracy):
    """At 0.9 of Greenhill's load with 10 N at its tip, cut into k
    members: ok, and its sway and base moment the plane member's under
    N(x) (on the mean N and the largest piece's bound it was ok at "low"
    at 64 pieces with the tip 9.2e-4 off)."""
    q = 0.9 * GREENHILL * E * 1e-5 / L ** 3
    plane = _solve(_plane_column(q))
    assert plane.ok, plane.message
    res = _solve(_space_column(k, q), accuracy)
    assert res.ok, res.message
    tol = 1e-9 if accuracy == "high" else 1e-4
    ref_u = plane.displacements["B"][0]
    assert res.displacements["B"][0] == pytest.approx(ref_u, rel=tol)
    # the base moment: fx bends the column about its local y (local z is
    # global X for a vertical member), My in space, the plane's M
    assert abs(res.diagram("c0", 2)[5][0]) == pytest.approx(abs(plane.diagram("c", 2)[3][0]),
                                                            rel=tol)


def test_the_heavy_space_cantilever_against_its_lumped_cuts_extrapolated():
    """Bending about both axes at once (tip force (10, 5) N, Iy = 2 Iz)
    against the column cut into 64 and 128 constant-N pieces with its weight
    lumped at the cuts (no member load along an axis), Richardson."""
    q = 0.5 * GREENHILL * E * 1e-5 / L ** 3
    sections = dict(Iy=2e-5, Iz=1e-5, tip=(10.0, 5.0))
    cut = [_solve(_space_column(n, q, lumped=True, **sections)) for n in (64, 128)]
    assert all(r.ok for r in cut)
    ref = (4 * np.array(cut[1].displacements["B"][:2]) - cut[0].displacements["B"][:2]) / 3
    res = _solve(_space_column(1, q, **sections))
    assert res.ok, res.message
    assert np.abs(np.array(res.displacements["B"][:2]) - ref).max() <= 1e-7 * np.abs(ref).max()


def _portal(space):
    """A sway portal under its own weight (HEB 300 columns, IPE 400 beam,
    30 kN/m, 20 kN sideways), the right column with a rigid top zone and
    hinged at its top: in the plane, or built in space in the x-z plane
    with its out-of-plane motion held (the columns' in-plane bending is
    about their local y: Iy the plane's I)."""
    A_C, I_C, A_B, I_B, gamma = 149e-4, 25170e-8, 84.5e-4, 23130e-8, 78.5e3
    fr = SpaceFrame() if space else Frame()
    for node, x, y in (("A", 0.0, 0.0), ("D", 12.0, 0.0), ("B", 0.0, 6.0), ("C", 12.0, 6.0)):
        fr.add_node(node, x, 0.0, y) if space else fr.add_node(node, x, y)

    def member(i, j, A_, I_, name, **kw):
        if space:
            fr.add_member(i, j, E, A_, I_, 0.5 * I_, G=G, J=1e-6, name=name, **kw)
        else:
            fr.add_member(i, j, E, A_, I_, name=name, **kw)
    member("A", "B", A_C, I_C, "cL")
    member("D", "C", A_C, I_C, "cR", offset_j=0.4,
           hinge_j=("ry",) if space else True)
    member("B", "C", A_B, I_B, "b")
    for name, a_ in (("cL", A_C), ("cR", A_C)):
        if space:
            fr.add_distributed_load(name, wz=-gamma * a_, case="D")
        else:
            fr.add_distributed_load(name, wy=-gamma * a_, case="D")
    w = -30e3 - gamma * A_B
    fr.add_distributed_load("b", **({"wz": w} if space else {"wy": w}), case="D")
    fr.add_support("A")
    fr.add_support("D")
    if space:
        for node in ("B", "C"):
            fr.add_support(node, ("uy", "rx", "rz"))
    fr.add_load("B", fx=20e3, case="D")
    return fr


def test_a_space_portal_under_its_weight_is_its_plane_twins_answer():
    """Ok at "high" (it was refused: "the member loads of member(s) …
    have axial parts … add nodes"), with the plane portal's sway, base
    moment, top moment under the right column's zone and α_cr."""
    plane, space = _solve(_portal(False)), _solve(_portal(True))
    assert plane.ok, plane.message
    assert space.ok, space.message
    assert space.displacements["B"][0] == pytest.approx(plane.displacements["B"][0], rel=1e-9)
    for member, at in (("cL", 0), ("cL", -1), ("cR", 0)):
        m_plane = plane.diagram(member, 5)[3][at]
        m_space = space.diagram(member, 5)[5][at]       # My: about local y
        assert abs(m_space) == pytest.approx(abs(m_plane), rel=1e-8)
    a_plane = critical_load_factor(_portal(False), plane)["alpha"]
    a_space = critical_load_factor(_portal(True), space)["alpha"]
    assert a_space == pytest.approx(a_plane, rel=1e-8)


def _engesser_shot(q, GAs, H=10.0):
    """(tip sway, base moment) of a cantilever under its weight q and a
    tip force H across it (:func:`tests.helpers.engesser.heavy_cantilever_shot`)."""
    sol, M0 = heavy_cantilever_shot(q, L, E * 1e-5, GAs, H)
    return sol(L)[0], M0


def _shear_column(k, q, GAs, H=10.0):
    fr = Frame()
    nodes = ["A"] + [f"n{j}" for j in range(1, k)] + ["B"]
    for j, node in enumerate(nodes):
        fr.add_node(node, 0.0, L * j / k)
    for j in range(k):
        fr.add_member(nodes[j], nodes[j + 1], E, A, 1e-5, name=f"c{j}", G=G, shear_area=GAs / G)
        fr.add_distributed_load(f"c{j}", wy=-q, case="D")
    fr.add_support("A")
    fr.add_load("B", fx=-H, case="D")
    return fr


@pytest.mark.parametrize("k", [1, 16, 128])
def test_a_shear_flexible_heavy_cantilever_is_ok_and_right_at_every_cut(k):
    """Cut into k pieces (G A_s 1e6 times A G, Euler–Bernoulli to 1e-10),
    at 0.9 of Greenhill's load with 10 N at the tip: ok at "low" and
    "high", the tip the shot's — at "high" to the cut frame's rounding,
    which grows as k³ (128 pieces: 9.7e-9, the Euler–Bernoulli twin's
    4.8e-9) — (when the members kept the mean N, ok at "low" at 64 and 128
    pieces 9.2e-4 and 2.3e-4 off; on the summed bound refused at every cut
    up to 256)."""
    GAs = G * A * 1e6
    q = 0.9 * GREENHILL * E * 1e-5 / L ** 3
    ref, _ = _engesser_shot(q, GAs)
    for accuracy, rel in (("low", 1e-4), ("high", 1e-9 * max(1.0, (k / 32) ** 3))):
        res = _solve(_shear_column(k, q, GAs), accuracy)
        assert res.ok, res.message
        assert abs(res.displacements["B"][0]) == pytest.approx(abs(ref), rel=rel)


@pytest.mark.parametrize("GAs", [1e7, 1e6, 3e5])
def test_a_shear_flexible_column_uncut_is_ok_and_right(GAs):
    """With real shear (G A_s = 1e7 N: its critical weight 3 % below
    Greenhill's; 1e6: 25 %; 3e5: 56 %, its base compressed to 0.96 G A_s
    at the critical weight), at 0.9 of the shot's critical weight, uncut:
    ok at "high", the tip and base moment the shot's, and α_cr the shot's
    critical weight (Engesser's pieces kept the mean N: 128 pieces needed
    at 1e-3 with G A_s = 1e7 on the summed bound, inf with G A_s ~ N)."""
    EI = E * 1e-5

    def determinant(q):          # M(L) of the homogeneous shot from M(0) = 1
        def rhs(x, y):
            N = -q * (L - x)
            dv = y[1] / (1 + N / GAs)
            return [dv, y[2] / EI, N * dv]
        return solve_ivp(rhs, (0, L), [0.0, 0.0, 1.0], method="DOP853", rtol=1e-13,
                         atol=1e-20).y[2, -1]
    top = min(1.0001 * GREENHILL * EI / L ** 3, 0.999 * GAs / L)
    grid = np.linspace(0.05, 1.0, 40) * top
    signs = np.sign([determinant(q) for q in grid])
    i = int(np.flatnonzero(signs[:-1] != signs[1:])[0])
    q_cr = brentq(determinant, grid[i], grid[i + 1], xtol=1e-14, rtol=1e-14)
    q = 0.9 * q_cr
    ref, M0 = _engesser_shot(q, GAs)
    fr = _shear_column(1, q, GAs)
    res = _solve(fr, "high")
    assert res.ok, res.message
    assert abs(res.displacements["B"][0]) == pytest.approx(abs(ref), rel=1e-9)
    assert res.end_forces("c0")["i"]["M"] == pytest.approx(M0, rel=1e-9)
    assert 0.9 * critical_load_factor(fr, res)["alpha"] == pytest.approx(1.0, rel=1e-9)


def _inclined(space):
    """A clamped strut 13 m long rising at 12 in 13 (in space along (3, 4,
    12)/13, in the plane along (5, 12)/13) with a rigid base zone of 1 m,
    under its weight 4 kN/m (global), 2 kN along its axis (member axes) at
    6.5 m and 100 N across it at the top, horizontal in its vertical plane:
    its loads have parts along and across it."""
    fr = SpaceFrame() if space else Frame()
    if space:
        fr.add_node("A", 0.0, 0.0, 0.0)
        fr.add_node("B", 3.0, 4.0, 12.0)
        fr.add_member("A", "B", E, A, 1e-5, 2e-5, G=G, J=2e-5, name="s", offset_i=1.0)
        fr.add_distributed_load("s", wz=-4e3, case="D")
        fr.add_point_load("s", 6.5, fx=-2e3, axes="member", case="D")
        fr.add_load("B", fx=60.0, fy=80.0, case="D")
    else:
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", 5.0, 12.0)
        fr.add_member("A", "B", E, A, 1e-5, name="s", offset_i=1.0)
        fr.add_distributed_load("s", wy=-4e3, case="D")
        fr.add_point_load("s", 6.5, fx=-2e3, axes="member", case="D")
        fr.add_load("B", fx=100.0, case="D")
    fr.add_support("A")
    return fr


def test_an_inclined_space_strut_under_loads_along_and_across_it_is_its_plane_twin():
    """Ok at "high" (its statics on the deformed member: ∫ N v' and the
    consistent loads' turn, in each plane), with the plane twin's top
    displacement, base moment and α_cr."""
    plane, space = _solve(_inclined(False)), _solve(_inclined(True))
    assert plane.ok, plane.message
    assert space.ok, space.message
    ux, uy, uz = space.displacements["B"][:3]
    assert ux / 0.6 == pytest.approx(uy / 0.8, rel=1e-9)
    assert ux / 0.6 == pytest.approx(plane.displacements["B"][0], rel=1e-9)
    assert uz == pytest.approx(plane.displacements["B"][1], rel=1e-9)
    assert abs(space.diagram("s", 3)[5][0]) == pytest.approx(abs(plane.diagram("s", 3)[3][0]),
                                                             rel=1e-9)
    a_plane = critical_load_factor(_inclined(False), plane)["alpha"]
    a_space = critical_load_factor(_inclined(True), space)["alpha"]
    assert a_space == pytest.approx(a_plane, rel=1e-8)


def test_a_space_trace_under_a_variable_weight_is_ok_and_its_answer_the_solves():
    """The heavy space column's weight (0.5 of Greenhill's) the variable
    load, bent both ways by a constant tip force: the trace is ok (it was
    NOT OK, "up to inf of its moments … add nodes") and its answer at p = 1
    the solve's; the plane twin's sway in the stiffer plane the same."""
    q = 0.5 * GREENHILL * E * 1e-5 / L ** 3
    sf = _space_column(1, q, Iy=1e-5, Iz=2e-5, tip=(10.0, 5.0))
    sf.span_loads[:] = [ld.__class__(ld.member, ld.kind, "W", ld.axes, ld.a, ld.b, ld.values)
                        for ld in sf.span_loads]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ft = sf.trace(1.0, "high", constant={"D": 1.0}, variable={"W": 1.0}, second_order=True)
    assert ft.ok, ft.message
    at, solved = ft.result_at(1.0), sf.solve(combination={"D": 1.0, "W": 1.0}, second_order=True)
    assert solved.ok, solved.message
    assert at.displacements["B"][:2] == pytest.approx(solved.displacements["B"][:2], rel=1e-9)
    # fx bends it about local y (Iy), fy about local z (Iz = 2e-5): the
    # plane twins' sways
    for force, I_, got in ((10.0, 1e-5, at.displacements["B"][0]),
                           (5.0, 2e-5, at.displacements["B"][1])):
        twin = _solve(_plane_column(q, I_, force))
        assert got == pytest.approx(twin.displacements["B"][0], rel=1e-9)


def _hinged_space_column(share, Iy=1e-5, Iz=2e-5):
    """A 5 m space column hinged at both ends in both bending planes
    (releases; its nodes' rotations fixed, which the hinges leave the
    member free of), its ends held across it, under its weight ``share`` ×
    E Iy/L³ (Iy the weaker)."""
    sf = SpaceFrame()
    sf.add_node("A", 0.0, 0.0, 0.0)
    sf.add_node("B", 0.0, 0.0, L)
    sf.add_member("A", "B", E, A, Iy, Iz, G=G, J=2e-5, name="c", hinge_i=True, hinge_j=True)
    sf.add_support("A")
    sf.add_support("B", ("ux", "uy", "rx", "ry", "rz"))
    sf.add_distributed_load("c", wz=-share * E * Iy / L ** 3, case="D")
    return sf


def test_a_hinged_heavy_space_column_buckles_on_its_own_in_its_weaker_plane():
    """Its chains' own buckling (both planes, each on its releases) limits
    α_cr at q L³/(E I_weak) = 18.5687 (the plane test's ODE shot), and a
    solve at 19 is UNSTABLE (the mean N, 9.5 E I/L², is below π² E I/L²:
    it was not judged so)."""
    from .test_second_order_varying_axial import buckles_on_its_own

    buckles_on_its_own(_hinged_space_column)


def _rolled(pieces=None):
    """A clamped member rising along (3, 4, 12) (13 m), rolled 0.3 rad, under
    its weight 4 kN/m (global: parts along it and across both its planes),
    300 N/m across its local y on [3.25, 9.75] and 2 kN along its axis at
    6.5 m (member axes), (60, −40, 0) N at its top.  With ``pieces``: cut
    into that many members (a multiple of 4: the loads' ends are nodes),
    the weight's part along the axis and the point load lumped at the
    nodes, the parts across as the pieces' member loads (constant N in
    each piece: the stability functions' route)."""
    xi, xj, w = np.zeros(3), np.array([3.0, 4.0, 12.0]), np.array([0.0, 0.0, -4e3])
    sf = SpaceFrame()
    if pieces is None:
        sf.add_node("A", *xi)
        sf.add_node("B", *xj)
        sf.add_member("A", "B", E, A, 1e-5, 2e-5, G=G, J=2e-5, name="s", roll=0.3)
        sf.add_distributed_load("s", *w, case="D")
        sf.add_distributed_load("s", wy=300.0, axes="member", start=3.25, end=9.75, case="D")
        sf.add_point_load("s", 6.5, fx=-2e3, axes="member", case="D")
    else:
        from formulations.frames.mechanics.space_element import axes

        R = axes(xi, xj, None, 0.3)[0]
        along, across = (R @ w)[0], R @ w
        names = ["A"] + [f"n{j}" for j in range(1, pieces)] + ["B"]
        for j, name in enumerate(names):
            sf.add_node(name, *(xi + (xj - xi) * j / pieces))
        for j in range(pieces):
            sf.add_member(names[j], names[j + 1], E, A, 1e-5, 2e-5, G=G, J=2e-5, name=f"s{j}",
                          roll=0.3)
            sf.add_distributed_load(f"s{j}", wy=across[1], wz=across[2], axes="member",
                                    case="D")
            if pieces // 4 <= j < 3 * pieces // 4:
                sf.add_distributed_load(f"s{j}", wy=300.0, axes="member", case="D")
            for name in names[j:j + 2]:
                sf.add_load(name, *(0.5 * along * 13.0 / pieces * R[0]), case="D")
        sf.add_load(names[pieces // 2], *(-2e3 * R[0]), case="D")
    sf.add_support("A")
    sf.add_load("B", 60.0, -40.0, 0.0, case="D")
    return sf


def test_a_rolled_member_loaded_across_both_planes_against_its_cuts_extrapolated():
    """The top's displacement and both bending moments at the base and at
    the quarter points (My, Mz) against the member cut into 32 and 64
    pieces, Richardson (the uncut answer within 8e-8; 64 pieces alone
    1e-4 off)."""
    res = _solve(_rolled())
    assert res.ok, res.message
    cuts = [_solve(_rolled(n)) for n in (32, 64)]
    assert all(c.ok for c in cuts)

    def read(r, n):
        out = list(r.displacements["B"][:3])
        for x in (0.0, 3.25, 6.5, 9.75):
            if n is None:
                xs, _, _, _, _, My, Mz = r.diagram("s", 5)
                at = int(np.argmin(np.abs(xs - x)))
                out += [My[at], Mz[at]]
            else:            # the piece starting at x: its end actions at i
                f = r.member_forces[f"s{int(round(x / 13.0 * n))}"]
                out += [f[4], -f[5]]
        return np.array(out)
    ref = (4 * read(cuts[1], 64) - read(cuts[0], 32)) / 3
    got = read(res, None)
    assert np.abs(got[:3] - ref[:3]).max() <= 1e-6 * np.abs(ref[:3]).max()
    assert np.all(np.abs(got[3:] - ref[3:]) <= 1e-6 * np.abs(ref[3:]))


#: an inclined member's top whose length the norm along an array's axis
#: gives 1 ulp longer than the norm of the member's own vector (found by a
#: review among random tripods: ~6 % of inclined members)
TOP = (0.6346985056304467, 1.0092400284617629, 7.849627066080663)


def test_an_inclined_cantilever_under_its_weight_is_its_plane_twin():
    """The assembly's length and the loads' (one member's vector norm) must
    be the same number: 1 ulp apart they cut a 1e-16 m piece (stiffness
    1e25) into the member's N(x) chain, and this cantilever raised
    SolverFailedError with raise_on_failure=False and gave α_cr 0.98 where
    its plane twin about the weak axis (the same member in its vertical
    plane, I = Iz) gives 3.328."""
    top = np.array(TOP)
    assert np.linalg.norm(top[None, :], axis=1)[0] != float(np.linalg.norm(top))
    h = float(np.hypot(top[0], top[1]))
    sf = SpaceFrame()
    sf.add_node("A", 0.0, 0.0, 0.0)
    sf.add_node("B", *top)
    sf.add_member("A", "B", 210e9, 1e-2, 2e-4, 1e-4, G=81e9, J=2e-5, name="c")
    sf.add_distributed_load("c", wz=-100e3, case="D")
    sf.add_support("A")
    twins = {}
    for inertia in (2e-4, 1e-4):          # bent in its vertical plane; buckling sideways
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", h, top[2])
        fr.add_member("A", "B", 210e9, 1e-2, inertia, name="c")
        fr.add_distributed_load("c", wy=-100e3, case="D")
        fr.add_support("A")
        twins[inertia] = fr
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rs = sf.solve(combination={"D": 1.0}, second_order=True, raise_on_failure=False)
        rp = twins[2e-4].solve(combination={"D": 1.0}, second_order=True, raise_on_failure=False)
        assert rs.ok and rp.ok, rs.message
        weak = twins[1e-4]
        a_space = sf.critical_load_factor(rs)["alpha"]
        a_plane = weak.critical_load_factor(weak.solve(combination={"D": 1.0}))["alpha"]
    assert a_space == pytest.approx(a_plane, rel=1e-9)
    # the top's displacement along the member's horizontal direction and up
    us, up = np.asarray(rs.displacements["B"]), np.asarray(rp.displacements["B"])
    assert np.hypot(us[0], us[1]) == pytest.approx(abs(up[0]), rel=1e-9)
    assert us[2] == pytest.approx(up[1], rel=1e-9)
