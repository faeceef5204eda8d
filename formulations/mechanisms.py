r"""Planar mechanisms whose parts may separate, stepped with P2's penalty QP.

SI units: positions m, angles rad, masses kg, inertias kg·m², forces N,
torques N·m, stiffness N/m, compliance m/N, time s.

Model
-----
Rigid bodies in the plane, each with a subset of the coordinates (x, y, θ) as
generalized coordinates (a bolt sliding on a guide has only x).  The inertia
matrix G = diag(m, m, I) restricted to those coordinates is constant.
Generalized forces Q collect the *effects* the model names:

- ``gravity``: -m g along y;
- ``springs``: linear springs between body points (or a body point and a ground
  anchor), force k (ℓ - ℓ₀) along the line between the points;
- applied forces (always): constant or f(t, q, v) -> (F_x, F_y, torque);
- ``compliance``: a contact compliance c_k [m/N] per contact, C = diag(c);
  without it the contacts are rigid (P2's regularized C, or the exact LCP).

A unilateral contact between point s_a of body a and point s_b of body b (or a
ground anchor) along a fixed unit normal n is

    Φ = n·(p_b - p_a) - offset >= 0,   p = r + R(θ) s,
    J = ∂Φ/∂q (n, and n·R'(θ)s for rotations),   D = q̇'∇²Φ q̇ = n·(-R_b s_b θ̇_b² + R_a s_a θ̇_a²).

Integration step (size h, look-ahead Δt)
----------------------------------------
1. Φ, Φ̇ = J v, D, Q at (t, q, v); B = (2/Δt²)(Φ + Δt Φ̇) (P2);
2. λ from the penalty QP (formulations.penalty; or the exact LCP);
3. a = G⁻¹(J'λ + Q);  q ← q + h v + ½h² a;  v ← v + h a.

With this update, an active contact satisfies Φ(t + h) ≈ Φ + hΦ̇ + ½h²Φ̈ = 0 when
Δt = h, to second order.  The look-ahead acts as a restitution: a contact
reached at Φ = 0 with speed Φ̇ leaves with -e Φ̇, e = 2h/Δt - 1, so Δt = h is
elastic (e = 1) and Δt = 2h plastic (e = 0); :func:`lookahead_for` inverts it.
A plastic impact penetrates by about ½ h |Φ̇| before it is pushed back: the
documented tolerance of the scenes' no-penetration test.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from qpcontact.errors import InvalidOptionError, InvalidProblemError
from qpcontact.plotting import save_figure
from qpcontact.solve import solve

from .penalty import PenaltyStep, exact_lcp, solve_penalty

__all__ = ["Mechanism", "MechanismResult", "lookahead_for", "ramming_scene", "pellet_scene",
           "ramming_impact_step",
           "EFFECTS", "GRAVITY"]

GRAVITY = 9.81
EFFECTS = ("gravity", "springs", "compliance")
_AXES = {"x": 0, "y": 1, "theta": 2}


def lookahead_for(h: float, restitution: float) -> float:
    """The look-ahead Δt [s] that gives restitution e ∈ [0, 1] at step h: 2h/(1 + e)."""
    if not 0.0 <= restitution <= 1.0:
        raise InvalidOptionError(f"restitution must lie in [0, 1]; got {restitution}")
    return 2.0 * h / (1.0 + restitution)


def _rot(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


@dataclass
class _Body:
    name: str
    mass: float
    inertia: float
    dofs: tuple
    pose: np.ndarray      # x, y, theta (all three, fixed ones stay)
    velocity: np.ndarray  # vx, vy, omega
    index: np.ndarray = field(default=None)  # generalized-coordinate index per axis, -1 if fixed


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


class Mechanism:
    """A planar mechanism with unilateral contacts (SI units; see the module docstring).

    ``effects`` names what is assembled: "gravity", "springs", "compliance".
    Data for an effect not named raises InvalidProblemError.
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
        self.bodies: list[_Body] = []
        self.springs: list[_Spring] = []
        self.forces: list = []
        self.contacts: list[_Contact] = []
        self._names = {}

    # -- building -------------------------------------------------------------
    def add_body(self, name: str, mass: float, inertia: float = 0.0, dofs=("x",),
                 position=(0.0, 0.0, 0.0), velocity=(0.0, 0.0, 0.0)) -> str:
        """A rigid body [kg, kg·m²] with generalized coordinates ``dofs`` ⊂ {x, y, theta}
        at ``position`` (x, y [m], θ [rad]) moving with ``velocity``."""
        if name in self._names:
            raise InvalidProblemError(f"a body named {name!r} exists already")
        dofs = tuple(dofs)
        bad = [d for d in dofs if d not in _AXES]
        if bad or len(set(dofs)) != len(dofs):
            raise InvalidProblemError(f"dofs must be distinct names among {list(_AXES)}; got {dofs}")
        if not mass > 0 or ("theta" in dofs and not inertia > 0):
            raise InvalidProblemError(f"body {name!r}: mass (and inertia if it rotates) must be > 0")
        pose = np.array(position, float).reshape(3)
        vel = np.array(velocity, float).reshape(3)
        self._names[name] = len(self.bodies)
        self.bodies.append(_Body(name, float(mass), float(inertia), dofs, pose, vel))
        return name

    def _body(self, name):
        if name is None:
            return None
        if name not in self._names:
            raise InvalidProblemError(f"no body named {name!r}; bodies: {list(self._names)}")
        return self._names[name]

    def add_spring(self, a: str, b: str | None, stiffness: float, rest_length: float,
                   point_a=(0.0, 0.0), point_b=(0.0, 0.0)) -> None:
        """Linear spring [N/m] between point_a of body a and point_b of body b,
        or the ground anchor point_b (world coordinates) when b is None."""
        if "springs" not in self.effects:
            raise InvalidProblemError("add_spring needs the effect 'springs'")
        self.springs.append(_Spring(self._body(a), self._body(b), float(stiffness),
                                    float(rest_length), np.array(point_a, float),
                                    np.array(point_b, float)))

    def add_force(self, body: str, fx: float = 0.0, fy: float = 0.0, torque: float = 0.0,
                  fn=None) -> None:
        """Applied force [N] and torque [N·m] on a body: constant, or
        ``fn(t, body_pose, body_velocity) -> (fx, fy, torque)``."""
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
        self.contacts.append(_Contact(name, self._body(a), self._body(b), n,
                                      np.array(point_a, float), np.array(point_b, float),
                                      float(offset), float(compliance or 0.0)))

    # -- assembly -------------------------------------------------------------
    def _index(self):
        k = 0
        for bd in self.bodies:
            bd.index = -np.ones(3, int)
            for d in bd.dofs:
                bd.index[_AXES[d]] = k
                k += 1
        return k

    def initial_state(self):
        n = self._index()
        q, v = np.zeros(n), np.zeros(n)
        for bd in self.bodies:
            for ax in range(3):
                if bd.index[ax] >= 0:
                    q[bd.index[ax]] = bd.pose[ax]
                    v[bd.index[ax]] = bd.velocity[ax]
        return q, v

    def inertia(self) -> np.ndarray:
        n = self._index()
        G = np.zeros(n)
        for bd in self.bodies:
            for ax in range(3):
                if bd.index[ax] >= 0:
                    G[bd.index[ax]] = bd.inertia if ax == 2 else bd.mass
        return np.diag(G)

    def _pose(self, bd, q, v):
        pose, vel = bd.pose.copy(), bd.velocity.copy()
        for ax in range(3):
            if bd.index[ax] >= 0:
                pose[ax] = q[bd.index[ax]]
                vel[ax] = v[bd.index[ax]]
            else:
                vel[ax] = 0.0
        return pose, vel

    def _point(self, i, s, q, v):
        """World position, velocity and the 3 partial derivatives of a body point."""
        if i is None:
            return s, np.zeros(2), None, None, 0.0
        bd = self.bodies[i]
        (x, y, th), (vx, vy, om) = self._pose(bd, q, v)
        R = _rot(th)
        Rs = R @ s
        dRs = np.array([-Rs[1], Rs[0]])  # d(R s)/dθ
        p = np.array([x, y]) + Rs
        pv = np.array([vx, vy]) + om * dRs
        return p, pv, dRs, Rs, om

    def _add(self, vec, bd_index, f3):
        bd = self.bodies[bd_index]
        for ax in range(3):
            if bd.index[ax] >= 0:
                vec[bd.index[ax]] += f3[ax]

    def generalized_forces(self, t, q, v) -> np.ndarray:
        Q = np.zeros(q.size)
        for i, bd in enumerate(self.bodies):
            if self.gravity:
                self._add(Q, i, np.array([0.0, -bd.mass * self.gravity, 0.0]))
        for sp_ in self.springs:
            pa, _, dRa, _, _ = self._point(sp_.a, sp_.point_a, q, v)
            pb, _, dRb, _, _ = self._point(sp_.b, sp_.point_b, q, v)
            d = pb - pa
            ell = np.linalg.norm(d)
            if ell == 0:
                continue
            u = d / ell
            f = sp_.stiffness * (ell - sp_.rest_length)   # tension > 0 pulls a toward b
            self._add(Q, sp_.a, np.array([f * u[0], f * u[1], f * (u @ dRa)]))
            if sp_.b is not None:
                self._add(Q, sp_.b, np.array([-f * u[0], -f * u[1], -f * (u @ dRb)]))
        for i, f3, fn in self.forces:
            if fn is not None:
                pose, vel = self._pose(self.bodies[i], q, v)
                f3 = np.asarray(fn(t, pose, vel), float)
            self._add(Q, i, f3)
        return Q

    def constraints(self, q, v):
        """Φ [m], J (ν x n), D [m/s²] at (q, v)."""
        nu, n = len(self.contacts), q.size
        Phi, J, D = np.zeros(nu), np.zeros((nu, n)), np.zeros(nu)
        for k, c in enumerate(self.contacts):
            pa, _, dRa, Rsa, oma = self._point(c.a, c.point_a, q, v)
            pb, _, dRb, Rsb, omb = self._point(c.b, c.point_b, q, v)
            Phi[k] = c.normal @ (pb - pa) - c.offset
            row = np.zeros(n)
            if c.b is not None:
                self._add(row, c.b, np.array([c.normal[0], c.normal[1], c.normal @ dRb]))
                D[k] += c.normal @ (-Rsb) * omb ** 2
            if c.a is not None:
                self._add(row, c.a, -np.array([c.normal[0], c.normal[1], c.normal @ dRa]))
                D[k] -= c.normal @ (-Rsa) * oma ** 2
            J[k] = row
        return Phi, J, D

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
        G = self.inertia()
        C = self.compliance()
        nu = len(self.contacts)
        T = np.arange(int(steps) + 1) * h
        Qs = np.zeros((T.size, q.size))
        Vs = np.zeros((T.size, q.size))
        Lam = np.zeros((T.size, nu))
        Phis = np.zeros((T.size, nu))
        Qs[0], Vs[0] = q, v
        Phis[0] = self.constraints(q, v)[0]
        mus = np.full(T.size, np.nan)
        mu_now = mu
        for i in range(1, T.size):
            t = T[i - 1]
            Phi, J, D = self.constraints(q, v)
            B = 2.0 / dt ** 2 * (Phi + dt * (J @ v))
            step = PenaltyStep(G, self.generalized_forces(t, q, v), J, B, D, C)
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
            q = q + h * v + 0.5 * h * h * a
            v = v + h * a
            Qs[i], Vs[i], Lam[i] = q, v, lam
            Phis[i] = self.constraints(q, v)[0]
        return MechanismResult(self, T, Qs, Vs, Lam, Phis, mus, h, dt)

    def coordinate_names(self) -> list[str]:
        self._index()
        names = []
        for bd in self.bodies:
            names += [f"{bd.name}.{d}" for d in bd.dofs]
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
    return PenaltyStep(mech.inertia(), mech.generalized_forces(res.t[i - 1], q, v), J, B, D)
