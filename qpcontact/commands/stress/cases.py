"""The stress suite's families, sizes and seeds, and how each case is built with
its answer (or its status) in it."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["CATEGORIES", "LCP_FAMILIES", "QP_FAMILIES", "ROUNDED_FAMILIES", "EDGE_FAMILIES",
           "FAMILIES", "StressConfig", "QUICK",
           "FULL", "build_case", "default_siconos"]

CATEGORIES = ("certified", "proved", "inaccurate", "failed", "silent_wrong", "hung")


#: family -> (problem kind, builder name); sizes apply to every family but siconos
LCP_FAMILIES = ("spd", "psd_singular", "degenerate", "badly_scaled", "p_matrix", "friction",
                "infeasible", "far_contact", "spread", "spread_sparse", "murty", "ties")


QP_FAMILIES = ("qp_convex", "qp_degenerate", "qp_infeasible", "qp_unbounded", "qp_penalty")

#: real-valued data whose status or solution is decided exactly, in rationals
#: (qpcontact.cases.rounded).  Appended after "siconos" so that the
#: older families keep their index in FAMILIES, which seeds their instances.
ROUNDED_LCP_FAMILIES = ("illposed_psd", "ill_conditioned_spd", "infeasible_rounded")
ROUNDED_QP_FAMILIES = ("qp_infeasible_rounded", "qp_unbounded_rounded")
#: real-valued data near the edge of solvability, decided exactly
#: (qpcontact.cases.rounded): condition 1e8..1e16 and near-singular PD (the
#: forward-error bound), Farkas vectors an LP cannot see (y = 1 beside far
#: contacts) or that a ray should have found (one row).  Appended last, so
#: that every older family keeps its index.
EDGE_FAMILIES = ("conditioned_spd", "near_singular_pd", "farkas_far_contacts", "farkas_one_row")
ROUNDED_FAMILIES = ROUNDED_LCP_FAMILIES + ROUNDED_QP_FAMILIES + EDGE_FAMILIES

FAMILIES = LCP_FAMILIES + QP_FAMILIES + ("siconos",) + ROUNDED_FAMILIES

# Siconos files whose answer SOURCE.md documents independently (by hand or by
# enumeration): status, and z where unique.  The others are judged by the
# complementarity check alone.
_SICONOS_KNOWN = {
    "lcp_deudeu": ("solved", [4 / 3, 7 / 3]),
    "lcp_deudeu_block": ("solved", [4 / 3, 7 / 3]),
    "lcp_trivial": ("solved", list(1.0 / np.arange(1, 10))),
    "lcp_trivial_block": ("solved", list(1.0 / np.arange(1, 10))),
    "lcp_ortiz": ("solved", [2 / 3, 0.0, 1 / 3, 0.0]),
    "lcp_ortiz_block": ("solved", [2 / 3, 0.0, 1 / 3, 0.0]),
    "lcp_exp_murty": ("solved", [0, 0, 0, 0, 0, 1.0]),
    "lcp_CPS_2": ("solved", [0.0, 1.0, 3.0]),
    "lcp_CPS_4": ("solved", [2.0, 2.0, 2.0, 92.0]),
    "lcp_Pang_isolated_sol": ("solved", [1.0, 0.0, 0.0]),
    "lcp_Pang_isolated_sol_perturbed": ("infeasible", None),
}


@dataclass(frozen=True)
class StressConfig:
    sizes: tuple = (6, 24)
    seeds: int = 2
    first_seed: int = 0                   # seeds first_seed .. first_seed + seeds - 1
    accuracies: tuple = ("high",)
    methods: tuple | None = None          # None: every installed method (cvxpy too unless no_cvxpy)
    no_cvxpy: bool = True
    families: tuple = FAMILIES
    time_limit: float = 10.0
    rotate_accuracy: bool = False         # one accuracy per problem, rotating (the full run)
    siconos_dir: str | None = None


QUICK = StressConfig()


FULL = StressConfig(sizes=(8, 30, 100), seeds=200, accuracies=("low", "default", "high"),
                    no_cvxpy=False, time_limit=2.0, rotate_accuracy=True)


def _scaled_lcp(case, rng, decades: float):
    """D M D, D q with D a diagonal of powers of two over ``decades`` decades:
    exact in floating point, so the planted answer (D⁻¹z, Dw) stays exact."""
    from ...core.problems import LCP

    if decades <= 0 or case.status != "solved":
        return case
    M = case.problem.M
    n = M.shape[0]
    d = 2.0 ** np.round(rng.uniform(-decades / 2, decades / 2, n) * math.log2(10))
    import scipy.sparse as sp

    Ms = (sp.diags(d) @ M @ sp.diags(d)).tocsc() if sp.issparse(M) else (M * d[:, None]) * d[None, :]
    case.problem = LCP(Ms, case.problem.q * d)
    if case.z is not None:
        zs, ws = case.scales()
        case.z, case.w = case.z / d, case.w * d
        case.z_scale, case.w_scale = zs / d, ws * d
    return case


def _scaled_qp(case, rng, decades: float):
    """x = D x', constraint rows times E: powers of two, exact."""
    from qpsolvers import Problem

    if decades <= 0:
        return case
    P, q, G, h, A, b, lb, ub = case.problem.unpack()
    n = q.size
    d = 2.0 ** np.round(rng.uniform(-decades / 2, decades / 2, n) * math.log2(10))
    Ps = (P * d[:, None]) * d[None, :]
    Gs = hs = None
    if G is not None:
        e = 2.0 ** np.round(rng.uniform(-decades / 2, decades / 2, G.shape[0]) * math.log2(10))
        Gs, hs = (G * e[:, None]) * d[None, :], h * e
    case.problem = Problem(Ps, q * d, Gs, hs, A, b,
                           None if lb is None else lb / d, None if ub is None else ub / d)
    if case.x is not None:
        case.x = case.x / d
    return case


def _murty(n: int):
    """Murty's example: M upper triangular, 1 on the diagonal and 2 above,
    q = -1; Lemke takes 2^n pivots on it.  M is a P-matrix (triangular, unit
    diagonal) so the solution is unique: z = e_n (w = Mz + q = (1, ..., 1, 0))."""
    from ...core.problems import LCP
    from ...cases.planted import Case

    M = np.triu(2.0 * np.ones((n, n)), 1) + np.eye(n)
    z = np.zeros(n)
    z[-1] = 1.0
    return Case("murty", LCP(M, -np.ones(n)), "solved", z=z, w=M @ z - 1.0, unique_z=True)


def _ties(n: int, rng):
    """M = c(I + J) (SPD), q = -c·1: every ratio test ties; z = 1/(n+1), w = 0
    (every pair degenerate on the w side)."""
    from ...core.problems import LCP
    from ...cases.planted import Case

    c = 2.0 ** int(rng.integers(-10, 11))
    M = c * (np.eye(n) + np.ones((n, n)))
    z = np.full(n, 1.0 / (n + 1))
    return Case("ties", LCP(M, -c * np.ones(n)), "solved", z=z, w=np.zeros(n), unique_z=True,
                z_scale=z, w_scale=np.full(n, c))


def build_case(family: str, n: int, seed: int, siconos_dir: str | None = None):
    """The instance ``(family, n, seed)``: a qpcontact.cases.planted.Case."""
    from ...cases.planted import Case, build_lcp, build_qp
    from ...cases.families import far_contact_lcp, spread_lcp
    from ...core.options import check_seed

    seed = check_seed(seed)
    rng = np.random.default_rng([seed, n, FAMILIES.index(family)])
    decades = float(rng.choice([0.0, 4.0, 8.0, 12.0]))
    cond = 10.0 ** rng.uniform(0.0, 8.0)
    if family in ROUNDED_FAMILIES:
        from ...cases.rounded import build_rounded

        return build_rounded(family, n, seed)
    if family == "siconos":
        from ...io import read_siconos_lcp

        path = Path(siconos_dir or default_siconos())
        files = sorted(path.glob("*.dat"))
        f = files[seed % len(files)]
        status, z = _SICONOS_KNOWN.get(f.stem, ("unknown", None))
        lcp = read_siconos_lcp(f)
        zz = None if z is None else np.asarray(z, float)
        case = Case(f"siconos/{f.stem}", lcp, status, z=zz,
                    w=None if zz is None else lcp.w(zz), unique_z=zz is not None,
                    unique_w=zz is not None, seed=seed)
        return case
    if family in ("spd", "psd_singular", "degenerate", "badly_scaled", "p_matrix", "friction",
                  "infeasible"):
        case = build_lcp(family, n, seed, cond=cond, decades=decades)
        return case if family == "badly_scaled" else _scaled_lcp(case, rng, decades)
    if family == "far_contact":
        lcp, z, w = far_contact_lcp(seed, n=max(n, 8), n_far=max(1, n // 8))
        return _scaled_lcp(Case(family, lcp, "solved", z=z, w=w, unique_z=True, seed=seed), rng,
                           decades)
    if family in ("spread", "spread_sparse"):
        lcp, z, w = spread_lcp(seed, n=n, cond=cond, sparse=family == "spread_sparse")
        return Case(family, lcp, "solved", z=z, w=w, unique_z=True, seed=seed)
    if family == "murty":
        return _murty(min(n, 16))
    if family == "ties":
        return _ties(n, rng)
    if family in QP_FAMILIES:
        case = build_qp(family[3:], max(n, 3), seed, cond=min(cond, 1e6))
        return _scaled_qp(case, rng, decades) if family != "qp_penalty" else case
    raise ValueError(f"unknown family {family!r}; choose from {', '.join(FAMILIES)}")


def default_siconos() -> Path | None:
    """The Siconos LCP files where :func:`qpcontact.core.files.find_data` finds them."""
    from ...core.files import find_data

    return find_data("siconos-lcp")
