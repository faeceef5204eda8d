"""Test helpers for projects whose code produces LCPs, QPs and frictional
contact problems (and for qpcontact's own tests).

Assertions
----------
:func:`assert_lcp_solution`, :func:`assert_qp_kkt` and
:func:`assert_friction_solution` check a candidate answer against the problem
data with qpcontact's componentwise measures (docs/certificates.md): every
condition — z >= 0, w = Mz + q >= 0, complementarity; stationarity,
feasibility, multiplier signs; each contact's cone, velocity and
complementarity — is judged against its *own* row's or contact's scale, so a
force of 1 N beside one of 1e9 N is held to 1 N's digits.  On failure the
message names the condition, the index, the raw residual and the scale it was
judged on::

    AssertionError: LCP solution fails w = Mz + q >= 0 at index 3: w_3 = -2.000e-04,
    judged against its row's scale 1.000e+00 (|q_3| + (|M||z|)_3): error 2.0e-04 > tol 1e-09

Cross-validation
----------------
:func:`cross_validate` solves one problem with several methods (the exact
pivoting ones, the QP backends, the friction methods), certifies each, and
raises :class:`CrossValidationError` when certified answers disagree — by
more than the answers' own forward-error estimates allow — where the solution
is unique (for frictional contact: where both answers are isolated, contact
by contact).  Where it is not unique (a singular PSD M, a QP with a singular
P) it compares what is unique instead (w = Mz + q, the optimal value) and
says so in the report.

Strategies and the pytest plugin
--------------------------------
:mod:`qpcontact.testing.strategies` holds hypothesis strategies for hard LCPs,
QPs and 2-D and 3-D frictional problems with a known answer or status built
in (``pip install "qpcontact[test]"`` for hypothesis).
:mod:`qpcontact.testing.plugin` is a pytest plugin, registered on install:
``qp_method`` and ``friction_method`` fixtures parametrised over the
installed methods that solve each kind, and a ``--qp-methods`` option.

Problem families
----------------
The seeded generators of :mod:`qpcontact.cases` (``random_spd_lcp``,
``far_contact_lcp``, ``spread_lcp``, ``planted_ok``, ``build_friction``) are
re-exported here.
"""

from __future__ import annotations

from ..cases.families import far_contact_lcp, planted_ok, random_spd, random_spd_lcp, spread_lcp
from ..cases.planted_friction import FRICTION_KINDS, FrictionCase, build_friction
from .assertions import assert_friction_solution, assert_lcp_solution, assert_qp_kkt
from .crossval import CrossValidation, CrossValidationError, cross_validate

__all__ = ["assert_lcp_solution", "assert_qp_kkt", "assert_friction_solution", "cross_validate",
           "CrossValidation", "CrossValidationError", "random_spd", "random_spd_lcp",
           "far_contact_lcp", "spread_lcp", "planted_ok", "build_friction", "FrictionCase",
           "FRICTION_KINDS"]
