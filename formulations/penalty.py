"""Mechanisms with unilateral constraints: the penalty QP of one integration
step (P2, Nikolsky, Kopylov, Romanenko & Kudryashov 2012) — the formulation's
front for ``qpcontact demo`` and ``compare`` (entry point ``penalty``).

The step problem, its derivation and units live in :mod:`.penalty_step`
(re-exported here).  The demo and the instances run on the ramming scene of
:mod:`.mechanisms`, which builds on the step problem, so the imports go one
way: penalty -> mechanisms -> stepping -> penalty_step (and
multibody.contacts -> penalty_step); nothing below imports this module.
"""

from __future__ import annotations

import numpy as np

from qpcontact import solve

from .mechanisms import ramming_impact_step
from .penalty_step import (MU_SINGULAR_COND, REGULARIZATION, PenaltyResult, PenaltyStep,
                           exact_lcp, gauss_qp, mu_threshold, penalty_qp, solve_penalty,
                           step_penalty_qp)

__all__ = ["PenaltyStep", "PenaltyResult", "penalty_qp", "step_penalty_qp", "exact_lcp",
           "gauss_qp", "mu_threshold", "solve_penalty", "random_step", "REGULARIZATION",
           "MU_SINGULAR_COND", "demo", "instances"]


def demo(console) -> int:
    """The penalty part of ``qpcontact demo``: the ramming scene's impact step
    solved as P2's penalty QP by every installed QP backend and checked against
    the exact LCP (Lemke).  Returns the number of certified answers that are
    wrong (0 when all is well)."""
    import time

    from rich.table import Table

    from qpcontact import methods

    step = ramming_impact_step()
    exact = solve(exact_lcp(step), method="lemke")
    auto = solve_penalty(step, mu="auto", method="clarabel")
    mu = auto.mu
    scale = max(np.abs(exact.z).max(), np.abs(step.b).max() / np.abs(step.A).max())
    table = Table(title=f"Penalty QP (P2): ramming impact step, mu = {mu:.3g} s^2 (auto; KKT "
                        f"threshold {mu_threshold(step, exact.z):.3g}); exact reaction "
                        f"{exact.z.round(2)} N by Lemke")
    for col in ("method", "status", "lambda [N]", "rel. error vs exact", "time [ms]"):
        table.add_column(col, justify="left" if col in ("method", "status") else "right")
    wrong = 0
    for name, m in methods().items():
        if m.takes != "qp" or m.constraints != "any":
            continue
        t0 = time.perf_counter()
        res = solve_penalty(step, mu=mu, method=name)
        dt = time.perf_counter() - t0
        err = np.abs(res.lam - exact.z).max() / scale if res.lam is not None else np.inf
        wrong += int(res.ok and err > 1e-6)
        style = "green" if res.ok else "yellow"
        table.add_row(name, f"[{style}]{res.status}[/{style}]",
                      "-" if res.lam is None else str(res.lam.round(3)), f"{err:.1e}", f"{1e3 * dt:.2f}")
    console.print(table)
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
