"""What the drawing and table tests share: the figure a plot call draws,
the one rule for overprinting (two texts overlap when their rendered boxes
intersect; each test picks which texts count), the check that a failed
write leaves the previous file whole, the tables' rounding rule written
out by hand, and the read-back of a result's CSV tables."""

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


def csv_reads_back(result, paths, *, nan: bool = False, floor: float | None = None) -> None:
    """Each CSV file of ``paths`` (``result.to_csv``) holds its table
    ``result.rows(name)``: the same header and rows, every float read back
    equal to the row's (rounded) value, written without a minus zero or an
    exponent; with ``nan`` a NaN is written "nan", with ``floor`` a nonzero
    value is at least that large."""
    import csv
    import math
    import re

    for path in paths:
        table = str(path).split("/")[-1][:-4]
        rows = result.rows(table)
        with open(path, newline="") as fh:
            reader = csv.DictReader(fh)
            assert reader.fieldnames == list(rows[0])
            back = list(reader)
        assert len(back) == len(rows)
        for text_row, row in zip(back, rows):
            for key, value in row.items():
                text = text_row[key]
                if not isinstance(value, float):
                    assert text == str(value)
                    continue
                if nan and math.isnan(value):
                    assert text == "nan"
                    continue
                assert float(text) == value, (table, key, text, value)
                assert not re.fullmatch(r"-0(\.0*)?", text), (table, key, text)
                assert "e" not in text.lower(), (table, key, text)
                if floor is not None:
                    assert text == "0" or abs(value) >= floor, (table, key, text)


def rounded_by_hand(rows, unit, size, digits=5):
    """docs/frames.md's rule, written out: in the float columns whose header
    ends in a unit ``unit`` matches (group 1 the unit), a value within 1e-9 of
    its unit's scale (the table's largest in that unit; a moment's at least
    the force scale x the frame's ``size``, a rotation's at least the length
    scale over it) is 0; each column keeps the decimals that give its
    largest remaining value ``digits`` significant digits; NaN stays NaN."""
    import math

    cols = [k for k in rows[0] if unit.search(k) and all(isinstance(r[k], float) for r in rows)]
    scale: dict = {}
    for k in cols:
        u = unit.search(k).group(1)
        scale[u] = max([scale.get(u, 0.0)] + [abs(r[k]) for r in rows if not math.isnan(r[k])])
    if "kN·m" in scale:
        scale["kN·m"] = max(scale["kN·m"], scale.get("kN", 0.0) * size)
    if "rad" in scale:
        scale["rad"] = max(scale["rad"], scale.get("m", 0.0) / size)
    out = [dict(r) for r in rows]
    for k in cols:
        s = scale[unit.search(k).group(1)]
        vals = [r[k] if math.isnan(r[k]) or abs(r[k]) > 1e-9 * s else 0.0 for r in rows]
        big = max([abs(v) for v in vals if not math.isnan(v)] + [0.0])
        d = max(0, digits - 1 - math.floor(math.log10(big))) if big else 0
        for r, v in zip(out, vals):
            r[k] = v if math.isnan(v) else float(f"{v:.{d}f}") + 0.0   # + 0.0: "-0.000" is 0
    return out
