"""A space frame's plan: one panel per level.

Looked at from above (elevation 90°), every storey of a frame lies on the
one below it — the beams of the roof over the pads, a column's top over its
foot — and a single orthographic view overprints them.  The plan draws
each level (the nodes at one height z, to a millionth of the frame's size)
in a panel of its own, x to the right and y up, at one magnification for
all of them: the members lying in the level (undeformed grey, deformed
black, each bent by its exact deflection), the nodes where members leave
the level (columns: a grey circle), the contacts by state with their
forces, the slip directions, the supports and springs, and the level's
loads (vertical ones as ⊙/⊗).  The drawing itself is
:mod:`.space_drawing`'s, given only what lies in the level.
"""

from __future__ import annotations

import copy
import math
from types import SimpleNamespace

import numpy as np

from .labels import Placer, value_text
from .plane_drawing import combination_title
from .space_drawing import (SpaceView, contact_labels, draw_frame, draw_space_loads,
                            legend_handles, peak_label, slip_arrows, triad)

#: the plan's view: from above, x to the right and y up
PLAN = (-90.0, 90.0)
_FONT = 7.5
_DPI = 110   # save_figure's: labels are placed at the resolution they print at
_BOX = dict(boxstyle="square,pad=0.05", fc="white", ec="none", alpha=0.8)


def levels(frame) -> list:
    """The heights z of the frame's levels, lowest first (nodes within a
    millionth of the frame's size of each other share one)."""
    z = np.sort(np.array([float(v[2]) for v in frame.nodes.values()]))
    pts = np.array(list(frame.nodes.values()), float)
    tol = 1e-6 * max(float(np.linalg.norm(np.ptp(pts, axis=0))), 1e-12)
    out = [z[0]]
    for v in z[1:]:
        if v - out[-1] > tol:
            out.append(v)
    return out


def level_view(view, z, tol):
    """The view restricted to the level at height z: its members, contacts,
    supports, springs and loads (the magnification the whole frame's)."""
    frame, res = view.frame, view.res
    at = {n for n, v in frame.nodes.items() if abs(float(v[2]) - z) <= tol}
    members = {k: m for k, m in frame.members.items() if m["i"] in at and m["j"] in at}
    keep = [k for k, c in enumerate(frame.contacts) if c.node in at]
    keys = list(res.supports)
    sub = copy.copy(view)
    sub.frame = SimpleNamespace(
        nodes=frame.nodes, units=frame.units, members=members,
        contacts=[frame.contacts[k] for k in keep],
        fixed={n: d for n, d in frame.fixed.items() if n in at},
        springs={n: d for n, d in frame.springs.items() if n in at},
        nodal_loads=[ld for ld in frame.nodal_loads if ld[0] in at],
        member_loads=[ld for ld in frame.member_loads if ld[0] in members],
        span_loads=[ld for ld in frame.span_loads if ld.member in members])
    sub.res = SimpleNamespace(supports={keys[k]: res.supports[keys[k]] for k in keep},
                              displacements=res.displacements, combination=res.combination)
    sub.curves = {k: c for k, c in view.curves.items() if k in members}
    moved = {n: float(np.hypot(*res.displacements[n][:2])) for n in at}
    sub.peak_node = max(moved, key=moved.get)
    sub.umax = view.umax if moved[sub.peak_node] > 0 else 0.0
    # nodes where a member leaves the level: the columns
    sub.columns = sorted({n for m in frame.members.values() for n in (m["i"], m["j"])
                          if n in at and not (m["i"] in at and m["j"] in at)})
    sub.nodes_here = at
    return sub


def plot_plan(frame, res, path, scale=None, title=None, loads=True) -> str:
    """Draw the plan of ``res``, one panel per level (the module docstring)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure

    view = SpaceView(frame, res, scale, *PLAN)
    zs = levels(frame)
    tol = 1e-6 * view.size
    subs = [level_view(view, z, tol) for z in zs]
    cols = min(len(zs), 3)
    rows = math.ceil(len(zs) / cols)
    pts = np.array(list(frame.nodes.values()), float)[:, :2]
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = np.maximum(hi - lo, 1e-3 * view.size)
    grow = 0.18 * span.max()
    panel = 11.0 / cols
    height = min(max(panel * (span[1] + 2 * grow) / (span[0] + 2 * grow), 2.5), 8.0)
    fig, axes = plt.subplots(rows, cols, figsize=(11.0, height * rows + 1.4), dpi=_DPI,
                             layout="constrained", squeeze=False)
    axes = list(axes.ravel())
    F, L = frame.units
    for ax, sub, z in zip(axes, subs, zs):
        ax.update_datalim([lo - grow, hi + grow])
        ax.margins(0.0)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xticks([])
        ax.set_yticks([])
        for side in ax.spines.values():
            side.set_color("0.8")
        if sub.columns:
            xy = np.array([sub.at(n) for n in sub.columns])
            ax.plot(xy[:, 0], xy[:, 1], "o", ms=9, mfc="none", mec="0.55", mew=1.0, zorder=3)
        nm, nc = len(sub.frame.members), len(sub.frame.contacts)
        ax.set_title(f"level z = {value_text(z, L, view.size)}: {nm} member"
                     f"{'s' * (nm != 1)}, {nc} contact{'s' * (nc != 1)}", fontsize=9)
    for ax in axes[len(zs):]:
        ax.set_axis_off()
    handles = legend_handles(view, loads)
    if any(s.columns for s in subs):
        from matplotlib.lines import Line2D
        handles.append(Line2D([], [], marker="o", ls="none", ms=9, mfc="none", mec="0.55",
                              label="member leaving the level (column)"))
    fig.legend(handles=handles, loc="outside lower center",
               ncols=len(handles) if len(handles) <= 6 else math.ceil(len(handles) / 2),
               fontsize=7.5, frameon=False)
    fig.suptitle((title or combination_title(res))
                 + f"\nplan, one panel per level (x right, y up); displacements × "
                   f"{view.scale:.3g}", fontsize=10)
    markers = [draw_frame(ax, sub) for ax, sub in zip(axes, subs)]
    placer = Placer(fig)
    placer.freeze()
    shown = total = 0
    for k, (ax, sub) in enumerate(zip(axes, subs)):
        for marker in markers[k]:
            placer.block(marker)
        if k == 0:
            triad(ax, placer, view)     # the whole frame in plan: where it leaves room
        slip_arrows(ax, placer, sub)
        shown += contact_labels(ax, placer, sub)
        total += len(sub.res.supports)
        if loads:
            draw_space_loads(ax, placer, sub)
        if sub.umax > 0:
            peak_label(ax, placer, sub)
    if shown < total:
        placer.note(axes[0], f"{shown} of {total} contacts labelled (the rest overprint; all: "
                    "res.rows('supports'))", _FONT, bbox=_BOX)
    return save_figure(fig, path)

