"""Planar mechanisms whose parts may separate (:mod:`.planar`: the model, its
scenes and the scene schema), stepped with the penalty QP of
:mod:`formulations.stepping`; :mod:`.penalty` is the formulation's front for
``qpcontact demo`` and ``compare`` (entry point ``penalty``)."""

from .planar import (EFFECTS, GRAVITY, SCENE, Mechanism, MechanismResult, lookahead_for,
                     pellet_scene, ramming_impact_step, ramming_scene)

__all__ = ["Mechanism", "MechanismResult", "lookahead_for", "ramming_scene", "pellet_scene",
           "ramming_impact_step", "EFFECTS", "GRAVITY"]
