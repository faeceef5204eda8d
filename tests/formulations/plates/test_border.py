"""A raft's step solved on a nearby step's LDLᵀ with a border
(formulations/plates/border.py): against SciPy's sparse LU of the new step's
own system, on a raft with soil and a rigid floor where floor nodes are
released and caught and soil springs change; refused where the border is
too large or leaves the raft free; and a floor raft's Newton answer, whose
steps run on borders, against the same raft with every step factorised and
against statics."""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spl

import formulations.plates.border as border
from formulations.plates import Raft
from formulations.plates.examples import windward_raft
from formulations.plates.newton import SupportSystem


def _mixed_system():
    """Soil under most of a 6 m x 4 m raft, a rigid floor under a strip."""
    raft = Raft(6.0, 4.0, thickness=0.3, E=30e6, nu=0.2, cells=(12, 8))
    raft.add_soil(3e4)
    raft.add_rigid_floor(zone=(0.0, 0.0, 2.5, 4.0))
    raft.add_self_weight(25.0)
    b = raft.build()
    return SupportSystem(b["qp"], b["mesh"].nodes)


def _random_states(system, seed):
    """A generator seeded ``seed`` and the states it draws: 70 % of the soil
    pressing, 60 % of the floor held."""
    rng = np.random.default_rng(seed)
    return (rng, rng.random(system.soil_w.size) < 0.7,
            rng.random(system.floor_w.size) < 0.6)


def _reference(system, soil_pressing, floor_held, rhs):
    """SciPy's LU of (K + the pressing springs) on the dofs not held."""
    springs = np.zeros(system.dofs.size)
    springs[system.soil_w] = np.where(soil_pressing, system.k, 0.0)
    keep = np.ones(system.dofs.size, bool)
    keep[system.floor_w[floor_held]] = False
    idx = np.flatnonzero(keep)
    A = (system.K + sp.diags(springs)).tocsc()[idx][:, idx]
    u = np.zeros(system.dofs.size)
    u[idx] = spl.spsolve(A, rhs[idx])
    return u


@pytest.mark.parametrize("released, caught, changed", [(6, 5, 7), (1, 1, 1)])
def test_a_bordered_step_solves_the_new_steps_own_system(released, caught, changed):
    """18 border columns go through the factor's paths, 3 through a solve
    each (FEW_COLUMNS)."""
    system = _mixed_system()
    rng, soil, floor = _random_states(system, 7)
    system.factorize(soil, floor)
    block = system.floor_block
    assert block is not None
    # release some held floor nodes, catch some free ones, change some springs
    released = rng.choice(np.flatnonzero(floor), released, replace=False)
    caught = rng.choice(np.flatnonzero(~floor), caught, replace=False)
    changed = rng.choice(system.soil_w.size, changed, replace=False)
    floor2, soil2 = floor.copy(), soil.copy()
    floor2[released], floor2[caught] = False, True
    soil2[changed] = ~soil2[changed]
    rhs = rng.standard_normal(system.dofs.size)
    u = system.factorize(soil2, floor2)(rhs)
    assert system.floor_block is block              # no factorisation: the border solved it
    ref = _reference(system, soil2, floor2, rhs)
    assert np.max(np.abs(u - ref)) <= 1e-12 * np.max(np.abs(ref))
    assert np.all(u[system.floor_w[floor2]] == 0.0)       # the held w are exactly zero


def test_a_border_too_large_or_leaving_the_raft_free_is_factorised(monkeypatch):
    system = _mixed_system()
    soil = np.ones(system.soil_w.size, bool)
    floor = np.ones(system.floor_w.size, bool)
    system.factorize(soil, floor)
    block = system.floor_block
    few = floor.copy()
    few[:3] = False
    monkeypatch.setattr(border, "BORDER_SHARE", 0.0)
    assert block.near(*_keep_springs(system, soil, few)) is None
    # every support gone: the raft is free to lift, the border's complement singular
    monkeypatch.setattr(border, "BORDER_SHARE", 1e9)
    nothing = np.zeros(system.floor_w.size, bool)
    assert block.near(*_keep_springs(system, np.zeros_like(soil), nothing)) is None
    assert block.near(*_keep_springs(system, soil, few)) is not None


def _keep_springs(system, soil_pressing, floor_held):
    springs = np.zeros(system.dofs.size)
    springs[system.soil_w] = np.where(soil_pressing, system.k, 0.0)
    keep = np.ones(system.dofs.size, bool)
    keep[system.floor_w[floor_held]] = False
    return keep, springs


@pytest.mark.parametrize("supernodal", [False, True])
def test_a_floor_rafts_answer_on_borders_is_the_answer_factorised_every_step(supernodal,
                                                                              monkeypatch):
    """On qdldl's factors and on SuperLU's (newton.SUPERNODAL_DOFS)."""
    import formulations.plates.newton as newton_module

    monkeypatch.setattr(newton_module, "SUPERNODAL_DOFS", 0 if supernodal else 10 ** 9)
    bordered_steps = []
    near = border.FactoredBlock.near

    def counted(self, keep, springs):
        solve = near(self, keep, springs)
        bordered_steps.append(solve is not None and solve != self.solve)
        return solve

    monkeypatch.setattr(border.FactoredBlock, "near", counted)
    raft = windward_raft(40, floor=True)
    bordered = raft.solve()
    assert sum(bordered_steps) >= 3                 # the borders ran, at both grids
    monkeypatch.setattr(border, "BORDER_SHARE", 0.0)
    factorised = windward_raft(40, floor=True).solve()
    for r in (bordered, factorised):
        assert r.ok and r.method == "active-set", r.message
        # statics: the floor carries the net load, and nothing pulls on it
        total = r.loads[0::3].sum()
        assert abs(r.support_force.sum() - total) <= 1e-9 * np.abs(r.loads[0::3]).sum()
        assert r.support_force.min() >= -1e-9 * r.support_force.max()
    assert np.array_equal(bordered.lifted, factorised.lifted)
    assert 0 < bordered.lifted.sum() < bordered.lifted.size
    scale = np.max(np.abs(factorised.w))
    assert np.max(np.abs(bordered.w - factorised.w)) <= 1e-9 * scale


@pytest.mark.parametrize("share", [0.0, 1e9])
def test_the_floor_raft_of_the_raft_tests_agrees_with_the_pinned_qp_either_way(share,
                                                                               monkeypatch):
    """Every floor step bordered (share huge) or none (0): the same answer as
    block pivoting on the pinned QP."""
    monkeypatch.setattr(border, "BORDER_SHARE", share)
    raft = Raft(4.0, 4.0, thickness=0.3, E=30e6, nu=0.2, cells=(12, 12))
    raft.add_rigid_floor()
    raft.add_self_weight(25.0)
    raft.add_point_load(0.0, 0.0, -30.0)
    raft.add_point_load(2.5, 2.5, 50.0)
    newton, pinned = raft.solve(), raft.solve(method="bpp")
    assert newton.ok and pinned.ok and newton.method == "active-set", newton.message
    assert np.array_equal(newton.lifted, pinned.lifted)
    assert np.max(np.abs(newton.w - pinned.w)) <= 1e-9 * np.max(np.abs(pinned.w))


def _splu_block(system, keep, springs):
    """The block's LDLᵀ by SuperLU (symmetric mode, diagonal pivots, its
    rows in reverse Cuthill–McKee order given, none of its own), as the
    border reads a factor: L = lu.L (its unit diagonal stored), d =
    diag(lu.U), p = that order, the tree read off L."""
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    idx = np.flatnonzero(keep)
    A = (system.K + sp.diags(springs)).tocsr()[idx][:, idx]
    order = idx[reverse_cuthill_mckee(A, symmetric_mode=True)]
    lu = spl.splu((system.K + sp.diags(springs)).tocsc()[order][:, order], permc_spec="NATURAL",
                  diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    assert np.array_equal(lu.perm_r, np.arange(order.size))

    def solve(rhs):
        u = np.zeros(keep.size)
        u[order] = lu.solve(rhs[order])
        return u

    def factors():
        return lu.L, lu.U.diagonal(), order, None

    return border.FactoredBlock(system.K, keep, springs, solve, factors)


@pytest.mark.parametrize("released, caught, changed", [(6, 5, 7), (1, 1, 1)])
def test_a_border_on_superlus_factor_solves_the_new_steps_own_system(released, caught,
                                                                       changed):
    """The border reads any LDLᵀ given as (L, d, order): SuperLU's here."""
    system = _mixed_system()
    rng, soil, floor = _random_states(system, 11)
    block = _splu_block(system, *_keep_springs(system, soil, floor))
    floor2, soil2 = floor.copy(), soil.copy()
    floor2[rng.choice(np.flatnonzero(floor), released, replace=False)] = False
    floor2[rng.choice(np.flatnonzero(~floor), caught, replace=False)] = True
    flip = rng.choice(system.soil_w.size, changed, replace=False)
    soil2[flip] = ~soil2[flip]
    rhs = rng.standard_normal(system.dofs.size)
    u = block.near(*_keep_springs(system, soil2, floor2))(rhs)
    ref = _reference(system, soil2, floor2, rhs)
    assert np.max(np.abs(u - ref)) <= 1e-12 * np.max(np.abs(ref))


@pytest.mark.parametrize("tree_of", ["L", "A"])
def test_a_factor_entry_that_cancels_to_zero_keeps_the_border_exact(tree_of, monkeypatch):
    """SciPy's SuperLU.L leaves out an entry of L that cancelled to exactly
    zero: here L₃₂ = 1 − 1·1 = 0, so column 2 stores no row and the least
    stored row of each column made 2 a root with column 1's row 3 off its
    path — the forward solve wrote row 3's update into another row (a
    Schur complement of 5 for A⁻¹₁₁ = 2.5, the bordered solve far off).
    The elimination tree read off L's rows and off the factorised matrix
    (what a step's Factorisation gives) both keep it exact."""
    import scipy.sparse.linalg as spla

    from formulations.plates.newton import Factorisation

    A = sp.csc_matrix(np.array([[1.0, 1.0, 1.0], [1.0, 2.0, 1.0], [1.0, 1.0, 3.0]]))
    lu = spla.splu(A, permc_spec="NATURAL", diag_pivot_thresh=0.0,
                   options={"SymmetricMode": True})
    factorisation = Factorisation(np.arange(3), lu=lu, matrix=A if tree_of == "A" else None)
    L, _, _, tree = factorisation.factors()
    assert sp.tril(L, -1).nnz == 2                          # L₃₂ left out
    assert (tree is None) == (tree_of == "L")
    if tree is not None:
        assert list(tree) == [1, 2, -1]
    monkeypatch.setattr(border, "FEW_COLUMNS", 0)           # through the factor's paths
    keep = np.ones(3, bool)
    block = border.FactoredBlock(A, keep, np.zeros(3), factorisation, factorisation.factors)
    springs = np.array([5.0, 0.0, 0.0])                     # a spring changed at dof 1
    rhs = np.array([1.0, 2.0, 3.0])
    u = block.near(keep, springs)(rhs)
    ref = np.linalg.solve(A.toarray() + np.diag(springs), rhs)
    assert np.max(np.abs(u - ref)) <= 1e-12 * np.max(np.abs(ref))


@pytest.mark.parametrize("entries", [border.BORDER_ENTRIES, "tight"])
def test_a_border_solves_only_the_columns_the_last_border_on_its_factor_had_not(entries,
                                                                                 monkeypatch):
    """Two steps on one factor: the first releases five floor nodes and
    changes three springs, the second holds those five again and releases
    three others, the springs as in the first.  The second forward-solves
    only its three new columns (counted), and both solve their own systems
    (SciPy's LU); with BORDER_ENTRIES too small for the columns kept and the
    new ones together, the kept ones are dropped and the second border
    solved alone (its six columns), as exactly."""
    import formulations.plates._border_kernels as kernels

    system = _mixed_system()
    rng, soil, floor = _random_states(system, 5)
    system.factorize(soil, floor)
    block = system.floor_block
    solved = []
    forward = kernels.forward_block

    def counted(Lp, Li, Lx, rows, X):
        solved.append(X.shape[1])
        forward(Lp, Li, Lx, rows, X)

    monkeypatch.setattr(kernels, "forward_block", counted)
    released = rng.choice(np.flatnonzero(floor), 8, replace=False)
    soil1 = soil.copy()
    soil1[rng.choice(np.flatnonzero(soil), 3, replace=False)] = False
    floor1, floor2 = floor.copy(), floor.copy()
    floor1[released[:5]] = False
    floor2[released[5:]] = False
    rhs = rng.standard_normal(system.dofs.size)
    u1 = system.factorize(soil1, floor1)(rhs)
    assert solved == [8]
    if entries == "tight":
        monkeypatch.setattr(border, "BORDER_ENTRIES", block.rows.size * 11 - 1)
    u2 = system.factorize(soil1, floor2)(rhs)
    assert system.floor_block is block              # a border, not a factorisation
    for u, f in ((u1, floor1), (u2, floor2)):
        ref = _reference(system, soil1, f, rhs)
        assert np.max(np.abs(u - ref)) <= 1e-12 * np.max(np.abs(ref))
    assert solved[1:] == ([6] if entries == "tight" else [3])
    assert block.W.shape[1] == (6 if entries == "tight" else 11)
