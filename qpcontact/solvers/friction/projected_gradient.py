r"""Coulomb friction as a variational inequality, solved by projected gradient
steps with Khobotov's step rule (Siconos numerics' ``VI_EG``).

**The VI.**  With u = W r + q the local velocities (velocity per force
times force: W in velocity / force, q in velocity, r in force) and De
Saxcé's modified velocity û_i = u_i + μ_i ‖u_T,i‖ e_N, Coulomb's law at every
contact is the complementarity K_i ∋ r_i ⟂ û_i ∈ K_i* between the friction
cone K_i = {‖r_T‖ <= μ_i r_N} and its dual (De Saxcé and Feng 1991).  That is
the variational inequality

    find r ∈ K = Π_i K_i with  F(r)ᵀ(s − r) >= 0  for every s ∈ K,
    F(r) = W r + q + μ‖u_T‖ e_N   (û, stacked),

and r solves it exactly where r = P_K(r − ρ F(r)) for one (every) ρ > 0, P_K
the Euclidean projection onto the cones, contact by contact
(:func:`qpcontact.core.friction_problem.project_cone`): the natural map that
Siconos's error measures.  ρ turns a velocity into a force, so it is in
force / velocity, a compliance's inverse: 1 / W_nn is each contact's own
scale.

**The iteration** (``VariationalInequality_ExtraGradient.c``, its Armijo
branch with Khobotov's ratio, Siconos's defaults): a predictor r̄ = P_K(r −
ρ F(r)); while ρ‖F(r̄) − F(r)‖ >= 0.9 ‖r̄ − r‖ (the step is too long for
F's local Lipschitz constant), ρ ← ⅔ ρ and the predictor again, 10 tries
(9 cuts) at most; then the corrector r⁺ = P_K(r̄ − ρ F(r̄)); ρ ← 1.5 ρ after an iteration
where ρ‖F(r̄) − F(r)‖ < 0.3 ‖r̄ − r‖ (Siconos grows it only where the
iteration's error also fell; here on the ratio alone, as measured in
docs/dev-notes.md).  Korpelevich's extragradient steps the
corrector from r, r⁺ = P_K(r − ρ F(r̄)); Siconos steps it from the predictor,
and so does this module: two projected-gradient steps an iteration, the
second at the step length the first accepted.  It is still a projection
method — every iterate lies in K, and a fixed point r = P_K(r − ρF(r)) is a
solution of the VI — with no convergence proof (F is not monotone where μ‖u_T‖
bends it, and W is only semidefinite); the certificate decides.  No linear
solve anywhere, so W's singularity (a hyperstatic pile) does not enter.

Its cost is the products W r, two or more an iteration, with W in CSR; the
iterations run compiled (:mod:`qpcontact.solvers.friction._vi_eg_kernels`):
in numpy the projections and norms cost twice the products on the dense
piles (docs/dev-notes.md, "A projected-gradient friction method").
The natural-map error of r comes free with F(r) and is
checked every ``check_every`` iterations; the iterate with the smallest one
is returned, and the method stops where a checked iterate is certified
(:func:`qpcontact.judge.friction_certificate.certified_error`).
"""

from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp

from ...core.deadline import Deadline
from ...core.friction_problem import project_cone
from ...core.options import PROGRESS, TIME_LIMIT, Option, read_options
from ...judge.friction_certificate import certified_error
from .nsgs import R0, starting_point

__all__ = ["solve_vi_eg", "VI_EG_OPTIONS"]

#: Siconos's constants: the step's cut and growth, Khobotov's ratio bounds,
#: the predictor's tries
_SHRINK, _GROW, _RATIO, _RATIO_LOW, _TRIES = 2.0 / 3.0, 1.5, 0.9, 0.3, 10

#: the longest a compiled chunk of iterations runs between reads of the clock (s)
CHUNK_SECONDS = 0.02

VI_EG_OPTIONS = (
    Option("max_iter", 1_000_000, "int", low=0, doc="iterations (predictor and corrector) at most"),
    Option("check_every", 50, "int", low=1, doc="iterations between error checks"),
    Option("rho", 1.0, "float", low=0.0, low_open=True, high=np.inf, high_open=True,
           doc="the first step (force per velocity); Khobotov's rule adapts it"),
    R0, PROGRESS, TIME_LIMIT,
)


def solve_vi_eg(problem, tol, options):
    """Projected gradient with Khobotov's step (Siconos's VI_EG; module
    docstring), from r = 0 or ``r0``.  Stops when a checked iterate is
    certified (both error measures <= tol), at ``max_iter`` iterations, at
    ``time_limit`` (wall s), or when the iterate is no longer finite;
    returns the iterate with the smallest natural-map error seen at the
    checks.  Options (:data:`VI_EG_OPTIONS`): ``max_iter`` (10⁶),
    ``check_every`` (50), ``rho`` (1, the first step), ``r0``,
    ``progress``, ``time_limit`` (s)."""
    opts = read_options("vi-eg", options, VI_EG_OPTIONS)
    max_iter, every, progress = opts["max_iter"], opts["check_every"], opts["progress"]
    time_limit = opts["time_limit"]
    deadline = Deadline(time_limit)
    d, mu, q = problem.dim, problem.mu, problem.q
    from ._vi_eg_kernels import iterations, modified_velocity   # numba: imported where it runs

    W = sp.csr_matrix(problem.W, dtype=float)
    W.sum_duplicates()
    csr = (W.indptr.astype(np.int64), W.indices.astype(np.int64), W.data)
    q, mu = np.ascontiguousarray(q, float), np.ascontiguousarray(mu, float)
    r0 = starting_point("vi-eg", problem, opts["r0"])
    r = project_cone(np.zeros(q.size) if r0 is None else r0, mu, d)
    scale = 1.0 + np.linalg.norm(q)
    rho = opts["rho"]
    best, best_r, certified = np.inf, r.copy(), np.inf
    why, it = None, 0
    f = np.empty(q.size)
    modified_velocity(*csr, q, mu, d, r, f)
    # a compiled chunk runs to its end: chunks are cut to CHUNK_SECONDS by the
    # time an iteration took, so the wall-clock limit is read between them
    # (one chunk of check_every = 20 000 ran 3.5 s past a 0.01 s limit)
    chunk = 1
    while True:
        if it % every == 0 or it >= max_iter:
            nat = np.linalg.norm(r - project_cone(r - f, mu, d)) / scale
            if nat < best:
                best, best_r = nat, r.copy()
                if nat <= tol:
                    certified = certified_error(problem, r)
            if progress is not None:
                progress(f"vi-eg: iteration {it}: natural-map error {nat:.2e}, step {rho:.2e}")
            if certified <= tol:
                why = "reached the tolerance"
            elif not np.isfinite(nat):
                why = "stopped: the iterate is no longer finite"
        if why is None and deadline.expired():
            why = f"stopped at its time limit of {time_limit:.3g} s"
        if why is None and it >= max_iter:
            why = f"stopped at max_iter = {max_iter}"
        if why is not None:
            break
        n = min(every - it % every, max_iter - it, chunk)
        start = time.perf_counter()
        rho = iterations(*csr, q, mu, d, r, f, rho, n, _SHRINK, _GROW, _RATIO, _RATIO_LOW, _TRIES)
        took = time.perf_counter() - start
        chunk = max(1, int(CHUNK_SECONDS * n / took)) if took > 0 else 2 * chunk
        it += n
    ok = certified <= tol
    return best_r, "solved" if ok else "stopped", \
        f"VI_EG {why} after {it} iterations (natural-map error {best:.2e})", \
        {"iterations": it, "natural_map_error": best, "rho": rho}
