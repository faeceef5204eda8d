"""Scene files: the engine's loader, the drum's schema,
`qpcontact simulate` and its HDF5 results.  Line numbers in the expected
messages are found in the test's own text, not taken from the loader."""

from __future__ import annotations


import numpy as np
import pytest

from formulations.drum import Drum, Log
from qpcontact.scenes import SceneError, load_scene, write_results
from tests.helpers.paths import SCENES

EXAMPLE = SCENES / "drum.toml"

BASE = """formulation = "drum"
effects = ["gravity", "damping"]

[effect.damping]
ratio = 0.05

[[logs]]
diameter = 0.12
length = 1.2

[[logs]]
diameter = 0.18
length = 1.2

[initial]
gaps = [0.01, 0.005]
velocities = [-1.0, -1.5]

[time]
steps = 300
"""


def _write(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _line_of(text, needle, nth=0):
    hits = [no for no, line in enumerate(text.splitlines(), 1) if needle in line]
    return hits[nth]


@pytest.mark.slow
def test_example_scene_equals_the_python_api(tmp_path):
    """The example scene and the same drum written in Python: the same
    forces, gaps and displacements, bit for bit."""
    scene = load_scene(EXAMPLE)
    drum, run = scene.schema.build(scene)
    logs = [Log.from_wood(0.12, 1.2, damping_ratio=0.05), Log.from_wood(0.18, 1.2, damping_ratio=0.05),
            Log.from_wood(0.15, 1.2, 450.0, damping_ratio=0.05)]
    same = Drum(logs, [0.01, 0.005, 0.02], [-1.0, -1.5, -0.5], effects=("gravity", "damping"))
    tau = same.contact_periods().min() / 40
    a = run()
    b = same.simulate(tau, 5000)
    for key in ("forces", "gaps", "displacements", "velocities"):
        assert np.array_equal(getattr(a, key), getattr(b, key)), key
    path = write_results(scene, a, tmp_path / "run.h5")
    import h5py

    with h5py.File(path) as h:
        assert np.array_equal(h["forces"][()], a.forces)
        assert h["scene"][()].decode() == EXAMPLE.read_text()
        assert h.attrs["formulation"] == "drum" and h.attrs["effects"] == "gravity,damping"
        assert "version_qpcontact" in h.attrs
        assert np.allclose(h["energy/viscous"][()], a.energy()["viscous"])
    assert not list(tmp_path.glob("*.tmp"))


@pytest.mark.parametrize("effects, damped, shell, g", [
    ('["gravity", "damping"]', True, False, 9.81),
    ('["damping"]', True, False, 0.0),
    ('["gravity"]', False, False, 9.81),
    ('[]', False, False, 0.0),
    ('["gravity", "shell_elasticity"]', False, True, 9.81),
])
def test_only_named_effects_are_assembled(tmp_path, effects, damped, shell, g):
    """What is built, not final numbers: no damping arrays and a step matrix
    without damping terms unless "damping" is named; no shell compliance
    without "shell_elasticity"; g = 0 without "gravity"."""
    text = BASE.replace('effects = ["gravity", "damping"]', f"effects = {effects}")
    if not damped:
        text = text.replace("[effect.damping]\nratio = 0.05\n", "")
    if shell:
        text += "\n[effect.shell_elasticity]\nstiffness = 5e6\n"
    drum, _ = load_scene(_write(tmp_path, text)).schema.build(load_scene(tmp_path / "scene.toml"))
    assert (drum.damping is not None) == damped
    assert drum.gravity == g
    assert (drum.shell_stiffness is not None) == shell
    c = 1.0 / drum.half_stiffness
    assert drum.compliance[0] == pytest.approx(c[0] + (1 / 5e6 if shell else 0.0), rel=1e-15)
    tau = drum.contact_periods().min() / 40
    undamped_h = drum.mass / tau ** 2
    h = drum._h(tau, np.ones(drum.n_logs, bool))
    assert np.array_equal(h, undamped_h) != damped      # damping terms exist only if named
    M = drum.step_matrix(tau, np.ones(drum.n_logs, bool) if damped else None)
    assert M.shape == (2, 2) and abs(M - M.T).max() == 0


@pytest.mark.parametrize("edit, needle, nth, message", [
    (lambda t: t.replace("length = 1.2\n\n[[logs]]", "lenght = 1.2\n\n[[logs]]", 1),
     "lenght", 0, r"logs.lenght: unknown key; valid keys in \[logs\]: diameter, length, density"),
    (lambda t: t.replace("steps = 300", "steps = 300\ndt = 1e-5"), "dt =", 0,
     r"time.dt: unknown key; valid keys in \[time\]: steps, tau, steps_per_period"),
    (lambda t: t.replace('"damping"]', '"damping", "friction"]'), "effects =", 0,
     r"unknown effect 'friction' for 'drum'; it knows gravity, damping, shell_elasticity"),
    (lambda t: t + "\n[effect.shell_elasticity]\nstiffness = 5e6\n", "[effect.shell_elasticity]",
     0, r"parameters given for effect 'shell_elasticity', which is not named"),
    (lambda t: t.replace("diameter = 0.18", 'diameter = "18 cm"'), "18 cm", 0,
     r"logs.diameter: expected a number \[m\], got '18 cm'"),
    (lambda t: t.replace("steps = 300", "steps = 300.5"), "steps =", 0,
     r"time.steps: expected an integer, got 300.5"),
    (lambda t: t.replace("ratio = 0.05\n", ""), "[effect.damping]", 0,
     r"effect.damping.ratio: missing required value: a number \[-\]"),
    (lambda t: t.replace("[time]\nsteps = 300\n", "[time]\n"), "[time]", 0,
     r"time.steps: missing required value: an integer"),
    (lambda t: t.replace("diameter = 0.12", "diameter = -0.12"), "diameter = -0.12", 0,
     r"logs.diameter: must be > 0 \[m\]"),
    (lambda t: t.replace('formulation = "drum"', 'formulation = "drums"'), "formulation", 0,
     r"'drums' is not a registered formulation; choose one of drum"),
    (lambda t: t + "\n[output]\nevery = 2\n", "[output]", 0,
     r"output: unknown key for 'drum'; valid top-level keys and tables: formulation, effects, "
     r"effect, logs, initial, time, solver"),
])
def test_scene_errors_name_file_line_key_and_choices(tmp_path, edit, needle, nth, message):
    text = edit(BASE)
    path = _write(tmp_path, text)
    with pytest.raises(SceneError, match=message) as info:
        load_scene(path)
    assert str(info.value).startswith(f"{path}:{_line_of(text, needle, nth)}: ")


def test_not_toml_and_missing_file(tmp_path):
    with pytest.raises(SceneError, match="not valid TOML"):
        load_scene(_write(tmp_path, "formulation = drum\n"))
    with pytest.raises(SceneError, match="no such scene file"):
        load_scene(tmp_path / "absent.toml")


def test_simulate_command_writes_a_readable_results_file(tmp_path):
    import h5py
    from typer.testing import CliRunner

    from qpcontact.commands.cli import app

    path = _write(tmp_path, BASE)
    out = tmp_path / "run.h5"
    res = CliRunner().invoke(app, ["simulate", str(path), "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert "results in" in " ".join(res.output.split())
    with h5py.File(out) as h:
        assert h["forces"].shape == (301, 2) and h["method"].shape == (301,)
        assert np.max(h["certificate_error"][()]) <= 1e-9
    bad = _write(tmp_path, BASE.replace("steps = 300", "steps = -3"), "bad.toml")
    res = CliRunner().invoke(app, ["simulate", str(bad)])
    assert res.exit_code == 2 and "time.steps: must be > 0" in " ".join(res.output.split())
    assert "Traceback" not in res.output


def test_h5dump_reads_the_results_file(tmp_path):
    """HDF5's own tool reads a results file (its gzip-compressed, chunked
    datasets included) and prints the values h5py reads; skipped without
    h5dump (Debian: hdf5-tools)."""
    import shutil
    import subprocess

    import h5py

    from qpcontact.scenes import parse_scene

    if shutil.which("h5dump") is None:
        pytest.skip("h5dump not installed (Debian package hdf5-tools)")
    scene = parse_scene(EXAMPLE.read_text())
    _, run = scene.schema.build(scene)
    path = write_results(scene, run(), tmp_path / "run.h5")
    with h5py.File(path) as h:
        k = int(np.argmax(h["forces"][()].max(axis=1)))      # a step with a contact force
        last = h["forces"][k, :2]
        assert h["forces"].compression == "gzip" and last.max() > 0
    out = subprocess.run(["h5dump", "-d", "/forces", "-s", f"{k},0", "-c", "1,2", str(path)],
                         capture_output=True, text=True, check=True).stdout
    data = out.split("DATA {")[1].split("}")[0].split(":")[1]
    np.testing.assert_allclose([float(v) for v in data.split(",") if v.strip()], last,
                               rtol=1e-5)


def test_plot_command_draws_from_the_file_alone(tmp_path):
    """The figures come from the HDF5 file: the scene file is deleted first."""
    from typer.testing import CliRunner

    from qpcontact.commands.cli import app

    scene = _write(tmp_path, BASE)
    out = tmp_path / "run.h5"
    assert CliRunner().invoke(app, ["simulate", str(scene), "--out", str(out)]).exit_code == 0
    scene.unlink()
    res = CliRunner().invoke(app, ["plot", str(out), "--out", str(tmp_path / "fig")])
    assert res.exit_code == 0, res.output
    for name in ("forces.png", "peaks.png", "energy.png"):
        assert (tmp_path / "fig" / name).stat().st_size > 10_000
    res = CliRunner().invoke(app, ["plot", str(tmp_path / "nothing.h5")])
    assert res.exit_code == 2 and "no such file" in " ".join(res.output.split())


@pytest.mark.parametrize("example, edit, steps, must_hold", [
    # the drum: its state is two displacement vectors, the forces (damped set,
    # bpp's warm start), the dissipation, the methods, the fallbacks
    # (each takes minutes of subprocess runs: make test-all)
    pytest.param("drum.toml", ("steps = 5000", "steps = 8000"), 8000, ("forces", "energy/viscous"),
                 marks=pytest.mark.slow),
    # a mechanism on the shared contact stepper: (q, v) and the penalty mu in use
    # (five runs of a subprocess: 70-200 s on a shared machine, make test-all too)
    pytest.param("pellets.toml", ("steps = 800", "steps = 500"), 500, ("reactions", "mu"),
                 marks=pytest.mark.slow),
    # a tree with compliant contacts: the automatic mu (c / 2 max|A|, A changing with
    # the configuration) must be restored, not re-chosen, for the bits to agree
    pytest.param("chain.toml", ('effects = ["gravity", "joint_damping"]',
                                'effects = ["gravity", "joint_damping", "compliance"]\n'
                                '[effect.compliance]\ncompliance = 1e-6\n#'), 1200,
                 ("reactions", "mu", "energy/kinetic"), marks=pytest.mark.slow),
], ids=["drum", "mechanism", "tree"])
def test_kill_and_resume_is_bit_identical(tmp_path, example, edit, steps, must_hold):
    """`qpcontact simulate` killed (SIGKILL) at random moments, three times
    (each once its checkpoints pass a random step, then after a random delay),
    then resumed to the end: every array in the file equals an
    uninterrupted run's, bit for bit; after each kill the file is readable
    and holds a checkpoint."""
    import os
    import signal
    import subprocess
    import sys
    import time

    import h5py

    text = EXAMPLE.with_name(example).read_text()
    assert edit[0] in text
    scene = _write(tmp_path, text.replace(*edit))
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    cmd = [sys.executable, "-m", "qpcontact", "simulate", str(scene), "--checkpoint-seconds", "0.3"]
    whole, parts = tmp_path / "whole.h5", tmp_path / "parts.h5"
    subprocess.run(cmd + ["--out", str(whole)], check=True, env=env, capture_output=True)
    rng = np.random.default_rng(7)
    killed_mid_run = 0

    def completed():
        with h5py.File(parts) as h:           # readable at every moment (atomic renames)
            return int(h.attrs["completed_steps"])
    for attempt in range(3):
        # killed once its checkpoints pass a random step of this attempt's third of
        # the run: mid-run whatever the machine's speed or load (fixed sleeps landed
        # after the end on a fast machine, before any checkpoint on a loaded one)
        target = int(steps * (attempt + rng.uniform(0.2, 0.8)) / 3)
        proc = subprocess.Popen(cmd + ["--out", str(parts), "--resume"], env=env,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        while proc.poll() is None and not (parts.exists() and completed() >= target):
            time.sleep(0.01)
        time.sleep(rng.uniform(0.0, 0.3))        # a random moment between checkpoints
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        if parts.exists():
            killed_mid_run += completed() < steps
    assert killed_mid_run >= 1, "no kill landed mid-run: the test proved nothing"
    subprocess.run(cmd + ["--out", str(parts), "--resume"], check=True, env=env,
                   capture_output=True)
    with h5py.File(whole) as a, h5py.File(parts) as b:
        assert a.attrs["completed_steps"] == b.attrs["completed_steps"] == steps
        names = []
        a.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
        assert set(must_hold) <= set(names)
        for name in names:
            x, y = a[name][()], b[name][()]
            assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), name
    assert not list(tmp_path.glob("*.tmp"))


def test_resume_refuses_a_changed_scene(tmp_path):
    from typer.testing import CliRunner

    from qpcontact.commands.cli import app

    scene = _write(tmp_path, BASE)
    out = tmp_path / "run.h5"
    assert CliRunner().invoke(app, ["simulate", str(scene), "--out", str(out)]).exit_code == 0
    scene.write_text(BASE.replace("ratio = 0.05", "ratio = 0.06"))
    res = CliRunner().invoke(app, ["simulate", str(scene), "--out", str(out), "--resume"])
    assert res.exit_code == 2 and "different scene text" in " ".join(res.output.split())


def test_vary_scene_edits_the_text_in_place():
    from qpcontact.scenes import parse_scene, vary_scene

    t = vary_scene(BASE, "effect.damping.ratio", "0.08")
    assert "ratio = 0.08" in t and "ratio = 0.05" not in t
    t = vary_scene(t, "logs.1.diameter", "0.2")                   # the second [[logs]]
    t = vary_scene(t, "time.steps_per_period", "30")              # absent key, existing table
    t = vary_scene(t, "solver.method", '"lemke"')                 # absent table
    sc = parse_scene(t)
    assert sc.effect_params["damping"]["ratio"] == 0.08
    assert [lg["diameter"] for lg in sc.data["logs"]] == [0.12, 0.2]
    assert sc.data["time"]["steps_per_period"] == 30.0 and sc.data["solver"]["method"] == "lemke"
    with pytest.raises(SceneError, match="number 5"):
        vary_scene(BASE, "logs.5.diameter", "0.2")


def test_sweep_command_takes_list_values(tmp_path):
    """`--vary initial.gaps=[..],[..]`: commas inside brackets belong to the
    value; each variant's file holds the gaps it was given."""
    import h5py
    from typer.testing import CliRunner

    from qpcontact.commands.cli import app

    scene = _write(tmp_path, BASE.replace("steps = 300", "steps = 20"))
    res = CliRunner().invoke(app, ["sweep", str(scene), "--vary",
                                   "initial.gaps=[0.02, 0.01],[0.03,0.004]",
                                   "--out", str(tmp_path / "sw")])
    assert res.exit_code == 0, res.output
    files = sorted((tmp_path / "sw").glob("*.h5"))
    assert len(files) == 2
    first_gaps = set()
    for f in files:
        with h5py.File(f) as h:
            first_gaps.add(tuple(np.round(h["gaps"][0], 6)))
    assert first_gaps == {(0.02, 0.01), (0.03, 0.004)}
    res = CliRunner().invoke(app, ["sweep", str(scene), "--vary", "initial.gaps=[0.02,0.01"])
    assert res.exit_code == 2 and "unclosed bracket" in " ".join(res.output.split())


@pytest.mark.slow
def test_sweep_on_dask_equals_the_serial_sweep(tmp_path):
    """Three variants of a short scene, serially and on a local Dask cluster
    of two processes: the same files, array for array, and the same summary."""
    import csv

    import h5py

    from qpcontact.scenes import sweep

    scene = _write(tmp_path, BASE.replace("steps = 300", "steps = 1500"))   # contacts happen
    vary = {"effect.damping.ratio": ["0.02", "0.05", "0.1"], "time.steps_per_period": ["30", "40", "50"]}
    serial = sweep(scene, vary, tmp_path / "serial", progress=False)
    dask = sweep(scene, vary, tmp_path / "dask", workers=2, progress=False)
    assert serial == dask and len(serial) == 3
    assert serial[1]["effect.damping.ratio"] == "0.05"
    peaks = [r["peak_force_0 [N]"] for r in serial]
    assert len(set(peaks)) == 3 and min(peaks) > 0              # the variants differ
    for r in serial:
        with h5py.File(tmp_path / "serial" / f"{r['variant']}.h5") as a, \
                h5py.File(tmp_path / "dask" / f"{r['variant']}.h5") as b:
            for name in ("forces", "gaps", "displacements", "energy/numerical"):
                assert np.array_equal(a[name][()], b[name][()]), name
            assert "ratio = " + r["effect.damping.ratio"] in a["scene"][()].decode()
    rows = list(csv.DictReader(open(tmp_path / "serial" / "summary.csv")))
    assert [float(x["peak_force_0 [N]"]) for x in rows] == peaks
    # the grid's count needs no contacts: the short scene
    grid = sweep(_write(tmp_path, BASE, "short.toml"),
                 {"effect.damping.ratio": ["0.02", "0.05"], "time.steps_per_period": ["30", "40"]},
                 tmp_path / "grid", grid=True, progress=False)
    assert len(grid) == 4
    with pytest.raises(SceneError, match="differ in length"):
        sweep(scene, {"effect.damping.ratio": ["0.02"], "time.steps": ["10", "20"]},
              tmp_path / "bad", progress=False)
    with pytest.raises(SceneError, match="ratio: expected a number"):
        sweep(scene, {"effect.damping.ratio": ['"high"']}, tmp_path / "bad", progress=False)


@pytest.mark.slow
def test_ramming_scene_file_equals_the_python_scene():
    """examples/scenes/ramming.toml is the penalty paper's ramming scene written as a
    user-defined mechanism: the same motion and reactions as ramming_scene()."""
    from formulations.mechanisms import ramming_scene
    from qpcontact.scenes import parse_scene, vary_scene

    # 700 of the 2500 steps: past the bolt/cartridge impact (~9 ms / 20 µs = 450 steps)
    text = vary_scene(EXAMPLE.with_name("ramming.toml").read_text(), "time.steps", "700")
    scene = parse_scene(text)
    mech, run = scene.schema.build(scene)
    ours = run()
    m, h, steps, lookahead = ramming_scene(effects=("springs",), restitution=0.3)
    ref = m.simulate(h, 700, lookahead=lookahead)
    assert ref.reactions[:, 0].max() > 0                       # the impact is inside
    assert mech.coordinate_names() == m.coordinate_names()
    np.testing.assert_allclose(ours.q, ref.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ours.reactions, ref.reactions, rtol=1e-9,
                               atol=1e-9 * np.abs(ref.reactions).max())
    assert mech.gravity == 0.0 and not any(c.compliance for c in mech.contacts)


def test_mechanism_springs_without_the_effect_point_at_their_table(tmp_path):
    text = EXAMPLE.with_name("ramming.toml").read_text().replace(
        'effects = ["springs"]', "effects = []")
    path = _write(tmp_path, text)
    scene = load_scene(path)
    with pytest.raises(SceneError, match="'springs' is not among the effects") as info:
        scene.schema.build(scene)
    assert str(info.value).startswith(f"{path}:{_line_of(text, '[[springs]]')}: ")


@pytest.mark.slow
def test_pellet_scene_file_equals_the_python_scene():
    """examples/scenes/pellets.toml (a force pulse given by `until`) is the
    penalty paper's pellet scene: the same motion and reactions as pellet_scene() through the
    first impacts."""
    from formulations.mechanisms import pellet_scene
    from qpcontact.scenes import parse_scene, vary_scene

    text = vary_scene(EXAMPLE.with_name("pellets.toml").read_text(), "time.steps", "120")
    scene = parse_scene(text)
    mech, run = scene.schema.build(scene)
    ours = run()
    m, h, steps, lookahead = pellet_scene()
    ref = m.simulate(h, 120, lookahead=lookahead)
    assert (ref.reactions.max(axis=0) > 0).sum() >= 3              # several impacts inside
    assert mech.coordinate_names() == m.coordinate_names()
    np.testing.assert_allclose(ours.q, ref.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ours.reactions, ref.reactions, rtol=1e-9,
                               atol=1e-9 * np.abs(ref.reactions).max())


def test_a_pulse_ends_at_until():
    """A 2 N pulse on a free 1 kg body for t < 0.01 s: v = 2 t up to the pulse's
    end, then constant (the step's update is exact for piecewise-constant force)."""
    from qpcontact.scenes import parse_scene

    scene = parse_scene('formulation = "mechanism"\n[[bodies]]\nname = "b"\nmass = 1.0\n'
                        '[[forces]]\nbody = "b"\nfx = 2.0\nuntil = 0.01\n'
                        '[time]\nh = 0.001\nsteps = 20\n')
    _, run = scene.schema.build(scene)
    res = run()
    t_on = np.minimum(res.t, 0.01)
    np.testing.assert_allclose(res.v[:, 0], 2.0 * t_on, rtol=1e-12, atol=1e-15)


MASS_ON_DAMPER = """formulation = "mechanism"
effects = ["damping"]

[[bodies]]
name = "block"
mass = 2.0
velocity = [1.5, 0.0, 0.0]

[[dampers]]
a = "block"
coefficient = 40.0
point_b = [-1.0, 0.0]

[time]
h = 1e-3
steps = 50
"""


def test_damping_effect_is_what_decays_the_motion():
    """A 2 kg block on a 40 N·s/m damper to the ground: the stepper's update
    (force at the step's start) gives v_n = v_0 (1 - h c/m)^n exactly; without
    the effect no damper is built and the block keeps its speed; dampers given
    without the effect are an error at their table's line."""
    from qpcontact.scenes import parse_scene

    scene = parse_scene(MASS_ON_DAMPER)
    mech, run = scene.schema.build(scene)
    res = run()
    n = np.arange(51)
    np.testing.assert_allclose(res.v[:, 0], 1.5 * (1 - 1e-3 * 40.0 / 2.0) ** n, rtol=1e-12)
    assert len(mech.dampers) == 1

    undamped = MASS_ON_DAMPER.replace('effects = ["damping"]', "effects = []")
    bad = parse_scene(undamped, "bad.toml")
    with pytest.raises(SceneError, match="'damping' is not among the effects") as info:
        bad.schema.build(bad)
    assert str(info.value).startswith(f"bad.toml:{_line_of(undamped, '[[dampers]]')}: ")
    free = parse_scene(undamped.split("[[dampers]]")[0] + "[time]\nh = 1e-3\nsteps = 50\n")
    mech, run = free.schema.build(free)
    assert mech.dampers == [] and np.all(run().v[:, 0] == 1.5)
