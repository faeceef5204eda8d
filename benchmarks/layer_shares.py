"""The share of each membrane's q that the first restriction cancels
(:func:`qpcontact.solvers.pivoting.multigrid.layer_share`: what turns on
mg-bpp's one-step shifted start for stepped obstacles), for every shape of
``mg_loads.py`` at several grid sizes, with the same share one level
coarser (of R q on the second prolongation) beside it.

    .venv/bin/python benchmarks/layer_shares.py --sizes 100,316,1000
"""

from __future__ import annotations

import argparse

import mg_loads


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", default="100,316")
    ap.add_argument("--shapes", default=",".join(mg_loads.SHAPES + tuple(
        k for k in mg_loads.held_out() if k not in mg_loads.SHAPES)))
    args = ap.parse_args(argv)
    from qpcontact.solvers.pivoting.multigrid import LAYER_MIN, LAYER_SHARE, layer_share

    print(f"fires above {LAYER_SHARE} from {LAYER_MIN} unknowns\n")
    print("| shape | N | share | one level coarser |\n|---|---|---|---|")
    for N in (int(v) for v in args.sizes.split(",")):
        for shape in args.shapes.split(","):
            lcp = mg_loads.build("membrane", shape, N)
            P0, P1 = lcp.structure.hierarchy[:2]
            q1 = P0.T @ lcp.q
            print(f"| {shape} | {N} | {layer_share(lcp.q, P0.T.tocsr()):.4f} | "
                  f"{layer_share(q1, P1.T.tocsr()):.4f} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
