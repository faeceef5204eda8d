"""ip-lcp: the 2-D frictional LCP by interior point, its central path followed
past its folds (qpcontact/solvers/friction/interior_lcp.py).  References from
outside the method: planted solutions, Lemke's exact answer, Coulomb's law
written out here."""

import numpy as np
import pytest

import qpcontact
from qpcontact.cases.piles import disc_pile
from qpcontact.cases.planted_friction import build_friction
from qpcontact.core.errors import InvalidOptionError, QpcontactError


def _coulomb_violation(p, r, scale):
    """The largest violation of Coulomb's law and Signorini's condition over
    the contacts, in force units relative to ``scale`` (written out here,
    not the judge's)."""
    u = np.asarray(p.W @ r).ravel() + p.q
    rn, rt, un, ut = r[0::2], r[1::2], u[0::2], u[1::2]
    wn = p.W.diagonal()[0::2]
    vn, vt = un / wn, ut / wn                       # speeds as forces, each contact's scale
    worst = [np.maximum(-rn, 0), np.maximum(np.abs(rt) - p.mu * rn, 0),
             np.maximum(-vn, 0), np.minimum(rn, np.maximum(vn, 0)),
             # sliding: friction at the cone's edge, against the slip
             np.where(np.abs(vt) > 1e-9 * scale, np.abs(rt + p.mu * rn * np.sign(vt)), 0.0)]
    return max(float(w.max()) for w in worst) / scale


def test_a_compact_pile_whose_path_folds_is_certified():
    """182 contacts, hyperstatic: Mehrotra's steps collapse and the path is
    followed past its turns; the answer satisfies Coulomb's law."""
    p = disc_pile(200, seed=7, agitation=0.1, polydispersity=0.005).problem
    s = qpcontact.solve(p, "ip-lcp", accuracy=1e-8)
    assert s.ok, s.message
    assert s.stats["path_stretches"] >= 1 and s.stats["folds"] >= 1
    scale = np.abs(s.r).max()
    assert _coulomb_violation(p, s.r, scale) <= 1e-8


def test_a_loose_pile_needs_no_followed_path():
    p = disc_pile(400, seed=3, agitation=0.1, polydispersity=0.02).problem
    s = qpcontact.solve(p, "ip-lcp", accuracy=1e-8)
    assert s.ok, s.message
    assert s.stats["path_stretches"] == 0 and s.stats["iterations"] <= 60
    assert _coulomb_violation(p, s.r, np.abs(s.r).max()) <= 1e-8


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_unique_forces_match_the_planted_ones_and_lemkes(seed):
    """Decoupled contacts: the solution is unique, planted; Lemke's exact
    answer is the second reference."""
    case = build_friction("decoupled", 30, seed, dim=2)
    s = qpcontact.solve(case.problem, "ip-lcp", accuracy=1e-10)
    lemke = qpcontact.solve(case.problem, "lemke", accuracy=1e-10)
    assert s.ok and lemke.ok, (s.message, lemke.message)
    assert case.agrees(s.r, rtol=1e-8)
    np.testing.assert_allclose(s.r, lemke.r, atol=1e-9 * np.abs(lemke.r).max())


@pytest.mark.parametrize("seed", [0, 1])
def test_coupled_planted_problems_satisfy_coulombs_law(seed):
    case = build_friction("mixed", 40, seed, dim=2)
    s = qpcontact.solve(case.problem, "ip-lcp", accuracy=1e-9)
    assert s.ok, s.message
    assert case.agrees(s.r)


def test_3d_problems_and_unknown_options_are_refused():
    p3 = build_friction("mixed", 5, 0, dim=3).problem
    with pytest.raises(QpcontactError):
        qpcontact.solve(p3, "ip-lcp")
    p2 = build_friction("mixed", 5, 0, dim=2).problem
    with pytest.raises(InvalidOptionError, match="does not take sweeps"):
        qpcontact.solve(p2, "ip-lcp", sweeps=3)
    with pytest.raises(InvalidOptionError, match="max_iter"):
        qpcontact.solve(p2, "ip-lcp", max_iter=0)


def test_auto_certifies_a_dense_pile_its_sweeps_do_not():
    """A 662-contact compact pile: NSGS + Newton stops short of 1e-8 within
    its tenth of "auto"'s budget, and "auto" goes on to ip-lcp, whose answer
    satisfies Coulomb's law."""
    from qpcontact.dispatch.routes import auto_chain, link_share

    p = disc_pile(700, seed=0, agitation=0.1, polydispersity=0.005).problem
    assert auto_chain(p)[:2] == ("nsgs-newton", "ip-lcp")
    assert link_share(p, "nsgs-newton", False) < link_share(p, "ip-lcp", False)
    sweeps = qpcontact.solve(p, "nsgs-newton", accuracy=1e-8, time_limit=6)
    s = qpcontact.solve(p, "auto", accuracy=1e-8)
    assert s.ok, s.message
    assert _coulomb_violation(p, s.r, np.abs(s.r).max()) <= 1e-8
    if not sweeps.ok:       # the route this test is about
        assert s.method == "ip-lcp", s.message



def test_large_2d_piles_give_their_sweeps_half():
    """From SWEEPS_LARGE_2D contacts "auto" gives nsgs-newton half of
    its budget (ip-lcp's path does not end within it there), below a tenth
    (ip-lcp certifies the 4 874-contact piles within its 0.8); ip-lcp's
    share is the same."""
    from qpcontact.dispatch.routes import SWEEPS_LARGE_2D, link_share

    large = disc_pile(10000, seed=0, agitation=0.1, polydispersity=0.005).problem
    smaller = disc_pile(5000, seed=0, agitation=0.1, polydispersity=0.005).problem
    assert smaller.n_contacts < SWEEPS_LARGE_2D <= large.n_contacts
    assert link_share(large, "nsgs-newton", False) == pytest.approx(0.5)
    assert link_share(smaller, "nsgs-newton", False) == pytest.approx(0.1)
    assert link_share(large, "ip-lcp", False) == link_share(smaller, "ip-lcp", False)


@pytest.mark.slow
def test_the_9842_contact_pile_of_seed_0_is_certified_by_its_sweeps():
    """What the half rests on: NSGS + Newton certifies the 9 842-contact
    compact pile of seed 0 after 14 140 sweeps (about 7 s of CPU; a tenth of
    60 s gave it 13 740 at a load of 2: not certified), its Newton tries
    where its errors put them; Coulomb's law checked here on the answer."""
    p = disc_pile(10000, seed=0, agitation=0.1, polydispersity=0.005).problem
    s = qpcontact.solve(p, "nsgs-newton", accuracy=1e-8, max_sweeps=15000)
    assert s.ok, s.message
    assert s.stats["iterations"] <= 15000
    assert _coulomb_violation(p, s.r, np.abs(s.r).max()) <= 1e-8


def _pile_with_factors(n, seed):
    return disc_pile(n, seed=seed, agitation=0.1, polydispersity=0.005).problem


@pytest.mark.parametrize("space, spread", [("contacts", 0.0), ("contacts", 4.0),
                                           ("contacts", 8.0), ("bodies", 0.0),
                                           ("bodies", 4.0), ("bodies", 8.0), ("bodies", 12.0)])
def test_the_condensed_system_solves_the_whole_system(space, spread):
    """(M + diag(d)) u = g with W + L solved by its LU in the order found once
    (the pattern without the blocks' lower entries, which the LU then
    carries), or in body space (Woodbury on the pile's factors
    W = Hᵀ diag(m⁻¹) H), d spread over 1e±spread: judged on the whole
    4-unknown system, formed densely here, and against NumPy's dense solve
    where it is well conditioned."""
    import scipy.sparse as sp

    from qpcontact.core.friction_problem import faceted_lcp
    from qpcontact.solvers.friction.body_space import BodySpaceLU
    from qpcontact.solvers.friction.interior_lcp import _Condensed, _Ordered

    p = _pile_with_factors(200, 7)
    M, W = sp.csc_matrix(faceted_lcp(p, 2)[0].M), sp.csr_matrix(p.W)
    solver = (_Ordered(W) if space == "contacts" else
              BodySpaceLU(*p.delassus_factors))
    rng = np.random.default_rng(int(spread))
    d = 10.0 ** rng.uniform(-spread, spread, M.shape[0])
    g = rng.standard_normal(M.shape[0])
    u = _Condensed(M, W, solver, p.mu, d, {"factorizations": 0},
                   np.abs(W.diagonal()[1::2])).solve(g)
    A = M.toarray() + np.diag(d)
    scale = np.abs(A).max() * np.abs(u).max() + np.abs(g).max()
    assert np.abs(A @ u - g).max() <= 1e-14 * scale
    if spread == 0.0:
        np.testing.assert_allclose(u, np.linalg.solve(A, g), rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("drop_zeros", [False, True])
def test_the_body_space_solve_where_a_contacts_rows_store_other_dofs(drop_zeros):
    """A stack of three discs on a floor along y: each contact's normal row
    touches the discs' y only, its tangent row x and the rotation, so with
    J's zeros not stored the two rows share no column, and B's
    tangent-normal entries lie outside any one row's pattern.  (W + L) u = g
    by the body-space LU against NumPy's dense solve of W + L formed here."""
    import scipy.sparse as sp

    from qpcontact.solvers.friction.body_space import BodySpaceLU, factors_match

    radius, nb = 0.5, 3
    rows, cols, vals = [], [], []
    for c, (a, b) in enumerate([(0, -1), (1, 0), (2, 1)]):   # (upper, lower) disc
        for body, sign in ((a, 1.0), (b, -1.0)):
            if body >= 0:
                rows += [2 * c, 2 * c, 2 * c + 1, 2 * c + 1, 2 * c + 1]
                cols += [3 * body + 1, 3 * body, 3 * body, 3 * body + 1, 3 * body + 2]
                vals += [sign, 0.0, -sign, 0.0, -radius]
    J = sp.csr_matrix((vals, (rows, cols)), shape=(6, 3 * nb))
    if drop_zeros:
        J.eliminate_zeros()
    inverse_mass = np.tile([1.0, 1.0, 2.0 / radius ** 2], nb)
    W = (J @ sp.diags(inverse_mass) @ J.T).toarray()
    assert factors_match(sp.csr_matrix(W), (J, inverse_mass))
    rng = np.random.default_rng(1)
    dn, low, inv_g = rng.uniform(0.5, 2, 3), rng.uniform(-1, 1, 3), rng.uniform(0.5, 2, 3)
    L = np.zeros((6, 6))
    for c in range(3):
        L[2 * c, 2 * c], L[2 * c + 1, 2 * c], L[2 * c + 1, 2 * c + 1] = dn[c], low[c], inv_g[c]
    g = rng.standard_normal(6)
    u = BodySpaceLU(J, inverse_mass).factor(
        np.concatenate([dn, low, inv_g])).solve(g)
    np.testing.assert_allclose(u, np.linalg.solve(W + L, g), rtol=1e-12, atol=1e-14)


def test_the_body_space_lu_has_a_fraction_of_the_contact_spaces_fill():
    """On a 662-contact compact pile the body-space LU (the bodies' graph)
    has under half the entries of W + L's in its own order, the same L."""
    import scipy.sparse as sp

    from qpcontact.solvers.friction.body_space import BodySpaceLU
    from qpcontact.solvers.friction.interior_lcp import _Ordered

    p = _pile_with_factors(700, 0)
    nc = p.n_contacts
    rng = np.random.default_rng(3)
    l_values = np.concatenate([10.0 ** rng.uniform(-6, 6, nc), rng.uniform(-0.3, 0.3, nc),
                               10.0 ** rng.uniform(-6, 6, nc)])
    contact = _Ordered(sp.csr_matrix(p.W)).factor(l_values)
    body = BodySpaceLU(*p.delassus_factors).factor(l_values)
    assert body.lu.L.nnz + body.lu.U.nnz < 0.5 * (contact.lu.L.nnz + contact.lu.U.nnz)


def test_factors_that_do_not_reproduce_w_are_not_used():
    """A problem whose W is not its factors' (here W doubled after the pile
    kept them) is solved on W's own LU, and certified."""
    import scipy.sparse as sp

    from qpcontact.solvers.friction.body_space import factors_match

    pile = _pile_with_factors(200, 7)
    assert factors_match(sp.csr_matrix(pile.W), pile.delassus_factors)
    p = qpcontact.FrictionProblem(2.0 * sp.csr_matrix(pile.W), pile.q, pile.mu, 2)
    p.delassus_factors = pile.delassus_factors
    assert not factors_match(sp.csr_matrix(p.W), p.delassus_factors)
    s = qpcontact.solve(p, "ip-lcp", accuracy=1e-8)
    assert s.ok and s.stats["body_space"] is False, s.message
    assert _coulomb_violation(p, s.r, np.abs(s.r).max()) <= 1e-8
    assert qpcontact.solve(pile, "ip-lcp", accuracy=1e-8).stats["body_space"] is True


@pytest.mark.slow
def test_auto_certifies_the_5000_contact_pile_whose_path_is_long():
    """Issue 50's 2-D row of 5 000 contacts, seed 1: ip-lcp's path past its
    folds takes about 410 steps, which W + L's LU (0.12 s of CPU a step) did
    not fit into "auto"'s 60 s after NSGS + Newton's share; in body space
    (0.03 s a step) it does.  The answer satisfies Coulomb's law.  The
    limit is wall time, so the test gives "auto" 240 s: on a loaded machine
    (a slow-suite run beside another job) 60 s left ip-lcp ~20 s of CPU, not
    enough; the 60 s figure is benchmarks/friction.py --dense's, idle."""
    p = _pile_with_factors(5000, 1)
    s = qpcontact.solve(p, "auto", accuracy=1e-8, time_limit=240)
    assert s.ok and s.method == "ip-lcp", s.message
    assert _coulomb_violation(p, s.r, np.abs(s.r).max()) <= 1e-8


def test_the_body_space_lu_keeps_its_pivots_on_the_diagonal():
    """B = diag(m) + Jᵀ L⁻¹ J formed densely from its definition (L⁻¹ per
    contact [[1/d_N, 0], [−ℓ G / d_N, G]]) on a 662-contact pile, L's
    entries spread over 1e±3: the body-space LU solves it to rounding
    against NumPy's dense solve, and at body_space.PIVOT_THRESHOLD its
    pivots stay on the diagonal — its fill within 2 % of the LU that never
    leaves it (at W + L's 1e-3 it grew by 13–22 % on these piles)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from qpcontact.solvers.friction.body_space import BodySpaceLU

    p = _pile_with_factors(700, 0)
    J, inverse_mass = p.delassus_factors
    J = sp.csr_matrix(J)
    nc = p.n_contacts
    for seed in range(3):
        rng = np.random.default_rng(seed)
        dn, inv_g = 10.0 ** rng.uniform(-3, 3, nc), 10.0 ** rng.uniform(-3, 3, nc)
        low = rng.uniform(-1, 1, nc) * 10.0 ** rng.uniform(-3, 3, nc)
        l_inverse = np.zeros((2 * nc, 2 * nc))
        k = np.arange(nc)
        l_inverse[2 * k, 2 * k] = 1.0 / dn
        l_inverse[2 * k + 1, 2 * k] = -low / (inv_g * dn)
        l_inverse[2 * k + 1, 2 * k + 1] = 1.0 / inv_g
        Jd = J.toarray()
        B = np.diag(1.0 / inverse_mass) + Jd.T @ l_inverse @ Jd
        solver = BodySpaceLU(J, inverse_mass).factor(np.concatenate([dn, low, inv_g]))
        z = rng.standard_normal(B.shape[0])

        def backward_error(x):
            return np.abs(B @ x - z).max() / (np.abs(B).max() * np.abs(x).max())

        dense = np.linalg.solve(B, z)
        assert backward_error(solver.in_order.solve(z)) <= 10.0 * max(backward_error(dense), 1e-19)
        ordered = sp.csc_matrix(B[solver.body.p][:, solver.body.p])
        on_diagonal = spla.splu(ordered, permc_spec="NATURAL", diag_pivot_thresh=0.0,
                                options={"SymmetricMode": True})
        fill = solver.lu.L.nnz + solver.lu.U.nnz
        assert fill <= 1.02 * (on_diagonal.L.nnz + on_diagonal.U.nnz)
