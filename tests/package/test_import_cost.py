"""What the first touch costs: ``import qpcontact`` and ``qpcontact
--help`` load none of the heavy modules, and a compiled kernel is kept on disk
so that a second process loads it instead of compiling it.  Each check runs in
a fresh interpreter: this one has imported everything already."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from tests.helpers.paths import ROOT

#: loaded by the methods that use them, never by the import: numba ~0.3 s,
#: scipy.linalg ~0.25 s, qpsolvers (every backend it finds) ~0.1–0.4 s
HEAVY = ("numba", "scipy.linalg", "scipy.optimize", "scipy.sparse.linalg", "qpsolvers", "cvxpy",
         "matplotlib", "h5py")


def _run(code: str, env=None, cwd=ROOT) -> dict:
    """Run ``code`` in a fresh interpreter; it prints one JSON value."""
    env = dict(os.environ if env is None else env)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")])
    res = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], cwd=cwd, env=env,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr[-3000:]
    return json.loads(res.stdout.strip().splitlines()[-1])


def test_the_facade_loads_no_heavy_module():
    """Every public name of qpcontact resolved, and still none of HEAVY."""
    loaded = _run(f"""
        import json, sys
        import qpcontact
        for name in qpcontact.__all__:
            getattr(qpcontact, name)
        print(json.dumps([m for m in {HEAVY!r} if m in sys.modules]))
    """)
    assert loaded == []


def test_the_control_sees_a_heavy_import():
    """The check above can fail: a solve by a pivoting method loads numba,
    one by a QP backend loads qpsolvers."""
    loaded = _run(f"""
        import json, sys
        import qpcontact
        lcp = qpcontact.LCP([[2.0, 1.0], [1.0, 2.0]], [-5.0, -6.0])
        qpcontact.solve(lcp, method="energy")
        qpcontact.solve(lcp, method="osqp")
        print(json.dumps([m for m in {HEAVY!r} if m in sys.modules]))
    """)
    assert "numba" in loaded and "qpsolvers" in loaded


def test_help_loads_neither_numpy_nor_the_engine():
    """`qpcontact --help` and `qpcontact solve --help` draw their help from
    typer alone."""
    loaded = _run("""
        import json, sys
        from qpcontact.commands.cli import app
        for args in (["--help"], ["solve", "--help"]):
            try:
                app(args)
            except SystemExit as exc:
                assert exc.code == 0, exc.code
        print(json.dumps(sorted(m for m in sys.modules if m == "numpy" or
                                m.startswith(("qpcontact.dispatch", "qpcontact.solvers")))))
    """)
    assert loaded == []


def test_the_facade_table_names_what_exists():
    import qpcontact

    for name in qpcontact.__all__:
        assert getattr(qpcontact, name) is not None, name
        assert name in dir(qpcontact)
    assert qpcontact.io.read_problem is not None          # a subpackage, imported on use
    with pytest.raises(AttributeError, match="no attribute 'solv'"):
        qpcontact.solv


_SOLVE_AND_REPORT = """
    import json
    import numpy as np
    import qpcontact
    from qpcontact.solvers.pivoting import _pivot_kernels
    rng = np.random.default_rng(0)
    A = rng.standard_normal((12, 12))
    lcp = qpcontact.LCP(A @ A.T + 12 * np.eye(12), rng.standard_normal(12))
    for method in ("energy", "lemke", "bpp"):
        assert qpcontact.solve(lcp, method=method).ok
    stats = {name: f.stats for name, f in vars(_pivot_kernels).items() if hasattr(f, "stats")}
    print(json.dumps({name: [sum(s.cache_hits.values()), sum(s.cache_misses.values()), s.cache_path]
                      for name, s in stats.items() if s.cache_hits or s.cache_misses}))
"""


def test_a_second_process_loads_the_kernels_instead_of_compiling(tmp_path):
    """The first process compiles the pivoting kernels it calls and writes
    them to the cache; the second loads every one of them."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    first = _run(_SOLVE_AND_REPORT, env)
    second = _run(_SOLVE_AND_REPORT, env)
    assert first and all(misses >= 1 for _, misses, _ in first.values()), first
    assert second.keys() == first.keys()
    for name, (hits, misses, path) in second.items():
        assert misses == 0 and hits >= 1, (name, second)
        assert Path(path).is_relative_to(tmp_path), path


@pytest.mark.skipif(not hasattr(os, "getuid"), reason="POSIX cache folders")
def test_kernels_compile_where_no_cache_folder_is_writable(tmp_path):
    """A read-only package folder and a read-only home: numba itself refuses
    to import a module with cached kernels; qpcontact's njit caches them in
    the temporary folder instead."""
    package = tmp_path / "package"
    package.mkdir()
    (package / "__pycache__").write_text("a file where numba wants a folder")
    (package / "plain_kernels.py").write_text(
        "import numba\n\n@numba.njit(cache=True)\ndef twice(x):\n    return 2 * x\n")
    (package / "our_kernels.py").write_text(
        "from qpcontact.core.compiled import njit\n\n@njit\ndef twice(x):\n    return 2 * x\n")
    temp = tmp_path / "tmp"
    temp.mkdir()
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env.update(HOME="/dev/null/home", XDG_CACHE_HOME="/dev/null/cache", TMPDIR=str(temp),
               PYTHONPATH=str(package))
    code = """
        import json, sys
        sys.path.insert(0, {where!r})
        try:
            import {module} as k
        except RuntimeError as exc:
            print(json.dumps(str(exc)))
        else:
            print(json.dumps([k.twice(21), k.twice.stats.cache_path]))
    """
    refused = _run(code.format(where=str(package), module="plain_kernels"), env)
    assert "no locator available" in refused
    value, cache_path = _run(code.format(where=str(package), module="our_kernels"), env)
    assert value == 42 and Path(cache_path).is_relative_to(temp)
    assert any(Path(cache_path).iterdir())
