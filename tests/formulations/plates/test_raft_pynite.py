"""Rafts against PyNite (an independent FE code; test extra PyNiteFEA): its
Quad3D plates (DKMQ, Katili et al.) on compression-only nodal springs
(``def_support_spring(..., "-")``), which PyNite iterates, against our
MITC4 raft on tensionless soil with the same nodal springs and loads.  The
elements differ, so the deflections agree to the discretization's error
(0.61 %, 0.57 %, 0.22 % on 8 x 6, 16 x 12, 32 x 24 cells, measured); the
lifted nodes are the same ones (34, 123, 469)."""

from __future__ import annotations

import numpy as np
import pytest

from formulations.plates import Raft

Pynite = pytest.importorskip("Pynite", reason="PyNite is in the test extra (PyNiteFEA)")

E, NU, T, K = 30e6, 0.2, 0.4, 2e4          # kN, m


def _ours(cells):
    raft = Raft(8.0, 6.0, thickness=T, E=E, nu=NU, cells=cells)
    raft.add_soil(K)
    raft.add_area_load(10.0)
    raft.add_point_load(2.0, 3.0, 300.0)
    raft.add_point_load(8.0, 6.0, -200.0)       # a corner pulled up: it lifts
    return raft, raft.solve()


def _pynite(raft):
    from Pynite import FEModel3D

    mesh = raft.mesh
    m = FEModel3D()
    m.add_material("c", E, E / (2 * (1 + NU)), NU, 0.0)
    area = mesh.tributary_areas()
    for i, (x, y) in enumerate(mesh.nodes):       # z up in PyNite: our w is −DZ
        m.add_node(f"N{i}", x, y, 0.0)
        m.def_support(f"N{i}", support_DX=True, support_DY=True, support_RZ=True)
        m.def_support_spring(f"N{i}", "DZ", K * area[i], "-")   # resists moving down only
    for e, (a, b, c, d) in enumerate(mesh.elements):
        m.add_quad(f"Q{e}", f"N{a}", f"N{b}", f"N{c}", f"N{d}", T, "c")
    f = raft.load_vector({"D": 1.0})              # nodal: the same lumping on both sides
    for i in np.flatnonzero(f[0::3]):
        m.add_node_load(f"N{i}", "FZ", -f[3 * i], case="D")
    m.add_load_combo("C", {"D": 1.0})
    m.analyze(check_statics=False, max_iter=30)
    n = mesh.nodes.shape[0]
    return (np.array([-m.nodes[f"N{i}"].DZ["C"] for i in range(n)]),
            np.array([m.nodes[f"N{i}"].RxnFZ["C"] for i in range(n)]))


@pytest.mark.parametrize("cells, tol, tol_force", [
    ((8, 6), 0.01, 0.025),                      # measured 0.61 %, 1.9 % (soil forces)
    pytest.param((16, 12), 0.008, 0.008, marks=pytest.mark.slow)])
def test_lift_off_and_deflections_agree_with_pynite(cells, tol, tol_force):
    raft, ours = _ours(cells)
    assert ours.ok, ours.message
    w, reaction = _pynite(raft)
    assert np.array_equal(w < 0, ours.lifted) and ours.lifted.sum() > 10
    assert np.max(np.abs(w - ours.w)) < tol * np.max(np.abs(ours.w))
    assert np.max(np.abs(reaction - ours.support_force)) < tol_force * np.max(ours.support_force)
