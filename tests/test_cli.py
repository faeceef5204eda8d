"""The command line, run as a user would (typer's runner)."""

from __future__ import annotations

from typer.testing import CliRunner

from qpcontact.commands.cli import app

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


def test_solve_friction_files(tmp_path):
    """A friction problem written with write_fclib (no shared data needed),
    then the same through a Siconos .dat file when the collection is here."""
    import numpy as np

    from qpcontact.friction.problem import FrictionProblem
    from qpcontact.io import write_fclib

    # one contact, W = I, q = (-1, 2, 0), mu = 0.5: it slides with r = (1, -0.5, 0)
    path = write_fclib(FrictionProblem(np.eye(3), [-1.0, 2.0, 0.0], [0.5], 3), tmp_path / "one.hdf5")
    res = runner.invoke(app, ["solve", str(path)])
    assert res.exit_code == 0, res.output
    out = " ".join(res.output.split())
    assert "natural-map error" in out and "status solved" in out
    import re
    r = [float(v) for v in re.search(r"r = \[([^\]]*)\]", out).group(1).split()]
    np.testing.assert_allclose(r, [1.0, -0.5, 0.0], atol=1e-8)
    res = runner.invoke(app, ["solve", str(path), "--method", "anitescu"])
    assert res.exit_code == 1 and "inaccurate" in " ".join(res.output.split())   # it lifts off
    res = runner.invoke(app, ["solve", str(path), "--method", "pgs"])
    assert res.exit_code == 2 and "no method named 'pgs'" in " ".join(res.output.split())
    assert "Traceback" not in res.output


def test_solve_siconos_friction_dat():
    from pathlib import Path

    import pytest

    f = Path(__file__).resolve().parents[2] / "shared/data/siconos-fc/FC2D_SliderCrankLagrangian00000.dat"
    if not f.exists():
        pytest.skip(f"Siconos friction data not found at {f.parent}")
    res = runner.invoke(app, ["solve", str(f)])
    assert res.exit_code == 0, res.output
    assert "dim 2" in res.output and "exact 2-D LCP" in " ".join(res.output.split())


def test_solve_refuses_a_file_with_trailing_garbage(tmp_path):
    """Issue 31: the CLI solved such a file and said nothing."""
    for tail, fragment in ((" 7\n", "more number"), ("\nleft over text\n", "text 'left'"),
                           ("\n\x00\x01", "binary data")):
        path = tmp_path / "deudeu_tail.dat"
        path.write_text("2\n0 2 2\n2 2\n2 1\n1 2\n-5 -6" + tail)
        res = runner.invoke(app, ["solve", str(path), "--method", "lemke"])
        out = " ".join(res.output.split())
        assert res.exit_code == 2, out
        assert "deudeu_tail.dat" in out and "line" in out and fragment in out, out
