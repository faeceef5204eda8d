"""The 2-D NSGS sweep on W's 2 x 2 blocks against Gauss–Seidel written out
(tests/helpers/references.py), and
nsgs-newton's square Newton step (``square_first``) against the default
minimum-norm route on a regular problem: both certified by the judge."""

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import qpcontact
from qpcontact.core.friction_problem import FrictionProblem
from qpcontact.solvers.friction.nsgs import NSGS
from qpcontact.judge.friction_certificate import certified_error
from tests.helpers.references import nsgs_sweeps_by_hand


def _problem(n_bodies=60, m=90, seed=0, compliance=1e-2):
    """A 2-D frictional problem W = Hᵀ H + D from random two-body contacts
    (H: 3 freedoms a body), D > 0 on the normals (compliant contacts)."""
    rng = np.random.default_rng(seed)
    rows, cols, vals = [], [], []
    for k in range(m):
        a, b = rng.choice(n_bodies, 2, replace=False)
        for body, sign in ((a, 1.0), (b, -1.0)):
            for col in (2 * k, 2 * k + 1):
                for dof in range(3):
                    rows.append(3 * body + dof)
                    cols.append(col)
                    vals.append(sign * rng.normal())
    H = sp.csc_matrix((vals, (rows, cols)), shape=(3 * n_bodies, 2 * m))
    D = np.zeros(2 * m)
    D[0::2] = compliance
    W = (H.T @ H + sp.diags(D)).tocsc()
    q = rng.normal(size=2 * m)
    return FrictionProblem(W, q, rng.uniform(0.1, 0.6, m), 2)


def test_block_sweeps_equal_the_sweeps_by_hand():
    """ω = 1: the compiled 2-D sweeps against Gauss–Seidel written out in
    tests/helpers (dense W, each local problem by its cases)."""
    p = _problem()
    a = NSGS(p)
    assert a.bsr is not None
    a.sweep(25)
    ref = nsgs_sweeps_by_hand(p.W, p.q, p.mu, np.zeros_like(a.r), 25)
    assert np.abs(a.r - ref).max() <= 1e-12 * np.abs(ref).max()
    assert np.abs(a.r).max() > 0      # the sweeps did something


def test_open_contacts_passed_over_leave_the_iterates_unchanged():
    """The 2-D sweep passes over an open contact while its b_N provably stays
    >= 0; with the bound's row sums infinite it visits every contact.  The
    same iterates bit for bit, chunk after chunk, on problems where about
    half the contacts open (q_N > 0 on them), from a start that pushes every
    other contact; a bound without the neighbours' changes (reach 0) gives
    other iterates."""
    for seed in range(5):
        p = _problem(n_bodies=40 + 10 * seed, m=80 + 20 * seed, seed=seed)
        p.q[0::2] = np.abs(p.q[0::2]) * np.where(np.arange(p.n_contacts) % 2, 1.0, -1.0)
        r0 = np.where(np.arange(p.q.size) % 4 == 0, 1.0, 0.0)      # every other contact pushed
        skip, visit = NSGS(p, r0, omega=1.5), NSGS(p, r0, omega=1.5)
        visit.held[:, 1] = np.inf
        for chunk in (1, 1, 1, 1, 5, 20, 40):
            skip.sweep(chunk)
            visit.sweep(chunk)
            assert np.array_equal(skip.r, visit.r)
        assert np.count_nonzero(skip.held[:, 0] >= 0) > 0.2 * p.n_contacts   # open ones held


def test_square_newton_step_gives_a_certified_answer():
    p = _problem(seed=3)
    plain = qpcontact.solve(p, method="nsgs-newton", accuracy="high")
    square = qpcontact.solve(p, method="nsgs-newton", accuracy="high", square_first=True)
    assert plain.ok and square.ok
    assert square.stats["newton_steps"] >= 1          # the Newton step was taken
    scale = np.abs(plain.r).max()
    # a regular problem (D > 0 on the normals, H of full column rank): one answer
    assert np.abs(square.r - plain.r).max() <= 1e-6 * scale


def test_w_blocks_are_those_of_w():
    """FrictionProblem.W_blocks (one compiled pass) against W's dense 2 x 2 slices."""
    p = _problem(seed=4)
    dense = p.W.toarray()
    diag, bptr, bcols, bdata = p.W_blocks
    nc = p.n_contacts
    for i in range(nc):
        assert np.array_equal(diag[i], dense[2 * i:2 * i + 2, 2 * i:2 * i + 2])
        cols = bcols[bptr[i]:bptr[i + 1]]
        assert np.all(np.diff(cols) > 0) and i not in cols
        for c, blk in zip(cols, bdata[bptr[i]:bptr[i + 1]]):
            assert np.array_equal(blk, dense[2 * i:2 * i + 2, 2 * c:2 * c + 2])
        others = [c for c in range(nc) if c != i and c not in cols]
        assert not np.any(dense[2 * i:2 * i + 2][:, [2 * c + k for c in others for k in (0, 1)]])


def test_compiled_2d_certified_error_equals_the_formulas():
    """certified_error's compiled pass for sparse 2-D problems against the
    certificate's array formulas (natural_map_error, componentwise_error):
    random, zero and sweep-made impulses, open, sticking and sliding contacts."""
    from qpcontact.judge.friction_certificate import (certified_error, componentwise_error,
                                                      natural_map_error)

    for seed in range(6):
        p = _problem(n_bodies=20 + 10 * seed, m=10 + 30 * seed, seed=seed)
        gs = NSGS(p, omega=1.3)
        rng = np.random.default_rng(seed)
        for r in (rng.normal(size=p.q.size), np.zeros(p.q.size), gs.sweep(5).copy(),
                  gs.sweep(200).copy()):
            u = p.velocities(r)
            want = max(natural_map_error(p, r, u), componentwise_error(p, r, u))
            # both relative measures: below 1e-15 they are rounding either way
            assert abs(certified_error(p, r) - want) <= 1e-13 * want + 1e-15


def test_the_square_step_with_a_reused_order_is_the_fresh_one():
    """nsgs-newton's square step takes the solve's first column order for its
    later LUs: the step equals a fresh minimum-degree LU's."""
    import scipy.sparse.linalg as spla
    from qpcontact.judge.friction_certificate import natural_map_jacobian
    from qpcontact.solvers.friction import hybrid

    p = _problem(seed=2)
    gs = NSGS(p, omega=1.3)
    r1, r2 = gs.sweep(3).copy(), gs.sweep(30).copy()
    square = {"on": True}
    for r in (r1, r2):            # the second LU reuses the first one's order
        J = sp.csc_matrix(natural_map_jacobian(p, r))
        F = np.random.default_rng(0).normal(size=r.size)
        step, _ = hybrid._square_step(p, r, J, F, square)
        fresh = spla.splu(J).solve(-F)
        assert np.abs(step - fresh).max() <= 1e-10 * np.abs(fresh).max()
    assert "order" in square


def test_the_compiled_closed_system_gives_the_array_routes_step():
    """nsgs-newton's square step on a sparse 2-D problem forms F and the
    system on the closed contacts in one compiled call, a sliding contact's
    tangential unknown tied to its normal one (d_T = v_T d_N − (F_T − v_T F_N),
    J_P of rank one on the cone's side); against the array formulas and
    scipy (natural_map_jacobian, the cone projection, restricted_system on
    J's CSC): F bit for bit, the step to rounding — from sweeps that leave
    contacts open, sticking and sliding, with and without a first LU's order.
    A tie of the wrong sign, or the tangential row kept, changes the step."""
    from qpcontact.core.friction_problem import modified_velocity, project_cone
    from qpcontact.judge.friction_certificate import (SLIP_RTOL, contact_scales,
                                                      natural_map_jacobian)
    from qpcontact.solvers.friction import hybrid
    from qpcontact.solvers.friction._newton_kernels import closed_system_2d

    kinds = set()
    for seed in range(4):
        p = _problem(n_bodies=30 + 10 * seed, m=40 + 30 * seed, seed=seed)
        gs = NSGS(p, omega=1.3)
        rng = np.random.default_rng(seed)
        rho_c = contact_scales(p)
        rho = np.repeat(rho_c, 2)
        n = p.q.size
        for r in (gs.sweep(3).copy(), gs.sweep(40).copy(), rng.normal(size=n)):
            for known in (None, rng.permutation(n)):
                F = r - project_cone(r - rho * modified_velocity(p.W @ r + p.q, p.mu, 2), p.mu, 2)
                J = sp.csc_matrix(natural_map_jacobian(p, r))
                want, _ = hybrid._square_step(p, r, J, F)
                got = closed_system_2d(p.W.indptr, p.W.indices, p.W.data, p.q, p.mu, rho_c, r,
                                       SLIP_RTOL, *p.W_blocks,
                                       np.zeros(0, np.int64) if known is None else known,
                                       known is not None)
                assert np.array_equal(got[0], F)
                F_, base, tie, order, ptr, idx, val, rhs = got
                assert np.all(np.diff(idx[ptr[0]:ptr[1]]) > 0)       # rows ascending
                if known is not None:     # the known order kept for the unknowns it has
                    kept = known[np.isin(known, order)]
                    assert np.array_equal(order[:kept.size], kept)
                step = base.copy()
                step[order] = spla.spsolve(sp.csc_matrix((val, idx, ptr), shape=(order.size,) * 2),
                                           rhs)
                step[1::2] += tie * step[0::2]
                assert np.abs(step - want).max() <= 1e-9 * np.abs(want).max()
                open_ = np.flatnonzero(~np.isin(np.arange(n), order) & (np.repeat(tie, 2) == 0))
                kinds.update({"open": open_.size > 0, "sliding": np.any(tie != 0)}.items())
    assert ("open", True) in kinds and ("sliding", True) in kinds


def _frictionless_pair():
    """Two frictionless 2-D contacts whose tangential rows are decoupled:
    the normal rows are the LCP W_NN = [[2, 1], [1, 2]], q_N = (1, −1),
    solved by hand: r_N = (0, 1/2), u_N = (3/2, 0)."""
    W = sp.csc_matrix(np.array([[2.0, 0, 1, 0], [0, 1, 0, 0], [1, 0, 2, 0], [0, 0, 0, 1.0]]))
    return FrictionProblem(W, np.array([1.0, 0.0, -1.0, 0.0]), [0.0, 0.0], 2), \
        np.array([0.0, 0.0, 0.5, 0.0])


def test_without_friction_a_negative_normal_is_in_the_polar_cone_not_inside():
    """μ = 0 and r_T = 0: the test |r_T| <= μ r_N reads 0 <= −0.0 for r_N < 0,
    which once put such points inside the cone (the compiled measure read the
    exact answer as error 1, Newton kept both unknowns, and over-relaxed NSGS
    left r_N < 0)."""
    p, exact = _frictionless_pair()
    assert certified_error(p, exact) == 0.0
    assert certified_error(p, exact, u=p.velocities(exact)) == 0.0
    res = qpcontact.solve(p, method="nsgs-newton")
    assert res.ok and np.allclose(res.r, exact, atol=1e-14)
    gs = NSGS(p, omega=1.3)
    for _ in range(10):
        assert gs.sweep(1)[0::2].min() >= 0.0
