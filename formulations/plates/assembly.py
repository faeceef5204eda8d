"""The raft's assembled stiffness and nodal loads (all 3n dofs, node-major
(w, θx, θy); see :mod:`.element` for the units and signs)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .element import pressure_load, stiffness

__all__ = ["element_dofs", "assemble_stiffness", "area_load"]


def element_dofs(elements: np.ndarray) -> np.ndarray:
    """(ne, 12) global dof numbers: node-major (w, θx, θy)."""
    return (3 * elements[:, :, None] + np.arange(3)).reshape(-1, 12)


def assemble_stiffness(mesh, E, nu, t) -> sp.csr_matrix:
    """The plate's stiffness [N/m, N, N·m by dof] over all 3n dofs."""
    Ke = stiffness(mesh.corners, E, nu, t)
    dofs = element_dofs(mesh.elements)
    rows = np.repeat(dofs, 12, axis=1).ravel()
    cols = np.tile(dofs, (1, 12)).ravel()
    n = 3 * mesh.nodes.shape[0]
    K = sp.csr_matrix((Ke.ravel(), (rows, cols)), shape=(n, n))
    return ((K + K.T) * 0.5).tocsr()      # exactly symmetric (the sums' rounding differs)


def area_load(mesh, pressure) -> np.ndarray:
    """Nodal forces on w (n,) [N] of an element-wise pressure (ne,) [N/m²]."""
    out = np.zeros(mesh.nodes.shape[0])
    np.add.at(out, mesh.elements, pressure_load(mesh.corners, pressure))
    return out


