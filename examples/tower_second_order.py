"""A 20-storey, 3-bay frame on a foundation beam resting on elastic
frictional pads, pushed sideways at every floor (10 kN x p) under its
weight: its load path to first order and on the deformed frame (P-Δ and
P-δ), with the limit of each, and the elastic critical load factor α_cr
under the weight alone.

    python examples/tower_second_order.py [--out docs/figures/frame_tower_second_order.png]

About half a minute on one core (the second-order path is traced a few
times, until the axial forces it is built from are those of its end; each
point drawn on it is a second-order solve at its load).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from formulations.frames.plane.plane_examples import tower  # noqa: E402
from formulations.frames.mechanics.equilibrium_checks import LargeDisplacementWarning  # noqa: E402


def path(ft, node, limit):
    """(p, ux at node) of the trace's answers up to ``limit`` (a
    second-order trace's are solves at p: at the limit itself, the verge of
    tipping, its fixed point need not converge, and such answers are left
    out)."""
    ps = np.unique(np.r_[np.linspace(0.0, limit, 80), ft.breakpoints[ft.breakpoints <= limit],
                         limit * (1.0 - 1e-6), limit])
    answers = [(p, ft.result_at(p)) for p in ps]
    ok = [(p, res.displacements[node][0]) for p, res in answers if res.ok]
    return np.array([p for p, _ in ok]), np.array([u for _, u in ok])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="frame_tower_second_order.png", help="the figure (PNG)")
    args = ap.parse_args()
    warnings.simplefilter("ignore", LargeDisplacementWarning)
    fr, _ = tower()
    top = "N20_0"
    weight = fr.solve(p=0.0, second_order=True)
    crit = fr.critical_load_factor(weight)
    print(f"under its weight: α_cr = {crit['alpha']:.4g} (Eurocode 3 asks for second-order "
          f"analysis below 10); top sway {weight.displacements[top][0] * 1e3:.3g} mm")
    t = time.perf_counter()
    first = fr.trace()
    print(f"first order: ends {first.ended!r}, limit [{first.limit[0]:.8g}, "
          f"{first.limit[1]:.8g}] ({time.perf_counter() - t:.0f} s)")
    t = time.perf_counter()
    second = fr.trace(second_order=True)
    print(f"second order: ends {second.ended!r}, limit {second.limit[0]:.8g} "
          f"({second.second_order['rounds']} rounds, {time.perf_counter() - t:.0f} s); the "
          f"path's axial forces within {second.second_order['path_axial_change']:.1e} of the "
          "members' Euler loads of its end's")
    print(f"  ok: {second.ok}; {second.message[:400]}")
    if not second.ok:
        print(f"  … {second.message[second.message.find('NOT OK'):][:300]}")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure

    fig, ax = plt.subplots(figsize=(7.5, 5.0))
    for ft, lim, style, name in ((first, first.limit[0], "-", "first order"),
                                 (second, second.limit[0], "-", "second order (P-Δ, P-δ)")):
        ps, ux = path(ft, top, lim)
        line, = ax.plot(ux, ps, style, lw=2, label=f"{name}: ends at p = {lim:.4g}")
        ax.plot(ux[-1], ps[-1], "o", color=line.get_color(), ms=7)
        ax.axhline(lim, color=line.get_color(), lw=0.8, ls=":")
    ax.set_xlabel(f"sway of the top ({top}), ux [m]")
    ax.set_ylabel("p (10 p kN at every floor)")
    ax.set_title(f"20-storey tower on pads: load paths to their limits (α_cr = "
                 f"{crit['alpha']:.3g} under the weight)", fontsize=10)
    ax.legend(loc="lower right", fontsize=9)
    ax.grid(alpha=0.3)
    ax.set_xlim(left=0.0)
    ax.set_ylim(bottom=0.0)
    print("figure:", save_figure(fig, args.out))


if __name__ == "__main__":
    main()
