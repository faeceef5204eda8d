"""What a method is: a run function and the capabilities it declares.

A method is ``run(problem, tol, options) -> MethodResult`` (a backend's run
may also take ``time_limit=``).  ``tol`` is the tolerance to ask of it, or
None for its own defaults; ``options`` are its own settings, passed through.
It receives the problem in the form it ``takes`` — :func:`qpcontact.solve`
converts (an LCP to its QP, a QP to its dual LCP, a frictional problem to its
faceted LCP), times the call and certifies the answer from the data: methods
never certify themselves.  ``problems`` lists every kind a method solves,
directly or through such a conversion; ``qpcontact methods`` prints them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

__all__ = ["Method", "PROBLEM_KINDS", "TAKES"]

#: The kinds of problem, as ``Method.problems`` names them (and the words
#: ``qpcontact methods`` prints for them).
PROBLEM_KINDS = {
    "lcp": "LCP",
    "qp": "QP",
    "parametric-lcp": "load trace",
    "friction-2d": "friction 2-D",
    "friction-3d": "friction 3-D",
    "friction-global": "friction, global",
}

#: What a run function may take, and the kinds it then solves by default.
TAKES = {
    "lcp": ("lcp", "qp"),
    "qp": ("lcp", "qp"),
    "friction": ("friction-2d", "friction-3d"),
    "friction-global": ("friction-global",),
    "parametric-lcp": ("parametric-lcp",),
}


@dataclass(frozen=True)
class Method:
    """A registered method and what it can do.

    Attributes
    ----------
    name : str
        Registry key, e.g. ``"osqp"``, ``"cvxpy:CLARABEL"``, ``"nsgs"``.
    run : callable
        ``run(problem, tol, options) -> MethodResult``.
    takes : str
        The form its ``run`` accepts (a key of :data:`TAKES`): "lcp", "qp",
        "friction" (a local frictional problem with W), "friction-global"
        (M, H kept, no W), "parametric-lcp".
    requires : {"monotone", "spd", "any"}
        What an LCP's M must be: M + M' PSD (any convex QP route), symmetric
        positive definite, or anything.
    accepts_sparse : bool
        Works on sparse matrices without densifying them.
    returns_duals : bool
        Gives the QP multipliers (for LCPs, w is recomputed anyway).
    algorithm : str
        "active-set", "interior-point", "ADMM", "pivoting", ...
    exact : bool
        Finite termination at an exact answer up to rounding (pivoting and
        active-set methods) rather than convergence to a tolerance, on every
        kind of ``problems`` except those of ``approximate_on``.
    family : str
        "pivoting", "qpsolvers", "cvxpy" or "friction".
    install : str
        The command that installs what the method needs.
    available : bool
        Installed on this machine.
    constraints : {"any", "lower-bounds"}
        The QPs it takes: any, or only those whose sole constraints are lower
        bounds x_i >= l_i (an LCP's QP form, the mixed contact problem).
    max_n : int or None
        The largest problem (unknowns of the form it takes) it accepts, or None.
    problems : tuple of str
        The kinds it solves (keys of :data:`PROBLEM_KINDS`), directly or
        through a conversion; default :data:`TAKES` [takes].
    approximate_on : tuple of str
        Kinds it solves only approximately by construction ("lemke" on 3-D
        friction: the cone faceted into a polyhedron).
    isolate_from : int or None
        None where it keeps a time limit itself (a backend's own setting, an
        in-house method's clock checks).  Otherwise it runs in a child
        process killed at the deadline whenever a time limit is in force and
        its problem has at least this many unknowns and constraints, or
        little time is left (qpcontact.dispatch.calls.isolated): 0 for a
        backend whose iteration cap does not bound its work (ProxQP).
    package : str
        The distribution whose version its results depend on (reports).
    """

    name: str
    run: Callable | None
    takes: str
    requires: str
    accepts_sparse: bool
    returns_duals: bool
    algorithm: str
    exact: bool
    family: str
    install: str
    available: bool = True
    constraints: str = "any"
    max_n: int | None = None
    problems: tuple = ()
    approximate_on: tuple = ()
    isolate_from: int | None = None
    package: str = "qpcontact"

    def __post_init__(self):
        if self.takes not in TAKES:
            raise ValueError(f"Method {self.name!r}: takes must be one of {', '.join(TAKES)}; "
                             f"got {self.takes!r}")
        if not self.problems:
            object.__setattr__(self, "problems", TAKES[self.takes])
        unknown = set(self.problems) - set(PROBLEM_KINDS)
        if unknown:
            raise ValueError(f"Method {self.name!r}: unknown problem kinds {sorted(unknown)}; "
                             f"the kinds are {', '.join(PROBLEM_KINDS)}")

    @property
    def needs_isolation(self) -> bool:
        """Whether it has no time limit of its own (a child process keeps it)."""
        return self.isolate_from is not None

    @property
    def needs_symmetric(self) -> bool:
        return self.requires == "spd"

    def solves(self, kind: str) -> bool:
        """Whether it takes problems of ``kind`` (a key of :data:`PROBLEM_KINDS`)."""
        return kind in self.problems

    def exact_on(self, kind: str) -> bool:
        """Whether its answer on ``kind`` is exact up to rounding."""
        return self.exact and kind in self.problems and kind not in self.approximate_on
