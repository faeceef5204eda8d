"""The 2-D drum's warm-started route (Drum2D.simulate(warm_start=...)): each
step's friction problem started from the previous step's impulses, matched by
contact identity, and solved again by "auto" wherever that is not certified.

The reference is the old route, "auto" on every step from zero: both must
give the same states to the certificate's tolerance, every step certified.
A warm start that cannot certify (one NSGS sweep) must end certified through
the fallback, with the same states.  The friction measures' Jacobian is
checked against finite differences of the natural map (an independent route)."""

import numpy as np
import pytest
import scipy.sparse as sp

from formulations.drum2d import Discs, Drum2D, Shell, hex_fill
from qpcontact.core.errors import InvalidOptionError
from qpcontact.judge.friction_certificate import contact_scales, natural_map_jacobian
from qpcontact.solvers.friction.nsgs import NSGS
from qpcontact.core.friction_problem import FrictionProblem, modified_velocity, project_cone


def _pile(n=16, steps=60):
    pos, dia = hex_fill(1.0, n, 0.2, spread=0.0, seed=3)   # touching
    shell = Shell(1.0, omega=1.0, lifter_angles=np.linspace(0, 2 * np.pi, 4, endpoint=False),
                  lifter_height=0.08, lifter_half_width=0.01)
    return Drum2D(Discs(dia, pos), shell, ("friction", "rotation", "damping"),
                  restitution=0.2), steps


def _same_states(a, b):
    scale = np.abs(a.velocities).max() + 1.0
    assert np.abs(a.velocities - b.velocities).max() <= 1e-7 * scale
    assert np.abs(a.spins - b.spins).max() <= 1e-7 * (np.abs(a.spins).max() + 1.0)
    assert np.abs(a.positions - b.positions).max() <= 1e-9
    assert np.array_equal(a.n_active, b.n_active)


@pytest.fixture(scope="module")
def reference():
    model, steps = _pile()
    return model, steps, model.simulate(2e-3, steps, keep_contacts=False, warm_start=None)


@pytest.mark.slow
def test_warm_route_gives_the_certified_states_of_auto(reference):
    model, steps, old = reference
    new = model.simulate(2e-3, steps, keep_contacts=False, warm_start="nsgs-newton")
    assert old.certified.all() and new.certified.all()
    assert new.worst_certificate <= 1e-9
    assert (new.n_active > 4).sum() > steps // 2       # a pile: contacts persist
    # the warm route certified most steps itself, not by falling back
    assert new.fallback.mean() < 0.5
    assert {m for m, fb in zip(new.method, new.fallback) if not fb and m} == {"nsgs-newton"}
    _same_states(old, new)


@pytest.mark.slow
def test_a_warm_start_that_cannot_certify_falls_back_to_auto(reference):
    model, steps, old = reference
    new = model.simulate(2e-3, steps, keep_contacts=False, warm_start="nsgs",
                         warm_options={"max_sweeps": 1, "check_every": 1})
    stepped = new.n_active > 1
    # one sweep from the last step's impulses certifies hardly any pile step
    assert new.fallback[stepped].mean() > 0.9
    assert new.certified.all() and new.worst_certificate <= 1e-9
    assert all(m == o for m, o, fb in zip(new.method, old.method, new.fallback) if fb)
    _same_states(old, new)


def test_warm_start_options_are_checked():
    model, _ = _pile(4)
    with pytest.raises(InvalidOptionError, match="r0"):
        model.simulate(2e-3, 2, warm_start="nsgs", warm_options={"r0": np.zeros(2)})
    frictionless = Drum2D(model.discs, model.shell, ("damping",))
    with pytest.raises(InvalidOptionError, match="friction"):
        frictionless.simulate(2e-3, 2, warm_start="nsgs")


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("dense", [False, True])
def test_natural_map_jacobian_matches_finite_differences(dim, dense):
    rng = np.random.default_rng(dim)
    nc = 12
    A = sp.random(dim * nc, 2 * dim * nc, 0.1, random_state=dim) + sp.eye(dim * nc, 2 * dim * nc)
    W = (A @ A.T).tocsc()
    p = FrictionProblem(W.toarray() if dense else W, rng.normal(size=dim * nc),
                        rng.uniform(0.2, 0.8, nc), dim)
    r = rng.normal(size=dim * nc)
    rho = np.repeat(contact_scales(p), dim)

    def F(r):
        u = np.asarray(p.W @ r).ravel() + p.q
        return r - project_cone(r - rho * modified_velocity(u, p.mu, dim), p.mu, dim)

    J = natural_map_jacobian(p, r)
    J = J.toarray() if sp.issparse(J) else J
    eps = 1e-7
    fd = np.column_stack([(F(r + eps * e) - F(r - eps * e)) / (2 * eps)
                          for e in np.eye(dim * nc)])
    assert np.abs(J - fd).max() <= 1e-5 * (1 + np.abs(fd).max())


def test_nsgs_diagonal_blocks_are_those_of_w():
    rng = np.random.default_rng(0)
    nc, d = 9, 3
    A = sp.random(d * nc, 2 * d * nc, 0.2, random_state=1) + sp.eye(d * nc, 2 * d * nc)
    W = (A @ A.T).tocsc()
    gs = NSGS(FrictionProblem(W, rng.normal(size=d * nc), np.full(nc, 0.5), d))
    dense = W.toarray()
    for i in range(nc):
        assert np.array_equal(gs.blocks[i], dense[d * i:d * i + d, d * i:d * i + d])




def test_a_regular_newton_step_is_kept_without_the_augmented_system(monkeypatch):
    """Where J is regular (W positive definite: compliant contacts) J's own
    LU step is the minimum-norm step.  From a start whose contact states are
    wrong the full step raises the error; it is still taken as it is, not
    solved again through the augmented system (the same step at ten times
    the fill), and the iteration goes on from it."""
    import qpcontact.solvers.friction.hybrid as hybrid

    rng = np.random.default_rng(5)
    nc, d = 40, 2
    A = sp.random(d * nc, 3 * d * nc, 0.05, random_state=5) + sp.eye(d * nc, 3 * d * nc)
    W = (A @ A.T + 0.1 * sp.eye(d * nc)).tocsc()
    p = FrictionProblem(W, rng.normal(size=d * nc), np.full(nc, 0.8), d)
    augmented = hybrid._minimum_norm_step
    calls = []
    monkeypatch.setattr(hybrid, "_minimum_norm_step",
                        lambda *a: calls.append(1) or augmented(*a))
    square = {"on": True}
    errors = []
    error_at = hybrid._error_at
    monkeypatch.setattr(hybrid, "_error_at", lambda *a: errors.append(error_at(*a)) or errors[-1])
    hybrid.minimum_norm_newton(p, 3 * rng.normal(size=d * nc), 1e-12, max_steps=6,
                               square=square)
    assert any(b > a for a, b in zip(errors, errors[1:])), errors   # a step that did not help
    assert not calls and square["on"]


def test_step_problem_w_is_h_t_minv_h_plus_the_springs_exactly_symmetric():
    """The stepper's W (delassus_kernel) against scipy's Hᵀ M⁻¹ H + D on
    random contacts, between two bodies or a body and a wall, most normal
    columns without a spin entry (as the drum's H): equal to rounding,
    symmetric bit for bit."""
    from formulations.drum2d.delassus_kernel import delassus

    rng = np.random.default_rng(7)
    n, m = 30, 50
    rows, cols, vals = [], [], []
    for k in range(m):                 # one or two bodies a contact, three freedoms a body
        for body in rng.choice(n, 1 + (k % 3 > 0), replace=False):
            for col in (2 * k, 2 * k + 1):
                for dof in range(2 if col == 2 * k and k % 4 else 3):
                    rows.append(3 * body + dof)
                    cols.append(col)
                    vals.append(rng.normal())
    H = sp.csc_matrix((vals, (rows, cols)), shape=(3 * n, 2 * m))
    H.sort_indices()
    minv = rng.uniform(0.5, 2.0, 3 * n)
    minv[5] = 0.0                      # a disc held from rolling
    diag = np.zeros(2 * m)
    diag[0::2] = rng.uniform(0, 1e-2, m)
    ptr, idx, val = delassus(H.indptr.astype(np.int64), H.indices.astype(np.int64), H.data,
                             3 * n, minv, diag)
    W = sp.csc_matrix((val, idx, ptr), shape=(2 * m, 2 * m)).toarray()
    ref = (H.T @ sp.diags(minv) @ H).toarray() + np.diag(diag)
    assert np.array_equal(W, W.T)
    assert np.abs(W - ref).max() <= 1e-14 * np.abs(ref).max()
