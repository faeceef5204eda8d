r"""The interior point's condensed systems solved in body space, where the
Delassus operator is known in its factors ("ip-lcp"'s linear algebra).

**The system.**  ip-lcp's Newton systems condense, contact by contact, to

    (W + L) u = g,     L block-diagonal, per contact [[d_N, 0], [ℓ, 1/G]]

(:mod:`qpcontact.solvers.friction.interior_lcp`, "The linear algebra": d_N,
G > 0, ℓ of either sign).  W + L has W's pattern: each contact couples to
every contact of its two bodies, 2 unknowns a contact; at 9 842 contacts its
LU in the order found once has 3.0–3.2 M entries and takes 0.09–0.10 s.

**Body space.**  Where W = J diag(m⁻¹) Jᵀ is known in its factors (J = Hᵀ:
the contacts' normal and tangent rows over the bodies' degrees of freedom,
m the masses and moments of inertia — a generator that forms W so keeps
them, :attr:`FrictionProblem.delassus_factors`), Woodbury's identity gives

    (W + L)⁻¹ = L⁻¹ − L⁻¹ J B⁻¹ Jᵀ L⁻¹,     B = diag(m) + Jᵀ L⁻¹ J,

L⁻¹ per contact [[1/d_N, 0], [−ℓ G / d_N, G]].  B lives on the bodies'
graph (3 unknowns a disc, each coupled to its touching neighbours): at 9 842
contacts (3 321 discs) 9 963 unknowns, 0.19 M entries against W's 0.40 M,
and its LU 1.42-1.45 M entries in 0.024-0.025 s against 0.10 s
(docs/dev-notes.md, "The dense 2-D piles in body space" and "The 10 000-
contact 2-D piles, round two").  B's pattern is fixed, so as for W + L the
order is found once (minimum degree on B + Bᵀ, symmetric mode, pivots off
the diagonal only below PIVOT_THRESHOLD of their column; a nested
dissection of the bodies' graph by breadth-first level separators filled
more at 2 000-10 000 contacts) and each step sums
B's values contact by contact from L⁻¹'s three entries.

**Accuracy.**  The identity is exact; in rounding it loses what L⁻¹'s spread
costs (d over 1e±12: backward errors 1e-16 … 2e-15 normwise, the direct LU's
1e-24 … 1e-16), which the condensed solve's refinement on the whole system
repairs down to the last iterations: there, at 1e-11 … 1e-12 of the start's
complementarity, Mehrotra's steps shorten and the interior point stops
(interior_lcp's NEAR), Newton's polish finishing from the purified point.

The factors are used only if they reproduce W (checked on a random vector
to 1e-12 of its size: a problem scaled or cut after the generator made it
would not, and W's own LU is used).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["OrderedPattern", "InOrder", "BodySpaceLU", "factors_match", "PIVOT_THRESHOLD"]

#: B's LU pivots off the diagonal only where a diagonal entry is below this
#: fraction of its column's largest.  B's diagonal carries the masses and
#: every contact's a = 1/d_N and G > 0 (module docstring), so it is rarely
#: small; at W + L's 1e-3 the LU still pivoted off it on the path and its
#: fill grew from 1.41 M to 1.64 M entries at 9 842 contacts (31 against
#: 24 ms), where 1e-6 keeps 1.42-1.45 M at the same backward error
#: (docs/dev-notes.md, "The 10 000-contact 2-D piles")
PIVOT_THRESHOLD = 1e-6


def factors_match(W, factors, rtol: float = 1e-12) -> bool:
    """Whether ``factors`` = (J, m⁻¹) reproduce W = J diag(m⁻¹) Jᵀ, judged
    on one random vector (seeded: the same in every run)."""
    try:
        J, inverse_mass = sp.csr_matrix(factors[0]), np.asarray(factors[1], float)
    except (TypeError, ValueError, IndexError):
        return False
    if J.shape != (W.shape[0], inverse_mass.size) or not np.all(inverse_mass > 0):
        return False
    x = np.random.default_rng(0).standard_normal(W.shape[0])
    wx = np.asarray(W @ x).ravel()
    return bool(np.abs(J @ (inverse_mass * (J.T @ x)) - wx).max()
                <= rtol * max(np.abs(wx).max(), np.finfo(float).tiny))


class OrderedPattern:
    """A square sparse ``pattern`` in one fill-reducing order, found once:
    SuperLU's minimum degree on A + Aᵀ, symmetric, from one factorization of
    ``dominant`` (a diagonally dominant matrix of that pattern), so that each
    later LU of values on the pattern keeps it.  ``p``: row and column k of
    the ordered matrix is p[k]; ``indices``, ``indptr``: its sorted CSC
    structure; :meth:`position` finds an entry's place in its data."""

    def __init__(self, pattern, dominant):
        import scipy.sparse.linalg as spla   # here: `import qpcontact` stays cheap

        n = pattern.shape[0]
        lu = spla.splu(sp.csc_matrix(dominant), permc_spec="MMD_AT_PLUS_A",
                       diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        self.p = np.argsort(lu.perm_c)
        self.where = np.empty(n, dtype=np.int64)
        self.where[self.p] = np.arange(n)
        ordered = sp.csc_matrix(pattern[self.p][:, self.p])
        ordered.sort_indices()
        self.indices, self.indptr, self.n = ordered.indices, ordered.indptr, n
        # entry (i, j) of the ordered matrix is at data[key ↦ position] (sorted CSC)
        self.keys = np.repeat(np.arange(n, dtype=np.int64), np.diff(ordered.indptr)) * n \
            + ordered.indices

    def position(self, i, j):
        """Where entries (i, j) (original numbering) sit in the ordered data."""
        keys, where, n = self.keys, self.where, self.n
        target = where[j] * n + where[i]
        pos = np.searchsorted(keys, target)
        # a key not in the pattern would add its value to a neighbour's entry
        if not np.array_equal(keys[np.minimum(pos, keys.size - 1)], target):
            raise AssertionError("an entry outside the ordered pattern")
        return pos


class InOrder:
    """An LU of a matrix ordered by p (:class:`OrderedPattern`), solving in
    the original order."""

    def __init__(self, lu, p):
        self.lu, self.p = lu, p

    def solve(self, r):
        x = np.empty(r.size)
        x[self.p] = self.lu.solve(r[self.p])
        return x


class BodySpaceLU:
    """B = diag(m) + Jᵀ L⁻¹ J on the bodies' pattern in one order, found
    once (module docstring); :meth:`factor` gives a solver of (W + L) u = g."""

    def __init__(self, J, inverse_mass):
        J = sp.csr_matrix(J, dtype=float)
        J.sum_duplicates()
        J.sort_indices()
        m2, nd = J.shape
        nc = m2 // 2
        self.J, self.JT, self.nc, self.nd = J, sp.csr_matrix(J.T), nc, nd
        # each row's nonzeros padded to one width; a padding entry is 0 at a
        # column of its own contact, so that its (zero) products land on
        # entries the pattern holds
        counts = np.diff(J.indptr)
        width = int(counts.max(initial=1))
        slot = np.arange(J.nnz) - np.repeat(J.indptr[:-1], counts)
        row = np.repeat(np.arange(m2), counts)
        first = np.zeros(nc, dtype=np.int64)
        first[(row // 2)[::-1]] = J.indices[::-1]     # one stored column per contact
        cols = np.repeat(first, 2)[:, None].repeat(width, axis=1)
        vals = np.zeros((m2, width))
        cols[row, slot], vals[row, slot] = J.indices, J.data
        # the pattern from J's structure, not its values: those can cancel or be
        # stored zeros (a disc's normal row has 0 on its rotation, an axis-aligned
        # tangent 0 on x), and an entry missing from it would take another's place.
        # By contact, not by row: the tangent-normal part couples a dof of the
        # tangent row with one of the normal row, which need not share a row
        ones = sp.csr_matrix((np.ones(J.nnz), (row // 2, J.indices)), shape=(nc, nd))
        ones.data[:] = 1.0
        pattern = sp.csc_matrix(sp.identity(nd) + ones.T @ ones)
        dominant = pattern + sp.diags(np.asarray(pattern.sum(axis=1)).ravel())
        order = OrderedPattern(pattern, dominant)
        self.p, self.indices, self.indptr = order.p, order.indices, order.indptr
        position, keys = order.position, order.keys

        self.mass_data = np.zeros(keys.size)
        self.mass_data[position(np.arange(nd), np.arange(nd))] = \
            1.0 / np.asarray(inverse_mass, float)
        # entry (i, j) of J_xᵀ diag(a) J_y is Σ_c J_x[c, i] a_c J_y[c, j]: per
        # contact width² terms, for (x, y) = (normal, normal), (tangent, normal),
        # (tangent, tangent) — L⁻¹'s three entries
        shape = (nc, width, width)
        self.parts = []
        for x, y in ((0, 0), (1, 0), (1, 1)):
            i = np.broadcast_to(cols[x::2][:, :, None], shape).ravel()
            j = np.broadcast_to(cols[y::2][:, None, :], shape).ravel()
            self.parts.append((position(i, j),
                               (vals[x::2][:, :, None] * vals[y::2][:, None, :]).reshape(nc, -1)))

    def factor(self, l_values):
        """The solver of (W + L) u = g, L's entries per contact in three
        blocks (d_N, ℓ, 1/G) as interior_lcp's W + L takes them."""
        import scipy.sparse.linalg as spla

        nc = self.nc
        dn, low, inv_g = l_values[:nc], l_values[nc:2 * nc], l_values[2 * nc:]
        a, g = 1.0 / dn, 1.0 / inv_g
        b = -low * g * a
        data = self.mass_data.copy()
        for (pos, products), coefficient in zip(self.parts, (a, b, g)):
            data += np.bincount(pos, weights=(products * coefficient[:, None]).ravel(),
                                minlength=data.size)
        B = sp.csc_matrix((data, self.indices, self.indptr), shape=(self.nd, self.nd))
        lu = spla.splu(B, permc_spec="NATURAL", diag_pivot_thresh=PIVOT_THRESHOLD,
                       options={"SymmetricMode": True})
        return _Woodbury(lu, self, a, b, g)


class _Woodbury:
    """(W + L)⁻¹ r = L⁻¹ (r − J B⁻¹ Jᵀ L⁻¹ r) in the contacts' own order."""

    def __init__(self, lu, body, a, b, g):
        self.lu, self.body, self.a, self.b, self.g = lu, body, a, b, g
        self.in_order = InOrder(lu, body.p)     # B's solves in the bodies' own order

    def _l_inverse(self, r):
        out = np.empty_like(r)
        out[0::2] = self.a * r[0::2]
        out[1::2] = self.b * r[0::2] + self.g * r[1::2]
        return out

    def solve(self, r):
        body = self.body
        z = body.JT @ self._l_inverse(r)
        return self._l_inverse(r - body.J @ self.in_order.solve(z))
