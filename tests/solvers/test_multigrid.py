"""The multilevel route "mg-bpp": its answers equal the exact
oracle's — the energy method's, a manufactured solution's, or a closed form —
on several meshes, with the problem's own grid hierarchy and with the one it
builds by aggregation; a hierarchy that does not match is refused; a poor
hierarchy costs time, never the answer; the exact finish reuses its
factorization; and "auto" routes by structure."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
import scipy.sparse as sp

import qpcontact
from formulations import meshes
from qpcontact import LCP, InvalidProblemError
from qpcontact.dispatch.routes import auto_order
from qpcontact.solvers.pivoting.multigrid import COARSEST_MAX


def _without_hierarchy(lcp):
    bare = LCP(lcp.M, lcp.q, q_terms=lcp.q_terms)
    bare.structure.declare_spd()
    return bare


def _energy(lcp):
    ref = qpcontact.solve(lcp, method="energy")
    assert ref.ok, ref.message
    return ref.z


@pytest.mark.parametrize("family,N", [("membrane", 15), ("membrane", 24), ("membrane", 31),
                                      ("plate", 12), ("plate", 19)])
@pytest.mark.parametrize("hierarchy", ["grid", "aggregation"])
def test_equals_the_energy_method_on_meshes(family, N, hierarchy):
    lcp = getattr(meshes, family)(N)
    assert lcp.structure.hierarchy is not None
    z_ref = _energy(lcp)
    assert 0 < np.count_nonzero(z_ref == 0) < z_ref.size
    problem = lcp if hierarchy == "grid" else _without_hierarchy(lcp)
    sol = qpcontact.solve(problem, method="mg-bpp")
    assert sol.ok, sol.message
    assert sol.stats["hierarchy"] == ("given" if hierarchy == "grid" else "aggregation")
    if hierarchy == "grid" or N * N > COARSEST_MAX:   # else solved at once, densely
        assert sol.stats["mg_levels"] >= 2
    np.testing.assert_allclose(sol.z, z_ref, rtol=0, atol=1e-10 * np.abs(z_ref).max())
    np.testing.assert_array_equal(sol.z == 0, z_ref == 0)


@pytest.mark.parametrize("family", ["membrane", "plate"])
@pytest.mark.parametrize("scale", [1.0, 1e9])
def test_degenerate_pairs_recover_the_manufactured_solution(family, scale):
    """10 % of the pairs have z_i = w_i = 0: no strict complementarity."""
    N = 20
    lcp = getattr(meshes, family)(N, degenerate=True, scale=scale, seed=5)
    z_true, w_true = meshes._manufactured(np.random.default_rng(5), N * N)
    assert np.count_nonzero((z_true == 0) & (w_true == 0)) >= 0.09 * N * N
    for problem in (lcp, _without_hierarchy(lcp)):
        sol = qpcontact.solve(problem, method="mg-bpp")
        assert sol.ok, sol.message
        np.testing.assert_allclose(sol.z, z_true, rtol=0, atol=1e-10 * z_true.max())


def test_obstacle_nowhere_active_gives_the_unconstrained_solution():
    """q = -M z* with z* > 0: the membrane never touches, z = z*."""
    N = 33
    M = meshes.membrane(N).M
    z_star = 1.0 + np.random.default_rng(0).uniform(size=N * N)
    lcp = LCP(M, -(M @ z_star), hierarchy=meshes.grid_hierarchy(N))
    sol = qpcontact.solve(lcp, method="mg-bpp")
    assert sol.ok, sol.message
    assert np.all(sol.z > 0)
    np.testing.assert_allclose(sol.z, z_star, rtol=1e-11)


def test_obstacle_above_the_membrane_everywhere_holds_it_on_the_obstacle():
    """A load pushing the membrane into an obstacle it touches everywhere
    (q > 0): z = 0 and w = q."""
    N = 33
    lcp = LCP(meshes.membrane(N).M, np.linspace(1.0, 2.0, N * N),
              hierarchy=meshes.grid_hierarchy(N))
    sol = qpcontact.solve(lcp, method="mg-bpp")
    assert sol.ok, sol.message
    np.testing.assert_array_equal(sol.z, 0.0)
    np.testing.assert_array_equal(sol.w, lcp.q)


def test_a_poor_hierarchy_costs_cycles_not_the_answer():
    """Random nonnegative prolongations of the right shapes: the coarse
    corrections are useless, the answer is still the exact one."""
    N = 24
    lcp = meshes.membrane(N)
    rng = np.random.default_rng(1)
    shapes = [N * N, 150, 40]
    junk = [sp.random(a, b, density=0.05, random_state=rng, format="csr")
            + sp.eye(a, b, format="csr") for a, b in zip(shapes, shapes[1:])]
    bad = LCP(lcp.M, lcp.q, q_terms=lcp.q_terms, hierarchy=junk)
    bad.structure.declare_spd()
    sol = qpcontact.solve(bad, method="mg-bpp")
    assert sol.ok, sol.message
    z_ref = _energy(lcp)
    np.testing.assert_allclose(sol.z, z_ref, rtol=0, atol=1e-10 * np.abs(z_ref).max())


def test_a_plate_stops_cycling_once_its_contact_set_holds():
    """On a plate (4th order) the truncated cycles stall at a residual near
    1e-4 of ‖q‖ once the contact set is found (the ridge on 50 x 50: the set
    held, 506 cycles to the 500-cycle limit); the set held for HELD_STOP
    cycles ends them, and the exact finish from it is the answer plain block
    pivoting finds from nothing."""
    lcp = meshes.plate(50, obstacle="ridge")
    sol = qpcontact.solve(lcp, method="mg-bpp")
    assert sol.ok, sol.message
    assert sol.stats["mg_cycles"] < 150
    ref = qpcontact.solve(lcp, method="bpp")
    assert ref.ok
    np.testing.assert_array_equal(sol.z > 0, ref.z > 0)
    np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-10 * np.abs(ref.z).max())


def _hierarchy_of(lcp, hierarchy):
    from qpcontact.solvers.pivoting.multigrid import _product, aggregation_hierarchy

    A = sp.csr_matrix(lcp.M)
    Ps = (list(lcp.structure.hierarchy) if hierarchy == "grid"
          else list(aggregation_hierarchy(lcp.M)))
    Rs = [P.T.tocsr() for P in Ps]
    patterns, B = [], A
    for P, R in zip(Ps, Rs):
        B = _product(R, B, P, None)
        patterns.append(B)
    return A, Ps, Rs, patterns


@pytest.mark.parametrize("family,N", [("plate", 37), ("membrane", 40)])
def test_the_sweeps_add_the_neighbour_just_written_last_and_stay_gauss_seidel(family, N):
    """The compiled sweeps sum each row's terms with the neighbour the
    previous row just wrote (i − 1 forward, i + 1 backward) last, off the
    dependency chain (_mg_kernels' comment says why): still Gauss–Seidel —
    each row reads that neighbour's new value — equal to the column-order
    sweeps of tests/helpers/multigrid_reference.py to rounding, on the
    fine operator (sorted columns) and on its Galerkin product (unsorted),
    with truncated rows, both directions; and the projected sweeps too.
    Fails where the neighbour's term is dropped or read before it is
    written (a Jacobi term): both differ by far more than rounding."""
    from qpcontact.solvers.pivoting import _mg_kernels as K
    from tests.helpers.multigrid_reference import gauss_seidel, projected_gauss_seidel

    lcp = getattr(meshes, family)(N)
    A, _, _, patterns = _hierarchy_of(lcp, "grid")
    rng = np.random.default_rng(3)
    for B in (A, patterns[0]):
        n = B.shape[0]
        ptr, idx = B.indptr.astype(np.int64), B.indices.astype(np.int64)
        d = B.diagonal()
        free = rng.random(n) < 0.8
        b, x0 = rng.standard_normal(n), rng.standard_normal(n)
        for forward in (True, False):
            ours, ref = x0.copy(), x0.copy()
            K.gauss_seidel(ptr, idx, B.data, 1.0 / d, b, ours, free, forward)
            gauss_seidel(ptr, idx, B.data, d, b, ref, free, forward)
            np.testing.assert_allclose(ours, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
            jacobi = x0 + np.where(free, (b - B @ x0) / d, 0.0)
            assert np.abs(ours - jacobi).max() > 1e-3 * np.abs(ref).max()
        q = rng.standard_normal(n) * np.abs(d)
        ours, ref = np.abs(x0), np.abs(x0)
        K.projected_gauss_seidel(ptr, idx, B.data, 1.0 / d, q, ours, 3)
        projected_gauss_seidel(ptr, idx, B.data, d, q, ref, 3)
        np.testing.assert_allclose(ours, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())


@pytest.mark.parametrize("family,N,hierarchy", [("plate", 37, "grid"), ("membrane", 40, "grid"),
                                                 ("plate", 30, "aggregation"),
                                                 ("membrane", 45, "aggregation")])
def test_truncated_coarse_operators_follow_the_contact_set(family, N, hierarchy):
    """The compiled cycle keeps P'TMTP current by recomputing only the
    coarse rows a moved unknown reaches: after moves of 1 to n/3 unknowns
    every level's operator equals SciPy's product R T A T P of the moved
    truncation (to rounding: the sums run in another order), bit for bit a
    build from nothing, and so does the V-cycle; the V-cycle and the
    W-cycle equal the Python recursion (tests/helpers/multigrid_reference.py)
    to rounding."""
    from qpcontact.solvers.pivoting import _mg_kernels as K
    from qpcontact.solvers.pivoting.multigrid import _Levels
    from tests.helpers.multigrid_reference import Correction, nonzero_rows

    lcp = getattr(meshes, family)(N)
    A, Ps, Rs, patterns = _hierarchy_of(lcp, hierarchy)
    n = A.shape[0]

    def truncated(free, levels=None):
        first = levels is None
        levels = levels or _Levels([A] + patterns, Ps, Rs)
        H, S = levels.below(0)
        changed = (free != levels.truncation(0)) | first
        levels.truncation(0)[:] = free
        K.retruncate(H, S, changed)
        return levels

    rng = np.random.default_rng(1)
    free = rng.random(n) < 0.6
    kept = truncated(free)
    for step in range(15):
        moved = rng.choice(n, [1, 3, 10, 50, n // 3][step % 5], replace=False)
        free = free.copy()
        free[moved] = ~free[moved]
        truncated(free, kept)
        fresh = truncated(free)
        keep, B = free, A
        for k, (P, R) in enumerate(zip(Ps, Rs), start=1):
            T = sp.diags(keep.astype(float))
            B = (R @ T @ B @ T @ P).tocsr()
            C = kept.operator(k)
            np.testing.assert_allclose(C.toarray(), B.toarray(), rtol=0,
                                       atol=1e-14 * np.abs(B.data).max())
            keep = nonzero_rows(B.diagonal())
            np.testing.assert_array_equal(kept.truncation(k), keep)
            np.testing.assert_array_equal(C.data, fresh.operator(k).data)
        b = np.where(free, rng.standard_normal(n), 0.0)
        c = K.cycle(*kept.below(0), b, 1).copy()
        np.testing.assert_array_equal(c, K.cycle(*fresh.below(0), b, 1))
        python = Correction(A, A.diagonal(), Ps, Rs, free, patterns)
        v = python.vcycle(b)
        np.testing.assert_allclose(c, v, rtol=0, atol=1e-10 * np.abs(v).max())
        # the W-cycle: the recursion's two visits per level, unrolled
        w = python.vcycle(b, visits=2)
        c = K.cycle(*kept.below(0), b, 2)
        np.testing.assert_allclose(c, w, rtol=0, atol=1e-10 * np.abs(w).max())
        if len(Ps) >= 2:    # else the one coarse level is solved once either way
            assert np.abs(w - v).max() > 1e-6 * np.abs(w).max()


@pytest.mark.parametrize("family,N,hierarchy,D,visits", [("membrane", 31, "grid", 1.0, 1),
                                                          ("plate", 31, "grid", 0.05, 2),
                                                          ("plate", 29, "grid", 1.0, 1),
                                                          ("plate", 27, "aggregation", 1.0, 2),
                                                          ("membrane", 33, "aggregation", 1.0, 1)])
def test_the_compiled_cycle_repeats_the_python_cycle(family, N, hierarchy, D, visits):
    """The whole cycle compiled (smoothing, truncation, V- or W-cycle, line
    search, the held-set count) gives the Python cycle's iterates
    (tests/helpers/multigrid_reference.py) to rounding after every cycle,
    and stops after the same number of cycles."""
    from qpcontact.solvers.pivoting.multigrid import _Levels, _tnnmg
    from tests.helpers.multigrid_reference import tnnmg

    kw = {"tension": D} if family == "membrane" else {"rigidity": D}
    lcp = getattr(meshes, family)(N, obstacle="bumps", **kw)
    A, Ps, Rs, patterns = _hierarchy_of(lcp, hierarchy)
    q = np.asarray(lcp.q, dtype=float)
    start = np.maximum(Ps[0] @ np.abs(np.random.default_rng(2).standard_normal(Ps[0].shape[1])),
                       0.0)
    runs = {}
    for cycles in (1, 2, 3, 5, 8, 500):
        for name in ("compiled", "python"):
            stats = {"mg_cycles": 0, "mg_rebuilds": 0}
            z = (_tnnmg(_Levels([A] + patterns, Ps, Rs, visits), 0, q, start.copy(), cycles,
                        1e-8, stats, None, "level 0") if name == "compiled"
                 else tnnmg(A, q, Ps, Rs, patterns, start.copy(), cycles, 1e-8, stats, None,
                            "level 0", visits))
            runs[name] = z, stats
        (z, stats), (z_ref, stats_ref) = runs["compiled"], runs["python"]
        np.testing.assert_allclose(z, z_ref, rtol=0, atol=1e-9 * np.abs(z_ref).max())
        np.testing.assert_array_equal(z > 0, z_ref > 0)
        assert stats == stats_ref
    assert stats["mg_cycles"] < 500


def test_a_plate_starts_from_the_shifted_coarse_answers():
    """A plate's coarse levels approximate z − z_u (z_u the gap with no
    contact), which vanishes on the held edge, instead of z = u − ψ and its
    boundary layer: on the 100 x 100 dome at D = 1 the plain nested start
    put 797 of the 2588 contact nodes at the obstacle and its set crept for
    143 cycles; the shifted start needs well under half of that, and the
    answer is the one block pivoting finds from nothing.  The injection it
    reads coarse values by is each coarse node's own fine node."""
    from qpcontact.solvers.pivoting.multigrid import _coincident, multilevel_guess

    N = 9
    fine = np.arange(N * N).reshape(N, N)
    P = meshes.grid_hierarchy(N)[0]
    np.testing.assert_array_equal(_coincident(P.T.tocsr()), fine[1::2, 1::2].ravel())

    lcp = meshes.plate(100, rigidity=1.0)
    cycles = {}
    for shifted in (False, True):
        stats = {}
        multilevel_guess(lcp.M, lcp.q, lcp.structure.hierarchy, cycles=500, stats=stats,
                         shifted=shifted)
        assert stats["shifted"] is shifted
        cycles[shifted] = stats["mg_cycles"]
    assert cycles[True] < 0.5 * cycles[False], cycles
    sol = qpcontact.solve(lcp, method="mg-bpp")
    assert sol.ok and sol.stats["shifted"]
    ref = qpcontact.solve(lcp, method="ip-bpp")
    assert ref.ok
    np.testing.assert_array_equal(sol.z > 0, ref.z > 0)
    np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-10 * np.abs(ref.z).max())


def _unconstrained_gap(lcp, visits):
    from qpcontact.solvers.pivoting import multigrid as mg

    Ps = lcp.structure.hierarchy
    As, Rs = [mg._csr(lcp.M)], [P.T.tocsr() for P in Ps]
    for P, R in zip(Ps, Rs):
        As.append(mg._product(R, As[-1], P, None))
    H, S = mg._Levels(As, Ps, Rs, visits).below(0)
    return mg._kernels().unconstrained_gap(H, S, lcp.q, mg.GAP_STEPS, mg.GAP_RTOL, visits)


@pytest.mark.parametrize("rigidity", [0.05, 1.0])
@pytest.mark.parametrize("visits", [1, 2])
def test_the_shift_is_the_unconstrained_gap_to_its_tolerance(rigidity, visits):
    """z_u = −M⁻¹q by conjugate gradients preconditioned with the V- or
    W-cycle: its residual, measured here with SciPy's product, is at the
    tolerance it reports, and z_u is SciPy's direct solve to within what
    that residual allows (M's condition on a 40 x 40 plate: ~1e4).  A
    W-cycle that were not symmetric would break CG here."""
    import scipy.sparse.linalg as spla

    from qpcontact.solvers.pivoting import multigrid as mg

    lcp = meshes.plate(40, obstacle="crate", rigidity=rigidity)
    x, steps, residual = _unconstrained_gap(lcp, visits)
    scale = np.abs(lcp.q).max()
    true = np.abs(lcp.M @ x + lcp.q).max() / scale
    assert true <= mg.GAP_RTOL and abs(true - residual) <= 1e-12, (true, residual)
    assert 0 < steps < mg.GAP_STEPS
    exact = spla.spsolve(sp.csc_matrix(lcp.M), -lcp.q)
    assert np.abs(x - exact).max() <= 1e-2 * np.abs(exact).max()


#: Obstacles not in meshes.OBSTACLES and not looked at when the W-cycle and
#: the interpolation weights were chosen (docs/dev-notes.md, round four's
#: held-out shapes): a damped ripple and a wedge under a wavy crest.
HELD_OUT = {
    "ripple": lambda x, y: (0.1 * np.cos(9.0 * np.hypot(x - 0.3, y - 0.7))
                            * np.exp(-2.0 * np.hypot(x - 0.3, y - 0.7)) + 0.04 * x),
    "wedge": lambda x, y: np.minimum(0.18 - 0.5 * np.abs(y - 0.3 - 0.4 * x),
                                     0.12 + 0.1 * np.sin(5.0 * x)),
}


@pytest.mark.parametrize("shape", sorted(HELD_OUT))
@pytest.mark.parametrize("N,rigidity", [(38, 0.05), (45, 1.0)])
def test_a_plates_w_cycles_give_block_pivotings_answer_on_shapes_held_out(shape, N, rigidity,
                                                                          monkeypatch):
    """mg-bpp on a plate (W-cycles, the shifted start) ends on the answer
    plain block pivoting finds from nothing, on obstacles not tuned on, at
    a size whose coarse grids are not uniform (N even) and one whose are."""
    monkeypatch.setitem(meshes.OBSTACLES, shape, HELD_OUT[shape])
    lcp = meshes.plate(N, obstacle=shape, rigidity=rigidity)
    sol = qpcontact.solve(lcp, method="mg-bpp")
    assert sol.ok, sol.message
    assert sol.stats["w_cycles"] and sol.stats["shifted"]
    ref = qpcontact.solve(lcp, method="bpp")
    assert ref.ok, ref.message
    assert 0 < np.count_nonzero(ref.z == 0) < ref.z.size
    np.testing.assert_array_equal(sol.z > 0, ref.z > 0)
    np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-10 * np.abs(ref.z).max())


def test_a_plates_w_cycle_keeps_the_gap_steps_from_growing_with_the_grid():
    """The 13-point biharmonic on the grid's bilinear coarse levels: CG on
    the V-cycle takes 19 steps at 100 x 100 and 30 at 316 x 316 (the steps
    grow with the grid), on the W-cycle 9 and 10.  With the coarse grids'
    interpolation weights of ½ next to their narrower last cell (as if they
    were uniform: N even) the W-cycle took 16 and 28.  Bounds with a
    margin: at most 12 W-cycle steps at both sizes."""
    steps = {}
    for N in (100, 316):
        lcp = meshes.plate(N, obstacle="crate", rigidity=0.05)
        for visits in (1, 2):
            _, steps[N, visits], residual = _unconstrained_gap(lcp, visits)
            assert residual <= 1e-4
    assert steps[100, 2] <= 12 and steps[316, 2] <= 12, steps
    assert steps[316, 1] > steps[100, 1] + 5, steps   # what the W-cycle is for


@pytest.mark.parametrize("make,needle", [
    (lambda n: [sp.random(n + 1, 30, density=0.3, format="csr")], "level 0: the prolongation has"),
    (lambda n: [sp.eye(n, 50, format="csr"), sp.eye(40, 10, format="csr")],
     "level 1: the prolongation has 40 rows but level 1's 50"),
    (lambda n: [sp.eye(n, n, format="csr")], "fewer unknowns"),
    (lambda n: [sp.csr_matrix(np.hstack([np.eye(n, 5), np.zeros((n, 1))]))],
     "coarse unknown 5 (of 6) has no fine support"),
    (lambda n: sp.eye(n, 10, format="csr"), "wrap it in a list"),
    (lambda n: [], "empty"),
    (lambda n: [np.full((n, 3), np.nan)], "not finite"),
])
def test_a_hierarchy_that_does_not_match_is_refused(make, needle):
    M = meshes.membrane(10).M
    with pytest.raises(InvalidProblemError, match="hierarchy") as info:
        LCP(M, np.ones(100), hierarchy=make(100))
    assert needle in str(info.value)


def test_hierarchy_survives_pickling_and_is_shared_by_a_structure():
    lcp = meshes.membrane(15)
    back = pickle.loads(pickle.dumps(lcp))
    assert len(back.structure.hierarchy) == len(lcp.structure.hierarchy)
    for a, b in zip(back.structure.hierarchy, lcp.structure.hierarchy):
        assert (a != b).nnz == 0
    other = LCP.with_structure(lcp.structure, -lcp.q)
    assert other.structure.hierarchy is lcp.structure.hierarchy


def test_the_aggregated_hierarchy_is_kept_for_the_next_lcp_on_the_same_matrix():
    bare = _without_hierarchy(meshes.membrane(40))
    first = qpcontact.solve(bare, method="mg-bpp")
    assert "setup_time" in first.stats
    again = qpcontact.solve(LCP.with_structure(bare.structure, bare.q * 2), method="mg-bpp")
    assert again.ok and "setup_time" not in again.stats


@pytest.mark.slow
def test_the_finish_solves_nearby_bases_on_one_factorization():
    """bpp started a few components away from the answer: one factorization,
    the rest on it, bordered — same answer as from nothing."""
    lcp = meshes.membrane(40)
    z_ref = _energy(lcp)   # the tableau method: no factorization shared with bpp
    guess = z_ref > 0
    flip = np.flatnonzero(np.diff(guess.astype(int)))[:6]   # on the free boundary
    guess[flip] = ~guess[flip]
    sol = qpcontact.solve(lcp, method="bpp", initial_active=guess)
    assert sol.ok, sol.message
    assert sol.stats["factorizations"] == 1
    assert sol.stats["bordered_solves"] >= 1
    np.testing.assert_allclose(sol.z, z_ref, rtol=0, atol=1e-12 * z_ref.max())


@pytest.mark.slow
def test_ip_bpp_pivoting_reuses_its_factorization_for_nearby_bases():
    """ip-bpp's pivoting phase from nothing (max_ip=0) on a plate: the late
    exchanges move few components and are solved by CG on the last factor."""
    lcp = meshes.plate(30)
    sol = qpcontact.solve(lcp, method="ip-bpp", max_ip=0)
    assert sol.ok, sol.message
    assert sol.stats["krylov_solves"] >= 1
    assert sol.stats["factorizations"] < sol.stats["iterations"]
    z_ref = _energy(lcp)
    np.testing.assert_allclose(sol.z, z_ref, rtol=0, atol=1e-10 * z_ref.max())


@pytest.mark.parametrize("rigidity", [0.05, 1.0])
def test_a_basis_near_the_factorized_one_is_solved_on_its_border(rigidity):
    """NearbyBases on a plate (entries of both signs): a basis with unknowns
    added to and removed from the factorized one, solved on the old factor
    bordered by them, equals SciPy's sparse solve of its own block (an LU
    of M_FF, not our factor) to rounding; one factorization, a solve per
    border column, and a second basis sharing part of the border reuses
    those columns.  Fails if a removed unknown's row kept its equation (its
    multiplier dropped) or an added column were left out."""
    import scipy.sparse.linalg as spla

    from qpcontact.solvers.pivoting.finish import NearbyBases

    lcp = meshes.plate(45, rigidity=rigidity)      # n / REUSE_SHARE = 10 >= the 5 moved
    M, q = lcp.M, lcp.q
    F0 = qpcontact.solve(lcp, method="bpp").z > 0
    stats = {}
    bases = NearbyBases(M, q, stats)
    bases.basic_solution(F0, refine=0)
    free, held = np.flatnonzero(F0), np.flatnonzero(~F0)
    F = F0.copy()
    F[free[::97][:3]] = False          # removed: held at zero by a multiplier
    F[held[::89][:2]] = True           # added: their columns border the factor
    for basis in (F, np.where(np.arange(F.size) == free[::97][0], True, F)):
        z, w = bases.basic_solution(basis)
        idx = np.flatnonzero(basis)
        ref = np.zeros(q.size)
        ref[idx] = spla.spsolve(sp.csc_matrix(M)[idx][:, idx], -q[idx])
        np.testing.assert_allclose(z, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
        assert np.all(z[~basis] == 0) and np.all(w[basis] == 0)
        np.testing.assert_allclose(w[~basis], (M @ ref + q)[~basis], rtol=0,
                                   atol=1e-10 * np.abs(q).max())
    assert stats["factorizations"] == 1 and stats["bordered_solves"] == 2
    assert stats["border_columns"] == 5          # the second basis: one column fewer, all kept


def test_the_finest_level_of_a_small_mesh_stops_at_its_first_held_cycle():
    """Below FIRST_HOLD_MAX unknowns the finest level's cycles end at the
    first that leaves the contact set unchanged (its exact finish checks
    the set); on the coarser levels, and above FIRST_HOLD_MAX on the finest,
    the set holds for more cycles.  The answer is block pivoting's."""
    from qpcontact.solvers.pivoting import multigrid

    lcp = meshes.plate(40, obstacle="crate", rigidity=0.05)
    lines = []
    sol = qpcontact.solve(lcp, method="mg-bpp", progress=lines.append)
    assert sol.ok, sol.message
    finest = [line for line in lines if "level 0 cycle" in line]
    assert finest[-1].endswith(" 0 changed") and not finest[-2].endswith(" 0 changed")
    ref = qpcontact.solve(lcp, method="bpp")
    np.testing.assert_array_equal(sol.z > 0, ref.z > 0)
    np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-10 * np.abs(ref.z).max())
    held = []
    stats = {}
    multigrid.multilevel_guess(lcp.M, lcp.q, lcp.structure.hierarchy, cycles=500, stats=stats,
                               shifted=True, w_cycles=True, progress=held.append)
    assert len([line for line in held if "level 0 cycle" in line]) == len(finest)


def test_a_held_set_whose_basis_breaks_many_bounds_sends_the_search_back_to_the_cycles():
    """The 140 x 140 plate at D = 1 under the terraces: its finest level
    holds a set 5 components off whose exact basic solution puts hundreds
    of free nodes below the obstacle (more than the factor can border).
    Block pivoting from it took 82 exchanges and 44 factorizations; the
    cycles resumed from that basic solution (projected) find the final set,
    and the finish is one more factorization and no exchange."""
    lcp = meshes.plate(140, obstacle="terraces", rigidity=1.0)
    sol = qpcontact.solve(lcp, method="mg-bpp")
    assert sol.ok, sol.message
    assert sol.stats["restarts"] == 1
    assert sol.stats["factorizations"] == 2 and sol.stats["iterations"] == 0


@pytest.mark.slow
def test_the_resumed_search_ends_at_interior_point_block_pivotings_answer():
    """The plate of the test above: mg-bpp (its search resumed once) and
    ip-bpp (an interior point and its own pivoting: another route) end on
    the same contact set and z."""
    lcp = meshes.plate(140, obstacle="terraces", rigidity=1.0)
    sol = qpcontact.solve(lcp, method="mg-bpp")
    ref = qpcontact.solve(lcp, method="ip-bpp")
    assert sol.ok and ref.ok
    assert sol.stats["restarts"] == 1
    np.testing.assert_array_equal(sol.z > 0, ref.z > 0)
    np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-9 * np.abs(ref.z).max())


def _finest_cycles(lines):
    """(free, changed) of each finest-level cycle in mg-bpp's progress lines."""
    out = []
    for line in lines:
        if "level 0 cycle" in line:
            words = line.replace(",", "").split()
            at, changed = int(words[-6]), int(words[-2])
            out.append((at, changed))
    return out


def test_a_membranes_finest_level_ends_where_its_cycles_have_settled(monkeypatch):
    """On a Z-matrix the finest level ends at its first held cycle at every
    size (150² is above FIRST_HOLD_MAX, where a plate's holds five times),
    and, where at most a third of the nodes are free, at its first cycle
    that flips at most SETTLED components: the finish borders the rest.
    The answers are plain block pivoting's from nothing."""
    from qpcontact.solvers.pivoting import multigrid

    assert 150 ** 2 > multigrid.FIRST_HOLD_MAX
    monkeypatch.setitem(meshes.OBSTACLES, "ripple", HELD_OUT["ripple"])
    for shape, small in (("ripple", True), ("dome", False)):
        lcp = meshes.membrane(150, obstacle=shape)
        lines = []
        sol = qpcontact.solve(lcp, method="mg-bpp", progress=lines.append)
        assert sol.ok, sol.message
        cycles = _finest_cycles(lines)
        n = lcp.n
        assert ((n - cycles[-1][0]) * multigrid.SETTLED_SHARE <= n) == small
        flips = [changed for _, changed in cycles]
        if small:       # the first cycle that flips a few ends it, not a held one
            assert 0 < flips[-1] <= multigrid.SETTLED
            assert all(f > multigrid.SETTLED for f in flips[:-1])
        else:           # the first held cycle ends it, a few flips do not
            assert flips[-1] == 0 and all(f > 0 for f in flips[:-1])
            assert any(0 < f <= multigrid.SETTLED for f in flips[:-1])
        ref = qpcontact.solve(lcp, method="bpp")
        assert ref.ok, ref.message
        np.testing.assert_array_equal(sol.z > 0, ref.z > 0)
        np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-12 * np.abs(ref.z).max())


def test_a_large_membranes_cycles_may_flip_more_before_the_finish_borders_them(monkeypatch):
    """Above SETTLED × SETTLED_SCALE unknowns a membrane's finest level
    ends at its first cycle that flips at most n / SETTLED_SCALE components
    (at most a third free).  The scale brought down to a 120² wedge under a
    heavier load (14 % free): its level ends at its second cycle, which
    flips 6 (more than SETTLED: the rule at 10⁴ would run a third), and the
    answer is still plain block pivoting's from nothing."""
    from qpcontact.solvers.pivoting import multigrid

    monkeypatch.setattr(multigrid, "SETTLED_SCALE", 1000)
    monkeypatch.setitem(meshes.OBSTACLES, "wedge", HELD_OUT["wedge"])
    lcp = meshes.membrane(120, obstacle="wedge", load=-30.0)
    allowed = multigrid.settled_flips(lcp.n)
    assert allowed == 14
    lines = []
    sol = qpcontact.solve(lcp, method="mg-bpp", progress=lines.append)
    assert sol.ok, sol.message
    flips = [changed for _, changed in _finest_cycles(lines)]
    assert multigrid.SETTLED < flips[-1] <= allowed and all(f > allowed for f in flips[:-1]), flips
    ref = qpcontact.solve(lcp, method="bpp")
    assert ref.ok, ref.message
    np.testing.assert_array_equal(sol.z > 0, ref.z > 0)
    np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-12 * np.abs(ref.z).max())


def test_the_first_restriction_cancels_a_stepped_obstacles_layer_not_a_smooth_q():
    """layer_share: the share of q's mass the first restriction cancels.
    By hand: a constant q loses none of it; a dipole ±1 on the two fine
    nodes either side of a coarse node loses half: that node takes ½ − ½,
    its neighbours either side ½ and −½, of a mass ‖R|q|‖₁ of 2.  On the membranes a
    stepped obstacle's dipoles (terraces) keep about half of q's mass at
    every size, above LAYER_SHARE, while the continuous obstacles' and a
    load with a jump cancel only O(h²): under LAYER_SHARE, and about 4 ×
    less at twice the grid (their kinks make it 3 × on the bumps)."""
    from qpcontact.solvers.pivoting.multigrid import LAYER_SHARE, layer_share

    P = meshes.grid_hierarchy(15)[0]
    R = P.T.tocsr()
    assert layer_share(np.ones(225), R) == 0.0
    dipole = np.zeros((15, 15))
    dipole[7, 6], dipole[7, 8] = 1.0, -1.0          # either side of coarse node (3, 3)
    assert layer_share(dipole.ravel(), R) == pytest.approx(0.5, abs=1e-15)

    def share(lcp):
        P = lcp.structure.hierarchy[0]
        return layer_share(lcp.q, P.T.tocsr())

    for N in (127, 255):
        assert share(meshes.membrane(N, obstacle="terraces")) > 0.4
    for shape in ("dome", "ridge", "bumps", "crate"):    # 0.0136-0.0238 at 127², 3.1-3.9 × less at 255²
        coarse, fine = (share(meshes.membrane(N, obstacle=shape)) for N in (127, 255))
        assert fine < coarse / 2.5 and coarse < LAYER_SHARE / 3, (shape, coarse, fine)
    dome = meshes.membrane(127)
    g = np.arange(1, 128) / 128.0                   # the membrane's interior nodes
    x, y = (a.ravel() for a in np.meshgrid(g, g, indexing="ij"))
    jump = LCP(dome.M, dome.M @ meshes.OBSTACLES["dome"](x, y) - np.where(x < 0.5, -8.0, -20.0),
               hierarchy=dome.structure.hierarchy)
    assert share(jump) < LAYER_SHARE / 3       # 0.018: an O(1) jump in q is no layer


def test_a_large_membrane_over_steps_starts_from_one_step_of_the_shift():
    """Above LAYER_MIN unknowns, where q's layer share is above
    LAYER_SHARE, a membrane's coarse levels approximate z − s, s one
    conjugate-gradient step of z_u on the V-cycle, each carrying its finer
    level's restricted residual: on the 150² terraces the finest level then
    starts nearer its set (fewer cycles in all than the plain nested
    start), and the answer is plain block pivoting's from nothing.  A
    smooth obstacle at the same size starts as before."""
    from qpcontact.solvers.pivoting import multigrid

    lcp = meshes.membrane(150, obstacle="terraces")
    assert lcp.n >= multigrid.LAYER_MIN
    cycles = {}
    for shifted in (False, True):
        stats = {}
        multigrid.multilevel_guess(lcp.M, lcp.q, lcp.structure.hierarchy, cycles=500, stats=stats,
                                   settled=multigrid.settled_flips(lcp.n), shifted=shifted,
                                   gap_steps=1)
        assert stats["shifted"] is shifted
        assert stats.get("gap_steps", 1) == 1
        cycles[shifted] = stats["mg_cycles"]
    assert cycles[True] <= cycles[False] - 4, cycles
    sol = qpcontact.solve(lcp, method="mg-bpp")
    assert sol.ok and sol.stats["shifted"] and sol.stats["gap_steps"] == 1
    assert sol.stats["mg_cycles"] == cycles[True]
    ref = qpcontact.solve(lcp, method="bpp")
    assert ref.ok, ref.message
    np.testing.assert_array_equal(sol.z > 0, ref.z > 0)
    np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-12 * np.abs(ref.z).max())
    smooth = qpcontact.solve(meshes.membrane(150, obstacle="crate"), method="mg-bpp")
    assert smooth.ok and not smooth.stats["shifted"]


def test_progress_reports_cycles_and_the_finish():
    lines = []
    qpcontact.solve(meshes.membrane(31), method="mg-bpp", progress=lines.append)
    assert any("level 0 cycle 1" in line for line in lines)
    assert "exact finish" in lines[-1]


def test_mg_bpp_refuses_what_it_cannot_solve():
    with pytest.raises(qpcontact.NotSymmetricError):
        qpcontact.solve(LCP(np.array([[2.0, 1.0], [0.0, 2.0]]), [-1.0, -1.0]), method="mg-bpp")
    with pytest.raises(qpcontact.InvalidOptionError, match="progress"):
        qpcontact.solve(meshes.membrane(9), method="mg-bpp", progress=3)


def test_auto_routes_by_structure():
    """Mesh-like Z-matrices (the membrane) to "mg-bpp" at every size from
    AUTO_MG_MIN, with or without a hierarchy (aggregation suits M-matrices);
    other mesh-like SPD matrices (the plate: off-diagonal entries of both
    signs) to "mg-bpp" at every size when they carry a hierarchy, and
    without one to "bpp" below AUTO_BPP_MAX and
    "ip-bpp" above; banded chains and small sparse meshes to "bpp"; dense
    problems to "bpp" too, tiny ones to the plain order ("energy" first)."""
    from qpcontact.dispatch.routes import AUTO_BPP_MAX, AUTO_MG_MIN

    small = int(np.ceil(np.sqrt(AUTO_MG_MIN)))
    large = 224                    # 50 176 unknowns: above the old cut to ip-bpp
    assert auto_order(meshes.membrane(small))[0] == "mg-bpp"
    assert auto_order(meshes.membrane(large))[0] == "mg-bpp"
    assert auto_order(_without_hierarchy(meshes.membrane(large)))[0] == "mg-bpp"
    assert auto_order(meshes.plate(small))[0] == "mg-bpp"
    assert auto_order(meshes.plate(large))[0] == "mg-bpp"
    below = int(np.sqrt(AUTO_BPP_MAX)) - 1
    above = int(np.ceil(np.sqrt(AUTO_BPP_MAX))) + 1
    assert auto_order(_without_hierarchy(meshes.plate(below)))[0] == "bpp"
    assert auto_order(_without_hierarchy(meshes.plate(above)))[0] == "ip-bpp"
    assert auto_order(meshes.membrane(small - 2))[0] == "bpp"
    n = 3000
    chain = sp.diags([-np.ones(n - 1), 2.5 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1],
                     format="csc")
    order = auto_order(LCP(chain, -np.ones(n)))
    assert order[0] == "bpp" and order.count("bpp") == 1
    assert auto_order(meshes.membrane(8))[0] == "energy"
    assert auto_order(LCP(chain.toarray(), -np.ones(n)))[0] == "bpp"
    assert auto_order(LCP(chain.toarray()[:50, :50], -np.ones(50)))[0] == "energy"
    sol = qpcontact.solve(meshes.membrane(small), method="auto")
    assert sol.ok and sol.method == "mg-bpp"


def test_dependent_coarsest_functions_cost_cycles_not_the_answer():
    """Two coarsest functions the same make the coarsest operator singular
    (to rounding; its Cholesky factor, or the regularized one's, or else
    Gauss–Seidel sweeps): the V-cycle stays finite, and the answer is block
    pivoting's."""
    from qpcontact.solvers.pivoting import _mg_kernels as K
    from qpcontact.solvers.pivoting.multigrid import _Levels

    lcp = meshes.membrane(24)
    Ps = list(lcp.structure.hierarchy)
    last = Ps[-1].tocsc()
    Ps[-1] = sp.hstack([last, last[:, :1]]).tocsr()
    A, _, Rs, patterns = _hierarchy_of(LCP(lcp.M, lcp.q, hierarchy=Ps), "grid")
    assert np.linalg.matrix_rank(patterns[-1].toarray()) < patterns[-1].shape[0]
    levels = _Levels([A] + patterns, Ps, Rs)
    H, S = levels.below(0)
    levels.truncation(0)[:] = True
    assert K.retruncate(H, S, np.ones(A.shape[0], dtype=bool))
    assert np.all(np.isfinite(K.cycle(H, S, np.ones(A.shape[0]), 1)))
    dup = LCP(lcp.M, lcp.q, q_terms=lcp.q_terms, hierarchy=Ps)
    dup.structure.declare_spd()
    sol = qpcontact.solve(dup, method="mg-bpp")
    ref = qpcontact.solve(lcp, method="bpp")
    assert sol.ok
    np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-10 * np.abs(ref.z).max())


def test_a_large_coarsest_level_is_swept_not_factorized():
    """A strongly diagonally dominant chain coarsens once by aggregation
    and stops with nothing strong left: a coarsest level of thousands of
    unknowns, which the cycle smooths by Gauss–Seidel sweeps instead of a
    dense factorization; the answer is block pivoting's."""
    from qpcontact.solvers.pivoting.multigrid import DENSE_COARSEST

    n = 20_000
    chain = sp.diags([-np.ones(n - 1), 2.5 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1],
                     format="csc")
    q = np.random.default_rng(0).standard_normal(n)
    lcp = LCP(chain, q)
    sol = qpcontact.solve(lcp, method="mg-bpp")
    assert sol.ok and sol.stats["mg_levels"] == 2
    assert lcp.structure.aggregated_hierarchy[-1].shape[1] > DENSE_COARSEST
    ref = qpcontact.solve(LCP(chain, q), method="bpp")
    np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-12 * np.abs(ref.z).max())


@pytest.mark.parametrize("N", [15, 16, 31, 40])
def test_grid_hierarchy_interpolates_linear_functions_exactly(N):
    """Each level lives on the odd-numbered nodes of the one above, and its
    prolongation is bilinear interpolation: a linear function sampled on the
    coarse nodes comes back exactly on every fine node whose neighbours are
    coarse nodes (all but the boundary rows, where the zero boundary value
    enters)."""
    P = meshes.grid_hierarchy(N)[0]
    idx = np.arange(N)
    coarse = idx[idx % 2 == 1]
    assert P.shape == (N * N, coarse.size ** 2)
    f = lambda i, j: 0.3 * i - 1.7 * j + 2.0   # noqa: E731
    I, J = np.meshgrid(coarse, coarse, indexing="ij")
    fine = P @ f(I, J).ravel()
    Fi, Fj = np.meshgrid(idx, idx, indexing="ij")
    inner = ((Fi >= 1) & (Fi <= coarse[-1]) & (Fj >= 1) & (Fj <= coarse[-1])).ravel()
    np.testing.assert_allclose(fine[inner], f(Fi, Fj).ravel()[inner], rtol=0, atol=1e-12)
    assert np.all(P.data > 0)   # nonnegative: coarse feasible points are fine feasible points


@pytest.mark.parametrize("N", [50, 100, 101, 316])
def test_coarser_grids_interpolate_in_their_nodes_true_positions(N):
    """Below the first level the grids are not uniform where a count was
    even (the last cell one finer cell wide).  With x the true position in
    fine grid steps (the boundary at 0 and N + 1), every level's
    prolongation takes (N + 1 − x)(N + 1 − y), sampled at the coarse nodes,
    to its values at the fine nodes exactly wherever the left and bottom
    boundary do not enter (right of and above the first coarse node), and
    x y likewise left of and below the last one.  Weights of ½ next to the
    narrow cell, as on a uniform grid, fail at all four N."""
    x = np.arange(1.0, N + 1.0)
    for P in meshes.grid_hierarchy(N):
        xc = x[1::2]
        for f, inside in ((lambda t: N + 1.0 - t, x >= xc[0]), (lambda t: t, x <= xc[-1])):
            got = (P @ np.outer(f(xc), f(xc)).ravel()).reshape(x.size, x.size)
            want = np.outer(f(x), f(x))
            mask = np.outer(inside, inside)
            np.testing.assert_allclose(got[mask], want[mask], rtol=0, atol=1e-12 * N * N)
        x = xc


@pytest.mark.slow
@pytest.mark.parametrize("hierarchy", ["grid", "aggregation"])
def test_a_hundred_thousand_unknowns_equal_ip_bpp(hierarchy):
    """n = 99 856 (the membrane row of docs/pivoting.md's mesh-scale table): the same certified answer as
    the interior-point route (its own pivoting and factorizations), with at
    most one exchange after the multilevel search."""
    lcp = meshes.membrane(316, obstacle="bumps")
    # no time limit: the answers are compared, not timed (the methods keep
    # solve's default 60 s, which a loaded machine's run of the Python cycle
    # went past: 5-17 s alone, over 60 s at a load of 6)
    ref = qpcontact.solve(lcp, method="ip-bpp", time_limit=None)
    assert ref.ok, ref.message
    problem = lcp if hierarchy == "grid" else _without_hierarchy(lcp)
    sol = qpcontact.solve(problem, method="mg-bpp", time_limit=None)
    assert sol.ok, sol.message
    assert sol.stats["factorizations"] <= 2
    np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-12 * ref.z.max())
    np.testing.assert_array_equal(sol.z == 0, ref.z == 0)


def test_obstacle_shapes_are_named_and_checked():
    for shape in meshes.OBSTACLES:
        lcp = meshes.membrane(20, obstacle=shape)
        z = qpcontact.solve(lcp, method="mg-bpp").z
        assert 0 < np.count_nonzero(z == 0) < z.size, shape   # some contact, some free
    with pytest.raises(InvalidProblemError, match="unknown obstacle 'volcano'.*dome"):
        meshes.plate(10, obstacle="volcano")


def test_a_warm_start_whose_every_unknown_leaves_the_basis():
    """q > 0: z = 0 by hand.  Started from two unknowns in the basis, block
    pivoting's next basis is empty, which the bordered finish (a few
    components from the factorized basis) once met with a reduction over
    nothing."""
    n = 400
    A = sp.random(n, n, density=0.02, random_state=1)
    M = (A @ A.T + 5.0 * sp.identity(n)).tocsc()
    q = np.abs(np.random.default_rng(0).normal(size=n)) + 0.1
    res = qpcontact.solve(LCP(M, q), method="bpp", initial_active=[0, 1])
    assert res.status == "solved" and np.all(res.z == 0.0)


def test_a_small_plate_is_not_restarted():
    """Below 200 unknowns nothing is bordered, so a first basis with a bound
    broken is block pivoting's to mend, not a reason to resume the cycles."""
    res = qpcontact.solve(meshes.plate(13, obstacle="terraces", rigidity=1.0), method="mg-bpp")
    assert res.ok and res.stats["restarts"] == 0
