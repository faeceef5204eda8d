"""The command line, run as a user would (typer's runner)."""

from __future__ import annotations

from typer.testing import CliRunner

from qpcontact.cli import app

runner = CliRunner()


def test_methods_table():
    res = runner.invoke(app, ["methods"])
    assert res.exit_code == 0
    for name in ("osqp", "clarabel", "proxqp", "daqp", "piqp", "highs", "quadprog", "cvxpy:CLARABEL"):
        assert name in res.output


def test_solve_file(siconos_dir):
    res = runner.invoke(app, ["solve", str(siconos_dir / "lcp_deudeu.dat"), "--method", "daqp"])
    assert res.exit_code == 0, res.output
    assert "solved" in res.output and "siconos_error" in res.output and "1.3333333333" in res.output


def test_solve_reports_misuse_without_traceback(siconos_dir):
    res = runner.invoke(app, ["solve", str(siconos_dir / "lcp_CPS_2.dat"), "--method", "osqp"])
    assert res.exit_code == 2 and "lemke" in res.output and "Traceback" not in res.output
    res = runner.invoke(app, ["solve", str(siconos_dir / "lcp_deudeu.dat"), "--accuracy", "ultra"])
    assert res.exit_code == 2 and "unknown accuracy" in res.output


def test_demo_runs_clean():
    res = runner.invoke(app, ["demo"])
    assert res.exit_code == 0, res.output
    assert "0 certified answers disagree with the paper" in " ".join(res.output.split())
