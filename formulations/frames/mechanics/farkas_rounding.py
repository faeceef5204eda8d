"""Whether a Farkas vector of a frame's contact LCP proves something about
the frame, or only about the LCP's rounded data: the margin of q'y against a
bound on the rounding of q and M.

The proof.  The contact LCP (:mod:`.contact_lcp`) is w = M z + q, z >= 0,
w >= 0, with M = W R P (kN/m: the contact stiffness R mapped to the
contact unknowns by P, ±1, and W, ±1 and the friction coefficients f) and
q = W (R_F c - R g) (kN: the basic system's link forces under the load
combination c, and the gaps g in m).  A vector y >= 0 with M'y <= 0 and
q'y < 0 proves that no z >= 0 has M z + q >= 0, since y'(M z + q) =
(M'y)'z + q'y < 0: no contact forces in their cones balance the loads.
The proof is checked exactly on the stored doubles (:mod:`qpcontact.proofs`),
so it is exact about those data.  They are not the frame's: R and R_F come
from a solve of the basic system, whose matrix and loads are themselves
rounded as they are formed from the members and the loads, and q and M are
rounded as they are formed from R and R_F.  At the frame's verge (a
three-hinged portal with f exactly L/(4h); a portal pushed exactly to its
tipping load) the exact q'y is 0, and the rounded one is a few eps of its
terms either side: whether the frame "stands" or is "proved to give way"
was then the last bit's (section "A verdict decided by the last bits" of
docs/dev-notes.md).

The bound.  Write the frame's exact data as R + ΔR, R_F + ΔR_F and the
formed q, M with their formation's rounding.  For the same y,

    q*'y = q'y + y'W (ΔR_F c - ΔR g) + (formation),

    |q*'y - q'y| <= y'|W| (|ΔR_F| |c| + |ΔR| |g|) + γ y'(|q|-terms),

with |ΔR_F| <= δ_F and |ΔR| <= δ_R entry by entry.  δ_R, δ_F are the
accuracy the assembly already claims for R and R_F — R_ROUNDING times the
largest translational stiffness κ (kN/m) for R, R_ROUNDING times the case's
largest load (kN) for R_F: the thresholds below which their entries are
zeroed as noise — or, where larger, the correction one step of refinement
with the residual in extended precision makes to them (κ |Δx| on the link
rows: :func:`.refinement.refined_columns`), which is what a basic system
of condition above 1/R_ROUNDING leaves.  γ = (n_terms + 4) u covers the
formation of M, q_gap and q from R and R_F (each entry a sum of at most
that many products).

M's part stays as each proof checks it.  A Farkas vector's M'y is exactly
zero on many columns: a tangential pair's columns are each other's
negatives (M'y <= 0 on both is M'y = 0 on both), and M'y = P'R W'y = 0
where W'y is a rigid motion's link displacement, which R annihilates — in
the frame exactly, in R's rounded copy to its rounding.  Those zeros are
identities of the mechanics, not data: R's error keeps the frame's rigid
motions in its null space.  A margin on M'y itself rejected every
legitimate proof (dev-notes, "a deck 1e12 times stiffer"), and a bound
that treats R's entries as independently perturbed by δ_R (e = (|W| δ_R
|P|)'|y| against the columns, the proof then limited to openings below
(margin - bound) / Σ (M'y + e)⁺) rejected six load-path collapse proofs of
the test suite whose margins are 1e3 to 1e5 times their q bound (dev-notes).
So M'y <= 0 is what Lemke's proof checks exactly and what the load path's
proof bounds by its own z_bound; the rounding of the data is put on q'y,
where the verge is decided.

So a Farkas vector proves "no equilibrium" of the frame when its margin
-q'y exceeds the bound; else the load is at the frame's limit to
rounding, and nothing is proved either way.  Along the load p, margin and
bound are linear (the same y), which gives the loads at the limit to
rounding with that vector (:func:`rounding_bracket`), and a load path's
collapse proof is moved to where its margin clears
(:func:`beyond_rounding`).  What this does not bound: the stiffness and the
loads as formed from the members' and loads' data are taken as exact to
the same R_ROUNDING (a contrast above :data:`.refinement.CONTRAST` gets
no Farkas proof at all).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from . import banded_saddle, contact_lcp, refinement
from .load_combinations import combination_at
from .loads import VARIABLE

#: the unit roundoff of a double
_U = np.finfo(float).eps / 2


def proof_rounding(b, combo: dict, y) -> dict:
    """How far the Farkas vector ``y`` (doubles or rationals) of the contact
    LCP of ``combo`` ({case: factor}) stands from the rounding of its data,
    y scaled to max |y| = 1: {"margin": -q'y (kN, exact, then rounded),
    "bound": the bound on its rounding (kN), "proves": margin > bound}
    (module docstring).  y may be negative on rows whose w a branch of the
    load path's proof fixes to zero: its sizes count."""
    M, Q, q_gap, P, g, fric = contact_lcp.lcp_matrices(b)
    q, terms = contact_lcp.combination_q(Q, q_gap, b, combo)
    y = [v if isinstance(v, Fraction) else Fraction(float(v)) for v in y]
    top = max((abs(v) for v in y), default=Fraction(0))
    if top <= 0:
        return {"margin": 0.0, "bound": np.inf, "proves": False}
    y = [v / top for v in y]
    ay = np.abs(np.array([float(v) for v in y]))
    # q'y exactly (the contacts' unknowns: tens to a few hundred terms)
    margin = -float(sum((Fraction(float(qi)) * v for qi, v in zip(q, y) if v and qi),
                        Fraction(0)))
    d_R, d_F = data_accuracy(b)
    R = b["R"]
    Wy = np.asarray(b["abs_W"].T @ ay).ravel()             # |y|'|W|, per link
    c = np.abs(contact_lcp.factors(b, combo))
    n_terms = R.shape[0] + c.size + 4
    bound = float(Wy @ (d_F @ c) + Wy @ (d_R @ np.abs(g))
                  + n_terms * _U * (terms @ ay + Wy @ (np.abs(R) @ np.abs(g))))
    return {"margin": margin, "bound": bound, "proves": bool(margin > bound)}


def rounding_bracket(b, const: dict, var: dict, y) -> tuple[float, float]:
    """The loads p >= 0 (``const`` + p ``var``) at which the Farkas vector
    ``y``'s margin is within its rounding bound (:func:`proof_rounding`):
    (p_lo, p_hi), p_hi = inf where the margin never clears it.  Both are
    linear in p (the bound through |c| = |const + p var|, linear where no
    case is in both with opposite signs, as in the frame's split)."""
    def at(p):
        combo = combination_at(const, var, p)
        r = proof_rounding(b, combo, y)
        return r["margin"], r["bound"]

    (m0, b0), (m1, b1) = at(0.0), at(1.0)
    dm, db = m1 - m0, b1 - b0
    # margin(p) = m0 + p dm within ±(b0 + p db)
    hi = (b0 - m0) / (dm - db) if dm > db else (np.inf if m0 <= b0 else 0.0)
    lo = (-b0 - m0) / (dm + db) if dm + db > 0 else (0.0 if m0 >= -b0 else np.inf)
    return max(lo, 0.0), max(hi, 0.0)


def verge_words(r: dict, bracket=None) -> str:
    """The words for a Farkas vector within its rounding (``r`` from
    :func:`proof_rounding`; ``bracket`` from :func:`rounding_bracket`)."""
    where = ""
    if bracket is not None:
        lo, hi = bracket
        where = (f"; with this vector the loads from p = {lo:.15g} to {hi:.15g} are at "
                 "the limit to rounding" if np.isfinite(hi) else
                 f"; with this vector every load from p = {lo:.15g} on is at the limit "
                 "to rounding (the margin grows no faster than its rounding)")
    why = (f"not beyond the bound {r['bound']:.2e} on the rounding of the data it is "
           "computed from (R, R_F and their products)")
    return (f"the load is at the frame's limit to rounding: a Farkas vector of the contact LCP "
            f"(y >= 0, M'y <= 0, q'y < 0), which holds on its rounded data, has the margin -q'y = "
            f"{r['margin']:.2e}, {why}; nothing is proved either way{where}")


def lcp_proof_vector(sol):
    """The Farkas vector a method's result proves its LCP infeasible by
    (the rationals it was checked with where they are kept), or None."""
    proof = sol.stats.get("proof")
    if proof is not None and getattr(proof, "kind", None) == "infeasible":
        return proof.vector.get("exact", {}).get("z") or proof.vector["z"]
    return sol.stats.get("farkas") if sol.stats.get("proved_infeasible") else None


def judge_proof(sol, b, combo: dict) -> None:
    """Where ``sol``'s proof that the LCP of ``combo`` has no solution is
    exact on the rounded data but within their rounding
    (:func:`proof_rounding`), it no longer counts as one: its stats say so
    (``stats["verge"]``, the words) and not "proved", so the frame's routes
    go on (the load path may still certify an equilibrium) and what they
    cannot settle is no proof.  Unchanged where the proof stands, or where
    none was made, or where no Farkas vector is a proof at all
    (:func:`.refinement.is_refined`)."""
    y = lcp_proof_vector(sol)
    if y is None or refinement.is_refined(b) or len(y) != contact_lcp.lcp_matrices(b)[0].shape[0]:
        return      # (a vector of another form than the LCP's rows: not read here)
    r = proof_rounding(b, combo, y)
    if r["proves"]:
        return
    bracket = None
    if VARIABLE in combo:
        const = {k: v for k, v in combo.items() if k != VARIABLE}
        bracket = rounding_bracket(b, const, {VARIABLE: 1.0}, y)
    sol.stats.update(proved_infeasible=False, proof=None, verge=verge_words(r, bracket))


def collapse_rounding(b, const: dict, var: dict, proof: dict) -> dict | None:
    """A load path's collapse proof (:mod:`qpcontact.proofs.parametric`:
    Farkas vectors, one per pattern of the branch and bound, each proving
    its pattern empty for every p >= ``proof["p_limit"]`` on the rounded
    data) judged by the same bound (:func:`proof_rounding`): None where
    every leaf proves beyond the rounding at p_limit; else the worst leaf's
    rounding and "p_clear", the load from which every leaf does (inf where
    some leaf's margin never clears)."""
    leaves = proof.get("leaves") or [{"y": proof["farkas"]}]
    p = float(proof["p_limit"])
    combo = combination_at(const, var, p)
    worst, clear = None, p
    for leaf in leaves:
        r = proof_rounding(b, combo, leaf["y"])
        if r["proves"]:
            continue
        worst = r if worst is None or r["margin"] - r["bound"] < worst["margin"] - worst["bound"] \
            else worst
        clear = max(clear, rounding_bracket(b, const, var, leaf["y"])[1])
    if worst is None:
        return None
    return dict(worst, p_clear=clear)


def beyond_rounding(b, const: dict, var: dict, proof: dict) -> tuple[dict, str | None]:
    """(the collapse proof, None) with its p_limit raised where needed to
    the load from which each leaf's margin clears its rounding
    (:func:`collapse_rounding`: the same vectors prove every p beyond, on
    the rounded data, and their margin grows faster than its rounding);
    (the proof, the words) where no load does."""
    rounding = collapse_rounding(b, const, var, proof)
    if rounding is None:
        return proof, None
    if np.isfinite(rounding["p_clear"]):
        # a hair beyond the crossing, which is computed in doubles
        moved = dict(proof, p_limit=rounding["p_clear"] * (1.0 + 1e-12) + 1e-300)
        if collapse_rounding(b, const, var, moved) is None:
            return moved, None
    return proof, verge_words(rounding, (float(proof["p_limit"]), rounding["p_clear"]))


def data_accuracy(b) -> tuple[np.ndarray, np.ndarray]:
    """(δ_R, δ_F): each entry of R (links x links, kN/m) and of R_F (links x
    cases, kN) known to within this — the assembly's zeroing threshold, or
    one extended-precision refinement step's correction where larger (made
    once per assembly, on first use)."""
    if "R_accuracy" in b:
        return b["R_accuracy"]
    nf, kappa = b["nf"], b["kappa"]
    nl = b["R"].shape[0]
    rhs = banded_saddle.dislocations(kappa, *contact_lcp.basic_columns(b))
    x = b["lu"].solve(rhs)
    x1, _ = refinement.refined_columns(b, rhs, x, steps=1)
    change = kappa * np.abs(x1[nf:] - x[nf:])
    d_R = np.maximum(contact_lcp.R_ROUNDING * kappa, change[:, :nl])
    d_R = np.maximum(d_R, d_R.T)
    d_F = np.maximum(contact_lcp.R_ROUNDING * contact_lcp.load_sizes(b)[None, :],
                     change[:, nl:])
    b["R_accuracy"] = (d_R, d_F)
    return b["R_accuracy"]
