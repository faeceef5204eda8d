"""Space frames (issue 35, in progress): the model and its linear assembly.

Six dofs per node, (ux, uy, uz, rx, ry, rz) in global axes (right-handed,
rotations counterclockwise about each axis); members are the 3-D
beam-column elements of :mod:`.elements3d`; bilateral supports fix any
subset of the six dofs; springs resist -k·u on any dof; loads belong to
named cases as in 2-D (:mod:`.loads`).  Units the user's, consistent.

What is here: the model, K and the load columns, and the linear solution of
a frame held by bilateral supports and springs (``solve_linear``), which the
tests hold against PyNite 3-D and the beam formulas.  Still to come (see
docs/dev-notes.md, "Issue 35"): contacts with the faceted and the circular
Coulomb cone, ``solve``/``solve_combinations``/``trace`` through the
machinery of :mod:`.assembly` and :mod:`.active_set`, results, tables and
drawings.

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

from qpcontact.core.errors import InvalidProblemError

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
        for node, ks in self.springs.items():
            for d, kval in ks.items():
                rows.append([idx[node] + DOFS.index(d)])
                cols.append([idx[node] + DOFS.index(d)])
                vals.append([kval])
        K = sp.coo_matrix((np.concatenate(vals) if vals else np.zeros(0),
                           (np.concatenate(rows) if rows else np.zeros(0, int),
                            np.concatenate(cols) if cols else np.zeros(0, int))),
                          shape=(N, N)).tocsr()
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


def _fixed_end(q, L) -> np.ndarray:
    """Equivalent nodal loads (member axes, 12) of a uniform load q = (qx,
    qy, qz) per unit length over a member of length L."""
    qx, qy, qz = q
    m_y, m_z = qz * L * L / 12.0, qy * L * L / 12.0
    return np.array([qx * L / 2, qy * L / 2, qz * L / 2, 0.0, -m_y, m_z,
                     qx * L / 2, qy * L / 2, qz * L / 2, 0.0, m_y, -m_z])
