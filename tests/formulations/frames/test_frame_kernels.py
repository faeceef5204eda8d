"""The frames' compiled assembly passes against independent routes: the
band's reverse Cuthill–McKee order against scipy's (the order decides the
band's width and the Cholesky's digits), K's CSR against scipy's COO → CSR
of the members' NumPy blocks, and the members' consistent loads against
their fixed-end forces by hand."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import reverse_cuthill_mckee

from formulations.frames.mechanics._frame_kernels import (band_pattern, cuthill_mckee,
                                                           equivalent_loads, global_stiffness)
from formulations.frames.mechanics.loads import MemberLoad, equivalent_nodal_many


@pytest.mark.parametrize("seed", range(40))
def test_the_band_order_is_scipys_reverse_cuthill_mckee(seed):
    """Random symmetric patterns, banded ones and ones in several pieces
    (each piece starts from its own seed): the pattern as scipy's
    canonical CSR of the entries, and the order step for step scipy's."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 250))
    m = int(rng.integers(0, 4 * n))
    r = rng.integers(0, n, m)
    c = np.clip(r + rng.integers(-6, 7, m), 0, n - 1) if seed % 2 else rng.integers(0, n, m)
    diag = np.flatnonzero(rng.random(n) < 0.8)
    rows, cols = np.r_[r, c, diag], np.r_[c, r, diag]
    bw, indptr, indices, degree = band_pattern(n, rows, cols, np.zeros((0, 1), np.int64),
                                               np.zeros(0, np.int64), np.zeros(0, np.int64))
    ref = sp.coo_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n)).tocsr()
    ref.sum_duplicates()
    assert (indptr == ref.indptr).all() and (indices == ref.indices).all()
    assert bw == int(np.abs(rows - cols).max(initial=0))
    order, pos, rcm_bw = cuthill_mckee(indptr, indices, degree, np.argsort(degree))
    want = reverse_cuthill_mckee(sp.csr_matrix((np.ones(indices.size), indices, indptr),
                                               shape=(n, n)), symmetric_mode=True)
    assert (order == want).all()
    assert (pos[order] == np.arange(n)).all()
    assert rcm_bw == int(np.abs(pos[rows] - pos[cols]).max(initial=0))


@pytest.mark.parametrize("nd", [6, 12])
def test_k_and_f_are_the_members_blocks_summed(nd):
    """Random members (3 × 3 rotation blocks, random k and loads, shared
    dofs, springs to the ground): K against scipy's COO → CSR of NumPy's
    Tᵀ k T, F against the bincount of Tᵀ Fe — the same structure (every
    member entry kept, exact zeros too) and sums to rounding."""
    rng = np.random.default_rng(nd)
    m, nodes, nc = 40, 12, 2
    N = nodes * nd // 2
    k = rng.normal(size=(m, nd, nd))
    k[:, 0, 1] = 0.0                         # exact zeros are K's structure too
    R = np.linalg.qr(rng.normal(size=(m, 3, 3)))[0]
    T = np.zeros((m, nd, nd))
    for o in range(0, nd, 3):
        T[:, o:o + 3, o:o + 3] = R
    ends = np.array([rng.choice(nodes, 2, replace=False) for _ in range(m)])
    half = nd // 2
    dofs = np.concatenate([half * ends[:, :1] + np.arange(half),
                           half * ends[:, 1:] + np.arange(half)], axis=1).astype(np.int64)
    Fe = rng.normal(size=(m, nd, nc))
    spring_dof, spring_k = np.array([0, 5, 5], np.int64), np.array([1.0, 2.0, 3.0])
    data, indices, indptr, F = global_stiffness(k, T, dofs, Fe, spring_dof, spring_k, N)
    kg = T.transpose(0, 2, 1) @ k @ T
    rows = np.r_[np.repeat(dofs, nd, axis=1).ravel(), spring_dof]
    cols = np.r_[np.tile(dofs, (1, nd)).ravel(), spring_dof]
    ref = sp.coo_matrix((np.r_[kg.ravel(), spring_k], (rows, cols)), shape=(N, N)).tocsr()
    ref.sum_duplicates()
    assert (indptr == ref.indptr).all() and (indices == ref.indices).all()
    assert np.abs(data - ref.data).max() <= 1e-14 * np.abs(ref.data).max()
    F_ref = np.zeros((N, nc))
    np.add.at(F_ref, dofs.ravel(), (T.transpose(0, 2, 1) @ Fe).reshape(-1, nc))
    assert np.abs(F - F_ref).max() <= 1e-14 * np.abs(F_ref).max()


def test_the_members_loads_are_their_fixed_end_forces():
    """Euler–Bernoulli members, by hand: a uniform load w over the whole
    length gives wL/2 and ±wL²/12; a point load P at a (b = L − a) gives
    P b²(3a + b)/L³, P a b²/L² at i and P a²(a + 3b)/L³, −P a² b/L² at j;
    an axial load is shared b/L, a/L; a member turned 90° sees a global
    y load along its axis."""
    L, w, P, a = 6.0, -4.0, 10.0, 2.0
    b = L - a
    loads = [MemberLoad("distributed", "D", "member", 0.0, L, (0.0, w, 0.0, w)),
             MemberLoad("point", "D", "member", a, a, (3.0, P, 0.0)),
             MemberLoad("distributed", "D", "global", 0.0, L, (0.0, w, 0.0, w))]
    out = equivalent_nodal_many(loads, [L] * 3, [1.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0] * 3)
    assert out[0] == pytest.approx([0.0, w * L / 2, w * L ** 2 / 12, 0.0, w * L / 2,
                                    -w * L ** 2 / 12], rel=1e-14, abs=1e-13)
    assert out[1] == pytest.approx([3.0 * b / L, P * b ** 2 * (3 * a + b) / L ** 3,
                                    P * a * b ** 2 / L ** 2, 3.0 * a / L,
                                    P * a ** 2 * (a + 3 * b) / L ** 3, -P * a ** 2 * b / L ** 2],
                                   rel=1e-14, abs=1e-13)
    # turned 90°: the global y load runs along the member's axis
    assert out[2] == pytest.approx([w * L / 2, 0.0, 0.0, w * L / 2, 0.0, 0.0], abs=1e-13)
    # the kernel on its own takes the same table
    table = np.array([ld.row for ld in loads])
    x = np.where(table[:, 1:2] > 0, table[:, 2:3], 0.5 * L * (np.polynomial.legendre.leggauss(4)[0]
                                                              + 1.0))
    direct = equivalent_loads(table, np.full(3, L), np.array([1.0, 1.0, 0.0]),
                              np.array([0.0, 0.0, 1.0]), np.zeros(3), (x / L) ** 3,
                              *np.polynomial.legendre.leggauss(4))
    assert np.abs(direct - out).max() <= 1e-14 * np.abs(out).max()
