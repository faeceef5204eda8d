"""Frames against PyNite (an independent FE code; test extra PyNiteFEA) on a
single combination with compression-only elastic supports, where PyNite is
right: the grade-beam shape of the member-load tests with member point and partial
trapezoidal loads and an uplift that lifts some supports off."""

from __future__ import annotations

import numpy as np
import pytest

from formulations.frames import Frame

Pynite = pytest.importorskip("Pynite", reason="PyNite is in the test extra (PyNiteFEA)")

E, A, I, K = 30e6, 0.32, 0.017, 6e4       # kN, m
XS = [0.0, 1.5, 3.0, 4.5, 6.0, 7.5, 9.0]


def _ours(uplift):
    fr = Frame()
    for k, x in enumerate(XS):
        fr.add_node(f"N{k}", x, 0.0)
    for k in range(len(XS) - 1):
        fr.add_member(f"N{k}", f"N{k + 1}", E, A, I, name=f"M{k}")
        fr.add_distributed_load(f"M{k}", wy=-8.0, case="D")
    fr.add_support("N0", fix=("ux",))
    for k in range(len(XS)):
        fr.add_contact(f"N{k}", normal=(0.0, 1.0), stiffness=K)
    fr.add_point_load("M2", 0.5, fy=-40.0, case="D")
    fr.add_distributed_load("M1", wy=-12.0, wy2=-2.0, start=0.3, end=1.2, case="D")
    fr.add_load("N6", fy=uplift, case="D")
    return fr.solve(combination={"D": 1.0})


def _pynite(uplift):
    from Pynite import FEModel3D

    m = FEModel3D()
    m.add_material("c", E, E / 2.4, 0.2, 0.0)
    m.add_section("s", A, I, I, 2 * I)
    for k, x in enumerate(XS):
        m.add_node(f"N{k}", x, 0.0, 0.0)
        m.def_support(f"N{k}", support_DX=k == 0, support_DZ=True, support_RX=True,
                      support_RY=True)
        m.def_support_spring(f"N{k}", "DY", K, "-")     # resists downward motion only
    for k in range(len(XS) - 1):
        m.add_member(f"M{k}", f"N{k}", f"N{k + 1}", "c", "s")
        m.add_member_dist_load(f"M{k}", "FY", -8.0, -8.0, case="D")
    m.add_member_pt_load("M2", "FY", -40.0, 0.5, case="D")
    m.add_member_dist_load("M1", "FY", -12.0, -2.0, 0.3, 1.2, case="D")
    m.add_node_load("N6", "FY", uplift, case="D")
    m.add_load_combo("C", {"D": 1.0})
    m.analyze(check_statics=False)
    return m


@pytest.mark.parametrize("uplift", [0.0, 30.0, 50.0])
def test_reactions_and_moments_agree_with_pynite(uplift):
    ours = _ours(uplift)
    assert ours.ok, ours.message
    pn = _pynite(uplift)
    got = np.array([ours.supports[f"N{k}"].normal for k in range(len(XS))])
    ref = np.array([pn.nodes[f"N{k}"].RxnFY["C"] for k in range(len(XS))])
    np.testing.assert_allclose(got, ref, atol=1e-6 * np.abs(ref).max())
    if uplift >= 50.0:
        assert any(s.state == "separated" for s in ours.supports.values())
    for k in range(len(XS) - 1):
        mm = pn.members[f"M{k}"]
        L = XS[k + 1] - XS[k]
        x, _, _, M = ours.diagram(f"M{k}", 11)
        # PyNite's Mz along the member, sign flipped to the sagging-positive convention
        ref_m = np.array([mm.moment("Mz", xx, "C") for xx in x])
        scale = max(np.abs(ref_m).max(), 1.0)
        np.testing.assert_allclose(M, -ref_m, atol=1e-6 * scale)
        assert x[-1] == pytest.approx(L)
