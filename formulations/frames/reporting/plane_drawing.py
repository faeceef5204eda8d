"""Drawings of a frame result: the deformed shape (exact member deflection,
not interpolated between the nodes) with the loads, reactions and support
states, and the diagrams of M, V and N, each panel on its own scale with a
scale bar.  Labels are placed on the rendered figure without overprinting
(:mod:`.labels`), numbers in engineering notation (:mod:`.notation`).  A
result that is not ok is never drawn.

Two kinds of drawing, chosen from the geometry:

* a **frame** (members in more than one line) is drawn to scale, equal
  aspect; each diagram is laid off across its members and a scale bar gives
  its units (the axes are metres of the structure);
* a **straight horizontal beam** is drawn as functions of x: the ordinate
  of each panel is the quantity itself, in its units (moment axis pointing
  down, so sagging is drawn on the tension side as on a frame).
"""

from __future__ import annotations

import math

import numpy as np

from qpcontact.core.errors import InvalidOptionError, SolverFailedError

from ..mechanics.plane_element import geometry
from .labels import Placer, around, nice, value_text
from .load_arrows import LOAD_COLOR, REACTION_COLOR, draw_loads, support_nodes

DIAGRAMS = ("deflection", "M", "V", "N")
DEFAULT = ("deflection", "M")
STATE_COLORS = {"separated": "tab:red", "closed": "tab:blue", "stick": "tab:green",
                "slip+": "tab:orange", "slip-": "tab:purple"}
_NAMES = {"M": "bending moment M", "V": "shear force V", "N": "axial force N"}
#: diagrams are scaled on this percentile of the members' peaks, so one
#: heavily loaded member (a foundation beam) does not flatten all the others
_TYPICAL = 75
_FONT = 6.5
#: the diagrams' values: read at the drawing's saved size (110 dpi)
_VALUES = 8.0
_DPI = 110   # save_figure's: labels are placed at the resolution they print at


def check_diagrams(diagrams) -> tuple:
    if isinstance(diagrams, str):
        diagrams = (diagrams,)
    try:
        kinds = tuple(diagrams)
    except TypeError:
        kinds = (diagrams,)
    bad = [k for k in kinds if k not in DIAGRAMS]
    if bad or not kinds or len(set(kinds)) != len(kinds):
        raise InvalidOptionError(
            f"diagrams: a sequence of distinct names among {', '.join(DIAGRAMS)} (e.g. "
            f"diagrams=('deflection', 'M', 'V')); got {diagrams!r}")
    return kinds


def combination_title(res) -> str:
    """The result in the user's words: the combination's name, the split
    constant + p x variable
    as "p = 2 (constant + 2 × variable)", or a dict as "1.2 × D + 1.6 × L"."""
    combo = {c: f for c, f in res.combination.items() if f}
    words = sum_words(combo)
    if res.name:
        return res.name if words in (res.name, "no load") else f"{res.name} = {words}"
    if set(res.combination) <= {"constant", "variable"}:
        return f"p = {res.p:g} ({words})"
    return words


def sum_words(combo: dict) -> str:
    """{case: factor} as "D + 1.5 × W − 0.5 × L"."""
    out = ""
    for case, f in combo.items():
        term = case if abs(f) == 1 else f"{abs(f):g} × {case}"
        out += (f" {'−' if f < 0 else '+'} " if out else ("−" if f < 0 else "")) + term
    return out or "no load"


class View:
    """What every panel needs of one result: member geometry, internal forces
    and deflections sampled once, the displacement magnification."""

    def __init__(self, frame, res, scale):
        self.frame, self.res = frame, res
        self.force, self.length = frame.units
        xy = np.array(list(frame.nodes.values()))
        self.size = max(np.ptp(xy[:, 0]), np.ptp(xy[:, 1]), 1e-12)
        self.tall = np.ptp(xy[:, 1]) > np.ptp(xy[:, 0])
        self.members = {}
        for m in frame.members.values():
            L, c, s = geometry(frame, m)
            x, N, V, M = res.diagram(m.name, 41)
            xd, dx, dy = res.deflection(m.name, 41, axes="global")
            self.members[m.name] = dict(m=m, L=L, c=c, s=s, a=np.array(frame.nodes[m.i]),
                                        x=x, N=N, V=V, M=M, xd=xd, dx=dx, dy=dy)
        self.straight = all(abs(d["s"]) < 1e-12 for d in self.members.values()) and \
            np.ptp(xy[:, 1]) <= 1e-12 * self.size
        umax = max([max(abs(d[0]), abs(d[1])) for d in res.displacements.values()]
                   + [np.abs(np.r_[d["dx"], d["dy"]]).max() for d in self.members.values()])
        self.umax = umax
        self.scale = scale or (0.08 * self.size / umax if umax > 0 else 1.0)

    def node_at(self, node):
        """Where a node's loads, reactions and support go: deformed by
        ``scale`` on a frame, on the undeformed axis (uy = 0) of a beam,
        whose curve is the deflection's ordinate."""
        x, y = self.frame.nodes[node]
        if self.straight:
            return np.array([x, 0.0])
        u = self.res.displacements[node]
        return np.array([x + self.scale * u[0], y + self.scale * u[1]])

    def member_at(self, name, x, curve=False):
        """The point of member ``name`` at distance x from node i, as node_at
        (``curve``: on a beam, on its deflection curve instead)."""
        d = self.members[name]
        ux, uy = np.interp(x, d["xd"], d["dx"]), np.interp(x, d["xd"], d["dy"])
        px, py = d["a"] + x * np.array([d["c"], d["s"]])
        if self.straight:
            return np.array([px, uy if curve else 0.0])
        return np.array([px + self.scale * ux, py + self.scale * uy])


def plot_result(frame, res, path, diagrams=DEFAULT, scale=None, title="", loads=True,
                reactions=True):
    if not res.ok:
        raise SolverFailedError(
            f"this result is not an equilibrium ({res.message}); nothing is drawn from it")
    kinds = check_diagrams(diagrams)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure

    view = View(frame, res, scale)
    fig, axes = _figure(plt, view, len(kinds))
    placer = Placer(fig)
    finish = []
    for ax, kind in zip(axes, kinds):
        if kind == "deflection":
            finish.append(_deflection(ax, view, loads, reactions))
        else:
            finish.append(_diagram(ax, view, kind))
        ax.tick_params(labelsize=7)
    handles = _legend_handles(view, "deflection" in kinds and (loads or reactions))
    if handles:
        fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 8),
                   fontsize=7.5, frameon=False)
    fig.suptitle(title or combination_title(res), fontsize=10)
    placer.freeze()
    for step in finish:
        step(placer)
    return save_figure(fig, path)


def _figure(plt, view, n):
    """Panels side by side for a tower, stacked otherwise, each about the
    drawing's own proportions."""
    xy = np.array(list(view.frame.nodes.values()))
    w, h = np.ptp(xy[:, 0]) + 0.3 * view.size, np.ptp(xy[:, 1]) + 0.3 * view.size
    if view.straight:
        figsize = (14.0, 1.2 + 2.7 * n)
        rows, cols = n, 1
    elif view.tall:
        panel = min(max(8.2 * w / h + 1.0, 4.6), 7.5)
        figsize = (panel * n, 10.0)
        rows, cols = 1, n
    else:
        panel = min(max(11.5 * h / w + 0.9, 3.0), 6.0)
        figsize = (13.0, 1.2 + panel * n)
        rows, cols = n, 1
    fig, axes = plt.subplots(rows, cols, figsize=figsize, dpi=_DPI, layout="constrained",
                             squeeze=False)
    return fig, list(axes.ravel())


def _segments(view, deformed):
    segs = []
    for d in view.members.values():
        x = d["xd"]
        px, py = d["a"][0] + d["c"] * x, d["a"][1] + d["s"] * x
        if deformed:
            px, py = px + view.scale * d["dx"], py + view.scale * d["dy"]
        segs.append(np.c_[px, py])
    return segs


def _deflection(ax, view, loads, reactions):
    """Deformed shape, support states, loads and reactions."""
    from matplotlib.collections import LineCollection

    L = view.length
    if view.straight:
        for d in view.members.values():
            ax.plot(d["a"][0] + d["c"] * d["xd"], d["dy"], color="k", lw=1.4)
        ax.axhline(0.0, color="0.6", lw=0.8)
        ax.set_ylabel(f"uy [{L}]", fontsize=8)
        ax.set_title("deflection uy (true scale on the ordinate); supports, loads and "
                     "reactions on the beam's axis uy = 0", fontsize=9)
        reach = 1.8 * max(abs(u[1]) for u in view.res.displacements.values()) or 1.0
        ax.set_ylim(-reach, reach)   # the curve in the middle, room for the arrows
        ax.margins(x=0.01)
    else:
        ax.add_collection(LineCollection(_segments(view, False), colors="0.8", lw=0.8))
        ax.add_collection(LineCollection(_segments(view, True), colors="k", lw=1.4))
        ax.set_aspect("equal", adjustable="datalim")
        ax.margins(0.06)
        lo, hi = ax.dataLim.y0, ax.dataLim.y1
        # room for the reactions and their values
        ax.update_datalim([(ax.dataLim.x0, lo - 0.12 * (hi - lo))])
        ax.autoscale_view()
        ax.set_ylabel(f"y [{L}]", fontsize=8)
        ax.set_title(f"deformed shape (displacements × {view.scale:.3g}), loads and reactions",
                     fontsize=9)
    for d in view.members.values():
        m = d["m"]
        for hinged, x in ((m.hinge_i, 0.0), (m.hinge_j, d["L"])):
            if hinged:
                ax.plot(*view.member_at(m.name, x, curve=True), "o", mfc="w", mec="k", ms=4.5,
                        zorder=4)
    _support_markers(ax, view)
    ax.set_xlabel(f"x [{L}]", fontsize=8)
    ax.grid(True, alpha=0.25)

    def finish(placer):
        if not view.straight:
            _scale_bar(ax, placer, view.scale, f"{view.length} (displacement)")
        draw_loads(ax, placer, view, loads, reactions, _FONT)
        _displacement_labels(ax, placer, view)
    return finish


def _support_markers(ax, view):
    frame, res = view.frame, view.res
    for key, c in zip(res.supports, frame.contacts):
        state = res.supports[key].state
        angle = math.degrees(math.atan2(c.normal[1], c.normal[0])) - 90.0
        ax.plot(*view.node_at(c.node), marker=(3, 0, angle), ms=7, color=STATE_COLORS[state],
                mec="k", mew=0.4, ls="none", zorder=5)
    for node, kind in support_nodes(frame).items():
        marker, face = _SYMBOLS[kind]
        ax.plot(*view.node_at(node), marker=marker, ms=7, mfc=face, mec="k", ls="none",
                zorder=5)


#: bilateral supports and springs: marker and face colour (the legend shows them)
_SYMBOLS = {"fixed": ("s", "k"), "pin": ("^", "w"), "roller": ("o", "w"),
            "inclined roller": ("o", "0.6"), "guided": ("P", "w"), "rotation held": ("X", "w"),
            "spring": ("D", "tab:brown")}


def _legend_handles(view, arrows):
    """Support states with their counts, support symbols, the arrows' colours."""
    from matplotlib.lines import Line2D

    counts: dict = {}
    for s in view.res.supports.values():
        counts[s.state] = counts.get(s.state, 0) + 1
    handles = [Line2D([], [], marker="^", ls="none", ms=7, color=STATE_COLORS[st], mec="k",
                      mew=0.4, label=f"{st} ({counts[st]})") for st in STATE_COLORS
               if st in counts]
    kinds: dict = {}
    for kind in support_nodes(view.frame).values():
        kinds[kind] = kinds.get(kind, 0) + 1
    for kind, n in kinds.items():
        marker, face = _SYMBOLS[kind]
        handles.append(Line2D([], [], marker=marker, ls="none", ms=7, mfc=face, mec="k",
                              label=f"{kind} ({n})"))
    if arrows:
        handles += [Line2D([], [], marker=r"$\rightarrow$", ls="none", ms=12, color=color,
                           label=what) for what, color in (("loads", LOAD_COLOR),
                                                           ("reactions", REACTION_COLOR))]
    return handles


def _displacement_labels(ax, placer, view):
    """The largest horizontal and vertical displacements, where they occur."""
    res = view.res
    done = set()
    for k, name in ((0, "ux"), (1, "uy")):
        node = max(res.displacements, key=lambda nd: abs(res.displacements[nd][k]))
        v = res.displacements[node][k]
        if v == 0.0 or (node, k) in done:
            continue
        done.add((node, k))
        at = np.array([view.frame.nodes[node][0], v]) if view.straight else view.node_at(node)
        text = f"{name} = {value_text(v, view.length, view.umax)} at {node}"
        placer.label(ax, text, at, around((1.0, 1.0), 6.0) + around((1.0, 1.0), 16.0),
                     fontsize=_FONT + 0.5, color="k", fontweight="bold", bbox=_BOX)


_BOX = dict(boxstyle="square,pad=0.05", fc="white", ec="none", alpha=0.75)


def _diagram(ax, view, kind):
    """The diagram of M, V or N over every member."""
    unit = view.force + (f"·{view.length}" if kind == "M" else "")
    values = {n: d[kind] * (d["c"] if view.straight and kind == "M" else 1.0)
              for n, d in view.members.items()}
    peaks = np.array([np.abs(v).max() for v in values.values()])
    ref = float(peaks.max())
    if view.straight:
        _beam_diagram(ax, view, values, kind, unit)
        dscale = None
    else:
        dscale = _frame_diagram(ax, view, values, kind, peaks)
    ax.set_xlabel(f"x [{view.length}]", fontsize=8)
    ax.grid(True, alpha=0.25)
    side = ", drawn on the tension side" if kind == "M" else ", + blue, − red"
    grouped = not view.straight and len(view.members) > GROUPED
    ax.set_title(f"{_NAMES[kind]} [{unit}]{side}" + (
        f"\nlabelled: the largest |{kind}| of each storey's columns, each level's beams"
        if grouped else ""), fontsize=9)

    def finish(placer):
        if ref == 0.0:
            placer.label(ax, f"{kind} = 0 in every member", (0.5, 0.5), [(0, 0, "center",
                         "center")], xycoords="axes fraction", fontsize=8)
            return
        if dscale is not None:
            _scale_bar(ax, placer, dscale, unit)
        _value_labels(ax, placer, view, values, kind, dscale, ref, unit)
    return finish


def _frame_diagram(ax, view, values, kind, peaks):
    """Laid off across each member: M on the tension side (-y of the member
    for sagging), V and N on +y when positive.  Scaled so that a typical
    member's peak is half the typical member length, the largest peak at
    most a third of the structure."""
    from matplotlib.collections import LineCollection, PolyCollection

    lengths = np.array([d["L"] for d in view.members.values()])
    live = peaks[peaks > 1e-9 * peaks.max()] if peaks.max() > 0 else peaks
    typical = np.percentile(live, _TYPICAL) if live.size else 0.0
    dscale = min(0.5 * np.median(lengths) / typical, 0.33 * view.size / peaks.max()) \
        if typical > 0 else 1.0
    sign = -1.0 if kind == "M" else 1.0
    ax.add_collection(LineCollection(_segments(view, False), colors="k", lw=1.0))
    pos, neg, outline = [], [], []
    for name, d in view.members.items():
        n = np.array([-d["s"], d["c"]])
        base = d["a"] + np.outer(d["x"], [d["c"], d["s"]])
        for part, bucket in ((np.maximum(values[name], 0), pos), (np.minimum(values[name], 0),
                                                                   neg)):
            if np.any(part):
                tip = base + sign * dscale * np.outer(part, n)
                bucket.append(np.r_[base, tip[::-1]])
        outline.append(base + sign * dscale * np.outer(values[name], n))
    blue, red = ("tab:blue", "tab:blue") if kind == "M" else ("tab:blue", "tab:red")
    ax.add_collection(PolyCollection(pos, facecolors=blue, alpha=0.3, edgecolors="none"))
    ax.add_collection(PolyCollection(neg, facecolors=red, alpha=0.3, edgecolors="none"))
    ax.add_collection(LineCollection(outline, colors="0.25", lw=0.6))
    ax.set_aspect("equal", adjustable="datalim")
    ax.margins(0.06)
    ax.autoscale_view()
    ax.set_ylabel(f"y [{view.length}]", fontsize=8)
    return dscale


def _beam_diagram(ax, view, values, kind, unit):
    """x against the quantity, every member in one collection (200 spans)."""
    from matplotlib.collections import LineCollection, PolyCollection

    pos, neg, lines = [], [], []
    for name, d in view.members.items():
        X = d["a"][0] + d["c"] * d["x"]
        v = values[name]
        for part, bucket in ((np.maximum(v, 0), pos), (np.minimum(v, 0), neg)):
            if np.any(part):
                bucket.append(np.r_[np.c_[X, np.zeros_like(X)], np.c_[X, part][::-1]])
        lines.append(np.c_[X, v])
    ax.add_collection(PolyCollection(pos, facecolors="tab:blue", alpha=0.3, edgecolors="none"))
    ax.add_collection(PolyCollection(neg, facecolors="tab:blue" if kind == "M" else "tab:red",
                                     alpha=0.3, edgecolors="none"))
    ax.add_collection(LineCollection(lines, colors="0.25", lw=0.6))
    ax.autoscale_view()
    ax.axhline(0.0, color="k", lw=1.0)
    ax.margins(x=0.01, y=0.25)
    if kind == "M":
        ax.invert_yaxis()   # sagging (positive) down: the tension side of a beam
        ax.set_ylabel(f"M [{unit}] (sagging down)", fontsize=8)
    else:
        ax.set_ylabel(f"{kind} [{unit}]", fontsize=8)


def _value_labels(ax, placer, view, values, kind, dscale, ref, unit):
    """Values where they matter, largest first, where they fit: each
    member's end values and span extremes on a small frame or a straight
    beam (the moments at the joints); on a frame of more than
    :data:`GROUPED` members only the largest |value| of each member group
    (:func:`member_groups`: the columns of a storey, the beams of a level),
    so that a 20-storey tower reads at its saved size.  The panel says what
    is shown and where every value is."""
    sign = -1.0 if kind == "M" else 1.0
    groups = member_groups(view) if not view.straight and len(view.members) > GROUPED else None
    cands, seen = [], set()
    for name, d in view.members.items():
        v = values[name]
        n = np.array([-d["s"], d["c"]])
        for k in {0, len(v) - 1, int(np.argmax(v)), int(np.argmin(v))}:
            if abs(v[k]) <= 1e-3 * ref:
                continue
            if view.straight:
                X = d["a"][0] + d["c"] * d["x"][k]
                at = np.array([X, v[k]])
                out = (0.0, -1.0) if (v[k] > 0) == (kind == "M") else (0.0, 1.0)
            else:
                at = d["a"] + d["x"][k] * np.array([d["c"], d["s"]]) + sign * dscale * v[k] * n
                out = sign * np.sign(v[k]) * n
            text = value_text(v[k], "", ref)
            spot = (text, *np.round(at / (1e-6 * view.size)).astype(int))
            if spot not in seen:   # two members' ends at one joint of a continuous beam
                seen.add(spot)
                cands.append((abs(v[k]), text, at, out, groups[name] if groups else name))
    cands.sort(key=lambda t: -t[0])
    if groups:
        first = {}
        for c in cands:
            first.setdefault(c[4], c)
        cands = sorted(first.values(), key=lambda t: -t[0])
    shown = 0
    for _, text, at, out, _ in cands:
        if placer.label(ax, text, at, around(out, 1.5) + around(out, 6.0), fontsize=_VALUES,
                        color="k", bbox=_BOX):
            shown += 1
    where = "(all: res.rows('members'), res.extremes(member))"
    if groups and shown < len(cands):
        placer.note(ax, f"{shown} of {len(cands)} groups' largest values labelled\n{where}",
                    _FONT + 0.5, bbox=_BOX)
    elif shown < len(cands):
        placer.note(ax, f"{shown} of {len(cands)} end and span values labelled [{unit}], the "
                    f"largest that fit\n{where}", _FONT + 0.5, bbox=_BOX)


#: a frame with more members than this is labelled by member groups
GROUPED = 24


def member_groups(view) -> dict:
    """{member: group}: members grouped by direction (nearer vertical:
    "columns", else "beams") and height (a column by its mid-height, a beam
    by its level), so that the columns of one storey and the beams of one
    level form a group each."""
    tol = 1e-3 * view.size
    out = {}
    for name, d in view.members.items():
        kind = "columns" if abs(d["s"]) > abs(d["c"]) else "beams"
        mid = float(d["a"][1] + 0.5 * d["L"] * d["s"])
        out[name] = (kind, int(round(mid / tol)))
    return out


def _scale_bar(ax, placer, per_unit, unit):
    """A bar of a round value in the diagram's units (``per_unit``: data
    length per unit of the quantity), about 60 points long, in the emptiest
    corner of the panel."""
    from matplotlib.lines import Line2D

    x0, x1 = ax.get_xlim()
    pts_per_data = ax.bbox.width / abs(x1 - x0) * 72.0 / ax.figure.dpi
    value = nice(60.0 / pts_per_data / per_unit)
    length = value * per_unit
    occupied = _occupied(ax)
    half, box = placer.px(length * pts_per_data / 2.0 + 6.0), ax.bbox
    best = None
    low, high = box.y0 + placer.px(8.0), box.y1 - placer.px(16.0)
    for cx, cy in ((box.x0 + half, low), (box.x1 - half, low), (box.x0 + half, high),
                   (box.x1 - half, high)):
        hits = np.count_nonzero((np.abs(occupied[:, 0] - cx) < half)
                                & (occupied[:, 1] > cy - placer.px(6.0))
                                & (occupied[:, 1] < cy + placer.px(14.0)))
        if best is None or hits < best[0]:
            best = (hits, cx, cy)
    cx, cy = ax.transData.inverted().transform(best[1:])
    xs = np.array([cx - length / 2, cx + length / 2])
    bar = Line2D(xs, [cy, cy], color="k", lw=2.5, solid_capstyle="butt", gid="scale bar")
    ax.add_line(bar)
    placer.block(bar)
    reach = length * pts_per_data / 2.0
    placer.label(ax, value_text(value, unit), (cx, cy), [(0, 4, "center", "bottom"),
                 (-reach, 4, "left", "bottom"), (reach, 4, "right", "bottom")],
                 fontsize=_FONT + 0.5, gid="scale bar label")


def _occupied(ax):
    """Display positions of everything drawn on the panel (lines, fills)."""
    pts = [np.empty((0, 2))]
    for line in ax.lines:
        pts.append(ax.transData.transform(line.get_xydata()))
    for coll in ax.collections:
        for path in coll.get_paths():
            pts.append(ax.transData.transform(path.vertices))
    return np.vstack(pts)
