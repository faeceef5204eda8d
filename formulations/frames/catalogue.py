"""The frames formulation's problems for ``qpcontact compare`` (its
``instances`` entry point): the plane frames' beams
(:func:`.plane.plane_examples.plane_instances`) and, with "hard", the space
frames' circular-cone problems (:func:`.space.space_examples.space_instances`:
FrictionProblems in FCLIB's global form)."""

from __future__ import annotations

from .plane.plane_examples import plane_instances
from .space.space_examples import space_instances


def instances(size: str = "small", hardness: str = "easy", seed: int = 0) -> list:
    """Frame LCPs for ``qpcontact compare``: a continuous beam on 3, 10 or 30
    unilateral supports (size small/medium/large) under gravity and uplifting
    point loads; "easy" without friction (symmetric), "hard" with friction
    f = 0.3 and a lateral load (nonsymmetric: QP backends are not applicable).
    Named ``frames/10-supports-friction``; the contact forces are w's first
    entries (X_n).  With "hard" also a space frame's circular-cone problem
    (a FrictionProblem in FCLIB's global form)."""
    return plane_instances(size, hardness, seed) + space_instances(size, hardness, seed)
