r"""Tree (and closed-loop) multibody systems with unilateral contacts, stepped
by the penalty QP of Nikolsky et al. (2012) on the O(N) model (formulations.stepping).

SI units: m, kg, s, rad; forces N, torques N·m, joint damping N·s/m or
N·m·s/rad, compliance m/N.

A :class:`ContactTree` is a :class:`Model` (any joints: revolute, prismatic,
Cardan, spherical, free, planar) plus the *effects* its scene names:

- ``gravity``: g along −z (the model's gravity is zero without it);
- ``joint_damping``: τ_j = −c_j ν_j on the joints given a coefficient (a
  generalized force, evaluated at the step's start like every force);
- ``compliance``: one compliance c [m/N] for every contact (C = c I);
  without it the contacts are rigid (the penalty paper's regularized C, or the exact LCP);
- ``loops``: closed loops (constraints.PointLoop) kept inside each step with
  Baumgarte stabilisation:

      G a − J_c'σ = Q + J'λ,   J_c a = −J̇_cν − 2αJ_cν − β²Φ_c.

  Eliminating σ gives a = P(Q + J'λ) + a₀ with the projected inverse
  P = G⁻¹ − G⁻¹J_c'S⁻¹J_cG⁻¹ (S = J_cG⁻¹J_c', m x m) and a₀ = G⁻¹J_c'S⁻¹r_c:
  the contact LCP keeps one unknown per contact (A = JPJ', b with J a₀ in
  D), and every G⁻¹ is the O(N) momentum-form solve.

A contact between point s_a of body a and point s_b of body b (or a world
anchor) along a fixed unit normal n is Φ = n·(p_b − p_a) − offset ≥ 0, with
J = n·(J_b − J_a) and D = n·(J̇_b − J̇_a)ν from the point Jacobians — the
rows :func:`contact_rows` computes for the planar mechanisms too.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from qpcontact.core.errors import InvalidOptionError, InvalidProblemError

from ..stepping.penalty_step import PenaltyStep
from ..stepping.contact_step import (ContactSystem, scene_arrays, scene_plot, scene_run,
                                     scene_summary, solver_section, time_section, contacts_section)
from . import algorithms as alg
from . import constraints as con
from .model import Cardan, Data, Free, Model, Prismatic, Revolute, Spherical

__all__ = ["ContactTree", "ModelContacts", "Contact", "contact_rows", "world_point", "TREE_EFFECTS", "JOINTS"]

TREE_EFFECTS = ("gravity", "joint_damping", "compliance", "loops")

#: joint name -> (factory from the scene's axes, how many axes it takes)
JOINTS = {"revolute": (lambda ax: Revolute(ax[0]), 1), "prismatic": (lambda ax: Prismatic(ax[0]), 1),
          "cardan": (lambda ax: Cardan(ax[0], ax[1]), 2), "spherical": (lambda ax: Spherical(), 0),
          "free": (lambda ax: Free(), 0)}


def _coordinates(joint) -> list[str]:
    if joint.label == "free":
        return ["x", "y", "z", "qx", "qy", "qz", "qw"]
    if joint.label == "spherical":
        return ["qx", "qy", "qz", "qw"]
    if joint.label.startswith("planar"):
        return [a for a, on in zip(("x", "y", "theta"), joint.mask) if on]
    return [f"q{k + 1}" for k in range(joint.nq)]


@dataclass
class Contact:
    """Φ = n·(p_b − p_a) − offset ≥ 0 [m]; a, b body numbers or None (a
    world anchor); points in the body frames (or the world for the ground)."""

    name: str
    a: int | None
    b: int | None
    normal: np.ndarray
    point_a: np.ndarray
    point_b: np.ndarray
    offset: float
    compliance: float = 0.0


def world_point(model, data, i, s):
    """World position of point s of body i (after forward kinematics), or the anchor s."""
    return s if i is None else alg.point_position(model, data, i, s)


def contact_rows(model: Model, data: Data, contacts, q, v):
    """(Φ [m], J (ν x nv), D = J̇ν [m/s²]) of the contacts at (q, ν)."""
    alg.forward_kinematics(model, data, q, v)
    nu, n = len(contacts), model.nv
    Phi, J, D = np.zeros(nu), np.zeros((nu, n)), np.zeros(nu)
    for k, c in enumerate(contacts):
        xa = world_point(model, data, c.a, c.point_a)
        xb = world_point(model, data, c.b, c.point_b)
        Phi[k] = c.normal @ (xb - xa) - c.offset
        for sign, i, s in ((1.0, c.b, c.point_b), (-1.0, c.a, c.point_a)):
            if i is not None:
                Jp, Jd = alg.point_jacobian(model, data, i, s)
                J[k] += sign * (c.normal @ Jp)
                D[k] += sign * (c.normal @ (Jd @ v))
    return Phi, J, D


class _LoopOperator:
    """The projected inverse P of the module docstring as an operator
    (``solve(r)`` = P r): what the step's contacts see once the loops' σ is
    eliminated.  There is no matrix G behind it (P is singular)."""

    def __init__(self, mass_operator, Jc):
        self._G = mass_operator
        self.shape = mass_operator.shape
        self.X = mass_operator.solve(np.ascontiguousarray(Jc.T))        # G⁻¹J_c'
        self.Jc = Jc
        try:
            self._S = scipy.linalg.cho_factor(Jc @ self.X)
        except np.linalg.LinAlgError:
            raise InvalidProblemError("the loop constraints are redundant or singular here "
                                      "(J_c G⁻¹ J_c' not positive definite)") from None

    def solve(self, r):
        x = self._G.solve(r)
        return x - self.X @ scipy.linalg.cho_solve(self._S, self.Jc @ x)

    def particular(self, rc):
        """a₀ = G⁻¹J_c'S⁻¹r_c: the loops' own acceleration."""
        return self.X @ scipy.linalg.cho_solve(self._S, rc)

    def toarray(self):
        raise InvalidOptionError("with closed loops a step has no single mass matrix G (the "
                                 "contacts see the projected inverse P); use the penalty QP or "
                                 "the exact LCP")


class ModelContacts(ContactSystem):
    """A contact system built on a multibody Model (``self.model``,
    ``self._data``) with ``self.contacts``: the gaps, the configuration update
    and the names the stepper needs."""

    def constraints(self, q, v):
        """Φ [m], J (ν x nv), D = J̇ν [m/s²] at (q, ν)."""
        return contact_rows(self.model, self._data, self.contacts, q, v)

    def gaps(self, q, v) -> np.ndarray:
        return self.constraints(q, v)[0]

    def integrate(self, q, dq) -> np.ndarray:
        return alg.integrate(self.model, q, dq)

    def contact_names(self) -> list[str]:
        return [c.name for c in self.contacts]


class ContactTree(ModelContacts):
    """A spatial tree of rigid bodies with unilateral contacts (module
    docstring).  ``effects`` ⊂ TREE_EFFECTS names what is assembled; data for
    an effect not named raises InvalidProblemError."""

    def __init__(self, effects=(), gravity: float = 9.81, alpha: float = 0.0, beta: float = 0.0):
        effects = frozenset((effects,) if isinstance(effects, str) else effects)
        unknown = sorted(effects - set(TREE_EFFECTS))
        if unknown:
            raise InvalidProblemError(f"unknown effect(s) {unknown}; trees know {list(TREE_EFFECTS)}")
        self.effects = effects
        self.gravity = float(gravity) if "gravity" in effects else 0.0
        self.model = Model(gravity=(0.0, 0.0, -self.gravity))
        self._data = Data(self.model)
        self._q0, self._v0, self._damping = [], [], []
        self.contacts: list[Contact] = []
        self.loops: list[con.PointLoop] = []
        self.alpha, self.beta = float(alpha), float(beta)

    def add_body(self, name: str, joint, *, parent=0, placement=(0.0, 0.0, 0.0), mass: float,
                 com=(0.0, 0.0, 0.0), inertia=(0.0, 0.0, 0.0), q=None, v=None,
                 damping: float | None = None) -> int:
        """Append a body hanging from ``parent`` by ``joint`` (a multibody
        Joint) at ``placement`` [m]; ``q``, ``v`` its joint's initial
        coordinates and velocities (default neutral, zero); ``damping``
        [N·s/m or N·m·s/rad] needs the effect 'joint_damping'."""
        if name == self.model.names[0]:
            raise InvalidProblemError(f"the name {name!r} is the ground's (body 0); choose another")
        if damping is not None and "joint_damping" not in self.effects:
            raise InvalidProblemError(f"body {name!r}: joint damping needs the effect 'joint_damping'")
        i = self.model.add_body(name, parent=parent, joint=joint, placement=placement, mass=mass,
                                com=com, inertia=inertia)
        q0 = joint.neutral() if q is None else np.asarray(q, float)
        v0 = np.zeros(joint.nv) if v is None else np.asarray(v, float)
        if q0.shape != (joint.nq,) or v0.shape != (joint.nv,):
            raise InvalidProblemError(f"body {name!r}: its {joint.label} joint takes {joint.nq} "
                                      f"coordinates and {joint.nv} velocities; got {q0.size} and "
                                      f"{v0.size}")
        if damping is not None and not damping >= 0:
            raise InvalidProblemError(f"body {name!r}: joint damping must be >= 0; got {damping}")
        self._q0 += list(q0)
        self._v0 += list(v0)
        self._damping += [0.0 if damping is None else float(damping)] * joint.nv
        return i

    def _body(self, name):
        return None if name is None else self.model.body_id(name)

    def add_contact(self, name: str, a, b, normal=(0.0, 0.0, 1.0), point_a=(0.0, 0.0, 0.0),
                    point_b=(0.0, 0.0, 0.0), offset: float = 0.0,
                    compliance: float | None = None) -> None:
        """Unilateral contact Φ = n·(p_b − p_a) − offset ≥ 0 [m]; a or b may be
        None (the ground: the point is a world anchor)."""
        if (compliance is not None) != ("compliance" in self.effects):
            raise InvalidProblemError(f"contact {name!r}: a compliance is given exactly when the "
                                      "effect 'compliance' is named")
        n = np.array(normal, float)
        if n.shape != (3,) or not np.isclose(np.linalg.norm(n), 1.0):
            raise InvalidProblemError(f"contact {name!r}: normal must be a unit 3-vector")
        self.contacts.append(Contact(name, self._body(a), self._body(b), n,
                                     np.array(point_a, float).reshape(3),
                                     np.array(point_b, float).reshape(3), float(offset),
                                     float(compliance or 0.0)))

    def add_loop(self, body_a, point_a, body_b, point_b, axes=(0, 1, 2)) -> None:
        """Close a loop: point_a of body_a coincides with point_b of body_b
        (body 0 or None: a world point) along the world ``axes``."""
        if "loops" not in self.effects:
            raise InvalidProblemError("a closed loop needs the effect 'loops'")
        self.loops.append(con.PointLoop(self._body(body_a) or 0, tuple(point_a),
                                        self._body(body_b) or 0, tuple(point_b), tuple(axes)))

    # -- what the stepper needs ---------------------------------------------------
    def initial_state(self):
        q, v = np.array(self._q0, float), np.array(self._v0, float)
        if self.loops:     # start on the loops: Newton on Φ(q) = 0, ν projected on J_cν = 0
            q, v = con.assemble_loop_state(self.model, q, v, self.loops)
        return q, v

    def generalized_forces(self, t, q, v) -> np.ndarray:
        """Q = −(gravity, Coriolis) − joint damping [N, N·m]."""
        Q = -alg.nonlinear_effects(self.model, self._data, q, v, None, t)
        if "joint_damping" in self.effects:
            Q -= np.array(self._damping) * v
        return Q

    def compliance(self):
        if "compliance" not in self.effects:
            return None
        return np.diag([c.compliance for c in self.contacts])

    def step_problem(self, t, q, v, dt):
        Phi, J, D = self.constraints(q, v)
        Q = self.generalized_forces(t, q, v)
        G = alg.MassOperator(self.model, q)
        a0 = 0.0
        if self.loops:
            Phic, Jc, Jcd = con.loop_jacobian(self.model, self._data, q, v, self.loops, t)
            G = _LoopOperator(G, Jc)
            a0 = G.particular(-Jcd @ v - 2 * self.alpha * (Jc @ v) - self.beta ** 2 * Phic)
            D = D + J @ a0
        B = 2.0 / dt ** 2 * (Phi + dt * (J @ v))
        return PenaltyStep(G, Q, J, B, D, self.compliance()), Phi, a0

    def coordinate_names(self) -> list[str]:
        """One name per generalized coordinate q (quaternions as qx..qw)."""
        names = []
        for name, j in zip(self.model.names[1:], self.model.joints[1:]):
            names += [name] if j.nq == 1 else [f"{name}.{c}" for c in _coordinates(j)]
        return names

    def energy(self, q, v, t: float = 0.0) -> tuple[float, float]:
        """(kinetic, gravity potential) [J] at (q, ν)."""
        return (alg.kinetic_energy(self.model, self._data, q, v, t),
                alg.potential_energy(self.model, self._data, q, t))

    def loop_residual(self, q) -> float:
        """max |Φ_c| [m] of the loops at q (0 without loops)."""
        if not self.loops:
            return 0.0
        return float(np.max(np.abs(con.loop_residual(self.model, self._data, q, self.loops))))


# -- scene files (qpcontact.scenes): formulation "multibody" -----------------------

_AXIS = {"x": 0, "y": 1, "z": 2}


def _scene_build(scene):
    """(ContactTree, run) from a checked scene: only the named effects'
    terms (gravity, joint damping, contact compliance, closed loops)."""
    d, eff = scene.data, scene.effect_params
    loops = eff.get("loops", {})
    tree = ContactTree(effects=scene.effects, gravity=eff.get("gravity", {}).get("g", 9.81),
                       alpha=loops.get("alpha", 0.0), beta=loops.get("beta", 0.0))
    if d["loops"] and "loops" not in eff:
        scene.fail("loops are given but 'loops' is not among the effects; add it to effects "
                   "or remove the [[loops]] tables", ("loops",), None, 0)
    for k, b in enumerate(d["bodies"]):
        if b["joint"] not in JOINTS:
            scene.fail(f"unknown joint {b['joint']!r}; choose one of {', '.join(JOINTS)}",
                       ("bodies",), "joint", k)
        make, n_axes = JOINTS[b["joint"]]
        if len(b["axes"]) != n_axes or any(a not in _AXIS for a in b["axes"]):
            scene.fail(f"a {b['joint']} joint takes {n_axes} axes among x, y, z; got "
                       f"{b['axes']}", ("bodies",), "axes", k)
        if b["damping"] is not None and "joint_damping" not in eff:
            scene.fail("joint damping is given but 'joint_damping' is not among the effects; "
                       "add it or remove the damping", ("bodies",), "damping", k)
        for key, size in (("placement", 3), ("com", 3), ("inertia", 3)):
            if len(b[key]) != size:
                scene.fail(f"expected {size} numbers, got {len(b[key])}", ("bodies",), key, k)
        try:
            tree.add_body(b["name"], make(b["axes"]), parent=b["parent"] or 0,
                          placement=b["placement"], mass=b["mass"], com=b["com"],
                          inertia=b["inertia"], q=b["q"], v=b["v"], damping=b["damping"])
        except InvalidProblemError as exc:
            scene.fail(str(exc), ("bodies",), "name", k)
    compliance = eff["compliance"]["compliance"] if "compliance" in eff else None
    for k, c in enumerate(d["contacts"]):
        try:
            tree.add_contact(c["name"], c["a"], c["b"], normal=c["normal"], point_a=c["point_a"],
                             point_b=c["point_b"], offset=c["offset"], compliance=compliance)
        except InvalidProblemError as exc:
            scene.fail(str(exc), ("contacts",), "name", k)
    for k, lp in enumerate(d["loops"]):
        if any(a not in _AXIS for a in lp["axes"]):
            scene.fail(f"axes must be among x, y, z; got {lp['axes']}", ("loops",), "axes", k)
        try:
            tree.add_loop(lp["a"], lp["point_a"], lp["b"], lp["point_b"],
                          tuple(_AXIS[a] for a in lp["axes"]))
        except InvalidProblemError as exc:
            scene.fail(str(exc), ("loops",), "a", k)
    return tree, scene_run(tree, d["time"], d["solver"])


def _scene_arrays(result) -> dict:
    """The stepper's arrays, the energy (kinetic, gravity potential) and the
    loops' residual per step."""
    tree = result.mechanism
    E = np.array([tree.energy(q, v, t) for t, q, v in zip(result.t, result.q, result.v)])
    return {**scene_arrays(result), "energy/kinetic": E[:, 0], "energy/potential": E[:, 1],
            "loop_residual": np.array([tree.loop_residual(q) for q in result.q])}


def _scene_plot(h, out) -> list:
    """Coordinates, velocities and reactions; the energy (and the loops' residual)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure

    paths = scene_plot(h, out)
    t_ms = 1e3 * h["t"][()]
    residual = h["loop_residual"][()]
    loops = bool(residual.any())
    fig, axes = plt.subplots(1 + loops, 1, figsize=(8, 3.5 + 2.5 * loops), sharex=True,
                             squeeze=False)
    axes = axes[:, 0]
    T, V = h["energy/kinetic"][()], h["energy/potential"][()]
    for y, lab in ((T, "kinetic"), (V, "gravity potential"), (T + V, "total")):
        axes[0].plot(t_ms, y, label=lab)
    axes[0].set_ylabel("energy [J]")
    axes[0].legend(fontsize=8)
    if loops:
        axes[1].semilogy(t_ms, np.maximum(residual, 1e-17))
        axes[1].set_ylabel("loop residual max|Φ_c| [m]")
    axes[-1].set_xlabel("time [ms]")
    for ax in axes:
        ax.grid(True, alpha=0.3)
    return paths + [save_figure(fig, f"{out}/energy.png")]


def _scene_schema():
    from qpcontact.scenes import Field, SceneSchema

    pt = "m (the body's frame, or the world's for the ground)"
    return SceneSchema(
        formulation="multibody",
        doc="a spatial tree of rigid bodies (Ivanov & Shimanovsky's O(N) model) with unilateral contacts and "
            "closed loops, stepped by Nikolsky et al.'s penalty QP",
        sections={
            "bodies": Field("tables", doc="one [[bodies]] table per body, parents first",
                            required=True, fields={
                "name": Field("str", "", "body name", required=True),
                "joint": Field("str", "", "revolute, prismatic, cardan, spherical or free",
                               required=True),
                "axes": Field("strs", "", "joint axes among x, y, z (1 for revolute and "
                              "prismatic, 2 for cardan, none otherwise)", default=[]),
                "parent": Field("str", "", "parent body (default: the ground)"),
                "placement": Field("floats", "m", "joint frame's origin in the parent's frame",
                                   default=[0.0, 0.0, 0.0]),
                "mass": Field("float", "kg", "mass", required=True, positive=True),
                "com": Field("floats", "m", "centre of mass in the body frame",
                             default=[0.0, 0.0, 0.0]),
                "inertia": Field("floats", "kg·m²", "principal moments about the centre of "
                                 "mass (body axes)", default=[0.0, 0.0, 0.0]),
                "q": Field("floats", "m, rad, quaternion (x, y, z, w)",
                           "the joint's initial coordinates (default neutral)"),
                "v": Field("floats", "m/s, rad/s", "the joint's initial velocities (default 0)"),
                "damping": Field("float", "N·s/m, N·m·s/rad", "joint damping coefficient "
                                 "(effect 'joint_damping')")}),
            "contacts": contacts_section((0.0, 0.0, 1.0)),
            "loops": Field("tables", doc="closed loops (effect 'loops'): point_a of a coincides "
                           "with point_b of b along axes", default=[], fields={
                "a": Field("str", "", "body a (default: the ground)"),
                "point_a": Field("floats", pt, "point on a", default=[0.0, 0.0, 0.0]),
                "b": Field("str", "", "body b (default: the ground)"),
                "point_b": Field("floats", pt, "point on b", default=[0.0, 0.0, 0.0]),
                "axes": Field("strs", "", "world axes constrained", default=["x", "y", "z"])}),
            "time": time_section(),
            "solver": solver_section(),
        },
        effects={
            "gravity": {"g": Field("float", "m/s²", "gravitational acceleration (−z)",
                                   default=9.81, positive=True)},
            "joint_damping": {},
            "compliance": {"compliance": Field("float", "m/N", "contact compliance of every "
                                               "contact", required=True, positive=True)},
            "loops": {"alpha": Field("float", "1/s", "Baumgarte velocity gain (2α J_cν)",
                                     default=0.0),
                      "beta": Field("float", "1/s", "Baumgarte position gain (β² Φ_c)",
                                    default=0.0)},
        },
        build=_scene_build, arrays=_scene_arrays, plot=_scene_plot,
        summary=scene_summary)


SCENE = _scene_schema()
