r"""Planar mechanisms whose parts may separate, stepped with the penalty QP
of Nikolsky, Kopylov, Romanenko & Kudryashov (2012).

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
- ``damping``: linear viscous dampers between body points (or a point and a
  ground anchor), force c ℓ̇ [N] along the line (c in N·s/m), evaluated at the
  step's start like every force (explicit: stable while h c / m stays small);
- applied forces (always): constant or f(t, q, v) -> (F_x, F_y, torque);
- ``compliance``: a contact compliance c_k [m/N] per contact, C = diag(c);
  without it the contacts are rigid (the penalty paper's regularized C, or the
  exact LCP).

A unilateral contact between point s_a of body a and point s_b of body b (or a
ground anchor) along a fixed unit normal n is ::

    Φ = n·(p_b - p_a) - offset >= 0,   p = a body point in the world,
    J = n·(J_b - J_a) (point Jacobians),   D = n·(J̇_b - J̇_a)ν  (so Φ̈ = Jν̇ + D).

Integration step (size h, look-ahead Δt)
----------------------------------------
1. Φ, Φ̇ = J v, D, Q at (t, q, v); B = (2/Δt²)(Φ + Δt Φ̇) (the penalty paper);
2. λ from the penalty QP (formulations.stepping.penalty_step; or the exact LCP);
3. a = G⁻¹(J'λ + Q);  q ← q ⊕ (h v + ½h² a);  v ← v + h a.

With this update, an active contact satisfies Φ(t + h) ≈ Φ + hΦ̇ + ½h²Φ̈ = 0 when
Δt = h, to second order.  The look-ahead acts as a restitution: a contact
reached at Φ = 0 with speed Φ̇ leaves with -e Φ̇, e = 2h/Δt - 1, so Δt = h is
elastic (e = 1) and Δt = 2h plastic (e = 0); :func:`lookahead_for` inverts it.
A plastic impact penetrates by about ``½ h |Φ̇|`` before it is pushed back: the
documented tolerance of the scenes' no-penetration test.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from .. import multibody as mb
from ..multibody.contacts import Contact, ModelContacts, world_point
from ..stepping.penalty_step import PenaltyStep
from ..stepping.contact_step import (MechanismResult, lookahead_for, scene_arrays, scene_plot,
                                     scene_run, scene_summary, solver_section, time_section,
                                     contacts_section)

__all__ = ["Mechanism", "MechanismResult", "lookahead_for", "ramming_scene", "pellet_scene",
           "ramming_impact_step",
           "EFFECTS", "GRAVITY"]

#: Gravitational acceleration [m/s²], the default of ``Mechanism(gravity=)``.
GRAVITY = 9.81
#: The effects a mechanism knows (module docstring); it assembles only those named.
EFFECTS = ("gravity", "springs", "damping", "compliance")
_AXES = ("x", "y", "theta")


@dataclass
class _Spring:
    a: int
    b: int | None
    stiffness: float
    rest_length: float
    point_a: np.ndarray
    point_b: np.ndarray   # on body b, or the ground anchor

    def tension(self, length, rate):
        return self.stiffness * (length - self.rest_length)


@dataclass
class _Damper:
    a: int
    b: int | None
    coefficient: float
    point_a: np.ndarray
    point_b: np.ndarray

    def tension(self, length, rate):
        return self.coefficient * rate


def _p3(xy):
    return np.array([xy[0], xy[1], 0.0])


class Mechanism(ModelContacts):
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
        self.dampers: list[_Damper] = []
        self.forces: list = []
        self.contacts: list[Contact] = []

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

    def add_damper(self, a: str, b: str | None, coefficient: float, point_a=(0.0, 0.0),
                   point_b=(0.0, 0.0)) -> None:
        """Linear viscous damper [N·s/m] between point_a of body a and point_b
        of body b, or the ground anchor point_b (world) when b is None."""
        if "damping" not in self.effects:
            raise InvalidProblemError("add_damper needs the effect 'damping'")
        if not coefficient > 0:
            raise InvalidProblemError(f"a damper's coefficient must be > 0 N·s/m; got {coefficient}")
        self.dampers.append(_Damper(self._body(a), self._body(b), float(coefficient),
                                    _p3(point_a), _p3(point_b)))

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
        self.contacts.append(Contact(name, self._body(a), self._body(b), _p3(n),
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

    def _world_velocity(self, i, s):
        """World velocity of point s of body i (zero for a ground anchor)."""
        if i is None:
            return np.zeros(3)
        V = self._data.V[i]
        return self._data.Ra[i] @ (V[:3] + np.cross(V[3:], s))

    def _body_forces(self, t):
        """Springs and applied forces as spatial forces on the bodies (body
        frames, moments about their origins), after forward kinematics."""
        d = self._data
        f = np.zeros((self.model.nbodies + 1, 6))

        def at(i, s):
            return world_point(self.model, d, i, s)

        def push(i, x, F, torque=0.0):
            if i is None:
                return
            Rt = d.Ra[i].T
            f[i, :3] += Rt @ F
            f[i, 3:] += Rt @ (np.cross(x - d.ra[i], F) + np.array([0.0, 0.0, torque]))

        for el in self.springs + self.dampers:   # forces along the line between two points
            xa, xb = at(el.a, el.point_a), at(el.b, el.point_b)
            ell = np.linalg.norm(xb - xa)
            if ell == 0:
                continue
            e = (xb - xa) / ell
            rate = e @ (self._world_velocity(el.b, el.point_b) - self._world_velocity(el.a, el.point_a))
            F = el.tension(ell, rate) * e      # a tension pulls a toward b
            push(el.a, xa, F)
            push(el.b, xb, -F)
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

    def step_data(self, t, q, v):
        """What one contact step needs at (t, q, ν): (G as an O(N) factorized
        operator, Q, J, D, Φ) — the penalty QP and the exact LCP of
        formulations.stepping.penalty_step are built from these, without forming G⁻¹."""
        Phi, J, D = self.constraints(q, v)
        return self.mass_operator(q), self.generalized_forces(t, q, v), J, D, Phi

    def compliance(self):
        if "compliance" not in self.effects:
            return None
        return np.diag([c.compliance for c in self.contacts])

    # -- the step (formulations.stepping.contact_step) ----------------------------------------
    def step_problem(self, t, q, v, dt):
        """(PenaltyStep, Φ, a₀ = 0) at (t, q, ν) with look-ahead Δt."""
        Gop, Q, J, D, Phi = self.step_data(t, q, v)
        B = 2.0 / dt ** 2 * (Phi + dt * (J @ v))
        return PenaltyStep(Gop, Q, J, B, D, self.compliance()), Phi, 0.0

    def coordinate_names(self) -> list[str]:
        names = []
        for name, j in zip(self.model.names[1:], self.model.joints[1:]):
            names += [f"{name}.{a}" for a, on in zip(_AXES, j.mask) if on]
        return names


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
    """(Mechanism, run) from a checked scene: bodies, springs and dampers (only
    with the effects "springs" and "damping"), applied forces (constant, or a
    pulse that ends at ``until``), contacts (compliant only with
    "compliance"), gravity only with "gravity"."""
    d, eff = scene.data, scene.effect_params
    for table, effect in (("springs", "springs"), ("dampers", "damping")):
        if d[table] and effect not in eff:
            scene.fail(f"{table} are given but '{effect}' is not among the effects; add it to "
                       f"effects or remove the [[{table}]] tables", (table,), None, 0)
    m = Mechanism(effects=scene.effects,
                  gravity=eff["gravity"]["g"] if "gravity" in eff else GRAVITY)
    for b in d["bodies"]:
        m.add_body(b["name"], b["mass"], b["inertia"], dofs=tuple(b["dofs"]),
                   position=tuple(b["position"]), velocity=tuple(b["velocity"]),
                   parent=b["parent"])
    for sp_ in d["springs"]:
        m.add_spring(sp_["a"], sp_["b"], sp_["stiffness"], sp_["rest_length"],
                     point_a=tuple(sp_["point_a"]), point_b=tuple(sp_["point_b"]))
    for dp in d["dampers"]:
        m.add_damper(dp["a"], dp["b"], dp["coefficient"], point_a=tuple(dp["point_a"]),
                     point_b=tuple(dp["point_b"]))
    for f in d["forces"]:
        if f["until"] is None:
            m.add_force(f["body"], f["fx"], f["fy"], f["torque"])
        else:
            on, until = (f["fx"], f["fy"], f["torque"]), f["until"]
            m.add_force(f["body"], fn=lambda t, pose, vel, on=on, until=until:
                        on if t < until else (0.0, 0.0, 0.0))
    compliance = eff["compliance"]["compliance"] if "compliance" in eff else None
    for c in d["contacts"]:
        m.add_contact(c["name"], c["a"], c["b"], normal=tuple(c["normal"]),
                      point_a=tuple(c["point_a"]), point_b=tuple(c["point_b"]),
                      offset=c["offset"], compliance=compliance)
    return m, scene_run(m, d["time"], d["solver"])


def _scene_schema():
    from qpcontact.scenes import Field, SceneSchema

    xy = "m (x, y in the body's frame, or the world's for the ground)"
    return SceneSchema(
        formulation="mechanism",
        doc="a planar mechanism from bodies, springs, forces and unilateral contacts (Nikolsky et al. 2012)",
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
            "dampers": Field("tables", doc="linear viscous dampers (effect 'damping')",
                             default=[], fields={
                "a": Field("str", "", "body a", required=True),
                "b": Field("str", "", "body b (default: a ground anchor at point_b)"),
                "coefficient": Field("float", "N·s/m", "damping coefficient", required=True,
                                     positive=True),
                "point_a": Field("floats", xy, "attachment on a", default=[0.0, 0.0]),
                "point_b": Field("floats", xy, "attachment on b", default=[0.0, 0.0])}),
            "forces": Field("tables", doc="applied forces at the body origin", default=[],
                            fields={
                "body": Field("str", "", "body", required=True),
                "fx": Field("float", "N", "force x (world)", default=0.0),
                "fy": Field("float", "N", "force y (world)", default=0.0),
                "torque": Field("float", "N·m", "torque", default=0.0),
                "until": Field("float", "s", "the force acts while t < until (a pulse; "
                               "default: always)")}),
            "contacts": contacts_section((1.0, 0.0)),
            "time": time_section(),
            "solver": solver_section(),
        },
        effects={
            "gravity": {"g": Field("float", "m/s²", "gravitational acceleration (−y)",
                                   default=GRAVITY, positive=True)},
            "springs": {},
            "damping": {},
            "compliance": {"compliance": Field("float", "m/N", "contact compliance of every "
                                               "contact", required=True, positive=True)},
        },
        build=_scene_build, arrays=scene_arrays, plot=scene_plot, summary=scene_summary)


#: The mechanism's scene-file schema (entry point ``qpcontact.scenes``: ``mechanism``).
SCENE = _scene_schema()
