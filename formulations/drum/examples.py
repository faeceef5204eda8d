"""The drum's instances for ``qpcontact compare``, its part of ``qpcontact
demo`` and the ten-log scene of the demo and examples/drum_stack.py."""

from __future__ import annotations

import numpy as np

from qpcontact.core.problems import LCP

from .model import GRAVITY, Drum, Log

__all__ = ["ten_log_scene", "demo", "instances"]


def ten_log_scene(seed: int = 1, shell_stiffness: float | None = None) -> Drum:
    """Ten green-spruce logs (diameters 0.10-0.20 m shuffled, 1.2 m, 5 % damping)
    5-50 mm apart, thrown down at 0.5-2 m/s into the shell (rigid unless
    ``shell_stiffness`` [N/m] is given): the demo's and examples/drum_stack.py's scene."""
    rng = np.random.default_rng(seed)
    diameters = np.linspace(0.10, 0.20, 10)
    rng.shuffle(diameters)
    logs = [Log.from_wood(d, 1.2, damping_ratio=0.05) for d in diameters]
    gaps = rng.uniform(0.005, 0.05, 10)           # m, below each log
    velocities = -rng.uniform(0.5, 2.0, 10)       # m/s, downward
    effects = ("gravity", "damping") + (("shell_elasticity",) if shell_stiffness else ())
    return Drum(logs, gaps, velocities, shell_stiffness=shell_stiffness, effects=effects)


def demo(console) -> int:
    """The drum part of ``qpcontact demo`` (found through the
    ``qpcontact.formulations`` entry point): one log dropped on the shell
    against the analytic peak force, with the energy the time steps lose,
    then ten logs falling into the shell.  Returns the number of checks that
    failed."""
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    log = Log.from_wood(0.15, 1.2)
    h = 0.02
    v = np.sqrt(2 * GRAVITY * h)
    exact = log.mass * GRAVITY + np.sqrt((log.mass * GRAVITY) ** 2 + log.stiffness * log.mass * v * v)
    impact = 0.5 * log.mass * v * v
    table = Table(title="Drum (Kolesnikov 2013): one 0.15 m x 1.2 m spruce log dropped 2 cm on a rigid shell",
                  box=box.SIMPLE_HEAD, title_justify="left", pad_edge=False)
    cols = ("steps per contact period", "tau [µs]", "peak force [kN]", "error", "order",
            "lost [J]")
    for col in cols:
        table.add_column(escape(col), justify="right", no_wrap=True, min_width=len(col))
    errors, losses = [], []
    for per_period in (20, 40, 80):
        drum = Drum([log], [h])
        T = drum.contact_periods()[0]
        res = drum.simulate(T / per_period, int((np.sqrt(2 * h / GRAVITY) + 0.75 * T) / (T / per_period)))
        peak = res.forces[:, 0].max()
        errors.append(abs(peak / exact - 1))
        losses.append(float(res.energy()["numerical"][-1]))
        order = f"{np.log2(errors[-2] / errors[-1]):.2f}" if len(errors) > 1 else ""
        table.add_row(str(per_period), f"{1e6 * T / per_period:.1f}", f"{peak / 1e3:.2f}",
                      f"{errors[-1]:.1%}", order, f"{losses[-1]:.2f}")
    console.print(table)
    _notes(console, [
        f"error: against the analytic peak mg + sqrt((mg)^2 + k m v^2) = {exact / 1e3:.2f} kN; "
        "order: the observed order of convergence.  lost: of the "
        f"{impact:.2f} J the log brings to the impact, the energy the implicit "
        "(backward-difference) time steps dissipate; halving tau cuts it by "
        f"{1 - losses[1] / losses[0]:.0%}, then {1 - losses[2] / losses[1]:.0%}: first order, "
        "like the peak's error."])
    failed = int(not (errors[-1] < errors[0] and np.log2(errors[-2] / errors[-1]) > 0.8))
    failed += int(not losses[2] < losses[1] < losses[0])

    drum = ten_log_scene()
    tau = drum.contact_periods().min() / 40
    res = drum.simulate(tau, int(0.12 / tau))
    s = res.summary()
    e = s.energy_final
    _notes(console, [
        f"Ten logs (0.10-0.20 m) thrown into the shell: 0.12 s in {len(res.t) - 1} steps of "
        f"tau = {1e6 * tau:.1f} µs (shortest contact period / 40), {res.wall_time:.2f} s with "
        "'bpp'.  Peak contact forces [kN], shell/log 0 first: "
        + ", ".join(f"{f / 1e3:.0f}" for f in s.peak_force) + f"; "
        f"{int(s.collisions_per_log.sum())} contact onsets; largest certificate error "
        f"{s.max_certificate_error:.1e}.",
        f"Energy [J]: {s.energy_initial:.1f} at the start = {sum(e.values()):.1f} at the end = "
        f"kinetic {e['kinetic']:.1f} + elastic {e['elastic']:.1f} + potential "
        f"{e['potential']:.1f} + viscous {e['viscous']:.1f} + numerical {e['numerical']:.1f}; "
        "numerical: lost by the time steps, first order in tau as in the table above.  "
        "examples/drum_stack.py plots it."])
    failed += int(s.max_certificate_error > 1e-9)
    return failed


def _notes(console, lines) -> None:
    """Plain text: units in brackets are words, not rich markup."""
    for line in lines:
        console.print(line, markup=False, highlight=False)


def instances(size: str = "small", hardness: str = "easy", seed: int = 0):
    """Step problems of falling stacks for ``qpcontact compare``: stacks of 10,
    100 or 1000 logs (size small/medium/large); "hard" mixes 0.05-0.30 m logs
    on an elastic shell with damping.  Names say what they are:
    ``drum/stack-100-hard/step-30``; the contact forces are z."""
    from qpcontact.cases.instance import Instance

    L = {"small": 10, "medium": 100, "large": 1000}[size]
    rng = np.random.default_rng(seed)
    if hardness == "hard":
        logs = [Log.from_wood(d, 1.2, damping_ratio=0.1) for d in rng.uniform(0.05, 0.30, L)]
        drum = Drum(logs, rng.uniform(0, 0.002, L), -rng.uniform(0, 2.0, L), shell_stiffness=5e8,
                    effects=("gravity", "damping", "shell_elasticity"))
    else:
        logs = [Log.from_wood(d, 1.2) for d in rng.uniform(0.10, 0.20, L)]
        drum = Drum(logs, rng.uniform(0, 0.002, L), -rng.uniform(0, 1.0, L))
    keep = {}
    wanted = (15, 30)
    drum.simulate(drum.contact_periods().min() / 20, max(wanted),
                  on_step=lambda n, lcp, sol: keep.__setitem__(n, lcp) if n in wanted else None)
    tag = f"stack-{L}" + ("-hard" if hardness == "hard" else "")
    return [Instance(f"drum/{tag}/step-{n}", "drum", f"stack-{L}", LCP(keep[n].M, keep[n].q))
            for n in wanted]
