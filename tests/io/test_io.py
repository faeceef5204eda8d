"""The Siconos LCP reader, on the peers' files and on broken ones."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from qpcontact import InvalidProblemError
from qpcontact.io import read_problem, read_siconos_fc, read_siconos_lcp

from tests.helpers.paths import siconos_files


def test_every_file_parses(siconos_dir):
    files = siconos_files()
    assert len(files) >= 16
    for path in files:
        lcp = read_siconos_lcp(path)
        assert lcp.n >= 2, path.name


def test_block_files_equal_their_dense_twins(siconos_dir):
    twins = [p for p in siconos_files() if p.stem.endswith("_block")]
    assert len(twins) == 3
    for block_path in twins:
        block = read_siconos_lcp(block_path)
        dense = read_siconos_lcp(block_path.with_name(block_path.stem[:-6] + ".dat"))
        assert sp.issparse(block.M)
        np.testing.assert_array_equal(block.M.toarray(), dense.M)
        np.testing.assert_array_equal(block.q, dense.q)


def test_known_contents(siconos_dir):
    """Column-major reading, checked against SOURCE.md's descriptions."""
    deudeu = read_siconos_lcp(siconos_dir / "lcp_deudeu.dat")
    np.testing.assert_array_equal(deudeu.M, [[2, 1], [1, 2]])
    np.testing.assert_array_equal(deudeu.q, [-5, -6])
    murty = read_siconos_lcp(siconos_dir / "lcp_exp_murty.dat")  # upper triangular, 2 above
    np.testing.assert_array_equal(murty.M, np.eye(6) + 2 * np.triu(np.ones((6, 6)), 1))
    cps4 = read_siconos_lcp(siconos_dir / "lcp_CPS_4.dat")  # KKT of a QP, comment after q
    np.testing.assert_array_equal(cps4.q, [50, 50, 10, -6])
    z = np.array([2.0, 2, 2, 92])  # SOURCE.md's solution
    w = cps4.w(z)
    assert np.all(w >= -1e-12) and abs(z @ w) <= 1e-9


@pytest.mark.parametrize("text, fragment", [
    ("2 0 2 2 2 2 1 0 0 1 5", "token 12: expected a value of q, the file ended"),
    ("2 0 2 2 2 2 1 0 x 1 5 6", "token 9: expected a number (a value of M), found 'x'"),
    ("2 7 2 2", "token 2: expected storage type 0"),
    ("2 0 3 3", "M is 3 x 3 but the LCP size is 2"),
    ("two", "token 1: expected an integer"),
    ("2 0 2 2 2 3", "token 5: expected the repeated size 2 2"),
    ("2 0 2 2 2 2 1 0 nan 1 5 6", "token 9: expected a finite number"),
])
def test_malformed_files_say_where(tmp_path, text, fragment):
    path = tmp_path / "broken.dat"
    path.write_text(text)
    with pytest.raises(InvalidProblemError) as info:
        read_siconos_lcp(path)
    assert "broken.dat" in str(info.value) and fragment in str(info.value)


def test_sparse_block_inconsistency(tmp_path):
    # one 2x2 block declared, but the block-row end says 3 rows
    path = tmp_path / "blk.dat"
    path.write_text("2 1 2 2 1 1 1 3 2 2 1 0 1 0 0 2 1 1 2 -5 -6")
    with pytest.raises(InvalidProblemError, match="blk.dat: block sizes"):
        read_siconos_lcp(path)


# A file with something after its data was once solved without a word.
_DEUDEU = "2\n0 2 2\n2 2\n2 1\n1 2\n-5 -6"   # M = [[2, 1], [1, 2]], q = (-5, -6) on line 6


@pytest.mark.parametrize("tail, fragment", [
    (b" garbage here\n", "line 6: text 'garbage' (a comment after the data must start with '#'"),
    (b"\n7\n", "line 7: 1 more number than the header announces (first: '7') after the 2 values of q"),
    (b"\n\n\n7 8 9\n", "line 9: 3 more numbers than the header announces"),
    (b"\ngarbage\n", "line 7: text 'garbage'"),
    (b"\n\x00\x01\xfe\xffPK\x03\x04", "line 7: binary data after the 2 values of q"),
    (b"\x00\x01", "line 6, token 12: expected a number (a value of q), found '-6\\x00\\x01'"),
    (b"\n\n\x89PNG\r\n\x1a\n", "line 8: binary data"),
])
def test_trailing_garbage_is_refused_with_file_and_line(tmp_path, tail, fragment):
    path = tmp_path / "tail.dat"
    path.write_bytes(_DEUDEU.encode() + tail)
    for reader in (read_siconos_lcp, read_problem):
        with pytest.raises(InvalidProblemError) as info:
            reader(path)
        assert "tail.dat" in str(info.value) and fragment in str(info.value), str(info.value)


@pytest.mark.parametrize("tail", ["", "\n\n\n", "\n\nExample 4.4.7 CPS 2009\n", "\n# from Murty 1988\n",
                                  "\n# 1 2 3\n"])
def test_comments_after_the_data_are_allowed(tmp_path, tail):
    path = tmp_path / "ok.dat"
    path.write_text(_DEUDEU + tail)
    lcp = read_problem(path)
    np.testing.assert_array_equal(lcp.q, [-5, -6])


def test_friction_files_keep_their_is_complete_flag_and_nothing_else(tmp_path):
    body = "2\n1\n0 2 2\n2 2\n1 0\n0 1\n-1 0\n0.5\n"   # d = 2, one contact, W = I, q, mu
    ok = tmp_path / "fc.dat"
    ok.write_text(body + "1\n")
    assert read_siconos_fc(ok).mu.tolist() == [0.5]
    bad = tmp_path / "fc_bad.dat"
    bad.write_text(body + "1\n0.25 0.25\n")
    with pytest.raises(InvalidProblemError, match=r"fc_bad.dat: line 10: 2 more numbers"):
        read_siconos_fc(bad)


def test_written_friction_files_read_back_the_same_problem(tmp_path):
    """write_siconos_fc's sparse-block layout read by the reader (which the
    shared Siconos files check): W, q and mu come back bit for bit, blocks
    that hold zeros included, and the reader takes it as frictional contact."""
    from qpcontact.cases.piles import sphere_pile
    from qpcontact.core.friction_problem import FrictionProblem
    from qpcontact.io import write_siconos_fc

    pile = sphere_pile(40, seed=1).problem
    # unsymmetric blocks (a row-major writer would transpose them), a zero
    # inside a stored block, an off-diagonal block
    W = np.array([[2.0, 0.5, 0.0, 0.0], [-0.2, 1.0, 0.0, 0.25], [0.0, 0.0, 3.0, 0.0],
                  [0.0, 0.125, 0.0, 1.0]])
    disc = FrictionProblem(W, np.array([-1.0, 0.1, 1 / 3, -2e-300]), np.array([0.3, 0.7]), 2)
    for problem in (pile, disc):
        path = write_siconos_fc(problem, tmp_path / "written.dat")
        back = read_problem(path)
        assert (back.dim, back.n_contacts) == (problem.dim, problem.n_contacts)
        original = problem.W.toarray() if sp.issparse(problem.W) else problem.W
        np.testing.assert_array_equal(back.W.toarray(), original)
        np.testing.assert_array_equal(back.q, problem.q)
        np.testing.assert_array_equal(back.mu, problem.mu)


def test_shared_friction_files_written_again_read_the_same(tmp_path):
    """Siconos's own local files (dense and sparse-block W) through the writer
    and back: the same W, q and mu."""
    from tests.helpers.paths import data_dir
    from qpcontact.io import write_siconos_fc

    folder = data_dir("siconos-fc")
    if not folder.is_dir():
        pytest.skip(f"Siconos frictional contact data not found at {folder}")
    done = 0
    for path in sorted(folder.glob("*.dat")):
        original = read_problem(path)
        if not hasattr(original, "mu") or not original.is_reduced or original.global_data:
            continue
        back = read_siconos_fc(write_siconos_fc(original, tmp_path / path.name))
        W = original.W.toarray() if sp.issparse(original.W) else original.W
        np.testing.assert_array_equal(back.W.toarray(), W, err_msg=path.name)
        np.testing.assert_array_equal(back.q, original.q, err_msg=path.name)
        np.testing.assert_array_equal(back.mu, original.mu, err_msg=path.name)
        done += 1
    assert done >= 8


def test_a_global_problem_without_w_is_refused(tmp_path):
    from qpcontact.core.friction_problem import FrictionProblem
    from qpcontact.io import write_siconos_fc

    problem = FrictionProblem.global_problem(np.eye(2), np.eye(2), np.array([1.0, 0.0]),
                                             np.zeros(2), np.array([0.5]), 2, reduce=False)
    assert not problem.is_reduced
    with pytest.raises(InvalidProblemError, match="write_fclib"):
        write_siconos_fc(problem, tmp_path / "global.dat")
    assert not (tmp_path / "global.dat").exists()


def test_an_interrupted_write_leaves_the_old_file(tmp_path, monkeypatch):
    """write_siconos_fc writes beside the file and renames: a failure at the
    rename keeps the old file whole and leaves no temporary behind."""
    import os

    from qpcontact.core.friction_problem import FrictionProblem
    from qpcontact.io import write_siconos_fc

    path = tmp_path / "kept.dat"
    path.write_text("the old file\n")
    problem = FrictionProblem(np.eye(2), np.array([-1.0, 0.0]), np.array([0.5]), 2)

    def fail(*_):
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", fail)
    with pytest.raises(OSError, match="disk full"):
        write_siconos_fc(problem, path)
    assert path.read_text() == "the old file\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kept.dat"]
