"""Space frames with the true circular Coulomb cone |X_t| <= f X_n: the
contact problem solved by the friction solvers and its answer given back as a
:class:`~.space_results.SpaceFrameResult`, checked from the data.

``SpaceFrame.solve(..., cone="circular")`` hands the frame's friction problem
(:meth:`~.solving.FrameSolving.friction_problem`: K v = H r + f, u = Hᵀ v +
w, r = (X_n, X_t1, X_t2) per contact, elastic contacts as springs to contact
points of their own) to :func:`qpcontact.solve` with the method asked
("auto": De Saxcé's fixed point of SOCPs, then semismooth Newton, ...; a
frame that is a mechanism without its contacts is solved in global form by
De Saxcé's SOCPs in the displacements).  The displacements are the global
velocity v (the free dofs; settlements at the fixed ones), the contact
forces are r; everything else — member end actions, reactions, the contact
states — is rebuilt from them as for the faceted cone, and ``ok`` is decided
by two independent checks at the requested accuracy:

* the friction certificate (:func:`qpcontact.judge.friction_certificate.certify_friction`:
  Siconos's natural-map error and each contact's residual on its own force
  scale) of r with the contact displacements computed from the frame's own
  displacements, opening = gap + n·u + X_n/k and slip = (t1·u, t2·u) + X_t/k;
* the frame's equilibrium, dof by dof and of the whole frame (the checks of
  the faceted cone's results).

A contact's state: separated when X_n is zero on its force scale (the forces
that meet at its node); slipping when its slip is nonzero on its length
scale (|n|ᵀ|u| + |t|ᵀ|u| + the gap + the spring's part) beyond what the
certificate's error leaves undecided; else sticking ("closed" without
friction).  Where no equilibrium exists the frame's rigid-motion proof names
the motion (its cone test a >= f(|s1| + |s2|) is stricter than the circular
cone's a >= f|s|, so what it proves holds for the circular cone too); failing that, the
friction problem's own proof (its ray, checked from the data) is reported as
it is — a ray may mix lifting and sliding at a contact, so it is not read
as words.
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import (InvalidOptionError, NoSolutionError, QpcontactError,
                                   SolverFailedError)
from qpcontact.core.accuracy import resolve_accuracy
from qpcontact.core.results import PROVED
from qpcontact.dispatch.context import RunContext
from qpcontact.dispatch.driver import Engine
from qpcontact.judge.friction_certificate import (certify_friction, contact_scales, contact_sizes,
                                         scales_from_diagonal, sizes)

from ..mechanics import contact_lcp
from ..mechanics.equilibrium_checks import STATE_RTOL, equilibrium
from ..mechanics.member_forces import stiffness_times
from ..mechanics.load_combinations import load_combination
from ..mechanics.loads import describe, support_keys
from ..mechanics.no_equilibrium import motion_words, raise_rigid_motion
from ..mechanics.solving import solve_lcp
from ..mechanics.time_limits import TIME_LIMIT, deadline_of, seconds_left
from .space_assembly import held, release_directions
from .circular_limit import prove_no_equilibrium
from .circular_polish import solve_on_states
from .space_recovery import as_reported, global_reactions, resultant, space_result
from .space_results import SpaceSupportResult

#: a contact's force or slip within this many times the certificate's error
#: of zero (on the contact's scale) is zero when its state is named
UNDECIDED = 10.0
#: a link's component in the friction problem's r (normal, then t1, t2)
_COMPONENT = {"n": 0, "t1": 1, "t2": 2}


def solve_either_cone(frame, p, method, accuracy, raise_on_failure, combination, _built,
                      options):
    """One combination on the frame's cone (``frame.cone``): "circular"
    (the module docstring) or a polygon, "inscribed" or "circumscribed"
    (the LCP of the facets, solved as the plane frame's:
    :func:`..mechanics.solving.solve_lcp`)."""
    if "cone" in options:
        raise InvalidOptionError(
            f"cone={options['cone']!r}: the friction cone is the frame's model, not a solve "
            "option: SpaceFrame(cone=...) or frame.cone = \"circular\" | \"inscribed\" | "
            "\"circumscribed\"")
    if frame.cone != "circular":
        return solve_lcp(frame, p, method, accuracy, raise_on_failure, combination, _built,
                         options)
    return solve_circular(frame, p, method, accuracy, raise_on_failure, combination, _built,
                          options)


def solve_circular(frame, p, method, accuracy, raise_on_failure, combination, _built,
                   options):
    """One combination on the circular cone, by the friction solvers (the
    module docstring)."""
    from qpcontact import methods as registry
    from qpcontact import solve

    _, tol = resolve_accuracy(accuracy)
    friction_methods = [n for n, m in registry().items() if m.family == "friction"]
    if method != "auto" and method not in friction_methods:
        raise InvalidOptionError(
            f"cone='circular' is solved by the friction methods: 'auto' or one of "
            f"{', '.join(map(repr, friction_methods))}; got {method!r} (Lemke solves a "
            "polygon: frame.cone = 'inscribed' or 'circumscribed')")
    b = _built if _built is not None else frame.build()
    combo = load_combination(frame, p, combination, b)
    prob = frame.friction_problem(combination=combo, _built=b)
    tried = None
    options = dict(options)
    # the call's wall-time limit is the friction solvers'; it is not a
    # method's setting that would replace the polygon's start
    limit = {"time_limit": seconds_left(deadline_of(options))}
    if method == "auto" and not options:
        # first the faceted cone's exact answer (Lemke on the circumscribed
        # polygon) carried to the circle by the active set: on the 16-pad
        # tower 2 s, where De Saxcé's SOCPs take 15 s
        tried = from_polygon(frame, prob, b, combo, accuracy, tol)
        if tried is not None and tried.ok:
            return tried
    sol = solve(prob, method=method, accuracy=accuracy, **limit, **options)
    res = None
    if sol.r is None:
        before = f"circular cone, {sol.method}: {sol.message}"
        raise_rigid_motion(frame, b, combo, before)
        if sol.status in PROVED:
            raise NoSolutionError(f"frame under {describe(combo)}: no equilibrium exists "
                                  f"({before})")
    else:
        v = sol.v if sol.v is not None else prob.global_velocity(sol.r)
        res = circular_result(frame, prob, sol.r, v, b, combo,
                              f"circular cone ({sol.method})", tol)
    if (res is None or not res.ok) and method != "auto":
        tried = from_polygon(frame, prob, b, combo, accuracy, tol)
    if tried is not None and (tried.ok or res is None):
        res = tried
    if res is None or not res.ok:
        # no answer passed: where the loads exceed what forces within the
        # circles can carry, a rigid motion checked in rationals proves it
        proof = prove_no_equilibrium(frame, b, combo)
        if proof is not None:
            carrying = list(support_keys(frame))
            raise NoSolutionError(
                f"frame under {describe(combo)}: no equilibrium exists — "
                f"{motion_words(frame, proof['opening'], proof['sliding'], carrying)}"
                f"{proof['turn']} (proved by a rigid motion of the whole frame in which the "
                "loads do positive work and no contact force within Coulomb's circles "
                "resists, checked in rational arithmetic)")
    if res is None:
        raise SolverFailedError(f"frame under {describe(combo)}: {before}; the active set on "
                                "the circle from the polygon's answer did not settle either; "
                                "nothing was proved either way")
    if not res.ok and raise_on_failure:
        raise SolverFailedError(f"frame: {res.message}")
    return res


def circular_result(frame, prob, r, v, b, combo, route, tol):
    """The frame's result for the friction problem's answer (r, v),
    checked (module docstring); always refined on its states in extended
    precision (:mod:`.circular_polish`), the refined answer kept if it
    checks at least as well."""
    r = np.asarray(r, float)
    factors = contact_lcp.factors(b, combo)
    u = b["U"] @ factors                        # settlements at the fixed dofs
    u[b["free"]] = np.asarray(v, float)[:b["free"].size]  # beyond: elastic contacts' points
    res, supports = judged(frame, prob, b, combo, u, r, None, route, tol)
    # refined even where it passes: a solver's answer certified to 1e-9
    # may carry 2e-9 in a displacement, which the states' system removes
    again = on_states(frame, prob, b, combo, u, r, [s.state for s in supports.values()],
                      route, tol)
    if again is not None and again.lcp_error <= max(res.lcp_error, tol) and (
            again.equilibrium_residual <= res.equilibrium_residual or not res.ok):
        return again
    return res


def on_states(frame, prob, b, combo, u, r, states, route, tol):
    """The checked result of the active set on the circle
    (:func:`.circular_polish.solve_on_states`) started from (u, r) on
    ``states``; None where it does not settle."""
    F, Hc, gap, flex, mu = contact_data(frame, b, combo)
    held_t = [[held(frame, c, t) for t in (c.t1, c.t2)] for c in frame.contacts]
    out = solve_on_states(b, F, u, r, Hc, gap, flex, mu, states, held_t)
    if out is None:
        return None
    u2, r2, _ = out
    return judged(frame, prob, b, combo, u2.astype(float), r2.astype(float),
                    stiffness_times(b, u2), route, tol)[0]


def from_polygon(frame, prob, b, combo, accuracy, tol, method="auto"):
    """The active set on the circle started from the polygon's answer
    (:func:`polygon_start`), checked; None where there is none."""
    start = polygon_start(frame, b, combo, accuracy, method)
    if start is None:
        return None
    return on_states(frame, prob, b, combo, *start, "circular cone (active set on the "
                     "circle from the polygon's exact answer)", tol)


def polygon_start(frame, b, combo, accuracy, method="auto"):
    """(u, r, states) of the faceted cone's answer for ``combo`` (the
    circumscribed polygon the assembly lays out), or None where it gives
    none: with ``method`` "auto" the frame's polygon solve (Lemke, then the
    load path); with "lemke" Lemke's answer alone, as a probe — no search
    for a proof that the polygon has none, which the circle's callers do
    not use (55 searches, a quarter of the 16-pad tower's trace)."""
    try:
        M, Q, q_gap, *_ = contact_lcp.lcp_matrices(b)
        lcp = contact_lcp.combination_lcp(M, Q, q_gap, b, combo)
        sol = Engine(RunContext.start(accuracy)).solve(lcp, "lemke", prove=False)
        res = None
        if sol.z is not None and np.all(np.isfinite(sol.z)):
            # judged as "auto" judges it (its tolerance); the probe alone as before
            tol = {} if method == "lemke" else {"tol": resolve_accuracy(accuracy)[1]}
            res = frame.kind.result_from_z(frame, sol.z, combo, "lemke", b=b, lcp=lcp, **tol)
    except QpcontactError:
        res = None
    if method != "lemke" and (res is None or not res.ok):
        # "auto" where Lemke's point alone is no checked answer: the
        # polygon's whole solve (the load path, a proof that it has none).
        # Where it is one, "auto" would return that same point, after a
        # search for a proof that the polygon has no solution (half the
        # 10-storey tower's solve), whose outcome a start does not use
        try:
            res = solve_lcp(frame, 1.0, method, accuracy, False, combo, b,
                            {"time_limit": TIME_LIMIT})
        except QpcontactError:
            return None
    if res is None or res._u is None:
        return None
    return (contact_lcp.to_nodes(b, res._u), contact_forces(res),
            [s.state for s in res.supports.values()])


def contact_forces(res) -> np.ndarray:
    """A result's contact forces as the friction problem's r: (X_n, X_t1,
    X_t2) per contact."""
    return np.concatenate([[s.normal, *s.tangential] for s in res.supports.values()])


def contact_data(frame, b, combo):
    """(F, H_c, gap, 1/k, f): the loads and, per contact component (n, t1,
    t2), the directions over the dofs, gaps and flexibilities; f per
    contact."""
    F = b["F"] @ contact_lcp.factors(b, combo)
    normals, tangents, mu = release_directions(frame, b)
    Hc = np.stack([normals] + tangents, axis=2).reshape(F.size, -1)
    flex = np.repeat([0.0 if c.stiffness is None else 1.0 / c.stiffness
                      for c in frame.contacts], 3)
    gap = np.zeros(Hc.shape[1])
    gap[0::3] = [c.gap for c in frame.contacts]
    return F, Hc, gap, flex, mu


def judged(frame, prob, b, combo, u, r, Ku, route, tol):
    """(result, supports): the answer (u, r) judged as it is — the friction
    certificate and the frame's equilibrium; ``Ku`` the extended-precision
    K u where the answer was refined (the reactions then come from it)."""
    F, Hc, gap, flex, _ = contact_data(frame, b, combo)
    factors = contact_lcp.factors(b, combo)
    X = np.array([r[3 * ci + _COMPONENT[kind]] for ci, kind in b["info"]])
    if Ku is None:
        r_all = b["K"] @ u - F - b["H"] @ X
    else:
        r_all = np.asarray(Ku - np.asarray(F, Ku.dtype)
                           - b["H"].astype(Ku.dtype) @ np.asarray(X, Ku.dtype), float)
    reactions = global_reactions(frame, b, r_all)
    ends = contact_lcp.member_end_actions(b, contact_lcp.to_global(b, u), factors)
    ft = contact_lcp.force_terms(b, u, F, ends)
    # each contact's opening and slip from the frame's displacements
    local = Hc.T @ u + gap + flex * r
    if prob.is_reduced:
        cert = certify_friction(prob, r, u=local)
        rho = contact_scales(prob)
        size = contact_sizes(prob, r, rho)
    else:
        # the global unknowns: the free dofs, then the elastic contacts'
        # own points (contact_springs: each at its node's motion plus r/k)
        v = np.r_[u[b["free"]], (Hc.T @ u + flex * r)[flex > 0]]
        cert = certify_friction(prob, r, v)
        rho, size = _global_scales(prob, r, v)
    eq = max(equilibrium(frame, b, F, X, u), resultant(frame, b, F, X, r_all, u, ft))
    supports = circular_supports(frame, r, local, rho, size, cert.error)
    off, where = as_reported(frame, b, F, u, X, r_all, supports, ends, tol)
    checked = (f"friction certificate {cert.error:.1e} (natural map "
               f"{cert.natural_map_error:.1e}, componentwise {cert.componentwise_error:.1e})")
    res = space_result(frame, b, combo, u, ends, reactions, supports, max(eq, off), cert.error,
                       checked, route, tol, where)
    return res, supports


def circular_supports(frame, r, local, rho, size, error) -> dict:
    """Each contact's state, forces, opening and slip, decided on the
    friction certificate's scales: contact i's force size s_i (its
    force, and ρ_i times the displacements its terms make) and ρ_i =
    1/W_nn,i, which turns its slip into a force.  A normal force or
    ρ_i|slip| below UNDECIDED x the certificate's error (at least
    STATE_RTOL) of s_i is zero: a sticking contact's residual is ρ_i|û_i|,
    so an answer certified to ε leaves slips up to ε s_i / ρ_i
    undecided.  A normal force is zero below UNDECIDED x the error only
    (at least rounding, R_ROUNDING): s_i holds ρ_i times the frame's
    motion, and a table tipping about two legs (turned 0.1 rad) had the
    other two legs' 5e-6 kN, certified to 2e-11, named separated below
    STATE_RTOL s_i = 1e-4 kN and its pads' forces reported 1e-5 kN short
    of its weight."""
    R, L = r.reshape(-1, 3), local.reshape(-1, 3)
    undecided = max(STATE_RTOL, UNDECIDED * float(error))
    unloaded = max(contact_lcp.R_ROUNDING, UNDECIDED * float(error))
    out = {}
    for ci, (key, c) in enumerate(zip(support_keys(frame), frame.contacts)):
        # a tangent the bilateral supports hold carries no friction (the
        # support's reaction does) and cannot slip, as with the facets
        is_held = [held(frame, c, t) for t in (c.t1, c.t2)]
        xt = np.where(is_held, 0.0, R[ci, 1:])
        slip = np.where(is_held, 0.0, L[ci, 1:])
        xn = float(R[ci, 0])
        if xn <= unloaded * size[ci]:
            state, xn, xt = "separated", 0.0, np.zeros(2)
        elif c.friction == 0:
            state = "closed"
        elif rho[ci] * np.linalg.norm(slip) > undecided * size[ci]:
            state = "slip"
        else:
            state = "stick"
        out[key] = SpaceSupportResult(state, xn, xt, float(L[ci, 0]), slip, t1=c.t1,
                                      t2=c.t2)
    return out


def _global_scales(prob, r, v):
    """(ρ, s) per contact for a global problem kept without W, as its
    certificate takes them (:func:`~qpcontact.judge.friction_certificate.global_errors`):
    W_nn estimated by Hᵀ diag(M)⁻¹ H, the displacements' terms |H|ᵀ|v|."""
    g = prob.global_data
    dm = np.asarray(g["M"].diagonal(), float)
    inv = np.where(dm > 0, 1.0 / np.where(dm > 0, dm, 1.0), 0.0)
    rho = scales_from_diagonal(np.asarray(g["H"].multiply(g["H"]).T @ inv).ravel()[0::3])
    return rho, sizes(r, rho, g["w"], np.asarray(abs(g["H"]).T @ np.abs(v)).ravel(), 3)
