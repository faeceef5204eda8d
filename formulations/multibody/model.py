"""Model (structure and constants) and Data (state-dependent work arrays).

SI units: lengths m, masses kg, inertias kg·m², angles rad.  Body 0 is the
base (the ground, or a body moving by a given law); every other body hangs on
a joint from a parent with a lower number, as in Ivanov & Shimanovsky (2017).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from . import _kernels as K

__all__ = ["Joint", "Revolute", "Prismatic", "Cardan", "Spherical", "Free", "Planar",
           "Model", "Data"]

_AXIS_NAMES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


def _unit(axis, what):
    a = np.array(_AXIS_NAMES.get(axis, axis) if isinstance(axis, str) else axis, float)
    if a.shape != (3,) or not np.all(np.isfinite(a)) or np.linalg.norm(a) == 0:
        raise InvalidProblemError(f"{what} must be 'x', 'y', 'z' or a nonzero 3-vector; got {axis!r}")
    return a / np.linalg.norm(a)


@dataclass(frozen=True)
class Joint:
    """A joint's kind and constants; use the factories below."""

    kind: int
    nq: int
    nv: int
    axes: np.ndarray = field(default_factory=lambda: np.zeros((2, 3)))
    fixed: np.ndarray = field(default_factory=lambda: np.zeros(3))
    mask: np.ndarray = field(default_factory=lambda: np.zeros(3, np.int64))
    label: str = ""

    def neutral(self) -> np.ndarray:
        q = np.zeros(self.nq)
        if self.kind == K.SPHERICAL:
            q[3] = 1.0
        elif self.kind == K.FREE:
            q[6] = 1.0
        return q


def Revolute(axis="z") -> Joint:
    """1 DOF: rotation θ [rad] about ``axis`` (joint frame)."""
    ax = np.zeros((2, 3))
    ax[0] = _unit(axis, "revolute axis")
    return Joint(K.REVOLUTE, 1, 1, ax, label=f"revolute {axis}")


def Prismatic(axis="x") -> Joint:
    """1 DOF: translation s [m] along ``axis`` (joint frame)."""
    ax = np.zeros((2, 3))
    ax[0] = _unit(axis, "prismatic axis")
    return Joint(K.PRISMATIC, 1, 1, ax, label=f"prismatic {axis}")


def Cardan(axis1="x", axis2="y") -> Joint:
    """2 DOF universal joint (Ivanov & Shimanovsky's experiments): rotation q1 about axis1, then
    q2 about axis2 of the once-rotated frame."""
    ax = np.array([_unit(axis1, "Cardan axis1"), _unit(axis2, "Cardan axis2")])
    if abs(ax[0] @ ax[1]) > 1 - 1e-12:
        raise InvalidProblemError("Cardan axes must not be parallel")
    return Joint(K.CARDAN, 2, 2, ax, label="cardan")


def Spherical() -> Joint:
    """3 DOF ball joint: q = unit quaternion (x, y, z, w), ν = relative angular
    velocity in the child frame (Pinocchio's convention)."""
    return Joint(K.SPHERICAL, 4, 3, label="spherical")


def Free() -> Joint:
    """6 DOF: q = (position in the joint frame, quaternion x, y, z, w), ν =
    (linear, angular) relative velocity in the child frame (Pinocchio's
    free-flyer convention)."""
    return Joint(K.FREE, 7, 6, label="free")


def Planar(free=("x", "y", "theta"), fixed=(0.0, 0.0, 0.0)) -> Joint:
    """Planar motion in the joint frame's xy plane: translation (x, y) then
    rotation θ about z.  Only the axes named in ``free`` are coordinates (in
    the order x, y, theta); the others stay at ``fixed``."""
    names = ("x", "y", "theta")
    free = (free,) if isinstance(free, str) else tuple(free)
    bad = [a for a in free if a not in names]
    if bad or not free or len(set(free)) != len(free):
        raise InvalidProblemError(f"Planar free axes must be distinct names among {names}; got {free}")
    mask = np.array([a in free for a in names], np.int64)
    n = int(mask.sum())
    fx = np.array(fixed, float).reshape(3)
    return Joint(K.PLANAR, n, n, fixed=fx, mask=mask,
                 label="planar " + ",".join(a for a in names if a in free))


def _spatial_inertia(mass, com, inertia):
    """6 x 6 inertia about the body origin, (linear, angular) ordering."""
    c = np.asarray(com, float)
    cx = np.array([[0, -c[2], c[1]], [c[2], 0, -c[0]], [-c[1], c[0], 0]])
    M = np.zeros((6, 6))
    M[:3, :3] = mass * np.eye(3)
    M[:3, 3:] = -mass * cx
    M[3:, :3] = mass * cx
    M[3:, 3:] = np.asarray(inertia, float) - mass * cx @ cx
    return M


class Model:
    """Tree of rigid bodies.  ``add_body`` appends body i hanging from
    ``parent`` (< i) by ``joint``; the joint frame sits at ``placement``
    (translation [m], optionally with a rotation matrix) in the parent frame and
    the body frame coincides with the joint frame at the joint's neutral
    configuration.

    ``gravity`` [m/s²] is a world vector.  ``base`` (optional) is the law of
    body 0: ``base(t) -> (R, r, V, A)`` with its orientation, origin, spatial
    velocity and the time derivative of that velocity's components (all in the
    base frame, (linear, angular)); default: fixed at the world frame.
    """

    def __init__(self, gravity=(0.0, 0.0, -9.81), base=None):
        self.gravity = np.array(gravity, float).reshape(3)
        self.base = base
        self.names = ["base"]
        self._parent = [-1]
        self.joints: list[Joint | None] = [None]
        self._R0 = [np.eye(3)]
        self._r0 = [np.zeros(3)]
        self._M = [np.zeros((6, 6))]
        self._mass = [0.0]
        self._com = [np.zeros(3)]
        self._frozen = None

    # -- building ----------------------------------------------------------------------
    def add_body(self, name: str, parent=0, joint: Joint | None = None, placement=(0.0, 0.0, 0.0),
                 rotation=None, mass: float = 1.0, com=(0.0, 0.0, 0.0),
                 inertia=((0.0, 0.0, 0.0),) * 3) -> int:
        """Append a body [kg, m, kg·m² about its centre of mass, body axes]; returns its number."""
        if name in self.names:
            raise InvalidProblemError(f"a body named {name!r} exists already")
        par = self.body_id(parent)
        if joint is None or not isinstance(joint, Joint):
            raise InvalidProblemError(f"body {name!r}: joint must be Revolute(...), Prismatic(...), "
                                      "Cardan(...), Spherical(), Free() or Planar(...)")
        I = np.array(inertia, float)
        if I.shape == (3,):
            I = np.diag(I)
        if I.shape != (3, 3) or not np.allclose(I, I.T, atol=1e-12 * max(1.0, np.abs(I).max())):
            raise InvalidProblemError(f"body {name!r}: inertia must be a symmetric 3 x 3 (or its diagonal)")
        if not (np.isfinite(mass) and mass > 0):
            raise InvalidProblemError(f"body {name!r}: mass must be > 0 kg; got {mass}")
        if np.linalg.eigvalsh(I).min() < -1e-12 * max(1.0, np.abs(I).max()):
            raise InvalidProblemError(f"body {name!r}: inertia must be positive semidefinite")
        R0 = np.eye(3) if rotation is None else np.array(rotation, float)
        if R0.shape != (3, 3) or not np.allclose(R0 @ R0.T, np.eye(3), atol=1e-10) \
                or np.linalg.det(R0) < 0:
            raise InvalidProblemError(f"body {name!r}: rotation must be a proper rotation matrix")
        self.names.append(name)
        self._parent.append(par)
        self.joints.append(joint)
        self._R0.append(R0)
        self._r0.append(np.array(placement, float).reshape(3))
        self._M.append(_spatial_inertia(float(mass), com, I))
        self._mass.append(float(mass))
        self._com.append(np.array(com, float).reshape(3))
        self._frozen = None
        return len(self.names) - 1

    def body_id(self, body) -> int:
        if isinstance(body, (int, np.integer)):
            if not 0 <= body < len(self.names):
                raise InvalidProblemError(f"no body number {body}; the model has bodies 0..{len(self.names) - 1}")
            return int(body)
        if body not in self.names:
            raise InvalidProblemError(f"no body named {body!r}; bodies: {self.names}")
        return self.names.index(body)

    # -- frozen arrays --------------------------------------------------------------------
    @property
    def arrays(self):
        if self._frozen is None:
            nb = len(self.names)
            jt = np.full(nb, -1, np.int64)
            axes = np.zeros((nb, 2, 3))
            fixed = np.zeros((nb, 3))
            mask = np.zeros((nb, 3), np.int64)
            nqj = np.zeros(nb, np.int64)
            nvj = np.zeros(nb, np.int64)
            for i in range(1, nb):
                j = self.joints[i]
                jt[i], axes[i], fixed[i], mask[i] = j.kind, j.axes, j.fixed, j.mask
                nqj[i], nvj[i] = j.nq, j.nv
            iq = np.concatenate([[0], np.cumsum(nqj)[:-1]]).astype(np.int64)
            iv = np.concatenate([[0], np.cumsum(nvj)[:-1]]).astype(np.int64)
            self._frozen = dict(parent=np.array(self._parent, np.int64), jtype=jt, axes=axes,
                                fixed=fixed, mask=mask, R0=np.array(self._R0),
                                r0=np.array(self._r0), iq=iq, iv=iv, nqj=nqj, nvj=nvj,
                                M=np.array(self._M), mass=np.array(self._mass),
                                com=np.array(self._com))
        return self._frozen

    @property
    def nbodies(self) -> int:
        """N, the number of moving bodies (body 0 not counted)."""
        return len(self.names) - 1

    @property
    def nq(self) -> int:
        return int(self.arrays["nqj"].sum())

    @property
    def nv(self) -> int:
        return int(self.arrays["nvj"].sum())

    def neutral(self) -> np.ndarray:
        """The configuration with every joint at rest (unit quaternions)."""
        return np.concatenate([np.zeros(0)] + [j.neutral() for j in self.joints[1:]])

    def q_slice(self, body) -> slice:
        i = self.body_id(body)
        a = self.arrays
        return slice(int(a["iq"][i]), int(a["iq"][i] + a["nqj"][i]))

    def v_slice(self, body) -> slice:
        i = self.body_id(body)
        a = self.arrays
        return slice(int(a["iv"][i]), int(a["iv"][i] + a["nvj"][i]))

    def check_state(self, q, v=None):
        """Validated float copies of q (nq) and v (nv); errors say what is wrong."""
        q = np.asarray(q, float)
        if q.shape != (self.nq,):
            raise InvalidProblemError(f"q must have shape ({self.nq},) for this model; got {q.shape}")
        if not np.all(np.isfinite(q)):
            raise InvalidProblemError("q has non-finite entries")
        if v is None:
            return q
        v = np.asarray(v, float)
        if v.shape != (self.nv,):
            raise InvalidProblemError(f"v must have shape ({self.nv},) for this model; got {v.shape}")
        if not np.all(np.isfinite(v)):
            raise InvalidProblemError("v has non-finite entries")
        return q, v

    def base_state(self, t: float):
        """(R, r, V0, A0) of body 0 at time t; A0 includes gravity as -g."""
        if self.base is None:
            R, r, V, A = np.eye(3), np.zeros(3), np.zeros(6), np.zeros(6)
        else:
            R, r, V, A = (np.asarray(x, float) for x in self.base(t))
        A = A.copy()
        A[:3] -= R.T @ self.gravity
        return R, r, V, A

    def __repr__(self):
        return f"Model({self.nbodies} bodies, nq={self.nq}, nv={self.nv})"


class Data:
    """Work arrays of one state: relative placements, motion subspaces, world
    placements Ra/ra, body velocities V, subtree momenta mu, mass matrix G.
    Filled by the algorithms; a Data belongs to one Model."""

    def __init__(self, model: Model):
        self.model = model
        nb = model.nbodies + 1
        self.Rrel = np.zeros((nb, 3, 3))
        self.rho = np.zeros((nb, 3))
        self.H = np.zeros((nb, 6, 6))
        self.Hd = np.zeros((nb, 6, 6))
        self.Ra = np.zeros((nb, 3, 3))
        self.ra = np.zeros((nb, 3))
        self.V = np.zeros((nb, 6))
        self.mu = np.zeros((nb, 6))
        self.G = None
        self.t = 0.0
