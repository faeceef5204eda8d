r"""Moreau–Jean time stepping of the 2-D drum, one certified contact problem per step.

SI units: s, m, m/s, rad/s, N·s (impulses), J (energies).

The step (h [s], midpoint positions, impulses implicit)
-------------------------------------------------------
With ν = (vx, vy, ω) per disc, M = diag(m, m, I), f the gravity forces
(0, −m g, 0) and H, w the contact kinematics of formulations.drum2d.contacts
(u = Hᵀ ν + w), one step from (q, ν) at t is

    ν⁺ = ν + h M⁻¹ f + M⁻¹ H r                                      (momentum)
    q⁺ = q + h (ν + ν⁺)/2                                            (θ = ½)
    u⁺ = Hᵀ ν⁺ + w,   u⁻ = Hᵀ ν + w,
    for each active contact:  0 <= r_N ⟂ u_N⁺ + e u_N⁻ >= 0           (Newton's law)
                              |r_T| <= μ r_N, Coulomb on u_T⁺           (friction)

r (N·s) the contact impulses over the step.  A contact is active when its
predicted gap g + h (u_N⁻ + u_N^free)/2 is <= 0, u^free = Hᵀ(ν + h M⁻¹ f) + w:
the gap the free motion would leave at the end of the step.  Substituting
ν⁺ gives the local problem

    û = W r + q,   W = Hᵀ M⁻¹ H  (M diagonal: sparse, cheap),
                   q = u^free + (e u_N⁻, 0),

a 2-D FrictionProblem (qpcontact.friction.problem), or without friction the
LCP 0 <= r_N ⟂ W_NN r_N + q_N >= 0 — both solved by qpcontact.solve and
certified from the data.  A step whose answer is not certified is recorded
(``Drum2DResult.uncertified``) and warned about, or raises with
``on_uncertified="raise"``; never silently kept.

Energy bookkeeping (exact identities of the scheme)
---------------------------------------------------
K = ½ νᵀ M ν, P = Σ m g y.  From the momentum line,
ΔK = (h f + H r)ᵀ (ν + ν⁺)/2, and the midpoint positions make ΔP = −h fᵀ (ν + ν⁺)/2
exactly (f constant), so

    ΔK + ΔP = rᵀ Hᵀ (ν + ν⁺)/2 = rᵀ (u⁻ + u⁺)/2 − rᵀ w.

−rᵀ w = Σ r · V is the work of the moving shell and lifters (the drive; the
wall takes −r at velocity V).  Friction dissipates D_f = −Σ r_T u_T⁺ >= 0
(Coulomb: r_T opposes the slip u_T⁺).  The rest, D_i = −rᵀ(u⁻ + u⁺)/2 − D_f,
is the impacts' loss: its normal part −r_N (u_N⁻ + u_N⁺)/2 = −r_N (1 − e) u_N⁻/2
where r_N > 0, so with e = 1 the scheme dissipates nothing at the normal
impacts (to the certificate's tolerance) and K + P is kept exactly when friction
is off and the shell still.  The remainder ΔK + ΔP − drive + D_f + D_i is
rounding and the certificate's residual; it is reported per run.

The scheme's own errors are in the positions: an impact is resolved up to one
step early (a gap of at most h |u_N|) and a contact carried along the curved
shell drifts into it by about (h v)²/(2ρ) per step (ρ the centre's radius of
curvature); the run reports the largest penetration.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from qpcontact import solve
from qpcontact.core.errors import InvalidOptionError, SolverFailedError
from qpcontact.core.problems import LCP
from qpcontact.friction.problem import FrictionProblem

from .contacts import find_contacts
from .geometry import GRAVITY, Discs, Shell

__all__ = ["Drum2D", "Drum2DResult", "EFFECTS", "UncertifiedStepWarning"]

#: the effects the model knows; gravity is always on
EFFECTS = ("gravity", "friction", "rotation", "damping")


class UncertifiedStepWarning(UserWarning):
    """A step's contact problem came back without a certificate meeting the accuracy."""


@dataclass
class Drum2DResult:
    """A run: times ``t`` (S+1,) [s], ``positions`` (S+1, n, 2) [m],
    ``velocities`` (S+1, n, 2) [m/s], ``spins`` (S+1, n) [rad/s]; per step
    (index s = the step from t[s] to t[s+1]) ``n_contacts``, ``n_active``,
    ``certificate_error``, ``certified``, ``method``, ``solve_seconds``,
    ``pairs_checked``; energies [J] per state (``kinetic``, ``potential``)
    and per step (``drive``, ``friction_loss``, ``impact_loss``,
    ``remainder``); ``contacts``: per step a dict of the active contacts'
    arrays (i, j, kind, r_n, r_t [N·s], slip u_T⁺ [m/s], gap [m]) when kept;
    ``fallback`` per step: the warm-started route was not certified and
    ``method`` solved the step instead (always False without ``warm_start``)."""

    t: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    spins: np.ndarray
    n_contacts: np.ndarray
    n_active: np.ndarray
    certificate_error: np.ndarray
    certified: np.ndarray
    method: list
    solve_seconds: np.ndarray
    pairs_checked: np.ndarray
    kinetic: np.ndarray
    potential: np.ndarray
    drive: np.ndarray
    friction_loss: np.ndarray
    impact_loss: np.ndarray
    remainder: np.ndarray
    max_penetration: float
    contacts: list = field(default_factory=list)
    effects: frozenset = frozenset()
    fallback: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))

    @property
    def uncertified(self) -> np.ndarray:
        """The steps whose contact problem was not certified."""
        return np.flatnonzero(~self.certified)

    @property
    def worst_certificate(self) -> float:
        return float(self.certificate_error.max(initial=0.0))

    def energy_summary(self) -> dict:
        """Totals [J]: ΔK, ΔP, drive work, friction and impact losses, remainder."""
        return {"kinetic_change": float(self.kinetic[-1] - self.kinetic[0]),
                "potential_change": float(self.potential[-1] - self.potential[0]),
                "drive": float(self.drive.sum()), "friction_loss": float(self.friction_loss.sum()),
                "impact_loss": float(self.impact_loss.sum()),
                "remainder": float(self.remainder.sum())}


class Drum2D:
    """The 2-D drum cross-section: ``discs`` (geometry.Discs, copied) in a
    ``shell`` (geometry.Shell); ``effects`` among EFFECTS (gravity always);
    ``mu_disc``, ``mu_shell``, ``mu_lifter`` the friction coefficients (used
    only with ``friction``), ``restitution`` e in [0, 1] (used only with
    ``damping``; without it e = 1, elastic impacts)."""

    def __init__(self, discs: Discs, shell: Shell, effects=("gravity",), *, mu_disc=0.4,
                 mu_shell=0.4, mu_lifter=0.4, restitution=0.0, gravity=GRAVITY):
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
        self.discs, self.shell, self.effects = discs, shell, effects
        self.mu = np.array([mu_disc, mu_shell, mu_lifter], float)
        self.restitution = float(restitution) if "damping" in effects else 1.0
        self.omega = shell.omega if "rotation" in effects else 0.0
        self.gravity = float(gravity)
        inside = np.hypot(*discs.positions.T) + discs.radii
        if np.any(inside > shell.radius * (1 + 1e-9)):
            k = int(np.argmax(inside - shell.radius))
            raise InvalidOptionError(f"disc {k} reaches {inside[k]:.4g} m from the axis, outside "
                                     f"the shell (R = {shell.radius} m)")

    def _margin(self, h, v, spin):
        rad = self.discs.radii
        speed = np.hypot(*v.T) + rad * np.abs(spin)
        reach = 2.0 * speed.max(initial=0.0) + abs(self.omega) * self.shell.radius \
            + 2.0 * self.gravity * h
        return 1.5 * h * reach + 1e-9 * self.shell.radius

    def simulate(self, h: float, steps: int, *, method: str = "auto", accuracy="high",
                 keep_contacts: bool = True, on_uncertified: str = "warn",
                 warm_start: str | None = None, warm_options=None) -> Drum2DResult:
        """``steps`` Moreau–Jean steps of ``h`` [s] (module docstring).

        ``warm_start`` (with friction only): a friction method taking ``r0``
        ("nsgs", "nsgs-newton", "newton") started from the previous step's
        impulses, matched contact by contact (module docstring, "Warm
        starts"); a step it does not certify at ``accuracy`` is solved again
        by ``method`` and flagged in ``Drum2DResult.fallback``.
        ``warm_options``: more options for that method (``max_sweeps``...)."""
        if warm_start is not None and "friction" not in self.effects:
            raise InvalidOptionError("warm_start needs the 'friction' effect (without it each "
                                     "step is an LCP, solved by `method`)")
        if not (np.isfinite(h) and h > 0) or int(steps) < 1:
            raise InvalidOptionError(f"h must be > 0 and steps >= 1; got h={h}, steps={steps}")
        if on_uncertified not in ("warn", "raise"):
            raise InvalidOptionError(f"on_uncertified must be 'warn' or 'raise'; got "
                                     f"{on_uncertified!r}")
        steps = int(steps)
        d = self.discs
        n = d.n
        minv = d.inverse_mass()
        mdiag = d.mass_diagonal()
        f = np.zeros(3 * n)
        f[1::3] = -d.masses * self.gravity
        q = d.positions.copy()
        v = np.column_stack([d.velocities, d.spins]).ravel()
        S = steps
        out = dict(t=np.arange(S + 1) * h, positions=np.zeros((S + 1, n, 2)),
                   velocities=np.zeros((S + 1, n, 2)), spins=np.zeros((S + 1, n)))
        per = {k: np.zeros(S) for k in ("certificate_error", "solve_seconds", "drive",
                                         "friction_loss", "impact_loss", "remainder")}
        counts = {k: np.zeros(S, np.int64) for k in ("n_contacts", "n_active", "pairs_checked")}
        certified = np.ones(S, bool)
        methods = [""] * S
        kin, pot = np.zeros(S + 1), np.zeros(S + 1)
        contacts_kept = []
        worst_pen = 0.0
        fallback = np.zeros(S, bool)
        warm = None if warm_start is None else _WarmStart(warm_start, warm_options, n)

        def record(s, q, v):
            V = v.reshape(n, 3)
            out["positions"][s], out["velocities"][s], out["spins"][s] = q, V[:, :2], V[:, 2]
            kin[s] = 0.5 * float(mdiag @ (v * v))
            pot[s] = float(self.gravity * d.masses @ q[:, 1])

        record(0, q, v)
        for s in range(S):
            t = s * h
            V = v.reshape(n, 3)
            c = find_contacts(d, self.shell, t, self.omega, self._margin(h, V[:, :2], V[:, 2]),
                              positions=q)
            counts["n_contacts"][s], counts["pairs_checked"][s] = c.m, c.pairs_checked
            worst_pen = max(worst_pen, float(-c.gap.min(initial=0.0)))
            v_free = v + h * minv * f
            u_minus = c.H.T @ v + c.w
            u_free = c.H.T @ v_free + c.w
            active = c.gap + 0.5 * h * (u_minus[0::2] + u_free[0::2]) <= 0.0
            c = c.subset(active)
            counts["n_active"][s] = c.m
            u_minus, u_free = u_minus[np.repeat(active, 2)], u_free[np.repeat(active, 2)]
            r = np.zeros(2 * c.m)
            if c.m:
                r, err, ok, name, secs, fallback[s] = self._solve_step(
                    c, u_minus, u_free, minv, method, accuracy, warm)
                per["certificate_error"][s], per["solve_seconds"][s] = err, secs
                certified[s], methods[s] = ok, name
                if not ok:
                    msg = (f"step {s} (t = {t:.6g} s): contact problem with {c.m} contacts not "
                           f"certified by {name} (error {err:.3g})")
                    if on_uncertified == "raise":
                        raise SolverFailedError(msg)
                    warnings.warn(msg, UncertifiedStepWarning, stacklevel=2)
            v_new = v_free + minv * (c.H @ r) if c.m else v_free
            q = q + 0.5 * h * (v.reshape(n, 3)[:, :2] + v_new.reshape(n, 3)[:, :2])
            record(s + 1, q, v_new)
            if c.m:
                u_plus = c.H.T @ v_new + c.w
                drive = -float(r @ c.w)
                fric = -float(r[1::2] @ u_plus[1::2])
                imp = -float(r @ (u_minus + u_plus)) / 2.0 - fric
                per["drive"][s], per["friction_loss"][s], per["impact_loss"][s] = drive, fric, imp
                if keep_contacts:
                    contacts_kept.append(dict(i=c.i, j=c.j, kind=c.kind, r_n=r[0::2],
                                              r_t=r[1::2], slip=u_plus[1::2], gap=c.gap,
                                              normal=c.normal))
            elif keep_contacts:
                contacts_kept.append(None)
            per["remainder"][s] = (kin[s + 1] + pot[s + 1] - kin[s] - pot[s] - per["drive"][s]
                                   + per["friction_loss"][s] + per["impact_loss"][s])
            if warm is not None:
                warm.remember(c, r)
            v = v_new
        return Drum2DResult(fallback=fallback, **out, **counts, certified=certified, method=methods,
                            kinetic=kin, potential=pot, max_penetration=worst_pen,
                            contacts=contacts_kept, effects=self.effects, **per)

    def _solve_step(self, c, u_minus, u_free, minv, method, accuracy, warm=None):
        W = (c.H.T @ sp.diags(minv) @ c.H).tocsc()
        W = 0.5 * (W + W.T)
        qv = u_free.copy()
        qv[0::2] += self.restitution * u_minus[0::2]
        t0 = time.perf_counter()
        fell_back = False
        if "friction" in self.effects:
            prob = FrictionProblem(W, qv, self.mu[c.kind], 2)
            sol = None
            if warm is not None:
                sol = solve(prob, method=warm.method, accuracy=accuracy,
                            r0=warm.guess(c), **warm.options)
            fell_back = sol is not None and not sol.ok
            if sol is None or fell_back:
                sol = solve(prob, method=method, accuracy=accuracy)
            r = np.zeros(2 * c.m) if sol.r is None else np.asarray(sol.r, float)
        else:
            Wn = W[0::2, :][:, 0::2].tocsc()
            sol = solve(LCP(Wn, qv[0::2]), method=method, accuracy=accuracy)
            r = np.zeros(2 * c.m)
            if sol.z is not None:
                r[0::2] = sol.z
        secs = time.perf_counter() - t0
        err = sol.certificate.error if sol.certificate is not None else np.inf
        return r, float(err), bool(sol.ok), sol.method, secs, fell_back


class _WarmStart:
    """The previous step's impulses by contact identity (disc i, other body j,
    kind), for the next step's initial guess r0."""

    def __init__(self, method, options, n_discs):
        self.method, self.options = method, dict(options or {})
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


