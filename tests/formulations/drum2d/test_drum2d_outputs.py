"""What the engineer reads off a 2-D drum run: per-revolution force
histograms, peaks and quantiles, sliding work per log (against a count of the
kept contacts themselves), revolution windows by hand, the stack model's
estimate (against the analytic peak of one log dropped on the shell and
against formulations.drum run by hand), the figures (units, no overprint,
the estimate drawn) and the animation's frames."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from formulations.drum import GRAVITY, Drum, Log
from formulations.drum2d.records import FORCE_BINS
from formulations.drum2d.revolutions import (BIN_RATIO, histogram_quantile, revolution_windows,
                                             revolutions)
from formulations.drum2d.stack import drop_height, stack_estimate, stack_estimate_for_run
from qpcontact.core.errors import InvalidOptionError

from tests.helpers.figures import figure_texts, overlapping

# twenty logs in a 1 m drum with two lifters, friction on: 60 steps of 5 ms
SMALL = """formulation = "drum2d"
effects = ["gravity", "rotation", "damping", "friction"]

[drum]
diameter = 1.0

[lifters]
count = 2
height = 0.05
thickness = 0.02

[logs]
count = 20
diameter_min = 0.08
diameter_max = 0.10
seed = 2
length = 1.0
density = 860.0

[effect.rotation]
speed = 0.5

[effect.damping]
restitution = 0.5

[effect.friction]
mu_disc = 0.3
mu_shell = 0.5
mu_lifter = 0.4

[time]
step = 0.005
duration = 0.3
"""
H = 0.005
STEPS = 60


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    """(the scene's run, its results file, the stack estimate from the file)."""
    import h5py

    from qpcontact.scenes import parse_scene
    from qpcontact.scenes.results_files import write_results

    tmp = tmp_path_factory.mktemp("drum2d_outputs")
    sc = parse_scene(SMALL, tmp / "small.toml")
    _, run = sc.schema.build(sc)
    r = run()
    assert r.result.certified.all() and len(r.t) == STEPS + 1
    path = write_results(sc, r, tmp / "small.h5", completed=STEPS, total=STEPS)
    with h5py.File(path) as h:
        est = stack_estimate_for_run(h)
    return r, path, est


# -- windows ---------------------------------------------------------------------------


def test_revolution_windows_by_hand():
    t = 0.1 * np.arange(26)                       # 25 steps of 0.1 s, T = 1 s
    w = revolution_windows(t, 2 * np.pi)
    assert [(x.first, x.stop, x.complete) for x in w] == [(0, 10, True), (10, 20, True),
                                                          (20, 25, False)]
    assert w[2].fraction == pytest.approx(0.5) and w[2].label == "rev 3 (partial, 0.50)"
    assert [x.label for x in w[:2]] == ["rev 1", "rev 2"]
    # the direction of turning does not matter
    assert [(x.first, x.stop) for x in revolution_windows(t, -2 * np.pi)] == \
        [(x.first, x.stop) for x in w]
    # a run from 0.35 s to 1.35 s: steps starting 0.35 .. 0.95 in revolution 1 (the
    # last straddles 1 s), the rest in 2; they cover 0.65 and 0.35 of a revolution
    w = revolution_windows(0.35 + 0.1 * np.arange(11), 2 * np.pi)
    assert [(x.index, x.first, x.stop) for x in w] == [(0, 0, 7), (1, 7, 10)]
    assert [x.fraction for x in w] == pytest.approx([0.65, 0.35])
    assert not any(x.complete for x in w)
    # a revolution that is no whole number of steps (2/3 s in steps of 0.2 s): the
    # step from 0.6 s to 0.8 s straddles it; both windows complete
    w = revolution_windows(0.2 * np.arange(8), 3 * np.pi)
    assert [(x.first, x.stop, x.complete) for x in w] == [(0, 4, True), (4, 7, True)]
    # steps of 1/30 s: 30 to a revolution although k/30 * 30 is not k in floating point
    w = revolution_windows(np.arange(91) / 30.0, 2 * np.pi)
    assert [(x.first, x.stop, x.complete) for x in w] == [(0, 30, True), (30, 60, True),
                                                          (60, 90, True)]
    # no rotation: the whole run
    w = revolution_windows(t, 0.0)
    assert len(w) == 1 and (w[0].first, w[0].stop, w[0].label) == (0, 25, "whole run")
    with pytest.raises(InvalidOptionError, match="at least one step"):
        revolution_windows([0.0], 1.0)


def test_histogram_quantile_by_hand():
    counts = np.zeros(FORCE_BINS.size - 1, int)
    counts[[30, 40, 50]] = [5, 4, 1]              # bins [10^2, 10^2.1), [10^3, ...), [10^4, ...)
    assert histogram_quantile(counts, 0.5, 2e4) == pytest.approx(10 ** 2.1)
    assert histogram_quantile(counts, 0.9, 2e4) == pytest.approx(10 ** 3.1)
    assert histogram_quantile(counts, 0.99, 1.1e4) == pytest.approx(1.1e4)   # the peak caps
    assert histogram_quantile(np.zeros_like(counts), 0.5, 0.0) == 0.0
    assert BIN_RATIO == pytest.approx(10 ** 0.1)
    with pytest.raises(InvalidOptionError, match=r"in \(0, 1\]"):
        histogram_quantile(counts, 0.0, 1.0)


# -- the per-revolution sums against the kept contacts -----------------------------------


def _by_hand(result, first, stop, n):
    """Histograms, peaks and sliding work of steps first..stop−1 recounted
    from the kept contacts (r_n / h, |r_t| · slip charged to the logs)."""
    counts = {k: np.zeros(FORCE_BINS.size - 1, int) for k in range(3)}
    peaks = np.zeros(3)
    work = np.zeros(n)
    for s in range(first, stop):
        c = result.contacts[s]
        if c is None:
            continue
        F = c["r_n"] / H
        for k in range(3):
            f = F[(c["kind"] == k) & (F >= FORCE_BINS[0])]    # under 0.1 N: not counted
            if f.size:
                counts[k] += np.histogram(np.minimum(f, FORCE_BINS[-1]), FORCE_BINS)[0]
                peaks[k] = max(peaks[k], f.max())
        for i, j, kind, rt, slip in zip(c["i"], c["j"], c["kind"], c["r_t"], c["slip"]):
            w = abs(rt) * slip                     # slip: the mean sliding speed >= 0
            if kind == 0:
                work[i] += w / 2
                work[j] += w / 2
            else:
                work[i] += w
    return counts, peaks, work


def test_revolution_sums_match_the_kept_contacts(small):
    import h5py

    run, path, _ = small
    res = run.result
    # every step kept: only the steps without an active contact have none
    assert all((c is None) == (m == 0) for c, m in zip(res.contacts, res.n_active))
    omega = 2 * np.pi / (25 * H)                           # windows of 25 steps, by choice
    revs = revolutions(res, omega=omega)
    assert [(r.window.first, r.window.stop, r.window.complete) for r in revs] == \
        [(0, 25, True), (25, 50, True), (50, 60, False)]
    with h5py.File(path) as h:
        from_file = revolutions(h, omega=omega)
    # by its path, as a string or a Path: the same (a string was read as a
    # mapping, and "t" in the path passed for the dataset t)
    for given in (str(path), Path(path)):
        by_path = revolutions(given, omega=omega)
        assert [r.forces["log-log"].peak_N for r in by_path] == \
            [r.forces["log-log"].peak_N for r in from_file]
    seen = 0
    for rev, again in zip(revs, from_file):
        counts, peaks, work = _by_hand(res, rev.window.first, rev.window.stop, 20)
        for k, name in enumerate(("log-log", "log-shell", "log-lifter")):
            np.testing.assert_array_equal(rev.forces[name].counts, counts[k])
            assert rev.forces[name].peak_N == pytest.approx(peaks[k], rel=1e-12, abs=0)
            seen += counts[k].sum()
        np.testing.assert_array_equal(rev.forces["log-steel"].counts, counts[1] + counts[2])
        assert rev.forces["log-steel"].peak_N == pytest.approx(max(peaks[1], peaks[2]))
        np.testing.assert_allclose(rev.sliding.per_log_J, work, rtol=1e-12, atol=1e-15)
        assert rev.sliding.max_log == int(np.argmax(work))
        assert rev.sliding.mean_J == pytest.approx(work.mean())
        # the work charged to the logs is the friction loss of the energy balance
        loss = res.friction_loss[rev.window.first:rev.window.stop].sum()
        assert rev.sliding.total_J == pytest.approx(loss, rel=1e-9, abs=1e-12)
        # the file says the same
        np.testing.assert_array_equal(again.forces["log-log"].counts, rev.forces["log-log"].counts)
        assert again.sliding.total_J == rev.sliding.total_J
    assert seen > 100 and revs[0].sliding.total_J > 0   # contacts and friction did happen


def test_quantiles_bound_the_true_ones_within_a_bin(small):
    res = small[0].result
    for rev in revolutions(res, omega=2 * np.pi / (25 * H)):
        for k, name in enumerate(("log-log", "log-shell")):
            F = np.concatenate([c["r_n"][(c["kind"] == k) & (c["r_n"] >= FORCE_BINS[0] * H)] / H
                                for c in res.contacts[rev.window.first:rev.window.stop]
                                if c is not None])
            for q, est in rev.forces[name].quantiles_N.items():
                true = np.quantile(F, q, method="inverted_cdf")
                assert true <= est * (1 + 1e-12)
                assert est <= max(true, FORCE_BINS[0]) * BIN_RATIO * (1 + 1e-12)


def test_a_result_needs_omega_and_a_file_its_statistics(small, tmp_path):
    import h5py

    with pytest.raises(InvalidOptionError, match="omega="):
        revolutions(small[0].result)
    old = tmp_path / "old.h5"
    with h5py.File(old, "w") as h:
        h["t"] = np.arange(3.0)
    with h5py.File(old) as h, pytest.raises(InvalidOptionError, match="run the scene again"):
        revolutions(h)
    with pytest.raises(InvalidOptionError, match="no drum2d results file at"):
        revolutions(str(tmp_path / "missing.h5"))


# -- the stack model's estimate ----------------------------------------------------------


def test_one_log_dropped_on_a_rigid_shell_gives_the_analytic_peak():
    d, ell, rho, E, drop = 0.15, 1.2, 860.0, 0.4e9, 0.5
    m = rho * np.pi * d ** 2 / 4 * ell
    k = 2 * E * ell                                  # the log's half: a prism, 2 E ℓ
    v = np.sqrt(2 * GRAVITY * drop)
    exact = m * GRAVITY + np.sqrt((m * GRAVITY) ** 2 + k * m * v * v)
    est = stack_estimate([d], [m], ell, drop, modulus=E, layers=1)
    assert est.impact_speed_m_s == pytest.approx(v)
    # the stack model is first order from below: ~3 % low at 160 steps a period
    assert 0.96 * exact < est.log_shell_N < exact
    assert est.log_log_N == 0.0 and est.layers == 1
    # an elastic shell in series with the log's half
    ks = 3e8
    keff = 1 / (1 / k + 1 / ks)
    soft = stack_estimate([d], [m], ell, drop, modulus=E, layers=1, shell_stiffness=ks)
    exact = m * GRAVITY + np.sqrt((m * GRAVITY) ** 2 + keff * m * v * v)
    assert 0.96 * exact < soft.log_shell_N < exact


def test_the_estimate_is_the_stack_model_run_by_hand():
    d = np.array([0.10, 0.20, 0.15])
    ell, rho, E, drop = 1.0, 700.0, 0.5e9, 1.2
    m = rho * np.pi * d ** 2 / 4 * ell
    est = stack_estimate(d, m, ell, drop, modulus=E, layers=2)
    # the two heaviest logs, the heaviest lowest, falling from the drop height
    logs = [Log.from_wood(0.20, ell, rho, E), Log.from_wood(0.15, ell, rho, E)]
    v = np.sqrt(2 * GRAVITY * drop)
    peaks = {}
    for case, vel in (("shell", [-v, -v]), ("log", [0.0, -v])):
        drum = Drum(logs, [0.0, 0.0], vel)
        T = drum.contact_periods()
        tau = T.min() / 160
        peaks[case] = drum.simulate(tau, int(np.ceil(2 * T.max() / tau))).forces.max(axis=0)
    assert est.log_shell_N == pytest.approx(peaks["shell"][0], rel=1e-9)
    assert est.log_log_N == pytest.approx(peaks["log"][1], rel=1e-9)
    np.testing.assert_allclose(est.masses_kg, [m[1], m[2]])


def test_the_estimate_for_a_run_and_its_drop(small):
    import h5py

    run, path, est = small
    # drop height by hand: D − d_max + (Ω R)²/(2 g), Ω = 2π · 0.5 rad/s, R = 0.5 m
    dmax = run.model.discs.diameters.max()
    assert est.drop_height_m == pytest.approx(1.0 - dmax + (np.pi * 0.5) ** 2 / (2 * GRAVITY))
    assert drop_height(1.0, dmax, np.pi, GRAVITY) == pytest.approx(est.drop_height_m)
    assert est.masses_kg[0] == pytest.approx(run.model.discs.masses.max())
    assert 2 <= est.layers <= 20
    same = stack_estimate_for_run(run.model)       # from the model, not the file
    assert same.log_shell_N == est.log_shell_N and same.log_log_N == est.log_log_N
    # above every 2-D peak of this run (rigid: impulse / h); not a bound in general
    with h5py.File(path) as h:
        peak = h["force_peak"][()].max(axis=0)
    assert peak[0] < est.log_log_N and max(peak[1], peak[2]) < est.log_shell_N
    with pytest.raises(InvalidOptionError, match="drop_height_m"):
        stack_estimate([0.1], [5.0], 1.0, 0.0)
    with pytest.raises(InvalidOptionError, match="smaller than the drum"):
        drop_height(1.0, 1.2)


# -- figures and animation ---------------------------------------------------------------


@pytest.mark.parametrize("which", ["histogram", "peaks", "sliding"])
def test_figures_have_units_no_overprint_and_the_estimate(small, which):
    import h5py
    import matplotlib.pyplot as plt

    from formulations.drum2d.figures import (force_histogram_figure, force_peak_figure,
                                             sliding_work_figure)

    _, path, est = small
    with h5py.File(path) as h:
        fig = {"histogram": lambda: force_histogram_figure(h, est),
               "peaks": lambda: force_peak_figure(h, est),
               "sliding": lambda: sliding_work_figure(h)}[which]()
        revs = revolutions(h)
    try:
        W, Hpx = fig.canvas.get_width_height()
        shown = figure_texts(fig, in_view=True)
        assert overlapping(fig, shown) == []
        for t in shown:                                   # nothing cut at the edges
            x0, y0, x1, y1 = t.get_window_extent().extents
            assert x0 >= 0 and y0 >= 0 and x1 <= W and y1 <= Hpx, t.get_text()
        for ax in fig.axes:
            for label in (ax.get_xlabel(), ax.get_ylabel()):
                assert not label or ("[" in label and "]" in label), label
            assert ax.get_xlabel()
        assert fig.axes[0].get_ylabel()
        if which == "histogram":    # a vertical line at the estimate in each panel
            for ax, bound in zip(fig.axes, (est.log_log_N, est.log_shell_N)):
                xs = [ln.get_xdata() for ln in ax.lines]
                assert any(np.allclose(x, bound) for x in xs)
                assert ax.get_xscale() == "log"
            drawn = sum(np.nansum(p.get_data()[0]) for p in fig.axes[0].patches)
            assert drawn == sum(r.forces["log-log"].contact_steps for r in revs)
        if which == "peaks":        # horizontal lines at both estimates
            ys = [ln.get_ydata() for ln in fig.axes[0].lines]
            for bound in (est.log_log_N, est.log_shell_N):
                assert any(len(y) == 2 and np.allclose(y, bound) for y in ys)
        if which == "sliding":
            line = fig.axes[0].lines[0]
            assert np.allclose(np.sort(line.get_ydata())[::-1],
                               np.sort(revs[0].sliding.per_log_J)[::-1])
    finally:
        plt.close(fig)


def test_the_animation_writes_frames_and_a_gif(small, tmp_path, monkeypatch):
    import h5py
    from matplotlib import animation

    from formulations.drum2d.animation import animation_states, write_animation

    _, path, _ = small
    with h5py.File(path) as h:
        kept = np.unique(h["contacts/step"][()]) + 1
        states = animation_states(h, stride=7)
        np.testing.assert_array_equal(states, kept[::7])
        assert animation_states(h, max_frames=4).size == 4
        a = write_animation(h, tmp_path / "anim", max_frames=5)
        assert len(a.frames) == 5 and all((tmp_path / "anim" / f"frame_{k:04d}.png").stat()
                                          .st_size > 5_000 for k in range(5))
        if animation.writers.is_available("pillow"):
            from PIL import Image

            assert a.movie == str(tmp_path / "animation.gif") and a.message == ""
            with Image.open(a.movie) as gif:
                assert gif.n_frames == 5
        # no writer: the frames and a message that says what to install
        monkeypatch.setattr(animation.writers, "is_available", lambda name: False)
        b = write_animation(h, tmp_path / "bare", max_frames=3)
        assert b.movie is None and len(b.frames) == 3
        assert "Pillow" in b.message and "ffmpeg" in b.message
        with pytest.raises(InvalidOptionError, match="movie must be"):
            write_animation(h, tmp_path / "x", movie="avi")


@pytest.mark.slow
def test_plot_writes_the_outputs(small, tmp_path):
    from typer.testing import CliRunner

    from qpcontact.commands.cli import app

    _, path, _ = small
    res = CliRunner().invoke(app, ["plot", str(path), "--out", str(tmp_path / "fig")])
    assert res.exit_code == 0, res.output
    for name in ("force_histograms.png", "force_peaks.png", "sliding_work.png"):
        assert (tmp_path / "fig" / name).stat().st_size > 10_000, res.output
    assert (tmp_path / "fig" / "animation" / "frame_0000.png").exists()
    assert (tmp_path / "fig" / "animation.gif").exists() or "no movie" in res.output
