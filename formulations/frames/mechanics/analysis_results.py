"""What every frame analysis gives back, plane or space: one result per load
combination (:class:`AnalysisResult`, read further by a plane frame's
:class:`~..plane.plane_results.FrameResult` and a space frame's
:class:`~..space.space_results.SpaceFrameResult`), the results over
combinations with their envelopes and tables (:class:`CombinationResults`:
built and rounded in the results' own table module; CSV always, written
atomically; pandas DataFrames with the ``tables`` extra), and the
increasing-load trace's objects (:class:`FrameTrace`, :class:`FrameEvent`).
"""

from __future__ import annotations

import copy
import functools
import weakref
from dataclasses import dataclass, field

import numpy as np

from qpcontact.core.errors import InvalidOptionError

from ..reporting import tables
from ..reporting.notation import DIGITS


def keeps_its_answers(cls):
    """Class decorator of a frame model: each ``add_*`` method first hands
    the answers given so far a copy of the model as they solved it.  An
    answer reads its frame again for diagrams, extremes, tables and
    drawings; a load added after a solve made an earlier answer's member
    diagram put the new load on the old displacements (a shear of −330 kN
    at the end of a span whose reaction is 30), silently.  The copy is made
    once, at the first edit after a solve, so a solve costs nothing more."""
    for name, method in list(vars(cls).items()):
        if name.startswith("add_") and callable(method):
            setattr(cls, name, _handing_over(method))
    cls.__getstate__ = _without_register
    return cls


def _without_register(frame) -> dict:
    """A frame's state to pickle or copy: the register of its answers (weak
    references, which do not pickle: a solved frame or its answer sent to
    another process raised TypeError) is not part of the model."""
    state = dict(frame.__dict__)
    state.pop("_answers", None)
    return state


def _registered_again(answer, state) -> None:
    """An answer unpickled or copied: its own frame (copied with it) keeps
    it as solved, as the original's keeps the original."""
    answer.__dict__.update(state)
    kept(answer)


def _handing_over(method):
    @functools.wraps(method)
    def edit(self, *args, **kwargs):
        hand_over(self)
        return method(self, *args, **kwargs)
    return edit


def hand_over(frame) -> None:
    """Give every live answer of ``frame`` (:func:`kept`) a deep copy of it
    as it is now, before the caller changes it."""
    answers = frame.__dict__.pop("_answers", None)
    live = list(answers.values()) if answers is not None else []
    if live:
        as_solved = copy.deepcopy(frame)
        for answer in live:
            answer.frame = as_solved


def kept(answer) -> None:
    """Register ``answer`` (a result or trace) with its frame, weakly, for
    :func:`hand_over`; a dead one leaves the register as it dies (a list
    swept of dead ones as it grew cost each answer a pass over the live
    ones: 8000 states of a trace kept for a plot, a third more each)."""
    frame = answer.frame
    if frame is None or not hasattr(frame, "__dict__"):
        return
    frame.__dict__.setdefault("_answers", weakref.WeakValueDictionary())[id(answer)] = answer


@dataclass
class AnalysisResult:
    """What every frame's analysed load combination holds (plane:
    :class:`~..plane.plane_results.FrameResult`, space:
    :class:`~..space.space_results.SpaceFrameResult`,
    which add their own readings of it)."""

    p: float
    supports: dict
    displacements: dict
    member_forces: dict
    reactions: dict
    equilibrium_residual: float
    lcp_error: float
    route: str
    ok: bool
    message: str
    frame: "object" = field(repr=False, default=None)
    _u: np.ndarray = field(repr=False, default=None)
    combination: dict = field(default_factory=dict)
    name: str = ""
    #: the largest nodal translation over the frame's size (the diagonal of
    #: its nodes' bounding box), and the largest rotation [rad]: beyond
    #: recovery.SMALL_DISPLACEMENT / SMALL_ROTATION the analysis (small
    #: displacements, equilibrium on the undeformed frame) no longer
    #: describes the structure, and solve warns
    displacement_ratio: float = 0.0
    max_rotation: float = 0.0
    #: the words for how far the frame moved where that is beyond those
    #: limits (equilibrium_checks.how_far's, made by the recovery: what
    #: solve's warning says), else ""
    displacement_words: str = field(repr=False, default="")
    #: a second-order answer's fixed point ({"rounds", "axial_error",
    #: "axial"}: mechanics.second_order_analysis); None for first order
    second_order: dict | None = None
    #: the members' axial forces (tension positive, member order) its
    #: second-order stiffness and member loads were built from, which its
    #: diagrams read (the beam-column between the ends); None for first order
    stiffness_axial: np.ndarray | None = field(repr=False, default=None)
    #: the combination whose member loads' axial parts made N vary along the
    #: members in that stiffness (a plane frame's: mechanics.varying_axial), or None
    stiffness_along: dict | None = field(repr=False, default=None)
    #: where no equilibrium exists, proved (solve(raise_on_failure=False)
    #: returns it, solve_combinations keeps it): how the frame fails and
    #: the proof, as the NoSolutionError's message would say; else None
    proof: str | None = None

    def __post_init__(self):
        kept(self)

    __setstate__ = _registered_again

    @property
    def status(self) -> str:
        """"solved" (ok), "infeasible" (no equilibrium exists: ``proof``
        says why) or "failed" (no certified answer: ``message`` says what
        was tried or which check failed)."""
        return "solved" if self.ok else ("infeasible" if self.proof else "failed")


class CombinationResults(dict):
    """{combination name: FrameResult}, each solved on its own.  A
    combination the frame cannot carry has ``ok`` False and a message saying
    what happens; it does not discard the others.  ``failed`` lists them.
    The tables are those of the results' kind (``table_kit``: a plane
    frame's :mod:`..reporting.tables`, a space frame's
    :mod:`..reporting.space_tables`)."""

    @property
    def failed(self) -> list:
        return [name for name, r in self.items() if not r.ok]

    def envelope(self) -> dict:
        """Max/min over the combinations that are ok (full precision): per
        member {"N"|"V"|"M": {"max": (value, x, combination), "min": ...}}
        (the diagrams' extremes, ends included), and per node the ground
        holds {"Fx"|"Fy"|"Mz": {"max": (value, combination), ...}} of its
        total reaction under the key "supports" (a space frame's: see
        :func:`..reporting.space_tables.envelope`)."""
        return self._kit().envelope(self)

    def rows(self, table: str, digits: int | None = DIGITS) -> list:
        """One table over all combinations, rounded per column over all of
        them (``digits=None``: full precision): a result table with a
        "combination" column first, "envelope" (members),
        "envelope_reactions" (nodes) or "combinations" (each one's status);
        a space frame's also "envelope_supports" (contacts)."""
        kit = self._kit()
        tables.check_table(table, kit.TABLES + kit.COMBINED)
        if table == "combinations":
            return [{"combination": n, "ok": r.ok, "route": r.route, "message": r.message}
                    for n, r in self.items()]
        frame = self._frame()
        if frame is None:
            return []
        if table in kit.COMBINED:
            raw = kit.envelope_rows(frame, self.envelope(), table)
        else:
            raw = [{"combination": name, "ok": r.ok, **row} for name, r in self.items()
                   for row in kit.rows(frame, r, table)]
        return tables.engineering(raw, frame, digits)

    def envelope_rows(self, digits: int | None = DIGITS) -> list:
        """The members' envelope table: rows("envelope")."""
        return self.rows("envelope", digits)

    def to_csv(self, folder, digits: int | None = DIGITS) -> list:
        """Every table of ``rows`` as folder/<table>.csv (atomic writes)."""
        kit = self._kit()
        return tables.write_tables(
            folder, {t: self.rows(t, digits) for t in kit.TABLES + kit.COMBINED}, digits)

    def to_dataframe(self, table: str = "members", digits: int | None = DIGITS):
        """A table of ``rows`` as a pandas DataFrame (the ``tables`` extra)."""
        return tables.dataframe(self.rows(table, digits))

    def _frame(self):
        return next((r.frame for r in self.values() if r.frame is not None), None)

    def _kit(self):
        return next((type(r).table_kit for r in self.values()), tables)


@dataclass
class FrameEvent:
    """A breakpoint of the trace: at load parameter ``p`` the supports in
    ``changes`` go from one state to another ({support: (before, after)});
    ``bracket`` (p_before, p_after) where the event is located between two
    certified answers rather than exactly (the circular cone's trace)."""

    p: float
    changes: dict
    bracket: tuple | None = None

    def __str__(self) -> str:
        return "; ".join(f"{k}: {a} \u2192 {b}" for k, (a, b) in self.changes.items())


@dataclass
class FrameTrace:
    """The increasing-load analysis (Osipova–Popov–Lovtsov's algorithm).

    ``breakpoints``: the values of p where some support changes state, with
    ``events`` saying which and how ("S3: stick → slip-"); ``intervals``
    [(p_start, p_end)] between them and ``states`` (a FrameResult at the
    middle of each); ``ended``: why the trace stopped — "p_max" (reached),
    "unbounded" (no support changes state again, p_max = inf), "collapse"
    (no equilibrium exists beyond the end: proved, and ``message`` says how
    the frame fails), "bounded" (the path stops unproved below a proved
    upper bound, ``bound``: the message says where it stands and how the
    frame moves there), "fold" (equilibria may exist beyond but none continues
    this path), "breakdown", "max_pieces" (see docs/frames.md); ``ok`` is True
    when every traced piece passed the LCP certificate and the equilibrium
    check at its start, middle and end, and the ending is proved.
    ``result_at(p)`` analyses any p inside the traced range; ``limit`` is
    the bracket [p_lo, p_hi] of a proved limit load.
    """

    breakpoints: np.ndarray
    states: list
    intervals: list
    events: list
    ended: str
    message: str
    ok: bool
    trace: object = field(repr=False, default=None)
    frame: "object" = field(repr=False, default=None)
    _built: dict = field(repr=False, default=None)   # the frame's assembly, reused by result_at
    constant: dict = field(default_factory=dict)
    variable: dict = field(default_factory=dict)
    #: (p_lo, p_hi) where the path ends at a limit: p_lo the last certified
    #: equilibrium on it, p_hi a proof that none exists at or beyond it
    limit: tuple | None = None
    #: (p_lo, p_hi) where the path stops short of a proved limit (ended
    #: "bounded"): p_lo its last certified equilibrium, p_hi a proof that
    #: none exists at or beyond it, the gap between them unresolved
    bound: tuple | None = None
    bound_words: str = field(repr=False, default="")
    #: where the path ends "bounded" because the pads' friction is exhausted
    #: under the normal forces the frame gives them: the largest p that
    #: friction carries with those normal forces (an LP,
    #: mechanics/friction_capacity.py), equal to the path's last load
    capacity: float | None = None
    #: a second-order trace's fixed point ({"rounds", "axial_error",
    #: "axial", "path_axial_change", "stable"}:
    #: mechanics.second_order_analysis.trace_second_order); None for first order
    second_order: dict | None = None

    def __post_init__(self):
        kept(self)

    __setstate__ = _registered_again

    @property
    def p_end(self) -> float:
        """Where the traced range ends (inf on an unbounded last interval)."""
        return self.intervals[-1][1] if self.intervals else 0.0

    def safety_factor(self, p_design: float) -> tuple:
        """(lower, upper): the proved limit's bracket over the design load
        level ``p_design`` of the variable part (the constant part as
        traced); raises where the trace proved no limit."""
        if self.limit is None:
            raise InvalidOptionError(
                f"this trace proved no limit (it ended {self.ended!r}: {self.message[:120]}); "
                "a safety factor needs one")
        if isinstance(p_design, bool) or not isinstance(p_design, (int, float)) \
                or not np.isfinite(p_design) or p_design <= 0:
            raise InvalidOptionError(f"p_design must be a positive number; got {p_design!r}")
        return (self.limit[0] / p_design, self.limit[1] / p_design)

    def result_at(self, p: float):
        """The frame's checked result at load level ``p`` in the traced range
        (everything is linear in p inside an interval)."""
        return self.frame.kind.result_from_z(self.frame, self.trace.z_at(p),
                                             self.combination_at(p), "trace", b=self._built)

    def combination_at(self, p: float) -> dict:
        """The combination {case: factor} at load level ``p``: the constant
        part plus p times the variable part."""
        combo = dict(self.constant)
        for case, f in self.variable.items():
            combo[case] = combo.get(case, 0.0) + p * f
        return combo

    def plot(self, path, node: str, dof: str = "ux", p_max: float | None = None) -> str:
        """Load parameter against a displacement of ``node`` (PNG), each
        breakpoint numbered on the curve and listed with its events in a key
        beside it.  Default range: the traced one (an unbounded last
        interval: 1.5 x the last breakpoint)."""
        from ..reporting.trace_plot import plot_trace

        return plot_trace(self.frame, self, path, node, dof, p_max)

