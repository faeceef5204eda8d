"""Frictional contact: readers for Siconos .dat and FCLIB HDF5 files, the
problem type, the natural-map error, and the exact 2-D LCP solved by Lemke — judged by an error function written here,
independently of the package's friction modules."""

from __future__ import annotations


import numpy as np
import pytest

import qpcontact
from qpcontact.core.errors import (InvalidOptionError, InvalidProblemError, NotConvexError,
                                  UnknownMethodError)
from qpcontact.core.friction_problem import FrictionProblem, project_cone
from qpcontact.judge.friction_certificate import natural_map_error
from qpcontact.io import read_fclib, read_siconos_fc, write_fclib
from tests.helpers.paths import SHARED_DATA
from tests.helpers.references import natural_map_error_by_hand

DATA = SHARED_DATA / "siconos-fc"
FILES = sorted(p.name for p in DATA.glob("*") if p.suffix in (".dat", ".hdf5")) if DATA.is_dir() \
    else []
needs_data = pytest.mark.skipif(not FILES, reason=f"Siconos friction data not found at {DATA}")
SMALL_2D = ["FC2D_SliderCrankLagrangian00000.dat", "FC2D_SliderCrankLagrangian00001.dat",
            "FrictionContactProblem00031.dat", "FrictionContactProblem00071.dat",
            "FrictionContactProblem00394.dat"]


def _tried(sol) -> list:
    """The methods "auto" ran, in order."""
    return [name for name, _, _ in sol.stats["auto_tried"]]


def _read(name):
    path = DATA / name
    return read_fclib(path) if path.suffix == ".hdf5" else read_siconos_fc(path)


@needs_data
@pytest.mark.parametrize("name", FILES)
def test_every_shared_file_reads_into_a_consistent_problem(name):
    p = _read(name)
    m = p.dim * p.n_contacts
    assert p.W.shape == (m, m) and p.q.shape == (m,) and np.all(p.mu >= 0)
    assert p.dim in (2, 3)
    if name.startswith("gfc2d"):
        assert p.global_data is not None


@needs_data
@pytest.mark.parametrize("name", SMALL_2D)
def test_2d_problems_are_solved_exactly_by_lemke(name):
    p, s, W = _solved_by_auto(name)
    assert s.method == "lemke"
    assert natural_map_error(p, s.r) == pytest.approx(
        natural_map_error_by_hand(W, p.q, p.mu, s.r), abs=1e-14)


def _solved_by_auto(name):
    """The shared problem, "auto"'s answer checked to 1e-8 by the error
    function written here, and W dense."""
    p = _read(name)
    # no time limit: under the default 60 s the 2 020-contact file's Lemke
    # link ran out of its share on a loaded machine (61 s of wall time for
    # 9.8 s of CPU), and the test would time the machine
    s = qpcontact.solve(p, "auto", accuracy=1e-8, time_limit=None)
    assert s.ok, s.message
    W = p.W.toarray() if hasattr(p.W, "toarray") else np.asarray(p.W)
    assert natural_map_error_by_hand(W, p.q, p.mu, s.r) <= 1e-8
    return p, s, W


@needs_data
def test_stored_reference_solution_satisfies_the_cone_conditions_with_its_velocity():
    """Capsules (FCLIB local) stores r and u from Siconos's NSGS at 1e-8: with
    the stored u, the natural-map error is at that level — the reader's r, u,
    mu and the cone measure agree with Siconos's."""
    p = read_fclib(DATA / "Capsules-i125-1213.hdf5")
    assert p.solution is not None and len(p.guesses) == 1
    assert natural_map_error(p, p.solution["r"], p.solution["u"]) < 1e-7


def test_cone_projection_satisfies_moreau():
    """x = P_K(x) + P_K°(x) with P_K(x) ⟂ P_K°(x): checked on random points."""
    rng = np.random.default_rng(0)
    for dim in (2, 3):
        mu = rng.uniform(0.0, 1.5, 200)
        x = rng.standard_normal(200 * dim)
        p = project_cone(x, mu, dim).reshape(-1, dim)
        X = x.reshape(-1, dim)
        for k in range(200):
            pk, rest = p[k], X[k] - p[k]
            assert np.linalg.norm(pk[1:]) <= mu[k] * pk[0] + 1e-12          # in K
            # rest in the polar cone: ‖rest_T‖ mu <= -rest_N
            assert mu[k] * np.linalg.norm(rest[1:]) <= -rest[0] + 1e-12
            assert abs(pk @ rest) <= 1e-12 * (1 + np.linalg.norm(X[k]) ** 2)


def test_bad_friction_data_is_named():
    with pytest.raises(InvalidProblemError, match=r"mu\[1\]"):
        FrictionProblem(np.eye(4), np.zeros(4), [0.3, -0.1], 2)
    with pytest.raises(InvalidProblemError, match="W must be 6 x 6"):
        FrictionProblem(np.eye(4), np.zeros(4), [0.3, 0.1], 3)
    with pytest.raises(InvalidProblemError, match="dim must be 2 or 3"):
        FrictionProblem(np.eye(4), np.zeros(4), [0.3], 4)


# -- 3-D and the cone methods ----------------------------------------------------------

THREE_D = [n for n in FILES if n not in SMALL_2D and not n.startswith(("fc2d", "gfc2d"))]
# the largest 3-D file (404 contacts of capsules: 15-40 s on a shared machine)
# runs in make test-all; the other 3-D files stay here
THREE_D = [pytest.param(n, marks=pytest.mark.slow) if n.startswith("Capsules-i101-404") else n
           for n in THREE_D]


def _one_contact(dim, a, mu=0.5):
    """W = I, q = (-1, a, 0...): the contact closes with r_N = 1; it sticks
    (r_T = -a, u = 0) when |a| <= mu and slides (r_T = -mu sign(a), u_T =
    a - mu sign(a)) when |a| > mu — solved by hand."""
    q = np.zeros(dim)
    q[0], q[1] = -1.0, a
    r = np.zeros(dim)
    r[0] = 1.0
    r[1] = -a if abs(a) <= mu else -mu * np.sign(a)
    return FrictionProblem(np.eye(dim), q, [mu], dim), r


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("a", [0.3, -0.3, 2.0, -2.0])
def test_one_contact_sticking_and_sliding_by_hand(dim, a):
    p, r_hand = _one_contact(dim, a)
    methods = ["lemke", "nsgs", "desaxce-fp", "tresca-fp", "newton", "auto"]
    for method in methods:
        s = qpcontact.solve(p, method, accuracy=1e-9)
        assert s.ok, (method, s.message)
        np.testing.assert_allclose(s.r, r_hand, atol=1e-7, err_msg=method)
        assert natural_map_error_by_hand(np.eye(dim), p.q, p.mu, s.r) <= 1e-9


@pytest.mark.parametrize("backend", ["osqp", "proxqp", "daqp", "highs", "cvxpy:OSQP"])
@pytest.mark.parametrize("a", [0.3, -2.0])
def test_2d_fixed_points_on_any_qp_backend_by_hand(backend, a):
    """In 2-D the subproblems are QPs (polyhedral cones, Tresca's interval):
    De Saxcé's and Tresca's fixed points on QP backends, sticking and
    sliding, against the hand solution."""
    p, r_hand = _one_contact(2, a)
    for method in ("desaxce-fp", "tresca-fp"):
        s = qpcontact.solve(p, method, accuracy=1e-8, backend=backend)
        assert s.ok, (method, s.message)
        np.testing.assert_allclose(s.r, r_hand, atol=1e-7, err_msg=method)
        assert natural_map_error_by_hand(np.eye(2), p.q, p.mu, s.r) <= 1e-8


@needs_data
@pytest.mark.parametrize("backend", ["osqp", "highs"])
@pytest.mark.slow
def test_2d_shared_problem_by_fixed_points_on_qp_backends(backend):
    """89 contacts: De Saxcé's and Tresca's fixed points with each iteration
    a QP (OSQP, HiGHS) certified at 1e-8 by this file's error function, and
    near Lemke's exact answer."""
    p = _read("FrictionContactProblem00071.dat")
    exact = qpcontact.solve(p, "lemke", accuracy=1e-10)
    W = p.W.toarray()
    for method in ("desaxce-fp", "tresca-fp"):
        s = qpcontact.solve(p, method, accuracy=1e-8, backend=backend)
        assert s.ok, (method, s.message)
        assert natural_map_error_by_hand(W, p.q, p.mu, s.r) <= 1e-8
        assert np.linalg.norm(s.r - exact.r) <= 1e-5 * np.linalg.norm(exact.r)


def test_qp_backends_are_refused_where_the_cones_are_not_polyhedral():
    p3, _ = _one_contact(3, 0.3)
    with pytest.raises(InvalidOptionError, match="'osqp' is a QP method.*clarabel or scs"):
        qpcontact.solve(p3, "tresca-fp", backend="osqp")
    with pytest.raises(InvalidOptionError, match="unknown cone backend 'lemke'"):
        qpcontact.solve(p3, "desaxce-fp", backend="lemke")     # an LCP method, not a QP one
    block = FrictionProblem.global_problem(np.eye(2), np.eye(2), [0.0, -1.0], np.zeros(2),
                                           [0.5], 2, reduce=False)
    with pytest.raises(InvalidOptionError, match="QP method"):
        qpcontact.solve(block, "desaxce-global", backend="osqp")
    indefinite = FrictionProblem(np.diag([1.0, -1e-9]), [-1.0, 0.1], [0.5], 2)
    with pytest.raises(NotConvexError, match="W is not positive semidefinite.*nsgs"):
        qpcontact.solve(indefinite, "tresca-fp", backend="osqp")


def test_anitescu_relaxation_is_exact_when_sticking_and_lifts_off_when_sliding():
    """The relaxation's sliding contact separates with u_N = mu (|a| - mu) /
    (1 + mu²) (projection of (1, -a) onto the cone): reported inaccurate,
    never solved."""
    stick, r_stick = _one_contact(3, 0.3)
    s = qpcontact.solve(stick, "anitescu", accuracy=1e-8)
    assert s.ok and np.allclose(s.r, r_stick, atol=1e-7)
    slide, _ = _one_contact(3, 2.0)
    s = qpcontact.solve(slide, "anitescu", accuracy=1e-8)
    assert s.status == "inaccurate" and not s.ok
    assert s.u[0] == pytest.approx(0.5 * (2.0 - 0.5) / 1.25, rel=1e-6)


def test_faceted_cone_error_shrinks_as_facets_grow():
    """Slip at 1 rad, off the facet directions: the faceted LCP's friction
    force lies in the true cone but points along the nearest facet direction,
    so its natural-map error falls with k, within 1 - cos(pi/k) (the k-gon's
    gap to the circle); slip along a facet direction is exact."""
    mu = 0.5
    d = np.array([np.cos(1.0), np.sin(1.0)])
    p = FrictionProblem(np.eye(3), np.r_[-1.0, 2.0 * d], [mu], 3)
    errors = []
    for k in (4, 8, 16, 32):
        s = qpcontact.solve(p, "lemke", accuracy=1e-8, facets=k)
        errors.append(natural_map_error_by_hand(np.eye(3), p.q, p.mu, s.r))
        assert np.linalg.norm(s.r[1:]) <= mu * s.r[0] + 1e-12          # inside the true cone
        assert 1e-4 < errors[-1] <= 1 - np.cos(np.pi / k)
        assert s.status == "inaccurate"
    assert all(b < a for a, b in zip(errors, errors[1:])), errors
    along, _ = _one_contact(3, 2.0)
    assert qpcontact.solve(along, "lemke", accuracy=1e-9, facets=8).ok


@needs_data
@pytest.mark.parametrize("name", THREE_D)
def test_every_3d_shared_problem_is_solved_to_siconos_tolerance(name):
    p, s, _ = _solved_by_auto(name)
    if p.solution is not None and np.any(p.solution["r"]):
        # solutions need not be unique: agreement is in the error measure
        stored = natural_map_error(p, p.solution["r"], p.solution["u"])
        assert s.natural_map_error <= max(1e-8, stored)


@needs_data
@pytest.mark.parametrize("name", ["FrictionContactProblem00071.dat"])
def test_2d_cone_methods_agree_with_the_exact_lcp(name):
    """89 contacts in 2-D: Lemke's exact answer is the oracle; the cone
    methods' answers satisfy the same law to their tolerance."""
    p = _read(name)
    exact = qpcontact.solve(p, "lemke", accuracy=1e-8)
    assert exact.ok, exact.message
    W = p.W.toarray()
    fp = qpcontact.solve(p, "desaxce-fp", accuracy=1e-8)
    # the fixed point stalls above 1e-8 here and says so
    assert fp.ok or fp.status == "inaccurate"
    assert fp.natural_map_error == pytest.approx(natural_map_error_by_hand(W, p.q, p.mu, fp.r), rel=1e-9)
    polished = qpcontact.solve(p, "newton", accuracy=1e-8, r0=fp.r)
    assert polished.ok, polished.message
    assert natural_map_error_by_hand(W, p.q, p.mu, polished.r) <= 1e-8
    assert np.linalg.norm(polished.r - exact.r) <= 1e-5 * np.linalg.norm(exact.r)


def test_cone_backends_and_options_are_checked():
    p, r_hand = _one_contact(3, 0.3)
    s = qpcontact.solve(p, "desaxce-fp", accuracy=1e-6, backend="scs")
    assert s.ok, s.message
    np.testing.assert_allclose(s.r, r_hand, atol=1e-5)
    with pytest.raises(InvalidOptionError, match="unknown cone backend 'mosek'"):
        qpcontact.solve(p, "desaxce-fp", backend="mosek")
    with pytest.raises(InvalidOptionError, match="does not take bogus"):
        qpcontact.solve(p, "tresca-fp", bogus=1)
    with pytest.raises(InvalidOptionError, match="facets"):
        qpcontact.solve(p, "lemke", facets=2)
    with pytest.raises(UnknownMethodError, match="no method named 'pgs'"):
        qpcontact.solve(p, "pgs")
    with pytest.raises(InvalidOptionError, match="'nsgs' does not take sweeps"):
        qpcontact.solve(p, "nsgs", sweeps=3)


@pytest.mark.slow
def test_auto_reports_what_it_tried_when_the_first_method_stalls():
    lines = []
    p = _read("Capsules-i101-404.dat") if FILES else None
    if p is None:
        pytest.skip(f"Siconos friction data not found at {DATA}")
    s = qpcontact.solve(p, "auto", accuracy=1e-8, progress=lines.append)
    assert s.ok
    assert _tried(s) == ["desaxce-fp", "newton"] and s.method == "newton"
    assert "also tried desaxce-fp" in s.message
    assert any(ln.startswith("desaxce-fp: iteration") for ln in lines)


# -- FCLIB writer ---------------------------------------------------------------------

@needs_data
@pytest.mark.parametrize("name", ["Capsules-i125-1213.hdf5", "Box_Stacks-i0122-82-5.hdf5",
                                  "FC3D_Example1_SBM.dat", "FrictionContactProblem00071.dat"])
def test_fclib_round_trip(name, tmp_path):
    p = _read(name)
    out = write_fclib(p, tmp_path / "out.hdf5", description="round trip")
    back = read_fclib(out)
    assert back.dim == p.dim and np.array_equal(back.mu, p.mu)
    W0 = p.W.toarray() if hasattr(p.W, "toarray") else np.asarray(p.W)
    W1 = back.W.toarray() if hasattr(back.W, "toarray") else np.asarray(back.W)
    if p.global_data is None:
        assert np.array_equal(W0, W1) and np.array_equal(back.q, p.q)
    else:
        for key in ("M", "H"):
            assert (abs(back.global_data[key] - p.global_data[key]) > 0).nnz == 0
        np.testing.assert_allclose(W1, W0, rtol=1e-12, atol=1e-12 * np.abs(W0).max())
    if p.solution is not None:
        for key, value in p.solution.items():
            assert np.array_equal(back.solution[key], value)
    assert len(back.guesses) == len(p.guesses)
    assert not list(tmp_path.glob("*.tmp"))


def test_fclib_writer_leaves_no_broken_file(tmp_path, monkeypatch):
    """A write that fails half-way leaves the previous file intact."""
    import h5py

    p, _ = _one_contact(3, 0.3)
    path = write_fclib(p, tmp_path / "p.hdf5", title="first")
    real = h5py.Group.create_dataset

    def broken(self, name, *a, **k):
        if name == "spacedim":
            raise OSError("disk full")
        return real(self, name, *a, **k)
    monkeypatch.setattr(h5py.Group, "create_dataset", broken)
    with pytest.raises(OSError, match="disk full"):
        write_fclib(p, path, title="second")
    monkeypatch.undo()
    assert read_fclib(path).dim == 3 and not list(tmp_path.glob("*.tmp"))


def test_componentwise_error_sees_what_the_siconos_measure_hides():
    """A stiff contact (W = 1e-5 I: displacements in m, forces in kN) whose
    exact reaction is r = (1, 0, 0).  A 1 % force error moves u by 1e-7 only:
    Siconos's measure (divided by 1 + ‖q‖ ~ 1) is 1e-7, the componentwise one
    0.01 / (1.01 + 1e5 (1e-5 + 1.01e-5)) = 3.31e-3 (by hand)."""
    from qpcontact.judge.friction_certificate import componentwise_error

    p = FrictionProblem(1e-5 * np.eye(3), [-1e-5, 0.0, 0.0], [0.3], 3)
    wrong = np.array([1.01, 0.0, 0.0])
    assert natural_map_error(p, wrong) == pytest.approx(1e-7 / (1 + 1e-5), rel=1e-6)
    assert natural_map_error_by_hand(np.asarray(p.W), p.q, p.mu, wrong) < 1e-6
    assert componentwise_error(p, wrong) == pytest.approx(0.01 / 3.02, rel=1e-6)
    assert componentwise_error(p, np.array([1.0, 0.0, 0.0])) == 0.0
    s = qpcontact.solve(p, "auto", accuracy=1e-8)
    assert s.ok and s.componentwise_error <= 1e-8
    np.testing.assert_allclose(s.r, [1.0, 0.0, 0.0], atol=1e-7)


def test_sparse_newton_on_many_independent_contacts():
    """700 independent 2-D contacts (W block diagonal and sparse: Newton's
    sparse linear algebra above 1000 unknowns), sticking and sliding mixed,
    each against its hand solution; forces on scales 1e-6 .. 1e3."""
    import scipy.sparse as sp

    rng = np.random.default_rng(3)
    nc = 700
    a = rng.uniform(-2.0, 2.0, nc)
    scale = 10.0 ** rng.uniform(-6, 3, nc)
    q = np.zeros(2 * nc)
    q[0::2], q[1::2] = -scale, a * scale
    W = sp.identity(2 * nc, format="csr")
    p = FrictionProblem(W, q, np.full(nc, 0.5), 2)
    s = qpcontact.solve(p, "newton", accuracy=1e-10)
    assert s.ok, s.message
    expected = np.zeros(2 * nc)
    expected[0::2] = scale
    expected[1::2] = np.where(np.abs(a) <= 0.5, -a, -0.5 * np.sign(a)) * scale
    np.testing.assert_allclose(s.r, expected, rtol=1e-8, atol=0)
    assert natural_map_error_by_hand(W.toarray(), q, p.mu, s.r) <= 1e-10


@needs_data
def test_the_667_contact_granular_file_is_solved_by_auto():
    """Above 200 contacts NSGS + Newton goes first, and solves it.  Every
    reaction here is ~1e-22: only the componentwise measure judges it."""
    p, s, _ = _solved_by_auto("fc2d_granularflowonwall_00667_00000.dat")
    assert s.componentwise_error <= 1e-8 and s.method == "nsgs-newton"
    assert _tried(s) == ["nsgs-newton"]


# -- global problems kept without W ----------------------------------------------------

A_HALF, H_LOW, WEIGHT, MU_BLOCK = 0.5, 0.2, 10.0, 0.5


def _block(push, M=None, reduce=None):
    """A rigid block (x, y, θ about its centre) on two frictional point
    supports at (±0.5, −0.2), weight 10 N, pushed by ``push`` [N] along x.
    Quasi-static with M = 0 by default: singular, W does not exist."""
    import scipy.sparse as sp

    cols = []
    for px in (-A_HALF, A_HALF):
        cols += [[0.0, 1.0, px], [1.0, 0.0, H_LOW]]   # normal (0, 1), tangent (1, 0) at (px, −h)
    H = np.array(cols).T
    M = np.zeros((3, 3)) if M is None else M
    return FrictionProblem.global_problem(sp.csc_matrix(M), sp.csc_matrix(H),
                                          [push, -WEIGHT, 0.0], np.zeros(4), [MU_BLOCK] * 2, 2,
                                          reduce=reduce)


def test_rigid_block_statics_by_the_global_method():
    """M = 0: kept global.  Normal reactions from the moment balance by hand,
    a(N₂ − N₁) = h P, N₁ + N₂ = W; the tangential split is not unique (only
    its sum, −P, is): checked as equilibrium and each |T| <= μN."""
    prob = _block(2.0)
    assert not prob.is_reduced and prob.W is None
    sol = qpcontact.solve(prob, accuracy=1e-9)
    assert sol.ok and sol.method == "desaxce-global", sol.message
    N = np.array([WEIGHT / 2 - H_LOW * 2.0 / (2 * A_HALF), WEIGHT / 2 + H_LOW * 2.0 / (2 * A_HALF)])
    np.testing.assert_allclose(sol.r[0::2], N, rtol=1e-9)
    np.testing.assert_allclose(sol.r[1::2].sum(), -2.0, rtol=1e-9)
    assert np.all(np.abs(sol.r[1::2]) <= MU_BLOCK * sol.r[0::2] * (1 + 1e-9))
    assert sol.equilibrium_error <= 1e-9 and sol.v is not None


def test_a_push_beyond_friction_is_proved_to_have_no_equilibrium():
    """P = 6 N > μW = 5 N: no reactions in the cones balance the loads.  The
    answer is "infeasible" with a ray d checked here: Md = 0, Hᵀd in each
    contact's dual cone, fᵀd > 0."""
    prob = _block(6.0)
    sol = qpcontact.solve(prob)
    assert sol.status == "infeasible" and not sol.ok and sol.r is None
    assert "no equilibrium exists" in sol.message
    d = sol.stats["ray"]
    g = prob.global_data
    U = (g["H"].T @ d).reshape(-1, 2)
    assert np.all(U[:, 0] >= MU_BLOCK * np.abs(U[:, 1]) - 1e-9 * np.abs(U).max())
    assert g["f"] @ d > 0


def test_reduced_and_unreduced_forms_agree_when_m_is_regular():
    """M = 1e3 I: reduced by default, kept global with reduce=False; both
    certified, with the same (unique) normal reactions, tangential sum and
    motion v."""
    M = 1e3 * np.eye(3)
    local, kept = _block(2.0, M), _block(2.0, M, reduce=False)
    assert local.is_reduced and not kept.is_reduced
    a, b = qpcontact.solve(local, accuracy=1e-9), qpcontact.solve(kept, accuracy=1e-9)
    assert a.ok and b.ok, (a.message, b.message)
    np.testing.assert_allclose(b.r[0::2], a.r[0::2], rtol=1e-8)
    np.testing.assert_allclose(b.r[1::2].sum(), a.r[1::2].sum(), rtol=1e-8)
    v_local = local.global_velocity(a.r)     # 0 here: both contacts stick
    free_scale = WEIGHT / 1e3                 # the motion the loads would cause unsupported
    np.testing.assert_allclose(b.v, v_local, atol=1e-8 * free_scale)


def test_unreduced_problems_name_what_solves_them():
    prob = _block(2.0)
    with pytest.raises(InvalidOptionError, match="kept without W.*desaxce-global"):
        qpcontact.solve(prob, "newton")
    with pytest.raises(InvalidOptionError, match="without W"):
        prob.velocities(np.zeros(4))
    with pytest.raises(InvalidProblemError, match="cannot reduce.*singular"):
        _block(2.0, reduce=True)
    with pytest.raises(InvalidOptionError, match="local form"):
        qpcontact.solve(_block(2.0, 1e3 * np.eye(3)), "desaxce-global")
    with pytest.raises(InvalidProblemError, match="symmetric"):
        _block(2.0, np.triu(np.ones((3, 3))))


def test_too_many_contacts_keep_a_global_problem_unreduced(monkeypatch):
    """Above DENSE_W_LIMIT local unknowns W would be dense and too large: the
    problem stays global (the reason says so) and is solved without W to the
    reduced form's normal reactions."""
    import qpcontact.core.friction_problem as friction

    M = 1e3 * np.eye(3)
    reference = qpcontact.solve(_block(2.0, M), accuracy=1e-9)
    monkeypatch.setattr(friction, "DENSE_W_LIMIT", 2)
    prob = _block(2.0, M)
    assert not prob.is_reduced and "dense" in prob.global_data["unreduced_because"]
    sol = qpcontact.solve(prob, accuracy=1e-9)
    assert sol.ok, sol.message
    np.testing.assert_allclose(sol.r[0::2], reference.r[0::2], rtol=1e-8)


NSGS_SOLVES = ["FC2D_SliderCrankLagrangian00000.dat", "FrictionContactProblem00071.dat",
               "fc2d_granularflowonwall_00667_00000.dat", "Capsules-i125-1213.hdf5",
               "Box_Stacks-i0122-82-5.hdf5", "NESpheres_10_1.dat", "Rover1040.dat"]


@needs_data
@pytest.mark.parametrize("name", NSGS_SOLVES)
def test_nsgs_solves_shared_problems_to_siconos_tolerance(name):
    """Nonsmooth Gauss–Seidel (Siconos's workhorse) on 2-D and 3-D files:
    certified at 1e-8, the answer checked by this file's own error function."""
    p = _read(name)
    s = qpcontact.solve(p, "nsgs", accuracy=1e-8)
    assert s.ok and s.method == "nsgs", s.message
    W = p.W.toarray() if hasattr(p.W, "toarray") else np.asarray(p.W)
    assert natural_map_error_by_hand(W, p.q, p.mu, s.r) <= 1e-8


def test_drum_and_mechanism_steps_export_as_frictionless_fclib_problems(tmp_path):
    """A drum step's LCP and a mechanism step's exact LCP, exported through
    FrictionProblem.frictionless and FCLIB, solved by qpcontact.solve: the
    same contact forces as the step's own certified solve, no friction."""
    from formulations.drum import Drum, Log
    from formulations.mechanisms import ramming_impact_step
    from formulations.mechanisms.penalty import exact_lcp
    from qpcontact.dispatch.driver import solve

    logs = [Log.from_wood(0.12, 1.2), Log.from_wood(0.18, 1.2)]
    drum = Drum(logs, [0.002, 0.001], [-1.0, -1.5], effects=("gravity",))
    kept = {}
    drum.simulate(drum.contact_periods().min() / 40, 300,
                  on_step=lambda n, lcp, sol: kept.setdefault("step", (lcp, sol))
                  if sol.z.max() > 0 else None)
    lcp_m = exact_lcp(ramming_impact_step())
    cases = [kept["step"], (lcp_m, solve(lcp_m, "lemke"))]
    for k, (lcp, sol) in enumerate(cases):
        assert sol.ok and sol.z.max() > 0
        prob = read_fclib(write_fclib(FrictionProblem.frictionless(lcp, 2), tmp_path / f"{k}.h5"))
        fs = qpcontact.solve(prob, accuracy=1e-10)
        assert fs.ok, fs.message
        np.testing.assert_allclose(fs.r[0::2], sol.z, rtol=1e-8, atol=1e-10 * sol.z.max())
        assert np.all(fs.r[1::2] == 0) or np.abs(fs.r[1::2]).max() <= 1e-12 * sol.z.max()


def test_a_load_on_a_free_motion_without_contacts_has_no_equilibrium():
    """M = diag(1, 0), no contacts, f = (1, 1): the second coordinate is free
    and loaded.  The ray, cleaned of the interior point's noise, is exactly
    d = (0, 1) (Md = 0, fᵀd = 1)."""
    import scipy.sparse as sp

    prob = FrictionProblem.global_problem(sp.csc_matrix(np.diag([1.0, 0.0])),
                                          sp.csc_matrix((2, 0)), [1.0, 1.0], np.zeros(0), [], 2)
    sol = qpcontact.solve(prob)
    assert sol.status == "infeasible", sol.message
    np.testing.assert_array_equal(sol.stats["ray"], [0.0, 1.0])
    held = FrictionProblem.global_problem(sp.csc_matrix(np.diag([1.0, 0.0])),
                                          sp.csc_matrix((2, 0)), [1.0, 0.0], np.zeros(0), [], 2)
    sol = qpcontact.solve(held, accuracy=1e-10)
    assert sol.ok and abs(sol.v[0] - 1.0) < 1e-10, sol.message


# the two granular-flow files take 17-30 s of Lemke each (make test-all);
# Lemke on the 2 020-contact one also runs in
# test_auto_goes_on_to_the_interior_point_where_nsgs_stalls
TWO_D = SMALL_2D + [pytest.param("fc2d_granularflowonwall_00667_00000.dat", marks=pytest.mark.slow),
                    pytest.param("fc2d_granularflowonwall_02020_00213.dat", marks=pytest.mark.slow),
                    "gfc2d_granularflowonwall_00000_00117.dat"]


@needs_data
@pytest.mark.parametrize("name", TWO_D)
def test_every_2d_shared_problem_is_solved_by_lemke(name):
    """The exact route on every 2-D file, up to 2020 contacts (8080 LCP
    unknowns: the sparse revised Lemke), at Siconos's tolerance 1e-8 by this
    file's own error function, and componentwise."""
    p = _read(name)
    s = qpcontact.solve(p, "lemke", accuracy=1e-8, time_limit=None)
    assert s.ok and s.method == "lemke", s.message
    assert s.componentwise_error <= 1e-8
    W = p.W.toarray() if hasattr(p.W, "toarray") else np.asarray(p.W)
    assert natural_map_error_by_hand(W, p.q, p.mu, s.r) <= 1e-8


@needs_data
@pytest.mark.slow   # two Lemke solves of 8 080 unknowns (33 s); the polish itself runs in
# test_auto_goes_on_to_the_interior_point_where_nsgs_stalls
def test_a_basic_solution_at_rounding_level_contacts_is_polished():
    """On the 2020-contact file q holds rounding residues (1e-17) beside
    forces of 1e-3; Lemke's basic solution, exact in the natural-map measure,
    misses the componentwise one at those contacts, and the message says it
    was polished.  Without the polish (its Newton stubbed out) the answer is
    reported inaccurate, not passed."""
    import qpcontact.solvers.friction.lcp_route as lcp_route

    p = _read("fc2d_granularflowonwall_02020_00213.dat")
    s = qpcontact.solve(p, "lemke", accuracy=1e-8, time_limit=None)
    assert s.ok and "polished by Newton" in s.message, s.message
    assert s.stats["polish_iterations"] <= 5
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(lcp_route, "solve_natural_newton", lambda p, tol, o: (None, "failed", "", {}))
        raw = qpcontact.solve(p, "lemke", accuracy=1e-8, time_limit=None)
    assert not raw.ok and raw.status == "inaccurate" and raw.natural_map_error <= 1e-12
    assert raw.componentwise_error > 1e-8 and "did not improve" in raw.message


@needs_data
@pytest.mark.slow
def test_auto_goes_on_to_the_interior_point_where_nsgs_stalls():
    """2020 contacts: NSGS + Newton first (above 200 contacts), which stalls
    near 4e-7 on this file; then ip-lcp certifies (the answer checked by the
    error function written here), and the message names both links with
    their times.  Lemke, the exact route "auto" took here before, certifies
    it too, its basic solution polished."""
    p, s, _ = _solved_by_auto("fc2d_granularflowonwall_02020_00213.dat")
    assert s.method == "ip-lcp" and _tried(s) == ["nsgs-newton", "ip-lcp"], s.message
    assert "links: nsgs-newton: error" in s.message and "ip-lcp: error" in s.message
    # Lemke's basic solution misses the rounding-level contacts and is polished
    # (the polish's must-fail half is test_a_basic_solution_..._is_polished, slow)
    lemke = qpcontact.solve(p, "lemke", accuracy=1e-8, time_limit=None)
    assert lemke.ok and "polished by Newton" in lemke.message, lemke.message
