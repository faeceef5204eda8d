"""The 3-D NSGS sweep: the closed-form local problem of a sphere's contact
block diag(a, c, c) against Coulomb's law (r ∈ K, û ∈ K*, r·û = 0) and
against its cases written out; the compiled sweeps on W's 3 x 3 blocks
(closed form, and the fixed point nsgs-newton uses) against Gauss–Seidel
written out in tests/helpers; "nsgs" on small piles judged by the
natural-map error written out."""

from __future__ import annotations

import numpy as np
import pytest

import qpcontact
from qpcontact.cases.piles import sphere_pile
from qpcontact.core.friction_problem import FrictionProblem
from qpcontact.solvers.friction._nsgs_kernels import _local_3d_closed_form, diagonal_blocks_3d
from qpcontact.solvers.friction.nsgs import NSGS
from tests.helpers.references import (coulomb_local_by_hand, natural_map_error_by_hand,
                                      nsgs_sweeps_by_hand)


def _closed_form(a, c, b, mu):
    r = np.full(3, np.nan)
    _local_3d_closed_form(a, c, np.asarray(b, float), mu, r)
    return r


def _in_law(a, c, b, mu, r):
    """Coulomb's law at one contact, De Saxcé's velocity: r ∈ K_μ, û ∈ K_μ*
    = {‖t‖ <= n/μ}, r·û = 0 (relative to the sizes involved)."""
    u = np.array([a, c, c]) * r + b
    uh = u + np.r_[mu * np.hypot(u[1], u[2]), 0.0, 0.0]
    size = np.abs(b).max()
    in_k = np.hypot(r[1], r[2]) <= mu * r[0] * (1 + 1e-12) and r[0] >= 0
    in_dual = mu * np.hypot(uh[1], uh[2]) <= uh[0] + 1e-12 * size
    return in_k and in_dual and abs(r @ uh) <= 1e-12 * size * np.abs(r).max(initial=1.0)


@pytest.mark.parametrize("case, b, expected", [
    ("open", (0.3, -2.0, 1.0), (0.0, 0.0, 0.0)),
    # r_N = 1/40 · 4 = 0.1, r_T = −b_T/25 = (0.04, −0.02): ‖r_T‖ 0.0447 <= 0.5 · 0.1
    ("stick", (-4.0, -1.0, 0.5), (0.1, 0.04, -0.02)),
    # ‖b_T‖ = 5 > μ c r_N = 1.25: r_T = −μ r_N b_T/‖b_T‖ = −0.05 (0.6, 0.8)
    ("slide", (-4.0, 3.0, 4.0), (0.1, -0.03, -0.04)),
])
def test_the_closed_form_local_solve_is_coulombs_law(case, b, expected):
    """W_ii = diag(40, 25, 25), μ = 0.5: each case's answer worked out by
    hand (comments), and the law's three conditions."""
    r = _closed_form(40.0, 25.0, b, 0.5)
    assert np.allclose(r, expected, rtol=1e-14, atol=1e-16), (case, r)
    assert _in_law(40.0, 25.0, np.array(b), 0.5, r), case


def test_the_closed_form_meets_the_law_on_random_contacts():
    """Random blocks, μ and b: every answer in the law, and equal to the
    cases written out in tests/helpers (a sliding sign or a stick bound
    changed fails here); all three cases met."""
    rng = np.random.default_rng(1)
    seen = set()
    for _ in range(2000):
        a, c, mu = rng.uniform(0.1, 50.0), rng.uniform(0.1, 50.0), rng.uniform(0.0, 1.5)
        b = rng.normal(size=3) * rng.uniform(0.01, 10.0)
        r = _closed_form(a, c, b, mu)
        assert _in_law(a, c, b, mu, r), (a, c, mu, b, r)
        ref = coulomb_local_by_hand(np.diag([a, c, c]), b, mu)
        assert np.allclose(r, ref, rtol=1e-12, atol=1e-14 * np.abs(b).max()), (r, ref)
        seen.add("open" if r[0] == 0 else
                 "stick" if np.hypot(r[1], r[2]) < mu * r[0] * (1 - 1e-9) else "slide")
    assert seen == {"open", "stick", "slide"}


def test_sphere_blocks_are_taken_as_diagonal_and_others_not():
    p = sphere_pile(100, seed=0).problem
    gs = NSGS(p, closed_form=True)
    assert gs.closed.all()
    assert not NSGS(p).closed.any()           # nsgs-newton's sweeps keep the fixed point
    blocks = np.tile(np.diag([2.0, 1.0, 1.0]), (4, 1, 1))
    blocks[1, 0, 1] = blocks[1, 1, 0] = 1e-3   # a coupled block
    blocks[2, 2, 2] = 1.1                       # unequal tangential entries
    blocks[3, 0, 0] = 0.0                       # no normal stiffness
    assert diagonal_blocks_3d(blocks, 1e-12).tolist() == [True, False, False, False]


@pytest.mark.parametrize("closed_form", [True, False])
def test_the_3d_block_sweeps_are_the_sweeps_by_hand(closed_form):
    """40 sweeps at ω = 1 on a loose sphere pile from zero: the compiled
    sweeps (the closed form, or the fixed point to 1e-14) and Gauss–Seidel
    written out agree to the last digits the contraction keeps."""
    p = sphere_pile(60, seed=3).problem
    gs = NSGS(p, closed_form=closed_form)
    gs.sweep(40)
    ref = nsgs_sweeps_by_hand(p.W, p.q, p.mu, np.zeros_like(gs.r), 40)
    assert np.abs(ref).max() > 0
    assert np.abs(gs.r - ref).max() <= 1e-10 * np.abs(ref).max()


def test_nsgs_certifies_a_loose_pile_as_the_fixed_point_sweep_does():
    """"nsgs" (closed form) and the fixed point's sweeps to 1e-14 end at the
    same reactions where both converge, to the certificate's digits, and the
    answer is in the law by the natural map written out."""
    p = sphere_pile(200, seed=1).problem
    s = qpcontact.solve(p, "nsgs", accuracy=1e-10, max_sweeps=20_000, check_every=20)
    assert s.ok, s.message
    assert natural_map_error_by_hand(p.W, p.q, p.mu, s.r) <= 1e-10
    gs = NSGS(p, local_rtol=1e-14)
    gs.sweep(s.stats["iterations"])
    assert np.abs(gs.r - s.r).max() <= 1e-8 * np.abs(s.r).max()


def test_a_coupled_block_goes_to_the_fixed_point():
    """Two contacts whose blocks are not diagonal (random SPD W): "nsgs"
    solves them by the fixed point and its answer is in the law."""
    rng = np.random.default_rng(4)
    B = rng.normal(size=(6, 6))
    W = B @ B.T + 6 * np.eye(6)
    q = np.array([-1.0, 0.4, -0.2, -0.5, 2.0, 1.0])
    p = FrictionProblem(W, q, np.array([0.4, 0.3]), 3)
    assert not NSGS(p, closed_form=True).closed.any()
    s = qpcontact.solve(p, "nsgs", accuracy=1e-10)
    assert s.ok and natural_map_error_by_hand(W, q, p.mu, s.r) <= 1e-10, s.message


def test_without_the_stall_rule_nsgs_runs_to_its_limit():
    """A compact pile where NSGS drifts: with stall_checks 0 it sweeps to
    max_sweeps; with 3 checks it stops at its first plateau."""
    p = sphere_pile(300, seed=2, agitation=0.1, polydispersity=0.005).problem
    s = qpcontact.solve(p, "nsgs", accuracy=1e-12, stall_checks=0, max_sweeps=3000)
    assert not s.ok and s.stats["iterations"] == 3000, s.message
    s = qpcontact.solve(p, "nsgs", accuracy=1e-12, stall_checks=3, max_sweeps=3000)
    assert s.stats["iterations"] < 3000 and "stalled (no better iterate in 3 checks)" in s.message
