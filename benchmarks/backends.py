"""What accuracy costs in time, per QP backend, on random SPD LCPs written as QPs.

For n = 100 and 1000 (dense) and n = 20 000 (sparse, banded): each backend's
median wall time over repeats and its certified error (componentwise, with the
normwise figure beside it) at accuracy "default" and "high", and the ratio of
that time to one Cholesky solve of the same matrix (dense: scipy.linalg.cho_factor
+ cho_solve; sparse: scipy's splu + solve), measured side by side in the same run.

Run with one BLAS thread (the Makefile's `make bench` sets it):

    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 .venv/bin/python benchmarks/backends.py

Options: --sizes 100,1000,20000  --repeats 3  --methods osqp,clarabel
         --time-limit 30 (seconds; a backend slower than that on a size is not
         re-run at larger sizes)  --plot out/backends.png
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import scipy.linalg  # noqa: E402
import scipy.sparse as sp  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402

import qpcontact  # noqa: E402
from qpcontact.plots.figures import save_figure  # noqa: E402
from qpcontact import LCP  # noqa: E402


def dense_spd_lcp(n: int, seed: int) -> LCP:
    rng = np.random.default_rng(seed)
    R = rng.standard_normal((n, n))
    M = R @ R.T / n + 0.1 * np.eye(n)
    z = np.where(rng.random(n) < 0.5, rng.uniform(0.5, 2, n), 0.0)
    w = np.where(z > 0, 0.0, rng.uniform(0.5, 2, n))
    return LCP(M, w - M @ z)


def banded_spd_lcp(n: int, seed: int) -> LCP:
    """A 1-D contact chain: tridiagonal stiffness plus a mass-like diagonal."""
    rng = np.random.default_rng(seed)
    k = rng.uniform(0.5, 1.5, n + 1)
    M = sp.diags([-k[1:-1], k[:-1] + k[1:] + 0.01, -k[1:-1]], [-1, 0, 1], format="csc")
    z = np.where(rng.random(n) < 0.5, rng.uniform(0.5, 2, n), 0.0)
    w = np.where(z > 0, 0.0, rng.uniform(0.5, 2, n))
    return LCP(M, w - M @ z)


# Backends that take a time limit, and its setting name: a stuck backend must not stall the run.
TIME_LIMIT_SETTING = {"highs": "time_limit", "osqp": "time_limit", "scs": "time_limit_secs",
                      "cvxpy:HIGHS": "time_limit", "cvxpy:SCS": "time_limit_secs"}


def cholesky_time(lcp: LCP, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        if lcp.is_sparse:
            spla.splu(lcp.M.tocsc()).solve(-lcp.q)
        else:
            scipy.linalg.cho_solve(scipy.linalg.cho_factor(lcp.M), -lcp.q)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="100,1000,20000")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--methods", default=",".join(n for n, m in qpcontact.methods().items()
                                                   if m.solves("lcp")))
    ap.add_argument("--time-limit", type=float, default=30.0)
    ap.add_argument("--plot", default="out/backends.png")
    args = ap.parse_args(argv)

    sizes = [int(s) for s in args.sizes.split(",")]
    names = args.methods.split(",")
    too_slow: set[str] = set()
    rows = []
    for n in sizes:
        lcp = banded_spd_lcp(n, seed=n) if n > 5000 else dense_spd_lcp(n, seed=n)
        kind = "sparse" if lcp.is_sparse else "dense"
        t_chol = cholesky_time(lcp, max(args.repeats, 3))
        print(f"\n== n = {n} ({kind}); one {'sparse LU' if lcp.is_sparse else 'Cholesky'} solve: "
              f"{t_chol * 1e3:.2f} ms", flush=True)
        print(f"{'method':16s} {'accuracy':8s} {'status':10s} {'error':>9s} {'normwise':>9s} "
              f"{'|min(z,w)|':>10s} {'time [ms]':>10s} {'x chol':>8s}")
        for name in names:
            method = qpcontact.get_method(name)
            if lcp.is_sparse and not method.accepts_sparse and n > 5000:
                print(f"{name:16s} skipped: dense-only backend (n x n dense copy of a sparse matrix)")
                continue
            if method.max_n is not None and n > method.max_n:
                # enumeration's 2^n bases: refused above its size limit (it ended the run)
                print(f"{name:16s} skipped: n = {n} above its size limit {method.max_n}")
                continue
            for acc in ("default", "high"):
                if (name, acc) in too_slow:
                    print(f"{name:16s} {acc:8s} skipped (over --time-limit at a smaller size)")
                    continue
                times, sol = [], None
                for r in range(args.repeats):
                    opts = {TIME_LIMIT_SETTING[name]: args.time_limit} if name in TIME_LIMIT_SETTING else {}
                    sol = qpcontact.solve(lcp, method=name, accuracy=acc, **opts)
                    times.append(sol.wall_time)
                    if sol.wall_time > args.time_limit:
                        too_slow.add((name, acc))
                        break
                t = statistics.median(times)
                comp = sol.certificate.comp_abs if sol.certificate else float("inf")
                normwise = sol.certificate.normwise_error if sol.certificate else float("inf")
                rows.append(dict(n=n, kind=kind, method=name, accuracy=acc, status=sol.status,
                                 error=sol.error, comp=comp, time=t, ratio=t / t_chol))
                print(f"{name:16s} {acc:8s} {sol.status:10s} {sol.error:9.1e} {normwise:9.1e} "
                      f"{comp:10.1e} {t * 1e3:10.2f} {t / t_chol:8.1f}", flush=True)
    if args.plot:
        plot(rows, args.plot)
    return 0


def plot(rows, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sizes = sorted({r["n"] for r in rows})
    fig, axes = plt.subplots(1, len(sizes), figsize=(6 * len(sizes), 5), squeeze=False)
    for ax, n in zip(axes[0], sizes):
        for r in (r for r in rows if r["n"] == n):
            err = max(r["error"], 1e-17)
            marker = "o" if r["accuracy"] == "high" else "s"
            color = "tab:green" if r["status"] == "solved" else "tab:red"
            ax.loglog(r["time"], err, marker, color=color, alpha=0.8)
            ax.annotate(f"{r['method']} ({r['accuracy'][0]})", (r["time"], err), fontsize=7,
                        xytext=(3, 3), textcoords="offset points")
        ax.axhline(1e-9, ls="--", color="gray", lw=0.8)
        ax.set_xlabel("wall time [s]")
        ax.set_ylabel("certified error (componentwise)")
        ax.set_title(f"n = {n}: green = certified, circle = high, square = default")
    fig.tight_layout()
    print(f"\nplot written to {save_figure(fig, path)}")


if __name__ == "__main__":
    sys.exit(main())
