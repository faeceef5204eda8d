"""What the 2-D drum's time step h costs and buys: a drum2d scene run at
several h, everything else the same, with each run's CPU and the figures a
drum engineer reads side by side.

For each --steps value (ms) the scene's text gets ``[time] step`` (and any
--vary KEY=VALUE: ``logs.seed=2``, ``time.revolutions=0.5``) by
qpcontact.scenes.vary_scene, and `qpcontact simulate` runs it in a child
process (--jobs at a time; its CPU, user + system, from os.wait4, so the
runs may share the cores).  Then, per h, from the results files (SI units,
per metre of drum where the cross-section's length ℓ enters):

- the certificates: steps certified, the worst error, fallbacks;
- drive power [kW/m] and torque [kN·m/m], energy per tonne per revolution
  [kJ/t], sliding work per log per revolution [J] and its share of the
  drive, the impact loss's share (outputs.py, records.py);
- peak normal forces [kN], log–log and log–steel: the largest, the 99.9 %
  quantile of the steps' peaks (a count per step: its window is h), and the
  force the steps' peaks exceed 1, 10 and 50 times a second (an impact is
  recorded once, in its step: a rate per second, whatever h);
- the histograms' 50 % and 99 % log–steel force (contact-steps; a cluster
  run's contact records its largest force over h + T/2, so the bulk
  depends on h by construction: docs/drum2d.md);
- the largest overlap [mm] (with springs: the spring's deflection), the
  bed's angle — the direction of its centroid from the drum's axis against
  the vertical, which for a flat surface is the surface's slope — its mean
  kinetic energy and mean active contacts.

With --dem P1,P2 the same scene from the same start is also run by the
resolved explicit penalty DEM of benchmarks/drum2d_dem.py at Δt = T_min/P
(in this process, one after the other; --dem-friction dashpot,spring runs
each P with its capped tangential dashpot and with Cundall–Strack's
tangential spring, spring:R with k_t = R k): its drive, tangential loss,
its sliding part (beside the 2-D's sliding work: its share of the drive and
per log per revolution; the dashpot's work at the cone, or the spring's
slip; the rest is the dashpot's creep of stuck contacts, or the spring's
dashpot) and the bed's angle beside the 2-D runs', and its log–log and
log–steel forces exceeded 1, 10 and 50 times a second by the largest force
of each window of h, for each h (the 2-D's steps' peaks are windows of h).

--from T0 restricts the figures to t >= T0 [s] (past the fall from the
lattice).  The results files are kept in --out and reused when present
(with their CPU in a .json beside them) unless --fresh.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/drum2d_step.py \\
        --steps 2,3,4 --from 1.5 --dem 100,200

(the 500-log example's revolution: 100–130 s of CPU at 1.5–3 ms, 140–150 s
at 4 ms, ~300 s at 5 ms; the DEM 46 and 89 s; docs/drum2d.md, "What
accuracy costs in time".)
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from formulations.drum2d.revolutions import histogram_quantile  # noqa: E402
from qpcontact.scenes import vary_scene  # noqa: E402

RATES = (1.0, 10.0, 50.0)      # the steps' peaks exceed the force this often [1/s]


def run(scene_text: str, out: Path, jobs: list):
    """Start `qpcontact simulate` on the text (one BLAS thread, its messages
    to a .log beside the results) and add it to ``jobs``."""
    toml = out.with_suffix(".toml")
    toml.write_text(scene_text)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
               MKL_NUM_THREADS="1", PYTHONPATH=str(ROOT))
    child = subprocess.Popen([sys.executable, "-m", "qpcontact", "simulate", str(toml),
                              "--out", str(out)], env=env, cwd=ROOT,
                             stdout=subprocess.DEVNULL,
                             stderr=open(out.with_suffix(".log"), "w"))
    jobs.append((child, out))


def wait_one(jobs: list):
    """Wait for any child; write its CPU [s] beside its results file."""
    pid, status, usage = os.wait4(-1, 0)
    for k, (child, out) in enumerate(jobs):
        if child.pid == pid:
            child.returncode = os.waitstatus_to_exitcode(status)
            cpu = usage.ru_utime + usage.ru_stime
            load = os.getloadavg()[0]
            out.with_suffix(".json").write_text(json.dumps({"cpu": cpu, "load": load}))
            if child.returncode:
                raise SystemExit(f"{out}: simulate failed; its messages: "
                                 f"{out.with_suffix('.log')}")
            del jobs[k]
            return


def tail(peaks, seconds: float) -> dict:
    """The force [kN] that ``peaks`` (one per window over ``seconds``) exceed
    RATES times a second."""
    top = np.sort(peaks)[::-1]
    return {rate: top[int(round(rate * seconds)) - 1] / 1e3 if round(rate * seconds) else np.nan
            for rate in RATES}


def figures(path: Path, t0: float) -> dict:
    """The module docstring's figures of one results file, from t >= t0."""
    import h5py

    with h5py.File(path, "r") as f:
        t, h, om = f["t"][()], float(f["drum/step"][()]), float(f["drum/omega"][()])
        a, b = int(np.searchsorted(t[:-1], t0 - 1e-9)), t.size - 1
        rows = slice(a, b)
        span = t[b] - t[a]
        revs = span * om / (2 * np.pi)
        m, d, ell = f["masses"][()], f["diameters"][()], float(f["logs/length"][()])
        drive = f["energy/drive"][rows].sum()
        sliding = f["sliding_work"][rows].sum()
        peaks = f["force_peak"][rows]
        counts = f["force_counts"][rows]
        P = f["positions"][a:b + 1]
        c = (P * m[None, :, None]).sum(1) / m.sum()
        r = {"h [ms]": 1e3 * h, "steps": b - a,
             "steps certified": int(f["certified"][rows].sum()),
             "worst certificate": float(f["certificate_error"][rows].max()),
             "fallbacks": int(f["fallback"][rows].sum()),
             "drive power [kW/m]": drive / span / ell / 1e3,
             "torque [kN·m/m]": drive / span / ell / om / 1e3,
             "energy [kJ/t/rev]": drive / revs / (m.sum() / 1e3) / 1e3,
             "sliding work [J/log/rev]": sliding / revs / m.size,
             "sliding / drive [%]": 100 * sliding / drive,
             "impact loss / drive [%]": 100 * f["energy/impact_loss"][rows].sum() / drive}
        for name, p, cnt in (("log-log", peaks[:, 0], counts[:, 0].sum(0)),
                             ("log-steel", peaks[:, 1:].max(1), counts[:, 1:].sum((0, 1)))):
            r[f"{name} largest [kN]"] = p.max() / 1e3
            r[f"{name} 99.9 % of steps [kN]"] = np.quantile(p, 0.999) / 1e3
            for rate, force in tail(p, span).items():
                r[f"{name} exceeded {rate:g}/s [kN]"] = force
            if name == "log-steel":
                for q in (0.5, 0.99):
                    r[f"{name} histogram {100 * q:g} % [kN]"] = \
                        histogram_quantile(cnt, q, p.max()) / 1e3
        r["largest overlap [mm]"] = 1e3 * float(f["drum/max_penetration"][()])
        r["bed angle [°]"] = float(np.degrees(np.arctan2(c[:, 0], -c[:, 1])).mean())
        r["mean kinetic energy [J]"] = float(f["energy/kinetic"][a:b + 1].mean())
        r["mean active contacts"] = float(f["n_active"][rows].mean())
    return r


def spring_ratio(friction: str) -> float:
    """k_t/k of --dem-friction's ``spring`` (1/3) or ``spring:R`` (R); 0 for ``dashpot``."""
    if friction == "dashpot":
        return 0.0
    return float(friction.split(":")[1]) if ":" in friction else 1.0 / 3.0


def dem_figures(scene_text: str, per_period: float, t0: float, steps_ms: list,
                spring: float = 0.0) -> dict:
    """The penalty DEM's figures (module docstring) of the scene from t >= t0
    (``spring``: Cundall–Strack's tangential spring, carried across t0)."""
    from benchmarks.drum2d_dem import penalty_dem
    from formulations.drum2d.scene import scene_model
    from qpcontact.scenes.schema import parse_scene

    model, h, n = scene_model(parse_scene(scene_text, "the scene"))
    base = 0.5e-3                        # windows of h are made of these [s]
    cpu, start, springs = 0.0, 0.0, None
    if t0 > 0:                           # to t0 without books, then on from its state
        early = penalty_dem(model, t0, per_period, spring=spring)
        d = model.discs
        d.positions[:], d.velocities[:], d.spins[:] = (early["positions"], early["velocities"],
                                                       early["spins"])
        cpu, start, springs = early["cpu"], early["steps"] * early["dt"], early["springs"]
    span = h * n - start
    run = penalty_dem(model, span, per_period, window=base, t0=start, spring=spring,
                      springs=springs)
    c = run["centroids"]
    revs = span * model.omega / (2 * np.pi)
    r = {"cpu": cpu + run["cpu"], "dt [µs]": 1e6 * run["dt"],
         "drive power [kW/m]": run["drive"] / span / model.discs.length / 1e3,
         "tangential loss / drive [%]": 100 * run["friction"] / run["drive"],
         "sliding / drive [%]": 100 * run["sliding"] / run["drive"],
         "sliding work [J/log/rev]": run["sliding"] / revs / model.discs.n,
         "bed angle [°]": float(np.degrees(np.arctan2(c[:, 0], -c[:, 1])).mean())}
    for ms in steps_ms:
        k = int(round(float(ms) * 1e-3 / base))
        for kind, name in ((0, "log-log"), (1, "log-steel")):
            p = run["peaks"][:, kind]
            for rate, force in tail(p[:p.size // k * k].reshape(-1, k).max(1), span).items():
                r[f"{name} exceeded {rate:g}/s, windows of {ms} ms [kN]"] = force
    return r


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(ROOT / "examples" / "scenes" / "drum2d_500.toml"))
    ap.add_argument("--steps", default="2,3,4", help="h in ms, comma-separated")
    ap.add_argument("--vary", action="append", default=[], help="KEY=VALUE, as for sweep")
    ap.add_argument("--from", dest="t0", type=float, default=0.0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default=str(ROOT / "out" / "bench" / "drum2d_step"))
    ap.add_argument("--fresh", action="store_true")
    ap.add_argument("--dem", default="", help="T_min/Δt of penalty DEM runs, comma-separated")
    ap.add_argument("--dem-friction", default="dashpot",
                    help="the DEM's friction, comma-separated: dashpot (capped, no "
                         "history), spring (Cundall–Strack, k_t = k/3), spring:R (k_t = R k)")
    args = ap.parse_args(argv)
    text = Path(args.scene).read_text()
    for kv in args.vary:
        key, value = kv.split("=", 1)
        text = vary_scene(text, key, value)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tag = Path(args.scene).stem + "".join(f"_{kv.replace('=', '-')}" for kv in args.vary)
    files, jobs = [], []
    for ms in args.steps.split(","):
        path = out / f"{tag}_h{ms}ms.h5"
        files.append(path)
        if args.fresh or not path.with_suffix(".json").exists():
            if len(jobs) >= args.jobs:
                wait_one(jobs)
            run(vary_scene(text, "time.step", str(float(ms) / 1e3)), path, jobs)
    while jobs:
        wait_one(jobs)
    got = [figures(p, args.t0) | json.loads(p.with_suffix(".json").read_text()) for p in files]
    base = got[0]
    print(f"{args.scene} {' '.join(args.vary)}, figures from t = {args.t0} s; "
          f"(x) = against h = {base['h [ms]']:g} ms")
    print("| figure | " + " | ".join(f"h = {g['h [ms]']:g} ms" for g in got) + " |")
    print("|---" * (len(got) + 1) + "|")
    for key in ["cpu", "load"] + [k for k in base if k not in ("cpu", "load")]:
        cells = []
        for g in got:
            v = g[key]
            cell = f"{v:.4g}" if isinstance(v, float) else str(v)
            if key.endswith("]") and key != "h [ms]" and g is not base and base[key]:
                cell += f" ({100 * (v / base[key] - 1):+.1f} %)"
            cells.append(cell)
        label = {"cpu": "CPU, user + system [s]", "load": "load at the end"}.get(key, key)
        print(f"| {label} | " + " | ".join(cells) + " |")
    steps_ms = args.steps.split(",")
    for per, friction in ((p, f) for p in filter(None, args.dem.split(","))
                          for f in args.dem_friction.split(",")):
        dem = dem_figures(text, float(per), args.t0, steps_ms, spring=spring_ratio(friction))
        print(f"\npenalty DEM at T_min/{per}, friction by the {friction} "
              f"(load {os.getloadavg()[0]:.1f}):")
        for key, v in dem.items():
            cell = f"{v:.4g}"
            h_ms = key.rsplit("windows of ", 1)[-1].split(" ms")[0] if "windows" in key else None
            at_h = next((g for g in got
                         if h_ms and f"{g['h [ms]']:g}" == f"{float(h_ms):g}"), None)
            twin = key.split(", windows")[0] + " [kN]" if at_h else key
            ref = at_h if at_h else base
            if twin in ref and key != "cpu" and ref[twin]:
                cell += f" (the 2-D at h = {ref['h [ms]']:g} ms: {ref[twin]:.4g}, " \
                        f"{100 * (ref[twin] / v - 1):+.1f} %)"
            print(f"| {key} | {cell} |")


if __name__ == "__main__":
    main()
