"""The stress suite's judge: each answer against the case's built-in one, by code
written here — never by :func:`qpcontact.certify`."""

from __future__ import annotations

import numpy as np

__all__ = ["judge", "judge_condition", "judge_rtol", "DIGIT_CAP", "forward_errors",
           "has_one_row_farkas", "DOUBT_WORDS"]


def _promised_scales(M, q, z_star) -> tuple[np.ndarray, np.ndarray]:
    """The scales on which qpcontact promises each component (docs/
    certificates.md), recomputed here from the planted answer by their
    definition, not by qpcontact.certify: ζ_j = min(cap, min_i σ_i / |M_ij|)
    over rows with data (σ = |q| + |M||z*|; cap = max(|z*|∞, |q|∞ / max|M|)),
    the change of z_j that moves some row by its own size; a row whose data
    are zero gets σ_i = Σ_j |M_ij| ζ_j.  A force of 1e-8 at an unloaded
    contact beside a gap of 4e10 is right on these scales."""
    A = np.abs(M.toarray() if hasattr(M, "toarray") else M)
    sig = np.abs(q) + A @ np.abs(z_star)
    idle = np.abs(q) == 0
    cap = max(float(np.abs(z_star).max()), float(np.abs(q).max()) / max(float(A.max()), 1e-300))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where((A > 0) & ~idle[:, None], sig[:, None] / A, np.inf)
    zeta = np.minimum(ratio.min(axis=0), cap)
    sig_idle = A @ np.where(np.isfinite(zeta), zeta, 0.0)
    return zeta, np.where(idle, np.maximum(sig, sig_idle), sig)


#: an ok answer promises at least one correct digit: whatever the judge's
#: own bound allows, no component may be off by more than this fraction of its
#: scale ("ok" with |z| 1e9 off by 66 % was once accepted)
DIGIT_CAP = 0.1


def _unique_scales(case):
    """The scales z and w are judged on: the planted magnitudes, their natural
    size where the data were scaled, and qpcontact's promised scales."""
    M, q = case.problem.M, case.problem.q
    zs, ws = case.scales()
    zeta, sigma = _promised_scales(M, q, case.z)
    return np.maximum(zs, zeta), np.maximum(ws, sigma)


def judge_condition(case, zs=None, ws=None) -> float:
    """The judge's own condition number of the reference answer, from the
    case data alone (NumPy, at the reference z*, not at the answer): how far,
    in units of its own scale, a component of z or w may move when every
    entry of M and q moves by a relative ε, divided by ε.  On the active
    set F = {z*_i > 0}: δz_F = M_FF⁻¹(δM z* + δq)_F, so |δz_F| <= ε v with
    v = |M_FF⁻¹| σ_F, σ = |q| + |M||z*|; and |δw_N| <= ε (|M_NF| v + σ_N).
    A singular or non-finite M_FF⁻¹ gives inf (no digit can be promised)."""
    M = case.problem.M
    M = np.asarray(M.toarray() if hasattr(M, "toarray") else M, float)
    q = case.problem.q
    if zs is None:
        zs, ws = _unique_scales(case)
    A = np.abs(M)
    sigma = np.abs(q) + A @ np.abs(case.z)
    F = case.z > 0
    # a degenerate pair (z*_i = w*_i = 0) may enter either side under a
    # perturbation: both active sets are measured (on the degenerate family
    # the first alone understated a backend's honest 1.7e-6 by 20 times)
    w_star = case.w if case.w is not None else M @ case.z + q
    degenerate = ~F & (np.abs(w_star) <= 1e-12 * ws)
    kappa = 1.0
    for active in ((F, F | degenerate) if degenerate.any() else (F,)):
        v = np.zeros(q.size)
        if active.any():
            try:
                with np.errstate(all="ignore"):
                    inv = np.linalg.inv(M[np.ix_(active, active)])
            except np.linalg.LinAlgError:
                return float("inf")
            if not np.all(np.isfinite(inv)):
                return float("inf")
            v[active] = np.abs(inv) @ sigma[active]
        with np.errstate(all="ignore"):
            dz = v[active] / zs[active]
            dw = (A[np.ix_(~active, active)] @ v[active] + sigma[~active]) / ws[~active]
        kappa = max(kappa, float(np.max(np.concatenate([dz, dw, [1.0]]))))
    return kappa if np.isfinite(kappa) else float("inf")


def judge_condition_w(case) -> float:
    """The judge's condition number of w alone, for cases where only w is
    determined (a PSD M singular on the active set: z is not unique, w is):
    δz_F = M_FF⁺(δM z* + δq)_F (the pseudo-inverse: any solution's change
    differs from it by a null vector, which leaves w alone), so |δw| <=
    ε (|M_:F| |M_FF⁺| σ_F + σ), in units of w's scales."""
    M = case.problem.M
    M = np.asarray(M.toarray() if hasattr(M, "toarray") else M, float)
    q = case.problem.q
    A = np.abs(M)
    sigma = np.abs(q) + A @ np.abs(case.z)
    _, ws = case.scales()
    F = case.z > 0
    spread = sigma.copy()
    if F.any():
        with np.errstate(all="ignore"):
            pinv = np.linalg.pinv(M[np.ix_(F, F)])
        if not np.all(np.isfinite(pinv)):
            return float("inf")
        spread += A[:, F] @ (np.abs(pinv) @ sigma[F])
    with np.errstate(all="ignore"):
        kappa = float(np.max(np.concatenate([spread / ws, [1.0]])))
    return kappa if np.isfinite(kappa) else float("inf")


def judge_rtol(case, tol: float) -> float:
    """How far an ok answer at tolerance ``tol`` may lie from the unique
    reference, as a fraction of each component's scale: 100 tol, or 10 times
    the judge's own condition times tol where that is larger — and never more
    than :data:`DIGIT_CAP`, since ok means correct digits."""
    kappa = judge_condition(case)
    return min(max(100 * tol, 10 * kappa * tol), DIGIT_CAP)


def _lcp_agrees(case, z, tol: float) -> bool:
    M, q = case.problem.M, case.problem.q
    z = np.asarray(z, float)
    if not np.all(np.isfinite(z)):
        return False
    w = np.asarray(M @ z).ravel() + q
    if case.z is not None and case.unique_z:
        zs, ws = _unique_scales(case)
        rtol = judge_rtol(case, tol)
        return bool(np.all(np.abs(z - case.z) <= rtol * zs) and np.all(np.abs(w - case.w) <= rtol * ws))
    rtol = 100 * tol
    if case.z is not None and case.unique_w:
        zs, ws = case.scales()
        rtol_w = min(max(rtol, 10 * judge_condition_w(case) * tol), DIGIT_CAP)
        return bool(np.all(np.abs(w - case.w) <= rtol_w * ws) and np.all(z >= -rtol * zs))
    # nothing determined: z >= 0, w >= 0, min(z_i, w_i) = 0, each pair on its
    # own scale (|q_i| + (|M||z|)_i for w_i; z's own magnitude for z_i)
    absM = abs(M) if hasattr(M, "tocsc") else np.abs(M)
    sig = np.abs(q) + np.asarray(absM @ np.abs(z)).ravel()
    # a row whose data are all (nearly) zero is judged on the others' scale
    sig = np.maximum(sig, 64 * np.finfo(float).eps * max(float(sig.max()), 1e-300))
    zs = max(float(np.abs(z).max()), 1e-300)
    zn, wn = z / zs, w / sig
    return bool(np.all(zn >= -rtol) and np.all(wn >= -rtol)
                and np.all(np.minimum(np.abs(zn), np.abs(wn)) <= rtol))


def _qp_agrees(case, x, rtol: float) -> bool:
    P, q, G, h, A, b, lb, ub = case.problem.unpack()
    x = np.asarray(x, float)
    f = 0.5 * x @ (P @ x) + q @ x
    scale = 0.5 * np.abs(x) @ (np.abs(P) @ np.abs(x)) + np.abs(q) @ np.abs(x)
    xs = case.x
    fscale = max(scale, 0.5 * np.abs(xs) @ (np.abs(P) @ np.abs(xs)) + np.abs(q) @ np.abs(xs), 1e-300)
    if abs(f - case.objective) > rtol * fscale:
        return False
    if G is not None and np.any(G @ x - h > rtol * (np.abs(G) @ np.abs(x) + np.abs(h))):
        return False
    if lb is not None:
        nz = np.abs(xs[xs != 0])
        floor = float(nz.min()) if nz.size else 1.0
        if np.any(lb - x > rtol * np.maximum(np.maximum(np.abs(lb), np.abs(xs)), floor)):
            return False
    return True


def judge(case, sol) -> tuple[str, str]:
    """(category, reason): ``sol`` judged against what ``case`` has built in."""
    from ...core.problems import LCP

    is_lcp = isinstance(case.problem, LCP)
    claimed = "solved" if sol.ok else (sol.status if sol.status in ("infeasible", "unbounded")
                                       else None)
    if sol.status == "time_limit":
        return "hung", sol.message[:120]
    if case.status in ("infeasible", "unbounded"):
        if claimed == case.status:
            return "proved", ""
        if claimed is not None:
            return "silent_wrong", f"claimed {claimed} on a {case.status} instance"
    elif case.status == "solved" and claimed in ("infeasible", "unbounded"):
        return "silent_wrong", f"claimed {claimed} on a solvable instance: {sol.message[:100]}"
    if sol.ok:
        if is_lcp:
            # tolerances from the case data only: an answer's own forward-error
            # estimate may be huge exactly where it has no digit
            good = _lcp_agrees(case, sol.z, sol.tol)
        else:
            good = _qp_agrees(case, sol.x, 1000 * sol.tol)
        return ("certified", "") if good else (
            "silent_wrong", f"certified (error {sol.error:.1e}) but disagrees with the known answer")
    # "ill_posed": not ok, said so — the honest answer where the
    # data are a rounding away from a problem without a solution
    if sol.status in ("inaccurate", "ill_posed", "max_pivots", "ray"):
        return "inaccurate", sol.status
    return "failed", sol.status


#: what an answer's message says where the data may have no solution
DOUBT_WORDS = ("may have no solution", "within rounding of a problem with no solution")


def forward_errors(case, sol) -> tuple[float, float]:
    """(true, estimated) forward error of an LCP answer on the certificate's
    scales — the truth against the unique reference (this judge's own
    recomputation of the scales ζ, σ at the answer, by their definition),
    the estimate the certificate's ``scale_forward_error``.  (nan, nan) where
    there is no unique reference or no estimate."""
    from ...core.problems import LCP

    nan = float("nan")
    cert = getattr(sol, "certificate", None)
    if (not isinstance(case.problem, LCP) or case.status != "solved" or not case.unique_z
            or case.z is None or sol.z is None or cert is None
            or not getattr(cert, "forward_error_known", False)):
        return nan, nan
    M, q = case.problem.M, case.problem.q
    z = np.asarray(sol.z, float)
    w = np.asarray(M @ z).ravel() + q
    zeta, sigma = _promised_scales(M, q, z)
    with np.errstate(all="ignore"):
        true = max(float(np.max(np.abs(z - case.z) / zeta)),
                   float(np.max(np.abs(w - case.w) / sigma)))
    return true, float(cert.scale_forward_error)


def has_one_row_farkas(case) -> bool:
    """Whether an LCP has a row i with every M_ij <= 0 and q_i < 0 (y = e_i
    is then an exact Farkas vector, read from the signs)."""
    from ...core.problems import LCP

    if not isinstance(case.problem, LCP):
        return False
    M = case.problem.M
    A = np.asarray(M.toarray() if hasattr(M, "toarray") else M)
    return bool(np.any((A.max(axis=1) <= 0) & (case.problem.q < 0)))
