"""Second-order analysis of frames: equilibrium written on the
deformed frame (P-Δ between the members' ends, P-δ along them), solved
together with the contact states.

The mechanics.  A straight Euler–Bernoulli member (E [F/L²], I [L⁴],
length L [L]) carrying an axial force N [F] (tension positive) has, on its
bending, the equation EI v'''' − N v'' = 0 written on the deformed axis.
Its exact end stiffness (Livesley's stability functions) in member axes,
end dofs (v_i, θ_i, v_j, θ_j), with f = EI/L and t = −N L²/(EI) (t > 0 in
compression, t = ψ² where ψ = L √(P/EI)):

    k_θθ  = s f                         (the far end held)
    k_θθ' = s c f                       (carried over to the far end)
    k_vθ  = (s + s c) f / L
    k_vv  = (2 (s + s c) − t) f / L²    (the − t f/L² = N/L: the P-Δ shear)

    compression (ψ² = t):  s = ψ (sin ψ − ψ cos ψ) / (2 − 2 cos ψ − ψ sin ψ),
                           s c = ψ (ψ − sin ψ) / (2 − 2 cos ψ − ψ sin ψ);
    tension (ψ² = −t):     s = ψ (ψ cosh ψ − sinh ψ) / (2 − 2 cosh ψ + ψ sinh ψ),
                           s c = ψ (sinh ψ − ψ) / (2 − 2 cosh ψ + ψ sinh ψ).

At N = 0 they are 4, 2 and 12: the first-order beam.  Near it the closed
forms cancel (their denominators are ψ⁴/12), so |t| < T_SERIES takes the
Taylor series in t, which is one series for tension and compression
(s = 4 − 2t/15 − 11t²/6300 − …; eight terms, 1e-15 of s at |t| = 0.25).
The consistent geometric matrix (cubic shape functions: −N/L [6/5, L/10,
2L²/15, −L²/30]) is their first-order term; one
element per member with it puts a cantilever's buckling load 0.75 % high,
the stability functions put it at π²EI/(4L²) exactly.  The axial row is
EA/L as before (no bowing): the axial force comes from the axial strain.

Members with shear deformation (Timoshenko: G A_s [F], the shear
parameter φ = 12 EI/(G A_s L²) [-]).  The section turns by θ, the axis
slopes by v', the shear strain is γ = v' − θ and M = EI θ' [F·L].  Under
an axial force the shear force Q [F] that strains the section needs a
direction, and the two classical beam-columns differ only there:
Engesser's takes Q across the deformed *axis* (Q = V − N v', V [F] the
end shear in member axes), Haringx's across the deformed *section*
(Q = V − N θ).  With M' = N v' − V (moments on the deformed axis) and
Q = G A_s γ:

    Engesser:  β EI v'''' − N v'' = 0,  β = 1 + N/(G A_s) = 1 − φ t/12,
               a pinned strut buckles at P_E/(1 + P_E/(G A_s));
    Haringx:   EI v'''' − N (1 − N/(G A_s)) v'' = 0,
               at (√(1 + 4 P_E/(G A_s)) − 1) G A_s/2;

P_E = π²EI/L².  **Engesser's is the one here.**  It is the
shear-flexible and built-up column of Timoshenko & Gere (§2.17) and the
textbooks, and of the design rules for built-up members (EN 1993-1-1,
6.4: 1/N_cr,eff = 1/N_cr + 1/S_v, S_v the shear stiffness G A_s); a
frame program's P-Δ on shear-flexible pieces turns N with each piece's
chord, the axis, so a member cut fine in it converges to Engesser's
(OpenSees' forceBeamColumn on an elastic section with shear under its
PDelta transformation: tests/formulations/frames/
test_timoshenko_beam_column.py).  Haringx's is the
elastomeric bearing's and the helical spring's, whose shear stiffness is
measured across their plates (Kelly, "Shear deformation and the buckling
of columns, revisited", 2017, compares them).  And it reads G A_s as the
first-order element does: the shear it carries is the one across the
member's axis.

Engesser's member is Livesley's with two changes.  Its solution is
v = a + b x + c sin kx + d cos kx with k² L² = μ² = t/β, its section
turns by θ = b + β k (c cos kx − d sin kx), and its rotation stiffness
with both ends on the chord (v_i = v_j = 0) is

    s   = μ (sin μ − β μ cos μ) / (2 − 2 cos μ − β μ sin μ),
    s c = μ (β μ − sin μ) / (2 − 2 cos μ − β μ sin μ)

(hyperbolic in tension, as Livesley's).  A rigid turn of the member
(v = ρ x, θ = ρ) strains nothing, and the end shears follow from moments
about end i, so its 4 × 4 block is laid out from s, s c as the
Euler–Bernoulli one (k_vθ = (s + s c) f/L, k_vv = (2 (s + s c) − t) f/L²,
t and f = EI/L as above).  With Livesley's s₀, s₀c₀ at μ² (their series
near 0), q = 2 (s₀ + s₀c₀) − μ² (= μ³ sin μ/(2 − 2 cos μ − μ sin μ), 12 at
μ = 0) and ε = φ q/12, the same functions are

    s = β (s₀ + ε) / (1 + β ε),   s c = β (s₀c₀ − ε) / (1 + β ε)

— exact algebra (1 − β = φ β μ²/12 cancels the closed forms' μ⁴ against
μ⁴, which is what keeps them accurate near N = 0): at N = 0 they are
(4 + φ)/(1 + φ) and (2 − φ)/(1 + φ), the first-order Timoshenko element's;
at φ = 0 Livesley's.  Their first pole is μ = 2π, a member clamped at both
ends buckling on its own (the antisymmetric mode, tan(μ/2) = β μ/2, comes
later for β ≤ 1): t* = 4π²/(1 + π²φ/3) (:func:`clamped_buckling_t`), below
t = 12/φ where β = 0, and 1 + β ε > 0 below it.  A cantilever (base
clamped, P and H at its free tip) sways H L/P (tan μ/(β μ) − 1), which is
H L³/(3EI) + H L/(G A_s) as P → 0, and buckles at μ = π/2:
P_c/(1 + P_c/(G A_s)), P_c = π²EI/(4L²).

A member's loads are the beam-column's: with N constant along it
(:mod:`.beam_column`, Engesser's with shear deformation: the fixed-end
forces of the stability functions above) — or, where its loads' axial
parts make N vary along it, the beam-column under N(x)
(:mod:`.varying_axial`: its stiffness too).  Along a
trace's one stiffness the change of N(x) from the load it was built at
is, as N̄'s, the path's change of its axial forces, which it reports
(:func:`axial_change`): result_at(p) solves at p on its own.

The matrices are the elements': a plane member's in
:func:`.plane_element.beam_column_k`, a space member's in
:func:`.space_element.stiffness`; this module gives them s and s c
(:func:`stability_functions`, both kinds of member).

Statics.  Each member's end forces satisfy, in its undeformed axes,
Σ moments about end i = N (v_j − v_i) exactly (the column v_i of k sums to
t f / L = P); so the frame's moment resultant is the members' P-Δ
couples, which the recovery's statics check adds (``b["axial"]``).  The
answer is a fixed point: the N that built k are the N its displacements
give, to the accuracy asked for
(:func:`.second_order_analysis.solve_second_order`).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy.optimize import brentq

#: |t| = |N| L² / EI below which the stability functions come from their
#: series (the closed forms' denominators cancel to ψ⁴/12 near 0)
T_SERIES = 0.25

# Taylor coefficients in t (compression positive) of s and s c: one series
# for tension and compression
_S = (4.0, -2 / 15, -11 / 6300, -1 / 27000, -509 / 582120000, -14617 / 681080400000,
      -153221 / 286053768000000, -93589 / 6947020080000000)
_SC = (2.0, 1 / 30, 13 / 12600, 11 / 378000, 907 / 1164240000, 27641 / 1362160800000,
       298183 / 572107536000000, 184697 / 13894040160000000)


def stability_functions(t, phi=0.0) -> tuple[np.ndarray, np.ndarray]:
    """(s, s c) for t = −N L²/EI (arrays) of members with the shear
    parameter ``phi`` (0: Euler–Bernoulli, Livesley's; > 0: Engesser's
    Timoshenko beam-column, module docstring); inf where a compressed
    member is at its own clamped–clamped buckling load
    (:func:`clamped_buckling_t`)."""
    t, phi = np.broadcast_arrays(np.asarray(t, float), np.asarray(phi, float))
    shear = phi > 0
    if not shear.any():
        return livesley(t)
    s, sc = livesley(np.where(shear, 0.0, t))
    t, phi = t[shear], phi[shear]
    beta = 1.0 - phi * t / 12.0
    with np.errstate(divide="ignore", invalid="ignore"):
        mu2 = t / beta
        s0, sc0 = livesley(mu2)
        eps = phi * (2.0 * (s0 + sc0) - mu2) / 12.0
        s[shear] = beta * (s0 + eps) / (1.0 + beta * eps)
        sc[shear] = beta * (sc0 - eps) / (1.0 + beta * eps)
    return s, sc


def livesley(t) -> tuple[np.ndarray, np.ndarray]:
    """Livesley's (s, s c) of Euler–Bernoulli members at t (arrays): the
    series below T_SERIES, the closed forms above."""
    t = np.asarray(t, float)
    s, sc = np.zeros_like(t), np.zeros_like(t)
    small = np.abs(t) < T_SERIES
    ts = t[small]
    s[small] = sum(c * ts ** k for k, c in enumerate(_S))
    sc[small] = sum(c * ts ** k for k, c in enumerate(_SC))
    comp = (t >= T_SERIES)
    if comp.any():
        psi = np.sqrt(t[comp])
        sn, cs = np.sin(psi), np.cos(psi)
        den = 2.0 - 2.0 * cs - psi * sn
        with np.errstate(divide="ignore", invalid="ignore"):
            s[comp] = psi * (sn - psi * cs) / den
            sc[comp] = psi * (psi - sn) / den
    ten = (t <= -T_SERIES)
    if ten.any():
        # the closed forms divided through by cosh ψ: as written they
        # overflow to inf/inf past ψ ≈ 710 (t < −5.04e5: a tie of small EI
        # in tension gave NaN, refused as "the frame at its critical load")
        psi = np.sqrt(-t[ten])
        decay = np.exp(-psi)
        sech, th = 2.0 * decay / (1.0 + decay * decay), np.tanh(psi)
        den = 2.0 * sech - 2.0 + psi * th
        s[ten] = psi * (psi - th) / den
        sc[ten] = psi * (th - psi * sech) / den
    return s, sc


def clamped_buckling_t(phi=0.0) -> float:
    """t at which a member clamped at both ends buckles on its own,
    4π²/(1 + π²φ/3) (4π² without shear deformation): the stability
    functions' pole (μ = 2π), which no load factor may pass."""
    return 4.0 * np.pi ** 2 / (1.0 + np.pi ** 2 * phi / 3.0)


def pdelta_couples(frame, b, u) -> np.ndarray:
    """Each member's P-Δ couple N (v_j − v_i) (m,): the moment its end
    forces make in the undeformed frame, from the axial forces that built
    its stiffness (``b["axial"]``) and the transverse displacements of its
    nodes in its own axes; ``u`` the global displacements.  Node to node,
    rigid end zones included: the flexible part's N (v'_j − v'_i) (v' = v ±
    the arm o times θ) plus each arm's own N o θ, which the assemblies add
    to K(N) (a cantilever with a rigid top zone buckled at its flexible
    part's load without it, 54 % high).  A space frame's (m, 3), global:
    N e_x × (u_j − u_i), e_x the member's axis (the same identity in each
    bending plane)."""
    _, T, dofs, _ = b["local"]
    if dofs.shape[1] == 12:
        xyz = np.asarray(b["coords"], float)
        axis = xyz[dofs[:, 6] // 6] - xyz[dofs[:, 0] // 6]
        axis /= np.linalg.norm(axis, axis=1)[:, None]
        u = np.asarray(u, float)
        du = u[dofs[:, 6:9]] - u[dofs[:, 0:3]]
        return b["axial"][:, None] * np.cross(axis, du)
    d = (T @ np.asarray(u, float)[dofs][..., None])[..., 0]
    return b["axial"] * (d[:, 4] - d[:, 1])


def bending(frame) -> tuple[np.ndarray, np.ndarray]:
    """(EI, L) per member: its weaker bending stiffness and its flexible
    length (a plane member's less its rigid end zones)."""
    EI, L = [], []
    for m in frame.members.values():
        if isinstance(m, dict):          # a space frame's member
            EI.append(m["E"] * min(m["Iy"], m["Iz"]))
            L.append(float(np.linalg.norm(np.subtract(frame.nodes[m["j"]], frame.nodes[m["i"]]))))
        else:
            EI.append(m.E * m.I)
            L.append(float(np.linalg.norm(np.subtract(frame.nodes[m.j], frame.nodes[m.i])))
                     - m.offset_i - m.offset_j)
    return np.array(EI, float), np.array(L, float)


def own_buckling(frame) -> np.ndarray:
    """Each member's own buckling load [F] (a compression, > 0): the least
    one at which it buckles between its nodes with them held, over its
    bending planes t* EI/L² (L its flexible length).  A member rigidly
    joined at both ends has no rotation of its own to lose: t* = 4π², the
    stability functions' pole (clamped–clamped).  Where an end is hinged
    or semi-rigid (a spring k), the member's rotation there is its own,
    condensed behind k: the block of those rotations, EI/L [[s, s c],
    [s c, s]] with k L/EI added on the diagonal, loses its positive
    definiteness at t* < 4π² — π² hinged at both ends (s = s c), 20.19
    (ψ = 4.4934, s = 0) at one; the condensed frame stiffness passes
    through a pole there and its negative eigenvalues no longer count the
    member's buckling (Wittrick–Williams' member term), so the frame's
    count alone calls a buckled strut stable.  With shear deformation (φ)
    the functions are Engesser's and every t* falls with φ: 4π²/(1 +
    π²φ/3) clamped, π²/(1 + π²φ/12) hinged at both ends."""
    return np.array([min(released_buckling_t(
        *(None if k is None else k * L / EI for k in (ki, kj)),
        0.0 if not GAs else 12.0 * EI / (GAs * L ** 2)) * EI / L ** 2
        for EI, ki, kj, GAs in planes) for L, planes in bending_planes(frame)], float)


def pinned_buckling(frame) -> np.ndarray:
    """Each member's buckling load [F] hinged at both ends, the least over
    its bending planes: π²EI/L² (L its flexible length), Engesser's
    P_E/(1 + P_E/(G A_s)) with shear deformation."""
    return np.array([min(np.pi ** 2 * EI / L ** 2 / (1.0 + (np.pi ** 2 * EI / (L ** 2 * GAs)
                                                            if GAs else 0.0))
                         for EI, _, _, GAs in planes) for L, planes in bending_planes(frame)],
                    float)


def bending_planes(frame):
    """Per member (L, [(EI, k_i, k_j, G A_s), …]): its flexible length and
    each bending plane's EI, end springs (None: rigid) and shear stiffness
    (None: none) — a space member's about z (rz, shear along y), then
    about y (ry, along z)."""
    for m in frame.members.values():
        if isinstance(m, dict):
            L = float(np.linalg.norm(np.subtract(frame.nodes[m["j"]], frame.nodes[m["i"]]))
                      - sum(m["offsets"]))
            rel = dict(m["releases"])
            yield L, [(m["E"] * I_, rel.get(r), rel.get(r + 6), GAs)
                      for I_, r, GAs in ((m["Iz"], 5, m["GAs"][0]), (m["Iy"], 4, m["GAs"][1]))]
        else:
            yield (float(np.linalg.norm(np.subtract(frame.nodes[m.j], frame.nodes[m.i]))
                         - m.offset_i - m.offset_j), [(m.E * m.I, *m.end_springs, m.GAs)])


@lru_cache(maxsize=4096)      # a frame's hinged members share one value; solves repeat them
def released_buckling_t(ki, kj, phi) -> float:
    """t* of :func:`own_buckling` for one bending plane: ``ki``, ``kj`` the
    end springs on the scale EI/L (None: a rigid joint), ``phi`` the
    shear parameter; the first t on a grid of (0, t_c), t_c the clamped
    member's (:func:`clamped_buckling_t`, the functions' pole), where the
    released block's least eigenvalue is ≤ 0, then Brent's root between
    the grid points."""
    pole = clamped_buckling_t(phi)
    if ki is None and kj is None:
        return pole

    def least(t):
        t = np.atleast_1d(np.asarray(t, float))
        s, sc = stability_functions(t, phi)
        if ki is None or kj is None:
            return s + (kj if ki is None else ki)
        a, d = s + ki, s + kj
        return 0.5 * (a + d) - np.sqrt(0.25 * (a - d) ** 2 + sc ** 2)

    # the last point a hair below the pole, where s → −∞: a stiff spring's root
    grid = np.r_[np.linspace(0.0, pole, 4001)[1:-1], pole * (1 - 1e-12)]
    below = np.flatnonzero(least(grid) <= 0)
    if not below.size:
        return pole
    lo, hi = (grid[below[0] - 1] if below[0] else 0.0), grid[below[0]]
    return float(brentq(lambda t: least(t)[0], lo, hi, xtol=1e-14, rtol=1e-15))


def past_own_buckling(frame, N, along=None) -> str:
    """Words naming the members that the axial forces ``N`` (those that
    built a second-order stiffness) compress to or past their own buckling
    load (:func:`own_buckling`), or "": a strut hinged at both ends at
    1.5 π²EI/L² has a condensed stiffness with no negative eigenvalue.  A
    member whose loads in ``along`` make N vary along it is judged on its
    own chain (:meth:`.varying_axial.Member.own_negatives`)."""
    from .varying_axial import end_springs, members_under

    varying = members_under(frame, N, along) if along else {}
    springs = [end_springs(m) for m in frame.members.values()]
    names = [f"{m} (N = {n:.6g}, its own buckling at N = {-o:.6g})" if k not in varying
             else f"{m} (N = {n:.6g} on average, varying along it)"
             for k, (m, n, o) in enumerate(zip(frame.members, np.asarray(N, float),
                                               own_buckling(frame)))
             if (varying[k].own_negatives(springs[k]) > 0 if k in varying else -n >= o)]
    return (f"member(s) {', '.join(names)} compressed past their own buckling load between "
            "their nodes") if names else ""


def _axial_load(load, d) -> float:
    """|ΔN| of one member load on a member (node i to j along d; plane or
    space) between its nodes: its force along the axis (a distributed
    one's largest |w| times its stretch, at most; a point force at a node
    none)."""
    length = float(np.linalg.norm(d))
    axis = d / length
    n = axis.size
    v = np.asarray(load.values, float)
    along = [v[0:n]] if load.kind == "point" else [v[0:n], v[n:2 * n]]
    size = max(abs(f[0]) if load.axes == "member" else abs(float(f @ axis)) for f in along)
    if load.kind == "point":
        return size if 0.0 < load.a < length else 0.0
    return size * max(0.0, min(load.b, length) - max(load.a, 0.0))


def _active_loads(frame, combination):
    """(k, load, d) for each member load of ``combination``: the member's
    index, the load and the member's vector node i → j (plane or space)."""
    index = {name: k for k, name in enumerate(frame.members)}
    if hasattr(frame, "span_loads"):                   # a space frame's loads
        pairs = [(ld.member, ld) for ld in frame.span_loads]
    else:
        pairs = [(name, ld) for name, m in frame.members.items() for ld in m.loads]
    for name, ld in pairs:
        if combination.get(ld.case):
            m = frame.members[name]
            i, j = (m["i"], m["j"]) if isinstance(m, dict) else (m.i, m.j)
            yield index[name], ld, np.subtract(frame.nodes[j], frame.nodes[i]).astype(float)


def axial_change(frame, combination, built) -> np.ndarray:
    """Per member, how far N(x) − N̄ of a member whose stiffness took N(x)
    of ``built`` (:mod:`.varying_axial`) is from that of ``combination``,
    at most [F]: half the sum of the axial parts of the loads' change, node
    to node (N − N̄ of loads ΔN in all is within ±ΔN/2)."""
    out = np.zeros(len(frame.members))
    cases = {c: 1.0 for c in set(combination) | set(built or {})}
    for k, ld, d in _active_loads(frame, cases):
        factor = combination.get(ld.case, 0.0) - (built or {}).get(ld.case, 0.0)
        out[k] += 0.5 * abs(factor) * _axial_load(ld, d)
    return out
