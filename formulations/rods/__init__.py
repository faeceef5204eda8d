"""Thin rods with large deflections (the rod paper: Pustovoy, Levin &
Krasnorutskiy 2014): the planar elastica and the spatial
Kirchhoff rod, their statics and motion, solved as two-point boundary-value
problems.

Layout: :mod:`.bvp` (the two-point BVP solver: trapezoidal finite
differences, Newton, deferred correction, continuation), :mod:`.statics`
(the equations, nondimensional; cantilevers, columns, the spatial rod),
:mod:`.dynamics` (one BVP per time step, Park's method), :mod:`.scene`
(scene files: ``SCENE``, SI units).
"""

from . import bvp
from .dynamics import PARK, RodMotion, cantilever_dynamics, spatial_cantilever_dynamics
from .scene import SCENE, RodRun
from .statics import (cantilever, cantilever_curve, cantilever_f, cantilever_general,
                      clamped_free_bc, column, column_f, qmul, rotate, rotate_T,
                      spatial_cantilever, spatial_f, tip_deflection)

__all__ = ["cantilever", "cantilever_general", "column", "cantilever_curve", "tip_deflection",
           "cantilever_dynamics", "spatial_cantilever_dynamics", "RodMotion",
           "spatial_cantilever", "cantilever_f", "column_f", "clamped_free_bc", "qmul", "rotate",
           "rotate_T", "spatial_f", "PARK", "RodRun", "SCENE", "bvp"]
