"""The drum formulation (Kolesnikov 2013) against independent references: the analytic
impact of a mass on a linear spring, statics of a stack, energy, and every
step's LCP solved by other methods."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import qpcontact
from formulations.drum import (EFFECTS, GRAVITY, Drum, Log, StepSizeWarning, log_half_stiffness,
                               log_mass)
from qpcontact import InvalidProblemError

G = GRAVITY


def _analytic_peak(m, k, h):
    """Mass m on a linear spring k hitting at v = sqrt(2 g h), gravity on."""
    v = np.sqrt(2 * G * h)
    return m * G + np.sqrt((m * G) ** 2 + k * m * v * v)


def _drop(log, h, per_period, shell_stiffness=None, effects=("gravity",)):
    drum = Drum([log], [h], shell_stiffness=shell_stiffness, effects=effects)
    T = drum.contact_periods()[0]
    tau = T / per_period
    steps = int((np.sqrt(2 * h / G) + 0.75 * T) / tau)
    return drum.simulate(tau, steps)


def test_engineering_helpers():
    assert log_mass(0.2, 1.0, 1000.0) == pytest.approx(1000.0 * np.pi * 0.01)
    assert log_half_stiffness(0.15, 1.2, 0.4e9) == pytest.approx(2 * 0.4e9 * 1.2)
    lg = Log.from_wood(0.15, 1.2, density=450.0, modulus=0.8e9, damping_ratio=0.1)
    assert lg.mass == pytest.approx(450.0 * np.pi * 0.15 ** 2 / 4 * 1.2)
    assert lg.damping == pytest.approx(2 * 0.1 * np.sqrt(lg.mass * lg.stiffness))
    with pytest.raises(InvalidProblemError, match="positive"):
        Log.from_wood(-0.1, 1.2)


@pytest.mark.slow
def test_single_log_drop_peak_force_converges_at_first_order(record_property):
    log = Log.from_wood(0.15, 1.2)
    h = 0.002
    exact = _analytic_peak(log.mass, log.stiffness, h)
    errors = []
    for per_period in (20, 40, 80, 160):
        res = _drop(log, h, per_period)
        assert res.summary().max_certificate_error < 1e-9
        errors.append(float(abs(res.forces[:, 0].max() / exact - 1.0)))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    record_property("relative_errors", [float(e) for e in errors])
    record_property("observed_orders", [float(o) for o in orders])
    assert np.all(np.diff(errors) < 0)
    assert 0.8 < orders[-1] < 1.2 and 0.8 < orders[-2] < 1.2
    assert errors[-1] < 0.04


@pytest.mark.slow
def test_elastic_shell_uses_series_stiffness():
    log = Log.from_wood(0.12, 1.2)
    k_shell = 0.5 * log.stiffness
    res = _drop(log, 0.001, 320, shell_stiffness=k_shell, effects=("gravity", "shell_elasticity"))
    k_series = 1.0 / (1.0 / log.stiffness + 1.0 / k_shell)
    exact = _analytic_peak(log.mass, k_series, 0.001)
    assert res.forces[:, 0].max() == pytest.approx(exact, rel=0.025)  # first-order error ~1.5% here
    rigid = _drop(log, 0.001, 320)
    assert rigid.forces[:, 0].max() > res.forces[:, 0].max()


@pytest.mark.slow
def test_damping_lowers_rebound_and_energy_never_grows():
    log = Log.from_wood(0.15, 1.2, damping_ratio=0.1)
    h = 0.02
    res = _drop(log, h, 80, effects=("gravity", "damping"))
    v_impact = np.sqrt(2 * G * h)
    in_contact = np.flatnonzero(res.forces[:, 0] > 0)
    after = res.velocities[in_contact[-1] + 1:, 0]
    assert after.size and after.max() < 0.95 * v_impact      # rebound slower than impact
    e = res.energy()
    total = e["mechanical"]
    assert np.all(np.diff(total) <= 1e-9 * abs(total).max())  # non-increasing
    assert e["viscous"][-1] > 0
    np.testing.assert_allclose(total + e["viscous"] + e["numerical"], total[0], rtol=0,
                               atol=1e-9 * abs(total).max())


def test_stack_at_rest_carries_the_weight_above_each_contact():
    rng = np.random.default_rng(3)
    logs = [Log.from_wood(d, 1.2, damping_ratio=0.2) for d in rng.uniform(0.1, 0.2, 6)]
    drum = Drum(logs, np.zeros(6), effects=("gravity", "damping"))
    T = drum.contact_periods().max()
    with pytest.warns(StepSizeWarning, match="too large"):
        res = drum.simulate(50 * T, 40)  # quasi-static steps: dynamics decay ~1/(ωτ) per step
    weight_above = G * np.cumsum([lg.mass for lg in logs][::-1])[::-1]
    np.testing.assert_allclose(res.forces[-1], weight_above, rtol=1e-9)


def _twenty_logs(seed=0, **kw):
    rng = np.random.default_rng(seed)
    logs = [Log.from_wood(d, 1.2, **kw) for d in rng.uniform(0.1, 0.2, 20)]
    return logs, rng.uniform(0.0, 0.002, 20), -rng.uniform(0.0, 1.0, 20)


@pytest.mark.slow
def test_twenty_log_drop_every_step_cross_validated():
    logs, gaps, v0 = _twenty_logs()
    drum = Drum(logs, gaps, v0)
    tau = drum.contact_periods().min() / 40
    others = [m for m in ("energy", "clarabel", "piqp", "osqp", "daqp", "quadprog")
              if m in qpcontact.methods()]
    assert len([m for m in others if m != "energy"]) >= 3
    checked = []

    misses = []

    def check(n, lcp, sol):
        assert sol.ok and sol.method == "bpp"
        scale = max(np.abs(sol.z).max(), np.abs(lcp.q).max() / lcp.matrix_scale)
        certified = 0
        for m in others:
            other = qpcontact.solve(lcp, method=m, accuracy="high")
            if not other.ok:
                # Interior-point backends sit near 1e-9 at contacts whose gap is a
                # micrometre (judged on their own scale): reported, never wrong.
                assert other.status == "inaccurate" and m not in ("energy", "daqp", "quadprog"), \
                    (n, m, other.message)
                misses.append((n, m))
                continue
            certified += 1
            assert np.abs(other.z - sol.z).max() <= 1e-6 * scale, (n, m)
        assert certified >= len(others) - 1, (n, misses)
        checked.append(n)

    res = drum.simulate(tau, 250, on_step=check)
    assert len(checked) == 250
    assert len(misses) <= 5, misses
    assert res.forces.max() > 0 and res.summary().collisions_per_log.sum() > 5


def test_no_damping_effect_equals_zero_damping_with_less_assembled():
    logs, gaps, v0 = _twenty_logs(1)
    without = Drum(logs, gaps, v0, effects=("gravity",))
    zero = Drum(logs, gaps, v0, effects=("gravity", "damping"))
    tau = without.contact_periods().min() / 30
    a, b = without.simulate(tau, 200), zero.simulate(tau, 200)
    np.testing.assert_array_equal(a.forces, b.forces)
    np.testing.assert_array_equal(a.displacements, b.displacements)
    assert without.damping is None
    assert without.assembled_nbytes(tau) < zero.assembled_nbytes(tau)


def test_effect_errors_name_what_is_known():
    log = Log.from_wood(0.15, 1.2)
    with pytest.raises(InvalidProblemError, match="shell_elasticity") as e:
        Drum([log], [0.0], effects=("gravity", "friction"))
    assert all(name in str(e.value) for name in EFFECTS)
    damped = Log.from_wood(0.15, 1.2, damping_ratio=0.1)
    with pytest.raises(InvalidProblemError, match="'damping' is not among the effects"):
        Drum([damped], [0.0])
    with pytest.raises(InvalidProblemError, match="shell_elasticity"):
        Drum([log], [0.0], shell_stiffness=1e9)
    with pytest.raises(InvalidProblemError, match="gaps"):
        Drum([log], [-0.1])
    with pytest.raises(InvalidProblemError, match="gaps"):
        Drum([log, log], [0.0])


def test_step_matrix_is_spd_and_banded():
    logs, gaps, v0 = _twenty_logs(2, damping_ratio=0.05)
    drum = Drum(logs, gaps, v0, effects=("gravity", "damping"))
    A = drum.step_matrix(1e-5, damped=np.ones(20, bool)).toarray()
    np.testing.assert_array_equal(A, A.T)
    assert np.linalg.eigvalsh(A).min() > 0
    assert np.count_nonzero(np.triu(A, 2)) == 0


def test_step_size_warning_and_result_file(tmp_path):
    drum = Drum([Log.from_wood(0.15, 1.2)], [0.01])
    T = drum.contact_periods()[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        drum.check_step(T / 40)
    with pytest.warns(StepSizeWarning):
        drum.check_step(T / 5)
    res = drum.simulate(T / 40, 50)
    path = res.save(tmp_path / "run.npz")
    data = np.load(path)
    np.testing.assert_array_equal(data["forces"], res.forces)
    assert not list(tmp_path.glob("*.tmp*"))
