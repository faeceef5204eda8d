r"""Mechanisms with unilateral constraints: the penalty QP of one integration
step (the penalty paper: Nikolsky, Kopylov, Romanenko & Kudryashov 2012).

Units: SI.  Generalized coordinates q (m or rad), inertia G (kg, kg·m²),
generalized forces Q (N, N·m), contact reactions λ (N), Jacobian J of the
constraint functions Φ(q) >= 0 (Φ in m), accelerations in m/s² (rad/s²);
A = J G⁻¹ J' [1/kg], b [m/s²], compliance C [m/N], P_y [N], penalty μ [s²]
(so that μ λ'(Aλ + b) is an energy, like ½λ'Cλ).

Derivation
----------
Equations of motion with contact reactions (the paper's eq. 1):

    G q̈ = Q + J'λ          =>   q̈ = G⁻¹ (J'λ + Q).

The constraint accelerations are Φ̈ = J q̈ + D, with D_k = q̇' ∇²Φ_k q̇.  With a
look-ahead time Δt, Φ(t + Δt) ≈ Φ + Δt Φ̇ + ½Δt² Φ̈ >= 0 reads Φ̈ + B >= 0 with
B = (2/Δt²)(Φ + Δt Φ̇) (the paper's B, reconstructed).  Substituting q̈:

    w = A λ + b >= 0,   λ >= 0,   λ'w = 0,
    A = J G⁻¹ J'  (symmetric PSD),   b = B + J G⁻¹ Q + D,

a linear complementarity problem in the reactions: the **exact reference**
(:func:`exact_lcp`), solved by the pivoting methods.  The paper's original problem
minimises ½λ'Cλ + P_y'Cλ over the complementary feasible λ (C the symmetric
positive definite matrix of contact influence coefficients); when A is
positive definite that set is the single LCP solution.

**Penalty QP** (the paper's eqs. 7-10): move the nonlinear complementarity product
into the objective with a weight μ > 0,

    minimise   ½ λ'Wλ + (C P_y + μ b)'λ,    W = C + 2μA,
    subject to A λ >= -b,  λ >= 0,

i.e. the original objective plus μ λ'(Aλ + b) >= 0.  W is positive definite
for μ > 0, so the QP is convex with one minimiser.

**When is it exact?**  Let λ* solve the LCP with strict complementarity,
B = {λ*_i > 0}, F = the rest, w* = Aλ* + b.  Take the QP multipliers
ν = μλ* + ν' (for Aλ >= -b) and η (for λ >= 0).  Stationarity
Wλ* + CP_y + μb - A'ν - η = 0 reduces, because A is symmetric, to
C(λ* + P_y) + μ w* - A'ν' - η = 0.  With ν'_B from A_BB ν'_B = [C(λ* + P_y)]_B
and ν'_F = 0, η_B = 0, the remaining conditions ν_B >= 0 and η_F >= 0 hold iff

    μ >= μ* = max( max_{i∈B} -ν'_i / λ*_i ,
                   max_{i∈F} ([A_FB ν'_B - C(λ* + P_y)]_i) / w*_i ).

So for μ > μ* the penalty QP's minimiser *is* λ* (an exact penalty), and for
μ < μ* it is not (:func:`mu_threshold` computes μ* from the exact solution).
Beyond that, nothing improves with μ: cond(W) grows like μ‖A‖/λ_min(C) when A
is singular (more contacts than degrees of freedom), and the backends'
tolerances, which are absolute, lose meaning against μb.  See docs/penalty.md
for the measured window.

**Rigid contacts** (effect ``compliance`` not named): C = ε I with
ε = REGULARIZATION · max|A| (documented: 1e-9), or solve the exact LCP.

Gauss' principle (rigid case): q̈ minimises ½(q̈ - q̈_free)'G(q̈ - q̈_free) subject
to J q̈ + D + B >= 0, with multipliers λ (:func:`gauss_qp`).

The bottom of the mechanisms' stack: stepping, mechanisms and
multibody.contacts build on this module and it imports none of them
(:mod:`formulations.mechanisms.penalty`, the formulation's front, sits on top).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from qpsolvers import Problem

from qpcontact import solve
from qpcontact.core.errors import InvalidOptionError, InvalidProblemError, NotConvexError
from qpcontact.core.matrices import MatrixStructure, as_matrix, as_vector
from qpcontact.core.problems import LCP
from qpcontact.judge.lcp_certificate import certify_lcp

__all__ = ["PenaltyStep", "PenaltyResult", "penalty_qp", "step_penalty_qp", "exact_lcp",
           "gauss_qp", "mu_threshold", "solve_penalty", "REGULARIZATION", "MU_SINGULAR_COND"]

#: Rigid contacts: C = REGULARIZATION * max|A| * I keeps W positive definite
#: while changing the objective by a relative 1e-9.
REGULARIZATION = 1e-9

#: cond(W) above this flags W as numerically singular (1 / (100 eps)).
MU_SINGULAR_COND = 1.0 / (100 * np.finfo(float).eps)


def _spd(M, name: str):
    """Validate a symmetric positive definite matrix with the engine's shared
    structure checks (symmetry to SYMMETRY_RTOL, Cholesky pivots above the
    rounding floor; sparse matrices stay sparse); errors name it."""
    M = as_matrix(M, name)
    if M.shape[0] != M.shape[1]:
        raise InvalidProblemError(f"{name} must be square; got shape {M.shape}")
    st = MatrixStructure(M)
    if not st.is_symmetric:
        raise NotConvexError(f"{name} must be symmetric (max|{name} - {name}'| = {st.asymmetry:.3g})")
    if not st.is_positive_definite:
        raise NotConvexError(f"{name} must be positive definite; its Cholesky factorization "
                             "failed or has pivots at rounding level")
    return M


class PenaltyStep:
    """The data of one integration step, validated, with G factorized once.

    Parameters (SI, see the module docstring): G (n x n SPD, dense or sparse,
    or a factorized operator with ``shape``, ``solve(r)`` = G⁻¹r and
    ``toarray()``, such as multibody.MassOperator: G⁻¹ is then never formed),
    Q (n), J (ν x n), B (ν), D (ν), C (ν x ν SPD, or None for rigid contacts),
    P_y (ν, default 0).
    """

    def __init__(self, G, Q, J, B, D=None, C=None, P_y=None):
        operator = hasattr(G, "solve") and hasattr(G, "shape") and hasattr(G, "toarray")
        self.G = G if operator else _spd(G, "G")
        n = self.G.shape[0]
        self.Q = as_vector(Q, n, "Q")
        J = as_matrix(J, "J")
        if J.ndim != 2 or J.shape[1] != n:
            raise InvalidProblemError(f"J must have shape (ν, {n}) to match G; got {J.shape}")
        self.J = J.toarray() if sp.issparse(J) else J
        nu = self.J.shape[0]
        self.B = as_vector(B, nu, "B")
        self.D = np.zeros(nu) if D is None else as_vector(D, nu, "D")
        self.rigid = C is None
        self.P_y = np.zeros(nu) if P_y is None else as_vector(P_y, nu, "P_y")
        if operator:
            self._solve = self.G.solve   # the operator's factorization checks definiteness
        elif sp.issparse(self.G):
            lu = spla.splu(sp.csc_matrix(self.G))
            self._solve = lu.solve
        else:
            cf = scipy.linalg.cho_factor(self.G, check_finite=False)
            self._solve = lambda r: scipy.linalg.cho_solve(cf, r, check_finite=False)
        GinvJt = self._solve(np.ascontiguousarray(self.J.T)) if nu else np.zeros((n, 0))
        A = self.J @ GinvJt
        self.A = 0.5 * (A + A.T)
        self.q_free = self._solve(self.Q)  # G⁻¹Q [m/s²]
        self.b = self.B + self.J @ self.q_free + self.D
        if self.rigid:
            eps = REGULARIZATION * max(float(np.max(np.abs(self.A))) if nu else 1.0, 1e-300)
            self.C = eps * np.eye(nu)
        else:
            C = _spd(C, "C")
            self.C = C.toarray() if sp.issparse(C) else np.asarray(C, float)
            if self.C.shape != (nu, nu):
                raise InvalidProblemError(f"C must be ({nu}, {nu}) to match J; got {self.C.shape}")

    @property
    def n(self) -> int:
        return self.G.shape[0]

    @property
    def nu(self) -> int:
        return self.J.shape[0]

    def accelerations(self, lam) -> np.ndarray:
        """q̈ = G⁻¹(J'λ + Q) [m/s², rad/s²]."""
        return self._solve(self.J.T @ np.asarray(lam, float) + self.Q)


def penalty_qp(G, Q, J, C, B, D, P_y, mu) -> Problem:
    """The penalty QP (Nikolsky et al. 2012) of one step as a ``qpsolvers.Problem`` in λ [N]:
    min ½λ'(C + 2μA)λ + (C P_y + μ b)'λ  s.t.  -Aλ <= b, λ >= 0.
    ``C=None`` means rigid contacts (regularized, see REGULARIZATION)."""
    return step_penalty_qp(PenaltyStep(G, Q, J, B, D, C, P_y), mu)


def step_penalty_qp(step: PenaltyStep, mu: float) -> Problem:
    """:func:`penalty_qp` of a validated :class:`PenaltyStep`."""
    if not (np.isfinite(mu) and mu > 0):
        raise InvalidOptionError(f"the penalty mu must be a positive finite number; got {mu}")
    W = step.C + 2.0 * mu * step.A
    W = 0.5 * (W + W.T)
    c = step.C @ step.P_y + mu * step.b
    return Problem(W, c, -step.A, step.b.copy(), lb=np.zeros(step.nu))


def exact_lcp(step: PenaltyStep) -> LCP:
    """The exact reference: w = Aλ + b >= 0, λ >= 0, λ'w = 0."""
    return LCP(step.A, step.b)


def gauss_qp(step: PenaltyStep) -> Problem:
    """Gauss' principle (rigid case): min ½(a - a_free)'G(a - a_free) s.t.
    J a + D + B >= 0, in the accelerations a; its multipliers are λ."""
    G = step.G.toarray() if hasattr(step.G, "toarray") else step.G
    return Problem(G, -(G @ step.q_free), -step.J, step.B + step.D)


def mu_threshold(step: PenaltyStep, lam: np.ndarray, w: np.ndarray | None = None,
                 tol: float = 1e-12) -> float:
    """μ* of the module docstring: above it the penalty QP's minimiser is the
    LCP solution ``lam``.  inf when the solution is degenerate (some λ_i = w_i
    = 0) or A_BB is singular — the KKT argument then gives no finite bound."""
    lam = np.asarray(lam, float)
    w = step.A @ lam + step.b if w is None else w
    scale_l = max(np.max(np.abs(lam), initial=0.0), 1e-300)
    scale_w = max(np.max(np.abs(w), initial=0.0), np.max(np.abs(step.b), initial=0.0), 1e-300)
    Bset = lam > tol * scale_l
    Fset = ~Bset
    if np.any(Fset & (w <= tol * scale_w)):
        return np.inf
    r = step.C @ (lam + step.P_y)
    nu_B = np.zeros(0)
    if Bset.any():
        try:
            nu_B = np.linalg.solve(step.A[np.ix_(Bset, Bset)], r[Bset])
        except np.linalg.LinAlgError:
            return np.inf
    bounds = [0.0]
    if Bset.any():
        bounds.append(float(np.max(-nu_B / lam[Bset])))
    if Fset.any():
        eta = step.A[np.ix_(Fset, Bset)] @ nu_B - r[Fset] if Bset.any() else -r[Fset]
        bounds.append(float(np.max(eta / w[Fset])))
    return max(bounds)


@dataclass
class PenaltyResult:
    """Reactions λ [N] and accelerations q̈ of one step, with what proves them.

    ``status`` is "solved" when λ solves the exact LCP (``lcp_certificate``) at
    the requested accuracy; "inaccurate" otherwise — whatever the QP backend
    said.  ``flags`` name what went wrong (W numerically singular, μ below the
    window, backend failure).  ``mu`` is the penalty used (the last tried when
    chosen automatically); ``mu_tried`` the sequence.
    """

    lam: np.ndarray | None
    accelerations: np.ndarray | None
    mu: float
    status: str
    ok: bool
    message: str
    lcp_certificate: object
    qp_solution: object
    cond_W: float
    flags: list = field(default_factory=list)
    mu_tried: list = field(default_factory=list)


def _cond(W: np.ndarray) -> float:
    try:
        return float(np.linalg.cond(W))
    except np.linalg.LinAlgError:
        return np.inf


def _one(step: PenaltyStep, mu: float, method: str, accuracy, tol: float, options) -> PenaltyResult:
    qp = step_penalty_qp(step, mu)
    cond = _cond(qp.P)
    flags = []
    if cond > MU_SINGULAR_COND:
        flags.append(f"W = C + 2 mu A is numerically singular (cond {cond:.1e} > "
                     f"{MU_SINGULAR_COND:.1e}): mu = {mu:.3g} is too large for double precision")
    sol = solve(qp, method=method, accuracy=accuracy, **options)
    lam = None if sol.x is None else np.maximum(sol.x, 0.0)
    cert = certify_lcp(exact_lcp(step), lam) if lam is not None else None
    ok = cert is not None and cert.ok(tol)
    if lam is None:
        flags.append(f"the QP backend returned no point ({sol.message})")
    elif not ok:
        flags.append(f"lambda is not the mechanics solution: LCP error {cert.error:.2e} > {tol:.0e}"
                     + ("" if sol.ok else f" (and the QP itself was not solved: {sol.message})"))
    msg = (f"certified against the exact LCP: error {cert.error:.2e} <= {tol:.0e}"
           + "".join(f"; note: {f}" for f in flags) if ok else "; ".join(flags))
    return PenaltyResult(lam=lam, accelerations=None if lam is None else step.accelerations(lam),
                         mu=mu, status="solved" if ok else "inaccurate", ok=ok, message=msg,
                         lcp_certificate=cert, qp_solution=sol, cond_W=cond, flags=flags,
                         mu_tried=[mu])


def solve_penalty(step: PenaltyStep, mu="auto", *, method: str = "auto", accuracy="high",
                  mu_start: float | None = None, mu_factor: float = 10.0, mu_max: float = 1e20,
                  **options) -> PenaltyResult:
    """Solve one step's penalty QP with a registered method and certify λ
    against the exact LCP.

    ``mu="auto"``: start at the balance point μ₀ = max|C| / (2 max|A|) (or
    ``mu_start``) and multiply by ``mu_factor`` until λ is certified as the
    LCP's solution and its active set did not change from the previous μ.  The
    result reports the μ chosen and the ones tried; if no μ up to ``mu_max``
    works (W numerically singular first, or a backend that cannot reach the
    accuracy) the result is flagged, never silently wrong.
    """
    from qpcontact.core.accuracy import resolve_accuracy

    _, tol = resolve_accuracy(accuracy)
    if step.nu == 0:
        a = step.accelerations(np.zeros(0))
        return PenaltyResult(np.zeros(0), a, 0.0, "solved", True, "no constraints", None, None,
                             1.0, [], [])
    if mu != "auto":
        return _one(step, float(mu), method, accuracy, tol, options)
    a_scale = float(np.max(np.abs(step.A)))
    if a_scale == 0:
        raise InvalidProblemError("A = J G⁻¹ J' is zero: the constraints do not involve any "
                                  "degree of freedom")
    mu = mu_start if mu_start is not None else float(np.max(np.abs(step.C))) / (2 * a_scale)
    tried, prev = [], None
    res = None
    while mu <= mu_max:
        res = _one(step, mu, method, accuracy, tol, options)
        tried.append(mu)
        active = None if res.lam is None else res.lam > 0
        if res.ok and prev is not None and np.array_equal(active, prev):
            break
        if any("numerically singular" in f for f in res.flags):
            break
        prev = active
        mu *= mu_factor
    res.mu_tried = tried
    if not res.ok:
        res.flags.append(f"no mu in [{tried[0]:.3g}, {tried[-1]:.3g}] gave a certified answer")
        res.message = "; ".join(res.flags)
    return res
