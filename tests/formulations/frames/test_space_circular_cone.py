"""Space frames with the true circular Coulomb cone : the exported
friction problem against hand values, ``solve()`` (the circular cone is the default) against
the statics of a pad and a cantilever by hand, the faceted cone's answers
converging to the circular one (at the rates the polygon's geometry gives by
hand), the FCLIB round trip and the instances ``qpcontact compare`` runs."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import qpcontact
from formulations.frames import SpaceFrame
from formulations.frames.space.circular_cone import circular_result, judged
from formulations.frames.space.space_examples import COLUMN, bays_on_pads, pad_example
from qpcontact.core.errors import InvalidOptionError, NoSolutionError, SolverFailedError

F_PAD, W_PAD, K_PAD = 0.4, 100.0, 1e4          # the pad: friction, weight (kN), spring (kN/m)
ANGLE = np.radians(30.0)                       # the push, from t1 towards t2


def _tangent(angle):
    return np.array([np.cos(angle), np.sin(angle)])


def test_the_friction_problem_in_3d_by_hand():
    """The post on an elastic pad with a gap, held by springs k (ux, uy) and
    kz (uz) at its foot, rotations held: the foot moves as a point on its
    springs, so W = diag(1/kz, 1/k, 1/k) + 1/kc and q = (g − W/kz, the
    push's components along t1, t2 over k) — by hand, whatever the post;
    the spring of the elastic pad is three more dofs of the global form.
    And for a contact with a tilted normal, Hᵀ of a rigid translation d is
    (n·d, t1·d, t2·d) with (n, t1, t2) orthonormal and right-handed."""
    kz, kc, gap, push = 3e4, 2e5, 1e-3, 35.0
    fr = pad_example(push, ANGLE, weight=W_PAD, friction=F_PAD, spring=K_PAD, stiffness=kc)
    fr.add_spring("P", uz=kz)
    fr.contacts[0].gap = gap
    prob = fr.friction_problem()
    assert prob.dim == 3 and prob.n_contacts == 1 and prob.is_reduced
    np.testing.assert_allclose(prob.mu, [F_PAD])
    np.testing.assert_allclose(prob.W, np.diag([1 / kz, 1 / K_PAD, 1 / K_PAD]) + np.eye(3) / kc,
                               rtol=1e-9, atol=1e-12 / K_PAD)
    np.testing.assert_allclose(prob.q, [gap - W_PAD / kz, *(push * _tangent(ANGLE) / K_PAD)],
                               rtol=1e-9)
    g = prob.global_data
    assert g["M"].shape == (3 + 6 + 3, 3 + 6 + 3)      # foot, post top, the pad's point
    # a tilted rigid contact: H's columns from a rigid translation
    n = np.array([0.3, -0.2, 1.0]) / np.linalg.norm([0.3, -0.2, 1.0])
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 2.0, 1.0, 0.5)
    fr.add_member("A", "B", **COLUMN)
    fr.add_support("A", fix=("rx", "ry", "rz"))
    fr.add_spring("A", ux=1e4, uy=1e4, uz=1e4)
    c = fr.contacts[fr.add_contact("B", normal=n, friction=0.3, gap=2e-3)]
    fr.add_load("B", fz=-10.0)
    frame = np.array([n, c.t1, c.t2])
    np.testing.assert_allclose(frame @ frame.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(frame) == pytest.approx(1.0)
    g = fr.friction_problem().global_data
    d = np.array([0.7, -1.3, 0.4])
    v = np.r_[d, d, np.zeros(3)]                     # A: ux, uy, uz; B: six dofs
    np.testing.assert_allclose(g["H"].T @ v + g["w"], [2e-3 + n @ d, c.t1 @ d, c.t2 @ d],
                               atol=1e-15)


@pytest.mark.parametrize("push", [0.5 * F_PAD * W_PAD, 0.95 * F_PAD * W_PAD,
                                  1.7 * F_PAD * W_PAD, 3.0 * F_PAD * W_PAD])
@pytest.mark.parametrize("kc", [None, 2e4])
def test_a_pad_pushed_obliquely_sticks_or_slips_as_by_hand(push, kc):
    """Coulomb's circular cone by hand: the pad carries the weight; with a
    rigid pad it sticks while push <= f W (friction −push along it), beyond
    it slips along the push, friction f W against it, the foot moving
    (push − f W)/k.  An elastic pad (kc) shares the push with its own
    spring: it sticks while push <= f W (1 + k/kc), friction
    −push/(1 + k/kc), and its slip counts its spring's part X_t/kc.  Every
    result field by hand: reactions (the held rotations carry the push's
    moment about the foot), the post's end actions, displacements."""
    fr = pad_example(push, ANGLE, weight=W_PAD, friction=F_PAD, spring=K_PAD, stiffness=kc)
    res = fr.solve()
    assert res.ok, res.message
    assert res.route.startswith("circular cone")
    s = res.supports["P"]
    e = _tangent(ANGLE)
    share = 1.0 + (0.0 if kc is None else K_PAD / kc)
    sticks = push <= F_PAD * W_PAD * share
    friction = push / share if sticks else F_PAD * W_PAD
    assert s.state == ("stick" if sticks else "slip")
    assert s.normal == pytest.approx(W_PAD, rel=1e-9)
    np.testing.assert_allclose(s.tangential, -friction * e, rtol=1e-9, atol=1e-9 * W_PAD)
    foot = (push - friction) / K_PAD                      # along the push
    slip = foot - (0.0 if kc is None else friction / kc)
    scale = push / K_PAD                                  # what the push makes of the springs
    np.testing.assert_allclose(s.slip, slip * e, rtol=1e-8, atol=1e-9 * scale)
    c = fr.contacts[0]
    d = (e[0] * c.t1 + e[1] * c.t2)
    uP = np.array(res.displacements["P"])
    np.testing.assert_allclose(uP[:3], foot * d + [0, 0, -(0.0 if kc is None else W_PAD / kc)],
                               rtol=1e-8, atol=1e-9 * scale)
    np.testing.assert_allclose(uP[3:], 0.0, atol=1e-15)
    # the held rotations: the push at 1 m above the foot, M = r x F, r = (0, 0, 1)
    F = push * d
    np.testing.assert_allclose(res.reactions["P"][3:], -np.cross([0, 0, 1.0], F), rtol=1e-9,
                               atol=1e-9 * push)
    end = res.end_forces(next(iter(fr.members)))
    assert end["j"]["N"] == pytest.approx(-W_PAD, rel=1e-9)       # compression at Q
    assert s.opening == pytest.approx(0.0, abs=1e-12)


def test_a_cantilever_tip_over_a_gap_separates_or_closes_as_by_hand():
    """A cantilever along x, clamped at A, a frictional contact under its tip
    B with gap g: the tip deflects P L³/(3 E Iy); below g the contact stays
    open (state separated, no force, opening g − δ), beyond it closes with
    X_n = P − 3 E Iy g / L³ and sticks with no friction."""
    E, Gm, A, Iy, Iz, J = (COLUMN[k] for k in ("E", "G", "A", "Iy", "Iz", "J"))
    L, P = 3.0, 20.0
    delta = P * L ** 3 / (3 * E * Iy)
    for gap in (2 * delta, 0.5 * delta):
        fr = SpaceFrame()
        fr.add_node("A", 0.0, 0.0, 0.0)
        fr.add_node("B", L, 0.0, 0.0)
        fr.add_member("A", "B", E, A, Iy, Iz, G=Gm, J=J)
        fr.add_support("A")
        fr.add_contact("B", friction=0.3, gap=gap)
        fr.add_load("B", fz=-P)
        res = fr.solve()
        assert res.ok, res.message
        s = res.supports["B"]
        if gap > delta:
            assert s.state == "separated" and s.normal == 0.0
            assert s.opening == pytest.approx(gap - delta, rel=1e-8)
        else:
            assert s.state == "stick"
            assert s.normal == pytest.approx(P - 3 * E * Iy * gap / L ** 3, rel=1e-8)
            np.testing.assert_allclose(s.tangential, 0.0, atol=1e-9 * P)


def _vertex_answer(push, angle, m, fn):
    """The faceted cone's answer by hand: the polygon {y: d_k·y <= f N}
    circumscribes the circle; pushed far enough along ``angle`` the
    friction −y sits at the vertex between the two facets whose directions
    bracket the push, at f N / cos(π/m) along their bisector — if the
    spring's pull P − v lies between those two facets' directions (checked)."""
    k = int(np.floor(angle * m / (2 * np.pi)))
    phi = (2 * k + 1) * np.pi / m
    v = fn / np.cos(np.pi / m) * _tangent(phi)
    pull = push * _tangent(angle) - v
    lo, hi = 2 * np.pi * k / m, 2 * np.pi * (k + 1) / m
    assert lo <= np.arctan2(pull[1], pull[0]) % (2 * np.pi) <= hi
    return -v, pull / K_PAD


def test_faceted_cone_converges_to_the_circular_cone_on_a_pad_pushed_obliquely():
    """The pad pushed at 30° from t1 with 2 f W: the faceted answers (Lemke,
    m = 4 ... 64 facets) are the polygon's vertex by hand, the circular one
    is f W against the push.  Their difference has two parts, each at the
    rate the polygon's geometry gives: along the push (the friction's size,
    what the slip dissipates) 1/cos(π/m) − 1 ~ π²/(2m²), a quarter per
    doubling of m, 1.1e-3 of f W at m = 64; across it (the friction's
    direction) the angle from the push to the vertex, π/(3m) here, a half
    per doubling.  The push sits a third of a sector from a facet direction
    for every m, so each doubling compares like with like."""
    fn = F_PAD * W_PAD
    push = 2 * fn
    e, n = _tangent(ANGLE), _tangent(ANGLE + np.pi / 2)
    circ = pad_example(push, ANGLE).solve().supports["P"]
    np.testing.assert_allclose(circ.tangential, -fn * e, rtol=1e-9)
    along, across, slips = [], [], []
    for m in (4, 8, 16, 32, 64):
        res = pad_example(push, ANGLE, facets=m, cone="circumscribed").solve()
        assert res.ok, res.message
        s = res.supports["P"]
        friction, slip = _vertex_answer(push, ANGLE, m, fn)
        np.testing.assert_allclose(s.tangential, friction, rtol=1e-9)
        np.testing.assert_allclose(s.slip, slip, rtol=1e-9)
        d = (s.tangential - circ.tangential) / fn
        along.append(abs(d @ e))
        across.append(abs(d @ n))
        slips.append(np.linalg.norm(s.slip - circ.slip) * K_PAD / fn)
        assert along[-1] <= 1 / np.cos(np.pi / m) - 1
        assert across[-1] <= np.pi / m
    along, across = np.array(along), np.array(across)
    ms = np.array([4, 8, 16, 32, 64])
    np.testing.assert_allclose(along, np.cos(np.pi / (3 * ms)) / np.cos(np.pi / ms) - 1,
                               rtol=1e-6)
    np.testing.assert_allclose(across, np.sin(np.pi / (3 * ms)) / np.cos(np.pi / ms), rtol=1e-6)
    # the rates per doubling: along 5.00, 4.20, 4.05, 4.01 (→ 4: π²/(2m²));
    # across 2.59, 2.12, 2.03, 2.01 (→ 2: π/(3m))
    np.testing.assert_allclose(along[1:-1] / along[2:], 4.0, rtol=0.06)
    np.testing.assert_allclose(across[2:-1] / across[3:], 2.0, rtol=0.02)
    # the slip is the spring's pull: the same difference over k
    np.testing.assert_allclose(slips, np.hypot(along, across), rtol=1e-6)
    assert along[-1] <= 1.1e-3 and across[-1] <= 1.7e-2


def _bays_statics(res, p):
    """Σ contact forces = −Σ loads (by hand: 20 kN/m on 12 beams of 5 m, and
    p (8, 5) kN at each of the 9 top nodes), and Coulomb's law at every pad
    read off the result: |X_t| <= f X_n; a slipping pad's friction at f X_n,
    against its slip."""
    forces = np.array(list(res.support_reactions.values()))
    np.testing.assert_allclose(forces.sum(axis=0), [-9 * 8.0 * p, -9 * 5.0 * p, 1200.0],
                               rtol=1e-9, atol=1e-9 * 1200)
    for s in res.supports.values():
        t = np.linalg.norm(s.tangential)
        assert t <= 0.5 * s.normal * (1 + 1e-9)
        if s.state == "slip":
            assert t == pytest.approx(0.5 * s.normal, rel=1e-8)
            cos = s.tangential @ s.slip / (t * np.linalg.norm(s.slip))
            assert cos == pytest.approx(-1.0, abs=1e-8)


def test_a_frame_on_nine_pads_faceted_and_circular():
    """The 2 x 2-bay frame on nine rigid pads (a mechanism without them: its
    problem stays global), pushed obliquely so that three pads slip: the
    circular answer meets the statics and Coulomb's law by hand, and so do
    the faceted ones (with the polygon's cone); from 16 facets on the two
    agree on every pad's state, and their friction forces come together as
    the facets' angle (the slips' directions are generic here: first order
    in π/m)."""
    p = 5.0
    circ = bays_on_pads(2).solve(p)
    assert circ.ok, circ.message
    assert circ.route.startswith("circular cone")
    _bays_statics(circ, p)
    assert sorted(s.state for s in circ.supports.values()).count("slip") == 3
    big = max(np.linalg.norm(s.tangential) for s in circ.supports.values())
    gaps = {}
    for m in (16, 64):
        res = bays_on_pads(2, facets=m, cone="circumscribed").solve(p)
        assert res.ok, res.message
        forces = np.array(list(res.support_reactions.values()))
        np.testing.assert_allclose(forces.sum(axis=0), [-9 * 8.0 * p, -9 * 5.0 * p, 1200.0],
                                   rtol=1e-9, atol=1e-9 * 1200)
        assert all(res.supports[k].state == s.state for k, s in circ.supports.items())
        gaps[m] = max(np.linalg.norm(res.supports[k].tangential - s.tangential)
                      for k, s in circ.supports.items()) / big
    assert gaps[64] <= 0.5 * gaps[16] and gaps[64] <= np.pi / 64


def test_combinations_warnings_and_what_cannot_be_carried():
    """solve_combinations takes the cone; an unknown cone or a method that
    solves the facets is refused by name; a method stopped early is reported
    not ok (and raises with raise_on_failure); a push the pads cannot carry
    is proved so (the friction problem's ray, checked from the data)."""
    fr = bays_on_pads(2, lateral=(40.0, 25.0), pinned_corners=True)
    out = fr.solve_combinations({"a": 1.0, "b": 2.0})
    assert all(r.ok and r.route.startswith("circular") for r in out.values())
    with pytest.raises(InvalidOptionError, match="not a solve option"):
        fr.solve(cone="round")
    with pytest.raises(InvalidOptionError, match="Lemke solves a polygon"):
        fr.solve(method="lemke")
    early = fr.solve(2.0, method="desaxce-fp", max_outer=1)
    assert early.ok or "CHECK FAILED" in early.message
    with pytest.raises(NoSolutionError, match="no equilibrium"):
        bays_on_pads(2).solve(20.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert fr.solve(1.0).ok


def test_a_wrong_answer_is_not_ok():
    """The checks can fail: the pad's circular answer with the friction 1e-6
    off (the same displacements) fails the friction certificate, and with
    the displacements 1e-6 off (the same forces) the frame's equilibrium;
    refined on its states, the first comes back right."""
    fr = pad_example(3 * F_PAD * W_PAD, ANGLE)
    b = fr.build()
    combo = {"constant": 1.0, "variable": 1.0}
    prob = fr.friction_problem(_built=b)
    sol = qpcontact.solve(prob, accuracy=1e-12)
    assert sol.ok
    good = circular_result(fr, prob, sol.r, sol.v, b, combo, "test", 1e-9)
    assert good.ok, good.message
    u = good._u
    r = sol.r.copy()
    r[1:] *= 1 + 1e-6
    assert not judged(fr, prob, b, combo, u, r, None, "test", 1e-9)[0].ok
    assert not judged(fr, prob, b, combo, u * (1 + 1e-6), sol.r, None, "test", 1e-9)[0].ok
    # circular_result refines a wrong answer on its states: it comes back right
    assert circular_result(fr, prob, r, sol.v, b, combo, "test", 1e-9).ok


@pytest.mark.parametrize("pinned, stiffness", [(False, None), (True, 2e5)])
def test_fclib_round_trip_gives_the_frames_answer(pinned, stiffness, tmp_path):
    """The space frame's circular problem written as an FCLIB global problem
    (fclib_global: M, H, f, w, mu), read back and solved: the frame's
    contact forces.  On pads alone it stays unreduced; with the corners
    pinned and elastic pads it is reduced too, and the local methods solve
    it as well."""
    import h5py

    from qpcontact.io import read_fclib, write_fclib

    lateral, p = ((40.0, 25.0), 2.0) if pinned else ((8.0, 5.0), 5.0)
    fr = bays_on_pads(2, lateral=lateral, pinned_corners=pinned, stiffness=stiffness)
    res = fr.solve(p)
    assert res.ok, res.message
    expected = np.array([[s.normal, *s.tangential] for s in res.supports.values()]).ravel()
    path = write_fclib(fr.friction_problem(p), tmp_path / "frame.hdf5")
    with h5py.File(path) as h:
        assert "fclib_global" in h and "fclib_local" not in h
        assert int(h["fclib_global/spacedim"][0]) == 3
    back = read_fclib(path)
    assert back.is_reduced == pinned
    for method in (("auto", "newton", "nsgs") if pinned else ("auto",)):
        sol = qpcontact.solve(back, method, accuracy=1e-9)
        assert sol.ok, (method, sol.message)
        np.testing.assert_allclose(sol.r, expected, rtol=0, atol=1e-7 * np.abs(expected).max())


def test_compare_lists_and_runs_the_space_frames():
    """``qpcontact compare`` collects both space-frame instances from the
    frames formulation ("hard"), plans the friction methods that take each
    form, and "auto" is certified on both at "high"."""
    from qpcontact.commands import compare

    insts = {i.name: i for i in compare.collect_instances(quick=True, formulations=["frames"])}
    pads, pinned = "frames/space-2x2-bays-on-9-pads", "frames/space-2x2-bays-pinned-on-5-pads"
    assert pads in insts and pinned in insts
    tasks = compare.plan([insts[pads], insts[pinned]], quick=True)
    planned = {(t[0].name, t[1]) for t in tasks}
    assert (pads, "desaxce-global") in planned and (pads, "newton") not in planned
    assert {(pinned, m) for m in ("newton", "nsgs", "desaxce-fp")} <= planned
    for name in (pads, pinned):
        row = compare.run_task((insts[name], "auto", "high"), repeats=1)
        assert row["success"] and row["family"] == "friction", row
