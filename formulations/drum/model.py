r"""Collisions of pulpwood logs in a debarking drum: one LCP per time step
(the decomposition paper, Kolesnikov 2013).

SI units throughout: metres, kilograms, seconds, newtons (stiffness N/m,
damping N·s/m, compliance m/N).

Model ("conditional stack", Kolesnikov 2013)
--------------------------------------------
L logs move along one vertical axis x (upward positive), log 0 lowest, the drum
shell below it.  Log i is two finite elements of stiffness s_i each (its lower
and upper halves) joining a massless lower boundary node, a centre node of mass
m_i, and a massless upper boundary node; element matrix over (lower, centre,
upper): s_i [[1, -1, 0], [-1, 2, -1], [0, -1, 1]].  Viscous damping λ_i acts on
the centre node while the log is in contact; gravity F_i = -m_i g.

Contact k (k = 0 .. L-1) lies below log k: k = 0 between the shell and log 0,
k >= 1 between the upper node of log k-1 and the lower node of log k.  N_k >= 0
is the compressive force, D_k >= 0 the gap, N_k D_k = 0.  The shell is rigid or
a spring k_s to ground carrying a massless surface node.

Derivation of the step problem (paper eqs. 17-21; its algebra 22-31 is lost)
---------------------------------------------------------------------------
Equations of motion and contact (17-20), with U_m the centre and U_b the
boundary displacements and C_b the (±1) contact incidence of boundary nodes:

    r_mm U_m + Λ U̇_m + M Ü_m + r_mb U_b = F_m                     (17)
    r_bm U_m + r_bb U_b = C_b N                                      (18)
    D = C_b' U_b + D_0 >= 0,  N >= 0,  N'D = 0                       (19-20)

1. *Boundary nodes.*  Each boundary node belongs to one element of one log, so
   r_bb = diag(s) and (18) reads, node by node, s_i (u_b - u_c) = f_b with f_b
   = (C_b N)_b: u_b = u_c + f_b / s_i, i.e. U_b = P U_m + S⁻¹ C_b N with P
   copying each log's centre displacement to its two boundary nodes.
2. *Centre nodes.*  Substituting in (17), r_mm U_m + r_mb U_b = 2 s_i u_c -
   s_i (u_b⁻ + u_b⁺) = -(f_b⁻ + f_b⁺): the massless halves transmit the contact
   forces unchanged, M Ü + Λ U̇ = F + G N, with G = P' C_b (L x L):
   G[i, i] = +1 (the contact below pushes log i up), G[i, i+1] = -1.
3. *Gaps.*  D = C_b' U_b + D_0 = G' U + C N + D_0 with the contact-path
   compliance C = C_b' S⁻¹ C_b (+ 1/k_s on contact 0 for an elastic shell):
   diagonal, C_00 = 1/s_0 (+1/k_s), C_kk = 1/s_{k-1} + 1/s_k.
4. *Time discretisation* (21), one-sided differences at step n, t_n = n τ:
   U̇ ≈ (U_n - U_{n-1})/τ, Ü ≈ (U_n - 2U_{n-1} + U_{n-2})/τ².  Then
   H U_n = R_n + G N_n with H = M/τ² + Λ/τ (diagonal, kg/s²) and
   R_n = F + M (2U_{n-1} - U_{n-2})/τ² + Λ U_{n-1}/τ (N), so
   U_n = H⁻¹ (R_n + G N_n).
5. *The LCP.*  Substituting in 3:

       D_n = A N_n + B_c(n),   A = C + G' H⁻¹ G,   B_c(n) = D_0 + G' H⁻¹ R_n,
       D_n >= 0, N_n >= 0, D_n' N_n = 0                                 (32-33)

   A [m/N], B_c [m].  H⁻¹ = τ²/(M + τΛ) is the bodies' mobility over one step.
6. *A is symmetric positive definite:* C is diagonal with positive entries
   (every contact path contains at least one log half of finite stiffness),
   and G' H⁻¹ G is symmetric positive semidefinite (H⁻¹ diagonal positive), so
   N'AN >= N'CN > 0 for N != 0.  Hence the LCP has exactly one solution, it is
   the minimiser of the convex QP  min ½ N'AN + B_c'N, N >= 0, and every
   registered method applies.  G' H⁻¹ G is tridiagonal, so A is banded
   (bandwidth 1): sparse, assembled once per set of damped logs.

Which logs are damped at step n is decided by the contact forces of step n-1
(a log is "in contact" if one of its two contacts carried force), so each step
stays one LCP.  Contact and free flight are the same equations: no event
detection.  The one-sided differences dissipate energy numerically (for a
free oscillator the amplitude shrinks by (1 + ω²τ²)^-½ per step); the energy
summary reports it as the balance's residual.

Stiffness model (documented choice)
-----------------------------------
:func:`log_half_stiffness`: each half of a log, between a contact and the
centre, is taken as a prism of height d/2, width d and length ℓ loaded across
the grain: s = E_T (d ℓ) / (d/2) = 2 E_T ℓ (Hooke's law k = EA/h).  The whole
log in diametral compression is then E_T ℓ.  Moduli across the grain for
spruce (USDA Forest Products Laboratory, *Wood Handbook*, FPL-GTR-190, 2010,
ch. 5, elastic ratios E_R/E_L ≈ 0.08, E_T/E_L ≈ 0.04): radial ≈ 0.8 GPa,
tangential ≈ 0.4 GPa.  A real cylinder flattens at a line contact (Hertz),
which is softer than the prism; since the peak force of an impact grows with
√k, the prism model errs on the high side — what an *upper* estimate of
collision forces needs.  Masses: :func:`log_mass` = ρ π d²/4 ℓ, with green
spruce ρ ≈ 860 kg/m³ and seasoned ≈ 450 kg/m³.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from qpcontact import solve
from qpcontact.core.errors import InvalidOptionError, InvalidProblemError
from qpcontact.core.matrices import as_vector
from qpcontact.core.problems import LCP
from qpcontact.core.progress import StepReporter

from .results import DrumResult

__all__ = ["Log", "Drum", "StepSizeWarning", "EFFECTS",
           "log_mass", "log_half_stiffness", "damping_from_ratio",
           "GREEN_SPRUCE_DENSITY", "SEASONED_SPRUCE_DENSITY", "SPRUCE_E_RADIAL",
           "SPRUCE_E_TANGENTIAL", "GRAVITY", "STEPS_PER_PERIOD"]

#: Gravitational acceleration [m/s²].
GRAVITY = 9.81
#: Density of green spruce [kg/m³] (module docstring: masses).
GREEN_SPRUCE_DENSITY = 860.0
#: Density of seasoned spruce [kg/m³].
SEASONED_SPRUCE_DENSITY = 450.0
#: Spruce's Young's modulus across the grain, radial [Pa] (module docstring:
#: stiffness model).
SPRUCE_E_RADIAL = 0.8e9
#: Spruce's Young's modulus across the grain, tangential [Pa]: the default of
#: :func:`log_half_stiffness`.
SPRUCE_E_TANGENTIAL = 0.4e9

#: The effects a drum model knows; a model assembles only the terms of those named.
EFFECTS = ("gravity", "damping", "shell_elasticity")

#: Fewer steps than this per shortest contact period trigger a StepSizeWarning.
STEPS_PER_PERIOD = 20


class StepSizeWarning(UserWarning):
    """The time step is too large to resolve a contact (see Drum.check_step)."""


def log_mass(diameter: float, length: float, density: float = GREEN_SPRUCE_DENSITY) -> float:
    """Mass [kg] of a cylindrical log: ρ π d²/4 ℓ (d, ℓ in m, ρ in kg/m³)."""
    return float(density * np.pi * diameter ** 2 / 4.0 * length)


def log_half_stiffness(diameter: float, length: float,
                       modulus: float = SPRUCE_E_TANGENTIAL) -> float:
    """Stiffness [N/m] of one half of a log across the grain: 2 E ℓ.

    The half between a contact and the centre is a prism of height d/2, width d
    and length ℓ (module docstring); ``modulus`` [Pa] is the transverse Young's
    modulus (spruce: 0.8e9 radial, 0.4e9 tangential).  ``diameter`` [m] cancels
    but is validated.
    """
    _positive(diameter=diameter, length=length, modulus=modulus)
    return float(modulus * (diameter * length) / (diameter / 2.0))


def damping_from_ratio(ratio: float, mass: float, stiffness: float) -> float:
    """Viscous coefficient [N·s/m] for a damping ratio ζ of the log on its own
    contact spring: λ = 2 ζ √(k m)  (m in kg, k in N/m)."""
    if ratio < 0:
        raise InvalidProblemError(f"damping ratio must be >= 0, got {ratio}")
    return float(2.0 * ratio * np.sqrt(stiffness * mass))


def _positive(**values):
    for name, v in values.items():
        if not (np.isfinite(v) and v > 0):
            raise InvalidProblemError(f"{name} must be a positive finite number (SI units); got {v}")


@dataclass(frozen=True)
class Log:
    """One log: mass [kg], half-element stiffness s [N/m], damping λ [N·s/m]."""

    mass: float
    stiffness: float
    damping: float = 0.0
    diameter: float | None = None   # m, informative
    length: float | None = None     # m, informative

    def __post_init__(self):
        _positive(mass=self.mass, stiffness=self.stiffness)
        if not (np.isfinite(self.damping) and self.damping >= 0):
            raise InvalidProblemError(f"damping must be >= 0 (N·s/m); got {self.damping}")

    @classmethod
    def from_wood(cls, diameter: float, length: float, density: float = GREEN_SPRUCE_DENSITY,
                  modulus: float = SPRUCE_E_TANGENTIAL, damping_ratio: float = 0.0) -> "Log":
        """A log from engineering data (SI): diameter and length [m], wood
        density [kg/m³], transverse Young's modulus [Pa], damping ratio ζ [-]
        (λ = 2ζ√(s m) on the half-element stiffness s)."""
        _positive(diameter=diameter, length=length, density=density)
        m = log_mass(diameter, length, density)
        s = log_half_stiffness(diameter, length, modulus)
        return cls(m, s, damping_from_ratio(damping_ratio, m, s), diameter, length)


class Drum:
    """A stack of logs above the drum shell, and its time stepper.

    Parameters
    ----------
    logs : sequence of Log
        Bottom to top.
    gaps : array_like
        Initial gap [m] below each log (gap 0: between the shell and log 0).
    velocities : array_like, optional
        Initial velocities [m/s] of the log centres, upward positive (default 0).
    shell_stiffness : float, optional
        Stiffness [N/m] of the shell at the contact; needs the effect
        ``"shell_elasticity"``.  Without it the shell is rigid.
    effects : iterable of str
        Subset of :data:`EFFECTS`.  Terms of effects not named are not
        assembled at all (no damping arrays without ``"damping"``).
    gravity : float
        g [m/s²].

    Raises
    ------
    InvalidProblemError
        Bad shapes or values, an unknown effect, or data for an effect not
        named (damping coefficients without ``"damping"``, a shell stiffness
        without ``"shell_elasticity"``) — never silently ignored.
    """

    def __init__(self, logs, gaps, velocities=None, *, shell_stiffness: float | None = None,
                 effects=("gravity",), gravity: float = GRAVITY):
        logs = list(logs)
        if not logs or not all(isinstance(lg, Log) for lg in logs):
            raise InvalidProblemError("logs must be a non-empty sequence of Log objects")
        self.logs = logs
        L = len(logs)
        self.effects = self._check_effects(effects)
        self.gaps = as_vector(gaps, L, "gaps")
        if np.any(self.gaps < 0):
            raise InvalidProblemError(
                f"initial gaps must be >= 0 m (interpenetrating logs); gap {int(np.argmin(self.gaps))} "
                f"is {self.gaps.min():g}")
        self.velocities = np.zeros(L) if velocities is None else as_vector(velocities, L, "velocities")
        self.mass = np.array([lg.mass for lg in logs])
        self.half_stiffness = np.array([lg.stiffness for lg in logs])
        damping = np.array([lg.damping for lg in logs])
        if "damping" in self.effects:
            self.damping = damping
        else:
            if np.any(damping > 0):
                raise InvalidProblemError(
                    "logs have damping coefficients but 'damping' is not among the effects; "
                    "add it to effects= or build the logs without damping")
            self.damping = None  # not assembled
        if shell_stiffness is not None:
            if "shell_elasticity" not in self.effects:
                raise InvalidProblemError(
                    "shell_stiffness given but 'shell_elasticity' is not among the effects")
            _positive(shell_stiffness=shell_stiffness)
        elif "shell_elasticity" in self.effects:
            raise InvalidProblemError("effect 'shell_elasticity' needs shell_stiffness= (N/m)")
        self.shell_stiffness = shell_stiffness
        self.gravity = float(gravity) if "gravity" in self.effects else 0.0
        # Contact-path compliance C (diagonal, m/N).
        c = 1.0 / self.half_stiffness
        self.compliance = c.copy()
        self.compliance[1:] += c[:-1]
        if shell_stiffness is not None:
            self.compliance[0] += 1.0 / shell_stiffness
        self._structures = {}

    @staticmethod
    def _check_effects(effects) -> frozenset:
        if isinstance(effects, str):
            effects = (effects,)
        effects = frozenset(effects)
        unknown = sorted(effects - set(EFFECTS))
        if unknown:
            raise InvalidProblemError(
                f"unknown effect(s) {unknown}; the drum model knows {list(EFFECTS)}")
        return effects

    @property
    def n_logs(self) -> int:
        return len(self.logs)

    @property
    def n_contacts(self) -> int:
        return len(self.logs)

    def contact_periods(self) -> np.ndarray:
        """Period 2π√(μ/k) [s] of each contact: μ the reduced mass of the two
        bodies (the log alone against the shell), k the series stiffness of the
        contact path (the two log halves, or the lowest half and the shell)."""
        m = self.mass
        mu = m.copy()
        mu[1:] = m[1:] * m[:-1] / (m[1:] + m[:-1])
        k = 1.0 / self.compliance
        return 2.0 * np.pi * np.sqrt(mu / k)

    def check_step(self, tau: float) -> float:
        """Warn (StepSizeWarning) when τ [s] gives fewer than STEPS_PER_PERIOD
        steps per shortest contact period; returns that period [s]."""
        _positive(tau=tau)
        T = float(self.contact_periods().min())
        if tau > T / STEPS_PER_PERIOD:
            warnings.warn(
                f"time step {tau:.3g} s is too large to resolve a contact: the shortest contact "
                f"period is {T:.3g} s, {T / tau:.1f} steps per period (< {STEPS_PER_PERIOD}); peak "
                f"forces will be underestimated. Use tau <= {T / STEPS_PER_PERIOD:.3g} s.",
                StepSizeWarning, stacklevel=3)
        return T

    # -- assembly ----------------------------------------------------------------

    def _h(self, tau: float, damped) -> np.ndarray:
        """Diagonal of H = M/τ² + Λ/τ [kg/s²]."""
        h = self.mass / tau ** 2
        if self.damping is not None and damped is not None:
            h = h + np.where(damped, self.damping, 0.0) / tau
        return h

    def step_matrix(self, tau: float, damped=None):
        """A = C + G' H⁻¹ G [m/N] (sparse, tridiagonal) for the damped-log mask."""
        hinv = 1.0 / self._h(tau, damped)
        main = self.compliance + hinv
        main[1:] += hinv[:-1]
        off = -hinv[:-1]
        return sp.diags([off, main, off], [-1, 0, 1], format="csc")

    def _structure(self, tau, damped):
        key = (tau, None if damped is None or self.damping is None else np.packbits(damped).tobytes())
        st = self._structures.get(key)
        if st is None:
            if len(self._structures) > 64:
                self._structures.clear()
            st = LCP(self.step_matrix(tau, damped), np.zeros(self.n_contacts)).structure
            st.declare_spd()  # proven in the module docstring (step 6); tested
            self._structures[key] = st
        return st

    def step_problem(self, tau: float, U1, U2, damped=None) -> LCP:
        """The LCP D = A N + B_c of the step after displacements U1 = U_{n-1},
        U2 = U_{n-2} [m]; z = N [N], w = D [m]."""
        _, B = self._rhs(tau, np.asarray(U1, float), np.asarray(U2, float), damped)
        return LCP.with_structure(self._structure(tau, damped), B)

    def _rhs(self, tau, U1, U2, damped):
        h = self._h(tau, damped)
        R = self.mass * (2.0 * U1 - U2) / tau ** 2 - self.mass * self.gravity
        if self.damping is not None and damped is not None:
            R = R + np.where(damped, self.damping, 0.0) * U1 / tau
        x = R / h
        B = self.gaps + x
        B[1:] -= x[:-1]
        return R, B

    # -- simulation ----------------------------------------------------------------

    def simulate(self, tau: float, steps: int, *, method: str = "bpp", accuracy="high",
                 on_step=None, progress: bool = False, resume: dict | None = None,
                 checkpoint=None, checkpoint_seconds: float = 5.0,
                 **options) -> DrumResult:
        """Run ``steps`` steps of size ``tau`` [s] from the initial state.

        The state before the first step is the exact free flight at t = -τ
        (U_{-1} = -τ v0 - ½ g τ²), so a free fall is reproduced exactly.  Each
        step's LCP is solved by ``method`` (default ``"bpp"``, warm-started with
        the previous step's contact set); an answer that fails its certificate
        is re-solved with ``method="auto"`` (counted in ``fallbacks``).
        ``on_step(n, lcp, solution)`` is called after every step.

        ``checkpoint(result)`` is called every ``checkpoint_seconds`` and at
        the end with the run so far (a :class:`DrumResult` of steps 0..n);
        ``resume`` = {"completed": n, and the arrays of a results file
        (:mod:`.scene`) for steps 0..n} continues such a run: the state of step n (the last
        two displacements, the contact forces that decide the damped set and
        the warm start, the cumulative dissipation) is all the stepper
        carries, so the continued run equals the uninterrupted one bit for bit.
        Returns a :class:`DrumResult` (SI units).
        """
        steps = int(steps)
        if steps < 1:
            raise InvalidOptionError(f"steps must be >= 1, got {steps}")
        self.check_step(tau)
        L = self.n_logs
        U = np.zeros((steps + 1, L))
        N = np.zeros((steps + 1, L))
        D = np.zeros((steps + 1, L))
        D[0] = self.gaps
        U_prev = -tau * self.velocities - 0.5 * self.gravity * tau ** 2
        errors = np.zeros(steps + 1)
        iterations = np.zeros(steps + 1, np.int64)
        methods_used = []
        fallbacks = 0
        solve_time = 0.0   # the certified solves' share of the wall time
        viscous = np.zeros(steps + 1)
        active = np.zeros(L, bool)
        first = 1
        if resume is not None:
            n0 = int(resume["completed"])
            if not 0 <= n0 <= steps or resume["forces"].shape[1] != L:
                raise InvalidOptionError(f"cannot resume: {n0} completed steps of {steps}, "
                                         f"{resume['forces'].shape[1]} contacts against {L}")
            U[:n0 + 1] = resume["displacements"][:n0 + 1]
            N[:n0 + 1] = resume["forces"][:n0 + 1]
            D[:n0 + 1] = resume["gaps"][:n0 + 1]
            errors[:n0 + 1] = resume["certificate_error"][:n0 + 1]
            if "iterations" in resume:
                iterations[:n0 + 1] = resume["iterations"][:n0 + 1]
            viscous[:n0 + 1] = resume["energy/viscous"][:n0 + 1]
            methods_used = list(resume["method"][1:n0 + 1])
            fallbacks = int(resume.get("fallbacks", 0))
            active = N[n0] > 0
            first = n0 + 1
        report = StepReporter(steps, "drum steps", progress, checkpoint, checkpoint_seconds)
        start = time.perf_counter()

        def partial(n):
            V = np.empty((n + 1, L))
            V[0] = self.velocities
            V[1:] = (U[1:n + 1] - U[:n]) / tau
            return DrumResult(drum=self, tau=tau, t=tau * np.arange(n + 1), forces=N[:n + 1],
                              gaps=D[:n + 1], displacements=U[:n + 1], velocities=V,
                              viscous_dissipation=viscous[:n + 1],
                              certificate_errors=errors[:n + 1], iterations=iterations[:n + 1],
                              methods=list(methods_used),
                              fallbacks=fallbacks, wall_time=time.perf_counter() - start,
                              solve_time=solve_time)
        for n in range(first, steps + 1):
            U1 = U[n - 1]
            U2 = U_prev if n == 1 else U[n - 2]
            damped = self._in_contact(N[n - 1]) if self.damping is not None else None
            R, B = self._rhs(tau, U1, U2, damped)
            lcp = LCP.with_structure(self._structure(tau, damped), B)
            opts = dict(options)
            if method == "bpp":
                opts.setdefault("initial_active", active)
            t_solve = time.perf_counter()
            sol = solve(lcp, method=method, accuracy=accuracy, **opts)
            if not sol.ok:
                fallbacks += 1
                sol = solve(lcp, method="auto", accuracy=accuracy)
                if not sol.ok:
                    raise _step_failed(n, sol)
            solve_time += time.perf_counter() - t_solve
            z = sol.z
            N[n] = z
            D[n] = sol.w
            active = z > 0
            x = (R + _g_times(z)) / self._h(tau, damped)
            U[n] = x
            errors[n] = sol.error
            iterations[n] = sol.iterations or 0
            methods_used.append(sol.method)
            if self.damping is not None:
                v = (U[n] - U1) / tau
                viscous[n] = viscous[n - 1] + tau * float(np.sum(np.where(damped, self.damping, 0.0) * v * v))
            if on_step is not None:
                on_step(n, lcp, sol)
            report.after(n, errors, partial)
        return report.finish(partial(steps))

    def _in_contact(self, forces) -> np.ndarray:
        """Logs touching something: the contact below or above carried force."""
        on = forces > 0
        damped = on.copy()
        damped[:-1] |= on[1:]
        return damped

    def assembled_nbytes(self, tau: float) -> int:
        """Bytes of the arrays the model assembles for one step (A's data, the
        diagonal H, and the damping coefficients when damping is an effect)."""
        A = self.step_matrix(tau)
        total = A.data.nbytes + A.indices.nbytes + A.indptr.nbytes + self._h(tau, None).nbytes
        total += self.compliance.nbytes + self.mass.nbytes
        if self.damping is not None:
            total += self.damping.nbytes
        return total


def _g_times(N: np.ndarray) -> np.ndarray:
    """G N: force on each log from its contacts (below +, above -)."""
    f = N.copy()
    f[:-1] -= N[1:]
    return f


def _step_failed(n, sol):
    from qpcontact.core.errors import SolverFailedError

    return SolverFailedError(
        f"drum step {n}: no method returned a certified contact force ({sol.message}); "
        "the step matrix may be too ill-conditioned for this tau")
