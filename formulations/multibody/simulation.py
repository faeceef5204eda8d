"""Time integration of tree (and closed-loop) systems.

``simulate`` integrates either Ivanov & Shimanovsky's momentum form (state q, p; ν from system
(6) at every evaluation, O(N)) or the Lagrange form (state q, ν; ν̇ from a
dense Cholesky of G), with an explicit integrator: SciPy's adaptive DOP853
(order 8; they used a 6th-order Störmer method) or classical fixed-step RK4
(order 4, to measure orders).  Closed loops (constraints.PointLoop) are
closed at velocity level with Baumgarte α in the momentum form, or
differentiated twice (Baumgarte α, β) in the Lagrange form.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from qpcontact.core.errors import InvalidOptionError, SolverFailedError

from . import algorithms as alg
from . import constraints as con
from .model import Data, Model

__all__ = ["simulate", "Trajectory", "FORMS", "INTEGRATORS"]

#: The forms of the equations of motion :func:`simulate` integrates (``form=``).
FORMS = ("momentum", "lagrange")
#: Its integrators (``integrator=``): adaptive DOP853 (rtol, atol) or fixed-step RK4 (h).
INTEGRATORS = ("DOP853", "RK4")


@dataclass
class Trajectory:
    """Samples of a simulation (SI): times t, configurations q (rows), joint
    velocities v, energy T + V_gravity [J] and, with loops, the constraint
    residual max|Φ| [m] per sample.  ``nfev``: right-hand-side evaluations."""

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    energy: np.ndarray
    constraint: np.ndarray
    nfev: int
    status: int
    message: str
    form: str
    integrator: str
    extra: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.status == 0


def _rk4(f, t0, y0, t_end, h, t_eval):
    n = int(round((t_end - t0) / h))
    if n < 1 or not np.isclose(n * h, t_end - t0, rtol=1e-9, atol=0):
        raise InvalidOptionError(f"RK4 needs (t_end - t0) / h to be a whole number; got {(t_end - t0) / h}")
    every = 1 if t_eval is None else max(1, int(round((t_eval[1] - t_eval[0]) / h)))
    ts, ys = [t0], [y0.copy()]
    y, t = y0.copy(), t0
    for k in range(1, n + 1):
        k1 = f(t, y)
        k2 = f(t + h / 2, y + h / 2 * k1)
        k3 = f(t + h / 2, y + h / 2 * k2)
        k4 = f(t + h, y + h * k3)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        t = t0 + k * h
        if k % every == 0 or k == n:
            ts.append(t)
            ys.append(y.copy())
    return np.array(ts), np.array(ys), 4 * n


def simulate(model: Model, q0, v0, t_end: float, *, form: str = "momentum", method: str = "ldlt",
             integrator: str = "DOP853", h: float | None = None, rtol: float = 1e-10,
             atol: float = 1e-12, tau=None, fext=None, loops=(), alpha: float = 0.0,
             beta: float = 0.0, samples: int = 201, t0: float = 0.0) -> Trajectory:
    """Integrate from (q0, v0) at t0 to t_end [s].

    ``tau`` (joint forces) and ``fext`` (body forces, (N+1) x 6) are arrays or
    callables (t, q, ν).  ``loops``: constraints.PointLoop list; ``alpha``,
    ``beta`` [1/s]: Baumgarte parameters (module docstring).  ``integrator``
    "DOP853" (rtol, atol) or "RK4" (step h).  Returns ``samples`` equally
    spaced samples."""
    if form not in FORMS:
        raise InvalidOptionError(f"form must be one of {FORMS}; got {form!r}")
    if integrator not in INTEGRATORS:
        raise InvalidOptionError(f"integrator must be one of {INTEGRATORS}; got {integrator!r}")
    if not t_end > t0:
        raise InvalidOptionError(f"t_end must exceed t0 = {t0}; got {t_end}")
    q0, v0 = model.check_state(q0, v0)
    loops = list(loops)
    data = Data(model)
    nq = model.nq
    counter = [0]

    if form == "momentum":
        def unpack(t, y):
            q, pb = y[:nq], y[nq:]
            if loops:
                nu, sigma = con.loop_velocities(model, data, t, q, pb, loops, alpha, method)
                return q, nu, sigma
            return q, alg.velocities_from_momenta(model, data, q, pb, t, method), None

        def rhs(t, y):
            counter[0] += 1
            q, nu, sigma = unpack(t, y)
            if loops:       # V, μ of the constrained motion ν (loop_velocities left x0's)
                alg.momenta(model, data, q, nu, t)
            pd = alg.momentum_rate(model, data, t, q, nu, tau, fext)
            if loops:
                _, _, Jd = con.loop_jacobian(model, data, q, nu, loops, t)
                pd = pd + Jd.T @ sigma
            return np.concatenate([alg.configuration_rate(model, q, nu), pd])

        p0 = alg.momenta(model, data, q0, v0, t0)    # p̄ = p at t0 (σ = 0)
        y0 = np.concatenate([q0, p0])
    else:
        def unpack(t, y):
            return y[:nq], y[nq:], None

        def rhs(t, y):
            counter[0] += 1
            q, v = y[:nq], y[nq:]
            tq = tau(t, q, v) if callable(tau) else tau
            fq = fext(t, q, v) if callable(fext) else fext
            if not loops:
                a = alg.forward_dynamics(model, data, q, v, tq, fq, t)
            else:
                c = alg.nonlinear_effects(model, data, q, v, fq, t)
                G = alg.mass_matrix(model, data, q)
                r = (np.zeros(model.nv) if tq is None else np.asarray(tq, float)) - c
                Phi, J, Jd = con.loop_jacobian(model, data, q, v, loops, t)
                m = Phi.size
                KKT = np.block([[G, J.T], [J, np.zeros((m, m))]])
                rhs_c = -Jd @ v - 2 * alpha * (J @ v) - beta ** 2 * Phi
                a = np.linalg.solve(KKT, np.concatenate([r, rhs_c]))[:model.nv]
            return np.concatenate([alg.configuration_rate(model, q, v), a])

        y0 = np.concatenate([q0, v0])

    t_eval = np.linspace(t0, t_end, samples)
    if integrator == "DOP853":
        sol = solve_ivp(rhs, (t0, t_end), y0, method="DOP853", rtol=rtol, atol=atol, t_eval=t_eval)
        ts, ys, status, message = sol.t, sol.y.T, sol.status, sol.message
    else:
        if h is None or not h > 0:
            raise InvalidOptionError("RK4 needs a step h > 0")
        ts, ys, _ = _rk4(rhs, t0, y0, t_end, h, t_eval)
        status, message = 0, "fixed-step RK4 completed"
    qs = np.empty((ts.size, nq))
    vs = np.empty((ts.size, model.nv))
    E = np.empty(ts.size)
    C = np.zeros(ts.size)
    for k, (t, y) in enumerate(zip(ts, ys)):
        q, nu, _ = unpack(t, y)
        qs[k], vs[k] = q, nu
        E[k] = alg.kinetic_energy(model, data, q, nu, t) + alg.potential_energy(model, data, q, t)
        if loops:
            C[k] = np.max(np.abs(con.loop_residual(model, data, q, loops, t)))
    if not np.all(np.isfinite(ys)):
        raise SolverFailedError("the integration produced non-finite values (step too large?)")
    return Trajectory(ts, qs, vs, E, C, counter[0], int(status), str(message), form, integrator)
