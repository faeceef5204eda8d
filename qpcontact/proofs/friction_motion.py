"""Proof that a frictional contact problem has no equilibrium: a ray of De Saxcé's
subproblem of a global problem, checked from the data (M, H, f, μ)."""

from __future__ import annotations

import numpy as np

__all__ = ["no_equilibrium"]


def no_equilibrium(problem, d):
    """Check a ray d of De Saxcé's subproblem from the data: Md = 0, Hᵀd in
    every contact's dual cone K_i* and fᵀd > 0 (each to rounding).  Then no
    r in the cones balances the loads — for any v, Mv = Hr + f would give
    0 = dᵀMv = (Hᵀd)·r + fᵀd > 0.  Returns (the sentence that says so, the
    checked d — scaled to max|d| = 1, entries below 1e-9 set to zero), or
    None when d does not prove it."""
    g, dim = problem.global_data, problem.dim
    d = np.asarray(d, float)
    if not np.all(np.isfinite(d)) or not np.abs(d).max(initial=0.0) > 0:
        return None
    d = d / np.abs(d).max()
    d[np.abs(d) < 1e-9] = 0.0     # an interior-point ray's noise; the checks below are on this d
    Md, size = np.asarray(g["M"] @ d).ravel(), np.asarray(abs(g["M"]) @ np.abs(d)).ravel()
    U = np.asarray(g["H"].T @ d).ravel().reshape(-1, dim)
    slack = U[:, 0] - problem.mu * np.linalg.norm(U[:, 1:], axis=1)
    work, work_size = float(g["f"] @ d), float(np.abs(g["f"]) @ np.abs(d))
    rounding = 1e-9 * max(np.abs(U).max(initial=0.0), 1e-300)
    if np.any(np.abs(Md) > 1e-9 * np.maximum(size, 1e-300)) or np.any(slack < -rounding) \
            or not work > 1e-9 * work_size:
        return None
    return (f"no equilibrium exists: no contact forces within the friction cones balance the "
            f"loads — the motion d (stats['ray']) has Md = 0, every contact admits it (Hᵀd in "
            f"its dual cone: it opens or slides within the cone), and the loads do positive "
            f"work fᵀd = {work:.3g} on it (checked from the data)"), d
