"""What the pivoting methods share: sign tolerances on each component's own
scale, the block exchange rule, and the refusals they raise.

The factorization of an active block and the scalings are in
:mod:`qpcontact.core.linalg`; the componentwise scales in
:mod:`qpcontact.judge.scales`.
"""

from __future__ import annotations

import functools

import numpy as np

from ...core.errors import InvalidProblemError, NotConvexError
from ...judge.scales import ComponentScales

__all__ = ["sign_tolerances", "negative_components", "overflow_result", "time_limit_result",
           "check_dense_size",
           "not_positive_definite", "DENSE_TABLEAU_LIMIT", "ExchangeRule", "SIGN_RTOL",
           "pivot_kernels"]

_EPS = np.finfo(float).eps

#: Largest n for which the tableau methods ("energy", "lemke", "trace") build their
#: dense n x n (or n x 2n) tableau: 8 n^2 bytes is 200 MB at n = 5000.
DENSE_TABLEAU_LIMIT = 5000


@functools.cache
def pivot_kernels():
    """The compiled loops of the pivoting methods (:mod:`._pivot_kernels`),
    imported on first use: numba costs 0.3 s to import, and a listing of the
    methods (`qpcontact methods`, `--help`) calls none of them."""
    from . import _pivot_kernels

    return _pivot_kernels


#: Relative size below which a value counts as zero when deciding signs.
SIGN_RTOL = 1e3 * _EPS


def overflow_result(method: str, exc: Exception):
    """The MethodResult of a method whose solution overflowed: no point, and a
    message that :func:`qpcontact.solve` completes with the data's range."""
    from ...core.results import MethodResult

    return MethodResult(x=None, backend_status="overflow",
                        backend_message=f"{method}: {exc}")


def time_limit_result(method: str, steps: int, what: str, stats: dict):
    """The MethodResult of a method stopped at its deadline (``solve``'s
    ``time_limit=``, checked once per pivot, exchange or cycle): no point —
    an intermediate basis is no answer — and how far it got."""
    from ...core.results import MethodResult

    return MethodResult(x=None, status="time_limit", backend_status="time_limit",
                        backend_message=f"{method}: stopped at the time limit after {steps} "
                        f"{what}", iterations=steps, stats=stats)


class ExchangeRule:
    """Kostreva's block exchange with the Júdice & Pires (1994) safeguard.

    Given the basis F (bool mask, changed in place) and the indices of its
    infeasible components, the whole infeasible set is exchanged while its
    size keeps reaching a new minimum; after ``patience`` exchanges without
    one, single pivots by Murty's least-index rule (finite for P-matrices)
    take over until the size drops again — so the iteration terminates for
    every SPD matrix, whatever basis it starts from.  ``stats`` counts the
    exchanges for the method's report.
    """

    def __init__(self, n: int, patience: int, stats: dict):
        self.best, self.patience, self.left = n + 1, patience, patience
        self.stats = stats
        for key in ("block_exchanges", "single_pivots", "exchanged"):
            stats.setdefault(key, 0)

    def step(self, F: np.ndarray, infeasible: np.ndarray) -> None:
        k = infeasible.size
        if k < self.best or self.left > 0:
            if k < self.best:
                self.best, self.left = k, self.patience
            else:
                self.left -= 1
            F[infeasible] = ~F[infeasible]
            self.stats["block_exchanges"] += 1
            self.stats["exchanged"] += k
        else:
            r = infeasible[0]
            F[r] = not F[r]
            self.stats["single_pivots"] += 1
            self.stats["exchanged"] += 1


def check_dense_size(method: str, n: int, what: str, instead: str) -> None:
    """InvalidProblemError when a dense-tableau method meets n > DENSE_TABLEAU_LIMIT."""
    if n > DENSE_TABLEAU_LIMIT:
        raise InvalidProblemError(
            f"{method!r} keeps a dense {what}; above n = {DENSE_TABLEAU_LIMIT} use {instead}."
        )


def not_positive_definite(method: str, exc: Exception):
    """The NotConvexError an SPD method raises when a block fails to factorize."""
    return NotConvexError(
        f"{method!r} met an active block that is not numerically positive definite ({exc}); "
        "the matrix (M of an LCP, P of a QP) is too close to singular for it — use 'lemke' "
        "for an LCP, a QP backend ('clarabel', 'piqp') for a QP."
    )


def sign_tolerances(scales: ComponentScales, z: np.ndarray, q_terms: np.ndarray | None = None
                    ) -> tuple[np.ndarray, np.ndarray]:
    """(tau_z, tau_w): per-component magnitudes below which z_i or w_i counts as zero.

    SIGN_RTOL times the certificate's own scales at z (ζ_i for z_i, σ_i =
    |q_i| + (|M||z|)_i for w_i): each decision is made on the component's own
    size, so a gap of 5e11 at one contact does not make -0.09 look like zero at
    another, and scaling M or q does not change any decision.
    """
    zeta, sigma = scales.at(z, q_terms)
    return SIGN_RTOL * zeta, SIGN_RTOL * sigma


def negative_components(scales: ComponentScales, values: np.ndarray, is_z: np.ndarray,
                        z: np.ndarray) -> np.ndarray:
    """Indices i with values_i < -tau_i, tau the per-component sign tolerances
    at the point z (ρ ζ_i where is_z, ρ σ_i elsewhere; see sign_tolerances).

    The exact scales cost a pass over |M| (O(n²) dense), which would double the
    cost of a dense pivot.  Cheap bounds decide almost every component:
    σ_i <= |q_i| + ‖M_i‖₁ ‖z‖∞ (+ ‖M_i‖₁ cap on idle rows, the floor) and
    ζ_i <= σ_i / |M_ii|, with 0 as the lower bound of both; the exact
    tolerances are computed only when some value falls between the two.
    """
    row_l1, inv_diag, cap_floor = scales.bound_data()
    surely, unsure = pivot_kernels().sure_negatives(np.asarray(values, dtype=float), np.asarray(is_z, dtype=bool),
                                    np.asarray(z, dtype=float), scales.q_terms, row_l1, inv_diag,
                                    cap_floor, SIGN_RTOL)
    if not unsure:
        return surely
    tau_z, tau_w = sign_tolerances(scales, z)
    return np.flatnonzero(values < -np.where(is_z, tau_z, tau_w))


