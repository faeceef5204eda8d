"""Compiled iterations of "vi-eg" (numba): Siconos's VI_EG step with
Khobotov's rule, as :mod:`qpcontact.solvers.friction.projected_gradient`
states it, with W in CSR.  One pass per product and per projection: in numpy
the projections and norms on the 1 620–2 946 entries of a dense pile cost
twice W's products (docs/dev-notes.md, "A projected-gradient friction
method")."""

from __future__ import annotations

import numpy as np

from ...core._cone_kernels import INSIDE, POLAR, cone_region
from ...core.compiled import njit


@njit
def modified_velocity(indptr, indices, data, q, mu, d, r, out):
    """out = F(r) = u + μ‖u_T‖ e_N per contact, u = W r + q."""
    for i in range(r.size):
        s = q[i]
        for k in range(indptr[i], indptr[i + 1]):
            s += data[k] * r[indices[k]]
        out[i] = s
    for c in range(mu.size):
        t = 0.0
        for k in range(1, d):
            t += out[c * d + k] * out[c * d + k]
        out[c * d] += mu[c] * np.sqrt(t)


@njit
def _step(x, g, rho, mu, d, out):
    """out = P_K(x − ρ g), contact by contact."""
    for c in range(mu.size):
        b = c * d
        t = 0.0
        for k in range(1, d):
            y = x[b + k] - rho * g[b + k]
            out[b + k] = y
            t += y * y
        t = np.sqrt(t)
        rn = x[b] - rho * g[b]
        out[b] = rn
        region = cone_region(rn, t, mu[c])
        if region == INSIDE:
            continue
        if region == POLAR:
            for k in range(d):
                out[b + k] = 0.0
            continue
        a = (mu[c] * t + rn) / (1.0 + mu[c] * mu[c])
        out[b] = a
        for k in range(1, d):
            out[b + k] = out[b + k] * mu[c] * a / t if t > 0.0 else 0.0


@njit
def _distance(x, y):
    s = 0.0
    for i in range(x.size):
        s += (x[i] - y[i]) * (x[i] - y[i])
    return np.sqrt(s)


@njit
def iterations(indptr, indices, data, q, mu, d, r, f, rho, n, shrink, grow, ratio, ratio_low,
               tries):
    """``n`` iterations from r with f = F(r): r and f updated in place;
    returns the step ρ after them."""
    bar, fbar = np.empty(r.size), np.empty(r.size)
    for _ in range(n):
        rho /= shrink
        moved = changed = 0.0
        for _t in range(tries):
            rho *= shrink
            _step(r, f, rho, mu, d, bar)
            modified_velocity(indptr, indices, data, q, mu, d, bar, fbar)
            moved, changed = _distance(bar, r), _distance(fbar, f)
            if rho * changed < ratio * moved:
                break
        _step(bar, fbar, rho, mu, d, r)
        modified_velocity(indptr, indices, data, q, mu, d, r, f)
        if rho * changed < ratio_low * moved:
            rho *= grow
    return rho
