"""The drum engineer's outputs of a 2-D drum run (formulations.drum2d.outputs,
packing, the histograms' rates, the animation's frame interval).

References by hand: a log held from rolling, resting at the friction angle
θ = atan μ on the shell turning under it, slides at the shell's speed ΩR
against the friction force m g sin θ, so the drive's torque is m g sin θ R,
its power m g sin θ ΩR, all of it the log's sliding work (masses from
ρ π d²/4 ℓ written here); a log resting in a still drum is one contact at
every instant whatever the step; the deposit's gaps come from the contact
detection (contacts.py), not from the packing's own arithmetic."""

from __future__ import annotations

import numpy as np
import pytest

from formulations.drum2d import Discs, Drum2D, Shell, find_contacts
from formulations.drum2d.animation import animation_states
from formulations.drum2d.outputs import run_summary
from formulations.drum2d.revolutions import revolutions
from qpcontact.core.errors import InvalidOptionError
from qpcontact.scenes import SceneError, load_scene

G = 9.81


def _sliding_log(length, omega=0.3, R=1.0, d=0.2, mu=0.4, h=2e-3, steps=100, density=700.0):
    theta = np.arctan(mu)
    rho = R - d / 2
    centre = rho * np.array([np.sin(theta), -np.cos(theta)])
    discs = Discs([d], [centre], length=length, density=density, spin_locked=True)
    model = Drum2D(discs, Shell(R, omega=omega), ("friction", "rotation", "damping"),
                   mu_shell=mu, restitution=0.0)
    return model, model.simulate(h, steps, keep_contacts=False)


@pytest.mark.parametrize("length", [1.0, 2.5])
def test_drive_power_torque_and_sliding_work_of_a_log_sliding_at_the_friction_angle(length):
    omega, R, d, mu, density = 0.3, 1.0, 0.2, 0.4, 700.0
    model, res = _sliding_log(length, omega, R, d, mu, density=density)
    assert res.certified.all()
    s = run_summary(res, model.discs, model.omega)
    m = density * np.pi * d ** 2 / 4 * length              # kg, by hand
    F = m * G * np.sin(np.arctan(mu))                      # N, the sliding friction
    power = F * omega * R / length                         # W per metre of drum
    assert s.per == "rev" and s.uncertified_steps == 0
    assert s.drive_power_W_per_m == pytest.approx(power, rel=0.01)
    assert s.drive_torque_Nm_per_m == pytest.approx(F * R / length, rel=0.01)
    assert s.drive_torque_Nm_per_m * omega == pytest.approx(s.drive_power_W_per_m, rel=1e-12)
    T_rev = 2 * np.pi / omega
    assert s.energy_J_per_t == pytest.approx(F * omega * R * T_rev / (m / 1e3), rel=0.01)
    # all the drive goes into the log's sliding (it does not move)
    assert s.sliding_J_per_log == pytest.approx(F * omega * R * T_rev, rel=0.01)
    assert s.sliding_J_per_m2 == pytest.approx(F * omega * R * T_rev / (np.pi * d * length),
                                               rel=0.01)
    assert s.log_mass_t == pytest.approx(m / 1e3, rel=1e-12)
    text = s.table()
    for piece in ("every step certified", "W per metre of drum", "N·m per metre",
                  "J per tonne of logs per revolution", "J per m² of log surface"):
        assert piece in text
    row = s.as_dict()
    assert row["drive torque [N·m/m]"] == s.drive_torque_Nm_per_m
    assert row["sliding/log/rev [J]"] == s.sliding_J_per_log


def _resting_log(h, steps):
    discs = Discs([0.2], [[0.0, -0.9]], length=1.0)
    model = Drum2D(discs, Shell(1.0), ("damping",), restitution=0.0)
    return model.simulate(h, steps, keep_contacts=False)


def test_rates_per_second_do_not_depend_on_the_step():
    a, b = _resting_log(4e-3, 10), _resting_log(2e-3, 20)         # 0.04 s each
    ka = revolutions(a, omega=0.0)[0].forces["log-shell"]
    kb = revolutions(b, omega=0.0)[0].forces["log-shell"]
    assert ka.counts.sum() == 10 and kb.counts.sum() == 20         # counts follow the step
    # one contact at every instant, on either step
    assert ka.at_a_time.sum() == pytest.approx(1.0, rel=1e-12)
    assert kb.at_a_time.sum() == pytest.approx(1.0, rel=1e-12)
    assert ka.per_second.sum() == pytest.approx(10 / 0.04, rel=1e-12)
    assert ka.seconds == pytest.approx(0.04) and ka.step_s == pytest.approx(4e-3)


def test_a_still_drum_reports_rates_per_second_and_no_torque():
    res = _resting_log(2e-3, 5)
    s = run_summary(res, Discs([0.2], [[0.0, -0.9]], length=1.0), 0.0)
    assert s.per == "s" and s.drive_torque_Nm_per_m is None
    assert "drive torque [N·m/m]" not in s.as_dict()
    assert "sliding/log/s [W]" in s.as_dict()


def test_frames_by_interval():
    t = np.arange(101) * 0.01
    h = {"contacts/step": np.repeat(np.arange(1, 100, 2), 3), "t": t}   # kept: states 2, 4, ...
    states = animation_states(h, interval=0.04, max_frames=1000)
    assert np.array_equal(states, np.arange(2, 101, 4))
    assert np.allclose(np.diff(t[states]), 0.04)
    # an interval between kept states: the first kept state at or after each mark
    states = animation_states(h, interval=0.05, max_frames=1000)
    assert np.allclose(np.diff(t[states]), 0.06)           # never closer than asked
    for bad in (0.0, -0.1, np.nan, np.inf):
        with pytest.raises(InvalidOptionError, match="frame interval"):
            animation_states(h, interval=bad)


SCENE = """formulation = "drum2d"
effects = ["gravity", "rotation", "damping"]

[drum]
diameter = {diameter}

[lifters]
count = 4
height = 0.1
thickness = 0.04

[logs]
count = {count}
diameter_min = {dmin}
diameter_max = {dmax}
seed = 2
length = 1.0
clearance = 0.002
{packing}

[effect.rotation]
speed = 0.15

[effect.damping]
restitution = 0.3

[time]
step = 0.002
duration = {duration}

[output]
{output}
"""


def _scene(tmp_path, name="s.toml", diameter=3.5, count=120, dmin=0.12, dmax=0.28,
           packing="", duration=0.02, output=""):
    p = tmp_path / name
    p.write_text(SCENE.format(diameter=diameter, count=count, dmin=dmin, dmax=dmax,
                              packing=packing, duration=duration, output=output))
    return load_scene(p)


def test_a_deposit_fits_logs_the_lattice_cannot(tmp_path):
    with pytest.raises(SceneError, match='packing = "deposit"'):
        sc = _scene(tmp_path)
        sc.schema.build(sc)
    sc = _scene(tmp_path, packing='packing = "deposit"')
    model, _ = sc.schema.build(sc)
    d = model.discs
    assert d.n == 120
    assert d.diameters.min() >= 0.12 and d.diameters.max() <= 0.28
    # the gaps by the stepper's own contact detection: none under the clearance
    c = find_contacts(d, model.shell, 0.0, 0.0, 0.01)
    assert c.m > 100                                      # a packed bed, not a scatter
    assert c.gap.min() >= 0.002 - 1e-9
    # denser than the lattice: the bed's top stays below the axis
    assert (d.positions[:, 1] + d.diameters / 2).max() < 0.5
    with pytest.raises(SceneError, match="room for"):
        sc = _scene(tmp_path, count=250, packing='packing = "deposit"')
        sc.schema.build(sc)
    with pytest.raises(SceneError, match="lattice, deposit"):
        sc = _scene(tmp_path, packing='packing = "random"')
        sc.schema.build(sc)


@pytest.mark.parametrize("output, message", [
    ("contacts_every = 5\nframe_interval = 0.004", r"at least contacts_every × step"),
    ("contacts_every = 0\nframe_interval = 0.01", r"contacts_every >= 1"),
    ("contacts_every = 1\nframe_interval = 1.0", r"the run's duration"),
    ("frame_interval = -0.1", r"frame_interval"),
    ("frame_interval = nan", r"frame_interval"),
])
def test_bad_frame_intervals_are_refused_with_the_fix(tmp_path, output, message):
    with pytest.raises(SceneError, match=message):
        sc = _scene(tmp_path, diameter=2.0, count=10, dmin=0.18, dmax=0.24, output=output)
        sc.schema.build(sc)


@pytest.mark.slow
def test_simulate_prints_the_summary_and_plot_honours_the_frame_interval(tmp_path):
    import h5py
    from typer.testing import CliRunner

    from qpcontact.commands.cli import app

    scene = tmp_path / "drum.toml"
    # deposited: the logs rest on the shell (2 mm clear) from the start
    scene.write_text(SCENE.format(diameter=2.0, count=10, dmin=0.18, dmax=0.24,
                                  packing='packing = "deposit"', duration=0.1,
                                  output="contacts_every = 2\nframe_interval = 0.02"))
    out = tmp_path / "drum.h5"
    res = CliRunner().invoke(app, ["simulate", str(scene), "--out", str(out)])
    assert res.exit_code == 0, res.output
    text = " ".join(res.output.split())
    for piece in ("every step certified", "peak normal force", "W per metre of drum",
                  "J per tonne of logs per revolution", "sliding work"):
        assert piece in text, text
    res = CliRunner().invoke(app, ["plot", str(out), "--out", str(tmp_path / "plots")])
    assert res.exit_code == 0, res.output
    frames = sorted((tmp_path / "plots" / "animation").glob("frame_*.png"))
    with h5py.File(out) as f:
        assert float(f["output/frame_interval"][()]) == 0.02
        kept = np.unique(f["contacts/step"][()]) + 1
        drawn = f["t"][()][animation_states(f, interval=0.02, max_frames=100)]
    assert len(frames) == drawn.size >= 3 and kept.size > 2 * drawn.size
    assert np.allclose(np.diff(drawn), 0.02)
