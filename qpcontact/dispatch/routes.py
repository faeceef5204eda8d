"""Which method applies to which problem, and the conversions on the way.

An LCP goes to a QP backend as its QP (symmetric M) or its monotone QP
(M + M' PSD), Jacobi-scaled; a QP goes to a pivoting method as its dual LCP;
a frictional problem goes to an LCP method as its faceted LCP.  What "auto"
tries, in order, per kind is here too.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from ..core.conversions import is_qp
from ..core.errors import NotConvexError, NotSymmetricError
from ..core.linalg import BANDED_MAX
from ..core.options import PROGRESS, read_options
from ..core.problems import LCP, ParametricLCP
from ..core.friction_problem import FrictionProblem
from ..solvers.method import Method

if TYPE_CHECKING:
    from qpsolvers import Problem

__all__ = ["AUTO_ORDER", "AUTO_DENSE_LIMIT", "AUTO_CHAIN", "GLOBAL_CHAIN",
           "LEMKE_FIRST_MAX_CONTACTS", "NSGS_FIRST_3D", "PROGRESS_LINKS", "auto_progress",
           "link_options", "link_share", "SHARES_2D", "SWEEPS_LARGE_2D",
           "SHARE_SWEEPS_LARGE_2D", "SHARE_RESTARTS_3D",
           "auto_order", "auto_chain", "kind_of",
           "lower_bounds_only", "jacobi_scaled", "check_applicable", "applicable", "data_range"]

#: Preference of ``method="auto"``: exact pivoting first where it applies (the
#: reference the others are judged against; docs/guide.md, docs/backends.md),
#: then the QP backends in the order that reached "high"
#: fastest in benchmarks/backends.py on this machine class (docs/backends.md).
#: "auto" tries them in turn until one is certified.
#: "enumeration" (n <= 16) follows Lemke: a general M's secondary ray proves
#: nothing, and all 2^n bases of a small LCP cost at most about a second.
#: Measured (docs/backends.md): PIQP reached "high" fastest at n = 100, 1000 and
#: 20 000 but stops at ~2e-7 on degenerate problems, where polished OSQP is exact.
AUTO_ORDER = ("energy", "bpp", "lemke", "enumeration", "piqp", "osqp", "clarabel", "daqp", "proxqp",
              "highs", "quadprog", "scs", "cvxpy:CLARABEL")


#: "auto" on a sparse SPD LCP (checked by the driver: a method whose
#: requirement fails is skipped) goes by structure, measured on this 2-core
#: machine (docs/pivoting.md, "Routing"; ratios to one LDLᵀ of the final
#: free block):
#:
#: * banded (bandwidth <= 16: contact chains, stacks): "bpp" first — 3-4
#:   exchanges, each a banded Cholesky (n = 3000: 2 ms, where "energy", first
#:   in AUTO_ORDER, densified the matrix and took 13 s);
#: * otherwise (meshes), from AUTO_MG_MIN unknowns: "mg-bpp" first where M is
#:   a Z-matrix (off-diagonal entries <= 0: a membrane, any M-matrix
#:   stiffness; n = 1e4: 2.8-3.3 x, ip-bpp 11-23 x, bpp 16-17 x);
#: * M with off-diagonal entries of both signs (a plate's 13-point
#:   operator) goes to "mg-bpp" only with a hierarchy of its own (the mesh's
#:   grids, ``LCP(..., hierarchy=)``), at every size (n = 1e4, fourteen
#:   plates: mg-bpp 3.2-17.6 x, ip-bpp 9.9-118 x, bpp 23-640 x; 4e4: mg-bpp
#:   ahead on 10 of 10; 1e5, seven shapes after the coarse operators were
#:   kept current: mg-bpp 6.5-17.7 s, ip-bpp 29-149 s or killed at 200 s —
#:   docs/pivoting.md; until then ip-bpp took plates above 50 000 unknowns,
#:   where mg-bpp had not finished the dome in 150 s).  Without one,
#:   mg-bpp would coarsen by smoothed aggregation, which is built for
#:   M-matrices (its prolongation is nonnegative only there): on plates
#:   built without a hierarchy it took 56-66 x at n = 3600 where bpp took
#:   17-31 x, and 503 x (1282 exchanges) on a dome at 1e4 where ip-bpp
#:   took 43 x.  Those go to "bpp" below AUTO_BPP_MAX unknowns (n = 3600,
#:   twelve plates: geometric mean 28 x, ip-bpp 47 x) and to "ip-bpp"
#:   above (n = 1e4: 44 x against bpp's 66 x, whose exchanges grow with the
#:   grid: 182 x on a dome);
#: * a QP whose only constraints are lower bounds (the mixed problem of
#:   finite-element contact): "ip-bpp" first;
#: * a dense LCP of AUTO_DENSE_BPP_MIN unknowns or more: "bpp" first, then
#:   the plain order ("energy" next where bpp misses).  A dense SPD LCP
#:   needs 3-5 block exchanges (20-24 at condition 1e8), each one Cholesky
#:   of the free block, where energy's ~n/2 principal pivots cost O(n²)
#:   each: CPU, one thread, random SPD M, bpp against energy: n = 100
#:   1.0/2.0 ms, 400 11.8/23.2 ms, 800 60/151 ms, 3000 1.7/11.8 s (what
#:   "auto" took then); condition 1e8: 1.8/2.4, 22/31, 79/189 ms.  Below
#:   it the order is the one the hard cases were measured with.
AUTO_MG_MIN = 1000
AUTO_DENSE_BPP_MIN = 100
AUTO_BPP_MAX = 5000


# Dense-only backends densify sparse input; beyond this size that costs more
# than it is worth for "auto" (an explicit method name is always honoured).
AUTO_DENSE_LIMIT = 3000


#: what "auto" tries, in order, per dimension: each answer is certified before
#: the next is tried, and the first certified one is returned
AUTO_CHAIN = {2: ("lemke", "nsgs-newton", "desaxce-fp", "newton"),
              3: ("desaxce-fp", "newton", "nsgs-newton", "tresca-fp")}
#: "auto" on a global problem kept without W
GLOBAL_CHAIN = ("desaxce-global",)

#: above this many contacts "auto" tries NSGS + Newton first in 2-D: Lemke's
#: pivots grow with the contacts (the 2020-contact granular file: 5461
#: pivots, 4 s; a 10 000-contact pile: not done in 15 minutes) while NSGS +
#: Newton takes seconds where it converges
LEMKE_FIRST_MAX_CONTACTS = 200

#: in 3-D from this many contacts: De Saxcé's SOCPs grow with the pile (a
#: 540-contact sphere pile: 28 SOCPs, stalled at 9.5e-4), while below it
#: De Saxcé then Newton is the faster route on the shared files (the
#: 225-contact Capsules-i101: NSGS + Newton stalls at 7.8e-7 there)
NSGS_FIRST_3D = 500

#: the methods of "auto"'s chains that report each iteration to ``progress``
#: ("auto" hands it to these only: the others refuse the option)
PROGRESS_LINKS = ("nsgs-newton", "nsgs-restarts", "newton", "desaxce-fp", "tresca-fp",
                  "desaxce-global", "mg-bpp", "ip-bpp")


def auto_progress(options: dict) -> tuple[dict, object]:
    """"auto"'s options without ``progress``, and ``progress`` checked (a
    callable or None): "auto" hands it only to the links that report their
    iterations (:func:`link_options`) — passed on to every link, Lemke
    refused it mid-chain."""
    options = dict(options)
    progress = read_options("auto", {"progress": options.pop("progress", None)},
                            (PROGRESS,))["progress"]
    return options, progress


def link_options(options: dict, name: str, progress, share) -> dict:
    """One link's options: ``options``, with ``progress`` where the link is
    one of PROGRESS_LINKS, and a line to ``progress`` saying the link starts
    (with up to ``share`` seconds)."""
    opts = dict(options)
    if progress is not None:
        if name in PROGRESS_LINKS:
            opts["progress"] = progress
        progress(f"auto: {name}" + ("" if share is None else f" (up to {share:.3g} s)"))
    return opts


def auto_chain(problem) -> tuple:
    """The methods "auto" tries on ``problem``, in order."""
    if not problem.is_reduced:
        return GLOBAL_CHAIN
    chain = AUTO_CHAIN[problem.dim]
    if _sweeps_first(problem):
        # in 3-D NSGS + Newton from zero, then from random reactions within
        # the cones (nsgs-restarts, most of the time: link_share): where the
        # sweeps stall on a compact pile depends on where they start
        # (docs/dev-notes.md, "The 3-D compact piles by restarts"); then
        # Newton from the best point; De Saxcé's SOCPs stall on piles (9.5e-4
        # at 540 contacts).  In 2-D the interior point on the exact LCP next
        # (link_share): it certifies dense piles where the sweeps stall
        head = ("nsgs-newton", "ip-lcp") if problem.dim == 2 else ("nsgs-restarts", "newton")
        chain = head + tuple(m for m in chain if m not in head)
    return chain


#: the shares of the time left that "auto" gives a 2-D chain's first two
#: links above LEMKE_FIRST_MAX_CONTACTS (the others: half, the last all):
#: NSGS + Newton certifies loose piles and the collection's granular files in
#: 0.01-2.3 s and otherwise stalls (the 1 941-contact compact pile: 2.4e-5
#: after its 30 s); ip-lcp's path past its folds takes 16-32 s of CPU there
#: (docs/dev-notes.md, "Dense 2-D piles by interior point")
SHARES_2D = {"nsgs-newton": 0.1, "ip-lcp": 0.8}
#: from this many contacts a 2-D chain gives nsgs-newton half of the time left
#: (SHARE_SWEEPS_LARGE_2D, every other link's default) instead of a tenth: there
#: ip-lcp's path does not end within the budget (the 9 842-contact compact
#: piles: over 2 000 path steps, 110 s of CPU, not done), while NSGS + Newton
#: certifies some of them after 14 140 and 23 840 sweeps (7-10 s of CPU, seeds 0
#: and 5; a tenth of 60 s gave 11 000-13 700 on the shared machine) and stops by
#: itself on the others within 5-9 s; the 4 874-contact piles, where ip-lcp
#: certifies within its share, keep a tenth (docs/dev-notes.md, "The 9 842-contact
#: 2-D piles by contact states and LPs")
SWEEPS_LARGE_2D = 8000
SHARE_SWEEPS_LARGE_2D = 0.5
#: the share of the time left that "auto" gives nsgs-restarts in a 3-D chain
#: from NSGS_FIRST_3D contacts: each start on the 540-contact compact piles
#: takes 1.5-5.3 s of CPU and certifies some seeds a first start misses; Newton
#: from the best point gets half of the rest, and De Saxcé's and Tresca's
#: SOCPs, which certified none of those piles, what is left (docs/dev-notes.md,
#: "Dense piles: where every iterative route stops")
SHARE_RESTARTS_3D = 0.8


def link_share(problem, name: str, last: bool) -> float:
    """The fraction of the time left that "auto" gives its link ``name``."""
    if last:
        return 1.0
    if problem.dim == 2 and _sweeps_first(problem):
        if name == "nsgs-newton" and problem.n_contacts >= SWEEPS_LARGE_2D:
            return SHARE_SWEEPS_LARGE_2D
        return SHARES_2D.get(name, 0.5)
    if name == "nsgs-restarts":
        return SHARE_RESTARTS_3D
    return 0.5


def _sweeps_first(problem) -> bool:
    """Whether "auto"'s chain for a reduced problem starts with NSGS + Newton
    (above LEMKE_FIRST_MAX_CONTACTS contacts in 2-D, from NSGS_FIRST_3D in 3-D)."""
    first = LEMKE_FIRST_MAX_CONTACTS + 1 if problem.dim == 2 else NSGS_FIRST_3D
    return problem.n_contacts >= first


def kind_of(problem) -> str:
    """The problem's kind, as :attr:`Method.problems` names it."""
    if isinstance(problem, LCP):
        return "lcp"
    if is_qp(problem):
        return "qp"
    if isinstance(problem, ParametricLCP):
        return "parametric-lcp"
    if isinstance(problem, FrictionProblem):
        if not problem.is_reduced:
            return "friction-global"
        return f"friction-{problem.dim}d"
    raise TypeError(f"not a problem qpcontact solves: {type(problem).__name__}")


def auto_order(problem) -> tuple:
    if isinstance(problem, LCP):
        first = _lcp_first(problem)
        return first + tuple(m for m in AUTO_ORDER if m not in first)
    if is_qp(problem) and lower_bounds_only(problem):
        return ("ip-bpp",) + AUTO_ORDER
    return AUTO_ORDER


def _lcp_first(problem: LCP) -> tuple:
    """The exact methods "auto" puts first for this LCP's structure (see
    AUTO_MG_MIN)."""
    if not problem.is_sparse:
        return ("bpp",) if problem.n >= AUTO_DENSE_BPP_MIN else ()
    if problem.n < 100:
        return ()
    structure = problem.structure
    if structure.bandwidth <= BANDED_MAX or problem.n < AUTO_MG_MIN:
        return ("bpp",)
    if structure.is_z_matrix:
        return ("mg-bpp",)
    if structure.hierarchy is not None:
        return ("mg-bpp",)
    return ("bpp",) if problem.n < AUTO_BPP_MAX else ("ip-bpp",)


def lower_bounds_only(problem: Problem) -> bool:
    return (problem.G is None and problem.A is None and problem.lb is not None
            and (problem.ub is None or not np.isfinite(problem.ub).any()))


def jacobi_scaled(lcp: LCP):
    """(LCP(DMD, Dq), d) with D = diag(M)^-1/2 (1 where M_ii = 0: such rows
    of a monotone M carry no quadratic term), or (lcp, None) when a diagonal
    entry is negative or the diagonal is already all ones.

    The QP handed to a backend is the LCP's scaled form, z = D y.  Backends
    stop on *absolute* residuals; in physical units (a compliance of 1e-9 m/N
    against forces of 1e4 N) their tolerances mean nothing.  Measured on the
    drum's step problems: OSQP at "high" certified 15 of 80 steps unscaled and
    80 of 80 scaled (docs/drum.md).  The certificate is always computed on the
    original problem.
    """
    M = lcp.M
    diag = np.asarray(M.diagonal(), dtype=float)
    if np.any(diag < 0):
        return lcp, None
    d = np.ones_like(diag)
    d[diag > 0] = 1.0 / np.sqrt(diag[diag > 0])
    if np.all(d == 1.0):
        return lcp, None
    with np.errstate(over="ignore", invalid="ignore"):
        if sp.issparse(M):
            D = sp.diags(d)
            Ms = (D @ M @ D).tocsc()
            finite = np.all(np.isfinite(Ms.data))
        else:
            Ms = (M * d[:, None]) * d[None, :]
            finite = np.all(np.isfinite(Ms))
        qs = lcp.q * d
    if not (finite and np.all(np.isfinite(qs))):
        return lcp, None
    if lcp.is_symmetric:
        Ms = 0.5 * (Ms + Ms.T)  # keep exact symmetry for the QP route
    scaled = LCP(Ms, qs)
    if lcp.structure.__dict__.get("is_positive_definite"):
        scaled.structure.declare_spd()   # D M D is congruent to M: no second factorization
    return scaled, d


def check_applicable(lcp: LCP, m: Method) -> None:
    if m.requires == "spd":
        if not lcp.is_symmetric:
            raise NotSymmetricError(
                f"method {m.name!r} needs a symmetric positive definite M and M is not symmetric; "
                "use 'lemke', which accepts any M."
            )
        if not lcp.is_positive_definite:
            raise NotConvexError(
                f"method {m.name!r} needs a positive definite M and M is not; use 'lemke'."
            )
    elif m.requires == "monotone" and not lcp.is_psd:
        if lcp.is_symmetric:
            raise NotConvexError(
                f"M is symmetric but not positive semidefinite, so the QP min ½z'Mz + q'z, z >= 0 "
                f"is nonconvex and {m.name!r} (a QP backend) may return a local minimum. "
                "Use a pivoting method such as 'lemke'."
            )
        raise NotSymmetricError(
            f"M is not symmetric and M + M' is not positive semidefinite, so no convex QP has "
            f"this LCP's solutions as minimisers and {m.name!r} (a QP backend) cannot solve it. "
            "Use a pivoting method such as 'lemke'."
        )


def applicable(problem, m: Method) -> bool:
    """Whether "auto" (and cross-validation) should try ``m`` on ``problem``:
    it solves the problem's kind, within its size limit, without a refusal
    the data already decide (an M its route needs definite, a dense copy of a
    large sparse problem)."""
    kind = kind_of(problem)
    if not m.solves(kind):
        return False
    if kind not in ("lcp", "qp"):
        if m.takes != "lcp":
            return True
        # the faceted LCP: normal, facet and slip unknowns per contact
        facets = 2 if problem.dim == 2 else 8
        return m.max_n is None or (2 + facets) * problem.n_contacts <= m.max_n
    if m.max_n is not None and (problem.n if isinstance(problem, LCP) else
                                problem.P.shape[0]) > m.max_n:
        return False
    if isinstance(problem, LCP):
        try:
            check_applicable(problem, m)
        except (NotSymmetricError, NotConvexError):
            return False
        n, sparse = problem.n, problem.is_sparse
    else:
        if m.takes == "lcp":
            return False  # QP -> dual LCP is dense; "auto" keeps QPs on QP backends
        if m.constraints == "lower-bounds" and not lower_bounds_only(problem):
            return False
        n, sparse = problem.P.shape[0], problem.has_sparse
    return m.accepts_sparse or not sparse or n <= AUTO_DENSE_LIMIT


def data_range(problem) -> tuple[float, float]:
    """(smallest nonzero, largest) |entry| of an LCP's or a QP's data."""
    parts = [problem.M, problem.q] if isinstance(problem, LCP) else list(problem.unpack())
    vals = []
    for part in parts:
        if part is None:
            continue
        v = part.data if sp.issparse(part) else np.asarray(part, dtype=float).ravel()
        v = np.abs(v[np.isfinite(v) & (v != 0)])
        if v.size:
            vals.append((v.min(), v.max()))
    if not vals:
        return 0.0, 0.0
    return min(a for a, _ in vals), max(b for _, b in vals)
