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

from qpcontact.core.errors import InvalidOptionError, NoSolutionError, SolverFailedError
from qpcontact.core.results import PROVED
from qpcontact.judge.friction_certificate import (certify_friction, contact_scales, contact_sizes,
                                         scales_from_diagonal, sizes)

from ..mechanics import contact_lcp
from ..mechanics.equilibrium_checks import STATE_RTOL, equilibrium
from ..mechanics.load_combinations import load_combination
from ..mechanics.loads import describe
from ..mechanics.no_equilibrium import raise_rigid_motion
from ..mechanics.solving import solve_lcp
from .space_assembly import held, release_directions
from .space_recovery import resultant, space_result, support_keys
from .space_results import SpaceSupportResult

#: the contact models of a space frame's solve
CONES = ("faceted", "circular")
#: a contact's force or slip within this many times the certificate's error
#: of zero (on the contact's scale) is zero when its state is named
UNDECIDED = 10.0
#: a link's component in the friction problem's r (normal, then t1, t2)
_COMPONENT = {"n": 0, "t1": 1, "t2": 2}


def solve_either_cone(frame, p, method, accuracy, raise_on_failure, combination, _built,
                      options):
    """One combination on the cone ``options["cone"]`` asks for: "faceted"
    (the default: the LCP of the facets' polygon, solved as the plane
    frame's, :func:`..mechanics.solving.solve_lcp`) or "circular" (the
    module docstring)."""
    cone = options.pop("cone", "faceted")
    if cone not in CONES:
        raise InvalidOptionError(f"cone must be one of {', '.join(map(repr, CONES))}; "
                                 f"got {cone!r}")
    if cone == "faceted":
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
    from qpcontact.core.accuracy import resolve_accuracy

    _, tol = resolve_accuracy(accuracy)
    friction_methods = [n for n, m in registry().items() if m.family == "friction"]
    if method != "auto" and method not in friction_methods:
        raise InvalidOptionError(
            f"cone='circular' is solved by the friction methods: 'auto' or one of "
            f"{', '.join(map(repr, friction_methods))}; got {method!r} (Lemke solves the "
            "faceted cone: cone='faceted')")
    b = _built if _built is not None else frame.build()
    combo = load_combination(frame, p, combination, b)
    prob = frame.friction_problem(combination=combo, _built=b)
    sol = solve(prob, method=method, accuracy=accuracy, **options)
    if sol.r is None:
        before = f"circular cone, {sol.method}: {sol.message}"
        raise_rigid_motion(frame, b, combo, before)
        if sol.status in PROVED:
            raise NoSolutionError(f"frame under {describe(combo)}: no equilibrium exists "
                                  f"({before})")
        raise SolverFailedError(f"frame under {describe(combo)}: {before}; nothing was "
                                "proved either way")
    v = sol.v if sol.v is not None else prob.global_velocity(sol.r)
    res = circular_result(frame, prob, sol.r, v, b, combo,
                                f"circular cone ({sol.method})", tol)
    if not res.ok and raise_on_failure:
        raise SolverFailedError(f"frame: {res.message}")
    return res


def circular_result(frame, prob, r, v, b, combo, route, tol):
    """The frame's result for the friction problem's answer (r, v),
    checked (module docstring)."""
    r = np.asarray(r, float)
    factors = contact_lcp.factors(b, combo)
    F = b["F"] @ factors
    free, K, H = b["free"], b["K"], b["H"]
    u = b["U"] @ factors                        # settlements at the fixed dofs
    u[free] = np.asarray(v, float)[:free.size]  # beyond: elastic contacts' points
    X = np.array([r[3 * ci + _COMPONENT[kind]] for ci, kind in b["info"]])
    r_all = K @ u - F - H @ X
    reactions = {node: tuple(float(x) for x in r_all[b["idx"][node]:b["idx"][node] + 6])
                 for node in b["names"] if node in frame.fixed}
    ends = contact_lcp.member_end_actions(b, u, factors)
    ft = contact_lcp.force_terms(b, u, F, ends)
    # each contact's opening and slip from the frame's displacements
    normals, tangents, _ = release_directions(frame, b)
    Hc = np.stack([normals] + tangents, axis=2).reshape(u.size, -1)
    flex = np.repeat([0.0 if c.stiffness is None else 1.0 / c.stiffness
                      for c in frame.contacts], 3)
    gap = np.zeros(r.size)
    gap[0::3] = [c.gap for c in frame.contacts]
    local = Hc.T @ u + gap + flex * r
    if prob.is_reduced:
        cert = certify_friction(prob, r, u=local)
        rho = contact_scales(prob)
        size = contact_sizes(prob, r, rho)
    else:
        cert = certify_friction(prob, r, v)
        rho, size = _global_scales(prob, r, v)
    eq = max(equilibrium(frame, b, F, X, u), resultant(frame, b, F, X, r_all, u, ft))
    supports = circular_supports(frame, r, local, rho, size, cert.error)
    checked = (f"friction certificate {cert.error:.1e} (natural map "
               f"{cert.natural_map_error:.1e}, componentwise {cert.componentwise_error:.1e})")
    return space_result(frame, b, combo, u, ends, reactions, supports, eq, cert.error, checked,
                              route, tol)


def circular_supports(frame, r, local, rho, size, error) -> dict:
    """Each contact's state, forces, opening and slip, decided on the
    friction certificate's scales: contact i's force size s_i (its
    force, and ρ_i times the displacements its terms make) and ρ_i =
    1/W_nn,i, which turns its slip into a force.  A normal force or
    ρ_i|slip| below UNDECIDED x the certificate's error (at least
    STATE_RTOL) of s_i is zero: a sticking contact's residual is ρ_i|û_i|,
    so an answer certified to ε leaves slips up to ε s_i / ρ_i
    undecided."""
    R, L = r.reshape(-1, 3), local.reshape(-1, 3)
    undecided = max(STATE_RTOL, UNDECIDED * float(error))
    out = {}
    for ci, (key, c) in enumerate(zip(support_keys(frame), frame.contacts)):
        # a tangent the bilateral supports hold carries no friction (the
        # support's reaction does) and cannot slip, as with the facets
        is_held = [held(frame, c, t) for t in (c.t1, c.t2)]
        xt = np.where(is_held, 0.0, R[ci, 1:])
        slip = np.where(is_held, 0.0, L[ci, 1:])
        xn = float(R[ci, 0])
        if xn <= undecided * size[ci]:
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
