"""Space-frame results as tables and a drawing: every table value
against the result it prints and against statics by hand (the reactions
against the loads, each member's end actions against its load, each pad's
force against its column's base), the rounding by the documented rule
written out here, envelopes against a brute-force pass over the
combinations, CSV written atomically and read back, DataFrames; the drawing
on the rendered figure — no two texts overprint, every state in the legend
with its count, a slip arrow at every slipping pad, the magnification
stated, the axes' triad — and a result that is not ok refused.  The
members' drawn deflection against the cantilever formulas."""

from __future__ import annotations

import csv
import dataclasses
import math
import re

import matplotlib
import numpy as np
import pytest

from tests.helpers.figures import (csv_reads_back, drawn, keeps_previous_file, overlapping,
                            rounded_by_hand)

from formulations.frames import SpaceFrame
from formulations.frames.space.space_examples import six_pads
from qpcontact.core.errors import InvalidOptionError, InvalidProblemError, SolverFailedError

matplotlib.use("Agg")

E, G = 2.1e8, 8.1e7                    # kN/m²
F_PAD = 0.4                            # the pads' friction coefficient
K_SPRING = 5e3                         # kN/m, horizontal spring at P10
XS, YS, H = (0.0, 4.0, 8.0), (0.0, 5.0), 3.5
SIZE = math.sqrt(8.0 ** 2 + 5.0 ** 2 + 3.5 ** 2)   # the nodes' bounding-box diagonal
COMBOS = {"D": {"D": 1.0}, "D+W": {"D": 1.0, "W": 1.0}, "D+W+U": {"D": 1.0, "W": 1.0, "U": 1.0},
          "D+3W": {"D": 1.0, "W": 3.0}, "D+10W": {"D": 1.0, "W": 10.0}}
UNIT = re.compile(r"\[(kN|kN·m|m|rad|-)\]$")
LABELS = {"member", "node", "support", "state", "kinds", "combination", "ok", "route", "message",
          "i", "j", "y axis", "z axis", "t1", "t2", "states"}


def _frame():
    """space_examples.six_pads with the constants above (its geometry and
    loads are restated by hand in _loads, the references' source), 8 facets."""
    fr = six_pads(friction=F_PAD, spring=K_SPRING, facets=8, cone="circumscribed")
    assert {n: tuple(fr.nodes[n]) for n in ("P00", "T21")} == {"P00": (XS[0], YS[0], 0.0),
                                                              "T21": (XS[2], YS[1], H)}
    return fr


def _loads(combo):
    """[(point, force)] of the combination, by hand: each beam's 10 kN/m over
    4 m is 40 kN at its middle."""
    d, w, u = (combo.get(c, 0.0) for c in "DWU")
    out = [((4.0 * a + 2.0, 5.0 * b, H), (0.0, 0.0, -40.0 * d)) for a in range(2)
           for b in range(2)]
    out += [((0.0, 0.0, H), (0.0, 0.0, -5.0 * d + 20.0 * u)),
            ((8.0, 5.0, H), (0.0, 0.0, -40.0 * d)), ((8.0, 0.0, H), (20.0 * w, 20.0 * w, 0.0))]
    return [(np.array(p), np.array(f)) for p, f in out]


@pytest.fixture(scope="module")
def res():
    out = _frame().solve_combinations(COMBOS)
    assert out.failed == ["D+10W"], {n: r.message for n, r in out.items()}
    return out


# -- the tables -------------------------------------------------------------------------

def test_the_example_shows_every_contact_state(res):
    states = {k: s.state for k, s in res["D+W+U"].supports.items()}
    assert states == {"P00": "separated", "P01": "slip", "P10": "stick", "P11": "stick",
                      "P20": "slip", "P21": "stick", "T21": "closed"}
    assert {s.state for s in res["D"].supports.values()} == {"stick", "separated"}


def test_supports_table_is_the_contacts_and_obeys_coulomb(res):
    for name, r in res.items():
        if not r.ok:
            assert r.rows("supports") == []
            continue
        rows = r.rows("supports", None)
        assert [row["support"] for row in rows] == list(r.supports)
        for row, (key, s) in zip(rows, r.supports.items()):
            n = np.array([-1.0, 0.0, 0.0]) if key == "T21" else np.array([0.0, 0.0, 1.0])
            t1, t2 = (np.array(eval(row[t])) for t in ("t1", "t2"))
            # a right-handed frame (t1, t2, n) in the contact's plane
            np.testing.assert_allclose(np.cross(t1, t2), n, atol=1e-12)
            assert row["state"] == s.state and row["X_n [kN]"] == s.normal
            assert (row["X_t1 [kN]"], row["X_t2 [kN]"]) == tuple(s.tangential)
            force = s.normal * n + s.tangential[0] * t1 + s.tangential[1] * t2
            got = [row[f"F{a} [kN]"] for a in "xyz"]
            np.testing.assert_allclose(got, force, rtol=0, atol=1e-12 * max(1.0, s.normal))
            xt = math.hypot(*s.tangential)
            assert row["|X_t| [kN]"] == pytest.approx(xt, abs=1e-12)
            assert row["opening [m]"] == s.opening
            assert row["|slip| [m]"] == pytest.approx(math.hypot(*s.slip), abs=1e-15)
            use = row["|X_t|/(f X_n) on Coulomb's circle [-]"]
            if key == "T21" or s.state == "separated":
                assert math.isnan(use)              # no friction cone to use
            else:
                assert use == pytest.approx(xt / (F_PAD * s.normal), rel=1e-12)
            if key != "T21" and s.state != "separated":
                _coulomb_on_the_facets(s, row)
            if s.state == "separated":
                assert row["X_n [kN]"] == 0.0 and row["opening [m]"] > 0


def _coulomb_on_the_facets(s, row):
    """The 8-facet cone (w_k = f X_n + d_k·X_t >= 0, d_k = cos(πk/4) t1 +
    sin(πk/4) t2): a sticking pad inside it, a slipping one on its boundary,
    slipping along a non-negative sum of the directions of its active facets
    (maximum dissipation) — |X_t| / (f X_n) between 1 and 1/cos(π/8)."""
    from scipy.optimize import nnls

    a = np.pi * np.arange(8) / 4
    dirs = np.c_[np.cos(a), np.sin(a)]
    fxn = F_PAD * s.normal
    w = fxn + dirs @ np.array([row["X_t1 [kN]"], row["X_t2 [kN]"]])
    assert w.min() >= -1e-9 * fxn
    use = row["|X_t|/(f X_n) on Coulomb's circle [-]"]
    assert use <= 1.0 / math.cos(math.pi / 8) + 1e-9
    # the model's own cone: its most loaded facet, -d_k·X_t / (f X_n), at
    # most 1 (1 where the pad slips) even where the circle's ratio is above 1
    facet = float(np.max(-(dirs @ np.array([row["X_t1 [kN]"], row["X_t2 [kN]"]])))) / fxn
    assert row["cone use (the model's cone) [-]"] == pytest.approx(max(facet, 0.0), abs=1e-9)
    assert row["cone use (the model's cone) [-]"] <= 1.0 + 1e-9
    slip = np.array([row["slip_t1 [m]"], row["slip_t2 [m]"]])
    if s.state == "stick":
        assert np.linalg.norm(slip) <= 1e-12
        return
    active = w <= 1e-9 * fxn
    assert active.any() and use >= 1.0 - 1e-9 and row["|slip| [m]"] > 0
    _, residual = nnls(dirs[active].T, slip)
    assert residual <= 1e-9 * np.linalg.norm(slip)


def _hand_reactions(r):
    """{node: 6 components} built from the result's attributes by hand: the
    contact forces, the bilateral reactions and -k u of the spring."""
    out = {}
    for key, s in r.supports.items():
        n = np.array([-1.0, 0.0, 0.0]) if key == "T21" else np.array([0.0, 0.0, 1.0])
        out[key] = np.r_[s.normal * n + s.tangential_global, 0.0, 0.0, 0.0]
    out["P21"] = out["P21"] + np.asarray(r.reactions["P21"])
    out["P10"] = out["P10"] + np.r_[-K_SPRING * r.displacements["P10"][0], 0, 0, 0, 0, 0]
    return out


def test_reactions_balance_the_loads_by_hand(res):
    fr = res["D"].frame
    for name, r in res.items():
        if not r.ok:
            continue
        rows = r.rows("reactions", None)
        hand = _hand_reactions(r)
        assert [row["node"] for row in rows] == ["P00", "P01", "P10", "P11", "P20", "P21", "T21"]
        heads = ("Fx [kN]", "Fy [kN]", "Fz [kN]", "Mx [kN·m]", "My [kN·m]", "Mz [kN·m]")
        force, moment = np.zeros(3), np.zeros(3)
        for row in rows:
            total = np.array([row[h] for h in heads])
            np.testing.assert_allclose(total, hand[row["node"]], rtol=0, atol=1e-9)
            parts = [np.array([row.get(h.replace(" ", f" {kind} "), 0.0) for h in heads])
                     for kind in ("support", "spring", "contact")]
            np.testing.assert_allclose(np.sum(parts, axis=0), total, rtol=0, atol=1e-12)
            force += total[:3]
            moment += total[3:] + np.cross(fr.nodes[row["node"]], total[:3])
        loads = _loads(COMBOS[name])
        np.testing.assert_allclose(force, -sum(f for _, f in loads), rtol=0, atol=1e-9)
        np.testing.assert_allclose(moment, -sum(np.cross(p, f) for p, f in loads), rtol=0,
                                   atol=1e-8)
        kinds = {row["node"]: row["kinds"] for row in rows}
        assert kinds["P10"] == f"spring ux + contact {r.supports['P10'].state}"
        assert kinds["P21"] == f"fixed uy + contact {r.supports['P21'].state}"
    # the spring carries something once P10 slides
    assert res["D+3W"].supports["P10"].state == "slip"
    assert res["D+3W"].rows("reactions")[2]["Fx spring [kN]"] < -1.0
    assert res["D+W+U"].rows("reactions")[6]["Fx [kN]"] < 0         # the bumper pushes back


#: the end actions at i from the internal forces at x = 0: (-N, Vy, Vz, -T,
#: My, -Mz); at j, from those at x = L, the opposite signs
I_END = np.array([-1.0, 1.0, 1.0, -1.0, 1.0, -1.0])


def _axes_of(row):
    y, z = (np.array(eval(row[k])) for k in ("y axis", "z axis"))
    return np.cross(y, z), y, z


def test_member_end_actions_balance_each_member_and_each_pad(res):
    """Statics by hand on the table's own numbers: each member's end actions
    and its load (10 kN/m down on the x beams) are in equilibrium, about its
    node i as well; at a pinned pad the column's base carries the pad's
    force and no moment."""
    fr = res["D"].frame
    for name, r in res.items():
        if not r.ok:
            continue
        rows = r.rows("members", None)
        assert [row["member"] for row in rows] == list(fr.members)
        for row in rows:
            x, y, z = _axes_of(row)
            a, b = fr.nodes[row["i"]], fr.nodes[row["j"]]
            L = row["L [m]"]
            assert L == pytest.approx(np.linalg.norm(b - a), rel=1e-15)
            np.testing.assert_allclose(x, (b - a) / L, atol=1e-4)   # axes printed to 4 digits
            assert abs(x @ y) < 1e-4 and abs(x @ z) < 1e-4
            R = np.array([x, y, z])
            # the table's internal forces (N tension positive, My and Mz
            # compressing the +z and +y fibre, V = dM/dx: docs/frames.md,
            # "Conventions") back to the end actions the nodes exert
            ends = {e: (np.array([row[f"{q}_{e} [kN]"] for q in ("N", "Vy", "Vz")]) * sign[:3],
                        np.array([row[f"{q}_{e} [kN·m]"] for q in ("T", "My", "Mz")]) * sign[3:])
                    for e, sign in (("i", I_END), ("j", -I_END))}
            np.testing.assert_allclose(np.r_[ends["i"][0], ends["i"][1], ends["j"][0],
                                             ends["j"][1]], r.member_forces[row["member"]],
                                       rtol=0, atol=0)
            q = R @ np.array([0.0, 0.0, -10.0 * COMBOS[name]["D"]]) \
                if row["member"].startswith("Bx") else np.zeros(3)
            ex = np.array([L, 0.0, 0.0])
            np.testing.assert_allclose(ends["i"][0] + ends["j"][0] + q * L, 0.0, atol=1e-9)
            np.testing.assert_allclose(ends["i"][1] + ends["j"][1] + np.cross(ex, ends["j"][0])
                                       + np.cross(ex / 2, q * L), 0.0, atol=1e-8)
        for key, s in r.supports.items():
            if key.startswith("P"):
                row = next(rw for rw in rows if rw["i"] == key)
                R = np.array(_axes_of(row))
                force = _hand_reactions(r)[key][:3] if key not in ("P10", "P21") else \
                    s.normal * np.array([0, 0, 1.0]) + s.tangential_global
                base = np.array([row[f"{q}_i [kN]"] for q in ("N", "Vy", "Vz")]) * I_END[:3]
                spring = np.zeros(3)
                if key == "P10":
                    spring[0] = -K_SPRING * r.displacements["P10"][0]
                if key == "P21":
                    spring += np.asarray(r.reactions["P21"][:3])
                np.testing.assert_allclose(base, R @ (force + spring), atol=1e-9)
                assert all(row[f"{q}_i [kN·m]"] == pytest.approx(0.0, abs=1e-9)
                           for q in ("T", "My", "Mz"))
    # the column on the lifted pad carries nothing at its base
    row = res["D+W+U"].rows("members")[0]
    assert row["member"] == "C00" and row["N_i [kN]"] == 0.0 and row["Mz_i [kN·m]"] == 0.0


def test_a_column_in_compression_reads_negative_at_both_ends(res):
    """Tension positive, as the plane frame's table: the columns carry the
    deck's weight, so N < 0 at i and at j, with the pad's force at i."""
    r = res["D"]
    for row in r.rows("members", None):
        if row["member"].startswith("C"):
            assert row["N_i [kN]"] < 0 and row["N_j [kN]"] < 0, row
            pad = r.supports[row["i"]]
            assert row["N_i [kN]"] == pytest.approx(-pad.normal, rel=1e-12)


def _sections_by_hand(r, member, x):
    """The internal forces along a member of the six pads from its end
    actions at i and its load — statics of the part [0, x] written out for
    this frame: the beams Bx carry 10 kN/m down (times D) and lie
    horizontal with their local z up, the other members carry nothing."""
    f = np.asarray(r.member_forces[member])
    qz = -10.0 * COMBOS[r_name(r)]["D"] if member.startswith("Bx") else 0.0
    return {"N": -f[0] + 0.0 * x, "Vy": f[1] + 0.0 * x, "Vz": f[2] + qz * x,
            "T": -f[3] + 0.0 * x, "My": f[4] + f[2] * x + qz * x * x / 2,
            "Mz": -f[5] + f[1] * x}


def r_name(r):
    """The combination's name of a result (its factors are COMBOS')."""
    return next(n for n, c in COMBOS.items() if c == r.combination)


def test_displacements_table(res):
    r = res["D+W+U"]
    rows = r.rows("displacements", None)
    heads = ["node", "ux [m]", "uy [m]", "uz [m]", "rx [rad]", "ry [rad]", "rz [rad]"]
    assert list(rows[0]) == heads
    for row in rows:
        assert tuple(row[h] for h in heads[1:]) == tuple(r.displacements[row["node"]])
    # the lifted pad rose by its opening; the sticking pads on rigid plates did not move
    lifted = next(row for row in rows if row["node"] == "P00")
    assert lifted["uz [m]"] == pytest.approx(r.supports["P00"].opening, rel=1e-12)
    for key in ("P10", "P11"):
        row = next(rw for rw in rows if rw["node"] == key)
        assert max(abs(row[h]) for h in ("ux [m]", "uy [m]", "uz [m]")) < 1e-12


def _rounded(rows, digits=5):
    """docs/frames.md's rounding rule by hand (figure_checks.rounded_by_hand)."""
    return rounded_by_hand(rows, UNIT, SIZE, digits)


def _same(a, b):
    """Row lists equal, NaN equal to NaN."""
    assert len(a) == len(b)
    for ra, rb in zip(a, b):
        assert list(ra) == list(rb)
        for k in ra:
            va, vb = ra[k], rb[k]
            if isinstance(va, float) and math.isnan(va):
                assert isinstance(vb, float) and math.isnan(vb), k
            else:
                assert va == vb, (k, va, vb)


@pytest.mark.parametrize("table", ["supports", "reactions", "members", "displacements"])
def test_rounded_tables_follow_the_documented_rule_and_units_head_every_column(res, table):
    r = res["D+W+U"]
    raw = r.rows(table, None)
    got = r.rows(table)
    _same(got, _rounded(raw))
    assert not any(isinstance(v, float) and v == 0 and math.copysign(1, v) < 0
                   for row in got for v in row.values())
    for key in got[0]:
        if all(isinstance(row[key], float) for row in got):
            assert UNIT.search(key), key
        else:
            assert key in LABELS, key
    # over the combinations: one table, a combination column first, rounded over all
    raw = [{"combination": n, "ok": True, **row} for n, rr in res.items() if rr.ok
           for row in rr.rows(table, None)]
    _same(res.rows(table), _rounded(raw))


def test_the_rounding_has_noise_to_remove(res):
    raw = res["D+W+U"].rows("members", None)
    noisy = [v for row in raw for v in row.values() if isinstance(v, float) and 0 < abs(v) < 1e-9]
    assert len(noisy) >= 3
    assert all(v == 0.0 for row in res["D+W+U"].rows("members") for v in row.values()
               if isinstance(v, float) and abs(v) < 1e-9)


def test_envelopes_against_every_combination(res):
    ok = {n: r for n, r in res.items() if r.ok}
    fr = res["D"].frame
    rows = res.rows("envelope", None)
    assert [row["member"] for row in rows] == list(fr.members)
    for row in rows:
        name = row["member"]
        ends = fr.members[name]
        L = float(np.linalg.norm(fr.nodes[ends["j"]] - fr.nodes[ends["i"]]))
        x = np.linspace(0.0, L, 4001)
        along = {n: _sections_by_hand(r, name, x) for n, r in ok.items()}
        for q in ("N", "Vy", "Vz", "T", "My", "Mz"):
            unit = "kN·m" if q in ("T", "My", "Mz") else "kN"
            for side, pick in (("max", np.max), ("min", np.min)):
                best = pick([pick(v[q]) for v in along.values()])
                got = row[f"{q}_{side} [{unit}]"]
                # a parabola between samples 1e-3 m apart moves by q h²/8 at most
                assert got == pytest.approx(best, abs=1e-9 * max(1.0, abs(best)) + 2e-6)
                # the combination named attains it at the x given
                there = _sections_by_hand(ok[row[f"combination({q}_{side})"]], name,
                                          np.array([row[f"x({q}_{side}) [m]"]]))[q][0]
                assert there == pytest.approx(got, abs=1e-9 * max(1.0, abs(got)))
    hand = {n: _hand_reactions(r) for n, r in ok.items()}
    heads = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
    for row in res.rows("envelope_reactions", None):
        for k, f in enumerate(heads):
            unit = "kN" if f[0] == "F" else "kN·m"
            vals = {n: h[row["node"]][k] for n, h in hand.items()}
            assert row[f"{f}_max [{unit}]"] == pytest.approx(max(vals.values()), abs=1e-9)
            assert row[f"{f}_min [{unit}]"] == pytest.approx(min(vals.values()), abs=1e-9)
    sup = {row["support"]: row for row in res.rows("envelope_supports", None)}
    assert sup["P00"]["states"] == "stick: D; slip: D+W; separated: D+W+U, D+3W"
    for key, row in sup.items():
        normals = {n: r.supports[key].normal for n, r in ok.items()}
        assert row["X_n_max [kN]"] == max(normals.values())
        assert row["X_n_min [kN]"] == min(normals.values())
        assert normals[row["combination(X_n_min)"]] == row["X_n_min [kN]"]
        slips = [math.hypot(*r.supports[key].slip) for r in ok.values()]
        assert row["|slip|_max [m]"] == pytest.approx(max(slips), abs=1e-15)
    assert sup["T21"]["X_n_min [kN]"] == 0.0
    assert math.isnan(sup["T21"]["|X_t|/(f X_n) on Coulomb's circle_max [-]"])
    assert math.isnan(sup["T21"]["cone use (the model's cone)_max [-]"])
    assert sup["P00"]["X_n_min [kN]"] == 0.0 and sup["P00"]["combination(X_n_min)"] == "D+W+U"
    # the failed combination is in no envelope, and listed as failed
    texts = {v for t in ("envelope", "envelope_reactions", "envelope_supports")
             for row in res.rows(t) for v in row.values() if isinstance(v, str)}
    assert not any("D+10W" in t for t in texts)
    combos = res.rows("combinations")
    assert [(c["combination"], c["ok"]) for c in combos][-1] == ("D+10W", False)
    assert set(res.envelope()) == set(fr.members) | {"supports", "contacts"}


def test_csv_written_atomically_and_read_back(res, tmp_path):
    paths = res.to_csv(tmp_path)
    assert sorted(p.split("/")[-1] for p in paths) == sorted(
        f"{t}.csv" for t in ("supports", "reactions", "members", "displacements", "envelope",
                             "envelope_reactions", "envelope_supports", "combinations"))
    assert not list(tmp_path.glob("*.tmp"))
    csv_reads_back(res, paths, nan=True)
    one = tmp_path / "one"
    res["D+W+U"].to_csv(one, digits=None)
    raw = res["D+W+U"].rows("supports", None)
    with open(one / "supports.csv", newline="") as fh:
        back = list(csv.DictReader(fh))
    assert [float(b["X_t1 [kN]"]) for b in back] == [r["X_t1 [kN]"] for r in raw]
    # a write that fails before its rename leaves the previous file whole
    assert keeps_previous_file(lambda: res["D"].to_csv(one), one / "members.csv")


def test_dataframes_equal_the_rows(res):
    pd = pytest.importorskip("pandas")
    for table in ("supports", "members", "reactions", "displacements"):
        df = res["D+W+U"].to_dataframe(table)
        assert df.equals(pd.DataFrame(res["D+W+U"].rows(table)))
        assert list(df.columns) == list(res["D+W+U"].rows(table)[0])
    for table in ("envelope", "envelope_supports", "supports"):
        assert res.to_dataframe(table).equals(pd.DataFrame(res.rows(table)))


def test_unknown_tables_are_refused_by_name(res):
    with pytest.raises(InvalidOptionError, match="envelope_supports"):
        res.rows("pads")
    with pytest.raises(InvalidOptionError, match="displacements"):
        res["D"].rows("pads")


# -- the drawing ------------------------------------------------------------------------

def _texts(fig):
    """Every text printed (tick labels of axes that are drawn only)."""
    from matplotlib.text import Text

    hidden = {t for ax in fig.axes if not ax.axison
              for t in ax.get_xticklabels() + ax.get_yticklabels()}
    return [t for t in fig.findobj(Text) if t not in hidden and t.get_visible()
            and t.get_text().strip()]


def _overlaps(fig):
    return overlapping(fig, _texts(fig))


@pytest.fixture(scope="module")
def drawing(res):
    return drawn(res["D+W+U"].plot)


def test_drawing_labels_do_not_overprint(drawing):
    words = [t.get_text() for t in _texts(drawing)]
    assert sum(bool(re.match(r"(P\d\d|T21): ", w)) for w in words) == 7   # every contact named
    assert _overlaps(drawing) == []


def test_drawing_shows_states_slips_scale_loads_and_axes(drawing, res):
    r = res["D+W+U"]
    ax = drawing.axes[0]
    legend = [t.get_text() for t in drawing.legends[0].get_texts()]
    for label in ("separated (1)", "closed (1)", "stick (3)", "slip (2)", "slip direction",
                  "bilateral support (1)", "spring (1)", "loads"):
        assert label in legend, legend
    # the magnification: by default the largest displacement drawn as 8 % of the frame
    umax = max(np.linalg.norm(r.deflection(m, 21, "global")[1], axis=1).max()
               for m in r.frame.members)
    scale = 0.08 * SIZE / umax
    assert f"displacements × {scale:.3g}" in ax.get_title()
    assert f"deformed (× {scale:.3g})" in legend
    assert "isometric view" in ax.get_title() and "8 × 5 × 3.5 m" in ax.get_title()
    assert drawing._suptitle.get_text() == "D+W+U = D + W + U"
    # a slip arrow at each slipping pad, along its slip on the screen
    orange = [a for a in ax.texts if getattr(a, "arrow_patch", None) is not None
              and matplotlib.colors.same_color(a.arrow_patch.get_edgecolor(), "tab:orange")]
    assert len(orange) == 2
    words = [t.get_text() for t in ax.texts]
    assert "(20, 20, 0)\u2009kN" in words
    assert "40\u2009kN" in words and "10\u2009kN/m" in words
    assert [w for w in words if w in ("x", "y", "z")] == ["x", "y", "z"]
    assert any(w.startswith("P00: open") and w.endswith("m") for w in words)
    assert any(w.startswith("P20: X_n") and "slip" in w for w in words)


def test_a_top_view_is_a_plan_one_panel_per_level(res):
    """Seen from above, the roof beams lay over the pads (T21's bumper over
    P21's guide): the plan draws the pads' level z = 0 and the roof's
    z = 3.5 m in panels of their own, the vertical loads end on."""
    fig = drawn(res["D+3W"].plot, azimuth=-90.0, elevation=90.0)
    assert _overlaps(fig) == []
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert [ax.get_title() for ax in panels] == ["level z = 0\u2009m: 0 members, 6 contacts",
                                                 "level z = 3.5\u2009m: 7 members, 1 contact"]
    base, roof = ([t.get_text() for t in ax.texts] for ax in panels)
    assert "40\u2009kN ⊗" in roof and not any("kN ⊗" in w for w in base)
    assert sum(w.startswith("P") and "X_n" in w or "open" in w for w in base) >= 5
    assert any(w.startswith("T21:") for w in roof) and not any(w.startswith("T21") for w in base)
    assert "plan, one panel per level" in fig._suptitle.get_text()


def _grid(nx=4, ny=3, storeys=2, push=60.0):
    """A crowded drawing: nx x ny bays, two storeys, 20 frictional pads,
    every x beam loaded, the left frame pushed in x and y."""
    fr = SpaceFrame()
    for k in range(storeys + 1):
        for a in range(nx + 1):
            for b in range(ny + 1):
                fr.add_node(f"N{k}_{a}_{b}", 5.0 * a, 4.0 * b, 3.2 * k)
                if k:
                    fr.add_member(f"N{k - 1}_{a}_{b}", f"N{k}_{a}_{b}", E, 0.01, 8e-5, 8e-5,
                                  G=G, J=1e-5)
                else:
                    fr.add_contact(f"N0_{a}_{b}", friction=0.35)
        for a in range(nx + 1):
            for b in range(ny + 1):
                if k and a < nx:
                    m = fr.add_member(f"N{k}_{a}_{b}", f"N{k}_{a + 1}_{b}", E, 0.01, 2e-4, 1e-4,
                                      G=G, J=2e-5)
                    fr.add_distributed_load(m, wz=-12.0, case="D")
                if k and b < ny:
                    fr.add_member(f"N{k}_{a}_{b}", f"N{k}_{a}_{b + 1}", E, 0.01, 2e-4, 1e-4,
                                  G=G, J=2e-5)
    for b in range(ny + 1):
        fr.add_load(f"N{storeys}_0_{b}", fx=push, fy=0.3 * push, case="W")
    return fr


def test_a_crowded_frame_keeps_its_labels_apart():
    """20 pads, 24 loaded beams, 4 point loads: placed where they first
    would go, 7 labels overprint (measured with the placement check
    removed); placed by the renderer's boxes, none."""
    r = _grid().solve(combination={"D": 1.0, "W": 1.0})
    assert r.ok and {s.state for s in r.supports.values()} == {"stick", "slip"}
    fig = drawn(r.plot)
    assert _overlaps(fig) == []
    words = [t.get_text() for t in fig.axes[0].texts]
    named = sum(w.startswith("N0_") for w in words)
    assert named >= 15
    assert named == 20 or any(f"{named} of 20 contacts labelled" in w for w in words)


def test_the_png_is_written_and_bad_results_or_views_are_refused(res, tmp_path):
    r = res["D+W+U"]
    path = r.plot(tmp_path / "frame.png", scale=50.0, title="my frame")
    with open(path, "rb") as fh:
        assert fh.read(8) == b"\x89PNG\r\n\x1a\n"
    broken = dataclasses.replace(r, ok=False, message="CHECK FAILED")
    with pytest.raises(SolverFailedError, match="not an equilibrium"):
        broken.plot(tmp_path / "broken.png")
    with pytest.raises(SolverFailedError):
        res["D+10W"].plot(tmp_path / "failed.png")
    for kw in ({"elevation": 120.0}, {"azimuth": float("nan")}, {"scale": -1.0},
               {"scale": "big"}):
        with pytest.raises(InvalidOptionError):
            r.plot(tmp_path / "bad.png", **kw)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frame.png"]


# -- the members' deflection ------------------------------------------------------------

def test_member_deflection_is_the_cantilevers_exact_curve():
    """A skew cantilever (along (3, 4, 12)/13, 13 m) under uniform loads in
    member axes: u = q_x (L x - x²/2)/EA, v = q_y x² (6L² - 4Lx + x²)/24 E Iz,
    w likewise with Iy.  Its tip has a contact 10 m away that stays open."""
    fr = SpaceFrame()
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 3.0, 4.0, 12.0)
    A_, Iy, Iz = 0.02, 3e-4, 1e-4
    fr.add_member("A", "B", E, A_, Iy, Iz, G=G, J=2e-4, name="AB")
    fr.add_support("A")
    fr.add_contact("B", normal=(0.0, 0.0, 1.0), gap=10.0)
    q = np.array([0.1, -0.15, 0.25])
    fr.add_distributed_load("AB", *q, axes="member")
    r = fr.solve()
    assert r.ok and r.supports["B"].state == "separated"
    x, d = r.deflection("AB", 41)
    L = 13.0
    bend = x ** 2 * (6 * L ** 2 - 4 * L * x + x ** 2) / 24.0
    hand = np.c_[q[0] * (L * x - x ** 2 / 2) / (E * A_), q[1] * bend / (E * Iz),
                 q[2] * bend / (E * Iy)]
    np.testing.assert_allclose(x, np.linspace(0, L, 41))
    np.testing.assert_allclose(d, hand, rtol=0, atol=1e-9 * np.abs(hand).max())
    # in global axes: the same vectors turned; at the tip the node's displacement
    xg, dg = r.deflection("AB", 41, axes="global")
    np.testing.assert_allclose(np.linalg.norm(dg, axis=1), np.linalg.norm(hand, axis=1),
                               rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(dg[-1], r.displacements["B"][:3], rtol=1e-12)
    np.testing.assert_allclose(dg[:, 0] * 3 + dg[:, 1] * 4 + dg[:, 2] * 12,
                               13.0 * hand[:, 0], atol=1e-9 * np.abs(hand).max())
    with pytest.raises(InvalidProblemError, match="no member named"):
        r.deflection("XY")
    with pytest.raises(InvalidOptionError):
        r.deflection("AB", axes="local")


def test_the_frames_own_units_head_the_tables_and_label_the_drawing():
    fr = SpaceFrame(units=("N", "mm"))
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 2000.0, 0.0, 0.0)
    fr.add_member("A", "B", 2.1e5, 5e3, 4e7, 2e7, G=8.1e4, J=6e7, name="AB")
    fr.add_support("A")
    fr.add_contact("B", friction=0.3, stiffness=1e3)
    fr.add_load("B", fx=300.0, fz=-1e3)
    r = fr.solve()
    assert r.ok and r.supports["B"].state == "stick"
    # the same on a rigid pad does not move: its rounding (at most 1e-19 mm,
    # zero once refined) is not magnified
    rigid = SpaceFrame(units=("N", "mm"))
    for name, x in (("A", 0.0), ("B", 2000.0)):
        rigid.add_node(name, x, 0.0, 0.0)
    rigid.add_member("A", "B", 2.1e5, 5e3, 4e7, 2e7, G=8.1e4, J=6e7, name="AB")
    rigid.add_support("A")
    rigid.add_contact("B", friction=0.3)
    rigid.add_load("B", fx=300.0, fz=-1e3)
    still = rigid.solve()
    assert max(abs(v) for v in still.displacements["B"]) < 1e-15
    title = drawn(still.plot).axes[0].get_title()
    assert "displacements × 1;" in title and "no displacement" in title
    heads = [k for t in ("supports", "reactions", "members", "displacements")
             for k in r.rows(t)[0]]
    for head in ("X_n [N]", "opening [mm]", "My [N·mm]", "Mz_i [N·mm]", "L [mm]", "ux [mm]",
                 "rz [rad]"):
        assert head in heads, head
    assert not any("kN" in h or "[m]" in h for h in heads)
    fig = drawn(r.plot)
    words = [t.get_text() for t in fig.axes[0].texts]
    assert "(300, 0, -1000)\u2009N" in words
    assert "2000 × 0 × 0 mm" in fig.axes[0].get_title()
    assert any(w.startswith("B: X_n") and w.endswith("\u2009N") for w in words)
    assert _overlaps(fig) == []


@pytest.mark.parametrize("cone", ["circular", "inscribed"])
def test_a_frictional_pad_whose_tangents_supports_hold_is_solved(cone):
    """A pad at a node whose ux and uy a bilateral support holds has no
    friction facet (the support carries the tangential force): the frame
    is solved, the pad's cone use is None (numpy's max of an empty array
    raised before, on the polygon and in the circle's start from it); the
    normal forces are the hand statics' (equal loads at the two pads)."""
    fr = SpaceFrame(cone=cone)
    fr.add_node("A", 0.0, 0.0, 0.0)
    fr.add_node("B", 6.0, 0.0, 0.0)
    fr.add_member("A", "B", 30e6, 0.32, 0.017, 0.01, G=12e6, J=0.02)
    fr.add_support("A", fix=("ux", "uy", "rx"))
    for node in ("A", "B"):
        fr.add_contact(node, friction=0.5, stiffness=6e4, facets=8)
        fr.add_load(node, fz=-10.0)
    fr.add_load("B", fy=2.0)
    res = fr.solve()
    assert res.ok, res.message
    assert res.supports["A"].cone_use is None
    if cone == "inscribed":
        assert 0.0 < res.supports["B"].cone_use < 1.0
    for node in ("A", "B"):
        assert abs(res.supports[node].normal - 10.0) <= 1e-9 * 10.0
