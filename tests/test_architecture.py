"""The layout of docs/architecture.md, kept true: every module's imports read
with ast (never imported), checked for circles, for arrows from a lower layer
to a higher one, for private names across modules, for size, and against the
layer table of the document itself.  Where ../shared/tools/imports_check.py is
present (an independent reading of the same rules) it must agree."""

from __future__ import annotations

import ast
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("qpcontact", "formulations")
LIMIT = 600
SHARED_CHECK = ROOT.parent / "shared" / "tools" / "imports_check.py"


def _modules() -> dict:
    """{module name: (path, is_package)} under the packages."""
    out = {}
    for pkg in PACKAGES:
        for path in sorted((ROOT / pkg).rglob("*.py")):
            if "__pycache__" in path.parts:
                continue
            parts = path.relative_to(ROOT).with_suffix("").parts
            is_pkg = parts[-1] == "__init__"
            out[".".join(parts[:-1] if is_pkg else parts)] = (path, is_pkg)
    return out


MODULES = _modules()


def _deepest(name: str):
    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        if ".".join(parts[:k]) in MODULES:
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


def _imports(name: str):
    """(the modules ``name`` imports, [(line, module, private name)])."""
    path, is_pkg = MODULES[name]
    tree = ast.parse(path.read_text(), str(path))
    edges, private, aliases = set(), [], {}
    for node in _nodes(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                target = _deepest(a.name)
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
            target = _deepest(full_base)
            if target is None:
                continue
            for a in node.names:
                sub = f"{full_base}.{a.name}"
                if sub in MODULES:
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
                and f"{aliases[node.value.id]}.{node.attr}" not in MODULES
                and aliases[node.value.id] != name):
            private.append((node.lineno, aliases[node.value.id], node.attr))
    edges.discard(name)
    return edges, private


GRAPH = {name: _imports(name) for name in MODULES}


def _layers():
    """(patterns: [(pattern, rank)], forbidden: [(from pattern, to pattern)])
    from docs/architecture.md's tables."""
    text = (ROOT / "docs" / "architecture.md").read_text()
    section = text.split("## Layers (read by tests/test_architecture.py)")[1].split("\n## ")[0]
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


def _rank(name: str):
    """The layer of ``name``: an exact entry first, then the longest pattern."""
    exact = [r for p, r in PATTERNS if not p.endswith(".*") and p == name]
    if exact:
        return exact[0]
    hits = sorted(((len(p), r) for p, r in PATTERNS if p.endswith(".*") and _matches(p, name)),
                  reverse=True)
    return hits[0][1] if hits else None


def _circles() -> list:
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]
    sys.setrecursionlimit(max(10_000, sys.getrecursionlimit()))

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(GRAPH[v][0]):
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

    for v in sorted(GRAPH):
        if v not in index:
            visit(v)
    return out


def test_the_document_places_every_module():
    assert PATTERNS, "docs/architecture.md lost its layer table"
    unplaced = [name for name in MODULES if _rank(name) is None]
    assert not unplaced, f"modules docs/architecture.md does not place in a layer: {unplaced}"


def test_no_import_circle():
    assert not _circles(), f"import circles: {_circles()}"


def test_imports_point_down():
    wrong = [(a, _rank(a), b, _rank(b)) for a, (edges, _) in GRAPH.items() for b in edges
             if _rank(b) > _rank(a)]
    wrong += [(a, "forbidden", b, "") for a, (edges, _) in GRAPH.items() for b in edges
              for src, dst in FORBIDDEN if _matches(src, a) and _matches(dst, b)]
    assert not wrong, "imports against docs/architecture.md's layers:\n" + "\n".join(
        f"  {a} (layer {ra}) imports {b} (layer {rb})" for a, ra, b, rb in wrong)


def test_no_private_name_across_modules():
    found = [f"{name}:{line} uses {mod}.{attr}" for name, (_, private) in GRAPH.items()
             for line, mod, attr in private]
    assert not found, "private names imported across modules:\n" + "\n".join(found)


def test_no_module_over_the_size_limit():
    big = [(str(path.relative_to(ROOT)), n) for path, _ in MODULES.values()
           if (n := path.read_text().count("\n")) > LIMIT
           and not (path.name.startswith("_") and path.name.endswith("_kernels.py"))]
    assert not big, f"modules over {LIMIT} lines: {big}"


def test_the_checker_sees_what_it_checks():
    """The reading above can fail: a planted circle, an upward import and a
    private name in a scratch package are all found."""
    global MODULES, GRAPH
    saved = MODULES, GRAPH
    try:
        MODULES = {"qpcontact.core.a": None, "qpcontact.judge.b": None}
        GRAPH = {"qpcontact.core.a": ({"qpcontact.judge.b"}, []),
                 "qpcontact.judge.b": ({"qpcontact.core.a"}, [(3, "qpcontact.core.a", "_x")])}
        assert _circles() == [["qpcontact.core.a", "qpcontact.judge.b"]]
        assert _rank("qpcontact.core.a") == 0 and _rank("qpcontact.judge.b") == 1
        assert _rank("qpcontact.friction.problem") == 0
        assert _rank("qpcontact.friction.nsgs") == 2 and _rank("qpcontact") == 6
    finally:
        MODULES, GRAPH = saved


@pytest.mark.skipif(not SHARED_CHECK.exists(), reason="../shared/tools/imports_check.py absent")
def test_the_shared_checker_agrees():
    """An independent reading (the shared tool): no circle, no oversized module,
    no private name across modules, and the same import edges."""
    spec = importlib.util.spec_from_file_location("imports_check", SHARED_CHECK)
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    res = tool.check(str(ROOT))
    assert res["circles"] == [] and res["oversized"] == [] and res["private"] == [], res
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
