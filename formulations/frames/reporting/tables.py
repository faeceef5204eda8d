"""Tables of a frame's results, as an engineer reads them and as a program
reads them back (docs/frames.md, "Tables").

Every table is a list of dicts, one per row, the same keys in every row;
every numeric column names its unit in its header ("Fy [kN]", "M_i [kN·m]",
"x(M_max) [m]", "rz [rad]").  Tables of one result:

* ``supports``: each contact (node, state, X_n, X_t, the share of its
  friction cone used, its force in global components, opening, slip) —
  the space frame's columns with one tangent;
* ``reactions``: one row per supported node, the total force of its
  bilateral support, spring and contacts on the structure (global axes),
  with each kind's part when the frame has more than one kind;
* ``members``: end forces N, V, M at i and j and the extremes of N, V, M
  and of the deflection v across the member, with where they occur (the
  diagrams' convention);
* ``displacements``: ux, uy, rz per node.

Over combinations: the same tables with a "combination" column, the
envelopes of the members (``envelope``: max/min of N, V, M with where and in
which combination), of the reactions (``envelope_reactions``) and of the
contacts (``envelope_supports``: each one's states and the extremes of its
X_n, |X_t|, cone use, opening and |slip|), and ``combinations`` (each
one's status).

**Rounding happens here and only here**: the result objects keep full
precision, the tables are for reading and are rounded by default
(``digits=DIGITS``): a value below ``NOISE`` x the scale of its quantity is
0, and each column is rounded to the decimals that give its largest value
``digits`` significant digits (:func:`.notation.round_column`).  The scale of
a quantity is the largest value of every column of the table in the same
unit (a column of 1e-14 axial forces beside shears of 50 kN is zero, not
"1e-14"); a moment's is at least the force scale times the frame's size, a
rotation's at least the displacement scale over it (a cantilever pulled
along its axis has a clamp moment of rounding size, alone in its column),
a share's ("[-]", the cone use) at least 1.
``digits=None`` returns the raw floats.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from qpcontact.core.errors import BackendUnavailableError, InvalidOptionError
from qpcontact.core.files import write_csv_atomic

from ..mechanics.plane_element import DOFS
from .notation import DIGITS, NOISE, round_column

TABLES = ("supports", "reactions", "members", "displacements")
#: the tables of a CombinationResults besides TABLES
COMBINED = ("envelope", "envelope_reactions", "envelope_supports", "combinations")
KINDS = ("support", "spring", "contact")
QUANTITIES = ("N", "V", "M")
#: what the members' tables give extremes of: the internal forces and the
#: deflection across the member (v, a length)
EXTREMES = QUANTITIES + ("v",)
FORCES = ("Fx", "Fy", "Mz")
#: the share of the contact's friction cone used: |X_t| / (f X_n), <= 1, 1
#: where it slips (NaN where there is no cone: separated, or f = 0)
USE = "cone use (the model's cone)"
#: the contact quantities whose extremes envelope_supports gives, and which side
CONTACT_EXTREMES = (("X_n", "max"), ("X_n", "min"), ("|X_t|", "max"), ("use", "max"),
                    ("opening", "max"), ("|slip|", "max"))

_UNIT = re.compile(r"\[([^\]]+)\]$")


def check_table(table, tables=TABLES) -> None:
    if table not in tables:
        raise InvalidOptionError(f"unknown table {table!r}; tables: {', '.join(tables)}")


def support_reactions(frame, result) -> dict:
    """Every support's force on the structure, global (Fx, Fy, Mz), keyed by
    support: bilateral supports by node, springs by node (or "N (spring)"
    beside a support), contacts by their key in ``result.supports`` (or
    "N (contact)"); a pair's is the force on its ``node``."""
    out = {node: tuple(float(v) for v in r) for node, r in result.reactions.items()}
    for node, r in _springs(frame, result).items():
        out[f"{node} (spring)" if node in out else node] = r
    # result.supports is built in contact order (recovery), so it pairs with frame.contacts
    for (key, s), c in zip(result.supports.items(), frame.contacts):
        out[f"{key} (contact)" if key in out else key] = _contact_force(c, s)
    return out


def reactions_by_node(frame, result) -> dict:
    """One entry per node the ground holds: {node: {"total": (Fx, Fy, Mz),
    "support"|"spring"|"contact": (Fx, Fy, Mz) for the kinds at that node,
    "contact states": [...]}}, global axes.  Node-to-node contact pairs are
    forces between two parts of the frame, not reactions: they are in the
    "supports" table only."""
    parts: dict = {}
    for node, r in result.reactions.items():
        parts.setdefault(node, {})["support"] = tuple(float(v) for v in r)
    for node, r in _springs(frame, result).items():
        parts.setdefault(node, {})["spring"] = r
    for (key, s), c in zip(result.supports.items(), frame.contacts):
        if c.other is not None:
            continue
        slot = parts.setdefault(c.node, {})
        slot["contact"] = tuple(a + b for a, b in zip(slot.get("contact", (0.0,) * 3),
                                                       _contact_force(c, s)))
        slot.setdefault("contact states", []).append(s.state)
    return with_totals(frame, parts)


def with_totals(frame, parts: dict) -> dict:
    """{node: {"total": the sum of its kinds' reactions, kind: ...}} in the
    frame's node order, for the nodes the ground holds (plane and space)."""
    out = {}
    for node in frame.nodes:
        if node in parts:
            kinds = [parts[node][k] for k in KINDS if k in parts[node]]
            out[node] = {"total": tuple(float(sum(v)) for v in zip(*kinds)), **parts[node]}
    return out


def _springs(frame, result) -> dict:
    return {node: tuple(-ks.get(d, 0.0) * result.displacements[node][k]
                        for k, d in enumerate(DOFS))
            for node, ks in frame.springs.items()}


def _contact_force(c, s):
    t = np.array([c.normal[1], -c.normal[0]])
    fxy = s.normal * c.normal + s.tangential * t
    return float(fxy[0]), float(fxy[1]), 0.0


def contact_values(c, s) -> dict:
    """A plane contact's numbers (full precision) under the supports
    table's names."""
    xt = abs(float(s.tangential))
    cone = c.friction * s.normal
    return {"X_n": float(s.normal), "X_t": float(s.tangential), "|X_t|": xt,
            "use": xt / cone if cone > 0 else float("nan"), "opening": float(s.opening),
            "slip": float(s.slip), "|slip|": abs(float(s.slip))}


def contact_envelope(good: dict, values, extremes) -> dict:
    """Per contact {"states": {state: [combinations]}, quantity: {side:
    (value, combination)}} over the results ``good`` that are ok;
    ``values(c, s)`` a contact's numbers, ``extremes`` (quantity, side)
    pairs — plane and space frames alike."""
    con: dict = {}
    for name, r in good.items():
        for (key, s), c in zip(r.supports.items(), r.frame.contacts):
            slot = con.setdefault(key, {"states": {}})
            slot["states"].setdefault(s.state, []).append(name)
            v = values(c, s)
            for q, side in extremes:
                best = slot.setdefault(q, {}).get(side)
                if not np.isnan(v[q]) and (best is None or (
                        v[q] > best[0] if side == "max" else v[q] < best[0])):
                    slot[q][side] = (v[q], name)
    return con


def contact_envelope_rows(contacts: dict, extremes, heads: dict, names: dict) -> list:
    """Rows of ``envelope_supports``: each contact's states and its
    quantities' extremes with their combinations (``heads``: quantity ->
    header unit; ``names``: quantity -> its header name where not itself)."""
    out = []
    for key, per in contacts.items():
        row = {"support": key,
               "states": "; ".join(f"{st}: {', '.join(names_)}"
                                   for st, names_ in per["states"].items())}
        for q, side in extremes:
            label = f"{names.get(q, q)}_{side}"
            value, name = per.get(q, {}).get(side, (float("nan"), ""))
            row[f"{label} {heads[q]}"] = value
            row[f"combination({label})"] = name
        out.append(row)
    return out


def rows(frame, result, table: str) -> list:
    """The raw rows (full precision) of one of TABLES for one result; none
    for a result that is no equilibrium."""
    check_table(table)
    if not result.displacements:
        return []
    force, length = frame.units
    unit = {"F": f"[{force}]", "M": f"[{force}·{length}]", "L": f"[{length}]"}
    if table == "supports":
        out = []
        for (k, s), c in zip(result.supports.items(), frame.contacts):
            v = contact_values(c, s)
            out.append({"support": k, "node": c.node, "state": s.state,
                        f"X_n {unit['F']}": v["X_n"], f"X_t {unit['F']}": v["X_t"],
                        f"{USE} [-]": v["use"],
                        **{f"{a} {unit['F']}": f
                           for a, f in zip(("Fx", "Fy"), _contact_force(c, s))},
                        f"opening {unit['L']}": v["opening"], f"slip {unit['L']}": v["slip"]})
        return out
    if table == "reactions":
        return _reaction_rows(frame, result, unit)
    if table == "members":
        return member_rows(frame, result, QUANTITIES, EXTREMES, _plane_unit(frame),
                           lambda name: plane_geometry(frame, name))
    return [{"node": nd, f"ux {unit['L']}": d[0], f"uy {unit['L']}": d[1], "rz [rad]": d[2]}
            for nd, d in result.displacements.items()]


def _reaction_rows(frame, result, unit) -> list:
    present = [k for k, has in zip(KINDS, (frame.fixed, frame.springs,
                                          [c for c in frame.contacts if c.other is None]))
               if has]
    units = (unit["F"], unit["F"], unit["M"])
    out = []
    for node, parts in reactions_by_node(frame, result).items():
        words = []
        if "support" in parts:
            words.append("fixed " + " ".join(d for d in DOFS if d in frame.fixed[node]))
        if "spring" in parts:
            words.append("spring " + " ".join(d for d in DOFS if d in frame.springs[node]))
        words += [f"contact {s}" for s in parts.get("contact states", [])]
        row = {"node": node, "kinds": " + ".join(words)}
        row.update({f"{f} {u}": v for f, u, v in zip(FORCES, units, parts["total"])})
        # the parts only where they differ from the total somewhere in the frame
        for kind in present if len(present) > 1 else ():
            for f, u, v in zip(FORCES, units, parts.get(kind, (0.0,) * 3)):
                if not (kind == "contact" and f == "Mz"):   # a contact carries no moment
                    row[f"{f} {kind} {u}"] = v
        out.append(row)
    return out


def _plane_unit(frame):
    """The header unit of a plane member's quantity ("[kN]", "[kN·m]", "[m]")."""
    force, length = frame.units
    units = {"N": force, "V": force, "M": f"{force}·{length}", "v": length}
    return lambda q: f"[{units[q]}]"


def plane_geometry(frame, name) -> dict:
    """A plane member's columns before its forces: its nodes and length."""
    m = frame.members[name]
    length = float(np.hypot(*(frame.nodes[m.j] - frame.nodes[m.i])))
    return {"i": m.i, "j": m.j, f"L [{frame.units[1]}]": length}


def member_rows(frame, result, quantities, extremes, unit_of, geometry) -> list:
    """The members table of either kind, one row per member: its
    ``geometry`` columns, the internal forces at i and at j (the diagrams'
    convention: ``end_forces``), then each of ``extremes`` — max and min
    along the member with the x where they occur (``extremes``).  The same
    columns in the same order for plane and space frames, the space frame
    having more quantities."""
    length = frame.units[1]
    out = []
    for name in frame.members:
        ends, ext = result.end_forces(name), result.extremes(name)
        row = {"member": name, **geometry(name)}
        for end in ("i", "j"):
            for q in quantities:
                row[f"{q}_{end} {unit_of(q)}"] = ends[end][q]
        for q in extremes:
            for side in ("max", "min"):
                row[f"{q}_{side} {unit_of(q)}"] = ext[q][side][0]
                row[f"x({q}_{side}) [{length}]"] = ext[q][side][1]
        out.append(row)
    return out


def member_envelope(good: dict) -> dict:
    """{member: {quantity: {"max": (value, x, combination), "min": ...}}}
    over the results ``good`` (all ok), from each one's ``extremes``."""
    env: dict = {}
    first = next(iter(good.values()))
    for member in first.member_forces:
        env[member] = {}
        for name, r in good.items():
            for key, ext in r.extremes(member).items():
                slot = env[member].setdefault(key, {"max": (-np.inf, 0.0, ""),
                                                    "min": (np.inf, 0.0, "")})
                if ext["max"][0] > slot["max"][0]:
                    slot["max"] = (*ext["max"], name)
                if ext["min"][0] < slot["min"][0]:
                    slot["min"] = (*ext["min"], name)
    return env


def member_envelope_rows(frame, env: dict, unit_of) -> list:
    """The rows of ``member_envelope``: per quantity its max and min, each
    with its x and its combination (plane and space frames alike)."""
    length = frame.units[1]
    out = []
    for member, per in env.items():
        if member in ("supports", "contacts"):
            continue
        row = {"member": member}
        for q, sides in per.items():
            for side in ("max", "min"):
                value, x, name = sides[side]
                row[f"{q}_{side} {unit_of(q)}"] = value
                row[f"x({q}_{side}) [{length}]"] = x
                row[f"combination({q}_{side})"] = name
        out.append(row)
    return out


def envelope(results: dict) -> dict:
    """Max/min over the results that are ok (see CombinationResults.envelope)."""
    good = {name: r for name, r in results.items() if r.ok}
    if not good:
        return {}
    env = member_envelope(good)
    sup: dict = {}
    for name, r in good.items():
        for node, parts in reactions_by_node(r.frame, r).items():
            for comp, v in zip(FORCES, parts["total"]):
                slot = sup.setdefault(node, {}).setdefault(
                    comp, {"max": (-np.inf, name), "min": (np.inf, name)})
                if v > slot["max"][0]:
                    slot["max"] = (v, name)
                if v < slot["min"][0]:
                    slot["min"] = (v, name)
    env["supports"] = sup
    env["contacts"] = contact_envelope(good, contact_values, CONTACT_EXTREMES)
    return env


def envelope_rows(frame, env: dict, table: str) -> list:
    """Raw rows of ``envelope`` (members), ``envelope_reactions`` (nodes)
    or ``envelope_supports`` (contacts)."""
    force, length = frame.units
    if table == "envelope":
        return member_envelope_rows(frame, env, _plane_unit(frame))
    if table == "envelope_supports":
        f, L = f"[{force}]", f"[{length}]"
        return contact_envelope_rows(env.get("contacts", {}), CONTACT_EXTREMES,
                                     {"X_n": f, "|X_t|": f, "use": "[-]", "opening": L,
                                      "|slip|": L}, {"use": USE})
    unit = {"Fx": force, "Fy": force, "Mz": f"{force}·{length}"}
    return reaction_envelope_rows(env.get("supports", {}), FORCES, lambda f: f"[{unit[f]}]")


def reaction_envelope_rows(supports: dict, forces, unit_of) -> list:
    """One row per node the ground holds: each reaction component's max and
    min with its combination (``unit_of(component)``: the header's unit);
    plane and space frames alike."""
    out = []
    for node, per in supports.items():
        row = {"node": node}
        for f in forces:
            for side in ("max", "min"):
                row[f"{f}_{side} {unit_of(f)}"] = per[f][side][0]
                row[f"combination({f}_{side})"] = per[f][side][1]
        out.append(row)
    return out


def engineering(table_rows: list, frame, digits: int | None = DIGITS) -> list:
    """The rows rounded for reading (module docstring); ``digits=None``: as
    they are."""
    if digits is None or not table_rows:
        return table_rows
    columns = {}
    for key in table_rows[0]:
        m = _UNIT.search(key)
        if m and all(isinstance(r[key], (int, float)) and not isinstance(r[key], bool)
                     for r in table_rows):
            columns[key] = (m.group(1), np.array([r[key] for r in table_rows], float))
    scale: dict = {}
    for unit, vals in columns.values():
        finite = np.abs(vals[np.isfinite(vals)])
        scale[unit] = max(scale.get(unit, 0.0), float(finite.max(initial=0.0)))
    force, length = frame.units
    size = _size(frame)
    if f"{force}·{length}" in scale:
        scale[f"{force}·{length}"] = max(scale[f"{force}·{length}"],
                                         scale.get(force, 0.0) * size)
    if "rad" in scale and size > 0:
        scale["rad"] = max(scale["rad"], scale.get(length, 0.0) / size)
    if "-" in scale:      # a share (of a friction cone): its whole is 1
        scale["-"] = max(scale["-"], 1.0)
    out = [dict(r) for r in table_rows]
    for key, (unit, vals) in columns.items():
        vals = np.where(np.abs(vals) <= NOISE * scale[unit], 0.0, vals)
        for r, v in zip(out, round_column(vals, digits)):
            r[key] = v
    return out


def _size(frame) -> float:
    """The frame's size: the diagonal of its nodes' bounding box (plane or
    space frame)."""
    xyz = np.array([tuple(v) for v in frame.nodes.values()], float)
    return float(np.linalg.norm(np.ptp(xyz, axis=0))) if len(xyz) else 0.0


def csv_rows(table_rows: list, digits: int | None) -> list:
    """Rows as CSV cells: rounded numbers in plain decimals ("0", "1234.6",
    "0.00001234", never "-0.0" or "1e-05"); raw ones (``digits=None``) as
    Python writes them, which read back to the same float."""
    if digits is None:
        return table_rows
    return [{k: (np.format_float_positional(v, trim="-")
                 if isinstance(v, float) else v) for k, v in r.items()} for r in table_rows]


def write_tables(folder, tables: dict, digits: int | None) -> list:
    """{name: rows} as folder/name.csv, each written atomically; the paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for table, table_rows in tables.items():
        path = folder / f"{table}.csv"
        write_csv_atomic(path, csv_rows(table_rows, digits),
                         list(table_rows[0]) if table_rows else ["empty"])
        paths.append(str(path))
    return paths


def dataframe(table_rows: list):
    """The rows as a pandas DataFrame (the ``tables`` extra installs pandas)."""
    try:
        import pandas as pd
    except ImportError:
        raise BackendUnavailableError(
            "to_dataframe needs pandas (pip install 'qpcontact[tables]' or pip install pandas); "
            "to_csv writes the same tables without it") from None
    return pd.DataFrame(table_rows)
