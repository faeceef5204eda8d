"""No silent wrong answer.  The componentwise certificate, the
pivoting methods' per-row decisions, convexity of QPs, extreme data.

Every reference here is independent of qpcontact's certificate: planted
solutions (qpcontact.testing builds the data around them), exact rational
arithmetic (tests/helpers/references.py), hand computations."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from qpsolvers import Problem

import qpcontact
from qpcontact import LCP, NotConvexError, NotSymmetricError
from qpcontact import certify
from qpcontact.testing import far_contact_lcp, planted_ok, random_spd

from tests.helpers.references import exact_basic_solution

EXACT = ("energy", "bpp", "lemke")


# --- the far-contact blind spot ------------------------------------------------

def _wrong_basis_point(lcp, z_star):
    """The basic point of the planted basis with one closed contact opened: a
    wrong answer whose residual sits at the near contacts."""
    F = np.flatnonzero(z_star > 0)
    F = F[1:]
    z = np.zeros(lcp.n)
    z[F] = np.linalg.solve(lcp.M[np.ix_(F, F)], -lcp.q[F])
    return z


def test_certificate_sees_a_near_contact_beside_far_gaps():
    """A gap of 5e11 elsewhere must not hide a violated contact whose own gap
    is 0.1: the normwise figure (kept beside) cannot see it, the componentwise
    one does, and it names the component."""
    lcp, z_star, w_star = far_contact_lcp(0)
    z = _wrong_basis_point(lcp, z_star)
    w = lcp.w(z)
    assert not planted_ok(z, w, z_star, w_star)
    i = int(np.argmin(w))
    assert w[i] < -0.01 and abs(lcp.q[i]) < 10  # a near contact, violated by much of its size
    cert = certify(lcp, z)
    assert cert.normwise_error < 1e-10          # the blind spot, by design of the normwise scales
    # by hand: row i is made of |q_i| + sum_j |M_ij| z_j; w_i is negative by that much
    sigma_i = abs(lcp.q[i]) + np.abs(lcp.M[i]) @ np.abs(z)
    assert cert.error >= -w[i] / sigma_i > 0.01
    assert cert.error == pytest.approx(np.max(np.maximum(-w, 0) / (np.abs(lcp.q) + np.abs(lcp.M) @ np.abs(z))))


@pytest.mark.parametrize("method", EXACT)
def test_exact_methods_right_on_far_contact_problems(method):
    """The far-contact reproducer: 'energy' returned 100 of 100 and 'bpp' 96 of 100
    wrong answers with ok=True before the sign tests became per-row."""
    wrong = []
    for seed in range(100):
        lcp, z_star, w_star = far_contact_lcp(seed)
        sol = qpcontact.solve(lcp, method=method)
        if not (sol.ok and planted_ok(sol.z, sol.w, z_star, w_star, rtol=1e-9)):
            wrong.append((seed, sol.status, sol.error))
    assert not wrong, wrong


def test_qp_backends_never_silently_wrong_on_far_contacts():
    """QP backends may fail on these data (most do: absolute tolerances against
    gaps of 5e11), but whatever they return as ok is right."""
    # proxqp is left out: on far_contact_lcp(7) it runs 13.6 M iterations (100 s)
    # on its first calls in a process, then 10 000 on later ones (a hang).
    names = [m for m in ("clarabel", "osqp", "piqp", "scs", "highs", "daqp", "quadprog")
             if m in qpcontact.methods()]
    silent = []
    for seed in range(10):
        lcp, z_star, w_star = far_contact_lcp(seed)
        for name in names:
            sol = qpcontact.solve(lcp, method=name)
            if sol.ok and not planted_ok(sol.z, sol.w, z_star, w_star):
                silent.append((seed, name, sol.error))
    assert not silent, silent


def test_componentwise_error_invariant_under_row_and_column_scaling():
    rng = np.random.default_rng(1)
    for seed in range(5):
        lcp, z_star, _ = far_contact_lcp(seed)
        z = z_star * (1 + 1e-7 * rng.standard_normal(lcp.n)) + (z_star == 0) * 1e-9
        dr, dc = 10 ** rng.uniform(-3, 3, lcp.n), 10 ** rng.uniform(-3, 3, lcp.n)
        scaled = LCP(lcp.M * dr[:, None] * dc[None, :], lcp.q * dr)
        assert certify(scaled, z / dc).error == pytest.approx(certify(lcp, z).error, rel=1e-6)


@pytest.mark.parametrize("seed", range(4))
def test_qp_certificate_equals_lcp_certificate(seed):
    """The QP min ½z'Mz + q'z, z >= 0 with z_box = -w is judged exactly as the LCP."""
    lcp, z_star, _ = far_contact_lcp(seed)
    rng = np.random.default_rng(seed)
    for z in (z_star, z_star + 1e-6 * rng.random(lcp.n), _wrong_basis_point(lcp, z_star)):
        assert certify(lcp.to_qp(), z, z_box=-lcp.w(z)).error == pytest.approx(
            certify(lcp, z).error, rel=1e-9, abs=1e-300)


def test_qp_far_constraint_does_not_hide_a_violated_near_one():
    """min ½|x|² - x1 - x2 s.t. x1 <= 0.1, x2 <= 5e11 (far): x = (0.1, 1).
    A point with x1 = 0.15 violates the near constraint by half its size."""
    qp = Problem(np.eye(2), np.array([-1.0, -1.0]), G=np.eye(2), h=np.array([0.1, 5e11]))
    good = certify(qp, [0.1, 1.0], z=[0.9, 0.0])
    assert good.error < 1e-15
    bad = certify(qp, [0.15, 1.0], z=[0.85, 0.0])
    # slack -0.05 against |h_1| + |x_1| = 0.25
    assert bad.error == pytest.approx(0.05 / 0.25) and "inequality" in bad.worst


def test_idle_row_noise_is_not_an_error_but_a_violation_is():
    """Kolesnikov example 3 has an idle row (q_4 = 0, z_3 = z_4 = 0 at the solution): a
    point correct to 1e-24 there is certified; a gap violated by 1e-3 is not."""
    from qpcontact.cases.paper import p0_examples

    ex = p0_examples()[2]
    assert ex.lcp.q[3] == 0 and ex.z[2] == ex.z[3] == 0
    noisy = ex.z + np.array([0.0, -1.6e-23, -1.7e-24, -1.4e-24])
    assert certify(ex.lcp, noisy).error < 1e-20
    violated = ex.z + np.array([0.0, 0.0, 0.0, -1e-3])
    assert certify(ex.lcp, violated).error > 1e-4


# --- forward error: what "solved" means on ill-conditioned data ------------------

def _badly_scaled(seed, n=20, decades=6.0):
    """D M0 D with D log-uniform in 1e-6..1e6 (cond ~ 1e24), z*, w* planted in
    [0.1, 2]: the exact solution of the stored data differs from the planted one
    by the rounding of q, so the reference is computed in rationals."""
    rng = np.random.default_rng(seed)
    M0 = random_spd(n, 100.0, rng)
    d = 10 ** rng.uniform(-decades, decades, n)
    M = M0 * d[:, None] * d[None, :]
    active = rng.random(n) < 0.5
    z = np.where(active, rng.uniform(0.1, 2, n), 0.0)
    w = np.where(active, 0.0, rng.uniform(0.1, 2, n))
    lcp = LCP(M, w - M @ z)
    return lcp, *exact_basic_solution(lcp.M, lcp.q, active)


@pytest.mark.parametrize("method", ["energy", "bpp", "lemke", "piqp", "daqp"])
def test_forward_error_bounds_the_distance_to_the_exact_solution(method):
    """"solved" is a backward statement (exact for data within tol of yours);
    beside it, forward_error must bound how far each component is from the
    exact solution of the data as stored, relative to its own size."""
    if method not in qpcontact.methods():
        pytest.skip(f"{method} not installed")
    flagged = 0
    for seed in range(12):
        lcp, z_ex, w_ex = _badly_scaled(seed)
        sol = qpcontact.solve(lcp, method=method)
        if not sol.ok:
            continue
        F = z_ex > 0
        actual = max(np.max(np.abs(sol.z[F] - z_ex[F]) / z_ex[F]),
                     np.max(np.abs(sol.w[~F] - w_ex[~F]) / w_ex[~F]))
        assert actual <= sol.forward_error, (seed, actual, sol.forward_error)
        if sol.forward_error > sol.tol:
            flagged += 1
            assert "forward error up to" in sol.message
    assert flagged > 0  # these data are ill-conditioned: some answers must say so


def test_well_conditioned_answers_carry_a_small_forward_error():
    lcp, z_star, _ = far_contact_lcp(3)
    sol = qpcontact.solve(lcp, method="bpp")
    assert sol.forward_error < 1e-11 and "forward error" not in sol.message
    assert np.max(np.abs(sol.z - z_star)) <= sol.forward_error * np.max(z_star)


# --- convexity of QPs ------------------------------------------------------------

def test_nonconvex_qp_is_refused_by_every_route():
    """min ½(x1² - x2²) on the box [-1, 1]²: backends said "solved" at the KKT
    point x = 0 (objective 0) while x = (0, ±1) gives -0.5."""
    qp = Problem(np.diag([1.0, -1.0]), np.zeros(2), lb=-np.ones(2), ub=np.ones(2))
    for method in ["auto", *[m for m in ("clarabel", "proxqp", "piqp", "highs", "osqp")
                             if m in qpcontact.methods()]]:
        with pytest.raises(NotConvexError, match="nonconvex"):
            qpcontact.solve(qp, method=method)
    nonsym = Problem(np.array([[1.0, 1.0], [0.0, 1.0]]), np.zeros(2), lb=np.zeros(2))
    with pytest.raises(NotSymmetricError, match=r"0\.5 \* \(P \+ P\.T\)"):
        qpcontact.solve(nonsym)


def test_convexity_check_is_scale_free_and_sparse_aware():
    import scipy.sparse as sp

    rng = np.random.default_rng(0)
    P0 = random_spd(30, 1e3, rng)
    d = 10 ** rng.uniform(-6, 6, 30)
    P = P0 * d[:, None] * d[None, :]                 # SPD, cond ~ 1e27
    q = rng.standard_normal(30)
    sol = qpcontact.solve(Problem(P, q, lb=np.zeros(30)), method="clarabel")
    assert sol.certificate is not None               # accepted as convex
    k = 40
    T = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(k, k))
    L = (sp.kron(T, sp.identity(k)) + sp.kron(sp.identity(k), T)).tocsc()   # PSD-definite grid
    Lneg = (L - 8.5 * sp.identity(k * k)).tocsc()   # a negative eigenvalue
    qpcontact.solve(Problem(L, np.ones(k * k), lb=np.zeros(k * k)), method="osqp")
    with pytest.raises(NotConvexError):
        qpcontact.solve(Problem(Lneg, np.ones(k * k), lb=np.zeros(k * k)), method="osqp")


def test_definiteness_tests_are_scale_free_and_do_not_overflow():
    rng = np.random.default_rng(2)
    A = random_spd(20, 1e3, rng)
    d = 10 ** rng.uniform(-6, 6, 20)
    lcp = LCP(A * d[:, None] * d[None, :], np.zeros(20))
    assert lcp.is_symmetric and lcp.is_positive_definite
    huge = LCP([[1e308, -1e308], [-1e308, 1e308]], [0.0, 0.0])   # singular PSD
    assert huge.is_symmetric and not huge.is_positive_definite and huge.is_psd
    # a coupling of 1e-8 is the only entry of its row: not rounding beside 1e300
    coupled = LCP([[1e300, -1e-8], [1e-8, 0.0]], [0.0, 0.0])
    assert not coupled.is_symmetric and coupled.is_psd   # skew part: monotone
    assert not LCP([[1e-8, 0.0], [1e300, 1e-300]], [0.0, 0.0]).is_psd


# --- data spanning hundreds of orders of magnitude --------------------------------

def test_extreme_data_solved_right_or_refused_never_a_false_proof():
    # (1) M = [[1e-8, 0], [1e300, 1e-300]], q = (-1e-8, 1e8): z = (1, 0) by hand
    # (w1 = 1e-8 - 1e-8 = 0, w2 = 1e300 + 1e8 > 0).  'auto' claimed infeasibility.
    sol = qpcontact.solve(LCP([[1e-8, 0.0], [1e300, 1e-300]], [-1e-8, 1e8]))
    assert sol.ok and np.array_equal(sol.z, [1.0, 0.0])
    # (2) M = [[1e-8, -1], [1e8, -1]], q = (1e300, -1): w = 0 gives z2 = 1e8 z1 - 1
    # and z1 (1e8 - 1e-8) = 1e300 + 1: z = (1e292, 1e300) to double precision.
    sol = qpcontact.solve(LCP([[1e-8, -1.0], [1e8, -1.0]], [1e300, -1.0]))
    assert np.all(np.isfinite(sol.z)) and sol.ok
    np.testing.assert_allclose(sol.z, [1e300 / (1e8 - 1e-8), 1e300], rtol=1e-15)
    # (3) a solution that does not fit: z1 = 1e200 / 1e-200 = 1e400.  Every method
    # says so — no NaN, no "solved", no warning from deep inside.
    import warnings

    lcp = LCP([[1e-200, 0.0], [0.0, 1.0]], [-1e200, -1.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for method in ("auto", "energy", "bpp", "lemke"):
            sol = qpcontact.solve(lcp, method=method)
            assert sol.status == "failed" and sol.z is None, (method, sol.status)
            assert "does not fit in double precision" in sol.message


def test_lemke_claims_infeasibility_only_with_a_checked_farkas_vector():
    # CPS 4.4.16 turned infeasible: w1 = z1 - z2 - 1, w2 = -z1 + z2 - 1.
    M, q = np.array([[1.0, -1.0], [-1.0, 1.0]]), np.array([-1.0, -1.0])
    sol = qpcontact.solve(LCP(M, q), method="lemke")
    assert sol.status == "infeasible" and sol.stats["proved_infeasible"]
    y = sol.stats["farkas"]
    assert np.all(y >= 0) and np.all(M.T @ y <= 0) and q @ y < 0   # checked here, by hand
    # the same on data spanning 1e±150: still a proof, never a guess
    sol = qpcontact.solve(LCP(M * 1e150, q * 1e-150), method="lemke")
    assert sol.status == "infeasible" and sol.stats["proved_infeasible"]


_HIGHS_CRASH = r"""
import numpy as np, qpcontact
from qpcontact import LCP
from qpsolvers import Problem
sol = qpcontact.solve(LCP([[1e300, -1e-8], [1e-8, 0.0]], [0.5, 1e-300]), method="highs")
print(sol.status)
sol = qpcontact.solve(Problem(np.diag([1e15, 0.0]), np.array([-1.0, 1.0]), lb=np.zeros(2)),
                      method="highs")
print(sol.status, sol.message)
"""


def test_no_backend_call_that_kills_the_process():
    """HiGHS 1.15 dies (SIGSEGV) on a singular Hessian holding 1e15: qpcontact
    either scales it away or does not call HiGHS.  Run in a subprocess, so a
    regression fails this test instead of killing the test run."""
    if "highs" not in qpcontact.methods():
        pytest.skip("highspy not installed")
    r = subprocess.run([sys.executable, "-c", _HIGHS_CRASH], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    first, second = r.stdout.splitlines()
    assert first in ("solved", "inaccurate", "failed")
    assert second.startswith("failed") and "rescale" in second
