"""``"lemke"``: Lemke's complementary pivoting method for LCP(M, q), any M.

Revised (basis-inverse) form of ``w - M z - d z0 = q`` with the covering vector d > 0
(default e): z0 enters at the value that makes q + d z0 >= 0, and from then on
the complement of the variable that just left enters.  The ratio test is
lexicographic (rows of the basis inverse), so degenerate problems cannot cycle; ties are resolved in
favour of z0 leaving.  The method ends

- ``solved``: z0 left the basis, the basis is complementary.  The basic values
  are then recomputed from the active block M_FF (LU with iterative refinement)
  and the better-certified of the two points is returned;
- ``ray``: the entering column has no positive entry (a secondary ray).  When M
  is copositive-plus (e.g. positive semidefinite) this means the LCP has no
  solution (Cottle, Pang & Stone 1992, Thm 4.4.13) — in exact arithmetic.  For
  other M it means nothing, so the method restarts with other covering vectors
  (``restarts``, seeded) before reporting the ray.  "No solution" is claimed
  only with a Farkas vector checked from the data in exact rational
  arithmetic (found by :func:`qpcontact.proofs.lcp_farkas.feasibility`'s LP, checked
  by :func:`qpcontact.proofs.lcp_farkas.check_farkas_hint`); one that holds only to
  rounding is reported as such, with nothing proved;
- ``max_pivots``: the pivot limit was reached.

The LCP is solved after row/column equilibration (w' = D_r w, z = D_c z'), which
keeps complementarity and makes sign tolerances meaningful for badly scaled data
(stiffness 1e8 next to loads of 1).  Cost: a dense n x n basis inverse, O(n²)
per pivot, up to DENSE_TABLEAU_LIMIT unknowns.  A sparse M from SPARSE_FROM
unknowns, and any M above DENSE_TABLEAU_LIMIT, goes to the sparse revised form
(:mod:`.lemke_sparse`: SuperLU and product-form updates) — on the 2668-unknown
LCP of a 667-contact granular file it takes 1413 pivots (7 s) where the dense
form took 44 000 pivots (529 s) to a secondary ray.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from ...core.deadline import Deadline
from ...core.linalg import ActiveBlock, SolutionOverflow, dense_matrix, ruiz_scaling
from ...core.options import BySize, Option, check_length, read_options
from ...core.results import MethodResult
from ...judge.scales import ComponentScales
from ...proofs.lcp_farkas import check_farkas_hint, feasibility
from .active_set import DENSE_TABLEAU_LIMIT, overflow_result, sign_tolerances
from .lemke_sparse import SingularBasis, sparse_lemke
from .lemke_tableau import lemke

__all__ = ["run_lemke", "SPARSE_FROM", "DENSE_FALLBACK_MAX", "LEMKE_OPTIONS"]

LEMKE_OPTIONS = (
    Option("covering", None, "vector", low=0.0, low_open=True,
           doc="the covering vector d, n positive numbers (default: scaled ones)"),
    Option("max_pivots", BySize(lambda n: max(10_000, 50 * n), "max(10 000, 50 n)"), "int",
           low=0, doc="pivots at most, per start"),
    # 3 left 8 of 430 equilibria of random frames (friction) and 38 of 723
    # Stewart-Trinkle LCPs on a secondary ray; 10 found all the frames', 8-33 the
    # others'.  Restarts cost only when a ray is met.
    Option("restarts", 30, "int", low=0,
           doc="restarts with a random covering vector after a secondary ray"),
    Option("seed", 0, "int", low=0, none_ok=True,
           doc="the restarts' random seed (None: fresh randomness)"),
)


def _sign_errors(lcp, M, z, basic_z) -> bool:
    """Whether z (nonbasic entries 0) leaves a nonbasic w negative or a basic
    w nonzero beyond the sign tolerances (each on its own row's scale)."""
    _, tau_w = sign_tolerances(ComponentScales(M, lcp.q_terms, lcp.matrix_scale), z)
    w = M @ z + lcp.q
    return bool(np.any(w[~basic_z] < -tau_w[~basic_z])
                or np.any(np.abs(w[basic_z]) > tau_w[basic_z]))


def _refined(lcp, M: np.ndarray, z_tab: np.ndarray, basic_z: np.ndarray) -> np.ndarray:
    """z recomputed from the active block M_FF (LU, refined) when its signs are
    right; the tableau's z otherwise (a singular or degenerate block)."""
    q = lcp.q
    try:
        with warnings.catch_warnings():
            # a singular basis (degenerate, or M_FF singular) keeps the tableau's z
            warnings.simplefilter("error", scipy.linalg.LinAlgWarning)
            z, w = ActiveBlock(M, basic_z, symmetric=False).basic_solution(M, q, refine=2)
    except (np.linalg.LinAlgError, scipy.linalg.LinAlgWarning, SolutionOverflow):
        return z_tab
    tau_z, tau_w = sign_tolerances(ComponentScales(M, lcp.q_terms, lcp.matrix_scale), z)
    if np.all(z[basic_z] >= -tau_z[basic_z]) and np.all(w[~basic_z] >= -tau_w[~basic_z]):
        return np.maximum(z, 0.0)
    return z_tab


#: the shifts ε of the regularised ladder (relative to the equilibrated M's unit entries)
REGULARISED_SHIFTS = tuple(10.0 ** -k for k in range(1, 13))


def _regularised(problem, M, Ms, qs, cs, max_pivots, deadline=None):
    """After every covering vector ended on a secondary ray: Lemke on M + εI
    for ε = 1e-1 ... 1e-12, each final basis tried on M itself (z_F from
    M_FF, refined); the first that solves M itself to rounding is kept.
    For a copositive M (the Stewart-Trinkle friction LCP) M + εI is strictly
    copositive, so Lemke ends with a solution there (Cottle, Pang & Stone
    1992, Thm 3.8.5), and the bases of the shifted problems approach one of
    M's as ε falls.  Measured on qpcontact stress's friction family (n = 8,
    30, 100; 30 seeds each, scaled over up to 12 decades): 7 of the 29 rays
    left after 30 covering vectors solved exactly.  Returns (z, pivots, ε)
    or None."""
    from ...judge.lcp_certificate import certify_lcp

    n, pivots = problem.n, 0
    eye = np.eye(n)
    for eps in REGULARISED_SHIFTS:
        out = lemke(Ms + eps * eye, qs, np.ones(n), max_pivots, deadline)
        pivots += out.pivots
        if out.status != "solved":
            continue
        z = _refined(problem, M, out.z * cs, out.basic_z)
        # only a basis that solves M itself, to rounding: an ε-solution
        # (w_F = -ε z_F where M_FF is singular) changes entries of M that are
        # zero — the diagonal of a friction-cone row — which no relative
        # perturbation of the data does (stress: "solved" at "low" with w =
        # -7e-11 on a row whose own terms sum to 7e-11)
        if np.all(np.isfinite(z)) and certify_lcp(problem, z).error <= _EXACT_LEVEL:
            return z, pivots, eps
    return None


#: a regularised basis is kept when it solves M to this backward error
_EXACT_LEVEL = 1e3 * np.finfo(float).eps


#: From this many unknowns a sparse M goes to the sparse revised form
#: (:mod:`.lemke_sparse`); above DENSE_TABLEAU_LIMIT every M does.  Measured
#: (benchmarks/lemke_sparse.py, membranes on k x k meshes): sparse / dense
#: time 1.8 at n = 400, 0.59 at 900, 0.07 at 2500.
SPARSE_FROM = 700


#: Up to this many unknowns an uncertified sparse-form answer is retried by
#: the dense form (run_lemke).  Its cost bounds it: on the 4050-unknown LCP
#: of Capsules-i101 faceted by 16 directions the sparse form ends in 1.2 s,
#: the dense form in 31 s (then on a ray) — and with its 30 restarts it had
#: run past 10 minutes; on n <= 100 it costs milliseconds.
DENSE_FALLBACK_MAX = 2000


def run_lemke(problem, tol, options, time_limit=None) -> MethodResult:
    """The "lemke" method: the sparse form for a sparse M from SPARSE_FROM
    unknowns and any M above DENSE_TABLEAU_LIMIT, the dense form otherwise.
    Where the sparse form's answer misses tol and n <= DENSE_FALLBACK_MAX,
    the dense form runs too (one covering vector) and the better certified
    answer is returned: its exact per-row scales decide ties that the sparse
    form's estimates miss on badly scaled data (qpcontact stress's LCP
    families, n <= 100, forced sparse: 2 of 390 certified by the dense form
    only, both with gaps over 1e0..1e12).  ``time_limit`` (s, from
    :func:`qpcontact.solve`) bounds both forms, checked at each pivot (the
    dense form's pivot cap alone let a 1000-span frame's 3003-unknown LCP,
    restarting on secondary rays, run for over 12 minutes).  Options
    (:data:`LEMKE_OPTIONS`): ``covering``, ``max_pivots`` (max(10 000, 50 n)),
    ``restarts`` (30), ``seed`` (0)."""
    from ...core.accuracy import DEFAULT_CERTIFY_TOL
    from ...judge.lcp_certificate import certify_lcp

    n = problem.n
    options = read_options("lemke", options, LEMKE_OPTIONS, size=n)
    deadline = Deadline(time_limit)
    if not (n > DENSE_TABLEAU_LIMIT or (problem.is_sparse and n >= SPARSE_FROM)):
        return _run_lemke(problem, options, sparse=False, deadline=deadline)
    res = _run_lemke(problem, options, sparse=True, deadline=deadline)
    if n > DENSE_FALLBACK_MAX or res.status == "time_limit":
        return res
    tol = DEFAULT_CERTIFY_TOL if tol is None else tol
    error = certify_lcp(problem, res.x).error if res.x is not None else np.inf
    if error <= tol:
        return res
    dense = _run_lemke(problem, dict(options, restarts=0), sparse=False, deadline=deadline)
    dense.iterations = (dense.iterations or 0) + (res.iterations or 0)
    dense.stats["sparse_form"] = {"status": res.status or res.backend_status,
                                  "pivots": res.iterations}
    if dense.x is None or error <= certify_lcp(problem, dense.x).error:
        res.stats["dense_form_tried"] = True
        return res
    return dense


def _run_lemke(problem, options, sparse: bool, deadline: Deadline) -> MethodResult:
    n = problem.n
    M = sp.csc_matrix(problem.M) if sparse else dense_matrix(problem.M)
    q = problem.q
    d_user = options["covering"]
    if d_user is not None:
        d_user = check_length("lemke", "covering", d_user, n)
    max_pivots, restarts, seed = options["max_pivots"], options["restarts"], options["seed"]
    rng = None

    diag = M.diagonal()
    if problem.is_symmetric and np.all(diag > 0):
        # symmetric (Jacobi) scaling in powers of two: exact, and it keeps M
        # symmetric PSD, which Ruiz's separate row and column factors do not.
        # Measured (qpcontact stress, the hard cases): on SPD M scaled over 12
        # decades with cond 1e8, Ruiz left 18 of 240 on a false ray or
        # uncertified; Jacobi none
        rs = cs = 2.0 ** -np.round(0.5 * np.log2(diag))
    else:
        rs, cs = ruiz_scaling(M)
    if (rs == 1).all() and (cs == 1).all():
        Ms = M
    elif sparse:
        Ms = sp.csc_matrix(sp.diags(rs) @ M @ sp.diags(cs))
    else:
        Ms = M * rs[:, None] * cs[None, :]
    qs = q * rs
    if not (np.all(np.isfinite(Ms.data if sparse else Ms)) and np.all(np.isfinite(qs))):
        return overflow_result("lemke", "the equilibrated data overflow")
    d = np.ones(n) if d_user is None else d_user
    total = 0
    tried = []
    proof = None
    while True:
        if sparse:
            try:
                out = sparse_lemke(Ms, qs, d * rs, max_pivots, deadline)
            except SingularBasis as exc:
                return MethodResult(x=None, backend_status="singular_basis",
                                    backend_message=f"SuperLU found a basis singular ({exc})",
                                    iterations=total, stats={"pivots": total})
        else:
            out = lemke(Ms, qs, d * rs, max_pivots, deadline)
        total += out.pivots
        tried.append(d)
        # A ray proves infeasibility for copositive-plus M in exact arithmetic;
        # otherwise another covering vector may well find a solution (CPS
        # Example 4.4.23).  For PSD M a ray is still only a numerical failure
        # when a feasible point exists (a 2 x 2 SPD M with cond 1e8 and both
        # pairs degenerate ended on one; another covering vector solved it).
        if out.status != "ray" or len(tried) > restarts:
            break
        if problem.is_psd:
            if proof is None:
                proof = feasibility(M, q, rs, cs, deadline)
            if proof[0] is False:
                break
        rng = rng or np.random.default_rng(seed)
        d = 0.5 + rng.random(n)
    stats = {"pivots": total, "last_run_pivots": out.pivots, "covering_vectors_tried": len(tried)}
    if out.status == "ray" and not sparse and not problem.is_psd:
        found = _regularised(problem, M, Ms, qs, cs, max_pivots, deadline)
        if found is not None:
            z, pivots, eps = found
            stats.update(pivots=total + pivots, regularised=eps)
            return MethodResult(x=z, backend_status="solved", iterations=total + pivots,
                                stats=stats)
    if out.status == "solved":
        z = out.z * cs
        if not np.all(np.isfinite(z)):
            return overflow_result("lemke", "the solution has entries beyond 1.8e308")
        # Always recomputed from the final basis (one LU of M_FF, refined):
        # the tableau's z carries the rounding of every pivot — 3e-8 on 2 x 2
        # SPD blocks of cond 1e8 (qpcontact stress), below the sign
        # tolerances but above "high".
        if not sparse:   # the sparse form already refactors and refines at the end
            z = _refined(problem, M, z, out.basic_z)
        return MethodResult(x=z, backend_status="solved", iterations=total, stats=stats)
    if out.status == "time_limit":
        return MethodResult(x=None, status="time_limit", backend_status="time_limit",
                            backend_message=f"stopped at the time limit after {total} pivots",
                            iterations=total, stats=stats)
    if out.status == "max_pivots":
        return MethodResult(x=None, status="max_pivots", backend_status="max_pivots",
                            backend_message=f"pivot limit {max_pivots} reached", iterations=total,
                            stats=stats)
    ray = out.ray
    stats["ray"] = {"z": ray["z"] * cs, "dz": ray["dz"] * cs, "z0": ray["z0"], "dz0": ray["dz0"]}
    feasible, evidence = (proof if proof is not None
                          else feasibility(M, q, rs, cs, deadline))
    stats["feasible"] = feasible
    stats.update(evidence)
    monotone = problem.is_psd
    exact = None
    if feasible is False:
        # the LP's vector holds to 1e-12 of each component's terms; only the
        # rational check makes it a proof (on an exactly positive definite M
        # within rounding of a singular one it held to 1e-12 and failed exactly)
        exact = check_farkas_hint(M, q, evidence["farkas"], deadline)
    if exact is not None:
        stats["proof"] = exact
        why = ("no solution exists: no z >= 0 has Mz + q >= 0 (a Farkas vector y >= 0 with "
               "M'y <= 0 and q'y < 0, stats['farkas'], checked from the data in exact rational "
               "arithmetic)")
    elif feasible is False:
        why = ("Lemke's method ended on a secondary ray, and a Farkas vector (stats['farkas']) "
               "holds to rounding — each component to 1e-12 of its own terms — but not in exact "
               "arithmetic: the data are within rounding of a problem with no solution, and "
               "whether these data have one is not proved")
    elif monotone and feasible:
        why = ("Lemke's method ended on a secondary ray although M is positive semidefinite and "
               "a feasible z exists (stats['point']), so a solution exists: a numerical failure "
               "(the data may be too badly scaled); try a QP backend or rescale the data")
    elif monotone:
        why = ("M is positive semidefinite (copositive-plus), so in exact arithmetic Lemke's "
               "secondary ray means no solution exists; no Farkas vector could be checked from "
               "the data, so this is not proved")
    else:
        why = (f"Lemke's method ended on a secondary ray with {len(tried)} covering vector(s); "
               "for this M that does not prove there is no solution (the feasible set is "
               f"{'nonempty' if feasible else 'of unknown emptiness'}); try other covering vectors "
               "(option covering=) or 'enumeration' (n <= 16)")
    stats["proved_infeasible"] = exact is not None
    return MethodResult(x=None, status="ray", backend_status="ray", backend_message=why,
                        iterations=total, stats=stats)
