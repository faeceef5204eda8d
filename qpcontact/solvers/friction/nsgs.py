"""Nonsmooth Gauss–Seidel (Siconos's NSGS workhorse)."""

from __future__ import annotations

import functools

import numpy as np
import scipy.sparse as sp

from ...core.deadline import Deadline
from ...core.errors import InvalidOptionError
from ...core.options import TIME_LIMIT, Option, check_length, read_options
from ...judge.friction_certificate import certified_error

__all__ = ["solve_nsgs", "NSGS", "NSGS_OPTIONS", "R0", "starting_point"]

#: a 3-D block is taken as diag(a, c, c) where its other entries, and the
#: difference of its two tangential ones, are within this of its largest
#: (a sphere's contact block: to 1e-16)
_DIAGONAL_RTOL = 1e-12

#: the starting reactions of the iterative friction methods
R0 = Option("r0", None, "vector", doc="starting reactions, dim entries per contact")

NSGS_OPTIONS = (
    Option("max_sweeps", 10_000, "int", low=0, doc="sweeps at most"),
    Option("check_every", 10, "int", low=1, doc="sweeps between error checks"),
    R0,
    Option("omega", 1.0, "float", low=0.0, high=2.0, low_open=True, high_open=True,
           doc="over-relaxation"),
    Option("local_rtol", 1e-14, "float", low=0.0, low_open=True,
           doc="relative tolerance of the 3-D local problems"),
    Option("max_local", 200, "int", low=1, doc="iterations of a 3-D local problem at most"),
    Option("stall_checks", 100, "int", low=0,
           doc="checks without a better iterate before stopping (0: no such stop)"),
    TIME_LIMIT,
)


def starting_point(method: str, problem, r0):
    """``r0`` as read by read_options, its length checked against
    ``problem`` (dim entries per contact); None stays None."""
    if r0 is None:
        return None
    return check_length(method, "r0", r0, problem.dim * problem.n_contacts)


class NSGS:
    """The sweeps' state on one problem: W by blocks (a 2-D problem's
    off-diagonal 2 x 2 blocks, ``bsr``; a 3-D one's 3 x 3 blocks,
    ``bsr_3d``, formed on first use), its diagonal blocks, the iterate ``r``
    and the sweeps ``done``; ``omega`` over-relaxes each local solution
    (then projected back onto the cone); ``closed_form`` solves the 3-D
    contacts whose block is diag(a, c, c) in closed form ("nsgs"), else the
    local fixed point to ``local_rtol`` (nsgs-newton)."""

    def __init__(self, problem, r0=None, *, omega=1.0, local_rtol=1e-14, max_local=200,
                 closed_form=False):
        d, nc = problem.dim, problem.n_contacts
        if not 0.0 < omega < 2.0:
            raise InvalidOptionError(f"'nsgs': omega must be in (0, 2); got {omega}")
        self.problem = problem
        if d == 2:        # W's 2 x 2 blocks, formed once per problem
            from ._nsgs_kernels import row_sums_2d   # numba: imported where it runs

            self.blocks, *bsr = problem.W_blocks
            self.bsr = tuple(bsr)
            # per contact: b_N when last found open, |W|'s normal row sum, the
            # changes' running sum then (_nsgs_kernels.sweeps_2d)
            self.held = np.zeros((nc, 3))
            self.held[:, 1] = row_sums_2d(bsr[0], bsr[2])
        else:
            # the diagonal blocks gathered in one pass: slicing W per contact
            # cost 9 ms a step on a 120-contact drum pile, more than its sweeps
            W = self.W
            rows = np.repeat(np.arange(W.shape[0]), np.diff(W.indptr))
            own = rows // d == W.indices // d
            self.blocks = np.zeros((nc, d, d))
            self.blocks[rows[own] // d, rows[own] % d, W.indices[own] % d] = W.data[own]
            self.bsr = None
        # 3-D contacts whose block is diag(a, c, c) (spheres) solved in
        # closed form where asked: exact, and a sweep 8 times cheaper than
        # the fixed point at nsgs-newton's local tolerance on the compact
        # piles; nsgs-newton keeps the fixed point, since the restarts'
        # certified rows hang on its path (a closed form there lost a loose
        # pile: docs/dev-notes.md, "Cheaper starts ..." and "Cheaper 3-D
        # sweeps, exact")
        self.closed = np.zeros(nc, bool)
        if closed_form and d == 3:
            from ._nsgs_kernels import diagonal_blocks_3d

            self.closed = diagonal_blocks_3d(self.blocks, _DIAGONAL_RTOL)
        self.omega = float(omega)
        self.local_rtol, self.max_local = float(local_rtol), int(max_local)
        self.done = 0
        self.restart(np.zeros(d * nc) if r0 is None else r0)

    @functools.cached_property
    def W(self):
        """W in CSR, duplicates summed (where the 3-D blocks come from)."""
        W = sp.csr_matrix(self.problem.W)
        W.sum_duplicates()
        return W

    @functools.cached_property
    def bsr_3d(self):
        """W by 3 x 3 blocks (indptr, indices, data), the 3-D sweep's: each
        neighbour's impulse read once for three rows, no test per entry —
        a sweep 1.6 times cheaper than on W's CSR rows at the restarts'
        local tolerance, with the same sums in the same order (the same
        iterates, bit for bit)."""
        B = sp.bsr_matrix(self.W, blocksize=(3, 3))
        B.sort_indices()
        return B.indptr.astype(np.int64), B.indices.astype(np.int64), B.data

    def restart(self, r):
        r = np.array(r, float).ravel()
        size = self.problem.dim * self.problem.n_contacts
        if r.shape != (size,):
            raise InvalidOptionError(f"'nsgs': r0 must have {size} entries; got {r.size}")
        self.r = r
        if self.bsr is not None:      # the 2-D sweep's open contacts, none known yet
            self.held[:, 0] = -1.0
            self.moved = np.zeros(1)

    def sweep(self, n: int) -> np.ndarray:
        p = self.problem
        if self.bsr is not None:     # numba: the kernels imported when a sweep runs
            from ._nsgs_kernels import sweeps_2d
            sweeps_2d(*self.bsr, p.q, p.mu, self.r, self.blocks, int(n), self.local_rtol,
                      self.max_local, self.omega, self.held, self.moved)
        else:
            from ._nsgs_kernels import sweeps_3d
            sweeps_3d(*self.bsr_3d, p.q, p.mu, self.r, self.blocks, self.closed, int(n),
                      self.local_rtol, self.max_local, self.omega)
        self.done += int(n)
        return self.r


def solve_nsgs(problem, tol, options):
    """Nonsmooth Gauss–Seidel (Siconos's NSGS; :mod:`qpcontact._nsgs_kernels`):
    sweeps over the contacts, each solving its local problem with the
    others frozen — exactly: in 2-D by enumeration, in 3-D in closed form
    where the contact's block is diag(a, c, c) (spheres), else by a local
    projected fixed point.  Stops when both error measures are <= tol, or
    when the best error has not improved for ``stall_checks`` checks;
    returns the best iterate.  No convergence guarantee (Coulomb friction is
    not a minimisation): the certificate decides.  Options
    (:data:`NSGS_OPTIONS`): ``max_sweeps`` (10 000), ``check_every`` (10
    sweeps between error checks), ``r0``, ``omega`` (over-relaxation, 1),
    ``local_rtol`` (1e-14), ``max_local`` (200 local iterations),
    ``stall_checks`` (100; 0: sweep to ``max_sweeps`` or the time limit, as
    Siconos's NSGS does), ``time_limit`` (s)."""
    opts = read_options("nsgs", options, NSGS_OPTIONS)
    max_sweeps, every, time_limit = opts["max_sweeps"], opts["check_every"], opts["time_limit"]
    local = {key: opts[key] for key in ("local_rtol", "max_local", "omega")}
    stall = opts["stall_checks"]
    r0 = starting_point("nsgs", problem, opts["r0"])
    deadline = Deadline(time_limit)
    gs = NSGS(problem, r0, closed_form=True, **local)
    best, best_r, since = np.inf, gs.r.copy(), 0
    why = f"stopped at {max_sweeps} sweeps"
    while gs.done < max_sweeps:
        r = gs.sweep(every)
        err = certified_error(problem, r)
        if err < best:
            best, best_r, since = err, r.copy(), 0
        else:
            since += 1
        if best <= tol:
            why = "reached the tolerance"
        elif stall and since >= stall:
            why = f"stalled (no better iterate in {stall} checks)"
        elif not np.all(np.isfinite(r)):
            why = "stopped: the iterate is no longer finite"
        elif deadline.expired():
            why = f"stopped at its time limit of {time_limit:.3g} s"
        else:
            continue
        break
    return best_r, "solved" if best <= tol else "stopped", \
        f"NSGS {why} after {gs.done} sweeps", {"iterations": gs.done}
