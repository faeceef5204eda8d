r"""The 2-D drum's scene files (``qpcontact.scenes``, formulation "drum2d").

SI units, except the drum's speed in rev/s (Ω = 2π · speed [rad/s]) as the
engineer gives it.  A scene is turned into the Drum2D model of this package:

- the shell: ``[drum] diameter`` D [m], R = D/2; ``[lifters] count`` bars at
  polar angles α_k = 2π k/count (k = 0 on the +x side, counter-clockwise) at
  t = 0, of radial ``height`` h [m] and ``thickness`` 2b [m];
- the fill: n logs of ``length`` ℓ [m] and ``density`` ρ [kg/m³], diameters
  drawn uniformly in [d_min, d_max] with ``seed``, placed at rest on a
  hexagonal lattice from the bottom up (geometry.hex_fill), lattice sites that
  a lifter's capsule would cut left out, or with ``packing = "deposit"``
  dropped one by one to the lowest place they reach (packing.deposit_fill:
  about 0.8 of the bed covered against the lattice's 0.907 E[d²]/d_max²,
  so 120 logs of 0.12–0.28 m fit a 3.5 m drum).  Either ``count`` = n, or
  ``fill_fraction`` f of the drum's cross-section covered by the discs:
  n = round(f π R² / (π E[d²]/4)), E[d²] = d̄² + (d_max − d_min)²/12;
- effects: gravity always (``[effect.gravity] g`` only when named); ``friction``
  (μ per contact kind), ``damping`` (restitution e), ``rotation`` (speed
  [rev/s]), ``log_elasticity`` (the stack model's springs: ``modulus`` E [Pa]
  across the grain, half stiffness 2 E ℓ), ``shell_elasticity`` (``stiffness``
  k_s [N/m]); without ``damping`` impacts are elastic (e = 1), without
  ``rotation`` the shell is still, without the elasticities contacts are rigid;
- solver: ``method`` (per step, or the fallback of the warm start),
  ``accuracy``, ``warm_start`` (a friction method started from the last
  step's impulses, "none" for none; used only with friction);
- output: ``contacts_every`` k keeps the active contacts of every k-th step
  (force chains in snapshots and animations; 0 none) — the force statistics
  (peaks, histograms, sliding work) cover every step whatever k;
  ``frame_interval`` [s] the simulated time between the animation's frames
  (at least k h: the frames are kept steps; default at most 40 frames);
- time: ``step`` h [s] and ``duration`` [s] or ``revolutions`` (with
  ``rotation``): steps = round(duration / h), duration = revolutions / speed.

The run is Drum2D.simulate; the results file holds the states, the per-step
certificates and energies, the force statistics, the kept contacts' forces
(impulse / h [N]), the drum's geometry and the logs' data, so that ``plot``
draws from the file alone, and what ``--resume`` continues from (the last
step's impulses for the warm start: a resumed run equals an uninterrupted
one).  A checkpoint rewrites the whole file, so the run writes one at most
every ten times the last write took (at least ``--checkpoint-seconds``).
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from .geometry import GRAVITY, SPRUCE_DENSITY, Discs, Shell, hex_fill
from .laws import SPRUCE_E_TANGENTIAL
from .outputs import run_summary
from .packing import deposit_fill
from .records import FORCE_BINS
from .stepper import WARM_METHODS, Drum2D

__all__ = ["SCENE", "Drum2DRun", "scene_model", "MAX_SPEED", "MAX_STEPS"]

#: the fastest drum a scene may turn [rev/s]: debarking drums turn at a
#: fraction of a revolution per second, and above sqrt(g/R)/2π (0.5 rev/s for
#: a 2 m drum) the logs are pinned to the shell
MAX_SPEED = 10.0
SPEED_WHY = ("600 rpm; a debarking drum turns at a fraction of a rev/s, and above "
             "sqrt(g/R)/2π the logs stay pinned to the shell")
#: the most steps a scene may ask for (duration / step)
MAX_STEPS = 10 ** 8
#: how the logs are placed at the start (module docstring)
PACKINGS = ("lattice", "deposit")
#: the most frames an animation with a scene's frame_interval draws
MAX_FRAMES = 2000


class Drum2DRun:
    """A scene's run: the ``model`` (Drum2D), the step ``h`` [s] and the
    ``result`` (Drum2DResult)."""

    def __init__(self, model: Drum2D, h: float, result, frame_interval=None):
        self.model, self.h, self.result = model, h, result
        self.t = result.t
        self.frame_interval = frame_interval

    def summary(self):
        """The end-of-run figures (outputs.RunSummary: certificates, peaks,
        drive power and torque per metre, energy per tonne, sliding work per
        log and per m² of log surface), printed by ``qpcontact simulate``."""
        return run_summary(self.result, self.model.discs, self.model.omega)


def _lifter_clear(points, dmax, shell: Shell):
    """Lattice sites whose disc (diameter up to dmax) stays off every lifter capsule."""
    if not shell.lifter_angles.size:
        return np.ones(len(points), bool)
    inner, outer = shell.lifter_segments(0.0, 0.0)
    ok = np.ones(len(points), bool)
    for a, b in zip(inner, outer):
        ab = b - a
        s = np.clip((points - a) @ ab / (ab @ ab), 0.0, 1.0)
        dist = np.hypot(*(points - (a + s[:, None] * ab)).T)
        ok &= dist > 0.5 * dmax + shell.lifter_half_width
    return ok


def _fill(scene, shell: Shell):
    """Centres (n, 2) and diameters (n,) of the fill (module docstring)."""
    logs = scene.data["logs"]
    dmin, dmax = logs["diameter_min"], logs["diameter_max"]
    if dmax < dmin:
        scene.fail(f"must be >= diameter_min = {dmin} m; got {dmax}", ("logs",), "diameter_max")
    if (logs["count"] is None) == (logs["fill_fraction"] is None):
        scene.fail("give exactly one of count (the number of logs) or fill_fraction (of the "
                   "drum's cross-section)", ("logs",), "count")
    if logs["count"] is not None:
        n = logs["count"]
    else:
        f = logs["fill_fraction"]
        if not 0 < f < 0.9:
            scene.fail(f"must be in (0, 0.9); got {f}", ("logs",), "fill_fraction")
        mean = 0.5 * (dmin + dmax)
        n = max(1, int(round(4 * f * shell.radius ** 2 / (mean ** 2 + (dmax - dmin) ** 2 / 12))))
    mean, spread = 0.5 * (dmin + dmax), (dmax - dmin) / (dmax + dmin)
    if logs["packing"] not in PACKINGS:
        scene.fail(f"must be one of {', '.join(PACKINGS)}; got {logs['packing']!r}", ("logs",),
                   "packing")
    if logs["packing"] == "deposit":
        # the diameters drawn as hex_fill draws them
        d = mean * (1.0 + spread * np.random.default_rng(logs["seed"]).uniform(-1.0, 1.0, n))
        inner, outer = shell.lifter_segments(0.0, 0.0)
        try:
            return deposit_fill(shell.radius, d, clearance=logs["clearance"],
                                lifters=list(zip(inner, outer)),
                                half_width=shell.lifter_half_width), d
        except InvalidProblemError as exc:
            scene.fail(str(exc), ("logs",), "count" if logs["count"] is not None
                       else "fill_fraction")
    extra = 0
    while True:   # more sites than logs where lifters cut some out
        try:
            pts, d = hex_fill(shell.radius, n + extra, mean, spread=spread, seed=logs["seed"],
                              clearance=logs["clearance"])
        except InvalidProblemError as exc:
            scene.fail(str(exc) + (" once the sites the lifters cut are left out"
                                   if extra else "") + "; packing = \"deposit\" packs "
                       "mixed diameters denser", ("logs",), "count")
        keep = _lifter_clear(pts, dmax, shell)
        if keep.sum() >= n:
            return pts[keep][:n], d[keep][:n]
        extra += n - int(keep.sum())


def scene_model(scene):
    """(Drum2D, h [s], steps) from a checked scene (module docstring)."""
    d, eff = scene.data, scene.effect_params
    R = 0.5 * d["drum"]["diameter"]
    lift = d["lifters"]
    count = lift["count"]
    if count < 0:
        scene.fail(f"must be >= 0; got {count}", ("lifters",), "count")
    if count:
        for key in ("height", "thickness"):
            if lift[key] is None:
                scene.fail(f"missing: {count} lifters need a {key} [m]", ("lifters",), key)
        if lift["height"] >= R:
            scene.fail(f"must be < the drum's radius {R} m; got {lift['height']}",
                       ("lifters",), "height")
    speed = eff["rotation"]["speed"] if "rotation" in eff else 0.0
    try:
        shell = Shell(R, 2 * np.pi * speed, 2 * np.pi * np.arange(count) / max(count, 1),
                      lift["height"] or 0.0, 0.5 * (lift["thickness"] or 0.0))
    except InvalidProblemError as exc:
        scene.fail(str(exc), ("lifters",))
    pos, diam = _fill(scene, shell)
    logs = d["logs"]
    discs = Discs(diam, pos, length=logs["length"], density=logs["density"])
    fr = eff.get("friction", {})
    for key, mu in fr.items():
        if mu < 0:
            scene.fail(f"must be >= 0; got {mu}", ("effect", "friction"), key)
    if "damping" in eff and not 0 <= eff["damping"]["restitution"] <= 1:
        scene.fail(f"must be in [0, 1]; got {eff['damping']['restitution']}",
                   ("effect", "damping"), "restitution")
    model = Drum2D(discs, shell, scene.effects, mu_disc=fr.get("mu_disc", 0.0),
                   mu_shell=fr.get("mu_shell", 0.0), mu_lifter=fr.get("mu_lifter", 0.0),
                   restitution=eff["damping"]["restitution"] if "damping" in eff else 0.0,
                   gravity=eff["gravity"]["g"] if "gravity" in eff else GRAVITY,
                   modulus=eff.get("log_elasticity", {}).get("modulus", SPRUCE_E_TANGENTIAL),
                   shell_stiffness=eff.get("shell_elasticity", {}).get("stiffness"))
    t = d["time"]
    if (t["duration"] is None) == (t["revolutions"] is None):
        scene.fail("give exactly one of duration [s] or revolutions", ("time",), "duration")
    if t["revolutions"] is not None:
        if "rotation" not in eff:
            scene.fail("revolutions needs the effect 'rotation' (a still drum does not turn); "
                       "give duration [s] instead", ("time",), "revolutions")
        duration = t["revolutions"] / speed
    else:
        duration = t["duration"]
    steps = duration / t["step"]
    if not steps <= MAX_STEPS:
        scene.fail(f"the duration {duration:.4g} s in steps of {t['step']:g} s makes {steps:.3g} "
                   f"steps, more than {MAX_STEPS:.0e}; give a shorter duration or a longer step",
                   ("time",), "step")
    steps = int(round(steps))
    if steps < 1:
        scene.fail(f"the duration {duration:.4g} s is shorter than one step {t['step']} s",
                   ("time",), "step")
    return model, t["step"], steps


def _scene_build(scene):
    from qpcontact.scenes import method_problem

    model, h, steps = scene_model(scene)
    solver, every = scene.data["solver"], scene.data["output"]["contacts_every"]
    if every < 0:
        scene.fail(f"must be >= 0 (0: keep no contacts); got {every}", ("output",),
                   "contacts_every")
    frames = scene.data["output"]["frame_interval"]
    if frames is not None and every == 0:
        scene.fail("the animation's frames are the steps whose contacts are kept: set "
                   "contacts_every >= 1 for frames", ("output",), "frame_interval")
    if frames is not None and frames < every * h * (1 - 1e-9):
        scene.fail(f"must be at least contacts_every × step = {every} × {h:g} s = "
                   f"{every * h:.6g} s (the frames are the kept steps); got {frames:g} s: "
                   "lengthen it or lower contacts_every", ("output",), "frame_interval")
    if frames is not None and frames > h * steps:
        scene.fail(f"must not exceed the run's duration {h * steps:.6g} s; got {frames:g} s",
                   ("output",), "frame_interval")
    warm = None if solver["warm_start"] == "none" else solver["warm_start"]
    if warm is not None and warm not in WARM_METHODS:
        scene.fail(f"must be one of {', '.join(WARM_METHODS)} or none; got {warm!r}",
                   ("solver",), "warm_start")
    if "friction" not in model.effects:
        warm = None
    kinds = ("friction-2d",) if "friction" in model.effects else ("lcp",)
    wrong = method_problem(solver["method"], kinds)
    if wrong:
        scene.fail(wrong + ("" if "friction" in model.effects else
                            " (without the effect 'friction' each step is an LCP)"),
                   ("solver",), "method")

    def run(progress: bool = False, resume=None, checkpoint=None, checkpoint_seconds=5.0,
            on_step=None):
        wrote = None if checkpoint is None else _Spaced(checkpoint, model, h, steps, frames)
        result = model.simulate(h, steps, method=solver["method"], accuracy=solver["accuracy"],
                                warm_start=warm, keep_contacts=every, progress=progress,
                                on_step=on_step, resume=resume, checkpoint_seconds=
                                checkpoint_seconds, checkpoint=wrote)
        return Drum2DRun(model, h, result, frames)
    run.total_steps = steps
    return model, run


class _Spaced:
    """The CLI's checkpoint, called at most every ten times its last write
    took (a big run's file takes seconds to write), always for the end."""

    def __init__(self, checkpoint, model, h, steps, frames=None):
        import time

        self.checkpoint, self.model, self.h, self.steps = checkpoint, model, h, steps
        self.frames = frames
        self.clock, self.next = time.perf_counter, 0.0

    def __call__(self, result):
        now = self.clock()
        if len(result.t) - 1 < self.steps and now < self.next:
            return
        self.checkpoint(Drum2DRun(self.model, self.h, result, self.frames))
        self.next = self.clock() + 10.0 * (self.clock() - now)


def _scene_arrays(run: Drum2DRun) -> dict:
    """The results file (SI): states per time, certificates, energies and
    force statistics per step (records.py), the kept contacts (one row each,
    ``contacts/step`` their step), the geometry and the logs' data as
    scalars, the warm start's last impulses (``warm/``)."""
    r, m, h = run.result, run.model, run.h
    rows = [(s, c) for s, c in enumerate(r.contacts) if c is not None]
    cat = (lambda key: np.concatenate([c[key] for _, c in rows]) if rows else np.zeros(0))
    sh = m.shell
    return {"t": r.t, "positions": r.positions, "velocities": r.velocities, "spins": r.spins,
            "diameters": m.discs.diameters, "masses": m.discs.masses,
            "certificate_error": r.certificate_error, "certified": r.certified.astype(np.int8),
            "method": np.array(r.method, dtype="S"), "n_contacts": r.n_contacts,
            "n_active": r.n_active, "solve_seconds": r.solve_seconds,
            "pairs_checked": r.pairs_checked,
            "energy/kinetic": r.kinetic, "energy/potential": r.potential,
            "energy/drive": r.drive, "energy/friction_loss": r.friction_loss,
            "energy/impact_loss": r.impact_loss, "energy/remainder": r.remainder,
            "energy/scheme": r.scheme,
            "contacts/step": (np.concatenate([np.full(c["i"].size, s) for s, c in rows])
                              if rows else np.zeros(0, np.int64)),
            "contacts/i": cat("i"), "contacts/j": cat("j"), "contacts/kind": cat("kind"),
            "contacts/force_n": cat("r_n") / h, "contacts/force_t": cat("r_t") / h,
            "contacts/slip": cat("slip"), "contacts/gap": cat("gap"),
            "contacts/normal": (np.concatenate([c["normal"] for _, c in rows]) if rows
                                else np.zeros((0, 2))),
            "energy/elastic": r.elastic, "fallback": r.fallback.astype(np.int8),
            "force_peak": r.force_peak, "force_counts": r.force_counts,
            "force_bins": FORCE_BINS, "sliding_work": r.sliding_work,
            "warm/keys": (r.last_contacts or {}).get("keys", np.zeros(0, np.int64)),
            "warm/r": (r.last_contacts or {}).get("r", np.zeros((0, 2))),
            "logs/length": np.float64(m.discs.length), "logs/density": np.float64(m.discs.density),
            "logs/modulus": np.float64(m.modulus), "drum/gravity": np.float64(m.gravity),
            "drum/restitution": np.float64(m.restitution),
            "drum/shell_stiffness": np.float64(m.shell_stiffness or 0.0),
            "drum/radius": np.float64(sh.radius), "drum/omega": np.float64(m.omega),
            "drum/lifter_angles": sh.lifter_angles, "drum/lifter_height":
            np.float64(sh.lifter_height), "drum/lifter_half_width":
            np.float64(sh.lifter_half_width), "drum/step": np.float64(h),
            "drum/max_penetration": np.float64(r.max_penetration),
            "output/frame_interval": np.float64(run.frame_interval or 0.0)}


def _scene_plot(h, out) -> list:
    """The snapshot and the energy balance; with the force statistics (issue
    37) the force histograms and peaks per revolution beside the stack
    model's estimate (computed once for both) and the sliding work per
    log; with two or more kept steps an animation (PNGs in ``animation/``
    and ``animation.gif`` where Pillow is installed): a frame every
    ``[output] frame_interval`` seconds (at most MAX_FRAMES), else at most 40
    frames over the run."""
    import warnings

    from qpcontact.plots.figures import save_figure

    from .figures import (energy_figure, force_histogram_figure, force_peak_figure,
                          sliding_work_figure, snapshot_figure)

    paths = [save_figure(snapshot_figure(h), f"{out}/snapshot.png"),
             save_figure(energy_figure(h), f"{out}/energy.png")]
    if "force_counts" in h and "logs/length" in h:
        from .stack import stack_estimate_for_run

        est = stack_estimate_for_run(h)
        paths += [save_figure(force_histogram_figure(h, est), f"{out}/force_histograms.png"),
                  save_figure(force_peak_figure(h, est), f"{out}/force_peaks.png"),
                  save_figure(sliding_work_figure(h), f"{out}/sliding_work.png")]
    if np.unique(h["contacts/step"][()]).size >= 2:
        from .animation import write_animation

        every = float(h["output/frame_interval"][()]) if "output/frame_interval" in h else 0.0
        anim = write_animation(h, f"{out}/animation", max_frames=MAX_FRAMES if every else 40,
                               interval=every or None)
        paths += [anim.movie] if anim.movie else []
        paths.append(f"{out}/animation/ ({len(anim.frames)} PNG frames)")
        if anim.message:
            warnings.warn(anim.message, stacklevel=2)
    return paths


def _scene_summary(run: Drum2DRun) -> dict:
    """A sweep's columns: outputs.RunSummary's (certificates, peaks, drive
    power and torque per metre, energy per tonne and sliding work per
    revolution, per second without rotation) and the energy totals."""
    return {**run.summary().as_dict(),
            **{f"{k} [J]": v for k, v in run.result.energy_summary().items()}}


def _scene_schema():
    from qpcontact.scenes import Field, SceneSchema, accuracy_problem

    pos = dict(positive=True)
    return SceneSchema(
        formulation="drum2d",
        doc="logs as discs tumbling in a rotating drum with lifters, one certified contact "
            "problem per step",
        sections={
            "drum": {"diameter": Field("float", "m", "the shell's inner diameter", required=True,
                                       **pos)},
            "lifters": {
                "count": Field("int", "", "lifter bars, evenly spaced", default=0),
                "height": Field("float", "m", "radial height of each bar", **pos),
                "thickness": Field("float", "m", "thickness of each bar (a capsule)", **pos),
            },
            "logs": {
                "count": Field("int", "", "number of logs (or fill_fraction)", **pos),
                "fill_fraction": Field("float", "-", "fraction of the cross-section the logs "
                                       "cover (or count)", **pos),
                "diameter_min": Field("float", "m", "smallest log diameter", required=True,
                                      **pos),
                "diameter_max": Field("float", "m", "largest log diameter", required=True,
                                      **pos),
                "seed": Field("int", "", "random seed of the diameters", default=0, low=0),
                "clearance": Field("float", "m", "extra spacing of the lattice (the least "
                                   "gap of a deposit)", default=0.0, low=0.0),
                "packing": Field("str", "", "lattice (hexagonal, the pitch of the largest "
                                 "diameter) or deposit (dropped one by one, denser)",
                                 default="lattice"),
                "length": Field("float", "m", "log length (along the drum axis)", required=True,
                                **pos),
                "density": Field("float", "kg/m³", "wood density", default=SPRUCE_DENSITY,
                                 **pos),
            },
            "time": {
                "step": Field("float", "s", "time step h", required=True, **pos),
                "duration": Field("float", "s", "simulated time (or revolutions)", **pos),
                "revolutions": Field("float", "", "simulated revolutions of the drum (needs "
                                     "rotation)", **pos),
            },
            "solver": {
                "method": Field("str", "", "contact solver per step (with friction: where the "
                                "warm start is not certified)", default="auto"),
                "accuracy": Field("str", "", "low, default or high", default="high",
                                  check=accuracy_problem),
                "warm_start": Field("str", "", "friction method started from the last step's "
                                    "impulses, or none", default="nsgs-newton"),
            },
            "output": {
                "contacts_every": Field("int", "", "keep the contacts of every k-th step (0: "
                                        "none; the force statistics cover every step)",
                                        default=1),
                "frame_interval": Field("float", "s", "simulated time between the "
                                        "animation's frames (default: at most 40 frames "
                                        "over the run)", **pos),
            },
        },
        effects={
            "gravity": {"g": Field("float", "m/s²", "gravitational acceleration (always on)",
                                   default=GRAVITY, **pos)},
            "friction": {k: Field("float", "-", f"Coulomb coefficient, {w}", default=0.4)
                         for k, w in (("mu_disc", "log on log"), ("mu_shell", "log on shell"),
                                      ("mu_lifter", "log on lifter"))},
            "damping": {"restitution": Field("float", "-", "Newton's restitution e in [0, 1] "
                                             "(elastic e = 1 without the effect)",
                                             required=True)},
            "rotation": {"speed": Field("float", "rev/s", "drum speed, counter-clockwise",
                                        required=True, high=MAX_SPEED, why=SPEED_WHY, **pos)},
            "log_elasticity": {"modulus": Field("float", "Pa", "the logs' Young's modulus "
                                                "across the grain (half stiffness 2 E ℓ, the "
                                                "stack model's)", default=SPRUCE_E_TANGENTIAL,
                                                **pos)},
            "shell_elasticity": {"stiffness": Field("float", "N/m", "the shell's contact "
                                                    "stiffness", required=True, **pos)},
        },
        build=_scene_build, arrays=_scene_arrays, plot=_scene_plot, summary=_scene_summary)


#: The 2-D drum's scene-file schema (entry point ``qpcontact.scenes``: ``drum2d``).
SCENE = _scene_schema()
