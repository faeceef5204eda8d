"""Rafts on tensionless soil and rigid floors answered by Newton's method
on the energy (formulations/plates/newton.py, "auto"), against the pinned
QP solved by block pivoting on its condensed LCP (method="bpp": another
formulation and another algorithm) on rafts of other shapes, loads, soil
zones, floors, openings, edge beams and bilateral supports; and the
fallback where Newton does not end."""

import numpy as np
import pytest

from formulations.plates import Raft
from formulations.plates.examples import COMBINATIONS, raft_example, windward_raft


def _corner_raft():
    """A 6 m x 4 m raft, a heavy column near one corner, a light one at the
    far side: most of the raft lifts."""
    raft = Raft(6.0, 4.0, thickness=0.4, E=30e6, nu=0.2, cells=(18, 12))
    raft.add_soil(5e4)
    raft.add_self_weight(25.0)
    raft.add_point_load(0.6, 0.6, 3000.0)
    raft.add_point_load(5.4, 2.4, 500.0)
    return raft


def _zoned_raft():
    """Soft and stiff soil zones, an edge beam along y = 0 and a line load
    pulling up along the far edge: the lift-off line crosses the zones."""
    raft = Raft(8.0, 5.0, thickness=0.35, E=30e6, nu=0.2, cells=(16, 10))
    raft.add_soil(1e4)
    raft.add_soil(8e4, zone=(0.0, 0.0, 3.0, 5.0))
    raft.add_self_weight(25.0)
    raft.add_edge_beam(0.0, 0.0, 8.0, 0.0, EI=2e5)
    raft.add_area_load(10.0)
    raft.add_line_load(8.0, 0.0, 8.0, 5.0, -60.0)
    raft.add_point_load(2.0, 2.5, 800.0)
    return raft


def _held_raft():
    """A slab held bilaterally along x = 0 (a wall) and on soil elsewhere,
    a point load near the free edge lifting the corners beside the wall."""
    raft = Raft(5.0, 5.0, thickness=0.25, E=30e6, nu=0.2, cells=(10, 10))
    raft.add_soil(2e4)
    raft.add_support(lambda x, y: np.isclose(x, 0.0), fix=("w",))
    raft.add_point_load(4.5, 2.5, 400.0)
    return raft


def _floor_raft():
    """A slab on a rigid floor, a corner pulled up: the corner lifts."""
    raft = Raft(4.0, 4.0, thickness=0.3, E=30e6, nu=0.2, cells=(12, 12))
    raft.add_rigid_floor()
    raft.add_self_weight(25.0)
    raft.add_point_load(0.0, 0.0, -30.0)
    raft.add_point_load(2.5, 2.5, 50.0)
    return raft


def _mixed_raft():
    """Soil under most of the raft, a rigid floor (an old footing) under a
    strip, a column off the strip and wind pulling the far edge up."""
    raft = Raft(6.0, 4.0, thickness=0.3, E=30e6, nu=0.2, cells=(12, 8))
    raft.add_soil(3e4)
    raft.add_rigid_floor(zone=(0.0, 0.0, 1.5, 4.0))
    raft.add_self_weight(25.0)
    raft.add_point_load(3.0, 2.0, 600.0)
    raft.add_line_load(6.0, 0.0, 6.0, 4.0, -40.0)
    return raft


@pytest.fixture(params=["qdldl", "superlu"])
def factorisation(request, monkeypatch):
    """Both of Newton's factorisations (formulations/plates/newton.py): qdldl
    under its own AMD on small rafts, SuperLU in nested-dissection order
    from SUPERNODAL_DOFS on — here each on every raft."""
    import formulations.plates.newton as newton_module

    monkeypatch.setattr(newton_module, "SUPERNODAL_DOFS",
                        10 ** 9 if request.param == "qdldl" else 0)
    return request.param


def _agree(newton, pinned):
    assert newton.ok and pinned.ok, (newton.message, pinned.message)
    assert newton.method == "active-set" and pinned.method != "active-set"
    assert np.array_equal(newton.lifted, pinned.lifted)
    scale = np.max(np.abs(pinned.w))
    assert np.max(np.abs(newton.w - pinned.w)) <= 1e-9 * scale


@pytest.mark.parametrize("combination", list(COMBINATIONS))
def test_the_example_raft_agrees_with_the_pinned_qp(combination, factorisation):
    raft = raft_example(cells=(16, 12))
    combo = COMBINATIONS[combination]
    _agree(raft.solve(combo), raft.solve(combo, method="bpp"))


@pytest.mark.parametrize("make", [_corner_raft, _zoned_raft, _held_raft, _floor_raft,
                                  _mixed_raft])
def test_other_rafts_agree_with_the_pinned_qp(make, factorisation):
    raft = make()
    newton, pinned = raft.solve(), raft.solve(method="bpp")
    _agree(newton, pinned)
    assert 0 < newton.lifted.sum() < newton.lifted.size     # lift-off is in the problem


def test_combinations_share_one_analysis_and_stay_independent():
    """The LDLᵀ's ordering is made once per raft; each combination still
    starts from its own bilateral answer (the second equals a fresh raft's)."""
    raft = raft_example(cells=(16, 12))
    first = raft.solve(COMBINATIONS["1.0D+1.5W"])
    system = raft.build()["qp"].newton
    second = raft.solve(COMBINATIONS["1.0D-1.5W"])
    assert raft.build()["qp"].newton is system
    fresh = raft_example(cells=(16, 12)).solve(COMBINATIONS["1.0D-1.5W"])
    assert first.ok and second.ok
    assert np.array_equal(second.w, fresh.w)


def test_where_newton_does_not_end_the_pinned_qp_answers(monkeypatch):
    import formulations.plates.newton as newton_module

    raft = _corner_raft()
    newton = raft.solve()
    monkeypatch.setattr(newton_module, "MAX_STEPS", 1)   # the bilateral step alone
    fallback = raft.solve()
    assert fallback.ok and fallback.method != "active-set", fallback.message
    assert np.array_equal(fallback.lifted, newton.lifted)
    assert np.max(np.abs(fallback.w - newton.w)) <= 1e-9 * np.max(np.abs(newton.w))


def test_a_time_limit_spent_in_newton_is_reported_not_answered():
    r = _corner_raft().solve(time_limit=1e-9)
    assert not r.ok and r.status == "time_limit", r.message
    assert "time limit" in r.message


def test_compiling_inside_a_rafts_time_limit_is_left_out_of_it(monkeypatch):
    """Newton's deadline was a raw perf_counter value, so numba compiling a
    kernel inside it (a cold cache's) ate a raft's time limit, where every
    other time limit leaves compiling out (grace's docstring).  1.5 s of
    compiling — booked as core.compiled books numba's compile events — in
    the first step's guess, under a 1 s limit: Newton still answers, in the
    ~0.01 s it takes."""
    import time

    from qpcontact.core.deadline import exclude_one_time

    def compiling_guess(self, combination, deadline=None):
        time.sleep(1.5)
        exclude_one_time(1.5, 0.0)
        return None

    raft = _corner_raft()
    assert raft.solve().method == "active-set"        # built, its kernels loaded
    monkeypatch.setattr(Raft, "_nested_start", compiling_guess)
    r = raft.solve(time_limit=1.0)
    assert r.ok and r.method == "active-set", r.message


@pytest.mark.parametrize("make", [lambda: windward_raft(40), lambda: windward_raft(40, floor=True),
                                  lambda: raft_example(cells=(36, 32))])
def test_a_start_from_the_coarser_grid_gives_the_same_answer(make, monkeypatch, factorisation):
    """Nested iteration: the twin on half the cells only guesses the first
    states; the answer is the one Newton finds from every node pressing."""
    import formulations.plates.model as model

    nested = make().solve()
    assert nested.ok and "coarser grid" in nested.message, nested.message
    monkeypatch.setattr(model, "NESTED_CELLS", 10 ** 6)
    plain = make().solve()
    assert plain.ok and "coarser grid" not in plain.message, plain.message
    assert np.array_equal(nested.lifted, plain.lifted)
    assert np.max(np.abs(nested.w - plain.w)) <= 1e-9 * np.max(np.abs(plain.w))


def test_no_coarser_grid_for_supports_given_as_nodes():
    raft = windward_raft(32)
    raft.add_support([0], fix=("w",))          # a node number names no node of another grid
    r = raft.solve()
    assert r.ok and "coarser grid" not in r.message, r.message
    assert raft.build()["twin"] is None
