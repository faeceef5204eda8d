"""What the pads' friction carries under the normal forces a frame gives
them: why a load path can stop below the rigid body's limit.

Mechanics.  The rigid body's limit (:mod:`.rigid_limit`) is the largest
load that contact forces in their cones balance — any normal forces the
statics allow.  The frame does not choose its normal forces: its stiffness
sets them.  A six-legged table twisted about its centre: the LP puts the
whole weight on the four corner legs (r = 1.17 m from the centre) and none
on the two middle ones (r = 0.6 m), and turns at 13.84 kN·m on inscribed
16-gons; the table keeps about W/6 on every leg whatever the torque, and
its friction is exhausted at 11.598 kN·m.  Coulomb's law is non-associated
(a pad slides without lifting), so nothing in the frame moves the weight
to the corners: the load path stops where the pads' friction is exhausted
under its own normal forces.

The check.  With the normal forces N_c of a state held, the loads' part
that the pads' friction must carry is the one in the rigid motions that
keep every carrying pad on its floor (a table's: the two translations
along the floor and the turn about the vertical).  Its largest p is one
LP over the polygons' extreme rays with each pad's multipliers summing to
N_c (:func:`capacity`).  Where that is the path's last load, the path
stopped because friction was exhausted under the frame's normal forces,
not for want of a scheme: the answer says so.  This is evidence in floats
about the state, not a proof that no equilibrium exists beyond it (other
normal forces may carry more, which the load path does not reach).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from . import contact_lcp
from .rigid_limit import contact_rays, ray_works, rigid_motions


def capacity(frame, b, normals, const, var):
    """The largest p whose loads F(const) + p F(var) the pads' friction
    carries in the rigid motions that keep every pad with a normal force
    on its floor, each pad's normal force held at ``normals`` (one per
    contact, in order); None where the frame is held otherwise (no rigid
    motion), no such motion is left, or the LP fails."""
    from scipy.optimize import linprog

    G = rigid_motions(frame, b)
    rays = contact_rays(b)
    if G is None or rays is None:
        return None
    normals = np.asarray(normals, float)
    Hd = sp.csc_matrix(b["H"])
    carrying = [links[0] for (links, _), n in zip(rays, normals) if n > 0]
    if not carrying:
        return None
    # the motions in which no carrying pad's normal link moves: the null
    # space of their normal motions over G's parameters
    lifts = np.asarray((Hd[:, carrying].T @ G.T))
    _, s, Vt = np.linalg.svd(lifts)
    rank = int(np.sum(s > 1e-12 * max(s.max(initial=0.0), 1e-300)))
    B = Vt[rank:].T                                    # params x k
    if B.shape[1] == 0:
        return None
    works = ray_works(G, b, rays) @ B                  # rays x k
    Fc = b["F"] @ contact_lcp.factors(b, const)
    Fv = b["F"] @ contact_lcp.factors(b, var)
    gc, gv = B.T @ (G @ Fc), B.T @ (G @ Fv)
    if not np.any(gv):
        return None
    nr = works.shape[0]
    # Σ μ (ray works) + p gv = -gc in the k motions; per pad Σ μ = N_c
    A_eq = [np.column_stack([works.T, gv])]
    b_eq = [-gc]
    per = np.zeros((len(rays), nr + 1))
    at = 0
    for c, (_, verts) in enumerate(rays):
        per[c, at:at + len(verts)] = 1.0
        at += len(verts)
    A_eq.append(per)
    b_eq.append(np.maximum(normals, 0.0))
    A = np.vstack(A_eq)
    scale = max(np.abs(A).max(), 1e-300)
    cost = np.zeros(nr + 1)
    cost[-1] = -1.0
    res = linprog(cost, A_eq=A / scale, b_eq=np.concatenate(b_eq) / scale,
                  bounds=[(0, None)] * nr + [(None, None)], method="highs")
    if res.status != 0:
        return None
    return float(res.x[-1])
