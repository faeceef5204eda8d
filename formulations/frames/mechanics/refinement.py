r"""The contact stiffness R refined past a stiffness contrast.

Where a frame's members differ in stiffness by more than :data:`CONTRAST`
(a deck 1e8 times stiffer than its legs), one solve of the basic system
S x = rhs in double leaves R — and with it the contact LCP's matrix M =
W R P in kN/m — wrong in its small entries by about cond(S) eps times the
largest.  Two steps of iterative refinement with the residual in extended
precision (K's part member by member) bring R back to its digits; what is
left of each column's error is about its last correction on the link rows.
Its small entries are then known only to that rounding, so a Farkas vector
of the LCP, exact on the rounded M and q, is no proof about the frame
(:func:`is_refined`, :func:`no_farkas_proof`).
"""
from __future__ import annotations

import numpy as np

from .member_forces import EXTENDED, contrast, stiffness_times

__all__ = ["CONTRAST", "is_refined", "no_farkas_proof", "refined_columns"]


#: members whose stiffness differs by more than this get R refined in
#: extended precision (a deck 1e8 times stiffer than its legs had R, and so
#: the LCP's matrix, 1e-8 off: the load path chose wrong states from it)
CONTRAST = 1e6


def is_refined(b) -> bool:
    """Whether R is refined in extended precision (:data:`CONTRAST`): its
    small entries are then known only to its rounding, so a Farkas vector,
    exact on the LCP's M and q, is no proof about the frame — a deck 1e12
    times stiffer than its columns (R's entries zeroed) and a beam of spans
    18 to 3.3e8 apart (noise kept) each had a "proof" where an equilibrium
    exists."""
    return contrast(b) > CONTRAST


def no_farkas_proof(b) -> str:
    """The words for why, where :func:`is_refined`, the LCP's Farkas
    certificates prove nothing about the frame, and what to do."""
    return (f"its Farkas certificates are not a proof here: the members' stiffnesses differ by "
            f"{contrast(b):.1e}, beyond which the contact matrix's small entries carry rounding "
            f"(model the stiff part as rigid, or bring the contrast under {CONTRAST:.0e})")


def refined_columns(b, rhs, sol, steps=2, chunk=256):
    """Solutions of the basic system S x = rhs (columns) refined by
    ``steps`` steps with the residual in extended precision (K's part
    member by member: :func:`.member_forces.stiffness_times`), and each
    column's last correction on the link rows, max |dx[nf:]|: what is left
    of their error is at most about that (the corrections shrink by about
    cond(S) eps a step where the refinement converges)."""
    nf, free, kappa = b["nf"], b["free"], b["kappa"]
    N = b["K"].shape[0]
    Hf = b["Hf"].astype(EXTENDED)
    flex = np.asarray(b["flex"], EXTENDED)[:, None]
    out = np.empty_like(sol)
    last = np.zeros(rhs.shape[1])
    for at in range(0, rhs.shape[1], chunk):
        cols = slice(at, min(at + chunk, rhs.shape[1]))
        x = np.asarray(sol[:, cols], EXTENDED)
        r_ = np.asarray(rhs[:, cols], EXTENDED)
        for _ in range(steps):
            U = np.zeros((N, x.shape[1]), EXTENDED)
            U[free] = x[:nf]
            top = stiffness_times(b, U)[free] + Hf @ x[nf:]
            bottom = Hf.T @ x[:nf] - kappa ** 2 * flex * x[nf:]
            dx = b["lu"].solve(np.asarray(r_ - np.vstack([top, bottom]), float))
            x += dx
            last[cols] = np.abs(dx[nf:]).max(axis=0, initial=0.0)
        out[:, cols] = np.asarray(x, float)
    return out, last
