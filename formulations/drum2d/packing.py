r"""A dense fill of the drum: discs deposited one by one at the lowest place
they can reach from above.

SI units: m.

The hexagonal lattice (geometry.hex_fill) spaces every site by the largest
diameter, so a fill of mixed diameters covers at most 0.907 E[d²]/d_max² of
the area it takes (0.49 for 0.12–0.28 m logs): 120 such logs do not fit a
3.5 m drum that holds them loosely.  Here each disc, in the order given (the
diameters as drawn, so sizes mix), is dropped vertically at every abscissa x
of a grid across the drum and lands at

    y(x) = max( −√((R − r − c)² − x²),                       the shell's floor
                max_j  y_j + √((r + r_j + c)² − (x − x_j)²) )  on disc j, |x − x_j| < r + r_j + c

(c the clearance); it is placed at the x where y(x) is lowest — a valley
between two discs or a disc and the shell — refined on a grid 20 times finer
around the best coarse point, provided it lies inside the shell
(|centre| ≤ R − r − c) and clear of every lifter capsule (distance to the
bar's segment ≥ r + b + c).  Every placement keeps the gaps ≥ c by
construction (checked at the end), so the fill has no overlap; it is a
deposit, not a settled pile: discs rest on one or two others, the bed's
surface is uneven by up to a diameter, and the stepper settles it in the
first steps.  The packing fraction of such deposits is about 0.8 for mixed
diameters against the lattice's 0.49 above.

Cost: O(G n) per disc for G grid points and n discs placed, O(G n²) in all
(G = 400: 500 logs in about a second).
"""

from __future__ import annotations

import numpy as np

from qpcontact.core.errors import InvalidProblemError

__all__ = ["deposit_fill"]

#: abscissae of the coarse grid across the drum
GRID = 400
#: the fine grid's points around the best coarse abscissa (±1 coarse step)
FINE = 41


def _landing(x, r, c, R, placed, radii):
    """y(x) (module docstring) at the abscissae x for a disc of radius r."""
    reach = R - r - c
    y = -np.sqrt(np.maximum(reach * reach - x * x, 0.0))
    if placed.shape[0]:
        dx = x[:, None] - placed[None, :, 0]
        s = r + radii[None, :] + c
        over = s * s - dx * dx
        top = np.where(over > 0, placed[None, :, 1] + np.sqrt(np.maximum(over, 0.0)), -np.inf)
        y = np.maximum(y, top.max(axis=1))
    return y


def _clear(points, r, c, R, segments, half_width):
    """Which candidate centres lie inside the shell and clear of the lifters."""
    ok = np.hypot(points[:, 0], points[:, 1]) <= R - r - c + 1e-12 * R
    for a, b in segments:
        ab = b - a
        s = np.clip((points - a) @ ab / (ab @ ab), 0.0, 1.0)
        dist = np.hypot(*(points - (a + s[:, None] * ab)).T)
        ok &= dist >= r + half_width + c
    return ok


def deposit_fill(radius: float, diameters, *, clearance: float = 0.0, lifters=(),
                 half_width: float = 0.0) -> np.ndarray:
    """Centres (n, 2) [m] of discs of ``diameters`` (n,) [m], in that order,
    deposited in a shell of ``radius`` R [m] (module docstring), ``clearance``
    c [m] the least gap kept, ``lifters`` a sequence of (inner, outer) end
    points (2,) of the lifter bars' segments at t = 0 and ``half_width`` b [m]
    their capsules' radius.  Raises InvalidProblemError naming how many fit
    when one does not."""
    d = np.asarray(diameters, float)
    R, c = float(radius), float(clearance)
    if not (np.all(np.isfinite(d)) and np.all(d > 0)):
        raise InvalidProblemError("the diameters must be finite and > 0 [m]")
    if not (np.isfinite(c) and c >= 0):
        raise InvalidProblemError(f"the clearance must be finite and >= 0 [m]; got {c}")
    segments = [(np.asarray(a, float), np.asarray(b, float)) for a, b in lifters]
    n = d.size
    pos = np.zeros((n, 2))
    step = 2.0 * R / GRID
    for k in range(n):
        r = 0.5 * d[k]
        reach = R - r - c
        if reach <= 0:
            raise InvalidProblemError(f"a disc of diameter {d[k]:.3g} m does not fit a shell "
                                      f"of radius {R} m")
        best = None
        xs = np.linspace(-reach, reach, GRID + 1)
        ys = _landing(xs, r, c, R, pos[:k], 0.5 * d[:k])
        ok = _clear(np.column_stack([xs, ys]), r, c, R, segments, half_width)
        if np.any(ok):
            i = int(np.flatnonzero(ok)[np.argmin(ys[ok])])
            fine = np.clip(np.linspace(xs[i] - step, xs[i] + step, FINE), -reach, reach)
            yf = _landing(fine, r, c, R, pos[:k], 0.5 * d[:k])
            okf = _clear(np.column_stack([fine, yf]), r, c, R, segments, half_width)
            j = int(np.flatnonzero(okf)[np.argmin(yf[okf])]) if np.any(okf) else None
            best = (fine[j], yf[j]) if j is not None else (xs[i], ys[i])
        if best is None:
            raise InvalidProblemError(
                f"{n} discs do not fit a shell of radius {R} m by deposition: room for {k} "
                f"(the {k + 1}th, of diameter {d[k]:.3g} m, finds no place inside the shell "
                "and clear of the lifters); give fewer logs or a lower fill_fraction")
        pos[k] = best
    _check(pos, d, c, R)
    return pos


def _check(pos, d, c, R):
    """No overlap, all inside (the construction's promise, checked)."""
    from scipy.spatial import cKDTree

    if pos.shape[0] > 1:
        pairs = cKDTree(pos).query_pairs(d.max() + c, output_type="ndarray")
        if pairs.size:
            gap = (np.hypot(*(pos[pairs[:, 0]] - pos[pairs[:, 1]]).T)
                   - 0.5 * (d[pairs[:, 0]] + d[pairs[:, 1]]))
            if gap.min() < c - 1e-9 * R:
                raise AssertionError(f"deposit_fill overlapped two discs by {c - gap.min():.3g} m")
    if np.any(np.hypot(*pos.T) + 0.5 * d > R - c + 1e-9 * R):
        raise AssertionError("deposit_fill put a disc across the shell")
