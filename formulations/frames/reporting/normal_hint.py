"""A hint for contacts whose normal points the wrong way.

A contact's ``normal`` is the direction in which the support pushes the
structure: from the ground into the frame (the pad under a beam has normal
+y, or +z in space).  Given the other way, (0, -1) under a beam loaded
downward, the support can only pull the frame down, and the frame has no
equilibrium: the proof then reads "tips over about A: B lift off" or "it
lifts off: P0, P1 would have to pull", true of the model but not what the
user meant.  Where no contact's normal points against the loads' resultant
and at least one points along it, the message adds what the normal means
and which normals to flip.  A frame loaded by a pure couple (zero
resultant) gets no hint: there is no gravity-like direction to judge by.
"""

from __future__ import annotations

import numpy as np

#: n·f̂ beyond this counts as along (or against) the load's direction f̂
ALONG = 1e-9


def resultant(frame, b, combo: dict) -> np.ndarray:
    """The loads' resultant force of a combination {case: factor} (the
    equivalent nodal loads keep it), in global axes; zero where the
    combination names no case the frame has."""
    dim = len(next(iter(frame.nodes.values())))
    nd = len(frame.DOFS)
    f = np.zeros(len(b["cases"]))
    for case, factor in combo.items():
        if case in b["cases"]:
            f[b["cases"].index(case)] = factor
    F = np.asarray(b["F"] @ f, float)
    if b.get("Tn") is not None:
        # turned node axes: the plane frame's F is written in them (Tn
        # turns global dofs into node axes, orthogonal)
        F = np.asarray(b["Tn"].T @ F, float)
    return F.reshape(-1, nd)[:, :dim].sum(axis=0)


def normal_hint(frame, b, combo: dict) -> str:
    """"" or the sentence to add to a no-equilibrium message when every
    contact's normal that is not across the load points along it."""
    if not frame.contacts:
        return ""
    R = resultant(frame, b, combo)
    size = np.linalg.norm(R)
    if not size > 0:
        return ""
    d = R / size
    along = [float(np.asarray(c.normal) @ d) for c in frame.contacts]
    if min(along) < -ALONG or max(along) <= ALONG:
        return ""
    keys = frame.kind.support_keys(frame)
    wrong = [k for k, a in zip(keys, along) if a > ALONG]
    shown = ", ".join(wrong[:8]) + (f" and {len(wrong) - 8} more" if len(wrong) > 8 else "")
    example = next(c for c, a in zip(frame.contacts, along) if a > ALONG)
    n = tuple(float(v) + 0.0 for v in np.round(example.normal, 6))
    flipped = tuple(-v + 0.0 for v in n)
    load = "(" + ", ".join(f"{v:.3g}" for v in np.round(d, 6) + 0.0) + ")"
    return (f" — check the contacts' normals: every one that is not across the loads points "
            f"along their resultant (direction {load}) at {shown}, so those supports could "
            f"only pull the frame the way the loads push it. A contact's normal is the "
            f"direction in which the support pushes the structure, from the ground into the "
            f"frame (a pad under a beam loaded downward has normal (0, 1), in space "
            f"(0, 0, 1)); flip them (normal={flipped} instead of {n}) if that is what was "
            "meant")
