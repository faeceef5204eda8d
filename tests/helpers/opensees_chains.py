"""OpenSees models for the frames' peer checks (tests and benchmarks): a
plane member cut into a chain of elastic pieces — with the PDelta
transformation its P-δ comes from the cut, O(1/n²) — and the static
analysis they run.  The caller imports openseespy and passes its module."""

from __future__ import annotations


def plane_chain(ops, a, b, xy_a, xy_b, sub, nxt, ele, A, E, I, transf=1):
    """The member from node tag ``a`` at ``xy_a`` to ``b`` at ``xy_b`` as
    ``sub`` elasticBeamColumn pieces (A, E, I; geometric transformation
    ``transf``), its inner nodes numbered from ``nxt`` along it and its
    pieces from ``ele``: (the pieces' element tags from a to b, the next
    free node tag, the next free element tag)."""
    (xa, ya), (xb, yb) = xy_a, xy_b
    chain = [a]
    for s in range(1, sub):
        ops.node(nxt, xa + (xb - xa) * s / sub, ya + (yb - ya) * s / sub)
        chain.append(nxt)
        nxt += 1
    chain.append(b)
    pieces = list(range(ele, ele + sub))
    for e, p, q in zip(pieces, chain[:-1], chain[1:]):
        ops.element("elasticBeamColumn", e, p, q, A, E, I, transf)
    return pieces, nxt, ele + sub


def static_analysis(ops, tol, steps=1) -> bool:
    """Newton on the displacement increment's norm to ``tol`` (100
    iterations a step), the loads in ``steps`` equal increments, on a
    banded system: whether OpenSees converged."""
    ops.system("BandGeneral")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test("NormDispIncr", tol, 100)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0 / steps)
    ops.analysis("Static")
    return ops.analyze(steps) == 0
