"""``"ip-bpp"``'s condensed branch (few bounded unknowns among many free ones)
on mixed QPs whose free unknowns couple strongly to the bounded ones: a beam on
tensionless Winkler soil, written here, against an independent reference —
scipy's bounded least squares (BVLS, an exact active-set method) for the
active set, then numpy's dense KKT solve on it, its KKT conditions checked."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp
from qpsolvers import Problem
from scipy.optimize import lsq_linear

import qpcontact


def _beam_on_tensionless_soil(elements, EI, k, q, loads, pins):
    """An Euler–Bernoulli beam 10 m long in ``elements`` elements of length
    h [m], bending stiffness EI [kN m²], nodal unknowns (w [m, down], θ [rad]); Hermite element stiffness
    EI/h³ [[12, 6h, −12, 6h], [6h, 4h², −6h, 2h²], ...] [kN/m].  Winkler
    soil of modulus k [kN/m²] lumped at every other node (spring k·2h, half
    at the ends) that pushes and never pulls: the node's deflection is the
    soil's compression minus a lift-off gap g ≥ 0, and the energy

        ½ u'K u + ½ Σ k_s (w_s + g_s)² − f'u,   g ≥ 0

    is the mixed QP min ½ x'Px + c'x, x = (u, g), g ≥ 0 (the raft's form in
    formulations/plates, in one dimension).  ``pins`` (soil node positions)
    keep their gap at 0, which makes P definite.  Loads: ``q`` [kN/m]
    downward lumped at the nodes, ``loads`` = [(node, kN)]."""
    h = 10.0 / elements
    nodes = elements + 1
    ke = EI / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                               [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
    nu = 2 * nodes
    K = np.zeros((nu, nu))
    for e in range(elements):
        K[2 * e:2 * e + 4, 2 * e:2 * e + 4] += ke
    f = np.zeros(nu)
    f[0::2] = q * h
    f[[0, -2]] = q * h / 2
    for node, p in loads:
        f[2 * node] += p
    soil = np.arange(0, nodes, 2)
    ks = np.full(soil.size, k * 2 * h)
    ks[[0, -1]] = k * h
    gapped = np.setdiff1d(np.arange(soil.size), pins)
    for s in pins:                        # a pinned node's spring pulls too
        K[2 * soil[s], 2 * soil[s]] += ks[s]
    m = gapped.size
    T = np.zeros((m, nu))                 # w of the gapped soil nodes
    T[np.arange(m), 2 * soil[gapped]] = 1.0
    Ks = np.diag(ks[gapped])
    P = np.block([[K + T.T @ Ks @ T, T.T @ Ks], [Ks @ T, Ks]])
    c = np.concatenate([-f, np.zeros(m)])
    lb = np.concatenate([np.full(nu, -np.inf), np.zeros(m)])
    return P, c, lb


def _kkt_solution(P, c, lb, A):
    """x with x_A = l_A and (Px + c)_F = 0 by numpy's dense solve, its KKT
    conditions checked with margins (so the active set A is the right one,
    not merely close, and no bound is degenerate)."""
    F = ~A
    x = np.where(A, lb, 0.0)
    x[F] = np.linalg.solve(P[np.ix_(F, F)], -(c[F] + P[np.ix_(F, A)] @ lb[A]))
    lam = P @ x + c
    scale = np.abs(P) @ np.abs(x) + np.abs(c)
    assert np.all(np.abs(lam[F]) <= 1e-10 * scale[F])           # stationarity on F
    assert np.all(lam[A] > 1e-6 * scale[A])                      # pressing, not degenerate
    bounded_free = F & np.isfinite(lb)
    assert np.all(x[bounded_free] - lb[bounded_free] > 1e-6 * np.abs(x).max())  # lifted clearly
    return x


def _reference(P, c, lb):
    """The minimizer from an independent route: with P = R'R, the QP is the
    bounded least-squares problem min ½|R x + R⁻ᵀc|², x_B >= l_B, which BVLS
    solves by an exact active-set method; its active set then gives x by the
    dense KKT solve."""
    R = scipy.linalg.cholesky(P)
    rhs = -scipy.linalg.solve_triangular(R, c, trans="T")
    fit = lsq_linear(R, rhs, bounds=(lb, np.full(c.size, np.inf)), method="bvls", tol=1e-14)
    A = fit.active_mask == -1
    return _kkt_solution(P, c, lb, A), A


@pytest.mark.parametrize("elements,EI,k,pins", [(40, 1e4, 2e5, [4, 10]), (60, 5e3, 1e5, [5, 12]),
                                                (80, 2e4, 5e5, [6, 18])])
def test_condensed_branch_on_a_beam_whose_gaps_couple_strongly(elements, EI, k, pins):
    """Self weight, a heavy load at a fifth of the length and an uplift at the
    far end: the middle presses, the end lifts.  The free unknowns couple to
    the gaps through springs far stiffer than the beam, so solving for them
    with all of P while the gaps are held (the condensed branch's old
    refinement) moves them away from the answer; on the final active set's
    free block it converges."""
    loads = [(elements // 5, 400.0), (elements - 1, -300.0)]
    P, c, lb = _beam_on_tensionless_soil(elements, EI, k, 10.0, loads, pins)
    x_ref, at_bound = _reference(P, c, lb)
    gaps = np.isfinite(lb)
    assert 0 < np.count_nonzero(at_bound) < np.count_nonzero(gaps)   # some press, some lift
    sol = qpcontact.solve(Problem(sp.csc_matrix(P), c, lb=lb), method="ip-bpp")
    assert "condensed" in sol.stats
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.x, x_ref, rtol=0, atol=1e-9 * np.abs(x_ref).max())
    np.testing.assert_array_equal(sol.x[gaps] == lb[gaps], at_bound[gaps])


@pytest.mark.slow
def test_condensed_branch_on_a_raft_held_by_three_pins():
    """The case that found the bug: a 20 x 20 raft (10 m square, t = 0.5 m,
    E = 30e6 kN/m², Winkler k = 2e4 kN/m³, 3000 kN at (1, 1), 1000 kN at
    (5, 5)) with three soil nodes pinned near the heavy load, the rest free
    to lift: 438 gaps among 1761 unknowns.  Reference: the QP condensed onto
    its gaps by dense algebra, that SPD LCP solved by Lemke, whose active set
    gives the dense KKT solution, checked."""
    from formulations.plates import Raft

    raft = Raft(10.0, 10.0, thickness=0.5, E=30e6, nu=0.2, cells=(20, 20))
    raft.add_soil(2e4)
    raft.add_point_load(1.0, 1.0, 3000.0)
    raft.add_point_load(5.0, 5.0, 1000.0)
    built = raft.build()
    qp, nodes = built["qp"], built["mesh"].nodes
    at = [(0.5, 0.5), (1.5, 1.0), (0.5, 2.0)]
    pins = [int(np.flatnonzero(np.all(nodes[qp.supported] == p, axis=1))[0]) for p in at]
    problem = qp.problem(raft.load_vector({"D": 1.0}), pins)
    P, c, lb = problem.P.toarray(), problem.q, problem.lb
    b, f = np.flatnonzero(np.isfinite(lb)), np.flatnonzero(~np.isfinite(lb))
    Pff_inv = np.linalg.solve(P[np.ix_(f, f)], np.column_stack([P[np.ix_(f, b)], c[f]]))
    S = P[np.ix_(b, b)] - P[np.ix_(b, f)] @ Pff_inv[:, :-1]
    lcp = qpcontact.solve(qpcontact.LCP(0.5 * (S + S.T), c[b] - P[np.ix_(b, f)] @ Pff_inv[:, -1]
                                        + S @ lb[b]), method="lemke")
    assert lcp.ok, lcp.message
    A = np.zeros(c.size, bool)
    A[b] = lcp.z == 0
    x_ref = _kkt_solution(P, c, lb, A)
    assert 0 < np.count_nonzero(A) < b.size
    sol = qpcontact.solve(problem, method="ip-bpp")
    assert "condensed" in sol.stats
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.x, x_ref, rtol=0, atol=1e-9 * np.abs(x_ref).max())
