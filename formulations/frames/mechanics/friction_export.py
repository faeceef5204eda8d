"""A frame's contact problem as a :class:`~qpcontact.FrictionProblem` (2-D
for a plane frame, 3-D for a space frame, with the true circular cone) —
the form FCLIB and Siconos's solvers take."""

from __future__ import annotations

import numpy as np

from .contact_springs import with_contact_springs
from .load_combinations import load_combination


def friction_problem(frame, p: float = 1.0, *, combination: dict | None = None, _built=None):
    """The frame's contact problem for one load combination as a
    :class:`~qpcontact.FrictionProblem` (2-D for a plane frame, 3-D for a
    space frame, with the true circular cone) — the form FCLIB and
    Siconos's solvers take (``qpcontact.io.write_fclib`` writes it).

    Global form: K v = H r + f (K the stiffness on the free dofs, v the
    displacements, f the combination's loads, settlements moved to the
    right-hand side), u = Hᵀ v + w with u = (opening, slip along each
    tangent) per contact (w: the gaps, and what settlements do to the
    contacts), r = (X_n, X_t...) the contact force on the structure along
    the normal and the tangents (plane: t = (n_y, −n_x); space: the
    contact's t1, t2), μ = the contact's friction (0: a frictionless
    contact, whose cone is its normal ray).  Quasi-static: "velocities"
    are displacements, units the frame's.  An elastic contact is a spring
    to a contact point of its own, whose displacement (normal, tangents)
    follows the free dofs in v (:mod:`.contact_springs`): reduced, W =
    Hᵀ K⁻¹ H + 1/k on its diagonal.  A frame that is a mechanism without
    its contacts (K singular: W does not exist) stays in global form,
    unreduced, which qpcontact.solve solves without W
    ("desaxce-global")."""
    from qpcontact import FrictionProblem

    b = _built if _built is not None else frame.build()
    combo = load_combination(frame, p, combination, b)
    K, F, U, fixed, free = b["K"], b["F"], b["U"], b["fixed"], b["free"]
    normals, tangents, mu = frame.kind.release_directions(frame, b)
    dim = 1 + len(tangents)
    nc = normals.shape[1]
    # contact by contact: normal, then its tangents
    H = np.stack([normals] + tangents, axis=2).reshape(normals.shape[0], nc * dim)
    factors = np.array([combo.get(case, 0.0) for case in b["cases"]])
    f_all, u_set = F @ factors, U @ factors
    fixed_idx = np.flatnonzero(fixed)
    f = f_all[free] - K[free][:, fixed_idx] @ u_set[fixed_idx]
    w = H[fixed_idx].T @ u_set[fixed_idx]
    w[0::dim] += [c.gap for c in frame.contacts]
    name = f"frame ({', '.join(f'{k}: {v:g}' for k, v in combo.items())})"
    flex = np.repeat([0.0 if c.stiffness is None else 1.0 / c.stiffness
                      for c in frame.contacts], dim)
    M, Hg, fg = with_contact_springs(K[free][:, free], H[free], f, flex, dim)
    return FrictionProblem.global_problem(M, Hg, fg, w, mu, dim, name=name)
