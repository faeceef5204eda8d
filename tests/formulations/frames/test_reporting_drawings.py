"""Drawings that read at 20 storeys and 200 spans, judged on the
rendered figure: every text box measured by the renderer and none
overprinting another, every axis labelled with a unit, a scale bar on each
frame diagram, loads and reactions with their values, the user's names in
the title; unknown diagrams and results that are not ok refused."""

from __future__ import annotations

import dataclasses
import re

import matplotlib
import numpy as np
import pytest

from tests.helpers.figures import drawn, overlapping

from formulations.frames import Frame
from qpcontact.core.errors import InvalidOptionError, SolverFailedError

from .frame_cases import beam_on_supports, three_bay_tower

matplotlib.use("Agg")


def _texts(fig):
    """Every text drawn: tick labels only where their tick is inside the axis
    (matplotlib keeps Text objects for ticks beyond the limits, unprinted)."""
    from matplotlib.text import Text

    ticks, shown = set(), []
    for ax in fig.axes:
        for labels, k, (lo, hi) in ((ax.get_xticklabels(), 0, sorted(ax.get_xlim())),
                                    (ax.get_yticklabels(), 1, sorted(ax.get_ylim()))):
            ticks.update(labels)
            shown += [t for t in labels if lo <= t.get_position()[k] <= hi]
    return [t for t in [t for t in fig.findobj(Text) if t not in ticks] + shown
            if t.get_visible() and t.get_text().strip()]


def _overlaps(fig):
    return overlapping(fig, _texts(fig))


def _axes_have_units(fig):
    for ax in fig.axes:
        if not ax.axison:
            continue
        for text in (ax.get_xlabel(), ax.get_ylabel()):
            assert re.search(r"\[[^\]]+\]", text), f"axis label without a unit: {text!r}"


@pytest.fixture(scope="module")
def tower():
    fr, _ = three_bay_tower()
    res = fr.solve(10.0)
    assert res.ok
    return fr, res


@pytest.fixture(scope="module")
def tower_drawing(tower):
    return drawn(tower[1].plot)


@pytest.fixture(scope="module")
def beam_drawing():
    res = beam_on_supports(200).solve(50.0)
    assert res.ok
    return drawn(res.plot, diagrams=("deflection", "M", "V"))


def test_tower_drawing_labels_do_not_overprint(tower_drawing):
    assert len(_texts(tower_drawing)) > 100      # the labels are there, not dropped wholesale
    assert _overlaps(tower_drawing) == []
    _axes_have_units(tower_drawing)


def test_tower_moments_label_each_storey_and_level_once_at_a_readable_size(tower_drawing, tower):
    """The 20-storey tower labels where it matters: the largest |M| of each
    storey's columns and of each level's beams, at 8 pt (before: 248 of 307
    end and span values at 6.5 pt).  The groups and their largest moments
    are found here from the frame's geometry and res.extremes."""
    fr, res = tower
    moment = tower_drawing.axes[1]
    values = [t for t in moment.texts if t.get_gid() != "scale bar label"
              and re.fullmatch(r"-?[\d.]+", t.get_text())]
    assert values and min(t.get_fontsize() for t in values) >= 8.0
    groups = {}
    for name, m in fr.members.items():
        (xi, yi), (xj, yj) = fr.nodes[m.i], fr.nodes[m.j]
        kind = "column" if abs(yj - yi) > abs(xj - xi) else "beam"
        ext = res.extremes(name)["M"]
        peak = max((abs(v), v) for v, _ in ext.values())
        key = (kind, round((yi + yj) / 2, 6))
        groups[key] = max(groups.get(key, (0.0, 0.0)), peak)
    assert len(values) == len(groups) == 41          # 20 storeys, 20 levels, the foundation
    expected = sorted(v for _, v in groups.values())
    shown = sorted(float(t.get_text()) for t in values)
    np.testing.assert_allclose(shown, expected, rtol=5e-3)
    assert "the largest |M| of each storey's columns" in moment.get_title()


def test_tower_drawing_has_scale_bars_loads_reactions_and_the_users_words(tower_drawing):
    deflection, moment = tower_drawing.axes
    bars = [ln for ln in moment.lines if ln.get_gid() == "scale bar"]
    labels = [t.get_text() for t in moment.texts if t.get_gid() == "scale bar label"]
    assert len(bars) == 1 and len(labels) == 1 and labels[0].endswith("kN·m")
    assert any(ln.get_gid() == "scale bar" for ln in deflection.lines)
    words = [t.get_text() for t in deflection.texts]
    assert sum(w == "100\u2009kN" for w in words) >= 10         # the floor loads, p x 10 kN
    assert "30\u2009kN/m" in words                              # the beams' load, one per floor
    assert sum(w.endswith("kN") and w.startswith("(") for w in words) >= 5   # reactions
    assert tower_drawing._suptitle.get_text() == "p = 10 (constant + 10 × variable)"
    legend = [t.get_text() for t in tower_drawing.legends[0].get_texts()]
    assert "separated (8)" in legend and "stick (8)" in legend
    assert not any("e+" in t.get_text() or "e-0" in t.get_text() for t in _texts(tower_drawing))


def test_tower_moments_are_readable_not_flattened_by_the_foundation(tower_drawing, tower):
    """A typical column's diagram spans a visible part of its bay: the scale
    follows the members' peaks, not only the foundation beam's."""
    fr, res = tower
    moment = tower_drawing.axes[1]
    bar = next(ln for ln in moment.lines if ln.get_gid() == "scale bar")
    value = float(next(t.get_text() for t in moment.texts
                       if t.get_gid() == "scale bar label").split("\u2009")[0])
    per_unit = np.ptp(bar.get_xdata()) / value                 # metres of drawing per kN·m
    peaks = [np.abs(res.diagram(m, 21)[3]).max() for m in fr.members]
    # before: 0.19 of a storey (the largest peak, the foundation beam's, set the scale)
    assert np.median(peaks) * per_unit > 0.3 * 3.5


def test_beam_drawing_labels_do_not_overprint_and_arrows_are_thinned(beam_drawing):
    assert _overlaps(beam_drawing) == []
    _axes_have_units(beam_drawing)
    deflection = beam_drawing.axes[0]
    words = [t.get_text() for t in deflection.texts]
    assert any("arrows drawn" in w for w in words)     # 81 reactions cannot all be drawn
    assert "18\u2009kN/m" in words
    assert any(w == "12500\u2009kN" for w in words)    # 250 kN x p = 50
    assert beam_drawing.axes[1].yaxis_inverted()       # sagging down, on the tension side


@pytest.mark.slow
def test_trace_numbers_do_not_overprint_and_the_key_lists_every_event():
    fr, _ = three_bay_tower()
    tr = fr.trace()
    assert len(tr.events) == 31
    fig = drawn(tr.plot, node="N20_0")
    assert _overlaps(fig) == []
    _axes_have_units(fig)
    curve = fig.axes[0]
    numbers = {t.get_text() for t in curve.texts if t.get_text().isdigit()}
    assert len(numbers) >= 25
    key = " ".join(t.get_text() for t in fig.axes[1].texts)
    assert all(f"{n:>3}  p = " in key for n in range(1, 32))


def _portal():
    fr = Frame(units=("kN", "m"))
    for name, x, y in (("A", 0, 0), ("B", 0, 4), ("C", 6, 4), ("D", 6, 0)):
        fr.add_node(name, x, y)
    fr.add_member("A", "B", 2e8, 0.01, 1e-4, name="L")
    fr.add_member("B", "C", 2e8, 0.01, 1e-4, name="T")
    fr.add_member("C", "D", 2e8, 0.01, 1e-4, name="R")
    fr.add_support("A")
    fr.add_contact("D", normal=(0.0, 1.0), friction=0.4)
    fr.add_distributed_load("T", wy=-20.0, case="D")
    fr.add_point_load("T", 2.0, fy=-30.0, case="L")
    fr.add_load("B", fx=15.0, case="W")
    return fr


def test_every_diagram_is_available_and_titles_use_the_users_names():
    fr = _portal()
    res = fr.solve_combinations({"1.2D+1.6L": {"D": 1.2, "L": 1.6}, "wind": {"D": 1.0, "W": 1.0}})
    fig = drawn(res["1.2D+1.6L"].plot, diagrams=("deflection", "M", "V", "N"))
    assert [ax.get_title().split(" [")[0] for ax in fig.axes[1:]] == \
        ["bending moment M", "shear force V", "axial force N"]
    assert _overlaps(fig) == []
    _axes_have_units(fig)
    assert fig._suptitle.get_text() == "1.2D+1.6L = 1.2 × D + 1.6 × L"
    for ax in fig.axes[1:]:
        assert any(ln.get_gid() == "scale bar" for ln in ax.lines), ax.get_title()
    one = fr.solve(combination={"D": 1.0, "W": -0.5})
    assert drawn(one.plot, diagrams="N")._suptitle.get_text() == "D − 0.5 × W"
    assert drawn(one.plot, title="my portal")._suptitle.get_text() == "my portal"


def test_unknown_diagrams_and_results_that_are_not_ok_are_refused(tmp_path):
    res = _portal().solve(combination={"D": 1.0})
    for bad in (("M", "moment"), "shear", (), ("M", "M")):
        with pytest.raises(InvalidOptionError, match="diagrams: .*deflection, M, V, N"):
            res.plot(tmp_path / "x.png", diagrams=bad)
    broken = dataclasses.replace(res, ok=False, message="CHECK FAILED")
    with pytest.raises(SolverFailedError, match="not an equilibrium"):
        broken.plot(tmp_path / "y.png")
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "y.png").exists()
