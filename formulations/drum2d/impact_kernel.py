"""The compiled inner loop of formulations.drum2d.impacts: a resolved
(sub-stepped) run of one impact cluster — linear spring–dashpot normal
forces, Coulomb friction regularized by a stiff viscous law, the discs'
spins.  SI units: m, s, kg, N.  Imported only by the function that calls it,
so that importing the drum does not load numba."""

from __future__ import annotations

import numpy as np

from qpcontact.core.compiled import njit

__all__ = ["cluster_peaks"]


@njit
def _forces(pos, vel, spin, gap_lin, inv_m, inv_i, g, radii, a, b, kind, normal, wn, wt, stiff,
            eta, mu, gam, R, acc, alpha, F):
    nd = pos.shape[0]
    for d in range(nd):
        acc[d, 0] = 0.0
        acc[d, 1] = -g
        alpha[d] = 0.0
    for k in range(a.size):
        i = a[k]
        j = b[k]
        if kind[k] == 0:
            dx, dy = pos[i, 0] - pos[j, 0], pos[i, 1] - pos[j, 1]
            dist = np.sqrt(dx * dx + dy * dy)
            nx, ny = dx / dist, dy / dist
            over = radii[i] + radii[j] - dist
            rvx, rvy = vel[i, 0] - vel[j, 0], vel[i, 1] - vel[j, 1]
            un = nx * rvx + ny * rvy
            ut = -ny * rvx + nx * rvy - radii[i] * spin[i] - radii[j] * spin[j]
        elif kind[k] == 1:
            dist = np.sqrt(pos[i, 0] ** 2 + pos[i, 1] ** 2)
            nx, ny = -pos[i, 0] / dist, -pos[i, 1] / dist
            over = dist + radii[i] - R
            un = nx * vel[i, 0] + ny * vel[i, 1]
            ut = -ny * vel[i, 0] + nx * vel[i, 1] - radii[i] * spin[i] + wt[k]
        else:
            nx, ny = normal[k, 0], normal[k, 1]
            over = -gap_lin[k]
            un = nx * vel[i, 0] + ny * vel[i, 1] + wn[k]
            ut = -ny * vel[i, 0] + nx * vel[i, 1] - radii[i] * spin[i] + wt[k]
        f = 0.0
        ft = 0.0
        if over > 0.0:
            f = stiff[k] * over - eta[k] * un
            if f < 0.0:
                f = 0.0
            ft = -gam[k] * ut
            cap = mu[k] * f
            if ft > cap:
                ft = cap
            elif ft < -cap:
                ft = -cap
        F[k] = f
        fx, fy = f * nx - ft * ny, f * ny + ft * nx
        acc[i, 0] += fx * inv_m[i]
        acc[i, 1] += fy * inv_m[i]
        alpha[i] -= radii[i] * ft * inv_i[i]
        if kind[k] == 0:
            acc[j, 0] -= fx * inv_m[j]
            acc[j, 1] -= fy * inv_m[j]
            alpha[j] -= radii[j] * ft * inv_i[j]


@njit
def cluster_peaks(pos, vel, spin, gap_lin, inv_m, inv_i, g, radii, a, b, kind, normal, wn, wt,
                  stiff, eta, mu, gam, R, tau, steps):
    """Velocity Verlet over ``steps`` sub-steps of ``tau``: discs at ``pos``,
    ``vel`` (nd, 2), ``spin`` (nd,); contact k from disc a[k] to disc b[k]
    (kind 0), the shell of radius R (1) or a lifter (2: gap ``gap_lin``
    advanced along the fixed ``normal``, the wall's velocity terms ``wn``,
    ``wt``); normal force max(0, stiff δ − eta u_N) where the overlap δ > 0,
    tangential −gam u_T capped at mu times it.  The velocity-dependent forces
    at the end of a sub-step use the velocity predicted with the last
    acceleration (the half-step velocity would lag: first order).  Returns
    each contact's largest normal force [N]."""
    nd, m = pos.shape[0], a.size
    acc, pred, F, peak = np.zeros((nd, 2)), np.zeros((nd, 2)), np.zeros(m), np.zeros(m)
    alpha, spred = np.zeros(nd), np.zeros(nd)
    pos, vel, spin, gap_lin = pos.copy(), vel.copy(), spin.copy(), gap_lin.copy()
    _forces(pos, vel, spin, gap_lin, inv_m, inv_i, g, radii, a, b, kind, normal, wn, wt, stiff,
            eta, mu, gam, R, acc, alpha, F)
    for k in range(m):
        peak[k] = F[k]
    for _ in range(steps):
        for d in range(nd):
            vel[d, 0] += 0.5 * tau * acc[d, 0]
            vel[d, 1] += 0.5 * tau * acc[d, 1]
            spin[d] += 0.5 * tau * alpha[d]
            pos[d, 0] += tau * vel[d, 0]
            pos[d, 1] += tau * vel[d, 1]
        for k in range(m):
            if kind[k] == 2:
                i = a[k]
                gap_lin[k] += tau * (normal[k, 0] * vel[i, 0] + normal[k, 1] * vel[i, 1]
                                     + wn[k])
        for d in range(nd):
            pred[d, 0] = vel[d, 0] + 0.5 * tau * acc[d, 0]
            pred[d, 1] = vel[d, 1] + 0.5 * tau * acc[d, 1]
            spred[d] = spin[d] + 0.5 * tau * alpha[d]
        _forces(pos, pred, spred, gap_lin, inv_m, inv_i, g, radii, a, b, kind, normal, wn, wt,
                stiff, eta, mu, gam, R, acc, alpha, F)
        for d in range(nd):
            vel[d, 0] += 0.5 * tau * acc[d, 0]
            vel[d, 1] += 0.5 * tau * acc[d, 1]
            spin[d] += 0.5 * tau * alpha[d]
        for k in range(m):
            if F[k] > peak[k]:
                peak[k] = F[k]
    return peak
