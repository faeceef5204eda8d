"""The API reference (docs/api, built by `make docs`): Sphinx builds it from the
docstrings with warnings as errors, and every public name — each public
module's ``__all__`` — is in it, with a description.  A name added to a
module's ``__all__`` is documented by the next build (docs/api/conf.py expands
each page's modules from ``__all__``); a new public module needs a page, and
the test that lists the public modules fails until it has one."""

from __future__ import annotations

import html
import importlib
import re
import subprocess
import sys
import zlib
from pathlib import Path

import pytest
from tests.helpers.paths import ROOT

DOCS = ROOT / "docs" / "api"

# The modules a user imports from; each one's public names are its __all__.
PUBLIC_MODULES = (
    "qpcontact", "qpcontact.testing", "qpcontact.testing.strategies", "qpcontact.scenes",
    "qpcontact.io", "qpcontact.plots.trace",
    "formulations.drum", "formulations.drum2d", "formulations.frames", "formulations.mechanisms",
    "formulations.meshes", "formulations.multibody", "formulations.mechanisms.penalty",
    "formulations.stepping.contact_step", "formulations.rods", "formulations.plates",
)
# Public names of modules without an __all__.
EXTRA_NAMES = {"qpcontact.plots.figures": ("save_figure",)}
# A formulation module whose public names are all re-exported by another.
REEXPORTED_BY = {"formulations.stepping.penalty_step": "formulations.mechanisms.penalty"}


def public_names() -> list[str]:
    names = []
    for module_name in PUBLIC_MODULES:
        module = importlib.import_module(module_name)
        names += [f"{module_name}.{name}" for name in module.__all__]
    for module_name, extra in EXTRA_NAMES.items():
        names += [f"{module_name}.{name}" for name in extra]
    return names


def read_inventory(path: Path) -> dict[str, str]:
    """{name: "domain:role"} from Sphinx's objects.inv (format version 2:
    four header lines, then zlib-compressed "name domain:role prio uri text")."""
    data = path.read_bytes()
    header = data.split(b"\n", 4)
    assert header[0] == b"# Sphinx inventory version 2", header[0]
    out = {}
    for line in zlib.decompress(header[4]).decode().splitlines():
        m = re.match(r"(.+?)\s+(\S+:\S+)\s+(-?\d+)\s+(\S+)\s+(.*)$", line)
        if m:
            out[m.group(1)] = m.group(2)
    return out


def descriptions(html_dir: Path) -> dict[str, str]:
    """{full name: the text of its entry before any member's} for every object
    described in the HTML pages (``<dt id="name">...<dd>text``)."""
    out = {}
    entry = re.compile(r'<dt class="sig sig-object py" id="([^"]+)">.*?</dt>\s*'
                       r'<dd>(.*?)(?=<dl|</dd>)', re.S)
    for page in html_dir.glob("*.html"):
        for name, body in entry.findall(page.read_text(encoding="utf-8")):
            body = re.sub(r"<p>Bases:.*?</p>", "", body, flags=re.S)
            out[name] = html.unescape(re.sub(r"<[^>]+>", " ", body)).strip()
    return out


def _resolve(full_name: str):
    module_name, _, name = full_name.rpartition(".")
    return getattr(importlib.import_module(module_name), name)


def test_reference_builds_cleanly_with_every_public_name_described(tmp_path):
    """One build (the checks share it; under xdist separate tests would each
    build): no warning, every public name has an entry, and each entry shows
    more than a signature — a docstring, or for a constant a ``#:`` comment
    where it is defined."""
    pytest.importorskip("sphinx", reason="the API reference needs Sphinx: "
                                         "pip install -e \".[docs]\" (in .[all])")
    out = tmp_path / "html"
    res = subprocess.run([sys.executable, "-m", "sphinx", "-b", "html", "-W", "--keep-going",
                          "-q", str(DOCS), str(out)], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, ("the API reference does not build cleanly (warnings are "
                                 f"errors):\n{res.stdout}\n{res.stderr}")
    assert (out / "index.html").is_file()

    inventory = read_inventory(out / "objects.inv")
    missing = [name for name in public_names() if name not in inventory]
    assert not missing, ("public names without an entry in the API reference (a page under "
                         "docs/api/ names each module with `.. public-names::`; facade.rst lists "
                         f"qpcontact's names by hand): {missing}")

    text = descriptions(out)
    bare = [name for name in public_names()
            if not text.get(name) and not isinstance(_resolve(name), type(sys))]
    assert not bare, ("public names documented by their signature alone (write a docstring, or a "
                      f"`#:` comment above a constant): {bare}")


def test_every_public_formulation_module_has_a_page():
    """A formulation module (``formulations/x.py`` or ``formulations/x/``) with
    an ``__all__`` is public: it is in PUBLIC_MODULES, or all its names are."""
    found = []
    for path in sorted((ROOT / "formulations").iterdir()):
        if path.suffix == ".py" and path.stem != "__init__":
            found.append((f"formulations.{path.stem}", path))
        elif (path / "__init__.py").is_file():
            found.append((f"formulations.{path.name}", path / "__init__.py"))
    assert len(found) >= 8, found
    unlisted = []
    for module_name, path in found:
        if "__all__" not in path.read_text(encoding="utf-8") or module_name in PUBLIC_MODULES:
            continue
        cover = REEXPORTED_BY.get(module_name)
        names = importlib.import_module(module_name).__all__
        if cover is None or not set(names) <= set(importlib.import_module(cover).__all__):
            unlisted.append(module_name)
    assert not unlisted, (f"public formulation modules with no page in docs/api/ (add one, and "
                          f"the module to PUBLIC_MODULES): {unlisted}")


def test_pages_name_the_public_modules():
    """Each public module is named on a page, so the build documents it."""
    pages = "\n".join(p.read_text(encoding="utf-8") for p in DOCS.glob("*.rst"))
    named = set(re.findall(r"^\.\. (?:public-names|automodule):: (\S+)", pages, re.M))
    assert set(PUBLIC_MODULES) <= named, sorted(set(PUBLIC_MODULES) - named)
