"""Proofs that a parametric LCP has no solution beyond a load: the collapse of a
load trace (the load-trace paper of Osipova, Popov & Lovtsov), by Farkas vectors and branch and
bound over the complementary patterns.

For the family w = M z + q0 + p q1, LCP(M, q(p')) has a solution only if one
of its complementary patterns (z_i = 0 or w_i = 0 for each i) has a feasible
point.  :meth:`LoadFamily.collapse_proof` proves every pattern empty for all
p' >= p_limit, each by a Farkas vector checked from the data (the root alone
is the classical Farkas alternative; the branches are needed when only
complementarity rules the loads out), or finds an equilibrium beyond.  The
LPs are those of :mod:`qpcontact.proofs.lp` (HiGHS with its feasibility
tolerances at 1e-10: its default 1e-7 left Farkas vectors that failed a
componentwise check on frames whose stiffnesses span 1e5).
"""

from __future__ import annotations

import numpy as np

from ..core.linalg import dense_matrix, ruiz_scaling
from ..judge.scales import ComponentScales
from .lcp_farkas import FARKAS_RTOL
from .lp import linprog

__all__ = ["LoadFamily", "TIE_RTOL", "COLLAPSE_NODES", "Z_BOUND"]

#: A z_i or w_i within TIE_RTOL of its own componentwise scale is zero at a
#: breakpoint: rows reaching zero together (ties) are decided together.
TIE_RTOL = 1e-10


#: the slacks on M'y <= 0 a pattern's Farkas LP is given in turn, relative
#: to its terms (see :meth:`LoadFamily._farkas`); a collapse proof uses the
#: first, the narrowing of a bracket (:meth:`LoadFamily.proof_at`) all
SLACKS = (1e-10, 1e-12, 1e-14)
#: the slack tried last where a pattern's LP finds it empty but no vector at
#: SLACKS[0] checks: where M'y = 0 is an identity its rounding can exceed
#: 1e-10 of its terms (a table's corner push on soft pads ended "bounded",
#: 9e-3 short of its collapse, on one machine and not another);
#: what the larger slack lets through is bounded by the same check
#: (z_bound >= Z_BOUND x the solution's size), so it proves no more than
#: that check allows (the slack is capped at half the accuracy's tolerance)
LOOSE_SLACK = 1e-8


#: Most branch-and-bound nodes spent proving that no equilibrium exists
#: beyond the end of the path (each one LP or two).
COLLAPSE_NODES = 400


#: A Farkas vector whose rounding leaves M'y slightly positive proves "no
#: equilibrium" only for z below a bound; it is accepted when the bound is at
#: least Z_BOUND times the size of the solution at the end of the path (far
#: beyond what a small-displacement model describes).
Z_BOUND = 1e3


class LoadFamily:
    """The data of a parametric LCP, equilibrated once (Ruiz: R M C), with its
    componentwise scales, and the proof that no equilibrium exists beyond a
    load.  The load trace's path follower extends it."""

    def __init__(self, plcp):
        self.plcp = plcp
        self.M = dense_matrix(plcp.M)
        self.q0, self.q1 = plcp.q0, plcp.q1
        self.rs, self.cs = ruiz_scaling(self.M)
        self.Ms = self.M * self.rs[:, None] * self.cs[None, :]
        self.values = ComponentScales(self.M, np.abs(self.q0))
        self.Ms_max = float(np.max(np.abs(self.Ms), initial=0.0)) or 1.0

    def q_terms(self, p: float) -> np.ndarray:
        return np.abs(self.q0) + abs(p) * np.abs(self.q1)

    def load_unit(self, p: float) -> float:
        """The load scale at p: p itself, or the p at which the variable load
        reaches the constant one (1 when either is absent: the problem is then
        homogeneous in p)."""
        q0, q1 = np.abs(self.q0).max(initial=0.0), np.abs(self.q1).max(initial=0.0)
        return max(abs(p), q0 / q1 if q0 > 0 and q1 > 0 else 1.0)

    def collapse_proof(self, p: float, z_scale: float, tol: float,
                       max_nodes: int = COLLAPSE_NODES, expired=None):
        """Prove that no solution exists for any load p' >= p_limit, p_limit a
        hair above p (1e-9, else 1e-6, else 1e-4 of the load scale): a dict with
        ``p_limit`` and the Farkas vectors; {"solution": (z, p')} when an
        equilibrium beyond p was found instead; None when neither.

        LCP(M, q(p')) has a solution only if one of its complementary patterns
        (z_i = 0 or w_i = 0 for each i) has a feasible point.  Branch and bound
        over the patterns, with p' as one more unknown >= p_limit: a node fixes
        some z_i = 0 and some w_i = 0 and

        - a Farkas vector y (y_i >= 0 on the inequalities, free on the fixed
          w's) with (M'y)_j <= 0 on the free z's, q1'y <= 0 and
          y'q(p_limit) < 0 proves it empty for every p' >= p_limit, since then
          y'w(p') = y'M z + y'q(p_limit) + (p' - p_limit) q1'y < 0 (:meth:`_farkas`);
        - otherwise an LP point (z, p') of it that is complementary is a
          solution beyond p (nothing to prove), and one that is not is split on
          its most violated pair.

        The root alone is the classical Farkas alternative; the branches are
        needed when only complementarity rules the loads out (a frame whose
        separated contacts could carry load only if they touched).

        Where M'y = 0 is an identity (a frame's equilibrium) rounding leaves
        (M'y)_j = δ_j > 0 of a few eps; then y'w <= δ'z + y'q(p') < 0 for
        every z with Σ z_j <= ``z_bound`` = -y'q(p_limit) / Σ δ_j, and a vector
        is accepted only when that bound exceeds Z_BOUND times ``z_scale`` (the
        solution's own size at p): "no equilibrium with openings and slips
        below 1000 times those at the last one".  A bound that small relative
        to the solution (seed 17 of the random frames: 4e-4 against slips of
        0.25, and Lemke found an equilibrium just beyond) proves nothing.

        ``expired() -> bool`` (optional): the caller's deadline; the
        branches stop there with None (nothing proved), each node being an
        LP or two (a 117-contact frame's 400 nodes ran for minutes).
        """
        unit = self.load_unit(p)
        z_scale = self.solution_scale(p, z_scale)
        # Just beyond p every LP point is within ~(p' - p) of the last
        # equilibrium, which an LP's tolerances cannot tell from feasible: if the
        # proof does not go through a hair above p it is tried a little further.
        # A "solution" a hair above p may be the last equilibrium itself, within
        # the tolerances; it is believed only if the proof fails further out too.
        found = None
        for rel in (1e-9, 1e-6, 1e-4):
            out = self._branch_and_bound(p + rel * unit, unit, z_scale, tol, max_nodes,
                                         expired=expired)
            if out is not None and "solution" not in out:
                return out
            found = out or found
        return found

    def solution_scale(self, p: float, z_scale: float) -> float:
        """The size of a solution at p that a proof's z bound is measured
        against: ``z_scale``, the one found there, or where that is 0 (at p
        = 0 with no constant load) that of the load a unit further, |q| /
        max|M|."""
        scale_M = float(np.abs(self.M).max(initial=0.0))
        if scale_M > 0:
            unit = self.load_unit(p)
            z_scale = max(z_scale, float(self.q_terms(p + unit).max(initial=0.0)) / scale_M)
        return z_scale

    def proof_at(self, p_lo: float, z_scale: float, tol: float,
                 max_nodes: int = COLLAPSE_NODES):
        """:meth:`collapse_proof` for p' >= ``p_lo`` itself (no hair added):
        the dict with ``p_limit`` = p_lo, or None where the branches found
        no proof there (an LP point beyond it, or a leaf without a
        certificate that checks).  For narrowing a collapse's bracket: p_lo
        between the last certified equilibrium and a proof further out."""
        out = self._branch_and_bound(p_lo, self.load_unit(p_lo),
                                     self.solution_scale(p_lo, z_scale), tol, max_nodes,
                                     slacks=SLACKS)
        return None if out is None or "solution" in out else out

    def _branch_and_bound(self, p_lo, unit, z_scale, tol, max_nodes, slacks=SLACKS[:1],
                          expired=None):
        n = self.q0.size
        stack = [(np.zeros(n, bool), np.zeros(n, bool))]
        leaves, nodes = [], 0
        while stack:
            nodes += 1
            if nodes > max_nodes or (expired is not None and expired()):
                return None
            Z0, W0 = stack.pop()
            cert = self._farkas(Z0, W0, p_lo, z_scale, tol, slacks)
            found = None if cert is not None else self._pattern_point(Z0, W0, p_lo, unit)
            if cert is None and found is None:
                # empty by the LP, but no vector at the first slack: a larger one
                cert = self._farkas(Z0, W0, p_lo, z_scale, tol, (LOOSE_SLACK,))
                if cert is None:
                    return None   # without a certificate that checks
            if cert is not None:
                leaves.append((np.flatnonzero(Z0), np.flatnonzero(W0)) + cert)
                continue
            z, pp = found
            w = self.M @ z + self.q0 + pp * self.q1
            zeta, sigma = self.values.at(z, self.q_terms(pp))
            with np.errstate(divide="ignore", invalid="ignore"):
                zr = np.where(zeta > 0, z / zeta, np.inf * (z > 0))
                wr = np.where(sigma > 0, w / sigma, np.sign(w) * np.inf)
            # The point only guides the branching.  A row it violates on its own
            # scale (the LP's tolerance) is split first; a complementary point
            # that holds is a solution beyond p: nothing to prove.
            open_ = ~(Z0 | W0)
            viol = np.where(open_, np.minimum(zr, np.maximum(wr, 0.0)), 0.0)
            bad = np.where(open_, -wr, 0.0)
            if bad.max() > TIE_RTOL:
                i = int(np.argmax(bad))
            elif viol.max() > TIE_RTOL:
                i = int(np.argmax(viol))
            elif np.all(wr[~W0] >= -TIE_RTOL) and np.all(np.abs(wr[W0]) <= TIE_RTOL):
                return {"solution": (z, pp)}
            else:
                return None
            Zc = Z0.copy()
            Zc[i] = True
            Wc = W0.copy()
            Wc[i] = True
            stack += [(Zc, W0), (Z0, Wc)]
        root = leaves[0] if len(leaves) == 1 and not leaves[0][0].size and not leaves[0][1].size else None
        return {"p_limit": p_lo, "patterns": len(leaves), "nodes": nodes,
                "backward_error": max(leaf[3] for leaf in leaves),
                "z_bound": min(leaf[4] for leaf in leaves),
                "farkas": root[2] if root is not None else None,
                "leaves": [{"z_zero": lf[0], "w_zero": lf[1], "y": lf[2]} for lf in leaves]}

    def _pattern_point(self, Z0, W0, p_lo, unit):
        """(z, p') with p' >= p_lo, z >= 0, w(p') >= 0, z_Z0 = 0, w_W0 = 0 and p'
        as small as the LP finds; None when the LP finds none (equilibrated)."""
        J, I, W = np.flatnonzero(~Z0), np.flatnonzero(~W0), np.flatnonzero(W0)
        n = self.q0.size
        Ms = self.Ms
        q_lo, q1 = self.rs * (self.q0 + p_lo * self.q1), self.rs * self.q1 * unit
        a = self.Ms_max
        # unknowns (z'_J, s): z = C z', p' = p_lo + unit * s; minimize s
        A = np.column_stack([Ms[:, J], q1]) / a
        c = np.zeros(J.size + 1)
        c[-1] = 1.0
        res = linprog(c, A_ub=-A[I] if I.size else None, b_ub=q_lo[I] / a if I.size else None,
                      A_eq=A[W] if W.size else None, b_eq=-q_lo[W] / a if W.size else None,
                      bounds=(0, None))
        if res is None or res.status != 0:
            return None
        z = np.zeros(n)
        z[J] = np.maximum(res.x[:-1], 0.0) * self.cs[J]
        pp = p_lo + unit * max(float(res.x[-1]), 0.0)
        # Polish the vertex on the original data: the rows the LP holds at zero
        # (and the fixed w's) with its positive z's (and p' when it moved off p_lo)
        # solved exactly — HiGHS's tolerances are absolute, the checks are not.
        w = self.M @ z + self.q0 + pp * self.q1
        _, sigma = self.values.at(z, self.q_terms(pp))
        tight = W0 | (np.abs(w) <= 1e-7 * np.maximum(sigma, 1e-300))
        S = np.flatnonzero(z > 0)
        free_p = pp > p_lo
        A = self.M[np.ix_(np.flatnonzero(tight), S)]
        if free_p:
            A = np.column_stack([A, self.q1[tight]])
        if A.size:
            x = np.linalg.lstsq(A, -(self.q0 + (0.0 if free_p else pp) * self.q1)[tight],
                                rcond=None)[0]
            cand = np.zeros(n)
            cand[S] = x[:S.size]
            p_c = float(x[-1]) if free_p else pp
            if np.all(cand >= 0) and p_c >= p_lo:
                z, pp = cand, p_c
        return z, pp

    def _farkas(self, Z0, W0, p_lo, z_scale, tol, slacks=SLACKS[:1]):
        """(y, backward, z_bound) proving {z >= 0, w(p') >= 0, z_Z0 = 0, w_W0 = 0}
        empty for every p' >= p_lo and every z below z_bound, checked from the
        data; or None.

        LP: min y'q(p_lo) over y_i in [0, 1] (i not in W0), y_i in [-1, 1]
        (i in W0), (M'y)_j <= 0 for the free z's (to a slack of 1e-10 of their
        terms), q1'y <= 0; a negative optimum is a Farkas vector.  It is polished
        on its support and checked by :meth:`_farkas_check`.
        """
        n = self.q0.size
        J = np.flatnonzero(~Z0)
        Ms, qs, q1s = self.Ms, self.rs * (self.q0 + p_lo * self.q1), self.rs * self.q1
        a = self.Ms_max
        b = float(np.max(np.abs(q1s))) or 1.0
        c = float(np.max(np.abs(qs))) or 1.0
        # Where M'y = 0 is an identity its rounding decides the sign, so the LP
        # gets a little slack: with none it was infeasible or not depending on
        # the number of BLAS threads.  What the slack lets through is bounded
        # in _farkas_check; where that bound (z_bound) is too small to prove
        # anything, a smaller slack is tried — near a collapse load the gap
        # y'q shrinks with p - p_limit, and a four-legged table's corner push
        # 5e-7 above its path's end had a vector with δ at the slack (1e-10)
        # bounding z by 0.28, and at a slack of 1e-14 by 2 700 (557 needed)
        # (only where the LP found a vector: where it found none the pattern
        # is feasible to its tolerance, and a smaller slack only constrains
        # it more; and only in :meth:`proof_at`, the narrowing of a bracket
        # — in every collapse proof's branch and bound it made a six-legged
        # table's trace on the circle 6x slower, 34 -> 205 s)
        for slack in dict.fromkeys(min(0.5 * tol, s) for s in slacks):
            best = self._farkas_with(J, W0, p_lo, z_scale, slack, Ms, qs, q1s, a, b, c, n)
            if best is None:
                return None
            if best is not False and best[1] <= tol:
                return best
        return None

    def _farkas_with(self, J, W0, p_lo, z_scale, slack, Ms, qs, q1s, a, b, c, n):
        """:meth:`_farkas`'s LP with ``slack`` on M'y <= 0, its vector
        polished and checked: (y, backward, z_bound); False where the LP
        found a vector that does not check; None where it found none."""
        from scipy.optimize import lsq_linear

        rows = [(Ms[:, J].T - slack * np.abs(Ms[:, J]).T) / a] if J.size else []
        rows.append((q1s - slack * np.abs(q1s))[None, :] / b)
        bounds = [(-1, 1) if W0[i] else (0, 1) for i in range(n)]
        res = linprog(qs / c, A_ub=np.vstack(rows), b_ub=np.zeros(J.size + 1), bounds=bounds)
        if res is None or res.status != 0 or not res.fun < 0:
            return None
        y0 = res.x * self.rs
        best = self._farkas_check(y0, J, W0, p_lo, z_scale)
        R = np.flatnonzero(np.abs(y0) > 1e-12 * np.abs(y0).max())
        if R.size:  # polish: M'y = 0 on the tight columns, y'q(p_lo) as found, on y's support
            My, scale = self.M[:, J].T @ y0, np.abs(self.M[:, J]).T @ np.abs(y0)
            T = J[My >= -1e-8 * scale]
            q_lo = self.q0 + p_lo * self.q1
            rows = [self.M[np.ix_(R, T)].T, q_lo[R][None, :]]
            rhs = [np.zeros(T.size), [float(q_lo @ y0)]]
            if float(self.q1 @ y0) >= -1e-8 * float(np.abs(self.q1) @ np.abs(y0)):
                rows.append(self.q1[R][None, :])
                rhs.append([0.0])
            # bounded least squares: y stays >= 0 on the inequality rows
            lower = np.where(W0[R], -np.inf, 0.0)
            yR = lsq_linear(np.vstack(rows), np.concatenate(rhs), bounds=(lower, np.inf),
                            method="bvls", tol=1e-15).x
            y = np.zeros(n)
            y[R] = yR
            polished = self._farkas_check(y, J, W0, p_lo, z_scale)
            if polished is not None and (best is None or polished[2] > best[2]):
                best = polished
        return False if best is None else best

    def _farkas_check(self, y, J, W0, p_lo, z_scale):
        """(y, backward, z_bound) for a candidate y, or None when it proves nothing.

        With δ = max(M_J'y, 0) and g = -y'q(p_lo) (less the rounding of q's
        terms): y'w(p') <= δ'z - g < 0 for every z >= 0 with Σ z_j < z_bound =
        g / Σ δ_j (inf when δ = 0), and for every p' >= p_lo when q1'y <= 0 (to
        FARKAS_RTOL of its terms).  Accepted when z_bound >= Z_BOUND * z_scale.
        ``backward`` = max δ_j / (|M|'|y|)_j is reported beside it.
        """
        if np.any(y[~W0] < 0):
            return None
        ay = np.abs(y)
        My, scale = self.M[:, J].T @ y, np.abs(self.M[:, J]).T @ ay
        q1y, q1s = float(self.q1 @ y), float(np.abs(self.q1) @ ay)
        if q1y > FARKAS_RTOL * q1s:
            return None
        delta = np.maximum(My, 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(delta > 0, delta / scale, 0.0)
        backward = max(FARKAS_RTOL, float(np.max(ratio, initial=0.0)))
        gap = -float((self.q0 + p_lo * self.q1) @ y) \
            - FARKAS_RTOL * float((np.abs(self.q0) + p_lo * np.abs(self.q1)) @ ay)
        if not (np.isfinite(backward) and gap > 0):
            return None
        total = float(delta.sum())
        z_bound = gap / total if total > 0 else np.inf
        if not z_bound >= Z_BOUND * z_scale:
            return None
        return y, backward, z_bound
