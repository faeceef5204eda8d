"""An independent census of second-order answers with P-δ along members
(issue 52, item 1): qpcontact's ``solve(second_order=True)`` against closed
forms and OpenSees, through the public API only.

Each case is written once as a plain model (nodes, members, supports,
nodal loads, span loads in member axes; benchmarks/pdelta_cases.py) and
built twice: as a qpcontact ``Frame``/``SpaceFrame`` (one element a
member, here) and as an OpenSees model (benchmarks/pdelta_references.py,
which also holds the closed forms and the cut model's α_cr and imports
nothing of qpcontact).

References
----------
* **Closed forms** (Timoshenko & Gere, *Theory of Elastic Stability*, ch. 1),
  evaluated in mpmath at 50 digits, k = √(|N|/EI), u = kL/2, compression
  (tension: the hyperbolic forms):
  - pinned span, uniform w: M(L/2) = (w/k²)(sec u − 1), end rotation
    w(tan u − u)/(EI k³), midspan deflection w(sec u − 1 − u²/2)/(EI k⁴);
  - clamped span (one end free to slide axially), uniform w: end moment
    (w/k²)(1 − u/tan u) = (wL²/12)·3(tan u − u)/(u² tan u), midspan
    (w/k²)(u/sin u − 1);
  - pinned span, force Q at midspan: M = (Q/2k) tan u, end rotation
    (Q/2P)(sec u − 1), midspan deflection Q(tan u − u)/(2Pk);
  - pinned span, end moments M_a, M_b (no span load):
    M(x) = [M_a sin k(L − x) + M_b sin kx]/sin kL, largest M sec u for two
    equal single-curvature moments;
  - cantilever, tip force H and uniform w across under P: the deformed
    cantilever's moment equation EI v'' = H(L − x) + P(δ − v) + w(L − x)²/2
    solved in closed form (three constants from v(0) = v'(0) = 0,
    v(L) = δ), base moment H L + P δ + w L²/2;
  - α_cr = the member's buckling load (π²EI/L², 4π²EI/L² clamped,
    π²EI/(4L²) cantilever) over its compression.
* **OpenSees** (openseespy): every member cut into 32 and 64
  elasticBeamColumn pieces under the PDelta transformation (one piece has
  P-Δ only; the cut carries the P-δ, its error falls as 1/n²), span loads as
  ``eleLoad -beamUniform / -beamPoint`` on the pieces, hinged ends as a node
  of their own tied by equalDOF, linear-elastic supports (and pads held
  along y where qpcontact's answer has every pad closed: the frames "on
  pads", whose answers go through the contact LCP); loads in 10
  LoadControl steps, Newton, NormDispIncr 1e-12.  The 64-cut answer is the
  reference, |64 − 32| its error bar (≈ 3× its own error).  The same 64-cut
  model under Corotational is printed beside: large-rotation terms that a
  linearised second order leaves out, a bound on the modelling error, not a
  reference for digits.  Its α_cr: every member cut into n and 2n cubic
  elements (n = 16 up to 12 members, 8 up to 40, else 4) with their
  consistent geometric stiffness, the axial forces OpenSees' 64-cut answer
  gives (qpcontact's α_cr scales its answer's), the least root of
  det(K + α K_G) = 0 extrapolated as n⁻⁴, judged to 10× the extrapolation's
  step plus the change from the 32-cut answer's axial forces, or the
  accuracy asked.  The deflection's extremes along the cut: each piece's
  cubic through its nodes' v and v' (a peak between the last two nodes is
  not missed); M's: the parabola through the best node and its neighbours.
* **Space frames**: a plane frame built in 3-D against the plane API (to
  1e-10: a consistency check within qpcontact), and genuinely 3-D members
  loaded about both axes against the closed forms (each bending plane on
  its own) and OpenSees 3-D (PDelta, vecxz = the member's ``ref``).

Each quantity is judged on its own scale: displacements against the
largest translation (rotations against the largest rotation), a member's
end moments, its diagram M(x) at x = kL/8 (a space member's My(x), Mz(x))
and its M extremes (space: the largest |My|, |Mz|) against the member's
largest |M|, its N and V against its largest end force, α_cr
relatively.  Tolerance: the accuracy asked of qpcontact (``--accuracy``,
default "low" = 1e-4), or the reference's own error bar where larger; the
extremes of the deflection v also get the error of the 201-section
sampling qpcontact documents for them (|v''| h²/8, h = L/200), and a
member with next to no moment (a hinged link) is judged on 1e-3 of the
frame's largest moment with 1e-11 of it for rounding.

Classes: **right** (ok and within tolerance everywhere), **FALSE OK** (ok
and off somewhere: the class that matters), **honest not ok** (refused,
and its numbers are off), **refused, right** (refused though its numbers
are within tolerance: conservative), **error** (an exception); the plane
frames built in 3-D are **same** or **MISMATCH**.  A second table counts,
whatever the status, the cases whose nodes, member end forces, diagrams
(M(x), extremes of M and v) and α_cr are within tolerance.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/frame_pdelta_census.py
        [--seeds 0-11] [--storeys 3] [--bays 2] [--no-hand] [--no-random]
        [--no-space] [--tower 20] [--accuracy low]

Exits non-zero when a case is a false ok or an error (so it can gate the
beam-column branches).
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import time
import warnings

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
# the repo root last: PYTHONPATH=<another worktree> runs this census on that tree's code
sys.path.append(os.path.join(HERE, ".."))
sys.path.insert(0, HERE)
from formulations.frames import Frame, SpaceFrame  # noqa: E402
from pdelta_cases import (hand_cases, in_3d, lumped, on_pads, portal_leaning,  # noqa: E402
                          random_frame, shear_cases, space_cases, sway_portal, tower)
from pdelta_references import (E, G, GRID, HAVE_OPENSEES, geometry, os_answer,  # noqa: E402
                               reference_alpha)

ACCURACY = {"low": 1e-4, "high": 1e-9}


# -- qpcontact --------------------------------------------------------------------------

def qp_frame(m):
    space = m["dim"] == 3
    fr = SpaceFrame() if space else Frame()
    for n, xy in m["nodes"].items():
        fr.add_node(n, *xy)
    for mem in m["members"]:
        if space:
            fr.add_member(mem["i"], mem["j"], E, mem["A"], mem["Iy"], mem["I"], G=G,
                          J=mem["Iy"] + mem["I"], name=mem["name"], ref=mem["ref"],
                          hinge_i=mem["hinge_i"], hinge_j=mem["hinge_j"])
        else:
            shear = dict(G=G, shear_area=mem["As"]) if mem["As"] else {}
            fr.add_member(mem["i"], mem["j"], E, mem["A"], mem["I"], name=mem["name"],
                          hinge_i=mem["hinge_i"], hinge_j=mem["hinge_j"], **shear)
    names = ("ux", "uy", "uz", "rx", "ry", "rz") if space else ("ux", "uy", "rz")
    for n, ds in m["fixed"].items():
        fr.add_support(n, fix=tuple(names[d] for d in ds))
    for n in m.get("pads", ()):               # a rigid frictionless pad under the node
        fr.add_contact(n, normal=(0.0, 1.0))
    for n, f in m["loads"].items():
        if space:
            fr.add_load(n, *f)
        else:
            fr.add_load(n, fx=f[0], fy=f[1], mz=f[2])
    for mem, *w in m["udl"]:
        fr.add_distributed_load(mem, *w, axes="member")
    for mem, a, *f in m["point"]:
        fr.add_point_load(mem, a, *f, axes="member")
    return fr


def qp_answer(m, accuracy):
    """qpcontact's answer in the census's form (see ``compare``)."""
    fr = qp_frame(m)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fr.solve(second_order=True, accuracy=accuracy, raise_on_failure=False)
        try:
            alpha = float(fr.critical_load_factor(res)["alpha"])
        except Exception as exc:          # noqa: BLE001 - recorded, judged as an error
            alpha = f"{type(exc).__name__}: {exc}"
    if not res.displacements:     # no equilibrium (a frame that lifts off its pads)
        return dict(ok=False, message=res.message, res=res, no_equilibrium=True)
    out = dict(ok=bool(res.ok), message=res.message, alpha=alpha,
               disp={n: np.array(res.displacements[n], float) for n in m["nodes"]},
               ends={}, grid={}, ext={}, res=res, frame=fr)
    for mem in m["members"]:
        nm = mem["name"]
        out["ends"][nm] = np.array(res.member_forces[nm], float)
        if m["dim"] == 2:
            x, N, V, M = res.diagram(nm, GRID + 1)
            L = geometry(m, mem)[2]
            out["grid"][nm] = np.array([M[np.argmin(abs(x - L * t / GRID))]
                                        for t in range(GRID + 1)])
            e = res.extremes(nm)
            out["ext"][nm] = {"M_max": e["M"]["max"][0], "M_min": e["M"]["min"][0],
                              "v_max": e["v"]["max"][0], "v_min": e["v"]["min"][0]}
        else:
            e = res.extremes(nm)
            out["ext"][nm] = {f"|{q}|": max(abs(e[q]["max"][0]), abs(e[q]["min"][0]))
                              for q in ("My", "Mz")}
            x, *_, My, Mz = res.diagram(nm, GRID + 1)
            L = geometry(m, mem)[2]
            at = [int(np.argmin(abs(x - L * t / GRID))) for t in range(GRID + 1)]
            out["grid"][nm] = {"My": My[at], "Mz": Mz[at]}
    return out


def group(row, closed_kinds):
    """Which of the four quantities a compared row is about."""
    what = row[0]
    kind = closed_kinds.get(what)
    if kind == "alpha" or what == "alpha":
        return "alpha"
    if kind == "disp" or what in ("translations", "rotations"):
        return "nodes"
    if kind == "end" or what.endswith(("end moments", "end N, V")):
        return "end forces"
    return "diagrams"


# -- comparing --------------------------------------------------------------------------

def compare(m, q, ref, coarse, acc):
    """[(what, error on its scale, tolerance)] for every quantity of ``q``
    against ``ref`` (OpenSees 64) with ``coarse`` (OpenSees 32) for its error
    bar."""
    rows = []
    rot = slice(2, 3) if m["dim"] == 2 else slice(3, 6)
    xyz = np.array(list(m["nodes"].values()), float)
    size, floor = max(np.linalg.norm(xyz.max(0) - xyz.min(0)), 1e-300), {}
    tr = slice(0, 2) if m["dim"] == 2 else slice(0, 3)
    for part, nm in ((tr, "translations"), (rot, "rotations")):
        r = np.array([ref["disp"][n][part] for n in m["nodes"]])
        c = np.array([coarse["disp"][n][part] for n in m["nodes"]])
        a = np.array([q["disp"][n][part] for n in m["nodes"]])
        scale = max(abs(r).max(), floor.get(nm, 0.0), 1e-300)
        floor["rotations"] = 1e-9 * scale / size      # a held frame's rotations: noise
        rows.append((nm, abs(a - r).max() / scale, max(acc, abs(c - r).max() / scale)))
    # a member with next to no moment (a hinged link, a leaning column) is
    # judged on 1e-3 of the frame's largest moment, not on its own rounding
    frame_M = max(abs(ref["ends"][mm["name"]][[2, 5] if m["dim"] == 2 else [4, 5, 10, 11]]).max()
                  for mm in m["members"])
    for mem in m["members"]:
        nm = mem["name"]
        e_r, e_c, e_q = ref["ends"][nm], coarse["ends"][nm], q["ends"][nm]
        if m["dim"] == 2:
            sM = max(abs(ref["chains"][nm]).max(), 1e-3 * frame_M, 1e-12)
            mom, force = [2, 5], [0, 1, 3, 4]
        else:
            sM = max(max(ref["ext"][nm].values()), 1e-3 * frame_M, 1e-12)
            mom, force = [3, 4, 5, 9, 10, 11], [0, 1, 2, 6, 7, 8]
        sF = max(abs(e_r[force]).max(), 1e-12)
        rounding = 1e-11 * frame_M / sM       # a member with next to no moment: rounding
        for idx, s, what, floor_ in ((mom, sM, "end moments", rounding),
                                     (force, sF, "end N, V", 0.0)):
            rows.append((f"{nm} {what}", abs(e_q[idx] - e_r[idx]).max() / s,
                         max(acc, floor_, abs(e_c[idx] - e_r[idx]).max() / s)))
        if m["dim"] == 2:
            rows.append((f"{nm} diagram M(x)", abs(q["grid"][nm] - ref["grid"][nm]).max() / sM,
                         max(acc, rounding, abs(coarse["grid"][nm] - ref["grid"][nm]).max() / sM)))
            L = geometry(m, mem)[2]
            s_v = max(abs(ref["ext"][nm]["v_max"]), abs(ref["ext"][nm]["v_min"]),
                      1e-6 * max(abs(ref["disp"][n][tr]).max() for n in m["nodes"]), 1e-15)
            # qpcontact documents its v extremes as the best of 201 sections: a
            # sampled peak misses by up to |v''| h²/8, h = L/200, v'' = M/EI
            sampled = sM / (E * mem["I"]) * (L / 200) ** 2 / 8 / s_v
            for keys, s, floor_ in ((("M_max", "M_min"), sM, rounding),
                                    (("v_max", "v_min"), s_v, sampled)):
                rows.append((f"{nm} extremes {keys[0][0]}",
                             max(abs(q["ext"][nm][k] - ref["ext"][nm][k]) for k in keys) / s,
                             max(acc, floor_, max(abs(coarse["ext"][nm][k] - ref["ext"][nm][k])
                                                  for k in keys) / s)))
        else:
            for k in ("|My|", "|Mz|"):
                rows.append((f"{nm} extreme {k}", abs(q["ext"][nm][k] - ref["ext"][nm][k]) / sM,
                             max(acc, rounding, abs(coarse["ext"][nm][k] - ref["ext"][nm][k]) / sM)))
            for k in ("My", "Mz"):
                rows.append((f"{nm} diagram {k}(x)",
                             abs(q["grid"][nm][k] - ref["grid"][nm][k]).max() / sM,
                             max(acc, rounding,
                                 abs(coarse["grid"][nm][k] - ref["grid"][nm][k]).max() / sM)))
    return rows


def compare_closed(m, q, acc):
    """[(what, error, tolerance)] against the case's closed forms: each
    (label, kind, key, value, scale[, allowance]) — kind "disp" (key: node,
    dof), "end" (member, index of the end actions), "ext" (member, key),
    "alpha"; allowance: a documented error of qpcontact's (relative)."""
    rows = []
    for label, kind, key, value, scale, *allowance in m["closed"]:
        value = float(value)
        if kind == "disp":
            got = q["disp"][key[0]][key[1]]
        elif kind == "end":
            got = q["ends"][key[0]][key[1]]
        elif kind == "ext":
            got = q["ext"][key[0]][key[1]]
        else:
            got = q["alpha"]
            if isinstance(got, str):
                rows.append((label, np.inf, acc))
                continue
            if np.isinf(value) and np.isinf(got):
                rows.append((label, 0.0, acc))
                continue
        rows.append((label, abs(got - value) / float(scale), max([acc] + allowance)))
    return rows


# -- the census -------------------------------------------------------------------------

def judge(rows):
    """(right?, the worst row by error/tolerance)."""
    worst = max(rows, key=lambda r: r[1] / r[2]) if rows else ("-", 0.0, 1.0)
    return all(r[1] <= r[2] for r in rows), worst


def run_case(m, acc_name):
    acc = ACCURACY[acc_name]
    t = time.perf_counter()
    try:
        q = qp_answer(m, acc_name)
    except Exception as exc:       # noqa: BLE001 - the census's "error" class
        return dict(name=m["name"], family=m["family"], cls="error", ok=None,
                    worst=(f"{type(exc).__name__}: {str(exc)[:120]}", np.nan, acc), note="")
    rows, note = [], ""
    opened = [] if q.get("no_equilibrium") else \
        [k for k, sup in q["res"].supports.items() if sup.state != "closed"]
    if opened or q.get("no_equilibrium"):  # OpenSees holds every pad: not this frame
        note = f"pads {opened} not closed" if opened else q["message"][:90]
        return dict(name=m["name"], family=m["family"], cls="no reference", ok=q["ok"],
                    worst=("-", 0.0, acc), note=note, groups={},
                    seconds=time.perf_counter() - t, message=q["message"])
    if m["closed"]:
        rows += compare_closed(m, q, acc)
    shear = any(mem["As"] for mem in m["members"])
    if shear:
        # OpenSees' ElasticTimoshenkoBeam2d leaves out its transformation's
        # P-Δ (measured: equal end moments stay 10.000 under PDelta and
        # Corotational, 16 and 64 cuts): the closed forms alone
        note = "shear members: closed forms only"
    if HAVE_OPENSEES and not shear:
        r64, r32 = os_answer(m, 64), os_answer(m, 32)
        if r64 is None or r32 is None:
            note = "OpenSees did not converge"
        else:
            rows += compare(m, q, r64, r32, acc)
            co = os_answer(m, 64, "Corotational")
            if co is not None:      # how far large rotations move the same quantities
                what, d, _ = max((r for r in compare(m, co, r64, r32, acc)
                                  if not r[0].endswith(("diagram M(x)", "extremes v", "|My|",
                                                        "|Mz|", "extremes M", "My(x)", "Mz(x)"))),
                                 key=lambda r: r[1])
                note = f"Corotational vs PDelta: {d:.1e} ({what})"
            else:
                note = "Corotational did not converge"
            if m["dim"] == 2 and not m["closed"]:
                alpha, err = reference_alpha(m, {nm: float(np.mean(v))
                                                 for nm, v in r64["axial"].items()})
                # the axial forces' own cut error: α on the 32-cut answer's
                coarse_alpha, _ = reference_alpha(m, {nm: float(np.mean(v))
                                                      for nm, v in r32["axial"].items()})
                if isinstance(q["alpha"], str):
                    rows.append(("alpha", np.inf, acc))
                elif np.isfinite(alpha):
                    rows.append(("alpha", abs(q["alpha"] - alpha) / alpha,
                                 max(acc, (10 * err + abs(coarse_alpha - alpha)) / alpha)))
    elif not m["closed"] and not shear:
        note = "openseespy missing: no reference"
    right, worst = judge(rows)
    kinds = {label: kind for label, kind, *_ in m["closed"]}
    groups = {}
    for row in rows:
        g = group(row, kinds)
        groups[g] = groups.get(g, True) and row[1] <= row[2]
    if not rows:
        cls = "no reference"
    elif not q["ok"]:
        cls = "honest not ok" if not right else "refused, right"
    else:
        cls = "right" if right else "FALSE OK"
    return dict(name=m["name"], family=m["family"], cls=cls, ok=q["ok"], worst=worst, note=note,
                groups=groups, seconds=time.perf_counter() - t, message=q["message"])


def consistency_3d(m, acc_name):
    """The plane model and the same in 3-D: (largest difference of
    displacements and end actions on their scales, both ok?)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a, b = qp_answer(m, acc_name), qp_answer(in_3d(m), acc_name)
    du = max(max(abs(a["disp"][n][:2] - b["disp"][n][:2]).max() for n in m["nodes"])
             / max(abs(a["disp"][n][:2]).max() for n in m["nodes"]),
             max(abs(a["disp"][n][2] - b["disp"][n][5]) for n in m["nodes"])
             / max(max(abs(a["disp"][n][2]) for n in m["nodes"]), 1e-300))
    df = 0.0
    for mem in m["members"]:
        x, y = a["ends"][mem["name"]], b["ends"][mem["name"]][[0, 1, 5, 6, 7, 11]]
        df = max(df, abs(x - y).max() / max(abs(x).max(), 1e-300))
    return max(du, df), a["ok"], b["ok"]


def parse_seeds(text):
    out = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out += list(range(int(lo), int(hi or lo) + 1))
    return out


def line(r):
    what, err, tol = r["worst"]
    return (f"  {r['cls']:<14} ok={str(r['ok']):<5} {r['name']:<58} worst: {what} "
            f"{err:.1e} (tol {tol:.0e})" + (f"; {r['note']}" if r["note"] else ""))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default="0-11", help="random frames' seeds, e.g. 0-11 or 3,5")
    ap.add_argument("--storeys", type=int, default=3, help="random frames: at most this many")
    ap.add_argument("--bays", type=int, default=2, help="random frames: at most this many")
    ap.add_argument("--tower", type=int, default=20, help="tower storeys (0: none)")
    ap.add_argument("--accuracy", default="low", choices=sorted(ACCURACY))
    ap.add_argument("--no-hand", action="store_true")
    ap.add_argument("--no-random", action="store_true")
    ap.add_argument("--no-space", action="store_true")
    args = ap.parse_args(argv)
    import formulations
    print(f"qpcontact's frames from {os.path.dirname(os.path.dirname(formulations.__file__))}")
    if not HAVE_OPENSEES:
        print("openseespy cannot be imported: the OpenSees rows are skipped "
              "(closed forms and the 3-D consistency only)")
    cases = []
    if not args.no_hand:
        cases += hand_cases() + shear_cases() + [portal_leaning(0.3), portal_leaning(0.8),
                                                 sway_portal(0.5), sway_portal(0.9)]
    if not args.no_random:
        frames = [random_frame(s, args.storeys, args.bays) for s in parse_seeds(args.seeds)]
        cases += frames + [lumped(m) for m in frames]
        # on pads: the frames whose loads press them down (turned up, they lift off)
        cases += [on_pads(m) for m in frames if "tension" not in m["name"]][:4]
    if args.tower:
        cases += [tower(args.tower, p=1.0)]
    results = []
    for m in cases:
        r = run_case(m, args.accuracy)
        results.append(r)
        print(line(r) + f" [{r.get('seconds', 0):.1f} s]", flush=True)
    if not args.no_space:
        pairs, threed = space_cases()
        for m in pairs:
            d, ok2, ok3 = consistency_3d(m, args.accuracy)
            cls = "same" if d <= 1e-10 and ok2 == ok3 else "MISMATCH"
            r = dict(name=m["name"] + " plane vs 3-D", family="plane in 3-D", cls=cls, ok=ok3,
                     worst=("plane vs 3-D", d, 1e-10), note=f"ok plane {ok2}, 3-D {ok3}")
            results.append(r)
            print(line(r), flush=True)
        for m in threed:
            r = run_case(m, args.accuracy)
            results.append(r)
            print(line(r) + f" [{r.get('seconds', 0):.1f} s]", flush=True)
    table = collections.OrderedDict()
    for r in results:
        table.setdefault(r["family"], collections.Counter())[r["cls"]] += 1
    classes = ["right", "FALSE OK", "honest not ok", "refused, right", "error", "same",
               "MISMATCH", "no reference"]
    print(f"\nsummary (accuracy {args.accuracy!r}; OpenSees "
          f"{'64 cuts, PDelta' if HAVE_OPENSEES else 'missing'}):")
    print(f"| family | cases | " + " | ".join(classes) + " |")
    print("|---|---:|" + "---:|" * len(classes))
    for fam, cnt in table.items():
        print(f"| {fam} | {sum(cnt.values())} | " + " | ".join(str(cnt[c]) for c in classes) + " |")
    print("\nper quantity, whatever the status (cases within tolerance / cases compared):")
    names = ("nodes", "end forces", "diagrams", "alpha")
    print("| family | " + " | ".join(names) + " |")
    print("|---|" + "---:|" * len(names))
    for fam in table:
        cells = []
        for g in names:
            got = [r["groups"][g] for r in results if r["family"] == fam and g in r.get("groups", {})]
            cells.append(f"{sum(got)}/{len(got)}" if got else "-")
        print(f"| {fam} | " + " | ".join(cells) + " |")
    bad = [r for r in results if r["cls"] in ("FALSE OK", "error", "MISMATCH")]
    if bad:
        print("\nfalse ok / error / mismatch:")
        for r in bad:
            print(line(r))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
