"""A drum run's per-step arrays and what an engineer reads off them (SI units)."""

from __future__ import annotations

import os
import textwrap
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .model import Drum

__all__ = ["DrumResult", "DrumSummary"]


@dataclass
class DrumSummary:
    """What an engineer reads off a run (SI units)."""

    peak_force: np.ndarray        # N, per contact (0: shell-log 0; k: log k-1 / log k)
    peak_time: np.ndarray         # s
    collisions_per_log: np.ndarray  # contact onsets touching each log
    energy_initial: float         # J: kinetic + elastic + gravitational (0 reference)
    energy_final: dict            # J: kinetic, elastic, potential, viscous, numerical
    max_certificate_error: float
    fallbacks: int
    tau: float = float("nan")     # s, the step size (the numerical dissipation's knob)

    def table(self) -> str:
        lines = ["contact  peak force [N]  at t [s]"]
        for k, (f, t) in enumerate(zip(self.peak_force, self.peak_time)):
            who = "shell/log 0" if k == 0 else f"log {k - 1}/log {k}"
            lines.append(f"{k:7d}  {f:14.4g}  {t:9.5f}   {who}")
        lines.append("collisions per log: " + ", ".join(str(int(c)) for c in self.collisions_per_log))
        e = self.energy_final
        # lines of at most 100 columns: the output reads on a 100-column terminal
        lines.append(textwrap.fill(
            f"energy [J]: initial {self.energy_initial:.6g}; final kinetic {e['kinetic']:.6g}, "
            f"elastic {e['elastic']:.6g}, potential {e['potential']:.6g}, viscous dissipated "
            f"{e['viscous']:.6g}, numerical dissipation {e['numerical']:.6g}", 100,
            subsequent_indent=" " * 12))
        lines.append(textwrap.fill(self.dissipation_note(), 100, subsequent_indent=" " * 12))
        lines.append(f"largest certificate error {self.max_certificate_error:.2e}; "
                     f"fallbacks {self.fallbacks}")
        return "\n".join(lines)

    def dissipation_note(self) -> str:
        """One line: where the numerical dissipation comes from and the knob
        that controls it.  The one-sided differences lose energy at first
        order in tau, so halving tau halves the loss only in the limit; on
        examples/scenes/drum.toml (20 -> 40 -> 80 -> 160 steps per period:
        20.1, 13.5, 8.3, 4.7 J), the demo's drop and its ten logs, halving cut
        it by 33-47 %: the line says 30-50 %
        (tests/commands/test_demo.py::test_halving_tau_cuts_the_numerical_dissipation_by_30_to_50_percent)."""
        of = f" of the initial {self.energy_initial:.3g} J" if self.energy_initial > 0 else ""
        return (f"numerical dissipation: {self.energy_final['numerical']:.3g} J{of} lost by the "
                f"implicit (backward-difference) time steps at tau = {self.tau:.3g} s; halving tau "
                "(time.steps_per_period or time.tau) cuts it by 30-50 %")

    __str__ = table


@dataclass
class DrumResult:
    """Per-step arrays of a drum run, rows = steps 0..n (SI units):
    ``forces`` N [N] and ``gaps`` D [m] per contact, ``displacements`` U [m] and
    ``velocities`` [m/s] per log centre (upward positive), time ``t`` [s]."""

    drum: Drum
    tau: float
    t: np.ndarray
    forces: np.ndarray
    gaps: np.ndarray
    displacements: np.ndarray
    velocities: np.ndarray
    viscous_dissipation: np.ndarray
    certificate_errors: np.ndarray
    iterations: np.ndarray = None     # per step: the method's iterations (pivots for bpp)
    methods: list = field(default_factory=list)
    fallbacks: int = 0
    wall_time: float = 0.0
    solve_time: float = 0.0

    def energy(self) -> dict:
        """Energy [J] per step: kinetic ½mv², elastic ½N'CN (log halves and shell),
        gravitational potential m g U (0 at the start), cumulative viscous
        dissipation, and numerical dissipation = the balance's residual."""
        d = self.drum
        kinetic = 0.5 * np.sum(d.mass * self.velocities ** 2, axis=1)
        elastic = 0.5 * np.sum(d.compliance * self.forces ** 2, axis=1)
        potential = d.gravity * np.sum(d.mass * self.displacements, axis=1)
        viscous = self.viscous_dissipation
        total0 = kinetic[0] + elastic[0] + potential[0]
        numerical = total0 - (kinetic + elastic + potential + viscous)
        return dict(kinetic=kinetic, elastic=elastic, potential=potential, viscous=viscous,
                    numerical=numerical, mechanical=kinetic + elastic + potential)

    def summary(self) -> DrumSummary:
        N = self.forces
        k_peak = np.argmax(N, axis=0)
        onsets = (N[1:] > 0) & ~(N[:-1] > 0)
        per_contact = onsets.sum(axis=0)
        per_log = per_contact.copy()          # contact k touches log k (from below)
        per_log[:-1] += per_contact[1:]       # and log k-1 (from above)
        e = self.energy()
        return DrumSummary(
            peak_force=N[k_peak, np.arange(N.shape[1])], peak_time=self.t[k_peak],
            collisions_per_log=per_log, energy_initial=float(e["mechanical"][0]),
            energy_final={k: float(v[-1]) for k, v in e.items() if k != "mechanical"},
            max_certificate_error=float(self.certificate_errors.max()), fallbacks=self.fallbacks,
            tau=float(self.tau))

    def save(self, path) -> str:
        """Write the arrays to a .npz file atomically (temporary file, then rename)."""
        path = os.fspath(path)
        tmp = path + ".tmp.npz"
        np.savez_compressed(tmp, t=self.t, forces=self.forces, gaps=self.gaps,
                            displacements=self.displacements, velocities=self.velocities,
                            viscous_dissipation=self.viscous_dissipation,
                            certificate_errors=self.certificate_errors, tau=self.tau)
        os.replace(tmp, path)
        return path
