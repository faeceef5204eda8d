"""Tree-structured multibody dynamics (Ivanov & Shimanovsky 2017): references
are analytic solutions, invariants, finite differences of the model's own
definitions, and Pinocchio."""

import numpy as np
import pytest
from scipy.special import ellipk

from formulations import multibody as mb
from formulations.multibody.demo import four_bar
from qpcontact.core.errors import InvalidOptionError, InvalidProblemError, SolverFailedError

G0 = 9.81


def pendulum(length=0.7, mass=1.3):
    m = mb.Model(gravity=(0.0, -G0, 0.0))
    m.add_body("bob", 0, mb.Revolute("z"), mass=mass, com=(length, 0.0, 0.0), inertia=np.zeros(3))
    return m


@pytest.mark.parametrize("amplitude", [0.1, 2.0])
def test_pendulum_half_and_full_period_match_the_elliptic_integral(amplitude):
    L = 0.7
    m = pendulum(L)
    period = 4 * np.sqrt(L / G0) * ellipk(np.sin(amplitude / 2) ** 2)
    q0 = np.array([-np.pi / 2 + amplitude])
    tr = mb.simulate(m, q0, [0.0], period, rtol=1e-12, atol=1e-13, samples=3)
    assert tr.ok
    assert abs(tr.q[1, 0] - (-np.pi / 2 - amplitude)) < 1e-8      # far turning point at T/2
    assert abs(tr.v[1, 0]) < 1e-7
    assert abs(tr.q[2, 0] - q0[0]) < 1e-8 and abs(tr.v[2, 0]) < 1e-7
    assert np.ptp(tr.energy) < 1e-9 * 1.3 * G0 * L


def double_pendulum(l1=0.5, l2=0.8, m1=1.0, m2=2.0):
    m = mb.Model(gravity=(0.0, -G0, 0.0))
    m.add_body("upper", 0, mb.Revolute("z"), mass=m1, com=(l1, 0, 0), inertia=np.zeros(3))
    m.add_body("lower", 1, mb.Revolute("z"), placement=(l1, 0, 0), mass=m2, com=(l2, 0, 0),
               inertia=np.zeros(3))
    return m


def test_double_pendulum_mass_matrix_and_bias_are_the_textbook_ones():
    l1, l2, m1, m2 = 0.5, 0.8, 1.0, 2.0
    m = double_pendulum(l1, l2, m1, m2)
    d = mb.Data(m)
    th1, th2, w1, w2 = 0.4, -1.1, 0.7, -2.3
    c = np.cos(th2)
    G_exact = np.array([[m1 * l1 ** 2 + m2 * (l1 ** 2 + l2 ** 2 + 2 * l1 * l2 * c), m2 * (l2 ** 2 + l1 * l2 * c)],
                        [m2 * (l2 ** 2 + l1 * l2 * c), m2 * l2 ** 2]])
    np.testing.assert_allclose(mb.mass_matrix(m, d, [th1, th2]), G_exact, rtol=1e-14, atol=1e-14)
    # Coriolis/centrifugal + gravity, relative angles (Spong's form)
    hh = -m2 * l1 * l2 * np.sin(th2)
    g1 = (m1 + m2) * G0 * l1 * np.cos(th1) + m2 * G0 * l2 * np.cos(th1 + th2)
    g2 = m2 * G0 * l2 * np.cos(th1 + th2)
    c_exact = np.array([hh * (2 * w1 * w2 + w2 ** 2) + g1, -hh * w1 ** 2 + g2])
    np.testing.assert_allclose(mb.nonlinear_effects(m, d, [th1, th2], [w1, w2]), c_exact, rtol=1e-13)


def test_momentum_and_lagrange_forms_agree_and_conserve_energy():
    m = double_pendulum()
    q0, v0 = np.array([0.3, 1.2]), np.array([2.0, -1.0])
    runs = {form: mb.simulate(m, q0, v0, 3.0, form=form, rtol=1e-11, atol=1e-12, samples=31)
            for form in mb.FORMS}
    sweep = mb.simulate(m, q0, v0, 3.0, method="sweep", rtol=1e-11, atol=1e-12, samples=31)
    for tr in (*runs.values(), sweep):
        assert tr.ok and np.ptp(tr.energy) < 1e-8 * np.abs(tr.energy).max()
    np.testing.assert_allclose(runs["momentum"].q, runs["lagrange"].q, atol=1e-7)
    np.testing.assert_allclose(runs["momentum"].q, sweep.q, atol=1e-9)


def random_tree(N, rng, kinds=("rev",), tree=True):
    """Random chain or tree in depth-first order (Pinocchio needs it), random
    joint placements, masses, centres and inertias."""
    m = mb.Model(gravity=(0.0, 0.0, -G0))
    spec = []
    path = [0]                      # ancestors of the last body: DFS order keeps subtrees contiguous
    for i in range(1, N + 1):
        if tree:
            path = path[: int(rng.integers(1, len(path) + 1))]
        par = path[-1]
        A = rng.standard_normal((3, 3))
        R0, _ = np.linalg.qr(A)
        R0 *= np.sign(np.linalg.det(R0))
        r0 = 0.3 * rng.standard_normal(3)
        B = rng.standard_normal((3, 3))
        inertia = 0.01 * (B @ B.T + np.eye(3))
        mass, com = rng.uniform(0.5, 2.0), 0.1 * rng.standard_normal(3)
        kind = kinds[i % len(kinds)]
        ax = rng.standard_normal(3)
        ax /= np.linalg.norm(ax)
        joint = {"rev": mb.Revolute(ax), "pri": mb.Prismatic(ax), "sph": mb.Spherical(),
                 "free": mb.Free()}[kind]
        m.add_body(f"b{i}", par, joint, placement=r0, rotation=R0, mass=mass, com=com, inertia=inertia)
        spec.append((par, kind, ax, R0, r0, mass, com, inertia))
        path.append(i)
    return m, spec


def random_state(m, rng):
    q = m.neutral()
    a = m.arrays
    for i in range(1, m.nbodies + 1):
        s, jt = a["iq"][i], a["jtype"][i]
        if jt in (mb._kernels.SPHERICAL, mb._kernels.FREE):
            o = 3 if jt == mb._kernels.FREE else 0
            quat = rng.standard_normal(4)
            q[s + o:s + o + 4] = quat / np.linalg.norm(quat)
            q[s:s + o] = rng.standard_normal(o)
        else:
            q[s] = rng.uniform(-1, 1)
    return q, rng.standard_normal(m.nv)


@pytest.mark.parametrize("kinds", [("rev",), ("rev", "pri", "sph", "free")])
@pytest.mark.parametrize("tree", [False, True])
def test_sweep_and_ldlt_invert_the_momenta_map(kinds, tree):
    rng = np.random.default_rng(3)
    m, _ = random_tree(25, rng, kinds, tree)
    d = mb.Data(m)
    q, v = random_state(m, rng)
    G = mb.mass_matrix(m, d, q)
    p = mb.momenta(m, d, q, v)
    np.testing.assert_allclose(p, G @ v, rtol=1e-12, atol=1e-12 * np.abs(p).max())
    bound = 1e-15 * np.linalg.cond(G) * np.abs(v).max() * 100
    for method in mb.METHODS:
        err = np.abs(mb.velocities_from_momenta(m, d, q, p, method=method) - v).max()
        assert err < bound, (method, err, bound)


def test_sweep_and_ldlt_stay_accurate_along_a_long_ill_conditioned_chain():
    """A 150-body Cardan chain (cond(G) ~ 1e8): both O(N) solvers as accurate as
    a dense Cholesky of G.  A sweep that used Ī' where the elimination needs Ī
    lost everything by N = 40 (errors 1e3), so this is a regression test."""
    from formulations.multibody.demo import cardan_chain

    rng = np.random.default_rng(0)
    m = cardan_chain(150)
    d = mb.Data(m)
    q, v = 0.3 * rng.standard_normal(m.nq), rng.standard_normal(m.nv)
    p = mb.momenta(m, d, q, v)
    G = mb.mass_matrix(m, d, q)
    dense = np.abs(np.linalg.solve(G, p) - v).max()
    for method in mb.METHODS:
        err = np.abs(mb.velocities_from_momenta(m, d, q, p, method=method) - v).max()
        assert err < 10 * max(dense, 1e-14), (method, err, dense)


def test_momentum_rate_is_the_derivative_of_the_momenta_along_the_lagrange_motion():
    rng = np.random.default_rng(4)
    m, _ = random_tree(12, rng, ("rev", "sph", "pri"), tree=True)
    d = mb.Data(m)
    q, v = random_state(m, rng)
    tau = rng.standard_normal(m.nv)
    a = mb.forward_dynamics(m, d, q, v, tau)
    p = mb.momenta(m, d, q, v)
    _, pdot, nu = mb.momentum_rhs(m, d, 0.0, q, p, tau)
    np.testing.assert_allclose(nu, v, atol=1e-12)
    eps = 1e-5        # central difference: error O(eps²) ~ 1e-10
    pp = mb.momenta(m, d, mb.integrate(m, q, eps * v + 0.5 * eps ** 2 * a), v + eps * a)
    pm = mb.momenta(m, d, mb.integrate(m, q, -eps * v + 0.5 * eps ** 2 * a), v - eps * a)
    np.testing.assert_allclose(pdot, (pp - pm) / (2 * eps), rtol=0, atol=1e-7 * np.abs(pdot).max())


def test_free_rigid_body_torque_free_precession_and_invariants():
    I1, I3, w1, w3 = 0.2, 0.5, 0.8, 3.0
    m = mb.Model(gravity=(0.0, 0.0, 0.0))
    m.add_body("top", 0, mb.Free(), mass=2.0, inertia=[I1, I1, I3])
    q0 = m.neutral()
    v0 = np.array([0.1, -0.2, 0.3, w1, 0.0, w3])
    T = 4.0
    tr = mb.simulate(m, q0, v0, T, rtol=1e-12, atol=1e-13, samples=41)
    lam = (I1 - I3) / I1 * w3
    t = tr.t
    np.testing.assert_allclose(tr.v[:, 3], w1 * np.cos(lam * t), atol=1e-8)
    np.testing.assert_allclose(tr.v[:, 4], -w1 * np.sin(lam * t), atol=1e-8)
    np.testing.assert_allclose(tr.v[:, 5], w3, atol=1e-9)
    # world angular momentum R I ω and energy conserved
    d = mb.Data(m)
    Lw = []
    for q, v in zip(tr.q, tr.v):
        mb.forward_kinematics(m, d, q, v)
        Lw.append(d.Ra[1] @ (np.diag([I1, I1, I3]) @ v[3:]))
    assert np.ptp(np.array(Lw), axis=0).max() < 1e-9
    assert np.ptp(tr.energy) < 1e-10
    # the centre (at the origin of the body frame) moves uniformly in the world
    mb.forward_kinematics(m, d, q0, v0)
    v_world = d.Ra[1] @ v0[:3]
    np.testing.assert_allclose(tr.q[-1, :3], T * v_world, atol=1e-8)


def test_asymmetric_free_body_with_gravity_conserves_energy():
    m = mb.Model()
    m.add_body("brick", 0, mb.Free(), mass=3.0, com=(0.05, -0.02, 0.1), inertia=[0.1, 0.2, 0.35])
    tr = mb.simulate(m, m.neutral(), [1.0, 0.0, 2.0, 0.3, 2.0, 0.1], 2.0, rtol=1e-12, atol=1e-13)
    assert np.ptp(tr.energy) < 1e-9 * np.abs(tr.energy).max()


def test_rk4_energy_error_has_order_four():
    m = double_pendulum()
    q0, v0 = np.array([0.3, 1.2]), np.array([2.0, -1.0])
    errs = []
    for h in (2e-3, 1e-3):
        tr = mb.simulate(m, q0, v0, 1.0, integrator="RK4", h=h, samples=11)
        errs.append(np.abs(tr.energy - tr.energy[0]).max())
    order = np.log2(errs[0] / errs[1])
    assert 3.5 < order < 4.5, (errs, order)


@pytest.mark.slow
def test_four_bar_drift_stays_bounded_with_stabilisation():
    m, loops, q, v = four_bar()
    runs = {}
    for name, kw in {"momentum, alpha=20": dict(form="momentum", alpha=20.0),
                     "lagrange, no stabilisation": dict(form="lagrange")}.items():
        runs[name] = mb.simulate(m, q, v, 8.0, loops=loops, rtol=1e-6, atol=1e-8, samples=161, **kw)
    stab = runs["momentum, alpha=20"].constraint
    raw = runs["lagrange, no stabilisation"].constraint
    # stabilised: bounded at the integrator's tolerance level; unstabilised:
    # growing, and far above it (measured 1.5e-4 m at 20 s, docs/multibody.md)
    assert stab[80:].max() < 1e-5
    assert raw[-1] > 2 * raw[80] and raw[-1] > 10 * stab[80:].max()
    # energy is conserved up to what the loose tolerance allows
    assert np.ptp(runs["momentum, alpha=20"].energy) < 1e-3 * np.abs(runs["momentum, alpha=20"].energy).max()


def test_point_jacobian_matches_finite_differences():
    rng = np.random.default_rng(7)
    m, _ = random_tree(8, rng, ("rev", "sph", "pri", "free"), tree=True)
    d = mb.Data(m)
    q, v = random_state(m, rng)
    a = rng.standard_normal(m.nv)
    s = np.array([0.1, -0.2, 0.05])

    def x_at(qq):
        mb.forward_kinematics(m, d, qq)
        return mb.point_position(m, d, 6, s)

    mb.forward_kinematics(m, d, q, v)
    J, Jd = mb.point_jacobian(m, d, 6, s)
    eps = 1e-5
    # along the motion q(t) = q ⊕ (tv + ½t²a): ẋ = Jv and ẍ = Ja + J̇v
    xp = x_at(mb.integrate(m, q, eps * v + 0.5 * eps ** 2 * a))
    xm = x_at(mb.integrate(m, q, -eps * v + 0.5 * eps ** 2 * a))
    x0 = x_at(q)
    np.testing.assert_allclose((xp - xm) / (2 * eps), J @ v, atol=1e-8)
    np.testing.assert_allclose((xp - 2 * x0 + xm) / eps ** 2, J @ a + Jd @ v, atol=2e-4)


def test_bad_input_is_named():
    m = pendulum()
    d = mb.Data(m)
    with pytest.raises(InvalidProblemError, match="q must have shape"):
        mb.mass_matrix(m, d, [0.0, 1.0])
    with pytest.raises(InvalidProblemError, match="non-finite"):
        mb.mass_matrix(m, d, [np.nan])
    with pytest.raises(InvalidProblemError, match="no body named"):
        m.add_body("x", "nobody", mb.Revolute())
    with pytest.raises(InvalidProblemError, match="mass must be > 0"):
        m.add_body("x", 0, mb.Revolute(), mass=0.0)
    with pytest.raises(InvalidProblemError, match="revolute axis"):
        mb.Revolute((0.0, 0.0, 0.0))
    with pytest.raises(InvalidOptionError, match="method must be"):
        mb.velocities_from_momenta(m, d, [0.0], [1.0], method="lu")
    # a joint moving nothing with inertia: named, not a NaN
    m2 = mb.Model()
    m2.add_body("ghost", 0, mb.Revolute("z"), mass=1.0, inertia=np.zeros(3))
    with pytest.raises(SolverFailedError, match="not positive definite"):
        mb.velocities_from_momenta(m2, mb.Data(m2), [0.0], [1.0])


pin = pytest.importorskip("pinocchio", reason="Pinocchio (PyPI 'pin', test extra) not installed")


def _pinocchio_twin(spec):
    pm = pin.Model()
    pm.gravity = pin.Motion(np.array([0.0, 0.0, -G0, 0.0, 0.0, 0.0]))
    ids = [0]
    for par, kind, ax, R0, r0, mass, com, inertia in spec:
        joint = {"rev": lambda: pin.JointModelRevoluteUnaligned(ax),
                 "pri": lambda: pin.JointModelPrismaticUnaligned(ax),
                 "sph": pin.JointModelSpherical, "free": pin.JointModelFreeFlyer}[kind]()
        ids.append(pm.addJoint(ids[par], joint, pin.SE3(R0, r0), f"j{len(ids)}"))
        pm.appendBodyToJoint(ids[-1], pin.Inertia(mass, com, inertia), pin.SE3.Identity())
    return pm


# Pinocchio's Data holds nv³-sized tensors (8 nv³ bytes each: 0.5 GB at nv = 400),
# so the 200-body case is a 1-DOF chain and the trees stay near nv = 200.
@pytest.mark.parametrize("N,kinds,tree", [(10, ("rev",), False), (200, ("rev",), False),
                                          (60, ("rev", "pri", "sph", "free"), True),
                                          (100, ("rev", "sph"), True)])
def test_mass_matrix_and_forward_dynamics_match_pinocchio(N, kinds, tree):
    rng = np.random.default_rng(N)
    m, spec = random_tree(N, rng, kinds, tree)
    pm = _pinocchio_twin(spec)
    pd, d = pm.createData(), mb.Data(m)
    q, v = random_state(m, rng)
    tau = rng.standard_normal(m.nv)
    Gp = pin.crba(pm, pd, q)
    Gp = np.triu(Gp) + np.triu(Gp, 1).T
    G = mb.mass_matrix(m, d, q)
    assert np.abs(G - Gp).max() <= 1e-10 * np.abs(Gp).max()
    ap = pin.aba(pm, pd, q, v, tau)
    a = mb.forward_dynamics(m, d, q, v, tau)
    assert np.abs(a - ap).max() <= 1e-10 * np.abs(ap).max() * max(1.0, np.linalg.cond(G) * 1e-6)
    # the O(N) inverse of G (momentum-form solve) against Pinocchio's G
    r = rng.standard_normal(m.nv)
    x = mb.MassOperator(m, q).solve(r)
    assert np.abs(Gp @ x - r).max() <= 1e-10 * np.abs(r).max() * max(1.0, np.linalg.cond(G) * 1e-6)
