"""The debarking drum's 2-D cross-section: logs as discs in a
rotating shell with lifter bars, Moreau–Jean steps with certified 2-D
frictional contact problems.  docs/drum2d.md derives the model; each module's
docstring derives its part (geometry, broadphase, contacts, stepper; what an
engineer reads: revolutions, stack, figures, animation)."""

from .animation import Animation, write_animation
from .broadphase import all_pairs, grid_pairs
from .contacts import DISC, KINDS, LIFTER, SHELL, Contacts, find_contacts
from .geometry import GRAVITY, Discs, Shell, disc_inertia, disc_mass, hex_fill, wall_velocity
from .laws import ContactLaw
from .records import FORCE_BINS
from .revolutions import (KindForces, Revolution, SlidingWork, Window, revolution_windows,
                          revolutions)
from .stack import StackEstimate, stack_estimate, stack_estimate_for_run
from .stepper import EFFECTS, Drum2D, Drum2DResult, UncertifiedStepWarning

__all__ = ["Discs", "Shell", "Drum2D", "Drum2DResult", "EFFECTS", "UncertifiedStepWarning",
           "Contacts", "find_contacts", "grid_pairs", "all_pairs", "KINDS", "DISC", "SHELL",
           "LIFTER", "GRAVITY", "hex_fill", "disc_mass", "disc_inertia", "wall_velocity",
           "ContactLaw", "FORCE_BINS", "revolutions", "revolution_windows", "Revolution", "Window",
           "KindForces", "SlidingWork", "stack_estimate", "stack_estimate_for_run",
           "StackEstimate", "write_animation", "Animation"]
