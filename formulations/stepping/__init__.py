"""The contact time step shared by the planar mechanisms
(:mod:`formulations.mechanisms`) and the spatial trees
(:mod:`formulations.multibody`): the penalty QP of one integration step
(:mod:`.penalty_step`, after Nikolsky, Kopylov, Romanenko & Kudryashov 2012,
with its derivation and units) and the semi-implicit step around it
(:mod:`.contact_step`).  It imports neither of the formulations that use it,
so the folders import one way: mechanisms -> multibody -> stepping."""

from .contact_step import ContactSystem, MechanismResult, ROUTES, lookahead_for
from .penalty_step import (MU_SINGULAR_COND, REGULARIZATION, PenaltyResult, PenaltyStep,
                           exact_lcp, gauss_qp, mu_threshold, penalty_qp, solve_penalty,
                           step_penalty_qp)

__all__ = ["ContactSystem", "MechanismResult", "ROUTES", "lookahead_for", "PenaltyStep",
           "PenaltyResult", "penalty_qp", "step_penalty_qp", "exact_lcp", "gauss_qp",
           "mu_threshold", "solve_penalty", "REGULARIZATION", "MU_SINGULAR_COND"]
