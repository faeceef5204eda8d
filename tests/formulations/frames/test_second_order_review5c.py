"""Review 5c: the axial forces' fixed point judged on each member's own
scale without the frame's rigid sway, and a second-order trace's
``result_at`` below the load its path starts from."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from formulations.frames import Frame
from formulations.frames.mechanics.second_order_analysis import critical_load_factor

E, A, I, h = 2e8, 1e-2, 1e-5, 5.0


def pinned_portal(P) -> Frame:
    """Two 5 m columns hinged at their bases, a weak beam (I/10) rigidly
    joined to them 4 m across, P on each column's top and 1e-4 of the
    columns' Euler load pushing sideways."""
    fr = Frame()
    for n, x, y in (("A", 0, 0), ("B", 4, 0), ("C", 0, h), ("D", 4, h)):
        fr.add_node(n, x, y)
    fr.add_member("A", "C", E, A, I, name="c1")
    fr.add_member("B", "D", E, A, I, name="c2")
    fr.add_member("C", "D", E, A, 0.1 * I, name="beam")
    fr.add_support("A", ("ux", "uy"))
    fr.add_support("B", ("ux", "uy"))
    fr.add_load("C", fx=1e-4 * np.pi ** 2 * E * I / h ** 2, fy=-P)
    fr.add_load("D", fy=-P)
    return fr


def test_a_swaying_frames_axial_forces_converge_on_the_members_not_on_the_sway():
    """At 0.98 of its α_cr the portal sways 0.19 m.  Its beam's axial
    force was judged converged on a scale of EA/L (|u_i| + |u_j|) = 1.9e5
    kN — the rigid sway of both its ends — so at "low" (1e-4) it stopped
    with the beam's N −0.036 kN where the answer's own is +0.129 (the
    high answer's 0.126): ok, with the columns' top moment 7.6e-3 off the
    answer at 1e-13.  The scale is capped at the member's Euler load (what
    N changes in its stiffness)."""
    P1 = critical_load_factor(pinned_portal(1.0), pinned_portal(1.0).solve(
        second_order=True))["alpha"]
    fr = pinned_portal(0.98 * P1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = fr.solve(second_order=True, accuracy=1e-13)
        low = fr.solve(second_order=True, accuracy="low")
        high = fr.solve(second_order=True)
    assert low.ok, low.message
    assert low.member_forces["c1"][5] == pytest.approx(ref.member_forces["c1"][5], rel=1e-4)
    assert low.displacements["C"][0] == pytest.approx(ref.displacements["C"][0], rel=1e-4)
    # and at "high": with N converged to 1e-9 the answer moved by N's
    # change times 1/(1 − 1/α_cr) = 50, 3.2e-9 off; the rounds now also
    # wait for the displacements to settle
    assert high.ok, high.message
    assert high.member_forces["c1"][5] == pytest.approx(ref.member_forces["c1"][5], rel=1e-9)
    assert high.displacements["C"][0] == pytest.approx(ref.displacements["C"][0], rel=1e-9)


def column_on_footing(H=0.5, h=6.0, a=3.0) -> Frame:
    from .test_engineer_checks import column_on_footing as made

    return made(H, h, a)


def test_a_second_order_traces_answer_below_where_its_path_starts():
    """Traced on the end's stiffness the column's path starts at p = 1.19
    (below it the end's compression without its loads stands nowhere), but
    the frame itself stands at p = 0 (its constant loads' own answer, ok).
    result_at(0) was that answer; started from the path's axial forces it
    raised InvalidOptionError ("p = -1.19 is outside the traced range
    [0, 198.8]")."""
    fr = column_on_footing()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tr = fr.trace(200.0, second_order=True)
        assert tr.intervals[0][0] > 1.0, tr.message
        for p in (0.0, 1.0):
            at, alone = tr.result_at(p), fr.solve(p=p, second_order=True)
            assert at.ok and alone.ok, at.message
            assert at.supports["L"].normal == pytest.approx(alone.supports["L"].normal, rel=1e-9)


def test_a_second_order_trace_on_the_circular_cone():
    """A space frame on the circular cone: its path is sampled by solves
    (no z_at); reading the path's axial forces at p raised AttributeError
    ('CircularPath' object has no attribute 'z_at') from trace() itself,
    whose states are the answers at their pieces' middles."""
    from formulations.frames.space.space_examples import pad_example

    fr = pad_example(0.0, 0.3, weight=100.0, stiffness=1e5)
    fr.add_load("Q", fx=1.0, case="W")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ft = fr.trace(30.0, constant={"constant": 1.0}, variable="W", second_order=True)
        assert ft.ok and all(s.ok for s in ft.states), ft.message
        at = ft.result_at(10.0)
        alone = fr.solve(combination=ft.combination_at(10.0), second_order=True)
    assert at.ok
    np.testing.assert_allclose(at.displacements["Q"], alone.displacements["Q"], rtol=1e-9,
                               atol=1e-15)


def _weighted_portal(n, share, shear=False, lumped=False):
    """The hinged-base portal at ``share`` of its α_cr (without weight),
    its columns under a self-weight of 3e-5 of their Euler load, cut into
    ``n`` pieces (shear-flexible ones where ``shear``; their weight lumped
    at the cuts where ``lumped``)."""
    q = 3e-5 * np.pi ** 2 * E * I / h ** 3
    fr = Frame()
    for name, x, y in (("A", 0, 0), ("B", 4, 0), ("C", 0, h), ("D", 4, h)):
        fr.add_node(name, x, y)
    for col, (i, j, x) in {"c1": ("A", "C", 0.0), "c2": ("B", "D", 4.0)}.items():
        pts = [i] + [f"{col}_{k}" for k in range(1, n)] + [j]
        for k in range(1, n):
            fr.add_node(pts[k], x, h * k / n)
        for k in range(n):
            name = fr.add_member(pts[k], pts[k + 1], E, A, I, name=f"{col}#{k}",
                                 **({"G": 8e7, "shear_area": A * 5 / 6} if shear else {}))
            if lumped:
                for node in pts[k:k + 2]:
                    fr.add_load(node, fy=-0.5 * q * h / n)
            else:
                fr.add_distributed_load(name, 0.0, -q)
    fr.add_member("C", "D", E, A, 0.1 * I, name="beam")
    fr.add_support("A", ("ux", "uy"))
    fr.add_support("B", ("ux", "uy"))
    fr.add_load("C", fx=1e-4 * np.pi ** 2 * E * I / h ** 2, fy=-share)
    fr.add_load("D", fy=-share)
    return fr


@pytest.mark.parametrize("shear", [True, False], ids=["shear-flexible", "euler-bernoulli"])
def test_a_portal_whose_columns_carry_their_weight_takes_their_n_as_it_varies(shear):
    """The hinged-base portal at 0.9 of its α_cr, its columns under a
    self-weight of 3e-5 of their Euler load, shear-flexible or
    Euler–Bernoulli: their element takes N(x) (mechanics.varying_axial:
    Engesser's beam-column under it), so uncut it is ok and its column's
    top moment is the cut columns' limit — 32 and 64 constant-N pieces,
    their weight lumped at the cuts, extrapolated as 1/n².  Shear-flexible
    columns were refused on the summed spread bound (before that bound ok
    at "low" with the moment 2.4e-4 off); Euler–Bernoulli ones refused
    before N(x), their moment 2.4e-4 off."""
    P1 = critical_load_factor(pinned_portal(1.0), pinned_portal(1.0).solve(
        second_order=True))["alpha"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        low = _weighted_portal(1, 0.9 * P1, shear=shear).solve(
            second_order=True, accuracy="low", raise_on_failure=False)
        one = _weighted_portal(1, 0.9 * P1, shear=shear).solve(
            second_order=True, raise_on_failure=False)
        cut = [_weighted_portal(n, 0.9 * P1, shear=shear, lumped=True).solve(
            second_order=True) for n in (32, 64)]
    assert low.ok and one.ok, (low.message, one.message)
    top = [r.member_forces[f"c1#{n - 1}"][5] for r, n in zip(cut, (32, 64))]
    limit = (4 * top[1] - top[0]) / 3
    assert one.member_forces["c1#0"][5] == pytest.approx(limit, rel=1e-8)
    assert low.member_forces["c1#0"][5] == pytest.approx(limit, rel=1e-4)
