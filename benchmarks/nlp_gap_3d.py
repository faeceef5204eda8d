"""The dense 3-D compact piles as a nonlinear program: Coulomb's law as the
zero of a smooth nonconvex gap function, solved by IPOPT (through CasADi),
judged by the package's certificate (docs/dev-notes.md, "The dense 3-D
piles as a nonlinear program solved by IPOPT").

The program.  Per contact i, u_i = (W r + q)_i = (u_N, u_T), r_i = (r_N,
r_T), u_T, r_T in R², μ_i > 0, and a slack s_i (the slip speed):

    minimise   Σ_i g_i,   g_i = r_N u_N + μ r_N s + r_T · u_T
    subject to r_N >= 0,  μ² r_N² − ‖r_T‖² >= 0      (r_i in the cone K_i)
               u_N >= 0,  s >= 0,  s² − ‖u_T‖² >= 0   (s >= ‖u_T‖)

Why its global minimum 0 is exactly Coulomb's law.  On the feasible set
‖r_T‖ <= μ r_N and ‖u_T‖ <= s, so by Cauchy–Schwarz r_T · u_T >= −‖r_T‖ ‖u_T‖
>= −μ r_N ‖u_T‖ and

    g_i >= r_N u_N + μ r_N (s − ‖u_T‖) >= 0   (both terms >= 0).

So Σ g_i >= 0, and Σ g_i = 0 forces every g_i = 0, hence (i) r_N u_N = 0
(Signorini); (ii) μ r_N (s − ‖u_T‖) = 0, i.e. s = ‖u_T‖ where r_N > 0;
(iii) equality in both inequalities on r_T · u_T: where r_N > 0 and u_T != 0,
‖r_T‖ = μ r_N and r_T antiparallel to u_T, r_T = −μ r_N u_T/‖u_T‖ (sliding,
with u_N = 0 by (i)); where u_T = 0, any r in K with u_N r_N = 0 (sticking
if r_N > 0); where r_N = 0, r_T = 0 by the cone and u_N >= 0 (open).  These
are the three cases of Coulomb–Signorini, i.e. r in K, û in K*, r ⟂ û.
Conversely a Coulomb solution with s = ‖u_T‖ is feasible with every g_i = 0.
The function is smooth (polynomial) and nonconvex (the μ r_N s term; with
μ = 0 it is r·(W r + q), convex for W >= 0), so it has local minima above
0; and the squared cones lose their gradient at the apex (an open contact's
r = 0, a sticking one's u_T = 0), where the solutions have no multipliers.

The cones given to IPOPT (``--deltas``).  "0": squared, as above.  Else
hyperboloids inside the cones, μ r_N >= sqrt(‖r_T‖² + δ²) and s >=
sqrt(‖u_T‖² + δ²), which keep a gradient (in r_N, s) everywhere; open
contacts get r_N >= δ/μ, sticking ones s >= δ, so the optimum is O(δ) per
contact, and the curvature at the apex is 1/δ.  A list of δ is one IPOPT
solve each, from the last one's point.

Variables given to IPOPT: x = (r̃, ũ, s̃) with r = R r̃, u = V ũ, s = V s̃
(R the start's largest impulse, or max|q| over the median of W's diagonal
when the start is zero; V = max|q|), ũ tied to r̃ by the linear equalities
ũ − (R/V) W r̃ − q/V = 0 (W's sparse pattern in the Jacobian, the Hessian
block-diagonal per contact; exact Hessian by CasADi's SX), objective
Σ g_i / (R V).  Variants (``--form``): "penalty" (the program above);
"scholtes" (the same constraints plus g_i <= τ per contact, τ = 1e-2 …
1e-10 in scaled units, one solve each from the last, objective Σ g_i or
none, ``--objective``).  Starts (``--start``): "zero" (r = 0, IPOPT's own
push into the interior) or "auto" (``qpcontact.solve(problem, "auto",
accuracy=1e-6)``'s answer r, its best point, u = W r + q, s = ‖u_T‖), given
with bound_push = bound_frac = 1e-9, mu_init = 1e-6 and IPOPT's
least-squares multipliers (a later solve of a list the same; IPOPT's warm
start with the last solve's duals diverged).  IPOPT's tol is 1e-8
(``NLP_TOL``): at 1e-12 it never stops, its complementarity never that
small.  ``NLP_OPTS`` (JSON) adds IPOPT options; ``NLP_CACHE`` (a folder)
keeps "auto"'s answer per row (the rerun of a row then shows the first
run's "auto" seconds).

The judge is the package: IPOPT's r goes to ``qpcontact.solve(problem,
"newton", max_iter=0, r0=r)`` (the certificate at 1e-6), then to Newton from
there (its polish, ``--newton-iters``).

Setup (CasADi's wheel bundles IPOPT and MUMPS; kept out of the project's
dependencies):

    python3 -m venv /work/venv-nlp
    /work/venv-nlp/bin/pip install casadi numpy scipy
    /work/venv-nlp/bin/pip install -e .          # the package and its own dependencies
    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 /work/venv-nlp/bin/python \\
        benchmarks/nlp_gap_3d.py --rows c500:2,c1000:0 --start auto --form penalty

Rows as in benchmarks/auto_side_by_side.py: {c: compact (agitation 0.1,
polydispersity 0.005), l: the generator's defaults}{n}:{seeds}; each row in
its own process.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[var] = "1"

import numpy as np  # noqa: E402
# the rows and the compact piles as the "auto" side-by-side reads them (this folder)
from auto_side_by_side import COMPACT, specs  # noqa: E402
TOL = 1e-6
TOL_IPOPT = float(os.environ.get("NLP_TOL", "1e-8"))


def pile(spec: str):
    from qpcontact.cases.piles import sphere_pile

    kind, rest = spec[0], spec[1:]
    n, seed = (int(x) for x in rest.split(":"))
    return sphere_pile(n, seed=seed, **(COMPACT if kind == "c" else {})).problem


def build(problem, R: float, V: float, form: str, objective: str, squared: bool):
    """The scaled program (module docstring) as a CasADi IPOPT solver factory
    over x = (r̃, ũ, s̃) with parameters p = (τ, δ); and the bounds."""
    import casadi as ca
    import scipy.sparse as sp

    nc, m = problem.n_contacts, 3 * problem.n_contacts
    W = sp.csc_matrix(problem.W) * (R / V)
    x = ca.SX.sym("x", 2 * m + nc)
    p = ca.SX.sym("p", 2)
    tau, delta = p[0], p[1]
    r, u, s = x[:m], x[m:2 * m], x[2 * m:]
    Wd = ca.DM(ca.Sparsity(m, m, W.indptr.tolist(), W.indices.tolist()), W.data.tolist())
    eq = u - ca.mtimes(Wd, r) - ca.DM(np.asarray(problem.q, float) / V)
    rN, rT1, rT2 = r[0::3], r[1::3], r[2::3]
    uN, uT1, uT2 = u[0::3], u[1::3], u[2::3]
    mu = ca.DM(np.asarray(problem.mu, float))
    gap = rN * uN + mu * rN * s + rT1 * uT1 + rT2 * uT2
    if squared:
        cone_r = (mu * rN) ** 2 - rT1 ** 2 - rT2 ** 2
        cone_u = s ** 2 - uT1 ** 2 - uT2 ** 2
    else:
        # The cones squared lose their gradient at the apex (open r = 0, sticking
        # u_T = 0), and with it every constraint qualification: the solutions have
        # no multipliers.  These hyperboloids inside the cones keep a gradient in
        # r_N (s) everywhere; open contacts get r_N >= δ/μ, sticking ones s >= δ.
        cone_r = mu * rN - ca.sqrt(rT1 ** 2 + rT2 ** 2 + delta ** 2)
        cone_u = s - ca.sqrt(uT1 ** 2 + uT2 ** 2 + delta ** 2)
    g = [eq, cone_r, cone_u]
    lbg = [np.zeros(m), np.zeros(nc), np.zeros(nc)]
    ubg = [np.zeros(m), np.full(nc, np.inf), np.full(nc, np.inf)]
    if form == "scholtes":
        g.append(gap - tau)
        lbg.append(np.full(nc, -np.inf))
        ubg.append(np.zeros(nc))
    f = ca.sum1(gap) if objective == "gap" else ca.SX(0.0)
    nlp = {"x": x, "f": f, "g": ca.vertcat(*g), "p": p}
    lbx = np.full(2 * m + nc, -np.inf)
    lbx[0:m:3] = 0.0          # r_N >= 0
    lbx[m:2 * m:3] = 0.0      # u_N >= 0
    lbx[2 * m:] = 0.0         # s >= 0

    def solver(opts):
        return ca.nlpsol("gap", "ipopt", nlp, {"ipopt": opts, "print_time": False})

    return solver, dict(lbx=lbx, ubx=np.full(2 * m + nc, np.inf),
                        lbg=np.concatenate(lbg), ubg=np.concatenate(ubg))


def stages(form: str, deltas: str):
    """(τ, δ) of each solve: "penalty" δ down the list; "scholtes" τ = 1e-2 …
    1e-10 at the list's last δ."""
    ds = [float(d) for d in deltas.split(",")]
    if form == "penalty":
        return [(np.inf, d) for d in ds]
    return [(t, ds[-1]) for t in 10.0 ** -np.arange(2, 11, 2)]


def certificate(problem, r) -> float:
    import qpcontact

    return float(qpcontact.solve(problem, "newton", accuracy=TOL, max_iter=0, r0=r).error)


def judge(problem, r, newton_iters: int):
    """The package's certificate of r at 1e-6, then Newton's polish from r."""
    import qpcontact

    c = qpcontact.solve(problem, "newton", accuracy=TOL, max_iter=0, r0=r)
    t = time.process_time()
    pol = qpcontact.solve(problem, "newton", accuracy=TOL, max_iter=newton_iters, r0=r,
                          time_limit=60)
    return dict(cert=float(c.error), cert_ok=bool(c.ok), newton=float(pol.error),
                newton_ok=bool(pol.ok), newton_cpu=time.process_time() - t)


def child(spec: str, form: str, start: str, max_iter: int, newton_iters: int,
          verbose: int, objective: str, deltas: str, limit: float,
          stage_newton: bool = False) -> dict:
    import qpcontact

    problem = pile(spec)
    nc, m = problem.n_contacts, 3 * problem.n_contacts
    row = dict(spec=spec, contacts=nc, form=form, start=start, objective_kind=objective,
               deltas=deltas,
               w_nnz=int(problem.W.nnz))
    qpcontact.solve(pile("c200:0"), "nsgs-newton")           # compiled kernels loaded
    if start == "auto":
        kept = os.path.join(os.environ.get("NLP_CACHE", ""), f"auto-{spec}.npz")
        if os.environ.get("NLP_CACHE") and os.path.exists(kept):
            with np.load(kept) as z:
                r0, seen = z["r"], json.loads(str(z["row"]))
        else:
            t0, c0 = time.perf_counter(), time.process_time()
            a = qpcontact.solve(problem, "auto", accuracy=TOL, time_limit=60)
            r0 = np.asarray(a.r, float)
            seen = dict(auto_err=float(a.error), auto_ok=bool(a.ok),
                        auto_wall=time.perf_counter() - t0, auto_cpu=time.process_time() - c0)
            if os.environ.get("NLP_CACHE"):
                np.savez(kept, r=r0, row=json.dumps(seen))
        row.update(seen)
        R = float(np.abs(r0).max())
    else:
        r0 = np.zeros(m)
        # the impulse that cancels the largest approach speed at a contact
        R = float(np.abs(problem.q).max() / np.median(problem.W.diagonal()))
    V = float(np.abs(problem.q).max())
    row.update(R=R, V=V)
    u0 = (problem.W @ r0 + problem.q) / V
    s0 = np.linalg.norm(u0.reshape(-1, 3)[:, 1:], axis=1)
    x0 = np.concatenate([r0 / R, u0, s0])
    t0, c0 = time.perf_counter(), time.process_time()
    solver, bounds = build(problem, R, V, form, objective, squared=deltas == "0")
    row["build_cpu"] = time.process_time() - c0
    opts = {"max_iter": max_iter, "tol": TOL_IPOPT, "acceptable_iter": 0,
            "print_level": verbose, "linear_solver": "mumps"}
    if start == "auto":
        # from the start itself, IPOPT's least-squares multipliers, a small barrier
        opts.update(bound_push=1e-9, bound_frac=1e-9, mu_init=1e-6)
    opts.update(json.loads(os.environ.get("NLP_OPTS", "{}")))
    # a later stage from the last one's point, with IPOPT's least-squares
    # multipliers (its own warm start, with the last stage's duals, diverged)
    warm = dict(opts, bound_push=1e-9, bound_frac=1e-9, mu_init=1e-6)
    iters, trail, x = 0, [], x0
    for k, (tau, delta) in enumerate(stages(form, deltas)):
        left = limit - (time.perf_counter() - t0)
        if left <= 0:
            break
        S = solver(dict(warm if k else opts, max_wall_time=left))
        sol = S(x0=x, p=[tau, delta], **bounds)
        st = S.stats()
        iters += st["iter_count"]
        x = np.asarray(sol["x"]).ravel()
        trail.append((tau, delta, float(sol["f"]), st["return_status"], st["iter_count"],
                      round(time.process_time() - c0, 1), certificate(problem, x[:m] * R)))
        if stage_newton:
            # Newton from every stage's point (its CPU counted in the stage's)
            trail[-1] += (judge(problem, x[:m] * R, newton_iters)["newton"],)
        if not st["success"]:
            break
    row.update(ipopt_wall=time.perf_counter() - t0, ipopt_cpu=time.process_time() - c0,
               iters=iters, trail=trail, objective=trail[-1][2], status=trail[-1][3])
    r = x[:m] * R
    # how far IPOPT's last iterate is from its own feasible set (scaled): u = W r + q
    # and s >= ‖u_T‖ (its objective is a gap only there)
    U = x[m:2 * m].reshape(-1, 3)
    row["infeasible"] = float(max(np.abs(x[m:2 * m] - (problem.W @ r + problem.q) / V).max(),
                                  np.maximum(np.linalg.norm(U[:, 1:], axis=1) - x[2 * m:],
                                             0).max(), np.maximum(-U[:, 0], 0).max()))
    # where IPOPT stopped, how far r is from the cone (it keeps the bounds, not the
    # quadratic constraints, exactly)
    Rr = r.reshape(-1, 3)
    row["cone_viol"] = float(np.maximum(np.linalg.norm(Rr[:, 1:], axis=1)
                                        - problem.mu * Rr[:, 0], 0).max() / R)
    row.update(judge(problem, r, newton_iters))
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", default="c200:0")
    ap.add_argument("--form", choices=("penalty", "scholtes"), default="penalty")
    ap.add_argument("--start", choices=("zero", "auto"), default="zero")
    ap.add_argument("--objective", choices=("gap", "zero"), default="gap",
                    help="Scholtes' objective: Σ g_i or none (a feasibility problem)")
    ap.add_argument("--deltas", default="1e-6",
                    help="0: the cones squared; else the hyperboloids' δ, one solve each "
                         "(comma-separated, penalty form; scholtes: the last)")
    ap.add_argument("--max-iter", type=int, default=3000, help="IPOPT's iterations at most")
    ap.add_argument("--newton-iters", type=int, default=100)
    ap.add_argument("--stage-newton", action="store_true",
                    help="Newton from every solve's point too (the trail's last entry)")
    ap.add_argument("--limit", type=float, default=180.0,
                    help="IPOPT's wall seconds over all its solves of a row")
    ap.add_argument("--verbose", type=int, default=0, help="IPOPT's print_level")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        row = child(args.rows, args.form, args.start, args.max_iter, args.newton_iters,
                    args.verbose, args.objective, args.deltas, args.limit,
                    args.stage_newton)
        print(json.dumps(row))
        return
    print("| row | contacts | start | form | load | IPOPT its | status | objective | "
          "wall / CPU s | cert | Newton | ✓ |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for spec in specs(args.rows):
        with open("/proc/loadavg") as f:
            load = f.read().split()[0]
        cmd = [sys.executable, __file__, "--child", "--rows", spec, "--form", args.form,
               "--start", args.start, "--objective", args.objective, "--deltas", args.deltas,
               "--limit", str(args.limit), "--max-iter", str(args.max_iter),
               "--newton-iters", str(args.newton_iters), "--verbose", str(args.verbose)]
        out = subprocess.run(cmd + (["--stage-newton"] if args.stage_newton else []),
                             capture_output=True, text=True)
        if args.verbose:
            print(out.stdout[-20000:], out.stderr[-3000:], file=sys.stderr)
        try:
            w = json.loads(out.stdout.strip().splitlines()[-1])
        except (IndexError, json.JSONDecodeError):
            print(f"| {spec} | failed: {out.stderr.strip()[-300:]} |", flush=True)
            continue
        ok = "✓" if (w["cert_ok"] or w["newton_ok"]) else ""
        auto = (f" (auto {w['auto_err']:.1e}{' ✓' if w['auto_ok'] else ''}, "
                f"{w['auto_wall']:.0f}/{w['auto_cpu']:.0f} s)") if "auto_err" in w else ""
        print(f"| {spec} | {w['contacts']} | {w['start']}{auto} | {w['form']} δ {args.deltas} | "
              f"{load} | "
              f"{w['iters']} | {w['status']} | {w['objective']:.2e} | "
              f"{w['ipopt_wall']:.1f} / {w['ipopt_cpu']:.1f} | {w['cert']:.1e} | "
              f"{w['newton']:.1e} | {ok} |", flush=True)
        print("    " + json.dumps({k: w[k] for k in ("trail", "infeasible", "cone_viol", "R", "V",
                                                       "build_cpu", "newton_cpu")}), flush=True)


if __name__ == "__main__":
    main()
