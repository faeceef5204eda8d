"""pytest plugin (entry point ``pytest11``, active once qpcontact is installed).

A test that takes one of these arguments runs once per selected method that
solves its kind of problem:

``qp_method``
    the methods that solve LCPs and QPs;
``friction_method``
    the methods that solve local frictional contact problems (2-D or 3-D:
    the friction methods, and Lemke's and enumeration through the faceted LCP);
``global_friction_method``
    the methods that solve global frictional problems kept without W.

::

    def test_my_contact_problem(qp_method):
        sol = qpcontact.solve(my_lcp(), method=qp_method)
        assert_lcp_solution(my_lcp(), sol.z)

    def test_my_frictional_model(friction_method):
        prob = my_model.friction_problem()
        sol = qpcontact.solve(prob, method=friction_method, accuracy=1e-8)
        assert_friction_solution(prob, sol.r, tol=1e-8)

Which methods: ``pytest --qp-methods=SPEC`` where SPEC is ``all`` (every
installed method, the default), ``exact`` (finite termination at an exact
answer on the fixture's kind: pivoting and active-set methods; for local
friction, the exact 2-D routes), ``pivoting``, ``backends`` (the QP backends,
qpsolvers' and cvxpy's), ``friction`` (the friction family), or a
comma-separated list of names (``--qp-methods=lemke,osqp,nsgs``).  A test
narrows the choice with the marker ``@pytest.mark.qp_methods("pivoting")``
(same SPEC syntax; the intersection with the command line is taken).
"""

from __future__ import annotations

import pytest

_GROUPS = ("all", "exact", "pivoting", "backends", "friction")

#: fixture name -> the problem kinds (``Method.problems``) its methods solve
FIXTURES = {
    "qp_method": ("lcp", "qp"),
    "friction_method": ("friction-2d", "friction-3d"),
    "global_friction_method": ("friction-global",),
}


def pytest_addoption(parser):
    group = parser.getgroup("qpcontact")
    group.addoption("--qp-methods", dest="qp_methods", default="all", metavar="SPEC",
                    help="methods the qp_method / friction_method fixtures run over: all "
                         "(default), exact, pivoting, backends, friction, or comma-separated "
                         "names (e.g. lemke,osqp,nsgs)")


def pytest_configure(config):
    config.addinivalue_line("markers", "qp_methods(spec): narrow the qp_method / friction_method "
                                       "fixtures' methods (all, exact, pivoting, backends, "
                                       "friction, or names)")
    spec = config.getoption("qp_methods", "all")
    if spec not in _GROUPS:
        select_methods(spec)  # a misspelt name stops the run at once, as a usage error


def select_methods(spec: str, kinds=None) -> list[str]:
    """Installed method names matching SPEC (see the module docstring) that
    solve at least one of ``kinds`` (default: any kind)."""
    from ..core.errors import QpcontactError
    from ..solvers.registry import get_method, methods

    installed = {n: m for n, m in methods().items()
                 if kinds is None or any(m.solves(k) for k in kinds)}
    spec = (spec or "all").strip()
    if spec == "all":
        return list(installed)
    if spec == "exact":
        return [n for n, m in installed.items()
                if any(m.exact_on(k) for k in (kinds or m.problems))]
    if spec == "pivoting":
        return [n for n, m in installed.items() if m.family == "pivoting"]
    if spec == "backends":
        return [n for n, m in installed.items() if m.family in ("qpsolvers", "cvxpy")]
    if spec == "friction":
        return [n for n, m in installed.items() if m.family == "friction"]
    names = []
    for name in (part.strip() for part in spec.split(",") if part.strip()):
        try:
            m = get_method(name)
        except QpcontactError as exc:
            raise pytest.UsageError(f"--qp-methods: {exc}") from None
        if m.name in installed:
            names.append(m.name)
    return names


def pytest_generate_tests(metafunc):
    for fixture, kinds in FIXTURES.items():
        if fixture not in metafunc.fixturenames:
            continue
        chosen = select_methods(metafunc.config.getoption("qp_methods"), kinds)
        marker = metafunc.definition.get_closest_marker("qp_methods")
        if marker is not None and marker.args:
            narrowed = set(select_methods(",".join(map(str, marker.args))
                                          if len(marker.args) > 1 else str(marker.args[0])))
            chosen = [name for name in chosen if name in narrowed]
        metafunc.parametrize(fixture, chosen, ids=chosen)
