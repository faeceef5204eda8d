r"""The contact time step shared by planar mechanisms (formulations.mechanisms)
and spatial trees (formulations.multibody.contacts): the semi-implicit step
of the penalty paper (Nikolsky et al. 2012) with its penalty QP, or the exact LCP.

SI units: coordinates m or rad, velocities m/s or rad/s, reactions N, gaps m,
time s.

A system (:class:`ContactSystem`) supplies, at (t, q, ν) and look-ahead Δt,
one :class:`formulations.stepping.penalty_step.PenaltyStep` (G as an operator, Q, J,
B = (2/Δt²)(Φ + ΔtΦ̇), D = J̇ν, C) and an acceleration offset a₀ that does
not depend on the reactions (zero unless bilateral constraints are closed
inside the step); the step is then ::

    λ from the penalty QP (or the exact LCP), certified against the exact LCP;
    a = G⁻¹(Q + J'λ) + a₀;   q ← q ⊕ (h ν + ½h² a);   ν ← ν + h a.

The loop below is the only place this happens, so every system gets the same
certification, progress bar, checkpoints and bit-identical resume: the
stepper's state after step n is (q_n, ν_n) and the penalty μ in use, and μ is
recovered from the per-step record (the last μ the automatic choice kept).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from qpcontact import solve
from qpcontact.core.errors import InvalidOptionError, SolverFailedError
from qpcontact.core.progress import StepReporter
from qpcontact.plots.figures import save_figure

from .penalty_step import exact_lcp, solve_penalty

__all__ = ["ContactSystem", "MechanismResult", "ROUTES", "lookahead_for"]

#: How a step's reactions are found (``simulate(route=)``): the penalty QP or the exact LCP.
ROUTES = ("penalty", "lcp")


class ContactSystem:
    """What a system provides to :meth:`simulate` (subclasses implement):

    - ``initial_state() -> (q0, ν0)``;
    - ``step_problem(t, q, ν, Δt) -> (PenaltyStep, Φ, a₀)``;
    - ``gaps(q, ν) -> Φ`` [m];
    - ``integrate(q, dq) -> q ⊕ dq``;
    - ``coordinate_names()`` and ``contact_names()`` (lists of str).
    """

    def simulate(self, h: float, steps: int, *, lookahead: float | None = None,
                 route: str = "penalty", mu="auto", method: str = "auto", accuracy="high",
                 progress: bool = False, resume: dict | None = None, checkpoint=None,
                 checkpoint_seconds: float = 5.0, **options) -> "MechanismResult":
        """Integrate ``steps`` steps of size ``h`` [s] with look-ahead Δt
        (default h, elastic; see mechanisms.lookahead_for).

        ``route="penalty"`` solves the penalty QP with ``method`` (μ chosen
        automatically at the first step that needs it, re-chosen whenever a
        step's λ fails its certificate against the exact LCP); ``route="lcp"``
        solves the exact LCP (pivoting).  Every step's λ is certified against
        the exact LCP; a step that cannot be certified raises SolverFailedError
        naming the step.  ``checkpoint(result)`` is called every
        ``checkpoint_seconds`` and at the end with the result so far;
        ``resume`` (a results file's arrays and "completed") continues an
        interrupted run so that the result equals an uninterrupted one.
        """
        if route not in ROUTES:
            raise InvalidOptionError(f"route must be one of {ROUTES}, not {route!r}")
        if not h > 0 or int(steps) < 1:
            raise InvalidOptionError("h must be > 0 and steps >= 1")
        steps = int(steps)
        dt = h if lookahead is None else float(lookahead)
        q, v = self.initial_state()
        names = self.contact_names()
        T = np.arange(steps + 1) * h
        Qs = np.zeros((T.size, q.size))
        Vs = np.zeros((T.size, v.size))
        Lam = np.zeros((T.size, len(names)))
        Phis = np.zeros((T.size, len(names)))
        mus = np.full(T.size, np.nan)
        errors = np.zeros(T.size)
        iterations = np.zeros(T.size, np.int64)
        methods = [""] * T.size
        Qs[0], Vs[0] = q, v
        mu_now, first = mu, 1
        if resume is not None:
            n0 = int(resume["completed"])
            if not 0 <= n0 <= steps or resume["q"].shape[1] != q.size \
                    or resume["reactions"].shape[1] != len(names):
                raise InvalidOptionError(f"cannot resume: {n0} completed steps of {steps}, "
                                         f"{resume['q'].shape[1]} coordinates and "
                                         f"{resume['reactions'].shape[1]} contacts against "
                                         f"{q.size} and {len(names)}")
            k = slice(0, n0 + 1)
            Qs[k], Vs[k], Lam[k], Phis[k] = (resume[a][k] for a in ("q", "v", "reactions", "gaps"))
            mus[k], errors[k], iterations[k] = (resume[a][k] for a in
                                                ("mu", "certificate_error", "iterations"))
            methods[k] = resume["method"][k]
            if mu == "auto":
                kept = [m for m in mus[1:n0 + 1] if np.isfinite(m) and m]
                mu_now = kept[-1] if kept else mu
            q, v, first = Qs[n0].copy(), Vs[n0].copy(), n0 + 1
        lcp_method = "lemke" if method == "auto" else method
        report = StepReporter(steps, "contact steps", progress, checkpoint, checkpoint_seconds)

        def partial(n):
            Phis[n] = self.gaps(Qs[n], Vs[n])    # what step n + 1 computes first, bit for bit
            return MechanismResult(self, T[:n + 1], Qs[:n + 1], Vs[:n + 1], Lam[:n + 1],
                                   Phis[:n + 1], mus[:n + 1], h, dt, errors[:n + 1],
                                   iterations[:n + 1], methods[:n + 1])

        for i in range(first, T.size):
            t = T[i - 1]
            step, Phi, a0 = self.step_problem(t, q, v, dt)
            Phis[i - 1] = Phi
            if route == "lcp":
                sol = solve(exact_lcp(step), method=lcp_method, accuracy=accuracy)
                if not sol.ok:
                    raise SolverFailedError(f"step {i} (t = {t:.6g} s): the exact LCP was not "
                                            f"solved ({sol.message})")
                lam, errors[i], iterations[i], methods[i] = (sol.z, sol.error,
                                                             sol.iterations or 0, sol.method)
            else:
                res = solve_penalty(step, mu_now, method=method, accuracy=accuracy, **options)
                if not res.ok and mu_now != "auto":
                    res = solve_penalty(step, "auto", method=method, accuracy=accuracy, **options)
                if not res.ok:
                    raise SolverFailedError(f"step {i} (t = {t:.6g} s): {res.message}")
                if mu == "auto" and res.mu:
                    mu_now = res.mu  # keep the chosen mu while it keeps being certified
                mus[i] = res.mu
                lam = res.lam
                if res.lcp_certificate is not None:     # None: no contacts
                    qp = res.qp_solution
                    errors[i] = res.lcp_certificate.error
                    iterations[i] = qp.iterations or 0
                    methods[i] = qp.method
            a = step.accelerations(lam) + a0
            q = self.integrate(q, h * v + 0.5 * h * h * a)
            v = v + h * a
            Qs[i], Vs[i], Lam[i] = q, v, lam
            report.after(i, errors, partial)
        return report.finish(partial(steps))


@dataclass
class MechanismResult:
    """Time histories (SI): generalized coordinates ``q`` and velocities ``v``
    (rows = steps), contact reactions ``reactions`` [N] and gaps ``gaps`` [m]
    (Φ) per contact, the penalty μ used at each step (NaN on the LCP route),
    and per step the certificate error of λ against the exact LCP, the
    iterations and the method that produced it."""

    mechanism: ContactSystem
    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    reactions: np.ndarray
    gaps: np.ndarray
    mu: np.ndarray
    h: float
    lookahead: float
    certificate_error: np.ndarray = None
    iterations: np.ndarray = None
    methods: list = field(default_factory=list)

    def coordinate(self, name: str) -> np.ndarray:
        names = self.mechanism.coordinate_names()
        if name not in names:
            raise KeyError(f"{name!r}; coordinates: {names}")
        return self.q[:, names.index(name)]

    def velocity(self, name: str) -> np.ndarray:
        return self.v[:, self.mechanism.coordinate_names().index(name)]

    def plot(self, path, title: str = "") -> str:
        """Positions, velocities and reactions against time in one PNG (atomic write)."""
        return save_figure(motion_figure(self.t, self.q, self.v, self.reactions,
                                         self.mechanism.coordinate_names(),
                                         self.mechanism.contact_names(), title), path)


def motion_figure(t, q, v, reactions, coordinates, contacts, title=""):
    """Positions, velocities and reactions against time (one figure)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, figsize=(8, 8.5), sharex=True)
    t_ms = 1e3 * np.asarray(t)
    for j, nm in enumerate(coordinates):
        axes[0].plot(t_ms, 1e3 * q[:, j], label=nm)
    for j in range(v.shape[1]):     # quaternion joints have fewer velocities than coordinates
        axes[1].plot(t_ms, v[:, j], label=coordinates[j] if v.shape == q.shape else f"v{j}")
    for k, nm in enumerate(contacts):
        axes[2].plot(t_ms, reactions[:, k], label=nm)
    for ax, lab in zip(axes, ("position [mm, mrad]", "velocity [m/s, rad/s]",
                              "contact reaction [N]")):
        ax.set_ylabel(lab)
        ax.grid(True, alpha=0.3)
        if 0 < len(ax.get_lines()) <= 12:
            ax.legend(fontsize=7, ncol=2)
    axes[2].set_xlabel("time [ms]")
    axes[0].set_title(title)
    fig.tight_layout()
    return fig


def lookahead_for(h: float, restitution: float) -> float:
    """The look-ahead Δt [s] that gives restitution e ∈ [0, 1] at step h: 2h/(1 + e)."""
    if not 0.0 <= restitution <= 1.0:
        raise InvalidOptionError(f"restitution must lie in [0, 1]; got {restitution}")
    return 2.0 * h / (1.0 + restitution)


# -- what the contact systems' scene schemas share (qpcontact.scenes) ---------------

def time_section() -> dict:
    from qpcontact.scenes import Field

    return {"h": Field("float", "s", "step size", required=True, positive=True),
            "steps": Field("int", "", "number of steps", required=True, positive=True),
            "restitution": Field("float", "-", "restitution e (sets the lookahead)", default=0.0)}


def solver_section() -> dict:
    from qpcontact.scenes import Field, accuracy_problem, method_problem

    return {"route": Field("str", "", "penalty (Nikolsky et al.'s QP) or lcp (exact)", default="penalty"),
            "method": Field("str", "", "QP method of the penalty route", default="auto",
                            check=lambda name: method_problem(name, ("qp", "lcp"))),
            "accuracy": Field("str", "", "low, default or high", default="high",
                              check=accuracy_problem)}


def contacts_section(normal):
    """The ``[[contacts]]`` tables, in the plane (2-vectors) or in space
    (3-vectors, by the default ``normal``'s length)."""
    from qpcontact.scenes import Field

    origin = [0.0] * len(normal)
    pt = "m (the body's frame, or the world's for the ground)"
    return Field("tables", doc="unilateral contacts Φ = n·(p_b − p_a) − offset ≥ 0", default=[],
                 fields={"name": Field("str", "", "contact name", required=True),
                         "a": Field("str", "", "body a (default: the ground)"),
                         "b": Field("str", "", "body b (default: the ground)"),
                         "normal": Field("floats", "-", "unit normal n (world)",
                                         default=list(normal)),
                         "point_a": Field("floats", pt, "point on a", default=origin),
                         "point_b": Field("floats", pt, "point on b", default=origin),
                         "offset": Field("float", "m", "offset", default=0.0)})


def scene_run(system, time_, solver):
    """The scene's ``run``: the shared contact stepper with the scene's time
    stepping and solver (formulations.stepping.contact_step)."""
    def run(progress: bool = False, resume=None, checkpoint=None, checkpoint_seconds=5.0):
        return system.simulate(time_["h"], time_["steps"],
                               lookahead=lookahead_for(time_["h"], time_["restitution"]),
                               route=solver["route"], method=solver["method"],
                               accuracy=solver["accuracy"], progress=progress, resume=resume,
                               checkpoint=checkpoint, checkpoint_seconds=checkpoint_seconds)
    run.total_steps = time_["steps"]
    return run


def scene_arrays(result) -> dict:
    """What a contact system's results file holds, per step."""
    return {"t": result.t, "q": result.q, "v": result.v, "reactions": result.reactions,
            "gaps": result.gaps, "mu": result.mu, "certificate_error": result.certificate_error,
            "iterations": result.iterations, "method": np.array(result.methods, dtype="S"),
            "coordinates": np.array(result.mechanism.coordinate_names(), dtype="S"),
            "contacts": np.array(result.mechanism.contact_names(), dtype="S")}


def scene_plot(h, out) -> list:
    """Positions, velocities and reactions against time, from the file."""
    names = [[nm.decode() for nm in h[k][()]] for k in ("coordinates", "contacts")]
    fig = motion_figure(h["t"][()], h["q"][()], h["v"][()], h["reactions"][()], *names,
                        title=f"{h.attrs.get('scene_file', '')}")
    return [save_figure(fig, f"{out}/motion.png")]


def scene_summary(result) -> dict:
    return {f"peak_reaction_{c} [N]": float(result.reactions[:, k].max())
            for k, c in enumerate(result.mechanism.contact_names())}
