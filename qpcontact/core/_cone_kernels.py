"""The 2-D cone projection in one compiled pass, and the test of where a
point lies against the cone that the compiled sweeps, Newton steps and
certificates share (numba).

Imported only by friction_problem.project_cone and by other compiled
kernels, where they run, so that importing qpcontact does not load numba."""

from __future__ import annotations

import numpy as np
from .compiled import njit

#: :func:`cone_region`'s answers
POLAR, INSIDE, SIDE = 0, 1, 2


@njit
def cone_region(xn, t, mu):
    """Where a point of normal part ``xn`` and tangential norm ``t`` lies
    against the cone {t <= μ x_N}: INSIDE (tested first, so the apex is
    inside: the projection's Jacobian there is the identity), POLAR (its
    projection is 0), else SIDE.  Inside needs x_N >= 0 as well: with μ = 0
    and t = 0, t <= μ x_N reads 0 <= −0.0, true for x_N < 0."""
    if t <= mu * xn and xn >= 0.0:
        return INSIDE
    if mu * t <= -xn:
        return POLAR
    return SIDE


@njit
def project_cone_2d(r: np.ndarray, mu: np.ndarray) -> np.ndarray:
    """Each 2-D contact's (r_N, r_T) projected onto {|r_T| <= μ r_N}: the
    array formulas of friction_problem.project_cone term by term (the polar
    cone's 0 before the cone's inside, as their masks are applied), so the
    same values bit for bit, without their masks and copies (0.1 ms a call
    on a 1 100-contact drum problem, called at each of Newton's steps)."""
    nc = mu.shape[0]
    out = np.empty(2 * nc)
    for i in range(nc):
        rn, rt, m = r[2 * i], r[2 * i + 1], mu[i]
        t = np.sqrt(rt * rt)
        if m * t <= -rn:                # the polar cone
            out[2 * i] = 0.0
            out[2 * i + 1] = 0.0
        elif t <= m * rn:               # inside
            out[2 * i] = rn
            out[2 * i + 1] = rt
        else:                           # onto the cone's side
            alpha = (m * t + rn) / (1.0 + m * m)
            out[2 * i] = alpha
            out[2 * i + 1] = rt * (m * alpha / t if t > 0 else 0.0)
    return out
