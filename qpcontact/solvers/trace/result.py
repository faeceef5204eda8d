"""What a load trace returns: the pieces of the solution path, its breakpoints
and events, and how it ended (with the evidence)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...core.errors import InvalidOptionError
from ...core.results import LCPSolution

__all__ = ["TracePiece", "TraceEvent", "LoadTrace", "END_REASONS"]

END_REASONS = ("p_max", "unbounded", "collapse", "fold", "breakdown", "max_pieces")


@dataclass
class TracePiece:
    """One interval of the load parameter on which the working scheme is fixed.

    ``active`` marks the z's that are basic (contacts closed, or the LCP's
    unknowns that are free) on the interval; on it ``z(p) = z_start + (p -
    p_start) dz`` and ``w(p) = w_start + (p - p_start) dw`` exactly.
    ``p_end`` is inf on a final unbounded piece.  ``error`` is the worst
    certificate of the piece (start, middle, end).
    """

    p_start: float
    p_end: float
    active: np.ndarray
    z_start: np.ndarray
    dz: np.ndarray
    w_start: np.ndarray
    dw: np.ndarray
    error: float = 0.0

    def z(self, p: float) -> np.ndarray:
        return np.maximum(self.z_start + (p - self.p_start) * self.dz, 0.0)

    def w(self, p: float) -> np.ndarray:
        return self.w_start + (p - self.p_start) * self.dw

    def contains(self, p: float) -> bool:
        return self.p_start <= p <= self.p_end


@dataclass
class TraceEvent:
    """A breakpoint: at ``p`` the z's in ``entered`` become basic (may grow
    from zero) and those in ``left`` leave the basis (stay zero; their w's may
    grow).  ``continuations`` is how many working schemes (distinct in w)
    could continue the path there (1 unless M is not a P-matrix);
    ``resolved`` marks a scheme found by a fresh solve just beyond p (the
    vertex's own schemes did not certify), continuations then 0."""

    p: float
    entered: np.ndarray
    left: np.ndarray
    continuations: int = 1
    resolved: bool = False

    def describe(self, names=None) -> str:
        name = (lambda i: names[i]) if names is not None else (lambda i: f"z[{i}]")
        parts = [f"+{name(i)}" for i in self.entered] + [f"-{name(i)}" for i in self.left]
        return " ".join(parts) or "(no change)"


@dataclass(kw_only=True, repr=False)
class LoadTrace(LCPSolution):
    """The solution path of a ParametricLCP: an ``LCPSolution`` for the final
    state (z, w at ``p_end``, certified) plus the pieces, breakpoints and events.

    ``status`` is "solved" when every piece was certified (start, middle and
    end) and the ending is proved (``end`` in "p_max", "unbounded",
    "collapse", "fold"), "failed" on "breakdown", "max_pivots" at the piece
    limit.  ``proof`` holds the ending's evidence (module docstring).
    """

    pieces: list = field(default_factory=list)
    breakpoints: np.ndarray = field(default_factory=lambda: np.empty(0))
    events: list = field(default_factory=list)
    end: str = ""
    p_end: float = 0.0
    proof: dict = field(default_factory=dict)

    _variables = ("end", "p_end", "breakpoints", "z", "w")

    def piece_at(self, p: float) -> TracePiece:
        for piece in self.pieces:
            if piece.contains(p):
                return piece
        lo = self.pieces[0].p_start if self.pieces else 0.0
        hi = self.pieces[-1].p_end if self.pieces else 0.0
        raise InvalidOptionError(f"p = {p} is outside the traced range [{lo:g}, {hi:g}] "
                                 f"(the trace ended: {self.end}; {self.message})")

    def z_at(self, p: float) -> np.ndarray:
        return self.piece_at(p).z(p)

    def w_at(self, p: float) -> np.ndarray:
        return self.piece_at(p).w(p)

    def plot_range(self) -> float:
        """The top of the default plot range: where the trace ended, or 1.5 x
        the last breakpoint (at least the last piece's start + 1) on an
        unbounded last piece."""
        if not self.pieces:
            return 1.0
        last = self.pieces[-1]
        if np.isfinite(last.p_end):
            return last.p_end if last.p_end > 0 else 1.0
        top = 1.5 * self.breakpoints[-1] if self.breakpoints.size else 0.0
        return max(top, last.p_start + 1.0)


    def traced_top(self) -> float:
        """The last load reached by a piece (0 without pieces)."""
        return self.pieces[-1].p_end if self.pieces else 0.0
