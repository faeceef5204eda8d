"""Bad input gets the documented exception, with a message that says what is
wrong (no raw exception from deep inside a backend), and "auto" neither gives up on valid
input nor wanders past a proof."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import qpcontact
from qpcontact import LCP, InvalidOptionError, InvalidProblemError, NoSolutionError
from qpcontact.core.errors import NotConvexError
from qpcontact.io import read_siconos_lcp
from qpcontact.solvers.registry import _REGISTRY, get_method
from qpcontact.dispatch import lcp_qp_run as lcp_qp


def test_ragged_matrix_is_an_invalid_problem():
    with pytest.raises(InvalidProblemError, match="rectangular"):
        LCP([[1.0, 2.0], [3.0]], [1.0, 2.0])
    with pytest.raises(InvalidProblemError, match="q"):
        LCP(np.eye(2), [[1.0], [2.0, 3.0]])


@pytest.mark.parametrize("method", [None, 3, ["lemke"]])
def test_method_must_be_a_name(method):
    with pytest.raises(InvalidOptionError, match="method must be a string"):
        qpcontact.solve(LCP(np.eye(2), [-1.0, -1.0]), method=method)


@pytest.mark.parametrize("method, option, value", [
    ("lemke", "max_pivots", "abc"), ("lemke", "max_pivots", None), ("lemke", "max_pivots", 2.5),
    ("lemke", "max_pivots", -1), ("lemke", "restarts", "x"), ("lemke", "restarts", True),
    ("lemke", "seed", "x"), ("energy", "max_pivots", "abc"), ("bpp", "max_iter", "x"),
    ("bpp", "patience", None),
])
def test_option_values_of_the_wrong_type(method, option, value):
    with pytest.raises(InvalidOptionError, match=option):
        qpcontact.solve(LCP(np.eye(2) * 2, [-1.0, -1.0]), method=method, **{option: value})


def test_integral_floats_and_numpy_ints_are_accepted():
    lcp = LCP(np.eye(2) * 2, [-1.0, -1.0])
    assert qpcontact.solve(lcp, method="lemke", max_pivots=100.0, restarts=np.int64(2)).ok


def test_siconos_file_paths_and_sizes(tmp_path):
    with pytest.raises(InvalidProblemError, match="directory"):
        read_siconos_lcp(tmp_path)
    with pytest.raises(InvalidProblemError, match="no such file"):
        read_siconos_lcp(tmp_path / "missing.dat")
    # a header announcing n = 1e5 dense (80 GB) in a file of a few bytes: refused
    # before anything is allocated, saying what the header claims
    f = tmp_path / "huge.dat"
    f.write_text("100000 0 100000 100000 100000 100000 1 2 3\n")
    with pytest.raises(InvalidProblemError, match="announces 10000000000 values"):
        read_siconos_lcp(f)


def test_auto_stops_at_a_proof_of_infeasibility():
    """M = 0, q = -1 and an infeasible PSD LCP: the proof sought before any
    method runs ends the call (no backend loop), and raise_on_failure says
    there is no solution; an explicit Lemke proves it with its own Farkas
    vector, which gives the same status."""
    with pytest.raises(NoSolutionError, match="Farkas"):
        qpcontact.solve(LCP(np.zeros((2, 2)), [-1.0, -1.0]), raise_on_failure=True)
    lcp = LCP(np.array([[1.0, -1.0], [-1.0, 1.0]]), [-1.0, -1.0])
    sol = qpcontact.solve(lcp)
    assert sol.status == "infeasible" and sol.stats["proved_infeasible"]
    assert [t[0] for t in sol.stats["auto_tried"]] == ["proof"]
    y = sol.stats["proof"].vector["z"]       # y = (1, 1): M'y = 0, q'y = -2
    assert np.all(y >= 0) and np.all(lcp.M.T @ y <= 0) and lcp.q @ y < 0
    sol = qpcontact.solve(lcp, "lemke")
    assert sol.status == "infeasible" and sol.stats["proved_infeasible"]


def _lemke_without_its_own_proof(monkeypatch):
    """Register a "lemke" whose rays never claim a proof themselves."""
    original = get_method("lemke")

    def run(problem, tol, options):
        res = original.run(problem, tol, options)
        res.stats["proved_infeasible"] = False
        res.stats.pop("proof", None)
        return res

    monkeypatch.setitem(_REGISTRY, "lemke", dataclasses.replace(original, run=run))


def test_unproved_ray_is_not_called_no_solution(monkeypatch):
    _lemke_without_its_own_proof(monkeypatch)
    # and no proof found afterwards either (on these data one exists: the
    # engine's own search finds it from Lemke's vector, tested below)
    monkeypatch.setattr(lcp_qp, "prove_lcp_infeasible", lambda *a, **k: None)
    monkeypatch.setattr(lcp_qp, "cheap_lcp_farkas", lambda *a, **k: None)
    with pytest.raises(qpcontact.SolverFailedError):
        qpcontact.solve(LCP(np.zeros((2, 2)), [-1.0, -1.0]), method="lemke", raise_on_failure=True)


def test_a_ray_with_a_farkas_vector_is_proved_by_the_engine_exactly(monkeypatch):
    """Lemke's own word dropped, the engine checks the vector it found in
    exact arithmetic and proves it (data with no row of nonpositive signs,
    which would be proved from the signs alone)."""
    _lemke_without_its_own_proof(monkeypatch)
    sol = qpcontact.solve(LCP([[1.0, -1.0], [-1.0, 1.0]], [-1.0, -1.0]), method="lemke")
    assert sol.status == "infeasible" and "exact rational" in sol.message


def test_auto_goes_on_when_a_method_finds_the_matrix_unfit_mid_run(monkeypatch):
    """A block that is not numerically positive definite is found only while
    factorizing; "auto" must try the next method, not pass the error on."""
    def refuse(problem, tol, options):
        raise NotConvexError("'energy' met an active block that is not numerically positive definite")

    monkeypatch.setitem(_REGISTRY, "energy", dataclasses.replace(get_method("energy"), run=refuse))
    sol = qpcontact.solve(LCP(np.eye(3) * 2, [-1.0, 1.0, -2.0]))
    assert sol.ok and sol.method == "bpp"
    assert sol.stats["auto_tried"][0][0] == "energy" and "skipped" in sol.stats["auto_tried"][0][1]


def _hierarchy_lcp(P):
    return LCP(2 * np.eye(8), -np.ones(8), hierarchy=[P])


def _pairs():
    P = np.zeros((8, 4))
    P[np.arange(8), np.arange(8) // 2] = 1.0
    return P


@pytest.mark.parametrize("make, words", [
    (lambda P: P * (1 + 1j), r"hierarchy level 0: the prolongation has complex entries "
                             r"\(dtype complex128\).*pass its real part"),
    (lambda P: __import__("scipy.sparse").sparse.csr_matrix(P * (1 + 0.5j)),
     r"hierarchy level 0: the prolongation has complex entries"),
    (lambda P: np.where(np.arange(32).reshape(8, 4) == 0, np.nan, P),
     r"not finite \(P_0\[0, 0\] = nan\)"),
    (lambda P: np.where(np.arange(32).reshape(8, 4) == 5, np.inf, P),
     r"not finite \(P_0\[1, 1\] = inf\)"),
])
def test_a_complex_or_non_finite_prolongation_is_refused(make, words):
    """Before: a complex P lost its imaginary part with a warning and the
    problem was solved ok=True."""
    with pytest.raises(InvalidProblemError, match=words):
        _hierarchy_lcp(make(_pairs()))


def _friction():
    return qpcontact.FrictionProblem(2 * np.eye(3), [-1.0, 0.0, 0.0], [0.3], 3)


@pytest.mark.parametrize("kw, words", [
    (dict(time_limit="5"), "time_limit must be a positive number of seconds or None .* got '5'"),
    (dict(method="nsgs", max_sweeps=-5), "'nsgs': option max_sweeps must be an integer >= 0; got -5"),
    (dict(method="nsgs", max_sweeps=1.5), "option max_sweeps must be an integer >= 0; got 1.5"),
    (dict(method="nsgs", r0=[np.nan, 0, 0]), "option r0 must be a vector of finite numbers.*entry 0 is nan"),
    (dict(method="newton", r0=[np.inf, 0, 0]), "'newton': option r0 .*entry 0 is inf"),
    (dict(progress="notcallable"), "'auto': option progress must be a callable; got 'notcallable'"),
])
def test_friction_options_name_the_bad_value(kw, words):
    with pytest.raises(InvalidOptionError, match=words):
        qpcontact.solve(_friction(), **kw)


@pytest.mark.parametrize("mu", ["0.3", ["abc"], [b"0.3"]])
def test_a_friction_coefficient_given_as_text_is_refused(mu):
    with pytest.raises(InvalidProblemError, match="friction coefficients mu must be numbers.*got"):
        qpcontact.FrictionProblem(2 * np.eye(3), [-1.0, 0.0, 0.0], mu, 3)


def test_a_global_problem_names_its_bad_coefficient():
    with pytest.raises(InvalidProblemError, match=r"mu\[0\] = nan"):
        qpcontact.FrictionProblem.global_problem(np.eye(3), np.eye(3), np.zeros(3), np.zeros(3),
                                                 [np.nan], 3)


def _generators():
    from qpcontact.cases.families import far_contact_lcp, random_spd_lcp, spread_lcp
    from qpcontact.cases.piles import disc_pile, sphere_pile
    from qpcontact.cases.planted import build_lcp, build_qp
    from qpcontact.cases.planted_friction import build_friction
    from qpcontact.cases.rounded import build_rounded
    from qpcontact.commands.stress.cases import build_case

    return [lambda s: random_spd_lcp(5, 10.0, s), lambda s: far_contact_lcp(s),
            lambda s: spread_lcp(s), lambda s: disc_pile(10, seed=s),
            lambda s: sphere_pile(10, seed=s), lambda s: build_lcp("spd", 5, s),
            lambda s: build_qp("convex", 5, s), lambda s: build_friction("sticking", 2, s),
            lambda s: build_rounded("illposed_psd", 5, s), lambda s: build_case("spd", 5, s)]


@pytest.mark.parametrize("k", range(10))
def test_a_negative_seed_is_refused_naming_it(k):
    with pytest.raises(InvalidOptionError, match=r"seed must be an integer >= 0 .*got -1 — pass 0"):
        _generators()[k](-1)
