"""O(nnz) loops of the multilevel method ("mg-bpp"), compiled with numba:
the sweeps, the truncated Galerkin products, and a whole TNNMG cycle
(:func:`tnnmg_cycle`: at n = 1e4 the Python around the cycle cost as much as
its arithmetic on the coarse levels).

Gauss–Seidel sweeps are sequential by nature (each row reads the values the
previous rows just wrote); as NumPy calls they would cost a Python loop per
row.  The Galerkin product R A P of a truncated hierarchy is rebuilt when the
contact set moves; one fused pass (a dense accumulator per coarse row) costs
a third of SciPy's two sparse products and their transposes, and as the set
moves only the coarse rows it touches are recomputed, in place on the
untruncated product's pattern (:func:`galerkin_values`, :func:`touched_rows`).
"""

from __future__ import annotations

import numpy as np
from ...core.compiled import njit


# The sweeps below are latency-bound, not bandwidth-bound: row i reads the
# value row i - 1 (forward; i + 1 backward) has just written, and a row's
# sum in column order puts that term in its middle, so each row waited for
# the whole chain of multiply-adds after it (a 13-point row: ~8 of them)
# while the previous row finished.  Each row therefore sums its other
# terms first — independent of the previous row, so they overlap it — and
# adds the just-written neighbour's term last: one multiply-add on the
# chain.  A plate's fine-level sweep (10⁴ unknowns) 0.17 → 0.10 ms, a
# Galerkin level's (25 a row) 0.051 → 0.036 ms; docs/dev-notes.md, round
# seven.  The other terms' order is unchanged, so a sweep differs from the
# plain column-order sum in rounding only (``last`` adds, so a row that
# stored that neighbour twice still sums both).  The two directions are
# written out: one loop with the direction as a variable, or a shared row
# helper, measured as slow as the plain sum.


@njit
def projected_gauss_seidel(indptr, indices, data, inv_diag, q, z, sweeps):
    """``sweeps`` projected Gauss–Seidel sweeps for LCP(M, q), alternating
    forward and backward (a symmetric smoother), in place:
    z_i <- max(0, z_i − (M z + q)_i / M_ii).  M in CSR (symmetric);
    ``inv_diag`` = 1 / diag(M): a product where a division would stall each
    row (the rows are sequential), 1.6 x faster on a membrane's sweep."""
    n = z.size
    for s in range(sweeps):
        if s % 2 == 0:
            for i in range(n):
                r = q[i]
                last = 0.0
                for p in range(indptr[i], indptr[i + 1]):
                    j = indices[p]
                    if j == i - 1:
                        last += data[p]
                    else:
                        r += data[p] * z[j]
                if i > 0:
                    r += last * z[i - 1]
                v = z[i] - r * inv_diag[i]
                z[i] = v if v > 0.0 else 0.0
        else:
            for i in range(n - 1, -1, -1):
                r = q[i]
                last = 0.0
                for p in range(indptr[i], indptr[i + 1]):
                    j = indices[p]
                    if j == i + 1:
                        last += data[p]
                    else:
                        r += data[p] * z[j]
                if i < n - 1:
                    r += last * z[i + 1]
                v = z[i] - r * inv_diag[i]
                z[i] = v if v > 0.0 else 0.0


@njit
def gauss_seidel(indptr, indices, data, inv_diag, b, x, free, forward):
    """One Gauss–Seidel sweep for A x = b on the rows where ``free`` (the
    others keep their value, zero for a truncated correction), in place."""
    n = x.size
    if forward:
        for i in range(n):
            if free[i]:
                r = b[i]
                last = 0.0
                for p in range(indptr[i], indptr[i + 1]):
                    j = indices[p]
                    if j == i - 1:
                        last += data[p]
                    else:
                        r -= data[p] * x[j]
                if i > 0:
                    r -= last * x[i - 1]
                x[i] += r * inv_diag[i]
    else:
        for i in range(n - 1, -1, -1):
            if free[i]:
                r = b[i]
                last = 0.0
                for p in range(indptr[i], indptr[i + 1]):
                    j = indices[p]
                    if j == i + 1:
                        last += data[p]
                    else:
                        r -= data[p] * x[j]
                if i < n - 1:
                    r -= last * x[i + 1]
                x[i] += r * inv_diag[i]


@njit
def _galerkin_row(I, r_ptr, r_idx, r_val, a_ptr, a_idx, a_val, p_ptr, p_idx, p_val, keep,
                  acc, mark, cols):
    """Row I of R diag(keep) A diag(keep) P into the accumulator ``acc``: the
    columns it reaches, in the order first reached, go to ``cols`` (their
    count returned) and are marked I in ``mark``; acc holds their values."""
    m = 0
    for a in range(r_ptr[I], r_ptr[I + 1]):
        i = r_idx[a]
        if not keep[i]:
            continue
        wi = r_val[a]
        for b in range(a_ptr[i], a_ptr[i + 1]):
            k = a_idx[b]
            if not keep[k]:
                continue
            wik = wi * a_val[b]
            for c in range(p_ptr[k], p_ptr[k + 1]):
                J = p_idx[c]
                if mark[J] != I:
                    mark[J] = I
                    acc[J] = 0.0
                    cols[m] = J
                    m += 1
                acc[J] += wik * p_val[c]
    return m


@njit
def galerkin(r_ptr, r_idx, r_val, a_ptr, a_idx, a_val, p_ptr, p_idx, p_val, keep, nc):
    """C = R diag(keep) A diag(keep) P in CSR (R = P', all CSR), rows of C in
    order, columns unsorted.  ``keep`` truncates the fine level."""
    acc = np.zeros(nc)
    mark = np.full(nc, -1, dtype=np.int64)
    cols = np.empty(nc, dtype=np.int64)
    cap = max(16, 9 * nc)
    out_idx = np.empty(cap, dtype=np.int64)
    out_val = np.empty(cap)
    out_ptr = np.zeros(nc + 1, dtype=np.int64)
    nnz = 0
    for I in range(nc):
        m = _galerkin_row(I, r_ptr, r_idx, r_val, a_ptr, a_idx, a_val, p_ptr, p_idx, p_val,
                          keep, acc, mark, cols)
        if nnz + m > cap:
            cap = max(2 * cap, nnz + m)
            grown_idx = np.empty(cap, dtype=np.int64)
            grown_val = np.empty(cap)
            grown_idx[:nnz] = out_idx[:nnz]
            grown_val[:nnz] = out_val[:nnz]
            out_idx, out_val = grown_idx, grown_val
        for t in range(m):
            J = cols[t]
            out_idx[nnz] = J
            out_val[nnz] = acc[J]
            nnz += 1
        out_ptr[I + 1] = nnz
    return out_ptr, out_idx[:nnz].copy(), out_val[:nnz].copy()


@njit
def galerkin_values(r_ptr, r_idx, r_val, a_ptr, a_idx, a_val, p_ptr, p_idx, p_val, keep,
                    c_ptr, c_idx, c_val, rows):
    """The rows ``rows`` of C = R diag(keep) A diag(keep) P written into
    c_val, in place, on C's pattern (c_ptr, c_idx): the untruncated
    product's, which holds every truncated one (a truncated entry is stored
    as 0).  The same sums in the same order as :func:`galerkin`, so the same
    bits; but as the pattern holds every column a row can reach, the
    accumulator is cleared on it before the row, and the innermost loop
    adds without asking whether a column is new (the truncated rows are
    most of what the cycles recompute: docs/dev-notes.md, round seven)."""
    nc = c_ptr.size - 1
    acc = np.zeros(nc)
    for t in range(rows.size):
        I = rows[t]
        for c in range(c_ptr[I], c_ptr[I + 1]):
            acc[c_idx[c]] = 0.0
        for a in range(r_ptr[I], r_ptr[I + 1]):
            i = r_idx[a]
            if not keep[i]:
                continue
            wi = r_val[a]
            for b in range(a_ptr[i], a_ptr[i + 1]):
                k = a_idx[b]
                if not keep[k]:
                    continue
                wik = wi * a_val[b]
                for c in range(p_ptr[k], p_ptr[k + 1]):
                    acc[p_idx[c]] += wik * p_val[c]
        for c in range(c_ptr[I], c_ptr[I + 1]):
            c_val[c] = acc[c_idx[c]]


@njit
def touched_rows(b_ptr, b_idx, p_ptr, p_idx, changed, nc):
    """The rows of R diag(keep) B diag(keep) P (R = P') that move when B's
    rows and columns, or ``keep``, change at the fine unknowns ``changed``
    (bool), B's pattern fixed: C_IJ = sum R_Ii keep_i B_ik keep_k P_kJ moves
    only if i or k changed, so i is a changed unknown or a neighbour of one
    in B's pattern and I a coarse function P spreads over i (C is symmetric:
    a moved column J is a moved row J, the same set)."""
    n = changed.size
    near = changed.copy()
    for i in range(n):
        if changed[i]:
            for p in range(b_ptr[i], b_ptr[i + 1]):
                near[b_idx[p]] = True
    out = np.zeros(nc, dtype=np.bool_)
    for i in range(n):
        if near[i]:
            for p in range(p_ptr[i], p_ptr[i + 1]):
                out[p_idx[p]] = True
    return out


@njit
def aggregate(indptr, indices, data, diag, theta):
    """Greedy aggregation on the strength graph |a_ij| >= theta sqrt(a_ii a_jj)
    (Vaněk, Mandel, Brezina): pass 1 makes a node whose strong neighbours are
    all free the root of a new aggregate with them; pass 2 joins every node
    left to the aggregate of a strong neighbour; pass 3 makes aggregates of
    what remains (isolated nodes).  Returns (aggregate of each node, count)."""
    n = diag.size
    agg = np.full(n, -1, dtype=np.int64)
    count = 0
    for i in range(n):
        if agg[i] >= 0:
            continue
        free = True
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if j != i and abs(data[p]) >= theta * np.sqrt(abs(diag[i] * diag[j])) and agg[j] >= 0:
                free = False
                break
        if not free:
            continue
        agg[i] = count
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if j != i and abs(data[p]) >= theta * np.sqrt(abs(diag[i] * diag[j])):
                agg[j] = count
        count += 1
    joined = agg.copy()
    for i in range(n):
        if agg[i] >= 0:
            continue
        best, best_w = -1, 0.0
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            w = abs(data[p]) / np.sqrt(abs(diag[i] * diag[j]))
            if j != i and agg[j] >= 0 and w >= theta and w > best_w:
                best, best_w = agg[j], w
        joined[i] = best
    for i in range(n):
        if joined[i] < 0:
            joined[i] = count
            count += 1
    return joined, count


@njit
def same_csr(ptr, idx, val, ptr2, idx2, val2):
    """Whether two CSR matrices' arrays hold the same entries, index widths
    aside (a kept setup's check of the operator it was built on: one pass,
    no copy, ended at the first difference)."""
    if ptr.size != ptr2.size or idx.size != idx2.size:
        return False
    for i in range(ptr.size):
        if ptr[i] != ptr2[i]:
            return False
    for p in range(idx.size):
        if idx[p] != idx2[p] or val[p] != val2[p]:
            return False
    return True


# --- one TNNMG cycle, whole (multigrid._Levels packs its arguments) ---------
#
# A level's hierarchy is packed into flat arrays, one segment per level k
# (k = 0 the level being cycled, k = m the coarsest): the operators' CSR
# arrays (``a_ptr`` segments of n_k + 1 row pointers local to the level,
# ``a_idx``/``a_val`` segments of its entries; ``pofs``, ``nofs`` the
# segments' starts), the prolongations P_k and restrictions R_k = P_k' alike,
# and vectors by ``rofs``.  Level 0's values are M's; the coarse levels'
# values are the truncated Galerkin products, on the untruncated products'
# patterns, rewritten in place as the truncation moves.


@njit
def _segment(ptr, idx, val, pofs, nofs, k):
    return (ptr[pofs[k]:pofs[k + 1]], idx[nofs[k]:nofs[k + 1]], val[nofs[k]:nofs[k + 1]])


@njit
def _matvec(ptr, idx, val, x, y):
    """y = A x (A in CSR)."""
    for i in range(y.size):
        s = 0.0
        for p in range(ptr[i], ptr[i + 1]):
            s += val[p] * x[idx[p]]
        y[i] = s


@njit
def _coarsest_factor(ptr, idx, val, keep, factor, kept):
    """Cholesky's lower factor of the coarsest operator on its kept rows,
    into ``factor``, and their indices into ``kept`` (their count in
    kept[-1]).  Where the truncated coarse functions are dependent, the
    factor of the operator plus 1e-10 of its diagonal; where even that
    fails, none.  Returns 0 (a factor) or 1 (none: the cycle sweeps the
    level instead)."""
    n = keep.size
    m = 0
    where = np.full(n, -1, dtype=np.int64)
    for i in range(n):
        if keep[i]:
            where[i] = m
            kept[m] = i
            m += 1
    kept[n] = m
    B = np.zeros((m, m))
    for i in range(n):
        if keep[i]:
            for p in range(ptr[i], ptr[i + 1]):
                j = where[idx[p]]
                if j >= 0:
                    B[where[i], j] = val[p]
    for attempt in range(2):
        try:
            factor[:m, :m] = np.linalg.cholesky(B)
            return 0
        except Exception:   # truncated coarse functions dependent: regularize once
            for a in range(m):
                B[a, a] *= 1.0 + 1e-10
    return 1


@njit
def _coarsest_solve(factor, kept, b, x):
    """x = the coarsest operator's solve of b on the kept rows (0 elsewhere)."""
    x[:] = 0.0
    n = x.size
    m = kept[n]
    y = np.empty(m)
    for a in range(m):
        y[a] = b[kept[a]]
    for a in range(m):                 # L y' = y
        s = y[a]
        for c in range(a):
            s -= factor[a, c] * y[c]
        y[a] = s / factor[a, a]
    for a in range(m - 1, -1, -1):     # L' x = y'
        s = y[a]
        for c in range(a + 1, m):
            s -= factor[c, a] * y[c]
        y[a] = s / factor[a, a]
    for a in range(m):
        x[kept[a]] = y[a]


@njit
def _truncate(H, S, changed):
    """Keep the coarse operators equal to R T B T P for the truncation T of
    level 0 (S's free[0]) after ``changed`` of its unknowns moved: each
    level's rows that a moved unknown reaches are recomputed in place
    (:func:`touched_rows`, :func:`galerkin_values`), the next level's moved
    set those rows and the rows whose own truncation changed.  Returns
    whether the coarsest level's operator moved (its factor is then stale)."""
    a_ptr, a_idx, a_val, pofs, nofs, p_ptr, p_idx, p_val, ppofs, pnofs, \
        r_ptr, r_idx, r_val, rpofs, rnofs, diagpos, dofs, rofs = H
    free, inv_diag = S[0], S[1]
    m = pofs.size - 2
    for k in range(m):
        bp, bi, bv = _segment(a_ptr, a_idx, a_val, pofs, nofs, k)
        pp, pi, pv = _segment(p_ptr, p_idx, p_val, ppofs, pnofs, k)
        rp, ri, rv = _segment(r_ptr, r_idx, r_val, rpofs, rnofs, k)
        cp, ci, cv = _segment(a_ptr, a_idx, a_val, pofs, nofs, k + 1)
        nc = cp.size - 1
        touched = touched_rows(bp, bi, pp, pi, changed, nc)
        rows = np.flatnonzero(touched)
        if rows.size == 0:
            return False          # nothing below this level moved
        keep = free[rofs[k]:rofs[k + 1]]
        galerkin_values(rp, ri, rv, bp, bi, bv, pp, pi, pv, keep, cp, ci, cv, rows)
        d = np.empty(nc)
        top = 1e-300
        for i in range(nc):
            d[i] = cv[diagpos[dofs[k] + i]]
            top = max(top, d[i])
        old = free[rofs[k + 1]:rofs[k + 2]]
        changed = touched.copy()
        dc = inv_diag[rofs[k + 1]:rofs[k + 2]]
        for i in range(nc):
            kept = d[i] > 1e-13 * top      # PSD: a zero diagonal entry is a zero row
            if kept != old[i]:
                changed[i] = True
            old[i] = kept
            dc[i] = 1.0 / d[i] if kept else 1.0
    return True


@njit
def retruncate(H, S, changed):
    """The coarse operators and the coarsest level's factor brought to level
    0's truncation (S's free) after ``changed`` of its unknowns moved.
    Returns whether anything was recomputed."""
    if not _truncate(H, S, changed):
        return False
    mode = S[7]
    if mode[0] != 2:
        a_ptr, a_idx, a_val, pofs, nofs, rofs = H[0], H[1], H[2], H[3], H[4], H[17]
        m = pofs.size - 2
        ap, ai, av = _segment(a_ptr, a_idx, a_val, pofs, nofs, m)
        mode[0] = _coarsest_factor(ap, ai, av, S[0][rofs[m]:rofs[m + 1]], S[5], S[6])
    return True


@njit
def cycle(H, S, b0, visits):
    """One multigrid cycle for (T A T) c = T b0 (T the truncations of S's
    free): on each level a forward Gauss–Seidel sweep, the residual
    restricted, ``visits`` visits of the level below (1: a V-cycle, 2: a
    W-cycle; the coarsest level's dense solve once), each level's prolonged
    correction and a backward sweep.  Symmetric for every ``visits``.
    Returns level 0's c."""
    a_ptr, a_idx, a_val, pofs, nofs, p_ptr, p_idx, p_val, ppofs, pnofs, \
        r_ptr, r_idx, r_val, rpofs, rnofs, diagpos, dofs, rofs = H
    free, inv_diag, x, b, t, factor, kept, mode = S[0], S[1], S[2], S[3], S[4], S[5], S[6], S[7]
    m = pofs.size - 2
    done = np.zeros(m + 1, dtype=np.int64)      # visits of the level below, per level
    b[rofs[0]:rofs[1]] = b0
    x[rofs[0]:rofs[1]] = 0.0
    k = 0
    while True:
        # down from level k: a sweep from its current x, the residual restricted
        while k < m:
            lo, hi = rofs[k], rofs[k + 1]
            ap, ai, av = _segment(a_ptr, a_idx, a_val, pofs, nofs, k)
            xk, bk, tk, fk = x[lo:hi], b[lo:hi], t[lo:hi], free[lo:hi]
            gauss_seidel(ap, ai, av, inv_diag[lo:hi], bk, xk, fk, True)
            _matvec(ap, ai, av, xk, tk)
            for i in range(hi - lo):
                tk[i] = bk[i] - tk[i] if fk[i] else 0.0
            rp, ri, rv = _segment(r_ptr, r_idx, r_val, rpofs, rnofs, k)
            _matvec(rp, ri, rv, tk, b[rofs[k + 1]:rofs[k + 2]])
            x[rofs[k + 1]:rofs[k + 2]] = 0.0
            done[k] = 0
            k += 1
        lo, hi = rofs[m], rofs[m + 1]
        if mode[0] == 0:
            _coarsest_solve(factor, kept, b[lo:hi], x[lo:hi])
        else:               # no factor (too large, or singular): Gauss–Seidel sweeps
            ap, ai, av = _segment(a_ptr, a_idx, a_val, pofs, nofs, m)
            for s in range(COARSE_SWEEPS):
                gauss_seidel(ap, ai, av, inv_diag[lo:hi], b[lo:hi], x[lo:hi], free[lo:hi],
                             s % 2 == 0)
        # up: each level adds its coarse correction and sweeps back, unless
        # it visits the level below again (the coarsest is solved once)
        again = False
        while k > 0 and not again:
            k -= 1
            done[k] += 1
            if done[k] < visits and k + 1 < m:
                k += 1
                again = True
                continue
            lo, hi = rofs[k], rofs[k + 1]
            pp, pi, pv = _segment(p_ptr, p_idx, p_val, ppofs, pnofs, k)
            tk, xk, fk = t[lo:hi], x[lo:hi], free[lo:hi]
            _matvec(pp, pi, pv, x[rofs[k + 1]:rofs[k + 2]], tk)
            for i in range(hi - lo):
                if fk[i]:
                    xk[i] += tk[i]
            ap, ai, av = _segment(a_ptr, a_idx, a_val, pofs, nofs, k)
            gauss_seidel(ap, ai, av, inv_diag[lo:hi], b[lo:hi], xk, fk, False)
        if not again:
            return x[rofs[0]:rofs[1]]


@njit
def unconstrained_gap(H, S, q, steps, rtol, visits):
    """(x, steps taken, max|A x + q| / max|q|): x ≈ −A⁻¹q, A level 0 of
    the packed hierarchy H, by conjugate gradients preconditioned with one
    untruncated cycle (:func:`cycle` with every unknown free, ``visits`` 1 a
    V-cycle, 2 a W-cycle: symmetric, forward sweeps down and backward sweeps
    up, an exact coarsest solve),
    until the residual is at ``rtol`` of q or after ``steps`` steps.  Leaves
    S untruncated; the first TNNMG cycle on any level truncates it afresh."""
    a_ptr, a_idx, a_val, pofs, nofs, rofs = H[0], H[1], H[2], H[3], H[4], H[17]
    free, inv_diag = S[0], S[1]
    m = pofs.size - 2
    for k in range(m + 1):
        ap, ai, av = _segment(a_ptr, a_idx, a_val, pofs, nofs, k)
        lo = rofs[k]
        for i in range(rofs[k + 1] - lo):
            free[lo + i] = True
            for p in range(ap[i], ap[i + 1]):
                if ai[p] == i:
                    inv_diag[lo + i] = 1.0 / av[p]
    mode = S[7]
    if mode[0] != 2:
        ap, ai, av = _segment(a_ptr, a_idx, a_val, pofs, nofs, m)
        mode[0] = _coarsest_factor(ap, ai, av, free[rofs[m]:rofs[m + 1]], S[5], S[6])
    ap, ai, av = _segment(a_ptr, a_idx, a_val, pofs, nofs, 0)
    n = q.size
    x = np.zeros(n)
    r = np.empty(n)
    scale = 0.0
    for i in range(n):
        r[i] = -q[i]
        scale = max(scale, abs(q[i]))
    if scale == 0.0:
        return x, 0, 0.0
    z = cycle(H, S, r, visits).copy()
    p = z.copy()
    rz = 0.0
    for i in range(n):
        rz += r[i] * z[i]
    Ap = np.empty(n)
    res = 1.0
    taken = 0
    for taken in range(1, steps + 1):
        _matvec(ap, ai, av, p, Ap)
        pAp = 0.0
        for i in range(n):
            pAp += p[i] * Ap[i]
        if not pAp > 0.0:
            break
        alpha = rz / pAp
        res = 0.0
        for i in range(n):
            x[i] += alpha * p[i]
            r[i] -= alpha * Ap[i]
            res = max(res, abs(r[i]))
        res /= scale
        if res <= rtol or taken == steps:     # no preconditioning for a step not taken
            break
        z[:] = cycle(H, S, r, visits)
        rz_new = 0.0
        for i in range(n):
            rz_new += r[i] * z[i]
        beta = rz_new / rz
        rz = rz_new
        for i in range(n):
            p[i] = z[i] + beta * p[i]
    return x, taken, res


#: Gauss–Seidel sweeps (alternating in direction) that stand for the solve
#: on a coarsest level too large to factorize densely: aggregation leaves
#: one that large typically where no connection is strong, a diagonally
#: dominant operator, on which the sweeps converge fast (the 2.5-diagonal
#: chain, 2e4 unknowns: the same 5 cycles as the sparse LDLᵀ it replaced).
COARSE_SWEEPS = 8


@njit
def tnnmg_cycle(H, S, q, z, previous, first, residual_wanted, visits):
    """One TNNMG cycle on LCP(A, q), A level 0 of the packed hierarchy H,
    from z (in place): a projected Gauss–Seidel sweep, the truncation at
    the unknowns left free, the coarse operators brought to it, one cycle
    (``visits`` 1: a V-cycle, 2: a W-cycle; :func:`cycle`) for the
    truncated Newton correction, its projection and exact line
    search, two projected sweeps (forward, then backward).  ``previous``
    (the set free after the last cycle) is updated.  Returns (unknowns whose
    membership in the free set changed, unknowns at the obstacle, whether the
    truncated operators moved, the natural-map residual max|min(A_ii z_i,
    (Az + q)_i)| — computed where ``residual_wanted`` is 2, or 1 and the
    free set held this cycle; inf otherwise)."""
    a_ptr, a_idx, a_val, pofs, nofs, rofs = H[0], H[1], H[2], H[3], H[4], H[17]
    free, inv_diag = S[0], S[1]
    n = z.size
    ap, ai, av = _segment(a_ptr, a_idx, a_val, pofs, nofs, 0)
    d = inv_diag[rofs[0]:rofs[1]]
    projected_gauss_seidel(ap, ai, av, d, q, z, 1)
    r = np.empty(n)
    _matvec(ap, ai, av, z, r)
    changed = np.zeros(n, dtype=np.bool_)
    f0 = free[rofs[0]:rofs[1]]
    for i in range(n):
        r[i] = -(r[i] + q[i])
        now = z[i] > 0.0
        if first or now != f0[i]:
            changed[i] = True
        f0[i] = now
    moved = first
    for i in range(n):
        if changed[i]:
            moved = True
            break
    if moved:
        retruncate(H, S, changed)
    b0 = np.empty(n)
    for i in range(n):
        b0[i] = r[i] if f0[i] else 0.0
    c = cycle(H, S, b0, visits)
    num = 0.0
    cap = np.inf
    for i in range(n):
        if c[i] < -z[i]:
            c[i] = -z[i]
        num += r[i] * c[i]
        if c[i] < 0.0:
            cap = min(cap, z[i] / -c[i])
    Ac = np.empty(n)
    _matvec(ap, ai, av, c, Ac)
    den = 0.0
    for i in range(n):
        den += c[i] * Ac[i]
    alpha = num / den if den > 0 else 0.0
    alpha = min(alpha, cap)
    if alpha > 0:
        for i in range(n):
            v = z[i] + alpha * c[i]
            z[i] = v if v > 0.0 else 0.0
    projected_gauss_seidel(ap, ai, av, d, q, z, 2)
    count, at = 0, 0
    for i in range(n):
        now = z[i] > 0.0
        if now != previous[i]:
            count += 1
        previous[i] = now
        if not now:
            at += 1
    if first:
        count = n
    res = np.inf
    if residual_wanted == 2 or (residual_wanted == 1 and count == 0):
        _matvec(ap, ai, av, z, r)
        res = 0.0
        for i in range(n):
            res = max(res, abs(min(z[i] / d[i], r[i] + q[i])))
    return count, at, moved, res
