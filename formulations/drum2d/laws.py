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

The step writes it, with F = r_N / h the step's mean force and the gap carried
to the end of the step, as

    0 <= r_N ⟂ u_N⁺ + e u_N⁻ + (1 + e) (ĝ/h + c r_N/h²) >= 0,

ĝ = g, except at a contact still open (g > 0) that the free motion closes
within the step (the rigid law's active set: g + h (u_N⁻ + u_N^free)/2 <= 0):
there ĝ = 0.

Why this form: where the step resolves the spring (h much less than the
contact period T = 2π √(m* c), m* = (1/m_i + 1/m_j)⁻¹), u_N⁺ ≈ u_N⁻ and it
reads g + h u_N + c F >= 0 — the spring at the end of the step (implicit, so
stable at any h; with e = 1 the gap advances by h (u_N⁻ + u_N⁺)/2, the
midpoint rule, and the collision of two logs gives the stack model's peak
force √(m*/c) Δv).  Where it does not (the drum's steps: 0.12 m spruce logs
have T ≈ 0.7 ms against h = 2 ms), c r_N/h² is small beside W's entries and
the law is Newton's, with e, plus the term (1 + e) g/h that pushes an overlap
out over the step instead of letting it drift.  For e = 0 it is the implicit
Euler spring (the "ERP = 1, CFM = c/h²" of rigid-body engines).

Why ĝ = 0 at a closing contact: an impact that begins inside the step.  With
g itself the law would ask the gap to reach 0 at the end of the step, which,
the spring unresolved, leaves u_N⁺ = −u_N⁻ (1 − 2 g/(h |u_N⁻|)) for e = 1: a
rebound anywhere between −1 and 1 times the impact speed, set by where in
the step the contact began (measured 0.10–0.80).  With ĝ = 0 the impact is
resolved from the start of the step, as the rigid law does (up to one step
early): one contact of a body of mass m* rebounds at
u_N⁺ = (γ u_N^free − e u_N⁻)/(1 + γ), γ = (1 + e) m* c/h² — Newton's law up
to γ = (1 + e)(T/(2π h))².  An open contact that the free motion leaves open
keeps g: pushed shut by the other contacts' impulses (a column settling), it
meets its spring at the end of the step.

What the scheme dissipates (tests/test_drum2d_compliance.py measures it):

- resolved, one collision: the step's map of (gap, u_N) has determinant
  1/(1 + ω²h²/2), ω = 2π/T, so over the contact's T/2 the energy falls by
  exp(−π² h/T): the rebound is exp(−π² h/(2T)) Δv and the peak force
  √(m*/c) Δv exp(−π² h/(4T)) (the stack model's backward differences lose
  twice that: the 2-D step h matches the stack's h/2).  e hardly acts here
  (it enters at O(h²)): the stack model damps with a viscous λ, not with e;
- unresolved: Newton's law, e_eff = (e − γ)/(1 + γ).  With e < 1/3 the
  midpoint positions leave an overlap of up to (1 − e) h |u_N⁻|/2 after the
  impact, which the next step's (1 + e) g/h pushes out: the rebound lies
  between e and (1 − 3 e²)/2 times the impact speed (½ for e = 0), set by
  where in the step the contact began;
- a contact that stays closed, unresolved: the implicit spring damps its
  vibration within a few steps, so a pile settles even with e = 1.

So a compliant contact adds (1 + e) c/h² to W's normal diagonal and
(1 + e) g/h to its offset: the same FrictionProblem or LCP, with W + D, D >= 0
diagonal — positive definite on the normal directions wherever every contact
has c > 0, which makes the forces on a pile unique (the elastic split) and the
step problem regular.  A compliant contact takes part in every step in which
it is within the broad phase's margin: its law says r_N = 0 while the spring
stays open.

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
        """(D, offset): what the contacts add to W's normal diagonal and to
        the offset q_N (module docstring), and their compliance; ``u_free_n``
        the normal velocities of the free motion (no contact impulses)."""
        comp = self.compliance(c)
        scale = 1.0 + self.e
        closing = c.gap + 0.5 * h * (u_minus_n + u_free_n) <= 0.0
        gap = np.where(closing, np.minimum(c.gap, 0.0), c.gap)
        offset = self.e * u_minus_n + np.where(comp > 0, scale * gap / h, 0.0)
        return scale * comp / h ** 2, offset, comp

    @staticmethod
    def elastic_energy(comp, r_n, h) -> float:
        """Σ ½ c F² [J] with F = r_N / h."""
        F = r_n / h
        return float(0.5 * comp @ (F * F))
