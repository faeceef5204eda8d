"""The space-frame element against independent
references: a cantilever in any orientation by the beam formulas in each
principal plane, torsion and tension; rigid motions cost nothing; and an
L-shaped space frame against PyNite 3-D (bilateral supports)."""

from __future__ import annotations

import numpy as np
import pytest

from formulations.frames.mechanics.space_element import axes, rotation, stiffness
from qpcontact.core.errors import InvalidProblemError
from tests.helpers.paths import DOCS

E, G, A, Iy, Iz, J = 2.1e8, 8.1e7, 0.012, 3e-5, 8e-5, 1.2e-5   # kN, m


def _global_k(xi, xj, ref=None, roll=0.0):
    L = np.linalg.norm(np.subtract(xj, xi))
    T = rotation(axes(xi, xj, ref, roll))[0]
    return T.T @ stiffness(E, G, A, Iy, Iz, J, L) @ T, T, L


@pytest.mark.parametrize("xj, ref, roll", [((3.0, 0.0, 0.0), None, 0.0),
                                           ((1.0, 2.0, 2.0), None, 0.3),
                                           ((0.0, 0.0, 4.0), None, 0.0),
                                           ((2.0, -1.0, 0.5), (0.3, 1.0, 0.2), -1.1)])
def test_cantilever_in_any_orientation_by_the_beam_formulas(xj, ref, roll):
    """Clamped at i, a tip load given in member axes (N along x, P_y, P_z,
    twist T): u = NL/EA, v = P_y L³/3EIz, w = P_z L³/3EIy, θx = TL/GJ,
    θz = P_y L²/2EIz, θy = -P_z L²/2EIy."""
    xi = np.zeros(3)
    K, T, L = _global_k(xi, xj, ref, roll)
    R = T[:3, :3]
    N, Py, Pz, Tq = 30.0, -12.0, 7.0, 5.0
    f_local = np.array([N, Py, Pz, Tq, 0.0, 0.0])
    f = np.r_[R.T @ f_local[:3], R.T @ f_local[3:]]
    d = np.linalg.solve(K[6:, 6:], f)
    d_local = np.r_[R @ d[:3], R @ d[3:]]
    ref_d = [N * L / (E * A), Py * L ** 3 / (3 * E * Iz), Pz * L ** 3 / (3 * E * Iy),
             Tq * L / (G * J), -Pz * L ** 2 / (2 * E * Iy), Py * L ** 2 / (2 * E * Iz)]
    np.testing.assert_allclose(d_local, ref_d, rtol=1e-10, atol=1e-14)


def test_rigid_motions_cost_nothing_and_the_rest_does():
    xi, xj = np.array([0.5, -1.0, 2.0]), np.array([3.0, 1.0, 0.0])
    K, _, L = _global_k(xi, xj, roll=0.7)
    rigid = []
    for k in range(3):                       # translations
        v = np.zeros(12)
        v[k] = v[6 + k] = 1.0
        rigid.append(v)
    for k in range(3):                       # small rotations about the origin
        w = np.eye(3)[k]
        rigid.append(np.r_[np.cross(w, xi), w, np.cross(w, xj), w])
    for v in rigid:
        assert np.abs(K @ v).max() <= 1e-9 * np.abs(K).max()
    eig = np.linalg.eigvalsh(K)
    assert np.sum(eig > 1e-9 * eig.max()) == 6        # six deformation modes
    assert np.allclose(K, K.T)


def test_reference_parallel_to_the_member_is_refused():
    with pytest.raises(InvalidProblemError, match="parallel to the member"):
        axes([0, 0, 0], [1, 1, 0], ref=[2, 2, 0])


def test_l_frame_against_pynite():
    """Two members (along x, then along y) from a clamped base, loads at the
    free end and the knee: nodal displacements against PyNite 3-D (Iy = Iz,
    so the section's orientation does not enter)."""
    pytest.importorskip("Pynite", reason="PyNite is in the test extra (PyNiteFEA)")
    from Pynite import FEModel3D

    I = 5e-5
    nodes = {"A": (0.0, 0.0, 0.0), "B": (4.0, 0.0, 0.0), "C": (4.0, 3.0, 1.0)}
    members = [("A", "B"), ("B", "C")]
    loads = {"B": (0.0, 0.0, -20.0, 0.0, 0.0, 0.0), "C": (5.0, -8.0, -12.0, 3.0, 0.0, 0.0)}
    names = list(nodes)
    K = np.zeros((18, 18))
    for i, j in members:
        L = np.linalg.norm(np.subtract(nodes[j], nodes[i]))
        T = rotation(axes(nodes[i], nodes[j]))[0]
        k = T.T @ stiffness(E, G, A, I, I, J, L) @ T
        dofs = np.r_[6 * names.index(i) + np.arange(6), 6 * names.index(j) + np.arange(6)]
        K[np.ix_(dofs, dofs)] += k
    F = np.zeros(18)
    for n, f in loads.items():
        F[6 * names.index(n) + np.arange(6)] += f
    free = np.arange(6, 18)
    u = np.zeros(18)
    u[free] = np.linalg.solve(K[np.ix_(free, free)], F[free])

    m = FEModel3D()
    m.add_material("s", E, G, 0.3, 0.0)
    m.add_section("x", A, I, I, J)
    for n, xyz in nodes.items():
        m.add_node(n, *xyz)
    m.def_support("A", True, True, True, True, True, True)
    for k, (i, j) in enumerate(members):
        m.add_member(f"M{k}", i, j, "s", "x")
    comps = ("FX", "FY", "FZ", "MX", "MY", "MZ")
    for n, f in loads.items():
        for c, v in zip(comps, f):
            if v:
                m.add_node_load(n, c, v, case="D")
    m.add_load_combo("C", {"D": 1.0})
    m.analyze(check_statics=False)
    for n in ("B", "C"):
        nd = m.nodes[n]
        theirs = [nd.DX["C"], nd.DY["C"], nd.DZ["C"], nd.RX["C"], nd.RY["C"], nd.RZ["C"]]
        ours = u[6 * names.index(n) + np.arange(6)]
        np.testing.assert_allclose(ours, theirs, rtol=1e-9, atol=1e-12 * np.abs(u).max())


def test_space_cantilever_under_uniform_loads_in_member_axes():
    """A cantilever along a skew direction under q_y and q_z (member axes) and
    its own axial q_x: tip v = q_y L⁴/8EIz, w = q_z L⁴/8EIy, u = q_x L²/2EA,
    θz = q_y L³/6EIz, θy = -q_z L³/6EIy (the beam formulas)."""
    from formulations.frames import SpaceFrame

    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 2.0, 1.0, 2.0)
    m = fr.add_member("A", "B", E, A, Iy, Iz, G=G, J=J, roll=0.4)
    fr.add_support("A")
    qx, qy, qz = 3.0, -5.0, 2.0
    fr.add_distributed_load(m, qx, qy, qz, axes="member")
    d = np.array(fr.solve().displacements["B"])
    R = axes([0, 0, 0], [2.0, 1.0, 2.0], None, 0.4)[0]
    t, r = R @ d[:3], R @ d[3:]
    L = 3.0
    np.testing.assert_allclose(
        np.r_[t, r], [qx * L ** 2 / (2 * E * A), qy * L ** 4 / (8 * E * Iz),
                      qz * L ** 4 / (8 * E * Iy), 0.0, -qz * L ** 3 / (6 * E * Iy),
                      qy * L ** 3 / (6 * E * Iz)], rtol=1e-10, atol=1e-15)


def test_space_frame_with_member_loads_against_pynite():
    """A two-storey space frame (four columns, beams both ways) on clamped
    feet under member and nodal loads: displacements against PyNite 3-D."""
    pytest.importorskip("Pynite", reason="PyNite is in the test extra (PyNiteFEA)")
    from Pynite import FEModel3D

    from formulations.frames import SpaceFrame

    I = 6e-5
    fr, m = SpaceFrame(), FEModel3D()
    m.add_material("s", E, G, 0.3, 0.0)
    m.add_section("x", A, I, I, J)
    corners = [(0.0, 0.0), (5.0, 0.0), (5.0, 4.0), (0.0, 4.0)]
    for lvl in range(3):
        for k, (x, y) in enumerate(corners):
            nm = f"N{lvl}{k}"
            fr.add_node(nm, x, y, 3.2 * lvl)
            m.add_node(nm, x, y, 3.2 * lvl)
    for k in range(4):
        fr.add_support(f"N0{k}")
        m.def_support(f"N0{k}", True, True, True, True, True, True)
    members = [(f"N{lvl}{k}", f"N{lvl + 1}{k}") for lvl in range(2) for k in range(4)]
    members += [(f"N{lvl}{k}", f"N{lvl}{(k + 1) % 4}") for lvl in (1, 2) for k in range(4)]
    for n, (i, j) in enumerate(members):
        fr.add_member(i, j, E, A, I, I, G=G, J=J, name=f"M{n}")
        m.add_member(f"M{n}", i, j, "s", "x")
    for n in range(8, len(members)):                     # the floor beams carry 12 kN/m
        fr.add_distributed_load(f"M{n}", wz=-12.0, case="D")
        m.add_member_dist_load(f"M{n}", "FZ", -12.0, -12.0, case="D")
    fr.add_distributed_load("M8", wy=4.0, case="D")      # a horizontal load along one beam
    m.add_member_dist_load("M8", "FY", 4.0, 4.0, case="D")
    fr.add_load("N22", fx=15.0, fy=-6.0, mz=4.0, case="D")
    m.add_node_load("N22", "FX", 15.0, case="D")
    m.add_node_load("N22", "FY", -6.0, case="D")
    m.add_node_load("N22", "MZ", 4.0, case="D")
    m.add_load_combo("C", {"D": 1.0})
    m.analyze(check_statics=False)
    ours = fr.solve(combination={"D": 1.0}).displacements
    big = max(np.abs(v).max() for v in ours.values())
    for nm, d in ours.items():
        nd = m.nodes[nm]
        theirs = [nd.DX["C"], nd.DY["C"], nd.DZ["C"], nd.RX["C"], nd.RY["C"], nd.RZ["C"]]
        np.testing.assert_allclose(d, theirs, rtol=1e-8, atol=1e-10 * big)


def test_a_planar_frame_built_in_space_gives_the_plane_frame_answers():
    """A beam on elastic frictional supports, uplifted and pushed along its
    axis, built in the x-z plane of a space frame (out-of-plane dofs held)
    and as a plane frame: the same contact states and forces to 1e-9 (the
    faceted cone's facets include the in-plane directions, where it is
    exact)."""
    from formulations.frames import Frame
    from formulations.frames import SpaceFrame

    Ep, Ap, Ip, k = 30e6, 0.32, 0.017, 6e4
    xs = [0.0, 3.0, 6.0, 9.0, 12.0]
    plane, space = Frame(), SpaceFrame()
    for n, x in enumerate(xs):
        plane.add_node(f"N{n}", x, 0.0)
        space.add_node(f"N{n}", x, 0.0, 0.0)
        space.add_support(f"N{n}", fix=("uy", "rx", "rz"))
    for n in range(len(xs) - 1):
        plane.add_member(f"N{n}", f"N{n + 1}", Ep, Ap, Ip, name=f"M{n}")
        plane.add_distributed_load(f"M{n}", wy=-18.0)
        # bending in x-z is about local y: Iy = Ip (ref Z puts local z up)
        space.add_member(f"N{n}", f"N{n + 1}", Ep, Ap, Ip, 2 * Ip, G=Ep / 2.4, J=2 * Ip,
                         name=f"M{n}")
        space.add_distributed_load(f"M{n}", wz=-18.0)
    for n in range(len(xs)):
        f = 0.0 if n == 0 else 0.3
        plane.add_contact(f"N{n}", normal=(0.0, 1.0), friction=f, stiffness=k)
        space.add_contact(f"N{n}", normal=(0.0, 0.0, 1.0), friction=f, stiffness=k, facets=8)
    plane.add_support("N0", fix=("ux",))
    space.add_support("N0", fix=("ux", "uy", "rx", "rz"))
    plane.add_load("N3", fy=100.0)
    space.add_load("N3", fz=100.0)
    plane.add_load("N4", fx=-25.0)
    space.add_load("N4", fx=-25.0)
    a, b = plane.solve(), space.solve()
    assert a.ok and b.ok, (a.message, b.message)
    big = max(abs(s.normal) for s in a.supports.values())
    for n in range(len(xs)):
        s2, s3 = a.supports[f"N{n}"], b.supports[f"N{n}"]
        force = s3.tangential_global
        assert s3.state == ("slip" if s2.state.startswith("slip") else s2.state), n
        assert abs(s3.normal - s2.normal) <= 1e-9 * big
        assert abs(force[0] - s2.tangential) <= 1e-9 * big
        assert abs(force[1]) <= 1e-9 * big                  # nothing out of the plane


def _table(f, push_at, ratio=0.9):
    from formulations.frames import SpaceFrame

    W = 40.0
    fr = SpaceFrame()
    for k, (x, y) in enumerate([(0, 0), (2, 0), (2, 2), (0, 2)]):
        fr.add_node(f"P{k}", x, y, 0.0)
        fr.add_node(f"T{k}", x, y, 0.5)
        fr.add_member(f"P{k}", f"T{k}", 2e8, 0.01, 1e-4, 1e-4, G=8e7, J=2e-4)
        fr.add_contact(f"P{k}", friction=f, facets=8)
        fr.add_load(f"T{k}", fz=-W / 4)
    for k in range(4):
        fr.add_member(f"T{k}", f"T{(k + 1) % 4}", 2e8, 0.01, 1e-4, 1e-4, G=8e7, J=2e-4)
    for node, share in push_at.items():
        fr.add_load(node, fx=share * ratio * f * W)
    return fr, W


def test_a_table_on_rigid_frictional_pads_sticks_below_its_friction():
    """Four legs on rigid frictional pads, pushed sideways through its
    centre (a quarter P/4 at each top corner, so by symmetry each pad's
    friction is P/4) at P = 0.5 f W: the back pads' normal force drops to
    W/4 - P h / 4 (h = 0.5 m over the pads' 2 m), whose friction f (W/4 -
    P/8) exceeds P/4 below P = f W / (1 + f/2) = 0.87 f W — so every pad
    sticks, and the pads carry W and the push.  (Lemke's faceted-cone answer to
    the corner push below held a free rigid rotation of 3.5e9 m whose
    rounding spoiled the forces; ok must never be said of such an answer.)"""
    from qpcontact.core.errors import NoSolutionError

    f = 0.3
    fr, W = _table(f, {f"T{k}": 0.25 for k in range(4)}, 0.5)
    r = fr.solve()
    assert r.ok, r.message
    forces = np.array([s.normal * np.array([0, 0, 1.0]) + s.tangential_global
                       for s in r.supports.values()])
    np.testing.assert_allclose(forces.sum(axis=0), [-0.5 * f * W, 0.0, W], atol=1e-9 * W)
    np.testing.assert_allclose(forces[:, 0], -0.125 * f * W, rtol=1e-9)
    assert {s.state for s in r.supports.values()} == {"stick"}
    # the same push at one corner turns the table as well: by the rigid
    # body's statics (an LP over the pads' faceted cones) it cannot be
    # carried beyond 0.8047 f W, so no equilibrium exists — proved, and read
    # as the table sliding (a Farkas vector read as a rigid motion)
    fr, W = _table(f, {"T0": 1.0})
    with pytest.raises(NoSolutionError, match="no equilibrium exists.*slid"):
        fr.solve()


def test_the_docs_space_frame_example_runs_and_says_what_hand_statics_say():
    """docs/frames.md's space-frame session, run as written: at p = 5 every
    pad sticks; the back pads slip at p = f W / (1 + f/2) (their normal force
    W/4 - P h/4, with h = 0.5 m over a 2 m pad spacing, against a friction
    demand P/4) and the table slides away at p = f W = 12 (W = 40 kN,
    f = 0.3)."""
    import re

    text = (DOCS / "frames.md").read_text()
    section = text[text.index("## Space frames"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    scope: dict = {}
    exec(compile(code.replace("print(", "(lambda *a: None)("), "frames.md", "exec"), scope)
    res, tr = scope["res"], scope["tr"]
    assert res.ok and {s.state for s in res.supports.values()} == {"stick"}
    assert tr.ok and tr.ended == "collapse", tr.message
    f, W = 0.3, 40.0
    # on Coulomb's circle (the default) an event is a bracket of certified
    # answers, the limit one between a certified answer and a proof
    (lo, hi), = [ev.bracket for ev in tr.events]
    assert lo <= f * W / (1 + f / 2) <= hi and hi - lo <= 1e-6 * hi
    assert set(tr.events[0].changes) == {"P0", "P3"}          # the back pads, x = 0
    lo, hi = tr.limit
    assert lo <= f * W <= hi and hi - lo <= 1e-6 * hi
    assert "slides away as a rigid body" in tr.message


@pytest.mark.slow
def test_the_trace_of_a_space_frame_is_plotted_against_any_of_its_six_dofs(tmp_path):
    from qpcontact.core.errors import InvalidOptionError

    fr, _ = _table(0.3, {}, 0.0)
    for k in range(4):
        fr.add_load(f"T{k}", fx=0.25, case="variable")
    tr = fr.trace()
    for dof in ("ux", "rz"):
        path = tr.plot(tmp_path / f"{dof}.png", "T0", dof)
        assert (tmp_path / f"{dof}.png").stat().st_size > 0 and str(path).endswith(".png")
    with pytest.raises(InvalidOptionError, match="uz"):
        tr.plot(tmp_path / "x.png", "T0", "fz")
