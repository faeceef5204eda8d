"""References for benchmarks/frame_pdelta_census.py, written without
qpcontact: the beam-column's closed forms (mpmath, 50 digits), the
census's plain frame model, OpenSees' answer on the same model cut into
pieces (openseespy), and α_cr of a cut model by a generalised eigenvalue
problem (scipy).  Nothing here imports qpcontact or formulations; the
census module's docstring says what each reference is and how far it is
trusted.

Units: kN and m (E = 2e8 kN/m², G = 8e7 kN/m²); N is tension positive;
span loads are per length in member axes; moments in the diagrams'
convention are sagging positive (they compress the member's +y fibre).
"""

from __future__ import annotations

import collections

import mpmath as mp
import numpy as np
import scipy.linalg as la

mp.mp.dps = 50
E, G = 2e8, 8e7
GRID = 8                                    # diagrams compared at x = kL/8

try:
    import openseespy.opensees as ops
    HAVE_OPENSEES = True
except (ImportError, RuntimeError):         # pragma: no cover - depends on the machine
    ops, HAVE_OPENSEES = None, False


# -- closed forms (mpmath, 50 digits) ---------------------------------------------------

def _k(N, EI):
    """(k, compression?) of an axial force N (tension positive)."""
    return mp.sqrt(abs(mp.mpf(N)) / mp.mpf(EI)), N < 0


def pinned_udl(w, N, EI, L):
    """Pinned span, uniform w (along local +y), axial N: {M_mid, theta_end, v_mid}
    (M sagging positive, θ at node i counterclockwise, v along +y)."""
    k, comp = _k(N, EI)
    u = k * L / 2
    if comp:
        m, th, v = (mp.sec(u) - 1) / k ** 2, (mp.tan(u) - u) / (EI * k ** 3), \
            (mp.sec(u) - 1 - u ** 2 / 2) / (EI * k ** 4)
    else:
        m, th, v = (1 - mp.sech(u)) / k ** 2, (u - mp.tanh(u)) / (EI * k ** 3), \
            (mp.sech(u) - 1 + u ** 2 / 2) / (EI * k ** 4)
    # a load along -y (w < 0) sags: M > 0, node i turns clockwise, v < 0
    return {"M_mid": -w * m, "theta_i": w * th, "v_mid": w * v}


def clamped_udl(w, N, EI, L):
    """Clamped span, uniform w: {M_end (sagging sign, both ends), M_mid}."""
    k, comp = _k(N, EI)
    u = k * L / 2
    if comp:
        end, mid = (1 - u / mp.tan(u)) / k ** 2, (u / mp.sin(u) - 1) / k ** 2
    else:
        end, mid = (u / mp.tanh(u) - 1) / k ** 2, (1 - u / mp.sinh(u)) / k ** 2
    return {"M_end": w * end, "M_mid": -w * mid}


def pinned_midpoint(Q, N, EI, L):
    """Pinned span, force Q (along local +y) at midspan: {M_mid, theta_i, v_mid}."""
    k, comp = _k(N, EI)
    u, P = k * L / 2, abs(mp.mpf(N))
    if comp:
        m, th, v = mp.tan(u) / (2 * k), (mp.sec(u) - 1) / (2 * P), (mp.tan(u) - u) / (2 * P * k)
    else:
        m, th, v = mp.tanh(u) / (2 * k), (1 - mp.sech(u)) / (2 * P), (u - mp.tanh(u)) / (2 * P * k)
    return {"M_mid": -Q * m, "theta_i": Q * th, "v_mid": Q * v}


def end_moments(Ma, Mb, N, EI, L):
    """Pinned span, sagging end moments M_a (x = 0), M_b (x = L): M(x), the
    end rotations and v(x) from v'' ± k²v = M_lin/EI with v(0) = v(L) = 0."""
    k, comp = _k(N, EI)
    Ma, Mb, L = mp.mpf(Ma), mp.mpf(Mb), mp.mpf(L)
    P = abs(mp.mpf(N))
    if comp:       # M = M_lin − P v, EI v'' = M
        c, s = mp.cos, mp.sin
        A = -Ma / P
        B = (-Mb / P - A * c(k * L)) / s(k * L)
        lin = lambda x: (Ma * (L - x) + Mb * x) / L / P                # noqa: E731
        v = lambda x: A * c(k * x) + B * s(k * x) + lin(x)             # noqa: E731
        dv = lambda x: -A * k * s(k * x) + B * k * c(k * x) + (Mb - Ma) / L / P  # noqa: E731
        M = lambda x: EI * (-A * k ** 2 * c(k * x) - B * k ** 2 * s(k * x))       # noqa: E731
    else:          # M = M_lin + T v
        c, s = mp.cosh, mp.sinh
        A = Ma / P
        B = (Mb / P - A * c(k * L)) / s(k * L)
        lin = lambda x: (Ma * (L - x) + Mb * x) / L / P                # noqa: E731
        v = lambda x: A * c(k * x) + B * s(k * x) - lin(x)             # noqa: E731
        dv = lambda x: A * k * s(k * x) + B * k * c(k * x) - (Mb - Ma) / L / P  # noqa: E731
        M = lambda x: EI * (A * k ** 2 * c(k * x) + B * k ** 2 * s(k * x))        # noqa: E731
    xs = [L * t / 400 for t in range(401)]
    # the extremes: the fine grid's best, polished where the derivative vanishes inside
    ext = {}
    for key, sgn in (("max", 1), ("min", -1)):
        best = max(xs, key=lambda x: sgn * M(x))
        if 0 < best < L:
            best = mp.findroot(lambda x: mp.diff(M, x), best)
        ext[key] = M(best)
    vx = max(xs, key=lambda x: abs(v(x)))
    if 0 < vx < L:
        vx = mp.findroot(lambda x: mp.diff(v, x), vx)
    return {"M": M, "theta_i": dv(0), "theta_j": dv(L), "M_max": ext["max"], "M_min": ext["min"],
            "v_ext": v(vx)}


def cantilever(H, w, N, EI, L):
    """Cantilever x ∈ [0, L] from its clamp, tip force H and uniform w along +v,
    axial N: {delta, theta_tip (dv/dx), M_base} from EI v'' = H(L−x) + P(δ−v) + w(L−x)²/2."""
    k, comp = _k(N, EI)
    P, L = -mp.mpf(N), mp.mpf(L)             # compression positive
    c = w / (2 * P)
    b = H / P
    if comp:
        C2 = (b + 2 * c * L) / k
        C1 = (w / (P * k ** 2) - C2 * mp.sin(k * L)) / mp.cos(k * L)
        a = -C1 - b * L - c * L ** 2
        delta = a + w / (P * k ** 2)
        dv = -C1 * k * mp.sin(k * L) + C2 * k * mp.cos(k * L) - b
    else:          # P = −T < 0: the same with v'' − k² v
        C2 = (b + 2 * c * L) / k
        C1 = (-w / (P * k ** 2) - C2 * mp.sinh(k * L)) / mp.cosh(k * L)
        a = -C1 - b * L - c * L ** 2
        delta = a - w / (P * k ** 2)
        dv = C1 * k * mp.sinh(k * L) + C2 * k * mp.cosh(k * L) - b
    return {"delta": delta, "theta_tip": dv, "M_base": H * L + P * delta + w * L ** 2 / 2}


def engesser(N, EI, GAs):
    """(k, μ, compression?) of a shear-flexible member under N, Engesser's
    model (the shear deformation driven by V = dM/dx with M on the deformed
    member): μ = 1 + N/GA_s, k² = |N|/(EI μ); then M'' ± k² M = M₀''/μ."""
    N = mp.mpf(N)
    mu = 1 + N / GAs
    return mp.sqrt(abs(N) / (EI * mu)), mu, N < 0


def shear_pinned(w, Q, Me, N, EI, GAs, L):
    """Pinned span with shear deformation (Engesser), under N and one of a
    uniform w, a midspan force Q (both along local +y) or equal sagging end
    moments Me: the midspan moment (sagging positive)."""
    k, mu, comp = engesser(N, EI, GAs)
    u = k * L / 2
    sec, tan = (mp.sec, mp.tan) if comp else (mp.sech, mp.tanh)
    if w:         # M'' ± k²M = −w/μ: (w/(μk²))(sec u − 1), tension (w/(μk²))(1 − sech u)
        return -w / (mu * k ** 2) * ((sec(u) - 1) if comp else (1 - sec(u)))
    if Q:         # a kink of Q/μ at midspan: (Q/(2μk)) tan u
        return -Q / (2 * mu * k) * tan(u)
    return Me * sec(u)


def shear_cantilever(H, N, EI, GAs, L):
    """Cantilever with shear deformation (Engesser), tip force H, axial N:
    (M at the clamp, tip sway) — M = A sin k(L − x), M'(0) = −H/μ (the clamp
    holds the bending slope, the shear slope is free), δ = (M(0) − HL)/P."""
    k, mu, comp = engesser(N, EI, GAs)
    L = mp.mpf(L)
    base = H * (mp.tan(k * L) if comp else mp.tanh(k * L)) / (mu * k)
    return base, (base - H * L) / (-mp.mpf(N))


# -- the plain model --------------------------------------------------------------------

def member(name, i, j, A, I, hinge_i=False, hinge_j=False, Iy=None, ref=None, As=None):
    """A member's data (E and G are the module's); ``As``: a plane member's
    shear area (Timoshenko), None for Euler–Bernoulli; such members have
    closed forms only (the census does not build them in OpenSees)."""
    return dict(name=name, i=i, j=j, A=A, I=I, hinge_i=hinge_i, hinge_j=hinge_j,
                Iy=I if Iy is None else Iy, ref=ref, As=As)


def model(name, family, nodes, members, fixed, loads, udl=(), point=(), closed=None, dim=2):
    """fixed {node: dofs (0 ux, 1 uy, 2 rz; space 0..5)}, loads {node: components},
    udl [(member, wx, wy[, wz])] and point [(member, a, px, py[, pz])] in member axes,
    closed: [(label, kind, key, value)] references from closed forms."""
    return dict(name=name, family=family, nodes=nodes, members=members, fixed=fixed,
                loads=loads, udl=list(udl), point=list(point), closed=closed or [], dim=dim)


def geometry(m, mem):
    p, q = np.array(m["nodes"][mem["i"]], float), np.array(m["nodes"][mem["j"]], float)
    L = float(np.linalg.norm(q - p))
    return p, q, L


# -- OpenSees ---------------------------------------------------------------------------

def os_answer(m, sub, transformation="PDelta"):
    """OpenSees' answer, each member cut into ``sub`` pieces; None where it
    does not converge."""
    space = m["dim"] == 3
    ndf = 6 if space else 3
    ops.wipe()
    ops.model("basic", "-ndm", m["dim"], "-ndf", ndf)
    tags = {n: k + 1 for k, n in enumerate(m["nodes"])}
    for n, xy in m["nodes"].items():
        ops.node(tags[n], *map(float, xy))
    # a node where every member is hinged has no rotational stiffness: held
    meets = collections.defaultdict(list)
    for mem in m["members"]:
        meets[mem["i"]].append(mem["hinge_i"])
        meets[mem["j"]].append(mem["hinge_j"])
    rotations = range(3, 6) if space else (2,)
    for n in m["nodes"]:
        held = set(m["fixed"].get(n, ()))
        if n in m.get("pads", ()):            # a pad the answer has closed: held along y
            held.add(1)
        if meets[n] and all(meets[n]):
            held |= set(rotations)
        if held:
            ops.fix(tags[n], *[1 if d in held else 0 for d in range(ndf)])
    nxt, ele, chains, transf = len(tags) + 1, 1, {}, 1
    for mem in m["members"]:
        p, q, L = geometry(m, mem)
        if space:
            ref = mem["ref"]
            if ref is None:
                ref = (1.0, 0.0, 0.0) if abs((q - p)[2]) > 0.999 * L else (0.0, 0.0, 1.0)
            ops.geomTransf(transformation, transf, *map(float, ref))
        else:
            ops.geomTransf(transformation, transf)
        chain = []
        for s in range(sub + 1):
            if s in (0, sub):
                n = mem["i"] if s == 0 else mem["j"]
                if mem["hinge_i" if s == 0 else "hinge_j"]:      # its own node, tied
                    ops.node(nxt, *map(float, m["nodes"][n]))
                    ops.equalDOF(tags[n], nxt, *range(1, ndf - (2 if space else 0)))
                    chain.append(nxt)
                    nxt += 1
                else:
                    chain.append(tags[n])
            else:
                ops.node(nxt, *map(float, p + (q - p) * s / sub))
                chain.append(nxt)
                nxt += 1
        pieces = []
        for a, b in zip(chain[:-1], chain[1:]):
            if space:
                ops.element("elasticBeamColumn", ele, a, b, mem["A"], E, G, mem["Iy"] + mem["I"],
                            mem["Iy"], mem["I"], transf)
            else:
                ops.element("elasticBeamColumn", ele, a, b, mem["A"], E, mem["I"], transf)
            pieces.append(ele)
            ele += 1
        chains[mem["name"]] = (chain, pieces, L)
        transf += 1
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for n, f in m["loads"].items():
        ops.load(tags[n], *map(float, f))
    for nm, *w in m["udl"]:
        pieces = chains[nm][1]
        if space:
            ops.eleLoad("-ele", *pieces, "-type", "-beamUniform", float(w[1]), float(w[2]),
                        float(w[0]))
        else:
            ops.eleLoad("-ele", *pieces, "-type", "-beamUniform", float(w[1]), float(w[0]))
    for nm, a, *f in m["point"]:
        chain, pieces, L = chains[nm]
        k = min(int(a / L * sub), sub - 1)
        xl = a / L * sub - k
        if space:
            ops.eleLoad("-ele", pieces[k], "-type", "-beamPoint", float(f[1]), float(f[2]), xl,
                        float(f[0]))
        else:
            ops.eleLoad("-ele", pieces[k], "-type", "-beamPoint", float(f[1]), xl, float(f[0]))
    ops.system("UmfPack")
    ops.numberer("RCM")
    ops.constraints("Transformation")
    ops.test("NormDispIncr", 1e-12, 100)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 0.1)
    ops.analysis("Static")
    if ops.analyze(10) != 0:
        return None
    out = dict(disp={n: np.array(ops.nodeDisp(tags[n]), float) for n in m["nodes"]},
               ends={}, grid={}, ext={}, axial={}, chains={})
    for mem in m["members"]:
        nm = mem["name"]
        chain, pieces, L = chains[nm]
        # end actions in the member's undeformed axes, as qpcontact's: the
        # global forces (the PDelta transformation's shear N·Δv/l included,
        # which "localForce" leaves out) turned into the member's axes
        R = axes(m, mem)
        first = np.array(ops.eleResponse(pieces[0], "globalForce"), float)
        last = np.array(ops.eleResponse(pieces[-1], "globalForce"), float)
        half = 6 if space else 3
        out["ends"][nm] = np.r_[turn(R, first[:half]), turn(R, last[half:])]
        forces = [np.array(ops.eleResponse(e, "localForce"), float) for e in pieces]
        out["axial"][nm] = np.array([-f[0] for f in forces])        # tension positive
        if space:
            # the largest |My|, |Mz| along the member (the sign convention of the
            # diagrams is not needed for a magnitude): the moments at the cut's
            # nodes, one sign along the chain (−M at each piece's i end, +M at the
            # last j end), polished between nodes as the plane's extremes are
            kinks = {round(a / L * sub) for nm2, a, *_ in m["point"] if nm2 == nm}
            ext, grid = {}, {}
            for key, k, sign in (("My", 4, 1.0), ("Mz", 5, -1.0)):
                M = np.r_[[-f[k] for f in forces], forces[-1][k + 6]]
                ext[f"|{key}|"] = max(peak(M, kinks, 1), -peak(M, kinks, -1))
                # the diagrams' signs (docs/frames.md, "Conventions": My compresses
                # the +z fibre, Mz the +y fibre): My(0) = +My_i, Mz(0) = −Mz_i
                grid[key] = -sign * M[[t * sub // GRID for t in range(GRID + 1)]]
            out["ext"][nm] = ext
            out["grid"][nm] = grid
            continue
        # M(x) at the cut's nodes in the diagrams' convention: M(0) = −M_i, M(L) = M_j
        M = np.r_[[-f[2] for f in forces], forces[-1][5]]
        p, q, _ = geometry(m, mem)
        c, s = (q - p) / L
        v = np.array([-s * ops.nodeDisp(t, 1) + c * ops.nodeDisp(t, 2) for t in chain])
        slope = np.array([ops.nodeDisp(t, 3) for t in chain])      # v' = θ (Euler–Bernoulli)
        at = {round(a / L * sub) for nm2, a, *_ in m["point"] if nm2 == nm}
        out["grid"][nm] = M[[t * sub // GRID for t in range(GRID + 1)]]
        out["ext"][nm] = {"M_max": peak(M, at, 1), "M_min": peak(M, at, -1),
                          "v_max": hermite_peak(v, slope, L / sub, 1),
                          "v_min": hermite_peak(v, slope, L / sub, -1)}
        out["chains"][nm] = M
    return out


def axes(m, mem):
    """The member's local axes as rows (x along it; plane: y turned 90°
    from x; space: y = ref × x, z = x × y, OpenSees' vecxz convention and
    qpcontact's documented one)."""
    p, q, L = geometry(m, mem)
    x = (q - p) / L
    if m["dim"] == 2:
        return np.array([[x[0], x[1], 0.0], [-x[1], x[0], 0.0], [0.0, 0.0, 1.0]])
    ref = mem["ref"]
    if ref is None:
        ref = (1.0, 0.0, 0.0) if abs(x[2]) > 0.999 else (0.0, 0.0, 1.0)
    y = np.cross(ref, x)
    y /= np.linalg.norm(y)
    return np.array([x, y, np.cross(x, y)])


def turn(R, f):
    """Global end forces (plane fx, fy, mz; space fx..mz) into member axes."""
    if f.size == 3:
        return R @ f
    return np.r_[R @ f[:3], R @ f[3:]]


def peak(y, kinks, sgn):
    """The largest (sgn = 1) or smallest value of a smooth curve sampled at
    equal steps: the best sample, polished by the parabola through it and its
    neighbours (not at a point load, where the curve has a kink); where the
    best sample is an end, by the parabola through the last three, whose
    vertex may lie in the last step (a peak close to the end)."""
    k = int(np.argmax(sgn * y))
    n = y.size - 1
    if k in kinks or n < 2:
        return float(y[k])
    j = min(max(k, 1), n - 1)                 # the middle of the three samples
    a, b, c = y[j - 1], y[j], y[j + 1]
    den = a - 2 * b + c
    best = float(y[k])
    if den != 0 and not ({j - 1, j + 1} & kinks):
        t = 0.5 * (a - c) / den               # the vertex, in steps from sample j
        if (k == j and abs(t) <= 1) or (k == 0 and -1 <= t <= 0) or (k == n and 0 <= t <= 1):
            best = sgn * max(sgn * best, sgn * float(b - 0.25 * (a - c) * t))
    return best


def hermite_peak(v, slope, h, sgn):
    """The largest (sgn = 1) or smallest deflection along a chain of cut
    pieces: each piece's cubic through its nodes' v and v' (exact for a
    piece's own cubic, O(h⁴) otherwise), its stationary points inside."""
    best = sgn * v.max() if sgn > 0 else sgn * v.min()
    for va, vb, ta, tb in zip(v[:-1], v[1:], slope[:-1] * h, slope[1:] * h):
        # v(ξ) = va H1 + ta H2 + vb H3 + tb H4, ξ ∈ [0, 1]; v'(ξ) = a ξ² + b ξ + c
        a = 6 * va + 3 * ta - 6 * vb + 3 * tb
        b = -6 * va - 4 * ta + 6 * vb - 2 * tb
        c = ta
        roots = np.roots([a, b, c]) if abs(a) > 0 or abs(b) > 0 else []
        for r in np.real(roots[np.isreal(roots)]) if len(roots) else []:
            if 0 < r < 1:
                H = (1 - 3 * r ** 2 + 2 * r ** 3, r - 2 * r ** 2 + r ** 3, 3 * r ** 2 - 2 * r ** 3,
                     -r ** 2 + r ** 3)
                best = max(best, sgn * (va * H[0] + ta * H[1] + vb * H[2] + tb * H[3]))
    return float(sgn * best)


# -- α_cr of the cut model (plane), written here ----------------------------------------

def _k_local(A, I, L):
    k = np.zeros((6, 6))
    a, b = E * A / L, E * I / L ** 3
    k[0, 0], k[3, 3], k[0, 3], k[3, 0] = a, a, -a, -a
    for i, j, v in ((1, 1, 12), (1, 2, 6 * L), (1, 4, -12), (1, 5, 6 * L), (2, 2, 4 * L * L),
                    (2, 4, -6 * L), (2, 5, 2 * L * L), (4, 4, 12), (4, 5, -6 * L),
                    (5, 5, 4 * L * L)):
        k[i, j] = k[j, i] = v * b
    return k


def _g_local(N, L):
    g = np.zeros((6, 6))
    c = N / (30 * L)
    for i, j, v in ((1, 1, 36), (1, 2, 3 * L), (1, 4, -36), (1, 5, 3 * L), (2, 2, 4 * L * L),
                    (2, 4, -3 * L), (2, 5, -L * L), (4, 4, 36), (4, 5, -3 * L),
                    (5, 5, 4 * L * L)):
        g[i, j] = g[j, i] = v * c
    return g


def cut_alpha(m, axial, cut):
    """The least α with det(K + α K_G(N)) = 0 on ``cut`` cubic elements a
    member, N per member (tension positive) given."""
    dof, nd = {}, 0
    for n in m["nodes"]:
        dof[n], nd = [nd, nd + 1, nd + 2], nd + 3
    parts = []
    for mem in m["members"]:
        p, q, L = geometry(m, mem)
        ids = [dof[mem["i"]]] + [[nd + 3 * k, nd + 3 * k + 1, nd + 3 * k + 2]
                                 for k in range(cut - 1)] + [dof[mem["j"]]]
        nd += 3 * (cut - 1)
        for end, hinged in ((0, mem["hinge_i"]), (-1, mem["hinge_j"])):
            if hinged:
                ids[end], nd = ids[end][:2] + [nd], nd + 1
        c, s = (q - p) / L
        T = np.zeros((6, 6))
        T[:3, :3] = T[3:, 3:] = [[c, s, 0], [-s, c, 0], [0, 0, 1]]
        for k in range(cut):
            parts.append((ids[k] + ids[k + 1], T, mem, L / cut))
    K, KG = np.zeros((nd, nd)), np.zeros((nd, nd))
    for ix, T, mem, l in parts:
        K[np.ix_(ix, ix)] += T.T @ _k_local(mem["A"], mem["I"], l) @ T
        KG[np.ix_(ix, ix)] += T.T @ _g_local(axial[mem["name"]], l) @ T
    held = {dof[n][d] for n, ds in m["fixed"].items() for d in ds}
    held |= {dof[n][1] for n in m.get("pads", ())}     # closed pads hold y
    held |= {k for k in range(nd) if K[k, k] == 0.0}
    free = np.array([k for k in range(nd) if k not in held])
    mu = la.eigh(-KG[np.ix_(free, free)], K[np.ix_(free, free)], eigvals_only=True)
    return 1.0 / mu.max() if mu.max() > 0 else np.inf


def reference_alpha(m, axial):
    """(α_cr, its error bar): n and 2n cuts extrapolated as n⁻⁴, n = 16 on
    frames of up to 12 members, 8 up to 40, 4 beyond (dense eigenvalues).
    (8 and 16 put a frame whose columns are in tension 3e-5 off the
    converged value: tension resolves slower.)"""
    n = 16 if len(m["members"]) <= 12 else 8 if len(m["members"]) <= 40 else 4
    a8, a16 = cut_alpha(m, axial, n), cut_alpha(m, axial, 2 * n)
    if not np.isfinite(a16):
        return np.inf, 0.0
    return a16 + (a16 - a8) / 15, abs(a16 - a8) / 15


def linear_axial(m):
    """Members' axial forces of a first-order solve of the uncut plane model."""
    dof, nd = {}, 0
    for n in m["nodes"]:
        dof[n], nd = [nd, nd + 1, nd + 2], nd + 3
    parts = []
    for mem in m["members"]:
        p, q, L = geometry(m, mem)
        ids = [list(dof[mem["i"]]), list(dof[mem["j"]])]
        for end, hinged in ((0, mem["hinge_i"]), (1, mem["hinge_j"])):
            if hinged:
                ids[end], nd = ids[end][:2] + [nd], nd + 1
        c, s = (q - p) / L
        T = np.zeros((6, 6))
        T[:3, :3] = T[3:, 3:] = [[c, s, 0], [-s, c, 0], [0, 0, 1]]
        parts.append((ids[0] + ids[1], T, mem, L))
    K, F = np.zeros((nd, nd)), np.zeros(nd)
    for n, f in m["loads"].items():
        F[dof[n]] += f
    fixed_end = {}
    for ix, T, mem, L in parts:
        k = _k_local(mem["A"], mem["I"], L)
        K[np.ix_(ix, ix)] += T.T @ k @ T
        fe = np.zeros(6)
        for nm, wx, wy in m["udl"]:
            if nm == mem["name"]:
                fe += [wx * L / 2, wy * L / 2, wy * L * L / 12, wx * L / 2, wy * L / 2,
                       -wy * L * L / 12]
        for nm, a, px, py in m["point"]:
            if nm == mem["name"]:
                b = L - a
                fe += [px * b / L, py * b * b * (3 * a + b) / L ** 3, py * a * b * b / L ** 2,
                       px * a / L, py * a * a * (a + 3 * b) / L ** 3, -py * a * a * b / L ** 2]
        F[ix] += T.T @ fe
        fixed_end[mem["name"]] = fe
    held = {dof[n][d] for n, ds in m["fixed"].items() for d in ds}
    held |= {dof[n][1] for n in m.get("pads", ())}     # closed pads hold y
    held |= {k for k in range(nd) if K[k, k] == 0.0}
    free = np.array([k for k in range(nd) if k not in held])
    u = np.zeros(nd)
    u[free] = la.solve(K[np.ix_(free, free)], F[free])
    out = {}
    for ix, T, mem, L in parts:
        d = T @ u[ix]
        # mean of the ends' axial forces (an axial span load makes them differ)
        out[mem["name"]] = E * mem["A"] / L * (d[3] - d[0])     # no axial span loads here
    return out
