"""The load-displacement plot of a load trace."""

from __future__ import annotations

import numpy as np

from .figures import save_figure

__all__ = ["plot_trace"]


def plot_trace(trace, path, indices=None, labels=None, p_max: float | None = None) -> str:
    """Save a load-displacement plot of a :class:`~qpcontact.solvers.trace.result.LoadTrace`:
    z_i against p for the chosen indices (default: every z that is ever
    positive, at most 12), breakpoints marked and labelled with their events.
    The plot ends at ``p_max``, by default at ``trace.plot_range()``.  Written
    atomically; returns the path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    top = trace.plot_range() if p_max is None else min(float(p_max), trace.traced_top())
    ps = [0.0]
    for pc in trace.pieces:
        end = min(pc.p_end, top)
        if end > pc.p_start:
            ps += list(np.linspace(pc.p_start, end, 3)[1:])
    zs = np.array([trace.z_at(p) for p in ps]) if trace.pieces else np.zeros((1, trace.z.size))
    if indices is None:
        indices = np.flatnonzero(zs.max(axis=0) > 0)[:12]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for k, i in enumerate(indices):
        ax.plot(ps, zs[:, i], label=labels[k] if labels else f"z[{i}]")
    for ev in trace.events:
        if ev.p <= top:
            ax.axvline(ev.p, color="0.7", lw=0.8, ls="--")
            ax.annotate(ev.describe(), (ev.p, ax.get_ylim()[1]), rotation=90, fontsize=7,
                        va="top", ha="right", color="0.4")
    ax.set_xlabel("load parameter p")
    ax.set_ylabel("z (contact forces or gaps, the LCP's units)")
    ax.set_title(f"load trace: {len(trace.breakpoints)} breakpoint(s), end: {trace.end}")
    ax.grid(True, alpha=0.3)
    if len(indices):
        ax.legend(fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path)
