r"""Peak contact forces of a step from the resolved dynamics of its impact's
cluster.

SI units: m, s, kg, N, N·s (impulses), compliance m/N.

Why.  With springs the drum's step h (2 ms) is longer than a contact period
T = 2π √(m* c) (0.7 ms for 0.12 m spruce logs): an impact is over within the
step, and r_N/h, the step's mean force, is a fraction of its peak.  Rebuilding
the peak from one two-body spring (the half-sine π r_N/T) is right for a
binary collision only.  Where the impulse passes through a chain — a log
striking a column, a log landing on one that rests on the shell — the struck
contact's impulse is the whole chain's momentum change, delivered over the
chain's wave time rather than the pair's half period, and the half-sine of
the pair overestimates the peak (a struck column: 860 kN against 195 kN from a
resolved simulation; a log struck on the shell: 86 kN against 61 kN).

What.  Each step whose unresolved impacts (laws: an impact contact with
T < π h) involve only compliant contacts is run again, for the force
statistics only, as a resolved simulation of the impact's cluster: the discs
connected to an impact's discs through contacts that carry an impulse in the
step (its connected component in the contact graph), with every active
contact among them, from the step's start state (positions, velocities,
overlaps), under gravity, each contact the step's own spring 1/c (laws.py)
with a dashpot of the step's restitution e (ζ = −ln e / √(π² + ln² e) on the
contact's m*; none with e = 1), no pull, and Coulomb friction with the
step's μ (regularized by a viscous law, below), the discs spinning.
Disc–disc and disc–shell contacts use their exact gaps as the discs move;
a lifter's gap moves linearly along its normal at the wall's velocity.  The
run is velocity Verlet (the dashpots at the predicted velocity) with
τ = 0.4 / ω_max (ω_max² <= max_i Σ_k (2/m_i + 2/√(m_i m_j))/c_k, Gershgorin
on the cluster's stiffness: at least 15 sub-steps a period of its fastest
mode; "The sub-step's size" below), over h + T_max/2 (an impact starting
at the step's end still reaches its peak), and on while a force still
rises (below).

The touch.  A dashpot's force jumps at the touch, to F_c = η |u_c| (u_c the
normal velocity then).  Sampled at the sub-steps' ends alone, a contact
that touches at t_c = t_n + θτ within a sub-step is credited by Verlet's
trapezoid with τ F_{n+1}/2 of impulse where it pushed for s = (1 − θ)τ from
F_c — an error (τ/2)((1 − θ) F_c − θ F_{n+1}) ~ η u τ, once a touch — and
its first sample over-reads the force by its own dashpot's deceleration
over s, which the predicted velocity lacks: the peak was first order in τ
(+1.5 % on a binary impact with e = 0.2 at 0.1 and 0.05/ω_max, +8 % at 0.2,
+4.6 % with e = 0.05 at 0.1, where the jump is the peak).  So the touch is
located — θ = δ_n/(δ_n − δ_{n+1}) from the overlap δ_n a drift back
(x − τ v_{n+1/2}, exact for Verlet's drift) — and over s the contact is
integrated on its own, its ends' normal inverse mass w: its force at the
sub-step's end F = k (δ_{n+1} − w s² (2F_c + F)/6) − η (u + w s (F_c + F)/2)
(its own trapezoid from the touch in displacement and velocity, solved for
F; u the predicted separation velocity), its ends' velocities take
s (F_c + F)/2 − τF/2 and their positions w s² (2F_c + F)/6 along the
normal (the tangential impulse scaled as the normal one), and F_c is a
sample of its force.  Each touch's error is then O(τ³) in impulse, and the
peak second order: velocity Verlet's own, +(ωτ)²/8 in amplitude on a
pair of frequency ω (+0.5 % at ωτ = 0.2), partly cancelled by the samples'
−(ωτ)²/8 at most.  Separations need nothing: the force goes to zero
continuously (no pull).

Friction.  Coulomb's stick is exact at each sub-step
(stick_kernel.exact_stick): a contact in touch takes the tangential force
that stops its slip at the next half step,

    u_T(t + τ/2) + τ (a_T,others + w_T F_T) = 0,

capped at μ F_N (w_T the contact's tangential inverse mass, 1/m + r²/I a
disc), by projected Gauss–Seidel over the cluster's contacts, one sweep a
sub-step from the last sub-step's forces (stick_kernel.py).  In the
sub-step a contact touches, its force is the touch's (above) with a
viscous law, γ w_T = 2 ω_max, at the half-step velocity (stable to
γ w_T τ < 2).  The viscous law alone, the runs' stick until 2026-12,
creeps under a steady tangential load (u_T = F_T/γ): the struck piles'
sliding at the cone read 7.5–10 % below a converged stiff-stick DEM,
against −1.4 … −4.3 % with the exact stick; stiffer viscous laws chattered
(γ w_T = 4 ω_max: +6 … +44 %).

Each cluster contact's force is the largest of that run; every other
contact's the step's mean r_N/h.

Sliding work.  The step books friction's work at a contact as |r_T| s̄ [J]:
the step's constant tangential force |r_T|/h times the mean of the slip
taken linear from u_T⁻ to u_T⁺ (records.sliding_speed).  Slip that starts
and stops within the step is not in those end points, and where the step
does not resolve an impact (h > T) its implicit impulse hardly shows the
slip the impact's wave drives through a pile (a pile struck from above:
0.34 J booked against a resolved 7.4 J, test_drum2d_sliding.py).  The
cluster run resolves it, with Coulomb's stick exact at each sub-step
(stick_kernel.exact_stick: a rigid stick, the law of the step and of the
converged DEM; the viscous stick it replaced crept, and its runs' sliding
on the struck piles read 7.5–10 % low).  Per contact it keeps, over the
whole run (from the step's start to h + T_max/2 and on while a force
rises), the sliding work at the cone W = ∫|F_T||u_T| dt [J] (each
sub-step's slip τ u_T(t + τ/2), Verlet's drift, times the mean of its
ends' forces), the tangential impulse R = ∫F_T dt [N·s], the slips
u_T(0), u_T(end) [m/s] read as the step reads u_T⁻ and u_T⁺ (the normal
through the centres, in touch or not) and whether it touched at the run's
start and end.  A contact books

    |r_T| s̄  +  W − |R| s̄(u_T(0), u_T(end)),        at least 0:

the step's own estimate plus what the resolved run slid beyond the same
linear-slip estimate of itself.  The bracket is zero where the slip is
linear in time under a constant force (steady sliding; a stuck contact
books nothing), whatever the run's length, so that the stretch past h,
which the next step's run overlaps, adds only the slip that starts and
stops in it (an impact late in the step slides after h: booked over
[0, h] alone, a struck pair at h = 0.5 ms read 0.08 of 2.68 J).  An
impact's own contact whose whole touch lies within the run — the striker
that glances off — books the run's W instead: both linear estimates read
its slip from before the touch and after the discs parted, and nothing
else books that touch.  So that a glancing touch ends within the run, the
run goes on while a contact that was not in touch at its start slides at
the cone, up to its longest span (2h + T_max/2).
Measured (docs/dev-notes.md, "The drum's sliding work, an exact stick in
the cluster runs"): the piles struck from above and obliquely (seeds
0–3) −1.4 … −4.8 % against a penalty DEM with a converged stiff stick
(the step's own booking −95 % and −30 %; before this booking −0.9 … +2.9 %
from above, a sum whose contacts were −28 … −31 % on the pairs that slide
and the viscous stick's creep at stuck ones, and −8 … −17 % obliquely);
the drums: docs/drum2d.md ("Sliding work and the energy books").

Measured (h = 2 ms, spruce 0.4 GPa, 1 m logs, μ = 0.4, e = 0.2 unless
said) against independent references — the damped pair's closed form for
binary impacts, elsewhere a penalty DEM of the whole scene at h/3200
(linear spring–dashpot, Coulomb, spins; the tests' DEM at h/400 is itself
first order at the touch: −3 % on a binary impact with e = 0.05) — the
peak's error, before (0.1/ω_max, the touch first order) → now
(0.3/ω_max, a third of the sub-steps), log–log; log–shell:

- binary 0.12 + 0.2 m at 2 m/s: +1.3 → −0.3 % (e = 1: 0.0 → +0.1 %);
- binary, 0.10–0.14, 0.14–0.14, 0.10–0.20 m, e = 0.05, 0.5, 1, and
  frictionless: −1.4 … +4.6 → −0.1 … +0.4 %;
- binary 30° oblique, e = 0.05, 0.2, 0.5, μ = 0.4, 0.6: −1.1 … +1.3 →
  −0.7 … −0.5 %;
- a log struck on a log on the shell: +1.1 → −0.5 %; +0.2 → −0.2 %;
- columns of 5 and 8 struck at 3 m/s (e = 0.2, 1): 0.0 … +0.4 →
  −0.6 … +0.1 %; −0.1 … 0.0 → −0.1 … +0.3 %;
- the same struck late (0.6–0.97 of the step): −1.1 … +2.9 → −1.0 … +0.2 %;
  −0.3 … +0.1 → −0.1 … +0.2 %;
- columns of 3 and 6 (e = 0.05, 0.5, μ = 0.6): −0.6 … +0.6 → −0.2 … 0.0 %;
  −0.2 … +0.2 → −0.2 … +0.1 %;
- piles of 6 struck obliquely (μ = 0, 0.4, 0.6): −0.6 … −0.2 →
  −0.5 … −0.2 %; −0.2 … +1.2 → −0.2 … +1.7 %

— within 4.6 % before, 1.7 % now (the pile's log–shell peak comes through
its friction, whose regularization differs from the DEM's: against the
tests' DEM at h/400, −1.2 … −0.4 → −0.8 … +0.1 %).  On 70 steps of the
500-log bed (the example, steps 300–1 000; 20 of seed 2, not tuned on),
each run h + T/2 long against itself at 0.025/ω_max: the step's largest
peak −1.2 … +3.4 → −0.5 … +0.1 % (seed 2: −0.7 … +3.0 → −0.3 … +0.1 %),
its 99th percentile −0.9 … +1.8 → −0.3 … +0.3 % (−0.2 … +0.1 →
−0.5 … +0.3 %).  The pair's half-sine, before
the cluster runs, gave −35 %, +27 %, +22 to +87 % and +12 to +27 % on the
binary, log-on-log, columns and pile (log–shell of the pile −76 %).

The sub-step's size.  The figures above are at 0.3/ω_max; the runs are at
0.4/ω_max, a quarter fewer sub-steps (the 500-log bed's runs were ~4.5 ms
of its ~20 ms step; each goes on to ~1.7 (h + T/2), every bed-wide run
holding a rise).  Against the same references, the tests' cases and
sixteen more binaries (four touch phases each): within 1.7 % at 0.4 (1.2 %
at 0.3), the binaries against the closed form within 0.8 % (Verlet's
amplitude error +(ωτ)²/8 on the elastic pair: +0.4 → +0.8 %).  On whole
revolutions (the 500-log example, seeds 1 and 2, and 200 logs, from
t = 1.5 s, 2 583 steps each; every run of a step at both sub-steps, the
trajectory being the same): the steps' log–log and log–steel peaks move by
−0.9 … +0.5 % (1st to 99th percentile), and the forces the steps' peaks
exceed 1, 10 and 50 times a second by −1.0 … +0.2 % (the histograms' 50
and 99 % log–steel bins the same).  At 0.45/ω_max the elastic binaries
read up to +0.98 % (the test's bound is 1 %), at 0.5 +1.27 %, and the
rates moved by up to −1.0 and −1.3 %.

What it leaves out: contacts to discs outside the cluster (they carried no
impulse in the step) and the bodies outside it (frozen); the lifters'
curvature of motion within the step; and a wave that outlasts 2h + T_max/2.
The run goes on past h + T_max/2 while a contact's force still rises (by
1 % per 0.3/ω_max over its largest within the last T_max/2, and at least
SIGNIFICANT of the run's largest force: a wave on its way through the
chain, not a settling contact of a bed-wide cluster), up to 2h + T_max/2: an impact late in the step reaches
its own contact's peak by h + T/2, but a far one's comes later, and the
next step's contacts are closed — no impact there to run again.  Ended at
h + T_max/2, a column of 8 struck at 3 m/s read its shell peak −12 % where
the top log touched 60 % into a 2 ms step, −72 % at 80 %, −89 % at 90 %;
continued, within 1.1 % at every phase (0.9 % at h = 1 ms, 2.7 % at 4 ms;
test_drum2d_peaks.py).  Its cost: a cluster is the connected
part of the bed, so a settled bed's every step with an impact runs the bed
(compiled; measured in docs/drum2d.md, "Peak forces").  It is not cut to the
logs the impact's wave reaches: within h + T/2 that is ~15 contacts from
each of a turning bed's 20–56 impacts a step, the whole bed.
The step itself — velocities, positions, the books — is the certified
contact problem's, untouched: this is a measurement of the step, not a
second model of it.  A cluster with a rigid contact (``shell_elasticity``
alone: rigid log–log) has no spring to resolve: its impacts keep the pair's
half-sine π r_N/T, the others the mean.
"""

from __future__ import annotations

import numpy as np

from .records import sliding_speed

__all__ = ["step_forces", "damping_ratio"]

#: ω_max τ of the cluster runs (module docstring)
OMEGA_TAU = 0.4


def damping_ratio(e: float) -> float:
    """ζ of a linear spring–dashpot whose restitution is ``e`` (0 < e <= 1;
    e = 0 is critical damping, ζ = 1)."""
    if e <= 0.0:
        return 1.0
    le = np.log(e)
    return float(-le / np.sqrt(np.pi ** 2 + le * le))


def step_forces(c, r_n, h, comp, impact, m_star, *, positions, velocities, masses, radii,
                inverse_inertia, mu, shell_radius, restitution, gravity, sliding_work):
    """(forces [N], sliding work [J]) of the step's contacts for the
    statistics and the books (module docstring): contacts ``c`` (active),
    impulses ``r_n`` [N·s], compliance ``comp`` [m/N], ``impact``
    (laws.ContactLaw.normal_terms), reduced masses ``m_star`` [kg], friction
    coefficients ``mu``; the step's start ``positions`` (n, 2) [m] and
    generalized ``velocities`` (3n,); the discs' ``inverse_inertia`` (n,)
    [1/(kg m²)], 0 where held from rolling; ``sliding_work`` the step's own
    |r_T| s̄ [J] (records.sliding_speed), to which a cluster run's contacts
    add what the run slid beyond its own linear-slip estimate ("Sliding
    work")."""
    F = r_n / h
    work = np.array(sliding_work, float)
    T = 2.0 * np.pi * np.sqrt(m_star * comp)
    pulse = impact & (T > 0) & (T < np.pi * h)
    if not pulse.any():
        return F, work
    from .impact_kernel import cluster_forces   # numba: imported where it runs

    # the clusters (connected through the contacts loaded in the step) found
    # and run in one compiled call: as scipy's connected_components and a
    # NumPy mask per cluster they were 0.2–0.3 ms a step of the 500-log bed
    books = np.full((5, c.m), np.nan)
    cluster_forces(F, np.asarray(r_n, float), T, pulse, (r_n > 0) | impact,
                   np.asarray(c.i, np.int64), np.asarray(c.j, np.int64),
                   np.asarray(c.kind, np.int64), np.asarray(c.gap, float),
                   np.ascontiguousarray(c.normal, float), np.asarray(c.w, float),
                   np.asarray(comp, float), np.asarray(m_star, float), np.asarray(mu, float),
                   np.ascontiguousarray(positions, float), np.asarray(velocities, float),
                   np.asarray(masses, float), np.asarray(radii, float),
                   np.asarray(inverse_inertia, float), damping_ratio(restitution),
                   float(gravity), float(shell_radius), float(h), OMEGA_TAU, books)
    ran = ~np.isnan(books[0])
    cone_work, impulse, slip_start, slip_end, touch = books[:, ran]
    beyond = cone_work - np.abs(impulse) * sliding_speed(slip_start, slip_end)
    booked = np.maximum(0.0, work[ran] + beyond)
    # an impact whose whole touch lies within the run books the run's slip:
    # the linear estimates read slips from before the touch and after the
    # discs parted, and nothing else books that touch
    within = (touch == 0) & pulse[ran]
    booked[within] = cone_work[within]
    work[ran] = booked
    return F, work
