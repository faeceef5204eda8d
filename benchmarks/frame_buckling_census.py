"""Random plane frames' elastic critical load factor α_cr against an
independent eigen analysis (issue 52: second order where users look).

Each frame (seeded): 1–3 bays of 3–8 m, 1–4 storeys of 2.8–4.5 m, bases
fixed, pinned or mixed, random column and beam sections (E = 2e8 kN/m²),
beams hinged at one or both ends in some frames, gravity loads at every
joint, a uniform load on every beam and a lateral load at the windward
joints; in about a third of them a leaning column (hinged at both ends)
beside the frame, tied at each floor by a hinged link and carrying its own
floor loads.  No contacts: α_cr is the frame's, not its supports'.

qpcontact: ``critical_load_factor(solve())`` — the first-order axial
forces scaled by α, its stability functions (one element a member) and the
count of negative eigenvalues.

Reference (written here, not the package's): every member cut into n
Euler–Bernoulli elements with the consistent geometric stiffness of the
cut elements' own axial forces (from a linear solve of the same cut model;
a hinged end gets a rotation of its own), and α_cr the least positive root
of det(K_E + α K_G) = 0 (scipy's symmetric-definite eigh of (−K_G, K_E)),
at n = 8 and 16 extrapolated as O(n⁻⁴).  Its own error: the extrapolation's,
up to ~1e-6 on the frames with the coarsest members.

``--space``: random space frames instead — 1–2 bays each way, 1–3 storeys,
bases fixed or pinned, columns with Iy ≠ Iz and ``ref`` = X, beams along X
and Y some hinged at one end (both bending rotations), in half of them a
slender brace hinged at both ends across the first bay; gravity at every
joint, a push along X and Y at one corner.  The reference is the same cut
analysis in 3-D (each plane's Hermite block and consistent geometric
block, torsion first order as in the package; a hinged end keeps its
node's twist x·r and has its own θy, θz), its local axes built here from
the documented convention (z in the plane of x and ``ref``, y = z × x), at
n = 4 and 8 (its own error up to ~6e-6 on a few frames, ≤ 1e-7 at 8 and 16).

``--offsets``: the plane frames with rigid end zones (`offset_i`,
`offset_j`, up to 15 % of the member at each end) on 70 % of the columns
and beams, and no span loads (a load on a zone goes to its node
statically, which the reference's arms would not copy).  The reference
models each zone as a member 100 and 1000 times stiffer (not cut) and
extrapolates as 1/stiffness (its own error up to ~2e-5).

``--shear``: the plane frames with shear deformation on every member
(G = 8e7, A_s = A times 0.01–0.5: φ = 12EI/(G A_s L²) from about 0.002 to
5), which the package answers with Engesser's beam-column (one element a
member).  The reference cuts each member into n two-node Timoshenko
pieces (their exact first-order stiffness, for any φ of the piece) with
the chord's geometric stiffness N/h on each piece's transverse dofs (its
P-Δ), which converge to Engesser's member as n⁻², then n⁻⁴; n = 8, 16, 32
extrapolated twice (Richardson: n⁻², then n⁻⁴).  Its own error: 1.8e-6 on
seed 1, where n = 16, 32, 64 moves it to 2.5e-8 of the package's.  The cubic's consistent
geometric matrix on Timoshenko pieces would not do: a chain of them
converges to a load below Engesser's (0.56 % on a pinned strut at
φ = 0.24), the shear strain's γ²/5 added to the axis's slope.

A frame counts "right" when the two agree to 1e-6 (plane; 1e-5 space and
shear; 5e-5 with offsets),
"too high" (the unsafe side), "too low" or "raised" otherwise.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/frame_buckling_census.py [--frames 60]
    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/frame_buckling_census.py --space --frames 30
    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/frame_buckling_census.py --offsets --frames 30
    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/frame_buckling_census.py --shear --frames 30
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import warnings

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import scipy.linalg as la  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.frames import Frame, SpaceFrame  # noqa: E402

E, G = 2e8, 8e7


def element_k(A, I, L, As=None):
    """Element stiffness (u, v, θ at each end), local: Euler–Bernoulli, or
    with a shear area ``As`` the exact two-node Timoshenko element."""
    k = np.zeros((6, 6))
    p = 0.0 if As is None else 12 * E * I / (G * As * L ** 2)
    a, b = E * A / L, E * I / (L ** 3 * (1 + p))
    k[0, 0] = k[3, 3] = a
    k[0, 3] = k[3, 0] = -a
    for i, j, v in ((1, 1, 12), (1, 2, 6 * L), (1, 4, -12), (1, 5, 6 * L),
                    (2, 2, (4 + p) * L * L), (2, 4, -6 * L), (2, 5, (2 - p) * L * L),
                    (4, 4, 12), (4, 5, -6 * L), (5, 5, (4 + p) * L * L)):
        k[i, j] = k[j, i] = v * b
    return k


def geometric_k(N, L, chord=False):
    """The consistent geometric stiffness of the cubic shape functions, or
    (``chord``) the chord's, N/L on the transverse dofs."""
    k = np.zeros((6, 6))
    if chord:
        k[1, 1] = k[4, 4] = N / L
        k[1, 4] = k[4, 1] = -N / L
        return k
    c = N / (30 * L)
    for i, j, v in ((1, 1, 36), (1, 2, 3 * L), (1, 4, -36), (1, 5, 3 * L), (2, 2, 4 * L * L),
                    (2, 4, -3 * L), (2, 5, -L * L), (4, 4, 36), (4, 5, -3 * L),
                    (5, 5, 4 * L * L)):
        k[i, j] = k[j, i] = v * c
    return k


def reference_alpha(frame, cut):
    """α_cr of the cut model described in the module's docstring."""
    dof, nd = {}, 0
    for n in frame["nodes"]:
        dof[n], nd = [nd, nd + 1, nd + 2], nd + 3
    elements = []
    full = cut
    for name, i, j, A, I, hi, hj in frame["members"]:
        cut = 1 if name.endswith(ARM) else full        # a stiff arm: not cut
        xi, xj = np.array(frame["nodes"][i], float), np.array(frame["nodes"][j], float)
        ids = [dof[i]] + [[nd + 3 * k, nd + 3 * k + 1, nd + 3 * k + 2]
                          for k in range(cut - 1)] + [dof[j]]
        nd += 3 * (cut - 1)
        for end, hinged in ((0, hi), (-1, hj)):
            if hinged:
                ids[end], nd = ids[end][:2] + [nd], nd + 1
        for k in range(cut):
            elements.append((name, ids[k] + ids[k + 1], xi + (xj - xi) * k / cut,
                             xi + (xj - xi) * (k + 1) / cut, A, I))
    K, F = np.zeros((nd, nd)), np.zeros(nd)
    for n, (fx, fy) in frame["loads"].items():
        F[dof[n][:2]] += (fx, fy)
    parts = []
    for name, ix, p, q, A, I in elements:
        L = float(np.hypot(*(q - p)))
        c, s = (q - p) / L
        T = np.zeros((6, 6))
        T[:3, :3] = T[3:, 3:] = [[c, s, 0], [-s, c, 0], [0, 0, 1]]
        k = element_k(A, I, L, frame.get("shear", {}).get(name))
        K[np.ix_(ix, ix)] += T.T @ k @ T
        parts.append((ix, T, k, L))
        w = frame["udl"].get(name, 0.0)          # global y, per length (beams are level)
        F[ix] += T.T @ np.array([0, w * L / 2, w * L * L / 12, 0, w * L / 2, -w * L * L / 12])
    held = {dof[n][d] for n, ds in frame["fixed"].items() for d in ds}
    held |= {k for k in range(nd) if K[k, k] == 0.0}     # a joint only hinged ends meet
    free = np.array([k for k in range(nd) if k not in held])
    u = np.zeros(nd)
    u[free] = la.solve(K[np.ix_(free, free)], F[free], assume_a="sym")
    Kg = np.zeros((nd, nd))
    for ix, T, k, L in parts:
        d = T @ u[ix]
        Kg[np.ix_(ix, ix)] += T.T @ geometric_k(k[3, 3] * (d[3] - d[0]), L,
                                                "shear" in frame) @ T
    mu = la.eigh(-Kg[np.ix_(free, free)], K[np.ix_(free, free)], eigvals_only=True)
    return 1.0 / mu.max() if mu.max() > 0 else np.inf


ARM = ("~i", "~j")


def with_offsets(frame, seed):
    """The frame with rigid end zones on 70 % of its columns and beams and
    no span loads (``--offsets``)."""
    rng = np.random.default_rng(500 + seed)
    offsets = {}
    for name, i, j, *_ in frame["members"]:
        if name[0] in "CB" and rng.random() < 0.7:
            L = float(np.hypot(*np.subtract(frame["nodes"][j], frame["nodes"][i])))
            offsets[name] = tuple(rng.uniform(0, 0.15, 2) * L)
    return dict(frame, udl={}, offsets=offsets)


def with_shear(frame, seed):
    """The frame with a shear area on every member (``--shear``)."""
    rng = np.random.default_rng(700 + seed)
    return dict(frame, shear={name: A * rng.uniform(0.01, 0.5)
                              for name, i, j, A, *_ in frame["members"]})


def reference_alpha_shear(frame, cuts):
    """The cut reference of ``--shear`` at n = cuts (three), extrapolated
    as n⁻² then n⁻⁴."""
    a8, a16, a32 = (reference_alpha(frame, n) for n in cuts)
    e16, e32 = a16 + (a16 - a8) / 3, a32 + (a32 - a16) / 3
    return e32 + (e32 - e16) / 15


def with_arms(frame, stiffer):
    """The reference's frame: each rigid zone a member ``stiffer`` times
    the member's EA and EI, ending at a node of its own (the face)."""
    nodes, members = dict(frame["nodes"]), []
    for name, i, j, A, I, hi, hj in frame["members"]:
        oi, oj = frame["offsets"].get(name, (0.0, 0.0))
        p, q = np.array(nodes[i], float), np.array(nodes[j], float)
        e = (q - p) / np.linalg.norm(q - p)
        a, b = i, j
        if oi > 0:
            a, nodes[name + "@i"] = name + "@i", tuple(p + e * oi)
            members.append((name + "~i", i, a, A * stiffer, I * stiffer, False, False))
        if oj > 0:
            b, nodes[name + "@j"] = name + "@j", tuple(q - e * oj)
            members.append((name + "~j", b, j, A * stiffer, I * stiffer, False, False))
        members.append((name, a, b, A, I, hi, hj))
    return dict(frame, nodes=nodes, members=members)


def reference_alpha_offsets(frame, cut):
    """The cut reference with zones 100 and 1000 times stiffer, as 1/stiffness."""
    soft, stiff = (reference_alpha(with_arms(frame, f), cut) for f in (1e2, 1e3))
    return stiff + (stiff - soft) / 9


def random_frame(seed):
    rng = np.random.default_rng(seed)
    bays, storeys = int(rng.integers(1, 4)), int(rng.integers(1, 5))
    xs = np.r_[0, np.cumsum(rng.uniform(3, 8, bays))]
    ys = np.r_[0, np.cumsum(rng.uniform(2.8, 4.5, storeys))]
    nodes = {f"N{c}_{r}": (xs[c], ys[r]) for c in range(bays + 1) for r in range(storeys + 1)}
    base = rng.choice(["fixed", "pinned", "mixed"])
    fixed = {}
    for c in range(bays + 1):
        kind = base if base != "mixed" else rng.choice(["fixed", "pinned"])
        fixed[f"N{c}_0"] = (0, 1, 2) if kind == "fixed" else (0, 1)
    members, udl, loads = [], {}, {}
    hinged_beams = rng.random() < 0.4
    for r in range(storeys):
        for c in range(bays + 1):
            members.append((f"C{c}_{r}", f"N{c}_{r}", f"N{c}_{r + 1}", rng.uniform(5e-3, 2e-2),
                            rng.uniform(1e-5, 2e-4), False, False))
    for r in range(1, storeys + 1):
        for c in range(bays):
            A, I = rng.uniform(5e-3, 2e-2), rng.uniform(2e-5, 5e-4)
            hi = hj = False
            if hinged_beams and rng.random() < 0.5:
                hi, hj = rng.random() < 0.5, rng.random() < 0.5
            members.append((f"B{c}_{r}", f"N{c}_{r}", f"N{c + 1}_{r}", A, I, hi, hj))
            udl[f"B{c}_{r}"] = -rng.uniform(5, 40)
        for c in range(bays + 1):
            loads[f"N{c}_{r}"] = (0.0, -rng.uniform(50, 800))
        loads[f"N0_{r}"] = (rng.uniform(1, 20), loads[f"N0_{r}"][1])
    if rng.random() < 0.3:                       # a leaning column beside it
        for r in range(storeys + 1):
            nodes[f"L{r}"] = (xs[-1] + 4.0, ys[r])
        fixed["L0"] = (0, 1)
        for r in range(storeys):
            members.append((f"LC{r}", f"L{r}", f"L{r + 1}", 1e-2, 3e-5, True, True))
        for r in range(1, storeys + 1):
            members.append((f"LB{r}", f"N{bays}_{r}", f"L{r}", 1e-2, 1e-4, True, True))
            loads[f"L{r}"] = (0.0, -rng.uniform(100, 1500))
    return dict(nodes=nodes, members=members, fixed=fixed, loads=loads, udl=udl)


def qpcontact_alpha(frame):
    fr = Frame()
    for n, (x, y) in frame["nodes"].items():
        fr.add_node(n, x, y)
    for name, i, j, A, I, hi, hj in frame["members"]:
        oi, oj = frame.get("offsets", {}).get(name, (0.0, 0.0))
        As = frame.get("shear", {}).get(name)
        fr.add_member(i, j, E, A, I, name=name, hinge_i=hi, hinge_j=hj, offset_i=oi,
                      offset_j=oj, **({} if As is None else {"G": G, "shear_area": As}))
    for n, ds in frame["fixed"].items():
        fr.add_support(n, fix=tuple(("ux", "uy", "rz")[d] for d in ds))
    for n, (fx, fy) in frame["loads"].items():
        fr.add_load(n, fx=fx, fy=fy)
    for m, w in frame["udl"].items():
        fr.add_distributed_load(m, wy=w)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        crit = fr.critical_load_factor(fr.solve())
    return crit["alpha"], crit["limited_by"]


# -- space frames ----------------------------------------------------------------------

FLIP = np.diag([1.0, -1.0, 1.0, -1.0])       # θy = −dw/dx: the x-z plane's rotations


def bending_k(EI, L):
    b = EI / L ** 3
    return b * np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                         [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]])


def bending_g(N, L):
    c = N / (30 * L)
    return c * np.array([[36, 3 * L, -36, 3 * L], [3 * L, 4 * L * L, -3 * L, -L * L],
                         [-36, -3 * L, 36, -3 * L], [3 * L, -L * L, -3 * L, 4 * L * L]])


def space_local(A, Iy, Iz, J, L, N=None):
    """12 × 12 in member axes (u, v, w, θx, θy, θz at i, then j): the
    elastic stiffness, or with ``N`` the consistent geometric one."""
    k = np.zeros((12, 12))
    xy, xz = [1, 5, 7, 11], [2, 4, 8, 10]
    if N is None:
        for ix, v in (([0, 6], E * A / L), ([3, 9], G * J / L)):
            k[np.ix_(ix, ix)] = v * np.array([[1, -1], [-1, 1]])
        k[np.ix_(xy, xy)] = bending_k(E * Iz, L)
        k[np.ix_(xz, xz)] = FLIP @ bending_k(E * Iy, L) @ FLIP
    else:
        k[np.ix_(xy, xy)] = bending_g(N, L)
        k[np.ix_(xz, xz)] = FLIP @ bending_g(N, L) @ FLIP
    return k


def member_axes(p, q, ref):
    """Rows x, y, z: x along the member, z in the plane of x and ``ref``,
    y = z × x (docs/frames.md, "Conventions")."""
    x = (q - p) / np.linalg.norm(q - p)
    z = ref - (ref @ x) * x
    z /= np.linalg.norm(z)
    return np.array([x, np.cross(z, x), z])


def end_map(R, node, own):
    """(M, dofs): an element end's local (u, θ) = M @ global[dofs]; a hinged
    end (``own``: its two rotations) keeps its node's twist x·r only."""
    if own is None:
        return la.block_diag(R, R), list(node)
    M = np.zeros((6, 8))
    M[:3, :3], M[3, 3:6], M[4, 6], M[5, 7] = R, R[0], 1.0, 1.0
    return M, list(node) + own


def reference_alpha_space(frame, cut):
    dof, nd = {}, 0
    for n in frame["nodes"]:
        dof[n], nd = list(range(nd, nd + 6)), nd + 6
    elements = []
    for name, i, j, A, Iy, Iz, J, ref, hi, hj in frame["members"]:
        p, q = np.array(frame["nodes"][i], float), np.array(frame["nodes"][j], float)
        ids = [dof[i]] + [list(range(nd + 6 * k, nd + 6 * k + 6)) for k in range(cut - 1)] \
            + [dof[j]]
        nd += 6 * (cut - 1)
        own = [None] * (cut + 1)
        for end, hinged in ((0, hi), (cut, hj)):
            if hinged:
                own[end], nd = [nd, nd + 1], nd + 2
        R = member_axes(p, q, np.array(ref, float))
        for k in range(cut):
            Mi, gi = end_map(R, ids[k], own[k] if k == 0 else None)
            Mj, gj = end_map(R, ids[k + 1], own[k + 1] if k + 1 == cut else None)
            elements.append((gi + gj, la.block_diag(Mi, Mj), np.linalg.norm(q - p) / cut,
                             (A, Iy, Iz, J)))
    K, F = np.zeros((nd, nd)), np.zeros(nd)
    for n, f in frame["loads"].items():
        F[dof[n][:3]] += f
    for ix, T, L, sec in elements:
        K[np.ix_(ix, ix)] += T.T @ space_local(*sec, L) @ T
    held = {dof[n][d] for n, ds in frame["fixed"].items() for d in ds}
    free = np.array([k for k in range(nd) if k not in held])
    u = np.zeros(nd)
    u[free] = la.solve(K[np.ix_(free, free)], F[free], assume_a="sym")
    Kg = np.zeros((nd, nd))
    for ix, T, L, sec in elements:
        d = T @ u[ix]
        Kg[np.ix_(ix, ix)] += T.T @ space_local(*sec, L, E * sec[0] / L * (d[6] - d[0])) @ T
    mu = la.eigh(-Kg[np.ix_(free, free)], K[np.ix_(free, free)], eigvals_only=True)
    return 1.0 / mu.max() if mu.max() > 0 else np.inf


def random_space_frame(seed):
    rng = np.random.default_rng(seed)
    nx, ny, ns = int(rng.integers(1, 3)), int(rng.integers(1, 3)), int(rng.integers(1, 4))
    xs, ys = np.r_[0, np.cumsum(rng.uniform(3, 7, nx))], np.r_[0, np.cumsum(rng.uniform(3, 7, ny))]
    zs = np.r_[0, np.cumsum(rng.uniform(3, 4.5, ns))]
    nodes = {f"N{a}{b}{c}": (xs[a], ys[b], zs[c]) for a in range(nx + 1) for b in range(ny + 1)
             for c in range(ns + 1)}
    fixed, members, loads = {}, [], {}
    base = rng.choice(["fixed", "pinned"])
    for a in range(nx + 1):
        for b in range(ny + 1):
            fixed[f"N{a}{b}0"] = range(6) if base == "fixed" else range(3)
            for c in range(ns):
                A, (Iy, Iz) = rng.uniform(5e-3, 2e-2), rng.uniform(1e-5, 2e-4, 2)
                members.append((f"C{a}{b}{c}", f"N{a}{b}{c}", f"N{a}{b}{c + 1}", A, Iy, Iz,
                                rng.uniform(1e-6, 1e-5), (1, 0, 0), False, False))
    hinged = rng.random() < 0.5
    for c in range(1, ns + 1):
        for a in range(nx + 1):
            for b in range(ny + 1):
                loads[f"N{a}{b}{c}"] = (0.0, 0.0, -rng.uniform(50, 600))
                for far, along, nm in ((a < nx, f"N{a + 1}{b}{c}", "X"),
                                       (b < ny, f"N{a}{b + 1}{c}", "Y")):
                    if far:
                        h = bool(hinged and rng.random() < 0.5)
                        members.append((f"{nm}{a}{b}{c}", f"N{a}{b}{c}", along, 1e-2,
                                        rng.uniform(2e-5, 4e-4), rng.uniform(2e-5, 4e-4), 1e-5,
                                        (0, 0, 1), h and nm == "X", h and nm == "Y"))
        loads[f"N00{c}"] = (rng.uniform(1, 20), rng.uniform(1, 20), loads[f"N00{c}"][2])
    if rng.random() < 0.5:        # a slender brace, hinged at both ends
        members.append(("BR", f"N{nx}00", "N001", 2e-3, 2e-7, 3e-7, 1e-7, (0, 0, 1), True, True))
    return dict(nodes=nodes, members=members, fixed=fixed, loads=loads)


def qpcontact_alpha_space(frame):
    fr = SpaceFrame()
    for n, p in frame["nodes"].items():
        fr.add_node(n, *p)
    for name, i, j, A, Iy, Iz, J, ref, hi, hj in frame["members"]:
        fr.add_member(i, j, E, A, Iy, Iz, G=G, J=J, name=name, ref=ref, hinge_i=hi, hinge_j=hj)
    for n, ds in frame["fixed"].items():
        fr.add_support(n, fix=tuple(("ux", "uy", "uz", "rx", "ry", "rz")[d] for d in ds))
    for n, f in frame["loads"].items():
        fr.add_load(n, *f)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        crit = fr.critical_load_factor(fr.solve())
    return crit["alpha"], crit["limited_by"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--frames", type=int, default=60)
    ap.add_argument("--space", action="store_true", help="space frames")
    ap.add_argument("--offsets", action="store_true", help="plane frames with rigid end zones")
    ap.add_argument("--shear", action="store_true", help="plane frames with shear deformation")
    ap.add_argument("--show", action="store_true", help="print every frame")
    args = ap.parse_args(argv)
    counts = collections.Counter()
    make, ours, reference, cuts, tol = (
        (random_space_frame, qpcontact_alpha_space, reference_alpha_space, (4, 8), 1e-5)
        if args.space else
        (lambda seed: with_shear(random_frame(seed), seed), qpcontact_alpha,
         reference_alpha_shear, (8, 16, 32), 1e-5) if args.shear else
        (lambda seed: with_offsets(random_frame(seed), seed), qpcontact_alpha,
         reference_alpha_offsets, (8, 16), 5e-5) if args.offsets else
        (random_frame, qpcontact_alpha, reference_alpha, (8, 16), 1e-6))
    for seed in range(args.frames):
        frame = make(seed)
        if args.shear:
            ref = reference(frame, cuts)
        else:
            coarse, fine = (reference(frame, n) for n in cuts)
            ref = fine + (fine - coarse) / 15
        try:
            alpha, limited = ours(frame)
            rel = (alpha - ref) / ref
            verdict = "right" if abs(rel) <= tol else ("too high" if rel > 0 else "too low")
        except Exception as exc:          # noqa: BLE001 - counted, and shown
            alpha, limited, rel, verdict = np.nan, f"{type(exc).__name__}: {exc}"[:80], np.nan, \
                "raised"
        counts[verdict] += 1
        if args.show or verdict != "right":
            print(f"seed {seed:3d}  {len(frame['members']):3d} members  α_cr {alpha:.10g}  "
                  f"reference {ref:.10g}  ({rel:+.1e})  {verdict}  {limited or ''}")
    print(", ".join(f"{k}: {counts[k]}" for k in ("right", "too high", "too low", "raised")))
    return 0 if counts["right"] == args.frames else 1


if __name__ == "__main__":
    sys.exit(main())
