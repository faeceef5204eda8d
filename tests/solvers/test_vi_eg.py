""""vi-eg", projected gradient with Khobotov's step (Siconos's VI_EG): answers
checked against closed forms and against the exact 2-D LCP solved by Lemke
(pivoting, no projection), errors recomputed here contact by contact."""

from __future__ import annotations

import time

import numpy as np
import pytest

import qpcontact
from qpcontact.core.friction_problem import FrictionProblem
from qpcontact.core.deadline import grace
from tests.helpers.paths import SHARED_DATA
from tests.helpers.references import natural_map_error_by_hand

DATA = SHARED_DATA / "siconos-fc"


# W = diag(kn, kt, kt) is stiffer than the first step ρ = 1 allows (ρ kn = 40 > 2):
# without Khobotov's cut the iteration runs away
KN, KT, MU = 40.0, 25.0, 0.5


def _one_contact_3d(qn, qt):
    """One contact, W = diag(KN, KT, KT), q = (qn, qt): by hand, it opens
    (r = 0) when qn >= 0; else r_N = −qn / KN, and it sticks (r_T = −qt / KT)
    when ‖qt‖ / KT <= μ r_N, or slides against qt (r_T = −μ r_N qt / ‖qt‖)."""
    qt = np.asarray(qt, float)
    r = np.zeros(3)
    if qn < 0:
        r[0] = -qn / KN
        stick = -qt / KT
        r[1:] = stick if np.linalg.norm(stick) <= MU * r[0] else \
            -MU * r[0] * qt / np.linalg.norm(qt)
    return FrictionProblem(np.diag([KN, KT, KT]), np.r_[qn, qt], [MU], 3), r


@pytest.mark.parametrize("qn, qt, state", [
    (-1.0, [0.1, -0.2], "sticks"), (-1.0, [3.0, 4.0], "slides"), (1.0, [3.0, -1.0], "opens")])
def test_one_3d_contact_sticks_slides_and_opens_as_by_hand(qn, qt, state):
    p, r_hand = _one_contact_3d(qn, qt)
    s = qpcontact.solve(p, "vi-eg", accuracy=1e-10)
    assert s.ok and s.method == "vi-eg", s.message
    np.testing.assert_allclose(s.r, r_hand, atol=1e-9 * np.abs(r_hand).max(initial=1.0))
    assert natural_map_error_by_hand(p.W, p.q, p.mu, s.r) <= 1e-10


def _random_2d(seed, nc=8):
    """A 2-D problem with W = B Bᵀ + I scaled past ρ = 1 (positive definite:
    one answer), some contacts pushed closed, some open."""
    rng = np.random.default_rng(seed)
    B = rng.standard_normal((2 * nc, 2 * nc))
    W = 5.0 * (B @ B.T / nc + np.eye(2 * nc))
    q = rng.standard_normal(2 * nc)
    q[0::2] -= 0.5
    return FrictionProblem(W, q, rng.uniform(0.1, 0.8, nc), 2)


@pytest.mark.parametrize("seed", range(4))
def test_2d_problems_agree_with_the_exact_lcp(seed):
    """W positive definite: one answer, which Lemke reaches by pivoting on
    the exact 2-D LCP."""
    p = _random_2d(seed)
    exact = qpcontact.solve(p, "lemke", accuracy=1e-10)
    assert exact.ok, exact.message
    s = qpcontact.solve(p, "vi-eg", accuracy=1e-10)
    assert s.ok and s.method == "vi-eg", s.message
    assert natural_map_error_by_hand(p.W, p.q, p.mu, s.r) <= 1e-10
    np.testing.assert_allclose(s.r, exact.r, atol=1e-8 * np.abs(exact.r).max())


def _pile():
    from qpcontact.cases.piles import sphere_pile
    return sphere_pile(500, seed=0, agitation=0.1, polydispersity=0.005).problem


def test_max_iter_stops_it_and_says_so():
    p = _pile()
    s = qpcontact.solve(p, "vi-eg", accuracy=1e-6, max_iter=7, check_every=3)
    assert not s.ok and s.iterations == 7
    assert "stopped at max_iter = 7 after 7 iterations" in s.message, s.message


def test_time_limit_stops_it_and_says_so():
    p = _pile()
    qpcontact.get_method("vi-eg")
    t = time.perf_counter()
    s = qpcontact.solve(p, "vi-eg", accuracy=1e-6, time_limit=1.0)
    wall = time.perf_counter() - t
    assert not s.ok and "time limit" in s.message, s.message
    assert wall <= 1.0 + grace(1.0) + 1.0      # + certifying the 540-contact answer
    assert s.iterations > 0


def test_time_limit_is_read_between_the_error_checks():
    """The iterations run compiled in chunks; with the error checked only
    every 200 000 of them, a 50 ms limit still stops the run long before the
    first check (a chunk ran to the next check before: 3.5 s past a 0.01 s
    limit with check_every = 20 000)."""
    p = _pile()
    qpcontact.get_method("vi-eg")
    s = qpcontact.solve(p, "vi-eg", accuracy=1e-6, time_limit=0.05, check_every=200_000,
                        max_iter=200_000)
    assert not s.ok and "time limit" in s.message, s.message
    assert s.iterations < 200_000      # no chunk ran on to the check


def test_an_infinite_first_step_is_refused():
    with pytest.raises(qpcontact.InvalidOptionError, match="rho"):
        qpcontact.solve(_pile(), "vi-eg", rho=np.inf)


#: the shared files "vi-eg" certifies at 1e-8 (benchmarks/friction.py --methods vi-eg,
#: docs/dev-notes.md); the others it does not claim
VI_EG_SOLVES = ["Box_Stacks-i0122-82-5.hdf5", "Capsules-i125-1213.hdf5",
                "Confeti-ex13-4contact-Fc3D-SBM.dat", "FC2D_SliderCrankLagrangian00000.dat",
                "FC2D_SliderCrankLagrangian00001.dat", "FC3D_Example1.dat", "FC3D_Example1_SBM.dat",
                "FrictionContact3D_1c.dat", "FrictionContact3D_RR_1c.dat",
                "FrictionContactProblem00031.dat", "FrictionContactProblem00071.dat",
                "FrictionContactProblem00394.dat", "NESpheres_10_1.dat", "Rover1039.dat",
                "Rover1040.dat", "Rover4396.dat"]


@pytest.mark.skipif(not DATA.is_dir(), reason=f"Siconos friction data not found at {DATA}")
@pytest.mark.parametrize("name", VI_EG_SOLVES)
def test_shared_problems_it_solves(name):
    from qpcontact.io import read_problem

    p = read_problem(DATA / name)
    s = qpcontact.solve(p, "vi-eg", accuracy=1e-8)
    assert s.ok and s.method == "vi-eg", s.message
    W = p.W.toarray() if hasattr(p.W, "toarray") else np.asarray(p.W)
    assert natural_map_error_by_hand(W, p.q, p.mu, s.r) <= 1e-8
