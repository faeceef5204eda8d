"""The rod's scene files (``qpcontact.scenes``, formulation "rod").

A planar cantilever's large motion (cantilever_dynamics) in SI units: length
L [m], bending stiffness EI [N·m²], mass per length ρA [kg/m].  The scales:
positions × L, forces × EI/L², distributed loads × EI/L³, time × T₀ =
L²√(ρA/EI).
"""

from __future__ import annotations

import numpy as np

from .dynamics import PARK, RodMotion, cantilever_dynamics

__all__ = ["SCENE", "RodRun"]


def _pulse(value, until, scale, T0):
    """A load [N] acting while t < until [s], as a function of the
    nondimensional time, in units of ``scale``."""
    value = np.asarray(value, float) / scale
    zero = 0.0 * value
    if until is None:
        return lambda tau: value
    return lambda tau: value if tau * T0 < until else zero


def _rod_build(scene):
    from qpcontact.core.errors import SolverFailedError

    d, eff = scene.data, scene.effect_params
    rod, init, time_ = d["rod"], d["initial"], d["time"]
    if time_["order"] not in PARK:
        scene.fail(f"order must be 1 (BDF1), 2 (BDF2) or 3 (Park); got {time_['order']}",
                   ("time",), "order")
    if rod["nodes"] < 5:
        scene.fail(f"nodes must be at least 5; got {rod['nodes']}", ("rod",), "nodes")
    L, EI, rhoA = rod["length"], rod["EI"], rod["mass_per_length"]
    T0 = L * L * np.sqrt(rhoA / EI)
    force = EI / L ** 2
    steps = time_["steps"]
    dead = eff.get("dead_load")
    fol = eff.get("follower_load")
    tip = None if dead is None else _pulse((dead["fx"], dead["fy"]), dead["until"], force, T0)
    follower = None if fol is None else _pulse(fol["force"], fol["until"], force, T0)
    g = eff["gravity"]["g"] if "gravity" in eff else 0.0
    distributed = (0.0, -rhoA * g * L ** 3 / EI)
    beta = EI / (eff["extensibility"]["EA"] * L * L) if "extensibility" in eff else 0.0
    # what the step's BVP is built from: only the named effects' loads
    model = {"L": L, "EI": EI, "rhoA": rhoA, "T0": T0, "g": g, "effects": scene.effects,
             "distributed": distributed, "dead_load": tip, "follower_load": follower,
             "extensibility": beta}

    def run(progress: bool = False, resume=None, checkpoint=None, checkpoint_seconds=5.0):
        from qpcontact.core.progress import ProgressBar

        if resume is not None:
            scene.fail("--resume is not supported for rod scenes (the march's state is its "
                       "multistep history); run it afresh", ("time",))
        bar = ProgressBar(steps, "rod steps", progress, transient=True, unit="steps")
        motion = cantilever_dynamics(init["preload"] / force, steps * time_["h"] / T0,
                                     time_["h"] / T0, tip_load=tip, follower=follower,
                                     distributed=distributed, extensibility=beta,
                                     nodes=rod["nodes"],
                                     order=time_["order"],
                                     on_step=lambda k, n, Y: bar.update(k, f"{k} of {n}"))
        bar.close()
        if not motion.ok:
            raise SolverFailedError(f"the rod's march stopped: {motion.message}; the states "
                                    f"up to t = {motion.t[-1] * T0:.4g} s were solved")
        result = RodRun(model, motion)
        if checkpoint is not None:
            checkpoint(result)
        return result
    run.total_steps = steps
    return model, run


class RodRun:
    """A rod scene's motion in SI units: times ``t`` [s], the centreline
    ``x``, ``y`` [m] and tangent angle ``theta`` [rad] per step (rows) and
    node, the root moment ``root_moment`` [N·m], the Newton steps per step,
    and the energy [J]: bending ½∫EI κ² dS, kinetic ½∫ρA|ṙ|² dS with ṙ by
    backward differences of the positions, gravity potential ∫ρA g y dS
    (zero without gravity); the tip loads' work is not in it."""

    def __init__(self, model, motion: RodMotion):
        L, EI = model["L"], model["EI"]
        Y = np.array(motion.y)
        self.model, self.motion = model, motion
        self.t = motion.t * model["T0"]
        self.s = motion.mesh * L
        self.theta, self.x, self.y = Y[:, 0], Y[:, 2] * L, Y[:, 3] * L
        kappa = Y[:, 1] / L
        self.root_moment = EI * kappa[:, 0]
        self.newton = np.concatenate([[0], motion.newton])
        w = np.full_like(self.s, self.s[1] - self.s[0])
        w[[0, -1]] *= 0.5                                   # the trapezoid rule's weights
        self.bending = 0.5 * EI * (kappa ** 2) @ w
        vx, vy = np.zeros_like(self.x), np.zeros_like(self.y)
        dt = np.diff(self.t)[:, None]
        vx[1:], vy[1:] = np.diff(self.x, axis=0) / dt, np.diff(self.y, axis=0) / dt
        self.kinetic = 0.5 * model["rhoA"] * (vx ** 2 + vy ** 2) @ w
        self.potential = model["rhoA"] * model["g"] * self.y @ w


def _rod_arrays(result) -> dict:
    return {"t": result.t, "s": result.s, "x": result.x, "y": result.y, "theta": result.theta,
            "tip": np.column_stack([result.x[:, -1], result.y[:, -1]]),
            "root_moment": result.root_moment, "newton_steps": result.newton,
            "energy/bending": result.bending, "energy/kinetic": result.kinetic,
            "energy/potential": result.potential}


def _rod_plot(h, out) -> list:
    """The tip's path against time, snapshots of the centreline, the root
    moment and the energy — from the file."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure

    t = h["t"][()]
    x, y, tip = h["x"][()], h["y"][()], h["tip"][()]
    fig, ax = plt.subplots(2, 2, figsize=(10, 7))
    ax[0, 0].plot(t, tip[:, 0], label="tip x")
    ax[0, 0].plot(t, tip[:, 1], label="tip y")
    ax[0, 0].set_ylabel("tip position [m]")
    ax[0, 0].legend(fontsize=8)
    for k in np.linspace(0, len(t) - 1, 8).astype(int):
        ax[0, 1].plot(x[k], y[k], lw=1, label=f"t = {t[k]:.3g} s")
    ax[0, 1].set_aspect("equal")
    ax[0, 1].set_xlabel("x [m]")
    ax[0, 1].set_ylabel("y [m]")
    ax[0, 1].legend(fontsize=6)
    ax[1, 0].plot(t, h["root_moment"][()])
    ax[1, 0].set_ylabel("root moment [N·m]")
    ax[1, 0].set_xlabel("t [s]")
    Eb, Ek, Ep = (h[f"energy/{k}"][()] for k in ("bending", "kinetic", "potential"))
    for e, lab in ((Eb, "bending"), (Ek, "kinetic (backward differences)"),
                   (Ep, "gravity potential"), (Eb + Ek + Ep, "sum")):
        ax[1, 1].plot(t, e, label=lab)
    ax[1, 1].set_ylabel("energy [J]")
    ax[1, 1].set_xlabel("t [s]")
    ax[1, 1].legend(fontsize=8)
    for a in ax.flat:
        a.grid(True, alpha=0.3)
    fig.tight_layout()
    return [save_figure(fig, f"{out}/rod.png")]


def _rod_schema():
    from qpcontact.scenes import Field, SceneSchema

    until = Field("float", "s", "the load acts while t < until (default: always)")
    return SceneSchema(
        formulation="rod",
        doc="a planar cantilever's large motion (Pustovoy et al. 2014): one BVP per time step",
        sections={
            "rod": {
                "length": Field("float", "m", "length L", required=True, positive=True),
                "EI": Field("float", "N·m²", "bending stiffness", required=True, positive=True),
                "mass_per_length": Field("float", "kg/m", "ρA", required=True, positive=True),
                "nodes": Field("int", "", "mesh nodes along the rod", default=41, positive=True),
            },
            "initial": {
                "preload": Field("float", "N", "transverse dead tip load (downward) of the "
                                 "static state the rod is released from", default=0.0),
            },
            "time": {
                "h": Field("float", "s", "step size", required=True, positive=True),
                "steps": Field("int", "", "number of steps", required=True, positive=True),
                "order": Field("int", "", "1 (BDF1), 2 (BDF2) or 3 (Park)", default=3,
                               positive=True),
            },
        },
        effects={
            "gravity": {"g": Field("float", "m/s²", "gravitational acceleration (−y)",
                                   default=9.81, positive=True)},
            "dead_load": {"fx": Field("float", "N", "tip force x (fixed direction)", default=0.0),
                          "fy": Field("float", "N", "tip force y (fixed direction)", default=0.0),
                          "until": until},
            "extensibility": {"EA": Field("float", "N", "axial stiffness (inextensible "
                                          "without the effect)", required=True, positive=True)},
            "follower_load": {"force": Field("float", "N", "tip force perpendicular to the "
                                             "tip's tangent (downward when straight)",
                                             required=True),
                              "until": until},
        },
        build=_rod_build, arrays=_rod_arrays, plot=_rod_plot,
        summary=lambda r: {"max_tip_deflection [m]": float(-r.y[:, -1].min()),
                           "max_root_moment [N·m]": float(np.abs(r.root_moment).max())})


#: The rod's scene-file schema (entry point ``qpcontact.scenes``: ``rod``).
SCENE = _rod_schema()
