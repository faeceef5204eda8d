r"""Tree-structured rigid-body systems (Ivanov & Shimanovsky 2017): O(N)
equations of motion in generalized momenta, with the Lagrange form beside them.

SI units: m, kg, s, rad; forces N, moments N·m, momenta kg·m/s and kg·m²/s.

Kinematics (the paper's eqs. 1-5)
---------------------------------
Body 0 moves by a given law; body i hangs from its parent λ(i) < i by joint i
with n_i coordinates.  In body i's frame its spatial velocity is V_i = (v_i, ω_i)
(v_i: velocity of the frame origin O_i).  With R_i, ρ_i the orientation and
origin of frame i in the parent frame and H_i (6 x n_i) the joint's motion
subspace in frame i, ::

    V_i = C_i V_λ(i) + H_i ν_i,     C_i = [[R_i', -R_i'ρ̃_i], [0, R_i']],        (1)

ν_i = q̇_i except for quaternion joints (then q̇ = K(q)ν).  Stacked, S V =
H ν + b with S block lower-triangular (E6 on the diagonal, -C_i at column
λ(i)) and b_i = C_i V_0 for the base's children: eq. (3).

Momentum form (the paper's eqs. 6-7, reconstructed)
---------------------------------------------------
T = ½ Σ V_i'M_iV_i with M_i the 6 x 6 inertia of body i about O_i.  Define the
subtree momenta μ by S'μ = M V, i.e. μ_i = M_iV_i + Σ_children C_c'μ_c (the
momentum of the subtree rooted at i, about O_i, in frame i).  Since
∂V_j/∂ν_i = (transport) H_i for j in the subtree of i, the generalized momenta
are p = ∂T/∂ν = H'μ.  Together::

    [ M   -S'   0 ] [V]   [ 0]
    [-S    0    H ] [μ] = [-b]      symmetric, indefinite, block tridiagonal   (6)
    [ 0    H'   0 ] [ν]   [ p]

and the momentum balance of each subtree (the joint reaction's H_i'-projection
is the joint force τ_i; F_i the applied forces on the subtree about O_i) ::

    ṗ_i = Ḣ_i'μ_i + H_i'(F_i - V_i ×* μ_i) + τ_i,   V ×* f = (ω × F, v × F + ω × N).   (7)

Given (q, p), (6) is solved in O(N): leaves to root, μ_i = Â_i C_iV_λ(i) + β_i
with Ī_i = M_i + Σ C_c'Â_cC_c, D_i = H_i'Ī_iH_i (n_i x n_i, positive definite),
Â_i = Ī_i - Ī_iH_iD_i⁻¹H_i'Ī_i; root to leaves, ν_i = D_i⁻¹(p_i - H_i'c̄_i -
H_i'Ī_iC_iV_λ(i)) and V_i by (1).  The *sweep* forms D_i⁻¹ explicitly and
updates full 6 x 6 blocks (an LU elimination); the *LDLᵀ* variant keeps the
Cholesky factor L_i of D_i, W_i = L_i⁻¹H_i'Ī_i, Â_i = Ī_i - W_i'W_i and
updates only upper triangles (the paper: 1.35-1.4x faster).  With V_0 = 0, (6) maps
p to ν = G⁻¹p: the same recursion is an O(N) factorized G⁻¹
(:class:`MassOperator`) for the contact formulations.

Lagrange form: G(q) ν̇ + c(q, ν) = τ, G by the composite-rigid-body recursion,
c by recursive Newton-Euler; the classical comparison.

Modules: model (Model, Data, joints), algorithms (kinematics, dynamics),
simulation (simulate), constraints (closed loops, Baumgarte), _kernels
(compiled recursions).  See docs/multibody.md.
"""

from .algorithms import (METHODS, MassOperator, configuration_rate, forward_dynamics,
                         forward_kinematics, gravity_forces, integrate, kinetic_energy,
                         mass_matrix, momenta, momentum_rate, momentum_rhs, nonlinear_effects,
                         point_jacobian, point_position, potential_energy, rnea,
                         velocities_from_momenta)
from .simulation import FORMS, INTEGRATORS, Trajectory, simulate
from .model import Cardan, Data, Free, Joint, Model, Planar, Prismatic, Revolute, Spherical

__all__ = ["METHODS", "MassOperator", "configuration_rate", "forward_dynamics",
           "forward_kinematics", "gravity_forces", "integrate", "kinetic_energy", "mass_matrix",
           "momenta", "momentum_rate", "momentum_rhs", "nonlinear_effects", "point_jacobian",
           "point_position", "potential_energy", "rnea",
           "velocities_from_momenta", "FORMS", "INTEGRATORS", "Trajectory", "simulate",
           "Cardan", "Data", "Free", "Joint", "Model", "Planar", "Prismatic", "Revolute",
           "Spherical"]
