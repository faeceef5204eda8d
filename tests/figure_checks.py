"""What the drawing and table tests share: the figure a plot call draws,
the one rule for overprinting (two texts overlap when their rendered boxes
intersect; each test picks which texts count), and the check that a failed
write leaves the previous file whole."""

from __future__ import annotations

import numpy as np
import pytest

import qpcontact.core.files
import qpcontact.plots.figures


def drawn(plot, *args, **kwargs):
    """The figure a plot call would save (the save replaced by a capture),
    drawn."""
    figs = []
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(qpcontact.plots.figures, "save_figure",
                   lambda fig, path, dpi=110: figs.append(fig) or str(path))
        plot("unused.png", *args, **kwargs)
    figs[0].canvas.draw()
    return figs[0]


def keeps_previous_file(write, path) -> bool:
    """Whether ``write()``, failing before its rename (a full disk), leaves
    the file at ``path`` as it was (the tables' atomic writes)."""
    before = path.read_text()

    def fail(*args):
        raise OSError("disk full")

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(qpcontact.core.files.os, "replace", fail)
        with pytest.raises(OSError, match="disk full"):
            write()
    return path.read_text() == before


def overlapping(fig, texts) -> list:
    """Pairs (text, text) of ``texts`` whose boxes, as ``fig`` renders them,
    intersect."""
    if not texts:
        return []
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    boxes = np.array([t.get_window_extent(renderer).extents for t in texts])
    x0, y0, x1, y1 = boxes.T
    hit = ((x0[:, None] < x1[None]) & (x1[:, None] > x0[None])
           & (y0[:, None] < y1[None]) & (y1[:, None] > y0[None]))
    np.fill_diagonal(hit, False)
    return [(texts[i].get_text(), texts[j].get_text()) for i, j in zip(*np.nonzero(np.triu(hit)))]


def figure_texts(fig, in_view: bool = False) -> list:
    """Every non-empty text of ``fig``: its own, each axes' title, labels,
    visible tick labels and legend entries; with ``in_view`` only the tick
    labels of ticks inside the axes' limits (matplotlib lists the others as
    visible but never draws them)."""
    out = list(fig.texts)
    for ax in fig.axes:
        out += [ax.title, ax.xaxis.label, ax.yaxis.label]
        for axis, (lo, hi) in ((ax.xaxis, sorted(ax.get_xlim())),
                               (ax.yaxis, sorted(ax.get_ylim()))):
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                if not in_view or lo <= tick.get_loc() <= hi:
                    out += [t for t in (tick.label1, tick.label2) if t.get_visible()]
        if ax.get_legend():
            out += list(ax.get_legend().get_texts())
    return [t for t in out if t.get_text()]
