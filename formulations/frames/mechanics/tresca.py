"""The Tresca fixed point for a frictional frame (``method="tresca"``): each
iteration the convex QP whose KKT system is the contact LCP with the
friction bounds f X_n frozen from the previous iterate, stopped on the full
LCP certificate and the frame's checks; Lemke, then the load path, where it
does not converge."""

from __future__ import annotations

import numpy as np

from qpcontact import solve as solve_problem
from qpcontact.core.errors import InvalidProblemError, NotConvexError
from qpcontact.core.options import check_options
from qpcontact.judge.lcp_certificate import certify_lcp

from . import contact_lcp
from .farkas_rounding import judge_proof
from .no_equilibrium import proved, raise_no_equilibrium
from .time_limits import out_of_time, seconds_left
from .tracing import trace_to


def tresca_fixed_point(frame, b, lcp, P, g, fric, combo, tol, accuracy, options, deadline):
    """Fixed point on Tresca bounds s = f X_n: each iteration the convex QP
    min ½(Pz-g)'R(Pz-g) + R_F'(Pz-g) + s'(Z⁺ + Z⁻), z >= 0 (its KKT system is
    the LCP with the bounds frozen); stopped when z solves the full LCP —
    all within ``deadline`` (:mod:`.time_limits`)."""
    from qpsolvers import Problem

    check_options("tresca", options, ("qp_method", "max_iter"))
    qp_method = options.get("qp_method", "auto")
    max_iter = int(options.get("max_iter", 50))
    R = b["R"]
    _, RF = contact_lcp.combine(b, combo)
    nc = len(frame.contacts)
    pos = contact_lcp.layout(b)
    H = tresca_matrix(P.T @ R @ P, b)
    base = P.T @ (RF - R @ g)
    xn = np.zeros(nc)
    for it in range(max_iter):
        if deadline.expired():
            break
        s = np.zeros(P.shape[1])
        for k, ci in enumerate(fric):
            s[nc + 2 * k] = s[nc + 2 * k + 1] = frame.contacts[ci].friction * max(xn[ci], 0.0)
        try:
            sol = solve_problem(Problem(H, base + s, lb=np.zeros(H.shape[0])), method=qp_method,
                                accuracy=accuracy, time_limit=seconds_left(deadline))
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
        if certify_lcp(lcp, z).ok(tol) and frame.kind.result_from_z(frame, z, combo, "", b=b,
                                                                    lcp=lcp, tol=tol).ok:
            return z, f"tresca fixed point ({sol.method}, {it + 1} iterations)"
        X = R @ (P @ z - g) + RF
        xn = np.array([X[pos[ci]["n"]] for ci in range(nc)])
    out_of_time(frame, combo, deadline, "the Tresca fixed point did not converge")
    sol = solve_problem(lcp, method="lemke", accuracy=accuracy, time_limit=seconds_left(deadline))
    judge_proof(sol, b, combo)
    if sol.ok:
        return sol.z, f"lemke (Tresca fixed point did not converge in {max_iter} iterations)"
    found = None if proved(sol) else trace_to(frame, b, combo, lcp, accuracy, tol, deadline)
    if found is None:
        out_of_time(frame, combo, deadline, f"{sol.method}: {sol.message}")
        raise_no_equilibrium(frame, sol, fric, b, combo)
    return found[0], f"{found[1]} (Tresca fixed point did not converge in {max_iter} iterations)"


def tresca_matrix(H, b):
    """The Tresca QP's Hessian P'RP, symmetric and convex to rounding.

    R is a stiffness, so P'RP is positive semidefinite in exact arithmetic;
    its computed copy is known only to R_ROUNDING x kappa per entry
    (contact_lcp.contact_stiffness), and on a ground beam resting on 31 elastic frictional
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
    rounding = 4.0 * n * contact_lcp.R_ROUNDING * b["kappa"] / d2.min()
    if -lam > rounding:
        raise InvalidProblemError(
            f"frame: the contact stiffness matrix seen by the Tresca fixed point is not "
            f"positive semidefinite (eigenvalue {lam:.2g} of its diagonal scaling, beyond its "
            f"rounding {rounding:.1g}): a stiffness cannot do that, so the model is "
            "ill-conditioned to the point of nonsense — check the units and the stiffness "
            "ratios (very stiff members on very soft supports); method='lemke' or 'auto' "
            "does not need a convex QP")
    return H + (-lam + 20.0 * n * np.finfo(float).eps) * np.diag(d2)
