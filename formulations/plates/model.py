r"""Rafts and slabs on tensionless soil: the :class:`Raft` model.

A rectangular plate (width along x, length along y [m]; thickness t [m],
Young's modulus E and Poisson's ratio ν) meshed with MITC4 elements
(:mod:`.element`) on a structured grid whose lines pass through every column,
patch edge, line load, edge beam, opening edge and soil-zone edge — a
column's section divided into COLUMN_CELLS cells each way and a wall inside
the raft flanked by graded lines (WALL_LINES), where the plate moment
peaks and the element-centre moments must sample it — with
edge beams along grid lines, resting on

* tensionless Winkler soil: a modulus of subgrade reaction k [force/length³]
  per zone, lumped to nodal springs by tributary area, that pushes and never
  pulls (:mod:`.contact`), or
* a rigid floor (the limit k → ∞: the slab cannot go down, may lift off),

and bilateral supports where the user fixes dofs (walls, piles; the classic
plates of the tests).  Loads belong to named cases; a combination {case:
factor} is solved as its own contact problem — lift-off makes the answers
of two combinations non-superposable — by Newton's method on the energy or
through ``qpcontact.solve``, with the certificate every answer carries
(``ok`` is never set on an uncertified one).

Units are the user's and consistent (``Raft(units=("kN", "m"))`` only names
them): k in kN/m³, E in kN/m², loads in kN, pressures in kN/m².  Signs: z and
w point **down** (into the soil); loads positive downward (gravity); the soil
pressure is positive when it pushes up; moments positive when they stretch
the bottom face (see :mod:`.element`).
"""

from __future__ import annotations

import copy

import numpy as np

from qpcontact.core.errors import InvalidProblemError

from .assembly import (area_load, assemble_stiffness, beam_stiffness, element_dofs, line_load,
                       segment_edges)
from .contact import ContactQP, solve_contact
from .newton import solve_supports, start_from
from .element import DOFS, rigidity
from .mesh import PlateMesh, grid, grid_lines

__all__ = ["Raft"]

#: a column's section is divided into this many cells each way (grid lines
#: through its centre and at every 1/COLUMN_CELLS of its width): the plate
#: moment peaks under a column's centre, and the element-centre moments
#: sample it there.  Against the infinite plate on Winkler soil under a
#: square patch (a Fourier integral, tests/formulations/plates/
#: test_column_moments.py), a 0.4 m column on 0.5 m cells: the patch one
#: element, 0.77 of the peak mx; 2, 4, 8 cells across: 0.87, 0.96, 0.98
COLUMN_CELLS = 8

#: grid lines beside a line load (a wall), in the raft's nominal cells: the
#: plate moment has a kink under it (its peak: M0 = P/(4β) on an infinite
#: strip, β = (k/4D)^¼), which element-centre moments sampled up to half a
#: cell off — 0.885 (t = 0.6 m) and 0.889 (thin) of M0 on 0.5 m cells,
#: β h = 0.155; with these lines the nearest centres are a thirty-second of
#: a cell off: 0.984 and 0.9875 (tests/formulations/plates/
#: test_raft_closed_forms.py).  A wall on the outline has none: the free
#: edge's moment is zero
WALL_LINES = np.array([-0.5, -0.25, -0.125, -0.0625, 0.0625, 0.125, 0.25, 0.5])

#: a grid raft with at least twice this many cells a side starts Newton's
#: method from its twin's answer on half the cells (nested iteration,
#: :func:`.newton.start_from`), down to twins of this many cells
NESTED_CELLS = 16


def _positive(name, value):
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)) \
            or not np.isfinite(value) or value <= 0:
        raise InvalidProblemError(f"{name} must be a positive finite number; got {value!r}")
    return float(value)


def _number(value) -> bool:
    """A real, finite number (not a bool, a string or an array)."""
    return (not isinstance(value, bool) and isinstance(value, (int, float, np.floating, np.integer))
            and bool(np.isfinite(value)))


def _rect(name, r):
    try:
        x0, y0, x1, y1 = (float(v) for v in r)
    except (TypeError, ValueError):
        raise InvalidProblemError(f"{name} must be a rectangle (x0, y0, x1, y1); got {r!r}") from None
    if not (x1 > x0 and y1 > y0) or not np.all(np.isfinite([x0, y0, x1, y1])):
        raise InvalidProblemError(f"{name} needs finite x0 < x1 and y0 < y1; got {r!r}")
    return x0, y0, x1, y1


class Raft:
    """A rectangular raft or slab; see the module docstring.

    Parameters
    ----------
    width, length : float
        Sides along x and y [length].
    thickness, E : float
        Plate thickness [length] and Young's modulus [force/length²].
    nu : float
        Poisson's ratio, in [0, 0.5).
    cells : (int, int)
        About how many cells along x and y (lines are moved or added to pass
        through the loads' and openings' coordinates).
    openings : rectangles (x0, y0, x1, y1)
        Cells whose centre lies inside are removed.
    mesh : PlateMesh, optional
        A mesh of the user's own instead of the grid (then point loads must
        sit on nodes and patches on element edges).
    units : (force, length)
        Names on tables and drawings.
    """

    #: the cells a column's section is divided into each way on the grid
    #: (:data:`COLUMN_CELLS`; a mesh of the user's is not refined): the
    #: results' notes compare a column's elements across with it
    column_cells = COLUMN_CELLS

    def __init__(self, width=None, length=None, *, thickness, E, nu=0.2, cells=(20, 20),
                 openings=(), mesh: PlateMesh | None = None, units=("kN", "m")):
        self.thickness = _positive("thickness", thickness)
        self.E = _positive("E", E)
        if not (_number(nu) and 0 <= nu < 0.5):
            raise InvalidProblemError(f"Poisson's ratio must be in [0, 0.5); got {nu!r}")
        self.nu = float(nu)
        self.units = tuple(units)
        self._user_mesh = mesh
        if mesh is None:
            self.width = _positive("width", width)
            self.length = _positive("length", length)
            try:
                nx, ny = cells
            except (TypeError, ValueError):
                raise InvalidProblemError(f"cells must be (nx, ny); got {cells!r}") from None
            self.cells = (nx, ny)
        else:
            lo, hi = mesh.nodes.min(axis=0), mesh.nodes.max(axis=0)
            self.width, self.length = float(hi[0] - lo[0]), float(hi[1] - lo[1])
        self.openings = [_rect("an opening", o) for o in openings]
        self.soil_zones = []            # (k, rectangle or None), later ones override
        self.supports = []              # (predicate or node list, dofs)
        self.loads = []                 # (case, kind, data)
        self.beams = []                 # (x0, y0, x1, y1, EI, GJ)
        self.columns = []               # (x, y, bx, by, case): their sections are meshed finer
        self._built = None

    # -- model building ---------------------------------------------------
    @property
    def D(self) -> float:
        """Bending stiffness E t³ / (12 (1 − ν²)) [force·length]."""
        return rigidity(self.E, self.thickness, self.nu)

    def add_soil(self, k: float, zone=None) -> None:
        """Tensionless Winkler soil of modulus k [force/length³] under the
        whole raft or a zone (x0, y0, x1, y1); a later zone overrides an
        earlier one where they overlap."""
        self.soil_zones.append((_positive("the modulus of subgrade reaction k", k),
                                None if zone is None else _rect("a soil zone", zone)))
        self._built = None

    def add_rigid_floor(self, zone=None) -> None:
        """A rigid floor under the raft or a zone: the slab cannot go down there
        and may lift off (the limit k → ∞)."""
        self.soil_zones.append((np.inf, None if zone is None else _rect("a floor zone", zone)))
        self._built = None

    def add_support(self, where, fix=("w",)) -> None:
        """Bilateral supports: ``fix`` among ("w", "theta_x", "theta_y") at the
        nodes ``where`` selects — a callable (x, y) -> bool array, or node numbers."""
        bad = [d for d in fix if d not in DOFS]
        if bad or not fix:
            raise InvalidProblemError(f"fix must name dofs among {DOFS}; got {fix!r}")
        self.supports.append((where, tuple(fix)))
        self._built = None

    def _case(self, case):
        if not isinstance(case, str) or not case:
            raise InvalidProblemError(f"a load case is a non-empty name; got {case!r}")
        return case

    def add_point_load(self, x: float, y: float, P: float, case: str = "D") -> None:
        """A column load P [force], downward positive, at (x, y)."""
        self._inside(x, y)
        if not _number(P):
            raise InvalidProblemError(f"a point load must be a finite number; got {P!r}")
        self.loads.append((self._case(case), "point", (float(x), float(y), float(P))))
        self._built = None

    def add_column(self, x: float, y: float, P: float, size, case: str = "D") -> None:
        """A column load P [force] spread over its section size = (bx, by)
        [length] centred at (x, y): a patch load of P / (bx by)."""
        try:
            bx, by = size
        except (TypeError, ValueError):     # a scalar, or three sides: not a TypeError's words
            raise InvalidProblemError(f"a column's size is its section (bx, by); got {size!r}") \
                from None
        bx, by = (_positive("a column's size", s) for s in (bx, by))
        self._inside(x, y)
        if not _number(P):
            raise InvalidProblemError(f"a column's load must be a finite number; got {P!r}")
        if self._user_mesh is None and not (0 <= x - bx / 2 and x + bx / 2 <= self.width
                                            and 0 <= y - by / 2 and y + by / 2 <= self.length):
            raise InvalidProblemError(
                f"the column at ({x}, {y}) of section {bx} x {by} overhangs the raft [0, "
                f"{self.width}] x [0, {self.length}]: move it inward by the overhang or give "
                "the part of its load on the raft")
        self.add_patch_load(x - bx / 2, y - by / 2, x + bx / 2, y + by / 2, P / (bx * by), case)
        self.columns.append((float(x), float(y), bx, by, case))

    def add_patch_load(self, x0, y0, x1, y1, p: float, case: str = "D") -> None:
        """A uniform pressure p [force/length²], downward positive, over a rectangle."""
        r = _rect("a patch", (x0, y0, x1, y1))
        self._inside(r[0], r[1])
        self._inside(r[2], r[3])
        if not _number(p):
            raise InvalidProblemError(f"a pressure must be a finite number; got {p!r}")
        self.loads.append((self._case(case), "patch", (*r, float(p))))
        self._built = None

    def add_line_load(self, x0, y0, x1, y1, q: float, case: str = "D") -> None:
        """A line load q [force/length], downward positive, along a segment
        parallel to x or y (a wall); on a mesh of the user's, along element edges."""
        self._segment("a line load", x0, y0, x1, y1)
        if not _number(q):
            raise InvalidProblemError(f"a line load must be a finite number; got {q!r}")
        self.loads.append((self._case(case), "line", (float(x0), float(y0), float(x1),
                                                       float(y1), float(q))))
        self._built = None

    def add_edge_beam(self, x0, y0, x1, y1, EI: float, GJ: float = 0.0) -> None:
        """A beam along a segment parallel to x or y (an edge beam, a ground
        beam under a wall), fixed to the plate: bending stiffness EI and
        torsional stiffness GJ [force·length²] about the plate's mid-surface
        (:func:`.assembly.beam_stiffness`)."""
        self._segment("an edge beam", x0, y0, x1, y1)
        EI = _positive("a beam's EI", EI)
        if not (np.isfinite(GJ) and GJ >= 0):
            raise InvalidProblemError(f"a beam's GJ must be a finite number >= 0; got {GJ!r}")
        self.beams.append((float(x0), float(y0), float(x1), float(y1), EI, float(GJ)))
        self._built = None

    def _segment(self, what, x0, y0, x1, y1):
        self._inside(x0, y0)
        self._inside(x1, y1)
        if (x0, y0) == (x1, y1):
            raise InvalidProblemError(f"{what} needs two different ends; got ({x0}, {y0}) twice")
        if self._user_mesh is None and x0 != x1 and y0 != y1:
            raise InvalidProblemError(f"{what} on the grid runs along x or along y; got "
                                      f"({x0}, {y0}) to ({x1}, {y1})")

    def add_area_load(self, p: float, case: str = "D") -> None:
        """A uniform pressure p [force/length²] over the whole raft."""
        if not _number(p):
            raise InvalidProblemError(f"a pressure must be a finite number; got {p!r}")
        self.loads.append((self._case(case), "area", float(p)))
        self._built = None

    def add_self_weight(self, unit_weight: float, case: str = "D") -> None:
        """The plate's weight: unit_weight [force/length³] × thickness, over its area."""
        self.add_area_load(_positive("unit_weight", unit_weight) * self.thickness, case)

    def _inside(self, x, y):
        if not (_number(x) and _number(y)):
            raise InvalidProblemError(f"coordinates must be finite numbers; got ({x!r}, {y!r})")
        if self._user_mesh is None and not (0 <= x <= self.width and 0 <= y <= self.length):
            raise InvalidProblemError(f"point ({x}, {y}) is outside the raft [0, {self.width}] x "
                                      f"[0, {self.length}]")

    @property
    def cases(self) -> list:
        return sorted({c for c, _, _ in self.loads})

    def as_solved(self) -> "Raft":
        """The model as it is now, built: a copy whose lists are its own and
        whose build is this one's, for a result to keep.  A result that read
        the raft itself went stale when the model changed after the solve
        (a column added: its contact area read off the new mesh's node
        areas — a wrong number on the old mesh's sizes, an IndexError on
        others)."""
        built = self.build()
        twin = copy.copy(self)
        for name, value in vars(self).items():
            if isinstance(value, (list, dict, set)):
                setattr(twin, name, copy.copy(value))
        twin._built = built
        return twin

    # -- the mesh and the matrices (built once per model) --------------------
    def build(self):
        """The mesh, stiffness, soil and contact QP (cached until the model changes)."""
        if self._built is not None:
            return self._built
        if self._user_mesh is not None:
            mesh = self._user_mesh
        else:
            xs, ys = [], []
            for _, kind, d in self.loads:
                if kind == "point":
                    xs.append(d[0])
                    ys.append(d[1])
                elif kind in ("patch", "line"):
                    xs += [d[0], d[2]]
                    ys += [d[1], d[3]]
            # a column's edges and centre are lines (its load's total, the
            # peak's place); an inner line only where no column's line lies
            # within half an inner cell: each line crosses the whole raft, and
            # 36 columns placed ±5 cm off a 6 m grid made 152 881 nodes (24 s
            # CPU to solve) with 9 lines each, 44 521 (4 s) sharing them —
            # the moments under columns whose inner lines were a neighbour's
            # 0.983-0.988 of the infinite plate's, against 0.985-0.988
            near = ([], [])
            for x, y, bx, by, _ in self.columns:
                for axis, c, b in ((0, x, bx), (1, y, by)):
                    have = np.asarray(near[axis])
                    for k, v in enumerate(c + b * (np.arange(COLUMN_CELLS + 1) / COLUMN_CELLS
                                                   - 0.5)):
                        if k in (0, COLUMN_CELLS // 2, COLUMN_CELLS) or not have.size \
                                or np.abs(have - v).min() >= b / (2 * COLUMN_CELLS):
                            near[axis].append(v)
            xs += near[0]
            ys += near[1]
            hx, hy = self.width / self.cells[0], self.length / self.cells[1]
            for _, kind, d in self.loads:        # a wall inside: lines beside it, graded
                if kind == "line" and d[1] == d[3] and 0 < d[1] < self.length:
                    ys += [y for y in d[1] + hy * WALL_LINES if 0 < y < self.length]
                elif kind == "line" and d[0] == d[2] and 0 < d[0] < self.width:
                    xs += [x for x in d[0] + hx * WALL_LINES if 0 < x < self.width]
            for d in self.beams:
                xs += [d[0], d[2]]
                ys += [d[1], d[3]]
            for r in self.openings + [z for _, z in self.soil_zones if z is not None]:
                xs += [min(max(r[0], 0), self.width), min(max(r[2], 0), self.width)]
                ys += [min(max(r[1], 0), self.length), min(max(r[3], 0), self.length)]
            mesh = grid(grid_lines(self.width, self.cells[0], xs),
                        grid_lines(self.length, self.cells[1], ys), self.openings)
        K = assemble_stiffness(mesh, self.E, self.nu, self.thickness)
        for x0, y0, x1, y1, EI, GJ in self.beams:
            K = K + beam_stiffness(mesh, segment_edges(mesh, x0, y0, x1, y1, "an edge beam"),
                                   EI, GJ)
        K = K.tocsr()
        ke = np.zeros(mesh.elements.shape[0])
        centres = mesh.centres
        for k, zone in self.soil_zones:
            inside = np.ones(ke.size, bool) if zone is None else (
                (centres[:, 0] > zone[0]) & (centres[:, 0] < zone[2])
                & (centres[:, 1] > zone[1]) & (centres[:, 1] < zone[3]))
            if not inside.any():
                raise InvalidProblemError(
                    f"the {'floor' if np.isinf(k) else 'soil'} zone {zone} covers no element of "
                    f"the raft (an element is in a zone where its centre is): the raft spans "
                    f"x {mesh.nodes[:, 0].min():.6g}..{mesh.nodes[:, 0].max():.6g}, y "
                    f"{mesh.nodes[:, 1].min():.6g}..{mesh.nodes[:, 1].max():.6g}")
            ke[inside] = k
        floor_nodes = np.unique(mesh.elements[np.isinf(ke)])
        ks = mesh.tributary_areas(np.where(np.isinf(ke), 0.0, ke))
        ks[floor_nodes] = np.inf
        area = mesh.tributary_areas(np.where(ke > 0, 1.0, 0.0))    # the supported area per node
        fixed = []
        X, Y = mesh.nodes[:, 0], mesh.nodes[:, 1]
        for where, dofs in self.supports:
            nodes = np.flatnonzero(np.asarray(where(X, Y), bool)) if callable(where) \
                else np.asarray(where, dtype=np.int64)
            for d in dofs:
                fixed += list(3 * nodes + DOFS.index(d))
        fixed = np.unique(np.asarray(fixed, dtype=np.int64))
        qp = ContactQP(K, ks, fixed)
        self._built = dict(mesh=mesh, K=K, ks=ks, ke=ke, area=area, qp=qp,
                           dofs=element_dofs(mesh.elements))
        return self._built

    @property
    def mesh(self) -> PlateMesh:
        return self.build()["mesh"]

    def load_vector(self, combination: dict) -> np.ndarray:
        """Nodal loads (3n,) [force] of a combination {case: factor}: each
        case's nodal loads are made once per build (a column is a patch load
        of its own, and every combination and the nested twin's solve read
        them: the 12-column example spent two thirds of a solve re-making
        its 36 patches)."""
        b = self.build()
        unknown = [c for c in combination if c not in self.cases]
        if unknown:
            raise InvalidProblemError(f"combination names cases {unknown} that have no load; this "
                                      f"raft's cases are {self.cases}")
        per_case = b.setdefault("case_loads", {})
        f = np.zeros(3 * b["mesh"].nodes.shape[0])
        for case in self.cases:
            factor = float(combination.get(case, 0.0))
            if factor == 0.0:
                continue
            if case not in per_case:
                per_case[case] = self._case_loads(case, b["mesh"])
            f += factor * per_case[case]
        return f

    def _case_loads(self, case, mesh) -> np.ndarray:
        """The nodal loads (3n,) of one case (its loads at factor 1)."""
        f = np.zeros(3 * mesh.nodes.shape[0])
        size = max(self.width, self.length)
        centres = mesh.centres
        for name, kind, d in self.loads:
            if name != case:
                continue
            if kind == "point":
                node = mesh.nearest_node(d[0], d[1])
                if np.hypot(*(mesh.nodes[node] - d[:2])) > 1e-9 * size:
                    raise InvalidProblemError(
                        f"the point load at ({d[0]}, {d[1]}) is not on a node of the mesh "
                        "(the grid passes through it unless it falls in an opening): move it "
                        "onto the slab or onto a node")
                f[3 * node] += d[2]
            elif kind == "patch":
                x0, y0, x1, y1, p = d
                inside = ((centres[:, 0] > x0) & (centres[:, 0] < x1)
                          & (centres[:, 1] > y0) & (centres[:, 1] < y1))
                covered = mesh.areas[inside].sum()
                if abs(covered - (x1 - x0) * (y1 - y0)) > 1e-9 * (x1 - x0) * (y1 - y0):
                    raise InvalidProblemError(
                        f"the patch ({x0}, {y0}, {x1}, {y1}) covers {covered:.6g} of the slab, "
                        f"not its {(x1 - x0) * (y1 - y0):.6g}: it overlaps an opening or the "
                        "edge, or its edges are not element edges")
                f[0::3] += area_load(mesh, np.full(int(inside.sum()), p), inside)
            elif kind == "line":
                edges = segment_edges(mesh, *d[:4], "a line load")
                f[0::3] += line_load(mesh, edges, d[4])
            else:
                f[0::3] += area_load(mesh, np.full(mesh.elements.shape[0], d))
        return f

    # -- analysis -------------------------------------------------------------
    def solve(self, combination: dict | None = None, *, name: str | None = None,
              method: str = "auto", accuracy="default", time_limit=None):
        """Solve one combination {case: factor} (default: every case × 1)."""
        from .results import RaftResult

        if combination is None:
            combination = {c: 1.0 for c in self.cases}
        if not combination:
            raise InvalidProblemError("the raft has no load: add loads to a case first")
        b = self.build()
        f = self.load_vector(combination)
        answer = solve_contact(b["qp"], b["mesh"].nodes, f, method=method, accuracy=accuracy,
                               time_limit=time_limit,
                               guess=lambda deadline: self._nested_start(combination, deadline))
        title = name or " + ".join(f"{v:g} × {k}" for k, v in combination.items())
        return RaftResult(self, dict(combination), title, f, answer)

    def _nested_start(self, combination, deadline=None):
        """Newton's first states from this raft's deflections on half the
        cells (Newton's method alone there, itself started from its own twin:
        a guess, not an answer — the fine raft's answer is certified), or
        None: a mesh of the user's, supports given as node numbers (they
        name no node of another grid), fewer than 2 NESTED_CELLS cells a
        side, or Newton's method not ending on the twin."""
        import copy

        b = self.build()
        if "twin" not in b:
            b["twin"] = None
            nx, ny = self.cells if self._user_mesh is None else (0, 0)
            if min(nx, ny) >= 2 * NESTED_CELLS and all(callable(w) for w, _ in self.supports):
                twin = copy.copy(self)     # the same inputs (read only), its own mesh
                twin.cells, twin._built = (nx // 2, ny // 2), None
                b["twin"] = twin
        twin = b["twin"]
        if twin is None:
            return None
        tb = twin.build()
        found = solve_supports(tb["qp"], tb["mesh"].nodes, twin.load_vector(combination), deadline,
                               twin._nested_start(combination, deadline))
        if found is None:
            return None
        w = (tb["qp"].T @ found[0])[0::3]
        return start_from(tb["mesh"].nodes, w, b["qp"], b["mesh"].nodes)

    def solve_combinations(self, combinations: dict, **kw):
        """Solve each combination {name: {case: factor}} as its own problem."""
        from .results import RaftCombinations

        if not combinations:
            raise InvalidProblemError("no combination given")
        return RaftCombinations({name: self.solve(c, name=name, **kw)
                                 for name, c in combinations.items()})
