r"""What a 2-D drum run keeps: states, per-step certificates and energies,
and the figures an engineer reads without keeping every contact of every step.

SI units: s, m, m/s, rad/s, N (forces = impulse / h), J.

Per step s (from t[s] to t[s+1]) the recorder keeps, by contact kind (0 log–log,
1 log–shell, 2 log–lifter: contacts.KINDS):

- ``force_peak`` (S, 3) [N]: the largest normal force, F = r_N / h (the
  step's mean), or where the step holds an impact it does not resolve the
  largest force of a resolved run of the impact's cluster (impacts.py; rigid
  contacts: the mean only);
- ``force_counts`` (S, 3, B) : how many contacts carried a normal force F in
  each bin of :data:`FORCE_BINS` (above the last edge counted in the last
  bin; forces under the first edge, 0.1 N — round-off at contacts that are
  opening, or a touch carrying a thousandth of a light log's weight — not
  counted) — the histograms per revolution are sums of these rows, so no
  contact list is needed for them;
- ``sliding_work`` (S, n) [J]: the friction work >= 0 of the step, ``|r_T| s̄``
  (s̄ its mean sliding speed, :func:`sliding_speed`: the slip taken linear
  from the step's start to its end, so slip that stops within the step
  counts) and, at the contacts of an impact's cluster run, what that
  resolved run slid beyond its own linear-slip estimate (impacts.py,
  "Sliding work"), charged to the logs it rubs — half to each log at a log–log
  contact (both surfaces slide on each other), all to the log at the shell
  or a lifter (the steel loses no bark).  Summed over logs it is the step's
  friction loss (stepper: energy bookkeeping).

``contacts`` keeps every active contact's arrays for the steps asked for
(``keep_contacts``: all, none, or every k-th step), for force chains in
snapshots and animations.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .contacts import DISC

__all__ = ["Drum2DResult", "FORCE_BINS", "Recorder", "sliding_speed"]

#: Edges [N] of the force histograms: 10 bins a decade from 0.1 N to 10 MN.
FORCE_BINS = np.logspace(-1, 7, 81)


def sliding_speed(u_before, u_after):
    """The step's mean sliding speed [m/s] at each contact: the mean of |u_T(t)|
    over the step for the slip u_T varying linearly from ``u_before`` (u_T⁻) to
    ``u_after`` (u_T⁺) — (|u⁻| + |u⁺|)/2 without a sign change, and
    (u⁻² + u⁺²)/(2 (|u⁻| + |u⁺|)) where the slip stops at t = h |u⁻|/(|u⁻| + |u⁺|)
    and turns (module docstring)."""
    a, b = np.abs(u_before), np.abs(u_after)
    turns = u_before * u_after < 0
    return np.where(turns, (a * a + b * b) / (2.0 * np.where(turns, a + b, 1.0)),
                    0.5 * (a + b))


@dataclass
class Drum2DResult:
    """A run: times ``t`` (S+1,) [s], ``positions`` (S+1, n, 2) [m],
    ``velocities`` (S+1, n, 2) [m/s], ``spins`` (S+1, n) [rad/s]; per step
    (index s = the step from t[s] to t[s+1]) ``n_contacts``, ``n_active``,
    ``certificate_error``, ``certified``, ``method``, ``solve_seconds``,
    ``pairs_checked``, ``fallback`` (the warm-started route was not certified
    and ``method`` solved the step instead); energies [J] per state
    (``kinetic``, ``potential``, ``elastic``: the contact springs'
    ½ c F²) and per step (``drive``, ``friction_loss``, ``impact_loss``: what
    the contacts dissipate besides friction, ``scheme``: gravity's work
    gained by θ = 1 positions (stepper), ``remainder``); the force
    statistics ``force_peak``, ``force_counts``, ``sliding_work`` (module
    docstring); ``contacts``: per step a dict of the active contacts' arrays
    (i, j, kind, r_n, r_t [N·s], slip: the step's mean sliding speed s̄ >= 0
    [m/s], whose work is ``|r_t| s̄`` where no cluster run adds to it, gap
    [m], normal) where kept,
    else None; ``last_contacts``: the last step's contacts and impulses (what
    a resumed run warm-starts from)."""

    t: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    spins: np.ndarray
    n_contacts: np.ndarray
    n_active: np.ndarray
    certificate_error: np.ndarray
    certified: np.ndarray
    method: list
    solve_seconds: np.ndarray
    pairs_checked: np.ndarray
    kinetic: np.ndarray
    potential: np.ndarray
    drive: np.ndarray
    friction_loss: np.ndarray
    impact_loss: np.ndarray
    remainder: np.ndarray
    max_penetration: float
    scheme: np.ndarray = field(default_factory=lambda: np.zeros(0))
    elastic: np.ndarray = field(default_factory=lambda: np.zeros(0))
    force_peak: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    force_counts: np.ndarray = field(default_factory=lambda: np.zeros((0, 3, 80), np.int32))
    sliding_work: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    contacts: list = field(default_factory=list)
    effects: frozenset = frozenset()
    fallback: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))
    last_contacts: dict | None = None

    @property
    def uncertified(self) -> np.ndarray:
        """The steps whose contact problem was not certified."""
        return np.flatnonzero(~self.certified)

    @property
    def worst_certificate(self) -> float:
        return float(self.certificate_error.max(initial=0.0))

    def energy_summary(self) -> dict:
        """Totals [J]: ΔK, ΔP, ΔE_el, drive work, friction and impact losses,
        the θ positions' term, remainder."""
        el = self.elastic if self.elastic.size else np.zeros(2)
        return {"kinetic_change": float(self.kinetic[-1] - self.kinetic[0]),
                "potential_change": float(self.potential[-1] - self.potential[0]),
                "elastic_change": float(el[-1] - el[0]),
                "drive": float(self.drive.sum()), "friction_loss": float(self.friction_loss.sum()),
                "impact_loss": float(self.impact_loss.sum()),
                "scheme": float(self.scheme.sum()), "remainder": float(self.remainder.sum())}


class Recorder:
    """Fills a Drum2DResult step by step (module docstring); ``start`` states
    and per-step rows may come from an interrupted run (``resume``)."""

    def __init__(self, steps: int, n: int, h: float, t0: float, keep_every: int):
        S = steps
        self.h, self.n, self.keep_every = h, n, keep_every
        self.state = dict(t=t0 + np.arange(S + 1) * h, positions=np.zeros((S + 1, n, 2)),
                          velocities=np.zeros((S + 1, n, 2)), spins=np.zeros((S + 1, n)))
        self.per = {k: np.zeros(S) for k in ("certificate_error", "solve_seconds", "drive",
                                             "friction_loss", "impact_loss", "remainder",
                                             "scheme")}
        self.counts = {k: np.zeros(S, np.int64) for k in ("n_contacts", "n_active",
                                                          "pairs_checked")}
        self.energy = {k: np.zeros(S + 1) for k in ("kinetic", "potential", "elastic")}
        self.certified = np.ones(S, bool)
        self.fallback = np.zeros(S, bool)
        self.method = [""] * S
        self.force_peak = np.zeros((S, 3))
        self.force_counts = np.zeros((S, 3, FORCE_BINS.size - 1), np.int32)
        self.sliding_work = np.zeros((S, n))
        self.contacts: list = [None] * S
        self.worst_pen = 0.0

    def state_at(self, s, q, v, mdiag, masses, gravity, elastic):
        V = v.reshape(self.n, 3)
        st = self.state
        st["positions"][s], st["velocities"][s], st["spins"][s] = q, V[:, :2], V[:, 2]
        self.energy["kinetic"][s] = 0.5 * float(mdiag @ (v * v))
        self.energy["potential"][s] = float(gravity * masses @ q[:, 1])
        self.energy["elastic"][s] = elastic

    def forces(self, s, c, r, slip, work, F):
        """The step's force statistics from its active contacts c, impulses r,
        mean sliding speeds (:func:`sliding_speed`), sliding work [J] and
        forces F [N] (impacts.step_forces; module docstring)."""
        from .records_kernel import force_books   # numba: imported where it runs

        force_books(np.asarray(F, float), c.kind, c.i, c.j, np.asarray(work, float), FORCE_BINS,
                    DISC, self.force_peak[s], self.force_counts[s], self.sliding_work[s])
        if self.keep_every and s % self.keep_every == 0:
            self.contacts[s] = dict(i=c.i, j=c.j, kind=c.kind, r_n=r[0::2], r_t=r[1::2],
                                    slip=slip, gap=c.gap, normal=c.normal)

    def restore(self, upto: int, arrays: dict):
        """Rows 0..upto of an interrupted run's results (the scene's file
        arrays, drum2d.scene): the run continues after state ``upto``."""
        for k in ("positions", "velocities", "spins"):
            self.state[k][:upto + 1] = arrays[k][:upto + 1]
        for k in self.energy:
            self.energy[k][:upto + 1] = arrays[f"energy/{k}"][:upto + 1]
        for k in ("drive", "friction_loss", "impact_loss", "remainder", "scheme"):
            self.per[k][:upto] = arrays[f"energy/{k}"][:upto]
        for k in ("certificate_error", "solve_seconds"):
            self.per[k][:upto] = arrays[k][:upto]
        for k in self.counts:
            self.counts[k][:upto] = arrays[k][:upto]
        self.certified[:upto] = np.asarray(arrays["certified"][:upto], bool)
        self.fallback[:upto] = np.asarray(arrays["fallback"][:upto], bool)
        self.method[:upto] = list(arrays["method"][:upto])
        self.force_peak[:upto] = arrays["force_peak"][:upto]
        self.force_counts[:upto] = arrays["force_counts"][:upto]
        self.sliding_work[:upto] = arrays["sliding_work"][:upto]
        self.worst_pen = float(arrays["drum/max_penetration"])
        step = np.asarray(arrays.get("contacts/step", np.zeros(0, np.int64)))
        for s in np.unique(step[step < upto]):
            at = step == s
            self.contacts[s] = dict(
                i=arrays["contacts/i"][at], j=arrays["contacts/j"][at],
                kind=arrays["contacts/kind"][at], r_n=arrays["contacts/force_n"][at] * self.h,
                r_t=arrays["contacts/force_t"][at] * self.h, slip=arrays["contacts/slip"][at],
                gap=arrays["contacts/gap"][at], normal=arrays["contacts/normal"][at])

    def result(self, upto: int, effects, last_contacts) -> Drum2DResult:
        """The run up to state ``upto`` (all of it at the end, a prefix for a checkpoint)."""
        st = {k: v[:upto + 1] for k, v in self.state.items()}
        return Drum2DResult(
            **st, **{k: v[:upto] for k, v in self.counts.items()},
            **{k: v[:upto] for k, v in self.per.items()},
            **{k: v[:upto + 1] for k, v in self.energy.items()},
            certified=self.certified[:upto], method=self.method[:upto],
            fallback=self.fallback[:upto], max_penetration=self.worst_pen,
            force_peak=self.force_peak[:upto], force_counts=self.force_counts[:upto],
            sliding_work=self.sliding_work[:upto], contacts=self.contacts[:upto],
            effects=effects, last_contacts=last_contacts)
