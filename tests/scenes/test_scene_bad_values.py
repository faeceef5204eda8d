"""Scene values that TOML accepts and physics or the engine does not: each
refused when the scene is loaded or built, naming the file, the key, the
value and what would do — never a ValueError or an OverflowError from deep
inside, never a silent run."""

from __future__ import annotations

import pytest

from qpcontact.scenes import SceneError, parse_scene
from tests.formulations.drum2d.test_drum2d_scene import TINY

FRICTIONLESS = (TINY.replace(', "friction"]', "]")
                .replace("[effect.friction]\nmu_disc = 0.3\nmu_shell = 0.5\nmu_lifter = 0.4\n", ""))


def _solver(text, line):
    return text.replace("[time]", f"[solver]\n{line}\n\n[time]")


@pytest.mark.parametrize("text, words", [
    (_solver(TINY, 'method = "nope"'), "solver.method: unknown method 'nope'; choose auto or one of"),
    (_solver(TINY, 'accuracy = "ultra"'),
     "solver.accuracy: unknown accuracy 'ultra'; use one of 'low', 'default', 'high'"),
    (TINY.replace("seed = 3", "seed = 3\nclearance = -0.01"),
     "logs.clearance: must be >= 0 [m], got -0.01"),
    (TINY.replace("seed = 3", "seed = -3"), "logs.seed: must be >= 0, got -3"),
    (TINY.replace("speed = 0.2", "speed = 1e9"),
     "effect.rotation.speed: must be <= 10 [rev/s] (600 rpm;"),
    (_solver(FRICTIONLESS, 'method = "nsgs"'),
     "solver.method: 'nsgs' does not solve lcp problems (it solves friction-2d, friction-3d); "
     "choose auto or one of bpp,"),
    (_solver(TINY, 'method = "bpp"'), "solver.method: 'bpp' does not solve friction-2d problems"),
    (TINY.replace("step = 0.002", "step = nan"), "time.step: must be a finite number [s], got nan"),
    (TINY.replace("duration = 0.2", "duration = inf"),
     "time.duration: must be a finite number [s], got inf"),
    (TINY.replace("duration = 0.2", "duration = 1e300"),
     "makes 5e+302 steps, more than 1e+08; give a shorter duration or a longer step"),
], ids=["method", "accuracy", "clearance", "seed", "speed", "friction-method-frictionless",
        "lcp-method-with-friction", "nan-step", "inf-duration", "too-many-steps"])
def test_drum2d_bad_values_are_refused_naming_key_and_value(text, words):
    with pytest.raises(SceneError) as exc:
        sc = parse_scene(text, "s.toml")
        sc.schema.build(sc)
    assert words in str(exc.value), str(exc.value)
    assert str(exc.value).startswith("s.toml:")


def test_frictionless_drum2d_takes_an_lcp_method():
    sc = parse_scene(_solver(FRICTIONLESS, 'method = "lemke"'), "s.toml")
    assert sc.schema.build(sc)[1].total_steps == 100


DRUM = """formulation = "drum"

[[logs]]
diameter = 0.12
length = 1.2

[initial]
gaps = [0.01]

[time]
steps = 10
"""


@pytest.mark.parametrize("edit, words", [
    ('[solver]\nmethod = "nsgs"\n', "solver.method: 'nsgs' does not solve lcp problems"),
    ('[solver]\naccuracy = "ultra"\n', "solver.accuracy: unknown accuracy 'ultra'"),
    ("[time]\nsteps = 10\ntau = nan\n", "time.tau: must be a finite number [s], got nan"),
])
def test_drum_solver_and_step_are_checked(edit, words):
    text = DRUM.replace("[time]\nsteps = 10\n", edit) if edit.startswith("[time]") \
        else DRUM + "\n" + edit
    with pytest.raises(SceneError, match=words.replace("(", r"\(").replace(")", r"\)")
                       .replace("[", r"\[").replace("]", r"\]")):
        parse_scene(text, "d.toml")
