"""``"trace"``: follow the solution of a parametric LCP as the load grows
(the load-trace paper of Osipova, Popov & Lovtsov).

For ``ParametricLCP(M, q0, q1)``, w = M z + q0 + p q1: q0 is the constant load
(gaps, dead weight), q1 the variable load scaled by the load parameter p >= 0
(units: z and w are the LCP's, p is dimensionless).  Osipova, Popov & Lovtsov
follow the solution from p = 0 upwards through the *working schemes* of the
structure: on an interval of p where the set F of basic z's (contacts closed,
links slipping) is fixed,

    z_F(p) = -M_FF^{-1} (q0_F + p q1_F),   z_N = 0,   w = M z + q0 + p q1,

is affine in p, and a breakpoint p_k is where some z_i (i in F) or w_i (i not
in F) reaches zero.

How the path is followed here
-----------------------------
1. Start from a solution at p = 0: z = 0 when q0 >= 0 (the paper's cases a and b),
   otherwise the one Lemke's method finds for LCP(M, q0) (case c).
2. At every breakpoint (and at the start) the next working scheme is *decided*,
   not guessed: with α = {z_i > 0}, γ = {w_i > 0} and β the pairs with z_i =
   w_i = 0 (each judged on its own componentwise scale, TIE_RTOL), a scheme F
   continues the path exactly when F contains α, avoids γ, M_FF is nonsingular
   and its direction dz_F = -M_FF^{-1} q1_F, dw = M dz + q1 keeps
   dz_i >= 0 on F ∩ β and dw_i >= 0 on β \\ F (the directional LCP of the
   vertex).  Up to ENUM_MAX degenerate pairs every one of the 2^|β| choices is
   checked, so several links changing at once, a slip turning into lift-off
   (where X_n, f X_n + X_t and f X_n - X_t vanish together) and any tie are
   resolved exactly; above that the directional LCP is solved by Lemke's
   method.  When several schemes continue the path (possible only when M is
   not a P-matrix) the one closest to the previous scheme is taken and the
   event records how many there were.
3. Candidates are tried closest first; a piece is computed from its own block
   (LU of the equilibrated M_FF, iteratively refined), certified from the
   data at its start, middle and end (:func:`qpcontact.judge.lcp_certificate.certify_lcp`),
   and only then kept.  When no candidate certifies (M with null vectors
   other than slip pairs: the same w written with other positive z's), a
   solve just beyond the vertex is tried and kept only if its scheme
   certifies back at the vertex.

Endings (``LoadTrace.end``), each with what proves it
-----------------------------------------------------
``"p_max"``      the requested load was reached.
``"unbounded"``  (p_max = inf) the last scheme never changes again: no z_i or
                 w_i decreases along its direction, which is in ``proof``.
``"collapse"``   no equilibrium exists for p >= p_limit, a hair above the end
                 point: a Farkas vector y (y >= 0, M'y <= 0, q1'y <= 0,
                 y'q(p_limit) < 0), found by an LP and checked component by
                 component from the data, makes y'w < 0 for every z >= 0; when
                 complementarity is what rules the loads out, branch and bound
                 over the complementary patterns gives one such vector per
                 remaining pattern (``proof["leaves"]``).
``"fold"``       equilibria may exist beyond the end point, but none continues
                 this path: all 2^|β| schemes at the vertex were checked, none
                 goes on with p increasing, and M's only null vectors are slip
                 pairs (a non-P matrix whose load-displacement path turns
                 back).  Solve at a fixed load with ``problem.at(p)`` for other
                 branches.
``"breakdown"``  none of the above could be established: the pieces before
                 are returned (certified), the message says what is known.
``"max_pieces"`` the piece limit was reached.

Nothing is added to the data: degenerate starts (q0 = 0, case a, or zero gaps)
are decided by the directional problem, so every reported state satisfies the
LCP of the real data.
"""

from __future__ import annotations

import time

import numpy as np

from ...core.accuracy import resolve_accuracy
from ...core.errors import InvalidOptionError, InvalidProblemError, NoSolutionError, SolverFailedError
from ...core.options import BySize, Option, names_only, read_options
from ...core.problems import ParametricLCP
from ...judge.doubt import doubt, no_digit
from ...judge.lcp_certificate import certify_lcp
from ..pivoting.active_set import check_dense_size
from .path import Path
from .result import LoadTrace, TraceEvent, TracePiece

__all__ = ["trace_load", "run_trace", "TRACE_OPTIONS"]

TRACE_OPTIONS = (
    Option("p_max", 1.0, "float", low=0.0, low_open=True,
           doc="the load parameter to stop at (inf: follow the path to its end)"),
    Option("max_pieces", BySize(lambda n: max(1000, 20 * n), "max(1000, 20 n)"), "int", low=1,
           doc="linear pieces at most"),
    Option("start", None, "vector", low=0.0,
           doc="a solution at p = 0 to start from (the caller's: a frame judges a degenerate "
               "point on its mechanics); checked here by the LCP's certificate"),
)


def _start(plcp: ParametricLCP, solve_lcp, given=None, tol=None):
    """A certified solution at p = 0 (``given``: the caller's, certified here)."""
    n = plcp.n
    if given is not None:
        if given.size != n:
            raise InvalidOptionError(f"trace: start has {given.size} entries; the problem has {n}")
        error = certify_lcp(plcp.at(0.0), given).error
        if not error <= tol:
            raise InvalidOptionError(
                f"trace: start is no solution at p = 0 (certificate {error:.1e} > {tol:.0e}); "
                "pass a certified one or leave start out")
        return given
    if np.all(plcp.q0 >= 0):
        return np.zeros(n)
    sol = solve_lcp(plcp.at(0.0))
    if sol.ok:
        return sol.z
    proved = sol.stats.get("proved_infeasible", False)
    # NoSolutionError only for what was proved: Lemke's secondary ray on a
    # matrix that is not copositive-plus proves nothing
    raise (NoSolutionError if proved else SolverFailedError)(
        "the constant load alone (p = 0) has no equilibrium"
        + (" (proved: " if proved else " that Lemke's method can find (")
        + f"{sol.message}); a load trace needs an equilibrium to start from"
    )


def trace_load(plcp: ParametricLCP, solve_lcp, *, accuracy="high", p_max: float = 1.0,
               max_pieces: int | None = None, expired=None, start=None) -> LoadTrace:
    """Trace the solution of ``plcp`` for p from 0 to ``p_max`` (see module docstring).

    Parameters
    ----------
    plcp : ParametricLCP
    solve_lcp : callable
        ``solve_lcp(lcp, prove=True) -> LCPSolution``: the engine's certified
        solve of one LCP by Lemke's method at ``accuracy`` (the start at p = 0,
        and with ``prove=False`` the schemes probed just beyond a vertex);
        :func:`qpcontact.solve` passes it.
    accuracy : level or float
        Tolerance every piece is certified at (:mod:`qpcontact.core.accuracy`).
    p_max : float
        Stop at this load parameter (``np.inf``: follow until the scheme stops
        changing, or no equilibrium continues the path).
    max_pieces : int, optional
        Default max(1000, 20 n).
    expired : callable, optional
        ``expired() -> bool``: whether the call's deadline has passed (the
        engine's); the trace then ends "time_limit" with the path certified
        up to where it stopped.
    start : array, optional
        A solution at p = 0 to start from instead of Lemke's (checked by the
        LCP's certificate at ``accuracy``).

    Raises
    ------
    NoSolutionError
        The constant load alone has no solution (nothing to start from), proved.
    SolverFailedError
        Lemke's method found no solution under the constant load alone and
        proved none impossible.
    """
    if not isinstance(plcp, ParametricLCP):
        raise InvalidProblemError(f"'trace' takes a ParametricLCP; got {type(plcp).__name__}")
    n = plcp.n
    given = {"p_max": p_max} if max_pieces is None else {"p_max": p_max, "max_pieces": max_pieces}
    if start is not None:
        given["start"] = start
    opts = read_options("trace", given, TRACE_OPTIONS, size=n)
    p_max, max_pieces = opts["p_max"], opts["max_pieces"]
    check_dense_size("trace", n, f"{n} x {n} block", "fixed loads with problem.at(p)")
    _, tol = resolve_accuracy(accuracy)
    start = time.perf_counter()
    path = Path(plcp)

    z = _start(plcp, solve_lcp, opts.get("start"), tol)
    p = 0.0
    w = path.M @ z + plcp.q0
    F_prev = np.zeros(n, bool)
    pieces: list[TracePiece] = []
    events: list[TraceEvent] = []
    end, proof, why = None, {}, ""
    worst = 0.0
    checked = 0
    while True:
        if expired is not None and expired():
            end = "time_limit"
            break
        found, exhaustive = path.continuation(p, z, w, F_prev, 50 * n + 1000)
        resolved = False
        accepted = None
        for F, block, dz, dw in found:
            accepted = path.certified_piece(block, F, p, dz, dw, p_max, tol)
            if accepted is not None:
                break
        if accepted is None:
            # Nothing from the vertex's own schemes: a solve just beyond p, kept
            # only if its scheme certifies back at p (the path is then continuous).
            accepted = path.resolved_piece(p, F_prev if pieces else None, p_max, tol, solve_lcp)
            resolved = accepted is not None
        beyond = None
        if accepted is None:
            zeta_end, _ = path.values.at(z, path.q_terms(p))
            found_y = path.collapse_proof(p, max(float(np.abs(z).max(initial=0.0)),
                                                 float(zeta_end.max(initial=0.0)), 1e-300), tol,
                                          expired=expired)
            if found_y is not None and "solution" in found_y:
                # an equilibrium just beyond p that the vertex's schemes did not
                # reach (M's null vectors): continue from its scheme if it holds at p
                beyond = found_y["solution"][1]
                accepted = path.piece_through(p, F_prev if pieces else None, *found_y["solution"],
                                              p_max, tol)
                resolved = accepted is not None
                found_y = None
        if accepted is None:
            if found_y is not None:
                end = "collapse"
                proof = found_y
            elif expired is not None and expired():
                end = "time_limit"     # the proof's branches stopped at the deadline
            elif exhaustive and path.unique:
                end = "fold"
                proof = {"p": p, "schemes_checked": "all"}
            else:
                end = "breakdown"
                why = (f"at p = {p:g} no working scheme that continues the path could be found "
                       "and certified" + ("" if path.unique else
                                          " (M has null vectors: the same forces can be written "
                                          "with other unknowns, so not every scheme was tried)")
                       + (f"; an equilibrium exists at p = {beyond:.10g}, on another branch"
                          if beyond is not None else
                          ", and no equilibrium could be proved impossible beyond it"))
            break
        piece, t, i_cross, cross_z = accepted
        F = piece.active
        worst = max(worst, piece.error)
        checked += 3
        if pieces:
            events.append(TraceEvent(p, np.flatnonzero(F & ~F_prev), np.flatnonzero(F_prev & ~F),
                                     0 if resolved else path.distinct(found), resolved))
        pieces.append(piece)
        if np.isfinite(p_max) and piece.p_end == p_max:
            end = "p_max"
            break
        if not np.isfinite(piece.p_end):
            end = "unbounded"
            proof = {"from": p, "dz": piece.dz, "dw": piece.dw}
            break
        if len(pieces) >= max_pieces:
            end = "max_pieces"
            break
        p = piece.p_end
        z = piece.z_start + t * piece.dz
        w = piece.w_start + t * piece.dw
        # the row that reached zero is zero (not a rounding error's worth off)
        if cross_z:
            z[i_cross] = 0.0
        else:
            w[i_cross] = 0.0
        z = np.maximum(z, 0.0)
        F_prev = F
    wall = time.perf_counter() - start

    last = pieces[-1] if pieces else None
    p_final = (last.p_end if np.isfinite(last.p_end) else last.p_start) if last else 0.0
    z_fin = last.z(p_final) if last else np.maximum(z, 0.0)
    lcp_final = plcp.at(p_final)
    cert = certify_lcp(lcp_final, z_fin)
    breakpoints = np.array([pc.p_end for pc in pieces[:-1]])
    status = {"breakdown": "failed", "max_pieces": "max_pivots",
              "time_limit": "time_limit"}.get(end, "solved")
    # At a collapse the last point is the limit itself, where the active block
    # turns singular: no digit of it is guaranteed by nature (the portal's
    # sliding load: condition 6e14), and the collapse is what the proof says.
    # There the backward statement is what is held to tol.
    at_limit = end == "collapse"
    if status == "solved" and not (cert.error <= tol and doubt(cert, tol) is None if at_limit
                                   else cert.ok(tol)):
        status = "inaccurate"
    message = _message(end, p, p_max, p_final, proof, why, max_pieces)
    if at_limit and no_digit(cert):
        message += ("; the state at the collapse load itself is singular (no digit of it is "
                    "guaranteed), as a limit state is")
    message += f"; {len(breakpoints)} breakpoint(s)"
    ambiguous = sum(ev.continuations > 1 for ev in events)
    if ambiguous:
        message += (f"; at {ambiguous} breakpoint(s) several working schemes continued the path "
                    "(non-P matrix; the one closest to the previous scheme was followed)")
    return LoadTrace(
        method="trace", status=status, ok=status == "solved", message=message,
        accuracy=accuracy, tol=tol, certificate=cert, backend_status=end,
        wall_time=wall, iterations=len(pieces),
        stats={"pieces": len(pieces), "worst_piece_error": worst, "certified_points": checked,
               "ambiguous_breakpoints": ambiguous},
        z=z_fin, w=lcp_final.w(z_fin), pieces=pieces, breakpoints=breakpoints, events=events,
        end=end, p_end=p_final, proof=proof,
    )


def _message(end, p, p_max, p_final, proof, why, max_pieces) -> str:
    if end == "p_max":
        return f"traced to p = {p_max:g}"
    if end == "unbounded":
        return (f"the working scheme no longer changes for p >= {proof['from']:g}: the solution "
                "grows along proof['dz'] without bound")
    if end == "collapse":
        how = ("by a Farkas vector" if proof["patterns"] == 1 else
               f"over {proof['patterns']} patterns of which z's and w's are zero, each by a Farkas "
               "vector")
        bound = ("" if not np.isfinite(proof["z_bound"]) else
                 f", for every z with sum below {proof['z_bound']:.1e}")
        return (f"no equilibrium exists for p >= {proof['p_limit']:.10g} (proved {how}, "
                f"checked from the data{bound}); the last equilibrium is at p = {p_final:.10g}")
    if end == "fold":
        return (f"the path turns back at p = {p:.10g}: no working scheme continues it with the load "
                "increasing (every scheme of the degenerate pairs checked; M is not a P-matrix, "
                "so other equilibria may exist beyond — solve problem.at(p) for them)")
    if end == "max_pieces":
        return f"piece limit {max_pieces} reached at p = {p:g}"
    if end == "time_limit":
        return (f"stopped at the time limit at p = {p_final:.10g} (solve's time_limit= bounds the "
                "whole trace); the path up to there is certified: raise time_limit= to go on")
    return why


def run_trace(plcp: ParametricLCP, tol: float, options: dict, engine) -> LoadTrace:
    """The "trace" method (registered in :mod:`.specs`): options
    (:data:`TRACE_OPTIONS`) ``p_max`` (1), ``max_pieces`` (max(1000, 20 n)),
    ``start`` (a solution at p = 0 to start from, certified here);
    every piece is certified to ``tol``.  It certifies each piece from the
    data itself, at its start, middle and end (a path, not a point, is its
    answer); its Lemke solves go through ``engine``."""
    # the names here, the values (and the size-dependent default) in trace_load
    read_options("trace", options, names_only(opt.name for opt in TRACE_OPTIONS))
    return trace_load(plcp, lambda lcp, prove=True: engine.solve(lcp, "lemke", prove=prove),
                      accuracy=tol, expired=engine.expired, **options)
