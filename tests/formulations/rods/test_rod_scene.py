"""The rod's scene (formulation "rod"): SI units in and out, checked against
Euler-Bernoulli's linear theory (period, suddenly applied load, static sag
under gravity) and the follower load's boundary condition."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from qpcontact.scenes import parse_scene
from tests.helpers.paths import SCENES

EXAMPLE = SCENES / "rod.toml"
BETA1 = 1.8751040687119611            # first root of 1 + cos β cosh β = 0 (cantilever)
L, EI, RHOA = 0.8, 2.77, 0.314
T1 = 2 * np.pi / BETA1 ** 2 * L ** 2 * np.sqrt(RHOA / EI)     # first period [s]


def _scene(effects="", extra="", preload=0.0, per_period=80, periods=3.0):
    h = float(T1 / per_period)
    return parse_scene(f"""formulation = "rod"
effects = [{effects}]
{extra}
[rod]
length = {L}
EI = {EI}
mass_per_length = {RHOA}

[initial]
preload = {preload}

[time]
h = {h!r}
steps = {int(round(periods * per_period))}
""")


def _run(scene):
    model, run = scene.schema.build(scene)
    return model, run()


def test_small_vibration_has_the_euler_bernoulli_period_in_seconds():
    """Released from a 0.01 N tip load's deflection: zero crossings of the tip
    every T₁ = 2π/β₁² · L²√(ρA/EI) seconds."""
    _, res = _run(_scene(preload=0.01))
    y, t = res.y[:, -1], res.t
    i = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    crossings = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
    assert len(crossings) >= 2
    assert abs(np.diff(crossings).mean() / T1 - 1) < 3e-3


def test_suddenly_applied_dead_load_doubles_the_static_deflection_in_metres():
    """A 0.01 N dead tip load applied at t = 0 to the straight rod: the tip
    swings to about twice PL³/3EI [m] (first mode)."""
    scene = _scene('"dead_load"', "[effect.dead_load]\nfy = -0.01\n", per_period=160,
                   periods=1.2)
    _, res = _run(scene)
    ratio = res.y[:, -1].min() / (-0.01 * L ** 3 / (3 * EI))
    assert 1.95 < ratio < 2.02, ratio


def test_gravity_sags_the_rod_about_its_static_deflection():
    """With gravity only, released straight: the tip oscillates about the
    static sag ρA g L⁴/8EI (its time average over whole first-mode periods)."""
    model, res = _run(_scene('"gravity"', periods=4.0))
    y = res.y[:, -1]
    sag = RHOA * 9.81 * L ** 4 / (8 * EI)
    k = int(round(4.0 * 80))
    mean = np.trapezoid(y[:k + 1], res.t[:k + 1]) / res.t[k]
    assert abs(mean / -sag - 1) < 0.02, mean / -sag
    assert res.potential[0] == 0.0 and np.all(res.potential[1:] < 0)


def test_follower_load_stays_perpendicular_to_the_tip_until_it_ends():
    """The internal force at the tip equals P(sin θ(1), −cos θ(1)) at every
    step while t < until, and zero after."""
    scene = _scene('"follower_load"', "[effect.follower_load]\nforce = 3.0\nuntil = 0.1\n",
                   per_period=40, periods=1.0)
    model, res = _run(scene)
    Y = np.array(res.motion.y)
    F = Y[:, 4:6, -1] * EI / L ** 2                     # tip internal force [N]
    th = Y[:, 0, -1]
    on = (res.t > 0) & (res.t < 0.1)
    assert on.sum() >= 3 and np.abs(th[on]).max() > 0.05     # the tip turned
    np.testing.assert_allclose(F[on], 3.0 * np.column_stack([np.sin(th[on]), -np.cos(th[on])]),
                               atol=1e-9)
    np.testing.assert_allclose(F[res.t > 0.1], 0.0, atol=1e-9)


@pytest.mark.parametrize("effects, built", [
    ("", {"distributed": (0.0, 0.0), "dead_load": None, "follower_load": None}),
    ('"gravity"', {"dead_load": None, "follower_load": None}),
])
def test_rod_assembles_only_the_named_loads(effects, built):
    model, _ = _scene(effects).schema.build(_scene(effects))
    for key, value in built.items():
        if value is None:
            assert model[key] is None, key
        else:
            assert tuple(model[key]) == value
    if "gravity" in effects:
        assert model["distributed"][1] < 0


def test_rod_example_runs_and_plots(tmp_path):
    from qpcontact.scenes import plot_results, vary_scene, write_results

    text = vary_scene(EXAMPLE.read_text(), "time.steps", "40")
    scene = parse_scene(text, "rod.toml")
    _, run = scene.schema.build(scene)
    res = run()
    path = write_results(scene, res, tmp_path / "rod.h5", completed=40, total=40)
    figs = plot_results(path, tmp_path / "figs")
    assert [Path(f).name for f in figs] == ["rod.png"]
    # inextensible: every centreline keeps the rod's length
    seg = np.hypot(np.diff(res.x, axis=1), np.diff(res.y, axis=1)).sum(axis=1)
    np.testing.assert_allclose(seg, 1.0, rtol=2e-3)


def test_extensibility_stretches_the_rod_by_pl_over_ea():
    """A 500 N axial tension on an extensible rod (EA = 1e5 N): Park's method
    damps the fast axial waves and the tip settles at L(1 + P/EA) — the
    inextensible rod (no effect) keeps x_tip = L; the transverse shape stays
    straight."""
    extra = "[effect.dead_load]\nfx = 500.0\n[effect.extensibility]\nEA = 1e5\n"
    model, res = _run(_scene('"dead_load", "extensibility"', extra, periods=0.5))
    assert model["extensibility"] == EI / (1e5 * L * L)
    np.testing.assert_allclose(res.x[-1, -1], L * (1 + 500.0 / 1e5), rtol=1e-7)
    assert np.abs(res.y).max() < 1e-12
    stiff, res0 = _run(_scene('"dead_load"', "[effect.dead_load]\nfx = 500.0\n", periods=0.5))
    assert stiff["extensibility"] == 0.0
    np.testing.assert_allclose(res0.x[-1, -1], L, rtol=1e-12)


def test_extensible_rod_released_from_its_own_static_state_stays_there():
    """Released from the extensible static state under a 1 N tip load and kept
    under the same load (dead_load fy = -1 N): the tip does not move — the
    start is the dynamics' own equilibrium (cantilever_general's statics).
    The floor, 3e-6 of the deflection, is the static solution's interpolation
    onto the march's mesh (the inextensible rod shows the same); starting
    from the inextensible state instead would move the tip by 2e-4 m, 4e-3."""
    extra = "[effect.dead_load]\nfy = -1.0\n[effect.extensibility]\nEA = 50.0\n"
    _, res = _run(_scene('"dead_load", "extensibility"', extra, preload=1.0, periods=0.5))
    drift = np.abs(res.y[:, -1] - res.y[0, -1]).max()
    assert drift < 1e-5 * abs(res.y[0, -1]), drift
