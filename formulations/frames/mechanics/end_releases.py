"""A member's released ends (a hinge, a rotational spring between the
member's end and its node): the end's own rotation θ_r [rad], not its
node's, read off the element's moment rows — shared by the constant-N
beam-column (:mod:`.beam_column`) and the member under N(x)
(:mod:`.varying_axial`), which differ only in how they build the element."""

from __future__ import annotations

import numpy as np


def released_ends(element, ends, springs) -> np.ndarray:
    """``ends`` (v_i, θ_i, v_j, θ_j) with each released end's own rotation
    θ_r in place of its node's, from the element's moment rows
    (:func:`.beam_column.axis`): (k_rr + k) θ_r + Σ k_rc u_c = f_r + k θ_node.
    ``element`` gives (K 4 × 4, f 4) when a released end asks for them (a
    member rigidly joined at both ends builds neither); ``springs`` (i, j)
    each None for a rigid joint, 0 for a hinge, else a rotational spring
    [moment / rad]."""
    ends = np.array(ends, float)
    own = [r for r, k in zip((1, 3), springs) if k is not None]
    if own:
        kb, fe = element()
        rest = [r for r in range(4) if r not in own]
        rhs = fe[own] - kb[np.ix_(own, rest)] @ ends[rest]
        A = kb[np.ix_(own, own)].copy()
        for n, r in enumerate(own):
            k = springs[(r - 1) // 2]
            A[n, n] += k
            rhs[n] += k * ends[r]
        ends[own] = np.linalg.solve(A, rhs)
    return ends
