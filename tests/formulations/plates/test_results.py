"""The raft's results over combinations, its tables, drawing and refusals:
each combination solved on its own (lift-off is not superposable), the
envelope against a brute-force pass over the combinations, the tables'
values against the result they print, the drawing written and refused for a
result that is not ok, and bad input refused with the value named."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from formulations.plates import PlateMesh, Raft, grid
from qpcontact.core.errors import InvalidProblemError


@pytest.fixture(scope="module")
def windy():
    raft = Raft(8.0, 6.0, thickness=0.4, E=30e6, nu=0.2, cells=(16, 12),
                openings=[(3.0, 2.0, 4.0, 3.0)])
    raft.add_soil(2e4)
    raft.add_self_weight(25.0)
    for x in (1.0, 7.0):
        for y in (1.0, 5.0):
            raft.add_column(x, y, 300.0, size=(0.4, 0.4), case="D")
            raft.add_point_load(x, y, 200.0 * (x - 4.0) / 3.0, case="W")
    combos = {"D": {"D": 1.0}, "D+W": {"D": 1.0, "W": 1.5}, "D-W": {"D": 1.0, "W": -1.5}}
    return raft, raft.solve_combinations(combos)


def test_each_combination_is_its_own_contact_problem(windy):
    raft, res = windy
    assert not res.failed
    assert not res["D"].lifted.any() and res["D+W"].lifted.any() and res["D-W"].lifted.any()
    # not superposable once a part lifts: were it linear, D−W would mirror D+W about D
    mirrored = res["D"].w - (res["D+W"].w - res["D"].w)
    assert np.max(np.abs(mirrored - res["D-W"].w)) > 1e-3 * np.max(np.abs(res["D"].w))
    for r in res.values():
        load = r.loads[0::3].sum()
        assert abs(r.support_force.sum() - load) < 1e-8 * load
        assert r.support_force.min() >= 0.0
        assert np.all(r.support_force[r.lifted] == 0) and np.all(r.w[r.lifted] < 0)


def test_the_envelope_is_the_brute_force_max_and_min(windy):
    _, res = windy
    env = res.envelope()
    for q in ("mx", "my", "mxy", "qx", "qy"):
        values = {k: r.element_values(q) for k, r in res.items()}
        top = max(values, key=lambda k: values[k].max())
        low = min(values, key=lambda k: values[k].min())
        assert env[q]["max"][0] == values[top].max() and env[q]["max"][3] == top
        assert env[q]["min"][0] == values[low].min() and env[q]["min"][3] == low
    assert env["pressure"]["max"][0] == max(r.pressure.max() for r in res.values())
    assert env["uplift"]["D"] == 0.0 and env["uplift"]["D+W"] > 0.0


def test_the_envelope_says_which_combinations_it_leaves_out(windy):
    """A combination that is not ok is left out of the envelope — it may be
    the one that governs — and every envelope row says so."""
    _, res = windy
    assert all("without" not in row["note"] for row in res.rows("envelope"))
    bad = res["D-W"]
    bad_ok, bad.ok = bad.ok, False
    try:
        rows = res.rows("envelope")
        assert all(row["note"].startswith("without D-W (not ok)") for row in rows)
        assert all(row["combination"] != "D-W" for row in rows)
    finally:
        bad.ok = bad_ok


def test_tables_print_the_result(windy, tmp_path):
    _, res = windy
    r = res["D+W"]
    rows = r.rows("nodes", digits=None)
    assert [row["w [m]"] for row in rows] == list(r.w)
    states = {row["state"] for row in rows}
    assert states == {"contact", "lifted"}
    ext = {(row["quantity"], row["extreme"]): row for row in r.rows("extremes", digits=None)}
    assert ext[("mx", "max")]["value"] == r.moments[:, 0].max()
    rounded = r.rows("extremes")                      # 5 digits on the largest of each unit
    raw = [row["value"] for row in r.rows("extremes", digits=None) if row["unit"] == "kN·m/m"]
    m = [row["value"] for row in rounded if row["unit"] == "kN·m/m"]
    decimals = 4 - int(np.floor(np.log10(max(abs(v) for v in raw))))
    assert m == [round(v, decimals) + 0.0 for v in raw]
    res.to_csv(tmp_path)
    with open(tmp_path / "envelope.csv") as fh:
        read = list(csv.DictReader(fh))
    assert {row["quantity"] for row in read} == {"w", "pressure", "mx", "my", "mxy", "qx", "qy"}
    assert "0 × D" not in r.table("summary") and "D+W" in res.table("combinations")


def test_drawing_is_written_and_refused_when_not_ok(windy, tmp_path):
    _, res = windy
    path = res["D-W"].plot(tmp_path / "raft.png")
    assert (tmp_path / "raft.png").stat().st_size > 10_000 and path.endswith("raft.png")
    bad = res["D"]
    bad_ok, bad.ok = bad.ok, False
    try:
        with pytest.raises(InvalidProblemError, match="not ok"):
            bad.plot(tmp_path / "bad.png")
    finally:
        bad.ok = bad_ok


def test_a_raft_on_a_mesh_of_its_own(tmp_path):
    """A distorted 4 x 3 mesh: loads on its nodes, soil everywhere, the answer
    certified and in equilibrium, and drawn."""
    base = grid(np.linspace(0, 4, 5), np.linspace(0, 3, 4))
    nodes = base.nodes.copy()
    inner = (nodes[:, 0] > 0) & (nodes[:, 0] < 4) & (nodes[:, 1] > 0) & (nodes[:, 1] < 3)
    nodes[inner] += np.random.default_rng(0).uniform(-0.2, 0.2, (inner.sum(), 2))
    raft = Raft(thickness=0.3, E=3e7, mesh=PlateMesh(nodes, base.elements))
    raft.add_soil(1e4)
    raft.add_point_load(*nodes[0], 50.0)
    raft.add_area_load(1.0)
    r = raft.solve()
    assert r.ok and r.lifted.any()
    assert abs(r.support_force.sum() - (50 + 12)) < 1e-8 * 62
    r.plot(tmp_path / "own.png")
    assert (tmp_path / "own.png").stat().st_size > 10_000
    with pytest.raises(InvalidProblemError, match="not on a node"):
        raft.add_point_load(2.05, 1.5, 1.0)
        raft.solve()


@pytest.mark.parametrize("build, match", [
    (lambda: Raft(4, 4, thickness=-0.3, E=3e7), "thickness must be a positive"),
    (lambda: Raft(4, 4, thickness=0.3, E=3e7, nu=0.5), "Poisson"),
    (lambda: Raft(4, 4, thickness=0.3, E=3e7).add_soil(0.0), "subgrade reaction k"),
    (lambda: Raft(4, 4, thickness=0.3, E=3e7).add_point_load(5.0, 1.0, 1.0), "outside the raft"),
    (lambda: Raft(4, 4, thickness=0.3, E=3e7).add_support(lambda x, y: x == 0, fix=("uz",)),
     "fix must name dofs"),
    # a column whose section crosses the edge: named as a column, not as a corner point
    (lambda: Raft(4, 4, thickness=0.3, E=3e7).add_column(0.1, 2.0, 100.0, size=(0.4, 0.4)),
     r"column at \(0.1, 2.0\) of section 0.4 x 0.4 overhangs"),
    (lambda: Raft(4, 4, thickness=0.3, E=3e7).add_point_load(1.0, 1.0, "10"),
     "a point load must be a finite number; got '10'"),
    (lambda: Raft(4, 4, thickness=0.3, E=3e7).add_column(1.0, 1.0, None, size=(0.4, 0.4)),
     "a column's load must be a finite number"),
    (lambda: Raft(4, 4, thickness=0.3, E=3e7).add_column(1.0, 1.0, 10.0, size=0.4),
     r"a column's size is its section \(bx, by\); got 0.4"),
    (lambda: Raft(4, 4, thickness=0.3, E=3e7).add_column(1.0, 1.0, 10.0, size=(0.4, 0.4, 1)),
     r"a column's size is its section \(bx, by\); got \(0.4, 0.4, 1\)"),
])
def test_bad_input_is_refused_naming_the_value(build, match):
    with pytest.raises(InvalidProblemError, match=match):
        build()


def test_a_plate_held_by_nothing_is_refused():
    raft = Raft(4, 4, thickness=0.3, E=3e7, cells=(4, 4))
    raft.add_support(lambda x, y: (x == 0) & (y == 0), fix=("w",))
    raft.add_area_load(1.0)
    with pytest.raises(InvalidProblemError, match="rigid motion free"):
        raft.solve()


def test_a_patch_over_an_opening_and_an_unknown_case_are_refused():
    raft = Raft(4, 4, thickness=0.3, E=3e7, cells=(8, 8), openings=[(1, 1, 2, 2)])
    raft.add_soil(1e4)
    raft.add_patch_load(0.5, 0.5, 1.5, 1.5, 10.0)
    with pytest.raises(InvalidProblemError, match="overlaps an opening"):
        raft.solve()
    with pytest.raises(InvalidProblemError, match="cases"):
        raft.solve({"L": 1.0})


def test_the_demo_checks_pass():
    """``qpcontact demo``'s plates part: its closed-form checks and the worked
    raft's combinations, zero failures, printed."""
    import io

    from rich.console import Console

    from formulations.plates import demo

    out = io.StringIO()
    assert demo(Console(file=out, width=160)) == 0
    text = out.getvalue()
    assert "closed form" in text and "1.0D+1.5W" in text


def test_a_soil_zone_off_the_raft_is_named():
    """A zone that covers no element was "the plate has no soil and its
    supports leave a rigid motion free"; now the zone and the raft's extent."""
    raft = Raft(8, 4, thickness=0.4, E=3e7, cells=(8, 4))
    raft.add_soil(2e4)
    raft.add_soil(5e4, zone=(10.0, 10.0, 12.0, 12.0))
    raft.add_self_weight(25.0)
    with pytest.raises(InvalidProblemError, match=r"soil zone \(10.0, 10.0, 12.0, 12.0\) covers no "
                       r"element of the raft .* x 0..8, y 0..4"):
        raft.solve()


def test_the_tables_mark_the_values_of_the_mesh():
    """A slab on a rigid floor, its corner pulled up by a point load: the
    shear extreme at the pull and the floor's largest pressure are values
    of the mesh — each grows as the cells halve (checked here on two
    meshes) — and the extremes and envelope tables say so beside them; the
    deflections are the plate's and carry no note."""
    found = {}
    for n in (12, 24):
        raft = Raft(6.0, 6.0, thickness=0.2, E=3e7, nu=0.2, cells=(n, n))
        raft.add_rigid_floor()
        raft.add_self_weight(25.0)
        raft.add_point_load(6.0, 6.0, -20.0, case="pull")
        res = raft.solve_combinations({"D+pull": {"D": 1.0, "pull": 1.0}})
        r = res["D+pull"]
        assert r.ok, r.message
        rows = {(row["quantity"], row["extreme"]): row for row in r.rows("extremes", digits=None)}
        env = {(row["quantity"], row["extreme"]): row for row in res.rows("envelope", digits=None)}
        for table in (rows, env):
            assert "point load" in table[("qx", "min")]["note"]
            assert "rigid floor" in table[("pressure", "max")]["note"]
            assert table[("w", "max")]["note"] == table[("w", "min")]["note"] == ""
        found[n] = rows[("qx", "min")]["value"], rows[("pressure", "max")]["value"]
    assert found[24][0] < 1.3 * found[12][0]          # the shear at the pull: more negative
    assert found[24][1] > 1.3 * found[12][1]          # the floor's peak pressure: larger


def test_cells_coarse_against_the_elastic_length_are_marked():
    """An 8 m slab, t = 0.15 m, on k = 5e4 (elastic length (D/k)^¼ = 0.65
    m) under a corner column: on 0.5 m cells (0.77 ℓ) its extremes are low
    — the largest hogging mx 14 % below the 64-cell answer (0.125 m, ℓ/5.2;
    measured −47.3 against −54.5 kN·m/m) — and every row says the cells are
    coarse; on 0.125 m cells no row does."""
    found = {}
    for n in (16, 64):
        raft = Raft(8.0, 8.0, thickness=0.15, E=30e6, nu=0.2, cells=(n, n))
        raft.add_soil(5e4)
        raft.add_self_weight(25.0)
        raft.add_column(0.15, 0.15, 300.0, size=(0.3, 0.3))
        r = raft.solve()
        assert r.ok, r.message
        rows = {(row["quantity"], row["extreme"]): row for row in r.rows("extremes", digits=None)}
        coarse = ["coarse cells" in row["note"] for row in rows.values()]
        assert all(coarse) if n == 16 else not any(coarse)
        found[n] = rows[("mx", "min")]["value"]
    assert found[16] > 0.9 * found[64]               # hogging: 14 % smaller in size


def test_parts_that_meet_at_a_point_are_refused():
    """Two openings whose corners touch leave the slab's halves joined at a
    node: a real slab carries nothing through a point, the elements pass
    moments through it (173, 258, 443 kN·m/m beside it on 0.5, 0.25, 0.125
    m cells, each answer certified).  Refused, naming the point; a gap of a
    cell between the openings is a slab."""
    with pytest.raises(InvalidProblemError, match=r"meet at a point only, at \(4, 2\)"):
        Raft(8, 4, thickness=0.4, E=3e7, cells=(16, 8),
             openings=[(4, 0, 8, 2), (0, 2, 4, 4)]).build()
    base = grid(np.linspace(0, 2, 3), np.linspace(0, 2, 3))
    with pytest.raises(InvalidProblemError, match=r"at \(1, 1\)"):
        PlateMesh(base.nodes, base.elements[[0, 3]])         # two diagonal cells of four
    raft = Raft(8, 4, thickness=0.4, E=3e7, cells=(16, 8), openings=[(4.5, 0, 8, 2), (0, 2, 4, 4)])
    raft.add_soil(2e4)
    raft.add_self_weight(25.0)
    assert raft.solve().ok


def test_a_column_on_a_mesh_of_the_users_is_not_said_two_percent_low():
    """A mesh of the user's is not refined under a column: a 0.5 m column on
    0.5 m cells is one element, its centre moment 203 against the grid's
    256 kN·m/m with the section meshed 8 x 8 (21 % low).  The note said the
    grid's "(on cells of (D/k)^¼/4.6 2 % low, /9 1 %)" on both; it now
    says how many elements the column has across."""
    notes = {}
    for mesh in (None, grid(np.linspace(0, 12, 25), np.linspace(0, 12, 25))):
        raft = (Raft(12.0, 12.0, thickness=0.6, E=3e7, nu=0.2, cells=(24, 24)) if mesh is None
                else Raft(thickness=0.6, E=3e7, nu=0.2, mesh=mesh))
        raft.add_soil(2e4)
        raft.add_self_weight(25.0)
        raft.add_column(6.25, 6.25, 1000.0, (0.5, 0.5))
        r = raft.solve()
        assert r.ok, r.message
        notes[mesh is None] = r.notes()["mx"]["max"], r.extremes()["mx"]["max"][0]
    (grid_note, grid_mx), (own_note, own_mx) = notes[True], notes[False]
    assert own_mx < 0.85 * grid_mx
    assert "2 % low" in grid_note and "2 % low" not in own_note
    assert "meshed 1 element(s) across" in own_note


def test_an_answer_is_not_changed_by_later_changes_to_its_raft():
    """A result keeps the model it solved: adding a column after the solve
    re-meshes the raft, and an answer that read the raft itself then took
    its node areas (and notes) off the new mesh."""
    raft = Raft(8.0, 6.0, thickness=0.4, E=30e6, nu=0.2, cells=(16, 12))
    raft.add_soil(2e4)
    raft.add_self_weight(25.0)
    raft.add_point_load(1.0, 1.0, 300.0)
    raft.add_point_load(7.0, 5.0, -150.0)
    r = raft.solve()
    assert r.ok and r.lifted.any()
    by_hand = 48.0 - sum(  # the lifted nodes' tributary areas on the 0.5 m grid
        (0.5 if x in (0.0, 8.0) else 1.0) * (0.5 if y in (0.0, 6.0) else 1.0) * 0.25
        for x, y in r.mesh.nodes[r.lifted])
    before = (r.contact_area, r.uplift_fraction, r.notes())
    assert r.contact_area == pytest.approx(by_hand, rel=1e-12)
    raft.add_column(4.3, 2.7, 500.0, size=(0.4, 0.4))
    assert (r.contact_area, r.uplift_fraction, r.notes()) == before
    assert raft.build()["mesh"].nodes.shape[0] > r.mesh.nodes.shape[0]
