"""Space frames on unilateral frictional supports: P3's displacement method
in three dimensions.

Six dofs per node, (ux, uy, uz, rx, ry, rz) in global axes (right-handed,
rotations counterclockwise about each axis); members are the 3-D
beam-column elements of :mod:`.elements3d`; bilateral supports fix any
subset of the six dofs; springs resist -k·u on any dof; loads belong to
named cases as in 2-D (:mod:`.loads`).  Units the user's, consistent.

What is here: the model, K and the load columns, the linear solution of a
frame held by bilateral supports and springs (``solve_linear``), and the
assembly of its contact problem (``build``).  Solving, combinations and the
trace are the plane frame's (:mod:`.solving`, :mod:`.tracing`: the LCP is
the same in any dimension once the links and the cone's facets are laid
out); the results are built in :mod:`.space_recovery` (the circular cone's
in :mod:`.space_circular`), tabulated in :mod:`.space_tables` and drawn in
:mod:`.space_drawing`.

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
agree, between them the facets allow up to 1/cos(π/m) more friction.  Where
the node's bilateral supports hold one tangent, that tangent has no link
and the cone is the segment along the other, two facets: a planar frame
built in space has exactly the plane frame's LCP.

Member loads: a uniform load per unit length over the whole member, in
global or member axes.  Its equivalent nodal loads are the fixed-end forces,
exact for this element: w L / 2 at each end along each axis, and the
end moments w L² / 12 — in the x-y plane +q_y L²/12 about z at i and minus
that at j; in the x-z plane the signs reversed (a positive θy turns +z
towards -x).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from qpcontact.core.errors import InvalidProblemError

from . import assembly
from .elements3d import axes, rotation, stiffness
from .loads import CONSTANT, VARIABLE, case_name, check_axes, combination, number
from .solving import FrameSolving
from .space_circular import CircularCone
from .space_recovery import DOFS, SpaceFrameResult, SpaceRecovery
from .tracing import FrameTracing


@dataclass
class SpaceContact:
    """A unilateral support at a node: unit normal n (from the support into
    the structure), tangents t1, t2, Coulomb coefficient, initial gap,
    stiffness (None: rigid), facets of the friction cone's polygon."""

    node: str
    normal: np.ndarray
    t1: np.ndarray
    t2: np.ndarray
    friction: float
    gap: float
    stiffness: float | None
    facets: int
    other: None = None


class SpaceFrame(CircularCone, SpaceRecovery, FrameSolving, FrameTracing):
    """A space frame (see the module docstring); ``units`` = (force, length)
    names, for tables and drawings only.

    ``solve(p, method="auto", combination=...)``, ``solve_combinations`` and
    ``trace`` are the plane frame's (:class:`~.model.Frame`): "auto" is
    Lemke on the faceted-cone LCP (the exact SPD method without friction),
    then the load path where Lemke's answer fails the frame's checks;
    "lemke" alone, or a registered LCP method or QP backend for a
    frictionless frame.  ``friction_problem`` gives the circular-cone
    problem (3-D FrictionProblem, global form) for the friction solvers and
    FCLIB; ``solve(..., cone="circular")`` solves it by them ("auto" or a
    friction method's name) and gives the frame's result
    (:mod:`.space_circular`)."""

    ROUTES = ("auto", "lemke")
    RESULT = SpaceFrameResult

    def __init__(self, units=("kN", "m")):
        self.units = tuple(units)
        self.nodes: dict[str, np.ndarray] = {}
        self.members: dict[str, dict] = {}
        self.fixed: dict[str, set] = {}
        self.springs: dict[str, dict] = {}
        self.nodal_loads: list = []   # (node, 6 values, case)
        self.member_loads: list = []  # (member, (wx, wy, wz), axes, case)
        self.contacts: list = []      # SpaceContact

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
        if not np.linalg.norm(self.nodes[j] - self.nodes[i]) > 0:
            raise InvalidProblemError(f"{what}: nodes {i} and {j} coincide")
        try:
            axes(self.nodes[i], self.nodes[j], ref, roll)
        except InvalidProblemError as exc:     # it numbers the member; name it
            raise InvalidProblemError(
                f"{what}: its reference vector {tuple(map(float, ref))} is parallel to the "
                "member; give one in the plane of the member's local x-z axes") from exc
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
                    gap: float = 0.0, stiffness: float | None = None, facets: int = 16) -> int:
        """A unilateral support at ``node`` (the module docstring): its
        normal, Coulomb coefficient, initial gap, spring (None: rigid) and
        the number of facets of its friction cone (even, >= 4; the default 16
        allows at most 2 % more friction than Coulomb's circle between facet
        directions, 8 facets 8.2 %: docs/frames.md)."""
        self._node(node)
        try:
            n = np.asarray(normal, float)
        except (TypeError, ValueError):
            n = np.zeros(0)
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
        self.contacts.append(SpaceContact(node, n, t1, np.cross(n, t1), friction, gap,
                                          None if stiffness is None else float(stiffness),
                                          facets))
        return len(self.contacts) - 1

    @property
    def load_cases(self) -> list:
        names = {CONSTANT, VARIABLE}
        names.update(c for *_, c in self.nodal_loads)
        names.update(c for *_, c in self.member_loads)
        return sorted(names)

    @property
    def has_friction(self) -> bool:
        return any(c.friction > 0 for c in self.contacts)

    def assemble(self):
        """(K (CSR), F (dofs x cases), fixed mask, cases, idx, local): local =
        the members' (k (m, 12, 12), T, dofs (m, 12), Fe (m, 12, cases):
        their fixed-end forces in member axes), as the plane frame's."""
        names = list(self.nodes)
        idx = {nm: 6 * k for k, nm in enumerate(names)}
        N = 6 * len(names)
        cases = self.load_cases
        col = {c: k for k, c in enumerate(cases)}
        F = np.zeros((N, len(cases)))
        ms = list(self.members.values())
        rows, cols, vals = [], [], []
        m = len(ms)
        k_local, T = np.zeros((m, 12, 12)), np.zeros((m, 12, 12))
        dofs, Fe = np.zeros((m, 12), int), np.zeros((m, 12, len(cases)))
        if ms:
            xi = np.array([self.nodes[m_["i"]] for m_ in ms])
            xj = np.array([self.nodes[m_["j"]] for m_ in ms])
            ref = np.array([np.full(3, np.nan) if m_["ref"] is None else m_["ref"] for m_ in ms])
            R = axes(xi, xj, ref, np.array([m_["roll"] for m_ in ms]))
            T = rotation(R)
            L = np.linalg.norm(xj - xi, axis=1)
            k_local = stiffness(*(np.array([m_[p] for m_ in ms]) for p in
                                  ("E", "G", "A", "Iy", "Iz", "J")), L)
            kg = T.transpose(0, 2, 1) @ k_local @ T
            dofs = np.array([np.r_[idx[m_["i"]] + np.arange(6), idx[m_["j"]] + np.arange(6)]
                             for m_ in ms])
            rows.append(np.repeat(dofs, 12, axis=1).ravel())
            cols.append(np.tile(dofs, (1, 12)).ravel())
            vals.append(kg.ravel())
            where = {nm: k for k, nm in enumerate(self.members)}
            for member, w, ax, case in self.member_loads:
                k = where[member]
                q = np.asarray(w) if ax == "member" else R[k] @ np.asarray(w)
                Fe[k, :, col[case]] += _fixed_end(q, L[k])
            np.add.at(F, dofs.ravel(), (T.transpose(0, 2, 1) @ Fe).reshape(-1, len(cases)))
        for node, v, case in self.nodal_loads:
            F[idx[node]:idx[node] + 6, col[case]] += v
        K = assembly.stiffness_matrix(rows, cols, vals, self.springs, idx, DOFS, N)
        fixed = np.zeros(N, bool)
        for node, fx in self.fixed.items():
            for d in fx:
                fixed[idx[node] + DOFS.index(d)] = True
        return K, F, fixed, cases, idx, (k_local, T, dofs, Fe)

    def solve_linear(self, combination_: dict | None = None) -> dict:
        """Displacements {node: 6-tuple} of a frame held by its bilateral
        supports and springs alone, under ``combination_`` {case: factor}
        (default the case "constant")."""
        K, F, fixed, cases, idx, _ = self.assemble()
        combo = combination(combination_ or {CONSTANT: 1.0}, set(cases))
        f = F @ np.array([combo.get(c, 0.0) for c in cases])
        free = np.flatnonzero(~fixed)
        lu = assembly.regular_lu(K[free][:, free].tocsc())
        if lu is None:
            raise InvalidProblemError("the space frame is a mechanism on its bilateral supports "
                                      "and springs: add supports or members")
        u = np.zeros(K.shape[0])
        u[free] = lu.solve(f[free])
        return {nd: tuple(u[idx[nd]:idx[nd] + 6]) for nd in self.nodes}

    def build(self):
        """The assembly the solving routes share with the plane frame (an
        :class:`~.assembly.Built`): K, loads, links, the basic system's LU,
        the faceted cones' maps; R and R_F on first use."""
        if not self.contacts:
            raise InvalidProblemError("the space frame has no contacts: it is a linear problem "
                                      "(solve_linear); add_contact() defines unilateral supports")
        self._check_conflicts()
        K, F, fixed, cases, idx, local = self.assemble()
        N = K.shape[0]
        H, info = self._links(idx, N)
        flex = np.array([0.0 if self.contacts[ci].stiffness is None
                         else 1.0 / self.contacts[ci].stiffness for ci, _ in info])
        basic = assembly.basic_system(K, H, fixed, flex, np.arange(N) % 6 < 3)
        if basic["lu"] is None:
            raise InvalidProblemError(assembly.mechanism_message(
                basic["S"], basic["free"], list(self.nodes), basic["nf"], DOFS))
        springs = np.zeros(N)
        for node, ks in self.springs.items():
            for d, kval in ks.items():
                springs[idx[node] + DOFS.index(d)] += kval
        b = assembly.Built(springs=springs, names=list(self.nodes), idx=idx, K=K, F=F,
                           U=np.zeros_like(F), cases=cases, fixed=fixed, H=H, info=info,
                           flex=flex, local=local, Tn=None, **basic)
        b["maps"] = self._lcp_maps(info)
        return b

    def _held(self, c, vec) -> bool:
        """Whether the bilateral supports at c's node fix the direction vec."""
        held = self.fixed.get(c.node, set())
        return all(d in held for d, comp in zip(DOFS[:3], vec) if abs(comp) > 1e-12)

    def _check_conflicts(self):
        """A contact's normal that bilateral supports fix makes the basic
        system singular: name it instead.  (A tangent they fix is no link:
        the support carries that part of the friction, :meth:`_links`.)"""
        for c in self.contacts:
            if self._held(c, c.normal):
                raise InvalidProblemError(
                    f"node {c.node!r}: the contact's normal direction is already fixed by its "
                    "bilateral support; a contact and a support may share a node only where "
                    "they constrain different directions — remove one of them")

    def _links(self, idx, N):
        """H (N x links) and per link (contact, kind "n" | "t1" | "t2").  A
        tangent that the node's bilateral supports hold gets no link (its
        slip is zero, its friction the support's reaction): a planar frame
        built in space, out-of-plane motion held, has the plane frame's
        links and, through the facets along the plane, its LCP."""
        rows, cols, vals, info = [], [], [], []
        for ci, c in enumerate(self.contacts):
            kinds = ("n", "t1", "t2") if c.friction > 0 else ("n",)
            for kind, vec in zip(kinds, (c.normal, c.t1, c.t2)):
                if kind != "n" and self._held(c, vec):
                    continue
                rows += [idx[c.node] + d for d in range(3)]
                cols += [len(info)] * 3
                vals += list(vec)
                info.append((ci, kind))
        H = sp.csr_matrix((vals, (rows, cols)), shape=(N, len(info)))
        H.eliminate_zeros()
        return H, info

    def _lcp_maps(self, info):
        """(P, W, g, fric) as :func:`.assembly.link_maps` gives the plane
        frame's: Δ = P z - g, w = W X; z = Z_n per contact, then the slips
        along each facet direction of each frictional contact."""
        nl = len(info)
        pos = {}
        for li, (ci, kind) in enumerate(info):
            pos.setdefault(ci, {})[kind] = li
        nc = len(self.contacts)
        pr, pc, pv, wr, wc, wv = [], [], [], [], [], []
        g = np.zeros(nl)
        nz = nc
        fric = []
        for ci, c in enumerate(self.contacts):
            pr.append(pos[ci]["n"]), pc.append(ci), pv.append(1.0)
            wr.append(ci), wc.append(pos[ci]["n"]), wv.append(1.0)
            g[pos[ci]["n"]] = c.gap
            angles = self._facet_angles(c)
            if not angles.size:
                continue
            fric.append(ci)
            for a in angles:
                for kind, comp in (("t1", np.cos(a)), ("t2", np.sin(a))):
                    if kind in pos[ci]:
                        pr.append(pos[ci][kind]), pc.append(nz), pv.append(comp)
                        wr.append(nz), wc.append(pos[ci][kind]), wv.append(comp)
                wr.append(nz), wc.append(pos[ci]["n"]), wv.append(c.friction)
                nz += 1
        P = sp.csr_matrix((pv, (pr, pc)), shape=(nl, nz))
        W = sp.csr_matrix((wv, (wr, wc)), shape=(nz, nl))
        P.eliminate_zeros(), W.eliminate_zeros()
        return P, W, g, fric

    def _facet_angles(self, c) -> np.ndarray:
        """The angles of c's facet directions from t1 towards t2: the m-gon's,
        or where bilateral supports hold one tangent only ±(the other) — the
        cone is then the segment |X_t| <= f X_n, exact with two facets, and
        the m-gon's oblique facets only repeat it, looser, with slips that
        move nothing the two do not (a planar portal built in space: the
        load path could not prove its sliding collapse through them) — and
        none where both are held or without friction."""
        if c.friction == 0:
            return np.zeros(0)
        free = [not self._held(c, t) for t in (c.t1, c.t2)]
        if all(free):
            return 2 * np.pi * np.arange(c.facets) / c.facets
        if not any(free):
            return np.zeros(0)
        return np.array([0.0, np.pi]) + (0.0 if free[0] else 0.5 * np.pi)

    def _release_directions(self, b):
        N = b["K"].shape[0]
        cols = []
        for vec in ("normal", "t1", "t2"):
            h = np.zeros((N, len(self.contacts)))
            for ci, c in enumerate(self.contacts):
                h[b["idx"][c.node]:b["idx"][c.node] + 3, ci] = getattr(c, vec)
            cols.append(h)
        return cols[0], cols[1:], np.array([c.friction for c in self.contacts])


def _fixed_end(q, L) -> np.ndarray:
    """Equivalent nodal loads (member axes, 12) of a uniform load q = (qx,
    qy, qz) per unit length over a member of length L."""
    qx, qy, qz = q
    m_y, m_z = qz * L * L / 12.0, qy * L * L / 12.0
    return np.array([qx * L / 2, qy * L / 2, qz * L / 2, 0.0, -m_y, m_z,
                     qx * L / 2, qy * L / 2, qz * L / 2, 0.0, m_y, -m_z])

