r"""An animation of the 2-D drum's cross-section with its force chains, drawn
from a results file alone (an open h5py.File written by the drum2d scene).

Each frame is figures.draw_cross_section at one state k: the shell and
lifters turned to Ω t_k, the logs at their positions, and a line per active
contact of step k − 1 (centre to centre, or centre to the wall's contact
point) of width ∝ its normal force (impulse / h [N]), on one scale for all
frames so that widths compare between frames: the 99th percentile of the
forces drawn gets the full width, stronger ones (an impact) up to 1.5 times.

Which states: those after the steps whose contacts were kept (the scene's
``contacts_every``), so every frame shows its force chains; a file that kept
no contacts gives frames of the motion alone.  ``stride`` takes every
stride-th of them (default: as few as keep at most ``max_frames``), or with
``interval`` [s] (the scene's ``[output] frame_interval``) each frame the
first kept state at least the interval after the one before, so that the
frames are that far apart in simulated time — exactly where the interval
is a multiple of the kept steps' spacing, else up to one spacing more;
``max_frames`` caps the count — an animation is a
look, not a record.

Output: PNG frames ``frame_0000.png``, ... in a folder (always), and a movie
beside them when a writer is installed: a GIF through Pillow (what
matplotlib's PillowWriter uses; a matplotlib dependency, so nearly always
there) from the very pixels of the PNG frames — each frame is rendered once —
else an MP4 through ffmpeg (matplotlib's FFMpegWriter); without either the
frames alone, and ``Animation.message`` says why.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from qpcontact.core.errors import InvalidOptionError

from .figures import cross_section_data, draw_cross_section

__all__ = ["Animation", "animation_states", "write_animation"]


@dataclass
class Animation:
    """What write_animation wrote: ``frames`` (PNG paths), ``movie`` (the
    GIF/MP4 path, or None), ``states`` (the state index of each frame) and a
    ``message`` (why there is no movie, else empty)."""

    frames: list
    movie: str | None
    states: np.ndarray
    message: str = ""


def animation_states(h, stride: int | None = None, max_frames: int = 60,
                     interval: float | None = None) -> np.ndarray:
    """The states drawn (module docstring): after each kept step (every state
    when none was kept), every ``stride``-th, or with ``interval`` [s] from
    the first, each the first kept state at least ``interval`` after the
    frame before; at most ``max_frames``."""
    if int(max_frames) < 1 or (stride is not None and int(stride) < 1):
        raise InvalidOptionError(f"max_frames and stride must be >= 1; got {max_frames}, "
                                 f"{stride}")
    if interval is not None and stride is not None:
        raise InvalidOptionError("give stride or interval, not both")
    if interval is not None and not (np.isfinite(interval) and interval > 0):
        raise InvalidOptionError(f"the frame interval must be a finite time > 0 [s]; got "
                                 f"{interval}")
    kept = np.unique(h["contacts/step"][()]).astype(np.int64) + 1
    states = kept if kept.size else np.arange(len(h["t"]))
    if interval is not None:
        t = np.asarray(h["t"][()], float)[states]
        picked = [0]
        while len(picked) < int(max_frames):
            # a hair of rounding: a state at t + interval − 1e-12 s is far enough
            k = int(np.searchsorted(t, t[picked[-1]] + interval * (1 - 1e-9)))
            if k >= t.size:
                break
            picked.append(k)
        return states[picked]
    if stride is None:
        stride = int(np.ceil(states.size / max_frames))
    return states[::int(stride)][:int(max_frames)]


def _movie_writer(movie: str, fps: int):
    """(writer, suffix, message) for ``movie`` in auto/gif/mp4/none; writer
    "pillow" for a GIF (the frames' own pixels, saved by Pillow: each frame
    rendered once), or a matplotlib writer for an MP4."""
    from matplotlib import animation

    if movie == "none":
        return None, "", "no movie asked for (movie='none')"
    if movie in ("auto", "gif") and animation.writers.is_available("pillow"):
        return "pillow", ".gif", ""
    if movie in ("auto", "mp4") and animation.writers.is_available("ffmpeg"):
        return animation.FFMpegWriter(fps=fps), ".mp4", ""
    need = {"gif": "Pillow (pip install pillow)", "mp4": "ffmpeg on the PATH"}.get(
        movie, "Pillow (pip install pillow) for a GIF or ffmpeg on the PATH for an MP4")
    return None, "", f"no movie written: {need} is not available; the PNG frames are there"


def write_animation(h, folder, *, stride: int | None = None, max_frames: int = 60,
                    fps: int = 8, dpi: int = 80, movie: str = "auto",
                    name: str = "animation", interval: float | None = None) -> Animation:
    """Frames of the cross-section with force chains (module docstring) as
    PNGs in ``folder`` and, with ``movie`` "auto" (GIF, else MP4), "gif" or
    "mp4", a movie ``name``.gif/.mp4 beside the folder; "none" for frames
    only.  ``fps`` frames per second, ``dpi`` of frames and movie;
    ``interval`` [s] the simulated time between frames (animation_states)."""
    if movie not in ("auto", "gif", "mp4", "none"):
        raise InvalidOptionError(f"movie must be auto, gif, mp4 or none; got {movie!r}")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    states = animation_states(h, stride, max_frames, interval)
    data = cross_section_data(h)
    shown = np.isin(data["step"], states - 1)
    # one scale for all frames, robust to a single impact: the 99th percentile
    # of the drawn forces gets the full width (stronger ones up to 1.5 times)
    drawn = data["force_n"][shown]
    fmax = float(np.percentile(drawn[drawn > 0], 99)) if np.any(drawn > 0) else 0.0
    folder = os.fspath(folder)
    os.makedirs(folder, exist_ok=True)
    for old in os.listdir(folder):       # a longer earlier animation's frames
        if old.startswith("frame_") and old.endswith(".png"):
            os.remove(os.path.join(folder, old))
    writer, suffix, message = _movie_writer(movie, fps)
    path = os.path.join(os.path.dirname(os.path.abspath(folder)), name + suffix) if writer \
        else None
    fig, ax = plt.subplots(figsize=(5.6, 5.9), dpi=dpi)
    frames, images = [], []
    part = path + ".part" + suffix if path else None
    try:
        if writer not in (None, "pillow"):
            writer.setup(fig, part, dpi=dpi)
        t, turns = data["t"], data["omega"] / (2 * np.pi)
        added = []
        for n, k in enumerate(states):
            for artist in added:      # the axes, ticks and labels stay: cheap frames
                artist.remove()
            _, added = draw_cross_section(ax, data, int(k), fmax)
            ax.set_title(f"t = {t[k]:.3f} s ({turns * t[k]:.2f} rev); line width ∝ contact "
                         f"force,\nfull width at {fmax / 1e3:.3g} kN (99 % of the forces "
                         "shown are below)", fontsize=9)
            if n == 0:
                fig.tight_layout()
            frames.append(os.path.join(folder, f"frame_{n:04d}.png"))
            if writer == "pillow":    # one rendering for the PNG and the GIF's frame
                from PIL import Image

                fig.canvas.draw()
                img = Image.frombuffer("RGBA", fig.canvas.get_width_height(),
                                       fig.canvas.buffer_rgba(), "raw", "RGBA", 0, 1)
                img = img.convert("RGB")
                img.save(frames[-1])
                images.append(img)
            else:
                fig.savefig(frames[-1], dpi=dpi)
                if writer is not None:
                    writer.grab_frame()
        if writer == "pillow":
            images[0].save(part, save_all=True, append_images=images[1:],
                           duration=int(1000 / fps), loop=0)
        elif writer is not None:
            writer.finish()
        if part:
            os.replace(part, path)
    finally:
        plt.close(fig)
        if part and os.path.exists(part):
            os.remove(part)
    return Animation(frames, path, states, message)
