"""A frame's assembly loops, compiled (numba): the plane members'
stiffness in their axes and their rotations, their loads' consistent nodal
loads, K's CSR and the load columns F from the members' blocks (plane and
space alike), the basic system's blocks on the free dofs, and the condensed
band's layout — the links' slots, the pattern, its reverse Cuthill–McKee
order, the link terms and LAPACK's band storage.

Imported only by the functions that run them (:mod:`.plane_element`,
:mod:`.loads`, :mod:`.contact_lcp`, :mod:`.banded_saddle`), so that
importing the frames does not load numba.  As array expressions each was
dozens of NumPy calls (and a scipy COO → CSR conversion, scipy's RCM) on a
20-storey tower's 156 members and 34 links, each call a few µs of set-up
for a fraction of a µs of arithmetic.  Where the NumPy expressions they
replace fixed an order of sums or a rounding (the loads' Gauss sums, ξ³,
scipy's RCM seeds), the kernels keep it, and the frames' answers their
bits (dev-notes, "compiled passes in the plane path, round eleven").
"""

from __future__ import annotations

import math

import numpy as np

from qpcontact.core.compiled import njit


@njit
def plane_members(i3, j3, E, A, I, oi, oj, GAs, xy):
    """Each plane member's (L, c, s, the flexible length Lf = L − oi − oj,
    φ = 12EI/(G A_s Lf²) (0 without shear deformation), k (m, 6, 6): its
    first-order stiffness in member axes — Euler–Bernoulli for φ = 0,
    Timoshenko otherwise —, T (m, 6, 6): global end displacements to member
    axes, dofs (m, 6)) from its nodes' first dofs i3, j3 and its numbers.
    k's terms: EA/Lf axially, 12f/Lf², 6f/Lf, (4 + φ) f, (2 − φ) f with
    f = EI/(Lf (1 + φ)) [force/length, force, force·length]."""
    m = i3.shape[0]
    L = np.empty(m)
    c = np.empty(m)
    s = np.empty(m)
    Lf = np.empty(m)
    phi = np.zeros(m)
    k = np.zeros((m, 6, 6))
    T = np.zeros((m, 6, 6))
    dofs = np.empty((m, 6), np.int64)
    for e in range(m):
        ni, nj = int(i3[e]), int(j3[e])
        dx = xy[nj // 3, 0] - xy[ni // 3, 0]
        dy = xy[nj // 3, 1] - xy[ni // 3, 1]
        L[e] = math.hypot(dx, dy)
        c[e], s[e] = dx / L[e], dy / L[e]
        lf = L[e] - oi[e] - oj[e]
        Lf[e] = lf
        if GAs[e] > 0:
            phi[e] = 12.0 * E[e] * I[e] / (GAs[e] * lf ** 2)
        p = phi[e]
        f = E[e] * I[e] / (lf * (1.0 + p))
        a, vv, vt = E[e] * A[e] / lf, 12 * f / lf ** 2, 6 * f / lf
        tt, tc = (4 + p) * f, (2 - p) * f
        ke = k[e]
        ke[0, 0] = ke[3, 3] = a
        ke[0, 3] = ke[3, 0] = -a
        ke[1, 1] = ke[4, 4] = vv
        ke[1, 4] = ke[4, 1] = -vv
        ke[1, 2] = ke[2, 1] = ke[1, 5] = ke[5, 1] = vt
        ke[2, 4] = ke[4, 2] = ke[4, 5] = ke[5, 4] = -vt
        ke[2, 2] = ke[5, 5] = tt
        ke[2, 5] = ke[5, 2] = tc
        for o in (0, 3):
            T[e, o, o] = T[e, o + 1, o + 1] = c[e]
            T[e, o, o + 1] = s[e]
            T[e, o + 1, o] = -s[e]
            T[e, o + 2, o + 2] = 1.0
        for d in range(3):
            dofs[e, d] = ni + d
            dofs[e, 3 + d] = nj + d
    return L, c, s, Lf, phi, k, T, dofs


@njit
def global_stiffness(k, T, dofs, Fe, spring_dof, spring_k, N):
    """K's CSR (data, indices, indptr: int32) and F (N, cases) from the
    members' blocks: Tᵀ k T and Tᵀ Fe of each member (T block diagonal,
    its 3 × 3 blocks the member's rotation R: Rᵀ k_pq R block by block),
    scattered to its dofs, then the springs to the ground (k at a dof).
    Each entry of K is summed from its first term in member order (the
    springs last), every member's entries kept, exact zeros included (K's
    structure is the members' dofs); F's rows likewise."""
    m, nd = dofs.shape
    nb = nd // 3
    nc = Fe.shape[2]
    kg = np.empty((m, nd, nd))
    F = np.zeros((N, nc))
    R = np.empty((3, 3))
    tmp = np.empty((3, 3))
    for e in range(m):
        R[:, :] = T[e, :3, :3]
        for p in range(nb):
            for q in range(nb):
                # tmp = k_pq R, then kg_pq = Rᵀ tmp
                for i in range(3):
                    for j in range(3):
                        tmp[i, j] = (k[e, 3 * p + i, 3 * q] * R[0, j]
                                     + k[e, 3 * p + i, 3 * q + 1] * R[1, j]
                                     + k[e, 3 * p + i, 3 * q + 2] * R[2, j])
                for i in range(3):
                    for j in range(3):
                        kg[e, 3 * p + i, 3 * q + j] = (R[0, i] * tmp[0, j] + R[1, i] * tmp[1, j]
                                                       + R[2, i] * tmp[2, j])
            for i in range(3):
                r = dofs[e, 3 * p + i]
                for cc in range(nc):
                    F[r, cc] += (R[0, i] * Fe[e, 3 * p, cc] + R[1, i] * Fe[e, 3 * p + 1, cc]
                                 + R[2, i] * Fe[e, 3 * p + 2, cc])
    # the triplets grouped by row, in member order (a counting sort)
    start = np.zeros(N + 1, np.int64)
    for e in range(m):
        for a in range(nd):
            start[dofs[e, a] + 1] += nd
    for q in range(spring_dof.shape[0]):
        start[spring_dof[q] + 1] += 1
    for r in range(N):
        start[r + 1] += start[r]
    fill = start[:-1].copy()
    col = np.empty(start[N], np.int64)
    val = np.empty(start[N])
    for e in range(m):
        for a in range(nd):
            r = dofs[e, a]
            for b in range(nd):
                col[fill[r]] = dofs[e, b]
                val[fill[r]] = kg[e, a, b]
                fill[r] += 1
    for q in range(spring_dof.shape[0]):
        r = spring_dof[q]
        col[fill[r]] = r
        val[fill[r]] = spring_k[q]
        fill[r] += 1
    # each row's equal columns summed in that order, then its columns sorted
    at = np.full(N, -1, np.int64)
    indptr = np.zeros(N + 1, np.int32)
    indices = np.empty(start[N], np.int32)
    data = np.empty(start[N])
    nnz = 0
    for r in range(N):
        first = nnz
        for p in range(start[r], start[r + 1]):
            j = col[p]
            if at[j] < 0:
                at[j] = nnz
                indices[nnz] = j
                data[nnz] = val[p]
                nnz += 1
            else:
                data[at[j]] += val[p]
        for p in range(first, nnz):
            at[indices[p]] = -1
        for p in range(first + 1, nnz):          # insertion sort: a row has a few dozen
            j, x = indices[p], data[p]
            q = p - 1
            while q >= first and indices[q] > j:
                indices[q + 1], data[q + 1] = indices[q], data[q]
                q -= 1
            indices[q + 1], data[q + 1] = j, x
        indptr[r + 1] = nnz
    return data[:nnz].copy(), indices[:nnz].copy(), indptr, F


@njit
def link_slots(nl, h_dof, h_link, h_val):
    """κH_f's entries (dof, link, value) sorted by link, stably (its CSC
    order), and as (nl, width) arrays, a row a link, padded to the widest
    with the link's own first dof (0 for a link on no free dof) and a zero
    value: (dofs, links, values, dof, hv)."""
    ne = h_link.shape[0]
    start = np.zeros(nl + 1, np.int64)
    for e in range(ne):
        start[h_link[e] + 1] += 1
    width = 1
    for j in range(nl):
        width = max(width, start[j + 1])
        start[j + 1] += start[j]
    fill = start[:-1].copy()
    dofs = np.empty(ne, np.int64)
    links = np.empty(ne, np.int64)
    vals = np.empty(ne)
    dof = np.zeros((nl, width), np.int64)
    hv = np.zeros((nl, width))
    for e in range(ne):
        j = h_link[e]
        p = fill[j]
        dofs[p], links[p], vals[p] = h_dof[e], j, h_val[e]
        dof[j, p - start[j]], hv[j, p - start[j]] = h_dof[e], h_val[e]
        fill[j] += 1
    for j in range(nl):
        if start[j + 1] > start[j]:
            for a in range(start[j + 1] - start[j], width):
                dof[j, a] = dofs[start[j]]
    return dofs, links, vals, dof, hv


@njit
def band_pattern(nf, kr, kc, dof, t, n):
    """The condensed matrix's pattern: K_ff's entries (kr, kc), each link's
    dofs among themselves (its spring) and a slipping tangent t's with its
    normal n's (friction's coupling).  Returns its half-bandwidth in the
    dofs' own order, and its distinct entries as CSR (indptr, indices:
    int32, each row's columns ascending) with each row's degree as scipy's
    reverse Cuthill–McKee counts it (the row's entries, the diagonal
    twice)."""
    nl, w = dof.shape
    rows = np.empty(kr.shape[0] + (nl + t.shape[0]) * w * w, np.int64)
    cols = np.empty(rows.shape[0], np.int64)
    q = 0
    for e in range(kr.shape[0]):
        rows[q], cols[q] = kr[e], kc[e]
        q += 1
    for j in range(nl + t.shape[0]):
        left = j if j < nl else t[j - nl]
        right = j if j < nl else n[j - nl]
        for a in range(w):
            for b in range(w):
                rows[q], cols[q] = dof[left, a], dof[right, b]
                q += 1
    bw = 0
    start = np.zeros(nf + 1, np.int64)
    for e in range(q):
        bw = max(bw, abs(rows[e] - cols[e]))
        start[rows[e] + 1] += 1
    for r in range(nf):
        start[r + 1] += start[r]
    fill = start[:-1].copy()
    by_row = np.empty(q, np.int64)
    for e in range(q):
        by_row[fill[rows[e]]] = cols[e]
        fill[rows[e]] += 1
    seen = np.zeros(nf, np.bool_)
    indptr = np.zeros(nf + 1, np.int32)
    indices = np.empty(q, np.int32)
    degree = np.zeros(nf, np.int32)
    nnz = 0
    for r in range(nf):
        first = nnz
        for p in range(start[r], start[r + 1]):
            j = by_row[p]
            if not seen[j]:
                seen[j] = True
                indices[nnz] = j
                nnz += 1
        for p in range(first, nnz):
            seen[indices[p]] = False
        for p in range(first + 1, nnz):          # insertion sort: a row has a few dozen
            j = indices[p]
            q = p - 1
            while q >= first and indices[q] > j:
                indices[q + 1] = indices[q]
                q -= 1
            indices[q + 1] = j
        indptr[r + 1] = nnz
        degree[r] = nnz - first
        for p in range(first, nnz):
            if indices[p] == r:
                degree[r] += 1
                break
    return bw, indptr, indices[:nnz].copy(), degree


@njit
def cuthill_mckee(indptr, indices, degree, inds):
    """scipy's reverse Cuthill–McKee order of a symmetric pattern (CSR,
    each row's columns ascending; ``degree`` and ``inds`` =
    ``np.argsort(degree)`` as scipy's ``_reverse_cuthill_mckee`` makes
    them): from a node of least degree in each connected part, breadth
    first, each node's new neighbours by increasing degree (an insertion
    sort: stable), the whole reversed — step for step, so the same order.
    Returns (the order, each dof's place in it, the pattern's half-bandwidth
    in it)."""
    nf = degree.shape[0]
    inds = inds.copy()
    rev = np.empty(nf, np.int64)
    for k in range(nf):
        rev[inds[k]] = k
    order = np.zeros(nf, np.int64)
    temp = np.zeros(nf, np.int64)
    N = 0
    for zz in range(nf):
        if inds[zz] != -1:
            seed = inds[zz]
            order[N] = seed
            N += 1
            inds[rev[seed]] = -1
            level_start, level_end = N - 1, N
            while level_start < level_end:
                for ii in range(level_start, level_end):
                    i = order[ii]
                    n_old = N
                    for jj in range(indptr[i], indptr[i + 1]):
                        j = indices[jj]
                        if inds[rev[j]] != -1:
                            inds[rev[j]] = -1
                            order[N] = j
                            N += 1
                    level_len = 0
                    for kk in range(n_old, N):
                        temp[level_len] = degree[order[kk]]
                        level_len += 1
                    for kk in range(1, level_len):
                        d, node = temp[kk], order[n_old + kk]
                        ll = kk
                        while ll > 0 and d < temp[ll - 1]:
                            temp[ll] = temp[ll - 1]
                            order[n_old + ll] = order[n_old + ll - 1]
                            ll -= 1
                        temp[ll] = d
                        order[n_old + ll] = node
                level_start, level_end = level_end, N
        if N == nf:
            break
    perm = order[::-1].copy()
    pos = np.empty(nf, np.int64)
    for k in range(nf):
        pos[perm[k]] = k
    bw = 0
    for r in range(nf):
        for p in range(indptr[r], indptr[r + 1]):
            bw = max(bw, abs(pos[r] - pos[indices[p]]))
    return perm, pos, bw


@njit
def equivalent_loads(table, L, c, s, phi, xi3, t, wg):
    """The consistent nodal loads (n, 6: member axes, ux, uy, rz at i then
    j) of n member loads, one a row of ``table`` (member axes?, a point
    load?, a, b, then (px, py, mz, 0) or a trapezoid's (wx1, wy1, wx2,
    wy2): :attr:`.loads.MemberLoad.row`), load k on a flexible element of
    length L[k], direction (c[k], s[k]) and φ[k]: a force against the
    element's displacement interpolation Nv, a moment against its
    rotation Nt — the interdependent interpolation of the exact
    Timoshenko element (Reddy; f = 1/(1 + φ)), the Hermite cubics for
    φ = 0 —, linear axially; a trapezoid on [a, b] by Gauss–Legendre
    points t with weights wg (four: exact for a cubic times a linear
    load).  ``xi3``: ξ³ = (x/L)³ at each load's points (a point load's in
    column 0), NumPy's power, which rounds as its vector library does.
    The sums in the order NumPy's expressions took them: the transverse
    terms' four points as einsum adds them (the even points' and the odd
    points' products apart, then together), the axial ones in order — so
    the same bits, which decide a frame exactly at its friction's verge
    (tests' three-hinged portal at f = L/4h)."""
    n = table.shape[0]
    out = np.zeros((n, 6))
    nv = np.empty(4)
    terms = np.empty((4, 4))
    for k in range(n):
        member_axes, a, b = table[k, 0] > 0, table[k, 2], table[k, 3]
        ck, sk, Lk, p = c[k], s[k], L[k], phi[k]
        f = 1.0 / (1.0 + p)
        if table[k, 1] > 0:                       # a point load (px, py, mz) at a
            px, py = table[k, 4], table[k, 5]
            if not member_axes:
                px, py = ck * px + sk * py, -sk * px + ck * py
            mz = table[k, 6]
            xi = a / Lk
            xi2 = xi * xi
            _deflections(nv, xi, xi2, xi3[k, 0], f, Lk, p)
            out[k, 0] = px * (1 - xi)
            out[k, 3] = px * xi
            out[k, 1] = py * nv[0] + mz * (f * (6 * (xi2 - xi) / Lk))
            out[k, 2] = py * nv[1] + mz * (f * (1 - 4 * xi + 3 * xi2 + p * (1 - xi)))
            out[k, 4] = py * nv[2] + mz * (f * (6 * (xi - xi2) / Lk))
            out[k, 5] = py * nv[3] + mz * (f * (-2 * xi + 3 * xi2 + p * xi))
        elif b > a:                               # a trapezoid on [a, b]
            w1x, w1y, w2x, w2y = table[k, 4], table[k, 5], table[k, 6], table[k, 7]
            if not member_axes:
                w1x, w1y = ck * w1x + sk * w1y, -sk * w1x + ck * w1y
                w2x, w2y = ck * w2x + sk * w2y, -sk * w2x + ck * w2y
            half = 0.5 * (b - a)
            for j in range(4):
                x = half * t[j] + 0.5 * (a + b)
                w = half * wg[j]
                u = (t[j] + 1.0) / 2.0
                qx = w1x + u * (w2x - w1x)
                qy = (w1y + u * (w2y - w1y)) * w
                xi = x / Lk
                _deflections(nv, xi, xi * xi, xi3[k, j], f, Lk, p)
                out[k, 0] += qx * (1 - xi) * w
                out[k, 3] += qx * xi * w
                for i in range(4):
                    terms[i, j] = nv[i] * qy
            for i in range(4):
                out[k, (1, 2, 4, 5)[i]] = (terms[i, 0] + terms[i, 2]) + (terms[i, 1] + terms[i, 3])
    return out


@njit
def _deflections(nv, xi, xi2, xi3, f, L, p):
    """Nv (v_i, θ_i, v_j, θ_j) at ξ = x/L into ``nv``."""
    nv[0] = f * (1 - 3 * xi2 + 2 * xi3 + p * (1 - xi))
    nv[1] = f * (L * (xi - 2 * xi2 + xi3 + 0.5 * p * (xi - xi2)))
    nv[2] = f * (3 * xi2 - 2 * xi3 + p * xi)
    nv[3] = f * (L * (-xi2 + xi3 - 0.5 * p * (xi - xi2)))


@njit
def free_blocks(k_ptr, k_ind, k_val, h_ptr, h_ind, h_val, fixed, translational):
    """The basic system's blocks on the free dofs, from K's and H's CSR
    arrays (stored order) and the fixed dofs: (free dofs, fixed dofs, κ —
    the largest |K_ii| over the free translational dofs, over all free
    ones where none is translational, 1 where that is 0 or nothing is
    free —, K_ff's entries (rows, columns, values: its exact zeros left
    out — a level member's axial-bending terms, nearly half of a beam's),
    κH_f's (values, rows, columns)), rows and columns counted among the
    free dofs."""
    N = fixed.shape[0]
    at = np.full(N, -1, np.int64)
    nf = 0
    for i in range(N):
        if not fixed[i]:
            at[i] = nf
            nf += 1
    free = np.empty(nf, np.int64)
    fixed_idx = np.empty(N - nf, np.int64)
    big_t, big, any_t = 0.0, 0.0, False
    q = 0
    for i in range(N):
        if fixed[i]:
            fixed_idx[q] = i
            q += 1
            continue
        free[at[i]] = i
        d = 0.0
        for p in range(k_ptr[i], k_ptr[i + 1]):
            if k_ind[p] == i:
                d += k_val[p]
        d = abs(d)
        big = max(big, d)
        if translational[i]:
            big_t = max(big_t, d)
            any_t = True
    kappa = (big_t if any_t else big) if nf else 1.0
    kappa = kappa if kappa > 0 else 1.0
    n = 0
    for i in range(N):
        if at[i] >= 0:
            for p in range(k_ptr[i], k_ptr[i + 1]):
                if at[k_ind[p]] >= 0 and k_val[p] != 0.0:
                    n += 1
    kr = np.empty(n, np.int64)
    kc = np.empty(n, np.int64)
    kv = np.empty(n)
    n = 0
    for i in range(N):
        if at[i] >= 0:
            for p in range(k_ptr[i], k_ptr[i + 1]):
                if at[k_ind[p]] >= 0 and k_val[p] != 0.0:
                    kr[n], kc[n], kv[n] = at[i], at[k_ind[p]], k_val[p]
                    n += 1
    m = 0
    for i in range(N):
        if at[i] >= 0:
            m += h_ptr[i + 1] - h_ptr[i]
    hv = np.empty(m)
    hr = np.empty(m, np.int64)
    hc = np.empty(m, np.int64)
    m = 0
    for i in range(N):
        if at[i] >= 0:
            for p in range(h_ptr[i], h_ptr[i + 1]):
                hv[m], hr[m], hc[m] = kappa * h_val[p], at[i], h_ind[p]
                m += 1
    return free, fixed_idx, kappa, (kr, kc, kv), (hv, hr, hc)


@njit
def link_terms(pos_dof, hv, flex, kappa, kin, coef, partner):
    """(rows, columns, values) of −κH_f C⁻¹ B in the band's order — each
    holding link's spring (its dofs ``pos_dof`` and values ``hv``, padded
    rows) and each slipping tangent's coupling to its normal link — and
    C⁻¹'s parts (diagonal, the slipping tangents, their normals, their
    entries): :func:`.banded_saddle._link_terms`, each product as NumPy's
    expressions made it (the same bits)."""
    nl, w = hv.shape
    cinv = np.empty(nl)
    for j in range(nl):
        cinv[j] = 1.0 / ((-(kappa * kappa)) * flex[j] if kin[j] else kappa)
    ns, nh = 0, 0
    for j in range(nl):
        if kin[j]:
            nh += 1
        elif coef[j] != 0.0:
            ns += 1
    slip = np.empty(ns, np.int64)
    held = np.empty(nh, np.int64)
    ns, nh = 0, 0
    for j in range(nl):
        if kin[j]:
            held[nh] = j
            nh += 1
        elif coef[j] != 0.0:
            slip[ns] = j
            ns += 1
    on = np.empty(ns, np.int64)
    off = np.empty(ns)
    for q in range(ns):
        on[q] = partner[slip[q]]
        off[q] = -cinv[slip[q]] * (kappa * coef[slip[q]]) * cinv[on[q]]
    n = (nh + ns) * w * w
    rows = np.empty(n, np.int64)
    cols = np.empty(n, np.int64)
    vals = np.empty(n)
    e = 0
    for q in range(nh + ns):
        left = held[q] if q < nh else slip[q - nh]
        right = held[q] if q < nh else on[q - nh]
        scale = -cinv[left] if q < nh else -off[q - nh]
        for a in range(w):
            x = hv[left, a] * scale
            for b in range(w):
                rows[e], cols[e], vals[e] = pos_dof[left, a], pos_dof[right, b], x * hv[right, b]
                e += 1
    return rows, cols, vals, cinv, slip, on, off


@njit
def band_storage(nf, bw, upper, kr, kc, kv, r, c, v):
    """K's scaled entries (kr, kc, kv: distinct) and the link terms (r, c, v)
    in LAPACK's band storage, held column by column (the C array of the
    transpose of the Fortran array LAPACK reads): with ``upper`` dpbtrf's
    (entries i ≤ j, row bw + i − j of column j: bw + 1 rows), else dgbtrf's
    (row 2bw + i − j: 3bw + 1 rows); each entry summed from zero, K's
    first, then the link terms in order."""
    rows = bw + 1 if upper else 3 * bw + 1
    shift = bw if upper else 2 * bw
    ab = np.zeros((nf, rows))
    for e in range(kr.shape[0]):
        if not upper or kr[e] <= kc[e]:
            ab[kc[e], shift + kr[e] - kc[e]] += kv[e]
    for e in range(r.shape[0]):
        if not upper or r[e] <= c[e]:
            ab[c[e], shift + r[e] - c[e]] += v[e]
    return ab
