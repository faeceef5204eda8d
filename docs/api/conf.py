"""Sphinx configuration of the API reference (``make docs``; tests/package/test_api_reference.py).

The reference is generated from the docstrings by autodoc (with napoleon for
their NumPy-style sections).  A page names its modules with a
``.. public-names:: MODULE`` line; it expands to one autodoc directive per
name in the module's ``__all__``, so a name added to ``__all__`` is in the
reference on the next build.  Built with ``-W --keep-going``: a docstring that
is not valid reStructuredText fails the build.

The guides (``docs/*.md``) are pages of the site too: each has a stub in
``docs/api/guides/`` that includes it (myst-parser reads the Markdown), and
index.rst lists the stubs in reading order.  A guide without a stub fails the
build (``check_guides``), and so does a stub missing from the listing (Sphinx:
"document isn't included in any toctree").
"""

import importlib
import inspect
import re
import sys
import types
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# Build from the checkout, installed or not.
sys.path.insert(0, str(ROOT))

project = "qpcontact"
author = "The qpcontact authors"
copyright = "2026, the qpcontact authors"  # the footer; the LICENSE file's line
release = version = "0.1.0"

try:
    import myst_parser  # noqa: F401
except ImportError:
    from sphinx.errors import ConfigError
    raise ConfigError("the guides (docs/*.md) need myst-parser: pip install -e \".[docs]\" "
                      "(in .[all]; `make docs` installs it)") from None
extensions = ["sphinx.ext.autodoc", "sphinx.ext.napoleon", "myst_parser"]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
# The guides link to each other's sections (certificates.md#statuses); GitHub's
# anchors, which MyST makes for these heading levels.
myst_heading_anchors = 3

# No undoc-members: a dataclass's fields are documented once, by its
# docstring's Attributes section (napoleon), not again as bare attributes.
# No show-inheritance: "Bases: object" on every class says nothing; a class
# with a public base shows it (directive_for; by hand on the facade's page).
autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "signature"
autodoc_class_signature = "mixed"
napoleon_google_docstring = False
napoleon_numpy_docstring = True

html_theme = "alabaster"
html_title = "qpcontact API reference"
html_theme_options = {"page_width": "1100px", "sidebar_width": "240px"}
exclude_patterns = ["_build"]
html_copy_source = False  # the pages are directives; the source worth reading is the code
smartquotes = False  # ' is the transpose in the docstrings' formulas (M'z), not a quote

PUBLIC_NAMES = re.compile(r"^\.\. public-names:: (\S+)[ \t]*$", re.MULTILINE)


def public_bases(cls) -> list:
    return [b for b in cls.__bases__ if b is not object and not b.__name__.startswith("_")]


def directive_for(obj) -> tuple[str, list[str]]:
    """The autodoc directive (with its options) that documents ``obj``."""
    if isinstance(obj, types.ModuleType):
        return "automodule", ["members"]
    if inspect.isclass(obj):
        kind = "autoexception" if issubclass(obj, BaseException) else "autoclass"
        return kind, ["members"] + (["show-inheritance"] if public_bases(obj) else [])
    if inspect.isroutine(obj):
        return "autofunction", []
    # a value a person reads at a glance, not a scene schema's repr
    return "autodata", [] if len(repr(obj)) <= 100 else ["no-value"]


def expand_public_names(module_name: str) -> str:
    """reST for every name in the module's ``__all__``, in its order."""
    module = importlib.import_module(module_name)
    lines = [f".. automodule:: {module_name}", "", f".. currentmodule:: {module_name}", ""]
    for name in module.__all__:
        obj = getattr(module, name)
        kind, options = directive_for(obj)
        target = obj.__name__ if isinstance(obj, types.ModuleType) else name
        lines.append(f".. {kind}:: {target}")
        lines += [f"   :{opt}:" for opt in options]
        lines.append("")
        if kind == "automodule":  # it moved the current module to the submodule
            lines += [f".. currentmodule:: {module_name}", ""]
    return "\n".join(lines)


def check_guides(app):
    """Every guide in ``docs/`` has its page: a stub ``docs/api/guides/NAME.md``
    that includes it (and index.rst places the stub in the reading order)."""
    from sphinx.util import logging
    stubs = {p.name for p in (Path(app.srcdir) / "guides").glob("*.md")}
    for page in sorted((ROOT / "docs").glob("*.md")):
        if page.name not in stubs:
            logging.getLogger(__name__).warning(
                f"docs/{page.name} is not in the API reference: add docs/api/guides/{page.name} "
                f"(a copy of another stub, naming it) and list it in docs/api/index.rst")


def on_source_read(app, docname, source):
    source[0] = PUBLIC_NAMES.sub(lambda m: expand_public_names(m.group(1)), source[0])


def data_comment(module_name: str, name: str, obj):
    """The ``#:`` comment of a module-level constant, read from the module that
    defines it (a package's ``__init__`` only re-exports it)."""
    from sphinx.pycode import ModuleAnalyzer
    top = module_name.split(".")[0]
    for modname, module in sorted(sys.modules.items()):
        if not (modname == top or modname.startswith(top + ".")) or module is None:
            continue
        if getattr(module, name, None) is not obj:
            continue
        try:
            docs = ModuleAnalyzer.for_module(modname).find_attr_docs()
        except Exception:  # no source: nothing to read
            continue
        if ("", name) in docs:
            return list(docs[("", name)])
    return None


ATTRIBUTE_KINDS = ("data", "attribute", "property")
_kept = {}


def before_napoleon(app, what, name, obj, options, lines):
    """A constant re-exported by a package keeps the comment written where it
    is defined, never the docstring of its type (``dict``, ``float``); and a
    constant's or attribute's text is kept from napoleon, which reads a first
    line "words: more" as "type: description" (the project writes no types
    there)."""
    if what not in ATTRIBUTE_KINDS:
        return
    if what == "data":  # a value has no docstring of its own, only its type's
        module_name, _, short = name.rpartition(".")
        lines[:] = data_comment(module_name, short, obj) or []
    _kept[id(lines)] = list(lines)


def after_napoleon(app, what, name, obj, options, lines):
    if id(lines) in _kept:
        lines[:] = _kept.pop(id(lines))


def on_process_bases(app, name, obj, options, bases):
    """Private bases (``_LCPBase``) are no part of the reference."""
    bases[:] = [b for b in bases if b in public_bases(obj)]


def setup(app):
    app.connect("builder-inited", check_guides)
    app.connect("source-read", on_source_read)
    # napoleon's handler runs at the default priority, 500
    app.connect("autodoc-process-docstring", before_napoleon, priority=499)
    app.connect("autodoc-process-docstring", after_napoleon, priority=501)
    app.connect("autodoc-process-bases", on_process_bases)
