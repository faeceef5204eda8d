"""The work-precision plot of ``qpcontact compare``: per method, certificate
error against time at the accuracy ladder's levels and along a tolerance
sweep; one colour and marker per method, exact zeros in a labelled band."""

from __future__ import annotations

import math

from .figures import save_figure
from .style import draw_zero_band, ink, method_styles, readable_log_ticks, zero_band_position

__all__ = ["plot_work_precision", "work_precision_figure", "LEVEL_FILL"]

#: The ladder's levels by how full the method's marker is: more ink, more accuracy.
LEVEL_FILL = {"low": "none", "default": "bottom", "high": "full"}


def plot_work_precision(points: dict, path, title: str, **kw) -> str:
    """Save :func:`work_precision_figure` at ``path``; returns the path."""
    return save_figure(work_precision_figure(points, title, **kw), path)


def work_precision_figure(points: dict, title: str, styles: dict | None = None,
                          target: float | None = None, target_label: str = "",
                          sweep_range: str = ""):
    """A work-precision plot (a matplotlib Figure, left open).

    ``points``: {method: {"levels": {level: (time [s], error)}, "sweep":
    [(time [s], error), ...]}}, the levels among ``LEVEL_FILL``'s, errors
    dimensionless and >= 0 (0: exact, drawn in the "exact (0)" band).
    ``styles``: {method: (colour, marker)} (default: :func:`method_styles`
    of the methods in order).  ``target``: a dashed line at that error,
    named ``target_label`` in the key.  ``sweep_range``: how the legend names the
    tolerances of the sweep lines, e.g. "1e-2 … 1e-12"."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    styles = styles or method_styles(points)
    every = [p for m in points.values() for p in list(m.get("levels", {}).values()) + m.get("sweep", [])]
    errors = [e for _, e in every if math.isfinite(e)]
    has_zero = any(e == 0 for e in errors)
    y0 = zero_band_position(errors + ([target] if target else []))

    def y(e):
        return y0 if e == 0 else e

    fig, ax = plt.subplots(figsize=(9.5, 5.5))
    # fixed margins, not tight_layout: the ticks below are thinned for this geometry
    fig.subplots_adjust(left=0.1, right=0.74, bottom=0.11, top=0.93)
    ax.set_xscale("log")
    ax.set_yscale("log")
    for m, data in points.items():
        colour, marker = styles[m]
        sweep = data.get("sweep", [])
        if sweep:
            ax.plot([1e3 * t for t, _ in sweep], [y(e) for _, e in sweep], "-", color=ink(colour),
                    lw=1.1, alpha=0.75)
        for level, (t, e) in data.get("levels", {}).items():
            ax.plot(1e3 * t, y(e), marker, color=colour, mec=ink(colour), mfc=colour,
                    fillstyle=LEVEL_FILL[level], ms=7, mew=1.3, ls="none", gid=f"{m} @ {level}")
    if target:
        ax.axhline(target, color="0.4", ls="--", lw=0.8)
    times = [1e3 * t for t, _ in every if t > 0 and math.isfinite(t)] or [1.0]
    ax.set_xlim(min(times) / 1.6, max(times) * 1.6)
    tops = [y(e) for e in errors] + ([target] if target else [])
    band_top = y0 * 10 ** 0.5
    ax.set_ylim(band_top if has_zero else min(tops) / 3, max(tops) * 5)
    ax.set_xlabel("median wall time over the instances [ms]")
    ax.set_ylabel("median certificate error [dimensionless]")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="major", alpha=0.3)
    readable_log_ticks(ax, "x", plain=True)
    readable_log_ticks(ax, "y", plain=False, pad_px=8.0)   # a decade a line is hard to read
    if has_zero:
        draw_zero_band(ax, y0)

    methods = [Line2D([], [], color=ink(styles[m][0]), mfc=styles[m][0], marker=styles[m][1],
                      ls="-" if points[m].get("sweep") else "none", lw=1.1, ms=7, label=m)
               for m in points]
    key = [Line2D([], [], color="0.3", marker="o", fillstyle=f, ls="none", ms=7, mew=1.3,
                  label=f"accuracy '{lv}'") for lv, f in LEVEL_FILL.items()]
    if any(m.get("sweep") for m in points.values()):
        key.append(Line2D([], [], color="0.3", lw=1.1, label="tolerance sweep"
                          + (f" {sweep_range}" if sweep_range else "")))
    if target:
        key.append(Line2D([], [], color="0.4", ls="--", lw=0.8, label=target_label or f"error {target:g}"))
    if has_zero:
        key.append(Line2D([], [], color="0.92", lw=8, label="exact (0): error exactly zero"))
    first = ax.legend(handles=methods, title="method", fontsize=7.5, title_fontsize=8,
                      loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.add_artist(first)
    ax.legend(handles=key, fontsize=7.5, loc="lower left", bbox_to_anchor=(1.01, 0.0),
              borderaxespad=0.0)
    return fig
