"""Nonsmooth Gauss–Seidel (Siconos's NSGS workhorse)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..core.errors import InvalidOptionError
from ._nsgs_kernels import sweeps
from .measures import certified_error

__all__ = ["solve_nsgs"]


def solve_nsgs(problem, tol, options):
    """Nonsmooth Gauss–Seidel (Siconos's NSGS; :mod:`qpcontact._nsgs_kernels`):
    sweeps over the contacts, each solving its local problem with the
    others frozen — exactly in 2-D, by a local projected fixed point in 3-D.
    Options: ``max_sweeps`` (10 000), ``check_every`` (10 sweeps between
    error checks), ``r0``, ``local_rtol`` (1e-14), ``max_local`` (200
    local iterations).  Stops when both error measures are <= tol, or
    when the best error has not improved for 100 checks; returns the best
    iterate.  No convergence guarantee (Coulomb friction is not a
    minimisation): the certificate decides."""
    options = dict(options)
    max_sweeps = int(options.pop("max_sweeps", 10_000))
    every = max(1, int(options.pop("check_every", 10)))
    local_rtol = float(options.pop("local_rtol", 1e-14))
    max_local = int(options.pop("max_local", 200))
    r0 = options.pop("r0", None)
    if options:
        raise InvalidOptionError(f"'nsgs' does not take {', '.join(sorted(options))}; its options "
                                 "are max_sweeps, check_every, r0, local_rtol, max_local")
    d, nc = problem.dim, problem.n_contacts
    W = sp.csr_matrix(problem.W)
    W.sort_indices()
    blocks = np.empty((nc, d, d))
    for i in range(nc):
        blocks[i] = W[d * i:d * i + d, d * i:d * i + d].toarray()
    r = np.zeros(d * nc) if r0 is None else np.array(r0, float).ravel()
    if r.shape != (d * nc,):
        raise InvalidOptionError(f"'nsgs': r0 must have {d * nc} entries; got {r.size}")
    indices = W.indices.astype(np.int64)
    best, best_r, since, done = np.inf, r.copy(), 0, 0
    while done < max_sweeps:
        sweeps(W.indptr, indices, W.data, problem.q, problem.mu, d, r, blocks, every,
               local_rtol, max_local)
        done += every
        err = certified_error(problem, r)
        if err < best:
            best, best_r, since = err, r.copy(), 0
        else:
            since += 1
        if best <= tol or since >= 100 or not np.all(np.isfinite(r)):
            break
    why = ("reached the tolerance" if best <= tol else
           "stalled (no better iterate in 100 checks)" if since >= 100 else
           f"stopped at {max_sweeps} sweeps")
    return best_r, "solved" if best <= tol else "stopped", \
        f"NSGS {why} after {done} sweeps", {"iterations": done}
