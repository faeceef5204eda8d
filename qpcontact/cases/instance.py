"""A named problem instance: what the formulations hand to ``qpcontact compare``
and the benchmarks (entry-point group ``qpcontact.formulations``, each module's
``instances(size, hardness, seed)``)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Instance"]


@dataclass(frozen=True)
class Instance:
    """A named problem.  ``forces``: where the physical contact forces are —
    ("z", None) the LCP's z (or the QP's x), ("w", k) the first k entries of w."""

    name: str
    formulation: str
    size: str
    problem: object
    forces: tuple = ("z", None)
