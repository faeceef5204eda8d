"""Thin rods with large deflections (Pustovoy, Levin & Krasnorutskiy
2014): the planar inextensible elastica
under a dead load, solved by :mod:`.bvp`, and what builds on it.

Nondimensional: arc length s in [0, 1] (s = S/L), load parameter α = P L²/EI,
positions x, y in units of L.  Unknowns y = (θ, κ, x, y): the tangent angle,
the curvature θ' (= M L/EI), and the centreline.  Clamped at s = 0
(θ = x = y = 0), free at s = 1 (κ = 0).

- Cantilever, transverse dead tip load P downward: EI θ'' = P cos θ
  (the moment of the tip load about a section), so θ' = κ, κ' = α cos θ.
- Column, axial dead load P along -x at the free end: θ'' = -α sin θ; the
  straight state is a solution for every α, the buckled branch leaves it at
  α_cr = π²/4.

Columns: clamped-free or pinned-pinned.  :func:`cantilever_general` adds
follower loads and extensibility; :func:`spatial_cantilever` is the spatial
Kirchhoff rod (statics); :func:`cantilever_dynamics` and
:func:`spatial_cantilever_dynamics` their motion, one BVP per time step with
Park's implicit multistep method (as in the rod paper).
"""

from __future__ import annotations

import numpy as np

from . import bvp

__all__ = ["cantilever", "cantilever_general", "column", "cantilever_curve", "tip_deflection",
           "spatial_cantilever", "cantilever_f", "column_f", "clamped_free_bc", "qmul", "rotate",
           "rotate_T", "spatial_f"]


def cantilever_f(s, Y, alpha):
    """y' of the cantilever under a transverse dead tip load α (rows θ, κ, x, y)."""
    th, ka, x, y = Y
    return np.array([ka, alpha * np.cos(th), np.cos(th), np.sin(th)])


def column_f(s, Y, alpha):
    """y' of the column under an axial dead load α (rows θ, κ, x, y)."""
    th, ka, x, y = Y
    return np.array([ka, -alpha * np.sin(th), np.cos(th), np.sin(th)])


def clamped_free_bc(ya, yb, *_):
    """Clamped at s = 0 (θ = x = y = 0), free at s = 1 (κ = 0)."""
    return np.array([ya[0], ya[2], ya[3], yb[1]])


def tip_deflection(res) -> float:
    """δ_v / L: the downward deflection of the free end."""
    return float(-res.y[3, -1])


def cantilever(alpha: float, *, nodes: int = 81, tol: float = 1e-8, continuation: bool = True):
    """Cantilever under a transverse dead tip load α = PL²/EI, from a straight
    initial guess.  Newton alone converges up to α ≈ 10; beyond, the load is
    reached by pseudo-arclength continuation in log10 α from α = 0.01 (on the
    same mesh) and the last point is refined to ``tol``.  Returns a BVPResult."""
    mesh = np.linspace(0.0, 1.0, nodes)
    f = lambda s, Y: cantilever_f(s, Y, alpha)  # noqa: E731
    res = bvp.solve(f, clamped_free_bc, mesh, np.zeros(4), tol=tol)
    if res.ok or not continuation:
        return res
    path = bvp.continuation(lambda s, Y, g: cantilever_f(s, Y, 10.0 ** g), clamped_free_bc, mesh, np.zeros(4),
                            (-2.0, np.log10(alpha)), ds=0.2, ds_max=1.0)
    if path.status != "solved":
        return bvp.BVPResult(mesh, path.ys[-1], path.status, False, path.message, np.inf, np.inf,
                             2, 0)
    return bvp.solve(f, clamped_free_bc, mesh, path.ys[-1], tol=tol)


def cantilever_curve(alpha_max: float, nodes: int = 81):
    """The load-deflection path α -> δ_v/L from 0.01 to ``alpha_max`` by continuation."""
    mesh = np.linspace(0.0, 1.0, nodes)
    path = bvp.continuation(lambda s, Y, g: cantilever_f(s, Y, 10.0 ** g), clamped_free_bc, mesh, np.zeros(4),
                            (-2.0, np.log10(alpha_max)), ds=0.2, ds_max=1.0)
    return 10.0 ** path.gammas, np.array([-Y[3, -1] for Y in path.ys]), path


def _pinned_bc(ya, yb, *_):
    # pins at both ends on the x axis: no moment at either end, the first end fixed
    # (y(1) = 0 follows from EI θ' = -P y with κ(1) = 0)
    return np.array([ya[1], ya[2], ya[3], yb[1]])


_ENDS = {
    # name: (boundary conditions, critical load, start load, buckling-mode guess)
    "clamped-free": (clamped_free_bc, np.pi ** 2 / 4, 2.6,
                     lambda s: np.array([0.8 * np.sin(np.pi * s / 2), 0.4 * np.pi * np.cos(np.pi * s / 2),
                                         s, 0.5 * (1 - np.cos(np.pi * s / 2))])),
    "pinned-pinned": (_pinned_bc, np.pi ** 2, 10.5,
                      lambda s: np.array([0.6 * np.cos(np.pi * s), -0.6 * np.pi * np.sin(np.pi * s),
                                          s, 0.6 / np.pi * np.sin(np.pi * s)])),
}


def column(alpha: float, *, ends: str = "clamped-free", nodes: int = 81, tol: float = 1e-8):
    """The buckled branch of a column under an axial dead load α = PL²/EI above
    its Euler load (π²/4 clamped-free, π² pinned-pinned): started just above the
    critical load from the buckling mode and continued in α.  Returns
    (BVPResult at α, the continuation path)."""
    if ends not in _ENDS:
        from qpcontact.core.errors import InvalidOptionError

        raise InvalidOptionError(f"ends must be one of {list(_ENDS)}, not {ends!r}")
    bc, a_cr, a0, mode = _ENDS[ends]
    if not alpha > a_cr:
        from qpcontact.core.errors import InvalidOptionError

        raise InvalidOptionError(f"alpha = {alpha} is below the Euler load {a_cr:.6g}: the straight "
                                 "column is the only equilibrium")
    mesh = np.linspace(0.0, 1.0, nodes)
    start = bvp.solve(lambda s, Y: column_f(s, Y, a0), bc, mesh, mode(mesh), tol=tol)
    if alpha <= a0:
        end = bvp.solve(lambda s, Y: column_f(s, Y, alpha), bc, start.mesh, start.y, tol=tol)
        return end, None
    path = bvp.continuation(column_f, bc, start.mesh, start.y, (a0, alpha), ds=0.1, ds_max=0.5)
    end = bvp.solve(lambda s, Y: column_f(s, Y, alpha), bc, path.mesh, path.ys[-1], tol=tol)
    return end, path


def cantilever_general(alpha: float, *, follower: bool = False, extensibility: float = 0.0,
                       nodes: int = 81, tol: float = 1e-8):
    """Cantilever with a transverse tip load α = PL²/EI that is dead (fixed
    direction, downward) or a *follower* (stays perpendicular to the tip
    tangent), and an extensible rod with β = EI/(EA L²) (0: inextensible).

    Extensible: the axial strain is ε = α β F_t (F_t the load's component along
    the tangent, in units of P), x' = (1 + ε) cos θ, y' = (1 + ε) sin θ and the
    moment equation picks up the stretched lever arm, κ' = -α (1 + ε)(r̂' × f̂).
    A follower load depends on the unknown tip angle θ_L, carried as a fifth
    unknown with θ_L' = 0 and θ_L = θ(1).  Continuation in log10 α from 0.01
    when Newton alone does not converge.  Returns a BVPResult (rows θ, κ, x,
    y, θ_L)."""
    beta = float(extensibility)

    def f(s, Y, g):
        a = 10.0 ** g
        th, ka, x, y, thL = Y
        fx, fy = (np.sin(thL), -np.cos(thL)) if follower else (0.0 * th, -1.0 + 0.0 * th)
        ft = fx * np.cos(th) + fy * np.sin(th)         # along the tangent
        cross = np.cos(th) * fy - np.sin(th) * fx       # (t x f)_z
        stretch = 1.0 + a * beta * ft
        return np.array([ka, -a * stretch * cross, stretch * np.cos(th), stretch * np.sin(th),
                         0.0 * th])

    def bc(ya, yb, *_):
        return np.array([ya[0], ya[2], ya[3], yb[1], yb[4] - yb[0]])

    mesh = np.linspace(0.0, 1.0, nodes)
    g = np.log10(alpha)
    res = bvp.solve(lambda s, Y: f(s, Y, g), bc, mesh, np.zeros(5), tol=tol)
    if res.ok:
        return res
    path = bvp.continuation(f, bc, mesh, np.zeros(5), (-2.0, g), ds=0.2, ds_max=1.0)
    if path.status != "solved":
        return bvp.BVPResult(mesh, path.ys[-1], path.status, False, path.message, np.inf, np.inf, 2, 0)
    return bvp.solve(lambda s, Y: f(s, Y, g), bc, mesh, path.ys[-1], tol=tol)


# -- the spatial rod (statics) ----------------------------------------------------------

def qmul(p, q):
    """Quaternion product, arrays (4, N): (w, x, y, z)."""
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return np.array([pw * qw - px * qx - py * qy - pz * qz,
                     pw * qx + px * qw + py * qz - pz * qy,
                     pw * qy - px * qz + py * qw + pz * qx,
                     pw * qz + px * qy - py * qx + pz * qw])


def rotate(q, v):
    """R(q) v for quaternions q (4, N) and vectors v (3, N)."""
    w, x, y, z = q
    R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                  [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                  [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
    return np.einsum("ijn,jn->in", R, v)


def rotate_T(q, v):
    """R(q)' v."""
    conj = q * np.array([1.0, -1.0, -1.0, -1.0])[:, None]
    return rotate(conj, v)


def spatial_f(Y, Binv):
    """Right-hand side of the spatial rod's statics (rows r, q, n, m), n' = 0."""
    N = Y.shape[1]
    q, n, m = Y[3:7], Y[7:10], Y[10:13]
    t = rotate(q, np.repeat(np.array([[1.0], [0.0], [0.0]]), N, axis=1))
    kappa = Binv * rotate_T(q, m)
    dq = 0.5 * qmul(q, np.vstack([np.zeros(N), kappa]))
    dm = -np.cross(t.T, n.T).T
    return np.vstack([t, dq, np.zeros((3, N)), dm])


def spatial_cantilever(force=(0.0, 0.0, 0.0), moment=(0.0, 0.0, 0.0), *, torsion_ratio: float = 1.0,
                       nodes: int = 81, tol: float = 1e-8, steps: int = 20):
    """A spatial, inextensible and unshearable Kirchhoff rod clamped at s = 0
    along x, loaded at its free end by a dead ``force`` and ``moment`` (units:
    force x L²/EI, moment x L/EI, i.e. nondimensional), ``torsion_ratio`` =
    GJ/EI.  Unknowns (13): position r, orientation quaternion q (body axis 1 =
    the tangent), internal force n and moment m (global frame)::

        r' = R(q) e1,   q' = ½ q ⊗ (0, κ),   κ = B⁻¹ R(q)' m,   n' = 0,   m' = -r' × n,

    B = diag(GJ/EI, 1, 1).  The rod paper uses 12 unknowns with three finite-rotation
    parameters; the quaternion (norm kept by the equations) avoids their
    singularity and keeps the right-hand side polynomial.  The load is applied
    in ``steps`` increments (natural-parameter continuation).  Returns a
    BVPResult with rows (r, q, n, m)."""
    F = np.asarray(force, float)
    Mo = np.asarray(moment, float)
    Binv = np.array([1.0 / torsion_ratio, 1.0, 1.0])[:, None]

    def fun_for(lam):
        def f(s, Y):
            return spatial_f(Y, Binv)

        def bc(ya, yb):
            return np.concatenate([ya[0:3], ya[3:7] - np.array([1.0, 0, 0, 0]),
                                   yb[7:10] - lam * F, yb[10:13] - lam * Mo])
        return f, bc

    mesh = np.linspace(0.0, 1.0, nodes)
    Y = np.zeros((13, nodes))
    Y[0] = mesh
    Y[3] = 1.0
    # intermediate load steps on the base mesh (no refinement: they only feed the
    # next step's initial guess); the full load is solved to ``tol``
    for lam in np.linspace(0.0, 1.0, steps + 1)[1:-1]:
        f, bc = fun_for(lam)
        res = bvp.solve(f, bc, mesh, Y, tol=1e-6, corrections=0, max_refinements=0)
        if not res.residual <= 1e-8 * max(1.0, float(np.max(np.abs(res.y)))):  # Newton failed
            res.message = f"load step {lam:.3g}: {res.message}"
            return res
        Y = res.y
    f, bc = fun_for(1.0)
    return bvp.solve(f, bc, mesh, Y, tol=tol)
