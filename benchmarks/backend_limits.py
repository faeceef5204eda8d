"""Which data magnitudes each QP backend survives: every backend on tiny QPs
whose data hold one entry of growing magnitude, each call in its own
subprocess, so a segmentation fault or a hang is recorded instead of ending
the run.  The results set qpcontact.solvers.backends.common.DATA_LIMIT
(docs/backends.md).

Patterns (x >= 0 in every one):
  P      Hessian diag(m, 0): singular, one huge entry
  Pdiag  Hessian diag(m, 1)
  q      linear term (m, -1)
  G      constraint row (m, 1) x <= 1
  tiny   Hessian diag(1/m, 1)

    .venv/bin/python benchmarks/backend_limits.py [--backends highs,osqp] [--timeout 30]
"""

from __future__ import annotations

import argparse
import subprocess
import sys

_CASE = r'''
import sys, warnings
import numpy as np, qpsolvers
warnings.simplefilter("ignore")
name, mag, pat = sys.argv[1], float(sys.argv[2]), sys.argv[3]
P, q, G, h = np.eye(2), np.array([-1.0, -1.0]), None, None
if pat == "P":
    P, q = np.diag([mag, 0.0]), np.array([-1.0, 1.0])
elif pat == "Pdiag":
    P = np.diag([mag, 1.0])
elif pat == "q":
    q = np.array([mag, -1.0])
elif pat == "G":
    G, h = np.array([[mag, 1.0]]), np.array([1.0])
elif pat == "tiny":
    P = np.diag([1.0 / mag, 1.0])
qpsolvers.solve_problem(qpsolvers.Problem(P, q, G, h, lb=np.zeros(2)), solver=name)
'''
MAGNITUDES = ("1e10", "1e14", "1e15", "1e20", "1e50", "1e100", "1e150", "1e200", "1e300")
PATTERNS = ("P", "Pdiag", "q", "G", "tiny")


def main(argv=None) -> int:
    import qpsolvers

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--backends", default=",".join(qpsolvers.available_solvers))
    ap.add_argument("--timeout", type=float, default=30.0)
    args = ap.parse_args(argv)
    print(f"{'backend':10s} {'pattern':6s} " + " ".join(f"{m:>6s}" for m in MAGNITUDES))
    for name in args.backends.split(","):
        for pat in PATTERNS:
            cells = []
            for mag in MAGNITUDES:
                try:
                    r = subprocess.run([sys.executable, "-c", _CASE, name, mag, pat],
                                       capture_output=True, timeout=args.timeout)
                    cells.append("ok" if r.returncode == 0 else
                                 ("SEGV" if r.returncode < 0 else "exc"))
                except subprocess.TimeoutExpired:
                    cells.append("hang")
            print(f"{name:10s} {pat:6s} " + " ".join(f"{c:>6s}" for c in cells), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
