"""α_cr where a member many orders of magnitude stiffer than the one it
tops leaves the sway mode's eigenvalue near the inertia count's rounding
floor: reported conservatively (the lower end of the band in which the
tangent's least eigenvalue is within rounding of zero), the band stated,
and a second-order answer inside that band not called stable.  Reference:
Greenhill's heavy cantilever with a rigid top zone, by a shot of
EI φ'' = −α q (L − x) φ on the flexible part (φ = v', φ(0) = 0, the zone's
weight and its P-Δ at the top: EI φ'(L₁) = α q o · o/2 · φ(L₁)), written here
with scipy."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from formulations.frames import Frame
from tests.formulations.frames.frame_cases import frictional_beam

E, I, A, L, ZONE = 210e9, 1e-5, 1e-2, 5.0, 0.625
EI = E * I
#: Greenhill's critical weight per length of a 5 m cantilever (its Bessel root)
Q_GREENHILL = 7.837347439 * EI / L ** 3


def shot_alpha(q: float, zone: float = ZONE) -> float:
    """α_cr of the cantilever of length L under its weight q per length,
    its top ``zone`` rigid (same weight), by shooting on the flexible part."""
    L1 = L - zone

    def end(alpha):
        sol = solve_ivp(lambda x, y: [y[1], -alpha * q * (L - x) * y[0] / EI], (0.0, L1),
                        [0.0, 1.0], rtol=1e-12, atol=1e-14)
        phi, dphi = sol.y[0, -1], sol.y[1, -1]
        return EI * dphi - alpha * q * zone * (zone / 2) * phi

    return brentq(end, 0.3, 3.0, xtol=1e-14)


def cantilever(q: float, contrast: float) -> Frame:
    """The column cut at the zone's foot F, the zone a member E × contrast."""
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("F", 0.0, L - ZONE)
    fr.add_node("B", 0.0, L)
    fr.add_member("A", "F", E, A, I, name="column")
    fr.add_member("F", "B", E * contrast, A, I, name="zone")
    fr.add_support("A")
    for m in ("column", "zone"):
        fr.add_distributed_load(m, -q, 0.0, "D", axes="member")
    fr.add_load("B", fx=100.0, case="D")
    return fr


def test_the_shot_is_greenhills_root_without_a_zone():
    """The shot's check: with no zone it is the Bessel root 7.837347439."""
    assert shot_alpha(Q_GREENHILL, zone=0.0) == pytest.approx(1.0, rel=1e-9)


@pytest.mark.parametrize("contrast", [1e2, 1e4, 1e6, 1e8])
def test_a_stiff_zone_member_gives_a_conservative_alpha_and_its_band(contrast):
    """Heavy cantilever at 1.1 of Greenhill's weight (α_cr ≈ 0.909): the
    count's band widens with the contrast (2.5e-6 of α at 1e4, 2.5e-4 at
    1e6, 2.5e-2 at 1e8); α_cr was its upper end (0.9323 at 1e8, 2.5 %
    unconservative) and is now its lower end, and the band holds the shot's
    value."""
    q = 1.1 * Q_GREENHILL
    ref = shot_alpha(q)
    fr = cantilever(q, contrast)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve(combination={"D": 1.0}, second_order=True, raise_on_failure=False)
        crit = fr.critical_load_factor(res)
    lo, hi = crit["bracket"]
    assert crit["alpha"] == lo
    if contrast <= 1e2:
        # a narrow band; the zone 100 times stiffer is not yet rigid (6e-7)
        assert (hi - lo) / hi <= 1e-7
        assert lo == pytest.approx(ref, rel=1e-6)
        return
    assert lo <= ref * (1 + 1e-9) and ref <= hi * (1 + 1e-9), (lo, ref, hi)
    assert lo >= ref * (1 - 0.05)


def test_an_answer_inside_the_band_is_not_called_stable():
    """At 1e-4 below its critical load (truly unstable) with the zone 1e6
    times stiffer, the count beyond rounding found no negative eigenvalue:
    the answer must say its stability is undecided (or unstable), not
    stand as stable."""
    q = 1.1 * Q_GREENHILL
    target = 0.9999
    q_at = q * shot_alpha(q) / target          # α_cr = 0.9999 of this load
    assert shot_alpha(q_at) == pytest.approx(target, rel=1e-9)
    fr = cantilever(q_at, 1e6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve(combination={"D": 1.0}, second_order=True, raise_on_failure=False)
    assert not res.ok
    assert "STABILITY UNDECIDED" in res.message or "UNSTABLE" in res.message, res.message


def _pinned_portal(beam_contrast: float, P: float, leaning: float = 0.0) -> Frame:
    """Pinned feet A, D, columns 4 m (EI = 4 000 kN m²), a beam E × contrast,
    P down on each column top (negative P: pulled up), and optionally a
    leaning column (hinged, its own Euler load at 2.2 × ``leaning``) tied to
    C carrying ``leaning``; a 1 kN push at B."""
    E, A, I, h, Lb = 2e8, 1e-2, 2e-5, 4.0, 6.0
    fr = Frame()
    for n, (x, y) in {"A": (0, 0), "B": (0, h), "C": (Lb, h), "D": (Lb, 0)}.items():
        fr.add_node(n, x, y)
    for i, j, e, name in (("A", "B", E, "C1"), ("D", "C", E, "C2"),
                          ("B", "C", E * beam_contrast, "B1")):
        fr.add_member(i, j, e, A, I, name=name)
    for n in ("A", "D"):
        fr.add_support(n, fix=("ux", "uy"))
    fr.add_load("B", fx=1.0, fy=-P)
    fr.add_load("C", fy=-P)
    if leaning:
        fr.add_node("L0", Lb + 4, 0)
        fr.add_node("L1", Lb + 4, h)
        fr.add_member("L0", "L1", E, A, 2.2 * leaning * h ** 2 / (np.pi ** 2 * E), name="LC",
                      hinge_i=True, hinge_j=True)
        fr.add_member("C", "L1", E, A, 1e-4, name="LB", hinge_i=True, hinge_j=True)
        fr.add_support("L0", fix=("ux", "uy"))
        fr.add_load("L1", fy=-leaning)
    return fr


def test_a_band_below_a_members_own_buckling_is_not_cut_off_by_it():
    """A leaning column whose own Euler load is at α = 2.2 beside a pinned
    portal with a beam 1e9 times stiffer than its columns: the count beyond
    rounding reaches the leaning column's load first, and α_cr was 2.2
    (limited_by the leaning column) while the sway's band starts lower.  By
    hand (rigid beam, inextensible columns): each pinned column held against
    turning at its top buckles at π²EI/(2h)² = 616.85 kN, so the sway's
    α = 2 × 616.85 / (2 × 300 + 3) = 2.0459 — α_cr must not be above it."""
    ref = 2 * np.pi ** 2 * 4000.0 / (2 * 4.0) ** 2 / (2 * 300.0 + 3.0)
    fr = _pinned_portal(1e9, 300.0, leaning=3.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve(second_order=True, raise_on_failure=False)
        crit = fr.critical_load_factor(res)
    lo, hi = crit["bracket"]
    assert crit["alpha"] == lo <= ref * (1 + 1e-3) and ref <= hi
    assert crit["limited_by"] is None


def test_a_stiff_beam_over_columns_in_tension_stays_stable():
    """Columns pulled up (tension lifts the sway's eigenvalue out of the
    rounding band that a beam 1e10 times stiffer puts it in at zero load):
    the answer is stable and ok, α_cr far above 1 — the band at the answer's
    load is not the one α_cr's search ends in."""
    fr = _pinned_portal(1e10, -300.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve(second_order=True, raise_on_failure=False)
        crit = fr.critical_load_factor(res)
    assert res.ok and res.second_order["stable"] is True, res.message
    assert crit["alpha"] > 1e3


def test_critical_load_factor_of_no_equilibrium_says_so():
    """A beam on frictional pads that tips over has no equilibrium to take
    α_cr of: a clear SolverFailedError (before: IndexError from its empty
    displacements)."""
    from qpcontact.core.errors import SolverFailedError

    fr = frictional_beam(2, 0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve(second_order=True, raise_on_failure=False)
    assert not res.ok and "no equilibrium" in res.message
    with pytest.raises(SolverFailedError, match="holds no equilibrium"):
        fr.critical_load_factor(res)


def test_no_compression_still_states_a_band():
    fr = _pinned_portal(1.0, -300.0)
    res = fr.solve(second_order=True)
    crit = fr.critical_load_factor(res)
    if crit["alpha"] == np.inf:
        assert crit["bracket"] == (np.inf, np.inf)
