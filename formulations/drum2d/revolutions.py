r"""Per-revolution statistics of a 2-D drum run: what the engineer reads.

SI units: s, rad/s, N (forces = impulse / h: the step's mean force), J.

Windows
-------
The shell turns at Ω [rad/s]; a revolution lasts T = 2π/|Ω| and revolution k
(k = 0, 1, ...) is the window t ∈ [k T, (k + 1) T), counted from t = 0 (the
shell's angle Ω t).  Step s (from t[s] to t[s + 1]) belongs to the window that
holds its start t[s] (a step straddling (k + 1) T is revolution k's).  The
run covers the fraction (min(t_end, (k+1) T) − max(t_start, k T)) / T of the
revolution (t_start the window's first step's start, or k T where an earlier
step straddles k T; t_end its last step's end); the window is complete when
that is 1 within half a step — whether or not T is a whole number of steps.
A window the run covers only in part (a run of 1.4 revolutions: the second;
a run started at t0 > 0: possibly the first) is kept and labelled partial
with its fraction.  Without rotation (Ω = 0) the whole run is
one window ("whole run").

Per window and contact kind
---------------------------
The recorder (records.py) keeps per step s and kind (0 log–log, 1 log–shell,
2 log–lifter) the largest normal force ``force_peak[s, kind]`` and the counts
``force_counts[s, kind, b]`` of active contacts whose force F >= 0.1 N fell
in bin b of :data:`FORCE_BINS` (10 bins a decade, 0.1 N to 10 MN; above
counted in the last bin); F is the step's mean force, or at an unresolved
impact of compliant contacts the resolved cluster's peak (impacts.py).  A window's histogram is the sum of its
steps' rows: it counts contact-steps (a contact carried for 50 steps counts
50 times: the histogram is time-weighted, so a resting log's weight dominates
it and impacts show in its tail); its peak is the largest ``force_peak``.

Quantiles come from the histogram: the q-quantile lies in the bin where the
cumulative count first reaches q · N, and is reported as that bin's upper
edge, capped at the window's peak (exact for q = 1) — an upper bound of the
true quantile, at most a factor :data:`BIN_RATIO` = 10^0.1 ≈ 1.26 above it.

Kinds: log–log and log–shell (the stack model's two kinds), log–lifter kept apart
(``"log-lifter"``), and ``"log-steel"`` = log–shell and log–lifter merged
(both steel; the stack model's shell contact is the estimate for
either, formulations.drum2d.stack).  The figures draw log–log and log–steel.

Sliding work
------------
``sliding_work[s, i]`` [J] is the friction work |r_T| s̄ of step s (records.py) charged to
log i (half each at a log–log contact, all to the log at the steel).  A
window's sliding work per log is the sum of its rows (n,) [J]; reported with
its total, mean over logs, maximum and the log (index) that takes it.
"""

from __future__ import annotations

import os

from dataclasses import dataclass, field

import numpy as np

from qpcontact.core.errors import InvalidOptionError

from .records import FORCE_BINS

__all__ = ["KIND_NAMES", "BIN_RATIO", "KindForces", "SlidingWork", "Revolution", "Window",
           "revolution_windows", "histogram_quantile", "revolutions", "run_arrays"]

#: The contact kinds of the statistics: records.py's three, then shell and
#: lifter merged ("log-steel").
KIND_NAMES = ("log-log", "log-shell", "log-lifter", "log-steel")
#: Ratio of neighbouring edges of FORCE_BINS (10 bins a decade): the
#: histogram's resolution, and how far above a true quantile its estimate can lie.
BIN_RATIO = float(FORCE_BINS[1] / FORCE_BINS[0])
#: The quantiles reported by default.
QUANTILES = (0.5, 0.9, 0.99)


@dataclass
class Window:
    """Revolution ``index`` (k, from t = 0; 0 for the whole run without
    rotation): steps ``first`` .. ``stop`` − 1, spanning ``t_start_s`` ..
    ``t_end_s`` [s], the ``fraction`` of the revolution they cover (1 when
    complete, and for the whole run without rotation), ``complete``, and a
    ``label``."""

    index: int
    first: int
    stop: int
    t_start_s: float
    t_end_s: float
    fraction: float
    complete: bool
    label: str


@dataclass
class KindForces:
    """One contact kind over one window: ``counts`` (B,) contact-steps per bin
    of FORCE_BINS, ``peak_N`` [N] the largest force (0 without contacts),
    ``quantiles_N`` {q: upper bound [N]} (module docstring), the window's
    ``seconds`` [s] and the step ``step_s`` h [s].

    The counts depend on the step: a contact carried for a time τ counts
    τ/h times, an unresolved impact once.  Two rates do not:
    ``per_second`` = counts / seconds [1/s] is, in the impact tail, the
    impacts a second; ``at_a_time`` = counts · h / seconds [-] is, in the
    resting part, the mean number of contacts in the bin at any instant
    (contact-seconds per second)."""

    counts: np.ndarray
    peak_N: float
    quantiles_N: dict
    seconds: float = 0.0
    step_s: float = 0.0

    @property
    def per_second(self) -> np.ndarray:
        """counts / window duration [1/s] (0 for an empty window)."""
        return self.counts / self.seconds if self.seconds > 0 else np.zeros(self.counts.shape)

    @property
    def at_a_time(self) -> np.ndarray:
        """counts · h / window duration [-]: the mean number of contacts in each bin."""
        return self.per_second * self.step_s

    @property
    def contact_steps(self) -> int:
        """How many (contact, step) pairs carried force in the window."""
        return int(self.counts.sum())


@dataclass
class SlidingWork:
    """The friction work charged to each log over a window: ``per_log_J`` (n,)
    [J], their ``total_J``, ``mean_J`` (over all logs), ``max_J`` and
    ``max_log`` (the index of the log that takes it)."""

    per_log_J: np.ndarray
    total_J: float = field(init=False)
    mean_J: float = field(init=False)
    max_J: float = field(init=False)
    max_log: int = field(init=False)

    def __post_init__(self):
        w = self.per_log_J
        self.total_J = float(w.sum())
        self.mean_J = float(w.mean()) if w.size else 0.0
        self.max_log = int(np.argmax(w)) if w.size else -1
        self.max_J = float(w[self.max_log]) if w.size else 0.0


@dataclass
class Revolution:
    """A window's statistics: ``window`` (Window), ``forces`` {kind name:
    KindForces} for KIND_NAMES, ``sliding`` (SlidingWork)."""

    window: Window
    forces: dict
    sliding: SlidingWork

    @property
    def label(self) -> str:
        """The window's label ("rev 2", "rev 3 (partial, 0.40)", "whole run")."""
        return self.window.label


def revolution_windows(t, omega: float) -> list:
    """The windows (Window) of a run with state times ``t`` (S+1,) [s] and the
    shell's speed ``omega`` [rad/s] (module docstring): one per revolution
    the steps touch, or the whole run when omega is 0."""
    t = np.asarray(t, float)
    S = t.size - 1
    if S < 1:
        raise InvalidOptionError(f"a run of {S} steps has no revolution to report; it needs "
                                 "at least one step (t holds S+1 state times)")
    if not np.isfinite(omega):
        raise InvalidOptionError(f"omega must be finite [rad/s]; got {omega}")
    if omega == 0:
        return [Window(0, 0, S, float(t[0]), float(t[-1]), 1.0, True, "whole run")]
    T = 2 * np.pi / abs(omega)
    h = float(np.min(np.diff(t)))
    # a step starting a hair below k T by rounding belongs to revolution k
    rev = np.floor(t[:-1] / T + 1e-9).astype(np.int64)
    out = []
    for k in np.unique(rev):
        steps = np.flatnonzero(rev == k)
        a, b = int(steps[0]), int(steps[-1]) + 1
        # the time of [k T, (k+1) T) the run covers; a step straddling k T
        # (the previous window's last) covers the window's start
        lo = k * T if a > 0 else max(float(t[0]), k * T)
        frac = (min(float(t[b]), (k + 1) * T) - lo) / T
        complete = frac > 1.0 - 0.5 * h / T
        label = f"rev {k + 1}" if complete else f"rev {k + 1} (partial, {frac:.2f})"
        out.append(Window(int(k), a, b, float(t[a]), float(t[b]), 1.0 if complete else frac,
                          bool(complete), label))
    return out


def histogram_quantile(counts, q: float, peak: float) -> float:
    """The q-quantile [N] of a force histogram ``counts`` over FORCE_BINS:
    the upper edge of the bin where the cumulative count reaches q · N,
    capped at ``peak`` [N] (module docstring); 0 for an empty histogram."""
    counts = np.asarray(counts)
    if not 0 < q <= 1:
        raise InvalidOptionError(f"a quantile must be in (0, 1]; got {q}")
    total = counts.sum()
    if total == 0:
        return 0.0
    b = int(np.searchsorted(np.cumsum(counts), q * total, side="left"))
    return float(min(FORCE_BINS[min(b, counts.size - 1) + 1], peak))


def run_arrays(source, omega=None) -> dict:
    """The arrays the statistics need, from a Drum2DResult (``omega`` [rad/s]
    given: the model's ``Drum2D.omega``), a drum2d results file's path or an
    open file / mapping (datasets ``t``, ``force_peak``, ``force_counts``,
    ``sliding_work``, ``drum/omega``; ``omega`` overrides the file's)."""
    if isinstance(source, (str, os.PathLike)):
        # a path: read as the open file (a string's ``in`` would test its
        # characters, and "t" is in most paths)
        import h5py

        if not os.path.isfile(source):
            raise InvalidOptionError(f"no drum2d results file at {os.fspath(source)!r}")
        with h5py.File(source, "r") as h:
            return run_arrays(h, omega)
    if hasattr(source, "force_counts") and hasattr(source, "t"):
        if omega is None:
            raise InvalidOptionError("a Drum2DResult does not hold the shell's speed: pass "
                                     "omega= (the model's Drum2D.omega [rad/s], 0 for a still "
                                     "shell)")
        return dict(t=np.asarray(source.t), force_peak=np.asarray(source.force_peak),
                    force_counts=np.asarray(source.force_counts),
                    sliding_work=np.asarray(source.sliding_work), omega=float(omega))
    missing = [k for k in ("t", "force_peak", "force_counts", "sliding_work")
               if k not in source]
    if missing or (omega is None and "drum/omega" not in source):
        raise InvalidOptionError(
            f"the results lack {missing or ['drum/omega']}: a drum2d results file written "
            "before the force statistics were recorded; run the scene again with this version")
    return dict(t=source["t"][()], force_peak=source["force_peak"][()],
                force_counts=source["force_counts"][()],
                sliding_work=source["sliding_work"][()],
                omega=float(source["drum/omega"][()]) if omega is None else float(omega))


def _kind(counts, peaks, quantiles, seconds, step) -> KindForces:
    peak = float(peaks.max(initial=0.0))
    return KindForces(counts, peak, {q: histogram_quantile(counts, q, peak) for q in quantiles},
                      seconds, step)


def revolutions(source, omega=None, quantiles=QUANTILES) -> list:
    """Per-revolution statistics (Revolution, one per window) of a run: a
    Drum2DResult with ``omega`` [rad/s], or a results file, by its path or
    open (run_arrays); force histograms, peaks [N] and ``quantiles`` per kind
    (KIND_NAMES), the sliding work per log [J] (module docstring)."""
    a = run_arrays(source, omega)
    S = a["t"].size - 1
    if a["force_peak"].shape[0] != S or a["force_counts"].shape[:2] != (S, 3):
        raise InvalidOptionError(f"force_peak {a['force_peak'].shape} and force_counts "
                                 f"{a['force_counts'].shape} must have one row per step ({S})")
    out = []
    for w in revolution_windows(a["t"], a["omega"]):
        rows = slice(w.first, w.stop)
        counts = a["force_counts"][rows].sum(axis=0).astype(np.int64)     # (3, B)
        peaks = a["force_peak"][rows]                                    # (steps, 3)
        seconds = w.t_end_s - w.t_start_s
        step = float(np.mean(np.diff(a["t"][w.first:w.stop + 1])))
        forces = {name: _kind(counts[k], peaks[:, k], quantiles, seconds, step)
                  for k, name in enumerate(KIND_NAMES[:3])}
        forces["log-steel"] = _kind(counts[1] + counts[2], peaks[:, 1:], quantiles, seconds,
                                    step)
        out.append(Revolution(w, forces, SlidingWork(a["sliding_work"][rows].sum(axis=0))))
    return out
