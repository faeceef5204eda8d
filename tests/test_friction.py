"""Frictional contact (issue 20, first part): readers for Siconos .dat and
FCLIB HDF5 files, the problem type, the natural-map error, and the exact 2-D
LCP solved by Lemke — judged by an error function written here, independently
of qpcontact.friction."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from qpcontact.errors import InvalidProblemError
from qpcontact.friction import FrictionProblem, natural_map_error, project_cone, solve_friction
from qpcontact.io import read_fclib, read_siconos_fc

DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "siconos-fc"
FILES = sorted(p.name for p in DATA.glob("*") if p.suffix in (".dat", ".hdf5")) if DATA.is_dir() \
    else []
needs_data = pytest.mark.skipif(not FILES, reason=f"Siconos friction data not found at {DATA}")
SMALL_2D = ["FC2D_SliderCrankLagrangian00000.dat", "FC2D_SliderCrankLagrangian00001.dat",
            "FrictionContactProblem00031.dat", "FrictionContactProblem00071.dat",
            "FrictionContactProblem00394.dat"]


def _read(name):
    path = DATA / name
    return read_fclib(path) if path.suffix == ".hdf5" else read_siconos_fc(path)


def _error_here(W, q, mu, r):
    """Siconos's natural-map error, written out contact by contact."""
    u = W @ r + q
    d = len(r) // len(mu)
    total = 0.0
    for i, m in enumerate(mu):
        ri, ui = r[d * i:d * i + d], u[d * i:d * i + d]
        uh = ui.copy()
        uh[0] += m * np.linalg.norm(ui[1:])
        x = ri - uh
        xn, xt = x[0], x[1:]
        nt = np.linalg.norm(xt)
        if nt <= m * xn:
            p = x
        elif m * nt <= -xn:
            p = np.zeros(d)
        else:
            a = (xn + m * nt) / (1 + m * m)
            p = np.r_[a, m * a * xt / nt]
        total += np.sum((ri - p) ** 2)
    return np.sqrt(total) / (1 + np.linalg.norm(q))


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
    p = _read(name)
    s = solve_friction(p, "auto", tol=1e-8)
    assert s.ok, s.message
    W = p.W.toarray() if hasattr(p.W, "toarray") else np.asarray(p.W)
    assert _error_here(W, p.q, p.mu, s.r) <= 1e-8
    assert natural_map_error(p, s.r) == pytest.approx(_error_here(W, p.q, p.mu, s.r), abs=1e-14)


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
