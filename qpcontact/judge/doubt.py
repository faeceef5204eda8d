"""When a backward error within tolerance is not enough: the doubt rule.

A componentwise backward error says the answer solves data within ``error``
of each entry's own size.  Its row scales σ_i = |q_i| + (|M||z|)_i grow with
the answer, so a point running off along a direction the data barely resist
(a mechanism loaded along itself, a QP's objective falling for ever to
rounding) is "exact for nearby data" at any size: residuals of 1e-16 against
|M||z| ~ 1e17 while |Mz| and |q| are 1.  The normwise error, which divides
every row by the data's norms (max(‖Mz‖∞, ‖q‖∞)), then exceeds the
componentwise one by the factor of cancellation σ_i / σ_w.

Where the componentwise error holds and the normwise one does not —
``normwise_error > max(DOUBT_RATIO × error, tol)`` — the answer is the
solution of nearby data only: no digit of it is guaranteed, and the data
may have no solution at all.  Measured (docs/certificates.md, the doubt rules): on
200 near-singular PSD LCPs with a nonnegative null vector d and q'd < 0 the
rule caught every accepted answer (normwise >= 0.13, componentwise 1e-16);
on 144 valid answers of 8 solvable families it fired on none (largest valid
normwise 6.5e-11).  A forward-error estimate is not the rule: it is infinite
wherever the solution is not isolated, which is common and harmless.
"""

from __future__ import annotations

import numpy as np

__all__ = ["DOUBT_RATIO", "FORWARD_LIMIT", "doubt", "no_digit", "singular_block"]

#: a known, finite forward error from this on leaves no digit guaranteed
FORWARD_LIMIT = 0.1

#: how far the normwise error may exceed the componentwise one before the
#: answer is in doubt (rounding makes them differ by small factors on every
#: well-posed problem)
DOUBT_RATIO = 10.0


def doubt(cert, tol: float) -> str | None:
    """Why ``cert``'s answer is in doubt although its backward error may meet
    ``tol``, or None.  LCPs and QPs: their ``normwise_error`` (a QP's is
    OSQP's relative residuals, with x's natural size |q| / max|P| as a floor).
    An LCP answer with no guaranteed digit (forward error >= 1) beside a
    vector that is Farkas to rounding (:mod:`qpcontact.judge.near_farkas`)
    is in doubt too: the data may have no solution.
    Certificates without a normwise measure (a frictional
    problem's error already includes Siconos' normwise natural-map error)
    are never in doubt here."""
    if getattr(cert, "near_farkas", None) is not None:
        return ("ill-posed: the solution is not isolated (its active block is singular to "
                "working precision, no digit guaranteed) and the data are within rounding of a "
                "problem with no solution: a vector y >= 0 on the active rows with M'y <= 0 and "
                "q'y <= 0 holds to rounding (stats['near_farkas'])")
    normwise = getattr(cert, "normwise_error", None)
    if normwise is None or not normwise > max(DOUBT_RATIO * cert.error, tol):
        return None
    return (f"ill-posed: the residuals are small only on scales that grew with the answer "
            f"(componentwise error {cert.error:.1e}, normwise {normwise:.1e}): it solves data "
            "within rounding of yours, which may have no solution at all, and no digit of it is "
            "guaranteed")


def no_digit(cert) -> str | None:
    """Why ``cert``'s answer has no guaranteed digit although its backward
    error may be small — a known, finite forward error of at least
    FORWARD_LIMIT — or None.  Unknown estimates say nothing, and neither do
    infinite ones or those of an active block singular to working precision
    (:func:`singular_block`): the solution is then not isolated, as at every
    Stewart-Trinkle friction LCP whose answer Lemke gets exactly (condition
    1e18..1e34, backward error 1e-16), and other solutions may be as right."""
    if not getattr(cert, "forward_error_known", False):
        return None
    ferr = getattr(cert, "scale_forward_error", cert.forward_error)
    if not (np.isfinite(ferr) and ferr >= FORWARD_LIMIT) or singular_block(cert):
        return None
    return (f"no digit guaranteed: the forward error may reach {ferr:.1e} of a component's scale "
            f"(the size its data give it; condition {cert.condition:.1e}, backward error "
            f"{cert.error:.1e}); ask for a tighter accuracy or use an exact method")


def singular_block(cert) -> bool:
    """Whether the certificate's active block is singular to working
    precision (its condition against the components' scales >= 1/eps, or
    infinite): the solution is then not isolated as far as double precision
    can tell.  Against the scales, not the components' own values, whose
    condition a tiny component inflates (an SPD LCP of condition 1e11 read
    1e17..1e22 there)."""
    return not getattr(cert, "scale_condition", cert.condition) * np.finfo(float).eps < 1.0
