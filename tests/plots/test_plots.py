"""Figures read at a glance: a colour and a marker of its own per
method, colour-blind-safe colours, exact zeros in a labelled band rather than
on an unlabelled floor, tick labels that do not overprint (judged on the
rendered figure), units on every axis."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

from tests.helpers.figures import overlapping

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from qpcontact.plots.style import (MARKERS, OKABE_ITO, method_styles,  # noqa: E402
                                   overlapping_tick_labels, readable_log_ticks)
from qpcontact.plots.work_precision import LEVEL_FILL, work_precision_figure  # noqa: E402

METHODS = ["bpp", "clarabel", "daqp", "energy", "enumeration", "highs", "ip-bpp", "lemke",
           "mg-bpp", "osqp", "piqp", "proxqp", "quadprog", "scs"]


def _points(rng, time_range=(1e-4, 1e1), zeros=True):
    """Invented work-precision points: every method at the three levels, the
    iterative ones with a sweep; a third of the exact methods' errors 0."""
    lo, hi = np.log10(time_range)
    pts = {}
    for k, m in enumerate(METHODS):
        levels = {}
        for lv in LEVEL_FILL:
            err = 0.0 if zeros and k % 3 == 0 else 10.0 ** rng.uniform(-17, -2)
            levels[lv] = (10.0 ** rng.uniform(lo, hi), err)
        sweep = ([(10.0 ** rng.uniform(lo, hi), 10.0 ** -j) for j in range(2, 13, 2)]
                 if k % 2 else [])
        pts[m] = {"levels": levels, "sweep": sweep}
    # the time range exactly: where matplotlib's own log ticks would land
    pts[METHODS[1]]["levels"]["low"] = (time_range[0], 1e-3)
    pts[METHODS[1]]["levels"]["high"] = (time_range[1], 1e-12)
    return pts


def _level_points(fig):
    """{gid "method @ level": Line2D} of the drawn ladder points."""
    ax = fig.axes[0]
    return {ln.get_gid(): ln for ln in ax.lines if ln.get_gid()}


def _texts(fig):
    return [t for t in fig.findobj(matplotlib.text.Text)
            if t.get_visible() and t.get_text().strip()]


def _overlaps(fig):
    return overlapping(fig, _texts(fig))


@pytest.mark.parametrize("n", [1, 7, 8, 14, 56])
def test_every_method_gets_its_own_colour_and_marker(n):
    names = [f"m{k}" for k in range(n)]
    styles = method_styles(names)
    assert len(set(styles.values())) == n
    assert {c for c, _ in styles.values()} <= set(OKABE_ITO)
    first = [styles[m] for m in names[:7]]
    # up to seven methods differ in colour AND in marker, not in one of them alone
    assert len({c for c, _ in first}) == len(first) == len({mk for _, mk in first})
    if n > len(OKABE_ITO):     # a shared colour never comes with a shared marker
        for a in names:
            for b in names:
                if a != b and styles[a][0] == styles[b][0]:
                    assert styles[a][1] != styles[b][1]


def test_more_methods_than_pairs_are_refused():
    with pytest.raises(ValueError, match="at most 56"):
        method_styles([f"m{k}" for k in range(len(OKABE_ITO) * len(MARKERS) + 1)])


# 2-40 ms: matplotlib's default minor labels overprint there (the old wp_meshes_n=64.png)
@pytest.mark.parametrize("time_range", [(1e-4, 1e1), (0.06, 0.2), (2e-3, 4e-2), (1e-3, 3e-3)])
def test_work_precision_plot_reads_at_a_glance(time_range):
    pts = _points(np.random.default_rng(0), time_range)
    fig = work_precision_figure(pts, "invented: work against precision", target=1e-9,
                                target_label="accuracy 'high': 1e-9", sweep_range="1e-2 … 1e-12")
    try:
        ax = fig.axes[0]
        drawn = _level_points(fig)
        assert len(drawn) == 3 * len(METHODS)
        look = {}
        for gid, ln in drawn.items():
            m, level = gid.split(" @ ")
            look.setdefault(m, set()).add((ln.get_color(), ln.get_marker()))
            assert ln.get_fillstyle() == LEVEL_FILL[level]
        assert all(len(v) == 1 for v in look.values())          # one look per method
        assert len({next(iter(v)) for v in look.values()}) == len(METHODS)   # ... its own
        # exact zeros: in a band below every positive error, named on the axis
        labels = {t.get_text(): y for t, y in zip(ax.get_yticklabels(), ax.get_yticks())}
        assert "exact (0)" in labels
        y0 = labels["exact (0)"]
        positive = [e for d in pts.values() for _, e in d["levels"].values() if e > 0]
        assert y0 < min(positive) / 5
        for gid, ln in drawn.items():
            m, level = gid.split(" @ ")
            err = pts[m]["levels"][level][1]
            assert ln.get_ydata()[0] == (y0 if err == 0 else err)
        assert ax.get_ylim()[0] < y0
        # nothing overprints, tick labels and the rest; units on both axes
        assert overlapping_tick_labels(ax, "x") == [] and overlapping_tick_labels(ax, "y") == []
        assert _overlaps(fig) == []
        assert "[ms]" in ax.get_xlabel() and "[dimensionless]" in ax.get_ylabel()
        legend_words = " ".join(t.get_text() for t in _texts(fig))
        for m in METHODS:
            assert m in legend_words
        assert "exact (0)" in legend_words and "accuracy 'low'" in legend_words
    finally:
        plt.close(fig)


def test_without_zeros_there_is_no_zero_band():
    fig = work_precision_figure(_points(np.random.default_rng(1), zeros=False), "no zeros")
    try:
        assert "exact (0)" not in [t.get_text() for t in fig.axes[0].get_yticklabels()]
    finally:
        plt.close(fig)


def test_the_overlap_check_sees_crowded_tick_labels():
    """The judge of the tests above can fail: every 1-2-5 tick labelled on a
    narrow axis overprints, and readable_log_ticks thins it until it does not."""
    fig, ax = plt.subplots(figsize=(2.5, 2))
    ax.set_xscale("log")
    ax.set_xlim(1e-3, 1e4)
    ticks = [m * 10.0 ** k for k in range(-3, 4) for m in (1, 2, 5)]
    ax.set_xticks(ticks, [f"{t:g}" for t in ticks])
    try:
        assert overlapping_tick_labels(ax, "x")
        readable_log_ticks(ax, "x")
        assert overlapping_tick_labels(ax, "x") == []
        assert len(ax.get_xticks()) >= 2
    finally:
        plt.close(fig)


def test_drum_figures_read_at_a_glance(monkeypatch):
    """The drum's standard figures (``qpcontact plot``), from arrays shaped like
    a results file: a colour and marker per contact and per energy term, units
    on every axis, no text over another, the time step named in the energy
    plot."""
    from formulations.drum.scene import SCENE
    import qpcontact.plots.figures as figures

    figs = {}
    monkeypatch.setattr(figures, "save_figure", lambda fig, path: figs.setdefault(path, fig) and path)
    t = np.linspace(0.0, 0.05, 501)
    rng = np.random.default_rng(2)
    N = np.maximum(0.0, np.sin(np.outer(t, rng.uniform(100, 400, 10)))) * 1e5
    h = {"t": t, "forces": N, **{f"energy/{k}": rng.uniform(0, 10, t.size)
                                  for k in ("kinetic", "elastic", "potential", "viscous", "numerical")}}
    SCENE.plot(h, "figs")
    try:
        assert sorted(p.rsplit("/", 1)[1] for p in figs) == ["energy.png", "forces.png", "peaks.png"]
        for path, fig in figs.items():
            assert _overlaps(fig) == [], path
            for ax in fig.axes:
                assert "[" in ax.get_ylabel(), path
                assert "[" in ax.get_xlabel() or "contact" in ax.get_xlabel(), path
        for name, n in (("forces.png", 10), ("energy.png", 5)):
            ax = figs[f"figs/{name}"].axes[0]
            looks = {(ln.get_color(), ln.get_marker(), ln.get_linestyle()) for ln in ax.lines}
            assert len(looks) == len(ax.lines) == n
            assert len({(c, m) for c, m, _ in looks}) == n
        assert "tau = 100 µs" in figs["figs/energy.png"].axes[0].get_title()
    finally:
        for fig in figs.values():
            plt.close(fig)
