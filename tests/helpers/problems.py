"""Seeded SPD problems with a planted solution, for tests that need many of a
given size and condition.  Named apart from the package's own generators
(qpcontact.cases.families.random_spd_lcp has another signature and returns an
Instance), so that neither shadows the other."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp


def seeded_spd_matrix(n: int, cond: float, seed: int, sparse: bool = False):
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


def planted_spd_lcp(n: int, cond: float, seed: int, sparse: bool = False):
    from qpcontact import LCP

    rng = np.random.default_rng(seed + 10_000)
    M = seeded_spd_matrix(n, cond, seed, sparse)
    # about half the constraints active: q = -M z* + w* with complementary z*, w*
    active = rng.random(n) < 0.5
    z_star = np.where(active, rng.uniform(0.5, 2.0, n), 0.0)
    w_star = np.where(active, 0.0, rng.uniform(0.5, 2.0, n))
    q = w_star - np.asarray(M @ z_star).ravel()
    return LCP(M, q), z_star
