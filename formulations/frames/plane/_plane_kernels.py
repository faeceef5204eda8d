"""The plane frame's active set, compiled (numba): the start's principal
pivots on the map of the links (:func:`.sparse_active_set._held_start`).

Imported only where it runs, so that importing the frames does not load
numba.  As array expressions a pivot was some fifteen NumPy calls on a
34 x 35 array (a 20-storey tower: eleven pivots, a sixteenth of its solve).
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.compiled import njit


@njit
def held_start(R, RF, required, n_link, t_link, gap, violation, rcond_min, pivots):
    """(found, closed): :func:`.sparse_active_set._held_start`'s pivots on
    T = [R R_F] [kN/m, kN], a contact's links its normal n_link[c] and,
    with friction, the next; ``found`` False where it gives no start (the
    pivots run out, a block is singular, the map stops being finite).
    Each choice as NumPy's argmin makes it (the first least value, the
    first NaN before any number)."""
    nl, nc = R.shape[0], n_link.shape[0]
    T = np.empty((nl, nl + 1))
    T[:, :nl] = R
    T[:, nl] = RF
    x = np.empty(nl + 1)
    x[:nl] = required
    x[nl] = 1.0
    floor = np.empty(nc)
    for k in range(nc):
        i = n_link[k]
        size = 0.0
        for j in range(nl):
            size += abs(R[i, j]) * abs(required[j])
        floor[k] = violation * (size + abs(RF[i]))
    pull = floor.copy()
    closed = np.ones(nc, np.bool_)
    out = np.empty(nl)
    inv = np.empty((2, 2))
    rows = np.empty((2, nl + 1))
    cols = np.empty((nl, 2))
    for _ in range(pivots * nc):
        for i in range(nl):
            v = 0.0
            for j in range(nl + 1):
                v += T[i, j] * x[j]
            out[i] = v
        c, least = 0, np.inf
        for k in range(nc):
            v = out[n_link[k]] + pull[k]
            if v != v or v < least:
                c, least = k, v
                if v != v:
                    break
        if not least < 0.0:
            c, least = 0, np.inf
            for k in range(nc):
                xn = out[n_link[k]]
                v = np.inf if closed[k] else xn + gap[k] + violation * (abs(xn) + abs(gap[k]))
                if v != v or v < least:
                    c, least = k, v
                    if v != v:
                        break
            if not least < 0.0:
                for i in range(nl):
                    if not np.isfinite(out[i]):
                        return False, closed
                return True, closed
        p = n_link[c]
        w = 2 if t_link[c] >= 0 else 1
        if w == 2:
            a, b, cc, d = T[p, p], T[p, p + 1], T[p + 1, p], T[p + 1, p + 1]
            det = a * d - b * cc
            if not abs(det) > rcond_min * (abs(a * d) + abs(b * cc)):
                return False, closed
            inv[0, 0], inv[0, 1], inv[1, 0], inv[1, 1] = d / det, -b / det, -cc / det, a / det
        else:
            if not T[p, p] != 0.0:
                return False, closed
            inv[0, 0] = 1.0 / T[p, p]
        # the exchange: T_pp⁻¹ in the block, −T_pp⁻¹ T_pr in its rows,
        # T_rp T_pp⁻¹ in its columns, T_rr − T_rp T_pp⁻¹ T_pr elsewhere
        for a_ in range(w):
            for j in range(nl + 1):
                v = 0.0
                for q in range(w):
                    v += inv[a_, q] * T[p + q, j]
                rows[a_, j] = v
        for i in range(nl):
            for q in range(w):
                cols[i, q] = T[i, p + q]
        for i in range(nl):
            for j in range(nl + 1):
                v = 0.0
                for q in range(w):
                    v += cols[i, q] * rows[q, j]
                T[i, j] -= v
        for i in range(nl):
            for a_ in range(w):
                v = 0.0
                for q in range(w):
                    v += cols[i, q] * inv[q, a_]
                T[i, p + a_] = v
        for a_ in range(w):
            for j in range(nl + 1):
                T[p + a_, j] = -rows[a_, j]
            for q in range(w):
                T[p + a_, p + q] = inv[a_, q]
        if closed[c]:
            for q in range(w):
                x[p + q] = 0.0
            pull[c] = np.inf
        else:
            for q in range(w):
                x[p + q] = required[p + q]
            pull[c] = floor[c]
        closed[c] = not closed[c]
    return False, closed


@njit
def contact_links(table, N):
    """The links of a plane frame's contacts from their table
    (:func:`.plane_assembly.contact_table`: first dof, the other node's
    first dof or −1, the unit normal, f, the gap, 1/k): per contact its
    normal link and, where f > 0, the tangent link after it (t = (n_y,
    −n_x)); H (N x links) as CSR (indptr, indices: int32, data) — a
    link's direction at its node's ux, uy and minus it at the other
    node's, its exact zeros left out, each row's entries by link (a node
    paired with itself keeps both of its entries, which cancel in every
    product); the LCP's maps Δ = P z − g (P: an n link takes its
    contact's Z_n, a t link Z⁺ − Z⁻) and w = W X (X_n; f X_n + X_t;
    f X_n − X_t) as CSR, and g.  Returns (n_link, t_link, H's three, P's
    three, W's three, g)."""
    nc = table.shape[0]
    n_link = np.empty(nc, np.int64)
    t_link = np.full(nc, -1, np.int64)
    nl = 0
    nf = 0
    for c in range(nc):
        n_link[c] = nl
        nl += 1
        if table[c, 4] > 0:
            t_link[c] = nl
            nl += 1
            nf += 1
    # H: each link's entries (ux, uy at its node, then at the other), by row
    direction = np.empty((nl, 2))
    owner = np.empty(nl, np.int64)
    for c in range(nc):
        j = n_link[c]
        direction[j, 0], direction[j, 1] = table[c, 2], table[c, 3]
        owner[j] = c
        if t_link[c] >= 0:
            j = t_link[c]
            direction[j, 0], direction[j, 1] = table[c, 3], -table[c, 2]
            owner[j] = c
    count = np.zeros(N + 1, np.int64)
    for j in range(nl):
        at, away = int(table[owner[j], 0]), int(table[owner[j], 1])
        for d in range(2):
            if direction[j, d] != 0.0:
                count[at + d + 1] += 1
                if away >= 0:
                    count[away + d + 1] += 1
    for r in range(N):
        count[r + 1] += count[r]
    indptr = count.astype(np.int32)
    fill = count[:-1].copy()
    indices = np.empty(count[N], np.int32)
    data = np.empty(count[N])
    for j in range(nl):               # by link: each row's columns ascending
        at, away = int(table[owner[j], 0]), int(table[owner[j], 1])
        for d in range(2):
            v = direction[j, d]
            if v != 0.0:
                indices[fill[at + d]], data[fill[at + d]] = j, v
                fill[at + d] += 1
                if away >= 0:
                    indices[fill[away + d]], data[fill[away + d]] = j, -v
                    fill[away + d] += 1
    # P (links x z) and W (z x links), z = Z_n per contact, then Z⁺, Z⁻ per
    # frictional one
    nz = nc + 2 * nf
    p_ptr = np.zeros(nl + 1, np.int32)
    p_ind = np.empty(nl + nf, np.int32)
    p_val = np.ones(nl + nf)
    w_ptr = np.zeros(nz + 1, np.int32)
    w_ind = np.empty(nc + 4 * nf, np.int32)
    w_val = np.ones(nc + 4 * nf)
    g = np.zeros(nl)
    k = 0
    for c in range(nc):
        j = n_link[c]
        g[j] = table[c, 5]
        p_ind[p_ptr[j]] = c
        p_ptr[j + 1] = p_ptr[j] + 1
        w_ind[c] = j
        w_ptr[c + 1] = c + 1
        if t_link[c] >= 0:
            t, plus = t_link[c], nc + 2 * k
            p_ind[p_ptr[t]], p_ind[p_ptr[t] + 1], p_val[p_ptr[t] + 1] = plus, plus + 1, -1.0
            p_ptr[t + 1] = p_ptr[t] + 2
            for side in range(2):
                q = nc + 4 * k + 2 * side
                w_ind[q], w_ind[q + 1] = j, t
                w_val[q], w_val[q + 1] = table[c, 4], 1.0 - 2.0 * side
                w_ptr[plus + side + 1] = q + 2
            k += 1
    return n_link, t_link, indptr, indices, data, p_ptr, p_ind, p_val, w_ptr, w_ind, w_val, g
