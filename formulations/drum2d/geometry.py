r"""Geometry of the 2-D drum cross-section: discs, the shell circle, lifter bars.

SI units: metres, kilograms, seconds, radians (rad/s for rates).

A log of diameter d and length ℓ (along the drum axis) is, in plane strain, a
disc of radius r = d/2 carrying the whole log's mass and moment of inertia
about its own axis:

    m = ρ π d²/4 ℓ  [kg],        I = m d²/8 = m r²/2  [kg·m²]

(a solid cylinder).  The generalized velocity of disc i is (vx, vy, ω) in m/s
and rad/s; its mass matrix diag(m, m, I).  A disc "held from rolling" has its
spin locked (I = ∞, inverse inertia 0): the hand-statics reference of a block
on the drum wall.

The shell is the circle of radius R about the origin, the drum axis; it turns
counter-clockwise at Ω [rad/s] (Ω = 0 unless the effect ``rotation`` is named),
so its material point p moves at V(p) = Ω ẑ × p = Ω (−p_y, p_x).  Gravity points
along −y.  A lifter bar is a radial segment from radius R − h to R at polar
angle α_k(t) = α_k(0) + Ω t, thickened by its half-width b (a capsule): a disc
meets it where the distance from the disc's centre to the segment falls to
r + b.  Lifters move with the shell, so the same V(p) gives their wall velocity.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from qpcontact.core.errors import InvalidProblemError
from qpcontact.core.options import check_seed

__all__ = ["Discs", "Shell", "GRAVITY", "SPRUCE_DENSITY", "disc_mass", "disc_inertia",
           "hex_fill"]

#: Gravitational acceleration [m/s²].
GRAVITY = 9.81
#: Density of green spruce [kg/m³], as formulations.drum.
SPRUCE_DENSITY = 860.0


def disc_mass(diameter, length, density=SPRUCE_DENSITY):
    """m = ρ π d²/4 ℓ [kg] of a log of diameter d [m] and length ℓ [m]."""
    return density * np.pi * np.asarray(diameter, float) ** 2 / 4.0 * length


def disc_inertia(mass, diameter):
    """I = m d²/8 [kg·m²]: a solid cylinder about its own axis."""
    return np.asarray(mass, float) * np.asarray(diameter, float) ** 2 / 8.0


def _finite(name, a, positive=False):
    if not np.all(np.isfinite(a)):
        raise InvalidProblemError(f"{name} must be finite; got {a}")
    if positive and np.any(a <= 0):
        raise InvalidProblemError(f"{name} must be > 0; got {a}")


@dataclass
class Discs:
    """The logs as discs: ``diameters`` (n,) [m], ``length`` ℓ [m] (one for all),
    ``positions`` (n, 2) [m] and ``velocities`` (n, 2) [m/s] of the centres,
    ``spins`` (n,) [rad/s], ``density`` [kg/m³]; ``spin_locked`` (bool or (n,))
    holds discs from rolling (infinite inertia)."""

    diameters: np.ndarray
    positions: np.ndarray
    length: float = 1.0
    density: float = SPRUCE_DENSITY
    velocities: np.ndarray | None = None
    spins: np.ndarray | None = None
    spin_locked: np.ndarray | bool = False
    masses: np.ndarray = field(init=False)
    inertias: np.ndarray = field(init=False)

    def __post_init__(self):
        self.diameters = np.atleast_1d(np.asarray(self.diameters, float))
        n = self.diameters.size
        self.positions = np.asarray(self.positions, float).reshape(n, 2).copy()
        self.velocities = (np.zeros((n, 2)) if self.velocities is None
                           else np.asarray(self.velocities, float).reshape(n, 2).copy())
        self.spins = np.zeros(n) if self.spins is None else \
            np.broadcast_to(np.asarray(self.spins, float), (n,)).copy()
        self.spin_locked = np.broadcast_to(np.asarray(self.spin_locked, bool), (n,)).copy()
        _finite("diameters", self.diameters, positive=True)
        _finite("length", np.float64(self.length), positive=True)
        _finite("density", np.float64(self.density), positive=True)
        _finite("positions", self.positions)
        _finite("velocities", self.velocities)
        _finite("spins", self.spins)
        self.masses = disc_mass(self.diameters, self.length, self.density)
        self.inertias = disc_inertia(self.masses, self.diameters)

    @property
    def n(self) -> int:
        return self.diameters.size

    @property
    def radii(self) -> np.ndarray:
        return 0.5 * self.diameters

    def inverse_mass(self) -> np.ndarray:
        """diag(M)⁻¹ over (vx, vy, ω) per disc, 0 for a locked spin [1/kg, 1/(kg·m²)]."""
        inv = np.empty((self.n, 3))
        inv[:, 0] = inv[:, 1] = 1.0 / self.masses
        inv[:, 2] = np.where(self.spin_locked, 0.0, 1.0 / self.inertias)
        return inv.ravel()

    def mass_diagonal(self) -> np.ndarray:
        """diag(M) with locked spins counted as 0 (they carry no kinetic energy: ω is fixed)."""
        m = np.empty((self.n, 3))
        m[:, 0] = m[:, 1] = self.masses
        m[:, 2] = np.where(self.spin_locked, 0.0, self.inertias)
        return m.ravel()


@dataclass
class Shell:
    """The drum: ``radius`` R [m], ``omega`` Ω [rad/s] (counter-clockwise > 0),
    lifters at polar angles ``lifter_angles`` [rad] at t = 0, of height
    ``lifter_height`` h [m] and half-width ``lifter_half_width`` b [m]."""

    radius: float
    omega: float = 0.0
    lifter_angles: np.ndarray = field(default_factory=lambda: np.zeros(0))
    lifter_height: float = 0.0
    lifter_half_width: float = 0.0

    def __post_init__(self):
        self.lifter_angles = np.atleast_1d(np.asarray(self.lifter_angles, float))
        _finite("shell radius", np.float64(self.radius), positive=True)
        _finite("omega", np.float64(self.omega))
        _finite("lifter angles", self.lifter_angles)
        if self.lifter_angles.size and not 0 < self.lifter_height < self.radius:
            raise InvalidProblemError(f"lifter_height must be in (0, R = {self.radius}); got "
                                      f"{self.lifter_height}")
        if not 0 <= self.lifter_half_width < self.radius:
            raise InvalidProblemError(f"lifter_half_width must be in [0, R); got "
                                      f"{self.lifter_half_width}")

    def lifter_segments(self, t: float, omega: float):
        """Endpoints (k, 2) inner and (k, 2) outer of the lifters at time t [s]
        when the shell turns at ``omega`` [rad/s]."""
        a = self.lifter_angles + omega * t
        u = np.column_stack([np.cos(a), np.sin(a)])
        return (self.radius - self.lifter_height) * u, self.radius * u

    def angle(self, t: float, omega: float) -> float:
        """The shell's rotation Ω t [rad]."""
        return omega * t


def wall_velocity(points: np.ndarray, omega: float) -> np.ndarray:
    """V(p) = Ω ẑ × p [m/s] of the shell's (and lifters') material points p (k, 2)."""
    return omega * np.column_stack([-points[:, 1], points[:, 0]])


__all__.append("wall_velocity")


def hex_fill(radius: float, n: int, diameter: float, *, spread: float = 0.0, seed=None,
             clearance: float = 0.0):
    """Centres (n, 2) [m] and diameters (n,) [m] of n discs on a hexagonal
    lattice of pitch (1 + spread) d + clearance filling the shell of radius R
    [m] from the bottom up; diameters drawn uniformly in d (1 ± spread) with
    ``seed``, so that no two discs overlap and none crosses the shell."""
    rng = np.random.default_rng(seed)
    dmax = diameter * (1.0 + spread)
    pitch = dmax + clearance
    reach = radius - 0.5 * dmax - clearance
    rows = int(2 * radius / (pitch * np.sqrt(3) / 2)) + 2
    cols = int(2 * radius / pitch) + 2
    iy, ix = np.mgrid[0:rows, -cols:cols + 1]
    x = (ix + 0.5 * (iy % 2)) * pitch
    y = -reach + iy * pitch * np.sqrt(3) / 2
    pts = np.column_stack([x.ravel(), y.ravel()])
    pts = pts[np.hypot(*pts.T) <= reach]
    pts = pts[np.lexsort((np.abs(pts[:, 0]), pts[:, 1]))]
    if pts.shape[0] < n:
        raise InvalidProblemError(f"{n} discs of diameter {dmax:.3g} m do not fit in a shell of "
                                  f"radius {radius} m (room for {pts.shape[0]})")
    d = diameter * (1.0 + spread * rng.uniform(-1.0, 1.0, n))
    return pts[:n], d
