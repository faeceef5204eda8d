"""Frames the frame tests share: built here once, imported by the test
modules that use them (never from one test module into another)."""

from __future__ import annotations

import numpy as np

from formulations.frames import Frame
from formulations.frames.plane import plane_examples


def tower(storeys, bays=2):
    """bays + 1 columns 6 m apart, `storeys` x 3.5 m, 30 kN/m on every beam, a
    foundation beam from x = -3 to 6 bays + 3 on elastic frictional contacts
    (f = 0.5, k = 5e5) every 1.5 m, 10 kN x p at every floor of the left
    column (:func:`formulations.frames.plane.plane_examples.tower`;
    :func:`three_bay_tower` is its 3-bay, 20-storey case)."""
    return plane_examples.tower(storeys, bays)


def three_bay_tower(storeys=20):
    """Four columns 6 m apart (3 bays), storeys x 3.5 m, 30 kN/m on every beam;
    a foundation beam x = -3 .. 21 on elastic frictional contacts (f = 0.5,
    k = 5e5) every 1.5 m; 10 kN x p at every floor of the left column."""
    return tower(storeys, bays=3)


def beam_on_supports(spans, every=10, P=250.0):
    """6 m spans, E = 30e6, A = 0.32, I = 1e-4, pinned (ux) at the left end,
    rigid unilateral supports at every node; weight 18 kN/m (constant) and
    P x p at midspan of every `every`-th span (variable)."""
    fr = Frame()
    for k in range(spans + 1):
        fr.add_node(f"N{k}", 6.0 * k, 0.0)
    for k in range(spans):
        fr.add_member(f"N{k}", f"N{k + 1}", 30e6, 0.32, 1e-4, name=f"M{k}")
        fr.add_distributed_load(f"M{k}", wy=-(25.0 * 0.32 + 10.0))
    fr.add_support("N0", fix=("ux",))
    for k in range(spans + 1):
        fr.add_contact(f"N{k}", normal=(0.0, 1.0))
    for k in range(every // 2, spans, every):
        fr.add_point_load(f"M{k}", 3.0, fy=-P, case="variable")
    return fr


# --- an independent plain beam code (Euler-Bernoulli, transverse dofs only) ----------
def beam_solve(xs, EI, w, point_loads, held):
    """Continuous beam on the x axis, uniform load w (per length, +up) and point
    loads {node: fy}; nodes in ``held`` have v = 0.  Returns (v, reactions)."""
    n = len(xs)
    K = np.zeros((2 * n, 2 * n))
    F = np.zeros(2 * n)
    for e in range(n - 1):
        L = xs[e + 1] - xs[e]
        k = EI / L ** 3 * np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                                    [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]])
        d = [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3]
        K[np.ix_(d, d)] += k
        F[d] += w * np.array([L / 2, L * L / 12, L / 2, -L * L / 12])
    for node, fy in point_loads.items():
        F[2 * node] += fy
    fixed = [2 * i for i in held]
    free = [i for i in range(2 * n) if i not in fixed]
    u = np.zeros(2 * n)
    u[free] = np.linalg.solve(K[np.ix_(free, free)], F[free])
    r = K @ u - F
    return u[0::2], r[0::2]


def frictional_beam(spans, seed, friction=0.3, stiffness=6e4, inclined=False):
    """Two elements per 6 m span on elastic frictional supports (every other
    one tilted by 0.3 rad where ``inclined``; the left end's frictionless,
    pinned in ux), weight 18 kN/m, uplift at a few nodes drawn from
    ``seed``, and a push of 100 kN at the right end."""
    rng = np.random.default_rng(seed)
    fr = Frame()
    n = 2 * spans + 1
    for k in range(n):
        fr.add_node(f"N{k}", 3.0 * k, 0.0)
    for k in range(n - 1):
        fr.add_distributed_load(fr.add_member(f"N{k}", f"N{k + 1}", 30e6, 0.32, 0.017), wy=-18.0)
    fr.add_support("N0", fix=("ux",))
    for k in range(0, n, 2):
        a = 0.3 * (k % 4 == 2) if inclined else 0.0
        fr.add_contact(f"N{k}", normal=(float(np.sin(a)), float(np.cos(a))),
                       friction=friction if k else 0.0, stiffness=stiffness)
    for k in rng.choice(np.arange(1, n - 1), size=max(1, spans // 5), replace=False):
        fr.add_load(f"N{k}", fy=float(rng.uniform(150.0, 300.0)))
    fr.add_load(f"N{n - 1}", fx=-100.0)
    return fr


def stub_cantilever(stiffness=None):
    """A 10 m cantilever (E = 30e6, A = 0.3, I = 0.02, ten 1 m members,
    clamped at N0) ending in a 1 cm stub to T, on a contact at T (rigid, or
    elastic of ``stiffness``), 10 kN down at T, straight into the contact."""
    fr = Frame()
    for k in range(11):
        fr.add_node(f"N{k}", float(k), 0.0)
    fr.add_node("T", 10.01, 0.0)
    for k in range(10):
        fr.add_member(f"N{k}", f"N{k + 1}", 30e6, 0.3, 0.02)
    fr.add_member("N10", "T", 30e6, 0.3, 0.02)
    fr.add_support("N0")
    fr.add_contact("T", stiffness=stiffness)
    fr.add_load("T", fy=-10.0)
    return fr


def random_beam(seed):
    """A random beam on elastic contacts (20–120 spans of 2–5 m, hinges,
    Timoshenko members, tilted and frictional contacts, gaps, and in two
    of five a second beam resting on it through paired contacts), as the
    stress runs of the frames' routes draw them; seed 36 (117 contacts) is
    one where the active set and Lemke find nothing and the load path's
    collapse proof branches for minutes."""
    rng = np.random.default_rng(seed)
    fr = Frame()
    spans = int(rng.integers(20, 120))
    n = 2 * spans + 1
    L = rng.uniform(2.0, 5.0)
    for k in range(n):
        fr.add_node(f"A{k}", L * k, 0.0)
    twin = rng.random() < 0.4
    if twin:
        for k in range(n):
            fr.add_node(f"B{k}", L * k, 1.0)
    E = 30e6 if rng.random() < 0.5 else 2.1e8
    for k in range(n - 1):
        m = fr.add_member(f"A{k}", f"A{k + 1}", E, rng.uniform(0.01, 0.4),
                          rng.uniform(1e-4, 0.05), hinge_i=bool(rng.random() < 0.05),
                          **({"G": E / 2.5, "shear_area": 0.1} if rng.random() < 0.2 else {}))
        fr.add_distributed_load(m, wy=-rng.uniform(5, 30))
        if twin:
            fr.add_member(f"B{k}", f"B{k + 1}", E, 0.2, 0.01)
    fr.add_support("A0", fix=("ux",))
    if twin:
        fr.add_support(f"B{n - 1}", fix=("ux",))
    kbase = 10 ** rng.uniform(3, 6)
    for k in range(0, n, int(rng.integers(1, 4))):
        a = rng.uniform(-0.4, 0.4) if rng.random() < 0.3 else 0.0
        f = float(rng.choice([0.0, 0.2, 0.5]))
        fr.add_contact(f"A{k}", normal=(float(np.sin(a)), float(np.cos(a))),
                       friction=f if k else 0.0, stiffness=kbase * rng.uniform(0.5, 2),
                       gap=float(rng.choice([0.0, 0.0, 1e-3])))
        if twin and k % 4 == 0:
            fr.add_contact(f"B{k}", normal=(0.0, 1.0), other=f"A{k}", friction=0.3,
                           stiffness=kbase)
            fr.add_load(f"B{k}", fy=-rng.uniform(10, 100))
    for k in rng.choice(np.arange(1, n - 1), size=max(1, spans // 5), replace=False):
        fr.add_load(f"A{k}", fy=float(rng.uniform(50.0, 400.0)))
    fr.add_load(f"A{n - 1}", fx=-rng.uniform(0, 200))
    return fr
