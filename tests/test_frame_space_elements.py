"""The space-frame element (issue 35, first part) against independent
references: a cantilever in any orientation by the beam formulas in each
principal plane, torsion and tension; rigid motions cost nothing; and an
L-shaped space frame against PyNite 3-D (bilateral supports)."""

from __future__ import annotations

import numpy as np
import pytest

from formulations.frames.elements3d import axes, rotation, stiffness
from qpcontact.core.errors import InvalidProblemError

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
