"""From the contact LCP's answer z to the frame's result: displacements,
member end actions, reactions, each support's state (decided on the
component's own scale), the global statics check; and what results read back
from the frame (diagrams, deflections; the tables are in :mod:`.tables`).  Mixed into
:class:`~.model.Frame`."""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidOptionError, SolverFailedError
from qpcontact.judge.lcp_certificate import certify_lcp
from qpcontact.judge.scales import ComponentScales

from . import assembly
from .assembly import DOFS
from .elements import geometry, rotation
from .loads import CONSTANT, VARIABLE, load_points, section_sums
from .results import FrameResult, SupportResult

#: A normal force or slip below STATE_RTOL of its own componentwise scale is zero
#: when the support's state is named.
STATE_RTOL = 1e-9
#: The equilibrium check's limit is the requested accuracy (1e-9 at "high"), but
#: never below what rounding leaves in a right answer's per-dof residual (a few
#: thousand eps: the saddle solve's backward error on a long member chain).
EQUILIBRIUM_FLOOR = 4096 * np.finfo(float).eps
#: Beyond a translation of SMALL_DISPLACEMENT x the frame's size, or a
#: rotation of SMALL_ROTATION rad, equilibrium written on the undeformed frame
#: is no longer the structure's (a 20-storey tower swayed 19.5 m, 0.28 of its
#: size, at its "collapse" load without a word): results say so and warn.
SMALL_DISPLACEMENT = 0.02
#: The rotation [rad] beside SMALL_DISPLACEMENT (see there).
SMALL_ROTATION = 0.05


class LargeDisplacementWarning(UserWarning):
    """A result's displacements are beyond small-displacement theory."""


def beyond_rounding(res, scale, largest=None) -> float:
    """max |res| / scale, not counting what rounding of the largest term of the
    same kind leaves (R_ROUNDING of it): a force that is zero in exact
    arithmetic comes out of the solve as a few eps times the largest force
    (a friction force of 1.6e-15 beside a reaction of 50), and judged against
    its own terms — all of them zero — it would be wrong by all of its size."""
    if res.size == 0:
        return 0.0
    floor = assembly.R_ROUNDING * (scale.max() if largest is None else largest)
    excess = np.maximum(res - floor, 0.0)
    ratio = np.divide(excess, scale, out=np.zeros_like(excess), where=scale > 0)
    ratio[(scale <= 0) & (excess > 0)] = np.inf
    return float(ratio.max())


class FrameRecovery:
    """The Frame's results construction (see the module docstring)."""

    #: a node's dofs, in order (rotations start with "r")
    DOFS = DOFS

    def _result_from_z(self, z, combo, route, b=None, lcp=None, tol=1e-9) -> FrameResult:
        """The frame's result for the LCP point z, checked: the contact
        certificate (the LCP's when its matrix is at hand, else the same
        componentwise measure on the contact quantities' mechanical scales:
        :meth:`_contact_certificate`) and equilibrium."""
        b = b or self.build()
        if not isinstance(combo, dict):   # a number p: the P3 split
            combo = {CONSTANT: 1.0, VARIABLE: float(combo)}
        P, W, g, fric = assembly.link_maps(self, b)
        z = np.maximum(np.asarray(z, float), 0.0)
        F, ua = assembly.load_vector(b, combo)  # ua: settlements (zero at free dofs)
        delta = P @ z - g                      # link displacements incl. contact flexibility
        nf, free, fixed_idx = b["nf"], b["free"], b["fixed_idx"]
        rhs = np.r_[F[free] - b["K_fa"] @ ua[fixed_idx],
                    b["kappa"] * (delta - b["H"][fixed_idx].T @ ua[fixed_idx])]
        sol = b["lu"].solve(rhs)
        u = ua.copy()
        u[free] = sol[:nf]
        # The contact forces from the same solve as u, not R Δ + R_F: R has its
        # rounding-level entries dropped (assembly.build), which times the large
        # openings of a long lifted stretch left forces 1e-9 off and out of
        # equilibrium with u (issue 31, a 200-span beam); the solve's own
        # multipliers satisfy K u = F + H X to rounding.
        X = -b["kappa"] * sol[nf:]
        # reactions at the fixed dofs: K u - F - H X on them (member loads
        # included), reported in global axes (a node's axes may be turned)
        r_all = b["K"] @ u - F - b["H"] @ X
        r_glob = assembly.to_global(b, np.where(b["fixed"], r_all, 0.0))
        reactions = {node: tuple(float(v) for v in r_glob[b["idx"][node]:b["idx"][node] + 3])
                     for node in b["names"] if node in self.fixed}
        # what meets at each dof: the members' end forces, springs, loads
        ends = assembly.member_end_actions(b, assembly.to_global(b, u), assembly.factors(b, combo))
        ft = assembly.force_terms(b, u, F, ends)
        if lcp is None and "R" not in b:
            cert_error, zeta, sigma = self._contact_certificate(b, z, X, u, ft, W, P, g)
        else:
            if lcp is None:
                M, Q, q_gap, *_ = assembly.lcp_matrices(self, b)
                lcp = assembly.combination_lcp(M, Q, q_gap, b, combo)
            cert_error = certify_lcp(lcp, z).error
            zeta, sigma = ComponentScales(lcp.M, lcp.q_terms).at(z)
        u_axes, u = u, assembly.to_global(b, u)
        ca = assembly.contact_arrays(self, b)
        nc = len(self.contacts)
        has_t = ca["t_link"] >= 0
        xn = X[ca["n_link"]]
        xt = np.where(has_t, X[ca["t_link"]], 0.0)
        # frictionless: no tangential link, the node slides freely (t·relative motion)
        u2 = u.reshape(-1, 3)[:, :2]
        rel = u2[ca["node"]] - np.where(ca["other"][:, None] >= 0, u2[ca["other"]], 0.0)
        tangent = np.c_[ca["normal"][:, 1], -ca["normal"][:, 0]]
        slip = np.where(has_t, delta[ca["t_link"]], np.einsum("ij,ij->i", tangent, rel))
        # each state decided on the component's own scale (the certificate's):
        # X_n against the terms it is made of, a slip part against its own size
        sl = nc + 2 * np.arange(int(has_t.sum()))      # Z⁺ of each frictional contact
        moving = np.zeros(nc, bool)
        moving[has_t] = (np.maximum(z[sl], z[sl + 1])
                         > STATE_RTOL * np.maximum(zeta[sl], zeta[sl + 1]))
        separated = xn <= STATE_RTOL * sigma[:nc]
        states = np.where(separated, "separated", np.where(
            ~has_t, "closed", np.where(~moving, "stick", np.where(slip > 0, "slip+", "slip-"))))
        xn = np.where(separated, 0.0, xn)   # rounding noise of a force that is zero
        xt = np.where(separated, 0.0, xt)
        supports = {key: SupportResult(str(st), float(a), float(t_), float(o), float(sp_))
                    for key, st, a, t_, o, sp_ in zip(self._support_keys(), states, xn, xt,
                                                      z[:nc], slip)}
        eq = max(self._equilibrium(b, F, X, u_axes), self._resultant(b, F, X, r_all, u_axes, ft))
        displacements = dict(zip(b["names"], map(tuple, u.reshape(-1, 3).tolist())))
        member_forces = dict(zip(self.members, ends))
        ok = cert_error <= tol and eq <= max(tol, EQUILIBRIUM_FLOOR)
        msg = (f"{route}: contact certificate {cert_error:.1e}, equilibrium residual {eq:.1e}"
               + ("" if ok else " — CHECK FAILED"))
        ratio, rot, words = self._how_far(u)
        if words:
            msg += "; " + words
        return FrameResult(p=float(combo.get(VARIABLE, 0.0)), supports=supports,
                           displacements=displacements, member_forces=member_forces,
                           reactions=reactions, equilibrium_residual=eq, lcp_error=cert_error,
                           route=route, ok=ok, message=msg, frame=self, _u=u,
                           combination=dict(combo), displacement_ratio=ratio,
                           max_rotation=rot)

    def _how_far(self, u, always=False):
        """(largest translation / frame size, largest rotation, words): the
        words say where small-displacement theory stops holding (or, with
        ``always``, how far the frame has moved in any case)."""
        xy = np.array(list(self.nodes.values()))
        size = float(np.linalg.norm(np.ptp(xy, axis=0))) or 1.0
        spin = np.array([d.startswith("r") for d in self.DOFS])   # a node's rotations
        per_node = np.asarray(u).reshape(-1, len(self.DOFS))
        trans = np.linalg.norm(per_node[:, ~spin], axis=1)
        k = int(np.argmax(trans))
        ratio, rot = float(trans[k]) / size, float(np.abs(per_node[:, spin]).max(initial=0.0))
        length = self.units[1]
        moved = (f"node {list(self.nodes)[k]} has moved {trans[k]:.3g} {length} "
                 f"({ratio:.2g} of the frame's size, {size:.3g} {length}), rotations up to "
                 f"{rot:.2g} rad")
        if ratio > SMALL_DISPLACEMENT or rot > SMALL_ROTATION:
            return ratio, rot, (f"{moved}: beyond small-displacement theory (limits "
                                f"{SMALL_DISPLACEMENT:g} of the size, {SMALL_ROTATION:g} rad), "
                                "which this analysis assumes — the deformed frame's equilibrium "
                                "(second-order effects) is not in it")
        return ratio, rot, (moved if always else "")

    def _contact_certificate(self, b, z, X, u, force_terms, W, P, g):
        """(error, ζ, σ): the LCP certificate's componentwise measure,
        max_i |min(z_i/ζ_i, w_i/σ_i)| with w = W X, where the LCP's matrix is
        not formed (the sparse active set never forms the dense R).  The
        scales are what each quantity is made of, as the certificate's
        |M||z| + |q| are, read off the mechanics instead of M: a link force
        against the forces that meet at its node (assembly.force_terms: the
        members' end forces, the springs', the loads), and a link
        displacement (an opening, a slip part) against |h|ᵀ|u| + |D X| + g.
        Equilibrium is checked on its own (_equilibrium, _resultant)."""
        absH = abs(b["H"])
        forces = absH.T @ force_terms
        lengths = absH.T @ np.abs(u) + np.abs(b["flex"] * X) + np.abs(g)
        forces = forces + assembly.R_ROUNDING * forces.max(initial=0.0)
        lengths = lengths + assembly.R_ROUNDING * lengths.max(initial=0.0)
        zeta = abs(P).T @ lengths
        w = W @ X
        e, sigma = self._complementarity(z, w, zeta, abs(W) @ forces)
        # the LCP's scale of a link force also holds the force its own link
        # displacement makes, R_ll |Δ_l|, which the rounding of the solve
        # follows: a lifted stretch of a foundation beam had X_n = -4e-10
        # from rounding against node forces of 1e-9, where R_ll |Δ| = 2e4 as
        # in the LCP's |R||Δ|.  R_ll is read off the basic system's LU, one
        # solve per moving link whose component is above rounding without it
        # (a bound such as the node's stiffness h'|K|h was 1e9 times too
        # large beside a 1 cm stub, and passed a tip lifted 1 m); leaving it
        # out elsewhere can only overstate the error
        delta = P @ z - g
        rows = np.flatnonzero(e > 64 * np.finfo(float).eps)
        touched = np.asarray(abs(W)[rows].sum(axis=0)).ravel() > 0
        moving = np.flatnonzero(touched & (delta != 0))
        if moving.size:
            nf, kappa = b["nf"], b["kappa"]
            unit = np.zeros((nf + len(delta), moving.size))
            unit[nf + moving, np.arange(moving.size)] = kappa
            R_ll = np.abs(kappa * b["lu"].solve(unit)[nf + moving, np.arange(moving.size)])
            forces[moving] += R_ll * np.abs(delta[moving])
            e, sigma = self._complementarity(z, w, zeta, abs(W) @ forces)
        return (float(e.max(initial=0.0)), zeta, sigma)

    @staticmethod
    def _complementarity(z, w, zeta, sigma):
        """(|min(z/ζ, w/σ)| per component, σ)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            Z = np.where(zeta > 0, z / np.where(zeta > 0, zeta, 1.0), np.where(z > 0, np.inf, 0.0))
            Wr = np.where(sigma > 0, w / np.where(sigma > 0, sigma, 1.0),
                          np.where(w != 0, np.sign(w) * np.inf, 0.0))
        return np.abs(np.minimum(Z, Wr)), sigma

    def _equilibrium(self, b, F, X, u):
        """Equilibrium judged dof by dof, each on its own scale: the residual of
        K u = F + H X at every free dof against the sum of the absolute values
        of the terms that make it, |K||u| + |F| + |H||X| (a componentwise
        backward error, like the LCP certificate's; the reactions at fixed
        dofs are those rows' remainders, so they hold by definition).  The old
        check — the resultant against the largest load, limit 1e-8 — failed
        right answers on long beams (200 spans: 1.1-2.5e-8 where independent
        statics agree to 1e-9)."""
        free = b["free"]
        K = b["K"]
        res = np.abs(K @ u - F - b["H"] @ X)[free]
        scale = (abs(K) @ np.abs(u) + np.abs(F) + abs(b["H"]) @ np.abs(X))[free]
        moment = np.array([d.startswith("r") for d in self.DOFS])[free % len(self.DOFS)]
        return max(beyond_rounding(res[~moment], scale[~moment]),
                   beyond_rounding(res[moment], scale[moment]))

    def _resultant(self, b, F, X, r_all, u, force_terms):
        """The frame's global statics: Σ forces and Σ moments (about the nodes'
        centroid) of the loads, contact forces, bilateral reactions and
        springs, each equation against the sum of the absolute values of its
        terms (a 200-span beam's resultant is the rounding of 200 reactions,
        judged against all of them).

        The per-dof check cannot replace it: its scale holds |K||u|, which a
        rigid motion makes huge while K u stays zero — a Tresca iterate that
        lifted a frame resting on its contacts by 2e9 m passed it and the LCP
        certificate, and fails here by the weight its "separated" supports
        do not carry.  For the same reason a reaction is sized by the forces
        that meet at its dof (``force_terms``: members' end forces, springs,
        loads), not by |K||u|: sized so, a lever lifted off as a rigid motion
        of 1e11 m had its wrong pin reaction pass."""
        xy = np.array([self.nodes[nd] for nd in b["names"]])
        xy = xy - xy.mean(axis=0)
        absHX = abs(b["H"]) @ np.abs(X)
        terms = [F, b["H"] @ X, np.where(b["fixed"], r_all, 0.0)]
        # each term by what it is made of: H X by |H||X|, a reaction (K u - F -
        # H X at its dof) by the forces meeting there and |H||X|
        size = np.abs(F) + absHX + np.where(b["fixed"], force_terms + absHX, 0.0)
        if b["Tn"] is not None:   # sums of forces are taken in global axes
            terms = [b["Tn"].T @ t for t in terms]
            size = abs(b["Tn"]).T @ size
            u = b["Tn"].T @ u
        spring = np.zeros_like(F)
        for node, ks in self.springs.items():
            for d, kval in ks.items():
                i = b["idx"][node] + DOFS.index(d)
                spring[i] -= kval * u[i]
        terms.append(spring)
        size = size + np.abs(spring)
        total = sum(terms)
        fx, fy, mz = total[0::3], total[1::3], total[2::3]
        ax, ay, am = size[0::3], size[1::3], size[2::3]
        lx, ly = np.abs(xy[:, 0]), np.abs(xy[:, 1])
        res = np.abs([fx.sum(), fy.sum(), (mz + xy[:, 0] * fy - xy[:, 1] * fx).sum()])
        scale = np.array([ax.sum(), ay.sum(), (am + lx * ay + ly * ax).sum()])
        big_m = (am + lx * ay + ly * ax).max(initial=0.0)
        # forces carry the rounding of the moments they balance too (a frame
        # loaded by a moment alone has shears that are zero but for it)
        size_xy = max(float(np.hypot(*np.ptp(xy, axis=0))), 1e-300)
        big_f = max(ax.max(initial=0.0), ay.max(initial=0.0), am.max(initial=0.0) / size_xy)
        # every term of a sum carries its own rounding (R_ROUNDING of the largest)
        n_f = max(np.count_nonzero(ax), np.count_nonzero(ay), 1)
        n_m = np.count_nonzero(size)
        return max(beyond_rounding(res[:2], scale[:2], n_f * big_f),
                   beyond_rounding(res[2:], scale[2:], n_m * big_m))

    def _diagram(self, res: FrameResult, member: str, points: int):
        m = self._diagram_member(res, member, points)
        L = geometry(self, m)[0]
        x = np.linspace(0.0, L, int(points))
        pts = [p for p in load_points(self._loads_of(res, m)) if 0.0 < p < L]
        # both sides of every load position: jumps of V (point loads) and M (moments)
        x = np.unique(np.r_[x, pts, np.nextafter(np.array(pts, float), -np.inf)])
        return (x, *self._sections(res, m, x))

    def _diagram_member(self, res, member, points):
        if not isinstance(member, str):
            raise InvalidOptionError(f"member: a member's name, one of {list(self.members)}; "
                                     f"got {member!r}")
        m = self._member(member)
        if isinstance(points, str) and points in ("N", "V", "M"):
            raise InvalidOptionError(
                f"points: the number of sample points, not the quantity {points!r}; diagram "
                f"returns all of them, x, N, V, M = result.diagram({member!r}), or give "
                f"points=, e.g. result.diagram({member!r}, 41)")
        if isinstance(points, bool) or not isinstance(points, (int, np.integer)) or points < 2:
            raise InvalidOptionError(f"points: the number of sample points along the member, an "
                                     f"integer >= 2 (default 21); got {points!r}")
        if not res.member_forces:
            raise SolverFailedError(f"no diagram: this result is not an equilibrium ({res.message})")
        return m

    def _direction(self, member):
        """(cos, sin) of a member's axis."""
        return geometry(self, self._member(member))[1:]

    @staticmethod
    def _loads_of(res, m):
        return [ld for ld in m.loads if res.combination.get(ld.case)]

    def _sections(self, res, m, x):
        """(N, V, M) at the sections x (member axes, engineering convention):
        the end actions at node i plus the member loads on [0, x)."""
        L, c, s = geometry(self, m)
        f = res.member_forces[m.name]
        loads = self._loads_of(res, m)
        fx, fy, mo = np.zeros_like(x), np.zeros_like(x), np.zeros_like(x)
        for case in {ld.case for ld in loads}:
            ax_, ay_, am_ = section_sums([ld for ld in loads if ld.case == case], x, c, s)
            factor = res.combination[case]
            fx += factor * ax_
            fy += factor * ay_
            mo += factor * am_
        return -f[0] - fx, f[1] + fy, -f[2] + f[1] * x + mo

    def _deflection(self, res: FrameResult, member: str, points: int):
        """(x, u, v): the displacement of the member's axis along (u) and
        across (v) it, member axes, at ``points`` sections plus the load
        positions and the faces of rigid end zones.  Integrated from the
        internal forces, not interpolated from the nodes: on the flexible
        length u' = N/EA and v'' = M/EI (sagging M bends the axis towards
        +y), plus the shear strain V/(G A_s) in v' for a Timoshenko member,
        with v at both flexible ends given by the nodes through the rigid
        arms — which fixes the slope constant without the end rotations, so
        a released end needs nothing special; a rigid zone moves with its
        node.  Each integral is a sum of 4-point Gauss rules between
        consecutive sections, which include every load position, so the
        integrand is one polynomial of degree <= 4 on each piece and the
        result is exact to rounding (the repeated integral by Cauchy's
        formula, v(x) = ∫ (x - s) M/EI ds)."""
        m = self._diagram_member(res, member, points)
        L, c, s = geometry(self, m)
        a, e = m.offset_i, L - m.offset_j          # the flexible length [a, e]
        pts = [p for p in load_points(self._loads_of(res, m)) + [a, e] if 0.0 < p < L]
        x = np.unique(np.r_[np.linspace(0.0, L, int(points)), pts])
        t, w = np.polynomial.legendre.leggauss(4)
        lo, hi = np.maximum(x[:-1, None], a), np.minimum(x[1:, None], e)
        gs = (0.5 * (hi - lo) * t + 0.5 * (lo + hi)).ravel()
        gw = (0.5 * np.maximum(hi - lo, 0.0) * w).ravel()
        N, V, M = self._sections(res, m, gs)
        idx = {nm: 3 * k for k, nm in enumerate(self.nodes)}
        T = rotation(c, s)[:3, :3]
        di = T @ res._u[idx[m.i]:idx[m.i] + 3]
        dj = T @ res._u[idx[m.j]:idx[m.j] + 3]
        va, ve = di[1] + a * di[2], dj[1] - m.offset_j * dj[2]   # through the rigid arms
        xf = np.clip(x, a, e)
        before = gs[None, :] < xf[:, None]
        u = di[0] + (before * (gw * N / (m.E * m.A))) @ np.ones_like(gs)
        bend = gw * M / (m.E * m.I)
        v = (before * (xf[:, None] - gs[None, :]) * bend) @ np.ones_like(gs)
        if m.GAs is not None:
            v = v + (before * (gw * V / m.GAs)) @ np.ones_like(gs)
        v_e = v[np.searchsorted(x, e)]
        v = va + v + (ve - va - v_e) * (xf - a) / (e - a)
        v = np.where(x < a, di[1] + x * di[2], np.where(x > e, dj[1] - (L - x) * dj[2], v))
        return x, u, v
    def _support_keys(self) -> list:
        """The key of each contact in FrameResult.supports, in contact order."""
        keys = []
        for c in self.contacts:
            key = c.node if c.other is None else f"{c.node}-{c.other}"
            keys.append(f"{key}#{len(keys)}" if key in keys else key)
        return keys
