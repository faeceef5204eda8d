"""What makes a figure read at a glance: a colour and a marker per method
(Okabe–Ito's colour-blind-safe palette, so no two methods differ by colour
alone), a labelled band for exact zeros on a log axis, and log-axis ticks
thinned until their rendered labels do not touch."""

from __future__ import annotations

import math

__all__ = ["OKABE_ITO", "MARKERS", "method_styles", "ink", "zero_band_position", "draw_zero_band",
           "readable_log_ticks", "overlapping_tick_labels"]

#: Okabe & Ito (2008), "Color Universal Design": distinguishable under the
#: common colour-vision deficiencies.  Yellow last: it is the palest on white.
OKABE_ITO = ("#0072B2", "#E69F00", "#009E73", "#D55E00", "#CC79A7", "#56B4E9", "#000000",
             "#F0E442")
#: Seven filled markers (fill styles still apply): seven is prime to the eight
#: colours, so (colour, marker) repeats only after 56 methods.
MARKERS = ("o", "s", "^", "D", "v", "P", "X")


def method_styles(names) -> dict:
    """{name: (colour, marker)}, distinct pairs for up to 56 names, in the
    order given (pass every method of a report, so a method looks the same in
    each of its figures)."""
    names = list(dict.fromkeys(names))
    if len(names) > len(OKABE_ITO) * len(MARKERS):
        raise ValueError(f"{len(names)} methods: at most {len(OKABE_ITO) * len(MARKERS)} get "
                         "distinct colour-and-marker pairs; plot fewer methods per figure")
    return {n: (OKABE_ITO[k % len(OKABE_ITO)], MARKERS[k % len(MARKERS)])
            for k, n in enumerate(names)}


def ink(colour: str) -> str:
    """The colour for thin strokes (lines, marker edges, hollow markers): the
    colour itself, darkened where it is too pale to see as a line on white
    (Okabe–Ito's yellow)."""
    from matplotlib.colors import to_hex, to_rgb

    r, g, b = to_rgb(colour)
    if 0.2126 * r + 0.7152 * g + 0.0722 * b <= 0.75:    # yellow 0.86; orange, sky blue 0.65
        return colour
    return to_hex((0.6 * r, 0.6 * g, 0.6 * b))


def zero_band_position(positives) -> float:
    """Where exact zeros go on a log axis: a whole decade below the smallest
    positive value (1e-16 when there is none), so they cannot be read as one."""
    lo = min((v for v in positives if v > 0 and math.isfinite(v)), default=1e-16)
    return 10.0 ** (math.floor(math.log10(lo)) - 1)


def draw_zero_band(ax, y0: float, label: str = "exact (0)") -> None:
    """Shade the strip around ``y0`` on ``ax``'s log y axis and name it
    ``label`` on the axis (call after the other y ticks are set: the band's
    tick joins them and the limits are widened to hold it)."""
    lo, hi = y0 / 10 ** 0.6, y0 * 10 ** 0.5
    ax.axhspan(lo, hi, color="0.92", zorder=0)
    ax.axhline(hi, color="0.55", lw=0.8, zorder=0.5)
    ticks = [t for t in ax.get_yticks() if t > hi]
    labels = [t.get_text() for t, v in zip(ax.get_yticklabels(), ax.get_yticks()) if v > hi]
    ax.set_yticks([y0] + ticks, [label] + labels)
    ax.set_ylim(lo, max(ax.get_ylim()[1], hi * 10))


def _decade_label(v: float) -> str:
    k = round(math.log10(v))
    return f"$10^{{{k}}}$" if abs(v / 10.0 ** k - 1) < 1e-9 else f"{v:g}"


def _plain_label(v: float) -> str:
    return f"{v:g}" if 1e-3 <= v < 1e5 else _decade_label(v)


def _candidates(lo: float, hi: float, subs, every: int = 1):
    k0, k1 = math.floor(math.log10(lo)), math.ceil(math.log10(hi))
    return [m * 10.0 ** k for k in range(k0, k1 + 1) if (k - k0) % every == 0 for m in subs
            if lo <= m * 10.0 ** k <= hi]


def readable_log_ticks(ax, axis: str = "x", plain: bool = True, pad_px: float = 4.0) -> None:
    """Major ticks of ``ax``'s log ``axis`` from the densest readable set
    (``plain``: 1-2-5 per decade, then 1-3; then every decade, every 2nd, ...):
    the first whose labels keep ``pad_px`` apart, measured by the renderer
    at their tick positions; minor labels off.  ``plain``: labels as
    numbers (0.5, 20) between 1e-3 and 1e5, else powers of ten.  Call once
    the limits and the axes' place in the figure are final."""
    from matplotlib.ticker import NullFormatter

    lo, hi = sorted(ax.get_xlim() if axis == "x" else ax.get_ylim())
    fmt = _plain_label if plain else _decade_label
    # powers of ten only where labels are powers of ten: "3e-06" beside "10^-6" reads badly
    sets = [_candidates(lo, hi, (1, 2, 5)), _candidates(lo, hi, (1, 3))] if plain else []
    sets += [_candidates(lo, hi, (1,), every) for every in range(1, 8)]
    sets = [t for t in sets if len(t) >= 2] or [_candidates(lo, hi, (1, 2, 5))]
    chosen = next((t for t in sets if not _would_touch(ax, axis, t, [fmt(v) for v in t], pad_px)),
                  sets[-1][:1] + sets[-1][-1:])
    (ax.set_xticks if axis == "x" else ax.set_yticks)(chosen, [fmt(t) for t in chosen])
    (ax.set_xlim if axis == "x" else ax.set_ylim)(lo, hi)
    (ax.xaxis if axis == "x" else ax.yaxis).set_minor_formatter(NullFormatter())


def _would_touch(ax, axis: str, ticks, labels, pad_px: float) -> bool:
    """Whether labels at these ticks would come within ``pad_px`` of each
    other: their sizes from the renderer, their centres from the axes'
    transform (x labels centred under their ticks, y labels beside theirs),
    with no full draw of the figure."""
    renderer = ax.figure.canvas.get_renderer()
    prop = (ax.xaxis if axis == "x" else ax.yaxis).get_major_ticks()[0].label1.get_fontproperties()
    k = 0 if axis == "x" else 1
    pts = [(t, 1.0) if axis == "x" else (1.0, t) for t in ticks]
    centres = ax.transData.transform(pts)[:, k]
    sizes = [renderer.get_text_width_height_descent(s, prop, ismath="$" in s)[k] for s in labels]
    order = sorted(range(len(ticks)), key=lambda i: centres[i])
    return any(centres[j] - centres[i] < (sizes[i] + sizes[j]) / 2 + pad_px
               for i, j in zip(order, order[1:]))


def overlapping_tick_labels(ax, axis: str = "x", pad_px: float = 0.0) -> list:
    """Pairs of ``ax``'s visible ``axis`` tick labels, major and minor, whose
    rendered boxes, widened by ``pad_px``, intersect (the figure is drawn
    first, without rendering, so the labels hold their final text and place)."""
    fig = ax.figure
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    lim = sorted(ax.get_xlim() if axis == "x" else ax.get_ylim())
    which = ax.xaxis if axis == "x" else ax.yaxis
    boxes = []
    for ticks, locs in ((which.get_major_ticks(), which.get_majorticklocs()),
                        (which.get_minor_ticks(), which.get_minorticklocs())):
        for tick, loc in zip(ticks, locs):
            label = tick.label1
            if label.get_visible() and label.get_text() and lim[0] <= loc <= lim[1]:
                boxes.append((label.get_text(), label.get_window_extent(renderer).padded(pad_px)))
    return [(a, b) for i, (a, ba) in enumerate(boxes) for b, bb in boxes[i + 1:]
            if ba.overlaps(bb)]
