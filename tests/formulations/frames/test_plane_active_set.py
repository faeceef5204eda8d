"""The frames' sparse active set: the same equilibrium as the
exact LCP route (Lemke) on frictional beams and towers where it is unique
(with friction it need not be: docs/frames.md), in both of its spaces (the
links' own on the condensed R, the sparse saddle system); its mechanical
contact certificate against the LCP's on the same points, and on wrong
points; no answer where a state set leaves a mechanism; and the hand-over
to the LCP when it finds no consistent states."""

from __future__ import annotations

import numpy as np
import pytest

from formulations.frames import Frame
from formulations.frames.mechanics import banded_saddle, contact_lcp
from formulations.frames.mechanics.equilibrium_checks import CLEAR, beyond_rounding
from formulations.frames.mechanics.load_combinations import load_combination
from formulations.frames.plane import plane_recovery
from formulations.frames.plane import sparse_active_set as active_set
from qpcontact.core.errors import NoSolutionError, SolverFailedError
from qpcontact.judge.lcp_certificate import componentwise_error

from .frame_cases import frictional_beam, stub_cantilever, three_bay_tower


def _same(a, b, rtol=1e-9):
    assert {k: s.state for k, s in a.supports.items()} == \
        {k: s.state for k, s in b.supports.items()}
    big = max(abs(s.normal) for s in b.supports.values())
    for k, s in b.supports.items():
        assert abs(a.supports[k].normal - s.normal) <= rtol * big, k
        assert abs(a.supports[k].tangential - s.tangential) <= rtol * big, k


@pytest.mark.parametrize("seed", range(4))
def test_both_spaces_agree_with_lemke(seed, monkeypatch):
    fr = frictional_beam(12, seed)
    ref = fr.solve(method="lemke")
    assert ref.ok, ref.message
    for limit in (0, 10_000):            # the sparse saddle system, the links' space
        monkeypatch.setattr(active_set, "LINK_SPACE_MAX", limit)
        r = fr.solve(method="active-set")
        assert r.ok and r.route.startswith("active set"), r.message
        _same(r, ref)


@pytest.mark.parametrize("seed, friction", [(0, 0.1), (1, 0.1), (2, 0.3), (3, 0.3)])
def test_state_sets_solved_on_the_last_factorization_agree_with_lemke(seed, friction,
                                                                     monkeypatch):
    """A state set that changes few link rows of the last factorized one is
    solved against that LU with the changed rows as a border (fewer sparse
    LUs than one per state set); the states and forces are Lemke's on the
    dense LCP, as with a fresh LU per state set (contacts closing, opening
    and starting to slip among the bordered rows)."""
    monkeypatch.setattr(active_set, "LINK_SPACE_MAX", 0)
    # the saddle matrix's SuperLU route (elastic contacts take the condensed
    # banded LU, which factorizes every state set afresh: tested below)
    monkeypatch.setattr(banded_saddle, "CONDENSE_MAX", 0.0)
    calls = []
    real = active_set.contact_lcp.regular_lu

    def counted(S):
        calls.append(S.shape)
        return real(S)

    monkeypatch.setattr(active_set.contact_lcp, "regular_lu", counted)
    fr = frictional_beam(30, seed, friction=friction)
    ref = fr.solve(method="lemke")
    assert ref.ok, ref.message
    lus, border = {}, active_set.BORDERED_MAX
    for limit in (0, border):                 # a fresh LU per state set; the border
        monkeypatch.setattr(active_set, "BORDERED_MAX", limit)
        calls.clear()
        r = fr.solve(method="active-set")
        assert r.ok and r.route.startswith("active set"), r.message
        _same(r, ref)
        lus[limit] = len(calls)
    assert lus[border] < lus[0], lus


# its 188 m lift is beyond small-displacement theory on purpose (the warning is
# tested in test_plane_features.py)
FAR_LIFT = pytest.mark.filterwarnings("ignore::formulations.frames.LargeDisplacementWarning")


def _far_lifted_beam():
    """frictional_beam(35, 4, f = 0.1): its right part lifts off, its end
    rising 188 m in small-displacement theory about the few contacts that
    still hold it, so the LCP's rows are measured on terms 1e7 times the
    forces (the forward-error estimate on Lemke's answer: no digit, 2e27),
    while the forces are unique."""
    return frictional_beam(35, 4, friction=0.1)


def _largest_force_off(r, ref) -> float:
    big = max(abs(s.normal) for s in ref.supports.values())
    return max(max(abs(r.supports[k].normal - s.normal),
                   abs(r.supports[k].tangential - s.tangential))
               for k, s in ref.supports.items()) / big


@FAR_LIFT
def test_a_certified_answer_whose_forces_are_loose_is_refined_to_the_active_sets(monkeypatch):
    """The answer Lemke gives on this beam, made without Lemke's path (which
    rounding decides: on some machines it ends on a secondary ray): the
    LCP in double solved on the active set's states (z_a = -M_aa^-1 q_a).
    It passes the LCP's certificate by CLEAR (3e-14), so only the
    certificate read in force units (equilibrium_checks.loose_forces) and
    the balance of the forces as reported (reported_balance: a lifted
    pad's 6e-5 kN dropped as "separated" leaves the resultant 6.4e-9 out)
    send it to the refinement; recovered without those, it is ok
    with its forces 7e-7 of the largest off: M, made from R in double,
    carries rounding that the basic system's forces do not (the active
    set's own z misses M's certificate, 1.1e-8), and the free part's 188 m
    magnify it; M_aa is not what is near singular (its condition 5e5, so a
    step along its smallest singular vector breaks the certificate before
    it moves a force).  Through the frame's result-from-z,
    as Lemke's answer goes, its forces are the active set's to 1e-12 (the
    reference: the active set's own states solved on the mechanics)."""
    fr = _far_lifted_beam()
    ref = fr.solve(method="active-set")
    assert ref.ok and ref.route.startswith("active set"), ref.message
    assert max(abs(d[1]) for d in ref.displacements.values()) > 100.0  # its end lifts far
    b = fr.build()
    combo = load_combination(fr, 1.0, None, b)
    z_states, _ = fr.kind.active_set(fr, b, combo)
    M, Q, q_gap, *_ = contact_lcp.lcp_matrices(b)
    lcp = contact_lcp.combination_lcp(M, Q, q_gap, b, combo)
    a = np.flatnonzero(z_states > 0)
    z = np.zeros_like(z_states)
    z[a] = np.linalg.solve(M[np.ix_(a, a)], -lcp.q[a])
    assert z.min() >= 0.0
    assert componentwise_error(lcp, z)[0] <= CLEAR * 1e-9     # certified, with the margin

    def recovered():
        return fr.kind.result_from_z(fr, z, combo, "lemke", b=b, lcp=lcp, tol=1e-9)

    with monkeypatch.context() as m:          # the premise: loose without the refinement
        m.setattr(plane_recovery, "loose_forces", lambda *args: False)
        m.setattr(plane_recovery, "reported_balance", lambda *args: (0.0, ""))
        loose = recovered()
    assert loose.ok and _largest_force_off(loose, ref) > 1e-8, _largest_force_off(loose, ref)
    for trigger in ("loose_forces", "reported_balance"):     # either one refines it
        with monkeypatch.context() as m:
            m.setattr(plane_recovery, trigger, {"loose_forces": lambda *args: False,
                                                "reported_balance": lambda *args: (0.0, "")}
                      [trigger])
            r = recovered()
        assert r.ok, (trigger, r.message)
        _same(r, ref, rtol=1e-12)


@FAR_LIFT
def test_lemke_on_a_beam_lifted_far_has_the_forces_digits_or_proves_nothing():
    """Whether Lemke finds a solution of this LCP depends on rounding (it
    ends on a secondary ray with numpy 2.4.6 / scipy 1.17.1 on one machine,
    finds one on others); either outcome keeps the contract: an ok answer
    has the forces' digits (to tol, the active set's), a failure claims no
    proof (a solution exists)."""
    fr = _far_lifted_beam()
    ref = fr.solve(method="active-set")
    assert ref.ok, ref.message
    try:
        r = fr.solve(method="lemke")
    except NoSolutionError:
        pytest.fail("Lemke's failure read as a proof that no equilibrium exists")
    except SolverFailedError as e:
        assert "nothing was proved" in str(e), str(e)
        return
    assert r.ok and r.route == "lemke", r.message
    _same(r, ref, rtol=1e-9)


def test_tower_states_and_forces_agree_with_lemke_below_tipping():
    fr, _ = three_bay_tower()
    for p in (4.0, 10.0, 14.0):
        r, ref = fr.solve(p, method="active-set"), fr.solve(p, method="lemke")
        assert r.ok and ref.ok
        _same(r, ref)


def _sets(route):
    """The number of state sets in an active-set route's name."""
    assert route.startswith("active set ("), route
    return int(route.split("(")[1].split()[0])


def test_the_towers_state_sets_start_where_lemke_ends_and_answer_as_without_a_start(
        monkeypatch):
    """The link-space state sets start from the closed set that single
    pivots on the contact stiffness choose (friction left out of the
    choice): on the tower, whose lift-off front the state sets moved one or
    two contacts at a time, that is Lemke's closed set, and two state sets
    (one fixing friction, one confirming) answer with Lemke's states and
    forces.  Without the start (no pivots allowed) the state sets run from
    every contact closed, five to seven of them, to the same answer bit for
    bit: the start decides no state."""
    fr, _ = three_bay_tower()
    for p in (10.0, 12.0, 14.0):
        r, ref = fr.solve(p, method="active-set"), fr.solve(p, method="lemke")
        assert r.ok and ref.ok and _sets(r.route) <= 2, r.route
        _same(r, ref)
        with monkeypatch.context() as m:
            m.setattr(active_set, "START_PIVOTS", 0)
            plain = fr.solve(p, method="active-set")
        assert _sets(plain.route) >= 5, plain.route
        assert plain.supports == r.supports and plain.displacements == r.displacements
        assert all(np.array_equal(plain.member_forces[k], v) for k, v in r.member_forces.items())


def test_a_start_that_leaves_a_mechanism_gives_way_to_every_contact_closed(monkeypatch):
    """A start is only a start: where its first state set is singular (every
    contact open: the tower floats) the state sets run again from every
    contact closed, as without one, to the same answer."""
    fr, _ = three_bay_tower()
    with monkeypatch.context() as m:
        m.setattr(active_set, "START_PIVOTS", 0)
        plain = fr.solve(12.0, method="active-set")
    monkeypatch.setattr(active_set, "_held_start",
                        lambda b, RF, ca, required: np.zeros(len(ca["n_link"]), bool))
    r = fr.solve(12.0, method="active-set")
    assert r.route == plain.route and _sets(r.route) >= 5
    assert r.supports == plain.supports and r.displacements == plain.displacements


def test_mechanical_certificate_tracks_the_lcp_one(monkeypatch):
    """The same points judged by the LCP's certificate (R formed) and by the
    mechanical one (R not formed): both at rounding level, and a point made
    wrong by moving one contact's opening is refused by both."""
    monkeypatch.setattr(active_set, "LINK_SPACE_MAX", 0)
    fr = frictional_beam(20, 7)
    b = fr.build()
    combo = load_combination(fr, 1.0, None, b)
    z, _ = active_set.solve_active_set(fr, b, combo)
    mech = plane_recovery.result_from_z(fr, z, combo, "", b=b)
    fr.lcp(b)                                      # forms R: the LCP's certificate from now on
    lcp = plane_recovery.result_from_z(fr, z, combo, "", b=b)
    assert mech.ok and lcp.ok
    assert mech.lcp_error < 1e-12 and lcp.lcp_error < 1e-12
    bad = z.copy()
    k = int(np.argmax(z[:len(fr.contacts)]))       # an open contact, closed by force
    bad[k] = 0.0
    b2 = fr.build()
    wrong_mech = plane_recovery.result_from_z(fr, bad, combo, "", b=b2)
    fr.lcp(b2)
    wrong_lcp = plane_recovery.result_from_z(fr, bad, combo, "", b=b2)
    assert not wrong_mech.ok and not wrong_lcp.ok
    assert wrong_mech.lcp_error > 1e-3 and wrong_lcp.lcp_error > 1e-3


def test_no_consistent_states_hands_over_to_the_lcp(monkeypatch):
    fr = frictional_beam(6, 3)
    ref = fr.solve(method="lemke")
    monkeypatch.setattr(active_set, "MAX_ITERATIONS", 1)    # stops before it settles
    r = fr.solve()
    assert r.ok and not r.route.startswith("active set"), r.route
    _same(r, ref)
    with pytest.raises(SolverFailedError, match="active set found no consistent"):
        fr.solve(method="active-set")


def test_badly_scaled_units_give_the_same_states():
    """The same beam in N and mm as in kN and m: states equal, forces x1000."""
    def beam(force, length):
        fr = Frame(units=("N", "mm") if force == 1e3 else ("kN", "m"))
        for k in range(9):
            fr.add_node(f"N{k}", 3.0 * k * length, 0.0)
        for k in range(8):
            m = fr.add_member(f"N{k}", f"N{k + 1}", 30e6 * force / length ** 2, 0.32 * length ** 2,
                            0.017 * length ** 4)
            fr.add_distributed_load(m, wy=-18.0 * force / length)
        fr.add_support("N0", fix=("ux",))
        for k in range(0, 9, 2):
            fr.add_contact(f"N{k}", friction=0.3 if k else 0.0, stiffness=6e4 * force / length)
        fr.add_load("N3", fy=260.0 * force)
        fr.add_load("N8", fx=-30.0 * force)
        return fr.solve(method="active-set")

    a, b = beam(1.0, 1.0), beam(1e3, 1e3)
    assert a.ok and b.ok, (a.message, b.message)
    assert {k: s.state for k, s in a.supports.items()} == \
        {k: s.state for k, s in b.supports.items()}
    for k, s in a.supports.items():
        assert abs(b.supports[k].normal - 1e3 * s.normal) <= 1e-9 * 1e3 * 300


def _lever(slope):
    """A lever pinned at N0 on turned axes, resting on three contacts with
    gaps, lifted at its tip harder than its load at N1 holds it down: no
    equilibrium exists (it tips over about N2)."""
    fr = Frame()
    for k in range(5):
        fr.add_node(f"N{k}", 2.0 * k * np.cos(slope), 2.0 * k * np.sin(slope))
    for k in range(4):
        fr.add_member(f"N{k}", f"N{k + 1}", 30e6, 0.3, 0.02, hinge_i=(k == 1))
    fr.add_support("N0", fix=("ux", "uy"), angle=25.0)
    fr.add_contact("N2", normal=(0.22, 1), gap=1e-3, stiffness=1e5)
    fr.add_contact("N3", normal=(-0.04, 1), gap=1e-3, stiffness=1e5)
    fr.add_contact("N4", normal=(0.28, 1), friction=0.3, gap=1e-3)
    fr.add_load("N4", fy=32.4, fx=2.05)
    fr.add_load("N1", fy=-10.0)
    return fr


@pytest.mark.parametrize("slope", [0.0, 0.0113, 0.3])
def test_a_mechanism_is_no_answer(slope, monkeypatch):
    """A state set that leaves a mechanism is singular only to rounding when
    the frame is not square to the axes; solved anyway it gave a rigid
    motion of 2.7e11 m with ok=True (a review of the active set).  Both spaces must
    refuse it, and "auto" must end in Lemke's proof."""
    for limit in (0, 10_000):
        monkeypatch.setattr(active_set, "LINK_SPACE_MAX", limit)
        fr = _lever(slope)
        with pytest.raises(SolverFailedError, match="active set found no consistent"):
            fr.solve(method="active-set")
        with pytest.raises(NoSolutionError, match="tips over"):
            fr.solve()


def test_mechanical_certificate_refuses_a_lifted_tip_beside_a_stub():
    """A cantilever ending in a 1 cm stub on a rigid contact, given a point
    with the tip lifted 1 m: the LCP's certificate says 1.0; the mechanical
    one, with a link stiffness bounded by the node's h'|K|h (1e9 times the
    true R_ll beside the stub), said 2.5e-10.  With R_ll it refuses it."""
    fr = stub_cantilever()
    right = fr.solve()
    assert right.ok and right.supports["T"].state == "closed"
    b = fr.build()
    combo = load_combination(fr, 1.0, None, b)
    for lift in (0.01, 1.0):
        r = plane_recovery.result_from_z(fr, np.array([lift]), combo, "wrong", b=b, tol=1e-6)
        assert "R" not in b and not r.ok and r.lcp_error > 0.1, r.message


def test_a_check_counts_what_rounding_leaves_as_nothing_and_nan_as_a_failure():
    """beyond_rounding by hand: with the largest term 1 the floor is
    R_ROUNDING; residuals below it count 0, one of 3 floors on a scale of 2
    counts (3 - 1) floors / 2, a residual above the floor on a zero scale
    is infinite, and a NaN residual is never read as passing."""
    floor = contact_lcp.R_ROUNDING
    scale = np.array([1.0, 2.0, 0.0, 4.0])
    assert beyond_rounding(np.array([0.5, 0.9, 0.0, 1.0]) * floor, scale, 1.0) == 0.0
    assert beyond_rounding(np.array([0.5, 3.0, 0.0, 1.0]) * floor, scale, 1.0) == \
        pytest.approx(floor, rel=1e-12)
    assert beyond_rounding(np.array([0.0, 0.0, 2.0 * floor, 0.0]), scale, 1.0) == np.inf
    worst = beyond_rounding(np.array([np.nan, 0.0, 0.0, 0.0]), scale, 1.0)
    assert not worst <= 1e-9
    # a NaN answer has NaN residuals on NaN scales (|K||u| of a NaN u): never
    # 0, and never a NaN that the checks' max(forces, moments) would drop
    for res, sc, big in (([np.nan], [np.nan], None), ([np.nan, 0.0], [np.nan, 1.0], 1.0),
                         ([0.0, 1.0], [1.0, np.nan], None)):
        worst = beyond_rounding(np.array(res), np.array(sc), big)
        assert worst == np.inf and max(0.0, worst) == np.inf
