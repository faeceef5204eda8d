"""Tables of a space frame's results, in the plane frame's form
(:mod:`.tables`: lists of dicts, units in every numeric header, rounded by
:func:`.tables.engineering`, written by :func:`.tables.write_tables`).

Tables of one result:

* ``supports``: each contact — state, X_n, the friction force along the
  contact's tangents (X_t1, X_t2) and its size |X_t|, the share of the
  model's own friction cone it uses (at most 1; 1 where it slips), its
  friction against Coulomb's circle |X_t| / (f X_n), the contact's whole force on the
  structure in global components (Fx, Fy, Fz), the opening, the slip along
  (t1, t2) and its size, and the tangents themselves;
* ``reactions``: one row per node the ground holds — the total force and
  moment of its bilateral support, spring and contacts on the structure
  (global axes, six components), with each kind's part when the frame has
  more than one kind;
* ``members``: the plane frame's columns in its order
  (:func:`.tables.member_rows`) — the member's ends, length and local y and
  z axes, the internal forces N, Vy, Vz, T, My, Mz at i and at j (N tension
  positive: ``end_forces``), and the max and min along the member of each
  and of the deflections v, w, with where they occur (``extremes``);
* ``displacements``: ux, uy, uz, rx, ry, rz per node.

Over combinations (:class:`~.results.CombinationResults`, which takes its
table functions from the result's ``table_kit``): the same tables with a
"combination" column, ``envelope`` (each member's internal forces and
deflections: max and min along it over the combinations that are ok, each
with its x and its combination, as the plane frame's),
``envelope_reactions`` (each node's six total reaction components, likewise),
``envelope_supports`` (each contact's largest and smallest X_n, largest |X_t|,
utilisation, opening and slip, and the states it takes) and ``combinations``.

Both shares are NaN where there is no cone to use (a separated contact, or
f = 0).  The cone use is the model's: on Coulomb's circle |X_t| / (f X_n),
on a polygon the most loaded facet's share max_k(-d_k·X_t) / (reach f X_n)
— at most 1 by construction, 1 where the contact slips.  The ratio to
Coulomb's circle is reported beside it, because a circumscribed m-gon lets
|X_t| reach f X_n / cos(π/m) between its facet directions: a slipping pad
reads up to 1/cos(π/m) there (1.0196 for m = 16) — the polygon's extra
friction over Coulomb's, not a violation of the model.
"""

from __future__ import annotations

import numpy as np

from .tables import (KINDS, USE, check_table, contact_envelope, contact_envelope_rows,
                     member_envelope, member_envelope_rows, member_rows, reaction_envelope_rows,
                     with_totals)

TABLES = ("supports", "reactions", "members", "displacements")
#: the tables of a CombinationResults besides TABLES
COMBINED = ("envelope", "envelope_reactions", "envelope_supports", "combinations")
FORCES = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
#: the contact quantities whose extremes envelope_supports gives, and which side
CONTACT_EXTREMES = (("X_n", "max"), ("X_n", "min"), ("|X_t|", "max"), ("use", "max"),
                    ("circle", "max"), ("opening", "max"), ("|slip|", "max"))
#: the share of the model's own cone used (<= 1), and the friction against
#: Coulomb's circle (up to 1/cos(π/m) on a circumscribed m-gon)
CIRCLE = "|X_t|/(f X_n) on Coulomb's circle"
NAMES = {"use": USE, "circle": CIRCLE}


def units(frame) -> dict:
    """Header units by kind of quantity: F force, M moment, L length."""
    force, length = frame.units
    return {"F": f"[{force}]", "M": f"[{force}·{length}]", "L": f"[{length}]", "-": "[-]"}


def vector_text(v) -> str:
    """A direction in global components, as "(0, 0.7071, -0.7071)"."""
    return "(" + ", ".join(f"{float(c) + 0.0:.4g}" for c in np.round(v, 4) + 0.0) + ")"


def contact_force(s) -> np.ndarray:
    """A contact's force on its node in global components: X_n n + X_t."""
    return s.normal * np.cross(s.t1, s.t2) + s.tangential_global


def contact_values(c, s) -> dict:
    """A contact's numbers (full precision) under the supports table's names."""
    xt = float(np.hypot(*s.tangential))
    cone = c.friction * s.normal
    circle = xt / cone if cone > 0 else float("nan")
    use = circle if s.cone_use is None or not cone > 0 else float(s.cone_use)
    return {"X_n": float(s.normal), "X_t1": float(s.tangential[0]),
            "X_t2": float(s.tangential[1]), "|X_t|": xt, "use": use, "circle": circle,
            "opening": float(s.opening),
            "slip_t1": float(s.slip[0]), "slip_t2": float(s.slip[1]),
            "|slip|": float(np.hypot(*s.slip))}


def reactions_by_node(frame, result) -> dict:
    """{node: {"total": 6-tuple, "support"|"spring"|"contact": 6-tuple for the
    kinds at that node, "contact states": [...]}}: what the ground exerts on
    each node it holds, global axes (a contact carries no moment)."""
    dofs = frame.DOFS
    parts: dict = {}
    for node, r in result.reactions.items():
        parts.setdefault(node, {})["support"] = tuple(float(v) for v in r)
    for node, ks in frame.springs.items():
        parts.setdefault(node, {})["spring"] = tuple(
            -ks.get(d, 0.0) * float(result.displacements[node][k]) for k, d in enumerate(dofs))
    for s, c in zip(result.supports.values(), frame.contacts):
        if c.other is not None:     # a pair: a force between two parts, not a reaction
            continue
        slot = parts.setdefault(c.node, {})
        before = slot.get("contact", (0.0,) * 6)
        slot["contact"] = tuple(float(a + b) for a, b in
                                zip(before, np.r_[contact_force(s), 0.0, 0.0, 0.0]))
        slot.setdefault("contact states", []).append(s.state)
    return with_totals(frame, parts)


def rows(frame, result, table: str) -> list:
    """The raw rows (full precision) of one of TABLES for one result; none for
    a result that is no equilibrium."""
    check_table(table, TABLES)
    if not result.displacements:
        return []
    u = units(frame)
    if table == "supports":
        return _support_rows(frame, result, u)
    if table == "reactions":
        return _reaction_rows(frame, result, u)
    if table == "members":
        return _member_rows(frame, result, u)
    rot = "[rad]"
    return [{"node": nd, **{f"{d} {u['L'] if d[0] == 'u' else rot}": float(v)
                            for d, v in zip(frame.DOFS, disp)}}
            for nd, disp in result.displacements.items()]


def _support_rows(frame, result, u) -> list:
    out = []
    for (key, s), c in zip(result.supports.items(), frame.contacts):
        v = contact_values(c, s)
        force = contact_force(s)
        out.append({"support": key, "node": c.node, "state": s.state,
                    f"X_n {u['F']}": v["X_n"], f"X_t1 {u['F']}": v["X_t1"],
                    f"X_t2 {u['F']}": v["X_t2"], f"|X_t| {u['F']}": v["|X_t|"],
                    f"{USE} {u['-']}": v["use"], f"{CIRCLE} {u['-']}": v["circle"],
                    **{f"{a} {u['F']}": float(f) for a, f in zip(FORCES, force)},
                    f"opening {u['L']}": v["opening"], f"slip_t1 {u['L']}": v["slip_t1"],
                    f"slip_t2 {u['L']}": v["slip_t2"], f"|slip| {u['L']}": v["|slip|"],
                    "t1": vector_text(s.t1), "t2": vector_text(s.t2)})
    return out


def _reaction_rows(frame, result, u) -> list:
    present = [k for k, has in zip(KINDS, (frame.fixed, frame.springs,
                                          [c for c in frame.contacts if c.other is None]))
               if has]
    heads = [f"{f} {u['F'] if f[0] == 'F' else u['M']}" for f in FORCES]
    out = []
    for node, parts in reactions_by_node(frame, result).items():
        words = []
        if "support" in parts:
            words.append("fixed " + " ".join(d for d in frame.DOFS if d in frame.fixed[node]))
        if "spring" in parts:
            words.append("spring " + " ".join(d for d in frame.DOFS if d in frame.springs[node]))
        words += [f"contact {s}" for s in parts.get("contact states", [])]
        row = {"node": node, "kinds": " + ".join(words)}
        row.update(dict(zip(heads, parts["total"])))
        # the parts only where a frame has more than one kind of support
        for kind in present if len(present) > 1 else ():
            for f, head, v in zip(FORCES, heads, parts.get(kind, (0.0,) * 6)):
                if not (kind == "contact" and f[0] == "M"):   # a contact carries no moment
                    row[head.replace(" ", f" {kind} ", 1)] = v
        out.append(row)
    return out


def _quantity_unit(frame):
    """The header unit of a space member's quantity: forces, moments, lengths."""
    u = units(frame)
    return lambda q: u["M"] if q in ("T", "My", "Mz") else u["L"] if q in ("v", "w") else u["F"]


def _member_rows(frame, result, u) -> list:
    from ..mechanics.space_element import EXTREMES, QUANTITIES, axes

    def geometry(name):
        m = frame.members[name]
        xi, xj = frame.nodes[m["i"]], frame.nodes[m["j"]]
        R = axes(xi, xj, m["ref"], m["roll"])[0]
        return {"i": m["i"], "j": m["j"], f"L {u['L']}": float(np.linalg.norm(xj - xi)),
                "y axis": vector_text(R[1]), "z axis": vector_text(R[2])}

    return member_rows(frame, result, QUANTITIES, EXTREMES, _quantity_unit(frame), geometry)


def envelope(results: dict) -> dict:
    """Max/min over the results that are ok, full precision: per member
    {"N"|...|"Mz"|"v"|"w": {"max": (value, x, combination), "min": ...}}
    (:func:`.tables.member_envelope`); under
    "supports" per node {"Fx"|...|"Mz": ...} of its total reaction; under
    "contacts" per contact {"X_n"|"|X_t|"|"use"|"opening"|"|slip|": ...} and
    "states" {state: [combinations]}."""
    good = {name: r for name, r in results.items() if r.ok}
    env: dict = {}
    if not good:
        return env

    def put(slot, key, value, name, sides=("max", "min")):
        s = slot.setdefault(key, {})
        for side in sides:
            if side not in s or (value > s[side][0] if side == "max" else value < s[side][0]):
                s[side] = (value, name)

    env.update(member_envelope(good))
    sup = {}
    for name, r in good.items():
        for node, parts in reactions_by_node(r.frame, r).items():
            for f, v in zip(FORCES, parts["total"]):
                put(sup.setdefault(node, {}), f, v, name)
    env["supports"] = sup
    env["contacts"] = contact_envelope(good, contact_values, CONTACT_EXTREMES)
    return env


def envelope_rows(frame, env: dict, table: str) -> list:
    """Raw rows of ``envelope`` (members), ``envelope_reactions`` (nodes) or
    ``envelope_supports`` (contacts)."""
    u = units(frame)
    if table == "envelope":
        return member_envelope_rows(frame, env, _quantity_unit(frame))
    if table == "envelope_reactions":
        return reaction_envelope_rows(env.get("supports", {}), FORCES,
                                      lambda f: u["F"] if f[0] == "F" else u["M"])
    heads = {"X_n": u["F"], "|X_t|": u["F"], "use": u["-"], "circle": u["-"], "opening": u["L"],
             "|slip|": u["L"]}
    return contact_envelope_rows(env.get("contacts", {}), CONTACT_EXTREMES, heads, NAMES)
