"""Saving figures: atomically (a temporary file, then a rename), so an
interrupted run never leaves a truncated PNG where a good one was."""

from __future__ import annotations

import os


def save_figure(fig, path, dpi: int = 110) -> str:
    """Write ``fig`` to ``path`` (folders created), close it, return the path."""
    import matplotlib.pyplot as plt

    path = os.fspath(path)
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=dpi)
    plt.close(fig)
    os.replace(tmp, path)
    return path
