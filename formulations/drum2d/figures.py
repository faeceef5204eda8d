"""The 2-D drum's standard figures, drawn from a results file alone (an open
h5py.File written by the drum2d scene): a snapshot of the cross-section with
its force chains, the energy balance over time, and per revolution
(formulations.drum2d.revolutions) the contact-force histograms and peaks
beside the stack model's estimate (formulations.drum2d.stack) and the
sliding work per log.  SI units on the axes (m, s, J, N).
``draw_cross_section`` draws one state on given axes: the snapshot's and the
animation's (formulations.drum2d.animation) frames."""

from __future__ import annotations

import numpy as np

__all__ = ["snapshot_figure", "energy_figure", "cross_section_data", "draw_cross_section",
           "force_histogram_figure", "force_peak_figure", "sliding_work_figure"]


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def cross_section_data(h) -> dict:
    """What the cross-section drawings read from a results file, loaded once
    (an animation draws many states from it): times, positions, diameters,
    the drum's geometry and the kept contacts' rows."""
    data = {k: h[k][()] for k in ("t", "positions", "diameters")}
    data.update({k: float(h[f"drum/{k}"][()]) for k in ("radius", "omega", "lifter_height",
                                                         "lifter_half_width")})
    data["lifter_angles"] = h["drum/lifter_angles"][()]
    data.update({k: h[f"contacts/{k}"][()] for k in ("step", "i", "j", "force_n", "normal")})
    return data


def draw_cross_section(ax, data: dict, k: int, fmax: float | None = None):
    """Draw state ``k`` of ``data`` (cross_section_data) on ``ax``: shell,
    lifters, discs, and a line per active contact of step k − 1 (when kept) —
    centre to centre between discs, centre to contact point at a wall — of
    width ∝ its normal force (impulse / h [N]) relative to ``fmax`` [N]
    (default: the largest of the step).  Returns the largest force drawn [N]
    and the artists added (an animation removes them for the next frame)."""
    from matplotlib.collections import LineCollection, PatchCollection
    from matplotlib.patches import Circle, Polygon

    t, diam, R = data["t"], data["diameters"], data["radius"]
    lh, lb = data["lifter_height"], data["lifter_half_width"]
    added = [ax.add_patch(Circle((0, 0), R, fill=False, lw=2.0, color="0.2"))]
    for a in data["lifter_angles"] + data["omega"] * t[k]:
        u, n = np.array([np.cos(a), np.sin(a)]), np.array([-np.sin(a), np.cos(a)])
        p0, p1 = (R - lh) * u, R * u
        added.append(ax.add_patch(Polygon([p0 - lb * n, p1 - lb * n, p1 + lb * n,
                                           p0 + lb * n], color="0.35")))
    q = data["positions"][k]
    added.append(ax.add_collection(PatchCollection(
        [Circle(c, 0.5 * d) for c, d in zip(q, diam)], facecolor="#E69F00",
        edgecolor="#8a5a00", lw=0.6, alpha=0.55)))
    rows = np.flatnonzero(data["step"] == k - 1) if k > 0 else np.zeros(0, int)
    top = 0.0
    if rows.size:
        i, j, F = data["i"][rows], data["j"][rows], data["force_n"][rows]
        a = q[i]
        b = np.where((j >= 0)[:, None], q[np.maximum(j, 0)],
                     a - 0.5 * diam[i][:, None] * data["normal"][rows])
        top = float(F.max(initial=0.0))
        scale = fmax if fmax else top
        if scale > 0:
            width = 0.3 + 4.0 * np.minimum(F / scale, 1.5)
            keep = F > 0
            added.append(ax.add_collection(LineCollection(
                np.stack([a, b], 1)[keep], linewidths=width[keep], colors="#0072B2")))
    ax.set_xlim(-1.08 * R, 1.08 * R)
    ax.set_ylim(-1.08 * R, 1.18 * R)
    ax.set_aspect("equal")
    ax.set(xlabel="x [m]", ylabel="y [m]")
    return top, added


def snapshot_figure(h, step: int | None = None):
    """The cross-section at state ``step`` (default: the last state after a
    step whose contacts were kept, else the last): shell, lifters, discs, and
    a line per active contact of the step before it — centre to centre
    between discs, centre to contact point at a wall — of width ∝ its normal
    force (impulse / h [N])."""
    plt = _pyplot()
    data = cross_section_data(h)
    t, diam = data["t"], data["diameters"]
    kept = data["step"]
    if step is not None:
        k = int(step)
    else:    # contacts kept every k-th step: the last state with its force chains
        k = int(kept.max()) + 1 if kept.size else len(t) - 1
    fig, ax = plt.subplots(figsize=(7.2, 7.0))
    fmax, _ = draw_cross_section(ax, data, k)
    ax.plot([], [], color="#0072B2", lw=4.3,
            label=f"contact force (width ∝ force; widest {fmax / 1e3:.3g} kN)")
    turns = data["omega"] * t[k] / (2 * np.pi)
    ax.set_title(f"Drum cross-section at t = {t[k]:.3g} s ({turns:.2f} rev), "
                 f"{len(diam)} logs", fontsize=10)
    ax.legend(loc="upper center", fontsize=8, frameon=False)
    fig.tight_layout()
    return fig


def energy_figure(h):
    """Cumulative energy balance [J] against time [s]: the drive's work, the
    change of kinetic + potential (+ the springs') energy, the friction and
    impact losses (above); the numerical remainder, ΔK + ΔP + ΔE_el − drive +
    losses (below)."""
    plt = _pyplot()
    t = h["t"][()]
    K, P = h["energy/kinetic"][()], h["energy/potential"][()]
    if "energy/elastic" in h:      # the contact springs (log/shell elasticity)
        P = P + h["energy/elastic"][()]
    cum = {k: np.concatenate([[0.0], np.cumsum(h[f"energy/{k}"][()])])
           for k in ("drive", "friction_loss", "impact_loss", "remainder")}
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(8.5, 6.4), sharex=True,
                                 gridspec_kw={"height_ratios": (2.2, 1)})
    ax.plot(t, cum["drive"], color="#0072B2", lw=1.6, label="work of the drive")
    springs = "energy/elastic" in h and np.any(h["energy/elastic"][()])
    ax.plot(t, K + P - K[0] - P[0], color="#000000", ls="--", lw=1.4,
            label="kinetic + potential" + (" + elastic" if springs else "") + " (change)")
    named = "friction" in str(h.attrs.get("effects", ""))
    ax.plot(t, cum["friction_loss"], color="#D55E00", ls="-.", lw=1.4,
            label="friction loss" + ("" if named else " (friction not simulated)"))
    ax.plot(t, cum["impact_loss"], color="#009E73", ls=":", lw=1.8, label="impact loss")
    scheme = h["energy/scheme"][()] if "energy/scheme" in h else np.zeros(len(t) - 1)
    if np.any(scheme):     # θ = 1 positions (with springs): the time scheme's own loss
        ax.plot(t, -np.concatenate([[0.0], np.cumsum(scheme)]), color="#E69F00", lw=1.2,
                label="time scheme's loss (θ = 1 positions)")
    ax.set_ylabel("energy since t = 0 [J]")
    ax.set_title("Energy balance: drive work = change of K + P + losses", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    big = float(np.abs(cum["remainder"]).max(initial=0.0))
    e = int(np.floor(np.log10(big))) if big > 0 else 0
    # the power of ten goes in the label: matplotlib's offset text would sit on the title
    bx.plot(t, cum["remainder"] / 10.0 ** e, color="#CC79A7", lw=1.2)
    from matplotlib.ticker import MaxNLocator
    bx.yaxis.set_major_locator(MaxNLocator(4))
    bx.ticklabel_format(axis="y", useOffset=False)
    bx.set(xlabel="time [s]", ylabel="remainder [J]" if e == 0 else f"remainder [1e{e} J]")
    bx.set_title("numerical remainder (rounding and certificate residual)", fontsize=9)
    bx.grid(True, alpha=0.3)
    fig.tight_layout(h_pad=2.5)   # the panels' end tick labels otherwise touch
    return fig


# -- per-revolution figures (formulations.drum2d.revolutions, .stack) ----------------------

#: the two panels of the force figures: log–log, and the steel (shell and lifters)
_PANELS = (("log-log", "log–log contacts", "log_log_N"),
           ("log-steel", "log–shell and log–lifter contacts", "log_shell_N"))
_OKABE_ITO = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000")


def _window_colors(n: int) -> list:
    if n <= len(_OKABE_ITO):
        return list(_OKABE_ITO[:n])
    import matplotlib

    cmap = matplotlib.colormaps["viridis"]
    return [cmap(x) for x in np.linspace(0.0, 0.9, n)]


def _short(rev) -> str:
    """A window's tick label: "1", "2*" (partial), "run" (no rotation)."""
    w = rev.window
    return "run" if w.label == "whole run" else f"{w.index + 1}" + ("" if w.complete else "*")


def _per(revs) -> str:
    """ "per revolution", or "over the run" without rotation (one window)."""
    return "over the run" if revs[0].window.label == "whole run" else "per revolution"


def _statistics(h, estimate):
    from .revolutions import revolutions
    from .stack import stack_estimate_for_run

    return revolutions(h), (stack_estimate_for_run(h) if estimate is None else estimate)


def _legend_labels(revs, limit: int = 8):
    """Which windows get a legend entry: all up to ``limit``, else evenly spaced."""
    keep = set(np.linspace(0, len(revs) - 1, min(len(revs), limit)).round().astype(int))
    return [r.label if k in keep else None for k, r in enumerate(revs)]


def force_histogram_figure(h, estimate=None):
    """Per revolution, the histogram of the normal contact forces [N] (every
    active contact of every step counted once per step, bins of
    revolutions.FORCE_BINS, 10 a decade), log–log and log–shell (with the
    lifters) in separate panels, force on a log axis; the stack model's
    estimate (formulations.drum2d.stack; computed from the file unless
    ``estimate`` is given) as a vertical line in each panel."""
    from .records import FORCE_BINS

    plt = _pyplot()
    revs, est = _statistics(h, estimate)
    colors, labels = _window_colors(len(revs)), _legend_labels(revs)
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.8), sharey=True)
    most = 1.0
    for ax, (kind, title, attr) in zip(axes, _PANELS):
        bound = getattr(est, attr)
        lo, hi = np.inf, bound
        for rev, c, lab in zip(revs, colors, labels):
            counts = rev.forces[kind].counts.astype(float)
            nz = np.flatnonzero(counts)
            if nz.size:
                lo, hi = min(lo, FORCE_BINS[nz[0]]), max(hi, FORCE_BINS[nz[-1] + 1])
                most = max(most, counts.max())
            ax.stairs(np.where(counts > 0, counts, np.nan), FORCE_BINS, color=c, lw=1.5,
                      label=lab)
        ax.axvline(bound, color="0.15", ls="--", lw=1.4,
                   label=f"stack model estimate (not a bound) {bound / 1e3:.4g} kN")
        ax.set_xscale("log")
        ax.set_yscale("log")
        lo = lo if np.isfinite(lo) else bound / 1e3
        # a third of a decade beyond the outer decade ticks: their labels stay
        # inside the panel instead of meeting the next panel's in the gap
        ax.set_xlim(10.0 ** (np.floor(np.log10(lo)) - 0.35),
                    10.0 ** (np.ceil(np.log10(hi)) + 0.35))
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("normal contact force [N]")
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=7.5, loc="upper left", ncol=1 if len(revs) < 5 else 2)
    # log headroom above the highest bin: the legend sits there, off the data
    axes[0].set_ylim(0.6, most * 10 ** (1.2 + 0.1 * min(len(revs), 8)))
    axes[0].set_ylabel("contact-steps per bin [count]")
    # the same counts as a rate over a whole window (revolutions.KindForces:
    # impacts a second in the tail, whatever the step)
    span = max((r.window.t_end_s - r.window.t_start_s) / r.window.fraction for r in revs)
    if span > 0:
        right = axes[1].secondary_yaxis("right", functions=(lambda c: c / span,
                                                            lambda x: x * span))
        right.set_ylabel(f"per second over a whole window ({span:.3g} s) [1/s]")
    fig.suptitle(f"Contact-force histograms {_per(revs)} (10 bins a decade from "
                 f"{FORCE_BINS[0]:g} N)\n" + est.describe(),
                 fontsize=9.5)
    fig.tight_layout(w_pad=2.5)   # the panels' end tick labels otherwise touch
    return fig


def force_peak_figure(h, estimate=None):
    """The peak normal contact force [N] of each revolution, log–log and
    log–shell (with the lifters) side by side, with the 99 % quantile of each
    (histogram bin's upper edge) as a tick, and the stack model's
    estimates as horizontal lines (computed from the file unless
    ``estimate`` is given)."""
    plt = _pyplot()
    revs, est = _statistics(h, estimate)
    x = np.arange(len(revs))
    fig, ax = plt.subplots(figsize=(8.5, 5.0))
    width = 0.36
    colors = ("#0072B2", "#D55E00")
    ratio = []
    for off, (kind, title, attr), c in zip((-0.5, 0.5), _PANELS, colors):
        peaks = np.array([r.forces[kind].peak_N for r in revs])
        q99 = np.array([r.forces[kind].quantiles_N.get(0.99, np.nan) for r in revs])
        bound = getattr(est, attr)
        name = title.replace(" contacts", "")
        ax.bar(x + off * width, np.where(peaks > 0, peaks, np.nan), width, color=c, alpha=0.8,
               label=f"peak, {name}")
        ax.plot(x + off * width, np.where(q99 > 0, q99, np.nan), ls="none", marker="_",
                ms=14, mew=2.0, color="0.1")
        ax.axhline(bound, color=c, ls="--", lw=1.5,
                   label=f"stack estimate, {name}: {bound / 1e3:.4g} kN")
        ratio.append(f"{name} {peaks.max(initial=0.0) / bound:.1%}")
    ax.plot([], [], ls="none", marker="_", ms=14, mew=2.0, color="0.1",
            label="99 % quantile (bin's upper edge)")
    ax.set_yscale("log")
    ax.set_xticks(x, [_short(r) for r in revs])
    ax.set_xlim(-0.8, len(revs) - 0.2)
    lo = np.nanmin([r.forces[k].quantiles_N.get(0.99, np.nan) or np.nan for r in revs
                    for k, _, _ in _PANELS] + [est.log_log_N])
    ax.set_ylim(lo / 3.0, 8.0 * max(est.log_shell_N, est.log_log_N))
    ax.set_xlabel("revolution [-] (* partial)" if revs[0].window.label != "whole run"
                  else "window [-] (no rotation: the whole run)")
    ax.set_ylabel("normal contact force [N]")
    ax.set_title(f"Peak contact force {_per(revs)} and the stack model's estimate\n"
                 "largest 2-D peak / estimate: " + ", ".join(ratio), fontsize=9.5)
    ax.grid(True, axis="y", which="major", alpha=0.3)
    ax.legend(fontsize=8, loc="upper right", ncol=2)
    fig.tight_layout()
    return fig


def sliding_work_figure(h):
    """The sliding (friction) work charged to each log in each revolution
    [J], logs ranked from the most rubbed, one line per revolution; the
    legend gives each revolution's mean over the logs and its most rubbed
    log (index and work)."""
    from .revolutions import revolutions

    plt = _pyplot()
    revs = revolutions(h)
    colors, labels = _window_colors(len(revs)), _legend_labels(revs)
    fig, ax = plt.subplots(figsize=(8.5, 4.8))
    n = revs[0].sliding.per_log_J.size
    rank = np.arange(1, n + 1)
    for rev, c, lab in zip(revs, colors, labels):
        s = rev.sliding
        ax.step(rank, np.sort(s.per_log_J)[::-1], where="mid", color=c, lw=1.5,
                label=None if lab is None else
                f"{lab}: mean {s.mean_J:.3g} J, max {s.max_J:.3g} J (log {s.max_log})")
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlim(0.5, n + 0.5)
    ax.set_ylim(0.0, 1.25 * max(r.sliding.max_J for r in revs) or 1.0)
    ax.set_xlabel("logs, ranked from the most rubbed [rank]")
    ax.set_ylabel("sliding work per log and revolution [J]" if revs[0].window.label !=
                  "whole run" else "sliding work per log over the run [J]")
    named = "friction" in str(h.attrs.get("effects", ""))
    ax.set_title(f"Sliding work per log {_per(revs)} (friction work ∫|F_T||u_T|dt, half to each "
                 "log at log–log contacts)" + ("" if named else ": friction not simulated"),
                 fontsize=9.5)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    return fig
