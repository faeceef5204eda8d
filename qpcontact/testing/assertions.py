"""Assertions for other projects' tests: an answer checked against the problem
data with qpcontact's componentwise measures, each condition on its own row's
(or contact's) scale, and a message that names the condition, the index, the
raw values and the scale they were judged on."""

from __future__ import annotations

import numpy as np
from qpsolvers import Problem

from ..core.errors import InvalidProblemError
from ..core.problems import LCP
from ..judge.friction_certificate import certify_friction, contact_scales, contact_sizes
from ..core.friction_problem import FrictionProblem
from ..judge.lcp_certificate import certify_lcp
from ..judge.qp_certificate import certify_qp
from ..judge.scales import ComponentScales

__all__ = ["assert_lcp_solution", "assert_qp_kkt", "assert_friction_solution"]


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
    zeta, sigma = ComponentScales.of(lcp).at(z)
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


def assert_friction_solution(problem: FrictionProblem, r, tol: float = 1e-9, v=None) -> None:
    """Assert that reactions ``r`` solve a frictional contact problem (Coulomb's
    law with Signorini's condition), held to ``tol`` in both of qpcontact's
    measures: Siconos's natural-map error and the componentwise one (each
    contact on its own force scale); for a global problem kept without W,
    give its global velocity ``v`` too (the equilibrium Mv = Hr + f is then
    held to ``tol`` as well, each equation on its own scale).

    Raises AssertionError naming the contact, the law it breaks (its reaction
    outside its friction cone, its velocity into the obstacle, or a contact
    neither open, sticking nor sliding against its slip), the raw values and
    the scale they were judged on::

        AssertionError: frictional contact fails at contact 2: the reaction is outside its
        friction cone: ‖r_T‖ = 1.200e+00, μ r_N = 1.000e+00 (μ = 0.5, r_N = 2.000e+00);
        natural-map residual judged against the contact's scale 3.1e+00 (‖r_2‖ + ρ_2(‖q_2‖
        + ‖(|W||r|)_2‖), ρ_2 = 1.000e+00): error 6.4e-02 > tol 1e-09
    """
    if r is None:
        raise AssertionError("no solution to check: r is None")
    if not isinstance(problem, FrictionProblem):
        raise InvalidProblemError(f"expected a FrictionProblem; got {type(problem).__name__}")
    r = np.asarray(r, dtype=float).ravel()
    d, m = problem.dim, problem.dim * problem.n_contacts
    if r.shape != (m,):
        raise AssertionError(f"r has {r.size} entries; the problem has {problem.n_contacts} "
                             f"contacts in dimension {d} ({m} entries)")
    bad = np.flatnonzero(~np.isfinite(r))
    if bad.size:
        raise AssertionError(f"r is not finite at index {int(bad[0])} (contact {int(bad[0]) // d}, "
                             f"r = {r[bad[0]]}); {bad.size} non-finite entries in all")
    cert = certify_friction(problem, r, v)
    if cert.overflow:
        raise AssertionError("W r + q overflows double precision at this r: rescale the data")
    if cert.error <= tol:
        return
    if not problem.is_reduced:
        raise AssertionError(
            f"frictional contact (global form) fails: natural-map error "
            f"{cert.natural_map_error:.1e}, componentwise {cert.componentwise_error:.1e}, "
            f"equilibrium Mv = Hr + f {cert.equilibrium_error:.1e}: error {cert.error:.1e} > "
            f"tol {tol:.0e}")
    if cert.componentwise_error <= tol:
        raise AssertionError(
            f"frictional contact fails Siconos's natural-map error ‖r − proj_K(r − û)‖ / "
            f"(1 + ‖q‖) = {cert.natural_map_error:.1e} > tol {tol:.0e} (every contact passes on "
            "its own scale: the residual is spread over many contacts)")
    i = cert.worst_contact
    mu = problem.mu[i]
    ri = r[d * i:d * i + d]
    ui = problem.velocities(r)[d * i:d * i + d]
    rho = contact_scales(problem)[i]
    size = contact_sizes(problem, r)[i]
    rn, rt, un, ut = ri[0], np.linalg.norm(ri[1:]), ui[0], np.linalg.norm(ui[1:])
    uhat = np.r_[un + mu * ut, ui[1:]]
    work = float(ri @ uhat)
    # in force units, on the contact's scale: a reaction outside its cone or
    # a velocity into the obstacle is named first (the answer is not even
    # admissible there), else the complementarity that fails
    cone, into = max(rt - mu * rn, -rn), rho * -un
    if cone > tol * size:
        what = (f"the reaction is outside its friction cone: ‖r_T‖ = {rt:.3e}, μ r_N = "
                f"{mu * rn:.3e} (μ = {mu:g}, r_N = {rn:.3e})")
    elif into > tol * size:
        what = (f"its velocity points into the obstacle: u_N = {un:.3e} < 0 (De Saxcé's "
                f"û_N = u_N + μ‖u_T‖ = {uhat[0]:.3e} below μ‖u_T‖ = {mu * ut:.3e})")
    else:
        what = (f"it is neither open, sticking nor sliding against its slip: r = "
                f"{np.array2string(ri, precision=3)}, u = {np.array2string(ui, precision=3)}, "
                f"r·û = {work:.3e} ≠ 0")
    raise AssertionError(
        f"frictional contact fails at contact {i}: {what}; natural-map residual judged against "
        f"the contact's scale {size:.3e} (‖r_{i}‖ + ρ_{i}(‖q_{i}‖ + ‖(|W||r|)_{i}‖), ρ_{i} = "
        f"{rho:.3e}): error {cert.componentwise_error:.1e} > tol {tol:.0e}")
