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

import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from ..core.errors import InvalidProblemError, QpcontactError

__all__ = ["Field", "SceneSchema", "Scene", "SceneError", "SourceLines", "load_scene", "schemas",
           "parse_scene", "accuracy_problem", "method_problem"]

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
    low: float | None = None     # the least value allowed (numbers)
    high: float | None = None    # the largest value allowed (numbers); ``why`` says why
    why: str = ""
    check: object = None         # value -> None, or what is wrong with it (a message)


def accuracy_problem(value) -> str | None:
    """None for an accuracy level the engine knows; else what is wrong, with
    the levels (a Field's ``check``)."""
    from ..core.accuracy import resolve_accuracy

    try:
        resolve_accuracy(value)
    except QpcontactError as exc:
        return str(exc)
    return None


def method_problem(name, kinds) -> str | None:
    """None when ``name`` is "auto" or a method that solves one of
    ``kinds`` (problem kinds: "lcp", "qp", "friction-2d", ...); else what is
    wrong, with the methods that would do."""
    from ..solvers.registry import all_methods

    known = all_methods()
    fits = sorted(n for n, m in known.items() if set(m.problems) & set(kinds))
    if name == "auto" or name in fits:
        return None
    choose = f"choose auto or one of {', '.join(fits)}"
    if name in known:
        return (f"{name!r} does not solve {' or '.join(kinds)} problems (it solves "
                f"{', '.join(known[name].problems)}); {choose}")
    return f"unknown method {name!r}; {choose}"


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
        _fail(self.path, SourceLines(self.text), where, message, tuple(table), key, index)


def schemas() -> dict:
    """Registered scene schemas by formulation name (entry points
    ``qpcontact.scenes``)."""
    from importlib.metadata import entry_points

    return {ep.name: ep.load() for ep in entry_points(group="qpcontact.scenes")}


class SourceLines:
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
    unit = f" [{f.unit}]" if f.unit else ""
    numbers = [value] if f.kind in ("float", "int") else value if f.kind == "floats" else []
    for v in numbers:
        if not math.isfinite(v):   # TOML has nan and inf
            _fail(path, lines, where, f"must be a finite number{unit}, got {v!r}", table, key,
                  index)
        if f.positive and v <= 0:
            _fail(path, lines, where, f"must be > 0{unit}, got {v!r}", table, key, index)
        if f.low is not None and v < f.low:
            _fail(path, lines, where, f"must be >= {f.low:g}{unit}, got {v!r}", table, key,
                  index)
        if f.high is not None and v > f.high:
            why = f" ({f.why})" if f.why else ""
            _fail(path, lines, where, f"must be <= {f.high:g}{unit}{why}, got {v!r}", table,
                  key, index)
    if f.check is not None:
        wrong = f.check(value)
        if wrong:
            _fail(path, lines, where, wrong, table, key, index)
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
    lines = SourceLines(text)
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
