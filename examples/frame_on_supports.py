"""A two-span portal frame on five frictional supports (Osipova, Popov and
Lovtsov's increasing load parameter): gravity on the
beams (case G), then a lateral load (case W) that grows until the working
scheme stops changing; then three design combinations, each solved on its own.

Units: kN, m (E in kN/m², loads in kN and kN/m).  Prints the load levels where
the scheme changes and the support states between them; saves the deformed
shape with the support states and the bending moments at the last state, and
load parameter against the sway of the top-left corner (PNG).

    .venv/bin/python examples/frame_on_supports.py          # plots in out/frame/
"""

from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.frames import Frame  # noqa: E402


def two_span_portal() -> Frame:
    fr = Frame()
    E, A, I = 2.1e8, 5.4e-3, 5.7e-5         # steel HE 200 A: kN/m², m², m⁴
    for name, x, y in (("A", 0, 0), ("B", 6, 0), ("C", 12, 0),
                       ("D", 0, 4), ("E", 6, 4), ("F", 12, 4)):
        fr.add_node(name, x, y)
    for i, j in (("A", "D"), ("B", "E"), ("C", "F")):
        fr.add_member(i, j, E=E, A=A, I=I, name=f"col {i}{j}")
    for i, j in (("D", "E"), ("E", "F")):
        m = fr.add_member(i, j, E=E, A=A, I=I, name=f"beam {i}{j}")
        fr.add_distributed_load(m, wy=-20.0, case="G")             # dead load, kN/m
    for base in ("A", "B", "C"):                                     # column bases on the ground
        fr.add_contact(base, normal=(0.0, 1.0), friction=0.4)
    fr.add_contact("F", normal=(-1.0, 0.0), friction=0.2, gap=0.005)  # wall 5 mm right of F
    fr.add_contact("D", normal=(1.0, 0.0), friction=0.2, gap=0.0)     # wall touching D on the left
    fr.add_load("D", fx=10.0, case="W")                              # wind, kN
    return fr


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--p-max", type=float, default=None, help="stop here (default: until a ray)")
    ap.add_argument("--show", type=float, default=30.0, help="p of the state to plot")
    ap.add_argument("--plot-p-max", type=float, default=40.0, help="p range of the trace plot")
    ap.add_argument("--out", default="out/frame")
    args = ap.parse_args(argv)

    fr = two_span_portal()
    tr = fr.trace(p_max=args.p_max, constant={"G": 1.0}, variable="W")   # G, then p x W
    print(f"trace: {tr.message}")
    print(f"{'interval of p':>24}  supports (A, B, C bases; F right wall; D left wall)")
    for (lo, hi), st in zip(tr.intervals, tr.states):
        states = ", ".join(f"{k}: {v.state}" for k, v in st.supports.items())
        print(f"{lo:10.4g} .. {hi:10.4g}  {states}   (equilibrium {st.equilibrium_residual:.0e}, "
              f"LCP {st.lcp_error:.0e})")
    st = tr.result_at(args.show)
    print(f"at p = {args.show:g} (lateral load {10 * args.show:g} kN), support forces [kN]: " + ", ".join(
        f"{k}: {v.state} N={v.normal:.2f} T={v.tangential:.2f}" for k, v in st.supports.items()))
    print(f"  {st.message}")
    os.makedirs(args.out, exist_ok=True)
    print("wrote", st.plot(os.path.join(args.out, "frame_state.png"),
                           title=f"p = {args.show:g}: deformed shape with support states, bending moments [kN m]"))
    print("wrote", tr.plot(os.path.join(args.out, "frame_trace.png"), node="D", dof="ux",
                           p_max=args.plot_p_max))
    # design combinations, each its own contact problem (never superposed)
    res = fr.solve_combinations({"1.35G": {"G": 1.35}, "1.0G+1.5W": {"G": 1.0, "W": 1.5},
                                 "1.0G+4.5W": {"G": 1.0, "W": 4.5}})
    for name, r in res.items():
        states = ", ".join(f"{k}: {v.state}" for k, v in r.supports.items()) or r.message
        print(f"{name:>10}: ok={r.ok}  {states}")
    for path in res.to_csv(os.path.join(args.out, "combinations")):
        print("wrote", path)


if __name__ == "__main__":
    main()
