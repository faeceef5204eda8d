"""The in-house pivoting methods: the exact oracle every backend is judged
against.  See docs/pivoting.md for guarantees and measured costs.

"lemke" and "enumeration" take any M, so they also solve frictional contact
problems through their LCP (:func:`qpcontact.core.friction_problem.faceted_lcp`):
exactly in 2-D, where the cone is polyhedral, and on the cone faceted into a
polyhedron in 3-D (an approximation, reported as such)."""

from __future__ import annotations

from ..method import Method
from .bpp import run_bpp
from .energy import run_energy
from .enumeration import ENUMERATION_MAX, run_enumeration
from .ip_bpp import run_ip_bpp
from .lemke import run_lemke
from .mg_bpp import run_mg_bpp

_INSTALL = "pip install qpcontact"
_ANY_M = ("lcp", "qp", "friction-2d", "friction-3d")


def specs() -> list[Method]:
    return [
        Method("energy", run_energy, takes="lcp", requires="spd", accepts_sparse=False,
               returns_duals=False, algorithm="principal pivoting (Kolesnikov's energy criterion)",
               exact=True, family="pivoting", install=_INSTALL),
        Method("bpp", run_bpp, takes="lcp", requires="spd", accepts_sparse=True,
               returns_duals=False, algorithm="block principal pivoting (Kostreva, Judice-Pires)",
               exact=True, family="pivoting", install=_INSTALL),
        Method("ip-bpp", run_ip_bpp, takes="qp", requires="spd", accepts_sparse=True,
               returns_duals=True,
               algorithm="interior-point warm start, block principal pivoting finish",
               exact=True, family="pivoting", install=_INSTALL, constraints="lower-bounds"),
        Method("mg-bpp", run_mg_bpp, takes="lcp", requires="spd", accepts_sparse=True,
               returns_duals=False,
               algorithm="nested truncated nonsmooth Newton multigrid, block pivoting finish",
               exact=True, family="pivoting", install=_INSTALL),
        Method("lemke", run_lemke, takes="lcp", requires="any", accepts_sparse=False,
               returns_duals=False, algorithm="complementary pivoting (Lemke)",
               exact=True, family="pivoting", install=_INSTALL, problems=_ANY_M,
               approximate_on=("friction-3d",)),
        Method("enumeration", run_enumeration, takes="lcp", requires="any",
               accepts_sparse=False, returns_duals=False,
               algorithm="complementary basis enumeration (n <= 16)", exact=True,
               family="pivoting", install=_INSTALL, max_n=ENUMERATION_MAX, problems=_ANY_M,
               approximate_on=("friction-3d",)),
    ]
