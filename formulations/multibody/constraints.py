"""Closed loops: extra geometric constraints Φ(q) = 0 on a tree.

Two ways to close them (Ivanov & Shimanovsky's comparison):

**Momentum form, closed by the constraint itself.**  With p = Gν the true
momenta, ṗ = F(q, ν) + J_c'λ.  Integrate instead p̄ = p + J_c'σ with σ̇ = -λ:
then ṗ̄ = F(q, ν) + J̇_c'σ — λ never appears — and at each instant (ν, σ)
solve

    G ν + J_c'σ = p̄,     J_c ν = -α Φ(q),

the velocity-level constraint with first-order Baumgarte stabilisation α
[1/s]: a violation decays like e^{-αt}, without oscillation.  Each G⁻¹ is the
O(N) momentum-form solve; the Schur complement J_c G⁻¹ J_c' is m x m.

**Lagrange form, differentiated twice** (the classical index-1 DAE):

    G ν̇ - J_c'λ = τ - c,    J_c ν̇ = -J̇_cν - 2αΦ̇ - β²Φ,

with α = β = 0 the unstabilised form whose position drift grows with time.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from qpcontact.core.errors import InvalidProblemError, SolverFailedError

from . import algorithms as alg
from .model import Data, Model

__all__ = ["PointLoop", "loop_residual", "loop_jacobian", "assemble_loop_state"]


@dataclass
class PointLoop:
    """Point ``point_a`` of body ``body_a`` coincides with point ``point_b`` of
    body ``body_b`` (body 0: a ground point) along the world ``axes``
    (indices among x, y, z; (0, 1) for a planar loop)."""

    body_a: object
    point_a: tuple
    body_b: object
    point_b: tuple
    axes: tuple = (0, 1, 2)


def _rows(model, data, loops):
    Phi, J, Jd = [], [], []
    for lp in loops:
        ax = list(lp.axes)
        xa = alg.point_position(model, data, lp.body_a, lp.point_a)
        xb = alg.point_position(model, data, lp.body_b, lp.point_b)
        Ja, Jda = alg.point_jacobian(model, data, lp.body_a, lp.point_a)
        Jb, Jdb = alg.point_jacobian(model, data, lp.body_b, lp.point_b)
        Phi.append((xb - xa)[ax])
        J.append((Jb - Ja)[ax])
        Jd.append((Jdb - Jda)[ax])
    if not loops:
        return np.zeros(0), np.zeros((0, model.nv)), np.zeros((0, model.nv))
    return np.concatenate(Phi), np.vstack(J), np.vstack(Jd)


def loop_residual(model: Model, data: Data, q, loops, t: float = 0.0) -> np.ndarray:
    """Φ(q) [m] of the loops."""
    alg.forward_kinematics(model, data, q, np.zeros(model.nv), t)
    return _rows(model, data, loops)[0]


def loop_jacobian(model: Model, data: Data, q, v, loops, t: float = 0.0):
    """(Φ, J_c, J̇_c) at (q, ν): Φ̇ = J_cν, Φ̈ = J_cν̇ + J̇_cν."""
    alg.forward_kinematics(model, data, q, v, t)
    return _rows(model, data, loops)


def assemble_loop_state(model: Model, q_guess, v_guess, loops, fixed=(), tol: float = 1e-13,
                        max_iter: int = 50):
    """A consistent initial state: Newton on Φ(q) = 0 moving only the
    coordinates not listed in ``fixed`` (indices into ν; revolute/prismatic
    coordinates), then ν projected onto J_cν = 0 keeping ``fixed`` velocities."""
    data = Data(model)
    q = np.array(q_guess, float)
    free = np.setdiff1d(np.arange(model.nv), np.asarray(fixed, int))
    for _ in range(max_iter):
        Phi, J, _ = loop_jacobian(model, data, q, np.zeros(model.nv), loops)
        if np.max(np.abs(Phi), initial=0.0) < tol:
            break
        dq = np.zeros(model.nv)
        dq[free] = np.linalg.lstsq(J[:, free], -Phi, rcond=None)[0]
        q = alg.integrate(model, q, dq)
    else:
        raise SolverFailedError(f"the loops could not be closed from this guess (|Φ| = "
                                f"{np.max(np.abs(Phi)):.3g} m after {max_iter} Newton steps)")
    _, J, _ = loop_jacobian(model, data, q, np.zeros(model.nv), loops)
    v = np.array(v_guess, float)
    v[free] -= np.linalg.lstsq(J[:, free], J @ v, rcond=None)[0]
    return q, v


def loop_velocities(model: Model, data: Data, t, q, pbar, loops, alpha, method="ldlt"):
    """(ν, σ) from the momentum-form state (q, p̄): the system of the module
    docstring by the Schur complement, G⁻¹ by the O(N) momentum-form factors."""
    Phi, J, _ = loop_jacobian(model, data, q, np.zeros(model.nv), loops, t)
    X = alg.MassOperator(model, q, method).solve(J.T)          # G⁻¹J_c'
    x0 = alg.velocities_from_momenta(model, data, q, pbar, t, method)   # base law included
    S = J @ X
    try:
        sigma = scipy.linalg.solve(S, J @ x0 + alpha * Phi, assume_a="pos")
    except (np.linalg.LinAlgError, ValueError):
        raise InvalidProblemError("the loop constraints are redundant or singular here "
                                  "(J_c G⁻¹ J_c' not positive definite)") from None
    return x0 - X @ sigma, sigma
