"""Hypothesis strategies for hard LCPs, QPs and frictional contact problems,
each with its answer built in.

Every strategy draws a :class:`Case`: the problem, the status a correct
solver must reach (``"solved"``, ``"infeasible"``, ``"unbounded"``) and,
where the data determine it, the planted answer — so a test can check more
than a residual::

    from hypothesis import given
    from qpcontact.testing import assert_lcp_solution
    from qpcontact.testing.strategies import lcps

    @given(lcps(kinds=("spd", "badly_scaled")))
    def test_my_solver(case):
        z = my_solver(case.problem.M, case.problem.q)
        assert_lcp_solution(case.problem, z)
        assert case.agrees(z)          # and it is the planted solution

The data are built with NumPy from a drawn seed and drawn sizes, scales and
conditioning; hypothesis shrinks towards small n, mild conditioning and
seed 0.  Needs hypothesis (``pip install "qpcontact[test]"``).

LCP kinds (:func:`lcps`)
    ``spd`` (unique solution, condition up to 1e8), ``psd_singular`` (w
    unique, z not), ``degenerate`` (pairs with z_i = w_i = 0), ``badly_scaled``
    (D M D with D over ``decades`` decades: units of N beside kN and mm beside
    m), ``p_matrix`` (nonsymmetric, M + M' PD: unique), ``friction``
    (Stewart–Trinkle 2-D Coulomb friction: nonsymmetric, copositive, not a
    P-matrix; solvable by construction), ``infeasible`` (PSD with a Farkas
    vector: no solution).
QP kinds (:func:`qps`)
    ``convex`` (P PD, unique x), ``degenerate`` (active constraints with zero
    multipliers, P singular on part of the space), ``infeasible``,
    ``unbounded``.
Frictional kinds (:func:`frictions`, 2-D and 3-D; :mod:`qpcontact.cases.planted_friction`)
    ``sticking``, ``sliding``, ``separated``, ``mixed`` (contacts in those
    states, planted exactly), ``badly_scaled`` (each contact in its own
    units over ``max_decades`` decades), ``decoupled`` (isotropic contacts:
    the unique solution is planted).  ``case.agrees(r)`` checks an answer
    against the planted one, or by Coulomb's law written out independently::

        @given(frictions(dims=(2, 3)))
        def test_my_friction_solver(case):
            r = my_solver(case.problem)
            assert_friction_solution(case.problem, r, tol=1e-8)
            assert case.agrees(r)
"""

from __future__ import annotations

import numpy as np

try:
    from hypothesis import strategies as st
except ImportError as exc:  # pragma: no cover - exercised only without the extra
    raise ImportError("qpcontact.testing.strategies needs hypothesis: "
                      'pip install "qpcontact[test]" (or pip install hypothesis)') from exc

from ..cases.planted_friction import FRICTION_KINDS, build_friction
from ..cases.planted import LCP_KINDS, QP_KINDS, Case, build_lcp, build_qp

__all__ = ["Case", "lcps", "qps", "frictions", "LCP_KINDS", "QP_KINDS", "FRICTION_KINDS",
           "build_lcp", "build_qp", "build_friction"]


def _checked(kinds, known, what: str) -> tuple:
    kinds = tuple(kinds)
    for k in kinds:
        if k not in known:
            raise ValueError(f"unknown {what} kind {k!r}; choose from {known}")
    return kinds


def lcps(kinds=LCP_KINDS, min_n: int = 2, max_n: int = 30, max_cond: float = 1e8,
         max_decades: float = 12.0):
    """Strategy drawing :class:`Case` objects holding LCPs of the given kinds."""
    kinds = _checked(kinds, LCP_KINDS, "LCP")

    @st.composite
    def draw(data):
        kind = data(st.sampled_from(kinds))
        n = data(st.integers(min_n, max_n))
        seed = data(st.integers(0, 2**32 - 1))
        cond = 10.0 ** data(st.floats(0.0, np.log10(max_cond)))
        decades = data(st.floats(0.0, max_decades))
        return build_lcp(kind, n, seed, cond=cond, decades=decades)

    return draw()


def qps(kinds=QP_KINDS, min_n: int = 2, max_n: int = 30, max_cond: float = 1e6):
    """Strategy drawing :class:`Case` objects holding QPs of the given kinds."""
    kinds = _checked(kinds, QP_KINDS, "QP")

    @st.composite
    def draw(data):
        kind = data(st.sampled_from(kinds))
        n = data(st.integers(max(min_n, 3), max_n))
        seed = data(st.integers(0, 2**32 - 1))
        cond = 10.0 ** data(st.floats(0.0, np.log10(max_cond)))
        return build_qp(kind, n, seed, cond=cond)

    return draw()


def frictions(kinds=FRICTION_KINDS, dims=(2, 3), min_contacts: int = 1, max_contacts: int = 8,
              max_cond: float = 1e4, max_decades: float = 8.0, max_mu: float = 1.0):
    """Strategy drawing :class:`~qpcontact.cases.planted_friction.FrictionCase` objects:
    frictional contact problems of the given kinds and dimensions with their
    planted solution."""
    kinds = _checked(kinds, FRICTION_KINDS, "friction")
    dims = tuple(dims)
    if not dims or any(d not in (2, 3) for d in dims):
        raise ValueError(f"dims must be a non-empty subset of (2, 3); got {dims}")

    @st.composite
    def draw(data):
        kind = data(st.sampled_from(kinds))
        dim = data(st.sampled_from(dims))
        contacts = data(st.integers(min_contacts, max_contacts))
        seed = data(st.integers(0, 2**32 - 1))
        cond = 10.0 ** data(st.floats(0.0, np.log10(max_cond)))
        decades = data(st.floats(0.0, max_decades))
        mu_max = data(st.floats(0.1, max_mu))
        return build_friction(kind, contacts, seed, dim=dim, cond=cond, decades=decades,
                              mu_max=mu_max)

    return draw()
