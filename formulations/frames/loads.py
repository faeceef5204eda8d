"""Loads on plane frames: load cases, nodal and member loads, combinations.

A load belongs to a named **load case** ("D", "L", "W", ...).  A
**combination** is a dict {case: factor}; each combination is analysed as its
own nonlinear problem (contact states differ between combinations, so results
are never superposed).  The cases "constant" and "variable" are the P3 split
used by ``Frame.solve(p)`` and ``Frame.trace``: constant + p x variable.

Member loads are stored in the axes they were given in ("global": x right,
y up; "member": x from node i to node j, y its normal turned counterclockwise)
and turned into member axes when the member's geometry is known:

* point force (px, py) and moment mz at a distance ``a`` from node i;
* distributed load, trapezoidal from (wx1, wy1) at ``a`` to (wx2, wy2) at
  ``b`` (per unit length of the member: for a load per horizontal projection,
  multiply by cos θ yourself);
* self-weight: a uniform global load of (weight per length) x direction.

Their equivalent nodal loads are the consistent ones, ∫ Nᵀ w dx with the
element's own shape functions (linear axially, cubic Hermite transversely),
which for an Euler–Bernoulli element are the exact fixed-end forces; the
integrals are computed by Gauss–Legendre quadrature exact for these
polynomial integrands.  Units: the user's, consistent.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from qpcontact.core.errors import InvalidProblemError

#: the two cases of the P3 split (constant + p x variable)
CONSTANT, VARIABLE = "constant", "variable"
AXES = ("global", "member")

_GAUSS = np.polynomial.legendre.leggauss(4)   # exact to degree 7: cubic x linear load


@dataclass(frozen=True)
class MemberLoad:
    """One load on a member (see the module docstring).  ``kind``: "point",
    "distributed"; positions ``a`` <= ``b`` in length units from node i."""

    kind: str
    case: str
    axes: str
    a: float
    b: float
    values: tuple   # point: (px, py, mz); distributed: (wx1, wy1, wx2, wy2)


def number(value, what: str) -> float:
    """A finite float, or an error that names ``what``."""
    if isinstance(value, (bool, str, bytes)) or value is None:
        raise InvalidProblemError(f"{what} must be a number; got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InvalidProblemError(f"{what} must be a number; got {value!r}") from None
    if not np.isfinite(v):
        raise InvalidProblemError(f"{what} must be finite; got {v}")
    return v


def case_name(case) -> str:
    if not isinstance(case, str) or not case:
        raise InvalidProblemError(f"a load case is named by a non-empty string; got {case!r}")
    return case


def check_axes(axes) -> str:
    if axes not in AXES:
        raise InvalidProblemError(f"axes must be one of {AXES}; got {axes!r}")
    return axes


def combination(combo, cases) -> dict:
    """Validate {case: factor}; every case named must have loads or be known."""
    if not isinstance(combo, dict) or not combo:
        raise InvalidProblemError(
            f"a combination is a non-empty dict {{case: factor}}, e.g. {{'D': 1.2, 'L': 1.6}}; "
            f"got {combo!r}")
    out = {}
    for case, f in combo.items():
        if case not in cases:
            raise InvalidProblemError(
                f"combination names the load case {case!r}, which has no loads; cases: "
                f"{sorted(cases)}")
        out[case] = number(f, f"the factor of case {case!r}")
    return out


def describe(combo: dict) -> str:
    """A combination in words: "1.2·D, 1.6·L" ("no load" when every factor is 0)."""
    return ", ".join(f"{f:g}·{c}" for c, f in combo.items() if f) or "no load"


def _local(axes, c, s, fx, fy):
    """Components in member axes of a vector given in ``axes``."""
    if axes == "member":
        return fx, fy
    return c * fx + s * fy, -s * fx + c * fy


# Hermite/linear shape functions as polynomials in xi = x/L (columns: 1, xi,
# xi², xi³); the rotation rows (2, 5) carry a factor L.
_N_POLY = np.array([[1, -1, 0, 0], [1, 0, -3, 2], [0, 1, -2, 1],
                    [0, 1, 0, 0], [0, 0, 3, -2], [0, 0, -1, 1]], float)
_DN_POLY = np.c_[_N_POLY[:, 1:] * (1, 2, 3), np.zeros(6)]


def shape_functions(x, L):
    """Shape functions and their x-derivatives at x (member axes): (6,) for
    a number, (6, len(x)) for an array."""
    xi = np.asarray(x, float) / L
    powers = xi[..., None] ** np.arange(4)      # (..., 4)
    scale = np.array([1, 1, L, 1, 1, L])
    N = scale[:, None] * (_N_POLY @ powers.T) if xi.ndim else scale * (_N_POLY @ powers)
    dN = (scale[:, None] * (_DN_POLY @ powers.T) if xi.ndim else scale * (_DN_POLY @ powers)) / L
    return N, dN


def _gauss(a, b):
    t, w = _GAUSS
    return 0.5 * (b - a) * t + 0.5 * (a + b), 0.5 * (b - a) * w


def _trapezoid(load, c, s):
    """(wx1, wy1, wx2, wy2) in member axes."""
    wx1, wy1, wx2, wy2 = load.values
    a1 = _local(load.axes, c, s, wx1, wy1)
    a2 = _local(load.axes, c, s, wx2, wy2)
    return a1[0], a1[1], a2[0], a2[1]


def equivalent_nodal(load: MemberLoad, L: float, c: float, s: float) -> np.ndarray:
    """Consistent nodal loads (member axes, order ux, uy, rz at i then j)."""
    if load.kind == "point":
        px, py = _local(load.axes, c, s, *load.values[:2])
        N, dN = shape_functions(load.a, L)
        axial = np.array([1.0, 0, 0, 1.0, 0, 0])
        trans = 1.0 - axial
        return N * (px * axial + py * trans) + load.values[2] * dN * trans
    wx1, wy1, wx2, wy2 = _trapezoid(load, c, s)
    if load.b <= load.a:
        return np.zeros(6)
    xs, ws = _gauss(load.a, load.b)
    t = (xs - load.a) / (load.b - load.a)
    qx, qy = wx1 + t * (wx2 - wx1), wy1 + t * (wy2 - wy1)
    N, _ = shape_functions(xs, L)              # (6, Gauss points)
    return (N * np.array([qx, qy, qy, qx, qy, qy])) @ ws


def section_sums(loads, x: np.ndarray, c: float, s: float):
    """For sections at x (member axes): the loads on [0, x) summed as
    (axial force, transverse force, moment about the section) — what the
    diagrams add to the end forces.  A point load exactly at a section counts
    as left of it (the diagram's value just right of the load)."""
    fx = np.zeros_like(x)
    fy = np.zeros_like(x)
    mo = np.zeros_like(x)
    for load in loads:
        if load.kind == "point":
            px, py = _local(load.axes, c, s, *load.values[:2])
            on = x >= load.a
            fx += np.where(on, px, 0.0)
            fy += np.where(on, py, 0.0)
            mo += np.where(on, py * (x - load.a) - load.values[2], 0.0)
            continue
        wx1, wy1, wx2, wy2 = _trapezoid(load, c, s)
        span = load.b - load.a
        if span <= 0:
            continue
        for k, xk in enumerate(x):
            top = min(xk, load.b)
            if top <= load.a:
                continue
            xs, ws = _gauss(load.a, top)
            t = (xs - load.a) / span
            qx, qy = wx1 + t * (wx2 - wx1), wy1 + t * (wy2 - wy1)
            fx[k] += ws @ qx
            fy[k] += ws @ qy
            mo[k] += ws @ (qy * (xk - xs))
    return fx, fy, mo


def load_points(loads) -> list:
    """Positions along the member where a diagram has a kink or a jump."""
    pts = []
    for load in loads:
        pts += [load.a, load.b]
    return pts
