"""Generated granular piles (qpcontact.cases.piles) and the route for large
frictional problems ("nsgs-newton", "auto" with time shares).

References: the Delassus entries of a contact between two rigid discs or
spheres by hand (1/m_a + 1/m_b along the normal; with the rolling terms
r²/I along a tangent), the planted solutions of qpcontact.cases.planted_friction,
Lemke's exact 2-D answer, and Coulomb's law written out here."""

from __future__ import annotations


import re

import numpy as np
import pytest
import scipy.sparse as sp

import qpcontact
from qpcontact.cases.piles import disc_pile, sphere_pile
from qpcontact.core.errors import InvalidProblemError
from qpcontact.testing import build_friction
from tests.helpers.limits import kept, timed


def _coulomb_error(W, q, mu, d, r):
    """The natural-map residual of De Saxcé's form, each contact over its own
    size (|r_i| + |u_i|/W_nn,i), computed here without qpcontact."""
    u = np.asarray(W @ r).ravel() + q
    R, U = r.reshape(-1, d), u.reshape(-1, d)
    wn = np.asarray(W.diagonal())[0::d]
    worst = 0.0
    for i in range(R.shape[0]):
        rho = 1.0 / wn[i] if wn[i] > 0 else 1.0
        uh = U[i].copy()
        uh[0] += mu[i] * np.linalg.norm(U[i, 1:])
        x = R[i] - rho * uh
        t, n = np.linalg.norm(x[1:]), x[0]
        if t <= mu[i] * n:
            p = x
        elif mu[i] * t <= -n:
            p = np.zeros(d)
        else:
            a = (mu[i] * t + n) / (1 + mu[i] ** 2)
            p = np.concatenate([[a], mu[i] * a * x[1:] / t])
        size = np.linalg.norm(R[i]) + rho * np.linalg.norm(U[i]) + 1e-300
        worst = max(worst, np.linalg.norm(R[i] - p) / size)
    return worst


# -- the generators --------------------------------------------------------------------

@pytest.mark.parametrize("make,n", [(disc_pile, 300), (sphere_pile, 300)])
def test_a_pile_is_reproducible_by_its_seed(make, n):
    a, b, c = make(n, seed=4), make(n, seed=4), make(n, seed=5)
    assert (a.problem.W != b.problem.W).nnz == 0
    np.testing.assert_array_equal(a.problem.q, b.problem.q)
    assert not np.array_equal(a.radii, c.radii)
    assert 0.6 * n <= a.n_contacts <= 1.6 * n, a.n_contacts


def test_disc_pile_delassus_entries_by_hand_and_its_redundancy():
    """Each contact's diagonal block by rigid-disc mechanics: along the
    normal 1/m_a + 1/m_b, along the tangent also r²/I = 2/m per disc (a disc
    per metre: m = ρπr², I = mr²/2); a wall contributes nothing.  The pile
    has more contact unknowns than its discs have degrees of freedom, so W
    is singular (statically indeterminate forces), and it is PSD."""
    pile = disc_pile(400, seed=2)
    p, rho = pile.problem, 2500.0
    m = rho * np.pi * pile.radii ** 2
    inv = lambda k: np.where(k >= 0, 1.0 / m[np.maximum(k, 0)], 0.0)   # noqa: E731
    a, b = pile.pairs[:, 0], pile.pairs[:, 1]
    diag = p.W.diagonal()
    np.testing.assert_allclose(diag[0::2], inv(a) + inv(b), rtol=1e-12)
    np.testing.assert_allclose(diag[1::2], 3 * (inv(a) + inv(b)), rtol=1e-12)
    W = p.W.toarray()
    eig = np.linalg.eigvalsh(W)
    assert eig.min() >= -1e-12 * eig.max()
    assert 2 * p.n_contacts > 3 * pile.n_bodies
    assert np.sum(eig > 1e-10 * eig.max()) <= 3 * pile.n_bodies


def test_disc_pile_geometry_has_no_overlap_and_contacts_are_near():
    pile = disc_pile(500, seed=1)
    c, r = pile.centers, pile.radii
    d = np.linalg.norm(c[:, None] - c[None], axis=2) - r[:, None] - r[None]
    np.fill_diagonal(d, np.inf)
    assert d.min() >= -1e-12
    a, b = pile.pairs[pile.pairs[:, 0] >= 0].T
    assert np.all(d[a, b] <= 0.05 * 0.01 + 1e-15)


def test_sphere_pile_delassus_entries_by_hand():
    """Spheres: m = ρ 4πr³/3, I = 2mr²/5, so each tangent adds r²/I = 5/(2m)."""
    pile = sphere_pile(300, seed=3)
    p = pile.problem
    m = 2500.0 * 4.0 / 3.0 * np.pi * pile.radii ** 3
    inv = lambda k: np.where(k >= 0, 1.0 / m[np.maximum(k, 0)], 0.0)   # noqa: E731
    a, b = pile.pairs[:, 0], pile.pairs[:, 1]
    diag = p.W.diagonal()
    np.testing.assert_allclose(diag[0::3], inv(a) + inv(b), rtol=1e-12)
    for k in (1, 2):
        np.testing.assert_allclose(diag[k::3], 3.5 * (inv(a) + inv(b)), rtol=1e-12)
    assert 3 * p.n_contacts > 6 * pile.n_bodies


@pytest.mark.parametrize("bad", [dict(n_contacts=5), dict(mu=-0.1), dict(polydispersity=0.9),
                                 dict(h=0.0), dict(radius=float("nan"))])
def test_a_pile_with_bad_parameters_is_refused_by_name(bad):
    kwargs = dict(n_contacts=300) | bad
    name = next(iter(bad))
    with pytest.raises(InvalidProblemError, match=name):
        disc_pile(**kwargs)


# -- the route: NSGS then minimum-norm Newton ------------------------------------------

@pytest.mark.parametrize("make,n", [(disc_pile, 600), (sphere_pile, 300)])
def test_nsgs_newton_certifies_a_generated_pile(make, n):
    """Certified at 1e-8, and the answer passes Coulomb's law as written
    here; in 2-D Lemke's exact answer is certified as well."""
    p = make(n, seed=0).problem
    s = qpcontact.solve(p, "nsgs-newton", accuracy=1e-8)
    assert s.ok, s.message
    assert _coulomb_error(sp.csr_matrix(p.W), p.q, p.mu, p.dim, s.r) <= 1e-7
    if p.dim == 2:
        exact = qpcontact.solve(p, "lemke", accuracy=1e-8)
        assert exact.ok, exact.message
        # the forces of a pile are not unique (W is singular), its velocities
        # are: u = W r + q agrees contact by contact on the velocities' scale
        scale = np.abs(exact.u).max()
        np.testing.assert_allclose(s.u, exact.u, atol=1e-6 * scale)


@pytest.mark.parametrize("kind", ["mixed", "sliding", "badly_scaled", "decoupled"])
@pytest.mark.parametrize("dim", [2, 3])
def test_nsgs_newton_on_planted_solutions(kind, dim):
    case = build_friction(kind, 12, 3, dim=dim, cond=1e2)
    s = qpcontact.solve(case.problem, "nsgs-newton", accuracy=1e-9)
    assert s.ok, s.message
    assert case.agrees(s.r)


def test_minimum_norm_newton_finishes_from_near_an_answer():
    """From NSGS's point at about 1e-6 the minimum-norm steps reach rounding
    level in a few steps (module docstring of qpcontact.solvers.friction.hybrid)."""
    from qpcontact.solvers.friction.hybrid import minimum_norm_newton
    from qpcontact.judge.friction_certificate import certified_error
    from qpcontact.solvers.friction.nsgs import NSGS

    p = disc_pile(1000, seed=0).problem
    gs = NSGS(p, omega=1.3)
    r = gs.sweep(50)
    while certified_error(p, r) > 1e-6 and gs.done < 5000:
        r = gs.sweep(50)
    start = certified_error(p, r)
    assert start <= 1e-6
    r_new, err, steps = minimum_norm_newton(p, r.copy(), 1e-12)
    assert err <= 1e-12 and steps <= 4, (start, err, steps)
    assert err == certified_error(p, r_new)


def test_the_stall_detector_ends_a_run_that_cannot_converge():
    """A contact pressed (q_N < 0) whose W block is zero has no solution; the
    run stops by itself, says it stalled, and reports "inaccurate"."""
    W = np.diag([1.0, 1.0, 0.0, 0.0])
    q = np.array([-1.0, 0.2, -1.0, 0.0])
    p = qpcontact.FrictionProblem(W, q, [0.5, 0.5], 2)
    s = qpcontact.solve(p, "nsgs-newton", accuracy=1e-8)
    assert not s.ok and s.status == "inaccurate" and "stalled" in s.message, s.message


def test_nsgs_newton_and_auto_keep_the_time_limit():
    """On a compact pile where every method stalls: "nsgs-newton" stops at
    time_limit, and "auto" shares its limit between its links — ip-lcp and
    Lemke stop
    at its share, the fixed points pass what is left of theirs to each
    subproblem's backend (a 5000-contact SOCP took 1.7 s of a 0.5 s share)
    — and names each link with where it stopped."""
    # seed 1: ip-lcp's path on seed 0 became short enough (2.7 s at a load of
    # 4) to certify it within auto's 4 s; on seed 1 it was not certified in
    # 59 s of CPU (docs/dev-notes.md, "Dense 2-D piles by interior point, round two")
    p = disc_pile(5000, seed=1, agitation=0.1, polydispersity=0.005).problem
    # first use of every kernel on the way: at 0.1 s no Newton try was reached
    # (20 sweeps), so the timed call paid the Newton step's first use and ran
    # 1.61 s of a 1 s limit (grace 0.6 s) in a test run beside two others;
    # on a fresh clone (numba's cache empty) at a load of 4 on 2 cores a warm-up
    # of 1 s did not reach it either (2.0 s): the warm-up gets 5 s
    qpcontact.solve(p, "nsgs-newton", accuracy=1e-12, time_limit=5.0)
    s, took = timed(qpcontact.solve, p, "nsgs-newton", accuracy=1e-12, time_limit=1.0)
    assert kept(1.0, took), took
    assert not s.ok and "time limit of 1 s" in s.message, s.message
    lines = []
    s, took = timed(qpcontact.solve, p, "auto", accuracy=1e-12, time_limit=4.0,
                    progress=lines.append)
    assert kept(4.0, took), took
    assert not s.ok and s.r is not None, s.message
    assert "links: nsgs-newton: error" in s.message
    assert "ip-lcp: " in s.message, s.message     # 2-D above 200 contacts: second
    if "lemke: not run" in s.message:
        # the links before it (ip-lcp on 0.8 of what nsgs-newton left; at a
        # fraction of a core a link's stop runs past its share) left Lemke
        # less than a link can use; the chain still kept the whole limit
        # (above) and says what was left
        assert re.search(r"lemke: not run \([0-9.e+-]+ s of the time limit of 4 s was left\)",
                         s.message), s.message
    else:
        assert "lemke: time_limit" in s.message, s.message
        assert any(ln.startswith("auto: lemke (up to") for ln in lines)
    assert any(ln.startswith("nsgs-newton: ") for ln in lines)


def test_lemke_stops_at_the_time_limit():
    """A cold Lemke on a compact pile's 8000-unknown LCP takes minutes; its
    sparse form checks solve()'s time_limit at each pivot."""
    p = disc_pile(2000, seed=0, agitation=0.1, polydispersity=0.005).problem
    s, took = timed(qpcontact.solve, p, "lemke", accuracy=1e-8, time_limit=1.0)
    assert kept(1.0, took), took
    assert s.status == "time_limit" and not s.ok, s.message
