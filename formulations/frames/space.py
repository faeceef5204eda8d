"""Space frames (issue 35, in progress): the model and its linear assembly.

Six dofs per node, (ux, uy, uz, rx, ry, rz) in global axes (right-handed,
rotations counterclockwise about each axis); members are the 3-D
beam-column elements of :mod:`.elements3d`; bilateral supports fix any
subset of the six dofs; springs resist -k·u on any dof; loads belong to
named cases as in 2-D (:mod:`.loads`).  Units the user's, consistent.

What is here: the model, K and the load columns, the linear solution of a
frame held by bilateral supports and springs (``solve_linear``), and
unilateral contacts with Coulomb's cone in facets solved as an LCP by
Lemke's method (``solve``).  Still to come (docs/dev-notes.md, "Issue 35"):
the circular cone through the friction solvers, ``solve_combinations`` and
``trace``, the active set, results, tables and drawings as in 2-D.

Contacts (P3 in 3-D): at a node, a contact plane with unit normal n from the
support into the structure, tangents t1, t2 (t1 = n x e normalised for the
global axis e least aligned with n, t2 = n x t1).  Links: the opening Z_n =
g + n·u (+X_n/k), and with friction f > 0 the tangential displacement
(t1·u, t2·u) (+X_t/k).  The cone |X_t| <= f X_n is replaced by the m-gon
circumscribing it: w_k = f X_n + d_k·X_t >= 0 for the facet directions d_k =
cos(2πk/m) t1 + sin(2πk/m) t2, k = 0..m-1, each complementary to a slip
magnitude Z_k >= 0 along d_k (the slip is Σ Z_k d_k; slipping along d_k
takes the friction force to -f X_n along it).  With m = 2 in a plane this
is P3's 2-D LCP; along the directions d_k the faceted and circular cones
agree, between them the facets allow up to 1/cos(π/m) more friction.

Member loads: a uniform load per unit length over the whole member, in
global or member axes.  Its equivalent nodal loads are the fixed-end forces,
exact for this element: w L / 2 at each end along each axis, and the
end moments w L² / 12 — in the x-y plane +q_y L²/12 about z at i and minus
that at j; in the x-z plane the signs reversed (a positive θy turns +z
towards -x).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from qpcontact.core.errors import InvalidProblemError, NoSolutionError, SolverFailedError

from qpcontact import solve as qp_solve
from qpcontact.core.problems import LCP
from qpcontact.judge.lcp import certify_lcp

from . import assembly
from .elements3d import axes, rotation, stiffness
from .loads import CONSTANT, case_name, check_axes, combination, number

DOFS = ("ux", "uy", "uz", "rx", "ry", "rz")


class SpaceFrame:
    """A space frame (see the module docstring); ``units`` = (force, length)
    names, for tables and drawings only."""

    def __init__(self, units=("kN", "m")):
        self.units = tuple(units)
        self.nodes: dict[str, np.ndarray] = {}
        self.members: dict[str, dict] = {}
        self.fixed: dict[str, set] = {}
        self.springs: dict[str, dict] = {}
        self.nodal_loads: list = []   # (node, 6 values, case)
        self.member_loads: list = []  # (member, (wx, wy, wz), axes, case)
        self.contacts: list = []      # dicts: node, n, t1, t2, friction, gap, stiffness, facets

    def _node(self, name):
        if name not in self.nodes:
            raise InvalidProblemError(f"no node named {name!r}; nodes: {list(self.nodes)}")
        return name

    def add_node(self, name: str, x: float, y: float, z: float) -> str:
        if name in self.nodes:
            raise InvalidProblemError(f"node {name!r} exists already")
        self.nodes[name] = np.array([number(v, f"node {name!r}: {c}")
                                     for v, c in zip((x, y, z), "xyz")])
        return name

    def add_member(self, i: str, j: str, E: float, G: float, A: float, Iy: float, Iz: float,
                   J: float, *, name: str | None = None, ref=None, roll: float = 0.0) -> str:
        """A member from node i to node j: E, G, A, Iy, Iz (about the local y
        and z axes), J; its local x-z plane contains ``ref`` (default global
        Z, or X for a vertical member), turned by ``roll`` (radians) about x."""
        self._node(i), self._node(j)
        if i == j:
            raise InvalidProblemError("a member needs two different nodes")
        what = f"member {i}-{j}" if name is None else f"member {name!r}"
        props = {}
        for v, nm in ((E, "E"), (G, "G"), (A, "A"), (Iy, "Iy"), (Iz, "Iz"), (J, "J")):
            props[nm] = number(v, f"{what}: {nm}")
            if not props[nm] > 0:
                raise InvalidProblemError(f"{what}: {nm} must be positive; got {v}")
        if ref is not None:
            ref = np.asarray(ref, float)
            if ref.shape != (3,) or not np.all(np.isfinite(ref)):
                raise InvalidProblemError(f"{what}: ref must be a finite 3-vector")
        roll = number(roll, f"{what}: roll")
        axes(self.nodes[i], self.nodes[j], ref, roll)      # refuses a bad reference now
        name = name or f"M{len(self.members) + 1}"
        if name in self.members:
            raise InvalidProblemError(f"member {name!r} exists already")
        self.members[name] = dict(i=i, j=j, ref=ref, roll=roll, **props)
        return name

    def add_support(self, node: str, fix=DOFS) -> None:
        self._node(node)
        fix = (fix,) if isinstance(fix, str) else tuple(fix)
        bad = [d for d in fix if d not in DOFS]
        if bad:
            raise InvalidProblemError(f"fix must name dofs among {DOFS}; got {bad}")
        self.fixed.setdefault(node, set()).update(fix)

    def add_spring(self, node: str, **stiffnesses) -> None:
        """Springs to the ground on the named dofs: add_spring("A", uz=1e5)."""
        self._node(node)
        bad = [d for d in stiffnesses if d not in DOFS]
        if bad:
            raise InvalidProblemError(f"spring at {node!r}: dofs among {DOFS}; got {bad}")
        slot = self.springs.setdefault(node, {})
        for d, v in stiffnesses.items():
            v = number(v, f"spring at {node!r}: {d}")
            if v < 0:
                raise InvalidProblemError(f"spring at {node!r}: {d} must be >= 0; got {v}")
            slot[d] = slot.get(d, 0.0) + v

    def add_load(self, node: str, fx=0.0, fy=0.0, fz=0.0, mx=0.0, my=0.0, mz=0.0,
                 case: str = CONSTANT) -> None:
        self._node(node)
        vals = tuple(number(v, f"load at {node!r}: {c}") for v, c in
                     zip((fx, fy, fz, mx, my, mz), ("fx", "fy", "fz", "mx", "my", "mz")))
        self.nodal_loads.append((node, vals, case_name(case)))

    def add_distributed_load(self, member: str, wx=0.0, wy=0.0, wz=0.0, case: str = CONSTANT,
                             *, axes: str = "global") -> None:
        """A uniform load per unit length over the whole member."""
        if member not in self.members:
            raise InvalidProblemError(f"no member named {member!r}; members: {list(self.members)}")
        w = tuple(number(v, f"distributed load on {member}: {c}")
                  for v, c in zip((wx, wy, wz), ("wx", "wy", "wz")))
        self.member_loads.append((member, w, check_axes(axes), case_name(case)))

    def add_contact(self, node: str, normal=(0.0, 0.0, 1.0), friction: float = 0.0,
                    gap: float = 0.0, stiffness: float | None = None, facets: int = 8) -> int:
        """A unilateral support at ``node`` (the module docstring): its
        normal, Coulomb coefficient, initial gap, spring (None: rigid) and
        the number of facets of its friction cone (even, >= 4)."""
        self._node(node)
        n = np.asarray(normal, float)
        if n.shape != (3,) or not np.all(np.isfinite(n)) or not np.linalg.norm(n) > 0:
            raise InvalidProblemError(f"contact at {node!r}: normal must be a nonzero 3-vector")
        n = n / np.linalg.norm(n)
        friction, gap = number(friction, "friction"), number(gap, "gap")
        if friction < 0 or gap < 0:
            raise InvalidProblemError(f"contact at {node!r}: friction and gap must be >= 0")
        if stiffness is not None and not number(stiffness, "stiffness") > 0:
            raise InvalidProblemError(f"contact at {node!r}: stiffness must be > 0 or None")
        if isinstance(facets, bool) or not isinstance(facets, int) or facets < 4 or facets % 2:
            raise InvalidProblemError(f"contact at {node!r}: facets must be an even integer "
                                      f">= 4 (opposite directions both facets); got {facets!r}")
        e = np.eye(3)[int(np.argmin(np.abs(n)))]
        t1 = np.cross(n, e)
        t1 /= np.linalg.norm(t1)
        self.contacts.append(dict(node=node, n=n, t1=t1, t2=np.cross(n, t1), friction=friction,
                                  gap=gap, stiffness=None if stiffness is None else
                                  float(stiffness), facets=facets))
        return len(self.contacts) - 1

    @property
    def load_cases(self) -> list:
        names = {CONSTANT}
        names.update(c for *_, c in self.nodal_loads)
        names.update(c for *_, c in self.member_loads)
        return sorted(names)

    def assemble(self):
        """(K (CSR), F (dofs x cases), fixed mask, cases, idx)."""
        names = list(self.nodes)
        idx = {nm: 6 * k for k, nm in enumerate(names)}
        N = 6 * len(names)
        cases = self.load_cases
        col = {c: k for k, c in enumerate(cases)}
        F = np.zeros((N, len(cases)))
        ms = list(self.members.values())
        rows, cols, vals = [], [], []
        if ms:
            xi = np.array([self.nodes[m["i"]] for m in ms])
            xj = np.array([self.nodes[m["j"]] for m in ms])
            R = np.stack([axes(xi[k], xj[k], m["ref"], m["roll"])[0] for k, m in enumerate(ms)])
            T = rotation(R)
            L = np.linalg.norm(xj - xi, axis=1)
            k_local = stiffness(*(np.array([m[p] for m in ms]) for p in
                                  ("E", "G", "A", "Iy", "Iz", "J")), L)
            kg = T.transpose(0, 2, 1) @ k_local @ T
            dofs = np.array([np.r_[idx[m["i"]] + np.arange(6), idx[m["j"]] + np.arange(6)]
                             for m in ms])
            rows.append(np.repeat(dofs, 12, axis=1).ravel())
            cols.append(np.tile(dofs, (1, 12)).ravel())
            vals.append(kg.ravel())
            where = {nm: k for k, nm in enumerate(self.members)}
            for member, w, ax, case in self.member_loads:
                k = where[member]
                q = np.asarray(w) if ax == "member" else R[k] @ np.asarray(w)
                fe = _fixed_end(q, L[k])
                F[dofs[k], col[case]] += T[k].T @ fe
        for node, v, case in self.nodal_loads:
            F[idx[node]:idx[node] + 6, col[case]] += v
        K = assembly.stiffness_matrix(rows, cols, vals, self.springs, idx, DOFS, N)
        fixed = np.zeros(N, bool)
        for node, fx in self.fixed.items():
            for d in fx:
                fixed[idx[node] + DOFS.index(d)] = True
        return K, F, fixed, cases, idx

    def solve_linear(self, combination_: dict | None = None) -> dict:
        """Displacements {node: 6-tuple} of a frame held by its bilateral
        supports and springs alone, under ``combination_`` {case: factor}
        (default the case "constant")."""
        K, F, fixed, cases, idx = self.assemble()
        combo = combination(combination_ or {CONSTANT: 1.0}, set(cases))
        f = F @ np.array([combo.get(c, 0.0) for c in cases])
        free = np.flatnonzero(~fixed)
        Kf = K[free][:, free].tocsc()
        try:
            lu = spla.splu(Kf)
            piv = np.abs(lu.U.diagonal())
            regular = piv.size and piv.min() > 1e-13 * piv.max()
        except RuntimeError:
            regular = False
        if not regular:
            raise InvalidProblemError("the space frame is a mechanism on its bilateral supports "
                                      "and springs: add supports or members")
        u = np.zeros(K.shape[0])
        u[free] = lu.solve(f[free])
        return {nd: tuple(u[idx[nd]:idx[nd] + 6]) for nd in self.nodes}


    def _links(self, idx, N):
        """H (N x links) and per link (contact, kind "n" | "t1" | "t2")."""
        rows, cols, vals, info = [], [], [], []
        for ci, c in enumerate(self.contacts):
            kinds = ("n", "t1", "t2") if c["friction"] > 0 else ("n",)
            for kind in kinds:
                for d in range(3):
                    rows.append(idx[c["node"]] + d)
                    cols.append(len(info))
                    vals.append(c[kind][d])
                info.append((ci, kind))
        H = sp.csr_matrix((vals, (rows, cols)), shape=(N, len(info)))
        H.eliminate_zeros()
        return H, info

    def _lcp_maps(self, info):
        """P (links x z) and W (z x links) of the faceted cones, the gaps g."""
        nl = len(info)
        pos = {}
        for li, (ci, kind) in enumerate(info):
            pos.setdefault(ci, {})[kind] = li
        nc = len(self.contacts)
        pr, pc, pv, wr, wc, wv = [], [], [], [], [], []
        g = np.zeros(nl)
        nz = nc
        for ci, c in enumerate(self.contacts):
            pr.append(pos[ci]["n"]), pc.append(ci), pv.append(1.0)
            wr.append(ci), wc.append(pos[ci]["n"]), wv.append(1.0)
            g[pos[ci]["n"]] = c["gap"]
            if c["friction"] == 0:
                continue
            for k in range(c["facets"]):
                a = 2 * np.pi * k / c["facets"]
                for kind, comp in (("t1", np.cos(a)), ("t2", np.sin(a))):
                    pr.append(pos[ci][kind]), pc.append(nz), pv.append(comp)
                    wr.append(nz), wc.append(pos[ci][kind]), wv.append(comp)
                wr.append(nz), wc.append(pos[ci]["n"]), wv.append(c["friction"])
                nz += 1
        P = sp.csr_matrix((pv, (pr, pc)), shape=(nl, nz))
        W = sp.csr_matrix((wv, (wr, wc)), shape=(nz, nl))
        return P, W, g

    def _resultant(self, idx, f, hx, reactions, size_hx, size_k):
        """Σ forces and Σ moments (about the nodes' centroid) of the loads,
        contact forces and reactions, each against the sum of its terms'
        sizes (as the plane frame's resultant check; a reaction by |K||u| at
        its dof only where it is one).  Refuses what a per-dof check passes
        when a rigid motion inflates |K||u|: Lemke's answer for a table on
        rigid frictional pads held a free sliding of 3.5e9 m, its normal
        forces summing to 40.26 under a 40 kN weight."""
        names = list(self.nodes)
        xyz = np.array([self.nodes[n] for n in names])
        xyz = xyz - xyz.mean(axis=0)
        rows = np.array([idx[n] for n in names])
        total = (f + hx + reactions).reshape(-1, 6)[np.argsort(rows)]
        size = (np.abs(f) + size_hx + np.where(reactions != 0, size_k, 0.0)).reshape(-1, 6)
        size = size[np.argsort(rows)]
        force, moment = total[:, :3], total[:, 3:] + np.cross(xyz, total[:, :3])
        fs, ms = size[:, :3], size[:, 3:] + np.abs(xyz).sum(axis=1)[:, None] * size[:, :3].sum(
            axis=1)[:, None]
        out = 0.0
        for res, sc in ((np.abs(force.sum(axis=0)), fs.sum(axis=0)),
                        (np.abs(moment.sum(axis=0)), ms.sum(axis=0))):
            floor = assembly.R_ROUNDING * len(names) * sc.max(initial=0.0)
            excess = np.maximum(res - floor, 0.0)
            out = max(out, float(np.max(excess / np.where(sc > 0, sc, 1.0), initial=0.0)))
        return out

    def solve(self, combination_: dict | None = None, accuracy="high") -> dict:
        """The frame under ``combination_`` {case: factor} (default the case
        "constant") on its contacts: Lemke on the faceted-cone LCP, the answer
        rebuilt from the data and checked (the LCP certificate and
        equilibrium at every free dof on its own scale).  Returns a dict:
        ``supports`` {contact: (state, X_n, X_t (t1, t2), opening, slip
        (t1, t2))}, ``displacements``, ``reactions`` (global, at fixed dofs),
        ``lcp_error``, ``equilibrium_residual``, ``ok``, ``message``."""
        from qpcontact.core.accuracy import resolve_accuracy

        _, tol = resolve_accuracy(accuracy)
        if not self.contacts:
            raise InvalidProblemError("the space frame has no contacts: use solve_linear")
        K, F, fixed, cases, idx = self.assemble()
        N = K.shape[0]
        H, info = self._links(idx, N)
        flex = np.array([0.0 if self.contacts[ci]["stiffness"] is None
                         else 1.0 / self.contacts[ci]["stiffness"] for ci, _ in info])
        b = dict(assembly.basic_system(K, H, fixed, flex, np.arange(N) % 6 < 3), info=info,
                 cases=cases, F=F, U=np.zeros_like(F), H=H)
        if b["lu"] is None:
            raise InvalidProblemError("the space frame is a mechanism even with every contact "
                                      "closed: add supports, contacts or friction")
        b.update(assembly.contact_stiffness(b))
        combo = combination(combination_ or {CONSTANT: 1.0}, set(cases))
        factors = np.array([combo.get(c, 0.0) for c in cases])
        P, W, g = self._lcp_maps(info)
        R, RF = b["R"], b["RF"] @ factors
        M = np.asarray((P.T @ (W @ R).T).T)
        q = np.asarray(W @ RF) - np.asarray(W @ (R @ g))
        lcp = LCP(M, q, q_terms=np.abs(W) @ np.abs(RF) + np.abs(W @ (R @ g)))
        sol = qp_solve(lcp, method="lemke", accuracy=accuracy)
        if sol.z is None:
            err = NoSolutionError if sol.stats.get("proved_infeasible") else SolverFailedError
            raise err(f"space frame: Lemke found no contact state ({sol.message})")
        z = np.maximum(sol.z, 0.0)
        delta = P @ z - g
        nf, kappa = b["nf"], b["kappa"]
        f = F @ factors
        out = b["lu"].solve(np.r_[f[b["free"]], kappa * delta])
        u = np.zeros(N)
        u[b["free"]] = out[:nf]
        X = -kappa * out[nf:]
        r_all = K @ u - f - H @ X
        res = np.abs(r_all)[b["free"]]
        scale = (abs(K) @ np.abs(u) + np.abs(f) + abs(H) @ np.abs(X))[b["free"]]
        floor = assembly.R_ROUNDING * scale.max(initial=0.0)
        eq = float(np.max(np.maximum(res - floor, 0.0) / np.where(scale > 0, scale, 1.0),
                          initial=0.0))
        eq = max(eq, self._resultant(idx, f, H @ X, np.where(fixed, r_all, 0.0), abs(H) @ np.abs(X),
                                     abs(K) @ np.abs(u)))
        cert = certify_lcp(lcp, z).error
        supports = {}
        pos = {}
        for li, (ci, kind) in enumerate(info):
            pos.setdefault(ci, {})[kind] = li
        big = np.abs(X).max(initial=0.0)
        for ci, c in enumerate(self.contacts):
            xn = X[pos[ci]["n"]]
            xt = np.array([X[pos[ci][k]] if k in pos[ci] else 0.0 for k in ("t1", "t2")])
            d = u[idx[c["node"]]:idx[c["node"]] + 3]
            slip = np.array([delta[pos[ci][k]] if k in pos[ci] else c[k] @ d
                             for k in ("t1", "t2")])
            if xn <= 1e-9 * big:
                state = "separated"
            elif c["friction"] == 0:
                state = "closed"
            elif np.linalg.norm(slip) <= 1e-9 * max(np.abs(delta).max(initial=0.0), 1e-300):
                state = "stick"
            else:
                state = "slip"
            supports[f"{c['node']}#{ci}" if any(o["node"] == c["node"] for o in
                                                 self.contacts[:ci]) else c["node"]] = (
                state, float(xn), xt, float(z[ci]), slip)
        ok = cert <= tol and eq <= max(tol, assembly.R_ROUNDING)
        return dict(supports=supports, ok=ok, lcp_error=cert, equilibrium_residual=eq,
                    displacements={nd: tuple(u[idx[nd]:idx[nd] + 6]) for nd in self.nodes},
                    reactions={nd: tuple(np.where(fixed, r_all, 0.0)[idx[nd]:idx[nd] + 6])
                               for nd in self.fixed},
                    message=f"lemke: LCP certificate {cert:.1e}, equilibrium residual {eq:.1e}"
                            + ("" if ok else " — CHECK FAILED"))


def _fixed_end(q, L) -> np.ndarray:
    """Equivalent nodal loads (member axes, 12) of a uniform load q = (qx,
    qy, qz) per unit length over a member of length L."""
    qx, qy, qz = q
    m_y, m_z = qz * L * L / 12.0, qy * L * L / 12.0
    return np.array([qx * L / 2, qy * L / 2, qz * L / 2, 0.0, -m_y, m_z,
                     qx * L / 2, qy * L / 2, qz * L / 2, 0.0, m_y, -m_z])

