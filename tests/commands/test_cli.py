"""The command line, run as a user would (typer's runner)."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from qpcontact.commands.cli import app
from tests.helpers.paths import data_dir

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

    from qpcontact.core.friction_problem import FrictionProblem
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
    import pytest

    folder = data_dir("siconos-fc")
    f = folder / "FC2D_SliderCrankLagrangian00000.dat"
    if not f.exists():
        pytest.skip(f"Siconos friction data not found at {f.parent}")
    res = runner.invoke(app, ["solve", str(f)])
    assert res.exit_code == 0, res.output
    assert "dim 2" in res.output and "exact 2-D LCP" in " ".join(res.output.split())


def test_solve_refuses_a_file_with_trailing_garbage(tmp_path):
    """A data file with something after its data: the CLI once solved it and
    said nothing."""
    for tail, fragment in ((" 7\n", "more number"), ("\nleft over text\n", "text 'left'"),
                           ("\n\x00\x01", "binary data")):
        path = tmp_path / "deudeu_tail.dat"
        path.write_text("2\n0 2 2\n2 2\n2 1\n1 2\n-5 -6" + tail)
        res = runner.invoke(app, ["solve", str(path), "--method", "lemke"])
        out = " ".join(res.output.split())
        assert res.exit_code == 2, out
        assert "deudeu_tail.dat" in out and "line" in out and fragment in out, out


# -- commands that fail loudly, help read from the registries ----------------------

def _words(text: str) -> str:
    return " ".join(text.split())


def _listed(output: str, option: str) -> list[str]:
    """The names an option's help lists after "from:" (up to "or"/"(")."""
    block = _words(output.split(option, 1)[1].split("\n --", 1)[0])
    names = block.split("from:", 1)[1].split("(", 1)[0].replace(" or ", ", ")
    return [n.strip(" ,.") for n in names.split(",") if n.strip(" ,.") and ":" not in n]


def _installed_formulations() -> set[str]:
    """Read independently of the CLI: the entry points that build compare
    instances, and the two data sets compare reads."""
    from importlib.metadata import entry_points

    return {ep.name for ep in entry_points(group="qpcontact.formulations")
            if hasattr(ep.load(), "instances")} | {"siconos", "friction"}


def test_help_lists_the_formulations_and_methods_accepted():
    """--help once listed four formulations where six were accepted."""
    from qpcontact.commands.stress import FAMILIES
    from qpcontact.solvers.registry import methods

    res = runner.invoke(app, ["compare", "--help"])
    assert res.exit_code == 0, res.output
    assert set(_listed(res.output, "--formulations")) == _installed_formulations()
    installed = {n for n, m in methods().items() if m.family != "cvxpy"} | {"auto"}
    assert set(_listed(res.output, "--methods")) == installed
    res = runner.invoke(app, ["stress", "--help"])
    assert res.exit_code == 0, res.output
    assert _listed(res.output, "--families") == list(FAMILIES)


def test_help_lines_are_whole_sentences_rewrapped():
    """Each command's summary is a whole sentence (not cut with "..."), and a
    paragraph's lines are filled to the width, not broken where the
    docstring's lines were (rich kept "an HDF5 file," alone on a line)."""
    res = runner.invoke(app, ["--help"], terminal_width=80)
    commands = res.output.split("Commands:")[1].strip().splitlines()
    assert len(commands) == 8
    for line in commands:
        assert line.rstrip().endswith(".") and not line.rstrip().endswith("..."), line
    for command in ("methods", "solve", "simulate", "sweep", "plot", "demo", "compare", "stress"):
        out = runner.invoke(app, [command, "--help"], terminal_width=80).output
        description = out.split("\n\n", 1)[1].split("Options:")[0] if "Arguments" not in out else \
            out.split("\n\n", 1)[1].split("Arguments:")[0]
        for paragraph in description.strip().split("\n\n"):
            lines = paragraph.splitlines()
            for line, following in zip(lines, lines[1:]):
                first_word = following.split()[0]
                assert len(line) + 1 + len(first_word) > 78, (command, line, following)


def test_unknown_formulation_method_family_or_accuracy_exits_2_with_the_valid_names():
    """A typo in a name is an error: `compare --formulations typo` once ran
    nothing and exited 0."""
    from qpcontact.commands.stress import FAMILIES
    from qpcontact.solvers.registry import methods

    installed = sorted(methods())
    cases = [
        (["compare", "--quick", "--formulations", "drum,typo"], "formulation 'typo'",
         sorted(_installed_formulations())),
        (["compare", "--quick", "--methods", "lemke,lemk"], "method 'lemk'", installed),
        (["stress", "--quick", "--families", "spdd"], "family 'spdd'", list(FAMILIES)),
        (["stress", "--quick", "--methods", "osqpp"], "method 'osqpp'", installed),
        (["demo", "--accuracy", "ultra"], "accuracy 'ultra'", ["'low'", "'default'", "'high'"]),
    ]
    for args, named, valid in cases:
        res = runner.invoke(app, args)
        out = _words(res.output)
        assert res.exit_code == 2, (args, out)
        assert named in out and "Traceback" not in out, (args, out)
        assert all(v in out for v in valid), (args, [v for v in valid if v not in out])
    res = runner.invoke(app, ["stress", "--quick", "--sizes", "6,x"])
    assert res.exit_code == 2 and "--sizes" in res.output


def test_an_unknown_method_in_solve_lists_the_installed_ones(tmp_path):
    from qpcontact.solvers.registry import methods

    path = tmp_path / "deudeu.dat"
    path.write_text("2\n0 2 2\n2 2\n2 1\n1 2\n-5 -6\n")
    res = runner.invoke(app, ["solve", str(path), "--method", "lemk"])
    out = _words(res.output)
    assert res.exit_code == 2 and "no method named 'lemk'" in out
    assert all(name in out for name in methods())


def test_options_that_leave_nothing_to_run_exit_2(tmp_path):
    """A command that would do nothing says why and exits non-zero."""
    res = runner.invoke(app, ["compare", "--quick", "--formulations", "drum", "--methods", "nsgs",
                              "-o", str(tmp_path / "compare")])
    assert res.exit_code == 2 and "nothing to run" in _words(res.output), res.output
    res = runner.invoke(app, ["stress", "--quick", "--families", "spd", "--methods", "nsgs",
                              "-o", str(tmp_path / "stress")])
    assert res.exit_code == 2 and "nothing to run" in _words(res.output), res.output


def test_missing_data_says_where_it_looked_and_how_to_point_at_it(tmp_path, monkeypatch):
    """The data sets were looked for relative to the current folder and
    skipped silently elsewhere."""
    empty = tmp_path / "empty"
    empty.mkdir()
    monkeypatch.chdir(tmp_path)
    res = runner.invoke(app, ["compare", "--quick", "--formulations", "siconos", "--data", str(empty)])
    out = _words(res.output)
    assert res.exit_code == 2, out
    assert str(empty / "siconos-lcp") in out and "QPCONTACT_DATA" in out and "--data" in out, out
    res = runner.invoke(app, ["compare", "--quick", "--formulations", "friction",
                              "--data", str(tmp_path / "nowhere")])
    assert res.exit_code == 2 and str(tmp_path / "nowhere") in _words(res.output)
    res = runner.invoke(app, ["stress", "--quick", "--families", "siconos", "--data", str(empty)])
    assert res.exit_code == 2 and str(empty / "siconos-lcp") in _words(res.output)
    res = runner.invoke(app, ["compare", "--quick", "--formulations", "siconos",
                              "--siconos", str(tmp_path / "nowhere")])
    assert res.exit_code == 2 and str(tmp_path / "nowhere") in _words(res.output)


def test_data_found_from_any_folder_by_qpcontact_data(tmp_path, monkeypatch):
    """QPCONTACT_DATA points at the data sets; the checkout's ../shared/data
    is found wherever the command runs from."""
    import csv
    from pathlib import Path

    import qpcontact
    from qpcontact.core.files import data_locations

    data = tmp_path / "data" / "siconos-lcp"
    data.mkdir(parents=True)
    (data / "deudeu.dat").write_text("2\n0 2 2\n2 2\n2 1\n1 2\n-5 -6\n")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    monkeypatch.setenv("QPCONTACT_DATA", str(tmp_path / "data"))
    checkout_data = Path(qpcontact.__file__).resolve().parents[1].parent / "shared" / "data"
    assert data_locations("siconos-lcp")[:2] == [data, checkout_data / "siconos-lcp"]
    res = runner.invoke(app, ["compare", "--quick", "--formulations", "siconos",
                              "--methods", "lemke", "-o", "out"])
    assert res.exit_code == 0, res.output
    with open(elsewhere / "out" / "results.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert {r["instance"] for r in rows} == {"siconos/deudeu"}
    assert all(r["success"] == "True" for r in rows)


def test_solve_prints_integer_fields_as_integers(tmp_path):
    """Integer fields print as integers: worst_index once printed as 0.000e+00."""
    import re

    path = tmp_path / "deudeu.dat"
    path.write_text("2\n0 2 2\n2 2\n2 1\n1 2\n-5 -6\n")
    res = runner.invoke(app, ["solve", str(path), "--method", "lemke"])
    assert res.exit_code == 0, res.output
    assert re.search(r"^\s+worst_index\s+-?\d+$", res.output, re.M), res.output
    assert re.search(r"^\s+error\s+ \d\.\d{3}e[+-]\d\d$", res.output, re.M), res.output


_SCENE = "examples/scenes/drum2d.toml"


@pytest.mark.parametrize("args, words", [
    (["compare", "--time-limit", "-5"], "'--time-limit': -5.0: expected a positive, finite"),
    (["compare", "--time-limit", "nan"], "'--time-limit': nan: expected a positive, finite"),
    (["compare", "--repeats", "0"], "'--repeats': 0: expected timed repeats per run, an integer >= 1"),
    (["compare", "--repeats", "-2"], "'--repeats': -2: expected timed repeats"),
    (["compare", "--workers", "-1"], "'--workers': -1: expected local Dask processes (0: run here)"),
    (["simulate", _SCENE, "--checkpoint-seconds", "-1"], "'--checkpoint-seconds': -1.0: expected"),
    (["simulate", _SCENE, "--checkpoint-seconds", "0"], "'--checkpoint-seconds': 0.0: expected"),
    (["simulate", _SCENE, "--checkpoint-seconds", "nan"], "'--checkpoint-seconds': nan: expected"),
    (["stress", "--time-limit", "0"], "'--time-limit': 0.0: expected a positive, finite"),
    (["stress", "--time-limit", "nan"], "'--time-limit': nan: expected a positive, finite"),
    (["stress", "--sizes", "-3"], "'--sizes': -3: expected a problem size in '-3', an integer >= 1"),
    (["stress", "--seeds", "0"], "'--seeds': 0: expected seeds per family and size"),
    (["stress", "--workers", "0"], "'--workers': 0: expected worker processes, an integer >= 1"),
    (["sweep", _SCENE, "--vary", "effect.rotation.speed=0.1", "--workers", "-1"],
     "'--workers': -1: expected local Dask processes"),
])
def test_bad_numbers_exit_2_naming_the_option_and_value(args, words):
    res = runner.invoke(app, args)
    out = " ".join(res.output.split())
    assert res.exit_code == 2, res.output
    assert words in out, out
    assert "Traceback" not in res.output


@pytest.mark.parametrize("command, where, words", [
    ("compare", "file/sub", "--out {t}/file/sub: cannot make the folder: {t}/file is a file"),
    ("compare", "file", "--out {t}/file: is a file, not a folder"),
    ("stress", "file/x", "--out {t}/file/x: cannot make the folder: {t}/file is a file"),
    ("simulate", ".", "--out {t}: is a folder; give the file's name"),
    ("simulate", "file/r.h5", "--out {t}/file/r.h5: its folder {t}/file: is a file"),
])
def test_an_out_path_that_cannot_be_used_exits_2_naming_it(tmp_path, command, where, words):
    (tmp_path / "file").write_text("x")
    out = tmp_path if where == "." else tmp_path / where
    args = [command] + ([_SCENE] if command == "simulate" else []) + ["--out", str(out)]
    res = runner.invoke(app, args)
    text = " ".join(res.output.split())
    assert res.exit_code == 2 and not isinstance(res.exception, (OSError, ValueError)), res.output
    assert words.format(t=tmp_path) in text, text


def test_an_unreachable_dask_scheduler_fails_within_seconds(tmp_path):
    import time

    pytest.importorskip("distributed")
    start = time.perf_counter()
    res = runner.invoke(app, ["compare", "--quick", "--formulations", "drum", "--methods", "bpp",
                              "--out", str(tmp_path), "--scheduler", "tcp://127.0.0.1:9"])
    text = " ".join(res.output.split())
    assert res.exit_code == 2, res.output
    assert "--scheduler tcp://127.0.0.1:9: no Dask scheduler answered within 5 s" in text, text
    assert time.perf_counter() - start < 30   # 40 s and a traceback before
