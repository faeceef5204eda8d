"""Ten pulpwood logs falling into a debarking drum's shell
(Kolesnikov's conditional stack).

Logs of unequal diameter (0.10-0.20 m, 1.2 m long, green spruce) start above
the shell with small gaps, thrown downward at 0.5-2 m/s; damping ratio 5 %.
The run prints the summary (peak force per contact and when, collisions per
log, energy balance) and saves two plots: contact forces against time and
the peak force per contact.  SI units throughout.

    .venv/bin/python examples/drum_stack.py            # plots in out/drum/
    .venv/bin/python examples/drum_stack.py --shell-stiffness 2e9 --out out/drum-elastic
"""

from __future__ import annotations

import argparse
import os
import sys


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from formulations.drum import ten_log_scene  # noqa: E402
from qpcontact.plots.figures import save_figure  # noqa: E402


def save_atomic(fig, path):
    print("wrote", save_figure(fig, path))


def plots(result, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(out, exist_ok=True)
    t_ms = 1e3 * result.t
    fig, ax = plt.subplots(figsize=(9, 4.8))
    for k in range(result.forces.shape[1]):
        label = "shell / log 0" if k == 0 else f"log {k - 1} / log {k}"
        ax.plot(t_ms, result.forces[:, k] / 1e3, lw=0.9, label=label)
    ax.set_xlabel("time [ms]")
    ax.set_ylabel("contact force [kN]")
    ax.set_title("Contact forces, ten logs falling into the shell")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    save_atomic(fig, os.path.join(out, "drum_forces.png"))

    s = result.summary()
    fig, ax = plt.subplots(figsize=(8, 4.2))
    names = ["shell/0"] + [f"{k - 1}/{k}" for k in range(1, len(s.peak_force))]
    bars = ax.bar(names, s.peak_force / 1e3, color="tab:brown")
    for b, t in zip(bars, s.peak_time):
        if b.get_height() > 0:
            ax.annotate(f"{1e3 * t:.0f} ms", (b.get_x() + b.get_width() / 2, b.get_height()),
                        ha="center", va="bottom", fontsize=7)
    ax.set_xlabel("contact (shell / log, or lower log / upper log)")
    ax.set_ylabel("peak force [kN]")
    ax.set_title("Peak force per contact (label: when it occurred)")
    ax.grid(True, axis="y", alpha=0.3)
    fig.tight_layout()
    save_atomic(fig, os.path.join(out, "drum_peaks.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=0.25, help="simulated time [s]")
    ap.add_argument("--steps-per-period", type=int, default=40,
                    help="time steps per shortest contact period")
    ap.add_argument("--shell-stiffness", type=float, default=None, help="N/m; rigid if omitted")
    ap.add_argument("--method", default="bpp")
    ap.add_argument("--out", default="out/drum")
    args = ap.parse_args(argv)

    drum = ten_log_scene(shell_stiffness=args.shell_stiffness)
    T = drum.contact_periods().min()
    tau = T / args.steps_per_period
    steps = int(round(args.duration / tau))
    print(f"{drum.n_logs} logs, masses {drum.mass.min():.1f}-{drum.mass.max():.1f} kg; shortest "
          f"contact period {1e3 * T:.3f} ms; tau = {1e6 * tau:.2f} us, {steps} steps")
    result = drum.simulate(tau, steps, method=args.method, progress=True)
    print(f"{steps} steps in {result.wall_time:.2f} s "
          f"({drum.n_contacts * steps / result.wall_time:.3g} contact-steps/s)")
    print(result.summary())
    plots(result, args.out)
    result.save(os.path.join(args.out, "drum_run.npz"))


if __name__ == "__main__":
    main()
