r"""A resolved explicit penalty DEM of the 2-D drum, the yardstick of
``benchmarks/drum.py --model 2d``'s speed (CPU per simulated second).

SI units.  The same discs, shell and lifters as formulations.drum2d, the
same contact stiffness as its springs: per contact k = 1/c, c = 1/s_i + 1/s_j
(s = 2 E ℓ, the stack model's half stiffness; 1/s_i at the steel), a
dashpot 2 ζ √(m* k) with ζ = −ln e / √(π² + ln² e) (the restitution e of
a binary collision), and Coulomb friction in one of two forms:

- ``spring=0`` (the yardstick's): a tangential dashpot of the same
  coefficient capped at μ F_n, no tangential spring and so no contact
  history; a stuck contact creeps at the speed its dashpot needs to carry
  the tangential load (2ζ√(m k) ≈ 6e4 N·s/m carries 1 kN at 17 mm/s).
- ``spring=ρ > 0`` (Cundall–Strack): an elastic tangential displacement δ
  per contact, δ += u_t Δt while the contact lasts, a spring k_t = ρ k and
  a dashpot c_t = c √(ρ/3).  Where the spring's trial force k_t |δ| exceeds
  μ F_n the contact slides: F_t = μ F_n against δ, δ is set back to
  μ F_n/k_t, and what it lost is the step's slip (it dissipates μ F_n |slip|
  exactly: the spring's store is ½ k_t δ²).  Within the cone the dashpot
  acts, clipped to what the cone leaves.  ρ = 1/3
  (benchmarks/drum2d_step.py's ``spring``): a disc's tangential effective mass is a third of the normal one
  (1/m_t = 1/m* + Σ r²/I = 3/m* with I = m r²/2, for any two discs and at
  the steel), so k_t = k/3 gives the tangential period the normal one and
  c_t = c/3 the same damping ratio (the spheres' 2/7 is this ratio for
  I = 2 m r²/5).  A stuck contact holds without creep: its elastic δ ≤
  μ F_n/k_t (3μ times the normal overlap at ρ = 1/3), and only Coulomb
  slip is booked as sliding.  The history is keyed by pair on the Verlet
  list (carried over by key when the list is rebuilt), by disc at the shell
  and by (disc, lifter) at the lifters.  The spring's increment u_t Δt is
  the step's relative slip: the disc's velocity there is the one that
  brought it here (symplectic Euler is leapfrog, v at t − Δt/2), so the
  wall's is taken at t − Δt/2 too, Ω ẑ × Rot(−Ω Δt/2) p (_wall_lag).  With
  V(p) at t a log carried in stick on a lifter's radial face read a slip
  Ω² ρ Δt/2 along the face that it did not make (1 µm/s at 0.9 m, T/400),
  and its spring k_t integrated it: 10k at T/400 drove a log wedged between
  a face and the shell to the face's cone within 0.1 s, whatever Δt
  (T/1600: 0.15 s), where with the lag its forces are the same at T/400 and
  T/1600 to 0.2 N (docs/dev-notes.md, "The lifter pocket's force loop").
  At the shell the two velocities differ along t by a factor cos(Ω Δt/2).

Explicit symplectic Euler with Δt = T_min/``per_period``, T_min
= 2π √(m*/k) the shortest contact period (50 steps a period: a resolved
contact).  Candidate disc pairs by the drum's own grid broad phase
(broadphase.grid_pairs) within a margin that the fastest disc cannot cross
before the list is rebuilt (a Verlet list); the shell and the lifters are
tested for every disc at every step (vectorized).

It keeps the books a drum engineer reads, as a resolved reference for the
2-D route's run-level figures (benchmarks/drum2d_step.py): the drive work
Σ F·V Δt of the shell and lifters on the logs (V = Ω ẑ × p at the contact
point) [J], the tangential loss [J] — the friction work Σ |F_t||u_t| Δt of
the capped dashpot, or with the spring the slip's μ F_n |slip| plus the
tangential dashpot's work within the cone — and its sliding part: the
capped dashpot's work at the cone (|F_t| = μ F_n; the rest is the creep of
stuck contacts, which a DEM without a tangential spring books as friction
too), or the spring's slip work,
and the largest log–log and log–steel normal force [N] in each window of
``window`` seconds.  It is not a test's reference for the mechanics: the
tests' resolved DEMs live in tests/ (written there).
"""

from __future__ import annotations

import time

import numpy as np

from formulations.drum2d.broadphase import grid_pairs


from qpcontact.core.compiled import njit


@njit
def _contact(nx, ny, ov, vx, vy, wa, ra, k, c, mu, lag):
    """(fx, fy, torque, F_n, |F_t u_t|, at the cone) on a disc of radius ra
    spinning at wa from a contact of overlap ov, normal (nx, ny) into it, the
    relative velocity (vx, vy) of its centre against the other body's point
    (that body's rolling part already in it), ``lag`` what the wall's
    tangential velocity at t exceeds its mean over the step that brought
    the disc here (_wall_lag; 0 between discs); zeros where the contact
    pulls."""
    tx, ty = -ny, nx
    un = vx * nx + vy * ny
    ut = vx * tx + vy * ty - ra * wa + lag
    fn = k * ov - c * un
    if fn <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, False
    cone = c * abs(ut) >= mu * fn
    ft = -min(c * abs(ut), mu * fn) * (1.0 if ut > 0 else -1.0)
    return fn * nx + ft * tx, fn * ny + ft * ty, -ra * ft, fn, abs(ft * ut), cone


@njit
def _contact_spring(nx, ny, ov, vx, vy, wa, ra, k, c, mu, dt, held, ratio, lag):
    """_contact's (fx, fy, torque, F_n, tangential loss rate, slides) by
    Cundall–Strack's tangential spring k_t = ``ratio`` k and dashpot
    c_t = c √(ratio/3) (module docstring), and the contact's elastic
    tangential displacement after the step [m] (``held`` before it; 0 where
    the contact is open or pulls).  The spring's trial force −k_t (δ + u_t Δt)
    beyond μ F_n slides: F_t = μ F_n, δ = −F_t/k_t, and the slip (the rest of
    δ + u_t Δt) dissipates μ F_n |slip| in the step; within the cone the
    dashpot acts, clipped to what the cone leaves, and dissipates its own
    force times u_t; ``lag`` as in _contact."""
    tx, ty = -ny, nx
    un = vx * nx + vy * ny
    ut = vx * tx + vy * ty - ra * wa + lag
    fn = k * ov - c * un
    if fn <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, False, 0.0
    kt, ct = ratio * k, c * np.sqrt(ratio / 3.0)
    held = held + ut * dt
    fs = -kt * held
    cap = mu * fn
    if abs(fs) > cap:                  # slides: the spring holds the cap
        ft = cap if fs > 0 else -cap
        return (fn * nx + ft * tx, fn * ny + ft * ty, -ra * ft, fn,
                cap * (abs(held) - cap / kt) / dt, True, -ft / kt)
    ft = min(max(fs - ct * ut, -cap), cap)
    return (fn * nx + ft * tx, fn * ny + ft * ty, -ra * ft, fn, abs((ft - fs) * ut), False,
            held)


@njit
def _wall_lag(nx, ny, px, py, omega, dt):
    """t · (V(p) − V_mid) [m/s]: the wall point p's velocity at t less its
    mean over the step [t − Δt, t] that brought the disc here (the disc's
    velocity in the step is that step's: symplectic Euler's leapfrog), so
    that a disc turning with the wall adds nothing to its tangential spring.
    V_mid = Ω ẑ × Rot(−Ω Δt/2) p; without it a disc carried on a lifter's
    radial face reads a slip Ω² ρ Δt/2 along the face (module docstring)."""
    eps = 0.5 * omega * dt
    a, b = 1.0 - np.cos(eps), np.sin(eps)
    # V − V_mid = Ω ((1 − cos ε) ẑ × p − sin ε p)
    dx = omega * (a * -py - b * px)
    dy = omega * (a * px - b * py)
    return -ny * dx + nx * dy


@njit
def _books(drive, rubbed, slid, top, fn, work, cone, power):
    """A contact's step added to the step's sums: the drive (the wall's
    ``power`` on the disc), friction, friction at the cone, the largest F_n."""
    return drive + power, rubbed + work, slid + (work if cone else 0.0), max(top, fn)


@njit
def _advance(x, v, w, pairs, m, I, rad, s, zeta, mu, omega, g, R, angles, height, b, t0, dt,
             nsteps, books, peaks, window, start, ratio, held_pair, held_shell, held_lift):
    """``nsteps`` symplectic Euler steps in place, adding to ``books`` (3,)
    and ``peaks`` (windows of ``window`` from ``start``, 2) (module
    docstring); with ``spring`` the tangential springs' displacements by
    pair, disc at the shell and (disc, lifter) are kept in ``held_*`` (in
    place); returns (the largest
    distance two discs can have closed, contact-steps in force)."""
    n = x.shape[0]
    F = np.zeros((n, 2))
    T = np.zeros(n)
    reach, counted = 0.0, 0
    nl = angles.shape[0]
    seg = np.zeros((nl, 2))                 # the lifters' directions at t
    for k in range(nsteps):
        t = t0 + k * dt
        # the books of this step, in registers (stored at its end)
        drive, rubbed, slid, top_ll, top_st = 0.0, 0.0, 0.0, 0.0, 0.0
        for a in range(n):
            F[a, 0] = 0.0
            F[a, 1] = -m[a] * g
            T[a] = 0.0
        for p in range(pairs.shape[0]):
            i, j = pairs[p, 0], pairs[p, 1]
            dx, dy = x[i, 0] - x[j, 0], x[i, 1] - x[j, 1]
            dist = np.sqrt(dx * dx + dy * dy)
            ov = rad[i] + rad[j] - dist
            if ov <= 0.0:
                held_pair[p] = 0.0
                continue
            nx, ny = dx / dist, dy / dist
            kc = 1.0 / (1.0 / s[i] + 1.0 / s[j])
            c = 2 * zeta * np.sqrt(m[i] * m[j] / (m[i] + m[j]) * kc)
            # the other disc's rolling part moved into the relative velocity
            vx = v[i, 0] - v[j, 0] + rad[j] * w[j] * ny
            vy = v[i, 1] - v[j, 1] - rad[j] * w[j] * nx
            if ratio > 0.0:
                fx, fy, ti, fn, work, cone, held_pair[p] = _contact_spring(
                    nx, ny, ov, vx, vy, w[i], rad[i], kc, c, mu[0], dt, held_pair[p], ratio,
                    0.0)
            else:
                fx, fy, ti, fn, work, cone = _contact(nx, ny, ov, vx, vy, w[i], rad[i], kc, c,
                                                      mu[0], 0.0)
            if fn > 0.0:
                F[i, 0] += fx
                F[i, 1] += fy
                F[j, 0] -= fx
                F[j, 1] -= fy
                T[i] += ti
                T[j] += ti * rad[j] / rad[i]
                counted += 1
                _, rubbed, slid, top_ll = _books(0.0, rubbed, slid, top_ll, fn, work, cone, 0.0)
        for q in range(nl):
            ang = angles[q] + omega * t
            seg[q, 0], seg[q, 1] = np.cos(ang), np.sin(ang)
        for a in range(n):
            rr = np.sqrt(x[a, 0] ** 2 + x[a, 1] ** 2)
            ov = rr + rad[a] - R
            if ov > 0.0:
                nx, ny = -x[a, 0] / rr, -x[a, 1] / rr
                px, py = x[a, 0] - rad[a] * nx, x[a, 1] - rad[a] * ny
                c = 2 * zeta * np.sqrt(m[a] * s[a])
                lag = _wall_lag(nx, ny, px, py, omega, dt)
                if ratio > 0.0:
                    fx, fy, ti, fn, work, cone, held_shell[a] = _contact_spring(
                        nx, ny, ov, v[a, 0] + omega * py, v[a, 1] - omega * px, w[a], rad[a],
                        s[a], c, mu[1], dt, held_shell[a], ratio, lag)
                else:
                    fx, fy, ti, fn, work, cone = _contact(nx, ny, ov, v[a, 0] + omega * py,
                                                          v[a, 1] - omega * px, w[a], rad[a],
                                                          s[a], c, mu[1], lag)
                F[a, 0] += fx
                F[a, 1] += fy
                T[a] += ti
                if fn > 0.0:
                    counted += 1
                    drive, rubbed, slid, top_st = _books(drive, rubbed, slid, top_st, fn, work,
                                                         cone, omega * (fy * px - fx * py))
            else:
                held_shell[a] = 0.0
            for q in range(nl):
                ux, uy = seg[q, 0], seg[q, 1]
                ax, ay = (R - height) * ux, (R - height) * uy
                ex, ey = height * ux, height * uy
                u = ((x[a, 0] - ax) * ex + (x[a, 1] - ay) * ey) / (height * height)
                u = min(max(u, 0.0), 1.0)
                qx, qy = x[a, 0] - (ax + u * ex), x[a, 1] - (ay + u * ey)
                dist = np.sqrt(qx * qx + qy * qy)
                ov = rad[a] + b - dist
                if ov > 0.0 and dist > 0.0:
                    nx, ny = qx / dist, qy / dist
                    px, py = x[a, 0] - rad[a] * nx, x[a, 1] - rad[a] * ny
                    c = 2 * zeta * np.sqrt(m[a] * s[a])
                    lag = _wall_lag(nx, ny, px, py, omega, dt)
                    if ratio > 0.0:
                        fx, fy, ti, fn, work, cone, held_lift[a, q] = _contact_spring(
                            nx, ny, ov, v[a, 0] + omega * py, v[a, 1] - omega * px, w[a],
                            rad[a], s[a], c, mu[2], dt, held_lift[a, q], ratio, lag)
                    else:
                        fx, fy, ti, fn, work, cone = _contact(
                            nx, ny, ov, v[a, 0] + omega * py, v[a, 1] - omega * px, w[a],
                            rad[a], s[a], c, mu[2], lag)
                    F[a, 0] += fx
                    F[a, 1] += fy
                    T[a] += ti
                    if fn > 0.0:
                        counted += 1
                        drive, rubbed, slid, top_st = _books(drive, rubbed, slid, top_st, fn,
                                                             work, cone,
                                                             omega * (fy * px - fx * py))
                else:
                    held_lift[a, q] = 0.0
        books[0] += drive * dt
        books[1] += rubbed * dt
        books[2] += slid * dt
        win = min(int((t - start) / window), peaks.shape[0] - 1)
        peaks[win, 0] = max(peaks[win, 0], top_ll)
        peaks[win, 1] = max(peaks[win, 1], top_st)
        vmax = 0.0
        for a in range(n):
            v[a, 0] += dt * F[a, 0] / m[a]
            v[a, 1] += dt * F[a, 1] / m[a]
            w[a] += dt * T[a] / I[a]
            x[a, 0] += dt * v[a, 0]
            x[a, 1] += dt * v[a, 1]
            vmax = max(vmax, np.sqrt(v[a, 0] ** 2 + v[a, 1] ** 2) + rad[a] * abs(w[a]))
        reach += 2.0 * dt * vmax
    return reach, counted


def _carried(old, held, new, n: int):
    """The tangential springs of the pairs ``new`` (k, 2) where ``old`` had
    them; a pair new to the list starts unloaded (it was beyond the margin,
    so not in contact)."""
    out = np.zeros(new.shape[0])
    if old.shape[0] and new.shape[0]:
        key_old, key_new = old[:, 0] * n + old[:, 1], new[:, 0] * n + new[:, 1]
        order = np.argsort(key_old)
        at = np.minimum(np.searchsorted(key_old[order], key_new), old.shape[0] - 1)
        hit = key_old[order][at] == key_new
        out[hit] = held[order][at[hit]]
    return out


def penalty_dem(model, duration: float, per_period: float = 50.0, margin_factor=0.5,
                window: float | None = None, t0: float = 0.0, spring: float = 0.0,
                springs=None):
    """Run ``model`` (a Drum2D: its discs' state, shell, μ, e, modulus,
    gravity, Ω) from time ``t0`` [s] (the lifters at Ω t0) for ``duration``
    [s] of simulated time by the penalty DEM of the module docstring; returns
    dict(cpu [s], steps, dt [s], contacts (mean disc–disc + wall contacts in
    force), the final positions, velocities and spins, drive, friction,
    sliding (the friction at the cone) [J], peaks (windows, 2): the largest
    log–log and log–steel normal force [N] in each ``window`` [s] from t0
    (default: the whole run), centroids (the discs' mass centre [m] every
    20 steps), springs (with ``spring``: the tangential springs' state, to
    pass as ``springs`` to a run that goes on from this one's end))."""
    d, sh = model.discs, model.shell
    n = d.n
    m, I, rad = d.masses, d.masses * d.diameters ** 2 / 8.0, d.radii
    s = 2.0 * model.modulus * d.length * np.ones(n)          # half stiffness [N/m]
    e = min(max(model.restitution, 1e-6), 1.0 - 1e-9)
    zeta = -np.log(e) / np.sqrt(np.pi ** 2 + np.log(e) ** 2)
    mu_d, mu_s, mu_l = (model.mu if "friction" in model.effects else np.zeros(3))
    omega, g = model.omega, model.gravity
    # between equal logs m* = m/2 and k = s/2, at the steel m* = m and k = s:
    # either way T = 2π √(m/s), shortest for the lightest log and the stiffest
    T_min = 2 * np.pi * np.sqrt(float(np.min(m)) / float(np.max(s)))
    dt = T_min / per_period
    steps = int(np.ceil(duration / dt))
    x = d.positions.copy()
    v = d.velocities.copy()
    w = d.spins.copy()
    R, b = sh.radius, sh.lifter_half_width
    margin = margin_factor * float(np.min(rad))
    pairs, since, reach = np.zeros((0, 2), np.int64), np.inf, 0.0
    counted, done = 0, 0
    chunk = 20                           # steps between checks of the Verlet list
    centroids = []
    mu = np.array([mu_d, mu_s, mu_l], float)
    angles = np.asarray(sh.lifter_angles, float)
    window = duration if window is None else window
    books, peaks = np.zeros(3), np.zeros((int(np.ceil(steps * dt / window)) + 1, 2))
    if springs is None:                  # (pairs, by pair, at the shell, at the lifters)
        springs = (pairs, np.zeros(0), np.zeros(n), np.zeros((n, angles.size)))
    held_pair, held_shell, held_lift = (a.copy() for a in springs[1:])
    first = grid_pairs(x, rad, margin)[0]
    _advance(x.copy(), v.copy(), w.copy(), first, m, I, rad, s, zeta,
             mu, omega, g, R, angles, sh.lifter_height, b, t0, dt, 1, books.copy(),
             peaks.copy(), window, t0, float(spring), np.zeros(first.shape[0]), held_shell.copy(),
             held_lift.copy())    # compiled
    pairs = springs[0]
    start = time.process_time()
    while done < steps:
        if reach >= 0.5 * margin or since > 0 and not pairs.size or done == 0:
            fresh, _ = grid_pairs(x, rad, margin)
            held_pair = _carried(pairs, held_pair, fresh, n)
            pairs, reach, since = fresh, 0.0, 0
        step = min(chunk, steps - done)
        closed, hits = _advance(x, v, w, pairs, m, I, rad, s, zeta, mu, omega, g, R, angles,
                                sh.lifter_height, b, t0 + done * dt, dt, step, books, peaks,
                                window, t0, float(spring), held_pair, held_shell, held_lift)
        centroids.append(m @ x / m.sum())
        reach += closed
        counted += hits
        done += step
        since += step
    cpu = time.process_time() - start
    return dict(cpu=cpu, steps=steps, dt=dt, contacts=counted / max(steps, 1),
                positions=x, velocities=v, spins=w, drive=books[0], friction=books[1],
                sliding=books[2], peaks=peaks, centroids=np.array(centroids),
                springs=(pairs, held_pair, held_shell, held_lift))
