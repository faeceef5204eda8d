"""The Frame: model building (nodes, members, supports, springs, contacts,
load cases), solving one combination or many, P3's trace, and the results'
tables.  Assembly lives in :mod:`.assembly`, loads in :mod:`.loads`, results
in :mod:`.results`, drawings in :mod:`.drawing`."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from qpcontact.judge.scales import ComponentScales
from qpcontact.judge.lcp import certify_lcp
from qpcontact.core.errors import (InvalidOptionError, InvalidProblemError, NoSolutionError,
                                   QpcontactError, SolverFailedError)
from qpcontact.core.options import check_options
from qpcontact.core.problems import ParametricLCP
from qpcontact.dispatch.driver import solve

from . import assembly
from .assembly import DOFS, geometry
from .loads import (CONSTANT, VARIABLE, MemberLoad, case_name, check_axes, combination,
                    describe, load_points, number, section_sums)
from .results import (CombinationResults, FrameEvent, FrameResult, FrameTrace, SupportResult)

#: A normal force or slip below STATE_RTOL of its own componentwise scale is zero
#: when the support's state is named.
STATE_RTOL = 1e-9
#: Global equilibrium residual (relative to the loads) above which a result is flagged.
EQUILIBRIUM_RTOL = 1e-8
#: seconds each QP backend may take inside a frame's "auto" route (Lemke's
#: proof comes first; a backend loop on a load the frame cannot carry took
#: 40 s in ProxQP before)
BACKEND_TIME_LIMIT = 10.0


@dataclass
class _Member:
    name: str
    i: str
    j: str
    E: float
    A: float
    I: float
    hinge_i: bool
    hinge_j: bool
    loads: list = field(default_factory=list)   # MemberLoad


@dataclass
class _Contact:
    node: str
    normal: np.ndarray
    friction: float
    gap: float
    stiffness: float | None
    other: str | None


class Frame:
    """A plane frame with bilateral supports and springs, unilateral
    (possibly frictional) contacts, and loads in named cases (package
    docstring: units and sign conventions).  ``units`` = (force, length)
    names, used on drawings and tables only: nothing is converted."""

    def __init__(self, units=("kN", "m")):
        if (not isinstance(units, (tuple, list)) or len(units) != 2
                or not all(isinstance(u, str) for u in units)):
            raise InvalidProblemError(f"units must be (force, length) names, e.g. ('kN', 'm'); "
                                      f"got {units!r}")
        self.units = tuple(units)
        self.nodes: dict[str, np.ndarray] = {}
        self.members: dict[str, _Member] = {}
        self.fixed: dict[str, set] = {}
        self.springs: dict[str, dict] = {}
        self.contacts: list[_Contact] = []
        self.nodal_loads: list = []   # (node, fx, fy, mz, case)
        self.settlements: list = []   # (node, dof, case, value)

    # -- model ------------------------------------------------------------
    def add_node(self, name: str, x: float, y: float) -> str:
        if name in self.nodes:
            raise InvalidProblemError(f"node {name!r} exists already")
        self.nodes[name] = np.array([number(x, f"node {name!r}: x"),
                                     number(y, f"node {name!r}: y")])
        return name

    def _node(self, name):
        if name not in self.nodes:
            raise InvalidProblemError(f"no node named {name!r}; nodes: {list(self.nodes)}")
        return name

    def _member(self, name) -> _Member:
        if name not in self.members:
            raise InvalidProblemError(f"no member named {name!r}; members: {list(self.members)}")
        return self.members[name]

    def add_beam(self, i: str, j: str, E: float, A: float, I: float, *, name: str | None = None,
                 hinge_i: bool = False, hinge_j: bool = False) -> str:
        """A frame member from node i to node j (E, A, I in consistent units);
        ``hinge_i``/``hinge_j`` release the end moment.  Returns its name."""
        self._node(i), self._node(j)
        if i == j:
            raise InvalidProblemError("a member needs two different nodes")
        vals = {}
        for v, nm in ((E, "E"), (A, "A"), (I, "I")):
            vals[nm] = number(v, f"member {i}-{j}: {nm}")
            if not vals[nm] > 0:
                raise InvalidProblemError(f"member {i}-{j}: {nm} must be positive; got {v}")
        name = name or f"M{len(self.members) + 1}"
        if name in self.members:
            raise InvalidProblemError(f"member {name!r} exists already")
        self.members[name] = _Member(name, i, j, vals["E"], vals["A"], vals["I"], bool(hinge_i),
                                     bool(hinge_j))
        return name

    def add_support(self, node: str, fix=("ux", "uy", "rz")) -> None:
        """Bilateral support: the listed degrees of freedom are fixed."""
        self._node(node)
        fix = (fix,) if isinstance(fix, str) else tuple(fix)
        bad = [d for d in fix if d not in DOFS]
        if bad:
            raise InvalidProblemError(f"fix must name dofs among {DOFS}; got {bad}")
        self.fixed.setdefault(node, set()).update(fix)

    def add_settlement(self, node: str, case: str = CONSTANT, *, ux: float | None = None,
                       uy: float | None = None, rz: float | None = None) -> None:
        """Prescribed displacement of bilateral supports (a settlement, in
        load case ``case``): each dof given must be fixed by add_support."""
        self._node(node)
        given = {d: v for d, v in (("ux", ux), ("uy", uy), ("rz", rz)) if v is not None}
        if not given:
            raise InvalidProblemError(f"settlement at {node!r}: give ux=, uy= and/or rz=")
        for d, v in given.items():
            if d not in self.fixed.get(node, set()):
                raise InvalidProblemError(
                    f"settlement at {node!r}: {d} is not fixed by a bilateral support there "
                    f"(fixed: {sorted(self.fixed.get(node, set())) or 'none'}); add_support("
                    f"{node!r}, fix=(..., {d!r})) first — a settlement moves a support")
            self.settlements.append((node, d, case_name(case),
                                     number(v, f"settlement at {node!r}: {d}")))

    def add_spring(self, node: str, ux: float = 0.0, uy: float = 0.0, rz: float = 0.0) -> None:
        """Bilateral elastic support to the ground: stiffnesses (force/length,
        moment/radian) along the global dofs; its reaction is -k u."""
        self._node(node)
        ks = {d: number(v, f"spring at {node!r}: {d}") for d, v in (("ux", ux), ("uy", uy),
                                                                      ("rz", rz))}
        if any(v < 0 for v in ks.values()):
            raise InvalidProblemError(f"spring at {node!r}: stiffnesses must be >= 0; got {ks}")
        slot = self.springs.setdefault(node, {})
        for d, v in ks.items():
            if v:
                slot[d] = slot.get(d, 0.0) + v

    def add_contact(self, node: str, normal=(0.0, 1.0), friction: float = 0.0, gap: float = 0.0,
                    stiffness: float | None = None, other: str | None = None) -> int:
        """A unilateral support (or node-to-node contact pair with ``other``):
        normal from the support into the structure, Coulomb coefficient
        ``friction`` (0: no tangential link), initial ``gap`` >= 0, rigid unless
        ``stiffness`` is given.  Returns the contact's index."""
        self._node(node)
        if other is not None:
            self._node(other)
        try:
            n = np.array(normal, float)
        except (TypeError, ValueError):
            n = np.zeros(0)
        if n.shape != (2,) or not np.isfinite(n).all() or np.linalg.norm(n) == 0:
            raise InvalidProblemError(f"contact at {node!r}: normal must be a nonzero 2-vector")
        friction = number(friction, f"contact at {node!r}: friction")
        gap = number(gap, f"contact at {node!r}: gap")
        if not friction >= 0:
            raise InvalidProblemError(f"contact at {node!r}: friction must be >= 0")
        if not gap >= 0:
            raise InvalidProblemError(f"contact at {node!r}: gap must be >= 0 (no initial overlap)")
        if stiffness is not None:
            stiffness = number(stiffness, f"contact at {node!r}: stiffness")
            if not stiffness > 0:
                raise InvalidProblemError(
                    f"contact at {node!r}: stiffness must be > 0 or None (rigid)")
        self.contacts.append(_Contact(node, n / np.linalg.norm(n), friction, gap, stiffness,
                                      other))
        return len(self.contacts) - 1

    # -- loads -------------------------------------------------------------
    def add_load(self, node: str, fx: float = 0.0, fy: float = 0.0, mz: float = 0.0,
                 case: str = CONSTANT) -> None:
        """Nodal force and moment (global axes) in load case ``case``."""
        self._node(node)
        self.nodal_loads.append((node, number(fx, f"load at {node!r}: fx"),
                                 number(fy, f"load at {node!r}: fy"),
                                 number(mz, f"load at {node!r}: mz"), case_name(case)))

    def _position(self, m: _Member, a, what, relative):
        L = geometry(self, m)[0]
        a = number(a, f"member {m.name}: {what}")
        if relative:
            a *= L
        if not -1e-12 * L <= a <= L * (1 + 1e-12):
            raise InvalidProblemError(
                f"member {m.name}: {what} = {a:g} lies outside the member (length {L:g}"
                + (", positions given as fractions with relative=True" if relative else "") + ")")
        return min(max(a, 0.0), L)

    def add_point_load(self, member: str, a: float, fx: float = 0.0, fy: float = 0.0,
                       mz: float = 0.0, *, axes: str = "global", case: str = CONSTANT,
                       relative: bool = False) -> None:
        """A force (fx, fy) and a moment mz at distance ``a`` from node i
        (a fraction of the length with ``relative=True``)."""
        m = self._member(member)
        a = self._position(m, a, "a", relative)
        vals = tuple(number(v, f"point load on {member}: {nm}")
                     for v, nm in ((fx, "fx"), (fy, "fy"), (mz, "mz")))
        m.loads.append(MemberLoad("point", case_name(case), check_axes(axes), a, a, vals))

    def add_distributed_load(self, member: str, wx: float = 0.0, wy: float = 0.0,
                             case: str = CONSTANT, *, wx2: float | None = None,
                             wy2: float | None = None, start: float = 0.0,
                             end: float | None = None, axes: str = "global",
                             relative: bool = False) -> None:
        """A load per unit length of the member, (wx, wy) at ``start`` varying
        linearly to (wx2, wy2) at ``end`` (defaults: uniform over the whole
        member), in global or member axes."""
        m = self._member(member)
        L = geometry(self, m)[0]
        a = self._position(m, start, "start", relative)
        b = self._position(m, L if end is None else end, "end", relative and end is not None)
        if b < a:
            raise InvalidProblemError(f"member {member}: end ({b:g}) before start ({a:g})")
        w = [number(v, f"distributed load on {member}: {nm}")
             for v, nm in ((wx, "wx"), (wy, "wy"))]
        w2 = [w[0] if wx2 is None else number(wx2, f"distributed load on {member}: wx2"),
              w[1] if wy2 is None else number(wy2, f"distributed load on {member}: wy2")]
        m.loads.append(MemberLoad("distributed", case_name(case), check_axes(axes), a, b,
                                  (w[0], w[1], w2[0], w2[1])))

    def add_self_weight(self, case: str = "D", *, unit_weight: float | None = None,
                        weight_per_length: float | None = None, members=None,
                        direction=(0.0, -1.0)) -> None:
        """Self-weight as a uniform global load: ``weight_per_length``
        (force/length) or ``unit_weight`` (force/volume, e.g. 78.5 kN/m³ for
        steel) times each member's A, along ``direction`` (default -y)."""
        if (unit_weight is None) == (weight_per_length is None):
            raise InvalidProblemError("give exactly one of unit_weight (force/volume, times A) "
                                      "or weight_per_length (force/length)")
        d = np.array(direction, float)
        if d.shape != (2,) or not np.linalg.norm(d) > 0:
            raise InvalidProblemError(f"direction must be a nonzero 2-vector; got {direction!r}")
        d = d / np.linalg.norm(d)
        names = list(self.members) if members is None else list(members)
        for nm in names:
            m = self._member(nm)
            w = (number(weight_per_length, "weight_per_length") if unit_weight is None
                 else number(unit_weight, "unit_weight") * m.A)
            self.add_distributed_load(nm, w * d[0], w * d[1], case)

    @property
    def load_cases(self) -> list:
        return assembly.cases(self)

    @property
    def has_friction(self) -> bool:
        return any(c.friction > 0 for c in self.contacts)

    # -- assembly -----------------------------------------------------------
    def build(self):
        """The assembly (K, links, R and R_F per case): see formulations.frames.assembly."""
        return assembly.build(self)

    def lcp(self, b=None):
        """The contact LCP of the P3 split as (M, q_constant, q_variable, P, g,
        fric) with link displacements Δ = P z - g: z = (Z_n per contact, then
        Z⁺, Z⁻ per frictional contact)."""
        b = b or self.build()
        M, Q, q_gap, P, g, fric = assembly.lcp_matrices(self, b)
        qc, _ = assembly.combination_q(Q, q_gap, b, {CONSTANT: 1.0})
        qv, _ = assembly.combination_q(Q, np.zeros_like(q_gap), b, {VARIABLE: 1.0})
        return M, qc, qv, P, g, fric

    def friction_problem(self, p: float = 1.0, *, combination: dict | None = None):
        """The frame's contact problem for one load combination as a 2-D
        :class:`~qpcontact.friction.FrictionProblem` — the form FCLIB and
        Siconos's solvers take (``qpcontact.io.write_fclib`` writes it).

        Global form: K v = H r + f (K the stiffness on the free dofs, v the
        displacements, f the combination's loads, settlements moved to the
        right-hand side), u = Hᵀ v + w with u = (opening, slip) per contact
        (w: the gaps, and what settlements do to the contacts), r = (X_n,
        X_t) the contact force on the structure along the normal and
        t = (n_y, −n_x), μ = the contact's friction (0: a frictionless
        contact, whose cone is its normal ray).  Quasi-static: "velocities"
        are displacements, units the frame's.  Elastic contacts add their
        flexibility 1/k to W's diagonal, so their problem is exported in local
        form.  A frame that is a mechanism without its contacts (K singular:
        W = Hᵀ K⁻¹ H does not exist) is exported in global form, unreduced,
        which solve_friction solves without W ("desaxce-global"); with elastic
        contacts too it raises InvalidProblemError."""
        import scipy.sparse as sp

        from qpcontact.friction.problem import FrictionProblem

        b = self.build()
        combo = self._combo(p, combination, b)
        K, F, U, fixed, free = b["K"], b["F"], b["U"], b["fixed"], b["free"]
        N = K.shape[0]
        cols = []
        for c in self.contacts:
            t = np.array([c.normal[1], -c.normal[0]])
            cols += [assembly.contact_column(b["idx"], N, c, c.normal),
                     assembly.contact_column(b["idx"], N, c, t)]
        H = np.array(cols).T
        factors = np.array([combo.get(case, 0.0) for case in b["cases"]])
        f_all, u_set = F @ factors, U @ factors
        fixed_idx = np.flatnonzero(fixed)
        f = f_all[free] - K[free][:, fixed_idx] @ u_set[fixed_idx]
        w = H[fixed_idx].T @ u_set[fixed_idx]
        w[0::2] += [c.gap for c in self.contacts]
        mu = np.array([c.friction for c in self.contacts])
        name = f"frame ({', '.join(f'{k}: {v:g}' for k, v in combo.items())})"
        prob = FrictionProblem.global_problem(sp.csc_matrix(K[free][:, free]),
                                              sp.csc_matrix(H[free]), f, w, mu, 2, name=name)
        flex = np.repeat([0.0 if c.stiffness is None else 1.0 / c.stiffness
                          for c in self.contacts], 2)
        if np.any(flex > 0) and not prob.is_reduced:
            raise InvalidProblemError(
                "this frame is a mechanism without its contacts and has elastic contacts: their "
                "flexibility enters W = Hᵀ K⁻¹ H, which does not exist; make the contacts rigid "
                "or support the free motion to export it")
        if np.any(flex > 0):
            W = np.asarray(prob.W) + np.diag(flex)
            prob = FrictionProblem(W, prob.q, mu, 2, name=name + ", elastic contacts")
        return prob

    # -- solving ------------------------------------------------------------------
    def _combo(self, p, combo, b) -> dict:
        if combo is None:
            return {CONSTANT: 1.0, VARIABLE: number(p, "p")}
        return combination(combo, set(b["cases"]))

    def solve(self, p: float = 1.0, method: str = "auto", accuracy="high",
              raise_on_failure: bool = False, *, combination: dict | None = None,
              **options) -> FrameResult:
        """Analyse one load combination: ``combination`` = {case: factor}, or
        by default the P3 split constant + p·variable.

        ``method``: "auto" (frictionless and positive definite: the exact SPD
        method "bpp"; otherwise Lemke, whose ray on a load the frame cannot
        carry comes with a Farkas vector checked from the data, then the QP
        backends with a time limit each), any registered LCP method or QP
        backend name (frictionless), "lemke", or "tresca" (with friction: a
        fixed point of convex QPs with Tresca bounds, stopped on the full LCP
        certificate; falls back to Lemke).

        Raises NoSolutionError when no equilibrium exists (proved), saying
        how the frame fails; SolverFailedError when no method found one and
        nothing was proved; with ``raise_on_failure`` also for a result whose
        checks fail.
        """
        if not isinstance(method, str):
            raise InvalidOptionError(f"method must be a string; got {method!r}")
        b = self.build()
        combo = self._combo(p, combination, b)
        M, Q, q_gap, P, g, fric = assembly.lcp_matrices(self, b)
        lcp = assembly.combination_lcp(M, Q, q_gap, b, combo)
        from qpcontact.core.accuracy import resolve_accuracy
        from qpcontact.solvers.registry import methods as registry

        _, tol = resolve_accuracy(accuracy)
        if method not in ("auto", "tresca", "lemke") and method not in registry():
            raise InvalidOptionError(
                f"unknown method {method!r}: 'auto', 'lemke', 'tresca' (with friction) or a name "
                f"from qpcontact.methods(): {', '.join(registry())}")
        if method == "tresca":
            if not fric:
                raise InvalidOptionError("'tresca' is for frictional frames; this one has no friction")
            z, route = self._tresca(b, lcp, P, g, fric, combo, tol, accuracy, options)
        else:
            if fric and method not in ("auto", "lemke"):
                raise InvalidOptionError(
                    f"with friction the LCP is not symmetric; use method='lemke' or 'tresca', "
                    f"not {method!r}")
            if method == "auto":
                sol = self._auto(lcp, fric, accuracy, options)
            else:
                sol = solve(lcp, method=method, accuracy=accuracy, **options)
            z, route = sol.z, sol.method
            if not sol.ok:
                self._no_equilibrium(sol, fric, b, combo)
        res = self._result_from_z(z, combo, route, b=b, lcp=lcp, tol=tol)
        if not res.ok and res.lcp_error <= tol:
            # the LCP's answer is no equilibrium of the frame: a contact matrix
            # singular to rounding (the frame is a mechanism once its contacts
            # open) solved at a point of huge openings
            self._raise_rigid_motion(b, combo, f"{route}'s answer failed the statics check "
                                               f"({res.message})")
        if raise_on_failure and not res.ok:
            raise SolverFailedError(f"frame: {res.message}")
        return res

    def _auto(self, lcp, fric, accuracy, options):
        if not fric and lcp.is_positive_definite:
            return solve(lcp, method="bpp", accuracy=accuracy)
        sol = solve(lcp, method="lemke", accuracy=accuracy, **options)
        if sol.ok or fric or sol.stats.get("farkas") is not None:
            return sol
        best = sol
        for name in ("clarabel", "piqp", "osqp", "highs"):
            try:
                s = solve(lcp, method=name, accuracy=accuracy, time_limit=BACKEND_TIME_LIMIT)
            except QpcontactError:
                continue
            if s.ok or s.stats.get("proof") is not None:
                return s
            if s.error < best.error:
                best = s
        return best

    def _no_equilibrium(self, sol, fric, b, combo):
        """Raise with what was proved (a Farkas vector: how the frame fails) or
        with what was tried."""
        y = sol.stats.get("farkas")
        proof = sol.stats.get("proof")
        if y is None and proof is not None and proof.kind == "infeasible":
            y = proof.vector["z"]
        what = describe(combo)
        if y is not None:
            words = self._collapse_words({"farkas": np.asarray(y, float)}, fric, carrying=None)
            raise NoSolutionError(
                f"frame under {what}: no equilibrium exists — {words} (proved by a Farkas "
                f"vector checked from the data: y >= 0, M'y <= 0, q'y < 0)")
        self._raise_rigid_motion(b, combo, f"{sol.method}: {sol.message}")
        raise SolverFailedError(
            f"frame under {what}: {sol.method} found no contact state ({sol.message}); nothing "
            "was proved either way")

    def _rigid_motion(self, b, combo):
        """A rigid motion φ of the frame with every contact released (a null
        vector of the free stiffness, springs and bilateral supports
        included) that only opens or slides the contacts within Coulomb's
        cone (a_c >= f |s_c|) and in which the loads do positive work: then
        no equilibrium exists (virtual work: F'φ = -Σ X·(H'φ) <= 0 for any
        admissible contact forces).  Found by one LP over the null space and
        checked in floating point to rounding; returns (a, s) or None.

        This is what proves "no equilibrium" when the contact matrix is
        singular only up to rounding (R has the rigid motion in its null
        space exactly, its computed copy only nearly), where the LCP's exact
        Farkas check cannot pass."""
        from scipy.optimize import linprog

        free = b["free"]
        if free.size > 3000:
            return None
        Kf = b["K"][free][:, free].toarray()
        d = np.sqrt(np.abs(np.diag(Kf)))
        d[d == 0] = 1.0
        lam, V = np.linalg.eigh(Kf / d[:, None] / d[None, :])
        null = V[:, lam <= 1e-10 * max(lam.max(initial=0.0), 1e-300)] / d[:, None]
        if null.shape[1] == 0:
            return None
        F, _ = assembly.combine(b, combo)
        Ff = F[free]
        N = b["K"].shape[0]
        rows_a, rows_s = [], []
        for c in self.contacts:
            t = np.array([c.normal[1], -c.normal[0]])
            for vec, rows in ((c.normal, rows_a), (t, rows_s)):
                rows.append(assembly.contact_column(b["idx"], N, c, vec)[free] @ null)
        Ha, Hs = np.array(rows_a), np.array(rows_s)
        f = np.array([c.friction for c in self.contacts])
        work = Ff @ null
        if not np.any(work):
            return None
        A_ub = np.vstack([-(Ha - f[:, None] * Hs), -(Ha + f[:, None] * Hs)])
        res = linprog(np.zeros(null.shape[1]), A_ub=A_ub, b_ub=np.zeros(A_ub.shape[0]),
                      A_eq=work[None, :], b_eq=[1.0], bounds=[(None, None)] * null.shape[1],
                      method="highs")
        if res.status != 0:
            return None
        phi = null @ res.x
        a, sl = Ha @ res.x, Hs @ res.x
        size = np.abs(phi).max()
        w_scale = np.abs(Ff) @ np.abs(phi)
        tol = 1e-9 * size
        if not (Ff @ phi > 1e-6 * w_scale and np.all(a - f * np.abs(sl) >= -tol)):
            return None
        a = np.where(np.abs(a) <= tol, 0.0, a)
        sl = np.where(np.abs(sl) <= tol, 0.0, sl)
        return a, sl

    def _raise_rigid_motion(self, b, combo, before: str):
        motion = self._rigid_motion(b, combo)
        if motion is None:
            return
        raise NoSolutionError(
            f"frame under {describe(combo)}: no equilibrium exists — {self._motion_words(*motion, None)} "
            f"(a rigid motion of the frame with its contacts released, in which the loads do "
            f"positive work while every contact opens or slides within its friction cone; "
            f"found by LP, checked to rounding; {before})")

    def solve_combinations(self, combinations: dict, **kw) -> CombinationResults:
        """Each named combination solved on its own — its own contact states,
        reactions and checks (no state carried over, never superposed).
        Values are {case: factor} dicts (or a number p for the P3 split).  A
        combination that cannot be carried gives a result with ok False and
        the reason; the others are kept.  Returns a CombinationResults."""
        if not isinstance(combinations, dict) or not combinations:
            raise InvalidProblemError("combinations: a non-empty dict {name: {case: factor}}")
        out = CombinationResults()
        for name, combo in combinations.items():
            args = dict(kw)
            if isinstance(combo, dict):
                args["combination"] = combo
            else:
                args["p"] = combo
            try:
                res = self.solve(**args)
            except (NoSolutionError, SolverFailedError) as exc:
                res = FrameResult(p=float("nan"), supports={}, displacements={},
                                  member_forces={}, reactions={},
                                  equilibrium_residual=float("nan"), lcp_error=float("nan"),
                                  route="", ok=False, message=str(exc), frame=self,
                                  combination=combo if isinstance(combo, dict) else {})
            res.name = str(name)
            out[name] = res
        return out

    def _tresca(self, b, lcp, P, g, fric, combo, tol, accuracy, options):
        """Fixed point on Tresca bounds s = f X_n: each iteration the convex QP
        min ½(Pz-g)'R(Pz-g) + R_F'(Pz-g) + s'(Z⁺ + Z⁻), z >= 0 (its KKT system is
        the LCP with the bounds frozen); stopped when z solves the full LCP."""
        from qpsolvers import Problem

        check_options("tresca", options, ("qp_method", "max_iter"))
        qp_method = options.get("qp_method", "auto")
        max_iter = int(options.get("max_iter", 50))
        R = b["R"]
        _, RF = assembly.combine(b, combo)
        nc = len(self.contacts)
        pos = assembly.layout(b)
        H = P.T @ R @ P
        H = 0.5 * (H + H.T)
        base = P.T @ (RF - R @ g)
        xn = np.zeros(nc)
        for it in range(max_iter):
            s = np.zeros(P.shape[1])
            for k, ci in enumerate(fric):
                s[nc + 2 * k] = s[nc + 2 * k + 1] = self.contacts[ci].friction * max(xn[ci], 0.0)
            sol = solve(Problem(H, base + s, lb=np.zeros(H.shape[0])), method=qp_method,
                        accuracy=accuracy)
            if sol.x is None:
                break
            z = np.maximum(sol.x, 0.0)
            if certify_lcp(lcp, z).ok(tol):
                return z, f"tresca fixed point ({sol.method}, {it + 1} iterations)"
            X = R @ (P @ z - g) + RF
            xn = np.array([X[pos[ci]["n"]] for ci in range(nc)])
        sol = solve(lcp, method="lemke", accuracy=accuracy)
        if not sol.ok:
            self._no_equilibrium(sol, fric, b, combo)
        return sol.z, f"lemke (Tresca fixed point did not converge in {max_iter} iterations)"

    # -- results --------------------------------------------------------------------
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
        eq = self._equilibrium(b, F, X, r_all, u)
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
        ok = cert.ok(tol) and eq <= EQUILIBRIUM_RTOL
        msg = (f"{route}: LCP certificate {cert.error:.1e}, equilibrium residual {eq:.1e}"
               + ("" if ok else " — CHECK FAILED"))
        return FrameResult(p=float(combo.get(VARIABLE, 0.0)), supports=supports,
                           displacements=displacements, member_forces=member_forces,
                           reactions=reactions, equilibrium_residual=eq, lcp_error=cert.error,
                           route=route, ok=ok, message=msg, frame=self, _u=u,
                           combination=dict(combo))

    def _equilibrium(self, b, F, X, r_all, u):
        """|Σ forces| and |Σ moments about the origin| of loads, contact forces,
        reactions and springs, relative to the largest load term (a statics check)."""
        xy = np.array([self.nodes[nd] for nd in b["names"]])
        spring = np.zeros_like(F)
        for node, ks in self.springs.items():
            for d, kval in ks.items():
                i = b["idx"][node] + DOFS.index(d)
                spring[i] -= kval * u[i]
        f_tot = F + b["H"] @ X + np.where(b["fixed"], r_all, 0.0) + spring
        fx, fy, mz = f_tot[0::3], f_tot[1::3], f_tot[2::3]
        res_f = np.array([fx.sum(), fy.sum(), mz.sum() + (xy[:, 0] * fy - xy[:, 1] * fx).sum()])
        Fx, Fy, Mz = F[0::3], F[1::3], F[2::3]
        ref = max(np.abs(F).max(initial=0.0), np.abs(b["H"] @ X).max(initial=0.0),
                  np.abs(spring).max(initial=0.0),
                  np.abs(Mz + xy[:, 0] * Fy - xy[:, 1] * Fx).max(initial=0.0), 1e-300)
        return float(np.abs(res_f).max() / ref)

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

    # -- trace -----------------------------------------------------------------------
    def _support_keys(self) -> list:
        """The key of each contact in FrameResult.supports, in contact order."""
        keys = []
        for c in self.contacts:
            key = c.node if c.other is None else f"{c.node}-{c.other}"
            keys.append(f"{key}#{len(keys)}" if key in keys else key)
        return keys

    def trace(self, p_max: float | None = None, accuracy="high", *, constant: dict | None = None,
              variable=None) -> FrameTrace:
        """P3's increasing-load analysis: the ``constant`` combination (default
        the case "constant"), then the ``variable`` loads (a case name or a
        combination; default the case "variable") scaled by p from 0 to
        ``p_max`` (None: until no support changes state again, or no
        equilibrium continues the path).

        Every piece of the path is checked like a single solve (LCP certificate
        and global equilibrium, at its start, middle and end); a piece that
        fails is not returned and the trace ends "breakdown".  Breakpoints where
        only the LCP's bookkeeping changes (a separated contact's slip changing
        sign) are merged: ``breakpoints`` are where a support changes state.
        """
        from qpcontact.core.accuracy import resolve_accuracy

        _, tol = resolve_accuracy(accuracy)
        b = self.build()
        known = set(b["cases"])
        const = combination(constant or {CONSTANT: 1.0}, known)
        var = combination({variable: 1.0} if isinstance(variable, str)
                          else (variable or {VARIABLE: 1.0}), known)
        M, Q, q_gap, P, g, fric = assembly.lcp_matrices(self, b)
        qc, _ = assembly.combination_q(Q, q_gap, b, const)
        qv, _ = assembly.combination_q(Q, np.zeros_like(q_gap), b, var)
        tr = solve(ParametricLCP(M, qc, qv), method="trace", accuracy=accuracy,
                   p_max=np.inf if p_max is None else p_max)
        ft = FrameTrace(breakpoints=np.zeros(0), states=[], intervals=[], events=[],
                        ended=tr.end, message="", ok=False, trace=tr, frame=self, _built=b,
                        constant=const, variable=var)
        runs = []        # [p_start, p_end, states]
        ended, failed = tr.end, None
        for piece in tr.pieces:
            hi = piece.p_end if np.isfinite(piece.p_end) else piece.p_start + max(1.0, piece.p_start)
            checks = [self._result_from_z(piece.z(pp), ft._combo(pp), "trace", b=b, tol=tol)
                      for pp in (piece.p_start, 0.5 * (piece.p_start + hi), hi)]
            bad = [r for r in checks if not r.ok]
            if bad:
                ended, failed = "breakdown", bad[0]
                break
            key = {k: v.state for k, v in checks[1].supports.items()}
            if runs and runs[-1][2] == key:
                runs[-1][1] = piece.p_end
            else:
                runs.append([piece.p_start, piece.p_end, key])
        ft.ended = ended
        ft.intervals = [(r[0], r[1]) for r in runs]
        ft.events = [FrameEvent(r1[0], {k: (r0[2][k], r1[2][k]) for k in r1[2]
                                        if r0[2][k] != r1[2][k]})
                     for r0, r1 in zip(runs[:-1], runs[1:])]
        ft.breakpoints = np.array([ev.p for ev in ft.events])
        for lo, hi in ft.intervals:
            top = hi if np.isfinite(hi) else lo + max(1.0, lo)
            ft.states.append(ft.result_at(0.5 * (lo + top)))
        if failed is not None:
            ft.message = (f"the piece from p = {failed.p:g} failed the frame's checks "
                          f"({failed.message}); the trace stops there")
        elif ended == "collapse":
            carrying = ([k for k, v in ft.states[-1].supports.items() if v.state != "separated"]
                        if ft.states else None)
            words = (self._collapse_words(tr.proof, fric, carrying)
                     if tr.proof["farkas"] is not None
                     else "no combination of support states carries the load")
            how = ("a Farkas certificate" if tr.proof["patterns"] == 1 else
                   f"Farkas certificates for all {tr.proof['patterns']} combinations of support "
                   "states left after branching")
            bound = ("" if not np.isfinite(tr.proof["z_bound"]) else
                     f" for openings and slips summing below {tr.proof['z_bound']:.1e}")
            ft.message = (f"no equilibrium exists for p >= {tr.proof['p_limit']:.10g} (the last one "
                          f"is at p = {tr.p_end:.10g}): {words} (proved by {how}, checked from "
                          f"the data{bound})")
        elif ended == "unbounded":
            ft.message = (f"no support changes state for p >= {tr.proof['from']:g}: the frame "
                          "carries any larger load in its last working scheme")
        else:
            ft.message = tr.message
        ft.ok = bool(tr.ok and failed is None)
        ft.message += f"; {len(ft.events)} change(s) of the working scheme"
        return ft

    def _collapse_words(self, proof, fric, carrying) -> str:
        """How the frame fails, read off the Farkas vector y.

        y'w = Σ_c (A_c X_n + T_c X_t) with A_c = y_n + f (y+ + y-) and T_c =
        y+ - y-, and y'M = 0 makes this combination independent of the
        displacements: it is the virtual work of the contact forces in a rigid
        motion of the frame with normal motion A_c >= f |T_c| and tangential
        motion T_c at each contact.  A contact lifts off in it when A_c >
        f |T_c|, slides (along ±t) when T_c != 0 and A_c = f |T_c| (Coulomb's
        cone), and stays (a pivot) when both are zero.
        """
        y = proof["farkas"]
        nc = len(self.contacts)
        A = y[:nc].copy()
        T = np.zeros(nc)
        for k, ci in enumerate(fric):
            yp, ym = y[nc + 2 * k], y[nc + 2 * k + 1]
            A[ci] += self.contacts[ci].friction * (yp + ym)
            T[ci] = yp - ym
        return self._motion_words(A, T, carrying)

    def _motion_words(self, A, T, carrying) -> str:
        """Words for a rigid motion with normal opening A_c >= f |T_c| and
        tangential motion T_c at each contact (see _collapse_words)."""
        keys = self._support_keys()
        nc = len(self.contacts)
        big = max(A.max(initial=0.0), np.abs(T).max(initial=0.0))
        lift, slide, stay = [], [], []
        for ci in range(nc):
            f = self.contacts[ci].friction
            if A[ci] <= 1e-9 * big and abs(T[ci]) <= 1e-9 * big:
                stay.append(keys[ci])
            elif A[ci] > f * abs(T[ci]) * (1 + 1e-6) + 1e-9 * big:
                lift.append(keys[ci])
            else:
                slide.append(f"{keys[ci]} ({'+t' if T[ci] > 0 else '-t'})")
        if slide and not lift:
            whole = carrying is None or all(any(s.startswith(k + " ") for s in slide)
                                            for k in carrying)
            return (("the frame slides away as a rigid body: " if whole else "it slides: ")
                    + "friction exhausted at " + ", ".join(slide))
        if lift and not slide:
            if stay:
                return f"it tips over about {', '.join(stay)}: {', '.join(lift)} lift off"
            return "it lifts off: " + ", ".join(lift) + " would have to pull"
        return ("it lifts off at " + ", ".join(lift) + " and slides at " + ", ".join(slide))
