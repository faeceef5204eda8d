"""The compiled inner loop of formulations.drum2d.impacts: a resolved
(sub-stepped) run of one impact cluster — linear spring–dashpot normal
forces, Coulomb friction with an exact stick at each sub-step
(stick_kernel.exact_stick), the discs' spins.  SI units: m, s, kg, N.
Imported only by the function that calls it,
so that importing the drum does not load numba.

:func:`cluster_forces` finds the step's clusters (impacts.py) and runs
each; as scipy's connected_components and a NumPy mask per cluster they
were 0.2–0.3 ms a step of the 500-log bed.  :func:`cluster_run` forms a
run's data from the step's arrays (the
cluster's discs numbered locally, each contact's spring, dashpot, friction
law and masses, the sub-step from Gershgorin's bound: impacts.py's docstring
derives them) and runs :func:`cluster_peaks`; formed in Python they took a
tenth of the run's time.  The contacts are taken kind by kind — disc–disc,
shell, lifter — each loop without a test of the kind, with its ends' inverse
masses and radii gathered once per run: 8–9 % of the kernel's time on the
500-log bed, the peaks within 5e-11 of the largest of the contact-ordered
loop's (other sums' order).  A contact that touches within a sub-step is
integrated from its touch (:func:`_touch`), which makes a run's peaks
second order in τ (impacts.py derives it).  A run also keeps, per contact,
its sliding work at the cone, tangential impulse, start and end slips and
whether it touched at the start and the end, from which the step books
the slip within it (impacts.py, "Sliding work")."""

from __future__ import annotations

import numpy as np

from qpcontact.core.compiled import njit

from .stick_kernel import exact_stick

__all__ = ["cluster_forces", "cluster_run", "cluster_peaks"]

#: a force above its contact's largest so far by this fraction per 0.3/ω_max
#: of run is a rise: the run goes on while one happened within the last
#: quiet sub-steps.  A rate, so that the same rises count at any sub-step.
#: (1 % per 0.1/ω_max, the old 1 % a sub-step as a rate, held a quarter of
#: the 500-log bed's runs open against 30 % before, whose first-order
#: touches made rises: the log–steel force exceeded 50 times a second fell
#: from −3.7 to −6.4 % of the penalty DEM's; at this rate 33 %, −3.8 %.)
RISE = 0.01
#: ... where that force is at least this fraction of the run's largest: a
#: wave worth resolving, not a settling contact of a bed-wide cluster
SIGNIFICANT = 0.1
#: the viscous friction's rate over ω_max, γ w_T / ω_max, at a contact in the
#: sub-step it touches (its force from the touch, _touch), and the first guess
#: that stick_kernel.exact_stick corrects everywhere else (γ w_T τ = STICK ω_max τ
#: under 2)
STICK = 2.0


@njit(fastmath=True, inline="always")
def _law(spring, dashpot, tangential, mu):
    """(normal, tangential) force of a contact in touch: the spring's push
    less the dashpot's, no pull; the ``tangential`` force given (the last
    sub-step's: exact_stick corrects it) capped at μ times the normal one."""
    f = spring - dashpot
    if f < 0.0:
        f = 0.0
    ft = tangential
    cap = mu * f
    if ft > cap:
        ft = cap
    elif ft < -cap:
        ft = -cap
    return f, ft


@njit(fastmath=True)
def _touch(k, i, j, nx, ny, over, over_prev, un, ut, wall_n, vx, vy, pvx, pvy, ima, imb, iia,
           iib, stiff, eta, mu, gam, tau, cx, cy, cs, qx, qy, touched, Fc, nt):
    """A contact that touched within the sub-step (overlap ``over`` > 0 at
    its end, ``over_prev`` <= 0 at its start): its (normal, tangential)
    force at the sub-step's end with its own impulse since the touch, and
    the corrections of its ends' velocities (cx, cy, cs) and positions
    (qx, qy) that make its impulse and displacement over the sub-step the
    trapezoid from the touch (impacts.py's docstring derives them).
    ``un``: the predicted normal separation velocity, which lacks the
    contact's own force (``wall_n`` the wall's part of it); ``ut`` the
    tangential one.  The touch is the ``nt``-th of the sub-step: k goes to
    touched[nt], the normal force at the touch to Fc[nt].  Returns (normal
    force, tangential force) at the sub-step's end."""
    theta = over_prev / (over_prev - over)      # the touch's fraction of the sub-step
    s = (1.0 - theta) * tau
    # the separation velocity at the touch, between the start's (v_n = 2 v_half − v_pred)
    # and the predicted end's
    u0 = nx * (2.0 * vx[i] - pvx[i]) + ny * (2.0 * vy[i] - pvy[i]) + wall_n
    if j >= 0:
        u0 -= nx * (2.0 * vx[j] - pvx[j]) + ny * (2.0 * vy[j] - pvy[j])
    fc = -eta[k] * (u0 + theta * (un - u0))
    if fc < 0.0:
        fc = 0.0
    w = ima[k] + imb[k]
    kk = stiff[k]
    ek = eta[k]
    # F = k (δ − w s² (2 F_c + F)/6) − η (u + w s (F_c + F)/2)
    f = (kk * (over - w * s * s * fc / 3.0) - ek * (un + 0.5 * w * s * fc)) / (
        1.0 + 0.5 * ek * w * s + kk * w * s * s / 6.0)
    if f < 0.0:
        f = 0.0
    ft = -gam[k] * ut
    cap = mu[k] * f
    if ft > cap:
        ft = cap
    elif ft < -cap:
        ft = -cap
    imp = 0.5 * s * (fc + f)                    # the trapezoid from the touch
    dn = imp - 0.5 * tau * f                    # less velocity Verlet's end half-kick
    dt = 0.0
    if f > 0.0:
        dt = (imp / (0.5 * tau * f) - 1.0) * 0.5 * tau * ft
    jx = dn * nx - dt * ny
    jy = dn * ny + dt * nx
    q = s * s * (2.0 * fc + f) / 6.0            # its displacement since the touch, × mass
    cx[i] += jx * ima[k]
    cy[i] += jy * ima[k]
    cs[i] -= dt * iia[k]
    qx[i] += q * nx * ima[k]
    qy[i] += q * ny * ima[k]
    if j >= 0:
        cx[j] -= jx * imb[k]
        cy[j] -= jy * imb[k]
        cs[j] -= dt * iib[k]
        qx[j] -= q * nx * imb[k]
        qy[j] -= q * ny * imb[k]
    touched[nt] = k
    Fc[nt] = fc
    return f, ft


@njit(fastmath=True)
def _forces(px, py, vx, vy, spin, pvx, pvy, ps, gap_lin, g, n0, n1, a, b, rsum, ra, rb, ima,
            imb, iia, iib, nrm_x, nrm_y, wn, wt, stiff, eta, mu, gam, R, tau, ax, ay, alpha,
            F, cx, cy, cs, qx, qy, touched, Fc, Ft, ut_half, Ft_prev, tx, ty):
    """The accelerations (ax, ay, alpha) and normal forces F at positions
    (px, py): the dashpots at the predicted velocities (pvx, pvy, ps); the
    tangential force the last sub-step's ``Ft_prev``, capped, which
    stick_kernel.exact_stick then corrects (in the sub-step a contact
    touches, the viscous law at the half-step velocities).  A contact in
    touch whose force in F (the last call's) is 0 and whose overlap a
    sub-step back (x − τ v_half) is not positive touched within the
    sub-step (:func:`_touch`): its number goes to ``touched``, its force at
    the touch to Fc.  Each contact's tangential force goes to ``Ft`` (0 out
    of touch) and, in touch, the half-step slip to ``ut_half`` and the
    tangent to (``tx``, ``ty``).  Returns the number of touches."""
    nd = px.size
    for d in range(nd):
        ax[d] = 0.0
        ay[d] = -g
        alpha[d] = 0.0
    nt = 0
    for k in range(n0):                         # disc–disc
        i = a[k]
        j = b[k]
        dx = px[i] - px[j]
        dy = py[i] - py[j]
        d2 = dx * dx + dy * dy
        rs = rsum[k]
        if d2 >= rs * rs:                       # out of touch: no square root
            F[k] = 0.0
            Ft[k] = 0.0
            continue
        dist = np.sqrt(d2)
        inv = 1.0 / dist
        nx = dx * inv
        ny = dy * inv
        un = nx * (pvx[i] - pvx[j]) + ny * (pvy[i] - pvy[j])
        ut = (-ny * (vx[i] - vx[j]) + nx * (vy[i] - vy[j]) - ra[k] * spin[i]
              - rb[k] * spin[j])
        over = rs - dist
        touch = False
        ex = ey = 0.0
        if F[k] == 0.0:
            ex = dx - tau * (vx[i] - vx[j])
            ey = dy - tau * (vy[i] - vy[j])
            touch = ex * ex + ey * ey >= rs * rs
        if touch:
            f, ft = _touch(k, i, j, nx, ny, over, rs - np.sqrt(ex * ex + ey * ey), un,
                                   ut, 0.0, vx, vy, pvx, pvy, ima, imb, iia, iib, stiff, eta,
                                   mu, gam, tau, cx, cy, cs, qx, qy, touched, Fc, nt)
            nt += 1
        else:
            f, ft = _law(stiff[k] * over, eta[k] * un, Ft_prev[k], mu[k])
        F[k] = f
        Ft[k] = ft
        ut_half[k] = ut
        tx[k] = -ny
        ty[k] = nx
        fx = f * nx - ft * ny
        fy = f * ny + ft * nx
        ax[i] += fx * ima[k]
        ay[i] += fy * ima[k]
        alpha[i] -= ft * iia[k]
        ax[j] -= fx * imb[k]
        ay[j] -= fy * imb[k]
        alpha[j] -= ft * iib[k]
    for k in range(n0, n1):                     # the shell
        i = a[k]
        d2 = px[i] * px[i] + py[i] * py[i]
        lim = R - ra[k]
        # out of touch: dist + r <= R (a disc as wide as the shell never is)
        if lim >= 0.0 and d2 <= lim * lim:
            F[k] = 0.0
            Ft[k] = 0.0
            continue
        dist = np.sqrt(d2)
        inv = 1.0 / dist
        nx = -px[i] * inv
        ny = -py[i] * inv
        un = nx * pvx[i] + ny * pvy[i]
        ut = -ny * vx[i] + nx * vy[i] - ra[k] * spin[i] + wt[k]
        over = dist + ra[k] - R
        touch = False
        ex = ey = 0.0
        if F[k] == 0.0:
            ex = px[i] - tau * vx[i]
            ey = py[i] - tau * vy[i]
            touch = lim >= 0.0 and ex * ex + ey * ey <= lim * lim
        if touch:
            f, ft = _touch(k, i, -1, nx, ny, over, np.sqrt(ex * ex + ey * ey) - lim, un,
                                   ut, 0.0, vx, vy, pvx, pvy, ima, imb, iia, iib, stiff, eta,
                                   mu, gam, tau, cx, cy, cs, qx, qy, touched, Fc, nt)
            nt += 1
        else:
            f, ft = _law(stiff[k] * over, eta[k] * un, Ft_prev[k], mu[k])
        F[k] = f
        Ft[k] = ft
        ut_half[k] = ut
        tx[k] = -ny
        ty[k] = nx
        ax[i] += (f * nx - ft * ny) * ima[k]
        ay[i] += (f * ny + ft * nx) * ima[k]
        alpha[i] -= ft * iia[k]
    for k in range(n1, a.size):                 # the lifters
        over = -gap_lin[k]
        if over <= 0.0:
            F[k] = 0.0
            Ft[k] = 0.0
            continue
        i = a[k]
        nx = nrm_x[k]
        ny = nrm_y[k]
        un = nx * pvx[i] + ny * pvy[i] + wn[k]
        ut = -ny * vx[i] + nx * vy[i] - ra[k] * spin[i] + wt[k]
        # the gap a sub-step back (cluster_peaks advanced it by τ (n·v_half + w_n))
        over_prev = over + tau * (nx * vx[i] + ny * vy[i] + wn[k])
        if F[k] == 0.0 and over_prev <= 0.0:
            f, ft = _touch(k, i, -1, nx, ny, over, over_prev, un, ut, wn[k], vx, vy,
                                   pvx, pvy, ima, imb, iia, iib, stiff, eta, mu, gam, tau, cx,
                                   cy, cs, qx, qy, touched, Fc, nt)
            nt += 1
        else:
            f, ft = _law(stiff[k] * over, eta[k] * un, Ft_prev[k], mu[k])
        F[k] = f
        Ft[k] = ft
        ut_half[k] = ut
        tx[k] = -ny
        ty[k] = nx
        ax[i] += (f * nx - ft * ny) * ima[k]
        ay[i] += (f * ny + ft * nx) * ima[k]
        alpha[i] -= ft * iia[k]
    return nt


@njit(fastmath=True)
def _slips(px, py, vx, vy, spin, n0, n1, a, b, ra, rb, nrm_x, nrm_y, wt, out):
    """Every contact's tangential slip u_T [m/s] at velocities (vx, vy,
    spin), in touch or not, as the step reads its u_T⁻ and u_T⁺: the normal
    through the centres, from the axis, or the lifter's."""
    for k in range(a.size):
        i = a[k]
        if k < n0:
            j = b[k]
            dx = px[i] - px[j]
            dy = py[i] - py[j]
            inv = 1.0 / np.sqrt(dx * dx + dy * dy)
            nx, ny = dx * inv, dy * inv
            out[k] = (-ny * (vx[i] - vx[j]) + nx * (vy[i] - vy[j]) - ra[k] * spin[i]
                      - rb[k] * spin[j])
        else:
            if k < n1:
                inv = 1.0 / np.sqrt(px[i] * px[i] + py[i] * py[i])
                nx, ny = -px[i] * inv, -py[i] * inv
            else:
                nx, ny = nrm_x[k], nrm_y[k]
            out[k] = -ny * vx[i] + nx * vy[i] - ra[k] * spin[i] + wt[k]


@njit(fastmath=True)
def cluster_peaks(px, py, vx, vy, spin, gap_lin, g, n0, n1, a, b, rsum, ra, rb, ima, imb, iia,
                  iib, nrm_x, nrm_y, wn, wt, stiff, eta, mu, gam, R, tau, steps, most, quiet,
                  rise_above, books):
    """Velocity Verlet over ``steps`` sub-steps of ``tau``, and on, up to
    ``most`` in all, while a contact's force has risen to ``rise_above``
    times its largest, and to at least SIGNIFICANT of the run's largest, within
    the last ``quiet`` sub-steps (a wave still on its way through the
    cluster) (all arrays are modified): discs at (``px``, ``py``) with velocities (``vx``, ``vy``) and
    ``spin``; contacts 0 .. n0 − 1 from disc a[k] to disc b[k], n0 .. n1 − 1
    to the shell of radius R, n1 .. to a lifter (the gap ``gap_lin``
    advanced along the fixed normal (``nrm_x``, ``nrm_y``), the wall's
    velocity terms ``wn``, ``wt``); per contact the sum of radii ``rsum``,
    its ends' radii ``ra``, ``rb``, inverse masses ``ima``, ``imb`` and
    radius over inertia ``iia``, ``iib`` (0 at a wall); normal force
    max(0, stiff δ − eta u_N) where the overlap δ > 0, tangential the exact
    stick of stick_kernel.exact_stick capped at mu times it (−gam u_T, the
    same capped, in the sub-step a contact touches).  The dashpots at the end of a
    sub-step use the velocity predicted with the last acceleration (the
    half-step velocity would lag: first order).
    A contact that touches within a sub-step has its impulse from the touch
    (:func:`_touch`), and its force at the touch is a sample of its force.
    Into ``books`` (5, m), per contact over the whole run: the sliding work
    ∫|F_T||u_T| dt [J] where the force is at the cone (a sub-step's slip is
    τ u_T(t + τ/2), Verlet's drift, its force the mean of the sub-step's
    ends: the force at the end with the half-step slip alone was first order
    in τ), the tangential impulse ∫F_T dt [N·s], the slip u_T [m/s] at the
    run's start and end, and 2 (in touch at the start) + 1 (in touch at the
    end) (impacts.py, "Sliding work").
    Returns (each contact's largest normal force [N], the sub-steps run)."""
    nd, m = px.size, a.size
    ax, ay, alpha = np.zeros(nd), np.zeros(nd), np.zeros(nd)
    pvx, pvy, ps = vx.copy(), vy.copy(), spin.copy()
    cx, cy, cs, qx, qy = np.zeros(nd), np.zeros(nd), np.zeros(nd), np.zeros(nd), np.zeros(nd)
    touched, Fc = np.zeros(m, np.int64), np.zeros(m)
    F, peak = np.ones(m), np.zeros(m)         # F ≠ 0: no touch in the first call
    Ft, Ft_next, ut_half = np.zeros(m), np.zeros(m), np.zeros(m)
    tx, ty, skip = np.zeros(m), np.zeros(m), np.zeros(m, np.int64)
    _forces(px, py, vx, vy, spin, pvx, pvy, ps, gap_lin, g, n0, n1, a, b, rsum, ra, rb, ima,
            imb, iia, iib, nrm_x, nrm_y, wn, wt, stiff, eta, mu, gam, R, tau, ax, ay, alpha, F,
            cx, cy, cs, qx, qy, touched, Fc, Ft, ut_half, Ft, tx, ty)
    exact_stick(n0, a, b, ra, rb, ima, imb, iia, iib, mu, tau, F, Ft, ut_half, touched, 0, ax,
                ay, alpha, tx, ty, skip)
    for k in range(m):
        peak[k] = F[k]
        books[4, k] = 2.0 if F[k] > 0.0 else 0.0
    ht = 0.5 * tau
    done, rose = 0, 0
    us = np.zeros(m)
    _slips(px, py, vx, vy, spin, n0, n1, a, b, ra, rb, nrm_x, nrm_y, wt, us)
    for k in range(m):
        books[2, k] = us[k]
    largest = 0.0
    for k in range(m):
        if peak[k] > largest:
            largest = peak[k]
    glancing = False
    while done < steps or (done < most and (done - rose < quiet or glancing)):
        done += 1
        for d in range(nd):
            vx[d] += ht * ax[d]
            vy[d] += ht * ay[d]
            spin[d] += ht * alpha[d]
            px[d] += tau * vx[d]
            py[d] += tau * vy[d]
            pvx[d] = vx[d] + ht * ax[d]
            pvy[d] = vy[d] + ht * ay[d]
            ps[d] = spin[d] + ht * alpha[d]
        for k in range(n1, m):
            i = a[k]
            gap_lin[k] += tau * (nrm_x[k] * vx[i] + nrm_y[k] * vy[i] + wn[k])
        nt = _forces(px, py, vx, vy, spin, pvx, pvy, ps, gap_lin, g, n0, n1, a, b, rsum, ra,
                     rb, ima, imb, iia, iib, nrm_x, nrm_y, wn, wt, stiff, eta, mu, gam, R, tau,
                     ax, ay, alpha, F, cx, cy, cs, qx, qy, touched, Fc, Ft_next, ut_half, Ft,
                     tx, ty)
        exact_stick(n0, a, b, ra, rb, ima, imb, iia, iib, mu, tau, F, Ft_next, ut_half, touched,
                    nt, ax, ay, alpha, tx, ty, skip)
        glancing = False
        for k in range(m):
            # slip work at the cone only: with the exact stick a stuck
            # contact does not move, and no creep is booked as rubbing (a
            # frictionless contact has no cone: it would read as sliding at
            # it, and every new touch would hold the run to ``most``)
            cap = mu[k] * F[k]
            if cap > 0.0 and abs(Ft_next[k]) >= (1.0 - 1e-9) * cap:
                books[0, k] += tau * 0.5 * (abs(Ft[k]) + abs(Ft_next[k])) * abs(ut_half[k])
                if books[4, k] == 0.0:      # a touch new in the run, still sliding
                    glancing = True
            books[1, k] += tau * 0.5 * (Ft[k] + Ft_next[k])
            Ft[k] = Ft_next[k]
        for d in range(nd):
            vx[d] += ht * ax[d]
            vy[d] += ht * ay[d]
            spin[d] += ht * alpha[d]
        if nt:
            for k in range(n1, m):              # the lifters' gaps follow their discs
                i = a[k]
                gap_lin[k] += nrm_x[k] * qx[i] + nrm_y[k] * qy[i]
            for t in range(nt):
                k = touched[t]
                for i in (a[k], b[k]):
                    if i >= 0:
                        vx[i] += cx[i]
                        vy[i] += cy[i]
                        spin[i] += cs[i]
                        px[i] += qx[i]
                        py[i] += qy[i]
                        cx[i] = cy[i] = cs[i] = qx[i] = qy[i] = 0.0
                if Fc[t] > peak[k]:             # the touch is a sample
                    peak[k] = Fc[t]
        for k in range(m):
            if F[k] > peak[k]:
                if F[k] > rise_above * peak[k] and F[k] > SIGNIFICANT * largest:
                    rose = done
                peak[k] = F[k]
                if F[k] > largest:
                    largest = F[k]
    _slips(px, py, vx, vy, spin, n0, n1, a, b, ra, rb, nrm_x, nrm_y, wt, us)
    for k in range(m):
        books[3, k] = us[k]
        books[4, k] += 1.0 if F[k] > 0.0 else 0.0
    return peak, done


@njit
def cluster_run(discs, ks, ci, cj, kind, gap, normal, w, comp, m_star, mu, positions,
                velocities, masses, radii, inverse_inertia, zeta, g, R, span, span_max,
                quiet_time, omega_tau, books):
    """The resolved run of one cluster (impacts.py's docstring): its
    ``discs`` (global numbers, increasing) and contacts ``ks`` (indices into
    the step's contact arrays ``ci``, ``cj``, ``kind``, ``gap``, ``normal``,
    ``w`` (2m: normal, tangential), ``comp``, ``m_star``, ``mu``), the
    step's start ``positions`` (n, 2), generalized ``velocities`` (3n,),
    ``masses``, ``radii``, ``inverse_inertia``; dashpot ratio ``zeta``,
    gravity ``g``, shell radius ``R``, run length ``span`` [s], continued
    up to ``span_max`` while a force still rises within ``quiet_time`` [s]
    (:func:`cluster_peaks`), ω_max τ = ``omega_tau``.  Returns (each
    contact's largest normal force [N] in the order of ``ks``, τ, sub-steps
    run); into ``books`` (5, len(ks)) the run's books (:func:`cluster_peaks`)."""
    nd, m = discs.size, ks.size
    local = np.full(masses.size, -1, np.int64)
    for d in range(nd):
        local[discs[d]] = d
    inv_m = np.empty(nd)
    inv_i = np.empty(nd)
    rad = np.empty(nd)
    px, py = np.empty(nd), np.empty(nd)
    vx, vy, spin = np.empty(nd), np.empty(nd), np.empty(nd)
    for d in range(nd):
        e = discs[d]
        inv_m[d] = 1.0 / masses[e]
        inv_i[d] = inverse_inertia[e]
        rad[d] = radii[e]
        px[d], py[d] = positions[e, 0], positions[e, 1]
        vx[d], vy[d], spin[d] = velocities[3 * e], velocities[3 * e + 1], velocities[3 * e + 2]
    # disc–disc first, then the shell, then the lifters (stable: the step's
    # order within a kind)
    order = np.empty(m, np.int64)
    ends = np.zeros(3, np.int64)
    p = 0
    for want in range(3):
        for k in range(m):
            if kind[ks[k]] == want:
                order[p] = k
                p += 1
        ends[want] = p
    n0, n1 = ends[0], ends[1]
    a, b = np.empty(m, np.int64), np.empty(m, np.int64)
    stiff, eta, mu_k = np.empty(m), np.empty(m), np.empty(m)
    ra, rb, rsum = np.empty(m), np.empty(m), np.empty(m)
    ima, imb, iia, iib = np.empty(m), np.empty(m), np.empty(m), np.empty(m)
    nrm_x, nrm_y, gap_lin = np.empty(m), np.empty(m), np.empty(m)
    wn, wt, gam = np.empty(m), np.empty(m), np.empty(m)
    row = np.zeros(nd)
    for p in range(m):
        k = ks[order[p]]
        i = local[ci[k]]
        a[p] = i
        stiff[p] = 1.0 / comp[k]
        eta[p] = 2.0 * zeta * np.sqrt(m_star[k] * stiff[p])
        mu_k[p] = mu[k]
        nrm_x[p], nrm_y[p], gap_lin[p] = normal[k, 0], normal[k, 1], gap[k]
        wn[p], wt[p] = w[2 * k], w[2 * k + 1]
        ra[p], ima[p], iia[p] = rad[i], inv_m[i], rad[i] * inv_i[i]
        mi = masses[ci[k]]
        if cj[k] >= 0:
            j = local[cj[k]]
            b[p] = j
            rb[p], imb[p], iib[p] = rad[j], inv_m[j], rad[j] * inv_i[j]
            mj = masses[cj[k]]
            # Gershgorin on M^-1/2 K M^-1/2: (2/m_i + 2/sqrt(m_i m_j)) / c per end
            cross = 2.0 / np.sqrt(mi * mj)
            row[i] += stiff[p] * (2.0 / mi + cross)
            row[j] += stiff[p] * (2.0 / mj + cross)
        else:
            b[p] = -1
            rb[p], imb[p], iib[p] = 0.0, 0.0, 0.0
            row[i] += stiff[p] * (2.0 / mi)
        rsum[p] = ra[p] + rb[p]
    omega_max = np.sqrt(row.max())
    tau = omega_tau / omega_max
    steps = int(np.ceil(span / tau))
    local_books = np.zeros((books.shape[0], m))
    for p in range(m):
        # the viscous law of a touching sub-step and exact_stick's first guess:
        # it relaxes a contact's slip at the rate STICK ω_max (a disc's
        # tangential inverse mass 1/m + r²/I)
        w_t = ima[p] + ra[p] * iia[p] + imb[p] + rb[p] * iib[p]
        gam[p] = STICK * omega_max / w_t
    peak, done = cluster_peaks(px, py, vx, vy, spin, gap_lin, g, n0, n1, a, b, rsum, ra, rb,
                               ima, imb, iia, iib, nrm_x, nrm_y, wn, wt, stiff, eta, mu_k, gam,
                               R, tau, steps, int(np.ceil(span_max / tau)),
                               int(np.ceil(quiet_time / tau)),
                               1.0 + RISE * omega_tau / 0.3, local_books)
    out = np.empty(m)
    for p in range(m):
        out[order[p]] = peak[p]
        for q in range(books.shape[0]):
            books[q, order[p]] = local_books[q, p]
    return out, tau, done


@njit
def _root(parent, d):
    """Disc d's cluster: the root of its tree, the path halved on the way."""
    while parent[d] != d:
        parent[d] = parent[parent[d]]
        d = parent[d]
    return d


@njit
def cluster_forces(F, r_n, T, pulse, loaded, ci, cj, kind, gap, normal, w, comp, m_star, mu,
                   positions, velocities, masses, radii, inverse_inertia, zeta, g, R, h,
                   omega_tau, books):
    """impacts.step_forces' clusters, each run (:func:`cluster_run`) into F
    [N] (the step's mean forces r_N/h on entry): the discs joined by the
    ``loaded`` disc–disc contacts, those with a ``pulse`` contact, each
    with every contact among its discs (the discs and contacts in
    increasing order, as np.flatnonzero lists them); a cluster with a
    rigid contact (comp <= 0) gets the pair's half-sine π r_N/T at its
    pulses instead.  ``T`` the contacts' periods [s], ``h`` the step [s];
    the rest as cluster_run's; each run's ``books`` (:func:`cluster_peaks`)
    into its contacts' columns of ``books`` (5, m)."""
    n, m = masses.size, ci.size
    parent = np.arange(n)
    for k in range(m):
        if cj[k] >= 0 and loaded[k]:
            a, b = _root(parent, ci[k]), _root(parent, cj[k])
            if a != b:
                parent[max(a, b)] = min(a, b)
    root = np.empty(n, np.int64)
    for d in range(n):
        root[d] = _root(parent, d)
    struck = np.zeros(n, np.bool_)
    for k in range(m):
        if pulse[k]:
            struck[root[ci[k]]] = True
    # each struck cluster's discs and contacts, increasing, by a counting sort
    size = np.zeros(n + 1, np.int64)
    for d in range(n):
        if struck[root[d]]:
            size[root[d] + 1] += 1
    owner = np.full(m, -1, np.int64)
    many = np.zeros(n + 1, np.int64)
    for k in range(m):
        r = root[ci[k]]
        if struck[r] and (cj[k] < 0 or root[cj[k]] == r):
            owner[k] = r
            many[r + 1] += 1
    for d in range(n):
        size[d + 1] += size[d]
        many[d + 1] += many[d]
    discs = np.empty(size[n], np.int64)
    ks = np.empty(many[n], np.int64)
    at = size[:n].copy()
    for d in range(n):
        if struck[root[d]]:
            discs[at[root[d]]] = d
            at[root[d]] += 1
    at = many[:n].copy()
    for k in range(m):
        if owner[k] >= 0:
            ks[at[owner[k]]] = k
            at[owner[k]] += 1
    for r in range(n):
        if not struck[r]:
            continue
        mine = ks[many[r]:many[r + 1]]
        rigid = False
        T_max = 0.0
        for k in mine:
            if comp[k] <= 0.0:
                rigid = True
            if pulse[k] and T[k] > T_max:
                T_max = T[k]
        if rigid:                            # a rigid contact: nothing to resolve
            for k in mine:
                if pulse[k]:
                    F[k] = np.pi * r_n[k] / T[k]
            continue
        run_books = np.zeros((books.shape[0], mine.size))
        peak, _, _ = cluster_run(discs[size[r]:size[r + 1]], mine, ci, cj, kind, gap, normal, w,
                                 comp, m_star, mu, positions, velocities, masses, radii,
                                 inverse_inertia, zeta, g, R, h + 0.5 * T_max,
                                 2.0 * h + 0.5 * T_max, 0.5 * T_max, omega_tau, run_books)
        for p in range(mine.size):
            F[mine[p]] = peak[p]
            for q in range(books.shape[0]):
                books[q, mine[p]] = run_books[q, p]
