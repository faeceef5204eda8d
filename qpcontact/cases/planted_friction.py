"""Frictional contact problems with a planted solution (no hypothesis needed).

Each contact i is given a state and a reaction r_i with a local velocity u_i
that satisfy Coulomb's law with Signorini's condition exactly (De Saxcé's
form, :mod:`qpcontact.core.friction_problem`; K_i = {‖r_T‖ <= μ_i r_N}):

``open``      r_i = 0, u_N > 0, u_T anything (the contact separates);
``stick``     r_i strictly inside K_i, u_i = 0;
``slide``     u_N = 0, u_T ≠ 0, r_T = −μ r_N u_T / ‖u_T‖ (on the cone's
              boundary, opposing the slip).

W is then drawn (symmetric positive definite, condition ``cond``) and q = u −
W r, so (r, u) solves the problem up to the rounding of that product.  The
kinds (:data:`FRICTION_KINDS`):

``sticking``, ``sliding``, ``separated``, ``mixed``
    every contact in that state, or each drawn at random;
``badly_scaled``
    mixed, with each contact's forces and velocities in its own units: W →
    D W D, q → D q over ``decades`` decades, one factor per contact (the cone
    is invariant under it, so r → D⁻¹ r, u → D u);
``decoupled``
    mixed, W block diagonal with each block a_i I (an isotropic contact):
    then each contact's answer is a projection and the solution is unique
    (r_N = −q_N / a_i when q_N < 0, r_T the projection of −q_T / a_i on the
    disc of radius μ r_N).

:meth:`FrictionCase.agrees` checks an answer without
:mod:`qpcontact.judge.friction_certificate`: against the planted reactions where the
solution is unique (``decoupled``), otherwise by Coulomb's law written out
here, each contact on its own scale.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.options import check_seed
from ..core.friction_problem import FrictionProblem
from .families import random_spd
from .planted import Case

__all__ = ["FrictionCase", "build_friction", "FRICTION_KINDS", "STATES"]

#: The kinds of frictional problem :func:`build_friction` (and the strategy
#: ``frictions``) can plant.
FRICTION_KINDS = ("sticking", "sliding", "separated", "mixed", "badly_scaled", "decoupled")
STATES = ("open", "stick", "slide")


@dataclass
class FrictionCase(Case):
    """A frictional problem and its planted answer: ``r`` (reactions), ``u``
    (local velocities u = W r + q), ``states`` (one of :data:`STATES` per
    contact), ``unique_r`` (whether r is the only solution), ``scale`` (each
    contact's natural force size, for judging a component that is zero)."""

    r: np.ndarray | None = None
    u: np.ndarray | None = None
    states: tuple = ()
    unique_r: bool = False
    scale: np.ndarray | None = None

    def agrees(self, answer, rtol: float = 1e-6) -> bool:
        """Whether reactions ``answer`` match the planted ones contact by
        contact (each within ``rtol`` of its contact's size) where the
        solution is unique, and otherwise satisfy Coulomb's law on each
        contact's own scale — checked here, independently of
        :mod:`qpcontact.judge.friction_certificate`."""
        if answer is None:
            return False
        p = self.problem
        d = p.dim
        r = np.asarray(answer, float).reshape(-1, d)
        size = np.maximum(np.linalg.norm(self.r.reshape(-1, d), axis=1), self.scale)
        if self.unique_r:
            return bool(np.all(np.linalg.norm(r - self.r.reshape(-1, d), axis=1) <= rtol * size))
        W = p.W.toarray() if hasattr(p.W, "toarray") else np.asarray(p.W)
        u = (W @ r.ravel() + p.q).reshape(-1, d)
        rho = 1.0 / np.diag(W)[0::d]
        return bool(np.all(_coulomb_residual(r, u, p.mu, rho) <= rtol * size))


def _coulomb_residual(r, u, mu, rho) -> np.ndarray:
    """Per contact, in force units: how far (r, u) is from Coulomb's law —
    the larger of r's distance from its cone, ρ û's distance from the dual
    cone, and |r·ρû| / max(‖r‖, ‖ρû‖) (complementarity), û = u + μ‖u_T‖ e_N."""
    rn, rt = r[:, 0], np.linalg.norm(r[:, 1:], axis=1)
    un, ut = u[:, 0], np.linalg.norm(u[:, 1:], axis=1)
    uhat_n = un + mu * ut
    outside_cone = np.maximum(0.0, np.maximum(rt - mu * rn, -rn))
    # û in K* = {v_N >= μ‖v_T‖}: ‖û_T‖ = ‖u_T‖
    outside_dual = rho * np.maximum(0.0, mu * ut - uhat_n)
    v = rho[:, None] * np.column_stack([uhat_n, u[:, 1:]])
    work = np.abs(np.sum(r * v, axis=1))
    big = np.maximum(np.linalg.norm(r, axis=1), np.linalg.norm(v, axis=1))
    complementarity = np.where(big > 0, work / np.where(big > 0, big, 1.0), 0.0)
    return np.maximum(np.maximum(outside_cone, outside_dual), complementarity)


def _directions(rng, nc: int, dim: int) -> np.ndarray:
    """Unit tangent directions, one per contact (±1 in 2-D)."""
    if dim == 2:
        return rng.choice([-1.0, 1.0], size=(nc, 1))
    t = rng.standard_normal((nc, dim - 1))
    return t / np.linalg.norm(t, axis=1, keepdims=True)


def _planted(states, mu, dim, rng):
    nc = len(states)
    R, U = np.zeros((nc, dim)), np.zeros((nc, dim))
    t = _directions(rng, nc, dim)
    for i, s in enumerate(states):
        if s == "open":
            U[i, 0] = rng.uniform(0.1, 2.0)
            U[i, 1:] = rng.standard_normal(dim - 1)
        elif s == "stick":
            R[i, 0] = rng.uniform(0.1, 2.0)
            R[i, 1:] = rng.uniform(0.0, 0.8) * mu[i] * R[i, 0] * t[i]
        else:
            R[i, 0] = rng.uniform(0.1, 2.0)
            U[i, 1:] = rng.uniform(0.1, 2.0) * t[i]
            R[i, 1:] = -mu[i] * R[i, 0] * t[i]
    return R.ravel(), U.ravel()


def build_friction(kind: str, contacts: int, seed: int, *, dim: int = 3, cond: float = 1e3,
                   decades: float = 6.0, mu_max: float = 0.8) -> FrictionCase:
    """One frictional case, deterministic in its arguments (module docstring)."""
    if kind not in FRICTION_KINDS:
        raise ValueError(f"unknown friction kind {kind!r}; choose from {FRICTION_KINDS}")
    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 or 3; got {dim!r}")
    seed = check_seed(seed)
    rng = np.random.default_rng(seed)
    nc, m = int(contacts), dim * int(contacts)
    mu = rng.uniform(0.1, mu_max, nc)
    one = {"sticking": "stick", "sliding": "slide", "separated": "open"}.get(kind)
    states = tuple([one] * nc if one else rng.choice(STATES, size=nc))
    r, u = _planted(states, mu, dim, rng)
    if kind == "decoupled":
        W = np.diag(np.repeat(10.0 ** rng.uniform(-1, 1, nc), dim))
    else:
        W = random_spd(m, cond, rng)
    scale = np.full(nc, 0.1)             # the smallest planted force: what a zero is judged on
    if kind == "badly_scaled":
        dc = 10.0 ** rng.uniform(-decades / 2, decades / 2, nc)
        D = np.repeat(dc, dim)
        W = (W * D[:, None]) * D[None, :]
        W = 0.5 * (W + W.T)
        r, u, scale = r / D, u * D, scale / dc
    q = u - W @ r
    return FrictionCase(kind, FrictionProblem(W, q, mu, dim, name=f"{kind}-{dim}d-{nc}-{seed}"),
                        "solved", r=r, u=u, states=states, unique_r=kind == "decoupled",
                        scale=scale, seed=seed)
