"""Certificates are computed from the data: known solutions pass, perturbed ones fail."""

from __future__ import annotations

import numpy as np
import pytest

from qpcontact import LCP, InvalidProblemError
from qpcontact import certify

# Murty (1988) p. 2: M = [[2, 1], [1, 2]], q = (-5, -6), z = (4/3, 7/3), w = 0.
MURTY = LCP([[2.0, 1.0], [1.0, 2.0]], [-5.0, -6.0])
Z_MURTY = np.array([4 / 3, 7 / 3])


def test_exact_solution_certifies():
    c = certify(MURTY, Z_MURTY)
    assert c.error <= 4 * np.finfo(float).eps and c.comp_abs <= 1e-15


def test_error_tracks_perturbation():
    for d in (1e-3, 1e-6, 1e-9):
        c = certify(MURTY, Z_MURTY + np.array([d, 0.0]))
        # By hand: w = (2d, d).  Row 1 is made of |q1| + 2 z1 + z2 = 5 + 2(4/3 + d)
        # + 7/3 = 10 + 2d, so w1 is off by 2d / (10 + 2d); row 2 by d / (12 + d).
        # Both z's are basic and far from zero, so the pair's error is w's.
        assert c.error == pytest.approx(2 * d / (10 + 2 * d), rel=1e-9)
        assert c.worst_index == 0
        # the former normwise figure: w1 = 2d against max(|Mz|, |q|) = 6
        assert c.normwise_error == pytest.approx(2 * d / 6.0, rel=1e-3)


def test_negative_entries_are_caught():
    lcp = LCP(np.eye(2), [1.0, 1.0])  # solution z = 0, w = q
    c = certify(lcp, [-1e-3, 0.0])
    # measured against the scale of z, max(|z|, |q|/max|M|) = 1
    assert c.min_z == pytest.approx(-1e-3) and c.error == pytest.approx(1e-3)
    c = certify(lcp, [0.0, 0.0])
    assert c.error == 0.0 and c.min_w == 0.0
    bad = certify(LCP(np.eye(2), [-1.0, 1.0]), [0.0, 0.0])  # w1 = -1 < 0
    assert bad.min_w == -1.0 and bad.error == pytest.approx(1.0)


def test_siconos_measure_by_hand():
    z = Z_MURTY + np.array([1e-4, -2e-4])
    w = MURTY.w(z)
    expected = np.linalg.norm(np.minimum(z, w)) / np.linalg.norm(MURTY.q)
    assert certify(MURTY, z).siconos_error == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("alpha, beta", [(1e8, 1.0), (1.0, 1e-8), (1e-6, 1e5)])
def test_error_is_scale_free(alpha, beta):
    """M -> alpha M scales z by 1/alpha; q -> beta q scales z and w by beta."""
    z = Z_MURTY + np.array([3e-7, -1e-7])
    ref = certify(MURTY, z).error
    scaled = LCP(alpha * MURTY.M, beta * MURTY.q)
    assert certify(scaled, beta * z / alpha).error == pytest.approx(ref, rel=1e-6)


def test_nonfinite_candidate_is_infinitely_wrong():
    c = certify(MURTY, [np.nan, 1.0])
    assert c.error == np.inf and not c.ok(1.0)


def test_wrong_length_is_misuse():
    with pytest.raises(InvalidProblemError, match="n = 2"):
        certify(MURTY, [1.0, 2.0, 3.0])


def test_qp_certificate_matches_lcp_certificate_and_catches_signs():
    qp = MURTY.to_qp()
    w = MURTY.w(Z_MURTY)
    good = certify(qp, Z_MURTY, z_box=-w)
    assert good.error <= 1e-14
    # primal residual as qpsolvers defines it: [lb - x]^+
    assert certify(qp, np.array([-0.5, 1.0]), z_box=np.zeros(2)).primal_residual == pytest.approx(0.5)
    # a point that is optimal but whose duals are missing cannot be certified
    assert certify(qp, Z_MURTY).error == np.inf
    # LCP at the solution of a bound-free coordinate: claim an upper bound that does not exist
    lcp = LCP(np.eye(2), [1.0, -1.0])  # z = (0, 1), w = (1, 0)
    qp2 = lcp.to_qp()
    ok = certify(qp2, [0.0, 1.0], z_box=[-1.0, 0.0])
    assert ok.error <= 1e-15
    wrong_sign = certify(qp2, [0.0, 1.0], z_box=[1.0, 0.0])  # stationarity fails, and the sign
    assert wrong_sign.min_multiplier == -1.0 and wrong_sign.error >= 0.5


def test_qp_per_constraint_complementarity_beyond_the_gap():
    """Two constraints each off by sqrt(gap) while the summed gap cancels: the
    per-constraint measure sees it (qpsolvers' gap alone does not)."""
    from qpsolvers import Problem
    P = np.eye(2)
    qp = Problem(P, np.zeros(2), G=np.array([[-1.0, 0.0], [0.0, -1.0]]), h=np.array([-1.0, 1.0]))
    # x = (1, 0): row 1 active (slack 0), row 2 slack 1; exact duals z = (1, 0)
    exact = certify(qp, [1.0, 0.0], z=[1.0, 0.0])
    assert exact.error <= 1e-15
    off = certify(qp, [1.0, 0.0], z=[1.0, 1e-4])
    assert off.comp_abs == pytest.approx(1e-4) and off.error >= 1e-4
