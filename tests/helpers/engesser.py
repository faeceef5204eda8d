"""Engesser's shear-flexible beam-column under its own weight, shot with
scipy: an independent reference for the frames' N(x) members (no code of
formulations is used)."""

from __future__ import annotations

from scipy.integrate import solve_ivp


def heavy_cantilever_shot(q, L, EI, GAs, H=10.0):
    """(solution, M(0)) of a cantilever clamped at x = 0 under its weight q
    (N/m, so N(x) = −q (L − x)) and a tip force H across it: v' = (θ +
    H/GAs)/(1 + N/GAs) (the shear across the deformed axis, Q = H − N v' =
    GAs (v' − θ)), EI θ' = M, M' = N v' − H; v(0) = θ(0) = 0, M(L) = 0 by
    two shots (linear in M(0)).  ``solution(x)`` is (v, θ, M) at x, DOP853
    dense output to rtol 1e-13."""

    def rhs(x, y):
        N = -q * (L - x)
        dv = (y[1] + H / GAs) / (1 + N / GAs)
        return [dv, y[2] / EI, N * dv - H]

    def shot(M0):
        return solve_ivp(rhs, (0, L), [0.0, 0.0, M0], method="DOP853", rtol=1e-13,
                         atol=1e-22, dense_output=True)

    e0, e1 = shot(0.0).y[2, -1], shot(1.0).y[2, -1]
    M0 = -e0 / (e1 - e0)
    return shot(M0).sol, M0
