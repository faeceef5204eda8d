"""The multilevel setup a matrix carries from one load to the next: "mg-bpp"
keeps what it builds of M and its hierarchy alone (Galerkin products, packed
levels, the coarsest problem) on M's structure, and an LCP with the same
structure and another q (a load combination) starts from it.  The answers
are those of a fresh solve bit for bit and block pivoting's to rounding;
a setup that does not fit M as it is now, or that another solve holds, is
not used."""

from __future__ import annotations

import numpy as np
import pytest

import qpcontact
from formulations import meshes
from qpcontact import LCP
from qpcontact.solvers.pivoting.multigrid import MultilevelSetup


def _on(lcp, other):
    """``other``'s load on ``lcp``'s matrix and structure."""
    return LCP.with_structure(lcp.structure, other.q, other.q_terms)


#: three loads per family: contact sets that differ
LOADS = {"membrane": (-8.0, -14.0, -4.0), "plate": (-1000.0, -1600.0, -500.0)}


@pytest.mark.parametrize("family,N,kw", [("membrane", 40, {"obstacle": "crate"}),
                                         ("membrane", 33, {"obstacle": "terraces"}),
                                         ("plate", 30, {"obstacle": "dome", "rigidity": 0.05}),
                                         ("plate", 28, {"obstacle": "bumps", "rigidity": 1.0})])
def test_the_loads_after_the_first_start_from_its_setup_with_the_same_answers(family, N, kw):
    """Three loads on one structure (the contact sets differ): the second
    and third keep the first's setup; every answer, and a repeat of the
    first load after them, equals a fresh solve bit for bit — cycles,
    exchanges and z — so each load found the coarse operators as built,
    not as the previous load's truncation left them — and block
    pivoting's from nothing (another route) to rounding."""
    make = getattr(meshes, family)
    first = make(N, load=LOADS[family][0], **kw)
    sets = []
    for k, load in enumerate(LOADS[family] + LOADS[family][:1]):
        fresh_lcp = make(N, load=load, **kw)
        problem = first if k == 0 else _on(first, fresh_lcp)
        sol = qpcontact.solve(problem, method="mg-bpp", accuracy="high")
        assert sol.ok, sol.message
        assert sol.stats["setup_kept"] is (k > 0)
        fresh = qpcontact.solve(fresh_lcp, method="mg-bpp", accuracy="high")
        assert fresh.stats["setup_kept"] is False
        np.testing.assert_array_equal(sol.z, fresh.z)
        for key in ("mg_cycles", "mg_rebuilds", "iterations", "factorizations",
                    "bordered_solves"):
            assert sol.stats[key] == fresh.stats[key], key
        ref = qpcontact.solve(LCP(fresh_lcp.M, fresh_lcp.q, q_terms=fresh_lcp.q_terms),
                              method="bpp")
        assert ref.ok
        np.testing.assert_array_equal(sol.z > 0, ref.z > 0)
        np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-11 * np.abs(ref.z).max())
        sets.append(sol.z > 0)
    assert not np.array_equal(sets[0], sets[1]) and not np.array_equal(sets[0], sets[2])


def test_a_resumed_search_on_a_kept_setup_is_a_fresh_solves():
    """The 140 x 140 plate under the terraces resumes its cycles once from
    the finish's basic solution (the restart reuses the setup within the
    solve); solved again on its structure, the same restart, the same z."""
    lcp = meshes.plate(140, obstacle="terraces", rigidity=1.0)
    first = qpcontact.solve(lcp, method="mg-bpp")
    again = qpcontact.solve(_on(lcp, lcp), method="mg-bpp")
    assert first.ok and again.ok and again.stats["setup_kept"]
    assert first.stats["restarts"] == again.stats["restarts"] == 1
    np.testing.assert_array_equal(first.z, again.z)


def test_a_setup_fits_only_its_own_matrix_hierarchy_and_cycles():
    lcp = meshes.membrane(30)
    rows = lcp.M.T.tocsr()
    P = lcp.structure.hierarchy
    setup = MultilevelSetup(rows, P, 1)
    assert setup.fits(rows, P, 1)
    assert setup.fits(lcp.M.tocsr(), P, 1)         # the same entries, another copy
    changed = rows.copy()
    changed.data[len(changed.data) // 2] *= 1.0 + 2.0 ** -52
    assert not setup.fits(changed, P, 1)
    moved = rows.copy()
    moved.indices = moved.indices.copy()
    row = 400
    a, b = moved.indptr[row], moved.indptr[row + 1]
    moved.data[a:b] = moved.data[a:b][::-1].copy()
    moved.indices[a:b] = moved.indices[a:b][::-1].copy()  # the same row, stored in another order
    assert not setup.fits(moved, P, 1)
    assert not setup.fits(rows, list(P), 1)          # an equal hierarchy, another object
    assert not setup.fits(rows, P, 2)                # W-cycles
    assert not setup.fits(meshes.membrane(31).M.T.tocsr(), meshes.membrane(31).structure.hierarchy, 1)


def test_a_setup_sees_its_prolongations_changed_in_place():
    """A prolongation shares the arrays its user passed: values rewritten
    there (the same hierarchy object) make the setup not fit, as M's do."""
    lcp = meshes.membrane(30)
    rows = lcp.M.T.tocsr()
    P = lcp.structure.hierarchy
    setup = MultilevelSetup(rows, P, 1)
    assert setup.fits(rows, P, 1)
    P[0].data[::3] *= 0.25
    assert not setup.fits(rows, P, 1)


def test_a_kept_answer_does_not_keep_its_problems_setup():
    """An answer outlives its problem without holding the structure (and
    the multilevel setup on it, several times M): the certificate's lazy
    forward error refers to the structure weakly, and once it is gone
    estimates by LU, with the same figure."""
    import gc
    import weakref

    lcp = meshes.membrane(40, obstacle="crate")   # > 400 active rows: the lazy estimate
    sol = qpcontact.solve(lcp, method="mg-bpp", accuracy="high")
    twin = qpcontact.solve(LCP(lcp.M, lcp.q, q_terms=lcp.q_terms), method="mg-bpp",
                           accuracy="high")
    assert sol.ok and lcp.structure.multilevel_setup is not None
    setup = weakref.ref(lcp.structure.multilevel_setup)
    del lcp
    gc.collect()
    assert setup() is None
    assert sol.forward_error == pytest.approx(twin.forward_error, rel=1e-6)


def test_a_setup_without_coarse_levels_sees_its_matrix_changed_in_place():
    """With no coarse level (a small problem that aggregation leaves
    whole) the setup keeps its own copy of M: the values rewritten in the
    very arrays it was built from do not fit."""
    lcp = meshes.membrane(15)
    rows = lcp.M.T.tocsr()
    setup = MultilevelSetup(rows, (), 1)
    assert setup.fits(rows, (), 1)
    rows.data *= 2.0
    assert not setup.fits(rows, (), 1)


def test_a_setup_that_does_not_fit_the_matrix_is_rebuilt():
    """A structure carrying another matrix's setup (built for a membrane
    of twice the tension: the same pattern and hierarchy, other values)
    does not use it, and its answer is block pivoting's."""
    lcp = meshes.membrane(40, obstacle="ridge")
    stiffer = meshes.membrane(40, obstacle="ridge", tension=2.0)
    lcp.structure.multilevel_setup = MultilevelSetup(stiffer.M.T.tocsr(),
                                                     lcp.structure.hierarchy, 1)
    sol = qpcontact.solve(lcp, method="mg-bpp")
    assert sol.ok and sol.stats["setup_kept"] is False
    ref = qpcontact.solve(LCP(lcp.M, lcp.q, q_terms=lcp.q_terms), method="bpp")
    np.testing.assert_allclose(sol.z, ref.z, rtol=0, atol=1e-12 * np.abs(ref.z).max())
    assert qpcontact.solve(_on(lcp, lcp), method="mg-bpp").stats["setup_kept"]


def test_a_setup_held_by_another_solve_is_not_shared():
    """While one solve holds the kept setup (another thread's), a solve on
    the same structure builds its own."""
    lcp = meshes.membrane(30, obstacle="bumps")
    first = qpcontact.solve(lcp, method="mg-bpp")
    kept = lcp.structure.multilevel_setup
    with kept.lock:
        other = qpcontact.solve(_on(lcp, lcp), method="mg-bpp")
    assert other.ok and other.stats["setup_kept"] is False
    np.testing.assert_array_equal(other.z, first.z)
    assert lcp.structure.multilevel_setup is kept     # still the one kept
    assert not kept.lock.locked()
    again = qpcontact.solve(_on(lcp, lcp), method="mg-bpp")
    assert again.stats["setup_kept"] is True
    np.testing.assert_array_equal(again.z, first.z)


def test_loads_solved_in_threads_share_the_kept_setup():
    """Loads on one M solved by two threads, the setup held for the cycles
    only (the exact finish reads M alone) and released between a search and
    its resumption: every answer is a fresh solve's bit for bit, whichever
    solves kept it (how many depends on the threads' timing: 31 of 32 here,
    4 of 32 when a held setup was replaced and held through the finish)."""
    from concurrent.futures import ThreadPoolExecutor

    lcp = meshes.membrane(60, obstacle="crate")
    qpcontact.solve(lcp, method="mg-bpp")
    loads = [meshes.membrane(60, obstacle="crate", load=-8.0 - k) for k in range(32)]
    with ThreadPoolExecutor(2) as pool:
        sols = list(pool.map(lambda o: qpcontact.solve(_on(lcp, o), method="mg-bpp"), loads))
    for sol, other in zip(sols, loads):
        fresh = qpcontact.solve(other, method="mg-bpp")
        np.testing.assert_array_equal(sol.z, fresh.z)
    assert any(s.stats["setup_kept"] for s in sols)
