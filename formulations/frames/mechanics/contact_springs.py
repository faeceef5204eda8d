"""Elastic contacts in a frame's global friction problem (FCLIB's form M v =
H r + f, u = Hᵀ v + w), for plane and space frames alike.

An elastic contact's local displacement is u = Hᵀv + w + r/k: its
flexibility sits on W's diagonal, which only the local form has.  Writing it
as a spring between the node and a contact point of its own keeps the
problem global: the point's displacement s (one entry per contact
component: normal, then the tangents) is a dof, the contact acts on s alone,
and the spring's energy ½ k ‖s − P v‖² (P the contact's rows of Hᵀ) adds

    M = [[K + k PᵀP, −k Pᵀ], [−k P, k I]],   H = [[0], [I]]   (the s rows)

Equilibrium at s, k (s − P v) = r, gives s = P v + r/k, so u = s + w is the
elastic contact's displacement; at the node K v = f + Pᵀ r, the frame's
equilibrium.  M's Schur complement on the s block is K, so M is singular
exactly when K is, and reduced to local form W = Hᵀ M⁻¹ H is the frame's
Hᵀ K⁻¹ H plus 1/k on the contact's diagonal.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp


def with_contact_springs(K, H, f, flex, dim):
    """(M, H, f) of the global problem with each elastic contact's spring
    (``flex`` = 1/k per local component, 0 for a rigid contact; ``dim``
    components per contact) as dofs after the frame's (module docstring)."""
    K, H = sp.csc_matrix(K), sp.csc_matrix(H)
    flex = np.asarray(flex, float)
    springs = np.flatnonzero(flex > 0)
    if springs.size == 0:
        return K, H, np.asarray(f, float)
    n, m, ns = K.shape[0], H.shape[1], springs.size
    k = sp.diags(1.0 / flex[springs])
    P = sp.csr_matrix(H[:, springs].T)                  # (ns x n): each spring's node motion
    M = sp.bmat([[K + P.T @ k @ P, -P.T @ k], [-k @ P, k]], format="csc")
    keep = np.setdiff1d(np.arange(m), springs)
    Hs = sp.lil_matrix((n + ns, m))
    Hs[:n, keep] = H[:, keep]
    Hs[n + np.arange(ns), springs] = 1.0
    return M, sp.csc_matrix(Hs), np.r_[f, np.zeros(ns)]
