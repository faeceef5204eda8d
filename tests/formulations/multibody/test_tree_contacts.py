"""Spatial trees with contacts and loops (formulations.multibody.contacts),
through their scene files.  References: statics worked out by hand, the
closed-form decay of the explicit damping update, the coupled mass of a loop."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from qpcontact.scenes import SceneError, parse_scene
from tests.helpers.paths import SCENES

EXAMPLES = SCENES
G = 9.81

# a 2 kg plate on a free joint, three legs 50 mm below its origin, its centre of
# mass off-centre; released with the legs 1 mm above the floor
LEGS = np.array([[0.10, 0.0], [-0.05, 0.0866], [-0.05, -0.0866]])
COM = np.array([0.02, -0.01])
TRIPOD = """formulation = "multibody"
effects = ["gravity"]

[[bodies]]
name = "plate"
joint = "free"
mass = 2.0
com = [0.02, -0.01, 0.0]
inertia = [0.01, 0.01, 0.02]
q = [0.0, 0.0, 0.051, 0.0, 0.0, 0.0, 1.0]
""" + "".join(f"""
[[contacts]]
name = "leg {k}"
b = "plate"
point_b = [{x}, {y}, -0.05]
""" for k, (x, y) in enumerate(LEGS)) + """
[time]
h = 1e-3
steps = 150
restitution = 0.0

[solver]
route = "{route}"
"""


# the penalty route takes ~10 s of stepping (make test-all); the LCP route stays here
@pytest.mark.parametrize("route", [pytest.param("penalty", marks=pytest.mark.slow), "lcp"])
def test_tripod_falls_freely_then_rests_on_the_statics_reactions(route):
    """Free fall z = z0 - g t²/2 (the step is exact for constant acceleration)
    until the legs touch; at rest the three reactions are the statics
    solution: ΣR = mg and the moments about the centre of mass vanish."""
    scene = parse_scene(TRIPOD.replace("{route}", route))
    tree, run = scene.schema.build(scene)
    res = run()
    t = res.t
    before = t < np.sqrt(2 * 0.001 / G) - 2e-3
    np.testing.assert_allclose(res.q[before, 2], 0.051 - 0.5 * G * t[before] ** 2, rtol=0,
                               atol=1e-14)
    statics = np.vstack([np.ones(3), LEGS[:, 0] - COM[0], LEGS[:, 1] - COM[1]])
    R = np.linalg.solve(statics, [2.0 * G, 0.0, 0.0])
    assert np.all(R > 0)
    np.testing.assert_allclose(res.reactions[-1], R, rtol=1e-6)
    assert np.all(res.gaps[-1] > -1e-9) and np.max(res.certificate_error) < 1e-9


def test_joint_damping_decays_a_spin_by_the_update_formula():
    """A body spinning about a revolute z axis (I_zz = 0.5 kg·m², c = 0.2
    N·m·s/rad, no gravity): ν_n = ν_0 (1 - h c / I)^n exactly."""
    scene = parse_scene('formulation = "multibody"\neffects = ["joint_damping"]\n'
                        '[[bodies]]\nname = "wheel"\njoint = "revolute"\naxes = ["z"]\n'
                        'mass = 1.0\ninertia = [0.3, 0.3, 0.5]\nv = [3.0]\ndamping = 0.2\n'
                        '[time]\nh = 1e-3\nsteps = 40\n')
    _, run = scene.schema.build(scene)
    res = run()
    np.testing.assert_allclose(res.v[:, 0], 3.0 * (1 - 1e-3 * 0.2 / 0.5) ** np.arange(41),
                               rtol=1e-12)


STACK = """formulation = "multibody"
effects = ["gravity", "loops"]

[effect.loops]
alpha = 10.0
beta = 10.0

[[bodies]]
name = "top"
joint = "prismatic"
axes = ["z"]
mass = 1.0
q = [0.5]

[[bodies]]
name = "foot"
joint = "prismatic"
axes = ["z"]
mass = 3.0
q = [0.2]

[[loops]]           # top's origin sits 0.3 m above base's origin
a = "top"
b = "foot"
point_b = [0.0, 0.0, 0.3]
axes = ["z"]

[[contacts]]
name = "foot/floor"
b = "foot"
point_b = [0.0, 0.0, -0.2]

[time]
h = 1e-3
steps = 30
"""


def test_a_loop_carries_the_top_body_onto_the_base_contact():
    """Two bodies on vertical slides tied by a loop: the contact under the base
    sees the coupled mass (A = J P J' = 1/(1 + 3) kg⁻¹: the loop is eliminated
    inside the step, not given unknowns) and carries both weights, 4 g; the
    loop stays closed."""
    scene = parse_scene(STACK)
    tree, run = scene.schema.build(scene)
    q0, v0 = tree.initial_state()
    step, Phi, a0 = tree.step_problem(0.0, q0, v0, 1e-3)
    assert step.nu == 1 and step.A.shape == (1, 1)
    np.testing.assert_allclose(step.A[0, 0], 1 / 4.0, rtol=1e-12)
    res = run()
    np.testing.assert_allclose(res.reactions[1:, 0], 4.0 * G, rtol=1e-7)
    assert max(tree.loop_residual(q) for q in res.q) < 1e-12


def test_tree_effects_are_assembled_only_when_named():
    """Without "gravity" the model's g is zero; without "compliance" the step's
    contacts are rigid (C = None), with it C = c I; without "loops" the step's
    G is the O(N) mass operator itself; loops, damping or compliance data
    without their effect are errors at their line."""
    from formulations.multibody.algorithms import MassOperator

    bare = parse_scene(STACK.replace('effects = ["gravity", "loops"]', 'effects = ["loops"]'))
    tree, _ = bare.schema.build(bare)
    assert np.all(tree.model.gravity == 0)
    soft = parse_scene(TRIPOD.replace("{route}", "penalty").replace(
        'effects = ["gravity"]', 'effects = ["compliance"]\n[effect.compliance]\ncompliance = 1e-6'))
    tree, _ = soft.schema.build(soft)
    q0, v0 = tree.initial_state()
    step, _, a0 = tree.step_problem(0.0, q0, v0, 1e-3)
    assert isinstance(step.G, MassOperator) and a0 == 0.0
    np.testing.assert_array_equal(step.C, 1e-6 * np.eye(3))
    rigid = parse_scene(TRIPOD.replace("{route}", "penalty"))
    tree, _ = rigid.schema.build(rigid)
    assert tree.step_problem(0.0, *tree.initial_state(), 1e-3)[0].rigid

    no_loops = STACK.replace('effects = ["gravity", "loops"]', 'effects = ["gravity"]').replace(
        "[effect.loops]\nalpha = 10.0\nbeta = 10.0\n", "")
    scene = parse_scene(no_loops, "s.toml")
    with pytest.raises(SceneError, match="'loops' is not among the effects") as info:
        scene.schema.build(scene)
    line = next(n for n, ln in enumerate(no_loops.splitlines(), 1) if ln.startswith("[[loops]]"))
    assert str(info.value).startswith(f"s.toml:{line}: ")
    damped = TRIPOD.replace("{route}", "penalty").replace("mass = 2.0", "mass = 2.0\ndamping = 0.1")
    scene = parse_scene(damped, "d.toml")
    with pytest.raises(SceneError, match="'joint_damping' is not among the effects") as info:
        scene.schema.build(scene)
    line = next(n for n, ln in enumerate(damped.splitlines(), 1) if ln.startswith("damping"))
    assert str(info.value).startswith(f"d.toml:{line}: ")


@pytest.mark.parametrize("edit, needle, message", [
    (('joint = "free"', 'joint = "hinge"'), 'joint = "hinge"',
     "unknown joint 'hinge'; choose one of revolute, prismatic, cardan, spherical, free"),
    (('joint = "free"', 'joint = "revolute"'), 'joint = "revolute"', None),
    (("q = [0.0, 0.0, 0.051, 0.0, 0.0, 0.0, 1.0]", "q = [0.0, 0.051]"), "name = \"plate\"",
     "its free joint takes 7 coordinates and 6 velocities; got 2 and 6"),
])
def test_tree_scene_errors_point_at_the_body(edit, needle, message):
    text = TRIPOD.replace("{route}", "penalty").replace(*edit)
    scene = parse_scene(text, "t.toml")
    with pytest.raises(SceneError) as info:
        scene.schema.build(scene)
    line = next(n for n, ln in enumerate(text.splitlines(), 1) if needle in ln)
    if message is None:       # a revolute joint without its axis: the axes line is absent,
        message = "a revolute joint takes 1 axes among x, y, z; got []"   # the table's
        line = next(n for n, ln in enumerate(text.splitlines(), 1) if ln == "[[bodies]]")
    assert str(info.value).startswith(f"t.toml:{line}: ")
    assert message in str(info.value)


@pytest.mark.slow
def test_chain_example_runs_writes_and_plots(tmp_path):
    """examples/scenes/chain.toml (shortened): the results file holds the
    energy, the per-step certificate and the reactions; plot draws from it."""
    import h5py

    from qpcontact.scenes import plot_results, vary_scene, write_results

    text = vary_scene((EXAMPLES / "chain.toml").read_text(), "time.steps", "80")
    scene = parse_scene(text, "chain.toml")
    tree, run = scene.schema.build(scene)
    res = run()
    path = write_results(scene, res, tmp_path / "chain.h5", completed=80, total=80)
    with h5py.File(path) as h:
        assert h.attrs["formulation"] == "multibody"
        E = h["energy/kinetic"][()] + h["energy/potential"][()]
        # released from rest: damping only removes energy before any impact
        assert np.all(np.diff(E) <= 1e-9 * abs(E[0]))
        assert h["certificate_error"].shape == (81,)
    figs = plot_results(path, tmp_path / "figs")
    assert {Path(f).name for f in figs} == {"motion.png", "energy.png"}


def test_loop_elimination_equals_the_dense_kkt_solve():
    """A slider-crank (two revolute links whose tip is held on the line x = 0.25
    by a loop), moving: the step's a = P(Q + J'λ) + a₀ equals the dense
    saddle-point solve [G -J_c'; J_c 0][a; σ] = [Q + J'λ; r_c] with G from the
    composite-rigid-body recursion, for a given λ, and meets J_c a = r_c."""
    from formulations.multibody import Revolute
    from formulations.multibody import algorithms as alg
    from formulations.multibody import constraints as con
    from formulations.multibody.contacts import ContactTree, contact_rows

    tree = ContactTree(effects=("gravity", "loops"), alpha=5.0, beta=7.0)
    tree.add_body("crank", Revolute("y"), mass=1.0, com=(0.05, 0, 0), inertia=(1e-3, 2e-3, 2e-3),
                  q=[-0.6], v=[2.0])
    tree.add_body("rod", Revolute("y"), parent="crank", placement=(0.1, 0, 0), mass=0.5,
                  com=(0.1, 0, 0), inertia=(1e-3, 3e-3, 3e-3), q=[1.2])
    tree.add_loop("rod", (0.2, 0, 0), None, (0.25, 0, 0), axes=(0,))
    tree.add_contact("tip/floor", None, "rod", point_b=(0.2, 0, 0), offset=-1.0)
    q, v = tree.initial_state()
    assert abs(v[0]) > 0 and tree.loop_residual(q) < 1e-12
    step, Phi, a0 = tree.step_problem(0.0, q, v, 1e-3)
    lam = np.array([3.7])
    a = step.accelerations(lam) + a0

    data = alg.Data(tree.model)
    Gd = alg.mass_matrix(tree.model, data, q)
    Phic, Jc, Jcd = con.loop_jacobian(tree.model, data, q, v, tree.loops)
    rc = -Jcd @ v - 2 * 5.0 * (Jc @ v) - 7.0 ** 2 * Phic
    m = Jc.shape[0]
    K = np.block([[Gd, -Jc.T], [Jc, np.zeros((m, m))]])
    rhs = np.concatenate([tree.generalized_forces(0.0, q, v) + step.J.T @ lam, rc])
    a_ref = np.linalg.solve(K, rhs)[:2]
    np.testing.assert_allclose(a, a_ref, rtol=1e-10, atol=1e-12 * np.abs(a_ref).max())
    np.testing.assert_allclose(Jc @ a, rc, atol=1e-10 * max(1.0, np.abs(rc).max()))
    # the LCP's w = Aλ + b is the contact's look-ahead acceleration Φ̈ + B at that a
    _, Jn, Dn = contact_rows(tree.model, data, tree.contacts, q, v)
    w_ref = Jn @ a_ref + Dn + step.B
    np.testing.assert_allclose(step.A @ lam + step.b, w_ref, rtol=1e-10)
    assert np.abs(a0).max() > 1e-3          # the loop's own acceleration is not negligible here
