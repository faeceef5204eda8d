"""The in-house pivoting methods, registered: the exact oracle every backend is
judged against.  See docs/pivoting.md for guarantees and measured costs."""

from __future__ import annotations

from ..registry import Method, register
from .bpp import run_bpp
from .energy import run_energy
from .enumeration import ENUMERATION_MAX, run_enumeration
from .ip_bpp import run_ip_bpp
from .lemke import run_lemke

_INSTALL = "pip install qpcontact"


def register_all() -> None:
    register(Method("energy", run_energy, takes="lcp", requires="spd", accepts_sparse=False,
                    returns_duals=False, algorithm="principal pivoting (energy criterion, P0)",
                    exact=True, family="pivoting", install=_INSTALL), replace=True)
    register(Method("bpp", run_bpp, takes="lcp", requires="spd", accepts_sparse=True,
                    returns_duals=False, algorithm="block principal pivoting (Kostreva, Judice-Pires)",
                    exact=True, family="pivoting", install=_INSTALL), replace=True)
    register(Method("ip-bpp", run_ip_bpp, takes="qp", requires="spd", accepts_sparse=True,
                    returns_duals=True,
                    algorithm="interior-point warm start, block principal pivoting finish",
                    exact=True, family="pivoting", install=_INSTALL,
                    constraints="lower-bounds"), replace=True)
    register(Method("lemke", run_lemke, takes="lcp", requires="any", accepts_sparse=False,
                    returns_duals=False, algorithm="complementary pivoting (Lemke)",
                    exact=True, family="pivoting", install=_INSTALL), replace=True)
    register(Method("enumeration", run_enumeration, takes="lcp", requires="any",
                    accepts_sparse=False, returns_duals=False,
                    algorithm="complementary basis enumeration (n <= 16)", exact=True,
                    family="pivoting", install=_INSTALL, max_n=ENUMERATION_MAX), replace=True)
