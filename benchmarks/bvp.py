"""The BVP solver (Pustovoy, Levin & Krasnorutskiy 2014) against
scipy.integrate.solve_bvp on the planar elastica.

For the tip-loaded cantilever (α = PL²/EI = 1 ... 1e4) and the axially loaded
column (buckled branch, α up to 10): time and error against tolerance for
formulations.rods.bvp and for solve_bvp (cold start from the straight rod, and with
manual load stepping: each α started from the previous solution), and the
load range each reaches from a cold start.  Saves the load-deflection curve
with the analytic one (PNG).  Errors are against the exact elliptic-integral
solutions.

    .venv/bin/python benchmarks/bvp.py --plot docs/figures/elastica.png
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
from scipy.integrate import solve_bvp
from scipy.optimize import brentq
from scipy.special import ellipe, ellipeinc, ellipk, ellipkinc

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations import rods  # noqa: E402
from qpcontact.plots.figures import save_figure  # noqa: E402

ALPHAS = (1.0, 10.0, 100.0, 1e3, 1e4)


def exact_cantilever(alpha):
    def phi1(m):
        return np.arcsin(1.0 / np.sqrt(2.0 * m))

    theta = brentq(lambda t: ellipk((1 + np.sin(t)) / 2) - ellipkinc(phi1((1 + np.sin(t)) / 2),
                                                                     (1 + np.sin(t)) / 2)
                   - np.sqrt(alpha), 1e-12, np.pi / 2 - 1e-14)
    m = (1 + np.sin(theta)) / 2
    return 1 - 2 / np.sqrt(alpha) * (ellipe(m) - ellipeinc(phi1(m), m))


def scipy_cantilever(alpha, tol, guess=None, mesh=None):
    mesh = np.linspace(0, 1, 41) if mesh is None else mesh
    y0 = np.zeros((4, mesh.size)) if guess is None else guess
    res = solve_bvp(lambda s, Y: rods.cantilever_f(s, Y, alpha), rods.clamped_free_bc, mesh, y0,
                    tol=tol, max_nodes=200000)
    return res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plot", default=None)
    args = ap.parse_args(argv)
    print("| alpha | tol | ours: time [s] | ours: error | scipy cold: time [s] | scipy cold: error "
          "| scipy load-stepped: time [s] | scipy load-stepped: error |")
    print("|---|---|---|---|---|---|---|---|")
    for alpha in ALPHAS:
        exact = exact_cantilever(alpha)
        for tol in (1e-4, 1e-8):
            t0 = time.perf_counter()
            ours = rods.cantilever(alpha, tol=tol)
            t_ours = time.perf_counter() - t0
            e_ours = abs(rods.tip_deflection(ours) - exact) if ours.ok else np.nan
            t0 = time.perf_counter()
            cold = scipy_cantilever(alpha, tol)
            t_cold = time.perf_counter() - t0
            e_cold = abs(-cold.y[3, -1] - exact) if cold.success else np.nan
            # manual load stepping: 20 steps in log alpha, each from the last solution
            t0 = time.perf_counter()
            sol = None
            for a in np.logspace(-2, np.log10(alpha), 20):
                sol = scipy_cantilever(a, tol, None if sol is None else sol.sol(sol.x), None if sol
                                       is None else sol.x)
                if not sol.success:
                    break
            t_step = time.perf_counter() - t0
            e_step = abs(-sol.y[3, -1] - exact) if sol.success else np.nan
            print(f"| {alpha:g} | {tol:.0e} | {t_ours:.3f} | {e_ours:.1e} | {t_cold:.3f} | "
                  f"{e_cold:.1e}{'' if cold.success else ' (failed)'} | {t_step:.3f} | {e_step:.1e}"
                  f"{'' if sol.success else ' (failed)'} |", flush=True)
    # load range from a cold start
    reach = {"ours": 0.0, "scipy": 0.0}
    for alpha in (1, 2, 5, 10, 20, 50, 100, 1e3, 1e4):
        ok_ours = rods.cantilever(alpha, tol=1e-6).ok
        cold = scipy_cantilever(alpha, 1e-6)
        ok_scipy = cold.success and abs(-cold.y[3, -1] - exact_cantilever(alpha)) < 1e-3
        if ok_ours:
            reach["ours"] = alpha
        if ok_scipy and reach["scipy"] == alpha_prev(alpha):
            reach["scipy"] = alpha
    print(f"\nlargest alpha reached from a straight initial guess (and right to 1e-3): "
          f"formulations.rods.bvp {reach['ours']:g}, scipy solve_bvp {reach['scipy']:g}")
    res, path = rods.column(10.0)
    print(f"column: buckled branch followed to alpha = 10, theta_L = {abs(res.y[0, -1]):.6f} "
          "(exact 2.795729)")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        alphas, defl, _ = rods.cantilever_curve(1e4)
        fig, ax = plt.subplots(figsize=(7, 4.5))
        ax.semilogx(alphas, defl, "-", lw=2,
                    label="formulations.rods.bvp, pseudo-arclength continuation")
        grid = np.logspace(-2, 4, 40)
        ax.semilogx(grid, [exact_cantilever(a) for a in grid], "o", ms=4, mfc="none",
                    label="exact (elliptic integrals)")
        ax.set_xlabel("alpha = P L^2 / EI")
        ax.set_ylabel("tip deflection / L")
        ax.set_title("Cantilever under a transverse dead tip load")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        fig.tight_layout()
        print("plot written to", save_figure(fig, args.plot))


def alpha_prev(alpha):
    seq = (1, 2, 5, 10, 20, 50, 100, 1e3, 1e4)
    i = seq.index(alpha)
    return 0.0 if i == 0 else seq[i - 1]


if __name__ == "__main__":
    main()
