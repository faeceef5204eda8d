"""pytest plugin (entry point ``pytest11``, active once qpcontact is installed).

A test that takes a ``qp_method`` argument runs once per selected method::

    def test_my_contact_problem(qp_method):
        sol = qpcontact.solve(my_lcp(), method=qp_method)
        assert_lcp_solution(my_lcp(), sol.z)

Which methods: ``pytest --qp-methods=SPEC`` where SPEC is ``all`` (every
installed method, the default), ``exact`` (the methods with finite
termination: pivoting and active-set), ``pivoting``, ``backends`` (the QP
backends, qpsolvers' and cvxpy's), or a comma-separated list of names
(``--qp-methods=lemke,osqp,clarabel``).  A test narrows the choice with the
marker ``@pytest.mark.qp_methods("pivoting")`` (same SPEC syntax; the
intersection with the command line is taken).
"""

from __future__ import annotations

import pytest

_GROUPS = ("all", "exact", "pivoting", "backends")


def pytest_addoption(parser):
    group = parser.getgroup("qpcontact")
    group.addoption("--qp-methods", dest="qp_methods", default="all", metavar="SPEC",
                    help="methods the qp_method fixture runs over: all (default), exact, "
                         "pivoting, backends, or comma-separated names (e.g. lemke,osqp)")


def pytest_configure(config):
    config.addinivalue_line("markers", "qp_methods(spec): narrow the qp_method fixture's methods "
                                       "(all, exact, pivoting, backends, or names)")
    spec = config.getoption("qp_methods", "all")
    if spec not in _GROUPS:
        select_methods(spec)  # a misspelt name stops the run at once, as a usage error


def select_methods(spec: str) -> list[str]:
    """Installed method names matching SPEC (see the module docstring)."""
    from ..core.errors import QpcontactError
    from ..solvers.registry import get_method, methods

    installed = methods()
    spec = (spec or "all").strip()
    if spec == "all":
        return list(installed)
    if spec == "exact":
        return [n for n, m in installed.items() if m.exact]
    if spec == "pivoting":
        return [n for n, m in installed.items() if m.family == "pivoting"]
    if spec == "backends":
        return [n for n, m in installed.items() if m.family != "pivoting"]
    names = []
    for name in (part.strip() for part in spec.split(",") if part.strip()):
        try:
            names.append(get_method(name).name)
        except QpcontactError as exc:
            raise pytest.UsageError(f"--qp-methods: {exc}") from None
    return names


def pytest_generate_tests(metafunc):
    if "qp_method" not in metafunc.fixturenames:
        return
    chosen = select_methods(metafunc.config.getoption("qp_methods"))
    marker = metafunc.definition.get_closest_marker("qp_methods")
    if marker is not None and marker.args:
        narrowed = set(select_methods(",".join(map(str, marker.args))
                                      if len(marker.args) > 1 else str(marker.args[0])))
        chosen = [name for name in chosen if name in narrowed]
    metafunc.parametrize("qp_method", chosen, ids=chosen)
