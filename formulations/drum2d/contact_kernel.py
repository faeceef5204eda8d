r"""The drum's contact detection and the step's contact kinematics in compiled
passes (numba).

SI units: m, m/s, rad/s.  The mechanics are contacts.py's (gaps, normals,
H and w) and broadphase.py's (the grid); these kernels do the same
arithmetic in the same order, so that every array is the NumPy route's bit
for bit: the grid's candidate pairs in the order ``grid_pairs`` lists them
(the same cell, then the four neighbour offsets, cell by cell), each kept
pair, shell and lifter contact in ``find_contacts``' order, H's CSC arrays
as scipy's COO → CSC conversion leaves them (each column's rows ascending),
and u = Hᵀ ν + w summed over a column's rows in that order from 0, as
scipy's CSR product with Hᵀ sums it.  Detection took 1.24 ms a step at
1 200 contacts in some forty NumPy calls of 20–150 µs; this, 0.39 (the
kernel ~0.27, the rest H's one csc_matrix).  Imported only where it runs,
so that importing the drum does not load numba.
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.compiled import njit

__all__ = ["candidate_pairs", "detect", "velocities", "impulses", "keep_columns"]

# Half of the 3 x 3 stencil (broadphase's docstring): each pair of adjacent cells once
_DX = np.array([1, -1, 0, 1], np.int64)
_DY = np.array([0, 1, 1, 1], np.int64)


@njit
def candidate_pairs(pos, rad, margin):
    """broadphase.grid_pairs' candidate pairs (a, b) in its order, as (min, max)."""
    n = pos.shape[0]
    if n < 2:
        return np.zeros((0, 2), np.int64)
    cell = 2.0 * rad.max() + margin
    x0, y0 = pos[0, 0], pos[0, 1]
    for k in range(1, n):
        x0 = min(x0, pos[k, 0])
        y0 = min(y0, pos[k, 1])
    ix = np.empty(n, np.int64)
    iy = np.empty(n, np.int64)
    for k in range(n):
        ix[k] = np.int64(np.floor((pos[k, 0] - x0) / cell))
        iy[k] = np.int64(np.floor((pos[k, 1] - y0) / cell))
    width = ix.max() + 3
    key = (iy + 1) * width + (ix + 1)
    order = np.argsort(key, kind="mergesort")       # stable, as kind="stable"
    skey = key[order]
    cells = np.empty(n, np.int64)
    starts = np.empty(n, np.int64)
    counts = np.zeros(n, np.int64)
    nc = 0
    for k in range(n):
        if nc == 0 or skey[k] != cells[nc - 1]:
            cells[nc], starts[nc] = skey[k], k
            nc += 1
        counts[nc - 1] += 1
    # the neighbour cells first, to size the list (a growing list cost seconds of compiling)
    nbr = np.full((4, nc), -1, np.int64)
    total = 0
    for c in range(nc):
        total += counts[c] * (counts[c] - 1) // 2
    for o in range(4):
        for c in range(nc):
            target = cells[c] + _DY[o] * width + _DX[o]
            t = np.searchsorted(cells[:nc], target)
            if t < nc and cells[t] == target:
                nbr[o, c] = t
                total += counts[c] * counts[t]
    out = np.empty((total, 2), np.int64)
    m = 0
    # the same cell: a < b within the block, a-major
    for c in range(nc):
        for a in range(counts[c]):
            for b in range(a + 1, counts[c]):
                i, j = order[starts[c] + a], order[starts[c] + b]
                out[m, 0], out[m, 1] = min(i, j), max(i, j)
                m += 1
    for o in range(4):
        for c in range(nc):
            t = nbr[o, c]
            for a in range(counts[c] if t >= 0 else 0):
                for b in range(counts[t]):
                    i, j = order[starts[c] + a], order[starts[t] + b]
                    out[m, 0], out[m, 1] = min(i, j), max(i, j)
                    m += 1
    return out


@njit(inline="always")
def _nearest(px, py, ax, ay, sx, sy):
    """The fraction along the segment from (ax, ay) by (sx, sy) of its point
    nearest (px, py)."""
    s = ((px - ax) * sx + (py - ay) * sy) / (sx * sx + sy * sy)
    return min(max(s, 0.0), 1.0)


@njit
def detect(pos, rad, margin, shell_radius, inner, outer, half_width, omega, step, vel):
    """find_contacts' arrays (contacts.py): (i, j, kind, normal, gap,
    wall_point, w, H's CSC indptr, indices, data, the candidate pairs
    examined) for discs at ``pos`` (n, 2) of radii ``rad``, the shell of
    radius ``shell_radius`` and lifter segments ``inner``–``outer`` (k, 2)
    of half thickness ``half_width``, contacts with gap <= ``margin``; the
    walls' tangential velocity their material point's mean over ``step``
    [s] (0: the velocity at t), and each gap's remainder beyond its linear
    part after ``step`` along the centres' velocities ``vel`` (n, 2) and
    the walls' turn (contacts.py; zeros at step 0)."""
    n = pos.shape[0]
    pairs = candidate_pairs(pos, rad, margin)
    nl = inner.shape[0]
    cap = pairs.shape[0] + n + n * nl     # disc pairs, shell, lifters at most
    ci = np.empty(cap, np.int64)
    cj = np.empty(cap, np.int64)
    kind = np.empty(cap, np.int8)
    normal = np.empty((cap, 2))
    gap = np.empty(cap)
    point = np.zeros((cap, 2))
    lifter = np.full(cap, -1, np.int64)
    m = 0
    for p in range(pairs.shape[0]):      # disc-disc: i the larger index, n from j to i
        a, b = pairs[p, 0], pairs[p, 1]
        dx, dy = pos[b, 0] - pos[a, 0], pos[b, 1] - pos[a, 1]
        dist = np.hypot(dx, dy)
        g = dist - rad[a] - rad[b]
        if g <= margin:
            ci[m], cj[m], kind[m], gap[m] = b, a, 0, g
            s = max(dist, 1e-300)
            normal[m, 0], normal[m, 1] = dx / s, dy / s
            m += 1
    n_disc = m
    for k in range(n):                   # the shell: normal towards the axis
        dist = np.hypot(pos[k, 0], pos[k, 1])
        g = shell_radius - dist - rad[k]
        if g <= margin:
            s = max(dist, 1e-300)
            ux, uy = pos[k, 0] / s, pos[k, 1] / s
            ci[m], cj[m], kind[m], gap[m] = k, -1, 1, g
            normal[m, 0], normal[m, 1] = -ux, -uy
            point[m, 0], point[m, 1] = shell_radius * ux, shell_radius * uy
            m += 1
    for k in range(n):                   # the lifters: from the segment's nearest point
        for L in range(nl):
            sx, sy = outer[L, 0] - inner[L, 0], outer[L, 1] - inner[L, 1]
            s = _nearest(pos[k, 0], pos[k, 1], inner[L, 0], inner[L, 1], sx, sy)
            nx, ny = inner[L, 0] + s * sx, inner[L, 1] + s * sy
            dx, dy = pos[k, 0] - nx, pos[k, 1] - ny
            dist = np.hypot(dx, dy)
            g = dist - rad[k] - half_width
            if g <= margin:
                d = max(dist, 1e-300)
                ex, ey = dx / d, dy / d
                ci[m], cj[m], kind[m], gap[m] = k, -1, 2, g
                lifter[m] = L
                normal[m, 0], normal[m, 1] = ex, ey
                point[m, 0], point[m, 1] = nx + half_width * ex, ny + half_width * ey
                m += 1
    w = np.empty(2 * m)
    # the wall point's chord over the step, (Rot(Ω h) − I) p / h (contacts.py)
    turn = omega * step
    across = -2.0 * np.sin(0.5 * turn) ** 2 / step if step > 0.0 else 0.0
    along = np.sin(turn) / step if step > 0.0 else omega
    for k in range(m):
        if k < n_disc:
            vx, vy, cx, cy = 0.0, 0.0, 0.0, 0.0
        else:
            vx, vy = omega * (-point[k, 1]), omega * point[k, 0]
            cx = across * point[k, 0] - along * point[k, 1]
            cy = across * point[k, 1] + along * point[k, 0]
        nx, ny = normal[k, 0], normal[k, 1]
        # NumPy's sum over the two components starts from +0.0 (the signs of zeros kept)
        w[2 * k] = -((0.0 + nx * vx) + ny * vy)
        w[2 * k + 1] = -((0.0 + (-ny) * cx) + nx * cy)
    bend = np.zeros(m)
    if step > 0.0:
        turn_c, turn_s = np.cos(turn), np.sin(turn)
        for k in range(m):
            i, j = ci[k], cj[k]
            x, y = pos[i, 0] + step * vel[i, 0], pos[i, 1] + step * vel[i, 1]
            u = normal[k, 0] * vel[i, 0] + normal[k, 1] * vel[i, 1]
            if kind[k] == 0:
                x -= pos[j, 0] + step * vel[j, 0]
                y -= pos[j, 1] + step * vel[j, 1]
                after = np.hypot(x, y) - rad[i] - rad[j]
                u -= normal[k, 0] * vel[j, 0] + normal[k, 1] * vel[j, 1]
            elif kind[k] == 1:
                after = shell_radius - np.hypot(x, y) - rad[i]
            else:
                L = lifter[k]
                ax = turn_c * inner[L, 0] - turn_s * inner[L, 1]
                ay = turn_s * inner[L, 0] + turn_c * inner[L, 1]
                sx = turn_c * outer[L, 0] - turn_s * outer[L, 1] - ax
                sy = turn_s * outer[L, 0] + turn_c * outer[L, 1] - ay
                f = _nearest(x, y, ax, ay, sx, sy)
                after = np.hypot(x - ax - f * sx, y - ay - f * sy) - rad[i] - half_width
            bend[k] = after - gap[k] - step * (u + w[2 * k])
    # H (3n x 2m) in CSC, rows ascending: (n, 0), (t, −r_i) on disc i, (−n, 0),
    # (−t, −r_j) on disc j (contacts.py's module docstring); j < i
    indptr = np.zeros(2 * m + 1, np.int64)
    indices = np.empty(10 * m, np.int64)
    data = np.empty(10 * m)
    e = 0
    for k in range(m):
        i, j = ci[k], cj[k]
        nx, ny = normal[k, 0], normal[k, 1]
        tx, ty = -ny, nx
        if j >= 0:
            indices[e], data[e] = 3 * j, -nx
            indices[e + 1], data[e + 1] = 3 * j + 1, -ny
            e += 2
        indices[e], data[e] = 3 * i, nx
        indices[e + 1], data[e + 1] = 3 * i + 1, ny
        e += 2
        indptr[2 * k + 1] = e
        if j >= 0:
            indices[e], data[e] = 3 * j, -tx
            indices[e + 1], data[e + 1] = 3 * j + 1, -ty
            indices[e + 2], data[e + 2] = 3 * j + 2, -rad[j]
            e += 3
        indices[e], data[e] = 3 * i, tx
        indices[e + 1], data[e + 1] = 3 * i + 1, ty
        indices[e + 2], data[e + 2] = 3 * i + 2, -rad[i]
        e += 3
        indptr[2 * k + 2] = e
    return (ci[:m].copy(), cj[:m].copy(), kind[:m].copy(), normal[:m].copy(), gap[:m].copy(),
            point[:m].copy(), w, indptr, indices[:e].copy(), data[:e].copy(), pairs.shape[0],
            bend)


@njit
def velocities(indptr, indices, data, w, v):
    """u = Hᵀ v + w, each column's products summed from 0 in its stored order
    (scipy's CSR product of Hᵀ, then w added)."""
    m = indptr.shape[0] - 1
    u = np.empty(m)
    for c in range(m):
        s = 0.0
        for p in range(indptr[c], indptr[c + 1]):
            s += data[p] * v[indices[p]]
        u[c] = s + w[c]
    return u


@njit
def impulses(indptr, indices, data, r, n_rows):
    """H r, column by column from 0 (scipy's CSC product, the same order)."""
    y = np.zeros(n_rows)
    for c in range(indptr.shape[0] - 1):
        for p in range(indptr[c], indptr[c + 1]):
            y[indices[p]] += data[p] * r[c]
    return y


@njit
def keep_columns(indptr, indices, data, keep):
    """H's column pairs (2k, 2k + 1) of the contacts k kept, in order: the CSC
    arrays of H[:, cols] (each column's rows as stored)."""
    m = keep.shape[0]
    total = 0
    kept = 0
    for k in range(m):
        if keep[k]:
            total += indptr[2 * k + 2] - indptr[2 * k]
            kept += 1
    ptr = np.zeros(2 * kept + 1, np.int64)
    idx = np.empty(total, indices.dtype)
    val = np.empty(total)
    e = 0
    c = 0
    for k in range(m):
        if keep[k]:
            for col in range(2 * k, 2 * k + 2):
                for p in range(indptr[col], indptr[col + 1]):
                    idx[e], val[e] = indices[p], data[p]
                    e += 1
                c += 1
                ptr[c] = e
    return ptr, idx, val
