"""Test helpers for projects whose code produces LCPs and QPs (and for qpcontact's own tests).

Assertions
----------
:func:`assert_lcp_solution` and :func:`assert_qp_kkt` check a candidate
answer against the problem data with qpcontact's componentwise measure
(docs/certificates.md): every condition — z >= 0, w = Mz + q >= 0,
complementarity; stationarity, feasibility, multiplier signs — is judged
against its *own* row's scale, so a force of 1 N beside one of 1e9 N is held
to 1 N's digits.  On failure the message names the condition, the index, the
raw residual and the scale it was judged on::

    AssertionError: LCP solution fails w = Mz + q >= 0 at index 3: w_3 = -2.000e-04,
    judged against its row's scale 1.000e+00 (|q_3| + (|M||z|)_3): error 2.0e-04 > tol 1e-09

Cross-validation
----------------
:func:`cross_validate` solves one problem with several methods (the exact
pivoting ones and the QP backends), certifies each, and raises
:class:`CrossValidationError` when certified answers disagree where the
solution is unique — by more than the answers' own forward-error estimates
allow.  Where it is not unique (a singular PSD M, a QP with a singular P) it
compares what is unique instead (w = Mz + q, the optimal value) and says so
in the report.

Strategies and the pytest plugin
--------------------------------
:mod:`qpcontact.testing.strategies` holds hypothesis strategies for hard LCPs
and QPs with a known answer or status built in (``pip install
"qpcontact[test]"`` for hypothesis).  :mod:`qpcontact.testing.plugin` is a
pytest plugin, registered on install: a ``qp_method`` fixture parametrised
over the installed methods and a ``--qp-methods`` command-line option.

Problem families
----------------
The seeded generators of :mod:`qpcontact.testing.problems` (``random_spd_lcp``,
``far_contact_lcp``, ``spread_lcp``, ``planted_ok``) are re-exported here.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from qpsolvers import Problem

from ..judge.scales import ComponentScales
from ..judge.lcp import certify_lcp
from ..judge.qp import certify_qp
from ..core.errors import InvalidProblemError
from ..core.problems import LCP
from ..cases.families import far_contact_lcp, planted_ok, random_spd, random_spd_lcp, spread_lcp

__all__ = ["assert_lcp_solution", "assert_qp_kkt", "cross_validate", "CrossValidation",
           "CrossValidationError", "random_spd", "random_spd_lcp", "far_contact_lcp",
           "spread_lcp", "planted_ok"]

_EPS = np.finfo(float).eps


def _as_lcp(lcp) -> LCP:
    if isinstance(lcp, LCP):
        return lcp
    if isinstance(lcp, tuple) and len(lcp) == 2:
        return LCP(*lcp)
    raise InvalidProblemError(f"expected an LCP or a tuple (M, q); got {type(lcp).__name__}")


def assert_lcp_solution(lcp, z, tol: float = 1e-9) -> None:
    """Assert that ``z`` solves LCP(M, q): z >= 0, w = Mz + q >= 0, z'w = 0,
    each component within ``tol`` of its own scale (qpcontact's componentwise
    measure).  ``lcp`` is an :class:`~qpcontact.LCP` or a tuple (M, q).

    Raises AssertionError naming the condition, the index, the raw values and
    the scales they were judged on."""
    lcp = _as_lcp(lcp)
    if z is None:
        raise AssertionError("no solution to check: z is None")
    z = np.asarray(z, dtype=float).ravel()
    if z.shape != (lcp.n,):
        raise AssertionError(f"z has shape {z.shape}; the LCP has n = {lcp.n} unknowns")
    bad = np.flatnonzero(~np.isfinite(z))
    if bad.size:
        raise AssertionError(f"z is not finite at index {int(bad[0])} (z = {z[bad[0]]}); "
                             f"{bad.size} non-finite entries in all")
    cert = certify_lcp(lcp, z)
    if cert.overflow:
        raise AssertionError("Mz + q overflows double precision at this z: rescale the data")
    if cert.error <= tol:
        return
    i = cert.worst_index
    zeta, sigma = ComponentScales(lcp.M, lcp.q_terms, lcp.matrix_scale).at(z)
    w = lcp.w(z)
    if z[i] < 0 and z[i] / zeta[i] <= w[i] / sigma[i]:
        what = (f"z >= 0 at index {i}: z_{i} = {z[i]:.3e}, judged against its scale "
                f"{zeta[i]:.3e} (the change of z_{i} that moves some row by its own size)")
    elif w[i] < 0:
        what = (f"w = Mz + q >= 0 at index {i}: w_{i} = {w[i]:.3e}, judged against its row's "
                f"scale {sigma[i]:.3e} (|q_{i}| + (|M||z|)_{i})")
    else:
        what = (f"complementarity at index {i}: z_{i} = {z[i]:.3e} (scale {zeta[i]:.3e}) and "
                f"w_{i} = {w[i]:.3e} (scale {sigma[i]:.3e}) are both positive")
    raise AssertionError(f"LCP solution fails {what}: error {cert.error:.1e} > tol {tol:.0e}")


def assert_qp_kkt(problem: Problem, x, y=None, z=None, z_box=None, tol: float = 1e-9) -> None:
    """Assert that (x, y, z, z_box) satisfies the KKT conditions of a convex
    ``qpsolvers.Problem`` in qpsolvers' conventions (P x + q + A'y + G'z +
    z_box = 0; z >= 0 complementary to h - Gx >= 0; z_box < 0 at active lower
    bounds, > 0 at active upper ones), each row within ``tol`` of its own scale.

    Raises AssertionError naming the condition, the index, the raw residual
    and the scale it was judged on."""
    if x is None:
        raise AssertionError("no solution to check: x is None")
    if not isinstance(problem, Problem):
        raise InvalidProblemError(f"expected a qpsolvers.Problem; got {type(problem).__name__}")
    cert = certify_qp(problem, x, y=y, z=z, z_box=z_box)
    if cert.overflow:
        raise AssertionError("the KKT residuals overflow double precision at this point: rescale")
    if cert.error <= tol:
        return
    raise AssertionError(f"QP KKT conditions fail: {cert.worst}: {cert.detail}: "
                         f"error {cert.error:.1e} > tol {tol:.0e}")


class CrossValidationError(AssertionError):
    """Certified answers of different methods disagree where the solution is unique."""


@dataclass
class CrossValidation:
    """What :func:`cross_validate` found.

    ``solutions``: method name -> certified solution object; ``certified``:
    the names whose answers are ``ok``; ``unique``: whether the data make the
    solution unique, and ``uniqueness`` why (or why not); ``disagreement``:
    the largest pairwise difference among certified answers, relative to the
    allowance (<= 1 means agreement)."""

    solutions: dict
    certified: list
    unique: bool
    uniqueness: str
    compared: str
    disagreement: float = 0.0
    pairs: list = field(default_factory=list)

    def summary(self) -> str:
        rows = [f"{name:16s} {s.status:11s} error {s.error:.1e}  {s.wall_time * 1e3:8.2f} ms"
                for name, s in self.solutions.items()]
        return "\n".join(rows + [f"unique: {self.unique} ({self.uniqueness}); compared {self.compared}; "
                                 f"largest disagreement / allowance {self.disagreement:.2g}"])


def _default_methods(problem) -> list[str]:
    from ..solvers.registry import methods
    from ..dispatch.routes import applicable

    return [name for name, m in methods().items() if applicable(problem, m)]


def _lcp_uniqueness(lcp: LCP) -> tuple[bool, str]:
    if lcp.is_symmetric and lcp.is_positive_definite:
        return True, "M is symmetric positive definite"
    if not lcp.is_symmetric and lcp.is_positive_definite:
        return True, "M + M' is positive definite, so M is a P-matrix"
    if lcp.is_symmetric and lcp.is_psd:
        return False, ("M is positive semidefinite and singular: z may not be unique, but w = Mz + q "
                       "is the same at every solution")
    return False, "M is not positive definite: solutions need not be unique"


def _qp_uniqueness(problem: Problem) -> tuple[bool, str]:
    from ..core.problems import LCP as _L

    P = problem.P
    structure = _L(P, np.zeros(P.shape[0]))
    if structure.is_positive_definite:
        return True, "P is positive definite"
    return False, "P is singular: x may not be unique, but the optimal value is"


def cross_validate(problem, methods=None, accuracy="high", *, time_limit: float | None = 60.0,
                   min_certified: int = 1, **options) -> CrossValidation:
    """Solve ``problem`` (an LCP or a qpsolvers.Problem) with several methods,
    certify each, and check that the certified answers agree.

    Parameters
    ----------
    methods : list of str, optional
        Method names; default every installed method that applies.
    accuracy, time_limit, **options
        Passed to :func:`qpcontact.solve` for each method.
    min_certified : int
        Raise CrossValidationError when fewer answers are certified.

    Agreement: for an LCP with a unique solution, two certified answers z_a,
    z_b must satisfy |z_a,i - z_b,i| <= (f_a + f_b + 64 eps) s_i at every i,
    where f is each answer's forward-error estimate (condition x backward
    error, docs/certificates.md) and s_i the component's own scale; the same
    for w.  For a QP with positive definite P, |x_a - x_b| <= (e_a + e_b + 64
    eps) cond(P) max(|x_a|, |x_b|, 1e-300), componentwise in infinity norm.
    Where the solution is not unique, w (LCP) or the optimal value (QP) is
    compared instead, at (e_a + e_b + 64 eps) times its scale.
    """
    from ..dispatch.driver import solve

    is_lcp = isinstance(problem, LCP)
    if not is_lcp and not isinstance(problem, Problem):
        raise InvalidProblemError(f"cross_validate takes an LCP or a qpsolvers.Problem; got "
                                  f"{type(problem).__name__}")
    names = list(methods) if methods is not None else _default_methods(problem)
    sols = {name: solve(problem, name, accuracy, time_limit=time_limit, **options) for name in names}
    ok = [name for name, s in sols.items() if s.ok]
    unique, why = _lcp_uniqueness(problem) if is_lcp else _qp_uniqueness(problem)
    report = CrossValidation(sols, ok, unique, why, compared="")
    if len(ok) < min_certified:
        raise CrossValidationError(
            f"only {len(ok)} of {len(sols)} methods certified an answer (at least {min_certified} "
            "asked):\n" + report.summary())
    worst, pairs = 0.0, []
    if is_lcp:
        report.compared = "z and w componentwise" if unique else "w componentwise"
        scales = ComponentScales(problem.M, problem.q_terms, problem.matrix_scale)
        for i, a in enumerate(ok):
            for b in ok[i + 1:]:
                sa, sb = sols[a], sols[b]
                za, wa = scales.at(sa.z)
                zb, wb = scales.at(sb.z)
                if unique:
                    fa, fb = sa.forward_error, sb.forward_error
                    if not (np.isfinite(fa) and np.isfinite(fb)):
                        continue  # not isolated numerically: nothing to hold them to
                    allow = fa + fb + 64 * _EPS
                    rz = np.abs(sa.z - sb.z) / (allow * np.maximum(za, zb))
                else:
                    allow = sa.error + sb.error + 64 * _EPS
                    rz = np.zeros(1)
                rw = np.abs(sa.w - sb.w) / (allow * np.maximum(wa, wb))
                ratio = float(max(np.max(rz), np.max(rw)))
                pairs.append((a, b, ratio))
                worst = max(worst, ratio)
    else:
        P = problem.P
        cond = None
        if unique and P.shape[0] <= 2000:
            ev = np.linalg.eigvalsh(P.toarray() if sp.issparse(P) else P)
            cond = float(ev[-1] / ev[0]) if ev[0] > 0 else None
        report.compared = "x componentwise" if cond is not None else "the optimal value"
        for i, a in enumerate(ok):
            for b in ok[i + 1:]:
                sa, sb = sols[a], sols[b]
                # the objective gap sums one term per KKT row, each within the
                # certified error of its own scale
                rows = problem.q.size + sum(m.shape[0] for m in (problem.G, problem.A) if m is not None)
                allow = (sa.error + sb.error + 64 * _EPS) * (1 if cond is not None else rows)
                if cond is not None:
                    size = max(np.max(np.abs(sa.x)), np.max(np.abs(sb.x)), 1e-300)
                    ratio = float(np.max(np.abs(sa.x - sb.x)) / (allow * cond * size))
                else:
                    fa, ta = _objective(problem, sa.x)
                    fb, tb = _objective(problem, sb.x)
                    ratio = abs(fa - fb) / (allow * max(ta, tb, 1e-300))
                pairs.append((a, b, ratio))
                worst = max(worst, ratio)
    report.disagreement, report.pairs = worst, pairs
    if worst > 1.0:
        a, b, r = max(pairs, key=lambda t: t[2])
        raise CrossValidationError(
            f"{a} and {b} both certified answers that differ by {r:.2g} times what their "
            f"certificates allow ({report.uniqueness}; compared {report.compared}):\n"
            + report.summary())
    return report


def _objective(problem: Problem, x) -> tuple[float, float]:
    """(½x'Px + q'x, its scale ½|x|'|P||x| + |q|'|x|)."""
    Px = np.asarray(problem.P @ x).ravel()
    absP = abs(problem.P) if sp.issparse(problem.P) else np.abs(problem.P)
    value = 0.5 * x @ Px + problem.q @ x
    scale = 0.5 * np.abs(x) @ np.asarray(absP @ np.abs(x)).ravel() + np.abs(problem.q) @ np.abs(x)
    return float(value), float(scale)
