"""The three test examples of the decomposition paper (Kolesnikov 2013),
with the solutions and pivot counts printed there.

The matrices are garbled in the extracted text; these are the reconstructions
of ``shared/PAPERS.md``, each checked to reproduce the printed solution.
Example 2's solution is printed to six digits; the exact values are
z2 = 428/9951 and z4 = 214/9951 (solve the 2 x 2 active block).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.problems import LCP

__all__ = ["PaperExample", "p0_examples"]


@dataclass(frozen=True)
class PaperExample:
    name: str
    lcp: LCP
    z: np.ndarray
    w: np.ndarray
    pivots: int
    note: str


def p0_examples() -> list[PaperExample]:
    """Kolesnikov's examples 1-3 as LCPs with their published solutions."""
    ex1 = LCP([[4, -1, 0, 0], [-1, 4, -1, 0], [0, -1, 4, -1], [0, 0, -1, 4]], [-4, 3, -4, 2])
    ex2 = LCP([[100, -2, -3, -4], [-2, 50, -6, -7], [-3, -6, 100, -11], [-4, -7, -11, 200]],
              [1, -2, 3, -4])
    ex3 = LCP([[4, -1, 2, 0], [-1, 4, -1, 0], [2, -1, 4, -1], [0, 0, -1, 4]], [-4, 1, -2, 0])
    z2 = np.array([0.0, 428 / 9951, 0.0, 214 / 9951])
    return [
        PaperExample("Kolesnikov example 1", ex1, np.array([1.0, 0, 1, 0]), np.array([0.0, 1, 0, 1]), 2,
                     "tie between i=1 and i=3 in the first step"),
        PaperExample("Kolesnikov example 2", ex2, z2, ex2.w(z2), 2,
                     "a published interior-point method needed 54 iterations"),
        PaperExample("Kolesnikov example 3", ex3, np.array([1.0, 0, 0, 0]), np.zeros(4), 1,
                     "degenerate: z_i = w_i = 0 for i = 2, 3, 4"),
    ]
