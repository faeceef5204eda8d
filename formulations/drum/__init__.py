"""Collisions of pulpwood logs in a debarking drum: one LCP per time step
(the decomposition paper, Kolesnikov 2013).

Layout: :mod:`.model` (the model derived from the mechanics, with units; the
Drum and its stepper), :mod:`.results` (a run's arrays, energy balance,
summary), :mod:`.scene` (scene files: ``SCENE``), :mod:`.examples` (the
ten-log scene, ``demo`` and ``instances`` for the ``qpcontact.formulations``
entry point).
"""

from .examples import demo, instances, ten_log_scene
from .model import (EFFECTS, GRAVITY, GREEN_SPRUCE_DENSITY, SEASONED_SPRUCE_DENSITY,
                    SPRUCE_E_RADIAL, SPRUCE_E_TANGENTIAL, STEPS_PER_PERIOD, Drum, Log,
                    StepSizeWarning, damping_from_ratio, log_half_stiffness, log_mass)
from .results import DrumResult, DrumSummary
from .scene import SCENE

__all__ = ["Log", "Drum", "DrumResult", "DrumSummary", "StepSizeWarning", "EFFECTS",
           "log_mass", "log_half_stiffness", "damping_from_ratio",
           "GREEN_SPRUCE_DENSITY", "SEASONED_SPRUCE_DENSITY", "SPRUCE_E_RADIAL",
           "SPRUCE_E_TANGENTIAL", "GRAVITY", "STEPS_PER_PERIOD", "ten_log_scene", "demo",
           "instances", "SCENE"]
