"""README.md kept true: every python block runs as written, each
in a fresh namespace, from a scratch folder laid out like a checkout (its
``../shared`` is the data beside this checkout, when there is one), and what
a block shows — ``# -> value`` comments, a ```text block of its output — is
what it gives (tests/helpers/readme.py says how values are compared).  The
lists the README keeps by hand (the `make bench` scripts, the layout's
folders, the extras, the commands) are checked against the Makefile, the
tree, pyproject.toml and the command line."""

from __future__ import annotations

import re
import tomllib

import pytest

import qpcontact

from tests.helpers.readme import README, blocks, output_differences, python_blocks, run
from tests.helpers.paths import ROOT

SHARED = ROOT.parent / "shared"          # where tests/helpers/paths.py looks for the data too
TEXT = README.read_text(encoding="utf-8")
BLOCKS = python_blocks()


def _section(title: str) -> str:
    return TEXT.split(f"\n## {title}\n", 1)[1].split("\n## ", 1)[0]


def test_the_readme_has_blocks_to_check():
    """The reading can fail: the first screen's example and its output are found."""
    assert len(BLOCKS) >= 5, [b.name for b in BLOCKS]
    assert BLOCKS[0].output and BLOCKS[0].line < 40, "the first screen's example lost its output"
    assert sum(b.code.count("-> ") for b in BLOCKS) >= 10


@pytest.mark.parametrize("block", BLOCKS, ids=[b.name for b in BLOCKS])
def test_block_runs_and_shows_what_it_gives(block, tmp_path, monkeypatch):
    if "../shared/data" in block.code and not (SHARED / "data").is_dir():
        pytest.skip(f"{block.name} reads ../shared/data, not found at {SHARED / 'data'}")
    checkout = tmp_path / "checkout"
    checkout.mkdir()
    if SHARED.is_dir():
        (tmp_path / "shared").symlink_to(SHARED, target_is_directory=True)
    monkeypatch.chdir(checkout)          # a block that writes out/... writes here
    try:
        printed, wrong = run(block, {"__name__": "__readme__"})
    except qpcontact.BackendUnavailableError as exc:
        pytest.skip(f"{block.name}: {exc}")
    except ModuleNotFoundError as exc:
        if exc.name and exc.name.split(".")[0] in ("qpcontact", "formulations"):
            raise
        pytest.skip(f"{block.name} needs {exc.name}, an optional package not installed here")
    assert not wrong, "\n".join(wrong)
    if block.output is not None:
        diff = output_differences(printed, block.output)
        assert not diff, f"{block.name}:\n" + "\n".join(diff)


def test_make_bench_list_is_the_makefile_s():
    recipe = (ROOT / "Makefile").read_text().split("\nbench:", 1)[1].split("\n\n", 1)[0]
    ran = set(re.findall(r"benchmarks/(\w+\.py)", recipe))
    bullet = next(p for p in _section("Other commands").split("\n- ") if p.startswith("`make bench`"))
    listed = set(re.findall(r"(\w+\.py)", bullet))
    assert ran and listed == ran, f"README lists {sorted(listed)}, the Makefile runs {sorted(ran)}"


def test_layout_names_every_package_formulation_and_example():
    layout = _section("Layout")
    names = [p.name for p in (ROOT / "qpcontact").iterdir() if (p / "__init__.py").exists()]
    names += [p.name for p in (ROOT / "formulations").iterdir()
              if (p / "__init__.py").exists() or (p.suffix == ".py" and p.stem != "__init__")]
    names += [p.name for p in (ROOT / "examples").glob("*.py")]
    names += [p.stem for p in (ROOT / "examples" / "scenes").glob("*.toml")]
    missing = sorted(n for n in names if not re.search(rf"(?<![\w.]){re.escape(n)}(?![\w])", layout))
    assert not missing, f"the README's Layout does not mention {missing}"


def test_extras_named_are_pyproject_s():
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    sentence = _section("Install").split("Extras:", 1)[1].split("\n\n", 1)[0]
    named = set(re.findall(r"`(\w+)`", sentence))
    assert named == set(extras), f"README names extras {sorted(named)}, pyproject has {sorted(extras)}"
    assert 'pip install -e ".[all]"' in _section("Install")


def test_make_targets_and_commands_named_exist():
    makefile = (ROOT / "Makefile").read_text()
    targets = set(re.findall(r"^([\w-]+):", makefile, flags=re.M))
    named = set(re.findall(r"\bmake ([\w-]+)", TEXT))
    assert named <= targets, f"README names make targets the Makefile lacks: {sorted(named - targets)}"
    from typer.main import get_command

    from qpcontact.commands.cli import app

    commands = set(get_command(app).commands)
    shell = "".join(b.code for b in blocks() if b.lang in ("", "sh", "bash", "console"))
    used = set(re.findall(r"^qpcontact ([a-z]+)", shell, flags=re.M))
    used |= set(re.findall(r"`qpcontact ([a-z]+)", TEXT))
    assert used and used <= commands, f"README uses commands that do not exist: {sorted(used - commands)}"
