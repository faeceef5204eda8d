"""Shared fixtures: the peers' data in ../shared/data, seeded random problems."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from qpcontact.core.files import find_data

# $QPCONTACT_DATA/siconos-lcp, else the checkout's ../shared/data (qpcontact.core.files)
SICONOS_DIR = (find_data("siconos-lcp")
               or Path(__file__).resolve().parents[2] / "shared" / "data" / "siconos-lcp")


@pytest.fixture
def siconos_dir() -> Path:
    if not SICONOS_DIR.is_dir():
        pytest.skip(f"Siconos LCP test data not found at {SICONOS_DIR} (the repo's ../shared/data); "
                    "these tests need the shared data set beside the checkout, or QPCONTACT_DATA")
    return SICONOS_DIR


def siconos_files() -> list[Path]:
    return sorted(SICONOS_DIR.glob("*.dat")) if SICONOS_DIR.is_dir() else []


def random_spd(n: int, cond: float, seed: int, sparse: bool = False):
    """A seeded SPD matrix with condition number ``cond``: Q diag(d) Q' with
    log-spaced d (dense), or a banded matrix shifted to the wanted spectrum
    (sparse: tridiagonal-plus-random-band, cond estimated exactly by eigvalsh
    for the sizes used in tests)."""
    rng = np.random.default_rng(seed)
    if not sparse:
        Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
        d = np.logspace(0, np.log10(cond), n)
        M = (Q * d) @ Q.T
        return 0.5 * (M + M.T)
    band = sp.diags([rng.uniform(-1, 0, n - 1), rng.uniform(-1, 0, n - 1)], [-1, 1]).tocsr()
    band = 0.5 * (band + band.T)
    ev = np.linalg.eigvalsh(band.toarray())
    lo, hi = ev[0], ev[-1]
    # shift so that eigenvalues span [s, s + (hi - lo)] with (s + hi - lo) / s = cond
    s = (hi - lo) / (cond - 1.0)
    M = band + sp.identity(n) * (s - lo)
    return sp.csc_matrix(M)


def random_spd_lcp(n: int, cond: float, seed: int, sparse: bool = False):
    from qpcontact import LCP

    rng = np.random.default_rng(seed + 10_000)
    M = random_spd(n, cond, seed, sparse)
    # about half the constraints active: q = -M z* + w* with complementary z*, w*
    active = rng.random(n) < 0.5
    z_star = np.where(active, rng.uniform(0.5, 2.0, n), 0.0)
    w_star = np.where(active, 0.0, rng.uniform(0.5, 2.0, n))
    q = w_star - np.asarray(M @ z_star).ravel()
    return LCP(M, q), z_star
