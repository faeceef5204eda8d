"""Frames at their verge: where the contact LCP's Farkas vector is exact on
the rounded data but its margin is within their rounding, the load is at
the frame's limit to rounding — never "proved to give way"
(formulations/frames/mechanics/farkas_rounding.py).  The references are
hand statics and the stored doubles read as exact rationals, never the
code under test.

* A three-hinged portal on frictional pads (span L, height h, hinge at
  midspan) stands under any uniform load iff f ≥ L/(4h) (thrust w L²/(8h)
  against f × w L/2 at each foot).  With f the double nearest L/(4h), the
  exact inequality between the stored doubles decides — by 1e-16 of f, far
  inside what the assembled stiffness and loads carry, so the only honest
  answers are "stands" (certified) or "at the limit to rounding".
* A portal on two rigid pads (f = 0.5, h = b = 4) pushed sideways: it
  tips and slides at p = W b/(2h) = f W = 50 exactly; at that load it
  stands (the windward pad's force W/2 − p h/b is 0 and the friction f N
  exactly carries the push), 1e-12 above it no equilibrium exists.
"""

from __future__ import annotations

from fractions import Fraction

import pytest

from qpcontact.core.errors import NoSolutionError, SolverFailedError
from tests.formulations.frames.test_engineer_checks import pushed_portal, three_hinged

pytestmark = pytest.mark.filterwarnings(
    "ignore::formulations.frames.LargeDisplacementWarning")


#: (L, h, w): spans and heights whose f = fl(L/(4h)) "proved to give way"
#: before — the first four stand in exact arithmetic on the stored doubles,
#: the last two fall by the last bit
VERGES = [(7.61, 5.8, 1.7), (11.54, 3.25, 4.1), (3.25, 5.01, 5.1), (5.52, 3.94, 8.8),
          (10.45, 3.64, 5.2), (4.83, 3.05, 6.9)]


def _stands_or_at_the_limit(frame, p):
    """``frame.solve(p=p)`` at a verge: a certified standing answer
    (returned) or "at the limit to rounding" (None) — never a proof."""
    try:
        r = frame.solve(p=p)
    except SolverFailedError as exc:
        assert "limit to rounding" in str(exc), str(exc)
        return None
    except NoSolutionError as exc:       # the failure this guards
        pytest.fail(f"'proved' at the verge: {exc}")
    assert r.ok, r.message
    return r


@pytest.mark.parametrize("L, h, w", VERGES)
def test_a_three_hinged_portal_at_its_verge_is_never_proved_to_give_way(L, h, w):
    f = L / (4 * h)
    stands = Fraction(f) >= Fraction(L) / (4 * Fraction(h))
    assert stands == (VERGES.index((L, h, w)) < 4)       # the reference, in rationals
    fr = three_hinged(f, L, h)
    r = _stands_or_at_the_limit(fr, w)
    if r is not None:
        V, H = w * L / 2, w * L ** 2 / (8 * h)
        assert r.supports["A"].normal == pytest.approx(V, rel=1e-10)
        assert abs(r.supports["A"].tangential) == pytest.approx(H, rel=1e-10)
    tr = fr.trace()
    assert tr.ended != "collapse", tr.message
    assert tr.ok == (tr.ended == "unbounded"), tr.message
    if tr.ended != "unbounded":
        assert "limit to rounding" in tr.message, tr.message


@pytest.mark.parametrize("rel", [1e-12, 1e-9, 1e-6])
def test_a_three_hinged_portal_just_off_its_verge_is_decided(rel):
    """1e-12 of f either side of L/(4h) is beyond the data's rounding: below
    the verge the feet spread at every load (proved, and the trace's limit
    at p = 0), above it the portal stands (the trace unbounded)."""
    L, h, w = 7.61, 5.8, 1.7
    below = three_hinged(L / (4 * h) * (1 - rel), L, h)
    with pytest.raises(NoSolutionError, match="mechanism"):
        below.solve(p=w)
    tr = below.trace()
    assert tr.ok and tr.ended == "collapse" and tr.limit[1] <= 1e-6, tr.message
    above = three_hinged(L / (4 * h) * (1 + rel), L, h)
    assert above.solve(p=w).ok
    tr = above.trace()
    assert tr.ok and tr.ended == "unbounded", tr.message


def test_a_portal_pushed_exactly_to_its_tipping_load_is_not_proved_to_tip():
    """At p = W b/(2h) = f W the portal stands (hand statics: N_A = 0, the
    leeward pad at f N exactly); 1e-12 and 1e-6 above it no equilibrium
    exists (proved), 1e-12 below it stands; the trace's limit brackets the
    hand value to 1e-13."""
    f, h, b, W = 0.5, 4.0, 4.0, 100.0
    ref = W * b / (2 * h)
    assert ref == f * W
    for p in (ref, ref * (1 + 1e-15)):
        r = _stands_or_at_the_limit(pushed_portal(f, h, b, W), p)
        if r is not None:
            assert r.supports["D"].normal == pytest.approx(W, rel=1e-9)
    for rel in (1e-12, 1e-6):
        with pytest.raises(NoSolutionError, match="tips over"):
            pushed_portal(f, h, b, W).solve(p=ref * (1 + rel))
    r = pushed_portal(f, h, b, W).solve(p=ref * (1 - 1e-12))
    assert r.ok and r.supports["A"].normal == pytest.approx(0.0, abs=1e-9 * W), r.message
    tr = pushed_portal(f, h, b, W).trace()
    assert tr.ok and tr.ended == "collapse", tr.message
    assert tr.limit[0] <= ref * (1 + 1e-13) and ref * (1 - 1e-13) <= tr.limit[1], tr.limit


def test_the_loads_at_the_limit_to_rounding_bracket_the_hand_limit():
    """Lemke's Farkas vector at p = 50 exactly (the portal's tipping and
    sliding load by hand) holds exactly on the rounded LCP, but its margin
    is within the rounding bound; the loads at which that vector's margin is
    within its rounding bracket 50 and are a few eps of it wide."""
    from formulations.frames.mechanics import contact_lcp
    from formulations.frames.mechanics.farkas_rounding import (lcp_proof_vector, proof_rounding,
                                                               rounding_bracket)
    from qpcontact import solve

    fr = pushed_portal(0.5, 4.0, 4.0, 100.0)
    b = fr.build()
    M, Q, q_gap, *_ = contact_lcp.lcp_matrices(b)
    combo = {"constant": 1.0, "variable": 50.0}
    sol = solve(contact_lcp.combination_lcp(M, Q, q_gap, b, combo), method="lemke")
    y = lcp_proof_vector(sol)
    assert y is not None          # the rounded LCP has no solution: a proof about it
    r = proof_rounding(b, combo, y)
    assert 0 < r["margin"] < r["bound"] and not r["proves"], r
    lo, hi = rounding_bracket(b, {"constant": 1.0}, {"variable": 1.0}, y)
    assert lo <= 50.0 <= hi and hi - lo < 1e-11 * 50.0, (lo, hi)
    assert proof_rounding(b, {"constant": 1.0, "variable": hi * (1 + 1e-14)}, y)["proves"]


def _table_on_four_pads(W=40.0, h=0.5, a=2.0, f=0.5):
    from formulations.frames import SpaceFrame

    fr = SpaceFrame(cone="circular")
    for k, (x, y) in enumerate([(0.0, 0.0), (a, 0.0), (a, a), (0.0, a)]):
        fr.add_node(f"P{k}", x, y, 0.0)
        fr.add_node(f"T{k}", x, y, h)
        fr.add_member(f"P{k}", f"T{k}", 2e8, 0.01, 1e-4, 1e-4, G=8e7, J=2e-4)
        fr.add_contact(f"P{k}", friction=f)
        fr.add_load(f"T{k}", fz=-W / 4)
        fr.add_load(f"T{k}", fx=0.25, case="variable")
    for k in range(4):
        fr.add_member(f"T{k}", f"T{(k + 1) % 4}", 2e8, 0.01, 1e-4, 1e-4, G=8e7, J=2e-4)
    return fr


def test_a_load_path_proof_above_the_load_asked_proves_nothing_about_it():
    """A table on four pads (circular cone, f 0.5, W 40) slides at p = f W =
    20 by hand.  Asked p = 20 (1 + 1e-12), the circle's solvers certify
    nothing and the load path to it ends in a collapse proved from p =
    20.00000002 up — above the load asked, so no proof of it: the answer is
    not ok (it raised NoSolutionError citing that proof).  Beyond the
    proof's load it is proved; below the limit it stands."""
    assert _table_on_four_pads().solve(19.99).ok
    try:
        res = _table_on_four_pads().solve(20.0 * (1 + 1e-12))
        assert not res.ok, res.message
    except SolverFailedError:
        pass
    with pytest.raises(NoSolutionError, match="slides away"):
        _table_on_four_pads().solve(20.001)
