"""Far contacts: how many generated problems each method solves right, and how
many it gets wrong while saying "solved".

The family (qpcontact.testing.far_contact_lcp): n = 21, SPD M with
cond 297, half the contacts closed (forces 0.1..2), the others open (gaps
0.1..2), three of the open ones far away (gaps 5e11).  The solution is planted,
so every answer is judged against it component by component
(qpcontact.testing.planted_ok, rtol 1e-6 of each component's own size) — not
by qpcontact's certificate, which is what is being tested.

Columns: right = ok and equal to the planted solution; silent wrong = ok but
not equal (the failure that must never happen); refused/failed = not ok
(honest); time = mean wall time per solve.

    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 .venv/bin/python benchmarks/far_contact.py

Options: --problems 1000  --methods energy,bpp,lemke,...  --accuracy high
"""

from __future__ import annotations

import argparse
import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import qpcontact  # noqa: E402
from qpcontact.core.errors import QpcontactError  # noqa: E402
from qpcontact.core.progress import ProgressBar  # noqa: E402
from qpcontact.testing import far_contact_lcp, planted_ok  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--problems", type=int, default=1000)
    ap.add_argument("--methods", default=None, help="default: every installed method and 'auto'")
    ap.add_argument("--accuracy", default="high")
    args = ap.parse_args(argv)
    names = args.methods.split(",") if args.methods else ["auto", *(n for n, m in qpcontact.methods().items() if m.solves("lcp"))]
    problems = [far_contact_lcp(seed) for seed in range(args.problems)]
    print(f"{args.problems} far-contact problems (n = 21, cond 297, 3 gaps of 5e11), "
          f"accuracy {args.accuracy!r}")
    silent_total = 0
    print(f"{'method':16s} {'right':>7s} {'silent wrong':>13s} {'not ok':>7s} {'time [ms]':>10s}",
          flush=True)
    for name in names:
        right = silent = not_ok = 0
        t0 = time.perf_counter()
        bar = ProgressBar(len(problems), name, enabled=sys.stdout.isatty(), transient=True)
        try:
            for lcp, z_star, w_star in problems:
                try:
                    sol = qpcontact.solve(lcp, method=name, accuracy=args.accuracy)
                except QpcontactError:
                    not_ok += 1
                    bar.advance()
                    continue
                good = planted_ok(sol.z, sol.w, z_star, w_star)
                if sol.ok:
                    right += good
                    silent += not good
                else:
                    not_ok += 1
                bar.advance()
        finally:
            bar.close()
        ms = 1e3 * (time.perf_counter() - t0) / len(problems)
        silent_total += silent
        print(f"{name:16s} {right:7d} {silent:13d} {not_ok:7d} {ms:10.2f}", flush=True)
    print(f"silent wrong answers, all methods: {silent_total}")
    return 1 if silent_total else 0


if __name__ == "__main__":
    sys.exit(main())
