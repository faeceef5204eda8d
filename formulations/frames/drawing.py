"""Drawings of frame results: the deformed shape (each member bent by its
element's own shape functions), support symbols and states, and the
bending-moment diagram with its span extremes; and the trace's load-
displacement curve.  A result that is not ok is never drawn."""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import SolverFailedError

from .assembly import DOFS, geometry, rotation
from .loads import describe, shape_functions

_COLORS = {"separated": "tab:red", "closed": "tab:blue", "stick": "tab:green",
           "slip+": "tab:orange", "slip-": "tab:purple"}
#: above this many members, labels are thinned to the largest ones
_DENSE = 24


def _fmt(v: float, ref: float) -> str:
    """A value as printed on a drawing: rounding noise (1.6e-13 beside 1e3) is 0."""
    return "0" if abs(v) <= 1e-9 * max(ref, 1e-300) else f"{v:.3g}"


def _curve(frame, res, m, scale, idx, points=21):
    """The member's deformed axis: x(s), y(s) from its end displacements and
    the cubic Hermite shape functions (the end rotation of a hinged end is
    the member's own, recovered from its uncondensed stiffness)."""
    L, c, s = geometry(frame, m)
    T = rotation(c, s)
    u = res._u
    d = T @ np.r_[u[idx[m.i]:idx[m.i] + 3], u[idx[m.j]:idx[m.j] + 3]]
    if m.hinge_i or m.hinge_j:
        from .assembly import beam_k

        k = beam_k(m.E, m.A, m.I, L)
        for r, hinged in ((2, m.hinge_i), (5, m.hinge_j)):
            if hinged:
                other = [j for j in range(6) if j != r]
                d[r] = -(k[r, other] @ d[other]) / k[r, r]
    xs = np.linspace(0.0, L, points)
    out = []
    for x in xs:
        N, _ = shape_functions(x, L)
        ua = N[0] * d[0] + N[3] * d[3]
        v = N[1] * d[1] + N[2] * d[2] + N[4] * d[4] + N[5] * d[5]
        out.append((x + scale * ua, scale * v))
    loc = np.array(out)
    a = frame.nodes[m.i]
    return a[0] + c * loc[:, 0] - s * loc[:, 1], a[1] + s * loc[:, 0] + c * loc[:, 1]


def _symbol(ax, frame, node, xy, size):
    """Pin (ux, uy), fixed (all three), roller (one direction), spring."""
    fixed = frame.fixed.get(node, set())
    x, y = xy
    if {"ux", "uy", "rz"} <= fixed:
        ax.plot([x - size, x + size], [y, y], color="k", lw=2.5)
        for k in np.linspace(-size, size, 5):
            ax.plot([x + k, x + k - 0.4 * size], [y, y - 0.4 * size], color="k", lw=0.8)
    elif {"ux", "uy"} <= fixed:
        ax.plot([x, x - size, x + size, x], [y, y - size, y - size, y], color="k", lw=1.2)
    elif fixed:
        ax.plot([x, x - size, x + size, x], [y, y - size, y - size, y], color="k", lw=1.2)
        ax.plot([x - size, x + size], [y - 1.3 * size] * 2, color="k", lw=1.2)
        ax.annotate(",".join(sorted(fixed)), (x, y - 1.3 * size), fontsize=6, ha="center",
                    va="top")
    if node in frame.springs:
        ax.plot(x + size * np.array([0, 0.3, -0.3, 0.3, -0.3, 0]),
                y - size * np.linspace(0, 1.2, 6), color="tab:brown", lw=1)


def plot_result(frame, res, path, scale=None, title=""):
    if not res.ok:
        raise SolverFailedError(
            f"this result is not an equilibrium ({res.message}); nothing is drawn from it")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure

    force, length = frame.units
    xy = np.array(list(frame.nodes.values()))
    span = max(np.ptp(xy[:, 0]), np.ptp(xy[:, 1]), 1e-12)
    umax = max(max(abs(d[0]), abs(d[1])) for d in res.displacements.values())
    scale = scale or (0.1 * span / umax if umax > 0 else 1.0)
    size = 0.02 * span
    tall = np.ptp(xy[:, 1]) > np.ptp(xy[:, 0])   # a tower: side by side
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 9)) if tall else plt.subplots(
        2, 1, figsize=(13, 9))
    diagrams = {m.name: res.diagram(m.name, 41) for m in frame.members.values()}
    m_max = max(max(np.abs(d[3]).max() for d in diagrams.values()), 1e-300)
    mscale = 0.15 * span / m_max
    dense = len(frame.members) > _DENSE
    label_members = set(frame.members)
    if dense:   # the largest moments only
        peak = sorted(frame.members, key=lambda k: -np.abs(diagrams[k][3]).max())
        label_members = set(peak[:6])
    joint_labels: dict = {}
    span_labels: list = []
    idx = {nm: 3 * k for k, nm in enumerate(frame.nodes)}   # the assembly's dof numbering
    for m in frame.members.values():
        a, bnode = frame.nodes[m.i], frame.nodes[m.j]
        ax1.plot([a[0], bnode[0]], [a[1], bnode[1]], color="0.8", lw=1)
        cx, cy = _curve(frame, res, m, scale, idx)
        ax1.plot(cx, cy, color="k", lw=1.6)
        if m.hinge_i or m.hinge_j:
            for end, hinged in ((0, m.hinge_i), (-1, m.hinge_j)):
                if hinged:
                    ax1.plot(cx[end], cy[end], "o", mfc="w", mec="k", ms=5)
        x, N, V, Mo = diagrams[m.name]
        L, c, sn = geometry(frame, m)
        px, py = a[0] + c * x, a[1] + sn * x
        # sagging moment compresses the +y fibre: drawn on the tension side (-y, member axes)
        ox, oy = -sn * Mo * mscale, c * Mo * mscale
        ax2.plot([a[0], bnode[0]], [a[1], bnode[1]], color="k", lw=1.2)
        ax2.fill(np.r_[px, (px - ox)[::-1]], np.r_[py, (py - oy)[::-1]], alpha=0.3,
                 color="tab:blue")
        ax2.plot(px - ox, py - oy, color="tab:blue", lw=1)
        if m.name not in label_members:
            continue
        # one label per joint (the largest end moment there), span extreme inside
        for end, node in ((0, m.i), (-1, m.j)):
            if abs(Mo[end]) > abs(joint_labels.get(node, (0.0,))[0]):
                joint_labels[node] = (Mo[end], px[end] - ox[end], py[end] - oy[end])
        # the span's extremes where they are not at an end (sagging between supports)
        for k in {int(np.argmax(Mo)), int(np.argmin(Mo))}:
            if 0 < k < len(x) - 1 and abs(Mo[k]) > 0.05 * m_max:
                text = _fmt(Mo[k], m_max) if dense else f"{_fmt(Mo[k], m_max)} (x={x[k]:.3g})"
                span_labels.append((abs(Mo[k]), text, px[k] - ox[k], py[k] - oy[k], "tab:blue"))
    labels = span_labels + [(abs(val), _fmt(val, m_max), lx, ly, "k")
                            for val, lx, ly in joint_labels.values()]
    _place_labels(ax2, labels)
    nmax = max([abs(s.normal) for s in res.supports.values()] + [1e-300])
    top_key = max(res.supports, key=lambda k: res.supports[k].normal) if res.supports else None
    for n_sup, (key, sres) in enumerate(res.supports.items()):
        node = key.split("-")[0].split("#")[0]
        p0 = frame.nodes[node] + scale * np.array(res.displacements[node][:2])
        ax1.plot(*p0, "^", ms=10 if len(res.supports) <= _DENSE else 6, color=_COLORS[sres.state])
        # many supports: only the most loaded one is labelled (the title lists those lifted)
        if len(res.supports) <= 12 or key == top_key:
            text = f"{key}: {sres.state}"
            if sres.state != "separated":
                text += f"\nN={_fmt(sres.normal, nmax)}"
                if frame.contacts[0].friction or sres.tangential:
                    text += f" T={_fmt(sres.tangential, nmax)}"
            ax1.annotate(text, p0, textcoords="offset points", xytext=(5, -22 - 20 * (n_sup % 2)),
                         fontsize=7)   # staggered: neighbours' labels do not overprint
    for node in set(frame.fixed) | set(frame.springs):
        _symbol(ax1, frame, node, frame.nodes[node], size)
    ax1.set_title(f"deformed shape (displacements x{scale:.3g});\nsupports: red separated, green "
                  "stick, blue closed (frictionless), orange/purple slip", fontsize=9)
    ax2.set_title(f"bending moment [{force}·{length}], drawn on the tension side", fontsize=9)
    for ax in (ax1, ax2):
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
        ax.set_xlabel(f"x [{length}]")
        ax.set_ylabel(f"y [{length}]")
    lifted = [k for k, s in res.supports.items() if s.state == "separated"]
    what = res.name or (describe(res.combination) if any(res.combination.values())
                        else f"p = {res.p:g}")
    fig.suptitle(title or (f"{what}: {len(lifted)} of {len(res.supports)} contacts lift off"
                           + (f" ({', '.join(lifted[:6])}{'…' if len(lifted) > 6 else ''})"
                              if lifted else "")), fontsize=10)
    fig.tight_layout()
    return save_figure(fig, path)


def _place_labels(ax, labels):
    """Annotate (size, text, x, y, colour) labels, largest first, skipping
    any that would overprint one already placed (a span extreme next to a
    joint's end moment): the box is judged in data units against the
    drawing's extent, which the equal aspect makes a fixed fraction of the
    axes."""
    if not labels:
        return
    xy = np.array([(lx, ly) for _, _, lx, ly, _ in labels])
    extent = max(np.ptp(xy[:, 0]), np.ptp(xy[:, 1]), 1e-300)
    placed = []   # (left, right, y) of each label's box; a 7-pt character ~ 0.005 extent
    for _, text, lx, ly, colour in sorted(labels, key=lambda t: -t[0]):
        right = lx + 0.005 * extent * (len(text) + 1)
        if any(lx < r and l < right and abs(ly - y) < 0.025 * extent for l, r, y in placed):
            continue
        placed.append((lx, right, ly))
        ax.annotate(text, (lx, ly), fontsize=7, color=colour)


def plot_trace(frame, ft, path, node, dof, p_max):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure

    if dof not in DOFS:
        from qpcontact.core.errors import InvalidOptionError

        raise InvalidOptionError(f"dof must be one of {DOFS}; got {dof!r}")
    frame._node(node)
    k = DOFS.index(dof)
    top = ft.trace.plot_range()
    if p_max is not None:
        top = min(float(p_max), ft.p_end)
    ps = np.unique(np.r_[0.0, ft.breakpoints[ft.breakpoints <= top], np.linspace(0, top, 60)])
    disp = [ft.result_at(p).displacements[node][k] for p in ps]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(disp, ps, "k-")
    lo, hi = min(disp), max(disp)
    for ev in ft.events:
        if ev.p <= top:
            d = ft.result_at(ev.p).displacements[node][k]
            ax.plot(d, ev.p, "o", color="tab:red")
            right = d > lo + 0.5 * (hi - lo)   # label on the side with room
            ax.annotate(f"p = {ev.p:.4g}: {ev}", (d, ev.p), textcoords="offset points",
                        xytext=(-6 if right else 6, 5), ha="right" if right else "left",
                        fontsize=7)
    if ft.ended in ("collapse", "fold", "breakdown") and ft.p_end <= top:
        ax.axhline(ft.p_end, color="tab:red", ls="--", lw=0.8)
        ax.annotate(ft.ended, (ax.get_xlim()[0], ft.p_end), textcoords="offset points",
                    xytext=(4, 4), fontsize=8, color="tab:red")
    force, length = frame.units
    ax.set_xlabel(f"{dof} at {node} [{'rad' if dof == 'rz' else length}]")
    ax.set_ylabel("load parameter p")
    ax.set_title(f"increasing load: {len(ft.breakpoints)} change(s) of the working scheme; "
                 f"ended: {ft.ended}", fontsize=9)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return save_figure(fig, path)

