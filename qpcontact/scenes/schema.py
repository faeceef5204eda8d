"""Scene files (TOML): a formulation, its data with units, the time stepping,
and the effects to simulate — read by one engine-side loader.

    formulation = "drum"
    effects = ["gravity", "damping"]        # only these are assembled

    [effect.damping]                        # parameters of a named effect
    ratio = 0.05                            # [-]

Formulations register a :class:`SceneSchema` under the entry-point group
``qpcontact.scenes`` (the engine never imports them): the sections and keys
they take (:class:`Field`: type, unit, required or default), the effects they
know with their parameters, and ``build(scene) -> (model, run)``.  The loader
checks everything before anything is built, and every error names the file,
the line and the key, and lists the valid choices: an unknown key, an unknown
effect, a parameter of an effect that is not named, a wrong type, a missing
required value.  A scene that names no effect gets none of their terms — the
formulation's constructor assembles only what it is given.
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from ..core.errors import InvalidProblemError

__all__ = ["Field", "SceneSchema", "Scene", "SceneError", "load_scene", "schemas",
           "write_results", "read_state", "plot_results", "parse_scene", "vary_scene",
           "split_values", "sweep"]

_TYPES = {"float": (int, float), "int": (int,), "str": (str,), "bool": (bool,),
          "floats": (list,), "strs": (list,), "tables": (list,)}


class SceneError(InvalidProblemError):
    """A scene file that cannot be used as written (file, line, key, choices)."""


@dataclass(frozen=True)
class Field:
    """One key: ``kind`` in float, int, str, bool, floats (a list of numbers),
    tables (an array of tables, each checked against ``fields``); ``unit``
    (shown in messages and docs); ``default`` (None and not ``required``: may
    be left out)."""

    kind: str
    unit: str = ""
    doc: str = ""
    required: bool = False
    default: object = None
    fields: dict = field(default_factory=dict)   # for kind "tables"
    positive: bool = False


@dataclass(frozen=True)
class SceneSchema:
    """What a formulation's scenes contain.  ``sections``: {name: {key:
    Field}} (tables of the file) or {name: Field(kind="tables")} (a
    top-level array of tables, ``[[name]]``); ``effects``: {effect: {parameter: Field}};
    ``build(scene)`` returns (model, run) with ``run(progress) -> result``;
    ``arrays(result)`` the per-step arrays a results file holds;
    ``plot(h5file, folder)`` its standard figures, drawn from the file."""

    formulation: str
    doc: str
    sections: dict
    effects: dict
    build: object
    arrays: object = None   # result -> {name: array per step} for the results file
    plot: object = None     # (open h5py.File, out folder) -> [paths of the figures]
    summary: object = None  # result -> {column: scalar} for a sweep's summary table


@dataclass
class Scene:
    """A checked scene: ``data`` {section: {key: value}} with defaults filled
    in, ``effects`` (tuple), ``effect_params`` {effect: {param: value}},
    the file ``path`` and its ``text`` (kept for the results file)."""

    schema: SceneSchema
    data: dict
    effects: tuple
    effect_params: dict
    path: Path
    text: str

    def fail(self, message: str, table=(), key=None, index=None):
        """Raise a SceneError at the line of ``table``/``key`` (a build-time
        check the schema's types cannot express, e.g. data for an effect
        that is not named)."""
        where = ".".join(tuple(table) + ((key,) if key else ()))
        _fail(self.path, _Lines(self.text), where, message, tuple(table), key, index)


def schemas() -> dict:
    """Registered scene schemas by formulation name (entry points
    ``qpcontact.scenes``)."""
    from importlib.metadata import entry_points

    return {ep.name: ep.load() for ep in entry_points(group="qpcontact.scenes")}


class _Lines:
    """Where a key sits in the file: tomllib gives values, not lines, so the
    text is scanned for table headers and ``key =`` lines."""

    _header = re.compile(r"^\s*(\[\[?)\s*([^\]]+?)\s*\]\]?\s*(#.*)?$")
    _key = re.compile(r"^\s*([A-Za-z0-9_\-\"']+)\s*=")

    def __init__(self, text: str):
        self.entries = []   # (line, table path, index of an array table, key or None)
        table, counts, index = (), {}, None
        for no, line in enumerate(text.splitlines(), 1):
            m = self._header.match(line)
            if m:
                table = tuple(part.strip().strip('"') for part in m.group(2).split("."))
                if m.group(1) == "[[":
                    counts[table] = index = counts.get(table, -1) + 1
                else:
                    index = None
                self.entries.append((no, table, index, None))
                continue
            m = self._key.match(line)
            if m:
                self.entries.append((no, table, index, m.group(1).strip("\"'")))

    def line(self, table=(), key=None, index=None) -> int | None:
        for no, t, i, k in self.entries:
            if t == tuple(table) and k == key and (index is None or i == index):
                return no
        if key is not None:   # a table's header, or a missing key: its table's header
            return self.line(tuple(table) + (key,), None) or self.line(table, None, index)
        return None


def _fail(path, lines, where, message, table=(), key=None, index=None):
    no = lines.line(table, key, index)
    at = f"{path}:{no}" if no else str(path)
    raise SceneError(f"{at}: {where}: {message}")


def _check_value(path, lines, where, f: Field, value, table, key, index=None):
    if (isinstance(value, bool) and f.kind != "bool") or not isinstance(value, _TYPES[f.kind]):
        unit = f" [{f.unit}]" if f.unit else ""
        _fail(path, lines, where, f"expected {_describe(f)}{unit}, got {value!r}", table, key,
              index)
    if f.kind == "floats":
        bad = [v for v in value if isinstance(v, bool) or not isinstance(v, (int, float))]
        if bad:
            _fail(path, lines, where, f"expected a list of numbers [{f.unit}], got {bad[0]!r} "
                  "in it", table, key, index)
        value = [float(v) for v in value]
    if f.kind == "strs" and not all(isinstance(v, str) for v in value):
        _fail(path, lines, where, f"expected a list of strings, got {value!r}", table, key, index)
    if f.kind == "float":
        value = float(value)
    if f.positive and f.kind in ("float", "int") and value <= 0:
        _fail(path, lines, where, f"must be > 0 [{f.unit}], got {value!r}", table, key, index)
    return value


def _describe(f: Field) -> str:
    return {"float": "a number", "int": "an integer", "str": "a string", "bool": "true or false",
            "floats": "a list of numbers", "strs": "a list of strings",
            "tables": "an array of tables [[...]]"}[f.kind]


def _check_table(path, lines, spec: dict, given: dict, table, index=None) -> dict:
    out = {}
    for key, value in given.items():
        where = ".".join(table + (key,))
        if key not in spec:
            _fail(path, lines, where, f"unknown key; valid keys in [{'.'.join(table)}]: "
                  f"{', '.join(spec)}", table, key, index)
        f = spec[key]
        if f.kind == "tables":
            if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
                _fail(path, lines, where, f"expected {_describe(f)}", table, key, index)
            out[key] = [_check_table(path, lines, f.fields, item, table + (key,), i)
                        for i, item in enumerate(value)]
        else:
            out[key] = _check_value(path, lines, where, f, value, table, key, index)
    for key, f in spec.items():
        if key in out:
            continue
        if f.required:
            unit = f" [{f.unit}]" if f.unit else ""
            _fail(path, lines, ".".join(table + (key,)),
                  f"missing required value: {_describe(f)}{unit} — {f.doc}", table, None, index)
        out[key] = f.default
    return out


def load_scene(path) -> Scene:
    """Read and check a scene file; raises :class:`SceneError` naming the
    file, line and key of the first problem, with the valid choices."""
    path = Path(path)
    if not path.is_file():
        raise SceneError(f"{path}: no such scene file")
    return parse_scene(path.read_text(), path)


def parse_scene(text: str, path="<scene>") -> Scene:
    """:func:`load_scene` on a scene's text (``path`` names it in messages)."""
    path = Path(path)
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{path}: not valid TOML: {exc}") from None
    lines = _Lines(text)
    known = schemas()
    name = raw.get("formulation")
    if name not in known:
        _fail(path, lines, "formulation",
              f"{'missing' if name is None else repr(name) + ' is not a registered formulation'}"
              f"; choose one of {', '.join(sorted(known)) or '(none installed)'}", (),
              "formulation" if name is not None else None)
    schema = known[name]
    effects = raw.get("effects", [])
    if not isinstance(effects, list) or not all(isinstance(e, str) for e in effects):
        _fail(path, lines, "effects", "expected a list of effect names, e.g. "
              f"effects = [{', '.join(repr(e) for e in schema.effects)}]", (), "effects")
    for e in effects:
        if e not in schema.effects:
            _fail(path, lines, "effects", f"unknown effect {e!r} for {name!r}; it knows "
                  f"{', '.join(schema.effects)}", (), "effects")
    data, effect_params = {}, {}
    for key in raw:
        if key in ("formulation", "effects", "effect"):
            continue
        if key not in schema.sections:
            valid = ["formulation", "effects", "effect"] + list(schema.sections)
            _fail(path, lines, key, f"unknown key for {name!r}; valid top-level keys and "
                  f"tables: {', '.join(valid)}", (), key)
    # TOML cannot make ``effects`` both the list and a table: parameters
    # live under [effect.NAME]
    params = raw.get("effect", {})
    if not isinstance(params, dict):
        _fail(path, lines, "effect", "expected tables [effect.NAME] of parameters", (), "effect")
    for e, given in params.items():
        if e not in schema.effects:
            _fail(path, lines, f"effect.{e}", f"unknown effect {e!r}; {name!r} knows "
                  f"{', '.join(schema.effects)}", ("effect", e))
        if e not in effects:
            _fail(path, lines, f"effect.{e}", f"parameters given for effect {e!r}, which is "
                  f"not named in effects = {effects}; add it there or remove [effect.{e}]",
                  ("effect", e))
    for e in effects:
        effect_params[e] = _check_table(path, lines, schema.effects[e], params.get(e, {}),
                                        ("effect", e))
    for section, spec in schema.sections.items():
        if isinstance(spec, Field):   # a top-level array of tables, [[section]]
            data[section] = _check_table(path, lines, {section: spec},
                                         {section: raw[section]} if section in raw else {},
                                         ())[section]
            continue
        given = raw.get(section, {})
        if not isinstance(given, dict):
            _fail(path, lines, section, f"expected a table [{section}]", (), section)
        data[section] = _check_table(path, lines, spec, given, (section,))
    return Scene(schema, data, tuple(effects), effect_params, path, text)


def _versions() -> dict:
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
    gzip), the scene's text and file name, the package versions, and the
    formulation, effects and ``completed_steps`` / ``total_steps`` as
    attributes.  Written to a temporary name and renamed: a killed run never
    leaves a half-written file under ``path`` — the last checkpoint stays."""
    import os

    import h5py
    import numpy as np

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
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
                if values.ndim == 0:
                    h.create_dataset(name, data=values)
                    continue
                chunks = (min(len(values), 4096),) + values.shape[1:]
                h.create_dataset(name, data=values, chunks=chunks,
                                 compression="gzip" if values.dtype.kind == "f" else None)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


def plot_results(path, out=None) -> list:
    """The formulation's standard figures from a results file (no re-run),
    saved in ``out`` (default: a folder next to the file, named after it)."""
    from ..core.files import open_hdf5

    path = Path(path)
    with open_hdf5(path, SceneError, "an HDF5 results file") as h:
        name = h.attrs.get("formulation")
        known = schemas()
        if name not in known or known[name].plot is None:
            raise SceneError(f"{path}: written for formulation {name!r}, which has no plots "
                             f"here; formulations with plots: "
                             f"{', '.join(n for n, s in known.items() if s.plot) or '(none)'}")
        return known[name].plot(h, str(out or path.with_suffix("")))


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


# -- sweeps ----------------------------------------------------------------------

def vary_scene(text: str, key: str, value: str) -> str:
    """The scene text with ``key`` (dotted: ``time.steps_per_period``,
    ``effect.damping.ratio``, ``logs.1.diameter`` for the second [[logs]])
    set to ``value`` (TOML: ``0.05``, ``"bpp"``), edited in place so the
    variant's text is a scene file of its own."""
    parts = key.split(".")
    index = None
    if len(parts) >= 3 and parts[-2].isdigit():
        index = int(parts[-2])
        table, name = tuple(parts[:-2]), parts[-1]
    else:
        table, name = tuple(parts[:-1]), parts[-1]
    lines = text.splitlines()
    where = _Lines(text)
    no = None
    for ln, t, i, k in where.entries:
        if t == table and k == name and (index is None or i == index):
            no = ln
            break
    if no is not None:
        m = re.match(r"^(\s*[^=]+=\s*)(.*?)(\s+#.*)?$", lines[no - 1])
        lines[no - 1] = m.group(1) + value + (m.group(3) or "")
        return "\n".join(lines) + "\n"
    header = where.line(table, None, index) if table else None
    if table and header is None:
        if index is not None:
            raise SceneError(f"--vary {key}: the scene has no [[{'.'.join(table)}]] number {index}")
        return text.rstrip("\n") + f"\n\n[{'.'.join(table)}]\n{name} = {value}\n"
    insert_at = header if table else 0   # right after the table's header (or at the top)
    lines.insert(insert_at, f"{name} = {value}")
    return "\n".join(lines) + "\n"


def split_values(values: str) -> list[str]:
    """A ``--vary`` list: TOML values separated by commas, where commas
    inside brackets or quotes belong to the value (``[0.01,0.02],[0.02,0.01]``
    is two lists)."""
    out, depth, quote, start = [], 0, None, 0
    for i, ch in enumerate(values):
        if quote:
            quote = None if ch == quote else quote
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
            if depth < 0:
                raise SceneError(f"unbalanced '{ch}' at character {i + 1} of {values!r}")
        elif ch == "," and depth == 0:
            out.append(values[start:i].strip())
            start = i + 1
    if depth or quote:
        raise SceneError(f"unclosed {'quote' if quote else 'bracket'} in {values!r}")
    out.append(values[start:].strip())
    if not all(out):
        raise SceneError(f"an empty value in {values!r}")
    return out


def _run_text(text: str, label: str):
    scene = parse_scene(text, label)
    _, run = scene.schema.build(scene)
    return run()


def sweep(path, variations: dict, out_dir, *, grid: bool = False, workers: int = 0,
          scheduler: str | None = None, progress: bool = True):
    """Run variants of a scene: ``variations`` {key: [values as TOML text]},
    zipped (all lists the same length) or, with ``grid``, every combination.
    Serial, or on Dask (``workers`` local processes or a ``scheduler``
    address) — the same code per variant either way, so the results are the
    same.  Writes one HDF5 file per variant and summary.csv (the varied
    values and the schema's summary of each run); returns the summary rows."""
    import itertools

    from ..core.files import write_csv_atomic
    from ..core.progress import ProgressBar

    path = Path(path)
    base = load_scene(path)
    keys = list(variations)
    if not keys:
        raise SceneError("sweep: give at least one --vary KEY=v1,v2,...")
    if grid:
        combos = list(itertools.product(*(variations[k] for k in keys)))
    else:
        sizes = {len(v) for v in variations.values()}
        if len(sizes) != 1:
            raise SceneError("sweep: the --vary lists differ in length "
                             f"({', '.join(f'{k}: {len(v)}' for k, v in variations.items())}); "
                             "give lists of one length, or --grid for every combination")
        combos = list(zip(*(variations[k] for k in keys)))
    texts, labels, scenes = [], [], []
    for n, combo in enumerate(combos):
        text = base.text
        for k, v in zip(keys, combo):
            text = vary_scene(text, k, v)
        # every variant checked before any runs
        scenes.append(parse_scene(text, f"{path} with {dict(zip(keys, combo))}"))
        texts.append(text)
        labels.append(f"{path.stem}-{n:03d}")
    if workers or scheduler:
        results = _dask_runs(texts, labels, workers, scheduler)
    else:
        results = (_run_text(t, lb) for t, lb in zip(texts, labels))
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    bar = ProgressBar(len(texts), "sweep variants", progress)
    rows = []
    for n, (scene, label, result) in enumerate(zip(scenes, labels, results), 1):
        write_results(scene, result, out / f"{label}.h5", completed=len(result.t) - 1,
                      total=len(result.t) - 1)
        row = {"variant": label, **dict(zip(keys, combos[n - 1]))}
        if scene.schema.summary is not None:
            row.update(scene.schema.summary(result))
        rows.append(row)
        bar.update(n)
    bar.close()
    fields = list(dict.fromkeys(k for r in rows for k in r))
    write_csv_atomic(out / "summary.csv", rows, fields)
    return rows


def _dask_runs(texts, labels, workers, scheduler):
    from ..core.cluster import dask_client

    with dask_client(workers, scheduler) as client:
        futures = [client.submit(_run_text, t, lb, pure=False) for t, lb in zip(texts, labels)]
        for fut in futures:   # in order: files and rows follow the variants
            yield fut.result()
