r"""The drum engineer's end-of-run figures of a 2-D drum run.

SI units unless named: s, N, J, W, kg (the log mass also in tonnes, t).

The cross-section stands for a drum slice as long as the logs, ℓ [m]: every
mass, force and energy of the 2-D run is that of logs ℓ long (geometry.Discs:
m = ρ π d²/4 ℓ), so a figure *per metre of drum* is the run's divided by ℓ.
Over a run of duration T [s] at the shell's speed Ω [rad/s], N = Ω T/2π
revolutions:

- **drive power** P = W_drive/(T ℓ) [W/m], W_drive = Σ_steps −rᵀw the work
  of the shell and lifters on the logs (stepper.py's books): what the motor
  delivers to the load, per metre of drum;
- **drive torque** τ = P/Ω [N·m/m]: the same work as a torque, since a rigid
  shell turning at Ω does work τ Ω per unit time (per metre);
- **energy per tonne per revolution** e = W_drive/(N M) [J/t], M = Σ m_i in
  tonnes — the load's specific energy, independent of ℓ;
- **sliding work** (the rubbing that takes the bark off, records.py: −r_T u_T⁺
  per step, half to each log at a log–log contact, all to the log at the
  steel): per log per revolution W_s/(n N) [J] and per square metre of log
  surface per revolution W_s/(N Σ π d_i ℓ) [J/m²], the logs' mantle area;
- the certificates: the worst error, the steps not certified, the steps the
  warm start did not certify (solved again by the fallback method);
- the peak normal force per contact kind [N] (records.py).

Without rotation there are no revolutions: the rates are per second instead
(the keys say which) and there is no torque.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["RunSummary", "run_summary"]


@dataclass
class RunSummary:
    """The figures of the module docstring.  ``per`` is "rev" (a rotating
    drum: the rates per revolution) or "s" (a still shell: per second)."""

    steps: int
    duration_s: float
    revolutions: float
    per: str
    worst_certificate: float
    uncertified_steps: int
    fallback_steps: int
    peaks_N: dict
    log_mass_t: float
    drive_work_J: float
    drive_power_W_per_m: float
    drive_torque_Nm_per_m: float | None
    energy_J_per_t: float
    sliding_J_per_log: float
    sliding_J_per_m2: float

    def as_dict(self) -> dict:
        """The figures as {column [unit]: value} (a sweep's summary row)."""
        per = self.per
        J = "J" if per == "rev" else "W"      # a rate per second is a power
        out = {"max_certificate_error": self.worst_certificate,
               "uncertified_steps": self.uncertified_steps,
               "fallback_steps": self.fallback_steps,
               **{f"peak {k} [N]": v for k, v in self.peaks_N.items()},
               "drive power [W/m]": self.drive_power_W_per_m,
               f"energy/t/{per} [{J}/t]": self.energy_J_per_t,
               f"sliding/log/{per} [{J}]": self.sliding_J_per_log,
               f"sliding/m²/{per} [{J}/m²]": self.sliding_J_per_m2}
        if self.drive_torque_Nm_per_m is not None:
            out["drive torque [N·m/m]"] = self.drive_torque_Nm_per_m
        return out

    def table(self) -> str:
        """The summary as text lines for the command line."""
        J, per = ("J", " per revolution") if self.per == "rev" else ("W", "")
        span = (f"{self.revolutions:.3g} revolutions" if self.per == "rev"
                else "a still shell")
        cert = ("every step certified" if self.uncertified_steps == 0
                else f"{self.uncertified_steps} steps NOT certified")
        rows = [
            f"drum2d run: {self.steps} steps, {self.duration_s:.4g} s ({span}); {cert}, worst "
            f"certificate error {self.worst_certificate:.2e}; {self.fallback_steps} steps "
            "solved again by the fallback method",
            "peak normal force: " + ", ".join(f"{k} {v / 1e3:.4g} kN"
                                              for k, v in self.peaks_N.items()),
            f"drive: {self.drive_power_W_per_m:.4g} W per metre of drum"
            + (f", torque {self.drive_torque_Nm_per_m:.4g} N·m per metre"
               if self.drive_torque_Nm_per_m is not None else "")
            + f"; {self.energy_J_per_t:.4g} {J} per tonne of logs{per} "
              f"({self.log_mass_t:.3g} t of logs in the section)",
            f"sliding work: {self.sliding_J_per_log:.4g} {J} per log, "
            f"{self.sliding_J_per_m2:.4g} {J} per m² of log surface{per}",
        ]
        return "\n".join(rows)


def run_summary(result, discs, omega: float) -> RunSummary:
    """The summary (module docstring) of a Drum2DResult ``result`` for its
    ``discs`` (geometry.Discs) and shell speed ``omega`` [rad/s] (0: a
    still shell)."""
    r = result
    steps = int(r.t.size - 1)
    T = float(r.t[-1] - r.t[0])
    revs = T * abs(omega) / (2 * np.pi)
    rotating = omega != 0 and revs > 0
    per_unit = revs if rotating else T
    length = float(discs.length)
    mass_t = float(np.sum(discs.masses)) / 1e3
    drive = float(np.sum(r.drive))
    power = drive / (T * length) if T > 0 else 0.0
    sliding = float(np.sum(r.sliding_work))
    surface = float(np.sum(np.pi * discs.diameters * length))
    peaks = np.max(r.force_peak, axis=0, initial=0.0) if r.force_peak.size else np.zeros(3)
    safe = per_unit if per_unit > 0 else np.inf
    return RunSummary(
        steps=steps, duration_s=T, revolutions=revs, per="rev" if rotating else "s",
        worst_certificate=r.worst_certificate, uncertified_steps=int(r.uncertified.size),
        fallback_steps=int(np.sum(r.fallback)),
        peaks_N={"log-log": float(peaks[0]), "log-shell": float(peaks[1]),
                 "log-lifter": float(peaks[2])},
        log_mass_t=mass_t, drive_work_J=drive, drive_power_W_per_m=power,
        drive_torque_Nm_per_m=power / omega if rotating else None,
        energy_J_per_t=drive / safe / mass_t if mass_t > 0 else 0.0,
        sliding_J_per_log=sliding / safe / discs.n,
        sliding_J_per_m2=sliding / safe / surface if surface > 0 else 0.0)
