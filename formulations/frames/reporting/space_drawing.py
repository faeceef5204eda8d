"""Drawing of a space frame's result: an orthographic view (isometric by
default, or any azimuth and elevation) drawn in two dimensions — the frame
thin grey, its deformed shape black (each member bent by its exact
deflection, not a straight line between its displaced ends), the contacts
by state, the slip direction at every slipping contact, the loads, and the
global axes.  Labels are placed on the rendered figure without overprinting
(:class:`.labels.Placer`), numbers with their units
(:func:`.labels.value_text`).  A result that is not ok is never drawn.

The view: a camera at azimuth a (from +x towards +y) and elevation e (above
the x-y plane) looks at the frame; the screen's right is (-sin a, cos a, 0)
and its up the camera direction crossed with it.  Isometric is a = -45°, e
= atan(1/√2) = 35.26°: x runs down to the right, y up to the right, z up,
all three shortened alike.  An orthographic view keeps parallel members
parallel and needs no perspective to read; lengths along the three axes
are shortened by different factors in a general view, so the drawing gives
the frame's extents in words instead of a scale bar.

Each member's deflection is the result's own (``res.deflection``,
:func:`..space.space_diagrams.deflection`): integrated from the internal
forces, exact for the element and its loads.
"""

from __future__ import annotations

import math

import numpy as np

from qpcontact.core.errors import InvalidOptionError, SolverFailedError

from ..mechanics.space_element import axes as member_axes
from .plane_drawing import combination_title
from .labels import Placer, around, value_text
from .load_arrows import LOAD_COLOR, band_arrow

#: azimuth and elevation of the isometric view (degrees)
ISOMETRIC = (-45.0, math.degrees(math.atan(1.0 / math.sqrt(2.0))))
#: marker, face and edge colour of each contact state (shape and colour
#: both differ, so the states read in grey print too)
STATE_STYLE = {"separated": ("o", "white", "tab:red"), "closed": ("s", "tab:blue", "k"),
               "stick": ("^", "tab:green", "k"), "slip": ("D", "tab:orange", "k")}
SLIP_COLOR = "tab:orange"
#: displacements below RIGID x the frame's size are rounding of zero
RIGID = 1e-12
_FONT = 7.0
_DPI = 110   # save_figure's: labels are placed at the resolution they print at
_BOX = dict(boxstyle="square,pad=0.05", fc="white", ec="none", alpha=0.8)


def view_axes(azimuth: float, elevation: float) -> np.ndarray:
    """(2, 3): the screen's right and up in global components."""
    a, e = math.radians(azimuth), math.radians(elevation)
    camera = np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    right = np.array([-math.sin(a), math.cos(a), 0.0])
    return np.stack([right, np.cross(camera, right)])


def _angles(azimuth, elevation):
    az, el = ISOMETRIC[0] if azimuth is None else azimuth, \
        ISOMETRIC[1] if elevation is None else elevation
    for name, v in (("azimuth", az), ("elevation", el)):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise InvalidOptionError(f"{name}: a finite number of degrees; got {v!r}")
    if not -90.0 <= el <= 90.0:
        raise InvalidOptionError(f"elevation: degrees in [-90, 90]; got {el!r}")
    return float(az), float(el)


class SpaceView:
    """What the drawing needs of one result: the projection, the members'
    undeformed and deflected axes, the displacement magnification."""

    def __init__(self, frame, res, scale, azimuth, elevation):
        self.frame, self.res = frame, res
        self.force, self.length = frame.units
        self.azimuth, self.elevation = azimuth, elevation
        self.P = view_axes(azimuth, elevation)
        self.xyz = {n: np.asarray(v, float) for n, v in frame.nodes.items()}
        pts = np.array(list(self.xyz.values()))
        self.extent = np.ptp(pts, axis=0)
        self.size = max(float(np.linalg.norm(self.extent)), 1e-12)
        self.curves = {}
        for name, m in frame.members.items():
            x, d = res.deflection(name, 21, axes="global")
            a, b = self.xyz[m["i"]], self.xyz[m["j"]]
            self.curves[name] = (a + np.outer(x / x[-1], b - a), d)
        trans = {n: float(np.linalg.norm(np.asarray(u[:3]))) for n, u in res.displacements.items()}
        self.peak_node = max(trans, key=trans.get)
        self.umax = max([trans[self.peak_node]]
                        + [float(np.linalg.norm(d, axis=1).max()) for _, d in self.curves.values()])
        if self.umax <= RIGID * self.size:
            self.umax = 0.0             # rounding of a frame that does not move: not magnified
        if scale is None:
            scale = 0.08 * self.size / self.umax if self.umax > 0 else 1.0
        self.scale = float(scale)

    def project(self, pts) -> np.ndarray:
        return np.atleast_2d(pts) @ self.P.T

    def at(self, node) -> np.ndarray:
        """A node's drawn (deformed) position."""
        return self.project(self.xyz[node] + self.scale * np.asarray(
            self.res.displacements[node][:3]))[0]

    def member_point(self, name, s) -> np.ndarray:
        """The drawn point at fraction s of member ``name``'s deflected axis."""
        base, d = self.curves[name]
        # the sections are not evenly spaced (a member load's positions are among them)
        along = np.linalg.norm(base - base[0], axis=1) / np.linalg.norm(base[-1] - base[0])
        drawn = base + self.scale * d
        p = np.array([np.interp(s, along, drawn[:, c]) for c in range(3)])
        return self.project(p)[0]

    def words(self) -> str:
        if np.allclose((self.azimuth, self.elevation), ISOMETRIC):
            return "isometric view"
        return f"view from azimuth {self.azimuth:g}°, elevation {self.elevation:g}°"

    def pad(self, c):
        """The corners of a contact's support plate: a square in its plane,
        where the support surface is (g behind the node, magnified)."""
        half = 0.035 * self.size
        base = self.xyz[c.node] - self.scale * c.gap * c.normal
        return self.project([base + half * (a * c.t1 + b * c.t2)
                             for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))])


def plot_space_result(frame, res, path, *, scale=None, title=None, azimuth=None,
                      elevation=None, loads=True) -> str:
    if not res.ok:
        raise SolverFailedError(
            f"this result is not an equilibrium ({res.message}); nothing is drawn from it")
    az, el = _angles(azimuth, elevation)
    if scale is not None and not (isinstance(scale, (int, float)) and not isinstance(scale, bool)
                                  and math.isfinite(scale) and scale > 0):
        raise InvalidOptionError(f"scale: a positive finite magnification; got {scale!r}")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from qpcontact.plots.figures import save_figure

    view = SpaceView(frame, res, scale, az, el)
    fig, ax = _figure(plt, view)
    markers = draw_frame(ax, view)
    handles = legend_handles(view, loads)
    fig.legend(handles=handles, loc="outside lower center",
               ncols=len(handles) if len(handles) <= 6 else math.ceil(len(handles) / 2),
               fontsize=7.5, frameon=False)
    fig.suptitle(title or combination_title(res), fontsize=10)
    ax.set_title(_subtitle(view), fontsize=8.5)
    placer = Placer(fig)
    placer.freeze()
    for marker in markers:
        placer.block(marker)
    triad(ax, placer, view)
    slips = slip_arrows(ax, placer, view)
    shown = contact_labels(ax, placer, view)
    if loads:
        draw_space_loads(ax, placer, view)
    peak_label(ax, placer, view)
    if shown < len(res.supports) or slips < sum(s.state == "slip" for s in res.supports.values()):
        placer.note(ax, f"{shown} of {len(res.supports)} contacts labelled (the rest overprint; "
                    "all: res.rows('supports'))", _FONT, bbox=_BOX)
    return save_figure(fig, path)


def _figure(plt, view):
    """One panel about the drawing's own proportions, room around it for
    the labels, the arrows and the axes' triad."""
    pts = np.vstack([view.project(b + view.scale * d) for b, d in view.curves.values()]
                    + [view.project(b) for b, _ in view.curves.values()]
                    + [view.pad(c) for c in view.frame.contacts]
                    + [view.project(list(view.xyz.values()))])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = np.maximum(hi - lo, 1e-3 * view.size)
    grow = 0.1 * span.max()
    width = 10.0
    # the panel's height for the drawing's proportions, then the titles' and the legend's
    height = min(max(9.8 * (span[1] + 2 * grow) / (span[0] + 2 * grow), 4.0), 9.0) + 1.1
    fig, ax = plt.subplots(figsize=(width, height), dpi=_DPI, layout="constrained")
    ax.update_datalim([lo - grow, hi + grow])
    ax.margins(0.0)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_axis_off()
    return fig, ax


def draw_frame(ax, view):
    """Members undeformed and deformed, support plates, contact and support
    markers; returns the markers (labels keep clear of them)."""
    from matplotlib.collections import LineCollection, PolyCollection

    ax.add_collection(LineCollection([view.project(b) for b, _ in view.curves.values()],
                                     colors="0.72", lw=0.8, zorder=1))
    ax.add_collection(PolyCollection([view.pad(c) for c in view.frame.contacts],
                                     facecolors="0.88", edgecolors="0.45", lw=0.6, zorder=1.5))
    ax.add_collection(LineCollection([view.project(b + view.scale * d)
                                      for b, d in view.curves.values()],
                                     colors="k", lw=1.5, zorder=2))
    markers = []
    for node in view.frame.fixed:
        markers += ax.plot(*view.at(node), "s", ms=12, mfc="none", mec="k", mew=1.2, zorder=4)
    for node in view.frame.springs:
        markers += ax.plot(*view.at(node), "D", ms=13, mfc="none", mec="tab:brown", mew=1.2,
                           zorder=4)
    for s, c in zip(view.res.supports.values(), view.frame.contacts):
        marker, face, edge = STATE_STYLE[s.state]
        markers += ax.plot(*view.at(c.node), marker, ms=7.5, mfc=face, mec=edge,
                           mew=1.4 if s.state == "separated" else 0.5, zorder=5)
    return markers


def legend_handles(view, loads):
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles = [Line2D([], [], color="0.72", lw=0.8, label="undeformed"),
               Line2D([], [], color="k", lw=1.5, label=f"deformed (× {view.scale:.3g})"),
               Patch(facecolor="0.88", edgecolor="0.45", label="contact plate")]
    counts: dict = {}
    for s in view.res.supports.values():
        counts[s.state] = counts.get(s.state, 0) + 1
    for state, (marker, face, edge) in STATE_STYLE.items():
        if state in counts:
            handles.append(Line2D([], [], marker=marker, ls="none", ms=7.5, mfc=face, mec=edge,
                                  mew=1.4 if state == "separated" else 0.5,
                                  label=f"{state} ({counts[state]})"))
    if "slip" in counts:
        handles.append(Line2D([], [], marker=r"$\rightarrow$", ls="none", ms=12,
                              color=SLIP_COLOR, label="slip direction"))
    if view.frame.fixed:
        handles.append(Line2D([], [], marker="s", ls="none", ms=10, mfc="none", mec="k",
                              mew=1.2, label=f"bilateral support ({len(view.frame.fixed)})"))
    if view.frame.springs:
        handles.append(Line2D([], [], marker="D", ls="none", ms=10, mfc="none", mec="tab:brown",
                              mew=1.2, label=f"spring ({len(view.frame.springs)})"))
    if loads and _has_loads(view):
        handles.append(Line2D([], [], marker=r"$\rightarrow$", ls="none", ms=12,
                              color=LOAD_COLOR, label="loads"))
    return handles


def _subtitle(view) -> str:
    L = view.length
    ext = " × ".join(value_text(v, "", view.size) for v in view.extent)
    peak = view.res.displacements[view.peak_node]
    moved = (f"largest nodal displacement {value_text(float(np.linalg.norm(peak[:3])), L)} at "
             f"{view.peak_node}") if view.umax > 0 else \
        f"no displacement (all below {RIGID:g} of the frame's size)"
    return (f"deformed shape, displacements × {view.scale:.3g}; {view.words()}\n"
            f"frame {ext} {L} (x × y × z); {moved}")


def triad(ax, placer, view):
    """The global axes x, y, z from one corner of the panel, in the corner
    where the drawing leaves most room; an axis pointing at the viewer (or
    away) is a circle."""
    length = placer.px(30.0)
    ends = {e: view.P[:, k] * length for k, e in enumerate("xyz")}
    reach = np.array([v for d in ends.values() for v in (d * 1.45, (0.0, 0.0))])
    reach = np.vstack([reach, reach + placer.px(8.0), reach - placer.px(8.0)])
    lo, hi = reach.min(axis=0), reach.max(axis=0)
    box, inset = ax.bbox, placer.px(6.0)
    taken = ax.transData.transform(np.vstack(
        [view.project(b + view.scale * d) for b, d in view.curves.values()]))
    best = None
    for ox, oy in ((box.x0 + inset - lo[0], box.y0 + inset - lo[1]),
                   (box.x1 - inset - hi[0], box.y0 + inset - lo[1]),
                   (box.x0 + inset - lo[0], box.y1 - inset - hi[1]),
                   (box.x1 - inset - hi[0], box.y1 - inset - hi[1])):
        inside = np.all((taken > (ox + lo[0], oy + lo[1])) & (taken < (ox + hi[0], oy + hi[1])),
                        axis=1)
        if best is None or inside.sum() < best[0]:
            best = (int(inside.sum()), np.array([ox, oy]))
    origin = best[1]
    inv = ax.transData.inverted()
    o = inv.transform(origin)
    for name, d in ends.items():
        if np.hypot(*d) < 0.2 * length:        # along the line of sight
            toward = float(np.dot(np.cross(*view.P), np.eye(3)["xyz".index(name)])) > 0
            ax.plot(*o, marker="o", ms=9, mfc="white", mec="k", zorder=6)
            ax.plot(*o, marker="." if toward else "x", ms=5, color="k", zorder=7)
            at = origin + placer.px(9.0) * np.array([1.0, -1.0])
        else:
            tip = inv.transform(origin + d)
            ax.annotate("", tip, xytext=o, arrowprops=dict(arrowstyle="-|>", color="k",
                                                            lw=1.0, shrinkA=0, shrinkB=0,
                                                            mutation_scale=9))
            placer.keep_clear(ax, o, tip)
            at = origin + d * 1.3
        text = ax.text(*inv.transform(at), name, fontsize=8.5, fontweight="bold",
                       ha="center", va="center", zorder=7)
        placer.block(text)


def slip_arrows(ax, placer, view) -> int:
    """An arrow along each slipping contact's slip, from its node."""
    drawn = 0
    for s, c in zip(view.res.supports.values(), view.frame.contacts):
        if s.state != "slip":
            continue
        d = view.project(s.slip_global)[0]
        if np.hypot(*d) <= 1e-3 * np.linalg.norm(s.slip_global):
            continue                      # along the line of sight: the label says it
        at = view.at(c.node)
        tip = placer.offset(ax, at, d, 30.0)
        if placer.arrow(ax, tip, d, 24.0, group="slip", color=SLIP_COLOR, lw=1.6) is not None:
            drawn += 1
    return drawn


def contact_labels(ax, placer, view) -> int:
    """Each contact's name and force (its opening where separated, its slip
    where slipping), beside it on the side of its support."""
    F, L = view.force, view.length
    big = max([s.normal for s in view.res.supports.values()] + [0.0])
    sizes = [max(s.normal, float(np.hypot(*s.slip)) * big / max(view.umax, 1e-300))
             for s in view.res.supports.values()]
    order = np.argsort(sizes)[::-1]
    items = list(zip(view.res.supports.items(), view.frame.contacts))
    shown = 0
    for k in order:
        (key, s), c = items[k]
        if s.state == "separated":
            text = f"{key}: open {value_text(s.opening, L)}"
        else:
            text = f"{key}: X_n {value_text(s.normal, F, big)}"
            if s.state == "slip":
                text += f", slip {value_text(float(np.hypot(*s.slip)), L)}"
        down = -view.project(c.normal)[0]
        if np.hypot(*down) < 0.2:
            down = np.array([1.0, -1.0])
        if placer.label(ax, text, view.at(c.node), around(down, 7.0) + around(down, 16.0),
                        fontsize=_FONT, color="k", bbox=_BOX):
            shown += 1
    return shown


def _has_loads(view) -> bool:
    combo = view.res.combination
    return any(combo.get(case, 0.0) and any(v) for _, v, case in view.frame.nodal_loads) or \
        any(combo.get(ld.case, 0.0) and any(ld.values) for ld in view.frame.span_loads)


def draw_space_loads(ax, placer, view):
    """The combination's nodal forces (one arrow per node, with its value),
    uniform member loads (a band of arrows on the member, one value), point
    loads on members (an arrow where they act) and partial or trapezoidal
    ones (a band over their stretch, its end values); a load along the line
    of sight is a circle (⊙ towards the viewer, ⊗ away)."""
    combo = view.res.combination
    per_node: dict = {}
    for node, v, case in view.frame.nodal_loads:
        f = combo.get(case, 0.0)
        if f:
            per_node[node] = per_node.get(node, np.zeros(6)) + f * np.asarray(v, float)
    for node, v in per_node.items():
        _point_load(ax, placer, view, view.at(node), v)
    for name, m in view.frame.members.items():
        q = np.zeros(3)
        R = member_axes(view.xyz[m["i"]], view.xyz[m["j"]], m["ref"], m["roll"])[0]
        for member, w, axes, case in view.frame.member_loads:
            f = combo.get(case, 0.0)
            if member == name and f:
                q += f * (np.asarray(w) if axes == "global" else R.T @ np.asarray(w))
        if np.any(q):
            _band(ax, placer, view, name, q)
    for ld in view.frame.span_loads:
        f = combo.get(ld.case, 0.0)
        m = view.frame.members[ld.member]
        a, b = view.xyz[m["i"]], view.xyz[m["j"]]
        length = float(np.linalg.norm(b - a))
        if not f or ld.whole_uniform(length):
            continue
        R = member_axes(a, b, m["ref"], m["roll"])[0]
        v = f * np.asarray(ld.values, float)
        v = v if ld.axes == "global" else np.r_[R.T @ v[:3], R.T @ v[3:]]
        if ld.kind == "point":
            _point_load(ax, placer, view, view.member_point(ld.member, ld.a / length), v)
        elif np.any(v):
            _band(ax, placer, view, ld.member, v[:3], (ld.a / length, ld.b / length), v[3:])


def _point_load(ax, placer, view, at, v):
    """A force (an arrow with its value) and a moment (its components) at
    the drawn point ``at``; v = (fx, fy, fz, mx, my, mz), global."""
    F, L = view.force, view.length
    if np.any(v[:3]):
        d, sight = _screen(view, v[:3])
        if sight:
            _sight_mark(ax, at, sight, 9.0)
            placer.label(ax, f"{force_text(v[:3], F)} {sight}", at,
                         around((1.0, 1.0), 7.0), fontsize=_FONT, color=LOAD_COLOR,
                         bbox=_BOX)
        else:
            tail = placer.arrow(ax, at, d, 34.0, back=5.0, group="loads",
                                color=LOAD_COLOR, lw=1.3)
            if tail is not None:
                placer.label(ax, force_text(v[:3], F), tail,
                             around(-d, 6.0) + around(-d, 12.0), fontsize=_FONT,
                             color=LOAD_COLOR, bbox=_BOX)
    if np.any(v[3:]):
        words = ", ".join(value_text(x, "", np.abs(v[3:]).max()) for x in v[3:])
        placer.label(ax, f"M = ({words}) {F}·{L}", at, around((1.0, 1.0), 8.0),
                     fontsize=_FONT, color=LOAD_COLOR, bbox=_BOX)


def _band(ax, placer, view, name, q, stretch=(0.0, 1.0), q2=None):
    """A member load per unit length over the fraction ``stretch`` of the
    member: arrows at five points joined at their tails, one value (or the
    values at its start and end, q then q2, for a trapezoid)."""
    mean = q if q2 is None else 0.5 * (q + q2)
    d, sight = _screen(view, mean if np.any(mean) else q)
    lo, hi = stretch
    spots = [view.member_point(name, s) for s in lo + (hi - lo) * np.linspace(0.1, 0.9, 5)]
    if sight:
        for p in spots:
            _sight_mark(ax, p, sight, 5.0)
        where = spots[2]
        d = np.array([0.0, 1.0])
    else:
        tails = []
        for tip in spots:
            tail = placer.offset(ax, tip, -d, 14.0)
            band_arrow(ax, placer, tip, tail)
            tails.append(tail)
        tails = np.array(tails)
        ax.plot(tails[:, 0], tails[:, 1], color=LOAD_COLOR, lw=0.6)
        placer.keep_clear(ax, tails[0], tails[-1])
        where = tails[2]
    unit = f"{view.force}/{view.length}"
    text = force_text(q, unit) if q2 is None or np.allclose(q, q2, rtol=1e-12, atol=0.0) \
        else f"{force_text(q, unit)} → {force_text(q2, unit)}"
    text += f" {sight}" if sight else ""
    placer.label(ax, text, where, around(-d, 3.5) + around(-d, 8.0), fontsize=_FONT - 0.5,
                 color=LOAD_COLOR, bbox=_BOX)


def _screen(view, vec):
    """(the vector's direction on the screen, "") or, for one along the line
    of sight, (None, "⊙" towards the viewer or "⊗" away from it)."""
    d = view.project(vec)[0]
    if np.hypot(*d) >= 0.2 * np.linalg.norm(vec):
        return d, ""
    return None, "⊙" if np.dot(np.cross(*view.P), vec) > 0 else "⊗"


def _sight_mark(ax, at, sight, size):
    ax.plot(*at, marker="o", ms=size, mfc="none", mec=LOAD_COLOR, mew=1.0, zorder=6)
    ax.plot(*at, marker="." if sight == "⊙" else "x", ms=size * 0.55, color=LOAD_COLOR,
            mew=1.0, zorder=6)


def force_text(v, unit: str) -> str:
    """A force along one global axis: its size (the arrow gives the sense);
    otherwise its global components, "(20, 20, 0) kN"."""
    v = np.asarray(v, float)
    ref = float(np.abs(v).max())
    live = np.abs(v) > 1e-9 * ref
    if live.sum() <= 1:
        return value_text(ref, unit)
    return "(" + ", ".join(value_text(c, "", ref) if k else "0" for c, k in zip(v, live)) + \
        f")\u2009{unit}"


def peak_label(ax, placer, view):
    node = view.peak_node
    u = float(np.linalg.norm(np.asarray(view.res.displacements[node][:3])))
    if view.umax > 0:
        placer.label(ax, f"|u| = {value_text(u, view.length)} at {node}", view.at(node),
                     around((1.0, 1.0), 8.0) + around((1.0, 1.0), 20.0),
                     fontsize=_FONT + 0.5, color="k", fontweight="bold", bbox=_BOX)
