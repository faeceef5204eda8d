r"""Narrow phase and contact kinematics of the 2-D drum.

SI units: metres, m/s, rad/s, N·s (impulses).

Every contact k joins disc i to an *other* body — disc j, the shell, or a
lifter — with the unit normal n_k pointing from the other body into disc i (an
impulse r_N > 0 pushes i along +n) and the tangent t_k = ẑ × n_k = (−n_y, n_x).
Disc i's material point at the contact, c_i − r_i n, moves at
v_i + ω_i ẑ × (−r_i n) = v_i − r_i ω_i t; disc j's, c_j + r_j n, at
v_j + r_j ω_j t; a wall point p at V(p) = Ω ẑ × p.  The relative velocity in
the local frame (u_N, u_T) is therefore

    u_N = n · (v_i − v_j),           u_T = t · (v_i − v_j) − r_i ω_i − r_j ω_j

between discs, and u_N = n · v_i − n · V,  u_T = t · v_i − r_i ω_i − t · V
against a wall:  u = Hᵀ ν + w with ν = (vx, vy, ω) per disc, H's column pair of
contact k carrying (n, 0), (t, −r_i) on disc i and (−n, 0), (−t, −r_j) on disc
j, and w = −(n · V, t · V) (zero between discs).  The same H maps the local
impulse (r_N, r_T) to generalized impulses on the discs (the torque on i is
(−r_i n) × (r_N n + r_T t) = −r_i r_T ẑ): the virtual-work pairing that makes
W = Hᵀ M⁻¹ H symmetric.

Gaps [m]: between discs |c_i − c_j| − r_i − r_j; to the shell R − |c_i| − r_i
(normal −c_i/|c_i|, towards the axis); to a lifter, the distance from c_i to
the lifter's segment minus r_i + b (normal from the segment's nearest point).
Contacts are listed when the gap is at most the margin δ the stepper asks for.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .broadphase import grid_pairs
from .geometry import Discs, Shell, wall_velocity

__all__ = ["Contacts", "find_contacts", "KINDS", "DISC", "SHELL", "LIFTER"]

#: contact kinds, the index in ``Contacts.kind``
KINDS = ("disc", "shell", "lifter")
#: ``Contacts.kind`` of a disc–disc contact
DISC = 0
#: ``Contacts.kind`` of a disc–shell contact
SHELL = 1
#: ``Contacts.kind`` of a disc–lifter contact
LIFTER = 2


@dataclass
class Contacts:
    """m contacts: disc ``i``, ``j`` (the other disc, −1 for a wall), ``kind``,
    ``normal`` (m, 2), ``gap`` (m,) [m], ``wall_point`` (m, 2) [m] (where the
    wall's velocity is taken; unused between discs), ``w`` (2m,) [m/s] and ``H``
    (3n x 2m, sparse)."""

    i: np.ndarray
    j: np.ndarray
    kind: np.ndarray
    normal: np.ndarray
    gap: np.ndarray
    wall_point: np.ndarray
    w: np.ndarray
    H: sp.csc_matrix
    pairs_checked: int = 0

    @property
    def m(self) -> int:
        return self.i.size

    def subset(self, keep: np.ndarray) -> "Contacts":
        cols = np.column_stack([2 * np.flatnonzero(keep), 2 * np.flatnonzero(keep) + 1]).ravel()
        return Contacts(self.i[keep], self.j[keep], self.kind[keep], self.normal[keep],
                        self.gap[keep], self.wall_point[keep], self.w[cols],
                        self.H[:, cols].tocsc(), self.pairs_checked)


def _disc_pairs(pos, rad, margin):
    pairs, checked = grid_pairs(pos, rad, margin)
    d = pos[pairs[:, 1]] - pos[pairs[:, 0]]
    dist = np.hypot(d[:, 0], d[:, 1])
    gap = dist - rad[pairs[:, 0]] - rad[pairs[:, 1]]
    keep = gap <= margin
    pairs, d, dist, gap = pairs[keep], d[keep], dist[keep], gap[keep]
    n = d / np.maximum(dist, 1e-300)[:, None]
    return pairs[:, 1], pairs[:, 0], n, gap, checked     # i = the larger index, n from j to i


def _shell(pos, rad, R, margin):
    dist = np.hypot(pos[:, 0], pos[:, 1])
    gap = R - dist - rad
    idx = np.flatnonzero(gap <= margin)
    u = pos[idx] / np.maximum(dist[idx], 1e-300)[:, None]
    return idx, -u, gap[idx], R * u


def _lifters(pos, rad, shell, t, omega, margin):
    inner, outer = shell.lifter_segments(t, omega)
    if inner.shape[0] == 0:
        e = np.zeros(0, np.int64)
        return e, np.zeros((0, 2)), np.zeros(0), np.zeros((0, 2))
    seg = outer - inner                                   # (k, 2)
    rel = pos[:, None, :] - inner[None, :, :]             # (n, k, 2)
    s = np.clip((rel * seg).sum(-1) / (seg * seg).sum(-1), 0.0, 1.0)
    near = inner[None] + s[..., None] * seg[None]
    d = pos[:, None, :] - near
    dist = np.hypot(d[..., 0], d[..., 1])
    gap = dist - rad[:, None] - shell.lifter_half_width
    di, lk = np.nonzero(gap <= margin)
    n = d[di, lk] / np.maximum(dist[di, lk], 1e-300)[:, None]
    return di, n, gap[di, lk], near[di, lk] + shell.lifter_half_width * n


def find_contacts(discs: Discs, shell: Shell, t: float, omega: float, margin: float,
                  positions: np.ndarray | None = None) -> Contacts:
    """Every contact with gap <= ``margin`` [m] at time t [s], the shell turning
    at ``omega`` [rad/s] (module docstring)."""
    pos = discs.positions if positions is None else positions
    rad = discs.radii
    di, dj, dn, dg, checked = _disc_pairs(pos, rad, margin)
    si, sn, sg, sp_ = _shell(pos, rad, shell.radius, margin)
    li, ln, lg, lp = _lifters(pos, rad, shell, t, omega, margin)
    i = np.concatenate([di, si, li]).astype(np.int64)
    j = np.concatenate([dj, -np.ones(si.size + li.size, np.int64)])
    kind = np.concatenate([np.full(di.size, DISC), np.full(si.size, SHELL),
                           np.full(li.size, LIFTER)]).astype(np.int8)
    normal = np.concatenate([dn, sn, ln]).reshape(-1, 2)
    gap = np.concatenate([dg, sg, lg])
    wall_point = np.concatenate([np.zeros((di.size, 2)), sp_, lp]).reshape(-1, 2)
    m = i.size
    tangent = np.column_stack([-normal[:, 1], normal[:, 0]])
    V = wall_velocity(wall_point, omega)
    V[:di.size] = 0.0
    w = np.empty(2 * m)
    w[0::2] = -(normal * V).sum(1)
    w[1::2] = -(tangent * V).sum(1)
    H = _jacobian(discs.n, i, j, normal, tangent, rad)
    return Contacts(i, j, kind, normal, gap, wall_point, w, H, checked + discs.n
                    * (1 + shell.lifter_angles.size))


def _jacobian(n_discs, i, j, normal, tangent, rad):
    m = i.size
    k = np.arange(m)
    cn, ct = 2 * k, 2 * k + 1
    rows = [3 * i, 3 * i + 1, 3 * i, 3 * i + 1, 3 * i + 2]
    cols = [cn, cn, ct, ct, ct]
    vals = [normal[:, 0], normal[:, 1], tangent[:, 0], tangent[:, 1], -rad[i]]
    other = j >= 0
    jj, ko = j[other], k[other]
    rows += [3 * jj, 3 * jj + 1, 3 * jj, 3 * jj + 1, 3 * jj + 2]
    cols += [2 * ko, 2 * ko, 2 * ko + 1, 2 * ko + 1, 2 * ko + 1]
    vals += [-normal[other, 0], -normal[other, 1], -tangent[other, 0], -tangent[other, 1],
             -rad[jj]]
    return sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(3 * n_discs, 2 * m))
