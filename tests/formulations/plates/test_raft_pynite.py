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

from tests.helpers.raft_peers import pynite_raft  # noqa: E402

E, NU, T, K = 30e6, 0.2, 0.4, 2e4          # kN, m


def _ours(cells):
    raft = Raft(8.0, 6.0, thickness=T, E=E, nu=NU, cells=cells)
    raft.add_soil(K)
    raft.add_area_load(10.0)
    raft.add_point_load(2.0, 3.0, 300.0)
    raft.add_point_load(8.0, 6.0, -200.0)       # a corner pulled up: it lifts
    return raft, raft.solve()


@pytest.mark.parametrize("cells, tol, tol_force", [
    ((8, 6), 0.01, 0.025),                      # measured 0.61 %, 1.9 % (soil forces)
    pytest.param((16, 12), 0.008, 0.008, marks=pytest.mark.slow)])
def test_lift_off_and_deflections_agree_with_pynite(cells, tol, tol_force):
    raft, ours = _ours(cells)
    assert ours.ok, ours.message
    w, reaction, converged, _ = pynite_raft(raft, K)
    assert converged, "PyNite raised (its spring iteration did not settle, or the model is unstable)"
    assert np.array_equal(w < 0, ours.lifted) and ours.lifted.sum() > 10
    assert np.max(np.abs(w - ours.w)) < tol * np.max(np.abs(ours.w))
    assert np.max(np.abs(reaction - ours.support_force)) < tol_force * np.max(ours.support_force)
