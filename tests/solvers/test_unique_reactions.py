"""The unique representative of reactions that are not unique: a rigid body on
redundant contacts.  References by hand statics — a rigid bar on equal
supports carries P/n ± M x/Σx² (the pseudo-inverse of its statics), on
springs of stiffness k_i = 1/c_i the compatible split k_i (a + b x_i)
(Menabrea) — and, on a peer's pile, the agreement of answers that differ."""

from __future__ import annotations

import numpy as np
import pytest

import qpcontact
from qpcontact import FrictionProblem
from qpcontact.core.errors import InvalidOptionError, InvalidProblemError
from tests.helpers.paths import data_dir

XS = np.array([-1.0, 0.0, 2.0])       # contact abscissae (m), unequally spaced
P, E, F = 9.0, 0.3, 1.2                # weight (N), its eccentricity (m), a side push (N)


def bar(push=F, mu=0.5):
    """A rigid bar (dofs v_x, v_y, ω) on three point contacts at its own
    height (so the side forces make no moment), loaded by P at x = E and
    pushed sideways; one step of unit length, so impulses read as forces."""
    M = np.diag([2.0, 2.0, 3.0])
    H = np.zeros((3, 2 * XS.size))
    for i, x in enumerate(XS):
        H[:, 2 * i] = [0.0, 1.0, x]          # normal: upward force at x
        H[:, 2 * i + 1] = [1.0, 0.0, 0.0]    # tangent: along x
    f = np.array([push, -P, -P * E])
    return FrictionProblem.global_problem(M, H, f, np.zeros(2 * XS.size), [mu] * XS.size, 2)


def linear_split(k):
    """Normal forces k_i (a + b x_i) with Σ = P and Σ x r = P E: a rigid bar's
    compatible deflections a + b x_i on springs k_i, by hand."""
    A = np.array([[k.sum(), (k * XS).sum()], [(k * XS).sum(), (k * XS ** 2).sum()]])
    a, b = np.linalg.solve(A, [P, P * E])
    return k * (a + b * XS)


def test_a_bar_on_three_supports_is_not_isolated_and_its_minimum_norm_split_is_statics():
    prob = bar()
    sol = qpcontact.solve(prob, accuracy=1e-10)
    assert sol.ok and sol.certificate.isolated is False
    assert "not unique" in repr(sol)
    rep = qpcontact.unique_reactions(prob, sol)
    assert rep.ok and rep.stats["null_dimension"] == 3, rep.message
    R = rep.r.reshape(-1, 2)
    np.testing.assert_allclose(R[:, 0], linear_split(np.ones(3)), rtol=0, atol=1e-10 * P)
    np.testing.assert_allclose(R[:, 1], -F / 3, rtol=0, atol=1e-10 * P)


def test_compliances_give_the_elastic_split():
    c = np.array([1.0, 2.0, 0.5])         # m/N: the middle support twice as soft
    prob = bar()
    rep = qpcontact.unique_reactions(prob, qpcontact.solve(prob, accuracy=1e-10), compliance=c)
    k = 1.0 / c
    R = rep.r.reshape(-1, 2)
    assert rep.ok, rep.message
    np.testing.assert_allclose(R[:, 0], linear_split(k), rtol=0, atol=1e-10 * P)
    np.testing.assert_allclose(R[:, 1], -F * k / k.sum(), rtol=0, atol=1e-10 * P)


def test_a_sliding_bar_keeps_every_contact_on_its_ray():
    """Pushed at 2 μP the bar slides: each r_T = -μ r_N (friction against the
    slip), and the normals split as on equal supports."""
    mu = 0.5
    prob = bar(push=2 * mu * P, mu=mu)
    sol = qpcontact.solve(prob, accuracy=1e-10)
    assert sol.ok and sol.u[1] > 0          # the first contact slips along +x
    rep = qpcontact.unique_reactions(prob, sol)
    R = rep.r.reshape(-1, 2)
    assert rep.ok and set(rep.stats["sliding"]) == {0, 1, 2}, rep.message
    np.testing.assert_allclose(R[:, 0], linear_split(np.ones(3)), rtol=0, atol=1e-10 * P)
    np.testing.assert_allclose(R[:, 1], -mu * R[:, 0], rtol=0, atol=1e-12 * P)


def test_a_plate_on_four_legs_splits_by_the_kern_formula():
    """A rigid plate on legs at (±1, ±0.5), its load P at (0.2, 0.1) and a
    side push through its plane: r_N = P/4 + P e_x x/Σx² + P e_y y/Σy², and
    each leg a quarter of the push."""
    legs = np.array([[1.0, 0.5], [-1.0, 0.5], [-1.0, -0.5], [1.0, -0.5]])
    ex, ey, push = 0.2, 0.1, np.array([0.8, -0.4])
    H = np.zeros((6, 12))
    for i, (x, y) in enumerate(legs):
        p = np.array([x, y, 0.0])
        for k, n in enumerate(np.eye(3)[[2, 0, 1]]):     # normal e_z, tangents e_x, e_y
            H[:, 3 * i + k] = np.concatenate([n, np.cross(p, n)])
    load = np.array([push[0], push[1], -P])
    f = np.concatenate([load, np.cross([ex, ey, 0.0], [0.0, 0.0, -P])])   # the push at the centre
    prob = FrictionProblem.global_problem(np.diag([2, 2, 2, 1, 1, 1.0]), H, f, np.zeros(12),
                                          [0.6] * 4, 3)
    sol = qpcontact.solve(prob, accuracy=1e-10)
    rep = qpcontact.unique_reactions(prob, sol)
    assert sol.ok and rep.ok and rep.stats["null_dimension"] == 6, rep.message
    R = rep.r.reshape(-1, 3)
    x, y = legs.T
    np.testing.assert_allclose(R[:, 0], P / 4 + P * ex * x / (x @ x) + P * ey * y / (y @ y),
                               rtol=0, atol=1e-9 * P)
    np.testing.assert_allclose(R[:, 1:], np.tile(-push / 4, (4, 1)), rtol=0, atol=1e-9 * P)


def test_unique_reactions_are_returned_as_they_are():
    prob = FrictionProblem(np.array([[2.0, 0.1], [0.1, 1.0]]), np.array([-1.0, 0.2]), [0.3], 2)
    sol = qpcontact.solve(prob, accuracy=1e-10)
    rep = qpcontact.unique_reactions(prob, sol)
    assert sol.certificate.isolated and rep.stats["null_dimension"] == 0
    np.testing.assert_array_equal(rep.r, sol.r)


def test_misuse_is_named():
    prob = bar()
    sol = qpcontact.solve(prob, accuracy=1e-10)
    with pytest.raises(InvalidOptionError, match=r"compliance\[1\] = -1"):
        qpcontact.unique_reactions(prob, sol, compliance=[1, -1, 1])
    with pytest.raises(InvalidOptionError, match="one number per contact"):
        qpcontact.unique_reactions(prob, sol, compliance=[1, 2])
    with pytest.raises(InvalidProblemError, match="FrictionProblem"):
        qpcontact.unique_reactions(qpcontact.LCP([[1.0]], [-1.0]), sol)
    sol.ok = False
    with pytest.raises(InvalidOptionError, match="ok FrictionSolution"):
        qpcontact.unique_reactions(prob, sol)


def test_a_peers_box_stack_gets_one_representative_from_answers_that_differ():
    """Siconos's Box_Stacks (82 contacts, boxes on four corners each): the
    methods' certified answers differ by 4-9 % of the largest reaction; their
    velocities agree, and so must the representative."""
    path = data_dir("siconos-fc") / "Box_Stacks-i0122-82-5.hdf5"
    if not path.exists():
        pytest.skip(f"Siconos friction data not found at {path.parent}")
    from qpcontact.io import read_problem

    prob = read_problem(path)
    answers = {m: qpcontact.solve(prob, m, accuracy=1e-8) for m in ("nsgs", "newton")}
    assert all(s.ok for s in answers.values())
    (ra, rb) = (s.r for s in answers.values())
    assert np.abs(ra - rb).max() > 1e-2 * np.abs(rb).max()      # different points of the set
    reps = [qpcontact.unique_reactions(prob, s) for s in answers.values()]
    assert all(r.ok for r in reps)
    assert np.abs(reps[0].r - reps[1].r).max() <= 1e-8 * np.abs(reps[1].r).max()
