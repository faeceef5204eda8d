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
