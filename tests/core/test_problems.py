"""Problem types: validation messages and cached structure."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
import scipy.sparse as sp

from qpcontact import LCP, InvalidProblemError, ParametricLCP


@pytest.mark.parametrize("M, q, fragment", [
    (np.ones((2, 3)), np.ones(2), "square"),
    (np.eye(3), np.ones(2), "q has length 2"),
    (np.zeros((0, 0)), np.zeros(0), "no rows"),
    (np.ones(3), np.ones(3), "2-D"),
    (np.array([[1.0, np.nan], [0.0, 1.0]]), np.ones(2), "index (0, 1)"),
    (np.eye(2), np.array([1.0, np.inf]), "q has a non-finite entry inf at index 1"),
    (np.eye(2) * 1j, np.ones(2), "complex"),
    (np.array([["a", "b"], ["c", "d"]]), np.ones(2), "real numbers"),
    (sp.csc_matrix(([np.nan], ([1], [0])), shape=(2, 2)), np.ones(2), "index (1, 0)"),
])
def test_invalid_lcp_names_the_problem(M, q, fragment):
    with pytest.raises(InvalidProblemError) as info:
        LCP(M, q)
    assert fragment in str(info.value)


def test_parametric_validation_names_argument():
    with pytest.raises(InvalidProblemError, match="q1 has length 3"):
        ParametricLCP(np.eye(2), [1, 2], [1, 2, 3])
    with pytest.raises(InvalidProblemError, match="q0 has a non-finite entry nan at index 0"):
        ParametricLCP(np.eye(2), [np.nan, 2], [1, 2])


def test_column_vector_q_is_accepted():
    lcp = LCP(np.eye(2), np.array([[1.0], [2.0]]))
    assert lcp.q.shape == (2,)


def test_symmetry_is_relative_to_scale():
    A = np.array([[1e8, 2e8], [2e8 + 1e-3, 5e8]])  # asymmetry 1e-3 against entries 5e8: rounding
    assert LCP(A, [0, 0]).is_symmetric
    B = np.array([[1.0, 2.0], [2.0 + 1e-6, 5.0]])  # the same absolute asymmetry is structural here
    assert not LCP(B, [0, 0]).is_symmetric


@pytest.mark.parametrize("make", [np.asarray, sp.csc_matrix])
def test_definiteness_dense_and_sparse(make):
    spd = make(np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 2]]))
    psd = make(np.ones((3, 3)))
    indefinite = make(np.array([[1.0, 2.0, 0], [2.0, 1.0, 0], [0, 0, 1.0]]))
    nonsym_pd = make(np.array([[1.0, 1.0, 0], [-1.0, 1.0, 0], [0, 0, 1.0]]))  # M + M' = 2I
    assert LCP(spd, np.zeros(3)).is_positive_definite
    assert LCP(spd, np.zeros(3)).is_psd
    assert not LCP(psd, np.zeros(3)).is_positive_definite
    assert LCP(psd, np.zeros(3)).is_psd
    assert not LCP(indefinite, np.zeros(3)).is_psd
    m = LCP(nonsym_pd, np.zeros(3))
    assert not m.is_symmetric and m.is_positive_definite


def test_sparse_stays_sparse_and_structure_matches_dense():
    rng = np.random.default_rng(0)
    n = 200
    main = 2.0 + rng.random(n)
    M = sp.diags([-np.ones(n - 1), main, -np.ones(n - 1)], [-1, 0, 1], format="csr")
    lcp = LCP(M, rng.standard_normal(n))
    assert lcp.is_sparse and sp.issparse(lcp.M)
    dense = LCP(M.toarray(), lcp.q)
    assert lcp.is_positive_definite == dense.is_positive_definite == bool(np.linalg.eigvalsh(M.toarray())[0] > 0)
    shifted = LCP(M - 3.5 * sp.identity(n), lcp.q)  # pushes eigenvalues below zero
    assert shifted.is_positive_definite == bool(np.linalg.eigvalsh(shifted.M.toarray())[0] > 0)


def test_parametric_at_shares_structure_and_pickles():
    fam = ParametricLCP(np.array([[2.0, 1.0], [1.0, 2.0]]), [1.0, -1.0], [-1.0, 0.5])
    lcp = fam.at(2.0)
    np.testing.assert_allclose(lcp.q, [1 - 2, -1 + 1.0])
    assert lcp.structure is fam.structure
    with pytest.raises(InvalidProblemError, match="finite"):
        fam.at(np.inf)
    again = pickle.loads(pickle.dumps(lcp))
    np.testing.assert_array_equal(again.M, lcp.M)
    assert again.is_symmetric
    fam2 = pickle.loads(pickle.dumps(fam))
    np.testing.assert_array_equal(fam2.q1, fam.q1)


def test_definiteness_by_diagonal_dominance_and_its_limits():
    """Gershgorin decides irreducibly diagonally dominant matrices without a
    factorization; singular weakly dominant ones are not passed.
    References: the Dirichlet Laplacian is PD, the periodic ring Laplacian
    is PSD and singular (eigenvalue 0 for the constant vector)."""
    import scipy.sparse as sp

    from formulations import meshes
    from qpcontact.core.matrices import MatrixStructure

    assert MatrixStructure(meshes.laplacian(30).tocsc()).is_positive_definite
    n = 50
    ring = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1]).tolil()
    ring[0, n - 1] = ring[n - 1, 0] = -1.0
    ring = ring.tocsc()
    assert np.allclose(ring @ np.ones(n), 0.0)
    assert not MatrixStructure(ring).is_positive_definite
    assert MatrixStructure(ring).is_psd
    both = sp.block_diag([meshes.laplacian(10), ring]).tocsc()   # one component has no strict row
    assert not MatrixStructure(both).is_positive_definite
    assert MatrixStructure(meshes.plate(12).M).is_positive_definite   # not dominant: factorized
    swapped = sp.csc_matrix(np.array([[1.0, 2.0], [2.0, 1.0]]))
    assert not MatrixStructure(swapped).is_psd
