"""Drum stepping speed, measured side by side in one run: the stack model
(formulations/drum) and the 2-D cross-section (formulations/drum2d).

Stack (``--model stack``): contact-steps per second of the default method
("bpp", warm-started) for stacks of 10 ... 10 000 logs, beside the per-step
time of the fastest QP backend at "high" on the same steps.  A stack of logs
(0.10-0.20 m, 1.2 m, green spruce, 5 % damping) falls onto the shell with
random gaps (0-2 mm) and velocities (0-1 m/s down), tau = 1/20 of the shortest
contact period.  Every step's answer is certified.  For the QP backends, every
k-th step's LCP (up to --sample of them) is re-solved and timed.
Target: >= 1e6 contact-steps/s for the 10 000-log stack on 2 cores.

2-D drum (``--model 2d``): a 4 m drum, 8 lifters (0.15 m high,
0.05 m thick), 0.15 rev/s, spruce logs 1 m long, 0.10-0.14 m across (above
500 logs the diameters shrink by sqrt(500/n) so that the fill fraction stays
that of 500 logs: 0.05-0.07 m at 2 000), effects friction (mu = 0.4 at every
contact), rotation, damping (e = 0.2) and log_elasticity (the stack model's
springs), h = 2 ms.  The logs start on a hexagonal lattice (5 mm
clearance, scaled as the diameters; the sites on the lifters left out) and
settle for --settle steps with friction, damping and the springs but the
shell still; then the drum turns and Drum2D.simulate's default route (NSGS +
Newton warm-started from the previous step's impulses, "auto" where that is
not certified) steps --warmup untimed steps and --d2-steps timed ones.  The
same settled bed is then stepped without friction (one LCP a step) for the
frictionless row.  Tables: speed (steps/s, certified contact-steps/s,
certified fraction, worst certificate, fallbacks, the share of the step in
solve()), time per step against the number of contacts (ratios between sizes
and log-log slopes across sizes and within each run), and, on --d2-sample
timed steps per size, the step's friction problem rebuilt from the run (its
contacts from the on_step hook, the state before it from the result; the
run's impulses must certify on it as in the run) and solved by every friction
method of the registry at "high" (time limit --time-limit s each) against the
warm-started route, plus the frictionless LCP of the same contacts.

Last, per size, the CPU per simulated second of the friction route (its
timed steps) against a resolved explicit penalty DEM of the same scene from
the same settled bed (benchmarks/drum2d_dem.py: the same springs, dashpots
for the restitution, Coulomb-capped tangential dashpots, 50 steps a contact
period, numba) run for --dem-time simulated seconds in the same process.

The settled beds are kept in out/bench/drum2d/ (--cache; --no-cache settles
afresh) and read back by the next run with the same sizes and --settle.

    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 .venv/bin/python benchmarks/drum.py
    .venv/bin/python benchmarks/drum.py --model 2d --d2-logs 100,500,2000
    .venv/bin/python benchmarks/drum.py --quick        # both models, small sizes

On the 2-core machine the default run (stack 10 ... 10 000 logs; 2-D 100 and
500 logs, settling included) took 97 s, --quick 50 s; 2 000 logs add about
18 minutes, 14 of them settling the bed (saved for the next run).

Options: --model both|stack|2d  --quick  --logs 10,100,1000,10000  --steps 200
--sample 10  --backends piqp,clarabel,osqp (QP backends, also for the 2-D
frictionless LCPs)  --d2-logs 100,500  --d2-steps 40  --warmup 10  --settle 400
--d2-sample 2  --time-limit 10 (s per method on a sampled step)  --methods
(friction methods, comma-separated; default all of the registry's for 2-D)
--dem-time 0.05 (s simulated by the DEM)  --cache DIR  --no-cache
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
import warnings

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, ROOT)
import qpcontact  # noqa: E402
from formulations.drum import Drum, Log  # noqa: E402
from formulations.drum2d import (LIFTER, Discs, Drum2D, Shell,  # noqa: E402
                                 UncertifiedStepWarning, find_contacts, hex_fill)
from benchmarks.drum2d_dem import penalty_dem  # noqa: E402


# ---------------------------------------------------------------- the stack model

def stack(n_logs: int, seed: int = 0) -> Drum:
    rng = np.random.default_rng(seed)
    logs = [Log.from_wood(d, 1.2, damping_ratio=0.05) for d in rng.uniform(0.10, 0.20, n_logs)]
    return Drum(logs, rng.uniform(0.0, 0.002, n_logs), -rng.uniform(0.0, 1.0, n_logs),
                effects=("gravity", "damping"))


def run_stack(args):
    backends = [b for b in args.backends.split(",") if b in qpcontact.methods()]
    rows = []
    for n in _sizes(args.logs):
        drum = stack(n)
        tau = drum.contact_periods().min() / 20
        sampled = []
        every = max(1, args.steps // args.sample)

        def keep(k, lcp, sol):
            if k % every == 0 and len(sampled) < args.sample:
                sampled.append((lcp, sol))

        drum.simulate(tau, 5)  # warm-up: imports, first assemblies
        res = drum.simulate(tau, args.steps, on_step=keep)
        per_step = res.wall_time / args.steps
        rate = n * args.steps / res.wall_time
        onsets = int(res.summary().collisions_per_log.sum())
        # the default method alone on the sampled steps (no stepping overhead)
        t_bpp = statistics.median(
            _time(lambda: qpcontact.solve(lcp, method="bpp", initial_active=sol.z > 0))
            for lcp, sol in sampled)
        best = None
        for b in backends:
            times, ok = [], True
            for lcp, sol in sampled:
                t0 = time.perf_counter()
                s = qpcontact.solve(lcp, method=b, accuracy="high")
                times.append(time.perf_counter() - t0)
                ok &= s.ok
            t = statistics.median(times)
            print(f"  {n} logs: {b} at 'high' {1e3 * t:.3f} ms/step, "
                  f"{'all certified' if ok else 'NOT all certified'}", flush=True)
            if ok and (best is None or t < best[1]):
                best = (b, t)
        rows.append((n, per_step, rate, t_bpp, best, onsets, res.fallbacks,
                     res.summary().max_certificate_error, res.wall_time / res.solve_time))
        print(f"{n} logs: {1e3 * per_step:.3f} ms/step, {rate:.3g} contact-steps/s, "
              f"{onsets} contact onsets, max error {rows[-1][7]:.1e}", flush=True)

    print("\nStack model (formulations/drum)\n")
    print("| logs | ms per step (stepper, bpp) | step / its certified solve | contact-steps/s "
          "| bpp re-solve of a sampled step [ms] | fastest QP at 'high' [ms] | QP / bpp solve "
          "| onsets | fallbacks |")
    print("|---|---|---|---|---|---|---|---|---|")
    for n, per_step, rate, t_bpp, best, onsets, fb, err, share in rows:
        qp = f"{best[0]} {1e3 * best[1]:.3f}" if best else "none certified"
        ratio = f"{best[1] / t_bpp:.1f}" if best else ""
        print(f"| {n} | {1e3 * per_step:.3f} | {share:.2f} | {rate:.3g} | {1e3 * t_bpp:.3f} "
              f"| {qp} | {ratio} | {onsets} | {fb} |")
    big = [r for r in rows if r[0] == 10000]
    if big:
        verdict = "met" if big[0][2] >= 1e6 else "NOT met"
        print(f"\ntarget >= 1e6 contact-steps/s at 10 000 logs: {big[0][2]:.3g} ({verdict})")


# ---------------------------------------------------------------- the 2-D drum

R2D = 2.0                 # m, the shell's radius (a 4 m drum)
H2D = 2e-3                # s, the step
REV_PER_S = 0.15
LIFTER_HEIGHT, LIFTER_THICKNESS, N_LIFTERS = 0.15, 0.05, 8     # m, m, -
D_MEAN, D_SPREAD = 0.12, 1.0 / 6.0      # 0.10-0.14 m
FULL_AT = 500             # above this many logs the diameters shrink as sqrt(FULL_AT/n)
EFFECTS_2D = ("friction", "rotation", "damping", "log_elasticity")
RESTITUTION = 0.2


def drum2d_shell() -> Shell:
    return Shell(R2D, omega=2 * np.pi * REV_PER_S,
                 lifter_angles=np.linspace(0, 2 * np.pi, N_LIFTERS, endpoint=False),
                 lifter_height=LIFTER_HEIGHT, lifter_half_width=LIFTER_THICKNESS / 2)


def lattice_clear_of_lifters(n: int, seed: int):
    """Centres (n, 2) [m] and diameters (n,) [m]: hex_fill's lattice (module
    docstring) without the sites that would overlap a lifter or come within
    the clearance of one (hex_fill knows only the shell circle)."""
    scale = min(1.0, (FULL_AT / n) ** 0.5)
    clearance, shell, k = 0.005 * scale, drum2d_shell(), n
    while True:
        pos, dia = hex_fill(R2D, k, D_MEAN * scale, spread=D_SPREAD, seed=seed,
                            clearance=clearance)
        c = find_contacts(Discs(dia, pos), shell, 0.0, 0.0, clearance)
        clear = np.ones(k, bool)
        clear[c.i[c.kind == LIFTER]] = False
        if clear.sum() >= n:
            keep = np.flatnonzero(clear)[:n]
            return pos[keep], dia[keep]
        k += n - int(clear.sum())


def settled_bed(n: int, settle: int, cache: str | None, seed: int = 1):
    """(Discs, settling statistics): n logs on the hexagonal lattice, settled
    for ``settle`` steps with friction, damping and the springs, the shell
    still (module docstring).  With ``cache`` (a folder) the settled state and
    its statistics are kept in a file named by n, settle and seed, and read
    back by the next run instead of settling again."""
    pos, dia = lattice_clear_of_lifters(n, seed)
    path = None if cache is None else os.path.join(cache, f"bed_{n}_{settle}_{seed}.npz")
    if path is not None and os.path.exists(path):
        z = np.load(path)
        stats = {k: z[k] for k in ("n_active", "seconds", "solve_seconds", "certified")}
        stats.update(kinetic=float(z["kinetic"]), worst=float(z["worst"]), cached=True)
        return Discs(dia, z["positions"], velocities=z["velocities"], spins=z["spins"]), stats
    clock = StepClock(f"{n} logs, settling", settle)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UncertifiedStepWarning)     # counted below
        run = Drum2D(Discs(dia, pos), drum2d_shell(), ("friction", "damping", "log_elasticity"),
                     restitution=RESTITUTION).simulate(H2D, settle, keep_contacts=False,
                                                       on_step=clock)
    stats = dict(n_active=run.n_active, seconds=clock.seconds(), solve_seconds=run.solve_seconds,
                 certified=run.certified, kinetic=float(run.kinetic[-1]),
                 worst=run.worst_certificate)
    if path is not None:
        os.makedirs(cache, exist_ok=True)
        np.savez(path, positions=run.positions[-1], velocities=run.velocities[-1],
                 spins=run.spins[-1], **stats)
    stats["cached"] = False
    return Discs(dia, run.positions[-1], velocities=run.velocities[-1],
                 spins=run.spins[-1]), stats


class StepClock:
    """The on_step hook: each step's wall time, the contacts and impulses of
    the sampled steps and of the steps just before them, and a progress line
    every ``every`` seconds."""

    def __init__(self, label, total, sampled=(), every=20.0):
        self.label, self.total, self.every = label, total, every
        self.want = set(sampled) | {s - 1 for s in sampled}
        self.kept = {}
        self.stamps = [time.perf_counter()]
        self.cpu = [time.process_time()]
        self.last_print = self.stamps[0]

    def __call__(self, n, contacts, r):
        now = time.perf_counter()
        self.stamps.append(now)
        self.cpu.append(time.process_time())
        s = n - 1                       # the step from t[s] to t[s+1]
        if s in self.want:
            self.kept[s] = (contacts, r.copy())
        if now - self.last_print > self.every:
            self.last_print = now
            print(f"    {self.label}: step {n}/{self.total}, {now - self.stamps[-2]:.2f} s for "
                  f"the last, {contacts.m} contacts", flush=True)

    def seconds(self):
        return np.diff(self.stamps)

    def cpu_seconds(self):
        return np.diff(self.cpu)


def step_problem(model: Drum2D, res, s, contacts):
    """Step s's FrictionProblem as the stepper builds it (Drum2D.step_problem),
    from the state at t[s] kept in ``res`` and the step's active ``contacts``."""
    v = np.column_stack([res.velocities[s], res.spins[s]]).ravel()
    return model.step_problem(contacts, v, H2D)


def warm_guess(prev, now):
    """The previous step's (r_N, r_T) for the contacts that persist (disc i,
    other body j, kind), 0 for new ones: the stepper's warm start."""
    (cp, rp), key = prev, (lambda c: (c.i.astype(np.int64) * 1_000_003 + c.j + 1) * 3 + c.kind)
    old = dict(zip(key(cp).tolist(), rp.reshape(-1, 2)))
    return np.concatenate([old.get(k, np.zeros(2)) for k in key(now).tolist()]) \
        if now.m else np.zeros(0)


def friction_methods(names):
    """The registry's friction methods for a 2-D problem of any size, and "auto"."""
    have = qpcontact.methods()
    found = [m for m, spec in have.items()
             if "friction-2d" in spec.problems and spec.max_n is None]
    return ["auto"] + (found if names is None else [m for m in names.split(",") if m in have])


def first_calls(prob, methods, lcp_methods):
    """Each method once on a 10-contact corner of ``prob`` (and its LCP),
    untimed, so that imports and compilation are not charged to the first
    sampled step."""
    k = min(10, prob.n_contacts)
    W = sp.csc_matrix(prob.W)[:2 * k, :][:, :2 * k]
    small = qpcontact.FrictionProblem(W, prob.q[:2 * k], prob.mu[:k], 2)
    for m in methods:
        qpcontact.solve(small, method=m, accuracy="high", time_limit=5.0)
    lcp = qpcontact.LCP(W[0::2, :][:, 0::2].tocsc(), prob.q[:2 * k:2])
    for m in lcp_methods:
        qpcontact.solve(lcp, method=m, accuracy="high", time_limit=5.0)


def on_sampled_step(model, res, s, kept, methods, lcp_methods, time_limit):
    """Step s of the run ``res`` rebuilt (step_problem, checked against the
    run's own impulses) and solved by the warm start from step s − 1's
    impulses, by each friction method cold, and (its normal LCP, without
    friction) by each LCP method: (the step's entry, the LCP rows)."""
    c, r_step = kept[s]
    prob = step_problem(model, res, s, c)
    check = qpcontact.certify(prob, r_step).error
    if not check <= max(1e-8, 10 * res.certificate_error[s]):
        raise RuntimeError(
            f"step {s}'s problem rebuilt here is not the stepper's (the run's impulses miss it "
            f"by {check:.1e} against {res.certificate_error[s]:.1e}): follow "
            "formulations/drum2d/stepper.py's _solve_step in step_problem")
    entry = dict(n=model.discs.n, step=s, contacts=c.m, in_loop=res.solve_seconds[s],
                 in_loop_err=res.certificate_error[s], in_loop_ok=bool(res.certified[s]),
                 rebuilt=check, runs=[])
    r0 = warm_guess(kept[s - 1], c) if s - 1 in kept else None
    # as the stepper solves it: compliant contacts, J's own LU first
    tries = [("warm nsgs-newton (re-solve)", "nsgs-newton",
              dict(r0=r0, square_first=model.law.compliant))]
    tries += [(m, m, {}) for m in methods]
    for label, m, opts in tries:
        fresh = step_problem(model, res, s, c)        # nothing kept from another method
        t0 = time.perf_counter()
        try:
            sol = qpcontact.solve(fresh, method=m, accuracy="high", time_limit=time_limit,
                                  **opts)
            err = sol.certificate.error if sol.certificate else np.inf
            ok, status, its = sol.ok, sol.status, sol.iterations
        except qpcontact.QpcontactError as exc:
            err, ok, status, its = np.inf, False, type(exc).__name__, None
        entry["runs"].append((label, time.perf_counter() - t0, err, ok, status, its))
        print(f"    step {s} ({c.m} contacts): {label} {entry['runs'][-1][1]:.3f} s, "
              f"error {err:.1e}{'' if ok else ' NOT certified (' + status + ')'}", flush=True)
    lcp = qpcontact.LCP(sp.csc_matrix(prob.W)[0::2, :][:, 0::2].tocsc(), prob.q[0::2])
    lcp_rows = []
    for m in lcp_methods:
        t0 = time.perf_counter()
        sol = qpcontact.solve(lcp, method=m, accuracy="high", time_limit=time_limit)
        lcp_rows.append((s, c.m, m, time.perf_counter() - t0,
                         sol.certificate.error if sol.certificate else np.inf, sol.ok))
    return entry, lcp_rows


def run_2d(args):
    sizes = _sizes(args.d2_logs)
    methods = friction_methods(args.methods)
    lcp_methods = ["auto", "bpp"] + [b for b in args.backends.split(",")
                                     if b in qpcontact.methods()]
    total = args.warmup + args.d2_steps
    spread = max(1, args.d2_steps // max(args.d2_sample, 1))
    sampled = [args.warmup + spread // 2 + k * spread for k in range(args.d2_sample)]
    rows, comparisons, lcps, per_step, settling, dems = [], [], [], {}, {}, []
    print(f"\n2-D drum: 4 m, {N_LIFTERS} lifters, {REV_PER_S} rev/s, h = {1e3 * H2D:g} ms, "
          f"effects {', '.join(EFFECTS_2D)}; settle {args.settle} steps, then {args.warmup} "
          f"untimed + {args.d2_steps} timed steps; friction methods {methods}", flush=True)
    for n in sizes:
        discs, st = settled_bed(n, args.settle, None if args.no_cache else args.cache)
        settle_ms = 1e3 * st["seconds"].mean()
        # the settling run fills up from no contacts: time against contacts
        # within one run (its first steps, compilation, left out)
        skip = slice(min(5, args.settle - 1), None)
        settling[n] = (st["n_active"][skip], st["seconds"][skip], st["solve_seconds"][skip])
        print(f"  {n} logs (Ø {discs.diameters.min():.3f}-{discs.diameters.max():.3f} m): "
              f"{'read back the bed' if st['cached'] else 'settled'} of {args.settle} steps at "
              f"{settle_ms:.0f} ms/step, kinetic energy left {st['kinetic']:.3g} J, "
              f"{int((~st['certified']).sum())} steps not certified (worst "
              f"{st['worst']:.1e})", flush=True)
        for route, effects in (("friction", EFFECTS_2D),
                               ("frictionless LCP", tuple(e for e in EFFECTS_2D
                                                          if e != "friction"))):
            model = Drum2D(discs, drum2d_shell(), effects, restitution=RESTITUTION)
            clock = StepClock(f"{n} logs, {route}", total,
                              sampled if route == "friction" else ())
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UncertifiedStepWarning)  # in the table
                res = model.simulate(H2D, total, keep_contacts=False, on_step=clock)
            timed = slice(args.warmup, total)
            secs = clock.seconds()[timed]
            act = res.n_active[timed]
            cert = res.certified[timed]
            wall = secs.sum()
            rows.append(dict(n=n, route=route, diam=discs.diameters.mean(), contacts=act.mean(),
                             ms=1e3 * wall / args.d2_steps, cps=act[cert].sum() / wall,
                             certified=cert.mean(), worst=res.certificate_error[timed].max(),
                             fallbacks=int(res.fallback[timed].sum()),
                             solve=res.solve_seconds[timed].sum() / wall,
                             settle_ms=settle_ms))
            per_step[(n, route)] = (act, secs, res.solve_seconds[timed])
            r = rows[-1]
            print(f"  {n} logs, {route}: {r['ms']:.1f} ms/step, {r['contacts']:.0f} contacts, "
                  f"certified {r['certified']:.3f}, worst {r['worst']:.1e}, fallbacks "
                  f"{r['fallbacks']}", flush=True)
            if route != "friction":
                continue
            # the resolved explicit DEM from the same settled bed, same scene
            dem = penalty_dem(model, args.dem_time)
            cpu = clock.cpu_seconds()[timed].sum() / (args.d2_steps * H2D)
            dems.append((n, cpu, dem["cpu"] / (dem["steps"] * dem["dt"]), dem))
            print(f"  {n} logs, penalty DEM: {dem['steps']} steps of {dem['dt']:.3g} s, "
                  f"{1e3 * dem['cpu'] / dem['steps']:.3f} ms CPU a step", flush=True)
            for s in sampled:
                if not comparisons:
                    first_calls(step_problem(model, res, s, clock.kept[s][0]), methods,
                                lcp_methods)
                entry, lcp_rows = on_sampled_step(model, res, s, clock.kept, methods,
                                                  lcp_methods, args.time_limit)
                comparisons.append(entry)
                lcps += [(n, *row) for row in lcp_rows]
    _print_2d(rows, per_step, settling, comparisons, lcps, args)
    _print_dem(dems)


def _print_dem(dems):
    print("\nPer simulated second against a resolved explicit penalty DEM of the same scene "
          "(benchmarks/drum2d_dem.py: the same springs, Δt = T_min/50), CPU seconds, side by "
          "side in this run\n")
    print("| logs | contact-implicit route [CPU s / simulated s] | penalty DEM [CPU s / "
          "simulated s] | DEM Δt [s] | DEM contacts in force | route / DEM |")
    print("|---|---|---|---|---|---|")
    for n, route, dem, d in dems:
        print(f"| {n} | {route:.3g} | {dem:.3g} | {d['dt']:.3g} | {d['contacts']:.0f} "
              f"| {route / dem:.2f} |")


def _slope(x, y):
    """The least-squares slope of log y against log x (nan under 2 distinct x)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    good = (x > 0) & (y > 0)
    if np.unique(x[good]).size < 2:
        return float("nan")
    return float(np.polyfit(np.log(x[good]), np.log(y[good]), 1)[0])


def _range(a):
    return f"{int(np.min(a))}-{int(np.max(a))}" if len(a) else ""


def _within(contacts, seconds):
    """The slope within one run, where its contacts span 1.3x or more."""
    a = np.asarray(contacts, float)
    a = a[a > 0]
    if a.size < 2 or a.max() < 1.3 * a.min():
        return "—"
    return f"{_slope(contacts, seconds):.2f}"


def _print_2d(rows, per_step, settling, comparisons, lcps, args):
    print("\n2-D drum (formulations/drum2d): speed\n")
    print("| logs | Ø [m] | route | mean active contacts | ms/step | steps/s | certified "
          "contact-steps/s | certified fraction | worst certificate | fallbacks | in solve() "
          "| settling ms/step |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['n']} | {r['diam']:.3f} | {r['route']} | {r['contacts']:.0f} | {r['ms']:.1f} "
              f"| {1e3 / r['ms']:.2f} | {r['cps']:.3g} | {r['certified']:.3f} | {r['worst']:.1e} "
              f"| {r['fallbacks']} | {100 * r['solve']:.0f} % | {r['settle_ms']:.0f} |")

    print("\nTime per step against contacts (slope of log time on log contacts: 1 = linear; "
          "within a run only where its contacts vary by 1.3x or more)\n")
    print("| route | logs | contacts | ms/step | µs per contact-step | × contacts | × time "
          "| within the timed steps: contacts, slope | within the settling run: contacts, "
          "slope of the step, of its solve |")
    print("|---|---|---|---|---|---|---|---|---|")
    for route in ("friction", "frictionless LCP"):
        mine = [r for r in rows if r["route"] == route]
        prev = None
        for r in mine:
            act, secs, _ = per_step[(r["n"], route)]
            ratio = (f"{r['contacts'] / prev['contacts']:.2f} | {r['ms'] / prev['ms']:.2f}"
                     if prev else " | ")
            settle = ""
            if route == "friction":
                a, t, ts = settling[r["n"]]
                settle = f"{_range(a)}, {_within(a, t)}, {_within(a, ts)}"
            print(f"| {route} | {r['n']} | {r['contacts']:.0f} | {r['ms']:.1f} "
                  f"| {1e3 * r['ms'] / r['contacts']:.1f} | {ratio} "
                  f"| {_range(act)}, {_within(act, secs)} | {settle} |")
            prev = r
        if len(mine) > 1:
            slope = _slope([r["contacts"] for r in mine], [r["ms"] for r in mine])
            print(f"| {route} | across sizes | | | | | slope {slope:.2f} | | |")

    print(f"\nSampled steps: the step's friction problem solved by each method at 'high' "
          f"(time limit {args.time_limit:g} s), against the warm-started route\n")
    print("| logs | step | contacts | in the run [ms] (error) | rebuilt: error of the run's r "
          "| method | time [ms] | iterations | certificate error | × warm in run |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for e in comparisons:
        head = (f"| {e['n']} | {e['step']} | {e['contacts']} | {1e3 * e['in_loop']:.1f} "
                f"({e['in_loop_err']:.1e}) | {e['rebuilt']:.1e} ")
        for label, secs, err, ok, status, its in e["runs"]:
            mark = "" if ok else f" ({status})"
            print(f"{head}| {label} | {1e3 * secs:.1f} | {'' if its is None else its} "
                  f"| {err:.1e}{mark} | {secs / e['in_loop']:.1f} |")
            head = "| | | | | "
    print("\nFastest certified method (cold) per size, median over the sampled steps:")
    for n in sorted({e["n"] for e in comparisons}):
        mine = [e for e in comparisons if e["n"] == n]
        warm = statistics.median(e["in_loop"] for e in mine)
        best = {}
        for e in mine:
            for label, secs, err, ok, *_ in e["runs"][1:]:
                best.setdefault(label, []).append(secs if ok else np.inf)
        label, t = min(((k, statistics.median(v)) for k, v in best.items()), key=lambda x: x[1])
        verdict = (f"{label} {1e3 * t:.1f} ms, {t / warm:.1f} × the warm route"
                   if np.isfinite(t) else "none certified every sampled step")
        print(f"  {n} logs: warm route {1e3 * warm:.1f} ms; {verdict}")

    print("\nThe same steps without friction (the normal LCP of the same contacts)\n")
    print("| logs | step | contacts | method | time [ms] | certificate error |")
    print("|---|---|---|---|---|---|")
    for n, s, m_c, m, secs, err, ok in lcps:
        print(f"| {n} | {s} | {m_c} | {m} | {1e3 * secs:.1f} | {err:.1e}"
              f"{'' if ok else ' (not certified)'} |")

    # the two tables above in one, by method and size: median time over the
    # sampled steps, against the warm route's in-run solve of the same steps
    sizes = sorted({e["n"] for e in comparisons})
    runs = {}
    for e in comparisons:
        runs.setdefault(("warm route, in the run", e["n"]), []).append(
            (e["in_loop"], e["in_loop_err"], e["in_loop_ok"], e["in_loop"]))
        for label, secs, err, ok, *_ in e["runs"]:
            runs.setdefault((label, e["n"]), []).append((secs, err, ok, e["in_loop"]))
    for n, s, m_c, m, secs, err, ok in lcps:
        warm = next(e["in_loop"] for e in comparisons if e["n"] == n and e["step"] == s)
        runs.setdefault((f"no friction: LCP by {m}", n), []).append((secs, err, ok, warm))
    contacts = {n: statistics.median(e["contacts"] for e in comparisons if e["n"] == n)
                for n in sizes}
    print("\nSampled steps by method: median time [ms] (× the warm route's in-run solve), "
          "steps certified at 'high', worst certificate error\n")
    print("| method | " + " | ".join(f"{n} logs (~{contacts[n]:.0f} contacts)" for n in sizes)
          + " |")
    print("|---|" + "---|" * len(sizes))
    for label in dict.fromkeys(k[0] for k in runs):
        cells = []
        for n in sizes:
            got = runs.get((label, n))
            if not got:
                cells.append("")
                continue
            t = statistics.median(g[0] for g in got)
            x = statistics.median(g[0] / g[3] for g in got)
            cells.append(f"{1e3 * t:.1f} (×{x:.2g}), {sum(g[2] for g in got)}/{len(got)}, "
                         f"{max(g[1] for g in got):.0e}")
        print(f"| {label} | " + " | ".join(cells) + " |")


# ---------------------------------------------------------------- common

def _sizes(text):
    return [int(x) for x in text.split(",") if x]


def _time(fn):
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", choices=("both", "stack", "2d"), default="both")
    ap.add_argument("--quick", action="store_true",
                    help="small sizes: stack 10,100,1000 logs x 100 steps; 2-D 100,500 logs")
    ap.add_argument("--logs", default="10,100,1000,10000")
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--sample", type=int, default=10)
    ap.add_argument("--backends", default="piqp,clarabel,osqp")
    ap.add_argument("--d2-logs", default="100,500")
    ap.add_argument("--d2-steps", type=int, default=40)
    ap.add_argument("--warmup", type=int, default=10)
    ap.add_argument("--settle", type=int, default=400)
    ap.add_argument("--d2-sample", type=int, default=2)
    ap.add_argument("--time-limit", type=float, default=10.0)
    ap.add_argument("--methods", default=None)
    ap.add_argument("--dem-time", type=float, default=0.05,
                    help="simulated seconds of the penalty DEM per size")
    ap.add_argument("--cache", default=os.path.join(ROOT, "out", "bench", "drum2d"),
                    help="folder for the settled beds (read back by the next run)")
    ap.add_argument("--no-cache", action="store_true", help="settle every bed afresh")
    args = ap.parse_args(argv)
    if args.quick:
        args.logs, args.steps = "10,100,1000", 100
        args.d2_logs, args.d2_steps, args.settle, args.d2_sample = "100,500", 20, 300, 1
        args.time_limit = 5.0
    start = time.perf_counter()
    if args.model in ("both", "stack"):
        run_stack(args)
    if args.model in ("both", "2d"):
        run_2d(args)
    print(f"\n(whole run {time.perf_counter() - start:.0f} s; OPENBLAS_NUM_THREADS="
          f"{os.environ['OPENBLAS_NUM_THREADS']})")


if __name__ == "__main__":
    main()
