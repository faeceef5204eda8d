"""The drawing tests' one rule for overprinting: two texts overlap when
their rendered boxes intersect (each test picks which texts count)."""

from __future__ import annotations

import numpy as np


def overlapping(fig, texts) -> list:
    """Pairs (text, text) of ``texts`` whose boxes, as ``fig`` renders them,
    intersect."""
    if not texts:
        return []
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    boxes = np.array([t.get_window_extent(renderer).extents for t in texts])
    x0, y0, x1, y1 = boxes.T
    hit = ((x0[:, None] < x1[None]) & (x1[:, None] > x0[None])
           & (y0[:, None] < y1[None]) & (y1[:, None] > y0[None]))
    np.fill_diagonal(hit, False)
    return [(texts[i].get_text(), texts[j].get_text()) for i, j in zip(*np.nonzero(np.triu(hit)))]
