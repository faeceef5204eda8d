"""The raft's drawing: the soil pressure map with the lift-off line, and the
moment contours beside it — made to read at the saved size (one panel per
quantity, a colour bar with units, the columns marked, the lifted zone
hatched and its edge drawn in one strong line)."""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidProblemError

__all__ = ["plot_raft"]


def _triangulation(mesh):
    """Each quadrilateral as two triangles (any mesh: structured, with
    openings, or the user's own)."""
    from matplotlib.tri import Triangulation

    e = mesh.elements
    tris = np.concatenate([e[:, [0, 1, 2]], e[:, [0, 2, 3]]])
    return Triangulation(mesh.nodes[:, 0], mesh.nodes[:, 1], tris)


def plot_raft(res, path, moment: str = "mx", dpi: int = 110) -> str:
    """Two panels: the soil pressure [force/length²] with the contact edge
    (the lift-off line) and the lifted zone hatched; the moment ``moment``
    (mx, my or mxy, per unit width) as filled contours.  Raises for a result
    that is not ok (a drawing of an uncertified answer would be believed)."""
    if not res.ok:
        raise InvalidProblemError(f"no drawing of a result that is not ok: {res.message}")
    if moment not in ("mx", "my", "mxy"):
        raise InvalidProblemError(f"moment must be mx, my or mxy; got {moment!r}")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure

    F, L = res.raft.units
    tri = _triangulation(res.mesh)
    P = np.where(res.supported, res.pressure, 0.0)
    C = res.contact.astype(float)
    M = res.nodal(moment)
    aspect = res.raft.length / res.raft.width
    width = 11.0
    fig, axes = plt.subplots(1, 2, figsize=(width, max(3.2, min(8.0, 0.45 * width * aspect + 1.2))),
                             constrained_layout=True)
    ax = axes[0]
    cs = ax.tricontourf(tri, P, levels=12, cmap="YlOrBr")
    fig.colorbar(cs, ax=ax, label=f"soil pressure [{F}/{L}²]", shrink=0.9)
    if res.lifted.any():
        ax.tricontourf(tri, 1 - C, levels=[0.5, 1.5], colors="none", hatches=["//"])
        ax.tricontour(tri, C, levels=[0.5], colors="k", linewidths=2.0)
        ax.plot([], [], "k-", lw=2, label=f"lift-off line ({100 * res.uplift_fraction:.0f} % lifted)")
    # the columns of the combination: point loads and patches of its cases
    points = {(d[0], d[1]) for c, kind, d in res.raft.loads
              if kind == "point" and res.combination.get(c)}
    points |= {(0.5 * (d[0] + d[2]), 0.5 * (d[1] + d[3])) for c, kind, d in res.raft.loads
               if kind == "patch" and res.combination.get(c)}
    if points:
        ax.plot(*np.array(sorted(points)).T, "s", ms=6, mfc="w", mec="k", label="columns")
    lines = [d for c, kind, d in res.raft.loads if kind == "line" and res.combination.get(c)]
    for k, d in enumerate(lines):
        ax.plot([d[0], d[2]], [d[1], d[3]], "-", color="0.3", lw=3,
                label="line loads" if k == 0 else None)
    ax.set_title(f"soil pressure — {res.name}", fontsize=11)
    ax2 = axes[1]
    lim = float(np.max(np.abs(M))) or 1.0
    cm = ax2.tricontourf(tri, M, levels=np.linspace(-lim, lim, 17), cmap="RdBu_r")
    fig.colorbar(cm, ax=ax2, label=f"{moment} [{F}·{L}/{L}] (+: bottom in tension)", shrink=0.9)
    ax2.set_title(f"{moment} per unit width", fontsize=11)
    for a in axes:
        a.set_aspect("equal")
        a.set_xlabel(f"x [{L}]")
        a.set_ylabel(f"y [{L}]")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, fontsize=9,
                  frameon=False)
    out = save_figure(fig, path, dpi=dpi)
    plt.close(fig)
    return out
