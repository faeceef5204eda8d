"""The 2-D drum's books: sliding work as ∫ F_T · slip dt over the step (slip
that stops within a step included), and rigid contacts that keep their gaps.

SI units: m, kg, s, N, J.  References (independent of the code under test):

- a block (a disc held from rolling) sliding on the bottom of a large still
  drum decelerates at μ g and stops after v0/(μ g): friction takes its
  kinetic energy ½ m v0², less the little it rises on the shell, m g Δy (the
  work–energy theorem on the run's own end position);
- hand geometry for the gap a resting disc keeps.
"""

import numpy as np
import pytest

from formulations.drum2d import Discs, Drum2D, Shell
from formulations.drum2d.records import sliding_speed

G = 9.81


def _certified(res):
    assert res.certified.all(), f"uncertified steps {res.uncertified[:5]}"
    assert res.worst_certificate <= 1e-8


def test_sliding_speed_by_hand():
    # linear slip from u⁻ to u⁺: mean |u| over the step
    u0, u1 = np.array([1.0, 1.0, -2.0, 0.0, 3.0]), np.array([0.0, 0.5, 1.0, 0.0, -1.0])
    expect = [0.5, 0.75, (4 + 1) / (2 * 3), 0.0, (9 + 1) / (2 * 4)]
    np.testing.assert_allclose(sliding_speed(u0, u1), expect, rtol=1e-15)


@pytest.mark.parametrize("h, v0", [(5e-3, 1.0), (2e-3, 0.7), (4e-3, 1.3)])
def test_a_block_sliding_to_a_stop_books_its_kinetic_energy_as_sliding_work(h, v0):
    R, d, mu = 50.0, 0.2, 0.4
    rho = R - d / 2
    discs = Discs([d], [[0.0, -rho]], length=1.0, velocities=[[v0, 0.0]], spin_locked=True)
    model = Drum2D(discs, Shell(R), ("friction", "damping"), mu_shell=mu, restitution=0.0)
    stop = v0 / (mu * G)
    res = model.simulate(h, int(stop / h) + 20)
    _certified(res)
    m = discs.masses[0]
    assert np.hypot(*res.velocities[-1, 0]) < 1e-9              # it has stopped
    theta = np.arctan2(res.positions[-1, 0, 0], -res.positions[-1, 0, 1])
    assert 0 < theta < 1e-2
    expect = 0.5 * m * v0 ** 2 - m * G * rho * (1 - np.cos(theta))
    booked = res.sliding_work.sum()
    # all of it is sliding work; the booking of the end slip alone missed
    # ½ μ g h m v0 (2 % at h = 5 ms), the scheme's polygon on the curved shell
    # leaves ~1e-4 to the impact loss
    assert abs(booked - expect) < 5e-4 * expect, (booked, expect)
    assert abs(res.friction_loss.sum() - booked) < 1e-12 * expect
    assert abs(res.impact_loss.sum()) < 5e-4 * expect
    # the block stops within a step: that step's work is its last slip's
    moving = np.hypot(*res.velocities[:, 0].T) > 1e-9
    last = int(np.flatnonzero(moving)[-1])
    v_last = np.hypot(*res.velocities[last, 0])
    assert res.sliding_work[last, 0] == pytest.approx(0.5 * m * v_last ** 2
                                                      - m * G * (res.positions[last + 1, 0, 1]
                                                                 - res.positions[last, 0, 1]),
                                                      rel=1e-4)
