"""Cross-validation: one problem solved by several methods, each answer
certified, and the certified answers held to agree as far as their own
forward-error estimates allow (where the data make the answer unique or, for
frictional contact, where both answers are isolated)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from qpsolvers import Problem

from ..core.errors import InvalidProblemError
from ..core.problems import LCP
from ..dispatch import driver
from ..dispatch.routes import applicable
from ..judge.friction_certificate import contact_sizes
from ..core.friction_problem import FrictionProblem
from ..judge.scales import ComponentScales
from ..solvers.registry import methods as installed

__all__ = ["cross_validate", "CrossValidation", "CrossValidationError"]

_EPS = np.finfo(float).eps


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
    return [name for name, m in installed().items() if applicable(problem, m)]


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
    P = problem.P
    structure = LCP(P, np.zeros(P.shape[0]))
    if structure.is_positive_definite:
        return True, "P is positive definite"
    return False, "P is singular: x may not be unique, but the optimal value is"


def cross_validate(problem, methods=None, accuracy="high", *, time_limit: float | None = 60.0,
                   min_certified: int = 1, **options) -> CrossValidation:
    """Solve ``problem`` (an LCP, a qpsolvers.Problem or a FrictionProblem)
    with several methods, certify each, and check that the certified answers
    agree.

    Parameters
    ----------
    methods : list of str, optional
        Method names; default every installed method that applies.
    accuracy, time_limit, **options
        Passed to :func:`qpcontact.solve` for each method.
    min_certified : int
        Raise CrossValidationError when fewer answers are certified.

    Notes
    -----
    Agreement: for an LCP with a unique solution, two certified answers z_a,
    z_b must satisfy ``|z_a,i - z_b,i| <= (f_a + f_b + 64 eps) s_i`` at every
    i, where f is each answer's forward-error estimate (condition x backward
    error, docs/certificates.md) and s_i the component's own scale; the same
    for w.  For a QP with positive definite P, ``|x_a - x_b| <= (e_a + e_b +
    64 eps) cond(P) max(|x_a|, |x_b|, 1e-300)``, componentwise in infinity
    norm.
    Where the solution is not unique, w (LCP) or the optimal value (QP) is
    compared instead, at (e_a + e_b + 64 eps) times its scale.  For
    frictional contact, contact by contact: ‖r_a,i − r_b,i‖ <= (f_a + f_b +
    64 eps) s_i, s_i the contact's force scale and f the forward errors from
    the natural map's Jacobian — for the pairs where both answers are
    isolated (finite f); Coulomb's law need not have a unique solution, so
    two isolated certified answers that differ are two solutions (or a
    wrong certificate), and either is worth a failing test.
    """
    kinds = (LCP, Problem, FrictionProblem)
    if not isinstance(problem, kinds):
        raise InvalidProblemError(f"cross_validate takes an LCP, a qpsolvers.Problem or a "
                                  f"FrictionProblem; got {type(problem).__name__}")
    names = list(methods) if methods is not None else _default_methods(problem)
    sols = {name: driver.solve(problem, name, accuracy, time_limit=time_limit, **options)
            for name in names}
    ok = [name for name, s in sols.items() if s.ok]
    compare = (_compare_lcp if isinstance(problem, LCP) else
               _compare_qp if isinstance(problem, Problem) else _compare_friction)
    unique, why = (_lcp_uniqueness(problem) if isinstance(problem, LCP) else
                   _qp_uniqueness(problem) if isinstance(problem, Problem) else
                   _friction_uniqueness(problem))
    report = CrossValidation(sols, ok, unique, why, compared="")
    if len(ok) < min_certified:
        raise CrossValidationError(
            f"only {len(ok)} of {len(sols)} methods certified an answer (at least {min_certified} "
            "asked):\n" + report.summary())
    report.compared, pairs = compare(problem, [(name, sols[name]) for name in ok], unique)
    report.pairs = [(a, b, ratio) for a, b, ratio, _ in pairs]
    report.disagreement = max((ratio for _, _, ratio, _ in pairs), default=0.0)
    if report.disagreement > 1.0:
        a, b, r, where = max(pairs, key=lambda t: t[2])
        hint = ("; both are isolated solutions to their tolerance, so either the problem has "
                "several solutions (compare only methods that should find the same one) or a "
                "certificate let a wrong answer through"
                if isinstance(problem, FrictionProblem) and not unique else "")
        raise CrossValidationError(
            f"{a} and {b} both certified answers that differ by {r:.2g} times what their "
            f"certificates allow{where} ({report.uniqueness}; compared {report.compared}{hint}):\n"
            + report.summary())
    return report


def _pairs(certified):
    for i, (a, sa) in enumerate(certified):
        for b, sb in certified[i + 1:]:
            yield a, sa, b, sb


def _compare_lcp(problem: LCP, certified, unique):
    """(what was compared, [(a, b, difference / allowance, where)])."""
    scales = ComponentScales(problem.M, problem.q_terms, problem.matrix_scale)
    out = []
    for a, sa, b, sb in _pairs(certified):
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
        out.append((a, b, float(max(np.max(rz), np.max(rw))), ""))
    return ("z and w componentwise" if unique else "w componentwise"), out


def _compare_qp(problem: Problem, certified, unique):
    P = problem.P
    cond = None
    if unique and P.shape[0] <= 2000:
        ev = np.linalg.eigvalsh(P.toarray() if sp.issparse(P) else P)
        cond = float(ev[-1] / ev[0]) if ev[0] > 0 else None
    out = []
    for a, sa, b, sb in _pairs(certified):
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
        out.append((a, b, ratio, ""))
    return ("x componentwise" if cond is not None else "the optimal value"), out


def _friction_uniqueness(problem: FrictionProblem) -> tuple[bool, str]:
    if problem.is_reduced and not np.any(problem.mu):
        lcp = LCP(problem.W, problem.q)
        if lcp.is_positive_definite:
            return True, "μ = 0 and W is positive definite: the frictionless problem has one solution"
    return False, ("Coulomb's law need not have a unique solution: answers are compared where "
                   "both are isolated (the natural map's Jacobian nonsingular at them)")


def _compare_friction(problem: FrictionProblem, certified, unique):
    d = problem.dim
    out, skipped = [], 0
    for a, sa, b, sb in _pairs(certified):
        fa, fb = sa.forward_error, sb.forward_error
        if not (np.isfinite(fa) and np.isfinite(fb)):
            skipped += 1
            continue
        allow = fa + fb + 64 * _EPS
        size = np.maximum(contact_sizes(problem, sa.r), contact_sizes(problem, sb.r))
        diff = np.linalg.norm((sa.r - sb.r).reshape(-1, d), axis=1) / (allow * size)
        i = int(np.argmax(diff))
        out.append((a, b, float(diff[i]), f" at contact {i}"))
    if not out and certified[1:]:
        return "nothing: no two certified answers are isolated (forward error infinite)", out
    what = "r contact by contact"
    return what + (f" ({skipped} pair(s) not isolated, not compared)" if skipped else ""), out


def _objective(problem: Problem, x) -> tuple[float, float]:
    """(½x'Px + q'x, its scale ½|x|'|P||x| + |q|'|x|)."""
    Px = np.asarray(problem.P @ x).ravel()
    absP = abs(problem.P) if sp.issparse(problem.P) else np.abs(problem.P)
    value = 0.5 * x @ Px + problem.q @ x
    scale = 0.5 * np.abs(x) @ np.asarray(absP @ np.abs(x)).ravel() + np.abs(problem.q) @ np.abs(x)
    return float(value), float(scale)
