"""Frames: qpcontact's plane-frame analysis against OpenSees (openseespy) and
PyNite, side by side in one run, on the same models built from one plain
description, each peer solving the same nonlinear contact problem by its own
iteration (which supports lift off, stick or slip is found, never given).

Models
------
- A continuous beam of N spans (6 m, 2 elements per span, concrete E = 30e6
  kN/m², A = 0.32 m², I = 0.017 m⁴) on N + 1 elastic compression-only
  frictional supports (k = 6e4 kN/m normal and tangential, f = 0.3), pinned in
  ux at the left end (whose contact is frictionless: the pin holds that
  direction), self-weight 18 kN/m, 250 kN uplift at N/10 supports (they lift
  off) and 100 kN pushing the right end to the left (the supports near it
  slip, the others stick).  N = 50, 200 (401 nodes) and 1000.
- A 20-storey, 3-bay frame on a foundation beam resting on 17 elastic
  frictional contacts (tests/formulations/frames/frame_cases.py's ``tower``: f = 0.5,
  k = 5e5) at p = 0.7 x its tipping load (tests/formulations/frames/test_plane_limits.py's
  P_TIP; for short towers, which slide first, 0.7 x their sliding load): the
  windward supports lift off, the tower stands on friction alone.

- A 10-storey concrete space frame, 3 x 3 bays of 6 m, on 16 frictional pads
  (formulations/frames/space/space_tower.py's ``space_tower``: f = 0.5, 8
  facets, elastic pads k = 5e6 kN/m) under 1.0 D + p W, at p = 7.5 (the
  windward corner pad lifted off, the others stick: no pad slips, so
  qpcontact's faceted cone and OpenSees' circular one give the same
  problem), 9 and 12 (pads lift off and slip: the codes differ by the
  faceting); then qpcontact's trace of p W on D to the collapse (rigid pads,
  no peer runs one), and its rigid pads against OpenSees' penalty ones
  (k = 5e6 ... 5e8, p = 7.5).  benchmarks/frames_space.py reads the
  SpaceFrame into OpenSees (flatSliderBearing 3-D elements, Krylov-Newton:
  Newton does not converge here) and PyNite (the frictionless variant on
  compression-only springs, every pad dowelled in x and y).

The contact law (qpcontact's holonomic Coulomb law): a normal spring k in
series with a rigid unilateral link, a tangential spring k with
|X_t| <= f X_n, total slip against total force.  For one proportional load
step the incremental elastic-plastic law of a peer is the same law.

- OpenSees: a frictional contact is a zero-length ``flatSliderBearing``
  (Coulomb friction model with f, kInit = k, an Elastic axial material of
  stiffness k; the element releases shear and axial force when the axial
  force turns to tension, and its yield force is f N), a frictionless one a
  ``zeroLength`` element with an ``ENT`` (elastic-no-tension) material; one
  static load step (LoadControl 1.0), Newton, NormUnbalance 1e-10 x the sum
  of the loads, at most 100 iterations, BandSPD.  Newton ends exactly (to
  rounding) once it has the right contact states: reactions agree to 1e-11
  or better, except qpcontact's own forward error where R's dropped
  rounding-level entries meet long lifted stretches (the 50-span beam:
  1.7e-9, while OpenSees and PyNite agree to 3e-13 there).  openseespy's
  Linux wheel needs the system's libblas.so.3 (Debian: libblas3).
- PyNite has compression-only springs (``def_support_spring(node, "DY", k,
  "-")``) and no friction: it runs on the frictionless variant of each model
  (f = 0; the tower gets a ux pin at its left foundation node), which
  qpcontact solves too for that comparison.  On the straight beam the normal
  forces do not depend on friction (bending and axial force decouple); on the
  tower they do.

Timings: each code builds a fresh model for every repetition (so nothing is
reused between repetitions); "solve" is the analysis alone (qpcontact:
``Frame.solve``, which assembles, solves, recovers and checks; OpenSees:
``analyze`` + ``reactions``; PyNite: ``analyze``), "+build" includes building
the model through the code's API.  Median of --repeat after one warm-up,
or of fewer runs where they exceed --budget seconds per code and model (the
table's n).  The cold start of qpcontact (import, then the first solve of
the 200-span beam) is measured in a fresh interpreter.

Targets: qpcontact within 2x of OpenSees on the 200-span beam, the
1000-span beam and the 20-storey frame (judged on the analysis alone, wall
time; the ratio of CPU times and the ratio with the build included are
printed beside it); the same ratio is printed for the 10-storey space frame.
The last lines sum the four ratios up.

    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 .venv/bin/python benchmarks/frames.py \\
        [--spans 50,200,1000] [--storeys 20] [--repeat 5] [--budget 60]
        [--space-storeys 10] [--space-facets 8,32,128] [--no-pynite]
        [--no-opensees] [--no-cold]

Exits non-zero when a qpcontact result is not ok or a peer's reactions
differ by more than 1e-6 of the largest reaction (or a peer fails) — on
the space frame where no pad slips; where pads slip, by more than
SLIP_AGREEMENT (the faceted cone's difference, measured 3e-3 to 2e-2).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from dataclasses import dataclass, field, replace

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, ROOT)
from benchmarks.frames_space import opensees_solve  # noqa: E402  (one analysis step, both rows)
from formulations.frames import Frame  # noqa: E402
from qpcontact.core.errors import QpcontactError  # noqa: E402

AGREEMENT = 1e-6
#: the space frame where pads slip: faceted against circular cones
SLIP_AGREEMENT = 5e-2
#: the targets: qpcontact / OpenSees, analysis alone
TARGETS = {"beam 200": 2.0, "beam 1000": 2.0, "tower 20": 2.0}


@dataclass
class Model:
    """A plane frame in plain lists, built into each code.  Member loads are
    uniform, per unit length along global y, on horizontal members only (so
    that global and member axes agree in every code); contacts have the
    normal (0, 1) and one stiffness k, normal and tangential."""

    name: str
    nodes: dict                                      # name -> (x, y)
    members: list                                    # (name, i, j, E, A, I)
    member_wy: dict = field(default_factory=dict)    # member -> wy
    node_loads: list = field(default_factory=list)   # (node, fx, fy)
    pins: dict = field(default_factory=dict)         # node -> fixed dofs among ux, uy
    contacts: list = field(default_factory=list)     # (node, k, friction)

    def load_scale(self) -> float:
        """The sum of the loads' magnitudes."""
        span = {name: abs(self.nodes[j][0] - self.nodes[i][0]) for name, i, j, *_ in self.members}
        return (sum(abs(w) * span[name] for name, w in self.member_wy.items())
                + sum(abs(fx) + abs(fy) for _, fx, fy in self.node_loads))

    def frictionless(self, pin: str | None = None) -> "Model":
        """f = 0 everywhere; ``pin`` gets a ux support (the frame would
        otherwise slide away under its lateral loads)."""
        pins = dict(self.pins)
        if pin is not None:
            pins[pin] = tuple(sorted(set(pins.get(pin, ())) | {"ux"}))
        return replace(self, name=self.name + " (f = 0)", pins=pins,
                       contacts=[(n, k, 0.0) for n, k, _ in self.contacts])


def beam(spans: int) -> Model:
    E, A, I, K = 30e6, 0.32, 0.017, 6e4
    rng = np.random.default_rng(spans)
    nodes = {f"N{k}": (3.0 * k, 0.0) for k in range(2 * spans + 1)}
    members = [(f"M{k}", f"N{k}", f"N{k + 1}", E, A, I) for k in range(2 * spans)]
    uplift = rng.choice(np.arange(1, spans), size=max(1, spans // 10), replace=False)
    loads = [(f"N{2 * int(s)}", 0.0, 250.0) for s in sorted(uplift)]
    loads.append((f"N{2 * spans}", -100.0, 0.0))
    # the pin holds N0 in ux, so its contact carries no friction (qpcontact
    # refuses a tangential link along a fixed dof)
    contacts = [(f"N{2 * s}", K, 0.3 if s else 0.0) for s in range(spans + 1)]
    return Model(f"beam {spans}", nodes, members, {m[0]: -(25.0 * A + 10.0) for m in members},
                 loads, {"N0": ("ux",)}, contacts)


def p_limit(storeys: int = 20, bays: int = 3) -> float:
    """The load factor p at which the tower fails, the smaller of tipping by
    moments about the toe (the last contact, 3 m beyond the last column:
    tests/formulations/frames/test_plane_limits.py's P_TIP for 20 storeys, 3 bays) and sliding
    when 10 p per floor exceeds f x the weight (short towers)."""
    width = 6.0 * bays
    weight = storeys * bays * 6.0 * 30.0
    tipping = weight * (width + 3.0 - width / 2) / (10.0 * 3.5 * storeys * (storeys + 1) / 2)
    return min(tipping, 0.5 * weight / (10.0 * storeys))


def tower(storeys: int = 20, bays: int = 3, p: float | None = None) -> Model:
    """tests/formulations/frames/frame_cases.py's ``tower`` with its two cases folded into
    one: 30 kN/m on every beam plus 10 p kN at every floor of the left column."""
    p = 0.7 * p_limit(storeys, bays) if p is None else p
    col, bm = (210e6, 1.5e-2, 5e-4), (210e6, 8e-3, 2e-4)
    xs = [6.0 * j for j in range(bays + 1)]
    nodes = {f"N{s}_{j}": (x, 3.5 * s) for s in range(storeys + 1) for j, x in enumerate(xs)}
    members, wy = [], {}
    for s in range(storeys):
        members += [(f"C{s}_{j}", f"N{s}_{j}", f"N{s + 1}_{j}", *col) for j in range(bays + 1)]
    for s in range(1, storeys + 1):
        for j in range(bays):
            members.append((f"B{s}_{j}", f"N{s}_{j}", f"N{s}_{j + 1}", *bm))
            wy[f"B{s}_{j}"] = -30.0
    base = []
    for k, x in enumerate(np.arange(-3.0, xs[-1] + 3.01, 1.5)):
        hit = [j for j, xx in enumerate(xs) if abs(x - xx) < 1e-9]
        name = f"N0_{hit[0]}" if hit else f"F{k}"
        nodes.setdefault(name, (float(x), 0.0))
        base.append(name)
    members += [(f"G{k}", a, b, 30e6, 1.2, 0.36) for k, (a, b) in enumerate(zip(base, base[1:]))]
    loads = [(f"N{s}_0", 10.0 * p, 0.0) for s in range(1, storeys + 1)]
    return Model(f"tower {storeys}", nodes, members, wy, loads, {},
                 [(n, 5e5, 0.5) for n in base])


# -- qpcontact ----------------------------------------------------------------

def ours_build(m: Model) -> Frame:
    fr = Frame()
    for name, (x, y) in m.nodes.items():
        fr.add_node(name, x, y)
    for name, i, j, E, A, I in m.members:
        fr.add_member(i, j, E, A, I, name=name)
    for name, w in m.member_wy.items():
        fr.add_distributed_load(name, wy=w, case="D")
    for node, fx, fy in m.node_loads:
        fr.add_load(node, fx=fx, fy=fy, case="D")
    for node, dofs in m.pins.items():
        fr.add_support(node, fix=dofs)
    for node, k, f in m.contacts:
        fr.add_contact(node, normal=(0.0, 1.0), friction=f, stiffness=k)
    return fr


def ours_solve(fr: Frame):
    return fr.solve(combination={"D": 1.0})


def ours_reactions(m: Model, res) -> np.ndarray:
    """(X_t, X_n) of every contact (the force on the structure along x and
    y), then the pins' reactions at their fixed dofs."""
    out = []
    for node, _, _ in m.contacts:
        s = res.supports[node]
        out += [s.tangential, s.normal]
    for node, dofs in m.pins.items():
        out += [res.reactions[node]["ux uy".split().index(d)] for d in dofs]
    return np.array(out)


# -- OpenSees -----------------------------------------------------------------

def opensees_build(m: Model):
    import openseespy.opensees as ops

    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    tag = {name: t for t, name in enumerate(m.nodes, start=1)}
    for name, (x, y) in m.nodes.items():
        ops.node(tag[name], x, y)
    for node, dofs in m.pins.items():
        ops.fix(tag[node], int("ux" in dofs), int("uy" in dofs), 0)
    ops.geomTransf("Linear", 1)
    for e, (_, i, j, E, A, I) in enumerate(m.members, start=1):
        ops.element("elasticBeamColumn", e, tag[i], tag[j], A, E, I, 1)
    ground, mats, frns = {}, {}, {}
    e0, g0 = len(m.members) + 1, len(m.nodes) + 1
    ops.uniaxialMaterial("Elastic", 1, 0.0)       # the slider's moment: none (zero length)
    for c, (node, k, f) in enumerate(m.contacts):
        gtag = g0 + c
        ground[node] = gtag
        ops.node(gtag, *m.nodes[node])
        ops.fix(gtag, 1, 1, 1)
        if f > 0:
            if k not in mats:
                mats[k] = len(mats) + 2
                ops.uniaxialMaterial("Elastic", mats[k], k)
            if f not in frns:
                frns[f] = len(frns) + 1
                ops.frictionModel("Coulomb", frns[f], f)
            # axial (basic x) along global y, shear along -x: zero length, so
            # the slider's P-delta moments fall on the fixed ground node
            ops.element("flatSliderBearing", e0 + c, gtag, tag[node], frns[f], k,
                        "-P", mats[k], "-Mz", 1, "-orient", 0, 1, 0, -1, 0, 0)
        else:
            key = ("ENT", k)
            if key not in mats:
                mats[key] = len(mats) + 2
                ops.uniaxialMaterial("ENT", mats[key], k)
            ops.element("zeroLength", e0 + c, gtag, tag[node], "-mat", mats[key], "-dir", 2)
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    etag = {name: e for e, (name, *_) in enumerate(m.members, start=1)}
    for name, w in m.member_wy.items():
        ops.eleLoad("-ele", etag[name], "-type", "-beamUniform", w)
    for node, fx, fy in m.node_loads:
        ops.load(tag[node], fx, fy, 0.0)
    ops.constraints("Plain")
    ops.numberer("RCM")
    # the fastest of UmfPack, BandGen, BandSPD, ProfileSPD, SparseSYM and
    # SparseGEN on these models (UmfPack: 2x slower); the tangent is
    # symmetric (the sliders' P-delta terms sit on the fixed ground rows)
    ops.system("BandSPD")
    # Newton on this piecewise-linear problem ends exactly once it has the
    # right contact states; the tolerance only needs to sit above rounding
    ops.test("NormUnbalance", 1e-10 * m.load_scale(), 100)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    return tag, ground


def opensees_reactions(m: Model, built) -> np.ndarray:
    import openseespy.opensees as ops

    tag, ground = built
    out = []
    for node, _, _ in m.contacts:
        fx, fy, _ = ops.nodeReaction(ground[node])
        out += [fx, fy]
    for node, dofs in m.pins.items():
        r = ops.nodeReaction(tag[node])
        out += [r["ux uy".split().index(d)] for d in dofs]
    return np.array(out)


# -- PyNite -------------------------------------------------------------------

def pynite_build(m: Model):
    from Pynite import FEModel3D

    if any(f > 0 for _, _, f in m.contacts):
        raise ValueError("PyNite has no friction: give it the frictionless variant")
    fe = FEModel3D()
    mats = {}
    for name, (x, y) in m.nodes.items():
        fe.add_node(name, x, y, 0.0)
    fixed = {node: set(d) for node, d in m.pins.items()}
    # the plane frame in a 3-D code: out-of-plane dofs held at every node
    for name in m.nodes:
        fe.def_support(name, support_DX="ux" in fixed.get(name, ()),
                       support_DY="uy" in fixed.get(name, ()), support_DZ=True,
                       support_RX=True, support_RY=True)
    for name, i, j, E, A, I in m.members:
        if (E, A, I) not in mats:
            key = f"s{len(mats)}"
            mats[(E, A, I)] = key
            fe.add_material(key, E, E / 2.4, 0.2, 0.0)
            # Iy = Iz: a member's local axes do not matter in its plane
            fe.add_section(key, A, I, I, 2 * I)
        fe.add_member(name, i, j, mats[(E, A, I)], mats[(E, A, I)])
    for name, w in m.member_wy.items():
        fe.add_member_dist_load(name, "FY", w, w, case="D")
    for node, fx, fy in m.node_loads:
        if fx:
            fe.add_node_load(node, "FX", fx, case="D")
        if fy:
            fe.add_node_load(node, "FY", fy, case="D")
    for node, k, _ in m.contacts:
        fe.def_support_spring(node, "DY", k, "-")     # resists downward motion only
    fe.add_load_combo("C", {"D": 1.0})
    return fe


def pynite_solve(fe):
    fe.analyze(check_statics=False)


def pynite_reactions(m: Model, fe) -> np.ndarray:
    """The springs' forces -k uy (PyNite's RxnFY of a spring node is the
    spring's force), then the pins' reactions."""
    out = []
    for node, _, _ in m.contacts:
        out += [0.0, fe.nodes[node].RxnFY["C"]]
    for node, dofs in m.pins.items():
        n = fe.nodes[node]
        out += [{"ux": n.RxnFX, "uy": n.RxnFY}[d]["C"] for d in dofs]
    return np.array(out)


# -- timing -------------------------------------------------------------------

@dataclass
class Timing:
    solve: float          # median, analysis alone
    total: float          # median, build + analysis
    runs: int             # how many runs the medians are of
    built: object         # the last run's model and answer
    out: object
    cpu: float = float("nan")   # median CPU time (time.process_time), analysis alone


def timed(build, solve, repeat: int, budget: float) -> Timing:
    """Median of ``repeat`` runs after one warm-up (first-call costs are the
    cold start's, reported apart); each run builds its own model so that no
    code reuses state from an earlier run.  Runs stop once they have taken
    ``budget`` seconds (at least one is timed); a warm-up that alone takes
    longer is the only run (the smaller models before it warmed the code)."""
    solves, totals, cpus = [], [], []
    start = time.perf_counter()
    for r in range(repeat + 1):
        t0 = time.perf_counter()
        built = build()
        t1, c1 = time.perf_counter(), time.process_time()
        out = solve(built)
        t2, c2 = time.perf_counter(), time.process_time()
        if r or t2 - start > budget:
            solves.append(t2 - t1)
            totals.append(t2 - t0)
            cpus.append(c2 - c1)
        if solves and time.perf_counter() - start > budget:
            break
    return Timing(statistics.median(solves), statistics.median(totals), len(solves), built, out,
                  statistics.median(cpus))


def agreement(ours: np.ndarray, ref: np.ndarray) -> float:
    return float(np.abs(ours - ref).max() / np.abs(ref).max())


def states(res) -> str:
    count = {}
    for s in res.supports.values():
        count[s.state] = count.get(s.state, 0) + 1
    return ", ".join(f"{v} {k}" for k, v in sorted(count.items()))


COLD = """
import time
t0 = time.perf_counter()
import formulations.frames
t1 = time.perf_counter()
from benchmarks import frames as bench
fr = bench.ours_build(bench.beam(200))
t2 = time.perf_counter()
res = bench.ours_solve(fr)
t3 = time.perf_counter()
print(t1 - t0, t3 - t2, res.ok)
"""


def cold_start() -> tuple:
    """(import, first solve of the 200-span beam) in a fresh interpreter:
    what a user's first script pays."""
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    out = subprocess.run([sys.executable, "-c", COLD], capture_output=True, text=True, env=env,
                         cwd=ROOT, check=True).stdout.split()
    return float(out[0]), float(out[1]), out[2] == "True"


def fmt_ms(t: float) -> str:
    return f"{1e3 * t:9.1f}"


def ours_timed(m: Model, args, failures):
    """qpcontact's timing, or None (with the failure recorded) where it
    raises: a proved "no equilibrium" is a wrong model here, not a result."""
    try:
        q = timed(lambda: ours_build(m), ours_solve, args.repeat, args.budget)
    except QpcontactError as exc:
        failures.append(f"{m.name}: qpcontact raised {type(exc).__name__}: {exc}")
        print(f"{m.name:>10}  qpcontact raised {type(exc).__name__}")
        return None
    if not q.out.ok:
        failures.append(f"{m.name}: qpcontact not ok: {q.out.message}")
    return q


def opensees_table(models, args, failures, ratios):
    print("\nqpcontact against OpenSees, the same frictional model")
    print(f"{'model':>10} {'qpc':>9} {'qpc+b':>9} {'OS':>9} {'OS+b':>9} {'qpc/OS':>7} "
          f"{'cpu':>5} {'+build':>7} {'target':>8} {'ΔR/R':>8} {'n':>4}  qpcontact route, "
          f"states; OpenSees Newton iterations")
    for m in models:
        q = ours_timed(m, args, failures)
        if q is None:
            continue
        o = timed(lambda: opensees_build(m), opensees_solve, args.repeat, args.budget)
        rc, iters = o.out
        diff = agreement(ours_reactions(m, q.out), opensees_reactions(m, o.built))
        if rc != 0 or not diff <= AGREEMENT:
            failures.append(f"{m.name}: OpenSees analyze returned {rc}, reactions differ by "
                            f"{diff:.1e}")
        ratio = q.solve / o.solve
        target = TARGETS.get(m.name)
        tgt = "" if target is None else f"≤{target:g} " + ("ok" if ratio <= target else "NO")
        if target is not None:
            ratios[m.name] = (ratio, q.cpu / o.cpu, tgt)
        print(f"{m.name:>10} {fmt_ms(q.solve)} {fmt_ms(q.total)} {fmt_ms(o.solve)} "
              f"{fmt_ms(o.total)} {ratio:7.2f} {q.cpu / o.cpu:5.2f} {q.total / o.total:7.2f} "
              f"{tgt:>8} {diff:8.1e} "
              f"{q.runs:>2}/{o.runs}  {q.out.route}, ok={q.out.ok}, {states(q.out)}; {iters}")


def pynite_table(models, args, failures, with_opensees):
    """PyNite has no friction: both codes solve the frictionless variant.
    With OpenSees at hand its answer (untimed) says which code a
    disagreement comes from (OS↔PyN: OpenSees against PyNite)."""
    print("\nqpcontact against PyNite, the frictionless variant (PyNite has no friction)")
    print(f"{'model':>10} {'qpc':>9} {'qpc+b':>9} {'PyNite':>9} {'PyN+b':>9} {'PyN/qpc':>8} "
          f"{'+build':>7} {'ΔR/R':>8} {'OS↔PyN':>8} {'n':>4}  qpcontact route, states")
    for m in models:
        m0 = m.frictionless(pin=None if m.pins else m.contacts[0][0])
        q = ours_timed(m0, args, failures)
        if q is None:
            continue
        p = timed(lambda: pynite_build(m0), pynite_solve, args.repeat, args.budget)
        ref = pynite_reactions(m0, p.built)
        diff = agreement(ours_reactions(m0, q.out), ref)
        if not diff <= AGREEMENT:
            failures.append(f"{m0.name}: PyNite's reactions differ by {diff:.1e}")
        peers = ""
        if with_opensees:
            built = opensees_build(m0)
            opensees_solve(built)
            peers = f"{agreement(opensees_reactions(m0, built), ref):8.1e}"
        print(f"{m.name:>10} {fmt_ms(q.solve)} {fmt_ms(q.total)} {fmt_ms(p.solve)} "
              f"{fmt_ms(p.total)} {p.solve / q.solve:8.1f} {p.total / q.total:7.1f} {diff:8.1e} "
              f"{peers:>8} {q.runs:>2}/{p.runs}  {q.out.route}, ok={q.out.ok}, {states(q.out)}")


# -- the space frame ---------------------------------------------------------

SPACE_K, SPACE_P, PENALTY_K = 5e6, (7.5, 9.0, 12.0), (5e6, 5e7, 5e8)


def space_opensees_table(storeys, args, failures, ratios):
    from benchmarks import frames_space as fs
    from formulations.frames.space.space_tower import space_tower

    print(f"\nqpcontact against OpenSees, the {storeys}-storey space frame on 16 elastic "
          f"frictional pads (k = {SPACE_K:g}, f = 0.5, 8 facets) at 1.0 D + p W")
    print(f"{'model':>14} {'qpc':>9} {'qpc+b':>9} {'OS':>9} {'OS+b':>9} {'qpc/OS':>7} "
          f"{'+build':>7} {'ΔR/R':>8} {'n':>5}  qpcontact route, states; states alike; "
          "OpenSees iterations")
    for p in SPACE_P:
        combo = {"D": 1.0, "W": p}
        name = f"tower3d p={p:g}"
        try:
            q = timed(lambda: space_tower(storeys, stiffness=SPACE_K),
                      lambda fr: fr.solve(combination=combo), args.repeat, args.budget)
        except QpcontactError as exc:
            failures.append(f"{name}: qpcontact raised {type(exc).__name__}: {exc}")
            continue
        if not q.out.ok:
            failures.append(f"{name}: qpcontact not ok: {q.out.message}")
        fr = q.built
        o = timed(lambda: fs.opensees_build(fr, combo), fs.opensees_solve, args.repeat,
                  args.budget)
        rc, iters = o.out
        ours, theirs = fs.ours_forces(fr, q.out), fs.opensees_forces(fr, o.built)
        diff = agreement(ours, theirs)
        slipping = any(s.state == "slip" for s in q.out.supports.values())
        alike = sum(a == s.state for a, s in zip(fs.states_from_forces(fr, theirs),
                                                  q.out.supports.values()))
        if rc != 0 or not diff <= (SLIP_AGREEMENT if slipping else AGREEMENT):
            failures.append(f"{name}: OpenSees analyze returned {rc} after {iters} iterations, "
                            f"forces differ by {diff:.1e}")
        if p == SPACE_P[0]:
            ratios[f"space tower {storeys} ({name})"] = (q.solve / o.solve, q.cpu / o.cpu, "")
        print(f"{name:>14} {fmt_ms(q.solve)} {fmt_ms(q.total)} {fmt_ms(o.solve)} "
              f"{fmt_ms(o.total)} {q.solve / o.solve:7.2f} {q.total / o.total:7.2f} {diff:8.1e} "
              f"{q.runs:>2}/{o.runs}  {q.out.route}, ok={q.out.ok}, {states(q.out)}; "
              f"{alike}/{len(fr.contacts)}; {iters}" + ("  (faceted cone)" if slipping else ""))
    # rigid pads (qpcontact) against OpenSees' penalty pads: where no pad
    # slips the difference is the pads' compliance, O(1/k)
    p = SPACE_P[0]
    combo = {"D": 1.0, "W": p}
    rigid = space_tower(storeys)
    ours = fs.ours_forces(rigid, rigid.solve(combination=combo))
    words = []
    for k in PENALTY_K:
        fr = space_tower(storeys, stiffness=k)
        built = fs.opensees_build(fr, combo)
        rc, iters = fs.opensees_solve(built)
        words.append(f"k = {k:.0e}: " + (f"{agreement(ours, fs.opensees_forces(fr, built)):.1e}"
                                          if rc == 0 else f"no convergence ({iters} iterations)"))
    print(f"{'':>14} rigid pads (qpcontact) against OpenSees' penalty pads at p = {p:g}, ΔR/R: "
          + "; ".join(words))
    if args.space_facets:
        # where pads slip: the faceted cone against OpenSees' circle as the
        # facets multiply (a facet fixes the slip's direction, not the force's
        # along it: the difference falls like 1/m, not like the 1/m² of the
        # polygon's reach beyond the circle)
        p = SPACE_P[1]
        combo = {"D": 1.0, "W": p}
        fr = space_tower(storeys, stiffness=SPACE_K)
        built = fs.opensees_build(fr, combo)
        fs.opensees_solve(built)
        theirs = fs.opensees_forces(fr, built)
        words = []
        for m in (int(v) for v in args.space_facets.split(",") if v):
            t = timed(lambda: space_tower(storeys, stiffness=SPACE_K, facets=m),
                      lambda fr: fr.solve(combination=combo), 1, args.budget)
            words.append(f"{m}: {agreement(fs.ours_forces(t.built, t.out), theirs):.1e} "
                         f"({1e3 * t.solve:.0f} ms)")
        print(f"{'':>14} facets of qpcontact's cones at p = {p:g}, ΔR/R against OpenSees "
              "(qpcontact's solve): " + "; ".join(words))


def space_trace_row(storeys, args, failures):
    """qpcontact's trace of p W on D to the collapse (no peer runs one)."""
    from formulations.frames.space.space_tower import space_tower

    print(f"\nqpcontact's trace, the {storeys}-storey space frame: 1.0 D + p W, p from 0 to "
          "the collapse")
    print(f"{'pads':>14} {'trace':>9} {'+build':>9} {'n':>3}  events, ending")
    for label, k in (("rigid", None), (f"k = {SPACE_K:g}", SPACE_K)):
        t = timed(lambda: space_tower(storeys, stiffness=k),
                  lambda fr: fr.trace(constant={"D": 1.0}, variable="W"), args.repeat,
                  args.budget)
        tr = t.out
        if not tr.ok or tr.ended != "collapse":
            failures.append(f"tower3d trace ({label}): ended {tr.ended}, ok={tr.ok}")
        print(f"{label:>14} {fmt_ms(t.solve)} {fmt_ms(t.total)} {t.runs:>3}  "
              f"{len(tr.events)} changes of the working scheme, {tr.ended} at p = "
              f"{tr.p_end:.6g}, ok={tr.ok}")


def space_pynite_table(storeys, args, failures, with_opensees):
    """The frictionless variant: every pad is held in ux and uy by a
    bilateral support (a dowel: the pads' horizontal reactions are compared
    too), its contact along z alone."""
    from benchmarks import frames_space as fs
    from formulations.frames.space.space_tower import space_tower

    def build():
        fr = space_tower(storeys, stiffness=SPACE_K, friction=0.0)
        for c in fr.contacts:
            fr.add_support(c.node, fix=("ux", "uy"))
        return fr

    print(f"\nqpcontact against PyNite, the {storeys}-storey space frame, frictionless "
          "variant (compression-only pads, dowelled in x and y)")
    print(f"{'model':>14} {'qpc':>9} {'qpc+b':>9} {'PyNite':>9} {'PyN+b':>9} {'PyN/qpc':>8} "
          f"{'+build':>7} {'ΔR/R':>8} {'OS↔PyN':>8} {'n':>5}  qpcontact route, states")
    for p in SPACE_P:
        combo = {"D": 1.0, "W": p}
        name = f"tower3d p={p:g}"
        q = timed(build, lambda fr: fr.solve(combination=combo), args.repeat, args.budget)
        if not q.out.ok:
            failures.append(f"{name} (f = 0): qpcontact not ok: {q.out.message}")
        fr = q.built
        pn = timed(lambda: fs.pynite_build(fr, combo), fs.pynite_solve, args.repeat, args.budget)
        ref = fs.pynite_forces(fr, pn.built)
        diff = agreement(fs.ours_forces(fr, q.out), ref)
        if not diff <= AGREEMENT:
            failures.append(f"{name} (f = 0): PyNite's forces differ by {diff:.1e}")
        peers = ""
        if with_opensees:
            built = fs.opensees_build(fr, combo)
            fs.opensees_solve(built)
            peers = f"{agreement(fs.opensees_forces(fr, built), ref):8.1e}"
        print(f"{name:>14} {fmt_ms(q.solve)} {fmt_ms(q.total)} {fmt_ms(pn.solve)} "
              f"{fmt_ms(pn.total)} {pn.solve / q.solve:8.1f} {pn.total / q.total:7.1f} "
              f"{diff:8.1e} {peers:>8} {q.runs:>2}/{pn.runs}  {q.out.route}, ok={q.out.ok}, "
              f"{states(q.out)}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--spans", default="50,200,1000", help="beam sizes, comma-separated")
    ap.add_argument("--storeys", type=int, default=20, help="tower storeys (0: no tower)")
    ap.add_argument("--space-storeys", type=int, default=10,
                    help="storeys of the space frame (0: none)")
    ap.add_argument("--space-facets", default="",
                    help="facet counts of the space frame's cones to compare, e.g. 8,32,128")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--budget", type=float, default=60.0,
                    help="seconds of runs per code and model before the median is taken")
    ap.add_argument("--no-pynite", action="store_true")
    ap.add_argument("--no-opensees", action="store_true")
    ap.add_argument("--no-cold", action="store_true", help="skip the fresh-interpreter start")
    args = ap.parse_args(argv)
    # each row as soon as it is measured: a slow model shows where it is
    sys.stdout.reconfigure(line_buffering=True)
    peers = {}
    for name, module, flag in (("OpenSees", "openseespy.opensees", args.no_opensees),
                               ("PyNite", "Pynite", args.no_pynite)):
        if flag:
            continue
        try:
            __import__(module)
            peers[name] = True
        except (ImportError, RuntimeError) as exc:   # openseespy raises RuntimeError without BLAS
            print(f"{name} not available ({exc}): skipped")
    models = [beam(int(s)) for s in args.spans.split(",") if s]
    if args.storeys:
        models.append(tower(args.storeys))
    failures, ratios = [], {}
    print(f"\ntimes in ms, median of up to {args.repeat} runs after a warm-up (n: runs "
          f"qpcontact/peer); ΔR/R = max |ΔR| / max |R| over contact and pin reactions")
    if "OpenSees" in peers:
        opensees_table(models, args, failures, ratios)
    if "PyNite" in peers:
        pynite_table(models, args, failures, "OpenSees" in peers)
    if args.space_storeys:
        if "OpenSees" in peers:
            space_opensees_table(args.space_storeys, args, failures, ratios)
        space_trace_row(args.space_storeys, args, failures)
        if "PyNite" in peers:
            space_pynite_table(args.space_storeys, args, failures, "OpenSees" in peers)
    from benchmarks.frames_second_order import table as second_order_table
    failures += ["second order"] * second_order_table(repeat=args.repeat)
    if not args.no_cold:
        t_import, t_first, ok = cold_start()
        print(f"\ncold start (fresh interpreter): import formulations.frames {1e3 * t_import:.0f} "
              f"ms, first solve (200-span beam) {1e3 * t_first:.0f} ms, ok={ok}")
        if not ok:
            failures.append("cold start: qpcontact not ok")
    if ratios:
        print("\nqpcontact / OpenSees, the analysis alone (wall-time medians; CPU in brackets):")
        for name, (wall, cpu, tgt) in ratios.items():
            print(f"  {name:>28}: {wall:5.2f} ({cpu:.2f})  {tgt}")
    for f in failures:
        print("FAILED:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    raise SystemExit(main())
