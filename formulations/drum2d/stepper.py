r"""Moreau–Jean time stepping of the 2-D drum, one certified contact problem per step.

SI units: s, m, m/s, rad/s, N·s (impulses), J (energies).

The step (h [s], θ positions, impulses implicit)
-----------------------------------------------
With ν = (vx, vy, ω) per disc, M = diag(m, m, I), f the gravity forces
(0, −m g, 0) and H, w the contact kinematics of formulations.drum2d.contacts
(u = Hᵀ ν + w), one step from (q, ν) at t is

    ν⁺ = ν + h M⁻¹ f + M⁻¹ H r                                      (momentum)
    q⁺ = q + h ((1 − θ) ν + θ ν⁺)                          (θ = ½, or 1 with springs)
    u⁺ = Hᵀ ν⁺ + w,   u⁻ = Hᵀ ν + w,
    for each active contact:  0 <= r_N ⟂ u_N⁺ + e u_N⁻ (+ the spring's terms) >= 0
                              |r_T| <= μ r_N, Coulomb on u_T⁺           (friction)

the normal law rigid (Newton's) or compliant (formulations.drum2d.laws:
``log_elasticity``, ``shell_elasticity``, the stack model's springs).

θ = ½ (the midpoint) with rigid contacts keeps K + P exactly through elastic
impacts.  With springs θ = 1: the positions advance by the velocity the
contact law has just set, so a spring the step does not resolve ends the
impact step without the overlap h (1 − e)|u_N⁻|/2 the midpoint would leave
— an overlap the spring would push out in the next step as a bounce of up to
(1 − e)/2 of the impact speed whatever e (measured: a log dropped with e = 0
rebounded at 0 to 0.43 of its speed depending on where in a step it struck;
with θ = 1 at −0.003 every time, e = 0.2 at 0.196).  The spring's law takes
the gap at the end of the step as g + h u_N⁺ + b, which is what θ = 1 gives
(b its second-order part along the start motion, contacts.py's ``bend``).
A wall's w is its material point's mean velocity along t over the step (its
arc's chord, contacts.py): stick then holds a log to the turning wall as
one body.

r (N·s) the contact impulses over the step.  A contact is active when its
predicted gap g + h (u_N⁻ + u_N^free)/2 is <= 0, u^free = Hᵀ(ν + h M⁻¹ f) + w:
the gap the free motion would leave at the end of the step.  Substituting
ν⁺ gives the local problem

    û = (W + D) r + q,   W = Hᵀ M⁻¹ H  (M diagonal: sparse, cheap),
                         q = u^free + (e u_N⁻ + the springs' gap terms, 0),

D the springs' diagonal (laws: 0 for rigid contacts),

a 2-D FrictionProblem (qpcontact.core.friction_problem), or without friction the
LCP 0 <= r_N ⟂ W_NN r_N + q_N >= 0 — both solved by qpcontact.solve and
certified from the data.  A step whose answer is not certified is recorded
(``Drum2DResult.uncertified``) and warned about, or raises with
``on_uncertified="raise"``; never silently kept.

Energy bookkeeping (exact identities of the scheme)
---------------------------------------------------
K = ½ νᵀ M ν, P = Σ m g y, E_el = Σ ½ c F² (the springs, F = r_N/h).  From
the momentum line,
ΔK = (h f + H r)ᵀ (ν + ν⁺)/2, and the θ positions make ΔP = −h fᵀ ((1 − θ) ν + θ ν⁺)
exactly (f constant), so

    ΔK + ΔP = rᵀ Hᵀ (ν + ν⁺)/2 + S = rᵀ (u⁻ + u⁺)/2 − rᵀ w + S,
    S = h (θ − ½) fᵀ (ν − ν⁺)   (``scheme``: 0 at the midpoint; with θ = 1
                                  −½ h² g² m per free disc and step),

−rᵀ w = Σ r · V is the work of the moving shell and lifters (the drive; the
wall takes −r at velocity V).  Friction dissipates the sliding work

    D_f = Σ |r_T| s̄ >= 0,   s̄ = (1/h) ∫ |u_T(t)| dt  over the step,

u_T taken linear from u_T⁻ to u_T⁺ (records.sliding_speed: (|u⁻| + |u⁺|)/2,
or (u⁻² + u⁺²)/(2(|u⁻| + |u⁺|)) where the slip turns), the force |r_T|/h
constant — ∫ F_T · slip dt, slip that stops within the step included (a
log sliding at u_T⁻ that sticks by the step's end rubs |r_T| u_T⁻/2; the end
slip alone would book 0).  Where r_T opposes the slip throughout this is
−r_T (u_T⁻ + u_T⁺)/2, the tangential part of the identity above.  At the
contacts of an unresolved impact's cluster D_f adds what the cluster's
resolved run slid beyond its own linear-slip estimate (impacts.py,
"Sliding work": the slip an impact's wave or a ringing contact drives
within the step, which the step's end points do not show).  The rest,
D_i = −rᵀ(u⁻ + u⁺)/2 − D_f, is what the contacts take: their springs' change
ΔE_el plus the impacts' loss ``impact_loss`` (reported net of ΔE_el).  A
step's impact loss can be negative: where the slip turns within the step,
or sticks with a friction impulse along its starting slip, the one constant
impulse of the step did less tangential work than Coulomb's ∫ |F_T||u_T|
charges, and D_i gives the difference back; with springs also the θ = 1
pairing below (docs/drum2d.md, "Energy books", measures both); and where a
cluster run books more sliding than the step's own estimate, the step's
total −rᵀ(u⁻ + u⁺)/2 stays the model's, so D_i gives that back too: the
books close exactly, the split between friction and impacts is the
resolved run's.  For rigid contacts its normal part −r_N (u_N⁻ + u_N⁺)/2 = −r_N (1 − e) u_N⁻/2
where r_N > 0, so with e = 1 the scheme dissipates nothing at the normal
impacts (to the certificate's tolerance) and K + P is kept exactly when friction
is off and the shell still.  The remainder ΔK + ΔP − drive + D_f + D_i is
rounding and the certificate's residual; it is reported per run (with
springs and θ = 1, ΔK + ΔP + ΔE_el − drive + D_f + D_i − S).

The scheme's own errors are in the positions: an impact is resolved up to one
step early (a gap of at most h |u_N|) and a contact carried along the curved
shell drifts into it by about (h v)²/(2ρ) per step (ρ the centre's radius of
curvature) — a rigid contact keeps that drift (drift.py projects it out), a
compliant one's law takes it in (b above); the run reports the largest
penetration.

Warm starts
-----------
With friction the step's problem is first solved by ``warm_start`` (NSGS +
Newton by default; with compliant contacts Newton's square step first and the
sweeps over-relaxed at :data:`COMPLIANT_OMEGA`) from the previous step's
impulses, matched contact by contact (disc i, other body j, kind); where that answer is not certified at
``accuracy`` the step is solved again by ``method`` ("auto") and flagged in
``fallback``.  The certificate judges either way.
"""

from __future__ import annotations

import time
import warnings

import numpy as np
import scipy.sparse as sp

from qpcontact import solve
from qpcontact.core.errors import InvalidOptionError, SolverFailedError
from qpcontact.core.problems import LCP
from qpcontact.core.progress import StepReporter
from qpcontact.core.friction_problem import FrictionProblem

from .contacts import find_contacts
from .geometry import GRAVITY, Discs, Shell
from .drift import keep_gaps
from .impacts import step_forces
from .laws import SPRUCE_E_TANGENTIAL, ContactLaw
from .records import Drum2DResult, Recorder, sliding_speed

__all__ = ["Drum2D", "Drum2DResult", "EFFECTS", "UncertifiedStepWarning", "WARM_START",
           "WARM_METHODS"]

#: the effects the model knows; gravity is always on
EFFECTS = ("gravity", "friction", "rotation", "damping", "log_elasticity", "shell_elasticity")

#: the warm start ``simulate`` uses with friction unless told otherwise
WARM_START = "nsgs-newton"
#: the friction methods that start from a given r0
WARM_METHODS = ("nsgs", "nsgs-newton", "newton")
#: NSGS's over-relaxation in the warm start where the contacts are compliant:
#: the sweeps to 1e-3 on 20 steps of the 500-log bed, median 125 at 1.3 (the
#: method's default, set for rigid piles), 85 at 1.5; whole steps 5-18 %
#: faster at 100 and 500 logs, on stretches other than those measured; 1.7
#: was slower than 1.5 (docs/dev-notes.md, "The drum's step")
COMPLIANT_OMEGA = 1.5


class UncertifiedStepWarning(UserWarning):
    """A step's contact problem came back without a certificate meeting the accuracy."""


class Drum2D:
    """The 2-D drum cross-section: ``discs`` (geometry.Discs, copied) in a
    ``shell`` (geometry.Shell); ``effects`` among EFFECTS (gravity always);
    ``mu_disc``, ``mu_shell``, ``mu_lifter`` the friction coefficients (used
    only with ``friction``), ``restitution`` e in [0, 1] (used only with
    ``damping``; without it e = 1, elastic impacts); ``modulus`` E [Pa] of
    the logs across the grain (only with ``log_elasticity``: half stiffness
    2 E ℓ), ``shell_stiffness`` k_s [N/m] (only with ``shell_elasticity``);
    laws.py derives the compliant contacts."""

    def __init__(self, discs: Discs, shell: Shell, effects=("gravity",), *, mu_disc=0.4,
                 mu_shell=0.4, mu_lifter=0.4, restitution=0.0, gravity=GRAVITY,
                 modulus=SPRUCE_E_TANGENTIAL, shell_stiffness=None):
        effects = frozenset(effects) | {"gravity"}
        unknown = effects - set(EFFECTS)
        if unknown:
            raise InvalidOptionError(f"unknown effects {sorted(unknown)}; the 2-D drum knows "
                                     f"{EFFECTS}")
        for name, mu in (("mu_disc", mu_disc), ("mu_shell", mu_shell), ("mu_lifter", mu_lifter)):
            if not (np.isfinite(mu) and mu >= 0):
                raise InvalidOptionError(f"{name} must be finite and >= 0; got {mu}")
        if not 0.0 <= restitution <= 1.0:
            raise InvalidOptionError(f"restitution must be in [0, 1]; got {restitution}")
        if not (np.isfinite(gravity) and gravity >= 0):
            raise InvalidOptionError(f"gravity must be finite and >= 0; got {gravity}")
        if "shell_elasticity" in effects and shell_stiffness is None:
            raise InvalidOptionError("the effect 'shell_elasticity' needs shell_stiffness [N/m]")
        if not (np.isfinite(modulus) and modulus > 0):
            raise InvalidOptionError(f"modulus must be finite and > 0 [Pa]; got {modulus}")
        self.discs, self.shell, self.effects = discs, shell, effects
        self.mu = np.array([mu_disc, mu_shell, mu_lifter], float)
        self.restitution = float(restitution) if "damping" in effects else 1.0
        self.omega = shell.omega if "rotation" in effects else 0.0
        self.gravity = float(gravity)
        self.modulus, self.shell_stiffness = float(modulus), shell_stiffness
        self.law = ContactLaw(
            2.0 * modulus * discs.length * np.ones(discs.n) if "log_elasticity" in effects
            else None, shell_stiffness if "shell_elasticity" in effects else None,
            self.restitution)
        #: the positions' θ (module docstring): the midpoint, or 1 with springs
        self.theta = 1.0 if self.law.compliant else 0.5
        # a start state may overlap the shell a little (a resumed or settled
        # run's drift); a centre beyond half a radius into it is a mistake
        inside = np.hypot(*discs.positions.T) + 0.5 * discs.radii
        if np.any(inside > shell.radius):
            k = int(np.argmax(inside - shell.radius))
            raise InvalidOptionError(
                f"disc {k} (radius {discs.radii[k]:.4g} m) overlaps the shell by "
                f"{inside[k] + 0.5 * discs.radii[k] - shell.radius:.4g} m, more than half its "
                f"radius: its centre must lie within R − r = {shell.radius - discs.radii[k]:.4g} "
                "m of the axis")

    def _margin(self, h, v, spin):
        rad = self.discs.radii
        speed = np.hypot(*v.T) + rad * np.abs(spin)
        reach = 2.0 * speed.max(initial=0.0) + abs(self.omega) * self.shell.radius \
            + 2.0 * self.gravity * h
        return 1.5 * h * reach + 1e-9 * self.shell.radius

    def simulate(self, h: float, steps: int, *, method: str = "auto", accuracy="high",
                 keep_contacts=True, on_uncertified: str = "warn", warm_start="default",
                 warm_options=None, t0: float = 0.0, progress: bool = False, on_step=None,
                 resume: dict | None = None, checkpoint=None,
                 checkpoint_seconds: float = 5.0) -> Drum2DResult:
        """``steps`` Moreau–Jean steps of ``h`` [s] from the discs' state at
        time ``t0`` [s] (module docstring).

        ``warm_start`` (with friction only): a friction method taking ``r0``
        ("nsgs", "nsgs-newton", "newton"; "default": nsgs-newton with friction,
        None: none) started from the previous step's impulses (module
        docstring, "Warm starts"); a step it does not certify at ``accuracy``
        is solved again by ``method`` and flagged in ``fallback``.
        ``warm_options``: more options for that method (``max_sweeps``...).
        ``keep_contacts``: True (every step's active contacts), False, or k
        (every k-th step).  ``on_step(n, contacts, r)``: called after step n
        with its active contacts and impulses [N·s].  ``progress``: a progress bar; ``checkpoint(partial_result)``
        every ``checkpoint_seconds``; ``resume``: an interrupted run's arrays
        (the scene's results file, with ``completed``) to continue from."""
        if warm_start == "default":
            warm_start = WARM_START if "friction" in self.effects else None
        if warm_start is not None and "friction" not in self.effects:
            raise InvalidOptionError("warm_start needs the 'friction' effect (without it each "
                                     "step is an LCP, solved by `method`)")
        if not (np.isfinite(h) and h > 0) or int(steps) < 1:
            raise InvalidOptionError(f"h must be > 0 and steps >= 1; got h={h}, steps={steps}")
        if on_uncertified not in ("warn", "raise"):
            raise InvalidOptionError(f"on_uncertified must be 'warn' or 'raise'; got "
                                     f"{on_uncertified!r}")
        every = int(keep_contacts) if not isinstance(keep_contacts, bool) else int(keep_contacts)
        if every < 0:
            raise InvalidOptionError(f"keep_contacts must be True, False or a step count >= 1; "
                                     f"got {keep_contacts}")
        from .contact_kernel import impulses, velocities   # numba: imported where it runs

        S, d = int(steps), self.discs
        n = d.n
        minv, mdiag, f = d.inverse_mass(), d.mass_diagonal(), self._gravity_forces()
        rec = Recorder(S, n, h, t0, every)
        warm = None if warm_start is None else _WarmStart(warm_start, warm_options, n,
                                                          self.law.compliant)
        q = d.positions.copy()
        v = np.column_stack([d.velocities, d.spins]).ravel()
        first, elastic = 0, 0.0
        if resume is not None:
            first = int(resume["completed"])
            if not 0 <= first <= S or resume["positions"].shape[1:] != (n, 2):
                raise InvalidOptionError(f"cannot resume: {first} completed steps of {S}, "
                                         f"{resume['positions'].shape[1]} discs against {n}")
            rec.restore(first, resume)
            q = rec.state["positions"][first].copy()
            v = np.column_stack([rec.state["velocities"][first],
                                 rec.state["spins"][first]]).ravel()
            elastic = float(rec.energy["elastic"][first])
            if warm is not None and "warm/keys" in resume:
                warm.keys, warm.r = np.asarray(resume["warm/keys"]), np.asarray(resume["warm/r"])
        else:
            rec.state_at(0, q, v, mdiag, d.masses, self.gravity, 0.0)
        report = StepReporter(S, "drum2d", progress, checkpoint, checkpoint_seconds)
        for s in range(first, S):
            t = t0 + s * h
            V = v.reshape(n, 3)
            c = find_contacts(d, self.shell, t, self.omega, self._margin(h, V[:, :2], V[:, 2]),
                              positions=q, step=h, velocities=V[:, :2])
            rec.counts["n_contacts"][s], rec.counts["pairs_checked"][s] = c.m, c.pairs_checked
            rec.worst_pen = max(rec.worst_pen, float(-c.gap.min(initial=0.0)))
            v_free = v + h * minv * f
            u_minus = velocities(c.H.indptr, c.H.indices, c.H.data, c.w, v)
            u_free = velocities(c.H.indptr, c.H.indices, c.H.data, c.w, v_free)
            active = c.gap + 0.5 * h * (u_minus[0::2] + u_free[0::2]) <= 0.0
            if self.law.compliant:
                active |= self.law.compliance(c) > 0
            near = c
            if not active.all():    # with springs every contact is: no copies
                c = c.subset(active)
                keep2 = np.repeat(active, 2)
                u_minus, u_free = u_minus[keep2], u_free[keep2]
            rec.counts["n_active"][s] = c.m
            r = np.zeros(2 * c.m)
            new_elastic = 0.0
            if c.m:
                r, err, ok, name, secs, rec.fallback[s], (comp, impact) = self._solve_step(
                    c, u_minus, u_free, minv, h, method, accuracy, warm)
                rec.per["certificate_error"][s], rec.per["solve_seconds"][s] = err, secs
                rec.certified[s], rec.method[s] = ok, name
                if not ok:
                    msg = (f"step {s} (t = {t:.6g} s): contact problem with {c.m} contacts not "
                           f"certified by {name} (error {err:.3g})")
                    if on_uncertified == "raise":
                        raise SolverFailedError(msg)
                    warnings.warn(msg, UncertifiedStepWarning, stacklevel=2)
                new_elastic = self.law.elastic_energy(comp, r[0::2], h)
            v_new = (v_free + minv * impulses(c.H.indptr, c.H.indices, c.H.data, r, 3 * n)
                     if c.m else v_free)
            th = self.theta
            q_start = q
            q = q + h * ((1 - th) * v.reshape(n, 3)[:, :2] + th * v_new.reshape(n, 3)[:, :2])
            rec.per["scheme"][s] = h * (th - 0.5) * float(f @ (v - v_new))
            v_step = v_new
            if near.m:     # rigid contacts keep their gaps, energy unchanged (drift.py)
                q, v_new, rest = keep_gaps(near, self.law.compliance(near) == 0, q_start, q,
                                           v_new, d, self.shell.radius, h, self.gravity,
                                           self.omega == 0.0, accuracy)
                rec.per["scheme"][s] += rest
            rec.state_at(s + 1, q, v_new, mdiag, d.masses, self.gravity, new_elastic)
            per = rec.per
            if c.m:
                u_plus = velocities(c.H.indptr, c.H.indices, c.H.data, c.w, v_step)
                # the step's mean sliding speed, slip stopped within the step
                # included; its work |r_T| times that (module docstring)
                slip = sliding_speed(u_minus[1::2], u_plus[1::2])
                m = d.masses
                m_star = np.where(c.j >= 0, m[c.i] * m[c.j] / (m[c.i] + m[np.maximum(c.j, 0)]),
                                  m[c.i])
                # the peak forces and, at the contacts of an impact's cluster,
                # the sliding work from its resolved run (impacts.py)
                F, work = step_forces(
                    c, r[0::2], h, comp, impact, m_star, positions=q_start, velocities=v,
                    masses=d.masses, radii=d.radii, inverse_inertia=minv[2::3],
                    mu=self.mu[c.kind] if "friction" in self.effects else np.zeros(c.m),
                    shell_radius=self.shell.radius, restitution=self.restitution,
                    gravity=self.gravity, sliding_work=np.abs(r[1::2]) * slip)
                fric = float(work.sum())
                per["drive"][s], per["friction_loss"][s] = -float(r @ c.w), fric
                per["impact_loss"][s] = (-float(r @ (u_minus + u_plus)) / 2.0 - fric
                                         - (new_elastic - elastic))
                rec.forces(s, c, r, slip, work, F)
            E = rec.energy
            per["remainder"][s] = (E["kinetic"][s + 1] + E["potential"][s + 1]
                                   + E["elastic"][s + 1] - E["kinetic"][s] - E["potential"][s]
                                   - E["elastic"][s] - per["drive"][s] - per["scheme"][s]
                                   + per["friction_loss"][s] + per["impact_loss"][s])
            if warm is not None:
                warm.remember(c, r)
            elastic, v = new_elastic, v_new
            if on_step is not None:
                on_step(s + 1, c, r)
            report.after(s + 1, np.concatenate([[0.0], per["certificate_error"]]),
                         lambda k: rec.result(k, self.effects, _warm_state(warm)))
        return report.finish(rec.result(S, self.effects, _warm_state(warm)))

    def step_problem(self, contacts, velocities, h):
        """The step's contact problem (module docstring) for the active
        ``contacts`` (as ``on_step`` hands them) from the generalized
        ``velocities`` ν (3n,) at the step's start: a 2-D FrictionProblem
        with W = Hᵀ M⁻¹ H + D and q = u^free + the laws' normal offsets
        (μ = 0 without ``friction``: then its normal part is the step's LCP)."""
        v, c = np.asarray(velocities, float), contacts
        minv = self.discs.inverse_mass()
        u_minus = c.H.T @ v + c.w
        u_free = c.H.T @ (v + h * minv * self._gravity_forces()) + c.w
        return self._assemble(c, u_minus, u_free, minv, h)[0]

    def _gravity_forces(self):
        """f = (0, −m g, 0) per disc [N]."""
        f = np.zeros(3 * self.discs.n)
        f[1::3] = -self.discs.masses * self.gravity
        return f

    def _assemble(self, c, u_minus, u_free, minv, h):
        """(problem, compliance, impact) of the step problem for the active
        contacts c, from their velocities u⁻ and u^free (module docstring)."""
        from .delassus_kernel import delassus   # numba: imported where it runs

        qv = u_free.copy()
        D, offset, comp, impact = self.law.normal_terms(c, h, u_minus[0::2], u_free[0::2])
        qv[0::2] += offset
        diag = np.zeros(2 * c.m)
        if self.law.compliant:
            diag[0::2] = D
        H = c.H
        H.sort_indices()
        # W = Hᵀ M⁻¹ H + D, exactly symmetric (delassus_kernel)
        W = sp.csc_matrix(delassus(H.indptr.astype(np.int64), H.indices.astype(np.int64),
                                   H.data.astype(float), H.shape[0], minv, diag)[::-1],
                          shape=(2 * c.m, 2 * c.m))
        mu = self.mu[c.kind] if "friction" in self.effects else np.zeros(c.m)
        return FrictionProblem(W, qv, mu, 2), comp, impact

    def _solve_step(self, c, u_minus, u_free, minv, h, method, accuracy, warm=None):
        prob, comp, impact = self._assemble(c, u_minus, u_free, minv, h)
        t0 = time.perf_counter()
        fell_back = False
        if "friction" in self.effects:
            sol = None
            if warm is not None:
                sol = solve(prob, method=warm.method, accuracy=accuracy,
                            r0=warm.guess(c), **warm.options)
            fell_back = sol is not None and not sol.ok
            if sol is None or fell_back:
                sol = solve(prob, method=method, accuracy=accuracy)
            r = np.zeros(2 * c.m) if sol.r is None else np.asarray(sol.r, float)
        else:
            Wn = prob.W[0::2, :][:, 0::2].tocsc()
            sol = solve(LCP(Wn, prob.q[0::2]), method=method, accuracy=accuracy)
            r = np.zeros(2 * c.m)
            if sol.z is not None:
                r[0::2] = sol.z
        secs = time.perf_counter() - t0
        err = sol.certificate.error if sol.certificate is not None else np.inf
        return r, float(err), bool(sol.ok), sol.method, secs, fell_back, (comp, impact)


def _warm_state(warm):
    """What a resumed run needs to warm-start as this one would have."""
    return None if warm is None else {"keys": warm.keys.copy(), "r": warm.r.copy()}


class _WarmStart:
    """The previous step's impulses by contact identity (disc i, other body j,
    kind), for the next step's initial guess r0; ``regular``: the contacts
    are compliant (J regular: nsgs-newton's ``square_first``)."""

    def __init__(self, method, options, n_discs, regular=False):
        if method not in WARM_METHODS:
            raise InvalidOptionError(f"warm_start must be one of {WARM_METHODS} (methods that "
                                     f"start from r0) or None; got {method!r}")
        self.method, self.options = method, dict(options or {})
        if method == "nsgs-newton" and regular:
            # compliant contacts make J regular: Newton's step by J's own LU
            # (a tenth of the minimum-norm system's fill; hybrid.py)
            self.options.setdefault("square_first", True)
            self.options.setdefault("omega", COMPLIANT_OMEGA)
        if "r0" in self.options:
            raise InvalidOptionError("warm_options must not set r0: the warm start sets it")
        self.n = n_discs
        self.keys, self.r = np.zeros(0, np.int64), np.zeros((0, 2))

    def _key(self, c):
        return (c.i.astype(np.int64) * (self.n + 1) + (c.j + 1)) * 3 + c.kind

    def remember(self, c, r):
        keys = self._key(c)
        order = np.argsort(keys, kind="stable")
        self.keys, self.r = keys[order], r.reshape(-1, 2)[order]

    def guess(self, c):
        """Last step's (r_N, r_T) for the contacts that persist, 0 for new ones."""
        keys = self._key(c)
        r0 = np.zeros((c.m, 2))
        if self.keys.size:
            at = np.minimum(np.searchsorted(self.keys, keys), self.keys.size - 1)
            hit = self.keys[at] == keys
            r0[hit] = self.r[at[hit]]
        return r0.ravel()


