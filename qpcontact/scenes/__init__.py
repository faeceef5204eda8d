"""Scene files (TOML) — a formulation, its data with units, the time stepping
and the effects to simulate —, their results files (HDF5) and their figures,
and sweeps of variants.  Formulations register their schemas under the
entry-point group ``qpcontact.scenes``; see docs/scenes.md."""

from .results_files import plot_results, read_state, write_results
from .schema import (Field, Scene, SceneError, SceneSchema, accuracy_problem, load_scene,
                     method_problem, parse_scene, schemas)
from .sweep import split_values, sweep, vary_scene

__all__ = ["Field", "SceneSchema", "Scene", "SceneError", "load_scene", "schemas",
           "write_results", "read_state", "plot_results", "parse_scene", "vary_scene",
           "split_values", "sweep", "accuracy_problem", "method_problem"]
