"""A frame's load path joined from traces that restart across degenerate
vertices.

Why.  On rigid pads under a flexible frame the faceted cone's LCP has null
vectors (opposite facets' slips cancel), and at some vertices of the path
no scheme that continues it can be certified by the parametric trace
("M has null vectors: not every scheme was tried") although equilibria go
on (a table on four legs: every pad slipping from p = 11.29 to its sliding
limit 12, each one certified by Lemke at a fixed load).  The law is
holonomic (total slip against total force), so the path's state at a load
is the equilibrium at that load: the path restarts just beyond the vertex,
at p_b (1 + RESTART), from a certified equilibrium there, and is traced on
from it.  The gap (p_b, p_b (1 + RESTART)) is not traced; both its ends are
certified, and the joined path says where it restarted.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: the relative step beyond a vertex where a stopped path restarts
RESTART = 1e-9

#: restarts at most along one path
RESTARTS = 12


@dataclass
class ShiftedPiece:
    """One linear piece of a restarted trace, in the whole path's p."""

    piece: object
    offset: float

    @property
    def p_start(self) -> float:
        return self.piece.p_start + self.offset

    @property
    def p_end(self) -> float:
        return self.piece.p_end + self.offset

    def z(self, p: float) -> np.ndarray:
        return self.piece.z(p - self.offset)


class JoinedTrace:
    """The engine's traces of one load path, each started at ``offset``:
    the LoadTrace interface the frame's trace reads (pieces, end, proof,
    p_end, ok, message, z_at, plot_range) in the whole path's p."""

    def __init__(self, first, offset: float = 0.0):
        self.segments = [(float(offset), first)]
        #: per segment, where the path leaves it (None: at its end)
        self.cuts = [None]

    def add(self, offset: float, trace) -> None:
        self.segments.append((offset, trace))
        self.cuts.append(None)

    def cut(self, p: float) -> None:
        """The last segment is kept up to p only (the path restarts beyond
        p from a certified equilibrium: its pieces after p failed the
        frame's checks)."""
        self.cuts[-1] = p

    @property
    def restarts(self) -> list:
        """Where the path restarted beyond a degenerate vertex."""
        return [off for off, _ in self.segments[1:]]

    @property
    def gaps(self) -> list:
        """(where the path left a segment, where the next one starts): the
        stretches not traced."""
        out = []
        for k in range(1, len(self.segments)):
            off, tr = self.segments[k - 1]
            left = self.cuts[k - 1] if self.cuts[k - 1] is not None else tr.p_end + off
            out.append((left, self.segments[k][0]))
        return out

    @property
    def last(self):
        return self.segments[-1]

    @property
    def pieces(self) -> list:
        return [p if off == 0.0 else ShiftedPiece(p, off)
                for (off, tr), cut in zip(self.segments, self.cuts) for p in tr.pieces
                if cut is None or p.p_start + off < cut]

    @property
    def end(self) -> str:
        return self.last[1].end

    @property
    def ok(self) -> bool:
        """The last segment is ok, and each before it ok or stopped where
        the next one restarted beyond it (a breakdown or fold at a
        degenerate vertex is what a restart resolves: a pipe rack traced to
        99.9 % of its limit was "not ok" for the stop at 43.3 it had
        restarted beyond, and solve() there raised SolverFailedError)."""
        *before, (_, last) = self.segments
        return last.ok and all(tr.ok or tr.end in ("breakdown", "fold") for _, tr in before)

    @property
    def message(self) -> str:
        return self.last[1].message

    @property
    def p_end(self) -> float:
        off, tr = self.last
        return tr.p_end + off

    @property
    def proof(self) -> dict:
        off, tr = self.last
        proof = dict(tr.proof)
        for key in ("p_limit", "from"):
            if key in proof and proof[key] is not None:
                proof[key] = proof[key] + off
        return proof

    def z_at(self, p: float) -> np.ndarray:
        for off, tr in reversed(self.segments):
            if p >= off:
                return tr.z_at(p - off)
        off, tr = self.segments[0]
        return tr.z_at(p - off)

    def plot_range(self) -> float:
        off, tr = self.last
        return tr.plot_range() + off
