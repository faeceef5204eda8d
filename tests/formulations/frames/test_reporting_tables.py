"""Frame tables: every value against the result it prints, rounded
by the rule docs/frames.md states (written out here on its own: string
formatting to the column's decimals, not notation.round_column), units in
every header, one reaction row per node whose parts sum to its total and
whose totals balance the loads, envelopes against a brute-force pass over
the combinations' diagrams, CSV text free of "-0" and rounding noise,
atomic CSV writes that read back, DataFrames equal to the rows."""

from __future__ import annotations

import csv
import math
import re

import numpy as np
import pytest

from formulations.frames import Frame
from qpcontact.core.errors import BackendUnavailableError, InvalidOptionError

from tests.helpers.figures import csv_reads_back, keeps_previous_file, rounded_by_hand

E, A, I = 2e8, 0.01, 1e-4          # kN/m², m², m⁴
K_RZ, K_B = 5e3, 1e5               # the spring at A (kN·m/rad), B's contact stiffness (kN/m)
XY = {"A": (0.0, 0.0), "B": (4.0, 0.0), "C": (8.0, 0.0), "D": (8.0, 3.0)}
SIZE = math.hypot(8.0, 3.0)        # the nodes' bounding-box diagonal
COMBOS = {"D": {"D": 1.0}, "1.2D+1.6L": {"D": 1.2, "L": 1.6}, "0.9D+1.6W": {"D": 0.9, "W": 1.6},
          "uplift": {"D": 0.1, "W": 10.0}}
UNIT = re.compile(r"\[(kN|kN·m|m|rad|-)\]$")
LABELS = {"member", "node", "support", "state", "kinds", "combination", "ok", "route", "message",
          "i", "j"}


def _frame():
    """A beam A-B-C with a column C-D.  A: a pin in ux, a rotational spring
    and an elastic vertical contact (three kinds at one node); B: an elastic
    frictional contact (lifts off under wind); C: a rigid frictionless one."""
    fr = Frame(units=("kN", "m"))
    for name, (x, y) in XY.items():
        fr.add_node(name, x, y)
    fr.add_member("A", "B", E, A, I, name="AB")
    fr.add_member("B", "C", E, A, I, name="BC")
    fr.add_member("C", "D", E, A, I, name="CD")
    fr.add_support("A", fix=("ux",))
    fr.add_spring("A", rz=K_RZ)
    fr.add_contact("A", normal=(0.0, 1.0), stiffness=K_B)
    fr.add_contact("B", normal=(0.0, 1.0), friction=0.3, stiffness=K_B)
    fr.add_contact("C", normal=(0.0, 1.0))
    fr.add_distributed_load("AB", wy=-10.0, case="D")
    fr.add_distributed_load("BC", wy=-10.0, case="D")
    fr.add_load("D", fy=-50.0, case="D")
    fr.add_point_load("BC", 1.0, fy=-20.0, case="L")
    fr.add_load("D", fx=8.0, case="W")
    fr.add_load("B", fy=30.0, case="W")
    return fr


def _loads(combo):
    """The resultant (Fx, Fy) of the applied loads, by hand."""
    fx = 8.0 * combo.get("W", 0.0)
    fy = -130.0 * combo.get("D", 0.0) - 20.0 * combo.get("L", 0.0) + 30.0 * combo.get("W", 0.0)
    return fx, fy


@pytest.fixture(scope="module")
def res():
    out = _frame().solve_combinations(COMBOS)
    assert out.failed == ["uplift"], [r.message for r in out.values()]
    return out


# -- the references: the results' own values, and the documented rounding ---------------

def _reaction_parts(fr, r):
    """{node: {kind: (Fx, Fy, Mz)}} from the result's attributes by hand."""
    parts = {"A": {"support": r.reactions["A"],
                   "spring": (0.0, 0.0, -K_RZ * r.displacements["A"][2])}}
    for node in ("A", "B", "C"):
        s = r.supports[node]    # normal (0, 1), tangent (1, 0)
        parts.setdefault(node, {})["contact"] = (s.tangential, s.normal, 0.0)
    return parts


def _expected(fr, r, table):
    """The table's raw rows built from the result objects."""
    if table == "reactions":
        rows = []
        for node, parts in _reaction_parts(fr, r).items():
            total = [sum(p[k] for p in parts.values()) for k in range(3)]
            row = {"node": node, "Fx [kN]": total[0], "Fy [kN]": total[1], "Mz [kN·m]": total[2]}
            for kind in ("support", "spring", "contact"):
                p = parts.get(kind, (0.0, 0.0, 0.0))
                row.update({f"Fx {kind} [kN]": p[0], f"Fy {kind} [kN]": p[1]})
                if kind != "contact":
                    row[f"Mz {kind} [kN·m]"] = p[2]
            rows.append(row)
        return rows
    if table == "members":
        rows = []
        for m in fr.members:
            x, *qs = r.diagram(m, 201)
            xe, *ends = r.diagram(m, 2)
            mm = fr.members[m]
            (xi, yi), (xj, yj) = fr.nodes[mm.i], fr.nodes[mm.j]
            row = {"member": m, "i": mm.i, "j": mm.j, "L [m]": math.hypot(xj - xi, yj - yi)}
            for end, k in (("i", 0), ("j", -1)):
                row.update({f"{q}_{end} [{u}]": float(v[k])
                            for q, u, v in zip("NVM", ("kN", "kN", "kN·m"), ends)})
            for q, u, v in zip("NV", ("kN", "kN"), qs):
                row.update({f"{q}_max [{u}]": v.max(), f"x({q}_max) [m]": x[v.argmax()],
                            f"{q}_min [{u}]": v.min(), f"x({q}_min) [m]": x[v.argmin()]})
            for side in ("max", "min"):
                value, at = _moment_extreme(r, m, side)
                row.update({f"M_{side} [kN·m]": value, f"x(M_{side}) [m]": at})
            rows.append(row)
        return rows
    if table == "displacements":
        return [{"node": n, "ux [m]": d[0], "uy [m]": d[1], "rz [rad]": d[2]}
                for n, d in r.displacements.items()]
    # the contact force in global components, X_n n + X_t t with t = (n_y, -n_x)
    # (the cone use's column, NaN where there is no cone, is checked by itself)
    return [{"support": k, "node": c.node, "X_n [kN]": s.normal, "X_t [kN]": s.tangential,
             "Fx [kN]": s.normal * c.normal[0] + s.tangential * c.normal[1],
             "Fy [kN]": s.normal * c.normal[1] - s.tangential * c.normal[0],
             "opening [m]": s.opening, "slip [m]": s.slip}
            for (k, s), c in zip(r.supports.items(), fr.contacts)]


def _moment_extreme(r, m, side):
    """The member's largest (or smallest) moment as ``extremes`` gives it,
    once checked against the diagram at 20001 sections: at least the
    densest sample's and above it by no more than a parabola between two
    samples can rise, |w| h²/8 (every load here is at most 25 kN/m) — the
    span moment between samples that 201 sections alone miss."""
    x, _, _, M = r.diagram(m, 20001)
    pick = np.argmax if side == "max" else np.argmin
    value, at = r.extremes(m)["M"][side]
    h = x[1] - x[0]
    sign = 1.0 if side == "max" else -1.0
    assert -1e-12 * max(1.0, abs(value)) <= sign * (value - M[pick(M)]) <= 25.0 * h * h / 8
    assert abs(at - x[pick(M)]) <= h or abs(value - M[pick(M)]) <= 1e-12 * abs(value)
    return value, at


def _rounded(rows, digits=5):
    """docs/frames.md's rounding rule by hand (figure_checks.rounded_by_hand)."""
    return rounded_by_hand(rows, UNIT, SIZE, digits)


def _numbers(rows, keys=None):
    return [(k, r[k]) for r in rows for k in (keys or r)
            if isinstance(r[k], float)]


# -- the tests --------------------------------------------------------------------------

@pytest.mark.parametrize("table", ["supports", "reactions", "members", "displacements"])
def test_every_value_is_the_results_value_rounded_as_documented(res, table):
    fr = res["D"].frame
    for name, r in res.items():
        if not r.ok:
            assert r.rows(table) == [] and r.rows(table, None) == []
            continue
        raw = _expected(fr, r, table)
        got_raw = r.rows(table, digits=None)
        assert [{k: v for k, v in row.items() if k in raw[0]} for row in got_raw] == raw
        got = r.rows(table)
        assert [{k: v for k, v in row.items() if k in raw[0]} for row in got] == _rounded(raw)
        assert not any(math.copysign(1.0, v) < 0 and v == 0 for _, v in _numbers(got))
    # one table over the combinations is rounded per column over all of them
    raw = [{"combination": n, **row} for n, r in res.items() if r.ok
           for row in _expected(fr, r, table)]
    got = res.rows(table)
    assert [row["combination"] for row in got] == [row["combination"] for row in raw]
    assert [{k: v for k, v in row.items() if k in raw[0]} for row in got] == _rounded(raw)


def test_the_rounding_has_something_to_remove(res):
    """The raw tables of this frame hold -0.0 and rounding noise (the beam's
    axial force, the column's moment), so the tests above can fail."""
    r = res["D"]
    noisy = [v for t in ("members", "reactions") for _, v in _numbers(r.rows(t, None))
             if v == 0 and math.copysign(1, v) < 0 or 0 < abs(v) < 1e-9]
    assert len(noisy) >= 3, noisy
    assert r.rows("members")[2]["M_i [kN·m]"] == 0.0 != r.rows("members", None)[2]["M_i [kN·m]"]


def test_units_in_every_header(res, tmp_path):
    tables = {t: res.rows(t) for t in ("supports", "reactions", "members", "displacements",
                                        "envelope", "envelope_reactions", "combinations")}
    tables.update({f"D/{t}": res["D"].rows(t) for t in ("supports", "reactions", "members",
                                                         "displacements")})
    for name, rows in tables.items():
        assert rows, name
        for key in rows[0]:
            numeric = all(isinstance(r[key], float) for r in rows)
            if numeric:
                assert UNIT.search(key), (name, key)
            else:
                assert key in LABELS or re.fullmatch(r"combination\([NVMvFxyz]+_(max|min)\)", key), \
                    (name, key)
    # the frame's own units, not kN and m
    fr = Frame(units=("N", "mm"))
    fr.add_node("P", 0.0, 0.0)
    fr.add_node("Q", 1000.0, 0.0)
    fr.add_member("P", "Q", 2e5, 5e3, 4e7, name="PQ")
    fr.add_support("P")
    fr.add_contact("Q", normal=(-1.0, 0.0), gap=10.0)
    fr.add_load("Q", fy=-1e3)
    heads = [k for t in ("reactions", "members", "displacements") for k in fr.solve().rows(t)[0]]
    assert "Mz [N·mm]" in heads and "x(M_max) [mm]" in heads and "ux [mm]" in heads
    assert not any("kN" in h or "[m]" in h for h in heads)


def test_a_moment_alone_in_its_column_is_noise_against_the_forces_times_the_size():
    """A cantilever pulled along its (inclined) axis: the clamp's moment is
    rounding of zero (1e-8 N·mm beside 1e4 N over 5 m), although it is the
    largest value of its column; its tip rotation likewise."""
    fr = Frame(units=("N", "mm"))
    fr.add_node("P", 0.0, 0.0)
    fr.add_node("Q", 3000.0, 4000.0)
    fr.add_member("P", "Q", 2e5, 5e3, 4e7, name="PQ")
    fr.add_support("P")
    fr.add_contact("Q", normal=(-1.0, 0.0), gap=1e3)
    fr.add_load("Q", fx=6e3, fy=8e3)
    r = fr.solve()
    raw = r.rows("reactions", None)[0]
    assert raw["Mz [N·mm]"] != 0.0                                      # noise to remove
    row = r.rows("reactions")[0]
    assert (row["Fx [N]"], row["Fy [N]"], row["Mz [N·mm]"]) == (-6000.0, -8000.0, 0.0)
    assert r.rows("displacements")[1]["rz [rad]"] == 0.0
    assert r.rows("displacements")[1]["ux [mm]"] == 0.03


def test_one_reaction_row_per_node_with_its_parts(res):
    for name, r in res.items():
        if not r.ok:
            continue
        rows = r.rows("reactions", None)
        assert [row["node"] for row in rows] == ["A", "B", "C"]
        a = rows[0]
        assert a["kinds"] == f"fixed ux + spring rz + contact {r.supports['A'].state}"
        for f, u in (("Fx", "kN"), ("Fy", "kN"), ("Mz", "kN·m")):
            parts = [a.get(f"{f} {kind} [{u}]", 0.0) for kind in ("support", "spring", "contact")]
            assert a[f"{f} [{u}]"] == pytest.approx(sum(parts), abs=1e-12)
        # the three kinds each carry something at A: the pin's Fx where a
        # horizontal load acts (under gravity alone nothing moves along x, so
        # it is zero by statics: before, its "something" was 4e-35 of rounding)
        assert a["Mz spring [kN·m]"] != 0
        if _loads(COMBOS[name])[0]:
            assert a["Fx support [kN]"] != 0
        else:
            assert abs(a["Fx support [kN]"]) <= 1e-12 * abs(a["Fy [kN]"])
        assert a["Fy contact [kN]"] > 0
        # the totals balance the loads (global statics, by hand)
        fx, fy = _loads(COMBOS[name])
        assert sum(row["Fx [kN]"] for row in rows) == pytest.approx(-fx, abs=1e-9)
        assert sum(row["Fy [kN]"] for row in rows) == pytest.approx(-fy, abs=1e-9)
        # the per-support view is kept, the per-node one sums it
        sr, by_node = r.support_reactions, r.reactions_by_node
        assert set(sr) == {"A", "A (spring)", "A (contact)", "B", "C"}
        total = np.sum([sr["A"], sr["A (spring)"], sr["A (contact)"]], axis=0)
        np.testing.assert_allclose(by_node["A"]["total"], total, rtol=0, atol=1e-12)
        assert by_node["C"]["total"] == sr["C"]
    assert res["0.9D+1.6W"].supports["B"].state == "separated"
    assert res["0.9D+1.6W"].rows("reactions")[1]["kinds"] == "contact separated"


def test_envelopes_against_every_combinations_diagrams(res):
    fr = res["D"].frame
    ok = {n: r for n, r in res.items() if r.ok}
    raw, brute = res.rows("envelope", None), []
    for m, row in zip(fr.members, raw):
        b = {"member": m}
        for k, q in enumerate("NV"):
            u = "kN"
            d = {n: r.diagram(m, 201) for n, r in ok.items()}
            hi = max(d, key=lambda n: d[n][k + 1].max())
            lo = min(d, key=lambda n: d[n][k + 1].min())
            b[f"{q}_max [{u}]"] = d[hi][k + 1].max()
            b[f"{q}_min [{u}]"] = d[lo][k + 1].min()
            # the combination named attains the extreme, at the x given
            for side, pick in (("max", np.argmax), ("min", np.argmin)):
                named = d[row[f"combination({q}_{side})"]]
                x, v = named[0], named[k + 1]
                assert v[pick(v)] == row[f"{q}_{side} [{u}]"]
                assert x[pick(v)] == row[f"x({q}_{side}) [m]"]
        for side, pick in (("max", max), ("min", min)):
            each = {n: _moment_extreme(r, m, side) for n, r in ok.items()}
            best = pick(each, key=lambda n: each[n][0])
            b[f"M_{side} [kN·m]"] = each[best][0]
            assert each[row[f"combination(M_{side})"]] == (row[f"M_{side} [kN·m]"],
                                                           row[f"x(M_{side}) [m]"])
        assert {k: row[k] for k in b} == b
        brute.append(b)
    got = res.rows("envelope")
    assert [{k: row[k] for k in brute[0]} for row in got] == _rounded(brute)
    # reactions: per node, max/min of the hand-built totals over the combinations
    totals = {n: {node: [sum(p[k] for p in parts.values()) for k in range(3)]
                  for node, parts in _reaction_parts(fr, r).items()} for n, r in ok.items()}
    rows = res.rows("envelope_reactions", None)
    assert [row["node"] for row in rows] == ["A", "B", "C"]
    for row in rows:
        for k, (f, u) in enumerate((("Fx", "kN"), ("Fy", "kN"), ("Mz", "kN·m"))):
            vals = [totals[n][row["node"]][k] for n in ok]
            assert row[f"{f}_max [{u}]"] == pytest.approx(max(vals), abs=1e-12)
            assert row[f"{f}_min [{u}]"] == pytest.approx(min(vals), abs=1e-12)
            assert totals[row[f"combination({f}_max)"]][row["node"]][k] == \
                pytest.approx(max(vals), abs=1e-12)
    assert min(row["Fy_min [kN]"] for row in rows) == 0.0     # B lifts off under wind
    assert all(row["combination"] != "uplift" for row in res.rows("members"))
    assert "uplift" not in {v for row in got for k, v in row.items() if k.startswith("comb")}


def test_csv_text_has_no_minus_zero_no_noise_and_reads_back(res, tmp_path):
    paths = res.to_csv(tmp_path)
    assert sorted(p.split("/")[-1] for p in paths) == sorted(
        f"{t}.csv" for t in ("supports", "reactions", "members", "displacements", "envelope",
                             "envelope_reactions", "envelope_supports", "combinations"))
    assert not list(tmp_path.glob("*.tmp"))
    csv_reads_back(res, paths, nan=True, floor=1e-6)   # nan: the cone use without a cone
    assert "uplift,False" in (tmp_path / "combinations.csv").read_text()
    # full precision on request: the raw floats, read back to the bit
    raw_dir = tmp_path / "raw"
    res["D"].to_csv(raw_dir, digits=None)
    raw = res["D"].rows("members", None)
    with open(raw_dir / "members.csv", newline="") as fh:
        back = list(csv.DictReader(fh))
    assert [float(b["M_max [kN·m]"]) for b in back] == [r["M_max [kN·m]"] for r in raw]


def test_csv_is_written_atomically(res, tmp_path):
    """A write that fails before its rename leaves the previous file whole."""
    res["D"].to_csv(tmp_path)
    assert keeps_previous_file(lambda: res["1.2D+1.6L"].to_csv(tmp_path),
                               tmp_path / "members.csv")


def test_dataframe_equals_the_rows(res):
    pytest.importorskip("pandas",
                        reason="pandas is not installed (pip install 'qpcontact[tables]')")
    for table in ("members", "reactions", "envelope", "envelope_reactions"):
        df = res.to_dataframe(table)
        rows = res.rows(table)
        assert list(df.columns) == list(rows[0])
        assert df.to_dict("records") == rows
    df = res["D"].to_dataframe("displacements", digits=None)
    assert df.to_dict("records") == res["D"].rows("displacements", None)


def test_dataframe_without_pandas_says_what_to_install(res, monkeypatch):
    monkeypatch.setitem(__import__("sys").modules, "pandas", None)
    with pytest.raises(BackendUnavailableError, match=r"pandas.*tables"):
        res["D"].to_dataframe("members")
    with pytest.raises(BackendUnavailableError, match="to_csv"):
        res.to_dataframe("envelope")


def test_unknown_table_names_the_tables(res):
    with pytest.raises(InvalidOptionError, match="envelope_reactions"):
        res.rows("nope")
    with pytest.raises(InvalidOptionError, match="displacements"):
        res["uplift"].rows("nope")


def test_the_contacts_cone_use_and_envelope_as_the_space_frames(res):
    """The plane supports table has the space frame's cone-use column
    (|X_t| / (f X_n), NaN without a cone) and the combinations an
    ``envelope_supports`` table: each contact's states and extremes, by
    hand from the results."""
    use = "cone use (the model's cone) [-]"
    good = {n: r for n, r in res.items() if r.ok}
    for r in good.values():
        for row, (key, s), c in zip(r.rows("supports", None), r.supports.items(),
                                    r.frame.contacts):
            if c.friction > 0 and s.normal > 0:
                assert row[use] == abs(s.tangential) / (c.friction * s.normal)
                assert row[use] <= 1.0 + 1e-12
            else:
                assert math.isnan(row[use])
    rows = {row["support"]: row for row in res.rows("envelope_supports", None)}
    assert set(rows) == {"A", "B", "C"}
    for key, row in rows.items():
        normals = {n: r.supports[key].normal for n, r in good.items()}
        top, low = max(normals, key=normals.get), min(normals, key=normals.get)
        assert row["X_n_max [kN]"] == normals[top] and row["combination(X_n_max)"] == top
        assert row["X_n_min [kN]"] == normals[low] and row["combination(X_n_min)"] == low
        states = {}
        for n, r in good.items():
            states.setdefault(r.supports[key].state, []).append(n)
        assert row["states"] == "; ".join(f"{st}: {', '.join(ns)}" for st, ns in states.items())
    b = {n: abs(r.supports["B"].tangential) / (0.3 * r.supports["B"].normal)
         for n, r in good.items() if r.supports["B"].normal > 0}
    assert rows["B"][f"{use[:-4]}_max [-]"] == max(b.values())
    assert math.isnan(rows["C"][f"{use[:-4]}_max [-]"])       # frictionless: no cone


@pytest.mark.parametrize("kind", ["plane", "space"])
def test_a_shear_extreme_inside_a_load_that_changes_sign_is_exact(kind):
    """A simply supported span L under w(x) = w1 + (w2 − w1) x/L (w1 < 0 <
    w2): V = R_A + ∫w is least where w = 0, at x0 = L w1/(w1 − w2), with
    R_A = −L (2 w1 + w2)/6 (moments about B).  x0 falls between the 201
    samples: before, the extreme was the nearest sample's, 1e-5 of V short
    of it (the unsafe side), in `extremes` and the envelope alike."""
    from formulations.frames import SpaceFrame

    L, w1, w2 = 7.3, -20.0, 10.0
    x0 = L * w1 / (w1 - w2)
    R_A = -L * (2 * w1 + w2) / 6
    V_min = R_A + w1 * x0 + (w2 - w1) * x0 ** 2 / (2 * L)
    if kind == "plane":
        fr = Frame()
        fr.add_node("A", 0.0, 0.0)
        fr.add_node("B", L, 0.0)
        fr.add_member("A", "B", E, A, I, name="AB")
        fr.add_support("A", fix=("ux", "uy"))
        fr.add_support("B", fix=("uy",))
        fr.add_distributed_load("AB", wy=w1, wy2=w2, case="D")
        V = "V"
    else:
        fr = SpaceFrame()
        fr.add_node("A", 0.0, 0.0, 0.0)
        fr.add_node("B", L, 0.0, 0.0)
        fr.add_member("A", "B", E, A, I, I, G=8e7, J=I, name="AB")
        fr.add_support("A", fix=("ux", "uy", "uz", "rx", "rz"))
        fr.add_support("B", fix=("uy", "uz"))
        fr.add_distributed_load("AB", wz=w1, wz2=w2, case="D")
        V = "Vz"
    res = fr.solve_combinations({"D": {"D": 1.0}})
    value, at = res["D"].extremes("AB")[V]["min"]
    assert value == pytest.approx(V_min, rel=1e-12)
    assert at == pytest.approx(x0, rel=1e-12)
    assert res.envelope()["AB"][V]["min"][:2] == (value, at)
    # V's largest is at an end: R_A, or R_A + (w1 + w2) L/2 = −R_B
    assert res["D"].extremes("AB")[V]["max"][0] == pytest.approx(
        max(R_A, R_A + (w1 + w2) * L / 2), rel=1e-12)
