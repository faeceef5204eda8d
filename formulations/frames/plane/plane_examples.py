"""Worked plane frames: the demo's beam and portal, a tower on a foundation
beam, and the plane frames' instances that ``qpcontact compare`` runs (all
of the frames' instances: :func:`..catalogue.instances`)."""

from __future__ import annotations

import numpy as np

from qpcontact.core.problems import ParametricLCP

from .frame import Frame


def demo(console) -> int:
    """The frame part of ``qpcontact demo``: a beam pinned at one end on a
    frictional support (limit f P/2 by hand) solved below and above the limit
    by Lemke and by the Tresca fixed point; then the portal of
    :func:`portal_example` traced to its collapse, against the hand values.
    Returns the number of failed checks."""
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    def beam(H):
        fr = Frame()
        for nm, x in (("A", 0.0), ("C", 2.0), ("B", 4.0)):
            fr.add_node(nm, x, 0.0)
        fr.add_member("A", "C", E=2e8, A=0.01, I=1e-4)
        fr.add_member("C", "B", E=2e8, A=0.01, I=1e-4)
        fr.add_support("A", fix=("ux", "uy"))
        fr.add_contact("B", normal=(0.0, 1.0), friction=0.3)
        fr.add_load("C", fy=-100.0)
        fr.add_load("B", fx=H)
        return fr

    def table_of(title, cols, left, wrap=()):
        table = Table(title=title, box=box.SIMPLE_HEAD, title_justify="left", pad_edge=False)
        for col in cols:
            table.add_column(escape(col), justify="left" if col in left else "right",
                             no_wrap=col not in wrap, min_width=len(col))
        return table

    table = table_of("Frame (Osipova–Popov–Lovtsov): beam A-C-B, pinned at A, on a support at B "
                     "with f = 0.3",
                     ("H [kN]", "route", "state at B", "X_n [kN]", "X_t [kN]", "LCP error",
                      "equilibrium"), left=("route", "state at B"), wrap=("route",))
    failed = 0
    for H in (10.0, 20.0):
        for method in ("active-set", "lemke", "tresca"):
            r = beam(H).solve(method=method)
            s = r.supports["B"]
            expect = "stick" if H <= 15 else "slip+"
            failed += int(not r.ok or s.state != expect)
            table.add_row(f"{H:g}", r.route, s.state, f"{s.normal:.3f}", f"{s.tangential:.3f}",
                          f"{r.lcp_error:.0e}", f"{r.equilibrium_residual:.0e}")
    console.print(table)
    _notes(console, [
        "Loads: 100 kN down at midspan C, H along the support at B.  By hand: B carries 50 kN, so "
        "it sticks while H <= f * 50 = 15 kN and slides (slip+) above.  X_n, X_t: the normal and "
        "tangential reactions at B; LCP error: the contact problem's certificate; equilibrium: "
        "the worst dof's residual against its own terms."])
    tr = portal_example().trace(p_max=40.0)
    table = table_of("Increasing load (Osipova–Popov–Lovtsov's trace): a pinned-base portal on "
                     "two frictional bases",
                     ("p [kN]", "by hand [kN]", "event"), left=("event",), wrap=("event",))
    hand = (25.4363, 0.3 * 20.0 * 6.0)   # force method; f w L
    rows = [(ev.p, str(ev)) for ev in tr.events] + [(tr.p_end, f"{tr.ended}: {tr.message}")]
    for (p, what), ref in zip(rows, hand):
        table.add_row(f"{p:.6g}", f"{ref:.6g}", escape(what))
    console.print(table)
    _notes(console, [
        "Portal 6 m x 4 m, bases A and D on frictional contacts (f = 0.3), 20 kN/m down on the "
        "beam, P = p kN sideways at B.  By hand: D starts slipping at p = 25.4363 (force method); "
        "the frame slides away at p = f w L = 36."])
    got = [p for p, _ in rows]
    failed += int(not (tr.ok and tr.ended == "collapse" and len(got) == 2
                       and abs(got[0] - hand[0]) < 5e-5 and abs(got[1] - hand[1]) < 1e-8 * hand[1]))
    return failed


def _notes(console, lines) -> None:
    """Plain text: units in brackets are words, not rich markup."""
    for line in lines:
        console.print(line, markup=False, highlight=False)


def portal_example() -> Frame:
    """The pinned-base portal of the trace's hand checks: columns A(0,0)-B(0,4)
    and D(6,0)-C(6,4), beam B-C,
    IPE 300 (E = 210e6 kN/m², A = 5.381e-3 m², I = 8.356e-5 m⁴), both bases rigid
    frictional contacts (normal (0, 1), f = 0.3, free rotation), 20 kN/m down on
    the beam (constant), P = p kN at B along +x (variable).  By hand: base D
    starts slipping at P = 25.4363 kN (force method) and the frame slides away
    at P = f w L = 36 kN."""
    fr = Frame()
    for name, x, y in (("A", 0.0, 0.0), ("B", 0.0, 4.0), ("C", 6.0, 4.0), ("D", 6.0, 0.0)):
        fr.add_node(name, x, y)
    E, A, I = 210e6, 5.381e-3, 8.356e-5
    fr.add_member("A", "B", E, A, I)
    beam = fr.add_member("B", "C", E, A, I)
    fr.add_member("D", "C", E, A, I)
    fr.add_contact("A", normal=(0.0, 1.0), friction=0.3)
    fr.add_contact("D", normal=(0.0, 1.0), friction=0.3)
    fr.add_distributed_load(beam, wy=-20.0)
    fr.add_load("B", fx=1.0, case="variable")
    return fr


def plane_instances(size: str = "small", hardness: str = "easy", seed: int = 0) -> list:
    """Frame LCPs for ``qpcontact compare``: a continuous beam on 3, 10 or 30
    unilateral supports (size small/medium/large) under gravity and uplifting
    point loads; "easy" without friction (symmetric), "hard" with friction
    f = 0.3 and a lateral load (nonsymmetric: QP backends are not applicable).
    Named ``frames/10-supports-friction``; the contact forces are w's first
    entries (X_n)."""
    from qpcontact.cases.instance import Instance

    spans = {"small": 3, "medium": 10, "large": 30}[size]
    rng = np.random.default_rng(seed + spans)
    fr = Frame()
    xs = np.cumsum(np.r_[0.0, rng.uniform(2.0, 4.0, spans)])
    for k, x in enumerate(xs):
        fr.add_node(f"N{k}", float(x), 0.0)
    for k in range(spans):
        m = fr.add_member(f"N{k}", f"N{k + 1}", E=2.1e8, A=5.4e-3, I=5.7e-5)
        fr.add_distributed_load(m, wy=-20.0)
    friction = 0.3 if hardness == "hard" else 0.0
    fr.add_support("N0", fix=("ux", "uy", "rz"))
    for k in range(1, spans + 1):
        fr.add_contact(f"N{k}", normal=(0.0, 1.0), friction=friction, gap=float(rng.uniform(0, 2e-3)))
    for k in rng.choice(np.arange(1, spans + 1), size=max(1, spans // 3), replace=False):
        fr.add_load(f"N{k}", fy=float(rng.uniform(20, 60)), fx=40.0 if friction else 0.0)
    M, qc, qv, P, g, fric = fr.lcp()
    name = f"frames/{spans}-supports" + ("-friction" if friction else "")
    return [Instance(name, "frames", f"{spans}-supports", ParametricLCP(M, qc, qv).at(1.0),
                     forces=("w", spans))]


def tower(storeys: int = 20, bays: int = 3) -> tuple:
    """(frame, foundation nodes): bays + 1 columns 6 m apart, ``storeys`` x
    3.5 m (HEB-like columns E = 210e6 kN/m², A = 1.5e-2 m², I = 5e-4 m⁴;
    beams A = 8e-3, I = 2e-4), 30 kN/m on every beam (the case "constant"),
    a foundation beam (E = 30e6, A = 1.2, I = 0.36) from 3 m beyond the
    outer columns on elastic frictional pads every 1.5 m (μ = 0.5, k = 5e5
    kN/m), and 10 kN x p at every floor of the left column (the case
    "variable")."""
    fr = Frame(units=("kN", "m"))
    col, beam = (210e6, 1.5e-2, 5e-4), (210e6, 8e-3, 2e-4)
    xs = tuple(6.0 * j for j in range(bays + 1))
    for s in range(storeys + 1):
        for j, x in enumerate(xs):
            fr.add_node(f"N{s}_{j}", x, 3.5 * s)
    for s in range(storeys):
        for j in range(bays + 1):
            fr.add_member(f"N{s}_{j}", f"N{s + 1}_{j}", *col)
    for s in range(1, storeys + 1):
        for j in range(bays):
            fr.add_distributed_load(fr.add_member(f"N{s}_{j}", f"N{s}_{j + 1}", *beam), wy=-30.0)
    base = []
    for k, x in enumerate(np.arange(-3.0, xs[-1] + 3.01, 1.5)):
        hit = [j for j, xx in enumerate(xs) if abs(x - xx) < 1e-9]
        base.append(f"N0_{hit[0]}" if hit else fr.add_node(f"F{k}", float(x), 0.0))
    for a, b in zip(base[:-1], base[1:]):
        fr.add_member(a, b, 30e6, 1.2, 0.36)
    for name in base:
        fr.add_contact(name, normal=(0.0, 1.0), friction=0.5, stiffness=5e5)
    for s in range(1, storeys + 1):
        fr.add_load(f"N{s}_0", fx=10.0, case="variable")
    return fr, base
