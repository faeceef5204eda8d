"""A one-storey space frame on six frictional pads: 2 x 1 bays,
8 m x 5 m, 3.5 m high, the columns standing on pads with f = 0.4 (a pad
carries no moment); a spring holds P10 in x, a guide holds P21 in y, and a
frictionless bumper 0.1 mm beside T21 stops it moving in +x.  Dead load D
(10 kN/m on the x beams, 40 kN at T21), a push W at T20 along (1, 1, 0) and
an uplift U at T00; four combinations, each solved on its own.

Units: kN, m.  Prints each combination's contact states, writes the tables
(CSV) and draws D + W + U, in which every contact state occurs: P00 lifts
off, P01 and P20 slip, the bumper closes, the rest stick.

    .venv/bin/python examples/space_frame_on_pads.py              # out/space_frame/
    .venv/bin/python examples/space_frame_on_pads.py --plot docs/figures/space_frame.png
"""

from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.frames.space.space_examples import six_pads  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/space_frame")
    ap.add_argument("--plot", default=None, help="where to draw D+W+U (default: in --out)")
    args = ap.parse_args(argv)
    res = six_pads().solve_combinations(
        {"D": {"D": 1.0}, "D+W": {"D": 1.0, "W": 1.0}, "D+W+U": {"D": 1.0, "W": 1.0, "U": 1.0},
         "D+3W": {"D": 1.0, "W": 3.0}})
    for name, r in res.items():
        states = ", ".join(f"{k}: {s.state}" for k, s in r.supports.items()) or r.message
        print(f"{name:>6}: ok={r.ok}  {states}")
    for path in res.to_csv(args.out):
        print("wrote", path)
    print("wrote", res["D+W+U"].plot(args.plot or os.path.join(args.out, "space_frame.png")))


if __name__ == "__main__":
    main()
