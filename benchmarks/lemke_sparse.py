"""Lemke's two forms side by side: the dense basis inverse (O(n²) a pivot)
against the sparse revised form (SuperLU + product-form updates,
qpcontact.methods.lemke_sparse), on the shapes that reach them:

- membranes over an obstacle: the 5-point Laplacian of a k x k mesh (a 2-D
  mesh's stiffness), loads drawn so that about half the nodes touch;
- the exact 2-D friction LCPs of Siconos's files (when ../shared/data is
  there): z = (r_N, β⁺, β⁻, λ) per contact, nonsymmetric and degenerate.

Printed per problem: pivots and time of each form, and the ratio
sparse / dense of the times measured in the same run.  What it decides:
``SPARSE_FROM`` in qpcontact.solvers.pivoting.lemke (a sparse M from that many
unknowns goes to the sparse form).

    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 .venv/bin/python benchmarks/lemke_sparse.py

Options: --mesh 10,20,30,40,50  --dense-max 2600 (the dense form is skipped
above it: on the 667-contact file's 2668 unknowns it takes 44 000 pivots,
about 9 minutes)  --friction / --no-friction
"""

from __future__ import annotations

import argparse
import importlib
import os
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402

import qpcontact  # noqa: E402
from qpcontact import LCP  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "siconos-fc"
FRICTION = ["FrictionContactProblem00071.dat", "fc2d_granularflowonwall_00667_00000.dat",
            "fc2d_granularflowonwall_02020_00213.dat"]
LEMKE = importlib.import_module("qpcontact.solvers.pivoting.lemke")


def membrane(k: int, seed: int = 0) -> LCP:
    """-Δu >= f, u >= 0 on a k x k mesh: M the 5-point Laplacian (SPD)."""
    T = sp.diags([-np.ones(k - 1), 2 * np.ones(k), -np.ones(k - 1)], [-1, 0, 1])
    M = sp.csc_matrix(sp.kron(sp.identity(k), T) + sp.kron(T, sp.identity(k)))
    q = np.random.default_rng(seed).standard_normal(k * k)
    return LCP(M, q)


def run(lcp: LCP, form: str):
    """One Lemke solve in the given form; (pivots, seconds, certified)."""
    saved = LEMKE.SPARSE_FROM
    LEMKE.SPARSE_FROM = 0 if form == "sparse" else 10 ** 9
    M = lcp.M if form == "sparse" else (lcp.M.toarray() if sp.issparse(lcp.M) else lcp.M)
    try:
        problem = LCP(M, lcp.q)
        t0 = time.perf_counter()
        sol = qpcontact.solve(problem, "lemke")
        return sol.iterations, time.perf_counter() - t0, sol.ok
    finally:
        LEMKE.SPARSE_FROM = saved


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", default="10,20,30,40,50")
    ap.add_argument("--dense-max", type=int, default=2600)
    ap.add_argument("--friction", action=argparse.BooleanOptionalAction, default=True)
    args = ap.parse_args(argv)
    cases = [(f"membrane {k}x{k}", membrane(int(k))) for k in args.mesh.split(",")]
    if args.friction and DATA.is_dir():
        from qpcontact.core.friction_problem import fc2d_lcp
        from qpcontact.io import read_problem

        cases += [(name.split(".")[0], fc2d_lcp(read_problem(DATA / name))) for name in FRICTION]
    elif args.friction:
        print(f"(friction files not found at {DATA}: skipped)")
    run(membrane(4), "dense"), run(membrane(4), "sparse")   # imports, numba kernels
    print(f"{'problem':42} {'n':>6} {'dense pivots':>12} {'dense s':>8} {'sparse pivots':>13} "
          f"{'sparse s':>8} {'sparse/dense':>12}")
    for name, lcp in cases:
        s_piv, s_t, s_ok = run(lcp, "sparse")
        if lcp.n <= args.dense_max:
            d_piv, d_t, d_ok = run(lcp, "dense")
            dense = f"{d_piv:>12} {d_t:>8.2f}{'' if d_ok else '*'}"
            ratio = f"{s_t / d_t:>12.2f}"
        else:
            dense, ratio = f"{'-':>12} {'-':>8}", f"{'-':>12}"
        print(f"{name:42} {lcp.n:>6} {dense} {s_piv:>13} {s_t:>8.2f}{'' if s_ok else '*'} {ratio}",
              flush=True)
    print("* not certified at 'high' (the friction measures judge those answers: "
          "benchmarks/friction.py)")


if __name__ == "__main__":
    main()
