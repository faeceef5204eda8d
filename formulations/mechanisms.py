r"""Planar mechanisms whose parts may separate, stepped with P2's penalty QP.

SI units: positions m, angles rad, masses kg, inertias kg·m², forces N,
torques N·m, stiffness N/m, compliance m/N, time s.

Model
-----
Rigid bodies in the plane, each hanging from the ground (or another body) by
a planar joint whose free axes, a subset of (x, y, θ), are its generalized
coordinates (a bolt sliding on a guide has only x).  The bodies form a tree in
one :mod:`formulations.multibody` model: G(q) is applied and inverted by its
O(N) momentum-form recursion (never formed, let alone inverted, in a step),
the bias forces come from its Newton-Euler recursion, the contact Jacobians
from its point Jacobians.  Generalized forces Q collect the *effects* the
model names:

- ``gravity``: -m g along y;
- ``springs``: linear springs between body points (or a body point and a ground
  anchor), force k (ℓ - ℓ₀) along the line between the points;
- applied forces (always): constant or f(t, q, v) -> (F_x, F_y, torque);
- ``compliance``: a contact compliance c_k [m/N] per contact, C = diag(c);
  without it the contacts are rigid (P2's regularized C, or the exact LCP).

A unilateral contact between point s_a of body a and point s_b of body b (or a
ground anchor) along a fixed unit normal n is

    Φ = n·(p_b - p_a) - offset >= 0,   p = a body point in the world,
    J = n·(J_b - J_a) (point Jacobians),   D = n·(J̇_b - J̇_a)ν  (so Φ̈ = Jν̇ + D).

Integration step (size h, look-ahead Δt)
----------------------------------------
1. Φ, Φ̇ = J v, D, Q at (t, q, v); B = (2/Δt²)(Φ + Δt Φ̇) (P2);
2. λ from the penalty QP (formulations.penalty; or the exact LCP);
3. a = G⁻¹(J'λ + Q);  q ← q ⊕ (h v + ½h² a);  v ← v + h a.

With this update, an active contact satisfies Φ(t + h) ≈ Φ + hΦ̇ + ½h²Φ̈ = 0 when
Δt = h, to second order.  The look-ahead acts as a restitution: a contact
reached at Φ = 0 with speed Φ̇ leaves with -e Φ̇, e = 2h/Δt - 1, so Δt = h is
elastic (e = 1) and Δt = 2h plastic (e = 0); :func:`lookahead_for` inverts it.
A plastic impact penetrates by about ½ h |Φ̇| before it is pushed back: the
documented tolerance of the scenes' no-penetration test.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from qpcontact.errors import InvalidOptionError, InvalidProblemError
from qpcontact.plotting import save_figure
from qpcontact.solve import solve

from . import multibody as mb
from .penalty import PenaltyStep, exact_lcp, solve_penalty

__all__ = ["Mechanism", "MechanismResult", "lookahead_for", "ramming_scene", "pellet_scene",
           "ramming_impact_step",
           "EFFECTS", "GRAVITY"]

GRAVITY = 9.81
EFFECTS = ("gravity", "springs", "compliance")
_AXES = ("x", "y", "theta")


def lookahead_for(h: float, restitution: float) -> float:
    """The look-ahead Δt [s] that gives restitution e ∈ [0, 1] at step h: 2h/(1 + e)."""
    if not 0.0 <= restitution <= 1.0:
        raise InvalidOptionError(f"restitution must lie in [0, 1]; got {restitution}")
    return 2.0 * h / (1.0 + restitution)


@dataclass
class _Spring:
    a: int
    b: int | None
    stiffness: float
    rest_length: float
    point_a: np.ndarray
    point_b: np.ndarray   # on body b, or the ground anchor


@dataclass
class _Contact:
    name: str
    a: int | None
    b: int | None
    normal: np.ndarray
    point_a: np.ndarray
    point_b: np.ndarray
    offset: float
    compliance: float


def _p3(xy):
    return np.array([xy[0], xy[1], 0.0])


class Mechanism:
    """A planar mechanism with unilateral contacts (SI units; see the module docstring).

    ``effects`` names what is assembled: "gravity", "springs", "compliance".
    Data for an effect not named raises InvalidProblemError.  The bodies form
    a tree in a :class:`formulations.multibody.Model` (``self.model``), whose
    recursions give G(q) (as an O(N) factorized operator), the bias forces
    and the contact Jacobians.
    """

    def __init__(self, effects=("springs",), gravity: float = GRAVITY):
        if isinstance(effects, str):
            effects = (effects,)
        effects = frozenset(effects)
        unknown = sorted(effects - set(EFFECTS))
        if unknown:
            raise InvalidProblemError(f"unknown effect(s) {unknown}; mechanisms know {list(EFFECTS)}")
        self.effects = effects
        self.gravity = gravity if "gravity" in effects else 0.0
        self.model = mb.Model(gravity=(0.0, -self.gravity, 0.0))
        self._data = mb.Data(self.model)
        self._q0, self._v0 = [], []
        self.springs: list[_Spring] = []
        self.forces: list = []
        self.contacts: list[_Contact] = []

    @property
    def bodies(self) -> list[str]:
        return self.model.names[1:]

    # -- building -------------------------------------------------------------
    def add_body(self, name: str, mass: float, inertia: float = 0.0, dofs=("x",),
                 position=(0.0, 0.0, 0.0), velocity=(0.0, 0.0, 0.0), parent=None) -> str:
        """A rigid body [kg, kg·m² about its centre] with generalized
        coordinates ``dofs`` ⊂ {x, y, theta} (a planar joint; the others stay
        at ``position``) at ``position`` (x, y [m], θ [rad], relative to
        ``parent``'s frame, default the ground) moving with ``velocity``
        (the rates of the ``dofs``, in the order x, y, theta)."""
        pose = np.array(position, float).reshape(3)
        vel = np.array(velocity, float).reshape(3)
        joint = mb.Planar(free=dofs, fixed=pose)      # validates the dofs
        if not mass > 0 or (joint.mask[2] and not inertia > 0):
            raise InvalidProblemError(f"body {name!r}: mass (and inertia if it rotates) must be > 0")
        # planar motion only meets I_zz; the same value on the other axes never enters
        self.model.add_body(name, parent=0 if parent is None else parent, joint=joint, mass=mass,
                            inertia=np.diag([inertia, inertia, inertia]))
        on = joint.mask.astype(bool)
        self._q0 += list(pose[on])
        self._v0 += list(vel[on])
        return name

    def _body(self, name):
        return None if name is None else self.model.body_id(name)

    def add_spring(self, a: str, b: str | None, stiffness: float, rest_length: float,
                   point_a=(0.0, 0.0), point_b=(0.0, 0.0)) -> None:
        """Linear spring [N/m] between point_a of body a and point_b of body b,
        or the ground anchor point_b (world coordinates) when b is None."""
        if "springs" not in self.effects:
            raise InvalidProblemError("add_spring needs the effect 'springs'")
        self.springs.append(_Spring(self._body(a), self._body(b), float(stiffness),
                                    float(rest_length), _p3(point_a), _p3(point_b)))

    def add_force(self, body: str, fx: float = 0.0, fy: float = 0.0, torque: float = 0.0,
                  fn=None) -> None:
        """Applied force [N] (world axes, at the body origin) and torque [N·m]
        on a body: constant, or ``fn(t, body_pose, body_velocity) -> (fx, fy,
        torque)`` with pose (x, y, θ) and velocity (ẋ, ẏ, θ̇) in the world."""
        self.forces.append((self._body(body), np.array([fx, fy, torque], float), fn))

    def add_contact(self, name: str, a: str | None, b: str | None, normal=(1.0, 0.0),
                    point_a=(0.0, 0.0), point_b=(0.0, 0.0), offset: float = 0.0,
                    compliance: float | None = None) -> None:
        """Unilateral contact Φ = n·(p_b - p_a) - offset >= 0 [m]; a or b may be
        None (ground, the point is then a world anchor).  ``compliance`` [m/N]
        needs the effect 'compliance'."""
        if compliance is not None and "compliance" not in self.effects:
            raise InvalidProblemError("a contact compliance needs the effect 'compliance'")
        if compliance is None and "compliance" in self.effects:
            raise InvalidProblemError(f"contact {name!r}: effect 'compliance' needs compliance= (m/N)")
        n = np.array(normal, float)
        if n.shape != (2,) or not np.isclose(np.linalg.norm(n), 1.0):
            raise InvalidProblemError(f"contact {name!r}: normal must be a unit 2-vector")
        self.contacts.append(_Contact(name, self._body(a), self._body(b), _p3(n),
                                      _p3(point_a), _p3(point_b),
                                      float(offset), float(compliance or 0.0)))

    # -- assembly -------------------------------------------------------------
    def initial_state(self):
        return np.array(self._q0, float), np.array(self._v0, float)

    def inertia(self, q=None) -> np.ndarray:
        """G(q) as a dense matrix (CRBA); the stepper uses :meth:`mass_operator`."""
        return mb.mass_matrix(self.model, self._data, self.initial_state()[0] if q is None else q)

    def mass_operator(self, q) -> mb.MassOperator:
        """G(q) factorized by the O(N) momentum-form recursion (G⁻¹ never formed)."""
        return mb.MassOperator(self.model, q)

    def _world_point(self, i, s):
        """World position of point s (body frame) of body i, or the anchor s for the ground."""
        return s if i is None else mb.point_position(self.model, self._data, i, s)

    def _body_forces(self, t):
        """Springs and applied forces as spatial forces on the bodies (body
        frames, moments about their origins), after forward kinematics."""
        d = self._data
        f = np.zeros((self.model.nbodies + 1, 6))

        def push(i, x, F, torque=0.0):
            if i is None:
                return
            Rt = d.Ra[i].T
            f[i, :3] += Rt @ F
            f[i, 3:] += Rt @ (np.cross(x - d.ra[i], F) + np.array([0.0, 0.0, torque]))

        for sp_ in self.springs:
            xa, xb = self._world_point(sp_.a, sp_.point_a), self._world_point(sp_.b, sp_.point_b)
            dvec = xb - xa
            ell = np.linalg.norm(dvec)
            if ell == 0:
                continue
            F = sp_.stiffness * (ell - sp_.rest_length) * dvec / ell   # tension pulls a toward b
            push(sp_.a, xa, F)
            push(sp_.b, xb, -F)
        for i, f3, fn in self.forces:
            if fn is not None:
                R, r, V = d.Ra[i], d.ra[i], d.V[i]
                pose = np.array([r[0], r[1], np.arctan2(R[1, 0], R[0, 0])])
                vw = R @ V[:3]
                f3 = np.asarray(fn(t, pose, np.array([vw[0], vw[1], (R @ V[3:])[2]])), float)
            push(i, d.ra[i], np.array([f3[0], f3[1], 0.0]), f3[2])
        return f

    def generalized_forces(self, t, q, v) -> np.ndarray:
        """Q(t, q, ν) = applied generalized forces - bias (gravity, Coriolis) [N, N·m]."""
        mb.forward_kinematics(self.model, self._data, q, v, t)
        return -mb.nonlinear_effects(self.model, self._data, q, v, self._body_forces(t), t)

    def constraints(self, q, v):
        """Φ [m], J (ν x n), D = J̇ν [m/s²] at (q, v)."""
        mb.forward_kinematics(self.model, self._data, q, v)
        nu, n = len(self.contacts), self.model.nv
        Phi, J, D = np.zeros(nu), np.zeros((nu, n)), np.zeros(nu)
        for k, c in enumerate(self.contacts):
            xa, xb = self._world_point(c.a, c.point_a), self._world_point(c.b, c.point_b)
            Phi[k] = c.normal @ (xb - xa) - c.offset
            for sign, i, s in ((1.0, c.b, c.point_b), (-1.0, c.a, c.point_a)):
                if i is not None:
                    Jp, Jd = mb.point_jacobian(self.model, self._data, i, s)
                    J[k] += sign * (c.normal @ Jp)
                    D[k] += sign * (c.normal @ (Jd @ v))
        return Phi, J, D

    def step_data(self, t, q, v):
        """What one contact step needs at (t, q, ν): (G as an O(N) factorized
        operator, Q, J, D, Φ) — the penalty QP and the exact LCP of
        formulations.penalty are built from these, without forming G⁻¹."""
        Phi, J, D = self.constraints(q, v)
        return self.mass_operator(q), self.generalized_forces(t, q, v), J, D, Phi

    def compliance(self):
        if "compliance" not in self.effects:
            return None
        return np.diag([c.compliance for c in self.contacts])

    # -- simulation -----------------------------------------------------------
    def simulate(self, h: float, steps: int, *, lookahead: float | None = None,
                 route: str = "penalty", mu="auto", method: str = "auto", accuracy="high",
                 **options) -> "MechanismResult":
        """Integrate ``steps`` steps of size ``h`` [s] (module docstring).

        ``route="penalty"`` solves P2's penalty QP with ``method`` (μ chosen
        automatically at the first step that needs it, re-chosen whenever a
        step's λ fails its certificate against the exact LCP); ``route="lcp"``
        solves the exact LCP (pivoting).  Every step's λ is certified against
        the exact LCP; a step that cannot be certified raises SolverFailedError.
        """
        from qpcontact.errors import SolverFailedError

        if route not in ("penalty", "lcp"):
            raise InvalidOptionError(f"route must be 'penalty' or 'lcp', not {route!r}")
        if not h > 0 or int(steps) < 1:
            raise InvalidOptionError("h must be > 0 and steps >= 1")
        dt = h if lookahead is None else float(lookahead)
        q, v = self.initial_state()
        C = self.compliance()
        nu = len(self.contacts)
        T = np.arange(int(steps) + 1) * h
        Qs = np.zeros((T.size, q.size))
        Vs = np.zeros((T.size, q.size))
        Lam = np.zeros((T.size, nu))
        Phis = np.zeros((T.size, nu))
        Qs[0], Vs[0] = q, v
        mus = np.full(T.size, np.nan)
        mu_now = mu
        for i in range(1, T.size):
            t = T[i - 1]
            Gop, Q, J, D, Phi = self.step_data(t, q, v)
            Phis[i - 1] = Phi
            B = 2.0 / dt ** 2 * (Phi + dt * (J @ v))
            step = PenaltyStep(Gop, Q, J, B, D, C)
            if route == "lcp":
                sol = solve(exact_lcp(step), method="lemke" if method == "auto" else method,
                            accuracy=accuracy)
                if not sol.ok:
                    raise SolverFailedError(f"step {i}: exact LCP not solved ({sol.message})")
                lam = sol.z
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
            a = step.accelerations(lam)
            q = mb.integrate(self.model, q, h * v + 0.5 * h * h * a)
            v = v + h * a
            Qs[i], Vs[i], Lam[i] = q, v, lam
        Phis[-1] = self.constraints(q, v)[0]
        return MechanismResult(self, T, Qs, Vs, Lam, Phis, mus, h, dt)

    def coordinate_names(self) -> list[str]:
        names = []
        for name, j in zip(self.model.names[1:], self.model.joints[1:]):
            names += [f"{name}.{a}" for a, on in zip(_AXES, j.mask) if on]
        return names


@dataclass
class MechanismResult:
    """Time histories (SI): generalized coordinates ``q`` and velocities ``v``
    (rows = steps), contact reactions ``reactions`` [N] and gaps ``gaps`` [m]
    (Φ) per contact, and the penalty μ used at each step (NaN on the LCP route)."""

    mechanism: Mechanism
    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    reactions: np.ndarray
    gaps: np.ndarray
    mu: np.ndarray
    h: float
    lookahead: float

    def coordinate(self, name: str) -> np.ndarray:
        names = self.mechanism.coordinate_names()
        if name not in names:
            raise KeyError(f"{name!r}; coordinates: {names}")
        return self.q[:, names.index(name)]

    def velocity(self, name: str) -> np.ndarray:
        return self.v[:, self.mechanism.coordinate_names().index(name)]

    def plot(self, path, title: str = "") -> str:
        """Positions, velocities and reactions against time in one PNG (atomic write)."""
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        names = self.mechanism.coordinate_names()
        fig, axes = plt.subplots(3, 1, figsize=(8, 8.5), sharex=True)
        t_ms = 1e3 * self.t
        for j, nm in enumerate(names):
            axes[0].plot(t_ms, 1e3 * self.q[:, j], label=nm)
            axes[1].plot(t_ms, self.v[:, j], label=nm)
        for k, c in enumerate(self.mechanism.contacts):
            axes[2].plot(t_ms, self.reactions[:, k], label=c.name)
        axes[0].set_ylabel("position [mm]")
        axes[1].set_ylabel("velocity [m/s]")
        axes[2].set_ylabel("contact reaction [N]")
        axes[2].set_xlabel("time [ms]")
        for ax in axes:
            ax.grid(True, alpha=0.3)
            if len(ax.get_lines()) <= 12:
                ax.legend(fontsize=7, ncol=2)
        axes[0].set_title(title)
        fig.tight_layout()
        return save_figure(fig, path)


def ramming_scene(effects=("springs",), restitution: float = 0.3, compliance: float = 1e-7):
    """A spring-driven bolt rams a cartridge along a guide into the chamber stop.

    Bolt 0.40 kg, cartridge 0.025 kg (lengths 60 mm and 70 mm, x = their
    centres), return spring 800 N/m compressed 120 mm; the cartridge lies 10 mm
    ahead of the bolt face and 80 mm from the chamber stop.  Contacts:
    "bolt/cartridge" and "cartridge/chamber".  Returns (mechanism, h, steps,
    lookahead): 1 ms... of motion at h = 20 µs.
    """
    effects = tuple(effects)
    m = Mechanism(effects=effects)
    m.add_body("bolt", 0.40, dofs=("x",), position=(0.0, 0.0, 0.0))
    m.add_body("cartridge", 0.025, dofs=("x",), position=(0.030 + 0.010 + 0.035, 0.0, 0.0))
    # return spring anchored 120 mm behind the bolt, rest length 240 mm: compressed 120 mm
    m.add_spring("bolt", None, 800.0, rest_length=0.240, point_b=(-0.120, 0.0))
    c = compliance if "compliance" in effects else None
    m.add_contact("bolt/cartridge", "bolt", "cartridge", normal=(1.0, 0.0), offset=0.030 + 0.035,
                  compliance=c)
    stop = 0.075 + 0.035 + 0.080
    m.add_contact("cartridge/chamber", "cartridge", None, normal=(1.0, 0.0),
                  point_b=(stop, 0.0), offset=0.035, compliance=c)
    h = 20e-6
    return m, h, 2500, lookahead_for(h, restitution)


def pellet_scene(n_pellets: int = 8, effects=(), restitution: float = 0.5,
                 pressure_force: float = 400.0, pulse: float = 2e-3):
    """N lead shot pellets (Ø 3 mm, 0.16 g) in a tube pushed by a piston
    (wad, 2 g) driven by a gas force pulse of ``pressure_force`` [N] lasting
    ``pulse`` [s]; pellets start 0.5 mm apart.  Contacts: piston/pellet 0 and
    pellet k/pellet k+1.  Returns (mechanism, h, steps, lookahead)."""
    m = Mechanism(effects=tuple(effects) or ("springs",))
    r = 1.5e-3
    m.add_body("piston", 2e-3, dofs=("x",), position=(0.0, 0.0, 0.0))
    m.add_force("piston", fn=lambda t, pose, vel: (pressure_force if t < pulse else 0.0, 0.0, 0.0))
    x = 0.005 + r + 0.5e-3
    prev, prev_half = "piston", 0.005
    for k in range(n_pellets):
        name = f"pellet {k}"
        m.add_body(name, 0.16e-3, dofs=("x",), position=(x, 0.0, 0.0))
        m.add_contact(f"{prev}/{name}", prev, name, normal=(1.0, 0.0), offset=prev_half + r)
        prev, prev_half = name, r
        x += 2 * r + 0.5e-3
    h = 5e-6
    return m, h, 800, lookahead_for(h, restitution)


def ramming_impact_step():
    """The ramming scene's step at which the bolt first touches the cartridge,
    as a PenaltyStep (rigid contacts): a small real step for demos and studies."""
    mech, h, steps, dt = ramming_scene()
    res = mech.simulate(h, 600, lookahead=dt, route="lcp")
    i = int(np.flatnonzero(res.reactions[:, 0] > 0)[0])
    q, v = res.q[i - 1], res.v[i - 1]
    Phi, J, D = mech.constraints(q, v)
    B = 2.0 / dt ** 2 * (Phi + dt * (J @ v))
    return PenaltyStep(mech.inertia(q), mech.generalized_forces(res.t[i - 1], q, v), J, B, D)


# -- scene files (qpcontact.scenes): a user-defined planar mechanism ----------------

def _scene_build(scene):
    """(Mechanism, run) from a checked scene: bodies, springs (only with the
    effect "springs"), constant forces, contacts (compliant only with
    "compliance"), gravity only with "gravity"."""
    d, eff = scene.data, scene.effect_params
    if d["springs"] and "springs" not in eff:
        scene.fail("springs are given but 'springs' is not among the effects; add it to "
                   "effects or remove the [[springs]] tables", ("springs",), None, 0)
    m = Mechanism(effects=scene.effects,
                  gravity=eff["gravity"]["g"] if "gravity" in eff else GRAVITY)
    for b in d["bodies"]:
        m.add_body(b["name"], b["mass"], b["inertia"], dofs=tuple(b["dofs"]),
                   position=tuple(b["position"]), velocity=tuple(b["velocity"]),
                   parent=b["parent"])
    for sp_ in d["springs"]:
        m.add_spring(sp_["a"], sp_["b"], sp_["stiffness"], sp_["rest_length"],
                     point_a=tuple(sp_["point_a"]), point_b=tuple(sp_["point_b"]))
    for f in d["forces"]:
        m.add_force(f["body"], f["fx"], f["fy"], f["torque"])
    compliance = eff["compliance"]["compliance"] if "compliance" in eff else None
    for c in d["contacts"]:
        m.add_contact(c["name"], c["a"], c["b"], normal=tuple(c["normal"]),
                      point_a=tuple(c["point_a"]), point_b=tuple(c["point_b"]),
                      offset=c["offset"], compliance=compliance)
    t, solver = d["time"], d["solver"]

    def run(progress: bool = False, resume=None, checkpoint=None, checkpoint_seconds=5.0):
        if resume is not None:
            scene.fail("--resume is not supported for mechanism scenes yet (the drum's is); "
                       "run it afresh", ("time",))
        result = m.simulate(t["h"], t["steps"], lookahead=lookahead_for(t["h"], t["restitution"]),
                            route=solver["route"], method=solver["method"],
                            accuracy=solver["accuracy"])
        if checkpoint is not None:
            checkpoint(result)
        return result
    run.total_steps = t["steps"]
    return m, run


def _scene_arrays(result) -> dict:
    return {"t": result.t, "q": result.q, "v": result.v, "reactions": result.reactions,
            "gaps": result.gaps, "mu": result.mu,
            "coordinates": np.array(result.mechanism.coordinate_names(), dtype="S"),
            "contacts": np.array([c.name for c in result.mechanism.contacts], dtype="S")}


def _scene_plot(h, out) -> list:
    """Positions, velocities and reactions against time, from the file."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t_ms = 1e3 * h["t"][()]
    fig, axes = plt.subplots(3, 1, figsize=(8, 8.5), sharex=True)
    for j, nm in enumerate(h["coordinates"][()]):
        axes[0].plot(t_ms, 1e3 * h["q"][:, j], label=nm.decode())
        axes[1].plot(t_ms, h["v"][:, j], label=nm.decode())
    for k, nm in enumerate(h["contacts"][()]):
        axes[2].plot(t_ms, h["reactions"][:, k], label=nm.decode())
    for ax, lab in zip(axes, ("position [mm]", "velocity [m/s]", "contact reaction [N]")):
        ax.set_ylabel(lab)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    axes[2].set_xlabel("time [ms]")
    return [save_figure(fig, f"{out}/motion.png")]


def _scene_summary(result) -> dict:
    return {f"peak_reaction_{c.name} [N]": float(result.reactions[:, k].max())
            for k, c in enumerate(result.mechanism.contacts)}


def _scene_schema():
    from qpcontact.scenes import Field, SceneSchema

    xy = "m (x, y in the body's frame, or the world's for the ground)"
    return SceneSchema(
        formulation="mechanism",
        doc="a planar mechanism from bodies, springs, forces and unilateral contacts (P2)",
        sections={
            "bodies": Field("tables", doc="one [[bodies]] table per body", required=True, fields={
                "name": Field("str", "", "body name", required=True),
                "mass": Field("float", "kg", "mass", required=True, positive=True),
                "inertia": Field("float", "kg·m²", "moment of inertia about the centre",
                                 default=0.0),
                "dofs": Field("strs", "", "generalized coordinates among x, y, theta",
                              default=["x"]),
                "position": Field("floats", "m, m, rad", "x, y, θ (relative to parent)",
                                  default=[0.0, 0.0, 0.0]),
                "velocity": Field("floats", "m/s, rad/s", "rates of the dofs",
                                  default=[0.0, 0.0, 0.0]),
                "parent": Field("str", "", "parent body (default: the ground)")}),
            "springs": Field("tables", doc="linear springs (effect 'springs')", default=[],
                             fields={
                "a": Field("str", "", "body a", required=True),
                "b": Field("str", "", "body b (default: a ground anchor at point_b)"),
                "stiffness": Field("float", "N/m", "stiffness", required=True, positive=True),
                "rest_length": Field("float", "m", "rest length", required=True),
                "point_a": Field("floats", xy, "attachment on a", default=[0.0, 0.0]),
                "point_b": Field("floats", xy, "attachment on b", default=[0.0, 0.0])}),
            "forces": Field("tables", doc="constant applied forces", default=[], fields={
                "body": Field("str", "", "body", required=True),
                "fx": Field("float", "N", "force x (world)", default=0.0),
                "fy": Field("float", "N", "force y (world)", default=0.0),
                "torque": Field("float", "N·m", "torque", default=0.0)}),
            "contacts": Field("tables", doc="unilateral contacts Φ = n·(p_b − p_a) − offset ≥ 0",
                              default=[], fields={
                "name": Field("str", "", "contact name", required=True),
                "a": Field("str", "", "body a (default: ground)"),
                "b": Field("str", "", "body b (default: ground)"),
                "normal": Field("floats", "-", "unit normal n (world)", default=[1.0, 0.0]),
                "point_a": Field("floats", xy, "point on a", default=[0.0, 0.0]),
                "point_b": Field("floats", xy, "point on b", default=[0.0, 0.0]),
                "offset": Field("float", "m", "offset", default=0.0)}),
            "time": {
                "h": Field("float", "s", "step size", required=True, positive=True),
                "steps": Field("int", "", "number of steps", required=True, positive=True),
                "restitution": Field("float", "-", "restitution e (sets the lookahead)",
                                     default=0.0),
            },
            "solver": {
                "route": Field("str", "", "penalty (P2's QP) or lcp (exact)", default="penalty"),
                "method": Field("str", "", "QP method of the penalty route", default="auto"),
                "accuracy": Field("str", "", "low, default or high", default="high"),
            },
        },
        effects={
            "gravity": {"g": Field("float", "m/s²", "gravitational acceleration (−y)",
                                   default=GRAVITY, positive=True)},
            "springs": {},
            "compliance": {"compliance": Field("float", "m/N", "contact compliance of every "
                                               "contact", required=True, positive=True)},
        },
        build=_scene_build, arrays=_scene_arrays, plot=_scene_plot, summary=_scene_summary)


SCENE = _scene_schema()
