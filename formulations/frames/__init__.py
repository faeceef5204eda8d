r"""Plane frames on unilateral supports with Coulomb friction (P3, Osipova,
Popov & Lovtsov): the displacement-method LCP, solved by Lemke, by the exact SPD
methods when there is no friction, or by a Tresca fixed point on QP backends;
P3's increasing-load algorithm (``"trace"``); load cases and combinations,
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
:mod:`.results`).

Layout: :mod:`.model` (the Frame: model building; its solving in
:mod:`.solving`, results construction in :mod:`.recovery`, the trace in
:mod:`.tracing`), :mod:`.loads` (cases, member loads, combinations),
:mod:`.elements` (the members: stiffness, releases, rigid zones, their
loads), :mod:`.assembly` (the frame: K, links, the contact LCP), :mod:`.active_set`
(the contact problem on the sparse system, "auto"'s first route),
:mod:`.results` (results, envelopes), :mod:`.tables`, :mod:`.notation`
(numbers as engineers read them), :mod:`.drawing` (with :mod:`.labels`,
:mod:`.load_arrows`, :mod:`.trace_plot`), :mod:`.examples`.  Space frames
(six dofs per node, contacts with a faceted or circular Coulomb cone):
:mod:`.space` (the SpaceFrame, solved by the same routes and trace),
:mod:`.elements3d`, :mod:`.space_recovery`, :mod:`.space_results`.

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
