"""The layout of docs/architecture.md, kept true: every module's imports read
with ast (never imported), checked for circles, for arrows from a lower layer
to a higher one, for private names across modules, for size, and against the
layer table of the document itself — module by module and folder by folder (a
folder, the first level under a package, is a wing of one layer; folders import
one way, down, without circles).  The self-test plants each fault in a scratch
tree and sees the checks find it.  Where ../shared/tools/imports_check.py is
present (an independent reading of the same rules) it must agree."""

from __future__ import annotations

import ast
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers.paths import ROOT

PACKAGES = ("qpcontact", "formulations")
LIMIT = 600
SHARED_CHECK = ROOT.parent / "shared" / "tools" / "imports_check.py"


def read_modules(root: Path) -> dict:
    """{module name: (path, is_package)} under the packages."""
    out = {}
    for pkg in PACKAGES:
        for path in sorted((root / pkg).rglob("*.py")):
            if "__pycache__" in path.parts:
                continue
            parts = path.relative_to(root).with_suffix("").parts
            is_pkg = parts[-1] == "__init__"
            out[".".join(parts[:-1] if is_pkg else parts)] = (path, is_pkg)
    return out


def _deepest(name: str, modules: dict):
    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        if ".".join(parts[:k]) in modules:
            return ".".join(parts[:k])
    return None


def _nodes(tree):
    """Every node, but not into the body of ``if TYPE_CHECKING:`` (never run)."""
    todo = [tree]
    while todo:
        node = todo.pop()
        yield node
        if isinstance(node, ast.If) and getattr(node.test, "id", getattr(node.test, "attr", "")) \
                == "TYPE_CHECKING":
            todo.extend(node.orelse)
            continue
        todo.extend(ast.iter_child_nodes(node))


def read_imports(name: str, modules: dict):
    """(the modules ``name`` imports, [(line, module, private name)])."""
    path, is_pkg = modules[name]
    tree = ast.parse(path.read_text(), str(path))
    edges, private, aliases = set(), [], {}
    for node in _nodes(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                target = _deepest(a.name, modules)
                if target:
                    edges.add(target)
                    aliases[a.asname or a.name.split(".")[0]] = target if a.asname else \
                        a.name.split(".")[0]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = name.split(".") if is_pkg else name.split(".")[:-1]
                base = base[:len(base) - node.level + 1]
                full_base = ".".join(base + ([node.module] if node.module else []))
            else:
                full_base = node.module or ""
            target = _deepest(full_base, modules)
            if target is None:
                continue
            for a in node.names:
                sub = f"{full_base}.{a.name}"
                if sub in modules:
                    edges.add(sub)
                    aliases[a.asname or a.name] = sub
                    continue
                edges.add(target)
                if a.name.startswith("_") and not a.name.startswith("__") and target != name:
                    private.append((node.lineno, target, a.name))
    for node in _nodes(tree):
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                and node.value.id in aliases and node.attr.startswith("_")
                and not node.attr.startswith("__")
                and f"{aliases[node.value.id]}.{node.attr}" not in modules
                and aliases[node.value.id] != name):
            private.append((node.lineno, aliases[node.value.id], node.attr))
    edges.discard(name)
    return edges, private


def read_graph(root: Path):
    """(modules, {module: (imported modules, private names used)}) of a tree."""
    modules = read_modules(root)
    return modules, {name: read_imports(name, modules) for name in modules}


MODULES, GRAPH = read_graph(ROOT)


def _layers():
    """(patterns: [(pattern, rank)], forbidden: [(from pattern, to pattern)])
    from docs/architecture.md's tables."""
    text = (ROOT / "docs" / "architecture.md").read_text()
    section = text.split("## Layers (read by tests/package/test_architecture.py)")[1]
    section = section.split("\n## ")[0]
    patterns, forbidden = [], []
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 3 and cells[1].isdigit():
            for pattern in re.findall(r"`([^`]+)`", cells[2]):
                patterns.append((pattern, int(cells[1])))
        elif len(cells) == 3 and cells[0].startswith("`") and cells[1].startswith("`"):
            forbidden.append((cells[0].strip("`"), cells[1].strip("`")))
    return patterns, forbidden


PATTERNS, FORBIDDEN = _layers()


def _matches(pattern: str, name: str) -> bool:
    if pattern.endswith(".*"):
        stem = pattern[:-2]
        return name == stem or name.startswith(stem + ".")
    return name == pattern


def rank(name: str):
    """The layer of ``name``: an exact entry first, then the longest pattern."""
    exact = [r for p, r in PATTERNS if not p.endswith(".*") and p == name]
    if exact:
        return exact[0]
    hits = sorted(((len(p), r) for p, r in PATTERNS if p.endswith(".*") and _matches(p, name)),
                  reverse=True)
    return hits[0][1] if hits else None


def folder(name: str, modules: dict) -> str:
    """The folder a module lives in: the first level under its top package
    (``qpcontact.solvers`` for ``qpcontact.solvers.pivoting.lemke``), or the
    top package for a module directly in it (as the shared checker counts)."""
    parts = name.split(".")
    first = ".".join(parts[:2])
    return first if len(parts) > 1 and first in modules and modules[first][1] else parts[0]


def strongly_connected(graph: dict) -> list:
    """Strongly connected components of more than one node (Tarjan);
    ``graph``: {node: iterable of nodes}."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]
    sys.setrecursionlimit(max(10_000, sys.getrecursionlimit()))

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def folder_graph(modules: dict, graph: dict) -> dict:
    """{folder: {folder it imports}}, arrows between different folders only."""
    out = {}
    for a, (edges, _) in graph.items():
        for b in edges:
            fa, fb = folder(a, modules), folder(b, modules)
            if fa != fb:
                out.setdefault(fa, set()).add(fb)
    return out


# -- the checks, each a function of a tree's graph (the self-test plants faults) --

def circles(graph: dict) -> list:
    return strongly_connected({a: edges for a, (edges, _) in graph.items()})


def upward_imports(graph: dict) -> list:
    """[(importer, its rank, imported, its rank)] against the layer table,
    and the forbidden pairs."""
    wrong = [(a, rank(a), b, rank(b)) for a, (edges, _) in graph.items() for b in edges
             if rank(b) is not None and rank(a) is not None and rank(b) > rank(a)]
    wrong += [(a, "forbidden", b, "") for a, (edges, _) in graph.items() for b in edges
              for src, dst in FORBIDDEN if _matches(src, a) and _matches(dst, b)]
    return wrong


def private_names(graph: dict) -> list:
    return [f"{name}:{line} uses {mod}.{attr}" for name, (_, private) in graph.items()
            for line, mod, attr in private]


def mixed_folders(modules: dict) -> dict:
    """{folder: its modules' ranks} for folders whose modules are not all in
    one layer."""
    ranks = {}
    for name in modules:
        ranks.setdefault(folder(name, modules), set()).add(rank(name))
    return {f: sorted(r, key=str) for f, r in ranks.items() if len(r) > 1}


def upward_folder_imports(modules: dict, graph: dict) -> list:
    """[(folder, its rank, imported folder, its rank)] where a folder imports
    one of a higher layer (a folder's rank: its own name's in the table)."""
    return [(fa, rank(fa), fb, rank(fb)) for fa, fbs in folder_graph(modules, graph).items()
            for fb in sorted(fbs) if rank(fb) > rank(fa)]


def folder_circles(modules: dict, graph: dict) -> list:
    return strongly_connected(folder_graph(modules, graph))


# -- the tests --

def test_the_document_places_every_module():
    assert PATTERNS, "docs/architecture.md lost its layer table"
    unplaced = [name for name in MODULES if rank(name) is None]
    assert not unplaced, f"modules docs/architecture.md does not place in a layer: {unplaced}"


def test_no_import_circle():
    assert not circles(GRAPH), f"import circles: {circles(GRAPH)}"


def test_imports_point_down():
    wrong = upward_imports(GRAPH)
    assert not wrong, "imports against docs/architecture.md's layers:\n" + "\n".join(
        f"  {a} (layer {ra}) imports {b} (layer {rb})" for a, ra, b, rb in wrong)


def test_no_private_name_across_modules():
    found = private_names(GRAPH)
    assert not found, "private names imported across modules:\n" + "\n".join(found)


def test_each_folder_is_a_wing_of_one_layer():
    mixed = mixed_folders(MODULES)
    assert not mixed, f"folders whose modules sit in several layers: {mixed}"


def test_folders_import_down_without_circles():
    wrong = upward_folder_imports(MODULES, GRAPH)
    assert not wrong, "folders importing a higher layer:\n" + "\n".join(
        f"  {a} (layer {ra}) imports {b} (layer {rb})" for a, ra, b, rb in wrong)
    assert not folder_circles(MODULES, GRAPH), f"folder circles: {folder_circles(MODULES, GRAPH)}"


def test_no_module_over_the_size_limit():
    big = [(str(path.relative_to(ROOT)), n) for path, _ in MODULES.values()
           if (n := path.read_text().count("\n")) > LIMIT
           and not (path.name.startswith("_") and path.name.endswith("_kernels.py"))]
    assert not big, f"modules over {LIMIT} lines: {big}"


def test_the_folder_counts_are_the_documents():
    """docs/architecture.md states how many folders and folder arrows the
    picture has; the reading agrees (a new arrow is a decision to write down)."""
    text = (ROOT / "docs" / "architecture.md").read_text()
    stated = re.search(r"(\d+) folders and (\d+) arrows between them", text)
    assert stated, "docs/architecture.md lost its folder count"
    folders = {folder(m, MODULES) for m in MODULES}
    arrows = sum(len(v) for v in folder_graph(MODULES, GRAPH).values())
    assert (len(folders), arrows) == (int(stated.group(1)), int(stated.group(2))), (
        f"the package now has {len(folders)} folders and {arrows} arrows between them; "
        "docs/architecture.md states its counts: change them there with the reason for the new "
        f"folder or arrow. The arrows: {sorted(folder_graph(MODULES, GRAPH).items())}")


def _plant(root: Path, files: dict) -> None:
    for rel, text in files.items():
        path = root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


def test_the_checker_sees_what_it_checks(tmp_path):
    """Each check can fail: in a scratch tree read as the real one is, a
    planted module circle, an upward import, a private name, a folder that
    mixes layers and a circle between two folders (with no module circle)
    are each found — and the clean parts of the same tree are not flagged."""
    _plant(tmp_path, {
        "qpcontact/__init__.py": "",
        "qpcontact/core/__init__.py": "",
        "qpcontact/judge/__init__.py": "",
        # upward (core -> judge) and a private name; with b -> a, a module circle
        "qpcontact/core/a.py": "from qpcontact.judge.b import _x\n",
        "qpcontact/judge/b.py": "from ..core import a\n_x = 1\n",
        # a clean downward import, through a relative form and inside a function
        "qpcontact/judge/c.py": "def f():\n    from ..core.a import y\n",
        "qpcontact/core/d.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                               "    from qpcontact.judge import c\n",
        # two formulation folders importing each other through different modules
        "formulations/__init__.py": "",
        "formulations/x/__init__.py": "",
        "formulations/x/m.py": "from formulations.y import n\n",
        "formulations/x/k.py": "",
        "formulations/y/__init__.py": "",
        "formulations/y/n.py": "",
        "formulations/y/p.py": "from formulations.x import k\n",
        # a judge module placed among the methods' folder: a mixed folder
        "qpcontact/solvers/__init__.py": "",
        "qpcontact/solvers/measures.py": "",
    })
    modules, graph = read_graph(tmp_path)
    assert circles(graph) == [["qpcontact.core.a", "qpcontact.judge.b"]]
    assert upward_imports(graph) == [("qpcontact.core.a", 0, "qpcontact.judge.b", 1)]
    assert private_names(graph) == ["qpcontact.core.a:1 uses qpcontact.judge.b._x"]
    # the module circle is a folder circle too; the formulations' is one of folders alone
    assert folder_circles(modules, graph) == [["formulations.x", "formulations.y"],
                                              ["qpcontact.core", "qpcontact.judge"]]
    assert upward_folder_imports(modules, graph) == [("qpcontact.core", 0, "qpcontact.judge", 1)]
    global PATTERNS
    saved = PATTERNS
    try:
        PATTERNS = saved + [("qpcontact.solvers.measures", 1)]
        assert mixed_folders(modules) == {"qpcontact.solvers": [1, 2]}
    finally:
        PATTERNS = saved
    assert rank("qpcontact.core.friction_problem") == 0
    assert rank("qpcontact.judge.friction_certificate") == 1
    assert rank("qpcontact.solvers.friction.nsgs") == 2 and rank("qpcontact") == 6


@pytest.mark.skipif(not SHARED_CHECK.exists(), reason="../shared/tools/imports_check.py absent")
def test_the_shared_checker_agrees():
    """An independent reading (the shared tool): no circle, no oversized module,
    no private name across modules, and the same import edges."""
    spec = importlib.util.spec_from_file_location("imports_check", SHARED_CHECK)
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    res = tool.check(str(ROOT))
    assert res["circles"] == [] and res["oversized"] == [] and res["private"] == [], res
    assert res.get("folder_circles", []) == [], res["folder_circles"]
    ours = {(a, b) for a, (edges, _) in GRAPH.items() for b in edges}
    theirs = {(a, b) for a, bs in res["graph"].items() for b in bs}
    assert ours == theirs, (sorted(ours - theirs)[:10], sorted(theirs - ours)[:10])


def test_requires_python_is_what_the_code_needs():
    """pyproject's requires-python equals the oldest Python the code runs on,
    as vermin reads it from the source (tomllib: 3.11)."""
    pytest.importorskip("vermin")
    # vermin has no __main__: its console script's entry point, in this interpreter
    code = "import sys; from vermin import main; sys.exit(main())"
    out = subprocess.run([sys.executable, "-c", code, "--no-tips", "--eval-annotations",
                          *PACKAGES], cwd=ROOT, capture_output=True, text=True).stdout
    found = re.search(r"Minimum required versions:.*?(3\.\d+)", out)
    assert found, out
    declared = re.search(r'requires-python\s*=\s*">=\s*(3\.\d+)"',
                         (ROOT / "pyproject.toml").read_text()).group(1)
    assert declared == found.group(1), f"requires-python >={declared}; the code needs {found.group(1)}"
