"""The exact oracle's cost: pivots and median time of "energy", "bpp" and
"lemke" against the fastest QP backend at "high" and against quantecon's
numba-compiled Lemke, measured side by side in one run.

Problems (the same generators as benchmarks/backends.py): dense SPD
n = 50 ... 2000 and sparse banded SPD (a 1-D contact chain) n = 1e4 ... 1e5,
about half the constraints active.  Printed ratios:

- Lemke / quantecon.optimize.lcp_lemke on the dense problems (target <= 2 at n = 200);
- bpp / one sparse factorization of the final active block, on the sparse
  ones (target <= 3 at n = 1e5): by QDLDL (a general sparse LDL') and by
  LAPACK's banded Cholesky (what bpp itself uses on banded M), and bpp / the
  fastest certified QP backend (target < 1).

    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 .venv/bin/python benchmarks/pivoting.py

Options: --dense 50,200,1000,2000  --sparse 10000,100000  --repeats 3
         --backends piqp,clarabel,osqp  --quick (n = 50, 200 dense; 1e4 sparse)
         --plot out/pivoting.png
quantecon is optional (``pip install -e ".[benchmark]"``); without it that
column is left empty.
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
import scipy.sparse as sp  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import qpcontact  # noqa: E402
from qpcontact.plots.figures import save_figure  # noqa: E402
from backends import banded_spd_lcp, dense_spd_lcp  # noqa: E402
from qpcontact.core.matrices import bandwidth  # noqa: E402


def timed(fn, repeats):
    """Median over ``repeats`` calls after one untimed call: the first call
    pays one-off costs (imports, numba compilation, and qpcontact's cached
    check of M's symmetry and definiteness — one sparse LDL' of M)."""
    fn()
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def quantecon_lemke():
    try:
        from quantecon.optimize import lcp_lemke
    except ImportError:
        return None
    lcp_lemke(np.eye(2), -np.ones(2))  # compile outside the timings
    return lcp_lemke


def run(args):
    rows = []
    qe = quantecon_lemke()
    backends = [b for b in args.backends.split(",") if b in qpcontact.methods()]
    print(f"methods: energy, bpp, lemke; QP backends {backends}; quantecon "
          f"{'installed' if qe else 'NOT installed (pip install -e .[benchmark])'}", flush=True)

    for kind, sizes in (("dense", args.dense), ("sparse", args.sparse)):
        for n in sizes:
            lcp = dense_spd_lcp(n, 0) if kind == "dense" else banded_spd_lcp(n, 0)
            reps = args.repeats if n <= 2000 else max(1, args.repeats // 2)
            row = {"kind": kind, "n": n}
            methods = ("energy", "bpp", "lemke") if kind == "dense" else ("bpp",)
            for m in methods:
                t, sol = timed(lambda: qpcontact.solve(lcp, method=m), reps)
                row[m] = (t, sol.iterations, sol.error, sol.ok)
                print(f"  {kind} n={n} {m}: {t:.4f} s, {sol.iterations} pivots, error {sol.error:.1e}",
                      flush=True)
            best = None
            for b in backends:
                if kind == "sparse" and not qpcontact.methods()[b].accepts_sparse:
                    continue  # a dense-only backend would densify n^2 entries
                t, sol = timed(lambda: qpcontact.solve(lcp, method=b, accuracy="high"), reps)
                print(f"  {kind} n={n} {b}: {t:.4f} s, error {sol.error:.1e}, {sol.status}", flush=True)
                if sol.ok and (best is None or t < best[1]):
                    best = (b, t, sol.error)
            row["qp"] = best
            if kind == "dense" and qe is not None:
                M, q = np.asarray(lcp.M), lcp.q
                t, res = timed(lambda: qe(M, q, max_iter=10**6), reps)
                err = qpcontact.certify(lcp, res.z).error
                row["quantecon"] = (t, res.num_iter, err, bool(res.success))
                print(f"  {kind} n={n} quantecon lcp_lemke: {t:.4f} s, {res.num_iter} pivots, "
                      f"error {err:.1e}", flush=True)
            if kind == "sparse":
                import qdldl
                import scipy.linalg
                F = qpcontact.solve(lcp, method="bpp").z > 0
                B = lcp.M[F][:, F].tocsc()
                U = sp.triu(B, format="csc")
                t, _ = timed(lambda: qdldl.Solver(U, upper=True), max(3, reps))
                row["factor"] = t
                b = bandwidth(U)
                C = U.tocoo()
                ab = np.zeros((b + 1, B.shape[0]))
                ab[b + C.row - C.col, C.col] = C.data
                tb, _ = timed(lambda: scipy.linalg.cholesky_banded(ab, lower=False), max(3, reps))
                row["factor_banded"] = tb
                print(f"  {kind} n={n} one factorization of the final active block "
                      f"({int(F.sum())} rows, bandwidth {b}): QDLDL {t:.4f} s, "
                      f"LAPACK banded {tb:.4f} s", flush=True)
            rows.append(row)
    return rows


def report(rows):
    print()
    print("| problem | n | energy s (piv) | bpp s (iter) | lemke s (piv) | quantecon s (piv) "
          "| lemke/quantecon | fastest QP at high | bpp/QP | bpp/QDLDL factor. | bpp/banded factor. |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        def cell(key):
            v = r.get(key)
            return f"{v[0]:.4f} ({v[1]})" + ("" if v[3] else " FAIL") if v else ""
        lq = (f"{r['lemke'][0] / r['quantecon'][0]:.2f}" if r.get("lemke") and r.get("quantecon")
              else "")
        qp = f"{r['qp'][0]} {r['qp'][1]:.4f}" if r.get("qp") else "none certified"
        bq = f"{r['bpp'][0] / r['qp'][1]:.2f}" if r.get("qp") else ""
        bf = f"{r['bpp'][0] / r['factor']:.2f}" if r.get("factor") else ""
        bb = f"{r['bpp'][0] / r['factor_banded']:.2f}" if r.get("factor_banded") else ""
        print(f"| {r['kind']} SPD | {r['n']} | {cell('energy')} | {cell('bpp')} | {cell('lemke')} "
              f"| {cell('quantecon')} | {lq} | {qp} | {bq} | {bf} | {bb} |")


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    kinds = [k for k in ("dense", "sparse") if any(r["kind"] == k for r in rows)]
    fig, axes = plt.subplots(1, len(kinds), figsize=(6 * len(kinds), 4.5), squeeze=False)
    for ax, kind in zip(axes[0], kinds):
        sel = [r for r in rows if r["kind"] == kind]
        for key, style, label in (("energy", "o-", "energy"), ("bpp", "s-", "bpp"),
                                  ("lemke", "^-", "lemke"),
                                  ("quantecon", "v--", "quantecon lcp_lemke")):
            pts = [(r["n"], r[key][0]) for r in sel if r.get(key) and r[key][0] > 0]
            if pts:
                ax.loglog(*zip(*pts), style, label=label)
        pts = [(r["n"], r["qp"][1]) for r in sel if r.get("qp")]
        if pts:
            ax.loglog(*zip(*pts), "k:", marker="x", label="fastest QP backend at 'high'")
        for key, style, label in (("factor", "c-.", "one QDLDL factorization (final block)"),
                                  ("factor_banded", "m-.", "one banded Cholesky (final block)")):
            pts = [(r["n"], r[key]) for r in sel if r.get(key)]
            if pts:
                ax.loglog(*zip(*pts), style, marker="d", label=label)
        ax.set_xlabel("n")
        ax.set_ylabel("median wall time [s]")
        ax.set_title(f"{kind} SPD LCPs" + (" (banded contact chain)" if kind == "sparse" else ""))
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Pivoting methods vs QP backends, certified answers only (1 BLAS thread)")
    fig.tight_layout()
    print(f"plot written to {save_figure(fig, path)}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dense", default="50,200,500,1000,2000")
    ap.add_argument("--sparse", default="10000,30000,100000")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--backends", default="piqp,clarabel,osqp,daqp")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--plot", default=None)
    args = ap.parse_args(argv)
    if args.quick:
        args.dense, args.sparse = "50,200", "10000"
    args.dense = [int(x) for x in args.dense.split(",") if x]
    args.sparse = [int(x) for x in args.sparse.split(",") if x]
    rows = run(args)
    report(rows)
    if args.plot:
        plot(rows, args.plot)


if __name__ == "__main__":
    main()
