"""Problem families with a planted solution (re-exported by qpcontact.testing): seeded, deterministic.

Each generator plants a solution (z*, w*) and builds the data around it, so a
method's answer can be judged without trusting any solver — or qpcontact's own
certificate.  All are seeded and deterministic.

- :func:`random_spd_lcp` — SPD M with a chosen condition number, about half
  the constraints active;
- :func:`far_contact_lcp` — the same with a few *far contacts*: gaps q_i of
  5e11 beside gaps of 0.1 (a log far away in a drum, a support with a large
  clearance).  A tolerance scaled by the largest entry of q lets the near
  contacts be wrong by most of their own size (docs/certificates.md);
- :func:`spread_lcp` — planted gaps spread over many orders of magnitude,
  with degenerate pairs (z_i = w_i = 0), dense or sparse.

:func:`planted_ok` judges an answer against the planted solution, component by
component against each component's own size.
"""

from __future__ import annotations

import numpy as np

from ..core.options import check_seed
from ..core.problems import LCP

__all__ = ["random_spd", "random_spd_lcp", "far_contact_lcp", "spread_lcp", "planted_ok"]


def random_spd(n: int, cond: float, rng: np.random.Generator, *, log_spaced_from: float = 1.0) -> np.ndarray:
    """Q diag(λ) Q' with Q a random orthogonal matrix and λ log-spaced in
    [log_spaced_from / cond, log_spaced_from] (so cond(M) = cond exactly, up to rounding)."""
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    lam = np.logspace(np.log10(log_spaced_from / cond), np.log10(log_spaced_from), n)
    M = (Q * lam) @ Q.T
    return 0.5 * (M + M.T)


def _planted(M: np.ndarray, rng: np.random.Generator, active_fraction: float = 0.5,
             low: float = 0.1, high: float = 2.0):
    n = M.shape[0]
    active = rng.random(n) < active_fraction
    z = np.where(active, rng.uniform(low, high, n), 0.0)
    w = np.where(active, 0.0, rng.uniform(low, high, n))
    return z, w


def random_spd_lcp(n: int, cond: float, seed: int):
    """(LCP, z*): dense SPD M with condition number ``cond``, about half the
    z* in [0.1, 2] and the other half of the w* in [0.1, 2]."""
    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    M = random_spd(n, cond, rng)
    z, w = _planted(M, rng)
    return LCP(M, w - M @ z), z


def far_contact_lcp(seed: int, n: int = 21, cond: float = 297.0, n_far: int = 3,
                    far: float = 5e11):
    """(LCP, z*, w*): the far-contact family: gaps spread over
    1e0..1e12, where one tolerance for every row gave silent wrong answers.

    M = Q diag(λ) Q' (λ log-spaced in [1/cond, 1]); z*_i uniform in [0.1, 2] on
    about half the indices and 0 elsewhere, w*_i uniform in [0.1, 2] where
    z*_i = 0; q = w* - M z*; then ``far`` is added to q_i (and w*_i) at
    ``n_far`` indices where z*_i = 0, which keeps z* the unique solution.
    """
    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    M = random_spd(n, cond, rng)
    z, w = _planted(M, rng)
    q = w - M @ z
    free = np.flatnonzero(z == 0)
    idx = rng.choice(free, size=min(n_far, free.size), replace=False)
    q[idx] += far
    w = w.copy()
    w[idx] += far
    return LCP(M, q), z, w


def spread_lcp(seed: int, n: int = 24, cond: float = 100.0, decades: float = 12.0,
               degenerate_fraction: float = 0.2, sparse: bool = False):
    """(LCP, z*, w*): planted gaps w* spread log-uniformly over 10^0 .. 10^decades,
    forces z* in [0.1, 2], and a fraction of degenerate pairs (z*_i = w*_i = 0).

    Gaps far apart are the far-contact situation generalised; degenerate pairs
    are contacts that touch without load.  Both leave the solution well
    determined by the data (the rounding of a large q_i only moves its own
    w_i), so an answer can be held to the planted solution.  M is dense SPD
    with condition number ``cond``, or (``sparse=True``) a tridiagonal contact
    chain as a SciPy CSC matrix.
    """
    import scipy.sparse as sp

    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    if sparse:
        k = rng.uniform(0.5, 1.5, n + 1)
        M = sp.diags([-k[1:-1], k[:-1] + k[1:] + 0.01, -k[1:-1]], [-1, 0, 1], format="csc")
    else:
        M = random_spd(n, cond, rng)
    kind = rng.choice(3, size=n, p=[(1 - degenerate_fraction) / 2] * 2 + [degenerate_fraction])
    z = np.where(kind == 0, rng.uniform(0.1, 2.0, n), 0.0)
    w = np.where(kind == 1, 10.0 ** rng.uniform(0.0, decades, n), 0.0)
    return LCP(M, w - np.asarray(M @ z).ravel()), z, w


def planted_ok(z, w, z_star, w_star, rtol: float = 1e-6) -> bool:
    """Whether (z, w) equals the planted (z*, w*) component by component:
    ``|z_i - z*_i| <= rtol * s_i`` with ``s_i = max(|z*_i|, floor)``, the same for w,
    where the floor is the smallest nonzero planted magnitude (a planted zero
    is judged on the scale of the smallest planted value, not the largest)."""
    if z is None or w is None:
        return False
    z, w = np.asarray(z, float), np.asarray(w, float)
    nz = np.concatenate([np.abs(z_star[z_star != 0]), np.abs(w_star[w_star != 0])])
    floor = float(nz.min()) if nz.size else 1.0
    ok_z = np.abs(z - z_star) <= rtol * np.maximum(np.abs(z_star), floor)
    ok_w = np.abs(w - w_star) <= rtol * np.maximum(np.abs(w_star), floor)
    return bool(np.all(ok_z) and np.all(ok_w))
