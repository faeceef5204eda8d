r"""The normal contact laws of the 2-D drum's step: rigid, or compliant with
the stack model's springs.

SI units: m, s, kg, N, N·s (impulses), compliance m/N, stiffness N/m.

Rigid contact (Moreau–Jean, Newton's impact law)
------------------------------------------------
A contact whose predicted gap at the end of the step is <= 0 obeys

    0 <= r_N ⟂ u_N⁺ + e u_N⁻ >= 0,

e the restitution (``damping``; e = 1 without it).  Its offset in the step's
problem is e u_N⁻ and W is left as it is.  On a pile, W = Hᵀ M⁻¹ H has more
rows than the discs have degrees of freedom: the forces are statically
indeterminate and the step problem singular (NSGS then creeps: thousands of
sweeps for a 700-contact bed).

Compliant contact (``log_elasticity``, ``shell_elasticity``)
----------------------------------------------------------
The stack model (formulations.drum) gives each log half between a contact and
the log's centre the stiffness s = 2 E ℓ [N/m] (E the modulus across the grain,
ℓ the log's length; formulations.drum.model.log_half_stiffness).  The path
through a contact then has the compliance

    c = 1/s_i + 1/s_j   between logs,     c = 1/s_i (+ 1/k_s)   at the shell or a lifter,

with k_s the shell's stiffness when ``shell_elasticity`` is named (without
``log_elasticity`` the log halves are rigid: c = 1/k_s at the walls, and the
log–log contacts rigid).  The contact is a spring without pull: with g the
rigid bodies' gap (negative: the overlap the halves take up) the force is
F = max(0, −g)/c, i.e.  0 <= F ⟂ g + c F >= 0.

The stepper advances a compliant run's positions with θ = 1 (q⁺ = q + h ν⁺),
so the gap at the end of the step is g + h u_N⁺ + b, b [m] its second-order
part along the step's start motion (contacts.py, ``bend``: a centre's
straight chord across the shell's curve, two logs passing each other, a
lifter turning), and the law, with F = r_N/h the step's mean force, is the
implicit (backward Euler) spring

    0 <= r_N ⟂ u_N⁺ + (g + b)/h + c r_N/h² >= 0              (closed or open)

except at an impact — a contact still open (g >= 0) that the free motion
closes within the step (the rigid law's active set: g + b + h (u_N⁻ +
u_N^free)/2 <= 0) — which obeys

    0 <= r_N ⟂ u_N⁺ + e u_N⁻ + (1 + e) c r_N/h² >= 0          (impact).

Why.  Where the step resolves the spring (h much less than the contact
period T = 2π √(m* c), m* = (1/m_i + 1/m_j)⁻¹), c r_N/h² dominates and both
read g + h u_N + c F >= 0: the spring at the end of the step, stable at any h,
and the same backward differences as the stack model's step (its
formulations.drum.model, point 4), so a collision of two logs gives the
stack model's peak force at the same h (√(m*/c) Δv as h → 0).  Where it does
not (the drum's steps: 0.12 m spruce logs have T ≈ 0.7 ms against h = 2 ms),
c r_N/h² is small beside W's entries: an impact is Newton's law with e,
resolved from the start of the step as the rigid law does (up to one step
early), whatever the phase of the step at which the contact began (with g
itself the rebound would depend on it); a contact that stays closed is the
spring at the end of the step, its overlap pushed out within the step
instead of drifting, and its forces on a pile the elastic split.  One
impact of a body of mass m* rebounds at e_eff = (e − γ)/(1 + γ),
γ = (1 + e) m* c/h² = (1 + e)(T/(2π h))².  For e = 0 the whole law is the
implicit Euler spring (the "ERP = 1, CFM = c/h²" of rigid-body engines).

Why θ = 1 and not the midpoint: after an unresolved impact the midpoint
positions would leave an overlap (1 − e) h |u_N⁻|/2 that the spring pushes
out at the next step as a bounce of up to (1 − e)/2 of the impact speed,
whatever e (measured, e = 0: 0 to 0.43 by phase; with θ = 1: −0.003 every
time).

What the scheme dissipates (tests/formulations/drum2d/test_drum2d_compliance.py measures it):
resolved, the backward Euler spring loses energy at the rate ω²h per unit
time (the stack model's scheme, the same figures at the same h); e hardly
acts there (the stack model damps resolved contacts with a viscous λ, not
with e); unresolved impacts lose Newton's (1 − e_eff²); a contact that stays
closed damps its vibration within a few steps, so a pile settles even with
e = 1.

Peak forces.  F = r_N/h is the step's mean force.  An impact the step
does not resolve delivers its impulse in less than the step, so its peak is
larger; formulations.drum2d.impacts measures it by a resolved run of the
impact's cluster over the step (the pair's half-sine π r_N/T is right for a
binary collision only).  A rigid run has only the mean force.

Why b.  Without it the law took the end gap to first order, and a log
carried on the shell (its centre on a chord, 1.6 µm a 2 ms step into the
shell's curve at 0.9 m) sat deeper than its spring's c F by that drift —
five times its weight's overlap — and one carried on a lifter's face,
whose gaps are a fraction of a micron, read its gap as alternately open and
closed (impact and spring laws in turn, docs/dev-notes.md, "The lifter
pocket's force loop").  With b a carried log sits at c F.

So a compliant contact adds c/h² (at an impact (1 + e) c/h²) to W's normal
diagonal and (g + b)/h (at an impact e u_N⁻) to its offset: the same FrictionProblem
or LCP, with W + D, D >= 0 diagonal — positive definite on the normal
directions wherever every contact has c > 0, which makes the forces on a pile
unique (the elastic split) and the step problem regular.  A compliant
contact takes part in every step in which it is within the broad phase's
margin: its law says r_N = 0 while the spring stays open.

The springs store E_el = Σ ½ c F² [J]; the step's contact dissipation is what
the springs do not store (stepper: energy bookkeeping).
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidOptionError

from .contacts import DISC

__all__ = ["ContactLaw", "SPRUCE_E_TANGENTIAL"]

#: Spruce's Young's modulus across the grain, tangential [Pa] (the stack
#: model's default, formulations.drum.model.SPRUCE_E_TANGENTIAL).
SPRUCE_E_TANGENTIAL = 0.4e9


class ContactLaw:
    """Each contact's compliance c [m/N] (0: rigid) for discs of
    ``half_stiffness`` s_i [N/m] (None: rigid logs) and a shell of
    ``shell_stiffness`` k_s [N/m] (None: rigid shell); ``restitution`` e."""

    def __init__(self, half_stiffness, shell_stiffness, restitution: float):
        if half_stiffness is not None:
            half_stiffness = np.asarray(half_stiffness, float)
            if not np.all(np.isfinite(half_stiffness) & (half_stiffness > 0)):
                raise InvalidOptionError("the logs' half stiffness 2 E ℓ must be finite and > 0; "
                                         "check the modulus E [Pa] and the length ℓ [m]")
        if shell_stiffness is not None and not (np.isfinite(shell_stiffness)
                                                and shell_stiffness > 0):
            raise InvalidOptionError(f"shell_stiffness must be finite and > 0 [N/m]; got "
                                     f"{shell_stiffness}")
        self.inverse_half = None if half_stiffness is None else 1.0 / half_stiffness
        self.shell_compliance = 0.0 if shell_stiffness is None else 1.0 / float(shell_stiffness)
        self.e = float(restitution)

    @property
    def compliant(self) -> bool:
        return self.inverse_half is not None or self.shell_compliance > 0

    def compliance(self, c) -> np.ndarray:
        """c_k [m/N] of the contacts c (module docstring)."""
        out = np.where(c.kind == DISC, 0.0, self.shell_compliance)
        if self.inverse_half is not None:
            out = out + self.inverse_half[c.i]
            pair = c.j >= 0
            out[pair] += self.inverse_half[c.j[pair]]
        return out

    def normal_terms(self, c, h, u_minus_n, u_free_n):
        """(D, offset, compliance, impact): what the contacts add to W's
        normal diagonal and to the offset q_N (module docstring), their
        compliance and which are impacts; ``u_free_n`` the normal velocities
        of the free motion (no contact impulses)."""
        comp = self.compliance(c)
        spring = comp > 0
        end = c.gap if c.bend is None else c.gap + c.bend
        impact = spring & (c.gap >= 0.0) & (end + 0.5 * h * (u_minus_n + u_free_n) <= 0.0)
        rigid_or_impact = ~spring | impact
        offset = np.where(rigid_or_impact, self.e * u_minus_n, end / h)
        D = np.where(impact, 1.0 + self.e, 1.0) * comp / h ** 2
        return D, offset, comp, impact

    @staticmethod
    def elastic_energy(comp, r_n, h) -> float:
        """Σ ½ c F² [J] with F = r_N / h."""
        F = r_n / h
        return float(0.5 * comp @ (F * F))
