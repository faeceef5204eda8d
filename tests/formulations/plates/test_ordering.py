"""The raft's nested-dissection order (formulations/plates/ordering.py) and
the LDLᵀ Newton's steps make in it (formulations/plates/newton.py): the
order is a permutation; the answer of a step equals SciPy's spsolve of
the same system (another factorisation in another order); the halves of a
cut do not fill each other and the order's fill is far below a banded
order's (counted on dense Cholesky factors, NumPy's)."""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from formulations.plates import Raft
from formulations.plates.newton import SupportSystem
from formulations.plates.ordering import dof_order, nested_dissection


def _opening_raft():
    """A raft with an opening, a wall holding w along x = 0 and a rigid
    floor under a strip: dofs missing, nodes missing, floor dofs held."""
    raft = Raft(6.0, 4.0, thickness=0.3, E=30e6, nu=0.2, cells=(15, 10),
                openings=[(2.0, 1.5, 3.0, 2.5)])
    raft.add_soil(3e4)
    raft.add_rigid_floor(zone=(4.5, 0.0, 6.0, 4.0))
    raft.add_support(lambda x, y: np.isclose(x, 0.0), fix=("w",))
    raft.add_self_weight(25.0)
    raft.add_point_load(3.0, 1.0, 300.0)
    return raft


def _grid_graph(nx, ny):
    """The node adjacency of an nx x ny grid of quadrilaterals (corners of
    one cell are neighbours) and its node coordinates."""
    ids = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1)
    quads = np.stack([ids[:-1, :-1], ids[:-1, 1:], ids[1:, 1:], ids[1:, :-1]], -1).reshape(-1, 4)
    rows = np.repeat(quads, 4, axis=1).ravel()
    cols = np.tile(quads, (1, 4)).ravel()
    n = ids.size
    graph = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n))
    x, y = np.meshgrid(np.arange(nx + 1), np.arange(ny + 1))
    return graph, np.column_stack([x.ravel(), y.ravel()]).astype(float)


def _dense_fill(A, order):
    """Nonzeros of the Cholesky factor of A (SPD) in ``order``, counted on
    NumPy's dense factor (entries below 1e-14 of their column's pivot are
    cancellation, not fill)."""
    L = np.linalg.cholesky(A[np.ix_(order, order)])
    return int(np.count_nonzero(np.abs(L) > 1e-14 * np.abs(np.diag(L))[None, :]))


def test_the_order_is_a_permutation(monkeypatch):
    import formulations.plates.newton as newton_module

    for nx, ny in [(1, 1), (7, 3), (40, 25)]:
        graph, points = _grid_graph(nx, ny)
        order = nested_dissection(points, graph)
        assert np.array_equal(np.sort(order), np.arange(points.shape[0]))
    raft = _opening_raft()
    b = raft.build()
    system = SupportSystem(b["qp"], b["mesh"].nodes)
    assert not system.supernodal        # too small: qdldl orders it itself
    monkeypatch.setattr(newton_module, "SUPERNODAL_DOFS", 0)
    system = SupportSystem(b["qp"], b["mesh"].nodes)
    assert system.supernodal
    assert np.array_equal(np.sort(system.order), np.arange(system.dofs.size))
    nodes_in_order = system.dofs[system.order] // 3      # each node's dofs together
    assert np.unique(nodes_in_order).size == np.count_nonzero(np.diff(nodes_in_order)) + 1


def test_the_halves_of_a_cut_do_not_fill_each_other():
    """A 20 x 12 grid is cut first at x = 10 (the median line across its
    longer side): the nodes left of it come first, then those right of it,
    the line last; eliminating the left half creates nothing in the right
    one — in NumPy's Cholesky factor of an SPD matrix with the grid's
    pattern, in this order, every entry between the two halves is zero."""
    graph, points = _grid_graph(20, 12)
    A = -graph.toarray()
    A += np.diag(1.0 - A.sum(axis=1))             # diagonally dominant: SPD
    order = nested_dissection(points, graph, leaf=8)
    x = points[order, 0]
    left, right, line = np.flatnonzero(x < 10), np.flatnonzero(x > 10), np.flatnonzero(x == 10)
    assert left.max() < right.min() and right.max() < line.min()
    L = np.linalg.cholesky(A[np.ix_(order, order)])
    assert np.all(L[np.ix_(right, left)] == 0.0)
    assert np.count_nonzero(L[np.ix_(line, left)]) > 0       # the separator does fill


def test_fill_far_below_a_banded_order():
    """A 40 x 40 grid (an SPD matrix with its pattern): the nested-dissection
    order against the node numbering (a band of one grid row) — nested
    dissection's fill grows as N log N, the band's as N √N (measured 38 325
    against 69 841; qdldl's AMD 36 850, which nested dissection passes from
    about 40 cells on the raft's 3-dof nodes: docs/dev-notes.md)."""
    graph, points = _grid_graph(40, 40)
    A = -graph.toarray()
    A += np.diag(1.0 - A.sum(axis=1))
    nested = _dense_fill(A, nested_dissection(points, graph))
    banded = _dense_fill(A, np.arange(A.shape[0]))
    assert nested < 0.6 * banded, (nested, banded)


@pytest.mark.parametrize("held", [False, True])
@pytest.mark.parametrize("supernodal", [False, True])
def test_a_step_equals_spsolve(held, supernodal, monkeypatch):
    """One Newton step's solve (SuperLU in nested-dissection order, or
    qdldl under its AMD; floor dofs held or not) against SciPy's spsolve
    (SuperLU's own ordering) of the same system built here from K, the
    springs and the held dofs."""
    import formulations.plates.newton as newton_module

    monkeypatch.setattr(newton_module, "SUPERNODAL_DOFS", 0 if supernodal else 10 ** 9)
    raft = _opening_raft()
    b = raft.build()
    qp = b["qp"]
    system = SupportSystem(qp, b["mesh"].nodes)
    assert system.supernodal == supernodal
    rng = np.random.default_rng(3)
    pressing = rng.random(qp.soil.size) < 0.7
    floor_held = (rng.random(qp.floor.size) < 0.5) if held else np.zeros(qp.floor.size, bool)
    assert qp.floor.size > 0
    rhs = rng.standard_normal(system.dofs.size)
    u = system.factor(pressing, floor_held)(rhs)
    A = (system.K + sp.diags(np.bincount(system.soil_w, np.where(pressing, system.k, 0.0),
                                         system.dofs.size))).tocsc()
    keep = np.ones(system.dofs.size, bool)
    keep[system.floor_w[floor_held]] = False
    ref = np.zeros_like(rhs)
    ref[keep] = spla.spsolve(A[keep][:, keep], rhs[keep])
    assert np.all(u[~keep] == 0.0)
    assert np.max(np.abs(u - ref)) <= 1e-9 * np.max(np.abs(ref))
    # several right-hand sides at once (the border's columns) alike
    many = system.factor(pressing, floor_held)(np.column_stack([rhs, 2 * rhs]))
    assert np.max(np.abs(many[:, 1] - 2 * u)) <= 1e-12 * np.max(np.abs(u))


def test_dof_order_groups_a_nodes_dofs():
    graph, points = _grid_graph(6, 4)
    K = sp.kron(graph, np.ones((3, 3))).tocsr()
    node_of = np.repeat(np.arange(points.shape[0]), 3)
    order = dof_order(K, node_of, points)
    assert np.array_equal(np.sort(order), np.arange(K.shape[0]))
    assert np.all(node_of[order].reshape(-1, 3) == node_of[order][::3, None])


def test_the_supernodal_factor_is_an_ldlt_in_the_order(monkeypatch):
    """What a border built on a step's factor reads (newton.Factorisation):
    SuperLU in the given order with diagonal pivots — perm_r and perm_c the
    identity, U = D Lᵀ with L unit lower triangular — and L D Lᵀ is the
    step's matrix in that order (floor dofs held or not)."""
    import formulations.plates.newton as newton_module

    monkeypatch.setattr(newton_module, "SUPERNODAL_DOFS", 0)
    raft = _opening_raft()
    b = raft.build()
    qp = b["qp"]
    system = SupportSystem(qp, b["mesh"].nodes)
    rng = np.random.default_rng(5)
    pressing = rng.random(qp.soil.size) < 0.7
    for held in (np.zeros(qp.floor.size, bool), rng.random(qp.floor.size) < 0.5):
        factor = system.factor(pressing, held)
        lu, dofs = factor.lu, factor.dofs
        identity = np.arange(dofs.size)
        assert np.array_equal(lu.perm_r, identity) and np.array_equal(lu.perm_c, identity)
        L, U = lu.L.tocsc(), lu.U.tocsc()
        assert np.all(L.diagonal() == 1.0) and sp.triu(L, 1).nnz == 0
        d = U.diagonal()
        assert np.all(d > 0)
        assert abs(U - sp.diags(d) @ L.T).max() <= 1e-12 * abs(U).max()
        # L D Lᵀ is K + the pressing springs on dofs, in the order dofs
        A = (system.K + sp.diags(np.bincount(system.soil_w, np.where(pressing, system.k, 0.0),
                                             system.dofs.size))).tocsc()[dofs][:, dofs]
        assert abs(L @ sp.diags(d) @ L.T - A).max() <= 1e-10 * abs(A).max()
        assert np.setdiff1d(np.arange(system.dofs.size), dofs).size == held.sum()


def _bisection_order(points, graph, leaf):
    """Nested dissection written plainly (the NumPy version the compiled
    kernel replaced): halves at the median distinct coordinate across the
    longer side, the far side's nodes with a neighbour across as the
    separator, halves first, separator last."""
    graph = sp.csr_matrix(graph)
    order, stack = [], [(False, np.arange(points.shape[0]))]
    while stack:
        placed, idx = stack.pop()
        p = points[idx]
        axis = 0 if np.ptp(p[:, 0]) >= np.ptp(p[:, 1]) else 1
        values = np.unique(p[:, axis])
        if placed or idx.size <= leaf or values.size < 2:
            order.append(idx)
            continue
        below = p[:, axis] < values[values.size // 2]
        a, b = idx[below], idx[~below]
        in_a = np.zeros(points.shape[0], bool)
        in_a[a] = True
        touches = np.array([in_a[graph[i].indices].any() for i in b], bool)
        stack += [(True, b[touches]), (False, b[~touches]), (False, a)]
    return np.concatenate(order)


def test_the_compiled_order_is_the_plain_bisections_on_a_mesh_with_an_opening_and_a_wall():
    raft = _opening_raft()
    b = raft.build()
    qp = b["qp"]
    held = np.zeros(qp.K.shape[0], bool)
    held[qp.fixed] = True
    dofs = np.flatnonzero(~held)
    K = qp.K.tocsc()[dofs][:, dofs]
    nodes = b["mesh"].nodes
    used, local = np.unique(dofs // 3, return_inverse=True)
    coo = K.tocoo()
    graph = sp.csr_matrix((np.ones(coo.nnz), (local[coo.row], local[coo.col])),
                          shape=(used.size, used.size))
    for leaf in (4, 32):
        plain = _bisection_order(nodes[used], graph, leaf)
        assert np.array_equal(nested_dissection(nodes[used], graph, leaf), plain)
    rank = np.empty(used.size, np.int64)
    rank[_bisection_order(nodes[used], graph, 32)] = np.arange(used.size)
    assert np.array_equal(dof_order(K, dofs // 3, nodes),
                          np.lexsort((np.arange(dofs.size), rank[local])))
