"""Random high-contrast beams on frictionless pads, counted against
independent references (issue 52: no answer called ok out of balance, no
false proof at extreme stiffness contrast).

Each beam: N0 … Nn at 3 m (n = 4 … 6), a pin at N0 (ux, uy), settled
downwards in most beams, frictionless pads at N1 … Nn, vertical loads at
N1 … Nn; its members' E and I scaled by factors 10^U(0, 10) (so EI by up to
1e20), some hinged at their j end (never the last: its end rotation would
be free).  Each is solved twice:

* as it is, by ``Frame.solve()``: ok, "proved" (NoSolutionError), or
  "not ok" (a result that is not ok, or SolverFailedError);
* its contrast-free twin (every factor 1, the same hinges, loads and
  settlement): whether an equilibrium exists depends only on which motions
  strain no member (the kernel of K: the hinges, not the stiffnesses), so
  the twin's verdict — ok or proved — is the reference for existence.

An ok answer is checked in mpmath (50 digits) on its own contact states:
the frame solved with its closed pads held (a stiffness written here, not
the package's), whose pad forces must be the answer's (to 1e-8 of the
largest) and admissible (closed ≥ 0, open pads not below the ground).
Counts: right (ok and checked, or proved where the twin is proved), false
proof (proved where the twin is ok), false ok (ok where the twin is proved,
or an ok answer that fails the check), honest not ok, and no reference
(the twin itself neither ok nor proved).

    .venv/bin/python benchmarks/frame_contrast_census.py            # 200 beams
    .venv/bin/python benchmarks/frame_contrast_census.py --beams 20 --show
"""

from __future__ import annotations

import argparse
import collections
import time
import warnings

import mpmath as mp
import numpy as np

from formulations.frames import Frame
from qpcontact.core.errors import NoSolutionError, SolverFailedError

E, A, I, L = 2e8, 1e-2, 2e-5, 3.0       # kN/m², m², m⁴, m


def draw(seed):
    """One random beam's data: factors, hinges, loads, settlement."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(4, 7))
    factors = 10.0 ** rng.uniform(0.0, 10.0, n)
    hinges = rng.random(n) < 0.3
    hinges[-1] = False
    loads = np.round(rng.uniform(-10.0, 5.0, n), 3)
    settle = -0.01 if rng.random() < 0.7 else 0.0
    return n, factors, hinges, loads, settle


def build(n, factors, hinges, loads, settle):
    fr = Frame()
    for k in range(n + 1):
        fr.add_node(f"N{k}", L * k, 0.0)
    for k in range(n):
        fr.add_member(f"N{k}", f"N{k + 1}", factors[k] * E, A, factors[k] * I,
                      hinge_j=bool(hinges[k]))
    fr.add_support("N0", fix=("ux", "uy"))
    for k in range(1, n + 1):
        fr.add_contact(f"N{k}")
        fr.add_load(f"N{k}", fy=float(loads[k - 1]))
    if settle:
        fr.add_settlement("N0", uy=settle)
    return fr


def verdict(fr):
    """("ok" | "proved" | "not ok", result or None, words)."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = fr.solve()
    except NoSolutionError as exc:
        return "proved", None, str(exc)
    except SolverFailedError as exc:
        return "not ok", None, str(exc)
    return ("ok" if r.ok else "not ok"), r, r.message


def element(f, hinge_j):
    """A level member's stiffness (ux, uy, rz at i and j) in mpmath, E and
    I scaled by f; hinged at j: its end rotation condensed out (3EI/L³)."""
    ea, ei = mp.mpf(f) * E * A / L, mp.mpf(f) * mp.mpf(f) * E * I
    k = mp.zeros(6, 6)
    k[0, 0] = k[3, 3] = ea
    k[0, 3] = k[3, 0] = -ea
    if hinge_j:
        c = 3 * ei / L ** 3
        bend = [[c, c * L, -c], [c * L, c * L * L, -c * L], [-c, -c * L, c]]
        at = [1, 2, 4]
    else:
        c = ei / L ** 3
        bend = [[12 * c, 6 * c * L, -12 * c, 6 * c * L],
                [6 * c * L, 4 * c * L * L, -6 * c * L, 2 * c * L * L],
                [-12 * c, -6 * c * L, 12 * c, -6 * c * L],
                [6 * c * L, 2 * c * L * L, -6 * c * L, 4 * c * L * L]]
        at = [1, 2, 4, 5]
    for a, ra in enumerate(at):
        for bb, rb in enumerate(at):
            k[ra, rb] += bend[a][bb]
    return k


def checked(n, factors, hinges, loads, settle, r):
    """Whether the ok answer ``r`` is the beam's: on its closed pads, the
    frame solved in mpmath; its pad forces the answer's to 1e-8 of the
    largest, closed ones ≥ 0, open pads not below the ground.  Returns
    (True|False, words)."""
    mp.mp.dps = 50
    N = 3 * (n + 1)
    K = mp.zeros(N, N)
    for m in range(n):
        k = element(factors[m], hinges[m])
        d = list(range(3 * m, 3 * m + 6))
        for a in range(6):
            for bb in range(6):
                K[d[a], d[bb]] += k[a, bb]
    F = mp.zeros(N, 1)
    for k in range(1, n + 1):
        F[3 * k + 1] = mp.mpf(float(loads[k - 1]))
    closed = [k for k in range(1, n + 1) if r.supports[f"N{k}"].state == "closed"]
    held = {0: 0.0, 1: settle, **{3 * k + 1: 0.0 for k in closed}}
    free = [i for i in range(N) if i not in held]
    u = mp.zeros(N, 1)
    for i, v in held.items():
        u[i] = mp.mpf(v)
    Kff = mp.matrix([[K[i, j] for j in free] for i in free])
    rhs = mp.matrix([F[i] - sum(K[i, j] * u[j] for j in held) for i in free])
    try:
        x = mp.lu_solve(Kff, rhs)
    except ZeroDivisionError:
        return False, "its closed set leaves a mechanism"
    for a, i in enumerate(free):
        u[i] = x[a]
    react = K * u - F
    want = np.array([float(react[3 * k + 1]) if k in closed else 0.0 for k in range(1, n + 1)])
    got = np.array([r.supports[f"N{k}"].normal for k in range(1, n + 1)])
    big = max(np.abs(want).max(), np.abs(loads).max())
    lift = [float(u[3 * k + 1]) for k in range(1, n + 1) if k not in closed]
    if want.min(initial=0.0) < -1e-9 * big:
        return False, f"a closed pad pulls ({want.min():.3g})"
    if lift and min(lift) < -1e-9:
        return False, f"an open pad is below the ground ({min(lift):.3g} m)"
    off = np.abs(got - want).max() / big
    return off <= 1e-8, f"pad forces {off:.1e} of the largest off"


def census(beams, show):
    counts = collections.Counter()
    cpu = time.process_time()
    for seed in range(beams):
        n, factors, hinges, loads, settle = draw(seed)
        got, res, words = verdict(build(n, factors, hinges, loads, settle))
        ref, _, ref_words = verdict(build(n, np.ones(n), hinges, loads, settle))
        if ref == "not ok":
            kind = "no reference"
        elif got == "not ok":
            kind = "honest not ok"
        elif got == "proved":
            kind = "right" if ref == "proved" else "FALSE PROOF"
        elif ref == "proved":
            kind = "FALSE OK"
        else:
            good, why = checked(n, factors, hinges, loads, settle, res)
            kind, words = ("right", words) if good else ("FALSE OK", why + "; " + words)
        counts[kind] += 1
        if show or kind.isupper() or kind == "no reference":
            print(f"seed {seed:3d}: {kind:13s} as built {got:6s} twin {ref:6s} "
                  f"contrast {factors.max() / factors.min():.0e} settle {settle}: "
                  f"{words[:160]}")
    print(dict(counts), f"CPU {time.process_time() - cpu:.1f} s")
    return counts


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--beams", type=int, default=200)
    ap.add_argument("--show", action="store_true", help="a line per beam")
    args = ap.parse_args()
    census(args.beams, args.show)
