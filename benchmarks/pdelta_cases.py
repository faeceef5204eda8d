"""The cases of benchmarks/frame_pdelta_census.py as plain models
(:mod:`pdelta_references`): named hand cases with closed forms, portals
with a leaning column and without span loads, random plane frames
(seeded), the 20-storey tower of examples/tower_second_order.py on fixed
bases, and space frames (a plane frame built in 3-D; members loaded about
both axes).  Loads are scaled to a share of α_cr computed by the cut
model of :mod:`pdelta_references`, not by qpcontact.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np

from pdelta_references import (E, G, axes, cantilever, clamped_udl, end_moments, geometry,
                               linear_axial, member, model, pinned_midpoint, pinned_udl,
                               reference_alpha, shear_cantilever, shear_pinned)


# -- the cases --------------------------------------------------------------------------

A0, I0, L0 = 1e-2, 1e-5, 5.0
EI0 = E * I0
P_E = float(mp.pi ** 2 * EI0 / L0 ** 2)


def span(name, fixed_b, N, udl=None, point=None, mz=(0.0, 0.0)):
    """A 5 m span A→B along x: pinned (A ux uy, B uy) or clamped (rz held at
    both), the axial force N (tension positive) applied at B."""
    nodes = {"A": (0.0, 0.0), "B": (L0, 0.0)}
    fixed = {"A": (0, 1) + ((2,) if fixed_b else ()), "B": (1,) + ((2,) if fixed_b else ())}
    return model(name, "hand", nodes, [member("S", "A", "B", A0, I0)], fixed,
                 {"A": (0.0, 0.0, mz[0]), "B": (N, 0.0, mz[1])},
                 udl=[("S", 0.0, udl)] if udl else (),
                 point=[("S", L0 / 2, 0.0, point)] if point else ())


def sampled(M, v):
    """qpcontact's v extremes are the best of 201 sections (documented): a
    sampled peak misses by up to |v''| h²/8, h = L/200, v'' = M/EI — relative
    to v."""
    return float(abs(M) / EI0 * (L0 / 200) ** 2 / 8 / abs(v))


def hand_cases():
    out = []
    w, Q, M0, H = -10.0, -20.0, 10.0, 5.0
    for s, sign in ((0.1, -1), (0.5, -1), (0.95, -1), (0.5, 1)):
        N = sign * s * P_E
        tag = f"{'C' if N < 0 else 'T'}{s:g}P_e"
        alpha = 1 / s if N < 0 else np.inf
        # pinned, uniform w
        r = pinned_udl(w, N, EI0, L0)
        c = span(f"pinned udl {tag}", False, N, udl=w)
        sc_M = abs(r["M_mid"])
        c["closed"] = [("M_mid", "ext", ("S", "M_max"), r["M_mid"], sc_M),
                       ("theta_A", "disp", ("A", 2), r["theta_i"], abs(r["theta_i"])),
                       ("v_mid", "ext", ("S", "v_min"), r["v_mid"], abs(r["v_mid"]),
                        sampled(sc_M, r["v_mid"])),
                       ("V_A", "end", ("S", 1), -w * L0 / 2, sc_M / L0),
                       ("alpha", "alpha", None, alpha, alpha if np.isfinite(alpha) else 1)]
        out.append(c)
        # clamped, uniform w: s of its own buckling load 4 P_e
        r = clamped_udl(w, 4 * N, EI0, L0)
        c = span(f"clamped udl {tag.replace('P_e', '·4P_e')}", True, 4 * N, udl=w)
        sc_M = max(abs(r["M_end"]), abs(r["M_mid"]))
        c["closed"] = [("M_i", "end", ("S", 2), -r["M_end"], sc_M),
                       ("M_j", "end", ("S", 5), r["M_end"], sc_M),
                       ("M_mid", "ext", ("S", "M_max"), r["M_mid"], sc_M),
                       ("alpha", "alpha", None, alpha, alpha if np.isfinite(alpha) else 1)]
        out.append(c)
        # pinned, midspan force
        r = pinned_midpoint(Q, N, EI0, L0)
        c = span(f"pinned midpoint force {tag}", False, N, point=Q)
        sc_M = abs(r["M_mid"])
        c["closed"] = [("M_mid", "ext", ("S", "M_max"), r["M_mid"], sc_M),
                       ("theta_A", "disp", ("A", 2), r["theta_i"], abs(r["theta_i"])),
                       ("v_mid", "ext", ("S", "v_min"), r["v_mid"], abs(r["v_mid"]),
                        sampled(sc_M, r["v_mid"]))]
        out.append(c)
        # end moments: equal single curvature, unequal single and double curvature
        for label, ma, mb in (("equal end moments", M0, M0),
                              ("end moments 1 : 0.5", M0, 0.5 * M0),
                              ("end moments 1 : -0.5", M0, -0.5 * M0)):
            r = end_moments(ma, mb, N, EI0, L0)
            c = span(f"{label} {tag}", False, N, mz=(-ma, mb))
            sc_M = max(abs(r["M_max"]), abs(r["M_min"]))
            c["closed"] = [("M_max", "ext", ("S", "M_max"), r["M_max"], sc_M),
                           ("M_min", "ext", ("S", "M_min"), r["M_min"], sc_M),
                           ("theta_A", "disp", ("A", 2), r["theta_i"], abs(r["theta_i"])),
                           ("theta_B", "disp", ("B", 2), r["theta_j"], abs(r["theta_i"])),
                           ("M_i", "end", ("S", 2), -ma, sc_M),
                           ("v extreme", "ext", ("S", "v_min" if r["v_ext"] < 0 else "v_max"),
                            r["v_ext"], abs(r["v_ext"]), sampled(sc_M, r["v_ext"]))]
            out.append(c)
        # cantilever column with a tip force and a uniform load across: s of π²EI/(4L²)
        Nc = N / 4
        r = cantilever(H, 2.0, Nc, EI0, L0)
        nodes = {"A": (0.0, 0.0), "B": (0.0, L0)}
        c = model(f"cantilever H + w {tag.replace('P_e', '·P_e/4')}", "hand", nodes,
                  [member("C", "A", "B", A0, I0)], {"A": (0, 1, 2)}, {"B": (H, Nc, 0.0)},
                  udl=[("C", 0.0, -2.0)])          # local y of a member up +y is global −x
        c["closed"] = [("tip sway", "disp", ("B", 0), r["delta"], abs(r["delta"])),
                       ("tip rotation", "disp", ("B", 2), -r["theta_tip"], abs(r["theta_tip"])),
                       ("M_base", "end", ("C", 2), r["M_base"], abs(r["M_base"])),
                       ("alpha", "alpha", None, alpha, alpha if np.isfinite(alpha) else 1)]
        out.append(c)
        # the same column without its span load: a tip force only (its tip moment is 0)
        r = cantilever(H, 0.0, Nc, EI0, L0)
        c = model(f"cantilever H only {tag.replace('P_e', '·P_e/4')}", "hand", nodes,
                  [member("C", "A", "B", A0, I0)], {"A": (0, 1, 2)}, {"B": (H, Nc, 0.0)})
        c["closed"] = [("tip sway", "disp", ("B", 0), r["delta"], abs(r["delta"])),
                       ("tip rotation", "disp", ("B", 2), -r["theta_tip"], abs(r["theta_tip"])),
                       ("M_base", "end", ("C", 2), r["M_base"], abs(r["M_base"])),
                       ("M_base (diagram)", "ext", ("C", "M_min"), -r["M_base"], abs(r["M_base"])),
                       ("M_tip (diagram) = 0", "ext", ("C", "M_max"), 0.0, abs(r["M_base"])),
                       ("alpha", "alpha", None, alpha, alpha if np.isfinite(alpha) else 1)]
        out.append(c)
    return out


def shear_cases():
    """Members with shear deformation (GA_s = 4000 kN, P_e/GA_s = 0.2),
    Engesser's closed forms: a pinned span under w, a midspan force, equal
    end moments; a cantilever with a tip force; at 0.5 of Engesser's
    buckling load P/(1 + P/GA_s) in compression and 0.5 P_e in tension."""
    As = 5e-5
    GAs = G * As
    out = []
    for share, sign in ((0.5, -1), (0.9, -1), (0.5, 1)):
        tag = f"{'C' if sign < 0 else 'T'}{share:g}"
        Pcr = P_E / (1 + P_E / GAs)
        N = sign * share * (Pcr if sign < 0 else P_E)
        alpha = 1 / share if sign < 0 else np.inf
        for label, w, Q, Me in (("udl", -10.0, 0.0, 0.0), ("midpoint force", 0.0, -20.0, 0.0),
                                ("equal end moments", 0.0, 0.0, 10.0)):
            c = span(f"shear: pinned {label} {tag}·P_cr", False, N, udl=w or None,
                     point=Q or None, mz=(-Me, Me))
            c["members"][0]["As"] = As
            c["family"] = "hand, shear"
            M = shear_pinned(w, Q, Me, N, EI0, GAs, L0)
            # equal end moments in tension: M sech u at midspan is the least
            # (the ends' M the largest), in compression M sec u the largest
            peak = "M_min" if Me and sign > 0 else "M_max"
            c["closed"] = [("M_mid", "ext", ("S", peak), M, abs(M)),
                           ("alpha", "alpha", None, alpha, alpha if np.isfinite(alpha) else 1)]
            out.append(c)
        Pc = P_E / 4 / (1 + P_E / 4 / GAs)                   # the cantilever's, with shear
        Nc = sign * share * (Pc if sign < 0 else P_E / 4)
        base, delta = shear_cantilever(5.0, Nc, EI0, GAs, L0)
        c = model(f"shear: cantilever H only {tag}·P_cr", "hand, shear",
                  {"A": (0.0, 0.0), "B": (0.0, L0)}, [member("C", "A", "B", A0, I0, As=As)],
                  {"A": (0, 1, 2)}, {"B": (5.0, Nc, 0.0)})
        c["closed"] = [("tip sway", "disp", ("B", 0), delta, abs(delta)),
                       ("M_base", "end", ("C", 2), base, abs(base)),
                       ("M_base (diagram)", "ext", ("C", "M_min"), -base, abs(base)),
                       ("M_tip (diagram) = 0", "ext", ("C", "M_max"), 0.0, abs(base)),
                       ("alpha", "alpha", None, alpha, alpha if np.isfinite(alpha) else 1)]
        out.append(c)
    return out


def sway_portal(share):
    """Two fixed-base columns (4 m) under P at their tops, a beam 1e8 times
    stiffer, a side force (benchmarks/frames_second_order.py's portal): no
    span loads; scaled to ``share`` of α_cr."""
    nodes = {"A": (0.0, 0.0), "B": (0.0, 4.0), "C": (6.0, 4.0), "D": (6.0, 0.0)}
    members = [member("C1", "A", "B", 1e2, 2e-5), member("C2", "D", "C", 1e2, 2e-5),
               member("B1", "B", "C", 1e2, 2e3)]
    m = model("sway portal, no span loads", "portal", nodes, members,
              {"A": (0, 1, 2), "D": (0, 1, 2)}, {"B": (4.0, -100.0, 0.0), "C": (0.0, -100.0, 0.0)})
    return scaled(m, share)


def portal_leaning(share=0.5):
    """A fixed-base portal (6 m × 4 m) with a uniform load on its beam and a
    side load, a leaning column beside it tied by a hinged link; the loads
    scaled to ``share`` of α_cr's reference (first order)."""
    nodes = {"A": (0.0, 0.0), "B": (0.0, 4.0), "C": (6.0, 4.0), "D": (6.0, 0.0),
             "L0": (10.0, 0.0), "L1": (10.0, 4.0)}
    members = [member("C1", "A", "B", 8e-3, 8e-5), member("C2", "D", "C", 8e-3, 8e-5),
               member("B1", "B", "C", 8e-3, 2e-4),
               member("LC", "L0", "L1", 8e-3, 3e-5, True, True),
               member("LB", "C", "L1", 8e-3, 1e-4, True, True)]
    m = model("portal + leaning column", "portal", nodes, members,
              {"A": (0, 1, 2), "D": (0, 1, 2), "L0": (0, 1)},
              {"B": (10.0, -300.0, 0.0), "C": (0.0, -300.0, 0.0), "L1": (0.0, -600.0, 0.0)},
              udl=[("B1", 0.0, -20.0), ("C1", 0.0, -4.0)])
    return scaled(m, share)


def scaled(m, share):
    """The model with every load times f, α_cr(f·loads) = 1/share on the
    first-order axial forces of the cut model (written here)."""
    axial = linear_axial(m)
    if not any(v < 0 for v in axial.values()):
        return m
    f = share * reference_alpha(m, axial)[0]
    m = dict(m)
    m["loads"] = {n: tuple(f * v for v in vals) for n, vals in m["loads"].items()}
    m["udl"] = [(nm, *(f * v for v in w)) for nm, *w in m["udl"]]
    m["point"] = [(nm, a, *(f * v for v in p)) for nm, a, *p in m["point"]]
    m["name"] += f" at {share:g}/α_cr"
    return m


def lumped(m):
    """The model with its span loads moved to the joints (a uniform w's wL/2
    at each end, no fixed-end moments): a frame with nodal loads only."""
    loads = {n: np.array(f, float) for n, f in m["loads"].items()}
    for nm, wx, wy in m["udl"]:
        mem = next(x for x in m["members"] if x["name"] == nm)
        p, q, L = geometry(m, mem)
        R = axes(m, mem)
        f = R.T @ np.array([wx, wy, 0.0]) * L / 2
        for n in (mem["i"], mem["j"]):
            loads[n] = loads.get(n, np.zeros(3)) + f
    out = dict(m, loads={n: tuple(f) for n, f in loads.items()}, udl=[], point=[])
    out["name"] = m["name"] + ", lumped"
    out["family"] = m["family"] + " (nodal loads)"
    return out


def on_pads(m):
    """The frame with each base standing on a rigid frictionless pad (a
    contact along y) instead of its vertical support: the answer goes
    through the contact LCP; OpenSees holds the pads, so it is the reference
    only where every pad stays closed (the census checks qpcontact's states)."""
    fixed = {n: tuple(d for d in ds if d != 1) if n.endswith("_0") else ds
             for n, ds in m["fixed"].items()}
    out = dict(m, fixed={n: ds for n, ds in fixed.items() if ds},
               pads=[n for n in m["fixed"] if n.endswith("_0")])
    out["name"] = m["name"] + ", on pads"
    out["family"] = m["family"] + " (on pads)"
    return out


def random_frame(seed, max_storeys=3, max_bays=2):
    """1..bays bays of 3–8 m, 1..storeys storeys of 2.8–4.5 m, fixed or
    pinned bases, random sections; a uniform load on every beam, a wind
    load across the windward columns, gravity at the joints; a third with a
    leaning column; then every load scaled to 0.1–0.95 of α_cr, and in a
    quarter of them the joints' vertical loads turned upward (the columns in
    tension)."""
    rng = np.random.default_rng(1000 + seed)
    bays, storeys = int(rng.integers(1, max_bays + 1)), int(rng.integers(1, max_storeys + 1))
    xs = np.r_[0, np.cumsum(rng.uniform(3, 8, bays))]
    ys = np.r_[0, np.cumsum(rng.uniform(2.8, 4.5, storeys))]
    nodes = {f"N{c}_{r}": (xs[c], ys[r]) for c in range(bays + 1) for r in range(storeys + 1)}
    base = rng.choice(["fixed", "pinned"])
    fixed = {f"N{c}_0": (0, 1, 2) if base == "fixed" else (0, 1) for c in range(bays + 1)}
    members, udl, loads = [], [], {}
    tension = rng.random() < 0.25
    up = 1.0 if tension else -1.0
    for r in range(storeys):
        for c in range(bays + 1):
            members.append(member(f"C{c}_{r}", f"N{c}_{r}", f"N{c}_{r + 1}",
                                  rng.uniform(5e-3, 2e-2), rng.uniform(1e-5, 2e-4)))
        udl.append((f"C0_{r}", 0.0, -rng.uniform(1, 6)))     # wind on the windward column, +x
    for r in range(1, storeys + 1):
        for c in range(bays):
            members.append(member(f"B{c}_{r}", f"N{c}_{r}", f"N{c + 1}_{r}",
                                  rng.uniform(5e-3, 2e-2), rng.uniform(2e-5, 5e-4)))
            udl.append((f"B{c}_{r}", 0.0, -rng.uniform(5, 40)))
        for c in range(bays + 1):
            loads[f"N{c}_{r}"] = (0.0, up * rng.uniform(50, 800), 0.0)
        loads[f"N0_{r}"] = (rng.uniform(1, 20), loads[f"N0_{r}"][1], 0.0)
    if rng.random() < 0.3:
        for r in range(storeys + 1):
            nodes[f"L{r}"] = (xs[-1] + 4.0, ys[r])
        fixed["L0"] = (0, 1)
        for r in range(storeys):
            members.append(member(f"LC{r}", f"L{r}", f"L{r + 1}", 1e-2, 3e-5, True, True))
        for r in range(1, storeys + 1):
            members.append(member(f"LB{r}", f"N{bays}_{r}", f"L{r}", 1e-2, 1e-4, True, True))
            loads[f"L{r}"] = (0.0, up * rng.uniform(100, 1500), 0.0)
    share = float(rng.uniform(0.1, 0.95))
    m = model(f"random {seed}: {bays}×{storeys} {base}" + (" +leaning" if "L0" in nodes else "")
              + (" tension" if tension else ""), "random", nodes, members, fixed, loads, udl=udl)
    if tension:
        # the gravity turned upward: the level is the compressed version's
        down = dict(m, loads={n: (f[0], -f[1], f[2]) for n, f in loads.items()})
        f = share * reference_alpha(down, linear_axial(down))[0]
        m["loads"] = {n: tuple(f * v for v in vals) for n, vals in m["loads"].items()}
        m["udl"] = [(nm, *(f * v for v in w)) for nm, *w in m["udl"]]
        m["name"] += f" (scaled as {share:.2f}/α_cr down)"
        return m
    return scaled(m, share)


def tower(storeys=20, bays=3, p=1.0):
    """docs' 20-storey tower (examples/tower_second_order.py) on fixed bases
    instead of its foundation beam on pads: columns 210e6, 1.5e-2, 5e-4,
    beams 210e6, 8e-3, 2e-4 with 30 kN/m, 10 p kN at every floor of the left
    column."""
    nodes = {f"N{s}_{j}": (6.0 * j, 3.5 * s) for s in range(storeys + 1) for j in range(bays + 1)}
    members, udl = [], []
    for s in range(storeys):
        for j in range(bays + 1):
            members.append(member(f"C{s}_{j}", f"N{s}_{j}", f"N{s + 1}_{j}", 1.5e-2, 5e-4))
    for s in range(1, storeys + 1):
        for j in range(bays):
            members.append(member(f"B{s}_{j}", f"N{s}_{j}", f"N{s}_{j + 1}", 8e-3, 2e-4))
            udl.append((f"B{s}_{j}", 0.0, -30.0))
    m = model(f"tower {storeys} storeys, fixed bases, p = {p:g}", "tower", nodes, members,
              {f"N0_{j}": (0, 1, 2) for j in range(bays + 1)},
              {f"N{s}_0": (10.0 * p, 0.0, 0.0) for s in range(1, storeys + 1)}, udl=udl)
    for mem in m["members"]:                  # E of the tower is 210e6: scale A, I to E = 2e8
        mem["A"] *= 210e6 / E
        mem["I"] *= 210e6 / E
    return m


def space_cases():
    """(plane-in-3-D pairs, genuinely 3-D models)."""
    pairs = []
    for m in hand_cases()[:: 7][:3] + [portal_leaning(0.5)]:
        pairs.append(m)
    threed = []
    # a pinned strut along x, Iy ≠ Iz, uniform loads about both axes, compression
    Iy, Iz = 2e-5, 1e-5
    for s in (0.3, 0.8):
        N = -s * float(mp.pi ** 2) * E * Iz / L0 ** 2
        wy, wz = -6.0, -9.0
        rz = pinned_udl(wy, N, E * Iz, L0)
        ry = pinned_udl(wz, N, E * Iy, L0)
        m = model(f"3-D pinned strut wy + wz C{s:g}P_e(z)", "space",
                  {"A": (0.0, 0.0, 0.0), "B": (L0, 0.0, 0.0)},
                  [member("S", "A", "B", A0, Iz, Iy=Iy)],
                  {"A": (0, 1, 2, 3), "B": (1, 2)}, {"B": (N, 0, 0, 0, 0, 0)},
                  udl=[("S", 0.0, wy, wz)], dim=3)
        m["closed"] = [("|Mz| mid", "ext", ("S", "|Mz|"), abs(rz["M_mid"]), abs(rz["M_mid"])),
                       ("|My| mid", "ext", ("S", "|My|"), abs(ry["M_mid"]), abs(ry["M_mid"])),
                       ("alpha", "alpha", None, 1 / s, 1 / s)]
        threed.append(m)
    # a cantilever column pushed both ways with loads across both axes
    for s in (0.3, 0.8):
        Iy, Iz = 3e-5, 1e-5
        Pc = s * float(mp.pi ** 2) * E * Iz / (4 * L0 ** 2)
        threed.append(model(f"3-D cantilever Hx, Hy, wx, wy at {s:g}·P_cr", "space",
                            {"A": (0.0, 0.0, 0.0), "B": (0.0, 0.0, L0)},
                            [member("C", "A", "B", A0, Iz, Iy=Iy, ref=(1.0, 0.0, 0.0))],
                            {"A": (0, 1, 2, 3, 4, 5)}, {"B": (3.0, 2.0, -Pc, 0, 0, 0)},
                            udl=[("C", 0.0, 1.5, -1.0)], dim=3))
        threed.append(model(f"3-D cantilever Hx, Hy only at {s:g}·P_cr", "space",
                            {"A": (0.0, 0.0, 0.0), "B": (0.0, 0.0, L0)},
                            [member("C", "A", "B", A0, Iz, Iy=Iy, ref=(1.0, 0.0, 0.0))],
                            {"A": (0, 1, 2, 3, 4, 5)}, {"B": (3.0, 2.0, -Pc, 0, 0, 0)}, dim=3))
    # a 3-D portal: four columns, beams both ways, gravity on the beams, a push
    h, a, b = 4.0, 6.0, 5.0
    nodes = {}
    for k, (x, y) in enumerate(((0, 0), (a, 0), (a, b), (0, b))):
        nodes[f"G{k}"] = (float(x), float(y), 0.0)
        nodes[f"T{k}"] = (float(x), float(y), h)
    mems = [member(f"C{k}", f"G{k}", f"T{k}", 8e-3, 6e-5, Iy=1.5e-4, ref=(1.0, 0.0, 0.0))
            for k in range(4)]
    for k in range(4):
        mems.append(member(f"B{k}", f"T{k}", f"T{(k + 1) % 4}", 8e-3, 2e-4, Iy=4e-4,
                           ref=(0.0, 0.0, 1.0)))
    m = model("3-D portal, beams loaded, pushed in x and y", "space", nodes, mems,
              {f"G{k}": (0, 1, 2, 3, 4, 5) for k in range(4)},
              {"T0": (20.0, 10.0, -1200.0, 0, 0, 0), "T1": (0, 0, -1200.0, 0, 0, 0),
               "T2": (0, 0, -1200.0, 0, 0, 0), "T3": (0, 0, -1200.0, 0, 0, 0)},
              udl=[(f"B{k}", 0.0, 0.0, -25.0) for k in range(4)] + [("C0", 0.0, 3.0, 2.0)], dim=3)
    threed.append(m)
    loads = {n: np.array(f, float) for n, f in m["loads"].items()}
    for k in range(4):        # the beams' loads to their ends (25 kN/m × 6 or 5 m / 2)
        for n, span_ in ((f"T{k}", (a, b)[k % 2]), (f"T{(k + 1) % 4}", (a, b)[k % 2])):
            loads[n][2] -= 25.0 * span_ / 2
    threed.append(dict(m, name="3-D portal, lumped loads, pushed in x and y",
                       loads={n: tuple(f) for n, f in loads.items()}, udl=[]))
    return pairs, threed


def in_3d(m):
    """A plane model in the x-y plane of a space frame: out-of-plane dofs held."""
    nodes = {n: (x, y, 0.0) for n, (x, y) in m["nodes"].items()}
    fixed = {n: (2, 3, 4) for n in nodes}
    for n, ds in m["fixed"].items():
        fixed[n] = tuple(sorted(set(fixed[n]) | {(0, 1, 5)[d] for d in ds}))
    for n in nodes:      # the space frame asks that a node only hinged ends meet be held
        ends = [mem["hinge_i"] if mem["i"] == n else mem["hinge_j"] for mem in m["members"]
                if n in (mem["i"], mem["j"])]
        if ends and all(ends):
            fixed[n] = tuple(sorted(set(fixed[n]) | {5}))
    members = [dict(mem, Iy=mem["I"], ref=(0.0, 0.0, 1.0)) for mem in m["members"]]
    loads = {n: (f[0], f[1], 0.0, 0.0, 0.0, f[2]) for n, f in m["loads"].items()}
    return model(m["name"] + " (in 3-D)", "space", nodes, members, fixed, loads,
                 udl=[(nm, wx, wy, 0.0) for nm, wx, wy in m["udl"]],
                 point=[(nm, a, px, py, 0.0) for nm, a, px, py in m["point"]], dim=3)
