"""One accuracy ladder for every method and every problem kind.

Levels
------
``"low"``      tolerance 1e-4
``"default"``  the backend's own default settings, untouched; the answer is
               certified against :data:`DEFAULT_CERTIFY_TOL` (Siconos' default
               tolerance) so ``ok`` still means something
``"high"``     tolerance 1e-9
a float        that tolerance, 0 < tol < 1

The tolerance is what :func:`qpcontact.certify` must confirm (``cert.error <=
tol``) for a solution to be ``ok``, for every problem kind: an LCP, a QP, a
frictional contact problem (whose methods stop at it too), a load trace.
How each QP backend is asked for it is in
:mod:`qpcontact.solvers.backends.settings`; those are requests, and the
certificate is the judge.
"""

from __future__ import annotations

from .errors import InvalidOptionError

__all__ = ["LEVELS", "DEFAULT_CERTIFY_TOL", "resolve_accuracy"]

#: The named levels and their tolerances (None: the backend's own defaults,
#: certified against DEFAULT_CERTIFY_TOL); see the module docstring.
LEVELS: dict[str, float | None] = {"low": 1e-4, "default": None, "high": 1e-9}

#: Threshold used to certify answers computed at the backends' default settings.
DEFAULT_CERTIFY_TOL = 1e-6


def resolve_accuracy(accuracy) -> tuple[float | None, float]:
    """Return (tolerance asked of the backend or None for its defaults,
    tolerance the certificate must meet)."""
    if isinstance(accuracy, str):
        if accuracy not in LEVELS:
            raise InvalidOptionError(
                f"unknown accuracy {accuracy!r}; use one of {', '.join(map(repr, LEVELS))} "
                "or a number such as 1e-6"
            )
        tol = LEVELS[accuracy]
        return tol, (DEFAULT_CERTIFY_TOL if tol is None else tol)
    try:
        tol = float(accuracy)
    except (TypeError, ValueError):
        raise InvalidOptionError(
            f"accuracy must be 'low', 'default', 'high' or a number; got {accuracy!r}"
        ) from None
    if not (0.0 < tol < 1.0):
        raise InvalidOptionError(f"a numeric accuracy must lie in (0, 1); got {tol!r}")
    return tol, tol


