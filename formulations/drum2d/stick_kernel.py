"""Coulomb's stick made exact at each sub-step of a cluster run
(impact_kernel.cluster_peaks): the projected Gauss–Seidel correction of the
tangential forces.  SI units: m, s, kg, N.

A run integrates the cluster by velocity Verlet with sub-step τ: the force
at t + τ acts on the velocities from t + τ/2 to t + 3τ/2, so a contact's
slip at the next half step is

    u_T(t + 3τ/2) = u_T(t + τ/2) + τ (a_T,others + w_T F_T),

with a_T,others the relative tangential acceleration of its two bodies from
every other force (springs, gravity, the other contacts' friction) and
w_T = 1/m_a + r_a²/I_a (+ the other disc's) [1/kg] its tangential inverse
mass.  Stick is u_T(t + 3τ/2) = 0; Coulomb caps |F_T| <= μ F_N with F_N the
spring's force at t + τ.  Solving that for every contact of the cluster
at once is a small frictional problem on the sub-step; projected
Gauss–Seidel solves it contact by contact, each change applied to the
accelerations of its bodies before the next contact reads them, one sweep
a sub-step started from the last sub-step's forces (a stuck bed's forces
change little in τ, so the sweeps of successive sub-steps iterate on one
slowly moving problem).
This is the rigid stick of the 2-D step and of the converged
Cundall–Strack DEM (k_t → ∞), where the viscous law F_T = −γ u_T the runs
used alone crept under a steady load (u_T = F_T/γ): the struck piles'
sliding at the cone read 7.5–10 % below the DEM's with it, −1.4 … −4.3 %
with this (docs/dev-notes.md, "The drum's sliding work, an exact stick in
the cluster runs").  Cost: the 500-log revolution 51.7 s of CPU against
43.8 s with the viscous law (side by side).
"""

from __future__ import annotations

from qpcontact.core.compiled import njit

__all__ = ["exact_stick", "STICK_SWEEPS"]

#: sweeps a sub-step, from the last sub-step's forces: on the struck piles
#: one sweep books within 0.2 % of eight from the viscous law's guess
#: (test_drum2d_sliding.py's scenes), and the 500-log revolution the same
#: sliding with one as with two
STICK_SWEEPS = 1


@njit(fastmath=True)
def exact_stick(n0, a, b, ra, rb, ima, imb, iia, iib, mu, tau, F, Ft, ut_half, touched, nt, ax,
                ay, alpha, tx, ty, skip):
    """Coulomb's stick, exact at the sub-step (module docstring): each
    contact in touch, not touching within this sub-step (its force is the
    touch's), takes the force that stops its slip at t + 3τ/2, capped at
    μ F_N, by STICK_SWEEPS projected Gauss–Seidel sweeps.  On entry ``Ft``
    [N] holds the first guess (the last sub-step's forces, capped) and the
    accelerations ``ax``, ``ay``, ``alpha`` include it; each change is
    applied to them before the next contact reads them.  Contacts 0 .. n0 − 1
    are disc–disc (discs a[k], b[k]), the others a disc against a wall; ``tx``,
    ``ty`` the tangents _forces left, ``ut_half`` the half-step slips [m/s];
    ``skip`` a work array."""
    m = a.size
    for k in range(m):
        skip[k] = 1 if F[k] <= 0.0 else 0
    for t in range(nt):
        skip[touched[t]] = 1
    for _ in range(STICK_SWEEPS):
        for k in range(m):
            if skip[k] == 1:
                continue
            i = a[k]
            if k < n0:
                j = b[k]
                du = (tx[k] * (ax[i] - ax[j]) + ty[k] * (ay[i] - ay[j]) - ra[k] * alpha[i]
                      - rb[k] * alpha[j])
            else:
                j = -1
                du = tx[k] * ax[i] + ty[k] * ay[i] - ra[k] * alpha[i]
            w = ima[k] + imb[k] + ra[k] * iia[k] + rb[k] * iib[k]
            new = Ft[k] - (ut_half[k] + tau * du) / (tau * w)
            cap = mu[k] * F[k]
            if new > cap:
                new = cap
            elif new < -cap:
                new = -cap
            d = new - Ft[k]
            Ft[k] = new
            ax[i] += tx[k] * d * ima[k]
            ay[i] += ty[k] * d * ima[k]
            alpha[i] -= d * iia[k]
            if j >= 0:
                ax[j] -= tx[k] * d * imb[k]
                ay[j] -= ty[k] * d * imb[k]
                alpha[j] -= d * iib[k]
