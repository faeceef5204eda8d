"""Space frames in OpenSees and PyNite, read off a qpcontact ``SpaceFrame``:
the same nodes, members, member and nodal loads, supports and
contacts, built through each code's API, so that one description
(:func:`formulations.frames.space.space_tower.space_tower`) feeds every code.
benchmarks/frames.py times them side by side; tests/formulations/frames/test_space_tower.py
checks the answers.

The law, as in 2-D (benchmarks/frames.py): an elastic contact is a normal
spring k in series with a rigid unilateral link, a tangential spring k with
|X_t| <= f X_n, total slip against total force.

- OpenSees (``model basic -ndm 3 -ndf 6``): members are elasticBeamColumn
  elements with a Linear geomTransf whose vecxz is the member's local z
  (the SpaceFrame's axes: OpenSees' y = vecxz x x, z = x x y are the same
  axes, :mod:`formulations.frames.mechanics.space_element`); uniform member loads go in
  as ``-beamUniform Wy Wz Wx`` in member axes.  A frictional contact is a
  zero-length ``flatSliderBearing`` from a fixed ground node (node i, so
  that its P-delta moments fall on the ground) to the structure's node:
  Coulomb friction f, kInit = k, an Elastic axial material k (the element
  drops its shear and axial force when the axial force turns to tension;
  an ENT material there gives the same answers and iterations), zero
  torsion and bending materials (a pad carries no moment), local x along
  the contact's normal and y along its t1.  Its friction cone is the
  circle |X_t| <= f X_n, qpcontact's the m-gon circumscribing it
  (``facets``): where pads slip the answers differ by the faceting, which
  fixes the slip direction to a facet's normal but not the force's
  direction along the facet (an O(1/m) difference); where none slips they
  are the same problem.  A frictionless contact is a zeroLength element with
  an ENT material along the normal.
- PyNite has no friction: the frictionless variant of a model (every
  contact f = 0, pins given by the model's bilateral supports) with
  compression-only springs along z (``def_support_spring(node, "DZ", k,
  "-")``).  PyNite's local axes of these members are the SpaceFrame's (its
  vertical bending uses its Iy, as ours), so the sections go in unchanged.

Only what the tower needs is translated: contacts with normal +z in
PyNite, members on the default reference there, loads in global axes or
member axes.
"""

from __future__ import annotations

import numpy as np

from formulations.frames.mechanics.space_element import axes

#: OpenSees' solution algorithm for the 3-D tower: Newton (the 2-D
#: benchmark's) does not converge in one load step once pads slip or lift
#: off (its residual falls by about 1 % per iteration); Krylov-Newton on the
#: initial stiffness does on the states compared here
ALGORITHM = ("KrylovNewton", "-iterate", "initial")
MAX_ITERATIONS = 1000


def member_axes(fr) -> dict:
    """{member: its rotation matrix (rows: local x, y, z in global
    components)}, in one call where the members take the default reference
    (a call per member would be most of a translator's time)."""
    names = list(fr.members)
    ms = [fr.members[n] for n in names]
    if any(m["ref"] is not None or m["roll"] for m in ms):
        return {n: axes(fr.nodes[m["i"]], fr.nodes[m["j"]], m["ref"], m["roll"])[0]
                for n, m in zip(names, ms)}
    R = axes(np.array([fr.nodes[m["i"]] for m in ms]), np.array([fr.nodes[m["j"]] for m in ms]))
    return dict(zip(names, R))


def _combined(fr, combination, R=None):
    """The model's member loads (member, q in member axes, length) and nodal
    loads (node, 6 values) scaled by ``combination`` {case: factor}; ``R``
    the members' axes (:func:`member_axes`)."""
    R = member_axes(fr) if R is None else R
    member_q = []
    if len(fr.member_loads) != len(fr.span_loads):
        # member_loads lists the whole-member uniform loads only
        raise ValueError("the peers' exports read uniform whole-member loads only")
    for member, w, ax, case in fr.member_loads:
        factor = combination.get(case, 0.0)
        if not factor:
            continue
        m = fr.members[member]
        q = np.asarray(w) if ax == "member" else R[member] @ np.asarray(w)
        member_q.append((member, factor * q, float(np.linalg.norm(fr.nodes[m["j"]]
                                                                  - fr.nodes[m["i"]]))))
    nodal = [(node, combination.get(case, 0.0) * np.asarray(v))
             for node, v, case in fr.nodal_loads if combination.get(case, 0.0)]
    return member_q, nodal


def load_scale(fr, combination, R=None) -> float:
    """The sum of the loads' magnitudes under ``combination``."""
    member_q, nodal = _combined(fr, combination, R)
    return (sum(np.abs(q).sum() * L for _, q, L in member_q)
            + sum(np.abs(v).sum() for _, v in nodal))


def ours_forces(fr, res) -> np.ndarray:
    """Each contact's force on the structure (Fx, Fy, Fz, global), then the
    bilateral supports' reactions at their fixed dofs (global)."""
    out = []
    for c in fr.contacts:
        s = res.supports[c.node]
        out += list(s.normal * c.normal + s.tangential_global)
    dofs = ("ux", "uy", "uz", "rx", "ry", "rz")
    for node, fixed in fr.fixed.items():
        out += [res.reactions[node][dofs.index(d)] for d in sorted(fixed, key=dofs.index)]
    return np.array(out)


# -- OpenSees -----------------------------------------------------------------

def opensees_build(fr, combination, algorithm=ALGORITHM, tol: float = 1e-10):
    """The SpaceFrame as an OpenSees model under ``combination`` (one
    static load step, LoadControl 1.0, NormUnbalance ``tol`` x the sum of
    the loads, at most MAX_ITERATIONS iterations of ``algorithm``).
    Returns (node tags, ground node tag per contact)."""
    import openseespy.opensees as ops

    dofs = ("ux", "uy", "uz", "rx", "ry", "rz")
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    tag = {name: t for t, name in enumerate(fr.nodes, start=1)}
    for name, x in fr.nodes.items():
        ops.node(tag[name], *map(float, x))
    for node, fixed in fr.fixed.items():
        ops.fix(tag[node], *(int(d in fixed) for d in dofs))
    transf, etag = {}, {}
    R = member_axes(fr)
    for e, (name, m) in enumerate(fr.members.items(), start=1):
        # vecxz = the local z (a roll turns it too)
        key = tuple(float(v) for v in np.round(R[name][2], 14))
        if key not in transf:
            transf[key] = len(transf) + 1
            ops.geomTransf("Linear", transf[key], *key)
        ops.element("elasticBeamColumn", e, tag[m["i"]], tag[m["j"]], m["A"], m["E"], m["G"],
                    m["J"], m["Iy"], m["Iz"], transf[key])
        etag[name] = e
    ops.uniaxialMaterial("Elastic", 1, 0.0)        # a pad's moments and torsion: none
    mats, frictions, ground = {}, {}, {}
    e0, g0 = len(fr.members) + 1, len(fr.nodes) + 1
    for ci, c in enumerate(fr.contacts):
        if c.stiffness is None or c.gap:
            raise ValueError(f"contact at {c.node}: OpenSees needs an elastic contact without gap")
        g = g0 + ci
        ground[c.node] = g
        ops.node(g, *map(float, fr.nodes[c.node]))
        ops.fix(g, 1, 1, 1, 1, 1, 1)
        kind = "Elastic" if c.friction > 0 else "ENT"
        if (kind, c.stiffness) not in mats:
            mats[(kind, c.stiffness)] = len(mats) + 2
            ops.uniaxialMaterial(kind, mats[(kind, c.stiffness)], c.stiffness)
        mat = mats[(kind, c.stiffness)]
        if c.friction > 0:
            if c.friction not in frictions:
                frictions[c.friction] = len(frictions) + 1
                ops.frictionModel("Coulomb", frictions[c.friction], c.friction)
            ops.element("flatSliderBearing", e0 + ci, g, tag[c.node], frictions[c.friction],
                        c.stiffness, "-P", mat, "-T", 1, "-My", 1, "-Mz", 1,
                        "-orient", *map(float, c.normal), *map(float, c.t1))
        else:
            ops.element("zeroLength", e0 + ci, g, tag[c.node], "-mat", mat, "-dir", 1,
                        "-orient", *map(float, c.normal), *map(float, c.t1))
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    member_q, nodal = _combined(fr, combination, R)
    for member, q, _ in member_q:
        ops.eleLoad("-ele", etag[member], "-type", "-beamUniform", float(q[1]), float(q[2]),
                    float(q[0]))
    for node, v in nodal:
        ops.load(tag[node], *map(float, v))
    ops.constraints("Plain")
    ops.numberer("RCM")
    # the initial stiffness is symmetric: the fastest of UmfPack, BandGen,
    # SparseGEN, BandSPD, ProfileSPD, SparseSYM and Mumps here
    ops.system("SparseSYM")
    ops.test("NormUnbalance", tol * load_scale(fr, combination, R), MAX_ITERATIONS)
    ops.algorithm(*algorithm)
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    return tag, ground


def opensees_solve(built):
    """(analyze's return code, iterations)."""
    import openseespy.opensees as ops

    rc = ops.analyze(1)
    ops.reactions()
    return rc, ops.testIter()


def opensees_forces(fr, built) -> np.ndarray:
    """As :func:`ours_forces`: the ground nodes' reactions (the pads' forces
    on the structure), then the bilateral supports' reactions."""
    import openseespy.opensees as ops

    tag, ground = built
    dofs = ("ux", "uy", "uz", "rx", "ry", "rz")
    out = []
    for c in fr.contacts:
        out += ops.nodeReaction(ground[c.node])[:3]
    for node, fixed in fr.fixed.items():
        r = ops.nodeReaction(tag[node])
        out += [r[dofs.index(d)] for d in sorted(fixed, key=dofs.index)]
    return np.array(out)


# -- PyNite -------------------------------------------------------------------

def pynite_build(fr, combination):
    """The frictionless SpaceFrame as a PyNite model (compression-only
    springs along z at the contacts)."""
    from Pynite import FEModel3D

    dofs = ("ux", "uy", "uz", "rx", "ry", "rz")
    if any(c.friction > 0 for c in fr.contacts):
        raise ValueError("PyNite has no friction: give it the frictionless variant")
    if any(abs(c.normal[2] - 1.0) > 1e-12 or c.stiffness is None or c.gap
           for c in fr.contacts):
        raise ValueError("PyNite: elastic contacts with normal +z and no gap only")
    fe = FEModel3D()
    for name, x in fr.nodes.items():
        fe.add_node(name, *map(float, x))
    for node, fixed in fr.fixed.items():
        fe.def_support(node, *(d in fixed for d in dofs))
    sections = {}
    for name, m in fr.members.items():
        if m["roll"] or m["ref"] is not None:
            raise ValueError(f"member {name}: PyNite gets default member axes only")
        key = tuple(m[p] for p in ("E", "G", "A", "Iy", "Iz", "J"))
        if key not in sections:
            sections[key] = f"s{len(sections)}"
            fe.add_material(sections[key], m["E"], m["G"], m["E"] / (2 * m["G"]) - 1, 0.0)
            fe.add_section(sections[key], m["A"], m["Iy"], m["Iz"], m["J"])
        fe.add_member(name, m["i"], m["j"], sections[key], sections[key])
    if len(fr.member_loads) != len(fr.span_loads):
        # member_loads lists the whole-member uniform loads only
        raise ValueError("the peers' exports read uniform whole-member loads only")
    for member, w, ax, case in fr.member_loads:
        factor = combination.get(case, 0.0)
        if not factor:
            continue
        if ax != "global":
            raise ValueError("PyNite: member loads in global axes only")
        for direction, value in zip(("FX", "FY", "FZ"), w):
            if value:
                fe.add_member_dist_load(member, direction, factor * value, factor * value,
                                        case="C")
    for node, v, case in fr.nodal_loads:
        factor = combination.get(case, 0.0)
        for direction, value in zip(("FX", "FY", "FZ", "MX", "MY", "MZ"), v):
            if factor and value:
                fe.add_node_load(node, direction, factor * value, case="C")
    for c in fr.contacts:
        fe.def_support_spring(c.node, "DZ", c.stiffness, "-")   # resists downward motion only
    fe.add_load_combo("C", {"C": 1.0})
    return fe


def pynite_solve(fe):
    fe.analyze(check_statics=False)


def pynite_forces(fr, fe) -> np.ndarray:
    """As :func:`ours_forces` (a frictionless pad: (0, 0, spring force))."""
    dofs = ("ux", "uy", "uz", "rx", "ry", "rz")
    out = []
    for c in fr.contacts:
        out += [0.0, 0.0, fe.nodes[c.node].RxnFZ["C"]]
    for node, fixed in fr.fixed.items():
        n = fe.nodes[node]
        rx = (n.RxnFX, n.RxnFY, n.RxnFZ, n.RxnMX, n.RxnMY, n.RxnMZ)
        out += [rx[dofs.index(d)]["C"] for d in sorted(fixed, key=dofs.index)]
    return np.array(out)


def states_from_forces(fr, forces, rtol: float = 1e-7) -> list:
    """Each contact's state read off its force (Fx, Fy, Fz) as a peer gives
    it: separated where the normal force vanishes (to ``rtol`` of the
    largest), slip where the friction force reaches the circular cone,
    stick (closed without friction) otherwise."""
    X = np.asarray(forces[:3 * len(fr.contacts)]).reshape(-1, 3)
    scale = np.abs(X).max()
    out = []
    for c, x in zip(fr.contacts, X):
        n = float(x @ c.normal)
        t = float(np.linalg.norm(x - n * c.normal))
        if n <= rtol * scale:
            out.append("separated")
        elif c.friction == 0:
            out.append("closed")
        else:
            out.append("slip" if t >= c.friction * n - rtol * scale else "stick")
    return out

