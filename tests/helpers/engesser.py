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


def span_shot(EI, GAs, N, L, loads, start=(0, 1), end=(0, 1)):
    """Engesser's beam-column under a constant N with span loads, shot with
    scipy: (state(x), state at 0, state at L), the state (v, θ, M, S) — v
    the deflection, θ the section's rotation, M = EI θ' the moment on the
    deformed axis (sagging positive), S = M' − N v' the force across the
    undeformed axis; v' = (θ − S/GAs)/(1 + N/GAs), S' = q.  ``loads``:
    ("point", a, py, mz) (S jumps by py, M by −mz at a) and
    ("distributed", a, b, w1, w2) (q linear from w1 at a to w2 at b).  The
    state's components ``start`` are zero at x = 0, ``end``'s at x = L (0:
    v, 1: θ, 2: M): clamped (0, 1), pinned (0, 2).  DOP853 to rtol 1e-13
    between the load positions; the two unknowns at 0 by three shots (the
    problem is linear)."""
    import numpy as np

    c = 1.0 / GAs

    def q(x, on):
        return sum(w1 + (w2 - w1) * (x - a) / (b - a) for _, a, b, w1, w2 in on)

    def rhs(x, y, scale, on):
        dv = (y[1] - c * y[3]) / (1.0 + c * N)
        return [dv, y[2] / EI, y[3] + N * dv, scale * q(x, on)]

    cuts = sorted({0.0, L} | {p for ld in loads for p in ld[1:3 if ld[0] == "distributed" else 2]
                              if 0.0 < p < L})

    def shoot(y0, scale):
        """The piecewise dense solutions from y0 (the loads times ``scale``)."""
        y, pieces = np.array(y0, float), []
        for a, b in zip(cuts[:-1], cuts[1:]):
            for ld in loads:
                if ld[0] == "point" and ld[1] == a and a > 0.0:
                    y = y + scale * np.array([0.0, 0.0, -ld[3], ld[2]])
            # the distributed loads on this stretch (its ends are cuts)
            on = [ld for ld in loads if ld[0] == "distributed" and ld[1] < 0.5 * (a + b) < ld[2]]
            sol = solve_ivp(rhs, (a, b), y, method="DOP853", rtol=1e-13, atol=1e-30,
                            dense_output=True, args=(scale, on))
            pieces.append((a, b, sol.sol))
            y = sol.y[:, -1]
        return pieces, y

    free = [k for k in range(4) if k not in start]
    unit = []
    for k in free:
        y0 = np.zeros(4)
        y0[k] = 1.0
        unit.append(shoot(y0, 0.0)[1][list(end)])
    rest = shoot(np.zeros(4), 1.0)[1][list(end)]
    y0 = np.zeros(4)
    y0[free] = np.linalg.solve(np.array(unit).T, -rest)
    pieces, yL = shoot(y0, 1.0)

    def state(x):
        x = np.atleast_1d(np.asarray(x, float))
        out = np.empty((x.size, 4))
        for n, xn in enumerate(x):
            a, b, sol = next(p for p in reversed(pieces) if p[0] <= xn) if xn > 0 else pieces[0]
            out[n] = sol(min(max(xn, a), b))
        return out

    return state, y0, yL
