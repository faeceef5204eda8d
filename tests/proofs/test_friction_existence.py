"""A solution's existence proved by a velocity that opens every contact
strictly (qpcontact.proofs.friction_existence): checked against hand
kinematics, and refused where no velocity can open the contacts."""

from __future__ import annotations

import numpy as np

from qpcontact import FrictionProblem
from qpcontact.cases.piles import sphere_pile
from qpcontact.proofs.friction_existence import solution_exists


def _disc_on_floor(q, mu=0.5):
    """A disc (m = 2 kg, r = 0.1 m, I = m r²/2) on a floor, 2-D: the contact's
    Delassus matrix by hand, W = diag(1/m, 1/m + r²/I)."""
    m, r = 2.0, 0.1
    W = np.diag([1 / m, 1 / m + r * r / (m * r * r / 2)])
    return FrictionProblem(W, np.asarray(q, float), [mu], 2)


def test_a_disc_pressed_into_the_floor_and_sliding_has_a_solution():
    """u = W y + q reaches every velocity (W definite): the disc can be lifted
    and its slip cancelled, so the theorem applies whatever q is."""
    p = _disc_on_floor([-3.0, 7.0])
    proof = solution_exists(p)
    assert proof is not None and proof[0].startswith("a solution exists")
    u = p.W @ proof[1] + p.q
    assert u[0] > 0.5 * abs(u[1])          # strictly inside the dual cone, by hand


def test_a_disc_pinched_between_two_walls_is_not_decided():
    """Two walls at x = ±r touching the disc, the global form (M = diag(m, m,
    I), H by hand): u_N1 = v_x and u_N2 = −v_x, whose sum is zero for every v,
    so no velocity opens both contacts and nothing is claimed."""
    m, r = 2.0, 0.1
    M = np.diag([m, m, m * r * r / 2])
    # contact rows of Hᵀ: (normal, tangent) at the left wall (normal +x) and
    # the right wall (normal −x); the tangent picks up the spin at the rim
    HT = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, r],
                   [-1.0, 0.0, 0.0], [0.0, -1.0, r]])
    p = FrictionProblem.global_problem(M, HT.T, np.array([0.0, -19.62, 0.0]), np.zeros(4),
                                       [0.3, 0.3], 2, reduce=False)
    assert solution_exists(p) is None
    # the same disc with a gap on the right (w_N2 > 0): now it can move left
    p = FrictionProblem.global_problem(M, HT.T, np.array([0.0, -19.62, 0.0]),
                                       np.array([0.0, 0.0, 1e-3, 0.0]), [0.3, 0.3], 2,
                                       reduce=False)
    proof = solution_exists(p)
    assert proof is not None
    v = proof[1]
    u = HT @ v + np.array([0.0, 0.0, 1e-3, 0.0])
    assert np.all(u[0::2] > 0.3 * np.abs(u[1::2]))


def test_a_singular_mass_matrix_is_not_decided():
    """The theorem needs M definite: a body without inertia about its spin is
    refused, whatever the LP would find."""
    M = np.diag([2.0, 2.0, 0.0])
    HT = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.1]])
    p = FrictionProblem.global_problem(M, HT.T, np.zeros(3), np.array([1.0, 0.0]), [0.3], 2,
                                       reduce=False)
    assert solution_exists(p) is None


def test_a_nearly_closed_sphere_pile_has_a_solution():
    """The 540-contact compact pile of seed 2, which no method certifies at
    1e-6 (docs/dev-notes.md): its velocity opens all 540 contacts, checked
    here independently of the module's own check."""
    _assert_every_contact_opened(sphere_pile(500, seed=2, agitation=0.1, polydispersity=0.005))


def _no_solution_on_an_indefinite_mass():
    """One body, two dofs, M = [[7, 1], [1, fl(1/7)]]: fl(1/7) lies below 1/7,
    so det M = 7 fl(1/7) − 1 < 0 exactly, yet NumPy's Cholesky factorization
    of M succeeds.  One frictionless 2-D contact, normal row (0, 1), w_N = −1,
    f = 0: M v = h_N r_N gives u_N = r_N h_Nᵀ M⁻¹ h_N − 1 = 7 r_N / det M − 1
    < 0 for every r_N >= 0, so no solution exists — while v = (0, 2) opens
    the contact (u_N = 1)."""
    from fractions import Fraction

    M = np.array([[7.0, 1.0], [1.0, 1.0 / 7.0]])
    assert Fraction(M[0, 0]) * Fraction(M[1, 1]) - Fraction(M[0, 1]) ** 2 < 0
    np.linalg.cholesky(M)                           # no error: rounding hides the sign
    HT = np.array([[0.0, 1.0], [1.0, 0.0]])
    return FrictionProblem.global_problem(M, HT.T, np.zeros(2), np.array([-1.0, 0.0]), [0.0], 2,
                                          reduce=False)


def test_an_indefinite_mass_matrix_that_factors_in_rounding_is_not_decided():
    """A successful floating-point Cholesky factorization is not a proof of
    definiteness (module docstring, "Definiteness"): on the problem above,
    which has no solution, nothing is claimed."""
    assert solution_exists(_no_solution_on_an_indefinite_mass()) is None


def test_a_local_w_not_shown_definite_is_not_decided():
    """The same 2 x 2 matrix as one contact's W (normal diagonal 7 > 0, so
    the problem is accepted): its eigenvalue −8e−18 is below zero, which no
    test to rounding can tell from zero, so nothing is claimed; a W shown
    definite still is."""
    W = np.array([[7.0, 1.0], [1.0, 1.0 / 7.0]])
    assert solution_exists(FrictionProblem(W, np.array([-1.0, 0.0]), [0.5], 2)) is None
    W = np.array([[7.0, 1.0], [1.0, 0.5]])
    assert solution_exists(FrictionProblem(W, np.array([-1.0, 0.0]), [0.5], 2)) is not None


def test_factors_that_do_not_form_w_prove_nothing():
    """Two frictionless 2-D contacts whose normal velocities sum to
    q_N1 + q_N2 = −2 whatever the impulses (W_N = [[1, −1], [−1, 1]]): no
    solution.  Factors that are not W's (identity bodies: W would be the
    identity) must not stand in for W: nothing is claimed, as without them."""
    import scipy.sparse as sp

    W = np.zeros((4, 4))
    W[np.ix_([0, 2], [0, 2])] = [[1.0, -1.0], [-1.0, 1.0]]
    W[1, 1] = W[3, 3] = 1.0
    p = FrictionProblem(W, np.array([-1.0, 0.0, -1.0, 0.0]), [0.0, 0.0], 2)
    assert solution_exists(p) is None
    p.delassus_factors = (sp.identity(4, format="csr"), np.ones(4))
    assert solution_exists(p) is None


def test_a_definite_mass_matrix_over_eight_decades_is_still_shown_definite():
    """The shift that makes the Cholesky test a proof is taken after scaling
    M by powers of two to a unit-sized diagonal: a definite, non-diagonal M
    whose entries span 1e±4 (masses and inertias) is still decided, its
    contact opened."""
    rng = np.random.default_rng(0)
    n = 60
    Q = np.linalg.qr(rng.standard_normal((n, n)))[0]
    S = np.diag(10.0 ** rng.uniform(-4, 4, n))
    M = S @ Q @ np.diag(rng.uniform(0.5, 2.0, n)) @ Q.T @ S
    M = 0.5 * (M + M.T)
    H = np.zeros((n, 2))
    H[0, 0], H[1, 1] = 1.0, 1.0
    p = FrictionProblem.global_problem(M, H, np.zeros(n), np.array([-1.0, 0.0]), [0.3], 2,
                                       reduce=False)
    proof = solution_exists(p)
    assert proof is not None and "M shown positive definite" in proof[0]


def _sphere_in_a_corner(mu=0.5):
    """One sphere (m = 1 kg, r = 0.1 m, I = 2 m r²/5) resting in a corner
    of its box, touching the floor (normal +z), the wall x = x_max (normal
    −x) and the wall y = y_max (normal −y), every gap 0; each contact's rows
    of Hᵀ written out: the normal n·v, the tangents t·(v + ω × (−r n)), the
    tangents along the box's axes.  Gravity's step h g = 0.0981 m/s presses
    it into the floor."""
    import scipy.sparse as sp

    m, r = 1.0, 0.1
    I = 0.4 * m * r * r
    ex, ey, ez = np.eye(3)
    rows = []
    for n, t1, t2 in ((ez, ex, ey), (-ex, ey, ez), (-ey, ex, ez)):
        arm = -r * n                          # the contact point from the centre
        rows.append(np.concatenate([n, np.zeros(3)]))
        for t in (t1, t2):                    # t·(ω × arm) = ω·(arm × t)
            rows.append(np.concatenate([t, np.cross(arm, t)]))
    HT = np.array(rows)
    minv = np.array([1 / m] * 3 + [1 / I] * 3)
    W = HT @ np.diag(minv) @ HT.T
    q = HT @ np.array([0.0, 0.0, -0.0981, 0.0, 0.0, 0.0])
    p = FrictionProblem(W, q, [mu] * 3, 3)
    p.delassus_factors = (sp.csr_matrix(HT), minv)
    return p, HT


def test_a_sphere_in_a_corner_has_a_solution():
    """Moving away from the floor and both walls at once slips the sphere at
    each contact by √2 times its normal speed: inside the round cone at
    μ = 0.5 (1 − 0.5·√2 > 0), on the edge of the inscribed square the search
    used before (1 − 0.5·2 = 0), which left every generated pile with a
    sphere in a corner undecided.  The velocity returned opens all three
    contacts, checked here by hand."""
    p, HT = _sphere_in_a_corner()
    proof = solution_exists(p)
    assert proof is not None and proof[0].startswith("a solution exists")
    U = (HT @ proof[1] + p.q).reshape(3, 3)
    assert np.all(U[:, 0] > 0.5 * np.linalg.norm(U[:, 1:], axis=1))


def test_a_compact_pile_with_a_sphere_in_a_corner_has_a_solution():
    """The 540-contact compact pile of seed 4: its largest sphere in a
    floor corner touches three faces of the box at gap 0; existence is now
    proved, the velocity checked by hand."""
    _assert_every_contact_opened(sphere_pile(500, seed=4, agitation=0.1, polydispersity=0.005))


def _assert_every_contact_opened(pile):
    """The proof's velocity puts every contact's u strictly inside its round
    cone, checked here from the pile's own factors, not by the module."""
    p = pile.problem
    proof = solution_exists(p)
    assert proof is not None
    HT, _ = p.delassus_factors
    U = (HT @ proof[1] + p.q).reshape(-1, 3)
    assert np.all(U[:, 0] > p.mu * np.linalg.norm(U[:, 1:], axis=1))
