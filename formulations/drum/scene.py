"""The drum's scene files (``qpcontact.scenes``, formulation "drum"): the
schema, the model and run built from a checked scene, the arrays of its
results file, its standard figures and a sweep's columns."""

from __future__ import annotations

import numpy as np

from .model import GRAVITY, GREEN_SPRUCE_DENSITY, SPRUCE_E_TANGENTIAL, Drum, Log

__all__ = ["SCENE"]


def _scene_build(scene):
    """(Drum, run) from a checked scene: logs from wood data, the effects
    named and nothing else (a damping ratio only with "damping", a shell
    stiffness only with "shell_elasticity", g only with "gravity")."""
    eff, data = scene.effect_params, scene.data
    ratio = eff["damping"]["ratio"] if "damping" in eff else 0.0
    logs = [Log.from_wood(lg["diameter"], lg["length"], lg["density"], lg["modulus"],
                          damping_ratio=ratio) for lg in data["logs"]]
    init = data["initial"]
    drum = Drum(logs, init["gaps"], init["velocities"],
                shell_stiffness=eff["shell_elasticity"]["stiffness"]
                if "shell_elasticity" in eff else None,
                effects=scene.effects,
                gravity=eff["gravity"]["g"] if "gravity" in eff else GRAVITY)
    time_ = data["time"]
    tau = time_["tau"] or float(drum.contact_periods().min() / time_["steps_per_period"])
    solver = data["solver"]

    def run(progress: bool = False, on_step=None, resume=None, checkpoint=None,
            checkpoint_seconds: float = 5.0):
        return drum.simulate(tau, time_["steps"], method=solver["method"],
                             accuracy=solver["accuracy"], progress=progress, on_step=on_step,
                             resume=resume, checkpoint=checkpoint,
                             checkpoint_seconds=checkpoint_seconds)
    run.total_steps = time_["steps"]
    return drum, run


def _scene_arrays(result) -> dict:
    """What a drum run's results file holds (SI units), per step."""
    e = result.energy()
    return {"fallbacks": np.array(result.fallbacks), "t": result.t, "forces": result.forces,
            "gaps": result.gaps,
            "displacements": result.displacements, "velocities": result.velocities,
            "certificate_error": result.certificate_errors, "iterations": result.iterations,
            "method": np.array([""] + result.methods, dtype="S"),
            **{f"energy/{k}": v for k, v in e.items()}}


def _scene_plot(h, out) -> list:
    """The drum's standard figures from a results file (an open h5py.File),
    without re-running: forces against time, peak force per contact, energy
    balance."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure
    from qpcontact.plots.style import ink, method_styles

    t_ms = 1e3 * h["t"][()]
    tau = float(h["t"][1] - h["t"][0]) if len(t_ms) > 1 else float("nan")
    N = h["forces"][()]
    names = ["shell/0"] + [f"{k - 1}/{k}" for k in range(1, N.shape[1])]
    styles = method_styles(names)       # a colour and marker per contact, colour-blind safe
    dashes = ("-", "--", ":", "-.")
    paths = []
    fig, ax = plt.subplots(figsize=(9, 4.8))
    for k in range(N.shape[1]):
        colour, marker = styles[names[k]]
        i = int(np.argmax(N[:, k]))     # the marker sits on the contact's peak
        ax.plot(t_ms, N[:, k] / 1e3, lw=0.9, color=ink(colour), mfc=colour, ls=dashes[k // 8 % 4],
                marker=marker, ms=6, markevery=[i] if N[i, k] > 0 else [], label=names[k])
    ax.set(xlabel="time [ms]", ylabel="contact force [kN]",
           title="Contact forces (marker: each contact's peak)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, ncol=2, title="contact (lower/upper)", title_fontsize=7)
    fig.tight_layout()
    paths.append(save_figure(fig, f"{out}/forces.png"))
    fig, ax = plt.subplots(figsize=(8, 4.2))
    k_peak = np.argmax(N, axis=0)
    bars = ax.bar(names, N.max(axis=0) / 1e3, color="#0072B2")
    for b, k in zip(bars, k_peak):
        if b.get_height() > 0:
            ax.annotate(f"{t_ms[k]:.0f} ms", (b.get_x() + b.get_width() / 2, b.get_height()),
                        ha="center", va="bottom", fontsize=7)
    ax.set(xlabel="contact (shell / log, or lower log / upper log)", ylabel="peak force [kN]",
           title="Peak force per contact (label: when)")
    ax.grid(True, axis="y", alpha=0.3)
    if len(names) > 12:                 # ten-log names still fit; more turn on their side
        ax.tick_params(axis="x", labelrotation=90)
    fig.tight_layout()
    paths.append(save_figure(fig, f"{out}/peaks.png"))
    fig, ax = plt.subplots(figsize=(9, 4.8))
    keys = ("kinetic", "elastic", "potential", "viscous", "numerical")
    styles = method_styles(keys)
    for key, ls in zip(keys, ("-", "--", "-.", ":", "-")):
        colour, marker = styles[key]
        ax.plot(t_ms, h[f"energy/{key}"][()], lw=1.2, color=colour, ls=ls, marker=marker,
                markevery=max(1, len(t_ms) // 8), ms=5, label=key)
    ax.set(xlabel="time [ms]", ylabel="energy [J]")
    ax.set_title("Energy balance\nnumerical: lost by the implicit time steps at "
                 f"tau = {1e6 * tau:.3g} µs; halving tau cuts it by 30-50 %", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    paths.append(save_figure(fig, f"{out}/energy.png"))
    return paths


def _scene_summary(result) -> dict:
    """A sweep's columns for one drum run: peak force per contact [N], the
    largest certificate error, the fallbacks."""
    s = result.summary()
    cols = {f"peak_force_{k} [N]": float(v) for k, v in enumerate(s.peak_force)}
    return {**cols, "max_certificate_error": s.max_certificate_error, "fallbacks": s.fallbacks}


def _scene_schema():
    from qpcontact.scenes import Field, SceneSchema, accuracy_problem, method_problem

    return SceneSchema(
        formulation="drum",
        doc="logs stacked above the drum shell, one LCP per time step (Kolesnikov 2013)",
        sections={
            "logs": Field("tables", doc="one [[logs]] table per log, bottom to top", required=True,
                          fields={
                              "diameter": Field("float", "m", "log diameter", required=True,
                                                positive=True),
                              "length": Field("float", "m", "log length", required=True,
                                              positive=True),
                              "density": Field("float", "kg/m³", "wood density",
                                               default=GREEN_SPRUCE_DENSITY, positive=True),
                              "modulus": Field("float", "Pa", "transverse Young's modulus",
                                               default=SPRUCE_E_TANGENTIAL, positive=True)}),
            "initial": {
                "gaps": Field("floats", "m", "gap below each log (0: shell to log 0)",
                              required=True),
                "velocities": Field("floats", "m/s", "log velocities, upward positive"),
            },
            "time": {
                "steps": Field("int", "", "number of time steps", required=True, positive=True),
                "tau": Field("float", "s", "step size (default: the shortest contact period / "
                             "steps_per_period)", positive=True),
                "steps_per_period": Field("float", "", "steps per shortest contact period",
                                          default=40.0, positive=True),
            },
            "solver": {
                "method": Field("str", "", "LCP method per step", default="bpp",
                                check=lambda name: method_problem(name, ("lcp",))),
                "accuracy": Field("str", "", "low, default or high", default="high",
                                  check=accuracy_problem),
            },
        },
        effects={
            "gravity": {"g": Field("float", "m/s²", "gravitational acceleration",
                                   default=GRAVITY, positive=True)},
            "damping": {"ratio": Field("float", "-", "damping ratio ζ of each log's half "
                                       "elements (λ = 2ζ√(s m))", required=True)},
            "shell_elasticity": {"stiffness": Field("float", "N/m", "shell stiffness at the "
                                                    "contact", required=True, positive=True)},
        },
        build=_scene_build,
        arrays=_scene_arrays,
        plot=_scene_plot,
        summary=_scene_summary,
    )


#: The drum's scene-file schema (entry point ``qpcontact.scenes``: ``drum``).
SCENE = _scene_schema()
