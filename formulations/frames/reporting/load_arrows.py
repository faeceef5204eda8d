"""Loads and reactions on a frame drawing, as arrows with their values.

The loads are the combination's: every nodal and member load times its
case's factor (``res.combination``).  Arrows are sized in points, not in
the structure's units, so they read the same on a 6 m portal and a 1 200 m
beam; where they would overprint (201 supports along a long beam) the largest
are drawn and the panel says how many.  A run of equal distributed loads
over consecutive collinear members (a floor, a long beam's self-weight) is
one band of arrows with one value.
"""

from __future__ import annotations

import numpy as np

from ..mechanics.plane_element import geometry
from .labels import around, value_text

LOAD_COLOR, REACTION_COLOR = "crimson", "teal"
_BOX = dict(boxstyle="square,pad=0.05", fc="white", ec="none", alpha=0.75)


def support_nodes(frame) -> dict:
    """{node: kind} for the bilateral supports and springs (contacts are
    drawn by their state): "fixed", "pin", "guided" (one translation and the
    rotation), "roller" (one translation; "inclined roller" on turned axes),
    "rotation held" (rz only), "spring"."""
    out = {}
    for node, dofs in frame.fixed.items():
        moves = dofs & {"ux", "uy"}
        if {"ux", "uy", "rz"} <= dofs:
            out[node] = "fixed"
        elif len(moves) == 2:
            out[node] = "pin"
        elif moves and "rz" in dofs:
            out[node] = "guided"
        elif moves:
            out[node] = "inclined roller" if node in frame.node_angles else "roller"
        elif dofs:
            out[node] = "rotation held"
    for node in frame.springs:
        out.setdefault(node, "spring")
    return out


def draw_loads(ax, placer, view, loads, reactions, font):
    frame, res = view.frame, view.res
    force, length = view.force, view.length
    counts = []
    if loads:
        forces, moments = _applied(frame, res, view)
        counts.append(("loads", *_arrows(ax, placer, forces, moments, LOAD_COLOR, force,
                                         length, font, back=0.0)))
    if reactions:
        forces, moments = _reactions(frame, res, view)
        counts.append(("reactions", *_arrows(ax, placer, forces, moments, REACTION_COLOR,
                                             force, length, font, back=5.0)))
    if loads:
        _distributed(ax, placer, view, font)
    dropped = [f"{name}: {shown} of {total} arrows drawn" for name, shown, total in counts
               if shown < total]
    if dropped:
        placer.note(ax, "; ".join(dropped) + " (the largest that do not overprint; all "
                    "values: res.support_reactions, frame.nodal_loads)", font, bbox=_BOX)


def _applied(frame, res, view):
    """Point forces [(tip, (fx, fy))] and moments [(at, mz)] of the combination."""
    combo = res.combination
    per_node: dict = {}
    for node, fx, fy, mz, case in frame.nodal_loads:
        f = combo.get(case, 0.0)
        if f:
            per_node[node] = per_node.get(node, np.zeros(3)) + f * np.array([fx, fy, mz])
    forces = [(view.node_at(nd), v[:2]) for nd, v in per_node.items() if np.any(v[:2])]
    moments = [(view.node_at(nd), v[2]) for nd, v in per_node.items() if v[2]]
    for m in frame.members.values():
        L, c, s = geometry(frame, m)
        for ld in m.loads:
            f = combo.get(ld.case, 0.0)
            if not f or ld.kind != "point":
                continue
            px, py, mz = (f * v for v in ld.values)
            g = _global(ld.axes, c, s, px, py)
            at = view.member_at(m.name, ld.a)
            if np.any(g):
                forces.append((at, g))
            if mz:
                moments.append((at, mz))
    return forces, moments


def _global(axes, c, s, vx, vy):
    return np.array([c * vx - s * vy, s * vx + c * vy]) if axes == "member" else \
        np.array([vx, vy])


def _reactions(frame, res, view):
    """Each node's support force (bilateral, spring and contact summed) on
    the structure; node-to-node contacts are internal and not drawn."""
    node_of = {}
    for key, c in zip(res.supports, frame.contacts):
        node_of[key] = c.node if c.other is None else None
    per_node: dict = {}
    for key, r in res.support_reactions.items():
        base = key.removesuffix(" (contact)").removesuffix(" (spring)")
        node = node_of.get(base, base if base in frame.nodes else None)
        if node is not None:
            per_node[node] = per_node.get(node, np.zeros(3)) + np.asarray(r, float)
    big = max([np.abs(v).max() for v in per_node.values()] + [0.0])
    forces = [(view.node_at(nd), v[:2]) for nd, v in per_node.items()
              if np.abs(v[:2]).max() > 1e-9 * big]
    moments = [(view.node_at(nd), v[2]) for nd, v in per_node.items() if abs(v[2]) > 1e-9 * big]
    return forces, moments


def _arrows(ax, placer, forces, moments, color, force, length, font, back):
    """Arrows for the forces (largest first, thinned), labels with their
    values, and the moments as ↺/↻ labels; (drawn, total)."""
    ref = max([float(np.abs(v).max()) for _, v in forces] + [0.0])
    mref = max([abs(m) for _, m in moments] + [0.0])
    shown = 0
    for at, v in sorted(forces, key=lambda t: -float(np.hypot(*t[1]))):
        size = float(np.hypot(*v))
        tail = placer.arrow(ax, at, v, 14.0 + 16.0 * size / ref, back=back, group=color,
                            color=color, lw=1.2)
        if tail is None:
            continue
        shown += 1
        # a near-vertical arrow's value runs along it: a row of supports 12 points
        # apart has room for upright labels only
        upright = abs(v[1]) > 2.0 * abs(v[0])
        where = [(0.0, 6.0 * np.sign(-v[1]), "center", "bottom" if v[1] < 0 else "top")] \
            if upright else around(-v, 6.0)
        placer.label(ax, _force_text(v, force, ref), tail, where, fontsize=font, color=color,
                     bbox=_BOX, rotation=90 if upright else 0)
    for at, mz in sorted(moments, key=lambda t: -abs(t[1])):
        text = f"{'↺' if mz > 0 else '↻'} {value_text(abs(mz), f'{force}·{length}', mref)}"
        placer.label(ax, text, at, around((1.0, -1.0), 5.0), fontsize=font, color=color,
                     bbox=_BOX)
    return shown, len(forces)


def _force_text(v, unit, ref) -> str:
    """One component: its size (the arrow gives the sense); two: (Fx, Fy)."""
    fx, fy = (0.0 if abs(c) <= 1e-9 * ref else float(c) for c in v)
    if fx == 0.0 or fy == 0.0:
        return value_text(abs(fx or fy), unit, ref)
    return f"({value_text(fx, '', ref)}, {value_text(fy, '', ref)}) {unit}"


def _distributed(ax, placer, view, font):
    """Bands of arrows for the distributed loads, one per run of equal loads."""
    runs = _runs(view)
    if not runs:
        return
    wref = max(max(np.hypot(*w1), np.hypot(*w2)) for run in runs for _, _, _, w1, w2 in run)
    unit = f"{view.force}/{view.length}"
    for run in runs:
        spots = []   # (member, x, w) along the run
        total = sum(b - a for _, a, b, _, _ in run)
        p0 = ax.transData.transform(view.member_at(run[0][0], run[0][1]))
        p1 = ax.transData.transform(view.member_at(run[-1][0], run[-1][2]))
        n = max(2, int(np.hypot(*(p1 - p0)) / placer.px(14.0)) + 1)
        for t in np.linspace(0.0, total, n):
            for name, a, b, w1, w2 in run:
                if t <= b - a + 1e-12 * total or (name, a, b) == run[-1][:3]:
                    x = a + min(t, b - a)
                    w = w1 + (w2 - w1) * (x - a) / (b - a)
                    spots.append((name, x, w))
                    break
                t -= b - a
        tails = []
        for name, x, w in spots:
            size = float(np.hypot(*w))
            tip = view.member_at(name, x)
            if size == 0.0:
                tails.append(tip)
                continue
            d = w / size
            tail = placer.offset(ax, tip, -d, 4.0 + 9.0 * size / wref)
            band_arrow(ax, placer, tip, tail)
            tails.append(tail)
        tails = np.array(tails)
        ax.plot(tails[:, 0], tails[:, 1], color=LOAD_COLOR, lw=0.6)
        w1, w2 = run[0][3], run[-1][4]
        s1, s2 = float(np.hypot(*w1)), float(np.hypot(*w2))
        text = value_text(s1, unit, wref) if np.isclose(s1, s2) else \
            f"{value_text(s1, '', wref)}…{value_text(s2, unit, wref)}"
        mid = len(spots) // 2
        d = spots[mid][2] / max(float(np.hypot(*spots[mid][2])), 1e-300)
        placer.label(ax, text, tails[mid], around(-d, 3.5), fontsize=font, color=LOAD_COLOR,
                     bbox=_BOX)


def _runs(view):
    """Distributed loads as runs [(member, a, b, w(a), w(b)) ...], global
    components times the combination's factor; a segment joins the run that
    ends where it starts with the same uniform load."""
    frame, combo = view.frame, view.res.combination
    runs, open_at = [], {}
    tol = 1e-9 * view.size
    for m in frame.members.values():
        L, c, s = geometry(frame, m)
        per_span: dict = {}
        for ld in m.loads:
            f = combo.get(ld.case, 0.0)
            if not f or ld.kind != "distributed":
                continue
            wx1, wy1, wx2, wy2 = (f * v for v in ld.values)
            w = (_global(ld.axes, c, s, wx1, wy1), _global(ld.axes, c, s, wx2, wy2))
            key = (ld.a, ld.b)   # loads of several cases on one stretch: one band
            old = per_span.get(key, (np.zeros(2), np.zeros(2)))
            per_span[key] = (old[0] + w[0], old[1] + w[1])
        for (a, b), (w1, w2) in per_span.items():
            start = np.array(frame.nodes[m.i]) + a * np.array([c, s])
            end = np.array(frame.nodes[m.i]) + b * np.array([c, s])
            uniform = np.allclose(w1, w2)
            key = (round(start[0] / tol), round(start[1] / tol), (round(c, 9), round(s, 9)))
            run = open_at.pop(key, None)
            if run is not None and uniform and np.allclose(run[-1][4], w1):
                run.append((m.name, a, b, w1, w2))
            else:
                run = [(m.name, a, b, w1, w2)]
                runs.append(run)
            if uniform:
                open_at[(round(end[0] / tol), round(end[1] / tol), (round(c, 9),
                                                                   round(s, 9)))] = run
    return runs


def band_arrow(ax, placer, tip, tail) -> None:
    """One small arrow of a distributed load's band, from tail to tip, kept
    clear of the labels placed after it."""
    ax.annotate("", tip, xytext=tail, textcoords="data", annotation_clip=False,
                arrowprops=dict(arrowstyle="-|>", shrinkA=0, shrinkB=0,
                                mutation_scale=5, color=LOAD_COLOR, lw=0.6))
    placer.keep_clear(ax, tip, tail)
