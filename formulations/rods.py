"""Thin rods with large deflections (P1): the planar inextensible elastica
under a dead load, solved by qpcontact.bvp, and what builds on it.

Nondimensional: arc length s in [0, 1] (s = S/L), load parameter α = P L²/EI,
positions x, y in units of L.  Unknowns y = (θ, κ, x, y): the tangent angle,
the curvature θ' (= M L/EI), and the centreline.  Clamped at s = 0
(θ = x = y = 0), free at s = 1 (κ = 0).

- Cantilever, transverse dead tip load P downward: EI θ'' = P cos θ
  (the moment of the tip load about a section), so θ' = κ, κ' = α cos θ.
- Column, axial dead load P along -x at the free end: θ'' = -α sin θ; the
  straight state is a solution for every α, the buckled branch leaves it at
  α_cr = π²/4.

Columns: clamped-free or pinned-pinned.  :func:`cantilever_general` adds
follower loads and extensibility; :func:`spatial_cantilever` is the spatial
Kirchhoff rod (statics); :func:`cantilever_dynamics` and
:func:`spatial_cantilever_dynamics` their motion, one BVP per time step with
Park's implicit multistep method (P1).
"""

from __future__ import annotations

import numpy as np

from qpcontact import bvp

__all__ = ["cantilever", "cantilever_general", "column", "cantilever_curve", "tip_deflection",
           "cantilever_dynamics", "spatial_cantilever_dynamics", "RodMotion",
           "spatial_cantilever"]


def _cantilever_f(s, Y, alpha):
    th, ka, x, y = Y
    return np.array([ka, alpha * np.cos(th), np.cos(th), np.sin(th)])


def _column_f(s, Y, alpha):
    th, ka, x, y = Y
    return np.array([ka, -alpha * np.sin(th), np.cos(th), np.sin(th)])


def _bc(ya, yb, *_):
    return np.array([ya[0], ya[2], ya[3], yb[1]])


def tip_deflection(res) -> float:
    """δ_v / L: the downward deflection of the free end."""
    return float(-res.y[3, -1])


def cantilever(alpha: float, *, nodes: int = 81, tol: float = 1e-8, continuation: bool = True):
    """Cantilever under a transverse dead tip load α = PL²/EI, from a straight
    initial guess.  Newton alone converges up to α ≈ 10; beyond, the load is
    reached by pseudo-arclength continuation in log10 α from α = 0.01 (on the
    same mesh) and the last point is refined to ``tol``.  Returns a BVPResult."""
    mesh = np.linspace(0.0, 1.0, nodes)
    f = lambda s, Y: _cantilever_f(s, Y, alpha)  # noqa: E731
    res = bvp.solve(f, _bc, mesh, np.zeros(4), tol=tol)
    if res.ok or not continuation:
        return res
    path = bvp.continuation(lambda s, Y, g: _cantilever_f(s, Y, 10.0 ** g), _bc, mesh, np.zeros(4),
                            (-2.0, np.log10(alpha)), ds=0.2, ds_max=1.0)
    if path.status != "solved":
        return bvp.BVPResult(mesh, path.ys[-1], path.status, False, path.message, np.inf, np.inf,
                             2, 0)
    return bvp.solve(f, _bc, mesh, path.ys[-1], tol=tol)


def cantilever_curve(alpha_max: float, nodes: int = 81):
    """The load-deflection path α -> δ_v/L from 0.01 to ``alpha_max`` by continuation."""
    mesh = np.linspace(0.0, 1.0, nodes)
    path = bvp.continuation(lambda s, Y, g: _cantilever_f(s, Y, 10.0 ** g), _bc, mesh, np.zeros(4),
                            (-2.0, np.log10(alpha_max)), ds=0.2, ds_max=1.0)
    return 10.0 ** path.gammas, np.array([-Y[3, -1] for Y in path.ys]), path


def _pinned_bc(ya, yb, *_):
    # pins at both ends on the x axis: no moment at either end, the first end fixed
    # (y(1) = 0 follows from EI θ' = -P y with κ(1) = 0)
    return np.array([ya[1], ya[2], ya[3], yb[1]])


_ENDS = {
    # name: (boundary conditions, critical load, start load, buckling-mode guess)
    "clamped-free": (_bc, np.pi ** 2 / 4, 2.6,
                     lambda s: np.array([0.8 * np.sin(np.pi * s / 2), 0.4 * np.pi * np.cos(np.pi * s / 2),
                                         s, 0.5 * (1 - np.cos(np.pi * s / 2))])),
    "pinned-pinned": (_pinned_bc, np.pi ** 2, 10.5,
                      lambda s: np.array([0.6 * np.cos(np.pi * s), -0.6 * np.pi * np.sin(np.pi * s),
                                          s, 0.6 / np.pi * np.sin(np.pi * s)])),
}


def column(alpha: float, *, ends: str = "clamped-free", nodes: int = 81, tol: float = 1e-8):
    """The buckled branch of a column under an axial dead load α = PL²/EI above
    its Euler load (π²/4 clamped-free, π² pinned-pinned): started just above the
    critical load from the buckling mode and continued in α.  Returns
    (BVPResult at α, the continuation path)."""
    if ends not in _ENDS:
        from qpcontact.core.errors import InvalidOptionError

        raise InvalidOptionError(f"ends must be one of {list(_ENDS)}, not {ends!r}")
    bc, a_cr, a0, mode = _ENDS[ends]
    if not alpha > a_cr:
        from qpcontact.core.errors import InvalidOptionError

        raise InvalidOptionError(f"alpha = {alpha} is below the Euler load {a_cr:.6g}: the straight "
                                 "column is the only equilibrium")
    mesh = np.linspace(0.0, 1.0, nodes)
    start = bvp.solve(lambda s, Y: _column_f(s, Y, a0), bc, mesh, mode(mesh), tol=tol)
    if alpha <= a0:
        end = bvp.solve(lambda s, Y: _column_f(s, Y, alpha), bc, start.mesh, start.y, tol=tol)
        return end, None
    path = bvp.continuation(_column_f, bc, start.mesh, start.y, (a0, alpha), ds=0.1, ds_max=0.5)
    end = bvp.solve(lambda s, Y: _column_f(s, Y, alpha), bc, path.mesh, path.ys[-1], tol=tol)
    return end, path


def cantilever_general(alpha: float, *, follower: bool = False, extensibility: float = 0.0,
                       nodes: int = 81, tol: float = 1e-8):
    """Cantilever with a transverse tip load α = PL²/EI that is dead (fixed
    direction, downward) or a *follower* (stays perpendicular to the tip
    tangent), and an extensible rod with β = EI/(EA L²) (0: inextensible).

    Extensible: the axial strain is ε = α β F_t (F_t the load's component along
    the tangent, in units of P), x' = (1 + ε) cos θ, y' = (1 + ε) sin θ and the
    moment equation picks up the stretched lever arm, κ' = -α (1 + ε)(r̂' × f̂).
    A follower load depends on the unknown tip angle θ_L, carried as a fifth
    unknown with θ_L' = 0 and θ_L = θ(1).  Continuation in log10 α from 0.01
    when Newton alone does not converge.  Returns a BVPResult (rows θ, κ, x,
    y, θ_L)."""
    beta = float(extensibility)

    def f(s, Y, g):
        a = 10.0 ** g
        th, ka, x, y, thL = Y
        fx, fy = (np.sin(thL), -np.cos(thL)) if follower else (0.0 * th, -1.0 + 0.0 * th)
        ft = fx * np.cos(th) + fy * np.sin(th)         # along the tangent
        cross = np.cos(th) * fy - np.sin(th) * fx       # (t x f)_z
        stretch = 1.0 + a * beta * ft
        return np.array([ka, -a * stretch * cross, stretch * np.cos(th), stretch * np.sin(th),
                         0.0 * th])

    def bc(ya, yb, *_):
        return np.array([ya[0], ya[2], ya[3], yb[1], yb[4] - yb[0]])

    mesh = np.linspace(0.0, 1.0, nodes)
    g = np.log10(alpha)
    res = bvp.solve(lambda s, Y: f(s, Y, g), bc, mesh, np.zeros(5), tol=tol)
    if res.ok:
        return res
    path = bvp.continuation(f, bc, mesh, np.zeros(5), (-2.0, g), ds=0.2, ds_max=1.0)
    if path.status != "solved":
        return bvp.BVPResult(mesh, path.ys[-1], path.status, False, path.message, np.inf, np.inf, 2, 0)
    return bvp.solve(lambda s, Y: f(s, Y, g), bc, mesh, path.ys[-1], tol=tol)


# -- the spatial rod (statics) ----------------------------------------------------------

def _qmul(p, q):
    """Quaternion product, arrays (4, N): (w, x, y, z)."""
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return np.array([pw * qw - px * qx - py * qy - pz * qz,
                     pw * qx + px * qw + py * qz - pz * qy,
                     pw * qy - px * qz + py * qw + pz * qx,
                     pw * qz + px * qy - py * qx + pz * qw])


def _rotate(q, v):
    """R(q) v for quaternions q (4, N) and vectors v (3, N)."""
    w, x, y, z = q
    R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                  [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                  [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
    return np.einsum("ijn,jn->in", R, v)


def _rotate_T(q, v):
    """R(q)' v."""
    conj = q * np.array([1.0, -1.0, -1.0, -1.0])[:, None]
    return _rotate(conj, v)


def _spatial_f(Y, Binv):
    """Right-hand side of the spatial rod's statics (rows r, q, n, m), n' = 0."""
    N = Y.shape[1]
    q, n, m = Y[3:7], Y[7:10], Y[10:13]
    t = _rotate(q, np.repeat(np.array([[1.0], [0.0], [0.0]]), N, axis=1))
    kappa = Binv * _rotate_T(q, m)
    dq = 0.5 * _qmul(q, np.vstack([np.zeros(N), kappa]))
    dm = -np.cross(t.T, n.T).T
    return np.vstack([t, dq, np.zeros((3, N)), dm])


def spatial_cantilever(force=(0.0, 0.0, 0.0), moment=(0.0, 0.0, 0.0), *, torsion_ratio: float = 1.0,
                       nodes: int = 81, tol: float = 1e-8, steps: int = 20):
    """A spatial, inextensible and unshearable Kirchhoff rod clamped at s = 0
    along x, loaded at its free end by a dead ``force`` and ``moment`` (units:
    force x L²/EI, moment x L/EI, i.e. nondimensional), ``torsion_ratio`` =
    GJ/EI.  Unknowns (13): position r, orientation quaternion q (body axis 1 =
    the tangent), internal force n and moment m (global frame):

        r' = R(q) e1,   q' = ½ q ⊗ (0, κ),   κ = B⁻¹ R(q)' m,   n' = 0,   m' = -r' × n,

    B = diag(GJ/EI, 1, 1).  P1 uses 12 unknowns with three finite-rotation
    parameters; the quaternion (norm kept by the equations) avoids their
    singularity and keeps the right-hand side polynomial.  The load is applied
    in ``steps`` increments (natural-parameter continuation).  Returns a
    BVPResult with rows (r, q, n, m)."""
    F = np.asarray(force, float)
    Mo = np.asarray(moment, float)
    Binv = np.array([1.0 / torsion_ratio, 1.0, 1.0])[:, None]

    def fun_for(lam):
        def f(s, Y):
            return _spatial_f(Y, Binv)

        def bc(ya, yb):
            return np.concatenate([ya[0:3], ya[3:7] - np.array([1.0, 0, 0, 0]),
                                   yb[7:10] - lam * F, yb[10:13] - lam * Mo])
        return f, bc

    mesh = np.linspace(0.0, 1.0, nodes)
    Y = np.zeros((13, nodes))
    Y[0] = mesh
    Y[3] = 1.0
    # intermediate load steps on the base mesh (no refinement: they only feed the
    # next step's initial guess); the full load is solved to ``tol``
    for lam in np.linspace(0.0, 1.0, steps + 1)[1:-1]:
        f, bc = fun_for(lam)
        res = bvp.solve(f, bc, mesh, Y, tol=1e-6, corrections=0, max_refinements=0)
        if not res.residual <= 1e-8 * max(1.0, float(np.max(np.abs(res.y)))):  # Newton failed
            res.message = f"load step {lam:.3g}: {res.message}"
            return res
        Y = res.y
    f, bc = fun_for(1.0)
    return bvp.solve(f, bc, mesh, Y, tol=tol)


# -- rod dynamics: one BVP per time step (P1) ---------------------------------------------

#: Backward-difference velocity formulas ẋ_{n+1} = (Σ_i a_i x_{n+1-i}) / h:
#: BDF1, BDF2 and Park's stiffly stable three-step formula (P1's choice).
_PARK = {1: (1.0, -1.0), 2: (1.5, -2.0, 0.5), 3: (10 / 6, -15 / 6, 6 / 6, -1 / 6)}


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
    if order not in _PARK:
        from qpcontact.core.errors import InvalidOptionError

        raise InvalidOptionError(f"order must be 1, 2 or 3 (BDF1, BDF2, Park); got {order}")
    a = np.array(_PARK[order])
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
    the part [0, s] from the part beyond s):

        θ' = κ,  κ' = F_x sin θ - F_y cos θ,  x' = cos θ,  y' = sin θ,
        F' = r̈ - q            (the element's momentum balance),

    clamped at s = 0 (θ = x = y = 0), free at s = 1 (κ = 0, F = tip load).
    Time: r̈_{n+1} by Park's three-step formula applied twice (ẋ from x, ẍ
    from ẋ; ``order`` 1 or 2 for BDF1/BDF2), so each step is one nonlinear BVP
    in s with F' = (a₀/h)² r_{n+1} + history — solved by qpcontact.bvp on a
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
            out = _spatial_f(Yv, Binv)
            out[7:10] = c * c * Yv[0:3] + hist
            return out

        def bc(ya, yb):
            return np.concatenate([ya[0:3], ya[3:7] - np.array([1.0, 0, 0, 0]), yb[7:10] - F,
                                   yb[10:13]])

        return f, bc, None

    return _park_march(mesh, start(mesh), slice(0, 3), t_end, h, order, tol, step_problem)


# -- scene files (qpcontact.scenes): formulation "rod" ------------------------------
#
# A planar cantilever's large motion (cantilever_dynamics) in SI units: length
# L [m], bending stiffness EI [N·m²], mass per length ρA [kg/m].  The scales:
# positions × L, forces × EI/L², distributed loads × EI/L³, time × T₀ =
# L²√(ρA/EI).

def _pulse(value, until, scale, T0):
    """A load [N] acting while t < until [s], as a function of the
    nondimensional time, in units of ``scale``."""
    value = np.asarray(value, float) / scale
    zero = 0.0 * value
    if until is None:
        return lambda tau: value
    return lambda tau: value if tau * T0 < until else zero


def _rod_build(scene):
    from qpcontact.core.errors import SolverFailedError

    d, eff = scene.data, scene.effect_params
    rod, init, time_ = d["rod"], d["initial"], d["time"]
    if time_["order"] not in _PARK:
        scene.fail(f"order must be 1 (BDF1), 2 (BDF2) or 3 (Park); got {time_['order']}",
                   ("time",), "order")
    if rod["nodes"] < 5:
        scene.fail(f"nodes must be at least 5; got {rod['nodes']}", ("rod",), "nodes")
    L, EI, rhoA = rod["length"], rod["EI"], rod["mass_per_length"]
    T0 = L * L * np.sqrt(rhoA / EI)
    force = EI / L ** 2
    steps = time_["steps"]
    dead = eff.get("dead_load")
    fol = eff.get("follower_load")
    tip = None if dead is None else _pulse((dead["fx"], dead["fy"]), dead["until"], force, T0)
    follower = None if fol is None else _pulse(fol["force"], fol["until"], force, T0)
    g = eff["gravity"]["g"] if "gravity" in eff else 0.0
    distributed = (0.0, -rhoA * g * L ** 3 / EI)
    beta = EI / (eff["extensibility"]["EA"] * L * L) if "extensibility" in eff else 0.0
    # what the step's BVP is built from: only the named effects' loads
    model = {"L": L, "EI": EI, "rhoA": rhoA, "T0": T0, "g": g, "effects": scene.effects,
             "distributed": distributed, "dead_load": tip, "follower_load": follower,
             "extensibility": beta}

    def run(progress: bool = False, resume=None, checkpoint=None, checkpoint_seconds=5.0):
        from qpcontact.core.progress import ProgressBar

        if resume is not None:
            scene.fail("--resume is not supported for rod scenes (the march's state is its "
                       "multistep history); run it afresh", ("time",))
        bar = ProgressBar(steps, "rod steps", progress, transient=True, unit="steps")
        motion = cantilever_dynamics(init["preload"] / force, steps * time_["h"] / T0,
                                     time_["h"] / T0, tip_load=tip, follower=follower,
                                     distributed=distributed, extensibility=beta,
                                     nodes=rod["nodes"],
                                     order=time_["order"],
                                     on_step=lambda k, n, Y: bar.update(k, f"{k} of {n}"))
        bar.close()
        if not motion.ok:
            raise SolverFailedError(f"the rod's march stopped: {motion.message}; the states "
                                    f"up to t = {motion.t[-1] * T0:.4g} s were solved")
        result = RodRun(model, motion)
        if checkpoint is not None:
            checkpoint(result)
        return result
    run.total_steps = steps
    return model, run


class RodRun:
    """A rod scene's motion in SI units: times ``t`` [s], the centreline
    ``x``, ``y`` [m] and tangent angle ``theta`` [rad] per step (rows) and
    node, the root moment ``root_moment`` [N·m], the Newton steps per step,
    and the energy [J]: bending ½∫EI κ² dS, kinetic ½∫ρA|ṙ|² dS with ṙ by
    backward differences of the positions, gravity potential ∫ρA g y dS
    (zero without gravity); the tip loads' work is not in it."""

    def __init__(self, model, motion: RodMotion):
        L, EI = model["L"], model["EI"]
        Y = np.array(motion.y)
        self.model, self.motion = model, motion
        self.t = motion.t * model["T0"]
        self.s = motion.mesh * L
        self.theta, self.x, self.y = Y[:, 0], Y[:, 2] * L, Y[:, 3] * L
        kappa = Y[:, 1] / L
        self.root_moment = EI * kappa[:, 0]
        self.newton = np.concatenate([[0], motion.newton])
        w = np.full_like(self.s, self.s[1] - self.s[0])
        w[[0, -1]] *= 0.5                                   # the trapezoid rule's weights
        self.bending = 0.5 * EI * (kappa ** 2) @ w
        vx, vy = np.zeros_like(self.x), np.zeros_like(self.y)
        dt = np.diff(self.t)[:, None]
        vx[1:], vy[1:] = np.diff(self.x, axis=0) / dt, np.diff(self.y, axis=0) / dt
        self.kinetic = 0.5 * model["rhoA"] * (vx ** 2 + vy ** 2) @ w
        self.potential = model["rhoA"] * model["g"] * self.y @ w


def _rod_arrays(result) -> dict:
    return {"t": result.t, "s": result.s, "x": result.x, "y": result.y, "theta": result.theta,
            "tip": np.column_stack([result.x[:, -1], result.y[:, -1]]),
            "root_moment": result.root_moment, "newton_steps": result.newton,
            "energy/bending": result.bending, "energy/kinetic": result.kinetic,
            "energy/potential": result.potential}


def _rod_plot(h, out) -> list:
    """The tip's path against time, snapshots of the centreline, the root
    moment and the energy — from the file."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure

    t = h["t"][()]
    x, y, tip = h["x"][()], h["y"][()], h["tip"][()]
    fig, ax = plt.subplots(2, 2, figsize=(10, 7))
    ax[0, 0].plot(t, tip[:, 0], label="tip x")
    ax[0, 0].plot(t, tip[:, 1], label="tip y")
    ax[0, 0].set_ylabel("tip position [m]")
    ax[0, 0].legend(fontsize=8)
    for k in np.linspace(0, len(t) - 1, 8).astype(int):
        ax[0, 1].plot(x[k], y[k], lw=1, label=f"t = {t[k]:.3g} s")
    ax[0, 1].set_aspect("equal")
    ax[0, 1].set_xlabel("x [m]")
    ax[0, 1].set_ylabel("y [m]")
    ax[0, 1].legend(fontsize=6)
    ax[1, 0].plot(t, h["root_moment"][()])
    ax[1, 0].set_ylabel("root moment [N·m]")
    ax[1, 0].set_xlabel("t [s]")
    Eb, Ek, Ep = (h[f"energy/{k}"][()] for k in ("bending", "kinetic", "potential"))
    for e, lab in ((Eb, "bending"), (Ek, "kinetic (backward differences)"),
                   (Ep, "gravity potential"), (Eb + Ek + Ep, "sum")):
        ax[1, 1].plot(t, e, label=lab)
    ax[1, 1].set_ylabel("energy [J]")
    ax[1, 1].set_xlabel("t [s]")
    ax[1, 1].legend(fontsize=8)
    for a in ax.flat:
        a.grid(True, alpha=0.3)
    fig.tight_layout()
    return [save_figure(fig, f"{out}/rod.png")]


def _rod_schema():
    from qpcontact.scenes.schema import Field, SceneSchema

    until = Field("float", "s", "the load acts while t < until (default: always)")
    return SceneSchema(
        formulation="rod",
        doc="a planar cantilever's large motion (P1): one BVP per time step",
        sections={
            "rod": {
                "length": Field("float", "m", "length L", required=True, positive=True),
                "EI": Field("float", "N·m²", "bending stiffness", required=True, positive=True),
                "mass_per_length": Field("float", "kg/m", "ρA", required=True, positive=True),
                "nodes": Field("int", "", "mesh nodes along the rod", default=41, positive=True),
            },
            "initial": {
                "preload": Field("float", "N", "transverse dead tip load (downward) of the "
                                 "static state the rod is released from", default=0.0),
            },
            "time": {
                "h": Field("float", "s", "step size", required=True, positive=True),
                "steps": Field("int", "", "number of steps", required=True, positive=True),
                "order": Field("int", "", "1 (BDF1), 2 (BDF2) or 3 (Park)", default=3,
                               positive=True),
            },
        },
        effects={
            "gravity": {"g": Field("float", "m/s²", "gravitational acceleration (−y)",
                                   default=9.81, positive=True)},
            "dead_load": {"fx": Field("float", "N", "tip force x (fixed direction)", default=0.0),
                          "fy": Field("float", "N", "tip force y (fixed direction)", default=0.0),
                          "until": until},
            "extensibility": {"EA": Field("float", "N", "axial stiffness (inextensible "
                                          "without the effect)", required=True, positive=True)},
            "follower_load": {"force": Field("float", "N", "tip force perpendicular to the "
                                             "tip's tangent (downward when straight)",
                                             required=True),
                              "until": until},
        },
        build=_rod_build, arrays=_rod_arrays, plot=_rod_plot,
        summary=lambda r: {"max_tip_deflection [m]": float(-r.y[:, -1].min()),
                           "max_root_moment [N·m]": float(np.abs(r.root_moment).max())})


SCENE = _rod_schema()
