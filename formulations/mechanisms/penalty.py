"""Mechanisms with unilateral constraints: the penalty QP of one integration
step (the penalty paper: Nikolsky, Kopylov, Romanenko & Kudryashov 2012) —
the formulation's front for ``qpcontact demo`` and ``compare`` (entry point ``penalty``).

The step problem, its derivation and units live in
:mod:`formulations.stepping.penalty_step` (re-exported here).  The demo and
the instances run on the ramming scene of :mod:`.planar`, which builds on the
step problem, so the imports go one way: penalty -> planar -> stepping (and
multibody -> stepping); nothing below imports this module.
"""

from __future__ import annotations

import numpy as np

from qpcontact import solve

from .planar import ramming_impact_step
from ..stepping.penalty_step import (MU_SINGULAR_COND, REGULARIZATION, PenaltyResult, PenaltyStep,
                                     exact_lcp, gauss_qp, mu_threshold, penalty_qp, solve_penalty,
                                     step_penalty_qp)

__all__ = ["PenaltyStep", "PenaltyResult", "penalty_qp", "step_penalty_qp", "exact_lcp",
           "gauss_qp", "mu_threshold", "solve_penalty", "random_step", "REGULARIZATION",
           "MU_SINGULAR_COND", "demo", "instances"]


def demo(console) -> int:
    """The penalty part of ``qpcontact demo``: the ramming scene's impact step
    solved as the penalty paper's QP by every installed QP backend and checked against
    the exact LCP (Lemke).  Returns the number of certified answers that are
    wrong (0 when all is well)."""
    import time

    from rich import box
    from rich.markup import escape
    from rich.table import Table

    from qpcontact import methods

    step = ramming_impact_step()
    exact = solve(exact_lcp(step), method="lemke")
    auto = solve_penalty(step, mu="auto", method="clarabel")
    mu = auto.mu
    scale = max(np.abs(exact.z).max(), np.abs(step.b).max() / np.abs(step.A).max())
    table = Table(title="Penalty QP (Nikolsky et al. 2012): the ramming scene's impact step, every QP backend",
                  box=box.SIMPLE_HEAD, title_justify="left", pad_edge=False)
    for col in ("method", "status", "lambda [N]", "rel. error vs exact", "time [ms]"):
        table.add_column(escape(col), justify="left" if col in ("method", "status") else "right",
                         no_wrap=True, min_width=len(col))
    wrong = 0
    runs = []
    for name, m in methods().items():
        if m.takes != "qp" or m.constraints != "any":
            continue
        solve_penalty(step, mu=mu, method=name)   # untimed: the first call pays the imports
        dt = np.inf
        for _ in range(3):      # the fastest of three: one call is mostly scheduling noise
            t0 = time.perf_counter()
            res = solve_penalty(step, mu=mu, method=name)
            dt = min(dt, time.perf_counter() - t0)
        runs.append((name, res))
        err = np.abs(res.lam - exact.z).max() / scale if res.lam is not None else None
        wrong += int(res.ok and err > 1e-6)
        style = "green" if res.ok else "yellow"
        table.add_row(name, f"[{style}]{res.status}[/{style}]",
                      "-" if res.lam is None else str(res.lam.round(3)),
                      "-" if err is None else f"{err:.1e}", f"{1e3 * dt:.2f}")
    console.print(table)
    notes = [f"mu = {mu:.3g} s^2, chosen by mu='auto' (the KKT threshold is "
             f"{mu_threshold(step, exact.z):.3g}); exact reaction {exact.z.round(2)} N by Lemke on "
             "the step's LCP.  rel. error: max|lambda - exact| over the reaction scale.  time: the "
             "fastest of 3 calls after a first, untimed one (it pays the backend's import).",
             "solved: lambda solves the step's exact LCP at the requested accuracy (its "
             "certificate, not the backend's word)."]
    bad = [(name, r) for name, r in runs if not r.ok]
    if bad:
        notes.append("inaccurate: lambda misses the exact LCP's certificate, or no lambda came "
                     "back ('-': nothing to compare), whatever the QP backend said; here: "
                     + "; ".join(f"{name}: {r.message}" for name, r in bad))
    for line in notes:
        console.print(line, markup=False, highlight=False)
    return wrong


def random_step(seed: int, n: int, nu: int) -> PenaltyStep:
    """A seeded random mechanism step: G = RR' + nI (n x n), J (nu x n) Gaussian,
    Q ~ 10 N(0, 1), B ~ N(0, 1), compliance C diagonal in [1e-3, 1e-2] m/N."""
    rng = np.random.default_rng(seed)
    R = rng.standard_normal((n, n))
    G = R @ R.T + n * np.eye(n)
    J = rng.standard_normal((nu, n))
    C = np.diag(rng.uniform(1e-3, 1e-2, nu))
    return PenaltyStep(G, 10 * rng.standard_normal(n), J, rng.standard_normal(nu), C=C)


def instances(size: str = "small", hardness: str = "easy", seed: int = 0):
    """Penalty QPs for ``qpcontact compare`` (the reactions are x): the ramming
    impact step (small) and random mechanism steps with n = 7, 30, 100 degrees
    of freedom and 4, 20, 60 contacts; "easy" at mu = 10 x the KKT threshold
    (at least 1), "hard" at mu = 1e6 (the ill-conditioned end of the window).
    Named ``penalty/ramming/mu=1e+06``."""
    from qpcontact.cases.instance import Instance

    n, nu = {"small": (7, 4), "medium": (30, 20), "large": (100, 60)}[size]
    steps = [(f"random-{n}x{nu}", random_step(seed + 1000 * n, n, nu))]
    if size == "small":
        steps.append(("ramming", ramming_impact_step()))
    out = []
    for label, st in steps:
        if hardness == "hard":
            mu = 1e6
        else:
            lam = solve(exact_lcp(st), method="lemke").z
            mu = max(10 * mu_threshold(st, lam), 1.0) if lam is not None else 1.0
            if not np.isfinite(mu):
                mu = 1e3
        out.append(Instance(f"penalty/{label}/mu={mu:.0e}", "penalty", f"{n}-dof" if label != "ramming"
                            else "ramming", step_penalty_qp(st, mu)))
    return out
