"""Algorithms on (Model, Data): kinematics, Lagrange and momentum-form dynamics.

Functions in the style of Pinocchio: each takes the model, a Data to fill
and the state, and returns its main result (also left in ``data``).  All are
O(N) in the number of bodies except :func:`mass_matrix` (O(N·depth), the
dense G has that many entries) and :func:`forward_dynamics` (dense Cholesky of
G, O(nv³): the classical Lagrange route, kept for comparison).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from qpcontact.core.errors import InvalidOptionError, InvalidProblemError, SolverFailedError

from . import _kernels as K
from .model import Data, Model

__all__ = ["forward_kinematics", "mass_matrix", "rnea", "nonlinear_effects", "forward_dynamics",
           "momenta", "velocities_from_momenta", "momentum_rhs", "momentum_rate",
           "configuration_rate", "gravity_forces",
           "kinetic_energy", "potential_energy", "point_jacobian", "point_position",
           "integrate", "MassOperator", "METHODS"]

#: Solvers of the momentum form's system (6): "ldlt" (Cholesky factors of the joint blocks,
#: symmetric updates) and "sweep" (block elimination with explicit inverses).
METHODS = ("ldlt", "sweep")


def _fill(model: Model, data: Data, q, v=None, t: float = 0.0, world: bool = True):
    """Joint data (and, if ``world``, world placements) of (q, ν) into data."""
    a = model.arrays
    nu = np.zeros(model.nv) if v is None else v
    data.Rrel, data.rho, data.H, data.Hd = K.relative(
        a["parent"], a["jtype"], a["axes"], a["fixed"], a["mask"], a["R0"], a["r0"],
        a["iq"], a["iv"], q, nu, v is not None)
    Rb, rb, V0, A0 = model.base_state(t)
    if world:
        data.Ra, data.ra = K.absolute(a["parent"], data.Rrel, data.rho, Rb, rb)
    data.t = t
    return a, V0, A0


def forward_kinematics(model: Model, data: Data, q, v=None, t: float = 0.0) -> Data:
    """World placements (data.Ra, data.ra) and, with v, body velocities data.V
    by Ivanov & Shimanovsky's recursions (1)."""
    if v is None:
        q = model.check_state(q)
        _fill(model, data, q, None, t)
        return data
    q, v = model.check_state(q, v)
    a, V0, _ = _fill(model, data, q, v, t)
    data.V = K.velocities(a["parent"], data.Rrel, data.rho, data.H, a["nvj"], a["iv"], v, V0)
    return data


def point_position(model: Model, data: Data, body, point=(0.0, 0.0, 0.0)) -> np.ndarray:
    """World position [m] of a point given in ``body``'s frame (after forward_kinematics)."""
    i = model.body_id(body)
    return data.ra[i] + data.Ra[i] @ np.asarray(point, float)


def point_jacobian(model: Model, data: Data, body, point=(0.0, 0.0, 0.0)):
    """(J, J̇) of a body point in world coordinates after forward_kinematics
    with v: its velocity is J ν [m/s] and its acceleration J ν̇ + J̇ν [m/s²].
    Both are 3 x nv (nonzero on the joints between the base and the body;
    zero for a point of the ground, body 0)."""
    i = model.body_id(body)
    if i == 0:
        return np.zeros((3, model.nv)), np.zeros((3, model.nv))
    a = model.arrays
    x = point_position(model, data, i, point)
    J, Jd = K.point_jacobians(a["parent"], data.Ra, data.ra, data.H, data.Hd, a["nvj"], a["iv"],
                              data.V, i, x, model.nv)
    return J, Jd


def gravity_forces(model: Model, data: Data) -> np.ndarray:
    """Gravity on every body as a spatial force (N+1) x 6 in its own frame
    about its origin (needs world orientations: forward_kinematics first)."""
    a = model.arrays
    g_body = np.einsum("bji,j->bi", data.Ra, model.gravity)      # R_i' g
    F = a["mass"][:, None] * g_body
    f = np.zeros((model.nbodies + 1, 6))
    f[:, :3] = F
    f[:, 3:] = np.cross(a["com"], F)
    f[0] = 0.0
    return f


def _fext(model, fext):
    nb = model.nbodies + 1
    if fext is None:
        return np.zeros((nb, 6))
    f = np.asarray(fext, float)
    if f.shape != (nb, 6):
        raise InvalidProblemError(f"fext must be ({nb}, 6): one spatial force (force, moment about "
                                  f"the body origin, body frame) per body incl. the base; got {f.shape}")
    return f


def _tau(model, tau):
    if tau is None:
        return np.zeros(model.nv)
    tau = np.asarray(tau, float)
    if tau.shape != (model.nv,):
        raise InvalidProblemError(f"tau must have shape ({model.nv},); got {tau.shape}")
    return tau


def mass_matrix(model: Model, data: Data, q) -> np.ndarray:
    """G(q) by the composite-rigid-body recursion (dense nv x nv, symmetric)."""
    q = model.check_state(q)
    a, _, _ = _fill(model, data, q)
    data.G = K.crba(a["parent"], data.Rrel, data.rho, data.H, a["nvj"], a["iv"], a["M"], model.nv)
    return data.G


def rnea(model: Model, data: Data, q, v, a_, fext=None, t: float = 0.0) -> np.ndarray:
    """Inverse dynamics (recursive Newton-Euler): τ = G ν̇ + c(q, ν) - Q_ext,
    with gravity and the base law included in c."""
    q, v = model.check_state(q, v)
    a_ = np.asarray(a_, float)
    if a_.shape != (model.nv,):
        raise InvalidProblemError(f"accelerations must have shape ({model.nv},); got {a_.shape}")
    a, V0, A0 = _fill(model, data, q, v, t)
    return K.rnea(a["parent"], data.Rrel, data.rho, data.H, data.Hd, a["nvj"], a["iv"], a["M"],
                  v, a_, V0, A0, _fext(model, fext))


def nonlinear_effects(model: Model, data: Data, q, v, fext=None, t: float = 0.0) -> np.ndarray:
    """c(q, ν) - Q_ext: gravity, Coriolis/centrifugal, base motion, minus the body forces."""
    return rnea(model, data, q, v, np.zeros(model.nv), fext, t)


def forward_dynamics(model: Model, data: Data, q, v, tau=None, fext=None, t: float = 0.0):
    """Lagrange form: ν̇ = G⁻¹(τ - c) with G by CRBA and a dense Cholesky
    factorization (O(nv³); the O(N) route is the momentum form)."""
    c = nonlinear_effects(model, data, q, v, fext, t)
    G = mass_matrix(model, data, q)
    try:
        cf = scipy.linalg.cho_factor(G, check_finite=False)
    except np.linalg.LinAlgError:
        raise SolverFailedError("the mass matrix G(q) is not positive definite: a body without "
                                "inertia along one of its joint's motions") from None
    return scipy.linalg.cho_solve(cf, _tau(model, tau) - c, check_finite=False)


def momenta(model: Model, data: Data, q, v, t: float = 0.0) -> np.ndarray:
    """Generalized momenta p = ∂T/∂ν = H_i'μ_i; also fills data.V and data.mu
    (the subtree momenta) for the motion (q, ν).  O(N)."""
    forward_kinematics(model, data, q, v, t)
    a = model.arrays
    data.mu = K.subtree(a["parent"], data.Rrel, data.rho, a["M"], data.V)
    return K.project(data.H, a["nvj"], a["iv"], data.mu, model.nv)


def _factor_momentum(model, data, a, method):
    """Factors of the momentum form's system (6) at the joint data in ``data`` (p-independent)."""
    if method not in METHODS:
        raise InvalidOptionError(f"method must be one of {METHODS}; got {method!r}")
    *factors, ok = K.momentum_factor(a["parent"], data.Rrel, data.rho, data.H, a["nvj"], a["M"],
                                     method == "ldlt")
    if not ok:
        raise SolverFailedError("a joint block H_i'Ī_iH_i is not positive definite: some joint "
                                "moves a subtree without inertia (give the bodies mass/inertia "
                                "along every joint motion)")
    return factors


def _apply_momentum(model, data, a, factors, p, V0, method):
    nu, data.V, data.mu = K.momentum_apply(a["parent"], data.Rrel, data.rho, data.H, a["nvj"],
                                           a["iv"], a["M"], *factors, p, V0, method == "ldlt")
    return nu


def _solve_momentum(model, data, a, p, V0, method):
    factors = _factor_momentum(model, data, a, method)
    return _apply_momentum(model, data, a, factors, p, V0, method)


def velocities_from_momenta(model: Model, data: Data, q, p, t: float = 0.0,
                            method: str = "ldlt") -> np.ndarray:
    """ν from (q, p): the momentum form's symmetric indefinite block-tridiagonal system (6),
    O(N) by ``method`` "ldlt" or "sweep".  Also fills data.V and data.mu."""
    q = model.check_state(q)
    p = np.asarray(p, float)
    if p.shape != (model.nv,):
        raise InvalidProblemError(f"p must have shape ({model.nv},); got {p.shape}")
    a, V0, _ = _fill(model, data, q, None, t, world=False)
    return _solve_momentum(model, data, a, p, V0, method)


def momentum_rhs(model: Model, data: Data, t: float, q, p, tau=None, fext=None,
                 method: str = "ldlt"):
    """Hamilton's equations in Ivanov & Shimanovsky's variables: (q̇, ṗ, ν) at (t, q, p).

    ν from system (6); ṗ_i = Ḣ_i'μ_i + H_i'(F_i - V_i ×* μ_i) + τ_i (eq. (7),
    derived in the package docstring) with F_i the gravity and body forces on
    the subtree of i; q̇ = K(q)ν.  O(N).  ``tau`` and ``fext`` may be arrays or
    callables (t, q, ν) -> array."""
    a, V0, _ = _fill(model, data, q, None, t, world=False)
    nu = _solve_momentum(model, data, a, p, V0, method)
    return configuration_rate(model, q, nu), momentum_rate(model, data, t, q, nu, tau, fext), nu


def momentum_rate(model: Model, data: Data, t: float, q, nu, tau=None, fext=None):
    """ṗ at (t, q, ν) from data.V and data.mu of that motion (as left by the
    momentum solve): eq. (7).  Recomputes the joint data with ν (for Ḣ) and
    the world orientations (for gravity)."""
    a, _, _ = _fill(model, data, q, nu, t)
    tau = tau(t, q, nu) if callable(tau) else tau
    fext = fext(t, q, nu) if callable(fext) else fext
    f = gravity_forces(model, data) + _fext(model, fext)
    return K.momentum_rate(a["parent"], data.Rrel, data.rho, data.H, data.Hd, a["nvj"], a["iv"],
                           data.V, data.mu, f, _tau(model, tau))


def configuration_rate(model: Model, q, v) -> np.ndarray:
    """q̇ = K(q)ν (identity except for quaternion joints)."""
    a = model.arrays
    return K.qdot(a["jtype"], a["iq"], a["iv"], a["nqj"], q, v)


def kinetic_energy(model: Model, data: Data, q, v, t: float = 0.0) -> float:
    """T = ½ Σ V_i'M_iV_i [J] (absolute motion, base law included)."""
    forward_kinematics(model, data, q, v, t)
    M = model.arrays["M"]
    return 0.5 * float(np.einsum("bi,bij,bj->", data.V[1:], M[1:], data.V[1:]))


def potential_energy(model: Model, data: Data, q, t: float = 0.0) -> float:
    """Gravity potential -Σ m_i g·x_ci [J] (world frame, origin at 0)."""
    forward_kinematics(model, data, q, None, t)
    a = model.arrays
    xc = data.ra + np.einsum("bij,bj->bi", data.Ra, a["com"])
    return -float(a["mass"][1:] @ (xc[1:] @ model.gravity))


def integrate(model: Model, q, dv) -> np.ndarray:
    """q ⊕ dv: the configuration reached moving with constant joint velocity
    dv for unit time (exact exponential map on quaternion joints; renormalised)."""
    a = model.arrays
    q = np.array(q, float)
    dv = np.asarray(dv, float)
    out = q.copy()
    for i in range(1, model.nbodies + 1):
        s, b, jt = int(a["iq"][i]), int(a["iv"][i]), int(a["jtype"][i])
        if jt in (K.SPHERICAL, K.FREE):
            o = 3 if jt == K.FREE else 0
            quat = q[s + o:s + o + 4]
            w = dv[b + o:b + o + 3]
            if jt == K.FREE:
                # constant body twist: translate along the rotating frame exactly
                out[s:s + 3] = q[s:s + 3] + K.quat_rotation(*quat) @ _se3_left_jacobian(w) @ dv[b:b + 3]
            out[s + o:s + o + 4] = _quat_mul(quat, _quat_exp(w))
        else:
            n = int(a["nqj"][i])
            out[s:s + n] = q[s:s + n] + dv[b:b + n]
    return out


def _quat_exp(w):
    th = float(np.linalg.norm(w))
    if th < 1e-12:
        return np.array([0.5 * w[0], 0.5 * w[1], 0.5 * w[2], 1.0])
    s = np.sin(0.5 * th) / th
    return np.array([s * w[0], s * w[1], s * w[2], np.cos(0.5 * th)])


def _quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    q = np.array([aw * bx + ax * bw + ay * bz - az * by,
                  aw * by - ax * bz + ay * bw + az * bx,
                  aw * bz + ax * by - ay * bx + az * bw,
                  aw * bw - ax * bx - ay * by - az * bz])
    return q / np.linalg.norm(q)


def _se3_left_jacobian(w):
    th = float(np.linalg.norm(w))
    W = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    if th < 1e-8:
        return np.eye(3) + 0.5 * W
    return (np.eye(3) + (1 - np.cos(th)) / th ** 2 * W + (th - np.sin(th)) / th ** 3 * W @ W)


class MassOperator:
    """G(q) as a factorized operator without forming G⁻¹: the momentum-form
    factors of system (6) are computed once; ``solve(r)`` applies G⁻¹ by one
    O(N) pass per right-hand side (the base at rest),
    ``matvec(x)`` applies G by the O(N) momenta recursion, ``toarray()`` forms G
    (CRBA) for those who need it.  Valid for the configuration it was built at."""

    def __init__(self, model: Model, q, method: str = "ldlt"):
        self.model = model
        self.q = model.check_state(q).copy()
        self.method = method
        self._data = Data(model)
        self._a, _, _ = _fill(model, self._data, self.q, world=False)
        self._factors = _factor_momentum(model, self._data, self._a, method)   # once
        self.shape = (model.nv, model.nv)

    def solve(self, r) -> np.ndarray:
        """G⁻¹r for a vector or for each column of a matrix (one O(N) pass each)."""
        r = np.asarray(r, float)
        if r.ndim == 2:
            out = np.zeros((self.model.nv, r.shape[1]))
            for k in range(r.shape[1]):
                out[:, k] = self.solve(r[:, k])
            return out
        return _apply_momentum(self.model, self._data, self._a, self._factors, r, np.zeros(6),
                               self.method)

    def matvec(self, x) -> np.ndarray:
        a, d = self._a, self._data
        return K.momenta(a["parent"], d.Rrel, d.rho, d.H, a["nvj"], a["iv"], a["M"],
                         np.asarray(x, float), np.zeros(6))

    def toarray(self) -> np.ndarray:
        a, d = self._a, self._data
        return K.crba(a["parent"], d.Rrel, d.rho, d.H, a["nvj"], a["iv"], a["M"], self.model.nv)
