"""The wheel and sdist a user would install: built from this
checkout, the wheel carries every module and entry point, the sdist every
file a checkout runs `make demo` and `make test` from, and the installed
wheel runs the README's first example and a scene file from a folder outside
the checkout.

By default the wheel goes into a scratch folder with ``pip install --no-deps
--target`` and runs on this interpreter (which has the dependencies), with
that folder first on PYTHONPATH; the test checks that ``qpcontact`` and
``formulations`` were imported from there and not from the checkout.  `make
wheel` sets QPCONTACT_WHEEL_VENV=fresh: a new virtual environment, the wheel
installed with its dependencies from the package index, and nothing else.
QPCONTACT_WHEEL_DIST names a folder with a wheel and sdist already built
(`make wheel` builds them into dist/ with `python -m build`)."""

from __future__ import annotations

import configparser
import os
import subprocess
import sys
import tarfile
import tomllib
import zipfile
from importlib import metadata
from pathlib import Path

import pytest

from tests.helpers.readme import output_differences, python_blocks
from tests.helpers.paths import ROOT

pytestmark = pytest.mark.slow

PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
PACKAGES = ("qpcontact", "formulations")
SCENE = "examples/scenes/rod.toml"       # the quickest scene (about 2 s)


def _run(cmd, **kw):
    res = subprocess.run(cmd, capture_output=True, text=True, **kw)
    assert res.returncode == 0, f"{' '.join(map(str, cmd))} exited {res.returncode}:\n" \
                                f"{res.stdout[-3000:]}\n{res.stderr[-3000:]}"
    return res


@pytest.fixture(scope="module")
def dist(tmp_path_factory) -> Path:
    if os.environ.get("QPCONTACT_WHEEL_DIST"):
        return Path(os.environ["QPCONTACT_WHEEL_DIST"]).resolve()
    pytest.importorskip("build", reason="`python -m build` missing: pip install -e \".[test]\"")
    need = PYPROJECT["build-system"]["requires"][0].split(">=")[1]
    have = metadata.version("setuptools")
    if tuple(map(int, have.split(".")[:2])) < tuple(map(int, need.split(".")[:2])):
        pytest.skip(f"setuptools {have} here, the build needs >={need}: pip install -e \".[test]\"")
    out = tmp_path_factory.mktemp("dist")
    # no isolation: the build backend installed here, no index needed; the
    # wheel is built from the unpacked sdist, as `python -m build` always does
    _run([sys.executable, "-m", "build", "--no-isolation", "--outdir", str(out), str(ROOT)])
    return out


def _one(folder: Path, pattern: str) -> Path:
    found = sorted(folder.glob(pattern))
    assert len(found) == 1, f"{folder}: {pattern} matches {found}"
    return found[0]


def test_the_wheel_carries_every_module_and_entry_point(dist):
    with zipfile.ZipFile(_one(dist, "*.whl")) as whl:
        names = set(whl.namelist())
        info = next(n.split("/")[0] for n in names if n.endswith(".dist-info/METADATA"))
        top = set(whl.read(f"{info}/top_level.txt").decode().split())
        entry_points = whl.read(f"{info}/entry_points.txt").decode()
    sources = {p.relative_to(ROOT).as_posix() for pkg in PACKAGES for p in (ROOT / pkg).rglob("*")
               if p.is_file() and "__pycache__" not in p.parts and p.suffix != ".pyc"}
    assert sources <= names, f"not in the wheel: {sorted(sources - names)[:20]}"
    assert top == set(PACKAGES), f"top-level packages {sorted(top)}"
    parser = configparser.ConfigParser(delimiters=("=",))
    parser.optionxform = str
    parser.read_string(entry_points)
    wanted = dict(PYPROJECT["project"]["entry-points"], console_scripts=PYPROJECT["project"]["scripts"])
    got = {group: dict(parser[group]) for group in parser.sections()}
    assert got == wanted


def test_the_sdist_carries_the_checkout(dist):
    with tarfile.open(_one(dist, "*.tar.gz")) as sdist:
        names = {n.split("/", 1)[1] for n in sdist.getnames() if "/" in n}
    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True)
    if tracked.returncode != 0:
        pytest.skip("not a git checkout: no list of the files the sdist should carry")
    wanted = {f for f in tracked.stdout.splitlines()
              if f.split("/")[0] in (*PACKAGES, "tests", "examples", "docs", "benchmarks")
              or f in ("Makefile", "README.md", "pyproject.toml")}
    wanted = {f for f in wanted if (ROOT / f).exists()}      # a deletion not committed yet
    assert wanted <= names, f"not in the sdist: {sorted(wanted - names)[:20]}"


@pytest.fixture(scope="module")
def installed(dist, tmp_path_factory):
    """(python, environment, site folder) running the installed wheel."""
    here = tmp_path_factory.mktemp("installed")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    wheel = str(_one(dist, "*.whl"))
    if os.environ.get("QPCONTACT_WHEEL_VENV") == "fresh":
        _run([sys.executable, "-m", "venv", str(here / "venv")])
        python = here / "venv" / "bin" / "python"
        _run([python, "-m", "pip", "install", "--quiet", wheel])
        site = here / "venv"
    else:
        site = here / "site"
        _run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--no-index",
              "--target", str(site), wheel])
        python, env["PYTHONPATH"] = Path(sys.executable), str(site)
    return python, env, site


def test_the_installed_wheel_is_what_runs(installed, tmp_path):
    python, env, site = installed
    check = ("import importlib.metadata as md, qpcontact, formulations\n"
             "print(qpcontact.__file__); print(formulations.__file__)\n"
             "for ep in md.entry_points(group='qpcontact.formulations'): print(ep.load().__file__)\n")
    files = _run([python, "-c", check], cwd=tmp_path, env=env).stdout.split()
    assert len(files) > 2 and all(Path(f).resolve().is_relative_to(site.resolve()) for f in files), \
        f"imported from outside {site}: {files}"


def test_the_readme_example_runs_from_the_wheel(installed, tmp_path):
    python, env, _ = installed
    first = python_blocks()[0]
    (tmp_path / "example.py").write_text(first.code)
    printed = _run([python, "example.py"], cwd=tmp_path, env=env).stdout
    diff = output_differences(printed, first.output)
    assert not diff, "\n".join(diff)


def test_a_scene_from_the_sdist_runs_on_the_wheel(dist, installed, tmp_path):
    python, env, _ = installed
    with tarfile.open(_one(dist, "*.tar.gz")) as sdist:
        member = next(m for m in sdist.getmembers() if m.name.endswith("/" + SCENE))
        (tmp_path / "scene.toml").write_bytes(sdist.extractfile(member).read())
    _run([python, "-m", "qpcontact", "simulate", "scene.toml", "--out", "scene.h5"],
         cwd=tmp_path, env=env)
    assert (tmp_path / "scene.h5").stat().st_size > 0


def test_the_console_script_runs(installed, tmp_path):
    python, env, site = installed
    script = site / "bin" / "qpcontact"
    out = _run([script, "--help"], cwd=tmp_path, env=env).stdout
    assert "simulate" in out and "compare" in out
