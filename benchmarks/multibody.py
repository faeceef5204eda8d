"""Time per forward-dynamics evaluation and peak memory for chains of N bodies
with 2-DOF Cardan joints (Ivanov & Shimanovsky's experiments), N = 10 ... 5000.

Candidates (each case runs in its own subprocess, so that peak memory is its
own and a runaway allocation cannot take the benchmark down):

  ldlt, sweep       the momentum form's system (6) solved for ν from (q, p): LDL' / sweep (O(N))
  momentum-rhs      the whole right-hand side (q̇, ṗ) of the momentum form (ldlt)
  lagrange-dense    CRBA + RNEA + dense Cholesky of G (O(N²) memory, O(N³) time)
  pinocchio-aba     Pinocchio's articulated-body algorithm         (if installed)
  pinocchio-chol    Pinocchio's CRBA + sparse Cholesky + solve      (if installed)
  mujoco-forward    MuJoCo mj_forward on the same chain (MjSpec)    (if installed)
  mujoco-step       MuJoCo mj_step

Prints a table, the fitted log-log slope of time against N per candidate,
the sweep/LDL' ratio per N (Ivanov & Shimanovsky: 1.35-1.4) and ours against
MuJoCo's step at N = 1000; ``--plot`` saves the log-log figure.  BLAS is pinned to one thread.

    python benchmarks/multibody.py [--sizes 10,100,1000] [--plot docs/figures/multibody.png]
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import resource  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

CANDIDATES = ("ldlt", "sweep", "momentum-rhs", "lagrange-dense", "pinocchio-aba",
              "pinocchio-chol", "mujoco-forward", "mujoco-step")
DENSE_MAX = 1000          # lagrange-dense beyond: G alone is 8 (2N)² bytes, O(N³) flops
MUJOCO_MAX = 1000         # mujoco beyond: MjSpec.compile failed at N = 3000 ("Element name '', id
                          # 1024", after ~6 min; a nesting limit) and its dense LDL is cubic anyway
MEMORY_LIMIT = 6 << 30    # address-space cap per case (Pinocchio's createData allocates nv³)
LINK, MASS, INERTIA = 0.1, 1.0, (1e-3, 1e-3, 1e-4)


def _rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _time(fn, budget=0.3) -> float:
    """Best of 3 batches, each of enough calls to last ``budget`` seconds."""
    fn()
    t0 = time.perf_counter()
    fn()
    one = max(time.perf_counter() - t0, 1e-7)
    reps = max(1, int(budget / one))
    best = np.inf
    for _ in range(3):
        t0 = time.perf_counter()
        for _ in range(reps):
            fn()
        best = min(best, (time.perf_counter() - t0) / reps)
    return best


def ours(N):
    from formulations import multibody as mb
    from formulations.multibody.demo import cardan_chain
    return mb, cardan_chain(N, LINK)


def make(name: str, N: int):
    """The evaluation to time for candidate ``name`` on an N-body chain, and a
    self-check value (max |ν - v| where the candidate returns ν, else NaN)."""
    rng = np.random.default_rng(0)
    q = 0.3 * rng.standard_normal(2 * N)
    v = rng.standard_normal(2 * N)
    tau = rng.standard_normal(2 * N)
    if name in ("ldlt", "sweep", "momentum-rhs", "lagrange-dense"):
        mb, m = ours(N)
        d = mb.Data(m)
        p = mb.momenta(m, d, q, v)
        if name in ("ldlt", "sweep"):
            def fn():
                return mb.velocities_from_momenta(m, d, q, p, method=name)
            return fn, lambda: np.abs(fn() - v).max()
        if name == "momentum-rhs":
            def fn():
                return mb.momentum_rhs(m, d, 0.0, q, p, tau)
            return fn, lambda: np.abs(fn()[2] - v).max()

        def fn():
            return mb.forward_dynamics(m, d, q, v, tau)
        return fn, lambda: float("nan")
    if name.startswith("pinocchio"):
        import pinocchio as pin
        pm = pin.Model()
        pm.gravity = pin.Motion(np.array([0.0, 0.0, -9.81, 0.0, 0.0, 0.0]))
        jid = 0
        for i in range(N):
            jc = pin.JointModelComposite()
            jc.addJoint(pin.JointModelRX())
            jc.addJoint(pin.JointModelRY())
            jid = pm.addJoint(jid, jc, pin.SE3(np.eye(3), np.array([0, 0, -LINK if i else 0.0])), f"j{i}")
            pm.appendBodyToJoint(jid, pin.Inertia(MASS, np.array([0, 0, -LINK / 2]), np.diag(INERTIA)),
                                 pin.SE3.Identity())
        pd = pm.createData()
        if name == "pinocchio-aba":
            def fn():
                return pin.aba(pm, pd, q, v, tau)
        else:
            def fn():
                pin.crba(pm, pd, q)
                pin.cholesky.decompose(pm, pd)
                return pin.cholesky.solve(pm, pd, tau - pin.nonLinearEffects(pm, pd, q, v))
        return fn, lambda: float("nan")
    import mujoco
    spec = mujoco.MjSpec()
    b = spec.worldbody
    for i in range(N):
        b = b.add_body(pos=[0, 0, -LINK if i else 0.0], mass=MASS, ipos=[0, 0, -LINK / 2],
                       inertia=list(INERTIA), explicitinertial=True)
        b.add_joint(type=mujoco.mjtJoint.mjJNT_HINGE, axis=[1, 0, 0])
        b.add_joint(type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 1, 0])
    mm = spec.compile()
    md = mujoco.MjData(mm)
    md.qpos[:], md.qvel[:], md.qfrc_applied[:] = q, v, tau
    step = mujoco.mj_step if name == "mujoco-step" else mujoco.mj_forward

    def fn():
        if name == "mujoco-step":     # keep the state fixed: time the same step again
            md.qpos[:], md.qvel[:], md.time = q, v, 0.0
        step(mm, md)
    return fn, lambda: float("nan")


def worker(name: str, N: int) -> dict:
    # warm up on a 2-body chain first: the baseline then excludes the libraries
    # and numba's loaded machine code (~100-200 MB), leaving what N costs
    make(name, 2)[0]()
    base = _rss_mb()
    fn, check = make(name, N)
    t = _time(fn)
    return {"name": name, "N": N, "time": t, "peak_mb": _rss_mb() - base, "check": float(check())}


def run_case(name, N):
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
    cmd = [sys.executable, __file__, "--worker", name, str(N)]
    pre = limit if name.startswith("pinocchio") else None
    r = subprocess.run(cmd, capture_output=True, text=True, preexec_fn=pre, timeout=900)
    if r.returncode != 0:
        tail = (r.stderr.strip().splitlines() or ["?"])[-1]
        why = "out of memory (> 6 GiB)" if "memory" in r.stderr.lower() or r.returncode in (-9, 137) \
            else tail[:80]
        return {"name": name, "N": N, "time": np.nan, "peak_mb": np.nan, "error": why}
    return json.loads(r.stdout.strip().splitlines()[-1])


def available(name):
    mod = {"pinocchio": "pinocchio", "mujoco": "mujoco"}.get(name.split("-")[0])
    if mod is None:
        return True
    try:
        __import__(mod)
        return True
    except ImportError:
        return False


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="10,30,100,300,1000,3000,5000")
    ap.add_argument("--candidates", default=",".join(CANDIDATES))
    ap.add_argument("--plot", default=None)
    ap.add_argument("--worker", nargs=2, metavar=("NAME", "N"))
    args = ap.parse_args(argv)
    if args.worker:
        print(json.dumps(worker(args.worker[0], int(args.worker[1]))))
        return 0
    sizes = [int(s) for s in args.sizes.split(",")]
    cands = [c for c in args.candidates.split(",") if c in CANDIDATES]
    missing = [c for c in cands if not available(c)]
    for c in missing:
        print(f"[skip] {c}: not installed (pip install -e '.[benchmark]')", file=sys.stderr)
    cands = [c for c in cands if c not in missing]
    results = []
    def skipped(c, N):
        return (c == "lagrange-dense" and N > DENSE_MAX) or (c.startswith("mujoco") and N > MUJOCO_MAX)

    total = sum(1 for N in sizes for c in cands if not skipped(c, N))
    k = 0
    for N in sizes:
        for c in cands:
            if skipped(c, N):
                continue
            k += 1
            r = run_case(c, N)
            results.append(r)
            msg = r.get("error") or f"{r['time'] * 1e3:9.3f} ms  peak +{r['peak_mb']:.0f} MB"
            print(f"[{k}/{total}] N={N:5d} {c:15s} {msg}", file=sys.stderr, flush=True)
    print("\nTime per evaluation [ms], Cardan chains (nv = 2N); peak RSS growth [MB] in ()")
    print(f"{'N':>6} " + " ".join(f"{c:>18}" for c in cands))
    for N in sizes:
        row = []
        for c in cands:
            r = next((r for r in results if r["name"] == c and r["N"] == N), None)
            if r is None:
                row.append(f"{'-':>18}")
            elif "error" in r:
                row.append(f"{'failed':>18}")
            else:
                row.append(f"{r['time'] * 1e3:10.4f} ({r['peak_mb']:4.0f})")
        print(f"{N:6d} " + " ".join(row))
    for r in results:
        if "error" in r:
            print(f"  {r['name']} at N={r['N']}: {r['error']}")
    worst = {c: max((r.get("check", np.nan) for r in results if r["name"] == c
                     and np.isfinite(r.get("check", np.nan))), default=None) for c in cands}
    print("max |ν - v| over the sizes (self-check of the O(N) solvers): " +
          ", ".join(f"{c} {w:.1e}" for c, w in worst.items() if w is not None))
    print("\nFitted slope of log(time) against log(N), N >= 100 (1 = linear):")
    slopes = {}
    for c in cands:
        pts = [(r["N"], r["time"]) for r in results if r["name"] == c and r["N"] >= 100
               and np.isfinite(r["time"])]
        if len(pts) >= 2:
            x, y = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
            slopes[c] = float(np.polyfit(x, y, 1)[0])
            print(f"  {c:15s} {slopes[c]:.2f}")
    by = {(r["name"], r["N"]): r for r in results}
    if "ldlt" in cands and "sweep" in cands:
        print("\nsweep / LDL' time ratio (Ivanov & Shimanovsky 2017 report 1.35-1.4):")
        for N in sizes:
            a, b = by.get(("sweep", N)), by.get(("ldlt", N))
            if a and b and np.isfinite(a["time"]) and np.isfinite(b["time"]):
                print(f"  N={N:5d}  {a['time'] / b['time']:.2f}")
    if ("mujoco-step", 1000) in by and ("momentum-rhs", 1000) in by:
        a, b = by[("mujoco-step", 1000)], by[("momentum-rhs", 1000)]
        print(f"\nN=1000: MuJoCo mj_step / our momentum-form right-hand side = {a['time'] / b['time']:.1f}x")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from qpcontact.plots.figures import save_figure
        fig, ax = plt.subplots(figsize=(7.5, 5))
        for c in cands:
            pts = sorted((r["N"], r["time"]) for r in results if r["name"] == c and np.isfinite(r["time"]))
            if pts:
                lab = c + (f" (slope {slopes[c]:.2f})" if c in slopes else "")
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=lab)
        ax.set_xlabel("bodies N (Cardan joints, nv = 2N)")
        ax.set_ylabel("time per evaluation [s]")
        ax.set_title("Forward dynamics of a chain: time against N")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        print(f"\nplot: {save_figure(fig, args.plot)}")
    return 0


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    sys.exit(main())
