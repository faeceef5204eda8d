"""Seeded problems with no solution, each with its certificate planted in
small integers (so that the certificate holds exactly in floating point and
a test can check a proof against it by hand):

* :func:`farkas_lcp` — LCP(M, q) with a planted y >= 0, M'y <= 0, q'y < 0:
  ``"psd"`` M = B B' with B'y = 0 (symmetric PSD, singular; every Farkas
  vector has M y = 0), ``"general"`` a dense nonsymmetric M, ``"row"`` one
  row of M with no positive entry beside q_i < 0 (y = e_i) hidden among
  random rows;
* :func:`ray_qp` — a convex QP with a planted ray: P = B B' with B'd = 0,
  G d <= -1, q'd < 0, x = 0 feasible.

Built here, independently of qpcontact.cases, from the definitions alone."""

from __future__ import annotations

import numpy as np
from qpsolvers import Problem

from qpcontact import LCP

KINDS = ("psd", "general", "row")


def farkas_lcp(n: int, seed: int, kind: str = "general"):
    """(LCP, y): an infeasible LCP and its planted Farkas vector."""
    rng = np.random.default_rng([seed, n, KINDS.index(kind)])
    if kind == "psd":
        y = rng.integers(1, 4, n).astype(float)
        y[-1] = 1.0
        B = rng.integers(-3, 4, (n, n - 1)).astype(float)
        B[-1] = -(y[:-1] @ B[:-1])
        q = rng.integers(-5, 6, n).astype(float)
        q[-1] -= (q @ y) + rng.integers(1, 4)
        return LCP(B @ B.T, q), y
    if kind == "row":
        M = rng.standard_normal((n, n))
        q = rng.standard_normal(n)
        i = int(rng.integers(n))
        M[i] = -rng.uniform(0.1, 1.0, n)
        q[i] = -rng.uniform(0.1, 1.0)
        y = np.zeros(n)
        y[i] = 1.0
        return LCP(M, q), y
    y = np.zeros(n)
    support = rng.choice(n, size=max(2, n // 2), replace=False)
    y[support] = rng.integers(1, 4, support.size)
    M = rng.integers(-5, 6, (n, n)).astype(float)
    k = support[0]
    rest = y.copy()
    rest[k] = 0.0
    # row k makes M'y = -s with s >= 0 (floor keeps it <= -s)
    M[k] = np.floor((-(rest @ M) - rng.integers(0, 3, n)) / y[k])
    q = rng.integers(-5, 6, n).astype(float)
    q[k] = np.floor((-(q @ rest) - rng.integers(1, 4)) / y[k])
    return LCP(M, q), y


def ray_qp(n: int, seed: int):
    """(Problem, d): an unbounded convex QP and its planted ray."""
    rng = np.random.default_rng([seed, n, 7])
    d = rng.integers(-2, 3, n).astype(float)
    d[-1] = 1.0
    B = rng.integers(-3, 4, (n, n)).astype(float)
    B[-1] = -(d[:-1] @ B[:-1])
    G = rng.integers(-3, 4, (n, n)).astype(float)
    G[:, -1] = -(G[:, :-1] @ d[:-1]) - rng.integers(1, 4, n)
    h = rng.integers(1, 5, n).astype(float)
    q = rng.integers(-5, 6, n).astype(float)
    q[-1] -= (q @ d) + rng.integers(1, 4)
    return Problem(B @ B.T, q, G, h), d
