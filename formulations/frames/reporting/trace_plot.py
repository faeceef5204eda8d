"""The trace's load-displacement curve: the load parameter p against one
displacement, each breakpoint numbered on the curve and its events listed
in a key beside it (31 events near a tower's tipping load cannot each carry
a sentence on the curve).  A number that would overprint another is left
off the curve; the key's p places it on the ordinate."""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidOptionError


from ..mechanics.loads import known_node
from .plane_drawing import sum_words
from .labels import Placer, around
from .notation import label

#: the key's lines are cut at this many characters (an event changing many supports)
_WIDTH = 58
_DPI = 110   # save_figure's: labels are placed at the resolution they print at


def plot_trace(frame, ft, path, node, dof, p_max):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure

    dofs = frame.DOFS           # (ux, uy, rz) in a plane frame, six in a space frame
    if dof not in dofs:
        raise InvalidOptionError(f"dof must be one of {dofs}; got {dof!r}")
    known_node(frame, node)
    k = dofs.index(dof)
    # never past the traced range nor a proved limit: a second-order trace
    # ended "stability" goes on through unstable pieces past it, where its
    # answers are solves at loads the frame does not carry (NoSolutionError)
    end = min(ft.p_end, ft.limit[1]) if ft.limit is not None else ft.p_end
    top = min(ft.trace.plot_range(), end)
    if p_max is not None:
        top = min(float(p_max), end)
    ps = np.unique(np.r_[0.0, ft.breakpoints[ft.breakpoints <= top], np.linspace(0, top, 60)])
    disp = np.array([ft.result_at(p).displacements[node][k] for p in ps])
    events = [ev for ev in ft.events if ev.p <= top]
    fig, (ax, key) = plt.subplots(1, 2, figsize=(11.5, 6.0), dpi=_DPI, layout="constrained",
                                  width_ratios=(1.5, 1.0))
    ax.plot(disp, ps, "k-", lw=1.2)
    at = [(ft.result_at(ev.p).displacements[node][k], ev.p) for ev in events]
    if at:
        ax.plot(*np.array(at).T, "o", color="tab:red", ms=3.5, zorder=3)
    unit = "rad" if dof.startswith("r") else frame.units[1]
    ax.set_xlabel(f"{dof} at {node} [{unit}]", fontsize=9)
    var = {c: f for c, f in ft.variable.items() if f}
    grows = sum_words(var) if len(var) == 1 and abs(next(iter(var.values()))) == 1 \
        else f"({sum_words(var)})"
    const = {c: f for c, f in ft.constant.items() if f}
    start = sum_words(const) + " + " if const else ""
    ax.set_ylabel(f"load parameter p [–]: {start}p × {grows}", fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.margins(x=0.08, y=0.05)
    ax.tick_params(labelsize=8)
    ended = ft.ended in ("collapse", "fold", "breakdown") and ft.p_end <= top
    if ended:
        ax.axhline(ft.p_end, color="tab:red", ls="--", lw=0.8)
    key.set_axis_off()
    bracket = (f"limit p in [{ft.limit[0]:.10g}, {ft.limit[1]:.10g}] (proved)"
               if ft.limit is not None else "")
    fig.suptitle(f"increasing load: {len(ft.breakpoints)} change(s) of the working scheme; "
                 f"ended: {ft.ended}" + (f" at p = {ft.p_end:.6g}" if ended else "")
                 + (f"\n{bracket}" if bracket else ""), fontsize=10)
    placer = Placer(fig)
    placer.freeze()
    if ended:
        placer.label(ax, ft.ended + (f": {bracket}" if bracket else ""), (0.01, ft.p_end),
                     [(2, 2, "left", "bottom"),
                     (2, -2, "left", "top")], xycoords=("axes fraction", "data"), fontsize=8,
                     color="tab:red")
    for a, b in zip(np.c_[disp, ps][:-1], np.c_[disp, ps][1:]):
        placer.keep_clear(ax, a, b, half=1.0)   # numbers beside the curve, not on it
    screen = ax.transData.transform(np.c_[disp, ps])
    on_curve = 0
    for n, (d, p) in enumerate(at, start=1):
        k = min(int(np.searchsorted(ps, p)), len(ps) - 1)
        t = screen[min(k + 1, len(ps) - 1)] - screen[max(k - 1, 0)]
        normal = (-t[1], t[0])   # to the upper left of a rising curve first
        spots = [o for dist in (4.0, 8.0, 14.0) for o in around(normal, dist)]
        if placer.label(ax, str(n), (d, p), spots, fontsize=7, color="tab:red"):
            on_curve += 1
    _key(fig, key, placer, events, len(ft.events) - len(events), top, on_curve)
    return save_figure(fig, path)


def _key(fig, key, placer, events, beyond, top, on_curve):
    """The events, one line each, as many as the key's height holds at a
    legible size; the rest counted."""
    if not events:
        key.text(0.0, 1.0, "no support changes state in this range", va="top", fontsize=8,
                 transform=key.transAxes)
        return
    ref = max(abs(ev.p) for ev in events)
    lines = []
    for n, ev in enumerate(events, start=1):
        text = f"{n:>3}  p = {label(ev.p, '', ref, digits=5)}   {ev}"
        lines.append(text if len(text) <= _WIDTH else text[:_WIDTH - 1] + "…")
    head = "breakpoints, numbered on the curve" + (
        f"\n({len(events) - on_curve} left off it where they would overprint)"
        if on_curve < len(events) else "") + (
        f"\n({beyond} more beyond the plotted range, p > {top:.5g})" if beyond else "")
    height = key.bbox.height * 72.0 / fig.dpi
    for size in (7.5, 7.0, 6.5, 6.0):
        rows = int((height - 2.5 * size) / (1.25 * size))
        if rows >= len(lines) or size == 6.0:
            break
    shown = lines if rows >= len(lines) else lines[:rows - 1] + [
        f"     … and {len(lines) - rows + 1} more (FrameTrace.events)"]
    text = key.text(0.0, 1.0, head + "\n" + "\n".join(shown), va="top", ha="left",
                    fontsize=size, family="monospace", linespacing=1.25,
                    transform=key.transAxes)
    placer.block(text)
