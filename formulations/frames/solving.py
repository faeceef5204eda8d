"""Solving a frame's contact problem: one combination (``Frame.solve``: the
"auto" route, a named method, or the Tresca fixed point), many
(``solve_combinations``), and when no equilibrium exists, the proof and the
words for how the frame fails.  Mixed into :class:`~.model.Frame`."""

from __future__ import annotations

import warnings

import numpy as np

from qpcontact import solve
from qpcontact.core.errors import (InvalidOptionError, InvalidProblemError, NoSolutionError,
                                   NotConvexError, QpcontactError, SolverFailedError)
from qpcontact.core.options import check_options
from qpcontact.judge.lcp_certificate import certify_lcp

from . import assembly
from .active_set import solve_active_set
from .contact_springs import with_contact_springs
from .recovery import SMALL_DISPLACEMENT, SMALL_ROTATION, LargeDisplacementWarning
from .loads import CONSTANT, VARIABLE, combination, describe, number
from .results import CombinationResults, FrameResult

#: seconds each QP backend may take inside a frame's "auto" route (Lemke's
#: proof comes first; a backend loop on a load the frame cannot carry took
#: 40 s in ProxQP before)
BACKEND_TIME_LIMIT = 10.0


def _proved(sol) -> bool:
    """Whether a failed solve came with a proof that no equilibrium exists."""
    proof = sol.stats.get("proof")
    # Lemke's stats["farkas"] may hold a vector that holds to rounding only
    # (issue 31): a proof is what was checked exactly
    return bool(sol.stats.get("proved_infeasible")) or (
        proof is not None and getattr(proof, "kind", None) == "infeasible")


class FrameSolving:
    """The Frame's solving methods (the model, its results and the trace are
    the other parts of :class:`~.model.Frame`); shared by the space frame
    (:class:`~.space.SpaceFrame`), which has no active set and no Tresca
    route.  A frame class provides ``build``, ``_result_from_z``,
    ``_release_directions`` (for the rigid-motion proof), ``_how_far``,
    ``_support_keys`` and its contacts' ``friction``."""

    #: the frame's own routes besides the registry's methods
    ROUTES = ("auto", "active-set", "lemke", "tresca")
    RESULT = FrameResult

    def solve(self, p: float = 1.0, method: str = "auto", accuracy="high",
              raise_on_failure: bool = False, *, combination: dict | None = None,
              _built=None, **options) -> FrameResult:
        """Analyse one load combination: ``combination`` = {case: factor}, or
        by default the P3 split constant + p·variable.

        ``method``: "auto" (first the sparse active set, :mod:`.active_set`,
        which never forms the dense contact LCP; where it finds no
        consistent states or its answer fails the checks, the LCP:
        frictionless and positive definite, the exact SPD method "bpp";
        otherwise Lemke, whose ray on a load the frame cannot carry comes
        with a Farkas vector checked from the data, then the QP backends
        with a time limit each), "active-set" alone, any registered LCP
        method or QP backend name (frictionless), "lemke", or "tresca" (with
        friction: a fixed point of convex QPs with Tresca bounds, stopped on
        the full LCP certificate; falls back to Lemke).

        Raises NoSolutionError when no equilibrium exists (proved), saying
        how the frame fails; SolverFailedError when no method found one and
        nothing was proved; with ``raise_on_failure`` also for a result whose
        checks fail.  Warns (LargeDisplacementWarning) when the displacements
        leave small-displacement theory (``displacement_ratio``,
        ``max_rotation`` of the result).
        """
        res = self._solve(p, method, accuracy, raise_on_failure, combination, _built, options)
        if res.ok and (res.displacement_ratio > SMALL_DISPLACEMENT
                       or res.max_rotation > SMALL_ROTATION):
            warnings.warn(f"frame under {describe(res.combination)}: {self._how_far(res._u)[2]}",
                          LargeDisplacementWarning, stacklevel=2)
        return res

    def _solve(self, p, method, accuracy, raise_on_failure, combination, _built,
               options) -> FrameResult:
        if not isinstance(method, str):
            raise InvalidOptionError(f"method must be a string; got {method!r}")
        from qpcontact import methods as registry
        from qpcontact.core.accuracy import resolve_accuracy

        _, tol = resolve_accuracy(accuracy)
        if method not in self.ROUTES and method not in registry():
            raise InvalidOptionError(
                f"unknown method {method!r}: {', '.join(repr(r) for r in self.ROUTES)} or a name "
                f"from qpcontact.methods(): {', '.join(registry())}")
        b = _built if _built is not None else self.build()
        combo = self._combo(p, combination, b)
        if method in ("auto", "active-set") and "active-set" in self.ROUTES:
            found = solve_active_set(self, b, combo)
            if found is not None:
                sets = f"{found[1]} state set" + ("s" if found[1] > 1 else "")
                res = self._result_from_z(found[0], combo, f"active set ({sets})", b=b, tol=tol)
                if res.ok:
                    return res
            if method == "active-set":
                raise SolverFailedError(
                    "frame: the active set found no consistent contact states (a cycle or a "
                    "singular state set); method='auto' goes on with the LCP (Lemke, the load "
                    "path)")
        M, Q, q_gap, P, g, fric = assembly.lcp_matrices(self, b)
        lcp = assembly.combination_lcp(M, Q, q_gap, b, combo)
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
                found = (self._trace_to(b, combo, lcp, accuracy, tol)
                         if method == "auto" and not _proved(sol) else None)
                if found is None:
                    self._no_equilibrium(sol, fric, b, combo, hint=method != "auto")
                z, route = found
        res = self._result_from_z(z, combo, route, b=b, lcp=lcp, tol=tol)
        if not res.ok and method == "auto" and not route.startswith("trace"):
            # an LCP answer that is no equilibrium of the frame: the load path
            # may still reach one (a table on rigid frictional pads: Lemke's
            # faceted-cone answer rotated it freely by 3.5e9 m, rounding
            # spoiling its forces; the path from the unloaded table sticks)
            found = self._trace_to(b, combo, lcp, accuracy, tol)
            if found is not None:
                again = self._result_from_z(found[0], combo, found[1], b=b, lcp=lcp, tol=tol)
                res = again if again.ok else res
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
        if sol.ok or fric or _proved(sol):
            return sol     # with friction, solve follows the load path where this is not ok
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

    def _no_equilibrium(self, sol, fric, b, combo, hint=False):
        """Raise with what was proved (a Farkas vector: how the frame fails) or
        with what was tried (``hint``: say that "auto" also follows the load
        path)."""
        proof = sol.stats.get("proof")
        y = sol.stats.get("farkas") if sol.stats.get("proved_infeasible") else None
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
            "was proved either way" + ("; method='auto' also follows the load path to this "
                                       "load (the trace's route)" if hint else
                                       "; following the load path to it (the trace) found no "
                                       "certified equilibrium either"))

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
        F, _ = assembly.load_vector(b, combo)
        Ff = F[free]
        normals, tangents, f = self._release_directions(b)
        Ha = normals[free].T @ null
        Hs = [t[free].T @ null for t in tangents]        # one (nc x null) per tangent
        work = Ff @ null
        if not np.any(work):
            return None
        # a_c >= f |s_c|: exact with one tangent (a >= ±f s); with two, by
        # a >= f (±s1 ±s2), which implies it (|s| <= |s1| + |s2|) — a proof
        # found under the stronger condition is still one
        signs = np.array(np.meshgrid(*[[1.0, -1.0]] * len(Hs))).reshape(len(Hs), -1).T
        A_ub = np.vstack([-(Ha + f[:, None] * sum(sg * h for sg, h in zip(row, Hs)))
                          for row in signs])
        res = linprog(np.zeros(null.shape[1]), A_ub=A_ub, b_ub=np.zeros(A_ub.shape[0]),
                      A_eq=work[None, :], b_eq=[1.0], bounds=[(None, None)] * null.shape[1],
                      method="highs")
        if res.status != 0:
            return None
        phi = null @ res.x
        a = Ha @ res.x
        sl = np.stack([h @ res.x for h in Hs], axis=1) if Hs else np.zeros((a.size, 0))
        size = np.abs(phi).max()
        w_scale = np.abs(Ff) @ np.abs(phi)
        tol = 1e-9 * size
        if not (Ff @ phi > 1e-6 * w_scale and np.all(a - f * np.linalg.norm(sl, axis=1) >= -tol)):
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
        # one assembly and one factorization of the basic system for all
        # combinations (and R, formed once if a combination needs the LCP)
        kw["_built"] = self.build()
        for name, combo in combinations.items():
            args = dict(kw)
            if isinstance(combo, dict):
                args["combination"] = combo
            else:
                args["p"] = combo
            try:
                res = self.solve(**args)
            except (NoSolutionError, SolverFailedError) as exc:
                res = self.RESULT(p=float("nan"), supports={}, displacements={},
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
        H = self._tresca_matrix(P.T @ R @ P, b)
        base = P.T @ (RF - R @ g)
        xn = np.zeros(nc)
        for it in range(max_iter):
            s = np.zeros(P.shape[1])
            for k, ci in enumerate(fric):
                s[nc + 2 * k] = s[nc + 2 * k + 1] = self.contacts[ci].friction * max(xn[ci], 0.0)
            try:
                sol = solve(Problem(H, base + s, lb=np.zeros(H.shape[0])), method=qp_method,
                            accuracy=accuracy)
            except NotConvexError as exc:
                raise InvalidProblemError(
                    f"frame: the Tresca fixed point needs the contact stiffness matrix to be "
                    f"positive semidefinite, and {qp_method!r} refused it ({exc}); "
                    "method='lemke' or 'auto' does not need it") from exc
            if sol.x is None:
                break
            z = np.maximum(sol.x, 0.0)
            # judged by the frame's checks, not the LCP certificate alone: with the
            # frame resting on its contacts a QP can answer with a rigid lift of
            # 2e9 m that the certificate (relative to |M||z|) passes
            if certify_lcp(lcp, z).ok(tol) and self._result_from_z(z, combo, "", b=b, lcp=lcp,
                                                                    tol=tol).ok:
                return z, f"tresca fixed point ({sol.method}, {it + 1} iterations)"
            X = R @ (P @ z - g) + RF
            xn = np.array([X[pos[ci]["n"]] for ci in range(nc)])
        sol = solve(lcp, method="lemke", accuracy=accuracy)
        if sol.ok:
            return sol.z, f"lemke (Tresca fixed point did not converge in {max_iter} iterations)"
        found = None if _proved(sol) else self._trace_to(b, combo, lcp, accuracy, tol)
        if found is None:
            self._no_equilibrium(sol, fric, b, combo)
        return found[0], f"{found[1]} (Tresca fixed point did not converge in {max_iter} iterations)"

    def _tresca_matrix(self, H, b):
        """The Tresca QP's Hessian P'RP, symmetric and convex to rounding.

        R is a stiffness, so P'RP is positive semidefinite in exact arithmetic;
        its computed copy is known only to R_ROUNDING x kappa per entry
        (assembly.build), and on a ground beam resting on 31 elastic frictional
        contacts its Jacobi scaling had the eigenvalue -4.4e-12, which the QP
        layer refused as a nonconvex objective ("a maximisation written as a
        minimisation?").  A negative eigenvalue within that rounding is lifted
        by a diagonal shift of the same size (the fixed point is stopped on
        the unshifted LCP's certificate, so the shift cannot change the
        answer); one beyond it is reported in the frame's terms."""
        H = 0.5 * (H + H.T)
        n = H.shape[0]
        d2 = np.abs(np.diag(H)).copy()
        if n == 0 or n > 3000 or not np.all(d2 > 0):
            return H
        d = np.sqrt(d2)
        lam = float(np.linalg.eigvalsh(H / d[:, None] / d[None, :])[0])
        if lam >= 0:
            return H
        rounding = 4.0 * n * assembly.R_ROUNDING * b["kappa"] / d2.min()
        if -lam > rounding:
            raise InvalidProblemError(
                f"frame: the contact stiffness matrix seen by the Tresca fixed point is not "
                f"positive semidefinite (eigenvalue {lam:.2g} of its diagonal scaling, beyond its "
                f"rounding {rounding:.1g}): a stiffness cannot do that, so the model is "
                "ill-conditioned to the point of nonsense — check the units and the stiffness "
                "ratios (very stiff members on very soft supports); method='lemke' or 'auto' "
                "does not need a convex QP")
        return H + (-lam + 20.0 * n * np.finfo(float).eps) * np.diag(d2)

    def _slide_words(self, ci, t) -> str:
        """Which way contact ci slides in a rigid motion with tangential part
        t (its components along the contact's tangents)."""
        return "+t" if t[0] > 0 else "-t"

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
        T = np.asarray(T, float).reshape(nc, -1)
        size = np.linalg.norm(T, axis=1)
        big = max(A.max(initial=0.0), size.max(initial=0.0))
        lift, slide, stay = [], [], []
        for ci in range(nc):
            f = self.contacts[ci].friction
            if A[ci] <= 1e-9 * big and size[ci] <= 1e-9 * big:
                stay.append(keys[ci])
            elif A[ci] > f * size[ci] * (1 + 1e-6) + 1e-9 * big:
                lift.append(keys[ci])
            else:
                slide.append(f"{keys[ci]} ({self._slide_words(ci, T[ci])})")
        if slide and not lift:
            # a carrying support that stays is a pivot (a table on a floor
            # turning about one leg)
            pivots = [k for k in stay if carrying is not None and k in carrying]
            if pivots:
                return (f"it turns about {', '.join(pivots)}: friction exhausted at "
                        + ", ".join(slide))
            whole = carrying is None or all(any(s.startswith(k + " ") for s in slide)
                                            for k in carrying)
            return (("the frame slides away as a rigid body: " if whole else "it slides: ")
                    + "friction exhausted at " + ", ".join(slide))
        if lift and not slide:
            if stay:
                return f"it tips over about {', '.join(stay)}: {', '.join(lift)} lift off"
            return "it lifts off: " + ", ".join(lift) + " would have to pull"
        return ("it lifts off at " + ", ".join(lift) + " and slides at " + ", ".join(slide))

    def friction_problem(self, p: float = 1.0, *, combination: dict | None = None, _built=None):
        """The frame's contact problem for one load combination as a
        :class:`~qpcontact.FrictionProblem` (2-D for a plane frame, 3-D for a
        space frame, with the true circular cone) — the form FCLIB and
        Siconos's solvers take (``qpcontact.io.write_fclib`` writes it).

        Global form: K v = H r + f (K the stiffness on the free dofs, v the
        displacements, f the combination's loads, settlements moved to the
        right-hand side), u = Hᵀ v + w with u = (opening, slip along each
        tangent) per contact (w: the gaps, and what settlements do to the
        contacts), r = (X_n, X_t...) the contact force on the structure along
        the normal and the tangents (plane: t = (n_y, −n_x); space: the
        contact's t1, t2), μ = the contact's friction (0: a frictionless
        contact, whose cone is its normal ray).  Quasi-static: "velocities"
        are displacements, units the frame's.  An elastic contact is a spring
        to a contact point of its own, whose displacement (normal, tangents)
        follows the free dofs in v (:mod:`.contact_springs`): reduced, W =
        Hᵀ K⁻¹ H + 1/k on its diagonal.  A frame that is a mechanism without
        its contacts (K singular: W does not exist) stays in global form,
        unreduced, which qpcontact.solve solves without W
        ("desaxce-global")."""
        from qpcontact import FrictionProblem

        b = _built if _built is not None else self.build()
        combo = self._combo(p, combination, b)
        K, F, U, fixed, free = b["K"], b["F"], b["U"], b["fixed"], b["free"]
        normals, tangents, mu = self._release_directions(b)
        dim = 1 + len(tangents)
        nc = normals.shape[1]
        # contact by contact: normal, then its tangents
        H = np.stack([normals] + tangents, axis=2).reshape(normals.shape[0], nc * dim)
        factors = np.array([combo.get(case, 0.0) for case in b["cases"]])
        f_all, u_set = F @ factors, U @ factors
        fixed_idx = np.flatnonzero(fixed)
        f = f_all[free] - K[free][:, fixed_idx] @ u_set[fixed_idx]
        w = H[fixed_idx].T @ u_set[fixed_idx]
        w[0::dim] += [c.gap for c in self.contacts]
        name = f"frame ({', '.join(f'{k}: {v:g}' for k, v in combo.items())})"
        flex = np.repeat([0.0 if c.stiffness is None else 1.0 / c.stiffness
                          for c in self.contacts], dim)
        M, Hg, fg = with_contact_springs(K[free][:, free], H[free], f, flex, dim)
        return FrictionProblem.global_problem(M, Hg, fg, w, mu, dim, name=name)

    def _combo(self, p, combo, b) -> dict:
        if combo is None:
            self._require_loads({CONSTANT: 1.0, VARIABLE: 1.0}, b, "solve(p)",
                                "constant + p x variable", only_if_named=True)
            return {CONSTANT: 1.0, VARIABLE: number(p, "p")}
        return combination(combo, set(b["cases"]))

    def _require_loads(self, combo, b, what, part, only_if_named=False) -> None:
        """Refuse a combination that puts no load on the frame where one is
        meant: solve(p) or trace() on a frame whose loads are all in named
        cases returned ok=True at zero load, silently (issue 31).  With
        ``only_if_named`` only when such cases exist (a frame with constant
        loads alone still solves, and traces trivially)."""
        factors = assembly.factors(b, combo)
        if np.any(b["F"] @ factors) or np.any(b["U"] @ factors):
            return
        named = [c for c in b["cases"] if c not in (CONSTANT, VARIABLE)
                 and (np.any(b["F"][:, b["cases"].index(c)])
                      or np.any(b["U"][:, b["cases"].index(c)]))]
        if only_if_named and not named:
            return
        cases = ", ".join(repr(c) for c in named) or "none"
        example = "{" + ", ".join(f"{c!r}: 1.0" for c in named[:2]) + "}"
        raise InvalidProblemError(
            f"{what}: {part} (the cases {', '.join(repr(c) for c in combo)}) has no load, so "
            f"there is nothing to analyse; this frame's loads are in the cases {cases} — pass "
            f"combination={example} to solve, constant=/variable= to trace (e.g. "
            f"variable={named[-1] if named else 'W'!r}), or add loads with case='variable'")
