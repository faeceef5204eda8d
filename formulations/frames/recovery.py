"""From the contact LCP's answer z to the frame's result: displacements,
member end actions, reactions, each support's state (decided on the
component's own scale), the global statics check; and what results read back
from the frame (diagrams, support reactions, table rows).  Mixed into
:class:`~.model.Frame`."""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidOptionError, SolverFailedError
from qpcontact.judge.lcp import certify_lcp
from qpcontact.judge.scales import ComponentScales

from . import assembly
from .assembly import DOFS, geometry
from .loads import CONSTANT, VARIABLE, load_points, section_sums
from .results import FrameResult, SupportResult

#: A normal force or slip below STATE_RTOL of its own componentwise scale is zero
#: when the support's state is named.
STATE_RTOL = 1e-9
#: The equilibrium check's limit is the requested accuracy (1e-9 at "high"), but
#: never below what rounding leaves in a right answer's per-dof residual (a few
#: thousand eps: the saddle solve's backward error on a long member chain).
EQUILIBRIUM_FLOOR = 4096 * np.finfo(float).eps


class FrameRecovery:
    """The Frame's results construction (see the module docstring)."""

    def _result_from_z(self, z, combo, route, b=None, lcp=None, tol=1e-9) -> FrameResult:
        b = b or self.build()
        if not isinstance(combo, dict):   # a number p: the P3 split
            combo = {CONSTANT: 1.0, VARIABLE: float(combo)}
        M, Q, q_gap, P, g, fric = assembly.lcp_matrices(self, b)
        lcp = lcp or assembly.combination_lcp(M, Q, q_gap, b, combo)
        z = np.maximum(np.asarray(z, float), 0.0)
        R = b["R"]
        F, RF = assembly.combine(b, combo)
        delta = P @ z - g                      # link displacements incl. contact flexibility
        X = R @ delta + RF
        nf, free = b["nf"], b["free"]
        ua = b["U"] @ assembly.factors(b, combo)     # settlements (zero at free dofs)
        fixed_idx = np.flatnonzero(b["fixed"])
        rhs = np.r_[F[free] - b["K"][free][:, fixed_idx] @ ua[fixed_idx],
                    b["kappa"] * (delta - b["H"][fixed_idx].T @ ua[fixed_idx])]
        sol = b["lu"].solve(rhs)
        u = ua.copy()
        u[free] = sol[:nf]
        # reactions at the fixed dofs: K u - F - H X on them (member loads included)
        r_all = b["K"] @ u - F - b["H"] @ X
        reactions = {}
        for node in b["names"]:
            i0 = b["idx"][node]
            if node in self.fixed:
                reactions[node] = tuple(float(r_all[i0 + k]) if b["fixed"][i0 + k] else 0.0
                                        for k in range(3))
        eq = self._equilibrium(b, combo, F, X, u, delta)
        cert = certify_lcp(lcp, z)
        pos = assembly.layout(b)
        # each state decided on the component's own scale (the certificate's):
        # X_n against the terms it is made of, a slip part against its own size
        zeta, sigma = ComponentScales(M, lcp.q_terms).at(z)
        nc = len(self.contacts)
        slot = {ci: nc + 2 * k for k, ci in enumerate(fric)}
        keys = self._support_keys()
        supports = {}
        for ci, c in enumerate(self.contacts):
            xn = float(X[pos[ci]["n"]])
            zn = float(z[ci])
            t = np.array([c.normal[1], -c.normal[0]])
            rel = np.array(u[b["idx"][c.node]:b["idx"][c.node] + 2])
            if c.other is not None:
                rel = rel - u[b["idx"][c.other]:b["idx"][c.other] + 2]
            if "t" in pos[ci]:
                xt = float(X[pos[ci]["t"]])
                slip = float(delta[pos[ci]["t"]])
            else:  # frictionless: no tangential link, the node slides freely
                xt, slip = 0.0, float(t @ rel)
            if xn <= STATE_RTOL * sigma[ci]:
                state = "separated"
                xn = 0.0 if ci not in slot else xn
            elif ci not in slot:
                state = "closed"
            elif max(z[slot[ci]], z[slot[ci] + 1]) <= STATE_RTOL * max(zeta[slot[ci]],
                                                                       zeta[slot[ci] + 1]):
                state = "stick"
            else:
                state = "slip+" if slip > 0 else "slip-"
            if state == "separated":
                xn, xt = 0.0, 0.0   # rounding noise of a force that is zero
            supports[keys[ci]] = SupportResult(state, xn, xt, zn, slip)
        displacements = {nd: tuple(float(u[b["idx"][nd] + k]) for k in range(3))
                         for nd in b["names"]}
        member_forces = {}
        for name, (k, fes, T, dofs) in b["local"].items():
            member_forces[name] = k @ (T @ u[dofs]) - sum(
                (combo[case] * fe for case, fe in fes.items() if combo.get(case)), np.zeros(6))
        ok = cert.ok(tol) and eq <= max(tol, EQUILIBRIUM_FLOOR)
        msg = (f"{route}: LCP certificate {cert.error:.1e}, equilibrium residual {eq:.1e}"
               + ("" if ok else " — CHECK FAILED"))
        return FrameResult(p=float(combo.get(VARIABLE, 0.0)), supports=supports,
                           displacements=displacements, member_forces=member_forces,
                           reactions=reactions, equilibrium_residual=eq, lcp_error=cert.error,
                           route=route, ok=ok, message=msg, frame=self, _u=u,
                           combination=dict(combo))

    def _equilibrium(self, b, combo, F, X, u, delta):
        """Equilibrium judged dof by dof, each on its own scale: the residual of
        K u = F + H X at every free dof against the sum of the absolute values
        of the terms that make it — |K||u|, |F| and, since X = R Δ + R_F is
        itself a sum, |H| (|R||Δ| + |R_F|).  Returns the largest ratio (a
        componentwise backward error, like the LCP certificate's; the reactions
        at fixed dofs are those rows' remainders, so they hold by definition
        and the global resultant follows from the free rows).

        R and R_F come from one LU solve each, accurate to rounding of their
        largest entries, not of each entry: R is known to R_ROUNDING x kappa
        (assembly.build drops entries that small) and R_F to R_ROUNDING of
        its case's largest entry, so that much of each X is not counted as a
        residual.  On a 200-span beam with long lifted stretches the dropped
        entries of R times the large openings there were the whole 1e-9; a
        zero friction force computed as 1.6e-15 out of loads of 200 is the
        other case.  The old check (the resultant against the largest load,
        fixed limit 1e-8) failed right answers that independent statics
        confirmed."""
        free = b["free"]
        K = b["K"]
        res = (K @ u - F - b["H"] @ X)[free]
        fac = np.abs(assembly.factors(b, combo))
        absH = np.abs(b["H"])
        x_terms = np.abs(b["R"]) @ np.abs(delta) + np.abs(b["RF"]) @ fac
        scale = (abs(K) @ np.abs(u) + np.abs(b["F"]) @ fac + absH @ x_terms)[free]
        rf_big = np.abs(b["RF"]).max(axis=0, initial=0.0) @ fac
        known = (absH @ np.full(X.shape, assembly.R_ROUNDING * (b["kappa"] * np.abs(delta).sum()
                                                                + rf_big)))[free]
        excess = np.maximum(np.abs(res) - known, 0.0)
        ratio = np.divide(excess, scale, out=np.zeros_like(excess), where=scale > 0)
        ratio[(scale <= 0) & (excess > 0)] = np.inf
        return float(ratio.max(initial=0.0))

    def _diagram(self, res: FrameResult, member: str, points: int):
        m = self._member(member)
        if not res.member_forces:
            raise SolverFailedError(f"no diagram: this result is not an equilibrium ({res.message})")
        L, c, s = geometry(self, m)
        f = res.member_forces[member]
        loads = [ld for ld in m.loads if res.combination.get(ld.case)]
        factor = {ld.case: res.combination[ld.case] for ld in loads}
        x = np.linspace(0.0, L, max(int(points), 2))
        pts = [p for p in load_points(loads) if 0.0 < p < L]
        # both sides of every load position: jumps of V (point loads) and M (moments)
        x = np.unique(np.r_[x, pts, np.nextafter(np.array(pts, float), -np.inf)])
        fx = np.zeros_like(x)
        fy = np.zeros_like(x)
        mo = np.zeros_like(x)
        for case in set(factor):
            ax_, ay_, am_ = section_sums([ld for ld in loads if ld.case == case], x, c, s)
            fx += factor[case] * ax_
            fy += factor[case] * ay_
            mo += factor[case] * am_
        N = -f[0] - fx
        V = f[1] + fy
        M = -f[2] + f[1] * x + mo
        return x, N, V, M

    def _support_reactions(self, res: FrameResult) -> dict:
        out = {}
        for node, r in res.reactions.items():
            out[node] = tuple(float(v) for v in r)
        for node, ks in self.springs.items():
            u = res.displacements[node]
            r = tuple(-ks.get(d, 0.0) * u[k] for k, d in enumerate(DOFS))
            key = f"{node} (spring)" if node in out else node
            out[key] = r
        for key, c in zip(self._support_keys(), self.contacts):
            s = res.supports[key]
            t = np.array([c.normal[1], -c.normal[0]])
            fxy = s.normal * c.normal + s.tangential * t
            out[f"{key} (contact)" if key in out else key] = (float(fxy[0]), float(fxy[1]), 0.0)
        return out

    def _rows(self, res: FrameResult, table: str) -> list:
        force, length = self.units
        if table == "supports":
            return [{"support": k, "state": s.state, f"X_n [{force}]": s.normal,
                     f"X_t [{force}]": s.tangential, f"opening [{length}]": s.opening,
                     f"slip [{length}]": s.slip} for k, s in res.supports.items()]
        if table == "reactions":
            return [{"support": k, f"Fx [{force}]": r[0], f"Fy [{force}]": r[1],
                     f"Mz [{force}·{length}]": r[2]}
                    for k, r in res.support_reactions.items()]
        if table == "members":
            rows = []
            for name in self.members:
                ends = res.end_forces(name)
                ext = res.extremes(name)
                rows.append({"member": name,
                             f"N_i [{force}]": ends["i"][0], f"V_i [{force}]": ends["i"][1],
                             f"M_i [{force}·{length}]": ends["i"][2],
                             f"N_j [{force}]": ends["j"][0], f"V_j [{force}]": ends["j"][1],
                             f"M_j [{force}·{length}]": ends["j"][2],
                             f"M_max [{force}·{length}]": ext["M"]["max"][0],
                             f"x(M_max) [{length}]": ext["M"]["max"][1],
                             f"M_min [{force}·{length}]": ext["M"]["min"][0],
                             f"x(M_min) [{length}]": ext["M"]["min"][1]})
            return rows
        if table == "displacements":
            return [{"node": nd, f"ux [{length}]": d[0], f"uy [{length}]": d[1], "rz [rad]": d[2]}
                    for nd, d in res.displacements.items()]
        raise InvalidOptionError(f"unknown table {table!r}; tables: supports, reactions, "
                                 "members, displacements")

    def _support_keys(self) -> list:
        """The key of each contact in FrameResult.supports, in contact order."""
        keys = []
        for c in self.contacts:
            key = c.node if c.other is None else f"{c.node}-{c.other}"
            keys.append(f"{key}#{len(keys)}" if key in keys else key)
        return keys
