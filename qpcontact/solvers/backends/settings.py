"""The accuracy ladder (:mod:`qpcontact.core.accuracy`) in each backend's own
settings: how each backend is asked for a tolerance.  They are requests; the
certificate is the judge.  The factors were measured per backend on a mixed
set of problems (docs/backends.md)."""

from __future__ import annotations

from typing import Callable

__all__ = ["backend_settings"]


def _tight(tol: float, factor: float = 1e-3, floor: float = 1e-13) -> float:
    """What to ask of an interior-point or augmented-Lagrangian backend so that
    our certificate meets ``tol``: ``max(factor * tol, floor)``.  Their
    tolerances bound absolute residuals and the *summed* gap; the componentwise
    complementarity at a contact whose own scale is small lags them by 1-6
    orders (a drum step: PIQP asked for 1e-13 left a force of 2e-7 N at a
    contact whose gap is 2.4e-7 m, 1.8e-9 of that contact's own force scale).
    The factors were measured per backend on a mixed set of 41 problems
    (docs/backends.md)."""
    return max(factor * tol, floor)


# Starting point: qpbenchmark's SolverSettings.set_eps_abs / set_eps_rel
# (qpbenchmark/solver_settings.py), whose "high accuracy" run sets the absolute
# tolerances to 1e-9 and the relative ones to 0.  Departures are commented:
# interior-point and augmented-Lagrangian backends are asked for _tight(tol).
_QPSOLVERS_TABLE: dict[str, Callable[[float], dict]] = {
    # Clarabel's static regularization (default 1e-8) caps what it can reach: at
    # tolerances 1e-12 it stopped with InsufficientProgress / AlmostSolved at
    # certificate errors 1e-2..1e-4 on 11 of 48 seeded SPD LCPs (n = 20..200,
    # cond 10..1e8, tests/solvers/test_pivoting.py's family); with 1e-10, 6 of 48, all at
    # cond 1e8 (docs/pivoting.md).
    # With the componentwise certificate, 1e-5 t certified 32/41 of a mixed set
    # (random SPD to cond 1e8, Siconos mmc, Kolesnikov's examples, far contacts, drum steps) where
    # 1e-3 t certified 27/41; smaller factors gained nothing (docs/backends.md).
    "clarabel": lambda t: {"tol_feas": _tight(t, 1e-5, 1e-15), "tol_gap_abs": _tight(t, 1e-5, 1e-15),
                           "tol_gap_rel": _tight(t, 1e-5, 1e-15),
                           "static_regularization_constant": 1e-10},
    "cvxopt": lambda t: {"feastol": t},
    "daqp": lambda t: {"primal_tol": t, "dual_tol": t},
    "ecos": lambda t: {"feastol": t},
    # HiGHS' QP solver is active-set and ignores the primal tolerance (qpbenchmark
    # notes it too).  It regularises the Hessian by 1e-7 by default, which moved
    # the solutions of Kolesnikov's examples by 2.5e-8 whatever the tolerances; shrinking the
    # regularisation with tol made them exact.
    # HiGHS refuses feasibility tolerances below 1e-10 (kError; cvxpy raises).
    "highs": lambda t: {"dual_feasibility_tolerance": max(t, 1e-10),
                        "primal_feasibility_tolerance": max(t, 1e-10),
                        "qp_regularization_value": min(1e-7, 1e-2 * t)},
    "hpipm": lambda t: {"tol_dual_gap": t, "tol_eq": t, "tol_ineq": t, "tol_stat": t},
    "kvxopt": lambda t: {"feastol": t},
    # Polishing added: measured here, OSQP without it stays 1e-2 off at eps 1e-3,
    # and with it reaches 1e-14 when the active set is right.
    "osqp": lambda t: {"eps_abs": t, "eps_rel": 0.0, "polishing": True},
    # 1e-5 t: 40/41 of the same set certified (Kolesnikov example 3 at 2.5e-8), 39/41 at
    # 1e-3 t (Siconos mmc 2.4e-9, Kolesnikov example 3 at 4.4e-7).  Not lower: asked for
    # 1e-15, PIQP ran to its 250-iteration limit on a dense n = 1000 problem
    # (5.8 s against 0.5 s at 1e-14, 12 iterations).
    "piqp": lambda t: {"eps_abs": _tight(t, 1e-5, 1e-15), "eps_rel": 0.0,
                       "eps_duality_gap_abs": _tight(t, 1e-5, 1e-15), "eps_duality_gap_rel": 0.0},
    # 1e-3 t: 41/41; 1e-4 t hits its iteration limit on two far-contact problems.
    # max_iter: at its own default ProxQP 0.8 ran 108 s on one far-contact problem
    # (qpcontact.testing.far_contact_lcp(7)).  1 000, not 10 000 (hangs):
    # max_iter counts outer iterations only, and the inner ones multiply it —
    # the SPD n = 300, cond 1e8 case of test_kkt_crossvalidation took 74 s
    # (3.3e5 inner iterations) at 10 000 and 4.6 s at 1 000, certified both
    # times; far_contact_lcp(7) certified at both; on unbounded and infeasible
    # QPs 10 000 ran past 25 s and 1 000 returned within 7 s.
    "proxqp": lambda t: {"eps_abs": _tight(t), "eps_rel": 0.0, "eps_duality_gap_abs": _tight(t),
                         "eps_duality_gap_rel": 0.0, "max_iter": 1_000},
    "qpalm": lambda t: {"eps_abs": t, "eps_rel": 0.0},
    "qpswift": lambda t: {"RELTOL": t * 3.0 ** 0.5},
    "scs": lambda t: {"eps_abs": t, "eps_rel": 0.0},
    "sip": lambda t: {"eps_abs": t, "eps_rel": 0.0},
    # quadprog (Goldfarb-Idnani) and qpOASES expose no tolerance: exact up to rounding by design.
    "quadprog": lambda t: {},
    "qpoases": lambda t: {},
}


# cvxpy passes keyword arguments straight to the solver, but under its own
# names for some of them (its OSQP interface takes `polish`, not `polishing`).
_CVXPY_TABLE: dict[str, Callable[[float], dict]] = {
    "CLARABEL": _QPSOLVERS_TABLE["clarabel"],
    "DAQP": _QPSOLVERS_TABLE["daqp"],
    "ECOS": lambda t: {"feastol": t, "abstol": t, "reltol": t},
    "HIGHS": _QPSOLVERS_TABLE["highs"],
    "OSQP": lambda t: {"eps_abs": t, "eps_rel": 0.0, "polish": True},
    "PIQP": _QPSOLVERS_TABLE["piqp"],
    "PROXQP": lambda t: {"eps_abs": _tight(t), "eps_rel": 0.0, "max_iter": 1_000},
    "QPALM": _QPSOLVERS_TABLE["qpalm"],
    "SCS": _QPSOLVERS_TABLE["scs"],
}


def backend_settings(family: str, solver: str, tol: float | None) -> dict:
    """Settings that ask ``solver`` (of ``family`` "qpsolvers" or "cvxpy") for
    tolerance ``tol``; empty for ``tol=None`` (the backend's defaults) and for
    solvers with no tolerance setting."""
    if tol is None:
        return {}
    table = _QPSOLVERS_TABLE if family == "qpsolvers" else _CVXPY_TABLE
    rule = table.get(solver)
    return rule(tol) if rule is not None else {}
