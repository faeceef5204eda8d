"""Rafts against OpenSees (openseespy, an independent FE code): ShellMITC4
on zeroLength springs of an ENT (elastic no-tension) material, which
OpenSees's Newton iteration re-stiffens until the contact set repeats,
against our MITC4 raft on tensionless soil with the same nodal springs and
loads (tests/helpers/raft_peers.py).  ShellMITC4's bending part is the same
element (Bathe & Dvorkin's assumed shear), so the answers agree to rounding,
not to a discretization error: measured 3.6e-13 (8 x 6 cells) and 1.6e-12
(16 x 12) of the peak deflection, the same lifted nodes (34, 123), OpenSees
converged in 7 Newton iterations on both."""

from __future__ import annotations

import numpy as np
import pytest

from formulations.plates import Raft

pytest.importorskip("openseespy.opensees", reason="openseespy is not installed: no OpenSees peer")

from tests.helpers.raft_peers import opensees_raft  # noqa: E402

E, NU, T, K = 30e6, 0.2, 0.4, 2e4          # kN, m


def _raft(cells, loads):
    raft = Raft(8.0, 6.0, thickness=T, E=E, nu=NU, cells=cells)
    raft.add_soil(K)
    raft.add_area_load(10.0)
    for x, y, P in loads:
        raft.add_point_load(x, y, P)
    return raft


@pytest.mark.parametrize("cells, loads", [
    ((8, 6), [(2.0, 3.0, 300.0), (8.0, 6.0, -200.0)]),      # a corner pulled up: it lifts
    # not tuned on: an eccentric column near one edge, the far edge lifting
    ((10, 8), [(1.0, 1.5, 900.0), (7.0, 4.5, -100.0)]),
    pytest.param((16, 12), [(2.0, 3.0, 300.0), (8.0, 6.0, -200.0)], marks=pytest.mark.slow)])
def test_lift_off_and_deflections_agree_with_opensees(cells, loads):
    raft = _raft(cells, loads)
    ours = raft.solve()
    assert ours.ok, ours.message
    w, force, converged, iterations = opensees_raft(raft, K)
    assert converged, f"OpenSees's iteration did not converge in {iterations} steps"
    assert ours.lifted.sum() > 5 and ours.contact.sum() > 5
    assert np.array_equal(w < 0, ours.lifted)
    # the same element: rounding, not a discretization error
    assert np.max(np.abs(w - ours.w)) < 1e-8 * np.max(np.abs(ours.w))
    assert np.max(np.abs(force - ours.support_force)) < 1e-8 * np.max(ours.support_force)
