"""The MITC4 plate element against independent references: the constant-
curvature patch test on a distorted mesh (exact to rounding), the simply
supported square plate under uniform load against Navier's double series
(with Mindlin's shear correction), its thin limit (no locking at t/a = 1e-3),
and the clamped square plate against Timoshenko's 0.00126 q a⁴ / D."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from formulations.plates import PlateMesh, Raft, rigidity
from formulations.plates.assembly import assemble_stiffness, element_dofs
from formulations.plates.element import SHEAR_FACTOR, resultants


def _navier(a, q, D, nu, terms=401):
    """Centre deflection and mx of the simply supported Kirchhoff plate
    (Timoshenko & Woinowsky-Krieger §30), summed in the test."""
    m = np.arange(1, terms, 2)[:, None]
    n = np.arange(1, terms, 2)[None, :]
    sign = (-1.0) ** ((m + n) // 2 - 1)
    amn = 16 * q / (np.pi ** 6 * m * n * D * ((m / a) ** 2 + (n / a) ** 2) ** 2)
    w = np.sum(amn * sign)
    mx = np.sum(amn * sign * D * np.pi ** 2 * ((m / a) ** 2 + nu * (n / a) ** 2))
    my = np.sum(amn * sign * D * np.pi ** 2 * ((n / a) ** 2 + nu * (m / a) ** 2))
    return w, mx, my


def _square(N, t, edges, a=1.0, E=1e7, nu=0.3, q=1.0):
    raft = Raft(a, a, thickness=t, E=E, nu=nu, cells=(N, N))
    on_x = lambda x, y: np.isclose(x, 0) | np.isclose(x, a)          # noqa: E731
    on_y = lambda x, y: np.isclose(y, 0) | np.isclose(y, a)          # noqa: E731
    if edges == "simply supported":     # hard: w and the tangential slope held
        raft.add_support(lambda x, y: on_x(x, y) | on_y(x, y), fix=("w",))
        raft.add_support(on_x, fix=("theta_y",))
        raft.add_support(on_y, fix=("theta_x",))
    else:
        raft.add_support(lambda x, y: on_x(x, y) | on_y(x, y), fix=("w", "theta_x", "theta_y"))
    raft.add_area_load(q)
    res = raft.solve()
    assert res.ok, res.message
    centre = res.mesh.nearest_node(a / 2, a / 2)
    around = np.flatnonzero((res.mesh.elements == centre).any(axis=1))
    return res.w[centre], res.moments[around, 0].mean(), raft.D


def test_constant_curvature_patch_on_a_distorted_mesh():
    """w = quadratic, θ = ∇w: every node of a distorted patch but the inner
    ones prescribed; the inner ones come out exact and the moments constant."""
    nodes = np.array([[0, 0], [2, 0], [2, 3], [0, 3],                    # the outline
                      [0.4, 0.4], [1.4, 0.3], [1.6, 2.1], [0.3, 2.4]])   # inner, distorted
    elements = np.array([[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7], [4, 5, 6, 7]])
    mesh = PlateMesh(nodes, elements)
    E, nu, t = 2.1e5, 0.3, 0.05
    a, b, c, d0, d1, d2 = 1e-3, -2e-3, 1.5e-3, 0.1, 0.02, -0.03

    def exact(x, y):
        return np.stack([d0 + d1 * x + d2 * y + a * x * x + b * y * y + c * x * y,
                         d1 + 2 * a * x + c * y, d2 + 2 * b * y + c * x], axis=1).ravel()

    K = assemble_stiffness(mesh, E, nu, t)
    u_exact = exact(nodes[:, 0], nodes[:, 1])
    inner = np.arange(12, 24)
    outer = np.arange(12)
    u = u_exact.copy()
    u[inner] = spla.spsolve(K[inner][:, inner].tocsc(), -K[inner][:, outer] @ u_exact[outer])
    assert np.max(np.abs(u - u_exact)) <= 1e-11 * np.max(np.abs(u_exact))
    D = rigidity(E, t, nu)
    kappa = np.array([2 * a, 2 * b, 2 * c])       # (w,xx, w,yy, 2 w,xy)
    m_exact = -D * np.array([kappa[0] + nu * kappa[1], kappa[1] + nu * kappa[0],
                             0.5 * (1 - nu) * kappa[2]])
    for xi, eta in ((0, 0), (0.577, -0.577), (-0.9, 0.3)):
        m, q = resultants(mesh.corners, u[element_dofs(mesh.elements)], E, nu, t, xi, eta)
        assert np.allclose(m, m_exact, rtol=0, atol=1e-10 * np.abs(m_exact).max())
        assert np.max(np.abs(q)) <= 1e-9 * np.abs(m_exact).max()


def test_simply_supported_plate_converges_to_navier():
    a, q, E, nu, t = 1.0, 1.0, 1e7, 0.3, 0.01
    D = rigidity(E, t, nu)
    wK, mx, my = _navier(a, q, D, nu)
    # Mindlin's plate: w = w_Kirchhoff + M / (κ G t), M = (mx + my)/(1 + ν) (Marcus' moment sum)
    G = E / (2 * (1 + nu))
    w_ref = wK + (mx + my) / (1 + nu) / (SHEAR_FACTOR * G * t)
    errors = []
    for N in (8, 16, 32):
        w, m, _ = _square(N, t, "simply supported")
        errors.append((abs(w / w_ref - 1), abs(m / mx - 1)))
    assert errors[0][0] > errors[1][0] > errors[2][0] and errors[0][1] > errors[1][1] > errors[2][1]
    assert errors[2][0] < 5e-4 and errors[2][1] < 5e-3, errors
    # second order: halving h quarters the error (measured 4.07, 4.02 on w)
    assert 3.5 < errors[1][0] / errors[2][0] < 4.5 and 3.5 < errors[1][1] / errors[2][1] < 4.5
    assert abs(wK * D / (q * a ** 4) - 0.00406) < 1e-5        # the series is Timoshenko's 0.00406


def test_no_shear_locking_in_the_thin_limit():
    """t/a = 1e-3 on a 16 x 16 mesh: as close to Kirchhoff's plate as t/a = 1e-2."""
    wK, _, _ = _navier(1.0, 1.0, 1.0, 0.3)
    thin, _, D = _square(16, 1e-3, "simply supported")
    assert abs(thin * D / wK - 1) < 2e-3


def test_clamped_plate_against_timoshenko():
    w, m, D = _square(24, 1e-3, "clamped")
    assert abs(w * D / 0.00126 - 1) < 0.01                      # Timoshenko's table 35: 0.00126 q a⁴/D
    assert abs(m / 0.0231 - 1) < 0.03                           # and mx = 0.0231 q a² at the centre
