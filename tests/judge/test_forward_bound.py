"""The forward-error estimate bounds the true error: on ill-conditioned SPD
LCPs whose exact solution is known (qpcontact.cases.rounded: exact rational
pivoting on the stored data), an answer's ``scale_forward_error`` is at least
half its true error on the same scales — the scales recomputed here by their
definition — so that "no digit on its scale" cannot miss a wrong answer."""

from __future__ import annotations

import numpy as np
import pytest

from qpcontact import certify, solve
from qpcontact.cases.rounded import build_rounded


def _true_error(case, z):
    """max |z - z*| / ζ and |w - w*| / σ, with σ = |q| + |M||z| and ζ_j =
    min(cap, min_i σ_i / |M_ij|) at the answer (docs/certificates.md)."""
    M, q = case.problem.M, case.problem.q
    A = np.abs(M)
    w = M @ z + q
    sig = np.abs(q) + A @ np.abs(z)
    cap = max(np.abs(z).max(), np.abs(q).max() / A.max())
    with np.errstate(divide="ignore", invalid="ignore"):
        zeta = np.minimum(np.where(A > 0, sig[:, None] / A, np.inf).min(axis=0), cap)
    return max(np.max(np.abs(z - case.z) / zeta), np.max(np.abs(w - case.w) / sig))


# answers whose estimate at their own basis missed the truth by 4x..200x
# (an ambiguous w_j of 2e-5 of its scale was a z_j > 0 of the exact solution)
MISSED = [("conditioned_spd", 8, 10, "highs", "low"), ("conditioned_spd", 8, 14, "highs", "high"),
          ("ill_conditioned_spd", 8, 9, "osqp", "high"),
          ("ill_conditioned_spd", 8, 24, "highs", "low"),
          ("ill_conditioned_spd", 8, 18, "osqp", "default"),
          # a well-conditioned active block whose estimate missed by 2.7x:
          # ProxQP's off z's of 1e-8 moved the one active row (σ = 0.02)
          ("conditioned_spd", 8, 39, "proxqp", "low"),
          ("conditioned_spd", 8, 39, "proxqp", "default"),
          ("conditioned_spd", 8, 39, "proxqp", "high")]


@pytest.mark.parametrize("family,n,seed,method,accuracy", MISSED)
def test_estimate_bounds_the_true_error(family, n, seed, method, accuracy):
    pytest.importorskip("qpsolvers")
    case = build_rounded(family, n, seed)
    assert case.status == "solved" and case.unique_z
    sol = solve(case.problem, method, accuracy=accuracy)
    if sol.z is None:
        pytest.skip(f"{method} returned no point here")
    true = _true_error(case, sol.z)
    est = certify(case.problem, sol.z).scale_forward_error
    assert est >= 0.5 * true, (true, est)
    if true >= 0.1:
        assert not sol.ok, sol.message            # no correct digit: never ok


def test_well_conditioned_exact_answer_stays_ok_and_sharp():
    # the exact solution, rounded: an estimate near rounding, ok
    case = build_rounded("conditioned_spd", 8, 3)
    cert = certify(case.problem, case.z)
    assert cert.scale_forward_error >= 0.5 * _true_error(case, case.z)
    sol = solve(case.problem, "bpp", accuracy="low")
    assert sol.ok and _true_error(case, sol.z) < 0.1


@pytest.mark.parametrize("family,seed", [("conditioned_spd", 5), ("conditioned_spd", 8),
                                         ("ill_conditioned_spd", 8), ("conditioned_spd", 39)])
def test_off_components_near_zero_are_counted(family, seed):
    """An answer whose off z's are not zero but 1e-8 of their scale, signed
    to push the active row of least size one way, and whose active rows hold
    exactly with them (w_F = 0, as an iterative backend's point does): its
    active z's differ from the exact solution's by M_FF⁻¹ M_FN z_N, which
    the estimate must bound (here without the factor 2 of slack: the change
    is linear, first order is exact) — σ at the answer holds only the tiny
    z_N (the estimate read 1/2.1 of the truth before they were counted)."""
    case = build_rounded(family, 8, seed)
    M, q, zs = case.problem.M, case.problem.q, case.z
    F = np.flatnonzero(zs > 0)
    N = np.flatnonzero(zs <= 0)
    assert F.size and N.size
    A = np.abs(M)
    sig = np.abs(q) + A @ np.abs(zs)
    zeta = np.where(A > 0, sig[:, None] / np.where(A > 0, A, 1.0), np.inf).min(axis=0)
    f = F[np.argmin(sig[F])]
    z = zs.copy()
    z[N] = 1e-8 * np.sign(M[f, N]) * np.minimum(zeta[N], np.abs(zs).max())
    z[F] = np.linalg.solve(M[np.ix_(F, F)], -q[F] - M[np.ix_(F, N)] @ z[N])
    true = _true_error(case, z)
    assert true > 1e-12
    est = certify(case.problem, z).scale_forward_error
    assert est >= true, (true, est)
