"""The load trace as a registered method."""

from __future__ import annotations

from ..method import Method
from .tracer import run_trace


def specs() -> list[Method]:
    return [Method("trace", run_trace, takes="parametric-lcp", requires="any",
                   accepts_sparse=False, returns_duals=False,
                   algorithm="parametric principal pivoting (load trace: Osipova, Popov, Lovtsov)", exact=True,
                   family="pivoting", install="pip install qpcontact")]
