"""Where text and arrows go on a frame drawing, judged on the rendered figure.

A label is tried at a few offsets around its anchor (in points, so the gap
does not depend on the drawing's scale), its box measured by the renderer
(``Text.get_window_extent``) and kept only where it overlaps no box already
taken and stays inside its axes; labels are placed in the caller's order of
importance, so on a crowded drawing the largest values are the ones shown.
Arrows are thinned the same way.  Everything here works in display pixels
of a figure whose layout is final: call :meth:`Placer.freeze` first.
"""

from __future__ import annotations

import math
import re

import numpy as np

from .notation import label

#: clearance between two labels' boxes, in points
GAP = 1.5


def nice(value: float) -> float:
    """The round number (1, 2 or 5 x 10^k) at or below ``value``."""
    if value <= 0 or not np.isfinite(value):
        return 1.0
    k = math.floor(math.log10(value))
    for m in (5.0, 2.0, 1.0):
        if m * 10.0 ** k <= value:
            return m * 10.0 ** k
    return 10.0 ** k


def value_text(value: float, unit: str = "", ref: float | None = None) -> str:
    """notation.label without trailing zeros (30 kN/m, not 30.0 kN/m): on a
    drawing the digits shown are a reading, not a stated precision."""
    text = label(value, unit, ref)
    return re.sub(r"^(-?\d+)(?:\.0+|(\.\d*?)0+)(?=$|×|\u2009)", r"\1\2", text)


def around(direction=(0.0, 1.0), distance: float = 2.0) -> list:
    """Offsets (dx, dy, ha, va) in points for a label beside its anchor: the
    eight compass positions, the one nearest ``direction`` first."""
    want = math.atan2(direction[1], direction[0])
    out = []
    for k in range(8):
        ang = k * math.pi / 4
        dx, dy = math.cos(ang), math.sin(ang)
        ha = "left" if dx > 0.3 else "right" if dx < -0.3 else "center"
        va = "bottom" if dy > 0.3 else "top" if dy < -0.3 else "center"
        turn = abs((ang - want + math.pi) % (2 * math.pi) - math.pi)
        out.append((turn, (distance * dx, distance * dy, ha, va)))
    return [o for _, o in sorted(out, key=lambda t: t[0])]


class Placer:
    """What is taken on one figure, in display pixels: text boxes and arrow
    shafts (segments with a half-width), and the renderer that measures."""

    def __init__(self, fig):
        self.fig = fig
        self.boxes = np.empty((0, 4))      # x0, y0, x1, y1
        self.shafts = np.empty((0, 5))     # x0, y0, x1, y1, half-width
        self.groups: list = []             # which set of arrows each shaft thins
        self.renderer = None

    def freeze(self) -> None:
        """Lay the figure out once and keep it: the axes' positions and limits
        stop moving, so a box measured now is where the text will print."""
        self.fig.canvas.draw()
        self.fig.set_layout_engine("none")
        for ax in self.fig.axes:
            ax.set_autoscale_on(False)
            ax.set_xlim(ax.get_xlim())
            ax.set_ylim(ax.get_ylim())
            if ax.get_aspect() != "auto":
                # the limits now fit the box: a later line must not move them
                ax.set_adjustable("box")
        self.renderer = self.fig.canvas.get_renderer()

    def px(self, points: float) -> float:
        return points * self.fig.dpi / 72.0

    def block(self, artist) -> None:
        """An artist already drawn (a scale bar, a key) that labels keep clear of."""
        self.boxes = np.vstack([self.boxes, artist.get_window_extent(self.renderer).extents])

    def _free(self, box, ax) -> bool:
        """Inside the axes and clear (by GAP) of every text box and arrow shaft."""
        inside = ax.bbox
        if (box[0] < inside.x0 or box[2] > inside.x1 or box[1] < inside.y0
                or box[3] > inside.y1):
            return False
        g, b = self.px(GAP), self.boxes
        if np.any((b[:, 0] < box[2] + g) & (b[:, 2] > box[0] - g) & (b[:, 1] < box[3] + g)
                  & (b[:, 3] > box[1] - g)):
            return False
        return not np.any(_crosses(self.shafts, box, g))

    def label(self, ax, text: str, xy, offsets, **style):
        """Annotate ``text`` at ``xy`` (data coordinates unless ``xycoords=``
        says otherwise) at the first offset (dx, dy, ha, va; points) where it
        fits; None (nothing drawn) where none does.  The text's size is
        measured once by the renderer; each offset moves that box."""
        style.setdefault("zorder", 10)   # over the members and support markers
        ann = ax.annotate(text, xy, xytext=(0, 0), textcoords="offset points",
                          annotation_clip=False, ha="left", va="bottom", **style)
        box = ann.get_window_extent(self.renderer)
        w, h = box.width, box.height
        shift = {"left": 0.0, "center": 0.5, "right": 1.0, "bottom": 0.0, "top": 1.0}
        for dx, dy, ha, va in offsets:
            x0 = box.x0 + self.px(dx) - shift[ha] * w
            y0 = box.y0 + self.px(dy) - shift[va] * h
            cand = (x0, y0, x0 + w, y0 + h)
            if self._free(cand, ax):
                ann.xyann = (dx, dy)
                ann.set_horizontalalignment(ha)
                ann.set_verticalalignment(va)
                self.boxes = np.vstack([self.boxes, cand])
                return ann
        ann.remove()
        return None

    def note(self, ax, text: str, fontsize: float, **style):
        """A remark on the panel, in the first corner where it fits."""
        for corner, ha, va in (((0.01, 0.01), "left", "bottom"), ((0.99, 0.01), "right", "bottom"),
                               ((0.01, 0.99), "left", "top"), ((0.99, 0.99), "right", "top")):
            if self.label(ax, text, corner, [(0, 0, ha, va)], xycoords="axes fraction",
                          fontsize=fontsize, color="0.3", **style):
                return

    def arrow(self, ax, tip, direction, length: float, back: float = 0.0, group="", **style):
        """An arrow pointing along ``direction`` (display orientation) whose
        tip sits ``back`` points short of the data point ``tip``; ``length`` in
        points.  Drawn only inside the axes and 4 points off the arrows of its
        ``group`` (loads from above do not thin the reactions from below):
        returns the tail (data coordinates) or None."""
        d = np.asarray(direction, float)
        d = d / max(np.hypot(*d), 1e-300)
        p = ax.transData.transform(tip)
        head = p - d * self.px(back)
        tail = head - d * self.px(length)
        inside = ax.bbox
        if not all(inside.x0 <= x <= inside.x1 and inside.y0 <= y <= inside.y1
                   for x, y in (head, tail)):
            return None
        mine = self.shafts[np.array(self.groups, object) == group] if self.groups else self.shafts
        if len(mine) and _distance(mine, head, tail).min() < self.px(4.0):
            return None
        self._shaft(head, tail, 2.5, group)
        inv = ax.transData.inverted()
        tail_xy, head_xy = inv.transform(tail), inv.transform(head)
        ax.annotate("", head_xy, xytext=tail_xy, textcoords="data", annotation_clip=False,
                    arrowprops=dict(arrowstyle="-|>", shrinkA=0, shrinkB=0,
                                    mutation_scale=8, **style))
        return tail_xy

    def keep_clear(self, ax, a, b, half: float = 1.5) -> None:
        """Labels keep off the segment a-b (data points), e.g. an arrow drawn unthinned."""
        self._shaft(ax.transData.transform(a), ax.transData.transform(b), half, None)

    def _shaft(self, p, q, half, group):
        self.shafts = np.vstack([self.shafts, [*p, *q, self.px(half)]])
        self.groups.append(group)

    def offset(self, ax, xy, direction, points: float):
        """The data point ``points`` away from ``xy`` along a display direction."""
        d = np.asarray(direction, float)
        d = d / max(np.hypot(*d), 1e-300)
        p = ax.transData.transform(xy) + d * self.px(points)
        return ax.transData.inverted().transform(p)


def _crosses(shafts, box, gap):
    """Which shafts pass through the box grown by their half-width and ``gap``
    (Liang-Barsky clipping of each segment against the rectangle)."""
    if not len(shafts):
        return np.zeros(0, bool)
    px, py, qx, qy, hw = shafts.T
    x0, y0, x1, y1 = box[0] - hw - gap, box[1] - hw - gap, box[2] + hw + gap, box[3] + hw + gap
    dx, dy = qx - px, qy - py
    t0, t1 = np.zeros(len(px)), np.ones(len(px))
    ok = np.ones(len(px), bool)
    for p, q in ((-dx, px - x0), (dx, x1 - px), (-dy, py - y0), (dy, y1 - py)):
        flat = p == 0
        ok &= ~(flat & (q < 0))
        with np.errstate(divide="ignore", invalid="ignore"):
            r = np.where(flat, 0.0, q / np.where(flat, 1.0, p))
        t0 = np.where(~flat & (p < 0), np.maximum(t0, r), t0)
        t1 = np.where(~flat & (p > 0), np.minimum(t1, r), t1)
    return ok & (t0 <= t1)


def _distance(shafts, a, b):
    """Distance from each shaft to the segment a-b, less the shaft's half-width
    (sampled along a-b: arrows are short)."""
    p, q = shafts[:, None, 0:2], shafts[:, None, 2:4]
    pts = a + np.linspace(0.0, 1.0, 7)[:, None] * (b - a)        # (7, 2)
    d = q - p
    t = np.clip(np.sum((pts[None] - p) * d, axis=2) / np.maximum(np.sum(d * d, axis=2), 1e-12),
                0.0, 1.0)
    near = p + t[..., None] * d
    return np.hypot(*(pts[None] - near).transpose(2, 0, 1)).min(axis=1) - shafts[:, 4]
