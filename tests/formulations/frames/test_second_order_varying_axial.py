"""Second-order plane members whose own loads make N vary along them (a
column's self-weight): the element takes N(x) as it is
(formulations/frames/mechanics/varying_axial.py), so an uncut member is ok
and right.  References from other routes: the stability functions'
closed forms (beam_column.py, constant N), Greenhill's heavy column (the
first zero of the Bessel function J_(−1/3), scipy), and the portal with its
columns cut into 32 and 64 constant-N elements (their weight lumped at the
cuts, so no member load has an axial part: the stability functions' route)
extrapolated by Richardson (the cut converges as 1/n²).  And the inertia
count that bisects α_cr (an LDLᵀ's) against the eigenvalues'."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import jv

from formulations.frames import Frame
from formulations.frames.mechanics import beam_column
from formulations.frames.mechanics.second_order_analysis import (critical_load_factor,
                                                                 negative_eigenvalues)
from formulations.frames.mechanics.varying_axial import Member

E, GAMMA = 210e9, 78.5e3
A_C, I_C, A_B, I_B = 149e-4, 25170e-8, 84.5e-4, 23130e-8          # HEB 300, IPE 400
H, SPAN = 6.0, 12.0


def _portal(pieces=1, lumped=False, hinged=False):
    """The sway portal: HEB 300 columns fixed at A and D (hinged at the
    base by a release where ``hinged``), an IPE 400 beam under 30 kN/m,
    20 kN sideways at B, self-weight — as member loads, or with the
    columns cut into ``pieces`` and their weight lumped at the cuts
    (``lumped``: each piece's half at each of its ends)."""
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("D", SPAN, 0.0)
    fr.add_node("B", 0.0, H)
    fr.add_node("C", SPAN, H)
    w = GAMMA * A_C
    for side, x, base, top in (("L", 0.0, "A", "B"), ("R", SPAN, "D", "C")):
        nodes = [base] + [f"{side}{j}" for j in range(1, pieces)] + [top]
        for j in range(1, pieces):
            fr.add_node(nodes[j], x, H * j / pieces)
        for j in range(pieces):
            fr.add_member(nodes[j], nodes[j + 1], E, A_C, I_C, name=f"c{side}{j + 1}",
                          **({"hinge_i": True} if hinged and j == 0 else {}))
            if lumped:
                for node in nodes[j:j + 2]:
                    fr.add_load(node, fy=-0.5 * w * H / pieces, case="D")
            else:
                fr.add_distributed_load(f"c{side}{j + 1}", wy=-w, case="D")
    fr.add_member("B", "C", E, A_B, I_B, name="b")
    fr.add_distributed_load("b", wy=-30e3 - GAMMA * A_B, case="D")
    fr.add_support("A")
    fr.add_support("D")
    fr.add_load("B", fx=20e3, case="D")
    return fr


def _solve(fr, accuracy="high"):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fr.solve(combination={"D": 1.0}, second_order=True, accuracy=accuracy,
                        raise_on_failure=False)


@pytest.fixture(scope="module")
def richardson():
    """M at the base A, at mid-height of the left column and at its top,
    and the sway of B, of the lumped cut portal at 32 and 64 pieces
    extrapolated: (4 f(64) − f(32))/3."""
    out = []
    for n in (32, 64):
        fr = _portal(n, lumped=True)
        res = _solve(fr)
        assert res.ok, res.message
        out.append(np.array([res.diagram("cL1", 2)[3][0], res.diagram(f"cL{n // 2}", 2)[3][-1],
                             res.diagram(f"cL{n}", 2)[3][-1], res.displacements["B"][0]]))
    return (4 * out[1] - out[0]) / 3, out[1]


def test_the_member_under_constant_N_is_the_stability_functions():
    EI, L = E * I_C, H
    parts = [("distributed", 1.0, 4.0, -3e4, 1e4), ("point", 2.5, 5e4, 3e4)]
    ends = np.array([1e-3, 2e-4, -3e-3, 5e-4])
    x = np.linspace(0.0, L, 13)
    for N in (0.0, -1e6, -3e7, -5e7, 2e6, 5e8):      # up to t = 34, and strong tension
        m = Member(EI, L, N, [], [1.0, 2.5, 4.0])
        kb = beam_column.end_block(EI, N, L)
        assert np.abs(m.stiffness() - kb).max() <= 1e-12 * np.abs(kb).max()
        fe = beam_column.nodal_loads(parts, EI, N, L)
        assert np.abs(m.nodal_loads(parts) - fe).max() <= 1e-12 * np.abs(fe).max()
        v, dv, added = m.axis(parts, ends, (None, None), x)
        v_ref, dv_ref = beam_column.deflection(parts, EI, N, L, ends, x)
        assert np.abs(v - v_ref).max() <= 1e-12 * np.abs(v_ref).max()
        assert np.abs(dv - dv_ref).max() <= 1e-12 * np.abs(dv_ref).max()
        # the second-order moment, ∫ N v', is N (v − v(0)) for N constant
        assert np.abs(added - N * (v_ref - v_ref[0])).max() <= 1e-12 * abs(N) * np.abs(v_ref).max()


def test_greenhills_heavy_column_buckles_at_its_bessel_root():
    """A cantilever under its own weight q alone buckles at q L³/EI =
    (9/4) j², j the first zero of J_(−1/3) (7.8373): the element's
    geometric stiffness with N linear along it.  The mean N put it at
    2 (π/2)² = 4.93."""
    j = brentq(lambda z: jv(-1.0 / 3.0, z), 1.0, 2.5)
    EI, L, q = 210e9 * 1e-5, 5.0, 1e3
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    fr.add_member("A", "B", 210e9, 1e-2, 1e-5, name="c")
    fr.add_support("A")
    fr.add_distributed_load("c", wy=-q, case="D")
    res = _solve(fr)
    assert res.ok, res.message
    alpha = critical_load_factor(fr, res)
    assert alpha["limited_by"] is None
    assert alpha["alpha"] * q * L ** 3 / EI == pytest.approx(2.25 * j * j, rel=1e-9)


@pytest.mark.parametrize("accuracy", ["low", "high"])
def test_the_sway_portal_under_its_own_weight_is_ok_uncut(accuracy):
    # it was NOT OK at every accuracy: "the member loads of member(s) cR1,
    # cL1 have axial parts ... add nodes along those members"
    res = _solve(_portal(), accuracy)
    assert res.ok, res.message


def test_the_sway_portal_agrees_with_its_columns_cut_fine(richardson):
    """Its base moment, mid-height and top moments of the column and the
    sway of B against the cut portal's Richardson limit, which 32 and 64
    pieces bracket to 1e-7 of M_A; the mean N put M_A 4.6e-5 off."""
    ref, fine = richardson
    res = _solve(_portal())
    got = np.array([res.diagram("cL1", 3)[3][0], res.diagram("cL1", 3)[3][1],
                    res.diagram("cL1", 3)[3][-1], res.displacements["B"][0]])
    assert abs(fine[0] - ref[0]) > 1e-8 * abs(ref[0])        # the cut is not yet there
    np.testing.assert_allclose(got, ref, rtol=1e-9)


def test_a_hinged_column_under_its_own_weight_has_no_moment_at_its_hinge():
    # the released end's rotation from the element's moment row under N(x)
    res = _solve(_portal(hinged=True))
    assert res.ok, res.message
    x, N, V, M = res.diagram("cL1", 5)
    assert abs(M[0]) <= 1e-9 * np.abs(M).max()
    # N(x) from the statics, linear: the weight of the column above x
    assert N[0] - N[-1] == pytest.approx(-GAMMA * A_C * H, rel=1e-12)
    # the diagram's moment at the top is the member's end moment there
    assert M[-1] == pytest.approx(res.member_forces["cL1"][5], rel=1e-9)


def _tangents():
    """Tangent stiffnesses of frames near and away from their α_cr, and
    one whose base is 1e4 times stiffer than the column on it (the scaled
    case negative_eigenvalues's docstring describes)."""
    out = []
    fr = _portal()
    res = _solve(fr)
    alpha = critical_load_factor(fr, res)["alpha"]
    b = fr.build()
    N = np.array([res.second_order["axial"][m] for m in fr.members])
    for a in (0.5, 0.999, 1.001, 2.0, 3.5):
        K = fr.stiffness(axial=a * alpha * N, along={"D": a * alpha})
        out.append(K[b["free"]][:, b["free"]].toarray())
    stiff = Frame()
    stiff.add_node("A", 0.0, 0.0)
    stiff.add_node("B", 0.0, 1.0)
    stiff.add_node("C", 0.0, 4.0)
    stiff.add_member("A", "B", 2e8 * 1e4, 1e-2, 1e-5, name="base")
    stiff.add_member("B", "C", 2e8, 1e-2, 1e-5, name="col")
    stiff.add_support("A")
    b = stiff.build()
    P = np.pi ** 2 * 2e8 * 1e-5 / (4 * 9.0)
    for share in (0.5, 0.9, 1.1, 3.0):
        K = stiff.stiffness(axial=[-share * P, -share * P])
        out.append(K[b["free"]][:, b["free"]].toarray())
    return out


def test_the_inertia_count_is_the_eigenvalues_count():
    import scipy.linalg as la

    counts = []
    for K in _tangents():
        d = 1.0 / np.sqrt(np.abs(np.diag(K)))
        lam = la.eigvalsh(K * d[:, None] * d[None, :])
        floor = 16 * lam.size * np.finfo(float).eps * np.abs(lam).max()
        counts.append(negative_eigenvalues(K))
        assert counts[-1] == int(np.sum(lam < -floor))
    assert counts[:2] == [0, 0] and min(counts[2:5]) >= 1 and counts[5:7] == [0, 0]


def test_alpha_cr_narrows_on_the_least_eigenvalue_to_the_bisections_alpha(monkeypatch):
    """α_cr's bracket is narrowed on the tangent's least eigenvalue (the
    Illinois rule), then checked and bisected on the inertia counts: the
    sway portal's α_cr is the counts' bisection's to ALPHA_RTOL, from 22
    tangents (the bisection built 42, each rebuilding the members under
    N(x))."""
    from formulations.frames.mechanics import critical_load as so
    from formulations.frames.mechanics.tangent_stiffness import ALPHA_RTOL

    fr = _portal()
    res = _solve(fr)
    built = []
    stiffness = fr.stiffness

    def counted(*args, **kwargs):
        built.append(1)
        return stiffness(*args, **kwargs)
    monkeypatch.setattr(fr, "stiffness", counted)
    alpha = critical_load_factor(fr, res)["alpha"]
    assert len(built) <= 24
    first_negative = so.first_negative
    monkeypatch.setattr(so, "first_negative",
                        lambda negatives, start, pole, least=None:
                        first_negative(negatives, start, pole))
    assert critical_load_factor(fr, res)["alpha"] == pytest.approx(alpha, rel=2 * ALPHA_RTOL)


def _rafter(pieces=1, lumped=False):
    """An inclined member A (0, 0) → B (4, 3), fixed at A and hinged to a
    strut C–B at B, under a global distributed load (parts along and
    across it), a point load at its middle with both parts, and 150 down
    at B: uncut (``pieces`` 1), or cut with the parts along it lumped at
    the cuts (``lumped``: each piece's half at each end; the point load a
    nodal one) and the parts across kept as member loads in member axes —
    the stability functions' route."""
    c, s, L, w = 0.8, 0.6, 5.0, -3.0
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("C", 8.0, 0.0)
    fr.add_node("B", 4.0, 3.0)
    nodes = ["A"] + [f"r{j}" for j in range(1, pieces)] + ["B"]
    for j in range(1, pieces):
        fr.add_node(nodes[j], c * L * j / pieces, s * L * j / pieces)
    for j in range(pieces):
        name = fr.add_member(nodes[j], nodes[j + 1], 2e8, 1e-2, 1e-5, name=f"r{j + 1}",
                             hinge_j=j == pieces - 1)
        if lumped:
            fr.add_distributed_load(name, wy=c * w, axes="member", case="D")
            for node in nodes[j:j + 2]:        # w s along the axis, down the slope
                fr.add_load(node, fx=0.5 * w * s * c * L / pieces,
                            fy=0.5 * w * s * s * L / pieces, case="D")
        else:
            fr.add_distributed_load(name, wy=w, case="D")
    if lumped:
        fr.add_load(nodes[pieces // 2], fx=-20.0, fy=-10.0, case="D")
    else:
        fr.add_point_load("r1", 2.5, fx=-20.0, fy=-10.0, case="D")
    fr.add_member("C", "B", 2e8, 1e-2, 1e-5, name="s")
    fr.add_support("A")
    fr.add_support("C")
    fr.add_load("B", fy=-150.0, fx=1.0, case="D")
    return fr


def test_an_inclined_member_with_loads_along_and_across_it_and_a_hinge():
    """Its statics check closes (the P-Δ couple ∫ N v' and the moment of
    its consistent loads, not of its span loads, where N varies: it failed
    by 1e-5), and its base moment, middle moment and the sway of B are
    the cut member's Richardson limit."""
    res = _solve(_rafter())
    assert res.ok, res.message
    x, N, V, M = res.diagram("r1", 3)
    got = np.array([M[0], M[1], res.displacements["B"][0]])
    assert abs(M[-1]) <= 1e-9 * abs(M[0])                   # the hinge
    out = []
    for n in (32, 64):
        cut = _solve(_rafter(n, lumped=True))
        assert cut.ok, cut.message
        out.append(np.array([cut.diagram("r1", 2)[3][0], cut.diagram(f"r{n // 2}", 2)[3][-1],
                             cut.displacements["B"][0]]))
    ref = (4 * out[1] - out[0]) / 3
    np.testing.assert_allclose(got, ref, rtol=1e-8)


def _swaying_column(weight_case):
    """A cantilever at 0.24 of π²EI/L² (α_cr ≈ 1.04) under a self-weight of
    1e-4 of it in ``weight_case``, pushed sideways by the variable "W"."""
    E_, A_, I_, L_ = 2e8, 1e-2, 1e-5, 5.0
    P_p = np.pi ** 2 * E_ * I_ / L_ ** 2
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L_)
    fr.add_member("A", "B", E_, A_, I_, name="col")
    fr.add_distributed_load("col", 0.0, -1e-4 * P_p / L_, case=weight_case)
    fr.add_support("A")
    fr.add_load("B", fy=-0.24 * P_p, case="D")
    fr.add_load("B", fx=0.01, case="W")
    return fr


def test_a_trace_takes_the_weight_of_its_columns_as_it_varies_along_them():
    """The trace's one stiffness takes N(x) of the load it is built at: the
    sway portal pushed sideways is ok (it was not: "the member loads of
    member(s) cR1, cL1 have axial parts").  Where the variable loads have
    axial parts, N(x)'s change along the path from that load is, as N̄'s,
    the path's change of the axial forces, reported (the column's weight
    1e-4 P_p, traced from 0 to 1 and built at 1: at the path's middle N̄
    and N − N̄ each move by up to 2.5e-5 P_p) and not judged: result_at(p)
    solves at p on its own (it was NOT OK, "up to inf of its moments ...
    add nodes", which no node cured)."""
    fr = _portal()
    fr.add_load("B", fx=20e3, case="W")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ft = fr.trace(3.0, "high", constant={"D": 1.0}, variable={"W": 1.0}, second_order=True)
        assert ft.ok, ft.message
        ok = _swaying_column("D").trace(1.0, "low", constant={"D": 1.0}, variable={"W": 1.0},
                                        second_order=True)
        assert ok.ok, ok.message
        column = _swaying_column("W")
        varying = column.trace(1.0, "high", constant={"D": 1.0}, variable={"W": 1.0},
                               second_order=True)
        assert varying.ok, varying.message
        assert varying.second_order["path_axial_change"] == pytest.approx(5e-5, rel=1e-2)
        for p in (0.5, 1.0):
            at = varying.result_at(p)
            solved = column.solve(combination={"D": 1.0, "W": p}, second_order=True,
                                  accuracy="high")
            assert at.ok and solved.ok
            M = solved.diagram("col", 9)[3]
            assert np.abs(at.diagram("col", 9)[3] - M).max() <= 1e-9 * np.abs(M).max()


@pytest.mark.parametrize("ends", [{"offset_i": 0.2}, {"offset_j": 0.3},
                                  {"offset_i": 0.2, "offset_j": 0.3, "hinge_j": True},
                                  {"spring_i": 500.0, "offset_j": 0.3}])
def test_rigid_end_zones_and_releases_under_n_varying(ends):
    """An inclined member under its weight and a point load along and
    across it, with rigid end zones and releases: the statics check closes
    (each rigid arm's P-Δ, θ ∫ N dx over it, which the couple reads too:
    the arm at B, which turns, on the mean N failed it by 2.5e-6 to
    5.5e-6) and the diagram's moments at the nodes are the member's end
    moments."""
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("C", 8.0, 0.0)
    fr.add_node("B", 4.0, 3.0)
    fr.add_member("A", "B", 2e8, 1e-2, 1e-5, name="r", **ends)
    fr.add_member("C", "B", 2e8, 1e-2, 1e-5, name="s")
    fr.add_support("A")
    fr.add_support("C")
    fr.add_distributed_load("r", wy=-3.0, case="D")
    fr.add_point_load("r", 2.5, fx=-20.0, fy=-10.0, mz=3.0, case="D")
    fr.add_load("B", fy=-150.0, fx=1.0, case="D")
    res = _solve(fr)
    assert res.ok, res.message
    x, N, V, M = res.diagram("r", 11)
    f = res.member_forces["r"]
    assert abs(M[0] + f[2]) <= 1e-9 * np.abs(M).max()
    assert abs(M[-1] - f[5]) <= 1e-9 * np.abs(M).max()


def _pinned_heavy_column_root():
    """q L³/EI at which a column hinged at both ends buckles under its own
    weight alone: EI w'''' + (q (L − x) w')' = 0 with w = w'' = 0 at both
    ends, shot from the base (scipy's DOP853 at 1e-13) — an independent
    route (18.5687)."""
    from scipy.integrate import solve_ivp

    def det(lam):
        ends = []
        for y0 in ([0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]):
            sol = solve_ivp(lambda x, y: [y[1], y[2], y[3], lam * y[1] - lam * (1 - x) * y[2]],
                            (0.0, 1.0), y0, rtol=1e-13, atol=1e-15, method="DOP853")
            ends.append([sol.y[0, -1], sol.y[2, -1]])
        return np.linalg.det(np.array(ends))
    return brentq(det, 15.0, 22.0, xtol=1e-14, rtol=1e-14)


def _hinged_column(share):
    EI, L = 210e9 * 1e-5, 5.0
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    fr.add_member("A", "B", 210e9, 1e-2, 1e-5, name="c", hinge_i=True, hinge_j=True)
    fr.add_support("A", ("ux", "uy"))
    fr.add_support("B", ("ux",))
    fr.add_distributed_load("c", wy=-share * EI / L ** 3, case="D")
    return fr


def test_a_hinged_heavy_column_buckles_on_its_own_where_its_chain_does():
    """Hinged at both ends, its nodes held, it buckles on its own under its
    weight at q L³/EI = 18.5687: α_cr is limited by it to 1e-9 (the largest
    compression's bound alone said π² = 9.87), and a solve at 19 is
    UNSTABLE (the mean N, 9.5 EI/L², is below π²: it was ok)."""
    buckles_on_its_own(_hinged_column)


def buckles_on_its_own(build):
    """The checks of a heavy column hinged at both ends, ``build(share)``
    under ``share`` × its weight (member "c"), plane or space: α_cr limited
    by its own buckling at the ODE shot's root to 1e-9, ok at 0.98 of it,
    UNSTABLE at 19."""
    ref = _pinned_heavy_column_root()
    fr = build(1.0)
    alpha = critical_load_factor(fr, _solve(fr))
    assert alpha["limited_by"] == "c"
    assert alpha["alpha"] == pytest.approx(ref, rel=1e-9)
    assert _solve(build(0.98 * ref)).ok
    res = _solve(build(19.0))
    assert not res.ok and "UNSTABLE" in res.message, res.message


#: Greenhill's heavy cantilever: q L³/EI at which it buckles under its weight
GREENHILL = 7.837347439


def _heavy_cantilever(zone, share, pieces=None):
    """A 5 m cantilever column (EI 2.1e6) under its weight q, ``share`` of
    Greenhill's load over its whole length, 100 N sideways at its top, with
    a rigid zone of 0.625 m at its ``zone`` end ("i": the base, "j": the
    top) that carries its share of the weight: as ``offset_i``/``offset_j``,
    or (``pieces``) its flexible length cut into that many members and the
    zone a member 1e6 times stiffer, all the weight lumped at the nodes
    (constant N in each piece: the stability functions' route; the zone's
    weight lumped at its ends keeps its ∫ N dx)."""
    EI, L, o = 210e9 * 1e-5, 5.0, 0.625
    q = share * GREENHILL * EI / L ** 3
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    if pieces is None:
        fr.add_member("A", "B", 210e9, 1e-2, 1e-5, name="c", **{f"offset_{zone}": o})
        fr.add_distributed_load("c", wy=-q, case="D")
    else:
        a, b = (o, L) if zone == "i" else (0.0, L - o)
        ys = sorted({0.0, L, *(a + (b - a) * np.arange(pieces + 1) / pieces)})
        names = ["A"] + [f"n{k}" for k in range(1, len(ys) - 1)] + ["B"]
        for k, y in enumerate(ys[1:-1], 1):
            fr.add_node(names[k], 0.0, y)
        for k in range(len(ys) - 1):
            rigid = k == (0 if zone == "i" else len(ys) - 2)
            fr.add_member(names[k], names[k + 1], 210e9 * (1e6 if rigid else 1.0), 1e-2, 1e-5,
                          name="c" if k == 0 else f"c{k}")
            for node in names[k:k + 2]:
                fr.add_load(node, fy=-0.5 * q * (ys[k + 1] - ys[k]), case="D")
    fr.add_support("A")
    fr.add_load("B", fx=100.0, case="D")
    return fr, q


def _heavy_cantilever_alpha(zone, q):
    """α at which the column of :func:`_heavy_cantilever` (its weight q)
    buckles, shot on its rotation φ = w' from the clamp: EI φ'' = N φ with
    N = −α q (L − x), the whole column's weight above x (the zone's
    share included); a base zone is a clamp at its face (Greenhill's column
    on the flexible length), a top zone turns with the face and its weight's
    P-Δ, θ ∫ N dx, is the face's moment: EI φ' = α q o²/2 φ there (energy:
    ½ ∫ EI φ'² + ½ ∫ N φ² node to node).  scipy's DOP853 at 1e-13: a route
    apart from the element's series and the frame's α_cr."""
    from scipy.integrate import solve_ivp

    EI, L, o = 210e9 * 1e-5, 5.0, 0.625
    a, b = (o, L) if zone == "i" else (0.0, L - o)

    def end(alpha):
        sol = solve_ivp(lambda x, y: [y[1], -alpha * q * (L - x) * y[0] / EI], (a, b),
                        [0.0, 1.0], rtol=1e-13, atol=1e-15, method="DOP853")
        phi, dphi = sol.y[:, -1]
        return EI * dphi - (alpha * q * o * o / 2 * phi if zone == "j" else 0.0)
    grid = np.linspace(0.2, 3.0, 57)
    k = np.flatnonzero(np.sign([end(g) for g in grid]) != np.sign(end(grid[0])))[0]
    return brentq(end, grid[k - 1], grid[k], xtol=1e-14, rtol=1e-14)


def _measured(fr, res, zone):
    """(M at the base, the top's sway, M at the zone's face): the member's
    diagram there, or the cut's stiff member's end moment."""
    if "n1" not in fr.nodes:
        x, _, _, M = res.diagram("c", 9)
        face = M[np.argmin(np.abs(x - (0.625 if zone == "i" else 4.375)))]
    else:
        stiff = "c" if zone == "i" else f"c{len(fr.members) - 1}"
        face = res.end_forces(stiff)["j" if zone == "i" else "i"]["M"]
    return res.end_forces("c")["i"]["M"], res.displacements["B"][0], face


@pytest.mark.parametrize("zone", ["i", "j"])
def test_a_rigid_end_zone_that_carries_its_share_of_the_weight(zone):
    """The zone's weight reaches the flexible length's N (its mean is not
    the node-to-node one) and the zone's own P-Δ is θ ∫ N dx: the member
    with ``offset_i``/``offset_j`` at 0.7 of Greenhill's load is right at
    "high" and "low" — its base moment, sway and diagram's moment at the
    zone's face against the column cut into 32 and 64 constant-N pieces,
    extrapolated (their own error ~1e-6: the
    zone as a member 1e6 stiffer), α_cr against the shot (on the flexible
    length's own mean: a top zone's M_A 25 % low, −1238.5 for −1649.5, α_cr
    1.6776 for 1.4287; a base zone's α_cr 1.7529 for 2.1324)."""
    fr, q = _heavy_cantilever(zone, 0.7)
    cut = [_measured(f, _solve(f), zone) for f, _ in
           (_heavy_cantilever(zone, 0.7, n) for n in (32, 64))]
    ref = (4 * np.array(cut[1]) - np.array(cut[0])) / 3
    for accuracy, rel in (("high", 2e-6), ("low", 1e-3)):
        res = _solve(fr, accuracy)
        assert res.ok, res.message
        assert np.array(_measured(fr, res, zone)) == pytest.approx(ref, rel=rel)
    assert critical_load_factor(fr, _solve(fr))["alpha"] == pytest.approx(
        _heavy_cantilever_alpha(zone, q), rel=1e-8)


@pytest.mark.parametrize("zone", ["i", "j"])
def test_a_rigid_end_zone_past_the_columns_buckling_is_unstable(zone):
    """At 1.1 × Greenhill's load (over the whole length, the zone's share
    included) the column with a rigid top zone buckles below it (α_cr 0.909,
    the shot's): UNSTABLE, where the flexible length's own mean said ok
    with α_cr 1.068; with a base zone it stands (α_cr 1.357)."""
    fr, q = _heavy_cantilever(zone, 1.1)
    alpha = _heavy_cantilever_alpha(zone, q)
    assert critical_load_factor(fr, _solve(fr))["alpha"] == pytest.approx(alpha, rel=1e-8)
    for accuracy in ("high", "low"):
        res = _solve(fr, accuracy)
        assert res.ok == (alpha > 1), res.message
        assert res.ok or "UNSTABLE" in res.message, res.message
