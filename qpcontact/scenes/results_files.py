"""A scene run's results file (HDF5, written atomically at each checkpoint): the
scene's text, the versions, the arrays — enough to resume a killed run bit for
bit and to draw the formulation's figures without running anything."""

from __future__ import annotations

import functools
from pathlib import Path

from .schema import Scene, SceneError, schemas

__all__ = ["write_results", "read_state", "plot_results"]


@functools.cache
def _versions() -> dict:
    """The packages' versions, read once a process: each read parses the
    packages' metadata (~3 ms), and a long run writes dozens of checkpoints."""
    from importlib.metadata import PackageNotFoundError, version

    out = {}
    for pkg in ("qpcontact", "numpy", "scipy", "qpsolvers", "h5py"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:
            pass
    return out


def write_results(scene: Scene, result, path, completed: int | None = None,
                  total: int | None = None) -> Path:
    """An HDF5 results file (h5py): the schema's per-step arrays (chunked,
    uncompressed), the scene's text and file name, the package versions, and the
    formulation, effects and ``completed_steps`` / ``total_steps`` as
    attributes.  Written to a temporary name and renamed: a killed run never
    leaves a half-written file under ``path`` — the last checkpoint stays."""
    import os

    import h5py
    import numpy as np

    from ..core.files import file_target

    path = file_target(path)
    tmp = path.with_name(path.name + ".tmp")
    try:
        with h5py.File(tmp, "w") as h:
            h.attrs["formulation"] = scene.schema.formulation
            h.attrs["effects"] = ",".join(scene.effects)
            h.attrs["scene_file"] = str(scene.path)
            h.create_dataset("scene", data=np.bytes_(scene.text.encode()))
            for pkg, ver in _versions().items():
                h.attrs[f"version_{pkg}"] = ver
            if completed is not None:
                h.attrs["completed_steps"] = int(completed)
            if total is not None:
                h.attrs["total_steps"] = int(total)
            for name, values in scene.schema.arrays(result).items():
                values = np.asarray(values)
                if values.ndim == 0 or values.size == 0:   # h5py refuses zero-size chunks
                    h.create_dataset(name, data=values)
                    continue
                # uncompressed: gzip took a 500-log drum revolution's file
                # (96 MB of states) to 83 MB for 2.5 s of CPU a write, and its
                # checkpoints 13 of the run's 124 s (docs/dev-notes.md)
                chunks = (min(len(values), 4096),) + values.shape[1:]
                h.create_dataset(name, data=values, chunks=chunks)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


def plot_results(path, out=None) -> list:
    """The formulation's standard figures from a results file (no re-run),
    saved in ``out`` (default: a folder next to the file, named after it)."""
    from ..core.files import make_folder, open_hdf5

    path = Path(path)
    with open_hdf5(path, SceneError, "an HDF5 results file") as h:
        name = h.attrs.get("formulation")
        known = schemas()
        if name not in known or known[name].plot is None:
            raise SceneError(f"{path}: written for formulation {name!r}, which has no plots "
                             f"here; formulations with plots: "
                             f"{', '.join(n for n, s in known.items() if s.plot) or '(none)'}")
        return known[name].plot(h, str(make_folder(out or path.with_suffix(""))))


def read_state(path, scene: Scene) -> dict:
    """What ``run(resume=...)`` continues from: the arrays of a results file
    written by an interrupted run of the same scene (byte-string datasets as
    lists of str), with ``completed``.
    Refuses a file written for another scene text (a changed scene would
    continue a different run)."""
    from ..core.files import open_hdf5

    with open_hdf5(path, SceneError, "an HDF5 results file to resume") as h:
        text = h["scene"][()].decode() if "scene" in h else None
        if text != scene.text:
            raise SceneError(f"{path}: written for a different scene text than {scene.path}; "
                             "resume only with the scene file the run started from, or start "
                             "afresh without --resume")
        if "completed_steps" not in h.attrs:
            raise SceneError(f"{path}: holds no completed-steps count; it cannot be resumed")
        state = {"completed": int(h.attrs["completed_steps"]),
                 "total": int(h.attrs.get("total_steps", -1))}

        def grab(name, obj):
            import h5py

            if isinstance(obj, h5py.Dataset) and name != "scene":
                value = obj[()]
                # byte strings (method names) come back as str, for every stepper
                state[name] = ([b.decode() for b in value] if getattr(value, "dtype", None)
                               is not None and value.dtype.kind == "S" else value)
        h.visititems(grab)
    return state
