"""One option checker for every method (qpcontact.core.options): the values
an audit found accepted silently or failing deep inside a method are refused
before any work, naming the method, the option and the value; good values
still pass."""

from __future__ import annotations

import numpy as np
import pytest

import qpcontact
from qpcontact import LCP
from qpcontact.cases.planted_friction import build_friction
from qpcontact.core.errors import InvalidOptionError, InvalidProblemError
from qpcontact.core.friction_problem import FrictionProblem
from qpcontact.core.options import (BySize, Option, check_options, int_option, names_only,
                                    options_doc, read_options)


@pytest.fixture(scope="module")
def friction():
    """A small frictional problem (3-D, 4 contacts, planted solution)."""
    return build_friction("mixed", 4, seed=1, dim=3).problem


# -- the checker itself -------------------------------------------------------

SPEC = (
    Option("count", 10, "int", low=0, doc="how many"),
    Option("size", BySize(lambda n: 2 * n, "2 n"), "int", low=1),
    Option("rate", 1.0, "float", low=0.0, high=2.0, low_open=True, high_open=True),
    Option("flag", False, "bool"),
    Option("hook", None, "callable"),
    Option("start", None, "vector"),
    Option("rule", "a", "choice", choices=("a", "b")),
    Option("settings", {}, "mapping", none_ok=True),
    Option("thing", None, "any"),
)


def test_defaults_are_filled_and_values_converted():
    out = read_options("m", {"count": np.int64(3), "rate": 1, "start": [1, 2]}, SPEC, size=5)
    assert out["count"] == 3 and type(out["count"]) is int
    assert out["size"] == 10 and out["rate"] == 1.0 and out["flag"] is False
    assert out["start"].dtype == float and out["start"].tolist() == [1.0, 2.0]
    assert out["rule"] == "a" and out["settings"] == {} and out["thing"] is None
    assert read_options("m", {"count": 4.0}, SPEC, size=1)["count"] == 4   # integral float
    assert read_options("m", {"hook": None, "settings": None}, SPEC, size=1)["settings"] is None


@pytest.mark.parametrize("name, value, expected", [
    ("count", -5, "an integer >= 0"), ("count", 1.5, "an integer >= 0"),
    ("count", True, "an integer"), ("count", "3", "an integer"), ("count", None, "an integer"),
    ("count", float("nan"), "an integer"), ("rate", 2.0, r"a number in \(0, 2\)"),
    ("rate", float("nan"), "a number"), ("flag", 1, "True or False"),
    ("hook", "notcallable", "a callable"), ("rule", "c", "one of 'a', 'b'"),
    ("rule", ["a"], "one of"), ("settings", [1], "a dict"), ("start", "abc", "vector"),
])
def test_bad_values_are_named(name, value, expected):
    with pytest.raises(InvalidOptionError, match=expected) as info:
        read_options("m", {name: value}, SPEC, size=1)
    text = str(info.value)
    assert text.startswith(f"'m': option {name} must be ")
    assert f"got {value!r}"[:20] in text
    assert "leave it out for the default" in text


def test_vectors_must_be_finite_and_the_first_bad_entry_is_named():
    for bad, shown in ((np.nan, "nan"), (np.inf, "inf"), (-np.inf, "-inf")):
        with pytest.raises(InvalidOptionError, match=f"option start .*entry 2 is {shown}"):
            read_options("m", {"start": [0.0, 1.0, bad, bad]}, SPEC, size=1)
    spec = (Option("d", None, "vector", low=0.0, low_open=True),)
    with pytest.raises(InvalidOptionError, match="each > 0.*entry 1 is -1"):
        read_options("m", {"d": [1.0, -1.0]}, spec)


def test_unknown_names_are_refused_with_a_close_match_and_the_list():
    with pytest.raises(InvalidOptionError,
                       match=r"'m' does not take cuont \(did you mean count\?\); it takes "
                             r"count, size, rate"):
        read_options("m", {"cuont": 3}, SPEC, size=1)
    with pytest.raises(InvalidOptionError, match="'m' does not take zzz; it takes no options"):
        read_options("m", {"zzz": 1}, ())


def test_names_only_and_the_first_interface():
    assert read_options("b", {"eps": 1}, names_only({"eps", "tol"})) == {"eps": 1}
    with pytest.raises(InvalidOptionError, match="did you mean eps"):
        read_options("b", {"ep": 1}, names_only({"eps", "tol"}), word="setting")
    check_options("tresca", {"max_iter": 3}, ("qp_method", "max_iter"))
    with pytest.raises(InvalidOptionError, match="does not take max_iters"):
        check_options("tresca", {"max_iters": 3}, ("qp_method", "max_iter"))
    assert int_option("m", {"k": 4.0}, "k", 1) == 4 and int_option("m", {}, "k", 7) == 7
    with pytest.raises(InvalidOptionError, match="option k must be an integer >= 2; got 1"):
        int_option("m", {"k": 1}, "k", 5, minimum=2)


def test_the_docstring_list_comes_from_the_spec():
    text = options_doc(SPEC)
    assert "``count``: how many (an integer >= 0; default 10)" in text
    assert "default 2 n" in text


# -- the methods ----------------------------------------------------------------

@pytest.mark.parametrize("method", ["nsgs", "nsgs-newton"])
@pytest.mark.parametrize("value", [-5, 1.5])
def test_max_sweeps_must_be_a_count(friction, method, value):
    with pytest.raises(InvalidOptionError,
                       match=rf"'{method}': option max_sweeps must be an integer >= 0; "
                             rf"got {value}.*leave it out for the default"):
        qpcontact.solve(friction, method, max_sweeps=value)


@pytest.mark.parametrize("method", ["nsgs", "newton", "nsgs-newton"])
@pytest.mark.parametrize("bad, shown", [(np.nan, "nan"), (np.inf, "inf")])
def test_r0_must_be_finite(friction, method, bad, shown):
    r0 = np.zeros(3 * friction.n_contacts)
    r0[4] = bad
    with pytest.raises(InvalidOptionError, match=rf"'{method}': option r0 .*entry 4 is {shown}"):
        qpcontact.solve(friction, method, r0=r0)


@pytest.mark.parametrize("method", ["nsgs", "newton", "nsgs-newton"])
def test_r0_must_have_the_problems_length(friction, method):
    with pytest.raises(InvalidOptionError, match=rf"'{method}': option r0 must have 12 entries"):
        qpcontact.solve(friction, method, r0=np.zeros(5))


@pytest.mark.parametrize("method", ["newton", "nsgs-newton", "desaxce-fp"])
def test_progress_must_be_callable(friction, method):
    with pytest.raises(InvalidOptionError,
                       match=rf"'{method}': option progress must be a callable; got 'notcallable'"):
        qpcontact.solve(friction, method, progress="notcallable")


def test_unknown_friction_option_gets_a_suggestion(friction):
    with pytest.raises(InvalidOptionError,
                       match=r"'nsgs' does not take max_sweep \(did you mean max_sweeps\?\); "
                             r"it takes max_sweeps, check_every"):
        qpcontact.solve(friction, "nsgs", max_sweep=10)
    with pytest.raises(InvalidOptionError, match=r"did you mean inner_tol\?"):
        qpcontact.solve(friction, "desaxce-fp", inner_tl=1e-9)


def test_other_friction_values(friction):
    with pytest.raises(InvalidOptionError, match=r"option omega must be a number in \(0, 2\)"):
        qpcontact.solve(friction, "nsgs", omega=2.5)
    with pytest.raises(InvalidOptionError, match="option max_outer must be an integer >= 1"):
        qpcontact.solve(friction, "tresca-fp", max_outer=0)
    with pytest.raises(InvalidOptionError, match="option backend_options must be a dict"):
        qpcontact.solve(friction, "anitescu", backend_options=3)
    with pytest.raises(InvalidOptionError, match="option facets must be an integer; got 8.5"):
        qpcontact.solve(friction, "lemke", facets=8.5)


def test_lemke_max_pivots_must_be_an_integer():
    lcp = LCP(np.eye(2) * 2, [-1.0, -1.0])
    with pytest.raises(InvalidOptionError,
                       match=r"'lemke': option max_pivots must be an integer >= 0; got 2.5 "
                             r"\(leave it out for the default, max\(10 000, 50 n\)\)"):
        qpcontact.solve(lcp, "lemke", max_pivots=2.5)
    with pytest.raises(InvalidOptionError, match="'enumeration' does not take seed"):
        qpcontact.solve(lcp, "enumeration", seed=1)


def test_good_options_still_solve(friction):
    r0 = np.zeros(3 * friction.n_contacts)
    lines = []
    for method, options in [
            ("nsgs", dict(max_sweeps=20_000, check_every=5, r0=r0, omega=1.2, local_rtol=1e-14,
                          max_local=300)),
            ("nsgs-newton", dict(omega=1.3, max_sweeps=50_000.0, r0=list(r0),
                                 progress=lines.append)),
            ("newton", dict(max_iter=np.int64(50), progress=lines.append)),
            ("desaxce-fp", dict(max_outer=200, inner_tol=1e-11, backend_options=None))]:
        # a fixed point of SOCPs stalls near 1e-8 on this problem: asked for 1e-6
        sol = qpcontact.solve(friction, method, accuracy=1e-6 if "fp" in method else 1e-8,
                              **options)
        assert sol.ok, (method, sol.message)
    assert lines
    lcp = LCP([[2.0, 1.0], [1.0, 2.0]], [-1.0, -1.0])
    for method, options in [("lemke", dict(max_pivots=100, restarts=2, seed=None,
                                           covering=[1.0, 2.0])),
                            ("bpp", dict(max_iter=50, patience=2, initial_active=[0])),
                            ("energy", dict(max_pivots=20, rule="murty")),
                            ("ip-bpp", dict(max_ip=10, ip_drop=1e8, progress=lines.append)),
                            ("mg-bpp", dict(max_cycles=5, max_iter=50)),
                            ("enumeration", {})]:
        sol = qpcontact.solve(lcp, method, **options)
        assert sol.ok and np.allclose(sol.z, [1 / 3, 1 / 3]), (method, sol.message)


def test_the_trace_reads_its_options():
    plcp = qpcontact.ParametricLCP(np.eye(2), [1.0, 1.0], [-1.0, -2.0])
    with pytest.raises(InvalidOptionError, match="'trace': option max_pieces must be an integer "
                                                 ">= 1; got 0"):
        qpcontact.solve(plcp, "trace", max_pieces=0)
    with pytest.raises(InvalidOptionError, match=r"'trace': option p_max must be a number > 0"):
        qpcontact.solve(plcp, "trace", p_max="far")
    with pytest.raises(InvalidOptionError, match=r"did you mean p_max\?"):
        qpcontact.solve(plcp, "trace", pmax=2.0)
    assert qpcontact.solve(plcp, "trace", p_max=3.0, max_pieces=50.0).status == "solved"


def test_method_docstrings_name_every_option():
    from qpcontact.solvers.friction.fixed_points import (ANITESCU_OPTIONS, FIXED_POINT_OPTIONS,
                                                         solve_anitescu, solve_desaxce_fp,
                                                         solve_desaxce_global, solve_tresca_fp)
    from qpcontact.solvers.friction.hybrid import NSGS_NEWTON_OPTIONS, solve_nsgs_newton
    from qpcontact.solvers.friction.newton import NEWTON_OPTIONS, solve_natural_newton
    from qpcontact.solvers.friction.nsgs import NSGS_OPTIONS, solve_nsgs
    from qpcontact.solvers.pivoting import bpp, energy, ip_bpp, lemke, mg_bpp
    from qpcontact.solvers.trace.tracer import TRACE_OPTIONS, run_trace

    pairs = [(solve_nsgs, NSGS_OPTIONS), (solve_nsgs_newton, NSGS_NEWTON_OPTIONS),
             (solve_natural_newton, NEWTON_OPTIONS), (solve_anitescu, ANITESCU_OPTIONS),
             (solve_desaxce_fp, FIXED_POINT_OPTIONS), (solve_tresca_fp, FIXED_POINT_OPTIONS),
             (solve_desaxce_global, FIXED_POINT_OPTIONS), (run_trace, TRACE_OPTIONS),
             (bpp.run_bpp, bpp.BPP_OPTIONS), (energy.run_energy, energy.ENERGY_OPTIONS),
             (lemke.run_lemke, lemke.LEMKE_OPTIONS)]
    for function, spec in pairs:
        for opt in spec:
            if opt.name != "engine":      # passed by qpcontact.solve, not by users
                assert f"``{opt.name}``" in function.__doc__, (function.__name__, opt.name)
    for module, spec in [(ip_bpp, ip_bpp.IP_BPP_OPTIONS), (mg_bpp, mg_bpp.MG_BPP_OPTIONS)]:
        for opt in spec:
            assert f"``{opt.name}``" in module.__doc__, (module.__name__, opt.name)


# -- the problem ------------------------------------------------------------------

@pytest.mark.parametrize("mu", ["abc", ["0.3", "x"], [0.3, [1, 2]]])
def test_friction_coefficients_must_be_numbers(mu):
    with pytest.raises(InvalidProblemError, match="friction coefficients mu must be numbers"):
        FrictionProblem(np.eye(2), [-1.0, 0.0], mu, 2)
    with pytest.raises(InvalidProblemError, match="friction coefficients mu must be numbers"):
        FrictionProblem.global_problem(np.eye(2), np.eye(2), np.zeros(2), np.zeros(2), mu, 2)
