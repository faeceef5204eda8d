"""Second order of members with shear deformation (Timoshenko: ``G``,
``shear_area``): Engesser's beam-column, β EI v'''' − N v'' = 0 with
β = 1 + N/(G A_s), one element a member (formulations/frames/mechanics/
second_order.py).  References written here, none from the code under
test: the pinned strut's P_E/(1 + P_E/(G A_s)) and the cantilever's
P_c/(1 + P_c/(G A_s)) (and not Haringx's, (√(1 + 4P_E/(G A_s)) − 1)
G A_s/2); the cantilever's tip sway under H and P by hand, H L/P
(tan μ/(β μ) − 1), itself checked against the three equations (M = EI θ',
M' = N v' − V, V − N v' = G A_s (v' − θ)) integrated in 30-digit
arithmetic; a strut between rotational springs, κ = −μ cot(μ/2); the
stability functions against Livesley's closed forms as φ → 0 and the
first-order Timoshenko element as N → 0; portals' α_cr against a
cut-element eigen analysis written here (each member cut into n
Timoshenko pieces with the chord's geometric stiffness N/h, which converge
to Engesser's as n⁻², extrapolated); OpenSees (forceBeamColumn on an
elastic section with shear, PDelta, cut) where it is installed."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.linalg as la
from scipy.optimize import brentq

from formulations.frames import Frame, SpaceFrame
from formulations.frames.mechanics.plane_element import beam_column_k
from formulations.frames.mechanics.second_order import stability_functions

E, G, A, I = 2e8, 8e7, 1e-2, 2e-5        # kN/m², m², m⁴
L = 5.0


def engesser(P_bending, GAs):
    return P_bending / (1.0 + P_bending / GAs)


def haringx(P_bending, GAs):
    return (np.sqrt(1.0 + 4.0 * P_bending / GAs) - 1.0) * GAs / 2.0


def tip_sway(P, H, GAs, EI=E * I):
    """The cantilever's (base clamped, P and H at its free tip) by hand:
    v = a + b x + c sin kx + d cos kx, V = H = N b, θ(0) = 0 gives
    c = H/(P β k), M(L) = 0 gives d = −c tan kL, so v(L) = b L + c tan kL."""
    beta = 1.0 - P / GAs
    mu = L * np.sqrt(P / (EI * beta))
    return H * L / P * (np.tan(mu) / (beta * mu) - 1.0)


def column(P, H, shear_area, hinge=None, springs=None):
    """A vertical member A (y = 0) to B (y = L): a cantilever (``hinge``
    None and no springs: A clamped, B free) or a strut (A held in ux, uy,
    B in ux; ``hinge`` True: hinged at both ends; ``springs``: both nodes
    also held in rz, the member joined to them by rotational springs)."""
    fr = Frame(units=("kN", "m"))
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    opts = {}
    if hinge:
        opts = {"hinge_i": True, "hinge_j": True}
    elif springs is not None:
        opts = {"spring_i": springs, "spring_j": springs}
    fr.add_member("A", "B", E, A, I, name="col", G=G, shear_area=shear_area, **opts)
    if hinge is None and springs is None:
        fr.add_support("A")
    else:
        fr.add_support("A", fix=("ux", "uy") if hinge else ("ux", "uy", "rz"))
        fr.add_support("B", fix=("ux",) if hinge else ("ux", "rz"))
    fr.add_load("B", fx=H, fy=-P)
    return fr


# φ = 12EI/(G A_s L²): 0.24 (a stocky section's order) and 3 (a deep,
# shear-flexible one)
SHEAR_AREAS = [1e-4, 8e-6]


@pytest.mark.parametrize("As", SHEAR_AREAS)
def test_a_pinned_strut_buckles_at_engessers_load_not_haringxs(As):
    """Hinged at both ends (its end rotations its own, condensed: the
    member's own buckling bounds α_cr) and pinned between nodes free to
    turn (the frame's eigenvalue count sees it): both at P_E/(1 + P_E/(G
    A_s)).  Before, the consistent geometric matrix put them at
    12EI/(L²(1 + φ))-like loads (22 % high at φ → 0) and a strut at 1.1 P
    was ok."""
    GAs, P = G * As, 100.0
    P_E = np.pi ** 2 * E * I / L ** 2
    P_cr = engesser(P_E, GAs)
    assert abs(haringx(P_E, GAs) / P_cr - 1.0) > 0.02       # the choice shows
    hinged = column(P, 0.0, As, hinge=True)
    crit = hinged.critical_load_factor(hinged.solve())
    assert crit["alpha"] * P == pytest.approx(P_cr, rel=1e-9)
    assert crit["limited_by"] == "col"

    def free(load):
        fr = Frame(units=("kN", "m"))
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", 0.0, L)
        fr.add_member("A", "B", E, A, I, name="col", G=G, shear_area=As)
        fr.add_support("A", fix=("ux", "uy"))
        fr.add_support("B", fix=("ux",))
        fr.add_load("B", fy=-load)
        return fr

    crit = free(P).critical_load_factor(free(P).solve())
    assert crit["alpha"] * P == pytest.approx(P_cr, rel=1e-8)
    for share, stable in ((0.95, True), (1.05, False)):
        for fr, why in ((column(share * P_cr, 0.0, As, hinge=True), "col (N = "),
                        (free(share * P_cr), "negative eigenvalue")):
            res = fr.solve(second_order=True)
            assert res.ok is stable and res.second_order["stable"] is stable, res.message
            assert stable or ("UNSTABLE" in res.message and why in res.message), res.message


@pytest.mark.parametrize("As", SHEAR_AREAS)
@pytest.mark.parametrize("share", [0.1, 0.5, 0.9])
def test_a_cantilever_with_shear_sways_and_buckles_as_engessers(As, share):
    """Tip sway H L/P (tan μ/(β μ) − 1) to 1e-9 (the first-order one
    H L³/(3EI) + H L/(G A_s) below it), base moment H L + P δ by statics
    on the deformed column, α_cr = P_c/(1 + P_c/(G A_s))/P; the answer is
    ok (before: not ok, "shear deformation")."""
    GAs = G * As
    P_cr = engesser(np.pi ** 2 * E * I / (4 * L ** 2), GAs)
    P, H = share * P_cr, 10.0
    fr = column(P, H, As)
    first = fr.solve()
    res = fr.solve(second_order=True)
    assert res.ok, res.message
    delta = tip_sway(P, H, GAs)
    assert first.displacements["B"][0] == pytest.approx(
        H * L ** 3 / (3 * E * I) + H * L / GAs, rel=1e-12)
    assert res.displacements["B"][0] == pytest.approx(delta, rel=1e-9)
    assert res.reactions["A"][2] == pytest.approx(H * L + P * delta, rel=1e-9)
    assert fr.critical_load_factor(res)["alpha"] == pytest.approx(1.0 / share, rel=1e-8)


def test_the_cantilevers_closed_form_is_the_three_equations():
    """The hand closed form of :func:`tip_sway` against the Engesser
    member's equations integrated numerically (mpmath's Taylor ODE solver,
    30 digits): v' = (G A_s θ + V)/(G A_s + N) (the shear across the axis,
    V − N v' = G A_s (v' − θ)), θ' = M/EI, M' = N v' − V, from v = θ = 0
    at the base, the base moment shot so that M(L) = 0 (the equations are
    linear in it).  Haringx's (V − N θ = G A_s (v' − θ)) gives another
    sway, so the check tells the two apart."""
    mp = pytest.importorskip("mpmath")
    mp.mp.dps = 30
    GAs, EI, H = G * SHEAR_AREAS[1], E * I, 10.0
    P = 0.6 * engesser(np.pi ** 2 * EI / (4 * L ** 2), GAs)
    N, V = -mp.mpf(P), mp.mpf(H)

    def tip(M0, haringx_shear):
        def rhs(x, y):
            v, th, M = y
            dv = ((GAs * th + V) / (GAs + N) if not haringx_shear
                  else th + (V - N * th) / GAs)
            return [dv, M / EI, N * dv - V]
        sol = mp.odefun(rhs, 0, [mp.mpf(0), mp.mpf(0), mp.mpf(M0)])
        return sol(L)

    for haringx_shear in (False, True):
        a, b = tip(0, haringx_shear), tip(1, haringx_shear)
        M0 = -a[2] / (b[2] - a[2])
        sway = a[0] + M0 * (b[0] - a[0])
        if haringx_shear:
            assert abs(float(sway) / tip_sway(P, H, GAs) - 1.0) > 1e-3
        else:
            assert float(sway) == pytest.approx(tip_sway(P, H, GAs), rel=1e-13)


@pytest.mark.parametrize("kappa", [1.0, 10.0, 1e4])
def test_a_shear_flexible_strut_between_springs_buckles_at_its_closed_form(kappa):
    """Both nodes held, the member joined to them by springs k = κ EI/L:
    its symmetric mode (V = 0, v = a + d cos k(x − L/2), θ = −β k d
    sin k(x − L/2)) meets M = k θ where κ = −μ cot(μ/2), μ in (π, 2π), as
    Livesley's with μ for ψ; then t = μ²/(1 + φ μ²/12)."""
    As = SHEAR_AREAS[0]
    phi = 12 * E * I / (G * As * L ** 2)
    mu = brentq(lambda m: -m / np.tan(m / 2) - kappa, np.pi + 1e-12, 2 * np.pi - 1e-12,
                xtol=1e-15)
    t = mu ** 2 / (1 + phi * mu ** 2 / 12)
    fr = column(100.0, 0.0, As, springs=kappa * E * I / L)
    crit = fr.critical_load_factor(fr.solve())
    assert crit["alpha"] * 100.0 == pytest.approx(t * E * I / L ** 2, rel=1e-9)


def _livesley(t):
    """Livesley's closed forms in 40-digit arithmetic (not the package's)."""
    import mpmath as mp

    mp.mp.dps = 40
    t = mp.mpf(t)
    psi = mp.sqrt(abs(t))
    if t > 0:
        den = 2 - 2 * mp.cos(psi) - psi * mp.sin(psi)
        return (psi * (mp.sin(psi) - psi * mp.cos(psi)) / den,
                psi * (psi - mp.sin(psi)) / den)
    den = 2 - 2 * mp.cosh(psi) + psi * mp.sinh(psi)
    return psi * (psi * mp.cosh(psi) - mp.sinh(psi)) / den, psi * (mp.sinh(psi) - psi) / den


def test_without_shear_deformation_they_are_livesleys():
    """φ → 0 (1e-15, whose own effect is below 1e-13): s, s c of t in
    (−100, 0.99 · 4π²), series and closed-form ranges alike, to 1e-12 of
    max(1, |s|)."""
    pytest.importorskip("mpmath")
    ts = np.r_[np.linspace(-100, -0.3, 20), [-0.2, -1e-3, 1e-3, 0.1, 0.24, 0.26],
               np.linspace(0.3, 0.99 * 4 * np.pi ** 2, 30)]
    s, sc = stability_functions(ts, 1e-15)
    for k, t in enumerate(ts):
        rs, rsc = (float(v) for v in _livesley(t))
        scale = max(1.0, abs(rs))
        assert abs(s[k] - rs) <= 1e-12 * scale and abs(sc[k] - rsc) <= 1e-12 * scale, t


@pytest.mark.parametrize("phi", [1e-6, 0.24, 3.0, 100.0])
def test_without_axial_force_it_is_the_first_order_timoshenko_element(phi):
    """N = 0 and |N| L²/EI = 1e-14 either side: the beam-column's 6 × 6 is
    the first-order Timoshenko element's (12, 6L, (4 + φ)L², (2 − φ)L²
    times EI/(L³ (1 + φ))) to 1e-15 of its largest term."""
    EI = E * I
    As = 12 * EI / (G * phi * L ** 2)
    f = EI / (L ** 3 * (1 + phi))
    b = np.array([[12, 6 * L, -12, 6 * L], [6 * L, (4 + phi) * L ** 2, -6 * L, (2 - phi) * L ** 2],
                  [-12, -6 * L, 12, -6 * L], [6 * L, (2 - phi) * L ** 2, -6 * L, (4 + phi) * L ** 2]])
    ref = np.zeros((6, 6))
    ref[np.ix_([1, 2, 4, 5], [1, 2, 4, 5])] = f * b
    ref[0, 0] = ref[3, 3] = E * A / L
    ref[0, 3] = ref[3, 0] = -E * A / L
    phi_of_As = 12 * EI / (G * As * L ** 2)
    for N in (0.0, 1e-14 * EI / L ** 2, -1e-14 * EI / L ** 2):
        k = beam_column_k(E, A, I, L, N, phi_of_As)
        assert np.abs(k - ref).max() <= 1e-15 * np.abs(ref).max(), N


def cut_alpha(members, supports, loads, n):
    """α_cr of a plane frame (nodes, members (i, j, EI, EA, G A_s), supports
    as fixed dofs, nodal loads) by a cut-element eigen analysis: every
    member cut into n two-node Timoshenko pieces (their exact first-order
    stiffness) with the chord's geometric stiffness N/h on the pieces'
    transverse dofs — a chain of them converges to Engesser's member as
    n⁻² (the Hermite cubic's consistent matrix instead converges to a
    load below it: it adds the shear strain's γ²/5 to the axis's slope) —
    N from a linear solve of the same cut model; the least α with
    det(K + α K_G) = 0."""
    nodes, mem = members
    coords = dict(nodes)
    names = list(coords)
    pieces, points = [], {nm: np.asarray(xy, float) for nm, xy in coords.items()}
    for m, (i, j, EI, EA, GAs) in enumerate(mem):
        chain = [i] + [f"m{m}p{k}" for k in range(1, n)] + [j]
        for k in range(1, n):
            points[chain[k]] = points[i] + (points[j] - points[i]) * k / n
        pieces += [(a, b, EI, EA, GAs) for a, b in zip(chain[:-1], chain[1:])]
    index = {nm: 3 * k for k, nm in enumerate(points)}
    nd = 3 * len(points)

    def local(a, b, EI, EA, GAs, N=None):
        d = points[b] - points[a]
        h = float(np.hypot(*d))
        c, s = d / h
        T = np.zeros((6, 6))
        for o in (0, 3):
            T[o:o + 2, o:o + 2] = [[c, s], [-s, c]]
            T[o + 2, o + 2] = 1.0
        k = np.zeros((6, 6))
        if N is None:
            p = 12 * EI / (GAs * h ** 2)
            f = EI / (h ** 3 * (1 + p))
            blk = f * np.array([[12, 6 * h, -12, 6 * h],
                                [6 * h, (4 + p) * h * h, -6 * h, (2 - p) * h * h],
                                [-12, -6 * h, 12, -6 * h],
                                [6 * h, (2 - p) * h * h, -6 * h, (4 + p) * h * h]])
            k[np.ix_([1, 2, 4, 5], [1, 2, 4, 5])] = blk
            k[0, 0] = k[3, 3] = EA / h
            k[0, 3] = k[3, 0] = -EA / h
        else:
            k[1, 1] = k[4, 4] = N / h
            k[1, 4] = k[4, 1] = -N / h
        dofs = np.r_[index[a] + np.arange(3), index[b] + np.arange(3)]
        return T.T @ k @ T, dofs, T

    K = np.zeros((nd, nd))
    for pc in pieces:
        k, dofs, _ = local(*pc)
        K[np.ix_(dofs, dofs)] += k
    F = np.zeros(nd)
    for nm, fx, fy in loads:
        F[index[nm]:index[nm] + 2] += (fx, fy)
    fixed = np.zeros(nd, bool)
    for nm, dofs in supports:
        for d in dofs:
            fixed[index[nm] + ("ux", "uy", "rz").index(d)] = True
    free = ~fixed
    u = np.zeros(nd)
    u[free] = la.solve(K[np.ix_(free, free)], F[free])
    Kg = np.zeros((nd, nd))
    for a, b, EI, EA, GAs in pieces:
        _, dofs, T = local(a, b, EI, EA, GAs)
        d = T @ u[dofs]
        Kg_, _, _ = local(a, b, EI, EA, GAs, N=EA / np.hypot(*(points[b] - points[a]))
                          * (d[3] - d[0]))
        Kg[np.ix_(dofs, dofs)] += Kg_
    lam = la.eigh(-Kg[np.ix_(free, free)], K[np.ix_(free, free)], eigvals_only=True)
    return 1.0 / lam.max()


def portal(As_columns, As_beam, scale=1.0):
    """A one-bay portal (h = 4, b = 6), fixed bases, shear-flexible columns
    and beam, gravity at the top joints and a push (times ``scale``):
    (Frame, the cut reference's description)."""
    h, b = 4.0, 6.0
    Ic, Ib = 3e-5, 6e-5
    nodes = {"A": (0.0, 0.0), "B": (0.0, h), "C": (b, h), "D": (b, 0.0)}
    mem = [("A", "B", E * Ic, E * A, G * As_columns), ("D", "C", E * Ic, E * A, G * As_columns),
           ("B", "C", E * Ib, E * A, G * As_beam)]
    loads = [("B", 20.0 * scale, -900.0 * scale), ("C", 0.0, -1500.0 * scale)]
    fr = Frame(units=("kN", "m"))
    for nm, (x, y) in nodes.items():
        fr.add_node(nm, x, y)
    for k, (i, j, EI, EA, GAs) in enumerate(mem):
        fr.add_member(i, j, E, A, EI / E, name=f"m{k}", G=G, shear_area=GAs / G)
    fr.add_support("A")
    fr.add_support("D")
    for nm, fx, fy in loads:
        fr.add_load(nm, fx=fx, fy=fy)
    return fr, ((nodes, mem), [("A", ("ux", "uy", "rz")), ("D", ("ux", "uy", "rz"))], loads)


@pytest.mark.parametrize("As_columns, As_beam", [(1e-4, 2e-4), (1e-5, 1e-5)])
def test_a_portal_with_shear_flexible_members_buckles_at_the_cut_analysis(As_columns,
                                                                             As_beam):
    """α_cr against the cut analysis at n = 32 and 64 extrapolated as
    n⁻² (its own error then ≤ 3e-8 of α; at 64/128 ≤ 2e-9): to 1e-7.
    At half that load the second-order answer is ok (before: not ok,
    "shear deformation")."""
    fr, ref = portal(As_columns, As_beam)
    a32, a64 = cut_alpha(*ref, 32), cut_alpha(*ref, 64)
    reference = a64 + (a64 - a32) / 3.0
    crit = fr.critical_load_factor(fr.solve())
    assert crit["alpha"] == pytest.approx(reference, rel=1e-7)
    assert abs(a32 / reference - 1.0) > 1e-5       # the extrapolation matters
    res = portal(As_columns, As_beam, 0.5 * reference)[0].solve(second_order=True)
    assert res.ok and res.second_order["stable"], res.message


def test_a_space_cantilever_with_shear_sways_in_each_plane_by_its_own():
    """A vertical column with A_sy ≠ A_sz and Iy ≠ Iz: the sway along
    global X (local z: bending on Iy, shear on A_sz) and along Y (local y:
    Iz, A_sy) each by tip_sway with that plane's EI and G A_s; α_cr by the
    weaker plane's Engesser load."""
    Iy, Iz, Asy, Asz = 2e-5, 5e-5, 2e-5, 8e-6
    fr = SpaceFrame(units=("kN", "m"))
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 0.0, 0.0, L)
    fr.add_member("A", "B", E, A, Iy, Iz, G=G, J=1e-5, name="col", shear_area=(Asy, Asz))
    fr.add_support("A")
    P_y = engesser(np.pi ** 2 * E * Iz / (4 * L ** 2), G * Asy)
    P_z = engesser(np.pi ** 2 * E * Iy / (4 * L ** 2), G * Asz)
    P = 0.5 * min(P_y, P_z)
    fr.add_load("B", fx=7.0, fy=10.0, fz=-P)
    res = fr.solve(second_order=True)
    assert res.ok, res.message
    assert res.displacements["B"][0] == pytest.approx(tip_sway(P, 7.0, G * Asz, E * Iy),
                                                      rel=1e-9)
    assert res.displacements["B"][1] == pytest.approx(tip_sway(P, 10.0, G * Asy, E * Iz),
                                                      rel=1e-9)
    assert fr.critical_load_factor(res)["alpha"] == pytest.approx(min(P_y, P_z) / P, rel=1e-8)


def test_a_space_strut_hinged_with_shear_buckles_on_its_own():
    """Hinged about both bending axes at both ends: its own buckling, the
    weaker plane's P_E/(1 + P_E/(G A_s)), bounds α_cr (limited_by)."""
    Iy, Iz, Asy, Asz = 2e-5, 5e-5, 8e-6, 1e-4
    fr = SpaceFrame(units=("kN", "m"))
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 0.0, 0.0, L)
    fr.add_member("A", "B", E, A, Iy, Iz, G=G, J=1e-5, name="strut", shear_area=(Asy, Asz),
                  hinge_i=("ry", "rz"), hinge_j=("ry", "rz"))
    fr.add_support("A")
    fr.add_support("B", fix=("ux", "uy", "rx", "ry", "rz"))
    fr.add_load("B", fz=-100.0)
    own = min(engesser(np.pi ** 2 * E * Iz / L ** 2, G * Asy),
              engesser(np.pi ** 2 * E * Iy / L ** 2, G * Asz))
    crit = fr.critical_load_factor(fr.solve())
    assert crit["alpha"] * 100.0 == pytest.approx(own, rel=1e-9)
    assert crit["limited_by"] == "strut"


@pytest.mark.slow
def test_the_cantilevers_sway_is_opensees_cut_fine():
    """OpenSees 3.7: the cantilever cut into 64 forceBeamColumn elements
    on an elastic section with shear (G, α_y = A_s/A) under the PDelta
    transformation (P-Δ of each piece: Engesser's as the cut refines), at
    0.5 of the buckling load: to its cut's error, 5e-5 (16 cuts: 7e-4,
    n⁻²).  (Its ElasticTimoshenkoBeam under PDelta answers the first-order
    sway: it leaves the geometric stiffness out.)"""
    ops = pytest.importorskip("openseespy.opensees")
    As, H = SHEAR_AREAS[0], 10.0
    P = 0.5 * engesser(np.pi ** 2 * E * I / (4 * L ** 2), G * As)
    ours = column(P, H, As).solve(second_order=True)
    n = 64
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for k in range(n + 1):
        ops.node(k, 0.0, L * k / n)
    ops.fix(0, 1, 1, 1)
    ops.geomTransf("PDelta", 1)
    ops.section("Elastic", 1, E, A, I, G, As / A)
    ops.beamIntegration("Lobatto", 1, 1, 3)
    for k in range(n):
        ops.element("forceBeamColumn", k + 1, k, k + 1, 1, 1)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(n, H, -P, 0.0)
    for cmd, args in (("system", ("BandGeneral",)), ("numberer", ("RCM",)),
                      ("constraints", ("Plain",)), ("test", ("NormDispIncr", 1e-12, 100)),
                      ("algorithm", ("Newton",)), ("integrator", ("LoadControl", 0.1)),
                      ("analysis", ("Static",))):
        getattr(ops, cmd)(*args)
    assert ops.analyze(10) == 0
    theirs = ops.nodeDisp(n, 1)
    ops.wipe()
    assert ours.displacements["B"][0] == pytest.approx(tip_sway(P, H, G * As), rel=1e-9)
    assert theirs == pytest.approx(ours.displacements["B"][0], rel=1e-4)
    assert abs(theirs / ours.displacements["B"][0] - 1.0) > 1e-6     # a cut, not the same


@pytest.mark.parametrize("share", [2e-4, 0.5, 0.9])
def test_a_shear_flexible_span_with_loads_is_engessers_beam_column(share):
    """A pinned span (φ = 3) under a uniform load w and a compression at
    ``share`` of its Engesser load P_p = P_E/(1 + P_E/(G A_s)): its loads
    are the beam-column's under N (mechanics.beam_column), so its
    midspan moment is (w EI/P)(sec(kL/2) − 1), k² = P/(β EI) (M'' + k² M
    = w/β from M' = N v' − V, V' = −w and β v'' = M/EI − w/(G A_s)).  Its
    fixed-end forces and diagram were first order (wL²/8), refused at
    2e-4 (2.1e-4 off; ok on the bound over π²EI/L² before)."""
    w, EI = 10.0, E * I
    As = 12 * EI / (G * 3.0 * L ** 2)
    P_E = np.pi ** 2 * EI / L ** 2
    P = share * P_E / (1 + P_E / (G * As))
    beta = 1 - P / (G * As)
    k = np.sqrt(P / (beta * EI))
    exact = w * EI / P * (1 / np.cos(k * L / 2) - 1)
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", L, 0.0)
    fr.add_member("A", "B", E, A, I, name="S", G=G, shear_area=As)
    fr.add_distributed_load("S", wy=-w, case="D")
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_support("B", fix=("uy",))
    fr.add_load("B", fx=-P, case="D")
    res = {acc: fr.solve(combination={"D": 1.0}, second_order=True, raise_on_failure=False,
                         accuracy=acc) for acc in ("low", "high")}
    assert res["low"].ok and res["high"].ok, res["low"].message
    mid = max(abs(res["high"].extremes("S")["M"][e][0]) for e in ("max", "min"))
    assert mid == pytest.approx(exact, rel=1e-9)


@pytest.mark.parametrize("share", [0.9, 0.5, 1e-3, 1e-9, -0.5, -30.0])
def test_a_shear_flexible_members_diagram_between_its_ends_is_engessers(share):
    """Two equal end moments M in single curvature on a pinned member with
    shear deformation under N = −P: Engesser's moment obeys
    M'' = N/(EI (1 + N/(G A_s))) M, so M(x) = M cos(k(x − L/2))/cos(kL/2),
    k² = P/(EI (1 − P/(G A_s))) (cosh in tension), and by statics on the
    deformed axis the deflection is (M(x) − M)/N.  The plane member and a
    space one bent about both axes give it; before, the diagram was the
    first-order M, ok (2.04 M at 0.5 of Engesser's load)."""
    E_, I_, A_, L, M = 2e8, 1e-5, 1e-2, 5.0, 10.0
    P_E = np.pi ** 2 * E_ * I_ / L ** 2
    GAs = 5.0 * P_E
    P = share * P_E / (1.0 + P_E / GAs)
    k2 = P / (E_ * I_ * (1.0 - P / GAs))
    x = np.linspace(0.0, L, 11)
    exact = M * (np.cos(np.sqrt(k2) * (x - L / 2)) / np.cos(np.sqrt(k2) * L / 2) if k2 > 0
                 else np.cosh(np.sqrt(-k2) * (x - L / 2)) / np.cosh(np.sqrt(-k2) * L / 2))
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    fr.add_member("A", "B", E_, A_, I_, name="c", G=GAs / (0.8 * A_), shear_area=0.8 * A_)
    fr.add_support("A", fix=("ux", "uy"))
    fr.add_support("B", fix=("ux",))
    fr.add_load("B", fy=-P, mz=-M)
    fr.add_load("A", mz=M)
    sf = SpaceFrame()
    sf.add_node("A", 0.0, 0.0, 0.0)
    sf.add_node("B", 0.0, 0.0, L)
    sf.add_member("A", "B", E_, A_, I_, I_, G=GAs / (0.8 * A_), J=1e-5, name="c",
                  shear_area=(0.8 * A_, 0.8 * A_))
    sf.add_support("A", fix=("ux", "uy", "uz", "rz"))
    sf.add_support("B", fix=("ux", "uy"))
    sf.add_load("B", fz=-P, my=-M, mx=M)
    sf.add_load("A", my=M, mx=-M)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res, space = fr.solve(second_order=True), sf.solve(second_order=True)
    assert res.ok and space.ok, (res.message, space.message)
    xs, _, _, Mx = res.diagram("c", 11)
    np.testing.assert_allclose(np.abs(Mx), exact, rtol=1e-9)
    _, v = res.deflection("c", 11)[1:]
    np.testing.assert_allclose(np.abs(v), np.abs(exact - M) / abs(P), rtol=1e-7,
                               atol=1e-12 * M / abs(P))
    d = space.diagram("c", 11)
    for My_or_Mz in d[-2:]:
        np.testing.assert_allclose(np.abs(My_or_Mz), exact, rtol=1e-9)


@pytest.mark.parametrize("shift", [0.0, 1e-13, -1e-13, 1e-9, -1e-4, 0.2])
def test_engessers_diagram_of_a_restrained_member_at_kl_pi(shift):
    """A column fixed at A and pinned at B, a moment M_e at B, N = −P with
    kL = π (1 + shift): below its own critical load (kL ≈ 4.49), so the
    answer is regular, but the end moments alone no longer fix the
    sin kx part (the two-point form divides by sin kL).  By hand, from
    M = M_a cos kx + B sin kx, v(L) = v(0) (statics on the deformed axis:
    V_1 = (M_e − M_a)/L) and the fixed end's section rotation
    θ(0) = v'(0) + M'(0)/(G A_s) = 0, v' = (M' − V_1)/N:
    B = (M_e − M_a)/(kL (1 + N/(G A_s))) and
    M_a = M_e (1 − β sin kL)/(cos kL − β sin kL), β = 1/(kL (1 + N/(G A_s))).
    Before, within 1e-12 of π the diagram was 2.1 M_e off, ok."""
    E_, I_, A_, L, Me = 2e8, 1e-5, 1e-2, 5.0, 10.0
    GAs = 5.0 * np.pi ** 2 * E_ * I_ / L ** 2
    Q = (np.pi * (1.0 + shift) / L) ** 2 * E_ * I_       # k² EI (1 − P/GAs) = P
    P = Q / (1.0 + Q / GAs)
    k = np.sqrt(P / (E_ * I_ * (1.0 - P / GAs)))
    beta = 1.0 / (k * L * (1.0 - P / GAs))
    c, s = np.cos(k * L), np.sin(k * L)
    Ma = Me * (1.0 - beta * s) / (c - beta * s)
    B = (Me - Ma) * beta
    x = np.linspace(0.0, L, 11)
    exact = Ma * np.cos(k * x) + B * np.sin(k * x)
    v = (exact - (Ma + (Me - Ma) / L * x)) / -P
    fr = Frame()
    fr.add_node("A", 0.0, 0.0)
    fr.add_node("B", 0.0, L)
    fr.add_member("A", "B", E_, A_, I_, name="c", G=GAs / (0.8 * A_), shear_area=0.8 * A_)
    fr.add_support("A", fix=("ux", "uy", "rz"))
    fr.add_support("B", fix=("ux",))
    fr.add_load("B", fy=-P, mz=Me)
    sf = SpaceFrame()
    sf.add_node("A", 0.0, 0.0, 0.0)
    sf.add_node("B", 0.0, 0.0, L)
    sf.add_member("A", "B", E_, A_, I_, I_, G=GAs / (0.8 * A_), J=1e-5, name="c",
                  shear_area=(0.8 * A_, 0.8 * A_))
    sf.add_support("A", fix=("ux", "uy", "uz", "rx", "ry", "rz"))
    sf.add_support("B", fix=("ux", "uy", "rz"))
    sf.add_load("B", fz=-P, my=Me, mx=Me)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res, space = fr.solve(second_order=True), sf.solve(second_order=True)
    assert res.ok and space.ok, (res.message, space.message)
    Mx = res.diagram("c", 11)[3]
    np.testing.assert_allclose(Mx / Mx[-1], exact / Me, atol=1e-8)
    np.testing.assert_allclose(np.abs(Mx[-1]), Me, rtol=1e-9)
    dv = res.deflection("c", 11)[2]
    np.testing.assert_allclose(np.abs(dv), np.abs(v), rtol=1e-6, atol=1e-9 * Me / P)
    d = space.diagram("c", 11)
    for M_plane in d[-2:]:
        np.testing.assert_allclose(M_plane / M_plane[-1], exact / Me, atol=1e-8)


def _hinged_joined_column(space, kL, pieces, foot="hinge", head=None):
    """A shear-flexible column on a fixed foot A, its end i released
    (``foot``: "hinge" or a rotational spring), joined at its head B
    (``head``: rigidly, None, or by a spring) to beams that restrain B's
    rotation, B held laterally, rigid end zones at both ends; P down and
    moments at B.  ``pieces``: the flexible length cut into that many
    members (the first and last carry the rigid zones and the ends'
    releases)."""
    E_, I_, A_, Lf, oi, oj = 2e8, 1e-5, 1e-2, 5.0, 0.3125, 0.15625
    GAs = 5.0 * np.pi ** 2 * E_ * I_ / Lf ** 2
    Q = (kL / Lf) ** 2 * E_ * I_
    P = Q / (1.0 + Q / GAs)
    L = oi + Lf + oj
    fr = SpaceFrame() if space else Frame()
    at = (lambda h: (0.0, 0.0, h)) if space else (lambda h: (0.0, h))
    fr.add_node("A", *at(0.0))
    names = []
    for k in range(pieces):
        i = "A" if k == 0 else f"n{k}"
        j = "B" if k == pieces - 1 else f"n{k + 1}"
        fr.add_node(j, *at(L if j == "B" else oi + Lf * (k + 1) / pieces))
        kw = dict(name=f"c{k}", offset_i=oi if k == 0 else 0.0,
                  offset_j=oj if k == pieces - 1 else 0.0)
        if k == 0:
            kw.update(hinge_i=True) if foot == "hinge" else kw.update(spring_i=foot)
        if k == pieces - 1 and head is not None:
            kw.update(spring_j=head)
        if space:
            fr.add_member(i, j, E_, A_, I_, I_, G=GAs / (0.8 * A_), J=1e-5,
                          shear_area=(0.8 * A_, 0.8 * A_), **kw)
        else:
            fr.add_member(i, j, E_, A_, I_, G=GAs / (0.8 * A_), shear_area=0.8 * A_, **kw)
        names.append(f"c{k}")
    if space:
        fr.add_node("C", 4.0, 0.0, L)
        fr.add_node("D", 0.0, 3.0, L)
        fr.add_member("B", "C", E_, A_, 3 * I_, 3 * I_, G=8e7, J=1e-5)
        fr.add_member("B", "D", E_, A_, 2 * I_, 2 * I_, G=8e7, J=1e-5)
        fr.add_support("A")
        fr.add_support("C")
        fr.add_support("D")
        fr.add_support("B", fix=("ux", "uy"))
        fr.add_load("B", fz=-P, mx=3.0, my=-2.1)
    else:
        fr.add_node("C", 4.0, L)
        fr.add_member("B", "C", E_, A_, 3 * I_)
        fr.add_support("A")
        fr.add_support("C")
        fr.add_support("B", fix=("ux",))
        fr.add_load("B", fy=-P, mz=3.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve(second_order=True)
    assert res.ok, res.message
    return res, names


@pytest.mark.parametrize("space", [False, True])
@pytest.mark.parametrize("kL", [np.pi - 0.26, np.pi - 0.24, np.pi, np.pi + 0.24, np.pi + 0.26])
@pytest.mark.parametrize("foot, head", [("hinge", None), (2000.0, None), ("hinge", 3000.0)])
def test_engessers_diagram_from_a_joined_end_that_turns(space, kL, foot, head):
    """Near kL = π the diagram starts from the joined end's section
    rotation.  Here that end is the member's end j (its end i is hinged)
    and it turns (B is restrained by beams, not fixed), through rigid end
    zones, in both of a space member's bending planes: the sign of θ and
    the branch that starts from end j are read (a fixed end, θ = 0, reads
    neither: the kL = π test above passes with θ's sign flipped).  Either
    side of |sin kL| = 0.25 (the two forms meet there: no jump).  An end
    joined by a spring starts it too, from θ_node ± M_end/k (before, a
    member with a spring at one end and a hinge at the other was ok at
    kL = π with its diagram 0.38 of max|M| off).  The reference: the same
    column cut into 32 members, each far from kL = π, read at its nodes —
    the whole member's diagram sampled there."""
    one, [m] = _hinged_joined_column(space, kL, 1, foot, head)
    cut, pieces = _hinged_joined_column(space, kL, 32, foot, head)
    # 36 sections of the whole member 0.3125 + 5 + 0.15625 m, every 5/32 m:
    # the cut column's nodes A, n1 … n31 and B are sections 0, 3 … 33, 35
    d = one.diagram(m, 36)
    planes = (-2, -1) if space else (3,)
    for j in planes:
        ref = [cut.diagram(p, 2)[j][0] for p in pieces] + [cut.diagram(pieces[-1], 2)[j][-1]]
        ref = np.array(ref)
        got = d[j][[0] + list(range(3, 34)) + [35]]
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-8 * np.abs(ref).max())


def _spring_footed_column(space, shift, pieces, head):
    """A shear-flexible column on a rotational spring at its foot A (end
    i), its head B (end j: ``head`` "hinge" or a spring) held laterally by
    a settlement of 0.01 and turned by nothing else, under P with
    kL = π (1 + shift) exactly (N statically determinate)."""
    E_, I_, A_, L = 2e8, 1e-5, 1e-2, 5.0
    GAs = 5.0 * np.pi ** 2 * E_ * I_ / L ** 2
    Q = (np.pi * (1.0 + shift) / L) ** 2 * E_ * I_
    P = Q / (1.0 + Q / GAs)
    fr = SpaceFrame() if space else Frame()
    at = (lambda h: (0.0, 0.0, h)) if space else (lambda h: (0.0, h))
    fr.add_node("A", *at(0.0))
    for k in range(pieces):
        i, j = ("A" if k == 0 else f"n{k}"), ("B" if k == pieces - 1 else f"n{k + 1}")
        fr.add_node(j, *at(L * (k + 1) / pieces))
        kw = dict(name=f"c{k}")
        if k == 0:
            kw["spring_i"] = 2000.0
        if k == pieces - 1:
            kw.update(hinge_j=True) if head == "hinge" else kw.update(spring_j=head)
        if space:
            fr.add_member(i, j, E_, A_, I_, I_, G=GAs / (0.8 * A_), J=1e-5,
                          shear_area=(0.8 * A_, 0.8 * A_), **kw)
        else:
            fr.add_member(i, j, E_, A_, I_, G=GAs / (0.8 * A_), shear_area=0.8 * A_, **kw)
    fr.add_support("A")
    if space:
        fr.add_support("B", fix=("ux", "uy", "rx", "ry", "rz"))
        fr.add_settlement("B", ux=0.01, uy=-0.007)
        fr.add_load("B", fz=-P)
    else:
        fr.add_support("B", fix=("ux",) if head == "hinge" else ("ux", "rz"))
        fr.add_settlement("B", ux=0.01)
        fr.add_load("B", fy=-P)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve(second_order=True)
    assert res.ok, res.message
    return res


@pytest.mark.parametrize("space", [False, True])
@pytest.mark.parametrize("head", ["hinge", 3000.0])
@pytest.mark.parametrize("shift", [0.0, 1e-13, -1e-13])
def test_engessers_diagram_at_kl_pi_from_an_end_on_a_spring(space, head, shift):
    """kL = π with no rigidly joined end: a spring at the foot, a hinge or
    a spring at the head.  The spring's end starts the form (θ = θ_node
    + M_a/k at end i).  Before, ok with the diagram 0.38 (hinge) and 0.50
    (spring) of max|M| off.  The reference: the column cut into 32."""
    one = _spring_footed_column(space, shift, 1, head)
    cut = _spring_footed_column(space, shift, 32, head)
    d = one.diagram("c0", 33)
    planes = (-2, -1) if space else (3,)
    for j in planes:
        ref = np.array([cut.diagram(f"c{k}", 2)[j][0] for k in range(32)]
                       + [cut.diagram("c31", 2)[j][-1]])
        np.testing.assert_allclose(d[j], ref, rtol=0, atol=1e-8 * np.abs(ref).max())
