"""The 2-D drum's scene (formulation "drum2d"): checked input, simulate and
plot from the command line, the file against a direct Drum2D run built from
the documented rules (hex_fill, evenly spaced lifters, Ω = 2π · speed), and
readable figures."""

from __future__ import annotations


import numpy as np
import pytest

from formulations.drum2d import Discs, Drum2D, Shell, hex_fill
from qpcontact.scenes import SceneError, load_scene, parse_scene, schemas

from tests.helpers.figures import figure_texts, overlapping
from tests.helpers.paths import SCENES

EXAMPLE = SCENES / "drum2d.toml"

# ten logs in the bottom of a 2 m drum; the two lifters at mid-height on the
# sides stay clear of them, so no lattice site is left out
TINY = """formulation = "drum2d"
effects = ["gravity", "rotation", "damping", "friction"]

[drum]
diameter = 2.0

[lifters]
count = 2
height = 0.1
thickness = 0.04

[logs]
count = 10
diameter_min = 0.18
diameter_max = 0.24
seed = 3
length = 1.5
density = 700.0

[effect.rotation]
speed = 0.2

[effect.damping]
restitution = 0.5

[effect.friction]
mu_disc = 0.3
mu_shell = 0.5
mu_lifter = 0.4

[time]
step = 0.002
duration = 0.2
"""


def _write(tmp_path, text, name="scene.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def _run_cli(*args):
    from typer.testing import CliRunner

    from qpcontact.commands.cli import app

    res = CliRunner().invoke(app, [str(a) for a in args])
    assert res.exit_code == 0, res.output
    return res


def test_registered_and_the_example_checks():
    assert "drum2d" in schemas(), "entry point qpcontact.scenes drum2d: reinstall (pip install -e .)"
    sc = load_scene(EXAMPLE)
    assert sc.data["logs"]["count"] == 40 and "rotation" in sc.effects
    model, run = sc.schema.build(sc)
    assert model.discs.n == 40 and model.shell.lifter_angles.size == 4
    assert run.total_steps == 500


@pytest.mark.parametrize("old, new, needle", [
    ("diameter = 2.0", "diameter = 2.0\nradius = 1.0", "drum.radius: unknown key"),
    ("diameter = 2.0", 'diameter = "2 m"', "drum.diameter: expected a number [m]"),
    ("diameter = 2.0", "diameter = -2.0", "drum.diameter: must be > 0 [m]"),
    ("count = 10", "count = 10\nfill_fraction = 0.3", "logs.count: give exactly one"),
    ("count = 10\n", "", "logs.count: give exactly one"),
    ("diameter_max = 0.24", "diameter_max = 0.1", "logs.diameter_max: must be >= diameter_min"),
    ("count = 10", "count = 5000", "logs.count: 5000 discs"),
    ("restitution = 0.5", "restitution = 1.5", "effect.damping.restitution: must be in [0, 1]"),
    ("mu_disc = 0.3", "mu_disc = -0.3", "effect.friction.mu_disc: must be >= 0"),
    ("height = 0.1\n", "", "lifters.height: missing"),
    ("height = 0.1", "height = 1.5", "lifters.height: must be < the drum's radius"),
    ("duration = 0.2", "duration = 0.2\nrevolutions = 1.0", "time.duration: give exactly one"),
    ("duration = 0.2", "duration = 0.0001", "time.step: the duration"),
    ('"rotation", ', "", "effect.rotation: parameters given for effect 'rotation', which is not"),
    ('"friction"]', '"friction", "wind"]', "unknown effect 'wind'"),
    ('"friction"]', '"friction", "shell_elasticity"]', "effect.shell_elasticity.stiffness"),
    ("[time]", "[solver]\nwarm_start = \"lemke\"\n\n[time]", "solver.warm_start: must be one of"),
    ("[time]", "[output]\ncontacts_every = -1\n\n[time]", "output.contacts_every: must be >= 0"),
    ("speed = 0.2", "speed = 0", "effect.rotation.speed: must be > 0 [rev/s]"),
])
def test_bad_input_names_the_key(tmp_path, old, new, needle):
    assert old in TINY
    p = _write(tmp_path, TINY.replace(old, new, 1))
    with pytest.raises(SceneError) as exc:
        sc = load_scene(p)
        sc.schema.build(sc)
    assert needle in str(exc.value), str(exc.value)
    assert str(exc.value).startswith(f"{p}:")


def test_revolutions_need_rotation(tmp_path):
    text = TINY.replace('"rotation", ', "").replace("[effect.rotation]\nspeed = 0.2\n", "")
    sc = parse_scene(text.replace("duration = 0.2", "revolutions = 0.5"), tmp_path / "s.toml")
    with pytest.raises(SceneError, match=r"time.revolutions: revolutions needs the effect"):
        sc.schema.build(sc)
    sc = parse_scene(TINY.replace("duration = 0.2", "revolutions = 0.01"), "s.toml")
    assert sc.schema.build(sc)[1].total_steps == round(0.01 / 0.2 / 0.002)


def test_fill_fraction_and_lifters_cut_from_the_fill():
    text = (TINY.replace("count = 10", "fill_fraction = 0.25").replace("count = 2", "count = 4"))
    sc = parse_scene(text, "s.toml")
    model, _ = sc.schema.build(sc)
    d = model.discs
    # n = round(4 f R² / E[d²]), E[d²] of a uniform diameter by hand
    mean, spread = 0.21, 0.06
    assert d.n == round(4 * 0.25 * 1.0 / (mean ** 2 + spread ** 2 / 12))
    assert 0.9 * 0.25 < np.sum(d.diameters ** 2) / 4 / 1.0 < 1.1 * 0.25
    # a lifter stands at the bottom (α = 3π/2): no log may start inside any lifter
    for a in model.shell.lifter_angles:
        u = np.array([np.cos(a), np.sin(a)])
        s = np.clip(d.positions @ u, 1.0 - 0.1, 1.0)
        dist = np.linalg.norm(d.positions - s[:, None] * u, axis=1)
        assert np.all(dist >= d.radii + 0.02)
    assert np.isclose(model.shell.lifter_angles, 1.5 * np.pi).any()


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("drum2d")
    scene = _write(tmp, TINY)
    out = tmp / "tiny.h5"
    _run_cli("simulate", scene, "--out", out)
    return scene, out


def test_the_file_matches_a_direct_drum2d_run(tiny_run):
    import h5py

    _, out = tiny_run
    # the same drum by the documented rules, through the Python API
    pos, diam = hex_fill(1.0, 10, 0.21, spread=0.03 / 0.21, seed=3)
    discs = Discs(diam, pos, length=1.5, density=700.0)
    shell = Shell(1.0, 2 * np.pi * 0.2, [0.0, np.pi], 0.1, 0.02)
    model = Drum2D(discs, shell, ("gravity", "rotation", "damping", "friction"), mu_disc=0.3,
                   mu_shell=0.5, mu_lifter=0.4, restitution=0.5)
    ref = model.simulate(0.002, 100)
    assert ref.certified.all() and ref.n_active.max() >= 3
    with h5py.File(out) as h:
        assert h.attrs["completed_steps"] == h.attrs["total_steps"] == 100
        np.testing.assert_array_equal(h["diameters"][()], diam)
        np.testing.assert_array_equal(h["positions"][()], ref.positions)
        np.testing.assert_array_equal(h["spins"][()], ref.spins)
        np.testing.assert_array_equal(h["energy/drive"][()], ref.drive)
        np.testing.assert_array_equal(h["n_active"][()], ref.n_active)
        assert h["certified"][()].all()
        step = h["contacts/step"][()]
        F = h["contacts/force_n"][()]
        hit = [s for s, c in enumerate(ref.contacts) if c is not None]
        assert len(hit) > 20 and sorted(set(step)) == hit
        for s in hit:
            np.testing.assert_array_equal(F[step == s], ref.contacts[s]["r_n"] / 0.002)
        assert float(h["drum/omega"][()]) == 2 * np.pi * 0.2


@pytest.mark.slow
def test_plot_writes_both_figures(tiny_run, tmp_path):
    _, out = tiny_run
    res = _run_cli("plot", out, "--out", tmp_path / "fig")
    for name in ("snapshot.png", "energy.png"):
        assert (tmp_path / "fig" / name).stat().st_size > 10_000, res.output


@pytest.mark.parametrize("which", ["snapshot", "energy"])
def test_figures_have_units_and_no_overprint(tiny_run, which):
    import h5py
    import matplotlib.pyplot as plt

    from formulations.drum2d.figures import energy_figure, snapshot_figure

    _, out = tiny_run
    with h5py.File(out) as h:
        fig = (snapshot_figure if which == "snapshot" else energy_figure)(h)
    try:
        # the labels matplotlib draws (ticks beyond the limits are listed, never drawn)
        assert overlapping(fig, figure_texts(fig, in_view=True)) == []
        for ax in fig.axes:
            if ax.get_xlabel():
                assert "[" in ax.get_xlabel() and "]" in ax.get_xlabel()
            assert "[" in ax.get_ylabel() and "]" in ax.get_ylabel(), ax.get_ylabel()
        assert fig.axes[-1].get_xlabel()
        if which == "snapshot":   # one line per active contact of the last step, none hidden
            with h5py.File(out) as h:
                last = int((h["contacts/step"][()] == 99).sum())
            lines = fig.axes[0].collections[-1]
            assert len(lines.get_segments()) == last > 0
    finally:
        plt.close(fig)


def test_a_killed_run_resumes_to_the_uninterrupted_file(tiny_run, tmp_path):
    """The run is stopped after step 37 (its last checkpoint somewhere before),
    then continued with --resume: every dataset equals the uninterrupted run's
    bit for bit (states, statistics, kept contacts, the warm start's impulses)."""
    import h5py

    from qpcontact.scenes import write_results

    scene, full = tiny_run
    sc = load_scene(scene)
    _, run = sc.schema.build(sc)
    partial = tmp_path / "partial.h5"

    class Killed(Exception):
        pass

    def stop(n, contacts, r):
        if n == 38:
            raise Killed

    def checkpoint(result):
        write_results(sc, result, partial, completed=len(result.t) - 1, total=run.total_steps)
    with pytest.raises(Killed):
        run(checkpoint=checkpoint, checkpoint_seconds=0.0, on_step=stop)
    with h5py.File(partial) as h:
        done = int(h.attrs["completed_steps"])
    assert 0 < done < 38
    _run_cli("simulate", scene, "--out", partial, "--resume")
    with h5py.File(full) as a, h5py.File(partial) as b:
        assert b.attrs["completed_steps"] == a.attrs["completed_steps"] == 100
        names = []
        a.visititems(lambda name, obj: names.append(name) if isinstance(obj, h5py.Dataset)
                     else None)
        for name in names:
            if name in ("solve_seconds", "scene"):   # wall-clock times differ, by design
                continue
            np.testing.assert_array_equal(a[name][()], b[name][()], err_msg=name)


def test_a_sweep_of_speed_and_fill_writes_one_row_per_variant(tmp_path):
    """speed x count on a short run: one results file per variant, and each
    summary row equals the statistics of its own file."""
    import csv

    import h5py

    scene = _write(tmp_path, TINY.replace("duration = 0.2", "duration = 0.1"))
    out = tmp_path / "sweep"
    _run_cli("sweep", scene, "--vary", "effect.rotation.speed=0.1,0.2", "--vary",
             "logs.count=6,10", "--grid", "--out", out)
    rows = list(csv.DictReader(open(out / "summary.csv")))
    assert [(r["effect.rotation.speed"], r["logs.count"]) for r in rows] == \
        [("0.1", "6"), ("0.1", "10"), ("0.2", "6"), ("0.2", "10")]
    for row in rows:
        with h5py.File(out / f"{row['variant']}.h5") as h:
            assert h["positions"].shape[1] == int(row["logs.count"])
            assert np.isclose(float(h["drum/omega"][()]),
                              2 * np.pi * float(row["effect.rotation.speed"]))
            peak = h["force_peak"][()].max(axis=0)
            assert float(row["peak log-shell [N]"]) == peak[1] > 0
            turns = 0.1 * float(row["effect.rotation.speed"])
            work = h["sliding_work"][()].sum() / int(row["logs.count"]) / turns
            assert np.isclose(float(row["sliding/log/rev [J]"]), work, rtol=1e-12)
