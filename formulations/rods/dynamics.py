"""Rod dynamics (Pustovoy, Levin & Krasnorutskiy 2014): one nonlinear BVP in the
arc length per time step, with Park's implicit multistep method — the planar
cantilever and the spatial Kirchhoff rod of :mod:`.statics` in motion
(nondimensional, as there)."""

from __future__ import annotations

import numpy as np

from . import bvp
from .statics import cantilever, cantilever_general, spatial_cantilever, spatial_f

__all__ = ["cantilever_dynamics", "spatial_cantilever_dynamics", "RodMotion", "PARK"]

#: Backward-difference velocity formulas ẋ_{n+1} = (Σ_i a_i x_{n+1-i}) / h:
#: BDF1, BDF2 and Park's stiffly stable three-step formula (the rod paper's choice).
PARK = {1: (1.0, -1.0), 2: (1.5, -2.0, 0.5), 3: (10 / 6, -15 / 6, 6 / 6, -1 / 6)}


class RodMotion:
    """A rod's motion: times ``t``, the states ``y`` per step (on ``mesh``; rows
    as the calling function says), the tip positions ``tip`` (the rows
    ``position`` at s = 1), Newton steps per time step, and how it ended
    (``status``, ``message``)."""

    def __init__(self, mesh, t, states, newton, status, message, position):
        self.mesh, self.t, self.y = mesh, np.array(t), states
        self.tip = np.array([Y[position, -1] for Y in states])
        self.newton = newton
        self.status, self.message = status, message
        self.ok = status == "solved"


def _park_march(mesh, Y0, position, t_end, h, order, tol, step_problem,
                on_step=None) -> RodMotion:
    """March a rod in time, one BVP per step: r̈_{n+1} = c² r_{n+1} + history
    (c = a₀/h) by the backward-difference formula of ``order`` applied twice
    (ẋ from x, ẍ from ẋ).  ``position``: the rows of r in the state;
    ``step_problem(t, c, hist) -> (f, bc, jac)`` the step's BVP given the
    history term (rows as r); ``on_step(step, n_steps, Y)`` after each step.
    The rod rests before t = 0 (constant history)."""
    if order not in PARK:
        from qpcontact.core.errors import InvalidOptionError

        raise InvalidOptionError(f"order must be 1, 2 or 3 (BDF1, BDF2, Park); got {order}")
    a = np.array(PARK[order])
    c = a[0] / h
    k = len(a) - 1
    X = [Y0[position].copy() for _ in range(k)]      # r_n, r_{n-1}, ...
    V = [np.zeros_like(X[0]) for _ in range(k)]
    Y = Y0.copy()
    states, times, newton = [Y0], [0.0], []
    n_steps = int(round(t_end / h))
    for step in range(1, n_steps + 1):
        t = step * h
        Xh = sum(a[i + 1] * X[i] for i in range(k)) / h    # ẋ = c x + Xh
        Vh = sum(a[i + 1] * V[i] for i in range(k)) / h    # ẍ = c ẋ + Vh = c² x + c Xh + Vh
        f, bc, jac = step_problem(t, c, c * Xh + Vh)
        res = bvp.solve(f, bc, mesh, Y, jac=jac, tol=tol, corrections=1, max_refinements=0)
        if not res.residual <= 1e-8 * max(1.0, float(np.max(np.abs(res.y)))):
            return RodMotion(mesh, times, states, newton, res.status,
                             f"time step {step} (t = {t:.4g}): {res.message}", position)
        Y = res.y
        r = Y[position]
        X = [r.copy()] + X[:-1]
        V = [c * r + Xh] + V[:-1]
        states.append(Y.copy())
        times.append(t)
        newton.append(res.newton_steps)
        if on_step is not None:
            on_step(step, n_steps, Y)
    return RodMotion(mesh, times, states, newton, "solved",
                     f"{n_steps} steps of h = {h:g} (order {order}), "
                     f"{np.mean(newton) if newton else 0:.1f} Newton steps per step", position)


def cantilever_dynamics(alpha0: float, t_end: float, h: float, *, tip_load=None,
                        follower=None, distributed=(0.0, 0.0), extensibility: float = 0.0,
                        nodes: int = 41, tol: float = 1e-9, order: int = 3,
                        on_step=None) -> RodMotion:
    """Large planar motion of an inextensible cantilever (rotary inertia
    neglected), released at t = 0 from its static equilibrium under a
    transverse tip load α0 = PL²/EI.

    Nondimensional: s = S/L, time in units of L²√(ρA/EI), forces × L²/EI.
    Unknowns along s: θ, κ = θ' (= ML/EI), x, y and the internal force F (on
    the part [0, s] from the part beyond s)::

        θ' = κ,  κ' = F_x sin θ - F_y cos θ,  x' = cos θ,  y' = sin θ,
        F' = r̈ - q            (the element's momentum balance),

    clamped at s = 0 (θ = x = y = 0), free at s = 1 (κ = 0, F = tip load).
    Time: r̈_{n+1} by Park's three-step formula applied twice (ẋ from x, ẍ
    from ẋ; ``order`` 1 or 2 for BDF1/BDF2), so each step is one nonlinear BVP
    in s with F' = (a₀/h)² r_{n+1} + history — solved by :mod:`.bvp` on a
    fixed mesh.  The rod was at rest before t = 0 (constant history).
    ``tip_load(t) -> (P_x, P_y)`` for t > 0 (default none: free vibration);
    ``follower(t) -> P`` a tip load of magnitude P that stays perpendicular
    to the tip's tangent, (P sin θ(1), -P cos θ(1)) (downward when straight);
    ``distributed`` (q_x, q_y) per unit length (gravity: (0, -ρAgL³/EI));
    ``extensibility`` β = EI/(EA L²): the axial strain ε = β F_t (F_t the
    internal force along the tangent) stretches the centreline, x' = (1 + ε)
    cos θ, y' = (1 + ε) sin θ, and the moment's lever arm, κ' = (1 + ε)(F_x
    sin θ - F_y cos θ); the released static state is then the extensible
    one (:func:`cantilever_general`).  s and ρA stay per unstretched length.
    ``on_step(step, n_steps, Y)`` after each step (progress).
    ``RodMotion.y`` rows: θ, κ, x, y, F_x, F_y; ``tip`` holds (x, y).
    """
    mesh = np.linspace(0.0, 1.0, nodes)
    Y0 = np.zeros((6, nodes))
    Y0[2] = mesh
    beta = float(extensibility)
    if alpha0:
        start = (cantilever_general(alpha0, extensibility=beta, nodes=nodes, tol=tol) if beta
                 else cantilever(alpha0, nodes=nodes, tol=tol))
        if not start.ok:
            return RodMotion(mesh, [0.0], [Y0], [], start.status, f"initial state: {start.message}",
                             slice(2, 4))
        Y0[:4] = start(mesh)[:4]
        Y0[5] = -alpha0
    qx, qy = (float(v) for v in distributed)

    def step_problem(t, c, hist):
        P = (0.0, 0.0) if tip_load is None else tuple(float(v) for v in tip_load(t))
        Pf = 0.0 if follower is None else float(follower(t))

        def f(s, Yv):
            th, ka, x, y, Fx, Fy = Yv
            cs, sn = np.cos(th), np.sin(th)
            e = 1.0 + beta * (Fx * cs + Fy * sn)          # stretch 1 + ε
            return np.array([ka, e * (Fx * sn - Fy * cs), e * cs, e * sn,
                             c * c * x + hist[0] - qx, c * c * y + hist[1] - qy])

        def jac(s, Yv):
            th, ka, x, y, Fx, Fy = Yv
            cs, sn = np.cos(th), np.sin(th)
            m, Ft = Fx * sn - Fy * cs, Fx * cs + Fy * sn
            e = 1.0 + beta * Ft
            J = np.zeros((6, 6, th.size))
            J[0, 1] = 1.0
            J[1, 0] = e * Ft - beta * m * m
            J[1, 4] = e * sn + beta * m * cs
            J[1, 5] = -e * cs + beta * m * sn
            J[2, 0] = -e * sn - beta * m * cs
            J[3, 0] = e * cs - beta * m * sn
            J[2, 4], J[2, 5] = beta * cs * cs, beta * cs * sn
            J[3, 4], J[3, 5] = beta * sn * cs, beta * sn * sn
            J[4, 2] = c * c
            J[5, 3] = c * c
            return J

        def bc(ya, yb):
            return np.array([ya[0], ya[2], ya[3], yb[1], yb[4] - P[0] - Pf * np.sin(yb[0]),
                             yb[5] - P[1] + Pf * np.cos(yb[0])])

        return f, bc, jac

    return _park_march(mesh, Y0, slice(2, 4), t_end, h, order, tol, step_problem, on_step)


def spatial_cantilever_dynamics(force0=(0.0, 0.0, 0.0), t_end: float = 1.0, h: float = 0.05, *,
                                tip_force=None, moment0=(0.0, 0.0, 0.0), torsion_ratio: float = 1.0,
                                nodes: int = 41, tol: float = 1e-8, order: int = 3) -> RodMotion:
    """Spatial motion of the Kirchhoff cantilever of :func:`spatial_cantilever`
    (rotary inertia neglected), released at t = 0 from its static equilibrium
    under ``force0``/``moment0``; ``tip_force(t) -> (3,)`` for t > 0 (default
    none).  The statics' n' = 0 becomes the momentum balance n' = r̈ with r̈ by
    Park's formula (see :func:`cantilever_dynamics`; units likewise): one
    13-unknown BVP per step.  ``RodMotion.y`` rows: r, q, n, m; ``tip`` holds
    (x, y, z)."""
    Binv = np.array([1.0 / torsion_ratio, 1.0, 1.0])[:, None]
    start = spatial_cantilever(force0, moment0, torsion_ratio=torsion_ratio, nodes=nodes, tol=tol)
    mesh = np.linspace(0.0, 1.0, nodes)
    if not start.ok:
        return RodMotion(mesh, [0.0], [np.zeros((13, nodes))], [], start.status,
                         f"initial state: {start.message}", slice(0, 3))

    def step_problem(t, c, hist):
        F = np.zeros(3) if tip_force is None else np.asarray(tip_force(t), float)

        def f(s, Yv):
            out = spatial_f(Yv, Binv)
            out[7:10] = c * c * Yv[0:3] + hist
            return out

        def bc(ya, yb):
            return np.concatenate([ya[0:3], ya[3:7] - np.array([1.0, 0, 0, 0]), yb[7:10] - F,
                                   yb[10:13]])

        return f, bc, None

    return _park_march(mesh, start(mesh), slice(0, 3), t_end, h, order, tol, step_problem)
