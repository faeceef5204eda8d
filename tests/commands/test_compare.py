"""The solver-comparison sweep: tables recomputed from the CSV, failures
recorded with their reason, resume after an interruption, Dask = serial."""

from __future__ import annotations

import csv
import dataclasses
import math
import re

import numpy as np
import pytest

import qpcontact
from qpcontact import LCP
from qpcontact.commands import compare
from qpcontact.solvers.registry import _REGISTRY
from qpcontact.cases.paper import p0_examples

from tests.helpers.problems import planted_spd_lcp

TIMING = set(compare.TIMING_FIELDS)


def _instances():
    out = [compare.Instance(ex.name.replace(" ", "-"), "p0", "n4", ex.lcp) for ex in p0_examples()]
    lcp, _ = planted_spd_lcp(12, 100.0, 1)
    out.append(compare.Instance("random/spd-12", "random", "n12", lcp))
    # M + M' indefinite: no convex QP route
    out.append(compare.Instance("random/nonsym", "random", "n2", LCP([[1.0, 3.0], [0.0, 1.0]], [-1.0, -1.0])))
    return out


METHODS = ["energy", "lemke", "osqp", "clarabel"]


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _strip(rows):
    return [{k: v for k, v in r.items() if k not in TIMING} for r in rows]


def test_shgeom_is_qpbenchmarks_definition():
    v = np.array([0.001, 0.1, 2.0])
    expected = math.exp(sum(math.log(x + 10.0) for x in v) / 3) - 10.0
    assert compare.shgeom(v) == pytest.approx(expected)


def test_report_tables_recomputed_from_the_csv(tmp_path):
    path = compare.sweep(tmp_path, instances=_instances(), methods=METHODS, progress=False)
    md = compare.report(path).read_text()
    rows = _rows(path)
    # every run is a row; the nonsymmetric LCP is "not applicable" for the QP backends
    assert len(rows) == len(compare.plan(_instances(), METHODS))
    na = [r for r in rows if r["instance"] == "random/nonsym" and r["method"] == "clarabel"]
    assert na and all(r["applicable"] == "False" and r["status"] == "not applicable" for r in na)
    # recompute one table independently: formulation p0, level "high"
    sel = [r for r in rows if r["formulation"] == "p0" and r["level"] == "high" and r["applicable"] == "True"]
    stats = {}
    for m in {r["method"] for r in sel}:
        rs = [r for r in sel if r["method"] == m]
        t = [float(r["time_median"]) if math.isfinite(float(r["cert_error"] or "nan")) else 10.0
             for r in rs]
        stats[m] = (100.0 * sum(r["success"] == "True" for r in rs) / len(rs),
                    math.exp(sum(math.log(x + 10) for x in t) / len(t)) - 10)
    best = min(v[1] for v in stats.values())
    section = md.split("## p0")[1].split('### accuracy "high"')[1].split("###")[0].split("## ")[0]
    for m, (succ, tm) in stats.items():
        line = re.search(rf"^\| {re.escape(m)} \| (\d+) \| ([\d.]+) \| ([\d.]+) \|", section, re.M)
        assert line, m
        assert float(line.group(2)) == pytest.approx(succ, abs=0.05)
        assert float(line.group(3)) == pytest.approx(tm / best, abs=0.006)
    assert list(tmp_path.glob("wp_p0_n4.png"))


def test_wrong_and_raising_methods_are_recorded(tmp_path, monkeypatch):
    good = qpcontact.get_method("lemke")  # also loads the registry

    def slightly_wrong(problem, tol, options):
        res = good.run(problem, tol, options)
        return dataclasses.replace(res, x=None if res.x is None else res.x * (1 + 1e-3))

    def raising(problem, tol, options):
        raise RuntimeError("backend crashed")

    monkeypatch.setitem(_REGISTRY, "wrong", dataclasses.replace(good, name="wrong", run=slightly_wrong))
    monkeypatch.setitem(_REGISTRY, "boom", dataclasses.replace(good, name="boom", run=raising))
    path = compare.sweep(tmp_path, instances=_instances()[:2], methods=["wrong", "boom", "lemke"],
                         progress=False)
    rows = _rows(path)
    wrong = [r for r in rows if r["method"] == "wrong" and r["level"] == "high"]
    assert wrong and all(r["success"] == "False" and "not certified" in r["reason"] for r in wrong)
    assert all(float(r["dist_solution"]) > 1e-4 for r in wrong)
    boom = [r for r in rows if r["method"] == "boom"]
    assert boom and all(r["status"] == "exception" and "backend crashed" in r["reason"] for r in boom)
    assert all(r["success"] == "True" for r in rows if r["method"] == "lemke")  # the sweep went on


def test_interrupted_sweep_resumes_to_the_same_csv(tmp_path, monkeypatch):
    full = compare.sweep(tmp_path / "full", instances=_instances(), methods=METHODS, progress=False)
    calls = {"n": 0}
    real = compare.run_task

    def dying(task, *a, **k):
        calls["n"] += 1
        if calls["n"] > 17:
            raise KeyboardInterrupt  # killed mid-sweep
        return real(task, *a, **k)

    monkeypatch.setattr(compare, "run_task", dying)
    with pytest.raises(KeyboardInterrupt):
        compare.sweep(tmp_path / "part", instances=_instances(), methods=METHODS, progress=False,
                      flush_every=5)
    partial = _rows(tmp_path / "part" / "results.csv")
    assert 0 < len(partial) < len(_rows(full))
    monkeypatch.setattr(compare, "run_task", real)
    resumed = compare.sweep(tmp_path / "part", instances=_instances(), methods=METHODS, progress=False,
                            resume=True)
    assert _strip(_rows(resumed)) == _strip(_rows(full))


@pytest.mark.slow
def test_two_dask_workers_give_the_serial_rows(tmp_path):
    pytest.importorskip("distributed", reason="Dask is in the test extra; install qpcontact[dask]")
    insts = _instances()[:3]
    serial = compare.sweep(tmp_path / "serial", instances=insts, methods=["lemke", "osqp"], progress=False)
    dask = compare.sweep(tmp_path / "dask", instances=insts, methods=["lemke", "osqp"], progress=False,
                         workers=2)
    rows = _rows(dask)
    assert all(r["timed_on"].startswith("dask worker") for r in rows)
    assert _strip(rows) == _strip(_rows(serial))


@pytest.mark.slow
def test_formulation_instances_are_named_and_solvable():
    insts = compare.collect_instances(quick=True, formulations=["drum", "frames", "penalty"])
    names = [i.name for i in insts]
    assert any(n.startswith("drum/stack-10/step-") for n in names)
    assert "frames/3-supports-friction" in names
    assert any(n.startswith("penalty/ramming/mu=") for n in names)
    assert "frames/space-2x2-bays-on-9-pads" in names
    for inst in insts:
        # the penalty QPs go through their dual LCP; the rigid ramming step's
        # multipliers reach 1e8, so the primal recovered from it is certified near 1e-9.
        # The space frames' circular cones are no LCP (Lemke takes a faceted one)
        circular = isinstance(inst.problem, qpcontact.FrictionProblem)
        sol = qpcontact.solve(inst.problem, method="auto" if circular else "lemke",
                              accuracy=1e-8)
        assert sol.ok, (inst.name, sol.message)


def test_friction_collection_in_the_sweep(tmp_path):
    """Friction instances run the friction methods at each ladder level;
    success is the natural-map error at the level's tolerance, recomputed here."""
    import numpy as np

    from qpcontact.core.friction_problem import FrictionProblem
    from qpcontact.judge.friction_certificate import natural_map_error

    def one(a):
        return compare.Instance(f"friction/one-{a}", "friction", "3D",
                                FrictionProblem(np.eye(3), [-1.0, a, 0.0], [0.5], 3))
    insts = [one(0.3), one(2.0)]
    path = compare.sweep(tmp_path, instances=insts, methods=["anitescu", "desaxce-fp", "osqp"],
                         progress=False)
    rows = list(csv.DictReader(open(path)))
    assert {r["method"] for r in rows} == {"anitescu", "desaxce-fp"}     # osqp takes no friction
    assert len(rows) == 2 * 2 * len(compare.LADDER)
    for r in rows:
        assert r["family"] == "friction"
        ok = r["success"] == "True"
        assert ok == (float(r["cert_error"]) <= float(r["tol"]))
    sliding = [r for r in rows if r["instance"].endswith("2.0") and r["method"] == "anitescu"]
    assert all(r["success"] == "False" for r in sliding)
    assert natural_map_error(insts[1].problem, np.array([1.0, -0.5, 0.0])) == 0.0
    md = compare.report(path)
    assert "## friction" in md.read_text()
