"""The saddle system of a frame on elastic contacts, solved through its
condensed stiffness with LAPACK's banded LU (as OpenSees' band solvers
factor K with the contact springs in it).

The basic system and every state set of the sparse active set
(:mod:`.contact_lcp`, :mod:`..plane.sparse_active_set`) solve

    [K_ff  κH_f] [x]   [r_1]
    [B     C   ] [y] = [r_2],          X = −κ y,

one row of (B, C) per link (κ: the largest translational stiffness of K,
which scales the link rows).  Where the link holds, B's row is κh' and C's
entry −κ²/k: the link's displacement h'u plus its spring's compression
X/k is prescribed.  Where it does not, B's row is zero and C's row is
static: κ on its diagonal (an open link: X = 0), and κf on its normal
link's column for a slipping tangent (X_t = ∓f X_n).  Where every contact
is elastic (k finite), C is invertible and its inverse explicit: diagonal,
plus for a slipping tangent t on its normal n the entry −C_tt⁻¹ C_tn C_nn⁻¹
(a normal link's row of C has no off-diagonal entry, so C's off-diagonal
part is nilpotent).  Eliminating y,

    (K_ff − κH_f C⁻¹ B) x = r_1 − κH_f C⁻¹ r_2,     y = C⁻¹ (r_2 − B x),

where K_ff − κH_f C⁻¹ B is K_ff with each holding link's spring k h h' [kN/m]
and each slipping contact's friction coupling (f k h_t h_n', unsymmetric)
added: a matrix with K's own sparsity, banded in the dofs' own order or a
reverse Cuthill–McKee one (a continuous beam: 4 wide in its own, a
20-storey tower 29 in RCM's).  LAPACK factors it in a sixth of SuperLU's
time on the saddle matrix (0.10 against 0.61 ms at 1 202 dofs, 0.47
against 2.6 at 6 002): SuperLU's cost at these sizes is its set-up per
unknown, not arithmetic.  Every link holding (the basic system), it is
symmetric positive definite: a band wider than NARROW is then factorized
by Cholesky, whose link rows (the contact stiffness R) take one forward
solve per link (:func:`factor`, :meth:`CondensedLU.link_rows`).

What eliminating y costs in accuracy: the link force comes out as
X = k (Δ − h'u), a difference of displacements times k, with an error of
about eps·k·|u| where the saddle solve has eps·κ|u|.  So the route is
taken only where every contact's k is at most CONDENSE_MAX·κ; a contact
much stiffer than the frame, and a rigid one (no spring to condense), keep
the saddle matrix's SuperLU (:func:`.contact_lcp.regular_lu`), as does a
frame whose band is wider than BAND_MAX (a banded LU's work grows as the
band's square).  Singular pivots (a mechanism) send the caller to the
saddle matrix's SuperLU too, which decides as before.  A single right-hand
side is refined once on the saddle matrix's own residual
(:meth:`CondensedLU.solve` says why).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg.lapack import dgbtrf, dgbtrs, dpbtrf, dpbtrs, dtbtrs

#: contacts at most this many times stiffer than the frame's largest
#: translational stiffness κ are condensed (X's error eps·k|u| within
#: CONDENSE_MAX of the saddle solve's)
CONDENSE_MAX = 1e3
#: the widest band factorized (half-bandwidth, dofs): a band LU's work
#: and a solve's grow as the width's square and the width, SuperLU's here
#: hardly with either.  A beam's 4 is 3–6 times faster at every step; the
#: 20-storey tower's 29 (reverse Cuthill–McKee), with its basic system by
#: Cholesky and R by forward solves (:func:`factor`), takes 0.09 ms to
#: factor against SuperLU's 0.58 and 0.33 ms for R against 0.45; the
#: 10-storey space tower's 100 stays with SuperLU
BAND_MAX = 32
#: a band this narrow in the dofs' own order is kept (no reordering)
NARROW = 12
#: a frame with fewer free dofs keeps the saddle matrix's SuperLU when its
#: own order is wider than NARROW: SuperLU costs little there, and a
#: 60-dof space table on soft pads, reordered (band 29), had its collapse
#: bracket widen from 1e-7 to 2.5e-4 of the load — the Farkas proofs just
#: above the last equilibrium read R's rounding (the tests'
#: test_a_corner_push_collapse_is_bracketed_as_narrowly_as_certified).  The
#: 20-storey tower (291 free dofs) is reordered
REORDER_MIN = 200
#: the same singularity test as the saddle matrix's LU
SINGULAR_PIVOTS = 1e-13


def layout(nf, nl, kappa, flex, k_triplets, h_triplets, pairs, stiffness):
    """What every factorization of one assembly shares: K_ff's part of the
    band, the links' columns of κH_f (padded to the widest), the band order
    and its width, the scaling — or None where the route does not apply (a
    rigid or a very stiff contact, no link, a band wider than BAND_MAX).
    ``k_triplets``: K_ff's (rows, columns, values), summed; ``h_triplets``:
    κH_f's (dofs, links, values); ``pairs``: (t, n), the links a slipping
    tangent couples (its contact's normal): a level beam's axial and
    bending dofs are two chains K does not join, which the order must keep
    near each other where friction joins them; ``stiffness``: (K, free
    dofs), K over all dofs, whose product at the free dofs is K_ff's (a
    refinement's residual: :meth:`CondensedLU.solve`)."""
    flex = np.asarray(flex, float)
    if nf == 0 or nl == 0 or not np.all(flex > 0) or 1.0 / flex.min() > CONDENSE_MAX * kappa:
        return None
    kr, kc, kv = k_triplets
    if nf < REORDER_MIN and np.abs(kr - kc).max(initial=0) > NARROW:
        return None                  # too wide in its own order, too small to reorder
    from ._frame_kernels import band_pattern, cuthill_mckee, link_slots
    # κH_f's entries link by link (its CSC order), and each link's dofs
    # padded with its own first dof (and a zero), which keeps the padding
    # inside the band
    h_dof, h_link, h_val, dof, hv = link_slots(nl, *h_triplets)
    # the pattern: K's, and each link's dofs among themselves (its spring)
    # and with its contact's other link (friction's coupling: same dofs)
    t, n = (np.zeros(0, int), np.zeros(0, int)) if pairs is None else pairs
    bw, indptr, indices, degree = band_pattern(nf, kr, kc, dof, t, n)
    # the dofs' own order where it is narrow already (a beam numbered
    # along its length: 4), else a reverse Cuthill–McKee order, whichever
    # is narrower (a beam's RCM order interleaves its axial and bending
    # chains 8 wide; the work goes as the width's square): scipy's, step
    # for step and from its own seeds (np.argsort of the degrees), in one
    # compiled pass with the pattern (as array expressions and scipy's
    # call: the layout was 182 µs of a 20-storey tower's 1 025 µs build)
    perm, pos = np.arange(nf), np.arange(nf)
    if bw > NARROW:
        rcm, rcm_pos, rcm_bw = cuthill_mckee(indptr, indices, degree, np.argsort(degree))
        if rcm_bw < bw:
            perm, pos, bw = rcm, rcm_pos, rcm_bw
    if bw > BAND_MAX:
        return None
    # κH_f's entries link by link (its CSC order), which its products read
    # (:func:`_links_to_dofs`, :func:`_dofs_to_links`)
    lay = dict(nf=nf, nl=nl, kappa=kappa, flex=flex, pos=pos, pos_dof=pos[dof], hv=hv,
               perm=perm, bw=bw, h=(h_dof, h_link, h_val), K=stiffness)
    # K's part of the band, once per assembly, scaled by powers of two
    # (exact), row and column i by the square root of the basic system's
    # diagonal entry (K's with every spring in), so that the pivots measure
    # singularity, not units: K plus springs is positive definite, so
    # |a_ij| <= sqrt(a_ii a_jj) and its scaled entries are at most 1.  A
    # state set's matrix has fewer springs: its entries are at most 1 too.
    # (The basic system's link terms, every link holding, are kept for its
    # factor.)
    lay["basic_terms"] = _link_terms(lay, np.ones(nl, bool), np.zeros(nl), np.zeros(nl, int))
    r, c, v = lay["basic_terms"][:3]
    on_diag = r == c
    diag = np.bincount(r[on_diag], weights=v[on_diag], minlength=nf)
    kr, kc = pos[kr], pos[kc]        # K's entries in the band's order
    kd = kr == kc
    diag += np.bincount(kr[kd], weights=kv[kd], minlength=nf)
    if not np.all(diag > 0):
        return None
    d = 2.0 ** -np.round(0.5 * np.log2(diag))
    # K's scaled entries in the band's order, which a factorization lays
    # out in LAPACK's band storage (:func:`._frame_kernels.band_storage`)
    lay.update(d=d, K_band=(kr, kc, kv * d[kr] * d[kc]))
    return lay


def _link_terms(lay, kin, coef, partner):
    """(rows, columns, values) of −κH_f C⁻¹ B in the band's order — each
    holding link's spring and each slipping tangent's coupling to its
    normal — and C⁻¹'s parts (diagonal, the slipping tangents, their
    normals, their entries), in one compiled pass
    (:func:`._frame_kernels.link_terms`)."""
    from ._frame_kernels import link_terms
    return link_terms(lay["pos_dof"], lay["hv"], lay["flex"], lay["kappa"],
                      np.asarray(kin, bool), np.asarray(coef, float), np.asarray(partner, np.int64))


def factor(lay, kin, coef, partner):
    """The condensed factorization of the state set whose links ``kin``
    hold (the others static; ``coef``: f·slip on a slipping tangent,
    coupling it to its normal link ``partner``), or None where its pivots
    say singular.  By LU (dgbtrf: a slipping contact's coupling is
    unsymmetric), but for the basic system (every link holding, none
    slipping: K plus springs, symmetric positive definite) of a band wider
    than NARROW, which is factorized by Cholesky (dpbtrf, as OpenSees'
    BandSPD): the contact stiffness R then takes one forward solve per
    link (:meth:`CondensedLU.link_rows`), where the LU takes a forward and
    a backward one per column over a band half again as wide (a 20-storey
    tower, 29 wide: R's solves 0.10 ms, the LU's 0.7, SuperLU's on the
    saddle matrix 0.28).  A narrow band keeps the LU, and with it today's digits: a
    beam's R costs little either way, and a random beam whose LCP Lemke
    ends on a secondary ray (tests' random_beam(10)) proved "no
    equilibrium" with the LU's rounding of R and ran out of time with the
    Cholesky's."""
    nf, bw, d = lay["nf"], lay["bw"], lay["d"]
    # every link holding, none slips, whatever coef says: the layout's terms
    r, c, v, cinv, slip, on, off = (lay["basic_terms"] if kin.all()
                                    else _link_terms(lay, kin, coef, partner))
    if r.size and np.abs(r - c).max() > bw:     # a coupling the layout's pairs did not name
        return None
    v = v * d[r] * d[c]
    from ._frame_kernels import band_storage
    kr, kc, kv = lay["K_band"]
    if bw > NARROW and kin.all() and not slip.size:
        # the upper triangle as dpbtrf stores it (K_ff is symmetric to
        # rounding; the one solve of an answer is refined on S itself):
        # K's entries on or above the diagonal, and the link terms there
        # added to them; in LAPACK's storage held column by column, which
        # f2py hands over without a transposing copy
        ab = band_storage(nf, bw, True, kr, kc, kv, r, c, v)
        chol, info = dpbtrf(ab.T, lower=0, overwrite_ab=1)
        if info != 0:
            return None
        pivots = chol[bw] ** 2       # an LU's pivots without row exchanges
        band = (chol, None)
    else:
        ab = band_storage(nf, bw, False, kr, kc, kv, r, c, v)
        lu, piv, info = dgbtrf(ab.T, bw, bw, overwrite_ab=1)
        if info != 0:
            return None
        pivots = np.abs(lu[2 * bw])
        band = (lu, piv)
    if not pivots.min() > SINGULAR_PIVOTS * pivots.max():
        return None
    return CondensedLU(lay, band, cinv, slip, on, off, kin)


class CondensedLU:
    """Solves the state set's saddle system S x = rhs (one vector or a
    column per right-hand side) through the condensed banded LU: the
    interface of :class:`.contact_lcp.ScaledLU`."""

    def __init__(self, lay, band, cinv, slip, on, off, kin):
        # band: (LU, pivots) by dgbtrf, or (Cholesky factor, None) by dpbtrf
        self.lay, self.bw, self.d = lay, lay["bw"], lay["d"]
        self.lu, self.piv = band
        self.g = None
        self.cinv, self.slip, self.on, self.off, self.kin = cinv, slip, on, off, kin
        # C itself, for the residual: its diagonal and a slipping tangent's κf
        self.cdiag = 1.0 / cinv
        self.c_off = -off / (cinv[slip] * cinv[on])

    def _cinv(self, r):
        """C⁻¹ r (r: links, one column per right-hand side)."""
        out = self.cinv.reshape(-1, *([1] * (r.ndim - 1))) * r
        if self.slip.size:
            off = self.off.reshape(-1, *([1] * (r.ndim - 1)))
            out[self.slip] += off * r[self.on]
        return out

    def solve(self, rhs):
        """x with S x = rhs, and one step of refinement on S's own residual.
        Eliminating y loses what the saddle solve keeps where the frame is
        nearly free: a beam sliding 459 m on a few sticking contacts had its
        forces 2.3e-9 of the largest off the extended-precision answer
        (SuperLU on S: 5.5e-10), and its checks, which that error does not
        reach, let it through unpolished; refined, the answer satisfies S
        to rounding, and its equilibrium residual sends it to the polish as
        the saddle route's did.  Over 79 random frames on elastic contacts
        the refined answers are never farther from the polished ones than
        SuperLU's (worst 2.9e-10 both), for a second solve (0.04 ms at 1 202
        dofs).  One right-hand side only — an answer's or a state set's;
        the many-column solves (the contact stiffness R, the certificate's
        link stiffnesses) are R's and the error estimate's, not an answer's,
        and the refinement doubled them (3–9 ms of a 1000-span solve)."""
        rhs = np.asarray(rhs, float)
        x = self._solve(rhs)
        return x if rhs.ndim > 1 else x + self._solve(rhs - self._times(x))

    def link_rows(self, rhs, nl):
        """The link rows y (nl) of S⁻¹ rhs (columns) where nothing reads the
        dofs' rows: the contact stiffness R (a unit dislocation per link)
        and its load columns.  On the Cholesky factor A = UᵀU of the basic
        system (every link holding), B x = κH_fᵀ x = Gᵀ U⁻ᵀ D Pᵀ t with
        G = U⁻ᵀ D Pᵀ κH_f, and t = r_1 − κH_f z, so U⁻ᵀ D Pᵀ t =
        U⁻ᵀ D Pᵀ r_1 − G z: one forward solve for G's nl columns and for
        the columns where r_1 is not zero (R's unit columns have none),
        where solving for x took a forward and a backward solve of every
        column (a 20-storey tower: 0.10 against 0.23 ms in LAPACK)."""
        rhs = np.asarray(rhs, float)
        lay, nf = self.lay, self.lay["nf"]
        if self.piv is not None or rhs.ndim == 1:
            return self._solve(rhs)[nf:]
        r1, r2 = rhs[:nf], rhs[nf:]
        z = self._cinv(r2)
        first, g = self._g()
        w = -(g @ z)
        live = np.flatnonzero(np.any(r1 != 0.0, axis=0))
        if live.size:
            w[:, live] += dtbtrs(self.lu, self.d[:, None] * r1[lay["perm"]][:, live],
                                 uplo="U", trans="T")[0][first:]
        return z - self._cinv(g.T @ w)

    def contact_rows(self, kappa, r1, r2):
        """The link rows of S⁻¹ [0 r1; κI r2]: the links' unit
        dislocations (scaled by κ), then the columns r1 (dofs), r2 (links)
        — what the contact stiffness R and its load columns R_F are read
        from (:func:`.contact_lcp.contact_stiffness`).  On the Cholesky
        factor (:meth:`link_rows`) a unit column has C⁻¹ r_2 = κ C⁻¹_jj e_j
        and no load on the dofs: its G z is G's column j times κ C⁻¹_jj (the
        product's one nonzero term, the same number) and its forward solve
        is none — no (dofs + links) x (links + cases) right-hand side made,
        scanned for loads and multiplied."""
        nl = self.lay["nl"]
        if self.piv is not None:
            return self.link_rows(dislocations(kappa, r1, r2), nl)
        first, g = self._g()
        unit = self.cinv * kappa              # C⁻¹ κ e_j's one entry (no link slips)
        z = np.zeros((nl, nl + r1.shape[1]))
        z[np.arange(nl), np.arange(nl)] = unit
        z[:, nl:] = self._cinv(r2)
        w = np.empty((g.shape[0], z.shape[1]))
        np.multiply(g, -unit, out=w[:, :nl])
        w[:, nl:] = -(g @ z[:, nl:])
        live = np.flatnonzero(np.any(r1 != 0.0, axis=0))
        if live.size:
            w[:, nl + live] += dtbtrs(self.lu, self.d[:, None] * r1[self.lay["perm"]][:, live],
                                      uplo="U", trans="T")[0][first:]
        return z - self._cinv(g.T @ w)

    def _g(self):
        """(p, G's rows from p on): G = U⁻ᵀ D Pᵀ κH_f (dense, dofs x links),
        once per factor.  Uᵀ is lower triangular, so G's rows above the
        first row p that a link pushes on (in the band's order) are zero:
        the forward solves start at p, on Uᵀ's trailing block — a tower
        whose foundation the order puts last (rows 176 to 290 of 291) is
        solved on 115 rows.  Where a whole solve made those rows its sums
        held exact zeros; the rest are the same sums, in LAPACK's order for
        the shorter block (the last digit may differ)."""
        if self.g is None:
            lay = self.lay
            h_dof, h_link, h_val = lay["h"]
            rows = lay["pos"][h_dof]
            first = int(rows.min()) if rows.size else 0
            # entries on one dof summed, as κH_f's products sum them: a
            # contact between a node and itself has two, which cancel
            n, nl = lay["nf"] - first, lay["nl"]
            block = np.bincount(h_link * n + rows - first, weights=h_val,
                                minlength=n * nl).reshape((n, nl), order="F")
            self.g = first, dtbtrs(self.lu[:, first:], self.d[first:, None] * block,
                                   uplo="U", trans="T")[0]
        return self.g

    def _b(self, xu):
        """B x_u: κh'x_u on a holding link's row, nothing on a static one."""
        bx = _dofs_to_links(self.lay, xu)
        bx[~self.kin] = 0.0
        return bx

    def _times(self, x):
        """S x (one vector), from K_ff, κH_f, B and C."""
        nf = self.lay["nf"]
        xu, y = x[:nf], x[nf:]
        cy = self.cdiag * y
        cy[self.slip] += self.c_off * y[self.on]
        return np.concatenate((self._k_times(xu) + _links_to_dofs(self.lay, y), self._b(xu) + cy))

    def _k_times(self, xu):
        """K_ff x_u as K's product at the free dofs: K_ff's sums plus exact
        zeros (the fixed dofs' columns times 0, K's stored zeros), without
        a CSR of K_ff (a tenth of a 20-storey tower's layout)."""
        K, free = self.lay["K"]
        if free.size == K.shape[0]:          # nothing fixed: K_ff is K
            return K @ xu
        u = np.zeros(K.shape[0])
        u[free] = xu
        return (K @ u)[free]

    def _solve(self, rhs):
        lay, nf = self.lay, self.lay["nf"]
        one = rhs.ndim == 1
        r1, r2 = rhs[:nf], rhs[nf:]
        z = self._cinv(r2)
        t = r1 - _links_to_dofs(lay, z)
        d = self.d if one else self.d[:, None]
        b = d * t[lay["perm"]]
        x_perm = (dpbtrs(self.lu, b)[0] if self.piv is None
                  else dgbtrs(self.lu, self.bw, self.bw, b, self.piv)[0])
        x = np.empty_like(t)
        x[lay["perm"]] = d * x_perm
        return np.concatenate((x, z - self._cinv(self._b(x))))


def dislocations(kappa, r1, r2):
    """[0 r1; κI r2]: the basic system's right-hand sides for the contact
    stiffness (a unit dislocation of each link, scaled by κ) and its load
    columns (r1 at the dofs, r2 at the links)."""
    nf, nl = r1.shape[0], r2.shape[0]
    rhs = np.zeros((nf + nl, nl + r1.shape[1]))
    rhs[nf:, :nl] = kappa * np.eye(nl)
    rhs[:nf, nl:], rhs[nf:, nl:] = r1, r2
    return rhs


def _links_to_dofs(lay, y):
    """κH_f y (y: links, one column per right-hand side) from κH_f's
    entries link by link, without a sparse matrix: a construction and a
    product of scipy's cost 10–30 and 3–6 µs of set-up where a tower's 34
    links have 34 entries."""
    h_dof, h_link, h_val = lay["h"]
    return _summed(h_dof, h_val, y, h_link, lay["nf"])


def _dofs_to_links(lay, x):
    """κH_fᵀ x (x: free dofs, one column per right-hand side)."""
    h_dof, h_link, h_val = lay["h"]
    return _summed(h_link, h_val, x, h_dof, lay["nl"])


def _summed(to, val, x, at, n):
    """Σ val·x[at] into rows ``to`` (n of them), each row's terms added from
    zero in the entries' order — the sums, in their order, of scipy's
    sparse product over these entries (CSC's for κH_f, CSR's for its
    transpose), so the same bits."""
    if x.ndim == 1:
        return np.bincount(to, weights=val * x[at], minlength=n)
    out = np.zeros((n,) + x.shape[1:])
    np.add.at(out, to, val[:, None] * x[at])
    return out
