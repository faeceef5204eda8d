r"""The stack model's estimate of collision forces for a 2-D drum's logs.

SI units: m, kg, s, N (stiffness N/m, modulus Pa).

The decomposition paper (Kolesnikov 2013; digest in ../shared/PAPERS.md) estimates
the collision forces in a debarking drum from above with a "conditional
stack": logs on one vertical axis, each two springs of stiffness s = 2 E ℓ
about a centre mass (formulations.drum.model derives it), colliding with the
shell and with each other as the drum's tumbling bed collapses.  This module
sets that stack up for the logs of a 2-D run and the drum they tumble in, runs
it with formulations.drum's public API (Drum, Log, log_half_stiffness) and
returns its peak log–shell and log–log forces [N].

Assumptions (each chosen to err on the high side)
-------------------------------------------------
- **Which logs.**  A column of L logs: the L heaviest logs of the run, the
  heaviest lowest (the peak of an impact grows with √m).  L is the number of
  layers of the bed at rest, round(bed depth / mean diameter) with the bed
  depth from the lowest to the highest log surface of the fill at the start
  (or given), clamped to [2, n].  Mass, diameter, length ℓ and modulus E are
  the run's (the modulus across the grain is the run's ``log_elasticity``
  modulus, the stack model's spruce default otherwise).
- **Which drop.**  The largest free fall the drum allows: from the top of the
  shell to its bottom, H = D − d_max, with the shell's speed Ω R added as
  kinetic energy, H_eq = D − d_max + (Ω R)²/(2 g): a log leaves the shell or a
  lifter no higher than the top of the drum and no faster than the shell.
  Impact speed v = √(2 g H_eq).  The lifter's release point is lower, so H
  bounds it.
- **log–shell**: the whole column falls together (gaps 0, all at −v at the
  impact) onto the shell; the estimate is the peak force of contact 0.
- **log–log**: the column's lowest log rests on the shell and the L − 1 logs
  above fall together onto it at v; the estimate is the largest peak of the
  log–log contacts 1 .. L−1.
- **Shell**: rigid, unless the run names ``shell_elasticity`` (then its
  stiffness k_s in series with the lowest log's half).
- **No damping** (undamped impacts: the run's restitution does not lower the
  estimate) and the stack model's prism stiffness 2 E ℓ, stiffer than a
  Hertzian line contact (docs/drum.md).
- **Time step** τ = (shortest contact period)/``steps_per_period`` (160 by
  default: the stack model's peak is first order in τ, from below, about 3 %
  low at 160 — docs/drum.md), over two longest contact periods: the peaks
  come within the first (columns of 1 to 12 logs of 0.08–0.2 m, run for ten
  periods: the largest force of the ten came in the first).

Not a bound.  Each assumption errs high, but nothing proves that no 2-D
impact exceeds the column's: a log can strike a bed that is not a column
(the 2-D peaks come from a resolved run of the impact's cluster,
formulations.drum2d.impacts, which sees the chain the impulse takes), and
friction, spin and the lifters' speed are not in the stack.  The figures
draw it as a reference line and print the ratio largest 2-D peak / estimate;
a ratio above 1 says the column is not the worst case of that run.

The 2-D run with rigid contacts reports impulse / h, the mean force over a
step h much longer than a contact period; those are far below this estimate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from qpcontact.core.errors import InvalidOptionError

from ..drum import Drum, Log, log_half_stiffness
from .geometry import GRAVITY
from .laws import SPRUCE_E_TANGENTIAL

__all__ = ["StackEstimate", "stack_estimate", "stack_estimate_for_run", "drop_height",
           "bed_layers"]


@dataclass
class StackEstimate:
    """The stack model's estimate: ``log_shell_N`` and ``log_log_N``
    [N] (peak forces), the ``drop_height_m`` H_eq [m] and ``impact_speed_m_s``
    v [m/s], the column's ``masses_kg`` (bottom to top) and ``stiffness_N_m``
    (each log half), the ``shell_stiffness_N_m`` (None: rigid) and the time
    step ``tau_s`` [s] of the stack runs."""

    log_shell_N: float
    log_log_N: float
    drop_height_m: float
    impact_speed_m_s: float
    masses_kg: np.ndarray
    stiffness_N_m: np.ndarray
    shell_stiffness_N_m: float | None
    tau_s: float

    @property
    def layers(self) -> int:
        """The number of logs L in the column."""
        return int(self.masses_kg.size)

    def describe(self) -> str:
        """One line for a figure or a report."""
        shell = ("rigid shell" if self.shell_stiffness_N_m is None
                 else f"shell {self.shell_stiffness_N_m:.3g} N/m")
        return (f"stack model: {self.layers} heaviest logs dropped {self.drop_height_m:.2f} m "
                f"(v = {self.impact_speed_m_s:.2f} m/s), {shell}, undamped")


def drop_height(diameter: float, d_max: float, omega: float = 0.0,
                gravity: float = GRAVITY) -> float:
    """H_eq = D − d_max + (Ω D/2)²/(2 g) [m] for a drum of inner diameter D
    [m], the largest log d_max [m], the shell's speed Ω [rad/s] (module
    docstring)."""
    if not 0 < d_max < diameter:
        raise InvalidOptionError(f"the largest log ({d_max} m) must be smaller than the drum's "
                                 f"diameter ({diameter} m)")
    return float(diameter - d_max + (0.5 * omega * diameter) ** 2 / (2.0 * gravity))


def bed_layers(positions, diameters) -> int:
    """round(bed depth / mean diameter), at least 1: the layers of a bed whose
    logs have centres ``positions`` (n, 2) [m] and ``diameters`` (n,) [m]
    (the depth from the lowest to the highest log surface)."""
    y, r = np.asarray(positions, float)[:, 1], 0.5 * np.asarray(diameters, float)
    depth = float((y + r).max() - (y - r).min())
    return max(1, int(round(depth / float(np.mean(diameters)))))


def _peaks(masses, s, gaps, velocities, shell_stiffness, gravity, steps_per_period):
    effects = ("gravity",) + (("shell_elasticity",) if shell_stiffness else ())
    drum = Drum([Log(m, k) for m, k in zip(masses, s)], gaps, velocities,
                shell_stiffness=shell_stiffness, effects=effects, gravity=gravity)
    periods = drum.contact_periods()
    tau = float(periods.min()) / steps_per_period
    steps = int(np.ceil(2.0 * float(periods.max()) / tau))
    return drum.simulate(tau, steps).forces.max(axis=0), tau


def stack_estimate(diameters, masses, length: float, drop_height_m: float, *,
                   modulus: float = SPRUCE_E_TANGENTIAL, shell_stiffness: float | None = None,
                   layers: int = 2, gravity: float = GRAVITY,
                   steps_per_period: int = 160) -> StackEstimate:
    """The stack model's peak log–shell and log–log forces [N] for the logs
    of ``diameters`` [m] and ``masses`` [kg] (n,), ``length`` ℓ [m],
    ``modulus`` E [Pa], dropped ``drop_height_m`` [m]: a column of the
    ``layers`` heaviest logs (module docstring); ``shell_stiffness`` [N/m]
    or None (rigid)."""
    d, m = np.atleast_1d(np.asarray(diameters, float)), np.atleast_1d(np.asarray(masses, float))
    if d.shape != m.shape or d.size == 0:
        raise InvalidOptionError(f"diameters {d.shape} and masses {m.shape} must be the same "
                                 "non-empty length (one per log)")
    if not (np.isfinite(drop_height_m) and drop_height_m > 0):
        raise InvalidOptionError(f"drop_height_m must be > 0 [m]; got {drop_height_m}")
    if int(layers) < 1 or int(steps_per_period) < 20:
        raise InvalidOptionError(f"layers must be >= 1 and steps_per_period >= 20 (the stack "
                                 f"model's resolution); got {layers}, {steps_per_period}")
    L = min(int(layers), d.size)
    heavy = np.argsort(-m, kind="stable")[:L]
    mass = m[heavy]
    s = np.array([log_half_stiffness(di, length, modulus) for di in d[heavy]])
    v = float(np.sqrt(2.0 * gravity * drop_height_m))
    falling = -v * np.ones(L)
    shell_peaks, tau = _peaks(mass, s, np.zeros(L), falling, shell_stiffness, gravity,
                              steps_per_period)
    log_log = 0.0
    if L >= 2:
        falling[0] = 0.0              # the lowest log rests on the shell
        ll, _ = _peaks(mass, s, np.zeros(L), falling, shell_stiffness, gravity,
                       steps_per_period)
        log_log = float(ll[1:].max())
    return StackEstimate(float(shell_peaks[0]), log_log, float(drop_height_m), v, mass, s,
                         shell_stiffness, tau)


def stack_estimate_for_run(source, *, layers: int | None = None,
                           steps_per_period: int = 160) -> StackEstimate:
    """The estimate (module docstring) for a run: a Drum2D model, or a drum2d
    results file (datasets ``diameters``, ``masses``, ``positions``,
    ``drum/radius``, ``drum/omega``, ``logs/length``; ``logs/modulus``,
    ``drum/shell_stiffness`` and ``drum/gravity`` where written).  ``layers``:
    the column's logs (default: the bed's layers at the start, clamped to
    [2, n])."""
    if hasattr(source, "discs") and hasattr(source, "shell"):
        d, m, pos = source.discs.diameters, source.discs.masses, source.discs.positions
        R, omega, length = source.shell.radius, source.omega, source.discs.length
        modulus = getattr(source, "modulus", SPRUCE_E_TANGENTIAL)
        ks = (getattr(source, "shell_stiffness", None) if "shell_elasticity" in source.effects
              else None)
        g = source.gravity
    else:
        if "logs/length" not in source:
            raise InvalidOptionError("the results file does not hold logs/length [m] (written "
                                     "by an older version): run the scene again")
        d, m, pos = source["diameters"][()], source["masses"][()], source["positions"][0]
        R, omega = float(source["drum/radius"][()]), float(source["drum/omega"][()])
        length = float(source["logs/length"][()])
        modulus = float(source["logs/modulus"][()]) if "logs/modulus" in source \
            else SPRUCE_E_TANGENTIAL
        ks = float(source["drum/shell_stiffness"][()]) if "drum/shell_stiffness" in source \
            else 0.0
        ks = ks if ks > 0 else None       # the file writes 0 for a rigid shell
        g = float(source["drum/gravity"][()]) if "drum/gravity" in source else GRAVITY
    if layers is None:
        layers = min(max(2, bed_layers(pos, d)), len(d))
    return stack_estimate(d, m, length, drop_height(2 * R, float(np.max(d)), omega, g),
                          modulus=modulus, shell_stiffness=ks, layers=layers, gravity=g,
                          steps_per_period=steps_per_period)
