r"""Plane frames on unilateral supports with Coulomb friction (Osipova,
Popov & Lovtsov): the displacement-method LCP, solved by Lemke, by the exact SPD
methods when there is no friction, or by a Tresca fixed point on QP backends;
their increasing-load algorithm (``"trace"``); load cases and combinations,
each combination solved as its own nonlinear problem.

Units: the user's, consistent (e.g. kN, m, kN·m, kN/m²); ``Frame(units=...)``
names them on drawings and tables.  Nothing is converted.

Sign conventions
----------------
Global axes x (right), y (up), rotations counterclockwise.  Nodal loads
(fx, fy, mz) and member loads in global axes are positive along the axes;
member loads in member axes along x from node i to node j and y turned
counterclockwise from it.  A contact at a node has a unit normal n pointing
from the support into the structure (the direction the support pushes) and
the tangent t = (n_y, -n_x).  X_n >= 0 is the normal force the support exerts
on the node (compression), X_t the tangential (friction) force on the node
along t (under a beam, n = (0, 1) and t = (1, 0)).  The gap opening is
Z_n = g + n·(u_node - u_other) (+ X_n/k for an elastic contact), >= 0; the
slip is Δ_t = t·(u_node - u_other) (+ X_t/k).  For a pair (``other=``) the
forces act on ``other`` with the opposite sign.  ``member_forces`` are end
actions in member axes; diagrams and ``end_forces``: axial N tension
positive, bending moment M positive when it compresses the member's +y fibre
(sagging for a beam drawn left to right), shear V = dM/dx (see
:mod:`.plane.plane_results`); a space frame's the same about each of its
member's axes (:mod:`.space.space_diagrams`; docs/frames.md, "Conventions").

Layout, in wings: :mod:`.plane` (the plane :class:`Frame`, one model whose
analysis is functions taking it; its assembly, results, member diagrams,
sparse active set, examples), :mod:`.space` (the :class:`SpaceFrame`, its
assembly, results, circular cone, tower and examples), :mod:`.mechanics`
(what both share: the elements, loads, the contact LCP, the checks, solving,
tracing, the Tresca fixed point, the proofs of no equilibrium, the export as
a friction problem, the result containers, and :class:`FrameKind`, the
hooks by which the shared functions reach each kind's own), and
:mod:`.reporting` (tables, notation, drawings, labels, load arrows, the
trace plot).  :mod:`.catalogue` gives ``qpcontact compare`` its instances.

Only the effects the model calls for: contacts with f = 0 build no tangential
link at all, and a frame without friction builds the normal-only LCP
(M = R_nn, symmetric), solved by the exact SPD method when it is positive
definite.
"""

from .catalogue import instances
from .mechanics.analysis_results import CombinationResults, FrameEvent, FrameTrace
from .mechanics.equilibrium_checks import (EQUILIBRIUM_FLOOR, SMALL_DISPLACEMENT, SMALL_ROTATION,
                                           STATE_RTOL, LargeDisplacementWarning)
from .mechanics.loads import CONSTANT, VARIABLE, MemberLoad
from .mechanics.plane_element import DOFS
from .plane.frame import Frame
from .plane.plane_examples import demo, portal_example
from .plane.plane_results import STATES, FrameResult, SupportResult
from .space.space_frame import SpaceContact, SpaceFrame
from .space.space_results import SpaceFrameResult, SpaceSupportResult

__all__ = ["Frame", "SpaceFrame", "SpaceFrameResult", "SpaceSupportResult", "SpaceContact",
           "FrameResult", "FrameTrace", "FrameEvent", "SupportResult",
           "CombinationResults", "MemberLoad", "STATES", "EQUILIBRIUM_FLOOR", "STATE_RTOL",
           "SMALL_DISPLACEMENT", "SMALL_ROTATION", "LargeDisplacementWarning",
           "CONSTANT", "VARIABLE", "DOFS", "demo", "instances", "portal_example"]
