"""An experiment: a two-level (coarse) correction for NSGS's slow mode on 2-D
deep beds and dense piles — measured against plain NSGS; not integrated, as
it removed no sweeps (docs/dev-notes.md, "A coarse correction for NSGS's
slow mode", has the tables, the reasons and the decision).

Why it was tried.  Gauss–Seidel over the contacts moves a load one contact
per sweep, so a bed-wide error (the weight of a deep bed not yet carried
down to the shell) would take about the bed's depth squared in sweeps; a
coarse correction removes smooth errors in one solve of a small system, as
in algebraic multigrid.

The correction (2-D problems; r = (r_N, r_T) per contact in impulse units,
u = W r + q in velocity units).  The contact states are frozen at the
iterate: open (r_N = 0: r stays 0), sticking (|r_T| < μ r_N: u_N = u_T = 0,
both components free), sliding (|r_T| = μ r_N: u_N = 0, r moves along
(1, r_T/r_N)).  On these states the step's equations are linear: with B the
free directions and C the tested components, Cᵀ W (r + B x) + Cᵀ q = 0.
x is restricted to a coarse space, x = P c, and the Galerkin problem
(Pᵀ Cᵀ W B P) c = −Pᵀ Cᵀ u is solved dense (least squares with a relative
cut-off: W is singular on a rigid pile, and so may the coarse matrix be);
then r += B P c, projected back onto the cones, and the sweeps go on.  The
coarse spaces, on aggregates of neighbours (greedy aggregation, ``rounds``
times): constant (r_N, r_T) amounts per contact aggregate; a uniform stress
per contact aggregate (contact c's share (n·σn, t·σn)); the bodies' motions,
Hᵀ P_b with P_b piecewise constant per body aggregate and dof, smoothed by
damped Jacobi on H Hᵀ.  Nothing here decides an answer: the certificate
(certified_error) judges every point, as in the solver.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/nsgs_coarse.py piles
    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/nsgs_coarse.py drum --logs 500,2000

(the drum's beds come from benchmarks/drum.py's cache, out/bench/drum2d/,
settled there on first use: ~10 minutes at 2 000 logs).
"""

from __future__ import annotations

import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import scipy.linalg as sla  # noqa: E402
import scipy.sparse as sp  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, ROOT)
import qpcontact.solvers.friction.hybrid as hybrid  # noqa: E402
from qpcontact.core.friction_problem import FrictionProblem  # noqa: E402
from qpcontact.judge.friction_certificate import certified_error  # noqa: E402
from qpcontact.solvers.friction.nsgs import NSGS  # noqa: E402


def aggregates(problem, rounds=2):
    """Contact → aggregate id: greedy aggregation on W's block graph (two
    contacts are neighbours when they share a body), repeated ``rounds``
    times on the graph of the aggregates."""
    _, bptr, bcols, _ = problem.W_blocks
    n = problem.n_contacts
    return _aggregate(sp.csr_matrix((np.ones(bcols.size), bcols, bptr), shape=(n, n)), rounds)


def _aggregate(G, rounds):
    """Node → aggregate id after ``rounds`` rounds of :func:`_greedy`, each
    on the graph of the last round's aggregates."""
    label = np.arange(G.shape[0])
    for _ in range(rounds):
        agg = _greedy(G)
        label = agg[label]
        m = agg.max() + 1
        S = sp.csr_matrix((np.ones(agg.size), (np.arange(agg.size), agg)), shape=(agg.size, m))
        G = (S.T @ G @ S).tocsr()
        G.setdiag(0)
        G.eliminate_zeros()
    return label


def _greedy(G):
    """One round: a node whose neighbours are all free roots an aggregate of
    itself and them; the rest join a neighbouring aggregate."""
    n = G.shape[0]
    agg = np.full(n, -1)
    ptr, idx = G.indptr, G.indices
    k = 0
    for i in range(n):
        nb = idx[ptr[i]:ptr[i + 1]]
        if agg[i] < 0 and np.all(agg[nb] < 0):
            agg[i] = k
            agg[nb] = k
            k += 1
    for _ in range(3):
        for i in np.flatnonzero(agg < 0):
            nb = idx[ptr[i]:ptr[i + 1]]
            taken = nb[agg[nb] >= 0]
            if taken.size:
                agg[i] = agg[taken[0]]
    lone = agg < 0
    agg[lone] = k + np.arange(lone.sum())
    return agg


def coarse_correction(problem, r, label, rcond=1e-10, normals=None):
    """r after one coarse correction on the states frozen at r (module
    docstring); returns (new r, coarse size).  With ``normals`` (m, 2; the
    tangent t = ẑ × n) the coarse unknowns are a uniform stress σ per
    aggregate (σ_xx, σ_yy, σ_xy), contact c's share (n·σn, t·σn) — the
    forces a uniform stress puts through a contact; else constant (r_N, r_T)
    amounts per aggregate."""
    R = r.reshape(-1, 2)
    rn, rt, mu = R[:, 0], R[:, 1], problem.mu
    closed = rn > 0
    slide = closed & (np.abs(rt) >= mu * rn * (1 - 1e-9))
    stick = closed & ~slide
    cl = np.flatnonzero(closed)
    if cl.size == 0:
        return r, 0
    a = np.unique(label[cl], return_inverse=True)[1].ravel()
    ratio = np.where(slide[cl], rt[cl] / np.where(rn[cl] > 0, rn[cl], 1.0), 0.0)
    sk = stick[cl]
    if normals is None:       # (r_N, r_T) amounts: row 0 -> column 2a, row 1 -> 2a + 1
        kn = np.zeros((cl.size, 2, 2))
        kn[:, 0, 0] = 1.0
        kn[:, 1, 1] = 1.0
        width = 2
    else:                     # σ -> (n·σn, t·σn)
        n = normals[cl]
        nx, ny = n[:, 0], n[:, 1]
        tx, ty = -ny, nx
        kn = np.stack([np.column_stack([nx * nx, ny * ny, 2 * nx * ny]),
                       np.column_stack([tx * nx, ty * ny, tx * ny + ty * nx])], axis=1)
        width = 3
    m = width * (a.max() + 1)
    cols = width * a[:, None] + np.arange(width)[None, :]          # (k, width)
    # the free directions: sticking both rows; sliding row 0 along (1, r_T/r_N)
    row_t = np.where(sk[:, None], kn[:, 1, :], ratio[:, None] * kn[:, 0, :])
    rows_b = np.concatenate([np.repeat(2 * cl, width), np.repeat(2 * cl + 1, width)])
    vals_b = np.concatenate([kn[:, 0, :].ravel(), row_t.ravel()])
    cols_b = np.concatenate([cols.ravel(), cols.ravel()])
    BP = sp.csc_matrix((vals_b, (rows_b, cols_b)), shape=(r.size, m))
    # the tested components: sticking both, sliding the normal one
    st = np.flatnonzero(sk)
    rows_c = np.concatenate([np.repeat(2 * cl, width), np.repeat(2 * cl[st] + 1, width)])
    vals_c = np.concatenate([kn[:, 0, :].ravel(), kn[st, 1, :].ravel()])
    cols_c = np.concatenate([cols.ravel(), cols[st].ravel()])
    CP = sp.csc_matrix((vals_c, (rows_c, cols_c)), shape=(r.size, m))
    W = problem.W
    u = np.asarray(W @ r).ravel() + problem.q
    A = (CP.T @ (W @ BP)).toarray()
    g = CP.T @ u
    c = sla.lstsq(A, -g, cond=rcond, lapack_driver="gelsd")[0]
    r = r + BP @ c
    R = r.reshape(-1, 2)
    _project_2d_all(R, mu)
    return r, m


def body_basis(Ht, rounds=2, smooth=1, omega=2.0 / 3.0):
    """The coarse basis in the contacts' space from a coarse basis of the
    bodies' motions: E = Hᵀ P_b, P_b piecewise constant per aggregate of
    bodies and per dof kind (x, y, θ), smoothed ``smooth`` times by damped
    Jacobi on the bodies' graph K = H Hᵀ (smoothed aggregation).  Why the
    bodies': W = Hᵀ M⁻¹ H, so its small eigenvalues' vectors are Hᵀ z with z
    a smooth eigenvector of M⁻¹ H Hᵀ — a smooth motion of the bodies, whose
    relative motion at each contact gives the slow force field."""
    Ht = sp.csr_matrix(Ht)
    K = (Ht.T @ Ht).tocsr()
    nd = K.shape[0]
    body = np.arange(nd) // 3
    nb = body.max() + 1
    # the bodies' graph: two bodies touch when a contact row has both
    Kb = sp.csr_matrix((np.ones(K.nnz), (body[K.nonzero()[0]], body[K.nonzero()[1]])),
                       shape=(nb, nb))
    Kb.data[:] = 1.0
    Kb.setdiag(0)
    Kb.eliminate_zeros()
    label = _aggregate(Kb, rounds)
    na = label.max() + 1
    P = sp.csr_matrix((np.ones(nd), (np.arange(nd), 3 * label[body] + np.arange(nd) % 3)),
                      shape=(nd, 3 * na))
    d = K.diagonal()
    Dinv = sp.diags(np.where(d > 0, 1.0 / np.where(d > 0, d, 1.0), 0.0))
    for _ in range(smooth):
        P = P - omega * (Dinv @ (K @ P))
    return sp.csr_matrix(Ht @ P), na


def coarse_correction_body(problem, r, E, rcond=1e-10):
    """One coarse correction with the contacts' basis E (m2 x k, from
    :func:`body_basis`) restricted to the free directions of the states
    frozen at r; (new r, coarse size)."""
    R = r.reshape(-1, 2)
    rn, rt, mu = R[:, 0], R[:, 1], problem.mu
    closed = rn > 0
    slide = closed & (np.abs(rt) >= mu * rn * (1 - 1e-9))
    stick = closed & ~slide
    ratio = np.where(slide, rt / np.where(rn > 0, rn, 1.0), 0.0)
    keep_n = closed.astype(float)
    keep_t = stick.astype(float)
    EN, ET = E[0::2], E[1::2]
    # free directions: normal row kept on closed contacts; tangential row kept
    # where sticking, ratio x the normal row where sliding
    BN = sp.diags(keep_n) @ EN
    BT = sp.diags(keep_t) @ ET + sp.diags(ratio) @ EN
    CT_ = sp.diags(keep_t) @ ET
    n2 = r.size
    B = _interleave(BN, BT, n2)
    C = _interleave(BN, CT_, n2)
    used = np.flatnonzero(np.asarray(abs(C).sum(0)).ravel() > 0)
    if used.size == 0:
        return r, 0
    B, C = B[:, used], C[:, used]
    u = np.asarray(problem.W @ r).ravel() + problem.q
    A = (C.T @ (problem.W @ B)).toarray()
    g = C.T @ u
    c = sla.lstsq(A, -g, cond=rcond, lapack_driver="gelsd")[0]
    r = r + B @ c
    _project_2d_all(r.reshape(-1, 2), mu)
    return r, used.size


def _interleave(N, T, n2):
    N, T = sp.coo_matrix(N), sp.coo_matrix(T)
    return sp.csc_matrix((np.concatenate([N.data, T.data]),
                          (np.concatenate([2 * N.row, 2 * T.row + 1]),
                           np.concatenate([N.col, T.col]))), shape=(n2, N.shape[1]))


class BlockFrozen:
    """A block Gauss–Seidel sweep on the frozen states: each aggregate's
    contacts solved together (their frozen-state linear system, least squares
    where singular) with the others held, the velocities updated after each
    block — what removes a self-stress mode that lives inside one block."""

    def __init__(self, problem, label):
        W = sp.csc_matrix(problem.W)
        self.problem = problem
        self.blocks = []
        for a in range(label.max() + 1):
            c = np.flatnonzero(label == a)
            idx = np.ravel(np.column_stack([2 * c, 2 * c + 1]))
            cols = W[:, idx]
            self.blocks.append((c, idx, cols, cols[idx].toarray()))

    def sweep(self, r, rcond=1e-12):
        p = self.problem
        mu = p.mu
        u = np.asarray(p.W @ r).ravel() + p.q
        for c, idx, cols, Waa in self.blocks:
            R = r[idx].reshape(-1, 2)
            rn, rt = R[:, 0], R[:, 1]
            closed = rn > 0
            if not closed.any():
                continue
            slide = closed & (np.abs(rt) >= mu[c] * rn * (1 - 1e-9))
            stick = closed & ~slide
            k = c.size
            # free directions B (2k x f) and tested rows T (indices into 2k)
            colsB, test = [], []
            for j in range(k):
                if stick[j]:
                    e0 = np.zeros(2 * k); e0[2 * j] = 1
                    e1 = np.zeros(2 * k); e1[2 * j + 1] = 1
                    colsB += [e0, e1]
                    test += [2 * j, 2 * j + 1]
                elif slide[j]:
                    e0 = np.zeros(2 * k); e0[2 * j] = 1; e0[2 * j + 1] = rt[j] / rn[j]
                    colsB.append(e0)
                    test.append(2 * j)
            B = np.column_stack(colsB)
            A = Waa[test] @ B
            x = sla.lstsq(A, -u[idx][test], cond=rcond, lapack_driver="gelsd")[0]
            d = B @ x
            new = (r[idx] + d).reshape(-1, 2)
            _project_2d_all(new, mu[c])
            d = new.ravel() - r[idx]
            r[idx] = new.ravel()
            u += cols @ d
        return r


def _project_2d_all(R, mu):
    rn, rt = R[:, 0].copy(), R[:, 1].copy()
    t = np.abs(rt)
    inside = t <= mu * rn
    dead = ~inside & (mu * t <= -rn)
    edge = ~inside & ~dead
    a = (mu * t + rn) / (1 + mu * mu)
    R[dead] = 0.0
    R[edge, 0] = a[edge]
    R[edge, 1] = np.sign(rt[edge]) * mu[edge] * a[edge]


class CoarseNSGS(NSGS):
    """NSGS with a coarse correction after every ``every`` sweeps."""

    every = 20
    rounds = 2
    basis = None      # E from body_basis: the bodies' coarse space; else aggregates
    normals = None    # with aggregates: a uniform stress per aggregate (coarse_correction)

    def __init__(self, problem, r0=None, **kw):
        super().__init__(problem, r0, **kw)
        t = time.process_time()
        self.label = aggregates(problem, self.rounds) if self.basis is None else None
        self.coarse_cpu = time.process_time() - t
        self.corrections = 0

    def sweep(self, n):
        left = int(n)
        while left > 0:
            k = min(left, self.every - self.done % self.every or self.every)
            super().sweep(k)
            left -= k
            if self.done % self.every == 0:
                t = time.process_time()
                if self.basis is None:
                    self.r, _ = coarse_correction(self.problem, self.r, self.label,
                                                  normals=self.normals)
                else:
                    self.r, _ = coarse_correction_body(self.problem, self.r, self.basis)
                self.coarse_cpu += time.process_time() - t
                self.corrections += 1
        return self.r


def trace(problem, r0, *, omega, every=None, rounds=2, sweeps=2000, check=10, cpu_limit=60.0,
          stop=1e-9, basis=None, normals=None):
    """Sweeps (with the coarse correction every ``every`` if given) from r0:
    the (sweeps, CPU s, certified error) at each check."""
    if every is None:
        gs = NSGS(problem, r0, omega=omega)
    else:
        CoarseNSGS.every, CoarseNSGS.rounds = every, rounds
        CoarseNSGS.basis, CoarseNSGS.normals = basis, normals
        gs = CoarseNSGS(problem, r0, omega=omega)
    t0 = time.process_time()
    out = [(0, 0.0, certified_error(problem, gs.r))]
    while gs.done < sweeps and time.process_time() - t0 < cpu_limit:
        gs.sweep(check)
        err = certified_error(problem, gs.r)
        out.append((gs.done, time.process_time() - t0, err))
        if err < stop or not np.isfinite(err):
            break
    return np.array(out)


def first_below(tr, level):
    hit = np.flatnonzero(tr[:, 2] <= level)
    return (int(tr[hit[0], 0]), tr[hit[0], 1]) if hit.size else None


def capture_drum(n, steps, warmup=5, settle=150, cache=None):
    """The drum's warm-started step problems on benchmarks/drum.py's bed of
    n logs (cached there), as its stepper solves them: a list of dicts with
    the problem, r0, the solve's options, H (3n x m) and the contacts'
    normals; the last ``steps`` of warmup + steps steps."""
    import formulations.drum2d.stepper as stepper
    from benchmarks.drum import EFFECTS_2D, H2D, RESTITUTION, drum2d_shell, settled_bed
    from formulations.drum2d import Drum2D

    cache = cache or os.path.join(ROOT, "out", "bench", "drum2d")
    discs, _ = settled_bed(n, settle, cache)
    got, last = [], {}
    inner_solve, inner_assemble = stepper.solve, Drum2D._assemble

    def assemble(self, c, u_minus, u_free, minv, *args):
        last.update(H=c.H.tocsc().copy(), normal=c.normal.copy(), minv=np.asarray(minv).copy())
        return inner_assemble(self, c, u_minus, u_free, minv, *args)

    def solve(prob, **kw):
        if "r0" in kw:
            got.append(dict(problem=prob, r0=np.asarray(kw["r0"]), H=last["H"],
                            normal=last["normal"], minv=last["minv"],
                            options={k: v for k, v in kw.items() if k != "r0"}))
        return inner_solve(prob, **kw)

    stepper.solve, Drum2D._assemble = solve, assemble
    try:
        Drum2D(discs, drum2d_shell(), EFFECTS_2D, restitution=RESTITUTION).simulate(
            H2D, warmup + steps, keep_contacts=False)
    finally:
        stepper.solve, Drum2D._assemble = inner_solve, inner_assemble
    return got[-steps:]


def pile_case(n):
    """The 2-D compact pile of about n contacts (agitation 0.1, δ = 0.005)
    with its Hᵀ (m2 x 3 bodies) and the contacts' normals, rebuilt from the
    pile's geometry."""
    from qpcontact.cases import piles

    pile = piles.disc_pile(n, agitation=0.1, polydispersity=0.005)
    a, b = pile.pairs[:, 0], pile.pairs[:, 1]
    normal = np.zeros((a.size, 2))
    disc = a >= 0
    d = pile.centers[b[disc]] - pile.centers[a[disc]]
    normal[disc] = d / np.linalg.norm(d, axis=1)[:, None]
    for w, n_w in enumerate(([0.0, 1.0], [1.0, 0.0], [-1.0, 0.0])):   # floor, left, right
        normal[a == -1 - w] = n_w
    return pile.problem, piles._jacobian(a, b, normal, pile.radii, 2), normal


LEVELS = (1e-3, 1e-4, 1e-6, 1e-8)


def variants(Ht, normals):
    return [("plain NSGS", {}),
            ("uniform stress per contact aggregate, 1 round, every 20",
             dict(every=20, rounds=1, normals=normals)),
            ("(r_N, r_T) per contact aggregate, 1 round, every 20", dict(every=20, rounds=1)),
            ("(r_N, r_T) per contact aggregate, 2 rounds, every 20", dict(every=20, rounds=2)),
            ("bodies' motions, 1 round, smoothed once, every 20",
             dict(every=20, basis=body_basis(Ht, 1, 1)[0])),
            ("bodies' motions, 2 rounds, smoothed once, every 20",
             dict(every=20, basis=body_basis(Ht, 2, 1)[0]))]


def sweeps_table(cases, omega, sweeps, cpu_limit):
    """Sweeps (CPU s) to each of LEVELS, per case and variant."""
    print("| case | variant | " + " | ".join(f"to {x:.0e}" for x in LEVELS) + " |")
    print("|---|---|" + "---|" * len(LEVELS))
    for name, prob, r0, Ht, normals in cases:
        for label, kw in variants(Ht, normals):
            tr = trace(prob, r0, omega=omega, sweeps=sweeps, cpu_limit=cpu_limit, **kw)
            hits = [first_below(tr, x) for x in LEVELS]
            print(f"| {name} | {label} | " + " | ".join(
                f"{h[0]} ({h[1]:.2f} s)" if h else f"- (best {tr[:, 2].min():.1e})" for h in hits)
                + " |", flush=True)


def compliance_table(steps, factors, sweeps):
    """Plain NSGS's sweeps to LEVELS on the drum's problems with the
    contacts' compliance D (W = Hᵀ M⁻¹ H + D) scaled by each factor: the
    bed's depth unchanged, the ratio D / W_nn changed."""
    for f in factors:
        tot = np.zeros(len(LEVELS))
        for g in steps:
            p, Ht = g["problem"], g["H"].T
            rigid = np.asarray((Ht @ sp.diags(g["minv"]) @ Ht.T).diagonal()).ravel()
            D = p.W.diagonal() - rigid
            p2 = FrictionProblem(sp.csc_matrix(p.W + sp.diags((f - 1.0) * D)), p.q, p.mu, 2)
            tr = trace(p2, g["r0"], omega=1.5, sweeps=sweeps, cpu_limit=30.0)
            tot += [h[0] if h else np.nan for h in (first_below(tr, x) for x in LEVELS)]
        print(f"| D x {f:g} | " + " | ".join(f"{x / len(steps):.0f}" for x in tot) + " |",
              flush=True)


def solver_table(steps, every=20, rounds=2, repeats=2):
    """The steps solved as the drum's stepper solves them (qpcontact.solve,
    nsgs-newton, the same certificate), plain and with the bodies' coarse
    space every ``every`` sweeps, alternated ``repeats`` times: CPU ms a
    solve, sweeps, steps certified."""
    import qpcontact

    for k in range(repeats):
        for coarse in (False, True):
            cpu, sweeps, ok = 0.0, 0, 0
            for g in steps:
                p = g["problem"]
                p = FrictionProblem(p.W, p.q, p.mu, 2)        # its cached blocks dropped
                opts = dict(g["options"])
                t = time.process_time()
                if coarse:
                    CoarseNSGS.every, CoarseNSGS.rounds = every, rounds
                    CoarseNSGS.basis, CoarseNSGS.normals = body_basis(g["H"].T, rounds, 1)[0], None
                    saved, hybrid.NSGS = hybrid.NSGS, CoarseNSGS
                try:
                    sol = qpcontact.solve(p, r0=g["r0"], **opts)
                finally:
                    if coarse:
                        hybrid.NSGS = saved
                cpu += time.process_time() - t
                sweeps += sol.iterations or 0
                ok += bool(sol.ok)
            print(f"| round {k} | {'coarse every %d' % every if coarse else 'plain'} | "
                  f"{1e3 * cpu / len(steps):.1f} ms | {sweeps / len(steps):.0f} | "
                  f"{ok}/{len(steps)} |", flush=True)


def main(argv=None):
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=("drum", "piles"))
    ap.add_argument("--logs", default="500,2000")
    ap.add_argument("--steps", type=int, default=12)
    ap.add_argument("--piles", default="2000,5000")
    ap.add_argument("--sweeps", type=int, default=10_000)
    ap.add_argument("--cpu", type=float, default=30.0, help="CPU s per trace at most")
    args = ap.parse_args(argv)
    if args.what == "piles":
        cases = []
        for n in (int(x) for x in args.piles.split(",")):
            prob, Ht, normals = pile_case(n)
            cases.append((f"2-D compact pile, {prob.n_contacts} contacts", prob,
                          np.zeros(2 * prob.n_contacts), Ht, normals))
        sweeps_table(cases, 1.3, args.sweeps, args.cpu)
    else:
        for n in (int(x) for x in args.logs.split(",")):
            steps = capture_drum(n, args.steps)
            cases = [(f"drum {n} logs, step {k}", g["problem"], g["r0"], g["H"].T, g["normal"])
                     for k, g in enumerate(steps)]
            sweeps_table(cases, 1.5, args.sweeps, args.cpu)
            print(f"\nplain NSGS, mean sweeps to {LEVELS} over the {len(steps)} steps of {n} "
                  "logs, the compliance D scaled (the depth unchanged):")
            compliance_table(steps, (0.25, 1.0, 4.0), args.sweeps)
            print("\n| round | variant | CPU a solve | sweeps | certified |\n|---|---|---|---|---|")
            solver_table(steps)
    print(f"(OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}; "
          f"load {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
