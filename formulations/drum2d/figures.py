"""The 2-D drum's standard figures, drawn from a results file alone (an open
h5py.File written by the drum2d scene): a snapshot of the cross-section with
its force chains, and the energy balance over time.  SI units on the axes
(m, s, J, N)."""

from __future__ import annotations

import numpy as np

__all__ = ["snapshot_figure", "energy_figure"]


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def snapshot_figure(h, step: int | None = None):
    """The cross-section at state ``step`` (default: the last): shell, lifters,
    discs, and a line per active contact of the step before it — centre to
    centre between discs, centre to contact point at a wall — of width ∝ its
    normal force (impulse / h [N])."""
    from matplotlib.collections import LineCollection, PatchCollection
    from matplotlib.patches import Circle, Polygon

    plt = _pyplot()
    t, pos, diam = h["t"][()], h["positions"][()], h["diameters"][()]
    S = len(t) - 1
    k = S if step is None else int(step)
    R, omega = float(h["drum/radius"][()]), float(h["drum/omega"][()])
    lh, lb = float(h["drum/lifter_height"][()]), float(h["drum/lifter_half_width"][()])
    fig, ax = plt.subplots(figsize=(7.2, 7.0))
    ax.add_patch(Circle((0, 0), R, fill=False, lw=2.0, color="0.2"))
    for a in h["drum/lifter_angles"][()] + omega * t[k]:
        u, n = np.array([np.cos(a), np.sin(a)]), np.array([-np.sin(a), np.cos(a)])
        p0, p1 = (R - lh) * u, R * u
        ax.add_patch(Polygon([p0 - lb * n, p1 - lb * n, p1 + lb * n, p0 + lb * n],
                             color="0.35"))
    q = pos[k]
    ax.add_collection(PatchCollection([Circle(c, 0.5 * d) for c, d in zip(q, diam)],
                                      facecolor="#E69F00", edgecolor="#8a5a00", lw=0.6,
                                      alpha=0.55))
    rows = np.flatnonzero(h["contacts/step"][()] == k - 1) if k > 0 else np.zeros(0, int)
    fmax = 0.0
    if rows.size:
        i, j = h["contacts/i"][()][rows], h["contacts/j"][()][rows]
        F = h["contacts/force_n"][()][rows]
        nrm = h["contacts/normal"][()][rows]
        a = q[i]
        b = np.where((j >= 0)[:, None], q[np.maximum(j, 0)], a - 0.5 * diam[i][:, None] * nrm)
        fmax = float(F.max(initial=0.0))
        if fmax > 0:
            width = 0.3 + 4.0 * F / fmax
            keep = F > 0
            ax.add_collection(LineCollection(np.stack([a, b], 1)[keep], linewidths=width[keep],
                                             colors="#0072B2"))
    ax.plot([], [], color="#0072B2", lw=4.3,
            label=f"contact force (width ∝ force; widest {fmax / 1e3:.3g} kN)")
    ax.set_xlim(-1.08 * R, 1.08 * R)
    ax.set_ylim(-1.08 * R, 1.18 * R)
    ax.set_aspect("equal")
    ax.set(xlabel="x [m]", ylabel="y [m]")
    turns = omega * t[k] / (2 * np.pi)
    ax.set_title(f"Drum cross-section at t = {t[k]:.3g} s ({turns:.2f} rev), "
                 f"{len(diam)} logs", fontsize=10)
    ax.legend(loc="upper center", fontsize=8, frameon=False)
    fig.tight_layout()
    return fig


def energy_figure(h):
    """Cumulative energy balance [J] against time [s]: the drive's work, the
    change of kinetic + potential (+ the springs') energy, the friction and
    impact losses (above); the numerical remainder, ΔK + ΔP + ΔE_el − drive +
    losses (below)."""
    plt = _pyplot()
    t = h["t"][()]
    K, P = h["energy/kinetic"][()], h["energy/potential"][()]
    if "energy/elastic" in h:      # the contact springs (log/shell elasticity)
        P = P + h["energy/elastic"][()]
    cum = {k: np.concatenate([[0.0], np.cumsum(h[f"energy/{k}"][()])])
           for k in ("drive", "friction_loss", "impact_loss", "remainder")}
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(8.5, 6.4), sharex=True,
                                 gridspec_kw={"height_ratios": (2.2, 1)})
    ax.plot(t, cum["drive"], color="#0072B2", lw=1.6, label="work of the drive")
    springs = "energy/elastic" in h and np.any(h["energy/elastic"][()])
    ax.plot(t, K + P - K[0] - P[0], color="#000000", ls="--", lw=1.4,
            label="kinetic + potential" + (" + elastic" if springs else "") + " (change)")
    named = "friction" in str(h.attrs.get("effects", ""))
    ax.plot(t, cum["friction_loss"], color="#D55E00", ls="-.", lw=1.4,
            label="friction loss" + ("" if named else " (friction not simulated)"))
    ax.plot(t, cum["impact_loss"], color="#009E73", ls=":", lw=1.8, label="impact loss")
    scheme = h["energy/scheme"][()] if "energy/scheme" in h else np.zeros(len(t) - 1)
    if np.any(scheme):     # θ = 1 positions (with springs): the time scheme's own loss
        ax.plot(t, -np.concatenate([[0.0], np.cumsum(scheme)]), color="#E69F00", lw=1.2,
                label="time scheme's loss (θ = 1 positions)")
    ax.set_ylabel("energy since t = 0 [J]")
    ax.set_title("Energy balance: drive work = change of K + P + losses", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    big = float(np.abs(cum["remainder"]).max(initial=0.0))
    e = int(np.floor(np.log10(big))) if big > 0 else 0
    # the power of ten goes in the label: matplotlib's offset text would sit on the title
    bx.plot(t, cum["remainder"] / 10.0 ** e, color="#CC79A7", lw=1.2)
    from matplotlib.ticker import MaxNLocator
    bx.yaxis.set_major_locator(MaxNLocator(4))
    bx.ticklabel_format(axis="y", useOffset=False)
    bx.set(xlabel="time [s]", ylabel="remainder [J]" if e == 0 else f"remainder [1e{e} J]")
    bx.set_title("numerical remainder (rounding and certificate residual)", fontsize=9)
    bx.grid(True, alpha=0.3)
    fig.tight_layout(h_pad=2.5)   # the panels' end tick labels otherwise touch
    return fig
