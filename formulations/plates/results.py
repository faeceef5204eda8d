"""A raft's answer for one combination (:class:`RaftResult`) and over many
(:class:`RaftCombinations`): deflections, the contact and lift-off zones,
soil pressures, moments and shears per unit width, their extremes and
envelopes, and readable tables.

Where values live: deflections, soil forces and pressures at the nodes;
moments (mx, my, mxy) [force·length/length] and shears (qx, qy)
[force/length] at the element centres (where the bilinear element's
moments are most accurate), and averaged to the nodes for drawings.  Under a
point load the plate moment is singular (it grows like log 1/r): its
extreme there depends on the mesh — spread a column over its section
(``Raft.add_column``, which meshes the section finer) for design moments.
Where an extreme is a value of the mesh rather than of the plate — at a
point load, under a column (from below), a rigid floor's peak pressure,
cells coarse against the elastic length, a result that is not ok — the
extremes and envelope tables say so in a ``note`` (:meth:`RaftResult.notes`).
"""

from __future__ import annotations

import csv
import math
import os
import tempfile

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from .element import resultants

__all__ = ["RaftResult", "RaftCombinations", "QUANTITIES", "round_column"]

#: the element quantities: name -> (column in (m | q), unit kind)
QUANTITIES = {"mx": ("m", 0), "my": ("m", 1), "mxy": ("m", 2), "qx": ("q", 0), "qy": ("q", 1)}


def round_column(values, digits=5):
    """Round a column so that its largest value keeps ``digits`` significant
    digits, every value with the same decimals; values within 1e-9 of the
    largest are 0 (rounding of a zero)."""
    v = np.asarray(values, dtype=float)
    if digits is None or v.size == 0:
        return v
    scale = float(np.max(np.abs(v)))
    if scale == 0 or not np.isfinite(scale):
        return v
    v = np.where(np.abs(v) <= 1e-9 * scale, 0.0, v)
    decimals = max(0, digits - 1 - int(math.floor(math.log10(scale))))
    return np.round(v, decimals) + 0.0


class RaftResult:
    """One combination's answer.  ``ok`` only when ``qpcontact.certify``
    certified it on the unpinned QP (:mod:`.contact`) — and, where the pinned
    QP answered, ``qpcontact.solve`` certified that too; otherwise the fields
    are what the solver returned and ``message`` says why it is not
    certified.  ``method``: "active-set" (Newton's method, :mod:`.newton`)
    or the pinned QP's method."""

    def __init__(self, raft, combination, name, f, answer):
        raft = raft.as_solved()          # later changes to the model leave this answer alone
        b = raft.build()
        self.raft, self.combination, self.name = raft, combination, name
        self.ok, self.status, self.message = answer.ok, answer.status, answer.message
        self.method, self.pinned = answer.method, answer.pinned
        self.wall_time, self.error = answer.wall_time, answer.error
        self.mesh = mesh = b["mesh"]
        qp = b["qp"]
        self.loads = f
        self.u = qp.T @ answer.x                        # every dof [length, rad]
        self.w = self.u[0::3]
        self.theta = self.u.reshape(-1, 3)[:, 1:]
        self.supported = np.zeros(mesh.nodes.shape[0], bool)
        self.supported[qp.supported] = True
        gaps = qp.gaps(answer.x)
        scale = float(np.abs(self.w).max()) or 1.0
        self.lifted = np.zeros(mesh.nodes.shape[0], bool)
        self.lifted[qp.supported] = gaps > 1e-9 * scale
        self.support_force = qp.support_forces(answer.x, f)         # upward [force]
        # a lifted node's force is zero by complementarity; k (w + g) computed
        # from the two leaves their rounding (1e-10 of the peak on stiff rafts)
        self.support_force[self.lifted] = 0.0
        area = b["area"]
        self.pressure = np.divide(self.support_force, area, out=np.zeros_like(area),
                                  where=area > 0)                   # [force/length²]
        self.contact = self.supported & ~self.lifted
        m, q = resultants(mesh.corners, self.u[b["dofs"]], raft.E, raft.nu, raft.thickness)
        self.moments, self.shears = m, q                # (ne, 3), (ne, 2) at the centres
        # bilateral supports' upward reactions, and the equilibrium check by statics
        r = f - b["K"] @ self.u
        self.reactions = np.zeros_like(self.u)
        self.reactions[qp.fixed] = r[qp.fixed]
        total_up = self.support_force.sum() + self.reactions[0::3].sum()
        self.equilibrium_error = abs(f[0::3].sum() - total_up) / max(np.abs(f[0::3]).sum(), 1e-300)

    # -- derived --------------------------------------------------------------
    @property
    def contact_area(self) -> float:
        """Area [length²] of the supported nodes' tributary areas that press."""
        return float(self.raft.build()["area"][self.contact].sum())

    @property
    def uplift_fraction(self) -> float:
        """Fraction of the supported area that lifted off."""
        area = self.raft.build()["area"]
        total = area[self.supported].sum()
        return float(area[self.lifted].sum() / total) if total else 0.0

    def element_values(self, quantity: str) -> np.ndarray:
        if quantity not in QUANTITIES:
            raise InvalidProblemError(f"unknown quantity {quantity!r}; one of {list(QUANTITIES)}")
        kind, col = QUANTITIES[quantity]
        return (self.moments if kind == "m" else self.shears)[:, col]

    def nodal(self, quantity: str) -> np.ndarray:
        """An element quantity averaged to the nodes (for drawings)."""
        v = self.element_values(quantity)
        acc = np.zeros(self.mesh.nodes.shape[0])
        cnt = np.zeros_like(acc)
        np.add.at(acc, self.mesh.elements, np.repeat(v[:, None], 4, axis=1))
        np.add.at(cnt, self.mesh.elements, 1.0)
        return acc / np.maximum(cnt, 1)

    def _extreme_places(self):
        """{quantity: (values, places (k, 2), "node" or "element")}."""
        out = {"w": (self.w, self.mesh.nodes, "node"),
               "pressure": (self.pressure, self.mesh.nodes, "node")}
        for name in QUANTITIES:
            out[name] = (self.element_values(name), self.mesh.centres, "element")
        return out

    def extremes(self) -> dict:
        """{quantity: {"max": (value, x, y), "min": (value, x, y)}} for w and the
        soil pressure (nodes) and mx, my, mxy, qx, qy (element centres)."""
        out = {}
        for name, (v, at, _) in self._extreme_places().items():
            i, j = int(np.argmax(v)), int(np.argmin(v))
            out[name] = {"max": (float(v[i]), *map(float, at[i])),
                         "min": (float(v[j]), *map(float, at[j]))}
        return out

    def notes(self) -> dict:
        """{quantity: {"max": words, "min": words}}: where an extreme is a
        value of the mesh rather than of the plate, and why ("" where not).
        A moment or shear extreme in an element with a corner at a point
        load: the plate's moment grows like log 1/r there, its shear like
        1/r — the value grows as the mesh is refined.  The largest pressure
        at a node of a rigid floor: where the plate leaves the floor the
        floor pushes along the contact edge as a line force (over about a
        thickness, Mindlin), and under a point load as the load itself,
        which the node's tributary area smears — on a 6 m slab, t = 0.2 m,
        its corner pulled up: 20.3, 31.6, 41.2, 48.2 kN/m² on 0.5, 0.25,
        0.125, 0.0625 m cells.  Every extreme, where the cells are coarser
        than half the elastic length ℓ = (D/k)^¼ of the stiffest soil: the
        plate's bending varies over ℓ, and on such cells it came out low —
        an 8 m slab, t = 0.15 m, k = 5e4 (ℓ = 0.65 m) under a corner column:
        on cells of ℓ/1.3 w and the peak pressure 5 % low, mx 14 %; on ℓ/2.6
        1.5 %; on ℓ/5.2 under 0.5 % (the reference: ℓ/21).  A moment
        extreme under a column (its section meshed, :data:`.model.
        COLUMN_CELLS`): from below, 2 % on cells of ℓ/4.6 against the
        infinite plate's; a shear extreme inside a column: its peak is on
        the face, the element centres 1/16 of the column inside (0.88 of
        it) — where the column has fewer elements across (a mesh of the
        user's), the note says how many instead (one: 0.77 of the moment).  And every extreme of a result that is not ok: "NOT OK" first."""
        b = self.raft.build()
        coarse = self._coarse_mesh(b)
        if not self.ok:             # its numbers are no answer: every row says so first
            coarse = "; ".join(n for n in ("NOT OK (no certified answer: see the summary)",
                                           coarse) if n)
        points = np.zeros(self.mesh.nodes.shape[0], bool)
        for case, kind, d in self.raft.loads:
            if kind == "point" and d[2] != 0 and self.combination.get(case, 0.0):
                points[self.mesh.nearest_node(d[0], d[1])] = True
        at_point = points[self.mesh.elements].any(axis=1)
        c = self.mesh.centres
        under = np.zeros(c.shape[0], bool)           # element centres inside a loaded column
        # the fewest elements across a column over each element: the
        # figures of the notes below were measured on the grid's
        # model.COLUMN_CELLS; a mesh of the user's is not refined under a
        # column, and on one element the moment came out 0.77 of the
        # plate's, not 0.98
        across = np.full(c.shape[0], np.inf)
        for x, y, bx, by, case in self.raft.columns:
            if self.combination.get(case, 0.0):
                inside = (np.abs(c[:, 0] - x) < bx / 2) & (np.abs(c[:, 1] - y) < by / 2)
                under |= inside
                n = min(np.unique(np.round(c[inside, k] / max(bx, by), 9)).size for k in (0, 1))
                across[inside] = np.minimum(across[inside], n)
        floor = np.isinf(b["ks"])
        cells = self.raft.column_cells
        out = {}
        for name, (v, _, where) in self._extreme_places().items():
            out[name] = {}
            for which, index in (("max", int(np.argmax(v))), ("min", int(np.argmin(v)))):
                note = ""
                if where == "element" and at_point[index]:
                    note = ("at a point load: singular there, a mesh value that grows as the "
                            "mesh is refined (give the column its section)")
                elif where == "element" and under[index] and across[index] < cells:
                    note = (f"under a column meshed {int(across[index])} element(s) across, "
                            f"fewer than the grid's {cells}: the mesh's value, far from "
                            "the plate's (one element: a moment 0.77 of it, a shear 0.48 of the "
                            "face's) — refine the mesh under the column")
                elif where == "element" and under[index] and name in ("mx", "my"):
                    note = ("under a column: the mesh's value, from below (on cells of "
                            "(D/k)^¼/4.6 2 % low, /9 1 %)")
                elif where == "element" and under[index]:
                    note = ("in a column: a shear peaks on its face, sampled 1/16 of the column "
                            "inside (0.88 of it in the test)")
                elif name == "pressure" and which == "max" and floor[index]:
                    note = ("on the rigid floor: its reaction concentrates (along the contact "
                            "edge, under a point load); over a node's area it is a mesh value "
                            "that grows as the mesh is refined")
                out[name][which] = "; ".join(n for n in (note, coarse) if n)
        return out

    def _coarse_mesh(self, b) -> str:
        """The words of :meth:`notes` where the cells are coarser than half
        the elastic length, else ""."""
        k = b["ke"][np.isfinite(b["ke"]) & (b["ke"] > 0)]
        if k.size == 0:
            return ""
        ell = (self.raft.D / k.max()) ** 0.25
        X = self.mesh.corners
        h = float(np.max(np.hypot(*(np.roll(X, -1, axis=1) - X).transpose(2, 0, 1))))
        if h <= ell / 2:
            return ""
        L = self.raft.units[1]
        return (f"coarse cells: up to {h:.3g} {L}, over half the elastic length (D/k)^¼ = "
                f"{ell:.3g} {L}, where bending comes out low (5-14 % at 0.77 of it): refine")

    # -- tables ---------------------------------------------------------------
    def _units(self):
        F, L = self.raft.units
        return {"w": L, "pressure": f"{F}/{L}²", "mx": f"{F}·{L}/{L}", "my": f"{F}·{L}/{L}",
                "mxy": f"{F}·{L}/{L}", "qx": f"{F}/{L}", "qy": f"{F}/{L}", "x": L, "y": L,
                "force": F}

    def rows(self, table: str, digits=5) -> list:
        """``"nodes"`` (x, y, w, state, soil force and pressure), ``"elements"``
        (centre, mx, my, mxy, qx, qy), ``"extremes"``, ``"summary"``."""
        u = self._units()
        if table == "nodes":
            state = np.where(self.lifted, "lifted", np.where(self.contact, "contact", "-"))
            cols = {f"x [{u['x']}]": self.mesh.nodes[:, 0], f"y [{u['y']}]": self.mesh.nodes[:, 1],
                    f"w [{u['w']}]": self.w, f"soil force [{u['force']}]": self.support_force,
                    f"pressure [{u['pressure']}]": self.pressure}
            rounded = {k: round_column(v, digits) for k, v in cols.items()}
            return [{"node": i, "state": str(state[i]), **{k: float(v[i]) for k, v in rounded.items()}}
                    for i in range(self.mesh.nodes.shape[0])]
        if table == "elements":
            c = self.mesh.centres
            cols = {f"x [{u['x']}]": c[:, 0], f"y [{u['y']}]": c[:, 1]}
            cols.update({f"{q} [{u[q]}]": self.element_values(q) for q in QUANTITIES})
            rounded = {k: round_column(v, digits) for k, v in cols.items()}
            return [{"element": e, **{k: float(v[e]) for k, v in rounded.items()}}
                    for e in range(c.shape[0])]
        if table == "extremes":
            rows = []
            notes = self.notes()
            for q, ext in self.extremes().items():
                for which in ("max", "min"):
                    v, x, y = ext[which]
                    rows.append({"quantity": q, "extreme": which, "value": v, "unit": u[q],
                                 f"x [{u['x']}]": x, f"y [{u['y']}]": y,
                                 "note": notes[q][which]})
            _round_coordinates(rows, u["x"], self.raft, digits)
            vals = {}
            for r in rows:          # round per unit (quantities of one unit share a scale)
                vals.setdefault(r["unit"], []).append(r["value"])
            for unit, v in vals.items():
                rv = iter(round_column(v, digits))
                for r in rows:
                    if r["unit"] == unit:
                        r["value"] = float(next(rv))
            return rows
        if table == "summary":
            F = u["force"]
            return [{"combination": self.name, "ok": self.ok, "method": self.method,
                     "message": self.message,
                     f"load [{F}]": float(round_column([self.loads[0::3].sum()], digits)[0]),
                     f"soil [{F}]": float(round_column([self.support_force.sum()], digits)[0]),
                     f"contact area [{u['x']}²]": round(self.contact_area, 6),
                     "uplift": f"{100 * self.uplift_fraction:.1f} %"}]
        raise InvalidProblemError(f"unknown table {table!r}; one of nodes, elements, extremes, "
                                  "summary")

    def table(self, table: str = "extremes", digits=5) -> str:
        """A table as aligned text."""
        return format_rows(self.rows(table, digits))

    def to_csv(self, folder, digits=5) -> None:
        for t in ("nodes", "elements", "extremes", "summary"):
            write_csv(os.path.join(folder, f"{t}.csv"), self.rows(t, digits))

    def plot(self, path, **kw):
        """The pressure map with the lift-off line and the moment contours
        (:func:`.figures.plot_raft`)."""
        from .figures import plot_raft

        return plot_raft(self, path, **kw)

    def __repr__(self):
        return (f"RaftResult({self.name!r}, ok={self.ok}, uplift {100 * self.uplift_fraction:.1f} %, "
                f"{self.message!r})")


class RaftCombinations(dict):
    """{combination name: RaftResult}, with envelopes over those that are ok."""

    @property
    def failed(self) -> dict:
        return {k: r.message for k, r in self.items() if not r.ok}

    def envelope(self) -> dict:
        """{quantity: {"max": (value, x, y, combination), "min": ...}} over the
        combinations that are ok (mx, my, mxy, qx, qy at element centres; w and
        pressure at nodes), and ``"uplift"``: {combination: lifted fraction}."""
        good = {k: r for k, r in self.items() if r.ok}
        if not good:
            raise InvalidProblemError("no combination is ok: nothing to envelope ("
                                      + "; ".join(f"{k}: {m}" for k, m in self.failed.items()) + ")")
        out = {}
        for name, res in good.items():
            for q, ext in res.extremes().items():
                cur = out.setdefault(q, {})
                for which, better in (("max", np.greater), ("min", np.less)):
                    v = ext[which]
                    if which not in cur or better(v[0], cur[which][0]):
                        cur[which] = (*v, name)
        out["uplift"] = {k: r.uplift_fraction for k, r in good.items()}
        return out

    def lifted_in(self) -> np.ndarray:
        """Per node: in how many of the ok combinations it lifts off."""
        good = [r for r in self.values() if r.ok]
        return np.sum([r.lifted for r in good], axis=0) if good else None

    def rows(self, table: str = "envelope", digits=5) -> list:
        if table == "envelope":
            first = next(iter(self.values()))
            u = first._units()
            env = self.envelope()
            notes = {name: self[name].notes() for name in env["uplift"]}
            # a combination left out is said on every row: the one that
            # failed may be the one that governs
            left_out = ("without " + ", ".join(self.failed) + " (not ok)") if self.failed else ""
            rows = [{"quantity": q, "extreme": which, "value": env[q][which][0], "unit": u[q],
                     f"x [{u['x']}]": env[q][which][1], f"y [{u['y']}]": env[q][which][2],
                     "combination": env[q][which][3],
                     "note": "; ".join(n for n in (left_out, notes[env[q][which][3]][q][which])
                                       if n)}
                    for q in env if q != "uplift" for which in ("max", "min")]
            _round_coordinates(rows, u["x"], first.raft, digits)
            for unit in {r["unit"] for r in rows}:
                idx = [i for i, r in enumerate(rows) if r["unit"] == unit]
                for i, v in zip(idx, round_column([rows[i]["value"] for i in idx], digits)):
                    rows[i]["value"] = float(v)
            return rows
        if table == "combinations":
            return [r.rows("summary", digits)[0] for r in self.values()]
        raise InvalidProblemError(f"unknown table {table!r}; one of envelope, combinations")

    def table(self, table: str = "envelope", digits=5) -> str:
        return format_rows(self.rows(table, digits))

    def to_csv(self, folder, digits=5) -> None:
        for t in ("envelope", "combinations"):
            write_csv(os.path.join(folder, f"{t}.csv"), self.rows(t, digits))


def _round_coordinates(rows, unit, raft, digits):
    """x and y to the decimals that give the raft's size ``digits`` digits."""
    if digits is None:
        return
    size = max(raft.width, raft.length)
    decimals = max(0, digits - 1 - int(math.floor(math.log10(size))))
    for r in rows:
        for key in (f"x [{unit}]", f"y [{unit}]"):
            r[key] = round(r[key], decimals) + 0.0


def format_rows(rows: list) -> str:
    """Rows (dicts with the same keys) as aligned text."""
    if not rows:
        return ""
    keys = list(rows[0])
    text = [[str(k) for k in keys]] + [[_fmt(r[k]) for k in keys] for r in rows]
    widths = [max(len(line[i]) for line in text) for i in range(len(keys))]
    return "\n".join("  ".join(c.rjust(w) if j else c.ljust(w) for j, (c, w) in
                               enumerate(zip(line, widths))) for line in text)


def _fmt(v):
    if isinstance(v, float):
        return "0" if v == 0 else repr(v) if abs(v) >= 1e-4 else f"{v:.6g}"
    return str(v)


def write_csv(path, rows) -> None:
    """Write atomically: a temporary file, flushed and renamed."""
    folder = os.path.dirname(path) or "."
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=folder, suffix=".tmp")
    try:
        with os.fdopen(fd, "w", newline="") as fh:
            if rows:
                wr = csv.DictWriter(fh, fieldnames=list(rows[0]))
                wr.writeheader()
                wr.writerows({k: _fmt(v) for k, v in r.items()} for r in rows)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise
